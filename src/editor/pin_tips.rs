//! Pins that read in full and say what they are: where egui-snarl places them, and the
//! tooltip of each (its port's type, unit, ranges and doc, from the node type's
//! declaration or the group's interface).
//!
//! egui-snarl 0.12 places pins inside the node frame by default ([`PinPlacement::Inside`]):
//! before an output's label it reserves the pin's width with a rect that starts at the
//! right-to-left cursor and runs to its *right*, out of the row. So each output label sat
//! under its pin, and each row widened the outputs' column by a pin's width, pushing the
//! next label further right, past the node's edge, where it was clipped: the geometry node
//! showed `positio`, `norm`, a sliver of `view` and nothing of `light`, `uv` or the rest.
//! On the frame's edge ([`PLACEMENT`], as Blender draws pins) no width is reserved (the
//! frame's 6-point margin is wider than half a pin), the labels end before the margin and
//! the column keeps its width.
//!
//! egui-snarl gives a viewer no response for a pin, and a hover region added while a pin's
//! row is drawn lies under the pin's own (added after the row), which egui does not hover
//! through; nor does it hover through the click region egui-snarl lays over the whole
//! canvas while the pointer is on a wire (and a wire starts at each linked pin). So
//! [`PinRows`] notes each row as it is drawn, and once the node is drawn
//! ([`egui_snarl::ui::SnarlViewer::final_node_rect`]) a region goes over each pin, sensing
//! only hover (drags and clicks still reach the pin), whose tooltip shows while the pointer
//! rests in it.

use super::entry;
use super::ports::Port;
use crate::types::SocketType;
use egui::{Rect, Ui};
use egui_snarl::NodeId;
use egui_snarl::ui::PinPlacement;

/// Where the canvas places its pins: on the node frame's edge.
pub const PLACEMENT: PinPlacement = PinPlacement::Edge;

/// The tooltip of a pin of port `port` (an input's, else an output's), whose type is `ty`
/// where known (a generic port's is its node's inferred `T`): its name, type and unit, an
/// input's default, slider range and hard range, and its doc.
pub fn tip(port: &Port, ty: Option<SocketType>, input: bool) -> String {
    let ty = ty.map_or("T (not inferred yet)".to_owned(), |t| t.name().to_owned());
    let side = if input { "input" } else { "output" };
    let mut s = format!("{}: {ty} {side}", port.name);
    if !port.unit.is_empty() {
        s.push_str(&format!(", in {}", port.unit));
    }
    if input {
        if !port.choices.is_empty() {
            s.push_str(&format!("\none of: {}", port.choices.join(", ")));
        }
        if let Some(r) = &port.soft
            && port.choices.is_empty()
        {
            s.push_str(&format!("\nslider range: {}", entry::range(r)));
        }
        match &port.hard {
            Some(r) if port.choices.is_empty() => s.push_str(&format!(
                "\nhard range: {} (a value outside is refused)",
                entry::range(r)
            )),
            None if port.choices.is_empty() => s.push_str("\nhard range: none"),
            _ => {}
        }
    }
    if !port.doc.is_empty() {
        s.push('\n');
        s.push_str(&port.doc);
    }
    s
}

/// A pin's row as egui-snarl laid it out: its node, side, index and the row's rect
/// (canvas points).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PinRow {
    /// The node.
    pub node: NodeId,
    /// An input pin (else an output pin).
    pub input: bool,
    /// Its index among the node's inputs or outputs.
    pub index: usize,
    /// The row's rect.
    pub rect: Rect,
}

/// The pin rows drawn this frame, until their node is drawn.
#[derive(Clone, Debug, Default)]
pub struct PinRows {
    rows: Vec<PinRow>,
}

impl PinRows {
    /// Notes the row `ui` lays out for pin `index` of `node` (called as the row is drawn).
    pub fn note(&mut self, node: NodeId, input: bool, index: usize, ui: &Ui) {
        self.rows.push(PinRow {
            node,
            input,
            index,
            rect: ui.max_rect(),
        });
    }

