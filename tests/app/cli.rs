//! The `matgraph` binary, run as a user would: exit codes, stdout and stderr of every
//! subcommand. Numbers are checked against f64 formulas written out here.

use matgraph::{Graph, Registry};
use serde_json::Value as J;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

// ---------------------------------------------------------------------------------------
// Helpers: one per boundary.
// ---------------------------------------------------------------------------------------

const GLASS: &str = "graphs/fresnel_glass.json";

/// Runs the binary in the repository root.
fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the matgraph binary runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8(bytes.to_vec()).expect("UTF-8 output")
}

/// Runs `args`, expects exit 0 and an empty stderr; returns stdout.
fn ok(args: &[&str]) -> String {
    let out = run(args);
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(
        out.status.success(),
        "matgraph {args:?} failed ({}):\nstdout:\n{stdout}\nstderr:\n{stderr}",
        out.status
    );
    assert_eq!(stderr, "", "matgraph {args:?} wrote to stderr");
    stdout
}

/// Runs `args`, expects a non-zero exit and every fragment of `expect` on stderr; returns
/// (stdout, stderr).
fn fails(args: &[&str], expect: &[&str]) -> (String, String) {
    let out = run(args);
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(
        !out.status.success(),
        "matgraph {args:?} succeeded:\nstdout:\n{stdout}\nstderr:\n{stderr}"
    );
    assert_eq!(out.status.code(), Some(1), "matgraph {args:?}: {stderr}");
    for fragment in expect {
        assert!(
            stderr.contains(fragment),
            "matgraph {args:?}: stderr lacks {fragment:?}:\n{stderr}"
        );
    }
    (stdout, stderr)
}

/// Runs `matgraph eval ... --json` and compares its one JSON object with `expect`: the same
/// keys in the same order, numbers within 1e-6 (arrays component-wise), bools exactly.
fn check_eval(args: &[&str], expect: &[(&str, J)]) {
    let mut full = vec!["eval"];
    full.extend_from_slice(args);
    full.push("--json");
    let stdout = ok(&full);
    assert_eq!(
        stdout.lines().count(),
        1,
        "eval --json prints one line:\n{stdout}"
    );
    let actual: J = serde_json::from_str(&stdout).expect("eval --json prints JSON");
    let map = actual.as_object().expect("a JSON object");
    let keys: Vec<&str> = map.keys().map(String::as_str).collect();
    let expected_keys: Vec<&str> = expect.iter().map(|(k, _)| *k).collect();
    assert_eq!(keys, expected_keys, "{args:?}: {stdout}");
    for (name, want) in expect {
        let got = &map[*name];
        let close = |a: &J, b: &J| match (a.as_f64(), b.as_f64()) {
            (Some(x), Some(y)) => (x - y).abs() <= 1e-6,
            _ => a == b,
        };
        let same = match (got, want) {
            (J::Array(a), J::Array(b)) => {
                a.len() == b.len() && a.iter().zip(b).all(|(x, y)| close(x, y))
            }
            _ => close(got, want),
        };
        assert!(same, "{args:?}: {name} = {got}, expected {want}");
    }
}

fn num(x: f64) -> J {
    serde_json::json!(x)
}

fn temp_copy(dir: &Path, name: &str, contents: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, contents).unwrap();
    path
}

// ---------------------------------------------------------------------------------------
// f64 references.
// ---------------------------------------------------------------------------------------

/// Exact unpolarised Fresnel reflectance, light arriving from the `n1` side.
fn fresnel(cos_i: f64, n1: f64, n2: f64) -> f64 {
    let sin2_t = (n1 / n2).powi(2) * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
    let rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// Normal-incidence reflectance from air.
fn r0(n: f64) -> f64 {
    ((n - 1.0) / (n + 1.0)).powi(2)
}

fn schlick(cos: f64, f0: f64) -> f64 {
    f0 + (1.0 - f0) * (1.0 - cos).powi(5)
}

/// The glass graph's three outputs for index `n` seen at `cos` (N·V).
fn glass(n: f64, cos: f64) -> Vec<(&'static str, J)> {
    vec![
        ("reflectance", num(fresnel(cos, 1.0, n))),
        ("schlick", num(schlick(cos, r0(n)))),
        ("specular", num(r0(n) / 0.08)),
    ]
}

#[test]
fn references_match_the_textbook_values() {
    assert!((r0(1.52) - 0.042580).abs() < 1e-6);
    assert!((r0(2.42) - 0.172395).abs() < 1e-6);
    assert!((fresnel(1.0, 1.0, 1.52) - r0(1.52)).abs() < 1e-12);
    // Brewster's angle (tan θ = n): rp vanishes and rs = (1 − n²)/(1 + n²).
    let n = 1.52f64;
    let rs = (1.0 - n * n) / (1.0 + n * n);
    assert!((fresnel(n.atan().cos(), 1.0, n) - rs * rs / 2.0).abs() < 1e-12);
    // Total internal reflection from the dense side past the critical angle.
    assert_eq!(fresnel(0.5, 1.52, 1.0), 1.0);
}

// ---------------------------------------------------------------------------------------
// --help
// ---------------------------------------------------------------------------------------

#[test]
fn help_for_every_subcommand() {
    let cases: &[(&str, &[&str])] = &[
        ("check", &["<FILES>..."]),
        ("nodes", &["--json"]),
        (
            "eval",
            &[
                "[FILE]",
                "--node <TYPE>",
                "--set <NAME=VALUE>",
                "--output <NODE.OUTPUT>",
                "--json",
                "NODE.INPUT=VALUE",
            ],
        ),
        ("schema", &["-o, --output <OUTPUT>"]),
        (
            "wgsl",
            &[
                "--target <TARGET>",
                "--entry <ENTRY>",
                "--bake",
                "-o, --out <OUT>",
            ],
        ),
        ("fmt", &["<FILES>...", "--check"]),
    ];
    let top = ok(&["--help"]);
    for (sub, options) in cases {
        assert!(
            top.lines()
                .any(|l| l.trim_start().starts_with(&format!("{sub} "))),
            "top-level help lacks {sub}:\n{top}"
        );
        for help in [ok(&[sub, "--help"]), ok(&["help", sub])] {
            assert!(
                help.contains(&format!("Usage: matgraph {sub}")),
                "{sub}:\n{help}"
            );
            for option in *options {
                assert!(
                    help.contains(option),
                    "{sub} --help lacks {option}:\n{help}"
                );
            }
        }
    }
}

#[test]
fn unknown_subcommand_and_missing_arguments_fail() {
    let out = run(&["frobnicate"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("unrecognized subcommand"));
    let out = run(&["check"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("<FILES>..."));
}

// ---------------------------------------------------------------------------------------
// check
// ---------------------------------------------------------------------------------------

#[test]
fn check_a_good_file() {
    let stdout = ok(&["check", GLASS]);
    assert_eq!(
        stdout,
        "graphs/fresnel_glass.json: ok (7 nodes, 3 outputs)\n"
    );
}

#[test]
fn check_a_bad_file_lists_every_error() {
    let dir = tempfile::tempdir().unwrap();
    let bad = temp_copy(
        dir.path(),
        "bad.json",
        r#"{"version": 1, "name": "bad", "nodes": [
            {"id": "geo", "type": "geometry"},
            {"id": "fr", "type": "fresnel_dielectric", "inputs": {"cos_theta": {"link": "geo.uv"}, "ior_insde": 1.5}},
            {"id": "x", "type": "fresnel_dielectrc"}
        ]}"#,
    );
    let path = bad.to_str().unwrap();
    let (stdout, stderr) = fails(&["check", path], &[]);
    assert_eq!(stdout, format!("{path}: 3 errors\n"));
    let expected = [
        format!(
            "{path}: node 'x': unknown node type 'fresnel_dielectrc' (did you mean 'fresnel_dielectric'?)"
        ),
        format!("{path}: node 'fr': unknown input 'ior_insde' (did you mean 'ior_inside'?)"),
        format!(
            "{path}: node 'fr': input 'cos_theta': cannot connect 'geo.uv' (vec2) to 'fr.cos_theta' (float): no implicit conversion"
        ),
        "1 of 1 file failed".to_owned(),
    ];
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines, expected, "{stderr}");
}

