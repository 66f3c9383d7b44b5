//! A split WGSL material function (large graphs: part functions sharing values through the
//! state arrays) computes on the GPU what the closed forms give: a chain adds 1 per node to
//! `c = normal·view`, a fan-in tree doubles `c + 1` per level (see `examples/scale.rs`).
//! Skips with a `SKIPPED:` line without an adapter, unless `MATGRAPH_REQUIRE_GPU` is set.

use crate::common;

#[path = "../../examples/scale.rs"]
#[allow(dead_code)]
mod scale;

use matgraph::exec::{Evaluator, SampleBatch};
use matgraph::gpu::GpuPlan;
use matgraph::node::Attribute;
use matgraph::{Graph, PlanOptions, Registry};

/// Seeded unit vectors and round ones.
fn directions(count: usize, seed: u64) -> Vec<[f32; 3]> {
    let mut state = seed;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut v = vec![[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]];
    while v.len() < count {
        let d = [next(), next(), next()];
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt().max(1e-3);
        v.push(d.map(|x| (x / l) as f32));
    }
    v
}

fn check(test: &str, text: &str, want: impl Fn(f64) -> f64, tolerance: f64) {
    let Some(ctx) = common::gpu_context(test) else {
        return;
    };
    let graph = Graph::from_json(text, Registry::builtin()).unwrap();
    let gpu = GpuPlan::compile(ctx, &graph, &PlanOptions::default()).unwrap();
    assert!(
        gpu.shader().source.contains("fn mg_part_0("),
        "the module is split"
    );
    let count = 64;
    let (normals, views) = (directions(count, 1), directions(count, 2));
    let mut batch = SampleBatch::new(count);
    batch.set_values(Attribute::Normal, &normals).unwrap();
    batch.set_values(Attribute::View, &views).unwrap();
    let out = gpu.evaluate(&batch, &gpu.default_parameters()).unwrap();
    for i in 0..count {
        let c: f64 = (0..3)
            .map(|k| normals[i][k] as f64 * views[i][k] as f64)
            .sum();
        let got = out.value(0, i).as_f32() as f64;
        let w = want(c);
        assert!((got - w).abs() <= tolerance, "sample {i}: {got} vs {w}");
    }
}

#[test]
fn a_split_chain_runs_on_the_gpu() {
    let n = 3_000;
    check(
        "a_split_chain_runs_on_the_gpu",
        &scale::chain(n),
        |c| c + n as f64,
        1e-3,
    );
}

#[test]
fn a_split_fan_in_tree_runs_on_the_gpu() {
    let (text, depth) = scale::fan_in_depth(3_000);
    let s = (1u64 << depth) as f64;
    check(
        "a_split_fan_in_tree_runs_on_the_gpu",
        &text,
        |c| (c + 1.0) * s,
        1e-5 * s,
    );
}

/// Issue 37: past 256 outputs the module holds them in chunk structs, each built and
/// stored by a function of its own. 600 outputs over 3 nodes (one material function, a
/// value returned many times bound once) and over 300 (a split one, its chunks read from
/// the state): every output on the GPU is the CPU plan's, `uv + k` or the uv itself.
#[test]
fn many_outputs_in_chunks_run_on_the_gpu() {
    let Some(ctx) = common::gpu_context("many_outputs_in_chunks_run_on_the_gpu") else {
        return;
    };
    for nodes in [3, 300] {
        let adds: Vec<String> = (0..nodes)
            .map(|k| {
                format!(
                    r#"{{"id":"a{k}","type":"add","inputs":{{"a":{{"link":"geo.uv"}},"b":{k}.0}}}}"#
                )
            })
            .collect();
        let outputs: Vec<String> = (0..600)
            .map(|j| match j % 2 {
                0 => format!(r#"{{"name":"o{j}","from":"a{}.result"}}"#, j % nodes),
                _ => format!(r#"{{"name":"o{j}","from":"geo.uv"}}"#),
            })
            .collect();
        let text = format!(
            r#"{{"version":1,"name":"many","nodes":[{{"id":"geo","type":"geometry"}},{}],"outputs":[{}]}}"#,
            adds.join(","),
            outputs.join(",")
        );
        let graph = Graph::from_json(&text, Registry::builtin()).unwrap();
        let gpu = GpuPlan::compile(ctx, &graph, &PlanOptions::default()).unwrap();
        assert!(
            gpu.shader().source.contains("struct MgOutputs2 {"),
            "chunked"
        );
        let count = 70;
        let uvs: Vec<[f32; 3]> = (0..count)
            .map(|i| [i as f32 * 0.013 - 0.4, 0.25 + i as f32 * 0.007, 0.0])
            .collect();
        let mut batch = SampleBatch::new(count);
        batch.set_values(Attribute::Uv, &uvs).unwrap();
        let out = gpu.evaluate(&batch, &gpu.default_parameters()).unwrap();
        for j in (0..600).step_by(7) {
            let k = out.index(&format!("o{j}")).unwrap();
            for (i, uv) in uvs.iter().enumerate() {
                let add = if j % 2 == 0 { (j % nodes) as f32 } else { 0.0 };
                let want = [uv[0] + add, uv[1] + add];
                let got = out.value(k, i).lanes().to_vec();
                assert_eq!(&got[..2], &want[..], "{nodes} nodes, o{j}, sample {i}");
            }
        }
    }
}
