//! The side panel's preview (the swatch with its orbit camera, play/pause and time) and
//! the parameters panel (the graph's exposed parameters as sliders) and their editor.

use super::params;
use super::ports::Port;
use super::preview::{Orbit, TIME_SPAN};
use super::state::EditorState;
use super::widgets::value_editor_checked;
use egui::{Color32, Ui};

/// Side of the main swatch on screen, points.
pub const SWATCH_POINTS: f32 = 192.0;

/// The preview: the swatch (drag to orbit, scroll to zoom, double-click to reset), where
/// it was drawn, and the time controls.
pub fn preview_panel(ui: &mut Ui, state: &mut EditorState) {
    let p = &mut state.preview;
    ui.horizontal(|ui| {
        ui.strong("Preview");
        if !p.enabled {
            return;
        }
        let backend = p.backend();
        if !backend.is_empty() {
            // The adapter's short name; the whole line and the last render's time on hover
            // (kept out of the panel so that snapshots do not depend on timing).
            let short = backend.split(" (").next().unwrap_or(backend);
            let mut latency = p.latency().map_or(String::new(), |l| {
                format!("\nlast render {} ms", l.as_millis())
            });
            if let Some((side, l)) = p.last_draft() {
                latency += &format!("\nlast draft {} ms at {side}²", l.as_millis());
            }
            ui.weak(short).on_hover_text(format!("{backend}{latency}"));
        }
    });
    if !p.enabled {
        ui.weak("off");
        return;
    }
    if let Some(id) = p.main_output().map(str::to_owned) {
        ui.horizontal(|ui| {
            ui.label(format!("showing '{id}' (not saved)"));
            if ui
                .small_button("show the outputs")
                .on_hover_text("Ctrl+Shift+click the node again, or click here")
                .clicked()
            {
                p.preview_output(None);
            }
        });
    }
    match (p.texture().map(|t| t.id()), p.message()) {
        (_, Some(m)) => {
            ui.colored_label(Color32::from_rgb(255, 120, 110), m);
        }
        (Some(id), None) => {
            let r = ui
                .add(
                    egui::Image::new((id, egui::vec2(SWATCH_POINTS, SWATCH_POINTS)))
                        .sense(egui::Sense::click_and_drag()),
                )
                .on_hover_text("drag to orbit, scroll to zoom, double-click to reset");
            if r.dragged() {
                let d = r.drag_delta();
                p.orbit.drag(d.x, d.y);
            }
            if r.hovered() {
                let dy = ui.input(|i| i.smooth_scroll_delta.y);
                if dy != 0.0 {
                    p.orbit.scroll(dy);
                }
            }
            if r.double_clicked() {
                p.orbit = Orbit::default();
            }
        }
        (None, None) => {
            ui.label("rendering…");
        }
    }
    ui.horizontal(|ui| {
        let label = if p.clock.playing { "⏸" } else { "▶" };
        if ui
            .button(label)
            .on_hover_text("play or pause the time")
            .clicked()
        {
            p.clock.playing = !p.clock.playing;
        }
        ui.add(
            egui::Slider::new(&mut p.clock.time, 0.0..=TIME_SPAN)
                .text("time")
                .suffix(" s")
                .max_decimals(2),
        );
    });
}

/// One exposed parameter as the panel shows it.
struct Row {
    name: String,
    node: String,
    group: Option<String>,
    doc: String,
    ty: crate::types::SocketType,
    lanes: Vec<f32>,
    decl: Port,
}

