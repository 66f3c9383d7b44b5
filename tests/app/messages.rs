//! User-facing messages (issue 37, item 15): no Rust type names or debug structs, paths
//! named once with what is wrong with them, negative numeric flags taken, and control and
//! bidirectional characters of user text spelt out, never echoed raw.

use std::path::Path;
use std::process::{Command, Output};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the matgraph binary runs")
}

/// Runs `args`, expects exit status 1; returns stderr.
fn refused(args: &[&str]) -> String {
    let out = run(args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "matgraph {args:?}: {stderr}");
    stderr
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    if let Some(parent) = p.parent() {
        std::fs::create_dir_all(parent).unwrap();
    }
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_owned()
}

/// Words a user never wrote: serde's and Rust's names for the types.
const INTERNAL: [&str; 9] = [
    "NodeDocument",
    "TextureSource",
    "SceneDoc",
    "CameraDoc",
    "untagged enum",
    "expected struct",
    "ChunkType {",
    "os error",
    "SampleBatch",
];

fn assert_plain(what: &str, stderr: &str) {
    for word in INTERNAL {
        assert!(!stderr.contains(word), "{what}: {word:?} in {stderr:?}");
    }
}

#[test]
fn malformed_documents_are_described_in_the_users_words() {
    let dir = tempfile::tempdir().unwrap();
    let node = write(
        dir.path(),
        "node.json",
        r#"{"version":1,"name":"t","nodes":["x"],"outputs":[]}"#,
    );
    let e = refused(&["check", &node]);
    assert!(e.contains("expected a node object"), "{e}");
    assert_plain("a node that is a string", &e);
    let tex = write(
        dir.path(),
        "tex.json",
        r#"{"version":1,"name":"t","nodes":[{"id":"t","type":"image_texture","texture":5}],"outputs":[]}"#,
    );
    let e = refused(&["check", &tex]);
    assert!(
        e.contains(
            "node 't': an image path, a list of image paths (a mip chain) or \"scene:NAME\""
        ),
        "{e}"
    );
    assert_plain("a texture that is a number", &e);
    let graph = r#"{"version":1,"name":"t","scene":SCENE,"nodes":[{"id":"k","type":"parameter","inputs":{"value":1.0}}],"outputs":[{"name":"o","from":"k.value"}]}"#;
    for (scene, expect) in [
        ("5", "expected a scene object"),
        (r#"{"camera":5}"#, "expected a camera object"),
    ] {
        let p = write(dir.path(), "s.json", &graph.replace("SCENE", scene));
        let png = dir.path().join("x.png");
        let e = refused(&["render", &p, "-o", png.to_str().unwrap(), "--size", "8x8"]);
        assert!(e.contains(expect), "{e}");
        assert_plain(scene, &e);
    }
}

#[test]
fn a_file_where_a_folder_belongs_is_named_with_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), "afile", "x");
    let e = refused(&[
        "render",
        "graphs/fresnel_glass.json",
        "--out-dir",
        &file,
        "--size",
        "8x8",
    ]);
    assert_eq!(
        e,
        format!(
            "--out-dir {file}: a file is there, not a folder; name a folder (it is made if missing)\n"
        )
    );
    let below = format!("{file}/sub");
    let e = refused(&[
        "render",
        "graphs/fresnel_glass.json",
        "--out-dir",
        &below,
        "--size",
        "8x8",
    ]);
    assert_eq!(
        e,
        format!("--out-dir {below}: cannot make the folder: {file} is a file, not a folder\n")
    );
    if Path::new("/dev/full").exists() {
        let e = refused(&["report", "--out", "/dev/full", "--quick", "--no-timing"]);
        assert_eq!(
            e,
            "--out /dev/full: a device is there, not a folder; name a folder (it is made if missing)\n"
        );
    }
    // The contract's path once, and the missing folder named.
    let contract = dir.path().join("nowhere/c.json");
    let c = contract.to_str().unwrap();
    let e = refused(&["wgsl", "graphs/fresnel_glass.json", "--contract", c]);
    assert_eq!(
        e,
        format!(
            "{c}: cannot write: the folder {} does not exist\n",
            dir.path().join("nowhere").display()
        )
    );
    let under = format!("{file}/c.json");
    let e = refused(&["wgsl", "graphs/fresnel_glass.json", "--contract", &under]);
    assert_eq!(
        e,
        format!("{under}: cannot write: {file} is a file, not a folder\n")
    );
}

#[test]
fn a_scene_files_environment_is_refused_for_the_scenes_folder() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/fresnel_glass.json"),
    )
    .unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    doc["scene"] = "sub/scene.json".into();
    let g = write(dir.path(), "g/glass.json", &doc.to_string());
    write(
        dir.path(),
        "g/sub/scene.json",
        r#"{"kind":"ball","environment":{"image":{"path":"../../away.hdr"}}}"#,
    );
    let png = dir.path().join("x.png");
    let e = refused(&["render", &g, "-o", png.to_str().unwrap(), "--size", "8x8"]);
    let sub = dir.path().canonicalize().unwrap().join("g/sub");
    assert!(
        e.contains(&format!("outside the scene's folder {}", sub.display()))
            && !e.contains("graph's folder"),
        "{e}"
    );
}

