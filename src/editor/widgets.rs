//! In-place editors of unlinked input values: sliders over the soft range (the hard range
//! while Ctrl is held), linear colours shown in sRGB, vectors, enum combos and toggles.

use super::entry;
use super::fields;
use super::ports::Port;
use crate::node::Range;
use crate::types::SocketType;
use crate::value::{Value, json_f32};
use egui::{SliderClamping, Ui};
use std::cell::RefCell;

/// The value `written` (the literal in the file, or `None` for the default `default`) of an
/// input of type `ty` as lanes, an enum input as its index.
pub fn current_lanes(
    decl: &Port,
    ty: SocketType,
    written: Option<&serde_json::Value>,
    default: &Value,
) -> Vec<f32> {
    if let Some(serde_json::Value::String(name)) = written
        && let Some(k) = decl.choices.iter().position(|c| c == name)
    {
        return vec![k as f32];
    }
    written
        .and_then(|j| Value::from_json(ty, j).or_else(|| Value::infer_json(j)?.convert(ty)))
        .unwrap_or(*default)
        .lanes()
        .to_vec()
}

/// The range a float input's slider spans: the soft range (the hard one with `hard`), else
/// the other, where finite; `None`: the input gets a drag value instead.
pub fn slider_range(decl: &Port, hard: bool) -> Option<Range> {
    let range = match hard {
        true => decl.hard.or(decl.soft),
        false => decl.soft.or(decl.hard),
    };
    range.filter(|r| r.min.is_finite() && r.max.is_finite())
}

/// Shows the editor of an input of type `ty` holding `lanes`; returns the new literal when
/// the user changed it. `hard` widens a slider to the hard range.
pub fn value_editor(
    ui: &mut Ui,
    decl: &Port,
    ty: SocketType,
    lanes: &[f32],
    hard: bool,
) -> Option<serde_json::Value> {
    value_editor_checked(ui, decl, ty, lanes, hard, false).value
}

/// [`value_editor`] on a node of the canvas, with the editor's response (its widgets'
/// union), for a context menu: its number fields keep their size whatever they show or
/// are typed ([`super::fields`]), so that the node keeps its size.
pub fn value_editor_response(
    ui: &mut Ui,
    decl: &Port,
    ty: SocketType,
    lanes: &[f32],
    hard: bool,
) -> (Option<serde_json::Value>, egui::Response) {
    let e = value_editor_checked(ui, decl, ty, lanes, hard, true);
    (e.value, e.response)
}

/// What an input's editor did in a frame ([`value_editor_checked`]).
pub struct Edited {
    /// The new literal, when the user changed the value.
    pub value: Option<serde_json::Value>,
    /// Why the text the user typed was refused ([`super::entry::check`]); the value is
    /// then unchanged.
    pub rejected: Option<String>,
    /// The editor's response (its widgets' union).
    pub response: egui::Response,
}

/// The lane names of a vector's fields, in its refusals (`n.y`).
const LANES: [&str; 4] = ["x", "y", "z", "w"];

