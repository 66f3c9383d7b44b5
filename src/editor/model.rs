//! The document being edited: a [`GraphDocument`] (the source of truth, what is saved) and its
//! validation by the loader ([`Graph::from_document`]), redone after every edit. Every edit
//! that could break the graph (a wire) is tried on a copy first and refused with the loader's
//! own message when it adds an error. A document with a file validates with the file's
//! [`GroupFiles`] ([`Graph::from_document_in`]), so that groups of other files resolve as
//! `matgraph check` resolves them.

use super::outputs::OUTPUT_NODE;
use super::ports::{Ports, ports_of};
use crate::document::{GraphDocument, NodeDocument};
use crate::error::GraphError;
use crate::graph::Graph;
use crate::group::GroupFiles;
use crate::node::{NodeType, PortType};
use crate::registry::Registry;
use crate::types::SocketType;
use std::collections::{BTreeMap, HashMap};
use std::sync::{Arc, OnceLock};

/// A graph document with its validation.
#[derive(Clone, Debug)]
pub struct EditorDoc {
    doc: GraphDocument,
    validation: Result<Graph, Vec<GraphError>>,
    registry: &'static Registry,
    /// [`EditorDoc::canonical_json`], made on first use after each change: the title bar asks
    /// for it every frame (is the document dirty?), and serialising a 300-node graph took 19 %
    /// of the frame.
    canonical: OnceLock<String>,
    /// [`EditorDoc::structure_key`], made on first use after each change: the preview asks
    /// for it every frame.
    structure: OnceLock<Arc<str>>,
    /// [`EditorDoc::node_sizes`], made on first use after each change: the canvas culls
    /// and draws its overview with them every frame.
    sizes: OnceLock<Vec<(f32, f32)>>,
    /// The index of each node id in the document: the canvas looks nodes up by id for
    /// every header and pin, and a linear search took 10 % of a 300-node frame.
    ids: HashMap<String, usize>,
    /// [`EditorDoc::ports`] of every node, made on first use after each change.
    ports: OnceLock<Vec<Ports>>,
    /// The files groups of other files are read from (the graph file's folder); `None`
    /// for a document without a file, whose groups must be its own.
    files: Option<Arc<dyn GroupFiles>>,
    /// Where the Material Output node ([`super::outputs`]) is on the canvas: editor-only,
    /// never saved; `None` until it is placed (a file with outputs places it right of its
    /// rightmost node when shown, [`EditorDoc::output_node_place`]).
    output_node: Option<[f32; 2]>,
    /// Where the Group Input node is on the canvas, inside a group (editor-only).
    input_node: Option<[f32; 2]>,
    /// Inside a group ([`super::scope`]): the group whose nodes and outputs the document
    /// holds; it is validated through [`super::scope::harness`].
    body: Option<super::scope::Body>,
    /// The harness' reroute ids, one per interface input, inside a group.
    harness_ids: Vec<String>,
    /// The Group Input node's pins (the interface inputs), made on first use after each
    /// change.
    input_ports: OnceLock<Ports>,
}

impl EditorDoc {
    /// Wraps `doc` and validates it against `registry` (without a file: groups of other
    /// files are errors; see [`EditorDoc::with_files`]).
    pub fn new(doc: GraphDocument, registry: &'static Registry) -> EditorDoc {
        EditorDoc::with_files(doc, registry, None)
    }

    /// Wraps `doc` and validates it against `registry`, reading the files its groups name
    /// through `files` (those of its graph file, [`EditorDoc::files_of`]).
    pub fn with_files(
        doc: GraphDocument,
        registry: &'static Registry,
        files: Option<Arc<dyn GroupFiles>>,
    ) -> EditorDoc {
        Self::build(doc, registry, files, None)
    }

    /// The body of a group ([`super::scope::body_doc`]), validated through its harness
    /// ([`super::scope::harness`]): the canvas inside the group.
    pub fn with_body(
        doc: GraphDocument,
        registry: &'static Registry,
        files: Option<Arc<dyn GroupFiles>>,
        body: super::scope::Body,
    ) -> EditorDoc {
        Self::build(doc, registry, files, Some(body))
    }

