//! Helpers shared by the integration tests.

use std::path::{Path, PathBuf};

/// Every bundled graph (`graphs/*.json`), sorted; fails if there is none.
pub fn bundled_graphs() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    v.sort();
    assert!(!v.is_empty(), "no graphs/*.json");
    v
}