/// [`value_editor`], where typed text is checked ([`super::entry::check`]): text that is
/// not a number, or a number outside the port's hard range, is refused (and the reason
/// returned); a drag stays within the hard range. Typed text is read once the edit ends
/// (Enter, or a click elsewhere), not at each keystroke. `fixed`: number fields of a fixed
/// size ([`super::fields`]), as on the canvas.
pub fn value_editor_checked(
    ui: &mut Ui,
    decl: &Port,
    ty: SocketType,
    lanes: &[f32],
    hard: bool,
    fixed: bool,
) -> Edited {
    let lane = |k: usize| lanes.get(k).copied().unwrap_or(0.0);
    let refused = RefCell::new(None::<String>);
    // A parser for egui's text entry that records why it refused `what`'s text.
    let parser = |what: String, whole: bool| {
        let refused = &refused;
        move |text: &str| {
            let read = entry::check(decl, &what, text).and_then(|x| match whole {
                true => entry::whole(&what, x),
                false => Ok(x),
            });
            match read {
                Ok(x) => Some(x),
                Err(why) => {
                    *refused.borrow_mut() = Some(why);
                    None
                }
            }
        }
    };
    let drag = drag_range(decl);
    let (value, response) = match ty {
        SocketType::Float => {
            let mut v = lane(0);
            let r = match slider_range(decl, hard) {
                Some(r) => fields::slider(
                    ui,
                    fixed,
                    egui::Slider::new(&mut v, r.min..=r.max)
                        .clamping(SliderClamping::Never)
                        .max_decimals(4)
                        .update_while_editing(false)
                        .custom_parser(parser(decl.name.to_string(), false)),
                ),
                _ => fields::drag_value(
                    ui,
                    fixed,
                    egui::DragValue::new(&mut v)
                        .speed(0.01)
                        .max_decimals(4)
                        .range(drag.clone())
                        .clamp_existing_to_range(false)
                        .update_while_editing(false)
                        .custom_parser(parser(decl.name.to_string(), false)),
                ),
            };
            ((r.changed() && v.is_finite()).then(|| json_f32(v)), r)
        }
        SocketType::Vec2 | SocketType::Vec3 | SocketType::Vec4 => {
            let mut v: Vec<f32> = (0..ty.width()).map(lane).collect();
            let mut changed = false;
            let r = ui
                .horizontal(|ui| {
                    let mut all: Option<egui::Response> = None;
                    for (k, x) in v.iter_mut().enumerate() {
                        let what = format!("{}.{}", decl.name, LANES[k]);
                        let r = fields::drag_value(
                            ui,
                            fixed,
                            egui::DragValue::new(x)
                                .speed(0.01)
                                .max_decimals(3)
                                .range(drag.clone())
                                .clamp_existing_to_range(false)
                                .update_while_editing(false)
                                .custom_parser(parser(what, false)),
                        );
                        changed |= r.changed();
                        all = Some(match all {
                            Some(a) => a | r,
                            None => r,
                        });
                    }
                    all
                })
                .inner
                .expect("a vector has lanes");
            (
                changed.then(|| serde_json::Value::Array(v.into_iter().map(json_f32).collect())),
                r,
            )
        }
        SocketType::Color => {
            // egui's picker takes linear RGB and shows (and lets the user type) sRGB.
            let mut c = [lane(0), lane(1), lane(2)];
            let r = ui.color_edit_button_rgb(&mut c);
            (
                r.changed()
                    .then(|| serde_json::Value::Array(c.into_iter().map(json_f32).collect())),
                r,
            )
        }
        SocketType::Int if !decl.choices.is_empty() => {
            let mut k = lane(0) as usize;
            let before = k;
            let r = egui::ComboBox::from_id_salt(ui.id().with(decl.name.as_ref()))
                .selected_text(decl.choices.get(k).copied().unwrap_or("?"))
                .show_ui(ui, |ui| {
                    for (i, c) in decl.choices.iter().enumerate() {
                        ui.selectable_value(&mut k, i, *c);
                    }
                })
                .response;
            (
                (k != before).then(|| serde_json::Value::String(decl.choices[k].to_owned())),
                r,
            )
        }
        SocketType::Int => {
            let mut v = lane(0) as i32;
            let r = fields::drag_value(
                ui,
                fixed,
                egui::DragValue::new(&mut v)
                    .range(drag.clone())
                    .clamp_existing_to_range(false)
                    .update_while_editing(false)
                    .custom_parser(parser(decl.name.to_string(), true)),
            );
            (r.changed().then(|| serde_json::Value::from(v)), r)
        }
        SocketType::Bool => {
            let mut b = lane(0) != 0.0;
            let r = ui.checkbox(&mut b, "");
            (r.changed().then_some(serde_json::Value::Bool(b)), r)
        }
    };
    Edited {
        value,
        rejected: refused.into_inner(),
        response,
    }
}

/// The range a drag of a number field stays in: the port's hard range, else any number.
fn drag_range(decl: &Port) -> std::ops::RangeInclusive<f64> {
    match decl.hard {
        Some(h) => f64::from(h.min)..=f64::from(h.max),
        None => f64::NEG_INFINITY..=f64::INFINITY,
    }
}

/// The hover text of a port: its type, unit and doc.
pub fn port_hover(ty: &str, unit: &str, doc: &str) -> String {
    let mut s = ty.to_owned();
    if !unit.is_empty() {
        s.push_str(&format!(" [{unit}]"));
    }
    if !doc.is_empty() {
        s.push('\n');
        s.push_str(doc);
    }
    s
}
