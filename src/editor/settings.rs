//! The editor's settings file: the keymap chosen ([`super::keymap::Keymap`]) and, per graph
//! file, the nodes collapsed with H ([`super::collapse`]), which the graph format has no
//! field for. Kept as JSON in `matgraph/editor.json` in the OS config folder, beside the
//! recent-files list ([`super::files::recent_list_path`]); written atomically whenever a
//! setting changes. A missing or unreadable file gives the defaults (the Blender keymap,
//! nothing collapsed).

use super::keymap::Keymap;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The settings file's name, in the folder of [`super::files::recent_list_path`].
pub const FILE_NAME: &str = "editor.json";

/// Where the window keeps its settings: `editor.json` beside `recent.json`.
pub fn settings_path() -> PathBuf {
    let recent = super::files::recent_list_path();
    match recent.parent() {
        Some(dir) if recent.file_name().is_some_and(|n| n == "recent.json") => dir.join(FILE_NAME),
        _ => std::env::temp_dir().join("matgraph-editor.json"),
    }
}

/// What the settings file holds.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Stored {
    /// The keymap.
    pub keymap: Keymap,
    /// The collapsed nodes of each graph file (absolute path), by key
    /// ([`super::collapse::key`]).
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub collapsed: BTreeMap<String, BTreeSet<String>>,
}

/// The settings, and the file they are kept in (`None`: kept in memory only, as the tests'
/// editors and the screenshots keep them).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Settings {
    /// Where they are written.
    pub store: Option<PathBuf>,
    /// The values.
    pub values: Stored,
}

impl Settings {
    /// The settings stored at `store` (the defaults when it is missing or unreadable); later
    /// changes are written there.
    pub fn load(store: &Path) -> Settings {
        let values = crate::io::read_text(store)
            .ok()
            .and_then(|t| serde_json::from_str::<Stored>(&t).ok())
            .unwrap_or_default();
        Settings {
            store: Some(store.to_owned()),
            values,
        }
    }

    /// The keymap.
    pub fn keymap(&self) -> Keymap {
        self.values.keymap
    }

    /// Chooses keymap `k` and writes the file; the message names it.
    pub fn set_keymap(&mut self, k: Keymap) -> Result<(), String> {
        self.values.keymap = k;
        self.write()
    }

    /// The collapsed nodes kept for graph file `file`.
    pub fn collapsed_of(&self, file: &Path) -> BTreeSet<String> {
        self.values
            .collapsed
            .get(&file_key(file))
            .cloned()
            .unwrap_or_default()
    }

    /// Keeps `keys` as graph file `file`'s collapsed nodes (none: the entry goes) and writes
    /// the file; the message names it.
    pub fn set_collapsed(&mut self, file: &Path, keys: &BTreeSet<String>) -> Result<(), String> {
        let k = file_key(file);
        match keys.is_empty() {
            true => self.values.collapsed.remove(&k),
            false => self.values.collapsed.insert(k, keys.clone()),
        };
        self.write()
    }

    /// Writes the settings to their file, when they have one.
    fn write(&self) -> Result<(), String> {
        let Some(store) = &self.store else {
            return Ok(());
        };
        if let Some(dir) = store.parent() {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        let text = serde_json::to_string_pretty(&self.values).map_err(|e| e.to_string())?;
        super::files::save(store, &(text + "\n"))
    }
}

/// A graph file's key in the settings: its absolute path.
fn file_key(file: &Path) -> String {
    std::path::absolute(file)
        .unwrap_or_else(|_| file.to_owned())
        .display()
        .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The keymap and a file's collapsed nodes are written, read back, and a missing or
    /// broken file gives the defaults.
    #[test]
    fn settings_round_trip_through_their_file() {
        let dir = std::env::temp_dir().join(format!("matgraph-settings-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let store = dir.join("matgraph").join(FILE_NAME);
        let mut s = Settings::load(&store);
        assert_eq!(s.keymap(), Keymap::Blender);
        s.set_keymap(Keymap::Classic).unwrap();
        let keys: BTreeSet<String> = ["a".to_owned(), "g/b".to_owned()].into();
        s.set_collapsed(Path::new("/x/graph.json"), &keys).unwrap();
        let back = Settings::load(&store);
        assert_eq!(back.keymap(), Keymap::Classic);
        assert_eq!(back.collapsed_of(Path::new("/x/graph.json")), keys);
        assert!(back.collapsed_of(Path::new("/x/other.json")).is_empty());
        let text = std::fs::read_to_string(&store).unwrap();
        assert!(text.contains("\"keymap\": \"classic\""), "{text}");
        std::fs::write(&store, "not json").unwrap();
        assert_eq!(Settings::load(&store).keymap(), Keymap::Blender);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
