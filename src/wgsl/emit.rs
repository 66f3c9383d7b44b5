//! WGSL text generation for a planned graph.

use super::{
    Binding, Entry, GEOMETRY_BINDING, OUTPUT_BINDING, ShaderError, ShaderOutput, WORKGROUP_SIZE,
    WgslOptions, wgsl_type,
};
use crate::graph::{Graph, InputSource, Node, NodeIndex, OutputRef};
use crate::node::{Attribute, Evaluation, NodeType, WgslChoice, WgslTable};
use crate::plan::Plan;
use crate::types::{LUMA_709, SocketType};
use crate::value::Value;
use std::collections::{BTreeMap, HashMap, HashSet};
use std::fmt::Write;
use std::ops::Range;

mod chains;

/// A uniform member the emitter declared in `MgParams`.
#[derive(Clone, Debug)]
pub(super) struct UniformSpec {
    /// WGSL member name.
    pub(super) field: String,
    /// Where its value comes from.
    pub(super) source: super::UniformSource,
    /// Its socket type.
    pub(super) ty: SocketType,
    /// Its value from the file (parameters not exposed keep it).
    pub(super) default: Value,
}

impl UniformSpec {
    /// The member holding node table `t`, under its fixed name.
    pub(super) fn table(t: &'static crate::node::WgslTable) -> UniformSpec {
        UniformSpec {
            field: t.field.to_owned(),
            source: super::UniformSource::Table(t.rows),
            ty: SocketType::Vec4,
            default: Value::zero(SocketType::Vec4),
        }
    }
}

/// `struct MgParams` with `fields`, and `mg_params` bound at `binding` of group 0.
pub(super) fn params_block(fields: &[UniformSpec], binding: u32) -> String {
    let mut out = String::from("struct MgParams {\n");
    for f in fields {
        let ty = super::layout::member_type(&f.source, f.ty);
        let _ = writeln!(out, "    {}: {ty},", f.field);
    }
    let _ = writeln!(
        out,
        "}}\n\n@group(0) @binding({binding}) var<uniform> mg_params: MgParams;\n"
    );
    out
}

/// What the emitter produced.
pub(super) struct Text {
    pub(super) source: String,
    pub(super) spans: Vec<(Range<usize>, String)>,
    pub(super) bindings: Vec<(u32, Binding)>,
    pub(super) attributes: Vec<Attribute>,
    pub(super) outputs: Vec<ShaderOutput>,
    pub(super) uniform_fields: Vec<UniformSpec>,
    pub(super) textures: Vec<String>,
}

/// Names that WGSL reserves or predeclares and that a port or parameter might be called.
const RESERVED: &[&str] = &[
    "alias",
    "array",
    "atomic",
    "bool",
    "break",
    "case",
    "const",
    "const_assert",
    "continue",
    "continuing",
    "default",
    "diagnostic",
    "discard",
    "else",
    "enable",
    "f16",
    "f32",
    "false",
    "fn",
    "for",
    "i32",
    "if",
    "let",
    "loop",
    "mat2x2",
    "mat3x3",
    "mat4x4",
    "override",
    "ptr",
    "requires",
    "return",
    "sampler",
    "struct",
    "switch",
    "true",
    "u32",
    "var",
    "vec2",
    "vec3",
    "vec4",
    "while",
    "self",
    "target",
    "mod",
    "type",
    "in",
    "out",
];

/// A WGSL identifier for `name`, valid whatever the name: non-ASCII-alphanumerics become
/// `_`; a name that is then empty, `_`, starts with a digit or with `__` gets a `p_` prefix;
/// a WGSL keyword or reserved word (naga's list, and the predeclared names above) gets a
/// `_` suffix. Different names may give the same identifier: callers make them unique.
pub(super) fn ident(name: &str) -> String {
    let mut s: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if s.is_empty()
        || s == "_"
        || s.starts_with(|c: char| c.is_ascii_digit())
        || s.starts_with("__")
    {
        s.insert_str(0, "p_");
    }
    if RESERVED.contains(&s.as_str()) || naga::keywords::wgsl::RESERVED.contains(&s.as_str()) {
        s.push('_');
    }
    s
}

/// A WGSL float literal of `x` that reads back as exactly `x` and stays in f32's range.
///
/// WGSL reads an unsuffixed literal as an abstract float (an f64) and converts it to f32 where
/// it is used, and Tint rejects a value outside f32's finite range. Rust's shortest f32
/// decimal is used when that reading gives back `x`'s bits; it does not for ±f32::MAX
/// (`3.4028235e38` exceeds f32::MAX as an f64), and then the shortest f64 decimal of `x`,
/// which converts to f32 exactly, is printed instead. WGSL has no literal for infinity or NaN,
/// and a constant `bitcast<f32>(0x7f800000u)` is rejected by Tint's constant evaluator ("value
/// inf cannot be represented as 'f32'"): a non-finite `x` is a call of the helper
/// [`NON_FINITE_WGSL`], whose bitcast of its argument is evaluated at run time, which naga and
/// Tint both accept. The emitter appends the helper to modules that call it.
pub(super) fn float_literal(x: f32) -> String {
    if !x.is_finite() {
        return format!("{NON_FINITE_FN}({:#010x}u)", x.to_bits());
    }
    let short = format!("{x:?}");
    match short.parse::<f64>() {
        Ok(d) if d.abs() <= f64::from(f32::MAX) && (d as f32).to_bits() == x.to_bits() => short,
        _ => format!("{:?}", f64::from(x)),
    }
}

/// The name of the helper that makes a non-finite f32 from its bits.
const NON_FINITE_FN: &str = "mg_non_finite";

/// The helper of non-finite constants: a user function is never evaluated as a constant
/// expression, so its bitcast happens at run time.
pub(super) const NON_FINITE_WGSL: &str =
    "fn mg_non_finite(bits: u32) -> f32 { return bitcast<f32>(bits); }\n";

/// A WGSL literal of a value.
pub(super) fn literal(v: &Value) -> String {
    match v.ty() {
        SocketType::Float => float_literal(v.as_f32()),
        SocketType::Int => format!("{}i", v.as_i32()),
        SocketType::Bool => v.as_bool().to_string(),
        t => {
            let parts: Vec<String> = v.lanes().iter().map(|&x| float_literal(x)).collect();
            format!("{}({})", wgsl_type(t), parts.join(", "))
        }
    }
}

#[cfg(test)]
mod constant_tests;
#[cfg(test)]
mod literal_tests;

/// `e` of type `from` converted to `to` along a link (the table of [`crate::types`]).
pub(super) fn convert(e: &str, from: SocketType, to: SocketType) -> String {
    use SocketType::*;
    let scalar = match from {
        Int => format!("f32({e})"),
        Bool => format!("select(0.0, 1.0, {e})"),
        _ => e.to_owned(),
    };
    match (from, to) {
        _ if from == to => e.to_owned(),
        (Vec3, Color) | (Color, Vec3) => e.to_owned(),
        (Float | Int | Bool, Float) => scalar,
        (Float | Int | Bool, _) => format!("{}({scalar})", wgsl_type(to)),
        (Color, Float) => {
            let [r, g, b] = LUMA_709.map(float_literal);
            format!("dot({e}, vec3<f32>({r}, {g}, {b}))")
        }
        (Vec2, Vec3 | Color) => format!("vec3<f32>({e}, 0.0)"),
        (Vec3 | Color, Vec2) => format!("({e}).xy"),
        _ => e.to_owned(),
    }
}

/// The suffix of a generic variant's function name.
fn type_suffix(t: SocketType) -> &'static str {
    match t {
        SocketType::Float => "f32",
        SocketType::Vec2 => "v2",
        SocketType::Vec3 | SocketType::Color => "v3",
        SocketType::Vec4 => "v4",
        SocketType::Int => "i32",
        SocketType::Bool => "bool",
    }
}

/// The WGSL function of a node type for generic type `generic`: its mangled name, the
/// output struct name when it has several outputs, and its definition text.
pub(super) struct NodeFunction {
    pub(super) name: String,
    pub(super) out_struct: Option<String>,
    pub(super) definition: String,
}

/// Member name of output `k` in a node's output struct.
pub(super) fn output_member(t: &NodeType, k: usize) -> String {
    ident(t.outputs()[k].name)
}

/// The emitted name of `t`'s function for generic type `generic` (colour shares vec3's).
pub(super) fn function_name(t: &NodeType, generic: SocketType) -> String {
    if t.is_generic() {
        format!("mg_{}_{}", t.name(), type_suffix(generic))
    } else {
        format!("mg_{}", t.name())
    }
}

/// The per-choice WGSL of `n`: its type's [`WgslChoice`] for the value its choice input is
/// written with (none where that input is linked).
pub(super) fn literal_choice(n: &Node) -> Option<&WgslChoice> {
    let t = &n.node_type;
    let k = t.input_index(t.wgsl_choices()?.input)?;
    match &n.inputs[k] {
        InputSource::Default(v) | InputSource::Value { value: v, .. } => t.wgsl_choice_at(*v),
        InputSource::Link(..) => None,
    }
}

