//! `matgraph report`: every family's variants measured against its reference (cost and
//! error), written as a markdown table, JSON data and a speed-against-error plot (SVG, PNG)
//! per family, plus the index `README.md`; and the `--max-error` pick of render, wgsl and
//! eval. The measuring is `matgraph::report`; this file loads graphs and writes files.

use super::{CliResult, graph_textures, path_policy, registry};
use matgraph::io::PathPolicy;
use matgraph::report::family::{FAMILIES, Family, VariantSpec};
use matgraph::report::measure::{
    abs_error, cpu_ns_per_sample, expression_count, image_error, node_samples, radiance,
    radiance_plan,
};
use matgraph::report::{
    FamilyReport, Settings, VariantRow, index as markdown_index, markdown, plot,
};
use matgraph::texture::TextureSet;
use matgraph::{Graph, GraphDocument, GraphErrors};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Seed of the node-space samples of the report.
const SEED: u64 = 0x5eed_f00d;
/// Plot size in pixels.
const PLOT_SIZE: (u32, u32) = (720, 480);
/// Width and height of the frame whose scene textures the node-space samples bind (as
/// `matgraph eval` does).
const SCENE_TEXTURE_FRAME: (u32, u32) = (512, 512);

/// Options of `matgraph report`.
#[derive(clap::Args)]
pub struct Args {
    /// Folder of the report's files. The default keeps a run out of the tracked files;
    /// the published copy is regenerated with `--out docs/report`.
    #[arg(long = "out", default_value = "target/report")]
    pub out: PathBuf,
    /// Folder of the bundled graphs the families name.
    #[arg(long, default_value = "graphs")]
    pub graphs: PathBuf,
    /// Only these families (repeatable; default: all); an existing index README.md, which
    /// lists every family, is then left as it is.
    #[arg(long = "family", value_name = "NAME")]
    pub families: Vec<String>,
    /// Short mode (CI): 32×32 renders, 1024 samples, 2 timing repeats.
    #[arg(long)]
    pub quick: bool,
    /// Do not time: the cost is naga's expression count, and every file is the same on
    /// every run.
    #[arg(long)]
    pub no_timing: bool,
    /// Do not time on the GPU even where an adapter exists.
    #[arg(long)]
    pub no_gpu: bool,
    /// Render size, WxH [default: 192x192; 32x32 with --quick].
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// Node-space samples, 1 to 262144 [default: 16384; 1024 with --quick].
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=super::flags::MAX_REPORT_SAMPLES))]
    pub samples: Option<u64>,
    /// Timing repeats, the best taken, 1 to 1000 [default: 7; 2 with --quick].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=super::flags::MAX_REPORT_REPEATS as i64))]
    pub repeats: Option<u32>,
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or("expected WxH, e.g. 192x192")?;
    let p = |v: &str| v.trim().parse::<u32>().map_err(|e| format!("'{v}': {e}"));
    let (w, h) = (p(w)?, p(h)?);
    if !(1..=4096).contains(&w) || !(1..=4096).contains(&h) {
        return Err(format!("{w}x{h}: each side must be 1 to 4096"));
    }
    Ok((w, h))
}

/// The machine the CPU times are taken on: CPU model, cores, memory (Linux `/proc`).
fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, v)| v.trim().to_owned())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_owned());
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mem = std::fs::read_to_string("/proc/meminfo").ok().and_then(|t| {
        t.lines()
            .find(|l| l.starts_with("MemTotal"))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|kb| kb.parse::<f64>().ok())
    });
    match mem {
        Some(kb) => format!("{cores}-core \"{cpu}\", {:.0} GiB", kb / (1024.0 * 1024.0)),
        None => format!("{cores}-core \"{cpu}\""),
    }
}

/// The GPU adapter, labelled software when it is one (lavapipe, llvmpipe, WARP).
fn gpu_label(ctx: &matgraph::gpu::GpuContext) -> String {
    let info = ctx.adapter_info();
    if info.device_type == wgpu::DeviceType::Cpu {
        format!(
            "{} ({:?}, software rasteriser: not a GPU's speed)",
            info.name, info.backend
        )
    } else {
        format!("{} ({:?})", info.name, info.backend)
    }
}

