//! The kinds of scene and their own parameters: the material ball over a checkered
//! backdrop, a water plane over a procedural seabed with objects standing in it, and the
//! soap bubble of seed 000 before its underwater backdrop ([`super::bubble`]).

use glam::Vec3;
use serde::de::{self, Deserializer, MapAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::fmt;

pub use super::bubble::BubbleSetup;
use super::environment::smoothstep;
use super::lod::WaterLod;
use super::snell::SnellRefraction;

/// What the scene is. In JSON: `"ball"`, `"water"` or `"bubble"` (all parameters at their
/// defaults), or `{"ball": {...}}` / `{"water": {...}}` / `{"bubble": {...}}`.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SceneKind {
    /// A material ball over a backdrop.
    Ball(BallSetup),
    /// A water plane over a seabed.
    Water(WaterSetup),
    /// A soap bubble moving before an underwater backdrop (seed 000).
    Bubble(BubbleSetup),
}

impl Default for SceneKind {
    fn default() -> Self {
        SceneKind::Ball(BallSetup::default())
    }
}

impl SceneKind {
    /// `"ball"`, `"water"` or `"bubble"`.
    pub fn name(&self) -> &'static str {
        match self {
            SceneKind::Ball(_) => "ball",
            SceneKind::Water(_) => "water",
            SceneKind::Bubble(_) => "bubble",
        }
    }
}

const KINDS: &[&str] = &["ball", "water", "bubble"];

