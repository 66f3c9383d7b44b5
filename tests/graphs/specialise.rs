//! Scene specialisation (src/specialise): every bundled graph's specialised build renders
//! as its full build (exact rewrites: RMSE 0 on the CPU, float rounding on the GPU), the
//! folds give closed forms, the light, time and environment constants are substituted, and
//! the thin film's incoherent limit matches an independent f64 sum and the spectral node at
//! large thickness within the stated error (docs/specialise.md).

use crate::common;
use common::bundled_graphs;
use common::scenes::{graph, render_options, scene_of};

use matgraph::gpu::Backend;
use matgraph::plan::{Plan, PlanOptions};
use matgraph::render::{HdrImage, render};
use matgraph::specialise::{
    EnvironmentInfo, LightInfo, RewriteKind, SceneInfo, SpecialiseOptions, Specialised, specialise,
    thin_film::COHERENCE_LENGTH_D65_NM,
};
use matgraph::{Graph, Registry, SampleBatch};
use std::path::Path;

/// RMSE of linear radiance over every pixel and channel, and the RMS of `a` (the scale).
fn rmse(a: &HdrImage, b: &HdrImage) -> (f64, f64) {
    let (mut d2, mut a2) = (0.0f64, 0.0f64);
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for c in 0..3 {
            d2 += (p[c] as f64 - q[c] as f64).powi(2);
            a2 += (p[c] as f64).powi(2);
        }
    }
    let n = (a.pixels.len() * 3) as f64;
    ((d2 / n).sqrt(), (a2 / n).sqrt())
}

fn spec(g: &Graph, scene: &SceneInfo, approximate: bool) -> Specialised {
    specialise(
        g,
        Registry::builtin(),
        scene,
        &SpecialiseOptions {
            approximate,
            ..Default::default()
        },
    )
    .unwrap_or_else(|e| panic!("{}: {e}", g.name))
}

/// Evaluates output `name` of `g` at one sample with the given attributes and time.
fn eval1(g: &Graph, name: &str, set: &[(matgraph::Attribute, Vec<f32>)], time: f32) -> Vec<f32> {
    let plan = Plan::compile(
        g,
        &PlanOptions {
            outputs: vec![name.into()],
            bake_parameters: false,
        },
    )
    .unwrap();
    let mut batch = SampleBatch::new(1);
    for (a, v) in set {
        batch.set_planar(*a, v.clone()).unwrap();
    }
    batch.set_time(time);
    let params = plan.default_parameters();
    plan.execute(&batch, &params).unwrap().planar(0).to_vec()
}

/// A seeded SplitMix64 generator drawing f32-exact values.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        let u = (self.next() >> 40) as f32 / (1u64 << 24) as f32;
        lo + (hi - lo) * u
    }
}

/// The largest RMSE (relative to the image's RMS) a specialised GPU render may differ from
/// the full one by: the folds are computed on the CPU, the full build computes the same
/// values on the GPU, and WGSL's sin, cos, pow, exp are not correctly rounded.
const GPU_RELATIVE_RMSE: f64 = 1e-4;

#[test]
fn every_bundled_graph_specialised_renders_as_its_full_build_on_the_cpu() {
    for path in bundled_graphs() {
        let g = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        let scene = scene_of(&g);
        let s = spec(&g, &SceneInfo::of(&scene, Some(scene.time)), false);
        assert!(s.is_exact());
        let o = render_options(40, Backend::Cpu, &g, &path);
        let full = render(&g, &scene, &o).unwrap();
        let fast = render(&s.graph, &scene, &o).unwrap();
        let (e, scale) = rmse(&full, &fast);
        eprintln!(
            "{}: {} rewrites, nodes {} -> {}, RMSE {e:.3e} (image RMS {scale:.3})",
            g.name,
            s.rewrites.len(),
            g.nodes().len(),
            s.graph.nodes().len()
        );
        assert_eq!(e, 0.0, "{}: exact rewrites changed the render", g.name);
    }
}

