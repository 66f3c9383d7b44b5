//! Every physics node (optics, PBR, skin) against a pointwise f64 reference written here from
//! the published equations, at seeded random f32-exact points and at the hard cases: grazing
//! (cos 1e-3 … 1e-7), near the critical angle (0.001°–0.1°), index match, roughness
//! 0.02–0.05, g = ±(1 − 2⁻ᵏ), very thin and very thick layers, low absorption.
//!
//! Each input is an f32; the reference takes the same values widened to f64, so what is
//! measured is the node's own arithmetic. None of the references calls the code under test
//! or copies its rearrangements: they are the textbook forms, evaluated in f64, except where
//! f64 itself would cancel (noted at each). Bound: max(2e-6 absolute, 1e-5 relative) unless a
//! node's doc states a limit, which the check names: near a critical angle the f32 rounding
//! of cos²θt times ∂out/∂cos²θt ([`critical_term`]); the GGX lobe's and the phase function's
//! conditioning in their direction inputs.
//!
//! `cargo test --test models physics_pointwise:: -- --nocapture` prints the largest error per node.

use crate::common;

use common::rng::Rng;

use glam::Vec3;
use matgraph::nodes::{optics, pbr, skin};
use matgraph::{Graph, Plan, PlanOptions, Registry, SampleBatch};
use serde_json::json;
use std::collections::BTreeMap;
use std::f64::consts::PI;

/// Absolute part of the bound.
const ABS: f64 = 2e-6;
/// Relative part of the bound.
const REL: f64 = 1e-5;
/// Random points per node.
const N: usize = 20_000;

// ------------------------------------------------------------------------------------------
// Harness
// ------------------------------------------------------------------------------------------

/// The draws these tests make from the shared seeded generator.
impl Rng {
    /// Log-uniform in [lo, hi] (lo > 0), rounded to f32.
    fn log(&mut self, lo: f64, hi: f64) -> f32 {
        let u = (self.next() >> 11) as f64 / (1u64 << 53) as f64;
        (lo.ln() + (hi.ln() - lo.ln()) * u).exp() as f32
    }
    /// A unit vector (rounded to f32) in the upper (z > 0) hemisphere.
    fn up(&mut self) -> Vec3 {
        let z = self.f(0.0, 1.0) as f64;
        let phi = self.f(0.0, 2.0 * PI) as f64;
        let s = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, z as f32)
    }
}

/// Largest errors of one node, and the failures.
struct Check {
    node: &'static str,
    worst_abs: f64,
    worst_rel: f64,
    worst_at: String,
    failures: Vec<String>,
    count: usize,
}

impl Check {
    fn new(node: &'static str) -> Check {
        Check {
            node,
            worst_abs: 0.0,
            worst_rel: 0.0,
            worst_at: String::new(),
            failures: Vec::new(),
            count: 0,
        }
    }
    /// Compares `got` with `want` under max(abs, rel·|want|).
    fn near_tol(&mut self, got: f32, want: f64, abs: f64, rel: f64, at: impl Fn() -> String) {
        self.count += 1;
        let err = (got as f64 - want).abs();
        let ok = got.is_finite() && err <= abs.max(rel * want.abs());
        if !got.is_finite() || err > self.worst_abs {
            self.worst_abs = if got.is_finite() { err } else { f64::INFINITY };
            self.worst_at = format!("{} (got {got:e}, want {want:e})", at());
        }
        if want.abs() > 1e-30 {
            self.worst_rel = self.worst_rel.max(err / want.abs());
        }
        if !ok && self.failures.len() < 20 {
            self.failures.push(format!(
                "{}: got {got:e}, want {want:e}, error {err:.3e}",
                at()
            ));
        }
    }
    /// [`Check::near_tol`] with the default bound.
    fn near(&mut self, got: f32, want: f64, at: impl Fn() -> String) {
        self.near_tol(got, want, ABS, REL, at);
    }
    /// Reports and asserts.
    fn finish(self) {
        eprintln!(
            "[{}] {} checks, max abs error {:.3e}, max rel error {:.3e}; worst at {}",
            self.node, self.count, self.worst_abs, self.worst_rel, self.worst_at
        );
        assert!(self.count > 0, "{}: nothing checked", self.node);
        assert!(
            self.failures.is_empty(),
            "{}: {} failures:\n{}",
            self.node,
            self.failures.len(),
            self.failures.join("\n")
        );
    }
}

type D3 = [f64; 3];
fn d3(v: Vec3) -> D3 {
    [v.x as f64, v.y as f64, v.z as f64]
}
fn dot(a: D3, b: D3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn add(a: D3, b: D3) -> D3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn scale(a: D3, s: f64) -> D3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn unit(a: D3) -> D3 {
    scale(a, 1.0 / dot(a, a).sqrt())
}

/// The outputs of one node evaluated through the graph pipeline, by output name.
fn eval(node: &str, inputs: serde_json::Value) -> BTreeMap<String, Vec<f32>> {
    let map: BTreeMap<String, serde_json::Value> =
        serde_json::from_value(inputs).expect("an object of inputs");
    let graph = Graph::single_node(Registry::builtin(), node, map).expect("a valid graph");
    let plan = Plan::compile(&graph, &PlanOptions::default()).expect("compiles");
    let out = plan
        .execute(&SampleBatch::new(1), &plan.default_parameters())
        .expect("evaluates");
    out.names()
        .iter()
        .enumerate()
        .map(|(k, name)| (name.to_string(), out.value(k, 0).lanes().to_vec()))
        .collect()
}

// ------------------------------------------------------------------------------------------
// References (f64, textbook forms)
// ------------------------------------------------------------------------------------------

/// Fresnel's equations (Hecht §4.6): unpolarised R for light from n1 into n2; 1 under TIR.
fn ref_fresnel(cos_theta: f64, n_out: f64, n_in: f64) -> f64 {
    let (n1, n2, ci) = if cos_theta >= 0.0 {
        (n_out, n_in, cos_theta.min(1.0))
    } else {
        (n_in, n_out, (-cos_theta).min(1.0))
    };
    let sin2_t = (n1 / n2).powi(2) * (1.0 - ci * ci);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let ct = (1.0 - sin2_t).sqrt();
    let rs = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct);
    let rp = (n2 * ci - n1 * ct) / (n2 * ci + n1 * ct);
    if !(rs.is_finite() && rp.is_finite()) {
        return 0.0; // 0/0 only at an index match at grazing: no interface.
    }
    0.5 * (rs * rs + rp * rp)
}

