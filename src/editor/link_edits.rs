//! The edits a line drawn across wires makes ([`super::line_tool`]): cutting them (Blender's
//! Cut Links, Ctrl+right-drag) and adding reroutes on them (Blender's Add Reroute,
//! Shift+right-drag). Each is one undo step.
//!
//! Reroutes follow Blender's `add_reroute_exec` (source/blender/editors/space_node/
//! node_add.cc): the wires crossed are grouped by the output they leave, and each output
//! gets one `reroute` node, at the mean of the points where its wires were crossed, wired
//! from the output; each of those wires then leaves the reroute. A reroute whose point lies
//! in a frame joins the frame, and the new reroute is selected where there is one crossing
//! (Blender makes it the active node), nothing otherwise.

use super::model::{EditorDoc, link_json};
use super::outputs::OUTPUT_NODE;
use super::state::EditorState;
use crate::document::GraphDocument;

/// A wire a line crossed: what it links, and where it was crossed (canvas points).
#[derive(Clone, Debug, PartialEq)]
pub struct Crossed {
    /// The node it leaves (inside a group, `@in` for the Group Input node).
    pub from: String,
    /// That node's output.
    pub output: String,
    /// The node it enters ([`OUTPUT_NODE`] for the Material Output or Group Output node).
    pub to: String,
    /// That node's input (the graph output's name on the Material Output node).
    pub input: String,
    /// Where the line crossed it.
    pub at: [f32; 2],
}

/// `doc` without the links `cut` (their inputs take their defaults again; a graph output
/// cut reads nothing, as Disconnect leaves it).
pub fn without_links(doc: &GraphDocument, cut: &[Crossed]) -> GraphDocument {
    let mut out = doc.clone();
    for c in cut {
        if c.to == OUTPUT_NODE {
            if let Some(o) = out.outputs.iter_mut().find(|o| o.name == c.input) {
                o.from.clear();
            }
        } else if let Some(n) = out.nodes.iter_mut().find(|n| n.id == c.to) {
            n.inputs.remove(&c.input);
        }
    }
    out
}

/// `d`'s document with a reroute on the wires `crossed` (one per output they leave, at the
/// mean of their crossings, [module docs](self)), and the reroutes' ids in the order of the
/// outputs' first crossing.
pub fn with_reroutes(
    d: &EditorDoc,
    crossed: &[Crossed],
) -> Result<(GraphDocument, Vec<String>), String> {
    // The outputs, in the order first crossed, each with its wires.
    let mut groups: Vec<((String, String), Vec<&Crossed>)> = Vec::new();
    for c in crossed {
        let key = (c.from.clone(), c.output.clone());
        match groups.iter_mut().find(|(k, _)| *k == key) {
            Some((_, v)) => v.push(c),
            None => groups.push((key, vec![c])),
        }
    }
    let mut work = d.clone();
    let mut ids = Vec::new();
    for ((from, output), wires) in &groups {
        let n = wires.len() as f32;
        let x = wires.iter().map(|c| c.at[0]).sum::<f32>() / n;
        let y = wires.iter().map(|c| c.at[1]).sum::<f32>() / n;
        let id = work.add_node(crate::group::REROUTE, [x, y])?;
        work.set_input(&id, "input", link_json(from, output));
        // Centred on the point (a node's position is its top-left corner), by its size
        // wired.
        let k = work.index(&id).expect("the reroute was added");
        let (w, h) = work.node_sizes()[k];
        work.set_positions(&[(id.clone(), [x - w / 2.0, y - h / 2.0])]);
        ids.push((id, [x, y]));
    }
    let mut doc = work.doc().clone();
    for ((_, wires), (id, at)) in groups.iter().zip(&ids) {
        for c in wires {
            if c.to == OUTPUT_NODE {
                if let Some(o) = doc.outputs.iter_mut().find(|o| o.name == c.input) {
                    o.from = format!("{id}.output");
                }
            } else if let Some(n) = doc.nodes.iter_mut().find(|n| n.id == c.to) {
                n.inputs.insert(c.input.clone(), link_json(id, "output"));
            }
        }
        // Blender attaches the reroute to the frame drawn behind its point.
        if d.body().is_none()
            && let Some(f) = super::frames::frame_at(d, egui::pos2(at[0], at[1]))
            && let Some(frame) = doc.frames.iter_mut().find(|x| x.id == f)
        {
            frame.nodes.push(id.clone());
        }
    }
    Ok((doc, ids.into_iter().map(|(id, _)| id).collect()))
}

impl EditorState {
    /// Removes the wires `crossed` (Ctrl+right-drag): one undo step.
    pub fn cut_links(&mut self, crossed: &[Crossed]) {
        if crossed.is_empty() {
            return;
        }
        let candidate = without_links(self.doc.doc(), crossed);
        let _ = self.edit(None, true, |d| {
            d.replace(candidate);
            Ok(())
        });
        self.status = Some(format!(
            "cut {} wire{}",
            crossed.len(),
            if crossed.len() == 1 { "" } else { "s" }
        ));
    }

    /// Adds a reroute on the wires `crossed` (Shift+right-drag, [module docs](self)): one
    /// undo step; refused, with the loader's message, where a reroute cannot carry a wire's
    /// type. Returns the reroutes' ids.
    pub fn add_reroutes(&mut self, crossed: &[Crossed]) -> Result<Vec<String>, String> {
        if crossed.is_empty() {
            return Ok(Vec::new());
        }
        let (candidate, ids) = with_reroutes(&self.doc, crossed)?;
        self.edit(None, true, |d| d.try_replace(candidate))?;
        match ids.as_slice() {
            [one] if crossed.len() == 1 => self.selection.set([one.clone()]),
            _ => self.selection.clear(),
        }
        self.status = Some(format!(
            "added {} on {} wire{}",
            ids.join(", "),
            crossed.len(),
            if crossed.len() == 1 { "" } else { "s" }
        ));
        Ok(ids)
    }
}
