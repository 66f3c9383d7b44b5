//! An in-app file browser (File → Open, Ctrl+O): the recent files on top, then the current
//! folder's subfolders and the files with the wanted extensions, each graph file with its
//! name and the first sentence of its doc. Typing filters the list (or types a path),
//! Up/Down move, Enter opens a file or enters a folder, Backspace on an empty filter goes up,
//! Escape cancels; a click selects, a double-click or Open opens. It is drawn by egui, so it
//! works the same on every platform, under Xvfb and in tests, without a desktop portal or
//! GTK; [`Browser::within`] keeps it inside a folder (the texture picker's folder rules).
//! [`Browser::images`] is the texture picker's: image files with a thumbnail each
//! ([`super::thumbnails`], decoded for the rows on screen only) and the image's size.

use egui::{Key, Ui};
use std::path::{Path, PathBuf};

/// Largest file whose description is read (a bigger one is listed without it).
const DESCRIBE_MAX_BYTES: u64 = 1 << 20;

/// The side of the box a row's thumbnail is drawn in, points.
pub const THUMB_POINTS: f32 = 40.0;

/// What a row of the browser is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EntryKind {
    /// A recent file (listed first, by its whole path).
    Recent,
    /// The folder above.
    Parent,
    /// A subfolder.
    Folder,
    /// A file with a wanted extension.
    File,
}

/// One row of the browser.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    /// What it is.
    pub kind: EntryKind,
    /// Its path.
    pub path: PathBuf,
    /// What the row shows: the whole path (recent), `..`, `name/` (folder) or the name.
    pub label: String,
    /// A graph file's name and the first sentence of its doc; empty otherwise.
    pub note: String,
}

/// How the browser was closed.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// A file was chosen.
    Open(PathBuf),
    /// Closed without one.
    Cancel,
}

/// The open browser.
#[derive(Clone, Debug, PartialEq)]
pub struct Browser {
    /// The folder listed.
    dir: PathBuf,
    /// The filter typed (or a path, relative to the folder).
    pub query: String,
    /// The highlighted row of [`Browser::entries`].
    pub selected: usize,
    /// The rows of the recent files, newest first (read once, when the browser opens).
    recent: Vec<Entry>,
    /// The extensions of the files listed (lower case, no dot).
    extensions: Vec<String>,
    /// The folder navigation stays inside, if any.
    root: Option<PathBuf>,
    /// The folder's rows (parent, folders, files), read when the folder changes.
    listing: Vec<Entry>,
    /// Why the folder could not be read, if it could not.
    pub error: Option<String>,
    /// Whether the selection moved by a key this frame (its row is scrolled to).
    moved: bool,
    /// The heading.
    title: String,
    /// The button that takes the highlighted file.
    verb: String,
    /// Whether the files are images: a thumbnail and the image's size beside each, no
    /// graph description.
    images: bool,
}

impl Browser {
    /// A browser of graph files (`*.json`) in `dir`, with `recent` files on top.
    pub fn graphs(dir: &Path, recent: &[PathBuf]) -> Browser {
        Browser::new(dir, &["json"], recent)
    }

    /// The texture picker of node `node`: the images
    /// ([`super::textures::IMAGE_EXTENSIONS`]) in `dir`, each with its thumbnail and size,
    /// kept inside `root` (the graph's folder, [`Browser::within`]).
    pub fn images(dir: &Path, root: &Path, node: &str) -> Browser {
        let mut b = Browser::build(&super::textures::IMAGE_EXTENSIONS, true);
        b.title = format!("Pick an image for '{node}'");
        b.verb = "Pick".into();
        b.dir = normalise(&std::path::absolute(dir).unwrap_or_else(|_| dir.to_owned()));
        b.within(root)
    }

    /// An empty browser of files with `extensions`, not yet in a folder.
    fn build(extensions: &[&str], images: bool) -> Browser {
        Browser {
            dir: PathBuf::new(),
            query: String::new(),
            selected: 0,
            recent: Vec::new(),
            extensions: extensions.iter().map(|e| e.to_lowercase()).collect(),
            root: None,
            listing: Vec::new(),
            error: None,
            moved: false,
            title: "Open a graph".into(),
            verb: "Open".into(),
            images,
        }
    }

