//! The GPU rasteriser of `matgraph render --gpu`: wgpu render pipelines draw the whole
//! frame, the CPU rasteriser is not used.
//!
//! - **Scene** (`scene.wgsl`, `objects.wgsl`): the sky and the built-in surfaces (backdrop,
//!   seabed, skirts, objects) with Lambert shading, hard shadows from the analytic casters
//!   and the ambient cube, each WGSL function a port of the CPU function it names.
//! - **Material** ([`material`]): drawn as an app of the contract
//!   ([`crate::material::Material`], docs/integration.md): its `mg_vertex` and `mg_fragment`
//!   (the light loop, lights in a storage buffer) with the scene's hooks, its group 0 in
//!   either texture mode; the vertices displaced first by a compute pass calling the library
//!   module's `mg_material` and a normal pass (`normals.wgsl`, the CPU's area-weighted
//!   welded normals).
//! - **Samples**: `--samples` 1, 2, 4 or 8 as MSAA with per-sample shading, on the standard
//!   patterns that [`crate::scene::sample_offsets`] also uses; the depth test is on `near / w`
//!   (greater is nearer), the CPU z-buffer's `1/w` up to scale.
//! - **Resolve** (`resolve.wgsl`): the composite `alpha · radiance + (1 − alpha) ·
//!   background` per sample, averaged in the CPU's sample order, read back as linear RGB.
//! - **Scene textures**: `scene:background`, `scene:refraction`, `scene:reflection` are
//!   drawn by the same scene pipelines (mirrored and clipped to the water plane per sample)
//!   and `scene:environment` by `envmap.wgsl`; their mip chains are built on the CPU from
//!   the read-back images, as for any texture.

mod material;

use super::context::GpuContext;
use super::device::{DeviceState, dispatch_shape, gpu_err};
use crate::graph::Graph;
use crate::material::{Material, MaterialError, MaterialOptions, VERTEX_STRIDE};
use crate::plan::{EvalError, ParamValues};
use crate::scene::{Mesh, PackedScene, Scene, ScenePass};
use crate::texture::TextureSet;
use crate::wgsl::TextureMode;
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
    pub mesh: &'a Mesh,
}

/// Whether the GPU rasteriser can draw `spp` samples per pixel on this device: a standard
/// pattern ([`crate::scene::STANDARD_SAMPLE_COUNTS`]) the colour format supports.
pub(crate) fn supports_samples(ctx: &GpuContext, spp: u32) -> bool {
    crate::scene::STANDARD_SAMPLE_COUNTS.contains(&spp)
        && (spp == 1
            || ctx.format_features(COLOR).flags.sample_count_supported(spp)
                && ctx.format_features(DEPTH).flags.sample_count_supported(spp))
}

fn texture_size_ok(ctx: &GpuContext, w: u32, h: u32) -> bool {
    let max = ctx.limits().max_texture_dimension_2d;
    w >= 1 && h >= 1 && w <= max && h <= max
}

/// Why the GPU rasteriser cannot draw a `w × h` frame at `spp` on this device, if it cannot.
pub(crate) fn unsupported(ctx: &GpuContext, w: u32, h: u32, spp: u32) -> Option<String> {
    if !ctx.features().contains(wgpu::Features::PRIMITIVE_INDEX) {
        return Some("without the device feature PRIMITIVE_INDEX".into());
    }
    if !supports_samples(ctx, spp) {
        return Some(format!(
            "{spp} samples per pixel (the GPU rasteriser draws 1, 2, 4 or 8 where the device's \
             Rgba32Float MSAA supports them)"
        ));
    }
    if !texture_size_ok(ctx, w, h) {
        return Some(format!(
            "a {w}x{h} frame (over the device's {} px texture limit)",
            ctx.limits().max_texture_dimension_2d
        ));
    }
    let bytes = w as u64 * h as u64 * (spp as u64 * 36 + 12);
    if bytes > ctx.limits().max_buffer_size {
        return Some(format!(
            "a {w}x{h} frame at {spp} spp (over the device's buffer limit)"
        ));
    }
    None
}

/// The value cached on the device under `key`, made by `make` the first time.
fn cached<T: Send + Sync + 'static>(
    s: &DeviceState,
    key: &str,
    make: impl FnOnce() -> T,
) -> Arc<T> {
    let mut cache = s.cache.lock().unwrap_or_else(|p| p.into_inner());
    if let Some(v) = cache.get(key).and_then(|v| v.clone().downcast::<T>().ok()) {
        return v;
    }
    let v = Arc::new(make());
    cache.insert(key.to_owned(), v.clone());
    v
}

