//! Issue 38 items 4–7: the renderer options on `matgraph wgsl` (`--sample-shading`,
//! `--displaced-vertices`, `--derived-tangents`), the contract's `pipeline` (how to draw the
//! mesh; contracts written before it still parse), the `@invariant` clip position of
//! `mg_vertex`, and the compute entry's one `mg_geometry` buffer that keeps every bundled
//! graph within WebGPU's default of 8 storage buffers per stage.

use crate::common;

use matgraph::Registry;
use matgraph::material::{Contract, Material, MaterialOptions, Pipeline};
use matgraph::wgsl::{Entry, TextureMode, WgslOptions, generate, geometry_layout};
use std::ffi::OsStr;
use std::path::{Path, PathBuf};

fn graph_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("graphs")
        .join(name)
}

/// Runs `matgraph` with `args`; its standard output (or panics with its standard error).
fn cli(args: &[&OsStr]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args(args)
        .output()
        .unwrap()
}

/// `matgraph wgsl GRAPH FLAGS… -o out.wgsl --contract out.json`: the module and the contract.
fn wgsl(dir: &Path, graph: &str, flags: &[&str]) -> (String, Contract) {
    let tag = flags.join("").replace('-', "");
    let (w, j) = (
        dir.join(format!("{graph}{tag}.wgsl")),
        dir.join(format!("{graph}{tag}.json")),
    );
    let mut args: Vec<&OsStr> = vec!["wgsl".as_ref()];
    let path = graph_path(graph);
    args.push(path.as_os_str());
    args.extend(flags.iter().map(OsStr::new));
    args.extend(["-o".as_ref(), w.as_os_str()]);
    args.extend(["--contract".as_ref(), j.as_os_str()]);
    let out = cli(&args);
    assert!(
        out.status.success(),
        "{graph} {flags:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json = std::fs::read_to_string(&j).unwrap();
    (
        std::fs::read_to_string(&w).unwrap(),
        Contract::from_json(&json).unwrap(),
    )
}

/// The body of `fn NAME(` up to its closing brace at the start of a line.
fn function<'a>(source: &'a str, name: &str) -> &'a str {
    let start = source
        .find(&format!("fn {name}("))
        .unwrap_or_else(|| panic!("no fn {name}"));
    let body = &source[start..];
    &body[..body.find("\n}\n").unwrap()]
}

/// Item 4: each flag edits the render module as docs/integration.md ("Options for
/// renderers") says, the result is the Rust API's module with the same option, and the
/// contract records the options.
#[test]
fn wgsl_render_options_edit_the_module_as_documented() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // bubble: displacement and alpha.
    let (plain, c) = wgsl(d, "bubble.json", &[]);
    assert!(c.options.is_default());
    assert!(!plain.contains("@interpolate(perspective, sample)"));
    assert!(function(&plain, "mg_vertex").contains("mg_displaced("));

    let (sample, c) = wgsl(d, "bubble.json", &["--sample-shading"]);
    assert!(c.options.sample_shading && !c.options.displaced_vertices);
    assert_eq!(
        sample.matches("@interpolate(perspective, sample)").count(),
        3,
        "position, normal and uv per sample"
    );
    assert_eq!(
        sample.replace(" @interpolate(perspective, sample)", ""),
        plain,
        "nothing else changes"
    );

    let (displaced, c) = wgsl(d, "bubble.json", &["--displaced-vertices"]);
    assert!(c.options.displaced_vertices);
    let vertex = function(&displaced, "mg_vertex");
    assert!(!vertex.contains("mg_displaced("), "{vertex}");
    assert!(vertex.contains("o.position = p;"), "{vertex}");
    assert_ne!(displaced, plain);
    assert!(c.to_json().contains(
        "\"options\": {\n    \"sample_shading\": false,\n    \"displaced_vertices\": true,"
    ));

    // The Rust API's module with the same options: the same text.
    let graph = matgraph::io::load_graph(&graph_path("bubble.json"), Registry::builtin()).unwrap();
    let both = Material::new(
        &graph,
        &MaterialOptions {
            sample_shading: true,
            displaced_vertices: true,
            ..MaterialOptions::default()
        },
    )
    .unwrap();
    let (flags, _) = wgsl(
        d,
        "bubble.json",
        &["--sample-shading", "--displaced-vertices"],
    );
    assert_eq!(flags, both.wgsl());

    // brick_wall reads the tangent frame: the tangent buffer, or none with --derived-tangents.
    let (tangents, c) = wgsl(d, "brick_wall.json", &[]);
    assert!(c.tangent_buffer.is_some());
    assert!(function(&tangents, "mg_vertex").contains("v.tangent"));
    let (derived, c) = wgsl(d, "brick_wall.json", &["--derived-tangents"]);
    assert!(c.options.derived_tangents);
    assert!(c.tangent_buffer.is_none(), "no tangent buffer to bind");
    assert!(!function(&derived, "mg_vertex").contains("v.tangent"));
    assert!(derived.contains("fn mg_derived_frame("));
    let vertex_in = &derived[derived.find("struct MgVertexIn {").unwrap()..];
    let vertex_in = &vertex_in[..vertex_in.find('}').unwrap()];
    assert!(!vertex_in.contains("@location(3)"), "{vertex_in}");

    // The flags need the render module's entries, and say so.
    for entry in ["compute", "library", "fragment"] {
        let out = cli(&[
            "wgsl".as_ref(),
            graph_path("bubble.json").as_os_str(),
            "--entry".as_ref(),
            entry.as_ref(),
            "--sample-shading".as_ref(),
        ]);
        assert!(!out.status.success(), "{entry}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("--sample-shading") && err.contains("--entry render"),
            "{err}"
        );
    }
    // Without --entry, a flag alone asks for the render module.
    let out = cli(&[
        "wgsl".as_ref(),
        graph_path("bubble.json").as_os_str(),
        "--displaced-vertices".as_ref(),
    ]);
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stdout).contains("fn mg_vertex("));
}

