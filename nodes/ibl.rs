//! Image-based lighting by the split sum (Karis 2013, "Real Shading in Unreal Engine 4"):
//! the scene's environment prefiltered for GGX (`env_specular`), the BRDF integration table
//! (`env_brdf`) and the irradiance in spherical harmonics (`env_diffuse`, Ramamoorthi &
//! Hanrahan 2001). The tables are made by `scene::ibl` (docs/models/ibl.md); these nodes
//! read them as the textures named by their `texture` field: `scene:environment_ggx`,
//! `scene:brdf_lut` and `scene:environment_sh`.
//!
//! A metal's environment specular is `env_specular(r, roughness) · single + env_diffuse(n) ·
//! multiple` with `single = F0·A + B` and `multiple` the multiple-scattering term of
//! Fdez-Agüera 2019 (see [`env_brdf`]); `r = reflect(−v, n)`.

use crate::node::{Category, In, NodeType, Out, TextureSampler};
use crate::plan::TILE;
use crate::scene::ibl::{GGX_LEVELS, LUT_SIZE};
use crate::texture::{Filter, Wrap};
use crate::value::Value;
use glam::{Vec2, Vec3};

use super::image::equirect_uv_of;

/// Reads component `c` … of a vec3 port at sample `i` of a tile.
#[inline]
fn vec3_at(port: &[f32], i: usize) -> Vec3 {
    Vec3::new(port[i], port[TILE + i], port[2 * TILE + i])
}

/// Writes a vec3 at sample `i` of a tile.
#[inline]
fn put3(port: &mut [f32], i: usize, v: Vec3) {
    port[i] = v.x;
    port[TILE + i] = v.y;
    port[2 * TILE + i] = v.z;
}

/// The prefiltered environment towards `direction` at perceptual `roughness`: the
/// equirectangular texture at `uv = equirect_uv(direction)` and mip level
/// `clamp(roughness, 0, 1) · (GGX_LEVELS − 1)` (level k is roughness k/(GGX_LEVELS − 1);
/// fractions blend two levels), clamped at the edges, bilinear.
pub fn env_specular(sample: &TextureSampler, direction: Vec3, roughness: f32) -> Vec3 {
    let uv = equirect_uv_of(direction);
    let lod = roughness.clamp(0.0, 1.0) * (GGX_LEVELS - 1) as f32;
    sample(uv, lod, Wrap::Clamp, Filter::Bilinear).truncate()
}

/// `(scale_bias, single, multiple)` at `n_dot_v` and perceptual `roughness` (both clamped to
/// [0, 1]) for `f0` (clamped to [0, 1]): `(A, B)` read from the BRDF table at
/// `uv = (½ + x·(LUT_SIZE − 1))/LUT_SIZE` (exact at its grid points), `single = F0·A + B`
/// (Karis 2013 eq. 8's second factor), and the multiple-scattering term of Fdez-Agüera 2019
/// ("A Multiple-Scattering Microfacet Model for Real-Time Image-based Lighting", JCGT 8(1),
/// eqs. 10–16): `E_ss = A + B` (clamped to [0, 1]), `F_avg = F0 + (1 − F0)/21`,
/// `multiple = single · F_avg (1 − E_ss) / (1 − (1 − E_ss) F_avg)`, the denominator kept
/// ≥ 10⁻⁶ (it is 0 only for E_ss = 0 and F0 = 1, where the numerator is 0 too). With a
/// uniform environment `single + multiple` is 1 for F0 = 1 (a white furnace).
pub fn env_brdf(
    sample: &TextureSampler,
    n_dot_v: f32,
    roughness: f32,
    f0: Vec3,
) -> (Vec2, Vec3, Vec3) {
    let n = LUT_SIZE as f32;
    let x = n_dot_v.clamp(0.0, 1.0);
    let y = roughness.clamp(0.0, 1.0);
    let uv = Vec2::new((0.5 + x * (n - 1.0)) / n, (0.5 + y * (n - 1.0)) / n);
    let t = sample(uv, 0.0, Wrap::Clamp, Filter::Bilinear);
    let f0 = f0.clamp(Vec3::ZERO, Vec3::ONE);
    let single = f0 * t.x + Vec3::splat(t.y);
    let ems = 1.0 - (t.x + t.y).clamp(0.0, 1.0);
    let favg = f0 + (Vec3::ONE - f0) / 21.0;
    let denom = (Vec3::ONE - favg * ems).max(Vec3::splat(1e-6));
    let multiple = single * favg * ems / denom;
    (Vec2::new(t.x, t.y), single, multiple)
}

