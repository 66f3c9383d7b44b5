//! The skin nodes (`nodes/skin.rs`, seed 001): the paper's errata, Jensen 2001's dipole
//! against an f64 reference written here, reciprocity and energy of the Hanrahan–Krueger
//! single-scattering BRDF, and the hard cases with explicit bounds.
//!
//! Run with `cargo test --test models skin:: -- --nocapture` to see the measured figures.

use glam::Vec3;
use matgraph::nodes::optics::hg_phase;
use matgraph::nodes::skin::*;
use std::f64::consts::PI;

// ---------------------------------------------------------------- errata

/// Erratum 1: the printed phase `(1 − g²)/(4π (1 − g² − 2g cos)^1.5)` is NaN for
/// cos > (1 − g²)/(2g) = 0.225 at g = 0.8; the corrected one is finite and normalised.
#[test]
fn erratum_1_printed_phase_is_nan_past_0_225() {
    let g = 0.8;
    assert!(hg_phase_printed(0.2, g).is_finite());
    for c in [0.23_f32, 0.5, 0.9, 1.0] {
        assert!(hg_phase_printed(c, g).is_nan(), "printed phase at cos {c}");
        assert!(hg_phase(c, g).is_finite() && hg_phase(c, g) > 0.0);
    }
    // The corrected phase integrates to 1 over the sphere (midpoint rule in cos).
    let n = 200_000;
    let s: f64 = (0..n)
        .map(|k| {
            let c = -1.0 + (k as f64 + 0.5) * 2.0 / n as f64;
            2.0 * PI * hg_phase(c as f32, g) as f64 * 2.0 / n as f64
        })
        .sum();
    assert!((s - 1.0).abs() < 2e-3, "∫p = {s}");
}