/// The exposed parameters as sliders (grouped as the file groups them, in its order); a
/// change writes the parameter node's value, which the preview renders without rebuilding
/// its program. A click on the heading opens the parameters' editor in the side panel
/// ([`parameters_editor`]).
pub fn parameters_panel(ui: &mut Ui, state: &mut EditorState, hard: bool) {
    let rows: Vec<Row> = match state.doc.graph() {
        Some(graph) => graph
            .parameters()
            .iter()
            .filter_map(|p| {
                let node = graph.nodes()[p.node].id.clone();
                // The slider spans the range of the first input the parameter feeds (the
                // first with a hard range, which the loader checks the value against, else
                // the first linked whose range holds the value), else the parameter node's own.
                let fed = p
                    .feeds
                    .first()
                    .and_then(|f| input_port(state, graph, &f.node, f.input))
                    .or_else(|| {
                        params::fed_inputs(state.doc.doc(), &node)
                            .into_iter()
                            .filter_map(|(n, i)| {
                                let ports = state.doc.ports(&n)?;
                                Some(ports.inputs[ports.input_index(&i)?].clone())
                            })
                            // Not where the value lies outside it (toon_ball's shininess, 48,
                            // feeds pow's exponent, soft range [-4, 8]): a drag value then.
                            .find(|d| d.soft.or(d.hard).is_some_and(|r| r.contains(&p.default)))
                    });
                let decl = fed.or_else(|| input_port(state, graph, &node, "value"))?;
                Some(Row {
                    name: p.name.clone(),
                    node,
                    group: p.group.clone(),
                    doc: p.doc.clone(),
                    ty: p.ty,
                    lanes: p.default.lanes().to_vec(),
                    decl,
                })
            })
            .collect(),
        None => Vec::new(),
    };
    let heading = ui
        .add(
            egui::Label::new(egui::RichText::new("Parameters").strong())
                .sense(egui::Sense::click()),
        )
        .on_hover_text("click to add, rename, group, reorder or remove the parameters");
    if heading.clicked() {
        state.focus = Some(params::PARAMETERS_PANEL.to_owned());
    }
    if rows.is_empty() {
        ui.weak(match state.doc.doc().parameters.is_empty() {
            true => "none: right-click an input → Expose as parameter",
            false => "shown once the graph has no errors",
        });
        return;
    }
    let mut group: Option<&str> = None;
    let mut changes = Vec::new();
    let mut refused = None;
    egui::Grid::new("matgraph-parameters")
        .num_columns(2)
        .show(ui, |ui| {
            for r in &rows {
                if r.group.as_deref() != group {
                    group = r.group.as_deref();
                    if let Some(g) = group {
                        ui.label(egui::RichText::new(g).italics());
                        ui.end_row();
                    }
                }
                let label = ui.label(&r.name);
                let mut hover = r.doc.clone();
                if !r.decl.unit.is_empty() {
                    hover.push_str(&format!(" [{}]", r.decl.unit));
                }
                if !hover.is_empty() {
                    label.on_hover_text(hover.trim_start());
                }
                ui.push_id(&r.name, |ui| {
                    let edited = value_editor_checked(ui, &r.decl, r.ty, &r.lanes, hard, false);
                    if let Some(v) = edited.value {
                        changes.push((r.name.clone(), r.node.clone(), v));
                    }
                    if let Some(why) = edited.rejected {
                        refused = Some(format!("parameter '{}': {why} (refused)", r.name));
                    }
                });
                ui.end_row();
            }
        });
    for (name, node, value) in changes {
        set_parameter(state, &name, &node, value);
    }
    if refused.is_some() {
        state.status = refused;
    }
}

/// What the parameters' editor was asked for this frame.
enum ParamOp {
    Rename(String, String),
    Doc(String, String),
    Group(String, String),
    Move(String, bool),
    Unexpose(String),
}

