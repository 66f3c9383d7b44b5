//! Automatic node layout: layered by link depth, left to right (sources in the first
//! column, each node one column right of its deepest input), each column ordered by the
//! mean row of the nodes feeding it (the barycentre heuristic of Sugiyama et al. 1981,
//! which reduces wire crossings) and stacked by each node's estimated size
//! ([`node_size`]). Used when a file has nodes without positions or nodes that overlap,
//! and by View → Arrange.

use super::model::link_of;
use crate::document::{GraphDocument, NodeDocument};
use crate::node::{InputDecl, PortType};
use crate::registry::Registry;
use crate::types::SocketType;
use std::collections::HashMap;

/// Horizontal gap between columns, canvas points (room for the wires).
pub const COLUMN_GAP: f32 = 60.0;

/// Vertical gap between nodes of a column, canvas points.
pub const ROW_GAP: f32 = 30.0;

/// The narrowest a node is drawn, canvas points.
pub const MIN_WIDTH: f32 = 160.0;

/// Points per character of a pin label or title (egui's default proportional font).
const CHAR: f32 = 7.0;

/// The estimated height of a node's header on the canvas, canvas points.
pub const HEADER_HEIGHT: f32 = 30.0;

/// The estimated height of an input row (its label and value widget), canvas points.
pub const INPUT_ROW: f32 = 22.0;

/// The estimated height of an output row (its label), canvas points.
pub const OUTPUT_ROW: f32 = 18.0;

/// The estimated height of a node with `inputs` input pins and `outputs` output pins on
/// the canvas: the header, then [`INPUT_ROW`] per input or [`OUTPUT_ROW`] per output,
/// whichever column of pins is taller (measured on egui-snarl 0.12 with the default style:
/// pbr_brdf, 7 inputs, is 163 tall; geometry, 8 outputs, 170).
pub fn node_height(inputs: usize, outputs: usize) -> f32 {
    HEADER_HEIGHT + (INPUT_ROW * inputs as f32).max(OUTPUT_ROW * outputs as f32)
}

/// The width of the value widget an unlinked input shows (0 when linked), canvas points:
/// sliders 130, vector fields 50 per lane, enum combos 110, colour buttons 45, toggles 20,
/// other numbers 50.
fn widget_width(decl: &InputDecl, node: &NodeDocument) -> f32 {
    if node.inputs.get(decl.name).and_then(link_of).is_some() {
        return 0.0;
    }
    match decl.ty {
        PortType::Generic => 50.0 * generic_lanes(node) as f32,
        PortType::Fixed(SocketType::Float)
            if decl
                .soft
                .is_some_and(|r| r.min.is_finite() && r.max.is_finite()) =>
        {
            130.0
        }
        PortType::Fixed(SocketType::Int) if !decl.choices.is_empty() => 110.0,
        PortType::Fixed(SocketType::Color) => 45.0,
        PortType::Fixed(SocketType::Bool) => 20.0,
        PortType::Fixed(t) => 50.0 * t.width() as f32,
    }
}

/// The lanes of a generic node's literals: the widest array literal among its inputs.
fn generic_lanes(node: &NodeDocument) -> usize {
    node.inputs
        .values()
        .filter_map(|v| v.as_array().map(Vec::len))
        .max()
        .unwrap_or(1)
}

/// The estimated size (width, height) of `node` on the canvas, canvas points: the title
/// (with the preview toggle), the widest input row (label and value widget) beside the
/// widest output label, and [`node_height`]; at least [`MIN_WIDTH`]. Estimated from the
/// egui-snarl 0.12 nodes of the bundled graphs to within about 10 % (pbr_brdf ≈ 260 wide,
/// fresnel_schlick with a vec3 literal ≈ 290), so the layout leaves room to spare.
pub fn node_size(node: &NodeDocument, registry: &Registry) -> (f32, f32) {
    let Some(t) = registry.get(&node.node_type) else {
        return (MIN_WIDTH, node_height(1, 1));
    };
    let input = t
        .inputs()
        .iter()
        .map(|i| 16.0 + CHAR * i.name.len() as f32 + widget_width(i, node))
        .fold(0.0f32, f32::max);
    let output = t
        .outputs()
        .iter()
        .map(|o| 16.0 + CHAR * o.name.len() as f32)
        .fold(0.0f32, f32::max);
    let title = 8.0 * node.id.chars().count() as f32 + 60.0;
    let width = (input + output + 20.0).max(title).max(MIN_WIDTH);
    (width, node_height(t.inputs().len(), t.outputs().len()))
}

