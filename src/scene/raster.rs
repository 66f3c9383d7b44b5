//! The CPU rasterizer: perspective projection, clipping against the near plane (and one
//! optional world plane), a z-buffer on `1/w`, perspective-correct barycentrics, several
//! samples per pixel on a fixed pattern. Rows of the image are cut into bands of
//! [`BAND_ROWS`] rows, each band rasterised by one rayon task over the triangles binned to
//! it, in the triangles' order: the result does not depend on the thread count.
//!
//! Coverage uses normalised edge functions (Pineda, "A parallel algorithm for polygon
//! rasterization", SIGGRAPH 1988) evaluated in f64 at each sample; a sample on an edge is
//! covered by both triangles (inclusive test), and the earlier triangle keeps it on a depth
//! tie. Interpolation is perspective-correct: attributes divided by `w` and `1/w` are
//! linear in screen space (Heckbert and Moreton, "Interpolation for polygon texture mapping
//! and shading", 1991). There is no back-face culling.

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use super::camera::CameraFrame;
use super::mesh::Mesh;

/// Rows per rasterisation band (one rayon task each).
pub(crate) const BAND_ROWS: usize = 8;

/// Tolerance of the inside test on normalised barycentrics.
const EDGE_EPS: f64 = 1e-9;

/// Sample counts whose pattern is the standard multisample pattern of Vulkan, D3D and
/// WebGPU, so that the GPU rasteriser's MSAA samples the same points.
pub const STANDARD_SAMPLE_COUNTS: [u32; 4] = [1, 2, 4, 8];

/// The standard multisample patterns (Vulkan "standard sample locations", the D3D11
/// patterns, WebGPU's 4-sample pattern) in sixteenths of a pixel, in the hardware's sample
/// order.
const STANDARD_PATTERNS: [&[[u8; 2]]; 4] = [
    &[[8, 8]],
    &[[12, 12], [4, 4]],
    &[[6, 2], [14, 6], [2, 10], [10, 14]],
    &[
        [9, 5],
        [7, 11],
        [13, 9],
        [5, 3],
        [3, 13],
        [1, 7],
        [11, 15],
        [15, 1],
    ],
];

/// For a standard sample count ([`STANDARD_SAMPLE_COUNTS`]), the hardware sample index of
/// each of [`sample_offsets`]'s samples, in order.
pub fn standard_sample_order(spp: u32) -> Option<Vec<u32>> {
    let k = STANDARD_SAMPLE_COUNTS.iter().position(|&c| c == spp)?;
    let mut order: Vec<u32> = (0..spp).collect();
    order.sort_by_key(|&i| STANDARD_PATTERNS[k][i as usize][0]);
    Some(order)
}

/// The sub-pixel sample offsets of `spp` samples per pixel (each in [0, 1)²), the same in
/// every pixel. For 1, 2, 4 and 8 samples, the standard multisample pattern
/// ([`STANDARD_SAMPLE_COUNTS`]) sorted by x, so that the GPU rasteriser's MSAA samples the
/// same points (all four are n-rooks patterns, one sample per column and per row stratum;
/// 1 is the pixel centre); for other counts, Hammersley points shifted by half a stratum,
/// `((s + 0.5) / spp, frac(φ₂(s) + 0.5 / spp))` for `s = 0..spp`, with `φ₂` the base-2
/// radical inverse (Hammersley and Handscomb, "Monte Carlo Methods", 1964): one sample per
/// column stratum, and for powers of two also one per row stratum.
pub fn sample_offsets(spp: u32) -> Vec<[f32; 2]> {
    if let Some(order) = standard_sample_order(spp) {
        let k = STANDARD_SAMPLE_COUNTS
            .iter()
            .position(|&c| c == spp)
            .unwrap_or(0);
        return order
            .iter()
            .map(|&i| STANDARD_PATTERNS[k][i as usize].map(|v| v as f32 / 16.0))
            .collect();
    }
    (0..spp)
        .map(|s| {
            let jx = (s as f64 + 0.5) / spp as f64;
            let radical = s.reverse_bits() as f64 / 4_294_967_296.0;
            let jy = (radical + 0.5 / spp as f64).fract();
            [jx as f32, jy as f32]
        })
        .collect()
}

