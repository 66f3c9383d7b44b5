//! The soap bubble of seed 000 (docs/models/bubble.md): film thickness with drainage, the
//! thickness-scaled internal and reflection vectors `d·R + d·T` and the two ways of showing
//! them as colour, texture flow, the rim light, the vertex wobble, the motion towards a
//! target, and the background: the "camera blend" of textures and the underwater quad with
//! two scrolling normal textures and an alpha texture.
//!
//! Section and equation numbers are those of the paper (seed 000, "Soap bubble shader",
//! §II.1.2–II.2.2, eqs. 3–12); the extracted text lost the equations' symbols, so each node
//! states how we read them. Conventions as in docs/models/README.md: `V` from the surface to
//! the eye, `N` out of the surface, `I = −V`.

use crate::node::{Category, In, NodeType, Out};
use crate::nodes::optics::{COS2_T_WGSL, cos2_transmitted};
use crate::nodes::precise::{self, SIN_COS_WGSL, sin_cos};
use crate::precision::{pow, sqrt};
use crate::value::Value;
use glam::{Vec2, Vec3};
use std::f32::consts::TAU;

/// `x` reduced to `[−π, π)` as `x − 2π·floor(x/2π + 1/2)`: the same sine and cosine, and
/// the same f32 steps on the CPU and in WGSL, whose `sin` and `cos` are only specified to
/// 2⁻¹¹ inside `[−π, π]`. The reduction itself is exact to the rounding of `x`.
#[inline]
pub fn wrap_phase(x: f32) -> f32 {
    x - TAU * (x * (1.0 / TAU) + 0.5).floor()
}

/// WGSL of [`wrap_phase`], `mg_bubble_wrap_phase(x)`: the same steps.
pub const WRAP_PHASE_WGSL: &str = r#"
fn mg_bubble_wrap_phase(x: f32) -> f32 {
    return x - 6.2831855 * floor(x * 0.15915494 + 0.5);
}
"#;

/// `1 − e^(−x)`, 0 for `x ≤ 0`, accurate where it is small (no cancellation) and computed
/// by the same f32 steps on the CPU and in WGSL (whose `exp` has no fixed precision), so
/// that an end value thousands of units from the start comes out the same on both:
/// `x = n ln 2 + r` (Cody and Waite's two-part ln 2, |r| ≤ 0.35), `q = 1 − e^(−r)` by its
/// Taylor series to r⁸ (truncation below 3e-10), `1 − e^(−x) = (1 − 2^−n) + 2^−n q`, with
/// `2^−n` built from its exponent bits; 1 for `x > 87`.
#[inline]
pub fn one_minus_exp_neg(x: f32) -> f32 {
    let x = x.max(0.0);
    if x > 87.0 {
        return 1.0;
    }
    let n = (x * std::f32::consts::LOG2_E + 0.5).floor();
    let r = (x - n * 0.693_145_75_f32) - n * 1.428_606_8e-6_f32;
    let q = r
        * (1.0
            - r * (0.5
                - r * (0.166_666_67
                    - r * (0.041_666_668
                        - r * (0.008_333_334
                            - r * (0.001_388_888_9
                                - r * (0.000_198_412_7 - r * 0.000_024_801_588)))))));
    let s = f32::from_bits(((127 - n as i32) as u32) << 23);
    (1.0 - s) + s * q
}

/// WGSL of [`one_minus_exp_neg`], `mg_bubble_one_minus_exp_neg(x)`: the same steps and
/// constants.
pub const ONE_MINUS_EXP_NEG_WGSL: &str = r#"
fn mg_bubble_one_minus_exp_neg(x_in: f32) -> f32 {
    let x = max(x_in, 0.0);
    if (x > 87.0) {
        return 1.0;
    }
    let n = floor(x * 1.442695 + 0.5);
    let r = (x - n * 0.69314575) - n * 1.4286068e-6;
    let q = r * (1.0 - r * (0.5 - r * (0.16666667 - r * (0.041666668 - r * (0.008333334 - r * (0.0013888889 - r * (0.0001984127 - r * 0.000024801588)))))));
    let s = bitcast<f32>(u32(127 - i32(n)) << 23u);
    return (1.0 - s) + s * q;
}
"#;

/// Choices of [`film_thickness`]'s `profile`.
pub const PROFILES: &[&str] = &["linear", "exponential"];

/// How far the drainage has gone at `time`, in [0, 1]: `linear`, `saturate(s·t)` (the
/// thickness moves at a constant rate and arrives after `1/s` seconds); `exponential`,
/// `1 − exp(−s·t)` (the limit of a per-frame `lerp(d, d_end, s·Δt)`). Negative times are 0.
#[inline]
pub fn drain_progress(time: f32, speed: f32, profile: i32) -> f32 {
    let st = speed * time.max(0.0);
    if profile == 1 {
        one_minus_exp_neg(st)
    } else {
        st.clamp(0.0, 1.0)
    }
}

