//! The graph's variant sets as the editor edits them (issue 35, item 4): a set declared in
//! the file's top-level `variants` (`{"fresnel": {"choices": ["schlick", "exact"], "default":
//! "exact", "doc": "…"}}`, see [`crate::variant`]), its choices added, renamed, removed and
//! reordered, its default set, the set renamed, documented and deleted; and `switch` nodes
//! bound to a set, one input per choice. Each edit builds the new document and hands it to
//! [`EditorDoc::replace`]; names are checked first as the loader checks them (letters,
//! digits, `_`, `-`, unique).
//!
//! A switch's inputs are named after its set's choices, so every edit of the choices keeps
//! the switches bound to the set in step: a renamed choice renames their input (its wire
//! kept), a removed one drops it, and a new one gets the link of the default choice's input
//! (the graph stays valid and renders as before; rewire it). Deleting a set that switches
//! use replaces each of them by its default choice: every input and graph output reading
//! the switch reads that choice's source, and the switch goes, so the graph renders as its
//! file did. Which choice the preview shows is not part of the file
//! ([`super::preview::Preview::set_variant`]).

use super::model::{EditorDoc, link_json, link_of};
use super::outputs::valid_name;
use super::state::EditorState;
use crate::document::{GraphDocument, NodeDocument, VariantDocument};
use crate::error::GraphError;
use crate::variant::{SWITCH, SWITCH_OUTPUT};
use std::collections::BTreeMap;

/// The side panel's focus id of the variants editor (not a node id: those are
/// `[A-Za-z0-9_-]+`).
pub const VARIANTS_PANEL: &str = "@variants";

/// The choices of a set added without any named.
pub const NEW_CHOICES: [&str; 2] = ["a", "b"];

/// Why `name` cannot name a variant set of `doc` (`except`: the set being renamed), as the
/// loader would refuse it: not letters, digits, `_`, `-`, or taken.
pub fn set_name_problem(doc: &GraphDocument, name: &str, except: Option<&str>) -> Option<String> {
    if !valid_name(name) {
        return Some(format!(
            "'{name}' cannot name a variant set: use letters, digits, '_' and '-'"
        ));
    }
    if Some(name) != except && doc.variants.contains_key(name) {
        return Some(format!("the graph already has a variant set '{name}'"));
    }
    None
}

/// Why `choice` cannot be a choice of set `set` of `doc` (`except`: the choice being
/// renamed): not letters, digits, `_`, `-`, or already one of its choices.
pub fn choice_problem(
    doc: &GraphDocument,
    set: &str,
    choice: &str,
    except: Option<&str>,
) -> Option<String> {
    if !valid_name(choice) {
        return Some(format!(
            "'{choice}' cannot be a choice: use letters, digits, '_' and '-'"
        ));
    }
    let taken = doc
        .variants
        .get(set)
        .is_some_and(|v| v.choices.iter().any(|c| c == choice));
    if Some(choice) != except && taken {
        return Some(format!(
            "variant set '{set}' already has a choice '{choice}'"
        ));
    }
    None
}

/// A name free in `names` made from `base` (`base`, `base_2`, ...).
fn unique(base: &str, taken: impl Fn(&str) -> bool) -> String {
    std::iter::once(base.to_owned())
        .chain((2..).map(|k| format!("{base}_{k}")))
        .find(|n| !taken(n))
        .expect("a free name exists")
}

/// The ids of the `switch` nodes bound to set `set`, in document order.
pub fn switches_of(doc: &GraphDocument, set: &str) -> Vec<String> {
    doc.nodes
        .iter()
        .filter(|n| n.node_type == SWITCH && n.variant.as_deref() == Some(set))
        .map(|n| n.id.clone())
        .collect()
}

/// Whether node `id` of `doc` is a `switch`.
pub fn is_switch(doc: &EditorDoc, id: &str) -> bool {
    doc.node(id).is_some_and(|n| n.node_type == SWITCH)
}

/// The set `name` of `doc`, or why there is none.
fn set_of<'d>(doc: &'d GraphDocument, name: &str) -> Result<&'d VariantDocument, String> {
    doc.variants
        .get(name)
        .ok_or_else(|| format!("no variant set '{name}'"))
}