/// Division of sample indices by a fixed divisor with a multiplication (then corrected, so
/// the quotient is exact for any `u32`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Divider {
    d: u32,
    inv: f64,
}

impl Divider {
    /// Division by `d` (≥ 1).
    pub(crate) fn new(d: u32) -> Divider {
        let d = d.max(1);
        Divider {
            d,
            inv: 1.0 / d as f64,
        }
    }

    /// `(i / d, i % d)`.
    #[inline]
    pub(crate) fn div_rem(&self, i: u32) -> (u32, u32) {
        let mut q = ((i as f64 + 0.5) * self.inv) as u64;
        let (i, d) = (i as u64, self.d as u64);
        if q * d > i {
            q -= 1;
        } else if (q + 1) * d <= i {
            q += 1;
        }
        (q as u32, (i - q * d) as u32)
    }
}

/// Pixel `(x, y)` and sample `s` of grid index `i`, for `spp` samples per pixel and image
/// width `width` given as dividers.
#[inline]
pub(crate) fn sample_coords(i: u32, spp: Divider, width: Divider) -> (u32, u32, u32) {
    let (pixel, s) = spp.div_rem(i);
    let (y, x) = width.div_rem(pixel);
    (x, y, s)
}

/// One mesh to draw.
#[derive(Clone, Copy, Debug)]
pub(crate) struct DrawItem<'a> {
    /// The triangles.
    pub mesh: &'a Mesh,
    /// Draw the mirror image about the plane `y = 0` (for planar reflections).
    pub mirror_y: bool,
    /// Keep only the part with `n·p + d ≥ 0` (`p` before mirroring), `(n, d)` packed.
    pub clip: Option<Vec4>,
}

impl<'a> DrawItem<'a> {
    /// `mesh` drawn as it is: not mirrored, not clipped.
    pub(crate) fn plain(mesh: &'a Mesh) -> DrawItem<'a> {
        DrawItem {
            mesh,
            mirror_y: false,
            clip: None,
        }
    }
}

/// What a sample sees: the nearest triangle and where on it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Fragment {
    /// `1 / w` (inverse view depth) of the nearest surface; 0 where nothing was hit.
    pub inv_w: f32,
    /// Index of the draw item.
    pub item: u32,
    /// Index of the triangle in its mesh.
    pub tri: u32,
    /// Perspective-correct barycentrics of the triangle's second and third vertices.
    pub b: [f32; 2],
}

impl Fragment {
    /// A sample that sees nothing.
    pub(crate) const EMPTY: Fragment = Fragment {
        inv_w: 0.0,
        item: u32::MAX,
        tri: u32::MAX,
        b: [0.0, 0.0],
    };

    /// Whether a surface was hit.
    #[inline]
    pub(crate) fn is_hit(&self) -> bool {
        self.tri != u32::MAX
    }
}

/// A clipped polygon's vertex.
#[derive(Clone, Copy, Debug, Default)]
struct ClipVert {
    /// View-space position.
    v: Vec3,
    /// Barycentrics of vertices 1 and 2 of the original triangle.
    b: [f32; 2],
    /// Signed distance to the optional clip plane.
    d: f32,
}

impl ClipVert {
    fn lerp(a: &ClipVert, b: &ClipVert, t: f32) -> ClipVert {
        ClipVert {
            v: a.v + (b.v - a.v) * t,
            b: [
                a.b[0] + (b.b[0] - a.b[0]) * t,
                a.b[1] + (b.b[1] - a.b[1]) * t,
            ],
            d: a.d + (b.d - a.d) * t,
        }
    }
}

/// A screen-space triangle ready to scan.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SetupTri {
    item: u32,
    tri: u32,
    /// Edge functions `λ_k = a x + b y + c`, normalised so that they are the screen-space
    /// barycentrics.
    e: [[f64; 3]; 3],
    /// `1/w` as a screen-space plane `a x + b y + c`.
    z: [f64; 3],
    /// The original triangle's barycentrics of vertices 1 and 2, times `1/w`, as planes.
    bw: [[f64; 3]; 2],
    /// Inclusive pixel bounds `[x0, y0, x1, y1]`.
    bbox: [u32; 4],
}

