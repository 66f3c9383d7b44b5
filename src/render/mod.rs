//! Rendering a material graph in a scene (deferred shading).
//!
//! 1. **Geometry.** The scene's material surface is a mesh. If the graph has a `displacement`
//!    output (vec3, world-space offset) it is evaluated at the mesh vertices (position,
//!    normal, uv and time set) and the mesh is displaced and its normals recomputed — on both
//!    paths this happens on the CPU, before rasterisation, so both shade the same surface.
//! 2. **G-buffer.** The CPU rasteriser of [`crate::scene`] finds, for every sample of the
//!    frame, the nearest surface; samples that see the material surface get its attributes
//!    (position, normal, view, uv, screen uv, depth below water), the others the radiance of
//!    the rest of the scene (backdrop, seabed, sky).
//! 3. **Material.** The graph is evaluated over the G-buffer samples by the chosen backend
//!    (the CPU executor or a wgpu compute pipeline): its `color` output once per light, with
//!    `light` and `light_color` set for that light, summed; `emission` and `alpha` once. A
//!    graph without a `color` output is shown unlit: its first output as is.
//! 4. **Composite.** `alpha · (color + emission) + (1 − alpha) · background` per sample, the
//!    samples of a pixel averaged (box filter), then tone mapped for display ([`tonemap`]).
//!
//! Stages 2–4 run band by band (rows of the image) so that a render fits
//! [`RenderOptions::memory_budget`] ([`plan_memory`]); a banded render equals the one-band
//! render bit for bit.

pub mod bake;
pub mod frames;
mod gpu;
mod ibl_cache;
pub mod sheet;
pub mod tonemap;
pub mod view;

use crate::exec::{Evaluator, SampleBatch};
use crate::gpu::Backend;
use crate::graph::Graph;
use crate::memo::{Memo, Same};
use crate::node::Attribute;
use crate::plan::{EvalError, PlanOptions};
use crate::scene::{GBuffer, Mesh, Scene};
use crate::texture::{Image, Texture, TextureSet};
use crate::types::SocketType;
use glam::Vec3;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Output names the renderer gives a meaning to.
pub mod outputs {
    /// Light-dependent radiance (color, vec3 or float), evaluated per light and summed.
    pub const COLOR: &str = "color";
    /// Light-independent radiance, added once.
    pub const EMISSION: &str = "emission";
    /// Coverage in [0, 1] over the background (1 when absent).
    pub const ALPHA: &str = "alpha";
    /// World-space vertex offset (vec3), applied to the mesh before rasterisation.
    pub const DISPLACEMENT: &str = "displacement";
}

/// Errors of a render, naming the output or stage at fault.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RenderError {
    /// Planning or evaluating the material failed.
    #[error(transparent)]
    Eval(#[from] EvalError),
    /// A texture could not be prepared.
    #[error("texture: {0}")]
    Texture(String),
    /// The render cannot fit the memory budget at any band size.
    #[error(
        "{width}x{height} at {samples} spp needs at least {} MiB ({}), over the memory budget of {} MiB",
        needed.div_ceil(1 << 20), what, budget >> 20
    )]
    Memory {
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
        /// Samples per pixel.
        samples: u32,
        /// Bytes needed with the smallest band (one row).
        needed: u64,
        /// What the bytes are for.
        what: String,
        /// The budget in bytes.
        budget: u64,
    },
    /// A mesh of the scene (or another input) does not fit the memory budget.
    #[error(transparent)]
    Budget(#[from] crate::budget::MemoryError),
    /// An output the renderer reads has a type it cannot use.
    #[error("output '{name}' is a {ty}; the renderer needs {expected}")]
    OutputType {
        /// The output.
        name: String,
        /// Its type.
        ty: SocketType,
        /// What the renderer accepts.
        expected: &'static str,
    },
}

impl From<crate::texture::TextureError> for RenderError {
    /// A texture that could not be prepared, in words.
    fn from(e: crate::texture::TextureError) -> RenderError {
        RenderError::Texture(e.to_string())
    }
}

