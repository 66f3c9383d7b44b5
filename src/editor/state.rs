//! The editor's state and every edit it makes, free of drawing: each edit goes through
//! [`EditorState::edit`], which records the undo step, and a structural one rebuilds the
//! canvas from the document.

use super::files;
use super::model::EditorDoc;
use super::undo::History;
use super::view::{NodeView, build_snarl};
use crate::document::GraphDocument;
use crate::registry::Registry;
use egui_snarl::Snarl;
use std::path::{Path, PathBuf};

/// Seconds without an edit after which a changed document is autosaved.
pub const AUTOSAVE_AFTER: f64 = 2.0;

/// A question the editor is waiting for an answer to.
#[derive(Clone, Debug, PartialEq)]
pub enum Dialog {
    /// A recovery file from a crash differs from the file: recover it or discard it.
    Recover {
        /// The recovery file.
        path: PathBuf,
        /// Its document.
        doc: Box<GraphDocument>,
    },
    /// Unsaved changes would be lost by `then`.
    Discard {
        /// What was asked for.
        then: Pending,
    },
    /// Save under a new path (typed in).
    SaveAs {
        /// The path being typed.
        path: String,
    },
    /// Open a file: the file browser ([`super::browser`]).
    Open {
        /// The browser.
        browser: Box<super::browser::Browser>,
    },
    /// Pick a texture node's image ([`super::textures::open_picker`]).
    PickTexture {
        /// The texture node.
        node: String,
        /// The browser of images, kept inside the graph's folder.
        browser: Box<super::browser::Browser>,
    },
    /// The file changed on disk while the document has unsaved changes: reload it
    /// (dropping them) or keep the document.
    Changed {
        /// The file.
        path: PathBuf,
    },
}

/// An action that discards the document, held until the user answers [`Dialog::Discard`].
#[derive(Clone, Debug, PartialEq)]
pub enum Pending {
    /// Close the window.
    Close,
    /// Open this file.
    Open(PathBuf),
    /// Start an empty graph.
    New,
}

/// The editor: the document, its history and file, and what the UI shows.
pub struct EditorState {
    /// The document and its validation.
    pub doc: EditorDoc,
    /// Undo and redo.
    pub history: History,
    /// The file, once saved or opened.
    pub path: Option<PathBuf>,
    /// The canonical text last saved or opened (the document is dirty when it differs).
    pub saved: String,
    /// The last message for the user (a refused wire, a save).
    pub status: Option<String>,
    /// The canvas' nodes: node `k` is the document's node `k`.
    pub snarl: Snarl<NodeView>,
    /// The node shown in the side panel (the selection, or a problem clicked).
    pub focus: Option<String>,
    /// The selected nodes, by id ([`super::selection`]).
    pub selection: super::selection::Selection,
    /// The open question, if any.
    pub dialog: Option<Dialog>,
    /// The add-node search, when open.
    pub search: Option<super::search_ui::SearchState>,
    /// The code panel.
    pub code: super::code::CodeState,
    /// The preview swatch.
    pub preview: super::preview::Preview,
    /// Time (egui seconds) of the last edit not yet autosaved.
    pub unsaved_since: Option<f64>,
    /// Whether the app may close now (the user answered the discard prompt).
    pub allow_close: bool,
    /// The recent-files list, when the editor keeps one (the window does; tests give theirs).
    pub recent: Option<files::Recent>,
    /// The file's modification time when it was last opened, saved or checked.
    pub disk_time: Option<std::time::SystemTime>,
    /// Time (egui seconds) the file was last checked for changes on disk.
    pub checked_at: f64,
    /// Inside a group ([`super::scope`], Tab): the whole document and the levels entered;
    /// [`EditorState::doc`] is then the group's body.
    pub scope: Option<super::scope::Scope>,
    /// The collapsed nodes (H, [`super::collapse`]): view state, undone with the document.
    pub collapsed: super::collapse::Collapsed,
    /// The editor's settings: the keymap, the collapsed nodes of each file
    /// ([`super::settings`]; the window reads them from its file, tests keep theirs).
    pub settings: super::settings::Settings,
}

