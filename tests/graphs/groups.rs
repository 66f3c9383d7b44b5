//! Graph format version 2 (`matgraph::group`): node groups inline, from other files and as
//! whole files, nested; reroutes; muted nodes; frames; and every bad input of issue 34.

use crate::common;

use common::parity::{compare_batches_within, graph_bound, grid_batch};
use matgraph::error::GraphError;
use matgraph::plan::{Plan, PlanOptions};
use matgraph::{Graph, GraphDocument, Registry};
use serde_json::json;
use std::path::{Path, PathBuf};

/// Writes `files` (relative path, JSON) into a fresh folder; returns it.
fn folder(files: &[(&str, serde_json::Value)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (name, v) in files {
        let p = dir.path().join(name);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(&p, serde_json::to_string_pretty(v).unwrap()).unwrap();
    }
    dir
}

fn load(path: &Path) -> Result<Graph, String> {
    matgraph::io::load_graph(path, Registry::builtin()).map_err(|e| e.to_string())
}

/// The errors of loading `path`, one a line.
fn errors(path: &Path) -> String {
    match load(path) {
        Ok(_) => panic!("{} loaded", path.display()),
        Err(e) => e,
    }
}

/// Every output of `graph` over the sample grid, as bits.
fn bits(graph: &Graph) -> Vec<Vec<u32>> {
    let plan = Plan::compile(graph, &PlanOptions::default()).unwrap();
    let out = plan
        .execute(&grid_batch(), &plan.default_parameters())
        .unwrap();
    (0..out.names().len())
        .map(|k| out.planar(k).iter().map(|x| x.to_bits()).collect())
        .collect()
}

/// The library of the three-deep graph: `twice` (2 × Schlick through the same file's
/// `schlick`), and a whole file `tint.json` whose parameter `gain` scales a colour.
fn library() -> Vec<(&'static str, serde_json::Value)> {
    vec![
        (
            "lib/layers.json",
            json!({
                "version": 2, "name": "layers", "nodes": [],
                "groups": {
                    "schlick": {
                        "doc": "Schlick's Fresnel.",
                        "inputs": [
                            { "name": "cos_theta", "type": "float", "default": 1.0, "hard_range": [-1.0, 1.0] },
                            { "name": "f0", "type": "float", "default": 0.04, "hard_range": [0.0, 1.0] }
                        ],
                        "nodes": [ { "id": "f", "type": "fresnel_schlick",
                            "inputs": { "cos_theta": { "link": "@in.cos_theta" }, "f0": { "link": "@in.f0" } } } ],
                        "outputs": [ { "name": "reflectance", "from": "f.reflectance" } ]
                    },
                    "twice": {
                        "inputs": [ { "name": "c", "type": "float" }, { "name": "f0", "type": "float", "default": 0.04 } ],
                        "nodes": [
                            { "id": "s", "type": "group", "group": "schlick",
                              "inputs": { "cos_theta": { "link": "@in.c" }, "f0": { "link": "@in.f0" } } },
                            { "id": "m", "type": "mul", "inputs": { "a": { "link": "s.reflectance" }, "b": 2.0 } }
                        ],
                        "outputs": [ { "name": "r", "from": "m.result" } ]
                    }
                }
            }),
        ),
        (
            "lib/tint.json",
            json!({
                "version": 1, "name": "tint",
                "nodes": [
                    { "id": "gain", "type": "parameter", "inputs": { "value": 0.5 } },
                    { "id": "geo", "type": "geometry" },
                    { "id": "m", "type": "mul", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "gain.value" } } }
                ],
                "outputs": [ { "name": "color", "from": "m.result" } ],
                "parameters": [ { "name": "gain", "node": "gain" } ]
            }),
        ),
    ]
}

/// The top graph: inline `outer` → `lib/layers.json#twice` → `schlick` (three deep), and the
/// whole file `lib/tint.json` fed by an outer parameter.
fn grouped() -> serde_json::Value {
    json!({
        "version": 2, "name": "grouped",
        "groups": {
            "outer": {
                "inputs": [ { "name": "x", "type": "float" }, { "name": "f0", "type": "float", "default": 0.04 } ],
                "nodes": [ { "id": "t", "type": "group", "group": "lib/layers.json#twice",
                             "inputs": { "c": { "link": "@in.x" }, "f0": { "link": "@in.f0" } } } ],
                "outputs": [ { "name": "y", "from": "t.r" } ]
            }
        },
        "nodes": [
            { "id": "geo", "type": "geometry" },
            { "id": "cos", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.view" } } },
            { "id": "f0", "type": "parameter", "inputs": { "value": 0.05 } },
            { "id": "g", "type": "group", "group": "outer", "inputs": { "x": { "link": "cos.result" }, "f0": { "link": "f0.value" } } },
            { "id": "k", "type": "group", "group": "outer", "inputs": { "x": 0.25 } },
            { "id": "w", "type": "group", "group": "lib/tint.json", "inputs": { "gain": { "link": "g.y" } } }
        ],
        "outputs": [
            { "name": "y", "from": "g.y" },
            { "name": "k", "from": "k.y" },
            { "name": "tint", "from": "w.color" }
        ],
        "parameters": [ { "name": "f0", "node": "f0" } ]
    })
}

/// The same graph written flat (version 1) by hand.
fn flat_twin() -> serde_json::Value {
    json!({
        "version": 1, "name": "flat",
        "nodes": [
            { "id": "geo", "type": "geometry" },
            { "id": "cos", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.view" } } },
            { "id": "f0", "type": "parameter", "inputs": { "value": 0.05 } },
            { "id": "gf", "type": "fresnel_schlick", "inputs": { "cos_theta": { "link": "cos.result" }, "f0": { "link": "f0.value" } } },
            { "id": "gm", "type": "mul", "inputs": { "a": { "link": "gf.reflectance" }, "b": 2.0 } },
            { "id": "kf", "type": "fresnel_schlick", "inputs": { "cos_theta": 0.25, "f0": 0.04 } },
            { "id": "km", "type": "mul", "inputs": { "a": { "link": "kf.reflectance" }, "b": 2.0 } },
            { "id": "wm", "type": "mul", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "gm.result" } } }
        ],
        "outputs": [
            { "name": "y", "from": "gm.result" },
            { "name": "k", "from": "km.result" },
            { "name": "tint", "from": "wm.result" }
        ],
        "parameters": [ { "name": "f0", "node": "f0" } ]
    })
}

fn done_when_folder() -> tempfile::TempDir {
    let mut files = library();
    files.push(("grouped.json", grouped()));
    files.push(("flat.json", flat_twin()));
    folder(&files)
}

/// Schlick's Fresnel in f64: f0 + (1 − f0)(1 − cosθ)⁵.
fn schlick(cos: f64, f0: f64) -> f64 {
    f0 + (1.0 - f0) * (1.0 - cos.clamp(0.0, 1.0)).powi(5)
}

