//! Output and parameter names are free text in the format; the WGSL mangles them into valid,
//! distinct identifiers, so `check` and `wgsl` agree: every graph that loads compiles.

use matgraph::wgsl::{Entry, WgslOptions, generate};
use matgraph::{Graph, Registry};

/// Names WGSL would refuse as identifiers, or that collide once mangled.
const NAMES: &[&str] = &[
    "é",
    "_",
    "__x",
    "__",
    "___",
    "p_",
    "p__",
    "x",
    "x_",
    "1st",
    "a b",
    "a-b",
    "日本",
    "ü",
    "",
    // WGSL keywords.
    "fn",
    "let",
    "var",
    "struct",
    "return",
    "loop",
    "true",
    // Reserved words (naga's list) and predeclared names.
    "NULL",
    "Self",
    "await",
    "module",
    "typeof",
    "vec3",
    "f32",
    "array",
    // Names the generated code itself uses.
    "mg_params",
    "geom",
    "s",
    "o",
    "mg_dispatch",
    "mg_out",
];

/// A graph with one output and one parameter per name (each parameter feeding an add).
fn graph_text(names: &[&str]) -> String {
    let mut nodes = vec![
        serde_json::json!({ "id": "geo", "type": "geometry" }),
        serde_json::json!({ "id": "cos", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.view" } } }),
    ];
    let mut outputs = Vec::new();
    let mut parameters = Vec::new();
    for (k, name) in names.iter().enumerate() {
        nodes.push(serde_json::json!({ "id": format!("p{k}"), "type": "parameter", "inputs": { "value": k as f64 } }));
        nodes.push(serde_json::json!({ "id": format!("s{k}"), "type": "add",
            "inputs": { "a": { "link": "cos.result" }, "b": { "link": format!("p{k}.value") } } }));
        outputs.push(serde_json::json!({ "name": name, "from": format!("s{k}.result") }));
        parameters.push(serde_json::json!({ "name": name, "node": format!("p{k}") }));
    }
    serde_json::json!({ "version": 1, "name": "names", "nodes": nodes,
        "outputs": outputs, "parameters": parameters })
    .to_string()
}

#[test]
fn every_name_that_loads_compiles_for_both_entries() {
    for name in NAMES {
        let text = graph_text(&[name]);
        let graph = Graph::from_json(&text, Registry::builtin())
            .unwrap_or_else(|e| panic!("{name:?} should load: {e:?}"));
        for entry in [Entry::Compute, Entry::Fragment] {
            let options = WgslOptions {
                entry,
                ..Default::default()
            };
            generate(&graph, &options).unwrap_or_else(|e| panic!("{name:?} ({entry:?}): {e}"));
        }
    }
}

#[test]
fn all_names_together_get_distinct_fields() {
    let graph = Graph::from_json(&graph_text(NAMES), Registry::builtin()).unwrap();
    let m = generate(&graph, &WgslOptions::default()).unwrap();
    // Parameters: one uniform field each, all distinct, in the order of the names.
    let fields: Vec<&str> = m.uniforms.fields.iter().map(|f| f.field.as_str()).collect();
    assert_eq!(fields.len(), NAMES.len());
    let mut unique = fields.clone();
    unique.sort();
    unique.dedup();
    assert_eq!(unique.len(), fields.len(), "{fields:?}");
    // Spot checks of the mangling: `_` and `é` get a prefix; keywords a suffix.
    assert_eq!(fields[0], "p__", "é");
    assert_eq!(fields[1], "p___2", "_ after é");
    assert_eq!(fields[2], "p___x", "__x");
    assert!(fields.contains(&"fn_") && fields.contains(&"NULL_") && fields.contains(&"await_"));
    // Outputs keep their names and their columns, in order.
    let names: Vec<&str> = m.outputs.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, NAMES);
    // Generation is deterministic.
    assert_eq!(
        generate(&graph, &WgslOptions::default()).unwrap().source,
        m.source
    );
}

#[test]
fn a_keyword_node_id_is_mangled_in_variable_names() {
    let text = r#"{"version": 1, "name": "g", "nodes": [
        {"id": "geo", "type": "geometry"},
        {"id": "fn", "type": "dot", "inputs": {"a": {"link": "geo.normal"}, "b": {"link": "geo.view"}}},
        {"id": "_", "type": "add", "inputs": {"a": {"link": "fn.result"}, "b": 1.0}},
        {"id": "__", "type": "add", "inputs": {"a": {"link": "_.result"}, "b": 1.0}}
    ], "outputs": [{"name": "_", "from": "__.result"}]}"#;
    let graph = Graph::from_json(text, Registry::builtin()).unwrap();
    let m = generate(&graph, &WgslOptions::default()).unwrap();
    assert!(m.source.contains("let n1_fn_ = "), "{}", m.source);
}
