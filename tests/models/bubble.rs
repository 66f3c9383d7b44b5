//! The soap bubble of seed 000 (docs/models/bubble.md): each paper node against an f64
//! reference written here from the geometry of the problem (angles, not the nodes'
//! vector formulas), at round and seeded random f32 points; the bubble scene; the graphs.

use crate::common;

use common::rng::Rng;

use glam::{Vec2, Vec3};
use matgraph::nodes::bubble::{
    camera_blend, film_thickness, internal_vector, motion, one_minus_exp_neg, rim, texture_flow,
    underwater, underwater_uv, vector_color, wobble,
};
use matgraph::render::{RenderOptions, render};
use matgraph::scene::{Scene, SceneError, SceneKind};
use matgraph::{Registry, Value};
use std::path::Path;

fn close(what: &str, got: f64, want: f64, abs: f64, rel: f64) {
    let err = (got - want).abs();
    assert!(
        err <= abs + rel * want.abs(),
        "{what}: got {got}, want {want} (error {err:e})"
    );
}

// ---- Rim (eq. 10) ------------------------------------------------------------------------

/// `(1 − max(0, cos θ))^p` for the view at angle `theta` from the normal.
fn rim_reference(theta: f64, p: f64) -> f64 {
    (1.0 - theta.cos().clamp(0.0, 1.0)).powf(p)
}

#[test]
fn rim_at_known_angles_and_random_ones() {
    // Round angles: facing (0), 60° (1 − 1/2)^2.8 = 0.14359, grazing (1).
    let n = Vec3::Z;
    assert_eq!(rim(Vec3::Z, n, 2.8), 0.0);
    close(
        "rim 60°",
        rim(Vec3::new(0.75f32.sqrt(), 0.0, 0.5), n, 2.8) as f64,
        0.5f64.powf(2.8),
        1e-7,
        1e-6,
    );
    assert_eq!(rim(Vec3::X, n, 2.8), 1.0);
    assert_eq!(rim(Vec3::Z, n, 0.0), 1.0, "0^0 is 1");
    assert_eq!(
        rim(-Vec3::Z, n, 2.8),
        1.0,
        "from behind: saturate gives 1 − 0"
    );
    let mut rng = Rng(0xB0B1);
    for _ in 0..2000 {
        let theta = rng.f(0.0, std::f64::consts::PI) as f64;
        let phi = rng.f(0.0, std::f64::consts::TAU) as f64;
        let p = rng.f(0.5, 8.0);
        let v = Vec3::new(
            (theta.sin() * phi.cos()) as f32,
            (theta.sin() * phi.sin()) as f32,
            theta.cos() as f32,
        );
        close(
            "rim",
            rim(v, n, p) as f64,
            rim_reference(theta, p as f64),
            2e-6,
            1e-5,
        );
    }
}

// ---- Drainage (eq. 3) --------------------------------------------------------------------

/// The thickness at height `h` and time `t`: both ends move from start to end with the
/// progress `min(1, s t)` (linear) or `1 − e^{−s t}` (exponential), blended by height, ≥ 0.
#[allow(clippy::too_many_arguments)]
fn thickness_reference(
    h: f64,
    t: f64,
    t0: f64,
    t1: f64,
    b0: f64,
    b1: f64,
    s: f64,
    exponential: bool,
) -> f64 {
    let st = s * t.max(0.0);
    let p = if exponential {
        -(-st).exp_m1()
    } else {
        st.min(1.0)
    };
    let top = t0 * (1.0 - p) + t1 * p;
    let bottom = b0 * (1.0 - p) + b1 * p;
    let h = h.clamp(0.0, 1.0);
    (bottom * (1.0 - h) + top * h).max(0.0)
}

