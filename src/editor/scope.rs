//! Inside a group (Tab): the canvas shows a group's nodes with a "Group Input" node for its
//! interface inputs and a "Group Output" node for its outputs, as Blender's group editing
//! does. The editor keeps the whole document (the *root*) and edits a *body*: a document
//! whose `nodes` and `outputs` are the group's, everything else (groups, variants, version)
//! the root's. After each edit the body is written back into the root's `groups`
//! ([`compose`]); the body is validated through a [`harness`] that stands a typed `reroute`
//! for each interface input, so the canvas gets the loader's types and errors by the group's
//! own node ids. A group of another file (`lib/x.json#name`) is shown read-only.
//!
//! The Group Input node's canvas id is [`INPUT_NODE`] (`@in`, which links inside a group
//! already name); the Group Output node is the Material Output node of the body
//! ([`super::outputs::OUTPUT_NODE`]). Neither is ever saved as a node.

use super::model::{EditorDoc, link_json, link_of};
use crate::document::{GraphDocument, GroupDocument, NodeDocument};
use crate::group::{GroupFile, GroupFiles, INPUT_ID, REROUTE};
use crate::types::SocketType;
use crate::value::Value;
use std::collections::{BTreeMap, HashSet};
use std::sync::Arc;

/// The canvas id of the Group Input node: `@in`, what links inside a group read.
pub const INPUT_NODE: &str = INPUT_ID;
/// The Group Input node's title.
pub const INPUT_TITLE: &str = "Group Input";
/// The title of the Material Output node inside a group.
pub const GROUP_OUTPUT_TITLE: &str = "Group Output";
/// The side panel's focus that shows the interface editor of the group being edited.
pub const GROUP_PANEL: &str = "@group";

/// What a body document is: the group whose nodes it holds.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// The group's name in the body's `groups` (the root's for a group of this file).
    pub group: String,
    /// Why it cannot be edited (a group of another file), if so.
    pub read_only: Option<String>,
}

/// One level entered.
#[derive(Clone, Debug)]
pub struct Level {
    /// The instance entered, an id of the level above.
    pub instance: String,
    /// Its group reference, as written on it.
    pub reference: String,
    /// Where the level above drew its Group Input and Group Output (or Material Output)
    /// nodes, restored on the way back.
    pub places: (Option<[f32; 2]>, Option<[f32; 2]>),
    /// The level above's selection, given back on the way back (each level keeps its own).
    pub selection: super::selection::Selection,
    /// The level above, when it is read-only (its body is not in the root).
    pub above: Option<Box<EditorDoc>>,
}

/// The levels entered, and the whole document.
#[derive(Clone, Debug)]
pub struct Scope {
    /// The whole document, validated: what is saved, undone and previewed.
    pub root: EditorDoc,
    /// The levels entered, outermost first (never empty).
    pub levels: Vec<Level>,
}

/// Whether `ty` can type a group's input (the loader's rule).
pub fn interface_type(ty: SocketType) -> bool {
    matches!(
        ty,
        SocketType::Float
            | SocketType::Vec2
            | SocketType::Vec3
            | SocketType::Vec4
            | SocketType::Color
    )
}

/// The body of group `group` of `root`: its nodes and outputs at the top, the root's
/// groups, variants and version; no parameters (they name the root's nodes) and no frames.
pub fn body_doc(root: &GraphDocument, group: &str) -> Option<GraphDocument> {
    let g = root.groups.get(group)?;
    Some(GraphDocument {
        version: root.version,
        name: root.name.clone(),
        doc: root.doc.clone(),
        nodes: g.nodes.clone(),
        outputs: g.outputs.clone(),
        parameters: Vec::new(),
        variants: root.variants.clone(),
        groups: root.groups.clone(),
        frames: Vec::new(),
        scene: root.scene.clone(),
    })
}

/// `root` with the body `body` of group `group` written back: the body's groups (a group
/// made inside it, an interface), the group's nodes and outputs the body's, the higher of the
/// two versions.
pub fn compose(root: &GraphDocument, body: &GraphDocument, group: &str) -> GraphDocument {
    let mut r = root.clone();
    r.version = r.version.max(body.version);
    r.groups = body.groups.clone();
    let g = r
        .groups
        .entry(group.to_owned())
        .or_insert_with(|| root.groups.get(group).cloned().unwrap_or(empty_group()));
    g.nodes = body.nodes.clone();
    g.outputs = body.outputs.clone();
    r
}

