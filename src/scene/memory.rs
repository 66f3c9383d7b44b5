//! What a scene's meshes need in memory, computed from its parameters before any mesh is
//! built ([`crate::budget`]): the material surface (the ball's or the bubble's sphere, the
//! water grid or its level-of-detail quadtree) and the water scene's seabed heightfield.
//! The room's other objects are fixed, small meshes, counted in [`FIXED_MESH_BYTES`].

use super::Scene;
use super::kind::SceneKind;
use crate::budget::{MemoryBudget, MemoryError};
use glam::{Vec2, Vec3};

/// Bytes per mesh vertex at the peak of a render, an upper bound with
/// [`MESH_TRIANGLE_BYTES`]: the mesh (position, normal, uv: 32), its displaced copy,
/// MikkTSpace tangents, the weld groups and normal adjacency of a displacement, the
/// level-of-detail builder's vertex map, the rasteriser's packed copy. Measured (debug
/// build, peak resident size above a 257 × 129-vertex ball's, 16 × 16 render): a 2049 ×
/// 1025-vertex ball (2.1 M vertices, 4.2 M triangles) takes 818 MiB on the CPU path and
/// 802 MiB on the GPU path with a displacement output, 390 bytes per vertex and its two
/// triangles; these constants give 448.
pub const MESH_VERTEX_BYTES: u64 = 256;

/// Bytes per mesh triangle at the peak of a render (see [`MESH_VERTEX_BYTES`]).
pub const MESH_TRIANGLE_BYTES: u64 = 96;

/// Bytes of the fixed meshes of the scenes (the room's walls and props, the water's skirts,
/// the bubble's backdrop), an upper bound.
pub const FIXED_MESH_BYTES: u64 = 16 << 20;

/// One mesh a scene will build: the field it comes from, its size in words, and bytes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MeshCost {
    /// The scene field that sets its size and the size (`kind.ball.segments [4096, 4096]: a
    /// UV sphere of 16785409 vertices`).
    pub what: String,
    /// Bytes it needs ([`MESH_VERTEX_BYTES`], [`MESH_TRIANGLE_BYTES`]).
    pub bytes: u64,
}

/// Bytes of a mesh of `vertices` and `triangles`.
fn mesh_bytes(vertices: u64, triangles: u64) -> u64 {
    vertices
        .saturating_mul(MESH_VERTEX_BYTES)
        .saturating_add(triangles.saturating_mul(MESH_TRIANGLE_BYTES))
}

/// The cost of a UV sphere of `[segments, rings]` named by `field`.
fn sphere(field: &str, [s, r]: [u32; 2]) -> MeshCost {
    let (s, r) = (s.max(3) as u64, r.max(2) as u64);
    let vertices = (s + 1) * (r + 1);
    MeshCost {
        what: format!("{field} [{s}, {r}]: a UV sphere of {vertices} vertices"),
        bytes: mesh_bytes(vertices, 2 * s * r),
    }
}

/// The cost of a grid of `[x, z]` cells named by `field`.
fn grid(field: &str, [x, z]: [u32; 2]) -> MeshCost {
    let (x, z) = (x.max(1) as u64, z.max(1) as u64);
    let vertices = (x + 1) * (z + 1);
    MeshCost {
        what: format!("{field} [{x}, {z}]: a grid of {vertices} vertices"),
        bytes: mesh_bytes(vertices, 2 * x * z),
    }
}

impl Scene {
    /// The meshes this scene builds and what each needs, from its parameters alone (the
    /// level-of-detail quadtree's leaves are counted, which takes at most 4 MiB for its
    /// finest level map; no mesh is built).
    pub fn mesh_costs(&self) -> Vec<MeshCost> {
        let mut costs = vec![MeshCost {
            what: "the scene's fixed objects".to_owned(),
            bytes: FIXED_MESH_BYTES,
        }];
        match &self.kind {
            SceneKind::Ball(b) => costs.push(sphere("kind.ball.segments", b.segments)),
            SceneKind::Bubble(b) => costs.push(sphere("kind.bubble.segments", b.segments)),
            SceneKind::Water(w) => {
                costs.push(match &w.lod {
                    None => grid("kind.water.grid", w.grid),
                    Some(lod) => {
                        let leaves = lod
                            .leaves(Vec2::from(w.size), Vec3::from(self.camera.position))
                            .len() as u64;
                        let block = lod.block.clamp(1, 64) as u64;
                        // Each leaf's (block + 1)² lattice, and up to a centre vertex and
                        // eight triangles per cell along its edges.
                        let vertices = leaves * (block + 1) * (block + 1) + leaves * 4 * block;
                        let triangles = leaves * block * block * 2 + leaves * 4 * block * 6;
                        MeshCost {
                            what: format!(
                                "kind.water.lod {{levels: {}, block: {}, split_distance: {:?}}}: a grid of {leaves} blocks, {vertices} vertices",
                                lod.levels, lod.block, lod.split_distance
                            ),
                            bytes: mesh_bytes(vertices, triangles),
                        }
                    }
                });
                costs.push(grid("kind.water.seabed.grid", w.seabed.grid));
            }
        }
        costs
    }

    /// Reserves the scene's meshes ([`Scene::mesh_costs`]) in `budget`, or names the first
    /// that does not fit.
    pub fn reserve_meshes(&self, budget: &MemoryBudget) -> Result<(), MemoryError> {
        for cost in self.mesh_costs() {
            budget.reserve(|| cost.what.clone(), cost.bytes)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_and_grid_counts_match_the_built_meshes() {
        // The counts are upper bounds of what Mesh builds: equal for grids, and for spheres
        // the vertices equal, the triangles 2·s·r against the built 2·s·(r − 1).
        let m = super::super::mesh::Mesh::uv_sphere(Vec3::ZERO, 1.0, 7, 5);
        let c = sphere("s", [7, 5]);
        assert_eq!(m.vertex_count(), 8 * 6);
        assert_eq!(c.bytes, mesh_bytes(48, 70));
        assert!(m.triangle_count() as u64 <= 70);
        let g = super::super::mesh::Mesh::grid(Vec3::ZERO, Vec2::ONE, [3, 4]);
        assert_eq!(g.vertex_count(), 20);
        assert_eq!(g.triangle_count(), 24);
        assert_eq!(grid("g", [3, 4]).bytes, mesh_bytes(20, 24));
    }

    #[test]
    fn lod_counts_bound_the_built_mesh() {
        let lod = super::super::lod::WaterLod::default();
        let (size, eye) = (Vec2::new(40.0, 40.0), Vec3::new(0.0, 3.0, 10.0));
        let mesh = lod.mesh(size, eye);
        let leaves = lod.leaves(size, eye).len() as u64;
        let block = lod.block as u64;
        let vertices = leaves * (block + 1) * (block + 1) + leaves * 4 * block;
        let triangles = leaves * block * block * 2 + leaves * 4 * block * 6;
        assert!(
            mesh.vertex_count() as u64 <= vertices,
            "{}",
            mesh.vertex_count()
        );
        assert!(mesh.triangle_count() as u64 <= triangles);
    }
}
