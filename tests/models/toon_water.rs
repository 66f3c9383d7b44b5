//! Seed 004's cartoon water (docs/models/toon_water.md): the Gerstner normal against a
//! finite difference of the offset in f64, the fold flag at its threshold, the depth colours
//! and the sky light against closed forms, the paper's presets, and the bundled graphs
//! checking and rendering deterministically.

use crate::common;

use common::rng::Rng;

use matgraph::node::NodeType;
use matgraph::nodes::toon_water::{DEFAULT_WAVES, GRAVITY, Wave, gerstner, wave};
use matgraph::render::{RenderOptions, graph_scene, render};
use matgraph::{Registry, SocketType, Value};
use std::path::Path;

/// Runs one node's CPU kernel on one sample: the named inputs set, the others at their
/// defaults; returns every output's lanes.
fn run_node(name: &str, set: &[(&str, Value)]) -> Vec<Vec<f32>> {
    let t: &NodeType = Registry::builtin().get(name).expect("registered");
    let inputs: Vec<Vec<f32>> = t
        .inputs()
        .iter()
        .enumerate()
        .map(|(k, d)| {
            let v = set
                .iter()
                .find(|(n, _)| *n == d.name)
                .map(|(_, v)| *v)
                .unwrap_or_else(|| t.default_for(k, SocketType::Float));
            v.lanes().to_vec()
        })
        .collect();
    let mut outputs: Vec<Vec<f32>> = t
        .outputs()
        .iter()
        .map(|o| vec![0.0; o.ty.resolve(SocketType::Float).width()])
        .collect();
    let ins: Vec<&[f32]> = inputs.iter().map(|v| v.as_slice()).collect();
    let mut outs: Vec<&mut [f32]> = outputs.iter_mut().map(|v| v.as_mut_slice()).collect();
    t.variants()[0].kernel.run(&ins, &mut outs, 1, 1);
    outputs
}

/// The Gerstner surface point P(x, z, t) in f64, written from GPU Gems ch. 1 eq. 9 (y up).
fn surface_f64(waves: &[Wave], x: f64, z: f64, t: f64) -> [f64; 3] {
    let mut p = [x, 0.0, z];
    for w in waves {
        let (dx, dz) = (w.direction[0] as f64, w.direction[1] as f64);
        let len = (dx * dx + dz * dz).sqrt();
        let (dx, dz) = (dx / len, dz / len);
        let k = 2.0 * std::f64::consts::PI / w.wavelength as f64;
        let omega = (GRAVITY as f64 * k).sqrt();
        let theta = k * (dx * x + dz * z) - omega * t + w.phase as f64;
        let (a, q) = (w.amplitude as f64, w.steepness as f64);
        p[0] += q * a * dx * theta.cos();
        p[1] += a * theta.sin();
        p[2] += q * a * dz * theta.cos();
    }
    p
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / l, v[1] / l, v[2] / l]
}

/// The angle in radians between unit vectors.
fn angle(a: [f64; 3], b: [f64; 3]) -> f64 {
    let c = cross(a, b);
    let s = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
    let d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    s.atan2(d)
}

/// The normal from a central difference of P in f64: normalize(∂P/∂z × ∂P/∂x).
fn fd_normal(waves: &[Wave], x: f64, z: f64, t: f64) -> [f64; 3] {
    let h = 1e-5;
    let px = |s: f64| surface_f64(waves, x + s, z, t);
    let pz = |s: f64| surface_f64(waves, x, z + s, t);
    let d = |a: [f64; 3], b: [f64; 3]| {
        [
            (a[0] - b[0]) / (2.0 * h),
            (a[1] - b[1]) / (2.0 * h),
            (a[2] - b[2]) / (2.0 * h),
        ]
    };
    let dpdx = d(px(h), px(-h));
    let dpdz = d(pz(h), pz(-h));
    unit(cross(dpdz, dpdx))
}

