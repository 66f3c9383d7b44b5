//! The canvas' model: one snarl node per document node, wires from the document's links,
//! and the colours of categories and socket types.

use super::model::{EditorDoc, link_of};
use super::outputs::OUTPUT_NODE;
use super::scope::INPUT_NODE;
use crate::node::Category;
use crate::types::SocketType;
use egui::Color32;
use egui_snarl::{InPinId, NodeId, OutPinId, Snarl};

/// A canvas node: the id of the document node it shows.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeView {
    /// The document node's id.
    pub id: String,
}

/// Horizontal and vertical spacing of the automatic layout of nodes without a position.
pub const LAYOUT_STEP: [f32; 2] = [220.0, 140.0];

/// The canvas of `doc`: node `k` is document node `k`, at its position (nodes without one
/// laid out in columns by link depth), and one wire per link.
pub fn build_snarl(doc: &EditorDoc) -> Snarl<NodeView> {
    build_snarl_prefix(doc, usize::MAX)
}

/// Where the canvas puts each node of `doc`: at its position, or (nodes without one) in
/// columns by link depth, each at the next row of its column ([`LAYOUT_STEP`]). A node's
/// place depends on the nodes before it only.
fn places(doc: &EditorDoc) -> Vec<[f32; 2]> {
    let depth = depths(doc);
    let mut rows = std::collections::HashMap::<usize, usize>::new();
    doc.doc()
        .nodes
        .iter()
        .enumerate()
        .map(|(k, n)| {
            n.position.unwrap_or_else(|| {
                let row = rows.entry(depth[k]).or_default();
                *row += 1;
                [
                    depth[k] as f32 * LAYOUT_STEP[0],
                    (*row - 1) as f32 * LAYOUT_STEP[1],
                ]
            })
        })
        .collect()
}

/// Canvas points around a node's estimated size ([`super::layout::node_size`]) that count
/// as the node when nodes shown together are checked for overlap: room for the estimate's
/// error (its frame's shadow is added to it).
pub const REVEAL_MARGIN: f32 = 12.0;

/// How many of `doc`'s nodes the canvas shows once the first `shown` are shown: the next
/// ones, up to the first whose painted rect (its estimated size with [`REVEAL_MARGIN`], and
/// the node frame's `shadow`) overlaps that of another node shown with it, and at least one
/// more. egui-snarl 0.12 stacks the nodes
/// that appear in the same frame in `HashSet` order, which varies from run to run; nodes
/// that do not overlap look the same in any order. So a laid-out file (the editor arranges
/// one whose nodes overlap, [`super::layout::needs_arranging`]) appears in one frame, and
/// overlapping nodes one per frame in file order (later nodes on top).
pub fn reveal_until(doc: &EditorDoc, shown: usize, shadow: egui::Shadow) -> usize {
    let d = doc.doc();
    let places = places(doc);
    let rect = |k: usize| {
        let (w, h) = doc.node_sizes()[k];
        let [x, y] = places[k];
        let r = egui::Rect::from_min_size(egui::pos2(x, y), egui::vec2(w, h)).expand(REVEAL_MARGIN);
        let offset = egui::vec2(shadow.offset[0] as f32, shadow.offset[1] as f32);
        r.union(
            r.translate(offset)
                .expand((shadow.blur + shadow.spread) as f32),
        )
    };
    let mut batch: Vec<egui::Rect> = Vec::new();
    for k in shown..d.nodes.len() {
        let r = rect(k);
        if batch.iter().any(|b| b.intersects(r)) {
            return k;
        }
        batch.push(r);
    }
    d.nodes.len()
}

