//! `matgraph check`: validate graph files.

use super::{CliResult, registry};
use std::path::PathBuf;

/// Options of `matgraph check`.
#[derive(clap::Args)]
pub struct Args {
    /// Graph files (JSON).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
}

/// Validates every file: one line per file on stdout, the errors on stderr.
pub fn run(args: &Args) -> CliResult {
    let files = &args.files;
    let mut failed = 0;
    for f in files {
        match matgraph::io::load_graph(f, registry()) {
            Ok(g) => println!(
                "{}: ok ({} nodes, {} outputs)",
                f.display(),
                g.nodes().len(),
                g.outputs().len()
            ),
            Err(e) => {
                failed += 1;
                println!(
                    "{}: {} error{}",
                    f.display(),
                    e.errors.len(),
                    if e.errors.len() == 1 { "" } else { "s" }
                );
                eprintln!("{e}");
            }
        }
    }
    if failed > 0 {
        Err(format!("{failed} of {} files failed", files.len()))
    } else {
        Ok(())
    }
}