    /// The document validated (through the harness of `body`'s group when it is a group's
    /// body), its caches empty.
    fn build(
        doc: GraphDocument,
        registry: &'static Registry,
        files: Option<Arc<dyn GroupFiles>>,
        body: Option<super::scope::Body>,
    ) -> EditorDoc {
        let group = body.as_ref().map(|b| b.group.as_str());
        let (validation, harness_ids) = validate(&doc, registry, files.as_ref(), group);
        let ids = id_index(&doc);
        EditorDoc {
            doc,
            validation,
            registry,
            canonical: OnceLock::new(),
            structure: OnceLock::new(),
            sizes: OnceLock::new(),
            ids,
            ports: OnceLock::new(),
            files,
            output_node: None,
            input_node: None,
            body,
            harness_ids,
            input_ports: OnceLock::new(),
        }
    }

    /// Inside a group: which group the document's nodes and outputs are.
    pub fn body(&self) -> Option<&super::scope::Body> {
        self.body.as_ref()
    }

    /// Why the document cannot be edited (a group of another file), if so.
    pub fn read_only(&self) -> Option<&str> {
        self.body.as_ref()?.read_only.as_deref()
    }

    /// The interface of the group the document is the body of (none at the top).
    pub fn interface(&self) -> Option<&crate::document::GroupDocument> {
        self.doc.groups.get(&self.body.as_ref()?.group)
    }

    /// The Group Input node's pins: an output per interface input, typed by it (none at
    /// the top).
    fn input_ports(&self) -> &Ports {
        self.input_ports.get_or_init(|| {
            let outputs = self
                .interface()
                .map(|g| {
                    g.inputs
                        .iter()
                        .map(|i| {
                            let ty = SocketType::from_name(&i.ty);
                            super::ports::Port {
                                name: std::borrow::Cow::Owned(i.name.clone()),
                                ty: ty.map_or(PortType::Generic, PortType::Fixed),
                                default: ty.map_or(
                                    crate::value::Value::float(0.0),
                                    crate::value::Value::zero,
                                ),
                                soft: None,
                                hard: None,
                                unit: std::borrow::Cow::Owned(i.unit.clone().unwrap_or_default()),
                                doc: std::borrow::Cow::Owned(i.doc.clone()),
                                choices: &[],
                            }
                        })
                        .collect()
                })
                .unwrap_or_default();
            Ports {
                kind: super::ports::Kind::Unknown,
                inputs: Vec::new(),
                outputs,
            }
        })
    }

    /// Where the Group Input node was placed (editor-only).
    pub fn input_node(&self) -> Option<[f32; 2]> {
        self.input_node
    }

    /// Places the Group Input node (editor-only, not a document change).
    pub fn set_input_node(&mut self, place: Option<[f32; 2]>) {
        self.input_node = place;
    }

    /// Where the canvas draws the Group Input node, given the nodes' `places`: its place,
    /// else left of the leftmost node, level with the topmost; `None` at the top.
    pub fn input_node_place(&self, places: &[[f32; 2]]) -> Option<[f32; 2]> {
        self.body.as_ref()?;
        Some(self.input_node.unwrap_or_else(|| {
            let left = places.iter().map(|p| p[0]).fold(f32::INFINITY, f32::min);
            let top = places.iter().map(|p| p[1]).fold(f32::INFINITY, f32::min);
            match left.is_finite() && top.is_finite() {
                true => [left - 160.0 - super::outputs::GAP, top],
                false => [-240.0, 0.0],
            }
        }))
    }

    /// The files of the graph file at `path`: groups of other files are read from its
    /// folder, as `matgraph check` reads them ([`crate::io::group_files`]; each file is read
    /// once, so an edit does not read the disk again).
    pub fn files_of(path: &std::path::Path) -> Arc<dyn GroupFiles> {
        crate::io::group_files(path, crate::io::PathPolicy::InsideGraphFolder)
    }

    /// Reads groups of other files through `files` from now on (the document was saved
    /// under a new path) and revalidates.
    pub fn set_files(&mut self, files: Option<Arc<dyn GroupFiles>>) {
        self.files = files;
        self.revalidate();
    }

