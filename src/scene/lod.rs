//! The water grid with quadtree level of detail (seed 004 §3.1, Fig. 9): the water plane is
//! cut into blocks of `block × block` cells (the paper's `(2ⁿ + 1)²` vertices per block), and
//! a quadtree picks each block's size, finer near the camera.
//!
//! A quadtree node is split while the camera is nearer than `split_distance` times the
//! node's side (distance in 3D from the camera to the node's nearest point on the plane),
//! down to `levels` splits; the tree is then balanced so that neighbouring leaves differ by
//! at most one level. Cracks (T-junctions, which a vertex displacement would open) are
//! closed on the coarse side: a coarse cell whose edge carries a vertex of the finer
//! neighbour (its edge midpoint) gets a centre vertex and is triangulated as a fan through
//! its corners and those midpoints, so every edge shared by two leaves has the same
//! vertices on both sides. With `levels` splits and `block` cells, the finest cells are
//! those of the uniform grid of `2^levels · block` cells per side.

use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

use super::mesh::Mesh;

/// The quadtree level of detail of the water grid (see the module doc). In JSON, the
/// water setup's `"lod": {"levels": 5, "block": 8, "split_distance": 1.5}`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[serde(expecting = "a water level-of-detail object")]
pub struct WaterLod {
    /// Largest number of splits of the whole plane (0–10): the finest blocks are
    /// `size / 2^levels`.
    pub levels: u32,
    /// Cells along each side of a block (1–64).
    pub block: u32,
    /// A node is split while the camera is nearer than this times its side (> 0).
    pub split_distance: f32,
}

impl Default for WaterLod {
    fn default() -> Self {
        WaterLod {
            levels: 5,
            block: 8,
            split_distance: 1.5,
        }
    }
}

/// A leaf of the quadtree: its level and its index among the nodes of that level.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Leaf {
    /// Level (0: the whole plane).
    pub level: u32,
    /// Column among the `2^level` nodes along `+x`.
    pub ix: u32,
    /// Row among the `2^level` nodes along `-z`.
    pub iz: u32,
}