/// `E(n)/π` — the light a white Lambert surface with normal `normal` reflects — from the 9
/// spherical-harmonic coefficients (texel k of the texture, nearest): `max(0, Σ cₖ Yₖ(n))`
/// with `n` normalised (zero stays zero) and `Yₖ` the real harmonics of bands 0–2 about
/// `+y` (Ramamoorthi & Hanrahan 2001 eq. 3; `scene::ibl::sh_basis`). The clamp at 0
/// removes the negative lobes nine coefficients ring with around a strong small source
/// (it adds light there: at most the ringing's depth).
pub fn env_diffuse(sample: &TextureSampler, normal: Vec3) -> Vec3 {
    let l2 = normal.dot(normal);
    let n = if l2 > 1e-20 {
        normal / l2.sqrt()
    } else {
        Vec3::ZERO
    };
    // Ramamoorthi & Hanrahan's (x, y, z) are our (x, z, y).
    let (x, y, z) = (n.x, n.z, n.y);
    let basis = [
        0.282095,
        0.488603 * y,
        0.488603 * z,
        0.488603 * x,
        1.092548 * x * y,
        1.092548 * y * z,
        0.315392 * (3.0 * z * z - 1.0),
        1.092548 * x * z,
        0.546274 * (x * x - y * y),
    ];
    let mut e = Vec3::ZERO;
    for (k, b) in basis.iter().enumerate() {
        let uv = Vec2::new((k as f32 + 0.5) / 9.0, 0.5);
        e += sample(uv, 0.0, Wrap::Clamp, Filter::Nearest).truncate() * *b;
    }
    e.max(Vec3::ZERO)
}

/// WGSL of [`equirect_uv_of`] (the `equirect_uv` node's body).
const EQUIRECT_WGSL: &str = r#"
fn mg_ibl_equirect_uv(d: vec3<f32>) -> vec2<f32> {
    let horizontal = d.x * d.x + d.z * d.z;
    let u = select(0.5 + atan2(d.x, -d.z) / 6.2831855, 0.5, horizontal == 0.0);
    let v = select(atan2(sqrt(horizontal), d.y) / 3.1415927, 0.5, all(d == vec3<f32>(0.0)));
    return vec2<f32>(u, v);
}
"#;

/// WGSL of [`env_specular`] (5 = GGX_LEVELS − 1; wrap 1 clamp, filter 1 bilinear).
const ENV_SPECULAR_WGSL: &str = r#"
fn $fn(tex: u32, direction: vec3<f32>, roughness: f32) -> vec3<f32> {
    let uv = mg_ibl_equirect_uv(direction);
    let lod = clamp(roughness, 0.0, 1.0) * 5.0;
    return mg_sample_texture(tex, uv, lod, 1u, 1u).xyz;
}
"#;

/// WGSL of [`env_brdf`] (32 = LUT_SIZE).
const ENV_BRDF_WGSL: &str = r#"
fn $fn(tex: u32, n_dot_v: f32, roughness: f32, f0_in: vec3<f32>) -> $out {
    let n = 32.0;
    let x = clamp(n_dot_v, 0.0, 1.0);
    let y = clamp(roughness, 0.0, 1.0);
    let uv = vec2<f32>((0.5 + x * (n - 1.0)) / n, (0.5 + y * (n - 1.0)) / n);
    let t = mg_sample_texture(tex, uv, 0.0, 1u, 1u);
    let f0 = clamp(f0_in, vec3<f32>(0.0), vec3<f32>(1.0));
    let single = f0 * t.x + vec3<f32>(t.y);
    let ems = 1.0 - clamp(t.x + t.y, 0.0, 1.0);
    let favg = f0 + (vec3<f32>(1.0) - f0) / 21.0;
    let denom = max(vec3<f32>(1.0) - favg * ems, vec3<f32>(1e-6));
    let multiple = single * favg * ems / denom;
    return $out(vec2<f32>(t.x, t.y), single, multiple);
}
"#;

