//! The graph's exposed parameters as the editor edits them (issue 35, item 2): an input
//! exposed as a `parameter` node linked into it and listed in the file's `parameters`;
//! parameters added, renamed, documented, grouped, reordered; and un-exposed, which writes
//! the parameter's value back on every input it fed. Each edit builds the new document and
//! hands it to [`EditorDoc`], which refuses one that adds a loader error.
//!
//! A parameter has no range or unit of its own in the file format: the loader checks its
//! value against the hard range of each input it feeds ([`crate::graph::Feed`],
//! `GraphError::ParameterOutOfRange`), and the Parameters panel's slider spans the soft range
//! of the first input it feeds, and shows that input's unit.

use super::model::{EditorDoc, link_json, link_of};
use super::outputs::{OUTPUT_NODE, valid_name};
use super::widgets::current_lanes;
use crate::document::{GraphDocument, NodeDocument, ParameterDocument};
use crate::node::{Attribute, PortType};
use crate::types::SocketType;
use crate::value::Value;
use std::collections::BTreeMap;

/// The side panel's focus id of the parameters editor (not a node id: those are
/// `[A-Za-z0-9_-]+`).
pub const PARAMETERS_PANEL: &str = "@parameters";

/// The node type of exposed parameters.
pub const PARAMETER: &str = "parameter";

/// The types a parameter can have (the `parameter` node's generic types).
pub const TYPES: [SocketType; 5] = [
    SocketType::Float,
    SocketType::Vec2,
    SocketType::Vec3,
    SocketType::Vec4,
    SocketType::Color,
];

/// Why `name` cannot name a parameter of `doc` (`except`: the parameter being renamed), as
/// the loader would refuse it (`GraphError::BadParameter`): a name taken, or a geometry
/// attribute's; and, for the command line's `--param NAME=VALUE`, letters, digits, `_`, `-`.
pub fn name_problem(doc: &GraphDocument, name: &str, except: Option<&str>) -> Option<String> {
    if !valid_name(name) {
        return Some(format!(
            "'{name}' cannot name a parameter: use letters, digits, '_' and '-'"
        ));
    }
    if Attribute::from_name(name).is_some() {
        return Some(format!(
            "'{name}' cannot name a parameter: the name is taken by a geometry attribute"
        ));
    }
    if Some(name) != except && doc.parameters.iter().any(|p| p.name == name) {
        return Some(format!("the graph already has a parameter '{name}'"));
    }
    None
}

/// A parameter name free in `doc` made from `base` (`ior`, `ior_2`, ...; `normal`, a
/// geometry attribute, gives `normal_2`).
pub fn unique_name(doc: &GraphDocument, base: &str) -> String {
    let base: String = base
        .chars()
        .map(|c| match c.is_ascii_alphanumeric() || c == '-' {
            true => c,
            false => '_',
        })
        .collect();
    let base = if base.is_empty() {
        "param".to_owned()
    } else {
        base
    };
    std::iter::once(base.clone())
        .chain((2..).map(|k| format!("{base}_{k}")))
        .find(|n| name_problem(doc, n, None).is_none())
        .expect("a free name exists")
}

/// The parameter (its entry in `parameters`) that exposes node `id`.
pub fn of_node<'d>(doc: &'d GraphDocument, id: &str) -> Option<&'d ParameterDocument> {
    doc.parameters.iter().find(|p| p.node == id)
}

/// The exposed parameter whose node `node.input` is linked to, if any.
pub fn feeding(doc: &EditorDoc, node: &str, input: &str) -> Option<String> {
    let (src, _) = doc.link(node, input)?.split_once('.')?;
    of_node(doc.doc(), src).map(|p| p.name.clone())
}

/// The inputs linked to node `id`'s `value` (a parameter node's), as (node, input), in
/// document order.
pub fn fed_inputs(doc: &GraphDocument, id: &str) -> Vec<(String, String)> {
    let source = format!("{id}.value");
    doc.nodes
        .iter()
        .flat_map(|n| {
            n.inputs
                .iter()
                .filter(|(_, v)| link_of(v) == Some(source.as_str()))
                .map(|(i, _)| (n.id.clone(), i.clone()))
        })
        .collect()
}

/// Whether node `id` is a `parameter` node.
pub fn is_parameter_node(doc: &EditorDoc, id: &str) -> bool {
    doc.node(id).is_some_and(|n| n.node_type == PARAMETER)
}