/// The conditioning term of the limit the optics nodes' docs state: k = cos²θt is formed
/// from f32 terms of size max(1, η²), so it carries a few u·max(1, η²) (u = 2⁻²⁴) of absolute
/// rounding, which `∂out/∂k` (diverging like 1/√k at the critical angle) amplifies:
/// 8u·max(1, η²)·|∂out/∂k|.
fn critical_term(dout_dk: f64, eta: f64) -> f64 {
    8.0 * (f32::EPSILON as f64 / 2.0) * (eta * eta).max(1.0) * dout_dk.abs()
}

/// ∂R/∂k of the exact reflectance, k = cos²θt (0 under TIR).
fn ref_fresnel_dk(cos_theta: f64, n_out: f64, n_in: f64) -> f64 {
    let (n1, n2, ci) = if cos_theta >= 0.0 {
        (n_out, n_in, cos_theta)
    } else {
        (n_in, n_out, -cos_theta)
    };
    let k = 1.0 - (n1 / n2).powi(2) * (1.0 - ci * ci);
    if k <= 0.0 {
        return 0.0;
    }
    let ct = k.sqrt();
    let (a, c) = (n1 * ci, n2 * ci);
    let rs = (a - n2 * ct) / (a + n2 * ct);
    let rp = (c - n1 * ct) / (c + n1 * ct);
    let drs = -2.0 * a * n2 / (a + n2 * ct).powi(2);
    let drp = -2.0 * c * n1 / (c + n1 * ct).powi(2);
    (rs * drs + rp * drp) / (2.0 * ct)
}

/// |∂T/∂k| of vector refraction with a unit normal: T depends on k through √k N.
fn ref_refract_dk(i: D3, n: D3, eta: f64) -> f64 {
    let c = dot(n, i);
    let k = 1.0 - eta * eta * (1.0 - c * c);
    if k <= 0.0 { 0.0 } else { 0.5 / k.sqrt() }
}

/// GLSL refract in f64: (T, tir).
fn ref_refract(i: D3, n: D3, eta: f64) -> (D3, bool) {
    let c = dot(n, i);
    let k = 1.0 - eta * eta * (1.0 - c * c);
    if k < 0.0 {
        (add(i, scale(n, -2.0 * c)), true)
    } else {
        (add(scale(i, eta), scale(n, -(eta * c + k.sqrt()))), false)
    }
}

/// Henyey–Greenstein, `(1 − g²)/(4π (1 + g² − 2g cosθ)^1.5)`. The base is formed from the
/// exact identities `1 + g² − 2gc = (1 − g)² + 2g(1 − c) = (1 + g)² − 2g(1 + c)`, whichever
/// adds non-negative terms: the textbook sum loses ~1e-16/(1 − |g|)² relative in f64, 2e-6 at
/// g = 1 − 2⁻¹⁷.
fn ref_hg(c: f64, g: f64) -> f64 {
    let base = if g >= 0.0 {
        (1.0 - g).powi(2) + 2.0 * g * (1.0 - c)
    } else {
        (1.0 + g).powi(2) - 2.0 * g * (1.0 + c)
    };
    (1.0 - g) * (1.0 + g) / (4.0 * PI * base.powf(1.5))
}

/// GGX D (Walter et al. 2007 eq. 33) with α = roughness².
fn ref_ggx(c: f64, roughness: f64) -> f64 {
    if c <= 0.0 {
        return 0.0;
    }
    let a2 = roughness.powi(4);
    a2 / (PI * (c * c * (a2 - 1.0) + 1.0).powi(2))
}

/// Height-correlated Smith V (Heitz 2014 eq. 99).
fn ref_smith(nv: f64, nl: f64, roughness: f64) -> f64 {
    if nv <= 0.0 || nl <= 0.0 {
        return 0.0;
    }
    let a2 = roughness.powi(4);
    0.5 / (nl * (nv * nv * (1.0 - a2) + a2).sqrt() + nv * (nl * nl * (1.0 - a2) + a2).sqrt())
}

/// n from F0 in air, `(1 + √F0)/(1 − √F0)`.
fn ref_f0_to_ior(f0: f64) -> f64 {
    (1.0 + f0.sqrt()) / (1.0 - f0.sqrt())
}

/// The metallic–roughness BRDF × N·L of docs/models/pbr.md, channel `k`.
#[allow(clippy::too_many_arguments)]
fn ref_brdf(
    n: D3,
    v: D3,
    l: D3,
    base: D3,
    metallic: f64,
    roughness: f64,
    specular: f64,
    exact: bool,
    k: usize,
) -> (f64, f64) {
    let (n, v, l) = (unit(n), unit(v), unit(l));
    let nl = dot(n, l);
    if nl <= 0.0 {
        return (0.0, 0.0);
    }
    let nv = dot(n, v).max(0.0);
    let h = unit(add(l, v));
    let f0 = 0.08 * specular * (1.0 - metallic) + base[k] * metallic;
    let fresnel = |c: f64| {
        if exact {
            if f0 >= 1.0 {
                1.0
            } else {
                ref_fresnel(c, 1.0, ref_f0_to_ior(f0))
            }
        } else {
            f0 + (1.0 - f0) * (1.0 - c).powi(5)
        }
    };
    let diffuse = base[k] * (1.0 - metallic) / PI * (1.0 - fresnel(nl)) * (1.0 - fresnel(nv)) * nl;
    let spec = fresnel(dot(v, h).clamp(0.0, 1.0))
        * ref_ggx(dot(n, h), roughness)
        * ref_smith(nv.max(1e-300), nl, roughness)
        * nl;
    (diffuse, spec)
}

