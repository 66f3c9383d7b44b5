//! Transmission through solid dielectric objects (docs/models/transmission.md): refraction in
//! and out of a sphere or a parallel slab with exact Fresnel at both interfaces, total
//! internal reflection, Beer–Lambert absorption along the path, and dispersion from
//! per-channel indices (Sellmeier).
//!
//! Conventions as in [`crate::nodes::optics`]: N points out of the object, V from the surface
//! to the eye, I = −V. Indices are per colour channel (R, G, B at [`RGB_WAVELENGTHS_NM`]) so a
//! dispersive object sends each channel along its own exit ray.

use crate::node::{Category, In, NodeType, Out};
use crate::nodes::optics::{
    COS2_T_SIN2_WGSL, COS2_T_WGSL, FRESNEL_HELPER_WGSL, FRESNEL_KNOWN_ANGLE_WGSL,
    cos2_transmitted_sin2, fresnel_dielectric_cos2t, fresnel_dielectric_sin2, reflect,
};
use crate::precision::{cross, exp, sqrt};
use crate::value::Value;
use glam::Vec3;

/// The wavelengths (nm) the R, G and B channels are evaluated at: 630 (red, the He–Ne/diode
/// red region), 532 (green, the Nd:YAG second harmonic) and 465 (blue), near the dominant
/// wavelengths of the sRGB primaries (611, 549, 464 nm) but spread a little wider in red.
pub const RGB_WAVELENGTHS_NM: [f32; 3] = [630.0, 532.0, 465.0];

/// Largest `n²` [`sellmeier_ior`] returns (n = 10): a Sellmeier sum next to a pole (a
/// coefficient `C` at the wavelength's square) is cut there instead of going infinite.
pub const SELLMEIER_N2_MAX: f32 = 100.0;

/// Sellmeier's dispersion formula at one wavelength:
/// `n² = 1 + Σₖ Bₖ λ² / (λ² − Cₖ)`, λ in µm, `Cₖ` in µm², three terms.
///
/// `n²` is clamped to [1, [`SELLMEIER_N2_MAX`]]: it leaves that range only within a
/// resonance (absorption band) where the formula does not describe a transparent medium;
/// the glasses and crystals it is fitted to stay inside it over 0.3–2 µm, so the clamp
/// costs them nothing. A zero denominator (λ² = Cₖ exactly) is read as `1e-30`.
/// Source: W. Sellmeier, Ann. Phys. 219 (1871); Born & Wolf, *Principles of Optics* §2.3.4;
/// coefficients on refractiveindex.info (docs/models/transmission.md has the table).
#[inline]
pub fn sellmeier_ior(b: Vec3, c: Vec3, wavelength_nm: f32) -> f32 {
    let l = wavelength_nm * 1e-3;
    let l2 = l * l;
    let term = |bk: f32, ck: f32| {
        let d = l2 - ck;
        bk * l2 / if d == 0.0 { 1e-30 } else { d }
    };
    let n2 = 1.0 + term(b.x, c.x) + term(b.y, c.y) + term(b.z, c.z);
    sqrt(n2.clamp(1.0, SELLMEIER_N2_MAX))
}

/// [`sellmeier_ior`] at the three wavelengths of `wavelengths_nm`, one index per channel.
#[inline]
pub fn sellmeier_rgb(b: Vec3, c: Vec3, wavelengths_nm: Vec3) -> Vec3 {
    Vec3::new(
        sellmeier_ior(b, c, wavelengths_nm.x),
        sellmeier_ior(b, c, wavelengths_nm.y),
        sellmeier_ior(b, c, wavelengths_nm.z),
    )
}

/// `v` scaled to unit length, or `fallback` where `v` is zero or not finite.
#[inline]
fn unit_or(v: Vec3, fallback: Vec3) -> Vec3 {
    let l2 = v.dot(v);
    if l2 > 0.0 && l2 <= f32::MAX {
        v * (1.0 / sqrt(l2))
    } else {
        fallback
    }
}

/// One wavelength's path through a sphere (see [`sphere_path`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpherePath {
    /// Direction of the ray leaving the sphere (unit when the inputs are).
    pub exit: Vec3,
    /// Fresnel reflectance at the entry point.
    pub reflectance: f32,
    /// `T_in · T_out · exp(−σ L)`: the fraction of the incident power leaving along `exit`.
    pub transmittance: f32,
    /// Chord length `L` inside the sphere, metres.
    pub length: f32,
    /// Total internal reflection at the exit (or at the entry, where `ior < ior_outside`).
    pub tir: bool,
}

