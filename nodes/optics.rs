//! Shared optics (docs/models/optics.md): reflection, refraction, Fresnel (exact, Schlick,
//! empirical), IOR ↔ F0 ↔ Unreal specular, and the Henyey–Greenstein phase.
//!
//! Conventions: `i` is the incident direction pointing *towards* the surface, `n` the unit
//! normal; `eta = n_incident / n_transmitted` (GLSL/RenderMan convention).
//!
//! Numerics (docs/models/optics.md "Numerics"): the transmitted cosine is computed as
//! `cos²θt = (1 − η²) + η² cos²θi`, which keeps `cos²θi` when it is tiny (grazing at an index
//! match), and the Fresnel transmittance is computed directly rather than as `1 − R`, which
//! cancels where `R → 1`.

use crate::node::{Category, In, NodeType, Out};
use crate::precision::{pow, sqrt};
use crate::types::SocketType::*;
use crate::value::Value;
use glam::Vec3;
use std::f32::consts::PI;

/// Mirror reflection `R = I − 2 (N·I) N`.
///
/// Source: Hecht, *Optics* §4.3 (law of reflection) in vector form; GLSL `reflect`.
#[inline]
pub fn reflect(i: Vec3, n: Vec3) -> Vec3 {
    i - 2.0 * n.dot(i) * n
}

/// `cos²θt` of Snell's law with `eta = n_i / n_t`: `1 − η² sin²θi` written as
/// `(1 − η)(1 + η) + (η cosθi)²`, exact in `cos²θi` at an index match (no `1 − cos²`).
/// Negative under total internal reflection.
///
/// Its limit, stated: near the critical angle `cos²θt` is the difference of two terms near
/// `|1 − η²|`, so its f32 rounding (about 2u = 1.2e-7 absolute, from `η = n1/n2` alone) is
/// amplified by the square root: 4e-6 in R at 48.7° inside water, up to ~3e-4 within 0.01°
/// of the critical angle. f64 would remove it on the CPU but not on the GPU (WGSL has no
/// f64), and cost the CPU executor 20% on the skin benchmark (docs/models/optics.md).
#[inline]
pub fn cos2_transmitted(cos_i: f32, eta: f32) -> f32 {
    (1.0 - eta) * (1.0 + eta) + (eta * cos_i) * (eta * cos_i)
}

/// [`cos2_transmitted`] for a caller that also knows `sin²θi` (from `|N × V|²`, say):
/// `1 − η² sin²θi` where `sin²θi < ½`, else [`cos2_transmitted`]. From a denser side
/// (η > √2) the critical angle is below 45°, where `(η cosθi)²` is within an ULP or two of
/// `η² − 1`: their difference then carries `2η²` times the relative error of `cosθi`, and a
/// GPU's `sqrt` leaves 8·2⁻²⁴ in the lengths of the normalised vectors `cosθi` comes from
/// (2η² = 430 at η = 14.7). `sin²θi` from a cross product carries the same relative error,
/// but `η² sin²θi` is near 1 there, so the difference keeps it at that size. Where
/// `sin²θi ≥ ½` (η < √2 near critical) the `cosθi` form is the exact one at an index match.
#[inline]
pub fn cos2_transmitted_sin2(cos_i: f32, sin2_i: f32, eta: f32) -> f32 {
    if sin2_i < 0.5 {
        1.0 - (eta * eta) * sin2_i
    } else {
        cos2_transmitted(cos_i, eta)
    }
}

/// Vector Snell refraction with `eta = n1 / n2`:
/// `k = cos²θt = (1 − η²) + η²(N·I)²`; TIR when `k < 0`; else `T = η I − (η (N·I) + √k) N`.
///
/// Under total internal reflection the result is the reflected direction and `tir` is true,
/// so a graph never receives a silent zero vector. Near the critical angle `k` inherits the
/// limit of [`cos2_transmitted`]: at η = 2.4, 0.001° from it, `T.z` is 0.44% off. Source: Hecht §4.4 (Snell's law) in the
/// vector form of GLSL `refract`, with `k` rearranged ([`cos2_transmitted`]).
#[inline]
pub fn refract(i: Vec3, n: Vec3, eta: f32) -> (Vec3, bool) {
    let cos = n.dot(i);
    let k = cos2_transmitted(cos, eta);
    if k < 0.0 {
        (reflect(i, n), true)
    } else {
        (eta * i - (eta * cos + sqrt(k)) * n, false)
    }
}

