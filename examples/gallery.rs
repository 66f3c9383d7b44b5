//! Regenerates docs/renders and docs/gallery.md: every bundled graph rendered in its scene by
//! `matgraph render` (one PNG per graph, named after the file, plus the labelled
//! contact_sheet.png), then a page with each material, what it shows (its graph's `doc`),
//! the node types that make it and its image.
//!
//! ```sh
//! cargo run --release --example gallery                       # 384×384, 8 samples per pixel
//! cargo run --release --example gallery -- --size 512x512 --samples 16
//! cargo run --release --example gallery -- --page-only        # docs/gallery.md alone
//! ```
//!
//! The renders go through the CLI (`cargo run --bin matgraph -- render …`, the same profile
//! as this example), so they are exactly what a user's `matgraph render` gives. Other
//! pictures in docs/renders (animations, time series, charts) come from the commands named
//! in their model pages and are left as they are.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Image size when none is given: big enough to read, small enough for the docs.
const DEFAULT_SIZE: &str = "384x384";
/// Samples per pixel when none is given: 8 stratified samples leave no stair-stepped edge.
const DEFAULT_SAMPLES: &str = "8";

fn main() -> Result<(), String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let (mut size, mut samples, mut page_only) =
        (DEFAULT_SIZE.to_owned(), DEFAULT_SAMPLES.to_owned(), false);
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--size" => size = args.next().ok_or("--size needs WxH")?,
            "--samples" => samples = args.next().ok_or("--samples needs a count")?,
            "--page-only" => page_only = true,
            other => {
                return Err(format!(
                    "unknown argument {other} (--size WxH, --samples N, --page-only)"
                ));
            }
        }
    }
    let graphs = bundled_graphs(&root.join("graphs"))?;
    if !page_only {
        render(root, &graphs, &size, &samples)?;
    }
    let page = gallery_page(&graphs, &size, &samples)?;
    let out = root.join("docs/gallery.md");
    std::fs::write(&out, page).map_err(|e| format!("{}: {e}", out.display()))?;
    println!("wrote {} ({} materials)", out.display(), graphs.len());
    Ok(())
}

/// The bundled graphs, `graphs/*.json`, sorted by name.
fn bundled_graphs(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    v.sort();
    Ok(v)
}

/// `matgraph render graphs/*.json --out-dir docs/renders --size … --samples …`.
fn render(root: &Path, graphs: &[PathBuf], size: &str, samples: &str) -> Result<(), String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_owned());
    let mut cmd = Command::new(cargo);
    cmd.current_dir(root)
        .args(["run", "--quiet", "--bin", "matgraph"]);
    if !cfg!(debug_assertions) {
        cmd.arg("--release");
    }
    cmd.args(["--", "render"]);
    for g in graphs {
        cmd.arg(g.strip_prefix(root).unwrap_or(g));
    }
    cmd.args([
        "--out-dir",
        "docs/renders",
        "--size",
        size,
        "--samples",
        samples,
    ]);
    println!("{cmd:?}");
    let status = cmd.status().map_err(|e| format!("cannot run cargo: {e}"))?;
    if !status.success() {
        return Err(format!("matgraph render failed: {status}"));
    }
    Ok(())
}

/// The scene a graph names: a preset's name, the kind of an inline scene, or `ball` (the
/// renderer's default) when it names none.
fn scene_kind(scene: &serde_json::Value) -> String {
    match scene {
        serde_json::Value::String(s) => s.clone(),
        serde_json::Value::Object(o) => match o.get("kind") {
            Some(serde_json::Value::String(k)) => k.clone(),
            Some(serde_json::Value::Object(k)) => k.keys().next().cloned().unwrap_or_default(),
            _ => "ball".to_owned(),
        },
        _ => "ball".to_owned(),
    }
}

/// The page: one section per graph, in file order.
fn gallery_page(graphs: &[PathBuf], size: &str, samples: &str) -> Result<String, String> {
    let mut s = String::new();
    let _ = writeln!(s, "# Gallery\n");
    let _ = writeln!(
        s,
        "Every bundled graph in its scene, rendered on the CPU at {size} with {samples} samples per \
         pixel. Regenerate the pictures and this page with\n\n```sh\ncargo run --release --example \
         gallery\n```\n\n(`examples/gallery.rs`: it runs `matgraph render graphs/*.json --out-dir \
         docs/renders --size {size} --samples {samples}`, which also writes the labelled \
         [contact sheet](renders/contact_sheet.png), then writes this page from the graphs' own \
         `doc` fields.) Each section says what the material shows (the graph's doc) and which \
         node types make it, in the order the graph lists them (`geometry`, `parameter` and \
         `constant`, the inputs, left out); the table links each model's page.\n"
    );
    let _ = writeln!(
        s,
        "| material | scene | model | node types |\n| --- | --- | --- | --- |"
    );
    let mut sections = String::new();
    for path in graphs {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let doc: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("graph");
        let scene = scene_kind(&doc["scene"]);
        // The first model page the graph's doc names, if any.
        let model = doc["doc"].as_str().and_then(|d| {
            let at = d.find("docs/models/")?;
            let rest = &d[at + "docs/models/".len()..];
            let end = rest.find(".md")?;
            Some(rest[..end].to_owned())
        });
        let mut types: Vec<&str> = Vec::new();
        for n in doc["nodes"].as_array().into_iter().flatten() {
            if let Some(t) = n["type"].as_str()
                && !types.contains(&t)
            {
                types.push(t);
            }
        }
        let shading: Vec<&str> = types
            .iter()
            .copied()
            .filter(|t| !matches!(*t, "geometry" | "parameter" | "constant"))
            .collect();
        let page = model
            .as_ref()
            .map_or("—".to_owned(), |m| format!("[{m}.md](models/{m}.md)"));
        let _ = writeln!(
            s,
            "| [{stem}](#{stem}) | {scene} | {page} | {} |",
            shading.len()
        );
        let _ = writeln!(sections, "## {stem}\n");
        let _ = writeln!(sections, "![{stem}](renders/{stem}.png)\n");
        let _ = writeln!(
            sections,
            "**Graph:** [`graphs/{stem}.json`](../graphs/{stem}.json), scene `{scene}`.\n"
        );
        if let Some(d) = doc["doc"].as_str() {
            let _ = writeln!(sections, "**What it shows:** {d}\n");
        }
        let list: Vec<String> = shading.iter().map(|t| format!("`{t}`")).collect();
        let _ = writeln!(sections, "**Nodes:** {}.\n", list.join(", "));
        let params: Vec<String> = doc["parameters"]
            .as_array()
            .into_iter()
            .flatten()
            .filter_map(|p| p["name"].as_str().map(|n| format!("`{n}`")))
            .collect();
        if !params.is_empty() {
            let _ = writeln!(sections, "**Parameters:** {}.\n", params.join(", "));
        }
    }
    s.push('\n');
    s.push_str(&sections);
    Ok(s)
}
