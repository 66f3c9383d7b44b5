//! The before/after table of docs/specialise.md: every bundled graph, full and specialised
//! for its own scene (exact rewrites), with nodes, per-sample steps, WGSL bytes, naga's
//! expression count, CPU and GPU time per frame and the RMSE between the two renders.
//!
//! ```sh
//! cargo run --release --example specialise_table -- --size 128 --runs 3 [--gpu] [--write]
//! ```
//!
//! `--write` replaces the table between the `<!-- table -->` markers of docs/specialise.md;
//! otherwise it is printed.

use matgraph::gpu::Backend;
use matgraph::plan::{Plan, PlanOptions};
use matgraph::render::{HdrImage, RenderOptions, render};
use matgraph::scene::Scene;
use matgraph::specialise::{
    RewriteKind, SceneInfo, SpecialiseOptions, Specialised, for_scene, specialise,
};
use matgraph::wgsl::{Entry, WgslOptions, generate};
use matgraph::{Graph, Registry};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

const BEGIN: &str = "<!-- table -->";
const END: &str = "<!-- /table -->";

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |name: &str, default: u32| -> Result<u32, String> {
        match args.iter().position(|a| a == name) {
            Some(i) => args
                .get(i + 1)
                .and_then(|v| v.parse().ok())
                .ok_or_else(|| format!("{name} takes a number")),
            None => Ok(default),
        }
    };
    let size = value("--size", 128)?;
    let runs = value("--runs", 3)?.max(1);
    let gpu = args.iter().any(|a| a == "--gpu");
    let write = args.iter().any(|a| a == "--write");
    if gpu && let Err(e) = matgraph::gpu::GpuContext::shared() {
        return Err(format!("--gpu: {e}"));
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files: Vec<PathBuf> = std::fs::read_dir(root.join("graphs"))
        .map_err(|e| e.to_string())?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    let mut table = String::new();
    table += &format!(
        "{size}×{size}, 1 sample per pixel, median of {runs} runs; before → after.\n\n\
         | graph | scene | rewrites | live nodes | per-sample steps | WGSL bytes | naga expressions | CPU ms/frame | GPU ms/frame | RMSE CPU | RMSE GPU | steps, parameters baked too |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n"
    );
    for path in &files {
        let g = matgraph::io::load_graph(path, Registry::builtin()).map_err(|e| e.to_string())?;
        let scene = matgraph::render::graph_scene(&g)
            .map_err(|e| e.to_string())?
            .unwrap_or_else(|| Scene::preset("ball").expect("preset"));
        let s = for_scene(&g, &scene, Some(scene.time), false).map_err(|e| e.to_string())?;
        let textures =
            Arc::new(matgraph::image_io::load_graph_textures(&g, path).map_err(|e| e.to_string())?);
        let options = |backend| RenderOptions {
            width: size,
            height: size,
            backend,
            textures: Some(textures.clone()),
            ..RenderOptions::default()
        };
        let (before, after) = (stats(&g)?, stats(&s.graph)?);
        let baked = specialise(
            &g,
            Registry::builtin(),
            &SceneInfo::of(&scene, Some(scene.time)),
            &SpecialiseOptions {
                bake_parameters: Some(Vec::new()),
                approximate: false,
            },
        )
        .map_err(|e| e.to_string())?;
        let baked = stats(&baked.graph)?;
        let (cpu_full, cpu_ms0) = timed(&g, &scene, &options(Backend::Cpu), runs)?;
        let (cpu_fast, cpu_ms1) = timed(&s.graph, &scene, &options(Backend::Cpu), runs)?;
        let (gpu_ms, gpu_rmse) = if gpu {
            let (a, t0) = timed(&g, &scene, &options(Backend::Gpu), runs)?;
            let (b, t1) = timed(&s.graph, &scene, &options(Backend::Gpu), runs)?;
            (
                format!("{t0:.1} → {t1:.1}"),
                format!("{:.1e}", rmse(&a, &b)),
            )
        } else {
            ("–".into(), "–".into())
        };
        let scene_name = match &g.scene {
            Some(serde_json::Value::String(n)) => n.clone(),
            Some(_) => format!("{} (inline)", kind_name(&scene)),
            None => "ball".into(),
        };
        table += &format!(
            "| {} | {} | {} | {} → {} | {} → {} | {} → {} | {} → {} | {cpu_ms0:.1} → {cpu_ms1:.1} | {gpu_ms} | {:.1e} | {gpu_rmse} | {} |\n",
            g.name,
            scene_name,
            summary(&s),
            before.live,
            after.live,
            before.steps,
            after.steps,
            before.bytes,
            after.bytes,
            before.expressions,
            after.expressions,
            rmse(&cpu_full, &cpu_fast),
            baked.steps,
        );
        eprintln!("{}: {}", g.name, summary(&s));
    }
    if write {
        let doc = root.join("docs/specialise.md");
        let text = std::fs::read_to_string(&doc).map_err(|e| format!("{}: {e}", doc.display()))?;
        let (Some(a), Some(b)) = (text.find(BEGIN), text.find(END)) else {
            return Err(format!("{}: no {BEGIN} … {END} markers", doc.display()));
        };
        let out = format!("{}{BEGIN}\n{table}{}", &text[..a], &text[b..]);
        std::fs::write(&doc, out).map_err(|e| format!("{}: {e}", doc.display()))?;
    } else {
        print!("{table}");
    }
    Ok(())
}

