//! `matgraph render --frames N --fps F`: numbered stills and an animated PNG (APNG), on the
//! CPU and GPU paths. Frame k must be byte for byte the still rendered at `--time t0 + k/F`,
//! the APNG must decode (with the `png` crate) to the same N frames, each shown 1/F s, and two
//! runs must write the same bytes. Bad counts and rates are refused with a message naming the
//! flag, before anything is written.

use crate::common;

use matgraph::render::frames::{Frames, FramesError};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A graph whose colour turns with time: the normal rotated about z by `time` radians, shown
/// as emission; `sin(time)` tints it, so every frame differs.
const PULSE: &str = r#"{
  "version": 1,
  "name": "pulse",
  "nodes": [
    { "id": "t", "type": "time" },
    { "id": "geo", "type": "geometry" },
    { "id": "r", "type": "rotate", "inputs": {
        "v": { "link": "geo.normal" }, "axis": [0, 0, 1], "angle": { "link": "t.time" } } },
    { "id": "s", "type": "sin", "inputs": { "x": { "link": "t.time" } } },
    { "id": "m", "type": "mix", "inputs": { "a": { "link": "r.result" }, "b": 1.0, "t": { "link": "s.result" } },
      "data_type": "color" },
    { "id": "c", "type": "remap", "inputs": { "x": { "link": "m.result" }, "from_min": -1, "from_max": 1 },
      "data_type": "color" }
  ],
  "outputs": [{ "name": "emission", "from": "c.result" }]
}"#;

fn matgraph(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .current_dir(dir)
        .env("XDG_RUNTIME_DIR", "/tmp")
        .args(args)
        .output()
        .expect("runs")
}

/// Runs `matgraph render pulse.json ARGS` in `dir` and asserts success.
fn render(dir: &Path, args: &[&str]) {
    let mut all = vec!["render", "pulse.json", "--size", "24x16"];
    all.extend_from_slice(args);
    let out = matgraph(dir, &all);
    assert!(
        out.status.success(),
        "{all:?}: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A temporary folder holding the pulse graph.
fn workdir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("pulse.json"), PULSE).unwrap();
    dir
}

/// The files in `dir` other than the graph, sorted.
fn outputs(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "pulse.json")
        .collect();
    v.sort();
    v
}

/// A decoded APNG: plays, then per frame its delay and RGB bytes.
struct Decoded {
    plays: u32,
    frames: Vec<((u16, u16), Vec<u8>)>,
    size: (u32, u32),
}

fn decode_apng(path: &Path) -> Decoded {
    let file = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    let mut reader = png::Decoder::new(file).read_info().unwrap();
    let info = reader.info();
    let actl = info.animation_control.expect("an animated PNG");
    let size = (info.width, info.height);
    assert_eq!(info.color_type, png::ColorType::Rgb);
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    let mut frames = Vec::new();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    for _ in 0..actl.num_frames {
        let out = reader.next_frame(&mut buf).unwrap();
        let fc = reader.info().frame_control.expect("an fcTL per frame");
        assert_eq!(
            (fc.width, fc.height, fc.x_offset, fc.y_offset),
            (size.0, size.1, 0, 0)
        );
        frames.push((
            (fc.delay_num, fc.delay_den),
            buf[..out.buffer_size()].to_vec(),
        ));
    }
    Decoded {
        plays: actl.num_plays,
        frames,
        size,
    }
}

/// The RGB8 bytes of a PNG still.
fn decode_still(path: &Path) -> Vec<u8> {
    image::open(path).unwrap().to_rgb8().into_raw()
}

/// Renders a 5-frame sequence at 4 fps from t0 = 0.5 in `dir`, on `backend`.
fn sequence(dir: &Path, backend: &str) {
    render(
        dir,
        &[
            backend, "--frames", "5", "--fps", "4", "--time", "0.5", "-o", "anim.png",
        ],
    );
}

