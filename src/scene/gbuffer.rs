//! The G-buffer of the material surface: which samples of the frame see it, the geometry
//! attributes a graph reads there, and what is seen everywhere without it.

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use super::Scene;
use super::camera::CameraFrame;
use super::columns::light_at;
use super::environment::EnvLookup;
use super::image::SceneImage;
use super::mesh::Mesh;
use super::objects::Geometry;
use super::objects::Shape;
use super::raster::{
    Divider, DrawItem, Fragment, SetupTri, interpolate, rasterize_rows, sample_coords,
    sample_offsets, setup_all,
};
use super::shade::{Prepared, Shading, shade_frame};
use crate::exec::SampleBatch;
use crate::node::Attribute;

/// The screen-space derivatives `(∂uv/∂x, ∂uv/∂y)` of the uv of triangle `tri` of `mesh` at
/// pixel `(x, y)`, and `(∂P/∂x, ∂P/∂y)` of its position, per pixel (x to the right, y downwards; see [`Attribute::UvDx`]), as a
/// fragment shader's fine derivatives `dpdxFine(uv)`, `dpdyFine(uv)` give them: the 2 × 2
/// quad's differences between pixel centres, `uv(x₁ + ½, y + ½) − uv(x₀ + ½, y + ½)` with
/// `x₀ = x & !1`, `x₁ = x₀ + 1` (and likewise down the column), the uv taken on the plane of
/// the triangle (a GPU's helper invocations extrapolate the triangle's attributes the same
/// way), in f64.
///
/// The ray through pixel coordinates (px, py) is `o + s·D` with
/// `D = forward + right·(2px/w − 1)·tan(fov/2)·aspect + up·(1 − 2py/h)·tan(fov/2)`; it meets
/// the plane `n·(q − P0) = 0` at `s = n·(P0 − o)/(n·D)` (also behind the eye, `s < 0`: the
/// projective extension that perspective-correct interpolation computes). A point `q` of the
/// plane is `P0 + a·e1 + b·e2` over the edges `e1 = P1 − P0`, `e2 = P2 − P0` (solved with
/// their Gram matrix), with uv `uv0 + a·(uv1 − uv0) + b·(uv2 − uv0)`; the position
/// derivatives are the differences of those points `q`.
///
/// From the camera and the surface rather than from neighbouring G-buffer samples: defined at
/// every sample, also where the neighbour is another object, the sky or off the surface's
/// edge, and independent of the sample pattern; and the quad's differences rather than the
/// exact derivative so that the level a graph picks from them is the one a GPU rasteriser
/// picks from `dpdx`/`dpdy` (they differ at first order, ½·∂²uv/∂x² per pixel, which the
/// alpha test of seed 002 turns into flipped texels). A degenerate triangle, or a pixel ray
/// parallel to its plane, gives zeros.
fn surface_derivatives(
    mesh: &Mesh,
    tri: u32,
    (x, y): (u32, u32),
    cam: &CameraFrame,
) -> Derivatives {
    use glam::{DVec2, DVec3};
    let [i0, i1, i2] = mesh.indices[tri as usize].map(|i| i as usize);
    let at = |i: usize| mesh.positions[i].as_dvec3();
    let (p0, p1, p2) = (at(i0), at(i1), at(i2));
    let (e1, e2) = (p1 - p0, p2 - p0);
    let (du1, du2) = (
        (mesh.uvs[i1] - mesh.uvs[i0]).as_dvec2(),
        (mesh.uvs[i2] - mesh.uvs[i0]).as_dvec2(),
    );
    let n = e1.cross(e2);
    let (g11, g12, g22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let det = g11 * g22 - g12 * g12;
    let o = cam.origin.as_dvec3();
    let (forward, right, up) = (
        cam.forward.as_dvec3(),
        cam.right.as_dvec3(),
        cam.up.as_dvec3(),
    );
    let tan = cam.tan_half_y as f64;
    let (w, h) = (cam.width as f64, cam.height as f64);
    let aspect = cam.aspect as f64;
    // The point of the triangle's plane under pixel coordinates (px, py), and its uv.
    let at_pixel = |px: f64, py: f64| -> Option<(DVec3, DVec2)> {
        let d: DVec3 = forward
            + right * ((2.0 * px / w - 1.0) * tan * aspect)
            + up * ((1.0 - 2.0 * py / h) * tan);
        let nd = n.dot(d);
        if nd == 0.0 || det == 0.0 {
            return None;
        }
        let q = o + d * (n.dot(p0 - o) / nd) - p0;
        let (r1, r2) = (e1.dot(q), e2.dot(q));
        let a = (g22 * r1 - g12 * r2) / det;
        let b = (g11 * r2 - g12 * r1) / det;
        Some((q, du1 * a + du2 * b))
    };
    let (x0, y0) = ((x & !1) as f64 + 0.5, (y & !1) as f64 + 0.5);
    let (xc, yc) = (x as f64 + 0.5, y as f64 + 0.5);
    let diff = |a: Option<(DVec3, DVec2)>, b: Option<(DVec3, DVec2)>| match (a, b) {
        (Some(a), Some(b)) => ((b.0 - a.0).as_vec3(), (b.1 - a.1).as_vec2()),
        _ => (Vec3::ZERO, glam::Vec2::ZERO),
    };
    let (p_dx, uv_dx) = diff(at_pixel(x0, yc), at_pixel(x0 + 1.0, yc));
    let (p_dy, uv_dy) = diff(at_pixel(xc, y0), at_pixel(xc, y0 + 1.0));
    Derivatives {
        uv_dx,
        uv_dy,
        p_dx,
        p_dy,
    }
}

/// A sample's screen-space derivatives (see [`surface_derivatives`]).
struct Derivatives {
    uv_dx: glam::Vec2,
    uv_dy: glam::Vec2,
    p_dx: Vec3,
    p_dy: Vec3,
}

/// Samples per parallel block when filling attribute columns.
const BLOCK: usize = 4096;

thread_local! {
    /// Frames this thread has prepared for the CPU rasteriser.
    static CPU_RASTER_FRAMES: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// How many frames the calling thread has rasterised on the CPU so far (G-buffer frames and
/// scene-texture passes): the proof that `render --gpu` rasterises on the GPU alone.
pub fn cpu_raster_frames() -> usize {
    CPU_RASTER_FRAMES.with(|c| c.get())
}

/// Counts one CPU-rasterised frame of the calling thread.
pub(crate) fn count_cpu_raster_frame() {
    CPU_RASTER_FRAMES.with(|c| c.set(c.get() + 1));
}

/// The material surface's samples of one frame, or of a band of its rows
/// ([`GBufferFrame::rows`]).
///
/// The band holds rows `first_row .. first_row + rows` of a `width × height` frame (the
/// whole frame: `first_row = 0`, `rows = height`): `width × rows × spp` samples, sample `s`
/// of pixel `(x, y)` (top-left origin) at index `((y − first_row) · width + x) · spp + s`,
/// placed by
/// [`sample_offsets`](super::sample_offsets). Every scene object takes part in the depth
/// test, so a sample is in `samples` only where the material surface is the nearest
/// surface; where something stands in front of it (a pole in the water), the sample is left
/// out and `background` holds that object. The final frame is therefore the material's
/// colour at `samples` and `background` elsewhere ([`GBuffer::resolve`]).
#[derive(Clone, Debug, PartialEq)]
pub struct GBuffer {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels (of the whole frame).
    pub height: u32,
    /// The first image row of this band.
    pub first_row: u32,
    /// Rows in this band.
    pub rows: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Indices into the sample grid of the samples where the material surface is nearest,
    /// ascending.
    pub samples: Vec<u32>,
    /// One entry per element of `samples`: `position` (world, m), `normal` (interpolated
    /// vertex normal, unit, out of the surface), `view` (unit, towards the camera), `uv`,
    /// `screen_uv` (`((x + jx) / width, (y + jy) / height)`), `depth` (water: vertical
    /// distance from the point down to the seabed, ≥ 0; ball: 0), `light` and `light_color`
    /// of the scene's first light (with shadows of the non-material objects; `+y` and black
    /// when the scene has no light), `uv_dx` and `uv_dy` (∂uv per pixel along x and y: the
    /// pixel's 2 × 2 quad differences on the triangle's plane, as `dpdxFine`/`dpdyFine`),
    /// `generated` ([`Scene::generated`]), `reflection` (`2 (N · V) N − V`), `window`
    /// (`(screen_uv.x, 1 − screen_uv.y, 0)`), `camera` (the position in the camera's right,
    /// up, forward frame) and `time`.
    pub batch: SampleBatch,
    /// Linear radiance of every sample of the grid with the material surface removed
    /// (built-in shading of the backdrop, seabed and objects, and the environment).
    pub background: Vec<[f32; 3]>,
}

impl GBuffer {
    /// Number of samples in the band's grid, `width · rows · spp`.
    pub fn sample_count(&self) -> usize {
        self.width as usize * self.rows as usize * self.spp as usize
    }

    /// Pixel `(x, y)` (image coordinates) and sample number `s` of grid index `index`.
    pub fn sample_coords(&self, index: u32) -> (u32, u32, u32) {
        let pixel = index / self.spp;
        (
            pixel % self.width,
            self.first_row + pixel / self.width,
            index % self.spp,
        )
    }

    /// The frame: `material[k]` at `samples[k]`, `background` elsewhere, averaged over each
    /// pixel's samples (a box filter).
    ///
    /// # Panics
    /// If `material.len() != samples.len()`.
    pub fn resolve(&self, material: &[[f32; 3]]) -> SceneImage {
        assert_eq!(
            material.len(),
            self.samples.len(),
            "GBuffer::resolve: {} material colours for {} samples",
            material.len(),
            self.samples.len()
        );
        let mut all = self.background.clone();
        for (&i, c) in self.samples.iter().zip(material) {
            all[i as usize] = *c;
        }
        let spp = self.spp as usize;
        let data = all
            .par_chunks(spp.max(1))
            .map(|px| {
                let sum = px.iter().fold(Vec3::ZERO, |a, c| a + Vec3::from(*c));
                (sum / spp as f32).to_array()
            })
            .collect();
        SceneImage {
            width: self.width,
            height: self.rows,
            data,
        }
    }
}

impl Scene {
    /// The G-buffer of `mesh` (the material surface, e.g. [`Scene::material_mesh`] or its
    /// [`Mesh::displaced`] copy) at `width × height` pixels and `spp` samples per pixel,
    /// with the default sky standing in for an image environment (see
    /// [`Scene::gbuffer_with`]).
    ///
    /// # Panics
    /// If `spp` is 0, `width · height · spp` exceeds `u32::MAX`, or `mesh` is not
    /// consistent ([`Mesh::is_consistent`]).
    pub fn gbuffer(&self, mesh: &Mesh, width: u32, height: u32, spp: u32) -> GBuffer {
        self.gbuffer_with(mesh, width, height, spp, None)
    }

    /// [`Scene::gbuffer`] with the caller's lookup of the environment image.
    ///
    /// # Panics
    /// As [`Scene::gbuffer`].
    pub fn gbuffer_with(
        &self,
        mesh: &Mesh,
        width: u32,
        height: u32,
        spp: u32,
        image: Option<&EnvLookup>,
    ) -> GBuffer {
        let total = width as u64 * height as u64 * spp as u64;
        assert!(
            total <= u32::MAX as u64,
            "Scene::gbuffer: {width} × {height} × {spp} samples exceed u32 indices"
        );
        GBufferFrame::new(self, mesh, width, height, spp, image).rows(0..height)
    }
}

/// A frame prepared for G-buffers of bands of its rows: the scene's geometry built, every
/// triangle clipped and set up, the built-in shading prepared, once. A band's G-buffer
/// ([`GBufferFrame::rows`]) equals the same rows of the whole frame's bit for bit, so a
/// frame can be rendered band by band in bounded memory.
pub struct GBufferFrame<'a> {
    scene: &'a Scene,
    mesh: &'a Mesh,
    width: u32,
    height: u32,
    spp: u32,
    geometry: Geometry,
    cam: CameraFrame,
    offsets: Vec<[f32; 2]>,
    back: Vec<SetupTri>,
    front: Vec<SetupTri>,
    shading: Shading<'a>,
    /// Per-vertex MikkTSpace tangents and signs ([`Mesh::tangents`]), when the material reads
    /// the tangent frame ([`GBufferFrame::with_tangents`]).
    tangents: Option<Vec<Vec4>>,
}

impl<'a> GBufferFrame<'a> {
    /// Prepares the frame of `mesh` (the material surface) in `scene` at `width × height`
    /// pixels and `spp` samples per pixel, `image` looking up an image environment.
    ///
    /// # Panics
    /// If `spp` is 0 or `mesh` is not consistent ([`Mesh::is_consistent`]).
    pub fn new(
        scene: &'a Scene,
        mesh: &'a Mesh,
        width: u32,
        height: u32,
        spp: u32,
        image: Option<&'a EnvLookup>,
    ) -> GBufferFrame<'a> {
        assert!(spp >= 1, "Scene::gbuffer: spp must be at least 1");
        count_cpu_raster_frame();
        assert!(
            mesh.is_consistent(),
            "Scene::gbuffer: the material mesh has attribute arrays of different lengths or an index out of range"
        );
        let geometry = scene.geometry();
        let cam = scene.camera.frame(width, height);
        let offsets = sample_offsets(spp);
        let (back, front) = if width == 0 || height == 0 {
            (Vec::new(), Vec::new())
        } else {
            let items: Vec<DrawItem> = geometry
                .objects
                .iter()
                .map(|o| DrawItem::plain(&o.mesh))
                .collect();
            let item = DrawItem::plain(mesh);
            rayon::join(|| setup_all(&items, &cam), || setup_all(&[item], &cam))
        };
        let shading = Shading::new(scene, &geometry, image);
        GBufferFrame {
            scene,
            mesh,
            width,
            height,
            spp,
            geometry,
            cam,
            offsets,
            back,
            front,
            shading,
            tangents: None,
        }
    }

    /// Supplies the `tangent` and `bitangent_sign` attributes from per-vertex `tangents`
    /// (`xyz` tangent, `w` sign: [`Mesh::tangents`] of the undisplaced mesh, as the GPU reads
    /// them): interpolated at each sample and made orthogonal to its normal
    /// ([`super::orthonormal_tangent`]). Without it the batch leaves them to their defaults.
    ///
    /// # Panics
    /// If `tangents` does not have one entry per vertex of the frame's mesh.
    pub fn with_tangents(mut self, tangents: Vec<Vec4>) -> GBufferFrame<'a> {
        assert_eq!(
            tangents.len(),
            self.mesh.positions.len(),
            "one tangent per vertex"
        );
        self.tangents = Some(tangents);
        self
    }

    /// The G-buffer of image rows `rows` (clamped to the image).
    ///
    /// # Panics
    /// If the band has more than `u32::MAX` samples.
    pub fn rows(&self, rows: std::ops::Range<u32>) -> GBuffer {
        let end = rows.end.min(self.height);
        let rows = rows.start.min(end)..end;
        let (width, spp) = (self.width, self.spp);
        let total = width as u64 * rows.len() as u64 * spp as u64;
        assert!(
            total <= u32::MAX as u64,
            "Scene::gbuffer: {width} × {} × {spp} samples exceed u32 indices",
            rows.len()
        );
        let range = rows.start as usize..rows.end as usize;
        let (cam, offsets) = (&self.cam, &self.offsets);
        let (back, front) = rayon::join(
            || rasterize_rows(&self.back, cam, offsets, range.clone()),
            || rasterize_rows(&self.front, cam, offsets, range.clone()),
        );
        let row = (width * spp) as usize;
        let hits: Vec<Vec<u32>> = back
            .par_chunks(row.max(1))
            .zip(front.par_chunks(row.max(1)))
            .enumerate()
            .map(|(y, (b, f))| {
                let base = (y * row) as u32;
                (0..b.len())
                    .filter(|&i| f[i].is_hit() && f[i].inv_w > b[i].inv_w)
                    .map(|i| base + i as u32)
                    .collect()
            })
            .collect();
        let samples = hits.concat();
        let objects: Vec<_> = self.geometry.objects.iter().collect();
        let background = shade_frame(
            &back,
            &objects,
            &self.shading,
            cam,
            offsets,
            false,
            range.start,
        );
        let batch = self.material_batch(&samples, &front, rows.start);
        GBuffer {
            width,
            height: self.height,
            first_row: rows.start,
            rows: rows.len() as u32,
            spp,
            samples,
            batch,
            background,
        }
    }
}

