//! Scenes for rendering materials: the material ball and the water scene of seed 004,
//! described in JSON, with the geometry side of deferred shading — meshes, a CPU
//! rasterizer, the G-buffer of the material surface, per-light columns, and the scene
//! textures (background, refraction, reflection).
//!
//! A scene file is a JSON object; every field may be left out (`{}` is the material ball):
//!
//! ```json
//! {
//!   "kind": "water",
//!   "camera": { "position": [0, 3, 18], "target": [0, 0, 0], "fov_y_deg": 50 },
//!   "lights": ["sunset", { "point": { "position": [2, 3, 4], "color": [1, 0.9, 0.7], "intensity": 20 } }],
//!   "environment": "sunset",
//!   "time": 1.5
//! }
//! ```
//!
//! - `kind`: `"ball"`, `"plane"` (the ball's setup with a flat card, [`BallShape::Plane`]),
//!   `"water"` or `"bubble"`, or `{"ball": {...}}` / `{"water": {...}}` / `{"bubble": {...}}`
//!   with the kind's parameters ([`BallSetup`], [`WaterSetup`], [`BubbleSetup`]);
//! - `camera`: [`Camera`]; fields left out take the kind's default camera's;
//! - `lights`: a list of [`Light`]s or preset names (`sunrise`, `day`, `sunset`, `night`);
//!   left out, the kind's default lights ([`Scene::default_lights`]);
//! - `environment`: [`Environment`] (`{"sky": {...}}`, `{"image": {...}}` or a sky preset
//!   name); left out, the kind's default sky;
//! - `time`: seconds, the `time` attribute.
//!
//! Unknown fields are errors, with line and column. A graph file may carry a scene under a
//! key of its own once the graph format has one: pass that value's text to
//! [`Scene::from_json`]. The core does no I/O: an image environment's file is loaded by the
//! caller and read through an [`EnvLookup`].
//!
//! World space is right-handed, metres, `y` up; the water plane is `y = 0`. Conventions of
//! the attributes are those of [`crate::node::Attribute`]: `N` out of the surface, `V` from
//! the surface to the eye, `L` from the surface to the light, all unit length.
//!
//! Deferred shading with it:
//!
//! ```
//! use glam::Vec3;
//! use matgraph::scene::Scene;
//! use matgraph::Attribute;
//!
//! let scene = Scene::from_json(r#"{"kind": "water", "lights": ["sunset"]}"#)?;
//! let mesh = scene.material_mesh();
//! // A graph's displacement, evaluated at the vertices (position, normal, uv), moves them:
//! let offsets: Vec<Vec3> = mesh.positions.iter().map(|p| Vec3::Y * 0.1 * p.x.sin()).collect();
//! let mesh = mesh.displaced(&offsets);
//! let g = scene.gbuffer(&mesh, 32, 24, 1); // the water's samples and their attributes
//! let textures = scene.scene_textures(32, 24); // refraction and reflection maps
//! let n = g.samples.len();
//! let positions = g.batch.column(Attribute::Position).unwrap();
//! for light in &scene.lights {
//!     let (_dir, _color) = scene.light_columns(light, positions, n); // set Light, LightColor
//!     // … evaluate the graph over `g.batch` and sum the lights …
//! }
//! let colours = vec![[0.0, 0.2, 0.4]; n];
//! let frame = g.resolve(&colours); // material where seen, background elsewhere
//! assert_eq!(frame.data.len(), 32 * 24);
//! assert_eq!(textures.reflection.data.len(), 32 * 24);
//! # Ok::<(), matgraph::scene::SceneError>(())
//! ```

mod bubble;
mod camera;
mod columns;
mod environment;
mod envmap;
mod error;
mod gbuffer;
pub mod ibl;
mod image;
mod json;
mod kind;
mod light;
mod lod;
mod memory;
mod mesh;
mod objects;
mod packed;
mod raster;
mod shade;
mod snell;
mod tangents;
mod textures;
mod validate;

pub use bubble::{BubbleBackdrop, BubbleMaps, MAP_SIZE as BUBBLE_MAP_SIZE, bubble_maps};
pub use camera::{Camera, CameraFrame, DEFAULT_NEAR};
pub use environment::{
    AmbientCube, EnvLookup, Environment, ImageEnvironment, Sky, SunPosition, equirect_uv,
    image_lookup,
};
pub use envmap::equirect_direction;
pub use error::SceneError;
pub use gbuffer::{GBuffer, GBufferFrame, cpu_raster_frames};
pub use image::SceneImage;
pub use kind::{
    Backdrop, BallSetup, BallShape, BoxObject, BubbleSetup, PoleObject, SceneKind, Seabed,
    SphereObject, WaterObject, WaterSetup,
};
pub use light::{DirectionalLight, LIGHT_PRESETS, Light, PointLight, sun_direction};
pub use lod::{Leaf, WaterLod};
pub use memory::{FIXED_MESH_BYTES, MESH_TRIANGLE_BYTES, MESH_VERTEX_BYTES, MeshCost};
pub use mesh::Mesh;
pub(crate) use packed::{PackedScene, SceneFeatures, ScenePass, Viewport};
pub use raster::{STANDARD_SAMPLE_COUNTS, sample_offsets, standard_sample_order};
pub use snell::{SnellRefraction, apparent_mesh, apparent_position};
pub use tangents::orthonormal_tangent;
pub use textures::SceneTextures;

