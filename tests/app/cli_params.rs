//! `matgraph eval --set` refuses parameter values outside the hard range of an input the
//! parameter feeds, naming the file, the parameter, the node, the input and the range.

use std::process::{Command, Output};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the matgraph binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn eval_refuses_a_parameter_outside_a_fed_range() {
    for (file, set, node, input, range) in [
        (
            "graphs/fresnel_glass.json",
            "ior=0",
            "exact",
            "ior_inside",
            "[0.001, 100]",
        ),
        (
            "graphs/fresnel_glass.json",
            "ior=-1",
            "exact",
            "ior_inside",
            "[0.001, 100]",
        ),
        (
            "graphs/skin.json",
            "eta=1e-40",
            "fl",
            "eta_i_over_t",
            "[0.01, 100]",
        ),
    ] {
        let out = run(&["eval", file, "--set", set, "--json"]);
        assert!(!out.status.success(), "{file} --set {set}");
        assert!(
            out.stdout.is_empty(),
            "{file} --set {set}: no outputs printed"
        );
        let err = stderr(&out);
        let name = set.split('=').next().unwrap();
        for part in [
            file.to_owned(),
            format!("parameter '{name}'"),
            format!("input '{input}' of node '{node}'"),
            range.to_owned(),
        ] {
            assert!(
                err.contains(&part),
                "{file} --set {set}: {err:?} lacks {part:?}"
            );
        }
    }
}

#[test]
fn eval_accepts_a_parameter_inside_the_range() {
    // Diamond, n = 2.42, at normal incidence: ((n - 1) / (n + 1))² = 0.17239...
    let out = run(&[
        "eval",
        "graphs/fresnel_glass.json",
        "--set",
        "ior=2.42",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let got = v["reflectance"].as_f64().unwrap();
    let want = ((2.42f64 - 1.0) / (2.42 + 1.0)).powi(2);
    assert!((got - want).abs() < 1e-6, "{got} vs {want}");
}

#[test]
fn eval_refuses_a_parameter_outside_its_own_range() {
    // Issue 37: water_sunshine's `tiling` feeds no ranged input, and 1e38 gave NaN.
    for (file, set, message) in [
        (
            "graphs/water_sunshine.json",
            "tiling=1e38",
            "graphs/water_sunshine.json: --set tiling: parameter 'tiling': 1e38 is outside its range [0, 100]",
        ),
        (
            "graphs/water_sunshine_sunset.json",
            "tiling=-1e38",
            "graphs/water_sunshine_sunset.json: --set tiling: parameter 'tiling': -1e38 is outside its range [0, 100]",
        ),
        (
            "graphs/skin.json",
            "sheen_color=[0.5,2,0.5]",
            "graphs/skin.json: --set sheen_color: parameter 'sheen_color': [0.5,2.0,0.5] is outside its range [0, 1]",
        ),
    ] {
        let out = run(&["eval", file, "--set", set]);
        assert!(!out.status.success(), "{file} --set {set}");
        assert!(
            out.stdout.is_empty(),
            "{file} --set {set}: no outputs printed"
        );
        assert_eq!(stderr(&out).trim_end(), message);
    }
}
