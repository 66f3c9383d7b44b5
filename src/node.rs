//! Node type declarations: typed ports, docs, hard cases and the compute kernels.
//!
//! A node type is declared with a few builder calls (Blender's `node_declare`, Maya's
//! attribute list), and its compute is a plain one-sample Rust function:
//!
//! ```
//! use matgraph::node::{Category, In, NodeType, Out};
//! fn scale(x: f32, k: f32) -> f32 { x * k }
//! let t = NodeType::new("scale", Category::Math, "Multiplies x by k.")
//!     .source("Closed form.")
//!     .input(In::float("x", 0.0).doc("Value to scale."))
//!     .input(In::float("k", 2.0).range(0.0, 4.0).doc("Factor."))
//!     .output(Out::float("result").doc("x · k."))
//!     .compute(scale);
//! assert_eq!(t.inputs().len(), 2);
//! ```

use crate::kernel::{SampleFn, Shape, TileKernel, kernel};
use crate::types::SocketType;
use crate::value::Value;
use std::fmt;

/// The family a node type belongs to, used to group the node list and the editor menu.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Category {
    /// Constants and exposed parameters.
    Input,
    /// Values supplied per sample by the caller (position, normal, ...).
    Geometry,
    /// Scalar and component-wise math.
    Math,
    /// Vector operations (dot, cross, normalize, ...).
    Vector,
    /// Colour operations.
    Color,
    /// Reflection, refraction, Fresnel and phase functions.
    Optics,
    /// Skin (seed 001).
    Skin,
    /// Physically based rendering (seed 003).
    Pbr,
    /// The soap bubble (seed 000).
    Bubble,
    /// Procedural and image textures (noise, checker, ramp).
    Texture,
    /// Cartoon water and waves (seed 004).
    Water,
}

impl Category {
    /// The category's name in docs and JSON.
    pub const fn name(self) -> &'static str {
        match self {
            Category::Input => "input",
            Category::Geometry => "geometry",
            Category::Math => "math",
            Category::Vector => "vector",
            Category::Color => "color",
            Category::Optics => "optics",
            Category::Skin => "skin",
            Category::Pbr => "pbr",
            Category::Bubble => "bubble",
            Category::Texture => "texture",
            Category::Water => "water",
        }
    }
}

impl fmt::Display for Category {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The declared type of a port: fixed, or the node's type variable `T`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PortType {
    /// Always this type.
    Fixed(SocketType),
    /// The node's generic type, resolved per node instance from its inputs.
    Generic,
}

impl PortType {
    /// The concrete type once the node's generic type is known.
    pub fn resolve(self, generic: SocketType) -> SocketType {
        match self {
            PortType::Fixed(t) => t,
            PortType::Generic => generic,
        }
    }
}

impl fmt::Display for PortType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PortType::Fixed(t) => t.fmt(f),
            PortType::Generic => f.write_str("T"),
        }
    }
}

/// A closed range of values for a float-valued input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// Lower bound.
    pub min: f32,
    /// Upper bound.
    pub max: f32,
}

impl Range {
    /// Whether every lane of `v` lies in the range.
    pub fn contains(&self, v: &Value) -> bool {
        v.lanes().iter().all(|x| (self.min..=self.max).contains(x))
    }
}

/// A declared input port.
#[derive(Clone, Debug)]
pub struct InputDecl {
    /// Stable snake_case name.
    pub name: &'static str,
    /// Declared type.
    pub ty: PortType,
    /// Default value (for a generic port: a float broadcast to `T`).
    pub default: Value,
    /// Range the editor's slider and the random tests cover.
    pub soft: Option<Range>,
    /// Range outside of which a literal value is rejected at load.
    pub hard: Option<Range>,
    /// Physical unit ("" when dimensionless).
    pub unit: &'static str,
    /// One-line description.
    pub doc: &'static str,
    /// Names of the choices of an enum (int) input, indexed from 0.
    pub choices: &'static [&'static str],
}

/// Builder for an [`InputDecl`].
pub struct In(InputDecl);

