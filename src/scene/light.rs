//! Lights: directional (a sun or moon) and point lights, and the four time-of-day presets of
//! seed 004 (Environment-adaptive real-time cartoon water, 2012; docs/models/README.md).
//!
//! Units and conventions: a light's `color × intensity` is the radiance scale that a white
//! Lambert surface facing the light reflects (no `1/π`), the convention of the toon and
//! Blinn–Phong nodes (`C = Kd · base · N·L`). Directions point from the surface towards
//! the light (`L`), unit length. A point light falls off with the inverse square of the
//! distance: `light_color = color · intensity / d²` (d in metres, clamped to ≥ 1 mm).
//!
//! Sun directions are written with [`sun_direction`]: elevation above the horizon and a
//! compass azimuth with north = `-z` (into the screen of the default cameras), east = `+x`.

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// The names accepted for light presets, in time-of-day order.
pub const LIGHT_PRESETS: [&str; 4] = ["sunrise", "day", "sunset", "night"];

/// Smallest distance used in the point-light falloff, metres.
pub(crate) const MIN_DISTANCE: f32 = 1e-3;

/// A light of the scene. In JSON: `{"directional": {...}}`, `{"point": {...}}`, or a preset
/// name (`"sunrise"`, `"day"`, `"sunset"`, `"night"`), which reads as its directional light.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", from = "LightDoc")]
pub enum Light {
    /// Parallel light from a direction (sun, moon).
    Directional(DirectionalLight),
    /// A point light with inverse-square falloff.
    Point(PointLight),
}

/// A directional light.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[serde(expecting = "a directional light object")]
pub struct DirectionalLight {
    /// Direction towards the light (normalised on use); default: the `day` sun.
    pub direction: [f32; 3],
    /// Linear RGB colour.
    pub color: [f32; 3],
    /// Scale on the colour (≥ 0).
    pub intensity: f32,
}

impl Default for DirectionalLight {
    fn default() -> Self {
        DirectionalLight {
            direction: sun_direction(50.0, 225.0).to_array(),
            color: [1.0, 1.0, 1.0],
            intensity: 1.0,
        }
    }
}

/// A point light.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[serde(expecting = "a point light object")]
pub struct PointLight {
    /// Position in world space, metres.
    pub position: [f32; 3],
    /// Linear RGB colour.
    pub color: [f32; 3],
    /// Scale on the colour (≥ 0): the radiance scale at 1 m.
    pub intensity: f32,
}

impl Default for PointLight {
    fn default() -> Self {
        PointLight {
            position: [0.0, 4.0, 2.0],
            color: [1.0, 1.0, 1.0],
            intensity: 10.0,
        }
    }
}

/// How a light is written in JSON: a full light or a preset's name.
#[derive(Deserialize)]
#[serde(rename_all = "snake_case")]
#[serde(expecting = "a light object { \"directional\": … } or { \"point\": … }")]
enum LightDoc {
    Sunrise,
    Day,
    Sunset,
    Night,
    Directional(DirectionalLight),
    Point(PointLight),
}

impl From<LightDoc> for Light {
    fn from(doc: LightDoc) -> Light {
        let preset = |name| Light::preset(name).expect("built-in preset");
        match doc {
            LightDoc::Sunrise => preset("sunrise"),
            LightDoc::Day => preset("day"),
            LightDoc::Sunset => preset("sunset"),
            LightDoc::Night => preset("night"),
            LightDoc::Directional(d) => Light::Directional(d),
            LightDoc::Point(p) => Light::Point(p),
        }
    }
}

/// Unit direction towards a sun at `elevation_deg` above the horizon and compass azimuth
/// `azimuth_deg` (0 = north = `-z`, 90 = east = `+x`, 180 = south = `+z`, 270 = west = `-x`):
/// `(sin az · cos el, sin el, -cos az · cos el)`.
pub fn sun_direction(elevation_deg: f32, azimuth_deg: f32) -> Vec3 {
    let (se, ce) = elevation_deg.to_radians().sin_cos();
    let (sa, ca) = azimuth_deg.to_radians().sin_cos();
    Vec3::new(sa * ce, se, -ca * ce).normalize()
}

impl Light {
    /// The directional light of a time-of-day preset of seed 004, or `None` for an unknown
    /// name. Colours are the paper's; elevations and azimuths are ours:
    ///
    /// | preset  | colour             | elevation | azimuth            |
    /// |---------|--------------------|-----------|--------------------|
    /// | sunrise | (0.8, 0.3, 0.0)    | 8°        | 70° (east-north-east, in front right) |
    /// | day     | (0.7, 0.7, 0.7)    | 50°       | 225° (south-west, behind left of the default cameras) |
    /// | sunset  | (0.8, 0.3, 0.0)    | 8°        | 290° (west-north-west, in front left) |
    /// | night   | (0.25, 0.25, 0.25) | 35°       | 160° (a moon, south-south-east) |
    ///
    /// Intensity is 1 for all four.
    pub fn preset(name: &str) -> Option<Light> {
        let (color, elevation, azimuth) = match name {
            "sunrise" => ([0.8, 0.3, 0.0], 8.0, 70.0),
            "day" => ([0.7, 0.7, 0.7], 50.0, 225.0),
            "sunset" => ([0.8, 0.3, 0.0], 8.0, 290.0),
            "night" => ([0.25, 0.25, 0.25], 35.0, 160.0),
            _ => return None,
        };
        Some(Light::Directional(DirectionalLight {
            direction: sun_direction(elevation, azimuth).to_array(),
            color,
            intensity: 1.0,
        }))
    }

    /// Unit direction from `p` towards the light, and the light's radiance scale arriving at
    /// `p` (unshadowed): `color · intensity` for a directional light, `color · intensity /
    /// d²` for a point light at distance `d` (d clamped to ≥ 1 mm; the direction at the light
    /// itself is `+y`). Also returns the distance to the light (infinite for directional).
    #[inline]
    pub fn incident(&self, p: Vec3) -> (Vec3, Vec3, f32) {
        match self {
            Light::Directional(d) => (
                Vec3::from(d.direction).normalize_or(Vec3::Y),
                Vec3::from(d.color) * d.intensity,
                f32::INFINITY,
            ),
            Light::Point(l) => {
                let to = Vec3::from(l.position) - p;
                let dist = to.length();
                let dir = if dist > 0.0 { to / dist } else { Vec3::Y };
                let d = dist.max(MIN_DISTANCE);
                (dir, Vec3::from(l.color) * (l.intensity / (d * d)), dist)
            }
        }
    }

    /// The light's colour times intensity (before falloff).
    pub fn radiance_scale(&self) -> Vec3 {
        match self {
            Light::Directional(d) => Vec3::from(d.color) * d.intensity,
            Light::Point(l) => Vec3::from(l.color) * l.intensity,
        }
    }
}
