//! Graph documents at the library boundary: every class of error with its rendered message,
//! save/load round trips of the committed graphs, "never panics" on arbitrary and mutated
//! input, and the committed JSON Schema.

use matgraph::node::{Category, In, NodeType, Out};
use matgraph::{Graph, GraphError, GraphErrors, Plan, PlanOptions, Registry, SampleBatch};
use std::path::{Path, PathBuf};

// ---------------------------------------------------------------------------------------
// Helpers: one per boundary.
// ---------------------------------------------------------------------------------------

/// Loads `input` against `registry`, expects it to fail, and compares every rendered error
/// (attributed to "g.json", one per line) with `expect`.
fn check_with(registry: &Registry, input: &str, expect: &str) {
    let errors = match Graph::from_json(input, registry) {
        Ok(_) => panic!("expected errors, but the graph loaded:\n{input}"),
        Err(errors) => errors,
    };
    assert!(!errors.is_empty(), "Err(vec![]) for:\n{input}");
    let actual = GraphErrors {
        source: "g.json".into(),
        errors,
    }
    .to_string();
    assert_eq!(
        actual,
        expect.trim(),
        "\n--- input ---\n{input}\n--- actual ---\n{actual}\n"
    );
}

/// [`check_with`] against the builtin node library.
fn check(input: &str, expect: &str) {
    check_with(Registry::builtin(), input, expect);
}

/// A version-1 document named "g" with the given nodes and (optional) trailing fields.
fn doc(nodes: &str, rest: &str) -> String {
    let rest = if rest.is_empty() {
        String::new()
    } else {
        format!(", {rest}")
    };
    format!("{{\"version\": 1, \"name\": \"g\", \"nodes\": [{nodes}]{rest}}}")
}

/// Loads `input` and expects success.
fn load(input: &str) -> Graph {
    Graph::from_json(input, Registry::builtin()).unwrap_or_else(|errors| {
        panic!(
            "{}",
            GraphErrors {
                source: "g.json".into(),
                errors
            }
        )
    })
}