/// Item 5: the contract's `pipeline` says how to draw the mesh: no culling, and for a graph
/// with an alpha output a depth pre-pass then the colour pass at less-equal without depth
/// writes. A contract written before the field parses, with the pipeline its outputs call for.
#[test]
fn the_contract_says_how_to_draw_the_mesh_and_old_contracts_still_parse() {
    let dir = tempfile::tempdir().unwrap();
    for (graph, translucent) in [
        ("skin.json", true),
        ("bubble.json", true),
        ("water_sunshine.json", true),
        ("pbr_gold.json", false),
        ("fresnel_glass.json", false),
    ] {
        let (_, c) = wgsl(dir.path(), graph, &[]);
        let p = &c.pipeline;
        assert_eq!(p.cull_mode, "none", "{graph}");
        assert_eq!(p.depth_prepass, translucent, "{graph}");
        assert_eq!(
            (p.depth_compare.as_str(), p.depth_write),
            if translucent {
                ("less-equal", false)
            } else {
                ("less", true)
            },
            "{graph}"
        );
        assert_eq!(*p, Pipeline::for_alpha(translucent));
        assert_eq!(
            c.outputs.iter().any(|o| o.role == "alpha"),
            translucent,
            "{graph}: translucent means an alpha output"
        );
        let json = c.to_json();
        assert!(json.contains("\n  \"pipeline\": {\n    \"cull_mode\": \"none\",\n"));
        // A contract without the field (as written before it): the same pipeline.
        let mut old: serde_json::Value = serde_json::from_str(&json).unwrap();
        old.as_object_mut().unwrap().remove("pipeline").unwrap();
        let old = serde_json::to_string_pretty(&old).unwrap();
        assert!(!old.contains("pipeline"));
        let parsed = Contract::from_json(&old).unwrap();
        assert_eq!(
            parsed, c,
            "{graph}: an old contract reads back with its pipeline"
        );
        // Plain serde reads it too (an opaque graph's default).
        let plain: Contract = serde_json::from_str(&old).unwrap();
        assert_eq!(plain.pipeline, Pipeline::default());
        // And the new one round-trips.
        assert_eq!(Contract::from_json(&json).unwrap(), c);
    }
    // wgpu's values.
    let t = Pipeline::for_alpha(true);
    assert_eq!(t.wgpu_cull_mode(), None);
    assert_eq!(t.wgpu_depth_compare(), wgpu::CompareFunction::LessEqual);
    assert_eq!(
        Pipeline::for_alpha(false).wgpu_depth_compare(),
        wgpu::CompareFunction::Less
    );
}