#[test]
fn exact_normal_matches_a_finite_difference_of_the_offset() {
    let mut rng = Rng(4);
    let mut points: Vec<(f32, f32, f32)> = vec![
        (0.0, 0.0, 0.0),
        (1.0, -2.0, 0.5),
        (10.0, 10.0, 3.0),
        (-25.0, 7.5, 12.0),
    ];
    for _ in 0..400 {
        points.push((
            rng.f32(-40.0, 40.0),
            rng.f32(-40.0, 40.0),
            rng.f32(0.0, 30.0),
        ));
    }
    // The scene's wave set, and a steeper random one (Q up to the fold).
    let mut random = Vec::new();
    for _ in 0..8 {
        let ang = rng.f32(0.0, std::f32::consts::TAU);
        let lambda = rng.f32(1.0, 20.0);
        let amp = rng.f32(0.0, 0.04) * lambda;
        random.push(wave(
            [ang.cos(), ang.sin()],
            lambda,
            amp,
            0.0,
            rng.f32(0.0, std::f32::consts::TAU),
        ));
    }
    let k_a: f32 = random
        .iter()
        .map(|w| std::f32::consts::TAU / w.wavelength * w.amplitude)
        .sum();
    for w in &mut random {
        w.steepness = 0.9 / k_a;
    }
    let mut worst = 0.0f64;
    let mut worst_offset = 0.0f64;
    for set in [&DEFAULT_WAVES[..], &random[..]] {
        for &(x, z, t) in &points {
            let g = gerstner(glam::Vec3::new(x, 0.0, z), t, set);
            let want = fd_normal(set, x as f64, z as f64, t as f64);
            let got = [g.normal.x as f64, g.normal.y as f64, g.normal.z as f64];
            worst = worst.max(angle(got, want));
            let p = surface_f64(set, x as f64, z as f64, t as f64);
            let off = [p[0] - x as f64, p[1], p[2] - z as f64];
            for (c, want) in off.iter().enumerate() {
                worst_offset = worst_offset.max((g.offset[c] as f64 - want).abs());
            }
        }
    }
    // f32 phases of up to ~100 rad carry ~1e-5 rad; the difference's own error is ~1e-9.
    assert!(
        worst < 2e-4,
        "largest angle between the exact normal and the FD: {worst} rad"
    );
    assert!(
        worst_offset < 2e-4,
        "largest offset error: {worst_offset} m"
    );
}

#[test]
fn gems_normal_is_exact_for_one_wave_and_not_for_several() {
    let one = [DEFAULT_WAVES[0]];
    let g = gerstner(glam::Vec3::new(3.0, 0.0, -4.0), 2.0, &one);
    assert!((g.normal - g.normal_gems).length() < 1e-6);
    let mut steep = DEFAULT_WAVES;
    let k_a: f32 = steep
        .iter()
        .map(|w| std::f32::consts::TAU / w.wavelength * w.amplitude)
        .sum();
    for w in &mut steep {
        w.steepness = 0.95 / k_a;
    }
    let max = (0..200)
        .map(|i| {
            let g = gerstner(
                glam::Vec3::new(i as f32 * 0.37, 0.0, i as f32 * -0.21),
                1.0,
                &steep,
            );
            g.normal.angle_between(g.normal_gems)
        })
        .fold(0.0f32, f32::max);
    assert!(
        max > 1e-2,
        "GPU Gems' normal should drop cross terms: max {max} rad"
    );
}

#[test]
fn fold_flag_switches_at_sum_q_k_a_of_one() {
    // λ = 2π m (k = 1), a = 0.5 m: Q k a = Q / 2, the threshold at Q = 2.
    let tau = std::f32::consts::TAU;
    let folds = |q: f32| {
        let out = run_node(
            "gerstner_waves",
            &[
                ("count", Value::int(1)),
                ("wavelengths_0_3", Value::vec4([tau, 1.0, 1.0, 1.0])),
                ("amplitudes_0_3", Value::vec4([0.5, 0.0, 0.0, 0.0])),
                ("steepness_0_3", Value::vec4([q, 0.0, 0.0, 0.0])),
            ],
        );
        out[3][0] != 0.0
    };
    assert!(!folds(1.99));
    assert!(!folds(2.0), "Σ Q k a = 1 exactly is not a fold (strict >)");
    assert!(folds(2.0f32.next_up().next_up()));
    assert!(folds(3.0));
    // The default set does not fold; all eight at Q = 2 do (Σ k a ≈ 0.59).
    assert_eq!(run_node("gerstner_waves", &[])[3][0], 0.0);
    assert_eq!(
        run_node(
            "gerstner_waves",
            &[
                ("steepness_0_3", Value::vec4([2.0; 4])),
                ("steepness_4_7", Value::vec4([2.0; 4]))
            ]
        )[3][0],
        1.0
    );
}

