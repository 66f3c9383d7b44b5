//! The scene as flat data for the GPU rasteriser (`crate::gpu::raster`): the frame uniform
//! of its `scene.wgsl`, the prepared lights, the shadow casters, the built-in surfaces'
//! vertices and albedos. Each field mirrors a CPU structure of this module, so the GPU
//! shades with the same numbers.

use glam::{Vec3, Vec4};

use super::Scene;
use super::environment::{AmbientCube, EnvLookup, Environment};
use super::kind::SceneKind;
use super::objects::{ABOVE_WATER, Albedo, BELOW_WATER, Geometry, Shape};
use super::shade::Prepared;

/// Which picture of the scene a pass draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ScenePass {
    /// Everything but the material surface (the frame's background, `scene:background`).
    Background,
    /// `scene:refraction`: below the water plane (the water scene; else the background).
    Refraction,
    /// `scene:reflection`: above the water, mirrored about it (else the background).
    Reflection,
}

/// One built-in surface's triangles in [`PackedScene::indices`].
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ObjectRange {
    /// Its index range.
    pub indices: std::ops::Range<u32>,
    /// Whether it lies wholly below the water plane.
    pub underwater: bool,
}

/// The scene's data in the layouts of `src/gpu/raster/scene.wgsl` and `objects.wgsl`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct PackedScene {
    /// `MgrLight` per light (12 words each).
    pub lights: Vec<u32>,
    /// `MgrCaster` per caster (12 words each): the scene's own casters first, then the
    /// material's (the undisplaced ball).
    pub casters: Vec<u32>,
    /// The scene's own casters (those that shadow the material's light).
    pub own_casters: u32,
    /// All casters.
    pub all_casters: u32,
    /// Built-in vertex positions (xyz, 1).
    pub positions: Vec<[f32; 4]>,
    /// Built-in vertex normals (xyz, the object index as bits).
    pub normals: Vec<[f32; 4]>,
    /// Where the refraction pass draws the vertices, when the water's Snell refraction is
    /// on: each at its `snell::apparent_position` from the eye, as the CPU pass draws
    /// `snell::apparent_mesh` (shading keeps `positions`).
    pub refracted: Option<Vec<[f32; 4]>>,
    /// Triangles of the built-in surfaces, in drawing order.
    pub indices: Vec<u32>,
    /// Each surface's triangles.
    pub ranges: Vec<ObjectRange>,
    /// `MgrObject` per surface (20 words each).
    pub objects: Vec<u32>,
    /// The ambient cube of built-in shading.
    pub ambient: AmbientCube,
    /// `MgrBackdrop` (24 floats): the bubble scene's backdrop and time, zero elsewhere.
    pub backdrop: Vec<f32>,
    /// What the scene's shaders branch on ([`SceneFeatures::wgsl`]), and so which scene
    /// textures they read: the bubble backdrop's maps (slots 0–5, `BubbleMaps::named`
    /// order) and the environment image (the scene texture after the maps).
    pub features: SceneFeatures,
}

/// What of `scene.wgsl` and `objects.wgsl` a scene uses: the code for the rest is left out
/// of its shaders by the constants of [`SceneFeatures::wgsl`]. Lavapipe (llvmpipe) runs a
/// shader on eight fragments at once and executes both sides of every branch under a
/// mask, so a branch no fragment takes still costs its full price: the bubble backdrop's six
/// texture reads cost the ball scene's built-in surfaces 50–80 ms of a 1024² frame
/// (docs/benchmarks.md, "Scene features"). A real GPU skips such a branch, and either way the
/// result is the same.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub(crate) struct SceneFeatures {
    /// A built-in surface is the bubble backdrop (object kind 2), whose maps are scene
    /// textures.
    pub backdrop: bool,
    /// The environment is an image, given (frame `env.x` 2).
    pub env_image: bool,
    /// The water scene: its seabed depth and the clip planes of its scene passes.
    pub water: bool,
    /// A caster is a sphere (kind 0).
    pub spheres: bool,
    /// A caster is a box (kind 1).
    pub boxes: bool,
    /// A caster is a cylinder (kind 2).
    pub cylinders: bool,
}