#[test]
fn check_a_malformed_file_gives_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let bad = temp_copy(
        dir.path(),
        "syntax.json",
        "{\n  \"version\": 1,\n  \"name\": }\n",
    );
    let path = bad.to_str().unwrap();
    fails(
        &["check", path],
        &[&format!(
            "{path}: malformed JSON at line 3, column 11: expected value"
        )],
    );
}

#[test]
fn check_several_files_prints_one_line_per_file() {
    let dir = tempfile::tempdir().unwrap();
    let glass = std::fs::read_to_string(glass_path()).unwrap();
    let a = temp_copy(dir.path(), "a.json", &glass);
    let b = temp_copy(dir.path(), "b.json", &glass.replace("\"dot\"", "\"dott\""));
    let c = temp_copy(dir.path(), "c.json", &glass);
    let (a, b, c) = (
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        c.to_str().unwrap(),
    );

    let stdout = ok(&["check", a, c]);
    assert_eq!(
        stdout,
        format!("{a}: ok (7 nodes, 3 outputs)\n{c}: ok (7 nodes, 3 outputs)\n")
    );

    let (stdout, stderr) = fails(
        &["check", a, b, c],
        &[
            &format!("{b}: node 'cos': unknown node type 'dott' (did you mean 'dot'?)"),
            "1 of 3 files failed",
        ],
    );
    assert_eq!(
        stdout,
        format!("{a}: ok (7 nodes, 3 outputs)\n{b}: 1 error\n{c}: ok (7 nodes, 3 outputs)\n")
    );
    assert!(!stderr.contains(a) && !stderr.contains(c), "{stderr}");
}

#[test]
fn check_a_missing_file() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.json");
    let path = missing.to_str().unwrap();
    let (stdout, _) = fails(
        &["check", path],
        &[&format!("cannot read {path}: no such file")],
    );
    assert_eq!(stdout, format!("{path}: 1 error\n"));
}

#[test]
fn check_refuses_what_eval_and_render_refuse_with_their_message() {
    // Issue 37: `check` passed (a) a parameter value whose hoisted product leaves a fed
    // input's hard range (the planner's check), (b) an unknown scene texture, (c) a scene
    // file that is not there; `eval` and `render` refused them.
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "hoisted.json",
            r#"{ "version": 1, "name": "t",
  "nodes": [ { "id": "k", "type": "parameter", "inputs": { "value": 5.0 } },
             { "id": "m", "type": "mul", "inputs": { "a": { "link": "k.value" }, "b": 30.0 } },
             { "id": "f", "type": "fresnel_dielectric", "inputs": { "ior_inside": { "link": "m.result" } } } ],
  "outputs": [ { "name": "o", "from": "f.reflectance" } ],
  "parameters": [ { "name": "ior", "node": "k" } ] }"#,
            "parameter 'ior': input 'ior_inside' of node 'f', which it feeds, would get 150.0, outside its hard range [0.001, 100]",
        ),
        (
            "bogus.json",
            r#"{ "version": 1, "name": "t",
  "nodes": [ { "id": "geo", "type": "geometry" },
             { "id": "tex", "type": "image_texture", "texture": "scene:bogus", "inputs": { "uv": { "link": "geo.uv" } } } ],
  "outputs": [ { "name": "o", "from": "tex.color" } ] }"#,
            "node 'tex': unknown scene texture 'scene:bogus': a scene supplies scene:background, scene:refraction, scene:reflection, scene:environment, scene:environment_ggx, scene:brdf_lut, scene:environment_sh",
        ),
        (
            "no_scene.json",
            r#"{ "version": 1, "name": "t", "scene": "room.json",
  "nodes": [ { "id": "k", "type": "parameter", "inputs": { "value": 1.0 } } ],
  "outputs": [ { "name": "o", "from": "k.value" } ] }"#,
            "room.json",
        ),
    ];
    for (name, json, message) in cases {
        let path = temp_copy(dir.path(), name, json);
        let p = path.to_str().unwrap();
        let (stdout, check) = fails(&["check", p], &[message]);
        assert_eq!(stdout, format!("{p}: 1 error\n"));
        let png = dir.path().join("x.png");
        let (_, render) = fails(
            &["render", p, "-o", png.to_str().unwrap(), "--size", "8x8"],
            &[message],
        );
        // The same first line: the file, then the same words.
        let first = |s: &str| s.lines().next().unwrap_or_default().to_owned();
        assert_eq!(first(&check), first(&render), "{name}");
        assert!(first(&check).starts_with(&format!("{p}: ")), "{check}");
        if name != "no_scene.json" {
            let (_, eval) = fails(&["eval", p], &[message]);
            assert_eq!(first(&check), first(&eval), "{name}");
        }
        assert!(!check.contains("SampleBatch"), "{check}");
    }
}

fn glass_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(GLASS)
}

// ---------------------------------------------------------------------------------------
// nodes
// ---------------------------------------------------------------------------------------

#[test]
fn nodes_lists_every_type() {
    let stdout = ok(&["nodes"]);
    let types = Registry::builtin().types();
    assert!(!types.is_empty());
    let headers: Vec<&str> = stdout
        .lines()
        .filter(|l| !l.starts_with(' ') && !l.is_empty())
        .collect();
    assert_eq!(headers.len(), types.len(), "{stdout}");
    for (t, header) in types.iter().zip(&headers) {
        assert!(
            header.starts_with(&format!("{} [{}] — ", t.name(), t.category())),
            "{header}"
        );
        for i in t.inputs() {
            assert!(
                stdout.contains(&format!("    in  {:<14} {:<6}", i.name, i.ty.to_string())),
                "{}: input {} missing",
                t.name(),
                i.name
            );
        }
    }
}

