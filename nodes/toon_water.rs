//! Environment-adaptive cartoon water (seed 004; docs/models/toon_water.md): the depth colour
//! `v`, the incident light after the atmosphere `s`, the base colour `w·v·s`, the modified
//! Blinn–Phong toon shading with a stepped 1D ramp, the simplified Fresnel that mixes the
//! reflection and refraction maps, and Gerstner waves with their exact normal.
//!
//! Source: "Environment-adaptive real-time cartoon-style fluid rendering for cartoon-style
//! games" (Journal of Korea Game Society 12(5), 2012, pp. 57–66), eqs. 1–3, 7, 8, 10–13; the
//! extracted text lost the equations' symbols, so our readings are stated per node and in
//! docs/models/toon_water.md. Waves: Finch, "Effective Water Simulation from Physical
//! Models", GPU Gems (2004), ch. 1, eqs. 9 (Gerstner surface) and 12 (its normal).
//!
//! Conventions: world space is `y` up (the water plane is `y = 0`), depth is positive down,
//! `n`, `l`, `v` are the normal, the direction to the light and to the eye.

use crate::node::{Category, In, NodeType, Out, WgslChoice};
use crate::nodes::precise::{self, SIN_COS_WGSL, sin_cos};
use crate::precision::{cross, exp, sqrt};
use crate::value::Value;
use glam::{Vec2, Vec3, Vec4};
use std::f32::consts::{LN_2, TAU};

use super::optics::fresnel_empirical;
use super::texture::ramp;

/// Standard gravity, m/s², in the deep-water dispersion `ω = √(g k)`.
pub const GRAVITY: f32 = 9.80665;

/// The most waves a [`gerstner_waves`] node sums.
pub const MAX_WAVES: usize = 8;

/// Choice of [`depth_color`]: the paper's `exp(−√(k·d))`.
pub const DEPTH_PAPER: i32 = 0;
/// Choice of [`depth_color`]: Beer–Lambert `exp(−k·d)`.
pub const DEPTH_BEER_LAMBERT: i32 = 1;
/// Names of the `model` choices of `toon_water_depth_color`, in index order.
pub const DEPTH_MODELS: &[&str] = &["paper", "beer_lambert"];

/// The time-of-day presets of seed 004 (§3.2, Fig. 10): the incident intensity `I0` per
/// channel. `custom` (index 0) takes the node's `light_color` instead.
pub const TIME_OF_DAY: [(&str, [f32; 3]); 4] = [
    ("sunrise", [0.8, 0.3, 0.0]),
    ("day", [0.7, 0.7, 0.7]),
    ("sunset", [0.8, 0.3, 0.0]),
    ("night", [0.25, 0.25, 0.25]),
];
/// Names of the `time_of_day` choices of `toon_water_sky_light`, in index order.
pub const TIME_OF_DAY_NAMES: &[&str] = &["custom", "sunrise", "day", "sunset", "night"];

/// The absorption coefficient `k` of one channel with half-life `h` (m) in depth model
/// `model`, chosen so that both models halve the colour at `d = h`:
/// paper `exp(−√(k h)) = ½ ⇒ k = (ln 2)² / h`; Beer–Lambert `exp(−k h) = ½ ⇒ k = ln 2 / h`.
#[inline]
pub fn depth_k(half_life: f32, model: i32) -> f32 {
    if model == DEPTH_BEER_LAMBERT {
        LN_2 / half_life
    } else {
        LN_2 * LN_2 / half_life
    }
}

/// Seed 004 eq. 2, the colour of the water by depth, per channel `c`:
/// `v_c = exp(−√(k_c · d))` (`paper`) or `v_c = exp(−k_c · d)` (`beer_lambert`), `k_c` from
/// the half-life by [`depth_k`], so that `v_c(h_c) = ½` in both; the paper's model is
/// `2^(−√(d/h))`, Beer–Lambert `2^(−d/h)`. Depth below 0 reads as 0 (colour 1); a
/// half-life below 1 mm reads as 1 mm (hard range).
#[inline]
pub fn depth_color(depth: f32, half_life: Vec3, model: i32) -> Vec3 {
    let d = depth.max(0.0);
    let h = half_life.max(Vec3::splat(1e-3));
    let channel = |h: f32| {
        let k = depth_k(h, model);
        if model == DEPTH_BEER_LAMBERT {
            exp(-k * d)
        } else {
            exp(-sqrt(k * d))
        }
    };
    Vec3::new(channel(h.x), channel(h.y), channel(h.z))
}

/// WGSL of [`depth_color`], the same steps.
const DEPTH_COLOR_WGSL: &str = r#"
fn $fn(depth: f32, half_life: vec3<f32>, model: i32) -> vec3<f32> {
    let d = max(depth, 0.0);
    let h = max(half_life, vec3<f32>(1e-3));
    return vec3<f32>(mg_tw_depth_channel${model}(d, h.x, model), mg_tw_depth_channel${model}(d, h.y, model), mg_tw_depth_channel${model}(d, h.z, model));
}
"#;

/// One channel of [`DEPTH_COLOR_WGSL`], `model` paper (it takes `model` and ignores it).
const DEPTH_PAPER_WGSL: &str = r#"
fn mg_tw_depth_channel_paper(d: f32, h: f32, model: i32) -> f32 {
    let k = 0.6931472 * 0.6931472 / h;
    return exp(-sqrt(k * d));
}
"#;

/// One channel of [`DEPTH_COLOR_WGSL`], `model` beer_lambert.
const DEPTH_BEER_LAMBERT_WGSL: &str = r#"
fn mg_tw_depth_channel_beer_lambert(d: f32, h: f32, model: i32) -> f32 {
    let k = 0.6931472 / h;
    return exp(-k * d);
}
"#;

