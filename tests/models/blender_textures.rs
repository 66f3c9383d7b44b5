//! matgraph's `noise_texture` against Blender's own Noise Texture: values Blender 4.2
//! computed (tests/blender/noise_reference.py, through geometry nodes, which share the
//! shader node's definition) at 64 points (round and seeded random) for 12 settings covering
//! 1D–4D, the five noise types, normalisation, fractional detail and distortion; and the
//! other Blender textures (white noise, gradient, Voronoi, wave, brick, magic) against their
//! own reference files in tests/blender/. Each node is evaluated through a graph on the CPU,
//! and on the GPU where there is one.

use crate::common;

use matgraph::{Attribute, Graph, Plan, PlanOptions, Registry, SampleBatch};
use serde_json::Value as J;

/// Largest |matgraph − Blender| allowed (the bound).
const BOUND: f64 = 1e-4;

fn reference() -> J {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/blender/noise_texture.json"
    );
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The graph of one case: noise_texture at geometry.position (1D: w = position.x).
fn case_graph(c: &J) -> Graph {
    let dims = match c["dimensions"].as_str().unwrap() {
        "1D" => "1d",
        "2D" => "2d",
        "3D" => "3d",
        _ => "4d",
    };
    let kind = c["type"].as_str().unwrap().to_ascii_lowercase();
    let w = if dims == "1d" {
        serde_json::json!({ "link": "p.x" })
    } else {
        c["w"].clone()
    };
    let text = serde_json::json!({
        "version": 1, "name": "noise",
        "nodes": [
            { "id": "geo", "type": "geometry" },
            { "id": "p", "type": "split", "inputs": { "v": { "link": "geo.position" } } },
            { "id": "n", "type": "noise_texture", "inputs": {
                "vector": { "link": "geo.position" }, "w": w,
                "scale": c["scale"], "detail": c["detail"], "roughness": c["roughness"],
                "lacunarity": c["lacunarity"], "offset": c["offset"], "gain": c["gain"],
                "distortion": c["distortion"], "dimensions": dims, "type": kind,
                "normalize": c["normalize"] } }
        ],
        "outputs": [ { "name": "fac", "from": "n.fac" }, { "name": "color", "from": "n.color" } ]
    });
    Graph::from_json(&text.to_string(), Registry::builtin()).unwrap_or_else(|e| panic!("{e:?}"))
}

fn batch(points: &[[f32; 3]]) -> SampleBatch {
    let mut b = SampleBatch::new(points.len());
    b.set_values(Attribute::Position, points).unwrap();
    b
}