/// Seconds between checks of the file for changes on disk.
pub const DISK_POLL: f64 = 1.0;

impl EditorState {
    /// An editor on `doc`, saved at `path` (if any) as `saved`; groups of other files are
    /// read from `path`'s folder.
    pub fn new(doc: GraphDocument, path: Option<PathBuf>, registry: &'static Registry) -> Self {
        let files = path.as_deref().map(EditorDoc::files_of);
        EditorState::with_doc(EditorDoc::with_files(doc, registry, files), path)
    }

    /// An editor on `doc` (validated), saved at `path` (if any) as it is.
    fn with_doc(doc: EditorDoc, path: Option<PathBuf>) -> Self {
        let saved = doc.canonical_json();
        let snarl = build_snarl(&doc);
        let mut state = EditorState {
            doc,
            history: History::default(),
            path,
            saved,
            status: None,
            snarl,
            focus: None,
            selection: Default::default(),
            dialog: None,
            search: None,
            code: Default::default(),
            preview: super::preview::Preview::new(),
            unsaved_since: None,
            allow_close: false,
            recent: None,
            disk_time: None,
            checked_at: f64::NEG_INFINITY,
            scope: None,
            collapsed: Default::default(),
            settings: Default::default(),
        };
        state.offer_recovery();
        state
    }

    /// An editor on the graph file `path`.
    /// Nodes without a position, or overlapping, are arranged ([`super::layout`]); the
    /// arranged layout counts as the file's (the document is not dirty) until saved.
    /// Groups of other files are read from the file's folder, as `matgraph check` reads
    /// them.
    pub fn open(path: &Path, registry: &'static Registry) -> Result<Self, String> {
        let group_files = EditorDoc::files_of(path);
        let doc = EditorDoc::with_files(files::open(path)?, registry, Some(group_files.clone()));
        let arrange = super::layout::needs_arranging(doc.doc(), doc.node_sizes());
        let doc = match arrange {
            true => EditorDoc::with_files(
                super::layout::arranged(doc.doc(), doc.node_sizes()),
                registry,
                Some(group_files),
            ),
            false => doc,
        };
        let mut s = EditorState::with_doc(doc, Some(path.to_owned()));
        s.disk_time = files::modified(path);
        if arrange {
            s.status = Some(format!(
                "{}: nodes without positions or overlapping were arranged (saving keeps the layout)",
                path.display()
            ));
        }
        Ok(s)
    }

    /// Arranges every node ([`super::layout::arranged`]) as one undoable edit, with room
    /// for the preview swatches that are on.
    pub fn arrange(&mut self) {
        let on: Vec<String> = self.preview.nodes_on().map(str::to_owned).collect();
        let _ = self.edit(None, true, |d| {
            let mut size = d.node_sizes().to_vec();
            for (s, n) in size.iter_mut().zip(&d.doc().nodes) {
                if on.contains(&n.id) {
                    s.1 += super::viewer::NODE_SWATCH_POINTS + 8.0;
                }
            }
            let arranged = super::layout::arranged(d.doc(), &size);
            d.replace(arranged);
            Ok(())
        });
        // The Material Output node goes right of the arranged nodes again.
        if self.doc.output_node().is_some() {
            self.doc.set_output_node(None);
            let places: Vec<[f32; 2]> = self
                .doc
                .doc()
                .nodes
                .iter()
                .map(|n| n.position.unwrap_or_default())
                .collect();
            let place = super::outputs::default_place(&self.doc, &places);
            self.doc.set_output_node(Some(place));
            self.snarl = build_snarl(&self.doc);
        }
    }