#[test]
fn nodes_json_describes_every_port() {
    let stdout = ok(&["nodes", "--json"]);
    let list: J = serde_json::from_str(&stdout).expect("nodes --json prints JSON");
    let list = list.as_array().expect("an array");
    let types = Registry::builtin().types();
    assert_eq!(list.len(), types.len());
    let range = |r: Option<matgraph::node::Range>| match r {
        Some(r) => serde_json::json!([r.min as f64, r.max as f64]),
        None => J::Null,
    };
    for (entry, t) in list.iter().zip(types) {
        assert_eq!(entry["name"], t.name());
        assert_eq!(entry["category"], t.category().name());
        assert_eq!(entry["summary"], t.summary());
        assert_eq!(entry["source"], t.source_doc());
        let inputs = entry["inputs"].as_array().expect("inputs");
        assert_eq!(inputs.len(), t.inputs().len(), "{}", t.name());
        for (j, i) in inputs.iter().zip(t.inputs()) {
            let at = format!("{}.{}", t.name(), i.name);
            assert_eq!(j["name"], i.name, "{at}");
            assert_eq!(j["type"], i.ty.to_string(), "{at}");
            assert_eq!(j["default"], i.default.to_json(), "{at}");
            assert_eq!(j["soft_range"], range(i.soft), "{at}");
            assert_eq!(j["hard_range"], range(i.hard), "{at}");
            assert_eq!(j["unit"], i.unit, "{at}");
            assert_eq!(j["doc"], i.doc, "{at}");
            assert!(!i.doc.is_empty(), "{at} has no doc");
            assert_eq!(j["choices"], serde_json::json!(i.choices), "{at}");
        }
        let outputs = entry["outputs"].as_array().expect("outputs");
        assert_eq!(outputs.len(), t.outputs().len(), "{}", t.name());
        for (j, o) in outputs.iter().zip(t.outputs()) {
            let at = format!("{}.{}", t.name(), o.name);
            assert_eq!(j["name"], o.name, "{at}");
            assert_eq!(j["type"], o.ty.to_string(), "{at}");
            assert_eq!(j["unit"], o.unit, "{at}");
            assert_eq!(j["doc"], o.doc, "{at}");
        }
        let generic = if t.is_generic() {
            serde_json::json!(
                t.generic_types()
                    .iter()
                    .map(|g| g.name())
                    .collect::<Vec<_>>()
            )
        } else {
            J::Null
        };
        assert_eq!(entry["generic_types"], generic, "{}", t.name());
    }
    // Spot-check one declaration against its literal values.
    let fr = list
        .iter()
        .find(|e| e["name"] == "fresnel_dielectric")
        .expect("fresnel_dielectric is listed");
    assert_eq!(fr["inputs"][0]["name"], "cos_theta");
    assert_eq!(fr["inputs"][0]["type"], "float");
    assert_eq!(fr["inputs"][0]["default"], 1.0);
    assert_eq!(
        fr["inputs"][0]["hard_range"],
        serde_json::json!([-1.0, 1.0])
    );
    assert_eq!(fr["inputs"][2]["default"], 1.5);
    assert_eq!(fr["outputs"][1]["name"], "transmittance");
}

// ---------------------------------------------------------------------------------------
// eval a graph
// ---------------------------------------------------------------------------------------

#[test]
fn eval_glass_at_normal_incidence() {
    check_eval(&[GLASS], &glass(1.52, 1.0));
    // The brief's numbers, written out.
    check_eval(
        &[GLASS],
        &[
            ("reflectance", num(0.042580)),
            ("schlick", num(0.042580)),
            ("specular", num(0.042580 / 0.08)),
        ],
    );
}

#[test]
fn eval_text_output_names_every_output() {
    let stdout = ok(&["eval", GLASS]);
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 3, "{stdout}");
    assert!(lines[0].starts_with("reflectance = 0.0425"), "{stdout}");
    assert!(lines[0].ends_with("(float)"), "{stdout}");
    assert!(lines[1].starts_with("schlick     = "), "{stdout}");
    assert!(lines[2].starts_with("specular    = 0.532"), "{stdout}");
}

#[test]
fn eval_sets_a_parameter() {
    // Diamond: R0 = (1.42 / 3.42)² ≈ 0.172395.
    check_eval(&[GLASS, "--set", "ior=2.42"], &glass(2.42, 1.0));
    check_eval(&[GLASS, "--set", "ior = 1.0"], &glass(1.0, 1.0));
}

#[test]
fn eval_sets_the_view_direction() {
    // V = (sin 30°, 0, cos 30°) against N = +z: N·V = cos 30°, 30° incidence.
    let cos30 = 0.8660254f64;
    check_eval(
        &[GLASS, "--set", "view=[0.5,0,0.8660254]"],
        &glass(1.52, cos30),
    );
    // V = (sin 60°, 0, cos 60°): 60° incidence.
    check_eval(
        &[GLASS, "--set", "view=[0.8660254,0,0.5]"],
        &glass(1.52, 0.5),
    );
    // The angle moves the exact reflectance, not the normal-incidence specular.
    assert!(fresnel(0.5, 1.0, 1.52) > fresnel(cos30, 1.0, 1.52) + 0.01);
    // Both the view and the parameter.
    check_eval(
        &[
            GLASS,
            "--set",
            "view=[0.8660254,0,0.5]",
            "--set",
            "ior=2.42",
        ],
        &glass(2.42, 0.5),
    );
}

#[test]
fn eval_sets_a_node_input() {
    // Light arriving from inside a denser medium than the glass.
    check_eval(
        &[GLASS, "--set", "exact.ior_outside=1.7"],
        &[
            ("reflectance", num(fresnel(1.0, 1.7, 1.52))),
            ("schlick", num(r0(1.52))),
            ("specular", num(r0(1.52) / 0.08)),
        ],
    );
}

#[test]
fn eval_selects_outputs() {
    check_eval(
        &[GLASS, "--output", "exact.transmittance"],
        &[("exact.transmittance", num(1.0 - r0(1.52)))],
    );
    check_eval(
        &[
            GLASS,
            "--output",
            "specular",
            "--output",
            "cos.result",
            "--output",
            "f0.f0",
        ],
        &[
            ("specular", num(r0(1.52) / 0.08)),
            ("cos.result", num(1.0)),
            ("f0.f0", num(r0(1.52))),
        ],
    );
    check_eval(
        &[GLASS, "--output", "geo.view", "--set", "view=[0.6,0,0.8]"],
        &[("geo.view", serde_json::json!([0.6, 0.0, 0.8]))],
    );
}

#[test]
fn eval_unknown_output_suggests() {
    fails(
        &["eval", GLASS, "--output", "exact.transmitance"],
        &["unknown output 'exact.transmitance' (did you mean 'exact.transmittance'?)"],
    );
    fails(
        &["eval", GLASS, "--output", "reflectanse", "--json"],
        &["unknown output 'reflectanse' (did you mean 'reflectance'?)"],
    );
}

#[test]
fn eval_graph_errors() {
    fails(
        &["eval", GLASS, "--set", "ir=2.0"],
        &["unknown parameter 'ir' (did you mean 'ior'?)"],
    );
    fails(
        &["eval", GLASS, "--set", "ior=[1,2]"],
        &["--set ior: expected a float value"],
    );
    fails(
        &["eval", GLASS, "--set", "view=[1,2]"],
        &["--set view: expected a vec3 value"],
    );
    fails(
        &["eval", GLASS, "--set", "nope.value=1"],
        &["--set nope.value: no node 'nope'"],
    );
    fails(
        &["eval", GLASS, "--set", "exact.cos_theta=2"],
        &["node 'exact': input 'cos_theta': value 2.0 is outside [-1, 1]"],
    );
    fails(&["eval", GLASS, "--set", "ior"], &["expected NAME=VALUE"]);
    fails(&["eval", "graphs/missing.json"], &["cannot read"]);
}

// ---------------------------------------------------------------------------------------
// eval --node
// ---------------------------------------------------------------------------------------