/// The inputs of `n` compiled into its function as constants (see
/// [`NodeType::wgsl_constant_inputs`]): each such input the file writes, by index, with its
/// value, in input order.
pub(super) fn literal_constants(n: &Node) -> Vec<(usize, Value)> {
    let t = &n.node_type;
    let mut out: Vec<(usize, Value)> = t
        .wgsl_constants()
        .iter()
        .filter_map(|name| {
            let k = t.input_index(name)?;
            match &n.inputs[k] {
                InputSource::Default(v) | InputSource::Value { value: v, .. } => Some((k, *v)),
                InputSource::Link(..) => None,
            }
        })
        .collect();
    out.sort_by_key(|(k, _)| *k);
    out
}

/// What one emitted form of a node type's function fixes: the written choice of its
/// per-choice input and the values of its constant inputs.
#[derive(Clone, Copy, Default)]
pub(super) struct Form<'a> {
    /// The per-choice WGSL at the written choice ([`literal_choice`]).
    pub(super) choice: Option<&'a WgslChoice>,
    /// The constant inputs, by index ([`literal_constants`]).
    pub(super) constants: &'a [(usize, Value)],
}

/// The name part of a constant input's value: the choice's name, `true`/`false`, or the
/// integer (`m` for minus).
fn constant_suffix(t: &NodeType, k: usize, v: &Value) -> String {
    let decl = &t.inputs()[k];
    let value = match v.ty() {
        SocketType::Bool => v.as_bool().to_string(),
        _ => usize::try_from(v.as_i32())
            .ok()
            .and_then(|c| decl.choices.get(c))
            .map_or_else(
                || v.as_i32().to_string().replace('-', "m"),
                |c| c.to_string(),
            ),
    };
    // Inside a name that starts `mg_`: any ASCII letter, digit or `_` is an identifier's.
    let clean = |s: &str| -> String {
        s.chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() {
                    c.to_ascii_lowercase()
                } else {
                    '_'
                }
            })
            .collect()
    };
    format!("_{}_{}", clean(decl.name), clean(&value))
}

/// The emitted name of `t`'s function: [`function_name`], suffixed `_is_<choice>` for a
/// per-choice template and `_<input>_<value>` for each constant input.
fn emitted_name(t: &NodeType, generic: SocketType, form: Form) -> String {
    let mut name = function_name(t, generic);
    // A choice input that is also a constant input is named once, by its constant.
    let constant_choice = t.wgsl_choices().is_some_and(|cs| {
        form.constants
            .iter()
            .any(|(k, _)| t.inputs()[*k].name == cs.input)
    });
    if let Some(c) = form.choice.filter(|_| !constant_choice) {
        let _ = write!(name, "_is_{}", c.choice);
    }
    for (k, v) in form.constants {
        name.push_str(&constant_suffix(t, *k, v));
    }
    name
}

/// The emitted name of node `n`'s function, whose constant inputs are `constants`.
fn node_key(n: &Node, constants: &[(usize, Value)]) -> String {
    emitted_name(
        &n.node_type,
        n.generic,
        Form {
            choice: literal_choice(n),
            constants,
        },
    )
}

/// Builds the WGSL function of `t` for generic type `generic` from its template, at the
/// written choice of its choice input and with its written constant inputs when given.
/// `None` where `t` has no WGSL, or its template's signature cannot take the constants.
pub(super) fn node_function(t: &NodeType, generic: SocketType, form: Form) -> Option<NodeFunction> {
    let template = t.wgsl_for(generic)?;
    let name = emitted_name(t, generic, form);
    let mut definition = String::new();
    let out_struct = (t.outputs().len() > 1).then(|| format!("{name}_out"));
    if let Some(s) = &out_struct {
        let _ = writeln!(definition, "struct {s} {{");
        for (k, o) in t.outputs().iter().enumerate() {
            let _ = writeln!(
                definition,
                "    {}: {},",
                output_member(t, k),
                wgsl_type(o.ty.resolve(generic))
            );
        }
        let _ = writeln!(definition, "}}\n");
    }
    // `${input}` names a per-choice helper: `_<choice>` at a written choice, nothing where
    // the dispatch picks it (see `WgslChoices`).
    let mut template = template.trim().to_owned();
    if let Some(cs) = t.wgsl_choices() {
        let suffix = form
            .choice
            .map_or(String::new(), |c| format!("_{}", c.choice));
        template = template.replace(&format!("${{{}}}", cs.input), &suffix);
    }
    let mut body = template
        .replace("$fn", &name)
        .replace("$out", out_struct.as_deref().unwrap_or("$out"))
        .replace("$T", wgsl_type(generic));
    if !form.constants.is_empty() {
        body = constant_parameters(&body, &name, t.inputs().len(), form.constants)?;
    }
    definition.push_str(&body);
    definition.push('\n');
    Some(NodeFunction {
        name,
        out_struct,
        definition,
    })
}

/// `function` (the text of `fn name(…) -> … { … }`, whose last `inputs` parameters are the
/// node's inputs) with the parameters of `constants` removed and declared instead as
/// function-scope `const`s of their values at the top of its body. `None` where the
/// signature is not found or has fewer parameters than inputs.
fn constant_parameters(
    function: &str,
    name: &str,
    inputs: usize,
    constants: &[(usize, Value)],
) -> Option<String> {
    let head = format!("fn {name}(");
    let open = function.find(&head)? + head.len();
    // The parameter list up to its matching `)`, split at top-level commas (template
    // arguments such as `array<f32, 4>` hold commas of their own).
    let mut depth = 0i32;
    let mut close = None;
    let mut cuts = vec![open];
    for (k, c) in function[open..].char_indices() {
        match c {
            '(' | '<' => depth += 1,
            ')' if depth == 0 => {
                close = Some(open + k);
                break;
            }
            ')' | '>' => depth -= 1,
            ',' if depth == 0 => cuts.push(open + k + 1),
            _ => {}
        }
    }
    let close = close?;
    cuts.push(close + 1);
    let params: Vec<&str> = cuts
        .windows(2)
        .map(|w| function[w[0]..w[1] - 1].trim())
        .filter(|p| !p.is_empty())
        .collect();
    let first_input = params.len().checked_sub(inputs)?;
    let brace = close + function[close..].find('{')?;
    let mut kept: Vec<&str> = Vec::new();
    let mut consts = String::new();
    for (j, p) in params.iter().enumerate() {
        match constants.iter().find(|(k, _)| first_input + k == j) {
            Some((_, v)) => {
                let (pname, ty) = p.split_once(':')?;
                let _ = write!(
                    consts,
                    "\n    const {}: {} = {};",
                    pname.trim(),
                    ty.trim(),
                    literal(v)
                );
            }
            None => kept.push(p),
        }
    }
    Some(format!(
        "{}{}{}{{{}{}",
        &function[..open],
        kept.join(", "),
        &function[close..brace],
        consts,
        &function[brace + 1..]
    ))
}

/// The hard range of every exposed float-valued parameter that has one, by its node.
fn parameter_clamps(graph: &Graph) -> HashMap<NodeIndex, crate::node::Range> {
    graph
        .parameters()
        .iter()
        .zip(crate::parameter_info::parameter_info(graph))
        .filter(|(p, _)| !matches!(p.ty, SocketType::Int | SocketType::Bool))
        .filter_map(|(p, info)| Some((p.node, info.hard?)))
        .collect()
}

/// Emits the module of one planned graph.
pub(super) struct Emitter<'a> {
    graph: &'a Graph,
    plan: &'a Plan,
    entry: Entry,
    out: String,
    spans: Vec<(Range<usize>, String)>,
    /// WGSL expression of each live attribute and parameter output.
    exprs: BTreeMap<OutputRef, String>,
    /// The variable of each node that becomes a call, by node index.
    vars: Vec<Option<CallVar>>,
    /// Where the text being emitted is.
    context: Context,
    /// Slot of each texture key in the plan's texture list.
    texture_slots: HashMap<String, usize>,
    /// The group instances called as functions ([`super::groups`]).
    groups: super::groups::GroupPlan,
    /// Whether the material's functions take `geom` (the graph reads attributes).
    has_geom: bool,
    /// The runs of group calls written as loops, by their last call ([`chains`]).
    runs: HashMap<NodeIndex, chains::Run>,
    /// The hard range each exposed float-valued parameter's read is clamped to
    /// ([`super::ParameterClamp::HardRange`]), by parameter node.
    clamps: HashMap<NodeIndex, crate::node::Range>,
}

/// Above this many outputs `MgOutputs` holds them in chunk structs of this many
/// (`MgOutputs{k}`, its member `c{k}`), each built and stored by a function of its own
/// (issue 37): naga's WGSL front end resolves a function's expression types by
/// `Arena::iter().skip(done)`, which walks the ones done, and finds a struct member by a
/// linear search, so a function of E expressions and a struct of M members cost E² and M
/// per access. Bounded functions and structs keep `wgsl` linear in the outputs.
pub(super) const OUT_CHUNK: usize = 256;

/// Above this many node calls the material function is split into part functions.
pub(super) const SPLIT_CALLS: usize = 256;
/// Node calls per part function of a split material function.
pub(super) const PART_CALLS: usize = 64;
/// Calls per function in the tree of functions that run the parts in order.
pub(super) const PART_FANOUT: usize = 64;

