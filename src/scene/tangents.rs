//! Tangent frames of meshes: MikkTSpace tangents per vertex (Mikkelsen 2008, "Simulation of
//! Wrinkled Surfaces Revisited", the convention Blender, glTF 2.0 and the common bakers
//! share), and the per-sample frame a normal map reads: the interpolated tangent made
//! orthogonal to the shading normal (Gram–Schmidt), `B = sign · (N × T)`.
//!
//! Degenerate uvs (a triangle whose uvs are collinear or coincide) give MikkTSpace no
//! direction: such a vertex gets the tangent of Duff et al.'s orthonormal basis of its normal
//! (2017, "Building an Orthonormal Basis, Revisited", JCGT 6(1)) and sign +1, a valid frame
//! that a normal map turns arbitrarily about N there (it cannot be right: the uvs say nothing
//! about the directions).

use super::mesh::Mesh;
use crate::nodes::ibl::frame;
use bevy_mikktspace::{Geometry, TangentSpace, generate_tangents};
use glam::{Vec3, Vec4};

/// The mesh as MikkTSpace reads it, and the per-vertex tangents it writes.
struct Faces<'a> {
    mesh: &'a Mesh,
    tangents: Vec<Option<Vec4>>,
}

impl Geometry for Faces<'_> {
    fn num_faces(&self) -> usize {
        self.mesh.indices.len()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.positions[self.mesh.indices[face][vert] as usize].to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.normals[self.mesh.indices[face][vert] as usize].to_array()
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        self.mesh.uvs[self.mesh.indices[face][vert] as usize].to_array()
    }

    fn set_tangent(&mut self, space: Option<TangentSpace>, face: usize, vert: usize) {
        let v = self.mesh.indices[face][vert] as usize;
        // Every corner of an indexed vertex has the same position, normal and uv, so
        // MikkTSpace gives them the same frame; keep the first it reports.
        if self.tangents[v].is_none() {
            self.tangents[v] = space.map(|s| Vec4::from_array(s.tangent_encoded()));
        }
    }
}

impl Mesh {
    /// The MikkTSpace tangent of every vertex: `xyz` the unit tangent (the direction of
    /// growing u), `w` the bitangent sign (±1: the bitangent, the direction of growing v, is
    /// `w · (N × T)`). Vertices MikkTSpace gives no usable direction (degenerate uvs, or on
    /// no triangle) get the tangent of Duff et al.'s basis of their normal and sign +1.
    pub fn tangents(&self) -> Vec<Vec4> {
        let mut faces = Faces {
            mesh: self,
            tangents: vec![None; self.positions.len()],
        };
        // The error type has no values: generation cannot fail.
        let _ = generate_tangents(&mut faces);
        faces
            .tangents
            .into_iter()
            .zip(&self.normals)
            .map(|(t, &n)| match t {
                Some(t) if usable(t.truncate(), n) => t.truncate().normalize().extend(t.w.signum()),
                _ => basis_tangent(n).extend(1.0),
            })
            .collect()
    }
}

/// Whether `t` is finite, not zero and not along `n` (so it gives a direction in the plane).
fn usable(t: Vec3, n: Vec3) -> bool {
    let l = t.length();
    t.is_finite() && l > 1e-6 && (t - n * n.dot(t)).length() > 1e-3 * l
}

/// The tangent of Duff et al.'s orthonormal basis of `n` (any unit vector perpendicular to
/// `n`; `(1, 0, 0)` for a zero or non-finite `n`).
fn basis_tangent(n: Vec3) -> Vec3 {
    let n = n.normalize_or_zero();
    if n == Vec3::ZERO {
        return Vec3::X;
    }
    frame(n).0
}

/// The unit tangent of the frame at a sample: the interpolated tangent `t` made orthogonal to
/// the unit shading normal `n` (Gram–Schmidt, `t − n (n · t)`, normalised), or Duff et al.'s
/// basis tangent of `n` where that leaves no direction. The WGSL render entry
/// (`mg_tangent`) computes the same.
pub fn orthonormal_tangent(n: Vec3, t: Vec3) -> Vec3 {
    let o = t - n * n.dot(t);
    let l = o.length();
    if l > 1e-6 * t.length() && l.is_finite() && l > 0.0 {
        o / l
    } else {
        basis_tangent(n)
    }
}
