//! Compiling graphs to WGSL: code generation, naga validation with errors mapped back to
//! nodes, the uniform layout read from naga, and cross-compilation through naga's backends.
//!
//! A generated module holds, in order: the uniform struct of the material's parameters, the
//! geometry and output structs, the helper and node functions the graph uses (each once), the
//! material function `mg_material` that calls them in plan order, and one entry point
//! (`mg_compute` for batch evaluation, `mg_fragment` for rendering). Generation is
//! deterministic: the same graph and options give the same bytes.

mod emit;
mod harness;
mod layout;
mod targets;
mod validate;

pub use harness::{HarnessModule, node_harness};
pub use layout::{UniformField, UniformLayout, UniformSource};
pub use targets::Target;

use crate::graph::Graph;
use crate::node::Attribute;
use crate::plan::{EvalError, Plan, PlanOptions};
use crate::types::SocketType;

/// The entry point a module is generated for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Entry {
    /// `mg_compute`: evaluates the material over planar storage buffers.
    #[default]
    Compute,
    /// `mg_fragment`: evaluates the material per pixel from interpolated geometry.
    Fragment,
}

impl Entry {
    /// The entry point's function name.
    pub const fn function(self) -> &'static str {
        match self {
            Entry::Compute => "mg_compute",
            Entry::Fragment => "mg_fragment",
        }
    }
    /// The naga shader stage.
    pub fn stage(self) -> naga::ShaderStage {
        match self {
            Entry::Compute => naga::ShaderStage::Compute,
            Entry::Fragment => naga::ShaderStage::Fragment,
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
}

/// Threads per compute workgroup.
pub const WORKGROUP_SIZE: u32 = 64;

/// A resource the compute entry binds (all in bind group 0).
#[derive(Clone, Debug, PartialEq)]
pub enum Binding {
    /// The material's parameters (`MgParams`, uniform).
    Params,
    /// The dispatch description (`MgDispatch { count, row }`, uniform).
    Dispatch,
    /// A planar `array<f32>` of one attribute (read-only storage).
    Attribute(Attribute),
    /// The planar `array<f32>` of every output (read-write storage).
    Output,
    /// `mg_texels`: RGBA floats of every texture level (see [`crate::texture::TexturePack`]).
    TextureTexels,
    /// `mg_levels`: the level table.
    TextureLevels,
    /// `mg_textures`: the texture table, in the order of [`ShaderModule::textures`].
    TextureTable,
}

/// One output of a generated module, as laid out in the compute output buffer.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderOutput {
    /// Output name.
    pub name: String,
    /// Its type.
    pub ty: SocketType,
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