#[test]
fn noise_texture_matches_blender_on_the_cpu() {
    let r = reference();
    assert_eq!(r["blender"], "4.2.0");
    let points = texture_points(&r);
    let mut report = Vec::new();
    let mut failed = Vec::new();
    for c in r["cases"].as_array().unwrap() {
        let graph = case_graph(c);
        let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
        let out = plan
            .execute(&batch(&points), &plan.default_parameters())
            .unwrap();
        let (d, at) = worst_of(&out, &c["fac"], &c["color"], points.len());
        let line = format!(
            "{} {} detail {} distortion {}: max |Δ| {d:.1e} ({at})",
            c["dimensions"], c["type"], c["detail"], c["distortion"]
        );
        if d > BOUND || d.is_nan() {
            failed.push(line.clone());
        }
        report.push(line);
    }
    println!("{}", report.join("\n"));
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

#[test]
fn noise_texture_matches_blender_on_the_gpu() {
    let Some(ctx) = common::gpu_context("noise_texture_matches_blender_on_the_gpu") else {
        return;
    };
    let r = reference();
    let points = texture_points(&r);
    let mut failed = Vec::new();
    for c in r["cases"].as_array().unwrap() {
        let graph = case_graph(c);
        let gpu = matgraph::gpu::GpuPlan::compile(ctx, &graph, &PlanOptions::default()).unwrap();
        let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
        let out = gpu
            .execute(&batch(&points), &plan.default_parameters())
            .unwrap();
        let (d, at) = worst_of(&out, &c["fac"], &c["color"], points.len());
        if d > BOUND || d.is_nan() {
            failed.push(format!("{} {}: {d:.1e} ({at})", c["dimensions"], c["type"]));
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

/// The reference points of a tests/blender/*.json file.
fn texture_points(r: &J) -> Vec<[f32; 3]> {
    r["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| [0, 1, 2].map(|k| p[k].as_f64().unwrap() as f32))
        .collect()
}

/// Evaluates `node` (its inputs, `vector` linked to the position; 1D: `w` to its x) on the
/// CPU, and on the GPU where there is one, at `points`: `[value, color]` per backend.
fn eval_node(
    node: serde_json::Value,
    value: &str,
    points: &[[f32; 3]],
) -> Vec<matgraph::OutputBatch> {
    let text = serde_json::json!({
        "version": 1, "name": "t",
        "nodes": [ { "id": "geo", "type": "geometry" },
                   { "id": "p", "type": "split", "inputs": { "v": { "link": "geo.position" } } },
                   node ],
        "outputs": [ { "name": "value", "from": format!("n.{value}") }, { "name": "color", "from": "n.color" } ]
    });
    let graph = Graph::from_json(&text.to_string(), Registry::builtin())
        .unwrap_or_else(|e| panic!("{e:?}"));
    let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
    let params = plan.default_parameters();
    let mut outs = vec![plan.execute(&batch(points), &params).unwrap()];
    if let Some(ctx) = common::gpu_context("blender_textures (GPU half)") {
        let gpu = matgraph::gpu::GpuPlan::compile(ctx, &graph, &PlanOptions::default()).unwrap();
        outs.push(gpu.execute(&batch(points), &params).unwrap());
    }
    outs
}

/// The worst |ours − Blender| over value (output 0) and colour (output 1), with where.
fn worst_of(out: &matgraph::OutputBatch, value: &J, color: &J, n: usize) -> (f64, String) {
    let mut w = (0.0f64, String::new());
    for i in 0..n {
        let mut check = |got: f32, want: f64, what: &str| {
            let d = (got as f64 - want).abs();
            if d > w.0 || d.is_nan() {
                w = (d, format!("point {i} {what}: ours {got} Blender {want}"));
            }
        };
        check(out.planar(0)[i], value[i].as_f64().unwrap(), "value");
        for k in 0..3 {
            check(
                out.planar(1)[k * n + i],
                color[i][k].as_f64().unwrap(),
                &format!("color[{k}]"),
            );
        }
    }
    w
}

#[test]
fn white_noise_and_gradient_texture_match_blender() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/blender/textures.json");
    let r: J = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    assert_eq!(r["blender"], "4.2.0");
    let points = texture_points(&r);
    let n = points.len();
    let mut failed = Vec::new();
    for c in r["white_noise"].as_array().unwrap() {
        let dims = c["dimensions"].as_str().unwrap().to_ascii_lowercase();
        let w = if dims == "1d" {
            serde_json::json!({ "link": "p.x" })
        } else {
            c["w"].clone()
        };
        let node = serde_json::json!({ "id": "n", "type": "white_noise", "inputs": {
            "vector": { "link": "geo.position" }, "w": w, "dimensions": dims } });
        for (b, out) in eval_node(node, "value", &points).iter().enumerate() {
            // A hash: bit-identical inputs give the same value; the only rounding is the
            // u32 → f32 conversion of the hash.
            let (d, at) = worst_of(out, &c["value"], &c["color"], n);
            if d > 1e-7 || d.is_nan() {
                failed.push(format!("white noise {dims} (backend {b}): {d:.1e} ({at})"));
            }
        }
    }
    for c in r["gradient"].as_array().unwrap() {
        let kind = c["type"].as_str().unwrap().to_ascii_lowercase();
        let node = serde_json::json!({ "id": "n", "type": "gradient_texture", "inputs": {
            "vector": { "link": "geo.position" }, "type": kind } });
        // Blender's shader node clamps to [0, 1] (svm_node_tex_gradient); the geometry-nodes
        // version that computed these values does not: clamp them here.
        let fac = clamp_json(&c["fac"]);
        let color = clamp_json(&c["color"]);
        for (b, out) in eval_node(node, "fac", &points).iter().enumerate() {
            let (d, at) = worst_of(out, &fac, &color, n);
            if d > BOUND || d.is_nan() {
                failed.push(format!("gradient {kind} (backend {b}): {d:.1e} ({at})"));
            }
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

/// A JSON number (or array of numbers) clamped to [0, 1].
fn clamp_json(v: &J) -> J {
    match v {
        J::Array(a) => J::Array(a.iter().map(clamp_json).collect()),
        J::Number(x) => serde_json::json!(x.as_f64().unwrap().clamp(0.0, 1.0)),
        other => other.clone(),
    }
}

#[test]
fn voronoi_texture_matches_blender() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/blender/voronoi_texture.json"
    );
    let r: J = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    assert_eq!(r["blender"], "4.2.0");
    let points = texture_points(&r);
    let n = points.len();
    let mut report = Vec::new();
    let mut failed = Vec::new();
    for c in r["cases"].as_array().unwrap() {
        let dims = c["dimensions"].as_str().unwrap().to_ascii_lowercase();
        let lower = |k: &str| c[k].as_str().unwrap().to_ascii_lowercase();
        let w = if dims == "1d" {
            serde_json::json!({ "link": "p.x" })
        } else {
            c["w"].clone()
        };
        let text = serde_json::json!({
            "version": 1, "name": "v",
            "nodes": [ { "id": "geo", "type": "geometry" },
                       { "id": "p", "type": "split", "inputs": { "v": { "link": "geo.position" } } },
                       { "id": "n", "type": "voronoi_texture", "inputs": {
                           "vector": { "link": "geo.position" }, "w": w, "scale": c["scale"],
                           "detail": c["detail"], "roughness": c["roughness"],
                           "lacunarity": c["lacunarity"], "smoothness": c["smoothness"],
                           "exponent": c["exponent"], "randomness": c["randomness"],
                           "dimensions": dims, "feature": lower("feature"),
                           "metric": lower("metric"), "normalize": c["normalize"] } } ],
            "outputs": [ { "name": "distance", "from": "n.distance" }, { "name": "color", "from": "n.color" },
                         { "name": "position", "from": "n.position" }, { "name": "w", "from": "n.w" },
                         { "name": "radius", "from": "n.radius" } ]
        });
        let graph = Graph::from_json(&text.to_string(), Registry::builtin())
            .unwrap_or_else(|e| panic!("{e:?}"));
        let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
        let params = plan.default_parameters();
        let mut outs = vec![plan.execute(&batch(&points), &params).unwrap()];
        if let Some(ctx) = common::gpu_context("voronoi_texture_matches_blender (GPU half)") {
            let gpu =
                matgraph::gpu::GpuPlan::compile(ctx, &graph, &PlanOptions::default()).unwrap();
            outs.push(gpu.execute(&batch(&points), &params).unwrap());
        }
        for (b, out) in outs.iter().enumerate() {
            let mut w = (0.0f64, String::new());
            for i in 0..n {
                let mut check = |got: f32, want: f64, what: &str| {
                    let d = (got as f64 - want).abs();
                    if d > w.0 || d.is_nan() {
                        w = (d, format!("point {i} {what}: ours {got} Blender {want}"));
                    }
                };
                check(
                    out.planar(0)[i],
                    c["distance"][i].as_f64().unwrap(),
                    "distance",
                );
                check(out.planar(3)[i], c["w_out"][i].as_f64().unwrap(), "w");
                check(out.planar(4)[i], c["radius"][i].as_f64().unwrap(), "radius");
                for k in 0..3 {
                    check(
                        out.planar(1)[k * n + i],
                        c["color"][i][k].as_f64().unwrap(),
                        "color",
                    );
                    check(
                        out.planar(2)[k * n + i],
                        c["position"][i][k].as_f64().unwrap(),
                        "position",
                    );
                }
            }
            let line = format!(
                "{} {} {} detail {} (backend {b}): max |Δ| {:.1e} ({})",
                c["dimensions"], c["feature"], c["metric"], c["detail"], w.0, w.1
            );
            if w.0 > BOUND || w.0.is_nan() {
                failed.push(line.clone());
            }
            report.push(line);
        }
    }
    println!("{}", report.join("\n"));
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

/// tests/blender/wave_brick_magic.json: Blender 4.2's Wave, Brick and Magic Texture at 64
/// f32-exact points (6 round, the rest seeded random in [−1.5, 1.5]³; brick's kept 10⁻³
/// away from every brick edge in every case, tests/blender/wave_brick_magic_reference.py).
fn wave_brick_magic() -> J {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/blender/wave_brick_magic.json"
    );
    let r: J = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    assert_eq!(r["blender"], "4.2.0");
    r
}

/// Runs `node` at the reference points on each backend and checks fac and colour against
/// Blender's: one report line per backend, and the failures.
fn check_cases(
    what: &str,
    node: serde_json::Value,
    case: &J,
    points: &[[f32; 3]],
    phase: bool,
    report: &mut Vec<String>,
    failed: &mut Vec<String>,
) {
    let n = points.len();
    for (b, out) in eval_node(node, "fac", points).iter().enumerate() {
        let (d, at) = if phase {
            worst_phase_of(out, &case["fac"], &case["color"], n)
        } else {
            worst_of(out, &case["fac"], &case["color"], n)
        };
        let line = format!("{what} (backend {b}): max |Δ| {d:.1e} ({at})");
        if d > BOUND || d.is_nan() {
            failed.push(line.clone());
        }
        report.push(line);
    }
}

/// [`worst_of`] for a saw wave: each difference taken mod 1, since 0 and 1 are the two sides
/// of the saw's jump (a point within an ULP of it may fall on either).
fn worst_phase_of(out: &matgraph::OutputBatch, value: &J, color: &J, n: usize) -> (f64, String) {
    let mut w = (0.0f64, String::new());
    for i in 0..n {
        let mut check = |got: f32, want: f64, what: &str| {
            let d = (got as f64 - want).rem_euclid(1.0);
            let d = d.min(1.0 - d);
            if d > w.0 || d.is_nan() {
                w = (d, format!("point {i} {what}: ours {got} Blender {want}"));
            }
        };
        check(out.planar(0)[i], value[i].as_f64().unwrap(), "fac");
        for k in 0..3 {
            check(
                out.planar(1)[k * n + i],
                color[i][k].as_f64().unwrap(),
                &format!("color[{k}]"),
            );
        }
    }
    w
}

#[test]
fn wave_texture_matches_blender() {
    let r = wave_brick_magic();
    let points = texture_points(&r);
    let (mut report, mut failed) = (Vec::new(), Vec::new());
    for c in r["wave"].as_array().unwrap() {
        let lower = |k: &str| c[k].as_str().unwrap().to_ascii_lowercase();
        let node = serde_json::json!({ "id": "n", "type": "wave_texture", "inputs": {
            "vector": { "link": "geo.position" }, "scale": c["scale"],
            "distortion": c["distortion"], "detail": c["detail"],
            "detail_scale": c["detail_scale"], "detail_roughness": c["detail_roughness"],
            "phase_offset": c["phase_offset"], "type": lower("type"),
            "bands_direction": lower("bands_direction"),
            "rings_direction": lower("rings_direction"), "profile": lower("profile") } });
        let what = format!(
            "wave {} {}/{} {} distortion {}",
            c["type"], c["bands_direction"], c["rings_direction"], c["profile"], c["distortion"]
        );
        let saw = c["profile"] == "SAW";
        check_cases(&what, node, c, &points, saw, &mut report, &mut failed);
    }
    println!("{}", report.join("\n"));
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

#[test]
fn brick_texture_matches_blender() {
    let r = wave_brick_magic();
    let points = texture_points(&r);
    let (mut report, mut failed) = (Vec::new(), Vec::new());
    for c in r["brick"].as_array().unwrap() {
        let node = serde_json::json!({ "id": "n", "type": "brick_texture", "inputs": {
            "vector": { "link": "geo.position" }, "color1": c["color1"], "color2": c["color2"],
            "mortar": c["mortar"], "scale": c["scale"], "mortar_size": c["mortar_size"],
            "mortar_smooth": c["mortar_smooth"], "bias": c["bias"],
            "brick_width": c["brick_width"], "row_height": c["row_height"],
            "offset": c["offset"], "offset_frequency": c["offset_frequency"],
            "squash": c["squash"], "squash_frequency": c["squash_frequency"] } });
        let what = format!(
            "brick offset {}/{} squash {}/{} mortar {} smooth {} bias {}",
            c["offset"],
            c["offset_frequency"],
            c["squash"],
            c["squash_frequency"],
            c["mortar_size"],
            c["mortar_smooth"],
            c["bias"]
        );
        check_cases(&what, node, c, &points, false, &mut report, &mut failed);
    }
    println!("{}", report.join("\n"));
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

#[test]
fn magic_texture_matches_blender() {
    let r = wave_brick_magic();
    let points = texture_points(&r);
    let (mut report, mut failed) = (Vec::new(), Vec::new());
    for c in r["magic"].as_array().unwrap() {
        let node = serde_json::json!({ "id": "n", "type": "magic_texture", "inputs": {
            "vector": { "link": "geo.position" }, "scale": c["scale"],
            "distortion": c["distortion"], "depth": c["depth"] } });
        let what = format!(
            "magic depth {} scale {} distortion {}",
            c["depth"], c["scale"], c["distortion"]
        );
        check_cases(&what, node, c, &points, false, &mut report, &mut failed);
    }
    println!("{}", report.join("\n"));
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}