    /// The files groups of other files are read from, when the document has a file.
    pub fn files(&self) -> Option<&Arc<dyn GroupFiles>> {
        self.files.as_ref()
    }

    /// An empty graph called `name`.
    pub fn empty(name: &str, registry: &'static Registry) -> EditorDoc {
        EditorDoc::new(
            GraphDocument {
                version: crate::FORMAT_VERSION,
                name: name.to_owned(),
                doc: String::new(),
                nodes: Vec::new(),
                outputs: Vec::new(),
                parameters: Vec::new(),
                variants: Default::default(),
                groups: Default::default(),
                frames: Vec::new(),
                scene: None,
            },
            registry,
        )
    }

    /// The document.
    pub fn doc(&self) -> &GraphDocument {
        &self.doc
    }

    /// The registry node types are looked up in.
    pub fn registry(&self) -> &'static Registry {
        self.registry
    }

    /// The validated graph, when the document is valid.
    pub fn graph(&self) -> Option<&Graph> {
        self.validation.as_ref().ok()
    }

    /// The loader's errors (none when valid).
    pub fn errors(&self) -> &[GraphError] {
        match &self.validation {
            Ok(_) => &[],
            Err(e) => e,
        }
    }

    /// Replaces the whole document (undo, redo, recovery) and revalidates.
    pub fn replace(&mut self, doc: GraphDocument) {
        (self.validation, self.harness_ids) =
            validate(&doc, self.registry, self.files.as_ref(), self.group());
        self.doc = doc;
        self.changed();
    }

    /// The group the document is the body of, by name.
    fn group(&self) -> Option<&str> {
        self.body.as_ref().map(|b| b.group.as_str())
    }

    /// The canonical text `matgraph fmt` writes: the validated graph's form (literals
    /// normalised), or the document's own deterministic form while it has errors.
    pub fn canonical_json(&self) -> String {
        self.canonical().to_owned()
    }

    /// [`EditorDoc::canonical_json`] without a copy.
    pub fn canonical(&self) -> &str {
        self.canonical.get_or_init(|| match &self.validation {
            Ok(g) => g.to_json(),
            Err(_) => self.doc.to_json_pretty(),
        })
    }

    /// The preview's key of the document's structure ([`super::preview::structure_key`]),
    /// shared: each frame's requests hold it without copying it.
    pub fn structure_key(&self) -> Arc<str> {
        self.structure
            .get_or_init(|| super::preview::structure_key(&self.doc).into())
            .clone()
    }

    /// The estimated canvas size of each node ([`super::layout::node_size`]), by index.
    pub fn node_sizes(&self) -> &[(f32, f32)] {
        self.sizes.get_or_init(|| {
            self.doc
                .nodes
                .iter()
                .zip(self.all_ports())
                .map(|(n, p)| super::layout::node_size_of(n, p, self.generic(&n.id)))
                .collect()
        })
    }

    /// The pins of every node, by index ([`super::ports`]).
    fn all_ports(&self) -> &[Ports] {
        self.ports.get_or_init(|| {
            let files = self.files.as_deref();
            self.doc
                .nodes
                .iter()
                .map(|n| ports_of(&self.doc, n, self.registry, self.graph(), files))
                .collect()
        })
    }

    /// The pins of node `k` (by index): its type's, or a group instance's interface.
    pub fn ports_at(&self, k: usize) -> Option<&Ports> {
        self.all_ports().get(k)
    }

    /// The pins of node `id`: its type's, or a group instance's interface
    /// ([`super::ports`]); inside a group, the Group Input node's ([`super::scope::INPUT_NODE`]).
    pub fn ports(&self, id: &str) -> Option<&Ports> {
        if id == super::scope::INPUT_NODE && self.body.is_some() {
            return Some(self.input_ports());
        }
        self.ports_at(self.index(id)?)
    }

    /// The index of node `id` in the document.
    pub fn index(&self, id: &str) -> Option<usize> {
        self.ids.get(id).copied()
    }

    /// The node `id` of the document.
    pub fn node(&self, id: &str) -> Option<&NodeDocument> {
        self.index(id).map(|k| &self.doc.nodes[k])
    }

    /// The type of node `id`, if it is registered.
    pub fn node_type(&self, id: &str) -> Option<&Arc<NodeType>> {
        self.registry.get(&self.node(id)?.node_type)
    }

    /// The resolved generic type `T` of node `id`: inferred by the loader when the graph is
    /// valid, else the written `data_type`, else none.
    pub fn generic(&self, id: &str) -> Option<SocketType> {
        if let Some(g) = self.graph()
            && let Some(k) = g.node_index(id)
        {
            return Some(g.nodes()[k].generic);
        }
        self.node(id)?
            .data_type
            .as_deref()
            .and_then(SocketType::from_name)
    }

    /// The concrete type of a port of node `id` (`None` for a generic port whose `T` is not
    /// known yet).
    pub fn port_type(&self, id: &str, port: PortType) -> Option<SocketType> {
        match port {
            PortType::Fixed(t) => Some(t),
            PortType::Generic => self.generic(id),
        }
    }

    /// The messages of the errors at node `id`: those naming it, and for a group instance
    /// those inside it ([`GraphError::InGroup`], or a node of its inlined body, `id/…`)
    /// and those of the group it uses (its interface, a recursion through it).
    pub fn node_errors(&self, id: &str) -> Vec<String> {
        if id == super::scope::INPUT_NODE && self.body.is_some() {
            // The harness' reroutes stand for the Group Input node.
            return self
                .errors()
                .iter()
                .filter(|e| {
                    e.node()
                        .is_some_and(|n| self.harness_ids.iter().any(|h| h == owner(n)))
                        || matches!(e, GraphError::BadGroupInput { group, .. }
                            if Some(group.as_str()) == self.group())
                })
                .map(|e| e.to_string())
                .collect();
        }
        let group = self.node(id).and_then(|n| n.group.as_deref());
        let top = self
            .files
            .as_ref()
            .map(|f| f.top_label())
            .unwrap_or_default();
        let names_group = |label: &str, reference: &str| names_group(label, reference, &top);
        self.errors()
            .iter()
            .filter(|e| match e {
                GraphError::Cycle { nodes } => nodes.iter().any(|n| owner(n) == id),
                GraphError::BadGroupInput { group: g, .. } => {
                    group.is_some_and(|r| names_group(g, r))
                }
                GraphError::GroupRecursion { chain } => {
                    group.is_some_and(|r| chain.iter().any(|g| names_group(g, r)))
                }
                e => e.node().is_some_and(|n| owner(n) == id),
            })
            .map(|e| e.to_string())
            .collect()
    }

    /// A fresh node id made from `base` (`add`, `add_2`, `add_3`, ...).
    pub fn fresh_id(&self, base: &str) -> String {
        let base: String = base
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        // An id a graph output still reads (its node was deleted) is taken: a new node
        // under it would silently become that output.
        let free = |id: &str| {
            self.index(id).is_none()
                && !self
                    .doc
                    .outputs
                    .iter()
                    .any(|o| o.from.split_once('.').is_some_and(|(n, _)| n == id))
        };
        if free(&base) {
            return base;
        }
        (2..)
            .map(|k| format!("{base}_{k}"))
            .find(|id| free(id))
            .expect("an unused id exists")
    }

    /// Adds a node of type `type_name` at `position`; returns its id. A node that needs a
    /// newer format version than the document's (a `reroute` in a version-1 file) raises the
    /// document's version to it, so that the file saved reads back.
    pub fn add_node(&mut self, type_name: &str, position: [f32; 2]) -> Result<String, String> {
        let t = self
            .registry
            .get(type_name)
            .ok_or_else(|| format!("unknown node type '{type_name}'"))?;
        let id = self.fresh_id(t.name());
        self.doc.nodes.push(NodeDocument {
            id: id.clone(),
            node_type: t.name().to_owned(),
            data_type: None,
            variant: None,
            group: None,
            muted: false,
            inputs: BTreeMap::new(),
            texture: None,
            color_space: None,
            position: Some(position),
        });
        if self.doc.version < crate::document::GROUPS_VERSION && self.doc.newer_feature().is_some()
        {
            self.doc.version = crate::document::GROUPS_VERSION;
        }
        self.revalidate();
        Ok(id)
    }

    /// Removes nodes and everything that refers to them (links, parameters, the frames'
    /// lists). A graph output reading a removed node is kept, still naming it: the loader
    /// reports it and the Material Output node marks its pin ("reads deleted node 'x'"),
    /// never dropping the output (undo brings the wire back).
    pub fn remove_nodes(&mut self, ids: &[String]) {
        let gone = |s: &str| {
            s.split_once('.')
                .is_some_and(|(n, _)| ids.iter().any(|i| i == n))
        };
        self.doc.nodes.retain(|n| !ids.contains(&n.id));
        for n in &mut self.doc.nodes {
            n.inputs.retain(|_, v| link_of(v).is_none_or(|l| !gone(l)));
        }
        self.doc.parameters.retain(|p| !ids.contains(&p.node));
        for f in &mut self.doc.frames {
            f.nodes.retain(|n| !ids.contains(n));
        }
        self.revalidate();
    }

    /// Copies nodes, `offset` away, with fresh ids: links between copied nodes follow the
    /// copies, links from other nodes are kept. Returns the new ids in order.
    pub fn duplicate(&mut self, ids: &[String], offset: [f32; 2]) -> Vec<String> {
        let mut renamed: HashMap<String, String> = HashMap::new();
        let mut copies = Vec::new();
        for id in ids {
            let Some(n) = self.node(id).cloned() else {
                continue;
            };
            let new_id = self.fresh_id(&n.id);
            renamed.insert(n.id.clone(), new_id.clone());
            let mut copy = n;
            copy.id = new_id.clone();
            copy.position = copy.position.map(|[x, y]| [x + offset[0], y + offset[1]]);
            // Reserve the id before the next fresh_id call.
            self.ids.insert(new_id.clone(), self.doc.nodes.len());
            self.doc.nodes.push(copy);
            copies.push(new_id);
        }
        let start = self.doc.nodes.len() - copies.len();
        for n in &mut self.doc.nodes[start..] {
            for v in n.inputs.values_mut() {
                if let Some((src, out)) = link_of(v).and_then(|l| l.split_once('.'))
                    && let Some(new_src) = renamed.get(src)
                {
                    *v = link_json(new_src, out);
                }
            }
        }
        self.revalidate();
        copies
    }

    /// Links `from_node.from_output` to `to_node.to_input`, replacing what the input held.
    /// Refused, with the loader's message, when the link adds an error: a type with no
    /// implicit conversion, a cycle, a generic type that cannot be inferred.
    pub fn connect(
        &mut self,
        from_node: &str,
        from_output: &str,
        to_node: &str,
        to_input: &str,
    ) -> Result<(), String> {
        if to_node == OUTPUT_NODE {
            return self.connect_output(from_node, from_output, to_input);
        }
        if super::variants::is_switch(self, to_node) {
            return super::variants::connect_switch(
                self,
                from_node,
                from_output,
                to_node,
                to_input,
            );
        }
        let k = self
            .index(to_node)
            .ok_or_else(|| format!("no node '{to_node}'"))?;
        let mut candidate = self.doc.clone();
        candidate.nodes[k]
            .inputs
            .insert(to_input.to_owned(), link_json(from_node, from_output));
        self.try_apply(candidate)
    }

    /// Removes the link (or literal) of `node.input`: it takes its default again.
    pub fn clear_input(&mut self, node: &str, input: &str) {
        if node == OUTPUT_NODE {
            if let Some(o) = self.doc.outputs.iter_mut().find(|o| o.name == input) {
                o.from.clear();
                self.revalidate();
            }
            return;
        }
        if let Some(k) = self.index(node) {
            self.doc.nodes[k].inputs.remove(input);
            self.revalidate();
        }
    }

    /// Writes the literal `value` on `node.input` (values out of the hard range are kept and
    /// reported by the loader, as in a file).
    pub fn set_input(&mut self, node: &str, input: &str, value: serde_json::Value) {
        if let Some(k) = self.index(node) {
            self.doc.nodes[k].inputs.insert(input.to_owned(), value);
            self.revalidate();
        }
    }

    /// Moves nodes: `(id, position)` pairs, unknown ids skipped; one revalidation for all
    /// (a box selection dragged, or a file's laid-out nodes placed at once).
    pub fn set_positions(&mut self, moves: &[(String, [f32; 2])]) {
        let mut moved = false;
        for (id, position) in moves {
            if let Some(k) = self.index(id) {
                self.doc.nodes[k].position = Some(*position);
                moved = true;
            }
        }
        if moved {
            // The validated graph carries positions into the canonical form.
            self.revalidate();
        }
    }

    /// The link written on `node.input`, as `node_id.output` (for the Material Output
    /// node, [`OUTPUT_NODE`], the graph output `input`'s `from`, when set).
    pub fn link(&self, node: &str, input: &str) -> Option<&str> {
        if node == OUTPUT_NODE {
            return self
                .doc
                .outputs
                .iter()
                .find(|o| o.name == input)
                .map(|o| o.from.as_str())
                .filter(|f| !f.is_empty());
        }
        link_of(self.node(node)?.inputs.get(input)?)
    }

    /// Where the Material Output node was placed on the canvas (editor-only).
    pub fn output_node(&self) -> Option<[f32; 2]> {
        self.output_node
    }

    /// Places the Material Output node (`None`: forgets its place; it is shown again, right
    /// of the rightmost node, while the graph has outputs). Not a document change.
    pub fn set_output_node(&mut self, place: Option<[f32; 2]>) {
        self.output_node = place;
    }

    /// Whether the canvas shows the Material Output node: the graph has outputs, or it
    /// was added; inside a group (the Group Output node) always.
    pub fn shows_output_node(&self) -> bool {
        self.output_node.is_some() || !self.doc.outputs.is_empty() || self.body.is_some()
    }

    /// Where the canvas draws the Material Output node, given the nodes' `places`: its
    /// place, else (a graph with outputs) right of the rightmost node; `None` when it is
    /// not shown.
    pub fn output_node_place(&self, places: &[[f32; 2]]) -> Option<[f32; 2]> {
        self.shows_output_node().then(|| {
            self.output_node
                .unwrap_or_else(|| super::outputs::default_place(self, places))
        })
    }

    /// Wires `from_node.from_output` into the graph output `name` (its `from`). Any type
    /// is accepted, as the loader accepts it; a source that does not exist is refused.
    pub fn connect_output(
        &mut self,
        from_node: &str,
        from_output: &str,
        name: &str,
    ) -> Result<(), String> {
        let k = self
            .doc
            .outputs
            .iter()
            .position(|o| o.name == name)
            .ok_or_else(|| format!("no graph output '{name}'"))?;
        let mut candidate = self.doc.clone();
        candidate.outputs[k].from = format!("{from_node}.{from_output}");
        self.try_apply(candidate)
    }

    /// Adds the graph output `name`, unconnected (empty `from`, reported by the loader
    /// until wired). Refused for a name that is taken or not letters, digits, `_`, `-`.
    pub fn add_output(&mut self, name: &str) -> Result<(), String> {
        if !super::outputs::valid_name(name) {
            return Err(format!(
                "'{name}' cannot name an output: use letters, digits, '_' and '-'"
            ));
        }
        if self.doc.outputs.iter().any(|o| o.name == name) {
            return Err(format!("the graph already has an output '{name}'"));
        }
        self.doc.outputs.push(crate::document::OutputDocument {
            name: name.to_owned(),
            from: String::new(),
        });
        self.revalidate();
        Ok(())
    }

    /// Renames the graph output `old` to `new`, keeping its wire and place.
    pub fn rename_output(&mut self, old: &str, new: &str) -> Result<(), String> {
        if old == new {
            return Ok(());
        }
        if !super::outputs::valid_name(new) {
            return Err(format!(
                "'{new}' cannot name an output: use letters, digits, '_' and '-'"
            ));
        }
        if self.doc.outputs.iter().any(|o| o.name == new) {
            return Err(format!("the graph already has an output '{new}'"));
        }
        let o = self
            .doc
            .outputs
            .iter_mut()
            .find(|o| o.name == old)
            .ok_or_else(|| format!("no graph output '{old}'"))?;
        o.name = new.to_owned();
        self.revalidate();
        Ok(())
    }

    /// Removes the graph output `name`.
    pub fn remove_output(&mut self, name: &str) {
        let before = self.doc.outputs.len();
        self.doc.outputs.retain(|o| o.name != name);
        if self.doc.outputs.len() != before {
            self.revalidate();
        }
    }

    /// Replaces the document by `candidate` when it has no error the current document
    /// lacks; otherwise keeps it and returns the new errors' messages, one a line (the
    /// edits of [`super::params`]).
    pub fn try_replace(&mut self, candidate: GraphDocument) -> Result<(), String> {
        self.try_apply(candidate)
    }

    /// Applies `candidate` when it has no error the current document lacks; otherwise
    /// returns the new errors' messages, one a line.
    fn try_apply(&mut self, candidate: GraphDocument) -> Result<(), String> {
        let (result, harness_ids) =
            validate(&candidate, self.registry, self.files.as_ref(), self.group());
        if let Err(errors) = &result {
            let before: Vec<String> = self.errors().iter().map(|e| e.to_string()).collect();
            let new: Vec<String> = errors
                .iter()
                .map(|e| e.to_string())
                .filter(|m| !before.contains(m))
                .collect();
            if !new.is_empty() {
                return Err(new.join("\n"));
            }
        }
        self.doc = candidate;
        self.validation = result;
        self.harness_ids = harness_ids;
        self.changed();
        Ok(())
    }

    fn revalidate(&mut self) {
        (self.validation, self.harness_ids) =
            validate(&self.doc, self.registry, self.files.as_ref(), self.group());
        self.changed();
    }

    /// After the document changed: the id index rebuilt, the texts made from it dropped.
    fn changed(&mut self) {
        self.canonical = OnceLock::new();
        self.structure = OnceLock::new();
        self.sizes = OnceLock::new();
        self.ports = OnceLock::new();
        self.input_ports = OnceLock::new();
        self.ids = id_index(&self.doc);
    }
}