/// Jensen's Fdr polynomial (Jensen et al. 2001, §2.4).
fn ref_fdr(eta: f64) -> f64 {
    -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta
}

/// Jensen et al. 2001 total diffuse reflectance (eq. 5 integrated).
fn ref_rd_total(s_s: f64, s_a: f64, eta: f64) -> f64 {
    let s_t = s_s + s_a;
    if s_t == 0.0 {
        return 0.0;
    }
    let alpha = s_s / s_t;
    let a = (1.0 + ref_fdr(eta)) / (1.0 - ref_fdr(eta));
    let s = (3.0 * (1.0 - alpha)).sqrt();
    0.5 * alpha * (1.0 + (-(4.0 / 3.0) * a * s).exp()) * (-s).exp()
}

/// Jensen et al. 2001 eq. 4, the dipole profile Rd(r).
fn ref_rd_profile(r: f64, s_s: f64, s_a: f64, eta: f64) -> f64 {
    let s_t = s_s + s_a;
    let alpha = s_s / s_t;
    let s_tr = (3.0 * s_a * s_t).sqrt();
    let a = (1.0 + ref_fdr(eta)) / (1.0 - ref_fdr(eta));
    let z_r = 1.0 / s_t;
    let z_v = z_r * (1.0 + 4.0 * a / 3.0);
    let term = |z: f64| {
        let d = (r * r + z * z).sqrt();
        z * (s_tr * d + 1.0) * (-s_tr * d).exp() / d.powi(3)
    };
    alpha / (4.0 * PI) * (term(z_r) + term(z_v))
}

/// Hanrahan & Krueger 1993 eq. 21 for one lobe.
fn ref_hk(cos: f64, g: f64, mu_i: f64, mu_o: f64, d: f64) -> f64 {
    ref_hg(cos, g) / (mu_i + mu_o) * (1.0 - (-d * (1.0 / mu_i + 1.0 / mu_o)).exp())
}

// ------------------------------------------------------------------------------------------
// Optics
// ------------------------------------------------------------------------------------------

/// The forms for callers that know sin²θi or cos²θt (the transmission nodes): against the f64
/// Fresnel at the angle their f32 inputs were rounded from, at seeded angles and index pairs
/// (soft and hard, denser side included), within 0.01°–1° of each side's critical angle, and
/// grazing; the same tolerance as `fresnel_dielectric`, whose critical term covers the
/// inputs' rounding.
#[test]
fn fresnel_from_sin2_and_cos2t_pointwise() {
    let mut ch = Check::new("fresnel_dielectric_sin2 / _cos2t, cos2_transmitted_sin2");
    let mut rng = Rng(0x5152);
    let check = |ch: &mut Check, theta: f64, n1: f32, n2: f32, why: &str| {
        let (c64, s64) = (theta.cos(), theta.sin());
        let (c, s2) = (c64 as f32, (s64 * s64) as f32);
        let (n1d, n2d) = (n1 as f64, n2 as f64);
        let want = ref_fresnel(c64, n1d, n2d);
        let tol = ABS + critical_term(ref_fresnel_dk(c64, n1d, n2d), (n1d / n2d).max(n2d / n1d));
        let k64 = 1.0 - (n1d / n2d).powi(2) * s64 * s64;
        let k = optics::cos2_transmitted_sin2(c, s2, n1 / n2);
        ch.near_tol(
            k,
            k64,
            8.0 * f32::EPSILON as f64 * (n1d / n2d).powi(2).max(1.0),
            0.0,
            || format!("{why}: cos²θt at θ {theta} n {n1} | {n2}"),
        );
        let k32 = (k64 as f32).max(-1.0);
        for (form, (r, t)) in [
            ("sin2", optics::fresnel_dielectric_sin2(c, s2, n1, n2)),
            ("cos2t", optics::fresnel_dielectric_cos2t(c, k32, n1, n2)),
        ] {
            ch.near_tol(r, want, tol, REL, || {
                format!("{why} ({form}): R at θ {theta} n {n1} | {n2}")
            });
            ch.near_tol(t, 1.0 - want, tol, REL, || {
                format!("{why} ({form}): T at θ {theta} n {n1} | {n2}")
            });
        }
    };
    for _ in 0..N {
        let theta = rng.f(0.0, std::f64::consts::FRAC_PI_2) as f64;
        let (n1, n2) = (rng.f(1.0, 3.0), rng.f(1.0, 3.0));
        check(&mut ch, theta, n1, n2, "random soft");
        let (n1, n2) = (rng.log(1.0, 100.0), rng.log(1.0, 100.0));
        check(&mut ch, theta, n1, n2, "random hard");
    }
    for (n1, n2) in [(1.33f32, 1.0f32), (2.42, 1.0), (14.7, 1.0), (97.0, 6.6)] {
        let crit = (n2 as f64 / n1 as f64).asin();
        for delta_deg in [0.01f64, 0.03, 0.1, 0.3, 1.0] {
            for side in [-1.0, 1.0] {
                check(
                    &mut ch,
                    crit + side * delta_deg.to_radians(),
                    n1,
                    n2,
                    "near critical",
                );
            }
        }
    }
    for k in 2..=7 {
        for (n1, n2) in [(1.0f32, 1.5f32), (1.5, 1.0), (1.5, 1.5000001)] {
            check(
                &mut ch,
                std::f64::consts::FRAC_PI_2 - 10f64.powi(-k),
                n1,
                n2,
                "grazing",
            );
        }
    }
    ch.finish();
}