/// The sequence checks on one backend: files, APNG contents, frames = stills, determinism.
fn check_backend(backend: &str) {
    let dir = workdir();
    let d = dir.path();
    sequence(d, backend);
    let names = outputs(d);
    let want: Vec<String> = std::iter::once("anim.png".to_owned())
        .chain((0..5).map(|k| format!("anim_{k:04}.png")))
        .collect();
    assert_eq!(names, want, "{backend}");

    let apng = decode_apng(&d.join("anim.png"));
    assert_eq!(apng.size, (24, 16));
    assert_eq!(apng.plays, 0, "loops forever");
    assert_eq!(apng.frames.len(), 5);
    let mut distinct = std::collections::BTreeSet::new();
    for (k, (delay, rgb)) in apng.frames.iter().enumerate() {
        assert_eq!(*delay, (1, 4), "frame {k}: 1/4 s");
        let still = decode_still(&d.join(format!("anim_{k:04}.png")));
        assert_eq!(
            rgb, &still,
            "{backend}: APNG frame {k} differs from its still"
        );
        distinct.insert(rgb.clone());
    }
    assert_eq!(
        distinct.len(),
        5,
        "every frame differs: time reached the graph"
    );

    // Frame k is the still at --time 0.5 + k/4, byte for byte (the times are exact in f32).
    for k in 0..5 {
        let t = format!("{}", 0.5 + k as f64 / 4.0);
        let name = format!("still_{k}.png");
        render(d, &[backend, "--time", &t, "-o", &name]);
        let (a, b) = (
            std::fs::read(d.join(format!("anim_{k:04}.png"))).unwrap(),
            std::fs::read(d.join(&name)).unwrap(),
        );
        assert!(
            a == b,
            "{backend}: frame {k} differs from the still at --time {t}"
        );
    }

    // A second run writes the same bytes.
    let again = workdir();
    sequence(again.path(), backend);
    for name in &want {
        let (a, b) = (
            std::fs::read(d.join(name)).unwrap(),
            std::fs::read(again.path().join(name)).unwrap(),
        );
        assert!(a == b, "{backend}: {name} differs between two runs");
    }
}

#[test]
fn cpu_sequence_writes_stills_and_an_apng_of_them() {
    check_backend("--cpu");
}

#[test]
fn gpu_sequence_writes_stills_and_an_apng_of_them() {
    if common::gpu_context("gpu_sequence_writes_stills_and_an_apng_of_them").is_none() {
        return;
    }
    check_backend("--gpu");
}

#[test]
fn without_time_the_sequence_starts_at_the_scene_time_and_time_alone_is_one_still() {
    let dir = workdir();
    let d = dir.path();
    render(d, &["--frames", "2", "-o", "seq.png"]);
    render(d, &["-o", "default.png"]);
    render(d, &["--time", "3.25", "-o", "t.png"]);
    assert_eq!(
        outputs(d),
        [
            "default.png",
            "seq.png",
            "seq_0000.png",
            "seq_0001.png",
            "t.png"
        ]
    );
    assert_eq!(
        std::fs::read(d.join("seq_0000.png")).unwrap(),
        std::fs::read(d.join("default.png")).unwrap(),
        "frame 0 without --time is the scene-time still"
    );
    // The default rate is 24 fps.
    assert_eq!(decode_apng(&d.join("seq.png")).frames[1].0, (1, 24));
}

