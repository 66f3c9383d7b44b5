//! Image-based lighting by the split sum (Karis 2013, "Real Shading in Unreal Engine 4",
//! SIGGRAPH course notes, pp. 5–7): the specular reflection of an environment `L` by the
//! GGX BRDF `f` is approximated by the product of two separately precomputed integrals,
//!
//! `∫ L(l) f(l, v) (n·l) dl ≈ [Σₖ L(lₖ)(n·lₖ) / Σₖ (n·lₖ)] · [∫ f(l, v) (n·l) dl]`,
//!
//! - the **prefiltered environment** (first factor, [`prefilter_ggx`]): `L` averaged over
//!   GGX-importance-sampled directions `lₖ` weighted by `n·lₖ`, under Karis's assumption
//!   `n = v = r` (the lobe seen head on, so the prefiltered map is a function of the
//!   reflection direction `r` and roughness only; what it costs: no stretching of the lobe
//!   at grazing view, the reflection at grazing angles is too sharp and too round). One mip
//!   level per roughness `k / (GGX_LEVELS − 1)`;
//! - the **BRDF integration table** (second factor, [`brdf_lut`]): with Schlick's Fresnel
//!   `F = F0 + (1 − F0)(1 − v·h)⁵` the integral is `F0·A + B` with
//!   `A = ∫ (1 − (1 − v·h)⁵) f/F (n·l) dl`, `B = ∫ (1 − v·h)⁵ f/F (n·l) dl`, tabulated over
//!   (n·v, roughness) in f64;
//! - **irradiance** for diffuse light ([`sh_irradiance`]): the environment projected on the 9
//!   real spherical harmonics of bands 0–2 and convolved with the clamped cosine (Ramamoorthi
//!   & Hanrahan 2001, "An Efficient Representation for Irradiance Environment Maps",
//!   SIGGRAPH, eqs. 3, 8 and 9: `E(n) = Σ Âₗ Lₗₘ Yₗₘ(n)`, `Â₀ = π`, `Â₁ = 2π/3`, `Â₂ = π/4`).
//!
//! The BRDF is the one of the `pbr_brdf` node: GGX `D` (Walter et al. 2007), height-correlated
//! Smith visibility (Heitz 2014 eq. 99), α = roughness², roughness clamped below at 0.02.
//! Everything here runs on the CPU, deterministically (fixed Hammersley point sets, sums in a
//! fixed order); the GPU render uploads these results.

use glam::{DVec3, Vec2, Vec3};
use rayon::prelude::*;
use std::f64::consts::PI;
use std::sync::LazyLock;

use crate::texture::{Filter, Image, Texture, TextureError, Wrap};

/// Mip levels of the prefiltered environment: level `k` is roughness `k / (GGX_LEVELS − 1)`.
pub const GGX_LEVELS: u32 = 6;
/// Width of the prefiltered environment's level 0 (its height is half).
pub const GGX_WIDTH: u32 = 256;
/// GGX samples per texel of a prefiltered level.
pub const GGX_SAMPLES: u32 = 96;
/// Side of the BRDF integration table (n·v along x, roughness along y).
pub const LUT_SIZE: u32 = 32;
/// Hammersley samples per entry of the BRDF integration table.
pub const LUT_SAMPLES: u32 = 1024;
/// The smallest roughness the tables use (that of `pbr_brdf`).
pub const MIN_ROUGHNESS: f64 = 0.02;
/// Texels of the irradiance texture: the 9 spherical-harmonic coefficients.
pub const SH_TEXELS: u32 = 9;

/// Point `i` of the `n`-point Hammersley set in [0, 1)²: `(i/n, radical inverse of i in base 2)`.
#[inline]
pub fn hammersley(i: u32, n: u32) -> (f64, f64) {
    (
        i as f64 / n as f64,
        i.reverse_bits() as f64 * (1.0 / 4_294_967_296.0),
    )
}

/// GGX α from perceptual roughness, roughness clamped to [[`MIN_ROUGHNESS`], 1].
#[inline]
fn alpha(roughness: f64) -> f64 {
    let r = roughness.clamp(MIN_ROUGHNESS, 1.0);
    r * r
}

