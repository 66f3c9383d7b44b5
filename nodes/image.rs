//! Sampling images: files referenced by the graph, custom mip chains, and the scene's
//! textures (refraction, reflection, background).

use crate::node::{Category, In, NodeType, Out};
use crate::texture::{Filter, SAMPLE_WGSL, Wrap};
use glam::{Vec2, Vec3};

/// The image-family node types.
pub fn all() -> Vec<NodeType> {
    vec![image_texture()]
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