/// One channel of [`DEPTH_COLOR_WGSL`], `model` chosen at run time.
const DEPTH_CHANNEL_WGSL: &str = r#"
fn mg_tw_depth_channel(d: f32, h: f32, model: i32) -> f32 {
    if (model == 1) {
        return mg_tw_depth_channel_beer_lambert(d, h, model);
    }
    return mg_tw_depth_channel_paper(d, h, model);
}
"#;

/// The channel of a written `model` of `toon_water_depth_color`.
fn depth_model_choices() -> [WgslChoice; 2] {
    [
        WgslChoice {
            choice: "paper",
            helpers: &[DEPTH_PAPER_WGSL],
            tables: &[],
        },
        WgslChoice {
            choice: "beer_lambert",
            helpers: &[DEPTH_BEER_LAMBERT_WGSL],
            tables: &[],
        },
    ]
}

/// Seed 004 eq. 3, the light arriving through the atmosphere ("Lambert's absorption law" in
/// the paper's words): `s = I0 · exp(−√(a · t))`, `a` the absorption coefficient, `t` the
/// thickness crossed, `I0` the time-of-day preset's colour ([`TIME_OF_DAY`]) or, for
/// `custom` (0), `light_color`. Negative `a·t` reads as 0; an unknown preset as `custom`.
#[inline]
pub fn sky_light(light_color: Vec3, absorption: f32, thickness: f32, time_of_day: i32) -> Vec3 {
    let i0 = match time_of_day {
        1..=4 => Vec3::from(TIME_OF_DAY[time_of_day as usize - 1].1),
        _ => light_color,
    };
    i0 * exp(-sqrt((absorption * thickness).max(0.0)))
}

/// WGSL of [`sky_light`], the same steps.
const SKY_LIGHT_WGSL: &str = r#"
fn $fn(light_color: vec3<f32>, absorption: f32, thickness: f32, time_of_day: i32) -> vec3<f32> {
    var i0 = light_color;
    if (time_of_day == 1 || time_of_day == 3) {
        i0 = vec3<f32>(0.8, 0.3, 0.0);
    } else if (time_of_day == 2) {
        i0 = vec3<f32>(0.7, 0.7, 0.7);
    } else if (time_of_day == 4) {
        i0 = vec3<f32>(0.25, 0.25, 0.25);
    }
    return i0 * exp(-sqrt(max(absorption * thickness, 0.0)));
}
"#;

/// Seed 004 eq. 1, the base colour per channel: `base = w · v · s` (weight, depth colour,
/// incident light).
#[inline]
pub fn base_color(weight: Vec3, depth_color: Vec3, light: Vec3) -> Vec3 {
    weight * depth_color * light
}

/// `normalize(v)`, or `fallback` where `v·v` is 0 or not finite (the same test in WGSL).
#[inline]
fn normalize_or(v: Vec3, fallback: Vec3) -> Vec3 {
    let l2 = v.dot(v);
    if l2 > 0.0 && l2.is_finite() {
        v / sqrt(l2)
    } else {
        fallback
    }
}

/// WGSL of [`normalize_or`].
const NORMALIZE_WGSL: &str = r#"
fn mg_tw_normalize_or(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let l2 = dot(v, v);
    if (l2 > 0.0 && l2 <= 0x1.fffffep+127f) {
        return v / sqrt(l2);
    }
    return fallback;
}
"#;

/// `x^m` for `x ≥ 0` with `0^m` spelled out (1 for `m = 0`, else 0), as in WGSL where `pow`
/// is undefined at a zero base. `x^m` is `exp2(m · log2 x)` with the node's own `log2`
/// (nodes/precise.rs): WGSL's `log2` is off by up to 2⁻²¹ near 1, which a shininess of 10⁴
/// multiplies into 1.4% of the highlight.
#[inline]
fn pow0(x: f32, m: f32) -> f32 {
    if x <= 0.0 {
        if m == 0.0 { 1.0 } else { 0.0 }
    } else {
        precise::pow(x, m)
    }
}

/// Seed 004 eqs. 7–8, the modified Blinn–Phong toon shading:
/// `C = Ka + Kd · base · ramp(n·l) + Ks · (n·h)^m`, `h = normalize(l + v)`, with `ramp` a 1D
/// texture of `steps` flat bands indexed by `n·l` (the `ramp` node's hard bands, softness 0)
/// whose darkest band is at level `shadow` and lightest at 1: `ramp = shadow + (1 − shadow) ·
/// level`. Returns `(C, ramp, highlight)` with `highlight = (n·h)^m`, taken as 0 where
/// `n·l ≤ 0` (the light is behind the surface; the paper leaves this case open) and for
/// `n·h ≤ 0`. `n`, `l`, `v` are normalised here (a zero `n` reads as `+y`, a zero `l + v` as
/// `n`).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn toon_shade(
    normal: Vec3,
    light: Vec3,
    view: Vec3,
    base: Vec3,
    ambient: Vec3,
    diffuse: Vec3,
    specular: Vec3,
    shininess: f32,
    steps: i32,
    shadow: f32,
) -> (Vec3, f32, f32) {
    let n = normalize_or(normal, Vec3::Y);
    let l = normalize_or(light, n);
    let v = normalize_or(view, n);
    let h = normalize_or(l + v, n);
    let n_dot_l = n.dot(l);
    let level = ramp(n_dot_l, steps, Vec3::ZERO, Vec3::ONE, 0.0).1;
    let shadow = shadow.clamp(0.0, 1.0);
    let r = shadow + (1.0 - shadow) * level;
    let highlight = if n_dot_l > 0.0 {
        pow0(n.dot(h).max(0.0), shininess.max(0.0))
    } else {
        0.0
    };
    (
        ambient + diffuse * base * r + specular * highlight,
        r,
        highlight,
    )
}

