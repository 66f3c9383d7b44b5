//! Compiling a validated graph into a CPU plan: a straight-line program over registers.
//!
//! Only nodes that reach the requested outputs are kept. Nodes whose inputs are all
//! constants are folded at compile time. Nodes whose inputs do not vary per sample
//! (constants, parameters, time) are hoisted into the *uniform program*, run once per
//! evaluation. What is left is the *varying program*: one step per node, each run over a
//! whole tile of samples by the node's tile kernel (see [`crate::exec`]).

use crate::graph::{Graph, InputSource, NodeIndex, OutputRef};
use crate::kernel::{TileKernel, kernel};
use crate::node::{Attribute, Evaluation, NodeType};
use crate::registry::nearest;
use crate::types::{Conversion, LUMA_709, SocketType};
use crate::value::Value;
use glam::{Vec2, Vec3, Vec4};
use std::collections::HashMap;
use std::sync::{Arc, LazyLock};

/// The dependency that marks a uniform slot as depending on the batch's time.
const TIME: NodeIndex = NodeIndex::MAX;

/// Samples per tile: a few hundred keeps a tile's registers in L1/L2.
pub const TILE: usize = 256;

/// Errors from compiling or running a plan; each names the output, parameter or attribute.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EvalError {
    /// A requested output that the graph does not have.
    #[error("unknown output '{}'{}", vis(.name), hint(.suggestion))]
    UnknownOutput {
        /// What was asked for.
        name: String,
        /// The nearest graph output.
        suggestion: Option<String>,
    },
    /// Nothing to evaluate.
    #[error("the graph has no outputs: name one as node_id.output")]
    NoOutputs,
    /// A parameter the plan does not have.
    #[error("unknown parameter '{}'{}", vis(.name), hint(.suggestion))]
    UnknownParameter {
        /// What was set.
        name: String,
        /// The nearest parameter name.
        suggestion: Option<String>,
    },
    /// A parameter value outside the parameter's own range (the file's `range`).
    #[error("parameter '{}': {value} is outside its range [{min}, {max}]", vis(.name))]
    ParameterOutsideItsRange {
        /// The parameter.
        name: String,
        /// The value refused.
        value: String,
        /// Lower bound.
        min: f32,
        /// Upper bound.
        max: f32,
    },
    /// A parameter value outside the hard range of an input it feeds (see
    /// [`crate::graph::Feed`]).
    #[error(
        "parameter '{}': input '{input}' of node '{}', which it feeds, would get {value}, outside its hard range [{min}, {max}]",
        vis(.name),
        vis(.node)
    )]
    ParameterOutOfRange {
        /// The parameter.
        name: String,
        /// The node whose input it feeds.
        node: String,
        /// That input.
        input: String,
        /// The value that would reach the input.
        value: String,
        /// Lower bound.
        min: f32,
        /// Upper bound.
        max: f32,
    },
    /// A parameter value of the wrong type.
    #[error("parameter '{}': expected {expected}, found {found}", vis(.name))]
    ParameterType {
        /// The parameter.
        name: String,
        /// Its type.
        expected: SocketType,
        /// The type given.
        found: SocketType,
    },
    /// An attribute column of the wrong length.
    #[error("attribute '{attribute}': expected {expected} floats, found {found}")]
    AttributeLength {
        /// The attribute.
        attribute: &'static str,
        /// Samples × width.
        expected: usize,
        /// What was given.
        found: usize,
    },
    /// A texture the plan samples that the batch does not hold.
    #[error("texture '{}' is not loaded (bind it to the batch with SampleBatch::set_textures)", vis(.name))]
    MissingTexture {
        /// The texture's key.
        name: String,
    },
    /// The GPU path could not run (no adapter, device lost, ...); callers may fall back to the CPU.
    #[error("GPU unavailable: {0}")]
    Gpu(String),
}

fn hint(s: &Option<String>) -> String {
    s.as_ref()
        .map(|s| format!(" (did you mean '{}'?)", vis(s)))
        .unwrap_or_default()
}

/// User text of a message, spelt out ([`crate::visible::visible`]).
fn vis(s: &str) -> std::borrow::Cow<'_, str> {
    crate::visible::visible(s)
}

/// Where a value lives at run time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Operand {
    /// Known at compile time.
    Const(Value),
    /// Slot of the uniform program (once per evaluation).
    Uniform(u32),
    /// Register of the varying program (per sample).
    Reg(u32),
}

/// Which kernel a step runs.
#[derive(Clone)]
pub(crate) enum KernelRef {
    /// A node type's variant.
    Node(Arc<NodeType>, usize),
    /// An implicit conversion on a link.
    Convert(usize),
    /// Sampling texture `k` of [`Plan::textures`]: with `None` the image sampler (inputs uv,
    /// lod, wrap, filter; outputs color, alpha), else the node type's own texture kernel.
    Texture(usize, Option<crate::node::TextureKernel>),
}

