//! Blender's Wave Texture node (Blender 4.x), its definition as Blender's sources state it
//! (`intern/cycles/kernel/svm/wave.h`; geometry nodes' `node_shader_tex_wave.cc`), written
//! again here: bands or rings of a phase `n` (20 radians a unit, along an axis, the diagonal,
//! or the distance from an axis or the origin), moved by `phase_offset` and by Blender's fBm
//! noise ([`super::blender_noise::fractal`], 3D, lacunarity 2, normalised) times
//! `distortion`, through a sine, saw or triangle profile.
//!
//! The sine is [`super::precise::sin_cos`] (WGSL's `sin` is specified to 2⁻¹¹ only), of the
//! phase clamped to ±10⁶ rad, where one ULP of an f32 phase is already 0.06 rad: past that
//! the Cody–Waite reduction's remainder leaves [−π/4, π/4] and the polynomial diverges, so the
//! clamp keeps huge coordinates finite. tests/models/blender_textures.rs holds the node to
//! values Blender 4.2 computed.

use super::blender_noise::{BLENDER_NOISE_WGSL, fractal};
use super::precise::{SIN_COS_WGSL, sin_cos};
use crate::node::{Category, In, NodeType, Out};
use crate::precision;
use crate::value::Value;
use glam::Vec3;

/// The choices of the `type` input (Blender's order).
pub const TYPES: &[&str] = &["bands", "rings"];
/// The choices of the `bands_direction` input (Blender's order).
pub const BANDS_DIRECTIONS: &[&str] = &["x", "y", "z", "diagonal"];
/// The choices of the `rings_direction` input (Blender's order).
pub const RINGS_DIRECTIONS: &[&str] = &["x", "y", "z", "spherical"];
/// The choices of the `profile` input (Blender's order).
pub const PROFILES: &[&str] = &["sin", "saw", "tri"];

/// 1/(2π) rounded to f32: the saw and triangle profiles count cycles by this product (Blender
/// divides by 2π; a product rounds the same on every GPU, a quotient may be 2.5 ULP off).
const INV_TAU: f32 = 0.159_154_94;
/// The bound on |coordinate · scale|: beyond it a phase is past [`PHASE_LIMIT`] anyway, and
/// the fBm's coordinates stay finite for every detail scale in the hard range.
const COORD_LIMIT: f32 = 1.0e12;
/// The bound on |phase| before the sine (see the module doc).
const PHASE_LIMIT: f32 = 1.0e6;

/// Blender's Wave Texture: `(color, fac)`, fac the profile of the phase and color its grey.
///
/// Source: Blender 4.x `svm_wave` (wave.h): `p = (vector·scale + 10⁻⁶)·0.999999` (Blender's
/// guard against unit coordinates); bands `n = 20·p.x` (y, z; diagonal `10·(x + y + z)`);
/// rings `n = 20·|p|` with the direction's axis zeroed (spherical: none); `n += phase_offset`;
/// where `distortion ≠ 0`, `n += distortion·(2·fBm(p·detail_scale) − 1)`; sine
/// `½ + ½ sin(n − π/2)` (computed as `½ − ½ cos n`, the same function without the rounding of
/// n − π/2 that Blender's geometry nodes do in double), saw `fract(n/2π)`, triangle
/// `2·|n/2π − ⌊n/2π + ½⌋|`. detail is clamped to [0, 15] and detail_roughness to [0, 1]
/// (Blender leaves a linked value as it is; past them its fBm overflows).
#[allow(clippy::too_many_arguments)]
pub fn wave_texture(
    vector: Vec3,
    scale: f32,
    distortion: f32,
    detail: f32,
    detail_scale: f32,
    detail_roughness: f32,
    phase_offset: f32,
    kind: i32,
    bands_direction: i32,
    rings_direction: i32,
    profile: i32,
) -> (Vec3, f32) {
    let p = (vector * scale).clamp(Vec3::splat(-COORD_LIMIT), Vec3::splat(COORD_LIMIT));
    let p = (p + 0.000_001) * 0.999_999;
    let mut n = if kind == 1 {
        let r = match rings_direction {
            0 => Vec3::new(0.0, p.y, p.z),
            1 => Vec3::new(p.x, 0.0, p.z),
            2 => Vec3::new(p.x, p.y, 0.0),
            _ => p,
        };
        precision::sqrt(r.x * r.x + r.y * r.y + r.z * r.z) * 20.0
    } else {
        match bands_direction {
            1 => p.y * 20.0,
            2 => p.z * 20.0,
            3 => (p.x + p.y + p.z) * 10.0,
            _ => p.x * 20.0,
        }
    };
    n += phase_offset;
    if distortion != 0.0 {
        let q = (p * detail_scale).extend(0.0);
        let detail = detail.clamp(0.0, 15.0);
        let roughness = detail_roughness.clamp(0.0, 1.0);
        let fbm = fractal(q, 3, detail, roughness, 2.0, 0.0, 0.0, FBM, true);
        n += distortion * (fbm * 2.0 - 1.0);
    }
    let f = match profile {
        1 => {
            let c = n * INV_TAU;
            c - c.floor()
        }
        2 => {
            let c = n * INV_TAU;
            (c - (c + 0.5).floor()).abs() * 2.0
        }
        _ => 0.5 - 0.5 * sin_cos(n.clamp(-PHASE_LIMIT, PHASE_LIMIT)).1,
    };
    (Vec3::splat(f), f)
}

