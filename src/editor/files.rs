//! Files of the editor: opening, saving in canonical form (atomically, through
//! [`crate::io::write_atomic`]) and the recovery file autosaves go to.

use crate::document::GraphDocument;
use std::path::{Path, PathBuf};

/// The recovery file of a graph file: `NAME.json` → `NAME.json.autosave` beside it; for an
/// untitled graph, `matgraph-untitled.json.autosave` in the temporary folder.
pub fn recovery_path(file: Option<&Path>) -> PathBuf {
    match file {
        Some(f) => {
            let mut name = f.file_name().unwrap_or_default().to_os_string();
            name.push(".autosave");
            f.with_file_name(name)
        }
        None => std::env::temp_dir().join("matgraph-untitled.json.autosave"),
    }
}

/// Reads and parses a graph file; the message names the file.
pub fn open(path: &Path) -> Result<GraphDocument, String> {
    let text = crate::io::read_text(path).map_err(|e| e.to_string())?;
    GraphDocument::parse(&text).map_err(|errors| {
        crate::error::GraphErrors {
            source: path.to_owned(),
            errors,
        }
        .to_string()
    })
}

/// Writes `text` to `path` atomically; the message names the file.
pub fn save(path: &Path, text: &str) -> Result<(), String> {
    crate::io::write_atomic(path, text).map_err(|e| format!("{}: {e}", path.display()))
}

/// The recovery file's document, when there is one that differs from `current` (the text of
/// the file as opened): what an autosave kept after a crash.
pub fn pending_recovery(file: Option<&Path>, current: &str) -> Option<(PathBuf, GraphDocument)> {
    let path = recovery_path(file);
    let text = crate::io::read_text(&path).ok()?;
    if text == current {
        return None;
    }
    GraphDocument::parse(&text).ok().map(|doc| (path, doc))
}

/// Removes the recovery file (after a save, or when the user discards it).
pub fn discard_recovery(file: Option<&Path>) {
    let _ = std::fs::remove_file(recovery_path(file));
}

/// How many files File → Open Recent lists.
pub const RECENT_MAX: usize = 10;

/// The file the recent-files list is kept in: `matgraph/recent.json` in the OS config
/// folder (`$XDG_CONFIG_HOME`, else `~/.config`; `%APPDATA%` on Windows), else
/// `matgraph-recent.json` in the temporary folder.
pub fn recent_list_path() -> PathBuf {
    let config = std::env::var_os("XDG_CONFIG_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("APPDATA").map(PathBuf::from))
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config")));
    match config {
        Some(c) => c.join("matgraph").join("recent.json"),
        None => std::env::temp_dir().join("matgraph-recent.json"),
    }
}

/// The recently opened or saved graph files, newest first, kept in a JSON list.
#[derive(Clone, Debug, PartialEq)]
pub struct Recent {
    /// Where the list is stored.
    pub store: PathBuf,
    /// The files, newest first, at most [`RECENT_MAX`].
    pub files: Vec<PathBuf>,
}

impl Recent {
    /// The list stored at `store` (empty when it is missing or unreadable).
    pub fn load(store: &Path) -> Recent {
        let files = crate::io::read_text(store)
            .ok()
            .and_then(|t| serde_json::from_str::<Vec<PathBuf>>(&t).ok())
            .unwrap_or_default();
        Recent {
            store: store.to_owned(),
            files,
        }
    }

    /// Puts `file` first (absolute, once) and writes the list; the message names the store.
    pub fn push(&mut self, file: &Path) -> Result<(), String> {
        let file = std::path::absolute(file).unwrap_or_else(|_| file.to_owned());
        self.files.retain(|f| f != &file);
        self.files.insert(0, file);
        self.files.truncate(RECENT_MAX);
        if let Some(dir) = self.store.parent() {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        let text = serde_json::to_string_pretty(&self.files).map_err(|e| e.to_string())?;
        save(&self.store, &(text + "\n"))
    }
}

/// The modification time of `path`, if it can be read.
pub fn modified(path: &Path) -> Option<std::time::SystemTime> {
    std::fs::metadata(path).and_then(|m| m.modified()).ok()
}