#[test]
fn drainage_thickness_at_given_heights_and_times() {
    // A 600 nm film whose top drains to −300 (black film spreading) and bottom thickens to
    // 1200, at the paper's speed 2, linear: at t = 0.25 s the progress is 1/2, the top 150
    // and the bottom 900; half way up 525; at t ≥ 0.5 s the top is −300 and the film is
    // black above h = 0.8 (where 1200 − 1500 h = 0).
    let d = |h, t| film_thickness(h, t, 600.0, -300.0, 600.0, 1200.0, 2.0, 0);
    assert_eq!(d(1.0, 0.25), (150.0, 150.0, 900.0));
    assert_eq!(d(0.5, 0.25).0, 525.0);
    assert_eq!(d(0.0, 0.0).0, 600.0);
    assert_eq!(d(0.9, 0.5).0, 0.0, "black film at the top");
    close("h = 0.7", d(0.7, 3.0).0 as f64, 150.0, 1e-4, 1e-6);
    assert_eq!(d(0.5, -1.0).0, 600.0, "before the start: the start");
    // Exponential: at s t = ln 2 half way.
    let half = std::f32::consts::LN_2 / 2.0;
    close(
        "exponential half way",
        film_thickness(1.0, half, 600.0, 0.0, 600.0, 1200.0, 2.0, 1).0 as f64,
        300.0,
        1e-3,
        1e-6,
    );
    let mut rng = Rng(0xD2A1);
    for i in 0..4000 {
        let exponential = i % 2 == 1;
        let (h, t) = (rng.f(-0.2, 1.2), rng.f(-1.0, 10.0));
        let (t0, t1) = (rng.f(0.0, 2000.0), rng.f(-500.0, 2000.0));
        let (b0, b1) = (rng.f(0.0, 2000.0), rng.f(0.0, 2000.0));
        let s = rng.f(0.0, 10.0);
        let got = film_thickness(h, t, t0, t1, b0, b1, s, exponential as i32).0;
        let want = thickness_reference(
            h as f64,
            t as f64,
            t0 as f64,
            t1 as f64,
            b0 as f64,
            b1 as f64,
            s as f64,
            exponential,
        );
        // f32 rounding of values up to a few thousand: a few 1e-4 absolute.
        close("thickness", got as f64, want, 2e-3, 1e-6);
    }
}

#[test]
fn one_minus_exp_is_accurate_where_it_is_small() {
    let mut rng = Rng(0xE4B);
    for _ in 0..5000 {
        let x = 10f32.powf(rng.f(-9.0, 2.0));
        let want = -(-(x as f64)).exp_m1();
        close("1 − e^−x", one_minus_exp_neg(x) as f64, want, 0.0, 3e-7);
    }
    assert_eq!(one_minus_exp_neg(0.0), 0.0);
    assert_eq!(one_minus_exp_neg(-5.0), 0.0);
    assert_eq!(one_minus_exp_neg(100.0), 1.0);
}

// ---- The final vector (eqs. 4–8) ----------------------------------------------------------

/// `d·R + d·T` and the TIR flag for a view at `theta` from the normal `+z`, turned by `phi`
/// about it, from the angles: `R = (−sin θi cos φ, −sin θi sin φ, cos θi)`; the refracted ray
/// leaves at `sin θt = (n1/n2) sin θi` along `(−sin θt cos φ, −sin θt sin φ, −cos θt)`; under
/// TIR (`sin θt ≥ 1`) the internal vector is `R`.
fn vector_reference(theta: f64, phi: f64, d: f64, n1: f64, n2: f64) -> ([f64; 3], bool) {
    let (si, ci) = theta.sin_cos();
    let st = n1 / n2 * si;
    let r = [-si * phi.cos(), -si * phi.sin(), ci];
    let (t, tir) = if st >= 1.0 {
        (r, true)
    } else {
        let ct = (1.0 - st * st).sqrt();
        ([-st * phi.cos(), -st * phi.sin(), -ct], false)
    };
    (
        [d * (r[0] + t[0]), d * (r[1] + t[1]), d * (r[2] + t[2])],
        tir,
    )
}

fn view_at(theta: f64, phi: f64) -> Vec3 {
    Vec3::new(
        (theta.sin() * phi.cos()) as f32,
        (theta.sin() * phi.sin()) as f32,
        theta.cos() as f32,
    )
}

