//! The validated graph: node types resolved, generic types inferred, links typed and
//! checked, no cycles. Built from a [`GraphDocument`] with every problem reported at once.

use crate::document::{
    FORMAT_VERSION, GraphDocument, NodeDocument, OutputDocument, ParameterDocument,
};
use crate::error::GraphError;
use crate::node::{Evaluation, InputDecl, NodeType, PortType};
use crate::registry::{Registry, nearest};
use crate::types::{Conversion, SocketType};
use crate::value::Value;
use std::collections::{BTreeMap, HashMap};
use std::sync::Arc;

/// Index of a node in [`Graph::nodes`].
pub type NodeIndex = usize;

/// A reference to one output of one node.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct OutputRef {
    /// The node.
    pub node: NodeIndex,
    /// The output's index in the node type's outputs.
    pub output: usize,
}

/// Where a node input's value comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum InputSource {
    /// Not written in the file: the declared default (already of the port's type).
    Default(Value),
    /// A literal written in the file.
    Value {
        /// The literal converted to the port's type.
        value: Value,
        /// The literal as written (for a generic port its shape drives the inference of
        /// `T`, so it is saved in that shape).
        written: Value,
    },
    /// A link to another node's output, with the conversion its types need.
    Link(OutputRef, Conversion),
}

/// A validated node.
#[derive(Clone, Debug)]
pub struct Node {
    /// Stable id from the file.
    pub id: String,
    /// Its type.
    pub node_type: Arc<NodeType>,
    /// The `data_type` written in the file, if any.
    pub data_type: Option<SocketType>,
    /// The resolved generic type `T` (float for non-generic nodes).
    pub generic: SocketType,
    /// One source per declared input, in port order.
    pub inputs: Vec<InputSource>,
    /// The image of a texture node.
    pub texture: Option<crate::document::TextureSource>,
    /// The colour space its image is read in, as the file writes it (`None`: the file
    /// type's default, [`crate::color_space::ColorSpace::default_for`]).
    pub color_space: Option<crate::color_space::ColorSpace>,
    /// Editor position.
    pub position: Option<[f32; 2]>,
    /// Muted: each output passes through [`Node::passthrough`] (Blender's rule).
    pub muted: bool,
}

impl Node {
    /// The key a texture node's image is bound under ([`crate::color_space::ColorSpace::key`]),
    /// or `None` for a node that samples none.
    pub fn texture_key(&self) -> Option<String> {
        let source = self.texture.as_ref()?;
        Some(crate::color_space::ColorSpace::key(
            &source.key(),
            self.color_space,
        ))
    }

    /// Whether the node only passes values on (a `reroute`, or a muted node other than a
    /// `parameter`): the CPU plan and the WGSL read its source in its place, at no cost.
    pub fn forwards(&self) -> bool {
        self.node_type.name() == crate::group::REROUTE
            || (self.muted && self.node_type.evaluation() != Evaluation::Parameter)
    }

    /// For a forwarding node ([`Node::forwards`]): the input output `k` passes on, the
    /// first of the output's type (Blender's rule for muted nodes); `None` where there is
    /// none, and the output is its type's zero.
    pub fn passthrough(&self, k: usize) -> Option<usize> {
        self.node_type.passthrough(self.generic, k)
    }

    /// The inputs whose values the node uses: all of them, or for a forwarding node the
    /// ones it passes on.
    pub fn used_inputs(&self) -> impl Iterator<Item = &InputSource> + '_ {
        let forwards = self.forwards();
        let outputs = self.node_type.outputs().len();
        self.inputs
            .iter()
            .enumerate()
            .filter(move |&(j, _)| {
                !forwards || (0..outputs).any(|k| self.passthrough(k) == Some(j))
            })
            .map(|(_, s)| s)
    }

    /// The concrete type of input `k`.
    pub fn input_type(&self, k: usize) -> SocketType {
        self.node_type.inputs()[k].ty.resolve(self.generic)
    }
    /// The concrete type of output `k`.
    pub fn output_type(&self, k: usize) -> SocketType {
        self.node_type.outputs()[k].ty.resolve(self.generic)
    }
}

/// A named output of the graph.
#[derive(Clone, Debug, PartialEq)]
pub struct GraphOutput {
    /// Name callers ask for.
    pub name: String,
    /// The node output it reads.
    pub source: OutputRef,
    /// Its type.
    pub ty: SocketType,
}

/// An exposed parameter of the graph.
#[derive(Clone, Debug, PartialEq)]
pub struct GraphParameter {
    /// Name callers set it by.
    pub name: String,
    /// The `parameter` node it exposes.
    pub node: NodeIndex,
    /// Its type.
    pub ty: SocketType,
    /// Its value in the file.
    pub default: Value,
    /// What it means.
    pub doc: String,
    /// Editor group.
    pub group: Option<String>,
    /// The values it accepts (the file's `range`), every component.
    pub range: Option<crate::node::Range>,
    /// The hard ranges its value must respect: one per input it feeds (see [`Feed`]).
    pub feeds: Vec<Feed>,
}

/// An input with a hard range that a `parameter` node *feeds*: an input linked directly to
/// the parameter node's `value` output. The parameter's value, after the link's implicit
/// conversion (a float broadcast to a vector input, a colour's luminance to a float input),
/// must lie in the input's hard range, as a literal written on that input must. This is the
/// load-time check of the file's value; values computed *from* parameters by other nodes, and
/// every value set later by [`crate::ParamValues::set`], are checked by the plan's guards
/// (`plan::Guards`), which run the uniform program.
#[derive(Clone, Debug, PartialEq)]
pub struct Feed {
    /// The id of the node whose input is fed.
    pub node: String,
    /// The input's name.
    pub input: &'static str,
    /// The input's hard range.
    pub range: crate::node::Range,
    /// The link's conversion.
    pub conversion: Conversion,
    /// The input's type.
    pub to: SocketType,
}

impl Feed {
    /// The value `v` of the parameter as the fed input sees it, if it is outside the range.
    pub fn violation(&self, v: Value) -> Option<Value> {
        let seen = Value::from_lanes(self.to, &self.conversion.apply(v.raw(), self.to));
        (!self.range.contains(&seen)).then_some(seen)
    }
}

