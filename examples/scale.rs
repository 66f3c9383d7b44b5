//! Large generated graphs, for measuring how check, eval and wgsl grow with graph size.
//!
//! Run (release; the figures in docs/benchmarks.md come from this):
//!
//! ```sh
//! cargo run --release --example scale -- 10000 100000 1000000
//! cargo run --release --example scale -- --write /tmp/graphs 100000   # also save the files
//! ```
//!
//! Two shapes, each of about N nodes, all live:
//! - **chain**: `geometry`, `c = dot(normal, view)`, then N `add` nodes each adding 1 to the
//!   one before (the deepest possible graph): the output is `c + N`;
//! - **fan-in**: N/2 leaf `add` nodes computing `c + 1`, then a balanced binary tree of `add`
//!   nodes summing them pairwise (an odd one out is added to itself), written leaves first
//!   (every leaf value is live at once): the output is `(c + 1) × 2^depth`.
//!
//! For each graph and phase it prints the best of a few runs, in seconds: `check` parses
//! and validates the text; `eval` also compiles the CPU plan and evaluates one sample (what
//! `matgraph eval` does); `wgsl` also generates the WGSL and has naga parse and validate it
//! (what `matgraph wgsl` does). `generate` is the WGSL step alone on the loaded graph
//! (plan, text, naga parse and validation), of which `naga` is naga's parse and validation.

use matgraph::exec::SampleBatch;
use matgraph::plan::{Plan, PlanOptions};
use matgraph::wgsl::{WgslOptions, generate};
use matgraph::{Graph, Registry};
use std::fmt::Write;
use std::time::Instant;

/// The text of a chain of `n` `add` nodes.
pub fn chain(n: usize) -> String {
    let mut s = head(&format!("chain_{n}"));
    let mut prev = "cos.result".to_owned();
    for k in 0..n {
        let _ = write!(
            s,
            ",\n    {{ \"id\": \"a{k}\", \"type\": \"add\", \"inputs\": {{ \"a\": {{ \"link\": \"{prev}\" }}, \"b\": 1.0 }} }}"
        );
        prev = format!("a{k}.result");
    }
    tail(s, &prev)
}

/// The text of a fan-in tree of about `n` `add` nodes, leaves first, and the tree's depth.
pub fn fan_in_depth(n: usize) -> (String, u32) {
    let mut s = head(&format!("fan_in_{n}"));
    let leaves = (n / 2).max(1);
    let mut level: Vec<String> = Vec::with_capacity(leaves);
    for k in 0..leaves {
        let _ = write!(
            s,
            ",\n    {{ \"id\": \"l{k}\", \"type\": \"add\", \"inputs\": {{ \"a\": {{ \"link\": \"cos.result\" }}, \"b\": 1.0 }} }}"
        );
        level.push(format!("l{k}.result"));
    }
    let mut depth = 0;
    while level.len() > 1 {
        let mut next = Vec::with_capacity(level.len().div_ceil(2));
        for (k, pair) in level.chunks(2).enumerate() {
            let id = format!("t{depth}_{k}");
            let b = pair.get(1).unwrap_or(&pair[0]);
            let _ = write!(
                s,
                ",\n    {{ \"id\": \"{id}\", \"type\": \"add\", \"inputs\": {{ \"a\": {{ \"link\": \"{}\" }}, \"b\": {{ \"link\": \"{b}\" }} }} }}",
                pair[0]
            );
            next.push(format!("{id}.result"));
        }
        level = next;
        depth += 1;
    }
    (tail(s, &level[0]), depth)
}

/// The text of a fan-in tree of about `n` `add` nodes, leaves first.
pub fn fan_in(n: usize) -> String {
    fan_in_depth(n).0
}

fn head(name: &str) -> String {
    format!(
        "{{\n  \"version\": 1,\n  \"name\": \"{name}\",\n  \"nodes\": [\n    {{ \"id\": \"geo\", \"type\": \"geometry\" }},\n    {{ \"id\": \"cos\", \"type\": \"dot\", \"inputs\": {{ \"a\": {{ \"link\": \"geo.normal\" }}, \"b\": {{ \"link\": \"geo.view\" }} }} }}"
    )
}

fn tail(mut s: String, from: &str) -> String {
    let _ = write!(
        s,
        "\n  ],\n  \"outputs\": [{{ \"name\": \"out\", \"from\": \"{from}\" }}]\n}}\n"
    );
    s
}

/// Best wall time of `runs` runs of `f`, in seconds.
fn best<T>(runs: usize, mut f: impl FnMut() -> T) -> f64 {
    (0..runs)
        .map(|_| {
            let t = Instant::now();
            std::hint::black_box(f());
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

#[allow(dead_code)]
fn main() {
    let mut sizes = Vec::new();
    let mut write_dir = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        if a == "--write" {
            write_dir = args.next();
        } else {
            sizes.push(a.parse::<usize>().expect("sizes are node counts"));
        }
    }
    if sizes.is_empty() {
        sizes = vec![10_000, 100_000, 1_000_000];
    }
    let registry = Registry::builtin();
    println!(
        "| graph | nodes | check (s) | eval (s) | wgsl (s) | generate (s) | naga (s) | WGSL bytes |"
    );
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for &n in &sizes {
        for (shape, text) in [("chain", chain(n)), ("fan-in", fan_in(n))] {
            if let Some(dir) = &write_dir {
                let path = std::path::Path::new(dir).join(format!("{}_{n}.json", shape));
                std::fs::create_dir_all(dir).expect("create the output folder");
                std::fs::write(&path, &text).expect("write the graph");
            }
            let runs = if n >= 1_000_000 { 1 } else { 3 };
            let graph = Graph::from_json(&text, registry).expect("the generated graph is valid");
            let nodes = graph.nodes().len();
            drop(graph);
            let check = best(runs, || Graph::from_json(&text, registry).unwrap());
            let eval = best(runs, || {
                let g = Graph::from_json(&text, registry).unwrap();
                let plan = Plan::compile(&g, &PlanOptions::default()).unwrap();
                plan.execute(&SampleBatch::new(1), &plan.default_parameters())
                    .unwrap()
            });
            let mut bytes = 0;
            let wgsl = best(runs, || {
                let g = Graph::from_json(&text, registry).unwrap();
                let m = generate(&g, &WgslOptions::default()).unwrap();
                bytes = m.source.len();
            });
            let g = Graph::from_json(&text, registry).unwrap();
            let generate_only = best(runs, || generate(&g, &WgslOptions::default()).unwrap());
            let source = generate(&g, &WgslOptions::default()).unwrap().source;
            let naga = best(runs, || {
                let module = naga::front::wgsl::parse_str(&source).unwrap();
                naga::valid::Validator::new(
                    naga::valid::ValidationFlags::all(),
                    naga::valid::Capabilities::empty(),
                )
                .validate(&module)
                .unwrap()
            });
            println!(
                "| {shape} | {nodes} | {check:.3} | {eval:.3} | {wgsl:.3} | {generate_only:.3} | {naga:.3} | {bytes} |"
            );
        }
    }
}