/// The type and current value (its literal, else its default) of `node.input`, when it
/// can be exposed: an unlinked float, vector or colour input of a node.
pub fn exposable(doc: &EditorDoc, node: &str, input: &str) -> Result<Value, String> {
    if node == OUTPUT_NODE {
        return Err("a graph output cannot be a parameter".into());
    }
    let n = doc.node(node).ok_or_else(|| format!("no node '{node}'"))?;
    if n.node_type == PARAMETER {
        return Err(format!("'{node}' is a parameter node"));
    }
    let decl = doc
        .ports(node)
        .and_then(|p| p.inputs.iter().find(|i| i.name == input))
        .ok_or_else(|| format!("node '{node}' has no input '{input}'"))?;
    if doc.link(node, input).is_some() {
        return Err(format!(
            "'{node}.{input}' is linked: disconnect it to expose its value"
        ));
    }
    // A generic node's type comes from the compiled graph; while the graph does not compile
    // (no outputs yet, say), from the literal written on this input, so that its value is
    // kept (a colour f0 stays a colour).
    let written = n.inputs.get(input);
    let generic = doc
        .generic(node)
        .or_else(|| match decl.ty {
            PortType::Generic => written.and_then(Value::infer_json).map(|v| v.ty()),
            PortType::Fixed(_) => None,
        })
        .unwrap_or(SocketType::Float);
    let ty = decl.ty.resolve(generic);
    if !TYPES.contains(&ty) {
        return Err(format!(
            "'{node}.{input}' is {ty}: only float, vector and colour inputs can be parameters"
        ));
    }
    let default = decl.default_for(generic);
    let lanes = current_lanes(decl, ty, written, &default);
    Ok(Value::from_lanes(ty, &lanes))
}

/// A new `parameter` node `id` of `value`'s type holding it, at `position`.
fn parameter_node(id: &str, value: Value, position: [f32; 2]) -> NodeDocument {
    NodeDocument {
        id: id.to_owned(),
        node_type: PARAMETER.to_owned(),
        // The literal's shape gives float and vectors; a colour must be named.
        data_type: (value.ty() == SocketType::Color).then(|| "color".to_owned()),
        variant: None,
        group: None,
        muted: false,
        inputs: BTreeMap::from([("value".to_owned(), value.to_json())]),
        texture: None,
        color_space: None,
        position: Some(position),
    }
}

/// Exposes `node.input` as a parameter: a `parameter` node holding the input's current
/// value, linked into it and placed left of the node, listed in `parameters` as `name`
/// (default: the input's name, made unique) with the port's doc. Returns the name.
pub fn expose(
    d: &mut EditorDoc,
    node: &str,
    input: &str,
    name: Option<&str>,
) -> Result<String, String> {
    let value = exposable(d, node, input)?;
    let name = match name {
        Some(n) => match name_problem(d.doc(), n, None) {
            Some(problem) => return Err(problem),
            None => n.to_owned(),
        },
        None => unique_name(d.doc(), input),
    };
    let ports = d.ports(node).expect("exposable");
    let k = ports.input_index(input).unwrap_or(0);
    let doc_text = ports.inputs[k].doc.to_string();
    let id = d.fresh_id(&name);
    let [x, y] = d.node(node).and_then(|n| n.position).unwrap_or_default();
    let position = [x - 200.0, y + 24.0 * k as f32];
    let mut candidate = d.doc().clone();
    let target = d.index(node).expect("exposable");
    candidate.nodes[target]
        .inputs
        .insert(input.to_owned(), link_json(&id, "value"));
    candidate.nodes.push(parameter_node(&id, value, position));
    candidate.parameters.push(ParameterDocument {
        name: name.clone(),
        node: id,
        doc: doc_text,
        group: None,
        range: None,
    });
    d.try_replace(candidate)?;
    Ok(name)
}

/// Adds a new, unlinked parameter of type `ty` (its value the type's zero) named `name`
/// (default `param`, made unique), its node left of the graph's nodes. Returns the name.
pub fn add(d: &mut EditorDoc, ty: SocketType, name: Option<&str>) -> Result<String, String> {
    if !TYPES.contains(&ty) {
        return Err(format!("a parameter cannot be {ty}"));
    }
    let name = match name.filter(|n| !n.is_empty()) {
        Some(n) => match name_problem(d.doc(), n, None) {
            Some(problem) => return Err(problem),
            None => n.to_owned(),
        },
        None => unique_name(d.doc(), "param"),
    };
    let id = d.fresh_id(&name);
    let places: Vec<[f32; 2]> = d.doc().nodes.iter().filter_map(|n| n.position).collect();
    let position = match places.is_empty() {
        true => [0.0, 0.0],
        false => [
            places.iter().map(|p| p[0]).fold(f32::MAX, f32::min) - 220.0,
            places.iter().map(|p| p[1]).fold(f32::MAX, f32::min),
        ],
    };
    let mut candidate = d.doc().clone();
    candidate
        .nodes
        .push(parameter_node(&id, Value::zero(ty), position));
    candidate.parameters.push(ParameterDocument {
        name: name.clone(),
        node: id,
        doc: String::new(),
        group: None,
        range: None,
    });
    d.try_replace(candidate)?;
    Ok(name)
}