/// The index of fBm in [`super::blender_noise::TYPES`].
const FBM: usize = 3;

/// WGSL of [`wave_texture`].
const WAVE_TEXTURE_WGSL: &str = r#"
fn $fn(vector: vec3<f32>, scale: f32, distortion: f32, detail: f32, detail_scale: f32, detail_roughness: f32, phase_offset: f32, kind: i32, bands_direction: i32, rings_direction: i32, profile: i32) -> $out {
    let p0 = clamp(vector * scale, vec3<f32>(-1e12), vec3<f32>(1e12));
    let p = (p0 + 0.000001) * 0.999999;
    var n = p.x * 20.0;
    if (kind == 1) {
        var r = p;
        if (rings_direction == 0) { r.x = 0.0; }
        if (rings_direction == 1) { r.y = 0.0; }
        if (rings_direction == 2) { r.z = 0.0; }
        n = sqrt(r.x * r.x + r.y * r.y + r.z * r.z) * 20.0;
    } else if (bands_direction == 1) {
        n = p.y * 20.0;
    } else if (bands_direction == 2) {
        n = p.z * 20.0;
    } else if (bands_direction == 3) {
        n = (p.x + p.y + p.z) * 10.0;
    }
    n = n + phase_offset;
    if (distortion != 0.0) {
        let q = vec4<f32>(p * detail_scale, 0.0);
        let fbm = mg_bn_fractal_fbm(q, 3, clamp(detail, 0.0, 15.0), clamp(detail_roughness, 0.0, 1.0), 2.0, 0.0, 0.0, 3, true);
        n = n + distortion * (fbm * 2.0 - 1.0);
    }
    var f = 0.0;
    if (profile == 1) {
        let c = n * 0.15915494;
        f = c - floor(c);
    } else if (profile == 2) {
        let c = n * 0.15915494;
        f = abs(c - floor(c + 0.5)) * 2.0;
    } else {
        f = 0.5 - 0.5 * mg_prec_sincos(clamp(n, -1e6, 1e6)).y;
    }
    return $out(vec3<f32>(f), f);
}
"#;