/// WGSL of [`toon_shade`]; the ramp's level is the `ramp` node's steps at softness 0.
const TOON_SHADE_WGSL: &str = r#"
fn mg_tw_ramp_level(x: f32, steps: i32) -> f32 {
    let n = clamp(steps, 1, 256);
    if (n == 1) {
        return 1.0;
    }
    let nf = f32(n);
    let y = clamp(x, 0.0, 1.0) * nf;
    let j = clamp(floor(y + 0.5), 1.0, nf - 1.0);
    let s = select(0.0, 1.0, y >= j);
    return ((j - 1.0) + s) / (nf - 1.0);
}

fn $fn(normal: vec3<f32>, light: vec3<f32>, view: vec3<f32>, base: vec3<f32>, ambient: vec3<f32>, diffuse: vec3<f32>, specular: vec3<f32>, shininess: f32, steps: i32, shadow: f32) -> $out {
    let n = mg_tw_normalize_or(normal, vec3<f32>(0.0, 1.0, 0.0));
    let l = mg_tw_normalize_or(light, n);
    let v = mg_tw_normalize_or(view, n);
    let h = mg_tw_normalize_or(l + v, n);
    let n_dot_l = dot(n, l);
    let level = mg_tw_ramp_level(n_dot_l, steps);
    let sh = clamp(shadow, 0.0, 1.0);
    let r = sh + (1.0 - sh) * level;
    var highlight = 0.0;
    if (n_dot_l > 0.0) {
        let x = max(dot(n, h), 0.0);
        let m = max(shininess, 0.0);
        highlight = select(mg_prec_pow(select(x, 1.0, x <= 0.0), m), select(0.0, 1.0, m == 0.0), x <= 0.0);
    }
    return $out(ambient + diffuse * base * r + specular * highlight, r, highlight);
}
"#;

/// Seed 004 eq. 10, the simplified Fresnel mixing the reflection and refraction maps:
/// `F = clamp(bias + scale · (1 + i·n)^power, 0, 1)` (the `fresnel_empirical` node; Fernando
/// & Kilgard, The Cg Tutorial §7.4, the paper's ref. 17), `color = refraction + F ·
/// (reflection − refraction)`. Returns `(color, F)`.
#[inline]
pub fn fresnel_mix(
    reflection: Vec3,
    refraction: Vec3,
    i_dot_n: f32,
    bias: f32,
    scale: f32,
    power: f32,
) -> (Vec3, f32) {
    let f = fresnel_empirical(i_dot_n, bias, scale, power);
    (refraction + (reflection - refraction) * f, f)
}

/// WGSL of [`fresnel_mix`]; the factor is the `fresnel_empirical` node's steps.
const FRESNEL_MIX_WGSL: &str = r#"
fn $fn(reflection: vec3<f32>, refraction: vec3<f32>, i_dot_n: f32, bias: f32, scale: f32, power: f32) -> $out {
    let base = max(1.0 + i_dot_n, 0.0);
    let p = select(pow(select(base, 1.0, base == 0.0), power), select(0.0, 1.0, power == 0.0), base == 0.0);
    let f = min(max(bias + scale * p, 0.0), 1.0);
    return $out(refraction + (reflection - refraction) * f, f);
}
"#;

/// The smallest wavelength a Gerstner wave is evaluated with, metres (the hard range's
/// minimum): shorter ones read as this.
pub const MIN_WAVELENGTH: f32 = 0.1;

/// One Gerstner wave: direction of travel `(x, z)` (normalised on use), wavelength λ (m),
/// amplitude a (m), steepness Q and phase φ (rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wave {
    /// Direction of travel in the water plane, `(x, z)`; normalised on use, zero reads as `+x`.
    pub direction: [f32; 2],
    /// Wavelength, metres.
    pub wavelength: f32,
    /// Amplitude, metres.
    pub amplitude: f32,
    /// Steepness `Q` (horizontal offset `Q a cos θ`).
    pub steepness: f32,
    /// Phase offset, radians.
    pub phase: f32,
}

/// The waves of the scene's default wave set (the `gerstner_waves` node's defaults): eight
/// waves spread ±45° about a wind towards `+z` (at 100° from `+x` towards `+z`; the
/// directions are `(cos α, sin α)` of α = 100°, 70°, 130°, 85°, 115°, 55°, 145°, 95° to 7
/// digits), wavelengths 14 m down to 1.1 m, each
/// with `k a ≈ 0.07–0.08` and `Q = 1` (so `Σ Q k a ≈ 0.59`, below the fold at 1).
pub const DEFAULT_WAVES: [Wave; MAX_WAVES] = [
    wave([-0.1736482, 0.9848078], 14.0, 0.18, 1.0, 0.0),
    wave([0.3420201, 0.9396926], 9.0, 0.11, 1.0, 1.3),
    wave([-0.6427876, 0.7660444], 6.5, 0.08, 1.0, 2.9),
    wave([0.0871557, 0.9961947], 4.3, 0.05, 1.0, 4.4),
    wave([-0.4226183, 0.9063078], 3.1, 0.035, 1.0, 0.7),
    wave([0.5735764, 0.819152], 2.2, 0.025, 1.0, 5.1),
    wave([-0.819152, 0.5735764], 1.6, 0.018, 1.0, 3.6),
    wave([-0.0871557, 0.9961947], 1.1, 0.012, 1.0, 2.2),
];

/// A wave travelling at `deg` degrees from `+x` towards `+z` (direction rounded to f32).
pub fn wave_at(deg: f64, wavelength: f32, amplitude: f32, steepness: f32, phase: f32) -> Wave {
    let (s, c) = deg.to_radians().sin_cos();
    wave(
        [c as f32, s as f32],
        wavelength,
        amplitude,
        steepness,
        phase,
    )
}

