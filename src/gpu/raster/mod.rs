//! The GPU rasteriser of `matgraph render --gpu`: wgpu render pipelines draw the whole
//! frame, the CPU rasteriser is not used.
//!
//! - **Scene** (`scene.wgsl`, `objects.wgsl`, `backdrop.wgsl`): the sky or the image
//!   environment, and the built-in surfaces (backdrop, seabed, skirts, objects) with Lambert
//!   shading, hard shadows from the analytic casters and the ambient cube, or unlit (the
//!   bubble scene's backdrop), each WGSL function a port of the CPU function it names. The
//!   scene's textures (an environment image; the bubble backdrop's maps in the exact texture
//!   mode) are sampled by the exact sampler of `texture.rs` (`SAMPLE_WGSL`, as `mgs_…`); in
//!   the hardware mode the maps are a texture array under the hardware's filter
//!   ([`backdrop`]).
//! - **Material** ([`material`]): drawn as an app of the contract
//!   ([`crate::material::Material`], docs/integration.md): its `mg_vertex` and `mg_fragment`
//!   (the light loop, lights in a storage buffer) with the scene's hooks, its group 0 in
//!   either texture mode; the vertices displaced first by a compute pass calling the library
//!   module's `mg_material` and a normal pass (`normals.wgsl`, the CPU's area-weighted
//!   welded normals).
//! - **Samples**: `--samples` on the CPU's sample positions ([`crate::scene::sample_offsets`]):
//!   MSAA with per-sample shading where the device has the count (the standard patterns of
//!   1, 2, 4, 8), else one pass per sample with the projection shifted so that the pass's
//!   pixel centres lie on that sample (any count); the depth test is on `near / w`
//!   (greater is nearer), the CPU z-buffer's `1/w` up to scale.
//! - **Tiles**: a frame over the device's texture side or buffer limits is drawn tile by
//!   tile (even-sized, so the 2 × 2 derivative quads stay whole), each tile's projection an
//!   affine map of the frame's, and stitched on read-back.
//! - **Resolve** (`resolve.wgsl`): the composite `alpha · radiance + (1 − alpha) ·
//!   background` per sample, averaged in the CPU's sample order (over the passes' sum when
//!   jittered), read back as linear RGB.
//! - **Scene textures**: `scene:background`, `scene:refraction`, `scene:reflection` are
//!   drawn by the same scene pipelines (mirrored and clipped to the water plane per sample)
//!   and `scene:environment` by `envmap.wgsl`; their mip chains are built on the CPU from
//!   the read-back images, as for any texture.
//!
//! One file per stage: [`resources`] (the wgpu helpers every stage builds with), [`scene`]
//! (the scene's buffers, meshes and pipelines), [`scene_pass`] (the screen-space scene
//! textures), [`environment`], [`displace`], [`material`], [`resolve`] and [`frame`] (one
//! frame, from the passes to the read-back).

mod backdrop;
mod displace;
mod drawn;
mod environment;
mod frame;
mod material;
mod resolve;
mod resources;
mod scene;
mod scene_pass;

pub(crate) use environment::render_environment;
pub(crate) use frame::render_frame;
pub(in crate::gpu) use scene::{MeshBuffers, SceneBuffers};
pub(crate) use scene_pass::render_scene_pass;

use displace::*;
use resolve::*;
use resources::*;
use scene::*;
use scene_pass::*;

pub(in crate::gpu) use drawn::{DrawnScene, DrawnSceneKey};

use super::context::GpuContext;
use super::device::{DeviceState, SMALL_UPLOAD_TEXELS, UploadKey, dispatch_shape, gpu_err};
use super::pool::Lent;
use crate::graph::Graph;
use crate::material::{GpuTextures, Material, MaterialError, MaterialOptions, VERTEX_STRIDE};
use crate::memo::{Memo, Same};
use crate::plan::{EvalError, ParamValues};
use crate::scene::{Mesh, PackedScene, Scene, SceneFeatures, ScenePass, Viewport};
use crate::texture::{Texture, TexturePack, TextureSet};
use crate::wgsl::TextureMode;
use std::cell::Cell;
use std::sync::Arc;
use std::time::{Duration, Instant};
use wgpu::util::DeviceExt;

/// Colour format of the multisampled targets.
const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Depth format (`near / w`, greater is nearer).
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Wall-clock time of each stage of a GPU frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RasterTimings {
    /// Generating the modules and creating the pipelines.
    pub compile: Duration,
    /// Creating and filling buffers and textures (the scene, the mesh, the textures).
    pub upload: Duration,
    /// Recording, submitting and waiting for the passes.
    pub draw: Duration,
    /// Mapping and copying the image back.
    pub readback: Duration,
}