impl In {
    fn new(name: &'static str, ty: PortType, default: Value) -> In {
        In(InputDecl {
            name,
            ty,
            default,
            soft: None,
            hard: None,
            unit: "",
            doc: "",
            choices: &[],
        })
    }
    /// A float input.
    pub fn float(name: &'static str, default: f32) -> In {
        In::new(
            name,
            PortType::Fixed(SocketType::Float),
            Value::float(default),
        )
    }
    /// A vec2 input.
    pub fn vec2(name: &'static str, default: [f32; 2]) -> In {
        In::new(
            name,
            PortType::Fixed(SocketType::Vec2),
            Value::vec2(default),
        )
    }
    /// A vec3 input.
    pub fn vec3(name: &'static str, default: [f32; 3]) -> In {
        In::new(
            name,
            PortType::Fixed(SocketType::Vec3),
            Value::vec3(default),
        )
    }
    /// A vec4 input.
    pub fn vec4(name: &'static str, default: [f32; 4]) -> In {
        In::new(
            name,
            PortType::Fixed(SocketType::Vec4),
            Value::vec4(default),
        )
    }
    /// A linear RGB colour input.
    pub fn color(name: &'static str, default: [f32; 3]) -> In {
        In::new(
            name,
            PortType::Fixed(SocketType::Color),
            Value::color(default),
        )
    }
    /// An int input.
    pub fn int(name: &'static str, default: i32) -> In {
        In::new(name, PortType::Fixed(SocketType::Int), Value::int(default))
    }
    /// A bool input.
    pub fn boolean(name: &'static str, default: bool) -> In {
        In::new(
            name,
            PortType::Fixed(SocketType::Bool),
            Value::boolean(default),
        )
    }
    /// An enum input: an int whose values are the indices of `choices`.
    pub fn choice(name: &'static str, choices: &'static [&'static str], default: usize) -> In {
        let mut i = In::new(
            name,
            PortType::Fixed(SocketType::Int),
            Value::int(default as i32),
        );
        i.0.choices = choices;
        i.0.hard = Some(Range {
            min: 0.0,
            max: (choices.len().max(1) - 1) as f32,
        });
        i
    }
    /// An input of the node's generic type `T`, default `default` in every component.
    pub fn generic(name: &'static str, default: f32) -> In {
        In::new(name, PortType::Generic, Value::float(default))
    }
    /// Sets the soft range: the editor's slider and the random tests cover it.
    pub fn range(mut self, min: f32, max: f32) -> In {
        self.0.soft = Some(Range { min, max });
        self
    }
    /// Sets the hard range: literal values outside it are rejected at load.
    pub fn hard(mut self, min: f32, max: f32) -> In {
        self.0.hard = Some(Range { min, max });
        self
    }
    /// Sets the physical unit.
    pub fn unit(mut self, unit: &'static str) -> In {
        self.0.unit = unit;
        self
    }
    /// Sets the one-line doc.
    pub fn doc(mut self, doc: &'static str) -> In {
        self.0.doc = doc;
        self
    }
}

/// A declared output port.
#[derive(Clone, Debug)]
pub struct OutputDecl {
    /// Stable snake_case name.
    pub name: &'static str,
    /// Declared type.
    pub ty: PortType,
    /// Physical unit ("" when dimensionless).
    pub unit: &'static str,
    /// One-line description.
    pub doc: &'static str,
}

/// Builder for an [`OutputDecl`].
pub struct Out(OutputDecl);

impl Out {
    fn new(name: &'static str, ty: PortType) -> Out {
        Out(OutputDecl {
            name,
            ty,
            unit: "",
            doc: "",
        })
    }
    /// A float output.
    pub fn float(name: &'static str) -> Out {
        Out::new(name, PortType::Fixed(SocketType::Float))
    }
    /// A vec2 output.
    pub fn vec2(name: &'static str) -> Out {
        Out::new(name, PortType::Fixed(SocketType::Vec2))
    }
    /// A vec3 output.
    pub fn vec3(name: &'static str) -> Out {
        Out::new(name, PortType::Fixed(SocketType::Vec3))
    }
    /// A vec4 output.
    pub fn vec4(name: &'static str) -> Out {
        Out::new(name, PortType::Fixed(SocketType::Vec4))
    }
    /// A colour output.
    pub fn color(name: &'static str) -> Out {
        Out::new(name, PortType::Fixed(SocketType::Color))
    }
    /// A bool output.
    pub fn boolean(name: &'static str) -> Out {
        Out::new(name, PortType::Fixed(SocketType::Bool))
    }
    /// An output of the node's generic type `T`.
    pub fn generic(name: &'static str) -> Out {
        Out::new(name, PortType::Generic)
    }
    /// Sets the physical unit.
    pub fn unit(mut self, unit: &'static str) -> Out {
        self.0.unit = unit;
        self
    }
    /// Sets the one-line doc.
    pub fn doc(mut self, doc: &'static str) -> Out {
        self.0.doc = doc;
        self
    }
}

/// A per-sample value the caller supplies (or the frame, for `time`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Attribute {
    /// World-space position.
    Position,
    /// Unit surface normal, pointing out of the surface.
    Normal,
    /// Unit direction from the surface towards the eye (`V`).
    View,
    /// Unit direction from the surface towards the light (`L`).
    Light,
    /// Surface texture coordinates.
    Uv,
    /// Radiance arriving from the light (colour × intensity × falloff), linear RGB.
    LightColor,
    /// Position on the screen, (0, 0) top left to (1, 1) bottom right.
    ScreenUv,
    /// Depth below the water surface in metres (0 above it or where there is no water).
    Depth,
    /// Time in seconds; the same for every sample of a batch.
    Time,
    /// Screen-space derivative of [`Attribute::Uv`] along the pixel x axis: `∂uv/∂x`, in uv
    /// units per pixel, where x is the framebuffer column coordinate in pixels, growing to the
    /// right (WGSL framebuffer coordinates, `@builtin(position).x`). It is what WGSL's
    /// `dpdx(uv)` gives a fragment shader (WGSL "Derivative Built-in Functions" section): the
    /// CPU G-buffer supplies `dpdxFine`'s value, the difference of uv between the centres of
    /// the pixel's 2 × 2 quad along its row, `uv(x₀ + 1.5, y + ½) − uv(x₀ + ½, y + ½)` with
    /// `x₀ = x & !1`, computed from the camera on the plane of the triangle (see
    /// `scene::GBuffer`); a first-order estimate of the derivative. Its sign follows uv: on the water plane (u along +x) a camera
    /// looking towards −z sees `∂u/∂x > 0`. (0, 0) when the caller supplies none.
    UvDx,
    /// Screen-space derivative of [`Attribute::Uv`] along the pixel y axis: `∂uv/∂y`, in uv
    /// units per pixel, where y is the framebuffer row coordinate in pixels, growing
    /// **downwards** (top-left origin, as `@builtin(position).y` in WGSL and as
    /// [`Attribute::ScreenUv`]). What `dpdy(uv)` gives a fragment shader; the CPU G-buffer
    /// supplies `dpdyFine`'s value, `uv(x + ½, y₀ + 1.5) − uv(x + ½, y₀ + ½)` with
    /// `y₀ = y & !1`, on the triangle's plane. On the water plane seen from above (v along −z, the
    /// far side at the top of the image) `∂v/∂y < 0`. (0, 0) when the caller supplies none.
    UvDy,
    /// Unit surface tangent T, the direction in which u grows, orthogonal to
    /// [`Attribute::Normal`]: the mesh's MikkTSpace tangent (Mikkelsen 2008) interpolated and
    /// made orthogonal to the shading normal (`scene::orthonormal_tangent`). (1, 0, 0) when
    /// the caller supplies none.
    Tangent,
    /// The bitangent sign s (±1): the direction in which v grows is `s · (N × T)` (−1 where
    /// the uvs are mirrored). 1 when the caller supplies none.
    BitangentSign,
    /// Blender's generated texture coordinate: the position in the material surface's
    /// axis-aligned bounding box, `0.5 + (p − centre) / (2 · half_size)` per axis, so the box
    /// spans [0, 1]³ (an axis of zero extent gives 0.5, as Blender's texture space of size 1
    /// there). (0.5, 0.5, 0.5) when the caller supplies none.
    Generated,
    /// The view direction mirrored about the normal, `2 (N · V) N − V` (Cycles'
    /// `svm_node_tex_coord` reflection, world space). (0, 0, 1) when the caller supplies none.
    Reflection,
    /// The screen position with Blender's window convention: (0, 0) bottom left to (1, 1) top
    /// right, z = 0; i.e. `(screen_uv.x, 1 − screen_uv.y, 0)`. (0.5, 0.5, 0) when the caller
    /// supplies none.
    Window,
    /// The position in camera space (Cycles' convention): x to the right of the screen, y up
    /// it, z along the viewing direction (positive in front of the camera), in metres from the
    /// eye. (0, 0, 1) when the caller supplies none.
    Camera,
    /// Screen-space derivative of [`Attribute::Position`] along the pixel x axis: `∂P/∂x`, in
    /// metres per pixel, x growing to the right, as [`Attribute::UvDx`] is uv's: what
    /// `dpdxFine(position)` gives a fragment shader, the CPU G-buffer supplying the difference of
    /// the positions on the triangle's plane under the centres of the pixel's 2 × 2 quad along
    /// its row. The `bump` node's one-pixel offset (Cycles' `dP.dx`). (0, 0, 0) when the caller
    /// supplies none.
    PositionDx,
    /// Screen-space derivative of [`Attribute::Position`] along the pixel y axis (downwards):
    /// `∂P/∂y`, metres per pixel, as `dpdyFine(position)`; see [`Attribute::PositionDx`].
    /// (0, 0, 0) when the caller supplies none.
    PositionDy,
}

