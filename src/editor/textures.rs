//! Texture nodes in the editor (`image_texture`, and every node type whose evaluation is
//! [`Evaluation::Texture`]): their image (`"texture"`), picked through the in-app browser
//! ([`super::browser::Browser::images`]) inside the graph's folder and written relative to
//! the graph file; their colour space (`"color_space"`, format version 2: choosing one
//! moves a version-1 file to version 2); and what is wrong with their files (missing,
//! outside the folder, not decodable), shown on the node.
//!
//! The folder rules are the loader's ([`crate::io::resolve_reference`] under
//! [`PathPolicy::InsideGraphFolder`]): the browser cannot leave the graph's folder, and a
//! picked file that resolves outside it (through a symbolic link) is refused with the
//! loader's message. An untitled graph has no folder: its image paths would have nothing to
//! be relative to, so the picker asks for the graph to be saved first.

use super::model::EditorDoc;
use super::state::{Dialog, EditorState};
use crate::color_space::ColorSpace;
use crate::document::{GROUPS_VERSION, TextureSource};
use crate::io::PathPolicy;
use crate::node::Evaluation;
use std::path::{Component, Path, PathBuf};

/// The image file types the picker lists (lower case, no dot): those
/// [`crate::image_io::load_image`] reads.
pub const IMAGE_EXTENSIONS: [&str; 5] = ["png", "jpg", "jpeg", "hdr", "exr"];

/// What the user asked of a texture node.
#[derive(Clone, Debug, PartialEq)]
pub enum TextureAction {
    /// Open the image picker for this node.
    Pick(String),
    /// Set the node's colour space (`None`: the file type's default, the field absent).
    ColorSpace(String, Option<ColorSpace>),
}

/// Whether node `id` samples a texture (its type's evaluation is [`Evaluation::Texture`]).
pub fn is_texture_node(doc: &EditorDoc, id: &str) -> bool {
    doc.node_type(id)
        .is_some_and(|t| t.evaluation() == Evaluation::Texture)
}

/// Whether the canvas shows node `id`'s image row: a texture node whose `texture` is absent
/// or names files (not a `scene:` texture, which the renderer supplies).
pub fn shows_image_row(doc: &EditorDoc, id: &str) -> bool {
    is_texture_node(doc, id)
        && doc
            .node(id)
            .is_none_or(|n| n.texture.as_ref().is_none_or(|t| t.scene_name().is_none()))
}

/// The label of a colour-space choice: `auto (srgb)` (the default of the file type of
/// `texture`) for `None`, else the space's name.
pub fn space_label(space: Option<ColorSpace>, texture: Option<&TextureSource>) -> String {
    match space {
        Some(s) => s.name().to_owned(),
        None => {
            let key = texture.map(TextureSource::key).unwrap_or_default();
            format!("auto ({})", ColorSpace::default_for(&key))
        }
    }
}

/// The graph file's folder, absolute (the folder the picker stays in).
pub fn graph_folder(graph_file: &Path) -> PathBuf {
    let folder = match graph_file.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_owned(),
        _ => PathBuf::from("."),
    };
    normalise(&std::path::absolute(&folder).unwrap_or(folder))
}

/// `path` without `.` and with `..` applied lexically.
fn normalise(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            c => out.push(c),
        }
    }
    out
}

/// The reference of `picked` as a texture of `graph_file`: its path relative to the
/// graph's folder, `/`-separated, checked by the loader's folder rules
/// ([`crate::io::resolve_reference`], [`PathPolicy::InsideGraphFolder`]: symbolic links
/// followed, a regular file). Refused, with the reason, outside the folder.
pub fn reference_of(graph_file: &Path, node: &str, picked: &Path) -> Result<String, String> {
    let folder = graph_folder(graph_file);
    let picked = normalise(&std::path::absolute(picked).unwrap_or_else(|_| picked.to_owned()));
    let rel = picked.strip_prefix(&folder).map_err(|_| {
        format!(
            "{} is outside the graph's folder {}: a texture must lie inside it",
            picked.display(),
            folder.display()
        )
    })?;
    let parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if parts.is_empty() {
        return Err(format!("{} is a folder, not an image", picked.display()));
    }
    let reference = parts.join("/");
    let by = format!("node '{node}'");
    crate::io::resolve_reference(graph_file, &by, &reference, PathPolicy::InsideGraphFolder)
        .map_err(|e| e.to_string())?;
    Ok(reference)
}

/// Writes `reference` as node `id`'s `texture` (one image: a mip chain or a scene texture
/// it named is replaced). Refused when it adds a loader error.
pub fn set_texture(d: &mut EditorDoc, id: &str, reference: &str) -> Result<(), String> {
    let k = d.index(id).ok_or_else(|| format!("no node '{id}'"))?;
    if !is_texture_node(d, id) {
        return Err(format!("node '{id}' samples no texture"));
    }
    let mut candidate = d.doc().clone();
    candidate.nodes[k].texture = Some(TextureSource::Image(reference.to_owned()));
    d.try_replace(candidate)
}