/// A wave from its fields.
pub const fn wave(
    direction: [f32; 2],
    wavelength: f32,
    amplitude: f32,
    steepness: f32,
    phase: f32,
) -> Wave {
    Wave {
        direction,
        wavelength,
        amplitude,
        steepness,
        phase,
    }
}

/// One field of the default waves `i0..i0 + 4` as a vec4 (`field`: 1 wavelength,
/// 2 amplitude, 3 steepness, 4 phase).
const fn default_vec4(i0: usize, field: usize) -> [f32; 4] {
    let mut out = [0.0; 4];
    let mut k = 0;
    while k < 4 {
        let w = DEFAULT_WAVES[i0 + k];
        out[k] = match field {
            1 => w.wavelength,
            2 => w.amplitude,
            3 => w.steepness,
            _ => w.phase,
        };
        k += 1;
    }
    out
}

/// The directions of default waves `i0` and `i0 + 1` as `(x0, z0, x1, z1)`.
const fn default_directions(i0: usize) -> [f32; 4] {
    let (a, b) = (DEFAULT_WAVES[i0].direction, DEFAULT_WAVES[i0 + 1].direction);
    [a[0], a[1], b[0], b[1]]
}

/// What [`gerstner`] returns at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GerstnerSample {
    /// Displacement of the lattice point, metres.
    pub offset: Vec3,
    /// Exact unit normal, `normalize(∂P/∂z × ∂P/∂x)`.
    pub normal: Vec3,
    /// GPU Gems ch. 1 eq. 12's unit normal.
    pub normal_gems: Vec3,
    /// `Σ Qᵢ kᵢ aᵢ`: the surface can fold over where it exceeds 1.
    pub fold_sum: f32,
}

/// The Gerstner surface of `waves` at lattice point `position` (its `x`, `z`; `y` is
/// ignored) and time `t` (GPU Gems ch. 1 eq. 9, seed 004 eqs. 11–13), `y` up:
///
/// ```text
/// k = 2π/λ, ω = √(g k), D the unit direction in (x, z), θ = k D·(x, z) − ω t + φ
/// P = (x + Σ Q a Dx cos θ, Σ a sin θ, z + Σ Q a Dz cos θ)
/// ∂P/∂x = (1 − Σ Q a k Dx² sin θ, Σ a k Dx cos θ, −Σ Q a k Dx Dz sin θ)
/// ∂P/∂z = (−Σ Q a k Dx Dz sin θ, Σ a k Dz cos θ, 1 − Σ Q a k Dz² sin θ)
/// normal = normalize(∂P/∂z × ∂P/∂x)
/// normal_gems = normalize(−Σ Dx k a cos θ, 1 − Σ Q k a sin θ, −Σ Dz k a cos θ)   (GPU Gems eq. 12)
/// ```
///
/// θ is reduced to `2π · fract(c)`, `c = D·(x, z)/λ − t √(g/(2πλ)) + φ/(2π)` in cycles, so
/// that `sin` and `cos` always see `[0, 2π)`. GPU Gems evaluates eq. 12 at the displaced
/// point; here both normals are at the lattice point, so they differ only by eq. 12's
/// dropped cross terms (exact for one wave). A zero cross product (a fold's edge) reads
/// as `+y`; a zero direction as `+x`. Wavelengths below [`MIN_WAVELENGTH`] read as it.
///
/// The direction is a vector, not an angle, on purpose: θ is tens to hundreds of cycles
/// over the scene, so a one-ulp difference in `D` (which `cos`/`sin` of an angle give
/// between backends) moves θ by ~10⁻⁴ rad; the normalisation uses only `sqrt` and `/`.
pub fn gerstner(position: Vec3, time: f32, waves: &[Wave]) -> GerstnerSample {
    let mut offset = Vec3::ZERO;
    let mut dpdx = Vec3::X;
    let mut dpdz = Vec3::Z;
    let mut gems = Vec3::Y;
    let mut fold_sum = 0.0;
    for w in waves {
        let lambda = w.wavelength.max(MIN_WAVELENGTH);
        let d = Vec2::from(w.direction);
        let l2 = d.dot(d);
        let (dx, dz) = if l2 > 0.0 && l2.is_finite() {
            let l = sqrt(l2);
            (d.x / l, d.y / l)
        } else {
            (1.0, 0.0)
        };
        let k = TAU / lambda;
        let freq = sqrt(GRAVITY / (TAU * lambda));
        let c = (dx * position.x + dz * position.z) / lambda - time * freq + w.phase / TAU;
        let theta = TAU * (c - c.floor());
        let (s, co) = sin_cos(theta);
        let (a, q) = (w.amplitude, w.steepness);
        let qak = q * a * k;
        let ak = a * k;
        offset += Vec3::new(q * a * dx * co, a * s, q * a * dz * co);
        dpdx += Vec3::new(-qak * dx * dx * s, ak * dx * co, -qak * dx * dz * s);
        dpdz += Vec3::new(-qak * dx * dz * s, ak * dz * co, -qak * dz * dz * s);
        gems += Vec3::new(-dx * ak * co, -qak * s, -dz * ak * co);
        fold_sum += qak;
    }
    GerstnerSample {
        offset,
        normal: normalize_or(cross(dpdz, dpdx), Vec3::Y),
        normal_gems: normalize_or(gems, Vec3::Y),
        fold_sum,
    }
}

