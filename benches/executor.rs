//! The batched executor against a hand-written fused Rust function of the same math.
//!
//! Graph: `benches/skin_chain.json`, 20 nodes of Fresnel, Snell and Henyey–Greenstein
//! (a single-scattering skin term with a Phong sheen) over 1M samples. The hand-written
//! version calls the same per-sample functions in one loop: the limit the executor is
//! measured against. The same graph also runs through wgpu (upload, dispatch, read back) on
//! whatever adapter is present. Run with `cargo bench --bench executor`.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use matgraph::gpu::GpuPlan;
use matgraph::nodes::math::safe_pow;
use matgraph::nodes::optics::{fresnel_dielectric, hg_phase, reflect, refract};
use matgraph::{Attribute, Graph, Plan, PlanOptions, Registry, SampleBatch};
use rayon::prelude::*;
use std::hint::black_box;

/// Samples per evaluation.
const N: usize = 1 << 20;

/// The graph's math, fused by hand over planar columns: samples `start..start + out.len()`.
/// Columns are re-sliced to the chunk first so the loop has no bounds checks.
fn fused(n: &[f32], v: &[f32], l: &[f32], out: &mut [f32], len: usize, start: usize) {
    let m = out.len();
    fn column(c: &[f32], k: usize, len: usize, start: usize, m: usize) -> &[f32] {
        &c[k * len + start..k * len + start + m]
    }
    let col = |c, k| column(c, k, len, start, m);
    let (nx, ny, nz) = (col(n, 0), col(n, 1), col(n, 2));
    let (vx, vy, vz) = (col(v, 0), col(v, 1), col(v, 2));
    let (lx, ly, lz) = (col(l, 0), col(l, 1), col(l, 2));
    for i in 0..m {
        let normal = Vec3::new(nx[i], ny[i], nz[i]);
        let view = Vec3::new(vx[i], vy[i], vz[i]);
        let light = Vec3::new(lx[i], ly[i], lz[i]);
        out[i] = shade(normal, view, light);
    }
}

/// One sample of the benchmark graph.
#[inline(always)]
fn shade(normal: Vec3, view: Vec3, light: Vec3) -> f32 {
    let eta = 1.0 / 1.4;
    let cos_v = normal.dot(view);
    let cos_l = normal.dot(light);
    let (_, kt_v) = fresnel_dielectric(cos_v, 1.0, 1.4);
    let (_, kt_l) = fresnel_dielectric(cos_l, 1.0, 1.4);
    let (t_v, _) = refract(view * -1.0, normal, eta);
    let (t_l, _) = refract(light * -1.0, normal, eta);
    let cos_s = t_v.dot(t_l);
    let phase = hg_phase(cos_s, 0.8);
    let single = phase * (kt_v * kt_l);
    let r = reflect(light * -1.0, normal);
    let sheen = safe_pow(r.dot(view).clamp(0.0, 1.0), 32.0);
    single + sheen * 0.3
}

fn inputs() -> SampleBatch {
    let mut b = SampleBatch::new(N);
    let mut normals = Vec::with_capacity(N);
    let mut views = Vec::with_capacity(N);
    let mut lights = Vec::with_capacity(N);
    for i in 0..N {
        let t = i as f32 / N as f32;
        let a = t * 1.5;
        let c = t * 97.0;
        normals.push(
            Vec3::new(0.1 * c.sin(), 0.1 * c.cos(), 1.0)
                .normalize()
                .to_array(),
        );
        views.push([a.sin(), 0.0, a.cos()]);
        lights.push(
            Vec3::new(-0.3, 0.4 * (c * 0.3).sin(), 0.8)
                .normalize()
                .to_array(),
        );
    }
    b.set_values(Attribute::Normal, &normals).unwrap();
    b.set_values(Attribute::View, &views).unwrap();
    b.set_values(Attribute::Light, &lights).unwrap();
    b
}

fn bench(c: &mut Criterion) {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/benches/skin_chain.json"
    ))
    .unwrap();
    let graph = Graph::from_json(&text, Registry::builtin()).unwrap();
    let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
    let params = plan.default_parameters();
    let batch = inputs();

    // The executor and the hand-written function must agree before they are timed.
    let out = plan.execute(&batch, &params).unwrap();
    let (n, v, l) = (
        batch.column(Attribute::Normal).unwrap(),
        batch.column(Attribute::View).unwrap(),
        batch.column(Attribute::Light).unwrap(),
    );
    let mut reference = vec![0.0; N];
    fused(n, v, l, &mut reference, N, 0);
    let worst = out
        .planar(0)
        .iter()
        .zip(&reference)
        .map(|(a, b)| (a - b).abs() / b.abs().max(1.0))
        .fold(0.0, f32::max);
    assert!(worst < 1e-5, "executor and hand-written differ by {worst}");

    let threads_all = rayon::current_num_threads();
    let mut group = c.benchmark_group("skin_chain_1M");
    group.throughput(Throughput::Elements(N as u64));
    group.sample_size(10);
    for threads in [1, threads_all] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        group.bench_with_input(BenchmarkId::new("executor", threads), &threads, |bch, _| {
            bch.iter(|| pool.install(|| black_box(plan.execute(&batch, &params).unwrap())))
        });
        group.bench_with_input(
            BenchmarkId::new("hand_written", threads),
            &threads,
            |bch, _| {
                bch.iter(|| {
                    pool.install(|| {
                        let mut out = vec![0.0f32; N];
                        out.par_chunks_mut(256)
                            .enumerate()
                            .for_each(|(t, chunk)| fused(n, v, l, chunk, N, t * 256));
                        black_box(out)
                    })
                })
            },
        );
    }
    group.finish();

    // The same graph through wgpu: upload, dispatch and read back, end to end.
    let mut gpu_group = c.benchmark_group("skin_chain_1M_gpu");
    gpu_group.throughput(Throughput::Elements(N as u64));
    gpu_group.sample_size(10);
    match matgraph::gpu::GpuContext::shared()
        .and_then(|ctx| GpuPlan::compile(ctx, &graph, &PlanOptions::default()).map(|p| (ctx, p)))
    {
        Ok((ctx, gpu)) => {
            let got = gpu.execute(&batch, &params).unwrap();
            let worst = got
                .planar(0)
                .iter()
                .zip(out.planar(0))
                .map(|(a, b)| (a - b).abs() / b.abs().max(1.0))
                .fold(0.0, f32::max);
            assert!(worst < 1e-4, "GPU and CPU differ by {worst}");
            let name = ctx.adapter_info().name.replace([' ', '(', ')', ','], "_");
            gpu_group.bench_function(BenchmarkId::new("wgpu", name), |bch| {
                bch.iter(|| black_box(gpu.execute(&batch, &params).unwrap()))
            });
        }
        Err(e) => eprintln!("SKIPPED GPU benchmark: {e}"),
    }
    gpu_group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
