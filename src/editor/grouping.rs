//! Making and undoing node groups in the document (Ctrl+G, Alt+G), free of drawing: each
//! returns the new document, which the state applies as one undo step.
//!
//! **Grouping** (Blender's Make Group) moves the selected nodes into a new inline group
//! (`"groups": { NAME: … }`) and puts one `group` instance where they were. Each distinct
//! source outside the selection that feeds it (a link, by its source and the type of the
//! input it feeds) becomes an interface input, named after the first input it feeds (made
//! unique), typed by that input, with its default, ranges, unit and doc; the instance links
//! the source into it. Each output of a selected node read from outside (by a node or a
//! graph output) becomes a group output, named after the output (made unique), and the
//! readers read the instance. The group inlines to the same flat graph, so it evaluates to
//! the same bits: an interface input is a reroute typed by the input it feeds, where the same
//! conversion happens as before.
//!
//! **Ungrouping** (Blender's Ungroup) copies an instance's group back in its place (ids made
//! unique, placed around the instance) and removes the group when nothing else uses it. A
//! link to `@in.NAME` reads what the instance passed; where that would change a conversion
//! (the source's type is not the interface input's and the reader's port is generic, or not
//! of the interface's type), a `reroute` typed by the interface input keeps it, as the
//! loader's inlining does, so the graph evaluates to the same bits. A group of another file
//! (`lib/x.json#name`) ungroups too: its nodes are copied in, their group references and
//! texture paths rebased onto this file.

use super::model::{EditorDoc, link_json, link_of};
use super::outputs::OUTPUT_NODE;
use super::ports::Port;
use super::scope::{INPUT_NODE, Resolved, fresh, interface_type, resolve};
use crate::document::{
    GraphDocument, GroupDocument, GroupInputDocument, NodeDocument, OutputDocument, TextureSource,
};
use crate::group::{GROUP, REROUTE};
use crate::node::PortType;
use crate::types::SocketType;
use crate::value::Value;
use std::collections::{BTreeMap, HashMap, HashSet};

/// The name new groups are given (made unique: `group_2`, …).
pub const GROUP_BASE: &str = "group";

/// A group made from a selection.
#[derive(Clone, Debug)]
pub struct Grouped {
    /// The document with the group and its instance.
    pub doc: GraphDocument,
    /// The group's name.
    pub group: String,
    /// The instance's id.
    pub instance: String,
}

/// A group instance ungrouped.
#[derive(Clone, Debug)]
pub struct Ungrouped {
    /// The document with the instance's nodes in its place.
    pub doc: GraphDocument,
    /// The ids of the nodes put in its place (the group's, then any reroute).
    pub nodes: Vec<String>,
    /// Whether the group's definition was removed (no other instance used it).
    pub removed: bool,
}

/// The type of the output `link` (`node.output`, or `@in.NAME` inside a group) reads in
/// `d`, where known.
pub fn source_type(d: &EditorDoc, link: &str) -> Option<SocketType> {
    let (src, out) = link.split_once('.')?;
    let p = d.ports(src)?.outputs.iter().find(|p| p.name == out)?;
    d.port_type(src, p.ty)
}

/// Whether `ids` can be grouped in `d`, and why not.
fn check_selection(d: &EditorDoc, ids: &[String]) -> Result<(), String> {
    if let Some(why) = d.read_only() {
        return Err(why.to_owned());
    }
    if ids.is_empty() {
        return Err("nothing selected: select the nodes to group, then Ctrl+G".into());
    }
    if ids.iter().any(|i| i == OUTPUT_NODE) {
        let what = match d.body() {
            Some(_) => "the Group Output node is the group's outputs",
            None => "the Material Output node is the graph's outputs",
        };
        return Err(format!(
            "cannot group: {what}, not a node (deselect it; what it reads becomes the group's output)"
        ));
    }
    if ids.iter().any(|i| i == INPUT_NODE) {
        return Err(
            "cannot group: the Group Input node is the group's inputs, not a node (deselect it)"
                .into(),
        );
    }
    for id in ids {
        if d.node(id).is_none() {
            return Err(format!("cannot group: no node '{id}'"));
        }
        if let Some(p) = d.doc().parameters.iter().find(|p| &p.node == id) {
            return Err(format!(
                "cannot group: '{id}' is the graph's parameter '{}', and an app sets parameters at the graph's top level; deselect it (it will feed the group through an input) or un-expose it first",
                p.name
            ));
        }
    }
    Ok(())
}