/// The first transmitted path of one wavelength through a sphere of radius `r` (metres),
/// given the unit shading normal `n`, unit view `v`, the unit geometric normal `g` at the
/// entry point (`(p − c)/r`), `cos_i = n·v` (clamped to [0, 1]) and `sin2_i = |n × v|²`.
///
/// 1. Entry (Snell, `η = n_out/n`): `t = η I + (η cosθi − cosθt) N`, Fresnel `R_in`, `T_in`
///    (exact, [`fresnel_dielectric_sin2`]); cos²θt from `sin²θi` where it is below ½
///    ([`cos2_transmitted_sin2`]: from a much denser outside, near the critical angle, the
///    `cosθi` form multiplies the rounding of the normalised N and V by 2η²).
/// 2. Chord: the second intersection of `p + s t` with the sphere is at
///    `s = L = 2 r cosθc`, `cosθc = −t·g` (for `t·g ≥ 0` the ray leaves at once, `L = 0`).
///    With `n = g` (the sphere's own normal) `cosθc = cosθt` and `L = 2 r cosθt`.
/// 3. Exit normal `m = (p + L t − c)/r = g + 2 cosθc t`; the internal angle of incidence is
///    again `cosθc` (a sphere's chords meet its surface at equal angles at both ends).
/// 4. Exit (Snell, `η' = n/n_out`): `e = η' t + (cosθe − η' cosθc) m`, Fresnel `T_out` from
///    the inside. `cos²θe = 1 − η'² sin²θc` is taken from the entry rather than from
///    `cosθc`: with `t × g = η (I × g + β (N − g) × g)`, `β = cosθi − cosθt/η` and `η'η = 1`,
///    `cos²θe = (I·g)² − β (2 (I × g)·((N − g) × g) + β |(N − g) × g|²)`. For `N = g` the
///    correction is exactly 0 and `cosθe = cosθi` (the chord's symmetry), where
///    `1 − η'² sin²θc` would cancel to rounding at grazing entry and flip the TIR flag. Under TIR (`cos²θe < 0`) the ray reflects internally; its next chord meets
///    the surface at the same angle, so it is trapped for every bounce: `T = 0` and `exit`
///    is the internally reflected direction (0 further bounces are traced; what the cut-off
///    costs is nothing, as none of them could leave).
/// 5. Beer–Lambert: `exp(−σ L)`.
///
/// The light reflected internally at the first exit (a fraction `T_in R_out` of the incident
/// power, at most `(1 − R)R ≤ 1/4`; 14% for diamond at normal incidence, 4% for glass) leaves
/// later in other directions and is dropped, so `R + T ≤ 1`.
/// Source: Snell's law and Fresnel's equations (Hecht, *Optics* §4.4, §4.6 eqs. 4.34, 4.40);
/// ray–sphere intersection (Glassner, *An Introduction to Ray Tracing* ch. 2);
/// Beer–Lambert (Bouguer 1729; Lambert 1760).
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn sphere_path(
    n: Vec3,
    v: Vec3,
    g: Vec3,
    cos_i: f32,
    sin2_i: f32,
    radius: f32,
    ior: f32,
    ior_outside: f32,
    sigma: f32,
) -> SpherePath {
    let i = -v;
    let (r_in, t_in) = fresnel_dielectric_sin2(cos_i, sin2_i, ior_outside, ior);
    let eta = ior_outside / ior;
    let k_in = cos2_transmitted_sin2(cos_i, sin2_i, eta);
    if k_in < 0.0 {
        // Denser outside than inside, past the critical angle: nothing enters.
        return SpherePath {
            exit: reflect(i, n),
            reflectance: r_in,
            transmittance: 0.0,
            length: 0.0,
            tir: true,
        };
    }
    let gamma = eta * cos_i - sqrt(k_in);
    let t = eta * i + gamma * n;
    let cos_c = (-t.dot(g)).clamp(0.0, 1.0);
    let length = 2.0 * radius * cos_c;
    let m = g + (2.0 * cos_c) * t;
    let eta_out = ior / ior_outside;
    let (a, b) = (cross(i, g), cross(n - g, g));
    let beta = gamma / eta;
    let ig = i.dot(g);
    let k_out = ig * ig - beta * (2.0 * a.dot(b) + beta * b.length_squared());
    let absorb = exp(-sigma * length);
    if k_out < 0.0 {
        return SpherePath {
            exit: t - (2.0 * cos_c) * m,
            reflectance: r_in,
            transmittance: 0.0,
            length,
            tir: true,
        };
    }
    let exit = eta_out * t + (sqrt(k_out) - eta_out * cos_c) * m;
    let (_, t_out) = fresnel_dielectric_cos2t(cos_c, k_out, ior, ior_outside);
    SpherePath {
        exit,
        reflectance: r_in,
        transmittance: t_in * t_out * absorb,
        length,
        tir: false,
    }
}