/// The `let` a node's call result is bound to.
struct CallVar {
    /// The variable's name (also its member name in `MgState`).
    name: String,
    /// Index of the node's function in the emitted function list.
    function: usize,
    /// The part function the call is in (0 when the material function is not split).
    part: usize,
    /// For each output read outside its part: the `MgState` array and index it is kept at.
    slots: Vec<Option<(&'static str, usize)>>,
}

/// Where generated text is placed, which decides how a node's value is named.
#[derive(Clone, Copy, PartialEq)]
enum Context {
    /// The one-piece material function: every value is a local `let`.
    Whole,
    /// Part function `k`: its own values are `let`s, others are read through `s`.
    Part(usize),
    /// The split material function's return: values are read from the local `s`.
    Material,
}

impl<'a> Emitter<'a> {
    pub(super) fn new(graph: &'a Graph, plan: &'a Plan, options: &WgslOptions) -> Emitter<'a> {
        Emitter {
            graph,
            plan,
            entry: options.entry,
            out: String::new(),
            spans: Vec::new(),
            exprs: BTreeMap::new(),
            vars: Vec::new(),
            context: Context::Whole,
            texture_slots: plan
                .textures()
                .iter()
                .enumerate()
                .rev()
                .map(|(k, key)| (key.clone(), k))
                .collect(),
            groups: super::groups::GroupPlan::new(graph, plan),
            has_geom: false,
            runs: HashMap::new(),
            clamps: match options.clamp {
                super::ParameterClamp::None => HashMap::new(),
                super::ParameterClamp::HardRange => parameter_clamps(graph),
            },
        }
    }

    fn live_order(&self) -> Vec<NodeIndex> {
        self.graph
            .order()
            .iter()
            .copied()
            .filter(|&i| self.plan.is_live(i))
            .collect()
    }

    /// Whether every output of node `i` was folded into a constant.
    fn folded(&self, i: NodeIndex) -> bool {
        let n = &self.graph.nodes()[i];
        (0..n.node_type.outputs().len()).all(|k| {
            let r = OutputRef { node: i, output: k };
            self.plan.folded(r).is_some() || !self.plan.node_operands.contains_key(&r)
        })
    }