/// The waves of a `gerstner_waves` node's inputs: the first `count` (clamped to 0..8) of the
/// eight whose fields are the components of the vec4s: wave `i`'s direction is
/// `directions[i / 2]`'s `(x, z)` pair `i mod 2`, its other fields component `i mod 4` of
/// the `*_0_3` (`i < 4`) or `*_4_7` vec4.
pub fn waves_from_inputs(
    count: i32,
    directions: [Vec4; 4],
    wavelengths: [Vec4; 2],
    amplitudes: [Vec4; 2],
    steepness: [Vec4; 2],
    phases: [Vec4; 2],
) -> Vec<Wave> {
    let n = count.clamp(0, MAX_WAVES as i32) as usize;
    (0..n)
        .map(|i| {
            let (h, j) = (i / 4, i % 4);
            let d = directions[i / 2];
            let dir = if i % 2 == 0 { [d.x, d.y] } else { [d.z, d.w] };
            wave(
                dir,
                wavelengths[h][j],
                amplitudes[h][j],
                steepness[h][j],
                phases[h][j],
            )
        })
        .collect()
}

/// The `gerstner_waves` node: [`gerstner`] of [`waves_from_inputs`];
/// `(offset, normal, normal_gems, folds)` with `folds = Σ Qᵢ kᵢ aᵢ > 1`.
#[allow(clippy::too_many_arguments)]
fn gerstner_node(
    position: Vec3,
    time: f32,
    count: i32,
    directions_0_1: Vec4,
    directions_2_3: Vec4,
    directions_4_5: Vec4,
    directions_6_7: Vec4,
    wavelengths_0_3: Vec4,
    wavelengths_4_7: Vec4,
    amplitudes_0_3: Vec4,
    amplitudes_4_7: Vec4,
    steepness_0_3: Vec4,
    steepness_4_7: Vec4,
    phases_0_3: Vec4,
    phases_4_7: Vec4,
) -> (Vec3, Vec3, Vec3, bool) {
    let waves = waves_from_inputs(
        count,
        [
            directions_0_1,
            directions_2_3,
            directions_4_5,
            directions_6_7,
        ],
        [wavelengths_0_3, wavelengths_4_7],
        [amplitudes_0_3, amplitudes_4_7],
        [steepness_0_3, steepness_4_7],
        [phases_0_3, phases_4_7],
    );
    let g = gerstner(position, time, &waves);
    (g.offset, g.normal, g.normal_gems, g.fold_sum > 1.0)
}

/// WGSL of [`gerstner`]: one helper call per wave, in the same order, accumulating the same
/// sums.
const GERSTNER_HELPERS_WGSL: &str = r#"
struct MgTwGerstner {
    offset: vec3<f32>,
    dpdx: vec3<f32>,
    dpdz: vec3<f32>,
    gems: vec3<f32>,
    fold_sum: f32,
}

fn mg_tw_wave(acc: MgTwGerstner, p: vec3<f32>, t: f32, d: vec2<f32>, wavelength: f32, a: f32, q: f32, phase: f32) -> MgTwGerstner {
    let lambda = max(wavelength, 0.1);
    let l2 = dot(d, d);
    var dx = 1.0;
    var dz = 0.0;
    if (l2 > 0.0 && l2 <= 0x1.fffffep+127f) {
        let l = sqrt(l2);
        dx = d.x / l;
        dz = d.y / l;
    }
    let k = 6.2831855 / lambda;
    let freq = sqrt(9.80665 / (6.2831855 * lambda));
    let c = (dx * p.x + dz * p.z) / lambda - t * freq + phase / 6.2831855;
    let theta = 6.2831855 * (c - floor(c));
    let sc = mg_prec_sincos(theta);
    let s = sc.x;
    let co = sc.y;
    let qak = q * a * k;
    let ak = a * k;
    var r = acc;
    r.offset = r.offset + vec3<f32>(q * a * dx * co, a * s, q * a * dz * co);
    r.dpdx = r.dpdx + vec3<f32>(-qak * dx * dx * s, ak * dx * co, -qak * dx * dz * s);
    r.dpdz = r.dpdz + vec3<f32>(-qak * dx * dz * s, ak * dz * co, -qak * dz * dz * s);
    r.gems = r.gems + vec3<f32>(-dx * ak * co, -qak * s, -dz * ak * co);
    r.fold_sum = r.fold_sum + qak;
    return r;
}
"#;

/// WGSL of the `gerstner_waves` node.
const GERSTNER_WGSL: &str = r#"
fn $fn(position: vec3<f32>, time: f32, count: i32, directions_0_1: vec4<f32>, directions_2_3: vec4<f32>, directions_4_5: vec4<f32>, directions_6_7: vec4<f32>, wavelengths_0_3: vec4<f32>, wavelengths_4_7: vec4<f32>, amplitudes_0_3: vec4<f32>, amplitudes_4_7: vec4<f32>, steepness_0_3: vec4<f32>, steepness_4_7: vec4<f32>, phases_0_3: vec4<f32>, phases_4_7: vec4<f32>) -> $out {
    let n = clamp(count, 0, 8);
    var g = MgTwGerstner(vec3<f32>(0.0), vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0, 1.0, 0.0), 0.0);
    let t = time;
    let p = position;
    if (n > 0) { g = mg_tw_wave(g, p, t, directions_0_1.xy, wavelengths_0_3.x, amplitudes_0_3.x, steepness_0_3.x, phases_0_3.x); }
    if (n > 1) { g = mg_tw_wave(g, p, t, directions_0_1.zw, wavelengths_0_3.y, amplitudes_0_3.y, steepness_0_3.y, phases_0_3.y); }
    if (n > 2) { g = mg_tw_wave(g, p, t, directions_2_3.xy, wavelengths_0_3.z, amplitudes_0_3.z, steepness_0_3.z, phases_0_3.z); }
    if (n > 3) { g = mg_tw_wave(g, p, t, directions_2_3.zw, wavelengths_0_3.w, amplitudes_0_3.w, steepness_0_3.w, phases_0_3.w); }
    if (n > 4) { g = mg_tw_wave(g, p, t, directions_4_5.xy, wavelengths_4_7.x, amplitudes_4_7.x, steepness_4_7.x, phases_4_7.x); }
    if (n > 5) { g = mg_tw_wave(g, p, t, directions_4_5.zw, wavelengths_4_7.y, amplitudes_4_7.y, steepness_4_7.y, phases_4_7.y); }
    if (n > 6) { g = mg_tw_wave(g, p, t, directions_6_7.xy, wavelengths_4_7.z, amplitudes_4_7.z, steepness_4_7.z, phases_4_7.z); }
    if (n > 7) { g = mg_tw_wave(g, p, t, directions_6_7.zw, wavelengths_4_7.w, amplitudes_4_7.w, steepness_4_7.w, phases_4_7.w); }
    let up = vec3<f32>(0.0, 1.0, 0.0);
    return $out(g.offset, mg_tw_normalize_or(cross(g.dpdz, g.dpdx), up), mg_tw_normalize_or(g.gems, up), g.fold_sum > 1.0);
}
"#;