fn repo_path(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

// ---------------------------------------------------------------------------------------
// 1. One test per error class.
// ---------------------------------------------------------------------------------------

#[test]
fn malformed_json_has_line_and_column() {
    check(
        "{\n  \"version\": 1,\n  \"name\": \"g\",\n  \"nodes\": [,]\n}",
        "g.json: malformed JSON at line 4, column 13: expected value",
    );
    check(
        "{\n  \"version\": 1,\n  \"name\": \"g\"",
        "g.json: malformed JSON at line 3, column 13: EOF while parsing an object",
    );
    check(
        "",
        "g.json: malformed JSON at line 1, column 0: EOF while parsing a value",
    );
}

#[test]
fn top_level_value_must_be_an_object() {
    check(
        "[1, 2]",
        "g.json: a graph file must be a JSON object at line 1, column 1",
    );
}

#[test]
fn unknown_node_type_suggests_the_nearest_name() {
    check(
        &doc(r#"{"id": "fr", "type": "fresnel_dielectrc"}"#, ""),
        "g.json: node 'fr': unknown node type 'fresnel_dielectrc' (did you mean 'fresnel_dielectric'?)",
    );
    // Nothing close: no suggestion.
    check(
        &doc(r#"{"id": "x", "type": "qqqqqqqq"}"#, ""),
        "g.json: node 'x': unknown node type 'qqqqqqqq'",
    );
}

#[test]
fn unknown_input_suggests_the_nearest_input() {
    check(
        &doc(
            r#"{"id": "fr", "type": "fresnel_dielectric", "inputs": {"ior_insde": 1.5}}"#,
            "",
        ),
        "g.json: node 'fr': unknown input 'ior_insde' (did you mean 'ior_inside'?)",
    );
}

#[test]
fn vector_literal_for_a_float_input() {
    check(
        &doc(
            r#"{"id": "fr", "type": "fresnel_dielectric", "inputs": {"cos_theta": [0.0, 0.0, 1.0]}}"#,
            "",
        ),
        "g.json: node 'fr': input 'cos_theta': expected float, found array of 3 items",
    );
}

#[test]
fn string_literal_for_a_float_input() {
    check(
        &doc(
            r#"{"id": "fr", "type": "fresnel_dielectric", "inputs": {"ior_inside": "glass"}}"#,
            "",
        ),
        "g.json: node 'fr': input 'ior_inside': expected float, found string \"glass\"",
    );
}

#[test]
fn wrong_literals_for_bool_and_vector_inputs() {
    check(
        &doc(
            r#"{"id": "r", "type": "remap", "inputs": {"clamp": "yes"}},
               {"id": "c", "type": "cross", "inputs": {"a": [1.0, 2.0]}},
               {"id": "s", "type": "add", "inputs": {"a": [1.0, 2.0, 3.0], "b": [1.0, 2.0]}}"#,
            "",
        ),
        "g.json: node 'r': input 'clamp': expected bool, found string \"yes\"\n\
         g.json: node 'c': input 'a': expected vec3, found array of 2 items\n\
         g.json: node 's': input 'b': expected vec3, found array of 2 items",
    );
}

/// A registry with one node type that has an enum input; no builtin node has one.
fn enum_registry() -> Registry {
    let mut r = Registry::default();
    r.register(
        NodeType::new("blend", Category::Math, "Test node with an enum input.")
            .input(In::choice("mode", &["mix", "add", "multiply"], 0).doc("Blend mode."))
            .output(Out::float("result").doc("The mode's index."))
            .compute(|mode: i32| mode as f32),
    );
    r
}

#[test]
fn wrong_enum_choice_name() {
    let r = enum_registry();
    check_with(
        &r,
        &doc(
            r#"{"id": "b", "type": "blend", "inputs": {"mode": "screen"}}"#,
            "",
        ),
        "g.json: node 'b': input 'mode': expected one of mix, add, multiply, found \"screen\"",
    );
    check_with(
        &r,
        &doc(r#"{"id": "b", "type": "blend", "inputs": {"mode": 7}}"#, ""),
        "g.json: node 'b': input 'mode': value 7 is outside [0, 2]",
    );
    check_with(
        &r,
        &doc(
            r#"{"id": "b", "type": "blend", "inputs": {"mode": true}}"#,
            "",
        ),
        "g.json: node 'b': input 'mode': expected one of mix, add, multiply, found bool true",
    );
    // A valid choice loads and saves by name.
    let text = doc(
        r#"{"id": "b", "type": "blend", "inputs": {"mode": "multiply"}}"#,
        r#""outputs": [{"name": "o", "from": "b.result"}]"#,
    );
    let g = Graph::from_json(&text, &r).expect("valid choice");
    let saved = g.to_json();
    assert!(saved.contains(r#""mode": "multiply""#), "{saved}");
}

#[test]
fn value_outside_the_hard_range() {
    check(
        &doc(
            r#"{"id": "fr", "type": "fresnel_dielectric", "inputs": {"cos_theta": 1.5, "ior_inside": 0.0}}"#,
            "",
        ),
        "g.json: node 'fr': input 'cos_theta': value 1.5 is outside [-1, 1]\n\
         g.json: node 'fr': input 'ior_inside': value 0.0 is outside [0.001, 100]",
    );
}

/// Schlick's F0 is a reflectance: a fraction per channel (before its hard range, f0 = −5 loaded
/// and turned the ball black).
#[test]
fn schlick_f0_outside_zero_to_one() {
    check(
        &doc(
            r#"{"id": "s", "type": "fresnel_schlick", "inputs": {"f0": -5.0}},
               {"id": "c", "type": "fresnel_schlick", "inputs": {"f0": [0.9, 1.5, 0.2]}}"#,
            "",
        ),
        "g.json: node 's': input 'f0': value -5.0 is outside [0, 1]\n\
         g.json: node 'c': input 'f0': value [0.9,1.5,0.2] is outside [0, 1]",
    );
}

#[test]
fn link_to_a_missing_node() {
    check(
        &doc(
            r#"{"id": "geom", "type": "geometry"},
               {"id": "d", "type": "dot", "inputs": {"a": {"link": "geo.normal"}, "b": {"link": "geom.view"}}}"#,
            "",
        ),
        "g.json: node 'd': input 'a': link to missing node 'geo' (did you mean 'geom'?)",
    );
}

#[test]
fn link_to_a_missing_output() {
    check(
        &doc(
            r#"{"id": "geo", "type": "geometry"},
               {"id": "d", "type": "dot", "inputs": {"a": {"link": "geo.normals"}, "b": {"link": "geo.view"}}}"#,
            "",
        ),
        "g.json: node 'd': input 'a': node 'geo' has no output 'normals' (did you mean 'normal'?)",
    );
}

#[test]
fn link_with_bad_syntax() {
    check(
        &doc(
            r#"{"id": "geo", "type": "geometry"},
               {"id": "d", "type": "dot", "inputs": {"a": {"link": "geo"}, "b": {"link": "geo.view", "extra": 1}}}"#,
            "",
        ),
        "g.json: node 'd': input 'a': link 'geo' must be written \"node_id.output\"\n\
         g.json: node 'd': input 'b': link '{\"link\":\"geo.view\",\"extra\":1}' must be written \"node_id.output\"",
    );
}

#[test]
fn type_mismatch_names_both_ends_and_both_types() {
    check(
        &doc(
            r#"{"id": "geo", "type": "geometry"},
               {"id": "fr", "type": "fresnel_dielectric", "inputs": {"cos_theta": {"link": "geo.uv"}}}"#,
            "",
        ),
        "g.json: node 'fr': input 'cos_theta': cannot connect 'geo.uv' (vec2) to 'fr.cos_theta' (float): no implicit conversion",
    );
}

#[test]
fn duplicate_ids() {
    check(
        &doc(
            r#"{"id": "a", "type": "add"}, {"id": "b", "type": "add"}, {"id": "a", "type": "mul"}"#,
            "",
        ),
        "g.json: node 'a': duplicate node id",
    );
}

#[test]
fn invalid_ids() {
    check(
        &doc(
            r#"{"id": "a.b", "type": "add"}, {"id": "", "type": "add"}"#,
            "",
        ),
        "g.json: node 'a.b': invalid node id (use letters, digits, '_' and '-', no '.')\n\
         g.json: node '': invalid node id (use letters, digits, '_' and '-', no '.')",
    );
}

#[test]
fn cycle_lists_its_nodes_in_link_order() {
    // Data flows a -> b -> c -> a; `d` hangs off the cycle and is not on it.
    check(
        &doc(
            r#"{"id": "a", "type": "add", "inputs": {"a": {"link": "c.result"}}},
               {"id": "b", "type": "add", "inputs": {"a": {"link": "a.result"}}},
               {"id": "c", "type": "add", "inputs": {"a": {"link": "b.result"}}},
               {"id": "d", "type": "add", "inputs": {"a": {"link": "c.result"}}}"#,
            "",
        ),
        "g.json: cycle through nodes a -> b -> c -> a",
    );
    // The same cycle written in a different file order starts at the first node in the file.
    check(
        &doc(
            r#"{"id": "c", "type": "add", "inputs": {"a": {"link": "b.result"}}},
               {"id": "a", "type": "add", "inputs": {"a": {"link": "c.result"}}},
               {"id": "b", "type": "add", "inputs": {"a": {"link": "a.result"}}}"#,
            "",
        ),
        "g.json: cycle through nodes c -> a -> b -> c",
    );
}

#[test]
fn two_cycles_are_both_reported() {
    let input = doc(
        r#"{"id": "a", "type": "add", "inputs": {"a": {"link": "b.result"}}},
           {"id": "b", "type": "add", "inputs": {"a": {"link": "a.result"}}},
           {"id": "x", "type": "mul", "inputs": {"a": {"link": "y.result"}}},
           {"id": "y", "type": "mul", "inputs": {"a": {"link": "x.result"}}}"#,
        "",
    );
    let errors = Graph::from_json(&input, Registry::builtin()).unwrap_err();
    let mut text: Vec<String> = errors.iter().map(ToString::to_string).collect();
    text.sort();
    assert_eq!(
        text,
        [
            "cycle through nodes a -> b -> a",
            "cycle through nodes x -> y -> x"
        ]
    );
}

#[test]
fn self_loop() {
    check(
        &doc(
            r#"{"id": "m", "type": "mul", "inputs": {"b": {"link": "m.result"}}}"#,
            "",
        ),
        "g.json: cycle through nodes m -> m",
    );
}

#[test]
fn newer_format_version() {
    check(
        r#"{"version": 3, "name": "g", "nodes": []}"#,
        "g.json: format version 3 is newer than the newest supported (2); update matgraph",
    );
}

#[test]
fn missing_version() {
    check(
        r#"{"name": "g", "nodes": []}"#,
        "g.json: missing format version: add \"version\": 2",
    );
    check(
        r#"{"version": "1", "name": "g", "nodes": []}"#,
        "g.json: \"version\" must be a non-negative integer, found \"1\" at line 1, column 1",
    );
}

#[test]
fn unknown_top_level_field() {
    check(
        "{\n  \"version\": 1,\n  \"name\": \"g\",\n  \"colour\": 1,\n  \"nodes\": []\n}",
        "g.json: unknown field `colour`, expected one of `version`, `name`, `doc`, `nodes`, \
         `outputs`, `parameters`, `variants`, `groups`, `frames`, `scene` at line 4, column 10",
    );
}

#[test]
fn unknown_field_inside_a_node_names_the_node() {
    check(
        "{\n  \"version\": 1,\n  \"name\": \"g\",\n  \"nodes\": [\n    \
         {\"id\": \"geo\", \"type\": \"geometry\"},\n    \
         {\"id\": \"fr\", \"type\": \"fresnel_dielectric\", \"colour\": 1}\n  ]\n}",
        "g.json: node 'fr': unknown field `colour`, expected one of `id`, `type`, `data_type`, \
         `variant`, `group`, `muted`, `inputs`, `texture`, `color_space`, `position` at line 6, column 55",
    );
}

#[test]
fn bad_graph_outputs() {
    check(
        &doc(
            r#"{"id": "geo", "type": "geometry"}"#,
            r#""outputs": [
                {"name": "n", "from": "geo.normal"},
                {"name": "n", "from": "geo.view"},
                {"name": "nodot", "from": "geo"},
                {"name": "missing_node", "from": "gel.normal"},
                {"name": "missing_output", "from": "geo.colour"}
            ]"#,
        ),
        "g.json: graph output 'n': duplicate output name\n\
         g.json: graph output 'nodot': 'geo' must be written \"node_id.output\"\n\
         g.json: graph output 'missing_node': no node 'gel' (did you mean 'geo'?)\n\
         g.json: graph output 'missing_output': node 'geo' has no output 'colour'",
    );
}

#[test]
fn parameter_pointing_at_a_non_parameter_node() {
    check(
        &doc(
            r#"{"id": "fr", "type": "fresnel_dielectric"}, {"id": "ior", "type": "parameter", "inputs": {"value": 1.5}}"#,
            r#""parameters": [
                {"name": "p", "node": "fr"},
                {"name": "q", "node": "nope"},
                {"name": "normal", "node": "ior"},
                {"name": "ior", "node": "ior"},
                {"name": "ior", "node": "ior"}
            ]"#,
        ),
        "g.json: parameter 'p': node 'fr' is a 'fresnel_dielectric', not a 'parameter' node\n\
         g.json: parameter 'q': no node 'nope'\n\
         g.json: parameter 'normal': the name is taken by a geometry attribute\n\
         g.json: parameter 'ior': duplicate parameter name",
    );
}

/// An exposed parameter node whose `value` is a link that does not resolve: the link error
/// must be reported, not a panic. (A resolvable link into a parameter is rejected with a
/// wrong-value-type error; see the next test.)
#[test]
fn unresolved_link_into_exposed_parameter_node() {
    check(
        &doc(
            r#"{"id": "p", "type": "parameter", "inputs": {"value": {"link": "nope.value"}}}"#,
            r#""parameters": [{"name": "k", "node": "p"}]"#,
        ),
        "g.json: node 'p': input 'value': link to missing node 'nope'",
    );
}

#[test]
fn linked_parameter_value() {
    check(
        &doc(
            r#"{"id": "geo", "type": "geometry"},
               {"id": "p", "type": "parameter", "inputs": {"value": {"link": "geo.uv"}}}"#,
            r#""parameters": [{"name": "k", "node": "p"}]"#,
        ),
        "g.json: node 'p': input 'value': expected a literal (a parameter's value cannot be linked), found a link",
    );
}

#[test]
fn bad_data_type() {
    check(
        &doc(r#"{"id": "d", "type": "dot", "data_type": "float"}"#, ""),
        "g.json: node 'd': data_type 'float' is not one of vec3, vec2, vec4, color",
    );
}

#[test]
fn several_errors_in_one_file_are_all_reported() {
    check(
        &doc(
            r#"{"id": "geo", "type": "geometry"},
               {"id": "fr", "type": "fresnel_dielectrc"},
               {"id": "x", "type": "fresnel_dielectric", "inputs": {
                   "cos_theta": {"link": "geo.uv"}, "ior_insde": 1.5, "ior_outside": 500.0}},
               {"id": "y", "type": "dot", "inputs": {"a": {"link": "ge.normal"}, "b": {"link": "geo.nrm"}}},
               {"id": "dup", "type": "add"},
               {"id": "dup", "type": "mul"}"#,
            r#""outputs": [{"name": "o", "from": "nothing_here.result"}],
               "parameters": [{"name": "p", "node": "geo"}]"#,
        ),
        "g.json: node 'fr': unknown node type 'fresnel_dielectrc' (did you mean 'fresnel_dielectric'?)\n\
         g.json: node 'dup': duplicate node id\n\
         g.json: node 'x': unknown input 'ior_insde' (did you mean 'ior_inside'?)\n\
         g.json: node 'y': input 'a': link to missing node 'ge' (did you mean 'geo'?)\n\
         g.json: node 'y': input 'b': node 'geo' has no output 'nrm'\n\
         g.json: node 'x': input 'cos_theta': cannot connect 'geo.uv' (vec2) to 'x.cos_theta' (float): no implicit conversion\n\
         g.json: node 'x': input 'ior_outside': value 500.0 is outside [0.001, 100]\n\
         g.json: graph output 'o': no node 'nothing_here'\n\
         g.json: parameter 'p': node 'geo' is a 'geometry', not a 'parameter' node",
    );
}

#[test]
fn malformed_entries_in_several_nodes_are_all_reported() {
    let input = doc(
        r#"{"id": "a", "type": "add", "colour": 1},
           {"id": "b", "type": "add"},
           {"id": "c", "type": 3},
           {"type": "add"}"#,
        "",
    );
    let errors = Graph::from_json(&input, Registry::builtin()).unwrap_err();
    let nodes: Vec<Option<&str>> = errors.iter().map(GraphError::node).collect();
    assert_eq!(nodes, [Some("a"), Some("c"), Some("#3")], "{errors:#?}");
    let text = GraphErrors {
        source: "g.json".into(),
        errors: errors.clone(),
    }
    .to_string();
    assert!(text.contains("unknown field `colour`"), "{text}");
    assert!(text.contains("invalid type: integer `3`"), "{text}");
    assert!(text.contains("missing field `id`"), "{text}");
}

/// Every error has a real location: lines and columns are 1-based, so "line 0" means the
/// location was lost.
#[test]
fn every_malformed_node_has_a_real_location() {
    let input = "{\"version\": 1, \"name\": \"g\", \"nodes\": [\n\
                 {\"id\": \"a\", \"type\": \"add\", \"colour\": 1},\n\
                 {\"id\": \"b\", \"type\": \"add\", \"flavour\": 1}\n]}";
    let errors = Graph::from_json(input, Registry::builtin()).unwrap_err();
    let text: Vec<String> = errors.iter().map(ToString::to_string).collect();
    assert_eq!(text.len(), 2, "{text:#?}");
    // Each error points at the end of its unknown key.
    assert!(text[0].ends_with("at line 2, column 35"), "{text:#?}");
    assert!(text[1].ends_with("at line 3, column 36"), "{text:#?}");
}

/// A malformed top-level entry and a malformed node entry in one file.
#[test]
fn top_level_and_node_structure_errors_are_both_reported() {
    let input = r#"{"version": 1, "name": "g", "extra": 1, "nodes": [{"id": "a", "type": "add", "colour": 1}]}"#;
    let errors = Graph::from_json(input, Registry::builtin()).unwrap_err();
    let text: Vec<String> = errors.iter().map(ToString::to_string).collect();
    assert!(
        text.iter().any(|t| t.contains("unknown field `extra`")),
        "{text:#?}"
    );
    assert!(
        text.iter()
            .any(|t| t.starts_with("node 'a': unknown field `colour`")),
        "{text:#?}"
    );
    // The node's error points at the end of its own unknown key.
    let column = input.find("\"colour\"").unwrap() + "\"colour\"".len();
    let located = format!("at line 1, column {column}");
    assert!(
        text.iter()
            .any(|t| t.contains("`colour`") && t.ends_with(&located)),
        "{located}: {text:#?}"
    );
}

// ---------------------------------------------------------------------------------------
// 2. Round trips.
// ---------------------------------------------------------------------------------------

fn committed_graphs() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(repo_path("graphs"))
        .expect("graphs/ exists")
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no graphs/*.json");
    files
}

#[test]
fn committed_graphs_load() {
    for path in committed_graphs() {
        let g =
            matgraph::io::load_graph(&path, Registry::builtin()).unwrap_or_else(|e| panic!("{e}"));
        assert!(!g.nodes().is_empty(), "{}", path.display());
        assert!(!g.outputs().is_empty(), "{}", path.display());
    }
}

/// Loads the text of the committed graph at `path`, reading the files its groups name.
fn load_at(path: &Path, text: &str) -> Graph {
    let files = matgraph::io::group_files(path, matgraph::io::PathPolicy::InsideGraphFolder);
    Graph::from_json_in(text, Registry::builtin(), files).unwrap_or_else(|errors| {
        panic!(
            "{}",
            GraphErrors {
                source: path.to_owned(),
                errors
            }
        )
    })
}

#[test]
fn load_save_load_save_is_byte_identical() {
    for path in committed_graphs() {
        let text = std::fs::read_to_string(&path).unwrap();
        let first = load_at(&path, &text).to_json();
        let second = load_at(&path, &first).to_json();
        assert_eq!(first, second, "{}", path.display());
    }
}

/// Regression (the fuzzer's one finding, 23 cases in 1,000,000): free-form JSON such as a
/// bare-number scene was read one unit in the last place off (serde_json without
/// `float_roundtrip`), so `fmt` flipped `1e-45` and `1.0000000000000001e-45`.
#[test]
fn free_form_numbers_round_trip_exactly() {
    for x in [
        "1e-45",
        "5e-324",
        "1.7976931348623157e308",
        "0.1",
        "2.2250738585072014e-308",
    ] {
        let text = doc(
            r#"{"id": "c", "type": "constant", "inputs": {"value": 0.5}}"#,
            &format!(r#""outputs": [{{"name": "x", "from": "c.value"}}], "scene": {x}"#),
        );
        let first = load(&text).to_json();
        let second = load(&first).to_json();
        assert_eq!(first, second, "scene {x}");
        let v: serde_json::Value = serde_json::from_str(&first).unwrap();
        let want: f64 = x.parse().unwrap();
        assert_eq!(v["scene"].as_f64(), Some(want), "scene {x} kept its value");
    }
}

#[test]
fn committed_graphs_are_canonical() {
    for path in committed_graphs() {
        let text = std::fs::read_to_string(&path).unwrap();
        let saved = load_at(&path, &text).to_json();
        assert_eq!(
            saved,
            text,
            "{} is not canonical: run `cargo run -- fmt {}`",
            path.display(),
            path.display()
        );
    }
}

#[test]
fn saving_normalises_literals_and_sorts_inputs() {
    // Inputs written out of order, an int for a float, and a float broadcast to a vec3 input.
    let text = doc(
        r#"{"id": "fr", "type": "fresnel_dielectric", "inputs": {"ior_inside": 2, "cos_theta": 0.5}},
           {"id": "c", "type": "cross", "inputs": {"b": 0.25}}"#,
        r#""outputs": [{"name": "r", "from": "fr.reflectance"}, {"name": "x", "from": "c.result"}]"#,
    );
    let saved = load(&text).to_json();
    assert!(
        saved.contains(r#""inputs": { "cos_theta": 0.5, "ior_inside": 2.0 }"#),
        "{saved}"
    );
    assert!(
        saved.contains(r#""inputs": { "b": [0.25, 0.25, 0.25] }"#),
        "{saved}"
    );
    assert_eq!(load(&saved).to_json(), saved);
}

/// Module doc of `document`: "saving writes ... the shortest decimal that reads back to the
/// same f32". Positions are `[f32; 2]` serialised through serde, which widens to f64.
#[test]
fn positions_are_saved_as_shortest_f32_decimals() {
    let text = doc(
        r#"{"id": "geo", "type": "geometry", "position": [0.1, 33.3]}"#,
        r#""outputs": [{"name": "n", "from": "geo.normal"}]"#,
    );
    let saved = load(&text).to_json();
    assert!(saved.contains(r#""position": [0.1, 33.3]"#), "{saved}");
}

/// A position that overflows f32 loads (serde casts it to infinity) but saves as `null`,
/// which does not load again.
#[test]
fn overflowing_position_round_trips_or_is_rejected() {
    let text = doc(
        r#"{"id": "geo", "type": "geometry", "position": [0.0, 1e39]}"#,
        r#""outputs": [{"name": "n", "from": "geo.normal"}]"#,
    );
    if let Ok(g) = Graph::from_json(&text, Registry::builtin()) {
        let saved = g.to_json();
        let again = Graph::from_json(&saved, Registry::builtin());
        assert!(again.is_ok(), "saved:\n{saved}\nerrors: {:?}", again.err());
    }
}

/// A generic node whose type `T` is inferred as colour from a link, with a float literal on
/// another generic input: saving writes the literal as a 3-array, which reloads as vec3, so
/// `T` becomes vec3 and the colour → float link downstream no longer type-checks.
#[test]
fn inferred_colour_type_survives_saving() {
    let text = doc(
        r#"{"id": "p", "type": "parameter", "data_type": "color", "inputs": {"value": 0.5}},
           {"id": "m", "type": "mul", "inputs": {"a": {"link": "p.value"}, "b": 2}},
           {"id": "f", "type": "fresnel_dielectric", "inputs": {"ior_inside": {"link": "m.result"}}}"#,
        r#""outputs": [{"name": "r", "from": "f.reflectance"}, {"name": "m", "from": "m.result"}]"#,
    );
    let g = load(&text);
    assert_eq!(g.outputs()[1].ty, matgraph::SocketType::Color);
    let saved = g.to_json();
    let again = Graph::from_json(&saved, Registry::builtin())
        .unwrap_or_else(|e| panic!("saved:\n{saved}\nerrors: {e:?}"));
    let types: Vec<_> = again.outputs().iter().map(|o| o.ty).collect();
    assert_eq!(
        types,
        [matgraph::SocketType::Float, matgraph::SocketType::Color]
    );
}

// ---------------------------------------------------------------------------------------
// 3. Never panic.
// ---------------------------------------------------------------------------------------

mod never_panic {
    use super::*;
    use proptest::prelude::*;
    use proptest::test_runner::Config;
    use serde_json::{Value as J, json};

    /// The committed graphs' texts, graphs/fresnel_glass.json first; a graph with groups
    /// in other files as its flat form (its groups inlined), which loads from text alone.
    fn fixtures() -> Vec<String> {
        let first = repo_path("graphs/fresnel_glass.json");
        let mut paths = committed_graphs();
        paths.retain(|p| *p != first);
        paths.insert(0, first);
        paths
            .iter()
            .map(|p| {
                let text = std::fs::read_to_string(p).unwrap();
                let g = load_at(p, &text);
                if g.has_groups() {
                    g.flat_document().to_json_pretty()
                } else {
                    text
                }
            })
            .collect()
    }

    fn fixture(seed: u8) -> String {
        let all = fixtures();
        // Two thirds of the cases mutate fresnel_glass.json, the rest the other graphs.
        if !seed.is_multiple_of(3) || all.len() == 1 {
            all[0].clone()
        } else {
            all[1 + seed as usize % (all.len() - 1)].clone()
        }
    }

    fn config(cases: u32) -> Config {
        Config {
            cases,
            // Keep failures in the test output, not in files beside the tests.
            failure_persistence: None,
            ..Config::default()
        }
    }

    /// Loads `text`; when it loads, saves it and compiles and runs it on small batches.
    /// Panics propagate to proptest.
    fn exercise(text: &str) {
        let Ok(g) = Graph::from_json(text, Registry::builtin()) else {
            return;
        };
        let _ = g.to_json();
        for bake in [false, true] {
            let options = PlanOptions {
                outputs: Vec::new(),
                bake_parameters: bake,
            };
            let Ok(plan) = Plan::compile(&g, &options) else {
                continue;
            };
            let mut batch = SampleBatch::new(3);
            batch.set_time(0.25);
            for attr in plan.attributes() {
                let v = match attr.ty().width() {
                    2 => matgraph::Value::vec2([0.25, -1.0]),
                    _ => matgraph::Value::vec3([0.0, 0.6, -0.8]),
                };
                let _ = batch.fill(*attr, v);
            }
            let mut params = plan.default_parameters();
            for p in plan.parameters() {
                let _ = params.set(&p.name, matgraph::Value::float(2.5));
            }
            let _ = plan.execute(&batch, &params);
            let _ = plan.execute(&SampleBatch::new(0), &plan.default_parameters());
        }
        // Every node output, requested by name.
        let all: Vec<String> = g
            .nodes()
            .iter()
            .flat_map(|n| {
                n.node_type
                    .outputs()
                    .iter()
                    .map(move |o| format!("{}.{}", n.id, o.name))
            })
            .collect();
        let options = PlanOptions {
            outputs: all,
            bake_parameters: false,
        };
        if let Ok(plan) = Plan::compile(&g, &options) {
            let _ = plan.execute(&SampleBatch::new(1), &plan.default_parameters());
        }
    }

    /// One byte-level edit: (kind, position seed, byte).
    fn apply_byte_edit(bytes: &mut Vec<u8>, (kind, at, b): (u8, usize, u8)) {
        if bytes.is_empty() {
            bytes.push(b);
            return;
        }
        let i = at % bytes.len();
        match kind % 4 {
            0 => bytes[i] ^= b | 1,
            1 => {
                bytes.remove(i);
            }
            2 => bytes.insert(i, b),
            _ => bytes.truncate(i),
        }
    }

    /// JSON pointers to every value in `v` (the root is "").
    fn pointers(v: &J, here: String, out: &mut Vec<String>) {
        match v {
            J::Array(items) => {
                for (i, item) in items.iter().enumerate() {
                    pointers(item, format!("{here}/{i}"), out);
                }
            }
            J::Object(map) => {
                for (k, item) in map {
                    let k = k.replace('~', "~0").replace('/', "~1");
                    pointers(item, format!("{here}/{k}"), out);
                }
            }
            _ => {}
        }
        out.push(here);
    }

    const NUMBERS: &[f64] = &[
        0.0,
        -0.0,
        1.0,
        -1.0,
        0.5,
        2.0,
        1.52,
        1e-3,
        1e-45,
        1e39,
        -1e39,
        1e308,
        3.0e38,
        100.0,
        4294967296.0,
    ];
    const STRINGS: &[&str] = &[
        "",
        ".",
        "x",
        "geo",
        "geo.normal",
        "geo.uv",
        "cos.result",
        "ior.value",
        "f0.f0",
        "exact.transmittance",
        "a.b.c",
        "ior",
        "#0",
        "vec4",
        "color",
        "int",
        "é.ü",
        "parameter",
        "constant",
        "time",
    ];
    const TYPES: &[&str] = &[
        "geometry",
        "time",
        "constant",
        "parameter",
        "add",
        "mix",
        "remap",
        "dot",
        "split",
        "combine",
        "normalize",
        "refract",
        "fresnel_dielectric",
        "fresnel_schlick",
        "fresnel_empirical",
        "hg_phase",
        "f0_to_ior",
        "nope",
    ];
    const IDS: &[&str] = &[
        "geo", "cos", "ior", "exact", "f0", "spec", "schlick", "water", "snell", "zz",
    ];
    const OUTPUTS: &[&str] = &[
        "normal",
        "view",
        "uv",
        "position",
        "result",
        "value",
        "reflectance",
        "transmittance",
        "f0",
        "specular",
        "x",
        "vec4",
        "color",
        "t",
        "tir",
        "time",
        "nope",
    ];

    fn pick<T: Clone>(list: &[T], seed: u64) -> T {
        list[(seed % list.len() as u64) as usize].clone()
    }

    /// Links that resolve in one of the committed graphs (so mutants reach type checks and
    /// cycles), and a few that do not.
    const LINKS: &[&str] = &[
        "geo.normal",
        "geo.view",
        "geo.uv",
        "cos.result",
        "ior.value",
        "exact.reflectance",
        "exact.transmittance",
        "f0.f0",
        "spec.specular",
        "schlick.reflectance",
        "incident.result",
        "water.value",
        "eta.result",
        "snell.t",
        "snell.tir",
        "inside.result",
        "fresnel.transmittance",
        "geo",
        "geo.",
        ".normal",
    ];

    fn random_link(seed: u64) -> J {
        let text = if seed.is_multiple_of(4) {
            format!("{}.{}", pick(IDS, seed / 4), pick(OUTPUTS, seed / 64))
        } else {
            pick(LINKS, seed / 4).to_owned()
        };
        json!({ "link": text })
    }

    /// One structured edit: (kind, target seed, payload seed).
    fn apply_json_edit(root: &mut J, (kind, target, payload): (u8, u64, u64)) {
        let mut ptrs = Vec::new();
        pointers(root, String::new(), &mut ptrs);
        let ptr = pick(&ptrs, target);
        let node_count = root
            .get("nodes")
            .and_then(J::as_array)
            .map_or(0, |n| n.len());
        match kind % 12 {
            0 => *root.pointer_mut(&ptr).unwrap() = J::Null,
            1 => {
                *root.pointer_mut(&ptr).unwrap() =
                    serde_json::Number::from_f64(pick(NUMBERS, payload)).map_or(J::Null, J::Number)
            }
            2 => *root.pointer_mut(&ptr).unwrap() = json!(pick(STRINGS, payload)),
            3 => {
                let n = (payload % 6) as usize;
                *root.pointer_mut(&ptr).unwrap() =
                    J::Array((0..n).map(|i| json!(i as f64 * 0.25)).collect());
            }
            4 => {
                *root.pointer_mut(&ptr).unwrap() = if payload.is_multiple_of(2) {
                    json!({})
                } else {
                    random_link(payload / 2)
                }
            }
            5 => {
                // Delete the value from its parent.
                if let Some(cut) = ptr.rfind('/') {
                    let (parent, key) = (&ptr[..cut], &ptr[cut + 1..]);
                    match root.pointer_mut(parent) {
                        Some(J::Object(map)) => {
                            map.shift_remove(&key.replace("~1", "/").replace("~0", "~"));
                        }
                        Some(J::Array(items)) => {
                            if let Ok(i) = key.parse::<usize>()
                                && i < items.len()
                            {
                                items.remove(i);
                            }
                        }
                        _ => {}
                    }
                }
            }
            6 => {
                // Retarget a link (or a graph output) to some id.output.
                let links: Vec<String> = ptrs
                    .iter()
                    .filter(|p| p.ends_with("/link") || p.ends_with("/from"))
                    .cloned()
                    .collect();
                if !links.is_empty() {
                    let p = pick(&links, target);
                    *root.pointer_mut(&p).unwrap() = random_link(payload)["link"].clone();
                }
            }
            7 if node_count > 0 => {
                // Change a node's type.
                let i = (target % node_count as u64) as usize;
                if root["nodes"][i].is_object() {
                    root["nodes"][i]["type"] = json!(pick(TYPES, payload));
                }
            }
            8 if node_count > 0 => {
                // Set an input of a node to a literal or a link.
                let i = (target % node_count as u64) as usize;
                let name = pick(
                    &[
                        "a",
                        "b",
                        "value",
                        "cos_theta",
                        "ior_inside",
                        "f0",
                        "v",
                        "x",
                        "clamp",
                        "t",
                    ],
                    payload,
                );
                let value = match (payload / 16) % 6 {
                    0 => json!(pick(NUMBERS, payload / 64)),
                    1 => json!([0.5, 0.25, 1.0]),
                    2 => json!([0.5, 0.25]),
                    3 => json!(true),
                    4 => json!([1.0, 0.0, 0.0, 1.0]),
                    _ => random_link(payload / 64),
                };
                if !root["nodes"][i].is_object() {
                    return;
                }
                let inputs = &mut root["nodes"][i]["inputs"];
                if !inputs.is_object() {
                    *inputs = json!({});
                }
                inputs[name] = value;
            }
            9 if node_count > 0 => {
                // Set a node's data_type.
                let i = (target % node_count as u64) as usize;
                if root["nodes"][i].is_object() {
                    root["nodes"][i]["data_type"] = json!(pick(
                        &[
                            "float", "vec2", "vec3", "vec4", "color", "int", "bool", "bogus"
                        ],
                        payload
                    ));
                }
            }
            10 if node_count > 0 => {
                // Duplicate a node under a new or the same id.
                let i = (target % node_count as u64) as usize;
                let mut copy = root["nodes"][i].clone();
                if copy.is_object() && payload.is_multiple_of(2) {
                    copy["id"] = json!(format!("n{payload}"));
                }
                root["nodes"].as_array_mut().unwrap().push(copy);
            }
            11 => {
                // Turn a literal input into a link (or a link into a literal).
                let inputs: Vec<String> = ptrs
                    .iter()
                    .filter(|p| p.starts_with("/nodes/") && p.split('/').nth(3) == Some("inputs"))
                    .filter(|p| p.split('/').count() == 5)
                    .cloned()
                    .collect();
                if !inputs.is_empty() {
                    let p = pick(&inputs, target);
                    let slot = root.pointer_mut(&p).unwrap();
                    *slot = if slot.is_object() {
                        json!(pick(NUMBERS, payload))
                    } else {
                        random_link(payload)
                    };
                }
            }
            _ => {}
        }
    }

    fn mutate(seed: u8, edits: &[(u8, u64, u64)], pretty: bool) -> String {
        let mut root: J = serde_json::from_str(&fixture(seed)).unwrap();
        for &e in edits {
            apply_json_edit(&mut root, e);
        }
        if pretty {
            serde_json::to_string_pretty(&root).unwrap()
        } else {
            root.to_string()
        }
    }

    fn json_edits() -> impl Strategy<Value = Vec<(u8, u64, u64)>> {
        proptest::collection::vec((any::<u8>(), any::<u64>(), any::<u64>()), 1..5)
    }

    proptest! {
        #![proptest_config(config(1000))]

        #[test]
        fn arbitrary_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
            exercise(&String::from_utf8_lossy(&bytes));
        }

        #[test]
        fn arbitrary_json_shaped_text(text in r#"[\{\}\[\]":,0-9a-z\. \-]{0,200}"#) {
            exercise(&text);
            exercise(&format!(r#"{{"version": 1, "name": "g", "nodes": [{text}]}}"#));
        }
    }

    proptest! {
        #![proptest_config(config(2500))]

        #[test]
        fn byte_mutations_of_the_fixture(
            seed in any::<u8>(),
            edits in proptest::collection::vec((any::<u8>(), any::<usize>(), any::<u8>()), 1..6),
        ) {
            let mut bytes = fixture(seed).into_bytes();
            for e in edits {
                apply_byte_edit(&mut bytes, e);
            }
            let text = String::from_utf8_lossy(&bytes);
            exercise(&text);
        }

        #[test]
        fn structured_mutations_of_the_fixture(
            seed in any::<u8>(), edits in json_edits(), pretty in any::<bool>(),
        ) {
            let text = mutate(seed, &edits, pretty);
            exercise(&text);
        }

        /// Mutants that load save to canonical text: it loads again and saves to itself.
        #[test]
        fn loaded_mutants_round_trip(seed in any::<u8>(), edits in json_edits()) {
            let text = mutate(seed, &edits, true);
            let Ok(g) = Graph::from_json(&text, Registry::builtin()) else {
                return Ok(());
            };
            let saved = g.to_json();
            let again = Graph::from_json(&saved, Registry::builtin());
            prop_assert!(again.is_ok(), "saved:\n{}\nerrors: {:?}", saved, again.err());
            let again = again.unwrap();
            let types = |g: &Graph| g.outputs().iter().map(|o| (o.name.clone(), o.ty)).collect::<Vec<_>>();
            prop_assert_eq!(types(&again), types(&g));
            prop_assert_eq!(again.to_json(), saved);
        }
    }

    /// The mutators reach the interesting outcomes: some mutants load, some fail in each of
    /// several ways. Guards against a fuzzer that only ever produces syntax errors.
    #[test]
    fn structured_mutations_reach_validation() {
        use proptest::strategy::ValueTree;
        use proptest::test_runner::{RngAlgorithm, TestRng, TestRunner};
        let mut runner = TestRunner::new_with_rng(
            Config::default(),
            TestRng::from_seed(RngAlgorithm::ChaCha, &[7; 32]),
        );
        let strategy = (any::<u8>(), json_edits());
        let (mut ok, mut kinds) = (0, std::collections::BTreeSet::new());
        for _ in 0..400 {
            let (seed, edits) = strategy.new_tree(&mut runner).unwrap().current();
            let text = mutate(seed, &edits[..edits.len().min(2)], false);
            match Graph::from_json(&text, Registry::builtin()) {
                Ok(_) => ok += 1,
                Err(errors) => {
                    for e in errors {
                        let debug = format!("{e:?}");
                        kinds.insert(debug.split([' ', '{', '(']).next().unwrap().to_owned());
                    }
                }
            }
        }
        assert!(ok >= 20, "only {ok} of 400 mutants loaded");
        for kind in [
            "Structure",
            "UnknownNodeType",
            "UnknownInput",
            "WrongValueType",
            "MissingNode",
            "MissingOutput",
            "TypeMismatch",
            "Cycle",
            "BadOutput",
        ] {
            assert!(kinds.contains(kind), "no {kind} error among {kinds:?}");
        }
    }
}

// ---------------------------------------------------------------------------------------
// 4. The committed JSON Schema.
// ---------------------------------------------------------------------------------------

#[test]
fn committed_schema_is_up_to_date() {
    let path = repo_path("docs/graph.schema.json");
    let committed = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "{} is missing ({e}): run `cargo run -- schema -o docs/graph.schema.json`",
            path.display()
        )
    });
    assert!(
        committed == matgraph::document::json_schema(),
        "{} is out of date: run `cargo run -- schema -o docs/graph.schema.json`",
        path.display()
    );
}

#[test]
fn schema_describes_the_format() {
    let schema: serde_json::Value =
        serde_json::from_str(&matgraph::document::json_schema()).expect("schema is JSON");
    assert_eq!(schema["title"], "matgraph graph");
    let required: Vec<&str> = schema["required"]
        .as_array()
        .expect("required list")
        .iter()
        .filter_map(|v| v.as_str())
        .collect();
    for field in ["version", "name", "nodes"] {
        assert!(required.contains(&field), "{required:?}");
    }
    assert_eq!(schema["additionalProperties"], false);
}

/// Regression: the library's loader said "… at line 0, column 0" for a file it could not read.
#[test]
fn unreadable_files_are_named_without_a_location() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.json");
    let e = matgraph::io::load_graph(&missing, Registry::builtin()).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("missing.json") && text.contains("no such file"),
        "{text}"
    );
    assert!(!text.contains("line 0"), "{text}");
    let e = matgraph::io::load_graph(dir.path(), Registry::builtin()).unwrap_err();
    assert!(e.to_string().contains("is a directory"), "{e}");
}
