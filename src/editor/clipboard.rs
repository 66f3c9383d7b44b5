//! Copy and paste of nodes as graph JSON text (Ctrl+C, Ctrl+V), through the system
//! clipboard, so that nodes go between two editor windows and into a text editor.
//!
//! The text is a graph file of the current format: `{"version": 2, "name": "clipboard",
//! "nodes": [...]}` with the copied nodes (positions included) and the links among them; a
//! link from a node not copied is left out, so that input takes its default, as it would in
//! Blender. The groups of the file a copied instance uses (`"group": "NAME"`) and the
//! variants a copied `switch` names go along. Pasting reads any graph JSON (a whole file
//! too; `name` and `version` may be left out): the nodes get fresh ids where theirs are
//! taken, keep their links to each other (renamed), drop their links to nodes not pasted,
//! and are placed with their top-left corner at the pointer.

use super::model::{EditorDoc, link_json, link_of};
use super::state::EditorState;
use crate::document::{FORMAT_VERSION, GROUPS_VERSION, GraphDocument};
use std::collections::{BTreeMap, HashMap, HashSet};

/// The `name` of the graph a copy writes.
pub const CLIPBOARD_NAME: &str = "clipboard";

/// The graph JSON of the nodes `ids` of `doc` (in the document's order) and the links among
/// them, with the groups and variants they need; `None` when no id names a node.
pub fn copy_text(doc: &GraphDocument, ids: &[String]) -> Option<String> {
    let picked: Vec<_> = doc.nodes.iter().filter(|n| ids.contains(&n.id)).collect();
    if picked.is_empty() {
        return None;
    }
    let inside: HashSet<&str> = picked.iter().map(|n| n.id.as_str()).collect();
    let nodes: Vec<_> = picked
        .iter()
        .map(|&n| {
            let mut n = n.clone();
            n.inputs.retain(|_, v| {
                link_of(v)
                    .map(|l| l.split_once('.').map_or(l, |(src, _)| src))
                    .is_none_or(|src| inside.contains(src))
            });
            n
        })
        .collect();
    // The groups of this file the nodes use, and those these groups use in turn.
    let mut groups = BTreeMap::new();
    let mut todo: Vec<&str> = nodes.iter().filter_map(|n| n.group.as_deref()).collect();
    while let Some(name) = todo.pop() {
        if let Some(g) = doc.groups.get(name)
            && !groups.contains_key(name)
        {
            groups.insert(name.to_owned(), g.clone());
            todo.extend(g.nodes.iter().filter_map(|n| n.group.as_deref()));
        }
    }
    let variants = nodes
        .iter()
        .chain(groups.values().flat_map(|g| &g.nodes))
        .filter_map(|n| n.variant.as_deref())
        .filter_map(|v| Some((v.to_owned(), doc.variants.get(v)?.clone())))
        .collect();
    let fragment = GraphDocument {
        version: FORMAT_VERSION,
        name: CLIPBOARD_NAME.to_owned(),
        doc: String::new(),
        nodes,
        outputs: Vec::new(),
        parameters: Vec::new(),
        variants,
        groups,
        frames: Vec::new(),
        scene: None,
    };
    Some(fragment.to_json_pretty())
}

/// The graph `text` holds, read as a graph file (`name` and `version` may be missing: a
/// fragment gets [`CLIPBOARD_NAME`] and the current version); the reason it is none, for
/// the status line, otherwise. Never panics.
pub fn parse(text: &str) -> Result<GraphDocument, String> {
    let mut value: serde_json::Value = serde_json::from_str(text.trim())
        .map_err(|e| format!("paste: the clipboard holds no graph JSON ({e})"))?;
    let Some(object) = value.as_object_mut().filter(|o| o.contains_key("nodes")) else {
        return Err("paste: the clipboard's JSON is not a graph (no \"nodes\" list)".into());
    };
    object
        .entry("name")
        .or_insert_with(|| CLIPBOARD_NAME.into());
    object
        .entry("version")
        .or_insert_with(|| FORMAT_VERSION.into());
    let doc = GraphDocument::parse(&value.to_string()).map_err(|errors| {
        let first = errors.first().map_or(String::new(), |e| e.to_string());
        format!("paste: the clipboard's graph does not read: {first}")
    })?;
    if doc.nodes.is_empty() {
        return Err("paste: the clipboard's graph has no nodes".into());
    }
    Ok(doc)
}

/// What a paste did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pasted {
    /// The pasted nodes' ids in the document, in the clipboard's order.
    pub ids: Vec<String>,
    /// How many pasted nodes got a new id (theirs was taken).
    pub renamed: usize,
    /// How many links to nodes not pasted were dropped.
    pub dropped: usize,
}

