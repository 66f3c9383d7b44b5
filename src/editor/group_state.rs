//! The editor's group commands ([`EditorState`]'s): Ctrl+G groups the selection, Alt+G
//! ungroups an instance, Tab enters an instance's group and leaves it, and the interface
//! edits; each document change is one undo step of the whole document. The document
//! changes are [`super::grouping`]'s and [`super::interface`]'s; entering and leaving are
//! [`super::scope`]'s.

use super::grouping;
use super::model::EditorDoc;
use super::scope::{self, GROUP_PANEL, Level, Scope};
use super::state::EditorState;
use super::view::build_snarl;
use crate::document::GraphDocument;

impl EditorState {
    /// The whole document: what is saved, undone and previewed (inside a group, not the
    /// body the canvas edits).
    pub fn root(&self) -> &EditorDoc {
        match &self.scope {
            Some(s) => &s.root,
            None => &self.doc,
        }
    }

    /// Whether the canvas shows a group's body.
    pub fn in_group(&self) -> bool {
        self.scope.is_some()
    }

    /// The breadcrumb: the graph's name, then each group entered (its name, or its
    /// reference for a group of another file).
    pub fn breadcrumb(&self) -> Vec<String> {
        let mut crumbs = vec![match self.root().doc().name.is_empty() {
            true => "graph".to_owned(),
            false => self.root().doc().name.clone(),
        }];
        if let Some(s) = &self.scope {
            crumbs.extend(s.levels.iter().map(|l| l.reference.clone()));
        }
        crumbs
    }

    /// Inside a group of this file: writes the body back into the whole document.
    pub(crate) fn sync_root(&mut self) {
        let Some(s) = &mut self.scope else {
            return;
        };
        let Some(body) = self.doc.body().filter(|b| b.read_only.is_none()) else {
            return;
        };
        let composed = scope::compose(s.root.doc(), self.doc.doc(), &body.group);
        if &composed != s.root.doc() {
            s.root.replace(composed);
        }
    }

    /// Replaces the whole document (undo, redo): inside a group, the body is made again
    /// from it, and levels whose group or instance it no longer has are left.
    pub(crate) fn replace_root(&mut self, doc: GraphDocument) {
        match &mut self.scope {
            None => self.doc.replace(doc),
            Some(s) => {
                s.root.replace(doc);
                self.reproject();
            }
        }
    }

    /// Makes the body of the innermost level again from the whole document (after a change
    /// of it), leaving the levels that no longer exist.
    fn reproject(&mut self) {
        let Some(s) = self.scope.take() else {
            return;
        };
        let places = (self.doc.input_node(), self.doc.output_node());
        let root = s.root;
        // Walk down the levels from the top, while each instance is still there.
        let mut doc = root.clone();
        let mut kept: Vec<Level> = Vec::new();
        let mut left = false;
        for level in s.levels {
            let same = doc
                .node(&level.instance)
                .is_some_and(|n| n.group.as_deref() == Some(level.reference.as_str()));
            let entered = match same {
                true => scope::enter(&doc, root.doc(), &level.instance).ok(),
                false => None,
            };
            match entered {
                Some(next) => {
                    doc = next;
                    kept.push(level);
                }
                None => {
                    // The level above the first one gone is shown again, its selection with it.
                    self.selection = level.selection;
                    left = true;
                    break;
                }
            }
        }
        if kept.is_empty() {
            self.doc = root;
            self.scope = None;
        } else {
            if !left {
                doc.set_input_node(places.0);
                doc.set_output_node(places.1);
            }
            self.doc = doc;
            self.scope = Some(Scope { root, levels: kept });
        }
        if left {
            self.status = Some(format!(
                "left to {}: the group entered is no longer in the graph",
                self.breadcrumb().join(" › ")
            ));
        }
    }

