//! The scene textures the shading papers read, rendered from the scene's camera at one
//! sample per pixel (the pixel centre), linear RGB:
//!
//! - `background`: the frame without the material surface (what a bubble lets through);
//! - `refraction`: for water, the seabed and the submerged parts of objects seen straight
//!   from the camera with the water surface removed (no bending: a graph distorts the
//!   lookup itself), or with the water setup's `refraction` through the flat water plane by
//!   Snell's law ([`super::snell`]), with built-in sandy Lambert shading and no depth tint (seed 004's graph
//!   applies its depth colour `exp(-sqrt(k·depth))` itself); the environment where nothing
//!   is hit;
//! - `reflection`: for water, the parts of objects above the water and the sky, seen from
//!   the camera mirrored about the water plane `y = 0` and stored so that it is read at
//!   the same screen uv as the water pixel (a planar reflection, rendered by drawing the
//!   mirrored geometry clipped to the water plane, as with the stencil-buffer technique of
//!   Kilgard, "Improving shadows and reflections via the stencil buffer", NVIDIA 1999:
//!   exact for the flat plane, an approximation for a displaced one);
//! - for the ball and the bubble, `refraction` and `reflection` are copies of `background`.

use super::Scene;
use super::environment::EnvLookup;
use super::image::SceneImage;
use super::kind::SceneKind;
use super::mesh::Mesh;
use super::objects::{ABOVE_WATER, BELOW_WATER, Object};
use super::raster::{DrawItem, rasterize, sample_offsets};
use super::shade::{Shading, shade_frame};
use super::snell::apparent_mesh;

/// The textures of [`Scene::scene_textures`].
#[derive(Clone, Debug, PartialEq)]
pub struct SceneTextures {
    /// The frame without the material surface.
    pub background: SceneImage,
    /// What lies under the water (water scene), else the background.
    pub refraction: SceneImage,
    /// The planar reflection in the water (water scene), else the background.
    pub reflection: SceneImage,
}

impl Scene {
    /// The inverse view depth (`1/w`, w the distance along the camera's forward axis) of
    /// the nearest surface of the scene without the material, at each pixel centre of a
    /// `width × height` frame, rows from the top; 0 where nothing is hit. What hides the
    /// material: the renderer draws it against these surfaces, and an app draws them into
    /// its depth buffer first.
    pub fn background_inv_depth(&self, width: u32, height: u32) -> Vec<f32> {
        let geometry = self.geometry();
        let cam = self.camera.frame(width, height);
        let items: Vec<DrawItem> = geometry
            .objects
            .iter()
            .map(|o| DrawItem::plain(&o.mesh))
            .collect();
        rasterize(&items, &cam, &sample_offsets(1))
            .iter()
            .map(|f| f.inv_w)
            .collect()
    }

    /// The scene textures at `width × height`, with the default sky standing in for an
    /// image environment (see [`Scene::scene_textures_with`]).
    pub fn scene_textures(&self, width: u32, height: u32) -> SceneTextures {
        self.scene_textures_with(width, height, None)
    }

    /// [`Scene::scene_textures`] with the caller's lookup of the environment image.
    pub fn scene_textures_with(
        &self,
        width: u32,
        height: u32,
        image: Option<&EnvLookup>,
    ) -> SceneTextures {
        super::gbuffer::count_cpu_raster_frame();
        let geometry = self.geometry();
        let shading = Shading::new(self, &geometry, image);
        let cam = self.camera.frame(width, height);
        let offsets = sample_offsets(1);
        // `drawn`: meshes drawn in place of the objects' own (the Snell view), which are
        // still the ones shaded.
        let pass_drawn = |objects: Vec<&Object>, drawn: Option<&[Mesh]>, mirror: bool, clip| {
            let items: Vec<DrawItem> = objects
                .iter()
                .enumerate()
                .map(|(k, o)| DrawItem {
                    mesh: drawn.map_or(&o.mesh, |d| &d[k]),
                    mirror_y: mirror,
                    clip,
                })
                .collect();
            let frags = rasterize(&items, &cam, &offsets);
            SceneImage {
                width,
                height,
                data: shade_frame(&frags, &objects, &shading, &cam, &offsets, mirror, 0),
            }
        };
        let pass =
            |objects: Vec<&Object>, mirror: bool, clip| pass_drawn(objects, None, mirror, clip);
        let all: Vec<&Object> = geometry.objects.iter().collect();
        let background = pass(all.clone(), false, None);
        match self.kind {
            SceneKind::Ball(_) | SceneKind::Bubble(_) => SceneTextures {
                refraction: background.clone(),
                reflection: background.clone(),
                background,
            },
            SceneKind::Water(ref water) => {
                let above: Vec<&Object> = all.iter().copied().filter(|o| !o.underwater).collect();
                let snell: Option<Vec<Mesh>> = water.refraction.as_ref().map(|s| {
                    let eye = glam::Vec3::from(self.camera.position);
                    all.iter()
                        .map(|o| apparent_mesh(&o.mesh, eye, s.ior_air, s.ior_water))
                        .collect()
                });
                let (refraction, reflection) = rayon::join(
                    || pass_drawn(all.clone(), snell.as_deref(), false, Some(BELOW_WATER)),
                    || pass(above, true, Some(ABOVE_WATER)),
                );
                SceneTextures {
                    background,
                    refraction,
                    reflection,
                }
            }
        }
    }
}