/// Sutherland–Hodgman clipping of a convex polygon to `dist ≥ 0` (Sutherland and Hodgman,
/// "Reentrant polygon clipping", CACM 1974); the crossing point is always computed from the
/// inside vertex so that neighbours clip a shared edge alike.
fn clip_polygon(
    input: &[ClipVert],
    out: &mut [ClipVert; 8],
    dist: impl Fn(&ClipVert) -> f32,
) -> usize {
    let mut m = 0;
    for i in 0..input.len() {
        let a = &input[i];
        let b = &input[(i + 1) % input.len()];
        let (da, db) = (dist(a), dist(b));
        if da >= 0.0 {
            out[m] = *a;
            m += 1;
        }
        if (da >= 0.0) != (db >= 0.0) {
            let (pin, pout, din, dout) = if da >= 0.0 {
                (a, b, da, db)
            } else {
                (b, a, db, da)
            };
            out[m] = ClipVert::lerp(pin, pout, din / (din - dout));
            m += 1;
        }
    }
    m
}

/// Sets up the screen triangle `(p0, p1, p2)`, or `None` when it is degenerate or off
/// screen.
fn setup(item: u32, tri: u32, p: [&ClipVert; 3], cam: &CameraFrame) -> Option<SetupTri> {
    let s = p.map(|v| cam.project_view(v.v));
    let [(x0, y0), (x1, y1), (x2, y2)] = s;
    let area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
    if area.is_nan() || area.abs() <= 1e-12 {
        return None;
    }
    let (w, h) = (cam.width as f64, cam.height as f64);
    let min_x = x0.min(x1).min(x2);
    let max_x = x0.max(x1).max(x2);
    let min_y = y0.min(y1).min(y2);
    let max_y = y0.max(y1).max(y2);
    if !(max_x >= 0.0 && max_y >= 0.0 && min_x < w && min_y < h) {
        return None;
    }
    let ia = 1.0 / area;
    let e = [
        [(y1 - y2) * ia, (x2 - x1) * ia, (x1 * y2 - x2 * y1) * ia],
        [(y2 - y0) * ia, (x0 - x2) * ia, (x2 * y0 - x0 * y2) * ia],
        [(y0 - y1) * ia, (x1 - x0) * ia, (x0 * y1 - x1 * y0) * ia],
    ];
    let inv_w = p.map(|v| 1.0 / -(v.v.z as f64));
    // A value given at the vertices, as the plane Σ_k λ_k(x, y) value_k.
    let plane = |v: [f64; 3]| [0, 1, 2].map(|c| e[0][c] * v[0] + e[1][c] * v[1] + e[2][c] * v[2]);
    let z = plane(inv_w);
    let bw = [0, 1].map(|j| plane([0, 1, 2].map(|k| p[k].b[j] as f64 * inv_w[k])));
    let clamp = |v: f64, hi: u32| v.floor().clamp(0.0, hi as f64) as u32;
    Some(SetupTri {
        item,
        tri,
        e,
        z,
        bw,
        bbox: [
            clamp(min_x, cam.width - 1),
            clamp(min_y, cam.height - 1),
            clamp(max_x, cam.width - 1),
            clamp(max_y, cam.height - 1),
        ],
    })
}

