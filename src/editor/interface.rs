//! Editing a group's interface (the side panel inside a group, or on an instance of a group
//! of this file): its inputs (add, rename, remove, reorder, type, default, soft and hard
//! range, unit, doc), its outputs (add, rename, remove, reorder; an output's type is what it
//! reads) and its doc. Each edit works on the whole document (the root): renaming an input
//! renames the `@in.NAME` links inside the group and the entry on every instance; renaming
//! an output renames what reads it on every instance; removing one drops them. Each is
//! checked by the loader: an edit that adds an error (a default outside the hard range, a
//! type the links inside cannot take, a name taken) is refused with its message; adding and
//! removing are applied as deleting a node is (an output just added reads nothing yet, and
//! the loader says so until it is wired).

use super::model::{EditorDoc, link_json, link_of};
use super::outputs::valid_name;
use super::scope::{fresh, interface_type, relink_input};
use crate::document::{GraphDocument, GroupDocument, GroupInputDocument, NodeDocument};
use crate::group::GROUP;
use crate::types::SocketType;
use crate::value::Value;
use std::collections::HashSet;

/// The group `group` of `doc`, or why there is none.
fn group_mut<'d>(doc: &'d mut GraphDocument, group: &str) -> Result<&'d mut GroupDocument, String> {
    doc.groups
        .get_mut(group)
        .ok_or_else(|| format!("no group '{group}' in this file"))
}

/// Applies `f` to every scope of `doc` (its top, each group's body) with the ids of the
/// instances of group `group` there: the nodes and outputs that may read them.
fn each_scope(
    doc: &mut GraphDocument,
    group: &str,
    mut f: impl FnMut(&mut [NodeDocument], &mut [crate::document::OutputDocument], &[String]),
) {
    let ids = |nodes: &[NodeDocument]| -> Vec<String> {
        nodes
            .iter()
            .filter(|n| n.node_type == GROUP && n.group.as_deref() == Some(group))
            .map(|n| n.id.clone())
            .collect()
    };
    let top = ids(&doc.nodes);
    f(&mut doc.nodes, &mut doc.outputs, &top);
    for g in doc.groups.values_mut() {
        let inner = ids(&g.nodes);
        f(&mut g.nodes, &mut g.outputs, &inner);
    }
}

/// Why `name` cannot name an input or output of `group` (`except`: the one renamed).
fn name_problem(names: &[&str], name: &str, except: Option<&str>, what: &str) -> Option<String> {
    if !valid_name(name) {
        return Some(format!(
            "'{name}' cannot name a group {what}: use letters, digits, '_' and '-'"
        ));
    }
    (Some(name) != except && names.contains(&name))
        .then(|| format!("the group already has an {what} '{name}'"))
}

/// The input `name` of `g`.
fn input_mut<'g>(
    g: &'g mut GroupDocument,
    name: &str,
) -> Result<&'g mut GroupInputDocument, String> {
    g.inputs
        .iter_mut()
        .find(|i| i.name == name)
        .ok_or_else(|| format!("the group has no input '{name}'"))
}

/// Adds an input of type `ty` to `group` (named `name`, else `input`, made unique); returns
/// its name.
pub fn add_input(
    d: &mut EditorDoc,
    group: &str,
    name: Option<&str>,
    ty: SocketType,
) -> Result<String, String> {
    if !interface_type(ty) {
        return Err(format!(
            "a group's inputs are float, vec2, vec3, vec4 or color, not {ty}"
        ));
    }
    let mut doc = d.doc().clone();
    let g = group_mut(&mut doc, group)?;
    let taken: HashSet<String> = g.inputs.iter().map(|i| i.name.clone()).collect();
    let name = match name.filter(|n| !n.is_empty()) {
        Some(n) => {
            let names: Vec<&str> = g.inputs.iter().map(|i| i.name.as_str()).collect();
            if let Some(p) = name_problem(&names, n, None, "input") {
                return Err(p);
            }
            n.to_owned()
        }
        None => fresh("input", &taken),
    };
    g.inputs.push(GroupInputDocument {
        name: name.clone(),
        ty: ty.name().to_owned(),
        default: None,
        soft_range: None,
        hard_range: None,
        unit: None,
        doc: String::new(),
    });
    d.try_replace(doc)?;
    Ok(name)
}

/// Renames input `old` of `group` to `new`: the `@in` links inside and the instances'
/// entries follow.
pub fn rename_input(d: &mut EditorDoc, group: &str, old: &str, new: &str) -> Result<(), String> {
    if old == new {
        return Ok(());
    }
    let mut doc = d.doc().clone();
    let g = group_mut(&mut doc, group)?;
    let names: Vec<&str> = g.inputs.iter().map(|i| i.name.as_str()).collect();
    if let Some(p) = name_problem(&names, new, Some(old), "input") {
        return Err(p);
    }
    input_mut(g, old)?.name = new.to_owned();
    relink_input(&mut g.nodes, &mut g.outputs, old, Some(new));
    each_scope(&mut doc, group, |nodes, _, ids| {
        for n in nodes.iter_mut().filter(|n| ids.contains(&n.id)) {
            if let Some(v) = n.inputs.remove(old) {
                n.inputs.insert(new.to_owned(), v);
            }
        }
    });
    d.try_replace(doc)
}

