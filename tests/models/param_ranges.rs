//! Parameter values are checked against the hard ranges of the inputs they feed: the file's
//! value at load (direct links) and at plan compilation (values computed from parameters),
//! every value set through `ParamValues::set`. Errors name the parameter, the node, the
//! input and the range. Reference values are f64 closed forms written here.

use matgraph::error::GraphError;
use matgraph::exec::SampleBatch;
use matgraph::plan::{EvalError, Plan, PlanOptions};
use matgraph::{Graph, Registry, Value};
use std::path::Path;

/// A bundled graph's canonical text without its parameters' own `"range"`s (checked before
/// the fed inputs' ranges, tests/graphs/param_ranges.rs), so that these tests reach the ranges
/// of the inputs the parameters feed.
fn read(rel: &str) -> String {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    if let Some(params) = doc["parameters"].as_array_mut() {
        for p in params {
            p.as_object_mut().unwrap().remove("range");
        }
    }
    Graph::from_json(&doc.to_string(), Registry::builtin())
        .unwrap()
        .to_json()
}

fn glass() -> Graph {
    Graph::from_json(&read("graphs/fresnel_glass.json"), Registry::builtin()).unwrap()
}

/// Exact Fresnel reflectance of a dielectric at normal incidence, ((n - 1) / (n + 1))².
fn normal_reflectance(n: f64) -> f64 {
    ((n - 1.0) / (n + 1.0)).powi(2)
}

#[test]
fn the_graph_lists_what_each_parameter_feeds() {
    let g = glass();
    let p = &g.parameters()[0];
    let fed: Vec<(String, &str, f32, f32)> = p
        .feeds
        .iter()
        .map(|f| (f.node.clone(), f.input, f.range.min, f.range.max))
        .collect();
    assert!(
        fed.contains(&("exact".into(), "ior_inside", 1e-3, 100.0)),
        "{fed:?}"
    );
}

#[test]
fn set_refuses_values_outside_a_fed_range_and_keeps_the_old_value() {
    let plan = Plan::compile(&glass(), &PlanOptions::default()).unwrap();
    let mut params = plan.default_parameters();
    for bad in [0.0, -1.0, 1e-4, 100.5, 1e30] {
        let err = params.set("ior", Value::float(bad)).unwrap_err();
        let EvalError::ParameterOutOfRange {
            name,
            node,
            input,
            min,
            max,
            ..
        } = &err
        else {
            panic!("{bad}: {err:?}");
        };
        assert_eq!(name, "ior");
        assert!(node == "exact" || node == "f0", "{node}");
        assert_eq!(input, "ior_inside");
        assert_eq!((*min, *max), (1e-3, 100.0));
        let text = err.to_string();
        assert!(
            text.starts_with("parameter 'ior': input 'ior_inside' of node '"),
            "{text}"
        );
        assert!(
            text.ends_with("outside its hard range [0.001, 100]"),
            "{text}"
        );
        assert_eq!(params.get("ior"), Some(Value::float(1.52)));
    }
    // In range, at both ends and at seeded random points: evaluates to the closed form.
    let mut state = 12345u32;
    let mut values = vec![1e-3, 1.0, 2.42, 100.0];
    for _ in 0..8 {
        state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        values.push(1.0 + 3.0 * (state >> 8) as f32 / (1u32 << 24) as f32);
    }
    for n in values {
        params.set("ior", Value::float(n)).unwrap();
        let out = plan.execute(&SampleBatch::new(1), &params).unwrap();
        let want = normal_reflectance(n as f64);
        let got = out.value(0, 0).as_f32() as f64;
        assert!(
            (got - want).abs() <= 1e-5 * want.max(1e-3),
            "n={n}: {got} vs {want}"
        );
    }
}

