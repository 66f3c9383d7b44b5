//! `matgraph fmt`: rewrite graph files in canonical form.

use super::{CliResult, read_graph_text, registry};
use matgraph::Graph;
use matgraph::error::GraphErrors;
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
    /// Rewrite in the newest format version (a file otherwise keeps its version).
    #[arg(long)]
    pub upgrade: bool,
}

/// Rewrites (or, with `--check`, reports) every file that is not canonical; without
/// `--check` every file gets a line saying what was done, and a canonical one still loses
/// the stale temporaries a killed write left beside it ([`matgraph::io::sweep_stale_temps`]).
/// A symlinked graph is rewritten through the link (its target changes, the link stays).
pub fn run(args: &Args) -> CliResult {
    let (files, check_only) = (&args.files, args.check);
    let mut differing = 0;
    for f in files {
        let current = read_graph_text(f)?;
        let files = matgraph::io::group_files(f, matgraph::io::PathPolicy::InsideGraphFolder);
        let g = Graph::from_json_in(&current, registry(), files).map_err(|errors| {
            GraphErrors {
                source: f.clone(),
                errors,
            }
            .to_string()
        })?;
        let canonical = if args.upgrade {
            let mut doc = g.to_document();
            doc.version = matgraph::FORMAT_VERSION;
            doc.to_json_pretty()
        } else {
            g.to_json()
        };
        if canonical == current {
            if !check_only {
                // A killed write's stale temporaries go, as a rewrite would remove them.
                matgraph::io::sweep_stale_temps(f);
                outln!("{}: already canonical", f.display())?;
            }
        } else {
            differing += 1;
            if check_only {
                outln!("{}: not canonical", f.display())?;
            } else {
                matgraph::io::write_atomic(f, &canonical)
                    .map_err(|e| super::out_dir::write_error(f, &e))?;
                outln!("{}: rewritten", f.display())?;
            }
        }
    }
    if check_only && differing > 0 {
        Err(format!(
            "{} not canonical",
            if differing == 1 {
                "1 file is".to_owned()
            } else {
                format!("{differing} files are")
            }
        ))
    } else {
        Ok(())
    }
}
