//! The `matgraph` command line: check, list nodes, evaluate, and write the JSON Schema.

use clap::{Parser, Subcommand};
use matgraph::document::{GraphDocument, json_schema};
use matgraph::error::GraphErrors;
use matgraph::node::{Attribute, NodeType, PortType};
use matgraph::{Graph, OutputBatch, Plan, PlanOptions, Registry, SampleBatch, Value};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
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
    Check {
        /// Graph files (JSON).
        #[arg(required = true)]
        files: Vec<PathBuf>,
    },
    /// List every node type with its ports, defaults, ranges and docs.
    Nodes {
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Evaluate a graph (or one node type) at one sample and print its outputs.
    #[command(
        after_help = "Values are written 0.5, [0.1,0.2,0.3], true, or an enum choice's name.\n\
        --set NODE.INPUT=VALUE sets a node input; --set NAME=VALUE sets a parameter or a geometry\n\
        attribute (position, normal, view, light, uv, time). With --node, --set INPUT=VALUE."
    )]
    Eval {
        /// Graph file to evaluate.
        #[arg(required_unless_present = "node", conflicts_with = "node")]
        file: Option<PathBuf>,
        /// Evaluate one node type alone, other inputs at their defaults.
        #[arg(long, value_name = "TYPE")]
        node: Option<String>,
        /// Set an input, parameter or attribute: NODE.INPUT=VALUE, NAME=VALUE.
        #[arg(long = "set", value_name = "NAME=VALUE")]
        sets: Vec<String>,
        /// Outputs to print (graph output names or NODE.OUTPUT); default: the graph's outputs.
        #[arg(long = "output", value_name = "NODE.OUTPUT")]
        outputs: Vec<String>,
        /// Print one JSON object: output name → number or array.
        #[arg(long)]
        json: bool,
        /// Print the compiled plan (folded, hoisted and per-sample steps) before the outputs.
        #[arg(long)]
        explain: bool,
    },
    /// Compile a graph to WGSL (validated by naga) or, through naga, SPIR-V, GLSL, MSL or HLSL.
    Wgsl {
        /// Graph file.
        file: PathBuf,
        /// Output language.
        #[arg(long, default_value = "wgsl", value_parser = ["wgsl", "spirv", "glsl", "msl", "hlsl"])]
        target: String,
        /// Entry point: batch evaluation (compute) or per-pixel rendering (fragment).
        #[arg(long, default_value = "compute", value_parser = ["compute", "fragment"])]
        entry: String,
        /// Fold parameters into constants instead of a uniform buffer.
        #[arg(long)]
        bake: bool,
        /// Outputs to compile (graph output names or NODE.OUTPUT); default: the graph's outputs.
        #[arg(long = "output", value_name = "NODE.OUTPUT")]
        outputs: Vec<String>,
        /// Output file; standard output when absent (SPIR-V is binary).
        #[arg(short = 'o', long = "out")]
        out: Option<PathBuf>,
    },
    /// Write the JSON Schema of the graph format (docs/graph.schema.json).
    Schema {
        /// Output file; standard output when absent.
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// Rewrite graph files in canonical form (sorted inputs, normalised values).
    Fmt {
        /// Graph files (JSON).
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// Only report files that are not canonical; exit non-zero if any.
        #[arg(long)]
        check: bool,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Check { files } => check(&files),
        Command::Nodes { json } => nodes(json),
        Command::Eval {
            file,
            node,
            sets,
            outputs,
            json,
            explain,
        } => eval(&EvalArgs {
            file,
            node,
            sets,
            outputs,
            json,
            explain,
        }),
        Command::Wgsl {
            file,
            target,
            entry,
            bake,
            outputs,
            out,
        } => wgsl(&file, &target, &entry, bake, &outputs, out.as_deref()),
        Command::Schema { output } => schema(output.as_deref()),
        Command::Fmt { files, check } => fmt(&files, check),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            if !message.is_empty() {
                eprintln!("{message}");
            }
            ExitCode::FAILURE
        }
    }
}

type CliResult = Result<(), String>;

fn registry() -> &'static Registry {
    Registry::builtin()
}

