//! The G-buffer of the material surface: which samples of the frame see it, the geometry
//! attributes a graph reads there, and what is seen everywhere without it.

use glam::Vec3;
use rayon::prelude::*;

use super::Scene;
use super::camera::CameraFrame;
use super::columns::light_at;
use super::environment::EnvLookup;
use super::image::SceneImage;
use super::mesh::Mesh;
use super::objects::Shape;
use super::raster::{
    Divider, DrawItem, Fragment, interpolate, rasterize, sample_coords, sample_offsets,
};
use super::shade::{Prepared, Shading, shade_frame};
use crate::exec::SampleBatch;
use crate::node::Attribute;

/// Samples per parallel block when filling attribute columns.
const BLOCK: usize = 4096;

/// The material surface's samples of one frame.
///
/// The frame has `width × height × spp` samples, sample `s` of pixel `(x, y)` (top-left
/// origin) at index `(y · width + x) · spp + s`, placed by
/// [`sample_offsets`](super::sample_offsets). Every scene object takes part in the depth
/// test, so a sample is in `samples` only where the material surface is the nearest
/// surface; where something stands in front of it (a pole in the water), the sample is left
/// out and `background` holds that object. The final frame is therefore the material's
/// colour at `samples` and `background` elsewhere ([`GBuffer::resolve`]).
#[derive(Clone, Debug, PartialEq)]
pub struct GBuffer {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
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
    /// when the scene has no light) and `time`.
    pub batch: SampleBatch,
    /// Linear radiance of every sample of the grid with the material surface removed
    /// (built-in shading of the backdrop, seabed and objects, and the environment).
    pub background: Vec<[f32; 3]>,
}

impl GBuffer {
    /// Number of samples in the full grid, `width · height · spp`.
    pub fn sample_count(&self) -> usize {
        self.width as usize * self.height as usize * self.spp as usize
    }

    /// Pixel `(x, y)` and sample number `s` of grid index `index`.
    pub fn sample_coords(&self, index: u32) -> (u32, u32, u32) {
        let pixel = index / self.spp;
        (pixel % self.width, pixel / self.width, index % self.spp)
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
            height: self.height,
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
        assert!(spp >= 1, "Scene::gbuffer: spp must be at least 1");
        let total = width as u64 * height as u64 * spp as u64;
        assert!(
            total <= u32::MAX as u64,
            "Scene::gbuffer: {width} × {height} × {spp} samples exceed u32 indices"
        );
        assert!(
            mesh.is_consistent(),
            "Scene::gbuffer: the material mesh has attribute arrays of different lengths or an index out of range"
        );
        let geometry = self.geometry();
        let cam = self.camera.frame(width, height);
        let offsets = sample_offsets(spp);
        let objects: Vec<_> = geometry.objects.iter().collect();
        let items: Vec<DrawItem> = objects
            .iter()
            .map(|o| DrawItem {
                mesh: &o.mesh,
                mirror_y: false,
                clip: None,
            })
            .collect();
        let (back, front) = rayon::join(
            || rasterize(&items, &cam, &offsets),
            || {
                let item = DrawItem {
                    mesh,
                    mirror_y: false,
                    clip: None,
                };
                rasterize(&[item], &cam, &offsets)
            },
        );
        let row = (width * spp) as usize;
        let rows: Vec<Vec<u32>> = back
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
        let samples = rows.concat();
        let shading = Shading::new(self, &geometry, image);
        let background = shade_frame(&back, &objects, &shading, &cam, &offsets, false);
        let batch = self.material_batch(mesh, &samples, &front, &geometry.casters, &cam, &offsets);
        GBuffer {
            width,
            height,
            spp,
            samples,
            batch,
            background,
        }
    }

    /// The attribute columns of the material samples.
    fn material_batch(
        &self,
        mesh: &Mesh,
        samples: &[u32],
        frags: &[Fragment],
        casters: &[Shape],
        cam: &CameraFrame,
        offsets: &[[f32; 2]],
    ) -> SampleBatch {
        let m = samples.len();
        let mut batch = SampleBatch::new(m);
        batch.set_time(self.time);
        if m == 0 {
            return batch;
        }
        let attrs = [
            Attribute::Position,
            Attribute::Normal,
            Attribute::View,
            Attribute::Uv,
            Attribute::ScreenUv,
            Attribute::Depth,
            Attribute::Light,
            Attribute::LightColor,
        ];
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
        let light = self.lights.first().map(Prepared::new);
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
                    let o = offsets[s as usize];
                    let su = (x as f32 + o[0]) / w;
                    let sv = (y as f32 + o[1]) / h;
                    let (l, lc) = match &light {
                        Some(light) => light_at(light, casters, p),
                        None => (Vec3::Y, Vec3::ZERO),
                    };
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
                        self.water_depth(p),
                        l.x,
                        l.y,
                        l.z,
                        lc.x,
                        lc.y,
                        lc.z,
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