use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

/// The names of the scene presets.
pub const SCENE_PRESETS: [&str; 4] = ["ball", "plane", "water", "bubble"];

/// A scene: what is in it, seen by which camera, under which lights and sky, at what time.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(from = "json::SceneDoc")]
pub struct Scene {
    /// The ball or the water scene, with its parameters.
    pub kind: SceneKind,
    /// The camera.
    pub camera: Camera,
    /// The lights, in order (the first directional light is the sky's sun by default).
    pub lights: Vec<Light>,
    /// What is seen where nothing is hit, and the ambient light.
    pub environment: Environment,
    /// Time in seconds (the `time` attribute).
    pub time: f32,
}

impl Default for Scene {
    /// The material ball.
    fn default() -> Self {
        Scene::for_kind(SceneKind::default())
    }
}

impl Scene {
    /// A scene of `kind` with that kind's default camera, lights and environment.
    pub fn for_kind(kind: SceneKind) -> Scene {
        Scene {
            camera: Scene::default_camera(&kind),
            lights: Scene::default_lights(&kind),
            environment: Scene::default_environment(&kind),
            kind,
            time: 0.0,
        }
    }

    /// The preset scene `"ball"`, `"plane"` (the ball's setup with a flat card,
    /// [`BallSetup::plane`]), `"water"` or `"bubble"` (every parameter at its default), or
    /// `None`.
    pub fn preset(name: &str) -> Option<Scene> {
        match name {
            "ball" => Some(Scene::for_kind(SceneKind::Ball(BallSetup::default()))),
            "plane" => Some(Scene::for_kind(SceneKind::Ball(BallSetup::plane()))),
            "water" => Some(Scene::for_kind(SceneKind::Water(WaterSetup::default()))),
            "bubble" => Some(Scene::for_kind(SceneKind::Bubble(BubbleSetup::default()))),
            _ => None,
        }
    }

    /// The default camera of a kind: ball, from `center + (0, 0.6, 5) · radius` (for the
    /// default ball, `(0, 1.6, 5)`) at the ball's centre with a 35° field of view; water,
    /// from `(0, 3, 18)` (3 m above the water) at the origin with 50°; bubble, from
    /// `(0, 0, 7)` at the origin with 40°.
    pub fn default_camera(kind: &SceneKind) -> Camera {
        match kind {
            SceneKind::Ball(b) => Camera {
                position: (Vec3::from(b.center) + Vec3::new(0.0, 0.6, 5.0) * b.radius).to_array(),
                target: b.center,
                fov_y_deg: 35.0,
                near: DEFAULT_NEAR,
            },
            SceneKind::Water(_) => Camera {
                position: [0.0, 3.0, 18.0],
                target: [0.0, 0.0, 0.0],
                fov_y_deg: 50.0,
                near: DEFAULT_NEAR,
            },
            SceneKind::Bubble(_) => Camera {
                position: [0.0, 0.0, 7.0],
                target: [0.0, 0.0, 0.0],
                fov_y_deg: 40.0,
                near: DEFAULT_NEAR,
            },
        }
    }

    /// The default lights of a kind: the `day` sun, plus for the ball a cool point fill
    /// light at `(3, 3.5, −2)` (colour (0.55, 0.6, 0.7), intensity 16), right, behind and
    /// high, so that its shadow falls on the floor in front of the ball on the left (centre
    /// `(−1.2, 0, 0.8)`), in view and apart from the sun's: every light's shadow is seen.
    pub fn default_lights(kind: &SceneKind) -> Vec<Light> {
        let day = Light::preset("day").expect("built-in preset");
        match kind {
            SceneKind::Ball(_) => vec![
                day,
                Light::Point(PointLight {
                    position: [3.0, 3.5, -2.0],
                    color: [0.55, 0.6, 0.7],
                    intensity: 16.0,
                }),
            ],
            SceneKind::Water(_) | SceneKind::Bubble(_) => vec![day],
        }
    }

    /// The default environment of a kind: the `day` sky; for water its ground colour is a
    /// far-sea blue (0.03, 0.09, 0.14), seen past the far edge of the water plane; for the
    /// bubble it is the sky seen from under water, bright overhead (Snell's window) and dark
    /// towards the horizon (zenith (1.3, 1.7, 1.8), horizon (0.06, 0.25, 0.33), ground
    /// (0.01, 0.05, 0.09)), what the bubble reflects.
    pub fn default_environment(kind: &SceneKind) -> Environment {
        let mut sky = Sky::default();
        match kind {
            SceneKind::Water(_) => sky.ground_color = [0.03, 0.09, 0.14],
            SceneKind::Bubble(_) => {
                sky.zenith_color = [1.3, 1.7, 1.8];
                sky.horizon_color = [0.06, 0.25, 0.33];
                sky.ground_color = [0.01, 0.05, 0.09];
            }
            SceneKind::Ball(_) => {}
        }
        Environment::Sky(sky)
    }

