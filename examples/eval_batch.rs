//! Evaluate a graph over a batch of samples from Rust: Fresnel reflectance of glass over the
//! angle of incidence, for two parameter values, without recompiling.
//!
//! Run: `cargo run --release --example eval_batch [GRAPH]` (default `graphs/fresnel_glass.json`).

use matgraph::{Attribute, Plan, PlanOptions, Registry, SampleBatch, Value};
use std::error::Error;
use std::path::PathBuf;

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
    let plan = Plan::compile(
        &graph,
        &PlanOptions {
            outputs: vec!["reflectance".into()],
            ..Default::default()
        },
    )?;

    // One sample per tenth of a degree, 0° to 90°.
    let n = 901;
    let views: Vec<[f32; 3]> = (0..n)
        .map(|i| {
            let theta = (i as f32 * 0.1).to_radians();
            [theta.sin(), 0.0, theta.cos()]
        })
        .collect();
    let mut batch = SampleBatch::new(n);
    batch.set_values(Attribute::View, &views)?;

    println!("angle  R(glass 1.52)  R(diamond 2.42)");
    let mut params = plan.default_parameters();
    let glass = plan.execute(&batch, &params)?;
    params.set("ior", Value::float(2.42))?; // a uniform: no recompile
    let diamond = plan.execute(&batch, &params)?;
    for i in (0..n).step_by(100).chain([850, 890, 900]) {
        println!(
            "{:5.1}  {:13.6}  {:15.6}",
            i as f32 * 0.1,
            glass.value(0, i).as_f32(),
            diamond.value(0, i).as_f32()
        );
    }
    Ok(())
}