/// Exact unpolarised Fresnel reflectance and transmittance of a smooth dielectric boundary.
///
/// With `a = n1 cosθi`, `b = n2 cosθt` (s) and `a' = n2 cosθi`, `b' = n1 cosθt` (p):
/// `rs = (a − b)/(a + b)`, `rp = (a' − b')/(a' + b')`, `R = (rs² + rp²)/2`, and the
/// transmittance `T = (1 − rs² + 1 − rp²)/2 = 2ab/(a + b)² + 2a'b'/(a' + b')²`, computed
/// directly so it keeps its precision where `R → 1` (grazing). `R = 1`, `T = 0` under total
/// internal reflection; `R = 0`, `T = 1` at an index match. `cos_theta > 0`: light arrives from the outside medium
/// (`n1 = ior_outside`); `cos_theta < 0`: from the inside, and the indices swap (pbrt-v4
/// `FrDielectric`). Source: Fresnel's equations, Hecht §4.6 eqs. 4.34 and 4.40.
///
/// `b` comes from `b² = n2² cos²θt = (n2 − n1)(n2 + n1) + (n1 cosθi)²` (Snell's law times n2²),
/// and the p terms are taken times n2 (`a' n2 = n2² cosθi`, `b' n2 = n1 b`), so neither the
/// quotient `n1/n2` nor `1 − η²` is rounded: `n2 − n1` is exact near an index match. Through
/// `η = n1/n2` a grazing ray at 1.5 | 1.5000001 (cosθi = 10⁻⁴) had R = 0.31889 where the
/// true value is 0.37043 (Mitsuba 3.9 and a 40-digit reference). Both indices are first scaled
/// by the same power of two ([`same_scale`], exact), so the squares stay in range for every
/// pair of indices.
#[inline]
pub fn fresnel_dielectric(cos_theta: f32, ior_outside: f32, ior_inside: f32) -> (f32, f32) {
    let (n1, n2, cos_i) = if cos_theta >= 0.0 {
        (ior_outside, ior_inside, cos_theta.min(1.0))
    } else {
        (ior_inside, ior_outside, (-cos_theta).min(1.0))
    };
    let (n1, n2) = same_scale(n1, n2);
    let b2 = (n2 - n1) * (n2 + n1) + (n1 * cos_i) * (n1 * cos_i);
    fresnel_terms(cos_i, n1, n2, b2)
}

/// [`fresnel_dielectric`] for light arriving from the side of index `n1` (`cos_i` ≥ 0) when
/// the caller also knows `sin²θi`: where `sin²θi < ½`, `b² = n2² − n1² sin²θi` (see
/// [`cos2_transmitted_sin2`]: from a much denser side near the critical angle the `cosθi`
/// form multiplies `cosθi`'s relative error by `2η²`), else as [`fresnel_dielectric`].
#[inline]
pub fn fresnel_dielectric_sin2(cos_i: f32, sin2_i: f32, n1: f32, n2: f32) -> (f32, f32) {
    let cos_i = cos_i.min(1.0);
    let (n1, n2) = same_scale(n1, n2);
    let b2 = if sin2_i < 0.5 {
        n2 * n2 - (n1 * n1) * sin2_i
    } else {
        (n2 - n1) * (n2 + n1) + (n1 * cos_i) * (n1 * cos_i)
    };
    fresnel_terms(cos_i, n1, n2, b2)
}

/// [`fresnel_dielectric`] for light arriving from the side of index `n1` (`cos_i` ≥ 0) when
/// the caller knows `cos²θt` (`cos2_t`, negative under TIR) better than the indices and
/// `cosθi` give it: `b² = n2² cos²θt`.
#[inline]
pub fn fresnel_dielectric_cos2t(cos_i: f32, cos2_t: f32, n1: f32, n2: f32) -> (f32, f32) {
    let (n1, n2) = same_scale(n1, n2);
    fresnel_terms(cos_i.min(1.0), n1, n2, (n2 * n2) * cos2_t)
}

/// `(R, T)` of [`fresnel_dielectric`] from `cosθi`, the indices (already [`same_scale`]d) and
/// `b² = n2² cos²θt`.
#[inline]
fn fresnel_terms(cos_i: f32, n1: f32, n2: f32, b2: f32) -> (f32, f32) {
    let b = sqrt(b2.max(0.0));
    let a = n1 * cos_i;
    let (ap, bp) = ((n2 * n2) * cos_i, n1 * b);
    let (inv_s, inv_p) = (1.0 / (a + b), 1.0 / (ap + bp));
    let rs = (a - b) * inv_s;
    let rp = (ap - bp) * inv_p;
    let r = 0.5 * (rs * rs + rp * rp);
    // Each factor is at most 1.
    let ts = 2.0 * (a * inv_s) * (b * inv_s);
    let tp = 2.0 * (ap * inv_p) * (bp * inv_p);
    // Selects rather than early returns, so a tile of samples vectorises.
    if n1 == n2 {
        // No interface: nothing is reflected, at every angle (grazing included, where the
        // quotients above are 0/0).
        (0.0, 1.0)
    } else if b2 < 0.0 {
        (1.0, 0.0)
    } else {
        (r, ts + tp)
    }
}