/// A storage buffer holding `bytes` (padded to at least `min` bytes).
fn storage(s: &DeviceState, label: &str, bytes: &[u8], min: usize) -> wgpu::Buffer {
    let mut data = bytes.to_vec();
    data.resize(data.len().max(min).next_multiple_of(16), 0);
    s.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: &data,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        })
}

fn uniform(s: &DeviceState, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    let mut data = bytes.to_vec();
    data.resize(data.len().max(16).next_multiple_of(16), 0);
    s.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: &data,
            usage: wgpu::BufferUsages::UNIFORM,
        })
}

/// Binding types of a layout.
#[derive(Clone, Copy)]
enum Kind {
    Uniform,
    Storage,
    StorageRw,
    Texture { multisampled: bool },
}

fn layout(
    s: &DeviceState,
    label: &str,
    entries: &[(u32, wgpu::ShaderStages, Kind)],
) -> wgpu::BindGroupLayout {
    let entries: Vec<wgpu::BindGroupLayoutEntry> = entries
        .iter()
        .map(|&(binding, visibility, kind)| wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty: match kind {
                Kind::Uniform => wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                Kind::Storage | Kind::StorageRw => wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage {
                        read_only: matches!(kind, Kind::Storage),
                    },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                Kind::Texture { multisampled } => wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled,
                },
            },
            count: None,
        })
        .collect();
    s.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries: &entries,
        })
}

fn bind(
    s: &DeviceState,
    layout: &wgpu::BindGroupLayout,
    resources: &[wgpu::BindingResource],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = resources
        .iter()
        .enumerate()
        .map(|(i, r)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: r.clone(),
        })
        .collect();
    s.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout,
        entries: &entries,
    })
}

/// A bind group of `layout` with each resource at its own binding number.
fn bind_entries(
    s: &DeviceState,
    layout: &wgpu::BindGroupLayout,
    resources: &[(u32, wgpu::BindingResource)],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = resources
        .iter()
        .map(|(binding, r)| wgpu::BindGroupEntry {
            binding: *binding,
            resource: r.clone(),
        })
        .collect();
    s.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout,
        entries: &entries,
    })
}

fn module(s: &DeviceState, label: &str, source: &str) -> wgpu::ShaderModule {
    s.device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}

fn pipeline_layout(s: &DeviceState, layouts: &[&wgpu::BindGroupLayout]) -> wgpu::PipelineLayout {
    let layouts: Vec<Option<&wgpu::BindGroupLayout>> = layouts.iter().map(|l| Some(*l)).collect();
    s.device
        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &layouts,
            immediate_size: 0,
        })
}

fn compute_pipeline(
    s: &DeviceState,
    label: &str,
    module: &wgpu::ShaderModule,
    entry: &str,
    layout: &wgpu::PipelineLayout,
) -> wgpu::ComputePipeline {
    s.device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(label),
            layout: Some(layout),
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        })
}

/// A render pipeline drawing triangle lists from storage buffers into one colour target,
/// with the `near / w` depth test (`test` false: always passes, depth not written).
#[allow(clippy::too_many_arguments)]
fn render_pipeline(
    s: &DeviceState,
    label: &str,
    module: &wgpu::ShaderModule,
    vs: &str,
    fs: &str,
    layout: &wgpu::PipelineLayout,
    samples: u32,
    test: bool,
) -> wgpu::RenderPipeline {
    s.device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(label),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some(vs),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH,
                depth_write_enabled: Some(test),
                depth_compare: Some(if test {
                    wgpu::CompareFunction::Greater
                } else {
                    wgpu::CompareFunction::Always
                }),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState {
                count: samples,
                mask: !0,
                alpha_to_coverage_enabled: false,
            },
            fragment: Some(wgpu::FragmentState {
                module,
                entry_point: Some(fs),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: COLOR,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        })
}

fn target(
    s: &DeviceState,
    label: &str,
    w: u32,
    h: u32,
    spp: u32,
    format: wgpu::TextureFormat,
) -> wgpu::TextureView {
    s.device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: spp,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&Default::default())
}