impl<'de> Deserialize<'de> for SceneKind {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct KindVisitor;
        impl<'de> Visitor<'de> for KindVisitor {
            type Value = SceneKind;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(r#""ball", "plane", "water", "bubble", or {"ball": {...}}, {"water": {...}}, {"bubble": {...}}"#)
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<SceneKind, E> {
                match v {
                    "ball" => Ok(SceneKind::Ball(BallSetup::default())),
                    "plane" => Ok(SceneKind::Ball(BallSetup::plane())),
                    "water" => Ok(SceneKind::Water(WaterSetup::default())),
                    "bubble" => Ok(SceneKind::Bubble(BubbleSetup::default())),
                    other => Err(E::unknown_variant(other, KINDS)),
                }
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<SceneKind, A::Error> {
                let key: String = map
                    .next_key()?
                    .ok_or_else(|| de::Error::invalid_length(0, &self))?;
                let kind = match key.as_str() {
                    "ball" => SceneKind::Ball(map.next_value()?),
                    "water" => SceneKind::Water(map.next_value()?),
                    "bubble" => SceneKind::Bubble(map.next_value()?),
                    other => return Err(de::Error::unknown_variant(other, KINDS)),
                };
                if let Some(extra) = map.next_key::<String>()? {
                    return Err(de::Error::custom(format!(
                        "a scene kind has one key (\"ball\", \"water\" or \"bubble\"), found also `{extra}`"
                    )));
                }
                Ok(kind)
            }
        }
        d.deserialize_any(KindVisitor)
    }
}

/// The material ball: a UV sphere (or a flat square card, [`BallShape::Plane`]) standing on a
/// checkered floor before a back wall.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[serde(expecting = "a ball scene object")]
pub struct BallSetup {
    /// What carries the material: the sphere (default) or the card.
    #[serde(skip_serializing_if = "BallShape::is_sphere")]
    pub shape: BallShape,
    /// Centre of the sphere (or of the card), metres.
    pub center: [f32; 3],
    /// Radius of the sphere (half the card's side), metres (> 0).
    pub radius: f32,
    /// Tessellation: of the sphere `[segments around, rings pole to pole]`, the default
    /// 256 × 128 keeping the silhouette smooth at 1024 px; of the card `[cells across,
    /// cells up]`.
    pub segments: [u32; 2],
    /// The floor and back wall.
    pub backdrop: Backdrop,
}

impl Default for BallSetup {
    fn default() -> Self {
        BallSetup {
            shape: BallShape::Sphere,
            center: [0.0, 1.0, 0.0],
            radius: 1.0,
            segments: [256, 128],
            backdrop: Backdrop::default(),
        }
    }
}

impl BallSetup {
    /// The `"plane"` preset: the ball's setup with a 2 m square card in place of the sphere,
    /// standing on the floor and facing the camera (`+z`), in 32 × 32 cells.
    pub fn plane() -> Self {
        BallSetup {
            shape: BallShape::Plane,
            segments: [32, 32],
            ..BallSetup::default()
        }
    }
}

/// The surface of a [`BallSetup`], as Blender's material preview offers a sphere and a flat
/// plane.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[serde(expecting = "a ball shape name")]
pub enum BallShape {
    /// The UV sphere.
    #[default]
    Sphere,
    /// A vertical square card of side `2 · radius` centred on `center`, facing `+z`: uv
    /// `(0, 0)` at its lower left, `u` along `+x`, `v` along `+y` (the sphere's convention,
    /// `v` up), normal `+z`, tangent `+x`.
    Plane,
}

impl BallShape {
    /// Whether this is the sphere (the default, left out of saved scenes).
    pub fn is_sphere(&self) -> bool {
        *self == BallShape::Sphere
    }
}

/// The classic material-ball backdrop: a floor at `floor_y` from the wall forward, and a
/// vertical wall at `wall_z` facing `+z`, both with a checker. Positions are absolute (they
/// do not follow the ball's centre).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[serde(expecting = "a backdrop object")]
pub struct Backdrop {
    /// Whether the backdrop is there (without it the environment shows).
    pub enabled: bool,
    /// Height of the floor, metres.
    pub floor_y: f32,
    /// Position of the back wall along z, metres.
    pub wall_z: f32,
    /// Width of floor and wall along x (centred on x = 0), metres.
    pub width: f32,
    /// Height of the wall above the floor, metres.
    pub wall_height: f32,
    /// How far the floor reaches forward from the wall, metres.
    pub floor_depth: f32,
    /// Side of a checker square, metres (> 0).
    pub checker_size: f32,
    /// The two checker albedos, linear RGB in [0, 1].
    pub colors: [[f32; 3]; 2],
}

impl Default for Backdrop {
    fn default() -> Self {
        Backdrop {
            enabled: true,
            floor_y: 0.0,
            wall_z: -4.0,
            width: 16.0,
            wall_height: 8.0,
            floor_depth: 14.0,
            checker_size: 0.5,
            colors: [[0.75, 0.75, 0.75], [0.25, 0.25, 0.25]],
        }
    }
}

/// The water scene: a water plane at `y = 0` over a seabed, with objects.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[serde(expecting = "a water scene object")]
pub struct WaterSetup {
    /// Extent of the water plane `[x, z]` in metres, centred on the origin.
    pub size: [f32; 2],
    /// Cells of the water grid along x and z (the default 256 × 256 is dense enough for
    /// vertex displacement by waves a few metres long).
    pub grid: [u32; 2],
    /// The sea floor.
    pub seabed: Seabed,
    /// Objects standing in or floating on the water (reflected, and refracted below it).
    pub objects: Vec<WaterObject>,
    /// Quadtree level of detail of the water grid (seed 004 §3.1; [`super::lod`]); left
    /// out, the uniform `grid`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lod: Option<WaterLod>,
    /// The refraction map seen through the flat water by Snell's law ([`super::snell`]);
    /// left out, straight along the camera rays.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refraction: Option<SnellRefraction>,
}

impl Default for WaterSetup {
    fn default() -> Self {
        let wood = [0.42, 0.28, 0.16];
        let pole = |x, z, top| {
            WaterObject::Pole(PoleObject {
                base: [x, z],
                bottom: -7.0,
                top,
                radius: 0.15,
                color: wood,
            })
        };
        WaterSetup {
            size: [80.0, 80.0],
            grid: [256, 256],
            seabed: Seabed::default(),
            objects: vec![
                pole(-4.0, 6.0, 2.5),
                pole(-3.2, 6.5, 2.0),
                pole(-4.5, 4.8, 1.6),
                WaterObject::Box(BoxObject {
                    center: [3.0, 0.15, 4.0],
                    size: [1.2, 0.8, 1.2],
                    color: [0.55, 0.40, 0.22],
                }),
                WaterObject::Sphere(SphereObject {
                    center: [-1.5, 0.15, 9.0],
                    radius: 0.5,
                    color: [0.75, 0.08, 0.05],
                }),
                WaterObject::Box(BoxObject {
                    center: [8.0, 1.0, -6.0],
                    size: [3.5, 14.0, 3.5],
                    color: [0.45, 0.45, 0.42],
                }),
            ],
            lod: None,
            refraction: None,
        }
    }
}

/// The sea floor: a procedural heightfield `y = -depth(x, z)` (see
/// [`WaterSetup::seabed_depth`]) under the water plane, closed by vertical skirts along the
/// plane's edges so that the water never shows through to nothing. Seed 004's depth series
/// (35, 85, 135, 185 m) are flat beds: `depth_min = depth_max`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[serde(expecting = "a seabed object")]
pub struct Seabed {
    /// Smallest depth below the water surface, metres (≥ 0).
    pub depth_min: f32,
    /// Largest depth, metres (≥ `depth_min`).
    pub depth_max: f32,
    /// Weight in [0, 1] of the shelf (shallow at the near `+z` edge, deep at the far `-z`
    /// edge) against the bumps.
    pub slope: f32,
    /// Shifts the phases of the bumps; the same seed gives the same seabed.
    pub seed: u32,
    /// Cells of the seabed grid along x and z.
    pub grid: [u32; 2],
    /// Albedo of the sand, linear RGB in [0, 1].
    pub color: [f32; 3],
}

impl Default for Seabed {
    fn default() -> Self {
        Seabed {
            depth_min: 0.5,
            depth_max: 5.0,
            slope: 0.6,
            seed: 0,
            grid: [256, 256],
            color: [0.76, 0.66, 0.48],
        }
    }
}

/// The bumps of the seabed: `(amplitude, k_x, k_z, phase)` of each sine, wave numbers in
/// rad/m (wavelengths of about 10 to 45 m).
pub(crate) const BUMPS: [(f32, f32, f32, f32); 4] = [
    (1.0, 0.16, 0.09, 0.3),
    (0.7, -0.07, 0.21, 1.7),
    (0.45, 0.33, -0.27, 4.1),
    (0.25, 0.61, 0.47, 2.2),
];

/// Phase step per seed and bump index: the golden angle in radians.
const SEED_PHASE: f32 = 2.399_963;

/// The phase each bump gets from the seabed's seed: `seed · 2.399963 · (i + 1)` mod 2π.
pub(crate) fn seed_phases(seed: u32) -> [f32; 4] {
    std::array::from_fn(|i| {
        (seed as f32 * SEED_PHASE * (i + 1) as f32).rem_euclid(std::f32::consts::TAU)
    })
}

impl WaterSetup {
    /// Depth of the seabed below the water plane at `(x, z)`, metres:
    ///
    /// ```text
    /// b(x, z) = Σ_i a_i sin(kx_i x + kz_i z + φ_i + seed · 2.399963 · (i + 1)) / Σ_i a_i   ∈ [-1, 1]
    /// r(z)    = smoothstep(0, 1, (size_z / 2 - z) / size_z)     0 at the near edge, 1 at the far edge
    /// s       = slope · r + (1 - slope) · (1 + b) / 2             ∈ [0, 1]
    /// depth   = depth_min + (depth_max - depth_min) · s
    /// ```
    ///
    /// with the four sines of our choosing listed in the source (`BUMPS`). The seabed mesh
    /// samples this function; the `depth` attribute uses it exactly.
    pub fn seabed_depth(&self, x: f32, z: f32) -> f32 {
        let s = &self.seabed;
        let (mut sum, mut norm) = (0.0, 0.0);
        let phases = seed_phases(s.seed);
        for (i, (a, kx, kz, phase)) in BUMPS.iter().enumerate() {
            let seed_phase = phases[i];
            sum += a * (kx * x + kz * z + phase + seed_phase).sin();
            norm += a;
        }
        let b = sum / norm;
        let size_z = self.size[1].max(f32::MIN_POSITIVE);
        let r = smoothstep(0.0, 1.0, (0.5 * size_z - z) / size_z);
        let slope = s.slope.clamp(0.0, 1.0);
        let t = slope * r + (1.0 - slope) * 0.5 * (1.0 + b);
        s.depth_min + (s.depth_max - s.depth_min) * t
    }

