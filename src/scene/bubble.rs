//! The soap-bubble scene of seed 000 (docs/models/bubble.md): the bubble (the material
//! surface, a UV sphere) moving towards its target in front of an unlit backdrop, the
//! paper's "camera blend" of texture layers with the underwater quad's shimmer over it.
//!
//! - The bubble's centre at time `t` is `nodes::bubble::motion(start, target, rate, t)`,
//!   the closed form of the paper's per-frame lerp towards the destination.
//! - The backdrop is a quad facing `+z` at `backdrop.z`, unlit (the paper uses Unity's unlit
//!   shader). At its uv (0, 0 top left) its radiance is
//!   `camera_blend(base, layer_a, layer_b, …) + alpha · shimmer`, where
//!   `(shimmer, alpha) = underwater(normal_a(uv_a), normal_b(uv_b), alpha_map(uv), …)` and
//!   `(uv_a, uv_b) = underwater_uv(tiles · uv, t, …)`: the node functions of
//!   [`crate::nodes::bubble`], so the scene and a graph built from those nodes agree. The
//!   underwater quad lies on the backdrop (between it and the bubble) and adds its light.
//! - The six maps ([`BubbleMaps`]) are procedural: tileable value noise with fixed seeds,
//!   256 × 256, generated once per process. Procedural because the core does no I/O (a
//!   scene is a JSON value with no files to resolve), the maps are the same bytes on every
//!   run, and a GPU port can upload [`bubble_maps`] as they are.
//!
//! Everything here is CPU code of its own so that it can be ported to a render pipeline
//! without touching the ball and water scenes.

use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};
use std::sync::OnceLock;

use super::mesh::Mesh;
use super::objects::{Albedo, Geometry, Object};
use crate::nodes::bubble as paper;
use crate::texture::{Filter, Image, Texture, Wrap};

/// The bubble scene's parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[serde(expecting = "a bubble scene object")]
pub struct BubbleSetup {
    /// Centre of the bubble at time 0, metres.
    pub start: [f32; 3],
    /// Where the bubble is heading, metres.
    pub target: [f32; 3],
    /// Lerp factor per second of the approach (≥ 0): `1 − exp(−rate · t)` of the way there.
    pub rate: f32,
    /// Radius of the bubble, metres (> 0).
    pub radius: f32,
    /// Tessellation of the sphere: `[segments around, rings pole to pole]`.
    pub segments: [u32; 2],
    /// The backdrop and the underwater quad.
    pub backdrop: BubbleBackdrop,
}

impl Default for BubbleSetup {
    fn default() -> Self {
        BubbleSetup {
            start: [-1.3, -0.9, 0.0],
            target: [0.4, 0.35, 0.0],
            rate: 0.6,
            radius: 1.0,
            segments: [128, 64],
            backdrop: BubbleBackdrop::default(),
        }
    }
}

impl BubbleSetup {
    /// Centre of the bubble at `time` seconds ([`crate::nodes::bubble::motion`]).
    pub fn center_at(&self, time: f32) -> Vec3 {
        paper::motion(
            Vec3::from(self.start),
            Vec3::from(self.target),
            self.rate,
            time,
        )
        .1
    }
}

/// The backdrop: the camera blend of two texture layers over the base image, and the
/// underwater quad's shimmer over it (the parameters of the nodes `bubble_camera_blend`,
/// `bubble_underwater_uv` and `bubble_underwater`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[serde(expecting = "a bubble backdrop object")]
pub struct BubbleBackdrop {
    /// Position of the backdrop plane along z, metres (it faces `+z`).
    pub z: f32,
    /// Width and height of the quad, metres (> 0), centred on x = y = 0.
    pub size: [f32; 2],
    /// Intensity of the light-shaft layer.
    pub intensity_a: f32,
    /// Intensity of the seabed layer.
    pub intensity_b: f32,
    /// Blend from layer a (0) to layer b (1), in [0, 1].
    pub mix: f32,
    /// How much of the blend is applied over the base image, in [0, 1].
    pub amount: f32,
    /// Repeats of the normal textures across the quad (> 0).
    pub tiles: f32,
    /// Scroll velocity of the first normal texture, uv per second.
    pub velocity_a: [f32; 2],
    /// Scroll velocity of the second normal texture, uv per second.
    pub velocity_b: [f32; 2],
    /// Direction of the sunlight in the quad's tangent space (non-zero).
    pub light: [f32; 3],
    /// Colour of the shimmer, linear RGB ≥ 0.
    pub tint: [f32; 3],
    /// Brightness of the shimmer (≥ 0).
    pub strength: f32,
    /// Exponent narrowing the shimmer's bright streaks (≥ 0).
    pub sharpness: f32,
    /// Scale on the alpha texture, in [0, 1].
    pub opacity: f32,
}