    pub(super) fn emit(mut self) -> Result<Text, ShaderError> {
        let order = self.live_order();
        let nodes = self.graph.nodes();

        // Uniforms: live unbaked parameters (exposed under their names), time, node tables.
        let mut uniform_fields: Vec<UniformSpec> = Vec::new();
        // Taken names, and for each base the next suffix to try (the ones before it are
        // taken), so that many colliding names stay linear.
        let mut taken: HashSet<String> = HashSet::new();
        let mut next_suffix: HashMap<String, usize> = HashMap::new();
        // Constant tables of the emitted node functions: their member names are fixed (the
        // helpers spell them), so they are taken before any parameter is named.
        let mut tables: Vec<&'static WgslTable> = Vec::new();
        for &i in &order {
            let n = &nodes[i];
            if self.is_call(i) || self.groups.body_calls.contains(&i) {
                for t in n.node_type.wgsl_tables_for(literal_choice(n)) {
                    if !tables.iter().any(|x| std::ptr::eq(*x, t)) {
                        tables.push(t);
                        taken.insert(t.field.to_owned());
                    }
                }
            }
        }
        let mut unique = |base: String| {
            let mut name = base.clone();
            let k = next_suffix.entry(base.clone()).or_insert(2);
            while taken.contains(&name) {
                name = format!("{base}_{k}");
                *k += 1;
            }
            taken.insert(name.clone());
            name
        };
        let exposed_by_node: HashMap<NodeIndex, &crate::graph::GraphParameter> = self
            .graph
            .parameters()
            .iter()
            .map(|p| (p.node, p))
            .collect();
        let mut attributes: Vec<Attribute> = Vec::new();
        let mut uses_time = false;
        for &i in &order {
            let n = &nodes[i];
            if n.forwards() {
                continue;
            }
            match n.node_type.evaluation() {
                Evaluation::Parameter if !self.folded(i) => {
                    let exposed = exposed_by_node.get(&i).copied();
                    let pname = exposed
                        .map(|p| p.name.clone())
                        .unwrap_or_else(|| n.id.clone());
                    let field = unique(ident(&pname));
                    let default = match &n.inputs[0] {
                        InputSource::Default(v) | InputSource::Value { value: v, .. } => *v,
                        InputSource::Link(..) => Value::zero(n.output_type(0)),
                    };
                    let access = match (n.output_type(0), self.clamps.get(&i)) {
                        (SocketType::Bool, _) => format!("(mg_params.{field} != 0u)"),
                        (SocketType::Int, _) | (_, None) => format!("mg_params.{field}"),
                        (SocketType::Float, Some(r)) => format!(
                            "clamp(mg_params.{field}, {}, {})",
                            float_literal(r.min),
                            float_literal(r.max)
                        ),
                        (t, Some(r)) => {
                            let ty = wgsl_type(t);
                            format!(
                                "clamp(mg_params.{field}, {ty}({}), {ty}({}))",
                                float_literal(r.min),
                                float_literal(r.max)
                            )
                        }
                    };
                    self.exprs.insert(OutputRef { node: i, output: 0 }, access);
                    uniform_fields.push(UniformSpec {
                        field,
                        source: match exposed {
                            Some(p) => super::UniformSource::Parameter(p.name.clone()),
                            None => super::UniformSource::Fixed,
                        },
                        ty: n.output_type(0),
                        default,
                    });
                }
                Evaluation::Attributes(attrs) => {
                    for (k, &a) in attrs.iter().enumerate() {
                        let r = OutputRef { node: i, output: k };
                        if !self.plan.node_operands.contains_key(&r) {
                            continue;
                        }
                        if a.is_uniform() {
                            uses_time = true;
                            self.exprs.insert(r, "mg_params.time".into());
                        } else {
                            if !attributes.contains(&a) {
                                attributes.push(a);
                            }
                            self.exprs.insert(r, format!("geom.{}", a.name()));
                        }
                    }
                }
                _ => {}
            }
        }
        attributes.sort();
        if uses_time {
            let field = unique("time".into());
            uniform_fields.push(UniformSpec {
                field,
                source: super::UniformSource::Time,
                ty: SocketType::Float,
                default: Value::float(0.0),
            });
        }
        uniform_fields.extend(tables.iter().map(|&t| UniformSpec::table(t)));

        // Node functions in first-use order, helpers before them.
        let mut helpers: Vec<&'static str> = Vec::new();
        let mut functions: Vec<(String, NodeFunction, String)> = Vec::new(); // (key, fn, first node id)
        let mut function_index: HashMap<String, usize> = HashMap::new();
        // The calls in plan order, each with the index of its function.
        let mut calls: Vec<(NodeIndex, usize)> = Vec::new();
        for &i in &order {
            let n = &nodes[i];
            if let Some(g) = self.groups.calls.get(&i) {
                // A group call: its function follows the node functions (index fixed below).
                calls.push((i, usize::MAX - g.function));
                continue;
            }
            let outer = self.is_call(i);
            if !outer && !self.groups.body_calls.contains(&i) {
                continue;
            }
            // Keyed by the emitted name: vec3 and colour share one function.
            let constants = literal_constants(n);
            let key = node_key(n, &constants);
            if let Some(&f) = function_index.get(&key) {
                if outer {
                    calls.push((i, f));
                }
                continue;
            }
            if outer {
                calls.push((i, functions.len()));
            }
            function_index.insert(key.clone(), functions.len());
            let form = Form {
                choice: literal_choice(n),
                constants: &constants,
            };
            let f = node_function(&n.node_type, n.generic, form).ok_or_else(|| {
                ShaderError::MissingWgsl {
                    node: n.id.clone(),
                    node_type: n.node_type.name().to_owned(),
                }
            })?;
            for h in n.node_type.wgsl_helpers_for(literal_choice(n)) {
                if !helpers.contains(&h) {
                    helpers.push(h);
                }
            }
            functions.push((key, f, n.id.clone()));
        }
        // The group functions, after the node functions they call.
        self.has_geom = !attributes.is_empty();
        self.vars = (0..nodes.len()).map(|_| None).collect();
        self.bake_group_arguments();
        let base = functions.len();
        for k in 0..self.groups.functions.len() {
            let f = self.group_function(k, &functions, &function_index);
            let label = self.groups.functions[k].label.clone();
            functions.push((format!("group:{k}"), f, format!("(group {label})")));
        }
        for (_, f) in calls.iter_mut() {
            if *f > usize::MAX - self.groups.functions.len().max(1) {
                *f = base + (usize::MAX - *f);
            }
        }

        // Header and declarations.
        let _ = writeln!(
            self.out,
            "// Generated by matgraph {} from graph '{}' ({} entry). Do not edit.\n",
            env!("CARGO_PKG_VERSION"),
            crate::visible::visible(&self.graph.name),
            self.entry.name()
        );
        let mut bindings = Vec::new();
        if !uniform_fields.is_empty() {
            self.out.push_str(&params_block(&uniform_fields, 0));
            bindings.push((0, Binding::Params));
        }
        if !attributes.is_empty() {
            self.out.push_str("struct MgGeometry {\n");
            for a in &attributes {
                let _ = writeln!(self.out, "    {}: {},", a.name(), wgsl_type(a.ty()));
            }
            self.out.push_str("}\n\n");
        }
        let outputs: Vec<(String, SocketType, OutputRef)> = self
            .plan
            .outputs()
            .iter()
            .map(|o| {
                let r = self
                    .graph
                    .outputs()
                    .iter()
                    .find(|g| g.name == o.name)
                    .map(|g| g.source)
                    .or_else(|| self.graph.output_ref(&o.name))
                    .expect("plan outputs resolve in their graph");
                (o.name.clone(), o.ty, r)
            })
            .collect();
        let out_fields: Vec<String> = {
            let mut seen: HashSet<String> = HashSet::new();
            let mut next_suffix: HashMap<String, usize> = HashMap::new();
            outputs
                .iter()
                .map(|(name, ..)| {
                    let base = ident(name);
                    // A taken name gets the next free `_2`, `_3`, … of its base, counted
                    // on from the last one tried, so that many colliding names (10,000
                    // `--output o0`, issue 37) stay linear in count and in length (an
                    // underscore more per collision made the fields, and the module,
                    // quadratic in size).
                    let mut f = base.clone();
                    let mut k = next_suffix.get(&base).copied().unwrap_or(1);
                    while seen.contains(&f) {
                        k += 1;
                        f = format!("{base}_{k}");
                    }
                    seen.insert(f.clone());
                    next_suffix.insert(base, k);
                    f
                })
                .collect()
        };
        let chunked = outputs.len() > OUT_CHUNK;
        if chunked {
            for (k, chunk) in outputs.chunks(OUT_CHUNK).enumerate() {
                let _ = writeln!(self.out, "struct MgOutputs{k} {{");
                for (j, (_, ty, _)) in chunk.iter().enumerate() {
                    let f = &out_fields[k * OUT_CHUNK + j];
                    let _ = writeln!(self.out, "    {f}: {},", wgsl_type(*ty));
                }
                self.out.push_str("}\n\n");
            }
            self.out.push_str("struct MgOutputs {\n");
            for k in 0..outputs.len().div_ceil(OUT_CHUNK) {
                let _ = writeln!(self.out, "    c{k}: MgOutputs{k},");
            }
            self.out.push_str("}\n\n");
        } else {
            self.out.push_str("struct MgOutputs {\n");
            for ((_, ty, _), f) in outputs.iter().zip(&out_fields) {
                let _ = writeln!(self.out, "    {f}: {},", wgsl_type(*ty));
            }
            self.out.push_str("}\n\n");
        }
        // How an entry reads each output from `MgOutputs`: its member, or in a chunk.
        let field_paths: Vec<String> = out_fields
            .iter()
            .enumerate()
            .map(|(j, f)| match chunked {
                true => format!("c{}.{f}", j / OUT_CHUNK),
                false => f.clone(),
            })
            .collect();

        let hardware = self.entry.texture_mode() == super::TextureMode::Hardware;
        // The hardware mode's sampler is generated below, after the bindings.
        helpers.retain(|h| !(hardware && *h == crate::texture::SAMPLE_WGSL));
        let roots: Vec<&str> = functions
            .iter()
            .map(|(_, f, _)| f.definition.as_str())
            .collect();
        self.out
            .push_str(&super::prune::reachable_helpers(&helpers, &roots));
        for (_, f, first) in &functions {
            let start = self.out.len();
            self.out.push_str(&f.definition);
            self.spans.push((start..self.out.len(), first.clone()));
            self.out.push('\n');
        }

        // The material function: one straight-line body, or for large graphs a tree of
        // bounded-size part functions sharing their values through a state struct.
        self.vars = (0..nodes.len()).map(|_| None).collect();
        for &(i, f) in &calls {
            let name = match self.groups.calls.get(&i) {
                Some(g) => format!("g{i}_{}", ident(&g.path)),
                None => format!("n{i}_{}", ident(&nodes[i].id)),
            };
            self.vars[i] = Some(CallVar {
                name,
                function: f,
                part: 0,
                slots: Vec::new(),
            });
        }
        let mut calls: Vec<NodeIndex> = calls.into_iter().map(|(i, _)| i).collect();
        if calls.len() <= SPLIT_CALLS {
            self.merge_equal_group_calls(&mut calls, &functions);
            self.fold_group_runs(&mut calls, &functions, &outputs);
        }
        let mut hoisted = false;
        if calls.len() > SPLIT_CALLS {
            self.split_material(&calls, &functions, &attributes, &outputs);
        } else if matches!(self.entry, Entry::Render(_) | Entry::Library(_))
            && self.hoisted_material(&calls, &functions, &outputs)
        {
            hoisted = true;
        } else {
            let arg = if attributes.is_empty() {
                ""
            } else {
                "geom: MgGeometry"
            };
            let _ = writeln!(self.out, "fn mg_material({arg}) -> MgOutputs {{");
            for &i in &calls {
                self.emit_call(i, &functions);
            }
            self.emit_return(&outputs);
        }

        // The entry point.
        let mut shader_outputs = Vec::new();
        let mut column = 0u32;
        for ((name, ty, _), field) in outputs.iter().zip(&field_paths) {
            shader_outputs.push(ShaderOutput {
                name: name.clone(),
                ty: *ty,
                field: field.clone(),
                column,
            });
            column += ty.width() as u32;
        }
        match self.entry {
            Entry::Compute => {
                self.compute_entry(&attributes, &shader_outputs, &out_fields, &mut bindings)
            }
            Entry::Fragment => self.fragment_entry(&attributes, &shader_outputs, &field_paths),
            Entry::Library(_) => {}
            Entry::Render(_) => super::render::emit_entries(
                &mut self.out,
                &attributes,
                &shader_outputs,
                &mut bindings,
                hoisted,
            ),
        }
        if !self.plan.textures().is_empty()
            && matches!(self.entry, Entry::Library(_) | Entry::Render(_))
        {
            // The app contract's layout: textures from binding 3, after the parameters (0),
            // the frame (1) and the lights (2).
            let first = super::render::FIRST_TEXTURE_BINDING;
            self.out.push('\n');
            if hardware {
                let combos = self.sampler_combos();
                super::hardware::emit(
                    &mut self.out,
                    self.plan.textures().len() as u32,
                    &combos,
                    first,
                    &mut bindings,
                );
            } else {
                self.out
                    .push_str(&crate::texture::sample_bindings_wgsl(0, first));
                bindings.push((first, Binding::TextureTexels));
                bindings.push((first + 1, Binding::TextureLevels));
                bindings.push((first + 2, Binding::TextureTable));
            }
        } else if !self.plan.textures().is_empty() {
            // Module-scope declarations may follow their use in WGSL.
            let first = bindings
                .iter()
                .map(|(b, _)| b + 1)
                .max()
                .unwrap_or(0)
                .max(1);
            self.out.push('\n');
            self.out
                .push_str(&crate::texture::sample_bindings_wgsl(0, first));
            bindings.push((first, Binding::TextureTexels));
            bindings.push((first + 1, Binding::TextureLevels));
            bindings.push((first + 2, Binding::TextureTable));
        }
        if self.out.contains(&format!("{NON_FINITE_FN}(")) {
            self.out.push('\n');
            self.out.push_str(NON_FINITE_WGSL);
        }
        Ok(Text {
            source: self.out,
            spans: self.spans,
            bindings,
            attributes,
            outputs: shader_outputs,
            uniform_fields,
            textures: self.plan.textures().to_vec(),
        })
    }

    /// The (wrap, filter) pairs the graph's texture nodes can ask for: the literal choices of
    /// each live texture node, every choice of an input that is linked and not folded.
    fn sampler_combos(&self) -> Vec<(crate::texture::Wrap, crate::texture::Filter)> {
        use crate::texture::{Filter, Wrap};
        let mut combos = Vec::new();
        for (i, n) in self.graph.nodes().iter().enumerate() {
            if n.texture.is_none() || !self.plan.is_live(i) {
                continue;
            }
            let choice = |name: &str| -> Option<i32> {
                let k = n.node_type.inputs().iter().position(|p| p.name == name)?;
                match &n.inputs[k] {
                    InputSource::Default(v) | InputSource::Value { value: v, .. } => {
                        Some(v.as_i32())
                    }
                    InputSource::Link(r, _) => self.plan.folded(*r).map(|v| v.as_i32()),
                }
            };
            let wraps: Vec<Wrap> = match choice("wrap") {
                Some(w) => vec![Wrap::from_index(w as u32)],
                None => Wrap::ALL.to_vec(),
            };
            let filters: Vec<Filter> = match choice("filter") {
                Some(f) => vec![Filter::from_index(f as u32)],
                None => Filter::ALL.to_vec(),
            };
            for &w in &wraps {
                for &f in &filters {
                    if !combos.contains(&(w, f)) {
                        combos.push((w, f));
                    }
                }
            }
        }
        combos.sort_by_key(|(w, f)| (w.index(), f.index()));
        combos
    }