#[test]
fn fresnel_dielectric_pointwise() {
    let mut ch = Check::new("fresnel_dielectric");
    let mut rng = Rng(1);
    let check = |ch: &mut Check, c: f32, n1: f32, n2: f32, why: &str| {
        let (r, t) = optics::fresnel_dielectric(c, n1, n2);
        let want = ref_fresnel(c as f64, n1 as f64, n2 as f64);
        let tol = ABS
            + critical_term(
                ref_fresnel_dk(c as f64, n1 as f64, n2 as f64),
                (n1 as f64 / n2 as f64).max(n2 as f64 / n1 as f64),
            );
        ch.near_tol(r, want, tol, REL, || {
            format!("{why}: R cos {c:e} n {n1} | {n2}")
        });
        ch.near_tol(t, 1.0 - want, tol, REL, || {
            format!("{why}: T cos {c:e} n {n1} | {n2}")
        });
    };
    for _ in 0..N {
        let c = rng.f(-1.0, 1.0);
        let (n1, n2) = (rng.f(1.0, 3.0), rng.f(1.0, 3.0));
        check(&mut ch, c, n1, n2, "random soft");
        let (n1, n2) = (rng.log(1e-3, 100.0), rng.log(1e-3, 100.0));
        check(&mut ch, c, n1, n2, "random hard");
    }
    for k in 3..=7 {
        for n2 in [1.0f32, 1.0001, 1.33, 1.5, 2.42] {
            check(&mut ch, 10f32.powi(-k), 1.0, n2, "grazing");
            check(&mut ch, -(10f32.powi(-k)), n2, 1.0, "grazing inside");
        }
    }
    // Within 0.001°–0.1° of the critical angle, on both sides.
    for n in [1.33f64, 1.5, 2.42] {
        let crit = (1.0 / n).asin();
        for delta_deg in [0.001f64, 0.003, 0.01, 0.03, 0.1] {
            for side in [-1.0, 1.0] {
                let theta = crit + side * delta_deg.to_radians();
                check(
                    &mut ch,
                    -(theta.cos() as f32),
                    1.0,
                    n as f32,
                    "near critical",
                );
            }
        }
    }
    // Near an index match at grazing (peers' report: 1.5 | 1.5000001 at cos 1e-4 gave
    // R = 0.31889 where the 40-digit value is 0.37043): n2 one to eight f32 steps above or below
    // n1, at round and seeded cosines. cos²θt is about 2(n2 − n1)/n1 + cos², which the node
    // forms without rounding n1/n2, so only ABS + REL is allowed, with no critical-angle term.
    let mut near = Check::new("fresnel_dielectric near an index match");
    for n1 in [1.0f32, 1.33, 1.5, 2.42] {
        for steps in [1i32, 2, 8, -1, -8] {
            let n2 = f32::from_bits((n1.to_bits() as i32 + steps) as u32);
            let mut cosines = vec![1e-4f32, 1e-3, 1e-2, 3e-4];
            cosines.extend((0..20).map(|_| rng.log(1e-5, 1e-1)));
            for c in cosines {
                let (r, t) = optics::fresnel_dielectric(c, n1, n2);
                let want = ref_fresnel(c as f64, n1 as f64, n2 as f64);
                near.near_tol(r, want, ABS, REL, || format!("R cos {c:e} n {n1} | {n2}"));
                near.near_tol(t, 1.0 - want, ABS, REL, || {
                    format!("T cos {c:e} n {n1} | {n2}")
                });
            }
        }
    }
    near.finish();
    ch.finish();
    // The audit's reproducers through the node: index match near grazing, T at grazing.
    let o = eval(
        "fresnel_dielectric",
        json!({"cos_theta": 0.0001, "ior_inside": 1.0}),
    );
    assert_eq!(o["reflectance"][0], 0.0, "index match: nothing reflects");
    // The peers' reproducer: 0.3704348430634738 in f64 from the f32 inputs (the formula above,
    // through (n2 − n1)(n2 + n1) in f64).
    let o = eval(
        "fresnel_dielectric",
        json!({"cos_theta": 0.0001, "ior_outside": 1.5, "ior_inside": 1.5000001}),
    );
    let r = o["reflectance"][0] as f64;
    assert!((r - 0.3704348430634738).abs() < 1e-6, "R = {r}");
    let o = eval("fresnel_dielectric", json!({"cos_theta": 1e-7}));
    let want_t = 1.0 - ref_fresnel(1e-7f32 as f64, 1.0, 1.5);
    let t = o["transmittance"][0] as f64;
    assert!(
        (t - want_t).abs() <= 1e-5 * want_t,
        "T = {t:e}, want {want_t:e}"
    );
}

