//! Triangle meshes and their generators: UV sphere, parallelogram grids (planes), horizontal
//! grids, heightfields, cuboids and vertical cylinders; vertex displacement with smooth
//! normals recomputed.
//!
//! Winding: triangles are counter-clockwise seen from the side their normals point to
//! (`cross(b - a, c - a)` along the normal). Smooth normals are the area-weighted sums of
//! the face normals around a vertex (the unnormalised cross product weights each face by
//! twice its area; Max, "Weights for computing vertex normals from facet normals", JGT
//! 1999, compares this with other weightings), with vertices at the same position welded
//! so that seams and poles stay smooth.

use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// An indexed triangle mesh in world space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions, metres.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, out of the surface.
    pub normals: Vec<Vec3>,
    /// Vertex texture coordinates.
    pub uvs: Vec<Vec2>,
    /// Triangles as three vertex indices, counter-clockwise seen from outside.
    pub indices: Vec<[u32; 3]>,
}

impl Mesh {
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Whether the attribute arrays have one entry per vertex and every index is in range.
    pub fn is_consistent(&self) -> bool {
        let n = self.positions.len();
        self.normals.len() == n
            && self.uvs.len() == n
            && self
                .indices
                .iter()
                .all(|t| t.iter().all(|&i| (i as usize) < n))
    }

    /// Appends `other`'s vertices and triangles.
    pub fn append(&mut self, other: &Mesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.uvs.extend_from_slice(&other.uvs);
        self.indices
            .extend(other.indices.iter().map(|t| t.map(|i| i + base)));
    }

    /// A UV sphere: `segments` around (≥ 3) × `rings` from pole to pole (≥ 2). Vertices are
    /// duplicated along the seam and at the poles so uvs are continuous: `u = j / segments`
    /// with the seam at the back (`-z`) and `u = 0.5` facing `+z`; `v = 1 - i / rings`, 1 at
    /// the north pole (`+y`). Normals are exact (`(p - center) / radius`).
    pub fn uv_sphere(center: Vec3, radius: f32, segments: u32, rings: u32) -> Mesh {
        let (segs, rings) = (segments.max(3), rings.max(2));
        let mut m = Mesh::default();
        for i in 0..=rings {
            let theta = PI * i as f32 / rings as f32;
            let (st, ct) = theta.sin_cos();
            for j in 0..=segs {
                // The seam's two copies (j = 0 and j = segs) get bitwise equal positions.
                let phi = 2.0 * PI * (j % segs) as f32 / segs as f32;
                let (sp, cp) = phi.sin_cos();
                let n = if i == 0 {
                    Vec3::Y
                } else if i == rings {
                    Vec3::NEG_Y
                } else {
                    Vec3::new(-st * sp, ct, -st * cp)
                };
                m.positions.push(center + radius * n);
                m.normals.push(n);
                m.uvs.push(Vec2::new(
                    j as f32 / segs as f32,
                    1.0 - i as f32 / rings as f32,
                ));
            }
        }
        let row = segs + 1;
        for i in 0..rings {
            for j in 0..segs {
                let a = i * row + j;
                let (b, c, d) = (a + row, a + row + 1, a + 1);
                // (a, b, c) runs down then around: cross(dθ, dφ) points out of the sphere.
                if i != 0 {
                    m.indices.push([a, c, d]);
                }
                if i != rings - 1 {
                    m.indices.push([a, b, c]);
                }
            }
        }
        m
    }

    /// A parallelogram grid: `origin + s · edge_u + t · edge_v` for `s, t` in [0, 1], with
    /// `resolution = [cells along u, cells along v]` (each ≥ 1), uv `(s, t)`, and the flat
    /// normal `normalize(cross(edge_u, edge_v))`.
    pub fn parallelogram(origin: Vec3, edge_u: Vec3, edge_v: Vec3, resolution: [u32; 2]) -> Mesh {
        let normal = edge_u.cross(edge_v).normalize_or(Vec3::Y);
        Mesh::grid_with(resolution, |s, t| {
            (origin + s * edge_u + t * edge_v, normal)
        })
    }

    /// A horizontal grid of `size = [x extent, z extent]` centred on `center`, normal `+y`,
    /// `resolution` cells along x and z. uv: `u` along `+x`, `v` along `-z` (0 at the near,
    /// `+z` edge).
    pub fn grid(center: Vec3, size: Vec2, resolution: [u32; 2]) -> Mesh {
        let origin = center + Vec3::new(-0.5 * size.x, 0.0, 0.5 * size.y);
        Mesh::parallelogram(
            origin,
            Vec3::new(size.x, 0.0, 0.0),
            Vec3::new(0.0, 0.0, -size.y),
            resolution,
        )
    }

