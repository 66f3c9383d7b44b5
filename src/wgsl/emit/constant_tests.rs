//! The constant inputs' rewrite of a node function's signature ([`super::constant_parameters`]).

use super::constant_parameters;
use crate::value::Value;

const F: &str = "fn mg_f(slot: u32, a: array<f32, 4>, kind: i32, v: vec3<f32>, on: bool) -> f32 {\n    return a[0];\n}";

#[test]
fn constants_leave_the_signature_for_the_body() {
    // Four inputs after the texture slot: `kind` (input 1) and `on` (input 3) are written.
    let got = constant_parameters(
        F,
        "mg_f",
        4,
        &[(1, Value::int(-3)), (3, Value::boolean(true))],
    );
    assert_eq!(
        got.as_deref(),
        Some(
            "fn mg_f(slot: u32, a: array<f32, 4>, v: vec3<f32>) -> f32 {\n    const kind: i32 = -3i;\n    const on: bool = true;\n    return a[0];\n}"
        )
    );
}

#[test]
fn a_signature_that_cannot_take_them_is_refused() {
    // Another function's name, and more inputs than parameters.
    assert_eq!(
        constant_parameters(F, "mg_g", 4, &[(1, Value::int(0))]),
        None
    );
    assert_eq!(
        constant_parameters(F, "mg_f", 6, &[(1, Value::int(0))]),
        None
    );
    // An unclosed parameter list.
    assert_eq!(
        constant_parameters("fn mg_f(a: i32 -> f32 {}", "mg_f", 1, &[(0, Value::int(0))]),
        None
    );
}