/// Erratum 2: the printed Fresnel gives Kr ≈ 0.486 at normal incidence from air into
/// eta 1.4; the exact value is ((1.4 − 1)/(1.4 + 1))² = 0.0278 (efresnel's smoothstep
/// then maps it to 0.0083).
#[test]
fn erratum_2_printed_fresnel_at_normal_incidence() {
    let printed = fresnel_printed(1.0, 1.0 / 1.4);
    eprintln!("printed Fresnel Kr(normal, eta 1.4) = {printed}");
    assert!((printed - 0.486).abs() < 1e-3, "{printed}");
    let (exact, _) = matgraph::nodes::optics::fresnel_dielectric(1.0, 1.0, 1.4);
    assert!((exact - 0.02778).abs() < 1e-4, "{exact}");
    let (kr, kt, t) = skin_efresnel(Vec3::new(0.0, 0.0, -1.0), Vec3::Z, 1.0 / 1.4);
    let x = 0.02778_f32 / 0.5;
    assert!((kr - x * x * (3.0 - 2.0 * x)).abs() < 1e-4, "{kr}");
    assert!((kr + kt - 1.0).abs() < 1e-6);
    assert!((t - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
}

/// Erratum 3: Pharr's phase lacks 1/(4π): the `pharr` form is 4π times the normalised one.
#[test]
fn erratum_3_pharr_phase_is_4pi_times() {
    let tl = Vec3::new(0.3, 0.0, -0.954).normalize();
    let tv = Vec3::new(-0.5, 0.2, -0.84).normalize();
    let (a, _) = skin_single_scattering(tl, tv, Vec3::Z, 0.8, Vec3::ONE, 0.7, 0, false);
    let (b, _) = skin_single_scattering(tl, tv, Vec3::Z, 0.8, Vec3::ONE, 0.7, 1, false);
    assert!((b.x / a.x - 4.0 * std::f32::consts::PI).abs() < 1e-4);
}

/// Erratum 4: eta is n_incident/n_transmitted; the reciprocal (pbrt) gives TIR at 60° instead
/// of a refracted ray bent towards the normal.
#[test]
fn erratum_4_eta_convention() {
    let i = Vec3::new(0.866, 0.0, -0.5);
    let (_, kt, t) = skin_efresnel(i, Vec3::Z, 1.0 / 1.4);
    assert!(kt > 0.8 && t.z < -0.7, "{kt} {t}");
    let (kr, kt, _) = skin_efresnel(i, Vec3::Z, 1.4);
    assert_eq!((kr, kt), (1.0, 0.0));
}

// ---------------------------------------------------------------- dipole

fn fdr64(eta: f64) -> f64 {
    -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta
}

fn rd_total64(s_s: f64, s_a: f64, eta: f64) -> f64 {
    let a = (1.0 + fdr64(eta)) / (1.0 - fdr64(eta));
    let alpha = s_s / (s_s + s_a);
    let s = (3.0 * (1.0 - alpha)).sqrt();
    0.5 * alpha * (1.0 + (-4.0 / 3.0 * a * s).exp()) * (-s).exp()
}

/// Jensen et al. 2001, Table 1 (σs', σa in 1/mm) and η.
const MATERIALS: [(&str, [f32; 3], [f32; 3], f32); 4] = [
    ("skin1", [0.74, 0.88, 1.01], [0.032, 0.17, 0.48], 1.3),
    ("skin2", [1.09, 1.59, 1.79], [0.013, 0.070, 0.145], 1.3),
    ("marble", [2.19, 2.62, 3.00], [0.0021, 0.0041, 0.0071], 1.5),
    ("ketchup", [0.18, 0.07, 0.03], [0.061, 0.97, 1.45], 1.3),
];

#[test]
fn dipole_total_matches_f64_reference() {
    for (name, s, a, eta) in MATERIALS {
        let rd = dipole_rd_total(Vec3::from(s), Vec3::from(a), eta);
        let rd = [rd.x, rd.y, rd.z];
        let want: Vec<f64> = (0..3)
            .map(|k| rd_total64(s[k] as f64, a[k] as f64, eta as f64))
            .collect();
        eprintln!("{name:8} Rd = {rd:.5?}  f64 reference {want:.5?}");
        for k in 0..3 {
            let err = (rd[k] as f64 - want[k]).abs();
            assert!(
                err < 1e-5 + 1e-5 * want[k],
                "{name}[{k}]: {} vs {}",
                rd[k],
                want[k]
            );
        }
    }
}

/// ∫₀^∞ 2πr Rd(r) dr = Rd_total (log-spaced trapezoid from 1e-6 to 1e3 mm, f32 profile).
#[test]
fn dipole_profile_integrates_to_total() {
    for (name, s, a, eta) in MATERIALS {
        let (s, a) = (Vec3::from(s), Vec3::from(a));
        let n = 40_000;
        let (lo, hi) = (1e-6_f64.ln(), 1e3_f64.ln());
        let mut sum = [0.0f64; 3];
        let mut prev: Option<(f64, [f64; 3])> = None;
        for k in 0..=n {
            let r = (lo + (hi - lo) * k as f64 / n as f64).exp();
            let p = dipole_rd_profile(r as f32, s, a, eta);
            let v = [p.x as f64, p.y as f64, p.z as f64].map(|x| 2.0 * PI * r * x);
            if let Some((r0, v0)) = prev {
                for c in 0..3 {
                    sum[c] += 0.5 * (v0[c] + v[c]) * (r - r0);
                }
            }
            prev = Some((r, v));
        }
        let total = dipole_rd_total(s, a, eta);
        let total = [total.x as f64, total.y as f64, total.z as f64];
        eprintln!("{name:8} ∫2πr Rd(r) dr = {sum:.5?}  Rd_total = {total:.5?}");
        for c in 0..3 {
            assert!(
                (sum[c] - total[c]).abs() < 1e-3 * total[c].max(0.01),
                "{name}[{c}]"
            );
        }
    }
}

// ---------------------------------------------------------------- single scattering

fn dir(theta: f64, phi: f64, down: bool) -> Vec3 {
    let z = theta.cos() * if down { -1.0 } else { 1.0 };
    Vec3::new(
        (theta.sin() * phi.cos()) as f32,
        (theta.sin() * phi.sin()) as f32,
        z as f32,
    )
}

/// f(wi, wo) = f(wo, wi) for the single-scattering BRDF, on a grid of directions.
#[test]
fn single_scattering_is_reciprocal() {
    let mut worst = 0.0f32;
    for form in [0, 1] {
        for three in [false, true] {
            for i in 0..12 {
                for j in 0..12 {
                    let a = dir(i as f64 * 0.13, 0.4, true);
                    let b = dir(j as f64 * 0.13 + 0.01, 2.7, true);
                    let (f1, _) =
                        skin_single_scattering(a, b, Vec3::Z, 0.8, Vec3::ONE, 0.6, form, three);
                    let (f2, _) =
                        skin_single_scattering(b, a, Vec3::Z, 0.8, Vec3::ONE, 0.6, form, three);
                    let rel = (f1 - f2).abs().max_element() / f1.max_element().max(1e-12);
                    worst = worst.max(rel);
                }
            }
        }
    }
    eprintln!("reciprocity: max relative |f(wi,wo) − f(wo,wi)| = {worst:e}");
    assert!(worst < 1e-6);
}

/// Directional albedo `∫ f(wi, wo) mu_o dω_o` over the outgoing hemisphere (inside the
/// layer) with albedo 1, midpoint rule in (cos θ, φ).
fn hemisphere_albedo(theta_i: f64, g: f32, d: f32, three: bool) -> f64 {
    let wi = dir(theta_i, 0.0, true);
    let (nt, np) = (400, 200);
    let mut s = 0.0;
    for a in 0..nt {
        let mu = (a as f64 + 0.5) / nt as f64;
        for b in 0..np {
            let phi = (b as f64 + 0.5) / np as f64 * 2.0 * PI;
            let wo = dir(mu.acos(), phi, true);
            let (f, _) = skin_single_scattering(wi, wo, Vec3::Z, g, Vec3::ONE, d, 0, three);
            s += f.x as f64 * mu * (1.0 / nt as f64) * (2.0 * PI / np as f64);
        }
    }
    s
}

/// The normalised single-scattering BRDF with albedo 1 reflects no more than it receives.
#[test]
fn single_scattering_energy_is_bounded() {
    let mut worst: f64 = 0.0;
    for theta in [0.0, 0.6, 1.2, 1.5] {
        for g in [0.8f32, 0.0, -0.5, 0.95] {
            for d in [0.1f32, 1.0, 100.0] {
                let e = hemisphere_albedo(theta, g, d, false);
                worst = worst.max(e);
                assert!(e <= 1.0 + 1e-3, "θ {theta} g {g} d {d}: {e}");
            }
        }
    }
    let three = (0..4)
        .map(|k| hemisphere_albedo(k as f64 * 0.5, 0.0, 100.0, true))
        .fold(0.0f64, f64::max);
    eprintln!(
        "energy: max directional albedo, one lobe = {worst:.4}; Pharr's three lobes (a sum 1.7) = {three:.4}"
    );
    assert!(three <= 1.0, "{three}");
}

// ---------------------------------------------------------------- hard cases

#[test]
fn hard_cases_are_finite_and_bounded() {
    let n = Vec3::Z;
    // Grazing light and view: f · mu_i stays below albedo · p_max.
    let graze = Vec3::new(1.0, 0.0, -1e-7);
    for g in [0.8, 0.999, -0.999, 0.0] {
        let p_max = hg_phase(1.0, g).max(hg_phase(-1.0, g));
        for (a, b) in [
            (graze, -graze),
            (graze, graze),
            (graze, Vec3::new(0.0, 0.0, -1.0)),
        ] {
            for d in [0.0, 1e-8, 0.5, 1e6] {
                let (f, fw) = skin_single_scattering(a, b, n, g, Vec3::ONE, d, 0, false);
                assert!(f.is_finite() && fw.is_finite(), "g {g} d {d}: {f} {fw}");
                assert!(
                    fw.max_element() <= p_max * 1.0001,
                    "g {g} d {d}: {fw} > {p_max}"
                );
                assert!(f.min_element() >= 0.0);
            }
        }
    }
    // Thickness → 0: f ≈ albedo p d (1/mu_i + 1/mu_o)/(mu_i + mu_o) = albedo p d/(mu_i mu_o), kept by expm1.
    let d = 1e-8;
    let (f, _) = skin_single_scattering(
        Vec3::new(0.0, 0.0, -1.0),
        Vec3::new(0.0, 0.0, -1.0),
        n,
        0.8,
        Vec3::ONE,
        d,
        0,
        false,
    );
    let want = hg_phase(-1.0, 0.8) * d;
    assert!((f.x / want - 1.0).abs() < 1e-5, "{} vs {want}", f.x);
    // Very thick: the semi-infinite limit albedo p/(mu_i + mu_o).
    let (f, _) = skin_single_scattering(
        Vec3::new(0.0, 0.0, -1.0),
        Vec3::new(0.0, 0.0, -1.0),
        n,
        0.8,
        Vec3::ONE,
        1e6,
        0,
        false,
    );
    assert!((f.x - hg_phase(-1.0, 0.8) / 2.0).abs() < 1e-7);
    // efresnel: grazing, light below the horizon, eta = 1.
    for i in [
        Vec3::new(1.0, 0.0, -1e-7),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 0.6, 0.8),
    ] {
        for eta in [1.0 / 1.4, 1.0, 1.4] {
            let (kr, kt, t) = skin_efresnel(i, n, eta);
            assert!(
                (0.0..=1.0).contains(&kr) && (0.0..=1.0).contains(&kt) && t.is_finite(),
                "{i} {eta}"
            );
            assert!((t.length() - 1.0).abs() < 1e-5);
        }
    }
    let (kr, kt, t) = skin_efresnel(Vec3::new(0.6, 0.0, -0.8), n, 1.0);
    assert!(
        kr.abs() < 1e-6
            && (kt - 1.0).abs() < 1e-6
            && (t - Vec3::new(0.6, 0.0, -0.8)).length() < 1e-6
    );
    // Multiple scattering at exactly grazing with l_c = 0: bounded by C_d I_ms / 1e-4.
    let m = skin_multiple_scattering(Vec3::ONE, 0.3, 0.0, 0.0);
    assert!(m.is_finite() && m.x <= 0.3e4 * 1.0001);
    // Sebum: light below the horizon (R·V < 0) gives 0; 0^0 = 1.
    assert_eq!(skin_sebum(0.5, 30.0, -0.3), 0.0);
    assert_eq!(skin_sebum(0.5, 0.0, 0.0), 0.5);
    // Dipole: no absorption, empty medium, eta 1, r = 0.
    let z = Vec3::ZERO;
    for (s, a, eta) in [
        (Vec3::ONE, z, 1.3),
        (z, z, 1.3),
        (Vec3::ONE, Vec3::ONE, 1.0),
    ] {
        let t = dipole_rd_total(s, a, eta);
        assert!(
            t.is_finite() && t.min_element() >= 0.0 && t.max_element() <= 1.0,
            "{t}"
        );
        let p = dipole_rd_profile(0.0, s, a, eta);
        assert!(p.is_finite() && p.min_element() >= 0.0, "{p}");
    }
}
