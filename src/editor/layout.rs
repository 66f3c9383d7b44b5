//! Automatic node layout: layered by link depth, left to right (sources in the first
//! column, each node one column right of its deepest input), each column ordered by the
//! mean row of the nodes feeding it (the barycentre heuristic of Sugiyama et al. 1981,
//! which reduces wire crossings) and stacked by each node's estimated size
//! ([`node_size`]). Used when a file has nodes without positions or nodes that overlap,
//! and by View → Arrange.

use super::model::link_of;
use super::ports::{Port, Ports};
use super::widgets::slider_range;
use crate::document::{GraphDocument, NodeDocument};
use crate::node::PortType;
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

/// The width of the value widget input `k` of type `t` shows on `node` (0 when linked),
/// canvas points, chosen as [`super::widgets::value_editor`] chooses it, by the port's type
/// (a generic port's `generic`, the node's inferred `T`, where known): sliders (a float with
/// a finite soft or hard range) 130, vector fields [`LANE_WIDTH`] per lane, enum combos 110, colour buttons 45, toggles 20, other numbers 50. A generic port
/// whose `T` is not known counts 50 per lane of its node's widest literal.
fn widget_width(decl: &Port, node: &NodeDocument, generic: Option<SocketType>) -> f32 {
    let written = node.inputs.get(decl.name.as_ref());
    if written.and_then(link_of).is_some() {
        return 0.0;
    }
    let ty = match (decl.ty, generic) {
        (PortType::Fixed(t), _) | (PortType::Generic, Some(t)) => t,
        (PortType::Generic, None) => return 50.0 * generic_lanes(node) as f32,
    };
    match ty {
        SocketType::Float if slider_range(decl, false).is_some() => 130.0,
        SocketType::Int if !decl.choices.is_empty() => 110.0,
        SocketType::Color => 45.0,
        SocketType::Bool => 20.0,
        SocketType::Vec2 | SocketType::Vec3 | SocketType::Vec4 => LANE_WIDTH * ty.width() as f32,
        other => 50.0 * other.width() as f32,
    }
}

/// The width of one field of a vector editor, canvas points, with the spacing after it:
/// the canvas' interact width of 44 (a number field keeps its size whatever it shows,
/// [`super::fields`]) and 8 to the next field. Before the fields were fixed, a field was as
/// wide as its text: the gerstner_waves node's vec4 rows of values like `-0.174` were drawn
/// 24 points wider than 50 a field allowed, and a value written could widen a node into its
/// neighbour.
pub const LANE_WIDTH: f32 = 44.0 + 8.0;

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
/// widest output label, and [`node_height`] (a texture node's image rows under its pins
/// added, [`super::textures_ui::rows_size`]); at least [`MIN_WIDTH`]. `generic` is the
/// node's inferred `T` where known (its generic ports' widgets follow it). Estimated from
/// the egui-snarl 0.12 nodes of the bundled graphs to within about 10 % (pbr_brdf ≈ 260
/// wide, fresnel_schlick with a vec3 literal ≈ 290), so the layout leaves room to spare.
pub fn node_size(
    node: &NodeDocument,
    registry: &Registry,
    generic: Option<SocketType>,
) -> (f32, f32) {
    match registry.get(&node.node_type) {
        Some(t) => node_size_of(node, &Ports::of_type(t), generic),
        None => (MIN_WIDTH, node_height(1, 1)),
    }
}

/// [`node_size`] of a node with pins `ports` ([`super::model::EditorDoc::ports`]: a
/// registered type's, or a group instance's interface); the header also holds what
/// [`header_notes`] adds to the title.
pub fn node_size_of(node: &NodeDocument, ports: &Ports, generic: Option<SocketType>) -> (f32, f32) {
    // The ramp-and-curve widget's nodes show their first inputs' pins (super::ramps).
    let widget = super::ramps::pinned(&node.node_type);
    let inputs = &ports.inputs[..widget.unwrap_or(ports.inputs.len()).min(ports.inputs.len())];
    let input = inputs
        .iter()
        .map(|i| 16.0 + CHAR * i.name.len() as f32 + widget_width(i, node, generic))
        .fold(0.0f32, f32::max);
    let output = ports
        .outputs
        .iter()
        .map(|o| 16.0 + CHAR * o.name.len() as f32)
        .fold(0.0f32, f32::max);
    // The notes are labels after the title, 8 points apart.
    let notes: usize = header_notes(node, ports)
        .iter()
        .map(|n| n.chars().count() + 1)
        .sum();
    let title = 8.0 * (node.id.chars().count() + notes) as f32 + 60.0;
    // A texture node's image rows under its pins (super::textures_ui).
    let (rows_w, rows_h) = super::textures_ui::rows_size(node, ports).unwrap_or((0.0, 0.0));
    let width = (input + output + 20.0)
        .max(title)
        .max(rows_w)
        .max(MIN_WIDTH);
    let (width, widget_h) = match super::ramp_ui::height(&node.node_type) {
        Some(h) => (width.max(super::ramp_ui::WIDTH + 20.0), h),
        None => (width, 0.0),
    };
    (
        width,
        node_height(inputs.len(), ports.outputs.len()) + rows_h + widget_h,
    )
}