    /// Shows the Material Output node at canvas position `pos` ([`super::outputs`]); when
    /// it is already on the canvas (one per graph) it is focused instead, where it is. Not
    /// an undo step: the node is the editor's picture of the graph's `outputs`.
    pub fn add_output_node(&mut self, pos: [f32; 2]) -> String {
        use super::outputs::OUTPUT_NODE;
        if self.doc.shows_output_node() {
            self.status = Some("the graph has one Material Output node: focused it".into());
        } else {
            self.doc.set_output_node(Some(pos));
            self.snarl = build_snarl(&self.doc);
            self.status = Some("added the Material Output node".into());
        }
        self.focus = Some(OUTPUT_NODE.to_owned());
        OUTPUT_NODE.to_owned()
    }

    /// Adds the graph output `name` (a new, unconnected pin of the Material Output node,
    /// which is shown if it was not).
    pub fn add_output(&mut self, name: &str) -> Result<(), String> {
        self.edit(None, true, |d| d.add_output(name))?;
        self.status = Some(format!("added output '{name}' (unconnected)"));
        Ok(())
    }

    /// Renames the graph output `old` to `new`, keeping its wire.
    pub fn rename_output(&mut self, old: &str, new: &str) -> Result<(), String> {
        self.edit(None, true, |d| d.rename_output(old, new))?;
        self.status = Some(format!("renamed output '{old}' to '{new}'"));
        Ok(())
    }

    /// Removes the graph output `name` (its pin).
    pub fn remove_output(&mut self, name: &str) {
        let _ = self.edit(None, true, |d| {
            d.remove_output(name);
            Ok(())
        });
        self.status = Some(format!("removed output '{name}'"));
    }

    /// Exposes `node.input` as a parameter ([`super::params::expose`]): one undo step.
    /// Returns the parameter's name.
    pub fn expose_input(
        &mut self,
        node: &str,
        input: &str,
        name: Option<&str>,
    ) -> Result<String, String> {
        let name = self.edit(None, true, |d| super::params::expose(d, node, input, name))?;
        self.status = Some(format!("exposed {node}.{input} as parameter '{name}'"));
        Ok(name)
    }

    /// Adds a new, unlinked parameter of type `ty` ([`super::params::add`]).
    pub fn add_parameter(
        &mut self,
        ty: crate::types::SocketType,
        name: Option<&str>,
    ) -> Result<String, String> {
        let name = self.edit(None, true, |d| super::params::add(d, ty, name))?;
        self.status = Some(format!("added parameter '{name}' ({ty})"));
        Ok(name)
    }

    /// Lists the `parameter` node `id` in the graph's parameters.
    pub fn list_parameter_node(&mut self, id: &str) -> Result<String, String> {
        let name = self.edit(None, true, |d| super::params::list_node(d, id))?;
        self.status = Some(format!("exposed '{id}' as parameter '{name}'"));
        Ok(name)
    }

    /// Renames parameter `old` to `new` (refused, with the reason in the status line, for a
    /// name the loader refuses).
    pub fn rename_parameter(&mut self, old: &str, new: &str) -> Result<(), String> {
        self.edit(None, false, |d| super::params::rename(d, old, new))?;
        self.status = Some(format!("renamed parameter '{old}' to '{new}'"));
        Ok(())
    }

    /// Sets parameter `name`'s doc.
    pub fn set_parameter_doc(&mut self, name: &str, doc: &str) -> Result<(), String> {
        self.edit(None, false, |d| super::params::set_doc(d, name, doc))
    }

    /// Sets parameter `name`'s group (`""`: none).
    pub fn set_parameter_group(&mut self, name: &str, group: &str) -> Result<(), String> {
        self.edit(None, false, |d| super::params::set_group(d, name, group))
    }

    /// Moves parameter `name` one place up or down.
    pub fn move_parameter(&mut self, name: &str, up: bool) -> Result<(), String> {
        self.edit(None, false, |d| super::params::move_by_one(d, name, up))
    }

    /// Un-exposes parameter `name`, keeping its value on the inputs it fed
    /// ([`super::params::unexpose`]): one undo step.
    pub fn unexpose_parameter(&mut self, name: &str) -> Result<(), String> {
        let fed = self.edit(None, true, |d| super::params::unexpose(d, name))?;
        self.status = Some(match fed.is_empty() {
            true => format!("removed parameter '{name}'"),
            false => format!(
                "un-exposed '{name}': its value is written on {}",
                fed.join(", ")
            ),
        });
        Ok(())
    }

