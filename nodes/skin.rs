//! Skin (seed 001, docs/models/skin.md): the paper's three-layer shader
//! (Phong sebum, faked multiple scattering of the epidermis, Hanrahan–Krueger single
//! scattering of the dermis behind Pharr's `efresnel`), and Jensen et al. 2001's dipole
//! diffusion as the physically based reference.
//!
//! Conventions: `i` is the incident direction pointing *towards* the surface, `n` the unit
//! normal. The Fresnel input is `eta_i_over_t = n_incident / n_transmitted` (RenderMan/GLSL,
//! 1/1.4 for light entering skin); the dipole takes `ior`, the medium's index relative to the
//! outside (Jensen's η, 1.3 for skin) — erratum 4.
//!
//! Errata of the paper's printed code, kept as functions so the tests can show them:
//! [`hg_phase_printed`] (erratum 1) and [`fresnel_printed`] (erratum 2).

use crate::node::{Category, In, NodeType, Out, WgslChoice};
use crate::precision::{exp, pow, sqrt};
use crate::value::Value;
use glam::Vec3;
use std::f32::consts::PI;

use super::optics::{fresnel_dielectric, hg_phase, refract};

/// Smallest cosine used inside the layer: directions within 1e-20 of the horizon are taken
/// at it. It keeps `1/μ` finite; the BRDF there is at most `albedo · p · 5e19` and `f · μ_i`
/// stays ≤ `albedo · p`. Only cosines below 1e-20 move (by less than 1e-20 absolute).
pub const MU_MIN: f32 = 1e-20;

/// Pharr's three lobes `(g, albedo)` of his skin shader (Pharr 2001, "Layered media for
/// surface shaders", skin example).
pub const PHARR_LOBES: [(f32, f32); 3] = [(0.8, 0.8), (0.3, 0.5), (0.0, 0.4)];

/// `1 − exp(−x)` without cancellation for small `x` (`−expm1(−x)`).
#[inline]
pub fn one_minus_exp_neg(x: f32) -> f32 {
    -(-x).exp_m1()
}

/// The paper's printed Henyey–Greenstein phase (erratum 1): denominator
/// `pow(1 − g² − 2g cos, 1.5)`. Negative base — NaN — for `cos > (1 − g²)/(2g)`, 0.225 at g = 0.8.
/// Kept for the erratum test only; use [`hg_phase`].
pub fn hg_phase_printed(cos_theta: f32, g: f32) -> f32 {
    (1.0 - g * g) / (4.0 * PI * pow(1.0 - g * g - 2.0 * g * cos_theta, 1.5))
}

/// The paper's printed Fresnel (erratum 2): `rParallel`'s numerator equals its denominator
/// (always 1) and `Kr = (rPar² − rPerp²)/2` takes the difference. `eta = n_i / n_t`.
/// At normal incidence from air into eta 1.4 it gives ≈ 0.486 instead of 0.0278.
/// Kept for the erratum test only; use [`skin_efresnel`].
#[allow(clippy::eq_op)] // the printed form's equal numerator and denominator is the erratum
pub fn fresnel_printed(cos_i: f32, eta_i_over_t: f32) -> f32 {
    let e = 1.0 / eta_i_over_t; // n_t / n_i
    let cos_t = sqrt((1.0 - (1.0 - cos_i * cos_i) / (e * e)).max(0.0));
    let r_par = (e * cos_i + cos_t) / (e * cos_i + cos_t);
    let r_perp = (cos_i - e * cos_t) / (cos_i + e * cos_t);
    0.5 * (r_par * r_par - r_perp * r_perp)
}

/// Pharr's `efresnel`: exact Fresnel at the boundary with `Kr = smoothstep(0, 0.5, Kr)`,
/// `Kt = 1 − Kr`, and the refracted direction.
///
/// The normal is turned to face the incident direction first (RenderMan `faceforward`), so
/// light arriving from behind is treated as arriving on the incident side. Under total
/// internal reflection `kr = 1`, `kt = 0` and `t` is the reflected direction.
/// Source: Pharr 2001, "Layered media for surface shaders" (SIGGRAPH course 48), `efresnel`;
/// Fresnel as [`fresnel_dielectric`] (Hecht §4.6).
pub fn skin_efresnel(i: Vec3, n: Vec3, eta_i_over_t: f32) -> (f32, f32, Vec3) {
    let nf = if n.dot(i) > 0.0 { -n } else { n };
    let cos = (-nf.dot(i)).clamp(0.0, 1.0);
    let (r, _) = fresnel_dielectric(cos, eta_i_over_t, 1.0);
    let (t, tir) = refract(i, nf, eta_i_over_t);
    let x = (r / 0.5).clamp(0.0, 1.0);
    let kr = if tir { 1.0 } else { x * x * (3.0 - 2.0 * x) };
    (kr, 1.0 - kr, t)
}