/// The index of `choice` in set `set` of `doc`.
fn choice_index(doc: &GraphDocument, set: &str, choice: &str) -> Result<usize, String> {
    set_of(doc, set)?
        .choices
        .iter()
        .position(|c| c == choice)
        .ok_or_else(|| format!("variant set '{set}' has no choice '{choice}'"))
}

/// Applies `f` to each switch of `doc` bound to `set`.
fn each_switch(doc: &mut GraphDocument, set: &str, mut f: impl FnMut(&mut NodeDocument)) {
    for n in &mut doc.nodes {
        if n.node_type == SWITCH && n.variant.as_deref() == Some(set) {
            f(n);
        }
    }
}

/// Declares a variant set `name` (default `variant`, made unique) with `choices` (default
/// [`NEW_CHOICES`]), its default the first. Returns the name.
pub fn add_set(d: &mut EditorDoc, name: Option<&str>, choices: &[&str]) -> Result<String, String> {
    let doc = d.doc();
    let name = match name.filter(|n| !n.is_empty()) {
        Some(n) => match set_name_problem(doc, n, None) {
            Some(problem) => return Err(problem),
            None => n.to_owned(),
        },
        None => unique("variant", |n| doc.variants.contains_key(n)),
    };
    let choices: Vec<String> = match choices.is_empty() {
        true => NEW_CHOICES.map(str::to_owned).to_vec(),
        false => choices.iter().map(|c| c.to_string()).collect(),
    };
    for (k, c) in choices.iter().enumerate() {
        if !valid_name(c) {
            return Err(format!(
                "'{c}' cannot be a choice: use letters, digits, '_' and '-'"
            ));
        }
        if choices[..k].contains(c) {
            return Err(format!("choice '{c}' is repeated"));
        }
    }
    let mut candidate = doc.clone();
    candidate.variants.insert(
        name.clone(),
        VariantDocument {
            default: choices[0].clone(),
            choices,
            doc: String::new(),
        },
    );
    d.replace(candidate);
    Ok(name)
}

/// Renames set `old` to `new`; every switch bound to it follows.
pub fn rename_set(d: &mut EditorDoc, old: &str, new: &str) -> Result<(), String> {
    set_of(d.doc(), old)?;
    if old == new {
        return Ok(());
    }
    if let Some(problem) = set_name_problem(d.doc(), new, Some(old)) {
        return Err(problem);
    }
    let mut candidate = d.doc().clone();
    let v = candidate.variants.remove(old).expect("checked");
    candidate.variants.insert(new.to_owned(), v);
    each_switch(&mut candidate, old, |n| n.variant = Some(new.to_owned()));
    d.replace(candidate);
    Ok(())
}

/// Sets set `set`'s doc.
pub fn set_doc(d: &mut EditorDoc, set: &str, text: &str) -> Result<(), String> {
    set_of(d.doc(), set)?;
    let mut candidate = d.doc().clone();
    candidate.variants.get_mut(set).expect("checked").doc = text.to_owned();
    d.replace(candidate);
    Ok(())
}

/// Adds a choice `name` (default `choice`, made unique) at the end of set `set`. Each switch
/// bound to the set gets an input for it holding the link of its default choice's input, so
/// that the graph stays valid and renders as before. Returns the choice.
pub fn add_choice(d: &mut EditorDoc, set: &str, name: Option<&str>) -> Result<String, String> {
    let v = set_of(d.doc(), set)?;
    let choice = match name.filter(|n| !n.is_empty()) {
        Some(n) => match choice_problem(d.doc(), set, n, None) {
            Some(problem) => return Err(problem),
            None => n.to_owned(),
        },
        None => unique("choice", |c| v.choices.iter().any(|x| x == c)),
    };
    let default = v.default.clone();
    let mut candidate = d.doc().clone();
    candidate
        .variants
        .get_mut(set)
        .expect("checked")
        .choices
        .push(choice.clone());
    each_switch(&mut candidate, set, |n| {
        if let Some(link) = n.inputs.get(&default).filter(|j| link_of(j).is_some()) {
            let link = link.clone();
            n.inputs.insert(choice.clone(), link);
        }
    });
    d.replace(candidate);
    Ok(choice)
}

