//! The keymaps (issue 35, item 7): in the Blender keymap (the default) the wheel zooms about
//! the pointer, Ctrl+right-drag cuts the wires it crosses and Shift+right-drag adds a
//! reroute on each output's wires it crosses; in "matgraph classic" all three pan, as the
//! editor did before. The keymap is picked in View → Keymap and kept in the settings file.
//! Driven through egui_kittest with pointer events, as a user does.
#![cfg(feature = "editor")]

use crate::drive::{
    H, drag, drag_between, frame, harness, link, material, node_ids, scratch, screen, untitled,
    wheel,
};
use egui::{Key, Modifiers, PointerButton};
use egui_kittest::kittest::Queryable;
use matgraph::editor::keymap::Keymap;
use matgraph::editor::settings::Settings;

/// `material()` in `keymap`.
fn in_keymap(keymap: Keymap) -> H {
    let mut s = material();
    s.settings.values.keymap = keymap;
    harness(s)
}

/// Ctrl+right-drag across the two wires from geometry into dot cuts both (dot's inputs take
/// their defaults again) and leaves the wire it does not cross; one undo step brings both
/// back.
#[test]
fn ctrl_right_drag_cuts_the_wires_it_crosses_in_one_undo_step() {
    let mut h = in_keymap(Keymap::Blender);
    assert_eq!(link(&h, "dot", "a").as_deref(), Some("geometry.normal"));
    let before = h.state().to_screen();
    drag_between(&mut h, "geometry", "dot", Modifiers::COMMAND);
    assert_eq!(link(&h, "dot", "a"), None);
    assert_eq!(link(&h, "dot", "b"), None);
    assert_eq!(
        link(&h, "fresnel_schlick", "cos_theta").as_deref(),
        Some("dot.result")
    );
    assert_eq!(h.state().state.status.as_deref(), Some("cut 2 wires"));
    assert_eq!(h.state().to_screen(), before, "the view held still");
    assert!(h.state().state.search.is_none(), "no menu");
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    assert_eq!(link(&h, "dot", "a").as_deref(), Some("geometry.normal"));
    assert_eq!(link(&h, "dot", "b").as_deref(), Some("geometry.view"));
    // A line that crosses no wire (left of geometry) cuts nothing.
    let r = frame(&h, "geometry");
    let (from, to) = (
        screen(&h, egui::pos2(r.left() - 40.0, r.top())),
        screen(&h, egui::pos2(r.left() - 40.0, r.bottom())),
    );
    drag(
        &mut h,
        from,
        to,
        PointerButton::Secondary,
        Modifiers::COMMAND,
    );
    assert_eq!(link(&h, "dot", "a").as_deref(), Some("geometry.normal"));
    assert_eq!(
        h.state().state.status.as_deref(),
        Some("the line crossed no wire")
    );
}

/// Shift+right-drag across geometry's two wires into dot (two outputs: normal, view) adds
/// one reroute per output, centred where the line crossed its wire, wired in place: the
/// graph stays valid and one undo step takes them out again.
#[test]
fn shift_right_drag_adds_a_reroute_per_output_crossed() {
    let mut h = in_keymap(Keymap::Blender);
    let x = drag_between(&mut h, "geometry", "dot", Modifiers::SHIFT);
    assert_eq!(
        node_ids(&h),
        [
            "geometry",
            "dot",
            "fresnel_schlick",
            "add",
            "reroute",
            "reroute_2"
        ]
    );
    // The line runs down: normal (the higher output pin) is crossed first.
    assert_eq!(
        link(&h, "reroute", "input").as_deref(),
        Some("geometry.normal")
    );
    assert_eq!(link(&h, "dot", "a").as_deref(), Some("reroute.output"));
    assert_eq!(
        link(&h, "reroute_2", "input").as_deref(),
        Some("geometry.view")
    );
    assert_eq!(link(&h, "dot", "b").as_deref(), Some("reroute_2.output"));
    let doc = &h.state().state.doc;
    assert!(doc.errors().is_empty(), "{:?}", doc.errors());
    for id in ["reroute", "reroute_2"] {
        let k = doc.index(id).unwrap();
        let [px, _] = doc.doc().nodes[k].position.unwrap();
        let (w, _) = doc.node_sizes()[k];
        assert!((px + w / 2.0 - x).abs() < 1e-3, "{id} centred on the line");
    }
    // Each reroute sits on its wire: normal's above view's.
    let y = |id: &str| h.state().state.doc.node(id).unwrap().position.unwrap()[1];
    assert!(y("reroute") < y("reroute_2"));
    assert_eq!(
        h.state().state.selection.ids(),
        [] as [String; 0],
        "two: none selected"
    );
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    assert_eq!(node_ids(&h), ["geometry", "dot", "fresnel_schlick", "add"]);
    assert_eq!(link(&h, "dot", "a").as_deref(), Some("geometry.normal"));
    assert_eq!(link(&h, "dot", "b").as_deref(), Some("geometry.view"));
}

