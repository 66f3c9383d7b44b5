//! Inlining groups: a document with groups becomes one flat document (see the module doc
//! of [`crate::group`]). Iterative over a work list of scopes (one per instance), so the
//! time is linear in the nodes produced and the stack constant whatever the nesting.

use super::{GROUP, GroupFiles, INPUT_ID, MAX_DEPTH, REROUTE, expansion_limit};
use crate::document::{GraphDocument, GroupDocument, NodeDocument, OutputDocument, TextureSource};
use crate::error::GraphError;
use crate::graph::valid_id;
use crate::registry::nearest;
use crate::types::SocketType;
use crate::value::Value;
use std::collections::{BTreeMap, HashMap, HashSet};
use std::sync::Arc;

/// A flat document and what is needed to move its errors back into the groups.
pub(crate) struct Expanded {
    /// The document with every instance inlined (no groups, no `group` nodes).
    pub doc: GraphDocument,
    /// For each instance, by its path in the flat document (`g`, `g/h`): the group
    /// reference as written on it.
    pub scopes: HashMap<String, String>,
    /// For each instance, by its path: the unique key of the group it uses (the file's key,
    /// then `#NAME` for a declared group): instances with one key have one body.
    pub defs: HashMap<String, String>,
    /// For each node that holds what an instance passes to one of its inputs (`g/@in:x`, or
    /// a whole file's parameter node `g/p`): the instance's path and the input's name.
    pub inputs: HashMap<String, (String, String)>,
}

/// A graph file taking part in the expansion.
struct File {
    key: String,
    label: String,
    folder: String,
    doc: Arc<GraphDocument>,
}

/// A resolved group: one of a file's `groups`, or a whole file.
struct Def {
    /// Unique: the file's key, then `#NAME` for a declared group.
    key: String,
    /// In messages: the file's label, then `#NAME`.
    label: String,
    file: Arc<File>,
    /// The declared group's name; `None` for a whole file.
    name: Option<String>,
    /// The interface: input names and types (`None`: taken from what is connected).
    inputs: Vec<(String, Option<SocketType>)>,
    /// The output names.
    outputs: Vec<String>,
}

impl Def {
    fn group(&self) -> Option<&GroupDocument> {
        self.name.as_ref().and_then(|n| self.file.doc.groups.get(n))
    }
    fn nodes(&self) -> &[NodeDocument] {
        match self.group() {
            Some(g) => &g.nodes,
            None => &self.file.doc.nodes,
        }
    }
    fn output_docs(&self) -> &[OutputDocument] {
        match self.group() {
            Some(g) => &g.outputs,
            None => &self.file.doc.outputs,
        }
    }
    /// The nodes one copy adds besides its instances' bodies: its inputs' and outputs'
    /// reroutes and its own nodes, as written.
    fn written_len(&self) -> usize {
        self.inputs.len() + self.nodes().len() + self.output_docs().len()
    }
}

/// The group references of the instance nodes among `nodes`, as written.
fn references(nodes: &[NodeDocument]) -> impl Iterator<Item = &str> {
    nodes
        .iter()
        .filter(|n| n.node_type == GROUP)
        .filter_map(|n| n.group.as_deref())
}

/// One body to copy: the top graph, or an instance's group.
struct Scope {
    /// Prefix of the flat ids: empty at the top, `g/` inside instance `g`.
    prefix: String,
    file: Arc<File>,
    /// The group copied (`None` at the top).
    def: Option<Arc<Def>>,
    /// The keys of the groups from the top to this one, and their labels.
    chain: Vec<(String, String)>,
    /// For a whole file: what the instance passes to each parameter (already in the flat
    /// namespace), by parameter name.
    passed: HashMap<String, serde_json::Value>,
}

/// What an id of a scope names.
enum Local {
    Node,
    Instance(Arc<Def>),
    /// An instance whose group could not be resolved (already reported).
    Broken,
    /// A whole file's exposed parameter, becoming the input it is.
    Parameter,
}

