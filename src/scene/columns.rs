//! Per-sample columns of the material surface besides the G-buffer's own: each light's
//! direction and colour, and the depth below the water.

use glam::Vec3;
use rayon::prelude::*;

use super::Scene;
use super::kind::SceneKind;
use super::light::Light;
use super::objects::Shape;
use super::shade::{Prepared, lit};

/// Samples per parallel block.
const BLOCK: usize = 4096;

impl Scene {
    /// The `depth` attribute at world point `p`: for water, the vertical distance from `p`
    /// down to the seabed, `max(0, p.y + seabed_depth(p.x, p.z))`; 0 for the ball.
    pub fn water_depth(&self, p: Vec3) -> f32 {
        match &self.kind {
            SceneKind::Water(w) => (p.y + w.seabed_depth(p.x, p.z)).max(0.0),
            SceneKind::Ball(_) | SceneKind::Bubble(_) => 0.0,
        }
    }

    /// The `light` and `light_color` columns (planar, `3 × count` each) of `light` at the
    /// points `positions_planar` (planar, `3 × count`): the unit direction towards the light
    /// and its radiance scale there (directional: `color · intensity`; point: `color ·
    /// intensity / d²`), zeroed where a non-material object of the scene (the water scene's
    /// boxes, spheres and poles) stands between the point and the light. The material
    /// surface does not shadow itself here: its own `N·L` does that.
    ///
    /// # Panics
    /// If `positions_planar.len() != 3 * count`.
    pub fn light_columns(
        &self,
        light: &Light,
        positions_planar: &[f32],
        count: usize,
    ) -> (Vec<f32>, Vec<f32>) {
        assert_eq!(
            positions_planar.len(),
            3 * count,
            "Scene::light_columns: {} floats for {count} positions",
            positions_planar.len()
        );
        let casters = self.geometry().casters;
        let light = Prepared::new(light);
        let mut dir = vec![0.0; 3 * count];
        let mut color = vec![0.0; 3 * count];
        if count == 0 {
            return (dir, color);
        }
        let (px, rest) = positions_planar.split_at(count);
        let (py, pz) = rest.split_at(count);
        let (dx, rest) = dir.split_at_mut(count);
        let (dy, dz) = rest.split_at_mut(count);
        let (cx, rest) = color.split_at_mut(count);
        let (cy, cz) = rest.split_at_mut(count);
        dx.par_chunks_mut(BLOCK)
            .zip(dy.par_chunks_mut(BLOCK))
            .zip(dz.par_chunks_mut(BLOCK))
            .zip(cx.par_chunks_mut(BLOCK))
            .zip(cy.par_chunks_mut(BLOCK))
            .zip(cz.par_chunks_mut(BLOCK))
            .enumerate()
            .for_each(|(b, (((((dx, dy), dz), cx), cy), cz))| {
                for k in 0..dx.len() {
                    let i = b * BLOCK + k;
                    let p = Vec3::new(px[i], py[i], pz[i]);
                    let (l, c) = light_at(&light, &casters, p);
                    (dx[k], dy[k], dz[k]) = (l.x, l.y, l.z);
                    (cx[k], cy[k], cz[k]) = (c.x, c.y, c.z);
                }
            });
        (dir, color)
    }
}

/// Direction and shadowed radiance scale of `light` at a material point `p` (the same
/// values as [`Scene::light_columns`]).
#[inline]
pub(crate) fn light_at(light: &Prepared, casters: &[Shape], p: Vec3) -> (Vec3, Vec3) {
    let (l, c, dist) = light.incident(p);
    if casters.is_empty() || lit(casters, None, p, Vec3::ZERO, l, dist) {
        (l, c)
    } else {
        (l, Vec3::ZERO)
    }
}