#[test]
fn the_final_vector_is_snell_plus_reflection_scaled_by_thickness() {
    // Normal incidence from air into the film: R = +z, T = −z, the sum is zero and the
    // direction falls back to R.
    let (v, dir, r, t, tir) = internal_vector(Vec3::Z, Vec3::Z, 1.0, 1.0, 1.33);
    assert_eq!(
        (v, dir, r, t, tir),
        (Vec3::ZERO, Vec3::Z, Vec3::Z, -Vec3::Z, false)
    );
    // 60° in air, the paper's indices: sin θt = 0.866/1.33.
    let theta = 60f64.to_radians();
    let (want, _) = vector_reference(theta, 0.0, 0.7, 1.0, 1.33);
    let (got, ..) = internal_vector(view_at(theta, 0.0), Vec3::Z, 0.7, 1.0, 1.33);
    for k in 0..3 {
        close("60°", got[k] as f64, want[k], 1e-6, 1e-6);
    }
    // From the dense side past the critical angle (48.75° for 1.33 → 1): TIR, 2d R.
    let (got, _, r, t, tir) =
        internal_vector(view_at(60f64.to_radians(), 0.0), Vec3::Z, 1.5, 1.33, 1.0);
    assert!(tir);
    assert_eq!(t, r);
    assert_eq!(got, 3.0 * r);
    let mut rng = Rng(0x5E11);
    let mut tirs = 0;
    for _ in 0..5000 {
        let theta = rng.f(0.0, 89.9f64.to_radians()) as f64;
        let phi = rng.f(0.0, std::f64::consts::TAU) as f64;
        let d = rng.f(0.0, 2.0);
        let (n1, n2) = (rng.f(1.0, 2.0), rng.f(1.0, 2.0));
        let st = n1 as f64 / n2 as f64 * theta.sin();
        if (st - 1.0).abs() < 1e-3 {
            // Within ~0.1° of the critical angle cos θt = √(1 − sin²θt) amplifies the f32
            // rounding of the inputs beyond the tolerance below.
            continue;
        }
        let v = view_at(theta, phi);
        let (want, want_tir) = vector_reference(theta, phi, d as f64, n1 as f64, n2 as f64);
        let (got, dir, _, _, tir) = internal_vector(v, Vec3::Z, d, n1, n2);
        assert_eq!(tir, want_tir, "TIR at θ = {theta}, n1 = {n1}, n2 = {n2}");
        tirs += tir as usize;
        for k in 0..3 {
            close("d·R + d·T", got[k] as f64, want[k], 2e-5, 1e-5);
        }
        let len = want.iter().map(|c| c * c).sum::<f64>().sqrt();
        if len > 1e-3 {
            for k in 0..3 {
                close("direction", dir[k] as f64, want[k] / len, 1e-4, 0.0);
            }
        }
    }
    assert!(tirs > 500, "the random points reach TIR ({tirs})");
}

#[test]
fn the_vector_as_colour_both_readings() {
    let env = Vec3::new(0.2, 0.4, 0.8);
    assert_eq!(vector_color(Vec3::ZERO, env, 0), Vec3::splat(0.5));
    assert_eq!(
        vector_color(Vec3::new(1.0, -1.0, 0.5), env, 0),
        Vec3::new(1.0, 0.0, 0.75)
    );
    assert_eq!(
        vector_color(Vec3::new(3.0, -3.0, 0.0), env, 0),
        Vec3::new(1.0, 0.0, 0.5)
    );
    assert_eq!(vector_color(Vec3::new(3.0, -3.0, 0.0), env, 1), env);
}

// ---- Flow (eq. 9), wobble (eq. 11), motion ------------------------------------------------

#[test]
fn texture_flow_circles_at_the_flow_speed() {
    // Round: a quarter period at the paper's 0.4 (t = π/0.8) gives (+1, 0).
    let t = std::f32::consts::PI / 0.8;
    let uv = texture_flow(Vec2::new(0.25, 0.5), t, 0.4, 1.0);
    close("u", uv.x as f64, 1.25, 1e-6, 0.0);
    close("v", uv.y as f64, 0.5, 1e-6, 0.0);
    let mut rng = Rng(0xF10);
    for _ in 0..5000 {
        let (u, v) = (rng.f(-2.0, 2.0), rng.f(-2.0, 2.0));
        let (t, s, a) = (rng.f(0.0, 100.0), rng.f(0.0, 4.0), rng.f(0.0, 2.0));
        let got = texture_flow(Vec2::new(u, v), t, s, a);
        // The f32 product s·t (up to 400) carries up to 2.4e-5 of rounding into the phase.
        let x = s as f64 * t as f64;
        close(
            "flow u",
            got.x as f64,
            u as f64 + a as f64 * x.sin(),
            6e-5,
            0.0,
        );
        close(
            "flow v",
            got.y as f64,
            v as f64 + a as f64 * x.cos(),
            6e-5,
            0.0,
        );
    }
}