#[test]
fn refract_and_reflect_pointwise() {
    let mut ch = Check::new("refract");
    let mut rf = Check::new("reflect");
    let mut rng = Rng(2);
    let n = Vec3::Z;
    let check = |ch: &mut Check, i: Vec3, eta: f32, why: &str| {
        let (t, tir) = optics::refract(i, n, eta);
        let (want, want_tir) = ref_refract(d3(i), d3(n), eta as f64);
        let tol = ABS + critical_term(ref_refract_dk(d3(i), d3(n), eta as f64), eta as f64);
        for (k, (&got, &w)) in t.to_array().iter().zip(&want).enumerate() {
            ch.near_tol(got, w, tol, REL, || format!("{why}: i {i} eta {eta} [{k}]"));
        }
        // TIR may flip only where k is within rounding of 0.
        let c = i.z as f64;
        let kk = 1.0 - (eta as f64).powi(2) * (1.0 - c * c);
        assert!(
            tir == want_tir || kk.abs() < 1e-6,
            "{why}: tir {tir} at i {i} eta {eta}"
        );
    };
    for _ in 0..N {
        let i = -rng.up();
        check(&mut ch, i, rng.f(0.2, 3.0), "random");
        let r = optics::reflect(i, n);
        let want = add(d3(i), scale(d3(n), -2.0 * dot(d3(n), d3(i))));
        for (k, (&got, &w)) in r.to_array().iter().zip(&want).enumerate() {
            rf.near(got, w, || format!("reflect i {i} [{k}]"));
        }
    }
    for k in 3..=7 {
        let i = Vec3::new(1.0, 0.0, -(10f32.powi(-k)));
        for eta in [1.0f32, 1.0 / 1.33, 1.0 / 1.5] {
            check(&mut ch, i, eta, "grazing");
        }
    }
    ch.finish();
    rf.finish();
    // The audit's reproducer: at eta = 1 a grazing ray passes straight.
    let o = eval("refract", json!({"i": [1.0, 0.0, -1e-4], "eta": 1.0}));
    assert_eq!(
        o["t"],
        vec![1.0, 0.0, -1e-4],
        "eta = 1 leaves the ray unchanged"
    );
}

#[test]
fn schlick_empirical_and_conversions_pointwise() {
    let mut rng = Rng(3);
    let mut s = Check::new("fresnel_schlick");
    let mut e = Check::new("fresnel_empirical");
    let mut conv = Check::new("ior_to_f0 / f0_to_ior / f0_to_specular / specular_to_f0");
    for _ in 0..N {
        let (c, f0) = (rng.f(0.0, 1.0), rng.f(0.0, 1.0));
        let want = f0 as f64 + (1.0 - f0 as f64) * (1.0 - c as f64).powi(5);
        s.near(optics::fresnel_schlick(c, f0), want, || {
            format!("cos {c} f0 {f0}")
        });
        let (idn, bias, sc, p) = (
            rng.f(-1.0, 0.0),
            rng.f(0.0, 1.0),
            rng.f(0.0, 2.0),
            rng.f(0.5, 8.0),
        );
        let want = (bias as f64 + sc as f64 * (1.0 + idn as f64).powf(p as f64)).clamp(0.0, 1.0);
        e.near(optics::fresnel_empirical(idn, bias, sc, p), want, || {
            format!("i·n {idn} bias {bias} scale {sc} power {p}")
        });
        let (n1, n2) = (rng.log(1e-3, 100.0), rng.log(1e-3, 100.0));
        let want = ((n1 as f64 - n2 as f64) / (n1 as f64 + n2 as f64)).powi(2);
        conv.near(optics::ior_to_f0(n1, n2), want, || {
            format!("ior_to_f0 {n1} {n2}")
        });
        let f = rng.f(0.0, 1.0);
        conv.near(optics::f0_to_ior(f), ref_f0_to_ior(f as f64), || {
            format!("f0_to_ior {f}")
        });
        conv.near(optics::f0_to_specular(f), f as f64 / 0.08, || {
            format!("f0_to_specular {f}")
        });
        let sp = rng.f(0.0, 12.5);
        conv.near(optics::specular_to_f0(sp), 0.08 * sp as f64, || {
            format!("specular_to_f0 {sp}")
        });
    }
    // Near a mirror: 1 − f0 down to one ulp.
    for k in 1..=24 {
        let f = 1.0 - 2f32.powi(-k);
        conv.near(optics::f0_to_ior(f), ref_f0_to_ior(f as f64), || {
            format!("f0_to_ior 1 − 2^-{k}")
        });
    }
    // The audit's reproducer, and the documented mirror.
    let o = eval("f0_to_ior", json!({"f0": 0.99999}));
    let want = ref_f0_to_ior(0.99999f32 as f64);
    assert!(
        (o["ior"][0] as f64 / want - 1.0).abs() < 1e-5,
        "{} vs {want}",
        o["ior"][0]
    );
    // Documented: a mirror gives 2^40 = 1099511627776, whose normal reflectance
    // ((n − 1)/(n + 1))² = 1 − 2^-38 is 1 in f32.
    assert_eq!(
        optics::f0_to_ior(1.0),
        1_099_511_627_776.0,
        "documented: a mirror gives 2^40"
    );
    let n = 1_099_511_627_776.0f64;
    assert_eq!((((n - 1.0) / (n + 1.0)).powi(2)) as f32, 1.0);
    // Documented: below the surface Schlick is taken at grazing, F = 1.
    for c in [-1.0f32, -0.5, -1e-7] {
        assert_eq!(optics::fresnel_schlick(c, 0.04f32), 1.0, "cos {c}");
    }
    s.finish();
    e.finish();
    conv.finish();
}