    /// Enters the group of instance `id` (Tab): the canvas shows its nodes, with Group
    /// Input and Group Output nodes; a group of another file is shown read-only.
    pub fn enter_group(&mut self, id: &str) -> Result<(), String> {
        let root_doc = self.root().doc().clone();
        let body = match scope::enter(&self.doc, &root_doc, id) {
            Ok(b) => b,
            Err(e) => {
                self.status = Some(e.clone());
                return Err(e);
            }
        };
        let reference = self
            .doc
            .node(id)
            .and_then(|n| n.group.clone())
            .unwrap_or_default();
        let above = std::mem::replace(&mut self.doc, body);
        let level = Level {
            instance: id.to_owned(),
            reference,
            places: (above.input_node(), above.output_node()),
            above: above.read_only().map(|_| Box::new(above.clone())),
            selection: std::mem::take(&mut self.selection),
        };
        match &mut self.scope {
            Some(s) => s.levels.push(level),
            None => {
                self.scope = Some(Scope {
                    root: above,
                    levels: vec![level],
                })
            }
        }
        self.snarl = build_snarl(&self.doc);
        self.focus = Some(GROUP_PANEL.to_owned());
        self.status = Some(match self.doc.read_only() {
            Some(why) => format!(
                "entered {} ({why}); Tab leaves",
                self.breadcrumb().join(" › ")
            ),
            None => format!("entered {}; Tab leaves", self.breadcrumb().join(" › ")),
        });
        Ok(())
    }

    /// Leaves the innermost group (Tab): the canvas shows the level above, the instance
    /// focused. Whether there was one to leave.
    pub fn leave_group(&mut self) -> bool {
        let Some(depth) = self.scope.as_ref().map(|s| s.levels.len()) else {
            return false;
        };
        self.leave_to(depth - 1);
        true
    }

    /// Leaves groups until `depth` levels are entered (0: the graph's top; the breadcrumb).
    pub fn leave_to(&mut self, depth: usize) {
        let Some(mut s) = self.scope.take() else {
            return;
        };
        if depth >= s.levels.len() {
            self.scope = Some(s);
            return;
        }
        let level = s.levels[depth].clone();
        s.levels.truncate(depth);
        let mut doc = if s.levels.is_empty() {
            s.root.clone()
        } else if let Some(above) = &level.above {
            (**above).clone()
        } else {
            // The level above is a group of this file: made again from the whole document.
            let mut doc = s.root.clone();
            for l in &s.levels {
                match scope::enter(&doc, s.root.doc(), &l.instance) {
                    Ok(d) => doc = d,
                    Err(_) => break,
                }
            }
            doc
        };
        doc.set_input_node(level.places.0);
        doc.set_output_node(level.places.1);
        let outer = level.instance.clone();
        self.selection = level.selection.clone();
        match s.levels.is_empty() {
            true => {
                self.doc = doc;
                self.scope = None;
            }
            false => {
                self.doc = doc;
                self.scope = Some(s);
            }
        }
        self.snarl = build_snarl(&self.doc);
        self.focus = Some(outer);
        self.status = Some(format!("back in {}", self.breadcrumb().join(" › ")));
    }

    /// Leaves every group entered (the graph's top again).
    pub fn leave_all(&mut self) {
        if self.scope.is_some() {
            self.leave_to(0);
        }
    }

    /// Groups the nodes `ids` (Ctrl+G, [`grouping::group`]): one undo step; returns the
    /// instance's id. A refusal's reason is in the status line.
    pub fn group_selection(&mut self, ids: &[String]) -> Result<String, String> {
        let made = self.edit(None, true, |d| {
            let made = grouping::group(d, ids)?;
            apply(d, made.doc.clone())?;
            Ok(made)
        })?;
        self.focus = Some(made.instance.clone());
        self.selection.set([made.instance.clone()]);
        self.status = Some(format!(
            "grouped {} node{} into '{}' (group '{}'); Tab enters it, Alt+G ungroups",
            ids.len(),
            if ids.len() == 1 { "" } else { "s" },
            made.instance,
            made.group
        ));
        Ok(made.instance)
    }