/// One Hanrahan–Krueger single-scattering lobe with `mu_i`, `mu_o` already clamped:
/// `albedo · p(cos) / (mu_i + mu_o) · (1 − exp(−d (1/mu_i + 1/mu_o)))`.
#[inline]
fn hk_lobe(cos: f32, g: f32, mu_i: f32, mu_o: f32, d: f32, pharr: bool) -> f32 {
    let p = hg_phase(cos, g) * if pharr { 4.0 * PI } else { 1.0 };
    p / (mu_i + mu_o) * one_minus_exp_neg(d * (1.0 / mu_i + 1.0 / mu_o))
}

/// Hanrahan–Krueger single scattering in a layer of optical thickness `d`, on the refracted
/// directions: `f = albedo p(w_i, w_o) / (mu_i + mu_o) (1 − exp(−d (1/mu_i + 1/mu_o)))`.
///
/// `t_light` is the refracted light's propagation direction (into the layer), `t_view` the
/// refracted view ray (from the eye, into the layer); the phase angle is between the
/// propagation directions `t_light` and `−t_view`. `mu = max(|t·n|, `[`MU_MIN`]`)`. `phase_form` 0 is
/// the normalised HG, 1 Pharr's form without `1/(4π)` (erratum 3). `three_lobe` sums Pharr's
/// lobes (g, a) = (0.8, 0.8), (0.3, 0.5), (0, 0.4), each scaled by `albedo`, instead of `g`.
/// Returns the BRDF `f` (symmetric in the two directions) and `f · mu_i`, the factor that
/// multiplies the transmitted irradiance-free radiance (bounded by `albedo · p`).
/// Source: Hanrahan & Krueger 1993, eq. 21 (single scattering from a layer); Pharr 2001.
#[allow(clippy::too_many_arguments)]
pub fn skin_single_scattering(
    t_light: Vec3,
    t_view: Vec3,
    n: Vec3,
    g: f32,
    albedo: Vec3,
    thickness: f32,
    phase_form: i32,
    three_lobe: bool,
) -> (Vec3, Vec3) {
    let mu_i = t_light.dot(n).abs().max(MU_MIN);
    let mu_o = t_view.dot(n).abs().max(MU_MIN);
    let cos = -t_light.dot(t_view);
    let d = thickness.max(0.0);
    let pharr = phase_form == 1;
    let s = if three_lobe {
        let mut s = 0.0;
        for (gk, ak) in PHARR_LOBES {
            s += ak * hk_lobe(cos, gk, mu_i, mu_o, d, pharr);
        }
        s
    } else {
        hk_lobe(cos, g, mu_i, mu_o, d, pharr)
    };
    let f = albedo * s;
    (f, f * mu_i)
}

/// The paper's faked multiple scattering of the epidermis: `C_d · I_ms / (|I·N| + l_c)`
/// (denominator kept ≥ 1e-4, which changes the result only where `|I·N| + l_c < 1e-4`, i.e.
/// with a clamp coefficient l_c below 1e-4 at grazing). Source: the paper (seed 001), epidermis
/// layer; docs/models/skin.md.
pub fn skin_multiple_scattering(diffusion_color: Vec3, i_ms: f32, l_c: f32, i_dot_n: f32) -> Vec3 {
    diffusion_color * (i_ms / (i_dot_n.abs() + l_c).max(MS_DENOMINATOR_MIN))
}

/// The smallest denominator `|I·N| + l_c` of [`skin_multiple_scattering`].
pub const MS_DENOMINATOR_MIN: f32 = 1e-4;

/// Phong sebum: `specularity · max(R_L·V, 0)^power`, `0^power` spelled out.
/// Source: the paper (seed 001), sebum layer; Phong 1975.
pub fn skin_sebum(specularity: f32, power: f32, r_dot_v: f32) -> f32 {
    let b = r_dot_v.clamp(0.0, 1.0);
    let p = if b == 0.0 {
        if power == 0.0 { 1.0 } else { 0.0 }
    } else if b < 0.5 {
        pow(b, power)
    } else {
        // The WGSL takes its own ln series here, not WGSL's pow (SEBUM_WGSL).
        b.powf(power)
    };
    specularity * p
}