/// The material surface of a frame: the graph, how it binds textures, its parameters and
/// textures, and its mesh (undisplaced).
pub(crate) struct MaterialInput<'a> {
    /// The graph.
    pub graph: &'a Graph,
    /// How the material binds its textures.
    pub texture_mode: TextureMode,
    /// Parameter values.
    pub params: &'a ParamValues,
    /// Scene time, seconds.
    pub time: f32,
    /// Textures the graph samples (scene textures included).
    pub textures: &'a TextureSet,
    /// The material mesh.
    pub mesh: &'a Arc<Mesh>,
}

/// Whether the GPU rasteriser draws `spp` samples per pixel as MSAA on this device (else as
/// `spp` jittered one-sample passes, the same sample positions).
pub fn draws_msaa(ctx: &GpuContext, spp: u32) -> bool {
    supports_samples(ctx, spp)
}

/// Whether the device has MSAA for `spp` samples per pixel: a standard pattern
/// ([`crate::scene::STANDARD_SAMPLE_COUNTS`]) the colour and depth formats support.
pub(crate) fn supports_samples(ctx: &GpuContext, spp: u32) -> bool {
    crate::scene::STANDARD_SAMPLE_COUNTS.contains(&spp)
        && (spp == 1
            || ctx.format_features(COLOR).flags.sample_count_supported(spp)
                && ctx.format_features(DEPTH).flags.sample_count_supported(spp))
}

/// Why the GPU rasteriser cannot draw at all on this device, if it cannot: it needs the
/// device feature `PRIMITIVE_INDEX` (the fragment stages rebuild the CPU's barycentrics
/// from their triangle).
pub(crate) fn unavailable(ctx: &GpuContext) -> Option<String> {
    (!ctx.features().contains(wgpu::Features::PRIMITIVE_INDEX)).then(|| {
        format!(
            "the GPU rasteriser needs the device feature PRIMITIVE_INDEX, which {} lacks \
             (render with --gpu-compute or --cpu)",
            ctx.describe()
        )
    })
}

thread_local! {
    /// A tile side forced below the device's limits on this thread ([`with_tile_limit`]).
    static TILE_LIMIT: Cell<Option<u32>> = const { Cell::new(None) };
}

/// Runs `f` with the GPU rasteriser's tiles limited to `side` pixels a side on this
/// thread, as on a device whose textures cannot be larger (a test hook: a frame over the
/// limit is drawn in tiles and stitched).
#[doc(hidden)]
pub fn with_tile_limit<R>(side: u32, f: impl FnOnce() -> R) -> R {
    let before = TILE_LIMIT.with(|t| t.replace(Some(side)));
    let r = f();
    TILE_LIMIT.with(|t| t.set(before));
    r
}

/// The largest tile (even sides, so that tiles keep the 2 × 2 quads of the derivatives)
/// a `w × h` frame is drawn in with `spp` samples per target pixel: within the device's
/// texture side, and with one sample layer of the tile (16 bytes a sample) within its
/// storage-binding and buffer limits.
fn tile_size(ctx: &GpuContext, w: u32, h: u32, spp: u32) -> (u32, u32) {
    let limits = ctx.limits();
    let mut side = limits.max_texture_dimension_2d;
    if let Some(l) = TILE_LIMIT.with(|t| t.get()) {
        side = side.min(l);
    }
    let side = (side & !1).max(2);
    let tw = w.min(side);
    let budget = limits
        .max_buffer_size
        .min(limits.max_storage_buffer_binding_size);
    let rows = (budget / (tw as u64 * 16 * spp as u64)).clamp(2, side as u64) as u32 & !1;
    (tw, h.min(rows))
}