#[test]
fn eval_node_fresnel_dielectric() {
    check_eval(
        &[
            "--node",
            "fresnel_dielectric",
            "--set",
            "cos_theta=0.5",
            "--set",
            "ior_inside=1.33",
        ],
        &[
            ("reflectance", num(fresnel(0.5, 1.0, 1.33))),
            ("transmittance", num(1.0 - fresnel(0.5, 1.0, 1.33))),
        ],
    );
    // From the inside past the critical angle of water: total internal reflection.
    check_eval(
        &[
            "--node",
            "fresnel_dielectric",
            "--set",
            "cos_theta=-0.5",
            "--set",
            "ior_inside=1.33",
        ],
        &[("reflectance", num(1.0)), ("transmittance", num(0.0))],
    );
    // Defaults: normal incidence on n = 1.5.
    check_eval(
        &["--node", "fresnel_dielectric"],
        &[("reflectance", num(0.04)), ("transmittance", num(0.96))],
    );
}

#[test]
fn eval_node_broadcasts_a_float_to_a_vector() {
    let expect = [("result", serde_json::json!([1.5, 2.5, 3.5]))];
    check_eval(
        &["--node", "add", "--set", "a=[1,2,3]", "--set", "b=0.5"],
        &expect,
    );
    check_eval(
        &["--node", "add", "--set", "a=0.5", "--set", "b=[1,2,3]"],
        &expect,
    );
    check_eval(
        &["--node", "mul", "--set", "a=[1,2,3,4]", "--set", "b=2"],
        &[("result", serde_json::json!([2.0, 4.0, 6.0, 8.0]))],
    );
    check_eval(
        &["--node", "add", "--set", "a=1", "--set", "b=0.25"],
        &[("result", num(1.25))],
    );
}

#[test]
fn eval_node_split() {
    check_eval(
        &["--node", "split", "--set", "v=[1,2,3]"],
        &[
            ("x", num(1.0)),
            ("y", num(2.0)),
            ("z", num(3.0)),
            ("w", num(0.0)),
        ],
    );
    check_eval(
        &["--node", "split", "--set", "v=[0.25,-0.5]"],
        &[
            ("x", num(0.25)),
            ("y", num(-0.5)),
            ("z", num(0.0)),
            ("w", num(0.0)),
        ],
    );
    check_eval(
        &["--node", "split", "--set", "v=[1,2,3,4]"],
        &[
            ("x", num(1.0)),
            ("y", num(2.0)),
            ("z", num(3.0)),
            ("w", num(4.0)),
        ],
    );
}

#[test]
fn eval_node_bool_input_and_output() {
    // remap's `clamp` is a bool input (no builtin node has an enum input).
    for (clamp, result) in [("true", 1.0), ("false", 1.5)] {
        check_eval(
            &[
                "--node",
                "remap",
                "--set",
                "x=1.5",
                "--set",
                &format!("clamp={clamp}"),
            ],
            &[("result", num(result))],
        );
    }
    // refract's `tir` is a bool output; t is checked against GLSL refract in f64.
    let refract = |i: [f64; 3], eta: f64| {
        let n = [0.0, 0.0, 1.0];
        let cos: f64 = (0..3).map(|k| n[k] * i[k]).sum();
        let k = 1.0 - eta * eta * (1.0 - cos * cos);
        if k < 0.0 {
            let t: Vec<f64> = (0..3).map(|c| i[c] - 2.0 * cos * n[c]).collect();
            (t, true)
        } else {
            let t: Vec<f64> = (0..3)
                .map(|c| eta * i[c] - (eta * cos + k.sqrt()) * n[c])
                .collect();
            (t, false)
        }
    };
    for (text, i, eta, tir) in [
        // From water into air past the critical angle (48.75°): 53.13° incidence.
        ("[0.8,0,-0.6]", [0.8, 0.0, -0.6], 1.33, true),
        // From air into water at 36.87° incidence.
        ("[0.6,0,-0.8]", [0.6, 0.0, -0.8], 1.0 / 1.33, false),
        // From water into air inside the window.
        ("[0.6,0,-0.8]", [0.6, 0.0, -0.8], 1.33, false),
    ] {
        let (t, expect_tir) = refract(i, eta);
        assert_eq!(expect_tir, tir);
        check_eval(
            &[
                "--node",
                "refract",
                "--set",
                &format!("i={text}"),
                "--set",
                &format!("eta={eta}"),
            ],
            &[("t", serde_json::json!(t)), ("tir", J::Bool(tir))],
        );
    }
    // Defaults: straight through at normal incidence.
    check_eval(
        &["--node", "refract"],
        &[
            ("t", serde_json::json!([0.0, 0.0, -1.0])),
            ("tir", J::Bool(false)),
        ],
    );
}

#[test]
fn eval_node_errors() {
    fails(
        &["eval", "--node", "fresnel_dielectrc", "--json"],
        &["unknown node type 'fresnel_dielectrc' (did you mean 'fresnel_dielectric'?)"],
    );
    fails(
        &[
            "eval",
            "--node",
            "fresnel_dielectric",
            "--set",
            "ior_insde=1.3",
        ],
        &["unknown input 'ior_insde' (did you mean 'ior_inside'?)"],
    );
    fails(
        &[
            "eval",
            "--node",
            "fresnel_dielectric",
            "--set",
            "cos_theta=[0,0,1]",
        ],
        &["input 'cos_theta': expected float, found array of 3 items"],
    );
    fails(
        &[
            "eval",
            "--node",
            "fresnel_dielectric",
            "--set",
            "cos_theta=steep",
        ],
        &["input 'cos_theta': expected float, found string \"steep\""],
    );
    fails(
        &["eval", "--node", "remap", "--set", "clamp=1"],
        &["input 'clamp': expected bool, found number 1"],
    );
    fails(
        &["eval", "--node", "hg_phase", "--set", "g=2"],
        &["input 'g': value 2.0 is outside [-1, 1]"],
    );
    // A file and --node conflict.
    let out = run(&["eval", GLASS, "--node", "add"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("cannot be used with"));
}

// ---------------------------------------------------------------------------------------
// schema
// ---------------------------------------------------------------------------------------

#[test]
fn schema_prints_the_library_schema() {
    let stdout = ok(&["schema"]);
    assert_eq!(stdout, matgraph::document::json_schema());
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("schema.json");
    assert_eq!(ok(&["schema", "-o", path.to_str().unwrap()]), "");
    assert_eq!(std::fs::read_to_string(&path).unwrap(), stdout);
}

// ---------------------------------------------------------------------------------------
// fmt
// ---------------------------------------------------------------------------------------

#[test]
fn fmt_check_and_rewrite() {
    let canonical = std::fs::read_to_string(glass_path()).unwrap();
    let registry = Registry::builtin();
    assert_eq!(
        Graph::from_json(&canonical, registry).unwrap().to_json(),
        canonical,
        "graphs/fresnel_glass.json is not canonical"
    );
    assert_eq!(ok(&["fmt", "--check", GLASS]), "");

    let dir = tempfile::tempdir().unwrap();
    let value: J = serde_json::from_str(&canonical).unwrap();
    let reindented = serde_json::to_string_pretty(&value).unwrap() + "\n";
    assert_ne!(reindented, canonical);
    let copy = temp_copy(dir.path(), "copy.json", &reindented);
    let path = copy.to_str().unwrap();

    let (stdout, _) = fails(&["fmt", "--check", path], &["1 file is not canonical"]);
    assert_eq!(stdout, format!("{path}: not canonical\n"));
    assert_eq!(std::fs::read_to_string(&copy).unwrap(), reindented);

    assert_eq!(ok(&["fmt", path]), format!("{path}: rewritten\n"));
    assert_eq!(std::fs::read_to_string(&copy).unwrap(), canonical);
    assert_eq!(ok(&["fmt", "--check", path]), "");
    assert_eq!(
        ok(&["fmt", path]),
        format!("{path}: already canonical\n"),
        "a canonical file is left alone, and fmt says so"
    );
    // No temporary files are left beside the graph.
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["copy.json"]);
}