/// Jensen's `Fdr = −1.440/η² + 0.710/η + 0.668 + 0.0636 η` (Jensen et al. 2001, eq. 18 area).
#[inline]
/// `ior` is clamped to [1, 3], where `Fdr < 1`.
pub fn fdr(ior: f32) -> f32 {
    let ior = ior.clamp(1.0, 3.0);
    -1.440 / (ior * ior) + 0.710 / ior + 0.668 + 0.0636 * ior
}

/// The reduced albedo `α' = σs'/σt'` and `1 − α' = σa/σt'` (written so, not as `1 − α'`,
/// which loses σa when it is tiny), with `σt' = σs' + σa`; `(0, 1)` for an empty medium.
#[inline]
fn reduced_albedo(s_s: f32, s_a: f32) -> (f32, f32) {
    let (s_s, s_a) = (s_s.max(0.0), s_a.max(0.0));
    let s_t = s_s + s_a;
    if s_t > 0.0 {
        (s_s / s_t, s_a / s_t)
    } else {
        (0.0, 1.0)
    }
}

#[inline]
fn dipole_total_1(s_s: f32, s_a: f32, a_coef: f32) -> f32 {
    let (alpha, one_minus_alpha) = reduced_albedo(s_s, s_a);
    let s = sqrt(3.0 * one_minus_alpha);
    0.5 * alpha * (1.0 + exp(-(4.0 / 3.0) * a_coef * s)) * exp(-s)
}

/// Jensen et al. 2001 total diffuse reflectance of the dipole (eq. 5 integrated, as in §4.3):
/// `Rd = (α'/2)(1 + exp(−(4/3) A √(3(1 − α')))) exp(−√(3(1 − α')))`, `α' = σs'/(σs' + σa)`,
/// `A = (1 + Fdr)/(1 − Fdr)`. Per colour channel. Rd depends on α' alone; `1 − α'` is
/// computed as `σa/σt'`, so low absorption keeps its effect; an empty medium (σt' = 0) gives 0.
pub fn dipole_rd_total(sigma_s_prime: Vec3, sigma_a: Vec3, ior: f32) -> Vec3 {
    let f = fdr(ior);
    let a = (1.0 + f) / (1.0 - f);
    Vec3::new(
        dipole_total_1(sigma_s_prime.x, sigma_a.x, a),
        dipole_total_1(sigma_s_prime.y, sigma_a.y, a),
        dipole_total_1(sigma_s_prime.z, sigma_a.z, a),
    )
}

/// One source of the dipole: `z (σtr d + 1) e^{−σtr d} / d³`, written `(z/d)(σtr d + 1)
/// e^{−σtr d}/d²` so that it does not overflow for the depths of a thin medium (z ~ 1/σt').
#[inline]
fn dipole_source(z: f32, r: f32, s_tr: f32) -> f32 {
    // d = √(r² + z²) scaled by the larger term, so that z² cannot overflow.
    let (big, small) = (r.max(z), r.min(z));
    let q = small / big;
    let d = big * sqrt(1.0 + q * q);
    (z / d) * (s_tr * d + 1.0) * exp(-s_tr * d) / (d * d)
}

/// Below this σt' the dipole profile is 0: its true value, at most σt'²/(2π) ≈ 1.6e-61 per
/// mm², is below the smallest f32.
const DIPOLE_MIN_SIGMA_T: f32 = 1e-30;

#[inline]
fn dipole_profile_1(r: f32, s_s: f32, s_a: f32, a_coef: f32) -> f32 {
    let (s_s, s_a) = (s_s.max(0.0), s_a.max(0.0));
    let s_t = s_s + s_a;
    if s_t < DIPOLE_MIN_SIGMA_T {
        return 0.0;
    }
    let alpha = s_s / s_t;
    let s_tr = sqrt(3.0 * s_a * s_t);
    let z_r = 1.0 / s_t;
    let z_v = z_r * (1.0 + 4.0 / 3.0 * a_coef);
    alpha / (4.0 * PI) * (dipole_source(z_r, r, s_tr) + dipole_source(z_v, r, s_tr))
}

