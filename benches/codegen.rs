//! WGSL generation plus naga parsing and validation, per bundled graph and for synthetic
//! graphs of 100, 1,000 and 5,000 nodes. Run with `cargo bench --bench codegen`.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use matgraph::wgsl::{WgslOptions, generate};
use matgraph::{Graph, Registry};
use serde_json::json;
use std::hint::black_box;

/// A synthetic graph of about `n` nodes: repeated blocks of normalize, dot, exact Fresnel,
/// Henyey–Greenstein, mul and mix, each block feeding the next, all reaching the output.
fn synthetic(n: usize) -> Graph {
    let mut nodes = vec![json!({ "id": "geo", "type": "geometry" })];
    let mut prev = "geo.normal".to_owned();
    let mut k = 0;
    while nodes.len() + 7 <= n.max(8) {
        let id = |s: &str| format!("{s}{k}");
        nodes.push(json!({ "id": id("sum"), "type": "add", "inputs": { "a": { "link": prev }, "b": { "link": "geo.view" } } }));
        nodes.push(json!({ "id": id("dir"), "type": "normalize", "inputs": { "v": { "link": format!("{}.result", id("sum")) } } }));
        nodes.push(json!({ "id": id("cos"), "type": "dot", "inputs": { "a": { "link": format!("{}.result", id("dir")) }, "b": { "link": "geo.normal" } } }));
        nodes.push(json!({ "id": id("fr"), "type": "fresnel_dielectric", "inputs": { "cos_theta": { "link": format!("{}.result", id("cos")) }, "ior_inside": 1.4 } }));
        nodes.push(json!({ "id": id("hg"), "type": "hg_phase", "inputs": { "cos_theta": { "link": format!("{}.result", id("cos")) }, "g": 0.8 } }));
        nodes.push(json!({ "id": id("w"), "type": "mul", "inputs": { "a": { "link": format!("{}.reflectance", id("fr")) }, "b": { "link": format!("{}.phase", id("hg")) } } }));
        nodes.push(json!({ "id": id("mix"), "type": "mix", "inputs": { "a": { "link": format!("{}.result", id("dir")) }, "b": { "link": "geo.light" }, "t": { "link": format!("{}.result", id("w")) } } }));
        prev = format!("{}.result", id("mix"));
        k += 1;
    }
    let doc = json!({ "version": 1, "name": format!("synthetic_{n}"), "nodes": nodes, "outputs": [{ "name": "out", "from": prev }] });
    Graph::from_json(&doc.to_string(), Registry::builtin()).unwrap()
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("wgsl_codegen_and_naga");
    group.sample_size(20);
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/graphs");
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    for path in files
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
    {
        let graph = matgraph::io::load_graph(path, Registry::builtin()).unwrap();
        group.bench_with_input(BenchmarkId::new("bundled", &graph.name), &graph, |b, g| {
            b.iter(|| black_box(generate(g, &WgslOptions::default()).unwrap()))
        });
    }
    for n in [100, 1000, 5000] {
        let graph = synthetic(n);
        group.bench_with_input(
            BenchmarkId::new("synthetic_nodes", graph.nodes().len()),
            &graph,
            |b, g| b.iter(|| black_box(generate(g, &WgslOptions::default()).unwrap())),
        );
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
