//! Range checks of a scene's values; errors name the field at fault by its path.

use glam::Vec3;

use super::Scene;
use super::environment::{Environment, SunPosition};
use super::error::SceneError;
use super::kind::{SceneKind, WaterObject};
use super::light::Light;

/// Largest grid or tessellation count accepted along one direction.
const MAX_CELLS: u32 = 4096;

impl Scene {
    /// Checks every value against its range; the error names the first field at fault.
    pub fn validate(&self) -> Result<(), SceneError> {
        let c = &self.camera;
        finite3("camera.position", c.position)?;
        finite3("camera.target", c.target)?;
        if c.position == c.target {
            return Err(SceneError::invalid(
                "camera.target",
                "equals camera.position",
            ));
        }
        range("camera.fov_y_deg", c.fov_y_deg, 0.0, 180.0, false)?;
        positive("camera.near", c.near)?;
        for (i, light) in self.lights.iter().enumerate() {
            let at = |f: &str| format!("lights[{i}].{f}");
            match light {
                Light::Directional(d) => {
                    nonzero(&at("direction"), d.direction)?;
                    color(&at("color"), d.color)?;
                    non_negative(&at("intensity"), d.intensity)?;
                }
                Light::Point(p) => {
                    finite3(&at("position"), p.position)?;
                    color(&at("color"), p.color)?;
                    non_negative(&at("intensity"), p.intensity)?;
                }
            }
        }
        match &self.environment {
            Environment::Sky(s) => {
                color("environment.sky.zenith_color", s.zenith_color)?;
                color("environment.sky.horizon_color", s.horizon_color)?;
                color("environment.sky.ground_color", s.ground_color)?;
                color("environment.sky.sun_color", s.sun_color)?;
                non_negative("environment.sky.sun_intensity", s.sun_intensity)?;
                range(
                    "environment.sky.sun_radius_deg",
                    s.sun_radius_deg,
                    0.0,
                    90.0,
                    true,
                )?;
                non_negative("environment.sky.halo", s.halo)?;
                non_negative("environment.sky.ambient", s.ambient)?;
                match s.sun {
                    SunPosition::FollowLight => {}
                    SunPosition::Direction(d) => nonzero("environment.sky.sun.direction", d)?,
                    SunPosition::Angles {
                        elevation_deg,
                        azimuth_deg,
                    } => {
                        range(
                            "environment.sky.sun.angles.elevation_deg",
                            elevation_deg,
                            -90.0,
                            90.0,
                            true,
                        )?;
                        finite("environment.sky.sun.angles.azimuth_deg", azimuth_deg)?;
                    }
                }
            }
            Environment::Image(img) => {
                non_negative("environment.image.intensity", img.intensity)?;
                finite("environment.image.rotation_deg", img.rotation_deg)?;
                if img.color_space == Some(crate::color_space::ColorSpace::Data) {
                    return Err(SceneError::invalid(
                        "environment.image.color_space",
                        "\"data\" is not colour: an environment is radiance; use \"linear\" or \"srgb\"",
                    ));
                }
            }
        }
        finite("time", self.time)?;
        match &self.kind {
            SceneKind::Ball(b) => {
                finite3("kind.ball.center", b.center)?;
                positive("kind.ball.radius", b.radius)?;
                count("kind.ball.segments[0]", b.segments[0], 3)?;
                count("kind.ball.segments[1]", b.segments[1], 2)?;
                let d = &b.backdrop;
                finite("kind.ball.backdrop.floor_y", d.floor_y)?;
                finite("kind.ball.backdrop.wall_z", d.wall_z)?;
                positive("kind.ball.backdrop.width", d.width)?;
                positive("kind.ball.backdrop.wall_height", d.wall_height)?;
                positive("kind.ball.backdrop.floor_depth", d.floor_depth)?;
                positive("kind.ball.backdrop.checker_size", d.checker_size)?;
                color("kind.ball.backdrop.colors[0]", d.colors[0])?;
                color("kind.ball.backdrop.colors[1]", d.colors[1])?;
            }
            SceneKind::Bubble(b) => {
                finite3("kind.bubble.start", b.start)?;
                finite3("kind.bubble.target", b.target)?;
                non_negative("kind.bubble.rate", b.rate)?;
                positive("kind.bubble.radius", b.radius)?;
                count("kind.bubble.segments[0]", b.segments[0], 3)?;
                count("kind.bubble.segments[1]", b.segments[1], 2)?;
                let d = &b.backdrop;
                finite("kind.bubble.backdrop.z", d.z)?;
                positive("kind.bubble.backdrop.size[0]", d.size[0])?;
                positive("kind.bubble.backdrop.size[1]", d.size[1])?;
                non_negative("kind.bubble.backdrop.intensity_a", d.intensity_a)?;
                non_negative("kind.bubble.backdrop.intensity_b", d.intensity_b)?;
                range("kind.bubble.backdrop.mix", d.mix, 0.0, 1.0, true)?;
                range("kind.bubble.backdrop.amount", d.amount, 0.0, 1.0, true)?;
                positive("kind.bubble.backdrop.tiles", d.tiles)?;
                for (k, v) in [d.velocity_a, d.velocity_b].iter().enumerate() {
                    let name = ["velocity_a", "velocity_b"][k];
                    finite(&format!("kind.bubble.backdrop.{name}[0]"), v[0])?;
                    finite(&format!("kind.bubble.backdrop.{name}[1]"), v[1])?;
                }
                nonzero("kind.bubble.backdrop.light", d.light)?;
                color("kind.bubble.backdrop.tint", d.tint)?;
                non_negative("kind.bubble.backdrop.strength", d.strength)?;
                non_negative("kind.bubble.backdrop.sharpness", d.sharpness)?;
                range("kind.bubble.backdrop.opacity", d.opacity, 0.0, 1.0, true)?;
            }
            SceneKind::Water(w) => {
                positive("kind.water.size[0]", w.size[0])?;
                positive("kind.water.size[1]", w.size[1])?;
                count("kind.water.grid[0]", w.grid[0], 1)?;
                count("kind.water.grid[1]", w.grid[1], 1)?;
                let s = &w.seabed;
                non_negative("kind.water.seabed.depth_min", s.depth_min)?;
                finite("kind.water.seabed.depth_max", s.depth_max)?;
                if s.depth_max < s.depth_min {
                    return Err(SceneError::invalid(
                        "kind.water.seabed.depth_max",
                        format!("{} is less than depth_min {}", s.depth_max, s.depth_min),
                    ));
                }
                range("kind.water.seabed.slope", s.slope, 0.0, 1.0, true)?;
                count("kind.water.seabed.grid[0]", s.grid[0], 1)?;
                count("kind.water.seabed.grid[1]", s.grid[1], 1)?;
                color("kind.water.seabed.color", s.color)?;
                if let Some(lod) = &w.lod {
                    range("kind.water.lod.levels", lod.levels as f32, 0.0, 10.0, true)?;
                    range("kind.water.lod.block", lod.block as f32, 1.0, 64.0, true)?;
                    positive("kind.water.lod.split_distance", lod.split_distance)?;
                }
                if let Some(r) = &w.refraction {
                    positive("kind.water.refraction.ior_air", r.ior_air)?;
                    positive("kind.water.refraction.ior_water", r.ior_water)?;
                }
                for (i, obj) in w.objects.iter().enumerate() {
                    let at = |f: &str| format!("kind.water.objects[{i}].{f}");
                    match obj {
                        WaterObject::Box(b) => {
                            finite3(&at("center"), b.center)?;
                            for k in 0..3 {
                                positive(&at(&format!("size[{k}]")), b.size[k])?;
                            }
                            color(&at("color"), b.color)?;
                        }
                        WaterObject::Sphere(s) => {
                            finite3(&at("center"), s.center)?;
                            positive(&at("radius"), s.radius)?;
                            color(&at("color"), s.color)?;
                        }
                        WaterObject::Pole(p) => {
                            finite(&at("base[0]"), p.base[0])?;
                            finite(&at("base[1]"), p.base[1])?;
                            finite(&at("bottom"), p.bottom)?;
                            finite(&at("top"), p.top)?;
                            if p.top <= p.bottom {
                                return Err(SceneError::invalid(
                                    at("top"),
                                    format!("{} is not above bottom {}", p.top, p.bottom),
                                ));
                            }
                            positive(&at("radius"), p.radius)?;
                            color(&at("color"), p.color)?;
                        }
                    }
                }
            }
        }
        Ok(())
    }
}