/// Jensen et al. 2001 dipole diffuse reflectance profile (eq. 4):
/// `Rd(r) = α'/(4π) [z_r (σtr d_r + 1) e^{−σtr d_r}/d_r³ + z_v (σtr d_v + 1) e^{−σtr d_v}/d_v³]`,
/// `σtr = √(3 σa σt')`, `z_r = 1/σt'`, `z_v = z_r (1 + 4A/3)`, `d = √(r² + z²)`. r in mm, σ in
/// 1/mm, result in 1/mm². Its integral `∫ 2πr Rd(r) dr` is [`dipole_rd_total`]. No clamp on
/// σt': an empty medium gives 0.
pub fn dipole_rd_profile(r: f32, sigma_s_prime: Vec3, sigma_a: Vec3, ior: f32) -> Vec3 {
    let f = fdr(ior);
    let a = (1.0 + f) / (1.0 - f);
    let r = r.abs();
    Vec3::new(
        dipole_profile_1(r, sigma_s_prime.x, sigma_a.x, a),
        dipole_profile_1(r, sigma_s_prime.y, sigma_a.y, a),
        dipole_profile_1(r, sigma_s_prime.z, sigma_a.z, a),
    )
}

/// WGSL of `1 − exp(−x)` for x ≥ 0: a Taylor series below 0.1 (error < 1e-10 relative),
/// `1 − exp(−x)` above (where f32 cancellation costs < 2e-6 relative). Matches `−expm1(−x)`.
const ONE_MINUS_EXP_WGSL: &str = r#"
fn skin_one_minus_exp_neg(x: f32) -> f32 {
    if (x < 0.1) {
        let y = -x;
        return -(y * (1.0 + y * (0.5 + y * (0.16666667 + y * (0.041666668 + y * (0.008333334 + y * 0.0013888889))))));
    }
    return 1.0 - exp(-x);
}
"#;

/// WGSL of [`hk_lobe`].
const HK_LOBE_WGSL: &str = r#"
fn skin_hk_lobe(cos_theta: f32, g: f32, mu_i: f32, mu_o: f32, d: f32, pharr: bool) -> f32 {
    let p = mg_hg(cos_theta, g) * select(1.0, 4.0 * 3.14159265358979, pharr);
    return p / (mu_i + mu_o) * skin_one_minus_exp_neg(d * (1.0 / mu_i + 1.0 / mu_o));
}
"#;

/// WGSL of [`skin_single_scattering`]'s lobes with `three_lobe` true: Pharr's three.
const LOBES_TRUE_WGSL: &str = r#"
fn skin_lobes_true(c: f32, g: f32, mu_i: f32, mu_o: f32, d: f32, pharr: bool, three_lobe: bool) -> f32 {
    var s = 0.0;
    s = s + 0.8 * skin_hk_lobe(c, 0.8, mu_i, mu_o, d, pharr);
    s = s + 0.5 * skin_hk_lobe(c, 0.3, mu_i, mu_o, d, pharr);
    s = s + 0.4 * skin_hk_lobe(c, 0.0, mu_i, mu_o, d, pharr);
    return s;
}
"#;

/// WGSL of [`skin_single_scattering`]'s lobes with `three_lobe` false: the one `g` lobe.
const LOBES_FALSE_WGSL: &str = r#"
fn skin_lobes_false(c: f32, g: f32, mu_i: f32, mu_o: f32, d: f32, pharr: bool, three_lobe: bool) -> f32 {
    return skin_hk_lobe(c, g, mu_i, mu_o, d, pharr);
}
"#;

/// WGSL of [`skin_single_scattering`]'s lobes, `three_lobe` chosen at run time.
const LOBES_WGSL: &str = r#"
fn skin_lobes(c: f32, g: f32, mu_i: f32, mu_o: f32, d: f32, pharr: bool, three_lobe: bool) -> f32 {
    if (three_lobe) {
        return skin_lobes_true(c, g, mu_i, mu_o, d, pharr, three_lobe);
    }
    return skin_lobes_false(c, g, mu_i, mu_o, d, pharr, three_lobe);
}
"#;

/// The lobe sets of a written `three_lobe`.
fn lobe_choices() -> [WgslChoice; 2] {
    [
        WgslChoice {
            choice: "true",
            helpers: &[LOBES_TRUE_WGSL],
            tables: &[],
        },
        WgslChoice {
            choice: "false",
            helpers: &[LOBES_FALSE_WGSL],
            tables: &[],
        },
    ]
}

/// WGSL of [`skin_single_scattering`].
const SINGLE_WGSL: &str = r#"
fn $fn(t_light: vec3<f32>, t_view: vec3<f32>, n: vec3<f32>, g: f32, albedo: vec3<f32>, thickness: f32, phase_form: i32, three_lobe: bool) -> $out {
    let mu_i = max(abs(dot(t_light, n)), 1e-20);
    let mu_o = max(abs(dot(t_view, n)), 1e-20);
    let c = -dot(t_light, t_view);
    let d = max(thickness, 0.0);
    let pharr = phase_form == 1;
    let s = skin_lobes${three_lobe}(c, g, mu_i, mu_o, d, pharr, three_lobe);
    let f = albedo * s;
    return $out(f, f * mu_i);
}
"#;