impl RenderError {
    /// A memory refusal restated against the whole `budget`, with `reserve` bytes already
    /// held (said as `MiB {held}`) counted in; other errors unchanged.
    pub fn with_reserve(self, reserve: u64, held: &str, budget: u64) -> RenderError {
        match self {
            RenderError::Memory {
                width,
                height,
                samples,
                needed,
                what,
                ..
            } => RenderError::Memory {
                width,
                height,
                samples,
                needed: needed + reserve,
                what: format!("{what}, {} MiB {held}", reserve.div_ceil(1 << 20)),
                budget,
            },
            e => e,
        }
    }
}

/// How to render.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel (stratified), averaged with a box filter.
    pub samples: u32,
    /// Scene time override in seconds (the scene's own time when `None`).
    pub time: Option<f32>,
    /// Where the material is evaluated.
    pub backend: Backend,
    /// Parameter values that replace the graph file's.
    pub parameters: Vec<(String, crate::value::Value)>,
    /// The graph's images (see [`crate::image_io::load_graph_textures`]); scene textures
    /// (`scene:refraction`, `scene:reflection`, `scene:background`, at
    /// [`scene_texture_size`]; `scene:environment`) are rendered and added.
    pub textures: Option<Arc<TextureSet>>,
    /// The equirectangular image of an image environment (see `scene::Environment::Image`);
    /// without it such a scene falls back to the default sky.
    pub environment: Option<Arc<Texture>>,
    /// Bytes the render may use ([`plan_memory`]); [`MEMORY_BUDGET`] by default.
    pub memory_budget: u64,
    /// Rows per band, overriding [`plan_memory`]'s choice (tests force tiny bands).
    pub band_rows: Option<u32>,
    /// How the GPU rasteriser (`Backend::Gpu`) binds the material's textures: hardware
    /// samplers (the default) or exact storage buffers (the CPU's filtering, bit for bit).
    pub texture_mode: crate::wgsl::TextureMode,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 512,
            height: 512,
            samples: 1,
            time: None,
            backend: Backend::Cpu,
            parameters: Vec::new(),
            textures: None,
            environment: None,
            memory_budget: MEMORY_BUDGET,
            band_rows: None,
            texture_mode: crate::wgsl::TextureMode::Hardware,
        }
    }
}

/// The memory a render may use by default: [`crate::budget::DEFAULT_MEMORY_BUDGET`], 2 GiB.
/// The scene's meshes are reserved first ([`Scene::reserve_meshes`]); the frame is then
/// rendered in bands of rows sized so that the whole render stays within what is left
/// ([`plan_memory`]).
pub const MEMORY_BUDGET: u64 = crate::budget::DEFAULT_MEMORY_BUDGET;

/// Bytes per sample of a band, an upper bound: two fragment buffers (40), the background
/// (12) and, when every sample sees the material, its index (4), 20 attribute floats (80),
/// the light columns and a copy of the positions (36), the outputs, radiance, alpha and the
/// composite (40), with headroom for the executor's registers and the GPU's staging buffers.
pub const BYTES_PER_SAMPLE: u64 = 256;

/// Bytes per pixel of the rendered HDR image (linear RGB f32).
pub const BYTES_PER_PIXEL: u64 = 12;

/// Largest side of the scene textures (`scene:background`, `scene:refraction`,
/// `scene:reflection`): larger images get textures scaled down to it, keeping the aspect.
pub const SCENE_TEXTURE_MAX: u32 = 2048;

/// Bytes per texel of the scene textures at their peak: three RGB maps (36), three RGBA
/// textures with mip chains (64) and headroom for the rasteriser of the passes.
pub const BYTES_PER_SCENE_TEXEL: u64 = 112;

/// The size of the scene textures of a `width × height` render: the same, or scaled down so
/// that the longer side is [`SCENE_TEXTURE_MAX`] (each side at least 1).
pub fn scene_texture_size(width: u32, height: u32) -> (u32, u32) {
    let side = width.max(height);
    if side <= SCENE_TEXTURE_MAX {
        return (width, height);
    }
    let scale = |v: u32| {
        ((v as u64 * SCENE_TEXTURE_MAX as u64 + side as u64 / 2) / side as u64).max(1) as u32
    };
    (scale(width), scale(height))
}

/// How a render is cut to fit its memory budget.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryPlan {
    /// Rows per band.
    pub band_rows: u32,
    /// Number of bands.
    pub bands: u32,
    /// Bytes held for the whole render (the HDR image, the scene textures).
    pub fixed_bytes: u64,
    /// Bytes of one band at most.
    pub band_bytes: u64,
}