fn finite(field: &str, v: f32) -> Result<(), SceneError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(SceneError::invalid(
            field,
            format!("{v} is not a finite number"),
        ))
    }
}

fn finite3(field: &str, v: [f32; 3]) -> Result<(), SceneError> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(())
    } else {
        Err(SceneError::invalid(
            field,
            format!("{v:?} has a component that is not finite"),
        ))
    }
}

fn nonzero(field: &str, v: [f32; 3]) -> Result<(), SceneError> {
    finite3(field, v)?;
    if Vec3::from(v).length_squared() > 0.0 {
        Ok(())
    } else {
        Err(SceneError::invalid(
            field,
            "is the zero vector; a direction is needed",
        ))
    }
}

fn color(field: &str, v: [f32; 3]) -> Result<(), SceneError> {
    finite3(field, v)?;
    if v.iter().all(|c| *c >= 0.0) {
        Ok(())
    } else {
        Err(SceneError::invalid(
            field,
            format!("{v:?} has a negative component"),
        ))
    }
}

fn positive(field: &str, v: f32) -> Result<(), SceneError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(SceneError::invalid(
            field,
            format!("{v} must be a finite number > 0"),
        ))
    }
}

fn non_negative(field: &str, v: f32) -> Result<(), SceneError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(SceneError::invalid(
            field,
            format!("{v} must be a finite number ≥ 0"),
        ))
    }
}

fn range(field: &str, v: f32, lo: f32, hi: f32, inclusive: bool) -> Result<(), SceneError> {
    let ok = if inclusive {
        v >= lo && v <= hi
    } else {
        v > lo && v < hi
    };
    if ok {
        Ok(())
    } else {
        let (a, b) = if inclusive { ('[', ']') } else { ('(', ')') };
        Err(SceneError::invalid(
            field,
            format!("{v} is outside {a}{lo}, {hi}{b}"),
        ))
    }
}

fn count(field: &str, v: u32, min: u32) -> Result<(), SceneError> {
    if (min..=MAX_CELLS).contains(&v) {
        Ok(())
    } else {
        Err(SceneError::invalid(
            field,
            format!("{v} is outside {min}..={MAX_CELLS}"),
        ))
    }
}