impl KernelRef {
    /// The tile kernel; `None` for a texture step, which the executor samples itself.
    pub(crate) fn kernel(&self) -> Option<&dyn TileKernel> {
        match self {
            KernelRef::Node(t, v) => t.variants().get(*v).map(|v| v.kernel.as_ref()),
            KernelRef::Convert(i) => Some(CONVERSIONS[*i].as_ref()),
            KernelRef::Texture(..) => None,
        }
    }
}

/// Conversion kernels: broadcast to vec2, vec3, vec4; Rec. 709 luminance; vec2 to
/// `(x, y, 0)`; a vector's `(x, y)`.
static CONVERSIONS: LazyLock<[Box<dyn TileKernel>; 6]> = LazyLock::new(|| {
    [
        kernel(|x: f32| Vec2::splat(x)),
        kernel(|x: f32| Vec3::splat(x)),
        kernel(|x: f32| Vec4::splat(x)),
        kernel(|c: Vec3| c.dot(Vec3::from_array(LUMA_709))),
        kernel(|v: Vec2| v.extend(0.0)),
        kernel(|v: Vec3| v.truncate()),
    ]
});

fn conversion_label(c: Conversion, to: SocketType) -> String {
    match c {
        Conversion::Luminance => "luminance (color → float)".into(),
        Conversion::Extend => format!("extend (vec2 → {to}, z = 0)"),
        Conversion::Truncate => "truncate (to vec2, the xy)".into(),
        _ => format!("broadcast (float → {to})"),
    }
}

fn conversion_kernel(c: Conversion, to: SocketType) -> Option<usize> {
    match (c, to.width()) {
        (Conversion::Broadcast, 2) => Some(0),
        (Conversion::Broadcast, 3) => Some(1),
        (Conversion::Broadcast, 4) => Some(2),
        (Conversion::Luminance, _) => Some(3),
        (Conversion::Extend, _) => Some(4),
        (Conversion::Truncate, _) => Some(5),
        _ => None,
    }
}

/// One call of a kernel: operands are uniform slots (uniform program) or registers
/// (varying program).
#[derive(Clone)]
pub(crate) struct Step {
    pub(crate) kernel: KernelRef,
    pub(crate) inputs: Vec<u32>,
    pub(crate) outputs: Vec<u32>,
    /// What the step computes: `node_id (type)` or the conversion's name.
    pub(crate) label: String,
}

/// How a register is filled before the steps run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum RegFill {
    /// Written by a step.
    Computed,
    /// Copied from the caller's attribute column each tile.
    Attribute(Attribute),
    /// A constant broadcast once per worker.
    Const(Value),
    /// A uniform slot broadcast once per worker.
    Uniform(u32),
}

/// A register of the varying program.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Register {
    pub(crate) width: usize,
    pub(crate) fill: RegFill,
}

/// A requested output of the plan.
#[derive(Clone, Debug)]
pub struct PlanOutput {
    /// The name it was asked by (graph output name or `node_id.output`).
    pub name: String,
    /// Its type.
    pub ty: SocketType,
    /// Where it lives.
    pub operand: Operand,
}

/// An exposed parameter of the plan.
#[derive(Clone, Debug)]
pub struct PlanParameter {
    /// Name.
    pub name: String,
    /// Type.
    pub ty: SocketType,
    /// Value from the graph file.
    pub default: Value,
    /// Uniform slot it fills (`None` when unused or baked).
    pub slot: Option<u32>,
    /// The values it accepts (the file's `range`), every component.
    pub range: Option<crate::node::Range>,
}

/// What the compiler did to the graph.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PlanStats {
    /// Nodes in the graph.
    pub graph_nodes: usize,
    /// Nodes that reach a requested output.
    pub live_nodes: usize,
    /// Nodes folded into constants at compile time.
    pub folded: usize,
    /// Nodes hoisted into the once-per-evaluation uniform program.
    pub hoisted: usize,
    /// Steps run per tile (nodes and link conversions).
    pub per_sample_steps: usize,
    /// Registers of the varying program after reuse.
    pub registers: usize,
}

/// Options for [`Plan::compile`].
#[derive(Clone, Debug, Default)]
pub struct PlanOptions {
    /// Outputs to compute: graph output names or `node_id.output`; empty means every
    /// graph output.
    pub outputs: Vec<String>,
    /// Fold parameters into constants (no per-evaluation override).
    pub bake_parameters: bool,
}