/// Plans a `width × height` render at `samples` per pixel within `budget` bytes: the fixed
/// part (the HDR image, [`BYTES_PER_PIXEL`]; the scene textures when `scene_textures`,
/// [`BYTES_PER_SCENE_TEXEL`] at [`scene_texture_size`]) and bands of as many rows as fit
/// at [`BYTES_PER_SAMPLE`], each band also within `u32` sample indices. An error naming
/// the budget when not even one row fits. Allocates nothing.
pub fn plan_memory(
    width: u32,
    height: u32,
    samples: u32,
    scene_textures: bool,
    budget: u64,
) -> Result<MemoryPlan, RenderError> {
    let (w, h, spp) = (width as u64, height as u64, samples.max(1) as u64);
    let image = w * h * BYTES_PER_PIXEL;
    let (tw, th) = scene_texture_size(width, height);
    let maps = if scene_textures {
        tw as u64 * th as u64 * BYTES_PER_SCENE_TEXEL
    } else {
        0
    };
    let fixed = image + maps;
    let row = w * spp * BYTES_PER_SAMPLE;
    if fixed + row > budget {
        let mut what = format!("{} MiB image", image.div_ceil(1 << 20));
        if maps > 0 {
            what += &format!(", {} MiB scene textures", maps.div_ceil(1 << 20));
        }
        what += &format!(", {} MiB per row of samples", row.div_ceil(1 << 20));
        return Err(RenderError::Memory {
            width,
            height,
            samples,
            needed: fixed + row,
            what,
            budget,
        });
    }
    let by_budget = (budget - fixed) / row.max(1);
    let by_index = u32::MAX as u64 / (w * spp).max(1);
    let band_rows = by_budget.min(by_index).min(h).max(1) as u32;
    Ok(MemoryPlan {
        band_rows,
        bands: height.div_ceil(band_rows),
        fixed_bytes: fixed,
        band_bytes: band_rows as u64 * row,
    })
}

/// Wall-clock time of each stage of a render.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderTimings {
    /// Compiling the material (CPU plan or GPU pipeline).
    pub compile: Duration,
    /// Displacing the mesh.
    pub displace: Duration,
    /// Rasterising the G-buffer and shading the background.
    pub gbuffer: Duration,
    /// Evaluating the material over the G-buffer, all lights.
    pub shade: Duration,
    /// Compositing and resolving the samples.
    pub resolve: Duration,
    /// GPU rasteriser: creating and filling buffers and textures.
    pub upload: Duration,
    /// GPU rasteriser: the passes, submitted and waited for.
    pub draw: Duration,
    /// GPU rasteriser: reading the image back.
    pub readback: Duration,
    /// Why a `Backend::Gpu` render fell back to the hybrid path (CPU rasteriser, GPU
    /// shading), when it did: one line for the user.
    pub fallback: Option<String>,
}

/// A rendered linear HDR image.
#[derive(Clone, Debug, PartialEq)]
pub struct HdrImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Linear RGB radiance per pixel, row-major, top row first.
    pub pixels: Vec<[f32; 3]>,
}

impl HdrImage {
    /// The tone-mapped 8-bit sRGB image (see [`tonemap::to_srgb8`]), in parallel (the same
    /// bytes on any number of threads).
    pub fn to_srgb8(&self, exposure: f32) -> sheet::Rgb8Image {
        use rayon::prelude::*;
        let scale = exposure.exp2();
        sheet::Rgb8Image {
            width: self.width,
            height: self.height,
            pixels: self
                .pixels
                .par_iter()
                .with_min_len(2048)
                .map(|&c| tonemap::scaled_to_srgb8(c, scale))
                .collect(),
        }
    }
}

/// The outputs of a graph the renderer reads, with their roles.
#[derive(Clone, Debug, Default)]
struct Roles {
    /// Lit radiance (per light), if any.
    color: Option<(String, SocketType)>,
    /// Unlit radiance, if any (the first output when there is no `color`).
    emission: Option<(String, SocketType)>,
    alpha: Option<String>,
    displacement: Option<String>,
}

