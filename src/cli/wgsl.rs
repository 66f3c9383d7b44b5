//! `matgraph wgsl`: compile a graph to WGSL or, through naga, another shading language.

use super::CliResult;
use matgraph::PlanOptions;
use std::path::PathBuf;

/// Options of `matgraph wgsl`.
#[derive(clap::Args)]
pub struct Args {
    /// Graph file.
    pub file: PathBuf,
    /// Output language.
    #[arg(long, default_value = "wgsl", value_parser = ["wgsl", "spirv", "glsl", "msl", "hlsl"])]
    pub target: String,
    /// Entry point: batch evaluation (compute) or per-pixel rendering (fragment).
    #[arg(long, default_value = "compute", value_parser = ["compute", "fragment"])]
    pub entry: String,
    /// Fold parameters into constants instead of a uniform buffer.
    #[arg(long)]
    pub bake: bool,
    /// Outputs to compile (graph output names or NODE.OUTPUT); default: the graph's outputs.
    #[arg(long = "output", value_name = "NODE.OUTPUT")]
    pub outputs: Vec<String>,
    /// Output file; standard output when absent (SPIR-V is binary).
    #[arg(short = 'o', long = "out")]
    pub out: Option<PathBuf>,
}

/// Compiles the graph and prints or writes the shader.
pub fn run(args: &Args) -> CliResult {
    let (file, target, entry, bake, outputs, out) = (
        args.file.as_path(),
        args.target.as_str(),
        args.entry.as_str(),
        args.bake,
        &args.outputs,
        args.out.as_deref(),
    );
    use matgraph::wgsl::{Entry, Target, WgslOptions, generate};
    let graph = super::load_graph(file)?;
    let options = WgslOptions {
        plan: PlanOptions {
            outputs: outputs.to_vec(),
            bake_parameters: bake,
        },
        entry: if entry == "fragment" {
            Entry::Fragment
        } else {
            Entry::Compute
        },
    };
    let shader = generate(&graph, &options).map_err(|e| format!("{}: {e}", file.display()))?;
    let target = Target::from_name(target).ok_or_else(|| format!("unknown target '{target}'"))?;
    let bytes = shader
        .translate(target)
        .map_err(|e| format!("{}: {e}", file.display()))?;
    match out {
        Some(p) => {
            matgraph::io::write_atomic(p, &bytes).map_err(|e| format!("{}: {e}", p.display()))
        }
        None => {
            use std::io::Write;
            std::io::stdout()
                .write_all(&bytes)
                .map_err(|e| e.to_string())
        }
    }
}
