//! Node groups (format version 2): a subgraph used as a node, with its own interface.
//!
//! A group is declared in a file's top-level `groups` (inputs, nodes, outputs) or is a whole
//! graph file (its parameters become the group's inputs, its outputs the group's outputs).
//! A node `{ "type": "group", "group": REF }` uses one: `NAME` (a group of the same file),
//! `PATH#NAME` (a group of another file) or `PATH` (a whole file), paths relative to the
//! file that writes them. Inside a group, `{ "link": "@in.NAME" }` reads its input `NAME`.
//! This follows Blender's node groups (Group Input/Output nodes become `@in` and the
//! group's `outputs`) and MaterialX's nodegraphs with their nodedefs.
//!
//! Groups are **inlined** before validation ([`expand`]): every instance's nodes are copied
//! into one flat document under the instance's id as a path (`g/f` is node `f` of instance
//! `g`), each interface input becomes a `reroute` node `g/@in:NAME` holding what the
//! instance passes (typed by the interface), and each group output a `reroute`
//! `g/@out:NAME`. Reroutes cost nothing in the CPU plan and the WGSL (their consumers read
//! their source), so a grouped graph evaluates to the same bits as the same graph written
//! flat; constant folding and dead-code elimination work through instances as through any
//! node. Errors found in the flat graph are moved back to the instance they come from
//! ([`relocate`]): `node 'g' (group lib/layers.json#blend) → node 'f': input 'x': …`.
//!
//! The core reads no files: references to other files go through a [`GroupFiles`]
//! (`matgraph::io::FileGroups` reads them from disk under the texture folder rules).

mod expand;
mod instances;
mod relocate;

pub use instances::{Instance, Instances};

pub(crate) use expand::{Expanded, expand};
pub(crate) use relocate::relocate;

use crate::document::GraphDocument;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// The node type name of a group instance.
pub const GROUP: &str = "group";
/// The node type name of a reroute: passes its input on, typed by what is connected.
pub const REROUTE: &str = "reroute";
/// The reserved node id that reads a group's inputs inside it (`@in.NAME`).
pub const INPUT_ID: &str = "@in";
/// How deep groups may nest; deeper is an error (so that a runaway chain of files is
/// reported, not followed).
pub const MAX_DEPTH: usize = 64;

/// How many nodes any graph may have once its groups are inlined (see also
/// [`expansion_limit`]); more is an error
/// ([`crate::GraphError::GroupTooLarge`]) raised before any node is copied, so that a group
/// using another twice at each of 30 levels (2³⁰ copies) is refused, not allocated. The
/// limit keeps what is accepted within linear time and a 4 GiB address space: 524 288
/// nodes; 100 000 instances of a one-node group (300 001 nodes) load, plan and evaluate
/// (`tests/graphs/groups.rs`), and `matgraph wgsl` on 170 000 of them (510 001 nodes) took
/// 49 s and 1.9 GiB (release build, 2-core Xeon).
pub const MAX_EXPANDED_NODES: usize = 1 << 19;

/// Inlined graphs up to this many nodes are accepted whatever their groups multiply; past
/// it, [`MAX_AMPLIFICATION`] applies. 16 384 nodes load, plan and compile in under 0.5 s
/// (release build, 2-core Xeon), far past any hand-made material.
pub const AMPLIFICATION_THRESHOLD: usize = 1 << 14;

/// Past [`AMPLIFICATION_THRESHOLD`] inlined nodes, at most this many times the nodes
/// written (the top graph's, and each group's inputs, nodes and outputs once): a file of
/// 50 nodes cannot make 160 000 by groups using groups twice, 17 levels deep (seconds of
/// work from a few hundred bytes), while a written graph of any size is accepted up to
/// [`MAX_EXPANDED_NODES`]. The habit of XML parsers against entity expansion ("billion
/// laughs": libexpat's maximum amplification factor past an activation threshold).
pub const MAX_AMPLIFICATION: usize = 32;

/// The most nodes a graph with `written` nodes written may have once inlined:
/// `max(AMPLIFICATION_THRESHOLD, MAX_AMPLIFICATION · written)`, at most
/// [`MAX_EXPANDED_NODES`].
pub fn expansion_limit(written: usize) -> usize {
    AMPLIFICATION_THRESHOLD
        .max(MAX_AMPLIFICATION.saturating_mul(written))
        .min(MAX_EXPANDED_NODES)
}

/// A graph file a group reference names, as a [`GroupFiles`] gives it.
#[derive(Clone, Debug)]
pub struct GroupFile {
    /// Unique per file (a canonical path): references inside the file are resolved from it,
    /// and a group is recognised by it when it reaches itself.
    pub key: String,
    /// The file's name in messages, relative to the top graph's folder (`lib/layers.json`).
    pub label: String,
    /// The folder of the file relative to the top graph's folder, with a trailing `/`
    /// (empty for the same folder): texture paths inside it are rebased onto it.
    pub folder: String,
    /// The parsed file.
    pub doc: Arc<GraphDocument>,
}

/// Reads the files that group references name. The core does no I/O; the loader of a
/// graph file passes one (see `matgraph::io::FileGroups`).
pub trait GroupFiles: Send + Sync + std::fmt::Debug {
    /// The file `reference` names, as written in the file keyed `from` (the top graph's
    /// key is [`GroupFiles::top_key`]). The error says why it cannot be read.
    fn load(&self, from: &str, reference: &str) -> Result<GroupFile, String>;
    /// The top graph's name in messages (`water.json`).
    fn top_label(&self) -> String {
        String::new()
    }
    /// The top graph's key, as [`GroupFile::key`] would give it (so that a group reaching
    /// back into the top file through another file is recognised).
    fn top_key(&self) -> String {
        String::new()
    }
}

/// No files: a graph given as text alone. Every reference to another file is an error
/// that says how to load the graph with its folder.
#[derive(Debug, Default)]
pub struct NoFiles;

impl GroupFiles for NoFiles {
    fn load(&self, _from: &str, reference: &str) -> Result<GroupFile, String> {
        Err(format!(
            "cannot read '{reference}': the graph was given without its file, so other files \
             cannot be found (load it with matgraph::io::load_graph)"
        ))
    }
}

/// Remembers every file another [`GroupFiles`] gave, so that the same graph can be
/// expanded again (another variant choice, a specialisation) without reading the disk.
#[derive(Debug)]
pub struct RememberedFiles {
    inner: Arc<dyn GroupFiles>,
    seen: Mutex<HashMap<(String, String), Result<GroupFile, String>>>,
}

impl RememberedFiles {
    /// Wraps `inner`.
    pub fn new(inner: Arc<dyn GroupFiles>) -> RememberedFiles {
        RememberedFiles {
            inner,
            seen: Mutex::new(HashMap::new()),
        }
    }
}

impl GroupFiles for RememberedFiles {
    fn load(&self, from: &str, reference: &str) -> Result<GroupFile, String> {
        let key = (from.to_owned(), reference.to_owned());
        if let Some(r) = self.seen.lock().ok().and_then(|m| m.get(&key).cloned()) {
            return r;
        }
        let r = self.inner.load(from, reference);
        if let Ok(mut m) = self.seen.lock() {
            m.insert(key, r.clone());
        }
        r
    }
    fn top_label(&self) -> String {
        self.inner.top_label()
    }
    fn top_key(&self) -> String {
        self.inner.top_key()
    }
}

/// Whether `doc` uses groups (and so is inlined before validation).
pub fn uses_groups(doc: &GraphDocument) -> bool {
    !doc.groups.is_empty() || doc.nodes.iter().any(|n| n.node_type == GROUP)
}
