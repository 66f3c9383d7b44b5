//! The document being edited: a [`GraphDocument`] (the source of truth, what is saved) and its
//! validation by the loader ([`Graph::from_document`]), redone after every edit. Every edit
//! that could break the graph (a wire) is tried on a copy first and refused with the loader's
//! own message when it adds an error.

use crate::document::{GraphDocument, NodeDocument};
use crate::error::GraphError;
use crate::graph::Graph;
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
}

impl EditorDoc {
    /// Wraps `doc` and validates it against `registry`.
    pub fn new(doc: GraphDocument, registry: &'static Registry) -> EditorDoc {
        let validation = Graph::from_document(&doc, registry);
        let ids = id_index(&doc);
        EditorDoc {
            doc,
            validation,
            registry,
            canonical: OnceLock::new(),
            structure: OnceLock::new(),
            sizes: OnceLock::new(),
            ids,
        }
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
        self.validation = Graph::from_document(&doc, self.registry);
        self.doc = doc;
        self.changed();
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
                .map(|n| super::layout::node_size(n, self.registry, self.generic(&n.id)))
                .collect()
        })
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

    /// The messages of the errors at node `id`.
    pub fn node_errors(&self, id: &str) -> Vec<String> {
        self.errors()
            .iter()
            .filter(|e| match e {
                GraphError::Cycle { nodes } => nodes.iter().any(|n| n == id),
                e => e.node() == Some(id),
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
        if self.index(&base).is_none() {
            return base;
        }
        (2..)
            .map(|k| format!("{base}_{k}"))
            .find(|id| self.index(id).is_none())
            .expect("an unused id exists")
    }

    /// Adds a node of type `type_name` at `position`; returns its id.
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
            inputs: BTreeMap::new(),
            texture: None,
            position: Some(position),
        });
        self.revalidate();
        Ok(id)
    }

    /// Removes nodes and everything that refers to them (links, graph outputs, parameters).
    pub fn remove_nodes(&mut self, ids: &[String]) {
        let gone = |s: &str| {
            s.split_once('.')
                .is_some_and(|(n, _)| ids.iter().any(|i| i == n))
        };
        self.doc.nodes.retain(|n| !ids.contains(&n.id));
        for n in &mut self.doc.nodes {
            n.inputs.retain(|_, v| link_of(v).is_none_or(|l| !gone(l)));
        }
        self.doc.outputs.retain(|o| !gone(&o.from));
        self.doc.parameters.retain(|p| !ids.contains(&p.node));
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

    /// The link written on `node.input`, as `node_id.output`.
    pub fn link(&self, node: &str, input: &str) -> Option<&str> {
        link_of(self.node(node)?.inputs.get(input)?)
    }

    /// Applies `candidate` when it has no error the current document lacks; otherwise
    /// returns the new errors' messages, one a line.
    fn try_apply(&mut self, candidate: GraphDocument) -> Result<(), String> {
        let result = Graph::from_document(&candidate, self.registry);
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
        self.changed();
        Ok(())
    }

    fn revalidate(&mut self) {
        self.validation = Graph::from_document(&self.doc, self.registry);
        self.changed();
    }

    /// After the document changed: the id index rebuilt, the texts made from it dropped.
    fn changed(&mut self) {
        self.canonical = OnceLock::new();
        self.structure = OnceLock::new();
        self.sizes = OnceLock::new();
        self.ids = id_index(&self.doc);
    }
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