/// WGSL of [`skin_efresnel`].
const EFRESNEL_WGSL: &str = r#"
fn $fn(i: vec3<f32>, n: vec3<f32>, eta_i_over_t: f32) -> $out {
    let nf = select(n, -n, dot(n, i) > 0.0);
    let c = min(max(-dot(nf, i), 0.0), 1.0);
    let r = mg_opth_fresnel(c, eta_i_over_t, 1.0).x;
    let cn = dot(nf, i);
    let k = mg_opth_cos2_t(cn, eta_i_over_t);
    let x = min(max(r / 0.5, 0.0), 1.0);
    if (k < 0.0) {
        return $out(1.0, 0.0, i - 2.0 * cn * nf);
    }
    let kr = x * x * (3.0 - 2.0 * x);
    return $out(kr, 1.0 - kr, eta_i_over_t * i - (eta_i_over_t * cn + sqrt(k)) * nf);
}
"#;

/// WGSL of [`skin_multiple_scattering`].
const MULTIPLE_WGSL: &str = "fn $fn(diffusion_color: vec3<f32>, i_ms: f32, l_c: f32, i_dot_n: f32) -> vec3<f32> { return diffusion_color * (i_ms / max(abs(i_dot_n) + l_c, 1e-4)); }";

/// WGSL of [`skin_sebum`]. `b^power` is `exp(power · ln b)` with `ln b` from the series
/// `2 atanh((b − 1)/(b + 1))` for b ≥ 0.5 (truncation < 3e-10 relative): a GPU's `pow` takes
/// `log2` with an absolute error of up to 2⁻²¹ near 1, which a Phong exponent of 10⁴
/// multiplies into a 1e-2 relative error.
const SEBUM_WGSL: &str = r#"
fn skin_pow_unit(b: f32, p: f32) -> f32 {
    if (b < 0.5) {
        return pow(b, p);
    }
    let z = (b - 1.0) / (b + 1.0);
    let z2 = z * z;
    let series = 1.0 + z2 * (0.33333334 + z2 * (0.2 + z2 * (0.14285715 + z2 * (0.11111111 + z2 * (0.09090909 + z2 * (0.07692308 + z2 * (0.06666667 + z2 * (0.05882353 + z2 * 0.05263158))))))));
    return exp(p * (2.0 * z * series));
}
fn $fn(specularity: f32, power: f32, r_dot_v: f32) -> f32 {
    let b = min(max(r_dot_v, 0.0), 1.0);
    let p = select(skin_pow_unit(select(b, 1.0, b == 0.0), power), select(0.0, 1.0, power == 0.0), b == 0.0);
    return specularity * p;
}
"#;

/// WGSL helpers of the dipole: the same steps as the Rust above.
const DIPOLE_HELPERS_WGSL: &str = r#"
fn skin_dipole_a(ior0: f32) -> f32 {
    let ior = min(max(ior0, 1.0), 3.0);
    let f = -1.440 / (ior * ior) + 0.710 / ior + 0.668 + 0.0636 * ior;
    return (1.0 + f) / (1.0 - f);
}
fn skin_dipole_total_1(s_s0: f32, s_a0: f32, a_coef: f32) -> f32 {
    let s_s = max(s_s0, 0.0);
    let s_a = max(s_a0, 0.0);
    let s_t = s_s + s_a;
    if (s_t <= 0.0) {
        return 0.0;
    }
    let alpha = s_s / s_t;
    let s = sqrt(3.0 * (s_a / s_t));
    return 0.5 * alpha * (1.0 + exp(-(4.0 / 3.0) * a_coef * s)) * exp(-s);
}
fn skin_dipole_source(z: f32, r: f32, s_tr: f32) -> f32 {
    let big = max(r, z);
    let q = min(r, z) / big;
    let d = big * sqrt(1.0 + q * q);
    return (z / d) * (s_tr * d + 1.0) * exp(-s_tr * d) / (d * d);
}
fn skin_dipole_profile_1(r: f32, s_s0: f32, s_a0: f32, a_coef: f32) -> f32 {
    let s_s = max(s_s0, 0.0);
    let s_a = max(s_a0, 0.0);
    let s_t = s_s + s_a;
    if (s_t < 1e-30) {
        return 0.0;
    }
    let alpha = s_s / s_t;
    let s_tr = sqrt(3.0 * s_a * s_t);
    let z_r = 1.0 / s_t;
    let z_v = z_r * (1.0 + 4.0 / 3.0 * a_coef);
    return alpha / (4.0 * 3.14159265358979) * (skin_dipole_source(z_r, r, s_tr) + skin_dipole_source(z_v, r, s_tr));
}
"#;

