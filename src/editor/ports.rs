//! The pins the editor draws on a node: a registered type's declared inputs and outputs,
//! or, for a group instance (`"type": "group"`, format version 2, see [`crate::group`]),
//! the group's interface, so that an instance is drawn as one node. A group of the same file
//! is read from the document's `groups`; a group of another file (`lib/layers.json#blend`,
//! or a whole file) through the [`GroupFiles`] of the graph's file. The types of a group's
//! outputs (and of a whole file's inputs) come from the validated graph, whose inlined nodes
//! hold them (`g/@out:NAME`, see [`crate::group`]), and are unknown while it has errors.
//! Where the interface cannot be read (no such group, no file to read it from), and for a
//! node whose type the registry lacks, the node gets the pins its links use, so that its
//! wires still show. A `switch` ([`crate::variant`]) gets one input per choice of the variant
//! set it names, in the set's order, and its output `result`, typed by the first linked
//! choice's source ([`super::variants`]).

use crate::document::{GraphDocument, GroupDocument, NodeDocument};
use crate::graph::Graph;
use crate::group::{GROUP, GroupFiles};
use crate::node::{InputDecl, NodeType, OutputDecl, PortType, Range};
use crate::registry::Registry;
use crate::types::SocketType;
use crate::value::Value;
use crate::variant::{SWITCH, SWITCH_OUTPUT};
use std::borrow::Cow;
use std::sync::Arc;

/// One pin of a node as the editor draws and edits it.
#[derive(Clone, Debug, PartialEq)]
pub struct Port {
    /// The input's or output's name.
    pub name: Cow<'static, str>,
    /// Its type (`Generic` for a generic port, and for a group port of unknown type).
    pub ty: PortType,
    /// An input's default (for a generic port: a float broadcast to `T`).
    pub default: Value,
    /// The range a slider spans.
    pub soft: Option<Range>,
    /// The range a literal must lie in.
    pub hard: Option<Range>,
    /// Its unit ("" when dimensionless).
    pub unit: Cow<'static, str>,
    /// What it means.
    pub doc: Cow<'static, str>,
    /// The choices of an enum (int) input.
    pub choices: &'static [&'static str],
}

impl Port {
    /// A registered type's input.
    pub fn input(d: &InputDecl) -> Port {
        Port {
            name: Cow::Borrowed(d.name),
            ty: d.ty,
            default: d.default,
            soft: d.soft,
            hard: d.hard,
            unit: Cow::Borrowed(d.unit),
            doc: Cow::Borrowed(d.doc),
            choices: d.choices,
        }
    }

    /// A registered type's output.
    pub fn output(d: &OutputDecl) -> Port {
        Port {
            name: Cow::Borrowed(d.name),
            ty: d.ty,
            default: Value::float(0.0),
            soft: None,
            hard: None,
            unit: Cow::Borrowed(d.unit),
            doc: Cow::Borrowed(d.doc),
            choices: &[],
        }
    }

    /// A port called `name` of type `ty` (`None`: unknown), nothing else known.
    fn named(name: &str, ty: Option<SocketType>) -> Port {
        Port {
            name: Cow::Owned(name.to_owned()),
            ty: ty.map_or(PortType::Generic, PortType::Fixed),
            default: ty.map_or(Value::float(0.0), Value::zero),
            soft: None,
            hard: None,
            unit: Cow::Borrowed(""),
            doc: Cow::Borrowed(""),
            choices: &[],
        }
    }

    /// The default at the node's generic type `generic` (as
    /// [`NodeType::default_for`]).
    pub fn default_for(&self, generic: SocketType) -> Value {
        let ty = self.ty.resolve(generic);
        self.default.convert(ty).unwrap_or(self.default)
    }
}

/// Where a node's pins come from.
#[derive(Clone, Debug)]
pub enum Kind {
    /// A registered node type.
    Type(Arc<NodeType>),
    /// A group instance.
    Group {
        /// The reference as written on the node (`NAME`, `PATH#NAME`, `PATH`).
        reference: String,
        /// The group's doc (a whole file's).
        doc: String,
        /// Whether the pins are the group's interface (else its links', the interface
        /// could not be read).
        interface: bool,
    },
    /// A `switch` node: one input per choice of its variant set.
    Switch {
        /// The variant set it names (`""` when it names none).
        variant: String,
        /// Whether the set is declared (else its pins are its links').
        declared: bool,
    },
    /// A node whose type the registry lacks: the pins of its links.
    Unknown,
}

/// The pins of one node.
#[derive(Clone, Debug)]
pub struct Ports {
    /// Where they come from.
    pub kind: Kind,
    /// The input pins, in order.
    pub inputs: Vec<Port>,
    /// The output pins, in order.
    pub outputs: Vec<Port>,
}

impl Ports {
    /// The pins of a registered type.
    pub fn of_type(t: &Arc<NodeType>) -> Ports {
        Ports {
            kind: Kind::Type(t.clone()),
            inputs: t.inputs().iter().map(Port::input).collect(),
            outputs: t.outputs().iter().map(Port::output).collect(),
        }
    }