/// `id` with every character an id may not hold (`[A-Za-z0-9_-]`) made `_`.
fn clean_id(id: &str) -> String {
    let clean: String = id
        .chars()
        .map(
            |c| match c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                true => c,
                false => '_',
            },
        )
        .collect();
    match clean.is_empty() {
        true => "node".into(),
        false => clean,
    }
}

/// Adds the nodes of `fragment` to `d` ([`super::clipboard`]'s rules), their bounding box's
/// top-left corner at canvas position `at`; with the groups and variants of `fragment` that
/// `d` lacks (a group or variant of the same name keeps `d`'s).
pub fn paste(d: &mut EditorDoc, fragment: &GraphDocument, at: [f32; 2]) -> Pasted {
    let mut doc = d.doc().clone();
    let mut pasted = Pasted::default();
    let mut renamed: HashMap<&str, String> = HashMap::new();
    let mut taken: HashSet<String> = HashSet::new();
    for n in &fragment.nodes {
        let base = clean_id(&n.id);
        let id = std::iter::once(base.clone())
            .chain((2..).map(|k| format!("{base}_{k}")))
            .find(|c| d.fresh_id(c) == *c && !taken.contains(c))
            .expect("an unused id exists");
        pasted.renamed += usize::from(id != n.id);
        taken.insert(id.clone());
        renamed.entry(n.id.as_str()).or_insert_with(|| id.clone());
        pasted.ids.push(id);
    }
    // Nodes without a position are stacked below the first, 40 points apart.
    let places: Vec<[f32; 2]> = (fragment.nodes.iter().enumerate())
        .map(|(k, n)| n.position.unwrap_or([0.0, 40.0 * k as f32]))
        .collect();
    let min = places
        .iter()
        .fold([f32::INFINITY; 2], |m, p| [m[0].min(p[0]), m[1].min(p[1])]);
    for ((n, id), place) in fragment.nodes.iter().zip(&pasted.ids).zip(&places) {
        let mut node = n.clone();
        node.id = id.clone();
        node.position = Some([place[0] - min[0] + at[0], place[1] - min[1] + at[1]]);
        node.inputs.retain(|_, v| {
            let Some(link) = link_of(v) else {
                return true;
            };
            let to = link
                .split_once('.')
                .and_then(|(src, out)| Some(link_json(renamed.get(src)?, out)));
            match to {
                Some(to) => {
                    *v = to;
                    true
                }
                None => {
                    pasted.dropped += 1;
                    false
                }
            }
        });
        doc.nodes.push(node);
    }
    for (name, g) in &fragment.groups {
        doc.groups.entry(name.clone()).or_insert_with(|| g.clone());
    }
    for (name, v) in &fragment.variants {
        doc.variants
            .entry(name.clone())
            .or_insert_with(|| v.clone());
    }
    if doc.version < GROUPS_VERSION && doc.newer_feature().is_some() {
        doc.version = GROUPS_VERSION;
    }
    d.replace(doc);
    pasted
}

impl EditorState {
    /// Copies the selected nodes (the Material Output node left out) as graph JSON
    /// ([`copy_text`]); the text, or `None` when no node is selected (the status line says
    /// what happened).
    pub fn copy_selection(&mut self) -> Option<String> {
        let ids = self.selection.ids().to_vec();
        let text = copy_text(self.doc.doc(), &ids);
        let count = ids.iter().filter(|i| self.doc.index(i).is_some()).count();
        self.status = Some(match &text {
            Some(_) => format!("copied {count} node{}", plural(count)),
            None => "copy: no node selected".into(),
        });
        text
    }

    /// Pastes the graph JSON `text` at canvas position `at` ([`paste`]) as one undo step,
    /// and selects the pasted nodes; text that holds no graph changes nothing and says why
    /// in the status line.
    pub fn paste_text(&mut self, text: &str, at: [f32; 2]) -> Result<Vec<String>, String> {
        let fragment = match parse(text) {
            Ok(f) => f,
            Err(e) => {
                self.status = Some(e.clone());
                return Err(e);
            }
        };
        let pasted = self.edit(None, true, |d| Ok(paste(d, &fragment, at)))?;
        let n = pasted.ids.len();
        let mut status = format!("pasted {n} node{}", plural(n));
        if pasted.renamed > 0 {
            status.push_str(&format!(", {} with a new id", pasted.renamed));
        }
        if pasted.dropped > 0 {
            status.push_str(&format!(
                "; {} link{} to nodes not pasted dropped",
                pasted.dropped,
                plural(pasted.dropped)
            ));
        }
        self.status = Some(status);
        self.selection.set(pasted.ids.iter().cloned());
        self.focus = pasted.ids.last().cloned();
        Ok(pasted.ids)
    }
}