struct Expander<'a> {
    files: &'a dyn GroupFiles,
    top_key: String,
    loaded: HashMap<String, Arc<File>>,
    defs: HashMap<String, Option<Arc<Def>>>,
    errors: Vec<GraphError>,
    recursions: HashSet<String>,
    /// The unresolved references reported: (the key of the group they are written in,
    /// the instance node's id, the reference), so each is reported once, not once per copy.
    unresolved: HashSet<(String, String, String)>,
    nodes: Vec<NodeDocument>,
    variants: BTreeMap<String, crate::document::VariantDocument>,
    scopes: HashMap<String, String>,
    keys: HashMap<String, String>,
    inputs: HashMap<String, (String, String)>,
}

/// Inlines every group instance of `doc` (see the module doc). The errors name the node in
/// the scope it is written in under its flat path; [`super::relocate`] moves them into the
/// groups with the returned document's `scopes` and `inputs`.
pub(crate) fn expand(
    doc: &Arc<GraphDocument>,
    files: &dyn GroupFiles,
) -> (Expanded, Vec<GraphError>) {
    let top = Arc::new(File {
        key: files.top_key(),
        label: files.top_label(),
        folder: String::new(),
        doc: doc.clone(),
    });
    let mut x = Expander {
        files,
        top_key: top.key.clone(),
        loaded: HashMap::new(),
        defs: HashMap::new(),
        errors: Vec::new(),
        recursions: HashSet::new(),
        unresolved: HashSet::new(),
        nodes: Vec::with_capacity(doc.nodes.len()),
        variants: doc.variants.clone(),
        scopes: HashMap::new(),
        keys: HashMap::new(),
        inputs: HashMap::new(),
    };
    // Every declared group's interface is checked, used or not.
    for name in doc.groups.keys() {
        x.def_in(&top, name);
    }
    // The size once inlined, counted from the groups before anything is copied: too large,
    // and nothing is.
    let mut work = Vec::new();
    let written = x.written(&top, &doc.nodes);
    let limit = expansion_limit(written);
    match x.too_large(&top, &doc.nodes, limit) {
        Some((node, group)) => x.errors.push(GraphError::GroupTooLarge {
            node,
            group,
            max: limit,
            written,
        }),
        None => work.push(Scope {
            prefix: String::new(),
            file: top.clone(),
            def: None,
            chain: Vec::new(),
            passed: HashMap::new(),
        }),
    }
    let mut outputs = Vec::new();
    // The groups copied once: after an error, further copies of a body would only repeat
    // its errors (reported once per place written), so they are skipped.
    let mut copied: HashSet<String> = HashSet::new();
    while let Some(scope) = work.pop() {
        if let Some(def) = &scope.def {
            if !copied.insert(def.key.clone()) && !x.errors.is_empty() {
                continue;
            }
            // Checked again before each copy (the count above skips what does not resolve):
            // what this instance adds (its body, its outputs' reroutes) must fit, or the
            // expansion stops here.
            let adds = def.nodes().len() + def.output_docs().len();
            if x.nodes.len() + adds > limit {
                let node = scope.prefix.trim_end_matches('/').to_owned();
                x.errors.push(GraphError::GroupTooLarge {
                    group: x.scopes.get(&node).cloned().unwrap_or_default(),
                    node,
                    max: limit,
                    written,
                });
                break;
            }
        }
        let (locals, mut inner) = x.scope(&scope);
        if scope.def.is_none() {
            for o in &doc.outputs {
                match x.rewrite(&scope, &locals, &o.from) {
                    Ok(from) => outputs.push(OutputDocument {
                        name: o.name.clone(),
                        from,
                    }),
                    Err(fault) => x.errors.push(GraphError::BadOutput {
                        name: o.name.clone(),
                        message: fault.message(&o.from),
                    }),
                }
            }
        }
        // Pushed in reverse so that instances are copied in document order.
        inner.reverse();
        work.extend(inner);
    }
    let expanded = Expanded {
        doc: GraphDocument {
            version: doc.version,
            name: doc.name.clone(),
            doc: doc.doc.clone(),
            nodes: x.nodes,
            outputs,
            parameters: doc.parameters.clone(),
            variants: x.variants,
            groups: BTreeMap::new(),
            frames: doc.frames.clone(),
            scene: doc.scene.clone(),
        },
        scopes: x.scopes,
        defs: x.keys,
        inputs: x.inputs,
    };
    (expanded, x.errors)
}