/// `(n1, n2)` times the power of two `2⁻ᵉ` that brings the larger into [0.5, 1) (`e` at most
/// 126, so the larger lands in [0.5, 4)): exact (a power of two only moves the exponent), so
/// their difference and ratio are kept, and their squares cannot overflow or underflow for
/// any pair of positive normal indices. The power of two is built from its bits (integer
/// operations keep the tile loop vectorised; `powi` is a library call that made the skin
/// benchmark's executor 48% slower). WGSL: `frexp` and `ldexp`, exact there too.
#[inline]
pub fn same_scale(n1: f32, n2: f32) -> (f32, f32) {
    let m = n1.max(n2).max(f32::MIN_POSITIVE);
    // m = f · 2^e with f in [0.5, 1), as WGSL's frexp.
    let e = (((m.to_bits() >> 23) & 0xff) as i32 - 126).min(126);
    let s = f32::from_bits(((127 - e) as u32) << 23);
    (n1 * s, n2 * s)
}

/// Schlick's approximation `F = F0 + (1 − F0)(1 − cosθ)⁵`.
///
/// Valid when light arrives from the less dense side; from the denser side feed it cosθt.
/// cosθ is clamped to [0, 1]: a direction below the surface (cosθ < 0) is shaded as grazing
/// (F = 1), where the unclamped polynomial would exceed 1 (up to 32 − 31 F0 at cosθ = −1).
/// Source: Schlick 1994, eq. 24.
#[inline]
pub fn fresnel_schlick<
    T: Copy
        + std::ops::Add<Output = T>
        + std::ops::Mul<f32, Output = T>
        + std::ops::Sub<Output = T>
        + OneT,
>(
    cos_theta: f32,
    f0: T,
) -> T {
    let m = (1.0 - cos_theta.clamp(0.0, 1.0)).max(0.0);
    let m2 = m * m;
    f0 + (T::one() - f0) * (m2 * m2 * m)
}

/// The value 1 in every component.
pub trait OneT {
    /// 1 in every component.
    fn one() -> Self;
}
impl OneT for f32 {
    fn one() -> Self {
        1.0
    }
}
impl OneT for Vec3 {
    fn one() -> Self {
        Vec3::ONE
    }
}

/// The Cg Tutorial's empirical Fresnel `clamp(bias + scale (1 + I·N)^power, 0, 1)`.
///
/// With `bias = F0`, `scale = 1 − F0`, `power = 5` it equals Schlick. Source: Fernando &
/// Kilgard, The Cg Tutorial (2003), §7.4; used by seed 004.
#[inline]
pub fn fresnel_empirical(i_dot_n: f32, bias: f32, scale: f32, power: f32) -> f32 {
    let base = (1.0 + i_dot_n).max(0.0);
    // 0^power spelled out, as in the WGSL (where pow is undefined at a zero base).
    let p = if base == 0.0 {
        if power == 0.0 { 1.0 } else { 0.0 }
    } else {
        pow(base, power)
    };
    (bias + scale * p).clamp(0.0, 1.0)
}

/// Normal-incidence reflectance `R0 = ((n1 − n2)/(n1 + n2))²`. Source: Hecht §4.6 eq. 4.47
/// (Fresnel's equations at θi = 0).
#[inline]
pub fn ior_to_f0(ior_outside: f32, ior_inside: f32) -> f32 {
    let r = (ior_outside - ior_inside) / (ior_outside + ior_inside);
    r * r
}

/// Inverse of [`ior_to_f0`] from air: `n = (1 + √R0)/(1 − √R0)`, written
/// `(1 + √R0)²/(1 − R0)`, which keeps its precision as `R0 → 1` (`1 − R0` is exact, `1 − √R0`
/// is not). R0 is taken in [0, 1]. Source: seed 003 (inverting Hecht eq. 4.47).
///
/// Capped at [`IOR_MAX`] = 2⁴⁰ (R0 = 1, a perfect mirror, is n = ∞): at 2⁴⁰ the normal
/// reflectance `((n − 1)/(n + 1))²` is 1 − 2⁻³⁸, which is 1 in f32, so the cap changes no f32
/// reflectance; it keeps `n²`, `n·cosθ` and their quotients inside [2⁻¹²⁶, 2¹²⁶], where WGSL
/// specifies division. The cap was `f32::MAX`, whose reciprocal is subnormal: a GPU that
/// flushes subnormals (WGSL §15.7.4.1 allows it) made the exact-Fresnel pbr_brdf 0 at normal
/// incidence on an NVIDIA H200, where the CPU gives 1.2732.
#[inline]
pub fn f0_to_ior(f0: f32) -> f32 {
    let f0 = f0.clamp(0.0, 1.0);
    let one_plus_s = 1.0 + sqrt(f0);
    if f0 >= 1.0 {
        IOR_MAX
    } else {
        (one_plus_s * one_plus_s / (1.0 - f0)).min(IOR_MAX)
    }
}

