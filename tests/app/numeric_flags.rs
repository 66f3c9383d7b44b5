//! Numeric command-line flags: every float flag refuses NaN, the infinities and values
//! beyond the f32 range, every count has a largest accepted value, and each refusal names
//! the flag, the value and what is accepted (never an abort, a black image or exit 0).

use std::process::{Command, Output};

const GLASS: &str = "graphs/fresnel_glass.json";

fn run<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the matgraph binary runs")
}

/// Runs `args`: a refusal (exit 1, or clap's 2 for a flag's value) whose stderr holds every
/// fragment of `expect`, without a panic.
fn refused<S: AsRef<std::ffi::OsStr> + std::fmt::Debug>(args: &[S], expect: &[&str]) {
    let out = run(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        matches!(out.status.code(), Some(1 | 2)),
        "matgraph {args:?}: status {:?}\n{stderr}",
        out.status
    );
    for fragment in expect {
        assert!(
            stderr.contains(fragment),
            "matgraph {args:?}: stderr lacks {fragment:?}:\n{stderr}"
        );
    }
}

#[test]
fn report_samples_and_repeats_are_bounded() {
    // 4294967295 samples aborted on allocation (or ran out of memory) after minutes.
    refused(
        &["report", "--samples", "4294967295"],
        &["'4294967295'", "--samples", "1..=262144"],
    );
    refused(&["report", "--samples", "0"], &["--samples", "1..=262144"]);
    refused(
        &["report", "--repeats", "4294967295"],
        &["--repeats", "1..=1000"],
    );
    refused(&["report", "--size", "4097x8"], &["--size", "1 to 4096"]);
}

#[test]
fn render_float_flags_refuse_non_finite_values() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("x.png");
    let out = png.to_str().unwrap();
    let render = |extra: &[&str]| -> Vec<String> {
        let mut args: Vec<String> = ["render", GLASS, "--size", "8x8", "-o", out]
            .map(str::to_owned)
            .to_vec();
        args.extend(extra.iter().map(|s| (*s).to_owned()));
        args
    };
    for value in ["NaN", "inf", "-inf", "1e39"] {
        // `--exposure NaN` wrote an all-black PNG with exit 0.
        let flag = format!("--exposure={value}");
        refused(&render(&[&flag]), &["--exposure", value]);
        // `--time NaN` was accepted for a still (and refused only with --frames).
        let flag = format!("--time={value}");
        refused(&render(&[&flag]), &["--time", value]);
        let flag = format!("--fps={value}");
        refused(&render(&["--frames", "2", &flag]), &["--fps", value]);
        // (--max-error is an f64: 1e39 is a finite bound.)
        if value != "1e39" {
            let flag = format!("--max-error={value}");
            refused(&render(&[&flag]), &["--max-error", value]);
        }
    }
    refused(
        &render(&["--exposure", "NaN"]),
        &["NaN is not a finite number"],
    );
    refused(
        &render(&["--time", "1e39"]),
        &["1e39 is beyond the f32 range of ±3.4028235e38"],
    );
    // 2^1000 overflows f32: every pixel would be NaN or infinite.
    refused(
        &render(&["--exposure", "1000"]),
        &["--exposure", "from -64 to 64 stops"],
    );
    refused(
        &render(&["--max-error=-0.5"]),
        &["--max-error", "must be 0 or more"],
    );
    refused(
        &render(&["--frames", "4294967295"]),
        &["--frames 4294967295", "1 to 10000"],
    );
    assert!(!png.exists(), "nothing rendered");
    // Finite values in range still render.
    let ok = run(&render(&["--exposure", "-64", "--time", "-2.5"]));
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    assert!(png.exists());
}

#[test]
fn set_values_say_which_number_is_not_finite() {
    refused(
        &["render", GLASS, "--size", "8x8", "--set", "ior=1e39"],
        &["--set ior=1e39", "beyond the f32 range"],
    );
    refused(
        &["render", GLASS, "--size", "8x8", "--set", "ior=NaN"],
        &["--set ior=NaN", "NaN is not a finite number"],
    );
    refused(
        &["eval", GLASS, "--set", "ior=inf"],
        &[GLASS, "--set ior", "inf is not a finite number"],
    );
    refused(
        &["eval", GLASS, "--set", "uv=[0.5,1e39]"],
        &["--set uv", "beyond the f32 range"],
    );
    refused(
        &["eval", GLASS, "--set", "time=NaN"],
        &["--set time", "NaN is not a finite number"],
    );
    for command in ["eval", "wgsl"] {
        refused(
            &[command, GLASS, "--max-error", "NaN"],
            &["--max-error", "NaN is not a finite number"],
        );
    }
}

#[test]
fn set_numbers_beyond_f32_are_called_out_of_range_not_the_wrong_type() {
    // Parameters, node inputs, attributes and `eval --node` inputs alike: the number as
    // written, said to be beyond the f32 range; never "expected a float value".
    for (args, want) in [
        (
            vec!["eval", GLASS, "--set", "ior=1e39"],
            "--set ior=1e39: 1e39 is beyond the f32 range of ±3.4028235e38",
        ),
        (
            vec!["eval", GLASS, "--set", "exact.ior_outside=-1e39"],
            "--set exact.ior_outside=-1e39: -1e39 is beyond the f32 range",
        ),
        (
            vec!["eval", GLASS, "--set", "view=[0,1e400,0]"],
            "--set view=[0,1e400,0]: 1e400 is beyond the f32 range",
        ),
        (
            vec!["eval", "--node", "add", "--set", "a=3.5e38"],
            "--set a=3.5e38: 3.5e38 is beyond the f32 range",
        ),
        (
            vec!["eval", GLASS, "--set", "ior=-Infinity"],
            "--set ior=-Infinity: -Infinity is not a finite number",
        ),
    ] {
        let out = run(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(
            stderr.contains(want),
            "{args:?}: stderr lacks {want:?}:\n{stderr}"
        );
        for wrong in ["expected a float value", "expected float", "found number"] {
            assert!(!stderr.contains(wrong), "{args:?}: {stderr}");
        }
    }
    // f32::MAX itself is a value.
    let out = run(&["eval", "--node", "add", "--set", "a=3.4028235e38", "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