    /// The index of input `name`.
    pub fn input_index(&self, name: &str) -> Option<usize> {
        self.inputs.iter().position(|p| p.name == name)
    }

    /// The index of output `name`.
    pub fn output_index(&self, name: &str) -> Option<usize> {
        self.outputs.iter().position(|p| p.name == name)
    }

    /// The registered type, when the node has one.
    pub fn node_type(&self) -> Option<&Arc<NodeType>> {
        match &self.kind {
            Kind::Type(t) => Some(t),
            _ => None,
        }
    }

    /// The group reference, for a group instance.
    pub fn group(&self) -> Option<&str> {
        match &self.kind {
            Kind::Group { reference, .. } => Some(reference),
            _ => None,
        }
    }

    /// The variant set a `switch` names, for a switch.
    pub fn switch(&self) -> Option<&str> {
        match &self.kind {
            Kind::Switch { variant, .. } => Some(variant),
            _ => None,
        }
    }
}

/// The pins of node `node` of `doc`: its registered type's, its group's interface, or
/// (failing those) its links'. `graph` is the validated document, when valid; `files`
/// reads the files other groups are in.
pub fn ports_of(
    doc: &GraphDocument,
    node: &NodeDocument,
    registry: &Registry,
    graph: Option<&Graph>,
    files: Option<&dyn GroupFiles>,
) -> Ports {
    if node.node_type == GROUP {
        return group_ports(doc, node, graph, files);
    }
    if node.node_type == SWITCH {
        return switch_ports(doc, node, registry, graph);
    }
    match registry.get(&node.node_type) {
        Some(t) => Ports::of_type(t),
        None => link_ports(doc, node, Kind::Unknown),
    }
}

/// A group's interface as written: a declared group, or a whole graph file.
enum Interface {
    Declared(GroupDocument),
    Whole(Arc<GraphDocument>),
}

/// The interface `reference` names from the top graph `doc`, resolved as the loader
/// resolves it (`NAME` of this file, `PATH#NAME`, `PATH` a whole file).
fn interface(
    doc: &GraphDocument,
    reference: &str,
    files: Option<&dyn GroupFiles>,
) -> Option<Interface> {
    let (path, name) = match reference.split_once('#') {
        Some((p, n)) => (Some(p), Some(n)),
        None if doc.groups.contains_key(reference) || !reference.ends_with(".json") => {
            (None, Some(reference))
        }
        None => (Some(reference), None),
    };
    let file = match path {
        None => None,
        Some(p) => {
            let files = files?;
            Some(files.load(&files.top_key(), p).ok()?.doc)
        }
    };
    let groups = file.as_deref().map_or(&doc.groups, |f| &f.groups);
    match (name, file.clone()) {
        (Some(n), _) => groups.get(n).cloned().map(Interface::Declared),
        (None, Some(f)) => Some(Interface::Whole(f)),
        (None, None) => None,
    }
}

/// The type the validated graph gives flat node `flat`'s output (an interface reroute).
fn flat_type(graph: Option<&Graph>, flat: &str) -> Option<SocketType> {
    let g = graph?;
    let k = g.node_index(flat)?;
    let n = &g.nodes()[k];
    (!n.node_type.outputs().is_empty()).then(|| n.output_type(0))
}

/// The pins of group instance `node`: its group's interface, else its links'.
fn group_ports(
    doc: &GraphDocument,
    node: &NodeDocument,
    graph: Option<&Graph>,
    files: Option<&dyn GroupFiles>,
) -> Ports {
    let reference = node.group.clone().unwrap_or_default();
    let out_type = |name: &str| flat_type(graph, &format!("{}/@out:{name}", node.id));
    match interface(doc, &reference, files) {
        Some(Interface::Declared(g)) => Ports {
            inputs: g
                .inputs
                .iter()
                .map(|i| {
                    let ty = SocketType::from_name(&i.ty);
                    let range = |r: Option<[f32; 2]>| r.map(|[min, max]| Range { min, max });
                    Port {
                        default: ty
                            .and_then(|t| Value::from_json(t, i.default.as_ref()?))
                            .or(ty.map(Value::zero))
                            .unwrap_or(Value::float(0.0)),
                        soft: range(i.soft_range),
                        hard: range(i.hard_range),
                        unit: Cow::Owned(i.unit.clone().unwrap_or_default()),
                        doc: Cow::Owned(i.doc.clone()),
                        ..Port::named(&i.name, ty)
                    }
                })
                .collect(),
            outputs: g
                .outputs
                .iter()
                .map(|o| Port::named(&o.name, out_type(&o.name)))
                .collect(),
            kind: Kind::Group {
                reference,
                doc: g.doc,
                interface: true,
            },
        },
        Some(Interface::Whole(f)) => Ports {
            inputs: f
                .parameters
                .iter()
                .map(|p| {
                    let at = f.nodes.iter().find(|n| n.id == p.node);
                    let written = at.and_then(|n| n.inputs.get("value"));
                    let ty = flat_type(graph, &format!("{}/{}", node.id, p.node))
                        .or_else(|| at?.data_type.as_deref().and_then(SocketType::from_name))
                        .or_else(|| Some(Value::infer_json(written?)?.ty()));
                    Port {
                        default: ty
                            .and_then(|t| Value::from_json(t, written?))
                            .or(ty.map(Value::zero))
                            .unwrap_or(Value::float(0.0)),
                        doc: Cow::Owned(p.doc.clone()),
                        ..Port::named(&p.name, ty)
                    }
                })
                .collect(),
            outputs: f
                .outputs
                .iter()
                .map(|o| Port::named(&o.name, out_type(&o.name)))
                .collect(),
            kind: Kind::Group {
                reference,
                doc: f.doc.clone(),
                interface: true,
            },
        },
        None => link_ports(
            doc,
            node,
            Kind::Group {
                reference,
                doc: String::new(),
                interface: false,
            },
        ),
    }
}