/// The Wave node type.
pub fn all() -> Vec<NodeType> {
    let f = Value::float;
    let v3 = Value::vec3;
    let i = Value::int;
    vec![
        NodeType::new(
            "wave_texture",
            Category::Texture,
            "Blender's Wave Texture: bands or rings with sine, saw or triangle profiles, distorted by fBm noise.",
        )
        .source(
            "Blender 4.x Wave Texture (intern/cycles/kernel/svm/wave.h; geometry nodes' \
             node_shader_tex_wave.cc): the phase n = 20·p.x (y, z; diagonal 10·(x + y + z)) for \
             bands or 20·|p| with one axis zeroed (spherical: none) for rings, at \
             p = (vector·scale + 10⁻⁶)·0.999999; plus phase_offset; plus distortion·(2·fBm − 1), \
             Blender's Noise Texture fBm (3D, lacunarity 2, normalised) at p·detail_scale; \
             then ½ − ½ cos n (Blender's ½ + ½ sin(n − π/2)), fract(n/2π) or \
             2·|n/2π − ⌊n/2π + ½⌋|. Matches Blender 4.2 within 1e-4 \
             (tests/models/blender_textures.rs). Deviations: `vector` defaults to the origin \
             (Blender: generated coordinates); detail is clamped to [0, 15] and \
             detail_roughness to [0, 1] (Blender's field limits; a linked value past them \
             overflows Blender's fBm); |vector·scale| is clamped to 10¹² and the phase to \
             ±10⁶ rad before the sine (an f32 phase there is already 0.06 rad coarse; past it \
             our sine's reduction diverges), so huge coordinates give a finite value where \
             Blender's may be NaN. Limits: the phase is 20 rad a unit of p, so at \
             |p| = 500 (vector 10, scale 50) one ULP of it is 1e-3 rad: the sine and saw \
             there follow Blender's to that precision, not better.",
        )
        .input(In::vec3("vector", [0.0, 0.0, 0.0]).range(-10.0, 10.0).doc("Where to evaluate (link geometry.position or uv)."))
        .input(In::float("scale", 5.0).range(0.0, 50.0).hard(-1.0e3, 1.0e3).doc("Multiplies vector."))
        .input(In::float("distortion", 0.0).range(0.0, 20.0).hard(-1.0e3, 1.0e3).doc("Radians of fBm noise added to the phase (times 2·fBm − 1)."))
        .input(In::float("detail", 2.0).range(0.0, 15.0).hard(0.0, 15.0).doc("Octaves of the distortion's fBm beyond the first."))
        .input(In::float("detail_scale", 1.0).range(0.0, 10.0).hard(-1.0e3, 1.0e3).doc("Frequency of the distortion's fBm relative to the bands."))
        .input(In::float("detail_roughness", 0.5).range(0.0, 1.0).hard(0.0, 1.0).doc("Amplitude ratio between the fBm's octaves."))
        .input(In::float("phase_offset", 0.0).range(-10.0, 10.0).hard(-1.0e3, 1.0e3).doc("Radians added to the phase (shifts the bands)."))
        .input(In::choice("type", TYPES, 0).doc("Bands (planes) or rings (cylinders or spheres)."))
        .input(In::choice("bands_direction", BANDS_DIRECTIONS, 0).doc("Bands only: the axis the bands advance along."))
        .input(In::choice("rings_direction", RINGS_DIRECTIONS, 0).doc("Rings only: the axis the rings turn about (spherical: the origin)."))
        .input(In::choice("profile", PROFILES, 0).doc("Sine, saw or triangle wave of the phase."))
        .output(Out::color("color").doc("fac as a grey."))
        .output(Out::float("fac").doc("The wave in [0, 1]."))
        .wgsl(WAVE_TEXTURE_WGSL)
        .wgsl_constant_inputs(&["type", "bands_direction", "rings_direction", "profile"])
        .wgsl_uses(&[BLENDER_NOISE_WGSL, SIN_COS_WGSL])
        .hard_case("a unit coordinate (Blender's nudge)", &[("vector", v3([1.0, 1.0, 1.0])), ("scale", f(1.0)), ("profile", i(1))])
        .hard_case("rings about the axis itself", &[("type", i(1)), ("vector", v3([0.5, 0.0, 0.0]))])
        .hard_case("spherical rings at the origin", &[("type", i(1)), ("rings_direction", i(3))])
        .hard_case("saw at a whole cycle", &[("vector", v3([0.314_159_27, 0.0, 0.0])), ("scale", f(1.0)), ("profile", i(1))])
        .hard_case(
            "strong distortion, 15 octaves",
            &[("vector", v3([0.3, 0.7, -0.2])), ("distortion", f(1.0e3)), ("detail", f(15.0)), ("detail_roughness", f(1.0)), ("detail_scale", f(1.0e3))],
        )
        .hard_case(
            "huge coordinates",
            &[("vector", v3([1.0e30, -1.0e30, 1.0e30])), ("scale", f(1.0e3)), ("distortion", f(1.0)), ("type", i(1)), ("rings_direction", i(3))],
        )
        .hard_case("zero scale", &[("scale", f(0.0)), ("distortion", f(2.0))])
        .compute(wave_texture),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The x bands' phase is 20·p.x: a quarter of Blender's 2π/20 period past the nudge is
    /// the sine's midpoint, half of it its crest.
    #[test]
    fn bands_have_blenders_period() {
        let at = |x: f32| {
            wave_texture(
                Vec3::new(x, 0.0, 0.0),
                1.0,
                0.0,
                0.0,
                1.0,
                0.5,
                0.0,
                0,
                0,
                0,
                0,
            )
            .1
        };
        let period = std::f32::consts::TAU / 20.0;
        let x0 = -0.000_001;
        assert!(at(x0).abs() < 1e-6);
        assert!((at(x0 + period / 4.0) - 0.5).abs() < 1e-5);
        assert!((at(x0 + period / 2.0) - 1.0).abs() < 1e-6);
    }
}