    /// Height of the seabed at `(x, z)`: `-seabed_depth(x, z)`.
    pub fn seabed_height(&self, x: f32, z: f32) -> f32 {
        -self.seabed_depth(x, z)
    }
}

/// An object of the water scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[serde(expecting = "a water object: a box, sphere or pole")]
pub enum WaterObject {
    /// An axis-aligned box.
    Box(BoxObject),
    /// A sphere.
    Sphere(SphereObject),
    /// A vertical pole (cylinder), for piers and posts.
    Pole(PoleObject),
}

/// An axis-aligned box.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[serde(expecting = "a box object")]
pub struct BoxObject {
    /// Centre, metres.
    pub center: [f32; 3],
    /// Edge lengths along x, y, z, metres (> 0).
    pub size: [f32; 3],
    /// Albedo, linear RGB in [0, 1].
    pub color: [f32; 3],
}

impl Default for BoxObject {
    fn default() -> Self {
        BoxObject {
            center: [0.0, 0.0, 0.0],
            size: [1.0, 1.0, 1.0],
            color: [0.6, 0.6, 0.6],
        }
    }
}

/// A sphere.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[serde(expecting = "a sphere object")]
pub struct SphereObject {
    /// Centre, metres.
    pub center: [f32; 3],
    /// Radius, metres (> 0).
    pub radius: f32,
    /// Albedo, linear RGB in [0, 1].
    pub color: [f32; 3],
}

impl Default for SphereObject {
    fn default() -> Self {
        SphereObject {
            center: [0.0, 0.5, 0.0],
            radius: 0.5,
            color: [0.6, 0.6, 0.6],
        }
    }
}

/// A vertical pole.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[serde(expecting = "a pole object")]
pub struct PoleObject {
    /// Position `[x, z]` of its axis, metres.
    pub base: [f32; 2],
    /// Height of its bottom end, metres (below the seabed to stand in it).
    pub bottom: f32,
    /// Height of its top end, metres (> `bottom`).
    pub top: f32,
    /// Radius, metres (> 0).
    pub radius: f32,
    /// Albedo, linear RGB in [0, 1].
    pub color: [f32; 3],
}

impl Default for PoleObject {
    fn default() -> Self {
        PoleObject {
            base: [0.0, 0.0],
            bottom: -7.0,
            top: 2.0,
            radius: 0.15,
            color: [0.42, 0.28, 0.16],
        }
    }
}

impl WaterObject {
    /// Its albedo.
    pub fn color(&self) -> Vec3 {
        Vec3::from(match self {
            WaterObject::Box(b) => b.color,
            WaterObject::Sphere(s) => s.color,
            WaterObject::Pole(p) => p.color,
        })
    }
}
