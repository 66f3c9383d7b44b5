//! README.md as a newcomer meets it on a fresh clone (issue 38): the tour's commands write
//! nowhere the main command writes, name graphs that exist, the materials table lists every
//! bundled graph, and every path the README names is in the repository.

use std::path::Path;

fn readme() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The text of the section whose heading is `heading`, up to the next heading of its level or
/// above.
fn section(text: &str, heading: &str) -> String {
    let level = heading.chars().take_while(|c| *c == '#').count();
    let mut lines = text.lines().skip_while(|l| *l != heading);
    assert!(lines.next().is_some(), "README.md has no {heading:?}");
    // A `#` inside a code block is a comment, not a heading.
    let mut in_code = false;
    lines
        .take_while(|l| {
            if l.starts_with("```") {
                in_code = !in_code;
            }
            let hashes = l.chars().take_while(|c| *c == '#').count();
            in_code || !(hashes > 0 && hashes <= level && l[hashes..].starts_with(' '))
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The `matgraph …` command lines of the first `sh` block of `text`, comments cut off.
fn commands(text: &str) -> Vec<String> {
    text.lines()
        .skip_while(|l| *l != "```sh")
        .skip(1)
        .take_while(|l| *l != "```")
        .filter(|l| l.starts_with("matgraph "))
        .map(|l| l.split(" # ").next().unwrap().trim().to_owned())
        .collect()
}

/// The tour's renders each name their own output (`-o` or `--out-dir`), none in `renders/`,
/// where the main command's images are: the `--max-error`, `--specialise` and
/// `--gpu --textures exact` lines once wrote into it by default.
#[test]
fn tour_commands_write_outside_renders() {
    let tour = commands(&section(&readme(), "## A short tour"));
    let renders: Vec<&String> = tour
        .iter()
        .filter(|c| c.starts_with("matgraph render "))
        .collect();
    assert!(renders.len() >= 8, "{tour:?}");
    for c in renders {
        let words: Vec<&str> = c.split_whitespace().collect();
        let out = words
            .windows(2)
            .find(|w| matches!(w[0], "-o" | "--out" | "--out-dir"))
            .map(|w| w[1]);
        let Some(out) = out else {
            panic!("{c}: names no -o or --out-dir, so it writes into renders/");
        };
        assert!(
            !out.trim_start_matches("./").starts_with("renders"),
            "{c}: writes into renders/"
        );
    }
}

/// Each tour command's graph is a bundled file (or `graphs/*.json`), not a placeholder such
/// as `graph.json` that fails when pasted.
#[test]
fn tour_commands_name_graphs_that_exist() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for c in commands(&section(&readme(), "## A short tour")) {
        for word in c.split_whitespace().filter(|w| w.ends_with(".json")) {
            // Outputs: contracts and schemas the command writes.
            if c.contains(&format!("--contract {word}")) || c.contains(&format!("-o {word}")) {
                continue;
            }
            assert!(
                word == "graphs/*.json" || root.join(word).is_file(),
                "{c}: {word} is not a file of the repository"
            );
        }
    }
}

/// The materials table names every `graphs/*.json`.
#[test]
fn materials_table_lists_every_bundled_graph() {
    let table = section(&readme(), "## Bundled materials");
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs");
    let mut missing = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        if name.ends_with(".json") && !table.contains(&format!("`{name}`")) {
            missing.push(name);
        }
    }
    missing.sort();
    assert!(
        missing.is_empty(),
        "not in the materials table: {missing:?}"
    );
}

/// Every link and every repository path in backticks is a file or folder of the repository,
/// none in a folder a clone lacks (`shared/`, or the ignored `target/` and `renders/`).
#[test]
fn readme_names_only_files_of_the_repository() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = readme();
    let mut paths: Vec<String> = Vec::new();
    // Links: ](path) and ](path#anchor).
    for part in text.split("](").skip(1) {
        let target = part.split(')').next().unwrap();
        if !target.starts_with('#') && !target.contains("://") {
            paths.push(target.split('#').next().unwrap().to_owned());
        }
    }
    // Paths in backticks under the repository's top-level folders.
    const TOP: [&str; 8] = [
        "src/",
        "docs/",
        "graphs/",
        "examples/",
        "tests/",
        "nodes/",
        "benches/",
        "shared/",
    ];
    for (k, span) in text.split('`').enumerate() {
        if k % 2 == 0 {
            continue;
        }
        for word in span.split_whitespace() {
            let word = word.trim_end_matches([',', ':', ';', ')', '.']);
            if TOP.iter().any(|t| word.starts_with(t)) && !word.contains('*') {
                paths.push(word.to_owned());
            }
        }
    }
    assert!(paths.len() > 30, "{paths:?}");
    for p in &paths {
        assert!(
            !["shared/", "target/", "renders/"]
                .iter()
                .any(|t| p.starts_with(t)),
            "README.md names {p}, which a fresh clone does not have"
        );
        assert!(
            root.join(p).exists(),
            "README.md names {p}, which is not here"
        );
    }
}
