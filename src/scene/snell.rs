//! The refraction map seen through the flat water plane by Snell's law (seed 004 §2.3.1,
//! eq. 4: `n₁ sin θ₁ = n₂ sin θ₂`, air 1.00, water 1.33), rather than straight along the
//! camera ray.
//!
//! The rasteriser draws straight rays, so the underwater geometry is drawn where it
//! *appears*: each vertex `q` below `y = 0` is moved onto the camera ray that, refracted at
//! the plane, reaches it. That ray meets the plane at the point `p` on the segment between
//! the feet of the eye `e` and of `q` where Snell's law holds,
//!
//! ```text
//! f(x) = n_air · x / √(x² + h²) − n_water · (D − x) / √((D − x)² + d²) = 0,   x ∈ [0, D]
//! ```
//!
//! (`h` the eye's height, `d` the point's depth, `D` their horizontal distance, `x` the
//! distance from the eye's foot to `p`; `f` increases from `f(0) < 0` to `f(D) > 0`, solved
//! by bisection in f64), and the vertex is placed on the ray `e → p` at the length of the
//! refracted path `|p − e| + |q − p|`, which keeps the depth order of what lies under the
//! water. Shading keeps the true positions (the fragments' barycentrics are applied to the
//! original triangles). Exact at the vertices; triangles are drawn straight between them.

use glam::{DVec3, Vec3};
use serde::{Deserialize, Serialize};

use super::mesh::Mesh;

/// The refraction map drawn through the flat water by Snell's law (the water setup's
/// `"refraction": {}`); without it the map looks straight along the camera rays.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[serde(expecting = "a refraction object")]
pub struct SnellRefraction {
    /// Index of refraction above the water (> 0; seed 004: air 1.00).
    pub ior_air: f32,
    /// Index of refraction of the water (> 0; seed 004: 1.33).
    pub ior_water: f32,
}

impl Default for SnellRefraction {
    fn default() -> Self {
        SnellRefraction {
            ior_air: 1.0,
            ior_water: 1.33,
        }
    }
}

/// Where underwater point `q` appears from eye `e` above the plane `y = 0` with indices
/// `n_air` above and `n_water` below (module doc). Points at or above the plane, or an eye
/// at or below it, are returned unchanged.
pub fn apparent_position(e: Vec3, q: Vec3, n_air: f32, n_water: f32) -> Vec3 {
    if q.y >= 0.0 || e.y <= 0.0 {
        return q;
    }
    let (e, q) = (e.as_dvec3(), q.as_dvec3());
    let (n1, n2) = (n_air as f64, n_water as f64);
    let (h, d) = (e.y, -q.y);
    let along = DVec3::new(q.x - e.x, 0.0, q.z - e.z);
    let dist = along.length();
    let u = if dist > 0.0 {
        along / dist
    } else {
        DVec3::ZERO
    };
    let f = |x: f64| {
        n1 * x / (x * x + h * h).sqrt() - n2 * (dist - x) / ((dist - x).powi(2) + d * d).sqrt()
    };
    let (mut lo, mut hi) = (0.0, dist);
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let x = 0.5 * (lo + hi);
    let p = DVec3::new(e.x, 0.0, e.z) + u * x;
    let to_p = p - e;
    let len = to_p.length() + (q - p).length();
    (e + to_p / to_p.length() * len).as_vec3()
}

/// A copy of `mesh` with every vertex at its [`apparent_position`] from `eye`.
pub fn apparent_mesh(mesh: &Mesh, eye: Vec3, n_air: f32, n_water: f32) -> Mesh {
    let mut m = mesh.clone();
    for p in &mut m.positions {
        *p = apparent_position(eye, *p, n_air, n_water);
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_apparent_ray_obeys_snell_and_equal_indices_change_nothing() {
        let e = Vec3::new(0.0, 3.0, 18.0);
        for q in [
            Vec3::new(1.0, -2.0, 4.0),
            Vec3::new(-7.5, -0.3, 10.0),
            Vec3::new(0.0, -5.0, 18.0),
        ] {
            let a = apparent_position(e, q, 1.0, 1.33);
            // The plane crossing of the apparent ray, and the angles either side.
            let t = e.y / (e.y - a.y);
            let p = e + (a - e) * t;
            let down = (p - e).normalize();
            let to_q = (q - p).normalize();
            let sin1 = (down.x * down.x + down.z * down.z).sqrt();
            let sin2 = (to_q.x * to_q.x + to_q.z * to_q.z).sqrt();
            assert!(
                (sin1 - 1.33 * sin2).abs() < 1e-5,
                "{q}: {sin1} vs 1.33 · {sin2}"
            );
            let same = apparent_position(e, q, 1.0, 1.0);
            assert!((same - q).length() < 1e-4, "{same} vs {q}");
        }
        assert_eq!(
            apparent_position(e, Vec3::new(1.0, 0.5, 1.0), 1.0, 1.33),
            Vec3::new(1.0, 0.5, 1.0)
        );
    }
}
