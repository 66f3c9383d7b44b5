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

mod backdrop;
mod drawn;
mod material;

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

/// The value cached on the device under `key`, made by `make` the first time (and again
/// after the bounded cache dropped it).
fn cached<T: Send + Sync + 'static>(
    s: &DeviceState,
    key: &str,
    make: impl FnOnce() -> T,
) -> Arc<T> {
    let mut make = Some(make);
    let value = s.cache.get_or(key.to_owned(), || {
        let made = make.take().expect("made once")();
        Arc::new(made) as Arc<dyn std::any::Any + Send + Sync>
    });
    match value.downcast::<T>() {
        Ok(v) => v,
        // A key is only ever used with one type; were it not, this value is not kept.
        Err(_) => Arc::new(make.take().expect("not made: the key held another type")()),
    }
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
    layout_with(s, label, entries, &[])
}

/// [`layout`] with `more` entries after those of `entries`.
fn layout_with(
    s: &DeviceState,
    label: &str,
    entries: &[(u32, wgpu::ShaderStages, Kind)],
    more: &[wgpu::BindGroupLayoutEntry],
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
        .chain(more.iter().cloned())
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
    let depth = if test {
        (wgpu::CompareFunction::Greater, true)
    } else {
        (wgpu::CompareFunction::Always, false)
    };
    render_pipeline_depth(s, label, (module, vs, Some(fs)), layout, samples, depth)
}

/// [`render_pipeline`] with the depth test `(compare, write)`; without a fragment stage it
/// writes depth only (the material's depth pre-pass).
fn render_pipeline_depth(
    s: &DeviceState,
    label: &str,
    (module, vs, fs): (&wgpu::ShaderModule, &str, Option<&str>),
    layout: &wgpu::PipelineLayout,
    samples: u32,
    (compare, write): (wgpu::CompareFunction, bool),
) -> wgpu::RenderPipeline {
    let targets = [Some(wgpu::ColorTargetState {
        format: COLOR,
        blend: None,
        write_mask: wgpu::ColorWrites::ALL,
    })];
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
                depth_write_enabled: Some(write),
                depth_compare: Some(compare),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState {
                count: samples,
                mask: !0,
                alpha_to_coverage_enabled: false,
            },
            fragment: fs.map(|fs| wgpu::FragmentState {
                module,
                entry_point: Some(fs),
                compilation_options: Default::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        })
}

/// A render target of a frame, lent by the device's pool ([`crate::gpu::pool`]) until
/// dropped; used as its view.
struct Target<'a> {
    view: wgpu::TextureView,
    texture: Lent<'a, wgpu::Texture>,
}

impl std::ops::Deref for Target<'_> {
    type Target = wgpu::TextureView;
    fn deref(&self) -> &wgpu::TextureView {
        &self.view
    }
}

/// The descriptor of a `w × h` target of `spp` samples in `format`, drawn into and read in
/// a shader (and `more`).
fn target_descriptor(
    label: &str,
    (w, h, spp): (u32, u32, u32),
    format: wgpu::TextureFormat,
    more: wgpu::TextureUsages,
) -> wgpu::TextureDescriptor<'_> {
    wgpu::TextureDescriptor {
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
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING | more,
        view_formats: &[],
    }
}

/// A `w × h` target of `spp` samples in `format`, for drawing and then reading in a shader
/// (and copying into, as `more` usage says).
fn target<'a>(
    s: &'a DeviceState,
    label: &str,
    size: (u32, u32, u32),
    format: wgpu::TextureFormat,
    more: wgpu::TextureUsages,
) -> Target<'a> {
    let texture = s
        .pool
        .texture(&s.device, &target_descriptor(label, size, format, more));
    Target {
        view: texture.create_view(&Default::default()),
        texture,
    }
}

/// The scene on the device: its buffers, the bind group of `scene.wgsl` (group 1) and the
/// pipelines of the built-in surfaces and the sky.
struct SceneGpu {
    packed: Arc<PackedScene>,
    pipes: Arc<ScenePipelines>,
    /// Whether the backdrop's maps are bound as textures ([`backdrop::uses_textures`]).
    map_textures: bool,
    buffers: Arc<SceneBuffers>,
    objects_group: wgpu::BindGroup,
    /// The refraction pass's group, drawing the Snell-refracted positions, when on.
    refracted_group: Option<wgpu::BindGroup>,
    /// The scene textures (texels, levels, table): the bubble backdrop's maps, the
    /// environment image.
    textures: Arc<[wgpu::Buffer; 3]>,
}

/// A packed scene's buffers on the device (`DeviceState::scenes`), uploaded once per
/// [`PackedScene`]: before, every frame uploaded them (a water scene's seabed and skirts,
/// 3.6 MB).
pub(in crate::gpu) struct SceneBuffers {
    lights: wgpu::Buffer,
    casters: wgpu::Buffer,
    positions: wgpu::Buffer,
    normals: wgpu::Buffer,
    table: wgpu::Buffer,
    index: wgpu::Buffer,
    /// `MgrBackdrop`.
    backdrop: wgpu::Buffer,
    /// The Snell-refracted positions, when the scene has them.
    refracted: Option<wgpu::Buffer>,
}

