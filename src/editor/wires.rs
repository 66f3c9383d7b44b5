//! Where the canvas drew its pins and wires in a frame, and which wires a line drawn over
//! the canvas crosses (for cutting wires and adding reroutes, [`super::line_tool`]).
//!
//! egui-snarl 0.12 tells a viewer neither where it puts a pin nor the curve of a wire. So
//! each pin the viewer returns is wrapped in a [`RecordedPin`], which notes the rect
//! egui-snarl draws it in (its centre is where the pin's wires end), and the wires are read
//! back from the shape egui-snarl paints them in ([`super::wire_order::Slot`]): one polyline
//! per wire, from its output pin's centre to its input pin's. A wire is matched to its
//! polyline by those two ends, and a line crosses it where a segment of the line crosses a
//! segment of the polyline, as Blender's `link_path_intersection` tests a link's evaluated
//! bezier points (source/blender/editors/space_node/node_add.cc). Wires off screen are not
//! painted, and a line drawn on screen cannot cross them there.

use egui::{Color32, Painter, Pos2, Rect, Shape, Style};
use egui_snarl::ui::{PinInfo, PinWireInfo, SnarlPin, SnarlStyle};
use egui_snarl::{InPinId, NodeId, OutPinId};
use std::cell::RefCell;
use std::rc::Rc;

/// A pin drawn in a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PinAt {
    /// Its node on the canvas.
    pub node: NodeId,
    /// An input pin (else an output pin).
    pub input: bool,
    /// Its index among the node's inputs or outputs.
    pub index: usize,
    /// Its centre, canvas points: where its wires end.
    pub at: Pos2,
}

/// The pins drawn in a frame, noted as egui-snarl draws them (shared with the pins it is
/// handed, which it keeps only while it draws them).
#[derive(Clone, Debug, Default)]
pub struct PinPlaces(Rc<RefCell<Vec<PinAt>>>);

impl PinPlaces {
    /// `info` for pin `index` (an input's, else an output's) of `node`, noting where it
    /// is drawn.
    pub fn wrap(&self, node: NodeId, input: bool, index: usize, info: PinInfo) -> RecordedPin {
        RecordedPin {
            info,
            node,
            input,
            index,
            places: self.clone(),
        }
    }

    /// The pins drawn so far this frame.
    pub fn pins(&self) -> Vec<PinAt> {
        self.0.borrow().clone()
    }

    /// The pins of node `node` drawn so far.
    pub fn of(&self, node: NodeId) -> Vec<PinAt> {
        self.0
            .borrow()
            .iter()
            .filter(|p| p.node == node)
            .copied()
            .collect()
    }
}

/// A pin as the viewer describes it, which notes where egui-snarl draws it.
pub struct RecordedPin {
    info: PinInfo,
    node: NodeId,
    input: bool,
    index: usize,
    places: PinPlaces,
}

impl SnarlPin for RecordedPin {
    fn draw(
        self,
        snarl_style: &SnarlStyle,
        style: &Style,
        rect: Rect,
        painter: &Painter,
    ) -> PinWireInfo {
        self.places.0.borrow_mut().push(PinAt {
            node: self.node,
            input: self.input,
            index: self.index,
            at: rect.center(),
        });
        self.info.draw(snarl_style, style, rect, painter)
    }
}

/// The wires egui-snarl painted at `slot` this frame, each a polyline in canvas points from
/// its output pin to its input pin.
pub fn painted(ctx: &egui::Context, slot: super::wire_order::Slot) -> Vec<Vec<Pos2>> {
    let (layer, index) = slot.place();
    let shape = ctx.graphics(|g| {
        g.get(layer)
            .and_then(|l| l.all_entries().nth(index.0))
            .map(|e| e.shape.clone())
    });
    let Some(Shape::Vec(wires)) = shape else {
        return Vec::new();
    };
    wires
        .into_iter()
        .filter_map(|w| match w {
            Shape::Path(p) if p.points.len() >= 2 => Some(p.points),
            Shape::LineSegment { points, .. } => Some(points.to_vec()),
            _ => None,
        })
        .collect()
}

/// How far apart (canvas points) a pin's centre and a painted wire's end may be and still
/// be the same point (egui-snarl scales a hovered pin's rect about its centre).
pub const END_TOLERANCE: f32 = 0.05;

/// The wires of `wires` that `line` (canvas points) crosses, each with the first point where
/// it does (in the line's order, then the wire's), given the `pins` drawn this frame and the
/// wires `painted` (polylines from output to input pin), in the order the line crosses them
/// (egui-snarl lists its wires in a random hash order). A wire whose pins or polyline were
/// not drawn is not crossed.
pub fn crossed(
    line: &[Pos2],
    wires: &[(OutPinId, InPinId)],
    pins: &[PinAt],
    painted: &[Vec<Pos2>],
) -> Vec<(OutPinId, InPinId, Pos2)> {
    let at = |node: NodeId, input: bool, index: usize| {
        pins.iter()
            .rev()
            .find(|p| p.node == node && p.input == input && p.index == index)
            .map(|p| p.at)
    };
    let near = |a: Pos2, b: Pos2| (a - b).length() <= END_TOLERANCE;
    let mut out = Vec::new();
    for &(from, to) in wires {
        let (Some(a), Some(b)) = (
            at(from.node, false, from.output),
            at(to.node, true, to.input),
        ) else {
            continue;
        };
        let Some(curve) = painted
            .iter()
            .find(|p| near(p[0], a) && near(p[p.len() - 1], b))
        else {
            continue;
        };
        if let Some((along, x)) = first_crossing(line, curve) {
            out.push((along, from, to, x));
        }
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0).then((a.1, a.2).cmp(&(b.1, b.2))));
    out.into_iter().map(|(_, f, t, x)| (f, t, x)).collect()
}

