//! Triplanar blending: three colours, one per axis, mixed by weights from the surface normal,
//! so that a texture projected along x, y and z covers a surface without uvs.
//!
//! Source: the blend of Geiss, "Generating Complex Procedural Terrains Using the GPU", GPU
//! Gems 3 ch. 1 (2007), §1.5 ("Texturing and Shading"): weights from |N| raised to a power,
//! normalised to sum to 1 (Golus, "Normal Mapping for a Triplanar Shader", 2017, §"Blend",
//! writes the same `pow(abs(N), k)` form). Blender has no node of this name; its Image
//! Texture's Box projection is a different (piecewise-linear) blend, not followed here.

use super::precise::{LOG2_EXACT_WGSL, POW_WGSL, pow};
use crate::node::{Category, In, NodeType, Out};
use crate::value::Value;
use glam::Vec3;

/// The weights `(wx, wy, wz)`, summing to 1: with `a = |n|` and `r = a / max(a)` per
/// component, `w = r^blend / Σ r^blend`. Dividing by the largest component first keeps the
/// largest term exactly 1, so the sum lies in [1, 3] and never underflows at a large `blend`.
/// `0^blend` is 0 for `blend > 0` and 1 for `blend = 0` (a plain average), a component below
/// f32's smallest normal counts as 0, and a zero normal gives ⅓ each.
pub fn triplanar_weights(normal: Vec3, blend: f32) -> Vec3 {
    let a = normal.abs();
    let m = a.x.max(a.y).max(a.z);
    if m == 0.0 {
        return Vec3::splat(1.0 / 3.0);
    }
    let p = blend.max(0.0);
    let term = |c: f32| {
        let r = c / m;
        if r >= f32::MIN_POSITIVE {
            pow(r, p)
        } else if p == 0.0 {
            1.0
        } else {
            0.0
        }
    };
    let t = Vec3::new(term(a.x), term(a.y), term(a.z));
    t / (t.x + t.y + t.z)
}

/// The triplanar colour `wx · x + wy · y + wz · z` with the weights of [`triplanar_weights`].
pub fn triplanar(normal: Vec3, x: Vec3, y: Vec3, z: Vec3, blend: f32) -> Vec3 {
    let w = triplanar_weights(normal, blend);
    x * w.x + y * w.y + z * w.z
}

/// WGSL of [`triplanar_weights`], the same operations in the same order.
pub const TRIPLANAR_WEIGHTS_WGSL: &str = r#"
fn mg_triplanar_term(c: f32, m: f32, p: f32) -> f32 {
    let r = c / m;
    if (r >= 1.17549435e-38) {
        return mg_prec_pow(r, p);
    }
    return select(0.0, 1.0, p == 0.0);
}

fn mg_triplanar_weights(normal: vec3<f32>, blend: f32) -> vec3<f32> {
    let a = abs(normal);
    let m = max(max(a.x, a.y), a.z);
    if (m == 0.0) {
        return vec3<f32>(1.0 / 3.0);
    }
    let p = max(blend, 0.0);
    let t = vec3<f32>(mg_triplanar_term(a.x, m, p), mg_triplanar_term(a.y, m, p), mg_triplanar_term(a.z, m, p));
    return t / (t.x + t.y + t.z);
}
"#;

/// WGSL of [`triplanar`].
const TRIPLANAR_WGSL: &str = r#"
fn $fn(normal: vec3<f32>, x: vec3<f32>, y: vec3<f32>, z: vec3<f32>, blend: f32) -> vec3<f32> {
    let w = mg_triplanar_weights(normal, blend);
    return x * w.x + y * w.y + z * w.z;
}
"#;

/// The triplanar node type.
pub fn all() -> Vec<NodeType> {
    let v3 = Value::vec3;
    let f = Value::float;
    let c = Value::color;
    vec![
        NodeType::new(
            "triplanar",
            Category::Texture,
            "Three colours, one per axis, blended by the surface normal (triplanar projection).",
        )
        .source(
            "GPU Gems 3 ch. 1 (Geiss 2007, §1.5) blend: with a = |N| and r = a / max(a), \
             w = r^blend / Σ r^blend, then color = wx·x + wy·y + wz·z. blend 0 is a plain \
             average, 1 weights by |N| (normalised), large values give hard seams; N along an \
             axis gives that axis's colour alone at any blend > 0; a zero normal gives ⅓ each \
             (not NaN). Only the weights are here: each axis's colour is whatever is linked to \
             x, y, z. For an image per axis, feed each image the position projected along its \
             axis — (p.y, p.z) for x, (p.x, p.z) for y, (p.x, p.y) for z, with `split` and \
             `combine` of geometry.position, scaled by a `mapping` — not from this node: an \
             output of this node feeding its own inputs would be a cycle. Unlike Blender's Box \
             projection the faces seen from −x, −y, −z are mirrored. blend is held to \
             [0, 10⁴] (past ~100 the seams are already hard); the power is the `pow` node's \
             (the same on every GPU).",
        )
        .input(
            In::vec3("normal", [0.0, 0.0, 1.0])
                .range(-1.0, 1.0)
                .doc("The surface normal (link geometry.normal); need not be unit."),
        )
        .input(
            In::color("x", [1.0, 0.0, 0.0])
                .range(0.0, 1.0)
                .doc("The colour seen along ±x (the projection onto the yz plane)."),
        )
        .input(
            In::color("y", [0.0, 1.0, 0.0])
                .range(0.0, 1.0)
                .doc("The colour seen along ±y (the projection onto the xz plane)."),
        )
        .input(
            In::color("z", [0.0, 0.0, 1.0])
                .range(0.0, 1.0)
                .doc("The colour seen along ±z (the projection onto the xy plane)."),
        )
        .input(
            In::float("blend", 4.0)
                .range(0.0, 16.0)
                .hard(0.0, 1e4)
                .doc("Sharpness: the power of |N|; 0 averages, large values give hard seams."),
        )
        .output(Out::color("color").doc("The blended colour; the weights sum to 1."))
        .wgsl(TRIPLANAR_WGSL)
        .wgsl_uses(&[LOG2_EXACT_WGSL, POW_WGSL, TRIPLANAR_WEIGHTS_WGSL])
        .hard_case("zero normal", &[("normal", v3([0.0, 0.0, 0.0]))])
        .hard_case("normal along -y", &[("normal", v3([0.0, -1.0, 0.0]))])
        .hard_case(
            "blend 0, normal along x",
            &[("normal", v3([1.0, 0.0, 0.0])), ("blend", f(0.0))],
        )
        .hard_case(
            "blend 10⁴, diagonal",
            &[("normal", v3([1.0, 1.0, 1.0])), ("blend", f(1e4))],
        )
        .hard_case(
            "blend 10⁴, near diagonal",
            &[("normal", v3([1.0, 0.999, 0.998])), ("blend", f(1e4))],
        )
        .hard_case(
            "tiny normal",
            &[
                ("normal", v3([1e-38, -1e-45, 3e-39])),
                ("x", c([0.9, 0.5, 0.1])),
            ],
        )
        .hard_case(
            "huge normal",
            &[("normal", v3([3e38, -3e38, 1e30])), ("blend", f(2.0))],
        )
        .compute(triplanar),
    ]
}