impl SceneBuffers {
    fn new(s: &DeviceState, packed: &PackedScene) -> SceneBuffers {
        SceneBuffers {
            lights: storage(s, "mgr lights", bytemuck::cast_slice(&packed.lights), 48),
            casters: storage(s, "mgr casters", bytemuck::cast_slice(&packed.casters), 48),
            positions: storage(
                s,
                "mgr positions",
                bytemuck::cast_slice(&packed.positions),
                16,
            ),
            normals: storage(s, "mgr normals", bytemuck::cast_slice(&packed.normals), 16),
            table: storage(
                s,
                "mgr object table",
                bytemuck::cast_slice(&packed.objects),
                80,
            ),
            index: index_buffer(s, &packed.indices),
            backdrop: storage(
                s,
                "mgr backdrop",
                bytemuck::cast_slice(&packed.backdrop),
                96,
            ),
            refracted: packed
                .refracted
                .as_ref()
                .map(|r| storage(s, "mgr refracted", bytemuck::cast_slice(r), 16)),
        }
    }
}

/// A material mesh's buffers on the device (`DeviceState::meshes`), made once per mesh:
/// the indices, the vertices in the contract's layout (drawn as they are without
/// displacement) and, on the first displaced frame, the displacement passes' inputs.
pub(in crate::gpu) struct MeshBuffers {
    index: wgpu::Buffer,
    /// Indices drawn.
    count: u32,
    vertices: wgpu::Buffer,
    displacement: std::sync::OnceLock<DisplacementInputs>,
    /// The MikkTSpace tangents and signs (`Mesh::tangents`), made on the first frame whose
    /// material reads them: the second vertex buffer, and storage for rebuilt samples.
    tangents: std::sync::OnceLock<wgpu::Buffer>,
}

/// The inputs of the displacement and normal passes: position and uv, normal and uv per
/// vertex, and the welded normals' adjacency (`Mesh::normal_adjacency`: weld groups, their
/// starts, their triangles), whose sort was most of a displaced frame's CPU time.
struct DisplacementInputs {
    vertices: wgpu::Buffer,
    adjacency: [wgpu::Buffer; 3],
}

impl MeshBuffers {
    fn new(s: &DeviceState, mesh: &Mesh) -> MeshBuffers {
        let idx: Vec<u32> = mesh.indices.iter().flatten().copied().collect();
        let vertices = s
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("mgr material vertices"),
                contents: bytemuck::cast_slice(&vertex_bytes(mesh)),
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE,
            });
        MeshBuffers {
            index: index_buffer(s, &idx),
            count: idx.len() as u32,
            vertices,
            displacement: std::sync::OnceLock::new(),
            tangents: std::sync::OnceLock::new(),
        }
    }

    /// The tangent buffer of `mesh` (the mesh these buffers were made from).
    fn tangents(&self, s: &DeviceState, mesh: &Mesh) -> &wgpu::Buffer {
        self.tangents.get_or_init(|| {
            s.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("mgr material tangents"),
                    contents: bytemuck::cast_slice(
                        &mesh
                            .tangents()
                            .iter()
                            .map(|t| t.to_array())
                            .collect::<Vec<_>>(),
                    ),
                    usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE,
                })
        })
    }

    /// The displacement passes' inputs of `mesh` (the mesh these buffers were made from),
    /// made on the first displaced frame.
    fn displacement(&self, s: &DeviceState, mesh: &Mesh) -> &DisplacementInputs {
        self.displacement.get_or_init(|| {
            let vertices: Vec<[f32; 4]> = (0..mesh.positions.len())
                .flat_map(|i| {
                    let (p, q, uv) = (mesh.positions[i], mesh.normals[i], mesh.uvs[i]);
                    [p.extend(uv.x).to_array(), q.extend(uv.y).to_array()]
                })
                .collect();
            let (groups, starts, tris) = mesh.normal_adjacency();
            DisplacementInputs {
                vertices: storage(s, "mgr vertices", bytemuck::cast_slice(&vertices), 16),
                adjacency: [
                    storage(s, "mgr groups", bytemuck::cast_slice(&groups), 16),
                    storage(s, "mgr starts", bytemuck::cast_slice(&starts), 16),
                    storage(s, "mgr adjacency", bytemuck::cast_slice(&tris), 16),
                ],
            }
        })
    }

    /// The buffers of `mesh`, made on the first frame that draws it.
    fn of(s: &DeviceState, mesh: &Arc<Mesh>) -> Arc<MeshBuffers> {
        s.meshes.get_or(Same(Some(mesh.clone())), || {
            Arc::new(MeshBuffers::new(s, mesh))
        })
    }
}

/// The bubble backdrop's maps, shared ([`crate::scene::bubble_maps`]).
fn backdrop_maps() -> &'static [Arc<Texture>] {
    static MAPS: std::sync::OnceLock<Vec<Arc<Texture>>> = std::sync::OnceLock::new();
    MAPS.get_or_init(|| {
        crate::scene::bubble_maps()
            .named()
            .iter()
            .map(|(_, t)| Arc::new((*t).clone()))
            .collect()
    })
}

/// The lookup of an equirectangular environment image, as the CPU renderer's
/// (`render::environment_lookup`): bilinear, repeating, level 0.
pub(crate) fn environment_lookup(tex: Arc<Texture>) -> impl Fn(glam::Vec3) -> glam::Vec3 + Sync {
    move |d| {
        let uv = crate::scene::equirect_uv(d);
        tex.sample(
            uv,
            0.0,
            crate::texture::Wrap::Repeat,
            crate::texture::Filter::Bilinear,
        )
        .truncate()
    }
}

