//! Compiling graphs to WGSL: code generation, naga validation with errors mapped back to
//! nodes, the uniform layout read from naga, and cross-compilation through naga's backends.
//!
//! A generated module holds, in order: the uniform struct of the material's parameters, the
//! geometry and output structs, the helper and node functions the graph uses (each once), the
//! material function `mg_material` that calls them in plan order, and the entry points
//! (`mg_compute` for batch evaluation, `mg_fragment` for a per-pixel preview, none for the
//! [`Entry::Library`] an app calls from its own shader, or `mg_vertex` and `mg_fragment` with
//! the light loop for [`Entry::Render`], the app contract of [`crate::material`]). Generation
//! is deterministic: the same graph and options give the same bytes.

mod emit;
mod groups;
mod hardware;
mod harness;
mod layout;
mod prune;
pub mod render;
mod targets;
mod validate;

pub use emit::fragment_location;
pub use harness::{HarnessModule, node_choice_harness, node_constant_harness, node_harness};
pub use layout::{UniformField, UniformLayout, UniformSource};
pub use targets::Target;

use crate::graph::Graph;
use crate::node::Attribute;
use crate::plan::{EvalError, Plan, PlanOptions};
use crate::types::SocketType;

/// How a module reads the textures its graph samples.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TextureMode {
    /// Three read-only storage buffers of f32 texels and tables, filtered by WGSL code that
    /// repeats the CPU's arithmetic step for step ([`crate::texture::SAMPLE_WGSL`]): bit for
    /// bit the CPU's result. Used by the compute path and the parity tests.
    #[default]
    Exact,
    /// One `texture_2d<f32>` per texture with every mip level, and one sampler per
    /// (wrap, filter) pair the graph uses, read with `textureSampleLevel`: the GPU's own
    /// filtering, within the bound stated in docs/integration.md of the CPU.
    Hardware,
}

impl TextureMode {
    /// The mode's name in the contract JSON and on the command line.
    pub const fn name(self) -> &'static str {
        match self {
            TextureMode::Exact => "exact",
            TextureMode::Hardware => "hardware",
        }
    }
    /// Parses a name written by [`TextureMode::name`].
    pub fn from_name(name: &str) -> Option<TextureMode> {
        [TextureMode::Exact, TextureMode::Hardware]
            .into_iter()
            .find(|m| m.name() == name)
    }
}

/// The entry point a module is generated for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Entry {
    /// `mg_compute`: evaluates the material over planar storage buffers.
    #[default]
    Compute,
    /// `mg_fragment`: evaluates the material per pixel from interpolated geometry.
    Fragment,
    /// No entry point: `mg_material(geom: MgGeometry) -> MgOutputs` and its bindings (group 0:
    /// parameters at 0, textures from 3), for an app's own shader to call.
    Library(TextureMode),
    /// `mg_vertex` (displacement on the GPU, normals rebuilt) and `mg_fragment` (the light
    /// loop, premultiplied colour and alpha): see [`render`] and docs/integration.md.
    Render(TextureMode),
}

impl Entry {
    /// The entry point's function name (the fragment entry of [`Entry::Render`], the material
    /// function of [`Entry::Library`]).
    pub const fn function(self) -> &'static str {
        match self {
            Entry::Compute => "mg_compute",
            Entry::Fragment | Entry::Render(_) => "mg_fragment",
            Entry::Library(_) => "mg_material",
        }
    }
    /// The naga shader stage of [`Entry::function`].
    pub fn stage(self) -> naga::ShaderStage {
        match self {
            Entry::Compute => naga::ShaderStage::Compute,
            _ => naga::ShaderStage::Fragment,
        }
    }
    /// Every entry point of the module, with its stage.
    pub fn entry_points(self) -> Vec<(&'static str, naga::ShaderStage)> {
        match self {
            Entry::Compute => vec![("mg_compute", naga::ShaderStage::Compute)],
            Entry::Fragment => vec![("mg_fragment", naga::ShaderStage::Fragment)],
            Entry::Library(_) => Vec::new(),
            Entry::Render(_) => vec![
                ("mg_vertex", naga::ShaderStage::Vertex),
                ("mg_fragment", naga::ShaderStage::Fragment),
            ],
        }
    }
    /// How the module reads textures.
    pub const fn texture_mode(self) -> TextureMode {
        match self {
            Entry::Library(m) | Entry::Render(m) => m,
            _ => TextureMode::Exact,
        }
    }
    /// A short name for headers and file names: `compute`, `fragment`, `library`, `render`.
    pub const fn name(self) -> &'static str {
        match self {
            Entry::Compute => "compute",
            Entry::Fragment => "fragment",
            Entry::Library(_) => "library",
            Entry::Render(_) => "render",
        }
    }
}

