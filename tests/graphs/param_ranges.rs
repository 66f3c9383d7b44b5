//! Every parameter of every bundled graph has a `range` that keeps the outputs finite
//! (issue 37): each is swept over its range's ends, middle, 0 and denormals on the CPU
//! executor (tests/gpu/gpu_parity.rs sweeps the same points on the GPU), values outside it
//! (±1e38, ±∞, NaN, just past an end) are refused by `set` with the parameter's name, and
//! denormal, tiny and huge normals and view vectors give finite outputs.

use crate::common;

use common::parity::{
    degenerate_geometry_batch, first_non_finite, parameter_sweep, refused_values,
    shipped_graph_cases, textured_grid_batch,
};
use matgraph::{EvalError, Graph, GraphDocument, Plan, PlanOptions, Registry, Value};
use std::sync::Arc;

#[test]
fn every_bundled_parameter_has_a_range() {
    for path in common::bundled_graphs() {
        let graph = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        for p in graph.parameters() {
            assert!(
                p.range.is_some(),
                "{}: parameter '{}' has no \"range\"",
                path.display(),
                p.name
            );
        }
    }
}

#[test]
fn every_parameter_over_its_range_gives_finite_outputs_on_the_cpu() {
    let mut failures = Vec::new();
    let mut points = 0;
    for case in shipped_graph_cases() {
        for (what, params) in parameter_sweep(&case.plan) {
            points += 1;
            let out = case.plan.execute(&case.batch, &params).unwrap();
            if let Some(bad) = first_non_finite(&out) {
                failures.push(format!("{} {what}: {bad}", case.name));
            }
        }
    }
    eprintln!("{points} sweep points");
    assert!(
        failures.is_empty(),
        "non-finite outputs:\n{}",
        failures.join("\n")
    );
}

#[test]
fn values_outside_a_parameters_range_are_refused_with_its_name() {
    // water_sunshine's `tiling` at 1e38 gave NaN; now no such value gets in.
    for case in shipped_graph_cases() {
        for p in case.plan.parameters() {
            let r = p.range.unwrap();
            for v in refused_values(r.min, r.max) {
                let mut params = case.plan.default_parameters();
                let before = params.get(&p.name);
                let err = params.set(&p.name, Value::float(v)).unwrap_err();
                // Refused by its own range, or first by an input it feeds (which says more).
                let text = err.to_string();
                match &err {
                    EvalError::ParameterOutsideItsRange { name, .. } => assert!(
                        *name == p.name
                            && text
                                .ends_with(&format!("is outside its range [{}, {}]", r.min, r.max)),
                        "{text}"
                    ),
                    EvalError::ParameterOutOfRange { name, .. } => {
                        assert!(*name == p.name, "{text}")
                    }
                    e => panic!("{} {} = {v}: {e:?}", case.name, p.name),
                }
                assert!(
                    text.starts_with(&format!("parameter '{}': ", p.name)),
                    "{text}"
                );
                assert_eq!(params.get(&p.name), before, "{} {}", case.name, p.name);
            }
        }
    }
}

#[test]
fn a_file_value_or_range_out_of_bounds_is_a_load_error() {
    let text = |value: &str, range: &str| {
        format!(
            r#"{{ "version": 1, "name": "t",
  "nodes": [ {{ "id": "k", "type": "parameter", "inputs": {{ "value": {value} }} }} ],
  "outputs": [ {{ "name": "o", "from": "k.value" }} ],
  "parameters": [ {{ "name": "gain", "node": "k", "range": {range} }} ] }}"#
        )
    };
    let err = |value: &str, range: &str| {
        matgraph::Graph::from_json(&text(value, range), Registry::builtin())
            .unwrap_err()
            .iter()
            .map(|e| e.to_string())
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(
        err("5.0", "[0, 2]"),
        "parameter 'gain': its value 5.0 (node 'k') is outside its range [0, 2]"
    );
    assert_eq!(
        err("[0.5, 3.0, 0.5]", "[0, 2]"),
        "parameter 'gain': its value [0.5,3.0,0.5] (node 'k') is outside its range [0, 2]"
    );
    assert!(err("1.0", "[2, 0]").contains("its range [2, 0] must be two finite numbers"));
    assert!(matgraph::Graph::from_json(&text("1.0", "[0, 2]"), Registry::builtin()).is_ok());
    // The range round-trips through the canonical form.
    let g = matgraph::Graph::from_json(&text("1.0", "[-1.5, 2]"), Registry::builtin()).unwrap();
    assert!(
        g.to_json().contains(r#""range": [-1.5, 2.0]"#),
        "{}",
        g.to_json()
    );
}

#[test]
fn degenerate_normals_and_views_give_finite_outputs() {
    // bubble_iridescent_fast with a denormal view or normal gave NaN (a tiny vector's
    // normalisation).
    let mut failures = Vec::new();
    for case in shipped_graph_cases() {
        let mut batch = degenerate_geometry_batch();
        if let Some(t) = case.batch.textures() {
            batch.set_textures(Arc::new(t.clone()));
        }
        let out = case
            .plan
            .execute(&batch, &case.plan.default_parameters())
            .unwrap();
        if let Some(bad) = first_non_finite(&out) {
            failures.push(format!("{}: {bad}", case.name));
        }
    }
    assert!(
        failures.is_empty(),
        "non-finite outputs:\n{}",
        failures.join("\n")
    );
}

#[test]
fn a_texture_read_at_a_uv_beyond_f32s_range_is_finite() {
    // The cause of water_sunshine's NaN at tiling = 1e38 (its range now refuses that):
    // the bilinear read at uv 5e37 × 128 texels took ∞ − ⌊∞⌋. Its graphs without their
    // ranges, swept to ±1e38.
    for name in [
        "water_sunshine",
        "water_sunshine_sunset",
        "water_sunshine_fresnel",
    ] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("graphs")
            .join(format!("{name}.json"));
        let mut doc = GraphDocument::parse(&std::fs::read_to_string(&path).unwrap()).unwrap();
        for p in &mut doc.parameters {
            p.range = None;
        }
        let graph = Graph::from_document(&doc, Registry::builtin()).unwrap();
        let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
        let batch = textured_grid_batch(&graph, &plan, &path);
        for v in [1e38, -1e38, 3.4e38, 1e20] {
            let mut params = plan.default_parameters();
            params.set("tiling", Value::float(v)).unwrap();
            let out = plan.execute(&batch, &params).unwrap();
            assert_eq!(first_non_finite(&out), None, "{name} tiling = {v:e}");
        }
    }
}