#[test]
fn every_bundled_graph_specialised_renders_as_its_full_build_on_the_gpu() {
    if common::gpu_context("every_bundled_graph_specialised_renders_as_its_full_build_on_the_gpu")
        .is_none()
    {
        return;
    }
    for path in bundled_graphs() {
        let g = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        let scene = scene_of(&g);
        let s = spec(&g, &SceneInfo::of(&scene, Some(scene.time)), false);
        let o = render_options(40, Backend::Gpu, &g, &path);
        let full = render(&g, &scene, &o).unwrap();
        let fast = render(&s.graph, &scene, &o).unwrap();
        let (e, scale) = rmse(&full, &fast);
        eprintln!("{} (GPU): RMSE {e:.3e} (image RMS {scale:.3})", g.name);
        assert!(
            e <= GPU_RELATIVE_RMSE * scale.max(1e-3),
            "{}: RMSE {e} over {scale}",
            g.name
        );
    }
}

/// `sin(2 · time)` at a fixed time and an exact Fresnel reflectance at a constant angle fold
/// into constants equal to their closed forms; the time node and the folded nodes are gone.
#[test]
fn folds_give_the_closed_forms() {
    let g = graph(
        r#"{"version": 1, "name": "folds", "nodes": [
        {"id": "t", "type": "time"},
        {"id": "two_t", "type": "mul", "inputs": {"a": {"link": "t.time"}, "b": 2.0}},
        {"id": "wave", "type": "sin", "inputs": {"x": {"link": "two_t.result"}}},
        {"id": "cos", "type": "cos", "inputs": {"x": 0.927295}},
        {"id": "f", "type": "fresnel_dielectric",
         "inputs": {"cos_theta": {"link": "cos.result"}, "ior_inside": 1.5}},
        {"id": "geo", "type": "geometry"},
        {"id": "lit", "type": "mul", "inputs": {"a": {"link": "f.reflectance"}, "b": {"link": "geo.uv"}}},
        {"id": "sum", "type": "add", "inputs": {"a": {"link": "wave.result"}, "b": {"link": "lit.result"}}}
      ],
      "outputs": [{"name": "wave", "from": "wave.result"}, {"name": "sum", "from": "sum.result"}]}"#,
    );
    let mut rng = Rng(7);
    for time in [0.0f32, 0.3, rng.range(0.0, 10.0), rng.range(0.0, 10.0)] {
        let scene = SceneInfo {
            time: Some(time),
            ..SceneInfo::nothing_fixed()
        };
        let s = spec(&g, &scene, false);
        let ids: Vec<&str> = s.graph.nodes().iter().map(|n| n.id.as_str()).collect();
        for gone in ["t", "two_t", "wave", "cos", "f"] {
            assert!(!ids.contains(&gone), "{gone} left in {ids:?}");
        }
        let kinds: Vec<RewriteKind> = s.rewrites.iter().map(|r| r.kind).collect();
        assert!(kinds.contains(&RewriteKind::Time) && kinds.contains(&RewriteKind::Fold));
        let wave = eval1(&s.graph, "wave", &[], 0.0)[0] as f64;
        let want = (2.0 * time as f64).sin();
        assert!(
            (wave - want).abs() <= 4e-7,
            "sin(2·{time}) = {wave}, want {want}"
        );
        // Fresnel at cos θ = cos(0.927295) = 0.6 (3-4-5 triangle), n = 1.5, f64.
        let c = (0.927295f32 as f64).cos();
        let st = (1.0 - c * c).sqrt() / 1.5;
        let ct = (1.0 - st * st).sqrt();
        let rs = ((c - 1.5 * ct) / (c + 1.5 * ct)).powi(2);
        let rp = ((1.5 * c - ct) / (1.5 * c + ct)).powi(2);
        let fresnel = 0.5 * (rs + rp);
        let uv = [rng.range(0.0, 1.0), rng.range(0.0, 1.0)];
        let sum = eval1(
            &s.graph,
            "sum",
            &[(matgraph::Attribute::Uv, uv.to_vec())],
            0.0,
        );
        for k in 0..2 {
            let want = want + fresnel * uv[k] as f64;
            assert!(
                (sum[k] as f64 - want).abs() <= 1e-6,
                "sum[{k}] = {}, want {want}",
                sum[k]
            );
        }
    }
}