/// A validated graph.
#[derive(Clone, Debug)]
pub struct Graph {
    /// Name.
    pub name: String,
    /// Description.
    pub doc: String,
    nodes: Vec<Node>,
    by_id: HashMap<String, NodeIndex>,
    order: Vec<NodeIndex>,
    outputs: Vec<GraphOutput>,
    parameters: Vec<GraphParameter>,
    /// The preview scene from the file, as written (checked by the renderer).
    pub scene: Option<serde_json::Value>,
    /// The variants and switches as written, when the file has any.
    written: Option<Arc<crate::variant::Written>>,
    /// The file's format version (saved back unchanged).
    version: u32,
    /// The frames, as written.
    frames: Vec<crate::document::FrameDocument>,
    /// For a graph with groups: the document as written (what it saves as; the nodes of
    /// this graph are its groups inlined, see [`crate::group`]).
    source: Option<Arc<GraphDocument>>,
    /// For a graph with groups: where the files its groups name were read from.
    files: Option<Arc<dyn crate::group::GroupFiles>>,
    /// For a graph with groups: where its instances lie.
    instances: Option<Arc<crate::group::Instances>>,
}

impl Graph {
    /// Parses and validates a graph file's text against `registry`. Groups of other files
    /// cannot be read from text alone: see [`Graph::from_json_in`].
    pub fn from_json(text: &str, registry: &Registry) -> Result<Graph, Vec<GraphError>> {
        let doc = GraphDocument::parse(text)?;
        Graph::from_document(&doc, registry)
    }

    /// [`Graph::from_json`], reading the files its groups name through `files`.
    pub fn from_json_in(
        text: &str,
        registry: &Registry,
        files: Arc<dyn crate::group::GroupFiles>,
    ) -> Result<Graph, Vec<GraphError>> {
        let doc = GraphDocument::parse(text)?;
        Graph::with_variants_in(&doc, registry, &[], files)
    }

    /// [`Graph::from_document`], reading the files its groups name through `files`.
    pub fn from_document_in(
        doc: &GraphDocument,
        registry: &Registry,
        files: Arc<dyn crate::group::GroupFiles>,
    ) -> Result<Graph, Vec<GraphError>> {
        Graph::with_variants_in(doc, registry, &[], files)
    }

    /// [`Graph::with_variants`], reading the files its groups name through `files`. A
    /// document with groups is inlined first ([`crate::group`]); its errors are reported
    /// inside the instances they come from.
    pub fn with_variants_in(
        doc: &GraphDocument,
        registry: &Registry,
        selection: &crate::variant::Selection,
        files: Arc<dyn crate::group::GroupFiles>,
    ) -> Result<Graph, Vec<GraphError>> {
        if !crate::group::uses_groups(doc) {
            return Graph::with_variants(doc, registry, selection);
        }
        doc.check_features()?;
        // One copy of the document, shared by the expansion and the graph (which saves it).
        let source = Arc::new(doc.clone());
        let (x, errors) = crate::group::expand(&source, &*files);
        let relocate = |errors: Vec<GraphError>| -> Vec<GraphError> {
            errors
                .into_iter()
                .map(|e| crate::group::relocate(e, &x.scopes, &x.inputs))
                .collect()
        };
        if !errors.is_empty() {
            return Err(relocate(errors));
        }
        let mut graph = Graph::flat_with_variants(&x.doc, registry, selection).map_err(relocate)?;
        graph.instances = Some(Arc::new(crate::group::Instances::new(&graph, &x)));
        graph.source = Some(source);
        graph.files = Some(files);
        Ok(graph)
    }

    /// Validates a document, its variants at their defaults; returns every problem found.
    pub fn from_document(
        doc: &GraphDocument,
        registry: &Registry,
    ) -> Result<Graph, Vec<GraphError>> {
        Graph::with_variants(doc, registry, &[])
    }

    /// Validates a document with each variant named in `selection` at the given choice (the
    /// others at their defaults; see [`crate::variant`]). Every switch is resolved by
    /// rewiring its consumers to the chosen source, so the unchosen branches reach no output
    /// and plans and shaders leave them out; they are still validated, and the graph saves
    /// as written, variants and switches included.
    pub fn with_variants(
        doc: &GraphDocument,
        registry: &Registry,
        selection: &crate::variant::Selection,
    ) -> Result<Graph, Vec<GraphError>> {
        if crate::group::uses_groups(doc) {
            return Graph::with_variants_in(
                doc,
                registry,
                selection,
                Arc::new(crate::group::NoFiles),
            );
        }
        Graph::flat_with_variants(doc, registry, selection)
    }

    /// [`Graph::with_variants`] of a document without groups.
    fn flat_with_variants(
        doc: &GraphDocument,
        registry: &Registry,
        selection: &crate::variant::Selection,
    ) -> Result<Graph, Vec<GraphError>> {
        doc.check_features()?;
        let builder = || Builder {
            registry,
            errors: Vec::new(),
        };
        let plain = doc.variants.is_empty()
            && selection.is_empty()
            && doc
                .nodes
                .iter()
                .all(|n| n.node_type != crate::variant::SWITCH && n.variant.is_none());
        if plain {
            return builder().build(doc);
        }
        let (rewired, written) = crate::variant::rewire(doc, selection)?;
        let mut graph = builder().build(&rewired)?;
        let errors = graph.check_switches(&written);
        if !errors.is_empty() {
            return Err(errors);
        }
        graph.written = Some(Arc::new(written));
        Ok(graph)
    }

    /// The same graph file resolved at another selection of variant choices.
    pub fn select(
        &self,
        registry: &Registry,
        selection: &crate::variant::Selection,
    ) -> Result<Graph, Vec<GraphError>> {
        match &self.files {
            Some(files) => {
                Graph::with_variants_in(&self.to_document(), registry, selection, files.clone())
            }
            None => Graph::with_variants(&self.to_document(), registry, selection),
        }
    }

    /// Whether the graph was written with groups (its nodes are them inlined).
    pub fn has_groups(&self) -> bool {
        self.source.is_some()
    }

    /// For a graph written with groups: where each instance lies in its nodes.
    pub fn instances(&self) -> Option<&crate::group::Instances> {
        self.instances.as_deref()
    }

    /// The declared variants, by name.
    pub fn variants(&self) -> BTreeMap<String, crate::document::VariantDocument> {
        self.written
            .as_ref()
            .map(|w| w.variants.clone())
            .unwrap_or_default()
    }

    /// The choice made for each declared variant.
    pub fn variant_choices(&self) -> BTreeMap<String, String> {
        self.written
            .as_ref()
            .map(|w| w.chosen.clone())
            .unwrap_or_default()
    }