fn empty_group() -> GroupDocument {
    GroupDocument {
        doc: String::new(),
        inputs: Vec::new(),
        nodes: Vec::new(),
        outputs: Vec::new(),
    }
}

/// The graph the loader checks for body `body` of group `group`: a `reroute` typed by each
/// interface input, holding its default, in place of `@in` (links to `@in.NAME` read it);
/// the group's outputs as the graph's. Returns it with the reroutes' ids, in interface order.
pub fn harness(body: &GraphDocument, group: &str) -> (GraphDocument, Vec<String>) {
    let inputs = body
        .groups
        .get(group)
        .map(|g| g.inputs.clone())
        .unwrap_or_default();
    let mut taken: HashSet<String> = body.nodes.iter().map(|n| n.id.clone()).collect();
    let mut ids = Vec::new();
    let mut nodes = Vec::with_capacity(inputs.len() + body.nodes.len());
    for decl in &inputs {
        let id = fresh(&format!("group_input_{}", decl.name), &taken);
        taken.insert(id.clone());
        let value = SocketType::from_name(&decl.ty).map(|t| {
            decl.default
                .clone()
                .unwrap_or_else(|| Value::zero(t).to_json())
        });
        nodes.push(NodeDocument {
            id: id.clone(),
            node_type: REROUTE.into(),
            data_type: Some(decl.ty.clone()),
            variant: None,
            group: None,
            muted: false,
            inputs: value
                .map(|v| BTreeMap::from([("input".to_owned(), v)]))
                .unwrap_or_default(),
            texture: None,
            color_space: None,
            position: None,
        });
        ids.push(id);
    }
    let rewrite = |text: &str| -> Option<String> {
        let (src, out) = text.split_once('.')?;
        let k = (src == INPUT_ID).then(|| inputs.iter().position(|d| d.name == out))??;
        Some(format!("{}.output", ids[k]))
    };
    for n in &body.nodes {
        let mut copy = n.clone();
        for v in copy.inputs.values_mut() {
            if let Some(l) = link_of(v).and_then(rewrite) {
                *v = serde_json::json!({ "link": l });
            }
        }
        nodes.push(copy);
    }
    let mut outputs = body.outputs.clone();
    for o in &mut outputs {
        if let Some(l) = rewrite(&o.from) {
            o.from = l;
        }
    }
    let doc = GraphDocument {
        version: body.version,
        name: body.name.clone(),
        doc: String::new(),
        nodes,
        outputs,
        parameters: Vec::new(),
        variants: body.variants.clone(),
        groups: body.groups.clone(),
        frames: Vec::new(),
        scene: None,
    };
    (doc, ids)
}

/// `base`, or `base_2`, `base_3`, … : the first not in `taken`.
pub fn fresh(base: &str, taken: &HashSet<String>) -> String {
    if !taken.contains(base) {
        return base.to_owned();
    }
    (2..)
        .map(|k| format!("{base}_{k}"))
        .find(|id| !taken.contains(id))
        .expect("an unused name exists")
}

/// The files of a graph file other than the top one: references inside it resolve from it,
/// others as `inner` resolves them (the groups of a library file viewed read-only).
#[derive(Debug)]
pub struct FileFiles {
    inner: Arc<dyn GroupFiles>,
    key: String,
    label: String,
}

impl GroupFiles for FileFiles {
    fn load(&self, from: &str, reference: &str) -> Result<GroupFile, String> {
        self.inner.load(from, reference)
    }
    fn top_label(&self) -> String {
        self.label.clone()
    }
    fn top_key(&self) -> String {
        self.key.clone()
    }
}

/// What a group reference on an instance names, resolved as the loader resolves it.
pub enum Resolved {
    /// A group of the document's own `groups` (`NAME`).
    Own(String),
    /// A group `name` of another file.
    Library {
        /// The file.
        file: GroupFile,
        /// The group's name in it.
        name: String,
    },
}

