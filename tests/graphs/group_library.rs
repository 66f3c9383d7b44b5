//! The group library `graphs/lib/` (issue 34): every group against an independent f64 closed
//! form at round and seeded random f32-exact points, evaluated through the public API
//! (`matgraph::io::load_graph` of a graph written beside a copy of the library, then
//! `Plan`), and the two bundled graphs rewritten to use the library
//! (`graphs/water_toon_you.json`, `graphs/water_toon_day.json`) against their flat originals
//! (`tests/groups_flat/`), bit for bit on the CPU.
//!
//! The test graphs carry per-sample values into the groups through the geometry attributes
//! (a `split` of a vector passes its components on exactly), so one plan evaluates every
//! point.

use crate::common;

use common::rng::Rng;
use matgraph::nodes::thin_film::{CMF_1931_2DEG, D65, LAMBDA_MIN_NM, LEN};
use matgraph::render::{RenderOptions, graph_scene, render};
use matgraph::{Attribute, Graph, OutputBatch, Plan, PlanOptions, Registry, SampleBatch, Value};
use serde_json::{Value as J, json};
use std::path::{Path, PathBuf};

/// The draws these tests make from the shared seeded generator.
impl Rng {
    /// A unit vector, uniform on the sphere, rounded to f32.
    fn unit_vector(&mut self) -> [f32; 3] {
        loop {
            let v = [
                self.f32(-1.0, 1.0),
                self.f32(-1.0, 1.0),
                self.f32(-1.0, 1.0),
            ];
            let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if l > 0.1 && l <= 1.0 {
                return v.map(|c| c / l);
            }
        }
    }
}

// ---- Workspace: a copy of graphs/lib beside the test graphs ----------------------------

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// The library files, sorted.
fn library_files() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(repo("graphs/lib"))
        .expect("graphs/lib exists")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    v.sort();
    assert!(!v.is_empty(), "no graphs/lib/*.json");
    v
}

/// A temporary folder holding `lib/` (a copy of graphs/lib), where test graphs are written
/// and loaded from disk, so that their `lib/NAME.json#GROUP` references resolve as a
/// bundled graph's do.
struct Workspace {
    dir: tempfile::TempDir,
}

impl Workspace {
    fn new() -> Workspace {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("lib")).unwrap();
        for f in library_files() {
            std::fs::copy(&f, dir.path().join("lib").join(f.file_name().unwrap())).unwrap();
        }
        Workspace { dir }
    }

    /// Writes `doc` as `name` and loads it with `matgraph::io::load_graph`.
    fn load(&self, name: &str, doc: &J) -> Graph {
        let path = self.dir.path().join(name);
        std::fs::write(&path, serde_json::to_string_pretty(doc).unwrap()).unwrap();
        matgraph::io::load_graph(&path, Registry::builtin())
            .unwrap_or_else(|e| panic!("{name}: {e}\n{doc:#}"))
    }
}

/// A version-2 test graph: `geo` (geometry), `p` = split(geo.position), `q` = split(geo.uv),
/// one instance `g` of `group` with `inputs`, and `outputs` (name, `node.output`).
fn graph_with(group: &str, inputs: J, outputs: &[(&str, &str)]) -> J {
    json!({
        "version": 2,
        "name": "test",
        "nodes": [
            { "id": "geo", "type": "geometry" },
            { "id": "p", "type": "split", "inputs": { "v": { "link": "geo.position" } } },
            { "id": "q", "type": "split", "inputs": { "v": { "link": "geo.uv" } } },
            { "id": "g", "type": "group", "group": group, "inputs": inputs }
        ],
        "outputs": outputs
            .iter()
            .map(|(name, from)| json!({ "name": name, "from": from }))
            .collect::<Vec<J>>()
    })
}

fn link(to: &str) -> J {
    json!({ "link": to })
}

/// Per-sample attribute values (unset ones take their defaults).
#[derive(Default)]
struct Samples {
    columns: Vec<(Attribute, Vec<[f32; 3]>)>,
    time: f32,
}

impl Samples {
    fn set(&mut self, attr: Attribute, values: Vec<[f32; 3]>) {
        self.columns.push((attr, values));
    }
}

/// Evaluates every graph output of `graph` at `samples` on the CPU.
fn eval(graph: &Graph, samples: &Samples) -> OutputBatch {
    let n = samples.columns.first().map_or(1, |(_, v)| v.len());
    let plan = Plan::compile(graph, &PlanOptions::default()).unwrap();
    let mut batch = SampleBatch::new(n);
    batch.set_time(samples.time);
    for (attr, values) in &samples.columns {
        batch.set_values(*attr, values).unwrap();
    }
    plan.execute(&batch, &plan.default_parameters()).unwrap()
}

/// Output `name` of sample `i`, as f64 lanes.
fn get(out: &OutputBatch, name: &str, i: usize) -> Vec<f64> {
    let k = out
        .index(name)
        .unwrap_or_else(|| panic!("no output {name}"));
    let v: Value = out.value(k, i);
    v.lanes()[..out.ty(k).width()]
        .iter()
        .map(|&x| x as f64)
        .collect()
}

/// `|got − want| ≤ tol` for every lane, with the point in the message.
fn close(what: &str, got: &[f64], want: &[f64], tol: f64, at: &dyn std::fmt::Debug) -> f64 {
    assert_eq!(got.len(), want.len(), "{what}");
    let mut worst = 0.0f64;
    for (g, w) in got.iter().zip(want) {
        let err = (g - w).abs();
        assert!(
            err <= tol,
            "{what} at {at:?}: got {got:?}, want {want:?} (error {err:e} > {tol:e})"
        );
        worst = worst.max(err);
    }
    worst
}

// ---- The library files ------------------------------------------------------------------

