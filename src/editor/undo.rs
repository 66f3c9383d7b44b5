//! Undo and redo: whole-document snapshots (graphs are small), with consecutive edits that
//! share a key (one slider drag, one node move) coalesced into one step. Each step also
//! keeps the nodes collapsed then ([`super::collapse`]: view state the format has no field
//! for), so that H is undone as Blender undoes it.

use crate::document::GraphDocument;
use std::collections::BTreeSet;

/// What one undo step gives back: the document and the collapsed nodes.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    /// The whole document.
    pub doc: GraphDocument,
    /// The collapsed nodes' keys ([`super::collapse::Collapsed`]).
    pub collapsed: BTreeSet<String>,
}

impl Snapshot {
    /// A snapshot of `doc` with nothing collapsed.
    pub fn of(doc: GraphDocument) -> Snapshot {
        Snapshot {
            doc,
            collapsed: BTreeSet::new(),
        }
    }
}

/// Most steps kept; the oldest are dropped past it.
pub const MAX_STEPS: usize = 500;

/// The undo and redo stacks.
#[derive(Clone, Debug, Default)]
pub struct History {
    undo: Vec<Snapshot>,
    redo: Vec<Snapshot>,
    /// The key of the open coalescing step, if the last edit had one and it is not sealed.
    open: Option<String>,
}

impl History {
    /// Records that the document was `before` until an edit just made. An edit with the
    /// same `key` as the open step joins it (its `before` is already saved).
    pub fn record(&mut self, before: Snapshot, key: Option<&str>) {
        self.redo.clear();
        if key.is_some() && key == self.open.as_deref() {
            return;
        }
        self.open = key.map(str::to_owned);
        self.undo.push(before);
        if self.undo.len() > MAX_STEPS {
            self.undo.remove(0);
        }
    }

    /// Ends the open coalescing step (a drag was released): the next edit is a new step.
    pub fn seal(&mut self) {
        self.open = None;
    }

    /// The snapshot before the last step, given the current one (pushed for redo).
    pub fn undo(&mut self, current: Snapshot) -> Option<Snapshot> {
        self.open = None;
        let before = self.undo.pop()?;
        self.redo.push(current);
        Some(before)
    }

    /// The snapshot the last undo left, given the current one (pushed for undo).
    pub fn redo(&mut self, current: Snapshot) -> Option<Snapshot> {
        self.open = None;
        let after = self.redo.pop()?;
        self.undo.push(current);
        Some(after)
    }

    /// Whether there is a step to undo.
    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty()
    }

    /// Whether there is a step to redo.
    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// Forgets every step (a file was opened).
    pub fn clear(&mut self) {
        *self = History::default();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doc(name: &str) -> Snapshot {
        Snapshot::of(GraphDocument {
            version: 1,
            name: name.into(),
            doc: String::new(),
            nodes: Vec::new(),
            outputs: Vec::new(),
            parameters: Vec::new(),
            variants: Default::default(),
            groups: Default::default(),
            frames: Vec::new(),
            scene: None,
        })
    }

    #[test]
    fn a_drag_is_one_step_and_a_sealed_drag_is_another() {
        let mut h = History::default();
        // Drag 1: a -> b -> c, one key; sealed; drag 2: c -> d with the same key.
        h.record(doc("a"), Some("k"));
        h.record(doc("b"), Some("k"));
        h.seal();
        h.record(doc("c"), Some("k"));
        assert_eq!(h.undo(doc("d")).unwrap().doc.name, "c");
        assert_eq!(h.undo(doc("c")).unwrap().doc.name, "a");
        assert!(h.undo(doc("a")).is_none());
        assert_eq!(h.redo(doc("a")).unwrap().doc.name, "c");
        assert_eq!(h.redo(doc("c")).unwrap().doc.name, "d");
        assert!(!h.can_redo());
    }

    #[test]
    fn a_new_edit_drops_the_redo_steps() {
        let mut h = History::default();
        h.record(doc("a"), None);
        assert_eq!(h.undo(doc("b")).unwrap().doc.name, "a");
        h.record(doc("a"), None);
        assert!(!h.can_redo());
    }
}
