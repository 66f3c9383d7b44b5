//! Blender's Mapping node: a vector scaled, rotated by Euler XYZ angles and translated, as a
//! point, a texture coordinate (the inverse transform), a direction or a normal.
//!
//! Source: Blender 4.x `gpu_shader_material_mapping.glsl` and Cycles `svm_mapping`
//! (intern/cycles/kernel/svm/mapping_util.h), with the rotation matrix of Blender's
//! `euler_to_mat3` (R = Rz·Ry·Rx: x turned first, each right-handed about a fixed axis).
//! Deviations, both where Blender's result is not a number: the `normal` type normalises with
//! the `normalize` node's rule (a zero vector gives 0, as Cycles' `safe_normalize`, where
//! Blender's GLSL `normalize` is undefined), and `safe_divide` gives 0 for a zero scale as
//! Blender's does.

use super::math::{NORMALIZE3_WGSL, normalize};
use crate::node::{Category, In, NodeType, Out};
use crate::nodes::precise::{SIN_COS_WGSL, sin_cos};
use crate::value::Value;
use glam::Vec3;

/// The mapping types, Blender's order (its default is `point`).
pub const MAPPING_TYPES: &[&str] = &["point", "texture", "vector", "normal"];

/// The rows of Blender's Euler XYZ rotation R = Rz(z)·Ry(y)·Rx(x) (`euler_to_mat3`).
pub fn euler_xyz_rows(r: Vec3) -> [Vec3; 3] {
    let (sx, cx) = sin_cos(r.x);
    let (sy, cy) = sin_cos(r.y);
    let (sz, cz) = sin_cos(r.z);
    [
        Vec3::new(cy * cz, sy * sx * cz - cx * sz, sy * cx * cz + sx * sz),
        Vec3::new(cy * sz, sy * sx * sz + cx * cz, sy * cx * sz - sx * cz),
        Vec3::new(-sy, cy * sx, cy * cx),
    ]
}

/// `m · v` for the rows `m`, each dot product summed left to right (as the WGSL does).
fn times(m: [Vec3; 3], v: Vec3) -> Vec3 {
    let dot = |r: Vec3| r.x * v.x + r.y * v.y + r.z * v.z;
    Vec3::new(dot(m[0]), dot(m[1]), dot(m[2]))
}

/// `mᵀ · v` for the rows `m`.
fn times_transposed(m: [Vec3; 3], v: Vec3) -> Vec3 {
    m[0] * v.x + m[1] * v.y + m[2] * v.z
}

/// Blender's `safe_divide`: `a / b` per component, 0 where `b` is 0.
fn safe_divide(a: Vec3, b: Vec3) -> Vec3 {
    let d = |a: f32, b: f32| if b != 0.0 { a / b } else { 0.0 };
    Vec3::new(d(a.x, b.x), d(a.y, b.y), d(a.z, b.z))
}

/// Blender's Mapping (`node_shader_mapping.cc`): `point` R(v ∘ s) + t, `texture`
/// Rᵀ(v − t) ⊘ s (the inverse of `point`), `vector` R(v ∘ s), `normal` normalize(R(v ⊘ s)),
/// with ∘ and ⊘ per component, ⊘ giving 0 for a zero scale component.
pub fn mapping(v: Vec3, location: Vec3, rotation: Vec3, scale: Vec3, kind: i32) -> Vec3 {
    let r = euler_xyz_rows(rotation);
    match kind {
        1 => safe_divide(times_transposed(r, v - location), scale),
        2 => times(r, v * scale),
        3 => normalize(times(r, safe_divide(v, scale))),
        _ => times(r, v * scale) + location,
    }
}

