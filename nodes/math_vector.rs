//! Vector operations of Blender's Vector Math and Vector Rotate nodes that `math` lacks:
//! scale by a scalar, projection onto a vector, rotation about an axis (Rodrigues).
//!
//! Degenerate directions are made total like `normalize`: projecting onto a zero vector
//! gives 0, rotating about a zero axis returns the vector unchanged (Blender's rule). The
//! direction vectors are normalised with `normalize`'s rescaling, so vectors beyond 1e18 or
//! below 1e-18 keep their direction.

use super::math::{Vector, normalize};
use crate::node::{Category, In, NodeType, Out};
use crate::nodes::precise::{SIN_COS_WGSL, sin_cos};
use crate::precision::cross;
use crate::types::SocketType::*;
use crate::value::Value;
use glam::{Vec2, Vec3, Vec4};

/// Registers `f::<T>` for vec3, vec2 and vec4 (colour uses the vec3 variant).
macro_rules! vector_types {
    ($t:expr, $f:ident) => {
        $t.variant(Vec3, $f::<Vec3>)
            .variant(Vec2, $f::<Vec2>)
            .variant(Vec4, $f::<Vec4>)
    };
}

fn scale<T: Vector>(v: T, s: f32) -> T {
    v * T::splat(s)
}

/// The projection of `a` onto the line of `b`: `n (a · n)` with `n = normalize(b)`; 0 for a
/// zero `b`.
pub fn project<T: Vector>(a: T, b: T) -> T {
    let n = normalize(b);
    n * T::splat(a.dot_(n))
}

/// `v` rotated by `angle` radians about the axis through `center` along `axis` (right-hand
/// rule), by Rodrigues' formula p cos θ + (k × p) sin θ + k (k · p)(1 − cos θ) with
/// p = v − center and k = normalize(axis); `v` itself for a zero axis (Blender's Vector
/// Rotate).
pub fn rotate(v: Vec3, center: Vec3, axis: Vec3, angle: f32) -> Vec3 {
    let k = normalize(axis);
    if k == Vec3::ZERO {
        return v;
    }
    let p = v - center;
    let (s, c) = sin_cos(angle);
    p * c + cross(k, p) * s + k * (k.dot(p) * (1.0 - c)) + center
}

/// WGSL of [`project`]: the normalisation of the `normalize` node, then `n (a · n)`.
const PROJECT_WGSL: &str = r#"
fn $fn(a: $T, b: $T) -> $T {
    let s = dot(abs(b), $T(0.25));
    var u = b;
    if (s > 1e18 || (s < 1e-18 && s > 0.0)) {
        u = b / s;
    }
    let l = sqrt(dot(u, u));
    if (l > 0.0 && l <= 0x1.fffffep+127f) {
        let n = u * (1.0 / l);
        return n * dot(a, n);
    }
    return $T(0.0);
}
"#;

/// WGSL of [`rotate`].
const ROTATE_WGSL: &str = r#"
fn $fn(v: vec3<f32>, center: vec3<f32>, axis: vec3<f32>, angle: f32) -> vec3<f32> {
    let s = dot(abs(axis), vec3<f32>(0.25));
    var u = axis;
    if (s > 1e18 || (s < 1e-18 && s > 0.0)) {
        u = axis / s;
    }
    let l = sqrt(dot(u, u));
    if (!(l > 0.0 && l <= 0x1.fffffep+127f)) {
        return v;
    }
    let k = u * (1.0 / l);
    let p = v - center;
    let sc = mg_prec_sincos(angle);
    let sn = sc.x;
    let c = sc.y;
    return p * c + cross(k, p) * sn + k * (dot(k, p) * (1.0 - c)) + center;
}
"#;

/// The vector-math node types.
pub fn all() -> Vec<NodeType> {
    let v3 = Value::vec3;
    vec![
        vector_types!(
            NodeType::new(
                "scale",
                Category::Vector,
                "v times a scalar (Blender's Scale)."
            )
            .source("Closed form, v · s.")
            .input(In::generic("v", 1.0).range(-2.0, 2.0).doc("Vector."))
            .input(In::float("scale", 1.0).range(-10.0, 10.0).doc("Factor."))
            .output(Out::generic("result").doc("v · scale."))
            .wgsl("fn $fn(v: $T, s: f32) -> $T { return v * s; }"),
            scale
        ),
        vector_types!(
            NodeType::new(
                "project",
                Category::Vector,
                "The projection of a onto the line of b."
            )
            .source(
                "Blender's Project, b (a · b)/(b · b), formed as n (a · n) with n = \
                     normalize(b) so that b beyond 1e18 or below 1e-18 does not overflow or \
                     underflow; 0 for a zero b (Blender's rule; the cost: no direction, no error).",
            )
            .input(
                In::generic("a", 1.0)
                    .range(-2.0, 2.0)
                    .doc("Vector to project.")
            )
            .input(
                In::generic("b", 1.0)
                    .range(-2.0, 2.0)
                    .doc("Direction to project onto.")
            )
            .output(Out::generic("result").doc("The component of a along b."))
            .wgsl(PROJECT_WGSL)
            .hard_case("onto zero", &[("b", Value::float(0.0))])
            .hard_case("onto a huge vector", &[("b", Value::float(1e30))])
            .hard_case("onto a tiny vector", &[("b", Value::float(1e-30))]),
            project
        ),
        NodeType::new(
            "rotate",
            Category::Vector,
            "v rotated about an axis through a centre.",
        )
        .source(
            "Rodrigues' rotation formula (Blender's Vector Rotate, axis-angle): p cos θ + \
                 (k × p) sin θ + k (k · p)(1 − cos θ) + center, p = v − center, k = \
                 normalize(axis), right-handed (positive angles turn counter-clockwise seen \
                 from the tip of the axis). A zero axis returns v unchanged (Blender's rule). \
                 GPU sin/cos accuracy as for the sin node, so angles are best kept to a few turns.",
        )
        .input(
            In::vec3("v", [1.0, 0.0, 0.0])
                .range(-2.0, 2.0)
                .doc("Vector or point to rotate."),
        )
        .input(
            In::vec3("center", [0.0, 0.0, 0.0])
                .range(-2.0, 2.0)
                .doc("Point the axis passes through."),
        )
        .input(
            In::vec3("axis", [0.0, 0.0, 1.0])
                .range(-1.0, 1.0)
                .doc("Axis direction (any length)."),
        )
        .input(
            In::float("angle", 0.0)
                .range(-6.2831855, 6.2831855)
                .unit("rad")
                .doc("Rotation angle."),
        )
        .output(Out::vec3("result").doc("The rotated vector."))
        .wgsl(ROTATE_WGSL)
        .wgsl_uses(&[SIN_COS_WGSL])
        .hard_case(
            "zero axis",
            &[("axis", v3([0.0, 0.0, 0.0])), ("angle", Value::float(1.0))],
        )
        .hard_case(
            "huge axis",
            &[
                ("axis", v3([1e30, 0.0, 1e30])),
                ("angle", Value::float(2.0)),
            ],
        )
        .hard_case(
            "tiny axis",
            &[
                ("axis", v3([0.0, 1e-30, 0.0])),
                ("angle", Value::float(-1.0)),
            ],
        )
        .compute(rotate),
    ]
}