impl WaterLod {
    /// The balanced leaves for a camera at `eye` over the plane of `size` centred on the
    /// origin, sorted.
    pub fn leaves(&self, size: Vec2, eye: Vec3) -> Vec<Leaf> {
        let top = self.levels.min(10);
        let n = 1u32 << top;
        // Leaf level of every finest node, row-major (iz, ix).
        let mut level = vec![0u32; (n * n) as usize];
        let (hx, hz) = (0.5 * size.x, 0.5 * size.y);
        let split = |l: u32, ix: u32, iz: u32| -> bool {
            let m = (1u32 << l) as f32;
            let (w, d) = (size.x / m, size.y / m);
            let x0 = -hx + ix as f32 * w;
            let z1 = hz - iz as f32 * d;
            let cx = eye.x.clamp(x0, x0 + w);
            let cz = eye.z.clamp(z1 - d, z1);
            let dist = Vec3::new(eye.x - cx, eye.y, eye.z - cz).length();
            dist < self.split_distance * w.max(d)
        };
        // Top-down refinement.
        let mut stack = vec![(0u32, 0u32, 0u32)];
        while let Some((l, ix, iz)) = stack.pop() {
            if l < top && split(l, ix, iz) {
                for (dx, dz) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    stack.push((l + 1, 2 * ix + dx, 2 * iz + dz));
                }
            } else {
                set_level(&mut level, n, top, l, ix, iz);
            }
        }
        // 2:1 balance: split any leaf with a neighbour two or more levels finer.
        loop {
            let mut changed = false;
            for leaf in collect_leaves(&level, n, top) {
                let s = 1u32 << (top - leaf.level);
                let (x0, z0) = (leaf.ix * s, leaf.iz * s);
                let mut finest = 0;
                for k in 0..s {
                    let around = [
                        (x0 as i64 - 1, (z0 + k) as i64),
                        ((x0 + s) as i64, (z0 + k) as i64),
                        ((x0 + k) as i64, z0 as i64 - 1),
                        ((x0 + k) as i64, (z0 + s) as i64),
                    ];
                    for (x, z) in around {
                        if x >= 0 && z >= 0 && x < n as i64 && z < n as i64 {
                            finest = finest.max(level[(z as u32 * n + x as u32) as usize]);
                        }
                    }
                }
                if finest > leaf.level + 1 {
                    for (dx, dz) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                        set_level(
                            &mut level,
                            n,
                            top,
                            leaf.level + 1,
                            2 * leaf.ix + dx,
                            2 * leaf.iz + dz,
                        );
                    }
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        collect_leaves(&level, n, top)
    }

    /// The water grid over `size` (centred on the origin, `y = 0`) for a camera at `eye`:
    /// the leaves' blocks, crack-free (module doc), normals `+y`, uv as [`Mesh::grid`]'s
    /// (`u` along `+x`, `v` along `-z`, 0..1), triangles wound counter-clockwise seen from
    /// above. Deterministic.
    pub fn mesh(&self, size: Vec2, eye: Vec3) -> Mesh {
        let top = self.levels.min(10);
        let block = self.block.clamp(1, 64);
        let cells = (1u32 << top) * block;
        let leaves = self.leaves(size, eye);
        let (hx, hz) = (0.5 * size.x, 0.5 * size.y);
        let mut mesh = Mesh::default();
        let mut index: HashMap<(u32, u32), u32> = HashMap::new();
        let mut vertex = |mesh: &mut Mesh, i: u32, j: u32| -> u32 {
            *index.entry((i, j)).or_insert_with(|| {
                let (u, v) = (i as f32 / cells as f32, j as f32 / cells as f32);
                mesh.positions
                    .push(Vec3::new(-hx + u * size.x, 0.0, hz - v * size.y));
                mesh.normals.push(Vec3::Y);
                mesh.uvs.push(Vec2::new(u, v));
                (mesh.positions.len() - 1) as u32
            })
        };
        // Every leaf's lattice first, so that midpoints can be looked up.
        for leaf in &leaves {
            let step = 1u32 << (top - leaf.level);
            let (i0, j0) = (leaf.ix * block * step, leaf.iz * block * step);
            for b in 0..=block {
                for a in 0..=block {
                    vertex(&mut mesh, i0 + a * step, j0 + b * step);
                }
            }
        }
        let lattice: std::collections::HashSet<(u32, u32)> = index_keys(&mesh, cells, size);
        for leaf in &leaves {
            let step = 1u32 << (top - leaf.level);
            let (i0, j0) = (leaf.ix * block * step, leaf.iz * block * step);
            let h = step / 2;
            for b in 0..block {
                for a in 0..block {
                    let (i, j) = (i0 + a * step, j0 + b * step);
                    // Corners and optional edge midpoints, counter-clockwise seen from +y.
                    let ring: [(u32, u32, bool); 8] = [
                        (i, j, true),
                        (i + h, j, false),
                        (i + step, j, true),
                        (i + step, j + h, false),
                        (i + step, j + step, true),
                        (i + h, j + step, false),
                        (i, j + step, true),
                        (i, j + h, false),
                    ];
                    let present: Vec<(u32, u32)> = ring
                        .iter()
                        .filter(|(x, z, corner)| *corner || (h > 0 && lattice.contains(&(*x, *z))))
                        .map(|&(x, z, _)| (x, z))
                        .collect();
                    let ids: Vec<u32> = present
                        .iter()
                        .map(|&(x, z)| vertex(&mut mesh, x, z))
                        .collect();
                    if ids.len() == 4 {
                        mesh.indices.push([ids[0], ids[1], ids[2]]);
                        mesh.indices.push([ids[0], ids[2], ids[3]]);
                    } else {
                        let c = vertex(&mut mesh, i + h, j + h);
                        for k in 0..ids.len() {
                            mesh.indices.push([c, ids[k], ids[(k + 1) % ids.len()]]);
                        }
                    }
                }
            }
        }
        mesh
    }
}

/// The lattice coordinates of the mesh's vertices so far.
fn index_keys(mesh: &Mesh, cells: u32, _size: Vec2) -> std::collections::HashSet<(u32, u32)> {
    mesh.uvs
        .iter()
        .map(|uv| {
            (
                (uv.x * cells as f32).round() as u32,
                (uv.y * cells as f32).round() as u32,
            )
        })
        .collect()
}

/// Sets the leaf level of every finest node under node `(l, ix, iz)` to `l`.
fn set_level(level: &mut [u32], n: u32, top: u32, l: u32, ix: u32, iz: u32) {
    let s = 1u32 << (top - l);
    for z in iz * s..(iz + 1) * s {
        for x in ix * s..(ix + 1) * s {
            level[(z * n + x) as usize] = l;
        }
    }
}

/// The leaves of a level map, sorted.
fn collect_leaves(level: &[u32], n: u32, top: u32) -> Vec<Leaf> {
    let mut out = Vec::new();
    for z in 0..n {
        for x in 0..n {
            let l = level[(z * n + x) as usize];
            let s = 1u32 << (top - l);
            if x % s == 0 && z % s == 0 {
                out.push(Leaf {
                    level: l,
                    ix: x / s,
                    iz: z / s,
                });
            }
        }
    }
    out.sort();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn leaves_tile_the_plane_and_are_balanced_and_the_mesh_has_no_t_junctions() {
        let lod = WaterLod::default();
        let size = Vec2::new(80.0, 80.0);
        let eye = Vec3::new(0.0, 3.0, 18.0);
        let leaves = lod.leaves(size, eye);
        let area: f64 = leaves.iter().map(|l| 0.25f64.powi(l.level as i32)).sum();
        assert!((area - 1.0).abs() < 1e-12, "{area}");
        assert!(leaves.iter().any(|l| l.level == 5) && leaves.iter().any(|l| l.level <= 2));
        let m = lod.mesh(size, eye);
        assert!(m.is_consistent());
        // Every triangle faces up and no vertex lies inside another triangle's edge.
        let cells = 256.0;
        let key = |p: Vec3| {
            (
                ((p.x + 40.0) / 80.0 * cells).round() as i64,
                ((40.0 - p.z) / 80.0 * cells).round() as i64,
            )
        };
        let verts: std::collections::HashSet<(i64, i64)> =
            m.positions.iter().map(|&p| key(p)).collect();
        for t in &m.indices {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            assert!((b - a).cross(c - a).y > 0.0);
            for (p, q) in [(a, b), (b, c), (c, a)] {
                let (p, q) = (key(p), key(q));
                let len = (q.0 - p.0).abs().max((q.1 - p.1).abs());
                for s in 1..len {
                    let r = (p.0 + (q.0 - p.0) * s / len, p.1 + (q.1 - p.1) * s / len);
                    assert!(!verts.contains(&r), "T-junction at {r:?} on {p:?}–{q:?}");
                }
            }
        }
        assert!(m.vertex_count() < 257 * 257 / 2, "{}", m.vertex_count());
    }
}