/// Removes input `name` of `group`: what read it inside takes its default again (a group
/// output reading it reads nothing), and the instances drop their entry.
pub fn remove_input(d: &mut EditorDoc, group: &str, name: &str) -> Result<(), String> {
    let mut doc = d.doc().clone();
    let g = group_mut(&mut doc, group)?;
    let before = g.inputs.len();
    g.inputs.retain(|i| i.name != name);
    if g.inputs.len() == before {
        return Err(format!("the group has no input '{name}'"));
    }
    relink_input(&mut g.nodes, &mut g.outputs, name, None);
    each_scope(&mut doc, group, |nodes, _, ids| {
        for n in nodes.iter_mut().filter(|n| ids.contains(&n.id)) {
            n.inputs.remove(name);
        }
    });
    d.replace(doc);
    Ok(())
}

/// Moves input `name` of `group` one place up or down.
pub fn move_input(d: &mut EditorDoc, group: &str, name: &str, up: bool) -> Result<(), String> {
    let mut doc = d.doc().clone();
    let g = group_mut(&mut doc, group)?;
    let k = g
        .inputs
        .iter()
        .position(|i| i.name == name)
        .ok_or_else(|| format!("the group has no input '{name}'"))?;
    let to = match up {
        true => k.checked_sub(1),
        false => (k + 1 < g.inputs.len()).then_some(k + 1),
    };
    if let Some(to) = to {
        g.inputs.swap(k, to);
    }
    d.try_replace(doc)
}

/// `json`, a literal of type `from`, as type `to` (`None` when it does not convert).
fn convert(
    json: &serde_json::Value,
    from: Option<SocketType>,
    to: SocketType,
) -> Option<serde_json::Value> {
    let v = Value::from_json(from?, json)?;
    Some(v.convert(to)?.to_json())
}

/// Sets input `name` of `group` to type `ty`: its default and the instances' literals are
/// converted (dropped where they do not convert); refused when the links inside cannot
/// take the type.
pub fn set_input_type(
    d: &mut EditorDoc,
    group: &str,
    name: &str,
    ty: SocketType,
) -> Result<(), String> {
    if !interface_type(ty) {
        return Err(format!(
            "a group's inputs are float, vec2, vec3, vec4 or color, not {ty}"
        ));
    }
    let mut doc = d.doc().clone();
    let g = group_mut(&mut doc, group)?;
    let i = input_mut(g, name)?;
    let old = SocketType::from_name(&i.ty);
    if old == Some(ty) {
        return Ok(());
    }
    i.ty = ty.name().to_owned();
    i.default = i.default.as_ref().and_then(|v| convert(v, old, ty));
    each_scope(&mut doc, group, |nodes, _, ids| {
        for n in nodes.iter_mut().filter(|n| ids.contains(&n.id)) {
            let Some(v) = n.inputs.get(name).filter(|v| link_of(v).is_none()) else {
                continue;
            };
            match convert(v, old, ty) {
                Some(c) => {
                    n.inputs.insert(name.to_owned(), c);
                }
                None => {
                    n.inputs.remove(name);
                }
            }
        }
    });
    d.try_replace(doc)
}

/// Sets input `name`'s default (`None`: the type's zero); refused outside its hard range.
pub fn set_input_default(
    d: &mut EditorDoc,
    group: &str,
    name: &str,
    value: Option<Value>,
) -> Result<(), String> {
    let mut doc = d.doc().clone();
    let i = input_mut(group_mut(&mut doc, group)?, name)?;
    i.default = value
        .filter(|v| *v != Value::zero(v.ty()))
        .map(|v| v.to_json());
    d.try_replace(doc)
}

/// Sets input `name`'s soft range (`hard`: its hard range), `None` removing it; refused
/// where min > max, or the default or an instance's literal falls outside a hard range.
pub fn set_input_range(
    d: &mut EditorDoc,
    group: &str,
    name: &str,
    hard: bool,
    range: Option<[f32; 2]>,
) -> Result<(), String> {
    let mut doc = d.doc().clone();
    let i = input_mut(group_mut(&mut doc, group)?, name)?;
    match hard {
        true => i.hard_range = range,
        false => i.soft_range = range,
    }
    d.try_replace(doc)
}