/// 2⁴⁰: the largest index [`f0_to_ior`] returns.
pub const IOR_MAX: f32 = 1_099_511_627_776.0;

/// Unreal's non-metal Specular input: `specular = R0 / 0.08`. Source: seed 003 (Unreal
/// Engine 4 material docs: Specular 0.5 ↔ 4%).
#[inline]
pub fn f0_to_specular(f0: f32) -> f32 {
    f0 / 0.08
}

/// Inverse of [`f0_to_specular`]: `R0 = 0.08 · specular`. Source: seed 003.
#[inline]
pub fn specular_to_f0(specular: f32) -> f32 {
    0.08 * specular
}

/// The largest |g| used: the largest f32 below 1. HG at |g| = 1 is a delta distribution;
/// `g = ±1` is evaluated as `±HG_G_MAX`, a lobe about 6e-8 rad wide whose peak is
/// 4.5e13 / sr: every |g| < 1 is evaluated as given.
pub const HG_G_MAX: f32 = 1.0 - f32::EPSILON / 2.0;

/// Henyey–Greenstein phase function normalised over the sphere:
/// `p(cosθ) = (1 − g²) / (4π (1 + g² − 2g cosθ)^1.5)`.
///
/// Evaluated through the symmetry `p(cosθ, g) = p(−cosθ, −g)` with `h = |g|`, `c = sign(g) cosθ`,
/// as `(1 − h)(1 + h) / (4π ((1 − h)² + 2h(1 − c))^1.5)`: every term is non-negative, so
/// there is no cancellation as `g → ±1`; `1 − h` and `1 − c` are exact in f32. `|g| = 1`
/// (a delta) is evaluated at `|g| = `[`HG_G_MAX`]. Source: Henyey & Greenstein 1941, eq. 6
/// (docs/models/optics.md).
#[inline]
pub fn hg_phase(cos_theta: f32, g: f32) -> f32 {
    let h = g.abs().min(HG_G_MAX);
    let c = cos_theta.clamp(-1.0, 1.0);
    let c = if g < 0.0 { -c } else { c };
    let one_minus_h = 1.0 - h;
    let base = one_minus_h * one_minus_h + 2.0 * h * (1.0 - c);
    one_minus_h * (1.0 + h) / (4.0 * PI * base * sqrt(base))
}

/// WGSL of [`cos2_transmitted`], `mg_opth_cos2_t(cos_i, eta)`: the same expression. Shared by every
/// node that refracts (`refract`, the Fresnel helper, `skin_efresnel`) through `wgsl_uses`.
pub const COS2_T_WGSL: &str = r#"
fn mg_opth_cos2_t(cos_i: f32, eta: f32) -> f32 {
    return (1.0 - eta) * (1.0 + eta) + (eta * cos_i) * (eta * cos_i);
}
"#;

/// WGSL of [`cos2_transmitted_sin2`], `mg_opth_cos2_t_sin2(cos_i, sin2_i, eta)`. Needs
/// [`COS2_T_WGSL`].
pub const COS2_T_SIN2_WGSL: &str = r#"
fn mg_opth_cos2_t_sin2(cos_i: f32, sin2_i: f32, eta: f32) -> f32 {
    if (sin2_i < 0.5) {
        return 1.0 - (eta * eta) * sin2_i;
    }
    return mg_opth_cos2_t(cos_i, eta);
}
"#;

