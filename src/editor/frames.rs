//! Frames (format version 2, the file's `frames`: an id, a label and the top-level nodes
//! each holds): Ctrl+J puts the selected nodes in a new frame (Blender's Join in New Frame),
//! Alt+P takes them out of theirs (Blender's Remove from Frame), and a frame is renamed or
//! removed, its nodes kept, from its side panel ([`super::frames_ui`]). A node is in one
//! frame at most, as a Blender node has one parent: joining moves it from its frame, and a
//! frame left without nodes goes (ours are drawn around their nodes, so an empty one would
//! not be seen). The format's frames hold top-level nodes only, so inside a group there
//! are none. Each change is one undo step; the first frame of a version-1 file raises its
//! version to 2.
//!
//! A frame is drawn behind its nodes ([`rect`]: around their rects, its label above them);
//! a click on its label strip ([`label_at`]) shows its panel.

use super::model::EditorDoc;
use super::state::EditorState;
use super::viewer::{FRAME_LABEL, FRAME_MARGIN};
use crate::document::{FrameDocument, GraphDocument};
use egui::{Pos2, Rect};

/// The side panel's focus of frame `ID`: `@frame:ID` (no node id holds `@`).
pub const FOCUS_PREFIX: &str = "@frame:";

/// The label of a new frame (Blender's frames are called "Frame").
pub const NEW_LABEL: &str = "Frame";

/// The side panel's focus of frame `id`.
pub fn focus_of(id: &str) -> String {
    format!("{FOCUS_PREFIX}{id}")
}

/// The frame a side panel focus names, if it names one.
pub fn focused(focus: &str) -> Option<&str> {
    focus.strip_prefix(FOCUS_PREFIX)
}

/// The frame holding node `id`, if any.
pub fn frame_of<'d>(doc: &'d GraphDocument, id: &str) -> Option<&'d FrameDocument> {
    doc.frames.iter().find(|f| f.nodes.iter().any(|n| n == id))
}

/// `doc` with the nodes `ids` (those of its nodes, in its order) in a new frame, out of the
/// frames they were in, and the new frame's id.
pub fn joined(doc: &GraphDocument, ids: &[String]) -> Result<(GraphDocument, String), String> {
    let nodes: Vec<String> = doc
        .nodes
        .iter()
        .filter(|n| ids.contains(&n.id))
        .map(|n| n.id.clone())
        .collect();
    if nodes.is_empty() {
        return Err("select nodes to put them in a frame (Ctrl+J)".into());
    }
    let (mut out, _) = detached(doc, &nodes);
    let id = fresh_id(&out);
    out.frames.push(FrameDocument {
        id: id.clone(),
        label: NEW_LABEL.to_owned(),
        nodes,
        color: None,
    });
    if out.version < crate::document::GROUPS_VERSION {
        out.version = crate::document::GROUPS_VERSION;
    }
    Ok((out, id))
}

/// `doc` with the nodes `ids` out of their frames (frames left empty removed), and how many
/// nodes left a frame.
pub fn detached(doc: &GraphDocument, ids: &[String]) -> (GraphDocument, usize) {
    let mut out = doc.clone();
    let mut left = 0;
    out.frames.retain_mut(|f| {
        let before = f.nodes.len();
        f.nodes.retain(|n| !ids.contains(n));
        left += before - f.nodes.len();
        before == f.nodes.len() || !f.nodes.is_empty()
    });
    (out, left)
}

/// An id no frame of `doc` has: `frame`, `frame_2`, …
fn fresh_id(doc: &GraphDocument) -> String {
    let taken = |id: &str| doc.frames.iter().any(|f| f.id == id);
    std::iter::once("frame".to_owned())
        .chain((2..).map(|k| format!("frame_{k}")))
        .find(|id| !taken(id))
        .expect("an unused frame id exists")
}

/// The rect frame `f` is drawn in, given each node's rect (by document index; `None` for one
/// not on the canvas): around them with [`FRAME_MARGIN`], its label's [`FRAME_LABEL`] above;
/// `None` when none of its nodes is on the canvas.
pub fn rect(
    doc: &EditorDoc,
    f: &FrameDocument,
    node: impl Fn(usize) -> Option<Rect>,
) -> Option<Rect> {
    let r = f
        .nodes
        .iter()
        .filter_map(|id| node(doc.index(id)?))
        .fold(Rect::NOTHING, Rect::union);
    r.is_positive().then(|| {
        r.expand(FRAME_MARGIN)
            .with_min_y(r.min.y - FRAME_MARGIN - FRAME_LABEL)
    })
}

/// Each node's rect at its document position with its estimated size (canvas points).
fn placed(doc: &EditorDoc) -> impl Fn(usize) -> Option<Rect> + '_ {
    |k| {
        let p = doc.doc().nodes.get(k)?.position?;
        let (w, h) = *doc.node_sizes().get(k)?;
        Some(Rect::from_min_size(
            egui::pos2(p[0], p[1]),
            egui::vec2(w, h),
        ))
    }
}