/// Options for [`generate`].
#[derive(Clone, Debug, Default)]
pub struct WgslOptions {
    /// Outputs and parameter baking, as for the CPU plan.
    pub plan: PlanOptions,
    /// The entry point.
    pub entry: Entry,
    /// Whether each parameter read is clamped to its hard range (the default).
    pub clamp: ParameterClamp,
}

/// How the module reads an exposed parameter from `MgParams` (docs/integration.md, "The
/// parameter block").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ParameterClamp {
    /// `clamp(mg_params.x, min, max)` with the parameter's hard range
    /// ([`crate::parameter_info::ParameterInfo::hard`]), per component, for float-valued
    /// parameters that have one: a value the CPU would refuse renders as the nearest accepted
    /// one instead of as inf or NaN (`ior = -5` as 0.001). NaN in, per WGSL, any value of
    /// the range or NaN out.
    #[default]
    HardRange,
    /// `mg_params.x` as written (`matgraph wgsl --no-clamp`): the app checks its values.
    None,
}

/// Threads per compute workgroup.
pub const WORKGROUP_SIZE: u32 = 64;

/// Binding of the compute entry's `mg_geometry` (read-only storage `array<f32>`: every
/// attribute of the batch, planar; see [`geometry_layout`]); absent when the graph reads no
/// attribute.
pub const GEOMETRY_BINDING: u32 = 2;
/// Binding of the compute entry's `mg_out` (read-write storage `array<f32>`: every output,
/// planar; see [`ShaderOutput::column`]). The exact textures' three buffers follow it.
pub const OUTPUT_BINDING: u32 = 3;

/// Where the compute entry reads each attribute in `mg_geometry`: `(attribute, offset)` in
/// `MgGeometry` order, the offset in lanes (floats per sample) from the first attribute's.
/// For a batch of `count` samples, lane `c` of `attribute` for sample `i` is the f32 at
/// `(offset + c) * count + i`: each attribute's planar column(s) one after another, as
/// [`crate::exec::SampleBatch::column`] holds them. The buffer holds
/// [`geometry_lanes`]` · count` floats.
pub fn geometry_layout(attributes: &[Attribute]) -> Vec<(Attribute, u32)> {
    let mut offset = 0;
    attributes
        .iter()
        .map(|&a| {
            let k = offset;
            offset += a.ty().width() as u32;
            (a, k)
        })
        .collect()
}

/// Lanes (floats per sample) of `mg_geometry` for `attributes`.
pub fn geometry_lanes(attributes: &[Attribute]) -> u32 {
    attributes.iter().map(|a| a.ty().width() as u32).sum()
}

/// A resource a module binds (all in bind group 0).
#[derive(Clone, Debug, PartialEq)]
pub enum Binding {
    /// The material's parameters (`MgParams`, uniform).
    Params,
    /// The dispatch description (`MgDispatch { count, row }`, uniform).
    Dispatch,
    /// `mg_geometry`: every attribute of the batch in one planar `array<f32>` (read-only
    /// storage; layout [`geometry_layout`]).
    Geometry,
    /// The planar `array<f32>` of every output (read-write storage).
    Output,
    /// `mg_texels`: RGBA floats of every texture level (see [`crate::texture::TexturePack`]).
    TextureTexels,
    /// `mg_levels`: the level table.
    TextureLevels,
    /// `mg_textures`: the texture table, in the order of [`ShaderModule::textures`].
    TextureTable,
    /// `mg_frame`: the render entries' per-draw uniform (`MgFrame`, see [`render`]).
    Frame,
    /// `mg_lights`: the render entries' lights (read-only storage `array<MgLight>`).
    Lights,
    /// `mg_sampler_WRAP_FILTER`: a sampler of the hardware texture mode.
    Sampler(crate::texture::Wrap, crate::texture::Filter),
    /// `mg_tex_K`: texture slot `K` (`texture_2d<f32>`) of the hardware texture mode.
    Texture(u32),
}

impl Binding {
    /// The WGSL variable bound.
    pub fn variable(&self) -> String {
        match self {
            Binding::Params => "mg_params".into(),
            Binding::Dispatch => "mg_dispatch".into(),
            Binding::Geometry => "mg_geometry".into(),
            Binding::Output => "mg_out".into(),
            Binding::TextureTexels => "mg_texels".into(),
            Binding::TextureLevels => "mg_levels".into(),
            Binding::TextureTable => "mg_textures".into(),
            Binding::Frame => "mg_frame".into(),
            Binding::Lights => "mg_lights".into(),
            Binding::Sampler(w, f) => format!("mg_sampler_{}_{}", w.name(), f.name()),
            Binding::Texture(k) => format!("mg_tex_{k}"),
        }
    }
}

