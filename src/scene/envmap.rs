//! The `scene:environment` map: the surroundings of the material object as an
//! equirectangular image, seen from the object's centre, so that what a material reflects
//! is what the camera sees around it.
//!
//! For the material ball each texel's ray (texel centre → direction by the inverse of
//! [`super::equirect_uv`]) starts at the ball's centre and is cast against the built-in
//! surfaces (the floor and back wall, their triangles in drawing order, Möller & Trumbore,
//! "Fast, minimum storage ray/triangle intersection", JGT 2(1), 1997); the nearest hit is
//! shaded as the camera sees it ([`Shading::surface`]: Lambert under the lights with the
//! ball's shadow, plus ambient, lit as seen from the centre), the environment (sky or image)
//! where nothing is hit. The ball itself is left out (it is the reflector). Other scenes
//! have the environment alone. The GPU pass (`src/gpu/raster/envmap.wgsl`) is a line-by-line
//! port.

use glam::Vec3;
use rayon::prelude::*;

use super::Scene;
use super::environment::EnvLookup;
use super::kind::SceneKind;
use super::objects::{Albedo, Object};
use super::raster::position_normal;
use super::shade::Shading;

/// Nearest ray parameter a hit may have, metres (hits closer than this are ignored).
pub(crate) const MIN_HIT: f32 = 1e-4;

/// Unit direction of texel `(x, y)`'s centre in a `w × h` equirectangular map: the inverse
/// of [`super::equirect_uv`], `φ = (u − ½)·2π`, `θ = v·π`, `d = (sin θ sin φ, cos θ, −sin θ cos φ)`.
#[inline]
pub fn equirect_direction(x: u32, y: u32, w: u32, h: u32) -> Vec3 {
    let phi = ((x as f32 + 0.5) / w as f32 - 0.5) * std::f32::consts::TAU;
    let theta = (y as f32 + 0.5) / h as f32 * std::f32::consts::PI;
    Vec3::new(
        theta.sin() * phi.sin(),
        theta.cos(),
        -theta.sin() * phi.cos(),
    )
}

/// The ray parameter `t > MIN_HIT` and barycentrics `(b1, b2)` where the ray `o + t d` meets
/// triangle `(p0, p1, p2)` (Möller & Trumbore 1997), if it does.
#[inline]
pub(crate) fn ray_triangle(
    o: Vec3,
    d: Vec3,
    p0: Vec3,
    p1: Vec3,
    p2: Vec3,
) -> Option<(f32, f32, f32)> {
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let pv = d.cross(e2);
    let det = e1.dot(pv);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let tv = o - p0;
    let u = tv.dot(pv) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let qv = tv.cross(e1);
    let v = d.dot(qv) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(qv) * inv;
    (t > MIN_HIT).then_some((t, u, v))
}

impl Scene {
    /// What the environment map ([`Scene::environment_map`]) and the tables made from it
    /// depend on, as a memo key: the scene as JSON without its camera and its mesh detail
    /// (the ball's and the bubble's segments, the water's and the seabed's grids and level
    /// of detail). The map is seen from the ball's centre and shows the backdrop's
    /// parallelograms, the lights and the environment, so an orbit or a draft's coarser
    /// mesh keeps the map; `tests::environment_map_ignores_camera_and_mesh_detail` checks
    /// it.
    pub fn environment_key(&self) -> String {
        let mut s = self.clone();
        s.camera = Scene::default_camera(&s.kind);
        match &mut s.kind {
            SceneKind::Ball(b) => b.segments = [0, 0],
            SceneKind::Water(w) => {
                w.grid = [0, 0];
                w.seabed.grid = [0, 0];
                w.lod = None;
            }
            SceneKind::Bubble(b) => b.segments = [0, 0],
        }
        serde_json::to_string(&s).unwrap_or_default()
    }

    /// Where the environment map is seen from: the ball's centre in a ball scene; `None`
    /// where the map is the environment alone (water, bubble).
    pub fn environment_origin(&self) -> Option<Vec3> {
        match &self.kind {
            SceneKind::Ball(b) => Some(Vec3::from(b.center)),
            _ => None,
        }
    }

