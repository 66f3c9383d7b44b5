//! The per-draw uniform `MgFrame` and the lights buffer `array<MgLight>` of the render
//! entries, as bytes.

use crate::wgsl::render::{FRAME_SIZE, LIGHT_DIRECTIONAL, LIGHT_POINT, LIGHT_STRIDE};
use glam::{Mat4, Vec3};

/// What `mg_frame` (group 0, binding 1) holds: the camera, the object transform and the
/// viewport. World space is right-handed, y up, in metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// World → clip (projection × view), wgpu's clip space (z in [0, 1]).
    pub view_proj: Mat4,
    /// Object → world for the vertex positions (identity for world-space meshes).
    pub model: Mat4,
    /// The eye's world position (V points from the surface towards it).
    pub camera_position: Vec3,
    /// Render target size in pixels: `screen_uv = frag_coord.xy / viewport`.
    pub viewport: [f32; 2],
}

impl Frame {
    /// The 224 bytes of `MgFrame`: `view_proj` at 0, `model` at 64, `normal_model` (the
    /// inverse transpose of `model`) at 128, `camera_position` at 192, `light_count` at 204,
    /// `viewport` at 208, zeros to 224. Matrices column-major, as WGSL reads them.
    pub fn bytes(&self, light_count: u32) -> Vec<u8> {
        let mut b = Vec::with_capacity(FRAME_SIZE as usize);
        let normal = self.model.inverse().transpose();
        for m in [self.view_proj, self.model, normal] {
            b.extend(m.to_cols_array().iter().flat_map(|x| x.to_le_bytes()));
        }
        b.extend(
            self.camera_position
                .to_array()
                .iter()
                .flat_map(|x| x.to_le_bytes()),
        );
        b.extend(light_count.to_le_bytes());
        b.extend(self.viewport.iter().flat_map(|x| x.to_le_bytes()));
        b.resize(FRAME_SIZE as usize, 0);
        b
    }
}

/// One light of the lights buffer (`mg_lights`, group 0, binding 2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// Parallel light: `direction` towards the light (normalised in the shader), `radiance`
    /// arriving from it (linear RGB, colour × intensity).
    Directional {
        /// Direction from the surface towards the light.
        direction: [f32; 3],
        /// Radiance scale, linear RGB.
        radiance: [f32; 3],
    },
    /// Point light at `position`: radiance `radiance / max(d, 1 mm)²` at distance d.
    Point {
        /// World position (m).
        position: [f32; 3],
        /// Radiance scale at 1 m, linear RGB.
        radiance: [f32; 3],
    },
}

impl Light {
    /// A scene light, with its colour × intensity as radiance.
    pub fn from_scene(light: &crate::scene::Light) -> Light {
        let radiance = light.radiance_scale().to_array();
        match light {
            crate::scene::Light::Directional(d) => Light::Directional {
                direction: d.direction,
                radiance,
            },
            crate::scene::Light::Point(p) => Light::Point {
                position: p.position,
                radiance,
            },
        }
    }

    /// The 32 bytes of `MgLight`: `vector` (vec3) at 0, `kind` (u32: 0 directional, 1 point)
    /// at 12, `color` (vec3) at 16, a pad to 32.
    pub fn bytes(&self) -> [u8; LIGHT_STRIDE as usize] {
        let (vector, kind, color) = match *self {
            Light::Directional {
                direction,
                radiance,
            } => (direction, LIGHT_DIRECTIONAL, radiance),
            Light::Point { position, radiance } => (position, LIGHT_POINT, radiance),
        };
        let mut b = [0u8; LIGHT_STRIDE as usize];
        for (k, x) in vector.iter().enumerate() {
            b[4 * k..4 * k + 4].copy_from_slice(&x.to_le_bytes());
        }
        b[12..16].copy_from_slice(&kind.to_le_bytes());
        for (k, x) in color.iter().enumerate() {
            b[16 + 4 * k..20 + 4 * k].copy_from_slice(&x.to_le_bytes());
        }
        b
    }
}

/// The bytes of the lights buffer: one record per light, and one zero record when there are
/// none (a binding cannot be empty; `light_count` 0 then keeps the loop from reading it).
pub fn lights_bytes(lights: &[Light]) -> Vec<u8> {
    let mut b: Vec<u8> = lights.iter().flat_map(|l| l.bytes()).collect();
    if b.is_empty() {
        b.resize(LIGHT_STRIDE as usize, 0);
    }
    b
}