/// The scene on the device: its buffers, the bind group of `scene.wgsl` (group 1) and the
/// pipelines of the built-in surfaces and the sky.
struct SceneGpu {
    packed: PackedScene,
    pipes: Arc<ScenePipelines>,
    lights: wgpu::Buffer,
    casters: wgpu::Buffer,
    objects_group: wgpu::BindGroup,
    /// The refraction pass's group, drawing the Snell-refracted positions, when on.
    refracted_group: Option<wgpu::BindGroup>,
    index: wgpu::Buffer,
}

/// The layouts and pipelines of the scene passes at one sample count.
struct ScenePipelines {
    scene_layout: wgpu::BindGroupLayout,
    objects_layout: wgpu::BindGroupLayout,
    objects: wgpu::RenderPipeline,
    sky: wgpu::RenderPipeline,
}

/// The group-1 layout of `scene.wgsl`.
fn scene_layout(s: &DeviceState) -> wgpu::BindGroupLayout {
    layout(
        s,
        "mgr scene",
        &[
            (0, ALL, Kind::Uniform),
            (1, FC, Kind::Storage),
            (2, FC, Kind::Storage),
        ],
    )
}

impl ScenePipelines {
    fn new(s: &DeviceState, spp: u32) -> ScenePipelines {
        let scene_layout = scene_layout(s);
        let f = wgpu::ShaderStages::FRAGMENT;
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let objects_layout = layout(
            s,
            "mgr objects",
            &[
                (0, vf, Kind::Storage),
                (1, vf, Kind::Storage),
                (2, f, Kind::Storage),
                (3, f, Kind::Storage),
                (4, vf, Kind::Storage),
            ],
        );
        let source = format!(
            "enable primitive_index;\n{}\n{}",
            include_str!("scene.wgsl"),
            include_str!("objects.wgsl")
        );
        let m = module(s, "mgr objects", &source);
        let pl = pipeline_layout(s, &[&objects_layout, &scene_layout]);
        let objects = render_pipeline(
            s,
            "mgr objects",
            &m,
            "mgr_object_vs",
            // Varyings at 1 sample per pixel, the CPU's barycentrics rebuilt under MSAA.
            if spp == 1 {
                "mgr_object_fs"
            } else {
                "mgr_object_sample_fs"
            },
            &pl,
            spp,
            true,
        );
        let sky = render_pipeline(
            s,
            "mgr sky",
            &m,
            "mgr_sky_vs",
            "mgr_sky_fs",
            &pl,
            spp,
            false,
        );
        ScenePipelines {
            scene_layout,
            objects_layout,
            objects,
            sky,
        }
    }
}

const ALL: wgpu::ShaderStages =
    wgpu::ShaderStages::VERTEX_FRAGMENT.union(wgpu::ShaderStages::COMPUTE);
const FC: wgpu::ShaderStages = wgpu::ShaderStages::FRAGMENT.union(wgpu::ShaderStages::COMPUTE);

impl SceneGpu {
    fn new(s: &DeviceState, scene: &Scene, spp: u32) -> SceneGpu {
        let packed = scene.packed();
        let pipes = cached(s, &format!("scene/{spp}"), || ScenePipelines::new(s, spp));
        let lights = storage(s, "mgr lights", bytemuck::cast_slice(&packed.lights), 48);
        let casters = storage(s, "mgr casters", bytemuck::cast_slice(&packed.casters), 48);
        let positions = storage(
            s,
            "mgr positions",
            bytemuck::cast_slice(&packed.positions),
            16,
        );
        let normals = storage(s, "mgr normals", bytemuck::cast_slice(&packed.normals), 16);
        let table = storage(
            s,
            "mgr object table",
            bytemuck::cast_slice(&packed.objects),
            80,
        );
        let index = index_buffer(s, &packed.indices);
        let group = |drawn: &wgpu::Buffer| {
            bind(
                s,
                &pipes.objects_layout,
                &[
                    positions.as_entire_binding(),
                    normals.as_entire_binding(),
                    table.as_entire_binding(),
                    index.as_entire_binding(),
                    drawn.as_entire_binding(),
                ],
            )
        };
        let objects_group = group(&positions);
        let refracted_group = packed
            .refracted
            .as_ref()
            .map(|r| group(&storage(s, "mgr refracted", bytemuck::cast_slice(r), 16)));
        SceneGpu {
            packed,
            pipes,
            lights,
            casters,
            objects_group,
            refracted_group,
            index,
        }
    }