/// Writes node `id`'s `color_space` (`None` removes it: the file type's default). A space
/// on a version-1 document moves it to version 2 ([`GROUPS_VERSION`]), the version that
/// reads it, so that the file saved reads back. Refused when it adds a loader error (a
/// space on a scene texture).
pub fn set_color_space(
    d: &mut EditorDoc,
    id: &str,
    space: Option<ColorSpace>,
) -> Result<(), String> {
    let k = d.index(id).ok_or_else(|| format!("no node '{id}'"))?;
    if !is_texture_node(d, id) {
        return Err(format!("node '{id}' samples no image"));
    }
    let mut candidate = d.doc().clone();
    candidate.nodes[k].color_space = space;
    if candidate.version < GROUPS_VERSION && candidate.newer_feature().is_some() {
        candidate.version = GROUPS_VERSION;
    }
    d.try_replace(candidate)
}

/// What is wrong with node `id`'s image files, for the node: `missing: PATH`, the loader's
/// refusal of a path outside the folder, or the file's decode error (from `decoded`, which
/// gives the decode error of a file, if known: [`super::thumbnails`]); `None` when nothing
/// is known to be wrong, for a scene texture, or a node without a texture (the loader
/// reports that). Paths are the node's references, relative to the graph file.
pub fn problem(
    doc: &EditorDoc,
    graph_file: Option<&Path>,
    id: &str,
    mut decoded: impl FnMut(&Path) -> Option<String>,
) -> Option<String> {
    let n = doc.node(id)?;
    let source = n.texture.as_ref()?;
    let files = source.files();
    if files.is_empty() {
        return None;
    }
    let Some(graph_file) = graph_file else {
        return Some(format!(
            "untitled: {} is read once the graph is saved beside it",
            files[0]
        ));
    };
    let by = format!("node '{id}'");
    for f in files {
        match crate::io::resolve_reference(graph_file, &by, f, PathPolicy::InsideGraphFolder) {
            Ok(path) => {
                if let Some(e) = decoded(&path) {
                    return Some(format!("{f}: {e}"));
                }
            }
            Err(crate::io::PathError::Outside { .. }) => {
                return Some(format!("outside the graph's folder: {f}"));
            }
            Err(crate::io::PathError::Unreadable { source, .. }) => {
                let missing = !graph_folder(graph_file).join(f).exists();
                return Some(match missing {
                    true => format!("missing: {f}"),
                    false => format!("{f}: {source}"),
                });
            }
        }
    }
    None
}

/// Opens the image picker for node `id`: the browser of images ([`IMAGE_EXTENSIONS`]) in
/// the folder of its current image (its row highlighted; else the graph's folder), kept
/// inside the graph's folder. An
/// untitled graph has no folder: the status line asks to save it first.
pub fn open_picker(s: &mut EditorState, id: &str) {
    let Some(file) = s.path.clone() else {
        s.status = Some(
            "save the graph first: a texture's path is relative to the graph file, and the picker stays inside its folder"
                .into(),
        );
        return;
    };
    let root = graph_folder(&file);
    let image = s
        .doc
        .node(id)
        .and_then(|n| n.texture.as_ref())
        .and_then(|t| t.files().first().map(|f| normalise(&root.join(f))));
    let folder = image
        .as_ref()
        .and_then(|p| p.parent().map(Path::to_owned))
        .filter(|d| d.is_dir())
        .unwrap_or_else(|| root.clone());
    let mut browser = super::browser::Browser::images(&folder, &root, id);
    // The current image's row is highlighted.
    if let Some(k) = image.and_then(|p| browser.entries().iter().position(|e| e.path == p)) {
        browser.selected = k;
    }
    s.dialog = Some(Dialog::PickTexture {
        node: id.to_owned(),
        browser: Box::new(browser),
    });
}

/// Picks `path` as node `id`'s image: written relative to the graph file, one undo step.
/// Refused (nothing changes), with the reason, outside the graph's folder.
pub fn pick(s: &mut EditorState, id: &str, path: &Path) -> Result<String, String> {
    let file = s
        .path
        .clone()
        .ok_or("save the graph first: a texture's path is relative to the graph file")?;
    let reference = reference_of(&file, id, path)?;
    s.edit(None, false, |d| set_texture(d, id, &reference))?;
    s.status = Some(format!("'{id}' samples {reference}"));
    Ok(reference)
}

/// Sets node `id`'s colour space, one undo step; the status line says when the file moves
/// to format version 2.
pub fn choose_space(s: &mut EditorState, id: &str, space: Option<ColorSpace>) {
    let before = s.doc.doc().version;
    if s.edit(None, false, |d| set_color_space(d, id, space))
        .is_ok()
    {
        let label = space_label(space, s.doc.node(id).and_then(|n| n.texture.as_ref()));
        s.status = Some(match s.doc.doc().version > before {
            true => format!(
                "'{id}' reads its image as {label}; the file moves to format version {GROUPS_VERSION} (\"color_space\")"
            ),
            false => format!("'{id}' reads its image as {label}"),
        });
    }
}

/// Applies a texture action to the editor.
pub fn apply(s: &mut EditorState, a: TextureAction) {
    match a {
        TextureAction::Pick(id) => open_picker(s, &id),
        TextureAction::ColorSpace(id, space) => choose_space(s, &id, space),
    }
}
