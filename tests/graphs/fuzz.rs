//! A short run of the mutation fuzzer (`examples/fuzz/`): 300 seeded cases, at least 20 of each
//! family (version-1 graphs, version-2 graphs with groups and library files in memory,
//! scenes, `--set` values) through every stage, with no panic, no finding and no case
//! over the slow bound (30 s in debug builds). The long run (`cargo run --release --example fuzz -- --cases 10000000`)
//! is recorded in docs/benchmarks.md.

#[path = "../../examples/fuzz/main.rs"]
#[allow(dead_code, clippy::module_inception)]
mod fuzz;

use fuzz::{Corpus, Family};

#[test]
fn a_short_fuzz_run_finds_nothing_in_any_family() {
    let corpus = Corpus::bundled();
    let cases = 300;
    let out = std::env::temp_dir().join(format!("matgraph-fuzz-{}", std::process::id()));
    let options = fuzz::RunOptions {
        cases,
        out: Some(&out),
        ..Default::default()
    };
    let report = fuzz::run(&corpus, 20_261_201, &options);
    assert_eq!(report.cases, cases);
    assert!(
        report.findings.is_empty(),
        "findings (reproducers in {}): {:#?}",
        out.display(),
        report.findings
    );
    for family in Family::ALL {
        let n = report.families.get(&family).copied().unwrap_or(0);
        assert!(n >= 20, "{}: {n} cases of {cases}", family.name());
    }
    assert_eq!(report.families.values().sum::<u64>(), cases);
}

#[test]
fn cases_are_reproducible_and_varied() {
    let corpus = Corpus::bundled();
    assert!(corpus.flat.len() >= 5, "the bundled graphs seed the fuzzer");
    assert!(!corpus.grouped.is_empty() && !corpus.libs.is_empty());
    assert!(corpus.scenes.len() >= 4, "the presets seed the scene cases");
    let a: Vec<fuzz::Case> = (0..200).map(|c| corpus.case(3, c)).collect();
    let b: Vec<fuzz::Case> = (0..200).map(|c| corpus.case(3, c)).collect();
    assert_eq!(a, b);
    let mut distinct: Vec<String> = a.iter().map(|c| c.to_json(3, 0)).collect();
    distinct.sort();
    distinct.dedup();
    assert!(distinct.len() >= 190, "{}", distinct.len());
    // In every family some cases get past the parser and some do not.
    let registry = matgraph::Registry::builtin();
    for family in [Family::Graph, Family::Grouped] {
        let of: Vec<&fuzz::Case> = a.iter().filter(|c| c.family == family).collect();
        let loads = of
            .iter()
            .filter(|c| {
                let files = std::sync::Arc::new(fuzz::files::MemFiles::new(c.files.clone()));
                matgraph::Graph::from_json_in(&c.text, registry, files).is_ok()
            })
            .count();
        assert!(
            loads > 0 && loads < of.len(),
            "{family:?}: {loads} of {} load",
            of.len()
        );
    }
    let scenes: Vec<&fuzz::Case> = a.iter().filter(|c| c.family == Family::Scene).collect();
    let valid = scenes
        .iter()
        .filter(|c| matgraph::scene::Scene::from_json(&c.text).is_ok())
        .count();
    assert!(
        valid > 0 && valid < scenes.len(),
        "{valid} of {} scenes",
        scenes.len()
    );
    // A case replays from its reproducer.
    let c = &a[7];
    assert_eq!(fuzz::replay_case(&c.to_json(3, 7)), *c);
}