/// Two wires leaving one output share one reroute (Blender's `add_reroute_exec` groups the
/// cuts by output socket), placed at the mean of the two crossings, and selected when the
/// line crossed one wire only.
#[test]
fn the_wires_of_one_output_share_a_reroute_at_their_mean_crossing() {
    let mut s = untitled();
    s.add_node("geometry", [0.0, 0.0]).unwrap();
    s.add_node("dot", [320.0, 60.0]).unwrap();
    s.add_node("sqrt", [320.0, 300.0]).unwrap();
    s.connect("geometry", "normal", "dot", "a").unwrap();
    s.connect("geometry", "normal", "dot", "b").unwrap();
    s.connect("geometry", "uv", "sqrt", "x").unwrap();
    s.history.clear();
    s.selection.clear();
    let mut h = harness(s);
    // Down the gap left of dot and sqrt: all three wires.
    let x = drag_between(&mut h, "geometry", "sqrt", Modifiers::SHIFT);
    let doc = &h.state().state.doc;
    let ids: Vec<&str> = doc.doc().nodes.iter().map(|n| n.id.as_str()).collect();
    assert_eq!(
        ids,
        ["geometry", "dot", "sqrt", "reroute", "reroute_2"],
        "one per output"
    );
    assert_eq!(doc.link("reroute", "input"), Some("geometry.normal"));
    assert_eq!(doc.link("dot", "a"), Some("reroute.output"));
    assert_eq!(doc.link("dot", "b"), Some("reroute.output"));
    assert_eq!(doc.link("reroute_2", "input"), Some("geometry.uv"));
    assert_eq!(doc.link("sqrt", "x"), Some("reroute_2.output"));
    let k = doc.index("reroute").unwrap();
    let [px, _] = doc.doc().nodes[k].position.unwrap();
    assert!((px + doc.node_sizes()[k].0 / 2.0 - x).abs() < 1e-3);
    assert!(doc.errors().is_empty(), "{:?}", doc.errors());
    // One wire crossed: its reroute is selected.
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    // Just left of sqrt, where only uv's wire runs.
    let b = frame(&h, "sqrt");
    let (from, to) = (
        screen(&h, egui::pos2(b.left() - 15.0, b.top() - 40.0)),
        screen(&h, egui::pos2(b.left() - 15.0, b.bottom())),
    );
    drag(&mut h, from, to, PointerButton::Secondary, Modifiers::SHIFT);
    assert_eq!(link(&h, "sqrt", "x").as_deref(), Some("reroute.output"));
    assert_eq!(h.state().state.selection.ids(), ["reroute"]);
}

/// In the classic keymap Ctrl+ and Shift+right-drag pan as before: no wire cut, no reroute.
#[test]
fn the_classic_keymap_pans_where_blender_cuts_and_reroutes() {
    for m in [Modifiers::COMMAND, Modifiers::SHIFT] {
        let mut h = in_keymap(Keymap::Classic);
        let before = h.state().to_screen();
        drag_between(&mut h, "geometry", "dot", m);
        assert_eq!(
            node_ids(&h),
            ["geometry", "dot", "fresnel_schlick", "add"],
            "{m:?}"
        );
        assert_eq!(link(&h, "dot", "a").as_deref(), Some("geometry.normal"));
        assert_eq!(link(&h, "dot", "b").as_deref(), Some("geometry.view"));
        assert!(!h.state().state.history.can_undo(), "{m:?}: no edit");
        let moved = h.state().to_screen().translation - before.translation;
        assert!(moved.y > 50.0, "{m:?}: panned by {moved:?}");
    }
}

/// The wheel over the canvas: in the Blender keymap it zooms by egui's Ctrl+wheel factor,
/// exp(Δ/200) for a 50-point turn, the canvas point under the pointer staying under it; in
/// the classic keymap it pans, the zoom unchanged.
#[test]
fn the_wheel_zooms_about_the_pointer_in_blender_and_pans_in_classic() {
    for keymap in Keymap::ALL {
        let mut h = in_keymap(keymap);
        let before = h.state().to_screen();
        let at = screen(&h, egui::pos2(200.0, 150.0));
        wheel(&mut h, at, 50.0);
        let after = h.state().to_screen();
        match keymap {
            Keymap::Blender => {
                let factor = after.scaling / before.scaling;
                let expected = (50.0f64 / 200.0).exp();
                assert!(
                    (factor as f64 - expected).abs() < 0.01 * expected,
                    "zoomed by {factor}, expected {expected}"
                );
                let under = after.inverse() * at;
                assert!(
                    (under - egui::pos2(200.0, 150.0)).length() < 0.5,
                    "the point under the pointer moved to {under:?}"
                );
            }
            Keymap::Classic => {
                assert_eq!(after.scaling, before.scaling, "no zoom");
                let moved = after.translation - before.translation;
                assert!(moved.y > 40.0, "panned by {moved:?}");
            }
        }
    }
}

/// View → Keymap picks "matgraph classic": the settings file keeps it, and the wheel pans
/// from then on; picking Blender again zooms.
#[test]
fn view_keymap_picks_the_keymap_and_the_settings_file_keeps_it() {
    let dir = scratch("keymap_menu");
    let store = dir.join("matgraph").join("editor.json");
    let mut s = material();
    s.settings = Settings::load(&store);
    let mut h = harness(s);
    assert_eq!(
        h.state().state.settings.keymap(),
        Keymap::Blender,
        "the default"
    );
    let pick = |h: &mut H, label: &str| {
        h.get_by_label("View").click();
        h.run();
        h.get_by_label("Keymap ⏵").click();
        h.run();
        h.get_by_label(label).click();
        h.run();
    };
    pick(&mut h, "matgraph classic");
    assert_eq!(h.state().state.settings.keymap(), Keymap::Classic);
    assert_eq!(
        Settings::load(&store).keymap(),
        Keymap::Classic,
        "kept in the file"
    );
    let text = std::fs::read_to_string(&store).unwrap();
    assert!(text.contains("\"keymap\": \"classic\""), "{text}");
    let turn = |h: &mut H| {
        let at = screen(h, egui::pos2(200.0, 150.0));
        wheel(h, at, 50.0)
    };
    assert_eq!(turn(&mut h), 1.0, "classic: the wheel pans");
    pick(&mut h, "Blender");
    assert_eq!(Settings::load(&store).keymap(), Keymap::Blender);
    assert!(turn(&mut h) > 1.2, "Blender: the wheel zooms");
    let _ = std::fs::remove_dir_all(&dir);
}
