//! Standard output that cannot be written, with real child processes: a pipe whose reader
//! is gone (`matgraph nodes | head -1`) stops the command quietly with status 141 (128 +
//! SIGPIPE, as a shell reports for `cat` cut off the same way); a full disk (`> /dev/full`)
//! stops it with `cannot write to standard output: …` and status 1. Never a panic (101).

use std::io::BufRead;
use std::path::Path;
use std::process::{Command, Output, Stdio};

const GLASS: &str = "graphs/fresnel_glass.json";

/// The commands that print, each with a file it may write (render's image) under `dir`.
fn printing_commands(dir: &Path) -> Vec<Vec<String>> {
    let png = dir.join("out.png").display().to_string();
    let fmt = dir.join("g.json");
    std::fs::copy(GLASS, &fmt).unwrap();
    let fmt = fmt.display().to_string();
    [
        vec!["check", GLASS],
        vec!["nodes"],
        vec!["nodes", "--json"],
        vec!["eval", GLASS],
        vec!["eval", GLASS, "--json"],
        vec!["eval", "--node", "fresnel_schlick"],
        vec!["schema"],
        vec!["wgsl", GLASS],
        vec!["render", GLASS, "--size", "8x8", "-o", &png],
        vec!["fmt", &fmt],
    ]
    .into_iter()
    .map(|v| v.into_iter().map(str::to_owned).collect())
    .collect()
}

/// Runs `args` in the repository root with standard output `stdout`.
fn run_to(args: &[String], stdout: impl Into<Stdio>) -> Output {
    Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(stdout)
        .stderr(Stdio::piped())
        .output()
        .expect("the matgraph binary runs")
}

#[test]
fn a_closed_pipe_stops_quietly_with_status_141() {
    let dir = tempfile::tempdir().unwrap();
    for args in printing_commands(dir.path()) {
        // A pipe whose reading end is closed before the child starts: its first write fails.
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let out = run_to(&args, writer);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(141), "matgraph {args:?}: {stderr}");
        assert_eq!(stderr, "", "matgraph {args:?} says nothing");
    }
    // The render wrote its image before it printed its line.
    let png = std::fs::read(dir.path().join("out.png")).unwrap();
    assert_eq!(&png[..4], b"\x89PNG");
}

#[test]
fn head_reading_one_line_stops_nodes() {
    // `matgraph nodes | head -1`: the listing (about 100 KB) is longer than a pipe's buffer,
    // so the command is still writing when the reader goes.
    let mut child = Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .arg("nodes")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    std::io::BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    assert!(first.starts_with("constant ["), "{first}");
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(141), "{stderr}");
    assert_eq!(stderr, "");
}

#[test]
fn a_full_disk_is_named_as_standard_output() {
    if !Path::new("/dev/full").exists() {
        eprintln!("SKIPPED a_full_disk_is_named_as_standard_output: no /dev/full");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for args in printing_commands(dir.path()) {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let out = run_to(&args, full);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "matgraph {args:?}: {stderr}");
        assert_eq!(
            stderr, "cannot write to standard output: the device is full (no space left)\n",
            "matgraph {args:?}"
        );
    }
    let png = std::fs::read(dir.path().join("out.png")).unwrap();
    assert_eq!(&png[..4], b"\x89PNG");
}