const DIPOLE_TOTAL_WGSL: &str = r#"
fn $fn(sigma_s_prime: vec3<f32>, sigma_a: vec3<f32>, ior: f32) -> vec3<f32> {
    let a = skin_dipole_a(ior);
    return vec3<f32>(skin_dipole_total_1(sigma_s_prime.x, sigma_a.x, a), skin_dipole_total_1(sigma_s_prime.y, sigma_a.y, a), skin_dipole_total_1(sigma_s_prime.z, sigma_a.z, a));
}
"#;

const DIPOLE_PROFILE_WGSL: &str = r#"
fn $fn(r0: f32, sigma_s_prime: vec3<f32>, sigma_a: vec3<f32>, ior: f32) -> vec3<f32> {
    let a = skin_dipole_a(ior);
    let r = abs(r0);
    return vec3<f32>(skin_dipole_profile_1(r, sigma_s_prime.x, sigma_a.x, a), skin_dipole_profile_1(r, sigma_s_prime.y, sigma_a.y, a), skin_dipole_profile_1(r, sigma_s_prime.z, sigma_a.z, a));
}
"#;

/// The skin node types.
pub fn all() -> Vec<NodeType> {
    let f = Value::float;
    let v3 = Value::vec3;
    let c3 = Value::color;
    let skin1_s = [0.74, 0.88, 1.01];
    let skin1_a = [0.032, 0.17, 0.48];
    vec![
        NodeType::new("skin_efresnel", Category::Skin, "Pharr's efresnel: Fresnel with the smoothstep(0, 0.5) tweak and the refracted direction.")
            .source(
                "Kr = smoothstep(0, 0.5, R_exact), Kt = 1 − Kr (Pharr 2001, \"Layered media for surface \
                 shaders\", efresnel; docs/models/skin.md). eta_i_over_t = n_incident / n_transmitted \
                 (1/1.4 for light entering skin; erratum 4). The normal is turned to face i; under \
                 TIR kr = 1, kt = 0 and t is the reflected direction. The paper's printed Fresnel \
                 (erratum 2) is corrected.",
            )
            .input(In::vec3("i", [0.0, 0.0, -1.0]).range(-1.0, 1.0).doc("Incident direction, towards the surface (−L or −V)."))
            .input(In::vec3("n", [0.0, 0.0, 1.0]).range(-1.0, 1.0).doc("Unit surface normal."))
            .input(
                In::float("eta_i_over_t", 1.0 / 1.4)
                    .range(0.3, 2.0)
                    .hard(0.01, 100.0)
                    .doc("n_incident / n_transmitted: 1/1.4 from air into skin (not the pbrt reciprocal)."),
            )
            .output(Out::float("kr").doc("Reflected weight, smoothstep(0, 0.5, Fresnel R)."))
            .output(Out::float("kt").doc("Transmitted weight, 1 − kr."))
            .output(Out::vec3("t").doc("Refracted direction (reflected under TIR)."))
            .wgsl(EFRESNEL_WGSL)
            .wgsl_uses(&[super::optics::COS2_T_WGSL, super::optics::FRESNEL_HELPER_WGSL])
            .hard_case("grazing", &[("i", v3([1.0, 0.0, -1e-4]))])
            .hard_case("exactly grazing", &[("i", v3([1.0, 0.0, 0.0]))])
            .hard_case("light below the horizon", &[("i", v3([0.0, 0.6, 0.8]))])
            .hard_case("index match", &[("eta_i_over_t", f(1.0))])
            .hard_case("grazing at index match", &[("i", v3([1.0, 0.0, 0.0])), ("eta_i_over_t", f(1.0))])
            .hard_case("TIR from inside", &[("i", v3([0.8, 0.0, -0.6])), ("eta_i_over_t", f(1.4))])
            .compute(skin_efresnel),
        NodeType::new("skin_single_scattering", Category::Skin, "Hanrahan–Krueger single scattering of a layer, on the refracted directions.")
            .source(
                "f = albedo p(w_i, w_o)/(mu_i + mu_o) (1 − exp(−d (1/mu_i + 1/mu_o))) (Hanrahan & \
                 Krueger 1993, eq. 21; Pharr 2001 \"Layered media for surface shaders\"). mu = \
                 max(|t·n|, 1e-4); 1 − exp(−x) via expm1 so thin layers keep their value. Phase \
                 angle between the propagation directions t_light and −t_view. phase_form \
                 normalised: HG with 1/(4π); pharr: without it (erratum 3). three_lobe: Pharr's \
                 lobes (g, a) = (0.8, 0.8), (0.3, 0.5), (0, 0.4), each × albedo, ignoring g. \
                 Outputs the symmetric BRDF and f·mu_i (multiply by Kt_light Kt_view and the \
                 light's radiance).",
            )
            .input(In::vec3("t_light", [0.0, 0.0, -1.0]).range(-1.0, 1.0).doc("Refracted light direction inside the layer (propagation, into the layer)."))
            .input(In::vec3("t_view", [0.0, 0.0, -1.0]).range(-1.0, 1.0).doc("Refracted view ray inside the layer (from the eye, into the layer)."))
            .input(In::vec3("n", [0.0, 0.0, 1.0]).range(-1.0, 1.0).doc("Unit surface normal."))
            .input(In::float("g", 0.8).range(-0.99, 0.99).hard(-1.0, 1.0).doc("HG mean cosine (0.8 for skin, Hanrahan & Krueger)."))
            .input(In::color("albedo", [0.8, 0.5, 0.4]).range(0.0, 1.0).hard(0.0, 10.0).doc("Single-scattering albedo per channel."))
            .input(In::float("thickness", 0.5).range(0.0, 10.0).hard(0.0, 1e6).doc("Optical depth d of the layer."))
            .input(In::choice("phase_form", &["normalised", "pharr"], 0).doc("normalised HG (default) or Pharr's form without 1/(4π)."))
            .input(In::boolean("three_lobe", false).doc("Sum Pharr's three lobes instead of the single g lobe."))
            .output(Out::color("brdf").unit("1/sr").doc("Single-scattering BRDF f (reciprocal)."))
            .output(Out::color("cos_weighted").unit("1/sr").doc("f · mu_i: bounded by albedo · p at grazing."))
            .wgsl(SINGLE_WGSL)
            .wgsl_uses(&[ONE_MINUS_EXP_WGSL, super::optics::HG_HELPER_WGSL, HK_LOBE_WGSL])
            .wgsl_per_choice("three_lobe", &[LOBES_WGSL], lobe_choices())
            .hard_case("grazing", &[("t_light", v3([1.0, 0.0, -1e-5])), ("t_view", v3([-1.0, 0.0, -1e-5]))])
            .hard_case("thickness → 0", &[("thickness", f(1e-8))])
            .hard_case("very thick", &[("thickness", f(1e6))])
            .hard_case("g = 0.999", &[("g", f(0.999)), ("t_view", v3([0.0, 0.0, 1.0]))])
            .hard_case("g = −0.999", &[("g", f(-0.999))])
            .hard_case("three lobes, Pharr form", &[("three_lobe", Value::boolean(true)), ("phase_form", Value::int(1))])
            .compute(skin_single_scattering),
        NodeType::new("skin_multiple_scattering", Category::Skin, "The paper's faked multiple scattering of the epidermis.")
            .source(
                "C_ms = C_d I_ms / (|I·N| + l_c) (seed 001, the 2004 Maya skin shader paper, epidermis; docs/models/skin.md). Brightens towards \
                 the silhouette; the denominator is kept ≥ 1e-4.",
            )
            .input(In::color("diffusion_color", [0.9, 0.6, 0.5]).range(0.0, 1.0).hard(0.0, 100.0).doc("Diffusion colour C_d."))
            .input(In::float("i_ms", 0.3).range(0.0, 2.0).hard(0.0, 100.0).doc("Multiple-scattering coefficient I_ms."))
            .input(In::float("l_c", 0.5).range(0.01, 2.0).hard(0.0, 100.0).doc("Clamp coefficient l_c."))
            .input(In::float("i_dot_n", 1.0).range(-1.0, 1.0).hard(-1.0, 1.0).doc("I·N, I the view (or incident) direction."))
            .output(Out::color("color").doc("Multiple-scattering colour."))
            .wgsl(MULTIPLE_WGSL)
            .hard_case("grazing, no clamp", &[("i_dot_n", f(0.0)), ("l_c", f(0.0))])
            .compute(skin_multiple_scattering),
        NodeType::new("skin_sebum", Category::Skin, "Phong highlight of the sebum (oil) layer.")
            .source("specularity · max(R_L·V, 0)^power (seed 001, sebum; Phong 1975); 0^power spelled out.")
            .input(In::float("specularity", 0.2).range(0.0, 1.0).hard(0.0, 100.0).doc("Specularity."))
            .input(In::float("power", 30.0).range(1.0, 200.0).hard(0.0, 10000.0).doc("Phong exponent (Power)."))
            .input(In::float("r_dot_v", 1.0).range(-1.0, 1.0).hard(-1.0, 1.0).doc("R_L·V, R_L the mirrored light direction."))
            .output(Out::float("specular").doc("Highlight weight."))
            .wgsl(SEBUM_WGSL)
            .hard_case("away from the highlight", &[("r_dot_v", f(-0.5))])
            .hard_case("power 0 at the edge", &[("r_dot_v", f(0.0)), ("power", f(0.0))])
            .hard_case("very sharp highlight", &[("specularity", f(100.0)), ("power", f(9000.0)), ("r_dot_v", f(0.99995))])
            .compute(skin_sebum),
        NodeType::new("dipole_rd_total", Category::Skin, "Jensen 2001 dipole: total diffuse reflectance.")
            .source(
                "Rd = (α'/2)(1 + exp(−(4/3) A √(3(1 − α')))) exp(−√(3(1 − α'))), α' = σs'/(σs' + σa), \
                 A = (1 + Fdr)/(1 − Fdr), Fdr = −1.440/η² + 0.710/η + 0.668 + 0.0636η (Jensen, \
                 Marschner, Levoy & Hanrahan 2001, eqs. 4–5 integrated over the plane; §2.4 for \
                 Fdr; ior clamped to [1, 3]). Per channel; σ in 1/mm.",
            )
            .input(In::color("sigma_s_prime", skin1_s).range(0.01, 5.0).hard(0.0, 1000.0).unit("1/mm").doc("Reduced scattering coefficient σs'."))
            .input(In::color("sigma_a", skin1_a).range(0.0, 5.0).hard(0.0, 1000.0).unit("1/mm").doc("Absorption coefficient σa."))
            .input(In::float("ior", 1.3).range(1.0, 2.0).hard(1.0, 3.0).doc("Medium index relative to outside (Jensen's η; 1.3 skin, not n_i/n_t)."))
            .output(Out::color("rd").doc("Total diffuse reflectance."))
            .wgsl(DIPOLE_TOTAL_WGSL)
            .wgsl_uses(&[DIPOLE_HELPERS_WGSL])
            .hard_case("no absorption", &[("sigma_a", c3([0.0, 0.0, 0.0]))])
            .hard_case("empty medium", &[("sigma_a", c3([0.0, 0.0, 0.0])), ("sigma_s_prime", c3([0.0, 0.0, 0.0]))])
            .hard_case("index match", &[("ior", f(1.0))])
            .compute(dipole_rd_total),
        NodeType::new("dipole_rd_profile", Category::Skin, "Jensen 2001 dipole: diffuse reflectance at distance r.")
            .source(
                "Rd(r) = α'/(4π)[z_r(σtr d_r + 1)e^{−σtr d_r}/d_r³ + z_v(σtr d_v + 1)e^{−σtr d_v}/d_v³], \
                 σtr = √(3σaσt'), z_r = 1/σt', z_v = z_r(1 + 4A/3), d = √(r² + z²) (Jensen et al. \
                 2001, eq. 4). ∫2πr Rd(r) dr = dipole_rd_total.",
            )
            .input(In::float("r", 1.0).range(0.0, 10.0).hard(-1e4, 1e4).unit("mm").doc("Distance from the point of entry."))
            .input(In::color("sigma_s_prime", skin1_s).range(0.01, 5.0).hard(0.0, 1000.0).unit("1/mm").doc("Reduced scattering coefficient σs'."))
            .input(In::color("sigma_a", skin1_a).range(0.0, 5.0).hard(0.0, 1000.0).unit("1/mm").doc("Absorption coefficient σa."))
            .input(In::float("ior", 1.3).range(1.0, 2.0).hard(1.0, 3.0).doc("Medium index relative to outside (Jensen's η)."))
            .output(Out::color("rd").unit("1/mm²").doc("Diffuse reflectance per unit area."))
            .wgsl(DIPOLE_PROFILE_WGSL)
            .wgsl_uses(&[DIPOLE_HELPERS_WGSL])
            .hard_case("at the entry point", &[("r", f(0.0))])
            .hard_case("far", &[("r", f(1000.0))])
            .hard_case("no absorption", &[("sigma_a", c3([0.0, 0.0, 0.0]))])
            .compute(dipole_rd_profile),
    ]
}