#[test]
fn fmt_normalises_literals_and_order() {
    let dir = tempfile::tempdir().unwrap();
    let copy = temp_copy(
        dir.path(),
        "lits.json",
        r#"{"nodes": [{"inputs": {"ior_inside": 2, "cos_theta": 0.5}, "type": "fresnel_dielectric", "id": "fr"}],
            "name": "lits", "version": 1, "outputs": [{"from": "fr.reflectance", "name": "r"}]}"#,
    );
    let path = copy.to_str().unwrap();
    fails(&["fmt", "--check", path], &["not canonical"]);
    ok(&["fmt", path]);
    assert_eq!(
        std::fs::read_to_string(&copy).unwrap(),
        "{\n  \"version\": 1,\n  \"name\": \"lits\",\n  \"nodes\": [\n    \
         { \"id\": \"fr\", \"type\": \"fresnel_dielectric\", \"inputs\": { \"cos_theta\": 0.5, \"ior_inside\": 2.0 } }\n  \
         ],\n  \"outputs\": [{ \"name\": \"r\", \"from\": \"fr.reflectance\" }]\n}\n"
    );
}

#[test]
fn fmt_refuses_invalid_files() {
    let dir = tempfile::tempdir().unwrap();
    let bad = temp_copy(
        dir.path(),
        "bad.json",
        r#"{"version": 1, "name": "g", "nodes": [{"id": "a", "type": "ad"}]}"#,
    );
    let before = std::fs::read_to_string(&bad).unwrap();
    let path = bad.to_str().unwrap();
    fails(
        &["fmt", path],
        &[&format!(
            "{path}: node 'a': unknown node type 'ad' (did you mean 'add'?)"
        )],
    );
    assert_eq!(std::fs::read_to_string(&bad).unwrap(), before);
}

// ---------------------------------------------------------------------------------------
// wgsl
// ---------------------------------------------------------------------------------------

#[test]
fn wgsl_prints_a_validated_module_with_only_the_functions_used() {
    let wgsl = ok(&["wgsl", GLASS]);
    assert!(wgsl.starts_with("// Generated by matgraph"), "{wgsl}");
    for needle in [
        "struct MgParams",
        "fn mg_fresnel_dielectric(",
        "fn mg_material(",
        "fn mg_compute(",
    ] {
        assert!(wgsl.contains(needle), "missing {needle}");
    }
    // Only the specular: no Fresnel function, no geometry.
    let spec = ok(&["wgsl", GLASS, "--output", "specular", "--bake"]);
    assert!(!spec.contains("mg_fresnel_dielectric"), "{spec}");
    assert!(!spec.contains("MgParams"), "baked: {spec}");
    assert!(
        spec.contains("0.53224987"),
        "the folded Unreal specular of glass: {spec}"
    );
    // Same input, same bytes.
    assert_eq!(ok(&["wgsl", GLASS]), wgsl);
}

#[test]
fn wgsl_targets_write_files() {
    let dir = tempfile::tempdir().unwrap();
    for (target, entry, check) in [
        ("spirv", "compute", "magic"),
        ("glsl", "fragment", "#version 450"),
        ("msl", "compute", "metal_stdlib"),
        ("hlsl", "fragment", "mg_fragment"),
    ] {
        let out = dir.path().join(format!("{target}.{entry}"));
        ok(&[
            "wgsl",
            GLASS,
            "--target",
            target,
            "--entry",
            entry,
            "-o",
            out.to_str().unwrap(),
        ]);
        let bytes = std::fs::read(&out).unwrap();
        if check == "magic" {
            assert_eq!(&bytes[..4], &0x0723_0203u32.to_le_bytes());
        } else {
            assert!(text(&bytes).contains(check), "{target}: lacks {check}");
        }
    }
}

#[test]
fn wgsl_errors() {
    fails(
        &["wgsl", "graphs/missing.json"],
        &["graphs/missing.json", "cannot read"],
    );
    fails(
        &["wgsl", GLASS, "--output", "reflectanse"],
        &["unknown output 'reflectanse'", "did you mean 'reflectance'"],
    );
    let out = run(&["wgsl", GLASS, "--target", "dxil"]);
    assert_eq!(out.status.code(), Some(2), "clap rejects an unknown target");
}

#[test]
fn eval_samples_images_relative_to_the_graph() {
    use matgraph::texture::Image;
    let dir = tempfile::tempdir().unwrap();
    // 2 × 2: red, green / blue, white (linear values 0 and 1 survive sRGB exactly).
    let px = [
        [1.0, 0.0, 0.0, 1.0],
        [0.0, 1.0, 0.0, 1.0],
        [0.0, 0.0, 1.0, 1.0],
        [1.0, 1.0, 1.0, 1.0],
    ];
    matgraph::image_io::save_png(
        &dir.path().join("tex.png"),
        &Image::new(2, 2, px.to_vec()).unwrap(),
    )
    .unwrap();
    let graph = dir.path().join("g.json");
    std::fs::write(
        &graph,
        r#"{ "version": 1, "name": "t", "nodes": [
          { "id": "geo", "type": "geometry" },
          { "id": "tex", "type": "image_texture", "texture": "tex.png", "inputs": { "uv": { "link": "geo.uv" }, "filter": "nearest" } } ],
          "outputs": [{ "name": "c", "from": "tex.color" }] }"#,
    )
    .unwrap();
    let g = graph.to_str().unwrap();
    for (uv, want) in [
        ("[0.25,0.25]", [1.0, 0.0, 0.0]),
        ("[0.75,0.25]", [0.0, 1.0, 0.0]),
        ("[0.25,0.75]", [0.0, 0.0, 1.0]),
    ] {
        let out = ok(&["eval", g, "--set", &format!("uv={uv}"), "--json"]);
        let v: J = serde_json::from_str(&out).unwrap();
        let got: Vec<f64> = v["c"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        assert_eq!(got, want.to_vec(), "uv {uv}");
    }
    std::fs::remove_file(dir.path().join("tex.png")).unwrap();
    fails(&["eval", g], &["tex.png"]);
}

// ---------------------------------------------------------------------------------------
// Reliability: bad files, confinement, safe writes, formats (issue 9)
// ---------------------------------------------------------------------------------------

/// Makes a FIFO at `path` with mkfifo(1).
fn mkfifo(path: &Path) {
    let status = Command::new("mkfifo").arg(path).status().unwrap();
    assert!(status.success(), "mkfifo {}", path.display());
}