/// One output of a generated module, as laid out in the compute output buffer.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderOutput {
    /// Output name.
    pub name: String,
    /// Its type.
    pub ty: SocketType,
    /// Its member in `MgOutputs` (the name made a unique WGSL identifier).
    pub field: String,
    /// First column in the planar output buffer (column `c` of sample `i` is at
    /// `(column + c) * count + i`).
    pub column: u32,
}

/// A validated WGSL module generated from a graph.
#[derive(Clone, Debug)]
pub struct ShaderModule {
    /// The WGSL text.
    pub source: String,
    /// The entry point.
    pub entry: Entry,
    /// The naga IR of the text.
    pub module: naga::Module,
    /// naga's validation info.
    pub info: naga::valid::ModuleInfo,
    /// Layout of `MgParams` as naga computed it (empty when nothing is uniform).
    pub uniforms: UniformLayout,
    /// Bindings of group 0, by binding number.
    pub bindings: Vec<(u32, Binding)>,
    /// Attributes the material reads, in `MgGeometry` order.
    pub attributes: Vec<Attribute>,
    /// Outputs in request order.
    pub outputs: Vec<ShaderOutput>,
    /// Keys of the textures the module samples, in slot order: pack the batch's textures in
    /// this order (see [`crate::plan::Plan::textures`]).
    pub textures: Vec<String>,
    /// Byte ranges of the text and the node id each was generated for.
    pub spans: Vec<(std::ops::Range<usize>, String)>,
}

impl ShaderModule {
    /// Total columns of the planar output buffer.
    pub fn output_columns(&self) -> u32 {
        self.outputs.iter().map(|o| o.ty.width() as u32).sum()
    }
    /// The node whose generated text contains byte `offset`.
    pub fn node_at(&self, offset: usize) -> Option<&str> {
        self.spans
            .iter()
            .find(|(r, _)| r.contains(&offset))
            .map(|(_, id)| id.as_str())
    }
    /// Cross-compiles the module with naga's backend for `target`.
    pub fn translate(&self, target: Target) -> Result<Vec<u8>, ShaderError> {
        targets::translate(self, target)
    }
}

/// Errors from generating, validating or translating a module.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ShaderError {
    /// The graph could not be planned (unknown output, no outputs).
    #[error(transparent)]
    Plan(#[from] EvalError),
    /// A node type has no WGSL function.
    #[error("node '{node}': node type '{node_type}' has no WGSL implementation")]
    MissingWgsl {
        /// The node.
        node: String,
        /// Its type.
        node_type: String,
    },
    /// naga rejected the generated text; `node` is where the error points, when known.
    #[error("{}naga: {message}", .node.as_ref().map(|n| format!("node '{n}': ")).unwrap_or_default())]
    Naga {
        /// The node the failing text was generated for.
        node: Option<String>,
        /// naga's message, with the offending source lines.
        message: String,
    },
    /// A naga backend failed.
    #[error("{target} backend: {message}")]
    Backend {
        /// The target.
        target: &'static str,
        /// The backend's message.
        message: String,
    },
}

/// Generates and validates the WGSL module of `graph`.
pub fn generate(graph: &Graph, options: &WgslOptions) -> Result<ShaderModule, ShaderError> {
    // The plan and the emitter see the same graph, its bump nodes' shifted heights included.
    let graph = &*crate::bump::expand(graph);
    let plan = Plan::compile(graph, &options.plan)?;
    let text = emit::Emitter::new(graph, &plan, options).emit()?;
    let (module, info) = validate::validate(&text.source, &text.spans)?;
    let uniforms = layout::UniformLayout::read(&module, &text.uniform_fields);
    Ok(ShaderModule {
        source: text.source,
        entry: options.entry,
        module,
        info,
        uniforms,
        bindings: text.bindings,
        attributes: text.attributes,
        outputs: text.outputs,
        textures: text.textures,
        spans: text.spans,
    })
}

/// The WGSL type of a socket type.
pub fn wgsl_type(t: SocketType) -> &'static str {
    match t {
        SocketType::Float => "f32",
        SocketType::Vec2 => "vec2<f32>",
        SocketType::Vec3 | SocketType::Color => "vec3<f32>",
        SocketType::Vec4 => "vec4<f32>",
        SocketType::Int => "i32",
        SocketType::Bool => "bool",
    }
}
