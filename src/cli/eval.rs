//! `matgraph eval`: evaluate a graph (or one node type) at one sample.

use super::{CliResult, registry};
use matgraph::document::GraphDocument;
use matgraph::error::GraphErrors;
use matgraph::overrides;
use matgraph::{Graph, OutputBatch, Plan, PlanOptions, SampleBatch, Value};
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
    #[command(flatten)]
    pub variant: super::shared::VariantFlags,
    #[command(flatten)]
    pub output: super::shared::OutputFlags,
    /// Print one JSON object: output name → number, array or bool; NaN, +∞ and −∞ are
    /// written as the strings "NaN", "inf" and "-inf" (JSON has no such numbers).
    #[arg(long)]
    pub json: bool,
    /// Print the compiled plan (folded, hoisted and per-sample steps) before the outputs.
    #[arg(long)]
    pub explain: bool,
    /// Read textures, scene files and environment images outside the graph's folder.
    #[arg(long)]
    pub allow_outside_paths: bool,
    /// Memory the command may use for the images, environment and scene meshes it loads
    /// and builds (bytes, or with a unit: 512MiB, 4GiB); each is refused before it is
    /// allocated when it does not fit.
    #[arg(long, value_name = "SIZE", default_value = "2GiB", value_parser = super::flags::memory_budget)]
    pub memory_budget: u64,
}

/// Width and height of the frame whose scene textures `eval` binds (those of a default
/// `matgraph render`).
pub const SCENE_TEXTURE_FRAME: (u32, u32) = (512, 512);

/// `--node TYPE` for an unknown type: the message names it and suggests the closest name
/// (Jaro–Winkler similarity ≥ 0.8), else points at `matgraph nodes`.
fn unknown_type(type_name: &str) -> String {
    let best = registry()
        .types()
        .iter()
        .map(|t| (strsim::jaro_winkler(type_name, t.name()), t.name()))
        .filter(|(score, _)| *score >= 0.8)
        .max_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(a.1)));
    let hint = match best {
        Some((_, name)) => format!("did you mean '{name}'?"),
        None => "`matgraph nodes` lists them".to_owned(),
    };
    format!("--node {type_name}: unknown node type '{type_name}' ({hint})")
}

/// One float of `--json` output: a number, or the strings `"NaN"`, `"inf"` and `"-inf"`
/// (JSON has no such numbers, and `null` would not tell them apart).
fn json_float(x: f32) -> serde_json::Value {
    if x.is_nan() {
        "NaN".into()
    } else if x == f32::INFINITY {
        "inf".into()
    } else if x == f32::NEG_INFINITY {
        "-inf".into()
    } else {
        matgraph::value::json_f32(x)
    }
}

/// A value as `--json` prints it: [`Value::to_json`] with non-finite floats as strings.
pub fn json_value(v: &Value, ty: matgraph::SocketType) -> serde_json::Value {
    use matgraph::SocketType as T;
    match ty {
        T::Int | T::Bool => v.to_json(),
        T::Float => json_float(v.lanes()[0]),
        _ => serde_json::Value::Array(v.lanes().iter().map(|&x| json_float(x)).collect()),
    }
}

