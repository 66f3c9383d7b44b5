//! A seeded, in-process mutation fuzzer over load → validate → save → plan → evaluate →
//! WGSL → naga validation, seeded with the bundled graphs (`graphs/*.json`). Runs on stable
//! Rust; every case is reproducible from `(seed, case)`.
//!
//! ```sh
//! cargo run --release --example fuzz -- --cases 1000000            # the long run
//! cargo run --release --example fuzz -- --cases 20000 --seed 7 --out fuzz-findings
//! cargo run --release --example fuzz -- --replay fuzz-findings/wgsl-123.json
//! cargo run --release --example fuzz -- --seed 7 --show 123     # print case 123's text
//! ```
//!
//! Mutations: node deletion, duplication (same id or a fresh one), swaps, type changes to
//! any registered type, `data_type` changes, inputs removed, added (known and unknown
//! names) or set to huge, tiny, negative, zero, wrong-typed, wrong-length, enum-name, unicode
//! or link values (to valid, missing, self and random outputs), textures on any node, output
//! and parameter renames (unicode, `_`, WGSL keywords), re-targets, duplications and
//! deletions, top-level field changes, and raw byte edits of the text.
//!
//! A *finding* is a panic at any stage (caught with `catch_unwind`), a graph that loads but
//! whose saved form does not load back to the same bytes, or a graph that loads and plans
//! but whose WGSL naga rejects. Each is written, with its text, to the `--out` folder
//! (default `fuzz-findings/`), at most 5 per distinct message.

use matgraph::exec::SampleBatch;
use matgraph::node::Attribute;
use matgraph::plan::{Plan, PlanOptions};
use matgraph::wgsl::{Entry, ShaderError, WgslOptions, generate};
use matgraph::{Graph, Registry};
use rayon::prelude::*;
use serde_json::{Value as J, json};
use std::collections::BTreeMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

/// A small, fast, seedable generator (xorshift64*).
pub struct Rng(u64);

