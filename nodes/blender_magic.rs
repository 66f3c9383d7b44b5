//! Blender's Magic Texture node (Blender 4.x), its definition as Blender's sources state it
//! (`intern/cycles/kernel/svm/magic.h`; geometry nodes' `node_shader_tex_magic.cc`; the
//! legacy Blender Internal "magic" texture), written again here: three sines of the
//! coordinates, then up to ten rounds that feed each channel's sine or cosine, times
//! `distortion`, into the next.
//!
//! Sines and cosines are [`super::precise::sin_cos`] (WGSL's are specified to 2⁻¹¹ only), of
//! arguments clamped to ±10⁶ rad (see [`super::blender_wave`]). Each round multiplies the
//! colour's sensitivity to rounding by about 1.4 at |distortion| 2, 1.7 at 3 and 2.2 at 4
//! (measured, in f64, over depths 2–10), so the hard range of distortion stops at 2 (see the
//! node's limits).

use super::precise::{SIN_COS_WGSL, sin_cos};
use crate::node::{Category, In, NodeType, Out};
use crate::value::Value;
use glam::Vec3;

/// The bound on |coordinate · scale|, so that infinite coordinates stay finite (the first
/// sines' arguments pass [`ARG_LIMIT`] long before it).
const COORD_LIMIT: f32 = 1.0e12;
/// The bound on the sines' arguments (see the module doc).
const ARG_LIMIT: f32 = 1.0e6;

#[inline]
fn sin(x: f32) -> f32 {
    sin_cos(x.clamp(-ARG_LIMIT, ARG_LIMIT)).0
}

#[inline]
fn cos(x: f32) -> f32 {
    sin_cos(x.clamp(-ARG_LIMIT, ARG_LIMIT)).1
}

/// Blender's Magic Texture: `(color, fac)`, fac the mean of the colour's channels.
///
/// Source: Blender 4.x geometry nodes' `MagicFunction` (node_shader_tex_magic.cc) and
/// EEVEE's `node_tex_magic`, a function of vector·scale (the Cycles `svm_magic` we read
/// reduces the unscaled coordinates mod 2π before scaling, which differs wherever 5·scale is
/// not whole; we follow geometry nodes, whose values the tests hold us to): with
/// `c = vector·scale`, `x = sin(5(cx + cy + cz))`, `y = cos(5(−cx + cy − cz))`,
/// `z = −cos(5(−cx − cy + cz))`, then `depth` (clamped to [0, 10]) rounds of Blender's fixed
/// sequence, each scaling by `distortion`; divided by 2·distortion (unless 0);
/// `color = ½ − (x, y, z)`; |vector·scale| is clamped to 10¹².
pub fn magic_texture(vector: Vec3, scale: f32, distortion: f32, depth: i32) -> (Vec3, f32) {
    let c = (vector * scale).clamp(Vec3::splat(-COORD_LIMIT), Vec3::splat(COORD_LIMIT));
    let d = distortion;
    let mut x = sin((c.x + c.y + c.z) * 5.0);
    let mut y = cos((-c.x + c.y - c.z) * 5.0);
    let mut z = -cos((-c.x - c.y + c.z) * 5.0);
    let depth = depth.clamp(0, 10);
    if depth > 0 {
        x *= d;
        y *= d;
        z *= d;
        y = -cos(x - y + z) * d;
    }
    if depth > 1 {
        x = cos(x - y - z) * d;
    }
    if depth > 2 {
        z = sin(-x - y - z) * d;
    }
    if depth > 3 {
        x = -cos(-x + y - z) * d;
    }
    if depth > 4 {
        y = -sin(-x + y + z) * d;
    }
    if depth > 5 {
        y = -cos(-x + y + z) * d;
    }
    if depth > 6 {
        x = cos(x + y + z) * d;
    }
    if depth > 7 {
        z = sin(x + y - z) * d;
    }
    if depth > 8 {
        x = -cos(-x - y + z) * d;
    }
    if depth > 9 {
        y = -sin(x - y + z) * d;
    }
    if d != 0.0 {
        let d2 = d * 2.0;
        x /= d2;
        y /= d2;
        z /= d2;
    }
    let color = Vec3::new(0.5 - x, 0.5 - y, 0.5 - z);
    (color, (color.x + color.y + color.z) * (1.0 / 3.0))
}

/// WGSL of the clamped sine and cosine (needs [`SIN_COS_WGSL`]).
const CLAMPED_SIN_COS_WGSL: &str = r#"
fn mg_bm_sin(x: f32) -> f32 {
    return mg_prec_sincos(clamp(x, -1e6, 1e6)).x;
}

fn mg_bm_cos(x: f32) -> f32 {
    return mg_prec_sincos(clamp(x, -1e6, 1e6)).y;
}
"#;