fn plural(n: usize) -> &'static str {
    match n {
        1 => "",
        _ => "s",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Registry;
    use serde_json::json;

    /// geometry → dot (a: normal, b: view), dot → fresnel_schlick.cos_theta, f0 written.
    fn doc() -> EditorDoc {
        let text = json!({
            "version": 1, "name": "g",
            "nodes": [
                { "id": "geometry", "type": "geometry", "position": [0, 0] },
                { "id": "dot", "type": "dot", "position": [250, 10],
                  "inputs": { "a": { "link": "geometry.normal" }, "b": { "link": "geometry.view" } } },
                { "id": "fresnel", "type": "fresnel_schlick", "position": [500, 30],
                  "inputs": { "cos_theta": { "link": "dot.result" }, "f0": [0.9, 0.6, 0.2] } }
            ]
        });
        EditorDoc::new(
            GraphDocument::parse(&text.to_string()).unwrap(),
            Registry::builtin(),
        )
    }

    fn ids(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn a_copy_keeps_the_inner_links_and_drops_the_others() {
        let d = doc();
        let text = copy_text(d.doc(), &ids(&["fresnel", "dot"])).unwrap();
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["version"], json!(2));
        assert_eq!(v["name"], json!("clipboard"));
        // In the document's order, with positions; dot's links from geometry are gone.
        assert_eq!(v["nodes"][0]["id"], json!("dot"));
        assert_eq!(v["nodes"][0]["position"], json!([250.0, 10.0]));
        assert_eq!(v["nodes"][0].get("inputs"), None);
        assert_eq!(
            v["nodes"][1]["inputs"],
            json!({ "cos_theta": { "link": "dot.result" }, "f0": [0.9, 0.6, 0.2] })
        );
        assert!(copy_text(d.doc(), &ids(&["@outputs", "nope"])).is_none());
    }

    #[test]
    fn a_paste_renames_clashing_ids_and_follows_the_links() {
        let mut d = doc();
        let text = copy_text(d.doc(), &ids(&["dot", "fresnel"])).unwrap();
        let pasted = paste(&mut d, &parse(&text).unwrap(), [1000.0, 500.0]);
        assert_eq!(pasted.ids, ["dot_2", "fresnel_2"]);
        assert_eq!(pasted.renamed, 2);
        assert_eq!(pasted.dropped, 0);
        let n = d.node("fresnel_2").unwrap();
        assert_eq!(d.link("fresnel_2", "cos_theta"), Some("dot_2.result"));
        assert_eq!(n.inputs["f0"], json!([0.9, 0.6, 0.2]));
        // The top-left of the pasted nodes (dot at 250, 10) goes to the pointer.
        assert_eq!(d.node("dot_2").unwrap().position, Some([1000.0, 500.0]));
        assert_eq!(n.position, Some([1250.0, 520.0]));
        // The originals are untouched.
        assert_eq!(d.link("fresnel", "cos_theta"), Some("dot.result"));
        assert_eq!(d.doc().nodes.len(), 5);
    }

    #[test]
    fn a_paste_drops_links_to_nodes_not_pasted_and_reads_fragments_and_files() {
        let mut d = doc();
        // Ids a file may not hold are made valid, and the links follow them.
        let text = json!({ "nodes": [
            { "id": "x y", "type": "dot" },
            { "id": "x y", "type": "dot", "inputs": { "a": { "link": "x y.result" } } }
        ]})
        .to_string();
        let pasted = paste(&mut d, &parse(&text).unwrap(), [0.0, 0.0]);
        assert_eq!(pasted.ids, ["x_y", "x_y_2"]);
        assert_eq!(d.link("x_y_2", "a"), Some("x_y.result"));
        // dot's link from a node that is not pasted is dropped, its literal kept.
        let text = json!({ "nodes": [
            { "id": "geometry", "type": "dot", "inputs": { "a": { "link": "elsewhere.normal" }, "b": [1, 2, 3] } },
            { "id": "z", "type": "add", "inputs": { "a": { "link": "geometry.result" } } }
        ]})
        .to_string();
        let pasted = paste(&mut d, &parse(&text).unwrap(), [0.0, 0.0]);
        assert_eq!(pasted.ids, ["geometry_2", "z"]);
        assert_eq!(pasted.dropped, 1);
        assert_eq!(d.node("geometry_2").unwrap().inputs.get("a"), None);
        assert_eq!(d.node("geometry_2").unwrap().inputs["b"], json!([1, 2, 3]));
        assert_eq!(d.link("z", "a"), Some("geometry_2.result"));
        // Without positions: stacked 40 apart from the pointer.
        assert_eq!(d.node("z").unwrap().position, Some([0.0, 40.0]));
    }

    #[test]
    fn garbage_is_refused_with_a_reason() {
        for text in [
            "",
            "hello",
            "[1, 2]",
            "{\"a\": 1}",
            "{\"nodes\": []}",
            "{\"nodes\": 3}",
        ] {
            let e = parse(text).unwrap_err();
            assert!(e.starts_with("paste: "), "{text:?}: {e}");
        }
    }
}
