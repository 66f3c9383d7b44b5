//! The group commands' UI: their entries in the Edit menu, the breadcrumb over the canvas inside a group
//! ("graph › fresnel_stack", a click leaves to that level), and the interface panel (a
//! group's inputs and outputs, edited through [`super::interface`]).

use super::interface;
use super::state::EditorState;
use crate::types::SocketType;
use crate::value::Value;
use egui::{Color32, Ui};

/// The types a group's input may have, in the order the panel offers them.
pub const INPUT_TYPES: [SocketType; 5] = [
    SocketType::Float,
    SocketType::Vec2,
    SocketType::Vec3,
    SocketType::Vec4,
    SocketType::Color,
];

/// What the group entries of the Edit menu asked for.
#[derive(Clone, Debug, PartialEq)]
pub enum GroupCommand {
    /// Group the selection (Ctrl+G).
    Group,
    /// Ungroup the selected instance (Alt+G).
    Ungroup,
    /// Enter the selected instance (Tab).
    Enter,
    /// Leave the group (Tab).
    Leave,
}

/// The group entries of the Edit menu; `instance`: the one group instance selected (else
/// focused), if so.
pub fn menu(ui: &mut Ui, state: &EditorState, instance: Option<&str>) -> Option<GroupCommand> {
    let mut asked = None;
    if ui.button("Group selected  (Ctrl+G)").clicked() {
        asked = Some(GroupCommand::Group);
    }
    if ui
        .add_enabled(instance.is_some(), egui::Button::new("Ungroup  (Alt+G)"))
        .clicked()
    {
        asked = Some(GroupCommand::Ungroup);
    }
    if ui
        .add_enabled(instance.is_some(), egui::Button::new("Enter group  (Tab)"))
        .clicked()
    {
        asked = Some(GroupCommand::Enter);
    }
    if ui
        .add_enabled(state.in_group(), egui::Button::new("Leave group  (Tab)"))
        .clicked()
    {
        asked = Some(GroupCommand::Leave);
    }
    if asked.is_some() {
        ui.close();
    }
    asked
}

/// The breadcrumb over the canvas' top-left corner inside a group: the graph, then each
/// group entered; a click on one leaves to it. Whether it left.
pub fn breadcrumb(ctx: &egui::Context, state: &mut EditorState, canvas: egui::Rect) -> bool {
    if !state.in_group() || !canvas.is_positive() {
        return false;
    }
    let crumbs = state.breadcrumb();
    let read_only = state.doc.read_only().map(str::to_owned);
    let mut leave = None;
    egui::Area::new(egui::Id::new("matgraph-breadcrumb"))
        .order(egui::Order::Foreground)
        .fixed_pos(canvas.left_top() + egui::vec2(10.0, 8.0))
        .show(ctx, |ui| {
            egui::Frame::popup(ui.style()).show(ui, |ui| {
                ui.horizontal(|ui| {
                    let last = crumbs.len() - 1;
                    for (k, c) in crumbs.iter().enumerate() {
                        if k > 0 {
                            ui.label("›");
                        }
                        match k == last {
                            true => {
                                ui.strong(c);
                            }
                            false => {
                                if ui
                                    .link(c)
                                    .on_hover_text("leave to this level (Tab leaves one)")
                                    .clicked()
                                {
                                    leave = Some(k);
                                }
                            }
                        }
                    }
                    if read_only.is_some() {
                        ui.label(
                            egui::RichText::new("read-only")
                                .italics()
                                .color(Color32::from_rgb(230, 200, 120)),
                        )
                        .on_hover_text(read_only.unwrap_or_default());
                    }
                });
            });
        });
    if let Some(k) = leave {
        state.leave_to(k);
        return true;
    }
    false
}

/// A text field kept in egui's memory under `key` until it loses focus; returns the text
/// when it was changed and committed (focus lost, Enter).
fn committed_text(
    ui: &mut Ui,
    key: egui::Id,
    current: &str,
    width: f32,
    hint: &str,
) -> Option<String> {
    let mut text = ui.data_mut(|d| d.get_temp::<String>(key).unwrap_or(current.to_owned()));
    let edit = ui.add(
        egui::TextEdit::singleline(&mut text)
            .hint_text(hint)
            .desired_width(width),
    );
    let done = edit.lost_focus();
    if done {
        ui.data_mut(|d| d.remove::<String>(key));
    } else {
        ui.data_mut(|d| d.insert_temp(key, text.clone()));
    }
    (done && text != current).then_some(text)
}