/// One directional light: `light` is folded; `light_color` only without shadow casters.
/// Two lights or a point light: neither.
#[test]
fn one_directional_light_folds_the_light() {
    let g = graph(
        r#"{"version": 1, "name": "lambert", "nodes": [
        {"id": "geo", "type": "geometry"},
        {"id": "nl", "type": "dot", "inputs": {"a": {"link": "geo.normal"}, "b": {"link": "geo.light"}}},
        {"id": "lit", "type": "mul", "inputs": {"a": {"link": "geo.light_color"}, "b": {"link": "nl.result"}}}
      ],
      "outputs": [{"name": "color", "from": "lit.result"}]}"#,
    );
    let d = [0.48f32, 0.6, 0.64];
    let sun = LightInfo::Directional {
        direction: d,
        radiance: [2.0, 1.5, 1.0],
    };
    let base = SceneInfo {
        time: Some(0.0),
        lights: vec![sun],
        shadow_casters: false,
        environment: EnvironmentInfo::Varying,
        coherence_length_nm: COHERENCE_LENGTH_D65_NM,
    };
    let kinds = |s: &SceneInfo| -> Vec<RewriteKind> {
        spec(&g, s, false).rewrites.iter().map(|r| r.kind).collect()
    };
    let k = kinds(&base);
    assert!(k.contains(&RewriteKind::LightDirection) && k.contains(&RewriteKind::LightColor));
    let shadowed = SceneInfo {
        shadow_casters: true,
        ..base.clone()
    };
    let k = kinds(&shadowed);
    assert!(k.contains(&RewriteKind::LightDirection) && !k.contains(&RewriteKind::LightColor));
    for lights in [vec![sun, sun], vec![LightInfo::Local]] {
        let k = kinds(&SceneInfo {
            lights,
            ..base.clone()
        });
        assert!(!k.contains(&RewriteKind::LightDirection) && !k.contains(&RewriteKind::LightColor));
    }
    // N·L with the folded light at random normals, against the f64 dot product.
    let s = spec(&g, &base, false);
    let mut rng = Rng(11);
    for _ in 0..16 {
        let n = [
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        ];
        let out = eval1(
            &s.graph,
            "color",
            &[(matgraph::Attribute::Normal, n.to_vec())],
            0.0,
        );
        let nl: f64 = (0..3).map(|i| n[i] as f64 * d[i] as f64).sum();
        for (c, w) in [2.0, 1.5, 1.0].iter().enumerate() {
            assert!((out[c] as f64 - w * nl).abs() <= 1e-6, "{out:?} vs {nl}");
        }
    }
}

/// Under a constant sky the bubble's environment lookup is replaced by its radiance: the
/// render is unchanged up to the bilinear filter's rounding, and the graph samples no scene
/// texture any more. (The IBL maps `scene:environment_ggx` and `scene:environment_sh` of the
/// PBR graphs are not replaced yet.)
#[test]
fn a_constant_environment_replaces_the_environment_lookups() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/bubble.json");
    let g = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
    let grey = [0.35f32, 0.4, 0.45];
    let mut scene = scene_of(&g);
    scene.environment = matgraph::scene::Environment::Sky(matgraph::scene::Sky {
        zenith_color: grey,
        horizon_color: grey,
        ground_color: grey,
        sun_intensity: 0.0,
        halo: 0.0,
        ..Default::default()
    });
    let info = SceneInfo::of(&scene, Some(scene.time));
    assert_eq!(info.environment, EnvironmentInfo::Constant(grey));
    let s = spec(&g, &info, false);
    assert!(
        s.rewrites
            .iter()
            .any(|r| r.kind == RewriteKind::Environment)
    );
    assert!(matgraph::render::uses_scene_textures(&g));
    assert!(!matgraph::render::uses_scene_textures(&s.graph));
    let o = render_options(32, Backend::Cpu, &g, &path);
    let (e, scale) = rmse(
        &render(&g, &scene, &o).unwrap(),
        &render(&s.graph, &scene, &o).unwrap(),
    );
    eprintln!("bubble under a constant sky: RMSE {e:.3e} (RMS {scale:.3})");
    assert!(e <= 1e-6 * scale, "RMSE {e}");
}

