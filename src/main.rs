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
    /// Render graphs in a scene (material ball or water) to PNG, on the CPU or the GPU.
    Render(RenderArgs),
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
        Command::Render(args) => render(&args),
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

/// Options of `matgraph render`.
#[derive(clap::Args)]
#[command(
    after_help = "With several graphs, -o OUT.png writes one labelled contact sheet; --out-dir writes \
    one PNG per graph (named after the file) plus contact_sheet.png. Without either, --out-dir renders.\n\
    A graph's `color` output is lit (evaluated per light and summed); `emission` is added once; `alpha` \
    blends over the background; `displacement` (vec3) moves the surface. A graph without `color` or \
    `emission` shows its first output unlit."
)]
struct RenderArgs {
    /// Graph files.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Output PNG (one graph), or the contact sheet of several.
    #[arg(short = 'o', long = "out", conflicts_with = "out_dir")]
    out: Option<PathBuf>,
    /// Folder for one PNG per graph and a contact sheet.
    #[arg(long)]
    out_dir: Option<PathBuf>,
    /// Image size, WxH.
    #[arg(long, default_value = "512x512", value_parser = parse_size)]
    size: (u32, u32),
    /// Scene: a preset (ball, water) or a scene JSON file; default: the graph's own scene,
    /// else ball.
    #[arg(long)]
    scene: Option<String>,
    /// Scene time in seconds (the scene's own time by default).
    #[arg(long)]
    time: Option<f32>,
    /// Samples per pixel (stratified, box-filtered).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=64))]
    samples: u32,
    /// Evaluate the material on the GPU (wgpu; any adapter, lavapipe included).
    #[arg(long, conflicts_with = "cpu")]
    gpu: bool,
    /// Evaluate the material on the CPU (the default).
    #[arg(long)]
    cpu: bool,
    /// Also write the linear HDR image as OpenEXR next to each PNG.
    #[arg(long)]
    exr: bool,
    /// Exposure in stops applied before tone mapping.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    exposure: f32,
    /// Override a parameter: NAME=VALUE.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    sets: Vec<String>,
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or("expected WxH, for example 512x512")?;
    let parse = |v: &str| v.trim().parse::<u32>().map_err(|e| format!("'{v}': {e}"));
    let (w, h) = (parse(w)?, parse(h)?);
    if w == 0 || h == 0 || w > 16384 || h > 16384 {
        return Err(format!("{w}x{h}: each side must be 1 to 16384"));
    }
    Ok((w, h))
}

/// Loads the scene named by `--scene`: a preset name or a scene file.
fn load_scene(spec: &str) -> Result<matgraph::scene::Scene, String> {
    if let Some(scene) = matgraph::scene::Scene::preset(spec) {
        return Ok(scene);
    }
    let path = Path::new(spec);
    if !path.exists() {
        return Err(format!(
            "--scene {spec}: not a preset ({}) nor a file",
            matgraph::scene::SCENE_PRESETS.join(", ")
        ));
    }
    let text = std::fs::read_to_string(path).map_err(|e| format!("{spec}: cannot read: {e}"))?;
    matgraph::scene::Scene::from_json(&text).map_err(|e| format!("{spec}: {e}"))
}

/// The image of an image environment, loaded relative to `base` (the file the scene was
/// written in); `None` for a sky.
fn environment_image(
    scene: &matgraph::scene::Scene,
    base: &Path,
) -> Result<Option<std::sync::Arc<matgraph::texture::Texture>>, String> {
    let matgraph::scene::Environment::Image(img) = &scene.environment else {
        return Ok(None);
    };
    let path = matgraph::image_io::resolve_relative(base, Path::new(&img.path));
    let texture = matgraph::image_io::load_texture(&[path], false)
        .map_err(|e| format!("environment: {e}"))?;
    Ok(Some(std::sync::Arc::new(texture)))
}

