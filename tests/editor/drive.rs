//! Driving the editor's canvas as a user does, through egui_kittest: the harness, a small
//! material, where nodes and pins are drawn, clicks, drags, the wheel. Shared by
//! `keymap.rs` and `node_states.rs`.
#![cfg(feature = "editor")]

use egui::{Event, Modifiers, PointerButton, Pos2, Rect};
use egui_kittest::Harness;
use matgraph::Registry;
use matgraph::editor::{EditorApp, EditorState};
use serde_json::json;

/// The editor under test.
pub type H = Harness<'static, EditorApp>;

/// A harness without a renderer, preview off, on `state`, settled (every node shown and
/// the view fitted).
pub fn harness(mut state: EditorState) -> H {
    state.preview.enabled = false;
    state.dialog = None;
    let mut h = Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .with_max_steps(64)
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), EditorApp::new(state));
    h.run();
    while !h.state().settled() {
        h.step();
    }
    h.run();
    h
}

/// An empty, untitled graph (a recovery file another run left is not this test's).
pub fn untitled() -> EditorState {
    let mut s = EditorState::untitled(Registry::builtin());
    s.dialog = None;
    s
}

/// geometry at (0, 0); dot at (300, 0) reading its normal and view; fresnel_schlick at
/// (600, 0) reading dot, f0 written; add at (0, 300), alone. Nothing selected, no history.
pub fn material() -> EditorState {
    let mut s = untitled();
    s.add_node("geometry", [0.0, 0.0]).unwrap();
    s.add_node("dot", [300.0, 0.0]).unwrap();
    s.add_node("fresnel_schlick", [600.0, 0.0]).unwrap();
    s.add_node("add", [0.0, 300.0]).unwrap();
    s.connect("geometry", "normal", "dot", "a").unwrap();
    s.connect("geometry", "view", "dot", "b").unwrap();
    s.connect("dot", "result", "fresnel_schlick", "cos_theta")
        .unwrap();
    s.set_input("fresnel_schlick", "f0", json!([0.9, 0.6, 0.2]), None);
    s.history.clear();
    s.status = None;
    s.selection.clear();
    s
}

/// The frame node `id` was drawn with in the last frame (canvas points).
pub fn frame(h: &H, id: &str) -> Rect {
    h.state()
        .drawn_frames()
        .iter()
        .find(|(n, _)| *n == id)
        .map(|(_, r)| *r)
        .unwrap_or_else(|| panic!("{id} is not drawn"))
}

/// The screen point of canvas point `p`.
pub fn screen(h: &H, p: Pos2) -> Pos2 {
    h.state().to_screen() * p
}

/// A point of node `id`'s header, on screen.
pub fn header(h: &H, id: &str) -> Pos2 {
    let r = frame(h, id);
    screen(h, r.min + egui::vec2(r.width() / 2.0, 6.0))
}

/// A click with `button` at `at` (screen), `modifiers` held.
pub fn click_button(h: &mut H, at: Pos2, button: PointerButton, modifiers: Modifiers) {
    h.event(Event::ModifiersChanged(modifiers));
    h.event(Event::PointerMoved(at));
    for pressed in [true, false] {
        h.event(Event::PointerButton {
            pos: at,
            button,
            pressed,
            modifiers,
        });
    }
    h.event(Event::ModifiersChanged(Modifiers::NONE));
    h.run();
}

/// A primary click on node `id`'s header, `modifiers` held.
pub fn click_node(h: &mut H, id: &str, modifiers: Modifiers) {
    let at = header(h, id);
    click_button(h, at, PointerButton::Primary, modifiers);
}

/// Selects the nodes `ids` by clicking them (the first plainly, the others with Shift).
pub fn select(h: &mut H, ids: &[&str]) {
    for (k, id) in ids.iter().enumerate() {
        let m = match k {
            0 => Modifiers::NONE,
            _ => Modifiers::SHIFT,
        };
        click_node(h, id, m);
    }
    let got = h.state().state.selection.ids().to_vec();
    assert_eq!(got, ids, "selected by clicks");
}

/// A drag with `button` from `from` to `to` (screen) in eight steps, `modifiers` held.
pub fn drag(h: &mut H, from: Pos2, to: Pos2, button: PointerButton, modifiers: Modifiers) {
    h.event(Event::ModifiersChanged(modifiers));
    h.event(Event::PointerMoved(from));
    h.event(Event::PointerButton {
        pos: from,
        button,
        pressed: true,
        modifiers,
    });
    for k in 1..=8 {
        h.event(Event::PointerMoved(from + (to - from) * (k as f32 / 8.0)));
    }
    h.event(Event::PointerButton {
        pos: to,
        button,
        pressed: false,
        modifiers,
    });
    h.event(Event::ModifiersChanged(Modifiers::NONE));
    h.run();
}

/// A right-drag down the middle of the gap between nodes `left` and `right`, from above
/// their tops to below their bottoms (screen), `modifiers` held: it crosses every wire
/// between them. Returns the line's canvas x.
pub fn drag_between(h: &mut H, left: &str, right: &str, modifiers: Modifiers) -> f32 {
    let (a, b) = (frame(h, left), frame(h, right));
    let x = (a.right() + b.left()) / 2.0;
    let top = a.top().min(b.top()) - 30.0;
    let bottom = a.bottom().max(b.bottom()) + 30.0;
    let (from, to) = (
        screen(h, egui::pos2(x, top)),
        screen(h, egui::pos2(x, bottom)),
    );
    drag(h, from, to, PointerButton::Secondary, modifiers);
    x
}

/// The link written on `node.input`, if any.
pub fn link(h: &H, node: &str, input: &str) -> Option<String> {
    h.state().state.doc.link(node, input).map(str::to_owned)
}

/// The ids of the document's nodes, in order.
pub fn node_ids(h: &H) -> Vec<String> {
    let doc = h.state().state.doc.doc();
    doc.nodes.iter().map(|n| n.id.clone()).collect()
}

/// A scratch folder of this test binary, made empty.
pub fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "matgraph-editor-keymap-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The mouse wheel turned by `dy` points at `at` (screen), no modifier held; returns the
/// view's zoom factor.
pub fn wheel(h: &mut H, at: Pos2, dy: f32) -> f32 {
    let before = h.state().to_screen().scaling;
    h.event(Event::PointerMoved(at));
    h.event(Event::MouseWheel {
        unit: egui::MouseWheelUnit::Point,
        delta: egui::vec2(0.0, dy),
        phase: egui::TouchPhase::Move,
        modifiers: Modifiers::NONE,
    });
    h.run();
    h.state().to_screen().scaling / before
}
