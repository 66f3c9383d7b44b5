//! Sampling images: files referenced by the graph, custom mip chains, and the scene's
//! textures (refraction, reflection, background).

use super::math_scalar::{ATAN2_HELPER_WGSL, atan2_total};
use crate::node::{Category, In, NodeType, Out};
use crate::precision::sqrt;
use crate::texture::{Filter, SAMPLE_WGSL, Wrap};
use glam::{Vec2, Vec3};

/// The image-family node types.
pub fn all() -> Vec<NodeType> {
    vec![image_texture(), equirect_uv()]
}

/// Texture coordinates of direction `d` in an equirectangular image (top-left origin), the
/// convention of `scene::equirect_uv`: `u = 0.5 + atan2(x, −z)/2π`, `v = atan2(√(x² + z²), y)/π`
/// (the zenith on the top row). `v` is written with `atan2` rather than `acos(y)` so it stays
/// well conditioned at the poles. Straight up or down u is 0.5; a zero direction gives (0.5, 0.5).
///
/// `atan2` is [`atan2_total`] (`mg_math_atan2` in WGSL), not WGSL's builtin, which is undefined
/// where an argument is 0 (a pole, the ±x and ±z half-planes) and may drop a zero's sign: with
/// it a GPU put the nadir at v = −1 and the seam's u at 0 or 1 at random. A zero is read as +0,
/// so the seam (x = 0 behind the viewer) is u = 1.
#[inline]
pub fn equirect_uv_of(d: Vec3) -> Vec2 {
    // Straight up or down (and the zero vector) get u = 0.5, the zero vector v = 0.5.
    let horizontal = d.x * d.x + d.z * d.z;
    let u = if horizontal == 0.0 {
        0.5
    } else {
        0.5 + atan2_total(d.x, -d.z) / std::f32::consts::TAU
    };
    let v = if d == Vec3::ZERO {
        0.5
    } else {
        atan2_total(sqrt(horizontal), d.y) / std::f32::consts::PI
    };
    Vec2::new(u, v)
}

/// WGSL of [`equirect_uv_of`], `mg_img_equirect_uv(d)`: the same steps. Needs
/// [`ATAN2_HELPER_WGSL`]; shared by `equirect_uv` and the IBL nodes.
pub const EQUIRECT_WGSL: &str = r#"
fn mg_img_equirect_uv(d: vec3<f32>) -> vec2<f32> {
    let horizontal = d.x * d.x + d.z * d.z;
    let u = select(0.5 + mg_math_atan2(d.x, -d.z) / 6.2831855, 0.5, horizontal == 0.0);
    let v = select(mg_math_atan2(sqrt(horizontal), d.y) / 3.1415927, 0.5, all(d == vec3<f32>(0.0)));
    return vec2<f32>(u, v);
}
"#;

fn equirect_uv() -> NodeType {
    NodeType::new(
        "equirect_uv",
        Category::Texture,
        "Where a direction lands in an equirectangular image.",
    )
    .source(
        "u = 0.5 + atan2(x, −z)/2π, v = atan2(√(x² + z²), y)/π: the convention of \
             scene::equirect_uv (−z at the image centre, the zenith on the top row), with an \
             atan2 defined at every input (a zero read as +0: the nadir is v = 1, the seam u = 1), \
             not WGSL's. Sample scene:environment with it to read the sky in a direction (for \
             example a reflection).",
    )
    .input(
        In::vec3("direction", [0.0, 0.0, -1.0])
            .range(-1.0, 1.0)
            .doc("Direction (need not be unit length)."),
    )
    .output(Out::vec2("uv").doc("Texture coordinates in the equirectangular image."))
    .hard_case(
        "zenith",
        &[("direction", crate::value::Value::vec3([0.0, 1.0, 0.0]))],
    )
    .hard_case(
        "nadir",
        &[("direction", crate::value::Value::vec3([0.0, -1.0, 0.0]))],
    )
    .hard_case(
        "zero",
        &[("direction", crate::value::Value::vec3([0.0, 0.0, 0.0]))],
    )
    .wgsl("fn $fn(d: vec3<f32>) -> vec2<f32> { return mg_img_equirect_uv(d); }")
    .wgsl_uses(&[ATAN2_HELPER_WGSL, EQUIRECT_WGSL])
    .compute(equirect_uv_of)
}

/// WGSL of `image_texture`: the code generator passes the texture's slot as `tex`.
const IMAGE_TEXTURE_WGSL: &str = r#"
fn $fn(tex: u32, uv: vec2<f32>, lod: f32, wrap: i32, filt: i32) -> $out {
    let c = mg_sample_texture(tex, uv, lod, u32(wrap), u32(filt));
    return $out(c.xyz, c.w);
}
"#;

fn image_texture() -> NodeType {
    NodeType::new(
        "image_texture",
        Category::Texture,
        "Samples an image at uv with an explicit mip level.",
    )
    .source(
        "The node's \"texture\" field names the image: a path relative to the graph file \
             (PNG and JPEG decoded from sRGB to linear, HDR and EXR linear; mips by a 2×2 box \
             filter), a list of paths for a custom mip chain (seed 002's sparkle band), or \
             scene:refraction, scene:reflection, scene:background. uv (0, 0) is the image's top \
             left corner; lod selects the mip level (fractions blend two levels); wrap and filter \
             as in crate::texture. CPU and GPU run the same arithmetic (texture::SAMPLE_WGSL).",
    )
    .input(
        In::vec2("uv", [0.0, 0.0])
            .range(-2.0, 2.0)
            .doc("Texture coordinates."),
    )
    .input(
        In::float("lod", 0.0)
            .range(0.0, 8.0)
            .hard(0.0, 64.0)
            .doc("Mip level: 0 is full resolution."),
    )
    .input(
        In::choice("wrap", Wrap::NAMES, Wrap::Repeat.index() as usize)
            .doc("What lies outside [0, 1]."),
    )
    .input(
        In::choice("filter", Filter::NAMES, Filter::Bilinear.index() as usize)
            .doc("Nearest texel or bilinear."),
    )
    .output(Out::color("color").doc("Linear RGB."))
    .output(Out::float("alpha").doc("Alpha (1 for images without one)."))
    .texture()
    .wgsl(IMAGE_TEXTURE_WGSL)
    .wgsl_uses(&[SAMPLE_WGSL])
    // The executor samples the bound texture; this kernel only declares the port shapes.
    .compute(|_uv: Vec2, _lod: f32, _wrap: i32, _filter: i32| (Vec3::ZERO, 0.0f32))
}