impl Rng {
    /// The generator of case `case` of run `seed`.
    pub fn new(seed: u64, case: u64) -> Rng {
        let mut r = Rng((seed ^ 0x9e37_79b9_7f4a_7c15)
            .wrapping_mul(case.wrapping_add(0x2545_f491_4f6c_dd1d))
            | 1);
        for _ in 0..4 {
            r.bits();
        }
        r
    }
    /// The next 64 random bits.
    pub fn bits(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    /// A number in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.bits() % n.max(1) as u64) as usize
    }
    /// True with probability `1 / n`.
    pub fn one_in(&mut self, n: usize) -> bool {
        self.below(n) == 0
    }
    /// One item of a non-empty slice.
    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// Names that stress identifiers: unicode, `_`, WGSL keywords and reserved words.
const NAMES: &[&str] = &[
    "é",
    "_",
    "__x",
    "",
    "fn",
    "let",
    "struct",
    "NULL",
    "await",
    "vec3",
    "f32",
    "mg_params",
    "geom",
    "s",
    "x y",
    "1a",
    "日本語",
    "\u{0}",
    "a.b",
    "normal",
    "time",
    "ior",
    "out",
    "p__",
];

/// Numbers at and past the edges of f32.
const NUMBERS: &[f64] = &[
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.5,
    1e-45,
    1e-40,
    -1e-40,
    1e-7,
    3.4e38,
    -3.4e38,
    3.5e38,
    1e39,
    -1e300,
    1e300,
    2147483648.0,
    -2147483649.0,
    16777217.0,
    100.0,
    1e6,
    0.001,
];

/// A random JSON number, from the edge list or uniformly scaled.
fn number(rng: &mut Rng) -> J {
    if rng.one_in(2) {
        json!(*rng.pick(NUMBERS))
    } else {
        let x = (rng.bits() >> 11) as f64 / (1u64 << 53) as f64;
        let e = rng.below(80) as i32 - 40;
        json!((x * 2.0 - 1.0) * 10f64.powi(e))
    }
}

/// A random input value: literals of every shape, or links.
fn value(rng: &mut Rng, doc: &J) -> J {
    match rng.below(10) {
        0 | 1 => number(rng),
        2 => J::Array((0..rng.below(6)).map(|_| number(rng)).collect()),
        3 => json!(rng.one_in(2)),
        4 => json!(*rng.pick(NAMES)),
        5 => json!(rng.pick(&[
            "linear",
            "nearest",
            "repeat",
            "clamp",
            "mirror",
            "phase_form",
            "pharr"
        ])),
        6 => J::Null,
        7 => json!({ "link": random_output(rng, doc) }),
        8 => json!({ "link": random_output(rng, doc), "extra": 1 }),
        _ => json!({ "link": format!("{}.{}", rng.pick(NAMES), rng.pick(NAMES)) }),
    }
}

/// `id.output` of a random node of `doc` and a random output of its type (or a random name).
fn random_output(rng: &mut Rng, doc: &J) -> String {
    let nodes = doc["nodes"].as_array().cloned().unwrap_or_default();
    if nodes.is_empty() {
        return "x.y".into();
    }
    let n = rng.pick(&nodes);
    let id = n["id"].as_str().unwrap_or("x").to_owned();
    let ty = n["type"].as_str().unwrap_or("");
    let out = match Registry::builtin().get(ty) {
        Some(t) if !t.outputs().is_empty() && !rng.one_in(8) => {
            t.outputs()[rng.below(t.outputs().len())].name.to_owned()
        }
        _ => rng.pick(NAMES).to_string(),
    };
    format!("{id}.{out}")
}

/// Applies one random mutation to `doc`.
fn mutate(rng: &mut Rng, doc: &mut J) {
    let registry = Registry::builtin();
    let len = doc["nodes"].as_array().map_or(0, Vec::len);
    let k = rng.below(len.max(1));
    // Entries that are objects can be edited in place (serde_json panics on indexing others).
    let node_obj = len > 0 && doc["nodes"][k].is_object();
    match rng.below(22) {
        0 if len > 0 => {
            doc["nodes"].as_array_mut().unwrap().remove(k);
        }
        1 if len > 0 => {
            let mut n = doc["nodes"][k].clone();
            if n.is_object() && rng.one_in(2) {
                n["id"] = json!(format!("dup{}", rng.below(1000)));
            }
            doc["nodes"].as_array_mut().unwrap().push(n);
        }
        2 if len > 1 => {
            let j = rng.below(len);
            doc["nodes"].as_array_mut().unwrap().swap(j, k);
        }
        3 if node_obj => {
            let t = rng.pick(registry.types());
            doc["nodes"][k]["type"] = json!(t.name());
        }
        4 if node_obj => {
            doc["nodes"][k]["data_type"] =
                json!(rng.pick(&["float", "vec2", "vec3", "vec4", "color", "int", "bool", "é"]));
        }
        5..=9 if node_obj => {
            // Set an input the type has (most of the time) to a random value.
            let ty = doc["nodes"][k]["type"].as_str().unwrap_or("").to_owned();
            let name = match registry.get(&ty) {
                Some(t) if !t.inputs().is_empty() && !rng.one_in(6) => {
                    t.inputs()[rng.below(t.inputs().len())].name.to_owned()
                }
                _ => rng.pick(NAMES).to_string(),
            };
            let v = value(rng, doc);
            if !doc["nodes"][k]["inputs"].is_object() {
                doc["nodes"][k]["inputs"] = json!({});
            }
            doc["nodes"][k]["inputs"][name] = v;
        }
        10 if node_obj => {
            if let Some(m) = doc["nodes"][k]["inputs"].as_object_mut()
                && !m.is_empty()
            {
                let key = m.keys().nth(rng.below(m.len())).cloned().unwrap();
                m.remove(&key);
            }
        }
        11 if node_obj => {
            // A link to itself or to a later node: cycles.
            let id = doc["nodes"][k]["id"].as_str().unwrap_or("x").to_owned();
            let j = rng.below(len);
            let ty = doc["nodes"][j]["type"].as_str().unwrap_or("").to_owned();
            if let Some(t) = registry.get(&ty)
                && !t.inputs().is_empty()
                && doc["nodes"][j].is_object()
            {
                let input = t.inputs()[rng.below(t.inputs().len())].name;
                let out = registry
                    .get(doc["nodes"][k]["type"].as_str().unwrap_or(""))
                    .and_then(|t| t.outputs().first().map(|o| o.name))
                    .unwrap_or("result");
                if !doc["nodes"][j]["inputs"].is_object() {
                    doc["nodes"][j]["inputs"] = json!({});
                }
                doc["nodes"][j]["inputs"][input] = json!({ "link": format!("{id}.{out}") });
            }
        }
        12 if node_obj => {
            doc["nodes"][k]["texture"] = match rng.below(4) {
                0 => json!("scene:refraction"),
                1 => json!(""),
                2 => json!([]),
                _ => json!(["a.png", "b.png"]),
            };
        }
        13 if node_obj => {
            doc["nodes"][k]["position"] = json!([number(rng), number(rng)]);
        }
        14 if node_obj => {
            doc["nodes"][k]["id"] = json!(rng.pick(NAMES));
        }
        15 => {
            // Outputs: rename, re-target, duplicate, delete, add.
            if !doc["outputs"].is_array() {
                doc["outputs"] = json!([]);
            }
            let target = random_output(rng, doc);
            let outs = doc["outputs"].as_array_mut().unwrap();
            match rng.below(4) {
                0 if !outs.is_empty() => {
                    let j = rng.below(outs.len());
                    if outs[j].is_object() {
                        outs[j]["name"] = json!(rng.pick(NAMES));
                    }
                }
                1 if !outs.is_empty() => {
                    let j = rng.below(outs.len());
                    let o = outs[j].clone();
                    outs.push(o);
                }
                2 if !outs.is_empty() => {
                    let j = rng.below(outs.len());
                    outs.remove(j);
                }
                _ => outs.push(json!({ "name": rng.pick(NAMES), "from": target })),
            }
        }
        16 => {
            // Parameters: rename, re-point, duplicate, add.
            if !doc["parameters"].is_array() {
                doc["parameters"] = json!([]);
            }
            let node = doc["nodes"]
                .as_array()
                .and_then(|n| (!n.is_empty()).then(|| n[rng.below(n.len())]["id"].clone()))
                .unwrap_or(json!("x"));
            let params = doc["parameters"].as_array_mut().unwrap();
            match rng.below(3) {
                0 if !params.is_empty() => {
                    let j = rng.below(params.len());
                    if params[j].is_object() {
                        params[j]["name"] = json!(rng.pick(NAMES));
                    }
                }
                1 if !params.is_empty() => {
                    let j = rng.below(params.len());
                    let p = params[j].clone();
                    params.push(p);
                }
                _ => params.push(json!({ "name": rng.pick(NAMES), "node": node })),
            }
        }
        17 => {
            let field = *rng.pick(&[
                "version",
                "name",
                "doc",
                "scene",
                "nodes",
                "outputs",
                "parameters",
                "extra",
            ]);
            doc[field] = match rng.below(5) {
                0 => number(rng),
                1 => json!(rng.pick(NAMES)),
                2 => J::Null,
                3 => json!([]),
                _ => json!({ "k": [1, 2, {"deep": [[[[]]]]}] }),
            };
        }
        18 if len > 0 => {
            // A parameter node with a random value feeding a random node.
            let id = format!("pz{}", rng.below(100));
            let v = number(rng);
            doc["nodes"]
                .as_array_mut()
                .unwrap()
                .push(json!({ "id": id, "type": "parameter", "inputs": { "value": v } }));
            if !doc["parameters"].is_array() {
                doc["parameters"] = json!([]);
            }
            doc["parameters"]
                .as_array_mut()
                .unwrap()
                .push(json!({ "name": id, "node": id }));
        }
        19 if len > 0 => {
            // A whole random node of a random type with random inputs.
            let t = rng.pick(registry.types());
            let mut inputs = serde_json::Map::new();
            for i in t.inputs() {
                if rng.one_in(2) {
                    inputs.insert(i.name.to_owned(), value(rng, doc));
                }
            }
            let id = format!("z{}", rng.below(10_000));
            doc["nodes"]
                .as_array_mut()
                .unwrap()
                .push(json!({ "id": id, "type": t.name(), "inputs": inputs }));
            if rng.one_in(2)
                && let Some(o) = t.outputs().first()
            {
                if !doc["outputs"].is_array() {
                    doc["outputs"] = json!([]);
                }
                doc["outputs"]
                    .as_array_mut()
                    .unwrap()
                    .push(json!({ "name": id, "from": format!("{id}.{}", o.name) }));
            }
        }
        20 if len > 0 => {
            doc["nodes"][k] = match rng.below(4) {
                0 => number(rng),
                1 => json!(rng.pick(NAMES)),
                2 => json!({ "id": 5, "type": [] }),
                _ => J::Null,
            };
        }
        _ => {
            doc["name"] = json!(rng.pick(NAMES));
        }
    }
}

/// Raw edits of the text: byte flips, insertions, deletions, truncation.
fn mutate_text(rng: &mut Rng, text: &mut Vec<u8>) {
    for _ in 0..1 + rng.below(4) {
        if text.is_empty() {
            return;
        }
        let at = rng.below(text.len());
        match rng.below(4) {
            0 => text[at] = rng.bits() as u8,
            1 => text.insert(at, *rng.pick(b"{}[],:\"\\0123456789e-.")),
            2 => {
                text.remove(at);
            }
            _ => text.truncate(at),
        }
    }
}

/// The text of case `case` of run `seed`, mutated from one of `seeds`.
pub fn case_text(seeds: &[J], seed: u64, case: u64) -> String {
    let mut rng = Rng::new(seed, case);
    let mut doc = rng.pick(seeds).clone();
    for _ in 0..1 + rng.below(4) {
        mutate(&mut rng, &mut doc);
    }
    let text = if rng.one_in(2) {
        serde_json::to_string_pretty(&doc).unwrap_or_default()
    } else {
        doc.to_string()
    };
    if rng.one_in(8) {
        let mut bytes = text.into_bytes();
        mutate_text(&mut rng, &mut bytes);
        String::from_utf8_lossy(&bytes).into_owned()
    } else {
        text
    }
}

/// What went wrong in one case.
#[derive(Clone, Debug)]
pub struct Finding {
    /// The stage: `load`, `save`, `plan`, `eval`, `wgsl`.
    pub stage: &'static str,
    /// A panic's message or the failed property.
    pub message: String,
}

/// Runs every stage on `text`; `None` when nothing is wrong.
pub fn run_case(text: &str) -> Option<Finding> {
    let stage = std::cell::Cell::new("load");
    let result = catch_unwind(AssertUnwindSafe(|| check_stages(text, &stage)));
    match result {
        Ok(r) => r.err().map(|message| Finding {
            stage: stage.get(),
            message,
        }),
        Err(payload) => Some(Finding {
            stage: stage.get(),
            message: format!(
                "panic: {}",
                payload
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_else(|| "(no message)".into())
            ),
        }),
    }
}

fn check_stages(text: &str, stage: &std::cell::Cell<&'static str>) -> Result<(), String> {
    let registry = Registry::builtin();
    let Ok(graph) = Graph::from_json(text, registry) else {
        return Ok(());
    };
    stage.set("save");
    let saved = graph.to_json();
    match Graph::from_json(&saved, registry) {
        Ok(again) if again.to_json() == saved => {}
        Ok(_) => return Err("save → load → save is not byte-identical".into()),
        Err(e) => return Err(format!("the saved graph does not load: {e:?}")),
    }
    stage.set("plan");
    let Ok(plan) = Plan::compile(&graph, &PlanOptions::default()) else {
        return Ok(());
    };
    stage.set("eval");
    let mut batch = SampleBatch::new(3);
    let _ = batch.set_values(
        Attribute::Normal,
        &[[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, -1.0, 0.0]],
    );
    let _ = plan.execute(&batch, &plan.default_parameters());
    stage.set("wgsl");
    for entry in [Entry::Compute, Entry::Fragment] {
        let options = WgslOptions {
            entry,
            ..Default::default()
        };
        match generate(&graph, &options) {
            Err(e @ ShaderError::Naga { .. }) => {
                return Err(format!(
                    "loads and plans, naga rejects its WGSL ({entry:?}): {e}"
                ));
            }
            Err(ShaderError::Plan(_)) | Ok(_) => {}
            Err(e) => return Err(format!("loads and plans, WGSL fails ({entry:?}): {e}")),
        }
    }
    Ok(())
}

/// The bundled graphs, parsed.
pub fn seeds() -> Vec<J> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs");
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    paths.retain(|p| p.extension().is_some_and(|e| e == "json"));
    paths.sort();
    // A graph with groups in other files as its flat form, which loads from text alone.
    paths
        .iter()
        .filter_map(|p| {
            let g = matgraph::io::load_graph(p, matgraph::Registry::builtin()).ok();
            match g.filter(|g| g.has_groups()) {
                Some(g) => serde_json::to_value(g.flat_document()).ok(),
                None => serde_json::from_str(&std::fs::read_to_string(p).ok()?).ok(),
            }
        })
        .collect()
}