/// Clips and sets up every triangle of `items`, in order.
pub(crate) fn setup_all(items: &[DrawItem], cam: &CameraFrame) -> Vec<SetupTri> {
    let mut all = Vec::new();
    for (k, item) in items.iter().enumerate() {
        let mesh = item.mesh;
        let view: Vec<Vec3> = mesh
            .positions
            .par_iter()
            .map(|&p| {
                let q = if item.mirror_y {
                    Vec3::new(p.x, -p.y, p.z)
                } else {
                    p
                };
                cam.to_view(q)
            })
            .collect();
        let dist: Vec<f32> = match item.clip {
            Some(plane) => mesh
                .positions
                .par_iter()
                .map(|p| plane.truncate().dot(*p) + plane.w)
                .collect(),
            None => Vec::new(),
        };
        let near = cam.near;
        let chunks: Vec<Vec<SetupTri>> = mesh
            .indices
            .par_chunks(4096)
            .enumerate()
            .map(|(c, tris)| {
                let mut out = Vec::with_capacity(tris.len());
                for (i, t) in tris.iter().enumerate() {
                    let tri = (c * 4096 + i) as u32;
                    let v = t.map(|i| i as usize);
                    let d = |i: usize| dist.get(i).copied().unwrap_or(0.0);
                    let verts = [
                        ClipVert {
                            v: view[v[0]],
                            b: [0.0, 0.0],
                            d: d(v[0]),
                        },
                        ClipVert {
                            v: view[v[1]],
                            b: [1.0, 0.0],
                            d: d(v[1]),
                        },
                        ClipVert {
                            v: view[v[2]],
                            b: [0.0, 1.0],
                            d: d(v[2]),
                        },
                    ];
                    let in_near = |c: &ClipVert| -c.v.z - near;
                    let in_plane = |c: &ClipVert| c.d;
                    let near_ok = verts.iter().all(|c| in_near(c) >= 0.0);
                    let plane_ok = verts.iter().all(|c| in_plane(c) >= 0.0);
                    if near_ok && plane_ok {
                        out.extend(setup(k as u32, tri, [&verts[0], &verts[1], &verts[2]], cam));
                        continue;
                    }
                    if verts.iter().all(|c| in_near(c) < 0.0)
                        || verts.iter().all(|c| in_plane(c) < 0.0)
                    {
                        continue;
                    }
                    let mut a = [ClipVert::default(); 8];
                    let mut b = [ClipVert::default(); 8];
                    let mut n = clip_polygon(&verts, &mut a, in_near);
                    if !plane_ok {
                        n = clip_polygon(&a[..n], &mut b, in_plane);
                        a = b;
                    }
                    for j in 1..n.saturating_sub(1) {
                        out.extend(setup(k as u32, tri, [&a[0], &a[j], &a[j + 1]], cam));
                    }
                }
                out
            })
            .collect();
        all.extend(chunks.into_iter().flatten());
    }
    all
}

/// Rasterises `items` seen by `cam` at `offsets.len()` samples per pixel. Returns one
/// fragment per sample, sample `s` of pixel `(x, y)` at `(y · width + x) · spp + s`.
pub(crate) fn rasterize(
    items: &[DrawItem],
    cam: &CameraFrame,
    offsets: &[[f32; 2]],
) -> Vec<Fragment> {
    if cam.width as usize * cam.height as usize * offsets.len() == 0 {
        return Vec::new();
    }
    rasterize_rows(&setup_all(items, cam), cam, offsets, 0..cam.height as usize)
}