/// The canvas of the first `count` nodes of `doc` and the links between them (a file's
/// nodes are shown in steps, [`reveal_until`]).
pub fn build_snarl_prefix(doc: &EditorDoc, count: usize) -> Snarl<NodeView> {
    let d = doc.doc();
    let count = count.min(d.nodes.len());
    let mut snarl = Snarl::new();
    let places = places(doc);
    for (k, (n, pos)) in d
        .nodes
        .iter()
        .zip(places.iter().copied())
        .enumerate()
        .take(count)
    {
        let id = snarl.insert_node(egui::pos2(pos[0], pos[1]), NodeView { id: n.id.clone() });
        debug_assert_eq!(id, NodeId(k));
    }
    for (k, n) in d.nodes.iter().enumerate().take(count) {
        let Some(ports) = doc.ports_at(k) else {
            continue;
        };
        for (i, decl) in ports.inputs.iter().enumerate() {
            let Some((src, out)) = n
                .inputs
                .get(decl.name.as_ref())
                .and_then(link_of)
                .and_then(|l| l.split_once('.'))
            else {
                continue;
            };
            let Some(s) = doc.index(src).filter(|&s| s < count) else {
                continue;
            };
            let Some(o) = doc.ports_at(s).and_then(|p| p.output_index(out)) else {
                continue;
            };
            snarl.connect(
                OutPinId {
                    node: NodeId(s),
                    output: o,
                },
                InPinId {
                    node: NodeId(k),
                    input: i,
                },
            );
        }
    }
    // The Material Output node ([`super::outputs`]) and, inside a group, the Group Input
    // node, after the document's nodes once they are all shown.
    if count < d.nodes.len() {
        return snarl;
    }
    let out = doc.output_node_place(&places).map(|place| {
        snarl.insert_node(
            egui::pos2(place[0], place[1]),
            NodeView {
                id: OUTPUT_NODE.to_owned(),
            },
        )
    });
    // Inside a group, the Group Input node ([`super::scope`]): one output pin per
    // interface input, wired to what reads `@in.NAME`.
    let input = doc.input_node_place(&places).map(|place| {
        snarl.insert_node(
            egui::pos2(place[0], place[1]),
            NodeView {
                id: INPUT_NODE.to_owned(),
            },
        )
    });
    // The source pin a link names: a node's output, or the Group Input node's.
    let source = |link: &str| -> Option<OutPinId> {
        let (src, name) = link.split_once('.')?;
        if src == INPUT_NODE {
            let k = doc.ports(INPUT_NODE)?.output_index(name)?;
            return Some(OutPinId {
                node: input?,
                output: k,
            });
        }
        let s = doc.index(src)?;
        let k = doc.ports_at(s)?.output_index(name)?;
        Some(OutPinId {
            node: NodeId(s),
            output: k,
        })
    };
    if input.is_some() {
        for (k, n) in d.nodes.iter().enumerate() {
            let Some(ports) = doc.ports_at(k) else {
                continue;
            };
            for (i, decl) in ports.inputs.iter().enumerate() {
                let Some(link) = n.inputs.get(decl.name.as_ref()).and_then(link_of) else {
                    continue;
                };
                if link.split_once('.').is_some_and(|(s, _)| s == INPUT_NODE)
                    && let Some(from) = source(link)
                {
                    snarl.connect(
                        from,
                        InPinId {
                            node: NodeId(k),
                            input: i,
                        },
                    );
                }
            }
        }
    }
    // The Material Output node ([`super::outputs`]) after the document's nodes, once they
    // are all shown: one input pin per graph output, wired from the node output it reads.
    if let Some(out) = out {
        for (i, o) in d.outputs.iter().enumerate() {
            if let Some(from) = source(&o.from) {
                snarl.connect(
                    from,
                    InPinId {
                        node: out,
                        input: i,
                    },
                );
            }
        }
    }
    snarl
}

/// The Group Input node's id on `snarl`, when it is shown (inside a group).
pub fn input_node_id(snarl: &Snarl<NodeView>) -> Option<NodeId> {
    snarl
        .node_ids()
        .find(|(_, v)| v.id == INPUT_NODE)
        .map(|(n, _)| n)
}

/// The Material Output node's id on `snarl`, when it is shown.
pub fn output_node_id(snarl: &Snarl<NodeView>) -> Option<NodeId> {
    snarl
        .node_ids()
        .find(|(_, v)| v.id == OUTPUT_NODE)
        .map(|(n, _)| n)
}

/// Link depth of every node (0 for nodes no link reaches), for the automatic layout.
fn depths(doc: &EditorDoc) -> Vec<usize> {
    let d = doc.doc();
    let mut depth = vec![0usize; d.nodes.len()];
    // Relax at most n times: a cycle cannot loop forever.
    for _ in 0..d.nodes.len() {
        let mut changed = false;
        for (k, n) in d.nodes.iter().enumerate() {
            for v in n.inputs.values() {
                if let Some(s) = link_of(v)
                    .and_then(|l| l.split_once('.'))
                    .and_then(|(s, _)| doc.index(s))
                    && depth[k] < depth[s] + 1
                {
                    depth[k] = depth[s] + 1;
                    changed = true;
                }
            }
        }
        if !changed {
            break;
        }
    }
    depth
}

/// The header colour of a category (Blender's shader editor families where they match).
pub fn category_color(c: Category) -> Color32 {
    match c {
        Category::Input => Color32::from_rgb(0x83, 0x31, 0x4a),
        Category::Geometry => Color32::from_rgb(0x7a, 0x2e, 0x5c),
        Category::Math => Color32::from_rgb(0x24, 0x6b, 0x83),
        Category::Vector => Color32::from_rgb(0x3c, 0x3c, 0x83),
        Category::Color => Color32::from_rgb(0x6c, 0x6c, 0x1e),
        Category::Optics => Color32::from_rgb(0x1e, 0x6e, 0x4a),
        Category::Skin => Color32::from_rgb(0x9a, 0x5a, 0x3c),
        Category::Pbr => Color32::from_rgb(0x2a, 0x7a, 0x2a),
        Category::Bubble => Color32::from_rgb(0x7a, 0x4a, 0x9a),
        Category::Texture => Color32::from_rgb(0xa0, 0x5a, 0x1e),
        Category::Water => Color32::from_rgb(0x1e, 0x5a, 0xa0),
    }
}

/// The pin and wire colour of a socket type (grey floats, purple vectors, yellow colours as
/// in Blender).
pub fn socket_color(t: SocketType) -> Color32 {
    match t {
        SocketType::Float => Color32::from_rgb(0xa1, 0xa1, 0xa1),
        SocketType::Vec2 => Color32::from_rgb(0x4f, 0x9f, 0xd8),
        SocketType::Vec3 => Color32::from_rgb(0x63, 0x63, 0xc7),
        SocketType::Vec4 => Color32::from_rgb(0x9a, 0x5c, 0xd6),
        SocketType::Color => Color32::from_rgb(0xc7, 0xc7, 0x29),
        SocketType::Int => Color32::from_rgb(0x3f, 0xb8, 0x6b),
        SocketType::Bool => Color32::from_rgb(0xcc, 0xa6, 0xd6),
    }
}

/// The colour of a generic pin whose `T` is not known yet.
pub const GENERIC_UNKNOWN: Color32 = Color32::from_rgb(0x60, 0x60, 0x60);