/// Film thickness with drainage (seed 000 §II.1.2, eq. 3): the top thickness moves from
/// `top_start` to `top_end` and the bottom one from `bottom_start` to `bottom_end`, each by
/// linear interpolation with the progress `p` of [`drain_progress`]; the thickness at a
/// point blends bottom to top by its height `h` in [0, 1] (clamped):
/// `d = max(0, lerp(lerp(b0, b1, p), lerp(t0, t1, p), h))`.
///
/// Returns `(thickness, top, bottom)`. The clamp at 0 is a film's black limit: a `top_end`
/// below 0 makes the black film spread down from the top as the film drains.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn film_thickness(
    height: f32,
    time: f32,
    top_start: f32,
    top_end: f32,
    bottom_start: f32,
    bottom_end: f32,
    speed: f32,
    profile: i32,
) -> (f32, f32, f32) {
    let p = drain_progress(time, speed, profile);
    let top = top_start + (top_end - top_start) * p;
    let bottom = bottom_start + (bottom_end - bottom_start) * p;
    let h = height.clamp(0.0, 1.0);
    ((bottom + (top - bottom) * h).max(0.0), top, bottom)
}

const THICKNESS_WGSL: &str = r#"
fn $fn(height: f32, time: f32, top_start: f32, top_end: f32, bottom_start: f32, bottom_end: f32, speed: f32, profile: i32) -> $out {
    let st = speed * max(time, 0.0);
    var p = min(max(st, 0.0), 1.0);
    if (profile == 1) {
        p = mg_bubble_one_minus_exp_neg(st);
    }
    let top = top_start + (top_end - top_start) * p;
    let bottom = bottom_start + (bottom_end - bottom_start) * p;
    let h = min(max(height, 0.0), 1.0);
    return $out(max(bottom + (top - bottom) * h, 0.0), top, bottom);
}
"#;

/// The paper's internal and reflection vectors (seed 000 §II.1.2, eqs. 4–8).
///
/// `cos_i = V·N` (eq. 4), `sin_i = √(1 − cos_i²)`, `sin_t = (n1/n2) sin_i` (eq. 5). When
/// `sin_t ≥ 1` (total internal reflection) the internal vector is `I + 2 cos_i N`, the
/// incident vector plus the projection (eq. 6); otherwise the refraction
/// `T = η I + (η cos_i − cos_t) N`, `η = n1/n2` (eq. 7). The reflection is
/// `R = I − 2 (N·I) N` (eq. 8), and the result `d·R + d·T` with the thickness `d`.
/// `cos_t² = 1 − sin_t²` is evaluated as `(1 − η)(1 + η) + (η cos_i)²`
/// ([`cos2_transmitted`]), the same number without the cancellation of `1 − cos_i²`; TIR is
/// `cos_t² ≤ 0`. Where `V·N < 0` (an interpolated normal turned away at a silhouette) the
/// equations are applied as written.
///
/// Returns `(vector, direction, reflected, internal, tir)`, `direction` the unit vector
/// along `vector`, or `R` where `vector` is zero (`d = 0`, or normal incidence).
///
/// Near normal incidence `R` and `T` cancel: `R + T` is summed regrouped as
/// `(1 + η)(I + cos_i N) + (cos_i − cos_t) N` with `cos_i − cos_t` written
/// `(1 − η)(1 + η)(cos_i − 1)(cos_i + 1)/(cos_i + cos_t)` (for `cos_i ≥ 0`), so nothing cancels
/// and the sum is exactly 0 at normal incidence, whatever `√` returns. Summed as written, the
/// rounding of `cos_t` (up to 4 ULP on a conformant GPU) decided the sign of that zero, and the
/// direction came out as `+N` or `−N`.
#[inline]
pub fn internal_vector(
    view: Vec3,
    normal: Vec3,
    thickness: f32,
    n1: f32,
    n2: f32,
) -> (Vec3, Vec3, Vec3, Vec3, bool) {
    let i = -view;
    let cos_i = view.dot(normal);
    let eta = n1 / n2;
    let cos2_t = cos2_transmitted(cos_i, eta);
    let reflected = i + 2.0 * cos_i * normal;
    let tir = cos2_t <= 0.0;
    let internal = if tir {
        reflected
    } else {
        eta * i + (eta * cos_i - sqrt(cos2_t)) * normal
    };
    let vector = if tir || cos_i < 0.0 {
        thickness * reflected + thickness * internal
    } else {
        let along =
            (1.0 - eta) * (1.0 + eta) * (cos_i - 1.0) * (cos_i + 1.0) / (cos_i + sqrt(cos2_t));
        thickness * ((1.0 + eta) * (i + cos_i * normal) + along * normal)
    };
    let len2 = vector.dot(vector);
    let direction = if len2 > 0.0 && len2.is_finite() {
        vector / sqrt(len2)
    } else {
        reflected
    };
    (vector, direction, reflected, internal, tir)
}

