//! The texture node's widgets ([`super::textures`]): on the canvas, under its pins, its
//! image (thumbnail and file name: click to pick another), its colour space and, in red,
//! what is wrong with its file; the same, larger, in the side panel; and the picker dialog.

use super::browser::{Browser, Outcome};
use super::model::EditorDoc;
use super::ports::{Kind, Ports};
use super::state::EditorState;
use super::textures::{TextureAction, pick, problem, space_label};
use super::thumbnails::{Status, Thumbnails, shared};
use crate::color_space::ColorSpace;
use crate::document::{NodeDocument, TextureSource};
use crate::node::Evaluation;
use egui::{Color32, Ui};
use std::path::Path;

/// The red of a texture's problem.
pub const PROBLEM_COLOR: Color32 = Color32::from_rgb(255, 120, 110);

/// The most characters of a file name on the node's button (a longer one keeps its end).
pub const NAME_CHARS: usize = 22;

/// The side of the thumbnail on the node, points.
pub const NODE_THUMB: f32 = 20.0;

/// The estimated height of the node's image rows (the image button, the colour space),
/// canvas points: two input rows ([`super::layout::INPUT_ROW`]) and the footer's spacing.
pub const ROWS_HEIGHT: f32 = 2.0 * super::layout::INPUT_ROW + 6.0;

/// The button text of a texture: the file name (of the first level of a mip chain, with how
/// many more), at most [`NAME_CHARS`] characters, or `pick an image…`.
pub fn button_text(texture: Option<&TextureSource>) -> String {
    let short = |f: &str| {
        let name = f.rsplit('/').next().unwrap_or(f);
        let n = name.chars().count();
        match n > NAME_CHARS {
            true => {
                let tail: String = name.chars().skip(n - (NAME_CHARS - 1)).collect();
                format!("…{tail}")
            }
            false => name.to_owned(),
        }
    };
    match texture {
        None => "pick an image…".into(),
        Some(TextureSource::Image(f)) => short(f),
        Some(TextureSource::MipChain(v)) => match v.split_first() {
            Some((first, rest)) => format!("{} +{}", short(first), rest.len()),
            None => "pick an image…".into(),
        },
    }
}

/// The estimated size (width, height) of the image rows under a texture node's pins
/// ([`super::textures::shows_image_row`]), canvas points; `None` for other nodes. Width: the
/// thumbnail, the button's text (7 points a character, 16 of padding) and spacing; the
/// colour row's label and combo box.
pub fn rows_size(node: &NodeDocument, ports: &Ports) -> Option<(f32, f32)> {
    let Kind::Type(t) = &ports.kind else {
        return None;
    };
    if t.evaluation() != Evaluation::Texture
        || node
            .texture
            .as_ref()
            .is_some_and(|s| s.scene_name().is_some())
    {
        return None;
    }
    let text = button_text(node.texture.as_ref()).chars().count() as f32;
    let button = NODE_THUMB + 8.0 + 7.0 * text + 16.0 + 16.0;
    let colour = 7.0 * "colour".len() as f32 + 8.0 + 120.0 + 16.0;
    Some((button.max(colour), ROWS_HEIGHT))
}

/// The colour-space combo box of node `id` (salted by `salt`); the choice made, if any.
fn space_combo(ui: &mut Ui, salt: &str, id: &str, node: &NodeDocument) -> Option<TextureAction> {
    let texture = node.texture.as_ref();
    let mut chosen = node.color_space;
    let before = chosen;
    egui::ComboBox::from_id_salt((salt, id))
        .selected_text(space_label(chosen, texture))
        .width(100.0)
        .show_ui(ui, |ui| {
            ui.selectable_value(&mut chosen, None, space_label(None, texture))
                .on_hover_text("the file type's: sRGB for PNG and JPEG, linear for HDR and EXR (no \"color_space\" written)");
            for s in ColorSpace::ALL {
                let hover = match s {
                    ColorSpace::Srgb => "sRGB-encoded colour, decoded to linear light",
                    ColorSpace::Linear => "linear-light colour, read unchanged",
                    ColorSpace::Data => {
                        "not colour (roughness, height, normals, masks): read unchanged"
                    }
                };
                ui.selectable_value(&mut chosen, Some(s), s.name())
                    .on_hover_text(hover);
            }
        })
        .response
        .on_hover_text("how the image's values are read (\"color_space\", format version 2)");
    (chosen != before).then(|| TextureAction::ColorSpace(id.to_owned(), chosen))
}

/// The problem of node `id`'s image for the node ([`problem`]), decode errors from the
/// thumbnail cache (a file is decoded once per modification, on its worker).
pub fn node_problem(
    doc: &EditorDoc,
    file: Option<&Path>,
    id: &str,
    thumbs: &mut Thumbnails,
) -> Option<String> {
    problem(doc, file, id, |p| match thumbs.get(p) {
        Status::Failed(why) => Some(why.to_owned()),
        _ => None,
    })
}

