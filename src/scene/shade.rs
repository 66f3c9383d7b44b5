//! Built-in shading of the non-material surfaces (backdrop, seabed, objects) and of the
//! environment where nothing is hit.
//!
//! A built-in surface is two-sided Lambert (Lambert, "Photometria", 1760; the normal turned
//! towards the eye) under the
//! scene's lights with hard shadows from the scene's analytic shapes, plus the
//! environment's ambient light through an ambient cube:
//! `L_o = albedo · (Σ_l vis_l · max(0, N·L_l) · light_color_l + ambient(N))`, with
//! `light_color` as in [`super::light`] (no `1/π`). Shadows are cast by the undisplaced
//! material ball, the water scene's objects (their analytic box, sphere and cylinder), not
//! by the water, the seabed or the backdrop.

use glam::Vec3;
use rayon::prelude::*;

use super::Scene;
use super::camera::CameraFrame;
use super::environment::{AmbientCube, EnvLookup, Environment};
use super::light::Light;
use super::objects::{Geometry, Object, Shape};
use super::raster::{Fragment, position_normal};

/// Offset of shadow-ray origins along the normal, metres.
const SHADOW_BIAS: f32 = 1e-3;

/// Whether the ray from `p` (moved off the surface along `n`) towards unit `l` reaches the
/// light at distance `dist` without meeting a caster other than `casters[skip]`.
#[inline]
pub(crate) fn lit(
    casters: &[Shape],
    skip: Option<usize>,
    p: Vec3,
    n: Vec3,
    l: Vec3,
    dist: f32,
) -> bool {
    let o = p + n * SHADOW_BIAS;
    !casters
        .iter()
        .enumerate()
        .any(|(i, s)| Some(i) != skip && s.occludes(o, l, dist))
}

/// A light with its direction normalised and its colour scaled, ready for shading.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Prepared {
    Directional { l: Vec3, radiance: Vec3 },
    Point { position: Vec3, radiance: Vec3 },
}

impl Prepared {
    /// The light ready for shading.
    pub(crate) fn new(light: &Light) -> Prepared {
        match light {
            Light::Directional(_) => {
                let (l, radiance, _) = light.incident(Vec3::ZERO);
                Prepared::Directional { l, radiance }
            }
            Light::Point(p) => Prepared::Point {
                position: Vec3::from(p.position),
                radiance: light.radiance_scale(),
            },
        }
    }

    /// As [`Light::incident`].
    #[inline]
    pub(crate) fn incident(&self, p: Vec3) -> (Vec3, Vec3, f32) {
        match *self {
            Prepared::Directional { l, radiance } => (l, radiance, f32::INFINITY),
            Prepared::Point { position, radiance } => {
                let to = position - p;
                let d2 = to.length_squared();
                let dist = d2.sqrt();
                let dir = if dist > 0.0 { to / dist } else { Vec3::Y };
                let d2 = d2.max(super::light::MIN_DISTANCE * super::light::MIN_DISTANCE);
                (dir, radiance / d2, dist)
            }
        }
    }
}

/// Everything built-in shading needs.
pub(crate) struct Shading<'a> {
    lights: Vec<Prepared>,
    casters: Vec<Shape>,
    ambient: AmbientCube,
    environment: &'a Environment,
    sun: Vec3,
    image: Option<&'a EnvLookup>,
}

impl<'a> Shading<'a> {
    /// Shading for `scene`'s built-in surfaces.
    pub(crate) fn new(scene: &'a Scene, geometry: &Geometry, image: Option<&'a EnvLookup>) -> Self {
        let sun = scene.sun_direction();
        let env = &scene.environment;
        let ambient = AmbientCube::from_radiance(|d| env.ambient_radiance(d, sun, image));
        let mut casters = geometry.casters.clone();
        casters.extend(geometry.material_caster);
        Shading {
            lights: scene.lights.iter().map(Prepared::new).collect(),
            casters,
            ambient,
            environment: env,
            sun,
            image,
        }
    }

    /// Radiance leaving a point `p` with normal `n` of built-in surface `obj` towards `eye`.
    #[inline]
    pub(crate) fn surface(&self, obj: &Object, p: Vec3, n: Vec3, eye: Vec3) -> Vec3 {
        if let super::objects::Albedo::Unlit(backdrop) = &obj.albedo {
            return backdrop.radiance(p);
        }
        let albedo = obj.albedo.at(p);
        let n = if n.dot(eye - p) < 0.0 { -n } else { n };
        let mut e = self.ambient.eval(n);
        for light in &self.lights {
            let (l, radiance, dist) = light.incident(p);
            let cos = n.dot(l);
            if cos > 0.0 && lit(&self.casters, obj.caster, p, n, l, dist) {
                e += radiance * cos;
            }
        }
        albedo * e
    }

    /// Radiance of the environment towards unit `dir`.
    #[inline]
    pub(crate) fn sky(&self, dir: Vec3) -> Vec3 {
        self.environment.radiance(dir, self.sun, self.image)
    }
}

/// Radiance of every sample of a rasterised frame: built-in shading where a surface was hit
/// (`objects[item]`), the environment elsewhere. With `mirror` the frame is a planar
/// reflection about `y = 0`: surfaces are lit as seen from the mirrored eye and the
/// environment is looked up in the mirrored direction. `frags` may hold a band of rows
/// starting at image row `first_row` ([`super::raster::rasterize_rows`]).
pub(crate) fn shade_frame(
    frags: &[Fragment],
    objects: &[&Object],
    shading: &Shading,
    cam: &CameraFrame,
    offsets: &[[f32; 2]],
    mirror: bool,
    first_row: usize,
) -> Vec<[f32; 3]> {
    let (spp, w) = (offsets.len(), cam.width as usize);
    let eye = if mirror {
        cam.origin * Vec3::new(1.0, -1.0, 1.0)
    } else {
        cam.origin
    };
    let mut out = vec![[0.0f32; 3]; frags.len()];
    if frags.is_empty() {
        return out;
    }
    out.par_chunks_mut(w * spp)
        .zip(frags.par_chunks(w * spp))
        .enumerate()
        .for_each(|(y, (out, row))| {
            let y = first_row + y;
            let pixels = out.chunks_exact_mut(spp).zip(row.chunks_exact(spp));
            for (x, (out, frags)) in pixels.enumerate() {
                for ((c, f), o) in out.iter_mut().zip(frags).zip(offsets) {
                    let radiance = if f.is_hit() {
                        let obj = objects[f.item as usize];
                        let (p, n) = position_normal(&obj.mesh, f.tri, f.b);
                        shading.surface(obj, p, n, eye)
                    } else {
                        let mut d = cam.ray_direction(x as f32 + o[0], y as f32 + o[1]);
                        if mirror {
                            d.y = -d.y;
                        }
                        shading.sky(d)
                    };
                    *c = radiance.to_array();
                }
            }
        });
    out
}