impl SceneFeatures {
    /// The WGSL constants the scene shaders test (`MGR_HAS_*`), one per feature.
    pub(crate) fn wgsl(&self) -> String {
        [
            ("MGR_HAS_BACKDROP", self.backdrop),
            ("MGR_HAS_ENV_IMAGE", self.env_image),
            ("MGR_HAS_WATER", self.water),
            ("MGR_HAS_SPHERES", self.spheres),
            ("MGR_HAS_BOXES", self.boxes),
            ("MGR_HAS_CYLINDERS", self.cylinders),
        ]
        .iter()
        .map(|(name, on)| format!("const {name}: bool = {on};\n"))
        .collect()
    }
}

/// The part of a frame one pass draws: a tile of `size` pixels from pixel `origin`, and in
/// a jittered pass the sample's sub-pixel offset (its position in the pixel minus the
/// centre), so that the pass's pixel centres lie on that sample of every pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Viewport {
    /// The tile's first pixel in the frame.
    pub origin: [u32; 2],
    /// The tile's size, pixels.
    pub size: [u32; 2],
    /// Sub-pixel offset of the pass's sample from the pixel centre, in (−0.5, 0.5]².
    pub jitter: [f32; 2],
}

impl Viewport {
    /// The affine map `(sx, tx, sy, ty)` taking a `width × height` frame's clip x and y to
    /// this tile's, `x' = sx·x + tx·w`, `y' = sy·y + ty·w` (1, 0, 1, 0 for the whole frame).
    pub(crate) fn tile_clip(&self, width: u32, height: u32) -> [f32; 4] {
        let (fw, fh) = (width as f64, height as f64);
        let (tw, th) = (self.size[0] as f64, self.size[1] as f64);
        let ox = self.origin[0] as f64 + self.jitter[0] as f64;
        let oy = self.origin[1] as f64 + self.jitter[1] as f64;
        [
            (fw / tw) as f32,
            ((fw - tw - 2.0 * ox) / tw) as f32,
            (fh / th) as f32,
            ((th - fh + 2.0 * oy) / th) as f32,
        ]
    }

    /// The whole `width × height` frame at the pixel centres.
    pub(crate) fn whole(width: u32, height: u32) -> Viewport {
        Viewport {
            origin: [0, 0],
            size: [width, height],
            jitter: [0.0, 0.0],
        }
    }
}

fn bits(v: &[f32]) -> impl Iterator<Item = u32> + '_ {
    v.iter().map(|x| x.to_bits())
}