impl GBufferFrame<'_> {
    /// The attribute columns of the material samples of the band starting at `first_row`.
    fn material_batch(&self, samples: &[u32], frags: &[Fragment], first_row: u32) -> SampleBatch {
        let (scene, mesh, cam) = (self.scene, self.mesh, &self.cam);
        let (casters, offsets): (&[Shape], &[[f32; 2]]) = (&self.geometry.casters, &self.offsets);
        let m = samples.len();
        let mut batch = SampleBatch::new(m);
        batch.set_time(scene.time);
        if m == 0 {
            return batch;
        }
        let mut attrs = vec![
            Attribute::Position,
            Attribute::Normal,
            Attribute::View,
            Attribute::Uv,
            Attribute::ScreenUv,
            Attribute::Depth,
            Attribute::Light,
            Attribute::LightColor,
            Attribute::UvDx,
            Attribute::UvDy,
            Attribute::Generated,
            Attribute::Reflection,
            Attribute::Window,
            Attribute::Camera,
            Attribute::PositionDx,
            Attribute::PositionDy,
        ];
        let (tex_center, tex_half) = scene.texture_space();
        let tangents = self.tangents.as_deref();
        if tangents.is_some() {
            attrs.extend([Attribute::Tangent, Attribute::BitangentSign]);
        }
        let mut columns: Vec<Vec<f32>> = attrs
            .iter()
            .map(|a| vec![0.0; a.ty().width() * m])
            .collect();
        // Component slices, then cut into blocks: blocks[b][c] is block b of component c.
        let blocks_n = m.div_ceil(BLOCK);
        let mut blocks: Vec<Vec<&mut [f32]>> = (0..blocks_n).map(|_| Vec::new()).collect();
        for column in &mut columns {
            for component in column.chunks_mut(m) {
                for (b, chunk) in component.chunks_mut(BLOCK).enumerate() {
                    blocks[b].push(chunk);
                }
            }
        }
        let (spp, width) = (Divider::new(offsets.len() as u32), Divider::new(cam.width));
        let (w, h) = (cam.width as f32, cam.height as f32);
        let light = scene.lights.first().map(Prepared::new);
        blocks
            .into_par_iter()
            .enumerate()
            .for_each(|(b, mut cols)| {
                for k in 0..cols[0].len() {
                    let index = samples[b * BLOCK + k];
                    let f = &frags[index as usize];
                    let (p, n, uv) = interpolate(mesh, f.tri, f.b);
                    let view = (cam.origin - p).normalize_or(n);
                    let (x, y, s) = sample_coords(index, spp, width);
                    let y = y + first_row;
                    let o = offsets[s as usize];
                    let dv = surface_derivatives(mesh, f.tri, (x, y), cam);
                    let (uv_dx, uv_dy) = (dv.uv_dx, dv.uv_dy);
                    let su = (x as f32 + o[0]) / w;
                    let sv = (y as f32 + o[1]) / h;
                    let (l, lc) = match &light {
                        Some(light) => light_at(light, casters, p),
                        None => (Vec3::Y, Vec3::ZERO),
                    };
                    let (tangent, sign) = match tangents {
                        Some(t) => tangent_at(mesh, t, f.tri, f.b, n),
                        None => (Vec3::X, 1.0),
                    };
                    let generated = Vec3::splat(0.5) + (p - tex_center) / (2.0 * tex_half);
                    let reflection = 2.0 * n.dot(view) * n - view;
                    let d = p - cam.origin;
                    let camera = Vec3::new(d.dot(cam.right), d.dot(cam.up), d.dot(cam.forward));

                    let values = [
                        p.x,
                        p.y,
                        p.z,
                        n.x,
                        n.y,
                        n.z,
                        view.x,
                        view.y,
                        view.z,
                        uv.x,
                        uv.y,
                        su,
                        sv,
                        scene.water_depth(p),
                        l.x,
                        l.y,
                        l.z,
                        lc.x,
                        lc.y,
                        lc.z,
                        uv_dx.x,
                        uv_dx.y,
                        uv_dy.x,
                        uv_dy.y,
                        generated.x,
                        generated.y,
                        generated.z,
                        reflection.x,
                        reflection.y,
                        reflection.z,
                        su,
                        1.0 - sv,
                        0.0,
                        camera.x,
                        camera.y,
                        camera.z,
                        dv.p_dx.x,
                        dv.p_dx.y,
                        dv.p_dx.z,
                        dv.p_dy.x,
                        dv.p_dy.y,
                        dv.p_dy.z,
                        tangent.x,
                        tangent.y,
                        tangent.z,
                        sign,
                    ];
                    for (col, v) in cols.iter_mut().zip(values) {
                        col[k] = v;
                    }
                }
            });
        for (attr, column) in attrs.into_iter().zip(columns) {
            batch
                .set_planar(attr, column)
                .expect("attribute columns are sized by their type");
        }
        batch
    }
}

/// The tangent frame's `(tangent, sign)` at barycentrics `b` of triangle `tri`: the vertex
/// tangents interpolated as the GPU interpolates its varyings, made orthogonal to the unit
/// normal `n`; the sign of the interpolated `w` (`≥ 0` is +1, as the WGSL's `select`).
fn tangent_at(mesh: &Mesh, tangents: &[Vec4], tri: u32, b: [f32; 2], n: Vec3) -> (Vec3, f32) {
    let [i0, i1, i2] = mesh.indices[tri as usize].map(|i| i as usize);
    let b0 = 1.0 - b[0] - b[1];
    let t = tangents[i0] * b0 + tangents[i1] * b[0] + tangents[i2] * b[1];
    let sign = if t.w >= 0.0 { 1.0 } else { -1.0 };
    (super::orthonormal_tangent(n, t.truncate()), sign)
}
