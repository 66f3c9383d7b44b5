//! Reading and writing graph files. The only module of the library that touches the disk.

use crate::error::{GraphError, GraphErrors};
use crate::graph::Graph;
use crate::registry::Registry;
use std::path::Path;

/// Reads and validates a graph file; every error is attributed to `path`.
pub fn load_graph(path: &Path, registry: &Registry) -> Result<Graph, GraphErrors> {
    let wrap = |errors| GraphErrors {
        source: path.to_owned(),
        errors,
    };
    let text = std::fs::read_to_string(path).map_err(|e| {
        wrap(vec![GraphError::Structure {
            node: None,
            line: 0,
            column: 0,
            message: format!("cannot read: {e}"),
        }])
    })?;
    Graph::from_json(&text, registry).map_err(wrap)
}

/// Writes `contents` to `path` atomically: a temporary file in the same folder, synced, then
/// renamed over the target, so a crash never leaves a half-written file.
pub fn write_atomic(path: &Path, contents: impl AsRef<[u8]>) -> std::io::Result<()> {
    use std::io::Write;
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("graph");
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(contents.as_ref())?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Saves a graph as pretty, deterministic JSON, atomically.
pub fn save_graph(path: &Path, graph: &Graph) -> std::io::Result<()> {
    write_atomic(path, graph.to_json())
}