    /// Shows node `id`'s output in the main preview ("Preview this output",
    /// Ctrl+Shift+click), or (`None`) the graph's outputs again; the file is unchanged.
    pub fn preview_output(&mut self, id: Option<&str>) {
        self.preview.preview_output(id);
        self.status = Some(match id {
            Some(id) => format!("the preview shows '{id}' (the file is unchanged)"),
            None => "the preview shows the graph's outputs".into(),
        });
    }

    /// Moves the Material Output node (editor-only; not an undo step).
    pub fn move_output_node(&mut self, pos: [f32; 2]) {
        self.doc.set_output_node(Some(pos));
    }

    /// Adds `path` to the recent files (when the editor keeps the list).
    fn remember(&mut self, path: &Path) {
        if let Some(r) = &mut self.recent
            && let Err(e) = r.push(path)
        {
            self.status = Some(format!("recent files: {e}"));
        }
    }

    /// Checks the file for a change on disk (every [`DISK_POLL`] seconds of egui time
    /// `now`): reloads it when the document has no unsaved changes, else asks
    /// ([`Dialog::Changed`]). Whether it reloaded.
    pub fn check_disk(&mut self, now: f64) -> bool {
        if now - self.checked_at < DISK_POLL || self.dialog.is_some() {
            return false;
        }
        self.checked_at = now;
        let Some(path) = self.path.clone() else {
            return false;
        };
        let time = files::modified(&path);
        if time.is_none() || time == self.disk_time {
            return false;
        }
        if self.dirty() {
            self.disk_time = time;
            self.dialog = Some(Dialog::Changed { path });
            return false;
        }
        self.reload()
    }

    /// Reloads the file from disk, dropping the document's changes. Whether it did.
    pub fn reload(&mut self) -> bool {
        let Some(path) = self.path.clone() else {
            return false;
        };
        let ok = self.load(&path).is_ok();
        if ok {
            self.dialog = None;
            self.status = Some(format!("reloaded {} (changed on disk)", path.display()));
        }
        ok
    }

    /// An empty, untitled graph.
    pub fn untitled(registry: &'static Registry) -> Self {
        EditorState::new(
            EditorDoc::empty("untitled", registry).doc().clone(),
            None,
            registry,
        )
    }

    /// Whether the document differs from the file.
    pub fn dirty(&self) -> bool {
        self.root().canonical() != self.saved || self.collapsed.unsaved()
    }

    /// Applies `f` to the document as one undo step (`key`: consecutive edits with the same
    /// key coalesce, as a slider drag does). `structural` edits rebuild the canvas.
    pub fn edit<R>(
        &mut self,
        key: Option<&str>,
        structural: bool,
        f: impl FnOnce(&mut EditorDoc) -> Result<R, String>,
    ) -> Result<R, String> {
        if let Some(why) = self.doc.read_only() {
            let why = why.to_owned();
            self.status = Some(why.clone());
            return Err(why);
        }
        let before = self.root().doc().clone();
        let result = f(&mut self.doc);
        if result.is_ok() {
            // Inside a group, the body goes back into the whole document.
            self.sync_root();
        }
        match &result {
            Ok(_) if self.root().doc() != &before => {
                let collapsed = self.collapsed.keys().clone();
                let before = super::undo::Snapshot {
                    doc: before,
                    collapsed,
                };
                self.history.record(before, key);
                if structural {
                    self.snarl = build_snarl(&self.doc);
                }
                self.changed();
            }
            Ok(_) => {}
            Err(message) => self.status = Some(message.clone()),
        }
        result
    }

    /// Adds a node of `type_name` at canvas position `pos`; returns its id.
    pub fn add_node(&mut self, type_name: &str, pos: [f32; 2]) -> Result<String, String> {
        let id = self.edit(None, true, |d| d.add_node(type_name, pos))?;
        self.status = Some(format!("added '{id}'"));
        self.focus = Some(id.clone());
        // A node added is selected (only it), as in Blender.
        self.selection.set([id.clone()]);
        Ok(id)
    }