/// The half vector of GGX importance sample `(u1, u2)` in the frame where `n = +z`:
/// `cos θh = √((1 − u1)/(1 + (α² − 1) u1))`, `φ = 2π u2` (Walter et al. 2007 eqs. 35–36;
/// Karis 2013 `ImportanceSampleGGX`); its pdf over `h` is `D(h) (n·h)`.
#[inline]
fn ggx_half_vector(u1: f64, u2: f64, a: f64) -> DVec3 {
    let cos = ((1.0 - u1) / (1.0 + (a * a - 1.0) * u1)).sqrt();
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = 2.0 * PI * u2;
    DVec3::new(sin * phi.cos(), sin * phi.sin(), cos)
}

/// An orthonormal frame `(t, b, n)` around unit `n` (Duff et al. 2017, "Building an
/// Orthonormal Basis, Revisited", JCGT 6(1)).
#[inline]
fn frame(n: DVec3) -> (DVec3, DVec3) {
    let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    (
        DVec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        DVec3::new(b, s + n.y * n.y * a, -n.y),
    )
}

/// GGX `D(n·h) = α² / (π ((n·h)²(α² − 1) + 1)²)` (Walter et al. 2007 eq. 33).
#[inline]
fn ggx_d(nh: f64, a: f64) -> f64 {
    let a2 = a * a;
    let k = nh * nh * (a2 - 1.0) + 1.0;
    a2 / (PI * k * k)
}

/// Height-correlated Smith visibility `V = G₂/(4 n·l n·v)`
/// `= 0.5 / (n·l √((n·v)²(1 − α²) + α²) + n·v √((n·l)²(1 − α²) + α²))` (Heitz 2014 eq. 99).
#[inline]
pub fn smith_visibility(nv: f64, nl: f64, a: f64) -> f64 {
    let a2 = a * a;
    0.5 / (nl * (nv * nv * (1.0 - a2) + a2).sqrt() + nv * (nl * nl * (1.0 - a2) + a2).sqrt())
}

/// The BRDF integration table entry `(A, B)` at `n·v` and perceptual `roughness`:
/// `LUT_SAMPLES` Hammersley GGX samples of `h`, `l = 2(v·h)h − v`, each weighing
/// `f (n·l) / pdf(l) = 4 V (n·l)(v·h)/(n·h)` (Karis 2013 `IntegrateBRDF`, with the
/// height-correlated visibility), split into `(1 − Fc)` and `Fc = (1 − v·h)⁵`.
pub fn integrate_brdf(n_dot_v: f64, roughness: f64) -> (f64, f64) {
    let nv = n_dot_v.clamp(1e-6, 1.0);
    let v = DVec3::new((1.0 - nv * nv).sqrt(), 0.0, nv);
    let a = alpha(roughness);
    let (mut sa, mut sb) = (0.0, 0.0);
    for i in 0..LUT_SAMPLES {
        let (u1, u2) = hammersley(i, LUT_SAMPLES);
        let h = ggx_half_vector(u1, u2, a);
        let vh = v.dot(h);
        let l = 2.0 * vh * h - v;
        let (nl, nh) = (l.z, h.z);
        if nl > 0.0 && vh > 0.0 {
            let g = 4.0 * smith_visibility(nv, nl, a) * nl * vh / nh;
            let fc = (1.0 - vh).powi(5);
            sa += (1.0 - fc) * g;
            sb += fc * g;
        }
    }
    let n = LUT_SAMPLES as f64;
    (sa / n, sb / n)
}

/// `n·v` or roughness of table index `i` (grid points `i / (LUT_SIZE − 1)`, both ends in).
#[inline]
pub fn lut_coordinate(i: u32) -> f64 {
    i as f64 / (LUT_SIZE - 1) as f64
}

/// The BRDF integration table as a `LUT_SIZE²` texture, no mips: texel `(i, j)` holds
/// `(A, B, 0, 1)` at `n·v = lut_coordinate(i)`, `roughness = lut_coordinate(j)`. Read it
/// with clamp and bilinear at `uv = (½ + x·(LUT_SIZE − 1)) / LUT_SIZE` (exact at the grid
/// points). Computed once per process.
pub fn brdf_lut() -> &'static Texture {
    static LUT: LazyLock<Texture> = LazyLock::new(|| {
        let n = LUT_SIZE;
        let data: Vec<[f32; 4]> = (0..n * n)
            .into_par_iter()
            .map(|k| {
                let (a, b) = integrate_brdf(lut_coordinate(k % n), lut_coordinate(k / n));
                [a as f32, b as f32, 0.0, 1.0]
            })
            .collect();
        let image = Image::new(n, n, data).expect("a LUT_SIZE² image");
        Texture::new(image, false).expect("a valid image")
    });
    &LUT
}