    /// A browser of the files with `extensions` (lower case, no dot) in `dir`, with
    /// `recent` files on top (those that exist and have one of the extensions).
    pub fn new(dir: &Path, extensions: &[&str], recent: &[PathBuf]) -> Browser {
        let mut b = Browser::build(extensions, false);
        b.recent = recent
            .iter()
            .filter(|p| b.wanted(p) && p.is_file())
            .map(|p| Entry {
                kind: EntryKind::Recent,
                path: p.clone(),
                label: p.display().to_string(),
                note: describe(p),
            })
            .collect();
        b.enter(dir);
        b
    }

    /// Keeps navigation inside `root` (and starts there unless the folder is inside it).
    pub fn within(mut self, root: &Path) -> Browser {
        let root = normalise(&std::path::absolute(root).unwrap_or_else(|_| root.to_owned()));
        self.recent.retain(|e| e.path.starts_with(&root));
        self.root = Some(root.clone());
        // Listed again with the root known: no `..` row at the root.
        let dir = match self.dir.starts_with(&root) {
            true => self.dir.clone(),
            false => root,
        };
        self.enter(&dir);
        self
    }

    /// The folder listed.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Whether `path` has one of the wanted extensions.
    fn wanted(&self, path: &Path) -> bool {
        path.extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| self.extensions.contains(&e.to_lowercase()))
    }

    /// Lists folder `dir` (made absolute); the filter and the selection start again.
    pub fn enter(&mut self, dir: &Path) {
        let dir = std::path::absolute(dir).unwrap_or_else(|_| dir.to_owned());
        self.dir = normalise(&dir);
        self.query.clear();
        self.selected = 0;
        self.error = None;
        self.listing.clear();
        let at_root = self.root.as_ref().is_some_and(|r| *r == self.dir);
        if let Some(parent) = self.dir.parent().filter(|_| !at_root) {
            self.listing.push(Entry {
                kind: EntryKind::Parent,
                path: parent.to_owned(),
                label: "..".into(),
                note: String::new(),
            });
        }
        let read = match std::fs::read_dir(&self.dir) {
            Ok(r) => r,
            Err(e) => {
                self.error = Some(format!("{}: {e}", self.dir.display()));
                return;
            }
        };
        let mut folders = Vec::new();
        let mut files = Vec::new();
        for e in read.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if name.starts_with('.') {
                continue;
            }
            let path = e.path();
            if path.is_dir() {
                folders.push((name, path));
            } else if self.wanted(&path) {
                files.push((name, path));
            }
        }
        let by_name = |a: &(String, PathBuf), b: &(String, PathBuf)| {
            a.0.to_lowercase()
                .cmp(&b.0.to_lowercase())
                .then(a.0.cmp(&b.0))
        };
        folders.sort_by(by_name);
        files.sort_by(by_name);
        self.listing
            .extend(folders.into_iter().map(|(name, path)| Entry {
                kind: EntryKind::Folder,
                label: format!("{name}/"),
                path,
                note: String::new(),
            }));
        let images = self.images;
        self.listing
            .extend(files.into_iter().map(|(name, path)| Entry {
                kind: EntryKind::File,
                note: match images {
                    true => String::new(),
                    false => describe(&path),
                },
                label: name,
                path,
            }));
    }

    /// The rows shown for the filter typed: the recent files (that exist, with a wanted
    /// extension, inside the root if any), then the folder's; each kept when its label or
    /// note holds the filter (any case). The parent stays while nothing is typed.
    pub fn entries(&self) -> Vec<Entry> {
        let q = self.query.trim().to_lowercase();
        let holds = |e: &Entry| {
            q.is_empty()
                || e.label.to_lowercase().contains(&q)
                || e.note.to_lowercase().contains(&q)
        };
        self.recent
            .iter()
            .chain(&self.listing)
            .filter(|e| match e.kind {
                EntryKind::Parent => q.is_empty(),
                _ => holds(e),
            })
            .cloned()
            .collect()
    }

    /// Activates row `e`: a file is the outcome, a folder is entered.
    fn activate(&mut self, e: &Entry) -> Option<Outcome> {
        match e.kind {
            EntryKind::File | EntryKind::Recent => Some(Outcome::Open(e.path.clone())),
            EntryKind::Folder | EntryKind::Parent => {
                self.enter(&e.path.clone());
                None
            }
        }
    }

    /// The filter read as a path (relative to the folder): a folder is entered, anything
    /// else is the outcome (a file that does not exist fails to open, with its message).
    fn open_typed(&mut self) -> Option<Outcome> {
        let typed = self.dir.join(self.query.trim());
        let typed = normalise(&typed);
        if self.root.as_ref().is_some_and(|r| !typed.starts_with(r)) {
            self.error = Some(format!(
                "{} is outside {}",
                typed.display(),
                self.root.as_ref()?.display()
            ));
            return None;
        }
        match typed.is_dir() {
            true => {
                self.enter(&typed);
                None
            }
            false => Some(Outcome::Open(typed)),
        }
    }

    /// Applies a key: Up/Down move, Enter activates the highlighted row (or the path
    /// typed, where no row matches), Backspace on an empty filter goes up, Escape cancels.
    pub fn key(&mut self, key: Key) -> Option<Outcome> {
        let entries = self.entries();
        match key {
            Key::ArrowDown if !entries.is_empty() => {
                self.selected = (self.selected + 1).min(entries.len() - 1);
                self.moved = true;
            }
            Key::ArrowUp => {
                self.selected = self.selected.saturating_sub(1);
                self.moved = true;
            }
            Key::Enter => {
                return match entries.get(self.selected) {
                    Some(e) => self.activate(e),
                    None if !self.query.trim().is_empty() => self.open_typed(),
                    None => None,
                };
            }
            Key::Backspace if self.query.is_empty() => {
                if let Some(p) = entries.iter().find(|e| e.kind == EntryKind::Parent) {
                    self.enter(&p.path.clone());
                }
            }
            Key::Escape => return Some(Outcome::Cancel),
            _ => {}
        }
        None
    }

    /// Draws the browser; returns how it was closed, if it was.
    pub fn show(&mut self, ui: &mut Ui) -> Option<Outcome> {
        ui.set_width(560.0);
        ui.set_max_width(760.0);
        ui.heading(&self.title);
        ui.horizontal(|ui| {
            ui.label("in");
            ui.monospace(self.dir.display().to_string());
        });
        let before = self.query.clone();
        let edit = ui.add(
            egui::TextEdit::singleline(&mut self.query)
                .hint_text("type to filter, or a path")
                .desired_width(f32::INFINITY)
                .id(egui::Id::new("matgraph-browser-filter")),
        );
        edit.request_focus();
        if self.query != before {
            self.selected = 0;
        }
        // Backspace reaches the filter first: on an empty one it goes up a folder.
        let keys: Vec<Key> = ui.input(|i| {
            [
                Key::ArrowDown,
                Key::ArrowUp,
                Key::Enter,
                Key::Escape,
                Key::Backspace,
            ]
            .into_iter()
            .filter(|k| i.key_pressed(*k))
            .filter(|k| *k != Key::Backspace || before.is_empty())
            .collect()
        });
        let mut outcome = None;
        for k in keys {
            outcome = outcome.or_else(|| self.key(k));
        }
        if let Some(e) = &self.error {
            ui.colored_label(egui::Color32::from_rgb(255, 120, 110), e);
        }
        let entries = self.entries();
        self.selected = self.selected.min(entries.len().saturating_sub(1));
        let mut clicked = None;
        let moved = std::mem::take(&mut self.moved);
        let thumbs = self.images.then(|| super::thumbnails::shared(ui.ctx()));
        let mut thumbs = thumbs
            .as_ref()
            .map(|t| t.lock().unwrap_or_else(|e| e.into_inner()));
        egui::ScrollArea::vertical()
            .max_height(320.0)
            .auto_shrink([false, true])
            .show(ui, |ui| {
                let mut shown_recent = false;
                for (k, e) in entries.iter().enumerate() {
                    if e.kind == EntryKind::Recent && !shown_recent {
                        ui.weak("Recent");
                        shown_recent = true;
                    }
                    if e.kind != EntryKind::Recent && shown_recent {
                        ui.separator();
                        shown_recent = false;
                    }
                    ui.horizontal(|ui| {
                        let mut note = None;
                        if let Some(thumbs) = thumbs.as_deref_mut() {
                            note = thumb_cell(ui, thumbs, e);
                        }
                        let r = ui.selectable_label(k == self.selected, &e.label);
                        if k == self.selected && moved {
                            r.scroll_to_me(None);
                        }
                        if r.clicked() {
                            self.selected = k;
                        }
                        if r.double_clicked() {
                            clicked = Some(e.clone());
                        }
                        if !e.note.is_empty() {
                            let note = egui::RichText::new(&e.note).weak();
                            ui.add(egui::Label::new(note).truncate());
                        }
                        match note {
                            Some(Ok(size)) => {
                                ui.weak(size);
                            }
                            Some(Err(why)) => {
                                let why = egui::RichText::new(why).color(ERROR_COLOR);
                                ui.add(egui::Label::new(why).truncate());
                            }
                            None => {}
                        }
                    });
                }
                if entries.is_empty() {
                    ui.weak(match (self.query.trim().is_empty(), self.images) {
                        (true, false) => "no folders or graph files here",
                        (true, true) => "no folders or images here",
                        (false, _) => "nothing matches: Enter opens the path typed",
                    });
                }
            });
        ui.horizontal(|ui| {
            if ui.button(&self.verb).clicked() {
                clicked = entries.get(self.selected).cloned();
                if clicked.is_none() && !self.query.trim().is_empty() {
                    outcome = outcome.clone().or_else(|| self.open_typed());
                }
            }
            if ui.button("Cancel").clicked() {
                outcome = Some(Outcome::Cancel);
            }
        });
        if let Some(e) = clicked {
            outcome = outcome.or_else(|| self.activate(&e));
        }
        if thumbs.as_ref().is_some_and(|t| t.pending()) {
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(30));
        }
        outcome
    }
}