    /// Links `from.output` to `to.input`, or refuses with the loader's message (kept in
    /// [`EditorState::status`]).
    pub fn connect(
        &mut self,
        from: &str,
        output: &str,
        to: &str,
        input: &str,
    ) -> Result<(), String> {
        self.edit(None, true, |d| d.connect(from, output, to, input))
    }

    /// Removes the link or literal of `node.input`.
    pub fn clear_input(&mut self, node: &str, input: &str) {
        let _ = self.edit(None, true, |d| {
            d.clear_input(node, input);
            Ok(())
        });
    }

    /// Writes a literal on `node.input`; `key` coalesces a drag.
    pub fn set_input(
        &mut self,
        node: &str,
        input: &str,
        value: serde_json::Value,
        key: Option<&str>,
    ) {
        let _ = self.edit(key, false, |d| {
            d.set_input(node, input, value);
            Ok(())
        });
    }

    /// Writes literals on several inputs of `node` as one edit (one undo step; edits with
    /// the same `key` coalesce).
    pub fn set_inputs(
        &mut self,
        node: &str,
        values: &[(String, serde_json::Value)],
        key: Option<&str>,
    ) {
        let _ = self.edit(key, false, |d| {
            for (input, value) in values {
                d.set_input(node, input, value.clone());
            }
            Ok(())
        });
    }

    /// Removes nodes.
    pub fn remove_nodes(&mut self, ids: &[String]) {
        if ids.is_empty() {
            return;
        }
        let _ = self.edit(None, true, |d| {
            d.remove_nodes(ids);
            Ok(())
        });
        if self.focus.as_ref().is_some_and(|f| ids.contains(f)) {
            self.focus = None;
        }
    }

    /// Duplicates nodes beside themselves; returns the copies' ids.
    pub fn duplicate(&mut self, ids: &[String]) -> Vec<String> {
        if ids.is_empty() {
            return Vec::new();
        }
        self.edit(None, true, |d| Ok(d.duplicate(ids, [40.0, 40.0])))
            .unwrap_or_default()
    }

    /// Moves nodes (a drag: coalesced until [`History::seal`]).
    pub fn move_nodes(&mut self, moves: &[(String, [f32; 2])]) {
        if self.doc.read_only().is_some() {
            // A group of another file: its nodes may be looked at where they are dragged.
            return;
        }
        let _ = self.edit(Some("move"), false, |d| {
            d.set_positions(moves);
            Ok(())
        });
    }

    /// Undoes the last step.
    pub fn undo(&mut self) {
        let current = self.snapshot();
        if let Some(s) = self.history.undo(current) {
            self.replace_root(s.doc);
            self.collapsed.set_keys(s.collapsed);
            self.snarl = build_snarl(&self.doc);
            self.changed();
            self.status = Some("undone".into());
        }
    }

    /// Redoes the last undone step.
    pub fn redo(&mut self) {
        let current = self.snapshot();
        if let Some(s) = self.history.redo(current) {
            self.replace_root(s.doc);
            self.collapsed.set_keys(s.collapsed);
            self.snarl = build_snarl(&self.doc);
            self.changed();
            self.status = Some("redone".into());
        }
    }

    /// The whole document and the collapsed nodes, as an undo step keeps them.
    fn snapshot(&self) -> super::undo::Snapshot {
        super::undo::Snapshot {
            doc: self.root().doc().clone(),
            collapsed: self.collapsed.keys().clone(),
        }
    }

    /// Saves to the file (asks for a path when untitled).
    pub fn save(&mut self) -> Result<(), String> {
        match self.path.clone() {
            Some(p) => self.save_as(&p),
            None => {
                self.dialog = Some(Dialog::SaveAs {
                    path: "untitled.json".into(),
                });
                Ok(())
            }
        }
    }