/// Every library file is a version-2 graph document with no nodes and no outputs of its own;
/// every group is documented, every input typed, defaulted and documented with its ranges
/// in order; and every group, used with its defaults alone, loads from another file and
/// evaluates to finite values at every output.
#[test]
fn library_files_parse_and_every_group_loads_with_its_defaults() {
    let ws = Workspace::new();
    let mut groups = 0;
    for path in library_files() {
        let file = path.file_name().unwrap().to_string_lossy().into_owned();
        let text = std::fs::read_to_string(&path).unwrap();
        let doc = matgraph::GraphDocument::parse(&text).unwrap_or_else(|e| panic!("{file}: {e:?}"));
        assert_eq!(doc.version, 2, "{file}");
        assert!(doc.nodes.is_empty() && doc.outputs.is_empty(), "{file}");
        assert!(!doc.doc.is_empty(), "{file}: no doc");
        assert!(!doc.groups.is_empty(), "{file}: no groups");
        for (name, g) in &doc.groups {
            assert!(g.doc.len() > 80, "{file}#{name}: doc too short");
            assert!(!g.outputs.is_empty(), "{file}#{name}: no outputs");
            for i in &g.inputs {
                let what = format!("{file}#{name} input {}", i.name);
                assert!(
                    ["float", "vec2", "vec3", "vec4", "color"].contains(&i.ty.as_str()),
                    "{what}"
                );
                assert!(i.default.is_some(), "{what}: no default");
                assert!(!i.doc.is_empty(), "{what}: no doc");
                assert!(i.soft_range.is_some(), "{what}: no soft range");
                if let (Some(s), Some(h)) = (i.soft_range, i.hard_range) {
                    assert!(h[0] <= s[0] && s[1] <= h[1], "{what}: soft outside hard");
                }
            }
            let outputs: Vec<(String, String)> = g
                .outputs
                .iter()
                .map(|o| (o.name.clone(), format!("g.{}", o.name)))
                .collect();
            let refs: Vec<(&str, &str)> = outputs
                .iter()
                .map(|(a, b)| (a.as_str(), b.as_str()))
                .collect();
            let reference = format!("lib/{file}#{name}");
            let graph = ws.load("defaults.json", &graph_with(&reference, json!({}), &refs));
            let out = eval(&graph, &Samples::default());
            for (o, _) in &outputs {
                let v = get(&out, o, 0);
                assert!(v.iter().all(|x| x.is_finite()), "{reference}.{o}: {v:?}");
            }
            groups += 1;
        }
    }
    assert!(groups >= 6, "{groups} groups");
}

// ---- Fresnel ----------------------------------------------------------------------------

/// Exact unpolarised Fresnel reflectance in f64 (Hecht, Optics §4.6 eqs. 4.34, 4.40):
/// light from the `n_out` side when `c > 0`, from the `n_in` side when `c < 0`; TIR gives 1.
/// Also how close the refracted ray is to grazing (1 − sin²θt).
fn fresnel_exact(c: f64, n_out: f64, n_in: f64) -> (f64, f64) {
    let (c, n1, n2) = if c < 0.0 {
        (-c, n_in, n_out)
    } else {
        (c, n_out, n_in)
    };
    if n1 == n2 {
        return (0.0, 1.0);
    }
    let sin2t = (n1 / n2).powi(2) * (1.0 - c * c);
    if sin2t >= 1.0 {
        return (1.0, 1.0 - sin2t);
    }
    let ct = (1.0 - sin2t).sqrt();
    let rs = (n1 * c - n2 * ct) / (n1 * c + n2 * ct);
    let rp = (n2 * c - n1 * ct) / (n2 * c + n1 * ct);
    (0.5 * (rs * rs + rp * rp), 1.0 - sin2t)
}

/// Schlick 1994 eq. 24 with F0 = ((n1 − n2)/(n1 + n2))², cos θ clamped to [0, 1].
fn fresnel_schlick(c: f64, n_out: f64, n_in: f64) -> (f64, f64) {
    let f0 = ((n_out - n_in) / (n_out + n_in)).powi(2);
    (f0 + (1.0 - f0) * (1.0 - c.clamp(0.0, 1.0)).powi(5), f0)
}

/// The f32 error of the exact form grows where the refracted ray grazes (cos²θt cancels):
/// node fresnel_dielectric's doc gives ~3e-4 within 0.01° of the critical angle.
fn exact_tolerance(margin: f64) -> f64 {
    if margin.abs() < 1e-3 { 1e-3 } else { 2e-5 }
}

/// Points (cos θ, n_inside, n_outside): round ones, then seeded random f32s.
fn fresnel_points(seed: u64, n: usize) -> Vec<[f32; 3]> {
    let mut points = Vec::new();
    for c in [1.0, 0.5, 0.0, -0.5, -1.0, 0.866_025_4, 0.1] {
        for (ior, out) in [
            (1.5, 1.0),
            (1.33, 1.0),
            (2.42, 1.0),
            (1.0, 1.33),
            (1.52, 1.33),
        ] {
            points.push([c, ior, out]);
        }
    }
    let mut rng = Rng(seed);
    for _ in 0..n {
        points.push([
            rng.f32(-1.0, 1.0),
            rng.f32(1.0, 3.0),
            if rng.next() & 1 == 0 {
                1.0
            } else {
                rng.f32(1.0, 2.0)
            },
        ]);
    }
    points
}

#[test]
fn fresnel_pair_is_schlick_and_the_exact_dielectric_fresnel() {
    let ws = Workspace::new();
    let graph = ws.load(
        "pair.json",
        &graph_with(
            "lib/fresnel.json#fresnel_pair",
            json!({ "cos_theta": link("p.x"), "ior": link("p.y"), "ior_outside": link("p.z") }),
            &[
                ("schlick", "g.schlick"),
                ("exact", "g.exact"),
                ("transmittance", "g.transmittance"),
                ("f0", "g.f0"),
            ],
        ),
    );
    let points = fresnel_points(0xf2e5, 2000);
    let mut samples = Samples::default();
    samples.set(Attribute::Position, points.clone());
    let out = eval(&graph, &samples);
    let (mut worst_s, mut worst_e) = (0.0f64, 0.0f64);
    for (i, p) in points.iter().enumerate() {
        let [c, n_in, n_out] = p.map(|x| x as f64);
        let (schlick, f0) = fresnel_schlick(c, n_out, n_in);
        let (exact, margin) = fresnel_exact(c, n_out, n_in);
        close("f0", &get(&out, "f0", i), &[f0], 1e-7, p);
        worst_s = worst_s.max(close(
            "schlick",
            &get(&out, "schlick", i),
            &[schlick],
            1e-6,
            p,
        ));
        let tol = exact_tolerance(margin);
        let e = close("exact", &get(&out, "exact", i), &[exact], tol, p);
        close(
            "transmittance",
            &get(&out, "transmittance", i),
            &[1.0 - exact],
            tol,
            p,
        );
        if tol < 1e-4 {
            worst_e = worst_e.max(e);
        }
    }
    // Round values: glass face-on 4 %, and total internal reflection from inside water.
    let at =
        |c: f32, n_in: f32, n_out: f32| points.iter().position(|p| *p == [c, n_in, n_out]).unwrap();
    let i = at(1.0, 1.5, 1.0);
    assert!((get(&out, "exact", i)[0] - 0.04).abs() < 1e-7);
    assert!((get(&out, "schlick", i)[0] - 0.04).abs() < 1e-7);
    // From inside water (cos θ < 0) 60° off the normal, beyond the critical angle.
    assert_eq!(get(&out, "exact", at(-0.5, 1.33, 1.0)), [1.0], "TIR");
    eprintln!("fresnel_pair: worst error schlick {worst_s:.2e}, exact {worst_e:.2e}");
}

