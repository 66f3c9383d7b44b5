//! The perspective camera: right-handed, y up, looking from `position` at `target`.
//!
//! Screen conventions: pixel `(x, y)` has its top-left corner at `(x, y)` in pixel units
//! (top-left origin, y down); a point at pixel coordinates `(px, py)` has screen uv
//! `(px / width, py / height)`. View space is right-handed with the camera looking down
//! `-z`, `+y` up on the screen and `+x` to the right (the OpenGL convention); the vertical
//! field of view spans the image height and the aspect ratio is `width / height`.

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// Distance of the near clipping plane used when a scene gives none, in metres.
pub const DEFAULT_NEAR: f32 = 0.05;

/// A pinhole camera.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[serde(expecting = "a camera object")]
pub struct Camera {
    /// Eye position in world space, metres.
    pub position: [f32; 3],
    /// The point looked at, world space.
    pub target: [f32; 3],
    /// Vertical field of view in degrees, in (0, 180).
    pub fov_y_deg: f32,
    /// Distance of the near clipping plane in metres (> 0); geometry nearer is clipped.
    pub near: f32,
}

impl Camera {
    /// The camera's orthonormal frame and projection for an image of `width × height`.
    pub fn frame(&self, width: u32, height: u32) -> CameraFrame {
        let origin = Vec3::from(self.position);
        let mut forward = (Vec3::from(self.target) - origin).normalize_or_zero();
        if forward == Vec3::ZERO {
            forward = Vec3::NEG_Z;
        }
        // Up hint +y; when looking straight up or down, screen up is the far (-z) side.
        let hint = if forward.y.abs() > 0.9999 {
            if forward.y < 0.0 {
                Vec3::NEG_Z
            } else {
                Vec3::Z
            }
        } else {
            Vec3::Y
        };
        let right = forward.cross(hint).normalize();
        let up = right.cross(forward);
        let tan_half_y = (self.fov_y_deg.to_radians() * 0.5).tan();
        let aspect = if height == 0 {
            1.0
        } else {
            width as f32 / height as f32
        };
        CameraFrame {
            origin,
            right,
            up,
            forward,
            tan_half_y,
            aspect,
            near: self.near,
            width,
            height,
        }
    }
}

/// A camera resolved for one image size: orthonormal basis and projection constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraFrame {
    /// Eye position.
    pub origin: Vec3,
    /// Unit vector to the right of the screen.
    pub right: Vec3,
    /// Unit vector up the screen.
    pub up: Vec3,
    /// Unit viewing direction.
    pub forward: Vec3,
    /// `tan(fov_y / 2)`.
    pub tan_half_y: f32,
    /// `width / height`.
    pub aspect: f32,
    /// Near-plane distance.
    pub near: f32,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

impl CameraFrame {
    /// A world-space point in view space (camera at the origin looking down `-z`).
    #[inline]
    pub fn to_view(&self, p: Vec3) -> Vec3 {
        let d = p - self.origin;
        Vec3::new(d.dot(self.right), d.dot(self.up), -d.dot(self.forward))
    }

    /// Unit direction of the eye ray through pixel coordinates `(px, py)` (top-left origin).
    #[inline]
    pub fn ray_direction(&self, px: f32, py: f32) -> Vec3 {
        let ndc_x = 2.0 * px / self.width as f32 - 1.0;
        let ndc_y = 1.0 - 2.0 * py / self.height as f32;
        (self.forward
            + self.right * (ndc_x * self.tan_half_y * self.aspect)
            + self.up * (ndc_y * self.tan_half_y))
            .normalize()
    }

    /// Pixel coordinates `(px, py)` of a view-space point in front of the camera (`z < 0`).
    #[inline]
    pub fn project_view(&self, v: Vec3) -> (f64, f64) {
        let w = -(v.z as f64);
        let sx = v.x as f64 / (w * (self.tan_half_y * self.aspect) as f64);
        let sy = v.y as f64 / (w * self.tan_half_y as f64);
        (
            (0.5 + 0.5 * sx) * self.width as f64,
            (0.5 - 0.5 * sy) * self.height as f64,
        )
    }

    /// Pixel coordinates of a world-space point, or `None` behind the near plane.
    pub fn project(&self, p: Vec3) -> Option<(f64, f64)> {
        let v = self.to_view(p);
        (-v.z >= self.near).then(|| self.project_view(v))
    }
}