/// WGSL of [`fresnel_dielectric`] as a helper, `mg_opth_fresnel(cos_theta, ior_outside, ior_inside)`
/// returning (R, T), with [`same_scale`] and the shared terms: the same steps.
pub const FRESNEL_HELPER_WGSL: &str = r#"
fn mg_opth_same_scale(n1: f32, n2: f32) -> vec2<f32> {
    let e = min(frexp(max(max(n1, n2), 1.1754944e-38)).exp, 126);
    return vec2<f32>(ldexp(n1, -e), ldexp(n2, -e));
}
fn mg_opth_fresnel_terms(cos_i: f32, n1: f32, n2: f32, b2: f32) -> vec2<f32> {
    if (n1 == n2) {
        return vec2<f32>(0.0, 1.0);
    }
    if (b2 < 0.0) {
        return vec2<f32>(1.0, 0.0);
    }
    let b = sqrt(b2);
    let a = n1 * cos_i;
    let ap = (n2 * n2) * cos_i;
    let bp = n1 * b;
    let inv_s = 1.0 / (a + b);
    let inv_p = 1.0 / (ap + bp);
    let rs = (a - b) * inv_s;
    let rp = (ap - bp) * inv_p;
    let ts = 2.0 * (a * inv_s) * (b * inv_s);
    let tp = 2.0 * (ap * inv_p) * (bp * inv_p);
    return vec2<f32>(0.5 * (rs * rs + rp * rp), ts + tp);
}
fn mg_opth_fresnel(cos_theta: f32, ior_outside: f32, ior_inside: f32) -> vec2<f32> {
    var n1_in = ior_outside;
    var n2_in = ior_inside;
    var cos_i = min(cos_theta, 1.0);
    if (cos_theta < 0.0) {
        n1_in = ior_inside;
        n2_in = ior_outside;
        cos_i = min(-cos_theta, 1.0);
    }
    let n = mg_opth_same_scale(n1_in, n2_in);
    let b2 = (n.y - n.x) * (n.y + n.x) + (n.x * cos_i) * (n.x * cos_i);
    return mg_opth_fresnel_terms(cos_i, n.x, n.y, b2);
}
"#;

/// WGSL of [`fresnel_dielectric_sin2`], `mg_opth_fresnel_sin2(cos_i, sin2_i, n1, n2)`, and
/// [`fresnel_dielectric_cos2t`], `mg_opth_fresnel_cos2t(cos_i, cos2_t, n1, n2)`: the same
/// steps. Needs [`FRESNEL_HELPER_WGSL`].
pub const FRESNEL_KNOWN_ANGLE_WGSL: &str = r#"
fn mg_opth_fresnel_cos2t(cos_i: f32, cos2_t: f32, n1_in: f32, n2_in: f32) -> vec2<f32> {
    let n = mg_opth_same_scale(n1_in, n2_in);
    return mg_opth_fresnel_terms(min(cos_i, 1.0), n.x, n.y, (n.y * n.y) * cos2_t);
}
fn mg_opth_fresnel_sin2(cos_theta: f32, sin2_i: f32, n1_in: f32, n2_in: f32) -> vec2<f32> {
    let cos_i = min(cos_theta, 1.0);
    let n = mg_opth_same_scale(n1_in, n2_in);
    var b2 = (n.y - n.x) * (n.y + n.x) + (n.x * cos_i) * (n.x * cos_i);
    if (sin2_i < 0.5) {
        b2 = n.y * n.y - (n.x * n.x) * sin2_i;
    }
    return mg_opth_fresnel_terms(cos_i, n.x, n.y, b2);
}
"#;

/// WGSL of [`f0_to_ior`] as a helper, `mg_opth_f0_to_ior(f0)`; the cap 2⁴⁰ is written in hex,
/// which every WGSL compiler reads exactly.
pub const F0_TO_IOR_HELPER_WGSL: &str = r#"
fn mg_opth_f0_to_ior(f0_in: f32) -> f32 {
    let f0 = min(max(f0_in, 0.0), 1.0);
    let one_plus_s = 1.0 + sqrt(f0);
    if (f0 >= 1.0) {
        return 0x1p40f;
    }
    return min(one_plus_s * one_plus_s / (1.0 - f0), 0x1p40f);
}
"#;

/// WGSL of [`refract`].
const REFRACT_WGSL: &str = r#"
fn $fn(i: vec3<f32>, n: vec3<f32>, eta: f32) -> $out {
    let c = dot(n, i);
    let k = mg_opth_cos2_t(c, eta);
    if (k < 0.0) {
        return $out(i - 2.0 * c * n, true);
    }
    return $out(eta * i - (eta * c + sqrt(k)) * n, false);
}
"#;

/// WGSL of [`fresnel_schlick`].
const SCHLICK_WGSL: &str = r#"
fn $fn(cos_theta: f32, f0: $T) -> $T {
    let m = max(1.0 - min(max(cos_theta, 0.0), 1.0), 0.0);
    let m2 = m * m;
    return f0 + ($T(1.0) - f0) * (m2 * m2 * m);
}
"#;