/// The `transmission_sphere` node: [`sphere_path`] per colour channel. Inputs are normalised
/// (a zero normal falls back to the geometric normal, a zero view to the normal); the entry
/// point is taken on the sphere, at `c + r·normalize(p − c)`.
#[allow(clippy::too_many_arguments)]
pub fn transmission_sphere(
    position: Vec3,
    normal: Vec3,
    view: Vec3,
    center: Vec3,
    radius: f32,
    ior: Vec3,
    ior_outside: f32,
    absorption: Vec3,
) -> (Vec3, Vec3, Vec3, Vec3, Vec3, Vec3, bool) {
    let g = unit_or(position - center, Vec3::Z);
    let n = unit_or(normal, g);
    let v = unit_or(view, n);
    let cos_i = n.dot(v).clamp(0.0, 1.0);
    // Light from behind is shaded as grazing (cosθi clamped to 0): sin²θi = 1 with it.
    let sin2_i = if cos_i > 0.0 {
        cross(n, v).length_squared()
    } else {
        1.0
    };
    let r = radius.max(0.0);
    let a = absorption.max(Vec3::ZERO);
    let pr = sphere_path(n, v, g, cos_i, sin2_i, r, ior.x, ior_outside, a.x);
    let pg = sphere_path(n, v, g, cos_i, sin2_i, r, ior.y, ior_outside, a.y);
    let pb = sphere_path(n, v, g, cos_i, sin2_i, r, ior.z, ior_outside, a.z);
    (
        pr.exit,
        pg.exit,
        pb.exit,
        Vec3::new(pr.reflectance, pg.reflectance, pb.reflectance),
        Vec3::new(pr.transmittance, pg.transmittance, pb.transmittance),
        Vec3::new(pr.length, pg.length, pb.length),
        pr.tir || pg.tir || pb.tir,
    )
}

/// A parallel slab of thickness `d` (metres), one channel, for light at `cos_i = cosθi`
/// (`sin2_i = sin²θi`, see [`cos2_transmitted_sin2`]): the exit ray is parallel to the
/// incident one (its lateral shift is ignored), every internal bounce leaves along it, and
/// their incoherent sum is closed:
/// `T = T_in T_out a / (1 − R_out² a²)`, `a = exp(−σ d / cosθt)`, `R_out = R_in` at the same
/// angle by reciprocity, and `T_out = T_in` (both taken from the entry, not recomputed from
/// cosθt). Returns `(R_in, T, d / cosθt)`; under TIR at the entry `T = 0` and the path is 0.
/// Source: Hecht §4.6; the geometric series of a plate (Born & Wolf §1.6 without the phase:
/// the incoherent limit).
#[inline]
pub fn slab_path(
    cos_i: f32,
    sin2_i: f32,
    thickness: f32,
    ior: f32,
    ior_outside: f32,
    sigma: f32,
) -> (f32, f32, f32) {
    let (r_in, t_in) = fresnel_dielectric_sin2(cos_i, sin2_i, ior_outside, ior);
    let k = cos2_transmitted_sin2(cos_i, sin2_i, ior_outside / ior);
    if k <= 0.0 {
        return (r_in, 0.0, 0.0);
    }
    let cos_t = sqrt(k).min(1.0);
    // The exit face is parallel to the entry and the same medium lies beyond both, so the
    // exit meets the outside at the entry's angle: by reciprocity (Stokes relations; Hecht
    // §4.10) R_out = R_in and T_out = T_in exactly. Computing them again from cosθt would
    // recover cosθi through cos²θt's cancellation, which at grazing entry is all rounding.
    let (r_out, t_out) = (r_in, t_in);
    let path = thickness / cos_t;
    let a = exp(-sigma * path);
    let ra = r_out * a;
    // f32 may round a grazing entry's internal angle past the critical one (R_out = 1,
    // T_out = 0): T = 0 then, its limit, where the series' 0/0 would be NaN.
    let denom = 1.0 - ra * ra;
    let t = if denom > 0.0 {
        t_in * t_out * a / denom
    } else {
        0.0
    };
    (r_in, t, path)
}