#[test]
fn fresnel_layer_blends_base_and_coat_by_the_exact_fresnel_weight() {
    let ws = Workspace::new();
    let graph = ws.load(
        "layer.json",
        &graph_with(
            "lib/fresnel.json#fresnel_layer",
            json!({
                "base": link("geo.light_color"),
                "coat": link("geo.light"),
                "cos_theta": link("p.x"),
                "ior": link("p.y"),
                "ior_outside": link("p.z")
            }),
            &[("color", "g.color"), ("weight", "g.weight")],
        ),
    );
    let points = fresnel_points(0x1a7e2, 2000);
    let mut rng = Rng(0xc0a7);
    let mut colour = || [rng.f32(0.0, 4.0), rng.f32(0.0, 1.0), rng.f32(0.0, 0.5)];
    let bases: Vec<[f32; 3]> = (0..points.len()).map(|_| colour()).collect();
    let coats: Vec<[f32; 3]> = (0..points.len()).map(|_| colour()).collect();
    let mut samples = Samples::default();
    samples.set(Attribute::Position, points.clone());
    samples.set(Attribute::LightColor, bases.clone());
    samples.set(Attribute::Light, coats.clone());
    let out = eval(&graph, &samples);
    for (i, p) in points.iter().enumerate() {
        let [c, n_in, n_out] = p.map(|x| x as f64);
        let (r, margin) = fresnel_exact(c, n_out, n_in);
        let tol = exact_tolerance(margin);
        close("weight", &get(&out, "weight", i), &[r], tol, p);
        let want: Vec<f64> = (0..3)
            .map(|k| {
                let (a, b) = (bases[i][k] as f64, coats[i][k] as f64);
                a + (b - a) * r
            })
            .collect();
        // The weight's error times |coat − base| ≤ 4, plus the f32 mix.
        close("color", &get(&out, "color", i), &want, 4.0 * tol + 1e-6, p);
    }
    // Face-on glass (R = 0.04) over black under a white coat: 0.04 grey.
    let mut one = Samples::default();
    one.set(Attribute::Position, vec![[1.0, 1.5, 1.0]]);
    one.set(Attribute::LightColor, vec![[0.0; 3]]);
    one.set(Attribute::Light, vec![[1.0; 3]]);
    let out = eval(&graph, &one);
    close(
        "color",
        &get(&out, "color", 0),
        &[0.04; 3],
        1e-7,
        &"face-on",
    );
}

// ---- Toon -------------------------------------------------------------------------------

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn f64v(v: [f32; 3]) -> [f64; 3] {
    v.map(|x| x as f64)
}