/// The outputs the material pass reads: colour, emission and alpha.
fn shaded_names(roles: &Roles) -> Vec<String> {
    let mut names: Vec<String> = roles.color.iter().map(|(n, _)| n.clone()).collect();
    names.extend(roles.emission.iter().map(|(n, _)| n.clone()));
    names.extend(roles.alpha.iter().cloned());
    names
}

fn roles(graph: &Graph) -> Result<Roles, RenderError> {
    let find = |name: &str| {
        graph
            .outputs()
            .iter()
            .find(|o| o.name == name)
            .map(|o| (o.name.clone(), o.ty))
    };
    let colorish = |o: Option<(String, SocketType)>| -> Result<_, RenderError> {
        match o {
            Some((n, t))
                if !matches!(
                    t,
                    SocketType::Float
                        | SocketType::Vec3
                        | SocketType::Color
                        | SocketType::Int
                        | SocketType::Bool
                ) =>
            {
                Err(RenderError::OutputType {
                    name: n,
                    ty: t,
                    expected: "a color, vec3 or float",
                })
            }
            o => Ok(o),
        }
    };
    let mut r = Roles {
        color: colorish(find(outputs::COLOR))?,
        emission: colorish(find(outputs::EMISSION))?,
        ..Roles::default()
    };
    if let Some((n, t)) = find(outputs::ALPHA) {
        if t.conversion_to(SocketType::Float).is_none() {
            return Err(RenderError::OutputType {
                name: n,
                ty: t,
                expected: "a float",
            });
        }
        r.alpha = Some(n);
    }
    if let Some((n, t)) = find(outputs::DISPLACEMENT) {
        if t != SocketType::Vec3 {
            return Err(RenderError::OutputType {
                name: n,
                ty: t,
                expected: "a vec3",
            });
        }
        r.displacement = Some(n);
    }
    if r.color.is_none() && r.emission.is_none() {
        // Unlit preview of the first output that is not a role of its own.
        let first = graph
            .outputs()
            .iter()
            .find(|o| o.name != outputs::ALPHA && o.name != outputs::DISPLACEMENT)
            .map(|o| (o.name.clone(), o.ty));
        r.emission = colorish(first).unwrap_or(None);
    }
    Ok(r)
}

/// Reads output `k` of a batch as RGB per sample (floats are grey).
fn rgb(out: &crate::exec::OutputBatch, k: usize) -> impl Fn(usize) -> Vec3 + '_ {
    let n = out.len();
    let w = out.ty(k).width();
    let d = out.planar(k);
    move |i| {
        if w >= 3 {
            Vec3::new(d[i], d[n + i], d[2 * n + i])
        } else {
            Vec3::splat(d[i])
        }
    }
}

/// Compiles the material for some of its outputs on `backend`.
/// Whether the outputs `names` of `graph` read the tangent frame (`tangent` or
/// `bitangent_sign`).
pub fn reads_tangents(graph: &Graph, names: &[String]) -> Result<bool, EvalError> {
    let plan = crate::plan::Plan::compile(
        graph,
        &PlanOptions {
            outputs: names.to_vec(),
            bake_parameters: false,
        },
    )?;
    Ok(crate::wgsl::render::uses_tangents(plan.attributes()))
}

fn evaluator(
    graph: &Graph,
    names: Vec<String>,
    backend: Backend,
) -> Result<Box<dyn Evaluator>, EvalError> {
    crate::gpu::compile(
        graph,
        &PlanOptions {
            outputs: names,
            bake_parameters: false,
        },
        backend,
    )
}