impl Expander<'_> {
    /// The nodes written: the top graph's `nodes`, and the inputs, nodes and outputs of
    /// each group they reach once (through any number of instances and files).
    fn written(&mut self, top: &Arc<File>, nodes: &[NodeDocument]) -> usize {
        let mut count = nodes.len();
        let mut seen: HashSet<String> = HashSet::new();
        let mut work: Vec<(Arc<File>, String)> = references(nodes)
            .map(|r| (top.clone(), r.to_owned()))
            .collect();
        while let Some((file, reference)) = work.pop() {
            let Ok(def) = self.resolve(&file, &reference) else {
                continue;
            };
            if !seen.insert(def.key.clone()) {
                continue;
            }
            count = count.saturating_add(def.written_len());
            work.extend(references(def.nodes()).map(|r| (def.file.clone(), r.to_owned())));
        }
        count
    }

    /// The first instance of the top graph's `nodes` at which the inlined graph passes
    /// `limit` nodes, and its group reference; `None` when it fits. Counted from each
    /// group's size once (memoised), so a group doubling at each of 30 levels costs 30
    /// steps, not 2³⁰.
    fn too_large(
        &mut self,
        top: &Arc<File>,
        nodes: &[NodeDocument],
        limit: usize,
    ) -> Option<(String, String)> {
        let mut sizes = HashMap::new();
        let mut total = nodes.len();
        for n in nodes {
            let Some(reference) = n.group.as_deref().filter(|_| n.node_type == GROUP) else {
                continue;
            };
            let Ok(def) = self.resolve(top, reference) else {
                continue;
            };
            let size = self.inlined_size(&def, &mut sizes, &mut Vec::new(), limit);
            total = total.saturating_add(size);
            if total > limit {
                return Some((n.id.clone(), reference.to_owned()));
            }
        }
        None
    }

    /// The nodes one instance of `def` adds once inlined: its inputs' and outputs'
    /// reroutes, its body, its instances' (saturating, stopped past `limit`). A group
    /// that reaches itself or nests past [`MAX_DEPTH`] counts no further (the expansion
    /// reports it); one that does not resolve counts nothing.
    fn inlined_size(
        &mut self,
        def: &Arc<Def>,
        sizes: &mut HashMap<String, usize>,
        visiting: &mut Vec<String>,
        limit: usize,
    ) -> usize {
        if let Some(&s) = sizes.get(&def.key) {
            return s;
        }
        if visiting.contains(&def.key) || visiting.len() > MAX_DEPTH {
            return 0;
        }
        visiting.push(def.key.clone());
        let mut size = def.written_len();
        let written: Vec<String> = references(def.nodes()).map(str::to_owned).collect();
        for reference in written {
            if size > limit {
                break;
            }
            if let Ok(inner) = self.resolve(&def.file, &reference) {
                size = size.saturating_add(self.inlined_size(&inner, sizes, visiting, limit));
            }
        }
        visiting.pop();
        sizes.insert(def.key.clone(), size);
        size
    }

    /// Copies one scope's nodes into the flat document; returns what its ids name and the
    /// scopes of its instances.
    fn scope(&mut self, scope: &Scope) -> (HashMap<String, Local>, Vec<Scope>) {
        let nodes: &[NodeDocument] = match &scope.def {
            Some(d) => d.nodes(),
            None => &scope.file.doc.nodes,
        };
        let exposed: HashMap<&str, &str> = match &scope.def {
            Some(d) if d.name.is_none() => d
                .file
                .doc
                .parameters
                .iter()
                .map(|p| (p.node.as_str(), p.name.as_str()))
                .collect(),
            _ => HashMap::new(),
        };
        let at = |id: &str| format!("{}{id}", scope.prefix);

        // 1. What each id names. A repeated id is reported here, once per place written,
        // and only its first node is copied: the error stops further copies of this body
        // (see `expand`), where the builder would find it again in every copy.
        let mut locals: HashMap<String, Local> = HashMap::with_capacity(nodes.len());
        let mut repeated: HashSet<usize> = HashSet::new();
        for (k, n) in nodes.iter().enumerate() {
            if locals.contains_key(&n.id) {
                self.errors
                    .push(GraphError::DuplicateId { node: at(&n.id) });
                repeated.insert(k);
                continue;
            }
            if !valid_id(&n.id) {
                self.errors.push(GraphError::InvalidId { node: at(&n.id) });
            }
            let local = if n.node_type == GROUP {
                match self.instance_def(scope, n) {
                    Some(d) => Local::Instance(d),
                    None => Local::Broken,
                }
            } else {
                if n.group.is_some() {
                    self.errors.push(GraphError::BadGroup {
                        node: at(&n.id),
                        group: n.group.clone().unwrap_or_default(),
                        message: format!(
                            "\"group\" is read only on nodes of type \"{GROUP}\", this is a '{}'",
                            n.node_type
                        ),
                        suggestion: None,
                    });
                }
                if exposed.contains_key(n.id.as_str()) {
                    Local::Parameter
                } else {
                    Local::Node
                }
            };
            locals.insert(n.id.clone(), local);
        }

        // 2. The nodes, links rewritten into the flat namespace.
        let mut inner = Vec::new();
        for (k, n) in nodes.iter().enumerate() {
            if repeated.contains(&k) {
                continue;
            }
            match &locals[&n.id] {
                Local::Broken => {}
                Local::Instance(def) => {
                    if let Some(s) = self.instance(scope, &locals, n, def.clone()) {
                        inner.push(s);
                    }
                }
                Local::Parameter => {
                    // A whole file's parameter: a reroute holding what the instance passes,
                    // or the file's value.
                    let name = exposed[n.id.as_str()];
                    let value = scope
                        .passed
                        .get(name)
                        .cloned()
                        .or_else(|| n.inputs.get("value").cloned());
                    let path = scope.prefix.trim_end_matches('/').to_owned();
                    self.inputs.insert(at(&n.id), (path, name.to_owned()));
                    self.nodes
                        .push(reroute(at(&n.id), n.data_type.clone(), value, n));
                }
                Local::Node => {
                    let mut copy = n.clone();
                    copy.id = at(&n.id);
                    for (input, json) in copy.inputs.iter_mut() {
                        let Some(text) = link(json) else { continue };
                        match self.rewrite(scope, &locals, text) {
                            Ok(t) => *json = serde_json::json!({ "link": t }),
                            Err(e) => self.errors.push(link_error(&copy.id, input, e)),
                        }
                    }
                    if !scope.file.folder.is_empty() {
                        copy.texture = copy.texture.map(|t| rebase(t, &scope.file.folder));
                    }
                    self.nodes.push(copy);
                }
            }
        }

        // 3. A group's outputs: reroutes `PREFIX@out:NAME`.
        if let Some(def) = &scope.def {
            for o in def.output_docs() {
                let id = format!("{}@out:{}", scope.prefix, o.name);
                match self.rewrite(scope, &locals, &o.from) {
                    Ok(from) => self.nodes.push(NodeDocument {
                        id,
                        node_type: REROUTE.into(),
                        data_type: None,
                        variant: None,
                        group: None,
                        muted: false,
                        inputs: BTreeMap::from([(
                            "input".to_owned(),
                            serde_json::json!({ "link": from }),
                        )]),
                        texture: None,
                        color_space: None,
                        position: None,
                    }),
                    Err(fault) => self.errors.push(GraphError::InGroup {
                        node: scope.prefix.trim_end_matches('/').to_owned(),
                        group: def.label.clone(),
                        error: Box::new(GraphError::BadOutput {
                            name: o.name.clone(),
                            message: fault.message(&o.from),
                        }),
                    }),
                }
            }
        }
        (locals, inner)
    }

    /// The group an instance node uses, after checking it does not reach itself and does
    /// not nest too deep.
    fn instance_def(&mut self, scope: &Scope, n: &NodeDocument) -> Option<Arc<Def>> {
        let node = format!("{}{}", scope.prefix, n.id);
        let Some(reference) = n.group.as_deref() else {
            self.errors.push(GraphError::BadGroup {
                node,
                group: String::new(),
                message:
                    "a group node names its group: \"group\": \"NAME\", \"PATH#NAME\" or \"PATH\""
                        .into(),
                suggestion: None,
            });
            return None;
        };
        let def = match self.resolve(&scope.file, reference) {
            Ok(d) => d,
            Err((message, suggestion)) => {
                // Once per place written: a group copied 4 096 times with a reference that
                // does not resolve is one error, on its first copy.
                let written = scope.def.as_ref().map_or("", |d| d.key.as_str());
                let place = (written.to_owned(), n.id.clone(), reference.to_owned());
                if !self.unresolved.insert(place) {
                    return None;
                }
                self.errors.push(GraphError::BadGroup {
                    node,
                    group: reference.to_owned(),
                    message,
                    suggestion,
                });
                return None;
            }
        };
        if let Some(first) = scope.chain.iter().position(|(k, _)| *k == def.key) {
            let mut chain: Vec<String> = scope.chain[first..]
                .iter()
                .map(|(_, l)| l.clone())
                .collect();
            chain.push(def.label.clone());
            if self.recursions.insert(chain.join("\u{1}")) {
                self.errors.push(GraphError::GroupRecursion { chain });
            }
            return None;
        }
        if scope.chain.len() >= MAX_DEPTH {
            self.errors.push(GraphError::GroupTooDeep {
                node,
                group: reference.to_owned(),
                max: MAX_DEPTH,
            });
            return None;
        }
        Some(def)
    }

    /// Copies instance `n` of `def`: reroutes for its inputs now, its body as a new scope.
    fn instance(
        &mut self,
        scope: &Scope,
        locals: &HashMap<String, Local>,
        n: &NodeDocument,
        def: Arc<Def>,
    ) -> Option<Scope> {
        let path = format!("{}{}", scope.prefix, n.id);
        self.scopes
            .insert(path.clone(), n.group.clone().unwrap_or_default());
        self.keys.insert(path.clone(), def.key.clone());
        let mut passed: HashMap<String, serde_json::Value> = HashMap::new();
        let errors_before = self.errors.len();
        for (input, json) in &n.inputs {
            if !def.inputs.iter().any(|(name, _)| name == input) {
                self.errors.push(GraphError::UnknownInput {
                    node: path.clone(),
                    input: input.clone(),
                    suggestion: nearest(input, def.inputs.iter().map(|(n, _)| n.as_str()))
                        .map(str::to_owned),
                });
                continue;
            }
            let json = match link(json) {
                Some(text) => match self.rewrite(scope, locals, text) {
                    Ok(t) => serde_json::json!({ "link": t }),
                    Err(e) => {
                        self.errors.push(link_error(&path, input, e));
                        continue;
                    }
                },
                None => json.clone(),
            };
            passed.insert(input.clone(), json);
        }
        if let Some(g) = def.group() {
            for decl in &g.inputs {
                let ty = SocketType::from_name(&decl.ty).unwrap_or(SocketType::Float);
                let value = match passed.remove(&decl.name) {
                    Some(json) => {
                        if link(&json).is_none() && !self.literal_fits(&path, decl, ty, &json) {
                            continue;
                        }
                        json
                    }
                    None => decl
                        .default
                        .clone()
                        .unwrap_or_else(|| Value::zero(ty).to_json()),
                };
                let id = format!("{path}/@in:{}", decl.name);
                self.inputs
                    .insert(id.clone(), (path.clone(), decl.name.clone()));
                self.nodes
                    .push(reroute(id, Some(decl.ty.clone()), Some(value), n));
            }
        }
        if self.errors.len() > errors_before {
            return None;
        }
        let mut chain = scope.chain.clone();
        chain.push((def.key.clone(), def.label.clone()));
        Some(Scope {
            prefix: format!("{path}/"),
            file: def.file.clone(),
            def: Some(def),
            chain,
            passed,
        })
    }

    /// Whether a literal passed to interface input `decl` has its type and lies in its
    /// hard range; reports it on the instance when not.
    fn literal_fits(
        &mut self,
        node: &str,
        decl: &crate::document::GroupInputDocument,
        ty: SocketType,
        json: &serde_json::Value,
    ) -> bool {
        let Some(v) = Value::from_json(ty, json) else {
            self.errors.push(GraphError::WrongValueType {
                node: node.to_owned(),
                input: decl.name.clone(),
                expected: ty.name().to_owned(),
                found: json.to_string(),
            });
            return false;
        };
        if let Some([min, max]) = decl.hard_range
            && !(crate::node::Range { min, max }).contains(&v)
        {
            self.errors.push(GraphError::OutOfRange {
                node: node.to_owned(),
                input: decl.name.clone(),
                value: v.to_string(),
                min,
                max,
            });
            return false;
        }
        true
    }

    /// The group `reference` names, written in `file`; the message and a suggestion when
    /// there is none.
    fn resolve(
        &mut self,
        file: &Arc<File>,
        reference: &str,
    ) -> Result<Arc<Def>, (String, Option<String>)> {
        let (path, name) = match reference.split_once('#') {
            Some((p, n)) => (Some(p), Some(n)),
            None if file.doc.groups.contains_key(reference) || !reference.ends_with(".json") => {
                (None, Some(reference))
            }
            None => (Some(reference), None),
        };
        let target = match path {
            None => file.clone(),
            Some(p) => self.file(file, p)?,
        };
        match name {
            Some(name) => {
                if !target.doc.groups.contains_key(name) {
                    let suggestion = nearest(name, target.doc.groups.keys().map(String::as_str))
                        .map(str::to_owned);
                    let place = if target.label.is_empty() || path.is_none() {
                        "this file".to_owned()
                    } else {
                        target.label.clone()
                    };
                    return Err((format!("no group '{name}' in {place}"), suggestion));
                }
                self.def_in(&target, name)
                    .ok_or_else(|| ("its interface is malformed (see above)".to_owned(), None))
            }
            None => Ok(self.whole(&target)),
        }
    }

    /// The file `reference` names from `from`, read once.
    fn file(
        &mut self,
        from: &File,
        reference: &str,
    ) -> Result<Arc<File>, (String, Option<String>)> {
        let f = self
            .files
            .load(&from.key, reference)
            .map_err(|m| (m, None))?;
        if let Some(known) = self.loaded.get(&f.key) {
            return Ok(known.clone());
        }
        for (name, v) in &f.doc.variants {
            self.variants
                .entry(name.clone())
                .or_insert_with(|| v.clone());
        }
        let file = Arc::new(File {
            key: f.key.clone(),
            label: f.label,
            folder: f.folder,
            doc: f.doc,
        });
        self.loaded.insert(f.key, file.clone());
        Ok(file)
    }

    /// Declared group `name` of `file`, its interface checked once; `None` (reported) when
    /// the interface is malformed.
    fn def_in(&mut self, file: &Arc<File>, name: &str) -> Option<Arc<Def>> {
        let key = format!("{}#{name}", file.key);
        if let Some(d) = self.defs.get(&key) {
            return d.clone();
        }
        let g = &file.doc.groups[name];
        let label = format!("{}#{name}", file.label);
        let shown = if file.key == self.top_key {
            name.to_owned()
        } else {
            label.clone()
        };
        let before = self.errors.len();
        let mut inputs = Vec::new();
        for decl in &g.inputs {
            let bad = |message: String| GraphError::BadGroupInput {
                group: shown.clone(),
                input: decl.name.clone(),
                message,
            };
            if inputs.iter().any(|(n, _)| *n == decl.name) {
                self.errors.push(bad("the name is used twice".into()));
                continue;
            }
            if !valid_id(&decl.name) {
                self.errors
                    .push(bad("use letters, digits, '_' and '-' in input names".into()));
            }
            let ty = SocketType::from_name(&decl.ty).filter(|t| {
                matches!(
                    t,
                    SocketType::Float
                        | SocketType::Vec2
                        | SocketType::Vec3
                        | SocketType::Vec4
                        | SocketType::Color
                )
            });
            let Some(ty) = ty else {
                self.errors.push(bad(format!(
                    "type '{}' is not one of float, vec2, vec3, vec4, color",
                    decl.ty
                )));
                continue;
            };
            for (field, range) in [
                ("hard_range", decl.hard_range),
                ("soft_range", decl.soft_range),
            ] {
                if let Some([min, max]) = range
                    && (min > max || !min.is_finite() || !max.is_finite())
                {
                    self.errors.push(bad(format!(
                        "{field} [{min}, {max}] must be two finite f32 numbers, min ≤ max"
                    )));
                }
            }
            if let Some(json) = &decl.default {
                match Value::from_json(ty, json) {
                    None => self
                        .errors
                        .push(bad(format!("default {json} is not a {}", ty.name()))),
                    Some(v) => {
                        if let Some([min, max]) = decl.hard_range
                            && !(crate::node::Range { min, max }).contains(&v)
                        {
                            self.errors.push(bad(format!(
                                "default {v} is outside its hard_range [{min}, {max}]"
                            )));
                        }
                    }
                }
            }
            inputs.push((decl.name.clone(), Some(ty)));
        }
        let def = (self.errors.len() == before).then(|| {
            Arc::new(Def {
                key: key.clone(),
                label,
                file: file.clone(),
                name: Some(name.to_owned()),
                inputs,
                outputs: g.outputs.iter().map(|o| o.name.clone()).collect(),
            })
        });
        self.defs.insert(key, def.clone());
        def
    }

    /// A whole file as a group: its parameters are the inputs, its outputs the outputs.
    fn whole(&mut self, file: &Arc<File>) -> Arc<Def> {
        if let Some(Some(d)) = self.defs.get(&file.key) {
            return d.clone();
        }
        let def = Arc::new(Def {
            key: file.key.clone(),
            label: file.label.clone(),
            file: file.clone(),
            name: None,
            inputs: file
                .doc
                .parameters
                .iter()
                .map(|p| (p.name.clone(), None))
                .collect(),
            outputs: file.doc.outputs.iter().map(|o| o.name.clone()).collect(),
        });
        self.defs.insert(file.key.clone(), Some(def.clone()));
        def
    }

    /// A link `text` written in `scope`, in the flat namespace.
    fn rewrite(
        &self,
        scope: &Scope,
        locals: &HashMap<String, Local>,
        text: &str,
    ) -> Result<String, LinkFault> {
        let Some((id, out)) = text.split_once('.') else {
            // Malformed: reported by the validation, under the node's flat id.
            return Ok(text.to_owned());
        };
        let p = &scope.prefix;
        if id == INPUT_ID {
            let Some(def) = scope.def.as_ref().filter(|d| d.name.is_some()) else {
                return Err(LinkFault::Message(format!(
                    "'{text}' reads a group's input, and this is not inside a group{}",
                    if scope.def.is_some() {
                        " (a whole file used as a group takes its inputs through its parameters)"
                    } else {
                        ""
                    }
                )));
            };
            if !def.inputs.iter().any(|(n, _)| n == out) {
                let hint = nearest(out, def.inputs.iter().map(|(n, _)| n.as_str()))
                    .map(|s| format!(" (did you mean '{s}'?)"))
                    .unwrap_or_default();
                return Err(LinkFault::Message(format!(
                    "link to '{text}': group {} has no input '{out}'{hint}",
                    def.label.trim_start_matches('#')
                )));
            }
            return Ok(format!("{p}@in:{out}.output"));
        }
        match locals.get(id) {
            Some(Local::Instance(def)) => {
                if def.outputs.iter().any(|o| o == out) {
                    Ok(format!("{p}{id}/@out:{out}.output"))
                } else {
                    let hint = nearest(out, def.outputs.iter().map(String::as_str))
                        .map(|s| format!(" (did you mean '{s}'?)"))
                        .unwrap_or_default();
                    Err(LinkFault::Message(format!(
                        "link to '{text}': group node '{id}' has no output '{out}'{hint}"
                    )))
                }
            }
            Some(Local::Parameter) if out == "value" => Ok(format!("{p}{id}.output")),
            // Inside a group body an id that is not one of its nodes is reported here, once
            // per place written (the error stops further copies of the body), with a
            // suggestion among the body's own ids; the builder would find it again in every
            // copy and search the whole inlined graph for each.
            None if scope.def.is_some() => Err(LinkFault::Missing {
                target: id.to_owned(),
                suggestion: nearest(id, locals.keys().map(String::as_str)).map(str::to_owned),
            }),
            _ => Ok(format!("{p}{id}.{out}")),
        }
    }
}

