//! The ramp-and-curve widget in `color_ramp`, `float_curve` and `rgb_curves` nodes
//! (src/editor/ramp_ui.rs) driven as a user drives it: a stop or point dragged writes the
//! node's literal where it was dropped, a click on the strip or plot adds one, the context
//! menu removes one, and Ctrl+Z undoes each edit as one step; the stop pins are hidden.
#![cfg(feature = "editor")]

use crate::drive::{H, harness, screen, untitled};
use egui::{Event, Key, Modifiers, PointerButton, Pos2, Rect};
use egui_kittest::kittest::Queryable;
use serde_json::{Value as J, json};

/// An editor holding one node of type `ty` at the origin, no history.
fn one_node(ty: &str) -> (H, String) {
    let mut s = untitled();
    let id = s.add_node(ty, [0.0, 0.0]).unwrap();
    s.history.clear();
    s.selection.clear();
    (harness(s), id)
}

/// The widget's strip (20 points high, its stop markers' row, 12 high, under it) or plot of
/// node `id` (canvas points).
fn widget(h: &H, id: &str) -> Rect {
    h.state()
        .drawn_widgets()
        .iter()
        .find(|(n, _)| n == id)
        .map(|(_, r)| *r)
        .unwrap_or_else(|| panic!("{id} has no widget drawn"))
}

/// Input `input`'s literal on node `id`, if written.
fn literal(h: &H, id: &str, input: &str) -> Option<J> {
    h.state().state.doc.node(id)?.inputs.get(input).cloned()
}

/// A primary drag from `from` to `to` (screen), one frame per step (egui tells a drag
/// from a click over frames).
fn drag(h: &mut H, from: Pos2, to: Pos2) {
    h.event(Event::PointerMoved(from));
    h.step();
    h.event(Event::PointerButton {
        pos: from,
        button: PointerButton::Primary,
        pressed: true,
        modifiers: Modifiers::NONE,
    });
    h.step();
    for k in 1..=8 {
        h.event(Event::PointerMoved(from + (to - from) * (k as f32 / 8.0)));
        h.step();
    }
    h.event(Event::PointerButton {
        pos: to,
        button: PointerButton::Primary,
        pressed: false,
        modifiers: Modifiers::NONE,
    });
    h.run();
}

/// A click with `button` at `at` (screen), over frames.
fn click(h: &mut H, at: Pos2, button: PointerButton) {
    h.event(Event::PointerMoved(at));
    h.step();
    for pressed in [true, false] {
        h.event(Event::PointerButton {
            pos: at,
            button,
            pressed,
            modifiers: Modifiers::NONE,
        });
        h.step();
    }
    h.run();
}

fn undo(h: &mut H) {
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
}

fn f(v: &J) -> f32 {
    v.as_f64().unwrap() as f32
}

#[test]
fn a_ramp_shows_its_widget_not_its_stop_pins() {
    let (h, id) = one_node("color_ramp");
    let r = widget(&h, &id);
    assert!(r.width() > 100.0, "{r:?}");
    // The pins: fac and interpolation; the 16 stops' 32 inputs and the count are the widget's.
    assert!(h.query_by_label("fac").is_some());
    assert!(h.query_by_label("interpolation").is_some());
    assert!(h.query_by_label("pos_1").is_none());
    assert!(h.query_by_label("color_0").is_none());
}

#[test]
fn dragging_a_stop_moves_it_and_undo_puts_it_back() {
    let (mut h, id) = one_node("color_ramp");
    let r = widget(&h, &id);
    // Stop 1 (white, at 1) from its marker under the strip's right end to a quarter.
    let from = screen(&h, egui::pos2(r.right() - 1.0, r.bottom() - 5.0));
    let to = screen(
        &h,
        egui::pos2(r.left() + 0.25 * r.width(), r.bottom() - 5.0),
    );
    drag(&mut h, from, to);
    let pos = literal(&h, &id, "pos_1").expect("pos_1 written");
    assert!((f(&pos) - 0.25).abs() < 0.01, "{pos}");
    assert_eq!(literal(&h, &id, "pos_0"), None, "stop 0 untouched");
    // One undo step for the whole drag: back to the default (unwritten).
    undo(&mut h);
    assert_eq!(literal(&h, &id, "pos_1"), None);
}

