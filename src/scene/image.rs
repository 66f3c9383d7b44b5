//! Linear RGB images at render resolution: the scene textures and resolved frames.

use glam::{Vec2, Vec3};

/// A linear RGB image, row-major with the top-left pixel first.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width × height` linear RGB radiances, pixel `(x, y)` at `y · width + x`.
    pub data: Vec<[f32; 3]>,
}

impl SceneImage {
    /// The pixel at `(x, y)`.
    ///
    /// # Panics
    /// If `(x, y)` is outside the image.
    pub fn get(&self, x: u32, y: u32) -> [f32; 3] {
        assert!(
            x < self.width && y < self.height,
            "SceneImage::get: ({x}, {y}) outside {}×{}",
            self.width,
            self.height
        );
        self.data[(y * self.width + x) as usize]
    }

    /// Bilinear lookup at screen uv (top-left origin, pixel centres at `(x + 0.5) / width`),
    /// clamped to the edge; black for an empty image.
    pub fn sample(&self, uv: Vec2) -> Vec3 {
        if self.width == 0 || self.height == 0 {
            return Vec3::ZERO;
        }
        let fx = (uv.x * self.width as f32 - 0.5).clamp(0.0, (self.width - 1) as f32);
        let fy = (uv.y * self.height as f32 - 0.5).clamp(0.0, (self.height - 1) as f32);
        let (x0, y0) = (fx.floor() as u32, fy.floor() as u32);
        let (x1, y1) = ((x0 + 1).min(self.width - 1), (y0 + 1).min(self.height - 1));
        let (tx, ty) = (fx - x0 as f32, fy - y0 as f32);
        let at = |x, y| Vec3::from(self.get(x, y));
        let top = at(x0, y0).lerp(at(x1, y0), tx);
        let bottom = at(x0, y1).lerp(at(x1, y1), tx);
        top.lerp(bottom, ty)
    }
}
