//! Which nodes the canvas hands egui-snarl in a frame. egui-snarl 0.12 gives every node of
//! its graph about seven child `Ui`s and their widget registration each frame, drawn or
//! culled ([`super::cull`]): a third of the frame of a 300-node graph framed whole
//! (benches/editor.rs). So each frame it gets a partial graph with the same node ids: the
//! nodes it must lay out (in view and zoomed in, selected, near the pointer, or holding a
//! wire to one in view), while the overview paints the others from how egui-snarl last drew
//! them ([`super::stand_in`]). The selected nodes (the editor's selection, by node id,
//! [`super::selection`]) are always handed over, so that they are drawn outlined and drag
//! together.

use super::view::NodeView;
use egui::Pos2;
use egui::emath::TSTransform;
use egui_snarl::{NodeId, Snarl};

/// Screen points around a node within which the pointer makes it handed over, so that it
/// is a widget a few frames before the pointer reaches it (egui hit-tests the last frame's
/// widgets).
pub const POINTER_REACH: f32 = 48.0;

/// egui-snarl's default zoom range (`SnarlStyle::get_min_scale`, `get_max_scale`).
pub const ZOOM_RANGE: (f32, f32) = (0.2, 2.0);

/// The transform egui-snarl will use this frame, as its pan and zoom (egui's `Scene`)
/// derive it from `last` and this frame's input: the zoom `zoom_delta` about the pointer
/// `pointer` (canvas → screen, when over `canvas`), then the scroll `scroll`. A drag pan
/// is left out: it moves the view by the pointer's motion, which [`super::cull::MARGIN`]
/// covers.
pub fn predict(
    last: TSTransform,
    zoom_delta: f32,
    scroll: egui::Vec2,
    pointer: Option<Pos2>,
    canvas: egui::Rect,
) -> TSTransform {
    let Some(pointer) = pointer.filter(|p| canvas.contains(*p)) else {
        return last;
    };
    let mut t = last;
    if zoom_delta != 1.0 {
        let (lo, hi) = ZOOM_RANGE;
        let zoom = zoom_delta.clamp(lo / t.scaling, hi / t.scaling);
        let at = (t.inverse() * pointer).to_vec2();
        t = t
            * TSTransform::from_translation(at)
            * TSTransform::from_scaling(zoom)
            * TSTransform::from_translation(-at);
        t.scaling = t.scaling.clamp(lo, hi);
    }
    TSTransform::from_translation(scroll) * t
}

/// A copy of `full` with only the nodes `keep` marks (by node id) and the wires between
/// them, each node under its id in `full`; `None` if egui-snarl's ids would not line up
/// (they are slab keys: a fresh slab hands out 0, 1, 2, …, and removing a node frees its
/// key).
pub fn partial(full: &Snarl<NodeView>, keep: &[bool]) -> Option<Snarl<NodeView>> {
    let last = full.node_ids().map(|(id, _)| id.0).max()?;
    let kept = |k: usize| keep.get(k).copied().unwrap_or(true);
    let mut part = Snarl::new();
    let mut stubs = Vec::new();
    for k in 0..=last {
        let node = full.get_node_info(NodeId(k)).filter(|_| kept(k));
        let id = match node {
            Some(n) => part.insert_node(n.pos, n.value.clone()),
            None => {
                let stub = part.insert_node(Pos2::ZERO, NodeView { id: String::new() });
                stubs.push(stub);
                stub
            }
        };
        if id != NodeId(k) {
            return None;
        }
    }
    for stub in stubs {
        part.remove_node(stub);
    }
    for (from, to) in full.wires() {
        if kept(from.node.0) && kept(to.node.0) {
            part.connect(from, to);
        }
    }
    Some(part)
}

/// Copies the positions of `part`'s nodes (moved this frame) back to `full`.
pub fn write_back(full: &mut Snarl<NodeView>, part: &Snarl<NodeView>) {
    for (id, pos, _) in part.nodes_pos_ids() {
        if let Some(n) = full.get_node_info_mut(id) {
            n.pos = pos;
        }
    }
}