    /// Saves in canonical form to `path`, atomically, and makes it the document's file
    /// (groups of other files are read from its folder from then on).
    pub fn save_as(&mut self, path: &Path) -> Result<(), String> {
        let text = self.root().canonical_json();
        let result = files::save(path, &text);
        match &result {
            Ok(()) => {
                files::discard_recovery(self.path.as_deref());
                if self.path.as_deref() != Some(path) || self.root().files().is_none() {
                    // Inside a group, the levels are left: their files are the old path's.
                    self.leave_all();
                    self.doc.set_files(Some(EditorDoc::files_of(path)));
                    self.snarl = build_snarl(&self.doc);
                }
                self.path = Some(path.to_owned());
                files::discard_recovery(Some(path));
                self.saved = text;
                self.unsaved_since = None;
                self.disk_time = files::modified(path);
                self.status = Some(format!("saved {}", path.display()));
                self.remember(path);
                self.save_collapsed(path);
            }
            Err(e) => self.status = Some(e.clone()),
        }
        result
    }

    /// Writes the recovery file now (the autosave).
    pub fn autosave(&mut self) {
        let path = files::recovery_path(self.path.as_deref());
        match files::save(&path, &self.root().canonical_json()) {
            Ok(()) => self.unsaved_since = None,
            Err(e) => self.status = Some(format!("autosave: {e}")),
        }
    }

    /// Autosaves when the last edit is [`AUTOSAVE_AFTER`] seconds old at time `now`.
    pub fn tick(&mut self, now: f64) {
        if self.unsaved_since.is_some_and(|t| t < 0.0) {
            self.unsaved_since = Some(now);
        }
        if let Some(t) = self.unsaved_since
            && now - t >= AUTOSAVE_AFTER
        {
            self.autosave();
        }
    }

    /// Takes the recovery file's document as the current one (an undoable step).
    pub fn recover(&mut self, doc: GraphDocument) {
        self.leave_all();
        let _ = self.edit(None, true, |d| {
            d.replace(doc);
            Ok(())
        });
        self.status = Some("recovered the autosaved changes".into());
    }

    /// Asks for `then`, through the discard prompt when there are unsaved changes.
    pub fn request(&mut self, then: Pending) -> Option<Pending> {
        if self.dirty() {
            self.dialog = Some(Dialog::Discard { then });
            None
        } else {
            Some(then)
        }
    }

    /// Replaces the editor with the file `path` (after the discard prompt).
    pub fn load(&mut self, path: &Path) -> Result<(), String> {
        let registry = self.doc.registry();
        match EditorState::open(path, registry) {
            Ok(s) => {
                self.replace_keeping_session(s);
                self.remember(path);
                Ok(())
            }
            Err(e) => {
                self.status = Some(e.clone());
                Err(e)
            }
        }
    }

    /// Starts an empty, untitled graph in place of this one (File → New), keeping the
    /// session as [`EditorState::load`] does.
    pub fn start_new(&mut self) {
        let s = EditorState::untitled(self.doc.registry());
        self.replace_keeping_session(s);
    }

    /// Becomes `s`, keeping the session: the preview (whether it is on, CPU only, its
    /// worker; the variant choices it shows only for the same file, reloaded), the recent
    /// files and the settings (the new file's collapsed nodes read from them).
    fn replace_keeping_session(&mut self, s: EditorState) {
        let mut preview = std::mem::take(&mut self.preview);
        if s.path.is_none() || s.path != self.path {
            preview.clear_variants();
        }
        let recent = self.recent.take();
        let settings = std::mem::take(&mut self.settings);
        *self = s;
        self.preview = preview;
        self.recent = recent;
        // The new file's collapsed nodes, as last saved.
        self.use_settings(settings);
    }

    fn changed(&mut self) {
        // Negative: set to the frame's time by the next tick.
        self.unsaved_since = Some(-1.0);
        self.code.invalidate();
    }

    fn offer_recovery(&mut self) {
        if let Some((path, doc)) =
            files::pending_recovery(self.path.as_deref(), &self.doc.canonical_json())
        {
            self.dialog = Some(Dialog::Recover {
                path,
                doc: Box::new(doc),
            });
        }
    }
}