/// Rasterises the set-up triangles `tris` ([`setup_all`]) for the image rows `rows` only.
/// Returns one fragment per sample of those rows, sample `s` of pixel `(x, y)` at
/// `((y − rows.start) · width + x) · spp + s`. Every sample is computed from its absolute
/// position and sees the triangles in the same order, so the fragments equal the
/// corresponding ones of the whole frame bit for bit.
pub(crate) fn rasterize_rows(
    tris: &[SetupTri],
    cam: &CameraFrame,
    offsets: &[[f32; 2]],
    rows: std::ops::Range<usize>,
) -> Vec<Fragment> {
    let rows = rows.start.min(cam.height as usize)..rows.end.min(cam.height as usize);
    let (w, h, spp) = (cam.width as usize, rows.len(), offsets.len());
    if w * h * spp == 0 {
        return Vec::new();
    }
    let y0 = rows.start;
    let bands = h.div_ceil(BAND_ROWS);
    let mut bins: Vec<Vec<u32>> = vec![Vec::new(); bands];
    for (i, t) in tris.iter().enumerate() {
        let (ta, tb) = (t.bbox[1] as usize, t.bbox[3] as usize);
        if tb < rows.start || ta >= rows.end {
            continue;
        }
        let first = ta.max(rows.start) - y0;
        let last = tb.min(rows.end - 1) - y0;
        for band in bins
            .iter_mut()
            .take(last / BAND_ROWS + 1)
            .skip(first / BAND_ROWS)
        {
            band.push(i as u32);
        }
    }
    let offs: Vec<[f64; 2]> = offsets.iter().map(|o| [o[0] as f64, o[1] as f64]).collect();
    // Depth pass: the nearest set-up triangle of each sample (its index kept in `tri`).
    let mut frags = vec![Fragment::EMPTY; w * h * spp];
    frags
        .par_chunks_mut(BAND_ROWS * w * spp)
        .zip(bins.par_iter())
        .enumerate()
        .for_each(|(band, (out, bin))| {
            let y_start = y0 + band * BAND_ROWS;
            let y_end = (y_start + BAND_ROWS).min(rows.end);
            for &ti in bin {
                let t = &tris[ti as usize];
                let ya = (t.bbox[1] as usize).max(y_start);
                let yb = (t.bbox[3] as usize).min(y_end - 1);
                for y in ya..=yb {
                    let row = (y - y_start) * w;
                    for (s, o) in offs.iter().enumerate() {
                        let py = y as f64 + o[1];
                        let Some((xa, xb)) = span(t, py, o[0]) else {
                            continue;
                        };
                        let zr = t.z[1] * py + t.z[2];
                        for x in xa..=xb {
                            let iw = (t.z[0] * (x as f64 + o[0]) + zr) as f32;
                            let f = &mut out[(row + x) * spp + s];
                            if iw > f.inv_w {
                                f.inv_w = iw;
                                f.tri = ti;
                            }
                        }
                    }
                }
            }
        });
    // Resolve in place: which item and triangle, and where on it.
    frags
        .par_chunks_mut(w * spp)
        .enumerate()
        .for_each(|(y, row)| {
            let py = (y0 + y) as f64;
            for (x, pixel) in row.chunks_exact_mut(spp).enumerate() {
                for (f, o) in pixel.iter_mut().zip(&offs) {
                    if f.tri == u32::MAX {
                        continue;
                    }
                    let t = &tris[f.tri as usize];
                    let (px, py) = (x as f64 + o[0], py + o[1]);
                    let eval = |p: &[f64; 3]| p[0] * px + p[1] * py + p[2];
                    let inv = 1.0 / eval(&t.z);
                    let b1 = eval(&t.bw[0]) * inv;
                    let b2 = eval(&t.bw[1]) * inv;
                    f.item = t.item;
                    f.tri = t.tri;
                    f.b = [b1.clamp(0.0, 1.0) as f32, b2.clamp(0.0, 1.0) as f32];
                }
            }
        });
    frags
}

/// The pixels `x` whose sample at `(x + ox, py)` lies in triangle `t` (every normalised
/// edge function ≥ -ε), clipped to its bounding box; `None` when there are none.
#[inline]
fn span(t: &SetupTri, py: f64, ox: f64) -> Option<(usize, usize)> {
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    for e in &t.e {
        let r = e[1] * py + e[2];
        if e[0] > 0.0 {
            lo = lo.max((-EDGE_EPS - r) / e[0]);
        } else if e[0] < 0.0 {
            hi = hi.min((-EDGE_EPS - r) / e[0]);
        } else if r < -EDGE_EPS {
            return None;
        }
    }
    let xa = (lo - ox).ceil().max(t.bbox[0] as f64);
    let xb = (hi - ox).floor().min(t.bbox[2] as f64);
    if xa.is_nan() || xb.is_nan() || xa > xb {
        return None;
    }
    Some((xa as usize, xb as usize))
}

/// Position and normal (normalised) of `mesh` at barycentrics `b` on triangle `tri`.
#[inline]
pub(crate) fn position_normal(mesh: &Mesh, tri: u32, b: [f32; 2]) -> (Vec3, Vec3) {
    let [i0, i1, i2] = mesh.indices[tri as usize].map(|i| i as usize);
    let b0 = 1.0 - b[0] - b[1];
    let (p, n) = (&mesh.positions, &mesh.normals);
    let pos = p[i0] * b0 + p[i1] * b[0] + p[i2] * b[1];
    let nrm = (n[i0] * b0 + n[i1] * b[0] + n[i2] * b[1]).normalize_or(n[i0]);
    (pos, nrm)
}