/// The frame drawn at canvas point `p` (the last drawn, on top, where frames overlap), by
/// its nodes' positions and estimated sizes.
pub fn frame_at(doc: &EditorDoc, p: Pos2) -> Option<String> {
    let at = placed(doc);
    doc.doc()
        .frames
        .iter()
        .rev()
        .find(|f| rect(doc, f, &at).is_some_and(|r| r.contains(p)))
        .map(|f| f.id.clone())
}

/// The frame whose label strip (the top [`FRAME_LABEL`] + 4 points of its rect) holds
/// canvas point `p`.
pub fn label_at(doc: &EditorDoc, p: Pos2) -> Option<String> {
    let at = placed(doc);
    doc.doc()
        .frames
        .iter()
        .rev()
        .find(|f| {
            rect(doc, f, &at).is_some_and(|r| r.with_max_y(r.min.y + FRAME_LABEL + 4.0).contains(p))
        })
        .map(|f| f.id.clone())
}

impl EditorState {
    /// Ctrl+J: the nodes `ids` in a new frame (shown in the side panel, to be renamed); one
    /// undo step. Returns its id.
    pub fn join_in_frame(&mut self, ids: &[String]) -> Result<String, String> {
        if self.in_group() {
            let why =
                "frames hold the graph's top-level nodes: leave the group (Tab) to frame nodes"
                    .to_owned();
            self.status = Some(why.clone());
            return Err(why);
        }
        let (candidate, id) = joined(self.doc.doc(), ids).inspect_err(|e| {
            self.status = Some(e.clone());
        })?;
        self.edit(None, false, |d| {
            d.replace(candidate);
            Ok(())
        })?;
        self.focus = Some(focus_of(&id));
        self.status = Some(format!(
            "framed {} as '{id}' (rename it in the side panel)",
            ids.join(", ")
        ));
        Ok(id)
    }

    /// Alt+P: the nodes `ids` out of their frames (a frame left empty goes); one undo step.
    pub fn remove_from_frames(&mut self, ids: &[String]) {
        let (candidate, left) = detached(self.doc.doc(), ids);
        if left == 0 {
            self.status = Some("no selected node is in a frame (Alt+P)".into());
            return;
        }
        let _ = self.edit(None, false, |d| {
            d.replace(candidate);
            Ok(())
        });
        self.status = Some(format!(
            "{left} node{} out of {} frame",
            if left == 1 { "" } else { "s" },
            if left == 1 { "its" } else { "their" }
        ));
    }

    /// Removes frame `id`, keeping its nodes where they are; one undo step.
    pub fn remove_frame(&mut self, id: &str) {
        let mut candidate = self.doc.doc().clone();
        candidate.frames.retain(|f| f.id != id);
        let _ = self.edit(None, false, |d| {
            d.replace(candidate);
            Ok(())
        });
        if self.focus.as_deref().and_then(focused) == Some(id) {
            self.focus = None;
        }
        self.status = Some(format!("removed frame '{id}' (its nodes stay)"));
    }

    /// Sets frame `id`'s label; one undo step.
    pub fn rename_frame(&mut self, id: &str, label: &str) -> Result<(), String> {
        let mut candidate = self.doc.doc().clone();
        let f = candidate
            .frames
            .iter_mut()
            .find(|f| f.id == id)
            .ok_or_else(|| format!("no frame '{id}'"))?;
        f.label = label.to_owned();
        self.edit(None, false, |d| {
            d.replace(candidate);
            Ok(())
        })?;
        self.status = Some(format!("frame '{id}' is labelled '{label}'"));
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doc() -> GraphDocument {
        GraphDocument::parse(
            r#"{"version": 1, "name": "g", "nodes": [
                {"id": "a", "type": "add"}, {"id": "b", "type": "mul"}, {"id": "c", "type": "add"}]}"#,
        )
        .unwrap()
    }

    /// Joining frames the nodes in document order, moves a node out of its old frame (which
    /// goes once empty), gives fresh ids and raises the version.
    #[test]
    fn joining_moves_nodes_and_removes_empty_frames() {
        let ids = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let (one, f1) = joined(&doc(), &ids(&["b", "a", "zz"])).unwrap();
        assert_eq!(f1, "frame");
        assert_eq!(one.version, 2);
        assert_eq!(one.frames[0].nodes, ["a", "b"]);
        assert_eq!(one.frames[0].label, "Frame");
        let (two, f2) = joined(&one, &ids(&["b", "c"])).unwrap();
        assert_eq!(f2, "frame_2");
        assert_eq!(two.frames.len(), 2);
        assert_eq!(two.frames[0].nodes, ["a"]);
        assert_eq!(two.frames[1].nodes, ["b", "c"]);
        let (three, _) = joined(&two, &ids(&["a"])).unwrap();
        assert_eq!(
            three
                .frames
                .iter()
                .map(|f| f.id.as_str())
                .collect::<Vec<_>>(),
            ["frame_2", "frame"],
            "the old frame, left empty, went; the id is free again"
        );
        let (out, left) = detached(&three, &ids(&["b", "c", "a"]));
        assert_eq!(left, 3);
        assert!(out.frames.is_empty());
        assert!(joined(&doc(), &ids(&["zz"])).is_err());
    }
}