/// Why a link in a scope cannot be rewritten into the flat namespace.
enum LinkFault {
    /// A link inside a group body to an id the body does not have.
    Missing {
        /// The id linked to, as written.
        target: String,
        /// The nearest id of the same body.
        suggestion: Option<String>,
    },
    /// Any other fault, as a message.
    Message(String),
}

impl LinkFault {
    /// The fault as a message (where it is reported inside another error).
    fn message(self, text: &str) -> String {
        match self {
            LinkFault::Message(m) => m,
            LinkFault::Missing { target, suggestion } => format!(
                "link to '{text}': there is no node '{target}' here{}",
                crate::error::did_you_mean(&suggestion)
            ),
        }
    }
}

/// The link text of an input entry, if it is a well-formed link.
fn link(json: &serde_json::Value) -> Option<&str> {
    let obj = json.as_object()?;
    (obj.len() == 1).then(|| obj.get("link")?.as_str())?
}

/// A link that cannot be rewritten, on `input` of flat node `node`.
fn link_error(node: &str, input: &str, fault: LinkFault) -> GraphError {
    match fault {
        LinkFault::Missing { target, suggestion } => GraphError::MissingNode {
            node: node.to_owned(),
            input: input.to_owned(),
            target,
            suggestion,
        },
        LinkFault::Message(message) => GraphError::GroupLink {
            node: node.to_owned(),
            input: input.to_owned(),
            message,
        },
    }
}

/// A reroute node `id` of type `data_type` (from what is connected when `None`) passing
/// `value` on, placed where `at` is.
fn reroute(
    id: String,
    data_type: Option<String>,
    value: Option<serde_json::Value>,
    at: &NodeDocument,
) -> NodeDocument {
    NodeDocument {
        id,
        node_type: REROUTE.into(),
        data_type,
        variant: None,
        group: None,
        muted: false,
        inputs: value
            .map(|v| BTreeMap::from([("input".to_owned(), v)]))
            .unwrap_or_default(),
        texture: None,
        color_space: None,
        position: at.position,
    }
}

/// A texture source written in a file of `folder` (relative to the top graph's), as the
/// top graph would write it.
fn rebase(t: TextureSource, folder: &str) -> TextureSource {
    let one = |p: String| {
        if p.starts_with(TextureSource::SCENE) || p.starts_with('/') {
            p
        } else {
            format!("{folder}{p}")
        }
    };
    match t {
        TextureSource::Image(p) => TextureSource::Image(one(p)),
        TextureSource::MipChain(v) => TextureSource::MipChain(v.into_iter().map(one).collect()),
    }
}
