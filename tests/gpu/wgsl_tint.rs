//! Tint, the WGSL compiler of Chrome, Edge and every Dawn-based app (an implementation
//! independent of naga), on every bundled graph's module for both entry points (parameters as
//! uniforms and baked; every non-default choice of its declared variants) and on every node type's parity harness (each generic type), through
//! `tests/tint/check.mjs` (Dawn's node bindings, `npm ci --prefix tests/tint`). Without node or
//! the package each test prints `SKIPPED ...`; with `MATGRAPH_REQUIRE_TOOLS` set (CI sets it)
//! it fails instead.

use crate::common;
use common::tint::{Diagnostic, Tint};
use common::{bundled_graphs, print_warning, tool_or_skip};

use matgraph::node::Evaluation;
use matgraph::wgsl::{Entry, ShaderError, WgslOptions, generate, node_harness};
use matgraph::{PlanOptions, Registry, SocketType};
use std::path::PathBuf;

/// The errors among `diagnostics`, after printing the warnings so that they show.
fn errors(test: &str, diagnostics: Vec<Diagnostic>) -> Vec<Diagnostic> {
    let (errors, warnings): (Vec<_>, Vec<_>) =
        diagnostics.into_iter().partition(|d| d.severity == "error");
    for w in &warnings {
        print_warning(test, &w.to_string());
    }
    errors
}

#[test]
fn tint_accepts_every_bundled_graph_for_both_entry_points() {
    const TEST: &str = "tint_accepts_every_bundled_graph_for_both_entry_points";
    let Some(tint) = tool_or_skip(TEST, Tint::find()) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    for path in bundled_graphs() {
        let full = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        // And specialised for its own scene (`matgraph wgsl --specialise`, docs/specialise.md).
        let scene = matgraph::render::graph_scene(&full)
            .unwrap()
            .unwrap_or_else(|| matgraph::scene::Scene::preset("ball").unwrap());
        let specialised = matgraph::specialise::for_scene(&full, &scene, Some(scene.time), true)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            .graph;
        // Parameters as uniforms, and baked into literals (`matgraph wgsl --bake`).
        for (graph, spec, entry, bake) in [Entry::Compute, Entry::Fragment]
            .into_iter()
            .flat_map(|e| [(e, false), (e, true)])
            .flat_map(|(e, b)| [(&full, "", e, b), (&specialised, ".specialised", e, b)])
        {
            let options = WgslOptions {
                entry,
                plan: PlanOptions {
                    bake_parameters: bake,
                    ..Default::default()
                },
                ..Default::default()
            };
            let m = generate(graph, &options)
                .unwrap_or_else(|e| panic!("{}: {entry:?}: {e}", path.display()));
            // Named `graph.entry[.baked].wgsl`: every message names the graph and the entry.
            let baked = if bake { ".baked" } else { "" };
            let name = format!("{}{spec}.{}{baked}.wgsl", graph.name, entry.function());
            let file = dir.path().join(name);
            std::fs::write(&file, &m.source).unwrap();
            files.push(file);
        }
        // Every other choice of each declared variant (the default is the graph above), for
        // both entry points: the WGSL of nodes only a non-default choice reaches.
        // Through the loaded graph, which reads the files its groups name.
        for (variant, decl) in &full.variants() {
            for choice in decl.choices.iter().filter(|c| **c != decl.default) {
                let selection = [(variant.clone(), choice.clone())];
                let graph = full
                    .select(Registry::builtin(), &selection)
                    .unwrap_or_else(|e| panic!("{}: {e:?}", path.display()));
                for entry in [Entry::Compute, Entry::Fragment] {
                    let options = WgslOptions {
                        entry,
                        plan: PlanOptions::default(),
                        ..Default::default()
                    };
                    let m = generate(&graph, &options)
                        .unwrap_or_else(|e| panic!("{}: {entry:?}: {e}", path.display()));
                    let name = format!(
                        "{}.{variant}={choice}.{}.wgsl",
                        graph.name,
                        entry.function()
                    );
                    let file = dir.path().join(name);
                    std::fs::write(&file, &m.source).unwrap();
                    files.push(file);
                }
            }
        }
    }
    let found = errors(TEST, tint.check(&files).unwrap_or_else(|e| panic!("{e}")));
    let report: Vec<String> = found
        .iter()
        .map(|d| {
            let name = d.file.file_name().unwrap().to_string_lossy();
            let source = std::fs::read_to_string(&d.file).unwrap();
            let text = source.lines().nth(d.line.saturating_sub(1) as usize);
            format!(
                "{d}\n    {name} line {}: {}",
                d.line,
                text.unwrap_or("").trim()
            )
        })
        .collect();
    assert!(
        report.is_empty(),
        "Tint rejects {} of {} modules:\n{}",
        report.len(),
        files.len(),
        report.join("\n")
    );
}