#[test]
fn depth_colours_match_their_closed_forms() {
    let mut rng = Rng(14);
    let mut cases: Vec<(f32, [f32; 3])> = vec![
        (0.0, [1.0, 2.0, 3.0]),
        (3.0, [3.0, 3.0, 3.0]),
        (156.0, [2.0, 12.0, 90.0]),
        (35.0, [0.5, 3.0, 20.0]),
    ];
    for _ in 0..500 {
        cases.push((
            rng.f32(0.0, 200.0),
            [
                rng.f32(0.1, 200.0),
                rng.f32(0.1, 200.0),
                rng.f32(0.1, 200.0),
            ],
        ));
    }
    for (model, name) in [(0, "paper"), (1, "beer_lambert")] {
        for &(d, h) in &cases {
            let out = run_node(
                "toon_water_depth_color",
                &[
                    ("depth", Value::float(d)),
                    ("half_life", Value::color(h)),
                    ("model", Value::int(model)),
                ],
            );
            for c in 0..3 {
                let x = d as f64 / h[c] as f64;
                // Halved at one half-life in both: paper 2^(−√(d/h)), Beer–Lambert 2^(−d/h).
                let want = if model == 0 {
                    0.5f64.powf(x.sqrt())
                } else {
                    0.5f64.powf(x)
                };
                let got = out[0][c] as f64;
                assert!(
                    (got - want).abs() <= 1e-6 + 2e-6 * want,
                    "{name} d={d} h={} : {got} vs {want}",
                    h[c]
                );
            }
        }
    }
    // Exactly a half at d = h; negative depth reads as the surface.
    let half = run_node(
        "toon_water_depth_color",
        &[
            ("depth", Value::float(12.0)),
            ("half_life", Value::color([12.0; 3])),
        ],
    );
    assert!((half[0][0] - 0.5).abs() < 1e-6);
    let above = run_node("toon_water_depth_color", &[("depth", Value::float(-3.0))]);
    assert_eq!(above[0], vec![1.0, 1.0, 1.0]);
}

#[test]
fn sky_light_presets_are_the_papers_and_follow_the_closed_form() {
    let paper = [
        (1, [0.8, 0.3, 0.0]),    // sunrise
        (2, [0.7, 0.7, 0.7]),    // day
        (3, [0.8, 0.3, 0.0]),    // sunset
        (4, [0.25, 0.25, 0.25]), // night
    ];
    let mut rng = Rng(3);
    for (index, i0) in paper {
        let clear = run_node(
            "toon_water_sky_light",
            &[
                ("time_of_day", Value::int(index)),
                ("absorption", Value::float(0.0)),
            ],
        );
        assert_eq!(clear[0], i0.to_vec(), "preset {index}");
        for _ in 0..50 {
            let (a, t) = (rng.f32(0.0, 1.0), rng.f32(0.0, 100.0));
            let out = run_node(
                "toon_water_sky_light",
                &[
                    ("time_of_day", Value::int(index)),
                    ("absorption", Value::float(a)),
                    ("thickness", Value::float(t)),
                ],
            );
            let f = (-(a as f64 * t as f64).sqrt()).exp();
            for c in 0..3 {
                let want = i0[c] as f64 * f;
                assert!((out[0][c] as f64 - want).abs() <= 1e-7 + 1e-6 * want);
            }
        }
    }
    let custom = run_node(
        "toon_water_sky_light",
        &[
            ("light_color", Value::color([0.1, 0.2, 0.4])),
            ("absorption", Value::float(0.0)),
        ],
    );
    assert_eq!(custom[0], vec![0.1, 0.2, 0.4]);
    // The scene's light presets carry the same colours.
    for (name, (_, i0)) in ["sunrise", "day", "sunset", "night"].iter().zip(paper) {
        let light = matgraph::scene::Light::preset(name).unwrap();
        assert_eq!(light.radiance_scale().to_array(), i0, "{name}");
    }
}

#[test]
fn toon_shade_follows_the_modified_blinn_phong() {
    // n = +y, l at 60° from n (n·l = 0.5 → band 1 of 3 → level 0.5), v = l mirrored.
    let l = [3f32.sqrt() / 2.0, 0.5, 0.0];
    let v = [-(3f32.sqrt()) / 2.0, 0.5, 0.0];
    let out = run_node(
        "toon_water_shade",
        &[
            ("light", Value::vec3(l)),
            ("view", Value::vec3(v)),
            ("base", Value::color([0.2, 0.4, 0.8])),
            ("ambient", Value::color([0.01, 0.02, 0.03])),
            ("diffuse", Value::color([1.0, 1.0, 1.0])),
            ("specular", Value::color([0.5, 0.5, 0.5])),
            ("shininess", Value::float(10.0)),
            ("steps", Value::int(3)),
            ("shadow", Value::float(0.2)),
        ],
    );
    // h = +y, so (n·h)^m = 1; ramp = 0.2 + 0.8 · floor(0.5 · 3)/2 = 0.6.
    let ramp = 0.2 + 0.8 * 0.5;
    let want = [
        0.01 + 0.2 * ramp + 0.5,
        0.02 + 0.4 * ramp + 0.5,
        0.03 + 0.8 * ramp + 0.5,
    ];
    for c in 0..3 {
        assert!(
            (out[0][c] as f64 - want[c]).abs() < 1e-6,
            "{:?} vs {want:?}",
            out[0]
        );
    }
    assert!((out[1][0] as f64 - ramp).abs() < 1e-6);
}