#[test]
fn out_dir_writes_one_sequence_per_graph() {
    let dir = workdir();
    let d = dir.path();
    std::fs::copy(d.join("pulse.json"), d.join("second.json")).unwrap();
    let out = matgraph(
        d,
        &[
            "render",
            "pulse.json",
            "second.json",
            "--size",
            "8x8",
            "--frames",
            "2",
            "--fps",
            "10",
            "--out-dir",
            "r",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let names = outputs(&d.join("r"));
    assert_eq!(
        names,
        [
            "contact_sheet.png",
            "pulse.png",
            "pulse_0000.png",
            "pulse_0001.png",
            "second.png",
            "second_0000.png",
            "second_0001.png"
        ]
    );
    assert_eq!(decode_apng(&d.join("r/second.png")).frames.len(), 2);
}

#[test]
fn bad_counts_and_rates_are_refused_before_anything_is_written() {
    let dir = workdir();
    let d = dir.path();
    let cases: &[(&[&str], &str)] = &[
        (
            &["--frames", "0"],
            "--frames 0: the number of frames must be 1 to 10000",
        ),
        (
            &["--frames", "10001"],
            "--frames 10001: the number of frames must be 1 to 10000",
        ),
        (
            &["--frames", "3", "--fps", "0"],
            "--fps 0: the frame rate must be a number from 0.001 to 1000",
        ),
        (
            &["--frames", "3", "--fps", "-2"],
            "--fps -2: the frame rate must be a number",
        ),
        (
            &["--frames", "3", "--fps", "NaN"],
            "invalid value 'NaN' for '--fps <FPS>': NaN is not a finite number",
        ),
        (
            &["--frames", "3", "--fps", "inf"],
            "invalid value 'inf' for '--fps <FPS>': inf is not a finite number",
        ),
        (
            &["--frames", "3", "--fps", "1e6"],
            "--fps 1000000: the frame rate must be a number",
        ),
        (&["--frames", "-1"], "invalid value '-1' for '--frames <N>'"),
        (
            &["--frames", "3", "--fps", "x"],
            "invalid value 'x' for '--fps <FPS>'",
        ),
        (
            &["--fps", "3"],
            "the following required arguments were not provided",
        ),
        (
            &["--frames", "3", "-o", "a.jpg"],
            "--frames writes an animated PNG: -o must end in .png",
        ),
        (
            &["--frames", "3", "-o", "a.exr"],
            "--frames writes an animated PNG: -o must end in .png",
        ),
        (
            &["--frames", "3", "--time", "NaN"],
            "invalid value 'NaN' for '--time <TIME>': NaN is not a finite number",
        ),
    ];
    for (args, message) in cases {
        let mut all = vec!["render", "pulse.json", "--size", "8x8"];
        all.extend_from_slice(args);
        if !args.contains(&"-o") {
            all.extend(["-o", "bad.png"]);
        }
        let out = matgraph(d, &all);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(
            stderr.contains(message),
            "{args:?}: stderr {stderr:?} lacks {message:?}"
        );
        assert_eq!(outputs(d), Vec::<String>::new(), "{args:?} wrote files");
    }
    let out = matgraph(
        d,
        &[
            "render",
            "pulse.json",
            "pulse.json",
            "--frames",
            "2",
            "-o",
            "sheet.png",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("use --out-dir"), "{stderr}");
}

#[test]
fn frame_times_delays_and_names() {
    let f = Frames::new(5, 4.0).unwrap();
    assert_eq!(f.times(0.5).unwrap(), [0.5, 0.75, 1.0, 1.25, 1.5]);
    // In f64, then rounded once: 1/3 s steps from 0.1 are the f32s nearest 0.1 + k/3.
    let f3 = Frames::new(4, 3.0).unwrap();
    for (k, t) in f3.times(0.1).unwrap().into_iter().enumerate() {
        assert_eq!(t, (0.1f32 as f64 + k as f64 / 3.0) as f32);
    }
    assert_eq!(Frames::new(2, 24.0).unwrap().delay(), (1, 24));
    assert_eq!(Frames::new(2, 0.5).unwrap().delay(), (2, 1));
    // 29.97 fps (NTSC, 30000/1001): a delay of 1001/30000 s is within 2e-9 of 1/29.97.
    let (n, d) = Frames::new(2, 29.97).unwrap().delay();
    assert!(
        (n as f64 / d as f64 - 1.0 / 29.97f32 as f64).abs() < 1e-8,
        "{n}/{d}"
    );
    assert_eq!(Frames::new(0, 24.0), Err(FramesError::FrameCount(0)));
    assert!(matches!(Frames::new(1, f32::NAN), Err(FramesError::Fps(_))));
    assert_eq!(
        Frames::numbered(Path::new("out/anim.png"), 7),
        PathBuf::from("out/anim_0007.png")
    );
}

/// The scene's own time-dependent parts (the bubble's motion towards its target) follow each
/// frame's time too: frame 1 is the still at that `--time`, and differs from frame 0.
#[test]
fn scene_motion_follows_the_frame_time() {
    let graph = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/bubble.json");
    let graph = graph.to_str().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let run = |args: &[&str]| {
        let mut all = vec!["render", graph, "--size", "32x32"];
        all.extend_from_slice(args);
        let out = matgraph(d, &all);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    run(&["--frames", "2", "--fps", "1", "--time", "1", "-o", "b.png"]);
    run(&["--time", "2", "-o", "t2.png"]);
    let read = |n: &str| std::fs::read(d.join(n)).unwrap();
    assert!(
        read("b_0001.png") == read("t2.png"),
        "frame 1 is the still at --time 2"
    );
    assert!(read("b_0000.png") != read("b_0001.png"), "the bubble moved");
}
