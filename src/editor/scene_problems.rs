//! The Problems list's entries for the graph's scene (issue 37): a scene file or an
//! environment image that the editor does not read (outside the graph's folder, missing,
//! not a regular file, or a scene that does not parse) is a Problem with the path and why,
//! where it used to fall back to the default room in silence.

use crate::io::PathPolicy;
use crate::scene::{Environment, Scene};
use std::path::{Path, PathBuf};

/// What the preview shows instead of a scene it does not read.
const INSTEAD: &str = "the preview shows the ball instead";

/// The problems of a graph's `scene` (its document's field), its paths taken from `file`
/// (none for an untitled graph, whose relative paths cannot be resolved yet). Checked again
/// at most every two seconds per scene (a file moved into place clears its problem), so
/// the list costs no file access on most frames.
pub fn scene_problems(scene: Option<&serde_json::Value>, file: Option<&Path>) -> Vec<String> {
    static CHECKED: crate::memo::Memo<(PathBuf, String, u64), Vec<String>, 4> =
        crate::memo::Memo::new();
    let (Some(file), Some(scene)) = (file, scene) else {
        return Vec::new();
    };
    let tick = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs() / 2);
    CHECKED.get_or((file.to_owned(), scene.to_string(), tick), || {
        check(scene, file)
    })
}

/// [`scene_problems`] without the memo.
fn check(scene: &serde_json::Value, file: &Path) -> Vec<String> {
    let policy = PathPolicy::InsideGraphFolder;
    let (scene, base) = match scene {
        serde_json::Value::String(name) if Scene::preset(name).is_some() => return Vec::new(),
        serde_json::Value::String(name) => {
            match crate::io::open_reference(file, "scene", name, policy) {
                Err(e) => return vec![format!("{e} ({INSTEAD})")],
                Ok(opened) => {
                    let parsed = crate::io::read_opened_text(&opened.path, &opened.file)
                        .map_err(|e| e.to_string())
                        .and_then(|text| Scene::from_json(&text).map_err(|e| e.to_string()));
                    match parsed {
                        Ok(s) => (s, opened.path),
                        Err(e) => {
                            return vec![format!(
                                "{}: scene: {e} ({INSTEAD})",
                                opened.path.display()
                            )];
                        }
                    }
                }
            }
        }
        value => match Scene::from_json(&value.to_string()) {
            Ok(s) => (s, file.to_owned()),
            Err(e) => return vec![format!("{}: scene: {e} ({INSTEAD})", file.display())],
        },
    };
    let Environment::Image(img) = &scene.environment else {
        return Vec::new();
    };
    match crate::io::resolve_reference(&base, "environment image", &img.path, policy) {
        Ok(_) => Vec::new(),
        Err(e) => vec![format!(
            "{} (the preview shows the default room instead)",
            e.message_for(file)
        )],
    }
}