    /// A heightfield over the horizontal grid of [`Mesh::grid`] (centre `(cx, 0, cz)`): each
    /// vertex at `y = height(x, z)`, normals recomputed from the faces.
    pub fn heightfield(
        center: Vec2,
        size: Vec2,
        resolution: [u32; 2],
        height: impl Fn(f32, f32) -> f32,
    ) -> Mesh {
        let mut m = Mesh::grid(Vec3::new(center.x, 0.0, center.y), size, resolution);
        for p in &mut m.positions {
            p.y = height(p.x, p.z);
        }
        m.recompute_normals();
        m
    }

    /// An axis-aligned box of `size` centred on `center`: 24 vertices (flat normals per
    /// face), uv 0..1 on each face.
    pub fn cuboid(center: Vec3, size: Vec3) -> Mesh {
        let h = 0.5 * size;
        let faces = [
            (Vec3::X, Vec3::NEG_Z),
            (Vec3::NEG_X, Vec3::Z),
            (Vec3::Y, Vec3::X),
            (Vec3::NEG_Y, Vec3::X),
            (Vec3::Z, Vec3::X),
            (Vec3::NEG_Z, Vec3::NEG_X),
        ];
        let mut m = Mesh::default();
        for (n, u) in faces {
            let v = n.cross(u);
            let (eu, ev) = (u * size.dot(u.abs()), v * size.dot(v.abs()));
            let origin = center + n * h.dot(n.abs()) - 0.5 * (eu + ev);
            m.append(&Mesh::parallelogram(origin, eu, ev, [1, 1]));
        }
        m
    }

    /// A vertical cylinder (a pole) of `radius` from `base` up by `height`, `segments`
    /// around (≥ 3), with flat caps. Side uv: `u` around, `v` up; cap uv: the disc mapped
    /// into [0, 1]².
    pub fn cylinder(base: Vec3, height: f32, radius: f32, segments: u32) -> Mesh {
        let segs = segments.max(3);
        let mut m = Mesh::default();
        // Side.
        for j in 0..=segs {
            let phi = 2.0 * PI * (j % segs) as f32 / segs as f32;
            let n = Vec3::new(phi.sin(), 0.0, phi.cos());
            for k in 0..2 {
                m.positions
                    .push(base + radius * n + Vec3::Y * (height * k as f32));
                m.normals.push(n);
                m.uvs.push(Vec2::new(j as f32 / segs as f32, k as f32));
            }
        }
        for j in 0..segs {
            let a = 2 * j;
            // a: bottom j, a+1: top j, a+2: bottom j+1, a+3: top j+1. Around +y (φ from +z
            // towards +x), cross(bottom j+1 - bottom j, top j - bottom j) points outwards.
            m.indices.push([a, a + 2, a + 3]);
            m.indices.push([a, a + 3, a + 1]);
        }
        // Caps.
        for (y, n) in [(height, Vec3::Y), (0.0, Vec3::NEG_Y)] {
            let c = m.positions.len() as u32;
            m.positions.push(base + Vec3::Y * y);
            m.normals.push(n);
            m.uvs.push(Vec2::splat(0.5));
            for j in 0..segs {
                let phi = 2.0 * PI * j as f32 / segs as f32;
                let (s, co) = phi.sin_cos();
                m.positions
                    .push(base + Vec3::new(radius * s, y, radius * co));
                m.normals.push(n);
                m.uvs.push(Vec2::new(0.5 + 0.5 * s, 0.5 - 0.5 * co));
            }
            for j in 0..segs {
                let (p, q) = (c + 1 + j, c + 1 + (j + 1) % segs);
                // Seen from above, φ increasing runs clockwise (from +z towards +x), so the
                // top cap is (c, q, p) and the bottom (c, p, q).
                m.indices
                    .push(if n.y > 0.0 { [c, p, q] } else { [c, q, p] });
            }
        }
        m.orient_to_normals();
        m
    }

    /// A grid of `(resolution[0] + 1) × (resolution[1] + 1)` vertices from
    /// `f(s, t) -> (position, normal)`, uv `(s, t)`, two triangles per cell.
    fn grid_with(resolution: [u32; 2], f: impl Fn(f32, f32) -> (Vec3, Vec3)) -> Mesh {
        let (nu, nv) = (resolution[0].max(1), resolution[1].max(1));
        let mut m = Mesh::default();
        let count = ((nu + 1) * (nv + 1)) as usize;
        m.positions.reserve(count);
        m.normals.reserve(count);
        m.uvs.reserve(count);
        for j in 0..=nv {
            let t = j as f32 / nv as f32;
            for i in 0..=nu {
                let s = i as f32 / nu as f32;
                let (p, n) = f(s, t);
                m.positions.push(p);
                m.normals.push(n);
                m.uvs.push(Vec2::new(s, t));
            }
        }
        let row = nu + 1;
        m.indices.reserve((2 * nu * nv) as usize);
        for j in 0..nv {
            for i in 0..nu {
                let a = j * row + i;
                m.indices.push([a, a + 1, a + row + 1]);
                m.indices.push([a, a + row + 1, a + row]);
            }
        }
        m
    }

