//! The environment seen where no geometry is hit: a procedural sky with a sun, or an
//! equirectangular image that the caller loads (the core does no file I/O).
//!
//! The sky is a simple analytic gradient of our own (not a physical sky model such as
//! Preetham's): for a unit direction `d`,
//!
//! - above the horizon (`d.y ≥ 0`): `mix(horizon, zenith, sqrt(d.y))`, plus the sun: a disc
//!   of angular radius `sun_radius_deg` with radiance `sun_color · sun_intensity`, and a halo
//!   `sun_color · halo · max(0, d·s)^64` around it (`s` the unit sun direction);
//! - below it: `mix(horizon, ground, smoothstep(0, 0.1, -d.y))`.
//!
//! Built-in shading uses the environment as ambient light through an ambient cube (see
//! [`AmbientCube`]), with the sun disc and halo left out (the sun reaches surfaces through
//! the scene's directional light instead).

use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};
use std::f32::consts::PI;

use super::light::sun_direction;

/// A caller-supplied lookup of an environment image: radiance for a unit direction given in
/// the image's own frame (map it to texture coordinates with [`equirect_uv`]).
pub type EnvLookup = dyn Fn(Vec3) -> Vec3 + Sync;

/// The lookup of an equirectangular environment image `tex`, as both renderers read it:
/// [`equirect_uv`] of the direction, bilinear, repeating, level 0.
pub fn image_lookup(
    tex: std::sync::Arc<crate::texture::Texture>,
) -> impl Fn(Vec3) -> Vec3 + Send + Sync {
    move |d: Vec3| {
        tex.sample(
            equirect_uv(d),
            0.0,
            crate::texture::Wrap::Repeat,
            crate::texture::Filter::Bilinear,
        )
        .truncate()
    }
}

/// What surrounds the scene. In JSON: `{"sky": {...}}`, `{"image": {...}}`, or the name of a
/// sky preset (`"sunrise"`, `"day"`, `"sunset"`, `"night"`, see [`Sky::preset`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", from = "EnvironmentDoc")]
pub enum Environment {
    /// The procedural sky.
    Sky(Sky),
    /// An equirectangular image loaded by the caller.
    Image(ImageEnvironment),
}

impl Default for Environment {
    fn default() -> Self {
        Environment::Sky(Sky::default())
    }
}

/// How an environment is written in JSON.
#[derive(Deserialize)]
#[serde(rename_all = "snake_case")]
#[serde(
    expecting = "an environment: \"sunrise\", \"day\", \"sunset\", \"night\", {\"sky\": …} or {\"image\": …}"
)]
enum EnvironmentDoc {
    Sunrise,
    Day,
    Sunset,
    Night,
    Sky(Sky),
    Image(ImageEnvironment),
}

impl From<EnvironmentDoc> for Environment {
    fn from(doc: EnvironmentDoc) -> Environment {
        let preset = |name| Environment::Sky(Sky::preset(name).expect("built-in preset"));
        match doc {
            EnvironmentDoc::Sunrise => preset("sunrise"),
            EnvironmentDoc::Day => preset("day"),
            EnvironmentDoc::Sunset => preset("sunset"),
            EnvironmentDoc::Night => preset("night"),
            EnvironmentDoc::Sky(s) => Environment::Sky(s),
            EnvironmentDoc::Image(i) => Environment::Image(i),
        }
    }
}

/// Where the sky's sun is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
#[serde(expecting = "a sun position object")]
pub enum SunPosition {
    /// Along the scene's first directional light (straight up when there is none).
    #[default]
    FollowLight,
    /// Towards this direction (normalised on use).
    Direction([f32; 3]),
    /// At these angles (see [`sun_direction`]).
    Angles {
        /// Degrees above the horizon.
        elevation_deg: f32,
        /// Compass degrees: 0 north (`-z`), 90 east (`+x`).
        azimuth_deg: f32,
    },
}

/// The procedural sky (the model is in the module docs). Colours are linear RGB radiance.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[serde(expecting = "a sky object")]
pub struct Sky {
    /// Radiance straight up.
    pub zenith_color: [f32; 3],
    /// Radiance at the horizon.
    pub horizon_color: [f32; 3],
    /// Radiance below the horizon (the ground, or the sea far away).
    pub ground_color: [f32; 3],
    /// Where the sun is.
    pub sun: SunPosition,
    /// The sun disc's colour.
    pub sun_color: [f32; 3],
    /// Scale on the sun disc's colour.
    pub sun_intensity: f32,
    /// Angular radius of the sun disc in degrees (the real sun: 0.27).
    pub sun_radius_deg: f32,
    /// Strength of the glow around the sun.
    pub halo: f32,
    /// Scale on the sky's ambient light in built-in shading (≥ 0; 0.4 in the presets, so
    /// that shadows keep their contrast).
    pub ambient: f32,
}

