//! Errors of scene loading and validation.

use thiserror::Error;

/// An error in a scene description: where in the JSON, or which field is at fault.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum SceneError {
    /// The text is not valid JSON, or does not match the scene format (an unknown field, a
    /// wrong type, an unknown preset name).
    #[error("scene JSON at line {line}, column {column}: {message}")]
    Json {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong, without the location.
        message: String,
    },
    /// A value is outside its allowed range (named by its path, e.g. `camera.fov_y_deg`).
    #[error("scene field `{field}`: {message}")]
    Invalid {
        /// Dotted path of the field, e.g. `water.seabed.depth_max` or `lights[1].intensity`.
        field: String,
        /// What is wrong with it.
        message: String,
    },
}

impl SceneError {
    /// An [`SceneError::Invalid`] for `field`.
    pub(crate) fn invalid(field: impl Into<String>, message: impl Into<String>) -> SceneError {
        SceneError::Invalid {
            field: field.into(),
            message: message.into(),
        }
    }

    /// A [`SceneError::Json`] from serde_json's error, with the location split off.
    pub(crate) fn from_json_error(e: &serde_json::Error) -> SceneError {
        let text = e.to_string();
        let suffix = format!(" at line {} column {}", e.line(), e.column());
        let message = text.strip_suffix(&suffix).unwrap_or(&text).to_string();
        SceneError::Json {
            line: e.line(),
            column: e.column(),
            message,
        }
    }
}
