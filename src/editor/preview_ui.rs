//! The side panel's preview (the swatch with its orbit camera, play/pause and time) and
//! the parameters panel (the graph's exposed parameters as sliders).

use super::ports::Port;
use super::preview::{Orbit, TIME_SPAN};
use super::state::EditorState;
use super::widgets::value_editor;
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

/// The exposed parameters as sliders (grouped as the file groups them); a change writes
/// the parameter node's value, which the preview renders without rebuilding its program.
pub fn parameters_panel(ui: &mut Ui, state: &mut EditorState, hard: bool) {
    let Some(graph) = state.doc.graph() else {
        return;
    };
    if graph.parameters().is_empty() {
        return;
    }
    let rows: Vec<Row> = graph
        .parameters()
        .iter()
        .filter_map(|p| {
            let node = graph.nodes()[p.node].id.clone();
            // The slider spans the range of the first input the parameter feeds, else the
            // parameter node's own.
            let fed = p
                .feeds
                .first()
                .and_then(|f| input_port(state, graph, &f.node, f.input));
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
        .collect();
    ui.strong("Parameters");
    let mut group: Option<&str> = None;
    let mut changes = Vec::new();
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
                if !r.doc.is_empty() {
                    label.on_hover_text(&r.doc);
                }
                ui.push_id(&r.name, |ui| {
                    if let Some(v) = value_editor(ui, &r.decl, r.ty, &r.lanes, hard) {
                        changes.push((r.name.clone(), r.node.clone(), v));
                    }
                });
                ui.end_row();
            }
        });
    for (name, node, value) in changes {
        set_parameter(state, &name, &node, value);
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
