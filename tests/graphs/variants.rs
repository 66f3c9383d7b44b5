//! Variants in the graph format: loader errors, resolution against hand-written
//! single-branch graphs, dead-branch removal, the CLI's `--variant`, round trip.

use matgraph::wgsl::{WgslOptions, generate};
use matgraph::{Graph, GraphDocument, Plan, PlanOptions, Registry, variant};

fn reg() -> &'static Registry {
    Registry::builtin()
}

const NODES: &str = r#"
    { "id": "ior", "type": "parameter", "inputs": { "value": 1.52 } },
    { "id": "exact", "type": "fresnel_dielectric", "inputs": { "cos_theta": 0.3, "ior_inside": { "link": "ior.value" } } },
    { "id": "f0", "type": "ior_to_f0", "inputs": { "ior_inside": { "link": "ior.value" } } },
    { "id": "schlick", "type": "fresnel_schlick", "inputs": { "cos_theta": 0.3, "f0": { "link": "f0.f0" } } }"#;

fn graph_text(switch: &str, variants: &str) -> String {
    format!(
        r#"{{"version": 1, "name": "g", "nodes": [{NODES}, {switch}],
        "outputs": [{{"name": "r", "from": "sw.result"}}],
        "parameters": [{{"name": "ior", "node": "ior"}}],
        "variants": {variants}}}"#
    )
}

const SWITCH: &str = r#"{ "id": "sw", "type": "switch", "variant": "fresnel",
    "inputs": { "schlick": { "link": "schlick.reflectance" }, "exact": { "link": "exact.reflectance" } } }"#;
const VARIANTS: &str = r#"{"fresnel": {"choices": ["schlick", "exact"], "default": "exact"}}"#;

fn errors(text: &str, selection: &[(&str, &str)]) -> Vec<String> {
    let doc = GraphDocument::parse(text).unwrap();
    let sel: Vec<(String, String)> = selection
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
    Graph::with_variants(&doc, reg(), &sel)
        .unwrap_err()
        .iter()
        .map(|e| e.to_string())
        .collect()
}

fn eval_r(g: &Graph) -> f32 {
    let plan = Plan::compile(g, &PlanOptions::default()).unwrap();
    let batch = matgraph::SampleBatch::new(1);
    let out = plan.execute(&batch, &plan.default_parameters()).unwrap();
    out.planar(out.index("r").unwrap())[0]
}

fn select(choice: &str) -> Graph {
    let doc = GraphDocument::parse(&graph_text(SWITCH, VARIANTS)).unwrap();
    Graph::with_variants(&doc, reg(), &[("fresnel".into(), choice.into())]).unwrap()
}

/// The graph of one branch alone, written by hand.
fn single(branch: &str) -> Graph {
    let text = format!(
        r#"{{"version": 1, "name": "g", "nodes": [{NODES}],
        "outputs": [{{"name": "r", "from": "{branch}.reflectance"}}]}}"#
    );
    Graph::from_json(&text, reg()).unwrap()
}

#[test]
fn each_choice_evaluates_as_its_branch_alone() {
    // Exact Fresnel of glass n = 1.52 at cosθ = 0.3, f64 from the Fresnel equations.
    let (n, c) = (1.52f64, 0.3f64);
    let ct = (1.0 - (1.0 - c * c) / (n * n)).sqrt();
    let rs = ((c - n * ct) / (c + n * ct)).powi(2);
    let rp = ((ct - n * c) / (ct + n * c)).powi(2);
    let exact = 0.5 * (rs + rp);
    let f0 = ((n - 1.0) / (n + 1.0)).powi(2);
    let schlick = f0 + (1.0 - f0) * (1.0 - c).powi(5);
    for (choice, want) in [("exact", exact), ("schlick", schlick)] {
        let v = eval_r(&select(choice));
        assert_eq!(v, eval_r(&single(choice)), "{choice}");
        assert!((v as f64 - want).abs() < 1e-5, "{choice}: {v} vs {want}");
    }
    // The default is exact.
    let g = Graph::from_json(&graph_text(SWITCH, VARIANTS), reg()).unwrap();
    assert_eq!(eval_r(&g), eval_r(&single("exact")));
}