/// The `transmission_slab` node: [`slab_path`] per channel; the exit direction is `−V`.
pub fn transmission_slab(
    normal: Vec3,
    view: Vec3,
    thickness: f32,
    ior: Vec3,
    ior_outside: f32,
    absorption: Vec3,
) -> (Vec3, Vec3, Vec3, Vec3) {
    let n = unit_or(normal, Vec3::Z);
    let v = unit_or(view, n);
    let cos_i = n.dot(v).clamp(0.0, 1.0);
    // Light from behind is shaded as grazing (cosθi clamped to 0): sin²θi = 1 with it.
    let sin2_i = if cos_i > 0.0 {
        cross(n, v).length_squared()
    } else {
        1.0
    };
    let d = thickness.max(0.0);
    let a = absorption.max(Vec3::ZERO);
    let (rr, tr, lr) = slab_path(cos_i, sin2_i, d, ior.x, ior_outside, a.x);
    let (rg, tg, lg) = slab_path(cos_i, sin2_i, d, ior.y, ior_outside, a.y);
    let (rb, tb, lb) = slab_path(cos_i, sin2_i, d, ior.z, ior_outside, a.z);
    (
        -v,
        Vec3::new(rr, rg, rb),
        Vec3::new(tr, tg, tb),
        Vec3::new(lr, lg, lb),
    )
}

/// The `transmission_combine` node: the radiance leaving the object,
/// `T ⊙ (L_r.r, L_g.g, L_b.b)`, each channel read from the lookup along its own exit ray.
#[inline]
pub fn transmission_combine(env_r: Vec3, env_g: Vec3, env_b: Vec3, transmittance: Vec3) -> Vec3 {
    transmittance * Vec3::new(env_r.x, env_g.y, env_b.z)
}

/// WGSL of [`sellmeier_ior`], `mg_tr_sellmeier(b, c, wavelength_nm)`.
const SELLMEIER_HELPER_WGSL: &str = r#"
fn mg_tr_sellmeier_term(bk: f32, ck: f32, l2: f32) -> f32 {
    let d = l2 - ck;
    return bk * l2 / select(d, 1e-30, d == 0.0);
}
fn mg_tr_sellmeier(b: vec3<f32>, c: vec3<f32>, wavelength_nm: f32) -> f32 {
    let l = wavelength_nm * 1e-3;
    let l2 = l * l;
    let n2 = 1.0 + mg_tr_sellmeier_term(b.x, c.x, l2) + mg_tr_sellmeier_term(b.y, c.y, l2) + mg_tr_sellmeier_term(b.z, c.z, l2);
    return sqrt(min(max(n2, 1.0), 100.0));
}
"#;

const SELLMEIER_WGSL: &str = r#"
fn $fn(b: vec3<f32>, c: vec3<f32>, wavelengths: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(mg_tr_sellmeier(b, c, wavelengths.x), mg_tr_sellmeier(b, c, wavelengths.y), mg_tr_sellmeier(b, c, wavelengths.z));
}
"#;