fn smoothstep(t: f64) -> f64 {
    let t = t.clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The three-band ramp's level at N·L = x, written as the sum of its two band edges (at
/// x = 1/3 and 2/3, in band units y = 3x at 1 and 2), each a step (softness 0) or a
/// smoothstep over `softness` of a band centred on the edge; half a level per edge
/// (Lake et al. 2000's banded 1D texture).
fn ramp_level(x: f64, softness: f64) -> f64 {
    let y = 3.0 * x.clamp(0.0, 1.0);
    let h = 0.5 * softness;
    let edge = |e: f64| {
        if h == 0.0 {
            if y >= e { 1.0 } else { 0.0 }
        } else {
            smoothstep((y - (e - h)) / (2.0 * h))
        }
    };
    0.5 * (edge(1.0) + edge(2.0))
}

#[test]
fn toon_ramp_is_three_bands_of_n_dot_l() {
    let ws = Workspace::new();
    let graph = ws.load(
        "ramp.json",
        &graph_with(
            "lib/toon.json#toon_ramp",
            json!({
                "normal": link("geo.normal"),
                "light": link("geo.light"),
                "color_dark": link("geo.light_color"),
                "color_light": link("geo.view"),
                "softness": link("geo.depth")
            }),
            &[
                ("color", "g.color"),
                ("level", "g.level"),
                ("n_dot_l", "g.n_dot_l"),
            ],
        ),
    );
    let mut rng = Rng(0x7007);
    let (mut normals, mut lights, mut darks, mut brights, mut soft) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    // Round points: N·L = 1, 0.5, 0, −1 (bands 2, 1, 0, 0) with the default colours.
    for (l, s) in [
        ([0.0, 1.0, 0.0], 0.0),
        ([0.866_025_4, 0.5, 0.0], 0.0),
        ([1.0, 0.0, 0.0], 0.0),
        ([0.0, -1.0, 0.0], 0.0),
        ([0.866_025_4, 0.5, 0.0], 1.0),
    ] {
        normals.push([0.0, 1.0, 0.0]);
        lights.push(l);
        darks.push([0.1, 0.1, 0.2]);
        brights.push([1.0, 1.0, 1.0]);
        soft.push([s, 0.0, 0.0]);
    }
    for k in 0..3000 {
        normals.push(rng.unit_vector());
        lights.push(rng.unit_vector());
        darks.push([rng.f32(0.0, 0.5), rng.f32(0.0, 0.5), rng.f32(0.0, 0.5)]);
        brights.push([rng.f32(0.5, 2.0), rng.f32(0.5, 2.0), rng.f32(0.5, 2.0)]);
        // A third hard edges, the rest soft.
        soft.push([if k % 3 == 0 { 0.0 } else { rng.f32(0.05, 1.0) }, 0.0, 0.0]);
    }
    let mut samples = Samples::default();
    samples.set(Attribute::Normal, normals.clone());
    samples.set(Attribute::Light, lights.clone());
    samples.set(Attribute::LightColor, darks.clone());
    samples.set(Attribute::View, brights.clone());
    samples.set(Attribute::Depth, soft.clone());
    let out = eval(&graph, &samples);
    let mut skipped = 0;
    for i in 0..normals.len() {
        let x = dot(f64v(normals[i]), f64v(lights[i]));
        let s = soft[i][0] as f64;
        let at = (normals[i], lights[i], s);
        close("n_dot_l", &get(&out, "n_dot_l", i), &[x], 1e-6, &at);
        // A hard edge within the f32 dot's error of x: either band is right.
        let y = 3.0 * x.clamp(0.0, 1.0);
        if s == 0.0 && [1.0, 2.0].iter().any(|e| (y - e).abs() < 1e-5) {
            skipped += 1;
            continue;
        }
        let level = ramp_level(x, s);
        // Soft edges: the smoothstep's slope (≤ 1.5 / softness per band, 3 bands per unit
        // of x) times the f32 error of N·L.
        let tol = if s == 0.0 { 1e-7 } else { 1e-5 / s };
        close("level", &get(&out, "level", i), &[level], tol, &at);
        let want: Vec<f64> = (0..3)
            .map(|k| {
                let (d, b) = (darks[i][k] as f64, brights[i][k] as f64);
                d + (b - d) * level
            })
            .collect();
        close(
            "color",
            &get(&out, "color", i),
            &want,
            2.0 * tol + 1e-6,
            &at,
        );
    }
    assert!(skipped < 10, "{skipped} points at a band edge");
    // The round points: bands 2, 1, 0, 0.
    for (i, want) in [1.0, 0.5, 0.0, 0.0].into_iter().enumerate() {
        assert_eq!(get(&out, "level", i), [want], "round point {i}");
    }
    let grey = 0.1 + 0.9 * 0.5;
    close(
        "color",
        &get(&out, "color", 1),
        &[grey, grey, 0.2 + 0.8 * 0.5],
        1e-7,
        &"N·L = 0.5",
    );
    // N·L = 0.5 is y = 1.5, the edge of the soft blends of both edges (softness 1):
    // smoothstep(1) + smoothstep(0) = one edge, level 0.5.
    close("level", &get(&out, "level", 4), &[0.5], 1e-6, &"soft");
}

#[test]
fn toon_highlight_is_a_stepped_blinn_phong_lobe() {
    let ws = Workspace::new();
    let graph = ws.load(
        "highlight.json",
        &graph_with(
            "lib/toon.json#toon_highlight",
            json!({
                "normal": link("geo.normal"),
                "light": link("geo.light"),
                "view": link("geo.view"),
                "shininess": link("p.x"),
                "threshold": link("p.y")
            }),
            &[("band", "g.band"), ("lobe", "g.lobe")],
        ),
    );
    let mut rng = Rng(0x4141);
    let (mut n, mut l, mut v, mut p) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    // Round points: the mirror configuration (N·H = 1: on) and 60° off it.
    n.push([0.0, 1.0, 0.0]);
    l.push([0.6, 0.8, 0.0]);
    v.push([-0.6, 0.8, 0.0]);
    p.push([48.0, 0.5, 0.0]);
    n.push([0.0, 1.0, 0.0]);
    l.push([0.866_025_4, 0.5, 0.0]);
    v.push([0.866_025_4, 0.5, 0.0]);
    p.push([48.0, 0.5, 0.0]);
    for _ in 0..3000 {
        let normal = rng.unit_vector();
        // Light and view mostly near the mirror direction, so that the band is often on.
        let h = rng.unit_vector();
        let h = if dot(f64v(h), f64v(normal)) < 0.0 {
            h.map(|c| -c)
        } else {
            h
        };
        let mix = |a: [f32; 3], b: [f32; 3], t: f32| {
            let m = [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * t);
            let len = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
            m.map(|c| c / len)
        };
        let t = rng.f32(0.0, 0.3);
        n.push(normal);
        l.push(mix(h, rng.unit_vector(), t));
        v.push(rng.unit_vector());
        p.push([rng.f32(1.0, 256.0), rng.f32(0.0, 1.0), 0.0]);
        // Every other point: the view mirrored about the normal-ish half vector.
        let last = l.len() - 1;
        if last % 2 == 0 {
            let lv = f64v(l[last]);
            let hn = f64v(normal);
            let d = dot(lv, hn);
            v[last] = [0, 1, 2].map(|k| (2.0 * d * hn[k] - lv[k]) as f32);
        }
    }
    let mut samples = Samples::default();
    samples.set(Attribute::Normal, n.clone());
    samples.set(Attribute::Light, l.clone());
    samples.set(Attribute::View, v.clone());
    samples.set(Attribute::Position, p.clone());
    let out = eval(&graph, &samples);
    let (mut on, mut checked) = (0, 0);
    for i in 0..n.len() {
        let (lv, vv) = (f64v(l[i]), f64v(v[i]));
        let sum = [lv[0] + vv[0], lv[1] + vv[1], lv[2] + vv[2]];
        let len = dot(sum, sum).sqrt();
        if len < 0.1 {
            continue;
        }
        let h = sum.map(|c| c / len);
        let nh = dot(f64v(n[i]), h).clamp(0.0, 1.0);
        let (m, threshold) = (p[i][0] as f64, p[i][1] as f64);
        let lobe = nh.powf(m);
        let at = (n[i], l[i], v[i], m, threshold);
        // pow's relative error is ~m times N·H's (a few f32 ulps).
        close(
            "lobe",
            &get(&out, "lobe", i),
            &[lobe],
            2e-4 * lobe + 1e-7,
            &at,
        );
        if (lobe - threshold).abs() < 1e-3 {
            continue;
        }
        let band = if lobe >= threshold { 1.0 } else { 0.0 };
        assert_eq!(get(&out, "band", i), [band], "band at {at:?}");
        on += band as usize;
        checked += 1;
    }
    assert!(
        checked > 2500 && on > 100 && on < checked - 100,
        "{on} of {checked}"
    );
    assert_eq!(get(&out, "band", 0), [1.0]);
    assert_eq!(get(&out, "lobe", 0), [1.0]);
    // 60° off the normal: N·H = cos 60° = 0.5, 0.5⁴⁸ ≈ 3.6e-15: off.
    assert_eq!(get(&out, "band", 1), [0.0]);
}

// ---- Water ------------------------------------------------------------------------------

/// The library's wave set, as its doc gives it: direction (x, z), wavelength (m), amplitude
/// (m), phase (rad).
const WAVES: [([f64; 2], f64, f64, f64); 8] = [
    ([-0.1736482, 0.9848078], 14.0, 0.18, 0.0),
    ([0.3420201, 0.9396926], 9.0, 0.11, 1.3),
    ([-0.6427876, 0.7660444], 6.5, 0.08, 2.9),
    ([0.0871557, 0.9961947], 4.3, 0.05, 4.4),
    ([-0.4226183, 0.9063078], 3.1, 0.035, 0.7),
    ([0.5735764, 0.819152], 2.2, 0.025, 5.1),
    ([-0.819152, 0.5735764], 1.6, 0.018, 3.6),
    ([-0.0871557, 0.9961947], 1.1, 0.012, 2.2),
];

/// Standard gravity (m/s²), deep-water dispersion ω² = g k.
const G: f64 = 9.80665;

/// Gerstner waves in f64 (GPU Gems 2004 ch. 1 eq. 9, y up): the offset of lattice point
/// (x, z) at time t and the unit normal ∂P/∂z × ∂P/∂x from the analytic derivatives.
fn gerstner_f64(x: f64, z: f64, t: f64, amp: f64, len: f64, q: f64) -> ([f64; 3], [f64; 3]) {
    let mut off = [0.0; 3];
    let mut dpdx = [1.0, 0.0, 0.0];
    let mut dpdz = [0.0, 0.0, 1.0];
    for (d, lambda, a, phase) in WAVES {
        let l = (d[0] * d[0] + d[1] * d[1]).sqrt();
        let (dx, dz) = (d[0] / l, d[1] / l);
        let lambda = (lambda * len).max(0.1);
        let a = a * amp;
        let k = 2.0 * std::f64::consts::PI / lambda;
        let omega = (G * k).sqrt();
        let theta = k * (dx * x + dz * z) - omega * t + phase;
        let (s, c) = theta.sin_cos();
        off[0] += q * a * dx * c;
        off[1] += a * s;
        off[2] += q * a * dz * c;
        // ∂θ/∂x = k dx, ∂θ/∂z = k dz.
        for (dp, dk) in [(&mut dpdx, k * dx), (&mut dpdz, k * dz)] {
            dp[0] -= q * a * dx * s * dk;
            dp[1] += a * c * dk;
            dp[2] -= q * a * dz * s * dk;
        }
    }
    let nrm = [
        dpdz[1] * dpdx[2] - dpdz[2] * dpdx[1],
        dpdz[2] * dpdx[0] - dpdz[0] * dpdx[2],
        dpdz[0] * dpdx[1] - dpdz[1] * dpdx[0],
    ];
    let l = dot(nrm, nrm).sqrt();
    (off, nrm.map(|c| c / l))
}

#[test]
fn gerstner_wave_set_is_the_eight_wave_sum_scaled() {
    let ws = Workspace::new();
    let graph = ws.load(
        "waves.json",
        &json!({
            "version": 2,
            "name": "waves",
            "nodes": [
                { "id": "geo", "type": "geometry" },
                { "id": "clock", "type": "time" },
                { "id": "q", "type": "split", "inputs": { "v": { "link": "geo.uv" } } },
                {
                    "id": "g",
                    "type": "group",
                    "group": "lib/water.json#gerstner_wave_set",
                    "inputs": {
                        "position": link("geo.position"),
                        "time": link("clock.time"),
                        "amplitude_scale": link("geo.depth"),
                        "wavelength_scale": link("q.x"),
                        "steepness": link("q.y")
                    }
                }
            ],
            "outputs": [
                { "name": "offset", "from": "g.offset" },
                { "name": "normal", "from": "g.normal" }
            ]
        }),
    );
    let mut rng = Rng(0x9e25);
    let (mut worst, mut checked) = ((0.0f64, 0.0f64), 0);
    for time in [0.0f32, 1.5, 17.25] {
        let (mut pos, mut uv, mut depth) = (Vec::new(), Vec::new(), Vec::new());
        // Round points with the scales at 1 (the water_toon_* waves), then random ones.
        for (x, z) in [(0.0, 0.0), (1.0, -2.0), (10.0, 10.0), (-25.0, 7.5)] {
            pos.push([x, 0.0, z]);
            uv.push([1.0, 1.0, 0.0]);
            depth.push([1.0, 0.0, 0.0]);
        }
        for _ in 0..500 {
            pos.push([rng.f32(-40.0, 40.0), 0.0, rng.f32(-40.0, 40.0)]);
            uv.push([rng.f32(0.5, 2.0), rng.f32(0.0, 1.5), 0.0]);
            depth.push([rng.f32(0.0, 2.0), 0.0, 0.0]);
        }
        let mut samples = Samples {
            time,
            ..Samples::default()
        };
        samples.set(Attribute::Position, pos.clone());
        samples.set(Attribute::Uv, uv.clone());
        samples.set(Attribute::Depth, depth.clone());
        let out = eval(&graph, &samples);
        for i in 0..pos.len() {
            let (x, z) = (pos[i][0] as f64, pos[i][2] as f64);
            let (amp, len, q) = (depth[i][0] as f64, uv[i][0] as f64, uv[i][1] as f64);
            let (off, nrm) = gerstner_f64(x, z, time as f64, amp, len, q);
            let at = (x, z, time, amp, len, q);
            // f32 phases of up to ~250 rad carry ~3e-5 rad (as tests/models/toon_water.rs).
            let e = close("offset", &get(&out, "offset", i), &off, 2e-4, &at);
            worst.0 = worst.0.max(e);
            // The normal where the surface does not fold (Σ Q k a < 0.9): beyond, ∂P/∂x
            // can vanish and the normal is ill-conditioned.
            let folding: f64 = WAVES
                .iter()
                .map(|w| q * 2.0 * std::f64::consts::PI / (w.1 * len).max(0.1) * w.2 * amp)
                .sum();
            if folding >= 0.9 {
                continue;
            }
            let got = get(&out, "normal", i);
            let c = cross([got[0], got[1], got[2]], nrm);
            let angle = dot(c, c).sqrt().atan2(dot([got[0], got[1], got[2]], nrm));
            assert!(
                angle < 2e-4,
                "normal at {at:?}: {got:?} vs {nrm:?} ({angle} rad)"
            );
            worst.1 = worst.1.max(angle);
            checked += 1;
        }
    }
    assert!(checked > 600, "{checked} normals checked");
    eprintln!(
        "gerstner_wave_set: worst offset error {:.2e} m, normal {:.2e} rad ({checked} normals)",
        worst.0, worst.1
    );
}

/// With its scales at 1 the wave set is the bare gerstner_waves node at its defaults, bit
/// for bit (what the rewritten water_toon_* graphs rely on).
#[test]
fn gerstner_wave_set_at_unit_scales_is_the_bare_node_bit_for_bit() {
    let ws = Workspace::new();
    let grouped = ws.load(
        "grouped.json",
        &json!({
            "version": 2,
            "name": "grouped",
            "nodes": [
                { "id": "geo", "type": "geometry" },
                { "id": "clock", "type": "time" },
                {
                    "id": "g",
                    "type": "group",
                    "group": "lib/water.json#gerstner_wave_set",
                    "inputs": { "position": link("geo.position"), "time": link("clock.time") }
                }
            ],
            "outputs": [
                { "name": "offset", "from": "g.offset" },
                { "name": "normal", "from": "g.normal" },
                { "name": "normal_gems", "from": "g.normal_gems" }
            ]
        }),
    );
    let bare = ws.load(
        "bare.json",
        &json!({
            "version": 1,
            "name": "bare",
            "nodes": [
                { "id": "geo", "type": "geometry" },
                { "id": "clock", "type": "time" },
                {
                    "id": "w",
                    "type": "gerstner_waves",
                    "inputs": { "position": link("geo.position"), "time": link("clock.time") }
                }
            ],
            "outputs": [
                { "name": "offset", "from": "w.offset" },
                { "name": "normal", "from": "w.normal" },
                { "name": "normal_gems", "from": "w.normal_gems" }
            ]
        }),
    );
    let mut rng = Rng(0xb17);
    let pos: Vec<[f32; 3]> = (0..2000)
        .map(|_| [rng.f32(-60.0, 60.0), 0.0, rng.f32(-60.0, 60.0)])
        .collect();
    for time in [0.0, 0.75, 42.5] {
        let mut samples = Samples {
            time,
            ..Samples::default()
        };
        samples.set(Attribute::Position, pos.clone());
        assert_eq!(
            bits(&eval(&grouped, &samples)),
            bits(&eval(&bare, &samples)),
            "time {time}"
        );
    }
}

#[test]
fn screen_distortion_moves_the_uv_by_the_normals_horizontal_part() {
    let ws = Workspace::new();
    let graph = ws.load(
        "distortion.json",
        &graph_with(
            "lib/water.json#screen_distortion",
            json!({
                "screen_uv": link("geo.screen_uv"),
                "normal": link("geo.normal"),
                "strength": link("geo.depth")
            }),
            &[("uv", "g.uv"), ("offset", "g.offset")],
        ),
    );
    let mut rng = Rng(0xd157);
    let (mut suv, mut nrm, mut k) = (Vec::new(), Vec::new(), Vec::new());
    // Round points: straight up (no offset), tilted 0.6 along x with the graphs' 0.04, and
    // pushed past the screen's edge (clamped).
    for (s, n, kk) in [
        ([0.5, 0.5], [0.0, 1.0, 0.0], 0.04),
        ([0.5, 0.5], [0.6, 0.8, 0.0], 0.04),
        ([0.99, 0.01], [0.8, 0.0, -0.6], 0.1),
    ] {
        suv.push([s[0], s[1], 0.0]);
        nrm.push(n);
        k.push([kk, 0.0, 0.0]);
    }
    for _ in 0..3000 {
        suv.push([rng.f32(-0.1, 1.1), rng.f32(-0.1, 1.1), 0.0]);
        nrm.push(rng.unit_vector());
        k.push([rng.f32(-0.2, 0.2), 0.0, 0.0]);
    }
    let mut samples = Samples::default();
    samples.set(Attribute::ScreenUv, suv.clone());
    samples.set(Attribute::Normal, nrm.clone());
    samples.set(Attribute::Depth, k.clone());
    let out = eval(&graph, &samples);
    for i in 0..suv.len() {
        let kk = k[i][0] as f64;
        let off = [kk * nrm[i][0] as f64, kk * nrm[i][2] as f64];
        let uv = [
            (suv[i][0] as f64 + off[0]).clamp(0.0, 1.0),
            (suv[i][1] as f64 + off[1]).clamp(0.0, 1.0),
        ];
        let at = (suv[i], nrm[i], kk);
        close("offset", &get(&out, "offset", i), &off, 1e-8, &at);
        close("uv", &get(&out, "uv", i), &uv, 2e-7, &at);
    }
    assert_eq!(get(&out, "uv", 0), [0.5, 0.5]);
    close("uv", &get(&out, "uv", 1), &[0.524, 0.5], 1e-7, &"tilted");
    close("uv", &get(&out, "uv", 2), &[1.0, 0.0], 0.0, &"clamped");
}

#[test]
fn noise_distortion_moves_the_uv_by_centred_value_noise() {
    use matgraph::nodes::texture::noise_value;
    let ws = Workspace::new();
    let graph = ws.load(
        "noise.json",
        &graph_with(
            "lib/water.json#noise_distortion",
            json!({
                "screen_uv": link("geo.screen_uv"),
                "position": link("geo.position"),
                "frequency": link("q.x"),
                "strength": link("q.y")
            }),
            &[("uv", "g.uv"), ("offset", "g.offset")],
        ),
    );
    let mut rng = Rng(0x2015e);
    let (mut suv, mut pos, mut fk) = (Vec::new(), Vec::new(), Vec::new());
    // The water_demo values first.
    suv.push([0.5, 0.5, 0.0]);
    pos.push([1.25, 0.0, -3.5]);
    fk.push([0.6, 0.03, 0.0]);
    for _ in 0..2000 {
        suv.push([rng.f32(0.0, 1.0), rng.f32(0.0, 1.0), 0.0]);
        pos.push([
            rng.f32(-30.0, 30.0),
            rng.f32(-1.0, 1.0),
            rng.f32(-30.0, 30.0),
        ]);
        fk.push([rng.f32(0.05, 5.0), rng.f32(0.0, 0.2), 0.0]);
    }
    let mut samples = Samples::default();
    samples.set(Attribute::ScreenUv, suv.clone());
    samples.set(Attribute::Position, pos.clone());
    samples.set(Attribute::Uv, fk.clone());
    let out = eval(&graph, &samples);
    let mut largest = 0.0f64;
    for i in 0..suv.len() {
        let (f, k) = (fk[i][0], fk[i][1] as f64);
        // Value noise has no closed form: the node's own function gives n at p·f (3 octaves,
        // lacunarity 2, gain 0.5, as the group sets), the rest is checked in f64.
        let p = glam::Vec3::from_array(pos[i]) * f;
        let (_, c) = noise_value(p, 1.0, 3, 2.0, 0.5);
        let off = [k * (c.x as f64 - 0.5), k * (c.y as f64 - 0.5)];
        let uv = [
            (suv[i][0] as f64 + off[0]).clamp(0.0, 1.0),
            (suv[i][1] as f64 + off[1]).clamp(0.0, 1.0),
        ];
        let at = (suv[i], pos[i], f, k);
        close("offset", &get(&out, "offset", i), &off, 1e-8, &at);
        close("uv", &get(&out, "uv", i), &uv, 2e-7, &at);
        assert!(off.iter().all(|o| o.abs() <= k / 2.0), "at {at:?}");
        largest = largest.max(off[0].abs().max(off[1].abs()) / k.max(1e-9));
    }
    // The noise is centred and spread: the offsets reach well into ±strength/2.
    assert!(largest > 0.25, "largest offset {largest} × strength");
}

// ---- Thin film --------------------------------------------------------------------------

/// A complex f64.
#[derive(Clone, Copy, Debug)]
struct Z(f64, f64);

impl Z {
    fn add(self, o: Z) -> Z {
        Z(self.0 + o.0, self.1 + o.1)
    }
    fn sub(self, o: Z) -> Z {
        Z(self.0 - o.0, self.1 - o.1)
    }
    fn mul(self, o: Z) -> Z {
        Z(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
    }
    fn div(self, o: Z) -> Z {
        let d = o.0 * o.0 + o.1 * o.1;
        Z(
            (self.0 * o.0 + self.1 * o.1) / d,
            (self.1 * o.0 - self.0 * o.1) / d,
        )
    }
    fn abs2(self) -> f64 {
        self.0 * self.0 + self.1 * self.1
    }
    fn scale(self, k: f64) -> Z {
        Z(self.0 * k, self.1 * k)
    }
    /// √x of a real x, with Im ≥ 0 where x < 0.
    fn sqrt_real(x: f64) -> Z {
        if x >= 0.0 {
            Z(x.sqrt(), 0.0)
        } else {
            Z(0.0, (-x).sqrt())
        }
    }
    fn cos(self) -> Z {
        Z(self.0.cos() * self.1.cosh(), -self.0.sin() * self.1.sinh())
    }
    fn sin(self) -> Z {
        Z(self.0.sin() * self.1.cosh(), self.0.cos() * self.1.sinh())
    }
}

/// Unpolarised (R, T) of a single film at one wavelength by its characteristic matrix
/// (Macleod, Thin-Film Optical Filters §2.2, eqs. 2.54–2.61): `[B; C] = [[cos β,
/// i sin β/η_f], [i η_f sin β, cos β]] [1; η3]`, β = 2π n_f d cos θ_f / λ, tilted
/// admittances η = n cos θ (s) and n / cos θ (p), R = |(η1 B − C)/(η1 B + C)|²,
/// T = 4 η1 Re(η3)/|η1 B + C|². A different formulation from the node's Airy sum.
fn abeles(cos1: f64, lambda: f64, d: f64, nf: f64, n1: f64, n3: f64) -> (f64, f64) {
    let sin2 = 1.0 - cos1 * cos1;
    let cf = Z::sqrt_real(1.0 - (n1 / nf).powi(2) * sin2);
    let c3 = Z::sqrt_real(1.0 - (n1 / n3).powi(2) * sin2);
    let c1 = Z(cos1, 0.0);
    let beta = cf.scale(2.0 * std::f64::consts::PI * nf * d / lambda);
    let (cb, sb) = (beta.cos(), beta.sin());
    let i = Z(0.0, 1.0);
    let (mut r, mut t) = (0.0, 0.0);
    for s_pol in [true, false] {
        let eta = |n: f64, c: Z| if s_pol { c.scale(n) } else { Z(n, 0.0).div(c) };
        let (e1, ef, e3) = (eta(n1, c1), eta(nf, cf), eta(n3, c3));
        let b = cb.add(i.mul(sb).mul(e3).div(ef));
        let c = i.mul(ef).mul(sb).add(e3.mul(cb));
        let den = e1.mul(b).add(c);
        r += e1.mul(b).sub(c).div(den).abs2();
        t += 4.0 * e1.0 * e3.0 / den.abs2();
    }
    (0.5 * r, 0.5 * t)
}

/// Linear sRGB weights per nm from the CIE 1931 2° observer and D65 (IEC 61966-2-1's
/// XYZ → sRGB matrix), each channel normalised to sum 1, in f64.
fn srgb_weights() -> Vec<[f64; 3]> {
    const M: [[f64; 3]; 3] = [
        [3.2406, -1.5372, -0.4986],
        [-0.9689, 1.8758, 0.0415],
        [0.0557, -0.2040, 1.0570],
    ];
    let mut w: Vec<[f64; 3]> = (0..LEN)
        .map(|k| M.map(|row| (0..3).map(|j| row[j] * D65[k] * CMF_1931_2DEG[k][j]).sum()))
        .collect();
    for c in 0..3 {
        let total: f64 = w.iter().map(|v| v[c]).sum();
        for v in &mut w {
            v[c] /= total;
        }
    }
    w
}

/// The film's reflected colour for white light, f64: Abelès per nm over 360–830 nm.
fn film_colour(weights: &[[f64; 3]], cos1: f64, d: f64, nf: f64, n1: f64, n3: f64) -> [f64; 3] {
    let mut r = [0.0; 3];
    for (k, w) in weights.iter().enumerate() {
        let (rl, _) = abeles(cos1, (LAMBDA_MIN_NM as usize + k) as f64, d, nf, n1, n3);
        for c in 0..3 {
            r[c] += w[c] * rl;
        }
    }
    r
}

#[test]
fn thin_film_coat_is_the_airy_film_over_its_base() {
    let ws = Workspace::new();
    let graph = ws.load(
        "coat.json",
        &graph_with(
            "lib/thin_film.json#thin_film_coat",
            json!({
                "cos_theta": link("p.x"),
                "thickness_nm": link("p.y"),
                "film_ior": link("p.z"),
                "outside_ior": link("q.x"),
                "substrate_ior": link("q.y"),
                "reflected": link("geo.light_color"),
                "transmitted": link("geo.view")
            }),
            &[
                ("color", "g.color"),
                ("reflectance", "g.reflectance"),
                ("transmittance", "g.transmittance"),
            ],
        ),
    );
    // (cos θ, d nm, n_film, n_outside, n_substrate): round cases first — the bare
    // interface (d = 0) on glass, a soap film, a quarter-wave MgF₂ coat on glass (its
    // reflectance minimum near 550 nm), an oil film on water.
    let mut cases: Vec<[f32; 5]> = vec![
        [1.0, 0.0, 1.33, 1.0, 1.5],
        [0.5, 0.0, 1.6, 1.0, 1.5],
        [1.0, 500.0, 1.33, 1.0, 1.0],
        [0.7, 300.0, 1.33, 1.0, 1.0],
        [1.0, 99.6, 1.38, 1.0, 1.52],
        [0.8, 400.0, 1.5, 1.0, 1.33],
        [0.9, 250.0, 1.6, 1.33, 1.5],
    ];
    let mut rng = Rng(0x7f11);
    for _ in 0..60 {
        cases.push([
            rng.f32(0.05, 1.0),
            rng.f32(0.0, 3000.0),
            rng.f32(1.2, 2.0),
            1.0,
            if rng.next() & 1 == 0 {
                1.0
            } else {
                rng.f32(1.0, 2.5)
            },
        ]);
    }
    let refl: Vec<[f32; 3]> = (0..cases.len())
        .map(|_| [rng.f32(0.0, 2.0), rng.f32(0.0, 2.0), rng.f32(0.0, 2.0)])
        .collect();
    let trans: Vec<[f32; 3]> = (0..cases.len())
        .map(|_| [rng.f32(0.0, 1.0), rng.f32(0.0, 1.0), rng.f32(0.0, 1.0)])
        .collect();
    let mut samples = Samples::default();
    samples.set(
        Attribute::Position,
        cases.iter().map(|c| [c[0], c[1], c[2]]).collect(),
    );
    samples.set(
        Attribute::Uv,
        cases.iter().map(|c| [c[3], c[4], 0.0]).collect(),
    );
    samples.set(Attribute::LightColor, refl.clone());
    samples.set(Attribute::View, trans.clone());
    let out = eval(&graph, &samples);
    let weights = srgb_weights();
    let mut worst = 0.0f64;
    for (i, c) in cases.iter().enumerate() {
        let [cos, d, nf, n1, n3] = c.map(|x| x as f64);
        let r = film_colour(&weights, cos, d, nf, n1, n3);
        // Method table against the spectral reference: ~5e-4 (tests/models/thin_film.rs), a little
        // more near grazing (5.7e-4 at cos θ = 0.105, d = 1216 nm).
        worst = worst.max(close(
            "reflectance",
            &get(&out, "reflectance", i),
            &r,
            1e-3,
            c,
        ));
        let t: Vec<f64> = r.iter().map(|x| 1.0 - x).collect();
        close("transmittance", &get(&out, "transmittance", i), &t, 1e-3, c);
        let want: Vec<f64> = (0..3)
            .map(|k| r[k] * refl[i][k] as f64 + t[k] * trans[i][k] as f64)
            .collect();
        close("color", &get(&out, "color", i), &want, 3e-3, c);
    }
    // d = 0 is the bare interface: a grey equal to the exact Fresnel of air → glass.
    for i in [0, 1] {
        let [cos, _, _, n1, n3] = cases[i].map(|x| x as f64);
        let (f, _) = fresnel_exact(cos, n1, n3);
        close(
            "bare interface",
            &get(&out, "reflectance", i),
            &[f; 3],
            5e-4,
            &cases[i],
        );
    }
    // The quarter-wave MgF₂ coat reflects less than bare glass (4.3 %) in every channel.
    let coat = get(&out, "reflectance", 4);
    assert!(coat.iter().all(|&x| x < 0.03), "{coat:?}");
    eprintln!("thin_film_coat: worst reflectance error {worst:.2e}");
}

// ---- The rewritten bundled graphs -------------------------------------------------------

/// The bundled graphs rewritten to use the library, and their flat originals.
const REWRITTEN: [&str; 2] = ["water_toon_you", "water_toon_day"];

fn bits(out: &OutputBatch) -> Vec<(String, Vec<u32>)> {
    (0..out.names().len())
        .map(|k| {
            (
                out.names()[k].clone(),
                out.planar(k).iter().map(|x| x.to_bits()).collect(),
            )
        })
        .collect()
}

/// A 32 × 32 grid of samples over every attribute the water graphs read: positions over
/// ±30 m, normals over the upper hemisphere, lights and views from every side (below the
/// horizon too), screen uvs over and past the screen, depths to 6 m.
fn water_grid() -> Samples {
    let n = 32;
    let (mut pos, mut nrm, mut view, mut light, mut lc, mut suv, mut depth) = (
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
    );
    let dir = |a: f32, b: f32| {
        let (sa, ca) = a.sin_cos();
        let (sb, cb) = b.sin_cos();
        [sa * cb, ca, sa * sb]
    };
    for i in 0..n {
        for j in 0..n {
            let (u, v) = (i as f32 / (n - 1) as f32, j as f32 / (n - 1) as f32);
            pos.push([-30.0 + 60.0 * u, 0.0, -30.0 + 60.0 * v]);
            nrm.push(dir(1.4 * u, 6.2 * v));
            view.push(dir(3.1 * v, 6.2 * u));
            light.push(dir(2.0 * u * v + 0.1, 3.0 * u + 2.0 * v));
            lc.push([3.0 * u, 2.0 * v, 1.0 + u * v]);
            suv.push([-0.05 + 1.1 * u, -0.05 + 1.1 * v, 0.0]);
            depth.push([6.0 * u * v, 0.0, 0.0]);
        }
    }
    let mut s = Samples::default();
    s.set(Attribute::Position, pos);
    s.set(Attribute::Normal, nrm);
    s.set(Attribute::View, view);
    s.set(Attribute::Light, light);
    s.set(Attribute::LightColor, lc);
    s.set(Attribute::ScreenUv, suv);
    s.set(Attribute::Depth, depth);
    s
}

/// Loads the rewritten graph and its flat original, checking that the one uses the library
/// and the other does not.
fn rewritten_and_flat(name: &str) -> (Graph, Graph) {
    let grouped_path = repo(&format!("graphs/{name}.json"));
    let flat_path = repo(&format!("tests/groups_flat/{name}.json"));
    let text = std::fs::read_to_string(&grouped_path).unwrap();
    assert!(
        text.contains("\"lib/water.json#"),
        "{name} uses no library group"
    );
    let flat_text = std::fs::read_to_string(&flat_path).unwrap();
    assert!(
        !flat_text.contains("\"group\""),
        "{name}'s original is flat"
    );
    let load = |p: &Path| {
        matgraph::io::load_graph(p, Registry::builtin())
            .unwrap_or_else(|e| panic!("{}: {e}", p.display()))
    };
    (load(&grouped_path), load(&flat_path))
}

/// Every graph output that needs no scene texture (color, displacement), and the nodes the
/// groups replaced (the distorted uv and the waves' normal, under their ids in each graph),
/// over a 1024-sample grid at three times and two shininess values: the same f32 bits; and
/// the same number of per-sample steps (the groups' reroutes cost nothing).
#[test]
fn rewritten_graphs_evaluate_bit_identically_to_their_flat_originals() {
    let grid = water_grid();
    for name in REWRITTEN {
        let (grouped, flat) = rewritten_and_flat(name);
        let options = |refs: [&str; 4]| PlanOptions {
            outputs: refs.iter().map(|s| s.to_string()).collect(),
            bake_parameters: false,
        };
        let g = Plan::compile(
            &grouped,
            &options([
                "color",
                "displacement",
                "distortion/uv.result",
                "waves/waves.normal",
            ]),
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        let f = Plan::compile(
            &flat,
            &options(["color", "displacement", "uv.result", "waves.normal"]),
        )
        .unwrap_or_else(|e| panic!("{name} (flat): {e}"));
        let (gs, fs) = (g.stats(), f.stats());
        // (The registers may differ by one or two: the instances' nodes come later in the
        // flat order, so registers are reused in another order.)
        assert_eq!(
            gs.per_sample_steps, fs.per_sample_steps,
            "{name}: {gs:?} vs {fs:?}"
        );
        let n = grid.columns[0].1.len();
        for time in [0.0, 1.5, 23.75] {
            let mut batch = SampleBatch::new(n);
            batch.set_time(time);
            for (attr, values) in &grid.columns {
                batch.set_values(*attr, values).unwrap();
            }
            for shininess in [None, Some(12.5)] {
                let (mut gp, mut fp) = (g.default_parameters(), f.default_parameters());
                if let Some(m) = shininess {
                    gp.set("shininess", Value::float(m)).unwrap();
                    fp.set("shininess", Value::float(m)).unwrap();
                }
                let a = bits(&g.execute(&batch, &gp).unwrap());
                let b = bits(&f.execute(&batch, &fp).unwrap());
                assert_eq!(a.len(), 4);
                for ((na, va), (nb, vb)) in a.iter().zip(&b) {
                    let differ = va.iter().zip(vb).filter(|(x, y)| x != y).count();
                    assert_eq!(
                        differ,
                        0,
                        "{name} at t = {time}, shininess {shininess:?}: {na} vs {nb}: {differ} of {} lanes differ",
                        va.len()
                    );
                }
            }
        }
    }
}

/// The whole render (the scene's water grid displaced by the waves, the refraction and
/// reflection maps sampled at the distorted uv, both outputs): the same f32 bits in every
/// pixel.
#[test]
fn rewritten_graphs_render_bit_identically_to_their_flat_originals() {
    for name in REWRITTEN {
        let (grouped, flat) = rewritten_and_flat(name);
        let scene = graph_scene(&grouped).unwrap().expect("an inline scene");
        assert_eq!(
            Some(scene.to_json()),
            graph_scene(&flat).unwrap().map(|s| s.to_json()),
            "{name}: the same scene"
        );
        for time in [0.0, 2.5] {
            let options = RenderOptions {
                width: 64,
                height: 40,
                samples: 2,
                time: Some(time),
                ..RenderOptions::default()
            };
            let a = render(&grouped, &scene, &options).unwrap();
            let b = render(&flat, &scene, &options).unwrap();
            let px = |img: &matgraph::render::HdrImage| -> Vec<u32> {
                img.pixels.iter().flatten().map(|v| v.to_bits()).collect()
            };
            let (pa, pb) = (px(&a), px(&b));
            assert_eq!(pa.len(), 64 * 40 * 3);
            let differ = pa.iter().zip(&pb).filter(|(x, y)| x != y).count();
            assert_eq!(differ, 0, "{name} at t = {time}: {differ} lanes differ");
            // Not a blank image: the water is there.
            assert!(a.pixels.iter().any(|p| p[2] > 0.05), "{name}: blank");
        }
    }
}