#[test]
fn a_file_value_outside_a_fed_range_fails_to_load() {
    let text = read("graphs/fresnel_glass.json").replace("\"value\": 1.52", "\"value\": 0.0");
    let errors = Graph::from_json(&text, Registry::builtin()).unwrap_err();
    let e = errors
        .iter()
        .find(|e| matches!(e, GraphError::ParameterOutOfRange { target, .. } if target == "exact"))
        .unwrap_or_else(|| panic!("{errors:?}"));
    assert_eq!(e.node(), Some("ior"));
    assert_eq!(
        e.to_string(),
        "parameter 'ior' (node 'ior'): value 0.0 is outside [0.001, 100], the range of input 'ior_inside' of node 'exact' it feeds"
    );
    // A parameter node the graph does not expose is named by its id.
    let hidden = text.replace(
        r#"{ "name": "ior", "node": "ior", "doc": "Index of refraction of the glass (589 nm)." }"#,
        "",
    );
    assert_ne!(hidden, text, "the test edits the parameter list");
    let errors = Graph::from_json(&hidden, Registry::builtin()).unwrap_err();
    assert!(
        errors
            .iter()
            .any(|e| matches!(e, GraphError::ParameterOutOfRange { name, .. } if name == "ior")),
        "{errors:?}"
    );
}

#[test]
fn values_computed_from_a_parameter_are_checked_too() {
    // skin.json: eta feeds div(1, eta), which feeds the efresnel nodes' eta_i_over_t
    // (hard range [0.01, 100]): 1 / 1e-40 overflows to inf.
    let text = read("graphs/skin.json");
    let skin = Graph::from_json(&text, Registry::builtin()).unwrap();
    let plan = Plan::compile(&skin, &PlanOptions::default()).unwrap();
    let mut params = plan.default_parameters();
    let err = params.set("eta", Value::float(1e-40)).unwrap_err();
    assert!(
        matches!(&err, EvalError::ParameterOutOfRange { name, input, value, min, max, .. }
            if name == "eta" && input == "eta_i_over_t" && value == "inf" && *min == 0.01 && *max == 100.0),
        "{err:?}"
    );
    // 1 / 200 = 0.005 < 0.01; 1 / 50 = 0.02 is in range.
    assert!(params.set("eta", Value::float(200.0)).is_err());
    params.set("eta", Value::float(50.0)).unwrap();
    assert_eq!(params.get("eta"), Some(Value::float(50.0)));
    // The same value in the file: the link is not direct, so load passes and the plan
    // refuses it.
    let bad = text.replace(
        r#"{ "id": "eta", "type": "parameter", "inputs": { "value": 1.4 }"#,
        r#"{ "id": "eta", "type": "parameter", "inputs": { "value": 1e-40 }"#,
    );
    assert_ne!(bad, text, "the test edits eta's value");
    let g = Graph::from_json(&bad, Registry::builtin()).unwrap();
    let err = Plan::compile(&g, &PlanOptions::default()).err().unwrap();
    assert!(
        matches!(&err, EvalError::ParameterOutOfRange { name, .. } if name == "eta"),
        "{err:?}"
    );
}

#[test]
fn a_float_parameter_broadcast_to_a_colour_input_is_checked_per_lane() {
    let text = |v: f32| {
        format!(
            r#"{{"version": 1, "name": "g", "nodes": [
                {{"id": "p", "type": "parameter", "inputs": {{"value": {v:?}}}}},
                {{"id": "ss", "type": "skin_single_scattering", "inputs": {{"albedo": {{"link": "p.value"}}}}}}
            ], "outputs": [{{"name": "out", "from": "ss.brdf"}}],
            "parameters": [{{"name": "albedo", "node": "p"}}]}}"#
        )
    };
    let errors = Graph::from_json(&text(11.0), Registry::builtin()).unwrap_err();
    assert!(
        matches!(&errors[0], GraphError::ParameterOutOfRange { input, value, .. }
            if input == "albedo" && value.contains("11")),
        "{errors:?}"
    );
    let g = Graph::from_json(&text(0.5), Registry::builtin()).unwrap();
    let plan = Plan::compile(&g, &PlanOptions::default()).unwrap();
    let mut params = plan.default_parameters();
    assert!(params.set("albedo", Value::float(10.5)).is_err());
    assert!(params.set("albedo", Value::float(-0.1)).is_err());
    params.set("albedo", Value::float(10.0)).unwrap();
}
