//! Collapsed nodes (H, Blender's "Collapse", formerly "Hide"): a collapsed node shows its
//! header only, its wired pins on the header's edges and its wires still drawn to them
//! (egui-snarl's closed node; the pins that hold no wire are not drawn).
//!
//! The graph format has no field for it (a node's `position`, the other thing the canvas
//! keeps of a node, is in the file). So it is the editor's view state: kept by the editor
//! as keys (a node id at the graph's top, `GROUP/id` inside a group), undone and redone
//! with the document ([`super::undo::Snapshot`]), and saved, when the graph is saved, in the
//! editor's settings file under the graph file's path ([`super::settings`]); a graph opened
//! gets the nodes collapsed when it was last saved. A document with collapse changes not
//! saved counts as unsaved.
//!
//! H follows Blender's `node_flag_toggle_exec` (source/blender/editors/space_node/
//! node_edit.cc): where every selected node is collapsed they are expanded, else every
//! selected node is collapsed.

use super::model::EditorDoc;
use super::state::EditorState;
use super::undo::Snapshot;
use super::view::NodeView;
use egui_snarl::Snarl;
use std::collections::BTreeSet;

/// The collapsed nodes, and those of the file as last saved or opened.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Collapsed {
    now: BTreeSet<String>,
    saved: BTreeSet<String>,
}

impl Collapsed {
    /// The collapsed nodes `keys` of a file just opened (saved as they are).
    pub fn opened(keys: BTreeSet<String>) -> Collapsed {
        Collapsed {
            now: keys.clone(),
            saved: keys,
        }
    }

    /// The collapsed nodes' keys.
    pub fn keys(&self) -> &BTreeSet<String> {
        &self.now
    }

    /// Whether the node of key `key` is collapsed.
    pub fn contains(&self, key: &str) -> bool {
        self.now.contains(key)
    }

    /// Sets the collapsed nodes (undo, redo).
    pub fn set_keys(&mut self, keys: BTreeSet<String>) {
        self.now = keys;
    }

    /// Whether they differ from the file's as last saved or opened.
    pub fn unsaved(&self) -> bool {
        self.now != self.saved
    }
}

/// The key of canvas node `id` of `doc`: the id at the graph's top, `GROUP/id` inside group
/// `GROUP` (ids hold no `/`).
pub fn key(doc: &EditorDoc, id: &str) -> String {
    match doc.body() {
        None => id.to_owned(),
        Some(b) => format!("{}/{id}", b.group),
    }
}

/// The collapsed keys after H on `keys` (Blender's rule): `current` without them where all
/// of them are collapsed, else with them all.
pub fn toggled(current: &BTreeSet<String>, keys: &[String]) -> BTreeSet<String> {
    let mut out = current.clone();
    let all = keys.iter().all(|k| current.contains(k));
    for k in keys {
        match all {
            true => out.remove(k),
            false => out.insert(k.clone()),
        };
    }
    out
}

/// Opens or closes each node of `snarl` (the canvas handed to egui-snarl) as `collapsed`
/// says.
pub fn apply(snarl: &mut Snarl<NodeView>, doc: &EditorDoc, collapsed: &Collapsed) {
    let closed: Vec<(egui_snarl::NodeId, bool)> = snarl
        .node_ids()
        .map(|(n, v)| (n, !collapsed.contains(&key(doc, &v.id))))
        .collect();
    for (n, open) in closed {
        if snarl.get_node_info(n).is_some_and(|i| i.open != open) {
            snarl.open_node(n, open);
        }
    }
}

impl EditorState {
    /// Whether canvas node `id` is collapsed.
    pub fn is_collapsed(&self, id: &str) -> bool {
        self.collapsed.contains(&key(&self.doc, id))
    }

    /// H on the nodes `ids` (Blender's rule, [`toggled`]): one undo step. Whether anything
    /// changed.
    pub fn toggle_collapse(&mut self, ids: &[String]) -> bool {
        if ids.is_empty() {
            self.status = Some("select nodes to collapse them (H)".into());
            return false;
        }
        let keys: Vec<String> = ids.iter().map(|id| key(&self.doc, id)).collect();
        let now = toggled(self.collapsed.keys(), &keys);
        if &now == self.collapsed.keys() {
            return false;
        }
        let collapsing = keys.iter().any(|k| now.contains(k));
        let before = Snapshot {
            doc: self.root().doc().clone(),
            collapsed: self.collapsed.keys().clone(),
        };
        self.history.record(before, None);
        self.collapsed.set_keys(now);
        self.status = Some(format!(
            "{} {} node{}",
            if collapsing { "collapsed" } else { "expanded" },
            ids.len(),
            if ids.len() == 1 { "" } else { "s" }
        ));
        true
    }

    /// After the graph was saved to `path`: its collapsed nodes (those still in the
    /// document) are written to the settings file under it, and count as saved.
    pub(crate) fn save_collapsed(&mut self, path: &std::path::Path) {
        let root = self.root().doc();
        let exists = |k: &str| match k.split_once('/') {
            None => k == super::outputs::OUTPUT_NODE || root.nodes.iter().any(|n| n.id == k),
            // A group's nodes: kept while the group is the file's (another file's are kept).
            Some((g, id)) => root.groups.get(g).is_none_or(|g| {
                id == super::outputs::OUTPUT_NODE
                    || id == super::scope::INPUT_NODE
                    || g.nodes.iter().any(|n| n.id == id)
            }),
        };
        let kept: BTreeSet<String> = self
            .collapsed
            .keys()
            .iter()
            .filter(|k| exists(k))
            .cloned()
            .collect();
        self.collapsed = Collapsed::opened(kept.clone());
        if let Err(e) = self.settings.set_collapsed(path, &kept) {
            self.status = Some(format!("collapsed nodes not kept: {e}"));
        }
    }

    /// Takes `settings` as the editor's (the window's, read from its file) and the
    /// collapsed nodes they keep for the graph's file.
    pub fn use_settings(&mut self, settings: super::settings::Settings) {
        self.settings = settings;
        self.collapsed = match &self.path {
            Some(p) => Collapsed::opened(self.settings.collapsed_of(p)),
            None => Collapsed::default(),
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(keys: &[&str]) -> BTreeSet<String> {
        keys.iter().map(|s| s.to_string()).collect()
    }

    /// Blender's rule: a mixed or uncollapsed selection is collapsed, an all-collapsed one
    /// expanded; other nodes keep their state.
    #[test]
    fn h_collapses_unless_all_are_collapsed() {
        let ids = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        assert_eq!(
            toggled(&set(&["x"]), &ids(&["a", "b"])),
            set(&["a", "b", "x"])
        );
        assert_eq!(
            toggled(&set(&["a", "x"]), &ids(&["a", "b"])),
            set(&["a", "b", "x"])
        );
        assert_eq!(
            toggled(&set(&["a", "b", "x"]), &ids(&["a", "b"])),
            set(&["x"])
        );
    }
}