    /// Every switch input must link to an existing output whose type is that of the
    /// switch's first choice (a switch input linking a switch has that switch's type).
    fn check_switches(&self, w: &crate::variant::Written) -> Vec<GraphError> {
        let by_id: HashMap<&str, &NodeDocument> =
            w.switches.iter().map(|(_, n)| (n.id.as_str(), n)).collect();
        let chosen_link = |n: &NodeDocument| -> Option<String> {
            let c = w.chosen.get(n.variant.as_deref()?)?;
            n.inputs.get(c)?.get("link")?.as_str().map(str::to_owned)
        };
        let mut errors = Vec::new();
        for (_, n) in &w.switches {
            let Some(v) = n.variant.as_ref().and_then(|v| w.variants.get(v)) else {
                continue;
            };
            let mut first: Option<(&str, SocketType)> = None;
            for c in &v.choices {
                let Some(mut link) = n
                    .inputs
                    .get(c)
                    .and_then(|j| j.get("link"))
                    .and_then(|l| l.as_str())
                    .map(str::to_owned)
                else {
                    continue;
                };
                for _ in 0..=by_id.len() {
                    match link.split_once('.').and_then(|(id, _)| by_id.get(id)) {
                        Some(inner) => match chosen_link(inner) {
                            Some(l) => link = l,
                            None => break,
                        },
                        None => break,
                    }
                }
                let Some(r) = self.output_ref(&link) else {
                    errors.push(GraphError::BadSwitchInput {
                        node: n.id.clone(),
                        input: c.clone(),
                        message: format!("link to a missing node or output '{link}'"),
                        suggestion: None,
                    });
                    continue;
                };
                let ty = self.output_type(r);
                match first {
                    None => first = Some((c, ty)),
                    Some((fc, ft)) if ft != ty => errors.push(GraphError::BadSwitchInput {
                        node: n.id.clone(),
                        input: c.clone(),
                        message: format!(
                            "type {} differs from the type {} of choice '{fc}': every choice of a switch has one type",
                            ty.name(),
                            ft.name()
                        ),
                        suggestion: None,
                    }),
                    Some(_) => {}
                }
            }
        }
        errors
    }

    /// The nodes, in file order.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }
    /// A topological order of the nodes (sources first).
    pub fn order(&self) -> &[NodeIndex] {
        &self.order
    }
    /// Adds a node the compiler made ([`crate::bump`]), outside the order and the ids: the
    /// caller places it with [`Graph::set_order`].
    pub(crate) fn push_node(&mut self, node: Node) -> NodeIndex {
        self.nodes.push(node);
        self.nodes.len() - 1
    }
    /// Node `i`, to rewire ([`crate::bump`]).
    pub(crate) fn node_mut(&mut self, i: NodeIndex) -> &mut Node {
        &mut self.nodes[i]
    }
    /// Replaces the evaluation order ([`crate::bump`]): a topological order of every node.
    pub(crate) fn set_order(&mut self, order: Vec<NodeIndex>) {
        self.order = order;
    }
    /// The node with id `id`.
    pub fn node_index(&self, id: &str) -> Option<NodeIndex> {
        self.by_id.get(id).copied()
    }
    /// The graph's outputs.
    pub fn outputs(&self) -> &[GraphOutput] {
        &self.outputs
    }
    /// The graph's exposed parameters.
    pub fn parameters(&self) -> &[GraphParameter] {
        &self.parameters
    }
    /// Resolves `node_id.output` to an output reference.
    pub fn output_ref(&self, text: &str) -> Option<OutputRef> {
        let (id, out) = text.split_once('.')?;
        let node = self.node_index(id)?;
        let output = self.nodes[node].node_type.output_index(out)?;
        Some(OutputRef { node, output })
    }
    /// The type of a node output.
    pub fn output_type(&self, r: OutputRef) -> SocketType {
        self.nodes[r.node].output_type(r.output)
    }
    /// `node_id.output` for a reference.
    pub fn output_name(&self, r: OutputRef) -> String {
        let n = &self.nodes[r.node];
        format!("{}.{}", n.id, n.node_type.outputs()[r.output].name)
    }

    /// The document this graph saves as: literals normalised to their port types; a graph
    /// with groups saves as written.
    pub fn to_document(&self) -> GraphDocument {
        match &self.source {
            Some(doc) => (**doc).clone(),
            None => self.flat_document(),
        }
    }

    /// The document of the graph's own nodes: for a graph with groups, its groups inlined
    /// (node ids are paths, `g/f`; see [`crate::group`]), which validates to the same graph.
    pub fn flat_document(&self) -> GraphDocument {
        let nodes = self
            .nodes
            .iter()
            .map(|n| {
                let mut inputs = BTreeMap::new();
                for (decl, src) in n.node_type.inputs().iter().zip(&n.inputs) {
                    let json = match src {
                        InputSource::Default(_) => continue,
                        InputSource::Value { written, .. } => literal_json(decl, written),
                        InputSource::Link(r, _) => {
                            serde_json::json!({ "link": self.output_name(*r) })
                        }
                    };
                    inputs.insert(decl.name.to_owned(), json);
                }
                if let Some(w) = &self.written {
                    for (input, json) in inputs.iter_mut() {
                        if let Some(l) = w.links.get(&(n.id.clone(), input.clone())) {
                            *json = serde_json::json!({ "link": l });
                        }
                    }
                }
                NodeDocument {
                    id: n.id.clone(),
                    node_type: n.node_type.name().to_owned(),
                    data_type: n.data_type.map(|t| t.name().to_owned()),
                    variant: None,
                    group: None,
                    muted: n.muted,
                    inputs,
                    texture: n.texture.clone(),
                    color_space: n.color_space,
                    position: n.position,
                }
            })
            .collect::<Vec<_>>();
        let mut nodes = nodes;
        if let Some(w) = &self.written {
            for (i, s) in &w.switches {
                nodes.insert((*i).min(nodes.len()), s.clone());
            }
        }
        GraphDocument {
            version: self.version,
            name: self.name.clone(),
            doc: self.doc.clone(),
            nodes,
            outputs: self
                .outputs
                .iter()
                .enumerate()
                .map(|(k, o)| OutputDocument {
                    name: o.name.clone(),
                    from: self
                        .written
                        .as_ref()
                        .and_then(|w| w.outputs.get(&k).cloned())
                        .unwrap_or_else(|| self.output_name(o.source)),
                })
                .collect(),
            parameters: self
                .parameters
                .iter()
                .map(|p| ParameterDocument {
                    name: p.name.clone(),
                    node: self.nodes[p.node].id.clone(),
                    doc: p.doc.clone(),
                    group: p.group.clone(),
                    range: p.range.map(|r| [r.min, r.max]),
                })
                .collect(),
            variants: self
                .written
                .as_ref()
                .map(|w| w.variants.clone())
                .unwrap_or_default(),
            groups: BTreeMap::new(),
            frames: self.frames.clone(),
            scene: self.scene.clone(),
        }
    }