/// Every node type's WGSL, in the harness the parity suite runs (one module per node and
/// generic type): nodes no bundled graph uses are compiled by Tint too.
#[test]
fn tint_accepts_every_node_harness() {
    const TEST: &str = "tint_accepts_every_node_harness";
    let Some(tint) = tool_or_skip(TEST, Tint::find()) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    for t in Registry::builtin().types() {
        if t.evaluation() != Evaluation::Compute {
            continue;
        }
        let generics = if t.is_generic() {
            t.generic_types()
                .into_iter()
                .filter(|g| *g != SocketType::Color)
                .collect()
        } else {
            vec![SocketType::Float]
        };
        for g in generics {
            let m = match node_harness(t, g) {
                Ok(m) => m,
                Err(ShaderError::MissingWgsl { .. }) => continue, // gpu_parity reports these
                Err(e) => panic!("{} ({g}): {e}", t.name()),
            };
            let file = dir.path().join(format!("{}.{g}.wgsl", t.name()));
            std::fs::write(&file, &m.source).unwrap();
            files.push(file);
        }
    }
    assert!(files.len() > 50, "only {} harnesses", files.len());
    let found = errors(TEST, tint.check(&files).unwrap_or_else(|e| panic!("{e}")));
    let report: Vec<String> = found.iter().map(|d| d.to_string()).collect();
    assert!(
        report.is_empty(),
        "Tint rejects {} of {} node harnesses:\n{}",
        report.len(),
        files.len(),
        report.join("\n")
    );
}

/// The app contract's modules (docs/integration.md): every bundled graph's render module
/// (Tint compiles it and Dawn builds a render pipeline from its own `mg_vertex` and
/// `mg_fragment` at WebGPU's default limits) and library module, in both texture modes. A
/// binding count over a default per-stage limit fails here: the contract must fit them.
#[test]
fn tint_accepts_every_bundled_graph_as_a_material_at_default_limits() {
    const TEST: &str = "tint_accepts_every_bundled_graph_as_a_material_at_default_limits";
    use matgraph::material::{Material, MaterialOptions};
    use matgraph::wgsl::TextureMode;
    let Some(tint) = checker(TEST) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    for path in bundled_graphs() {
        let graph = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        for mode in [TextureMode::Hardware, TextureMode::Exact] {
            let m = Material::new(
                &graph,
                &MaterialOptions {
                    textures: mode,
                    ..MaterialOptions::default()
                },
            )
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            for (kind, source) in [("render", m.wgsl()), ("library", m.library_wgsl())] {
                let name = format!("{}.{kind}.{}.wgsl", graph.name, mode.name());
                files.push(write(&dir, &name, source));
            }
        }
    }
    let found = tint.check(&files).unwrap_or_else(|e| panic!("{e}"));
    let report: Vec<String> = found.iter().map(|d| d.to_string()).collect();
    assert!(
        report.is_empty(),
        "Tint/Dawn report {} problems in {} modules:\n{}",
        report.len(),
        files.len(),
        report.join("\n")
    );
}