/// What a node's header shows after its id: the group a group instance uses, as written
/// (`blend`, `lib/layers.json#blend`), the variant set a switch follows (`switch fresnel`),
/// and `muted` on a muted node (format version 2).
pub fn header_notes(node: &NodeDocument, ports: &Ports) -> Vec<String> {
    let mut notes = Vec::new();
    if let Some(r) = ports.group() {
        notes.push(r.to_owned());
    }
    if let Some(v) = ports.switch() {
        notes.push(format!("switch {v}"));
    }
    if node.muted {
        notes.push("muted".to_owned());
    }
    notes
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

/// The arranged position (top-left corner) of every node of `doc`, in node order, each
/// node taking `size[k]` (width, height), canvas points: its [`node_size`], as
/// [`super::model::EditorDoc::node_sizes`] has them, plus whatever the caller draws under
/// it (a preview swatch).
pub fn arrange(doc: &GraphDocument, size: &[(f32, f32)]) -> Vec<[f32; 2]> {
    let n = doc.nodes.len();
    let depth = depths(doc);
    let src = sources(doc);
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

/// Whether `doc` needs arranging: a node without a position, or two nodes whose
/// rectangles of `size` (their [`node_size`]s, by node) overlap.
pub fn needs_arranging(doc: &GraphDocument, size: &[(f32, f32)]) -> bool {
    if doc.nodes.iter().any(|n| n.position.is_none()) {
        return true;
    }
    let rects: Vec<[f32; 4]> = doc
        .nodes
        .iter()
        .zip(size.iter().copied())
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

/// `doc` with every node at its [`arrange`] position.
pub fn arranged(doc: &GraphDocument, size: &[(f32, f32)]) -> GraphDocument {
    let mut d = doc.clone();
    for (n, p) in d.nodes.iter_mut().zip(arrange(doc, size)) {
        n.position = Some(p);
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A vector field is as wide whatever value it shows (`super::fields`): a node's
    /// estimate does not change with its values.
    #[test]
    fn a_vector_field_is_as_wide_whatever_its_value() {
        let registry = Registry::builtin();
        let size = |a: serde_json::Value| {
            let node: NodeDocument = serde_json::from_value(serde_json::json!({
                "id": "d", "type": "dot", "inputs": { "a": a }
            }))
            .unwrap();
            node_size(&node, registry, Some(SocketType::Vec3))
        };
        let small = size(serde_json::json!([1.0, 0.25, 14.0]));
        assert_eq!(
            size(serde_json::json!([-0.173_648_2, -1000.0, 12345.678])),
            small
        );
        // "a" and "b" rows: 16 + 7 + 3 fields of 44 + 8; "result" 16 + 7·6; 20 between.
        assert_eq!(small.0, (16.0 + 7.0 + 3.0 * 52.0) + (16.0 + 42.0) + 20.0);
    }

    /// A generic node is estimated by its inferred type: `mul` with `b` a literal −1 shows
    /// three fields of "-1.00" once `T` is vec3, a slider over its soft range once `T` is
    /// float, and 50 points a lane of its literal while `T` is not known.
    #[test]
    fn a_generic_node_is_estimated_by_its_inferred_type() {
        let registry = Registry::builtin();
        let node: NodeDocument = serde_json::from_value(serde_json::json!({
            "id": "incident", "type": "mul",
            "inputs": { "a": { "link": "geo.view" }, "b": -1.0 }
        }))
        .unwrap();
        // Widest input row ("b" and its editor) + widest output ("result") + 20.
        let output = 16.0 + 7.0 * 6.0;
        let width = |editor: f32| (16.0 + 7.0 + editor) + output + 20.0;
        let vec3 = node_size(&node, registry, Some(SocketType::Vec3));
        assert_eq!(vec3.0, width(3.0 * 52.0));
        assert_eq!(vec3.0, 257.0);
        let float = node_size(&node, registry, Some(SocketType::Float));
        assert_eq!(float.0, width(130.0));
        assert_eq!(
            node_size(&node, registry, None).0,
            MIN_WIDTH.max(width(50.0))
        );
        // Two inputs, one output: the header and two input rows.
        assert_eq!(vec3.1, HEADER_HEIGHT + 2.0 * INPUT_ROW);
    }
}
