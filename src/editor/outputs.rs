//! The "Material Output" node: the canvas' picture of the graph document's top-level
//! `outputs` (one input pin per output, named by it). It is the editor's own node, not a
//! registered type and not a [`crate::document::NodeDocument`]: its id [`OUTPUT_NODE`]
//! cannot be a node id (those are `[A-Za-z0-9_-]+`), and its place on the canvas is kept
//! in the editor only ([`super::model::EditorDoc::output_node`]), never in the file, so that
//! the saved file stays what `matgraph fmt` writes. A file with outputs shows it right of
//! its rightmost node each time it opens ([`default_place`]).
//!
//! An output not wired yet (a pin just added, a wire dragged off) is kept in the document
//! with an empty `from` (the loader reports it: "must be written node_id.output"); one
//! whose node was deleted keeps reading it (the loader reports "no node 'x'"), so that the
//! entry is never lost and undo brings the wire back. [`note`] says which, for the pin.

use super::model::EditorDoc;

/// The canvas id of the Material Output node (not a valid node id).
pub const OUTPUT_NODE: &str = "@outputs";

/// Its title on the canvas and in the search.
pub const OUTPUT_TITLE: &str = "Material Output";

/// The output names the node offers first (the render path's, `src/render/outputs.rs`).
pub const STANDARD: [&str; 4] = ["color", "emission", "alpha", "displacement"];

/// Canvas points between the rightmost node and the Material Output node placed by
/// default.
pub const GAP: f32 = 80.0;

/// Whether `name` may name an output: letters, digits, `_` and `-`, not empty.
pub fn valid_name(name: &str) -> bool {
    !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// Why output `k` of `doc` reads nothing, when it does not: "unconnected", "reads deleted
/// node 'x'", or the loader's message.
pub fn note(doc: &EditorDoc, k: usize) -> Option<String> {
    let o = doc.doc().outputs.get(k)?;
    if o.from.is_empty() {
        return Some("unconnected".into());
    }
    if let Some((node, _)) = o.from.split_once('.')
        && doc.index(node).is_none()
    {
        return Some(format!("reads deleted node '{node}'"));
    }
    doc.errors().iter().find_map(|e| match e {
        crate::GraphError::BadOutput { name, message } if name == &o.name => Some(message.clone()),
        _ => None,
    })
}

/// Where the Material Output node goes when it has no place yet: right of the rightmost
/// node (by its estimated width), level with the topmost; the origin in an empty graph.
pub fn default_place(doc: &EditorDoc, places: &[[f32; 2]]) -> [f32; 2] {
    let sizes = doc.node_sizes();
    let mut right = f32::NEG_INFINITY;
    let mut top = f32::INFINITY;
    for (k, p) in places.iter().enumerate() {
        let w = sizes.get(k).map_or(200.0, |s| s.0);
        right = right.max(p[0] + w);
        top = top.min(p[1]);
    }
    if right.is_finite() && top.is_finite() {
        [right + GAP, top]
    } else {
        [0.0, 0.0]
    }
}

/// A name for a new output: the first standard name not taken, else `output`, `output_2`, …
pub fn fresh_name(doc: &EditorDoc, base: Option<&str>) -> String {
    let taken = |n: &str| doc.doc().outputs.iter().any(|o| o.name == n);
    if let Some(b) = base.filter(|b| valid_name(b) && !taken(b)) {
        return b.to_owned();
    }
    if let Some(s) = STANDARD.iter().find(|s| !taken(s)) {
        return (*s).to_owned();
    }
    let base = base.filter(|b| valid_name(b)).unwrap_or("output");
    if !taken(base) {
        return base.to_owned();
    }
    (2..)
        .map(|k| format!("{base}_{k}"))
        .find(|n| !taken(n))
        .expect("an unused name exists")
}