    /// Flips every triangle whose face normal points against its vertex normals (used by
    /// generators so their winding needs no case analysis).
    fn orient_to_normals(&mut self) {
        for t in &mut self.indices {
            let [a, b, c] = t.map(|i| i as usize);
            let face = (self.positions[b] - self.positions[a])
                .cross(self.positions[c] - self.positions[a]);
            let n = self.normals[a] + self.normals[b] + self.normals[c];
            if face.dot(n) < 0.0 {
                t.swap(1, 2);
            }
        }
    }

    /// A copy with every vertex moved by `offsets[i]` and smooth normals recomputed
    /// (area-weighted face normals; vertices that share a position in `self` are welded, so
    /// seams and poles stay smooth). uvs and triangles are kept.
    ///
    /// # Panics
    /// If `offsets.len()` differs from the vertex count.
    pub fn displaced(&self, offsets: &[Vec3]) -> Mesh {
        assert_eq!(
            offsets.len(),
            self.positions.len(),
            "Mesh::displaced: {} offsets for {} vertices",
            offsets.len(),
            self.positions.len()
        );
        let groups = weld_groups(&self.positions);
        let mut m = self.clone();
        for (p, o) in m.positions.iter_mut().zip(offsets) {
            *p += *o;
        }
        m.normals = smooth_normals(&m.positions, &m.indices, &groups, &self.normals);
        m
    }

    /// What [`Mesh::displaced`] sums its normals over, for doing it elsewhere (the GPU): per
    /// vertex its weld group's smallest vertex index, and per group (indexed by that vertex,
    /// CSR: `starts[g]..starts[g + 1]` into `triangles`) the triangles touching the group, in
    /// the order and with the multiplicity in which [`Mesh::displaced`] adds their faces.
    pub fn normal_adjacency(&self) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
        let groups = weld_groups(&self.positions);
        let mut counts = vec![0u32; self.positions.len() + 1];
        for t in &self.indices {
            for &v in t {
                counts[groups[v as usize] as usize + 1] += 1;
            }
        }
        for i in 1..counts.len() {
            counts[i] += counts[i - 1];
        }
        let starts = counts.clone();
        let mut next = counts;
        let mut triangles = vec![0u32; *starts.last().unwrap_or(&0) as usize];
        for (k, t) in self.indices.iter().enumerate() {
            for &v in t {
                let g = groups[v as usize] as usize;
                triangles[next[g] as usize] = k as u32;
                next[g] += 1;
            }
        }
        (groups, starts, triangles)
    }

    /// Recomputes the normals in place as [`Mesh::displaced`] does.
    pub fn recompute_normals(&mut self) {
        let groups = weld_groups(&self.positions);
        self.normals = smooth_normals(&self.positions, &self.indices, &groups, &self.normals);
    }
}

/// For each vertex, the smallest index of a vertex at exactly the same position (bitwise,
/// with -0.0 read as 0.0). Deterministic.
fn weld_groups(positions: &[Vec3]) -> Vec<u32> {
    let key = |p: Vec3| {
        p.to_array()
            .map(|c| if c == 0.0 { 0u32 } else { c.to_bits() })
    };
    let mut order: Vec<u32> = (0..positions.len() as u32).collect();
    order.sort_unstable_by_key(|&i| (key(positions[i as usize]), i));
    let mut groups = vec![0u32; positions.len()];
    let mut start = 0;
    while start < order.len() {
        let k = key(positions[order[start] as usize]);
        let mut end = start + 1;
        while end < order.len() && key(positions[order[end] as usize]) == k {
            end += 1;
        }
        // Sorted by (key, index): the run's first is its smallest index.
        let rep = order[start];
        for &i in &order[start..end] {
            groups[i as usize] = rep;
        }
        start = end;
    }
    groups
}

/// Area-weighted smooth normals over welded groups; a vertex whose faces cancel (or have no
/// area) keeps `fallback[i]`.
fn smooth_normals(
    positions: &[Vec3],
    indices: &[[u32; 3]],
    groups: &[u32],
    fallback: &[Vec3],
) -> Vec<Vec3> {
    let mut sums = vec![Vec3::ZERO; positions.len()];
    for t in indices {
        let [a, b, c] = t.map(|i| i as usize);
        let face = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
        for v in [a, b, c] {
            sums[groups[v] as usize] += face;
        }
    }
    (0..positions.len())
        .map(|i| {
            let n = sums[groups[i] as usize];
            let len = n.length();
            if len > 0.0 && len.is_finite() {
                n / len
            } else {
                fallback.get(i).copied().unwrap_or(Vec3::Y)
            }
        })
        .collect()
}