    /// Puts a hover region over each pin noted for `node`, whose frame egui-snarl drew at
    /// `frame`, in `ui` (the node's), with the tooltip `text` gives for it (side, index);
    /// forgets the node's rows. A pin is on the frame's edge ([`PLACEMENT`]), centred on
    /// its row, `pin` points wide.
    pub fn hover(
        &mut self,
        node: NodeId,
        frame: Rect,
        pin: f32,
        ui: &mut Ui,
        mut text: impl FnMut(bool, usize) -> Option<String>,
    ) {
        let (mine, rest): (Vec<PinRow>, Vec<PinRow>) =
            self.rows.drain(..).partition(|r| r.node == node);
        self.rows = rest;
        for r in mine {
            let x = if r.input { frame.left() } else { frame.right() };
            let at = egui::pos2(x, r.rect.center().y);
            let area = Rect::from_center_size(at, egui::vec2(pin * 1.5, pin * 1.5));
            let id = egui::Id::new(("matgraph-pin-tip", node, r.input, r.index));
            let response = ui.interact(area, id, egui::Sense::hover());
            // Not `response.hovered()`: a wire under the pointer (one leaves each linked
            // pin) makes egui-snarl add a click region over the whole canvas, on top.
            let resting = !ui.input(|i| i.pointer.any_down());
            if resting
                && pointer_in(ui, area)
                && let Some(t) = text(r.input, r.index)
            {
                response.show_tooltip_ui(|ui| {
                    ui.label(t);
                });
            }
        }
    }
}

/// Whether the pointer is over `rect` (in `ui`'s layer, which egui-snarl transforms) within
/// `ui`'s clip rect, and no window, menu or popup covers it. (`Ui::rect_contains_pointer`
/// asks for the top layer under the pointer to be `ui`'s, and egui-snarl's canvas is a
/// sublayer, never the top one.)
fn pointer_in(ui: &Ui, rect: Rect) -> bool {
    let ctx = ui.ctx();
    let to_global = ctx
        .layer_transform_to_global(ui.layer_id())
        .unwrap_or_default();
    let rect = to_global * rect.intersect(ui.clip_rect());
    let order = ui.layer_id().order;
    ctx.pointer_hover_pos()
        .is_some_and(|p| rect.contains(p) && ctx.layer_id_at(p).is_none_or(|l| l.order <= order))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::node::{PortType, Range};
    use crate::value::Value;
    use std::borrow::Cow;

    #[test]
    fn a_pins_tip_holds_its_type_unit_ranges_and_doc() {
        let p = Port {
            name: Cow::Borrowed("thickness_nm"),
            ty: PortType::Fixed(SocketType::Float),
            default: Value::float(400.0),
            soft: Some(Range {
                min: 0.0,
                max: 2000.0,
            }),
            hard: Some(Range {
                min: 0.0,
                max: 10000.0,
            }),
            unit: Cow::Borrowed("nm"),
            doc: Cow::Borrowed("Film thickness."),
            choices: &[],
        };
        assert_eq!(
            tip(&p, Some(SocketType::Float), true),
            "thickness_nm: float input, in nm\nslider range: 0 … 2000\n\
             hard range: 0 … 10000 (a value outside is refused)\nFilm thickness."
        );
        let out = Port {
            soft: None,
            hard: None,
            ..p.clone()
        };
        assert_eq!(
            tip(&out, None, false),
            "thickness_nm: T (not inferred yet) output, in nm\nFilm thickness."
        );
        let any = Port {
            soft: Some(Range {
                min: -1.0,
                max: 1.0,
            }),
            hard: None,
            unit: Cow::Borrowed(""),
            ..p
        };
        assert_eq!(
            tip(&any, Some(SocketType::Vec3), true),
            "thickness_nm: vec3 input\nslider range: −1 … 1\nhard range: none\nFilm thickness."
        );
    }
}
