//! The scene a graph is rendered (or evaluated) in, and its environment image, with every
//! path the graph names confined to its folder.

use super::path_message;
use matgraph::io::{PathError, PathPolicy};
use matgraph::scene::{Environment, SCENE_PRESETS, Scene};
use matgraph::texture::Texture;
use matgraph::{Graph, image_io};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A scene's text (read from `path`) parsed; messages name the file.
fn scene_text(path: &Path, text: &str) -> Result<Scene, String> {
    Scene::from_json(text).map_err(|e| format!("{}: {e}", path.display()))
}

/// Which of `lights` and `environment` a scene's JSON states (a preset name states
/// neither: its lights and environment are its kind's defaults).
fn stated(value: &serde_json::Value) -> Stated {
    let has = |key: &str| value.as_object().is_some_and(|o| o.contains_key(key));
    Stated {
        lights: has("lights"),
        environment: has("environment"),
    }
}

/// [`stated`] of a scene file's text (already parsed as a scene, so valid JSON).
fn stated_in(text: &str) -> Stated {
    serde_json::from_str(text)
        .map(|v| stated(&v))
        .unwrap_or_default()
}

/// Which of a scene's time-of-day fields its JSON writes out.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stated {
    /// `lights` is written.
    pub lights: bool,
    /// `environment` is written.
    pub environment: bool,
}

/// The scene of `--scene SPEC`, and what its file states.
pub struct Forced {
    /// The scene: the preset, or the file's scene with its kind's defaults filled in.
    pub scene: Scene,
    /// Which of its lights and environment the file writes out (none for a preset).
    pub stated: Stated,
}

/// The scene named by `--scene` on the command line: a preset name or a scene file (the
/// user's own choice, so not confined).
pub fn forced_scene(spec: &str) -> Result<Forced, String> {
    if let Some(scene) = Scene::preset(spec) {
        return Ok(Forced {
            scene,
            stated: Stated::default(),
        });
    }
    let path = Path::new(spec);
    if std::fs::symlink_metadata(path).is_err() {
        return Err(format!(
            "--scene {spec}: not a preset ({}) nor a file",
            SCENE_PRESETS.join(", ")
        ));
    }
    let text = matgraph::io::read_text(path).map_err(|e| e.to_string())?;
    let scene = scene_text(path, &text)?;
    let stated = stated_in(&text);
    Ok(Forced { scene, stated })
}

/// The message of a path error, with the flag's hint when the path is outside.
fn path_error(e: PathError) -> String {
    let outside = matches!(e, PathError::Outside { .. });
    path_message(e, outside)
}

/// The scene `graph` (read from `file`) names itself: a scene file inside the graph's folder,
/// an inline scene, a preset, or none (the ball); the path its environment image is relative
/// to; and which of its lights and environment it writes out.
fn own_scene(
    graph: &Graph,
    file: &Path,
    policy: PathPolicy,
) -> Result<(Scene, PathBuf, Stated), String> {
    match &graph.scene {
        Some(serde_json::Value::String(name)) if Scene::preset(name).is_none() => {
            let opened =
                matgraph::io::open_reference(file, "scene", name, policy).map_err(path_error)?;
            let text = matgraph::io::read_opened_text(&opened.path, &opened.file)
                .map_err(|e| format!("{}: scene: {e}", file.display()))?;
            let scene = scene_text(&opened.path, &text)
                .map_err(|e| format!("{}: scene: {e}", file.display()))?;
            let stated = stated_in(&text);
            Ok((scene, opened.path, stated))
        }
        value => Ok((
            matgraph::render::graph_scene(graph)
                .map_err(|e| format!("{}: scene: {e}", file.display()))?
                .unwrap_or_else(|| Scene::preset("ball").expect("the ball preset exists")),
            file.to_owned(),
            value.as_ref().map(stated).unwrap_or_default(),
        )),
    }
}

/// The scene of `graph` (read from `file`): `forced` (from `--scene SPEC`) when given, else
/// the scene the graph names (a preset, an inline scene or a scene file inside the graph's
/// folder), else the ball; and its environment image, resolved inside the folder of the
/// file that names it. Each file is opened once and checked against `policy` as opened
/// ([`matgraph::io::open_reference`]), then read from that handle; the environment image is
/// reserved in `budget` before it is decoded.
///
/// A forced scene keeps the graph's time of day: where the graph's own scene writes out
/// `lights` or `environment` (the toon water's sunrise, day, sunset and night) and the
/// forced scene does not (a preset never does), the graph's are used in the forced scene.
pub fn resolve(
    graph: &Graph,
    file: &Path,
    forced: Option<(&str, &Forced)>,
    policy: PathPolicy,
    budget: &matgraph::budget::MemoryBudget,
) -> Result<(Scene, Option<Arc<Texture>>), String> {
    let (scene, base): (Scene, PathBuf) = match forced {
        Some((spec, f)) => {
            let mut scene = f.scene.clone();
            let mut base = PathBuf::from(spec);
            // The graph's own scene is read only when it could give something.
            if graph.scene.is_some() && !(f.stated.lights && f.stated.environment) {
                let (own, own_base, own_stated) = own_scene(graph, file, policy)?;
                if own_stated.lights && !f.stated.lights {
                    scene.lights = own.lights;
                }
                if own_stated.environment && !f.stated.environment {
                    scene.environment = own.environment;
                    base = own_base;
                }
            }
            (scene, base)
        }
        None => {
            let (scene, base, _) = own_scene(graph, file, policy)?;
            (scene, base)
        }
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
