//! Muting nodes (M): each selected node's `muted` flag flips, one at a time, as Blender's
//! `node_mute_exec` (source/blender/editors/space_node/node_edit.cc) flips each selected
//! node's. What a muted node computes is the core's rule ([`crate::graph::Node::forwards`]):
//! each output passes on the node's first input of the output's type, else is its type's
//! zero; a `parameter` node is unaffected. `muted` is format version 2: muting in a
//! version-1 file raises its version in the same undo step.
//!
//! A muted node is drawn with a red-tinted header, a "muted" note after its title and, for
//! each output that passes an input on, a red line inside the node from that input's pin to
//! the output's (Blender's internal links, [`paint_passthrough`]).

use super::state::EditorState;
use super::wires::PinAt;
use crate::document::GraphDocument;
use egui::{Color32, Painter, Stroke};
use egui_snarl::NodeId;

/// The colour of a muted node's pass-through lines (Blender's muted wires' red).
pub const PASSTHROUGH_COLOR: Color32 = Color32::from_rgba_premultiplied(0xb0, 0x30, 0x30, 0xd0);

/// `doc` with the `muted` flag of each of the nodes `ids` flipped (ids that are not its
/// nodes, the Material Output node's, are skipped), its version raised to 2 where a node
/// is muted; with the ids muted and unmuted.
pub fn toggled(doc: &GraphDocument, ids: &[String]) -> (GraphDocument, Vec<String>, Vec<String>) {
    let mut out = doc.clone();
    let (mut muted, mut unmuted) = (Vec::new(), Vec::new());
    for n in &mut out.nodes {
        if ids.contains(&n.id) {
            n.muted = !n.muted;
            match n.muted {
                true => muted.push(n.id.clone()),
                false => unmuted.push(n.id.clone()),
            }
        }
    }
    if !muted.is_empty() && out.version < crate::document::GROUPS_VERSION {
        out.version = crate::document::GROUPS_VERSION;
    }
    (out, muted, unmuted)
}

impl EditorState {
    /// M on the nodes `ids`: each muted node unmuted and each other one muted, one undo
    /// step. Refused, with the loader's message in the status line, where muting adds an
    /// error.
    pub fn toggle_mute(&mut self, ids: &[String]) -> Result<(), String> {
        let (candidate, muted, unmuted) = toggled(self.doc.doc(), ids);
        if muted.is_empty() && unmuted.is_empty() {
            let why = "select nodes to mute them (M)".to_owned();
            self.status = Some(why.clone());
            return Err(why);
        }
        self.edit(None, true, |d| d.try_replace(candidate))?;
        let list = |v: &[String]| v.join(", ");
        self.status = Some(match (muted.is_empty(), unmuted.is_empty()) {
            (false, true) => format!("muted {}", list(&muted)),
            (true, false) => format!("unmuted {}", list(&unmuted)),
            _ => format!("muted {}; unmuted {}", list(&muted), list(&unmuted)),
        });
        Ok(())
    }
}

/// The inputs muted node `id` passes on, as `(input, output)` pin pairs: each output's
/// first input of its type ([`crate::node::NodeType::passthrough`], at the node's inferred
/// `T`); none for a node that is not muted, a `parameter` node (muting it changes nothing)
/// or a node whose type is not registered (a group instance).
pub fn passes(doc: &super::model::EditorDoc, id: &str) -> Vec<(usize, usize)> {
    let (Some(n), Some(t)) = (doc.node(id), doc.node_type(id)) else {
        return Vec::new();
    };
    if !n.muted || t.evaluation() == crate::node::Evaluation::Parameter {
        return Vec::new();
    }
    let generic = doc.generic(id).unwrap_or(crate::types::SocketType::Float);
    (0..t.outputs().len())
        .filter_map(|k| Some((t.passthrough(generic, k)?, k)))
        .collect()
}

/// Paints muted node `node`'s pass-through lines inside its frame: for each output `k`
/// that passes input `j` on (`passes`), a line from input pin `j` to output pin `k` as the
/// canvas drew them this frame (`pins`, canvas points), `width` points wide.
pub fn paint_passthrough(
    painter: &Painter,
    node: NodeId,
    passes: &[(usize, usize)],
    pins: &[PinAt],
    width: f32,
) {
    let at = |input: bool, k: usize| {
        pins.iter()
            .rev()
            .find(|p| p.node == node && p.input == input && p.index == k)
            .map(|p| p.at)
    };
    for &(j, k) in passes {
        if let (Some(a), Some(b)) = (at(true, j), at(false, k)) {
            painter.line_segment([a, b], Stroke::new(width, PASSTHROUGH_COLOR));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each node flips on its own (Blender XORs each selected node's flag); a version-1
    /// file muting a node becomes version 2; unknown ids are skipped.
    #[test]
    fn each_node_flips_and_muting_raises_the_version() {
        let doc = GraphDocument::parse(
            r#"{"version": 1, "name": "g", "nodes": [
                {"id": "a", "type": "add"}, {"id": "b", "type": "mul"}]}"#,
        )
        .unwrap();
        let ids = ["a".to_owned(), "@outputs".to_owned()];
        let (once, muted, unmuted) = toggled(&doc, &ids);
        assert_eq!((muted, unmuted), (vec!["a".to_owned()], vec![]));
        assert_eq!(once.version, 2);
        assert!(once.nodes[0].muted && !once.nodes[1].muted);
        let both = ["a".to_owned(), "b".to_owned()];
        let (twice, muted, unmuted) = toggled(&once, &both);
        assert_eq!(
            (muted, unmuted),
            (vec!["b".to_owned()], vec!["a".to_owned()])
        );
        assert!(!twice.nodes[0].muted && twice.nodes[1].muted);
    }
}