    /// Ungroups instance `id` (Alt+G, [`grouping::ungroup`]): one undo step; returns the
    /// ids of the nodes put in its place.
    pub fn ungroup(&mut self, id: &str) -> Result<Vec<String>, String> {
        let elsewhere = self.instances_outside();
        let group = self.doc.node(id).and_then(|n| n.group.clone());
        let done = self.edit(None, true, |d| {
            let skip = d.body().map(|b| b.group.clone());
            let elsewhere = group
                .as_deref()
                .and_then(|g| {
                    elsewhere
                        .as_ref()
                        .map(|o| grouping::instances_of(o, g, skip.as_deref()))
                })
                .unwrap_or(0);
            let done = grouping::ungroup(d, id, elsewhere)?;
            apply(d, done.doc.clone())?;
            Ok(done)
        })?;
        self.focus = done.nodes.last().cloned();
        self.selection.set(done.nodes.iter().cloned());
        self.status = Some(format!(
            "ungrouped '{id}' into {} node{}{}",
            done.nodes.len(),
            if done.nodes.len() == 1 { "" } else { "s" },
            match done.removed {
                true => format!(
                    " (group '{}' removed: nothing else used it)",
                    group.unwrap_or_default()
                ),
                false => String::new(),
            }
        ));
        Ok(done.nodes)
    }

    /// Inside a group: the whole document without the body's own nodes (the top's nodes and
    /// the other groups'), where other instances of a group may be.
    fn instances_outside(&self) -> Option<GraphDocument> {
        let s = self.scope.as_ref()?;
        let group = self.doc.body()?.group.clone();
        let mut outside = s.root.doc().clone();
        outside.groups.remove(&group);
        Some(outside)
    }

    /// The group whose interface the side panel edits: inside a group, its own; else the
    /// group of this file that instance `id` uses.
    pub fn interface_group(&self, id: Option<&str>) -> Option<String> {
        match (id, self.doc.body()) {
            (None, Some(b)) => Some(b.group.clone()),
            (Some(id), _) => {
                let r = self.doc.node(id)?.group.clone()?;
                match scope::resolve(&self.doc, &r).ok()? {
                    scope::Resolved::Own(name) if self.doc.read_only().is_none() => Some(name),
                    _ => None,
                }
            }
            (None, None) => None,
        }
    }

    /// Applies an interface edit ([`super::interface`]) to the whole document, as one
    /// undo step; inside a group the body is made again from it. A refusal's reason is in
    /// the status line.
    pub fn edit_interface<R>(
        &mut self,
        f: impl FnOnce(&mut EditorDoc) -> Result<R, String>,
    ) -> Result<R, String> {
        self.edit_interface_keyed(None, f)
    }

    /// [`EditorState::edit_interface`], consecutive edits with the same `key` one step (a
    /// default or a range dragged).
    pub fn edit_interface_keyed<R>(
        &mut self,
        key: Option<&str>,
        f: impl FnOnce(&mut EditorDoc) -> Result<R, String>,
    ) -> Result<R, String> {
        if let Some(why) = self.doc.read_only() {
            let why = why.to_owned();
            self.status = Some(why.clone());
            return Err(why);
        }
        if self.scope.is_none() {
            return self.edit(key, true, f);
        }
        let r = self.with_root(|s| s.edit(key, true, f));
        if let Err(e) = &r {
            self.status = Some(e.clone());
        }
        r
    }

    /// Runs `f` on the editor as if at the graph's top (the whole document as
    /// [`EditorState::doc`]), then comes back into the groups entered, their bodies made
    /// again where `f` changed the document: the parameters panel and the variant sets work
    /// on the whole document from inside a group.
    pub fn with_root<R>(&mut self, f: impl FnOnce(&mut EditorState) -> R) -> R {
        let Some(mut s) = self.scope.take() else {
            return f(self);
        };
        std::mem::swap(&mut self.doc, &mut s.root);
        let before = self.doc.doc().clone();
        let r = f(self);
        std::mem::swap(&mut self.doc, &mut s.root);
        let changed = s.root.doc() != &before;
        self.scope = Some(s);
        if changed {
            self.reproject();
            // The canvas is the body's again (an edit rebuilt it from the whole document).
            self.snarl = build_snarl(&self.doc);
        }
        r
    }
}

/// Replaces `d`'s document by `doc`: refused when it adds an error to a document that had
/// none; a document with errors takes it as it is (grouping does not fix them).
fn apply(d: &mut EditorDoc, doc: GraphDocument) -> Result<(), String> {
    match d.errors().is_empty() {
        true => d.try_replace(doc),
        false => {
            d.replace(doc);
            Ok(())
        }
    }
}