/// The pins node `node` of `doc` uses: an input per entry it writes, an output per name
/// other nodes (and the graph's outputs) link from, in the order they are first written.
fn link_ports(doc: &GraphDocument, node: &NodeDocument, kind: Kind) -> Ports {
    let inputs = node.inputs.keys().map(|k| Port::named(k, None)).collect();
    let mut names: Vec<&str> = Vec::new();
    let links = doc
        .nodes
        .iter()
        .flat_map(|n| n.inputs.values().filter_map(super::model::link_of))
        .chain(doc.outputs.iter().map(|o| o.from.as_str()));
    for l in links {
        if let Some((src, out)) = l.split_once('.')
            && src == node.id
            && !names.contains(&out)
        {
            names.push(out);
        }
    }
    Ports {
        kind,
        inputs,
        outputs: names.into_iter().map(|n| Port::named(n, None)).collect(),
    }
}

/// The pins of `switch` node `node`: one input per choice of its variant set (and one per
/// other input it writes, which the loader reports), and the output `result`; all of the
/// type of the first choice whose source's type is known ([`link_type`]).
fn switch_ports(
    doc: &GraphDocument,
    node: &NodeDocument,
    registry: &Registry,
    graph: Option<&Graph>,
) -> Ports {
    let variant = node.variant.clone().unwrap_or_default();
    let Some(set) = doc.variants.get(&variant) else {
        let mut ports = link_ports(
            doc,
            node,
            Kind::Switch {
                variant,
                declared: false,
            },
        );
        if ports.outputs.is_empty() {
            ports.outputs.push(Port::named(SWITCH_OUTPUT, None));
        }
        return ports;
    };
    let names: Vec<&String> = set
        .choices
        .iter()
        .chain(node.inputs.keys().filter(|k| !set.choices.contains(k)))
        .collect();
    let ty = names.iter().find_map(|c| {
        let link = super::model::link_of(node.inputs.get(c.as_str())?)?;
        link_type(doc, registry, graph, link, 0)
    });
    let doc_of = |c: &str| match set.choices.iter().any(|x| x == c) {
        true => format!("Passed on when variant '{variant}' is '{c}'."),
        false => format!("Not a choice of variant '{variant}'."),
    };
    Ports {
        inputs: names
            .iter()
            .map(|c| Port {
                doc: Cow::Owned(doc_of(c)),
                ..Port::named(c, ty)
            })
            .collect(),
        outputs: vec![Port {
            doc: Cow::Owned(format!(
                "The input of the chosen value of variant '{variant}'."
            )),
            ..Port::named(SWITCH_OUTPUT, ty)
        }],
        kind: Kind::Switch {
            variant,
            declared: true,
        },
    }
}

/// The type of the output `link` (`node_id.output`) names in `doc`: the validated graph's,
/// else (the graph has errors, as while a new switch is wired) the source's declared type
/// (its `data_type` for a generic one), through switches `depth` deep at most.
fn link_type(
    doc: &GraphDocument,
    registry: &Registry,
    graph: Option<&Graph>,
    link: &str,
    depth: usize,
) -> Option<SocketType> {
    let (src, out) = link.split_once('.')?;
    if let Some(g) = graph
        && let Some(r) = g.output_ref(link)
    {
        return Some(g.output_type(r));
    }
    let n = doc.nodes.iter().find(|n| n.id == src)?;
    match n.node_type.as_str() {
        GROUP => flat_type(graph, &format!("{src}/@out:{out}")),
        SWITCH if depth < 16 => {
            let set = doc.variants.get(n.variant.as_deref()?)?;
            set.choices.iter().find_map(|c| {
                let l = super::model::link_of(n.inputs.get(c)?)?;
                link_type(doc, registry, graph, l, depth + 1)
            })
        }
        t => {
            let t = registry.get(t)?;
            let k = t.output_index(out)?;
            match t.outputs()[k].ty {
                PortType::Fixed(ty) => Some(ty),
                PortType::Generic => n.data_type.as_deref().and_then(SocketType::from_name),
            }
        }
    }
}