/// The textures a render binds: the caller's graph images plus the scene textures the graph
/// samples, rendered at the image's size.
fn textures(
    graph: &Graph,
    scene: &Scene,
    options: &RenderOptions,
    environment: Option<&crate::scene::EnvLookup>,
) -> Result<TextureSet, RenderError> {
    let mut set = TextureSet::new();
    if let Some(given) = &options.textures {
        set.extend_shared(given)?;
    }
    let wanted: Vec<&str> = graph
        .nodes()
        .iter()
        .filter_map(|n| n.texture.as_ref()?.scene_name())
        .collect();
    if wanted.is_empty() {
        return Ok(set);
    }
    if wanted.iter().any(|w| is_environment_texture(w)) {
        // Made once per environment (the map is 512 × 256 texels cast against the room: 10 ms
        // of a 24² draft's 12 ms on the CPU, measured on pbr_gold), as on the GPU path.
        static ENVIRONMENT: Memo<(String, Vec<String>, Same<Texture>), Arc<TextureSet>, 4> =
            Memo::new();
        let key = (
            scene.environment_key(),
            scene_names(&wanted, true),
            Same(options.environment.clone()),
        );
        let made = ENVIRONMENT.get_or_make(key, || {
            let env = environment_map(scene, environment)?;
            let mut made = TextureSet::new();
            insert_environment_textures(&mut made, &wanted, env)?;
            Ok::<_, crate::texture::TextureError>(Arc::new(made))
        });
        set.extend_shared(&*made?)?;
        if wanted.iter().all(|w| is_environment_texture(w)) {
            return Ok(set);
        }
    }
    // The passes (at the frame's size, seen by the camera) of a small frame once per scene
    // and size: a material's edit draws none (a toon water's refraction through the
    // apparent mesh was 10 ms of its 24² draft's 13 ms on the CPU). A large frame's are
    // not kept (four 2048² frames' would hold 800 MB).
    static PASSES: Memo<PassKey, Arc<TextureSet>, 4> = Memo::new();
    let size = scene_texture_size(options.width, options.height);
    let make = || {
        let maps = scene.scene_textures_with(size.0, size.1, environment);
        let mut made = TextureSet::new();
        for name in SCREEN_TEXTURES {
            if !wanted.contains(&name) {
                continue;
            }
            let img = match name {
                "background" => &maps.background,
                "refraction" => &maps.refraction,
                _ => &maps.reflection,
            };
            let key = format!("{}{name}", crate::document::TextureSource::SCENE);
            made.insert(key, screen_texture(img)?)?;
        }
        Ok::<_, crate::texture::TextureError>(Arc::new(made))
    };
    let made = match size.0 as u64 * size.1 as u64 <= KEPT_PASS_TEXELS {
        true => PASSES.get_or_make(
            (
                serde_json::to_string(scene).unwrap_or_default(),
                scene_names(&wanted, false),
                size,
                Same(options.environment.clone()),
            ),
            make,
        ),
        false => make(),
    };
    set.extend_shared(&*made?)?;
    Ok(set)
}

/// The screen-space scene textures, by their names without `scene:`, in the order they
/// are made and baked.
pub const SCREEN_TEXTURES: [&str; 3] = ["background", "refraction", "reflection"];

/// A screen-space scene pass as the texture a render binds: alpha 1, box mips.
pub(super) fn screen_texture(
    img: &crate::scene::SceneImage,
) -> Result<Texture, crate::texture::TextureError> {
    let image = Image::new(
        img.width,
        img.height,
        img.data.iter().map(|c| [c[0], c[1], c[2], 1.0]).collect(),
    )?;
    Texture::new(image, true)
}

/// Texels of the largest scene passes the CPU path keeps between frames (512²).
const KEPT_PASS_TEXELS: u64 = 512 * 512;

/// The scene texture names in `wanted` made from the environment map (`environment`) or
/// not, sorted, each once: part of a memo's key.
fn scene_names(wanted: &[&str], environment: bool) -> Vec<String> {
    let mut names: Vec<String> = wanted
        .iter()
        .filter(|w| is_environment_texture(w) == environment)
        .map(|w| w.to_string())
        .collect();
    names.sort_unstable();
    names.dedup();
    names
}

/// What the CPU's scene passes of a frame depend on: the scene as JSON, the pass names,
/// the textures' size and the environment image.
type PassKey = (String, Vec<String>, (u32, u32), Same<Texture>);

/// The scene textures made from the environment map: the map itself and its
/// image-based-lighting tables ([`crate::scene::ibl`]).
const ENVIRONMENT_TEXTURES: [&str; 4] = [
    "environment",
    "environment_ggx",
    "brdf_lut",
    "environment_sh",
];

/// Whether scene texture `name` is made from the environment map.
fn is_environment_texture(name: &str) -> bool {
    ENVIRONMENT_TEXTURES.contains(&name)
}