impl Default for Sky {
    fn default() -> Self {
        Sky::preset("day").expect("built-in preset")
    }
}

impl Sky {
    /// The sky to go with a light preset of the same name, or `None` for an unknown name.
    /// Our choices: `day` a clear blue sky; `sunrise` and `sunset` an orange horizon under a
    /// dim blue zenith; `night` a dark blue sky with a moon disc.
    pub fn preset(name: &str) -> Option<Sky> {
        let sky = |zenith, horizon, ground, sun_color, sun_intensity| Sky {
            zenith_color: zenith,
            horizon_color: horizon,
            ground_color: ground,
            sun: SunPosition::FollowLight,
            sun_color,
            sun_intensity,
            sun_radius_deg: 0.5,
            halo: 0.3,
            ambient: 0.4,
        };
        Some(match name {
            "day" => sky(
                [0.18, 0.36, 0.80],
                [0.62, 0.74, 0.90],
                [0.22, 0.21, 0.19],
                [1.0, 0.95, 0.85],
                20.0,
            ),
            "sunrise" | "sunset" => sky(
                [0.12, 0.16, 0.38],
                [0.90, 0.50, 0.22],
                [0.12, 0.09, 0.07],
                [1.0, 0.55, 0.15],
                20.0,
            ),
            "night" => sky(
                [0.004, 0.008, 0.025],
                [0.025, 0.035, 0.07],
                [0.008, 0.008, 0.01],
                [0.8, 0.85, 1.0],
                2.0,
            ),
            _ => return None,
        })
    }

    /// Radiance towards unit direction `d` with the sun towards unit `sun`; `with_sun`
    /// false leaves out the disc and halo.
    pub fn radiance(&self, d: Vec3, sun: Vec3, with_sun: bool) -> Vec3 {
        let zenith = Vec3::from(self.zenith_color);
        let horizon = Vec3::from(self.horizon_color);
        if d.y < 0.0 {
            let t = smoothstep(0.0, 0.1, -d.y);
            return horizon.lerp(Vec3::from(self.ground_color), t);
        }
        let mut c = horizon.lerp(zenith, d.y.sqrt());
        if with_sun {
            let cos = d.dot(sun);
            let color = Vec3::from(self.sun_color);
            if cos >= self.sun_radius_deg.to_radians().cos() {
                c += color * self.sun_intensity;
            }
            c += color * (self.halo * cos.max(0.0).powi(64));
        }
        c
    }
}

/// An equirectangular environment image. The caller loads the file at `path` and passes a
/// lookup (see [`EnvLookup`], [`equirect_uv`]); without one the default sky stands in.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[serde(expecting = "an environment image object { \"path\", … }")]
pub struct ImageEnvironment {
    /// The image file, as written in the scene (resolved by the caller).
    pub path: String,
    /// How its values are read ([`crate::color_space`]); absent, by the file type (linear
    /// for HDR and EXR, sRGB for PNG and JPEG). An environment is radiance: `data` is
    /// refused.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub color_space: Option<crate::color_space::ColorSpace>,
    /// Scale on the image's radiance (≥ 0).
    pub intensity: f32,
    /// Rotation of the environment about `+y` in degrees (counter-clockwise seen from above).
    pub rotation_deg: f32,
}

impl Default for ImageEnvironment {
    fn default() -> Self {
        ImageEnvironment {
            path: String::new(),
            color_space: None,
            intensity: 1.0,
            rotation_deg: 0.0,
        }
    }
}

/// Texture coordinates of unit direction `d` in an equirectangular image (top-left origin):
/// `u = 0.5 + atan2(d.x, -d.z) / 2π` (so `-z` is the image centre and `+x` at u = 0.75),
/// `v = acos(d.y) / π` (zenith at the top row).
pub fn equirect_uv(d: Vec3) -> Vec2 {
    let u = 0.5 + d.x.atan2(-d.z) / (2.0 * PI);
    let v = d.y.clamp(-1.0, 1.0).acos() / PI;
    Vec2::new(u, v)
}