#[test]
fn a_three_deep_graph_of_inline_cross_file_and_whole_file_groups_matches_its_flat_twin_bit_for_bit()
{
    let dir = done_when_folder();
    let grouped = load(&dir.path().join("grouped.json")).unwrap();
    let flat = load(&dir.path().join("flat.json")).unwrap();
    assert!(grouped.has_groups());
    assert_eq!(bits(&grouped), bits(&flat));

    // And against the closed form: the literal instance is 2 × Schlick(0.25, 0.04).
    let plan = Plan::compile(&grouped, &PlanOptions::default()).unwrap();
    let out = plan
        .execute(&grid_batch(), &plan.default_parameters())
        .unwrap();
    let k = out.index("k").unwrap();
    let want = 2.0 * schlick(0.25, 0.04);
    assert!(
        (out.planar(k)[0] as f64 - want).abs() <= 2e-7 * want,
        "{}",
        out.planar(k)[0]
    );
    // The literal instance folds away entirely: nothing of it runs per sample.
    assert!(
        plan.folded(grouped.output_ref("k/@out:y.output").unwrap())
            .is_some()
    );

    // The outer parameter feeds the group; the contract shows it and no group input.
    let names: Vec<&str> = plan.parameters().iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["f0"]);
    let mut params = plan.default_parameters();
    params.set("f0", matgraph::Value::float(0.5)).unwrap();
    let y = out.index("y").unwrap();
    let again = plan.execute(&grid_batch(), &params).unwrap();
    let batch = grid_batch();
    let (n, v) = (
        batch.column(matgraph::node::Attribute::Normal).unwrap(),
        batch.column(matgraph::node::Attribute::View).unwrap(),
    );
    let len = batch.len();
    for i in [0, 17, 4095, 9000, len - 1] {
        let cos: f64 = (0..3)
            .map(|c| n[c * len + i] as f64 * v[c * len + i] as f64)
            .sum();
        let want = 2.0 * schlick(cos, 0.5);
        let got = again.planar(y)[i] as f64;
        assert!((got - want).abs() <= 1e-6, "sample {i}: {got} vs {want}");
    }
}

#[test]
fn the_three_deep_graph_is_within_the_parity_bound_on_the_gpu() {
    let Some(ctx) =
        common::gpu_context("the_three_deep_graph_is_within_the_parity_bound_on_the_gpu")
    else {
        return;
    };
    let dir = done_when_folder();
    let graph = load(&dir.path().join("grouped.json")).unwrap();
    let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
    let gpu = matgraph::gpu::GpuPlan::compile(ctx, &graph, &PlanOptions::default()).unwrap();
    let batch = grid_batch();
    let params = plan.default_parameters();
    let want = plan.execute(&batch, &params).unwrap();
    let got = gpu.execute(&batch, &params).unwrap();
    let (_, bad) = compare_batches_within(&want, &got, graph_bound(&graph));
    assert!(bad.is_empty(), "{bad:?}");
}

#[test]
fn grouped_graphs_compile_to_naga_valid_wgsl_without_interface_nodes() {
    let dir = done_when_folder();
    let graph = load(&dir.path().join("grouped.json")).unwrap();
    let m = matgraph::wgsl::generate(&graph, &Default::default()).unwrap();
    // Reroutes (the interface) emit nothing: two Schlick calls (the literal instance is
    // folded), two products, the tint.
    assert_eq!(
        m.source.matches("= mg_fresnel_schlick_f32(").count(),
        1,
        "{}",
        m.source
    );
    assert!(!m.source.contains("reroute"), "{}", m.source);
    // Deterministic.
    let again = matgraph::wgsl::generate(&graph, &Default::default()).unwrap();
    assert_eq!(m.source, again.source);
}