/// The image rows under texture node `id`'s pins on the canvas: its thumbnail and file name
/// (a button: pick another image), its colour space, and what is wrong with its file, in
/// red. Returns what the user asked for.
pub fn node_rows(
    ui: &mut Ui,
    doc: &EditorDoc,
    file: Option<&Path>,
    id: &str,
) -> Option<TextureAction> {
    let node = doc.node(id)?;
    let thumbs = shared(ui.ctx());
    let mut thumbs = thumbs.lock().unwrap_or_else(|e| e.into_inner());
    let mut action = None;
    let problem = node_problem(doc, file, id, &mut thumbs);
    ui.vertical(|ui| {
        ui.horizontal(|ui| {
            let first = node
                .texture
                .as_ref()
                .and_then(|t| t.files().first().map(|f| f.to_string()));
            let path = file
                .zip(first.as_deref())
                .map(|(g, f)| super::textures::graph_folder(g).join(f));
            let size = egui::vec2(NODE_THUMB, NODE_THUMB);
            let (rect, _) = ui.allocate_exact_size(size, egui::Sense::hover());
            let mut hover = first.clone().unwrap_or_else(|| {
                "the node's \"texture\": an image inside the graph's folder".into()
            });
            if problem.is_none()
                && let Some(p) = &path
                && let Some((tex, s, [w, h])) = thumbs.texture(ui.ctx(), p)
            {
                let at =
                    egui::Rect::from_center_size(rect.center(), s * (NODE_THUMB / s.max_elem()));
                egui::Image::new((tex, at.size())).paint_at(ui, at);
                hover = format!("{hover}\n{w}×{h}");
            }
            let b = ui
                .button(button_text(node.texture.as_ref()))
                .on_hover_text(format!("{hover}\nclick to pick another image"));
            if b.clicked() {
                action = Some(TextureAction::Pick(id.to_owned()));
            }
        });
        ui.horizontal(|ui| {
            ui.label("colour");
            if let Some(a) = space_combo(ui, "node-color-space", id, node) {
                action = Some(a);
            }
        });
        if let Some(p) = &problem {
            ui.add(egui::Label::new(egui::RichText::new(p).color(PROBLEM_COLOR)).truncate())
                .on_hover_text(p);
        }
    });
    if thumbs.pending() {
        ui.ctx()
            .request_repaint_after(std::time::Duration::from_millis(30));
    }
    action
}

/// The side panel's image section of texture node `id`: its reference, the thumbnail at
/// twice the browser's size, the image's size, what is wrong with it, "Pick an image…" and
/// the colour space. Returns what the user asked for.
pub fn inspector_section(ui: &mut Ui, s: &EditorState, id: &str) -> Option<TextureAction> {
    let node = s.doc.node(id)?;
    let file = s.path.as_deref();
    let thumbs = shared(ui.ctx());
    let mut thumbs = thumbs.lock().unwrap_or_else(|e| e.into_inner());
    let mut action = None;
    ui.separator();
    ui.strong("Image");
    match &node.texture {
        None => {
            ui.weak("none yet: pick one");
        }
        Some(t) if t.scene_name().is_some() => {
            ui.label(format!("{} (rendered by the scene)", t.key()));
        }
        Some(t) => {
            for f in t.files() {
                ui.monospace(f);
            }
        }
    }
    let problem = node_problem(&s.doc, file, id, &mut thumbs);
    let first = node
        .texture
        .as_ref()
        .and_then(|t| t.files().first().map(|f| f.to_string()));
    if let (None, Some(g), Some(f)) = (&problem, file, &first) {
        let path = super::textures::graph_folder(g).join(f);
        if let Some((tex, size, [w, h])) = thumbs.texture(ui.ctx(), &path) {
            let side = 2.0 * super::browser::THUMB_POINTS;
            ui.image((tex, size * (side / size.max_elem())));
            ui.weak(format!("{w}×{h}"));
        }
    }
    if let Some(p) = &problem {
        ui.colored_label(PROBLEM_COLOR, p);
    }
    ui.horizontal(|ui| {
        let pick = ui.add_enabled(file.is_some(), egui::Button::new("Pick an image…"));
        let pick = pick.on_disabled_hover_text(
            "save the graph first: a texture's path is relative to the graph file",
        );
        if pick.clicked() {
            action = Some(TextureAction::Pick(id.to_owned()));
        }
    });
    if node
        .texture
        .as_ref()
        .is_none_or(|t| t.scene_name().is_none())
    {
        ui.horizontal(|ui| {
            ui.label("colour space");
            if let Some(a) = space_combo(ui, "panel-color-space", id, node) {
                action = Some(a);
            }
        });
    }
    if thumbs.pending() {
        ui.ctx()
            .request_repaint_after(std::time::Duration::from_millis(30));
    }
    action
}

/// The picker dialog of node `node`: the browser; a file picked is written as the node's
/// texture ([`pick`]), or refused with the reason shown in the browser. Returns whether the
/// dialog stays open.
pub fn picker(ui: &mut Ui, s: &mut EditorState, node: &str, browser: &mut Browser) -> bool {
    match browser.show(ui) {
        Some(Outcome::Open(path)) => match pick(s, node, &path) {
            Ok(_) => false,
            Err(why) => {
                browser.error = Some(why);
                true
            }
        },
        Some(Outcome::Cancel) => false,
        None => true,
    }
}