/// An input's range editor: a checkbox (on: the range is written) and its min and max;
/// returns the new range when changed.
fn range_editor(
    ui: &mut Ui,
    label: &str,
    range: Option<[f32; 2]>,
    enabled: bool,
) -> Option<Option<[f32; 2]>> {
    let mut changed = None;
    ui.horizontal(|ui| {
        let mut on = range.is_some();
        if ui
            .add_enabled(enabled, egui::Checkbox::new(&mut on, label))
            .changed()
        {
            changed = Some(on.then_some(range.unwrap_or([0.0, 1.0])));
        }
        if let Some([mut lo, mut hi]) = range {
            let a = ui.add_enabled(enabled, egui::DragValue::new(&mut lo).speed(0.01));
            let b = ui.add_enabled(enabled, egui::DragValue::new(&mut hi).speed(0.01));
            if a.changed() || b.changed() {
                changed = Some(Some([lo, hi]));
            }
        }
    });
    changed
}

/// The interface panel of group `group`: its doc, inputs and outputs, each editable (one
/// undo step each; a refusal's reason in the status line); read-only for a group of another
/// file.
pub fn interface_panel(ui: &mut Ui, state: &mut EditorState, group: &str) {
    let def = match state.doc.read_only() {
        Some(_) => state.doc.interface(),
        None => state.root().doc().groups.get(group),
    };
    let Some(def) = def.cloned() else {
        ui.weak(format!("Group '{group}' is no longer in the graph."));
        return;
    };
    let editable = state.doc.read_only().is_none();
    ui.heading(format!("Group '{group}'"));
    if let Some(why) = state.doc.read_only() {
        ui.colored_label(Color32::from_rgb(230, 200, 120), why);
    }
    let id = egui::Id::new("matgraph-interface").with(group);
    ui.add_enabled_ui(editable, |ui| {
        ui.horizontal(|ui| {
            ui.label("doc");
            if let Some(text) = committed_text(
                ui,
                id.with("doc"),
                &def.doc,
                200.0,
                "what the group computes",
            ) {
                let _ = state.edit_interface(|d| interface::set_group_doc(d, group, &text));
            }
        });
    });
    ui.separator();
    ui.strong(format!("Inputs ({})", def.inputs.len()));
    for (k, i) in def.inputs.iter().enumerate() {
        let key = id.with("in").with(&i.name);
        let ty = SocketType::from_name(&i.ty);
        ui.add_enabled_ui(editable, |ui| {
            ui.horizontal(|ui| {
                if let Some(new) = committed_text(ui, key.with("name"), &i.name, 90.0, "name") {
                    rename_input(state, group, &i.name, &new);
                }
                let mut picked = ty;
                egui::ComboBox::from_id_salt(key.with("type"))
                    .width(60.0)
                    .selected_text(ty.map_or(i.ty.clone(), |t| t.name().to_owned()))
                    .show_ui(ui, |ui| {
                        for t in INPUT_TYPES {
                            ui.selectable_value(&mut picked, Some(t), t.name());
                        }
                    });
                if let Some(t) = picked.filter(|t| Some(*t) != ty) {
                    let _ =
                        state.edit_interface(|d| interface::set_input_type(d, group, &i.name, t));
                }
                if ui
                    .add_enabled(k > 0, egui::Button::new("up").small())
                    .on_hover_text("move up")
                    .clicked()
                {
                    let _ =
                        state.edit_interface(|d| interface::move_input(d, group, &i.name, true));
                }
                if ui
                    .add_enabled(k + 1 < def.inputs.len(), egui::Button::new("down").small())
                    .on_hover_text("move down")
                    .clicked()
                {
                    let _ =
                        state.edit_interface(|d| interface::move_input(d, group, &i.name, false));
                }
                if ui
                    .small_button("×")
                    .on_hover_text(format!("remove input '{}'", i.name))
                    .clicked()
                {
                    let _ = state.edit_interface(|d| interface::remove_input(d, group, &i.name));
                }
            });
            // The default, one drag value per lane.
            if let Some(t) = ty {
                let value = i
                    .default
                    .as_ref()
                    .and_then(|v| Value::from_json(t, v))
                    .unwrap_or(Value::zero(t));
                let mut lanes = value.lanes().to_vec();
                let mut changed = false;
                ui.horizontal(|ui| {
                    ui.label("default");
                    for l in &mut lanes {
                        changed |= ui.add(egui::DragValue::new(l).speed(0.01)).changed();
                    }
                });
                if changed {
                    let v = Value::from_lanes(t, &lanes);
                    let k = format!("iface-default:{group}.{}", i.name);
                    let _ = state.edit_interface_keyed(Some(&k), |d| {
                        interface::set_input_default(d, group, &i.name, Some(v))
                    });
                }
            }
            for (label, hard, range) in [
                ("soft range", false, i.soft_range),
                ("hard range", true, i.hard_range),
            ] {
                if let Some(r) = range_editor(ui, label, range, editable) {
                    let k = format!("iface-range:{group}.{}.{hard}", i.name);
                    let _ = state.edit_interface_keyed(Some(&k), |d| {
                        interface::set_input_range(d, group, &i.name, hard, r)
                    });
                }
            }
            ui.horizontal(|ui| {
                ui.label("unit");
                if let Some(u) = committed_text(
                    ui,
                    key.with("unit"),
                    i.unit.as_deref().unwrap_or(""),
                    60.0,
                    "nm, rad…",
                ) {
                    let _ =
                        state.edit_interface(|d| interface::set_input_unit(d, group, &i.name, &u));
                }
                ui.label("doc");
                if let Some(text) =
                    committed_text(ui, key.with("doc"), &i.doc, 120.0, "what it means")
                {
                    let _ = state
                        .edit_interface(|d| interface::set_input_doc(d, group, &i.name, &text));
                }
            });
        });
        ui.add_space(4.0);
    }
    ui.add_enabled_ui(editable, |ui| {
        ui.horizontal(|ui| {
            let key = id.with("add-input");
            let mut ty = ui.data_mut(|d| d.get_temp::<usize>(key.with("type")).unwrap_or(0));
            egui::ComboBox::from_id_salt(key.with("type-combo"))
                .width(60.0)
                .selected_text(INPUT_TYPES[ty.min(4)].name())
                .show_ui(ui, |ui| {
                    for (k, t) in INPUT_TYPES.iter().enumerate() {
                        ui.selectable_value(&mut ty, k, t.name());
                    }
                });
            ui.data_mut(|d| d.insert_temp(key.with("type"), ty));
            if ui.button("add input").clicked() {
                let t = INPUT_TYPES[ty.min(4)];
                if let Ok(name) = state.edit_interface(|d| interface::add_input(d, group, None, t))
                {
                    state.status = Some(format!("added input '{name}' ({t}) to group '{group}'"));
                }
            }
        });
    });
    ui.separator();
    ui.strong(format!("Outputs ({})", def.outputs.len()));
    for (k, o) in def.outputs.iter().enumerate() {
        let key = id.with("out").with(&o.name);
        ui.add_enabled_ui(editable, |ui| {
            ui.horizontal(|ui| {
                if let Some(new) = committed_text(ui, key.with("name"), &o.name, 90.0, "name") {
                    let _ =
                        state.edit_interface(|d| interface::rename_output(d, group, &o.name, &new));
                }
                if ui
                    .add_enabled(k > 0, egui::Button::new("up").small())
                    .on_hover_text("move up")
                    .clicked()
                {
                    let _ =
                        state.edit_interface(|d| interface::move_output(d, group, &o.name, true));
                }
                if ui
                    .add_enabled(k + 1 < def.outputs.len(), egui::Button::new("down").small())
                    .on_hover_text("move down")
                    .clicked()
                {
                    let _ =
                        state.edit_interface(|d| interface::move_output(d, group, &o.name, false));
                }
                if ui
                    .small_button("×")
                    .on_hover_text(format!("remove output '{}'", o.name))
                    .clicked()
                {
                    let _ = state.edit_interface(|d| interface::remove_output(d, group, &o.name));
                }
            });
        });
        match o.from.is_empty() {
            true => ui.colored_label(
                Color32::from_rgb(255, 120, 110),
                format!("{}: unconnected", o.name),
            ),
            false => ui.weak(format!("{} ← {}", o.name, o.from)),
        };
    }
    ui.add_enabled_ui(editable, |ui| {
        if ui.button("add output").clicked()
            && let Ok(name) = state.edit_interface(|d| interface::add_output(d, group, None))
        {
            state.status = Some(format!(
                "added output '{name}' to group '{group}' (unconnected: wire it inside)"
            ));
        }
    });
}

/// Renames input `old` of `group` to `new` (a refusal's reason in the status line).
fn rename_input(state: &mut EditorState, group: &str, old: &str, new: &str) {
    if state
        .edit_interface(|d| interface::rename_input(d, group, old, new))
        .is_ok()
    {
        state.status = Some(format!(
            "renamed input '{old}' to '{new}' of group '{group}'"
        ));
    }
}