/// WGSL of [`fresnel_empirical`]; `0^power` is spelled out (1 for power 0, else 0) because
/// WGSL's `pow` is undefined at a zero base.
const EMPIRICAL_WGSL: &str = r#"
fn $fn(i_dot_n: f32, bias: f32, scale: f32, power: f32) -> f32 {
    let base = max(1.0 + i_dot_n, 0.0);
    let p = select(pow(select(base, 1.0, base == 0.0), power), select(0.0, 1.0, power == 0.0), base == 0.0);
    return min(max(bias + scale * p, 0.0), 1.0);
}
"#;

/// WGSL of [`hg_phase`] as a helper, `mg_hg(cos_theta, g)`: the same steps. Nodes that need
/// the phase function (`hg_phase`, the skin's single scattering) declare it with `wgsl_uses`.
pub const HG_HELPER_WGSL: &str = r#"
fn mg_hg(cos_theta: f32, g: f32) -> f32 {
    let h = min(abs(g), 0.99999994);
    let c0 = min(max(cos_theta, -1.0), 1.0);
    let c = select(c0, -c0, g < 0.0);
    let one_minus_h = 1.0 - h;
    let base = one_minus_h * one_minus_h + 2.0 * h * (1.0 - c);
    return one_minus_h * (1.0 + h) / (4.0 * 3.14159265358979 * base * sqrt(base));
}
"#;

/// WGSL of [`fresnel_dielectric`], the same steps.
const FRESNEL_DIELECTRIC_WGSL: &str = r#"
fn $fn(cos_theta: f32, ior_outside: f32, ior_inside: f32) -> $out {
    let rt = mg_opth_fresnel(cos_theta, ior_outside, ior_inside);
    return $out(rt.x, rt.y);
}
"#;