/// The interface input made for `port` of type `ty` (its default, ranges, unit and doc).
fn interface_input(
    name: &str,
    port: Option<&Port>,
    ty: SocketType,
    generic: Option<SocketType>,
) -> GroupInputDocument {
    let range = |r: Option<crate::node::Range>| r.map(|r| [r.min, r.max]);
    let default = port
        .map(|p| p.default_for(generic.unwrap_or(ty)))
        .and_then(|v| v.convert(ty))
        .filter(|v| *v != Value::zero(ty))
        .map(|v| v.to_json());
    GroupInputDocument {
        name: name.to_owned(),
        ty: ty.name().to_owned(),
        default,
        soft_range: port.and_then(|p| range(p.soft)),
        hard_range: port.and_then(|p| range(p.hard)),
        unit: port.map(|p| p.unit.to_string()).filter(|u| !u.is_empty()),
        doc: port.map(|p| p.doc.to_string()).unwrap_or_default(),
    }
}

/// Groups the nodes `ids` of `d` into a new inline group and one instance of it (see the
/// module doc); refused, with the reason, for an empty selection, the Material Output or
/// Group Input node, an exposed parameter, an input of a type a group's interface cannot
/// carry (int, bool) fed from outside, or a read-only group.
pub fn group(d: &EditorDoc, ids: &[String]) -> Result<Grouped, String> {
    check_selection(d, ids)?;
    let doc = d.doc();
    let sel: HashSet<&str> = ids.iter().map(String::as_str).collect();
    let taken_groups: HashSet<String> = doc.groups.keys().cloned().collect();
    let name = fresh(GROUP_BASE, &taken_groups);
    let instance = d.fresh_id(&name);

    // Inputs: each distinct outside source, by the type of the input it feeds.
    let mut inputs: Vec<GroupInputDocument> = Vec::new();
    let mut by_source: HashMap<(String, SocketType), String> = HashMap::new();
    let mut passed: BTreeMap<String, serde_json::Value> = BTreeMap::new();
    let mut body: Vec<NodeDocument> = Vec::new();
    for n in doc.nodes.iter().filter(|n| sel.contains(n.id.as_str())) {
        let mut copy = n.clone();
        let ports = d.ports(&n.id);
        // In pin order, then any other input written.
        let mut names: Vec<String> = ports
            .map(|p| p.inputs.iter().map(|i| i.name.to_string()).collect())
            .unwrap_or_default();
        names.extend(
            n.inputs
                .keys()
                .filter(|k| !names.contains(k))
                .cloned()
                .collect::<Vec<_>>(),
        );
        for input in names {
            let Some(link) = n.inputs.get(&input).and_then(link_of) else {
                continue;
            };
            let src = link.split_once('.').map_or(link, |(s, _)| s);
            if sel.contains(src) {
                continue;
            }
            let port = ports.and_then(|p| p.inputs.iter().find(|i| i.name == input.as_str()));
            let Some(ty) = port.and_then(|p| d.port_type(&n.id, p.ty)) else {
                return Err(format!(
                    "cannot group: the type of input '{input}' of '{}' is not known yet (the graph has errors); fix them first",
                    n.id
                ));
            };
            if !interface_type(ty) {
                return Err(format!(
                    "cannot group: input '{input}' of '{}' is {ty}, fed from outside by {link}, and a group's inputs are float, vec2, vec3, vec4 or color; select its source too, or leave '{}' out",
                    n.id, n.id
                ));
            }
            let key = (link.to_owned(), ty);
            let iname = match by_source.get(&key) {
                Some(k) => k.clone(),
                None => {
                    let taken: HashSet<String> = inputs.iter().map(|i| i.name.clone()).collect();
                    let iname = fresh(&input, &taken);
                    inputs.push(interface_input(&iname, port, ty, d.generic(&n.id)));
                    passed.insert(iname.clone(), link_json_text(link));
                    by_source.insert(key, iname.clone());
                    iname
                }
            };
            copy.inputs.insert(input, link_json(INPUT_NODE, &iname));
        }
        body.push(copy);
    }

    // Outputs: each output of a selected node read from outside, in node and pin order.
    let mut read: Vec<(usize, usize, String, String)> = Vec::new();
    let mut note = |link: &str| {
        let Some((src, out)) = link.split_once('.') else {
            return;
        };
        if !sel.contains(src) || read.iter().any(|r| r.2 == src && r.3 == out) {
            return;
        }
        let k = d.index(src).unwrap_or(usize::MAX);
        let o = d
            .ports(src)
            .and_then(|p| p.output_index(out))
            .unwrap_or(usize::MAX);
        read.push((k, o, src.to_owned(), out.to_owned()));
    };
    for n in doc.nodes.iter().filter(|n| !sel.contains(n.id.as_str())) {
        for v in n.inputs.values() {
            if let Some(l) = link_of(v) {
                note(l);
            }
        }
    }
    for o in &doc.outputs {
        note(&o.from);
    }
    read.sort();
    let mut outputs: Vec<OutputDocument> = Vec::new();
    let mut out_name: HashMap<String, String> = HashMap::new();
    for (_, _, src, out) in &read {
        let taken: HashSet<String> = outputs.iter().map(|o| o.name.clone()).collect();
        let oname = fresh(out, &taken);
        outputs.push(OutputDocument {
            name: oname.clone(),
            from: format!("{src}.{out}"),
        });
        out_name.insert(format!("{src}.{out}"), oname);
    }

    // The instance, at the centre of the selection's box (ungrouping puts the nodes back
    // where they were), in the document where its first node was.
    let places: Vec<[f32; 2]> = body.iter().filter_map(|n| n.position).collect();
    let position = (!places.is_empty()).then(|| {
        let (lo, hi) = bounds(&places);
        [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0]
    });
    let inst = NodeDocument {
        id: instance.clone(),
        node_type: GROUP.into(),
        data_type: None,
        variant: None,
        group: Some(name.clone()),
        muted: false,
        inputs: passed,
        texture: None,
        color_space: None,
        position,
    };
    let mut new = doc.clone();
    new.nodes.clear();
    let mut placed = false;
    for n in &doc.nodes {
        if sel.contains(n.id.as_str()) {
            if !placed {
                new.nodes.push(inst.clone());
                placed = true;
            }
            continue;
        }
        let mut copy = n.clone();
        for v in copy.inputs.values_mut() {
            if let Some(o) = link_of(v).and_then(|l| out_name.get(l)) {
                *v = link_json(&instance, o);
            }
        }
        new.nodes.push(copy);
    }
    for o in &mut new.outputs {
        if let Some(k) = out_name.get(&o.from) {
            o.from = format!("{instance}.{k}");
        }
    }
    // Frames: the nodes leave theirs; the instance joins a frame that held them all.
    let whole = new
        .frames
        .iter()
        .position(|f| ids.iter().all(|i| f.nodes.contains(i)));
    for f in &mut new.frames {
        f.nodes.retain(|n| !sel.contains(n.as_str()));
    }
    if let Some(k) = whole {
        new.frames[k].nodes.push(instance.clone());
    }
    new.groups.insert(
        name.clone(),
        GroupDocument {
            doc: String::new(),
            inputs,
            nodes: body,
            outputs,
        },
    );
    new.version = new.version.max(crate::document::GROUPS_VERSION);
    Ok(Grouped {
        doc: new,
        group: name,
        instance,
    })
}