/// The cartoon-water node types.
pub fn all() -> Vec<NodeType> {
    let f = Value::float;
    let i = Value::int;
    let v3 = Value::vec3;
    let v4 = Value::vec4;
    vec![
        NodeType::new("toon_water_depth_color", Category::Water, "Seed 004's colour of water by depth, or Beer–Lambert.")
            .source(
                "Seed 004 eq. 2 (the 2012 cartoon-water paper; docs/models/toon_water.md): v_c = \
                 exp(−√(k_c d)) (`paper`) or exp(−k_c d) (`beer_lambert`) per channel, depth d ≥ 0 \
                 in metres. The half-life h_c sets k_c so that v_c(h_c) = ½ in both models: paper \
                 k = (ln 2)²/h, Beer–Lambert k = ln 2/h (so paper = 2^(−√(d/h)), Beer–Lambert = \
                 2^(−d/h)). Negative depth reads as 0.",
            )
            .input(In::float("depth", 3.0).range(0.0, 200.0).unit("m").doc("Depth below the surface, positive down (link geometry.depth)."))
            .input(In::color("half_life", [0.5, 3.0, 20.0]).range(0.1, 200.0).hard(1e-3, 1e6).unit("m").doc("Depth at which each channel is halved."))
            .input(In::choice("model", DEPTH_MODELS, 0).doc("paper: exp(−√(k d)); beer_lambert: exp(−k d)."))
            .output(Out::color("color").doc("Colour factor per channel in (0, 1]."))
            .wgsl(DEPTH_COLOR_WGSL)
            .wgsl_per_choice("model", &[DEPTH_CHANNEL_WGSL], depth_model_choices())
            .hard_case("surface", &[("depth", f(0.0))])
            .hard_case("abyss, short half-life", &[("depth", f(1e4)), ("half_life", v3([1e-3, 1e-3, 1e-3]))])
            .hard_case("Beer–Lambert at the paper's maximum depth", &[("depth", f(156.0)), ("model", i(1))])
            .hard_case("above the surface", &[("depth", f(-2.0))])
            .compute(depth_color),
        NodeType::new("toon_water_sky_light", Category::Water, "Seed 004's light after the atmosphere, with time-of-day presets.")
            .source(
                "Seed 004 eq. 3 (\"Lambert's absorption law\" in the paper): s = I0 · exp(−√(a t)), a \
                 the absorption coefficient and t the thickness crossed (the units cancel in a·t). \
                 I0 is a preset of §3.2: sunrise (0.8, 0.3, 0.0), day (0.7, 0.7, 0.7), sunset \
                 (0.8, 0.3, 0.0), night (0.25, 0.25, 0.25), or light_color for `custom`. Negative \
                 a·t reads as 0.",
            )
            .input(In::color("light_color", [1.0, 1.0, 1.0]).range(0.0, 4.0).doc("I0 for `custom` (link geometry.light_color for the scene's sun)."))
            .input(In::float("absorption", 0.01).range(0.0, 1.0).hard(0.0, 1e3).unit("1/km").doc("Absorption coefficient a of the atmosphere."))
            .input(In::float("thickness", 8.0).range(0.0, 100.0).hard(0.0, 1e3).unit("km").doc("Thickness t of atmosphere crossed."))
            .input(In::choice("time_of_day", TIME_OF_DAY_NAMES, 0).doc("I0: custom (light_color), sunrise, day, sunset or night."))
            .output(Out::color("light").doc("Incident light s per channel."))
            .wgsl(SKY_LIGHT_WGSL)
            .hard_case("no atmosphere", &[("absorption", f(0.0))])
            .hard_case("thick atmosphere", &[("absorption", f(1e3)), ("thickness", f(1e3))])
            .hard_case("night preset", &[("time_of_day", i(4))])
            .compute(sky_light),
        NodeType::new("toon_water_base_color", Category::Water, "Seed 004's base colour w · v · s.")
            .source("Seed 004 eq. 1: base = w · v · s per RGB channel (weight, depth colour, incident light).")
            .input(In::color("weight", [1.0, 1.0, 1.0]).range(0.0, 2.0).doc("Weight w per channel."))
            .input(In::color("depth_color", [0.2, 0.5, 0.8]).range(0.0, 1.0).doc("Depth colour v (link toon_water_depth_color.color)."))
            .input(In::color("light", [0.7, 0.7, 0.7]).range(0.0, 4.0).doc("Incident light s (link toon_water_sky_light.light)."))
            .output(Out::color("base").doc("Base colour."))
            .wgsl("fn $fn(weight: vec3<f32>, depth_color: vec3<f32>, light: vec3<f32>) -> vec3<f32> { return weight * depth_color * light; }")
            .compute(base_color),
        NodeType::new("toon_water_shade", Category::Water, "Seed 004's toon shading: modified Blinn–Phong with a stepped ramp.")
            .source(
                "Seed 004 eqs. 7–8 (a modified Blinn–Phong, Blinn 1977): C = Ka + Kd · base · ramp(n·l) + \
                 Ks · (n·h)^m, h = normalize(l + v). ramp is a 1D texture of `steps` flat bands \
                 indexed by n·l (the `ramp` node, softness 0; Lake et al. 2000), darkest band at \
                 level `shadow`: ramp = shadow + (1 − shadow) · level. The highlight is 0 where \
                 n·l ≤ 0 or n·h ≤ 0 (our choice; the paper leaves it open). n, l, v are normalised \
                 (zero n reads as +y, zero l or v as n).",
            )
            .input(In::vec3("normal", [0.0, 1.0, 0.0]).range(-1.0, 1.0).doc("Surface normal n (normalised here)."))
            .input(In::vec3("light", [0.0, 1.0, 0.0]).range(-1.0, 1.0).doc("Direction to the light l (normalised here)."))
            .input(In::vec3("view", [0.0, 1.0, 0.0]).range(-1.0, 1.0).doc("Direction to the eye v (normalised here)."))
            .input(In::color("base", [0.2, 0.5, 0.8]).range(0.0, 1.0).doc("Base colour w · v · s (link toon_water_base_color.base)."))
            .input(In::color("ambient", [0.02, 0.04, 0.08]).range(0.0, 1.0).doc("Ambient term Ka."))
            .input(In::color("diffuse", [1.0, 1.0, 1.0]).range(0.0, 2.0).doc("Diffuse coefficient Kd."))
            .input(In::color("specular", [0.6, 0.6, 0.6]).range(0.0, 2.0).doc("Specular coefficient Ks."))
            .input(In::float("shininess", 64.0).range(1.0, 256.0).hard(0.0, 1e4).doc("Highlight exponent m."))
            .input(In::int("steps", 3).range(1.0, 8.0).hard(1.0, 256.0).doc("Bands of the ramp."))
            .input(In::float("shadow", 0.35).range(0.0, 1.0).hard(0.0, 1.0).doc("Level of the darkest band."))
            .output(Out::color("color").doc("Toon-shaded colour C."))
            .output(Out::float("ramp").doc("The ramp's value at n·l, in [shadow, 1]."))
            .output(Out::float("highlight").doc("(n·h)^m, 0 where the light is behind."))
            .wgsl(TOON_SHADE_WGSL)
            .wgsl_uses(&[NORMALIZE_WGSL, precise::LOG2_EXACT_WGSL, precise::POW_WGSL])
            .hard_case("light at the horizon", &[("light", v3([1.0, 0.0, 0.0]))])
            .hard_case("light behind", &[("light", v3([0.0, -1.0, 0.0]))])
            .hard_case("view opposite the light", &[("light", v3([0.6, 0.8, 0.0])), ("view", v3([-0.6, -0.8, 0.0]))])
            .hard_case("zero vectors", &[("normal", v3([0.0, 0.0, 0.0])), ("light", v3([0.0, 0.0, 0.0])), ("view", v3([0.0, 0.0, 0.0]))])
            .hard_case("shininess 0", &[("shininess", f(0.0))])
            .hard_case("on a band edge", &[("light", v3([0.8, 0.6, 0.0])), ("steps", i(5)), ("normal", v3([1.0, 0.0, 0.0]))])
            .compute(toon_shade),
        NodeType::new("toon_water_fresnel_mix", Category::Water, "Seed 004's simplified Fresnel mixing reflection and refraction.")
            .source(
                "Seed 004 eq. 10: F = clamp(bias + scale (1 + i·n)^power, 0, 1) (the paper's ref. 17, \
                 Fernando & Kilgard, The Cg Tutorial §7.4; the fresnel_empirical node), color = \
                 refraction + F (reflection − refraction).",
            )
            .input(In::color("reflection", [0.6, 0.7, 0.9]).range(0.0, 4.0).doc("Reflection map colour (scene:reflection)."))
            .input(In::color("refraction", [0.1, 0.3, 0.4]).range(0.0, 4.0).doc("Refraction map colour (scene:refraction)."))
            .input(In::float("i_dot_n", -1.0).range(-1.0, 0.0).hard(-1.0, 1.0).doc("I·N, I the incident direction (−1 at normal incidence)."))
            .input(In::float("bias", 0.02).range(0.0, 1.0).doc("Fresnel bias (reflectance at normal incidence)."))
            .input(In::float("scale", 0.98).range(0.0, 2.0).doc("Fresnel scale."))
            .input(In::float("power", 5.0).range(0.5, 8.0).hard(0.0, 64.0).doc("Fresnel power."))
            .output(Out::color("color").doc("Mixed colour."))
            .output(Out::float("factor").doc("Reflection weight F in [0, 1]."))
            .wgsl(FRESNEL_MIX_WGSL)
            .hard_case("grazing", &[("i_dot_n", f(-1e-4))])
            .hard_case("power 0", &[("power", f(0.0)), ("i_dot_n", f(0.0))])
            .compute(fresnel_mix),
        NodeType::new("gerstner_waves", Category::Water, "Up to eight Gerstner waves: offset, exact and GPU Gems normals, fold flag.")
            .source(
                "Gerstner waves (Finch, GPU Gems 2004 ch. 1 eq. 9; seed 004 eqs. 11–13), y up: k = 2π/λ, \
                 ω = √(g k) (deep water, g = 9.80665), θ = k D·(x, z) − ω t + φ with D the unit direction; \
                 offset = (Σ Q a Dx cos θ, Σ a sin θ, Σ Q a Dz cos θ). normal = normalize(∂P/∂z × ∂P/∂x) \
                 from the analytic partial derivatives at the lattice point; normal_gems is GPU Gems eq. 12 \
                 (drops the cross terms; exact for one wave); folds = Σ Q k a > 1. The first `count` \
                 waves are summed; wave i's direction is the (x, z) pair i mod 2 of directions_{i/2 pair}, \
                 its other fields component i mod 4 of the `*_0_3` (i < 4) or `*_4_7` vec4s. θ is reduced to 2π·fract(cycles) before sin/cos. Wavelengths below \
                 0.1 m read as 0.1 m; a zero direction reads as +x, a zero cross product as +y.",
            )
            .input(In::vec3("position", [0.0, 0.0, 0.0]).range(-50.0, 50.0).unit("m").doc("Undisplaced lattice point (x, z used; link geometry.position)."))
            .input(In::float("time", 0.0).range(0.0, 60.0).unit("s").doc("Time (link geometry.time)."))
            .input(In::int("count", MAX_WAVES as i32).range(0.0, 8.0).hard(0.0, 8.0).doc("Number of waves summed (0–8)."))
            .input(In::vec4("directions_0_1", default_directions(0)).range(-1.0, 1.0).hard(-1e3, 1e3).doc("Directions (x, z) of waves 0 and 1, normalised here (zero reads as +x)."))
            .input(In::vec4("directions_2_3", default_directions(2)).range(-1.0, 1.0).hard(-1e3, 1e3).doc("Directions (x, z) of waves 2 and 3, normalised here (zero reads as +x)."))
            .input(In::vec4("directions_4_5", default_directions(4)).range(-1.0, 1.0).hard(-1e3, 1e3).doc("Directions (x, z) of waves 4 and 5, normalised here (zero reads as +x)."))
            .input(In::vec4("directions_6_7", default_directions(6)).range(-1.0, 1.0).hard(-1e3, 1e3).doc("Directions (x, z) of waves 6 and 7, normalised here (zero reads as +x)."))
            .input(In::vec4("wavelengths_0_3", default_vec4(0, 1)).range(0.5, 50.0).hard(0.1, 1e4).unit("m").doc("Wavelengths λ of waves 0–3."))
            .input(In::vec4("wavelengths_4_7", default_vec4(4, 1)).range(0.5, 50.0).hard(0.1, 1e4).unit("m").doc("Wavelengths λ of waves 4–7."))
            .input(In::vec4("amplitudes_0_3", default_vec4(0, 2)).range(0.0, 1.0).hard(0.0, 10.0).unit("m").doc("Amplitudes a of waves 0–3."))
            .input(In::vec4("amplitudes_4_7", default_vec4(4, 2)).range(0.0, 1.0).hard(0.0, 10.0).unit("m").doc("Amplitudes a of waves 4–7."))
            .input(In::vec4("steepness_0_3", default_vec4(0, 3)).range(0.0, 2.0).hard(0.0, 10.0).doc("Steepness Q of waves 0–3 (horizontal offset Q a cos θ)."))
            .input(In::vec4("steepness_4_7", default_vec4(4, 3)).range(0.0, 2.0).hard(0.0, 10.0).doc("Steepness Q of waves 4–7."))
            .input(In::vec4("phases_0_3", default_vec4(0, 4)).range(0.0, 6.2831855).hard(-100.0, 100.0).unit("rad").doc("Phases φ of waves 0–3."))
            .input(In::vec4("phases_4_7", default_vec4(4, 4)).range(0.0, 6.2831855).hard(-100.0, 100.0).unit("rad").doc("Phases φ of waves 4–7."))
            .output(Out::vec3("offset").unit("m").doc("Displacement of the lattice point (link to the displacement output)."))
            .output(Out::vec3("normal").doc("Exact unit normal of the displaced surface."))
            .output(Out::vec3("normal_gems").doc("GPU Gems eq. 12's unit normal, for comparison."))
            .output(Out::boolean("folds").doc("Whether Σ Q k a > 1 (the surface can loop over itself)."))
            .wgsl(GERSTNER_WGSL)
            .wgsl_uses(&[NORMALIZE_WGSL, SIN_COS_WGSL, GERSTNER_HELPERS_WGSL])
            .hard_case("no waves", &[("count", i(0))])
            .hard_case("one wave", &[("count", i(1))])
            .hard_case("folding", &[("steepness_0_3", v4([10.0, 10.0, 10.0, 10.0])), ("steepness_4_7", v4([10.0, 10.0, 10.0, 10.0]))])
            .hard_case("tiny wavelengths", &[("wavelengths_0_3", v4([0.1, 0.1, 0.1, 0.1])), ("position", v3([3.7, 0.0, -1.3]))])
            .hard_case("flat (zero amplitude)", &[("amplitudes_0_3", v4([0.0; 4])), ("amplitudes_4_7", v4([0.0; 4]))])
            .compute(gerstner_node),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_wave_normals_agree_and_waves_from_inputs_reads_the_vec4s() {
        let w = [wave_at(30.0, 5.0, 0.2, 0.8, 0.4)];
        for x in [-3.0f32, 0.0, 1.7, 12.5] {
            let g = gerstner(Vec3::new(x, 0.0, 0.3 * x), 1.25, &w);
            assert!((g.normal - g.normal_gems).length() < 1e-5, "{g:?}");
        }
        let a = Vec4::new(1.0, 2.0, 3.0, 4.0);
        let b = Vec4::new(5.0, 6.0, 7.0, 8.0);
        let ws = waves_from_inputs(6, [a, b, a, b], [a, b], [a, b], [a, b], [a, b]);
        assert_eq!(ws.len(), 6);
        assert_eq!(ws[5], wave([3.0, 4.0], 6.0, 6.0, 6.0, 6.0));
    }
}