    /// Saves as pretty, deterministic JSON.
    pub fn to_json(&self) -> String {
        self.to_document().to_json_pretty()
    }

    /// The graph as compact, deterministic JSON: equal for two graphs exactly when their
    /// [`Graph::to_json`] is, as a cache key (a third of the time of the pretty form, which
    /// a GPU frame's material lookup spent a millisecond on).
    pub fn key(&self) -> String {
        self.with_choices(serde_json::to_string(&self.flat_document()).unwrap_or_default())
    }

    /// [`Graph::key`] without the values of the exposed parameters
    /// ([`GraphDocument::remove_parameter_values`]): equal for two graphs that compile to
    /// the same shaders, as the key of a compiled material whose parameters are set per
    /// frame.
    pub fn structure_key(&self) -> String {
        let mut d = self.flat_document();
        d.remove_parameter_values();
        self.with_choices(serde_json::to_string(&d).unwrap_or_default())
    }

    /// `key` followed by the choice made for each variant, where the graph declares any:
    /// the flat document keeps the switches as written, so two choices of one file would
    /// otherwise share a key (and a cached material).
    fn with_choices(&self, key: String) -> String {
        let chosen = self.variant_choices();
        if chosen.is_empty() {
            return key;
        }
        format!(
            "{key}\nvariants {}",
            serde_json::to_string(&chosen).unwrap_or_default()
        )
    }
}

/// The JSON of a literal: enum choices by name, everything else by value.
fn literal_json(decl: &InputDecl, v: &Value) -> serde_json::Value {
    if !decl.choices.is_empty()
        && let Some(name) = usize::try_from(v.as_i32())
            .ok()
            .and_then(|i| decl.choices.get(i))
    {
        return serde_json::Value::String((*name).to_owned());
    }
    v.to_json()
}

/// A link as written, before the source node's types are known.
struct PendingLink {
    input: usize,
    target: NodeIndex,
    output: usize,
}

struct Builder<'r> {
    registry: &'r Registry,
    errors: Vec<GraphError>,
}