const VECTOR_WGSL: &str = r#"
fn $fn(view: vec3<f32>, normal: vec3<f32>, thickness: f32, n1: f32, n2: f32) -> $out {
    let i = -view;
    let cos_i = dot(view, normal);
    let eta = n1 / n2;
    let cos2_t = mg_opth_cos2_t(cos_i, eta);
    let reflected = i + 2.0 * cos_i * normal;
    let tir = cos2_t <= 0.0;
    var internal = reflected;
    if (!tir) {
        internal = eta * i + (eta * cos_i - sqrt(cos2_t)) * normal;
    }
    var v = thickness * reflected + thickness * internal;
    if (!tir && cos_i >= 0.0) {
        let along = (1.0 - eta) * (1.0 + eta) * (cos_i - 1.0) * (cos_i + 1.0) / (cos_i + sqrt(cos2_t));
        v = thickness * ((1.0 + eta) * (i + cos_i * normal) + along * normal);
    }
    let len2 = dot(v, v);
    var direction = reflected;
    if (len2 > 0.0 && len2 <= 0x1.fffffep+127f) {
        direction = v / sqrt(len2);
    }
    return $out(v, direction, reflected, internal, tir);
}
"#;

/// Choices of [`vector_color`]'s `reading`.
pub const READINGS: &[&str] = &["rgb", "environment"];

/// The final vector shown as colour, the two readings of seed 000 Fig. 2 (the paper does
/// not say which): `rgb`, the vector remapped to RGB as a normal map is,
/// `saturate(0.5 + 0.5·v)` (the thickness scales the colour's distance from grey);
/// `environment`, the radiance looked up along the vector's direction, passed in as
/// `environment` (sample `scene:environment` at `equirect_uv(direction)`).
#[inline]
pub fn vector_color(vector: Vec3, environment: Vec3, reading: i32) -> Vec3 {
    if reading == 1 {
        environment
    } else {
        (Vec3::splat(0.5) + 0.5 * vector).clamp(Vec3::ZERO, Vec3::ONE)
    }
}

const VECTOR_COLOR_WGSL: &str = r#"
fn $fn(v: vec3<f32>, environment: vec3<f32>, reading: i32) -> vec3<f32> {
    if (reading == 1) {
        return environment;
    }
    return clamp(vec3<f32>(0.5) + 0.5 * v, vec3<f32>(0.0), vec3<f32>(1.0));
}
"#;

/// Texture flow (seed 000 §II.1.3, eq. 9): `uv' = uv + a·(sin(s t), cos(s t))`, the uv
/// circling with period `2π/s` (a larger flow speed `s`, a shorter period). The amplitude
/// `a` (1 in our reading of eq. 9) is ours. The phase is reduced by [`wrap_phase`].
#[inline]
pub fn texture_flow(uv: Vec2, time: f32, speed: f32, amplitude: f32) -> Vec2 {
    let phase = wrap_phase(speed * time);
    let (s, c) = sin_cos(phase);
    uv + amplitude * Vec2::new(s, c)
}

const FLOW_WGSL: &str = r#"
fn $fn(uv: vec2<f32>, time: f32, speed: f32, amplitude: f32) -> vec2<f32> {
    let phase = mg_bubble_wrap_phase(speed * time);
    return uv + amplitude * mg_prec_sincos(phase);
}
"#;

/// The rim light (seed 000 §II.1.3, eq. 10): `rim = (1 − saturate(V·N))^p`, brightest
/// where the view grazes the surface; a larger `p` narrows the rim. `0^p` is spelled out
/// (0 for `p > 0`, 1 for `p = 0`), as WGSL's `pow` is undefined at a zero base.
#[inline]
pub fn rim(view: Vec3, normal: Vec3, power: f32) -> f32 {
    let base = 1.0 - view.dot(normal).clamp(0.0, 1.0);
    if base == 0.0 {
        if power == 0.0 { 1.0 } else { 0.0 }
    } else {
        pow(base, power)
    }
}

const RIM_WGSL: &str = r#"
fn $fn(view: vec3<f32>, normal: vec3<f32>, power: f32) -> f32 {
    let base = 1.0 - min(max(dot(view, normal), 0.0), 1.0);
    return select(pow(select(base, 1.0, base == 0.0), power), select(0.0, 1.0, power == 0.0), base == 0.0);
}
"#;

/// The vertex wobble (seed 000 §II.1.4, eq. 11): each coordinate offset by a small sine or
/// cosine of time at frequency `f`,
/// `(A sin(f t + k p_y), A cos(f t + k p_z), A sin(f t + k p_x))`. The phase term `k p` of
/// the point's own (object-space) coordinates is our reading of the paper's "squirming":
/// with `k = 0` it is eq. 11 literally, a rigid shake. Phases reduced by [`wrap_phase`].
#[inline]
pub fn wobble(position: Vec3, time: f32, frequency: f32, amplitude: f32, wavenumber: f32) -> Vec3 {
    let ft = frequency * time;
    let s = |c: f32| wrap_phase(ft + wavenumber * c);
    amplitude
        * Vec3::new(
            sin_cos(s(position.y)).0,
            sin_cos(s(position.z)).1,
            sin_cos(s(position.x)).0,
        )
}