/// WGSL of `unit_or` and [`sphere_path`] / [`slab_path`] as helpers: the same steps.
const PATH_HELPER_WGSL: &str = r#"
struct MgTrPath {
    exit: vec3<f32>,
    reflectance: f32,
    transmittance: f32,
    path: f32,
    tir: bool,
}
fn mg_tr_unit_or(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let l2 = dot(v, v);
    if (l2 > 0.0 && l2 <= 0x1.fffffep+127f) {
        return v * (1.0 / sqrt(l2));
    }
    return fallback;
}
fn mg_tr_sphere_path(n: vec3<f32>, v: vec3<f32>, g: vec3<f32>, cos_i: f32, sin2_i: f32, radius: f32, ior: f32, ior_outside: f32, sigma: f32) -> MgTrPath {
    let i = -v;
    let rt_in = mg_opth_fresnel_sin2(cos_i, sin2_i, ior_outside, ior);
    let eta = ior_outside / ior;
    let k_in = mg_opth_cos2_t_sin2(cos_i, sin2_i, eta);
    if (k_in < 0.0) {
        return MgTrPath(i - 2.0 * dot(n, i) * n, rt_in.x, 0.0, 0.0, true);
    }
    let gamma = eta * cos_i - sqrt(k_in);
    let t = eta * i + gamma * n;
    let cos_c = min(max(-dot(t, g), 0.0), 1.0);
    let len = 2.0 * radius * cos_c;
    let m = g + (2.0 * cos_c) * t;
    let eta_out = ior / ior_outside;
    let a = cross(i, g);
    let b = cross(n - g, g);
    let beta = gamma / eta;
    let ig = dot(i, g);
    let k_out = ig * ig - beta * (2.0 * dot(a, b) + beta * dot(b, b));
    let absorb = exp(-sigma * len);
    if (k_out < 0.0) {
        return MgTrPath(t - (2.0 * cos_c) * m, rt_in.x, 0.0, len, true);
    }
    let e = eta_out * t + (sqrt(k_out) - eta_out * cos_c) * m;
    let rt_out = mg_opth_fresnel_cos2t(cos_c, k_out, ior, ior_outside);
    return MgTrPath(e, rt_in.x, rt_in.y * rt_out.y * absorb, len, false);
}
fn mg_tr_slab_path(cos_i: f32, sin2_i: f32, thickness: f32, ior: f32, ior_outside: f32, sigma: f32) -> vec3<f32> {
    let rt_in = mg_opth_fresnel_sin2(cos_i, sin2_i, ior_outside, ior);
    let k = mg_opth_cos2_t_sin2(cos_i, sin2_i, ior_outside / ior);
    if (k <= 0.0) {
        return vec3<f32>(rt_in.x, 0.0, 0.0);
    }
    let cos_t = min(sqrt(k), 1.0);
    let path = thickness / cos_t;
    let a = exp(-sigma * path);
    let ra = rt_in.x * a;
    let denom = 1.0 - ra * ra;
    var t = 0.0;
    if (denom > 0.0) {
        t = rt_in.y * rt_in.y * a / denom;
    }
    return vec3<f32>(rt_in.x, t, path);
}
"#;

const SPHERE_WGSL: &str = r#"
fn $fn(position: vec3<f32>, normal: vec3<f32>, view: vec3<f32>, center: vec3<f32>, radius: f32, ior: vec3<f32>, ior_outside: f32, absorption: vec3<f32>) -> $out {
    let g = mg_tr_unit_or(position - center, vec3<f32>(0.0, 0.0, 1.0));
    let n = mg_tr_unit_or(normal, g);
    let v = mg_tr_unit_or(view, n);
    let cos_i = min(max(dot(n, v), 0.0), 1.0);
    let nv = cross(n, v);
    let sin2_i = select(1.0, dot(nv, nv), cos_i > 0.0);
    let r = max(radius, 0.0);
    let a = max(absorption, vec3<f32>(0.0));
    let pr = mg_tr_sphere_path(n, v, g, cos_i, sin2_i, r, ior.x, ior_outside, a.x);
    let pg = mg_tr_sphere_path(n, v, g, cos_i, sin2_i, r, ior.y, ior_outside, a.y);
    let pb = mg_tr_sphere_path(n, v, g, cos_i, sin2_i, r, ior.z, ior_outside, a.z);
    return $out(pr.exit, pg.exit, pb.exit,
        vec3<f32>(pr.reflectance, pg.reflectance, pb.reflectance),
        vec3<f32>(pr.transmittance, pg.transmittance, pb.transmittance),
        vec3<f32>(pr.path, pg.path, pb.path),
        pr.tir || pg.tir || pb.tir);
}
"#;