impl Builder<'_> {
    fn build(mut self, doc: &GraphDocument) -> Result<Graph, Vec<GraphError>> {
        // 1. Ids and types.
        let mut by_id: HashMap<String, NodeIndex> = HashMap::new();
        let mut types: Vec<Option<Arc<NodeType>>> = Vec::with_capacity(doc.nodes.len());
        for (i, n) in doc.nodes.iter().enumerate() {
            if !valid_id(&n.id) && !valid_path_id(&n.id) {
                self.errors
                    .push(GraphError::InvalidId { node: n.id.clone() });
            }
            if n.position.is_some_and(|p| !p.iter().all(|x| x.is_finite())) {
                self.errors
                    .push(GraphError::BadPosition { node: n.id.clone() });
            }
            if by_id.insert(n.id.clone(), i).is_some() {
                self.errors
                    .push(GraphError::DuplicateId { node: n.id.clone() });
            }
            let t = self.registry.get(&n.node_type).cloned();
            if t.is_none() {
                self.errors.push(GraphError::UnknownNodeType {
                    node: n.id.clone(),
                    type_name: n.node_type.clone(),
                    suggestion: self.registry.suggest(&n.node_type).map(str::to_owned),
                });
            }
            types.push(t);
        }

        // 2. Input names and link targets.
        let mut links: Vec<Vec<PendingLink>> = Vec::with_capacity(doc.nodes.len());
        for (n, t) in doc.nodes.iter().zip(&types) {
            let mut pending = Vec::new();
            if let Some(t) = t {
                for (name, json) in &n.inputs {
                    let Some(k) = t.input_index(name) else {
                        self.errors.push(GraphError::UnknownInput {
                            node: n.id.clone(),
                            input: name.clone(),
                            suggestion: nearest(name, t.inputs().iter().map(|i| i.name))
                                .map(str::to_owned),
                        });
                        continue;
                    };
                    if let Some(link) = link_text(json) {
                        match link {
                            Ok(text) => {
                                if let Some(p) =
                                    self.resolve_link(n, name, text, &by_id, &types, k, doc)
                                {
                                    pending.push(p);
                                }
                            }
                            Err(()) => self.errors.push(GraphError::BadLink {
                                node: n.id.clone(),
                                input: name.clone(),
                                link: json.to_string(),
                            }),
                        }
                    }
                }
            }
            links.push(pending);
        }

        // 3. Cycles.
        let order = self.topological_order(doc, &links);

        // 4. Generic types and input values, in topological order.
        let mut nodes: Vec<Option<Node>> = vec![None; doc.nodes.len()];
        if let Some(order) = &order {
            for &i in order {
                let Some(t) = types[i].clone() else { continue };
                nodes[i] = self.resolve_node(&doc.nodes[i], t, &links[i], &nodes, doc);
            }
        }

        let feeds = self.parameter_feeds(doc, &nodes);
        let outputs = self.graph_outputs(doc, &by_id, &nodes);
        let parameters = self.graph_parameters(doc, &by_id, &nodes, &feeds);
        self.check_frames(doc, &by_id);

        if !self.errors.is_empty() {
            return Err(self.errors);
        }
        let nodes: Vec<Node> = nodes.into_iter().flatten().collect();
        Ok(Graph {
            name: doc.name.clone(),
            doc: doc.doc.clone(),
            nodes,
            by_id,
            order: order.unwrap_or_default(),
            outputs,
            parameters,
            scene: doc.scene.clone(),
            written: None,
            version: doc.version,
            frames: doc.frames.clone(),
            source: None,
            files: None,
            instances: None,
        })
    }

    /// Frames have unique ids and hold nodes of the graph.
    fn check_frames(&mut self, doc: &GraphDocument, by_id: &HashMap<String, NodeIndex>) {
        if doc.frames.is_empty() {
            return;
        }
        // A group instance is written as one node: its id is the first segment of the ids
        // inlined from it.
        let instances: std::collections::HashSet<&str> = doc
            .nodes
            .iter()
            .filter_map(|n| n.id.split_once('/').map(|(g, _)| g))
            .collect();
        let mut ids = std::collections::HashSet::new();
        for f in &doc.frames {
            let bad = |message: String| GraphError::BadFrame {
                frame: f.id.clone(),
                message,
            };
            if !ids.insert(f.id.as_str()) {
                self.errors.push(bad("duplicate frame id".into()));
            }
            if let Some(c) = f.color
                && !c.iter().all(|x| (0.0..=1.0).contains(x))
            {
                self.errors
                    .push(bad("color components must lie in [0, 1]".into()));
            }
            for n in &f.nodes {
                let exists = by_id.contains_key(n) || instances.contains(n.as_str());
                if !exists || n.contains('/') {
                    let hint = self
                        .nearest_id(n, doc)
                        .map(|s| format!(" (did you mean '{s}'?)"))
                        .unwrap_or_default();
                    self.errors
                        .push(bad(format!("holds node '{n}', which does not exist{hint}")));
                }
            }
        }
    }

    /// The node id nearest to `id`, for a "did you mean"; searched (a pass over every id)
    /// only while fewer errors than are shown have been found, so a file full of dangling
    /// links stays linear.
    fn nearest_id(&self, id: &str, doc: &GraphDocument) -> Option<String> {
        if self.errors.len() >= crate::error::MAX_SHOWN {
            return None;
        }
        nearest(id, doc.nodes.iter().map(|n| n.id.as_str())).map(str::to_owned)
    }

    #[allow(clippy::too_many_arguments)]
    fn resolve_link(
        &mut self,
        n: &NodeDocument,
        input: &str,
        text: &str,
        by_id: &HashMap<String, NodeIndex>,
        types: &[Option<Arc<NodeType>>],
        k: usize,
        doc: &GraphDocument,
    ) -> Option<PendingLink> {
        let Some((target_id, out_name)) = text.split_once('.') else {
            self.errors.push(GraphError::BadLink {
                node: n.id.clone(),
                input: input.to_owned(),
                link: text.to_owned(),
            });
            return None;
        };
        if target_id == crate::group::INPUT_ID {
            self.errors.push(GraphError::GroupLink {
                node: n.id.clone(),
                input: input.to_owned(),
                message: format!("'{text}' reads a group's input, and this is not inside a group"),
            });
            return None;
        }
        let Some(&target) = by_id.get(target_id) else {
            self.errors.push(GraphError::MissingNode {
                node: n.id.clone(),
                input: input.to_owned(),
                target: target_id.to_owned(),
                suggestion: self.nearest_id(target_id, doc),
            });
            return None;
        };
        // An unknown source type was already reported.
        let source_type = types[target].as_ref()?;
        let Some(output) = source_type.output_index(out_name) else {
            self.errors.push(GraphError::MissingOutput {
                node: n.id.clone(),
                input: input.to_owned(),
                target: target_id.to_owned(),
                output: out_name.to_owned(),
                suggestion: nearest(out_name, source_type.outputs().iter().map(|o| o.name))
                    .map(str::to_owned),
            });
            return None;
        };
        Some(PendingLink {
            input: k,
            target,
            output,
        })
    }

    /// A topological order, or `None` after reporting every cycle. Iterative throughout
    /// (Kahn's sort, then petgraph's `kosaraju_scc` over what it could not sort), so a chain
    /// of any length runs in linear time and constant stack. The sort is Kahn's with the
    /// lowest file index first among ready nodes, not petgraph's `toposort` (a depth-first
    /// order): the order follows the file, so plans and WGSL stay stable under edits
    /// elsewhere in the graph.
    fn topological_order(
        &mut self,
        doc: &GraphDocument,
        links: &[Vec<PendingLink>],
    ) -> Option<Vec<NodeIndex>> {
        let g = Successors::new(doc.nodes.len(), links);
        let n = g.len();
        // Kahn's sort, lowest file index first among ready nodes, so the order is stable.
        let mut indegree = vec![0usize; n];
        for u in 0..n {
            for &v in g.of(u) {
                indegree[v] += 1;
            }
        }
        let mut ready: std::collections::BTreeSet<NodeIndex> =
            (0..n).filter(|&i| indegree[i] == 0).collect();
        let mut order = Vec::with_capacity(n);
        while let Some(i) = ready.pop_first() {
            order.push(i);
            for &j in g.of(i) {
                indegree[j] -= 1;
                if indegree[j] == 0 {
                    ready.insert(j);
                }
            }
        }
        if order.len() == n {
            return Some(order);
        }
        // What is left is the cycles and what hangs off them: report each cycle once.
        let mut sorted = vec![false; n];
        for &i in &order {
            sorted[i] = true;
        }
        let components = strongly_connected(&g, &sorted);
        let mut component_of = vec![usize::MAX; n];
        for (c, members) in components.iter().enumerate() {
            for &m in members {
                component_of[m] = c;
            }
        }
        for (c, members) in components.iter().enumerate() {
            let self_loop = members.len() == 1 && g.of(members[0]).contains(&members[0]);
            if members.len() > 1 || self_loop {
                self.errors.push(GraphError::Cycle {
                    nodes: cycle_path(&g, &component_of, c, members, doc),
                });
            }
        }
        None
    }

    fn resolve_node(
        &mut self,
        n: &NodeDocument,
        t: Arc<NodeType>,
        links: &[PendingLink],
        done: &[Option<Node>],
        doc: &GraphDocument,
    ) -> Option<Node> {
        let link_type = |p: &PendingLink| done[p.target].as_ref().map(|s| s.output_type(p.output));
        let errors_before = self.errors.len();
        let mut incomplete = false;
        if t.evaluation() == Evaluation::Parameter {
            for p in links {
                self.errors.push(GraphError::WrongValueType {
                    node: n.id.clone(),
                    input: t.inputs()[p.input].name.to_owned(),
                    expected: "a literal (a parameter's value cannot be linked)".into(),
                    found: "a link".into(),
                });
            }
        }

        // The node's generic type T.
        let data_type = match &n.data_type {
            None => None,
            Some(name) => {
                match SocketType::from_name(name).filter(|ty| t.generic_types().contains(ty)) {
                    Some(ty) => Some(ty),
                    None => {
                        self.errors.push(GraphError::BadDataType {
                            node: n.id.clone(),
                            data_type: name.clone(),
                            allowed: type_list(&t.generic_types()),
                        });
                        None
                    }
                }
            }
        };
        let generic = if !t.is_generic() {
            SocketType::Float
        } else if let Some(d) = data_type {
            d
        } else {
            let mut candidates = Vec::new();
            for (k, decl) in t.inputs().iter().enumerate() {
                if decl.ty != PortType::Generic {
                    continue;
                }
                if let Some(p) = links.iter().find(|p| p.input == k) {
                    candidates.extend(link_type(p));
                } else if let Some(v) = n.inputs.get(decl.name).and_then(Value::infer_json) {
                    candidates.push(v.ty());
                }
            }
            infer_generic(&candidates, &t.generic_types())
        };

        // Inputs.
        let mut inputs = Vec::with_capacity(t.inputs().len());
        for (k, decl) in t.inputs().iter().enumerate() {
            let ty = decl.ty.resolve(generic);
            let src = if let Some(p) = links.iter().find(|p| p.input == k) {
                let Some(from_type) = link_type(p) else {
                    inputs.push(InputSource::Default(t.default_for(k, generic)));
                    continue;
                };
                match from_type.conversion_to(ty) {
                    Some(c) => InputSource::Link(
                        OutputRef {
                            node: p.target,
                            output: p.output,
                        },
                        c,
                    ),
                    None => {
                        let target = &doc.nodes[p.target];
                        let out_name = done[p.target]
                            .as_ref()
                            .map(|s| s.node_type.outputs()[p.output].name)
                            .unwrap_or("");
                        self.errors.push(GraphError::TypeMismatch {
                            node: n.id.clone(),
                            input: decl.name.to_owned(),
                            from: format!("{}.{}", target.id, out_name),
                            from_type,
                            to_type: ty,
                        });
                        continue;
                    }
                }
            } else if let Some(json) = n.inputs.get(decl.name) {
                if link_text(json).is_some() {
                    incomplete = true; // a bad or dangling link, already reported
                    continue;
                }
                match self.literal(n, decl, ty, json) {
                    Some(value) => {
                        let written = match decl.ty {
                            PortType::Generic => Value::infer_json(json).unwrap_or(value),
                            PortType::Fixed(_) => value,
                        };
                        InputSource::Value { value, written }
                    }
                    None => continue,
                }
            } else {
                InputSource::Default(t.default_for(k, generic))
            };
            inputs.push(src);
        }
        match (t.evaluation() == Evaluation::Texture, &n.texture) {
            (true, None) => self.errors.push(GraphError::BadTexture {
                node: n.id.clone(),
                message: "a texture node needs \"texture\": an image path, a list of mip level paths or a scene: texture".into(),
            }),
            (true, Some(src)) if src.files().iter().any(|f| f.is_empty()) || matches!(src, crate::document::TextureSource::MipChain(v) if v.is_empty()) => {
                self.errors.push(GraphError::BadTexture { node: n.id.clone(), message: "empty texture path".into() })
            }
            (false, Some(_)) => self.errors.push(GraphError::BadTexture {
                node: n.id.clone(),
                message: format!("a '{}' node samples no texture: remove \"texture\"", t.name()),
            }),
            _ => {}
        }
        if t.evaluation() == Evaluation::Texture
            && let Some(crate::document::TextureSource::MipChain(levels)) = &n.texture
            && levels.len() > crate::texture::MAX_MIP_LEVELS
        {
            self.errors.push(GraphError::BadTexture {
                node: n.id.clone(),
                message: format!(
                    "a mip chain of {} levels: a chain has at most {} (an image of 2^31 texels a side halves 31 times to 1×1)",
                    levels.len(),
                    crate::texture::MAX_MIP_LEVELS
                ),
            });
        }
        if t.evaluation() == Evaluation::Texture
            && let Some(src) = &n.texture
            && let Some(message) = crate::color_space::texture_key_conflict(src)
        {
            self.errors.push(GraphError::BadTexture {
                node: n.id.clone(),
                message,
            });
        }
        if let Some(name) = n.texture.as_ref().and_then(|s| s.scene_name())
            && !crate::document::TextureSource::SCENE_TEXTURES.contains(&name)
        {
            self.errors.push(GraphError::BadTexture {
                node: n.id.clone(),
                message: format!(
                    "unknown scene texture '{}{name}': a scene supplies {}",
                    crate::document::TextureSource::SCENE,
                    crate::document::TextureSource::SCENE_TEXTURES
                        .map(|t| format!("scene:{t}"))
                        .join(", ")
                ),
            });
        }
        match (&n.texture, n.color_space) {
            (None, Some(_)) if t.evaluation() != Evaluation::Texture => self.errors.push(GraphError::BadTexture {
                node: n.id.clone(),
                message: format!("a '{}' node samples no image: remove \"color_space\"", t.name()),
            }),
            (Some(src), Some(space)) if src.scene_name().is_some() => self.errors.push(GraphError::BadTexture {
                node: n.id.clone(),
                message: format!("\"color_space\": \"{space}\" on a scene texture: the renderer supplies scene textures in linear light; remove \"color_space\""),
            }),
            _ => {}
        }
        if incomplete || self.errors.len() > errors_before {
            return None;
        }
        Some(Node {
            id: n.id.clone(),
            node_type: t,
            data_type,
            generic,
            inputs,
            texture: n.texture.clone(),
            color_space: n.color_space,
            position: n.position,
            muted: n.muted,
        })
    }

    /// Reads a literal for `decl` of concrete type `ty`, reporting wrong types and ranges.
    fn literal(
        &mut self,
        n: &NodeDocument,
        decl: &InputDecl,
        ty: SocketType,
        json: &serde_json::Value,
    ) -> Option<Value> {
        let value = if let (false, Some(name)) = (decl.choices.is_empty(), json.as_str()) {
            match decl.choices.iter().position(|c| *c == name) {
                Some(i) => Some(Value::int(i as i32)),
                None => {
                    self.errors.push(GraphError::WrongValueType {
                        node: n.id.clone(),
                        input: decl.name.to_owned(),
                        expected: format!("one of {}", decl.choices.join(", ")),
                        found: format!("\"{name}\""),
                    });
                    return None;
                }
            }
        } else {
            Value::from_json(ty, json)
        };
        let Some(v) = value else {
            let expected = if decl.choices.is_empty() {
                ty.name().to_owned()
            } else {
                format!("one of {}", decl.choices.join(", "))
            };
            self.errors.push(GraphError::WrongValueType {
                node: n.id.clone(),
                input: decl.name.to_owned(),
                expected,
                found: describe_json(json),
            });
            return None;
        };
        if let Some(h) = decl.hard
            && !h.contains(&v)
        {
            self.errors.push(GraphError::OutOfRange {
                node: n.id.clone(),
                input: decl.name.to_owned(),
                value: v.to_string(),
                min: h.min,
                max: h.max,
            });
            return None;
        }
        Some(v)
    }

    fn graph_outputs(
        &mut self,
        doc: &GraphDocument,
        by_id: &HashMap<String, NodeIndex>,
        nodes: &[Option<Node>],
    ) -> Vec<GraphOutput> {
        let mut out = Vec::new();
        let mut seen = std::collections::HashSet::new();
        for o in &doc.outputs {
            if !seen.insert(o.name.as_str()) {
                self.errors.push(GraphError::BadOutput {
                    name: o.name.clone(),
                    message: "duplicate output name".into(),
                });
                continue;
            }
            let Some((id, out_name)) = o.from.split_once('.') else {
                let message = match o.from.is_empty() {
                    true => "is not connected: wire a node's output into it (\"from\": \"node_id.output\")".into(),
                    false => format!("'{}' must be written \"node_id.output\"", o.from),
                };
                self.errors.push(GraphError::BadOutput {
                    name: o.name.clone(),
                    message,
                });
                continue;
            };
            let Some(&i) = by_id.get(id) else {
                let hint = self
                    .nearest_id(id, doc)
                    .map(|s| format!(" (did you mean '{s}'?)"))
                    .unwrap_or_default();
                self.errors.push(GraphError::BadOutput {
                    name: o.name.clone(),
                    message: format!("no node '{id}'{hint}"),
                });
                continue;
            };
            let Some(node) = &nodes[i] else { continue };
            match node.node_type.output_index(out_name) {
                Some(k) => out.push(GraphOutput {
                    name: o.name.clone(),
                    source: OutputRef { node: i, output: k },
                    ty: node.output_type(k),
                }),
                None => self.errors.push(GraphError::BadOutput {
                    name: o.name.clone(),
                    message: format!("node '{id}' has no output '{out_name}'"),
                }),
            }
        }
        out
    }

    /// The inputs each `parameter` node feeds (by node index), reporting every file value
    /// outside a fed input's hard range.
    fn parameter_feeds(
        &mut self,
        doc: &GraphDocument,
        nodes: &[Option<Node>],
    ) -> HashMap<NodeIndex, Vec<Feed>> {
        let mut feeds: HashMap<NodeIndex, Vec<Feed>> = HashMap::new();
        let mut exposed: HashMap<&str, &str> = HashMap::new();
        for q in doc.parameters.iter().rev() {
            exposed.insert(q.node.as_str(), q.name.as_str());
        }
        for n in nodes.iter().flatten() {
            for (k, src) in n.inputs.iter().enumerate() {
                let (InputSource::Link(r, c), Some(range)) = (src, n.node_type.inputs()[k].hard)
                else {
                    continue;
                };
                let Some(p) = &nodes[r.node] else { continue };
                if p.node_type.evaluation() != Evaluation::Parameter {
                    continue;
                }
                let feed = Feed {
                    node: n.id.clone(),
                    input: n.node_type.inputs()[k].name,
                    range,
                    conversion: *c,
                    to: n.input_type(k),
                };
                if let InputSource::Default(v) | InputSource::Value { value: v, .. } = p.inputs[0]
                    && let Some(seen) = feed.violation(v)
                {
                    let name = exposed
                        .get(p.id.as_str())
                        .unwrap_or(&p.id.as_str())
                        .to_string();
                    self.errors.push(GraphError::ParameterOutOfRange {
                        name,
                        node: p.id.clone(),
                        target: n.id.clone(),
                        input: feed.input.to_owned(),
                        value: seen.to_string(),
                        min: range.min,
                        max: range.max,
                    });
                }
                feeds.entry(r.node).or_default().push(feed);
            }
        }
        feeds
    }

    fn graph_parameters(
        &mut self,
        doc: &GraphDocument,
        by_id: &HashMap<String, NodeIndex>,
        nodes: &[Option<Node>],
        feeds: &HashMap<NodeIndex, Vec<Feed>>,
    ) -> Vec<GraphParameter> {
        let mut out: Vec<GraphParameter> = Vec::new();
        let mut names = std::collections::HashSet::new();
        for p in &doc.parameters {
            let bad = |message: String| GraphError::BadParameter {
                name: p.name.clone(),
                message,
            };
            if names.contains(p.name.as_str()) {
                self.errors.push(bad("duplicate parameter name".into()));
                continue;
            }
            if crate::node::Attribute::from_name(&p.name).is_some() {
                self.errors
                    .push(bad("the name is taken by a geometry attribute".into()));
                continue;
            }
            let Some(&i) = by_id.get(&p.node) else {
                self.errors.push(bad(format!("no node '{}'", p.node)));
                continue;
            };
            let Some(node) = &nodes[i] else { continue };
            if node.node_type.evaluation() != Evaluation::Parameter {
                self.errors.push(bad(format!(
                    "node '{}' is a '{}', not a 'parameter' node",
                    p.node,
                    node.node_type.name()
                )));
                continue;
            }
            let default = match &node.inputs[0] {
                InputSource::Default(v) | InputSource::Value { value: v, .. } => *v,
                InputSource::Link(..) => {
                    self.errors
                        .push(bad("a parameter node's value must be a literal".into()));
                    continue;
                }
            };
            let range = match p.range {
                None => None,
                Some([min, max]) if min.is_finite() && max.is_finite() && min <= max => {
                    Some(crate::node::Range { min, max })
                }
                Some([min, max]) => {
                    self.errors.push(bad(format!(
                        "its range [{min}, {max}] must be two finite numbers, the first not above the second"
                    )));
                    continue;
                }
            };
            if let Some(r) = range
                && !r.contains(&default)
            {
                self.errors.push(bad(format!(
                    "its value {default} (node '{}') is outside its range [{}, {}]",
                    p.node, r.min, r.max
                )));
                continue;
            }
            names.insert(p.name.as_str());
            out.push(GraphParameter {
                name: p.name.clone(),
                node: i,
                ty: node.output_type(0),
                default,
                doc: p.doc.clone(),
                group: p.group.clone(),
                range,
                feeds: feeds.get(&i).cloned().unwrap_or_default(),
            });
        }
        out
    }
}