const WOBBLE_WGSL: &str = r#"
fn $fn(p: vec3<f32>, time: f32, frequency: f32, amplitude: f32, wavenumber: f32) -> vec3<f32> {
    let ft = frequency * time;
    let x = mg_bubble_wrap_phase(ft + wavenumber * p.y);
    let y = mg_bubble_wrap_phase(ft + wavenumber * p.z);
    let z = mg_bubble_wrap_phase(ft + wavenumber * p.x);
    return amplitude * vec3<f32>(mg_prec_sincos(x).x, mg_prec_sincos(y).y, mg_prec_sincos(z).x);
}
"#;

/// The bubble's motion towards a target (seed 000 §II.1.4): the paper moves it from its
/// position towards the destination by linear interpolation each frame,
/// `p ← lerp(p, target, k Δt)`; over time that is the exponential approach
/// `p(t) = target + (start − target)·exp(−k t)`, which this returns as the offset from the
/// start, `(target − start)(1 − exp(−k t))`, with the position. Negative times are 0.
/// Per frame at a finite rate the discrete form `(1 − kΔt)^(t/Δt)` differs by O(kΔt): at
/// 60 frames/s and `k t = 1`, 0.3632 against e⁻¹ = 0.3679.
#[inline]
pub fn motion(start: Vec3, target: Vec3, rate: f32, time: f32) -> (Vec3, Vec3) {
    let w = one_minus_exp_neg(rate * time.max(0.0));
    let offset = (target - start) * w;
    (offset, start + offset)
}

const MOTION_WGSL: &str = r#"
fn $fn(start: vec3<f32>, goal: vec3<f32>, rate: f32, time: f32) -> $out {
    let w = mg_bubble_one_minus_exp_neg(rate * max(time, 0.0));
    let offset = (goal - start) * w;
    return $out(offset, start + offset);
}
"#;

/// The camera blend (seed 000 §II.2.1, eq. 12): two texture layers scaled by their
/// intensities and mixed by `mix`, applied over the current screen image `base` by the
/// amount `amount`: `lerp(base, lerp(i_a A, i_b B, mix), amount)`.
#[inline]
pub fn camera_blend(
    base: Vec3,
    layer_a: Vec3,
    layer_b: Vec3,
    intensity_a: f32,
    intensity_b: f32,
    mix: f32,
    amount: f32,
) -> Vec3 {
    let a = intensity_a * layer_a;
    let b = intensity_b * layer_b;
    let layers = a + (b - a) * mix;
    base + (layers - base) * amount
}

const CAMERA_BLEND_WGSL: &str = r#"
fn $fn(base: vec3<f32>, layer_a: vec3<f32>, layer_b: vec3<f32>, intensity_a: f32, intensity_b: f32, m: f32, amount: f32) -> vec3<f32> {
    let a = intensity_a * layer_a;
    let b = intensity_b * layer_b;
    let layers = a + (b - a) * m;
    return base + (layers - base) * amount;
}
"#;

/// The uvs of the underwater quad's two normal textures scrolled over time (seed 000
/// §II.2.2): `uv + fract(v t)` for each velocity. The `fract` keeps the offsets small and
/// changes nothing under repeat wrapping.
#[inline]
pub fn underwater_uv(uv: Vec2, time: f32, velocity_a: Vec2, velocity_b: Vec2) -> (Vec2, Vec2) {
    let fract = |v: Vec2| v - v.floor();
    (uv + fract(velocity_a * time), uv + fract(velocity_b * time))
}

const UNDERWATER_UV_WGSL: &str = r#"
fn $fn(uv: vec2<f32>, time: f32, velocity_a: vec2<f32>, velocity_b: vec2<f32>) -> $out {
    let a = velocity_a * time;
    let b = velocity_b * time;
    return $out(uv + (a - floor(a)), uv + (b - floor(b)));
}
"#;

/// The underwater shimmer (seed 000 §II.2.2): the two normal textures decoded
/// (`n = 2c − 1`) and summed, `n = normalize(n_a + n_b)` (`+z` where the sum is zero), lit
/// by the light direction `l` (normalised; `+z` for a zero vector) in the quad's tangent
/// space: `color = tint · strength · saturate(n·l)^sharpness`, and the quad's coverage
/// `alpha = saturate(alpha_map · opacity)`. The sum of the normals, the lighting and the
/// sharpness exponent are ours (the paper names only the textures); the scene adds
/// `alpha · color` to the backdrop, as light.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn underwater(
    normal_a: Vec3,
    normal_b: Vec3,
    alpha: f32,
    light: Vec3,
    tint: Vec3,
    strength: f32,
    sharpness: f32,
    opacity: f32,
) -> (Vec3, f32) {
    let sum = (2.0 * normal_a - Vec3::ONE) + (2.0 * normal_b - Vec3::ONE);
    let n = safe_unit(sum);
    let l = safe_unit(light);
    let c = n.dot(l).clamp(0.0, 1.0);
    // 0^sharpness spelled out, as in the WGSL.
    let lit = if c == 0.0 {
        if sharpness == 0.0 { 1.0 } else { 0.0 }
    } else {
        // The node's own pow (nodes/precise.rs): WGSL's log2 near 1 times a sharpness of 256
        // would be 3.7e-4 of the streak.
        precise::pow(c, sharpness)
    };
    (tint * (strength * lit), (alpha * opacity).clamp(0.0, 1.0))
}

