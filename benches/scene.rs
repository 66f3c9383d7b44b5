//! The geometry side of rendering (`matgraph::scene`): the G-buffer and the scene textures of
//! the two preset scenes at 1024 × 1024, one sample per pixel, and the displacement of the
//! water grid (256 × 256 cells) with its normals recomputed. Run with
//! `cargo bench --bench scene`; `RAYON_NUM_THREADS=2` for the two-core figure.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::Vec3;
use matgraph::scene::Scene;
use std::hint::black_box;

/// Image side in pixels.
const SIZE: u32 = 1024;

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("scene");
    group.sample_size(10);
    for name in ["ball", "water"] {
        let scene = Scene::preset(name).expect("preset");
        let mesh = scene.material_mesh();
        group.bench_with_input(
            BenchmarkId::new("gbuffer_1024_spp1", name),
            &mesh,
            |b, m| b.iter(|| black_box(scene.gbuffer(m, SIZE, SIZE, 1))),
        );
        group.bench_function(BenchmarkId::new("scene_textures_1024", name), |b| {
            b.iter(|| black_box(scene.scene_textures(SIZE, SIZE)))
        });
    }
    let water = Scene::preset("water").expect("preset").material_mesh();
    let offsets: Vec<Vec3> = water
        .positions
        .iter()
        .map(|p| Vec3::new(0.0, 0.3 * (0.8 * p.x + 0.5 * p.z).sin(), 0.0))
        .collect();
    group.bench_function("displace_water_grid", |b| {
        b.iter(|| black_box(water.displaced(&offsets)))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