/// Item 6: the clip position of `mg_vertex` is `@invariant` in every render module and every
/// option's variant (the depth pre-pass and the colour pass compute the same depth), and
/// naga reads it so.
#[test]
fn the_clip_position_is_invariant() {
    let variants = [
        MaterialOptions::default(),
        MaterialOptions {
            textures: TextureMode::Exact,
            ..MaterialOptions::default()
        },
        MaterialOptions {
            sample_shading: true,
            displaced_vertices: true,
            ..MaterialOptions::default()
        },
        MaterialOptions {
            derived_tangents: true,
            sample_shading: true,
            ..MaterialOptions::default()
        },
    ];
    for path in common::bundled_graphs() {
        let graph = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        for options in &variants {
            // Material::new validates the module with naga.
            let m = Material::new(&graph, options).unwrap_or_else(|e| panic!("{e}"));
            let src = m.wgsl();
            assert_eq!(
                src.matches("@builtin(position) @invariant clip: vec4<f32>,")
                    .count(),
                1,
                "{}",
                graph.name
            );
            assert!(!src.contains("@builtin(position) clip"));
            let module = naga::front::wgsl::parse_str(src).unwrap();
            let vertex = module
                .entry_points
                .iter()
                .find(|e| e.name == "mg_vertex")
                .unwrap();
            let ty = vertex.function.result.as_ref().unwrap().ty;
            let naga::TypeInner::Struct { members, .. } = &module.types[ty].inner else {
                panic!("MgVertexOut is a struct");
            };
            assert!(
                members.iter().any(|m| m.binding
                    == Some(naga::Binding::BuiltIn(naga::BuiltIn::Position {
                        invariant: true
                    }))),
                "{}: naga reads an invariant position",
                graph.name
            );
        }
    }
}

/// Item 7: every bundled graph's compute module (`matgraph wgsl`'s default entry) binds at
/// most 5 storage buffers (WebGPU's default limit is 8): the attributes in one planar
/// `mg_geometry`, the outputs in `mg_out`, and the three exact texture buffers; counted in
/// naga's module. The WGSL states the layout it reads.
#[test]
fn every_bundled_compute_module_fits_the_default_storage_buffer_limit() {
    let mut widest = 0;
    for path in common::bundled_graphs() {
        let graph = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        let m = generate(
            &graph,
            &WgslOptions {
                entry: Entry::Compute,
                ..Default::default()
            },
        )
        .unwrap();
        let storage: Vec<String> = m
            .module
            .global_variables
            .iter()
            .filter(|(_, v)| matches!(v.space, naga::AddressSpace::Storage { .. }))
            .map(|(_, v)| v.name.clone().unwrap())
            .collect();
        assert!(
            storage.len() <= 5,
            "{}: {} storage buffers {storage:?}",
            graph.name,
            storage.len()
        );
        widest = widest.max(storage.len());
        if !m.attributes.is_empty() {
            assert!(storage.contains(&"mg_geometry".to_owned()));
            // The layout comment names each attribute's offset, which the reads use.
            let offsets: Vec<String> = geometry_layout(&m.attributes)
                .iter()
                .map(|(a, k)| format!("{} {k}", a.name()))
                .collect();
            assert!(
                m.source
                    .contains(&format!("// offsets: {}.\n", offsets.join(", "))),
                "{}",
                graph.name
            );
            for (a, k) in geometry_layout(&m.attributes) {
                assert!(
                    m.source.contains(&format!(
                        "geom.{} = {}(mg_geometry[{k}u * n + i]",
                        a.name(),
                        matgraph::wgsl::wgsl_type(a.ty())
                    )),
                    "{}: {}",
                    graph.name,
                    a.name()
                );
            }
        }
        assert!(
            m.source
                .contains("@group(0) @binding(3) var<storage, read_write> mg_out")
        );
    }
    assert_eq!(
        widest, 5,
        "a graph with textures: geometry, output, 3 texture buffers"
    );
}
