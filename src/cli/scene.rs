//! The scene a graph is rendered (or evaluated) in, and its environment image, with every
//! path the graph names confined to its folder.

use super::path_message;
use matgraph::io::{PathError, PathPolicy};
use matgraph::scene::{Environment, SCENE_PRESETS, Scene};
use matgraph::texture::Texture;
use matgraph::{Graph, image_io};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A scene file's text parsed; messages name the file.
fn scene_file(path: &Path) -> Result<Scene, String> {
    let text = matgraph::io::read_text(path).map_err(|e| e.to_string())?;
    scene_text(path, &text)
}

/// A scene's text (read from `path`) parsed; messages name the file.
fn scene_text(path: &Path, text: &str) -> Result<Scene, String> {
    Scene::from_json(text).map_err(|e| format!("{}: {e}", path.display()))
}

/// The scene named by `--scene` on the command line: a preset name or a scene file (the
/// user's own choice, so not confined).
pub fn forced_scene(spec: &str) -> Result<Scene, String> {
    if let Some(scene) = Scene::preset(spec) {
        return Ok(scene);
    }
    let path = Path::new(spec);
    if std::fs::symlink_metadata(path).is_err() {
        return Err(format!(
            "--scene {spec}: not a preset ({}) nor a file",
            SCENE_PRESETS.join(", ")
        ));
    }
    scene_file(path)
}

/// The message of a path error, with the flag's hint when the path is outside.
fn path_error(e: PathError) -> String {
    let outside = matches!(e, PathError::Outside { .. });
    path_message(e, outside)
}

/// The scene of `graph` (read from `file`): `forced` (from `--scene SPEC`) when given, else
/// the scene the graph names (a preset, an inline scene or a scene file inside the graph's
/// folder), else the ball; and its environment image, resolved inside the folder of the
/// file that names it. Each file is opened once and checked against `policy` as opened
/// ([`matgraph::io::open_reference`]), then read from that handle; the environment image is
/// reserved in `budget` before it is decoded.
pub fn resolve(
    graph: &Graph,
    file: &Path,
    forced: Option<(&str, &Scene)>,
    policy: PathPolicy,
    budget: &matgraph::budget::MemoryBudget,
) -> Result<(Scene, Option<Arc<Texture>>), String> {
    let (scene, base): (Scene, PathBuf) = match (forced, &graph.scene) {
        (Some((spec, s)), _) => (s.clone(), PathBuf::from(spec)),
        (None, Some(serde_json::Value::String(name))) if Scene::preset(name).is_none() => {
            let opened =
                matgraph::io::open_reference(file, "scene", name, policy).map_err(path_error)?;
            let scene = matgraph::io::read_opened_text(&opened.path, &opened.file)
                .map_err(|e| e.to_string())
                .and_then(|text| scene_text(&opened.path, &text))
                .map_err(|e| format!("{}: scene: {e}", file.display()))?;
            (scene, opened.path)
        }
        (None, _) => (
            matgraph::render::graph_scene(graph)
                .map_err(|e| format!("{}: scene: {e}", file.display()))?
                .unwrap_or_else(|| Scene::preset("ball").expect("the ball preset exists")),
            file.to_owned(),
        ),
    };
    let Environment::Image(img) = &scene.environment else {
        return Ok((scene, None));
    };
    let opened = matgraph::io::open_reference(&base, "environment image", &img.path, policy)
        .map_err(|e| {
            // Named by a scene file: said of the scene's folder, not the graph's (issue 37).
            let outside = matches!(e, PathError::Outside { .. });
            path_message(e.message_for(file), outside)
        })?;
    let texture = image_io::load_opened_texture(vec![opened], false, img.color_space, budget)
        .map_err(|e| format!("{}: environment: {e}", file.display()))?;
    Ok((scene, Some(Arc::new(texture))))
}