/// The bundled cartoon-water graphs.
fn toon_graphs() -> Vec<std::path::PathBuf> {
    let names = [
        "sunrise",
        "day",
        "sunset",
        "night",
        "eden",
        "you",
        "beer_lambert",
    ];
    names
        .iter()
        .map(|n| Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("graphs/water_toon_{n}.json")))
        .collect()
}

#[test]
fn graphs_check_and_render_the_same_bytes_twice() {
    for path in toon_graphs() {
        let graph = matgraph::io::load_graph(&path, Registry::builtin())
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let scene = graph_scene(&graph).unwrap().expect("an inline scene");
        let options = RenderOptions {
            width: 48,
            height: 32,
            time: Some(1.5),
            ..RenderOptions::default()
        };
        let a = render(&graph, &scene, &options).unwrap();
        let b = render(&graph, &scene, &options).unwrap();
        let bits = |img: &matgraph::render::HdrImage| -> Vec<u32> {
            img.pixels.iter().flatten().map(|v| v.to_bits()).collect()
        };
        assert_eq!(bits(&a), bits(&b), "{}", path.display());
        assert!(a.pixels.iter().flatten().all(|v| v.is_finite()));
        // The water is there: most pixels of the lower half are bluish.
        let lower = &a.pixels[a.pixels.len() / 2..];
        let blue = lower.iter().filter(|p| p[2] >= p[0]).count();
        assert!(
            blue * 2 > lower.len(),
            "{}: {blue} of {}",
            path.display(),
            lower.len()
        );
    }
}

#[test]
fn lod_and_snell_fields_are_opt_in_and_checked() {
    use matgraph::scene::{Scene, SceneKind};
    let water = |s: &Scene| match &s.kind {
        SceneKind::Water(w) => w.clone(),
        _ => panic!("not water"),
    };
    // Left out, today's scene: the uniform 256 × 256 grid and the straight refraction map.
    let plain = Scene::preset("water").unwrap();
    assert!(water(&plain).lod.is_none() && water(&plain).refraction.is_none());
    assert_eq!(plain.material_mesh().vertex_count(), 257 * 257);
    assert!(!plain.to_json().contains("lod") && !plain.to_json().contains("refraction"));
    // Given, the quadtree grid (fewer vertices) and the paper's indices.
    let toon = Scene::from_json(r#"{"kind": {"water": {"lod": {}, "refraction": {}}}}"#).unwrap();
    let w = water(&toon);
    assert_eq!(
        w.refraction.as_ref().map(|r| (r.ior_air, r.ior_water)),
        Some((1.0, 1.33))
    );
    let n = toon.material_mesh().vertex_count();
    assert!(n > 1000 && n < 257 * 257 / 4, "{n}");
    // Bad values name their field.
    for (text, field) in [
        (
            r#"{"kind": {"water": {"lod": {"block": 0}}}}"#,
            "kind.water.lod.block",
        ),
        (
            r#"{"kind": {"water": {"lod": {"levels": 11}}}}"#,
            "kind.water.lod.levels",
        ),
        (
            r#"{"kind": {"water": {"lod": {"split_distance": -1}}}}"#,
            "kind.water.lod.split_distance",
        ),
        (
            r#"{"kind": {"water": {"refraction": {"ior_water": 0}}}}"#,
            "kind.water.refraction.ior_water",
        ),
    ] {
        let err = Scene::from_json(text).unwrap_err().to_string();
        assert!(err.contains(field), "{text}: {err}");
    }
    let err = Scene::from_json(r#"{"kind": {"water": {"lod": {"blocks": 4}}}}"#)
        .unwrap_err()
        .to_string();
    assert!(err.contains("blocks"), "{err}");
}