/// Under a constant environment only plain lookups of it are replaced: the Monte Carlo
/// reference of pbr_glass (`ibl` = `monte_carlo`) integrates the environment against the
/// GGX BRDF, so its `color` (the radiance times F0·A + B, about 0.04 for glass seen head on)
/// is not the environment's radiance and stays; it was replaced by the radiance before the
/// rewrite looked at the node's kernel.
#[test]
fn a_constant_environment_keeps_what_integrates_it() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/pbr_glass.json");
    let text = std::fs::read_to_string(&path).unwrap();
    let doc = matgraph::GraphDocument::parse(&text).unwrap();
    let selection = [("ibl".to_owned(), "monte_carlo".to_owned())];
    let g = Graph::with_variants(&doc, Registry::builtin(), &selection).unwrap();
    let grey = [0.35f32, 0.4, 0.45];
    let info = SceneInfo {
        environment: EnvironmentInfo::Constant(grey),
        ..SceneInfo::nothing_fixed()
    };
    let s = spec(&g, &info, false);
    assert!(
        s.rewrites.iter().all(|r| r.node != "env_mc"),
        "{}",
        s.listing()
    );
    assert!(s.graph.nodes().iter().any(|n| n.id == "env_mc"));
}

/// The incoherent sum of a free film in f64, written independently of the rewrite: the
/// general two-interface form `R = R12 + T12² R23/(1 − R12 R23)` per polarisation with the
/// Fresnel reflectances of both faces at their own angles (Born & Wolf §1.5.3), averaged.
fn incoherent_f64(cos1: f64, nf: f64, n1: f64, n3: f64) -> (f64, f64) {
    let c1 = cos1.abs();
    let s1 = (1.0 - c1 * c1).sqrt();
    let sf = n1 * s1 / nf;
    let s3 = n1 * s1 / n3;
    if sf >= 1.0 || s3 >= 1.0 {
        return (1.0, 0.0);
    }
    let cf = (1.0 - sf * sf).sqrt();
    let c3 = (1.0 - s3 * s3).sqrt();
    let rs =
        |na: f64, ca: f64, nb: f64, cb: f64| ((na * ca - nb * cb) / (na * ca + nb * cb)).powi(2);
    let rp =
        |na: f64, ca: f64, nb: f64, cb: f64| ((nb * ca - na * cb) / (nb * ca + na * cb)).powi(2);
    let (mut r, mut t) = (0.0, 0.0);
    for f in [rs, rp] {
        let r12 = f(n1, c1, nf, cf);
        let r23 = f(nf, cf, n3, c3);
        let d = 1.0 - r12 * r23;
        r += 0.5 * (r12 + (1.0 - r12).powi(2) * r23 / d);
        t += 0.5 * ((1.0 - r12) * (1.0 - r23) / d);
    }
    (r, t)
}

fn film_graph(thickness: f32, nf: f32, n: f32) -> Graph {
    graph(&format!(
        r#"{{"version": 1, "name": "film", "nodes": [
        {{"id": "geo", "type": "geometry"}},
        {{"id": "c", "type": "dot", "inputs": {{"a": {{"link": "geo.normal"}}, "b": {{"link": "geo.view"}}}}}},
        {{"id": "film", "type": "thin_film", "inputs": {{"cos_theta": {{"link": "c.result"}},
          "thickness_nm": {thickness}, "film_ior": {nf}, "outside_ior": {n}, "substrate_ior": {n}}}}}
      ],
      "outputs": [{{"name": "reflectance", "from": "film.reflectance"}},
                  {{"name": "transmittance", "from": "film.transmittance"}}]}}"#
    ))
}

/// Evaluates `g` at incidence cosine `c` (normal +z, view in the xz plane).
fn at_cos(g: &Graph, name: &str, c: f32) -> Vec<f32> {
    let s = (1.0 - c * c).max(0.0).sqrt();
    eval1(
        g,
        name,
        &[
            (matgraph::Attribute::Normal, vec![0.0, 0.0, 1.0]),
            (matgraph::Attribute::View, vec![s, 0.0, c]),
        ],
        0.0,
    )
}