impl Environment {
    /// Radiance towards unit direction `dir`, with the sky's sun towards unit `sun` (the
    /// resolved [`SunPosition`], see `Scene::sun_direction`). An image environment turns
    /// `dir` by `-rotation_deg` about `+y` into the image's frame and scales the caller's
    /// lookup by `intensity`; with no lookup it falls back to the default sky.
    pub fn radiance(&self, dir: Vec3, sun: Vec3, image: Option<&EnvLookup>) -> Vec3 {
        match self {
            Environment::Sky(sky) => sky.radiance(dir, sun, true),
            Environment::Image(img) => img.intensity * image_or_default(img, dir, sun, image),
        }
    }

    /// Radiance without the sky's sun disc and halo (used for ambient light).
    pub(crate) fn ambient_radiance(&self, dir: Vec3, sun: Vec3, image: Option<&EnvLookup>) -> Vec3 {
        match self {
            Environment::Sky(sky) => sky.ambient * sky.radiance(dir, sun, false),
            Environment::Image(img) => img.intensity * image_or_default(img, dir, sun, image),
        }
    }
}

fn image_or_default(
    img: &ImageEnvironment,
    dir: Vec3,
    sun: Vec3,
    image: Option<&EnvLookup>,
) -> Vec3 {
    match image {
        Some(f) => {
            let (s, c) = (-img.rotation_deg.to_radians()).sin_cos();
            // Rotation about +y by the angle a: x' = c x + s z, z' = -s x + c z.
            f(Vec3::new(
                c * dir.x + s * dir.z,
                dir.y,
                -s * dir.x + c * dir.z,
            ))
        }
        None => Sky::default().radiance(dir, sun, true),
    }
}

/// Hermite smoothstep between `e0` and `e1`.
#[inline]
pub(crate) fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Ambient light as an ambient cube: six cosine-weighted mean radiances, one per axis
/// direction (McTaggart, "Half-Life 2 / Valve Source Shading", GDC 2004). For a unit
/// normal `n`, `eval(n) = Σ n_i² · face(sign n_i)`; a white Lambert surface reflects it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AmbientCube {
    /// Mean radiance over the hemispheres around +x, -x, +y, -y, +z, -z (cosine weighted).
    pub faces: [Vec3; 6],
}

impl AmbientCube {
    /// Integrates `radiance` over each axis hemisphere on a fixed 16 × 16 stratified grid of
    /// cosine-distributed directions (Malley's method); deterministic.
    pub fn from_radiance(radiance: impl Fn(Vec3) -> Vec3) -> AmbientCube {
        const N: usize = 16;
        let axes = [
            Vec3::X,
            Vec3::NEG_X,
            Vec3::Y,
            Vec3::NEG_Y,
            Vec3::Z,
            Vec3::NEG_Z,
        ];
        let faces = axes.map(|axis| {
            let (t, b) = axis.any_orthonormal_pair();
            let mut sum = Vec3::ZERO;
            for i in 0..N {
                for j in 0..N {
                    let u = (i as f32 + 0.5) / N as f32;
                    let v = (j as f32 + 0.5) / N as f32;
                    let r = u.sqrt();
                    let (s, c) = (2.0 * PI * v).sin_cos();
                    let d = t * (r * c) + b * (r * s) + axis * (1.0 - u).sqrt();
                    sum += radiance(d.normalize());
                }
            }
            sum / (N * N) as f32
        });
        AmbientCube { faces }
    }

    /// The ambient radiance a white Lambert surface with unit normal `n` reflects.
    #[inline]
    pub fn eval(&self, n: Vec3) -> Vec3 {
        let sq = n * n;
        let f = &self.faces;
        sq.x * if n.x >= 0.0 { f[0] } else { f[1] }
            + sq.y * if n.y >= 0.0 { f[2] } else { f[3] }
            + sq.z * if n.z >= 0.0 { f[4] } else { f[5] }
    }
}

/// The direction of a [`SunPosition`], given the scene's first directional light if any.
pub(crate) fn resolve_sun(sun: SunPosition, first_light: Option<Vec3>) -> Vec3 {
    match sun {
        SunPosition::FollowLight => first_light.unwrap_or(Vec3::Y),
        SunPosition::Direction(d) => Vec3::from(d).normalize_or(Vec3::Y),
        SunPosition::Angles {
            elevation_deg,
            azimuth_deg,
        } => sun_direction(elevation_deg, azimuth_deg),
    }
}
