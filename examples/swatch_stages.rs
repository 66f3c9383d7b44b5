//! Times the editor's preview swatch of every bundled graph on the GPU rasteriser, per
//! stage: the scene at the swatch's mesh detail ([`matgraph::editor::preview::swatch_detail`]),
//! 1 spp, as `render_swatch` draws it, then the sRGB conversion. Prints a Markdown table
//! (best of `--runs`, default 12, after one warm-up frame that builds what later frames
//! reuse) for docs/benchmarks.md.
//!
//! With `--draft`, the editor's draft instead: the mesh at
//! [`matgraph::editor::preview::draft_detail`] (run it at `--size 48`, the draft's side).
//! With `--cpu`, on the CPU renderer, as the editor's stand-ins draw a structure the GPU
//! has not compiled (run it with `--draft --size 48`; its stages are then `gbuffer` and
//! `shade`, in the `draw` column).
//! With `--compare`, also the error of the swatch against the same frame at the scene's
//! full mesh detail, in 8-bit sRGB: RMSE and largest difference over the RGB channels.
//!
//! `cargo run --release --example swatch_stages [-- --size 128 --runs 12 --graphs a,b --draft --cpu --compare]`

#[path = "common/bundled.rs"]
mod bundled;

use matgraph::gpu::Backend;
use matgraph::render::{RenderOptions, RenderTimings, render_timed};
use matgraph::scene::Scene;
use std::time::{Duration, Instant};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let arg = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .cloned()
    };
    let size: u32 = arg("--size").and_then(|v| v.parse().ok()).unwrap_or(128);
    let runs: usize = arg("--runs")
        .and_then(|v| v.parse().ok())
        .unwrap_or(12)
        .max(1);
    let only: Option<Vec<String>> =
        arg("--graphs").map(|v| v.split(',').map(str::to_owned).collect());
    let compare = args.iter().any(|a| a == "--compare");
    let draft = args.iter().any(|a| a == "--draft");
    let cpu = args.iter().any(|a| a == "--cpu");
    let (backend, on) = match cpu {
        true => (Backend::Cpu, "the CPU".to_owned()),
        false => {
            let ctx = matgraph::gpu::GpuContext::shared().expect("a GPU adapter");
            (Backend::Gpu, ctx.describe())
        }
    };
    println!(
        "{} {size}² at 1 spp on {on}; best of {runs}; times in ms\n",
        if draft { "draft" } else { "swatch" },
    );
    match compare {
        false => {
            println!("| graph | frame | compile | upload | draw | readback | sRGB |");
            println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: |");
        }
        true => {
            println!(
                "| graph | frame | compile | upload | draw | readback | sRGB | full detail | RMSE /255 | max /255 |"
            );
            println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
        }
    }
    let files = bundled::graph_files(only.as_deref());
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    for path in files {
        let (graph, full, textures) = bundled::load(&path);
        let mut scene = full.clone();
        match draft {
            false => matgraph::editor::preview::swatch_detail(&mut scene, size),
            true => matgraph::editor::preview::draft_detail(&mut scene),
        }
        let options = RenderOptions {
            width: size,
            height: size,
            samples: 1,
            time: Some(0.0),
            backend,
            textures: Some(textures),
            ..RenderOptions::default()
        };
        render_timed(&graph, &scene, &options).unwrap();
        // Best of `runs` frames of `scene`: (frame, its stages, sRGB conversion), the pixels.
        let best_of = |scene: &Scene| {
            let mut best: Option<(Duration, RenderTimings, Duration)> = None;
            let mut pixels = Vec::new();
            for _ in 0..runs {
                let start = Instant::now();
                let (hdr, t) = render_timed(&graph, scene, &options).unwrap();
                let frame = start.elapsed();
                let s = Instant::now();
                pixels = std::hint::black_box(hdr.to_srgb8(1.0)).pixels;
                let srgb = s.elapsed();
                if best.as_ref().is_none_or(|b| frame + srgb < b.0 + b.2) {
                    best = Some((frame, t, srgb));
                }
            }
            (best.unwrap(), pixels)
        };
        let ((frame, t, srgb), pixels) = best_of(&scene);
        let error = compare.then(|| {
            render_timed(&graph, &full, &options).unwrap();
            let ((f, _, s), reference) = best_of(&full);
            let d: Vec<f64> = pixels
                .iter()
                .zip(&reference)
                .flat_map(|(a, b)| (0..3).map(move |c| a[c] as f64 - b[c] as f64))
                .collect();
            let rmse = (d.iter().map(|x| x * x).sum::<f64>() / d.len() as f64).sqrt();
            let max = d.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            format!(" {:.1} | {rmse:.3} | {max:.0} |", ms(f + s))
        });
        println!(
            "| {} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} |{}",
            graph.name,
            ms(frame + srgb),
            ms(t.compile),
            ms(t.upload),
            ms(match cpu {
                true => t.gbuffer + t.shade + t.resolve,
                false => t.draw,
            }),
            ms(t.readback),
            ms(srgb),
            error.unwrap_or_default()
        );
    }
}