/// A [`MaterialError`] as the renderer's error (a missing texture keeps its name).
fn material_err(e: MaterialError) -> EvalError {
    match e {
        MaterialError::MissingTexture(name) => EvalError::MissingTexture { name },
        MaterialError::Parameter(e) => e,
        MaterialError::NoOutputs(_) => EvalError::NoOutputs,
        e => EvalError::Gpu(e.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Where the device's MSAA samples lie: the fragment position of each sample's
    /// invocation (per-sample shading), read back.
    fn sample_positions(ctx: &GpuContext, spp: u32) -> Vec<[f32; 2]> {
        let s = &*ctx.state;
        let src = r#"
@vertex fn vs(@builtin(vertex_index) k: u32) -> @builtin(position) vec4<f32> {
    let xy = vec2<f32>(f32((k << 1u) & 2u) * 2.0 - 1.0, f32(k & 2u) * 2.0 - 1.0);
    return vec4<f32>(xy, 0.5, 1.0);
}
@fragment fn fs(@builtin(position) p: vec4<f32>, @builtin(sample_index) s: u32) -> @location(0) vec4<f32> {
    return vec4<f32>(p.xy, f32(s), 1.0);
}
@group(0) @binding(0) var t: texture_multisampled_2d<f32>;
@group(0) @binding(1) var<storage, read_write> o: array<vec4<f32>>;
@compute @workgroup_size(1) fn cs(@builtin(global_invocation_id) id: vec3<u32>) {
    o[id.x] = textureLoad(t, vec2<i32>(0, 0), i32(id.x));
}
"#;
        let m = module(s, "probe", src);
        let empty = layout(s, "empty", &[]);
        let rp = render_pipeline(
            s,
            "probe",
            &m,
            "vs",
            "fs",
            &pipeline_layout(s, &[&empty]),
            spp,
            false,
        );
        let c = wgpu::ShaderStages::COMPUTE;
        let l = layout(
            s,
            "probe",
            &[
                (0, c, Kind::Texture { multisampled: true }),
                (1, c, Kind::StorageRw),
            ],
        );
        let cp = compute_pipeline(s, "probe", &m, "cs", &pipeline_layout(s, &[&l]));
        let color = target(s, "probe", (1, 1, spp), COLOR, wgpu::TextureUsages::empty());
        let depth = target(s, "probe", (1, 1, spp), DEPTH, wgpu::TextureUsages::empty());
        let out = s.buffer(
            "probe",
            spp as u64 * 16,
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        );
        let g = bind(
            s,
            &l,
            &[
                wgpu::BindingResource::TextureView(&color),
                out.as_entire_binding(),
            ],
        );
        let eg = bind(s, &empty, &[]);
        let mut enc = s.device.create_command_encoder(&Default::default());
        {
            let mut p = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: None,
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &color,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(0.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            p.set_pipeline(&rp);
            p.set_bind_group(0, &eg, &[]);
            p.draw(0..3, 0..1);
        }
        {
            let mut p = enc.begin_compute_pass(&Default::default());
            p.set_pipeline(&cp);
            p.set_bind_group(0, &g, &[]);
            p.dispatch_workgroups(spp, 1, 1);
        }
        let st = staging(s, spp as u64 * 16);
        enc.copy_buffer_to_buffer(&out, 0, &st, 0, spp as u64 * 16);
        submit_and_wait(s, enc).unwrap();
        let d = read_back(s, st, spp as u64 * 16).unwrap();
        d.chunks_exact(4).map(|c| [c[0], c[1]]).collect()
    }

    /// The bubble backdrop's maps through the hardware mode's texture array against the
    /// exact sampler (the CPU's arithmetic, bit for bit): the background pass of the bubble
    /// scene at 256², linear radiance. The differences are the maps' 16-bit float texels
    /// (11 significant bits: half an ulp is 2⁻¹² at values in [0.5, 1)) and the texture
    /// unit's filter; bound 2⁻¹⁰ per channel (measured on lavapipe: max 2.65e-4, RMS 2.9e-5).
    #[test]
    fn backdrop_hardware_maps_match_the_exact_sampler() {
        let Ok(ctx) = GpuContext::shared() else {
            eprintln!("SKIPPED backdrop_hardware_maps_match_the_exact_sampler: no GPU adapter");
            return;
        };
        let scene = Scene::preset("bubble").expect("the bubble preset");
        let draw = |mode| {
            render_scene_pass(ctx, &scene, None, (256, 256), ScenePass::Background, mode)
                .expect("the background pass")
        };
        let (exact, hardware) = (draw(TextureMode::Exact), draw(TextureMode::Hardware));
        let (mut worst, mut sq, mut lit) = (0.0f64, 0.0f64, 0usize);
        for (e, h) in exact.iter().zip(&hardware) {
            for c in 0..3 {
                let d = (e[c] as f64 - h[c] as f64).abs();
                worst = worst.max(d);
                sq += d * d;
            }
            lit += usize::from(e.iter().any(|&x| x > 0.0));
        }
        let rms = (sq / (3 * exact.len()) as f64).sqrt();
        println!("backdrop hardware vs exact: max {worst:.2e}, RMS {rms:.2e}");
        assert!(
            lit * 2 > exact.len(),
            "the backdrop covers {lit} of {} pixels",
            exact.len()
        );
        assert!(worst <= 1.0 / 1024.0, "max difference {worst}");
        assert!(rms > 0.0, "the hardware mode drew the exact maps");
    }

    #[test]
    fn msaa_samples_lie_on_the_cpu_pattern() {
        let Ok(ctx) = GpuContext::shared() else {
            eprintln!("SKIPPED msaa_samples_lie_on_the_cpu_pattern: no GPU adapter");
            return;
        };
        for spp in crate::scene::STANDARD_SAMPLE_COUNTS {
            if !supports_samples(ctx, spp) || spp == 1 {
                continue;
            }
            let got = sample_positions(ctx, spp);
            let order = crate::scene::standard_sample_order(spp).unwrap();
            let want = crate::scene::sample_offsets(spp);
            for (s, &hw) in order.iter().enumerate() {
                let g = got[hw as usize];
                assert!(
                    (g[0] - want[s][0]).abs() < 1e-5 && (g[1] - want[s][1]).abs() < 1e-5,
                    "spp {spp}: hardware sample {hw} at {g:?}, CPU sample {s} at {:?} (all: {got:?})",
                    want[s]
                );
            }
        }
    }
}