    /// The group-1 bind group of a pass's frame uniform.
    fn frame_group(&self, s: &DeviceState, frame: &[u8]) -> wgpu::BindGroup {
        let u = uniform(s, "mgr frame", frame);
        bind(
            s,
            &self.pipes.scene_layout,
            &[
                u.as_entire_binding(),
                self.lights.as_entire_binding(),
                self.casters.as_entire_binding(),
            ],
        )
    }

    /// Records the sky and the built-in surfaces of `pass` into `color` and `depth`.
    fn record(
        &self,
        enc: &mut wgpu::CommandEncoder,
        frame: &wgpu::BindGroup,
        pass: ScenePass,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
    ) {
        let mut rp = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("mgr scene"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: color,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
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
        let group = match (pass, &self.refracted_group) {
            (ScenePass::Refraction, Some(g)) => g,
            _ => &self.objects_group,
        };
        rp.set_bind_group(0, group, &[]);
        rp.set_bind_group(1, frame, &[]);
        rp.set_pipeline(&self.pipes.sky);
        rp.draw(0..3, 0..1);
        rp.set_pipeline(&self.pipes.objects);
        rp.set_index_buffer(self.index.slice(..), wgpu::IndexFormat::Uint32);
        for (k, r) in self.packed.ranges.iter().enumerate() {
            // The reflection shows what stands above the water only.
            if pass == ScenePass::Reflection && r.underwater {
                continue;
            }
            if !r.indices.is_empty() {
                // The instance is the object (objects.wgsl).
                rp.draw_indexed(r.indices.clone(), 0, k as u32..k as u32 + 1);
            }
        }
    }
}

/// An index buffer of `indices` (padded to four), also bound as storage for the fragment
/// stages that rebuild the CPU's barycentrics.
fn index_buffer(s: &DeviceState, indices: &[u32]) -> wgpu::Buffer {
    let mut idx = indices.to_vec();
    idx.resize(idx.len().max(4), 0);
    s.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("mgr indices"),
            contents: bytemuck::cast_slice(&idx),
            usage: wgpu::BufferUsages::INDEX | wgpu::BufferUsages::STORAGE,
        })
}

/// Submits `enc` and waits for the device.
fn submit_and_wait(s: &DeviceState, enc: wgpu::CommandEncoder) -> Result<(), EvalError> {
    s.queue.submit([enc.finish()]);
    s.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| gpu_err("waiting for the GPU", e))?;
    Ok(())
}

/// Maps `staging` and returns its first `bytes` bytes as floats.
fn read_back(s: &DeviceState, staging: &wgpu::Buffer, bytes: u64) -> Result<Vec<f32>, EvalError> {
    let slice = staging.slice(0..bytes);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    s.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| gpu_err("waiting for the GPU", e))?;
    rx.recv()
        .map_err(|e| gpu_err("reading back", e))?
        .map_err(|e| gpu_err("reading back", e))?;
    let data = slice
        .get_mapped_range()
        .map_err(|e| gpu_err("reading back", e))
        .map(|view| bytemuck::cast_slice::<u8, f32>(&view).to_vec());
    staging.unmap();
    data
}

fn staging(s: &DeviceState, bytes: u64) -> wgpu::Buffer {
    s.buffer(
        "mgr staging",
        bytes,
        wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
    )
}

/// The resolve pass: composite and average the samples of `scene` and `material` into a
/// linear RGB storage buffer.
fn resolve(
    s: &DeviceState,
    enc: &mut wgpu::CommandEncoder,
    scene: &wgpu::TextureView,
    material: &wgpu::TextureView,
    (w, h, spp): (u32, u32, u32),
) -> wgpu::Buffer {
    let ms = spp > 1;
    let texture = if ms {
        "texture_multisampled_2d<f32>"
    } else {
        "texture_2d<f32>"
    };
    let pipes = cached(s, &format!("resolve/{ms}"), || {
        let source = include_str!("resolve.wgsl").replace("MGR_TEXTURE", texture);
        let m = module(s, "mgr resolve", &source);
        let c = wgpu::ShaderStages::COMPUTE;
        let l = layout(
            s,
            "mgr resolve",
            &[
                (0, c, Kind::Texture { multisampled: ms }),
                (1, c, Kind::Texture { multisampled: ms }),
                (2, c, Kind::StorageRw),
                (3, c, Kind::Uniform),
            ],
        );
        let p = compute_pipeline(
            s,
            "mgr resolve",
            &m,
            "mgr_resolve_main",
            &pipeline_layout(s, &[&l]),
        );
        (l, p)
    });
    let (l, p) = (&pipes.0, &pipes.1);
    let order = crate::scene::standard_sample_order(spp).unwrap_or_else(|| (0..spp).collect());
    let mut words = vec![w, h, spp, 0];
    words.extend(order);
    words.resize(20, 0);
    let u = uniform(s, "mgr resolve", bytemuck::cast_slice(&words));
    let out = s.buffer(
        "mgr pixels",
        w as u64 * h as u64 * 12,
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
    );
    let g = bind(
        s,
        l,
        &[
            wgpu::BindingResource::TextureView(scene),
            wgpu::BindingResource::TextureView(material),
            out.as_entire_binding(),
            u.as_entire_binding(),
        ],
    );
    let mut cp = enc.begin_compute_pass(&Default::default());
    cp.set_pipeline(p);
    cp.set_bind_group(0, &g, &[]);
    cp.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
    drop(cp);
    out
}

