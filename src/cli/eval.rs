//! `matgraph eval`: evaluate a graph (or one node type) at one sample.

use super::{CliResult, registry, split_set};
use matgraph::document::GraphDocument;
use matgraph::error::GraphErrors;
use matgraph::node::Attribute;
use matgraph::{Graph, OutputBatch, Plan, PlanOptions, SampleBatch, Value};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// Help text after the options of `matgraph eval`.
pub const AFTER_HELP: &str = "Values are written 0.5, [0.1,0.2,0.3], true, or an enum choice's name.\n\
--set NODE.INPUT=VALUE sets a node input; --set NAME=VALUE sets a parameter or a geometry\n\
attribute (position, normal, view, light, uv, time). With --node, --set INPUT=VALUE.";

/// Options of `matgraph eval`.
#[derive(clap::Args)]
pub struct Args {
    /// Graph file to evaluate.
    #[arg(required_unless_present = "node", conflicts_with = "node")]
    pub file: Option<PathBuf>,
    /// Evaluate one node type alone, other inputs at their defaults.
    #[arg(long, value_name = "TYPE")]
    pub node: Option<String>,
    /// Set an input, parameter or attribute: NODE.INPUT=VALUE, NAME=VALUE.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub sets: Vec<String>,
    /// Outputs to print (graph output names or NODE.OUTPUT); default: the graph's outputs.
    #[arg(long = "output", value_name = "NODE.OUTPUT")]
    pub outputs: Vec<String>,
    /// Print one JSON object: output name → number or array.
    #[arg(long)]
    pub json: bool,
    /// Print the compiled plan (folded, hoisted and per-sample steps) before the outputs.
    #[arg(long)]
    pub explain: bool,
}

/// Evaluates the graph or node at one sample and prints its outputs.
pub fn run(args: &Args) -> CliResult {
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
    if let Some(path) = file {
        // Images the graph samples, relative to it (scene textures need `render`).
        let textures = matgraph::image_io::load_graph_textures(&graph, path)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        batch.set_textures(std::sync::Arc::new(textures));
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