impl Default for BubbleBackdrop {
    fn default() -> Self {
        BubbleBackdrop {
            z: -6.0,
            size: [22.0, 14.0],
            intensity_a: 1.2,
            intensity_b: 1.0,
            mix: 0.5,
            amount: 0.8,
            tiles: 2.0,
            velocity_a: [0.03, 0.012],
            velocity_b: [-0.02, 0.027],
            light: [0.3, 0.4, 0.866],
            tint: [0.55, 0.85, 1.0],
            strength: 0.5,
            sharpness: 6.0,
            opacity: 0.8,
        }
    }
}

/// Side of every map, texels.
pub const MAP_SIZE: u32 = 256;

/// The backdrop's six maps (linear RGBA, row 0 at the top, tileable).
#[derive(Clone, Debug, PartialEq)]
pub struct BubbleMaps {
    /// The current screen image under the blend: deep water, light above, dark below.
    pub base: Texture,
    /// Layer a: light shafts from the surface.
    pub layer_a: Texture,
    /// Layer b: the seabed, with murky water above it.
    pub layer_b: Texture,
    /// The first normal texture (encoded `0.5 + 0.5 n`).
    pub normal_a: Texture,
    /// The second normal texture.
    pub normal_b: Texture,
    /// The alpha texture (in every channel): strongest near the surface.
    pub alpha: Texture,
}

impl BubbleMaps {
    /// The maps with their names, in a fixed order.
    pub fn named(&self) -> [(&'static str, &Texture); 6] {
        [
            ("base", &self.base),
            ("layer_a", &self.layer_a),
            ("layer_b", &self.layer_b),
            ("normal_a", &self.normal_a),
            ("normal_b", &self.normal_b),
            ("alpha", &self.alpha),
        ]
    }
}

/// The maps, generated on first use ([`BubbleMaps`]); the same texels on every run.
pub fn bubble_maps() -> &'static BubbleMaps {
    static MAPS: OnceLock<BubbleMaps> = OnceLock::new();
    MAPS.get_or_init(generate_maps)
}