/// The scene textures of `packed` as the three buffers of `mgs_sample_texture`: the
/// backdrop's maps (slots 0–5, when drawn), then the environment image (when given). The
/// maps alone are packed once per device.
fn scene_textures(
    s: &DeviceState,
    packed: &PackedScene,
    environment: Option<&Arc<Texture>>,
) -> Result<Arc<[wgpu::Buffer; 3]>, EvalError> {
    let buffers = |pack: &TexturePack| {
        [
            storage(s, "mgs_texels", pack.texel_bytes(), 16),
            storage(s, "mgs_levels", pack.level_bytes(), 16),
            storage(s, "mgs_textures", pack.texture_bytes(), 16),
        ]
    };
    let mut set = TextureSet::new();
    if packed.features.backdrop {
        for (k, t) in backdrop_maps().iter().enumerate() {
            set.insert_shared(format!("backdrop {k}"), t.clone())
                .map_err(|e| gpu_err("packing the scene textures", e))?;
        }
    }
    match environment.filter(|_| packed.features.env_image) {
        Some(env) => {
            set.insert_shared("environment", env.clone())
                .map_err(|e| gpu_err("packing the scene textures", e))?;
            let pack = set
                .pack()
                .map_err(|e| gpu_err("packing the scene textures", e))?;
            Ok(Arc::new(buffers(&pack)))
        }
        None => {
            // The maps alone (or nothing) pack the same every frame: once per device.
            let key = format!("scene textures/{}", packed.features.backdrop);
            let mut failed = None;
            let made = cached(s, &key, || match set.pack() {
                Ok(pack) => Some(buffers(&pack)),
                Err(e) => {
                    failed = Some(gpu_err("packing the scene textures", e));
                    None
                }
            });
            match (&*made, failed) {
                (_, Some(e)) => Err(e),
                (Some(b), None) => Ok(Arc::new(b.clone())),
                (None, None) => Err(EvalError::Gpu("packing the scene textures failed".into())),
            }
        }
    }
}

/// The layouts and pipelines of the scene passes at one sample count.
struct ScenePipelines {
    scene_layout: wgpu::BindGroupLayout,
    objects_layout: wgpu::BindGroupLayout,
    objects: wgpu::RenderPipeline,
    sky: wgpu::RenderPipeline,
}

/// `scene.wgsl` for a scene with `features`, with what it needs before it: the constants
/// that leave out what the scene lacks ([`SceneFeatures::wgsl`]) and the sampler of the
/// scene textures (`texture.rs` SAMPLE_WGSL, its names prefixed `mgs_` so as not to meet
/// the material's own `mg_` sampler) on group 1, bindings 3–5.
pub(super) fn scene_source(features: &SceneFeatures) -> String {
    let sampler = format!(
        "{}\n{}",
        crate::texture::sample_bindings_wgsl(1, 3),
        crate::texture::SAMPLE_WGSL
    );
    format!(
        "{}\n{}\n{}",
        features.wgsl(),
        sampler.replace("mg_", "mgs_"),
        include_str!("scene.wgsl")
    )
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
            (3, FC, Kind::Storage),
            (4, FC, Kind::Storage),
            (5, FC, Kind::Storage),
            (6, FC, Kind::Storage),
        ],
    )
}