/// Sets input `name`'s unit (`""`: none).
pub fn set_input_unit(
    d: &mut EditorDoc,
    group: &str,
    name: &str,
    unit: &str,
) -> Result<(), String> {
    let mut doc = d.doc().clone();
    let i = input_mut(group_mut(&mut doc, group)?, name)?;
    i.unit = (!unit.is_empty()).then(|| unit.to_owned());
    d.try_replace(doc)
}

/// Sets input `name`'s doc.
pub fn set_input_doc(d: &mut EditorDoc, group: &str, name: &str, text: &str) -> Result<(), String> {
    let mut doc = d.doc().clone();
    input_mut(group_mut(&mut doc, group)?, name)?.doc = text.to_owned();
    d.try_replace(doc)
}

/// Sets the group's doc.
pub fn set_group_doc(d: &mut EditorDoc, group: &str, text: &str) -> Result<(), String> {
    let mut doc = d.doc().clone();
    group_mut(&mut doc, group)?.doc = text.to_owned();
    d.try_replace(doc)
}

/// Adds output `name` (else `output`, made unique) to `group`, reading nothing yet (the
/// loader reports it until it is wired inside); returns its name.
pub fn add_output(d: &mut EditorDoc, group: &str, name: Option<&str>) -> Result<String, String> {
    let mut doc = d.doc().clone();
    let g = group_mut(&mut doc, group)?;
    let taken: HashSet<String> = g.outputs.iter().map(|o| o.name.clone()).collect();
    let name = match name.filter(|n| !n.is_empty()) {
        Some(n) => {
            let names: Vec<&str> = g.outputs.iter().map(|o| o.name.as_str()).collect();
            if let Some(p) = name_problem(&names, n, None, "output") {
                return Err(p);
            }
            n.to_owned()
        }
        None => fresh("output", &taken),
    };
    g.outputs.push(crate::document::OutputDocument {
        name: name.clone(),
        from: String::new(),
    });
    d.replace(doc);
    Ok(name)
}

/// Renames output `old` of `group` to `new`: whatever reads it on an instance follows.
pub fn rename_output(d: &mut EditorDoc, group: &str, old: &str, new: &str) -> Result<(), String> {
    if old == new {
        return Ok(());
    }
    let mut doc = d.doc().clone();
    let g = group_mut(&mut doc, group)?;
    let names: Vec<&str> = g.outputs.iter().map(|o| o.name.as_str()).collect();
    if let Some(p) = name_problem(&names, new, Some(old), "output") {
        return Err(p);
    }
    g.outputs
        .iter_mut()
        .find(|o| o.name == old)
        .ok_or_else(|| format!("the group has no output '{old}'"))?
        .name = new.to_owned();
    each_scope(&mut doc, group, |nodes, outputs, ids| {
        let renamed = |l: &str| -> Option<String> {
            let (src, out) = l.split_once('.')?;
            (out == old && ids.iter().any(|i| i == src)).then(|| src.to_owned())
        };
        for n in nodes.iter_mut() {
            for v in n.inputs.values_mut() {
                if let Some(src) = link_of(v).and_then(renamed) {
                    *v = link_json(&src, new);
                }
            }
        }
        for o in outputs.iter_mut() {
            if let Some(src) = renamed(&o.from) {
                o.from = format!("{src}.{new}");
            }
        }
    });
    d.try_replace(doc)
}

/// Removes output `name` of `group`: the inputs that read it on an instance take their
/// defaults again; a graph output reading it keeps naming it (the loader reports it), as
/// one reading a deleted node does.
pub fn remove_output(d: &mut EditorDoc, group: &str, name: &str) -> Result<(), String> {
    let mut doc = d.doc().clone();
    let g = group_mut(&mut doc, group)?;
    let before = g.outputs.len();
    g.outputs.retain(|o| o.name != name);
    if g.outputs.len() == before {
        return Err(format!("the group has no output '{name}'"));
    }
    each_scope(&mut doc, group, |nodes, _, ids| {
        let reads = |l: &str| {
            l.split_once('.')
                .is_some_and(|(src, out)| out == name && ids.iter().any(|i| i == src))
        };
        for n in nodes.iter_mut() {
            n.inputs.retain(|_, v| link_of(v).is_none_or(|l| !reads(l)));
        }
    });
    d.replace(doc);
    Ok(())
}

/// Moves output `name` of `group` one place up or down.
pub fn move_output(d: &mut EditorDoc, group: &str, name: &str, up: bool) -> Result<(), String> {
    let mut doc = d.doc().clone();
    let g = group_mut(&mut doc, group)?;
    let k = g
        .outputs
        .iter()
        .position(|o| o.name == name)
        .ok_or_else(|| format!("the group has no output '{name}'"))?;
    let to = match up {
        true => k.checked_sub(1),
        false => (k + 1 < g.outputs.len()).then_some(k + 1),
    };
    if let Some(to) = to {
        g.outputs.swap(k, to);
    }
    d.try_replace(doc)
}
