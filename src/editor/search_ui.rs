//! The add-node search window (Shift+A, Tab, right-click on the canvas, or a wire dropped in
//! empty space): type to filter, Up/Down to move, Enter or a click to add, Escape to close.

use super::outputs::{OUTPUT_NODE, OUTPUT_TITLE};
use super::search::{Hit, WireFilter, compatible_port, search_all};
use crate::registry::Registry;
use egui::{Key, Ui};

/// The open search.
#[derive(Clone, Debug, PartialEq)]
pub struct SearchState {
    /// The query typed so far.
    pub query: String,
    /// Where the new node goes, in canvas coordinates.
    pub pos: [f32; 2],
    /// The dropped wire the new node connects to: node id, port name, filter.
    pub wire: Option<(String, String, WireFilter)>,
    /// The highlighted result.
    pub selected: usize,
}

/// What the user picked: the node type and, for a dropped wire, the port of it to connect.
#[derive(Clone, Debug, PartialEq)]
pub struct Pick {
    /// The node type's name ([`OUTPUT_NODE`] for the Material Output node).
    pub type_name: String,
    /// The index of the new node's port the wire connects to.
    pub port: Option<usize>,
}

/// Most results listed.
pub const MAX_RESULTS: usize = 14;

/// Shows the search; returns the pick, or `Err(())` when it was closed without one.
pub fn show(ui: &mut Ui, s: &mut SearchState, registry: &Registry) -> Option<Result<Pick, ()>> {
    let filter = s.wire.as_ref().map(|w| w.2);
    if let Some(f) = filter {
        ui.label(match f {
            WireFilter::InputAccepting(t) => format!("nodes with an input taking {t}"),
            WireFilter::OutputFeeding(t) => format!("nodes with an output for {t}"),
        });
    }
    let edit = ui.add(
        egui::TextEdit::singleline(&mut s.query)
            .hint_text("search nodes")
            .id(egui::Id::new("matgraph-search-query")),
    );
    edit.request_focus();
    let hits = search_all(registry, &s.query, filter);
    let (down, up, enter, escape) = ui.input(|i| {
        (
            i.key_pressed(Key::ArrowDown),
            i.key_pressed(Key::ArrowUp),
            i.key_pressed(Key::Enter),
            i.key_pressed(Key::Escape),
        )
    });
    if escape {
        return Some(Err(()));
    }
    if edit.changed() {
        s.selected = 0;
    }
    if down {
        s.selected = (s.selected + 1).min(hits.len().saturating_sub(1));
    }
    if up {
        s.selected = s.selected.saturating_sub(1);
    }
    let pick = |k: usize| match &hits[k] {
        Hit::Type(t) => Pick {
            type_name: t.name().to_owned(),
            port: filter.and_then(|f| compatible_port(t, f)),
        },
        Hit::Output => Pick {
            type_name: OUTPUT_NODE.to_owned(),
            port: None,
        },
    };
    if enter && !hits.is_empty() {
        return Some(Ok(pick(s.selected.min(hits.len() - 1))));
    }
    let mut chosen = None;
    egui::ScrollArea::vertical()
        .max_height(320.0)
        .show(ui, |ui| {
            for (k, hit) in hits.iter().enumerate().take(MAX_RESULTS) {
                let (text, hover) = match hit {
                    Hit::Type(t) => (format!("{}   ({})", t.name(), t.category()), t.summary()),
                    Hit::Output => (
                        format!("{OUTPUT_TITLE}   (output)"),
                        "the graph's outputs (one per graph)",
                    ),
                };
                let r = ui
                    .selectable_label(k == s.selected, text)
                    .on_hover_text(hover);
                if r.clicked() {
                    chosen = Some(k);
                }
            }
            if hits.len() > MAX_RESULTS {
                ui.weak(format!("… {} more", hits.len() - MAX_RESULTS));
            }
            if hits.is_empty() {
                ui.weak("no node matches");
            }
        });
    chosen.map(|k| Ok(pick(k)))
}