#[test]
fn negative_and_non_finite_times_are_taken_then_judged() {
    for args in [["--time", "-inf"], ["--time=-inf", ""]] {
        let mut all = vec!["render", "graphs/fresnel_glass.json", "--size", "8x8"];
        all.extend(args.iter().filter(|a| !a.is_empty()));
        let out = run(&all);
        let e = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?}");
        assert!(
            e.contains("-inf is not a finite number (NaN and infinities are refused)"),
            "{args:?}: {e}"
        );
        assert!(!e.contains("unexpected argument"), "{e}");
    }
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("t.png");
    let out = run(&[
        "render",
        "graphs/fresnel_glass.json",
        "-o",
        png.to_str().unwrap(),
        "--size",
        "8x8",
        "--time",
        "-1.5",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_corrupt_png_is_described_without_a_debug_struct() {
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/textures");
    let src = std::fs::read_dir(root.join("brick"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "png"))
        .unwrap();
    let mut png = std::fs::read(src).unwrap();
    png[29] ^= 0xff; // the IHDR chunk's CRC
    std::fs::create_dir_all(dir.path().join("t")).unwrap();
    std::fs::write(dir.path().join("t/bad.png"), png).unwrap();
    let g = write(
        dir.path(),
        "g.json",
        r#"{"version":1,"name":"t","nodes":[{"id":"geo","type":"geometry"},{"id":"tex","type":"image_texture","texture":"t/bad.png","inputs":{"uv":{"link":"geo.uv"}}}],"outputs":[{"name":"o","from":"tex.color"}]}"#,
    );
    let e = refused(&["eval", &g]);
    assert!(
        e.contains("CRC error") && e.contains("while decoding IHDR chunk"),
        "{e}"
    );
    assert_plain("a PNG with a bad CRC", &e);
}

/// Bytes that act on a terminal or reorder text: ESC, BEL, NUL, U+202E, CR.
fn raw_controls(s: &str) -> Vec<char> {
    s.chars()
        .filter(|&c| (c.is_control() && c != '\n') || c == '\u{202e}')
        .collect()
}

#[test]
fn control_and_bidi_characters_of_user_text_are_spelt_out() {
    let dir = tempfile::tempdir().unwrap();
    // A node id, output, parameter and graph name with an ANSI escape, BEL, NUL, U+202E and
    // line breaks: every message that echoes one shows it escaped, one error per line.
    let g = write(
        dir.path(),
        "ctl.json",
        "{ \"version\": 1, \"name\": \"t\\u001b[31m\\r\\n\", \"nodes\": [ { \"id\": \"a\\u0007b\\u202e\\n\\u0000\", \"type\": \"parameter\", \"inputs\": { \"value\": 1.0 } } ], \"outputs\": [ { \"name\": \"o\\u001b\", \"from\": \"k.value\" } ], \"parameters\": [ { \"name\": \"p\\u202e\", \"node\": \"zz\" } ] }",
    );
    let e = refused(&["check", &g]);
    assert!(raw_controls(&e).is_empty(), "{e:?}");
    assert!(
        e.contains(r"node 'a\u{7}b\u{202e}\n\u{0}': invalid node id"),
        "{e}"
    );
    assert!(e.contains(r"parameter 'p\u{202e}'"), "{e}");
    // Three errors and the summary: four lines, a line break inside an id adds none.
    assert_eq!(e.lines().count(), 4, "{e}");
    let e = refused(&[
        "eval",
        "graphs/fresnel_glass.json",
        "--output",
        "x\u{1b}[31m\n\u{202e}",
    ]);
    assert!(
        raw_controls(&e).is_empty() && e.lines().count() == 1,
        "{e:?}"
    );
    assert!(e.contains(r"unknown output 'x\u{1b}[31m\n\u{202e}'"), "{e}");
    let e = refused(&["eval", "graphs/fresnel_glass.json", "--set", "\u{7}zz=1"]);
    assert!(raw_controls(&e).is_empty(), "{e:?}");
    // A graph name with a carriage return: naga parsed the comment's rest as code.
    let named = write(
        dir.path(),
        "named.json",
        r#"{"version":1,"name":"a\rb\u2028c\u001b","nodes":[{"id":"k","type":"parameter","inputs":{"value":1.0}}],"outputs":[{"name":"o","from":"k.value"}]}"#,
    );
    let out = run(&["wgsl", &named]);
    let wgsl = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        wgsl.starts_with(r"// Generated by matgraph ")
            && wgsl
                .lines()
                .next()
                .unwrap()
                .contains(r"graph 'a\rb\u{2028}c\u{1b}'"),
        "{wgsl}"
    );
    assert!(raw_controls(&wgsl).is_empty());
}
