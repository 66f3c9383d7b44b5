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