/// The colour of a row's error (a file that cannot be decoded).
const ERROR_COLOR: egui::Color32 = egui::Color32::from_rgb(255, 120, 110);

/// A row's thumbnail cell ([`THUMB_POINTS`] square; empty for a folder): the image's
/// thumbnail, decoded only once the row is on screen. Returns the note beside the name:
/// the image's size, or why it cannot be read; `None` while it is decoded.
fn thumb_cell(
    ui: &mut Ui,
    thumbs: &mut super::thumbnails::Thumbnails,
    e: &Entry,
) -> Option<Result<String, String>> {
    let side = egui::vec2(THUMB_POINTS, THUMB_POINTS);
    let (rect, _) = ui.allocate_exact_size(side, egui::Sense::hover());
    if !matches!(e.kind, EntryKind::File | EntryKind::Recent) || !ui.is_rect_visible(rect) {
        return None;
    }
    match thumbs.get(&e.path) {
        super::thumbnails::Status::Pending => {
            ui.painter()
                .rect_filled(rect.shrink(4.0), 2.0, ui.visuals().faint_bg_color);
            None
        }
        super::thumbnails::Status::Failed(why) => Some(Err(why.to_owned())),
        super::thumbnails::Status::Ready(_) => {
            let (id, size, [w, h]) = thumbs.texture(ui.ctx(), &e.path)?;
            let at = egui::Rect::from_center_size(
                rect.center(),
                size * (THUMB_POINTS / size.max_elem()),
            );
            egui::Image::new((id, at.size())).paint_at(ui, at);
            Some(Ok(format!("{w}×{h}")))
        }
    }
}

