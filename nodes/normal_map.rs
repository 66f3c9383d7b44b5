//! Blender's Normal Map node: a normal-map texel turned into a world-space shading normal,
//! in the tangent frame (MikkTSpace) or as an object- or world-space normal, with a strength.
//!
//! Source: Blender 4.x Normal Map (Cycles `svm_node_normal_map`, kernel/svm/tex_coord.h;
//! EEVEE `node_normal_map` and `node_normal_map_mix`): in tangent space
//! `N' = normalize(m.x T + m.y B + m.z N)` with `m = 2c − 1` and `B = sign · (N × T)`; then
//! `normalize(N + (N' − N) · max(strength, 0))`.

use super::math::{NORMALIZE3_WGSL, normalize};
use crate::node::{Category, In, NodeType, Out};
use crate::precision::cross;
use crate::value::Value;
use glam::Vec3;

/// The spaces a normal map's texels are written in.
pub const NORMAL_MAP_SPACES: &[&str] = &["tangent", "object", "world"];

/// Green's direction: OpenGL (Blender, glTF, Unity: +v up) or DirectX (Unreal, 3ds Max).
pub const NORMAL_MAP_CONVENTIONS: &[&str] = &["opengl", "directx"];

/// Blender's Normal Map: the texel `color` (clamped to [0, 1]; DirectX maps' green flipped)
/// as `m = 2c − 1`, in the frame `(tangent, sign · (normal × tangent), normal)` for the
/// tangent space or as it is for the object and world spaces, normalised, then blended from
/// `normal` by `strength` (≥ 0) and normalised again. Where a result has no direction (a
/// texel of (½, ½, ½), or a blend that cancels) the unperturbed `normal` is returned.
pub fn normal_map(
    color: Vec3,
    strength: f32,
    normal: Vec3,
    tangent: Vec3,
    sign: f32,
    space: i32,
    convention: i32,
) -> Vec3 {
    let mut c = color.clamp(Vec3::ZERO, Vec3::ONE);
    if convention == 1 {
        c.y = 1.0 - c.y;
    }
    let m = c * 2.0 - Vec3::ONE;
    let mapped = if space == 0 {
        let b = cross(normal, tangent) * if sign >= 0.0 { 1.0 } else { -1.0 };
        tangent * m.x + b * m.y + normal * m.z
    } else {
        m
    };
    let u = normalize(mapped);
    if u == Vec3::ZERO {
        return normal;
    }
    let out = normalize(normal + (u - normal) * strength.max(0.0));
    if out == Vec3::ZERO { normal } else { out }
}

/// WGSL of [`normal_map`], the same operations in the same order.
const NORMAL_MAP_WGSL: &str = r#"
fn $fn(color: vec3<f32>, strength: f32, normal: vec3<f32>, tangent: vec3<f32>, sign: f32, space: i32, convention: i32) -> vec3<f32> {
    var c = clamp(color, vec3<f32>(0.0), vec3<f32>(1.0));
    if (convention == 1) {
        c.y = 1.0 - c.y;
    }
    let m = c * 2.0 - vec3<f32>(1.0);
    var mapped = m;
    if (space == 0) {
        let b = cross(normal, tangent) * select(-1.0, 1.0, sign >= 0.0);
        mapped = tangent * m.x + b * m.y + normal * m.z;
    }
    let u = mg_normalize3(mapped);
    if (all(u == vec3<f32>(0.0))) {
        return normal;
    }
    let o = mg_normalize3(normal + (u - normal) * max(strength, 0.0));
    return select(o, normal, all(o == vec3<f32>(0.0)));
}
"#;

/// The normal-map node type.
pub fn all() -> Vec<NodeType> {
    let v3 = Value::vec3;
    let f = Value::float;
    let i = Value::int;
    vec![
        NodeType::new(
            "normal_map",
            Category::Vector,
            "Blender's Normal Map: a normal-map texel as a world-space shading normal.",
        )
        .source(
            "Blender 4.x Normal Map (Cycles svm_node_normal_map, EEVEE node_normal_map): m = 2c − 1; \
             tangent space: N' = normalize(m.x T + m.y B + m.z N), B = sign · (N × T), the \
             MikkTSpace frame (link geometry.normal, geometry.tangent, geometry.bitangent_sign); \
             object and world space: N' = normalize(m); then normalize(N + (N' − N) · strength). \
             The texel is clamped to [0, 1] (a filtered or linked value may stray: the cost is \
             none for real maps). DirectX maps (Unreal, 3ds Max) have green pointing down: \
             `convention` flips it. Object space is world space here: matgraph's meshes are built \
             in world space (an app with a model matrix transforms the result itself). Where the \
             result has no direction (a texel of ½ grey, or a blend that cancels) the input \
             normal is returned, where Blender's GLSL would give NaN.",
        )
        .input(In::color("color", [0.5, 0.5, 1.0]).range(0.0, 1.0).hard(0.0, 1.0).doc("The texel, from an image read as data (0.5, 0.5, 1 is flat)."))
        .input(In::float("strength", 1.0).range(0.0, 2.0).hard(0.0, 100.0).doc("0: the surface's normal; 1: the map's; above 1 exaggerated."))
        .input(In::vec3("normal", [0.0, 0.0, 1.0]).range(-1.0, 1.0).doc("Unit shading normal N (link geometry.normal)."))
        .input(In::vec3("tangent", [1.0, 0.0, 0.0]).range(-1.0, 1.0).doc("Unit tangent T orthogonal to N (link geometry.tangent)."))
        .input(In::float("bitangent_sign", 1.0).range(-1.0, 1.0).doc("±1 (link geometry.bitangent_sign); ≥ 0 reads as +1."))
        .input(In::choice("space", NORMAL_MAP_SPACES, 0).doc("What the map's texels are relative to."))
        .input(In::choice("convention", NORMAL_MAP_CONVENTIONS, 0).doc("opengl: green up (Blender, glTF); directx: green down."))
        .output(Out::vec3("normal").doc("The unit world-space shading normal."))
        .wgsl(NORMAL_MAP_WGSL)
        .wgsl_uses(&[NORMALIZE3_WGSL])
        .hard_case("grey texel: no direction", &[("color", Value::color([0.5, 0.5, 0.5]))])
        .hard_case("strength 0", &[("color", Value::color([1.0, 0.0, 0.5])), ("strength", f(0.0))])
        .hard_case("strength 100", &[("color", Value::color([1.0, 0.5, 0.5])), ("strength", f(100.0))])
        .hard_case("the map opposite the normal, strength ¼", &[("color", Value::color([0.5, 0.5, 0.0])), ("strength", f(0.25))])
        .hard_case("tangent along the normal", &[("tangent", v3([0.0, 0.0, 1.0])), ("color", Value::color([1.0, 1.0, 1.0]))])
        .hard_case("zero normal and tangent", &[("normal", v3([0.0, 0.0, 0.0])), ("tangent", v3([0.0, 0.0, 0.0]))])
        .hard_case("world space, DirectX", &[("color", Value::color([0.0, 0.0, 1.0])), ("space", i(2)), ("convention", i(1))])
        .compute(normal_map),
    ]
}