/// A progress spinner on stderr that appears only once the work has taken a second.
fn delayed_progress() -> indicatif::ProgressBar {
    let bar =
        indicatif::ProgressBar::with_draw_target(None, indicatif::ProgressDrawTarget::hidden());
    bar.set_style(
        indicatif::ProgressStyle::with_template("{spinner} [{elapsed}] {pos}/{len} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
    );
    let shown = bar.clone();
    std::thread::spawn(move || {
        std::thread::sleep(std::time::Duration::from_secs(1));
        if !shown.is_finished() {
            shown.set_draw_target(indicatif::ProgressDrawTarget::stderr());
            shown.enable_steady_tick(std::time::Duration::from_millis(120));
        }
    });
    bar
}

fn render(args: &RenderArgs) -> CliResult {
    use matgraph::render::{RenderOptions, render_timed, sheet};
    let forced = args.scene.as_deref().map(load_scene).transpose()?;
    let mut parameters = Vec::new();
    for s in &args.sets {
        let (name, json) = split_set(s)?;
        let v = Value::infer_json(&json).ok_or_else(|| {
            format!("--set {s}: expected a number, an array of 2-4 numbers or a bool")
        })?;
        parameters.push((name.to_owned(), v));
    }
    let (out_dir, sheet_path) = match (&args.out, &args.out_dir) {
        // One graph: its image; several: their contact sheet.
        (Some(o), _) => (None, Some(o.clone())),
        (None, Some(d)) => (
            Some(d.clone()),
            (args.files.len() > 1).then(|| d.join("contact_sheet.png")),
        ),
        (None, None) => {
            let d = PathBuf::from("renders");
            (
                Some(d.clone()),
                (args.files.len() > 1).then(|| d.join("contact_sheet.png")),
            )
        }
    };
    if let Some(d) = &out_dir {
        std::fs::create_dir_all(d).map_err(|e| format!("{}: {e}", d.display()))?;
    }
    let backend = if args.gpu {
        matgraph::gpu::Backend::Gpu
    } else {
        matgraph::gpu::Backend::Cpu
    };
    let progress = delayed_progress();
    progress.set_length(args.files.len() as u64);
    let mut tiles = Vec::new();
    let mut failures = Vec::new();
    for file in &args.files {
        progress.set_message(file.display().to_string());
        let result = (|| -> Result<(String, sheet::Rgb8Image), String> {
            let graph = matgraph::io::load_graph(file, registry()).map_err(|e| e.to_string())?;
            let textures = matgraph::image_io::load_graph_textures(&graph, file)
                .map_err(|e| format!("{}: {e}", file.display()))?;
            // Paths inside a scene (an environment image) are relative to where it was written.
            let scene_base = match (&args.scene, &graph.scene) {
                (Some(spec), _) => PathBuf::from(spec),
                (None, Some(serde_json::Value::String(name))) => {
                    matgraph::image_io::resolve_relative(file, Path::new(name))
                }
                _ => file.clone(),
            };
            let scene = match (&forced, &graph.scene) {
                (Some(s), _) => s.clone(),
                (None, Some(serde_json::Value::String(name)))
                    if matgraph::scene::Scene::preset(name).is_none() =>
                {
                    // A scene file, relative to the graph file.
                    load_scene(&scene_base.display().to_string())
                        .map_err(|e| format!("{}: scene: {e}", file.display()))?
                }
                (None, _) => matgraph::render::graph_scene(&graph)
                    .map_err(|e| format!("{}: scene: {e}", file.display()))?
                    .unwrap_or_else(|| {
                        matgraph::scene::Scene::preset("ball").expect("the ball preset exists")
                    }),
            };
            let options = RenderOptions {
                width: args.size.0,
                height: args.size.1,
                samples: args.samples,
                time: args.time,
                backend,
                parameters: parameters.clone(),
                textures: Some(std::sync::Arc::new(textures)),
                environment: environment_image(&scene, &scene_base)
                    .map_err(|e| format!("{}: {e}", file.display()))?,
            };
            let start = std::time::Instant::now();
            let (hdr, _) = render_timed(&graph, &scene, &options)
                .map_err(|e| format!("{}: {e}", file.display()))?;
            let elapsed = start.elapsed();
            let image = hdr.to_srgb8(args.exposure);
            let stem = file
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or("graph")
                .to_owned();
            let single = if args.files.len() == 1 {
                sheet_path.clone()
            } else {
                None
            };
            let target = single.or_else(|| out_dir.as_ref().map(|d| d.join(format!("{stem}.png"))));
            if let Some(png) = &target {
                matgraph::image_io::save_png_rgb8(png, image.width, image.height, &image.pixels)
                    .map_err(|e| e.to_string())?;
                if args.exr {
                    let exr = png.with_extension("exr");
                    let data = hdr.pixels.iter().map(|c| [c[0], c[1], c[2], 1.0]).collect();
                    let img = matgraph::texture::Image::new(hdr.width, hdr.height, data)
                        .map_err(|e| e.to_string())?;
                    matgraph::image_io::save_exr(&exr, &img).map_err(|e| e.to_string())?;
                }
                progress.suspend(|| {
                    println!(
                        "{} -> {} ({}x{}, {} spp, {}, {:.2} s)",
                        file.display(),
                        png.display(),
                        image.width,
                        image.height,
                        args.samples,
                        if args.gpu { "gpu" } else { "cpu" },
                        elapsed.as_secs_f64()
                    )
                });
            }
            Ok((graph.name.clone(), image))
        })();
        match result {
            Ok(tile) => tiles.push(tile),
            Err(e) => {
                progress.suspend(|| eprintln!("{e}"));
                failures.push(file.display().to_string());
            }
        }
        progress.inc(1);
    }
    progress.finish_and_clear();
    if args.files.len() > 1
        && let Some(path) = &sheet_path
        && !tiles.is_empty()
    {
        let sheet = sheet::contact_sheet(&tiles);
        matgraph::image_io::save_png_rgb8(path, sheet.width, sheet.height, &sheet.pixels)
            .map_err(|e| e.to_string())?;
        println!(
            "contact sheet of {} graphs -> {}",
            tiles.len(),
            path.display()
        );
    }
    if failures.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{} of {} graphs failed",
            failures.len(),
            args.files.len()
        ))
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
