//! Evaluate a graph over a batch on the GPU and check it against the CPU plan: a few samples
//! side by side and the largest difference per output. Without a GPU adapter it says so and
//! evaluates on the CPU only.
//!
//! Run: `cargo run --release --example gpu_eval [GRAPH]` (default `graphs/fresnel_glass.json`).
//! Any wgpu adapter works, software ones included (Mesa's lavapipe); `WGPU_BACKEND=vulkan`
//! or `gl` restricts the backends tried.

use matgraph::gpu::{GpuContext, GpuPlan};
use matgraph::{Attribute, Plan, PlanOptions, Registry, SampleBatch};
use std::error::Error;
use std::path::PathBuf;
use std::time::Instant;

fn main() -> Result<(), Box<dyn Error>> {
    let path = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/graphs/fresnel_glass.json"
            ))
        });
    let graph = matgraph::io::load_graph(&path, Registry::builtin())?;
    let options = PlanOptions::default();
    let cpu = Plan::compile(&graph, &options)?;
    let params = cpu.default_parameters();

    // 256 × 256 view directions over the hemisphere above a +z normal.
    let side = 256;
    let views: Vec<[f32; 3]> = (0..side * side)
        .map(|i| {
            let theta = ((i / side) as f32 + 0.5) / side as f32 * std::f32::consts::FRAC_PI_2;
            let phi = (i % side) as f32 / side as f32 * std::f32::consts::TAU;
            [
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            ]
        })
        .collect();
    let mut batch = SampleBatch::new(views.len());
    batch.set_values(Attribute::View, &views)?;

    let start = Instant::now();
    let want = cpu.execute(&batch, &params)?;
    println!("CPU: {} samples in {:.2?}", batch.len(), start.elapsed());

    let ctx = match GpuContext::shared() {
        Ok(ctx) => ctx,
        Err(e) => {
            println!("{e}; falling back to the CPU result only");
            for k in 0..want.names().len() {
                println!("  {} at sample 0: {:?}", want.names()[k], want.value(k, 0));
            }
            return Ok(());
        }
    };
    println!("GPU adapter: {}", ctx.describe());
    let start = Instant::now();
    let gpu = GpuPlan::compile(ctx, &graph, &options)?;
    println!("GPU pipeline compiled in {:.2?}", start.elapsed());
    let start = Instant::now();
    let got = gpu.execute(&batch, &params)?;
    println!(
        "GPU: {} samples in {:.2?} (upload, dispatch, readback)",
        batch.len(),
        start.elapsed()
    );

    for k in 0..want.names().len() {
        let name = &want.names()[k];
        println!("\n{name} ({}):", want.ty(k));
        println!(
            "  {:>6}  {:>8}  {:>36}  {:>36}",
            "sample", "θ (deg)", "CPU", "GPU"
        );
        for i in [0, side * side / 4, side * side / 2, side * side - 1] {
            let theta = ((i / side) as f32 + 0.5) / side as f32 * 90.0;
            println!(
                "  {i:>6}  {theta:>8.2}  {:>36}  {:>36}",
                format!("{:?}", want.value(k, i).lanes()),
                format!("{:?}", got.value(k, i).lanes())
            );
        }
        let max = want
            .planar(k)
            .iter()
            .zip(got.planar(k))
            .map(|(a, b)| {
                if a.is_nan() && b.is_nan() {
                    0.0
                } else {
                    (a - b).abs()
                }
            })
            .fold(0.0f32, f32::max);
        println!(
            "  max |CPU − GPU| over {} values: {max:e}",
            want.planar(k).len()
        );
    }
    Ok(())
}