#[test]
fn dead_branch_is_absent_from_wgsl_and_plan() {
    let wgsl = |g: &Graph| generate(g, &WgslOptions::default()).unwrap().source;
    let (e, s) = (wgsl(&select("exact")), wgsl(&select("schlick")));
    assert!(
        e.contains("fresnel_dielectric") && !e.contains("schlick"),
        "{e}"
    );
    assert!(
        s.contains("schlick") && !s.contains("fresnel_dielectric"),
        "{s}"
    );
    assert_eq!(e, wgsl(&select("exact")), "deterministic");
    let live = |g: &Graph| {
        Plan::compile(g, &PlanOptions::default())
            .unwrap()
            .stats()
            .live_nodes
    };
    assert_eq!(live(&select("exact")), live(&single("exact")));
    assert_eq!(live(&select("schlick")), live(&single("schlick")));
    // The document-level resolution removes the dead nodes.
    let doc = GraphDocument::parse(&graph_text(SWITCH, VARIANTS)).unwrap();
    let r = variant::resolve(&doc, &[("fresnel".into(), "schlick".into())]).unwrap();
    let ids: Vec<&str> = r.nodes.iter().map(|n| n.id.as_str()).collect();
    assert_eq!(ids, ["ior", "f0", "schlick"]);
    assert!(r.variants.is_empty());
    assert_eq!(r.outputs[0].from, "schlick.reflectance");
}

#[test]
fn round_trip_keeps_variants() {
    let g = Graph::from_json(&graph_text(SWITCH, VARIANTS), reg()).unwrap();
    let saved = g.to_json();
    assert!(
        saved.contains("\"variants\"") && saved.contains("\"switch\""),
        "{saved}"
    );
    assert_eq!(Graph::from_json(&saved, reg()).unwrap().to_json(), saved);
    // A graph resolved at another choice still saves as written.
    assert_eq!(select("schlick").to_json(), saved);
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/graphs/fresnel_variants.json"
    ))
    .unwrap();
    assert_eq!(Graph::from_json(&text, reg()).unwrap().to_json(), text);
}

#[test]
fn loader_errors_name_the_node_and_field() {
    let e = errors(&graph_text(SWITCH, VARIANTS), &[("fresnl", "exact")]);
    assert_eq!(
        e,
        ["--variant fresnl=exact: unknown variant 'fresnl' (did you mean 'fresnel'?)"]
    );
    let e = errors(&graph_text(SWITCH, VARIANTS), &[("fresnel", "schlik")]);
    assert_eq!(
        e,
        [
            "--variant fresnel=schlik: unknown choice 'schlik' (choices: schlick, exact) (did you mean 'schlick'?)"
        ]
    );
    let bad_default = r#"{"fresnel": {"choices": ["schlick", "exact"], "default": "exakt"}}"#;
    assert_eq!(
        errors(&graph_text(SWITCH, bad_default), &[]),
        ["variant 'fresnel': default: 'exakt' is not one of its choices (did you mean 'exact'?)"]
    );
    let undeclared = SWITCH.replace("\"fresnel\"", "\"fresnell\"");
    assert_eq!(
        errors(&graph_text(&undeclared, VARIANTS), &[]),
        [
            "node 'sw': variant: variant 'fresnell' is not declared in \"variants\" (did you mean 'fresnel'?)"
        ]
    );
    let missing = r#"{ "id": "sw", "type": "switch", "variant": "fresnel",
        "inputs": { "exact": { "link": "exact.reflectance" } } }"#;
    assert_eq!(
        errors(&graph_text(missing, VARIANTS), &[]),
        [
            "node 'sw': input 'schlick': missing: variant 'fresnel' needs a link for each of its choices"
        ]
    );
    let stray = r#"{ "id": "sw", "type": "switch", "variant": "fresnel",
        "inputs": { "exact": { "link": "exact.reflectance" }, "schlick": { "link": "schlick.reflectance" }, "shlick": { "link": "schlick.reflectance" } } }"#;
    assert_eq!(
        errors(&graph_text(stray, VARIANTS), &[]),
        ["node 'sw': input 'shlick': not a choice of variant 'fresnel' (did you mean 'schlick'?)"]
    );
    let mistyped = r#"{ "id": "sw", "type": "switch", "variant": "fresnel",
        "inputs": { "schlick": { "link": "schlick.reflectance" }, "exact": { "link": "ior.value" } } }"#;
    // ior.value is a float like the reflectances: no error. A vec3 choice is one.
    assert!(Graph::from_json(&graph_text(mistyped, VARIANTS), reg()).is_ok());
    let vec3 = format!(
        r#"{{"version": 1, "name": "g", "nodes": [{NODES},
        {{ "id": "c", "type": "combine" }},
        {{ "id": "sw", "type": "switch", "variant": "fresnel",
          "inputs": {{ "schlick": {{ "link": "schlick.reflectance" }}, "exact": {{ "link": "c.vec3" }} }} }}],
        "outputs": [{{"name": "r", "from": "sw.result"}}], "variants": {VARIANTS}}}"#
    );
    let e = errors(&vec3, &[]);
    assert_eq!(e.len(), 1, "{e:?}");
    assert!(
        e[0].starts_with(
            "node 'sw': input 'exact': type vec3 differs from the type float of choice 'schlick'"
        ),
        "{e:?}"
    );
}