/// Every attribute, in declaration order.
pub const ALL_ATTRIBUTES: [Attribute; 19] = [
    Attribute::Position,
    Attribute::Normal,
    Attribute::View,
    Attribute::Light,
    Attribute::Uv,
    Attribute::LightColor,
    Attribute::ScreenUv,
    Attribute::Depth,
    Attribute::Time,
    Attribute::UvDx,
    Attribute::UvDy,
    Attribute::Tangent,
    Attribute::BitangentSign,
    Attribute::Generated,
    Attribute::Reflection,
    Attribute::Window,
    Attribute::Camera,
    Attribute::PositionDx,
    Attribute::PositionDy,
];

impl Attribute {
    /// The name used on the command line and in docs.
    pub const fn name(self) -> &'static str {
        match self {
            Attribute::Position => "position",
            Attribute::Normal => "normal",
            Attribute::View => "view",
            Attribute::Light => "light",
            Attribute::Uv => "uv",
            Attribute::LightColor => "light_color",
            Attribute::ScreenUv => "screen_uv",
            Attribute::Depth => "depth",
            Attribute::Time => "time",
            Attribute::UvDx => "uv_dx",
            Attribute::UvDy => "uv_dy",
            Attribute::Tangent => "tangent",
            Attribute::BitangentSign => "bitangent_sign",
            Attribute::Generated => "generated",
            Attribute::Reflection => "reflection",
            Attribute::Window => "window",
            Attribute::Camera => "camera",
            Attribute::PositionDx => "position_dx",
            Attribute::PositionDy => "position_dy",
        }
    }
    /// Parses a name written by [`Attribute::name`].
    pub fn from_name(name: &str) -> Option<Attribute> {
        ALL_ATTRIBUTES.into_iter().find(|a| a.name() == name)
    }
    /// The attribute's type.
    pub const fn ty(self) -> SocketType {
        match self {
            Attribute::Uv | Attribute::ScreenUv | Attribute::UvDx | Attribute::UvDy => {
                SocketType::Vec2
            }
            Attribute::LightColor => SocketType::Color,
            Attribute::Time | Attribute::Depth | Attribute::BitangentSign => SocketType::Float,
            _ => SocketType::Vec3,
        }
    }
    /// Whether the value is the same for every sample of a batch.
    pub const fn is_uniform(self) -> bool {
        matches!(self, Attribute::Time)
    }
    /// The value used when the caller supplies none: the origin, a +z normal, view and
    /// light straight above (normal incidence), uv and screen uv (0.5, 0.5), white light,
    /// depth 0, time 0, uv derivatives (0, 0), tangent +x with sign 1 (the frame of the +z
    /// normal whose u grows along x and v along y), generated (½, ½, ½) (the box's centre),
    /// reflection +z (of the view +z about the normal +z), window (½, ½, 0) (the screen's
    /// centre), camera (0, 0, 1) (a point a metre in front of the eye) and position derivatives
    /// (0, 0, 0).
    pub const fn default_value(self) -> Value {
        match self {
            Attribute::Position => Value::vec3([0.0, 0.0, 0.0]),
            Attribute::Normal | Attribute::View | Attribute::Light => Value::vec3([0.0, 0.0, 1.0]),
            Attribute::Uv | Attribute::ScreenUv => Value::vec2([0.5, 0.5]),
            Attribute::LightColor => Value::color([1.0, 1.0, 1.0]),
            Attribute::Depth | Attribute::Time => Value::float(0.0),
            Attribute::UvDx | Attribute::UvDy => Value::vec2([0.0, 0.0]),
            Attribute::Tangent => Value::vec3([1.0, 0.0, 0.0]),
            Attribute::BitangentSign => Value::float(1.0),
            Attribute::Generated => Value::vec3([0.5, 0.5, 0.5]),
            Attribute::Reflection => Value::vec3([0.0, 0.0, 1.0]),
            Attribute::Window => Value::vec3([0.5, 0.5, 0.0]),
            Attribute::Camera => Value::vec3([0.0, 0.0, 1.0]),
            Attribute::PositionDx | Attribute::PositionDy => Value::vec3([0.0, 0.0, 0.0]),
        }
    }
}

