//! `matgraph check`: validate graph files.

use super::{CliResult, count, read_graph_text, registry};
use matgraph::Graph;
use matgraph::error::GraphErrors;
use std::path::PathBuf;

/// Options of `matgraph check`.
#[derive(clap::Args)]
pub struct Args {
    /// Graph files (JSON).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
}

/// Validates every file: one line per file on stdout, the errors on stderr. A graph
/// without outputs is an error here as in `render` and `eval`, which have nothing to show.
pub fn run(args: &Args) -> CliResult {
    let files = &args.files;
    let mut failed = 0;
    for f in files {
        let text = match read_graph_text(f) {
            Ok(t) => t,
            Err(e) => {
                failed += 1;
                println!("{}: 1 error", f.display());
                eprintln!("{e}");
                continue;
            }
        };
        match Graph::from_json(&text, registry()) {
            Ok(g) if g.outputs().is_empty() => {
                failed += 1;
                println!("{}: 1 error", f.display());
                eprintln!(
                    "{}: the graph has no outputs: add one to \"outputs\" (render and eval need one)",
                    f.display()
                );
            }
            Ok(g) => println!(
                "{}: ok ({}, {})",
                f.display(),
                count(g.nodes().len(), "node"),
                count(g.outputs().len(), "output")
            ),
            Err(errors) => {
                failed += 1;
                let e = GraphErrors {
                    source: f.clone(),
                    errors,
                };
                println!("{}: {}", f.display(), count(e.errors.len(), "error"));
                eprintln!("{e}");
            }
        }
    }
    if failed > 0 {
        Err(format!("{failed} of {} failed", count(files.len(), "file")))
    } else {
        Ok(())
    }
}
