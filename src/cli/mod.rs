//! The commands of the `matgraph` binary, one file each, and what they share.

#[macro_use]
pub mod out;

pub mod bake_env;
pub mod check;
#[cfg(feature = "editor")]
pub mod edit;
pub mod env;
pub mod eval;
pub mod flags;
pub mod fmt;
pub mod nodes;
pub mod out_dir;
pub mod outputs;
pub mod render;
pub mod report;
pub mod scene;
pub mod schema;
pub mod shared;
pub mod wgsl;

use matgraph::error::GraphErrors;
use matgraph::io::PathPolicy;
use matgraph::{Graph, Registry};
use std::path::Path;

/// What a command returns: `Err` holds the message printed on stderr (exit status 1).
pub type CliResult = Result<(), String>;

/// The built-in node registry.
pub fn registry() -> &'static Registry {
    Registry::builtin()
}

/// `n` and `noun`, the noun in the plural unless `n` is 1 ("1 output", "3 outputs").
pub fn count(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// Reads a graph file as text: a missing file, a folder, a FIFO or a device is refused
/// with a message naming it (before opening it, so a FIFO never blocks).
pub fn read_graph_text(path: &Path) -> Result<String, String> {
    matgraph::io::read_text(path).map_err(|e| e.to_string())
}

/// Reads and validates a graph file with the choices of `--variant NAME=CHOICE` flags;
/// every message names the file.
pub fn load_graph_with(path: &Path, variants: &[String]) -> Result<Graph, String> {
    let selection = variants
        .iter()
        .map(|s| split_variant(s))
        .collect::<Result<Vec<_>, _>>()?;
    let text = read_graph_text(path)?;
    let wrap = |errors| {
        GraphErrors {
            source: path.to_owned(),
            errors,
        }
        .to_string()
    };
    let doc = matgraph::GraphDocument::parse(&text).map_err(wrap)?;
    let files = matgraph::io::group_files(path, PathPolicy::InsideGraphFolder);
    Graph::with_variants_in(&doc, registry(), &selection, files).map_err(wrap)
}

/// Splits `--variant NAME=CHOICE`.
pub fn split_variant(s: &str) -> Result<(String, String), String> {
    match s.split_once('=') {
        Some((name, choice)) if !name.trim().is_empty() && !choice.trim().is_empty() => {
            Ok((name.trim().to_owned(), choice.trim().to_owned()))
        }
        _ => Err(format!("--variant '{s}': expected NAME=CHOICE")),
    }
}

/// The path policy of `--allow-outside-paths`.
pub fn path_policy(allow_outside: bool) -> PathPolicy {
    if allow_outside {
        PathPolicy::Anywhere
    } else {
        PathPolicy::InsideGraphFolder
    }
}

/// A path error with the hint of the flag that allows it.
pub fn path_message(e: impl std::fmt::Display, outside: bool) -> String {
    if outside {
        format!("{e} (pass --allow-outside-paths to read it)")
    } else {
        e.to_string()
    }
}

/// The graph's images, each path opened once and checked against `policy` as opened, each
/// image and its mips reserved in `budget` before they are allocated.
pub fn graph_textures(
    graph: &Graph,
    file: &Path,
    policy: PathPolicy,
    budget: &matgraph::budget::MemoryBudget,
) -> Result<matgraph::texture::TextureSet, String> {
    use matgraph::image_io::GraphTextureError;
    use matgraph::io::PathError;
    matgraph::image_io::load_graph_textures_within(graph, file, policy, budget).map_err(|e| {
        let outside = matches!(e, GraphTextureError::Path(PathError::Outside { .. }));
        path_message(e, outside)
    })
}