    /// The expression for input `k` of node `i`, converted to the port's type.
    fn input_expr(&self, i: NodeIndex, k: usize) -> String {
        let n = &self.graph.nodes()[i];
        let to = n.input_type(k);
        match &n.inputs[k] {
            InputSource::Default(v) | InputSource::Value { value: v, .. } => literal(v),
            InputSource::Link(r, _) => self.source_expr(*r, to),
        }
    }

    /// The expression of node output `r`, converted to `to`.
    fn source_expr(&self, r: OutputRef, to: SocketType) -> String {
        let from = self.graph.output_type(r);
        if let Some(v) = self.plan.folded(r) {
            return literal(&v.convert(to).unwrap_or(v));
        }
        let r = self.canonical(r);
        let n = &self.graph.nodes()[r.node];
        if n.forwards() && !self.groups.calls.contains_key(&r.node) {
            // A reroute or muted node: its passed input's expression (a constant passed on
            // was folded above).
            let e = match n.passthrough(r.output).map(|j| (j, &n.inputs[j])) {
                Some((j, InputSource::Link(src, _))) => self.source_expr(*src, n.input_type(j)),
                Some((_, InputSource::Default(v) | InputSource::Value { value: v, .. })) => {
                    literal(v)
                }
                None => literal(&Value::zero(from)),
            };
            return convert(&e, from, to);
        }
        let e = match &self.vars[r.node] {
            Some(var) => {
                let stored = var.slots.get(r.output).copied().flatten();
                match (self.context, stored) {
                    (Context::Part(p), Some((array, k))) if p != var.part => {
                        format!("(*s).{array}[{k}]")
                    }
                    (Context::Material, Some((array, k))) => format!("s.{array}[{k}]"),
                    _ => self.local_value(r),
                }
            }
            None => self.exprs.get(&r).cloned().unwrap_or_else(|| "0.0".into()),
        };
        convert(&e, from, to)
    }

    /// The node output whose value `r` is: `r`, or through reroutes and muted nodes the
    /// output they pass on; `None` where that is a constant.
    fn resolve(&self, mut r: OutputRef) -> Option<OutputRef> {
        let nodes = self.graph.nodes();
        while nodes[r.node].forwards() {
            if self.groups.out_of.contains_key(&r.node) {
                return Some(self.canonical(r));
            }
            let n = &nodes[r.node];
            match n.passthrough(r.output).map(|j| &n.inputs[j]) {
                Some(InputSource::Link(src, _)) => r = *src,
                _ => return None,
            }
        }
        Some(r)
    }

    /// The node outputs whose values node `i` reads (through reroutes and muted nodes), in
    /// port order.
    fn sources(&self, i: NodeIndex) -> Vec<OutputRef> {
        if let Some(run) = self.runs.get(&i) {
            // A run's loop reads what its first call reads.
            return self.sources(run.head);
        }
        if let Some(g) = self.groups.calls.get(&i) {
            // A group call reads what its instance passes to its inputs.
            return g.inputs.iter().flat_map(|&n| self.sources(n)).collect();
        }
        self.graph.nodes()[i]
            .inputs
            .iter()
            .filter_map(|src| match src {
                InputSource::Link(r, _) => self.resolve(*r),
                _ => None,
            })
            .collect()
    }

    /// `r`, or for an output of a called group instance the call's node and member.
    fn canonical(&self, r: OutputRef) -> OutputRef {
        match self.groups.out_of.get(&r.node) {
            Some(&(node, output)) => OutputRef { node, output },
            None => r,
        }
    }

    /// Whether node `i` is a call of the material function (not a group call).
    fn is_call(&self, i: NodeIndex) -> bool {
        let n = &self.graph.nodes()[i];
        emits_call(n.node_type.evaluation())
            && !self.folded(i)
            && !n.forwards()
            && !self.groups.hidden.contains(&i)
    }

    /// The arguments every call of a group function passes alike and that read nothing
    /// local (a literal, a folded value, a parameter's uniform, the time, an attribute of
    /// `geom`): written into the function's body instead of each call, as specialising the
    /// function on them.
    fn bake_group_arguments(&mut self) {
        let nodes = self.graph.nodes();
        let mut calls: Vec<(NodeIndex, usize)> = self
            .groups
            .calls
            .iter()
            .map(|(&c, g)| (c, g.function))
            .collect();
        calls.sort_unstable();
        let mut baked: Vec<Vec<Option<String>>> = self
            .groups
            .functions
            .iter()
            .map(|f| {
                let inputs = self
                    .graph
                    .instances()
                    .map_or(0, |i| i.list[f.rep].inputs.len());
                vec![None; inputs]
            })
            .collect();
        let mut seen: Vec<bool> = vec![false; self.groups.functions.len()];
        for (c, f) in calls {
            let inputs = self.groups.calls[&c].inputs.clone();
            for (j, &n) in inputs.iter().enumerate() {
                let global = match &nodes[n].inputs[0] {
                    InputSource::Link(r, _) => match self.resolve(*r) {
                        None => true,
                        Some(r) => {
                            self.plan.folded(r).is_some()
                                || matches!(
                                    nodes[r.node].node_type.evaluation(),
                                    Evaluation::Parameter
                                )
                                || self.exprs.get(&r).is_some_and(|e| {
                                    e.starts_with("mg_params.") || e.starts_with("geom.")
                                })
                        }
                    },
                    _ => true,
                };
                let arg = global.then(|| self.input_expr(n, 0));
                let slot = &mut baked[f][j];
                if !seen[f] {
                    *slot = arg;
                } else if *slot != arg {
                    *slot = None;
                }
            }
            seen[f] = true;
        }
        for (f, b) in self.groups.functions.iter_mut().zip(baked) {
            f.baked = b;
        }
    }

    /// Instances called with the same arguments compute the same values: each such call
    /// after the first is dropped and its outputs read from the first. (Not in a split
    /// material function, where the first call's values may lie in another part.)
    fn merge_equal_group_calls(
        &mut self,
        calls: &mut Vec<NodeIndex>,
        functions: &[(String, NodeFunction, String)],
    ) {
        let mut first: HashMap<String, NodeIndex> = HashMap::new();
        let mut merged: HashMap<NodeIndex, NodeIndex> = HashMap::new();
        for &c in calls.iter() {
            let Some(g) = self.groups.calls.get(&c) else {
                continue;
            };
            let baked = &self.groups.functions[g.function].baked;
            let args: Vec<String> = g
                .inputs
                .iter()
                .zip(baked)
                .filter(|(_, b)| b.is_none())
                .map(|(&n, _)| self.input_expr(n, 0))
                .collect();
            let name = &functions[self.var(c).function].1.name;
            let key = format!("{name}({})", args.join(", "));
            match first.get(&key) {
                Some(&c0) => {
                    merged.insert(c, c0);
                }
                None => {
                    first.insert(key, c);
                }
            }
        }
        if merged.is_empty() {
            return;
        }
        for (c, _) in self.groups.out_of.values_mut() {
            if let Some(&c0) = merged.get(c) {
                *c = c0;
            }
        }
        calls.retain(|c| !merged.contains_key(c));
        for c in merged.keys() {
            self.vars[*c] = None;
        }
    }

    /// The number of values call node `i` gives.
    fn call_outputs(&self, i: NodeIndex) -> usize {
        match self.groups.calls.get(&i) {
            Some(g) => self.groups.functions[g.function].members.len(),
            None => self.graph.nodes()[i].node_type.outputs().len(),
        }
    }

    /// The type of value `k` of call node `i`.
    fn call_output_type(&self, i: NodeIndex, k: usize) -> SocketType {
        match self.groups.calls.get(&i) {
            Some(g) => self.groups.functions[g.function].members[k].1,
            None => self.graph.nodes()[i].output_type(k),
        }
    }