/// The textures a graph's samples bind: its images and its scene's textures (as
/// `matgraph eval` binds them).
pub fn sample_textures(
    graph: &Graph,
    file: &Path,
    policy: PathPolicy,
) -> Result<Arc<TextureSet>, String> {
    let budget = matgraph::budget::MemoryBudget::default();
    let mut textures = graph_textures(graph, file, policy, &budget)?;
    if matgraph::render::uses_scene_textures(graph) {
        let (scene, environment) = super::scene::resolve(graph, file, None, policy, &budget)?;
        let (w, h) = SCENE_TEXTURE_FRAME;
        let maps =
            matgraph::render::scene_texture_set_within(graph, &scene, w, h, environment, &budget)
                .map_err(|e| format!("{}: {e}", file.display()))?;
        textures
            .extend_shared(&maps)
            .map_err(|e| format!("{}: {e}", file.display()))?;
    }
    Ok(Arc::new(textures))
}

/// `--max-error E` of render, wgsl and eval: re-selects `graph` (loaded from `file` with the
/// `--variant` flags `variants`) with, for each variant set not fixed by a flag, the
/// cheapest choice within `E` (`matgraph::report::pick`), and says on stderr what was
/// picked and why. Without `E`, the graph as it is.
pub fn apply_max_error(
    graph: Graph,
    file: &Path,
    variants: &[String],
    max_error: Option<f64>,
    policy: PathPolicy,
) -> Result<Graph, String> {
    let Some(e) = max_error else {
        return Ok(graph);
    };
    let at = |m: &dyn std::fmt::Display| format!("{}: {m}", file.display());
    let mut selection = variants
        .iter()
        .map(|s| super::split_variant(s))
        .collect::<Result<Vec<_>, _>>()?;
    if graph.variants().is_empty() {
        errln!(
            "{}: --max-error: the graph declares no variants; nothing to pick",
            file.display()
        );
        return Ok(graph);
    }
    let textures = sample_textures(&graph, file, policy)?;
    let picks =
        matgraph::report::pick::pick_variants(&graph, registry(), &selection, e, Some(textures))
            .map_err(|e| at(&e))?;
    for p in &picks {
        errln!("{}: {}", file.display(), p.explain(e));
        selection.push((p.variant.clone(), p.choice.clone()));
    }
    graph.select(registry(), &selection).map_err(|errors| {
        GraphErrors {
            source: file.to_owned(),
            errors,
        }
        .to_string()
    })
}

/// A variant's graph: the family's file with its input overrides applied, then its choices.
fn load_variant(file: &Path, v: &VariantSpec) -> Result<Graph, String> {
    let text = super::read_graph_text(file)?;
    let wrap = |errors| {
        GraphErrors {
            source: file.to_owned(),
            errors,
        }
        .to_string()
    };
    let mut doc = GraphDocument::parse(&text).map_err(wrap)?;
    for (node, input, literal) in v.set {
        let value: serde_json::Value = serde_json::from_str(literal)
            .map_err(|e| format!("{}: {node}.{input} = {literal}: {e}", file.display()))?;
        let n = doc
            .nodes
            .iter_mut()
            .find(|n| n.id == *node)
            .ok_or_else(|| format!("{}: variant {}: no node '{node}'", file.display(), v.name))?;
        n.inputs.insert((*input).to_owned(), value);
    }
    let choices: Vec<(String, String)> = v
        .choices
        .iter()
        .map(|(a, b)| ((*a).to_owned(), (*b).to_owned()))
        .collect();
    let files = matgraph::io::group_files(file, matgraph::io::PathPolicy::InsideGraphFolder);
    Graph::with_variants_in(&doc, registry(), &choices, files).map_err(wrap)
}

/// What one variant measured, before the errors against the reference.
struct Measured {
    spec: VariantSpec,
    expressions: usize,
    cpu_ns: Option<f64>,
    gpu_ms: Option<f64>,
    radiance: Vec<[f32; 3]>,
    image: matgraph::render::HdrImage,
}

/// How the report is measured.
struct Plan {
    size: (u32, u32),
    samples: usize,
    repeats: Option<u32>,
    gpu: Option<&'static matgraph::gpu::GpuContext>,
}

