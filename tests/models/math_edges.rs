//! The math nodes' finiteness contract (nodes/math.rs): for finite inputs the output is finite
//! wherever the exact result is within f32's range, even when an intermediate is not
//! (`length`, `normalize`, `cross`, `mix`; `dot` is kept bare, as documented); a result beyond the range overflows to
//! ±inf, as documented on `div`, `pow` and `remap`. Each expected value is the exact result,
//! worked out in f64 here.

use matgraph::{Graph, Plan, PlanOptions, Registry, SampleBatch};
use serde_json::{Value as J, json};
use std::collections::BTreeMap;

/// The first output of one node, evaluated on the CPU through the graph pipeline.
fn eval(node: &str, inputs: J) -> Vec<f32> {
    let map: BTreeMap<String, J> = serde_json::from_value(inputs).expect("an object");
    let graph = Graph::single_node(Registry::builtin(), node, map).expect("a valid graph");
    let plan = Plan::compile(&graph, &PlanOptions::default()).expect("compiles");
    let out = plan
        .execute(&SampleBatch::new(1), &plan.default_parameters())
        .expect("evaluates");
    out.value(0, 0).lanes().to_vec()
}

/// `got` within `rel` of `want` (f64), per component, or within two steps of the smallest
/// subnormal (1.4e-45) where the result is subnormal.
fn assert_near(what: &str, got: &[f32], want: &[f64], rel: f64) {
    assert_eq!(got.len(), want.len(), "{what}");
    for (g, w) in got.iter().zip(want) {
        let ok = if *w == 0.0 {
            *g == 0.0
        } else {
            let err = (*g as f64 - w).abs();
            err <= rel * w.abs() || err <= 2.0 * f32::from_bits(1) as f64
        };
        assert!(ok, "{what}: got {got:?}, want {want:?}");
    }
}

#[test]
fn vectors_beyond_1e18_or_below_1e_18_keep_their_length_and_direction() {
    for (s, n) in [
        (1e30f32, 3usize),
        (1e-30, 3),
        (3e38, 2),
        (1e-40, 3),
        (1e20, 4),
    ] {
        let v: Vec<f32> = (0..n).map(|k| if k % 2 == 0 { s } else { -s }).collect();
        let len = (s as f64) * (n as f64).sqrt();
        let got = eval("length", json!({ "v": v }));
        if len <= f32::MAX as f64 {
            assert_near(&format!("length of {n} × {s:e}"), &got, &[len], 1e-6);
        } else {
            assert_eq!(got, [f32::INFINITY], "a length beyond f32 overflows");
        }
        let unit: Vec<f64> = v.iter().map(|x| *x as f64 / len).collect();
        let got = eval("normalize", json!({ "v": v }));
        assert_near(&format!("normalize of {n} × {s:e}"), &got, &unit, 1e-6);
    }
    assert_eq!(eval("normalize", json!({ "v": [0.0, 0.0, 0.0] })), [0.0; 3]);
}

#[test]
fn cross_does_not_overflow_where_the_result_is_representable() {
    // The audit's case: two [1e30; 3] vectors are parallel, their cross product is 0.
    let big = [1e30f32, 1e30, 1e30];
    assert_eq!(eval("cross", json!({ "a": big, "b": big })), [0.0; 3]);
    let got = eval(
        "cross",
        json!({ "a": [1e30, 0.0, 0.0], "b": [0.0, 1e-30, 0.0] }),
    );
    assert_near("cross 1e30 x × 1e-30 y", &got, &[0.0, 0.0, 1.0], 1e-6);
    let got = eval(
        "cross",
        json!({ "a": [1e20, 0.0, 0.0], "b": [0.0, 1e20, 0.0] }),
    );
    assert_eq!(got[2], f32::INFINITY, "1e40 overflows");
    // dot is kept bare for speed, as its doc says: products within range are exact, and
    // overflowing products of opposite signs give NaN (inf − inf).
    let got = eval(
        "dot",
        json!({ "a": [1e30, 2e30, 0.0], "b": [3e-20, 1e-20, 0.0] }),
    );
    assert_near("dot 1e30 · 1e-20", &got, &[5e10], 1e-6);
    let got = eval(
        "dot",
        json!({ "a": [1e30, -1e30, 0.0], "b": [1e30, 1e30, 0.0] }),
    );
    assert!(got[0].is_nan(), "documented: inf − inf, got {got:?}");
}

#[test]
fn mix_of_values_of_opposite_sign_near_the_limit() {
    let (a, b) = (-3e38f32, 3e38f32);
    for (t, want) in [
        (0.0f32, a as f64),
        (0.5, 0.0),
        (1.0, b as f64),
        (0.25, -1.5e38),
    ] {
        let got = eval("mix", json!({ "a": a, "b": b, "t": t }));
        let ok = if want == 0.0 {
            got[0].abs() <= 1e31
        } else {
            ((got[0] as f64 - want) / want).abs() <= 1e-6
        };
        assert!(ok, "mix t {t}: got {got:?}, want {want:e}");
    }
}

#[test]
fn results_beyond_f32_overflow_as_documented() {
    assert_eq!(
        eval("div", json!({ "a": 10.0, "b": 2e-38 })),
        [f32::INFINITY]
    );
    assert_eq!(
        eval("div", json!({ "a": 10.0, "b": 0.0 })),
        [0.0],
        "x / 0 = 0"
    );
    assert_eq!(
        eval("pow", json!({ "a": 1e-20, "b": -2.0 })),
        [f32::INFINITY]
    );
    let got = eval(
        "remap",
        json!({ "x": 0.5, "from_min": 0.0, "from_max": 1e-40 }),
    );
    assert_eq!(got, [f32::INFINITY]);
    // Within range they are exact: 10 / 4e-38 = 2.5e38.
    let got = eval("div", json!({ "a": 10.0, "b": 4e-38 }));
    assert_near("div 10 / 4e-38", &got, &[10.0 / 4e-38f32 as f64], 1e-6);
}