/// The first point where polyline `a` crosses polyline `b` (by `a`'s segments, then `b`'s),
/// with how far along `a` it is (segment index plus the fraction of that segment).
pub fn first_crossing(a: &[Pos2], b: &[Pos2]) -> Option<(f32, Pos2)> {
    a.windows(2).enumerate().find_map(|(k, s)| {
        b.windows(2).find_map(|t| {
            let x = segment_crossing(s[0], s[1], t[0], t[1])?;
            let run = (s[1] - s[0]).length();
            let part = match run > 0.0 {
                true => (x - s[0]).length() / run,
                false => 0.0,
            };
            Some((k as f32 + part, x))
        })
    })
}

/// Where segments `p0 p1` and `q0 q1` cross, if they do (touching ends count; parallel
/// segments never cross).
pub fn segment_crossing(p0: Pos2, p1: Pos2, q0: Pos2, q1: Pos2) -> Option<Pos2> {
    let r = p1 - p0;
    let s = q1 - q0;
    let denom = r.x * s.y - r.y * s.x;
    if denom == 0.0 {
        return None;
    }
    let qp = q0 - p0;
    let t = (qp.x * s.y - qp.y * s.x) / denom;
    let u = (qp.x * r.y - qp.y * r.x) / denom;
    ((0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u)).then(|| p0 + r * t)
}

/// A line's colour on the canvas: the cut's red, the reroute line's pale blue.
pub fn line_color(cut: bool) -> Color32 {
    match cut {
        true => Color32::from_rgb(0xe0, 0x50, 0x40),
        false => Color32::from_rgb(0x90, 0xc0, 0xf0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::pos2;

    /// Segments cross where the closed form says; parallel and disjoint ones do not.
    #[test]
    fn segments_cross_where_they_meet() {
        // y = x and y = 10 - x meet at (5, 5).
        let x = segment_crossing(
            pos2(0.0, 0.0),
            pos2(10.0, 10.0),
            pos2(0.0, 10.0),
            pos2(10.0, 0.0),
        );
        assert_eq!(x, Some(pos2(5.0, 5.0)));
        // The second segment stops short of the first.
        let short = segment_crossing(
            pos2(0.0, 0.0),
            pos2(10.0, 10.0),
            pos2(0.0, 10.0),
            pos2(4.0, 6.0),
        );
        assert_eq!(short, None);
        let parallel = segment_crossing(
            pos2(0.0, 0.0),
            pos2(10.0, 0.0),
            pos2(0.0, 1.0),
            pos2(10.0, 1.0),
        );
        assert_eq!(parallel, None);
        // A vertical line at x = 3 crosses the polyline (0,0)-(2,4)-(6,0) on its second
        // segment, where y = 4 - (3 - 2) = 3.
        let line = [pos2(3.0, -10.0), pos2(3.0, 10.0)];
        let wire = [pos2(0.0, 0.0), pos2(2.0, 4.0), pos2(6.0, 0.0)];
        // Its point (3, 3) is 13/20 of the way down the line.
        assert_eq!(first_crossing(&line, &wire), Some((0.65, pos2(3.0, 3.0))));
    }

    /// A wire is matched to the polyline whose ends are its pins; one whose pins were not
    /// drawn is never crossed.
    #[test]
    fn wires_are_found_by_their_pins() {
        let pin = |node, input, index, x, y| PinAt {
            node: NodeId(node),
            input,
            index,
            at: pos2(x, y),
        };
        let pins = [
            pin(0, false, 0, 0.0, 0.0),
            pin(1, true, 0, 100.0, 0.0),
            pin(1, true, 1, 100.0, 40.0),
        ];
        let w = |a: usize, o: usize, b: usize, i: usize| {
            (
                OutPinId {
                    node: NodeId(a),
                    output: o,
                },
                InPinId {
                    node: NodeId(b),
                    input: i,
                },
            )
        };
        let wires = [w(0, 0, 1, 0), w(0, 0, 1, 1), w(0, 1, 1, 0)];
        let painted = vec![
            vec![pos2(0.0, 0.0), pos2(100.0, 0.0)],
            vec![pos2(0.0, 0.0), pos2(50.0, 20.0), pos2(100.0, 40.0)],
        ];
        let line = [pos2(50.0, -5.0), pos2(50.0, 10.0)];
        let got = crossed(&line, &wires, &pins, &painted);
        assert_eq!(got, vec![(wires[0].0, wires[0].1, pos2(50.0, 0.0))]);
        let longer = [pos2(50.0, -5.0), pos2(50.0, 30.0)];
        assert_eq!(crossed(&longer, &wires, &pins, &painted).len(), 2);
    }
}