    /// The `w × h` equirectangular environment map, RGBA (alpha 1), row-major from the top
    /// row (the zenith): see the module docs. `image` is the caller's lookup of an image
    /// environment.
    pub fn environment_map(&self, w: u32, h: u32, image: Option<&EnvLookup>) -> Vec<[f32; 4]> {
        let geometry = self.geometry();
        let shading = Shading::new(self, &geometry, image);
        let origin = self.environment_origin();
        let objects: Vec<&Object> = match origin {
            Some(_) => geometry
                .objects
                .iter()
                .filter(|o| !matches!(o.albedo, Albedo::Unlit(_)))
                .collect(),
            None => Vec::new(),
        };
        let sun = self.sun_direction();
        let mut out = vec![[0.0f32; 4]; (w * h) as usize];
        out.par_chunks_mut(w.max(1) as usize)
            .enumerate()
            .for_each(|(y, row)| {
                for (x, texel) in row.iter_mut().enumerate() {
                    let d = equirect_direction(x as u32, y as u32, w, h);
                    let c = match origin.and_then(|o| nearest_hit(&objects, o, d)) {
                        Some((k, tri, b)) => {
                            let obj = objects[k];
                            let (p, n) = position_normal(&obj.mesh, tri, b);
                            shading.surface(obj, p, n, origin.unwrap_or_default())
                        }
                        None => self.environment.radiance(d, sun, image),
                    };
                    *texel = [c.x, c.y, c.z, 1.0];
                }
            });
        out
    }
}

/// The nearest surface the ray `o + t d` meets: (object, triangle, barycentrics); the first
/// in drawing order wins a tie.
fn nearest_hit(objects: &[&Object], o: Vec3, d: Vec3) -> Option<(usize, u32, [f32; 2])> {
    let mut best: Option<(usize, u32, [f32; 2])> = None;
    let mut t_best = f32::INFINITY;
    for (k, obj) in objects.iter().enumerate() {
        let m = &obj.mesh;
        for (tri, idx) in m.indices.iter().enumerate() {
            let [p0, p1, p2] = idx.map(|i| m.positions[i as usize]);
            if let Some((t, u, v)) = ray_triangle(o, d, p0, p1, p2)
                && t < t_best
            {
                t_best = t;
                best = Some((k, tri as u32, [u, v]));
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::WaterLod;

    /// The environment key leaves out what the map does not see: for each preset scene,
    /// another camera and another mesh detail give the same key and the same map texel for
    /// texel, and a moved light gives another key and another map (in the ball's room,
    /// where the floor and wall are lit by it).
    #[test]
    fn environment_map_ignores_camera_and_mesh_detail() {
        for name in ["ball", "water", "bubble"] {
            let base = Scene::preset(name).unwrap();
            let mut other = base.clone();
            other.camera.position = [2.5, 4.0, -7.0];
            other.camera.fov_y_deg = 20.0;
            match &mut other.kind {
                SceneKind::Ball(b) => b.segments = [24, 12],
                SceneKind::Water(w) => {
                    w.grid = [16, 16];
                    w.seabed.grid = [20, 12];
                    w.lod = Some(WaterLod::default());
                }
                SceneKind::Bubble(b) => b.segments = [16, 16],
            }
            assert_eq!(base.environment_key(), other.environment_key(), "{name}");
            assert_eq!(
                base.environment_map(32, 16, None),
                other.environment_map(32, 16, None),
                "{name}: the map depends on what its key leaves out"
            );
        }
        let base = Scene::preset("ball").unwrap();
        let mut lit = base.clone();
        match &mut lit.lights[0] {
            crate::scene::Light::Directional(d) => d.direction = [0.6, 0.5, -0.6],
            crate::scene::Light::Point(p) => p.position[0] += 1.0,
        }
        assert_ne!(base.environment_key(), lit.environment_key());
        assert_ne!(
            base.environment_map(32, 16, None),
            lit.environment_map(32, 16, None)
        );
    }
}