fn check(files: &[PathBuf]) -> CliResult {
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

fn nodes(json: bool) -> CliResult {
    let types = registry().types();
    if json {
        let list: Vec<serde_json::Value> = types.iter().map(|t| node_json(t)).collect();
        print!(
            "{}",
            matgraph::pretty::to_string(&serde_json::Value::Array(list))
        );
        return Ok(());
    }
    for t in types {
        println!("{} [{}] — {}", t.name(), t.category(), t.summary());
        println!("    {}", t.source_doc());
        if t.is_generic() {
            let ts: Vec<&str> = t.generic_types().iter().map(|t| t.name()).collect();
            println!("    T ∈ {{{}}}", ts.join(", "));
        }
        for i in t.inputs() {
            let mut extra = String::new();
            if let Some(r) = i.soft {
                extra += &format!(" soft [{}, {}]", r.min, r.max);
            }
            if let Some(r) = i.hard {
                extra += &format!(" hard [{}, {}]", r.min, r.max);
            }
            if !i.unit.is_empty() {
                extra += &format!(" ({})", i.unit);
            }
            if !i.choices.is_empty() {
                extra += &format!(" choices: {}", i.choices.join(", "));
            }
            println!(
                "    in  {:<14} {:<6} = {:<18}{extra} — {}",
                i.name,
                i.ty.to_string(),
                i.default.to_string(),
                i.doc
            );
        }
        for o in t.outputs() {
            let unit = if o.unit.is_empty() {
                String::new()
            } else {
                format!(" ({})", o.unit)
            };
            println!(
                "    out {:<14} {:<6}{unit} — {}",
                o.name,
                o.ty.to_string(),
                o.doc
            );
        }
        println!();
    }
    Ok(())
}

fn port_type(t: PortType) -> String {
    t.to_string()
}

fn node_json(t: &NodeType) -> serde_json::Value {
    use serde_json::json;
    let range = |r: Option<matgraph::node::Range>| r.map(|r| json!([r.min, r.max]));
    json!({
        "name": t.name(),
        "category": t.category().name(),
        "summary": t.summary(),
        "source": t.source_doc(),
        "generic_types": if t.is_generic() { json!(t.generic_types().iter().map(|t| t.name()).collect::<Vec<_>>()) } else { json!(null) },
        "inputs": t.inputs().iter().map(|i| json!({
            "name": i.name,
            "type": port_type(i.ty),
            "default": i.default.to_json(),
            "soft_range": range(i.soft),
            "hard_range": range(i.hard),
            "unit": i.unit,
            "choices": i.choices,
            "doc": i.doc,
        })).collect::<Vec<_>>(),
        "outputs": t.outputs().iter().map(|o| json!({
            "name": o.name,
            "type": port_type(o.ty),
            "unit": o.unit,
            "doc": o.doc,
        })).collect::<Vec<_>>(),
    })
}

/// Parses a command-line value: JSON (`0.5`, `[0.1,0.2]`, `true`), else a bare enum choice name.
fn parse_value(text: &str) -> serde_json::Value {
    serde_json::from_str(text).unwrap_or_else(|_| serde_json::Value::String(text.to_owned()))
}

fn split_set(s: &str) -> Result<(&str, serde_json::Value), String> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| format!("--set '{s}': expected NAME=VALUE"))?;
    Ok((name.trim(), parse_value(value.trim())))
}

/// The options of `matgraph eval`.
struct EvalArgs {
    file: Option<PathBuf>,
    node: Option<String>,
    sets: Vec<String>,
    outputs: Vec<String>,
    json: bool,
    explain: bool,
}