/// Regression: a constant infinity or NaN was `bitcast<f32>(0x7f800000u)`, which Tint's
/// constant evaluator rejects ("value inf cannot be represented as 'f32'"); it is now a call of
/// a helper whose bitcast happens at run time.
#[test]
fn tint_accepts_non_finite_constants() {
    const TEST: &str = "tint_accepts_non_finite_constants";
    let Some(tint) = checker(TEST) else {
        return;
    };
    let graph = matgraph::Graph::from_json(
        r#"{
          "version": 1, "name": "non_finite",
          "nodes": [
            { "id": "huge", "type": "exp", "data_type": "float", "inputs": { "x": 100.0 } },
            { "id": "minus", "type": "mul", "data_type": "float", "inputs": { "a": { "link": "huge.result" }, "b": -1.0 } },
            { "id": "nan", "type": "add", "data_type": "float", "inputs": { "a": { "link": "huge.result" }, "b": { "link": "minus.result" } } }
          ],
          "outputs": [
            { "name": "inf", "from": "huge.result" },
            { "name": "minus_inf", "from": "minus.result" },
            { "name": "nan", "from": "nan.result" }
          ]
        }"#,
        Registry::builtin(),
    )
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    for entry in [Entry::Compute, Entry::Fragment] {
        let m = generate(
            &graph,
            &WgslOptions {
                entry,
                ..Default::default()
            },
        )
        .unwrap();
        assert!(
            m.source.contains("mg_non_finite(0x7f800000u)"),
            "{}",
            m.source
        );
        files.push(write(
            &dir,
            &format!("non_finite.{}.wgsl", entry.function()),
            &m.source,
        ));
    }
    let found = errors(TEST, tint.check(&files).unwrap_or_else(|e| panic!("{e}")));
    assert!(found.is_empty(), "{found:?}");
}

/// The checker, or `None` after the skip line.
fn checker(test: &str) -> Option<Tint> {
    tool_or_skip(test, Tint::find())
}

fn write(dir: &tempfile::TempDir, name: &str, source: &str) -> PathBuf {
    let file = dir.path().join(name);
    std::fs::write(&file, source).unwrap();
    file
}

#[test]
fn tint_checker_reports_an_unrepresentable_literal_where_it_is() {
    let Some(tint) = checker("tint_checker_reports_an_unrepresentable_literal_where_it_is") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    // The normalize template that toon_ball's module carried: 3.4028235e38 as an abstract
    // float exceeds f32::MAX (3.40282347e38).
    let bad = write(
        &dir,
        "old_normalize.wgsl",
        "fn mg_normalize(v: vec3<f32>) -> vec3<f32> {\n    let l = sqrt(dot(v, v));\n    \
         if (l > 0.0 && l <= 3.4028235e38) {\n        return v * (1.0 / l);\n    }\n    \
         return vec3<f32>(0.0);\n}\n",
    );
    let fixed = write(
        &dir,
        "new_normalize.wgsl",
        "fn mg_normalize(v: vec3<f32>) -> vec3<f32> {\n    let l = sqrt(dot(v, v));\n    \
         if (l > 0.0 && l <= 0x1.fffffep+127f) {\n        return v * (1.0 / l);\n    }\n    \
         return vec3<f32>(0.0);\n}\n",
    );
    let got = tint.check(&[bad.clone(), fixed]).unwrap();
    assert_eq!(
        got,
        [Diagnostic {
            file: bad,
            line: 3,
            column: 25,
            severity: "error".into(),
            message: "value 340282349999999991754788743781432688640.0 cannot be represented as \
                      'f32'"
                .into(),
        }],
    );
}

#[test]
fn tint_checker_runs_the_entry_points_pipeline_checks() {
    let Some(tint) = checker("tint_checker_runs_the_entry_points_pipeline_checks") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    // Valid WGSL for Tint, but a workgroup of 1024 invocations exceeds WebGPU's limit (256).
    let wide = write(
        &dir,
        "wide.wgsl",
        "@group(0) @binding(0) var<storage, read_write> o: array<f32>;\n\
         @compute @workgroup_size(1024)\nfn main(@builtin(global_invocation_id) g: vec3<u32>) {\n    \
         o[g.x] = 1.0;\n}\n",
    );
    // A fragment entry whose inputs the checker's vertex stage must write.
    let fragment = write(
        &dir,
        "fragment.wgsl",
        "struct V {\n    @builtin(position) p: vec4<f32>,\n    @location(3) n: vec3<f32>,\n    \
         @location(4) @interpolate(flat) k: u32,\n}\n@fragment\nfn main(v: V) -> @location(0) \
         vec4<f32> {\n    return vec4<f32>(v.n, f32(v.k));\n}\n",
    );
    let got = tint.check(&[wide.clone(), fragment]).unwrap();
    assert_eq!(got.len(), 1, "{got:?}");
    assert_eq!((&got[0].file, got[0].severity.as_str()), (&wide, "error"));
    assert!(got[0].message.contains("1024"), "{}", got[0]);
}