    /// The definition of group function `k` (see [`super::groups`]): its result struct,
    /// then `fn NAME(geom, inputs…) -> STRUCT` with its body's calls and its return.
    fn group_function(
        &self,
        k: usize,
        functions: &[(String, NodeFunction, String)],
        function_index: &HashMap<String, usize>,
    ) -> NodeFunction {
        let g = &self.groups.functions[k];
        let nodes = self.graph.nodes();
        let inst = &self.graph.instances().expect("a grouped graph").list[g.rep];
        let mut def = format!("struct {} {{\n", g.out_struct);
        for (field, ty, _) in &g.members {
            let _ = writeln!(def, "    {field}: {},", wgsl_type(*ty));
        }
        def.push_str("}\n\n");
        let mut params: HashMap<NodeIndex, String> = HashMap::new();
        let mut args: Vec<String> = Vec::new();
        for (j, (name, node)) in inst.inputs.iter().enumerate() {
            if let Some(value) = &g.baked[j] {
                params.insert(*node, value.clone());
                continue;
            }
            let p = format!("a{j}_{}", ident(name));
            args.push(format!("{p}: {}", wgsl_type(nodes[*node].output_type(0))));
            params.insert(*node, p);
        }
        let mut body = String::new();
        let prefix = format!("{}/", inst.path);
        let mut vars: HashMap<NodeIndex, String> = HashMap::new();
        for &i in &g.body {
            let n = &nodes[i];
            let local = n.id.strip_prefix(&prefix).unwrap_or(&n.id);
            let var = format!("b{i}_{}", ident(local));
            let constants = literal_constants(n);
            let key = node_key(n, &constants);
            let fname = function_index
                .get(&key)
                .map_or(key.as_str(), |&f| functions[f].1.name.as_str());
            let mut call_args: Vec<String> = Vec::new();
            if let Some(key) = n.texture_key() {
                let slot = self.texture_slots.get(&key).copied().unwrap_or(0);
                call_args.push(format!("{slot}u"));
            }
            for (j, src) in n.inputs.iter().enumerate() {
                if constants.iter().any(|(k, _)| *k == j) {
                    continue;
                }
                call_args.push(match src {
                    InputSource::Default(v) | InputSource::Value { value: v, .. } => literal(v),
                    InputSource::Link(r, _) => {
                        self.body_expr(g, &params, &vars, *r, n.input_type(j))
                    }
                });
            }
            let _ = writeln!(body, "    let {var} = {fname}({});", call_args.join(", "));
            vars.insert(i, var);
        }
        let values: Vec<String> = g
            .members
            .iter()
            .map(|(_, ty, node)| {
                self.body_expr(
                    g,
                    &params,
                    &vars,
                    OutputRef {
                        node: *node,
                        output: 0,
                    },
                    *ty,
                )
            })
            .collect();
        let _ = writeln!(
            body,
            "    return {}({});\n}}",
            g.out_struct,
            values.join(", ")
        );
        // `geom` is passed only to a body that reads it.
        if body.contains("geom.") {
            args.insert(0, "geom: MgGeometry".into());
        }
        let _ = writeln!(
            def,
            "fn {}({}) -> {} {{",
            g.name,
            args.join(", "),
            g.out_struct
        );
        def.push_str(&body);
        NodeFunction {
            name: g.name.clone(),
            out_struct: Some(g.out_struct.clone()),
            definition: def,
        }
    }

    /// The expression of node output `r` inside group function `g`, converted to `to`.
    fn body_expr(
        &self,
        g: &super::groups::GroupFunction,
        params: &HashMap<NodeIndex, String>,
        vars: &HashMap<NodeIndex, String>,
        r: OutputRef,
        to: SocketType,
    ) -> String {
        let from = self.graph.output_type(r);
        if let Some(p) = params.get(&r.node) {
            return convert(p, from, to);
        }
        if !g.varying.contains(&r.node)
            && let Some(v) = self.plan.folded(r)
        {
            return literal(&v.convert(to).unwrap_or(v));
        }
        let n = &self.graph.nodes()[r.node];
        let e = if n.forwards() {
            match n.passthrough(r.output).map(|j| (j, &n.inputs[j])) {
                Some((j, InputSource::Link(src, _))) => {
                    self.body_expr(g, params, vars, *src, n.input_type(j))
                }
                Some((_, InputSource::Default(v) | InputSource::Value { value: v, .. })) => {
                    literal(v)
                }
                None => literal(&Value::zero(from)),
            }
        } else if let Some(var) = vars.get(&r.node) {
            if n.node_type.outputs().len() > 1 {
                format!("{var}.{}", output_member(&n.node_type, r.output))
            } else {
                var.clone()
            }
        } else {
            self.exprs.get(&r).cloned().unwrap_or_else(|| "0.0".into())
        };
        convert(&e, from, to)
    }

    /// The variable of call node `i`.
    fn var(&self, i: NodeIndex) -> &CallVar {
        self.vars[i].as_ref().expect("a call node has a variable")
    }

    /// Node output `r` of a call, by its local variable.
    fn local_value(&self, r: OutputRef) -> String {
        let var = self.var(r.node);
        if let Some(g) = self.groups.calls.get(&r.node) {
            let member = &self.groups.functions[g.function].members[r.output].0;
            return format!("{}.{member}", var.name);
        }
        let n = &self.graph.nodes()[r.node];
        if n.node_type.outputs().len() > 1 {
            format!("{}.{}", var.name, output_member(&n.node_type, r.output))
        } else {
            var.name.clone()
        }
    }

    /// The arguments written in group call `i`: `geom` where its function takes it, then
    /// the inputs not baked into the function.
    fn group_call_args(
        &self,
        i: NodeIndex,
        functions: &[(String, NodeFunction, String)],
    ) -> Vec<String> {
        let g = &self.groups.calls[&i];
        let f = &functions[self.var(i).function].1;
        let mut args: Vec<String> = Vec::new();
        if f.definition.contains("geom: MgGeometry") {
            args.push("geom".into());
        }
        let baked = &self.groups.functions[g.function].baked;
        args.extend(
            g.inputs
                .iter()
                .zip(baked)
                .filter(|(_, b)| b.is_none())
                .map(|(&n, _)| self.input_expr(n, 0)),
        );
        args
    }

    /// The arguments written in call `i` (a node's or a group instance's).
    fn call_args(&self, i: NodeIndex, functions: &[(String, NodeFunction, String)]) -> Vec<String> {
        if self.groups.calls.contains_key(&i) {
            return self.group_call_args(i, functions);
        }
        let n = &self.graph.nodes()[i];
        let mut args: Vec<String> = Vec::new();
        if let Some(key) = n.texture_key() {
            // Texture nodes take their slot in the packed texture set first.
            let slot = self.texture_slots.get(&key).copied().unwrap_or(0);
            args.push(format!("{slot}u"));
        }
        // Constant inputs are compiled into the function (`literal_constants`).
        let constants = literal_constants(n);
        args.extend(
            (0..n.inputs.len())
                .filter(|k| !constants.iter().any(|(c, _)| c == k))
                .map(|k| self.input_expr(i, k)),
        );
        args
    }

    /// Emits the `let` of node `i`'s call (and its store into `MgState` when shared).
    fn emit_call(&mut self, i: NodeIndex, functions: &[(String, NodeFunction, String)]) {
        let n = &self.graph.nodes()[i];
        if let Some(run) = self.runs.get(&i) {
            let text = self.emit_run(i, run, functions);
            let start = self.out.len();
            self.out.push_str(&text);
            self.spans.push((start..self.out.len(), n.id.clone()));
            return;
        }
        let var = self.var(i);
        let f = &functions[var.function].1;
        let args = self.call_args(i, functions);
        let mut text = format!("    let {} = {}({});\n", var.name, f.name, args.join(", "));
        for (k, slot) in var.slots.iter().enumerate() {
            if let Some((array, j)) = slot {
                let value = self.local_value(OutputRef { node: i, output: k });
                let _ = writeln!(text, "    (*s).{array}[{j}] = {value};");
            }
        }
        let start = self.out.len();
        self.out.push_str(&text);
        self.spans.push((start..self.out.len(), n.id.clone()));
    }

    /// The calls in depth-first post-order from the outputs (inputs in port order), so that
    /// a value is mostly read by calls close after it, in the same part; calls no output
    /// reaches follow in their first order. Iterative: any depth.
    fn post_order(
        &self,
        calls: &[NodeIndex],
        outputs: &[(String, SocketType, OutputRef)],
    ) -> Vec<NodeIndex> {
        let mut done: HashSet<NodeIndex> = HashSet::with_capacity(calls.len());
        let mut order = Vec::with_capacity(calls.len());
        let mut stack: Vec<(NodeIndex, Vec<OutputRef>, usize)> = Vec::new();
        let roots = outputs
            .iter()
            .filter_map(|(_, _, r)| self.resolve(*r))
            .map(|r| r.node)
            .chain(calls.iter().copied());
        for root in roots {
            if self.vars[root].is_none() || !done.insert(root) {
                continue;
            }
            stack.push((root, self.sources(root), 0));
            while let Some((i, sources, k)) = stack.last_mut() {
                if let Some(r) = sources.get(*k).copied() {
                    *k += 1;
                    if self.vars[r.node].is_some() && done.insert(r.node) {
                        stack.push((r.node, self.sources(r.node), 0));
                    }
                    continue;
                }
                order.push(*i);
                stack.pop();
            }
        }
        order
    }

