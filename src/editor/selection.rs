//! The canvas' selection, kept by node id (the document's ids, and the Material Output
//! node's [`super::outputs::OUTPUT_NODE`]), in the order the nodes were picked: the last is
//! the active node. egui-snarl 0.12 keeps its own selection by its `NodeId`, a slab key the
//! editor reuses for another node after a removal (so a selection kept there moved to the
//! next node after a Delete); the editor keeps egui-snarl's empty
//! ([`super::select_ui`]) and draws this one.

use egui::Modifiers;

/// How a click or a box selection changes the selection (Blender's rules).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pick {
    /// The picked nodes become the selection (a plain click or box).
    Replace,
    /// The picked nodes are added (Shift); a click on the active node deselects it, on
    /// another selected node makes it the active one.
    Extend,
    /// Each picked node is selected if it was not, deselected if it was (Ctrl+click).
    Toggle,
    /// The picked nodes are deselected (Ctrl+box).
    Subtract,
}

impl Pick {
    /// The pick of a click with `modifiers` held: plain replaces, Shift extends, Ctrl
    /// (Cmd on a Mac) toggles.
    pub fn of_click(modifiers: Modifiers) -> Pick {
        if modifiers.command {
            Pick::Toggle
        } else if modifiers.shift {
            Pick::Extend
        } else {
            Pick::Replace
        }
    }

    /// The pick of a box selection with `modifiers` held at its end: plain replaces, Shift
    /// adds, Ctrl subtracts.
    pub fn of_box(modifiers: Modifiers) -> Pick {
        if modifiers.command {
            Pick::Subtract
        } else if modifiers.shift {
            Pick::Extend
        } else {
            Pick::Replace
        }
    }
}

/// The selected nodes, by id, the active one last.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Selection {
    ids: Vec<String>,
}

impl Selection {
    /// The selected ids, in the order they were picked (the active node last).
    pub fn ids(&self) -> &[String] {
        &self.ids
    }

    /// Whether node `id` is selected.
    pub fn contains(&self, id: &str) -> bool {
        self.ids.iter().any(|i| i == id)
    }

    /// Whether nothing is selected.
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    /// The active node: the last picked.
    pub fn active(&self) -> Option<&str> {
        self.ids.last().map(String::as_str)
    }

    /// Selects exactly `ids` (duplicates dropped), the last one active.
    pub fn set<S: Into<String>>(&mut self, ids: impl IntoIterator<Item = S>) {
        self.ids.clear();
        for id in ids {
            let id = id.into();
            if !self.contains(&id) {
                self.ids.push(id);
            }
        }
    }

    /// Deselects everything.
    pub fn clear(&mut self) {
        self.ids.clear();
    }

    /// Applies a click on node `id` (`None`: on empty canvas, which deselects everything
    /// on a plain click and changes nothing otherwise).
    pub fn click(&mut self, id: Option<&str>, pick: Pick) {
        let Some(id) = id else {
            if pick == Pick::Replace {
                self.clear();
            }
            return;
        };
        match pick {
            Pick::Replace => self.set([id]),
            Pick::Extend if self.active() == Some(id) => self.remove(id),
            Pick::Extend => {
                self.remove(id);
                self.ids.push(id.to_owned());
            }
            Pick::Toggle | Pick::Subtract if self.contains(id) => self.remove(id),
            Pick::Toggle => self.ids.push(id.to_owned()),
            Pick::Subtract => {}
        }
    }

    /// Applies a box selection that caught `ids`.
    pub fn boxed(&mut self, ids: &[String], pick: Pick) {
        match pick {
            Pick::Replace => self.set(ids.iter().cloned()),
            Pick::Extend => {
                for id in ids {
                    if !self.contains(id) {
                        self.ids.push(id.clone());
                    }
                }
            }
            Pick::Toggle => {
                for id in ids {
                    self.click(Some(id), Pick::Toggle);
                }
            }
            Pick::Subtract => self.ids.retain(|i| !ids.contains(i)),
        }
    }

    /// Keeps only the ids `keep` accepts (the nodes still on the canvas).
    pub fn retain(&mut self, keep: impl Fn(&str) -> bool) {
        self.ids.retain(|i| keep(i));
    }

    fn remove(&mut self, id: &str) {
        self.ids.retain(|i| i != id);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sel(ids: &[&str]) -> Selection {
        let mut s = Selection::default();
        s.set(ids.iter().copied());
        s
    }

    #[test]
    fn a_plain_click_replaces_shift_extends_and_ctrl_toggles() {
        let mut s = sel(&["a", "b"]);
        s.click(Some("c"), Pick::Replace);
        assert_eq!(s.ids(), ["c"]);
        s.click(Some("a"), Pick::Extend);
        assert_eq!(s.ids(), ["c", "a"]);
        // Shift on a selected node that is not the active one makes it active.
        s.click(Some("c"), Pick::Extend);
        assert_eq!(s.ids(), ["a", "c"]);
        // Shift on the active node deselects it.
        s.click(Some("c"), Pick::Extend);
        assert_eq!(s.ids(), ["a"]);
        s.click(Some("b"), Pick::Toggle);
        assert_eq!(s.ids(), ["a", "b"]);
        s.click(Some("a"), Pick::Toggle);
        assert_eq!(s.ids(), ["b"]);
        // On empty canvas: a plain click deselects all, a modified one keeps the selection.
        s.click(None, Pick::Extend);
        s.click(None, Pick::Toggle);
        assert_eq!(s.ids(), ["b"]);
        s.click(None, Pick::Replace);
        assert!(s.is_empty());
    }

    #[test]
    fn a_box_replaces_adds_or_subtracts() {
        let ids = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let mut s = sel(&["a"]);
        s.boxed(&ids(&["b", "c"]), Pick::Replace);
        assert_eq!(s.ids(), ["b", "c"]);
        s.boxed(&ids(&["c", "d"]), Pick::Extend);
        assert_eq!(s.ids(), ["b", "c", "d"]);
        s.boxed(&ids(&["b", "d", "x"]), Pick::Subtract);
        assert_eq!(s.ids(), ["c"]);
        s.retain(|i| i != "c");
        assert!(s.is_empty());
    }

    #[test]
    fn modifiers_map_to_picks() {
        assert_eq!(Pick::of_click(Modifiers::NONE), Pick::Replace);
        assert_eq!(Pick::of_click(Modifiers::SHIFT), Pick::Extend);
        assert_eq!(Pick::of_click(Modifiers::COMMAND), Pick::Toggle);
        assert_eq!(Pick::of_box(Modifiers::COMMAND), Pick::Subtract);
        assert_eq!(Pick::of_box(Modifiers::SHIFT), Pick::Extend);
    }
}
