//! `matgraph fmt`: rewrite graph files in canonical form.

use super::{CliResult, registry};
use std::path::PathBuf;

/// Options of `matgraph fmt`.
#[derive(clap::Args)]
pub struct Args {
    /// Graph files (JSON).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Only report files that are not canonical; exit non-zero if any.
    #[arg(long)]
    pub check: bool,
}

/// Rewrites (or, with `--check`, reports) every file that is not canonical.
pub fn run(args: &Args) -> CliResult {
    let (files, check_only) = (&args.files, args.check);
    let mut differing = 0;
    for f in files {
        let g = matgraph::io::load_graph(f, registry()).map_err(|e| e.to_string())?;
        let canonical = g.to_json();
        let current = std::fs::read_to_string(f).map_err(|e| format!("{}: {e}", f.display()))?;
        if canonical != current {
            differing += 1;
            if check_only {
                println!("{}: not canonical", f.display());
            } else {
                matgraph::io::write_atomic(f, &canonical)
                    .map_err(|e| format!("{}: {e}", f.display()))?;
                println!("{}: rewritten", f.display());
            }
        }
    }
    if check_only && differing > 0 {
        Err(format!("{differing} files are not canonical"))
    } else {
        Ok(())
    }
}