/// Lists the (unlisted) `parameter` node `id` in `parameters`, named after it (made
/// unique). Returns the name.
pub fn list_node(d: &mut EditorDoc, id: &str) -> Result<String, String> {
    if !is_parameter_node(d, id) {
        return Err(format!("'{id}' is not a parameter node"));
    }
    if let Some(p) = of_node(d.doc(), id) {
        return Err(format!("'{id}' is already the parameter '{}'", p.name));
    }
    let name = unique_name(d.doc(), id);
    let mut candidate = d.doc().clone();
    candidate.parameters.push(ParameterDocument {
        name: name.clone(),
        node: id.to_owned(),
        doc: String::new(),
        group: None,
        range: None,
    });
    d.try_replace(candidate)?;
    Ok(name)
}

/// The index of parameter `name` in `doc`'s `parameters`.
fn position_of(doc: &GraphDocument, name: &str) -> Result<usize, String> {
    doc.parameters
        .iter()
        .position(|p| p.name == name)
        .ok_or_else(|| format!("no parameter '{name}'"))
}

/// Renames parameter `old` to `new` (its node keeps its id); refused for a name the loader
/// would refuse ([`name_problem`]).
pub fn rename(d: &mut EditorDoc, old: &str, new: &str) -> Result<(), String> {
    let k = position_of(d.doc(), old)?;
    if old == new {
        return Ok(());
    }
    if let Some(problem) = name_problem(d.doc(), new, Some(old)) {
        return Err(problem);
    }
    let mut candidate = d.doc().clone();
    candidate.parameters[k].name = new.to_owned();
    d.try_replace(candidate)
}

/// Sets parameter `name`'s doc.
pub fn set_doc(d: &mut EditorDoc, name: &str, text: &str) -> Result<(), String> {
    let k = position_of(d.doc(), name)?;
    let mut candidate = d.doc().clone();
    candidate.parameters[k].doc = text.to_owned();
    d.try_replace(candidate)
}

/// Sets parameter `name`'s group (`""`: none).
pub fn set_group(d: &mut EditorDoc, name: &str, group: &str) -> Result<(), String> {
    let k = position_of(d.doc(), name)?;
    let mut candidate = d.doc().clone();
    let group = group.trim();
    candidate.parameters[k].group = (!group.is_empty()).then(|| group.to_owned());
    d.try_replace(candidate)
}

/// Moves parameter `name` one place up (`up`) or down in `parameters` (the panel's and the
/// callers' order); nothing at either end.
pub fn move_by_one(d: &mut EditorDoc, name: &str, up: bool) -> Result<(), String> {
    let k = position_of(d.doc(), name)?;
    let j = match up {
        true => k.checked_sub(1),
        false => Some(k + 1).filter(|&j| j < d.doc().parameters.len()),
    };
    let Some(j) = j else { return Ok(()) };
    let mut candidate = d.doc().clone();
    candidate.parameters.swap(k, j);
    d.try_replace(candidate)
}

/// Un-exposes parameter `name`: its entry leaves `parameters`, and every input linked to
/// its node gets the parameter's value as a literal (converted to the input's type, as the
/// link converted it); the node is deleted when nothing else reads it (a graph output,
/// another entry). Returns the inputs that got the value, as `node.input`.
pub fn unexpose(d: &mut EditorDoc, name: &str) -> Result<Vec<String>, String> {
    let k = position_of(d.doc(), name)?;
    let id = d.doc().parameters[k].node.clone();
    let written = d
        .node(&id)
        .and_then(|n| n.inputs.get("value"))
        .cloned()
        .unwrap_or(serde_json::json!(0.0));
    // The value with its type: the loader's, else the literal's shape (a colour named).
    let value = d
        .graph()
        .and_then(|g| g.parameters().iter().find(|p| p.name == name))
        .map(|p| p.default)
        .or_else(|| {
            let v = Value::infer_json(&written)?;
            match d.node(&id)?.data_type.as_deref() {
                Some("color") => v.convert(SocketType::Color),
                _ => Some(v),
            }
        });
    let source = format!("{id}.value");
    let mut candidate = d.doc().clone();
    candidate.parameters.remove(k);
    let mut fed = Vec::new();
    for n in &mut candidate.nodes {
        for (input, v) in n.inputs.iter_mut() {
            if link_of(v) != Some(source.as_str()) {
                continue;
            }
            let to = d
                .ports(&n.id)
                .and_then(|p| p.inputs.iter().find(|i| i.name == input.as_str()))
                .and_then(|decl| d.port_type(&n.id, decl.ty));
            *v = match (value, to) {
                (Some(value), Some(to)) => {
                    value.convert(to).map_or(written.clone(), |c| c.to_json())
                }
                _ => written.clone(),
            };
            fed.push(format!("{}.{input}", n.id));
        }
    }
    let read = candidate.parameters.iter().any(|p| p.node == id)
        || candidate
            .outputs
            .iter()
            .any(|o| o.from.split_once('.').is_some_and(|(n, _)| n == id));
    if !read {
        candidate.nodes.retain(|n| n.id != id);
        for f in &mut candidate.frames {
            f.nodes.retain(|n| *n != id);
        }
    }
    d.replace(candidate);
    Ok(fed)
}