/// The rewritten film (math nodes) equals the independent f64 incoherent sum at seeded
/// random angles and indices, grey in every channel.
#[test]
fn the_incoherent_film_is_the_f64_incoherent_sum() {
    let mut rng = Rng(3);
    let scene = SceneInfo {
        coherence_length_nm: COHERENCE_LENGTH_D65_NM,
        ..SceneInfo::nothing_fixed()
    };
    for _ in 0..8 {
        let nf = rng.range(1.2, 2.4);
        let n = rng.range(1.0, 1.15);
        let s = spec(&film_graph(9000.0, nf, n), &scene, true);
        assert!(!s.is_exact());
        assert!(
            s.graph
                .nodes()
                .iter()
                .all(|x| x.node_type.name() != "thin_film")
        );
        for _ in 0..8 {
            let c = rng.range(0.02, 1.0);
            let (r, t) = incoherent_f64(c as f64, nf as f64, n as f64, n as f64);
            let got_r = at_cos(&s.graph, "reflectance", c);
            let got_t = at_cos(&s.graph, "transmittance", c);
            // The view vector's own rounding moves cos θ by ~1e-7.
            for k in 0..3 {
                assert!(
                    (got_r[k] as f64 - r).abs() <= 2e-6,
                    "R({c}, {nf}, {n}) = {got_r:?}, want {r}"
                );
                assert!(
                    (got_t[k] as f64 - t).abs() <= 2e-6,
                    "T({c}, {nf}, {n}) = {got_t:?}, want {t}"
                );
            }
        }
    }
}

/// Measured error of the incoherent limit against the spectral reference (the thin_film
/// node, 471 wavelengths, D65 × CIE 1931) for soap films (n_f = 1.33 in air) whose smallest
/// optical path difference is at least the coherence length: at most
/// [`INCOHERENT_MAX_ERROR`] per channel over seeded random thicknesses and angles
/// (measured: 0.0243 for path differences from 1 to 3.3 coherence lengths).
const INCOHERENT_MAX_ERROR: f64 = 0.03;

#[test]
fn a_thick_film_costs_the_stated_error_and_a_thin_one_is_kept() {
    let scene = SceneInfo {
        coherence_length_nm: COHERENCE_LENGTH_D65_NM,
        ..SceneInfo::nothing_fixed()
    };
    // Grazing cos θ_f of a soap film in air: √(1 − 1/1.33²).
    let cf_min = (1.0f64 - 1.0 / (1.33f64 * 1.33)).sqrt();
    let d_min = COHERENCE_LENGTH_D65_NM as f64 / (2.0 * 1.33 * cf_min);
    // Below the threshold: kept.
    let thin = spec(&film_graph((d_min * 0.9) as f32, 1.33, 1.0), &scene, true);
    assert!(thin.is_exact());
    assert!(
        thin.graph
            .nodes()
            .iter()
            .any(|x| x.node_type.name() == "thin_film")
    );
    let mut rng = Rng(5);
    let mut worst = 0.0f64;
    // Worst |ΔR| by the sample's own path difference in coherence lengths: [1, 2), [2, 4),
    // [4, 8), ≥ 8.
    let mut bands = [0.0f64; 4];
    for _ in 0..6 {
        let d = rng.range(d_min as f32 * 1.01, 10_000.0);
        let g = film_graph(d, 1.33, 1.0);
        let s = spec(&g, &scene, true);
        assert!(
            s.rewrites
                .iter()
                .any(|r| r.kind == RewriteKind::IncoherentFilm)
        );
        for _ in 0..8 {
            let c = rng.range(0.05, 1.0);
            let full = at_cos(&g, "reflectance", c);
            let fast = at_cos(&s.graph, "reflectance", c);
            let cf = (1.0 - (1.0 - c as f64 * c as f64) / (1.33f64 * 1.33)).sqrt();
            let ratio = 2.0 * 1.33 * d as f64 * cf / COHERENCE_LENGTH_D65_NM as f64;
            let band = (ratio.log2().floor().max(0.0) as usize).min(3);
            for k in 0..3 {
                let e = (full[k] - fast[k]).abs() as f64;
                worst = worst.max(e);
                bands[band] = bands[band].max(e);
            }
        }
    }
    eprintln!(
        "incoherent film vs spectral, d ≥ {d_min:.0} nm: max |ΔR| = {worst:.4}; by path difference / l_c in [1,2) [2,4) [4,8) ≥8: {bands:.4?}"
    );
    assert!(worst <= INCOHERENT_MAX_ERROR, "max |ΔR| = {worst}");
}