/// `doc` validated against `registry`, groups of other files read through `files`; the body
/// of group `body` through its harness ([`super::scope::harness`], whose reroute ids come
/// second).
fn validate(
    doc: &GraphDocument,
    registry: &Registry,
    files: Option<&Arc<dyn GroupFiles>>,
    body: Option<&str>,
) -> (Result<Graph, Vec<GraphError>>, Vec<String>) {
    let (harness, ids);
    let doc = match body {
        Some(group) => {
            (harness, ids) = super::scope::harness(doc, group);
            &harness
        }
        None => {
            ids = Vec::new();
            doc
        }
    };
    let result = match files {
        Some(f) => Graph::from_document_in(doc, registry, f.clone()),
        None => Graph::from_document(doc, registry),
    };
    (result, ids)
}

/// The top-level node a node id of the validated graph belongs to: itself, or for a node
/// inlined from a group instance (`g/f`, `g/@in:x`, see [`crate::group`]) the instance.
pub fn owner(id: &str) -> &str {
    id.split_once('/').map_or(id, |(top, _)| top)
}

/// Whether `label`, a group as an error names it (`NAME`, `TOP#NAME` for a group of the top
/// file `top`, `FILE#NAME`, `FILE`), is the group `reference` (as written on an instance)
/// names.
fn names_group(label: &str, reference: &str, top: &str) -> bool {
    label == reference
        || label
            .strip_suffix(reference)
            .and_then(|f| f.strip_suffix('#'))
            .is_some_and(|f| f == top)
}

/// The index of each node id in `doc` (the first, where an id is written twice, as the
/// loader reports the second).
fn id_index(doc: &GraphDocument) -> HashMap<String, usize> {
    let mut ids = HashMap::with_capacity(doc.nodes.len());
    for (k, n) in doc.nodes.iter().enumerate() {
        ids.entry(n.id.clone()).or_insert(k);
    }
    ids
}

/// The `node_id.output` of a link literal `{ "link": ... }`.
pub fn link_of(v: &serde_json::Value) -> Option<&str> {
    v.as_object()?.get("link")?.as_str()
}

/// The link literal `{ "link": "node.output" }`.
pub fn link_json(node: &str, output: &str) -> serde_json::Value {
    serde_json::json!({ "link": format!("{node}.{output}") })
}