/// Adds to `set` the environment textures in `wanted` made from the equirectangular map
/// `env` ([`ENVIRONMENT_TEXTURES`]): `scene:environment` (box mips), and the prefiltered
/// GGX levels, BRDF table and irradiance coefficients of [`crate::scene::ibl`], computed on
/// the CPU (the GPU render uploads them too) once per map ([`ibl_cache`]).
pub(super) fn insert_environment_textures(
    set: &mut TextureSet,
    wanted: &[&str],
    env: Image,
) -> Result<(), crate::texture::TextureError> {
    use crate::scene::ibl;
    let key = |name: &str| format!("{}{name}", crate::document::TextureSource::SCENE);
    let map_key = ibl_cache::key(&env);
    let source = Texture::new(env, true)?;
    if wanted.contains(&"environment_ggx") {
        let ggx = ibl_cache::environment_ggx(map_key, &source)?;
        set.insert_shared(key("environment_ggx"), ggx)?;
    }
    if wanted.contains(&"brdf_lut") {
        set.insert(key("brdf_lut"), ibl::brdf_lut().clone())?;
    }
    if wanted.contains(&"environment_sh") {
        let sh = ibl_cache::sh_irradiance(map_key, &source);
        set.insert(key("environment_sh"), ibl::sh_texture(&sh)?)?;
    }
    if wanted.contains(&"environment") {
        set.insert(key("environment"), source)?;
    }
    Ok(())
}

/// Whether `graph` samples any scene texture (`scene:…`).
pub fn uses_scene_textures(graph: &Graph) -> bool {
    graph
        .nodes()
        .iter()
        .any(|n| n.texture.as_ref().and_then(|t| t.scene_name()).is_some())
}

/// The scene textures `graph` samples (`scene:environment`, `scene:background`,
/// `scene:refraction`, `scene:reflection`), rendered from `scene` as a `width × height`
/// render would bind them, `environment` being the image of an image environment. For
/// evaluating a graph outside a render (`matgraph eval`).
pub fn scene_texture_set(
    graph: &Graph,
    scene: &Scene,
    width: u32,
    height: u32,
    environment: Option<Arc<Texture>>,
) -> Result<TextureSet, RenderError> {
    let budget = crate::budget::MemoryBudget::default();
    scene_texture_set_within(graph, scene, width, height, environment, &budget)
}

/// [`scene_texture_set`] with the scene's meshes reserved in `budget` first
/// ([`Scene::reserve_meshes`]): a scene whose meshes do not fit is refused before any is
/// built.
pub fn scene_texture_set_within(
    graph: &Graph,
    scene: &Scene,
    width: u32,
    height: u32,
    environment: Option<Arc<Texture>>,
    budget: &crate::budget::MemoryBudget,
) -> Result<TextureSet, RenderError> {
    scene.reserve_meshes(budget)?;
    // The image rides in the options too: the environment's memo is keyed by it.
    let lookup = environment.clone().map(crate::scene::image_lookup);
    let lookup: Option<&crate::scene::EnvLookup> =
        lookup.as_ref().map(|f| f as &crate::scene::EnvLookup);
    let options = RenderOptions {
        width,
        height,
        environment,
        ..RenderOptions::default()
    };
    textures(graph, scene, &options, lookup)
}

/// The scene a graph names in its file, when it names one inline: a preset name
/// (`"ball"`, `"water"`) or a scene object. `Ok(None)` when the graph names none or names a
/// scene file (a string that is not a preset), which the caller resolves relative to the
/// graph file.
pub fn graph_scene(graph: &Graph) -> Result<Option<Scene>, crate::scene::SceneError> {
    match &graph.scene {
        None => Ok(None),
        Some(serde_json::Value::String(name)) => Ok(Scene::preset(name)),
        Some(value) => Scene::from_json(&value.to_string()).map(Some),
    }
}

/// Width of the `scene:environment` map (its height is half).
pub const ENVIRONMENT_MAP_WIDTH: u32 = 512;

/// The scene's surroundings as an equirectangular map ([`Scene::environment_map`]: the
/// room seen from the ball's centre, the sky or image elsewhere).
fn environment_map(
    scene: &Scene,
    image: Option<&crate::scene::EnvLookup>,
) -> Result<Image, crate::texture::TextureError> {
    let (w, h) = (ENVIRONMENT_MAP_WIDTH, ENVIRONMENT_MAP_WIDTH / 2);
    Image::new(w, h, scene.environment_map(w, h, image))
}

