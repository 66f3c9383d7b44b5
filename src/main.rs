//! The `matgraph` command line: argument parsing and dispatch. Each command lives in its
//! own file under `src/cli/` and reaches the core only through the public library API.

mod cli;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// A node-graph material host: validate, inspect and evaluate material graphs.
#[derive(Parser)]
#[command(name = "matgraph", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Validate graph files: one line per file, then every error found.
    Check(cli::check::Args),
    /// List every node type with its ports, defaults, ranges and docs.
    Nodes(cli::nodes::Args),
    /// Evaluate a graph (or one node type) at one sample and print its outputs.
    #[command(after_help = cli::eval::AFTER_HELP)]
    Eval(cli::eval::Args),
    /// Compile a graph to WGSL (validated by naga) or, through naga, SPIR-V, GLSL, MSL or HLSL.
    Wgsl(cli::wgsl::Args),
    /// Render graphs in a scene (material ball or water) to PNG, on the CPU or the GPU.
    #[command(after_help = cli::render::AFTER_HELP)]
    Render(cli::render::Args),
    /// Write the JSON Schema of the graph format (docs/graph.schema.json).
    Schema(cli::schema::Args),
    /// Write every image-based-lighting texture a graph can ask for (environment, GGX
    /// prefilter chain, SH irradiance, BRDF table) with a manifest, for apps.
    BakeEnv(cli::bake_env::Args),
    /// Rewrite graph files in canonical form (sorted inputs, normalised values).
    Fmt(cli::fmt::Args),
    /// Measure every material family's variants (cost, error against the reference) and
    /// write target/report/ (the published docs/report/ with `--out docs/report`): a table,
    /// data and a speed-against-error plot per family.
    Report(cli::report::Args),
    /// Open the node editor on a graph file (or render it headless with --screenshot).
    #[cfg(feature = "editor")]
    Edit(cli::edit::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    // Before any thread starts (see `cli::env::quiet_mesa`); dropped at the end of main.
    let _runtime = match &cli.command {
        Command::Render(args) if args.gpu || args.gpu_compute => Some(cli::env::quiet_mesa()),
        Command::Report(args) if !args.no_timing && !args.no_gpu => Some(cli::env::quiet_mesa()),
        #[cfg(feature = "editor")]
        Command::Edit(_) => Some(cli::env::quiet_mesa()),
        _ => None,
    };
    let result = match cli.command {
        Command::Check(args) => cli::check::run(&args),
        Command::Nodes(args) => cli::nodes::run(&args),
        Command::Eval(args) => cli::eval::run(&args),
        Command::Wgsl(args) => cli::wgsl::run(&args),
        Command::Render(args) => cli::render::run(&args),
        Command::Schema(args) => cli::schema::run(&args),
        Command::BakeEnv(args) => cli::bake_env::run(&args),
        Command::Fmt(args) => cli::fmt::run(&args),
        Command::Report(args) => cli::report::run(&args),
        #[cfg(feature = "editor")]
        Command::Edit(args) => cli::edit::run(&args),
    };
    // What is still buffered; a full disk or closed pipe shows here at the latest.
    let result = result.and_then(|()| cli::out::flush_stdout());
    if cli::out::stdout_closed() {
        return ExitCode::from(cli::out::BROKEN_PIPE_STATUS);
    }
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            if !message.is_empty() {
                cli::out::stderr_fmt(format_args!("{message}\n"));
            }
            ExitCode::FAILURE
        }
    }
}