/// Where a node's outputs come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Evaluation {
    /// Computed by the node's kernel from its inputs.
    Compute,
    /// An exposed parameter: the `value` input is the default, callers override it per
    /// evaluation without recompiling; never folded into a constant.
    Parameter,
    /// Output `k` is the caller-supplied attribute `k`.
    Attributes(&'static [Attribute]),
    /// Samples the image named by the node's `texture` field; its kernel is the texture
    /// sampler, run with the textures bound to the batch.
    Texture,
}

/// The sampler a [`TextureKernel`] reads its texture through: `(uv, lod, wrap, filter)` to
/// RGBA, as [`crate::texture::Texture::sample`].
pub type TextureSampler<'a> =
    dyn Fn(glam::Vec2, f32, crate::texture::Wrap, crate::texture::Filter) -> glam::Vec4 + 'a;

/// The CPU kernel of a texture node whose ports are not `image_texture`'s: for `n` samples
/// of a tile it reads the node's texture through `sample` and writes its outputs from its
/// inputs (component `c` of a port at `c · TILE + i`, as in [`TileKernel::run`]). The node's
/// WGSL does the same through `mg_sample_texture(tex, ...)`.
pub type TextureKernel =
    fn(sample: &TextureSampler, ins: &[&[f32]], outs: &mut [&mut [f32]], n: usize);

/// One concrete implementation of a node type, for one resolved generic type.
pub struct Variant {
    /// The generic type this variant implements (`None` for non-generic nodes).
    pub generic: Option<SocketType>,
    /// The whole-tile CPU kernel.
    pub kernel: Box<dyn TileKernel>,
}

impl fmt::Debug for Variant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Variant")
            .field("generic", &self.generic)
            .finish_non_exhaustive()
    }
}