#[test]
fn hg_phase_pointwise_for_every_g_below_one() {
    let mut ch = Check::new("hg_phase");
    let mut rng = Rng(4);
    for _ in 0..N {
        let (c, g) = (rng.f(-1.0, 1.0), rng.f(-1.0, 1.0));
        if g.abs() < 1.0 {
            ch.near_tol(
                optics::hg_phase(c, g),
                ref_hg(c as f64, g as f64),
                0.0,
                REL,
                || format!("cos {c} g {g}"),
            );
        }
    }
    for k in 1..=24 {
        let h = 1.0 - 2f32.powi(-k);
        for g in [h, -h] {
            for c in [1.0f32, -1.0, 0.99999, -0.99999, 0.5, -0.2655, 0.0] {
                let c = c * g.signum();
                ch.near_tol(
                    optics::hg_phase(c, g),
                    ref_hg(c as f64, g as f64),
                    0.0,
                    REL,
                    || format!("g = ±(1 − 2^-{k}) = {g}, cos {c}"),
                );
                let c2 = -c;
                ch.near_tol(
                    optics::hg_phase(c2, g),
                    ref_hg(c2 as f64, g as f64),
                    0.0,
                    REL,
                    || format!("g = ±(1 − 2^-{k}) = {g}, cos {c2}"),
                );
            }
        }
    }
    ch.finish();
    // The audit's reproducers through the node.
    let g = 1.0 - 2f32.powi(-17);
    let o = eval("hg_phase", json!({"cos_theta": 1.0, "g": g}));
    let want = ref_hg(1.0, g as f64);
    assert!(
        (o["phase"][0] as f64 / want - 1.0).abs() < 1e-5,
        "{} vs {want}",
        o["phase"][0]
    );
    let g = -(1.0 - 2f32.powi(-20));
    let o = eval("hg_phase", json!({"cos_theta": -0.2655, "g": g}));
    let want = ref_hg(-0.2655f32 as f64, g as f64);
    assert!(
        (o["phase"][0] as f64 / want - 1.0).abs() < 1e-5,
        "{} vs {want}",
        o["phase"][0]
    );
    // Documented: |g| = 1 is evaluated at |g| = 1 − 2⁻²⁴.
    let h = optics::HG_G_MAX as f64;
    assert_eq!(h, 1.0 - 2f64.powi(-24));
    let p = optics::hg_phase(1.0, 1.0) as f64;
    assert!((p / ref_hg(1.0, h) - 1.0).abs() < 1e-5, "g = 1: {p:e}");
}

// ------------------------------------------------------------------------------------------
// PBR
// ------------------------------------------------------------------------------------------

#[test]
fn ggx_smith_and_f0_pointwise() {
    let mut d = Check::new("pbr_ggx_d");
    let mut v = Check::new("pbr_smith_visibility");
    let mut f = Check::new("pbr_f0");
    let mut rng = Rng(5);
    for i in 0..N {
        let r = if i % 2 == 0 {
            rng.f(0.02, 1.0)
        } else {
            rng.f(0.02, 0.05)
        };
        let c = if i % 3 == 0 {
            1.0 - rng.log(1e-7, 1e-2)
        } else {
            rng.f(-1.0, 1.0)
        };
        d.near(pbr::ggx_d(c, r), ref_ggx(c as f64, r as f64), || {
            format!("n·h {c} roughness {r}")
        });
        let (nv, nl) = (rng.f(-1.0, 1.0), rng.log(1e-7, 1.0));
        v.near(
            pbr::smith_visibility(nv, nl, r),
            ref_smith(nv as f64, nl as f64, r as f64),
            || format!("n·v {nv} n·l {nl} roughness {r}"),
        );
        let (m, b, s) = (rng.f(0.0, 1.0), rng.f(0.0, 1.0), rng.f(0.0, 12.5));
        let want = 0.08 * s as f64 * (1.0 - m as f64) + b as f64 * m as f64;
        f.near(pbr::f0(m, Vec3::splat(b), s).x, want, || {
            format!("metallic {m} base {b} specular {s}")
        });
    }
    // Documented: roughness below 0.02 is shaded as 0.02.
    assert_eq!(pbr::ggx_d(1.0, 0.0), pbr::ggx_d(1.0, pbr::MIN_ROUGHNESS));
    d.finish();
    v.finish();
    f.finish();
}

/// The conditioning limit the node's doc states (docs/models/pbr.md "Numerics"): normalising
/// V and L in f32 perturbs L + V by ~3u√2 (u = 2⁻²⁴), turning H by 2.5e-7/|L + V| rad, and
/// |d ln D/dθh| = 4 sin θh cos θh (1 − α²)/(sin²θh + cos²θh α²) ≤ 2/α: a relative error of
/// up to 5e-7/(α |L + V|) in the specular term.
fn brdf_direction_limit(roughness: f32, v: Vec3, l: Vec3) -> f64 {
    let a = (roughness.max(pbr::MIN_ROUGHNESS) as f64).powi(2);
    let sum = dot(add(unit(d3(v)), unit(d3(l))), add(unit(d3(v)), unit(d3(l)))).sqrt();
    5e-7 / (a * sum)
}

/// The rounding bound of an f32 dot product of 3-vectors, γ₃ Σ|aᵢbᵢ| (Higham, *Accuracy and
/// Stability of Numerical Algorithms*, §3.1).
fn dot_rounding(a: Vec3, b: Vec3) -> f64 {
    let u = f32::EPSILON as f64 / 2.0;
    3.0 * u / (1.0 - 3.0 * u)
        * (0..3)
            .map(|k| (a[k] as f64 * b[k] as f64).abs())
            .sum::<f64>()
}

/// |d ln p / d cosθ| of Henyey–Greenstein: 3g / (1 + g² − 2g cosθ).
fn hg_log_slope(c: f64, g: f64) -> f64 {
    let base = if g >= 0.0 {
        (1.0 - g).powi(2) + 2.0 * g * (1.0 - c)
    } else {
        (1.0 + g).powi(2) - 2.0 * g * (1.0 + c)
    };
    (3.0 * g / base).abs()
}