/// `v / |v|`, or `+z` where `|v|` is 0 or not finite.
#[inline]
fn safe_unit(v: Vec3) -> Vec3 {
    let l2 = v.dot(v);
    if l2 > 0.0 && l2.is_finite() {
        v / sqrt(l2)
    } else {
        Vec3::Z
    }
}

/// WGSL of `safe_unit`, `mg_bubble_safe_unit(v)`: the same steps.
const SAFE_UNIT_WGSL: &str = r#"
fn mg_bubble_safe_unit(v: vec3<f32>) -> vec3<f32> {
    let l2 = dot(v, v);
    if (l2 > 0.0 && l2 <= 0x1.fffffep+127f) {
        return v / sqrt(l2);
    }
    return vec3<f32>(0.0, 0.0, 1.0);
}
"#;

const UNDERWATER_WGSL: &str = r#"
fn $fn(normal_a: vec3<f32>, normal_b: vec3<f32>, alpha: f32, light: vec3<f32>, tint: vec3<f32>, strength: f32, sharpness: f32, opacity: f32) -> $out {
    let n = mg_bubble_safe_unit((2.0 * normal_a - vec3<f32>(1.0)) + (2.0 * normal_b - vec3<f32>(1.0)));
    let l = mg_bubble_safe_unit(light);
    let c = min(max(dot(n, l), 0.0), 1.0);
    let lit = select(mg_prec_pow(select(c, 1.0, c == 0.0), sharpness), select(0.0, 1.0, sharpness == 0.0), c == 0.0);
    return $out(tint * (strength * lit), min(max(alpha * opacity, 0.0), 1.0));
}
"#;