    /// What [`Scene::material_mesh`] is made from, as a key: the scene kind, and the
    /// camera's position under a water level of detail or the time in the bubble scene
    /// (the meshes that move with them); an orbit about a ball keeps its mesh.
    pub fn material_mesh_key(&self) -> String {
        let moving = match &self.kind {
            SceneKind::Water(w) if w.lod.is_some() => format!("{:?}", self.camera.position),
            SceneKind::Bubble(_) => format!("{:?}", self.time),
            SceneKind::Water(_) | SceneKind::Ball(_) => String::new(),
        };
        let kind = serde_json::to_string(&self.kind).unwrap_or_default();
        format!("{kind}/{moving}")
    }

    /// The texture space of the material surface, Blender's generated coordinates' box: its
    /// centre and half size per axis, from the surface as built (undisplaced): the ball's and
    /// the bubble's sphere `centre ± radius` (the card's `centre ± (radius, radius, 0)`), the
    /// water plane's `size` about the origin. A
    /// half size of 0 (the plane's height) is 1 and one below 10⁻⁵ is 10⁻⁵, as Blender's
    /// `BKE_mesh_texspace_calc`, so that the generated coordinate is 0.5 across a flat axis.
    pub fn texture_space(&self) -> (Vec3, Vec3) {
        let (center, half) = match &self.kind {
            SceneKind::Ball(b) => {
                let r = b.radius.abs();
                let half = match b.shape {
                    BallShape::Sphere => Vec3::splat(r),
                    BallShape::Plane => Vec3::new(r, r, 0.0),
                };
                (Vec3::from(b.center), half)
            }
            SceneKind::Bubble(b) => (b.center_at(self.time), Vec3::splat(b.radius.abs())),
            SceneKind::Water(w) => (
                Vec3::ZERO,
                Vec3::new(0.5 * w.size[0].abs(), 0.0, 0.5 * w.size[1].abs()),
            ),
        };
        let blender = |h: f32| {
            if h == 0.0 { 1.0 } else { h.max(1e-5) }
        };
        (
            center,
            Vec3::new(blender(half.x), blender(half.y), blender(half.z)),
        )
    }

    /// The generated texture coordinate of `p` in the box of [`Scene::texture_space`]:
    /// `0.5 + (p − centre) / (2 · half)` per axis, the box spanning [0, 1]³.
    pub fn generated(&self, p: Vec3) -> Vec3 {
        let (center, half) = self.texture_space();
        Vec3::splat(0.5) + (p - center) / (2.0 * half)
    }

    /// The mesh that carries the material: the ball's UV sphere (`segments`) or card, the water
    /// plane at `y = 0` as a grid of `size` and `grid` cells (uv 0..1, `u` along `+x`, `v`
    /// along `-z`), or with `lod` the quadtree grid for the camera ([`WaterLod::mesh`]), or
    /// the bubble's UV sphere at its centre at the scene's time ([`BubbleSetup::center_at`]).
    pub fn material_mesh(&self) -> Mesh {
        match &self.kind {
            SceneKind::Ball(b) => match b.shape {
                BallShape::Sphere => {
                    Mesh::uv_sphere(Vec3::from(b.center), b.radius, b.segments[0], b.segments[1])
                }
                BallShape::Plane => Mesh::parallelogram(
                    Vec3::from(b.center) - Vec3::new(b.radius, b.radius, 0.0),
                    Vec3::new(2.0 * b.radius, 0.0, 0.0),
                    Vec3::new(0.0, 2.0 * b.radius, 0.0),
                    b.segments,
                ),
            },
            SceneKind::Water(w) => match &w.lod {
                Some(lod) => lod.mesh(Vec2::from(w.size), Vec3::from(self.camera.position)),
                None => Mesh::grid(Vec3::ZERO, Vec2::from(w.size), w.grid),
            },
            SceneKind::Bubble(b) => Mesh::uv_sphere(
                b.center_at(self.time),
                b.radius,
                b.segments[0],
                b.segments[1],
            ),
        }
    }

    /// Unit direction towards the sky's sun ([`SunPosition`]; an image environment uses the
    /// first directional light, or `+y`).
    pub fn sun_direction(&self) -> Vec3 {
        let first = self.lights.iter().find_map(|l| match l {
            Light::Directional(d) => Some(Vec3::from(d.direction).normalize_or(Vec3::Y)),
            Light::Point(_) => None,
        });
        match &self.environment {
            Environment::Sky(s) => environment::resolve_sun(s.sun, first),
            Environment::Image(_) => first.unwrap_or(Vec3::Y),
        }
    }

    /// Radiance of the environment towards unit `dir` (see [`Environment::radiance`]).
    pub fn environment_radiance(&self, dir: Vec3, image: Option<&EnvLookup>) -> Vec3 {
        self.environment.radiance(dir, self.sun_direction(), image)
    }
}