/// `{ "link": link }`.
fn link_json_text(link: &str) -> serde_json::Value {
    serde_json::json!({ "link": link })
}

/// How many instances of the group `name` of the document's own `groups` `doc` holds, in
/// its nodes and in every group's but `skip`'s (the group whose body `doc` is).
pub fn instances_of(doc: &GraphDocument, name: &str, skip: Option<&str>) -> usize {
    let uses = |nodes: &[NodeDocument]| {
        nodes
            .iter()
            .filter(|n| n.node_type == GROUP && n.group.as_deref() == Some(name))
            .count()
    };
    uses(&doc.nodes)
        + doc
            .groups
            .iter()
            .filter(|(g, _)| Some(g.as_str()) != skip)
            .map(|(_, g)| uses(&g.nodes))
            .sum::<usize>()
}

/// What an interface input reads where an instance is ungrouped: what the instance
/// passes, else the input's default.
enum Passed {
    Link(String),
    Literal(serde_json::Value),
}

/// Ungroups the group instance `id` of `d` (see the module doc). `elsewhere`: how many
/// instances of its group the root holds outside `d` (inside a group, those of the graph's
/// top and of other groups), so that the group is removed only when none is left.
pub fn ungroup(d: &EditorDoc, id: &str, elsewhere: usize) -> Result<Ungrouped, String> {
    if let Some(why) = d.read_only() {
        return Err(why.to_owned());
    }
    let Some(node) = d.node(id).cloned() else {
        return Err(format!("cannot ungroup: no node '{id}'"));
    };
    if node.node_type != GROUP {
        return Err(format!(
            "cannot ungroup '{id}': it is not a group instance (Alt+G ungroups one)"
        ));
    }
    let reference = node.group.clone().unwrap_or_default();
    let resolved = resolve(d, &reference).map_err(|e| format!("cannot ungroup '{id}': {e}"))?;
    let doc = d.doc();
    let (def, own, lib) = match &resolved {
        Resolved::Own(name) => (doc.groups[name].clone(), Some(name.clone()), None),
        Resolved::Library { file, name } => (file.doc.groups[name].clone(), None, Some(file)),
    };
    let registry = d.registry();
    // The context the group's nodes are written in: this document, or their file.
    let ctx: &GraphDocument = lib.map_or(doc, |f| &f.doc);
    let files = d.files().map(|f| f.as_ref());

    // Fresh ids for the group's nodes.
    let mut taken: HashSet<String> = doc.nodes.iter().map(|n| n.id.clone()).collect();
    taken.extend(
        doc.outputs
            .iter()
            .filter_map(|o| o.from.split_once('.').map(|(n, _)| n.to_owned())),
    );
    let mut renamed: HashMap<String, String> = HashMap::new();
    for n in &def.nodes {
        let new = fresh(&n.id, &taken);
        taken.insert(new.clone());
        renamed.insert(n.id.clone(), new);
    }

    // Where the copies go: their bounding box centred on the instance.
    let depth = super::layout::depths(&GraphDocument {
        nodes: def.nodes.clone(),
        ..empty_like(doc)
    });
    let mut rows: HashMap<usize, usize> = HashMap::new();
    let inner: Vec<[f32; 2]> = def
        .nodes
        .iter()
        .enumerate()
        .map(|(k, n)| {
            n.position.unwrap_or_else(|| {
                let row = rows.entry(depth[k]).or_default();
                *row += 1;
                let [dx, dy] = super::view::LAYOUT_STEP;
                [depth[k] as f32 * dx, (*row - 1) as f32 * dy]
            })
        })
        .collect();
    let (lo, hi) = bounds(&inner);
    let at = node.position.unwrap_or([0.0, 0.0]);
    let offset = match lo[0].is_finite() {
        true => [at[0] - (lo[0] + hi[0]) / 2.0, at[1] - (lo[1] + hi[1]) / 2.0],
        false => [0.0, 0.0],
    };

    // What each interface input reads.
    let iface: Vec<(String, Option<SocketType>, Passed)> =
        def.inputs
            .iter()
            .map(|decl| {
                let ty = SocketType::from_name(&decl.ty);
                let passed =
                    match node.inputs.get(&decl.name) {
                        Some(v) => match link_of(v) {
                            Some(l) => Passed::Link(l.to_owned()),
                            None => Passed::Literal(v.clone()),
                        },
                        None => Passed::Literal(decl.default.clone().unwrap_or_else(|| {
                            Value::zero(ty.unwrap_or(SocketType::Float)).to_json()
                        })),
                    };
                (decl.name.clone(), ty, passed)
            })
            .collect();
    // The type the loader inferred for each generic node of the group in this instance.
    let flat = d.graph();
    let old_t: HashMap<String, SocketType> = def
        .nodes
        .iter()
        .filter(|n| registry.get(&n.node_type).is_some_and(|t| t.is_generic()))
        .filter_map(|n| {
            let g = flat?;
            let k = g.node_index(&format!("{id}/{}", n.id))?;
            Some((n.id.clone(), g.nodes()[k].generic))
        })
        .collect();
    // Builds the document; the generic nodes in `careful` read `@in` through reroutes
    // (else a generic port counts as one of the type the loader inferred for it).
    let assemble = |careful: &HashSet<String>| -> (GraphDocument, Vec<String>, bool) {
        let mut taken = taken.clone();
        let mut reroutes: BTreeMap<String, NodeDocument> = BTreeMap::new();
        let mut reroute_ids: Vec<String> = Vec::new();
        // The entry written where `@in.NAME` was read by a port of type `port` (a generic
        // port: the type inferred for it; `None`: a switch's, a graph output, or not known).
        let mut read_input = |name: &str, port: Option<SocketType>| -> Option<serde_json::Value> {
            let (_, ty, passed) = iface.iter().find(|(n, ..)| n == name)?;
            let ty = *ty;
            let direct = match passed {
                Passed::Link(l) => ty.is_some() && (source_type(d, l) == ty || port == ty),
                Passed::Literal(_) => ty.is_some() && port == ty,
            };
            if direct {
                return Some(match passed {
                    Passed::Link(l) => link_json_text(l),
                    Passed::Literal(v) => v.clone(),
                });
            }
            let r = reroutes.entry(name.to_owned()).or_insert_with(|| {
                let rid = fresh(name, &taken);
                taken.insert(rid.clone());
                reroute_ids.push(rid.clone());
                NodeDocument {
                    id: rid,
                    node_type: REROUTE.into(),
                    data_type: ty.map(|t| t.name().to_owned()),
                    variant: None,
                    group: None,
                    muted: false,
                    inputs: BTreeMap::from([(
                        "input".to_owned(),
                        match passed {
                            Passed::Link(l) => link_json_text(l),
                            Passed::Literal(v) => v.clone(),
                        },
                    )]),
                    texture: None,
                    color_space: None,
                    position: None,
                }
            });
            Some(link_json(&r.id, "output"))
        };

        // The copies, links rewritten.
        let mut copies: Vec<NodeDocument> = Vec::new();
        for (k, n) in def.nodes.iter().enumerate() {
            let mut copy = n.clone();
            copy.id = renamed[&n.id].clone();
            copy.position = Some([inner[k][0] + offset[0], inner[k][1] + offset[1]]);
            let ports = super::ports::ports_of(ctx, n, registry, None, files);
            let switch = n.node_type == crate::variant::SWITCH;
            let mut entries = BTreeMap::new();
            for (input, v) in &n.inputs {
                let entry = match link_of(v).and_then(|l| l.split_once('.')) {
                    Some((src, out)) if src == INPUT_NODE => {
                        let port = ports
                            .inputs
                            .iter()
                            .find(|p| p.name == input.as_str())
                            .and_then(|p| match p.ty {
                                PortType::Fixed(t) if !switch => Some(t),
                                PortType::Generic if !careful.contains(&n.id) => {
                                    old_t.get(&n.id).copied()
                                }
                                _ => None,
                            });
                        match read_input(out, port) {
                            Some(e) => e,
                            None => continue,
                        }
                    }
                    Some((src, out)) => match renamed.get(src) {
                        Some(new) => link_json(new, out),
                        None => v.clone(),
                    },
                    None => v.clone(),
                };
                entries.insert(input.clone(), entry);
            }
            copy.inputs = entries;
            if let Some(file) = lib {
                rebase_node(&mut copy, &file.label, &file.folder, &file.doc);
            }
            copies.push(copy);
        }
        // What each of the group's outputs becomes: the entry its readers get.
        let mut outputs: HashMap<String, Option<serde_json::Value>> = HashMap::new();
        for o in &def.outputs {
            let entry = match o.from.split_once('.') {
                Some((src, out)) if src == INPUT_NODE => read_input(out, None),
                Some((src, out)) => Some(match renamed.get(src) {
                    Some(new) => link_json(new, out),
                    None => link_json_text(&o.from),
                }),
                None => None,
            };
            outputs.insert(o.name.clone(), entry);
        }
        // Reroutes go left of the copies, one under the other.
        let left = copies
            .iter()
            .filter_map(|c| c.position)
            .fold(f32::INFINITY, |m, p| m.min(p[0]));
        let left = if left.is_finite() { left } else { at[0] };
        let reroutes: Vec<NodeDocument> = reroute_ids
            .iter()
            .enumerate()
            .filter_map(|(k, rid)| {
                let mut r = reroutes.values().find(|r| &r.id == rid)?.clone();
                r.position = Some([left - 160.0, at[1] + 60.0 * k as f32]);
                Some(r)
            })
            .collect();

        let mut new = doc.clone();
        new.nodes.clear();
        let read_of = |l: &str| -> Option<&Option<serde_json::Value>> {
            let (src, out) = l.split_once('.')?;
            (src == id).then(|| outputs.get(out))?
        };
        for n in &doc.nodes {
            if n.id == id {
                new.nodes.extend(reroutes.iter().cloned());
                new.nodes.extend(copies.iter().cloned());
                continue;
            }
            let mut copy = n.clone();
            let mut gone = Vec::new();
            for (input, v) in copy.inputs.iter_mut() {
                match link_of(v).and_then(read_of) {
                    Some(Some(e)) => *v = e.clone(),
                    Some(None) => gone.push(input.clone()),
                    None => {}
                }
            }
            for g in gone {
                copy.inputs.remove(&g);
            }
            new.nodes.push(copy);
        }
        for o in &mut new.outputs {
            match read_of(&o.from) {
                Some(Some(e)) => match link_of(e) {
                    Some(l) => o.from = l.to_owned(),
                    None => o.from.clear(),
                },
                Some(None) => o.from.clear(),
                None => {}
            }
        }
        let mut ids: Vec<String> = copies.iter().map(|c| c.id.clone()).collect();
        ids.extend(reroutes.iter().map(|r| r.id.clone()));
        for f in &mut new.frames {
            if let Some(k) = f.nodes.iter().position(|n| n == id) {
                f.nodes.splice(k..=k, ids.iter().cloned());
            }
        }
        (new, ids, !reroutes.is_empty())
    };
    // Direct links where they keep each generic node's type; where one changes, that node
    // reads through reroutes (as the inlined group did), until every type is the same.
    let mut careful: HashSet<String> = HashSet::new();
    let (mut new, mut ids, mut rerouted) = assemble(&careful);
    for _ in 0..=def.nodes.len() {
        let mut probe = d.clone();
        probe.replace(new.clone());
        let changed: Vec<String> = match probe.graph() {
            Some(_) => old_t
                .iter()
                .filter(|(f, t)| !careful.contains(*f) && probe.generic(&renamed[*f]) != Some(**t))
                .map(|(f, _)| f.clone())
                .collect(),
            None => old_t
                .keys()
                .filter(|f| !careful.contains(*f))
                .cloned()
                .collect(),
        };
        if changed.is_empty() {
            break;
        }
        careful.extend(changed);
        (new, ids, rerouted) = assemble(&careful);
    }
    if let Some(file) = lib {
        for (k, v) in &file.doc.variants {
            new.variants.entry(k.clone()).or_insert_with(|| v.clone());
        }
    }
    let removed = match &own {
        Some(name) => {
            let skip = d.body().map(|b| b.group.as_str());
            let left = instances_of(&new, name, skip) + elsewhere;
            if left == 0 {
                new.groups.remove(name);
            }
            left == 0
        }
        None => false,
    };
    if rerouted {
        new.version = new.version.max(crate::document::GROUPS_VERSION);
    }
    Ok(Ungrouped {
        doc: new,
        nodes: ids,
        removed,
    })
}

