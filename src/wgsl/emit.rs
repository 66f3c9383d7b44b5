//! WGSL text generation for a planned graph.

use super::{Binding, Entry, ShaderError, ShaderOutput, WORKGROUP_SIZE, WgslOptions, wgsl_type};
use crate::graph::{Graph, InputSource, NodeIndex, OutputRef};
use crate::node::{Attribute, Evaluation, NodeType};
use crate::plan::Plan;
use crate::types::{LUMA_709, SocketType};
use crate::value::Value;
use std::collections::BTreeMap;
use std::fmt::Write;
use std::ops::Range;

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

/// A WGSL identifier for `name`: non-alphanumerics become `_`, reserved words get a `_` suffix.
pub(super) fn ident(name: &str) -> String {
    let mut s: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if s.is_empty() || s.starts_with(|c: char| c.is_ascii_digit()) || s.starts_with("__") {
        s.insert_str(0, "p_");
    }
    if RESERVED.contains(&s.as_str()) {
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
/// which converts to f32 exactly, is printed instead. WGSL has no literal for infinity or NaN:
/// a non-finite `x` is `bitcast<f32>(bits)`, which naga accepts but Tint's constant evaluator
/// rejects ("value inf cannot be represented as 'f32'"); only a runtime bitcast (of a
/// `var<private>`, say) passes both, and that needs a module-scope declaration.
pub(super) fn float_literal(x: f32) -> String {
    if !x.is_finite() {
        return format!("bitcast<f32>({:#010x}u)", x.to_bits());
    }
    let short = format!("{x:?}");
    match short.parse::<f64>() {
        Ok(d) if d.abs() <= f64::from(f32::MAX) && (d as f32).to_bits() == x.to_bits() => short,
        _ => format!("{:?}", f64::from(x)),
    }
}

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

/// Builds the WGSL function of `t` for generic type `generic` from its template.
pub(super) fn node_function(t: &NodeType, generic: SocketType) -> Option<NodeFunction> {
    let template = t.wgsl_for(generic)?;
    let name = function_name(t, generic);
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
    let body = template
        .trim()
        .replace("$fn", &name)
        .replace("$out", out_struct.as_deref().unwrap_or("$out"))
        .replace("$T", wgsl_type(generic));
    definition.push_str(&body);
    definition.push('\n');
    Some(NodeFunction {
        name,
        out_struct,
        definition,
    })
}

/// Emits the module of one planned graph.
pub(super) struct Emitter<'a> {
    graph: &'a Graph,
    plan: &'a Plan,
    entry: Entry,
    out: String,
    spans: Vec<(Range<usize>, String)>,
    /// WGSL expression of each live node output.
    exprs: BTreeMap<OutputRef, String>,
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

        // Uniforms: live unbaked parameters (exposed under their names), then time.
        let mut uniform_fields: Vec<UniformSpec> = Vec::new();
        let mut taken: Vec<String> = Vec::new();
        let mut unique = |base: String| {
            let mut name = base.clone();
            let mut k = 2;
            while taken.contains(&name) {
                name = format!("{base}_{k}");
                k += 1;
            }
            taken.push(name.clone());
            name
        };
        let mut attributes: Vec<Attribute> = Vec::new();
        let mut uses_time = false;
        for &i in &order {
            let n = &nodes[i];
            match n.node_type.evaluation() {
                Evaluation::Parameter if !self.folded(i) => {
                    let exposed = self.graph.parameters().iter().find(|p| p.node == i);
                    let pname = exposed
                        .map(|p| p.name.clone())
                        .unwrap_or_else(|| n.id.clone());
                    let field = unique(ident(&pname));
                    let default = match &n.inputs[0] {
                        InputSource::Default(v) | InputSource::Value { value: v, .. } => *v,
                        InputSource::Link(..) => Value::zero(n.output_type(0)),
                    };
                    let access = match n.output_type(0) {
                        SocketType::Bool => format!("(mg_params.{field} != 0u)"),
                        _ => format!("mg_params.{field}"),
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

        // Node functions in first-use order, helpers before them.
        let mut helpers: Vec<&'static str> = Vec::new();
        let mut functions: Vec<(String, NodeFunction, String)> = Vec::new(); // (key, fn, first node id)
        for &i in &order {
            let n = &nodes[i];
            if !emits_call(n.node_type.evaluation()) || self.folded(i) {
                continue;
            }
            // Keyed by the emitted name: vec3 and colour share one function.
            let key = function_name(&n.node_type, n.generic);
            if functions.iter().any(|(k, ..)| *k == key) {
                continue;
            }
            let f =
                node_function(&n.node_type, n.generic).ok_or_else(|| ShaderError::MissingWgsl {
                    node: n.id.clone(),
                    node_type: n.node_type.name().to_owned(),
                })?;
            for h in n.node_type.wgsl_helpers() {
                if !helpers.contains(h) {
                    helpers.push(h);
                }
            }
            functions.push((key, f, n.id.clone()));
        }

        // Header and declarations.
        let _ = writeln!(
            self.out,
            "// Generated by matgraph {} from graph '{}' ({} entry). Do not edit.\n",
            env!("CARGO_PKG_VERSION"),
            self.graph.name,
            match self.entry {
                Entry::Compute => "compute",
                Entry::Fragment => "fragment",
            }
        );
        let mut bindings = Vec::new();
        if !uniform_fields.is_empty() {
            self.out.push_str("struct MgParams {\n");
            for f in &uniform_fields {
                let ty = match f.ty {
                    SocketType::Bool => "u32",
                    t => wgsl_type(t),
                };
                let _ = writeln!(self.out, "    {}: {ty},", f.field);
            }
            self.out
                .push_str("}\n\n@group(0) @binding(0) var<uniform> mg_params: MgParams;\n\n");
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
            let mut seen: Vec<String> = Vec::new();
            outputs
                .iter()
                .map(|(name, ..)| {
                    let mut f = ident(name);
                    while seen.contains(&f) {
                        f.push('_');
                    }
                    seen.push(f.clone());
                    f
                })
                .collect()
        };
        self.out.push_str("struct MgOutputs {\n");
        for ((_, ty, _), f) in outputs.iter().zip(&out_fields) {
            let _ = writeln!(self.out, "    {f}: {},", wgsl_type(*ty));
        }
        self.out.push_str("}\n\n");

        for h in &helpers {
            self.out.push_str(h.trim());
            self.out.push_str("\n\n");
        }
        for (_, f, first) in &functions {
            let start = self.out.len();
            self.out.push_str(&f.definition);
            self.spans.push((start..self.out.len(), first.clone()));
            self.out.push('\n');
        }

        // The material function.
        let arg = if attributes.is_empty() {
            ""
        } else {
            "geom: MgGeometry"
        };
        let _ = writeln!(self.out, "fn mg_material({arg}) -> MgOutputs {{");
        for &i in &order {
            let n = &nodes[i];
            if !emits_call(n.node_type.evaluation()) || self.folded(i) {
                continue;
            }
            let f = &functions
                .iter()
                .find(|(k, ..)| *k == function_name(&n.node_type, n.generic))
                .expect("declared")
                .1;
            let mut args: Vec<String> = Vec::new();
            if let Some(src) = &n.texture {
                // Texture nodes take their slot in the packed texture set first.
                let key = src.key();
                let slot = self
                    .plan
                    .textures()
                    .iter()
                    .position(|k| *k == key)
                    .unwrap_or(0);
                args.push(format!("{slot}u"));
            }
            args.extend((0..n.inputs.len()).map(|k| self.input_expr(i, k)));
            let var = format!("n{i}_{}", ident(&n.id));
            let start = self.out.len();
            let _ = writeln!(self.out, "    let {var} = {}({});", f.name, args.join(", "));
            self.spans.push((start..self.out.len(), n.id.clone()));
            for k in 0..n.node_type.outputs().len() {
                let e = if f.out_struct.is_some() {
                    format!("{var}.{}", output_member(&n.node_type, k))
                } else {
                    var.clone()
                };
                self.exprs.insert(OutputRef { node: i, output: k }, e);
            }
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

        // The entry point.
        let mut shader_outputs = Vec::new();
        let mut column = 0u32;
        for (name, ty, _) in &outputs {
            shader_outputs.push(ShaderOutput {
                name: name.clone(),
                ty: *ty,
                column,
            });
            column += ty.width() as u32;
        }
        match self.entry {
            Entry::Compute => {
                self.compute_entry(&attributes, &shader_outputs, &out_fields, &mut bindings)
            }
            Entry::Fragment => self.fragment_entry(&attributes, &shader_outputs, &out_fields),
        }
        if !self.plan.textures().is_empty() {
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
        let e = self.exprs.get(&r).cloned().unwrap_or_else(|| "0.0".into());
        convert(&e, from, to)
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
        let mut b = 2;
        for a in attributes {
            let _ = writeln!(
                self.out,
                "@group(0) @binding({b}) var<storage, read> mg_{}: array<f32>;",
                a.name()
            );
            bindings.push((b, Binding::Attribute(*a)));
            b += 1;
        }
        let _ = writeln!(
            self.out,
            "@group(0) @binding({b}) var<storage, read_write> mg_out: array<f32>;\n"
        );
        bindings.push((b, Binding::Output));

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
            for a in attributes {
                let w = a.ty().width();
                let comps: Vec<String> = (0..w)
                    .map(|c| format!("mg_{}[{c}u * n + i]", a.name()))
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
                    self.out,
                    "    mg_out[{}u * n + i] = {e};",
                    o.column as usize + c
                );
            }
        }
        self.out.push_str("}\n");
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
    }
}