/// WGSL of [`env_diffuse`] (wrap 1 clamp, filter 0 nearest).
const ENV_DIFFUSE_WGSL: &str = r#"
fn $fn(tex: u32, normal: vec3<f32>) -> vec3<f32> {
    let l2 = dot(normal, normal);
    let nn = select(vec3<f32>(0.0), normal / sqrt(l2), l2 > 1e-20);
    let x = nn.x;
    let y = nn.z;
    let z = nn.y;
    var basis = array<f32, 9>(
        0.282095,
        0.488603 * y,
        0.488603 * z,
        0.488603 * x,
        1.092548 * x * y,
        1.092548 * y * z,
        0.315392 * (3.0 * z * z - 1.0),
        1.092548 * x * z,
        0.546274 * (x * x - y * y),
    );
    var e = vec3<f32>(0.0);
    for (var k = 0u; k < 9u; k++) {
        let uv = vec2<f32>((f32(k) + 0.5) / 9.0, 0.5);
        e += mg_sample_texture(tex, uv, 0.0, 1u, 0u).xyz * basis[k];
    }
    return max(e, vec3<f32>(0.0));
}
"#;

fn env_specular_tile(sample: &TextureSampler, ins: &[&[f32]], outs: &mut [&mut [f32]], n: usize) {
    for i in 0..n {
        let c = env_specular(sample, vec3_at(ins[0], i), ins[1][i]);
        put3(outs[0], i, c);
    }
}

fn env_brdf_tile(sample: &TextureSampler, ins: &[&[f32]], outs: &mut [&mut [f32]], n: usize) {
    for i in 0..n {
        let (ab, single, multiple) = env_brdf(sample, ins[0][i], ins[1][i], vec3_at(ins[2], i));
        outs[0][i] = ab.x;
        outs[0][TILE + i] = ab.y;
        put3(outs[1], i, single);
        put3(outs[2], i, multiple);
    }
}

fn env_diffuse_tile(sample: &TextureSampler, ins: &[&[f32]], outs: &mut [&mut [f32]], n: usize) {
    for i in 0..n {
        let c = env_diffuse(sample, vec3_at(ins[0], i));
        put3(outs[0], i, c);
    }
}