/// The parameters' editor (the side panel, a click on the Parameters heading): each
/// parameter's name (rename by typing, Enter), group and doc, moved up or down, or
/// un-exposed (×); and a new parameter of a chosen type added.
pub fn parameters_editor(ui: &mut Ui, state: &mut EditorState) {
    ui.heading("Parameters");
    ui.label(
        "The graph's exposed parameters, in the order callers and the sliders list them. \
         Right-click an input to expose it; × un-exposes one (the inputs it feeds keep its value).",
    );
    ui.separator();
    let list = state.doc.doc().parameters.clone();
    let mut op = None;
    for (k, p) in list.iter().enumerate() {
        let field = |what: &str| egui::Id::new("matgraph-parameter").with(what).with(k);
        let text = |ui: &mut Ui, what: &str, now: &str| {
            ui.data_mut(|d| d.get_temp::<String>(field(what)).unwrap_or(now.to_owned()))
        };
        let mut name = text(ui, "name", &p.name);
        let mut group = text(ui, "group", p.group.as_deref().unwrap_or(""));
        let mut doc = text(ui, "doc", &p.doc);
        ui.horizontal(|ui| {
            let edit = ui.add(egui::TextEdit::singleline(&mut name).desired_width(120.0));
            if edit.lost_focus() && name != p.name {
                op = Some(ParamOp::Rename(p.name.clone(), name.clone()));
            }
            if ui
                .add_enabled(k > 0, egui::Button::new("up").small())
                .on_hover_text(format!("move '{}' up", p.name))
                .clicked()
            {
                op = Some(ParamOp::Move(p.name.clone(), true));
            }
            if ui
                .add_enabled(k + 1 < list.len(), egui::Button::new("down").small())
                .on_hover_text(format!("move '{}' down", p.name))
                .clicked()
            {
                op = Some(ParamOp::Move(p.name.clone(), false));
            }
            if ui
                .small_button("×")
                .on_hover_text(format!(
                    "un-expose '{}': the inputs it feeds keep its value",
                    p.name
                ))
                .clicked()
            {
                op = Some(ParamOp::Unexpose(p.name.clone()));
            }
        });
        let edit = ui.add(
            egui::TextEdit::singleline(&mut group)
                .hint_text("group")
                .desired_width(120.0),
        );
        if edit.lost_focus() && group != p.group.as_deref().unwrap_or("") {
            op = Some(ParamOp::Group(p.name.clone(), group.clone()));
        }
        let edit = ui.add(
            egui::TextEdit::multiline(&mut doc)
                .hint_text("doc")
                .desired_rows(1)
                .desired_width(f32::INFINITY),
        );
        if edit.lost_focus() && doc != p.doc {
            op = Some(ParamOp::Doc(p.name.clone(), doc.clone()));
        }
        let fed = params::fed_inputs(state.doc.doc(), &p.node);
        let ty = state
            .doc
            .graph()
            .and_then(|g| g.parameters().iter().find(|q| q.name == p.name))
            .map_or(String::new(), |q| format!(" · {}", q.ty));
        ui.weak(match fed.is_empty() {
            true => format!("node '{}'{ty} · feeds nothing", p.node),
            false => format!(
                "node '{}'{ty} · feeds {}",
                p.node,
                fed.iter()
                    .map(|(n, i)| format!("{n}.{i}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        });
        ui.data_mut(|d| {
            d.insert_temp(field("name"), name);
            d.insert_temp(field("group"), group);
            d.insert_temp(field("doc"), doc);
        });
        ui.separator();
    }
    let ty_key = egui::Id::new("matgraph-parameter-add-type");
    let name_key = egui::Id::new("matgraph-parameter-add-name");
    let mut ty = ui.data_mut(|d| d.get_temp::<usize>(ty_key).unwrap_or(0));
    let mut name = ui.data_mut(|d| d.get_temp::<String>(name_key).unwrap_or_default());
    let mut add = false;
    ui.horizontal(|ui| {
        egui::ComboBox::from_id_salt("matgraph-parameter-add-type")
            .selected_text(params::TYPES[ty].name())
            .width(70.0)
            .show_ui(ui, |ui| {
                for (k, t) in params::TYPES.iter().enumerate() {
                    ui.selectable_value(&mut ty, k, t.name());
                }
            });
        ui.add(
            egui::TextEdit::singleline(&mut name)
                .hint_text("name")
                .desired_width(100.0),
        );
        add = ui
            .button("add parameter")
            .on_hover_text("a new parameter node, unlinked: wire its output where it is needed")
            .clicked();
    });
    if add {
        let wanted = Some(name.as_str()).filter(|n| !n.is_empty());
        if state.add_parameter(params::TYPES[ty], wanted).is_ok() {
            name.clear();
        }
    }
    ui.data_mut(|d| {
        d.insert_temp(ty_key, ty);
        d.insert_temp(name_key, name);
    });
    if let Some(op) = op {
        // Refused edits (a name taken or an attribute's) leave the reason in the status line.
        let _ = match op {
            ParamOp::Rename(old, new) => state.rename_parameter(&old, &new),
            ParamOp::Doc(name, doc) => state.set_parameter_doc(&name, &doc),
            ParamOp::Group(name, group) => state.set_parameter_group(&name, &group),
            ParamOp::Move(name, up) => state.move_parameter(&name, up),
            ParamOp::Unexpose(name) => state.unexpose_parameter(&name),
        };
        // The fields show the document's parameters again.
        ui.data_mut(|d| {
            for k in 0..list.len() {
                for what in ["name", "group", "doc"] {
                    d.remove::<String>(egui::Id::new("matgraph-parameter").with(what).with(k));
                }
            }
        });
    }
}

/// Input `input` of node `node` of the validated `graph` (a node inlined from a group
/// instance included, `g/f`), as the editor edits it; an instance's interface input
/// (`g/@in:x`, see [`crate::group`]) as the instance shows it.
fn input_port(state: &EditorState, graph: &crate::Graph, node: &str, input: &str) -> Option<Port> {
    if let Some((instance, name)) = node.split_once("/@in:")
        && !instance.contains('/')
        && let Some(ports) = state.doc.ports(instance)
        && let Some(k) = ports.input_index(name)
    {
        return Some(ports.inputs[k].clone());
    }
    let n = &graph.nodes()[graph.node_index(node)?];
    n.node_type
        .inputs()
        .iter()
        .find(|i| i.name == input)
        .map(Port::input)
}

/// Writes exposed parameter `name` (the `value` of its node `node`); consecutive writes
/// while the pointer is held are one undo step.
pub fn set_parameter(state: &mut EditorState, name: &str, node: &str, value: serde_json::Value) {
    let key = format!("param:{name}");
    state.set_input(node, "value", value, Some(&key));
}