impl Scene {
    /// The scene packed for the GPU rasteriser; `image` looks up the environment image of
    /// an image environment (for the ambient cube; the GPU samples the image itself).
    pub(crate) fn packed(&self, image: Option<&EnvLookup>) -> PackedScene {
        let geometry: Geometry = self.geometry();
        let sun = self.sun_direction();
        let env = &self.environment;
        let ambient = AmbientCube::from_radiance(|d| env.ambient_radiance(d, sun, image));
        let mut lights = Vec::new();
        for light in &self.lights {
            let (kind, a, b) = match Prepared::new(light) {
                Prepared::Directional { l, radiance } => (0u32, l, radiance),
                Prepared::Point { position, radiance } => (1, position, radiance),
            };
            lights.extend([kind, 0, 0, 0]);
            lights.extend(bits(&[a.x, a.y, a.z, 0.0, b.x, b.y, b.z, 0.0]));
        }
        let mut casters = Vec::new();
        let own = geometry.casters.len() as u32;
        let shapes = || geometry.casters.iter().chain(&geometry.material_caster);
        for s in shapes() {
            let (kind, a, b) = match *s {
                Shape::Sphere { center, radius } => (0u32, center.extend(radius), Vec4::ZERO),
                Shape::Aabb { min, max } => (1, min.extend(0.0), max.extend(0.0)),
                Shape::Cylinder {
                    x,
                    z,
                    radius,
                    y0,
                    y1,
                } => (2, Vec4::new(x, z, radius, y0), Vec4::new(y1, 0.0, 0.0, 0.0)),
            };
            casters.extend([kind, 0, 0, 0]);
            casters.extend(bits(&a.to_array()));
            casters.extend(bits(&b.to_array()));
        }
        let mut packed = PackedScene {
            lights,
            own_casters: own,
            all_casters: casters.len() as u32 / 12,
            casters,
            positions: Vec::new(),
            normals: Vec::new(),
            refracted: None,
            indices: Vec::new(),
            ranges: Vec::new(),
            objects: Vec::new(),
            ambient,
            backdrop: vec![0.0; 24],
            features: SceneFeatures {
                backdrop: geometry
                    .objects
                    .iter()
                    .any(|o| matches!(o.albedo, Albedo::Unlit(_))),
                env_image: matches!(env, Environment::Image(_)) && image.is_some(),
                water: matches!(self.kind, SceneKind::Water(_)),
                spheres: shapes().any(|s| matches!(s, Shape::Sphere { .. })),
                boxes: shapes().any(|s| matches!(s, Shape::Aabb { .. })),
                cylinders: shapes().any(|s| matches!(s, Shape::Cylinder { .. })),
            },
        };
        for (k, obj) in geometry.objects.iter().enumerate() {
            let base = packed.positions.len() as u32;
            let first = packed.indices.len() as u32;
            let m = &obj.mesh;
            packed
                .positions
                .extend(m.positions.iter().map(|p| p.extend(1.0).to_array()));
            packed.normals.extend(
                m.normals
                    .iter()
                    .map(|n| [n.x, n.y, n.z, f32::from_bits(k as u32)]),
            );
            packed
                .indices
                .extend(m.indices.iter().flat_map(|t| t.map(|i| i + base)));
            packed.ranges.push(ObjectRange {
                indices: first..packed.indices.len() as u32,
                underwater: obj.underwater,
            });
            let skip = obj.caster.map_or(u32::MAX, |c| c as u32);
            let words: [f32; 16] = match &obj.albedo {
                // The bubble's unlit backdrop: kind 2, its parameters in `backdrop`.
                Albedo::Unlit(shader) => {
                    packed.objects.extend([2, skip, first / 3, 0]);
                    packed.backdrop = shader.words().to_vec();
                    [0.0; 16]
                }
                &Albedo::Constant(c) => {
                    packed.objects.extend([0, skip, first / 3, 0]);
                    let mut w = [0.0; 16];
                    w[8..11].copy_from_slice(&c.to_array());
                    w
                }
                &Albedo::Checker {
                    u,
                    v,
                    v0,
                    size,
                    colors,
                } => {
                    packed.objects.extend([1, skip, first / 3, 0]);
                    let mut w = [0.0; 16];
                    w[..4].copy_from_slice(&u.extend(v0).to_array());
                    w[4..8].copy_from_slice(&v.extend(size).to_array());
                    w[8..11].copy_from_slice(&colors[0].to_array());
                    w[12..15].copy_from_slice(&colors[1].to_array());
                    w
                }
            };
            packed.objects.extend(bits(&words));
        }
        if let SceneKind::Water(w) = &self.kind
            && let Some(snell) = &w.refraction
        {
            let eye = Vec3::from(self.camera.position);
            let mut drawn = Vec::with_capacity(packed.positions.len());
            for obj in &geometry.objects {
                let m = super::snell::apparent_mesh(&obj.mesh, eye, snell.ior_air, snell.ior_water);
                drawn.extend(m.positions.iter().map(|p| p.extend(1.0).to_array()));
            }
            packed.refracted = Some(drawn);
        }
        packed
    }