/// Evaluates the graph or node at one sample and prints its outputs.
pub fn run(args: &Args) -> CliResult {
    let (file, node, sets, outputs, json) = (
        args.file.as_deref(),
        args.node.as_deref(),
        &args.sets,
        &args.output.outputs,
        args.json,
    );
    let mut rest = overrides::Remaining::default();
    let (graph, source) = if let Some(type_name) = node {
        if registry().get(type_name).is_none() {
            return Err(unknown_type(type_name));
        }
        let given = overrides::parse_all(sets).map_err(|e| format!("--node {type_name}: {e}"))?;
        let g = Graph::single_node(registry(), type_name, overrides::node_inputs(&given)).map_err(
            |errors| {
                GraphErrors {
                    source: PathBuf::from(format!("--node {type_name}")),
                    errors,
                }
                .to_string()
            },
        )?;
        (g, PathBuf::from(type_name))
    } else {
        let path = file.ok_or("no graph file")?;
        let text = super::read_graph_text(path)?;
        let wrap = |errors| {
            GraphErrors {
                source: path.to_owned(),
                errors,
            }
            .to_string()
        };
        let mut doc = GraphDocument::parse(&text).map_err(wrap)?;
        let at = |e: overrides::OverrideError| format!("{}: {e}", path.display());
        let given = overrides::parse_all(sets).map_err(at)?;
        rest = overrides::apply_to_document(&mut doc, &given).map_err(at)?;
        let selection = args
            .variant
            .variants
            .iter()
            .map(|s| super::split_variant(s))
            .collect::<Result<Vec<_>, _>>()?;
        let policy = super::path_policy(args.allow_outside_paths);
        let graph = Graph::with_variants_in(
            &doc,
            registry(),
            &selection,
            matgraph::io::group_files(path, policy),
        )
        .map_err(wrap)?;
        let graph = super::report::apply_max_error(
            graph,
            path,
            &args.variant.variants,
            args.variant.max_error,
            policy,
        )?;
        (graph, path.to_owned())
    };
    let options = PlanOptions {
        outputs: outputs.to_vec(),
        bake_parameters: false,
    };
    let plan = Plan::compile(&graph, &options).map_err(|e| format!("{}: {e}", source.display()))?;
    if args.explain {
        err!("{}", plan.listing());
    }
    let mut values = plan.default_parameters();
    overrides::set_parameters(&plan, &mut values, &rest.parameters)
        .map_err(|e| format!("{}: {e}", source.display()))?;
    let mut batch = SampleBatch::new(1);
    for (a, v) in rest.attributes {
        batch.fill(a, v).map_err(|e| e.to_string())?;
    }
    if let Some(path) = file {
        // Images the graph samples, inside its folder; the scene textures of its scene as a
        // default render binds them.
        let policy = super::path_policy(args.allow_outside_paths);
        let budget = matgraph::budget::MemoryBudget::new(args.memory_budget);
        let mut textures = super::graph_textures(&graph, path, policy, &budget)?;
        if matgraph::render::uses_scene_textures(&graph) {
            let (scene, environment) = super::scene::resolve(&graph, path, None, policy, &budget)?;
            let (w, h) = SCENE_TEXTURE_FRAME;
            let maps = matgraph::render::scene_texture_set_within(
                &graph,
                &scene,
                w,
                h,
                environment,
                &budget,
            )
            .map_err(|e| format!("{}: {e}", path.display()))?;
            textures
                .extend_shared(&maps)
                .map_err(|e| format!("{}: {e}", path.display()))?;
        }
        batch.set_textures(std::sync::Arc::new(textures));
    }
    let out = plan
        .execute(&batch, &values)
        .map_err(|e| format!("{}: {e}", source.display()))?;
    print_outputs(&out, json)
}

/// Prints the outputs of sample 0, as text or one JSON object.
fn print_outputs(out: &OutputBatch, json: bool) -> CliResult {
    if json {
        let mut map = serde_json::Map::new();
        for (k, name) in out.names().iter().enumerate() {
            map.insert(name.clone(), json_value(&out.value(k, 0), out.ty(k)));
        }
        outln!("{}", serde_json::Value::Object(map))
    } else {
        let width = out.names().iter().map(|n| n.len()).max().unwrap_or(0);
        for (k, name) in out.names().iter().enumerate() {
            outln!("{name:<width$} = {}  ({})", out.value(k, 0), out.ty(k))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use matgraph::SocketType;
    use serde_json::json;

    #[test]
    fn json_tells_nan_and_infinities_apart() {
        let f = |x: f32| json_value(&Value::float(x), SocketType::Float);
        assert_eq!(f(f32::NAN), json!("NaN"));
        assert_eq!(f(-f32::NAN), json!("NaN"));
        assert_eq!(f(f32::INFINITY), json!("inf"));
        assert_eq!(f(f32::NEG_INFINITY), json!("-inf"));
        assert_eq!(f(0.1), json!(0.1));
        assert_eq!(f(-3.0e38), json!(-3.0e38));
        assert_eq!(f(f32::MIN_POSITIVE), json!(1.1754944e-38));
        let v = Value::vec3([f32::NAN, 1.5, f32::NEG_INFINITY]);
        assert_eq!(
            json_value(&v, SocketType::Vec3),
            json!(["NaN", 1.5, "-inf"])
        );
        assert_eq!(
            json_value(&Value::boolean(true), SocketType::Bool),
            json!(true)
        );
        assert_eq!(json_value(&Value::int(-7), SocketType::Int), json!(-7));
    }
}
