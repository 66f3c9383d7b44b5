//! The node commands ([`NodeCommand`]: mute, collapse, join in a frame, remove from frame)
//! run on nodes, and where they are offered besides their keys: the Edit menu, a node's
//! right-click menu, and View → Keymap, which picks the keymap
//! ([`super::keymap`]) and keeps it in the settings file.

use super::keymap::{BINDINGS, Keymap, NodeCommand};
use super::model::EditorDoc;
use super::state::EditorState;
use super::viewer::Action;
use egui::Ui;

impl EditorState {
    /// Runs `c` on the nodes `ids` (the selection, or the node whose menu asked).
    pub fn run_node_command(&mut self, c: NodeCommand, ids: &[String]) {
        match c {
            NodeCommand::Mute => {
                let _ = self.toggle_mute(ids);
            }
            NodeCommand::Collapse => {
                self.toggle_collapse(ids);
            }
            NodeCommand::JoinFrame => {
                let _ = self.join_in_frame(ids);
            }
            NodeCommand::Unframe => self.remove_from_frames(ids),
        }
    }

    /// Chooses keymap `k` and keeps it in the settings file.
    pub fn set_keymap(&mut self, k: Keymap) {
        self.status = Some(match self.settings.set_keymap(k) {
            Ok(()) => format!("keymap: {}", k.label()),
            Err(e) => format!("keymap: {} (not kept: {e})", k.label()),
        });
    }
}

/// The node commands' entries of the Edit menu, on the selected nodes; the one asked for.
pub fn menu(ui: &mut Ui, state: &EditorState) -> Option<NodeCommand> {
    let any = !state.selection.is_empty();
    let mut asked = None;
    for c in NodeCommand::ALL {
        let enabled = any
            && match c {
                NodeCommand::JoinFrame | NodeCommand::Unframe => !state.in_group(),
                _ => true,
            };
        if ui
            .add_enabled(enabled, egui::Button::new(c.label()))
            .on_hover_text(c.help())
            .on_disabled_hover_text("select nodes first (frames: at the graph's top)")
            .clicked()
        {
            asked = Some(c);
            ui.close();
        }
    }
    asked
}

/// The command entries of node `id`'s right-click menu (they act on the selection when
/// the node is in it, else on the node), and its frame's: "Remove from frame" and the
/// frame's panel.
pub fn node_menu(ui: &mut Ui, doc: &EditorDoc, id: &str, actions: &mut Vec<Action>) {
    let muted = doc.node(id).is_some_and(|n| n.muted);
    let mute = match muted {
        true => "Unmute  (M)",
        false => "Mute  (M)",
    };
    let top = doc.body().is_none();
    let entries = [
        (NodeCommand::Mute, mute, doc.node(id).is_some()),
        (NodeCommand::Collapse, "Collapse / expand  (H)", true),
        (
            NodeCommand::JoinFrame,
            NodeCommand::JoinFrame.label(),
            top && doc.node(id).is_some(),
        ),
    ];
    for (c, label, enabled) in entries {
        if ui
            .add_enabled(enabled, egui::Button::new(label))
            .on_hover_text(c.help())
            .clicked()
        {
            actions.push(Action::Command(c, id.to_owned()));
            ui.close();
        }
    }
    if let Some(f) = super::frames::frame_of(doc.doc(), id).filter(|_| top) {
        if ui
            .button(NodeCommand::Unframe.label())
            .on_hover_text(NodeCommand::Unframe.help())
            .clicked()
        {
            actions.push(Action::Command(NodeCommand::Unframe, id.to_owned()));
            ui.close();
        }
        let name = match f.label.is_empty() {
            true => f.id.clone(),
            false => f.label.clone(),
        };
        if ui
            .button(format!("Frame '{name}'…"))
            .on_hover_text("its panel: rename it, or remove it (its nodes stay)")
            .clicked()
        {
            actions.push(Action::Focus(super::frames::focus_of(&f.id)));
            ui.close();
        }
    }
}

/// View → Keymap: the keymaps, the one in use ticked; hovering one lists its bindings.
pub fn keymap_menu(ui: &mut Ui, state: &mut EditorState) {
    ui.menu_button("Keymap", |ui| {
        let current = state.settings.keymap();
        for k in Keymap::ALL {
            let text: Vec<String> = BINDINGS
                .iter()
                .map(|b| {
                    let how = match k {
                        Keymap::Blender => b.blender,
                        Keymap::Classic => b.classic,
                    };
                    format!("{}: {how}", b.action)
                })
                .collect();
            if ui
                .radio(current == k, k.label())
                .on_hover_text(text.join("\n"))
                .clicked()
            {
                state.set_keymap(k);
                ui.close();
            }
        }
    });
}

/// The nodes a command from node `id`'s menu acts on: the selection when `id` is in it,
/// else `id` alone (as Blender's menus act on the selection).
pub fn targets(state: &EditorState, id: &str) -> Vec<String> {
    match state.selection.contains(id) {
        true => state.selection.ids().to_vec(),
        false => vec![id.to_owned()],
    }
}