/// The group `reference` (written in the document of `doc`) names; a whole graph file used
/// as a group, or one that cannot be read, is an error saying so.
pub fn resolve(doc: &EditorDoc, reference: &str) -> Result<Resolved, String> {
    let groups = &doc.doc().groups;
    let (path, name) = match reference.split_once('#') {
        Some((p, n)) => (Some(p), n),
        None if groups.contains_key(reference) || !reference.ends_with(".json") => {
            (None, reference)
        }
        None => {
            return Err(format!(
                "'{reference}' is a whole graph file used as a group: open it to see or edit it"
            ));
        }
    };
    let Some(path) = path else {
        return match groups.contains_key(name) {
            true => Ok(Resolved::Own(name.to_owned())),
            false => Err(format!("no group '{name}' in this file")),
        };
    };
    let files = doc.files().ok_or_else(|| {
        format!("'{reference}' is in another file: save the graph next to it first")
    })?;
    let file = files.load(&files.top_key(), path)?;
    if !file.doc.groups.contains_key(name) {
        return Err(format!("no group '{name}' in {}", file.label));
    }
    Ok(Resolved::Library {
        file,
        name: name.to_owned(),
    })
}

/// The body of the group instance `id` of `doc` uses, to enter it: a group of the
/// document's own (editable unless `doc` itself is read-only), or of another file
/// (read-only, its references resolved from that file).
pub fn enter(doc: &EditorDoc, root: &GraphDocument, id: &str) -> Result<EditorDoc, String> {
    let node = doc.node(id).ok_or_else(|| format!("no node '{id}'"))?;
    if node.node_type != crate::group::GROUP {
        return Err(format!(
            "'{id}' is not a group instance: Tab enters a group (select one; Tab again leaves)"
        ));
    }
    let reference = node.group.clone().unwrap_or_default();
    match resolve(doc, &reference)? {
        Resolved::Own(name) => {
            let read_only = doc.body().and_then(|b| b.read_only.clone());
            let body = match &read_only {
                // A group of a library file, from inside another of its groups.
                Some(_) => {
                    body_doc(doc.doc(), &name).ok_or_else(|| format!("no group '{name}'"))?
                }
                None => body_doc(root, &name).ok_or_else(|| format!("no group '{name}'"))?,
            };
            Ok(EditorDoc::with_body(
                body,
                doc.registry(),
                doc.files().cloned(),
                Body {
                    group: name,
                    read_only,
                },
            ))
        }
        Resolved::Library { file, name } => {
            let lib = &file.doc;
            let mut variants = root.variants.clone();
            for (k, v) in &lib.variants {
                variants.entry(k.clone()).or_insert_with(|| v.clone());
            }
            let g = &lib.groups[&name];
            let body = GraphDocument {
                version: lib.version,
                name: lib.name.clone(),
                doc: lib.doc.clone(),
                nodes: g.nodes.clone(),
                outputs: g.outputs.clone(),
                parameters: Vec::new(),
                variants,
                groups: lib.groups.clone(),
                frames: Vec::new(),
                scene: None,
            };
            let files: Option<Arc<dyn GroupFiles>> = doc.files().map(|inner| {
                Arc::new(FileFiles {
                    inner: inner.clone(),
                    key: file.key.clone(),
                    label: file.label.clone(),
                }) as Arc<dyn GroupFiles>
            });
            let why = format!(
                "{reference} is a group of another file: read-only here (open {} to edit it)",
                file.label
            );
            Ok(EditorDoc::with_body(
                body,
                doc.registry(),
                files,
                Body {
                    group: name,
                    read_only: Some(why),
                },
            ))
        }
    }
}

/// Rewrites every link of `nodes` and `outputs` to `@in.old` into `@in.new` (`None`:
/// removes it: an input takes its default again, an output's `from` is emptied).
pub fn relink_input(
    nodes: &mut [NodeDocument],
    outputs: &mut [crate::document::OutputDocument],
    old: &str,
    new: Option<&str>,
) {
    let reads = |l: &str| l.split_once('.') == Some((INPUT_ID, old));
    for n in nodes {
        n.inputs
            .retain(|_, v| new.is_some() || link_of(v).is_none_or(|l| !reads(l)));
        if let Some(new) = new {
            for v in n.inputs.values_mut() {
                if link_of(v).is_some_and(reads) {
                    *v = link_json(INPUT_ID, new);
                }
            }
        }
    }
    for o in outputs {
        if reads(&o.from) {
            o.from = new.map_or(String::new(), |n| format!("{INPUT_ID}.{n}"));
        }
    }
}