/// Position, normal (normalised) and uv of `mesh` at barycentrics `b` on triangle `tri`.
#[inline]
pub(crate) fn interpolate(mesh: &Mesh, tri: u32, b: [f32; 2]) -> (Vec3, Vec3, glam::Vec2) {
    let (pos, nrm) = position_normal(mesh, tri, b);
    let [i0, i1, i2] = mesh.indices[tri as usize].map(|i| i as usize);
    let b0 = 1.0 - b[0] - b[1];
    let uv = mesh.uvs[i0] * b0 + mesh.uvs[i1] * b[0] + mesh.uvs[i2] * b[1];
    (pos, nrm, uv)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn divider_is_exact() {
        for d in [1u32, 2, 3, 7, 64, 1000, 1024, 4095, 65_537, 1 << 20] {
            let div = Divider::new(d);
            for i in [0u32, 1, d - 1, d, d + 1, 12_345_678, u32::MAX - 1, u32::MAX] {
                assert_eq!(div.div_rem(i), (i / d, i % d), "{i} / {d}");
            }
        }
        let (spp, w) = (Divider::new(4), Divider::new(640));
        assert_eq!(sample_coords((7 * 640 + 5) * 4 + 3, spp, w), (5, 7, 3));
    }

    #[test]
    fn clipping_keeps_the_inside_and_interpolates_barycentrics() {
        let v = |x: f32, b: [f32; 2]| ClipVert {
            v: Vec3::new(x, 0.0, -1.0),
            b,
            d: x,
        };
        let tri = [v(-1.0, [0.0, 0.0]), v(1.0, [1.0, 0.0]), v(1.0, [0.0, 1.0])];
        let mut out = [ClipVert::default(); 8];
        let n = clip_polygon(&tri, &mut out, |c| c.d);
        assert_eq!(n, 4, "one vertex out: a quad");
        assert!(out[..n].iter().all(|c| c.d >= 0.0));
        // The crossing on edge 0 → 1 is halfway: barycentrics (0.5, 0).
        assert!(out[..n].iter().any(|c| c.d == 0.0 && c.b == [0.5, 0.0]));
        assert_eq!(clip_polygon(&tri, &mut out, |c| -c.d - 2.0), 0, "all out");
        assert_eq!(clip_polygon(&tri, &mut out, |c| c.d + 2.0), 3, "all in");
    }

    #[test]
    fn rows_equal_the_rows_of_the_whole_frame() {
        let cam = crate::scene::Camera {
            position: [0.3, 0.4, 3.0],
            target: [0.0, 0.0, 0.0],
            fov_y_deg: 50.0,
            near: 0.05,
        }
        .frame(23, 19);
        let sphere = Mesh::uv_sphere(Vec3::ZERO, 1.0, 24, 12);
        let item = DrawItem::plain(&sphere);
        let offsets = sample_offsets(3);
        let whole = rasterize(&[item], &cam, &offsets);
        assert!(whole.iter().any(Fragment::is_hit) && !whole.iter().all(Fragment::is_hit));
        let tris = setup_all(&[item], &cam);
        let row = 23 * 3;
        for (a, b) in [(0, 19), (0, 1), (5, 14), (18, 19), (7, 30)] {
            let part = rasterize_rows(&tris, &cam, &offsets, a..b);
            let b = b.min(19);
            assert_eq!(part, whole[a * row..b * row], "rows {a}..{b}");
        }
    }

    #[test]
    fn a_depth_tie_keeps_the_first_item() {
        let cam = crate::scene::Camera {
            position: [0.0, 0.0, 3.0],
            target: [0.0, 0.0, 0.0],
            fov_y_deg: 60.0,
            near: 0.05,
        }
        .frame(8, 8);
        let quad = Mesh::parallelogram(
            Vec3::new(-5.0, -5.0, 0.0),
            Vec3::new(10.0, 0.0, 0.0),
            Vec3::new(0.0, 10.0, 0.0),
            [1, 1],
        );
        let item = DrawItem::plain(&quad);
        let frags = rasterize(&[item, item], &cam, &sample_offsets(1));
        assert!(frags.iter().all(|f| f.is_hit() && f.item == 0));
        // Nearer 1/w: the second, closer copy wins.
        let near = quad.displaced(&[Vec3::new(0.0, 0.0, 0.5); 4]);
        let second = DrawItem {
            mesh: &near,
            ..item
        };
        let frags = rasterize(&[item, second], &cam, &sample_offsets(1));
        assert!(
            frags
                .iter()
                .all(|f| f.item == 1 && (f.inv_w - 1.0 / 2.5).abs() < 1e-6)
        );
    }
}