/// Runs `args` and fails the test if it does not finish within 20 s (a blocked read).
fn run_with_deadline(args: &[&str]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > std::time::Duration::from_secs(20) {
            child.kill().unwrap();
            panic!("matgraph {args:?} blocked");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

#[test]
fn every_bundled_graph_evaluates() {
    let mut graphs: Vec<PathBuf> =
        std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "json"))
            .collect();
    graphs.sort();
    // The graphs of every material family are there (a lost glob would test nothing).
    for family in [
        "skin",
        "pbr_",
        "toon_ball",
        "water_demo",
        "bubble",
        "water_sunshine",
        "water_toon",
    ] {
        assert!(
            graphs
                .iter()
                .any(|p| p.file_name().unwrap().to_str().unwrap().starts_with(family)),
            "no {family}* graph in {graphs:?}"
        );
    }
    for path in &graphs {
        let p = path.to_str().unwrap();
        let graph = matgraph::io::load_graph(path, Registry::builtin()).unwrap();
        let stdout = ok(&["eval", p, "--json"]);
        let v: J = serde_json::from_str(&stdout).unwrap();
        let map = v.as_object().unwrap();
        let names: Vec<&str> = graph.outputs().iter().map(|o| o.name.as_str()).collect();
        assert_eq!(
            map.keys().map(String::as_str).collect::<Vec<_>>(),
            names,
            "{p}"
        );
        for (name, value) in map {
            let finite = |x: &J| x.as_f64().is_some_and(f64::is_finite) || x.is_boolean();
            let all = match value {
                J::Array(items) => items.iter().all(finite),
                x => finite(x),
            };
            assert!(all, "{p}: {name} = {value}");
        }
    }
    // The pbr graphs reflect `scene:environment`: the ball's default sky at the default
    // view (+z, the normal +z: the mirror direction is +z, the horizon) is not black.
    let v: J = serde_json::from_str(&ok(&["eval", "graphs/pbr_gold.json", "--json"])).unwrap();
    let e: Vec<f64> = v["emission"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert!(e.iter().all(|&x| x > 0.0), "{e:?}");
}

#[test]
fn missing_files_folders_and_fifos_are_named_not_located() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.json");
    let m = missing.to_str().unwrap();
    let d = dir.path().to_str().unwrap();
    for cmd in ["check", "eval", "wgsl", "fmt", "render"] {
        let (_, stderr) = fails(&[cmd, m], &[&format!("cannot read {m}: no such file")]);
        assert!(!stderr.contains("line 0"), "{cmd}: {stderr}");
        let (_, stderr) = fails(&[cmd, d], &[&format!("cannot read {d}: is a directory")]);
        assert!(!stderr.contains("line 0"), "{cmd}: {stderr}");
    }
    // A FIFO is refused from its metadata, without opening it (which would block).
    let fifo = dir.path().join("pipe.json");
    mkfifo(&fifo);
    let f = fifo.to_str().unwrap();
    for cmd in ["check", "eval", "fmt"] {
        let out = run_with_deadline(&[cmd, f]);
        assert_eq!(out.status.code(), Some(1));
        let stderr = text(&out.stderr);
        assert!(
            stderr.contains(&format!("cannot read {f}: not a regular file (a FIFO)")),
            "{cmd}: {stderr}"
        );
    }
}

#[test]
fn eval_node_unknown_type_names_the_users_type() {
    let (_, stderr) = fails(
        &["eval", "--node", "nope"],
        &["--node nope: unknown node type 'nope' (`matgraph nodes` lists them)"],
    );
    assert!(!stderr.contains("node 'node'"), "{stderr}");
    fails(
        &["eval", "--node", "hg_phse"],
        &["--node hg_phse: unknown node type 'hg_phse' (did you mean 'hg_phase'?)"],
    );
}

#[test]
fn check_and_render_agree_on_a_graph_without_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let g = temp_copy(
        dir.path(),
        "empty.json",
        r#"{"version": 1, "name": "empty", "nodes": [{"id": "geo", "type": "geometry"}]}"#,
    );
    let p = g.to_str().unwrap();
    let (stdout, _) = fails(
        &["check", p],
        &[
            &format!("{p}: the graph has no outputs"),
            "1 of 1 file failed",
        ],
    );
    assert_eq!(stdout, format!("{p}: 1 error\n"));
    let out = dir.path().join("out.png");
    fails(
        &["render", p, "--size", "8x8", "-o", out.to_str().unwrap()],
        &[p],
    );
    fails(&["eval", p], &[p]);
    // One output: singular.
    let one = temp_copy(
        dir.path(),
        "one.json",
        r#"{"version": 1, "name": "one", "nodes": [{"id": "geo", "type": "geometry"}],
            "outputs": [{"name": "n", "from": "geo.normal"}]}"#,
    );
    let p = one.to_str().unwrap();
    assert_eq!(ok(&["check", p]), format!("{p}: ok (1 node, 1 output)\n"));
}

/// A folder `root/graph/` with the graph, an inside texture, and `root/outside/secret.png`.
fn confinement_fixture(texture: &str) -> (tempfile::TempDir, PathBuf) {
    use matgraph::texture::Image;
    let root = tempfile::tempdir().unwrap();
    let inside = root.path().join("graph");
    let outside = root.path().join("outside");
    std::fs::create_dir_all(inside.join("tex")).unwrap();
    std::fs::create_dir_all(&outside).unwrap();
    let img = Image::new(1, 1, vec![[1.0, 0.0, 0.0, 1.0]]).unwrap();
    matgraph::image_io::save_png(&outside.join("secret.png"), &img).unwrap();
    matgraph::image_io::save_png(&inside.join("tex/red.png"), &img).unwrap();
    std::os::unix::fs::symlink(outside.join("secret.png"), inside.join("escape.png")).unwrap();
    std::os::unix::fs::symlink("tex/red.png", inside.join("alias.png")).unwrap();
    let graph = inside.join("g.json");
    std::fs::write(
        &graph,
        format!(
            r#"{{ "version": 1, "name": "t", "nodes": [
              {{ "id": "geo", "type": "geometry" }},
              {{ "id": "tex", "type": "image_texture", "texture": "{texture}", "inputs": {{ "uv": {{ "link": "geo.uv" }} }} }} ],
              "outputs": [{{ "name": "c", "from": "tex.color" }}] }}"#
        ),
    )
    .unwrap();
    (root, graph)
}