#[test]
fn wobble_offsets_are_sines_and_cosines_of_time() {
    let mut rng = Rng(0x3AB);
    for _ in 0..5000 {
        let p = Vec3::new(rng.f(-2.0, 2.0), rng.f(-2.0, 2.0), rng.f(-2.0, 2.0));
        let (t, f, a, k) = (
            rng.f(0.0, 100.0),
            rng.f(0.0, 10.0),
            rng.f(0.0, 0.2),
            rng.f(0.0, 10.0),
        );
        let got = wobble(p, t, f, a, k);
        let ph = |c: f32| f as f64 * t as f64 + k as f64 * c as f64;
        let want = [
            a as f64 * ph(p.y).sin(),
            a as f64 * ph(p.z).cos(),
            a as f64 * ph(p.x).sin(),
        ];
        for c in 0..3 {
            // Phases up to 1000 rad: their f32 rounding (6e-5) times the amplitude.
            close("wobble", got[c] as f64, want[c], 2e-5, 0.0);
        }
    }
}

#[test]
fn motion_is_the_closed_form_of_repeated_lerp() {
    // The discrete per-frame lerp converges to the closed form as the frame rate grows.
    let (start, target, k, t) = (
        Vec3::new(-1.0, 2.0, 0.5),
        Vec3::new(3.0, 0.0, -1.0),
        0.8f32,
        2.5f32,
    );
    let frames = 100_000;
    let dt = t as f64 / frames as f64;
    let mut p = [start.x as f64, start.y as f64, start.z as f64];
    for _ in 0..frames {
        for c in 0..3 {
            p[c] += (target[c] as f64 - p[c]) * k as f64 * dt;
        }
    }
    let (offset, position) = motion(start, target, k, t);
    for c in 0..3 {
        close("lerp limit", position[c] as f64, p[c], 1e-4, 0.0);
        close(
            "offset",
            offset[c] as f64,
            position[c] as f64 - start[c] as f64,
            1e-6,
            0.0,
        );
    }
    let mut rng = Rng(0x10E);
    for _ in 0..5000 {
        let s = Vec3::new(rng.f(-10.0, 10.0), rng.f(-10.0, 10.0), rng.f(-10.0, 10.0));
        let g = Vec3::new(rng.f(-10.0, 10.0), rng.f(-10.0, 10.0), rng.f(-10.0, 10.0));
        let (k, t) = (rng.f(0.0, 10.0), rng.f(-1.0, 100.0));
        let w = -(-(k as f64 * (t as f64).max(0.0))).exp_m1();
        let (offset, _) = motion(s, g, k, t);
        for c in 0..3 {
            let want = (g[c] as f64 - s[c] as f64) * w;
            close("motion", offset[c] as f64, want, 4e-6, 1e-6);
        }
    }
    assert_eq!(motion(start, target, k, -3.0).0, Vec3::ZERO);
}

// ---- Background (eq. 12, §II.2.2) ---------------------------------------------------------

#[test]
fn camera_blend_and_underwater_quad() {
    // lerp(base, lerp(2·A, 0.5·B, 0.25), 0.5) with base 0, A = 1, B = 4: (0.75·2 + 0.25·2)/2 = 1.
    let c = camera_blend(Vec3::ZERO, Vec3::ONE, Vec3::splat(4.0), 2.0, 0.5, 0.25, 0.5);
    assert_eq!(c, Vec3::ONE);
    // Flat normals (0.5, 0.5, 1) sum to +z; light along +z: full shimmer.
    let flat = Vec3::new(0.5, 0.5, 1.0);
    let tint = Vec3::new(0.5, 0.8, 1.0);
    let (col, a) = underwater(flat, flat, 0.6, Vec3::Z * 3.0, tint, 2.0, 8.0, 0.5);
    assert_eq!((col, a), (tint * 2.0, 0.3));
    // Two normals tilted ±x by 30° sum to +z; light 60° from +z: cos = 1/2, 0.5^3.
    let s = 30f32.to_radians().sin() * 0.5;
    let c30 = 30f32.to_radians().cos() * 0.5 + 0.5;
    let (col, _) = underwater(
        Vec3::new(0.5 + s, 0.5, c30),
        Vec3::new(0.5 - s, 0.5, c30),
        1.0,
        Vec3::new(0.75f32.sqrt(), 0.0, 0.5),
        Vec3::ONE,
        1.0,
        3.0,
        1.0,
    );
    close("60° shimmer", col.x as f64, 0.125, 1e-6, 1e-5);
    // Scrolling: uv + fract(v t).
    let (a, b) = underwater_uv(
        Vec2::new(0.1, 0.2),
        10.0,
        Vec2::new(0.03, -0.05),
        Vec2::ZERO,
    );
    close("uv_a.x", a.x as f64, 0.4, 1e-6, 0.0);
    close("uv_a.y", a.y as f64, 0.7, 1e-6, 0.0);
    assert_eq!(b, Vec2::new(0.1, 0.2));
}