/// `path` without `.` and with `..` applied to the part before it (no file system access).
fn normalise(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            std::path::Component::CurDir => {}
            std::path::Component::ParentDir => {
                out.pop();
            }
            c => out.push(c),
        }
    }
    out
}

/// A graph file's `name` and the first sentence of its `doc` ("name: doc."; the name left
/// out where it is the file's), when it reads as a graph (a JSON object with `nodes`);
/// empty otherwise.
pub fn describe(path: &Path) -> String {
    let small = std::fs::metadata(path).is_ok_and(|m| m.len() <= DESCRIBE_MAX_BYTES);
    let Some(v) = small
        .then(|| std::fs::read_to_string(path).ok())
        .flatten()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .filter(|v| v.get("nodes").is_some())
    else {
        return String::new();
    };
    let stem = path.file_stem().and_then(|s| s.to_str());
    let name = v
        .get("name")
        .and_then(|n| n.as_str())
        .filter(|n| Some(*n) != stem)
        .unwrap_or("");
    let doc = v.get("doc").and_then(|d| d.as_str()).unwrap_or("");
    let sentence = match doc.find(". ") {
        Some(k) => &doc[..=k],
        None => doc,
    };
    let sentence: String = match sentence.chars().count() > 90 {
        true => sentence.chars().take(89).chain(['…']).collect(),
        false => sentence.to_owned(),
    };
    match (name.is_empty(), sentence.is_empty()) {
        (true, _) => sentence,
        (false, true) => name.to_owned(),
        (false, false) => format!("{name}: {sentence}"),
    }
}