/// WGSL of [`magic_texture`].
const MAGIC_TEXTURE_WGSL: &str = r#"
fn $fn(vector: vec3<f32>, scale: f32, d: f32, depth0: i32) -> $out {
    let c = clamp(vector * scale, vec3<f32>(-1e12), vec3<f32>(1e12));
    var x = mg_bm_sin((c.x + c.y + c.z) * 5.0);
    var y = mg_bm_cos((-c.x + c.y - c.z) * 5.0);
    var z = -mg_bm_cos((-c.x - c.y + c.z) * 5.0);
    let depth = clamp(depth0, 0, 10);
    if (depth > 0) {
        x = x * d;
        y = y * d;
        z = z * d;
        y = -mg_bm_cos(x - y + z) * d;
    }
    if (depth > 1) { x = mg_bm_cos(x - y - z) * d; }
    if (depth > 2) { z = mg_bm_sin(-x - y - z) * d; }
    if (depth > 3) { x = -mg_bm_cos(-x + y - z) * d; }
    if (depth > 4) { y = -mg_bm_sin(-x + y + z) * d; }
    if (depth > 5) { y = -mg_bm_cos(-x + y + z) * d; }
    if (depth > 6) { x = mg_bm_cos(x + y + z) * d; }
    if (depth > 7) { z = mg_bm_sin(x + y - z) * d; }
    if (depth > 8) { x = -mg_bm_cos(-x - y + z) * d; }
    if (depth > 9) { y = -mg_bm_sin(x - y + z) * d; }
    if (d != 0.0) {
        let d2 = d * 2.0;
        x = x / d2;
        y = y / d2;
        z = z / d2;
    }
    let color = vec3<f32>(0.5 - x, 0.5 - y, 0.5 - z);
    return $out(color, (color.x + color.y + color.z) * (1.0 / 3.0));
}
"#;

/// The Magic node type.
pub fn all() -> Vec<NodeType> {
    let f = Value::float;
    let v3 = Value::vec3;
    let i = Value::int;
    vec![
        NodeType::new(
            "magic_texture",
            Category::Texture,
            "Blender's Magic Texture: psychedelic interference colours from nested sines of the coordinates.",
        )
        .source(
            "Blender 4.x Magic Texture (geometry nodes' node_shader_tex_magic.cc; \
             intern/cycles/kernel/svm/magic.h): x, y, z = sin, cos, −cos of 5·(±cx ± cy ± cz) \
             at c = vector·scale, then depth rounds of Blender's fixed sequence of nested sines \
             and cosines times distortion, divided by 2·distortion; colour ½ − (x, y, z), fac \
             its mean. Matches Blender 4.2 within 1e-4 (tests/models/blender_textures.rs). \
             Deviations: `vector` defaults to the origin (Blender: generated coordinates); \
             the Cycles svm_magic we read reduces the unscaled coordinates mod 2π first, which \
             changes the pattern wherever 5·scale is not whole: we follow geometry nodes and \
             EEVEE (a function of vector·scale); |vector·scale| is clamped to 10¹² and every sine's argument is clamped to ±10⁶ rad (an f32 there is 0.06 \
             rad coarse already), so huge coordinates give a finite colour. Limits: each round \
             multiplies the colour's sensitivity to rounding (an ULP of the coordinates, a \
             product a GPU fuses into the next round's sum) by about 1.4 at |distortion| 2 and \
             2.2 at 4, so distortion's hard range is [−2, 2] (Blender: ±1000): at depth 10, 4 \
             ULPs of the coordinates move the colour by 6e-4 typically (0.18 at worst over \
             20 000 samples) at 2, by its whole range at 4, where the CPU and a GPU agree only \
             as two samples of the same noise. A file past it is refused at load; a linked distortion is used as it is.",
        )
        .input(In::vec3("vector", [0.0, 0.0, 0.0]).range(-10.0, 10.0).doc("Where to evaluate (link geometry.position or uv)."))
        .input(In::float("scale", 5.0).range(0.0, 50.0).hard(-1.0e3, 1.0e3).doc("Multiplies vector."))
        .input(In::float("distortion", 1.0).range(0.0, 2.0).hard(-2.0, 2.0).doc("Multiplies each round's sines (Blender allows ±1000; past ±2 deep patterns turn chaotic, see the node's limits)."))
        .input(In::int("depth", 2).range(0.0, 10.0).hard(0.0, 10.0).doc("Rounds of nested sines (0–10)."))
        .output(Out::color("color").doc("½ − (x, y, z): interference colours about 0.5."))
        .output(Out::float("fac").doc("The mean of the colour's channels."))
        .wgsl(MAGIC_TEXTURE_WGSL)
        .wgsl_constant_inputs(&["depth"])
        .wgsl_uses(&[SIN_COS_WGSL, CLAMPED_SIN_COS_WGSL])
        .hard_case("distortion 0", &[("vector", v3([0.3, 0.7, -0.2])), ("distortion", f(0.0)), ("depth", i(10))])
        .hard_case("depth 0", &[("vector", v3([0.3, 0.7, -0.2])), ("depth", i(0))])
        .hard_case("depth 10, strongest distortion", &[("vector", v3([0.3, 0.7, -0.2])), ("depth", i(10)), ("distortion", f(-2.0))])
        .hard_case("huge coordinates", &[("vector", v3([1.0e30, -1.0e30, 3.0e30])), ("scale", f(1.0e3)), ("depth", i(10))])
        .compute(magic_texture),
    ]
}