    /// Emits the material function of a large graph as part functions of at most
    /// [`PART_CALLS`] calls (in depth-first post-order, so most values are read in the part
    /// that computes them), run in order by a tree of functions of at most [`PART_FANOUT`]
    /// calls, so that no function body grows with the graph (naga's WGSL front end types a
    /// function's expressions in time quadratic in their number). Values read outside the
    /// part that computes them live in the `MgState` struct the parts share by pointer, in
    /// one array per WGSL type.
    fn split_material(
        &mut self,
        calls: &[NodeIndex],
        functions: &[(String, NodeFunction, String)],
        attributes: &[Attribute],
        outputs: &[(String, SocketType, OutputRef)],
    ) {
        let calls = &self.post_order(calls, outputs);
        for (k, i) in calls.iter().enumerate() {
            if let Some(v) = &mut self.vars[*i] {
                v.part = k / PART_CALLS;
            }
        }
        // Which values cross a part boundary (or reach an output).
        let mut shared: HashSet<OutputRef> = HashSet::new();
        for &i in calls {
            let part = self.var(i).part;
            for r in self.sources(i) {
                if self.vars[r.node].as_ref().is_some_and(|v| v.part != part) {
                    shared.insert(r);
                }
            }
        }
        for r in outputs.iter().filter_map(|(_, _, r)| self.resolve(*r)) {
            if self.vars[r.node].is_some() {
                shared.insert(r);
            }
        }
        // They are kept in one array per WGSL type (index lookups stay constant-time, where
        // naga resolves a struct member by a search over the members).
        let mut arrays: Vec<(&'static str, &'static str, usize)> = Vec::new(); // (member, type, len)
        for &i in calls {
            let outs = self.call_outputs(i);
            let mut slots = vec![None; outs];
            for (k, slot) in slots.iter_mut().enumerate() {
                if !shared.contains(&OutputRef { node: i, output: k }) {
                    continue;
                }
                let ty = wgsl_type(self.call_output_type(i, k));
                let a = match arrays.iter().position(|(_, t, _)| *t == ty) {
                    Some(a) => a,
                    None => {
                        arrays.push((state_member(ty), ty, 0));
                        arrays.len() - 1
                    }
                };
                *slot = Some((arrays[a].0, arrays[a].2));
                arrays[a].2 += 1;
            }
            if let Some(v) = &mut self.vars[i] {
                v.slots = slots;
            }
        }
        arrays.sort_by_key(|(member, ..)| *member);
        self.out.push_str("struct MgState {\n");
        for (member, ty, len) in &arrays {
            let _ = writeln!(self.out, "    {member}: array<{ty}, {len}>,");
        }
        if arrays.is_empty() {
            // WGSL structs need a member.
            self.out.push_str("    unused: f32,\n");
        }
        self.out.push_str("}\n\n");

        let (param, arg) = if attributes.is_empty() {
            ("", "")
        } else {
            ("geom: MgGeometry, ", "geom, ")
        };
        let parts = calls.len().div_ceil(PART_CALLS);
        for (p, chunk) in calls.chunks(PART_CALLS).enumerate() {
            self.context = Context::Part(p);
            let _ = writeln!(
                self.out,
                "fn mg_part_{p}({param}s: ptr<function, MgState>) {{"
            );
            for &i in chunk {
                self.emit_call(i, functions);
            }
            self.out.push_str("}\n\n");
        }
        // The tree of sequencing functions, level by level, until one level fits a body.
        let mut level: Vec<String> = (0..parts).map(|p| format!("mg_part_{p}")).collect();
        let mut depth = 1;
        while level.len() > PART_FANOUT {
            let mut next = Vec::new();
            for (k, group) in level.chunks(PART_FANOUT).enumerate() {
                let name = format!("mg_parts_{depth}_{k}");
                let _ = writeln!(self.out, "fn {name}({param}s: ptr<function, MgState>) {{");
                for f in group {
                    let _ = writeln!(self.out, "    {f}({arg}s);");
                }
                self.out.push_str("}\n\n");
                next.push(name);
            }
            level = next;
            depth += 1;
        }
        let _ = writeln!(
            self.out,
            "fn mg_material({}) -> MgOutputs {{\n    var s: MgState;",
            param.trim_end_matches(", ")
        );
        for f in &level {
            let _ = writeln!(self.out, "    {f}({arg}&s);");
        }
        self.context = Context::Material;
        self.emit_return(outputs);
        self.context = Context::Whole;
    }

    /// The calls that depend on the light: those reading the `light` or `light_color`
    /// attribute, and those reading such a call.
    fn light_dependent(&self, calls: &[NodeIndex]) -> HashSet<NodeIndex> {
        let nodes = self.graph.nodes();
        let is_light = |r: &OutputRef| match nodes[r.node].node_type.evaluation() {
            Evaluation::Attributes(attrs) => matches!(
                attrs.get(r.output),
                Some(Attribute::Light | Attribute::LightColor)
            ),
            _ => false,
        };
        let mut lit = HashSet::new();
        // Calls are in dependency order: a call's sources come before it.
        for &i in calls {
            let reads_light = self.groups.calls.get(&i).is_some_and(|g| g.reads_light)
                || self.sources(i).iter().any(|r| {
                    self.plan.folded(*r).is_none() && (is_light(r) || lit.contains(&r.node))
                });
            if reads_light {
                lit.insert(i);
            }
        }
        lit
    }

    /// The material function of a render or library module, hoisted out of the light loop:
    /// `mg_material_unlit` computes the calls that do not depend on the light (once per
    /// fragment), `mg_material_lit` the rest from its result (once per light), and
    /// `mg_material` is the two in turn (the library's function, unchanged in value).
    /// Returns false, having emitted nothing, when there is nothing to split.
    fn hoisted_material(
        &mut self,
        calls: &[NodeIndex],
        functions: &[(String, NodeFunction, String)],
        outputs: &[(String, SocketType, OutputRef)],
    ) -> bool {
        let lit = self.light_dependent(calls);
        let (unlit, lit_calls): (Vec<NodeIndex>, Vec<NodeIndex>) =
            calls.iter().partition(|i| !lit.contains(i));
        if unlit.is_empty() || lit_calls.is_empty() {
            return false;
        }
        // The unlit values the lit calls or the outputs read, in call order.
        let nodes = self.graph.nodes();
        let read: HashSet<NodeIndex> = lit_calls
            .iter()
            .flat_map(|&i| self.sources(i))
            .chain(outputs.iter().filter_map(|(_, _, r)| self.resolve(*r)))
            .map(|r| r.node)
            .collect();
        let carried: Vec<(String, String)> = unlit
            .iter()
            .filter(|i| read.contains(i))
            .map(|&i| {
                let var = self.var(i);
                let ty = match &functions[var.function].1.out_struct {
                    Some(s) => s.clone(),
                    None => wgsl_type(nodes[i].output_type(0)).to_owned(),
                };
                (var.name.clone(), ty)
            })
            .collect();
        self.out.push_str("struct MgUnlit {\n");
        for (name, ty) in &carried {
            let _ = writeln!(self.out, "    {name}: {ty},");
        }
        if carried.is_empty() {
            self.out.push_str("    unused: f32,\n");
        }
        self.out.push_str("}\n\n");
        self.out
            .push_str("fn mg_material_unlit(geom: MgGeometry) -> MgUnlit {\n");
        for &i in &unlit {
            self.emit_call(i, functions);
        }
        let values: Vec<&str> = carried.iter().map(|(n, _)| n.as_str()).collect();
        let values = if values.is_empty() {
            "0.0".to_owned()
        } else {
            values.join(", ")
        };
        let _ = writeln!(self.out, "    return MgUnlit({values});\n}}\n");
        self.out
            .push_str("fn mg_material_lit(geom: MgGeometry, u: MgUnlit) -> MgOutputs {\n");
        for (name, _) in &carried {
            let _ = writeln!(self.out, "    let {name} = u.{name};");
        }
        for &i in &lit_calls {
            self.emit_call(i, functions);
        }
        self.emit_return(outputs);
        self.out.push_str(
            "fn mg_material(geom: MgGeometry) -> MgOutputs {\n    \
             return mg_material_lit(geom, mg_material_unlit(geom));\n}\n\n",
        );
        true
    }

    /// The material function's `return MgOutputs(...)` and closing brace; past
    /// [`OUT_CHUNK`] outputs, [`Self::emit_chunked_return`].
    fn emit_return(&mut self, outputs: &[(String, SocketType, OutputRef)]) {
        if outputs.len() > OUT_CHUNK {
            self.emit_chunked_return(outputs);
            return;
        }
        let values: Vec<String> = outputs
            .iter()
            .map(|(_, ty, r)| self.source_expr(*r, *ty))
            .collect();
        let _ = writeln!(
            self.out,
            "    return MgOutputs({});\n}}\n",
            values.join(", ")
        );
    }