// ---- The scene ----------------------------------------------------------------------------

fn graph(name: &str) -> matgraph::Graph {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("graphs")
        .join(name);
    matgraph::io::load_graph(&path, Registry::builtin()).expect("bundled graph loads")
}

fn render_at(time: f32, size: u32) -> Vec<[f32; 3]> {
    let mut scene = Scene::preset("bubble").unwrap();
    scene.time = time;
    let options = RenderOptions {
        width: size,
        height: size,
        time: Some(time),
        ..RenderOptions::default()
    };
    render(&graph("bubble.json"), &scene, &options)
        .unwrap()
        .pixels
}

/// `RenderOptions::time` moves the scene as well as the material: the bubble rendered at
/// `time: Some(t)` from a scene at time 0 is the bubble of a scene at time `t`.
#[test]
fn the_time_override_moves_the_bubble_too() {
    let at_four = render_at(4.0, 32);
    let scene = Scene::preset("bubble").unwrap();
    assert_eq!(scene.time, 0.0);
    let options = RenderOptions {
        width: 32,
        height: 32,
        time: Some(4.0),
        ..RenderOptions::default()
    };
    let overridden = render(&graph("bubble.json"), &scene, &options)
        .unwrap()
        .pixels;
    assert!(overridden == at_four, "time override and scene time agree");
}

#[test]
fn the_bubble_scene_renders_deterministically_and_moves() {
    let a = render_at(1.0, 48);
    let b = render_at(1.0, 48);
    assert!(a == b, "same time, same pixels");
    assert!(a.iter().flatten().all(|c| c.is_finite() && *c >= 0.0));
    let later = render_at(4.0, 48);
    assert!(a != later, "the bubble and the shimmer move");
    let scene = Scene::preset("bubble").unwrap();
    let SceneKind::Bubble(setup) = &scene.kind else {
        panic!("the bubble preset is a bubble scene");
    };
    // The centre follows start + (target − start)(1 − e^{−rate t}).
    for t in [0.0f32, 0.5, 2.0, 10.0] {
        let c = setup.center_at(t);
        let w = -(-(setup.rate as f64 * t as f64)).exp_m1();
        for k in 0..3 {
            let want = setup.start[k] as f64 + (setup.target[k] as f64 - setup.start[k] as f64) * w;
            close("centre", c[k] as f64, want, 1e-6, 0.0);
        }
        let mut s = scene.clone();
        s.time = t;
        let mesh = s.material_mesh();
        let mean = mesh.positions.iter().copied().sum::<Vec3>() / mesh.positions.len() as f32;
        assert!(
            (mean - c).length() < 0.05,
            "mesh centred on the bubble at t = {t}"
        );
    }
}

