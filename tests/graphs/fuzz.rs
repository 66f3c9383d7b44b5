//! A short run of the mutation fuzzer (`examples/fuzz.rs`): a few thousand seeded cases over
//! load → save → plan → evaluate → WGSL → naga, with no panic and no finding. The long run
//! (`cargo run --release --example fuzz -- --cases 1000000`) is documented in
//! docs/reliability.md.

#[path = "../../examples/fuzz.rs"]
#[allow(dead_code)]
mod fuzz;

#[test]
fn a_short_fuzz_run_finds_nothing() {
    let cases = 3_000;
    let out = std::env::temp_dir().join(format!("matgraph-fuzz-{}", std::process::id()));
    let report = fuzz::run(20_261_201, cases, Some(&out));
    assert_eq!(report.cases, cases);
    assert!(
        report.findings.is_empty(),
        "findings (reproducers in {}): {:#?}",
        out.display(),
        report.findings
    );
}

#[test]
fn cases_are_reproducible_and_varied() {
    let seeds = fuzz::seeds();
    assert!(seeds.len() >= 5, "the bundled graphs seed the fuzzer");
    let a: Vec<String> = (0..50).map(|c| fuzz::case_text(&seeds, 3, c)).collect();
    let b: Vec<String> = (0..50).map(|c| fuzz::case_text(&seeds, 3, c)).collect();
    assert_eq!(a, b);
    let mut distinct = a.clone();
    distinct.sort();
    distinct.dedup();
    assert!(distinct.len() >= 45, "{}", distinct.len());
    // Some cases load and some do not: the mutations reach past the parser.
    let loads = a
        .iter()
        .filter(|t| matgraph::Graph::from_json(t, matgraph::Registry::builtin()).is_ok())
        .count();
    assert!(loads > 0 && loads < a.len(), "{loads} of {} load", a.len());
}