fn sizes(doc: &GraphDocument, registry: &Registry) -> Vec<(f32, f32)> {
    doc.nodes.iter().map(|n| node_size(n, registry)).collect()
}

/// The indices of the nodes feeding each node (its links' sources), in input order.
fn sources(doc: &GraphDocument) -> Vec<Vec<usize>> {
    let index: HashMap<&str, usize> = doc
        .nodes
        .iter()
        .enumerate()
        .map(|(k, n)| (n.id.as_str(), k))
        .collect();
    doc.nodes
        .iter()
        .map(|n| {
            n.inputs
                .values()
                .filter_map(|v| {
                    let (src, _) = link_of(v)?.split_once('.')?;
                    index.get(src).copied()
                })
                .collect()
        })
        .collect()
}

/// The link depth of every node: 0 for nodes with no linked input, else one more than
/// its deepest source (relaxed at most n times, so a cycle cannot loop forever).
pub fn depths(doc: &GraphDocument) -> Vec<usize> {
    let src = sources(doc);
    let mut depth = vec![0usize; doc.nodes.len()];
    for _ in 0..doc.nodes.len() {
        let mut changed = false;
        for k in 0..depth.len() {
            for &s in &src[k] {
                if depth[k] < depth[s] + 1 {
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

/// The arranged position (top-left corner) of every node of `doc`, in node order.
pub fn arrange(doc: &GraphDocument, registry: &Registry) -> Vec<[f32; 2]> {
    arrange_with(doc, registry, &|_| 0.0)
}

/// [`arrange`] with `extra(id)` points added to node `id`'s height (its preview swatch).
pub fn arrange_with(
    doc: &GraphDocument,
    registry: &Registry,
    extra: &dyn Fn(&str) -> f32,
) -> Vec<[f32; 2]> {
    let n = doc.nodes.len();
    let depth = depths(doc);
    let src = sources(doc);
    let mut size = sizes(doc, registry);
    for (s, node) in size.iter_mut().zip(&doc.nodes) {
        s.1 += extra(&node.id);
    }
    let columns = depth.iter().copied().max().map_or(0, |d| d + 1);
    let mut row = vec![0.0f32; n];
    let mut pos = vec![[0.0f32; 2]; n];
    let mut x = 0.0;
    for c in 0..columns {
        let mut members: Vec<usize> = (0..n).filter(|&k| depth[k] == c).collect();
        // Barycentre of the sources' rows (file order for the first column and ties).
        let key = |k: usize| -> f32 {
            let s: Vec<f32> = src[k].iter().map(|&s| row[s]).collect();
            if s.is_empty() {
                k as f32
            } else {
                s.iter().sum::<f32>() / s.len() as f32
            }
        };
        let keys: HashMap<usize, f32> = members.iter().map(|&k| (k, key(k))).collect();
        members.sort_by(|a, b| keys[a].total_cmp(&keys[b]).then(a.cmp(b)));
        let mut y = 0.0;
        let mut widest = 0.0f32;
        for (r, &k) in members.iter().enumerate() {
            row[k] = r as f32;
            pos[k] = [x, y];
            y += size[k].1 + ROW_GAP;
            widest = widest.max(size[k].0);
        }
        x += widest + COLUMN_GAP;
    }
    pos
}

/// Whether `doc` needs arranging: a node without a position, or two nodes whose estimated
/// rectangles ([`node_size`]) overlap.
pub fn needs_arranging(doc: &GraphDocument, registry: &Registry) -> bool {
    if doc.nodes.iter().any(|n| n.position.is_none()) {
        return true;
    }
    let rects: Vec<[f32; 4]> = doc
        .nodes
        .iter()
        .zip(sizes(doc, registry))
        .filter_map(|(n, (w, h))| {
            let [x, y] = n.position?;
            Some([x, y, x + w, y + h])
        })
        .collect();
    rects.iter().enumerate().any(|(i, a)| {
        rects[i + 1..]
            .iter()
            .any(|b| a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3])
    })
}

/// `doc` with every node at its arranged position.
pub fn arranged(doc: &GraphDocument, registry: &Registry) -> GraphDocument {
    arranged_with(doc, registry, &|_| 0.0)
}

/// `doc` with every node at its [`arrange_with`] position.
pub fn arranged_with(
    doc: &GraphDocument,
    registry: &Registry,
    extra: &dyn Fn(&str) -> f32,
) -> GraphDocument {
    let mut d = doc.clone();
    for (n, p) in d.nodes.iter_mut().zip(arrange_with(doc, registry, extra)) {
        n.position = Some(p);
    }
    d
}