/// Renames choice `old` of set `set` to `new`: the default follows, and so does the input
/// of every switch bound to the set (its wire kept).
pub fn rename_choice(d: &mut EditorDoc, set: &str, old: &str, new: &str) -> Result<(), String> {
    let k = choice_index(d.doc(), set, old)?;
    if old == new {
        return Ok(());
    }
    if let Some(problem) = choice_problem(d.doc(), set, new, Some(old)) {
        return Err(problem);
    }
    let mut candidate = d.doc().clone();
    let v = candidate.variants.get_mut(set).expect("checked");
    v.choices[k] = new.to_owned();
    if v.default == old {
        v.default = new.to_owned();
    }
    each_switch(&mut candidate, set, |n| {
        if let Some(link) = n.inputs.remove(old) {
            n.inputs.insert(new.to_owned(), link);
        }
    });
    d.replace(candidate);
    Ok(())
}

/// Removes choice `choice` of set `set` (refused for its last one: a set needs a choice).
/// The switches bound to the set drop its input and wire; a removed default becomes the
/// first choice left.
pub fn remove_choice(d: &mut EditorDoc, set: &str, choice: &str) -> Result<(), String> {
    let k = choice_index(d.doc(), set, choice)?;
    if set_of(d.doc(), set)?.choices.len() == 1 {
        return Err(format!(
            "'{choice}' is the only choice of variant set '{set}': a set needs one (delete the set instead)"
        ));
    }
    let mut candidate = d.doc().clone();
    let v = candidate.variants.get_mut(set).expect("checked");
    v.choices.remove(k);
    if v.default == choice {
        v.default = v.choices[0].clone();
    }
    each_switch(&mut candidate, set, |n| {
        n.inputs.remove(choice);
    });
    d.replace(candidate);
    Ok(())
}

/// Moves choice `choice` of set `set` one place up (`up`) or down; nothing at either end.
/// The switches' pins follow the set's order.
pub fn move_choice(d: &mut EditorDoc, set: &str, choice: &str, up: bool) -> Result<(), String> {
    let k = choice_index(d.doc(), set, choice)?;
    let len = set_of(d.doc(), set)?.choices.len();
    let j = match up {
        true => k.checked_sub(1),
        false => Some(k + 1).filter(|&j| j < len),
    };
    let Some(j) = j else { return Ok(()) };
    let mut candidate = d.doc().clone();
    candidate
        .variants
        .get_mut(set)
        .expect("checked")
        .choices
        .swap(k, j);
    d.replace(candidate);
    Ok(())
}

/// Makes `choice` the default of set `set` (what the file renders without a selection).
pub fn set_default(d: &mut EditorDoc, set: &str, choice: &str) -> Result<(), String> {
    choice_index(d.doc(), set, choice)?;
    let mut candidate = d.doc().clone();
    candidate.variants.get_mut(set).expect("checked").default = choice.to_owned();
    d.replace(candidate);
    Ok(())
}

/// Deletes set `set`. Each switch bound to it is replaced by its default choice: the inputs
/// and graph outputs reading the switch read the source of its default choice's input
/// (nothing, where that input is not wired), and the switch is removed. Returns the
/// switches removed, each with what its readers read now.
pub fn remove_set(d: &mut EditorDoc, set: &str) -> Result<Vec<(String, Option<String>)>, String> {
    let default = set_of(d.doc(), set)?.default.clone();
    let mut candidate = d.doc().clone();
    candidate.variants.remove(set);
    let replaced: Vec<(String, Option<String>)> = candidate
        .nodes
        .iter()
        .filter(|n| n.node_type == SWITCH && n.variant.as_deref() == Some(set))
        .map(|n| {
            let link = n.inputs.get(&default).and_then(link_of).map(str::to_owned);
            (n.id.clone(), link)
        })
        .collect();
    for (id, link) in &replaced {
        let read = format!("{id}.{SWITCH_OUTPUT}");
        for n in &mut candidate.nodes {
            n.inputs
                .retain(|_, j| link.is_some() || link_of(j) != Some(read.as_str()));
            for j in n.inputs.values_mut() {
                if let Some(l) = link.as_deref()
                    && link_of(j) == Some(read.as_str())
                {
                    let (src, out) = l.split_once('.').unwrap_or((l, ""));
                    *j = link_json(src, out);
                }
            }
        }
        for o in &mut candidate.outputs {
            if o.from == read {
                o.from = link.clone().unwrap_or_default();
            }
        }
    }
    let gone: Vec<&String> = replaced.iter().map(|(id, _)| id).collect();
    candidate.nodes.retain(|n| !gone.contains(&&n.id));
    for f in &mut candidate.frames {
        f.nodes.retain(|n| !gone.contains(&n));
    }
    d.replace(candidate);
    Ok(replaced)
}

