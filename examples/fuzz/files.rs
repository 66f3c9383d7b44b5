//! Graph files in memory: the group library files a case's graph names by relative path,
//! served through the loader's [`GroupFiles`] so that no case touches the disk.

use matgraph::GraphDocument;
use matgraph::group::{GroupFile, GroupFiles};
use std::collections::BTreeMap;
use std::sync::Arc;

/// The key and label of the top graph.
pub const TOP: &str = "top.json";

/// A folder of graph files by path (`lib/fresnel.json`), the top graph at [`TOP`].
#[derive(Clone, Debug, Default)]
pub struct MemFiles {
    /// Each file's text by its path in the folder.
    pub files: BTreeMap<String, String>,
}

impl MemFiles {
    /// The files.
    pub fn new(files: BTreeMap<String, String>) -> MemFiles {
        MemFiles { files }
    }
}

/// `reference` written in the file at `from`, as a path in the folder: `..` and `.`
/// resolved; `None` when it leaves the folder or is absolute.
pub fn join(from: &str, reference: &str) -> Option<String> {
    if reference.starts_with('/') || reference.contains('\\') {
        return None;
    }
    let mut parts: Vec<&str> = from.split('/').collect();
    parts.pop();
    for p in reference.split('/') {
        match p {
            "" | "." => {}
            ".." => {
                parts.pop()?;
            }
            p => parts.push(p),
        }
    }
    Some(parts.join("/"))
}

impl GroupFiles for MemFiles {
    fn load(&self, from: &str, reference: &str) -> Result<GroupFile, String> {
        let path = join(from, reference)
            .ok_or_else(|| format!("cannot read '{reference}': outside the graph's folder"))?;
        let text = self
            .files
            .get(&path)
            .ok_or_else(|| format!("cannot read '{reference}': no such file"))?;
        let doc = GraphDocument::parse(text).map_err(|errors| {
            let shown: Vec<String> = errors.iter().map(|e| e.to_string()).collect();
            format!("{reference}: {}", shown.join("; "))
        })?;
        let folder = match path.rsplit_once('/') {
            Some((dir, _)) => format!("{dir}/"),
            None => String::new(),
        };
        Ok(GroupFile {
            key: path.clone(),
            label: path,
            folder,
            doc: Arc::new(doc),
        })
    }
    fn top_label(&self) -> String {
        TOP.to_owned()
    }
    fn top_key(&self) -> String {
        TOP.to_owned()
    }
}