fn eval(args: &EvalArgs) -> CliResult {
    let (file, node, sets, outputs, json) = (
        args.file.as_deref(),
        args.node.as_deref(),
        &args.sets,
        &args.outputs,
        args.json,
    );
    let mut attrs: Vec<(Attribute, Value)> = Vec::new();
    let mut params: Vec<(String, serde_json::Value)> = Vec::new();
    let (graph, source) = if let Some(type_name) = node {
        let mut inputs = BTreeMap::new();
        for s in sets {
            let (name, value) = split_set(s)?;
            inputs.insert(name.to_owned(), value);
        }
        let g = Graph::single_node(registry(), type_name, inputs).map_err(|errors| {
            GraphErrors {
                source: PathBuf::from(format!("--node {type_name}")),
                errors,
            }
            .to_string()
        })?;
        (g, PathBuf::from(type_name))
    } else {
        let path = file.ok_or("no graph file")?;
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
        let wrap = |errors| {
            GraphErrors {
                source: path.to_owned(),
                errors,
            }
            .to_string()
        };
        let mut doc = GraphDocument::parse(&text).map_err(wrap)?;
        for s in sets {
            let (name, value) = split_set(s)?;
            if let Some((node_id, input)) = name.split_once('.') {
                let n = doc
                    .nodes
                    .iter_mut()
                    .find(|n| n.id == node_id)
                    .ok_or_else(|| {
                        format!("{}: --set {name}: no node '{node_id}'", path.display())
                    })?;
                n.inputs.insert(input.to_owned(), value);
            } else if let Some(a) = Attribute::from_name(name) {
                let v = Value::from_json(a.ty(), &value)
                    .ok_or_else(|| format!("--set {name}: expected a {} value", a.ty()))?;
                attrs.push((a, v));
            } else {
                params.push((name.to_owned(), value));
            }
        }
        (
            Graph::from_document(&doc, registry()).map_err(wrap)?,
            path.to_owned(),
        )
    };
    let options = PlanOptions {
        outputs: outputs.to_vec(),
        bake_parameters: false,
    };
    let plan = Plan::compile(&graph, &options).map_err(|e| format!("{}: {e}", source.display()))?;
    if args.explain {
        eprint!("{}", plan.listing());
    }
    let mut values = plan.default_parameters();
    for (name, json) in &params {
        let ty = plan
            .parameters()
            .iter()
            .find(|p| &p.name == name)
            .map(|p| p.ty)
            .ok_or_else(|| {
                let e = values
                    .set(name, Value::float(0.0))
                    .err()
                    .map(|e| e.to_string())
                    .unwrap_or_default();
                format!(
                    "{}: --set {name}: {e} (not a node input, parameter or attribute)",
                    source.display()
                )
            })?;
        let v = Value::from_json(ty, json)
            .ok_or_else(|| format!("{}: --set {name}: expected a {ty} value", source.display()))?;
        values
            .set(name, v)
            .map_err(|e| format!("{}: {e}", source.display()))?;
    }
    let mut batch = SampleBatch::new(1);
    for (a, v) in attrs {
        batch.fill(a, v).map_err(|e| e.to_string())?;
    }
    let out = plan
        .execute(&batch, &values)
        .map_err(|e| format!("{}: {e}", source.display()))?;
    print_outputs(&out, json);
    Ok(())
}

fn print_outputs(out: &OutputBatch, json: bool) {
    if json {
        let mut map = serde_json::Map::new();
        for (k, name) in out.names().iter().enumerate() {
            map.insert(name.clone(), out.value(k, 0).to_json());
        }
        println!("{}", serde_json::Value::Object(map));
    } else {
        let width = out.names().iter().map(|n| n.len()).max().unwrap_or(0);
        for (k, name) in out.names().iter().enumerate() {
            println!("{name:<width$} = {}  ({})", out.value(k, 0), out.ty(k));
        }
    }
}

fn wgsl(
    file: &Path,
    target: &str,
    entry: &str,
    bake: bool,
    outputs: &[String],
    out: Option<&Path>,
) -> CliResult {
    use matgraph::wgsl::{Entry, Target, WgslOptions, generate};
    let graph = matgraph::io::load_graph(file, registry()).map_err(|e| e.to_string())?;
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
        Some(p) => std::fs::write(p, &bytes).map_err(|e| format!("{}: {e}", p.display())),
        None => {
            use std::io::Write;
            std::io::stdout()
                .write_all(&bytes)
                .map_err(|e| e.to_string())
        }
    }
}

fn schema(output: Option<&Path>) -> CliResult {
    let text = json_schema();
    match output {
        Some(p) => {
            matgraph::io::write_atomic(p, &text).map_err(|e| format!("{}: {e}", p.display()))
        }
        None => {
            print!("{text}");
            Ok(())
        }
    }
}

fn fmt(files: &[PathBuf], check_only: bool) -> CliResult {
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