/// Adds a `switch` node bound to set `set` at `position`, its id made from the set's name;
/// its inputs (one per choice) are unwired, which the loader reports until each is wired.
/// Returns its id.
pub fn add_switch(d: &mut EditorDoc, set: &str, position: [f32; 2]) -> Result<String, String> {
    set_of(d.doc(), set)?;
    let id = d.fresh_id(set);
    let mut candidate = d.doc().clone();
    candidate.nodes.push(NodeDocument {
        id: id.clone(),
        node_type: SWITCH.to_owned(),
        data_type: None,
        variant: Some(set.to_owned()),
        group: None,
        muted: false,
        inputs: BTreeMap::new(),
        texture: None,
        color_space: None,
        position: Some(position),
    });
    d.replace(candidate);
    Ok(id)
}

/// Binds switch `id` to set `set`: its inputs named after choices of both sets keep their
/// wires, the others are dropped (the loader reports the choices left unwired).
pub fn bind_switch(d: &mut EditorDoc, id: &str, set: &str) -> Result<(), String> {
    let choices = set_of(d.doc(), set)?.choices.clone();
    let k = d
        .index(id)
        .filter(|_| is_switch(d, id))
        .ok_or_else(|| format!("no switch '{id}'"))?;
    let mut candidate = d.doc().clone();
    let n = &mut candidate.nodes[k];
    n.variant = Some(set.to_owned());
    n.inputs.retain(|c, _| choices.contains(c));
    d.replace(candidate);
    Ok(())
}

/// Links `from_node.from_output` into choice `input` of switch `to_node`. While a switch has
/// an unwired choice the loader stops before checking the rest of the graph, so wiring its
/// last choice may bring other errors to light (an output not wired yet): those are not the
/// wire's. The wire is refused, with the loader's message, only for an error it adds on the
/// switch (its choices of different types, switches in a cycle) or a cycle.
pub fn connect_switch(
    d: &mut EditorDoc,
    from_node: &str,
    from_output: &str,
    to_node: &str,
    input: &str,
) -> Result<(), String> {
    let k = d
        .index(to_node)
        .ok_or_else(|| format!("no node '{to_node}'"))?;
    let mut candidate = d.doc().clone();
    candidate.nodes[k]
        .inputs
        .insert(input.to_owned(), link_json(from_node, from_output));
    let trial = EditorDoc::with_files(candidate.clone(), d.registry(), d.files().cloned());
    let before: Vec<String> = d.errors().iter().map(|e| e.to_string()).collect();
    let added: Vec<String> = trial
        .errors()
        .iter()
        .filter(|e| match e {
            GraphError::Cycle { .. } => true,
            e => e.node() == Some(to_node),
        })
        .map(|e| e.to_string())
        .filter(|m| !before.contains(m))
        .collect();
    if !added.is_empty() {
        return Err(added.join("\n"));
    }
    d.replace(candidate);
    Ok(())
}

impl EditorState {
    /// Declares a variant set ([`add_set`]): one undo step. Returns its name.
    pub fn add_variant_set(
        &mut self,
        name: Option<&str>,
        choices: &[&str],
    ) -> Result<String, String> {
        let name = self.edit(None, false, |d| add_set(d, name, choices))?;
        self.status = Some(format!("added variant set '{name}'"));
        Ok(name)
    }

