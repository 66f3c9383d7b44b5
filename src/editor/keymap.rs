//! The editor's keymaps: "Blender" (the default: Blender's node editor habits) and "matgraph
//! classic" (the bindings the editor had before, kept where the two conflict). Both share
//! every key binding (M mutes, H collapses, Ctrl+J frames, Alt+P takes nodes out of their
//! frame, and the bindings [`BINDINGS`] lists as the same in both); they differ on the
//! pointer:
//!
//! | | Blender | matgraph classic |
//! | --- | --- | --- |
//! | mouse wheel | zooms about the pointer | pans (Ctrl+wheel zooms) |
//! | Ctrl+right-drag | cuts the wires it crosses | pans |
//! | Shift+right-drag | adds a reroute on each output's wires it crosses | pans |
//!
//! The choice is made in View → Keymap and kept in the editor's settings file
//! ([`super::settings`]).

use egui::{Context, Key, KeyboardShortcut, Modifiers};
use serde::{Deserialize, Serialize};

/// A set of bindings.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Keymap {
    /// Blender's node editor: the wheel zooms, Ctrl+right-drag cuts wires, Shift+right-drag
    /// adds reroutes.
    #[default]
    Blender,
    /// The editor's bindings before the Blender keymap: the wheel and right-drags pan.
    Classic,
}

impl Keymap {
    /// Every keymap, in the order the menu lists them.
    pub const ALL: [Keymap; 2] = [Keymap::Blender, Keymap::Classic];

    /// Its name in the menu.
    pub fn label(self) -> &'static str {
        match self {
            Keymap::Blender => "Blender",
            Keymap::Classic => "matgraph classic",
        }
    }

    /// Whether the plain mouse wheel zooms (else it pans, and Ctrl+wheel zooms).
    pub fn wheel_zooms(self) -> bool {
        self == Keymap::Blender
    }

    /// The line tool a right-drag begun with `modifiers` held draws, if any: Ctrl cuts,
    /// Shift adds reroutes (Blender's); none in the classic keymap, where it pans.
    pub fn line_tool(self, modifiers: Modifiers) -> Option<LineTool> {
        if self != Keymap::Blender || modifiers.alt {
            return None;
        }
        match (modifiers.command, modifiers.shift) {
            (true, false) => Some(LineTool::Cut),
            (false, true) => Some(LineTool::Reroute),
            _ => None,
        }
    }
}

/// What a line drawn with the right button does on release.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LineTool {
    /// Removes every wire it crosses (Blender's Cut Links, Ctrl+right-drag).
    Cut,
    /// Adds a reroute on the wires it crosses (Blender's Add Reroute, Shift+right-drag).
    Reroute,
}

/// A command on the selected nodes, bound to a key in both keymaps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NodeCommand {
    /// Mute or unmute each selected node (M).
    Mute,
    /// Collapse the selected nodes, or expand them where all are collapsed (H).
    Collapse,
    /// Put the selected nodes in a new frame (Ctrl+J).
    JoinFrame,
    /// Take the selected nodes out of their frames (Alt+P).
    Unframe,
}

impl NodeCommand {
    /// Every command, in the order the menus list them.
    pub const ALL: [NodeCommand; 4] = [
        NodeCommand::Mute,
        NodeCommand::Collapse,
        NodeCommand::JoinFrame,
        NodeCommand::Unframe,
    ];

    /// Its key.
    pub fn shortcut(self) -> KeyboardShortcut {
        match self {
            NodeCommand::Mute => KeyboardShortcut::new(Modifiers::NONE, Key::M),
            NodeCommand::Collapse => KeyboardShortcut::new(Modifiers::NONE, Key::H),
            NodeCommand::JoinFrame => KeyboardShortcut::new(Modifiers::COMMAND, Key::J),
            NodeCommand::Unframe => KeyboardShortcut::new(Modifiers::ALT, Key::P),
        }
    }

