//! No command writes an output over one of its inputs (the graph, a file the graph names,
//! through a symlink or a hard link too) or over another of its outputs; each refusal
//! names the path and both roles, and leaves every file as it was. `fmt` still rewrites
//! its own input.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const GLASS: &str = "graphs/fresnel_glass.json";

/// Runs the binary in `dir`.
fn run_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the matgraph binary runs")
}

/// Runs `args` in `dir`, expects exit 1 and every fragment of `expect` on stderr.
fn refused(dir: &Path, args: &[&str], expect: &[&str]) {
    let out = run_in(dir, args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "matgraph {args:?}: {stderr}");
    for fragment in expect {
        assert!(
            stderr.contains(fragment),
            "matgraph {args:?}: stderr lacks {fragment:?}:\n{stderr}"
        );
    }
}

/// A copy of the glass graph as `dir/name`, and its text.
fn glass_in(dir: &Path, name: &str) -> (PathBuf, String) {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(GLASS))
        .expect("the glass graph");
    let path = dir.join(name);
    std::fs::write(&path, &text).unwrap();
    (path, text)
}

#[test]
fn wgsl_never_writes_over_its_graph() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (graph, text) = glass_in(d, "g.json");
    std::fs::hard_link(&graph, d.join("hard.json")).unwrap();
    std::os::unix::fs::symlink("g.json", d.join("soft.wgsl")).unwrap();
    for out in ["g.json", "./g.json", "hard.json", "soft.wgsl"] {
        refused(
            d,
            &["wgsl", "g.json", "-o", out],
            &[
                &format!("{out}: the -o output would overwrite the input graph g.json"),
                "choose another output file",
            ],
        );
        refused(
            d,
            &["wgsl", "g.json", "--entry", "render", "--contract", out],
            &["the --contract output would overwrite the input graph g.json"],
        );
    }
    assert_eq!(std::fs::read_to_string(&graph).unwrap(), text);
}

#[test]
fn two_outputs_of_one_command_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    glass_in(d, "g.json");
    // `--contract X -o X` kept one of the two.
    refused(
        d,
        &["wgsl", "g.json", "--contract", "x.out", "-o", "x.out"],
        &["x.out: the --contract output and the -o output are the same file"],
    );
    assert!(!d.join("x.out").exists());
    // Two graphs with one file name write one image in --out-dir.
    for sub in ["a", "b"] {
        std::fs::create_dir(d.join(sub)).unwrap();
        glass_in(&d.join(sub), "glass.json");
    }
    refused(
        d,
        &[
            "render",
            "a/glass.json",
            "b/glass.json",
            "--size",
            "8x8",
            "--out-dir",
            "out",
        ],
        &[
            "out/glass.png: the output of b/glass.json and the output of a/glass.json are the same file",
        ],
    );
    assert!(!d.join("out/glass.png").exists());
    // A graph named like the contact sheet.
    glass_in(d, "contact_sheet.json");
    refused(
        d,
        &[
            "render",
            "g.json",
            "contact_sheet.json",
            "--size",
            "8x8",
            "--out-dir",
            "out",
        ],
        &["the contact sheet and the output of contact_sheet.json are the same file"],
    );
    // Numbered frames, their EXRs and the animation are distinct files: this one renders.
    let ok = run_in(
        d,
        &[
            "render", "g.json", "--size", "8x8", "-o", "r.png", "--exr", "--frames", "2",
        ],
    );
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
}

#[test]
fn render_never_writes_over_a_file_the_graph_reads() {
    use matgraph::texture::Image;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let img = Image::new(1, 1, vec![[1.0, 0.0, 0.0, 1.0]]).unwrap();
    matgraph::image_io::save_png(&d.join("tex.png"), &img).unwrap();
    let before = std::fs::read(d.join("tex.png")).unwrap();
    std::fs::write(
        d.join("t.json"),
        r#"{ "version": 1, "name": "t", "nodes": [
          { "id": "geo", "type": "geometry" },
          { "id": "tex", "type": "image_texture", "texture": "tex.png", "inputs": { "uv": { "link": "geo.uv" } } } ],
          "outputs": [{ "name": "color", "from": "tex.color" }] }"#,
    )
    .unwrap();
    refused(
        d,
        &["render", "t.json", "--size", "8x8", "-o", "tex.png"],
        &["tex.png: the -o output would overwrite the image tex.png of node 'tex' in t.json"],
    );
    assert_eq!(std::fs::read(d.join("tex.png")).unwrap(), before);
    // The render's own image elsewhere is fine.
    let ok = run_in(d, &["render", "t.json", "--size", "8x8", "-o", "out.png"]);
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
}

#[test]
fn report_never_writes_over_the_family_graphs() {
    // The skin family reads skin.json and skin_dipole.json; its report files are
    // skin.{md,json,svg,png}: `--out` the graphs' folder wrote skin.json over the graph.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let skin = std::fs::read_to_string(root.join("graphs/skin.json")).unwrap();
    std::fs::write(d.join("skin.json"), &skin).unwrap();
    std::fs::copy(
        root.join("graphs/skin_dipole.json"),
        d.join("skin_dipole.json"),
    )
    .unwrap();
    refused(
        d,
        &[
            "report",
            "--graphs",
            ".",
            "--out",
            ".",
            "--family",
            "skin",
            "--quick",
            "--no-timing",
        ],
        &["skin.json: the report file ./skin.json would overwrite the graph ./skin.json"],
    );
    assert_eq!(std::fs::read_to_string(d.join("skin.json")).unwrap(), skin);
}

#[test]
fn edit_screenshot_never_writes_over_its_graph() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (graph, text) = glass_in(d, "g.json");
    // A .png name that leads to the graph (the extension alone does not tell).
    std::os::unix::fs::symlink("g.json", d.join("shot.png")).unwrap();
    refused(
        d,
        &["edit", "g.json", "--screenshot", "shot.png"],
        &["shot.png: the --screenshot output would overwrite the graph g.json"],
    );
    assert_eq!(std::fs::read_to_string(&graph).unwrap(), text);
}

#[test]
fn fmt_still_rewrites_its_own_input() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (graph, text) = glass_in(d, "g.json");
    let value: serde_json::Value = serde_json::from_str(&text).unwrap();
    std::fs::write(&graph, serde_json::to_string(&value).unwrap()).unwrap();
    let out = run_in(d, &["fmt", "g.json"]);
    assert_eq!(String::from_utf8_lossy(&out.stdout), "g.json: rewritten\n");
    assert_eq!(std::fs::read_to_string(&graph).unwrap(), text);
}
