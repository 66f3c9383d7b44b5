//! `matgraph schema`: write the JSON Schema of the graph format.

use super::CliResult;
use std::path::PathBuf;

/// Options of `matgraph schema`.
#[derive(clap::Args)]
pub struct Args {
    /// Output file; standard output when absent.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

/// Prints or writes the schema.
pub fn run(args: &Args) -> CliResult {
    let text = matgraph::document::json_schema();
    match &args.output {
        Some(p) => {
            matgraph::io::write_atomic(p, &text).map_err(|e| super::out_dir::write_error(p, &e))
        }
        None => {
            out!("{text}")
        }
    }
}