/// The box around `places`: its lowest and highest corner (infinite when empty).
fn bounds(places: &[[f32; 2]]) -> ([f32; 2], [f32; 2]) {
    places.iter().fold(
        ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]),
        |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1])],
                [hi[0].max(p[0]), hi[1].max(p[1])],
            )
        },
    )
}

/// An empty document with `doc`'s header.
fn empty_like(doc: &GraphDocument) -> GraphDocument {
    GraphDocument {
        version: doc.version,
        name: String::new(),
        doc: String::new(),
        nodes: Vec::new(),
        outputs: Vec::new(),
        parameters: Vec::new(),
        variants: Default::default(),
        groups: Default::default(),
        frames: Vec::new(),
        scene: None,
    }
}

/// A node copied from the library file `label` (in folder `folder`, relative to this
/// graph's) into this graph: its group reference and texture paths rewritten so that they
/// name what they named there.
fn rebase_node(n: &mut NodeDocument, label: &str, folder: &str, lib: &GraphDocument) {
    let path = |p: &str| -> String {
        if p.starts_with('/') || p.starts_with(TextureSource::SCENE) {
            p.to_owned()
        } else {
            format!("{folder}{p}")
        }
    };
    if let Some(r) = &n.group {
        n.group = Some(match r.split_once('#') {
            Some((p, name)) => format!("{}#{name}", path(p)),
            None if lib.groups.contains_key(r) || !r.ends_with(".json") => format!("{label}#{r}"),
            None => path(r),
        });
    }
    n.texture = n.texture.take().map(|t| match t {
        TextureSource::Image(p) => TextureSource::Image(path(&p)),
        TextureSource::MipChain(v) => TextureSource::MipChain(v.iter().map(|p| path(p)).collect()),
    });
}