#[test]
fn a_click_on_the_strip_adds_a_stop_with_the_ramps_colour_and_the_menu_removes_it() {
    let (mut h, id) = one_node("color_ramp");
    let r = widget(&h, &id);
    let at = screen(&h, egui::pos2(r.left() + 0.5 * r.width(), r.top() + 10.0));
    click(&mut h, at, PointerButton::Primary);
    assert_eq!(literal(&h, &id, "count"), Some(json!(3)));
    let p = f(&literal(&h, &id, "pos_2").unwrap());
    assert!((p - 0.5).abs() < 0.01, "{p}");
    // The default ramp, black to white, linear: grey p there.
    let c = literal(&h, &id, "color_2").unwrap();
    for k in 0..3 {
        assert!((f(&c[k]) - p).abs() < 1e-6, "{c}");
    }
    assert_eq!(f(&c[3]), 1.0);
    // Right-click the new stop's marker, "Remove stop": count back to 2.
    let mark = screen(&h, egui::pos2(r.left() + p * r.width(), r.bottom() - 5.0));
    click(&mut h, mark, PointerButton::Secondary);
    h.get_by_label("Remove stop").click();
    h.run();
    assert_eq!(literal(&h, &id, "count"), Some(json!(2)));
    // Undo: the stop is back; undo again: it was never added.
    undo(&mut h);
    assert_eq!(literal(&h, &id, "count"), Some(json!(3)));
    undo(&mut h);
    assert_eq!(literal(&h, &id, "count"), None);
}

#[test]
fn dragging_a_curve_point_moves_it_and_undo_puts_it_back() {
    let (mut h, id) = one_node("float_curve");
    let r = widget(&h, &id);
    // Point 1 at (1, 1), the plot's top-right corner, down to (1, 0.25)... then left a bit.
    let from = screen(&h, egui::pos2(r.right() - 1.0, r.top() + 1.0));
    let to = screen(
        &h,
        egui::pos2(r.left() + 0.75 * r.width(), r.bottom() - 0.25 * r.height()),
    );
    drag(&mut h, from, to);
    let p = literal(&h, &id, "point_1").expect("point_1 written");
    assert!(
        (f(&p[0]) - 0.75).abs() < 0.01 && (f(&p[1]) - 0.25).abs() < 0.01,
        "{p}"
    );
    undo(&mut h);
    assert_eq!(literal(&h, &id, "point_1"), None);
}

#[test]
fn rgb_curves_edit_the_tab_shown() {
    let (mut h, id) = one_node("rgb_curves");
    // The tab's rect as accesskit gives it is in the canvas layer's points.
    let tab = screen(&h, h.get_by_label("R").rect().center());
    click(&mut h, tab, PointerButton::Primary);
    let r = widget(&h, &id);
    // A click in the plot's empty middle-top adds a point to R only.
    let at = screen(
        &h,
        egui::pos2(r.left() + 0.5 * r.width(), r.top() + 0.2 * r.height()),
    );
    click(&mut h, at, PointerButton::Primary);
    assert_eq!(literal(&h, &id, "c_count"), None);
    assert_eq!(literal(&h, &id, "r_count"), Some(json!(3)));
    let p = literal(&h, &id, "r_2").unwrap();
    assert!(
        (f(&p[0]) - 0.5).abs() < 0.01 && (f(&p[1]) - 0.8).abs() < 0.01,
        "{p}"
    );
}

#[test]
fn delete_over_the_strip_removes_the_selected_stop_not_the_node() {
    let (mut h, id) = one_node("color_ramp");
    // The node selected, as a user who clicked it has it.
    crate::drive::click_node(&mut h, &id, Modifiers::NONE);
    assert_eq!(h.state().state.selection.ids(), std::slice::from_ref(&id));
    let r = widget(&h, &id);
    // Select stop 1 (its marker at the right end), then Delete with the pointer on the strip.
    let mark = screen(&h, egui::pos2(r.right() - 1.0, r.bottom() - 5.0));
    click(&mut h, mark, PointerButton::Primary);
    h.key_press(Key::Delete);
    h.run();
    assert!(h.state().state.doc.node(&id).is_some(), "the node stays");
    assert_eq!(literal(&h, &id, "count"), Some(json!(1)));
    // Stop 0 (black at 0) is the one left: stop 1 was removed, nothing shifted into it.
    assert_eq!(literal(&h, &id, "pos_0"), None);
}