#[test]
fn cli_variant_flag_on_eval_wgsl_and_render() {
    let exe = env!("CARGO_BIN_EXE_matgraph");
    let file = concat!(env!("CARGO_MANIFEST_DIR"), "/graphs/fresnel_variants.json");
    let run = |args: &[&str]| {
        std::process::Command::new(exe)
            .args(args)
            .env("XDG_RUNTIME_DIR", "/tmp")
            .output()
            .unwrap()
    };
    let eval = |choice: &str| {
        let o = run(&[
            "eval",
            file,
            "--json",
            "--variant",
            &format!("fresnel={choice}"),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8(o.stdout).unwrap()
    };
    assert_ne!(eval("schlick"), eval("exact"));
    let bad = run(&["eval", file, "--variant", "fresnel=schlik"]);
    assert!(!bad.status.success());
    let msg = String::from_utf8_lossy(&bad.stderr);
    assert!(
        msg.contains("fresnel_variants.json: --variant fresnel=schlik: unknown choice 'schlik'")
            && msg.contains("did you mean 'schlick'"),
        "{msg}"
    );
    let w = run(&["wgsl", file, "--variant", "fresnel=schlick"]);
    let w = String::from_utf8(w.stdout).unwrap();
    assert!(w.contains("schlick") && !w.contains("fresnel_dielectric"));
    let dir = tempfile::tempdir().unwrap();
    let png = |choice: &str| {
        let p = dir.path().join(format!("{choice}.png"));
        let o = run(&[
            "render",
            file,
            "--size",
            "32x32",
            "-o",
            p.to_str().unwrap(),
            "--variant",
            &format!("fresnel={choice}"),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        std::fs::read(p).unwrap()
    };
    assert_ne!(png("schlick"), png("exact"));
    assert_eq!(png("exact"), png("exact"));
}

/// Two choices of one file compile to different modules, so they must not share a cache key
/// (the GPU rasteriser keeps materials by `structure_key`: before, a choice rendered after
/// the default in one process showed the default's material).
#[test]
fn each_choice_has_its_own_key() {
    let (a, b) = (select("schlick"), select("exact"));
    assert_ne!(a.structure_key(), b.structure_key());
    assert_ne!(a.key(), b.key());
    assert_eq!(a.structure_key(), select("schlick").structure_key());
    // A graph without variants keys as its flat document alone.
    let g = single("schlick");
    assert_eq!(g.key(), serde_json::to_string(&g.flat_document()).unwrap());
}