#[test]
fn texture_paths_stay_inside_the_graphs_folder() {
    let secret = |root: &Path| root.join("outside/secret.png").to_str().unwrap().to_owned();
    for case in [
        "../outside/secret.png",
        "ABSOLUTE",
        "escape.png",
        "../outside/none.png",
    ] {
        let (root, graph) = confinement_fixture(case);
        let texture = if case == "ABSOLUTE" {
            let t = secret(root.path());
            let text = std::fs::read_to_string(&graph).unwrap().replace(case, &t);
            std::fs::write(&graph, text).unwrap();
            t
        } else {
            case.to_owned()
        };
        let g = graph.to_str().unwrap();
        let out = root.path().join("graph/out.png");
        for args in [
            vec!["eval", g, "--json"],
            vec!["render", g, "--size", "8x8", "-o", out.to_str().unwrap()],
        ] {
            let (_, stderr) = fails(
                &args,
                &[
                    g,
                    "node 'tex'",
                    &format!("path '{texture}'"),
                    "outside the graph's folder",
                    "--allow-outside-paths",
                ],
            );
            let mut allowed = args.clone();
            allowed.push("--allow-outside-paths");
            if case.contains("none") {
                // Missing and outside: reported as outside, so existence is not revealed.
                assert!(stderr.contains("outside/none.png"), "{stderr}");
                fails(&allowed, &["none.png: no such file"]);
                continue;
            }
            assert!(stderr.contains(&secret(root.path())), "{case}: {stderr}");
            ok(&allowed);
        }
    }
    // Inside, directly or through a symlink that stays inside: allowed without the flag.
    for texture in ["tex/red.png", "alias.png", "./tex/../tex/red.png"] {
        let (_root, graph) = confinement_fixture(texture);
        let v: J = serde_json::from_str(&ok(&["eval", graph.to_str().unwrap(), "--json"])).unwrap();
        assert_eq!(v["c"], serde_json::json!([1.0, 0.0, 0.0]), "{texture}");
    }
    // A non-regular file is refused before it is opened (a FIFO would block), even with
    // the flag.
    let (root, graph) = confinement_fixture("../outside/pipe.png");
    mkfifo(&root.path().join("outside/pipe.png"));
    let g = graph.to_str().unwrap();
    let out = run_with_deadline(&["eval", g, "--allow-outside-paths"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("not a regular file (a FIFO)"),
        "{}",
        text(&out.stderr)
    );
    let out = run_with_deadline(&["eval", g]);
    assert!(
        text(&out.stderr).contains("outside the graph's folder"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn scene_files_and_environment_images_stay_inside_too() {
    use matgraph::texture::Image;
    let (root, graph) = confinement_fixture("tex/red.png");
    let sky = Image::filled(4, 2, [0.5, 0.5, 0.5, 1.0]);
    matgraph::image_io::save_exr(&root.path().join("outside/sky.exr"), &sky).unwrap();
    std::fs::write(
        root.path().join("graph/scene.json"),
        r#"{ "kind": "ball", "environment": { "image": { "path": "../outside/sky.exr" } } }"#,
    )
    .unwrap();
    std::fs::write(
        root.path().join("outside/scene.json"),
        r#"{ "kind": "ball" }"#,
    )
    .unwrap();
    let text_of = std::fs::read_to_string(&graph).unwrap();
    let with_scene = |scene: &str| {
        let p = root
            .path()
            .join(format!("graph/{}.json", scene.replace(['/', '.'], "_")));
        std::fs::write(
            &p,
            text_of.replacen(
                "\"version\": 1,",
                &format!("\"version\": 1, \"scene\": \"{scene}\","),
                1,
            ),
        )
        .unwrap();
        p
    };
    let out = root.path().join("graph/out.png");
    let o = out.to_str().unwrap();
    let g = with_scene("scene.json");
    let g = g.to_str().unwrap();
    fails(
        &["render", g, "--size", "8x8", "-o", o],
        &[
            "environment image",
            "path '../outside/sky.exr'",
            "outside the graph's folder",
        ],
    );
    ok(&[
        "render",
        g,
        "--size",
        "8x8",
        "-o",
        o,
        "--allow-outside-paths",
    ]);
    let g = with_scene("../outside/scene.json");
    let g = g.to_str().unwrap();
    fails(
        &["render", g, "--size", "8x8", "-o", o],
        &[
            "scene: path '../outside/scene.json'",
            "outside the graph's folder",
        ],
    );
    ok(&[
        "render",
        g,
        "--size",
        "8x8",
        "-o",
        o,
        "--allow-outside-paths",
    ]);
}

/// The first bytes of `path`.
fn magic(path: &Path, n: usize) -> Vec<u8> {
    std::fs::read(path).unwrap()[..n].to_vec()
}

#[test]
fn render_chooses_the_encoder_by_extension() {
    let dir = tempfile::tempdir().unwrap();
    for (name, want) in [
        ("a.png", &b"\x89PNG\r\n\x1a\n"[..]),
        ("b.jpg", &b"\xff\xd8\xff"[..]),
        ("c.JPEG", &b"\xff\xd8\xff"[..]),
        ("d.exr", &b"\x76\x2f\x31\x01"[..]),
    ] {
        let out = dir.path().join(name);
        let stdout = ok(&[
            "render",
            GLASS,
            "--size",
            "8x8",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(stdout.contains(out.to_str().unwrap()), "{stdout}");
        assert_eq!(magic(&out, want.len()), want, "{name}");
    }
    let back = image::open(dir.path().join("b.jpg")).unwrap();
    assert_eq!((back.width(), back.height()), (8, 8));
    for bad in ["e.bmp", "noext"] {
        let out = dir.path().join(bad);
        fails(
            &[
                "render",
                GLASS,
                "--size",
                "8x8",
                "-o",
                out.to_str().unwrap(),
            ],
            &[bad, "use one of .png, .jpg, .jpeg, .exr"],
        );
        assert!(!out.exists());
    }
    // --exr names the file it wrote, next to the PNG.
    let png = dir.path().join("f.png");
    let stdout = ok(&[
        "render",
        GLASS,
        "--size",
        "8x8",
        "--exr",
        "-o",
        png.to_str().unwrap(),
    ]);
    let exr = dir.path().join("f.exr");
    assert!(
        stdout.contains(&format!("{} + {}", png.display(), exr.display())),
        "{stdout}"
    );
    assert_eq!(magic(&exr, 4), b"\x76\x2f\x31\x01");
}

/// Names in `dir`, sorted.
fn names_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn writes_go_through_symlinks_and_keep_the_mode() {
    use std::os::unix::fs::{MetadataExt, PermissionsExt};
    let dir = tempfile::tempdir().unwrap();
    let real = dir.path().join("real.png");
    std::fs::write(&real, b"old").unwrap();
    std::fs::set_permissions(&real, std::fs::Permissions::from_mode(0o640)).unwrap();
    let link = dir.path().join("link.png");
    std::os::unix::fs::symlink("real.png", &link).unwrap();
    ok(&[
        "render",
        GLASS,
        "--size",
        "8x8",
        "-o",
        link.to_str().unwrap(),
    ]);
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert_eq!(magic(&real, 4), b"\x89PNG");
    assert_eq!(std::fs::metadata(&real).unwrap().mode() & 0o7777, 0o640);
    // fmt on a symlinked graph formats the target and keeps the link, mode and owner.
    let canonical = std::fs::read_to_string(glass_path()).unwrap();
    let value: J = serde_json::from_str(&canonical).unwrap();
    let target = dir.path().join("target.json");
    std::fs::write(&target, serde_json::to_string_pretty(&value).unwrap()).unwrap();
    std::fs::set_permissions(&target, std::fs::Permissions::from_mode(0o604)).unwrap();
    let root = std::fs::metadata(&target).unwrap().uid() == 0;
    if root {
        std::os::unix::fs::chown(&target, Some(1234), Some(5678)).unwrap();
    }
    let glink = dir.path().join("g.json");
    std::os::unix::fs::symlink(&target, &glink).unwrap();
    let g = glink.to_str().unwrap();
    assert_eq!(ok(&["fmt", g]), format!("{g}: rewritten\n"));
    assert!(
        std::fs::symlink_metadata(&glink)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert_eq!(std::fs::read_to_string(&target).unwrap(), canonical);
    let meta = std::fs::metadata(&target).unwrap();
    assert_eq!(meta.mode() & 0o7777, 0o604);
    if root {
        assert_eq!((meta.uid(), meta.gid()), (1234, 5678));
    }
    // A new file gets 0666 less the umask (as the shell would create it), not 0600.
    let fresh = dir.path().join("fresh.png");
    ok(&[
        "render",
        GLASS,
        "--size",
        "8x8",
        "-o",
        fresh.to_str().unwrap(),
    ]);
    assert_ne!(
        std::fs::metadata(&fresh).unwrap().mode() & 0o077,
        0,
        "not private"
    );
    assert_eq!(
        names_in(dir.path()),
        ["fresh.png", "g.json", "link.png", "real.png", "target.json"]
    );
}

#[test]
fn writes_refuse_fifos_and_devices_and_leave_no_temporaries() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe.png");
    mkfifo(&fifo);
    let f = fifo.to_str().unwrap();
    let out = run_with_deadline(&["render", GLASS, "--size", "8x8", "-o", f]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("is a FIFO, not a regular file; refusing to replace it"),
        "{}",
        text(&out.stderr)
    );
    // A device node like /dev/null (made here, so a failure cannot hurt the real one);
    // only root may make one.
    let dev = dir.path().join("null.png");
    let made = Command::new("mknod")
        .arg(&dev)
        .args(["c", "1", "3"])
        .status()
        .is_ok_and(|s| s.success());
    if made {
        fails(
            &[
                "render",
                GLASS,
                "--size",
                "8x8",
                "-o",
                dev.to_str().unwrap(),
            ],
            &["is a character device, not a regular file; refusing to replace it"],
        );
        use std::os::unix::fs::FileTypeExt;
        assert!(
            std::fs::symlink_metadata(&dev)
                .unwrap()
                .file_type()
                .is_char_device()
        );
    }
    let sym = dir.path().join("to_pipe.json");
    std::os::unix::fs::symlink("pipe.png", &sym).unwrap();
    fails(&["schema", "-o", sym.to_str().unwrap()], &["is a FIFO"]);
    let mut expected = vec!["pipe.png", "to_pipe.json"];
    if made {
        expected.insert(0, "null.png");
    }
    assert_eq!(names_in(dir.path()), expected, "no temporary left behind");
}

#[test]
fn a_killed_writes_temporary_is_cleaned_up_by_the_next_write() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("schema.json");
    let stale = dir.path().join(".schema.json.Ab3dEf.matgraph-tmp");
    let fresh = dir.path().join(".schema.json.Zz9yYx.matgraph-tmp");
    let other = dir.path().join(".other.json.Ab3dEf.matgraph-tmp");
    for p in [&stale, &fresh, &other] {
        std::fs::write(p, b"half").unwrap();
    }
    let two_hours_ago = std::time::SystemTime::now() - std::time::Duration::from_secs(7200);
    for p in [&stale, &other] {
        std::fs::File::options()
            .write(true)
            .open(p)
            .unwrap()
            .set_modified(two_hours_ago)
            .unwrap();
    }
    ok(&["schema", "-o", out.to_str().unwrap()]);
    // The stale one of this target is gone; a recent one (a write in progress) and another
    // target's are kept.
    assert_eq!(
        names_in(dir.path()),
        [
            ".other.json.Ab3dEf.matgraph-tmp",
            ".schema.json.Zz9yYx.matgraph-tmp",
            "schema.json"
        ]
    );
}

/// Without `XDG_RUNTIME_DIR` (no desktop session), `render --gpu` keeps Mesa quiet: the
/// binary points it at a private temporary folder, removed afterwards.
#[test]
fn render_gpu_without_a_runtime_dir_is_quiet() {
    let dir = tempfile::tempdir().unwrap();
    let out_png = dir.path().join("gpu.png");
    let out = Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args(["render", GLASS, "--gpu", "--size", "8x8", "-o"])
        .arg(&out_png)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env_remove("XDG_RUNTIME_DIR")
        .env("TMPDIR", dir.path())
        .output()
        .unwrap();
    let stderr = text(&out.stderr);
    assert!(!stderr.contains("XDG_RUNTIME_DIR"), "{stderr}");
    if !out.status.success() {
        println!("SKIPPED: render --gpu found no adapter: {stderr}");
        return;
    }
    // Only the adapter's line (render_gpu_names_its_adapter).
    assert!(
        stderr.starts_with("adapter: ") && stderr.lines().count() == 1,
        "{stderr}"
    );
    assert_eq!(magic(&out_png, 4), b"\x89PNG");
    assert_eq!(
        names_in(dir.path()),
        ["gpu.png"],
        "the private folder is removed"
    );
}

/// `render --gpu` and `--gpu-compute` name the adapter that ran, once, on stderr:
/// `adapter: NAME (BACKEND)`, the adapter this process's shared context finds too; a CPU
/// render names none. Without an adapter this prints `SKIPPED`, and fails instead when
/// `MATGRAPH_REQUIRE_GPU` is set.
#[test]
fn render_gpu_names_its_adapter() {
    let Some(ctx) = crate::common::gpu_context("render_gpu_names_its_adapter") else {
        return;
    };
    let info = ctx.adapter_info();
    let want = format!("adapter: {} ({})\n", info.name, info.backend.to_str());
    let dir = tempfile::tempdir().unwrap();
    for (flag, files) in [
        ("--gpu", vec![GLASS]),
        ("--gpu-compute", vec![GLASS]),
        // Several graphs: still one line.
        ("--gpu", vec![GLASS, "graphs/snell_window.json"]),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_matgraph"))
            .arg("render")
            .args(&files)
            .args([flag, "--size", "8x8", "--out-dir"])
            .arg(dir.path())
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .unwrap();
        let stderr = text(&out.stderr);
        assert!(out.status.success(), "{flag} {files:?}: {stderr}");
        assert_eq!(stderr, want, "{flag} {files:?}");
    }
    let cpu = dir.path().join("cpu.png");
    // `ok` asserts an empty stderr: a CPU render names no adapter.
    ok(&[
        "render",
        GLASS,
        "--size",
        "8x8",
        "-o",
        cpu.to_str().unwrap(),
    ]);
}

/// `--scene water` keeps the time of day the graph's own scene writes out: the toon water at
/// night forced into the water preset is the render of a scene file that says night, not the
/// preset's default day; a scene file that writes its own lights and environment wins.
#[test]
fn forced_scene_keeps_the_graphs_time_of_day() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let night = "graphs/water_toon_night.json";
    let scene = |name: &str, json: &str| {
        let p = d.join(name);
        std::fs::write(&p, json).unwrap();
        p.to_str().unwrap().to_owned()
    };
    let night_file = scene(
        "night.json",
        r#"{ "kind": "water", "lights": ["night"], "environment": "night" }"#,
    );
    let silent_file = scene("silent.json", r#"{ "kind": "water" }"#);
    let day_file = scene(
        "day.json",
        r#"{ "kind": "water", "lights": ["day"], "environment": "day" }"#,
    );
    let render = |scene: &str, name: &str| -> Vec<u8> {
        let out = d.join(name);
        ok(&[
            "render",
            night,
            "--size",
            "24x24",
            "--scene",
            scene,
            "-o",
            out.to_str().unwrap(),
        ]);
        std::fs::read(out).unwrap()
    };
    let preset = render("water", "preset.png");
    assert!(
        preset == render(&night_file, "night.png"),
        "--scene water is the graph's night"
    );
    assert!(
        preset == render(&silent_file, "silent.png"),
        "a scene file that states no lights keeps the graph's"
    );
    assert!(
        preset != render(&day_file, "day.png"),
        "a scene file's own lights and environment win"
    );
}

/// `--json` writes non-finite values as the strings "inf", "-inf" and "NaN" (JSON has no such
/// numbers), so a reader can tell them apart; here from the documented overflows of `div`
/// and `dot`.
#[test]
fn eval_json_tells_inf_and_nan_apart() {
    check_eval(
        &["--node", "div", "--set", "a=10", "--set", "b=2e-38"],
        &[("result", J::String("inf".into()))],
    );
    check_eval(
        &["--node", "div", "--set", "a=-10", "--set", "b=2e-38"],
        &[("result", J::String("-inf".into()))],
    );
    check_eval(
        &[
            "--node",
            "dot",
            "--set",
            "a=[1e30,-1e30,0]",
            "--set",
            "b=[1e30,1e30,0]",
        ],
        &[("result", J::String("NaN".into()))],
    );
}