    /// Renames a variant set, its switches and the preview's choice following.
    pub fn rename_variant_set(&mut self, old: &str, new: &str) -> Result<(), String> {
        self.edit(None, true, |d| rename_set(d, old, new))?;
        self.preview.rename_variant_set(old, new);
        self.status = Some(format!("renamed variant set '{old}' to '{new}'"));
        Ok(())
    }

    /// Sets a variant set's doc.
    pub fn set_variant_doc(&mut self, set: &str, text: &str) -> Result<(), String> {
        self.edit(None, false, |d| set_doc(d, set, text))
    }

    /// Adds a choice to a variant set ([`add_choice`]). Returns the choice.
    pub fn add_variant_choice(&mut self, set: &str, name: Option<&str>) -> Result<String, String> {
        let choice = self.edit(None, true, |d| add_choice(d, set, name))?;
        self.status = Some(format!("added choice '{choice}' to variant set '{set}'"));
        Ok(choice)
    }

    /// Renames a choice ([`rename_choice`]), the preview's choice following.
    pub fn rename_variant_choice(&mut self, set: &str, old: &str, new: &str) -> Result<(), String> {
        self.edit(None, true, |d| rename_choice(d, set, old, new))?;
        if self.preview.variant(set) == Some(old) {
            self.preview.set_variant(set, Some(new));
        }
        self.status = Some(format!("renamed choice '{old}' of '{set}' to '{new}'"));
        Ok(())
    }

    /// Removes a choice ([`remove_choice`]).
    pub fn remove_variant_choice(&mut self, set: &str, choice: &str) -> Result<(), String> {
        self.edit(None, true, |d| remove_choice(d, set, choice))?;
        self.status = Some(format!("removed choice '{choice}' of '{set}'"));
        Ok(())
    }

    /// Moves a choice one place up or down.
    pub fn move_variant_choice(&mut self, set: &str, choice: &str, up: bool) -> Result<(), String> {
        self.edit(None, true, |d| move_choice(d, set, choice, up))
    }

    /// Makes `choice` the file's default of `set`.
    pub fn set_variant_default(&mut self, set: &str, choice: &str) -> Result<(), String> {
        self.edit(None, false, |d| set_default(d, set, choice))?;
        self.status = Some(format!("variant set '{set}' defaults to '{choice}'"));
        Ok(())
    }

    /// Deletes a variant set ([`remove_set`]: its switches replaced by their default
    /// choice), one undo step.
    pub fn remove_variant_set(&mut self, set: &str) -> Result<(), String> {
        let replaced = self.edit(None, true, |d| remove_set(d, set))?;
        self.preview.set_variant(set, None);
        let said: Vec<String> = replaced
            .iter()
            .map(|(id, link)| match link {
                Some(l) => format!("switch '{id}' replaced by {l}"),
                None => format!("switch '{id}' removed (its default was not wired)"),
            })
            .collect();
        self.status = Some(match said.is_empty() {
            true => format!("removed variant set '{set}'"),
            false => format!("removed variant set '{set}': {}", said.join(", ")),
        });
        if self
            .focus
            .as_ref()
            .is_some_and(|f| replaced.iter().any(|(id, _)| id == f))
        {
            self.focus = Some(VARIANTS_PANEL.to_owned());
        }
        Ok(())
    }

    /// Adds a `switch` bound to `set` at canvas position `pos` ([`add_switch`]) and shows it
    /// in the side panel. Returns its id.
    pub fn add_switch(&mut self, set: &str, pos: [f32; 2]) -> Result<String, String> {
        let id = self.edit(None, true, |d| add_switch(d, set, pos))?;
        self.status = Some(format!(
            "added switch '{id}' for variant set '{set}': wire a node into each choice"
        ));
        self.focus = Some(id.clone());
        Ok(id)
    }

    /// Binds switch `id` to another set ([`bind_switch`]).
    pub fn bind_switch(&mut self, id: &str, set: &str) -> Result<(), String> {
        self.edit(None, true, |d| bind_switch(d, id, set))?;
        self.status = Some(format!("switch '{id}' follows variant set '{set}'"));
        Ok(())
    }
}