/// The link text of an input entry: `Some(Ok(text))` for `{"link": "..."}`, `Some(Err)` for
/// an object that is not a well-formed link, `None` for a literal.
fn link_text(json: &serde_json::Value) -> Option<Result<&str, ()>> {
    let obj = json.as_object()?;
    match (obj.len(), obj.get("link").and_then(|l| l.as_str())) {
        (1, Some(text)) => Some(Ok(text)),
        _ => Some(Err(())),
    }
}

/// Chooses `T` from the types feeding generic ports: the widest, colour when every
/// three-wide candidate is a colour; float when nothing constrains it. Falls back to the
/// node's first accepted type when the choice is not accepted.
fn infer_generic(candidates: &[SocketType], allowed: &[SocketType]) -> SocketType {
    let rank = |t: SocketType| match t {
        SocketType::Vec2 => 1,
        SocketType::Vec3 | SocketType::Color => 2,
        SocketType::Vec4 => 3,
        _ => 0,
    };
    let top = candidates.iter().map(|&t| rank(t)).max().unwrap_or(0);
    let t = match top {
        1 => SocketType::Vec2,
        2 if candidates
            .iter()
            .filter(|&&t| rank(t) == 2)
            .all(|&t| t == SocketType::Color) =>
        {
            SocketType::Color
        }
        2 => SocketType::Vec3,
        3 => SocketType::Vec4,
        _ => SocketType::Float,
    };
    if allowed.contains(&t) {
        t
    } else {
        allowed.first().copied().unwrap_or(t)
    }
}