/// The image-based-lighting node types.
pub fn all() -> Vec<NodeType> {
    let f = Value::float;
    let v3 = Value::vec3;
    let c = Value::color;
    vec![
        NodeType::new(
            "env_specular",
            Category::Pbr,
            "The scene's environment prefiltered for GGX, towards a direction.",
        )
        .source(
            "Karis 2013, \"Real Shading in Unreal Engine 4\", split sum, first factor: the \
             environment averaged over GGX-importance-sampled directions weighted by n·l, \
             assuming n = v = r (no lobe stretching at grazing view), one mip level per \
             roughness k/5 (scene::ibl::prefilter_ggx; docs/models/ibl.md). Set \"texture\": \
             \"scene:environment_ggx\". Read at equirect_uv(direction), lod = 5·roughness \
             (roughness clamped to [0, 1]), clamped at the edges, bilinear.",
        )
        .input(In::vec3("direction", [0.0, 0.0, -1.0]).range(-1.0, 1.0).doc("Where to look: the reflection direction reflect(−view, normal) (need not be unit length)."))
        .input(In::float("roughness", 0.5).range(0.0, 1.0).hard(0.0, 1.0).doc("Perceptual roughness (α = roughness²); clamped to [0, 1]."))
        .output(Out::color("color").doc("Prefiltered radiance, linear RGB."))
        .wgsl(ENV_SPECULAR_WGSL)
        .wgsl_uses(&[EQUIRECT_WGSL, crate::texture::SAMPLE_WGSL])
        .hard_case("zenith, mirror", &[("direction", v3([0.0, 1.0, 0.0])), ("roughness", f(0.0))])
        .hard_case("zero direction", &[("direction", v3([0.0, 0.0, 0.0]))])
        .hard_case("roughest", &[("direction", v3([0.3, -0.8, 0.5])), ("roughness", f(1.0))])
        .compute(|_d: Vec3, _r: f32| Vec3::ZERO)
        .texture_kernel(env_specular_tile),
        NodeType::new(
            "env_brdf",
            Category::Pbr,
            "The split sum's BRDF integral: scale and bias of F0, with multiple scattering.",
        )
        .source(
            "Karis 2013, split sum, second factor: ∫ f (n·l) dl = F0·A + B with Schlick's \
             Fresnel, A and B tabulated over (n·v, roughness) by importance-sampled GGX with \
             height-correlated Smith (scene::ibl::brdf_lut, 32 × 32, f64). multiple: the \
             multiple-scattering term of Fdez-Agüera 2019 (JCGT 8(1)), F_avg = F0 + (1 − F0)/21, \
             multiple = single·F_avg·(1 − E)/(1 − (1 − E)·F_avg), E = A + B; light it with \
             env_diffuse. Set \"texture\": \"scene:brdf_lut\". Inputs clamped to [0, 1].",
        )
        .input(In::float("n_dot_v", 1.0).range(0.0, 1.0).hard(-1.0, 1.0).doc("Cosine between normal and view; clamped to [0, 1]."))
        .input(In::float("roughness", 0.5).range(0.0, 1.0).hard(0.0, 1.0).doc("Perceptual roughness (α = roughness²); clamped to [0, 1]."))
        .input(In::color("f0", [0.04, 0.04, 0.04]).range(0.0, 1.0).hard(0.0, 1.0).doc("Reflectance at normal incidence; clamped to [0, 1]."))
        .output(Out::vec2("scale_bias").doc("(A, B): the directional albedo is F0·A + B."))
        .output(Out::color("single").doc("F0·A + B: weight of env_specular (single scattering)."))
        .output(Out::color("multiple").doc("Multiple-scattering weight (Fdez-Agüera 2019): weight of env_diffuse."))
        .wgsl(ENV_BRDF_WGSL)
        .wgsl_uses(&[crate::texture::SAMPLE_WGSL])
        .hard_case("grazing, smooth", &[("n_dot_v", f(0.0)), ("roughness", f(0.0))])
        .hard_case("white metal, roughest", &[("roughness", f(1.0)), ("f0", c([1.0, 1.0, 1.0]))])
        .hard_case("back-facing", &[("n_dot_v", f(-0.5))])
        .compute(|_nv: f32, _r: f32, _f0: Vec3| (Vec2::ZERO, Vec3::ZERO, Vec3::ZERO))
        .texture_kernel(env_brdf_tile),
        NodeType::new(
            "env_diffuse",
            Category::Pbr,
            "The scene's environment irradiance over π, from 9 spherical harmonics.",
        )
        .source(
            "Ramamoorthi & Hanrahan 2001, \"An Efficient Representation for Irradiance \
             Environment Maps\": E(n) = Σ Â_l L_lm Y_lm(n), bands 0–2, Â = (π, 2π/3, π/4); the \
             coefficients (times Â_l/π) are texels 0–8 of \"texture\": \"scene:environment_sh\" \
             (scene::ibl::sh_irradiance). Returns max(0, E/π): multiply by the albedo for \
             Lambert diffuse.",
        )
        .input(In::vec3("normal", [0.0, 1.0, 0.0]).range(-1.0, 1.0).doc("Surface normal (normalised here)."))
        .output(Out::color("color").doc("E(n)/π: the light a white Lambert surface reflects, linear RGB."))
        .wgsl(ENV_DIFFUSE_WGSL)
        .wgsl_uses(&[crate::texture::SAMPLE_WGSL])
        .hard_case("zero normal", &[("normal", v3([0.0, 0.0, 0.0]))])
        .hard_case("straight down", &[("normal", v3([0.0, -1.0, 0.0]))])
        .compute(|_n: Vec3| Vec3::ZERO)
        .texture_kernel(env_diffuse_tile),
    ]
}
