//! The scene file format: parsing with located errors, kind-dependent defaults, and
//! deterministic saving.

use serde::Deserialize;

use super::Scene;
use super::environment::Environment;
use super::error::SceneError;
use super::kind::SceneKind;
use super::light::Light;

/// How a scene is written in JSON: kind-dependent defaults are filled in afterwards.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
#[serde(expecting = "a scene object { \"kind\", \"camera\", \"lights\", … }")]
pub(crate) struct SceneDoc {
    #[serde(default)]
    kind: SceneKind,
    #[serde(default)]
    camera: CameraDoc,
    lights: Option<Vec<Light>>,
    environment: Option<Environment>,
    #[serde(default)]
    time: f32,
}

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
#[serde(expecting = "a camera object { \"position\", \"target\", … }")]
struct CameraDoc {
    position: Option<[f32; 3]>,
    target: Option<[f32; 3]>,
    fov_y_deg: Option<f32>,
    near: Option<f32>,
}

impl From<SceneDoc> for Scene {
    fn from(doc: SceneDoc) -> Scene {
        let mut scene = Scene::for_kind(doc.kind);
        let c = doc.camera;
        let cam = &mut scene.camera;
        cam.position = c.position.unwrap_or(cam.position);
        cam.target = c.target.unwrap_or(cam.target);
        cam.fov_y_deg = c.fov_y_deg.unwrap_or(cam.fov_y_deg);
        cam.near = c.near.unwrap_or(cam.near);
        if let Some(lights) = doc.lights {
            scene.lights = lights;
        }
        if let Some(env) = doc.environment {
            scene.environment = env;
        }
        scene.time = doc.time;
        scene
    }
}

impl Scene {
    /// Parses a scene file's text (see the module docs) and validates it. Errors give the
    /// line and column, or name the field out of range.
    pub fn from_json(text: &str) -> Result<Scene, SceneError> {
        let scene: Scene =
            serde_json::from_str(text).map_err(|e| SceneError::from_json_error(&e))?;
        scene.validate()?;
        Ok(scene)
    }

    /// The scene as JSON with every field written, in the project's pretty form
    /// ([`crate::pretty`]) with floats in their shortest `f32` decimals; the same scene
    /// gives the same bytes, and [`Scene::from_json`] reads it back equal.
    pub fn to_json(&self) -> String {
        // Compact serialisation writes f32s in their shortest form; reading that text back
        // as f64s keeps those decimals for the printer.
        let compact = serde_json::to_string(self).expect("a scene serialises to JSON");
        let value: serde_json::Value =
            serde_json::from_str(&compact).expect("serde_json reads its own output");
        crate::pretty::to_string(&value)
    }
}