/// Renders `graph` in `scene`.
pub fn render(
    graph: &Graph,
    scene: &Scene,
    options: &RenderOptions,
) -> Result<HdrImage, RenderError> {
    render_timed(graph, scene, options).map(|(img, _)| img)
}

/// Renders `graph` in `scene` and reports how long each stage took.
pub fn render_timed(
    graph: &Graph,
    scene: &Scene,
    options: &RenderOptions,
) -> Result<(HdrImage, RenderTimings), RenderError> {
    let mut t = RenderTimings::default();
    let roles = roles(graph)?;
    let time = options.time.unwrap_or(scene.time);
    // The override moves the scene too (a bubble's path, the G-buffer's displacement), not
    // only the material's `time` attribute.
    let at_time;
    let scene = if time == scene.time {
        scene
    } else {
        at_time = Scene {
            time,
            ..scene.clone()
        };
        &at_time
    };
    let Some(first) = roles.color.as_ref().or(roles.emission.as_ref()) else {
        return Err(EvalError::NoOutputs.into());
    };
    // Refused before anything is compiled or allocated when it cannot fit: the scene's
    // meshes first (computed from its parameters), then the frame in what is left.
    let budget = crate::budget::MemoryBudget::new(options.memory_budget);
    scene.reserve_meshes(&budget)?;
    let meshes = budget.used();
    let plan = plan_memory(
        options.width,
        options.height,
        options.samples.max(1),
        uses_scene_textures(graph),
        budget.remaining(),
    )
    .map_err(|e| e.with_reserve(meshes, "scene meshes", options.memory_budget))?;
    // Every plan of a graph exposes the same parameters, so one set serves all evaluators.
    let mut params = crate::gpu::default_parameters(
        graph,
        &PlanOptions {
            outputs: vec![first.0.clone()],
            bake_parameters: false,
        },
    )?;
    for (name, value) in &options.parameters {
        params.set(name, *value)?;
    }

    if options.backend == Backend::Gpu {
        // The GPU rasteriser draws every render (render/gpu.rs): no fallback.
        let ctx = crate::gpu::GpuContext::shared()?;
        let image = gpu::render(ctx, graph, scene, options, &params, time, &mut t)?;
        return Ok((image, t));
    }

    let start = Instant::now();
    let lit = roles
        .color
        .as_ref()
        .map(|(n, _)| evaluator(graph, vec![n.clone()], options.backend))
        .transpose()?;
    let mut unlit_names: Vec<String> = Vec::new();
    unlit_names.extend(roles.emission.iter().map(|(n, _)| n.clone()));
    unlit_names.extend(roles.alpha.iter().cloned());
    let unlit = (!unlit_names.is_empty())
        .then(|| evaluator(graph, unlit_names.clone(), options.backend))
        .transpose()?;
    t.compile = start.elapsed();

    // 1. Displacement at the vertices.
    let start = Instant::now();
    let mut mesh: Mesh = scene.material_mesh();
    // The tangent frame, when the shading reads it: the undisplaced mesh's MikkTSpace
    // tangents, as the GPU's vertex buffer holds them.
    let tangents = reads_tangents(graph, &shaded_names(&roles))?.then(|| mesh.tangents());
    if let Some(name) = &roles.displacement {
        let plan = crate::plan::Plan::compile(
            graph,
            &PlanOptions {
                outputs: vec![name.clone()],
                bake_parameters: false,
            },
        )?;
        let n = mesh.positions.len();
        let mut batch = SampleBatch::new(n);
        let flat3 =
            |v: &[Vec3]| -> Vec<f32> { (0..3).flat_map(|c| v.iter().map(move |p| p[c])).collect() };
        batch.set_planar(Attribute::Position, flat3(&mesh.positions))?;
        batch.set_planar(Attribute::Normal, flat3(&mesh.normals))?;
        batch.set_planar(
            Attribute::Uv,
            (0..2)
                .flat_map(|c| mesh.uvs.iter().map(move |p| p[c]))
                .collect(),
        )?;
        batch.set_time(time);
        let out = plan.execute(&batch, &params)?;
        let d = out.planar(0);
        let offsets: Vec<Vec3> = (0..n)
            .map(|i| Vec3::new(d[i], d[n + i], d[2 * n + i]))
            .collect();
        mesh = mesh.displaced(&offsets);
    }
    t.displace = start.elapsed();

    // 2.–4. Band by band: G-buffer, material, composite and resolve.
    let band_rows = options.band_rows.unwrap_or(plan.band_rows).max(1);
    let start = Instant::now();
    let lookup = options.environment.clone().map(crate::scene::image_lookup);
    let lookup: Option<&crate::scene::EnvLookup> =
        lookup.as_ref().map(|f| f as &crate::scene::EnvLookup);
    let bound = Arc::new(textures(graph, scene, options, lookup)?);
    let mut frame = crate::scene::GBufferFrame::new(
        scene,
        &mesh,
        options.width,
        options.height,
        options.samples.max(1),
        lookup,
    );
    if let Some(tangents) = tangents {
        frame = frame.with_tangents(tangents);
    }
    t.gbuffer = start.elapsed();
    let mut pixels: Vec<[f32; 3]> =
        Vec::with_capacity(options.width as usize * options.height as usize);
    let mut first = 0;
    while first < options.height {
        let last = first.saturating_add(band_rows).min(options.height);
        let start = Instant::now();
        let mut g = frame.rows(first..last);
        g.batch.set_time(time);
        g.batch.set_textures(bound.clone());
        t.gbuffer += start.elapsed();
        shade_band(
            &mut g,
            &mut pixels,
            scene,
            &lit,
            &unlit,
            &roles,
            &params,
            &mut t,
        )?;
        first = last;
    }
    let (width, height) = (options.width, options.height);
    Ok((
        HdrImage {
            width,
            height,
            pixels,
        },
        t,
    ))
}