const SLAB_WGSL: &str = r#"
fn $fn(normal: vec3<f32>, view: vec3<f32>, thickness: f32, ior: vec3<f32>, ior_outside: f32, absorption: vec3<f32>) -> $out {
    let n = mg_tr_unit_or(normal, vec3<f32>(0.0, 0.0, 1.0));
    let v = mg_tr_unit_or(view, n);
    let cos_i = min(max(dot(n, v), 0.0), 1.0);
    let nv = cross(n, v);
    let sin2_i = select(1.0, dot(nv, nv), cos_i > 0.0);
    let d = max(thickness, 0.0);
    let a = max(absorption, vec3<f32>(0.0));
    let pr = mg_tr_slab_path(cos_i, sin2_i, d, ior.x, ior_outside, a.x);
    let pg = mg_tr_slab_path(cos_i, sin2_i, d, ior.y, ior_outside, a.y);
    let pb = mg_tr_slab_path(cos_i, sin2_i, d, ior.z, ior_outside, a.z);
    return $out(-v, vec3<f32>(pr.x, pg.x, pb.x), vec3<f32>(pr.y, pg.y, pb.y), vec3<f32>(pr.z, pg.z, pb.z));
}
"#;

const COMBINE_WGSL: &str = r#"
fn $fn(env_r: vec3<f32>, env_g: vec3<f32>, env_b: vec3<f32>, transmittance: vec3<f32>) -> vec3<f32> {
    return transmittance * vec3<f32>(env_r.x, env_g.y, env_b.z);
}
"#;

/// BK7 (SCHOTT N-BK7 data sheet) Sellmeier coefficients `B`, the default of `sellmeier_ior`.
pub const BK7_B: [f32; 3] = [1.039_612, 0.231_792_35, 1.010_469_6];
/// BK7 Sellmeier coefficients `C`, µm².
pub const BK7_C: [f32; 3] = [0.006_000_699, 0.020_017_914, 103.560_65];