/// Animated time and a local light fold nothing of the scene's; the same input gives the
/// same specialised document, byte for byte.
#[test]
fn nothing_fixed_folds_no_scene_constant_and_results_are_deterministic() {
    for path in bundled_graphs() {
        let g = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        let s = spec(&g, &SceneInfo::nothing_fixed(), false);
        assert!(s.rewrites.iter().all(|r| !matches!(
            r.kind,
            RewriteKind::Time
                | RewriteKind::LightDirection
                | RewriteKind::LightColor
                | RewriteKind::Environment
        )));
        let scene = scene_of(&g);
        let info = SceneInfo::of(&scene, Some(scene.time));
        let a = spec(&g, &info, false).document.to_json_pretty();
        let b = spec(&g, &info, false).document.to_json_pretty();
        assert_eq!(a, b, "{}", g.name);
    }
}

/// The specialised modules validate (naga, inside `generate`) for every bundled graph and
/// for a thick film's incoherent limit, and the film's is smaller than the spectral node's.
#[test]
fn specialised_wgsl_validates() {
    use matgraph::wgsl::{Entry, WgslOptions, generate};
    let compute = WgslOptions {
        entry: Entry::Compute,
        ..Default::default()
    };
    for path in bundled_graphs() {
        let g = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        let scene = scene_of(&g);
        let s = spec(&g, &SceneInfo::of(&scene, Some(scene.time)), true);
        let full = generate(&g, &compute).unwrap();
        let fast = generate(&s.graph, &compute).unwrap_or_else(|e| panic!("{}: {e}", g.name));
        assert!(
            fast.source.len() <= full.source.len(),
            "{}: {} > {} bytes",
            g.name,
            fast.source.len(),
            full.source.len()
        );
    }
    let scene = SceneInfo {
        coherence_length_nm: COHERENCE_LENGTH_D65_NM,
        ..SceneInfo::nothing_fixed()
    };
    let g = film_graph(8000.0, 1.33, 1.0);
    let s = spec(&g, &scene, true);
    let full = generate(&g, &compute).unwrap();
    let fast = generate(&s.graph, &compute).unwrap();
    eprintln!(
        "thick film: WGSL {} -> {} bytes",
        full.source.len(),
        fast.source.len()
    );
    assert!(fast.source.len() < full.source.len());
}

/// `matgraph wgsl --specialise` prints the rewrites on standard error and a smaller module;
/// `matgraph render --specialise` renders.
#[test]
fn the_cli_specialises_wgsl_and_render() {
    let exe = env!("CARGO_BIN_EXE_matgraph");
    let graph = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/water_sunshine.json");
    let run = |args: &[&str]| {
        let out = std::process::Command::new(exe)
            .args(args)
            .env("XDG_RUNTIME_DIR", "/tmp")
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        out
    };
    let g = graph.to_str().unwrap();
    let full = run(&["wgsl", g]);
    let fast = run(&["wgsl", g, "--specialise"]);
    let listing = String::from_utf8_lossy(&fast.stderr);
    assert!(
        listing.contains("specialised 'water_sunshine'"),
        "{listing}"
    );
    assert!(listing.contains("[time]: time fixed at"), "{listing}");
    assert!(fast.stdout.len() < full.stdout.len());
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("w.png");
    let out = run(&[
        "render",
        g,
        "--specialise",
        "--size",
        "24x24",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("[time]"));
    assert!(png.exists());
}
