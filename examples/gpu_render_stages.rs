//! Times `render` of every bundled graph at 1024² on the three paths: the CPU renderer on
//! 2 threads, the hybrid path (CPU rasteriser, GPU compute shading: `--gpu-compute`) and the
//! GPU rasteriser (`--gpu`, per stage: compile, upload, draw, readback). Prints a Markdown
//! table (best of `--runs`, default 3, and the GPU's first frame) for docs/benchmarks.md.
//!
//! `cargo run --release --example gpu_render_stages [-- --size 1024 --runs 3 --graphs a,b]`
//! (`--graphs`: only the bundled graphs of those names).

#[path = "common/bundled.rs"]
mod bundled;

use matgraph::gpu::Backend;
use matgraph::render::{RenderOptions, RenderTimings, render_timed};
use std::time::{Duration, Instant};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let arg = |name: &str, default: u32| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    let (size, runs) = (arg("--size", 1024), arg("--runs", 3).max(1));
    let only: Option<Vec<String>> = args
        .iter()
        .position(|a| a == "--graphs")
        .and_then(|i| args.get(i + 1))
        .map(|v| v.split(',').map(str::to_owned).collect());
    let ctx = matgraph::gpu::GpuContext::shared().expect("a GPU adapter");
    println!(
        "{size}² at 1 spp on {}; best of {runs}; times in ms\n",
        ctx.describe()
    );
    println!(
        "| graph | CPU, 2 threads | hybrid (`--gpu-compute`) | GPU, first frame | GPU total | compile | upload | draw | readback |"
    );
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let files = bundled::graph_files(only.as_deref());
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    for path in files {
        let (graph, scene, textures) = bundled::load(&path);
        let options = |backend| RenderOptions {
            width: size,
            height: size,
            backend,
            textures: Some(textures.clone()),
            ..RenderOptions::default()
        };
        // (first run, best run): a first frame makes what later frames reuse (pipelines,
        // scene textures, IBL tables, the packed scene).
        let runs_of = |backend: Backend, in_pool: bool| -> (Duration, (Duration, RenderTimings)) {
            let o = options(backend);
            let all: Vec<(Duration, RenderTimings)> = (0..runs)
                .map(|_| {
                    let start = Instant::now();
                    let (_, t) = if in_pool {
                        pool.install(|| render_timed(&graph, &scene, &o).unwrap())
                    } else {
                        render_timed(&graph, &scene, &o).unwrap()
                    };
                    (start.elapsed(), t)
                })
                .collect();
            let best = all.iter().min_by_key(|(d, _)| *d).unwrap().clone();
            (all[0].0, best)
        };
        let (_, (cpu, _)) = runs_of(Backend::Cpu, true);
        let (_, (hybrid, _)) = runs_of(Backend::GpuCompute, false);
        let (first, (gpu, t)) = runs_of(Backend::Gpu, false);
        println!(
            "| {} | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} |",
            graph.name,
            ms(cpu),
            ms(hybrid),
            ms(first),
            ms(gpu),
            ms(t.compile),
            ms(t.upload),
            ms(t.draw),
            ms(t.readback)
        );
    }
}