/// Measures one variant.
fn measure(args: &Args, plan: &Plan, v: &VariantSpec) -> Result<Measured, String> {
    use matgraph::gpu::Backend;
    use matgraph::render::{RenderOptions, render_timed};
    let file = args.graphs.join(v.graph);
    let at = |e: &dyn std::fmt::Display| format!("{} (variant {}): {e}", file.display(), v.name);
    let graph = load_variant(&file, v)?;
    let policy = path_policy(false);
    let expressions = expression_count(&graph).map_err(|e| at(&e))?;
    let textures = sample_textures(&graph, &file, policy)?;
    let mut batch = node_samples(plan.samples, SEED);
    let radiance = radiance(&graph, &batch, Some(textures.clone())).map_err(|e| at(&e))?;
    let cpu_ns = match plan.repeats {
        Some(n) => {
            batch.set_textures(textures);
            let p = radiance_plan(&graph).map_err(|e| at(&e))?;
            Some(cpu_ns_per_sample(&p, &batch, n).map_err(|e| at(&e))?)
        }
        None => None,
    };
    let budget = matgraph::budget::MemoryBudget::default();
    let (scene, environment) = super::scene::resolve(&graph, &file, None, policy, &budget)?;
    let images = graph_textures(&graph, &file, policy, &budget)?;
    let mut options = RenderOptions {
        width: plan.size.0,
        height: plan.size.1,
        samples: 1,
        textures: Some(Arc::new(images)),
        environment,
        ..RenderOptions::default()
    };
    let (image, _) = render_timed(&graph, &scene, &options).map_err(|e| at(&e))?;
    let gpu_ms = match (plan.gpu, plan.repeats) {
        (Some(_), Some(n)) => {
            options.backend = Backend::Gpu;
            let mut best = f64::INFINITY;
            for _ in 0..n {
                // The GPU's part of the frame, the pipeline's compilation left out: the
                // passes submitted and waited for, or the shading of the G-buffer where the
                // GPU rasteriser cannot draw the scene (the hybrid path).
                let (_, t) = render_timed(&graph, &scene, &options).map_err(|e| at(&e))?;
                let gpu = if t.fallback.is_none() {
                    t.draw
                } else {
                    t.shade
                };
                best = best.min(gpu.as_secs_f64() * 1e3);
            }
            Some(best)
        }
        _ => None,
    };
    Ok(Measured {
        spec: *v,
        expressions,
        cpu_ns,
        gpu_ms,
        radiance,
        image,
    })
}