    /// The `MgrFrame` uniform (480 bytes) of a `width × height` pass: the camera, the sky,
    /// the ambient cube, the counts, for `pass` the mirror and the clip plane, the tile and
    /// jitter of `view`, the environment, the scene texture slots and the material surface's
    /// texture space.
    pub(crate) fn frame_uniform(
        &self,
        packed: &PackedScene,
        width: u32,
        height: u32,
        pass: ScenePass,
        view: &Viewport,
    ) -> Vec<u8> {
        let cam = self.camera.frame(width, height);
        let water = matches!(self.kind, SceneKind::Water(_));
        let (mirror, clip) = match (pass, water) {
            (ScenePass::Refraction, true) => (false, Some(BELOW_WATER)),
            (ScenePass::Reflection, true) => (true, Some(ABOVE_WATER)),
            _ => (false, None),
        };
        let eye = if mirror {
            cam.origin * Vec3::new(1.0, -1.0, 1.0)
        } else {
            cam.origin
        };
        let sky = match &self.environment {
            Environment::Sky(s) => *s,
            Environment::Image(_) => super::Sky::default(),
        };
        let sun = self.sun_direction();
        let mut w: Vec<f32> = Vec::with_capacity(96);
        let mut put = |v: Vec3, s: f32| w.extend([v.x, v.y, v.z, s]);
        put(cam.origin, cam.near);
        put(cam.right, cam.tan_half_y);
        put(cam.up, cam.aspect);
        put(cam.forward, width as f32);
        put(eye, height as f32);
        put(sun, sky.sun_radius_deg.to_radians().cos());
        put(Vec3::from(sky.zenith_color), sky.sun_intensity);
        put(Vec3::from(sky.horizon_color), sky.halo);
        put(Vec3::from(sky.ground_color), if mirror { 1.0 } else { 0.0 });
        put(Vec3::from(sky.sun_color), if water { 1.0 } else { 0.0 });
        let c = clip.unwrap_or(Vec4::ZERO);
        put(c.truncate(), c.w);
        for f in packed.ambient.faces {
            put(f, 0.0);
        }
        let counts = [
            packed.lights.len() as u32 / 12,
            packed.all_casters,
            packed.own_casters,
            clip.is_some() as u32,
        ];
        w.extend(counts.map(f32::from_bits));
        match &self.kind {
            SceneKind::Water(wa) => {
                let s = &wa.seabed;
                w.extend([
                    s.depth_min,
                    s.depth_max,
                    s.slope.clamp(0.0, 1.0),
                    wa.size[1].max(f32::MIN_POSITIVE),
                ]);
                w.extend(super::kind::seed_phases(s.seed));
                for b in super::kind::BUMPS {
                    w.extend([b.0, b.1, b.2, b.3]);
                }
            }
            SceneKind::Ball(_) | SceneKind::Bubble(_) => w.extend([0.0; 24]),
        }
        // The tile: frame clip x, y to the tile's (scale 1, offset 0 for the whole frame).
        w.extend(view.tile_clip(width, height));
        let ox = view.origin[0] as f64 + view.jitter[0] as f64;
        let oy = view.origin[1] as f64 + view.jitter[1] as f64;
        w.extend([
            ox as f32,
            oy as f32,
            view.origin[0] as f32,
            view.origin[1] as f32,
        ]);
        let (mode, turn, intensity) = match &self.environment {
            Environment::Sky(_) => (0.0, 0.0, 1.0),
            Environment::Image(img) => (
                if packed.features.env_image { 2.0 } else { 1.0 },
                -img.rotation_deg.to_radians(),
                img.intensity,
            ),
        };
        let (sin, cos) = turn.sin_cos();
        w.extend([mode, cos, sin, intensity]);
        let slots = [if packed.features.backdrop { 6u32 } else { 0 }, 0, 0, 0];
        w.extend(slots.map(f32::from_bits));
        let (center, half) = self.texture_space();
        w.extend([
            center.x, center.y, center.z, 0.0, half.x, half.y, half.z, 0.0,
        ]);
        debug_assert_eq!(w.len(), 120);
        bytemuck::cast_slice(&w).to_vec()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn features(preset: &str) -> SceneFeatures {
        Scene::preset(preset)
            .expect("a preset")
            .packed(None)
            .features
    }

    /// The ball casts with its sphere alone; the water has poles, boxes and a buoy over
    /// its seabed; the bubble's backdrop is its maps. No preset has an image environment.
    #[test]
    fn each_preset_turns_on_what_it_holds() {
        let none = SceneFeatures::default();
        assert_eq!(
            features("ball"),
            SceneFeatures {
                spheres: true,
                ..none
            }
        );
        assert_eq!(
            features("water"),
            SceneFeatures {
                water: true,
                spheres: true,
                boxes: true,
                cylinders: true,
                ..none
            }
        );
        let bubble = features("bubble");
        assert!(bubble.backdrop && !bubble.water && !bubble.env_image);
    }

    #[test]
    fn the_constants_name_every_feature_once() {
        let wgsl = SceneFeatures {
            boxes: true,
            ..Default::default()
        }
        .wgsl();
        assert_eq!(wgsl.lines().count(), 6);
        assert!(wgsl.contains("const MGR_HAS_BOXES: bool = true;"));
        assert!(wgsl.contains("const MGR_HAS_BACKDROP: bool = false;"));
        for name in [
            "BACKDROP",
            "ENV_IMAGE",
            "WATER",
            "SPHERES",
            "BOXES",
            "CYLINDERS",
        ] {
            assert_eq!(wgsl.matches(&format!("MGR_HAS_{name}:")).count(), 1);
        }
    }
}
