//! A seeded, in-process mutation fuzzer (issue 37) over graph JSON version 1 and version 2
//! (groups, with group library files served from memory), scene JSON, the app contract
//! writer and `--set` values: load → validate → save → reload → plan → evaluate → WGSL →
//! naga → contract; scene parse → validate → save → reserve meshes → build (tiny frames);
//! `--set` parse → apply → plan → evaluate. Runs on stable Rust, on all cores (rayon);
//! every case is reproducible from `(seed, case)`.
//!
//! ```sh
//! cargo run --release --example fuzz -- --cases 10000000 --seed 37 --progress 1000000
//! cargo run --release --example fuzz -- --cases 20000 --seed 7 --out fuzz-findings
//! cargo run --release --example fuzz -- --replay fuzz-findings/wgsl-123.json
//! cargo run --release --example fuzz -- --seed 7 --show 123     # print case 123
//! cargo run --release --example fuzz -- --seed 7 --case 123     # run case 123 alone
//! # --only graph-v1|graph-v2|scene|set: one family; --max-seconds S: stop starting cases
//! # after S seconds (the report counts the cases that ran); --first N: start at case N
//! ```
//!
//! A *finding* is a panic at any stage (caught with `catch_unwind`), a graph or scene that
//! loads but whose saved form does not load back to the same bytes, a graph that loads and
//! plans but whose WGSL (or render module) naga rejects, a contract that is not the same
//! JSON twice, a scene mesh larger than its memory reservation, a `--set` value accepted
//! with a number past f32, or a case that takes over a second when run again alone after
//! the run (every case over a second in the run is listed in `slow-cases.txt` and run
//! again alone, three times; the fastest counts). Each is written, as a
//! replayable case, to the `--out` folder (default `fuzz-findings/`), at most 5 per
//! distinct message.

pub mod cases;
pub mod files;
pub mod mutate_graph;
pub mod mutate_groups;
pub mod mutate_scene;
pub mod report;
pub mod rng;
pub mod set_values;
pub mod stages;

pub use cases::{Case, Corpus, Family};
pub use report::{RunOptions, run};
pub use stages::run_case;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The case a reproducer file holds: a case written by [`Case::to_json`], or a graph file
/// (run as a version-1 or version-2 graph case with no other files).
pub fn replay_case(text: &str) -> Case {
    let v: serde_json::Value = serde_json::from_str(text).unwrap_or_default();
    if let Some(meta) = v.get("fuzz_case") {
        let family = Family::ALL
            .into_iter()
            .find(|f| meta["family"].as_str() == Some(f.name()))
            .unwrap_or(Family::Graph);
        let files: BTreeMap<String, String> =
            serde_json::from_value(v["files"].clone()).unwrap_or_default();
        let sets: Vec<String> = serde_json::from_value(v["sets"].clone()).unwrap_or_default();
        return Case {
            family,
            text: v["text"].as_str().unwrap_or_default().to_owned(),
            files,
            sets,
        };
    }
    Case {
        family: Family::Graph,
        text: text.to_owned(),
        files: BTreeMap::new(),
        sets: Vec::new(),
    }
}

/// Runs one case and prints its outcome and time.
fn run_one(label: &str, case: &Case) {
    let t = std::time::Instant::now();
    let o = run_case(case);
    let secs = t.elapsed().as_secs_f64();
    match (o.finding, o.known) {
        (Some(f), _) => println!("{label}: {}: {} ({secs:.3} s)", f.stage, f.message),
        (None, Some(k)) => println!("{label}: known: {k} ({secs:.3} s)"),
        (None, None) => println!("{label}: no finding ({secs:.3} s)"),
    }
}

#[allow(dead_code)]
fn main() {
    let mut cases = 100_000u64;
    let mut seed = 1u64;
    let mut first = 0u64;
    let mut progress = 0u64;
    let mut out = PathBuf::from("fuzz-findings");
    let mut only = None;
    let mut max_seconds = None;
    let mut args = std::env::args().skip(1);
    let corpus = Corpus::bundled();
    while let Some(a) = args.next() {
        let mut value = || args.next().expect("a value after the flag");
        match a.as_str() {
            "--cases" => cases = value().parse().expect("--cases N"),
            "--seed" => seed = value().parse().expect("--seed N"),
            "--first" => first = value().parse().expect("--first N"),
            "--progress" => progress = value().parse().expect("--progress N"),
            "--out" => out = PathBuf::from(value()),
            "--max-seconds" => max_seconds = Some(value().parse().expect("--max-seconds S")),
            "--only" => {
                let name = value();
                only = Some(
                    Family::ALL
                        .into_iter()
                        .find(|f| f.name() == name)
                        .expect("--only graph-v1|graph-v2|scene|set"),
                );
            }
            "--replay" => {
                let path = PathBuf::from(value());
                let text = std::fs::read_to_string(&path).expect("read the reproducer");
                run_one(&path.display().to_string(), &replay_case(&text));
                return;
            }
            "--show" => {
                let case = value().parse().expect("--show CASE");
                println!("{}", corpus.case(seed, case).to_json(seed, case));
                return;
            }
            "--case" => {
                let case = value().parse().expect("--case CASE");
                run_one(
                    &format!("seed {seed} case {case}"),
                    &corpus.case(seed, case),
                );
                return;
            }
            other => panic!("unknown argument {other}"),
        }
    }
    let options = RunOptions {
        first,
        cases,
        out: Some(Path::new(&out)),
        progress,
        only,
        max_seconds,
    };
    let r = run(&corpus, seed, &options);
    print!("{}", r.summary());
    if !r.findings.is_empty() {
        println!("reproducers in {}", out.display());
    }
}