/// A compiled CPU plan.
#[derive(Clone)]
pub struct Plan {
    pub(crate) outputs: Vec<PlanOutput>,
    pub(crate) parameters: Vec<PlanParameter>,
    /// Initial value (and type) of each uniform slot: constants keep theirs.
    pub(crate) uniform_init: Vec<Value>,
    pub(crate) uniform_steps: Vec<Step>,
    pub(crate) time_slot: Option<u32>,
    pub(crate) registers: Vec<Register>,
    pub(crate) steps: Vec<Step>,
    pub(crate) attributes: Vec<Attribute>,
    pub(crate) stats: PlanStats,
    /// Keys of the textures the plan samples, in slot order (see `TextureSource::key`).
    pub(crate) textures: Vec<String>,
    /// Which graph nodes reach a requested output.
    pub(crate) live: Vec<bool>,
    /// Where each node output of a live node lives (constants are folded values).
    pub(crate) node_operands: HashMap<OutputRef, Operand>,
    /// The hard-range guards parameter values are checked against.
    pub(crate) guards: Arc<Guards>,
}

impl Plan {
    /// Compiles `graph` for the outputs in `options` (its `bump` nodes' shifted heights
    /// written in first: [`crate::bump`]).
    pub fn compile(graph: &Graph, options: &PlanOptions) -> Result<Plan, EvalError> {
        let graph = crate::bump::expand(graph);
        Compiler::new(&graph).compile(options)
    }
    /// The outputs, in request order.
    pub fn outputs(&self) -> &[PlanOutput] {
        &self.outputs
    }
    /// The exposed parameters, in graph order.
    pub fn parameters(&self) -> &[PlanParameter] {
        &self.parameters
    }
    /// Per-sample attributes the varying program reads.
    pub fn attributes(&self) -> &[Attribute] {
        &self.attributes
    }
    /// Keys of the textures the plan samples, in slot order: the keys the batch's texture
    /// set must hold (see [`crate::document::TextureSource::key`]).
    pub fn textures(&self) -> &[String] {
        &self.textures
    }
    /// Whether the plan reads `time`.
    pub fn uses_time(&self) -> bool {
        self.time_slot.is_some()
    }
    /// What the compiler kept, folded and hoisted.
    pub fn stats(&self) -> PlanStats {
        self.stats
    }
    /// Whether graph node `i` reaches a requested output.
    pub fn is_live(&self, i: NodeIndex) -> bool {
        self.live.get(i).copied().unwrap_or(false)
    }
    /// The value of a node output that was folded into a constant.
    pub fn folded(&self, r: OutputRef) -> Option<Value> {
        match self.node_operands.get(&r) {
            Some(Operand::Const(v)) => Some(*v),
            _ => None,
        }
    }
    /// A readable listing of the compiled program: uniform steps, per-sample steps, outputs.
    pub fn listing(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(s, "{:?}", self.stats);
        let _ = writeln!(s, "uniform program (once per evaluation):");
        for step in &self.uniform_steps {
            let _ = writeln!(
                s,
                "  u{:?} <- {}(u{:?})",
                step.outputs, step.label, step.inputs
            );
        }
        let _ = writeln!(s, "per-sample program (once per tile of {TILE}):");
        for step in &self.steps {
            let _ = writeln!(
                s,
                "  r{:?} <- {}(r{:?})",
                step.outputs, step.label, step.inputs
            );
        }
        for o in &self.outputs {
            let _ = writeln!(s, "output {} ({}) = {:?}", o.name, o.ty, o.operand);
        }
        s
    }

    /// The parameter values from the graph file, ready to be overridden.
    pub fn default_parameters(&self) -> ParamValues {
        ParamValues {
            names: self.parameters.iter().map(|p| p.name.clone()).collect(),
            values: self.parameters.iter().map(|p| p.default).collect(),
            guards: Some(self.guards.clone()),
        }
    }
}

/// Parameter values for one evaluation, in the plan's parameter order.
#[derive(Clone, Default)]
pub struct ParamValues {
    names: Vec<String>,
    values: Vec<Value>,
    /// The plan's range guards (not part of equality).
    guards: Option<Arc<Guards>>,
}

/// The hard-range guards of a plan: inputs whose value is computed from parameters and
/// constants alone (a parameter's output linked directly, or through nodes hoisted into the
/// uniform program), with the uniform program that computes them. A parameter *feeds* such
/// an input when the input's value depends on it; every value set for the parameter is
/// refused if it would put a fed input outside its hard range. Inputs that also depend on
/// per-sample values (geometry, textures) or on time are not guarded.
pub(crate) struct Guards {
    init: Vec<Value>,
    steps: Vec<Step>,
    /// Uniform slot of each plan parameter (plan order).
    param_slots: Vec<Option<u32>>,
    /// Graph node of each plan parameter (plan order).
    param_nodes: Vec<NodeIndex>,
    /// The range of each plan parameter (plan order), from the file.
    ranges: Vec<Option<crate::node::Range>>,
    guards: Vec<Guard>,
}