#[test]
fn brdf_pointwise() {
    let mut ch = Check::new("pbr_brdf");
    let mut rng = Rng(6);
    let n = Vec3::Z;
    let check = |ch: &mut Check,
                 v: Vec3,
                 l: Vec3,
                 base: Vec3,
                 m: f32,
                 r: f32,
                 s: f32,
                 mode: i32| {
        let (total, diffuse, spec) = pbr::brdf(n, v, l, base, m, r, s, mode);
        for k in 0..3 {
            let (wd, ws) = ref_brdf(
                d3(n),
                d3(v),
                d3(l),
                d3(base),
                m as f64,
                r as f64,
                s as f64,
                mode == 1,
                k,
            );
            let at = || {
                format!(
                    "v {v} l {l} base {base} metallic {m} roughness {r} specular {s} fresnel {mode} [{k}]"
                )
            };
            ch.near(diffuse.to_array()[k], wd, at);
            let rel = REL + brdf_direction_limit(r, v, l);
            ch.near_tol(spec.to_array()[k], ws, ABS, rel, at);
            ch.near_tol(total.to_array()[k], wd + ws, ABS, rel, at);
        }
    };
    for i in 0..N / 4 {
        let (v, l) = (rng.up(), rng.up());
        let base = Vec3::new(rng.f(0.0, 1.0), rng.f(0.0, 1.0), rng.f(0.0, 1.0));
        let r = if i % 2 == 0 {
            rng.f(0.02, 1.0)
        } else {
            rng.f(0.02, 0.05)
        };
        let (m, s) = (rng.f(0.0, 1.0), rng.f(0.0, 1.0));
        check(&mut ch, v, l, base, m, r, s, (i % 2) as i32);
    }
    // Near the peak at low roughness: L the mirror image of V about N, slightly perturbed.
    for i in 0..2000 {
        let v = rng.up();
        let l = Vec3::new(-v.x + rng.f(-1e-3, 1e-3), -v.y + rng.f(-1e-3, 1e-3), v.z);
        let r = rng.f(0.02, 0.05);
        check(&mut ch, v, l, Vec3::ONE, 1.0, r, 0.5, i % 2);
    }
    // The audit's reproducer: +120% before |N × H|² replaced 1 − (N·H)².
    let v = Vec3::new(-0.645_648_4, -0.691_011_6, 0.325_024_9);
    let l = Vec3::new(0.646_429_5, 0.691_630_5, 0.325_024_9);
    check(&mut ch, v, l, Vec3::ONE, 1.0, 0.02, 0.5, 0);
    let (_, _, spec) = pbr::brdf(n, v, l, Vec3::ONE, 1.0, 0.02, 0.5, 0);
    let (_, want) = ref_brdf(d3(n), d3(v), d3(l), [1.0; 3], 1.0, 0.02, 0.5, false, 0);
    eprintln!(
        "[pbr_brdf] audit reproducer: {} vs f64 {want} ({:.2e} relative)",
        spec.x,
        spec.x as f64 / want - 1.0
    );
    ch.finish();
}

// ------------------------------------------------------------------------------------------
// Skin
// ------------------------------------------------------------------------------------------

#[test]
fn efresnel_pointwise() {
    let mut ch = Check::new("skin_efresnel");
    let mut rng = Rng(7);
    let n = Vec3::Z;
    let check = |ch: &mut Check, i: Vec3, eta: f32| {
        let (kr, kt, t) = skin::skin_efresnel(i, n, eta);
        let nf = if i.z > 0.0 {
            [0.0, 0.0, -1.0]
        } else {
            [0.0, 0.0, 1.0]
        };
        let c = (-dot(nf, d3(i))).clamp(0.0, 1.0);
        let (want_t, tir) = ref_refract(d3(i), nf, eta as f64);
        let x = (ref_fresnel(c, eta as f64, 1.0) / 0.5).clamp(0.0, 1.0);
        let want_kr = if tir { 1.0 } else { x * x * (3.0 - 2.0 * x) };
        // smoothstep(0, 0.5, R) has slope at most 3 in R.
        let tol_r = ABS + 3.0 * critical_term(ref_fresnel_dk(c, eta as f64, 1.0), eta as f64);
        let tol_t = ABS + critical_term(ref_refract_dk(d3(i), nf, eta as f64), eta as f64);
        ch.near_tol(kr, want_kr, tol_r, REL, || format!("kr i {i} eta {eta}"));
        ch.near_tol(kt, 1.0 - want_kr, tol_r, REL, || {
            format!("kt i {i} eta {eta}")
        });
        for (k, (&got, &w)) in t.to_array().iter().zip(&want_t).enumerate() {
            ch.near_tol(got, w, tol_t, REL, || format!("t i {i} eta {eta} [{k}]"));
        }
    };
    for _ in 0..N {
        let i = -rng.up();
        check(&mut ch, i, rng.f(0.3, 2.0));
    }
    for k in 3..=7 {
        check(&mut ch, Vec3::new(1.0, 0.0, -(10f32.powi(-k))), 1.0);
        check(&mut ch, Vec3::new(1.0, 0.0, -(10f32.powi(-k))), 1.0 / 1.4);
    }
    ch.finish();
    // The audit's reproducer: at eta 1 nothing reflects, beside a non-TIR t.
    let o = eval(
        "skin_efresnel",
        json!({"i": [1.0, 0.0, -1e-4], "eta_i_over_t": 1.0}),
    );
    assert_eq!(o["kr"][0], 0.0);
}