/// The optics node types.
pub fn all() -> Vec<NodeType> {
    let f = Value::float;
    let v3 = Value::vec3;
    let grazing = |name: &'static str| [(name, f(1e-4))];
    vec![
        NodeType::new("reflect", Category::Optics, "Mirror reflection of an incident direction.")
            .source("R = I − 2 (N·I) N (Hecht, Optics §4.3; GLSL reflect; docs/models/optics.md). I points towards the surface.")
            .input(In::vec3("i", [0.0, 0.0, -1.0]).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Incident direction, towards the surface."))
            .input(In::vec3("n", [0.0, 0.0, 1.0]).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Unit surface normal."))
            .output(Out::vec3("r").doc("Reflected direction, away from the surface."))
            .wgsl("fn $fn(i: vec3<f32>, n: vec3<f32>) -> vec3<f32> { return i - 2.0 * dot(n, i) * n; }")
            .hard_case("grazing", &[("i", v3([1.0, 0.0, -1e-4]))])
            .compute(reflect),
        NodeType::new("refract", Category::Optics, "Snell refraction of an incident direction, with TIR flagged.")
            .source(
                "k = cos²θt = (1 − η)(1 + η) + η²(N·I)²; T = η I − (η N·I + √k) N (Hecht, Optics §4.4; \
                 GLSL refract with k rearranged so grazing rays at an index match pass straight; \
                 docs/models/optics.md), \
                 eta = n_incident / n_transmitted. Under total internal reflection (k < 0) t is the \
                 reflected direction and tir is true. Limit, stated: near the critical angle k is the \
                 difference of two terms near 1 − η², so its f32 rounding (about 2⁻²³) is amplified \
                 by the square root: at η = 2.4, 0.001° from the critical angle, t.z is 0.44% off \
                 (Mitsuba 3.9 and a 40-digit reference), as for fresnel_dielectric.",
            )
            .input(In::vec3("i", [0.0, 0.0, -1.0]).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Unit incident direction, towards the surface."))
            .input(In::vec3("n", [0.0, 0.0, 1.0]).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Unit normal on the incident side."))
            .input(In::float("eta", 1.0 / 1.5).range(0.2, 3.0).hard(0.0, 100.0).doc("n_incident / n_transmitted."))
            .output(Out::vec3("t").doc("Refracted direction (reflected under TIR)."))
            .output(Out::boolean("tir").doc("True under total internal reflection."))
            .wgsl(REFRACT_WGSL)
            .wgsl_uses(&[COS2_T_WGSL])
            .hard_case("grazing from air", &[("i", v3([1.0, 0.0, -1e-4])), ("eta", f(1.0 / 1.33))])
            .hard_case("just past the critical angle", &[("i", v3([0.7518, 0.0, -0.6594])), ("eta", f(1.33))])
            .hard_case("index match", &[("eta", f(1.0))])
            .compute(refract),
        NodeType::new("fresnel_dielectric", Category::Optics, "Exact unpolarised Fresnel reflectance of a dielectric.")
            .source(
                "R = (rs² + rp²)/2 and T = (ts² + tp²)/2 computed directly (not 1 − R), cos²θt = \
                 (1 − η²) + η²cos²θi (Fresnel's equations, Hecht, Optics §4.6 eqs. 4.34, 4.40; \
                 docs/models/optics.md; pbrt-v4 FrDielectric). cos_theta > 0: light arrives from the \
                 outside medium; < 0: from the inside, where TIR gives R = 1. R = 0 at an index match. \
                 Within 0.01° of the critical angle the f32 error of R reaches ~3e-4 (cos²θt cancels \
                 there; see docs/models/optics.md).",
            )
            .input(In::float("cos_theta", 1.0).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Cosine of the angle of incidence; sign gives the side."))
            .input(In::float("ior_outside", 1.0).range(1.0, 3.0).hard(1e-3, 100.0).doc("Index of refraction on the normal's side."))
            .input(In::float("ior_inside", 1.5).range(1.0, 3.0).hard(1e-3, 100.0).doc("Index of refraction behind the surface."))
            .output(Out::float("reflectance").doc("Fraction of power reflected."))
            .output(Out::float("transmittance").doc("Fraction of power transmitted, 1 − R (computed directly)."))
            .hard_case("grazing", &grazing("cos_theta"))
            .hard_case("exactly grazing", &[("cos_theta", f(0.0))])
            .hard_case("inside at the critical angle", &[("cos_theta", f(-0.6593)), ("ior_outside", f(1.0)), ("ior_inside", f(1.33))])
            .hard_case("index match", &[("ior_inside", f(1.0))])
            .hard_case("grazing at an index match", &[("cos_theta", f(1e-4)), ("ior_inside", f(1.0))])
            .hard_case("very grazing", &[("cos_theta", f(1e-7))])
            .compute(fresnel_dielectric)
            .wgsl(FRESNEL_DIELECTRIC_WGSL)
            .wgsl_uses(&[COS2_T_WGSL, FRESNEL_HELPER_WGSL]),
        NodeType::new("fresnel_schlick", Category::Optics, "Schlick's Fresnel approximation.")
            .source(
                "F = F0 + (1 − F0)(1 − cosθ)⁵ (Schlick 1994, eq. 24; docs/models/optics.md). f0 may be a \
                 colour (metals). cosθ is clamped to [0, 1]: below the surface (cosθ < 0) is shaded as \
                 grazing, F = 1, where the polynomial would exceed 1.",
            )
            .input(In::float("cos_theta", 1.0).range(0.0, 1.0).doc("Cosine of the angle of incidence (use cosθt from the dense side)."))
            .input(In::generic("f0", 0.04).range(0.0, 1.0).hard(0.0, 1.0).doc("Reflectance at normal incidence: a fraction (per channel for a colour)."))
            .output(Out::generic("reflectance").doc("Approximate reflectance."))
            .wgsl(SCHLICK_WGSL)
            .hard_case("grazing", &grazing("cos_theta"))
            .variant(Float, fresnel_schlick::<f32>)
            .variant(Vec3, fresnel_schlick::<Vec3>),
        NodeType::new("fresnel_empirical", Category::Optics, "The Cg Tutorial's empirical Fresnel.")
            .source(
                "F = clamp(bias + scale (1 + I·N)^power, 0, 1) (Fernando & Kilgard, The Cg Tutorial \
                 §7.4; seed 004). bias = F0, scale = 1 − F0, power = 5 gives Schlick.",
            )
            .input(In::float("i_dot_n", -1.0).range(-1.0, 0.0).hard(-1.0, 1.0).doc("I·N, I the incident direction (−1 at normal incidence)."))
            .input(In::float("bias", 0.04).range(0.0, 1.0).doc("Reflectance at normal incidence."))
            .input(In::float("scale", 0.96).range(0.0, 2.0).doc("Weight of the angular term."))
            .input(In::float("power", 5.0).range(0.5, 8.0).hard(0.0, 64.0).doc("Exponent of the angular term."))
            .output(Out::float("factor").doc("Reflection weight in [0, 1]."))
            .wgsl(EMPIRICAL_WGSL)
            .hard_case("grazing", &[("i_dot_n", f(-1e-4))])
            .compute(fresnel_empirical),
        NodeType::new("ior_to_f0", Category::Optics, "Normal-incidence reflectance from two indices.")
            .source("R0 = ((n1 − n2)/(n1 + n2))² (Hecht, Optics §4.6 eq. 4.47; seed 003).")
            .input(In::float("ior_outside", 1.0).range(1.0, 3.0).hard(1e-3, 100.0).doc("Index of refraction outside."))
            .input(In::float("ior_inside", 1.5).range(1.0, 3.0).hard(1e-3, 100.0).doc("Index of refraction inside."))
            .output(Out::float("f0").doc("Reflectance at normal incidence."))
            .wgsl("fn $fn(ior_outside: f32, ior_inside: f32) -> f32 { let r = (ior_outside - ior_inside) / (ior_outside + ior_inside); return r * r; }")
            .compute(ior_to_f0),
        NodeType::new("f0_to_ior", Category::Optics, "Index of refraction (from air) giving a normal-incidence reflectance.")
            .source(
                "n = (1 + √R0)/(1 − √R0) (seed 003), evaluated as (1 + √R0)²/(1 − R0), exact as R0 → 1; \
                 R0 = 1 (a perfect mirror, n = ∞) gives 2⁴⁰ (1.1e12), whose R0 is 1 in f32.",
            )
            .input(In::float("f0", 0.04).range(0.0, 0.9).hard(0.0, 1.0).doc("Reflectance at normal incidence."))
            .output(Out::float("ior").doc("Index of refraction relative to air."))
            .wgsl("fn $fn(f0: f32) -> f32 { return mg_opth_f0_to_ior(f0); }")
            .wgsl_uses(&[F0_TO_IOR_HELPER_WGSL])
            .hard_case("mirror", &[("f0", f(1.0))])
            .hard_case("nearly a mirror", &[("f0", f(0.99999))])
            .compute(f0_to_ior),
        NodeType::new("f0_to_specular", Category::Optics, "Unreal's Specular input from a normal-incidence reflectance.")
            .source("specular = R0 / 0.08, so 0.5 ↔ 4% ↔ n = 1.5 (seed 003).")
            .input(In::float("f0", 0.04).range(0.0, 0.2).hard(0.0, 1.0).doc("Reflectance at normal incidence."))
            .output(Out::float("specular").doc("Unreal Specular (0–1 covers R0 0–8%)."))
            .wgsl("fn $fn(f0: f32) -> f32 { return f0 / 0.08; }")
            .compute(f0_to_specular),
        NodeType::new("specular_to_f0", Category::Optics, "Normal-incidence reflectance from Unreal's Specular input.")
            .source("R0 = 0.08 · specular (seed 003).")
            .input(In::float("specular", 0.5).range(0.0, 1.0).hard(0.0, 12.5).doc("Unreal Specular."))
            .output(Out::float("f0").doc("Reflectance at normal incidence."))
            .wgsl("fn $fn(specular: f32) -> f32 { return 0.08 * specular; }")
            .compute(specular_to_f0),
        NodeType::new("hg_phase", Category::Optics, "Henyey–Greenstein phase function, normalised over the sphere.")
            .source(
                "p = (1 − g²)/(4π (1 + g² − 2g cosθ)^1.5) (Henyey & Greenstein 1941, eq. 6; docs/models/optics.md), \
                 evaluated with h = |g|, c = sign(g) cosθ as (1 − h)(1 + h)/(4π ((1 − h)² + \
                 2h(1 − c))^1.5), free of cancellation as g → ±1: accurate for every f32 |g| < 1. \
                 |g| = 1 (a delta) is evaluated at |g| = 1 − 2⁻²⁴, a 6e-8 rad lobe with a 4.5e13/sr peak.",
            )
            .input(In::float("cos_theta", 1.0).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Cosine between the propagation directions."))
            .input(In::float("g", 0.8).range(-0.99, 0.99).hard(-1.0, 1.0).doc("Mean cosine; > 0 scatters forward."))
            .output(Out::float("phase").unit("1/sr").doc("Probability density per steradian."))
            .wgsl("fn $fn(cos_theta: f32, g: f32) -> f32 { return mg_hg(cos_theta, g); }")
            .wgsl_uses(&[HG_HELPER_WGSL])
            .hard_case("strong forward peak", &[("cos_theta", f(1.0)), ("g", f(0.999))])
            .hard_case("strong backward peak", &[("cos_theta", f(-1.0)), ("g", f(-0.999))])
            .hard_case("g = 1", &[("cos_theta", f(1.0)), ("g", f(1.0))])
            .hard_case("g = -1", &[("cos_theta", f(-1.0)), ("g", f(-1.0))])
            .hard_case("isotropic", &[("g", f(0.0))])
            .hard_case("g = 1 − 2⁻¹⁷ at the peak", &[("cos_theta", f(1.0)), ("g", f(1.0 - 2f32.powi(-17)))])
            .hard_case("g = −(1 − 2⁻²⁰) off the peak", &[("cos_theta", f(-0.2655)), ("g", f(-(1.0 - 2f32.powi(-20))))])
            .compute(hg_phase),
    ]
}