fn kind_name(scene: &Scene) -> &'static str {
    match scene.kind {
        matgraph::scene::SceneKind::Ball(_) => "ball",
        matgraph::scene::SceneKind::Water(_) => "water",
        matgraph::scene::SceneKind::Bubble(_) => "bubble",
    }
}

/// The rewrites by kind: `time 1, fold 4, dead 2`.
fn summary(s: &Specialised) -> String {
    let mut by: BTreeMap<RewriteKind, usize> = BTreeMap::new();
    for r in &s.rewrites {
        *by.entry(r.kind).or_default() += 1;
    }
    if by.is_empty() {
        return "none".into();
    }
    by.iter()
        .map(|(k, n)| format!("{} {n}", k.name()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Sizes of one build.
struct Stats {
    live: usize,
    steps: usize,
    bytes: usize,
    expressions: usize,
}

fn stats(g: &Graph) -> Result<Stats, String> {
    let plan = Plan::compile(g, &PlanOptions::default()).map_err(|e| e.to_string())?;
    let m = generate(
        g,
        &WgslOptions {
            entry: Entry::Compute,
            ..Default::default()
        },
    )
    .map_err(|e| e.to_string())?;
    let expressions = m
        .module
        .functions
        .iter()
        .map(|(_, f)| f.expressions.len())
        .chain(
            m.module
                .entry_points
                .iter()
                .map(|e| e.function.expressions.len()),
        )
        .sum();
    Ok(Stats {
        live: plan.stats().live_nodes,
        steps: plan.stats().per_sample_steps,
        bytes: m.source.len(),
        expressions,
    })
}

/// Renders `runs` times; the last image and the median milliseconds.
fn timed(
    g: &Graph,
    scene: &Scene,
    options: &RenderOptions,
    runs: u32,
) -> Result<(HdrImage, f64), String> {
    let mut times = Vec::new();
    let mut image = None;
    // One warm-up render (pipeline caches, thread pool) that is not counted.
    render(g, scene, options).map_err(|e| e.to_string())?;
    for _ in 0..runs {
        let start = Instant::now();
        image = Some(render(g, scene, options).map_err(|e| e.to_string())?);
        times.push(start.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    Ok((image.expect("runs ≥ 1"), times[times.len() / 2]))
}

fn rmse(a: &HdrImage, b: &HdrImage) -> f64 {
    let mut d2 = 0.0f64;
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for c in 0..3 {
            d2 += (p[c] as f64 - q[c] as f64).powi(2);
        }
    }
    (d2 / (a.pixels.len() * 3).max(1) as f64).sqrt()
}
