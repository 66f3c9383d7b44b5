//! Issue 38 item 3: the contracts of the library module (`mg_material` for an app's own
//! shader) and of the compute entry (`mg_compute`), from `matgraph wgsl --entry
//! library|compute --contract`: bindings as naga reads the WGSL, the compute entry's
//! geometry offsets and output columns as its reads and writes spell them.

use crate::common;

use matgraph::Registry;
use matgraph::material::ModuleContract;
use matgraph::wgsl::{Entry, ParameterClamp, ShaderModule, TextureMode, WgslOptions, generate};
use std::path::Path;

/// Lanes of a WGSL type, counted from its spelling.
fn lanes(wgsl_type: &str) -> u32 {
    match wgsl_type {
        "f32" | "i32" | "u32" | "bool" => 1,
        t if t.starts_with("vec2") => 2,
        t if t.starts_with("vec3") => 3,
        t if t.starts_with("vec4") => 4,
        t => panic!("unexpected type {t}"),
    }
}

/// `(binding, name, kind)` of every group-0 resource of naga's module, the contract's kind
/// spelled from its address space.
fn naga_bindings(m: &ShaderModule) -> Vec<(u32, String, &'static str)> {
    let mut v: Vec<(u32, String, &'static str)> = m
        .module
        .global_variables
        .iter()
        .filter_map(|(_, g)| {
            let b = g.binding.as_ref()?;
            assert_eq!(b.group, 0);
            let kind = match g.space {
                naga::AddressSpace::Uniform => "uniform-buffer",
                naga::AddressSpace::Storage { access }
                    if access.contains(naga::StorageAccess::STORE) =>
                {
                    "storage-buffer"
                }
                naga::AddressSpace::Storage { .. } => "read-only-storage-buffer",
                _ => match m.module.types[g.ty].inner {
                    naga::TypeInner::Sampler { .. } => "filtering-sampler",
                    _ => "texture-2d-float",
                },
            };
            Some((b.binding, g.name.clone().unwrap(), kind))
        })
        .collect();
    v.sort();
    v
}

fn contract_bindings(c: &ModuleContract) -> Vec<(u32, String, &str)> {
    c.bindings
        .iter()
        .map(|b| (b.binding, b.name.clone(), b.kind.as_str()))
        .collect()
}

#[test]
fn library_and_compute_contracts_match_the_modules_of_every_bundled_graph() {
    for path in common::bundled_graphs() {
        let graph = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        for entry in [
            Entry::Compute,
            Entry::Library(TextureMode::Hardware),
            Entry::Library(TextureMode::Exact),
        ] {
            let m = generate(
                &graph,
                &WgslOptions {
                    entry,
                    ..Default::default()
                },
            )
            .unwrap();
            let c = ModuleContract::new(&graph, &m, ParameterClamp::HardRange);
            let at = format!("{} {}", graph.name, entry.name());
            assert_eq!(c.schema, "matgraph-contract/1");
            assert_eq!(c.module, entry.name(), "{at}");
            assert_eq!(contract_bindings(&c), naga_bindings(&m), "{at}");
            assert!(
                m.module
                    .functions
                    .iter()
                    .any(|(_, f)| f.name.as_deref() == Some("mg_material"))
            );
            assert!(c.per_stage.storage_buffers <= 8, "{at}");
            if entry != Entry::Compute {
                assert_eq!(c.function, "mg_material");
                assert!(c.geometry.iter().all(|g| g.offset.is_none()));
                // Visible to every stage, because nothing in it needs a fragment's quad:
                // no derivative and no texture sample at an implicit level (naga's IR).
                assert!(
                    c.bindings
                        .iter()
                        .all(|b| b.visibility == ["vertex", "fragment", "compute"]),
                    "{at}"
                );
                for (_, f) in m.module.functions.iter() {
                    for (_, e) in f.expressions.iter() {
                        let quad = match e {
                            naga::Expression::Derivative { .. } => true,
                            naga::Expression::ImageSample { level, .. } => matches!(
                                level,
                                naga::SampleLevel::Auto | naga::SampleLevel::Bias(_)
                            ),
                            _ => false,
                        };
                        assert!(!quad, "{at}: {:?} uses {e:?}", f.name);
                    }
                }
                continue;
            }
            assert_eq!(c.function, "mg_compute");
            assert_eq!(c.workgroup_size, Some(64));
            assert!(c.bindings.iter().all(|b| b.visibility == ["compute"]));
            // Offsets: each attribute after the lanes of those before it, and read there.
            let mut lane = 0;
            for g in &c.geometry {
                assert_eq!(g.offset, Some(lane), "{at}: {}", g.name);
                assert!(
                    m.source.contains(&format!(
                        "geom.{} = {}(mg_geometry[{lane}u * n + i]",
                        g.name, g.wgsl_type
                    )),
                    "{at}: {}",
                    g.name
                );
                lane += lanes(&g.wgsl_type);
            }
            assert_eq!(c.geometry_lanes, Some(lane), "{at}");
            // Columns: each output after those before it, written there.
            let mut column = 0;
            for o in &c.outputs {
                assert_eq!(o.column, Some(column), "{at}: {}", o.name);
                let write = format!("mg_out[{column}u * n + i] = ");
                let member = format!("o.{}", o.member);
                assert!(
                    m.source
                        .lines()
                        .any(|l| l.trim_start().starts_with(&write) && l.contains(&member)),
                    "{at}: {}",
                    o.name
                );
                column += lanes(&o.wgsl_type);
            }
            assert_eq!(c.output_columns, Some(column), "{at}");
        }
    }
}

/// The command line writes them (`--entry library|compute --contract`), the same bytes
/// twice, and refuses a contract of the editor's fragment preview.
#[test]
fn wgsl_writes_library_and_compute_contracts() {
    let dir = tempfile::tempdir().unwrap();
    let graph = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/skin.json");
    let run = |entry: &str, name: &str| {
        let json = dir.path().join(name);
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_matgraph"))
            .arg("wgsl")
            .arg(&graph)
            .args(["--entry", entry, "-o"])
            .arg(dir.path().join(format!("{name}.wgsl")))
            .arg("--contract")
            .arg(&json)
            .output()
            .unwrap();
        (out, std::fs::read_to_string(&json).unwrap_or_default())
    };
    for entry in ["library", "compute"] {
        let (out, a) = run(entry, &format!("{entry}_a.json"));
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let (_, b) = run(entry, &format!("{entry}_b.json"));
        assert_eq!(a, b);
        let c: ModuleContract = serde_json::from_str(&a).unwrap();
        assert_eq!(c.module, entry);
        // skin.json's parameters, in the block with their ranges.
        let eta = c
            .parameters
            .members
            .iter()
            .find(|m| m.parameter.as_deref() == Some("eta"))
            .unwrap();
        assert_eq!(eta.hard_range, Some([1.0, 3.0]));
    }
    let (out, _) = run("fragment", "fragment.json");
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--entry render, library or compute"), "{err}");
}

/// docs/integration.md's table of `MgVarying` locations is the emitter's, for every
/// attribute, and the preview module of a graph reading them declares them there.
#[test]
fn the_documented_varying_locations_are_the_fragment_entrys() {
    let doc =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/integration.md"))
            .unwrap();
    let section = doc
        .split("## The fragment preview entry")
        .nth(1)
        .expect("the section")
        .split("\n## ")
        .next()
        .unwrap();
    let mut seen = 0;
    for line in section
        .lines()
        .filter(|l| l.starts_with("| ") && l.contains('`'))
    {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        for pair in cells[1..cells.len() - 1].chunks(2) {
            let [loc, name] = pair else { continue };
            let Ok(loc) = loc.parse::<u32>() else {
                continue;
            };
            let a = matgraph::Attribute::from_name(name.trim_matches('`'))
                .unwrap_or_else(|| panic!("{name}"));
            assert_eq!(matgraph::wgsl::fragment_location(a), loc, "{name}");
            seen += 1;
        }
    }
    assert_eq!(seen, 19, "every attribute is in the table");
    // pbr_gold reads the normal: its preview declares it at location 1.
    let graph = matgraph::io::load_graph(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/pbr_gold.json"),
        Registry::builtin(),
    )
    .unwrap();
    let m = generate(
        &graph,
        &WgslOptions {
            entry: Entry::Fragment,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(
        m.source
            .contains("struct MgVarying {\n    @builtin(position) frag_coord: vec4<f32>,\n")
    );
    assert!(m.source.contains("    @location(1) normal: vec3<f32>,\n"));
}

/// `--downlevel` (issue 38 item 8): a module that fits WebGL2/GLES 3.0 is written; one that
/// does not is refused, naming each limit. bubble_iridescent_fast's parameter block holds
/// `thin_film`'s 471-row table: 32,784 bytes (the measure) > 16,384.
#[test]
fn downlevel_refuses_naming_each_limit_and_passes_what_fits() {
    let dir = tempfile::tempdir().unwrap();
    let run = |graph: &str, entry: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_matgraph"))
            .arg("wgsl")
            .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("graphs/{graph}.json")))
            .args(["--entry", entry, "--downlevel", "-o"])
            .arg(dir.path().join(format!("{graph}_{entry}.wgsl")))
            .output()
            .unwrap()
    };
    let ok = run("skin", "library");
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    let render = run("skin", "render");
    let err = String::from_utf8_lossy(&render.stderr);
    assert!(!render.status.success());
    assert!(
        err.contains("skin.json: the render module does not fit a downlevel device"),
        "{err}"
    );
    assert!(
        err.contains("max_storage_buffers_per_shader_stage 0, the module needs 1"),
        "{err}"
    );
    let bubble = run("bubble_iridescent_fast", "library");
    let err = String::from_utf8_lossy(&bubble.stderr);
    assert!(!bubble.status.success());
    assert!(
        err.contains("max_uniform_buffer_binding_size 16384, the module needs 32784"),
        "{err}"
    );
    let compute = run("skin", "compute");
    let err = String::from_utf8_lossy(&compute.stderr);
    assert!(err.contains("run no compute shaders"), "{err}");
    // The contract states the same needs.
    let graph = matgraph::io::load_graph(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/bubble_iridescent_fast.json"),
        Registry::builtin(),
    )
    .unwrap();
    let m = matgraph::material::Material::new(&graph, &Default::default()).unwrap();
    let limits = m.contract().limits.unwrap();
    assert_eq!(limits.max_uniform_buffer_binding_size, 32_784);
    assert_eq!(limits.max_storage_buffers_per_shader_stage, 1);
    assert_eq!(
        m.library_contract().limits.max_uniform_buffer_binding_size,
        32_784
    );
    // As docs/integration.md says: every bundled library module but that one fits.
    let webgl2 = wgpu::Limits::downlevel_webgl2_defaults();
    let refused: Vec<String> = common::bundled_graphs()
        .iter()
        .filter_map(|p| {
            let g = matgraph::io::load_graph(p, Registry::builtin()).unwrap();
            let m = matgraph::material::Material::new(&g, &Default::default()).unwrap();
            (!m.library_contract().limits.unmet(&webgl2).is_empty()).then_some(g.name)
        })
        .collect();
    assert_eq!(refused, ["bubble_iridescent_fast"]);
}