/// The transmission node types.
pub fn all() -> Vec<NodeType> {
    let f = Value::float;
    let v3 = Value::vec3;
    vec![
        NodeType::new("sellmeier_ior", Category::Optics, "Refractive index per colour channel from Sellmeier coefficients (dispersion).")
            .source(
                "n² = 1 + Σₖ Bₖ λ²/(λ² − Cₖ), λ in µm, three terms (Sellmeier 1871; Born & Wolf §2.3.4; \
                 docs/models/transmission.md lists BK7, fused silica, sapphire (ordinary ray) and diamond \
                 from refractiveindex.info). Evaluated at each channel's wavelength (default R 630, G 532, \
                 B 465 nm). n² is clamped to [1, 100]: it leaves that range only inside an absorption \
                 band, where the formula no longer describes a transparent medium; tabulated materials \
                 stay inside it over 0.3–2 µm, so the clamp costs them nothing.",
            )
            .input(In::vec3("b", BK7_B).range(0.0, 6.0).hard(0.0, 100.0).doc("Oscillator strengths B₁, B₂, B₃ (default BK7)."))
            .input(In::vec3("c", BK7_C).range(0.0, 400.0).hard(0.0, 999.0).unit("µm²").doc("Resonance wavelengths squared C₁, C₂, C₃ (default BK7)."))
            .input(In::vec3("wavelengths", RGB_WAVELENGTHS_NM).range(380.0, 780.0).hard(200.0, 999.0).unit("nm").doc("Wavelength of each channel (R, G, B)."))
            .output(Out::vec3("ior").doc("Refractive index at each channel's wavelength."))
            .wgsl(SELLMEIER_WGSL)
            .wgsl_uses(&[SELLMEIER_HELPER_WGSL])
            .hard_case("on a pole", &[("c", v3([0.396_9, 0.02, 103.56])), ("wavelengths", v3([630.0, 630.0, 630.0]))])
            .hard_case("no dispersion", &[("b", v3([0.0, 0.0, 0.0]))])
            .hard_case("diamond", &[("b", v3([0.3306, 4.3356, 0.0])), ("c", v3([0.030_625, 0.011_236, 0.0]))])
            .compute(sellmeier_rgb),
        NodeType::new("transmission_sphere", Category::Optics, "Light through a solid dielectric sphere: refraction in and out, exact Fresnel, TIR, Beer–Lambert, one exit ray per channel.")
            .source(
                "Per channel (docs/models/transmission.md): Snell in at the shaded point, t = η I + (η cosθi − \
                 cosθt) N, η = n_out/n; the chord to the far side L = 2 r cosθc, cosθc = −t·g with g = \
                 (p − c)/|p − c| the sphere's own normal (L = 2 r cosθt when N = g); the exit normal m = g + \
                 2 cosθc t; Snell out, e = η' t + (cosθe − η' cosθc) m, η' = n/n_out; exact Fresnel at both \
                 interfaces (Hecht §4.6), T = T_in T_out exp(−σ L) (Beer–Lambert). Assumes the object is a \
                 sphere of the given centre and radius (the material ball; other shapes: \
                 transmission_slab with a thickness); the entry point is taken on the sphere. Under TIR \
                 at the exit the ray reflects, and since a sphere's chords meet its surface at one angle \
                 it stays trapped at every bounce: T = 0, exit is the internal reflection, tir is true \
                 (0 further bounces traced: none could leave). The light reflected internally at the first \
                 exit (T_in R_out of the incident power: 4% for glass, 14% for diamond at normal incidence) \
                 leaves later in other directions and is dropped, so R + T ≤ 1. Look exit_r/g/b up in \
                 scene:environment (equirect_uv) and combine with transmission_combine.",
            )
            .input(In::vec3("position", [0.0, 1.0, 1.0]).range(-2.0, 2.0).hard(-100.0, 100.0).unit("m").doc("World position of the shaded point (on the sphere)."))
            .input(In::vec3("normal", [0.0, 0.0, 1.0]).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Unit shading normal N at the entry point."))
            .input(In::vec3("view", [0.0, 0.0, 1.0]).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Unit direction V from the surface to the eye."))
            .input(In::vec3("center", [0.0, 1.0, 0.0]).range(-2.0, 2.0).hard(-100.0, 100.0).unit("m").doc("Centre of the sphere (the ball scene's: 0, 1, 0)."))
            .input(In::float("radius", 1.0).range(0.1, 2.0).hard(0.0, 100.0).unit("m").doc("Radius of the sphere (the ball scene's: 1)."))
            .input(In::vec3("ior", [1.5168, 1.5168, 1.5168]).range(1.0, 2.6).hard(1e-3, 100.0).doc("Refractive index inside, per channel (sellmeier_ior for dispersion)."))
            .input(In::float("ior_outside", 1.0).range(1.0, 1.5).hard(1e-3, 100.0).doc("Refractive index outside (air: 1)."))
            .input(In::color("absorption", [0.0, 0.0, 0.0]).range(0.0, 4.0).hard(0.0, 100.0).unit("1/m").doc("Absorption coefficient σ per channel (Beer–Lambert)."))
            .output(Out::vec3("exit_r").doc("Direction leaving the sphere, red channel."))
            .output(Out::vec3("exit_g").doc("Direction leaving the sphere, green channel."))
            .output(Out::vec3("exit_b").doc("Direction leaving the sphere, blue channel."))
            .output(Out::color("reflectance").doc("Exact Fresnel reflectance at the entry, per channel."))
            .output(Out::color("transmittance").doc("T_in · T_out · exp(−σ L) per channel."))
            .output(Out::vec3("path_length").unit("m").doc("Chord length L inside the sphere per channel."))
            .output(Out::boolean("tir").doc("True where a channel is totally internally reflected."))
            .wgsl(SPHERE_WGSL)
            .wgsl_uses(&[
                COS2_T_WGSL,
                COS2_T_SIN2_WGSL,
                FRESNEL_HELPER_WGSL,
                FRESNEL_KNOWN_ANGLE_WGSL,
                PATH_HELPER_WGSL,
            ])
            .hard_case("normal incidence through the centre", &[("position", v3([0.0, 1.0, 1.0])), ("view", v3([0.0, 0.0, 1.0]))])
            .hard_case("grazing", &[("position", v3([1.0, 1.0, 0.0])), ("normal", v3([1.0, 0.0, 0.0])), ("view", v3([1e-4, 0.0, 1.0]))])
            .hard_case("exactly grazing", &[("position", v3([1.0, 1.0, 0.0])), ("normal", v3([1.0, 0.0, 0.0])), ("view", v3([0.0, 0.0, 1.0]))])
            .hard_case("TIR inside diamond (tilted shading normal)", &[("normal", v3([0.8, 0.0, 0.6])), ("view", v3([0.8, 0.0, 0.6])), ("ior", v3([2.42, 2.42, 2.42]))])
            .hard_case("denser outside, TIR at the entry", &[("view", v3([0.8, 0.0, 0.6])), ("ior", v3([1.0, 1.0, 1.0])), ("ior_outside", f(1.5))])
            .hard_case("index match", &[("ior", v3([1.0, 1.0, 1.0]))])
            .hard_case("zero radius", &[("radius", f(0.0))])
            .hard_case("centre on the point", &[("position", v3([0.0, 1.0, 0.0]))])
            .hard_case("opaque", &[("absorption", v3([100.0, 100.0, 100.0])), ("radius", f(100.0))])
            .compute(transmission_sphere),
        NodeType::new("transmission_slab", Category::Optics, "Light through a parallel dielectric slab of a given thickness: exact Fresnel, all internal bounces, Beer–Lambert.")
            .source(
                "Per channel (docs/models/transmission.md): cosθt from Snell, path d/cosθt, a = exp(−σ d/cosθt) \
                 (Beer–Lambert), exact Fresnel at both faces (Hecht §4.6), and the incoherent sum of every \
                 internal bounce, T = T_in T_out a/(1 − R_out² a²) (Born & Wolf §1.6, incoherent limit). The \
                 exit ray is parallel to the incident one (−V; the lateral shift is ignored), so a slab \
                 shows no dispersion. For objects other than a sphere, with their thickness along the \
                 refracted ray's normal. Under TIR at the entry (denser outside) T = 0.",
            )
            .input(In::vec3("normal", [0.0, 0.0, 1.0]).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Unit surface normal N."))
            .input(In::vec3("view", [0.0, 0.0, 1.0]).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Unit direction V from the surface to the eye."))
            .input(In::float("thickness", 0.01).range(0.0, 1.0).hard(0.0, 100.0).unit("m").doc("Thickness d of the slab."))
            .input(In::vec3("ior", [1.5168, 1.5168, 1.5168]).range(1.0, 2.6).hard(1e-3, 100.0).doc("Refractive index inside, per channel."))
            .input(In::float("ior_outside", 1.0).range(1.0, 1.5).hard(1e-3, 100.0).doc("Refractive index outside (air: 1)."))
            .input(In::color("absorption", [0.0, 0.0, 0.0]).range(0.0, 4.0).hard(0.0, 100.0).unit("1/m").doc("Absorption coefficient σ per channel (Beer–Lambert)."))
            .output(Out::vec3("exit").doc("Direction leaving the slab (−V)."))
            .output(Out::color("reflectance").doc("Exact Fresnel reflectance at the first face, per channel."))
            .output(Out::color("transmittance").doc("Fraction of the incident power transmitted, per channel."))
            .output(Out::vec3("path_length").unit("m").doc("Path d/cosθt of one crossing, per channel."))
            .wgsl(SLAB_WGSL)
            .wgsl_uses(&[
                COS2_T_WGSL,
                COS2_T_SIN2_WGSL,
                FRESNEL_HELPER_WGSL,
                FRESNEL_KNOWN_ANGLE_WGSL,
                PATH_HELPER_WGSL,
            ])
            .hard_case("grazing", &[("view", v3([1.0, 0.0, 1e-4]))])
            .hard_case("exactly grazing", &[("view", v3([1.0, 0.0, 0.0]))])
            .hard_case("denser outside, TIR", &[("view", v3([0.8, 0.0, 0.6])), ("ior", v3([1.0, 1.0, 1.0])), ("ior_outside", f(1.5))])
            .hard_case("index match", &[("ior", v3([1.0, 1.0, 1.0]))])
            .hard_case("zero thickness", &[("thickness", f(0.0))])
            .compute(transmission_slab),
        NodeType::new("transmission_combine", Category::Optics, "The transmitted radiance: each channel's environment lookup along its own exit ray, times the transmittance.")
            .source(
                "L = T ⊙ (L_r.r, L_g.g, L_b.b) (docs/models/transmission.md): env_r is the radiance looked up \
                 along transmission_sphere's exit_r (its red channel is used), likewise green and blue; with \
                 one index for all channels link the same lookup to all three.",
            )
            .input(In::color("env_r", [1.0, 1.0, 1.0]).range(0.0, 4.0).doc("Radiance along the red exit ray."))
            .input(In::color("env_g", [1.0, 1.0, 1.0]).range(0.0, 4.0).doc("Radiance along the green exit ray."))
            .input(In::color("env_b", [1.0, 1.0, 1.0]).range(0.0, 4.0).doc("Radiance along the blue exit ray."))
            .input(In::color("transmittance", [1.0, 1.0, 1.0]).range(0.0, 1.0).doc("Transmittance per channel."))
            .output(Out::color("color").doc("Transmitted radiance."))
            .wgsl(COMBINE_WGSL)
            .compute(transmission_combine),
    ]
}