/// One guarded input.
#[derive(Clone, Debug)]
pub(crate) struct Guard {
    /// The uniform slot holding the input's value.
    slot: u32,
    /// The node whose input it is.
    node: String,
    /// The input.
    input: &'static str,
    /// Its hard range.
    range: crate::node::Range,
    /// The `parameter` nodes the value depends on.
    params: Vec<NodeIndex>,
}

impl Guards {
    /// Runs the uniform program for `values` (plan order) and returns the first guard that
    /// fails among those depending on parameter node `only` (or on any, when `None`), with
    /// the value that reached it.
    fn first_violation(
        &self,
        values: &[Value],
        only: Option<NodeIndex>,
    ) -> Option<(&Guard, Value)> {
        let relevant = |g: &&Guard| only.is_none_or(|p| g.params.contains(&p));
        if !self.guards.iter().any(|g| relevant(&g)) {
            return None;
        }
        let mut slots = self.init.clone();
        for (slot, v) in self.param_slots.iter().zip(values) {
            if let Some(s) = slot {
                slots[*s as usize] = *v;
            }
        }
        run_uniform_steps(&self.steps, &mut slots);
        self.guards
            .iter()
            .filter(relevant)
            .find(|g| !g.range.contains(&slots[g.slot as usize]))
            .map(|g| (g, slots[g.slot as usize]))
    }
}

impl std::fmt::Debug for ParamValues {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ParamValues")
            .field("names", &self.names)
            .field("values", &self.values)
            .finish_non_exhaustive()
    }
}

impl PartialEq for ParamValues {
    fn eq(&self, other: &ParamValues) -> bool {
        self.names == other.names && self.values == other.values
    }
}

/// Runs uniform steps over `slots` in order.
pub(crate) fn run_uniform_steps(steps: &[Step], slots: &mut [Value]) {
    for step in steps {
        let ins: Vec<Value> = step.inputs.iter().map(|&s| slots[s as usize]).collect();
        let types: Vec<SocketType> = step
            .outputs
            .iter()
            .map(|&s| slots[s as usize].ty())
            .collect();
        let Some(k) = step.kernel.kernel() else {
            continue; // uniform steps are never texture steps
        };
        for (&s, v) in step.outputs.iter().zip(run_single(k, &ins, &types)) {
            slots[s as usize] = v;
        }
    }
}

impl ParamValues {
    /// Sets parameter `name`; a float is broadcast to a vector parameter. A value outside
    /// the hard range of an input the parameter feeds is refused (the value is unchanged).
    pub fn set(&mut self, name: &str, value: Value) -> Result<(), EvalError> {
        let Some(i) = self.names.iter().position(|n| n == name) else {
            return Err(EvalError::UnknownParameter {
                name: name.to_owned(),
                suggestion: nearest(name, self.names.iter().map(String::as_str)).map(str::to_owned),
            });
        };
        let ty = self.values[i].ty();
        let v = value.convert(ty).ok_or(EvalError::ParameterType {
            name: name.to_owned(),
            expected: ty,
            found: value.ty(),
        })?;
        if let Some(guards) = &self.guards {
            let mut values = self.values.clone();
            values[i] = v;
            if let Some((g, seen)) = guards.first_violation(&values, Some(guards.param_nodes[i])) {
                return Err(EvalError::ParameterOutOfRange {
                    name: name.to_owned(),
                    node: g.node.clone(),
                    input: g.input.to_owned(),
                    value: seen.to_string(),
                    min: g.range.min,
                    max: g.range.max,
                });
            }
            // The parameter's own range after the inputs it feeds, whose refusal says more.
            if let Some(r) = guards.ranges[i]
                && !r.contains(&v)
            {
                return Err(EvalError::ParameterOutsideItsRange {
                    name: name.to_owned(),
                    value: v.to_string(),
                    min: r.min,
                    max: r.max,
                });
            }
        }
        self.values[i] = v;
        Ok(())
    }
    /// The value of parameter `name`.
    pub fn get(&self, name: &str) -> Option<Value> {
        self.names
            .iter()
            .position(|n| n == name)
            .map(|i| self.values[i])
    }
    /// All values, in plan order.
    pub fn values(&self) -> &[Value] {
        &self.values
    }
}