/// The outcome of a run.
pub struct Report {
    /// Cases run.
    pub cases: u64,
    /// Seconds taken.
    pub seconds: f64,
    /// Findings by message: how many, and the first few case numbers.
    pub findings: BTreeMap<String, (u64, Vec<u64>)>,
}

/// Runs cases `0..cases` of run `seed` on all threads; findings (at most 5 per message)
/// are saved under `out` as `<stage>-<case>.json` plus a `.txt` with the message.
pub fn run(seed: u64, cases: u64, out: Option<&Path>) -> Report {
    let seeds = seeds();
    let findings: Mutex<BTreeMap<String, (u64, Vec<u64>)>> = Mutex::new(BTreeMap::new());
    let start = Instant::now();
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {})); // panics are caught and reported per case
    (0..cases).into_par_iter().for_each(|case| {
        let text = match catch_unwind(|| case_text(&seeds, seed, case)) {
            Ok(text) => text,
            Err(_) => {
                let mut map = findings.lock().unwrap_or_else(|e| e.into_inner());
                let entry = map
                    .entry("mutate: the fuzzer itself panicked".into())
                    .or_default();
                entry.0 += 1;
                entry.1.push(case);
                return;
            }
        };
        let Some(f) = run_case(&text) else { return };
        let key = format!("{}: {}", f.stage, f.message.lines().next().unwrap_or(""));
        let mut map = findings.lock().unwrap_or_else(|e| e.into_inner());
        let entry = map.entry(key).or_insert((0, Vec::new()));
        entry.0 += 1;
        if entry.1.len() < 5 {
            entry.1.push(case);
            if let Some(dir) = out {
                let _ = std::fs::create_dir_all(dir);
                let base = dir.join(format!("{}-{case}", f.stage));
                let _ = std::fs::write(base.with_extension("json"), &text);
                let _ = std::fs::write(
                    base.with_extension("txt"),
                    format!("seed {seed} case {case}\n{}\n", f.message),
                );
            }
        }
    });
    std::panic::set_hook(previous);
    Report {
        cases,
        seconds: start.elapsed().as_secs_f64(),
        findings: findings.into_inner().unwrap_or_else(|e| e.into_inner()),
    }
}