/// Measures a family: every variant, then the errors against the reference.
fn family_report(
    args: &Args,
    plan: &Plan,
    f: &Family,
    settings: &Settings,
) -> Result<FamilyReport, String> {
    let mut measured = Vec::new();
    for v in f.variants {
        let m = measure(args, plan, v)?;
        outln!(
            "{}/{}: {} expressions{}{}",
            f.name,
            v.name,
            m.expressions,
            m.cpu_ns
                .map(|t| format!(", {t:.0} ns/sample CPU"))
                .unwrap_or_default(),
            m.gpu_ms
                .map(|t| format!(", {t:.2} ms/frame GPU"))
                .unwrap_or_default()
        )?;
        measured.push(m);
    }
    let reference = measured
        .iter()
        .find(|m| m.spec.name == f.reference)
        .ok_or_else(|| format!("family {}: no reference variant '{}'", f.name, f.reference))?;
    let rows = measured
        .iter()
        .map(|m| {
            let mut selection: Vec<String> = m
                .spec
                .choices
                .iter()
                .map(|(a, b)| format!("{a}={b}"))
                .collect();
            selection.extend(m.spec.set.iter().map(|(n, i, l)| format!("{n}.{i}={l}")));
            Ok(VariantRow {
                name: m.spec.name.to_owned(),
                doc: m.spec.doc.to_owned(),
                graph: m.spec.graph.to_owned(),
                selection,
                reference: m.spec.name == f.reference,
                expressions: m.expressions,
                cpu_ns: m.cpu_ns,
                gpu_ms: m.gpu_ms,
                node: abs_error(&reference.radiance, &m.radiance),
                image: image_error(&reference.image, &m.image)
                    .ok_or_else(|| format!("family {}: renders of different sizes", f.name))?,
                front: false,
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let mut report = FamilyReport {
        name: f.name.to_owned(),
        title: f.title.to_owned(),
        doc: f.doc.to_owned(),
        reference: f.reference.to_owned(),
        settings: settings.clone(),
        rows,
        pending: f
            .pending
            .iter()
            .map(|(a, b)| ((*a).to_owned(), (*b).to_owned()))
            .collect(),
    };
    report.mark_front();
    Ok(report)
}

/// Writes `bytes` to `dir/name`.
fn write(dir: &Path, name: &str, bytes: &[u8]) -> Result<(), String> {
    let path = dir.join(name);
    matgraph::io::write_atomic(&path, bytes).map_err(|e| super::out_dir::write_error(&path, &e))
}

/// Measures the families and writes the report.
pub fn run(args: &Args) -> CliResult {
    for name in &args.families {
        if matgraph::report::family::family(name).is_none() {
            let names: Vec<&str> = FAMILIES.iter().map(|f| f.name).collect();
            return Err(format!(
                "--family {name}: no such family (families: {})",
                names.join(", ")
            ));
        }
    }
    let families: Vec<&Family> = FAMILIES
        .iter()
        .filter(|f| args.families.is_empty() || args.families.iter().any(|n| n == f.name))
        .collect();
    let timed = !args.no_timing;
    let gpu = if timed && !args.no_gpu {
        matgraph::gpu::GpuContext::shared().ok()
    } else {
        None
    };
    let plan = Plan {
        size: args
            .size
            .unwrap_or(if args.quick { (32, 32) } else { (192, 192) }),
        samples: args
            .samples
            .map_or(if args.quick { 1024 } else { 16384 }, |n| n as usize),
        repeats: timed.then(|| args.repeats.unwrap_or(if args.quick { 2 } else { 7 })),
        gpu,
    };
    let settings = Settings {
        width: plan.size.0,
        height: plan.size.1,
        samples: plan.samples,
        seed: SEED,
        repeats: plan.repeats,
        machine: timed.then(machine),
        gpu: gpu.map(gpu_label),
    };
    // Nothing is written over a graph the families read, nor twice.
    let mut files = super::outputs::Files::default();
    for f in &families {
        for v in f.variants {
            let graph = args.graphs.join(v.graph);
            files.input(&graph, format!("the graph {}", graph.display()))?;
        }
    }
    let index = args.families.is_empty() || !args.out.join("README.md").exists();
    for f in &families {
        for ext in ["md", "json", "svg", "png"] {
            let path = args.out.join(format!("{}.{ext}", f.name));
            files.output(&path, format!("report file {}", path.display()))?;
        }
    }
    if index {
        let path = args.out.join("README.md");
        files.output(&path, format!("report index {}", path.display()))?;
    }
    super::out_dir::make_out_dir("--out", &args.out)?;
    let mut reports = Vec::new();
    for f in families {
        let r = family_report(args, &plan, f, &settings)?;
        let spec = r.plot_spec();
        let svg = plot::svg(&spec, PLOT_SIZE.0, PLOT_SIZE.1).map_err(|e| e.to_string())?;
        let rgb = plot::rgb(&spec, PLOT_SIZE.0, PLOT_SIZE.1).map_err(|e| e.to_string())?;
        write(
            &args.out,
            &format!("{}.md", r.name),
            markdown(&r).as_bytes(),
        )?;
        let json = serde_json::to_string_pretty(&r).map_err(|e| e.to_string())? + "\n";
        write(&args.out, &format!("{}.json", r.name), json.as_bytes())?;
        write(&args.out, &format!("{}.svg", r.name), svg.as_bytes())?;
        let png = args.out.join(format!("{}.png", r.name));
        let rgb: Vec<[u8; 3]> = rgb.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        matgraph::image_io::save_rgb8(&png, PLOT_SIZE.0, PLOT_SIZE.1, &rgb)
            .map_err(|e| e.to_string())?;
        outln!(
            "{} -> {}/{}.md, .json, .svg, .png",
            r.name,
            args.out.display(),
            r.name
        )?;
        reports.push(r);
    }
    if index {
        write(&args.out, "README.md", markdown_index(&reports).as_bytes())?;
    }
    Ok(())
}