    /// The return of more than [`OUT_CHUNK`] outputs, in chunk structs, with every
    /// function's expressions bounded: in a split material function each chunk is built by
    /// a function of its own reading the state (`mg_out_chunk_{k}`); elsewhere the values
    /// are the function's own `let`s and calls (at most [`SPLIT_CALLS`]), and a value
    /// returned more than once is bound to a `let` once (`mg_v{j}`: naming a `let` adds no
    /// expression).
    fn emit_chunked_return(&mut self, outputs: &[(String, SocketType, OutputRef)]) {
        let chunks: Vec<_> = outputs.chunks(OUT_CHUNK).collect();
        if self.context == Context::Material {
            let saved = self.context;
            // No part owns the values: each is read through the state pointer `s`.
            self.context = Context::Part(usize::MAX);
            let (param, arg) = match self.has_geom {
                true => (", geom: MgGeometry", ", geom"),
                false => ("", ""),
            };
            let mut defs = String::new();
            for (k, chunk) in chunks.iter().enumerate() {
                let values: Vec<String> = chunk
                    .iter()
                    .map(|(_, ty, r)| self.source_expr(*r, *ty))
                    .collect();
                let _ = writeln!(
                    defs,
                    "fn mg_out_chunk_{k}(s: ptr<function, MgState>{param}) -> MgOutputs{k} {{\n    return MgOutputs{k}({});\n}}\n",
                    values.join(", ")
                );
            }
            self.context = saved;
            let parts: Vec<String> = (0..chunks.len())
                .map(|k| format!("mg_out_chunk_{k}(&s{arg})"))
                .collect();
            let _ = writeln!(
                self.out,
                "    return MgOutputs({});\n}}\n",
                parts.join(", ")
            );
            self.out.push_str(&defs);
            return;
        }
        let values: Vec<String> = outputs
            .iter()
            .map(|(_, ty, r)| self.source_expr(*r, *ty))
            .collect();
        let mut uses: HashMap<&str, usize> = HashMap::new();
        for v in &values {
            *uses.entry(v.as_str()).or_default() += 1;
        }
        let mut bound: HashMap<&str, String> = HashMap::new();
        for v in &values {
            if uses[v.as_str()] > 1 && !bound.contains_key(v.as_str()) {
                let name = format!("mg_v{}", bound.len());
                let _ = writeln!(self.out, "    let {name} = {v};");
                bound.insert(v.as_str(), name);
            }
        }
        let named: Vec<&str> = values
            .iter()
            .map(|v| bound.get(v.as_str()).map_or(v.as_str(), String::as_str))
            .collect();
        let parts: Vec<String> = named
            .chunks(OUT_CHUNK)
            .enumerate()
            .map(|(k, c)| format!("MgOutputs{k}({})", c.join(", ")))
            .collect();
        let _ = writeln!(
            self.out,
            "    return MgOutputs({});\n}}\n",
            parts.join(", ")
        );
    }

    fn compute_entry(
        &mut self,
        attributes: &[Attribute],
        outputs: &[ShaderOutput],
        fields: &[String],
        bindings: &mut Vec<(u32, Binding)>,
    ) {
        self.out
            .push_str("struct MgDispatch {\n    count: u32,\n    row: u32,\n}\n\n");
        self.out
            .push_str("@group(0) @binding(1) var<uniform> mg_dispatch: MgDispatch;\n");
        bindings.push((1, Binding::Dispatch));
        // Every attribute in one buffer (WebGPU's default limit is 8 storage buffers per
        // stage; one buffer per attribute took 9–11 for half the bundled graphs), planar
        // like mg_out: lane c of an attribute at offset k is at (k + c) * count + i.
        if !attributes.is_empty() {
            let layout: Vec<String> = super::geometry_layout(attributes)
                .iter()
                .map(|(a, k)| format!("{} {k}", a.name()))
                .collect();
            let _ = writeln!(
                self.out,
                "// mg_geometry: the attributes, planar, lane c of sample i at \
                 (offset + c) * count + i;\n// offsets: {}.\n\
                 @group(0) @binding({GEOMETRY_BINDING}) var<storage, read> mg_geometry: array<f32>;",
                layout.join(", ")
            );
            bindings.push((GEOMETRY_BINDING, Binding::Geometry));
        }
        let _ = writeln!(
            self.out,
            "@group(0) @binding({OUTPUT_BINDING}) var<storage, read_write> mg_out: array<f32>;\n"
        );
        bindings.push((OUTPUT_BINDING, Binding::Output));

        let _ = writeln!(self.out, "@compute @workgroup_size({WORKGROUP_SIZE})");
        self.out
            .push_str("fn mg_compute(@builtin(global_invocation_id) id: vec3<u32>) {\n");
        self.out.push_str(
            "    let n = mg_dispatch.count;\n    let i = id.x + id.y * mg_dispatch.row;\n",
        );
        self.out
            .push_str("    if (i >= n) {\n        return;\n    }\n");
        if !attributes.is_empty() {
            self.out.push_str("    var geom: MgGeometry;\n");
            for (a, k) in super::geometry_layout(attributes) {
                let w = a.ty().width() as u32;
                let comps: Vec<String> = (k..k + w)
                    .map(|c| format!("mg_geometry[{c}u * n + i]"))
                    .collect();
                let _ = writeln!(
                    self.out,
                    "    geom.{} = {}({});",
                    a.name(),
                    wgsl_type(a.ty()),
                    comps.join(", ")
                );
            }
            self.out.push_str("    let o = mg_material(geom);\n");
        } else {
            self.out.push_str("    let o = mg_material();\n");
        }
        if outputs.len() <= OUT_CHUNK {
            self.out.push_str(&stores(outputs, fields));
            self.out.push_str("}\n");
            return;
        }
        // Past OUT_CHUNK outputs, one store function per chunk (see OUT_CHUNK).
        let mut defs = String::new();
        for (k, (o, f)) in outputs
            .chunks(OUT_CHUNK)
            .zip(fields.chunks(OUT_CHUNK))
            .enumerate()
        {
            let _ = writeln!(self.out, "    mg_out_store_{k}(o.c{k}, n, i);");
            let _ = writeln!(
                defs,
                "\nfn mg_out_store_{k}(o: MgOutputs{k}, n: u32, i: u32) {{\n{}}}",
                stores(o, f)
            );
        }
        self.out.push_str("}\n");
        self.out.push_str(&defs);
    }

    fn fragment_entry(
        &mut self,
        attributes: &[Attribute],
        outputs: &[ShaderOutput],
        fields: &[String],
    ) {
        self.out
            .push_str("struct MgVarying {\n    @builtin(position) frag_coord: vec4<f32>,\n");
        for a in attributes {
            let _ = writeln!(
                self.out,
                "    @location({}) {}: {},",
                fragment_location(*a),
                a.name(),
                wgsl_type(a.ty())
            );
        }
        self.out
            .push_str("}\n\n@fragment\nfn mg_fragment(v: MgVarying) -> @location(0) vec4<f32> {\n");
        if !attributes.is_empty() {
            self.out.push_str("    var geom: MgGeometry;\n");
            for a in attributes {
                // Interpolated directions are renormalised.
                let e = match a {
                    Attribute::Normal | Attribute::View | Attribute::Light => {
                        format!("normalize(v.{})", a.name())
                    }
                    _ => format!("v.{}", a.name()),
                };
                let _ = writeln!(self.out, "    geom.{} = {e};", a.name());
            }
            self.out.push_str("    let o = mg_material(geom);\n");
        } else {
            self.out.push_str("    let o = mg_material();\n");
        }
        let first = &outputs[0];
        let e = format!("o.{}", fields[0]);
        let rgba = match first.ty {
            SocketType::Vec4 => e,
            SocketType::Vec3 | SocketType::Color => format!("vec4<f32>({e}, 1.0)"),
            SocketType::Vec2 => format!("vec4<f32>({e}, 0.0, 1.0)"),
            t => format!(
                "vec4<f32>(vec3<f32>({}), 1.0)",
                convert(&e, t, SocketType::Float)
            ),
        };
        let _ = writeln!(self.out, "    return {rgba};\n}}");
    }
}

/// The compute entry's stores of `outputs` (members `fields` of `o`) into `mg_out`, one
/// line per component.
fn stores(outputs: &[ShaderOutput], fields: &[String]) -> String {
    let mut text = String::new();
    for (o, f) in outputs.iter().zip(fields) {
        let w = o.ty.width();
        for c in 0..w {
            let e = if w == 1 {
                format!("o.{f}")
            } else {
                format!("o.{f}.{}", ["x", "y", "z", "w"][c])
            };
            let e = convert(
                &e,
                if w == 1 { o.ty } else { SocketType::Float },
                SocketType::Float,
            );
            let _ = writeln!(
                text,
                "    mg_out[{}u * n + i] = {e};",
                o.column as usize + c
            );
        }
    }
    text
}

/// The `MgState` member holding the shared values of WGSL type `ty`.
fn state_member(ty: &str) -> &'static str {
    match ty {
        "f32" => "f",
        "vec2<f32>" => "v2",
        "vec3<f32>" => "v3",
        "vec4<f32>" => "v4",
        "i32" => "i",
        _ => "b",
    }
}

/// Whether nodes of this kind become a function call in the material function.
fn emits_call(e: Evaluation) -> bool {
    matches!(e, Evaluation::Compute | Evaluation::Texture)
}

/// The fixed `@location` of an attribute in the fragment entry's varyings.
pub fn fragment_location(a: Attribute) -> u32 {
    match a {
        Attribute::Position => 0,
        Attribute::Normal => 1,
        Attribute::View => 2,
        Attribute::Light => 3,
        Attribute::Uv => 4,
        Attribute::LightColor => 5,
        Attribute::ScreenUv => 6,
        Attribute::Depth => 7,
        Attribute::Time => 8,
        Attribute::UvDx => 9,
        Attribute::UvDy => 10,
        Attribute::Tangent => 11,
        Attribute::BitangentSign => 12,
        Attribute::Generated => 13,
        Attribute::Reflection => 14,
        Attribute::Window => 15,
        Attribute::Camera => 16,
        Attribute::PositionDx => 17,
        Attribute::PositionDy => 18,
    }
}