/// Evaluates the material over band `g`, composites it over the background and appends
/// the band's resolved pixels to `pixels`.
#[allow(clippy::too_many_arguments)]
fn shade_band(
    g: &mut GBuffer,
    pixels: &mut Vec<[f32; 3]>,
    scene: &Scene,
    lit: &Option<Box<dyn Evaluator>>,
    unlit: &Option<Box<dyn Evaluator>>,
    roles: &Roles,
    params: &crate::plan::ParamValues,
    t: &mut RenderTimings,
) -> Result<(), RenderError> {
    // 3. Material.
    let start = Instant::now();
    let n = g.samples.len();
    let mut radiance = vec![Vec3::ZERO; n];
    let mut alpha = vec![1.0f32; n];
    if n > 0 {
        if let Some(lit) = lit {
            let positions = g
                .batch
                .column(Attribute::Position)
                .map(<[f32]>::to_vec)
                .unwrap_or_default();
            for light in &scene.lights {
                let (dir, color) = scene.light_columns(light, &positions, n);
                g.batch.set_planar(Attribute::Light, dir)?;
                g.batch.set_planar(Attribute::LightColor, color)?;
                let out = lit.evaluate(&g.batch, params)?;
                let c = rgb(&out, 0);
                for (i, r) in radiance.iter_mut().enumerate() {
                    *r += c(i);
                }
            }
        }
        if let Some(unlit) = unlit {
            let out = unlit.evaluate(&g.batch, params)?;
            let mut k = 0;
            if roles.emission.is_some() {
                let c = rgb(&out, 0);
                for (i, r) in radiance.iter_mut().enumerate() {
                    *r += c(i);
                }
                k = 1;
            }
            if roles.alpha.is_some() {
                let a = out.planar(k);
                for (i, x) in alpha.iter_mut().enumerate() {
                    *x = if a[i].is_finite() {
                        a[i].clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                }
            }
        }
    }
    t.shade += start.elapsed();

    // 4. Composite and resolve.
    let start = Instant::now();
    let mut samples: Vec<Vec3> = std::mem::take(&mut g.background)
        .into_iter()
        .map(Vec3::from_array)
        .collect();
    for (k, &s) in g.samples.iter().enumerate() {
        let bg = samples[s as usize];
        let c = radiance[k];
        let c = if c.is_finite() { c } else { Vec3::ZERO };
        samples[s as usize] = c * alpha[k] + bg * (1.0 - alpha[k]);
    }
    let spp = g.spp as usize;
    pixels.extend(
        samples
            .chunks(spp)
            .map(|px| (px.iter().copied().sum::<Vec3>() / spp as f32).to_array()),
    );
    t.resolve += start.elapsed();
    Ok(())
}
