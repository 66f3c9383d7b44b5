//! The canvas overview, below [`super::viewer::LOW_DETAIL_ZOOM`]: each node's pins are
//! painted in a body of the node's estimated full-detail size ([`super::layout::node_size`])
//! and the wires between them are painted behind the nodes, all without widgets.
//!
//! egui-snarl 0.12 gives every pin a child `Ui`, an interaction and a scan of every wire
//! for its remotes; on a 300-node graph framed whole that was half of the frame
//! (benches/editor.rs). Unreal's graph editor draws its lowest level of detail the same
//! way. Zoomed this far out a pin is 3 pixels, too small to aim a wire at: the overview
//! keeps selecting, moving, box selection and the node menus (egui-snarl's, on the node
//! frames), and wires are made and removed zoomed in.

use super::layout::{INPUT_ROW, OUTPUT_ROW};
use egui::layers::ShapeIdx;
use egui::{Color32, Painter, Pos2, Rect, Shape, Stroke, pos2, vec2};
use egui_snarl::ui::PinShape;
use egui_snarl::{InPinId, NodeId, OutPinId};
use std::collections::HashMap;

/// Where one node's pins sit in the overview: the rect of its body, canvas points. Input
/// `k` is on the body's left edge in row `k` of [`INPUT_ROW`]s, output `k` on its right
/// edge in row `k` of [`OUTPUT_ROW`]s, as the rows of the full-detail node are estimated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body(pub Rect);

impl Body {
    /// The centre of input pin `k`.
    pub fn input(&self, k: usize) -> Pos2 {
        pos2(self.0.left(), self.0.top() + (k as f32 + 0.5) * INPUT_ROW)
    }

    /// The centre of output pin `k`.
    pub fn output(&self, k: usize) -> Pos2 {
        pos2(self.0.right(), self.0.top() + (k as f32 + 0.5) * OUTPUT_ROW)
    }
}

/// A pin as the overview paints it: egui-snarl's shapes (circle for fixed types, square
/// for generic ones) at `centre`, `side` across.
pub fn pin_shape(shape: PinShape, centre: Pos2, side: f32, fill: Color32) -> Shape {
    match shape {
        PinShape::Square => {
            Shape::rect_filled(Rect::from_center_size(centre, vec2(side, side)), 0.0, fill)
        }
        _ => Shape::circle_filled(centre, side * 0.5, fill),
    }
}

/// A wire from an output pin at `from` to an input pin at `to`: a cubic Bézier that leaves
/// and enters horizontally, its handles half the horizontal distance long and at least
/// `frame` (egui-snarl's wire frame, so a wire running backwards loops round as there),
/// drawn as a line through `segments` + 1 points on it. (egui flattens a Bézier shape to
/// within a tenth of a pixel: a third of the tessellation of a 300-node graph framed
/// whole, for wires a few pixels long.)
pub fn wire_shape(from: Pos2, to: Pos2, frame: f32, segments: usize, stroke: Stroke) -> Shape {
    let handle = ((to.x - from.x).abs() * 0.5).max(frame);
    let [p0, p1, p2, p3] = [
        from.to_vec2(),
        (from + vec2(handle, 0.0)).to_vec2(),
        (to - vec2(handle, 0.0)).to_vec2(),
        to.to_vec2(),
    ];
    let n = segments.max(1);
    let points = (0..=n)
        .map(|k| {
            let t = k as f32 / n as f32;
            let s = 1.0 - t;
            (p0 * (s * s * s) + p1 * (3.0 * s * s * t) + p2 * (3.0 * s * t * t) + p3 * (t * t * t))
                .to_pos2()
        })
        .collect();
    Shape::line(points, stroke)
}

/// Segments enough for a wire from `from` to `to` drawn at `scale` (canvas → screen) to
/// look smooth: one per 12 pixels of its control polygon, 2 to 24.
pub fn wire_segments(from: Pos2, to: Pos2, frame: f32, scale: f32) -> usize {
    let reach = (to.x - from.x).abs().max(frame) * 2.0 + (to.y - from.y).abs();
    ((reach * scale / 12.0).ceil() as usize).clamp(2, 24)
}

/// The overview of one frame: the bodies the nodes drew and the shape slots, behind the
/// nodes, that the wires and then the stand-ins ([`super::stand_in`]) fill once every node
/// is drawn.
#[derive(Default)]
pub struct Overview {
    bodies: HashMap<NodeId, Body>,
    slot: Option<(Painter, ShapeIdx)>,
    stand_ins: Option<ShapeIdx>,
}

impl Overview {
    /// Reserves the wires' and the stand-ins' places in `painter`'s layer (call before the
    /// nodes are drawn).
    pub fn reserve(&mut self, painter: &Painter) {
        self.slot = Some((painter.clone(), painter.add(Shape::Noop)));
        self.stand_ins = Some(painter.add(Shape::Noop));
    }

    /// Paints the stand-ins' `shapes` in their slot, and records their `bodies`.
    pub fn paint_stand_ins(&mut self, shapes: Vec<Shape>, bodies: Vec<(NodeId, Body)>) {
        if let (Some((painter, _)), Some(slot)) = (&self.slot, self.stand_ins) {
            painter.set(slot, Shape::Vec(shapes));
        }
        self.bodies.extend(bodies);
    }

    /// Records the body node `node` drew this frame.
    pub fn record(&mut self, node: NodeId, body: Body) {
        self.bodies.insert(node, body);
    }

    /// The body node `node` drew this frame.
    pub fn body(&self, node: NodeId) -> Option<Body> {
        self.bodies.get(&node).copied()
    }

    /// Paints `wires` (each with its stroke) between the bodies drawn this frame into the
    /// reserved slot, at `scale` (canvas → screen); wires with an end on a node not drawn are left out. Returns how many
    /// were painted.
    pub fn paint_wires(
        &self,
        wires: impl IntoIterator<Item = (OutPinId, InPinId, Stroke)>,
        frame: f32,
        scale: f32,
    ) -> usize {
        let Some((painter, slot)) = &self.slot else {
            return 0;
        };
        let shapes: Vec<Shape> = wires
            .into_iter()
            .filter_map(|(from, to, stroke)| {
                let a = self.body(from.node)?.output(from.output);
                let b = self.body(to.node)?.input(to.input);
                let segments = wire_segments(a, b, frame, scale);
                Some(wire_shape(a, b, frame, segments, stroke))
            })
            .collect();
        let n = shapes.len();
        painter.set(*slot, Shape::Vec(shapes));
        n
    }
}
