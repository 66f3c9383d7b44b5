//! A frame's side panel ([`super::frames`]), shown when its label strip is clicked or it was
//! just made (Ctrl+J): its label (typed, read on Enter or a click elsewhere), its nodes,
//! "Select its nodes" and "Remove frame" (its nodes stay).

use super::state::EditorState;
use egui::Ui;

/// Frame `id`'s panel.
pub fn panel(ui: &mut Ui, state: &mut EditorState, id: &str) {
    let Some(frame) = state.doc.doc().frames.iter().find(|f| f.id == id).cloned() else {
        ui.weak(format!("Frame '{id}' is no longer in the graph."));
        return;
    };
    ui.heading(format!("Frame {id}"));
    ui.label("A labelled box drawn behind its nodes (saved in the file's \"frames\").");
    ui.separator();
    let key = egui::Id::new("matgraph-frame-label").with(id);
    let mut text = ui.data_mut(|d| d.get_temp::<String>(key).unwrap_or(frame.label.clone()));
    let mut commit = false;
    ui.horizontal(|ui| {
        ui.label("label");
        let edit = ui.add(egui::TextEdit::singleline(&mut text).desired_width(160.0));
        commit = edit.lost_focus() && text != frame.label;
    });
    if commit {
        let _ = state.rename_frame(id, &text);
        ui.data_mut(|d| d.remove::<String>(key));
    } else {
        ui.data_mut(|d| d.insert_temp(key, text));
    }
    ui.label(format!("nodes: {}", frame.nodes.join(", ")));
    ui.horizontal(|ui| {
        if ui.button("Select its nodes").clicked() {
            state.selection.set(frame.nodes.iter().cloned());
        }
        if ui
            .button("Remove frame")
            .on_hover_text(
                "the frame goes, its nodes stay where they are (Alt+P takes selected nodes out)",
            )
            .clicked()
        {
            state.remove_frame(id);
        }
    });
}

/// A primary click on a frame's label strip (not on a node drawn over it, `drawn`: id and
/// rect, canvas points) shows the frame's panel; `to_screen` and `canvas` are the frame's
/// view and the canvas' rect on screen.
pub fn click(
    ctx: &egui::Context,
    state: &mut EditorState,
    drawn: &[(String, egui::Rect)],
    to_screen: egui::emath::TSTransform,
    canvas: egui::Rect,
) {
    let (clicked, at) = ctx.input(|i| (i.pointer.primary_clicked(), i.pointer.interact_pos()));
    let Some(at) = at.filter(|p| clicked && canvas.contains(*p)) else {
        return;
    };
    if ctx
        .layer_id_at(at)
        .is_some_and(|l| l.order != egui::Order::Background)
    {
        return;
    }
    let p = to_screen.inverse() * at;
    if drawn.iter().any(|(_, r)| r.contains(p)) {
        return;
    }
    if let Some(id) = super::frames::label_at(&state.doc, p) {
        state.focus = Some(super::frames::focus_of(&id));
    }
}
