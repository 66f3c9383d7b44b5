//! `render --gpu`: the whole frame drawn by the GPU rasteriser ([`crate::gpu::raster`]), with
//! the scene textures drawn by GPU passes. Every scene, environment, sample count and frame
//! size is drawn there (sample counts without MSAA on the device as jittered passes, frames
//! over the device's limits in tiles); the CPU rasteriser is never used. The one error is a
//! device without the feature the rasteriser needs.

use super::{HdrImage, RenderError, RenderOptions, RenderTimings, SCENE_TEXTURE_MAX};
use crate::gpu::GpuContext;
use crate::gpu::raster::{self, MaterialInput};
use crate::graph::Graph;
use crate::memo::{Memo, Same};
use crate::plan::ParamValues;
use crate::scene::{Mesh, Scene, ScenePass};
use crate::texture::{Image, Texture, TextureSet};
use std::sync::Arc;
use std::time::Instant;

/// The textures the GPU render binds: the caller's images and the scene textures the graph
/// samples ([`scene_textures`]).
fn textures(
    ctx: &GpuContext,
    graph: &Graph,
    scene: &Scene,
    options: &RenderOptions,
) -> Result<TextureSet, RenderError> {
    let mut set = TextureSet::new();
    if let Some(given) = &options.textures {
        set.extend_shared(given)?;
    }
    let mut wanted: Vec<&str> = graph
        .nodes()
        .iter()
        .filter_map(|n| n.texture.as_ref()?.scene_name())
        .collect();
    wanted.sort_unstable();
    wanted.dedup();
    let (environment, passes): (Vec<&str>, Vec<&str>) = wanted
        .iter()
        .partition(|w| super::is_environment_texture(w));
    // The environment's textures (a map and its prefiltered tables, the same at every frame
    // size) apart from the passes' (at the frame's size): the editor's drafts, whose side
    // follows their time, redraw only the passes.
    static ENVIRONMENT_TEXTURES: Memo<SceneKey, Arc<TextureSet>, 4> = Memo::new();
    static PASS_TEXTURES: Memo<SceneKey, Arc<TextureSet>, 4> = Memo::new();
    let size = super::scene_texture_size(options.width, options.height);
    for (memo, names, size) in [
        (&ENVIRONMENT_TEXTURES, &environment, (0, 0)),
        (&PASS_TEXTURES, &passes, size),
    ] {
        if names.is_empty() {
            continue;
        }
        // The environment's key leaves out the camera and the mesh detail, which its map
        // does not see: an orbit or a draft keeps its tables.
        let scene_key = match size {
            (0, 0) => scene.environment_key(),
            _ => serde_json::to_string(scene).unwrap_or_default(),
        };
        let key: SceneKey = (
            scene_key,
            names.iter().map(|w| w.to_string()).collect(),
            size,
            Same(options.environment.clone()),
        );
        let made = memo.get_or_make(key, || {
            scene_textures(ctx, scene, options, names).map(Arc::new)
        })?;
        set.extend_shared(&made)?;
    }
    Ok(set)
}

/// What the scene textures of a frame depend on: the scene (its time included; for the
/// environment's, [`Scene::environment_key`]), the names the graph samples, the scene textures' size (none for the environment's) and the environment
/// image. A material's parameters are not in it, so a parameter change redraws no scene
/// texture.
type SceneKey = (String, Vec<String>, (u32, u32), Same<Texture>);

/// The scene textures in `wanted` (`scene:` names), drawn on the GPU (their mip chains built
/// here).
fn scene_textures(
    ctx: &GpuContext,
    scene: &Scene,
    options: &RenderOptions,
    wanted: &[&str],
) -> Result<TextureSet, RenderError> {
    let mut set = TextureSet::new();
    let key = |name: &str| format!("{}{name}", crate::document::TextureSource::SCENE);
    if wanted.iter().any(|w| super::is_environment_texture(w)) {
        // The map is drawn on the GPU; its image-based-lighting tables are made from it on
        // the CPU and uploaded (super::insert_environment_textures).
        let (w, h) = (
            super::ENVIRONMENT_MAP_WIDTH,
            super::ENVIRONMENT_MAP_WIDTH / 2,
        );
        let data = raster::render_environment(ctx, scene, options.environment.as_ref(), w, h)?;
        let image = Image::new(w, h, data)?;
        super::insert_environment_textures(&mut set, wanted, image)?;
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
        let rgb = raster::render_scene_pass(
            ctx,
            scene,
            options.environment.as_ref(),
            (tw, th),
            pass,
            options.texture_mode,
        )?;
        let image = Image::new(
            tw,
            th,
            rgb.iter().map(|c| [c[0], c[1], c[2], 1.0]).collect(),
        )?;
        set.insert(key(name), Texture::new(image, true)?)?;
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
    if let Some(why) = raster::unavailable(ctx) {
        return Err(crate::plan::EvalError::Gpu(why).into());
    }
    let start = Instant::now();
    let set = textures(ctx, graph, scene, options)?;
    t.gbuffer = start.elapsed();
    // Made once per mesh (`Scene::material_mesh_key`): frames that change only the
    // material or the camera reuse it, and the device its buffers.
    static MESHES: Memo<String, Arc<Mesh>, 4> = Memo::new();
    let mesh = MESHES.get_or(scene.material_mesh_key(), || {
        Arc::new(scene.material_mesh())
    });
    let input = MaterialInput {
        graph,
        texture_mode: options.texture_mode,
        params,
        time,
        textures: &set,
        mesh: &mesh,
    };
    let (w, h) = (options.width, options.height);
    let (pixels, rt) = raster::render_frame(
        ctx,
        scene,
        options.environment.as_ref(),
        (w, h, options.samples.max(1)),
        &input,
    )?;
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