#[allow(dead_code)]
fn main() {
    let mut cases = 100_000u64;
    let mut seed = 1u64;
    let mut out = PathBuf::from("fuzz-findings");
    let mut replay = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().expect("a value after the flag");
        match a.as_str() {
            "--cases" => cases = value().parse().expect("--cases N"),
            "--seed" => seed = value().parse().expect("--seed N"),
            "--out" => out = PathBuf::from(value()),
            "--replay" => replay = Some(PathBuf::from(value())),
            "--show" => {
                let case = value().parse().expect("--show CASE");
                println!("{}", case_text(&seeds(), seed, case));
                return;
            }
            other => panic!("unknown argument {other}"),
        }
    }
    if let Some(path) = replay {
        let text = std::fs::read_to_string(&path).expect("read the reproducer");
        match run_case(&text) {
            None => println!("{}: no finding", path.display()),
            Some(f) => println!("{}: {}: {}", path.display(), f.stage, f.message),
        }
        return;
    }
    let r = run(seed, cases, Some(&out));
    println!(
        "{} cases in {:.1} s: {:.0} cases/s on {} threads; {} distinct findings",
        r.cases,
        r.seconds,
        r.cases as f64 / r.seconds,
        rayon::current_num_threads(),
        r.findings.len()
    );
    for (message, (count, cases)) in &r.findings {
        println!("  {count} × {message} (cases {cases:?})");
    }
    if !r.findings.is_empty() {
        println!("reproducers in {}", out.display());
    }
}