#[test]
fn a_graph_with_groups_saves_as_written_and_fmt_keeps_its_version() {
    let dir = done_when_folder();
    let path = dir.path().join("grouped.json");
    let graph = load(&path).unwrap();
    let doc = graph.to_document();
    assert_eq!(doc.version, 2);
    assert!(doc.groups.contains_key("outer"));
    assert_eq!(doc.nodes.len(), 6);
    // load → save → load → save is byte-identical.
    let text = graph.to_json();
    std::fs::write(&path, &text).unwrap();
    assert_eq!(load(&path).unwrap().to_json(), text);

    // `fmt` keeps a version-1 file at version 1, and `--upgrade` moves it to 2.
    let flat = dir.path().join("flat.json");
    let run = |args: &[&str]| {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_matgraph"))
            .args(args)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    run(&["fmt", flat.to_str().unwrap()]);
    let v1 = GraphDocument::parse(&std::fs::read_to_string(&flat).unwrap()).unwrap();
    assert_eq!(v1.version, 1);
    run(&["fmt", "--upgrade", flat.to_str().unwrap()]);
    let v2 = GraphDocument::parse(&std::fs::read_to_string(&flat).unwrap()).unwrap();
    assert_eq!(v2.version, 2);
    assert_eq!(v2.nodes, v1.nodes);
}

#[test]
fn a_version_1_file_with_a_version_2_feature_names_the_feature_and_the_version() {
    for (feature, node) in [
        (
            "nodes of type \"group\"",
            json!({ "id": "g", "type": "group", "group": "x" }),
        ),
        (
            "nodes of type \"reroute\"",
            json!({ "id": "r", "type": "reroute" }),
        ),
        (
            "\"muted\" nodes",
            json!({ "id": "m", "type": "add", "muted": true }),
        ),
    ] {
        let text = json!({ "version": 1, "name": "v1", "nodes": [node] }).to_string();
        let e = Graph::from_json(&text, Registry::builtin()).unwrap_err();
        assert_eq!(
            e[0].to_string(),
            format!(
                "{feature} need format version 2, the file says version 1: set \"version\": 2 (matgraph fmt --upgrade)"
            )
        );
    }
    let text =
        json!({ "version": 1, "name": "v1", "nodes": [], "frames": [{ "id": "f" }] }).to_string();
    assert!(
        Graph::from_json(&text, Registry::builtin()).unwrap_err()[0]
            .to_string()
            .starts_with("\"frames\" need format version 2")
    );
}

/// A graph whose output reads node `n` through what `wire` makes of it.
fn single(nodes: serde_json::Value, from: &str) -> Graph {
    let text = json!({ "version": 2, "name": "t", "nodes": nodes, "outputs": [ { "name": "o", "from": from } ] });
    Graph::from_json(&text.to_string(), Registry::builtin()).unwrap()
}

fn eval_first(graph: &Graph) -> (Vec<f32>, Plan) {
    let plan = Plan::compile(graph, &PlanOptions::default()).unwrap();
    let out = plan
        .execute(&grid_batch(), &plan.default_parameters())
        .unwrap();
    let len = out.len();
    let w = out.ty(0).width();
    ((0..w).map(|c| out.planar(0)[c * len]).collect(), plan)
}

#[test]
fn muted_nodes_follow_blenders_rule_and_cost_nothing() {
    // mix (vec3): the first vec3 input, `a`, passes to `result`.
    let g = single(
        json!([
            { "id": "m", "type": "mix", "muted": true, "inputs": { "a": [0.25, 0.5, 0.75], "b": [1.0, 1.0, 1.0], "t": 0.5 } }
        ]),
        "m.result",
    );
    assert_eq!(eval_first(&g).0, [0.25, 0.5, 0.75]);
    // dot has vec3 inputs and a float output: no input of its type, so its zero.
    let g = single(
        json!([
            { "id": "geo", "type": "geometry" },
            { "id": "d", "type": "dot", "muted": true, "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.view" } } }
        ]),
        "d.result",
    );
    let (v, plan) = eval_first(&g);
    assert_eq!(v, [0.0]);
    assert_eq!(plan.stats().per_sample_steps, 0);
    // sqrt of a linked value passes it on, with no step for the muted node.
    let g = single(
        json!([
            { "id": "geo", "type": "geometry" },
            { "id": "d", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.view" } } },
            { "id": "s", "type": "sqrt", "muted": true, "inputs": { "x": { "link": "d.result" } } },
            { "id": "r1", "type": "reroute", "inputs": { "input": { "link": "s.result" } } },
            { "id": "r2", "type": "reroute", "inputs": { "input": { "link": "r1.output" } } },
            { "id": "n", "type": "negate", "inputs": { "x": { "link": "r2.output" } } }
        ]),
        "n.result",
    );
    let plain = single(
        json!([
            { "id": "geo", "type": "geometry" },
            { "id": "d", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.view" } } },
            { "id": "n", "type": "negate", "inputs": { "x": { "link": "d.result" } } }
        ]),
        "n.result",
    );
    assert_eq!(bits(&g), bits(&plain));
    let steps = |g: &Graph| {
        Plan::compile(g, &PlanOptions::default())
            .unwrap()
            .stats()
            .per_sample_steps
    };
    assert_eq!(steps(&g), steps(&plain));
    let wgsl = matgraph::wgsl::generate(&g, &Default::default())
        .unwrap()
        .source;
    assert!(
        !wgsl.contains("sqrt") && !wgsl.contains("reroute"),
        "{wgsl}"
    );
    // The muted node saves as muted.
    assert!(g.to_json().contains("\"muted\": true"));
}

#[test]
fn a_reroute_takes_the_type_of_what_is_connected() {
    let g = single(
        json!([
            { "id": "c", "type": "constant", "inputs": { "value": [1.0, 2.0] } },
            { "id": "r", "type": "reroute", "inputs": { "input": { "link": "c.value" } } }
        ]),
        "r.output",
    );
    assert_eq!(g.outputs()[0].ty, matgraph::types::SocketType::Vec2);
    assert_eq!(eval_first(&g).0, [1.0, 2.0]);
}

#[test]
fn frames_are_layout_only_and_checked() {
    let nodes = json!([{ "id": "c", "type": "constant", "inputs": { "value": 0.5 } }]);
    let with = json!({ "version": 2, "name": "t", "nodes": nodes,
        "frames": [ { "id": "f", "label": "Inputs", "nodes": ["c"], "color": [0.2, 0.4, 0.6] } ],
        "outputs": [ { "name": "o", "from": "c.value" } ] });
    let g = Graph::from_json(&with.to_string(), Registry::builtin()).unwrap();
    assert_eq!(eval_first(&g).0, [0.5]);
    let saved = g.to_json();
    assert!(saved.contains("\"label\": \"Inputs\""), "{saved}");
    let mut bad = with.clone();
    bad["frames"][0]["nodes"] = json!(["cc"]);
    let e = Graph::from_json(&bad.to_string(), Registry::builtin()).unwrap_err();
    assert_eq!(
        e[0].to_string(),
        "frame 'f': holds node 'cc', which does not exist (did you mean 'c'?)"
    );
}

/// A graph file `g.json` with one instance `i` of `group`, in a folder with `files`.
fn instance_of(
    group: &str,
    inputs: serde_json::Value,
    groups: serde_json::Value,
    files: &[(&'static str, serde_json::Value)],
) -> (tempfile::TempDir, PathBuf) {
    let mut all = files.to_vec();
    all.push((
        "g.json",
        json!({ "version": 2, "name": "g", "groups": groups,
            "nodes": [ { "id": "i", "type": "group", "group": group, "inputs": inputs } ],
            "outputs": [ { "name": "o", "from": "i.y" } ] }),
    ));
    let dir = folder(&all);
    let path = dir.path().join("g.json");
    (dir, path)
}

fn pass_group(input: serde_json::Value) -> serde_json::Value {
    json!({ "p": {
        "inputs": [ input ],
        "nodes": [ { "id": "n", "type": "negate", "inputs": { "x": { "link": "@in.x" } } } ],
        "outputs": [ { "name": "y", "from": "n.result" } ]
    } })
}

#[test]
fn every_bad_group_reference_is_a_clear_error() {
    let x = json!({ "name": "x", "type": "float" });
    let cases: Vec<(&str, serde_json::Value, serde_json::Value, &str)> = vec![
        (
            "q",
            json!({}),
            pass_group(x.clone()),
            "g.json: node 'i': group 'q': no group 'q' in this file",
        ),
        (
            "lib/none.json#p",
            json!({}),
            json!({}),
            "g.json: node 'i': group 'lib/none.json#p': cannot read",
        ),
        (
            "lib/layers.json#nope",
            json!({}),
            json!({}),
            "g.json: node 'i': group 'lib/layers.json#nope': no group 'nope' in lib/layers.json",
        ),
        (
            "p",
            json!({ "z": 1.0 }),
            pass_group(x.clone()),
            "g.json: node 'i': unknown input 'z'",
        ),
        (
            "p",
            json!({ "x": [1.0, 2.0] }),
            pass_group(x.clone()),
            "g.json: node 'i': input 'x': expected float, found [1.0,2.0]",
        ),
        (
            "p",
            json!({ "x": 3.0 }),
            pass_group(json!({ "name": "x", "type": "float", "hard_range": [0.0, 1.0] })),
            "g.json: node 'i': input 'x': value 3.0 is outside [0, 1]",
        ),
        (
            "p",
            json!({}),
            pass_group(json!({ "name": "x", "type": "matrix" })),
            "g.json: group 'p': input 'x': type 'matrix' is not one of float, vec2, vec3, vec4, color",
        ),
        (
            "p",
            json!({}),
            pass_group(
                json!({ "name": "x", "type": "float", "default": 2.0, "hard_range": [0.0, 1.0] }),
            ),
            "g.json: group 'p': input 'x': default 2.0 is outside its hard_range [0, 1]",
        ),
        (
            "p",
            json!({}),
            pass_group(json!({ "name": "x", "type": "vec3", "default": true })),
            "g.json: group 'p': input 'x': default true is not a vec3",
        ),
        (
            "p",
            json!({}),
            json!({ "p": { "inputs": [x.clone()],
            "nodes": [ { "id": "n", "type": "negate", "inputs": { "x": { "link": "@in.w" } } } ],
            "outputs": [ { "name": "y", "from": "n.result" } ] } }),
            "g.json: node 'i' (group p) → node 'n': input 'x': link to '@in.w': group g.json#p has no input 'w'",
        ),
        (
            "p",
            json!({}),
            json!({ "p": { "inputs": [x.clone()],
            "nodes": [ { "id": "n", "type": "negate", "inputs": { "x": { "link": "@in.x" }, "k": 1 } } ],
            "outputs": [ { "name": "y", "from": "n.result" } ] } }),
            "g.json: node 'i' (group p) → node 'n': unknown input 'k'",
        ),
    ];
    let lib = [("lib/layers.json", library()[0].1.clone())];
    for (group, inputs, groups, want) in cases {
        let (_dir, path) = instance_of(group, inputs, groups, &lib);
        let e = errors(&path);
        let shown = e.replace(&format!("{}", path.display()), "g.json");
        assert!(
            shown.starts_with(want),
            "{group}: got\n{shown}\nwant\n{want}"
        );
    }
    // `@in` outside a group.
    let dir = folder(&[(
        "g.json",
        json!({ "version": 2, "name": "g",
            "nodes": [ { "id": "n", "type": "negate", "inputs": { "x": { "link": "@in.x" } } } ] }),
    )]);
    let e = errors(&dir.path().join("g.json"));
    assert!(
        e.ends_with(
            "node 'n': input 'x': '@in.x' reads a group's input, and this is not inside a group"
        ),
        "{e}"
    );
    // A link to an output the group does not have.
    let (_dir, path) = instance_of("p", json!({}), pass_group(x), &[]);
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    doc["outputs"][0]["from"] = json!("i.yy");
    std::fs::write(&path, doc.to_string()).unwrap();
    let e = errors(&path);
    assert!(
        e.ends_with("graph output 'o': link to 'i.yy': group node 'i' has no output 'yy' (did you mean 'y'?)"),
        "{e}"
    );
}

#[test]
fn a_group_from_a_file_outside_the_graphs_folder_needs_the_flag() {
    let dir = folder(&[
        ("lib/layers.json", library()[0].1.clone()),
        (
            "sub/g.json",
            json!({ "version": 2, "name": "g",
                "nodes": [ { "id": "i", "type": "group", "group": "../lib/layers.json#schlick" } ],
                "outputs": [ { "name": "o", "from": "i.reflectance" } ] }),
        ),
    ]);
    let path = dir.path().join("sub/g.json");
    let e = errors(&path);
    assert!(
        e.contains("outside the graph's folder") && e.contains("--allow-outside-paths"),
        "{e}"
    );
    let g = matgraph::io::load_graph_with(
        &path,
        Registry::builtin(),
        matgraph::io::PathPolicy::Anywhere,
    )
    .unwrap();
    assert_eq!(eval_first(&g).0, [0.04]);
}

#[test]
fn a_group_that_reaches_itself_through_files_names_the_chain() {
    let dir = folder(&[
        (
            "a.json",
            json!({ "version": 2, "name": "a",
                "groups": { "x": { "nodes": [ { "id": "u", "type": "group", "group": "b.json#y" } ] } },
                "nodes": [ { "id": "top", "type": "group", "group": "x" } ] }),
        ),
        (
            "b.json",
            json!({ "version": 2, "name": "b",
                "groups": { "y": { "nodes": [ { "id": "v", "type": "group", "group": "a.json#x" } ] } },
                "nodes": [] }),
        ),
    ]);
    let e = errors(&dir.path().join("a.json"));
    assert!(
        e.ends_with("group recursion: a.json#x → b.json#y → a.json#x"),
        "{e}"
    );
    // A whole file that uses itself.
    let dir = folder(&[(
        "w.json",
        json!({ "version": 2, "name": "w", "nodes": [ { "id": "me", "type": "group", "group": "w.json" } ] }),
    )]);
    let e = errors(&dir.path().join("w.json"));
    assert!(
        e.ends_with("group recursion: w.json → w.json") || e.contains("group recursion"),
        "{e}"
    );
}

/// `depth` groups, each using the next.
fn nested(depth: usize) -> serde_json::Value {
    let mut groups = serde_json::Map::new();
    for d in 0..depth {
        let nodes = if d + 1 == depth {
            json!([ { "id": "n", "type": "negate", "inputs": { "x": { "link": "@in.x" } } } ])
        } else {
            json!([ { "id": "n", "type": "group", "group": format!("g{}", d + 1), "inputs": { "x": { "link": "@in.x" } } } ])
        };
        let from = if d + 1 == depth { "n.result" } else { "n.y" };
        groups.insert(
            format!("g{d}"),
            json!({ "inputs": [ { "name": "x", "type": "float", "default": 0.5 } ], "nodes": nodes,
                    "outputs": [ { "name": "y", "from": from } ] }),
        );
    }
    json!({ "version": 2, "name": "deep", "groups": groups,
        "nodes": [ { "id": "top", "type": "group", "group": "g0" } ],
        "outputs": [ { "name": "o", "from": "top.y" } ] })
}

#[test]
fn ten_thousand_nested_levels_are_a_clear_error_and_sixty_four_a_result() {
    let text = nested(10_000).to_string();
    let e = Graph::from_json(&text, Registry::builtin()).unwrap_err();
    assert_eq!(e.len(), 1, "{e:?}");
    let shown = e[0].to_string();
    assert!(
        shown.starts_with("node 'top' (group g0) → node 'n' (group g1) →"),
        "{}",
        &shown[..200]
    );
    assert!(
        shown.ends_with("node 'n': groups nest deeper than 64 levels (through g64)"),
        "{}",
        &shown[shown.len() - 200..]
    );
    assert!(matches!(e[0], GraphError::InGroup { .. }));
    // At the limit it evaluates: the innermost negation of the outermost default.
    let g = Graph::from_json(&nested(64).to_string(), Registry::builtin()).unwrap();
    assert_eq!(eval_first(&g).0, [-0.5]);
}

#[test]
fn a_hundred_thousand_instances_load_plan_and_evaluate() {
    let n = 100_000;
    let mut nodes = vec![json!({ "id": "geo", "type": "geometry" })];
    let mut prev = "geo.normal".to_owned();
    for k in 0..n {
        nodes.push(json!({ "id": format!("i{k}"), "type": "group", "group": "p", "inputs": { "x": { "link": prev } } }));
        prev = format!("i{k}.y");
    }
    let doc = json!({ "version": 2, "name": "many",
        "groups": { "p": {
            "inputs": [ { "name": "x", "type": "vec3" } ],
            "nodes": [ { "id": "n", "type": "negate", "inputs": { "x": { "link": "@in.x" } } } ],
            "outputs": [ { "name": "y", "from": "n.result" } ] } },
        "nodes": nodes, "outputs": [ { "name": "o", "from": prev } ] });
    let g = Graph::from_json(&doc.to_string(), Registry::builtin()).unwrap();
    // Each instance is its node and its two interface reroutes.
    assert_eq!(g.nodes().len(), 1 + 3 * n);
    let plan = Plan::compile(&g, &PlanOptions::default()).unwrap();
    assert_eq!(plan.stats().per_sample_steps, n);
    let mut batch = matgraph::exec::SampleBatch::new(4);
    batch
        .set_values(
            matgraph::node::Attribute::Normal,
            &[
                [1.0, -2.0, 0.5],
                [0.0, 0.0, 1.0],
                [3.0, 4.0, 5.0],
                [-1.0, 0.25, 8.0],
            ],
        )
        .unwrap();
    let out = plan.execute(&batch, &plan.default_parameters()).unwrap();
    // An even number of negations: the normal itself.
    assert_eq!(&out.planar(0)[..4], &[1.0, 0.0, 3.0, -1.0]);
}

#[test]
fn a_switch_inside_a_group_is_resolved_in_every_instance() {
    let doc = json!({ "version": 2, "name": "v",
        "variants": { "fresnel": { "choices": ["schlick", "exact"], "default": "schlick" } },
        "groups": { "f": {
            "inputs": [ { "name": "c", "type": "float" } ],
            "nodes": [
                { "id": "s", "type": "fresnel_schlick", "inputs": { "cos_theta": { "link": "@in.c" }, "f0": 0.04 } },
                { "id": "e", "type": "fresnel_dielectric", "inputs": { "cos_theta": { "link": "@in.c" }, "ior_inside": 1.5 } },
                { "id": "w", "type": "switch", "variant": "fresnel",
                  "inputs": { "schlick": { "link": "s.reflectance" }, "exact": { "link": "e.reflectance" } } }
            ],
            "outputs": [ { "name": "r", "from": "w.result" } ] } },
        "nodes": [
            { "id": "a", "type": "group", "group": "f", "inputs": { "c": 0.5 } },
            { "id": "b", "type": "group", "group": "f", "inputs": { "c": 0.9 } }
        ],
        "outputs": [ { "name": "a", "from": "a.r" }, { "name": "b", "from": "b.r" } ] });
    let parsed = GraphDocument::parse(&doc.to_string()).unwrap();
    let first = |g: &Graph| {
        let plan = Plan::compile(g, &PlanOptions::default()).unwrap();
        let out = plan
            .execute(&grid_batch(), &plan.default_parameters())
            .unwrap();
        [out.planar(0)[0] as f64, out.planar(1)[0] as f64]
    };
    let schlick_graph = Graph::from_document(&parsed, Registry::builtin()).unwrap();
    let [a, b] = first(&schlick_graph);
    assert!((a - schlick(0.5, 0.04)).abs() < 1e-7 && (b - schlick(0.9, 0.04)).abs() < 1e-7);
    let exact = schlick_graph
        .select(Registry::builtin(), &[("fresnel".into(), "exact".into())])
        .unwrap();
    let [a, b] = first(&exact);
    // Exact dielectric Fresnel in f64 (unpolarised, n = 1.5).
    let fresnel = |c: f64| {
        let g = (1.5f64 * 1.5 - 1.0 + c * c).sqrt();
        let r = (g - c) / (g + c);
        let t = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
        0.5 * r * r * (1.0 + t * t)
    };
    assert!((a - fresnel(0.5)).abs() < 1e-6, "{a} vs {}", fresnel(0.5));
    assert!((b - fresnel(0.9)).abs() < 1e-6, "{b} vs {}", fresnel(0.9));
}

/// A group `coat` of a dozen nodes: exact Fresnel of the view, the base blended towards the
/// coat by it, lit by N·L (so it reads the light); `n` instances in a chain, each coating
/// the last, `literal` of them with every input a literal.
fn coat_chain(n: usize, literal: usize) -> serde_json::Value {
    coat_chain_with(n, literal, false)
}

/// [`coat_chain`], where `distinct` gives every instance its own coat colour (so that no
/// two calls pass alike but for the last one's result: no loop, a call each).
fn coat_chain_with(n: usize, literal: usize, distinct: bool) -> serde_json::Value {
    let mut nodes = vec![
        json!({ "id": "geo", "type": "geometry" }),
        json!({ "id": "cos", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.view" } } }),
        json!({ "id": "ior", "type": "parameter", "inputs": { "value": 1.45 } }),
    ];
    let mut prev = json!([0.2, 0.3, 0.4]);
    for k in 0..n {
        let inputs = if k < literal {
            json!({ "cos_theta": 0.5, "ior": 1.3, "base": [0.1, 0.2, 0.3], "coat": [0.9, 0.8, 0.7] })
        } else {
            let coat = if distinct {
                let t = k as f64 / 64.0;
                json!([0.9 - 0.5 * t, 0.8, 0.2 + 0.5 * t])
            } else {
                json!([0.9, 0.8, 0.7])
            };
            json!({ "cos_theta": { "link": "cos.result" }, "ior": { "link": "ior.value" },
                    "base": prev, "coat": coat })
        };
        nodes.push(
            json!({ "id": format!("c{k}"), "type": "group", "group": "coat", "inputs": inputs }),
        );
        if k >= literal {
            prev = json!({ "link": format!("c{k}.color") });
        }
    }
    let last = format!("c{}.color", n - 1);
    let mut outputs = vec![json!({ "name": "color", "from": last })];
    if literal > 0 {
        outputs.push(json!({ "name": "literal", "from": "c0.fresnel" }));
    }
    json!({ "version": 2, "name": "coats",
        "groups": { "coat": {
            "doc": "A clear coat over a base, weighted by exact Fresnel and lit by N·L.",
            "inputs": [
                { "name": "cos_theta", "type": "float", "default": 1.0, "hard_range": [-1.0, 1.0] },
                { "name": "ior", "type": "float", "default": 1.5, "hard_range": [1.0, 3.0] },
                { "name": "base", "type": "color" },
                { "name": "coat", "type": "color", "default": [1.0, 1.0, 1.0] }
            ],
            "nodes": [
                { "id": "f", "type": "fresnel_dielectric", "inputs": { "cos_theta": { "link": "@in.cos_theta" }, "ior_inside": { "link": "@in.ior" } } },
                { "id": "r", "type": "reroute", "inputs": { "input": { "link": "f.reflectance" } } },
                { "id": "m", "type": "mix", "inputs": { "a": { "link": "@in.base" }, "b": { "link": "@in.coat" }, "t": { "link": "r.output" } } },
                { "id": "geo", "type": "geometry" },
                { "id": "ndl", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.light" } } },
                { "id": "lit", "type": "saturate", "inputs": { "x": { "link": "ndl.result" } } },
                { "id": "k", "type": "mul", "inputs": { "a": { "link": "m.result" }, "b": { "link": "lit.result" } } },
                { "id": "amb", "type": "mul", "inputs": { "a": { "link": "m.result" }, "b": 0.1 } },
                { "id": "sum", "type": "add", "inputs": { "a": { "link": "k.result" }, "b": { "link": "amb.result" } } }
            ],
            "outputs": [ { "name": "color", "from": "sum.result" }, { "name": "fresnel", "from": "r.output" } ]
        } },
        "nodes": nodes, "outputs": outputs,
        "parameters": [ { "name": "ior", "node": "ior" } ] })
}

fn coat_graph(n: usize, literal: usize) -> Graph {
    Graph::from_json(&coat_chain(n, literal).to_string(), Registry::builtin()).unwrap()
}

fn wgsl(graph: &Graph, entry: matgraph::wgsl::Entry) -> String {
    let options = matgraph::wgsl::WgslOptions {
        entry,
        ..Default::default()
    };
    matgraph::wgsl::generate(graph, &options)
        .unwrap_or_else(|e| panic!("{e}"))
        .source
}

/// How a chain of instances of a library group is wired: its reference, the input that
/// takes the last instance's output (and that output), and the other inputs' links.
struct LibraryChain {
    group: &'static str,
    chained: (&'static str, &'static str),
    first: serde_json::Value,
    others: serde_json::Value,
}

/// A chain for each group of `graphs/lib/`: each instance's `chained` input reads the last
/// one's output, the first's reads `first`, and the others read the geometry (so that no
/// instance folds to a constant).
fn library_chains() -> Vec<LibraryChain> {
    let n = json!({ "link": "geo.normal" });
    let (l, v) = (
        json!({ "link": "geo.light" }),
        json!({ "link": "geo.view" }),
    );
    let cos = json!({ "link": "cos.result" });
    let uv = json!({ "link": "geo.uv" });
    let chain = |group, chained, first, others| LibraryChain {
        group,
        chained,
        first,
        others,
    };
    vec![
        chain(
            "fresnel.json#fresnel_layer",
            ("base", "color"),
            json!([0.2, 0.3, 0.4]),
            json!({ "cos_theta": cos, "coat": [0.9, 0.8, 0.7], "ior": 1.45 }),
        ),
        chain(
            "fresnel.json#fresnel_pair",
            ("cos_theta", "exact"),
            cos.clone(),
            json!({ "ior": 1.45 }),
        ),
        chain(
            "water.json#gerstner_wave_set",
            ("position", "offset"),
            json!({ "link": "geo.position" }),
            json!({ "time": 1.5 }),
        ),
        chain(
            "water.json#noise_distortion",
            ("screen_uv", "uv"),
            uv.clone(),
            json!({ "position": { "link": "geo.position" } }),
        ),
        chain(
            "water.json#screen_distortion",
            ("screen_uv", "uv"),
            uv,
            json!({ "normal": n }),
        ),
        chain(
            "toon.json#toon_highlight",
            ("threshold", "band"),
            json!(0.5),
            json!({ "normal": n, "light": l, "view": v }),
        ),
        chain(
            "toon.json#toon_ramp",
            ("color_dark", "color"),
            json!([0.1, 0.1, 0.2]),
            json!({ "normal": n, "light": l }),
        ),
        chain(
            "thin_film.json#thin_film_coat",
            ("reflected", "color"),
            json!([0.9, 0.9, 0.9]),
            json!({ "cos_theta": cos, "transmitted": [0.1, 0.1, 0.1] }),
        ),
    ]
}

/// `n` instances of `chain`'s group, in a folder with the library.
fn library_chain(chain: &LibraryChain, n: usize) -> (tempfile::TempDir, Graph) {
    let mut nodes = vec![
        json!({ "id": "geo", "type": "geometry" }),
        json!({ "id": "cos", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.view" } } }),
    ];
    let mut prev = chain.first.clone();
    let mut last = String::new();
    for k in 0..n {
        let mut inputs = chain.others.clone();
        inputs[chain.chained.0] = prev;
        nodes.push(json!({ "id": format!("g{k}"), "type": "group",
            "group": format!("lib/{}", chain.group), "inputs": inputs }));
        last = format!("g{k}.{}", chain.chained.1);
        prev = json!({ "link": last });
    }
    let mut files: Vec<(String, serde_json::Value)> = Vec::new();
    for lib in ["fresnel", "water", "toon", "thin_film"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("graphs/lib/{lib}.json"));
        let text = std::fs::read_to_string(path).unwrap();
        files.push((
            format!("lib/{lib}.json"),
            serde_json::from_str(&text).unwrap(),
        ));
    }
    files.push((
        "g.json".into(),
        json!({ "version": 2, "name": "chain", "nodes": nodes,
            "outputs": [ { "name": "color", "from": last } ] }),
    ));
    let files: Vec<(&str, serde_json::Value)> =
        files.iter().map(|(n, v)| (n.as_str(), v.clone())).collect();
    let dir = folder(&files);
    let graph = load(&dir.path().join("g.json")).unwrap_or_else(|e| panic!("{e}"));
    (dir, graph)
}

#[test]
fn fifty_instances_of_a_group_are_one_function_and_one_loop_or_fifty_calls() {
    use matgraph::wgsl::Entry;
    for entry in [Entry::Compute, Entry::Render(Default::default())] {
        let one = wgsl(&coat_graph(1, 0), entry);
        let fifty = wgsl(&coat_graph(50, 0), entry);
        // One instance is inlined (nothing to share); fifty share one function.
        assert!(!one.contains("fn mg_group_"), "{one}");
        assert_eq!(fifty.matches("fn mg_group_").count(), 1, "{fifty}");
        // Each passes the last one's colour on, all else alike: one loop of 50 calls.
        assert_eq!(fifty.matches("= mg_group_0_coat(").count(), 2, "{fifty}");
        assert!(fifty.contains("mg_k < 50u; mg_k += 1u"), "{fifty}");
        // What every call passes alike (the IOR parameter, the coat colour, the geometry)
        // is in the body, not in the calls (the IOR read clamped to the hard range of
        // the fresnel input it feeds, [0.001, 100]).
        assert!(
            fifty.contains(
                "mg_fresnel_dielectric(a0_cos_theta, 1.0, clamp(mg_params.ior, 0.001, 100.0))"
            ),
            "{fifty}"
        );
        let ratio = fifty.len() as f64 / one.len() as f64;
        assert!(
            ratio <= 1.5,
            "{entry:?}: {} / {} bytes = {ratio:.2}",
            fifty.len(),
            one.len()
        );
        // Each its own coat colour: fifty calls, each instance one line (its body's ten
        // lines are in the function once).
        let distinct = Graph::from_json(
            &coat_chain_with(50, 0, true).to_string(),
            Registry::builtin(),
        )
        .unwrap();
        let distinct = wgsl(&distinct, entry);
        assert_eq!(
            distinct.matches("= mg_group_0_coat(").count(),
            50,
            "{distinct}"
        );
        assert!(!distinct.contains("mg_k"), "{distinct}");
        let per_instance = (distinct.len() - one.len()) as f64 / 49.0;
        assert!(
            per_instance <= 120.0,
            "{entry:?}: {per_instance:.0} bytes an instance"
        );
        // Every group of the library, chained 50 times: within 1.5× of one instance.
        for chain in library_chains() {
            let (_one_dir, one) = library_chain(&chain, 1);
            let (_fifty_dir, fifty) = library_chain(&chain, 50);
            let (one, fifty) = (wgsl(&one, entry), wgsl(&fifty, entry));
            assert!(fifty.contains("mg_k < 50u"), "{}: {fifty}", chain.group);
            let ratio = fifty.len() as f64 / one.len() as f64;
            assert!(
                ratio <= 1.5,
                "{} {entry:?}: {} / {} bytes = {ratio:.2}",
                chain.group,
                fifty.len(),
                one.len()
            );
        }
    }
    // In a render module the calls read the light: the lit part makes them.
    let render = wgsl(&coat_graph(50, 0), Entry::Render(Default::default()));
    let lit = &render[render.find("fn mg_material_lit").unwrap_or(0)..];
    assert!(lit.contains("= mg_group_0_coat("), "{render}");
}

#[test]
fn called_instances_match_the_cpu_within_the_parity_bound() {
    let Some(ctx) = common::gpu_context("called_instances_match_the_cpu_within_the_parity_bound")
    else {
        return;
    };
    // 40 linked instances (a loop of calls), 3 with literal inputs (folded on the CPU and in
    // the module alike); 40 each with its own coat (a call each); and 300 (a split material
    // function, its calls in part functions).
    for (n, literal, distinct) in [(40, 3, false), (40, 0, true), (300, 0, false)] {
        let graph = Graph::from_json(
            &coat_chain_with(n, literal, distinct).to_string(),
            Registry::builtin(),
        )
        .unwrap();
        let source = wgsl(&graph, Default::default());
        // A chain of like calls is a loop; calls each with their own coat are not.
        assert_eq!(source.contains("mg_k <"), !distinct && n <= 256, "{source}");
        assert_eq!(source.matches("fn mg_group_").count(), 1);
        if n > 256 {
            assert!(source.contains("fn mg_part_0("), "not split");
        }
        let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
        let gpu = matgraph::gpu::GpuPlan::compile(ctx, &graph, &PlanOptions::default()).unwrap();
        let batch = grid_batch();
        let params = plan.default_parameters();
        let want = plan.execute(&batch, &params).unwrap();
        let got = gpu.execute(&batch, &params).unwrap();
        let (_, bad) = compare_batches_within(&want, &got, graph_bound(&graph));
        assert!(bad.is_empty(), "{n} instances: {bad:?}");
    }
}

#[test]
fn chains_of_every_library_group_written_as_loops_match_the_cpu() {
    let Some(ctx) =
        common::gpu_context("chains_of_every_library_group_written_as_loops_match_the_cpu")
    else {
        return;
    };
    // Each chain is a loop in the module (its group's function, or for a group of one
    // used node that node's, called 50 times): the values of the unrolled calls.
    for chain in library_chains() {
        let (_dir, graph) = library_chain(&chain, 50);
        let source = wgsl(&graph, Default::default());
        assert!(source.contains("mg_k < 50u"), "{}: {source}", chain.group);
        let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
        let gpu = matgraph::gpu::GpuPlan::compile(ctx, &graph, &PlanOptions::default())
            .unwrap_or_else(|e| panic!("{}: {e}", chain.group));
        let batch = grid_batch();
        let params = plan.default_parameters();
        let want = plan.execute(&batch, &params).unwrap();
        let got = gpu.execute(&batch, &params).unwrap();
        let (_, bad) = compare_batches_within(&want, &got, graph_bound(&graph));
        assert!(bad.is_empty(), "{}: {bad:?}", chain.group);
    }
}

#[test]
fn a_grouped_graph_evaluates_like_the_closed_form_of_its_body() {
    // One instance, all literal: 0.1·m + m·sat(N·L) with m = base + (coat − base)·F.
    let graph = coat_graph(2, 1);
    let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
    let out = plan
        .execute(&grid_batch(), &plan.default_parameters())
        .unwrap();
    let k = out.index("literal").unwrap();
    // Exact dielectric Fresnel in f64 at cosθ = 0.5, n = 1.3.
    let (c, n) = (0.5f64, 1.3f64);
    let g = (n * n - 1.0 + c * c).sqrt();
    let f = 0.5
        * ((g - c) / (g + c)).powi(2)
        * (1.0 + ((c * (g + c) - 1.0) / (c * (g - c) + 1.0)).powi(2));
    assert!(
        (out.planar(k)[0] as f64 - f).abs() < 1e-6,
        "{} vs {f}",
        out.planar(k)[0]
    );
}

#[test]
fn tint_accepts_modules_with_group_functions() {
    const TEST: &str = "tint_accepts_modules_with_group_functions";
    let Some(tint) = common::tool_or_skip(TEST, common::tint::Tint::find()) else {
        return;
    };
    use matgraph::wgsl::Entry;
    let dir = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    let distinct = Graph::from_json(
        &coat_chain_with(40, 0, true).to_string(),
        Registry::builtin(),
    )
    .unwrap();
    for (name, graph) in [
        ("chain", coat_graph(40, 3)),
        ("calls", distinct),
        ("split", coat_graph(300, 0)),
    ] {
        for entry in [
            Entry::Compute,
            Entry::Fragment,
            Entry::Render(Default::default()),
        ] {
            let source = wgsl(&graph, entry);
            assert!(source.contains("fn mg_group_0_coat("));
            let file = dir.path().join(format!("{name}.{}.wgsl", entry.function()));
            std::fs::write(&file, source).unwrap();
            files.push(file);
        }
    }
    let errors: Vec<String> = tint
        .check(&files)
        .unwrap_or_else(|e| panic!("{e}"))
        .into_iter()
        .filter(|d| d.severity == "error")
        .map(|d| d.to_string())
        .collect();
    assert!(errors.is_empty(), "{errors:#?}");
}

#[test]
fn a_frame_may_hold_a_group_instance() {
    let mut doc = coat_chain(2, 0);
    doc["frames"] = json!([{ "id": "coats", "label": "Coats", "nodes": ["c0", "c1", "cos"] }]);
    let g = Graph::from_json(&doc.to_string(), Registry::builtin()).unwrap();
    assert_eq!(g.to_document().frames[0].nodes, ["c0", "c1", "cos"]);
}

/// Blender's rule for a muted node, written from the node's declared ports: output `k`
/// passes the first input of its type.
fn first_of_type(
    t: &matgraph::node::NodeType,
    g: matgraph::types::SocketType,
    k: usize,
) -> Option<usize> {
    let want = t.outputs()[k].ty.resolve(g);
    t.inputs().iter().position(|i| i.ty.resolve(g) == want)
}

#[test]
fn every_muted_node_type_passes_its_first_input_of_each_outputs_type() {
    use matgraph::node::Evaluation;
    use matgraph::types::SocketType;
    let mut rng = common::rng::Rng(0x5eed_0034);
    let mut checked = 0;
    for t in Registry::builtin().types() {
        if matches!(
            t.evaluation(),
            Evaluation::Parameter | Evaluation::Texture | Evaluation::Attributes(_)
        ) {
            continue;
        }
        let g = t
            .generic_types()
            .into_iter()
            .max_by_key(|t| t.width())
            .unwrap_or(SocketType::Float);
        // Every input a seeded literal of its type (enum inputs keep their defaults).
        let mut inputs = serde_json::Map::new();
        let mut written: Vec<Option<matgraph::Value>> = Vec::new();
        for i in t.inputs() {
            let ty = i.ty.resolve(g);
            if !i.choices.is_empty() || matches!(ty, SocketType::Int | SocketType::Bool) {
                written.push(None);
                continue;
            }
            // Seeded, within the input's soft (else hard) range.
            let r = i.soft.or(i.hard).unwrap_or(matgraph::node::Range {
                min: -0.5,
                max: 1.5,
            });
            let lanes: Vec<f32> = (0..ty.width())
                .map(|_| {
                    let u = (rng.next() >> 40) as f32 / (1u64 << 24) as f32;
                    (r.min + u * (r.max - r.min)).clamp(r.min, r.max)
                })
                .collect();
            let v = matgraph::Value::from_lanes(ty, &lanes);
            inputs.insert(i.name.to_owned(), v.to_json());
            written.push(Some(v));
        }
        let outputs: Vec<serde_json::Value> = t
            .outputs()
            .iter()
            .map(|o| json!({ "name": o.name, "from": format!("m.{}", o.name) }))
            .collect();
        let doc = json!({ "version": 2, "name": "muted",
            "nodes": [ { "id": "m", "type": t.name(), "data_type": g.name(), "muted": true, "inputs": inputs } ],
            "outputs": outputs });
        let mut doc = doc;
        if !t.is_generic() {
            doc["nodes"][0].as_object_mut().unwrap().remove("data_type");
        }
        let graph = Graph::from_json(&doc.to_string(), Registry::builtin())
            .unwrap_or_else(|e| panic!("{}: {e:?}", t.name()));
        let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
        assert_eq!(
            plan.stats().per_sample_steps,
            0,
            "{}: a muted node is no step",
            t.name()
        );
        let out = plan
            .execute(&grid_batch(), &plan.default_parameters())
            .unwrap();
        for k in 0..t.outputs().len() {
            let ty = t.outputs()[k].ty.resolve(g);
            let want: Vec<f32> = match first_of_type(t, g, k) {
                Some(j) => match written[j] {
                    Some(v) => v.lanes()[..ty.width()].to_vec(),
                    None => t.inputs()[j].default.lanes()[..ty.width()].to_vec(),
                },
                None => vec![0.0; ty.width()],
            };
            let got: Vec<f32> = (0..ty.width())
                .map(|c| out.planar(k)[c * out.len()])
                .collect();
            assert_eq!(got, want, "{} output {}", t.name(), t.outputs()[k].name);
        }
        checked += 1;
    }
    assert!(checked > 50, "{checked}");
}

/// A version-2 graph whose group `g0` uses `g1` twice, `g1` uses `g2` twice, … down to
/// `g{levels-1}`, one `negate`: inlined, 2^levels copies of it.
fn doubling_groups(levels: usize) -> serde_json::Value {
    let x = json!({ "name": "x", "type": "float" });
    let mut groups = serde_json::Map::new();
    for k in 0..levels {
        let body = if k + 1 == levels {
            json!({ "inputs": [x], "nodes": [
                { "id": "n", "type": "negate", "inputs": { "x": { "link": "@in.x" } } } ],
                "outputs": [ { "name": "y", "from": "n.result" } ] })
        } else {
            let next = format!("g{}", k + 1);
            json!({ "inputs": [x], "nodes": [
                { "id": "a", "type": "group", "group": next, "inputs": { "x": { "link": "@in.x" } } },
                { "id": "b", "type": "group", "group": next, "inputs": { "x": { "link": "a.y" } } } ],
                "outputs": [ { "name": "y", "from": "b.y" } ] })
        };
        groups.insert(format!("g{k}"), body);
    }
    json!({ "version": 2, "name": "doubling",
        "nodes": [ { "id": "i", "type": "group", "group": "g0", "inputs": { "x": 0.5 } } ],
        "outputs": [ { "name": "o", "from": "i.y" } ],
        "groups": groups })
}

/// A repeated node id inside a group body is one error, at the place it is written, however
/// many copies the graph makes of the body (issue 37's slow fuzz cases: 2^13 copies each
/// reported the id again, 8,192 errors built, relocated and dropped in seconds).
#[test]
fn a_repeated_id_in_a_multiplied_body_is_reported_once() {
    let mut doc = doubling_groups(12);
    let body = &mut doc["groups"]["g11"]["nodes"];
    let again = body[0].clone();
    body.as_array_mut().unwrap().push(again);
    let errors = Graph::from_json(&doc.to_string(), Registry::builtin())
        .expect_err("the repeated id is refused");
    let shown: Vec<String> = errors.iter().map(|e| e.to_string()).collect();
    assert_eq!(shown.len(), 1, "{shown:#?}");
    assert!(
        shown[0].ends_with("→ node 'n': duplicate node id"),
        "{}",
        shown[0]
    );
    // At the top level too: the second 'i' is refused, the first still expands.
    let mut doc = doubling_groups(3);
    let again = doc["nodes"][0].clone();
    doc["nodes"].as_array_mut().unwrap().push(again);
    let errors = Graph::from_json(&doc.to_string(), Registry::builtin()).unwrap_err();
    let shown: Vec<String> = errors.iter().map(|e| e.to_string()).collect();
    assert_eq!(shown, ["node 'i': duplicate node id"]);
}

#[test]
fn groups_that_multiply_past_the_node_cap_are_refused_before_they_are_copied() {
    // 2^30 copies would take hundreds of GiB; the groups' sizes are counted first, and
    // nothing is copied.
    let start = std::time::Instant::now();
    let errors = Graph::from_json(&doubling_groups(30).to_string(), Registry::builtin())
        .expect_err("2^30 nodes are refused");
    assert!(start.elapsed().as_secs_f64() < 0.5, "{:?}", start.elapsed());
    fn innermost(e: &GraphError) -> &GraphError {
        match e {
            GraphError::InGroup { error, .. } => innermost(error),
            e => e,
        }
    }
    let too_large: Vec<&GraphError> = errors
        .iter()
        .filter(|e| matches!(innermost(e), GraphError::GroupTooLarge { .. }))
        .collect();
    assert_eq!(too_large.len(), 1, "{errors:#?}");
    let message = too_large[0].to_string();
    // Written: the top's node, 29 groups of 1 input, 2 instances, 1 output, and the last
    // group's 1 input, 1 node, 1 output: 1 + 29·4 + 3 = 120, which may make at most
    // max(16 384, 32·120) nodes.
    assert_eq!(
        message,
        "node 'i': group g0 makes the graph larger than 16384 nodes once inlined, from 120 \
         written (each instance copies its group's nodes, so groups using groups multiply; a \
         graph may have 16384 nodes, or 32 times the nodes written, whichever is more, and \
         never more than 524288)"
    );
    assert_eq!(matgraph::group::MAX_EXPANDED_NODES, 524_288);
    // Below the cap the same shape loads and evaluates: 2^9 negations of 0.5.
    let graph = Graph::from_json(&doubling_groups(10).to_string(), Registry::builtin())
        .expect("512 copies fit");
    let (values, _) = eval_first(&graph);
    assert!(values.iter().all(|&v| v == 0.5), "{values:?}");
    // Counted before copying, every node written counting (instance nodes too): L levels
    // count 1 + (7·2^(L−1) − 4) (the last group 3 with its reroutes, each one above 4 +
    // twice the next). 12 levels count 14 333 (under the 16 384 threshold) and load (10 238
    // nodes built: 2 048 bodies of 3, 2 047 instances' 2 reroutes); 13 levels count 28 669
    // from 52 written (more than 32 times) and are refused at once, as are 18 (917 501,
    // past the absolute cap too).
    let graph = Graph::from_json(&doubling_groups(12).to_string(), Registry::builtin())
        .expect("14 333 nodes fit");
    assert_eq!(graph.nodes().len(), 2048 * 3 + 2047 * 2);
    for levels in [13, 18] {
        let start = std::time::Instant::now();
        let errors = Graph::from_json(&doubling_groups(levels).to_string(), Registry::builtin())
            .expect_err("past 32 times the nodes written");
        assert!(start.elapsed().as_secs_f64() < 0.5, "{:?}", start.elapsed());
        let written = 1 + 4 * (levels - 1) + 3;
        assert!(
            errors.iter().any(|e| {
                let mut e = e;
                while let GraphError::InGroup { error, .. } = e {
                    e = error;
                }
                matches!(e, GraphError::GroupTooLarge { max: 16_384, written: w, .. } if *w == written)
            }),
            "{errors:#?}"
        );
    }
}

/// The expansion limit is `max(16 384, 32 · written)`, at most 524 288: a multiplying
/// group is refused, a large written graph is not.
#[test]
fn the_expansion_limit_follows_the_nodes_written() {
    use matgraph::group::expansion_limit;
    assert_eq!(expansion_limit(0), 16_384);
    assert_eq!(expansion_limit(512), 16_384);
    assert_eq!(expansion_limit(513), 16_416);
    assert_eq!(expansion_limit(10_000), 320_000);
    assert_eq!(expansion_limit(16_384), 524_288);
    assert_eq!(expansion_limit(usize::MAX), 524_288);
    // A group of 40 nodes used 600 times: 600 + 40 + 2 written (instances, body, the
    // interface's input and output), 600 + 600·42 = 25 800 counted: refused (more than
    // 32·642 = 20 544 and past 16 384); used 300 times (300 + 12 600) it loads, each
    // instance its 40 nodes and 2 reroutes.
    let body: Vec<serde_json::Value> = (0..40)
        .map(|k| {
            let from = if k == 0 {
                "@in.x".to_owned()
            } else {
                format!("n{}.result", k - 1)
            };
            json!({ "id": format!("n{k}"), "type": "negate", "inputs": { "x": { "link": from } } })
        })
        .collect();
    let doc = |count: usize| {
        let nodes: Vec<serde_json::Value> = (0..count)
            .map(|k| json!({ "id": format!("i{k}"), "type": "group", "group": "p", "inputs": { "x": k as f64 } }))
            .collect();
        json!({ "version": 2, "name": "many",
            "groups": { "p": { "inputs": [ { "name": "x", "type": "float" } ], "nodes": body.clone(),
                "outputs": [ { "name": "y", "from": "n39.result" } ] } },
            "nodes": nodes, "outputs": [ { "name": "o", "from": "i0.y" } ] })
    };
    let errors = Graph::from_json(&doc(600).to_string(), Registry::builtin()).unwrap_err();
    assert!(
        matches!(
            &errors[0],
            GraphError::GroupTooLarge {
                max: 20_544,
                written: 642,
                ..
            }
        ),
        "{errors:#?}"
    );
    let graph = Graph::from_json(&doc(300).to_string(), Registry::builtin()).unwrap();
    assert_eq!(graph.nodes().len(), 300 * 42);
}

/// A link to a node a group body does not have is one error where it is written, with a
/// suggestion among the body's own ids, however many copies the graph makes of the body
/// (issue 37's 13 s fuzz case: 2^13 copies each reported it, each searching every id of
/// the inlined graph for a suggestion).
#[test]
fn a_missing_node_in_a_multiplied_body_is_reported_once() {
    let mut doc = doubling_groups(12);
    doc["groups"]["g11"]["nodes"][0]["inputs"]["x"] = json!({ "link": "nn.result" });
    let errors = Graph::from_json(&doc.to_string(), Registry::builtin()).unwrap_err();
    let shown: Vec<String> = errors.iter().map(|e| e.to_string()).collect();
    assert_eq!(shown.len(), 1, "{shown:#?}");
    assert!(
        shown[0].starts_with("node 'i' (group g0) → node 'a' (group g1) → "),
        "{}",
        shown[0]
    );
    assert!(
        shown[0].ends_with("→ node 'n': input 'x': link to missing node 'nn' (did you mean 'n'?)"),
        "{}",
        shown[0]
    );
    // In a group's output: one error on the output, inside the group.
    let mut doc = doubling_groups(12);
    doc["groups"]["g11"]["outputs"][0]["from"] = json!("m.result");
    let errors = Graph::from_json(&doc.to_string(), Registry::builtin()).unwrap_err();
    let shown: Vec<String> = errors.iter().map(|e| e.to_string()).collect();
    assert_eq!(shown.len(), 1, "{shown:#?}");
    assert!(
        shown[0].ends_with("link to 'm.result': there is no node 'm' here (did you mean 'n'?)"),
        "{}",
        shown[0]
    );
}

#[test]
fn a_reference_that_does_not_resolve_is_one_error_not_one_per_copy() {
    // g10 is copied 2^10 times; its two instances name g11, which is gone. Reported once
    // per place written (2 errors), not once per copy (2 048 errors after copying every
    // body): after the first error, further copies of a body are skipped.
    let mut doc = doubling_groups(12);
    doc["groups"].as_object_mut().unwrap().remove("g11");
    let start = std::time::Instant::now();
    let errors =
        Graph::from_json(&doc.to_string(), Registry::builtin()).expect_err("g17 is missing");
    assert!(start.elapsed().as_secs_f64() < 1.0, "{:?}", start.elapsed());
    assert_eq!(errors.len(), 2, "{:#?}", &errors[..errors.len().min(3)]);
    for e in &errors {
        let mut inner = e;
        while let GraphError::InGroup { error, .. } = inner {
            inner = error;
        }
        assert!(
            matches!(inner, GraphError::BadGroup { group, .. } if group == "g11"),
            "{inner:?}"
        );
        assert!(e.to_string().contains("no group 'g11' in this file"), "{e}");
    }
}