/// The bubble node types.
pub fn all() -> Vec<NodeType> {
    let f = Value::float;
    let v3 = Value::vec3;
    vec![
        NodeType::new("bubble_thickness", Category::Bubble, "Soap film thickness with drainage: the top thins, the bottom thickens.")
            .source(
                "Seed 000 §II.1.2 eq. 3 (docs/models/bubble.md): top = lerp(top_start, top_end, p), bottom = \
                 lerp(bottom_start, bottom_end, p), thickness = max(0, lerp(bottom, top, saturate(height))), with \
                 the progress p = saturate(speed·time) (linear) or 1 − exp(−speed·time) (exponential, the limit \
                 of a per-frame lerp); negative times count as 0. The clamp at 0 is the black film: a top_end \
                 below 0 spreads it down from the top. Units are the caller's (the paper's unitless d, or nm for \
                 thin_film).",
            )
            .input(In::float("height", 0.5).range(0.0, 1.0).hard(-1e4, 1e4).doc("Height on the bubble, 0 at the bottom to 1 at the top (clamped)."))
            .input(In::float("time", 0.0).range(0.0, 10.0).hard(-1e6, 1e6).unit("s").doc("Time since the film was made."))
            .input(In::float("top_start", 0.8).range(0.0, 2000.0).hard(-1e4, 1e4).doc("Thickness at the top at time 0."))
            .input(In::float("top_end", 0.2).range(-500.0, 2000.0).hard(-1e4, 1e4).doc("Thickness at the top once drained (below 0: black film spreading)."))
            .input(In::float("bottom_start", 1.2).range(0.0, 2000.0).hard(-1e4, 1e4).doc("Thickness at the bottom at time 0."))
            .input(In::float("bottom_end", 1.8).range(0.0, 2000.0).hard(-1e4, 1e4).doc("Thickness at the bottom once drained."))
            .input(In::float("speed", 2.0).range(0.0, 10.0).hard(0.0, 1e4).unit("1/s").doc("Thickness change speed (the paper's 2)."))
            .input(In::choice("profile", PROFILES, 0).doc("Progress over time: linear ramp or exponential approach."))
            .output(Out::float("thickness").doc("Film thickness at the point, ≥ 0."))
            .output(Out::float("top").doc("Thickness at the top (may be below 0)."))
            .output(Out::float("bottom").doc("Thickness at the bottom."))
            .wgsl(THICKNESS_WGSL)
            .wgsl_uses(&[ONE_MINUS_EXP_NEG_WGSL])
            .hard_case("drained, black film spreading", &[("height", f(0.9)), ("time", f(1.0)), ("top_start", f(600.0)), ("top_end", f(-300.0)), ("bottom_start", f(600.0)), ("bottom_end", f(1200.0))])
            .hard_case("long after, exponential", &[("time", f(1e5)), ("profile", Value::int(1))])
            .hard_case("before the start", &[("time", f(-3.0)), ("profile", Value::int(1))])
            .hard_case("no drainage", &[("speed", f(0.0))])
            .compute(film_thickness),
        NodeType::new("bubble_vector", Category::Bubble, "The bubble's final vector d·R + d·T: Snell refraction (reflection under TIR) plus reflection, scaled by the thickness.")
            .source(
                "Seed 000 §II.1.2 eqs. 4–8 (docs/models/bubble.md): cos_i = V·N, sin_t = (n1/n2) sin_i; TIR \
                 (sin_t ≥ 1): internal = I + 2 cos_i N (eq. 6); else internal = η I + (η cos_i − cos_t) N, η = \
                 n1/n2 (eq. 7); R = I − 2(N·I)N; vector = d·R + d·internal (eq. 8), I = −V. cos_t² is evaluated \
                 as (1 − η)(1 + η) + (η cos_i)², free of the cancellation in 1 − cos_i². Applied as written where \
                 V·N < 0. direction is the unit vector along it (R where it is zero).",
            )
            .input(In::vec3("view", [0.0, 0.0, 1.0]).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Unit direction from the surface to the eye (V)."))
            .input(In::vec3("normal", [0.0, 0.0, 1.0]).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Unit surface normal (N)."))
            .input(In::float("thickness", 1.0).range(0.0, 2.0).hard(-10.0, 10.0).doc("Film thickness d scaling both vectors."))
            .input(In::float("n1", 1.0).range(1.0, 2.0).hard(1e-3, 100.0).doc("Refractive index outside (air, the paper's 1)."))
            .input(In::float("n2", 1.33).range(1.0, 2.0).hard(1e-3, 100.0).doc("Refractive index of the film (the paper's 1.33)."))
            .output(Out::vec3("vector").doc("d·R + d·T, the paper's final vector."))
            .output(Out::vec3("direction").doc("Unit vector along it (R where it is zero), for an environment lookup."))
            .output(Out::vec3("reflected").doc("R, the mirror reflection of I."))
            .output(Out::vec3("internal").doc("T, the refracted vector (the reflection under TIR)."))
            .output(Out::boolean("tir").doc("True under total internal reflection (sin_t ≥ 1)."))
            .wgsl(VECTOR_WGSL)
            .wgsl_uses(&[COS2_T_WGSL])
            .hard_case("grazing", &[("view", v3([1.0, 0.0, 1e-4]))])
            .hard_case("exactly grazing", &[("view", v3([1.0, 0.0, 0.0]))])
            .hard_case("TIR from the dense side", &[("view", v3([0.8, 0.0, 0.6])), ("n1", f(1.33)), ("n2", f(1.0))])
            .hard_case("just past the critical angle", &[("view", v3([0.7518, 0.0, 0.6594])), ("n1", f(1.33)), ("n2", f(1.0))])
            .hard_case("index match", &[("n2", f(1.0))])
            .hard_case("zero thickness", &[("thickness", f(0.0))])
            .hard_case("normal turned away", &[("view", v3([0.6, 0.0, -0.8]))])
            .compute(internal_vector),
        NodeType::new("bubble_vector_color", Category::Bubble, "The final vector as colour: remapped to RGB, or the environment along it.")
            .source(
                "Seed 000 Fig. 2 shows the vector as colour without saying how (docs/models/bubble.md): rgb \
                 gives saturate(0.5 + 0.5·v), the normal-map remap (the clamp keeps |v| > 1 in gamut); \
                 environment passes the radiance looked up along the vector (link image_texture of \
                 scene:environment at equirect_uv of bubble_vector.direction).",
            )
            .input(In::vec3("vector", [0.0, 0.0, 1.0]).range(-2.0, 2.0).doc("The bubble's final vector."))
            .input(In::color("environment", [0.0, 0.0, 0.0]).range(0.0, 4.0).doc("Radiance along the vector's direction (used by the environment reading)."))
            .input(In::choice("reading", READINGS, 0).doc("How the vector becomes colour."))
            .output(Out::color("color").doc("The colour shown."))
            .wgsl(VECTOR_COLOR_WGSL)
            .hard_case("long vector", &[("vector", v3([3.0, -3.0, 0.5]))])
            .compute(vector_color),
        NodeType::new("bubble_flow", Category::Bubble, "Texture flow: the uv circling over time at the flow speed.")
            .source(
                "Seed 000 §II.1.3 eq. 9 (docs/models/bubble.md): uv' = uv + amplitude·(sin(s t), cos(s t)), \
                 period 2π/s (the paper's s = 0.4); the phase s t is reduced to [−π, π) first.",
            )
            .input(In::vec2("uv", [0.5, 0.5]).range(-2.0, 2.0).doc("Texture coordinates of the surface."))
            .input(In::float("time", 0.0).range(0.0, 100.0).unit("s").doc("Time."))
            .input(In::float("speed", 0.4).range(0.0, 4.0).unit("rad/s").doc("Flow speed s (the paper's 0.4)."))
            .input(In::float("amplitude", 1.0).range(0.0, 2.0).doc("Radius of the circle in uv (1 in our reading of eq. 9)."))
            .output(Out::vec2("uv").doc("The flowed texture coordinates."))
            .wgsl(FLOW_WGSL)
            .wgsl_uses(&[WRAP_PHASE_WGSL, SIN_COS_WGSL])
            .hard_case("a minute in", &[("time", f(60.0)), ("speed", f(4.0))])
            .hard_case("phase at π", &[("time", f(std::f32::consts::PI)), ("speed", f(1.0))])
            .compute(texture_flow),
        NodeType::new("bubble_rim", Category::Bubble, "Rim light (1 − saturate(V·N))^p.")
            .source(
                "Seed 000 §II.1.3 eq. 10 (docs/models/bubble.md): rim = (1 − saturate(V·N))^p, p the rim \
                 exponent (the paper's 2.8); 0^p is 0 for p > 0 and 1 for p = 0.",
            )
            .input(In::vec3("view", [0.0, 0.0, 1.0]).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Unit direction from the surface to the eye (V)."))
            .input(In::vec3("normal", [0.0, 0.0, 1.0]).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Unit surface normal (N)."))
            .input(In::float("power", 2.8).range(0.5, 8.0).hard(0.0, 64.0).doc("Rim exponent p (the paper's 2.8)."))
            .output(Out::float("rim").doc("Rim intensity in [0, 1]."))
            .wgsl(RIM_WGSL)
            .hard_case("facing, p = 0", &[("power", f(0.0))])
            .hard_case("grazing", &[("view", v3([1.0, 0.0, 1e-4]))])
            .hard_case("behind", &[("view", v3([0.0, 0.0, -1.0]))])
            .compute(rim),
        NodeType::new("bubble_wobble", Category::Bubble, "Vertex wobble: small sine and cosine offsets of time, as a displacement.")
            .source(
                "Seed 000 §II.1.4 eq. 11 (docs/models/bubble.md): displacement = A·(sin(f t + k p_y), \
                 cos(f t + k p_z), sin(f t + k p_x)), f the frequency; the phase k p from the point's \
                 object-space coordinates is our reading (k = 0 is the literal, rigid shake). Phases are \
                 reduced to [−π, π) first. Link it to a `displacement` output.",
            )
            .input(In::vec3("position", [0.0, 0.0, 1.0]).range(-2.0, 2.0).doc("Object-space point (the normal, on a unit sphere)."))
            .input(In::float("time", 0.0).range(0.0, 100.0).unit("s").doc("Time."))
            .input(In::float("frequency", 2.0).range(0.0, 10.0).unit("rad/s").doc("Angular frequency f of the wobble."))
            .input(In::float("amplitude", 0.03).range(0.0, 0.2).unit("m").doc("Size A of the offsets."))
            .input(In::float("wavenumber", 3.0).range(0.0, 10.0).doc("Phase k per unit of position."))
            .output(Out::vec3("displacement").unit("m").doc("Offset of the vertex."))
            .wgsl(WOBBLE_WGSL)
            .wgsl_uses(&[WRAP_PHASE_WGSL, SIN_COS_WGSL])
            .hard_case("rigid shake", &[("wavenumber", f(0.0)), ("time", f(1.0))])
            .hard_case("a minute in", &[("time", f(60.0)), ("frequency", f(10.0))])
            .compute(wobble),
        NodeType::new("bubble_motion", Category::Bubble, "The bubble's offset on its way to a target: repeated lerp, an exponential approach.")
            .source(
                "Seed 000 §II.1.4 (docs/models/bubble.md): the per-frame p ← lerp(p, target, k Δt) in closed \
                 form, offset = (target − start)(1 − exp(−k t)), position = start + offset; negative times \
                 count as 0. At a finite frame rate the discrete approach differs by O(kΔt).",
            )
            .input(In::vec3("start", [0.0, 0.0, 0.0]).range(-10.0, 10.0).unit("m").doc("Position at time 0."))
            .input(In::vec3("target", [1.0, 0.0, 0.0]).range(-10.0, 10.0).unit("m").doc("Destination."))
            .input(In::float("rate", 1.0).range(0.0, 10.0).hard(0.0, 1e4).unit("1/s").doc("Lerp factor per second k."))
            .input(In::float("time", 0.0).range(0.0, 100.0).hard(-1e6, 1e6).unit("s").doc("Time."))
            .output(Out::vec3("offset").unit("m").doc("Offset from the start (a displacement)."))
            .output(Out::vec3("position").unit("m").doc("Position at time t."))
            .wgsl(MOTION_WGSL)
            .wgsl_uses(&[ONE_MINUS_EXP_NEG_WGSL])
            .hard_case("arrived", &[("time", f(1e6)), ("rate", f(1e4))])
            .hard_case("before the start", &[("time", f(-1.0))])
            .compute(motion),
        NodeType::new("bubble_camera_blend", Category::Bubble, "The camera blend: two texture layers at their intensities, mixed, over the screen image.")
            .source(
                "Seed 000 §II.2.1 eq. 12 (docs/models/bubble.md): lerp(base, lerp(i_a·A, i_b·B, mix), amount), \
                 base the current screen image, A and B the texture layers.",
            )
            .input(In::color("base", [0.0, 0.0, 0.0]).range(0.0, 1.0).doc("The current screen image."))
            .input(In::color("layer_a", [1.0, 1.0, 1.0]).range(0.0, 1.0).doc("First texture layer."))
            .input(In::color("layer_b", [1.0, 1.0, 1.0]).range(0.0, 1.0).doc("Second texture layer."))
            .input(In::float("intensity_a", 1.0).range(0.0, 4.0).doc("Intensity of the first layer."))
            .input(In::float("intensity_b", 1.0).range(0.0, 4.0).doc("Intensity of the second layer."))
            .input(In::float("mix", 0.5).range(0.0, 1.0).doc("Blend from layer a (0) to layer b (1)."))
            .input(In::float("amount", 0.8).range(0.0, 1.0).doc("How much of the blend is applied over the base."))
            .output(Out::color("color").doc("The blended background."))
            .wgsl(CAMERA_BLEND_WGSL)
            .compute(camera_blend),
        NodeType::new("bubble_underwater_uv", Category::Bubble, "The underwater quad's two normal-texture uvs, scrolled over time.")
            .source(
                "Seed 000 §II.2.2 (docs/models/bubble.md): uv_a = uv + fract(velocity_a·t), uv_b = uv + \
                 fract(velocity_b·t); the fract changes nothing under repeat wrapping and keeps the offsets small.",
            )
            .input(In::vec2("uv", [0.5, 0.5]).range(-2.0, 2.0).doc("Texture coordinates on the quad."))
            .input(In::float("time", 0.0).range(0.0, 100.0).unit("s").doc("Time."))
            .input(In::vec2("velocity_a", [0.03, 0.01]).range(-0.5, 0.5).unit("1/s").doc("Scroll velocity of the first normal texture."))
            .input(In::vec2("velocity_b", [-0.02, 0.025]).range(-0.5, 0.5).unit("1/s").doc("Scroll velocity of the second normal texture."))
            .output(Out::vec2("uv_a").doc("Where to sample the first normal texture."))
            .output(Out::vec2("uv_b").doc("Where to sample the second normal texture."))
            .wgsl(UNDERWATER_UV_WGSL)
            .hard_case("an hour in", &[("time", f(3600.0))])
            .compute(underwater_uv),
        NodeType::new("bubble_underwater", Category::Bubble, "The underwater shimmer from two normal textures and an alpha texture.")
            .source(
                "Seed 000 §II.2.2 (docs/models/bubble.md): n = normalize((2a − 1) + (2b − 1)) of the two sampled \
                 normal textures (+z where zero), color = tint·strength·saturate(n·l)^sharpness with l the \
                 normalised light (+z where zero), alpha = saturate(alpha_map·opacity). The normal sum, lighting \
                 and exponent are our reading; the paper names only the textures.",
            )
            .input(In::color("normal_a", [0.5, 0.5, 1.0]).range(0.0, 1.0).doc("First normal texture sample (encoded 0.5 + 0.5 n)."))
            .input(In::color("normal_b", [0.5, 0.5, 1.0]).range(0.0, 1.0).doc("Second normal texture sample (encoded 0.5 + 0.5 n)."))
            .input(In::float("alpha", 1.0).range(0.0, 1.0).doc("Alpha texture sample."))
            .input(In::vec3("light", [0.3, 0.4, 0.866]).range(-1.0, 1.0).doc("Direction of the sunlight in the quad's tangent space."))
            .input(In::color("tint", [0.6, 0.9, 1.0]).range(0.0, 1.0).doc("Colour of the shimmer."))
            .input(In::float("strength", 1.0).range(0.0, 4.0).doc("Brightness of the shimmer."))
            .input(In::float("sharpness", 8.0).range(0.0, 32.0).hard(0.0, 256.0).doc("Exponent narrowing the bright streaks."))
            .input(In::float("opacity", 0.5).range(0.0, 1.0).doc("Scale on the alpha texture."))
            .output(Out::color("color").doc("Light of the shimmer."))
            .output(Out::float("alpha").doc("Coverage of the quad in [0, 1]."))
            .wgsl(UNDERWATER_WGSL)
            .wgsl_uses(&[SAFE_UNIT_WGSL, precise::LOG2_EXACT_WGSL, precise::POW_WGSL])
            .hard_case("flat, opposite normals", &[("normal_a", v3([0.0, 0.0, 0.5])), ("normal_b", v3([1.0, 1.0, 0.5]))])
            .hard_case("zero light, sharpness 0", &[("light", v3([0.0, 0.0, 0.0])), ("sharpness", f(0.0))])
            .hard_case("light from below", &[("light", v3([0.0, 0.0, -1.0]))])
            .hard_case("huge alpha", &[("alpha", f(1e6))])
            .compute(underwater),
    ]
}
