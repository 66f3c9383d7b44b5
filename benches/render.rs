//! A 1024 × 1024 render of each bundled graph in its scene: CPU on one thread and on all
//! threads, and the material on the GPU (whatever adapter wgpu finds; lavapipe in CI).
//! Run with `cargo bench --bench render`.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use matgraph::gpu::Backend;
use matgraph::render::{RenderOptions, render};
use matgraph::scene::Scene;
use matgraph::{Graph, Registry};
use std::hint::black_box;
use std::sync::Arc;

const SIZE: u32 = 1024;

fn scene_of(graph: &Graph) -> Scene {
    matgraph::render::graph_scene(graph)
        .unwrap()
        .unwrap_or_else(|| Scene::preset("ball").unwrap())
}

fn bench(c: &mut Criterion) {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/graphs");
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let gpu = matgraph::gpu::GpuContext::shared();
    if let Err(e) = &gpu {
        eprintln!("SKIPPED GPU renders: {e}");
    }
    let mut group = c.benchmark_group("render_1024");
    group.sample_size(10);
    for path in files
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
    {
        let graph = matgraph::io::load_graph(path, Registry::builtin()).unwrap();
        let scene = scene_of(&graph);
        let textures = Arc::new(matgraph::image_io::load_graph_textures(&graph, path).unwrap());
        let options = |backend| RenderOptions {
            width: SIZE,
            height: SIZE,
            backend,
            textures: Some(textures.clone()),
            ..RenderOptions::default()
        };
        let all = rayon::current_num_threads();
        for threads in [1, all] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let id = BenchmarkId::new(format!("cpu_{threads}_threads"), &graph.name);
            let o = options(Backend::Cpu);
            group.bench_function(id, |b| {
                b.iter(|| pool.install(|| black_box(render(&graph, &scene, &o).unwrap())))
            });
        }
        if gpu.is_ok() {
            let o = options(Backend::Gpu);
            group.bench_function(BenchmarkId::new("gpu", &graph.name), |b| {
                b.iter(|| black_box(render(&graph, &scene, &o).unwrap()))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