/// A named set of input values that a stability or parity test must feed the node.
#[derive(Clone, Debug)]
pub struct HardCase {
    /// Why the case is hard (grazing, TIR, g → 1, ...).
    pub why: &'static str,
    /// Inputs set by this case; the others keep their defaults.
    pub values: Vec<(&'static str, Value)>,
}

/// A constant table that a node's WGSL reads as the `MgParams` member `field`
/// (`array<vec4<f32>, N>`), written by the host with the parameters.
///
/// A module-scope `const` array indexed at run time is the obvious spelling, but naga's
/// SPIR-V backend stores the whole array into a temporary at every access, and lavapipe's
/// LLVM then spends minutes compiling a 471-entry one (measured: 263 s for one pipeline,
/// against 1 ms for the same loop over a uniform array; docs/benchmarks.md).
#[derive(Debug, PartialEq)]
pub struct WgslTable {
    /// The `MgParams` member name the WGSL spells (`mg_params.<field>[k]`).
    pub field: &'static str,
    /// The rows, one `vec4<f32>` each.
    pub rows: &'static [[f32; 4]],
}

/// The per-choice WGSL of one enum or bool input ([`NodeType::wgsl_per_choice`]): where the
/// input is written in the file (not linked), the module holds only that choice's helpers
/// and tables. naga keeps every branch of an `if (method == k)` on a function argument, so
/// without it a constant choice would still compile (and count, and upload the tables of)
/// every other one.
///
/// The node's template names the per-choice helper as `mg_name${input}(…, input)`: at a
/// written choice that reads `mg_name_<choice>`, defined by the choice's helpers; otherwise
/// `mg_name`, defined by [`WgslChoices::dispatch`], which calls the choice's function at run
/// time. A bool input's choices are `"false"` and `"true"`.
#[derive(Debug)]
pub struct WgslChoices {
    /// The enum (or bool) input.
    pub input: &'static str,
    /// The helpers that pick a choice at run time, emitted only where the input is not
    /// written (with every choice's helpers).
    pub dispatch: &'static [&'static str],
    /// The choices that have WGSL of their own.
    pub choices: Vec<WgslChoice>,
}

/// One choice of [`WgslChoices`]: what it adds to the node's own helpers and tables.
#[derive(Debug)]
pub struct WgslChoice {
    /// The choice, by name (`"false"` or `"true"` for a bool).
    pub choice: &'static str,
    /// Its helpers, besides the node's [`NodeType::wgsl_uses`].
    pub helpers: &'static [&'static str],
    /// Its tables, besides the node's [`NodeType::wgsl_uses_tables`].
    pub tables: &'static [&'static WgslTable],
}