fn type_list(types: &[SocketType]) -> String {
    types
        .iter()
        .map(|t| t.name())
        .collect::<Vec<_>>()
        .join(", ")
}

fn describe_json(json: &serde_json::Value) -> String {
    use serde_json::Value as J;
    match json {
        J::Null => "null".into(),
        J::Bool(b) => format!("bool {b}"),
        J::Number(n) => format!("number {n}"),
        J::String(s) => format!("string \"{s}\""),
        J::Array(a) => format!("array of {} items", a.len()),
        J::Object(_) => "object".into(),
    }
}

/// An id of a node inlined from a group ([`crate::group`]): the instance path, then the
/// node's id, or `@in:NAME` / `@out:NAME` for the nodes that carry the group's interface.
fn valid_path_id(id: &str) -> bool {
    id.contains('/')
        && id.split('/').all(|s| {
            valid_id(s)
                || s.strip_prefix("@in:")
                    .or_else(|| s.strip_prefix("@out:"))
                    .is_some_and(valid_id)
        })
}

pub(crate) fn valid_id(id: &str) -> bool {
    !id.is_empty()
        && id
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// The links of a graph as successor lists in compressed form: `of(u)` are the nodes that
/// read an output of `u` (one entry per link).
struct Successors {
    start: Vec<usize>,
    targets: Vec<NodeIndex>,
}

impl Successors {
    fn new(n: usize, links: &[Vec<PendingLink>]) -> Successors {
        let mut start = vec![0usize; n + 1];
        for pending in links {
            for p in pending {
                start[p.target + 1] += 1;
            }
        }
        for u in 0..n {
            start[u + 1] += start[u];
        }
        let mut fill = start.clone();
        let mut targets = vec![0; start[n]];
        for (i, pending) in links.iter().enumerate() {
            for p in pending {
                targets[fill[p.target]] = i;
                fill[p.target] += 1;
            }
        }
        Successors { start, targets }
    }
    fn len(&self) -> usize {
        self.start.len() - 1
    }
    fn of(&self, u: NodeIndex) -> &[NodeIndex] {
        &self.targets[self.start[u]..self.start[u + 1]]
    }
}

/// The strongly connected components of the nodes not marked `skip`, by petgraph's
/// Kosaraju (iterative: any depth in constant stack, linear time), each component's members
/// in ascending order and the components ordered by their lowest member.
fn strongly_connected(g: &Successors, skip: &[bool]) -> Vec<Vec<NodeIndex>> {
    let kept: Vec<NodeIndex> = (0..g.len()).filter(|&i| !skip[i]).collect();
    let mut at = vec![usize::MAX; g.len()];
    for (k, &i) in kept.iter().enumerate() {
        at[i] = k;
    }
    let mut sub: petgraph::Graph<NodeIndex, (), petgraph::Directed, usize> =
        petgraph::Graph::with_capacity(kept.len(), kept.len());
    for &i in &kept {
        sub.add_node(i);
    }
    for &u in &kept {
        for &v in g.of(u) {
            if !skip[v] {
                sub.add_edge(
                    petgraph::graph::NodeIndex::new(at[u]),
                    petgraph::graph::NodeIndex::new(at[v]),
                    (),
                );
            }
        }
    }
    let mut components: Vec<Vec<NodeIndex>> = petgraph::algo::kosaraju_scc(&sub)
        .into_iter()
        .map(|c| {
            let mut members: Vec<NodeIndex> = c.into_iter().map(|n| sub[n]).collect();
            members.sort_unstable();
            members
        })
        .collect();
    components.sort_unstable_by_key(|m| m[0]);
    components
}

/// The nodes of one shortest cycle through the lowest-indexed node of strongly connected
/// component `c` (members `scc`), in link order, ending where it starts.
fn cycle_path(
    g: &Successors,
    component_of: &[usize],
    c: usize,
    scc: &[NodeIndex],
    doc: &GraphDocument,
) -> Vec<String> {
    let start = *scc.iter().min().unwrap_or(&0);
    // Breadth-first search from `start` back to `start`, inside the component.
    let mut parent: HashMap<NodeIndex, NodeIndex> = HashMap::new();
    let mut queue = std::collections::VecDeque::from([start]);
    let mut last = start;
    'search: while let Some(cur) = queue.pop_front() {
        let mut next: Vec<NodeIndex> = g
            .of(cur)
            .iter()
            .copied()
            .filter(|&n| component_of[n] == c)
            .collect();
        next.sort_unstable();
        next.dedup();
        for n in next {
            if n == start {
                last = cur;
                break 'search;
            }
            if let std::collections::hash_map::Entry::Vacant(e) = parent.entry(n) {
                e.insert(cur);
                queue.push_back(n);
            }
        }
    }
    let mut path = vec![start];
    let mut cur = last;
    while cur != start {
        path.push(cur);
        cur = parent[&cur];
    }
    path.push(start);
    let end = path.len() - 1;
    path[1..end].reverse();
    path.into_iter().map(|i| doc.nodes[i].id.clone()).collect()
}

impl Graph {
    /// A graph of one node of type `type_name` with the given inputs (the others at their
    /// defaults), whose graph outputs are the node's outputs under their own names.
    pub fn single_node(
        registry: &Registry,
        type_name: &str,
        inputs: BTreeMap<String, serde_json::Value>,
    ) -> Result<Graph, Vec<GraphError>> {
        let id = "node";
        let outputs = registry
            .get(type_name)
            .map(|t| {
                t.outputs()
                    .iter()
                    .map(|o| OutputDocument {
                        name: o.name.to_owned(),
                        from: format!("{id}.{}", o.name),
                    })
                    .collect()
            })
            .unwrap_or_default();
        let doc = GraphDocument {
            version: FORMAT_VERSION,
            name: type_name.to_owned(),
            doc: String::new(),
            nodes: vec![NodeDocument {
                id: id.to_owned(),
                node_type: type_name.to_owned(),
                data_type: None,
                variant: None,
                group: None,
                muted: false,
                inputs,
                texture: None,
                color_space: None,
                position: None,
            }],
            outputs,
            parameters: Vec::new(),
            variants: BTreeMap::new(),
            groups: Default::default(),
            frames: Vec::new(),
            scene: None,
        };
        Graph::from_document(&doc, registry)
    }
}
