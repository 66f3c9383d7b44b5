//! A compute module that runs one node type's WGSL function on packed samples, for the
//! node-level CPU/GPU parity tests and for anyone checking a node's WGSL in isolation.

use super::emit::{Form, UniformSpec, node_function, output_member, params_block};
use super::{ShaderError, UniformLayout, WORKGROUP_SIZE, validate};
use crate::node::{NodeType, WgslChoice};
use crate::types::SocketType;
use crate::value::Value;
use std::fmt::Write;

/// A validated harness module.
///
/// Bindings (group 0): 0 `mg_in: array<f32>` with `input_width` floats per sample (inputs
/// in port order, ints and bools as floats), 1 `mg_out: array<f32>` with `output_width`
/// floats per sample (bools as 0.0 / 1.0), 2 the `MgDispatch { count, row }` uniform, and
/// 3 `mg_params` holding the node's constant tables ([`HarnessModule::params`]) if it has any.
#[derive(Clone, Debug)]
pub struct HarnessModule {
    /// The WGSL text.
    pub source: String,
    /// naga IR.
    pub module: naga::Module,
    /// Floats per sample in `mg_in`.
    pub input_width: usize,
    /// Floats per sample in `mg_out`.
    pub output_width: usize,
    /// The bytes of `mg_params` (binding 3): the node's constant tables; empty without any.
    pub params: Vec<u8>,
}

/// Builds the harness of `t` for generic type `generic` (ignored for non-generic nodes).
pub fn node_harness(t: &NodeType, generic: SocketType) -> Result<HarnessModule, ShaderError> {
    harness(t, generic, Form::default())
}

/// Builds the harness of `t` at one written choice of its choice input (see
/// [`crate::node::WgslChoices`]): the function ignores that input, so feed it the choice.
pub fn node_choice_harness(
    t: &NodeType,
    generic: SocketType,
    choice: &WgslChoice,
) -> Result<HarnessModule, ShaderError> {
    harness(
        t,
        generic,
        Form {
            choice: Some(choice),
            constants: &[],
        },
    )
}

/// Builds the harness of `t` with the inputs of `constants` (by input index; each declared
/// by [`NodeType::wgsl_constant_inputs`]) compiled into its function as an emitted graph
/// does where the file writes them: the function ignores those inputs, so feed them the
/// same values.
pub fn node_constant_harness(
    t: &NodeType,
    generic: SocketType,
    constants: &[(usize, Value)],
) -> Result<HarnessModule, ShaderError> {
    harness(
        t,
        generic,
        Form {
            choice: None,
            constants,
        },
    )
}

/// The harness of `t` in one emitted form of its function.
fn harness(t: &NodeType, generic: SocketType, form: Form) -> Result<HarnessModule, ShaderError> {
    let choice = form.choice;
    let f = node_function(t, generic, form).ok_or_else(|| ShaderError::MissingWgsl {
        node: t.name().to_owned(),
        node_type: t.name().to_owned(),
    })?;
    let mut s = String::new();
    for h in t.wgsl_helpers_for(choice) {
        s.push_str(h.trim());
        s.push_str("\n\n");
    }
    s.push_str(&f.definition);
    s.push_str("\n@group(0) @binding(0) var<storage, read> mg_in: array<f32>;\n");
    s.push_str("@group(0) @binding(1) var<storage, read_write> mg_out: array<f32>;\n");
    s.push_str("struct MgDispatch {\n    count: u32,\n    row: u32,\n}\n");
    s.push_str("@group(0) @binding(2) var<uniform> mg_dispatch: MgDispatch;\n\n");
    let tables: Vec<UniformSpec> = t
        .wgsl_tables_for(choice)
        .into_iter()
        .map(UniformSpec::table)
        .collect();
    if !tables.is_empty() {
        s.push_str(&params_block(&tables, 3));
    }
    let _ = writeln!(s, "@compute @workgroup_size({WORKGROUP_SIZE})");
    s.push_str("fn mg_compute(@builtin(global_invocation_id) id: vec3<u32>) {\n");
    s.push_str("    let i = id.x + id.y * mg_dispatch.row;\n    if (i >= mg_dispatch.count) {\n        return;\n    }\n");

    let in_width: usize = t
        .inputs()
        .iter()
        .map(|d| d.ty.resolve(generic).width())
        .sum();
    let out_width: usize = t
        .outputs()
        .iter()
        .map(|d| d.ty.resolve(generic).width())
        .sum();
    let _ = writeln!(s, "    let b = i * {in_width}u;");
    let mut at = 0;
    let mut args = Vec::new();
    for (k, d) in t.inputs().iter().enumerate() {
        let ty = d.ty.resolve(generic);
        let lane = |c: usize| format!("mg_in[b + {}u]", at + c);
        let e = match ty {
            SocketType::Float => lane(0),
            SocketType::Int => format!("i32({})", lane(0)),
            SocketType::Bool => format!("({} != 0.0)", lane(0)),
            t => format!(
                "{}({})",
                super::wgsl_type(t),
                (0..t.width()).map(lane).collect::<Vec<_>>().join(", ")
            ),
        };
        at += ty.width();
        if form.constants.iter().any(|(c, _)| *c == k) {
            continue;
        }
        let _ = writeln!(s, "    let a{k} = {e};");
        args.push(format!("a{k}"));
    }
    let _ = writeln!(s, "    let r = {}({});", f.name, args.join(", "));
    let _ = writeln!(s, "    let o = i * {out_width}u;");
    let mut at = 0;
    for (k, d) in t.outputs().iter().enumerate() {
        let ty = d.ty.resolve(generic);
        let v = if f.out_struct.is_some() {
            format!("r.{}", output_member(t, k))
        } else {
            "r".to_owned()
        };
        for c in 0..ty.width() {
            let e = match ty {
                SocketType::Bool => format!("select(0.0, 1.0, {v})"),
                SocketType::Int => format!("f32({v})"),
                SocketType::Float => v.clone(),
                _ => format!("{v}.{}", ["x", "y", "z", "w"][c]),
            };
            let _ = writeln!(s, "    mg_out[o + {}u] = {e};", at + c);
        }
        at += ty.width();
    }
    s.push_str("}\n");
    let span = 0..s.len();
    let (module, _) = validate::validate(&s, &[(span, t.name().to_owned())])?;
    let params = match tables.is_empty() {
        true => Vec::new(),
        false => UniformLayout::read(&module, &tables).pack(&Default::default(), 0.0),
    };
    Ok(HarnessModule {
        source: s,
        module,
        input_width: in_width,
        output_width: out_width,
        params,
    })
}