/// Runs a kernel on one sample of uniform values.
pub(crate) fn run_single(
    k: &dyn TileKernel,
    inputs: &[Value],
    out_types: &[SocketType],
) -> Vec<Value> {
    let ins: Vec<[f32; 4]> = inputs.iter().map(|v| v.raw()).collect();
    let in_refs: Vec<&[f32]> = ins.iter().map(|a| &a[..]).collect();
    let mut outs: Vec<[f32; 4]> = vec![[0.0; 4]; out_types.len()];
    let mut out_refs: Vec<&mut [f32]> = outs.iter_mut().map(|a| &mut a[..]).collect();
    k.run(&in_refs, &mut out_refs, 1, 1);
    outs.iter()
        .zip(out_types)
        .map(|(o, &t)| Value::from_lanes(t, o))
        .collect()
}

struct Compiler<'g> {
    graph: &'g Graph,
    operands: HashMap<OutputRef, Operand>,
    uniform_init: Vec<Value>,
    uniform_steps: Vec<Step>,
    time_slot: Option<u32>,
    registers: Vec<Register>,
    steps: Vec<Step>,
    attribute_regs: HashMap<Attribute, u32>,
    broadcast_regs: HashMap<(u32, SocketType), u32>,
    converted: HashMap<(u32, bool, SocketType), u32>,
    param_slots: HashMap<NodeIndex, u32>,
    const_regs: HashMap<(SocketType, [u32; 4]), u32>,
    textures: Vec<String>,
    texture_slots: HashMap<String, usize>,
    /// The `parameter` nodes each uniform slot depends on; [`TIME`] marks time.
    uniform_deps: HashMap<u32, Vec<NodeIndex>>,
    guards: Vec<Guard>,
    read: std::collections::HashSet<OutputRef>,
    stats: PlanStats,
}