/// A node type: declaration, docs, hard cases and compute.
#[derive(Debug)]
pub struct NodeType {
    name: &'static str,
    category: Category,
    summary: &'static str,
    source: &'static str,
    inputs: Vec<InputDecl>,
    outputs: Vec<OutputDecl>,
    evaluation: Evaluation,
    variants: Vec<Variant>,
    hard_cases: Vec<HardCase>,
    wgsl: Option<&'static str>,
    wgsl_variants: Vec<(SocketType, &'static str)>,
    wgsl_helpers: Vec<&'static str>,
    wgsl_tables: Vec<&'static WgslTable>,
    wgsl_choices: Option<WgslChoices>,
    wgsl_constants: Vec<&'static str>,
    texture_kernel: Option<TextureKernel>,
}

impl NodeType {
    /// Starts a declaration with its stable name, category and one-line summary.
    pub fn new(name: &'static str, category: Category, summary: &'static str) -> NodeType {
        NodeType {
            name,
            category,
            summary,
            source: "",
            inputs: Vec::new(),
            outputs: Vec::new(),
            evaluation: Evaluation::Compute,
            variants: Vec::new(),
            hard_cases: Vec::new(),
            wgsl: None,
            wgsl_variants: Vec::new(),
            wgsl_helpers: Vec::new(),
            wgsl_tables: Vec::new(),
            wgsl_choices: None,
            wgsl_constants: Vec::new(),
            texture_kernel: None,
        }
    }
    /// Sets the longer doc: the source (paper, equation) and conventions.
    pub fn source(mut self, text: &'static str) -> NodeType {
        self.source = text;
        self
    }
    /// Adds an input port.
    pub fn input(mut self, input: In) -> NodeType {
        self.inputs.push(input.0);
        self
    }
    /// Adds an output port.
    pub fn output(mut self, output: Out) -> NodeType {
        self.outputs.push(output.0);
        self
    }
    /// Sets the CPU compute of a non-generic node.
    pub fn compute<F: SampleFn<Args>, Args: 'static>(mut self, f: F) -> NodeType {
        self.variants.push(Variant {
            generic: None,
            kernel: kernel(f),
        });
        self
    }
    /// Adds the CPU compute for one resolved generic type `T`.
    pub fn variant<F: SampleFn<Args>, Args: 'static>(mut self, t: SocketType, f: F) -> NodeType {
        self.variants.push(Variant {
            generic: Some(t),
            kernel: kernel(f),
        });
        self
    }
    /// Marks the node as an exposed parameter (see [`Evaluation::Parameter`]).
    pub fn parameter(mut self) -> NodeType {
        self.evaluation = Evaluation::Parameter;
        self
    }
    /// Marks the node as sampling the image named by its `texture` field.
    pub fn texture(mut self) -> NodeType {
        self.evaluation = Evaluation::Texture;
        self
    }
    /// Marks the node as sampling the image named by its `texture` field through its own
    /// CPU kernel (see [`TextureKernel`]); [`NodeType::compute`] still declares the ports.
    pub fn texture_kernel(mut self, k: TextureKernel) -> NodeType {
        self.evaluation = Evaluation::Texture;
        self.texture_kernel = Some(k);
        self
    }
    /// The CPU kernel of a texture node with ports of its own; `None` for `image_texture`'s
    /// sampler (inputs uv, lod, wrap, filter; outputs colour and alpha).
    pub fn texture_kernel_fn(&self) -> Option<TextureKernel> {
        self.texture_kernel
    }
    /// Marks the node's outputs as caller-supplied attributes, one per output.
    pub fn attributes(mut self, attrs: &'static [Attribute]) -> NodeType {
        self.evaluation = Evaluation::Attributes(attrs);
        self
    }
    /// Adds a hard case: the named inputs set, the others at their defaults.
    pub fn hard_case(mut self, why: &'static str, values: &[(&'static str, Value)]) -> NodeType {
        self.hard_cases.push(HardCase {
            why,
            values: values.to_vec(),
        });
        self
    }
    /// Sets the node's WGSL function: the same math as the CPU compute, written once.
    ///
    /// The template defines one function named `$fn` taking the inputs in port order. For a
    /// generic node `$T` stands for the WGSL type of `T`. A node with several outputs returns
    /// `$out`, a struct the code generator declares with one member per output, built
    /// positionally: `return $out(r, 1.0 - r);`. Ints are `i32`, bools `bool`.
    pub fn wgsl(mut self, template: &'static str) -> NodeType {
        self.wgsl = Some(template);
        self
    }
    /// Sets the WGSL template for one generic type only, where the body must differ by type
    /// (for example component access); it takes precedence over [`NodeType::wgsl`].
    pub fn wgsl_variant(mut self, t: SocketType, template: &'static str) -> NodeType {
        self.wgsl_variants.push((t, template));
        self
    }
    /// Declares WGSL helper functions the node's template calls (emitted once per module).
    pub fn wgsl_uses(mut self, helpers: &[&'static str]) -> NodeType {
        self.wgsl_helpers.extend_from_slice(helpers);
        self
    }
    /// Declares constant tables the node's WGSL reads from `MgParams` (see [`WgslTable`]).
    pub fn wgsl_uses_tables(mut self, tables: &[&'static WgslTable]) -> NodeType {
        self.wgsl_tables.extend_from_slice(tables);
        self
    }
    /// Declares the per-choice WGSL of the enum or bool input `input` (see [`WgslChoices`]).
    ///
    /// # Panics
    /// If the node already has per-choice WGSL, or `input` is not an enum or bool input of it
    /// with those choices (a declaration error, caught by the registry's tests).
    pub fn wgsl_per_choice(
        mut self,
        input: &'static str,
        dispatch: &'static [&'static str],
        choices: impl IntoIterator<Item = WgslChoice>,
    ) -> NodeType {
        assert!(
            self.wgsl_choices.is_none(),
            "{}: one wgsl_per_choice",
            self.name
        );
        let decl = self.inputs.iter().find(|i| i.name == input);
        let choices: Vec<WgslChoice> = choices.into_iter().collect();
        for c in &choices {
            let known = decl.is_some_and(|i| {
                i.choices.contains(&c.choice)
                    || (i.ty == PortType::Fixed(SocketType::Bool)
                        && matches!(c.choice, "false" | "true"))
            });
            assert!(
                known,
                "{}: wgsl_per_choice {input}={} is not a declared choice",
                self.name, c.choice
            );
        }
        self.wgsl_choices = Some(WgslChoices {
            input,
            dispatch,
            choices,
        });
        self
    }
    /// Declares the int and bool inputs whose value, where the file writes it (not linked),
    /// the emitter compiles into the node's WGSL function as a function-scope `const` in
    /// place of the parameter (see `docs/benchmarks.md`, procedural textures): the GPU
    /// compiler then drops the branches and loop trips that value rules out, as Blender's
    /// GLSL does with one function per dimension and type. Each written combination is its
    /// own function (`mg_<type>_<input>_<value>…`); a linked input stays a parameter.
    ///
    /// # Panics
    /// If an input is not an int or bool input of the node (a declaration error, caught by
    /// the registry's tests).
    pub fn wgsl_constant_inputs(mut self, inputs: &[&'static str]) -> NodeType {
        for name in inputs {
            let ok = self.inputs.iter().any(|i| {
                i.name == *name
                    && matches!(
                        i.ty,
                        PortType::Fixed(SocketType::Int) | PortType::Fixed(SocketType::Bool)
                    )
            });
            assert!(
                ok,
                "{}: wgsl_constant_inputs {name} is not an int or bool input",
                self.name
            );
        }
        self.wgsl_constants.extend_from_slice(inputs);
        self
    }

    /// Stable snake_case type name.
    pub fn name(&self) -> &'static str {
        self.name
    }
    /// Category.
    pub fn category(&self) -> Category {
        self.category
    }
    /// One-line summary.
    pub fn summary(&self) -> &'static str {
        self.summary
    }
    /// Longer doc naming the source (paper, equation).
    pub fn source_doc(&self) -> &'static str {
        self.source
    }
    /// Input ports in order.
    pub fn inputs(&self) -> &[InputDecl] {
        &self.inputs
    }
    /// Output ports in order.
    pub fn outputs(&self) -> &[OutputDecl] {
        &self.outputs
    }
    /// Where the outputs come from.
    pub fn evaluation(&self) -> Evaluation {
        self.evaluation
    }
    /// The compute variants.
    pub fn variants(&self) -> &[Variant] {
        &self.variants
    }
    /// The hard cases the tests feed the node.
    pub fn hard_cases(&self) -> &[HardCase] {
        &self.hard_cases
    }
    /// The WGSL function template (see [`NodeType::wgsl`]).
    pub fn wgsl_source(&self) -> Option<&'static str> {
        self.wgsl
    }
    /// The WGSL template for generic type `t` (colour uses vec3's).
    pub fn wgsl_for(&self, t: SocketType) -> Option<&'static str> {
        let t = if t == SocketType::Color {
            SocketType::Vec3
        } else {
            t
        };
        self.wgsl_variants
            .iter()
            .find(|(v, _)| *v == t)
            .map(|(_, s)| *s)
            .or(self.wgsl)
    }
    /// The WGSL helper functions every form of the template calls (see [`NodeType::wgsl_helpers_for`]).
    pub fn wgsl_helpers(&self) -> &[&'static str] {
        &self.wgsl_helpers
    }
    /// The constant tables every form of the WGSL reads from `MgParams` (see [`NodeType::wgsl_tables_for`]).
    pub fn wgsl_tables(&self) -> &[&'static WgslTable] {
        &self.wgsl_tables
    }
    /// The per-choice WGSL (see [`WgslChoices`]).
    pub fn wgsl_choices(&self) -> Option<&WgslChoices> {
        self.wgsl_choices.as_ref()
    }
    /// The inputs compiled as constants where written (see [`NodeType::wgsl_constant_inputs`]).
    pub fn wgsl_constants(&self) -> &[&'static str] {
        &self.wgsl_constants
    }
    /// The per-choice WGSL of the choice input's literal `value` (an enum's index, a bool).
    pub fn wgsl_choice_at(&self, value: Value) -> Option<&WgslChoice> {
        let cs = self.wgsl_choices.as_ref()?;
        let decl = &self.inputs[self.input_index(cs.input)?];
        let name = if decl.choices.is_empty() {
            if value.as_bool() { "true" } else { "false" }
        } else {
            decl.choices.get(usize::try_from(value.as_i32()).ok()?)?
        };
        cs.choices.iter().find(|c| c.choice == name)
    }
    /// Every helper the node's function calls, in order without repeats: its own
    /// ([`NodeType::wgsl_uses`]), then `choice`'s, or (`None`: the choice made at run time)
    /// every choice's and the dispatch.
    pub fn wgsl_helpers_for(&self, choice: Option<&WgslChoice>) -> Vec<&'static str> {
        let mut out: Vec<&'static str> = self.wgsl_helpers.clone();
        let extra: Vec<&'static str> = match (choice, &self.wgsl_choices) {
            (Some(c), _) => c.helpers.to_vec(),
            (None, Some(cs)) => cs
                .choices
                .iter()
                .flat_map(|c| c.helpers.iter().copied())
                .chain(cs.dispatch.iter().copied())
                .collect(),
            (None, None) => Vec::new(),
        };
        for h in extra {
            if !out.contains(&h) {
                out.push(h);
            }
        }
        out
    }
    /// Every table the node's function reads, without repeats: its own, then `choice`'s, or
    /// (`None`) every choice's.
    pub fn wgsl_tables_for(&self, choice: Option<&WgslChoice>) -> Vec<&'static WgslTable> {
        let mut out: Vec<&'static WgslTable> = self.wgsl_tables.clone();
        let extra: Vec<&'static WgslTable> = match (choice, &self.wgsl_choices) {
            (Some(c), _) => c.tables.to_vec(),
            (None, Some(cs)) => cs
                .choices
                .iter()
                .flat_map(|c| c.tables.iter().copied())
                .collect(),
            (None, None) => Vec::new(),
        };
        for t in extra {
            if !out.iter().any(|x| std::ptr::eq(*x, t)) {
                out.push(t);
            }
        }
        out
    }
    /// Index of the input called `name`.
    pub fn input_index(&self, name: &str) -> Option<usize> {
        self.inputs.iter().position(|i| i.name == name)
    }
    /// Index of the output called `name`.
    pub fn output_index(&self, name: &str) -> Option<usize> {
        self.outputs.iter().position(|o| o.name == name)
    }
    /// Muted at generic type `generic` (Blender's rule): the input output `k` passes on,
    /// the first of the output's type; `None` where there is none and the output is its
    /// type's zero.
    pub fn passthrough(&self, generic: SocketType, k: usize) -> Option<usize> {
        let ty = self.outputs[k].ty.resolve(generic);
        self.inputs.iter().position(|i| i.ty.resolve(generic) == ty)
    }
    /// What muting the node does, one clause per output: `result ← a`, `alpha = 0`; for a
    /// generic node at its widest `T` (where no port of fixed type shares `T`'s type).
    pub fn muted_rule(&self) -> String {
        let generic = self
            .generic_types()
            .into_iter()
            .max_by_key(|t| t.width())
            .unwrap_or(SocketType::Float);
        if self.evaluation == Evaluation::Parameter {
            return "no effect (the value is the input)".into();
        }
        (0..self.outputs.len())
            .map(|k| match self.passthrough(generic, k) {
                Some(j) => format!("{} ← {}", self.outputs[k].name, self.inputs[j].name),
                None => format!("{} = 0", self.outputs[k].name),
            })
            .collect::<Vec<_>>()
            .join(", ")
    }
    /// Whether any port has the generic type `T`.
    pub fn is_generic(&self) -> bool {
        self.variants.iter().any(|v| v.generic.is_some())
    }
    /// The generic types this node accepts (colour is served by the vec3 variant).
    pub fn generic_types(&self) -> Vec<SocketType> {
        let mut out: Vec<SocketType> = self.variants.iter().filter_map(|v| v.generic).collect();
        if out.contains(&SocketType::Vec3) && !out.contains(&SocketType::Color) {
            out.push(SocketType::Color);
        }
        out
    }
    /// The variant that computes the node for generic type `t` (ignored if not generic).
    pub fn variant_for(&self, t: SocketType) -> Option<&Variant> {
        if !self.is_generic() {
            return self.variants.first();
        }
        let want = if t == SocketType::Color {
            SocketType::Vec3
        } else {
            t
        };
        self.variants.iter().find(|v| v.generic == Some(want))
    }
    /// The default value of input `k` for generic type `t`.
    pub fn default_for(&self, k: usize, t: SocketType) -> Value {
        let decl = &self.inputs[k];
        let ty = decl.ty.resolve(t);
        decl.default.convert(ty).unwrap_or(decl.default)
    }

    /// Checks the declaration against its kernels; returns every problem found.
    pub fn check(&self) -> Vec<String> {
        let mut problems = Vec::new();
        let n = self.name;
        if !is_snake_case(n) {
            problems.push(format!("{n}: type name is not snake_case"));
        }
        if self.summary.is_empty() || self.source.is_empty() {
            problems.push(format!("{n}: summary and source doc are required"));
        }
        if self.variants.is_empty() {
            problems.push(format!("{n}: no compute"));
        }
        let mut seen = Vec::new();
        for p in self
            .inputs
            .iter()
            .map(|i| (i.name, i.doc))
            .chain(self.outputs.iter().map(|o| (o.name, o.doc)))
        {
            if !is_snake_case(p.0) {
                problems.push(format!("{n}.{}: port name is not snake_case", p.0));
            }
            if p.1.is_empty() {
                problems.push(format!("{n}.{}: port has no doc", p.0));
            }
        }
        for i in &self.inputs {
            if seen.contains(&i.name) {
                problems.push(format!("{n}.{}: duplicate input", i.name));
            }
            seen.push(i.name);
            if let Some(h) = i.hard
                && !h.contains(&i.default)
            {
                problems.push(format!(
                    "{n}.{}: default {} outside hard range",
                    i.name, i.default
                ));
            }
        }
        if let Evaluation::Attributes(a) = self.evaluation
            && a.len() != self.outputs.len()
        {
            problems.push(format!("{n}: one attribute per output expected"));
        }
        for v in &self.variants {
            let t = v.generic.unwrap_or(SocketType::Float);
            let ins: Vec<Shape> = self
                .inputs
                .iter()
                .map(|i| Shape::of(i.ty.resolve(t)))
                .collect();
            let outs: Vec<Shape> = self
                .outputs
                .iter()
                .map(|o| Shape::of(o.ty.resolve(t)))
                .collect();
            if v.kernel.input_shapes() != ins {
                problems.push(format!(
                    "{n} ({t}): compute arguments {:?} do not match inputs {ins:?}",
                    v.kernel.input_shapes()
                ));
            }
            if v.kernel.output_shapes() != outs {
                problems.push(format!(
                    "{n} ({t}): compute results {:?} do not match outputs {outs:?}",
                    v.kernel.output_shapes()
                ));
            }
        }
        for case in &self.hard_cases {
            for (name, value) in &case.values {
                match self.input_index(name) {
                    None => problems.push(format!(
                        "{n}: hard case '{}' sets unknown input {name}",
                        case.why
                    )),
                    Some(k) => {
                        if let PortType::Fixed(t) = self.inputs[k].ty
                            && value.convert(t).is_none()
                        {
                            problems.push(format!(
                                "{n}: hard case '{}' gives {name} a {}",
                                case.why,
                                value.ty()
                            ));
                        }
                    }
                }
            }
        }
        problems
    }
}

/// Whether `s` is a non-empty snake_case identifier.
pub fn is_snake_case(s: &str) -> bool {
    let mut chars = s.chars();
    matches!(chars.next(), Some('a'..='z'))
        && s.chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
}