/// Unit direction of texel `(x, y)`'s centre in a `w × h` equirectangular map.
#[inline]
fn texel_direction(x: u32, y: u32, w: u32, h: u32) -> DVec3 {
    super::equirect_direction(x, y, w, h).as_dvec3().normalize()
}

/// Radiance of `env` towards unit `d` at mip level `lod` (bilinear, linear across levels,
/// clamped at the edges).
#[inline]
fn lookup(env: &Texture, d: DVec3, lod: f64) -> DVec3 {
    let uv: Vec2 = super::equirect_uv(d.as_vec3());
    env.sample(uv, lod as f32, Wrap::Clamp, Filter::Bilinear)
        .truncate()
        .as_dvec3()
}

/// One level of the prefiltered environment at perceptual `roughness`, `w × h` texels:
/// texel direction `r`, with `n = v = r`, `GGX_SAMPLES` Hammersley GGX half vectors `h`,
/// `l = 2(v·h)h − v`, `Σ L(l)(n·l) / Σ (n·l)` over `n·l > 0` (Karis 2013
/// `PrefilterEnvMap`). Each sample reads `env` at the mip level whose texel covers the
/// sample's solid angle `1/(N pdf)`, `pdf = D/4` at `n = v` (Colbert & Křivánek 2007,
/// "GPU-Based Importance Sampling", GPU Gems 3 ch. 20, eq. 13: lod = ½ log₂(Ωs/Ωp) + 1),
/// so a few samples do not alias. Roughness 0 is the mirror: `env` read along `r`.
pub fn prefilter_ggx(env: &Texture, roughness: f64, w: u32, h: u32) -> Image {
    let a = alpha(roughness);
    let texel_solid_angle = 4.0 * PI / (env.width() as f64 * env.height() as f64);
    let data: Vec<[f32; 4]> = (0..w * h)
        .into_par_iter()
        .map(|k| {
            let r = texel_direction(k % w, k / w, w, h);
            let c = if roughness <= 0.0 {
                // The mirror, filtered to this level's texel size.
                lookup(env, r, (env.width() as f64 / w as f64).log2())
            } else {
                let (t, b) = frame(r);
                let (mut sum, mut weight) = (DVec3::ZERO, 0.0);
                for i in 0..GGX_SAMPLES {
                    let (u1, u2) = hammersley(i, GGX_SAMPLES);
                    let hl = ggx_half_vector(u1, u2, a);
                    let hv = t * hl.x + b * hl.y + r * hl.z;
                    let l = 2.0 * r.dot(hv) * hv - r;
                    let nl = r.dot(l);
                    if nl > 0.0 {
                        let pdf = ggx_d(hl.z, a) / 4.0;
                        let sample_solid_angle = 1.0 / (GGX_SAMPLES as f64 * pdf);
                        let lod =
                            (0.5 * (sample_solid_angle / texel_solid_angle).log2() + 1.0).max(0.0);
                        sum += lookup(env, l.normalize(), lod) * nl;
                        weight += nl;
                    }
                }
                sum / weight
            };
            [c.x as f32, c.y as f32, c.z as f32, 1.0]
        })
        .collect();
    Image::new(w, h, data).expect("a w × h image")
}

/// The prefiltered environment of the equirectangular map `source` (with its box mips): a mip
/// chain of [`GGX_LEVELS`] levels from [`GGX_WIDTH`] × [`GGX_WIDTH`]/2, level `k` at
/// roughness `k / (GGX_LEVELS − 1)` ([`prefilter_ggx`]).
pub fn environment_ggx(source: &Texture) -> Result<Texture, TextureError> {
    let levels = (0..GGX_LEVELS)
        .map(|k| {
            let w = (GGX_WIDTH >> k).max(2);
            let roughness = k as f64 / (GGX_LEVELS - 1) as f64;
            prefilter_ggx(source, roughness, w, w / 2)
        })
        .collect();
    Texture::from_levels(levels)
}