/// WGSL of [`mapping`], the same operations in the same order.
const MAPPING_WGSL: &str = r#"
fn $fn(v: vec3<f32>, location: vec3<f32>, rotation: vec3<f32>, scale: vec3<f32>, kind: i32) -> vec3<f32> {
    let x = mg_prec_sincos(rotation.x);
    let y = mg_prec_sincos(rotation.y);
    let z = mg_prec_sincos(rotation.z);
    let sx = x.x;
    let cx = x.y;
    let sy = y.x;
    let cy = y.y;
    let sz = z.x;
    let cz = z.y;
    let r0 = vec3<f32>(cy * cz, sy * sx * cz - cx * sz, sy * cx * cz + sx * sz);
    let r1 = vec3<f32>(cy * sz, sy * sx * sz + cx * cz, sy * cx * sz - sx * cz);
    let r2 = vec3<f32>(-sy, cy * sx, cy * cx);
    if (kind == 1) {
        let p = v - location;
        let q = r0 * p.x + r1 * p.y + r2 * p.z;
        return select(vec3<f32>(0.0), q / scale, scale != vec3<f32>(0.0));
    }
    var p = v * scale;
    if (kind == 3) {
        p = select(vec3<f32>(0.0), v / scale, scale != vec3<f32>(0.0));
    }
    let q = vec3<f32>(
        r0.x * p.x + r0.y * p.y + r0.z * p.z,
        r1.x * p.x + r1.y * p.y + r1.z * p.z,
        r2.x * p.x + r2.y * p.y + r2.z * p.z,
    );
    if (kind == 0) {
        return q + location;
    }
    if (kind == 3) {
        return mg_normalize3(q);
    }
    return q;
}
"#;

/// The mapping node type.
pub fn all() -> Vec<NodeType> {
    let v3 = Value::vec3;
    let i = Value::int;
    vec![
        NodeType::new(
            "mapping",
            Category::Vector,
            "Blender's Mapping: scale, rotate (Euler XYZ) and move a point, texture coordinate, direction or normal.",
        )
        .source(
            "Blender 4.x Mapping (gpu_shader_material_mapping.glsl, Cycles svm_mapping): point \
             R(v∘s) + t; texture Rᵀ(v − t)⊘s, the inverse of point, which moves the texture the \
             other way (Blender's habit); vector R(v∘s); normal normalize(R(v⊘s)). R = \
             Rz·Ry·Rx of the rotation's x, y, z angles (Blender's euler_to_mat3). ⊘ gives 0 for \
             a zero scale component (Blender's safe_divide) and a zero normal stays 0 (Cycles' \
             safe_normalize; Blender's GLSL would give NaN). sin and cos are the `sin` node's \
             (the same on every GPU), so angles are best kept to a few turns.",
        )
        .input(In::vec3("vector", [0.0, 0.0, 0.0]).range(-2.0, 2.0).hard(-1e18, 1e18).doc("The vector mapped (link uv, geometry.position or a normal)."))
        .input(In::vec3("location", [0.0, 0.0, 0.0]).range(-2.0, 2.0).hard(-1e18, 1e18).unit("m").doc("Translation t (point and texture types only)."))
        .input(In::vec3("rotation", [0.0, 0.0, 0.0]).range(-3.1415927, 3.1415927).hard(-1e4, 1e4).unit("rad").doc("Euler XYZ angles: x is turned first, then y, then z."))
        .input(In::vec3("scale", [1.0, 1.0, 1.0]).range(-4.0, 4.0).hard(-1e18, 1e18).doc("Scale s per axis (the texture type divides by it)."))
        .input(In::choice("type", MAPPING_TYPES, 0).doc("What the vector is: a point, a texture coordinate, a direction or a normal."))
        .output(Out::vec3("vector").doc("The mapped vector."))
        .wgsl(MAPPING_WGSL)
        .wgsl_uses(&[SIN_COS_WGSL, NORMALIZE3_WGSL])
        .hard_case("texture, zero scale", &[("vector", v3([1.0, 2.0, 3.0])), ("scale", v3([0.0, 2.0, 0.0])), ("type", i(1))])
        .hard_case("normal, zero scale", &[("vector", v3([1.0, 2.0, 3.0])), ("scale", v3([0.0, 0.0, 0.0])), ("type", i(3))])
        .hard_case("normal of a zero vector", &[("type", i(3))])
        .hard_case("normal, tiny", &[("vector", v3([1e-30, -1e-30, 0.0])), ("scale", v3([1e18, 1e18, 1e18])), ("type", i(3))])
        .hard_case("point, huge", &[("vector", v3([1e18, -1e18, 1e18])), ("scale", v3([1e18, 1e18, -1e18])), ("location", v3([1e18, 1e18, 1e18])), ("rotation", v3([1.0, 2.0, 3.0]))])
        .hard_case("texture, huge over tiny", &[("vector", v3([1e18, -1e18, 1e18])), ("location", v3([-1e18, 1e18, -1e18])), ("scale", v3([1e-18, 1e-18, 1e-18])), ("type", i(1))])
        .hard_case("large angles", &[("vector", v3([1.0, 1.0, 1.0])), ("rotation", v3([1e4, -1e4, 5e3])), ("type", i(2))])
        .compute(mapping),
    ]
}