/// A picture of the scene without the material (`pass`) at `w × h`, one sample per pixel
/// at the pixel centre, linear RGB.
pub(crate) fn render_scene_pass(
    ctx: &GpuContext,
    scene: &Scene,
    w: u32,
    h: u32,
    pass: ScenePass,
) -> Result<Vec<[f32; 3]>, EvalError> {
    let s = &*ctx.state;
    s.scoped("drawing a scene texture on the GPU", || {
        let gpu = SceneGpu::new(s, scene, 1);
        let frame = gpu.frame_group(s, &scene.frame_uniform(&gpu.packed, w, h, pass));
        let color = target(s, "mgr scene", w, h, 1, COLOR);
        let depth = target(s, "mgr depth", w, h, 1, DEPTH);
        let material = target(s, "mgr no material", w, h, 1, COLOR);
        let mut enc = s.device.create_command_encoder(&Default::default());
        gpu.record(&mut enc, &frame, pass, &color, &depth);
        clear(&mut enc, &material);
        let out = resolve(s, &mut enc, &color, &material, (w, h, 1));
        let bytes = w as u64 * h as u64 * 12;
        let st = staging(s, bytes);
        enc.copy_buffer_to_buffer(&out, 0, &st, 0, bytes);
        submit_and_wait(s, enc)?;
        let data = read_back(s, &st, bytes)?;
        Ok(data.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
    })
}

/// The clear colour of a material target: "no material here" (alpha −1).
const NO_MATERIAL: wgpu::Color = wgpu::Color {
    r: 0.0,
    g: 0.0,
    b: 0.0,
    a: -1.0,
};

/// Clears a material target to [`NO_MATERIAL`].
fn clear(enc: &mut wgpu::CommandEncoder, view: &wgpu::TextureView) {
    enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("mgr clear"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(NO_MATERIAL),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
}

/// The scene's environment as a `w × h` equirectangular map (RGBA, alpha 1).
pub(crate) fn render_environment(
    ctx: &GpuContext,
    scene: &Scene,
    w: u32,
    h: u32,
) -> Result<Vec<[f32; 4]>, EvalError> {
    let s = &*ctx.state;
    s.scoped("drawing the environment map on the GPU", || {
        let packed = scene.packed();
        let c = wgpu::ShaderStages::COMPUTE;
        let pipes = cached(s, "environment", || {
            let scene_layout = scene_layout(s);
            let l = layout(
                s,
                "mgr environment",
                &[
                    (0, c, Kind::Storage),
                    (1, c, Kind::Storage),
                    (2, c, Kind::Storage),
                    (3, c, Kind::Storage),
                    (5, c, Kind::StorageRw),
                    (6, c, Kind::Uniform),
                ],
            );
            let source = format!(
                "enable primitive_index;\n{}\n{}\n{}",
                include_str!("scene.wgsl"),
                include_str!("objects.wgsl"),
                include_str!("envmap.wgsl")
            );
            let m = module(s, "mgr environment", &source);
            let pl = pipeline_layout(s, &[&l, &scene_layout]);
            let p = compute_pipeline(s, "mgr environment", &m, "mgr_environment", &pl);
            (scene_layout, l, p)
        });
        let (scene_layout, l, p) = (&pipes.0, &pipes.1, &pipes.2);
        let u = uniform(
            s,
            "mgr frame",
            &scene.frame_uniform(&packed, w, h, ScenePass::Background),
        );
        let lights = storage(s, "mgr lights", bytemuck::cast_slice(&packed.lights), 48);
        let casters = storage(s, "mgr casters", bytemuck::cast_slice(&packed.casters), 48);
        let g1 = bind(
            s,
            scene_layout,
            &[
                u.as_entire_binding(),
                lights.as_entire_binding(),
                casters.as_entire_binding(),
            ],
        );
        // MgrEnvView: the rays' origin and the triangles they meet (none: the sky alone).
        let (origin, triangles) = match scene.environment_origin() {
            Some(o) => (o, packed.indices.len() as u32 / 3),
            None => (glam::Vec3::ZERO, 0),
        };
        let view: [u32; 4] = [
            origin.x.to_bits(),
            origin.y.to_bits(),
            origin.z.to_bits(),
            triangles,
        ];
        let view = uniform(s, "mgr environment view", bytemuck::cast_slice(&view));
        let positions = storage(
            s,
            "mgr positions",
            bytemuck::cast_slice(&packed.positions),
            16,
        );
        let normals = storage(s, "mgr normals", bytemuck::cast_slice(&packed.normals), 16);
        let table = storage(
            s,
            "mgr object table",
            bytemuck::cast_slice(&packed.objects),
            80,
        );
        let index = index_buffer(s, &packed.indices);
        let bytes = w as u64 * h as u64 * 16;
        let out = s.buffer(
            "mgr environment",
            bytes,
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        );
        let g0 = bind_entries(
            s,
            l,
            &[
                (0, positions.as_entire_binding()),
                (1, normals.as_entire_binding()),
                (2, table.as_entire_binding()),
                (3, index.as_entire_binding()),
                (5, out.as_entire_binding()),
                (6, view.as_entire_binding()),
            ],
        );
        let mut enc = s.device.create_command_encoder(&Default::default());
        {
            let mut cp = enc.begin_compute_pass(&Default::default());
            cp.set_pipeline(p);
            cp.set_bind_group(0, &g0, &[]);
            cp.set_bind_group(1, &g1, &[]);
            cp.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        }
        let st = staging(s, bytes);
        enc.copy_buffer_to_buffer(&out, 0, &st, 0, bytes);
        submit_and_wait(s, enc)?;
        let data = read_back(s, &st, bytes)?;
        Ok(data
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect())
    })
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

/// The contract's interleaved vertex buffer of `mesh` (position, normal, uv), undisplaced.
fn vertex_bytes(mesh: &Mesh) -> Vec<[f32; 8]> {
    (0..mesh.positions.len())
        .map(|i| {
            let (p, n, uv) = (mesh.positions[i], mesh.normals[i], mesh.uvs[i]);
            [p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y]
        })
        .collect()
}

/// The displacement and normal passes: the library module's `displacement` at every
/// vertex, then the welded normals, into a new vertex buffer of the contract's layout.
fn displace(
    ctx: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    material: &Material,
    m: &MaterialInput,
    index: &wgpu::Buffer,
) -> Result<wgpu::Buffer, EvalError> {
    let s = &*ctx.state;
    let mesh = m.mesh;
    let n = mesh.positions.len() as u32;
    let library = material.library_module();
    let name = material
        .roles()
        .displacement
        .map(|k| material.render_module().outputs[k].name.clone())
        .unwrap_or_default();
    let field = library
        .outputs
        .iter()
        .find(|o| o.name == name)
        .map(|o| o.field.clone())
        .ok_or_else(|| {
            EvalError::Gpu(format!("output '{name}' missing from the library module"))
        })?;
    let src = material::displacement_source(material.library_wgsl(), &library.attributes, &field);
    let c = wgpu::ShaderStages::COMPUTE;
    let pipes = cached(s, &format!("displace/{src}"), || {
        let mut entries = material.library_bind_group_layout_entries();
        for e in &mut entries {
            e.visibility = c;
        }
        let dl = s
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("mgr displacement"),
                entries: &entries,
            });
        let vl = layout(
            s,
            "mgr displace io",
            &[
                (0, c, Kind::Storage),
                (1, c, Kind::StorageRw),
                (2, c, Kind::Uniform),
            ],
        );
        let dm = module(s, "mgr displacement", &src);
        let dp = compute_pipeline(
            s,
            "mgr displacement",
            &dm,
            "mgr_displace",
            &pipeline_layout(s, &[&dl, &vl]),
        );
        let nl = layout(
            s,
            "mgr normals",
            &[
                (0, c, Kind::Storage),
                (1, c, Kind::Storage),
                (2, c, Kind::Storage),
                (3, c, Kind::Storage),
                (4, c, Kind::Storage),
                (5, c, Kind::Storage),
                (6, c, Kind::StorageRw),
                (7, c, Kind::Uniform),
            ],
        );
        let nm = module(s, "mgr normals", include_str!("normals.wgsl"));
        let np = compute_pipeline(
            s,
            "mgr normals",
            &nm,
            "mgr_smooth_normals",
            &pipeline_layout(s, &[&nl]),
        );
        (dl, vl, dp, nl, np)
    });
    let (dl, vl, dp, nl, np) = (&pipes.0, &pipes.1, &pipes.2, &pipes.3, &pipes.4);
    let mut params = material.library_params();
    params.set_values(m.params);
    params.set_time(m.time);
    let params_buf = uniform(s, "mgr displacement params", &params.bytes());
    let textures = material
        .upload_library_textures(&s.device, &s.queue, m.textures)
        .map_err(material_err)?;
    let dg = material.library_bind_group(&s.device, dl, &params_buf, &textures);
    let vertices: Vec<[f32; 4]> = (0..n as usize)
        .flat_map(|i| {
            let (p, q, uv) = (mesh.positions[i], mesh.normals[i], mesh.uvs[i]);
            [p.extend(uv.x).to_array(), q.extend(uv.y).to_array()]
        })
        .collect();
    let vin = storage(s, "mgr vertices", bytemuck::cast_slice(&vertices), 16);
    let displaced = s.buffer(
        "mgr displaced",
        n.max(1) as u64 * 16,
        wgpu::BufferUsages::STORAGE,
    );
    let max_x = ctx.limits().max_compute_workgroups_per_dimension;
    let (gx, gy, row) = dispatch_shape(n, max_x);
    let count = uniform(s, "mgr count", bytemuck::cast_slice(&[n, row, 0, 0]));
    let vg = bind(
        s,
        vl,
        &[
            vin.as_entire_binding(),
            displaced.as_entire_binding(),
            count.as_entire_binding(),
        ],
    );
    let (groups, starts, tris) = mesh.normal_adjacency();
    let g_buf = storage(s, "mgr groups", bytemuck::cast_slice(&groups), 16);
    let s_buf = storage(s, "mgr starts", bytemuck::cast_slice(&starts), 16);
    let t_buf = storage(s, "mgr adjacency", bytemuck::cast_slice(&tris), 16);
    let out = s.buffer(
        "mgr displaced vertices",
        n.max(1) as u64 * VERTEX_STRIDE,
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::VERTEX,
    );
    let ng = bind(
        s,
        nl,
        &[
            displaced.as_entire_binding(),
            vin.as_entire_binding(),
            index.as_entire_binding(),
            g_buf.as_entire_binding(),
            s_buf.as_entire_binding(),
            t_buf.as_entire_binding(),
            out.as_entire_binding(),
            count.as_entire_binding(),
        ],
    );
    if n > 0 {
        let mut cp = enc.begin_compute_pass(&Default::default());
        cp.set_pipeline(dp);
        cp.set_bind_group(0, &dg, &[]);
        cp.set_bind_group(1, &vg, &[]);
        cp.dispatch_workgroups(gx, gy, 1);
        cp.set_pipeline(np);
        cp.set_bind_group(0, &ng, &[]);
        cp.dispatch_workgroups(gx, gy, 1);
    }
    Ok(out)
}

/// Renders the frame of `scene` with `m` at `w × h` and `spp` samples per pixel, all on the
/// GPU, the material drawn through the app contract ([`Material`]). Returns linear RGB per
/// pixel, rows from the top.
pub(crate) fn render_frame(
    ctx: &GpuContext,
    scene: &Scene,
    (w, h, spp): (u32, u32, u32),
    m: &MaterialInput,
) -> Result<(Vec<[f32; 3]>, RasterTimings), EvalError> {
    let s = &*ctx.state;
    let mut t = RasterTimings::default();
    s.scoped("rendering on the GPU", || {
        // The material, its module with the scene's hooks, and the pipelines.
        let start = Instant::now();
        let options = MaterialOptions {
            textures: m.texture_mode,
            float32_filterable: ctx.features().contains(wgpu::Features::FLOAT32_FILTERABLE),
            // The CPU shades every sample.
            sample_shading: spp > 1,
            // Displaced by `displace`, in the CPU's order (normals from the displaced mesh).
            displaced_vertices: true,
        };
        // Generated and validated once per graph and options on the device: later frames
        // (an animation) only write their parameters and time.
        let made = cached(
            s,
            &format!("material/{options:?}/{}", m.graph.to_json()),
            || -> Result<(Material, String), MaterialError> {
                let material = Material::new(m.graph, &options)?;
                let source = material.wgsl_with_hooks(&material::hooks())?;
                Ok((material, source))
            },
        );
        let (material, source) = match &*made {
            Ok((material, source)) => (material, source),
            Err(e) => return Err(material_err(e.clone())),
        };
        let gpu = SceneGpu::new(s, scene, spp);
        let pipes = cached(s, &format!("material pipeline/{spp}/{source}"), || {
            let mat_layout = s
                .device
                .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("mgr material"),
                    entries: &material.bind_group_layout_entries(),
                });
            let fm = module(s, "mgr material", source);
            let pl = pipeline_layout(s, &[&mat_layout, &gpu.pipes.scene_layout]);
            let surface = material::pipeline(s, &fm, &pl, spp);
            (mat_layout, surface)
        });
        let (mat_layout, surface) = (&pipes.0, &pipes.1);
        t.compile = start.elapsed();

        // Buffers: group 0 of the contract, the scene's group 1, the mesh.
        let start = Instant::now();
        let mut params = material.params();
        params.set_values(m.params);
        params.set_time(m.time);
        let params_buf = uniform(s, "mgr params", &params.bytes());
        let (frame_bytes, lights_bytes) = material::frame_and_lights(scene, w, h);
        let frame_buf = uniform(s, "mgr material frame", &frame_bytes);
        let lights_buf = storage(s, "mgr material lights", &lights_bytes, 32);
        let textures = material
            .upload_textures(&s.device, &s.queue, m.textures)
            .map_err(material_err)?;
        let mat_group = material.bind_group(
            &s.device,
            mat_layout,
            &params_buf,
            &frame_buf,
            &lights_buf,
            &textures,
        );
        let mesh = m.mesh;
        let idx: Vec<u32> = mesh.indices.iter().flatten().copied().collect();
        let tri_count = idx.len() as u32;
        let index = index_buffer(s, &idx);
        let frame = gpu.frame_group(
            s,
            &scene.frame_uniform(&gpu.packed, w, h, ScenePass::Background),
        );
        let color = target(s, "mgr scene", w, h, spp, COLOR);
        let depth = target(s, "mgr depth", w, h, spp, DEPTH);
        let mat_target = target(s, "mgr material", w, h, spp, COLOR);
        let mut enc = s.device.create_command_encoder(&Default::default());

        // 1. Displacement and normals, on the GPU.
        let vertices = match material.roles().displacement {
            None => s
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("mgr material vertices"),
                    contents: bytemuck::cast_slice(&vertex_bytes(mesh)),
                    usage: wgpu::BufferUsages::VERTEX,
                }),
            Some(_) => displace(ctx, &mut enc, material, m, &index)?,
        };
        t.upload = start.elapsed();

        // 2. The scene, 3. the material surface over its depth, 4. the resolve.
        let start = Instant::now();
        gpu.record(&mut enc, &frame, ScenePass::Background, &color, &depth);
        {
            let mut rp = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("mgr material"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &mat_target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(NO_MATERIAL),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            rp.set_pipeline(surface);
            rp.set_bind_group(0, &mat_group, &[]);
            rp.set_bind_group(1, &frame, &[]);
            rp.set_vertex_buffer(0, vertices.slice(..));
            rp.set_index_buffer(index.slice(..), wgpu::IndexFormat::Uint32);
            if tri_count > 0 {
                rp.draw_indexed(0..tri_count, 0, 0..1);
            }
        }
        let out = resolve(s, &mut enc, &color, &mat_target, (w, h, spp));
        let bytes = w as u64 * h as u64 * 12;
        let st = staging(s, bytes);
        enc.copy_buffer_to_buffer(&out, 0, &st, 0, bytes);
        submit_and_wait(s, enc)?;
        t.draw = start.elapsed();

        let start = Instant::now();
        let data = read_back(s, &st, bytes)?;
        let pixels = data.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        t.readback = start.elapsed();
        Ok(pixels)
    })
    .map(|p| (p, t))
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
        let color = target(s, "probe", 1, 1, spp, COLOR);
        let depth = target(s, "probe", 1, 1, spp, DEPTH);
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
        let d = read_back(s, &st, spp as u64 * 16).unwrap();
        d.chunks_exact(4).map(|c| [c[0], c[1]]).collect()
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