#[test]
fn single_multiple_scattering_and_sebum_pointwise() {
    let mut ss = Check::new("skin_single_scattering");
    let mut ms = Check::new("skin_multiple_scattering");
    let mut sb = Check::new("skin_sebum");
    let mut rng = Rng(8);
    let n = Vec3::Z;
    for i in 0..N {
        let tl = -rng.up();
        let tv = -rng.up();
        let g = rng.f(-0.99, 0.99);
        let d = if i % 3 == 0 {
            rng.log(1e-8, 1e6)
        } else {
            rng.f(0.0, 10.0)
        };
        let albedo = rng.f(0.0, 1.0);
        let (f, fw) = skin::skin_single_scattering(tl, tv, n, g, Vec3::splat(albedo), d, 0, false);
        let (mi, mo) = (
            (tl.z as f64).abs().max(1e-20),
            (tv.z as f64).abs().max(1e-20),
        );
        let cos = -dot(d3(tl), d3(tv));
        let want = albedo as f64 * ref_hk(cos, g as f64, mi, mo, d as f64);
        // The doc's stated limit: the phase angle's cosine is an f32 dot product, whose
        // rounding the phase function's slope amplifies near a strong peak.
        let rel = |g: f64| REL + hg_log_slope(cos, g) * dot_rounding(tl, tv);
        ss.near_tol(f.x, want, ABS, rel(g as f64), || {
            format!("t_l {tl} t_v {tv} g {g} d {d:e}")
        });
        ss.near_tol(fw.x, want * mi, ABS, rel(g as f64), || {
            format!("f·mu_i t_l {tl} t_v {tv} g {g} d {d:e}")
        });
        // Pharr's three lobes.
        let (f3, _) = skin::skin_single_scattering(tl, tv, n, g, Vec3::ONE, d, 1, true);
        let want3: f64 = [(0.8, 0.8), (0.3, 0.5), (0.0, 0.4)]
            .iter()
            .map(|&(gk, ak): &(f64, f64)| {
                ak * 4.0 * PI * ref_hk(cos, gk as f32 as f64, mi, mo, d as f64)
            })
            .sum();
        ss.near_tol(f3.x, want3, ABS, rel(0.8), || {
            format!("three lobes t_l {tl} t_v {tv} d {d:e}")
        });
        let (cd, ims, lc, idn) = (
            rng.f(0.0, 1.0),
            rng.f(0.0, 2.0),
            rng.f(0.01, 2.0),
            rng.f(-1.0, 1.0),
        );
        let want = cd as f64 * ims as f64 / ((idn as f64).abs() + lc as f64);
        ms.near(
            skin::skin_multiple_scattering(Vec3::splat(cd), ims, lc, idn).x,
            want,
            || format!("C_d {cd} I_ms {ims} l_c {lc} i·n {idn}"),
        );
        let (spec, p) = (
            rng.f(0.0, 100.0),
            if i % 2 == 0 {
                rng.f(1.0, 200.0)
            } else {
                rng.f(1600.0, 10000.0)
            },
        );
        let rv = if i % 2 == 0 {
            rng.f(-1.0, 1.0)
        } else {
            1.0 - rng.log(1e-7, 1e-3)
        };
        let want = spec as f64 * (rv as f64).max(0.0).powf(p as f64);
        sb.near(skin::skin_sebum(spec, p, rv), want, || {
            format!("spec {spec} power {p} r·v {rv}")
        });
    }
    // Grazing inside the layer, down to cosines of 1e-7 (the 1e-4 floor cost −90% at 1e-5).
    for k in 3..=7 {
        let c = 10f32.powi(-k);
        let tl = Vec3::new(1.0, 0.0, -c);
        let tv = Vec3::new(0.0, 0.6, -0.8);
        let (f, _) = skin::skin_single_scattering(tl, tv, n, 0.8, Vec3::ONE, 0.5, 0, false);
        let want = ref_hk(
            -dot(d3(tl), d3(tv)),
            0.8f32 as f64,
            c as f64,
            0.8f32 as f64,
            0.5,
        );
        ss.near(f.x, want, || format!("grazing mu {c:e}"));
    }
    ss.finish();
    ms.finish();
    sb.finish();
}

#[test]
fn dipole_pointwise() {
    let mut tot = Check::new("dipole_rd_total");
    let mut prof = Check::new("dipole_rd_profile");
    let mut rng = Rng(9);
    for i in 0..N {
        let s_s = rng.log(1e-3, 1000.0);
        let s_a = if i % 3 == 0 {
            rng.log(1e-9, 1e-3)
        } else {
            rng.log(1e-3, 1000.0)
        };
        let eta = rng.f(1.0, 3.0);
        let rd = skin::dipole_rd_total(Vec3::splat(s_s), Vec3::splat(s_a), eta);
        tot.near(
            rd.x,
            ref_rd_total(s_s as f64, s_a as f64, eta as f64),
            || format!("σs' {s_s:e} σa {s_a:e} η {eta}"),
        );
        let r = if i % 2 == 0 {
            rng.f(0.0, 10.0)
        } else {
            rng.log(1e-4, 1e4)
        };
        let p = skin::dipole_rd_profile(r, Vec3::splat(s_s), Vec3::splat(s_a), eta);
        let want = ref_rd_profile(r as f64, s_s as f64, s_a as f64, eta as f64);
        // The profile spans 1e-30 … 1e8 per mm²: relative bound, with an absolute floor far
        // below its scale.
        prof.near_tol(p.x, want, 1e-30, REL, || {
            format!("r {r:e} σs' {s_s:e} σa {s_a:e} η {eta}")
        });
    }
    // The audit's reproducers: low absorption, and a thin non-absorbing medium.
    let rd = skin::dipole_rd_total(Vec3::ONE, Vec3::new(3e-8, 1e-7, 1e-6), 1.3);
    for (k, s_a) in [3e-8f32, 1e-7, 1e-6].into_iter().enumerate() {
        tot.near(
            rd.to_array()[k],
            ref_rd_total(1.0, s_a as f64, 1.3f32 as f64),
            || format!("low absorption σa {s_a:e}"),
        );
    }
    let rd = skin::dipole_rd_total(Vec3::new(1e-7, 5e-7, 1e-6), Vec3::ZERO, 1.3);
    for k in 0..3 {
        tot.near(rd.to_array()[k], 1.0, || {
            format!("thin, no absorption [{k}]")
        });
    }
    // Very thin media: no clamp on σt'.
    for s_t in [1e-7f32, 1e-12, 1e-20] {
        let p = skin::dipole_rd_profile(1.0, Vec3::splat(s_t), Vec3::splat(s_t), 1.3);
        let want = ref_rd_profile(1.0, s_t as f64, s_t as f64, 1.3f32 as f64);
        prof.near_tol(p.x, want, 1e-38, REL, || format!("thin medium σ {s_t:e}"));
    }
    tot.finish();
    prof.finish();
}