    /// Its name in the menus, with its key.
    pub fn label(self) -> &'static str {
        match self {
            NodeCommand::Mute => "Mute / unmute  (M)",
            NodeCommand::Collapse => "Collapse / expand  (H)",
            NodeCommand::JoinFrame => "Join in new frame  (Ctrl+J)",
            NodeCommand::Unframe => "Remove from frame  (Alt+P)",
        }
    }

    /// What it does, for the menus' hover text.
    pub fn help(self) -> &'static str {
        match self {
            NodeCommand::Mute => {
                "each selected node passes its first input of each output's type on (Blender's mute); saved as \"muted\""
            }
            NodeCommand::Collapse => {
                "only the header and the wired pins shown; all collapsed: expanded again"
            }
            NodeCommand::JoinFrame => "a new frame around the selected nodes (saved in \"frames\")",
            NodeCommand::Unframe => {
                "the selected nodes leave their frames; a frame left empty goes"
            }
        }
    }
}

/// Takes this frame's key presses of the node commands (the same in both keymaps), in the
/// order of [`NodeCommand::ALL`].
pub fn node_commands(ctx: &Context) -> Vec<NodeCommand> {
    ctx.input_mut(|i| {
        NodeCommand::ALL
            .into_iter()
            .filter(|c| i.consume_shortcut(&c.shortcut()))
            .collect()
    })
}

/// One binding as the docs and the keymap menu list it: the action, then how each keymap
/// does it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Binding {
    /// What it does.
    pub action: &'static str,
    /// In the Blender keymap.
    pub blender: &'static str,
    /// In the matgraph classic keymap.
    pub classic: &'static str,
}

/// Every binding of the canvas, in both keymaps (docs/editor.md's table lists the same).
pub const BINDINGS: &[Binding] = &[
    Binding {
        action: "zoom",
        blender: "wheel, Ctrl+wheel, pinch",
        classic: "Ctrl+wheel, pinch",
    },
    Binding {
        action: "pan",
        blender: "middle- or right-drag, Shift+wheel (sideways)",
        classic: "middle- or right-drag, wheel",
    },
    Binding {
        action: "cut wires",
        blender: "Ctrl+right-drag across them",
        classic: "right-click a pin, or drag the wire off",
    },
    Binding {
        action: "add reroutes",
        blender: "Shift+right-drag across wires",
        classic: "Shift+A → reroute",
    },
    Binding {
        action: "mute / unmute",
        blender: "M",
        classic: "M",
    },
    Binding {
        action: "collapse / expand",
        blender: "H",
        classic: "H",
    },
    Binding {
        action: "join in new frame",
        blender: "Ctrl+J",
        classic: "Ctrl+J",
    },
    Binding {
        action: "remove from frame",
        blender: "Alt+P",
        classic: "Alt+P",
    },
    Binding {
        action: "select / box-select",
        blender: "click, left-drag on the canvas",
        classic: "click, left-drag on the canvas",
    },
    Binding {
        action: "add node",
        blender: "Shift+A, Tab (at the top), right-click",
        classic: "Shift+A, Tab (at the top), right-click",
    },
    Binding {
        action: "group / ungroup / enter or leave",
        blender: "Ctrl+G / Alt+G / Tab",
        classic: "Ctrl+G / Alt+G / Tab",
    },
    Binding {
        action: "delete / duplicate",
        blender: "X or Delete / Shift+D",
        classic: "X or Delete / Shift+D",
    },
    Binding {
        action: "frame all",
        blender: "Home",
        classic: "Home",
    },
];

#[cfg(test)]
mod tests {
    use super::*;

    /// The line tools are Blender's only, Ctrl for cutting and Shift for reroutes; the
    /// wheel zooms in Blender's keymap only.
    #[test]
    fn only_the_blender_keymap_draws_lines_and_zooms_with_the_wheel() {
        let b = Keymap::Blender;
        assert_eq!(b.line_tool(Modifiers::COMMAND), Some(LineTool::Cut));
        assert_eq!(b.line_tool(Modifiers::SHIFT), Some(LineTool::Reroute));
        assert_eq!(b.line_tool(Modifiers::NONE), None);
        assert_eq!(b.line_tool(Modifiers::COMMAND | Modifiers::SHIFT), None);
        assert_eq!(b.line_tool(Modifiers::ALT | Modifiers::COMMAND), None);
        for m in [Modifiers::COMMAND, Modifiers::SHIFT, Modifiers::NONE] {
            assert_eq!(Keymap::Classic.line_tool(m), None);
        }
        assert!(b.wheel_zooms());
        assert!(!Keymap::Classic.wheel_zooms());
        assert_eq!(Keymap::default(), Keymap::Blender);
    }
}
