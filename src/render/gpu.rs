//! `render --gpu`: the whole frame drawn by the GPU rasteriser ([`crate::gpu::raster`]), with
//! the scene textures drawn by GPU passes. Where the rasteriser cannot draw a frame (an image
//! environment, a sample count without a standard MSAA pattern on the device, a frame over
//! the device's limits) the caller falls back to the hybrid path and says why.

use super::{HdrImage, RenderError, RenderOptions, RenderTimings, SCENE_TEXTURE_MAX};
use crate::gpu::GpuContext;
use crate::gpu::raster::{self, MaterialInput};
use crate::graph::Graph;
use crate::plan::ParamValues;
use crate::scene::{Mesh, Scene, ScenePass};
use crate::texture::{Image, Texture, TextureSet};
use std::time::Instant;

/// Why the GPU rasteriser cannot draw this render, if it cannot.
pub(super) fn unsupported(
    ctx: &GpuContext,
    scene: &Scene,
    options: &RenderOptions,
) -> Option<String> {
    if let Err(why) = scene.gpu_supported() {
        return Some(why);
    }
    raster::unsupported(ctx, options.width, options.height, options.samples.max(1))
}

/// The textures the GPU render binds: the caller's images and the scene textures the graph
/// samples, drawn on the GPU (their mip chains built here).
fn textures(
    ctx: &GpuContext,
    graph: &Graph,
    scene: &Scene,
    options: &RenderOptions,
) -> Result<TextureSet, RenderError> {
    let texture_error = |e: crate::texture::TextureError| RenderError::Texture(e.to_string());
    let mut set = TextureSet::new();
    if let Some(given) = &options.textures {
        set.extend_shared(given).map_err(texture_error)?;
    }
    let wanted: Vec<&str> = graph
        .nodes()
        .iter()
        .filter_map(|n| n.texture.as_ref()?.scene_name())
        .collect();
    let key = |name: &str| format!("{}{name}", crate::document::TextureSource::SCENE);
    if wanted.iter().any(|w| super::is_environment_texture(w)) {
        // The map is drawn on the GPU; its image-based-lighting tables are made from it on
        // the CPU and uploaded (super::insert_environment_textures).
        let (w, h) = (
            super::ENVIRONMENT_MAP_WIDTH,
            super::ENVIRONMENT_MAP_WIDTH / 2,
        );
        let data = raster::render_environment(ctx, scene, w, h)?;
        let image = Image::new(w, h, data).map_err(texture_error)?;
        super::insert_environment_textures(&mut set, &wanted, image).map_err(texture_error)?;
    }
    let (tw, th) = super::scene_texture_size(options.width, options.height);
    debug_assert!(tw.max(th) <= SCENE_TEXTURE_MAX);
    for (name, pass) in [
        ("background", ScenePass::Background),
        ("refraction", ScenePass::Refraction),
        ("reflection", ScenePass::Reflection),
    ] {
        if !wanted.contains(&name) {
            continue;
        }
        let rgb = raster::render_scene_pass(ctx, scene, tw, th, pass)?;
        let image = Image::new(
            tw,
            th,
            rgb.iter().map(|c| [c[0], c[1], c[2], 1.0]).collect(),
        )
        .map_err(texture_error)?;
        set.insert(key(name), Texture::new(image, true).map_err(texture_error)?)
            .map_err(texture_error)?;
    }
    Ok(set)
}

/// Renders on the GPU rasteriser; `t` gets the stages' times.
pub(super) fn render(
    ctx: &GpuContext,
    graph: &Graph,
    scene: &Scene,
    options: &RenderOptions,
    params: &ParamValues,
    time: f32,
    t: &mut RenderTimings,
) -> Result<HdrImage, RenderError> {
    let start = Instant::now();
    let set = textures(ctx, graph, scene, options)?;
    t.gbuffer = start.elapsed();
    let mesh: Mesh = scene.material_mesh();
    let input = MaterialInput {
        graph,
        texture_mode: options.texture_mode,
        params,
        time,
        textures: &set,
        mesh: &mesh,
    };
    let (w, h) = (options.width, options.height);
    let (pixels, rt) = raster::render_frame(ctx, scene, (w, h, options.samples.max(1)), &input)?;
    t.compile = rt.compile;
    t.upload = rt.upload;
    t.draw = rt.draw;
    t.readback = rt.readback;
    Ok(HdrImage {
        width: w,
        height: h,
        pixels,
    })
}