impl ScenePipelines {
    /// The pipelines at `spp` samples for a scene with `features`, the backdrop's maps read
    /// from textures when `map_textures` ([`backdrop::uses_textures`]).
    fn new(
        s: &DeviceState,
        spp: u32,
        features: &SceneFeatures,
        map_textures: bool,
    ) -> ScenePipelines {
        let scene_layout = scene_layout(s);
        let f = wgpu::ShaderStages::FRAGMENT;
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let maps = match map_textures {
            true => backdrop::layout_entries().to_vec(),
            false => Vec::new(),
        };
        let objects_layout = layout_with(
            s,
            "mgr objects",
            &[
                (0, vf, Kind::Storage),
                (1, vf, Kind::Storage),
                (2, f, Kind::Storage),
                (3, f, Kind::Storage),
                (4, vf, Kind::Storage),
            ],
            &maps,
        );
        let source = format!(
            "enable primitive_index;\n{}\n{}\n{}",
            scene_source(features),
            backdrop::source(map_textures),
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
        let sky = render_pipeline_depth(
            s,
            "mgr sky",
            (&m, "mgr_sky_vs", Some("mgr_sky_fs")),
            &pl,
            spp,
            (wgpu::CompareFunction::GreaterEqual, false),
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
    /// `scene` on the device for frames of `spp` samples, `environment` the image of an
    /// image environment, the backdrop's maps bound as texture mode `mode` says.
    fn new(
        s: &DeviceState,
        scene: &Scene,
        spp: u32,
        environment: Option<&Arc<Texture>>,
        mode: TextureMode,
    ) -> Result<SceneGpu, EvalError> {
        // Packed once per scene and environment (the Snell-refracted seabed alone is a
        // quarter of a water preview's CPU time): frames that change only the material
        // reuse it.
        static PACKED: Memo<(String, Same<Texture>), Arc<PackedScene>, 4> = Memo::new();
        let key = (
            serde_json::to_string(scene).unwrap_or_default(),
            Same(environment.cloned()),
        );
        let packed = PACKED.get_or(key, || {
            let lookup = environment.map(|t| environment_lookup(t.clone()));
            Arc::new(scene.packed(lookup.as_ref().map(|f| f as &crate::scene::EnvLookup)))
        });
        let textures = scene_textures(s, &packed, environment)?;
        let features = packed.features;
        let map_textures = backdrop::uses_textures(features.backdrop, mode);
        let pipes = cached(
            s,
            &format!("scene/{spp}/{features:?}/{map_textures}"),
            || ScenePipelines::new(s, spp, &features, map_textures),
        );
        let maps = map_textures.then(|| backdrop::MapTextures::of(s));
        let b = s.scenes.get_or(Same(Some(packed.clone())), || {
            Arc::new(SceneBuffers::new(s, &packed))
        });
        let group = |drawn: &wgpu::Buffer| {
            let mut entries = vec![
                (0, b.positions.as_entire_binding()),
                (1, b.normals.as_entire_binding()),
                (2, b.table.as_entire_binding()),
                (3, b.index.as_entire_binding()),
                (4, drawn.as_entire_binding()),
            ];
            entries.extend(maps.iter().flat_map(|m| m.entries()));
            bind_entries(s, &pipes.objects_layout, &entries)
        };
        let objects_group = group(&b.positions);
        let refracted_group = b.refracted.as_ref().map(group);
        Ok(SceneGpu {
            packed,
            pipes,
            map_textures,
            buffers: b,
            objects_group,
            refracted_group,
            textures,
        })
    }

    /// The group-1 bind group of a pass's frame uniform.
    fn frame_group(&self, s: &DeviceState, frame: &[u8]) -> wgpu::BindGroup {
        let u = uniform(s, "mgr frame", frame);
        bind(
            s,
            &self.pipes.scene_layout,
            &[
                u.as_entire_binding(),
                self.buffers.lights.as_entire_binding(),
                self.buffers.casters.as_entire_binding(),
                self.textures[0].as_entire_binding(),
                self.textures[1].as_entire_binding(),
                self.textures[2].as_entire_binding(),
                self.buffers.backdrop.as_entire_binding(),
            ],
        )
    }

    /// Records the sky and the built-in surfaces of `pass` into `color` and `depth`; with
    /// `prepass` over the depth already there (the material's), so that what lies behind
    /// it is not shaded.
    fn record(
        &self,
        enc: &mut wgpu::CommandEncoder,
        frame: &wgpu::BindGroup,
        pass: ScenePass,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        prepass: bool,
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
                    load: if prepass {
                        wgpu::LoadOp::Load
                    } else {
                        wgpu::LoadOp::Clear(0.0)
                    },
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
        rp.set_pipeline(&self.pipes.objects);
        rp.set_index_buffer(self.buffers.index.slice(..), wgpu::IndexFormat::Uint32);
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
        // The sky last, at depth 0 under `GreaterEqual`: only where nothing was drawn (the
        // depth still cleared), so that it is not shaded under the surfaces and the
        // material (the same picture as drawing it first, each fragment shaded once).
        rp.set_pipeline(&self.pipes.sky);
        rp.draw(0..3, 0..1);
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

/// Maps `staging` and returns its first `bytes` bytes as floats; gives it back to the pool
/// unmapped (and drops it where the mapping failed).
fn read_back(
    s: &DeviceState,
    staging: Lent<'_, wgpu::Buffer>,
    bytes: u64,
) -> Result<Vec<f32>, EvalError> {
    let data = map_and_read(s, &staging, bytes);
    if data.is_err() {
        staging.forget();
    }
    data
}

fn map_and_read(
    s: &DeviceState,
    staging: &wgpu::Buffer,
    bytes: u64,
) -> Result<Vec<f32>, EvalError> {
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

/// A buffer of `bytes` for a frame's resolved pixels, lent by the pool.
fn pixels_buffer(s: &DeviceState, bytes: u64) -> Lent<'_, wgpu::Buffer> {
    s.lend_buffer(
        "mgr pixels",
        bytes,
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
    )
}

/// A read-back buffer of `bytes`, lent by the pool.
fn staging(s: &DeviceState, bytes: u64) -> Lent<'_, wgpu::Buffer> {
    s.lend_buffer(
        "mgr staging",
        bytes,
        wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
    )
}

/// The resolve pass: composite and average the samples of `scene` and `material` into
/// `out`, linear RGB (`w × h × 3` floats).
fn resolve(
    s: &DeviceState,
    enc: &mut wgpu::CommandEncoder,
    scene: &wgpu::TextureView,
    material: &wgpu::TextureView,
    out: &wgpu::Buffer,
    (w, h, spp): (u32, u32, u32),
) {
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
}

/// One jittered pass of a frame: its sample (the composite of `scene` and `material`, one
/// sample per pixel) added to `sum` (pass 0 stores it), and the sum divided by `spp` after
/// the last pass, the resolve's arithmetic in the CPU's sample order.
fn accumulate(
    s: &DeviceState,
    enc: &mut wgpu::CommandEncoder,
    scene: &wgpu::TextureView,
    material: &wgpu::TextureView,
    sum: &wgpu::Buffer,
    (w, h, spp, pass): (u32, u32, u32, u32),
) {
    let pipes = cached(s, "accumulate", || {
        let source = include_str!("resolve.wgsl").replace("MGR_TEXTURE", "texture_2d<f32>");
        let m = module(s, "mgr accumulate", &source);
        let c = wgpu::ShaderStages::COMPUTE;
        let l = layout(
            s,
            "mgr accumulate",
            &[
                (
                    0,
                    c,
                    Kind::Texture {
                        multisampled: false,
                    },
                ),
                (
                    1,
                    c,
                    Kind::Texture {
                        multisampled: false,
                    },
                ),
                (2, c, Kind::StorageRw),
                (3, c, Kind::Uniform),
            ],
        );
        let p = compute_pipeline(
            s,
            "mgr accumulate",
            &m,
            "mgr_accumulate_main",
            &pipeline_layout(s, &[&l]),
        );
        (l, p)
    });
    let (l, p) = (&pipes.0, &pipes.1);
    let mut words = vec![w, h, spp, pass];
    words.resize(20, 0);
    let u = uniform(s, "mgr accumulate", bytemuck::cast_slice(&words));
    let g = bind(
        s,
        l,
        &[
            wgpu::BindingResource::TextureView(scene),
            wgpu::BindingResource::TextureView(material),
            sum.as_entire_binding(),
            u.as_entire_binding(),
        ],
    );
    let mut cp = enc.begin_compute_pass(&Default::default());
    cp.set_pipeline(p);
    cp.set_bind_group(0, &g, &[]);
    cp.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
}

/// A picture of the scene without the material (`pass`) at `w × h`, one sample per pixel
/// at the pixel centre, linear RGB; `environment` is the image of an image environment,
/// `mode` how the bubble backdrop's maps are sampled.
pub(crate) fn render_scene_pass(
    ctx: &GpuContext,
    scene: &Scene,
    environment: Option<&Arc<Texture>>,
    (w, h): (u32, u32),
    pass: ScenePass,
    mode: TextureMode,
) -> Result<Vec<[f32; 3]>, EvalError> {
    let s = &*ctx.state;
    s.scoped("drawing a scene texture on the GPU", || {
        let gpu = SceneGpu::new(s, scene, 1, environment, mode)?;
        let view = Viewport::whole(w, h);
        let frame = gpu.frame_group(s, &scene.frame_uniform(&gpu.packed, w, h, pass, &view));
        let color = target(
            s,
            "mgr scene",
            (w, h, 1),
            COLOR,
            wgpu::TextureUsages::empty(),
        );
        let depth = target(
            s,
            "mgr depth",
            (w, h, 1),
            DEPTH,
            wgpu::TextureUsages::empty(),
        );
        let material = target(
            s,
            "mgr no material",
            (w, h, 1),
            COLOR,
            wgpu::TextureUsages::empty(),
        );
        let mut enc = s.device.create_command_encoder(&Default::default());
        gpu.record(&mut enc, &frame, pass, &color, &depth, false);
        clear(&mut enc, &material);
        let bytes = w as u64 * h as u64 * 12;
        let out = pixels_buffer(s, bytes);
        resolve(s, &mut enc, &color, &material, &out, (w, h, 1));
        let st = staging(s, bytes);
        enc.copy_buffer_to_buffer(&out, 0, &st, 0, bytes);
        submit_and_wait(s, enc)?;
        let data = read_back(s, st, bytes)?;
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

/// The scene's environment as a `w × h` equirectangular map (RGBA, alpha 1);
/// `environment` is the image of an image environment.
pub(crate) fn render_environment(
    ctx: &GpuContext,
    scene: &Scene,
    environment: Option<&Arc<Texture>>,
    w: u32,
    h: u32,
) -> Result<Vec<[f32; 4]>, EvalError> {
    let s = &*ctx.state;
    s.scoped("drawing the environment map on the GPU", || {
        // The map is the image-based lighting's source: the exact maps, as on the CPU.
        let gpu = SceneGpu::new(s, scene, 1, environment, TextureMode::Exact)?;
        let packed = &gpu.packed;
        let c = wgpu::ShaderStages::COMPUTE;
        let pipes = cached(s, &format!("environment/{:?}", packed.features), || {
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
                "enable primitive_index;\n{}\n{}\n{}\n{}",
                scene_source(&packed.features),
                backdrop::source(false),
                include_str!("objects.wgsl"),
                include_str!("envmap.wgsl")
            );
            let m = module(s, "mgr environment", &source);
            let pl = pipeline_layout(s, &[&l, &gpu.pipes.scene_layout]);
            let p = compute_pipeline(s, "mgr environment", &m, "mgr_environment", &pl);
            (l, p)
        });
        let (l, p) = (&pipes.0, &pipes.1);
        let view = Viewport::whole(w, h);
        let g1 = gpu.frame_group(
            s,
            &scene.frame_uniform(&gpu.packed, w, h, ScenePass::Background, &view),
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
        let data = read_back(s, st, bytes)?;
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

/// `material`'s textures from `set`, uploaded for its render module (or with `library` its
/// library module), reused while the material (`owner`, the cached value holding it) and
/// every texture it binds are the same ([`DeviceState::uploads`], or [`DeviceState::small_uploads`]
/// where every texture is small): a frame that changes only
/// parameters, time or camera uploads no texel. Measured on lavapipe at 1024²:
/// `bubble_iridescent`'s `scene:background` with its mips, 27 ms a frame before.
fn uploaded(
    s: &DeviceState,
    owner: &Arc<dyn std::any::Any + Send + Sync>,
    material: &Material,
    library: bool,
    set: &TextureSet,
) -> Result<Arc<GpuTextures>, EvalError> {
    let library_infos;
    let infos = match library {
        true => {
            library_infos = material.library_textures();
            &library_infos
        }
        false => material.textures(),
    };
    let key = UploadKey {
        material: owner.clone(),
        library,
        textures: infos
            .iter()
            .map(|t| Same(set.index_of(&t.name).and_then(|i| set.shared(i)).cloned()))
            .collect(),
    };
    let small = infos.iter().all(|t| {
        set.index_of(&t.name)
            .and_then(|i| set.get(i))
            .is_some_and(|t| t.width() as u64 * t.height() as u64 <= SMALL_UPLOAD_TEXELS)
    });
    let make = || {
        match library {
            true => material.upload_library_textures(&s.device, &s.queue, set),
            false => material.upload_textures(&s.device, &s.queue, set),
        }
        .map(Arc::new)
        .map_err(material_err)
    };
    match small {
        true => s.small_uploads.get_or_make(key, make),
        false => s.uploads.get_or_make(key, make),
    }
}

/// The displacement and normal passes: the library module's `displacement` at every
/// vertex, then the welded normals, into a new vertex buffer of the contract's layout;
/// `owner` holds `material` ([`uploaded`]).
fn displace(
    ctx: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    (owner, material): (&Arc<dyn std::any::Any + Send + Sync>, &Material),
    m: &MaterialInput,
    buffers: &MeshBuffers,
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
    let textures = uploaded(s, owner, material, true, m.textures)?;
    let dg = material.library_bind_group(&s.device, dl, &params_buf, &textures);
    let inputs = buffers.displacement(s, mesh);
    let vin = &inputs.vertices;
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
    let [g_buf, s_buf, t_buf] = &inputs.adjacency;
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
            buffers.index.as_entire_binding(),
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
    environment: Option<&Arc<Texture>>,
    (w, h, spp): (u32, u32, u32),
    m: &MaterialInput,
) -> Result<(Vec<[f32; 3]>, RasterTimings), EvalError> {
    let s = &*ctx.state;
    let mut t = RasterTimings::default();
    s.scoped("rendering on the GPU", || {
        // The material, its module with the scene's hooks, and the pipelines.
        let start = Instant::now();
        // Real MSAA where the device has the count, else one jittered pass per sample.
        let msaa = supports_samples(ctx, spp);
        let (ts, passes) = if msaa { (spp, 1) } else { (1, spp) };
        let options = MaterialOptions {
            textures: m.texture_mode,
            float32_filterable: ctx.features().contains(wgpu::Features::FLOAT32_FILTERABLE),
            // Over one sample the varyings are rebuilt per sample ([`material::sample_source`]).
            sample_shading: false,
            // Displaced by `displace`, in the CPU's order (normals from the displaced mesh).
            displaced_vertices: true,
            // The mesh's MikkTSpace tangents, as the CPU's G-buffer reads them.
            derived_tangents: false,
            clamp: crate::wgsl::ParameterClamp::HardRange,
        };
        // Generated and validated once per graph and options on the device: later frames
        // (an animation) only write their parameters and time. At 1 sample the contract's
        // `mg_fragment` as is; over 1 (MSAA or jittered passes) the varyings rebuilt at the
        // CPU's sample and the CPU's uv derivatives. `screen_uv` is the frame's, through the
        // tile's offset (`mgr_screen_uv`).
        let rebuilt = spp > 1;
        let gpu = SceneGpu::new(s, scene, ts, environment, m.texture_mode)?;
        let features = gpu.packed.features;
        // Keyed without the parameters' values, which `set_values` below replaces: the
        // editor's program of a structure is built with the values of its moment (an edit
        // back to a structure drawn before missed, and made its material again: 19 ms).
        let key = format!(
            "material/{rebuilt}/{options:?}/{features:?}/{}",
            m.graph.structure_key()
        );
        let made = cached(s, &key, || -> Result<(Material, String), MaterialError> {
            let material = Material::new(m.graph, &options)?;
            // The contract's clip position is `@invariant`, so the depth pre-pass and the
            // surface over it (two pipelines, the surface's test `GreaterEqual` against the
            // pre-pass) compute the same depth.
            let hooked = material
                .wgsl_with_hooks(&material::hooks(&features))?
                .replace("v.clip.xy / mg_frame.viewport", "mgr_screen_uv(v.clip.xy)");
            let source = match rebuilt {
                false => Some(hooked),
                true => material::sample_source(&hooked),
            }
            .ok_or_else(|| MaterialError::Shader {
                graph: m.graph.name.clone(),
                source: Box::new(crate::wgsl::ShaderError::Naga {
                    node: None,
                    message: "the render module has no mg_fragment entry".into(),
                }),
            })?;
            Ok((material, source))
        });
        let (material, source) = match &*made {
            Ok((material, source)) => (material, source),
            Err(e) => return Err(material_err(e.clone())),
        };
        // By the source: graphs that differ only in what the source does not show share
        // their pipelines.
        let pipes = cached(s, &format!("material pipeline/{ts}/{source}"), || {
            let mat_layout = s
                .device
                .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("mgr material"),
                    entries: &material.bind_group_layout_entries(),
                });
            let fm = module(s, "mgr material", source);
            let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
            let tangents = material::reads_tangents(source);
            let mesh_entries = [
                (0, vf, Kind::Storage),
                (1, vf, Kind::Storage),
                (2, vf, Kind::Storage),
            ];
            let mesh_layout = layout(s, "mgr mesh", &mesh_entries[..if tangents { 3 } else { 2 }]);
            let (fs, pl) = match rebuilt {
                false => (
                    "mg_fragment",
                    pipeline_layout(s, &[&mat_layout, &gpu.pipes.scene_layout]),
                ),
                true => (
                    "mgr_material_sample_fs",
                    pipeline_layout(s, &[&mat_layout, &gpu.pipes.scene_layout, &mesh_layout]),
                ),
            };
            use wgpu::CompareFunction::{Greater, GreaterEqual};
            // The material's depth, and its surface over that depth (the samples whose
            // depth it drew).
            let depth_only = material::pipeline(s, &fm, None, &pl, ts, (Greater, true), tangents);
            let surface =
                material::pipeline(s, &fm, Some(fs), &pl, ts, (GreaterEqual, false), tangents);
            (mat_layout, mesh_layout, depth_only, surface)
        });
        let (mat_layout, mesh_layout, depth_only, surface) =
            (&pipes.0, &pipes.1, &pipes.2, &pipes.3);
        // The material's depth is drawn before its colour, so that the material pass shades
        // one fragment per sample, the nearest, as the CPU's G-buffer does (the mesh is not
        // culled: without it a sphere's back faces drawn before its front are shaded too;
        // measured, the bubble's frame 1.14× as long). An opaque material (no alpha) hides
        // what lies behind it, so its depth is drawn first of all and the scene pass shades
        // only the samples the material leaves visible (the composite there is the
        // material's radiance alone, as on the CPU, where alpha 1 weighs the background by
        // 0); a material with alpha draws its depth after the scene, which shows through it.
        let has_mesh = !m.mesh.indices.is_empty();
        let opaque = material.roles().alpha.is_none();
        t.compile = start.elapsed();

        // Buffers: group 0 of the contract (its frame per pass), the scene's group 1, the
        // mesh.
        let start = Instant::now();
        let mut params = material.params();
        params.set_values(m.params);
        params.set_time(m.time);
        let params_buf = uniform(s, "mgr params", &params.bytes());
        let (_, lights_bytes) = material::frame_and_lights(scene, w, h, &Viewport::whole(w, h));
        let lights_buf = storage(s, "mgr material lights", &lights_bytes, 32);
        let owner: Arc<dyn std::any::Any + Send + Sync> = made.clone();
        let textures = uploaded(s, &owner, material, false, m.textures)?;
        let mesh = MeshBuffers::of(s, m.mesh);
        let (index, tri_count) = (&mesh.index, mesh.count);
        let mut enc = s.device.create_command_encoder(&Default::default());

        // 1. Displacement and normals, on the GPU.
        let vertices = match material.roles().displacement {
            None => mesh.vertices.clone(),
            Some(_) => displace(ctx, &mut enc, (&owner, material), m, &mesh)?,
        };
        let tangents = material::reads_tangents(source).then(|| mesh.tangents(s, m.mesh));
        let mut mesh_entries = vec![vertices.as_entire_binding(), index.as_entire_binding()];
        mesh_entries.extend(tangents.map(|t| t.as_entire_binding()));
        let mesh_group = bind(s, mesh_layout, &mesh_entries);
        t.upload = start.elapsed();

        // Tile by tile (one tile where the frame fits the device): 2. the scene, 3. the
        // material surface over its depth, 4. the resolve (or, jittered, the pass's sample
        // added to the tile's sum), 5. the tile read back into the frame.
        let start = Instant::now();
        let offsets = crate::scene::sample_offsets(spp);
        let (tw, th) = tile_size(ctx, w, h, ts);
        let mut pixels = vec![[0.0f32; 3]; w as usize * h as usize];
        let mut readback = Duration::ZERO;
        for y0 in (0..h).step_by(th as usize) {
            for x0 in (0..w).step_by(tw as usize) {
                let size = [tw.min(w - x0), th.min(h - y0)];
                let (cw, ch) = (size[0], size[1]);
                // A small frame in one pass keeps its scene pass ([`drawn`]); any other draws
                // its own, under an opaque material's depth.
                let kept = passes == 1
                    && (cw, ch) == (w, h)
                    && cw as u64 * ch as u64 * ts as u64 <= drawn::MAX_SAMPLES;
                let none = wgpu::TextureUsages::empty();
                let color = (!kept).then(|| target(s, "mgr scene", (cw, ch, ts), COLOR, none));
                let depth = match kept {
                    true => wgpu::TextureUsages::COPY_DST,
                    false => none,
                };
                let depth = target(s, "mgr depth", (cw, ch, ts), DEPTH, depth);
                let mat_target = target(s, "mgr material", (cw, ch, ts), COLOR, none);
                // The resolved pixels (jittered: the passes' sum).
                let bytes = cw as u64 * ch as u64 * 12;
                let out = pixels_buffer(s, bytes);
                for pass in 0..passes {
                    let jitter = if msaa {
                        [0.0, 0.0]
                    } else {
                        let o = offsets[pass as usize];
                        [o[0] - 0.5, o[1] - 0.5]
                    };
                    let view = Viewport {
                        origin: [x0, y0],
                        size,
                        jitter,
                    };
                    let frame_bytes =
                        scene.frame_uniform(&gpu.packed, w, h, ScenePass::Background, &view);
                    let frame = gpu.frame_group(s, &frame_bytes);
                    let (frame_bytes, _) = material::frame_and_lights(scene, w, h, &view);
                    let frame_buf = uniform(s, "mgr material frame", &frame_bytes);
                    let mat_group = material.bind_group(
                        &s.device,
                        mat_layout,
                        &params_buf,
                        &frame_buf,
                        &lights_buf,
                        &textures,
                    );
                    // The material's depth, over the scene's (`clear`: none yet).
                    let material_depth = |enc: &mut wgpu::CommandEncoder, clear: bool| {
                        let mut rp = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                            label: Some("mgr material depth"),
                            color_attachments: &[],
                            depth_stencil_attachment: Some(
                                wgpu::RenderPassDepthStencilAttachment {
                                    view: &depth,
                                    depth_ops: Some(wgpu::Operations {
                                        load: match clear {
                                            true => wgpu::LoadOp::Clear(0.0),
                                            false => wgpu::LoadOp::Load,
                                        },
                                        store: wgpu::StoreOp::Store,
                                    }),
                                    stencil_ops: None,
                                },
                            ),
                            timestamp_writes: None,
                            occlusion_query_set: None,
                            multiview_mask: None,
                        });
                        rp.set_pipeline(depth_only);
                        rp.set_bind_group(0, &mat_group, &[]);
                        rp.set_bind_group(1, &frame, &[]);
                        if rebuilt {
                            rp.set_bind_group(2, &mesh_group, &[]);
                        }
                        rp.set_vertex_buffer(0, vertices.slice(..));
                        if let Some(t) = tangents {
                            rp.set_vertex_buffer(1, t.slice(..));
                        }
                        rp.set_index_buffer(index.slice(..), wgpu::IndexFormat::Uint32);
                        rp.draw_indexed(0..tri_count, 0, 0..1);
                    };
                    // The scene's colour: drawn here, or kept from an earlier frame.
                    let kept_scene: Arc<DrawnScene>;
                    let scene_color = match &color {
                        Some(color) => {
                            if has_mesh && opaque {
                                material_depth(&mut enc, true);
                            }
                            gpu.record(
                                &mut enc,
                                &frame,
                                ScenePass::Background,
                                color,
                                &depth,
                                has_mesh && opaque,
                            );
                            if has_mesh && !opaque {
                                material_depth(&mut enc, false);
                            }
                            &color.view
                        }
                        None => {
                            kept_scene =
                                DrawnScene::of(s, &gpu, (&frame_bytes, &frame), [cw, ch, ts]);
                            kept_scene.copy_depth(&mut enc, &depth.texture);
                            if has_mesh {
                                material_depth(&mut enc, false);
                            }
                            &kept_scene.color
                        }
                    };
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
                            depth_stencil_attachment: Some(
                                wgpu::RenderPassDepthStencilAttachment {
                                    view: &depth,
                                    depth_ops: Some(wgpu::Operations {
                                        load: wgpu::LoadOp::Load,
                                        store: wgpu::StoreOp::Store,
                                    }),
                                    stencil_ops: None,
                                },
                            ),
                            timestamp_writes: None,
                            occlusion_query_set: None,
                            multiview_mask: None,
                        });
                        rp.set_pipeline(surface);
                        rp.set_bind_group(0, &mat_group, &[]);
                        rp.set_bind_group(1, &frame, &[]);
                        if rebuilt {
                            rp.set_bind_group(2, &mesh_group, &[]);
                        }
                        rp.set_vertex_buffer(0, vertices.slice(..));
                        if let Some(t) = tangents {
                            rp.set_vertex_buffer(1, t.slice(..));
                        }
                        rp.set_index_buffer(index.slice(..), wgpu::IndexFormat::Uint32);
                        if tri_count > 0 {
                            rp.draw_indexed(0..tri_count, 0, 0..1);
                        }
                    }
                    match msaa {
                        true => resolve(s, &mut enc, scene_color, &mat_target, &out, (cw, ch, spp)),
                        false => accumulate(
                            s,
                            &mut enc,
                            scene_color,
                            &mat_target,
                            &out,
                            (cw, ch, spp, pass),
                        ),
                    }
                }
                let st = staging(s, bytes);
                enc.copy_buffer_to_buffer(&out, 0, &st, 0, bytes);
                let done = std::mem::replace(
                    &mut enc,
                    s.device.create_command_encoder(&Default::default()),
                );
                submit_and_wait(s, done)?;
                let r = Instant::now();
                let data = read_back(s, st, bytes)?;
                for (row, line) in data.chunks_exact(cw as usize * 3).enumerate() {
                    let first = (y0 as usize + row) * w as usize + x0 as usize;
                    for (k, c) in line.chunks_exact(3).enumerate() {
                        pixels[first + k] = [c[0], c[1], c[2]];
                    }
                }
                readback += r.elapsed();
            }
        }
        drop(enc);
        t.draw = start.elapsed() - readback;
        t.readback = readback;
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
