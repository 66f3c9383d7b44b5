//! The node editor (`matgraph edit`), on eframe (wgpu backend) and egui-snarl; built with
//! the default cargo feature `editor`. It reaches the core only through the public API: the
//! document it edits is a [`crate::GraphDocument`], checked by the loader after every edit.
//!
//! Modules: [`model`] (the document and its validation), [`outputs`] (the Material Output
//! node: the graph's `outputs` on the canvas), [`params`] (exposing, editing and un-exposing
//! parameters), [`grouping`], [`scope`], [`interface`], [`group_state`] and [`group_ui`]
//! (node groups made, undone, entered, and their interface), [`variants`] and [`variants_ui`] (variant sets, their switches and the
//! previewed choice), [`browser`] (the in-app file browser of File → Open and the texture
//! picker), [`textures`], [`textures_ui`] and [`thumbnails`] (texture nodes: their image,
//! colour space and missing files; image thumbnails), [`ports`] (a node's pins: its
//! type's, or a group instance's interface), [`undo`], [`state`] (every edit,
//! files, autosave), [`view`], [`viewer`], [`pin_tips`] (pin placement and tooltips), [`cull`] and [`overview`] (the canvas), [`widgets`] (value editors), [`fields`] (their fixed-size number fields) and [`entry`] (typed values checked),
//! [`selection`] and [`select_ui`] (the selection, by node id, and picking, box-selecting
//! and moving nodes with the pointer), [`keymap`] (the Blender and matgraph classic
//! keymaps), [`node_commands`] (mute, collapse and frame commands, their menus),
//! [`mute`], [`collapse`], [`frames`] and [`frames_ui`] (muted, collapsed and framed nodes),
//! [`wheel`] (the wheel's zoom), [`line_tool`], [`wires`] and [`link_edits`] (cutting wires
//! and adding reroutes with a line), [`settings`] (the editor's settings file),
//! [`clipboard`] (copy and paste as graph JSON),
//! [`layout`] (automatic node layout), [`search`] and [`search_ui`] (add-node search), [`code`] (generated code), [`crisp_text`] (the canvas' text rasterised at its zoom), [`preview`]
//! (the live GPU preview) and [`preview_ui`] (its panel, the parameters panel), [`files`], [`first_view`] (where the canvas looks as a graph opens), [`glyphs`] (characters the fonts lack), [`app`] (the frame) and [`headless`] (screenshots).

pub mod app;
pub mod browser;
pub mod clipboard;
pub mod code;
pub mod collapse;
pub mod crisp_text;
pub mod cull;
pub mod entry;
pub mod fields;
pub mod files;
pub mod first_view;
pub mod frames;
pub mod frames_ui;
pub mod glyphs;
pub mod group_state;
pub mod group_ui;
pub mod grouping;
pub mod handoff;
pub mod headless;
pub mod interface;
pub mod keymap;
pub mod layout;
pub mod line_tool;
pub mod link_edits;
pub mod model;
pub mod mute;
pub mod node_commands;
pub mod outputs;
pub mod overview;
pub mod params;
pub mod pin_tips;
pub mod ports;
pub mod preview;
pub mod preview_ui;
pub mod ramp_ui;
pub mod ramps;
pub mod scene_problems;
pub mod scope;
pub mod search;
pub mod search_ui;
pub mod select_ui;
pub mod selection;
pub mod settings;
pub mod stand_in;
pub mod state;
pub mod textures;
pub mod textures_ui;
pub mod thumbnails;
pub mod undo;
pub mod variants;
pub mod variants_ui;
pub mod view;
pub mod viewer;
pub mod wheel;
pub mod widgets;
pub mod wire_order;
pub mod wires;

pub use app::EditorApp;
pub use state::EditorState;

use std::path::Path;

/// Why the editor could not start.
#[derive(Debug, thiserror::Error)]
pub enum EditorError {
    /// No display to open a window on.
    #[error(
        "matgraph edit: no display (DISPLAY and WAYLAND_DISPLAY are unset); run it in a desktop session or under Xvfb, or render the editor headless with --screenshot out.png"
    )]
    NoDisplay,
    /// The graph file could not be opened.
    #[error("{0}")]
    Open(String),
    /// eframe failed (no GPU adapter, a window-system error).
    #[error("matgraph edit: {0}")]
    Window(String),
}