/// The 9 real spherical harmonics of bands 0–2 at unit `d`, in the order
/// `Y₀₀, Y₁₋₁, Y₁₀, Y₁₁, Y₂₋₂, Y₂₋₁, Y₂₀, Y₂₁, Y₂₂` (Ramamoorthi & Hanrahan 2001 eq. 3, with
/// their `(x, y, z)` our `(x, z, y)`: `y` is up here, so the zonal harmonics are about `y`).
#[inline]
pub fn sh_basis(d: DVec3) -> [f64; 9] {
    let (x, y, z) = (d.x, d.z, d.y);
    [
        0.282095,
        0.488603 * y,
        0.488603 * z,
        0.488603 * x,
        1.092548 * x * y,
        1.092548 * y * z,
        0.315392 * (3.0 * z * z - 1.0),
        1.092548 * x * z,
        0.546274 * (x * x - y * y),
    ]
}

/// The convolution weights `Âₗ/π` of the 9 harmonics (`Â₀ = π`, `Â₁ = 2π/3`, `Â₂ = π/4`,
/// Ramamoorthi & Hanrahan 2001 eq. 8), so that `Σ (Âₗ/π) Lₗₘ Yₗₘ(n) = E(n)/π`.
pub const SH_COSINE: [f64; 9] = [
    1.0,
    2.0 / 3.0,
    2.0 / 3.0,
    2.0 / 3.0,
    0.25,
    0.25,
    0.25,
    0.25,
    0.25,
];

/// `E(n)/π` — what a white Lambert surface with unit normal `n` reflects — from the
/// coefficients of [`sh_irradiance`].
#[inline]
pub fn sh_eval(coefficients: &[[f32; 3]; 9], n: DVec3) -> DVec3 {
    let y = sh_basis(n);
    coefficients
        .iter()
        .zip(y)
        .fold(DVec3::ZERO, |s, (c, y)| s + Vec3::from(*c).as_dvec3() * y)
}

/// The irradiance coefficients of an equirectangular map: `Lₗₘ = Σ L(d) Yₗₘ(d) ΔΩ` over its
/// texels (`ΔΩ = (2π/w)(π/h) sin θ` at the texel centre), times `Âₗ/π` ([`SH_COSINE`]):
/// evaluated by [`sh_eval`] they give `E(n)/π`. `env` is read at level
/// `lod` of its box-filtered mips (the projection needs few texels; box filtering keeps the
/// energy).
pub fn sh_irradiance(env: &Texture, lod: usize) -> [[f32; 3]; 9] {
    let level = &env.levels()[lod.min(env.level_count() - 1)];
    let (w, h) = (level.width, level.height);
    let rows: Vec<[DVec3; 9]> = (0..h)
        .into_par_iter()
        .map(|y| {
            let mut acc = [DVec3::ZERO; 9];
            let theta = (y as f64 + 0.5) / h as f64 * PI;
            let d_omega = (2.0 * PI / w as f64) * (PI / h as f64) * theta.sin();
            for x in 0..w {
                let t = level.texel(x, y);
                let l = DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64);
                let d = texel_direction(x, y, w, h);
                for (a, b) in acc.iter_mut().zip(sh_basis(d)) {
                    *a += l * (b * d_omega);
                }
            }
            acc
        })
        .collect();
    let mut out = [[0.0f32; 3]; 9];
    for (k, o) in out.iter_mut().enumerate() {
        let s: DVec3 = rows.iter().map(|r| r[k]).sum();
        *o = (s * SH_COSINE[k]).as_vec3().to_array();
    }
    out
}

/// The irradiance coefficients as a `SH_TEXELS × 1` texture (texel k: coefficient k, alpha
/// 1), no mips; read texel k at `uv = ((k + ½)/9, ½)`, nearest.
pub fn sh_texture(coefficients: &[[f32; 3]; 9]) -> Result<Texture, TextureError> {
    let data = coefficients
        .iter()
        .map(|c| [c[0], c[1], c[2], 1.0])
        .collect();
    Texture::new(Image::new(SH_TEXELS, 1, data)?, false)
}

/// The mip level of a 512 × 256 environment map the irradiance is projected from
/// (128 × 64 texels).
pub const SH_LEVEL: usize = 2;