/// A 32-bit integer hash of a lattice point (Jarzynski and Olano, "Hash functions for GPU
/// rendering", JCGT 2020: PCG3D), as a value in [0, 1).
fn lattice(x: u32, y: u32, seed: u32) -> f32 {
    let mut v = [
        x.wrapping_mul(1664525).wrapping_add(1013904223),
        y.wrapping_mul(1664525).wrapping_add(1013904223),
        seed.wrapping_mul(1664525).wrapping_add(1013904223),
    ];
    v[0] = v[0].wrapping_add(v[1].wrapping_mul(v[2]));
    v[1] = v[1].wrapping_add(v[2].wrapping_mul(v[0]));
    v[2] = v[2].wrapping_add(v[0].wrapping_mul(v[1]));
    v[0] ^= v[0] >> 16;
    v[1] ^= v[1] >> 16;
    v[2] ^= v[2] >> 16;
    v[0] = v[0].wrapping_add(v[1].wrapping_mul(v[2]));
    (v[0] >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// Value noise of period `period` lattice cells over the unit square (so it tiles), with
/// Perlin's quintic fade `6t⁵ − 15t⁴ + 10t³` (continuous slopes, so the normal maps have
/// no facets); in [0, 1).
fn periodic_noise(u: f32, v: f32, period: u32, seed: u32) -> f32 {
    let (x, y) = (u * period as f32, v * period as f32);
    let (fx, fy) = (x.floor(), y.floor());
    let (tx, ty) = (x - fx, y - fy);
    let p = period as i64;
    let cell = |i: f32, d: i64| ((i as i64 + d).rem_euclid(p)) as u32;
    let (x0, x1, y0, y1) = (cell(fx, 0), cell(fx, 1), cell(fy, 0), cell(fy, 1));
    let fade = |t: f32| t * t * t * (t * (6.0 * t - 15.0) + 10.0);
    let (sx, sy) = (fade(tx), fade(ty));
    let a = lattice(x0, y0, seed) + (lattice(x1, y0, seed) - lattice(x0, y0, seed)) * sx;
    let b = lattice(x0, y1, seed) + (lattice(x1, y1, seed) - lattice(x0, y1, seed)) * sx;
    a + (b - a) * sy
}

/// Four octaves of [`periodic_noise`] (periods `period · 2^k`, weights `2^−k`), in [0, 1).
fn fbm(u: f32, v: f32, period: u32, seed: u32) -> f32 {
    let (mut sum, mut weight, mut total) = (0.0, 1.0, 0.0);
    for k in 0..4 {
        sum += weight * periodic_noise(u, v, period << k, seed.wrapping_add(k));
        total += weight;
        weight *= 0.5;
    }
    sum / total
}

fn lerp3(a: Vec3, b: Vec3, t: f32) -> Vec3 {
    a + (b - a) * t
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The texel centre `(u, v)` of texel `(x, y)`.
fn centre(x: u32, y: u32) -> (f32, f32) {
    (
        (x as f32 + 0.5) / MAP_SIZE as f32,
        (y as f32 + 0.5) / MAP_SIZE as f32,
    )
}

/// A map from a colour function of the texel centre.
fn map(f: impl Fn(f32, f32) -> Vec3) -> Texture {
    let image = Image::from_fn(MAP_SIZE, MAP_SIZE, |x, y| {
        let (u, v) = centre(x, y);
        let c = f(u, v);
        [c.x, c.y, c.z, 1.0]
    });
    Texture::new(image, false).expect("a generated map is valid")
}

/// A normal map from the height field `fbm(period, seed)`, by central differences over
/// one texel with wrapping, slopes scaled by `bumpiness`.
fn normal_map(period: u32, seed: u32, bumpiness: f32) -> Texture {
    let n = MAP_SIZE as f32;
    map(|u, v| {
        let h = |du: f32, dv: f32| {
            fbm(
                (u + du).rem_euclid(1.0),
                (v + dv).rem_euclid(1.0),
                period,
                seed,
            )
        };
        let dx = (h(1.0 / n, 0.0) - h(-1.0 / n, 0.0)) * 0.5 * n / period as f32;
        let dy = (h(0.0, 1.0 / n) - h(0.0, -1.0 / n)) * 0.5 * n / period as f32;
        let normal = Vec3::new(-bumpiness * dx, bumpiness * dy, 1.0).normalize();
        Vec3::splat(0.5) + 0.5 * normal
    })
}

fn generate_maps() -> BubbleMaps {
    let deep = Vec3::new(0.01, 0.05, 0.10);
    let shallow = Vec3::new(0.08, 0.40, 0.52);
    BubbleMaps {
        base: map(|u, v| {
            let n = fbm(u, v, 4, 11);
            lerp3(shallow, deep, v.powf(0.8)) * (0.85 + 0.3 * n)
        }),
        layer_a: map(|u, v| {
            // Slanted shafts: a 1-D noise across them, sharpened, fading with depth.
            let across = (u + 0.35 * v).rem_euclid(1.0);
            let ray = periodic_noise(across, 0.0, 24, 21).powi(3);
            let fade = (1.0 - v).powf(1.5);
            let water = lerp3(shallow, deep, v) * 0.6;
            water + Vec3::new(0.55, 0.85, 0.9) * (ray * fade)
        }),
        layer_b: map(|u, v| {
            let line = 0.74 + 0.08 * (fbm(u, 0.0, 3, 31) - 0.5);
            let sand = Vec3::new(0.55, 0.48, 0.32) * (0.6 + 0.4 * fbm(u, v, 16, 41));
            let murk = Vec3::new(0.03, 0.12, 0.18) * (0.7 + 0.6 * fbm(u, v, 6, 51));
            let t = smoothstep(line - 0.01, line + 0.01, v);
            // The seabed darkens towards the horizon line (further away).
            lerp3(murk, sand * (0.5 + 0.5 * smoothstep(line, 1.0, v)), t)
        }),
        normal_a: normal_map(3, 61, 1.6),
        normal_b: normal_map(5, 71, 1.2),
        alpha: map(|u, v| {
            let a = smoothstep(1.0, 0.1, v) * (0.5 + 0.5 * fbm(u, v, 5, 81));
            Vec3::splat(a)
        }),
    }
}

/// The scene's built-in geometry at `time`: the backdrop quad, unlit; no shadow casters
/// (the bubble lets the light through).
pub(crate) fn geometry(setup: &BubbleSetup, time: f32) -> Geometry {
    let b = &setup.backdrop;
    let [w, h] = b.size;
    let quad = Mesh::parallelogram(
        Vec3::new(-0.5 * w, -0.5 * h, b.z),
        Vec3::new(w, 0.0, 0.0),
        Vec3::new(0.0, h, 0.0),
        [1, 1],
    );
    Geometry {
        objects: vec![Object {
            mesh: quad,
            albedo: Albedo::Unlit(std::sync::Arc::new(BackdropShader::new(setup, time))),
            underwater: false,
            caster: None,
        }],
        casters: Vec::new(),
        material_caster: None,
    }
}

/// The backdrop's built-in shading: unlit, at one time.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct BackdropShader {
    /// The parameters.
    backdrop: BubbleBackdrop,
    /// Time in seconds.
    time: f32,
}

impl BackdropShader {
    /// The backdrop of `setup` at `time`.
    pub(crate) fn new(setup: &BubbleSetup, time: f32) -> BackdropShader {
        BackdropShader {
            backdrop: setup.backdrop.clone(),
            time,
        }
    }

    /// The parameters as the GPU rasteriser's `MgrBackdrop` (src/gpu/raster/backdrop.wgsl):
    /// size, intensities; mix, amount, tiles, time; velocities; light, strength; tint,
    /// sharpness; opacity.
    pub(crate) fn words(&self) -> [f32; 24] {
        let b = &self.backdrop;
        [
            b.size[0],
            b.size[1],
            b.intensity_a,
            b.intensity_b,
            b.mix,
            b.amount,
            b.tiles,
            self.time,
            b.velocity_a[0],
            b.velocity_a[1],
            b.velocity_b[0],
            b.velocity_b[1],
            b.light[0],
            b.light[1],
            b.light[2],
            b.strength,
            b.tint[0],
            b.tint[1],
            b.tint[2],
            b.sharpness,
            b.opacity,
            0.0,
            0.0,
            0.0,
        ]
    }

    /// The quad's uv at world point `p` (0, 0 at the top left seen from `+z`).
    pub(crate) fn uv(&self, p: Vec3) -> Vec2 {
        let [w, h] = self.backdrop.size;
        Vec2::new(p.x / w + 0.5, 0.5 - p.y / h)
    }

    /// Radiance leaving the backdrop at world point `p` (see the module docs).
    pub(crate) fn radiance(&self, p: Vec3) -> Vec3 {
        let b = &self.backdrop;
        let maps = bubble_maps();
        let uv = self.uv(p);
        let at = |t: &Texture, uv: Vec2, wrap| t.sample(uv, 0.0, wrap, Filter::Bilinear);
        let rgb = |t: &Texture, uv: Vec2, wrap| at(t, uv, wrap).truncate();
        let blend = paper::camera_blend(
            rgb(&maps.base, uv, Wrap::Clamp),
            rgb(&maps.layer_a, uv, Wrap::Clamp),
            rgb(&maps.layer_b, uv, Wrap::Clamp),
            b.intensity_a,
            b.intensity_b,
            b.mix,
            b.amount,
        );
        let (uv_a, uv_b) = paper::underwater_uv(
            uv * b.tiles,
            self.time,
            Vec2::from(b.velocity_a),
            Vec2::from(b.velocity_b),
        );
        let (shimmer, alpha) = paper::underwater(
            rgb(&maps.normal_a, uv_a, Wrap::Repeat),
            rgb(&maps.normal_b, uv_b, Wrap::Repeat),
            at(&maps.alpha, uv, Wrap::Clamp).x,
            Vec3::from(b.light),
            Vec3::from(b.tint),
            b.strength,
            b.sharpness,
            b.opacity,
        );
        blend + alpha * shimmer
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_tiles_and_stays_in_range() {
        for k in 0..50 {
            let v = k as f32 / 50.0;
            let a = periodic_noise(0.0, v, 6, 3);
            let b = periodic_noise(1.0, v, 6, 3);
            assert!((a - b).abs() < 1e-6, "{a} vs {b}");
            assert!((0.0..1.0).contains(&fbm(v, 0.3, 4, 9)));
        }
    }

    #[test]
    fn the_backdrop_is_unlit_and_moves_with_time() {
        let setup = BubbleSetup::default();
        let p = Vec3::new(1.0, 2.0, setup.backdrop.z);
        let a = BackdropShader::new(&setup, 0.0).radiance(p);
        let b = BackdropShader::new(&setup, 3.0).radiance(p);
        assert!(a.is_finite() && a.min_element() >= 0.0);
        assert_ne!(a, b, "the shimmer scrolls");
        assert_eq!(
            BackdropShader::new(&setup, 0.0).uv(Vec3::new(-11.0, 7.0, -6.0)),
            Vec2::ZERO
        );
    }
}