/// Whether a window system is reachable (X11 `DISPLAY` or `WAYLAND_DISPLAY` set).
pub fn has_display() -> bool {
    ["DISPLAY", "WAYLAND_DISPLAY"]
        .iter()
        .any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()))
}

/// The editor state for `file`: the file when it exists, else an empty graph that saves to it.
pub fn state_for(file: Option<&Path>) -> Result<EditorState, EditorError> {
    let registry = crate::Registry::builtin();
    Ok(match file {
        Some(f) if f.exists() => EditorState::open(f, registry).map_err(EditorError::Open)?,
        // A new file: an empty graph named after it (`brick.json` → "brick"), whose
        // recovery file is the file's own (`brick.json.autosave`), not the untitled one.
        Some(f) => {
            let name = f
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .filter(|s| !s.is_empty())
                .unwrap_or_else(|| "untitled".to_owned());
            let doc = model::EditorDoc::empty(&name, registry).doc().clone();
            EditorState::new(doc, Some(f.to_owned()), registry)
        }
        None => EditorState::untitled(registry),
    })
}

/// The editor in an eframe window, with the window title kept up to date.
struct WindowApp {
    app: EditorApp,
    title: String,
}

impl eframe::App for WindowApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let title = self.app.title();
        if title != self.title {
            ui.ctx()
                .send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.title = title;
        }
        self.app.ui(ui);
    }
}

/// The name of the bundled fallback font ([`fonts`]).
pub const FALLBACK_FONT: &str = "DejaVuSans-subset";

/// egui's fonts with two fallbacks, last in the proportional and monospace families (a
/// character is drawn from the first font of its family that has it): Hack (egui's
/// monospace font; Ubuntu Light has no arrows, and messages inside groups read
/// `node 'g' (group G) → node 'f': …`), then a 103 KB subset of DejaVu Sans (Latin-1 and
/// Latin Extended-A, Greek, phonetic and modifier letters, punctuation, super- and
/// subscripts, letterlike symbols, arrows, mathematical operators, technical symbols,
/// geometric shapes; src/editor/fonts/DejaVuSans-LICENSE.txt says how it was made, and
/// its licence) for the registry's docs' `Σ aᵢbᵢ`, `Bₖ` and `gainᵏ`, which no egui font
/// has. `tests/editor/readable.rs` checks every character the editor prints.
pub fn fonts() -> egui::FontDefinitions {
    let mut fonts = egui::FontDefinitions::default();
    fonts.font_data.insert(
        FALLBACK_FONT.to_owned(),
        std::sync::Arc::new(egui::FontData::from_static(include_bytes!(
            "fonts/DejaVuSans-subset.ttf"
        ))),
    );
    let last = [
        (egui::FontFamily::Proportional, "Hack"),
        (egui::FontFamily::Proportional, FALLBACK_FONT),
        (egui::FontFamily::Monospace, FALLBACK_FONT),
    ];
    for (family, font) in last {
        if let Some(f) = fonts.families.get_mut(&family)
            && !f.iter().any(|x| x == font)
        {
            f.push(font.to_owned());
        }
    }
    fonts
}

/// Opens the editor window on `file` (eframe, wgpu backend).
pub fn run_window(file: Option<&Path>) -> Result<(), EditorError> {
    if !has_display() {
        return Err(EditorError::NoDisplay);
    }
    let mut state = state_for(file)?;
    let mut recent = files::Recent::load(&files::recent_list_path());
    if let Some(f) = file.filter(|f| f.exists()) {
        let _ = recent.push(f);
    }
    state.recent = Some(recent);
    state.use_settings(settings::Settings::load(&settings::settings_path()));
    let app = EditorApp::new(state);
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default().with_inner_size([1400.0, 900.0]),
        ..Default::default()
    };
    eframe::run_native(
        "matgraph",
        options,
        Box::new(move |cc| {
            cc.egui_ctx.set_fonts(fonts());
            Ok(Box::new(WindowApp {
                app,
                title: String::new(),
            }))
        }),
    )
    .map_err(|e| EditorError::Window(e.to_string()))
}