#[test]
fn the_bubble_scene_reads_and_checks_its_json() {
    let s = Scene::from_json(r#"{"kind": {"bubble": {"rate": 2, "backdrop": {"mix": 0.25}}}}"#)
        .unwrap();
    let SceneKind::Bubble(b) = &s.kind else {
        panic!("a bubble scene");
    };
    assert_eq!((b.rate, b.backdrop.mix), (2.0, 0.25));
    assert_eq!(
        Scene::from_json(r#"{"kind": "bubble"}"#).unwrap(),
        Scene::preset("bubble").unwrap()
    );
    for (text, field) in [
        (
            r#"{"kind": {"bubble": {"radius": 0}}}"#,
            "kind.bubble.radius",
        ),
        (r#"{"kind": {"bubble": {"rate": -1}}}"#, "kind.bubble.rate"),
        (
            r#"{"kind": {"bubble": {"backdrop": {"mix": 2}}}}"#,
            "kind.bubble.backdrop.mix",
        ),
        (
            r#"{"kind": {"bubble": {"backdrop": {"light": [0, 0, 0]}}}}"#,
            "kind.bubble.backdrop.light",
        ),
    ] {
        match Scene::from_json(text) {
            Err(SceneError::Invalid { field: f, .. }) => assert_eq!(f, field),
            other => panic!("{text}: expected an error in {field}, got {other:?}"),
        }
    }
    assert!(matches!(
        Scene::from_json(r#"{"kind": {"bubble": {"colour": 1}}}"#),
        Err(SceneError::Json { .. })
    ));
}

#[test]
fn the_bubble_maps_are_fixed() {
    let maps = matgraph::scene::bubble_maps();
    for (name, t) in maps.named() {
        assert_eq!((t.width(), t.height()), (256, 256), "{name}");
        let texels = &t.levels()[0].data;
        assert!(
            texels
                .iter()
                .flatten()
                .all(|c| c.is_finite() && (0.0..=1.5).contains(c)),
            "{name}"
        );
        // Normal maps decode to unit vectors.
        if name.starts_with("normal") {
            for c in texels.iter().step_by(97) {
                let n = Vec3::new(2.0 * c[0] - 1.0, 2.0 * c[1] - 1.0, 2.0 * c[2] - 1.0);
                close(name, n.length() as f64, 1.0, 1e-5, 0.0);
            }
        }
    }
}

// ---- The graphs ---------------------------------------------------------------------------

#[test]
fn bubble_graph_carries_the_papers_constants() {
    let g = graph("bubble.json");
    let plan = matgraph::Plan::compile(&g, &matgraph::PlanOptions::default()).unwrap();
    let params = plan.default_parameters();
    for (name, want) in [
        ("n2", 1.33f32),
        ("thickness_speed", 2.0),
        ("flow_speed", 0.4),
        ("rim_power", 2.8),
        ("boost", 3.0),
    ] {
        assert_eq!(params.get(name), Some(Value::float(want)), "{name}");
    }
    let names: Vec<&str> = g.outputs().iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["color", "emission", "alpha", "displacement"]);
}

/// The reflectance of `graph`'s film at normals with the given `N_y` (the view along the
/// normal, uv 0.5) at `time`.
fn film_reflectance(graph: &matgraph::Graph, normal_y: &[f32], time: f32) -> Vec<[f32; 3]> {
    let plan = matgraph::Plan::compile(
        graph,
        &matgraph::PlanOptions {
            outputs: vec!["film.reflectance".into()],
            bake_parameters: false,
        },
    )
    .unwrap();
    let normals: Vec<[f32; 3]> = normal_y
        .iter()
        .map(|&y| [(1.0 - y * y).sqrt(), y, 0.0])
        .collect();
    let mut batch = matgraph::SampleBatch::new(normals.len());
    batch
        .set_values(matgraph::Attribute::Normal, &normals)
        .unwrap();
    batch
        .set_values(matgraph::Attribute::View, &normals)
        .unwrap();
    batch.set_time(time);
    let out = plan.execute(&batch, &plan.default_parameters()).unwrap();
    (0..normals.len())
        .map(|i| {
            let v = out.value(0, i);
            let r = v.raw();
            [r[0], r[1], r[2]]
        })
        .collect()
}

#[test]
fn the_iridescent_bubbles_drain_to_black_film_from_the_top() {
    // Thickness (the graphs' drainage, exponential at 0.5/s): top 500 → −600 nm, bottom
    // 500 → 1000 nm. The top reaches 0 at p = 5/11, t = −ln(6/11)/0.5 = 1.212 s; at
    // t = 5 s, p = 1 − e^(−2.5), and the film is black above h0 = b/(b − t) with
    // b = 500 + 500 p, t = 500 − 1100 p: h0 = 0.6530, N_y = 2 h0 − 1 = 0.3060.
    let p = 1.0 - (-2.5f64).exp();
    let (top, bottom) = (500.0 - 1100.0 * p, 500.0 + 500.0 * p);
    let h0 = bottom / (bottom - top);
    close("h0", h0, 0.6530, 1e-4, 0.0);
    let ny0 = (2.0 * h0 - 1.0) as f32;
    for name in ["bubble_iridescent.json", "bubble_iridescent_fast.json"] {
        let g = graph(name);
        let start = film_reflectance(&g, &[0.9], 0.0);
        assert!(
            start[0].iter().sum::<f32>() > 0.03,
            "{name}: a 500 nm film reflects at first"
        );
        let ny = [0.9, ny0 + 0.01, ny0 - 0.01, -0.5];
        let r = film_reflectance(&g, &ny, 5.0);
        assert!(
            r[0].iter().all(|c| c.abs() < 1e-6),
            "{name}: black film at the top: {:?}",
            r[0]
        );
        assert!(
            r[1].iter().all(|c| c.abs() < 1e-6),
            "{name}: black film just above h0: {:?}",
            r[1]
        );
        assert!(
            r[2].iter().sum::<f32>() > 0.0,
            "{name}: a film just below h0"
        );
        assert!(
            r[3].iter().sum::<f32>() > 0.03,
            "{name}: a thick film lower down"
        );
    }
}