impl<'g> Compiler<'g> {
    fn new(graph: &'g Graph) -> Compiler<'g> {
        Compiler {
            graph,
            operands: HashMap::new(),
            uniform_init: Vec::new(),
            uniform_steps: Vec::new(),
            time_slot: None,
            registers: Vec::new(),
            steps: Vec::new(),
            attribute_regs: HashMap::new(),
            broadcast_regs: HashMap::new(),
            converted: HashMap::new(),
            param_slots: HashMap::new(),
            const_regs: HashMap::new(),
            textures: Vec::new(),
            texture_slots: HashMap::new(),
            uniform_deps: HashMap::new(),
            guards: Vec::new(),
            read: Default::default(),
            stats: PlanStats {
                graph_nodes: graph.nodes().len(),
                ..PlanStats::default()
            },
        }
    }

    fn compile(mut self, options: &PlanOptions) -> Result<Plan, EvalError> {
        let wanted = self.requested(options)?;
        let live = self.live(&wanted);
        self.stats.live_nodes = live.iter().filter(|&&l| l).count();

        // Outputs read by a live node or requested: unread attribute outputs get no register.
        for &i in self.graph.order() {
            if live[i] {
                for src in self.graph.nodes()[i].used_inputs() {
                    if let InputSource::Link(r, _) = src {
                        self.read.insert(*r);
                    }
                }
            }
        }
        self.read.extend(wanted.iter().map(|(_, r)| *r));
        for &i in self.graph.order() {
            if live[i] {
                self.node(i, options.bake_parameters);
            }
        }

        let mut outputs = wanted
            .iter()
            .map(|(name, r)| PlanOutput {
                name: name.clone(),
                ty: self.graph.output_type(*r),
                operand: self.operands[r],
            })
            .collect::<Vec<_>>();
        let parameters: Vec<PlanParameter> = self
            .graph
            .parameters()
            .iter()
            .map(|p| PlanParameter {
                name: p.name.clone(),
                ty: p.ty,
                default: p.default,
                slot: self.param_slots.get(&p.node).copied(),
                range: p.range,
            })
            .collect();
        self.allocate(&mut outputs);
        let guards = Arc::new(Guards {
            init: self.uniform_init.clone(),
            steps: self.uniform_steps.clone(),
            param_slots: parameters.iter().map(|p: &PlanParameter| p.slot).collect(),
            param_nodes: self.graph.parameters().iter().map(|p| p.node).collect(),
            ranges: parameters.iter().map(|p: &PlanParameter| p.range).collect(),
            guards: std::mem::take(&mut self.guards),
        });
        // The file's values must respect the guards too.
        let defaults: Vec<Value> = parameters
            .iter()
            .map(|p: &PlanParameter| p.default)
            .collect();
        if let Some((g, seen)) = guards.first_violation(&defaults, None) {
            let node = g.params[0];
            let name = self
                .graph
                .parameters()
                .iter()
                .find(|p| p.node == node)
                .map_or_else(|| self.graph.nodes()[node].id.clone(), |p| p.name.clone());
            return Err(EvalError::ParameterOutOfRange {
                name,
                node: g.node.clone(),
                input: g.input.to_owned(),
                value: seen.to_string(),
                min: g.range.min,
                max: g.range.max,
            });
        }
        let mut attributes: Vec<Attribute> = self.attribute_regs.keys().copied().collect();
        attributes.sort();
        self.stats.per_sample_steps = self.steps.len();
        self.stats.registers = self.registers.len();
        Ok(Plan {
            outputs,
            parameters,
            uniform_init: self.uniform_init,
            uniform_steps: self.uniform_steps,
            time_slot: self.time_slot,
            registers: self.registers,
            steps: self.steps,
            attributes,
            stats: self.stats,
            textures: self.textures,
            live,
            node_operands: self.operands,
            guards,
        })
    }

    /// The requested outputs, by the name they were asked by.
    fn requested(&self, options: &PlanOptions) -> Result<Vec<(String, OutputRef)>, EvalError> {
        let g = self.graph;
        if options.outputs.is_empty() {
            if g.outputs().is_empty() {
                return Err(EvalError::NoOutputs);
            }
            return Ok(g
                .outputs()
                .iter()
                .map(|o| (o.name.clone(), o.source))
                .collect());
        }
        options
            .outputs
            .iter()
            .map(|name| {
                let r = g
                    .outputs()
                    .iter()
                    .find(|o| &o.name == name)
                    .map(|o| o.source)
                    .or_else(|| g.output_ref(name));
                r.map(|r| (name.clone(), r)).ok_or_else(|| {
                    let mut candidates: Vec<String> =
                        g.outputs().iter().map(|o| o.name.clone()).collect();
                    for n in g.nodes() {
                        for o in n.node_type.outputs() {
                            candidates.push(format!("{}.{}", n.id, o.name));
                        }
                    }
                    EvalError::UnknownOutput {
                        name: name.clone(),
                        suggestion: nearest(name, candidates.iter().map(String::as_str))
                            .map(str::to_owned),
                    }
                })
            })
            .collect()
    }

    /// Marks the nodes that reach a requested output.
    fn live(&self, wanted: &[(String, OutputRef)]) -> Vec<bool> {
        let mut live = vec![false; self.graph.nodes().len()];
        let mut stack: Vec<NodeIndex> = wanted.iter().map(|(_, r)| r.node).collect();
        while let Some(i) = stack.pop() {
            if std::mem::replace(&mut live[i], true) {
                continue;
            }
            for src in self.graph.nodes()[i].used_inputs() {
                if let InputSource::Link(r, _) = src {
                    stack.push(r.node);
                }
            }
        }
        live
    }

    fn new_uniform(&mut self, init: Value) -> u32 {
        self.uniform_init.push(init);
        (self.uniform_init.len() - 1) as u32
    }

    fn new_register(&mut self, width: usize, fill: RegFill) -> u32 {
        self.registers.push(Register { width, fill });
        (self.registers.len() - 1) as u32
    }

    /// Compiles node `i`, recording its outputs' operands.
    fn node(&mut self, i: NodeIndex, bake: bool) {
        let node = &self.graph.nodes()[i];
        let t = node.node_type.clone();
        let out_types: Vec<SocketType> = (0..t.outputs().len())
            .map(|k| node.output_type(k))
            .collect();
        let set = |c: &mut Self, k: usize, op: Operand| {
            c.operands.insert(OutputRef { node: i, output: k }, op);
        };
        if node.forwards() {
            // A reroute or a muted node: each output is its passed input's operand (after
            // the input's own conversion), or its type's zero. No step.
            for (k, &ty) in out_types.iter().enumerate() {
                let op = match node.passthrough(k).map(|j| (j, &node.inputs[j])) {
                    Some((_, InputSource::Default(v) | InputSource::Value { value: v, .. })) => {
                        Operand::Const(*v)
                    }
                    Some((j, InputSource::Link(r, c))) => {
                        self.convert(self.operands[r], *c, node.input_type(j))
                    }
                    None => Operand::Const(Value::zero(ty)),
                };
                set(self, k, op);
            }
            return;
        }
        match t.evaluation() {
            Evaluation::Attributes(attrs) => {
                for (k, &a) in attrs.iter().enumerate() {
                    if !self.read.contains(&OutputRef { node: i, output: k }) {
                        continue;
                    }
                    let op = if a.is_uniform() {
                        let slot = match self.time_slot {
                            Some(s) => s,
                            None => {
                                let s = self.new_uniform(a.default_value());
                                self.time_slot = Some(s);
                                self.uniform_deps.insert(s, vec![TIME]);
                                s
                            }
                        };
                        Operand::Uniform(slot)
                    } else {
                        let reg = match self.attribute_regs.get(&a) {
                            Some(&r) => r,
                            None => {
                                let r = self.new_register(a.ty().width(), RegFill::Attribute(a));
                                self.attribute_regs.insert(a, r);
                                r
                            }
                        };
                        Operand::Reg(reg)
                    };
                    set(self, k, op);
                }
                return;
            }
            Evaluation::Parameter if !bake => {
                // The file's value until a caller overrides an exposed parameter.
                let init = match node.inputs[0] {
                    InputSource::Default(v) | InputSource::Value { value: v, .. } => v,
                    InputSource::Link(..) => Value::zero(out_types[0]),
                };
                let slot = self.new_uniform(init);
                self.param_slots.insert(i, slot);
                self.uniform_deps.insert(slot, vec![i]);
                set(self, 0, Operand::Uniform(slot));
                return;
            }
            _ => {}
        }

        // Input operands, converted to the ports' types.
        let mut ins = Vec::with_capacity(node.inputs.len());
        for (k, src) in node.inputs.iter().enumerate() {
            let to = node.input_type(k);
            let op = match src {
                InputSource::Default(v) | InputSource::Value { value: v, .. } => Operand::Const(*v),
                InputSource::Link(r, c) => self.convert(self.operands[r], *c, to),
            };
            ins.push(op);
        }
        for (k, op) in ins.iter().enumerate() {
            if let (Operand::Uniform(slot), Some(range)) = (op, t.inputs()[k].hard) {
                let params = self.deps(*slot);
                if !params.is_empty() && !params.contains(&TIME) {
                    self.guards.push(Guard {
                        slot: *slot,
                        node: node.id.clone(),
                        input: t.inputs()[k].name,
                        range,
                        params,
                    });
                }
            }
        }
        let variant = t.variants().iter().position(|v| match v.generic {
            None => true,
            Some(g) => {
                g == if node.generic == SocketType::Color {
                    SocketType::Vec3
                } else {
                    node.generic
                }
            }
        });
        let is_texture = t.evaluation() == Evaluation::Texture;
        let kref = if is_texture {
            let key = node.texture_key().unwrap_or_default();
            let slot = match self.texture_slots.get(&key) {
                Some(&k) => k,
                None => {
                    self.texture_slots.insert(key.clone(), self.textures.len());
                    self.textures.push(key);
                    self.textures.len() - 1
                }
            };
            KernelRef::Texture(slot, t.texture_kernel_fn())
        } else {
            let Some(variant) = variant else { return };
            KernelRef::Node(t.clone(), variant)
        };

        if !is_texture && ins.iter().all(|o| matches!(o, Operand::Const(_))) {
            // Fold.
            let values: Vec<Value> = ins
                .iter()
                .map(|o| {
                    if let Operand::Const(v) = o {
                        *v
                    } else {
                        unreachable!()
                    }
                })
                .collect();
            for (k, v) in run_single(
                kref.kernel().expect("compute nodes have kernels"),
                &values,
                &out_types,
            )
            .into_iter()
            .enumerate()
            {
                set(self, k, Operand::Const(v));
            }
            self.stats.folded += 1;
        } else if !is_texture && ins.iter().all(|o| !matches!(o, Operand::Reg(_))) {
            // Hoist.
            let inputs: Vec<u32> = ins.iter().map(|o| self.uniform_slot(*o)).collect();
            let mut deps: Vec<NodeIndex> = inputs.iter().flat_map(|&s| self.deps(s)).collect();
            deps.sort_unstable();
            deps.dedup();
            let outputs: Vec<u32> = out_types
                .iter()
                .map(|&t| self.new_uniform(Value::zero(t)))
                .collect();
            for &s in &outputs {
                self.uniform_deps.insert(s, deps.clone());
            }
            for (k, &s) in outputs.iter().enumerate() {
                set(self, k, Operand::Uniform(s));
            }
            self.uniform_steps.push(Step {
                kernel: kref,
                inputs,
                outputs,
                label: format!("{} ({})", node.id, t.name()),
            });
            self.stats.hoisted += 1;
        } else {
            let inputs = ins
                .iter()
                .zip(0..)
                .map(|(o, k)| self.register(*o, node.input_type(k)))
                .collect();
            let outputs: Vec<u32> = out_types
                .iter()
                .map(|t| self.new_register(t.width(), RegFill::Computed))
                .collect();
            for (k, &r) in outputs.iter().enumerate() {
                set(self, k, Operand::Reg(r));
            }
            self.steps.push(Step {
                kernel: kref,
                inputs,
                outputs,
                label: format!("{} ({})", node.id, t.name()),
            });
        }
    }

    /// Applies a link conversion to an operand.
    fn convert(&mut self, op: Operand, c: Conversion, to: SocketType) -> Operand {
        let Some(k) = conversion_kernel(c, to) else {
            return op;
        };
        match op {
            Operand::Const(v) => Operand::Const(Value::from_lanes(to, &c.apply(v.raw(), to))),
            Operand::Uniform(s) => {
                let out = self.new_uniform(Value::zero(to));
                let deps = self.deps(s);
                self.uniform_deps.insert(out, deps);
                self.uniform_steps.push(Step {
                    kernel: KernelRef::Convert(k),
                    inputs: vec![s],
                    outputs: vec![out],
                    label: conversion_label(c, to),
                });
                Operand::Uniform(out)
            }
            Operand::Reg(r) => {
                let key = (r, c == Conversion::Luminance, to);
                if let Some(&out) = self.converted.get(&key) {
                    return Operand::Reg(out);
                }
                let out = self.new_register(to.width(), RegFill::Computed);
                self.steps.push(Step {
                    kernel: KernelRef::Convert(k),
                    inputs: vec![r],
                    outputs: vec![out],
                    label: conversion_label(c, to),
                });
                self.converted.insert(key, out);
                Operand::Reg(out)
            }
        }
    }

    /// The `parameter` nodes (and [`TIME`]) uniform slot `s` depends on.
    fn deps(&self, s: u32) -> Vec<NodeIndex> {
        self.uniform_deps.get(&s).cloned().unwrap_or_default()
    }

    /// A uniform slot holding `op` (constants get a slot of their own).
    fn uniform_slot(&mut self, op: Operand) -> u32 {
        match op {
            Operand::Uniform(s) => s,
            Operand::Const(v) => self.new_uniform(v),
            Operand::Reg(_) => unreachable!("uniform steps never read registers"),
        }
    }

    /// A register holding `op` of type `ty` (constants and uniforms are broadcast once).
    fn register(&mut self, op: Operand, ty: SocketType) -> u32 {
        match op {
            Operand::Reg(r) => r,
            Operand::Const(v) => {
                let key = (ty, v.raw().map(f32::to_bits));
                match self.const_regs.get(&key) {
                    Some(&r) => r,
                    None => {
                        let r = self.new_register(ty.width(), RegFill::Const(v));
                        self.const_regs.insert(key, r);
                        r
                    }
                }
            }
            Operand::Uniform(s) => match self.broadcast_regs.get(&(s, ty)) {
                Some(&r) => r,
                None => {
                    let r = self.new_register(ty.width(), RegFill::Uniform(s));
                    self.broadcast_regs.insert((s, ty), r);
                    r
                }
            },
        }
    }

    /// Reuses computed registers once their last reader has run.
    fn allocate(&mut self, outputs: &mut [PlanOutput]) {
        let n = self.registers.len();
        let mut last_use = vec![usize::MAX; n]; // MAX: never freed
        let mut pinned: Vec<bool> = (0..n)
            .map(|r| self.registers[r].fill != RegFill::Computed)
            .collect();
        for o in outputs.iter() {
            if let Operand::Reg(r) = o.operand {
                pinned[r as usize] = true;
            }
        }
        for (s, step) in self.steps.iter().enumerate() {
            for &r in step.inputs.iter().chain(&step.outputs) {
                if !pinned[r as usize] {
                    last_use[r as usize] = s;
                }
            }
        }
        let mut map: Vec<u32> = vec![u32::MAX; n];
        let mut physical: Vec<Register> = Vec::new();
        let mut free: [Vec<u32>; 5] = Default::default();
        let mut is_free: Vec<bool> = Vec::new(); // by physical register
        for r in 0..n {
            if pinned[r] {
                map[r] = physical.len() as u32;
                physical.push(self.registers[r]);
            }
        }
        for s in 0..self.steps.len() {
            for k in 0..self.steps[s].outputs.len() {
                let r = self.steps[s].outputs[k] as usize;
                if map[r] == u32::MAX {
                    let w = self.registers[r].width;
                    map[r] = match free[w].pop() {
                        Some(p) => {
                            is_free[p as usize] = false;
                            p
                        }
                        None => {
                            physical.push(Register {
                                width: w,
                                fill: RegFill::Computed,
                            });
                            (physical.len() - 1) as u32
                        }
                    };
                    is_free.resize(physical.len(), false);
                }
            }
            let step = &self.steps[s];
            for &r in step.inputs.iter().chain(&step.outputs) {
                if last_use[r as usize] == s {
                    let p = map[r as usize];
                    if !is_free[p as usize] {
                        is_free[p as usize] = true;
                        free[self.registers[r as usize].width].push(p);
                    }
                }
            }
        }
        for step in &mut self.steps {
            for r in step.inputs.iter_mut().chain(step.outputs.iter_mut()) {
                *r = map[*r as usize];
            }
        }
        for o in outputs.iter_mut() {
            if let Operand::Reg(r) = &mut o.operand {
                *r = map[*r as usize];
            }
        }
        self.registers = physical;
    }
}
