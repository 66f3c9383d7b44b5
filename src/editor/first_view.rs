//! Where the canvas looks when a graph opens, and zooming about the canvas' centre.
//!
//! egui-snarl scales the canvas with a layer transform: text is rasterised at 1× and the
//! glyphs scaled as images, so below 1× thin strokes (a minus sign, a decimal point) fade
//! or vanish and above it they blur. A graph therefore opens at [`OPEN_ZOOM`] (1×): framed
//! whole and centred where it fits, else at 1× on its *outputs' end* — the right end of the
//! graph (where the Material Output node is drawn), with the Material Output node (or the
//! rightmost nodes) centred vertically as far as the graph's extent allows. A material is
//! read back from its result, and the nodes left of the view are a pan away; Home (View →
//! Frame all) still shows the whole graph at any zoom.

use egui::emath::TSTransform;
use egui::{Rect, Vec2};

/// The zoom a graph opens at, and File → New and View → Zoom 1:1 set.
pub const OPEN_ZOOM: f32 = 1.0;

/// Screen points kept between the framed nodes and the canvas' edges.
pub const MARGIN: f32 = 30.0;

/// The zoom range of "Frame all" (egui-snarl's own default range is 0.1–2).
pub const FIT_RANGE: std::ops::RangeInclusive<f32> = 0.1..=1.0;

/// The canvas → screen transform that shows `nodes` (canvas) whole in `canvas` (screen),
/// with [`MARGIN`], zoomed in [`FIT_RANGE`]; `None` with nothing to frame.
pub fn frame_all(nodes: Rect, canvas: Rect) -> Option<TSTransform> {
    if !nodes.is_positive() || !canvas.is_positive() {
        return None;
    }
    let nodes = nodes.expand(MARGIN);
    let scale = (canvas.size() / nodes.size())
        .min_elem()
        .clamp(*FIT_RANGE.start(), *FIT_RANGE.end());
    Some(centred(nodes.center(), canvas, scale))
}

/// The transform a graph opens with, its nodes' rects (canvas) being `nodes`: framed whole
/// at [`OPEN_ZOOM`] where they fit in `canvas` (screen), else at [`OPEN_ZOOM`] with the
/// graph's right end (its outputs') at the canvas' right edge, less [`MARGIN`], and the
/// nodes in that view centred vertically, as far as the graph's extent allows (no empty
/// canvas above or below a graph taller than the view). `None` with nothing to frame.
pub fn opening(nodes: &[Rect], canvas: Rect) -> Option<TSTransform> {
    let all = nodes.iter().fold(Rect::NOTHING, |a, r| a.union(*r));
    if !all.is_positive() || !canvas.is_positive() {
        return None;
    }
    let graph = all.expand(MARGIN / OPEN_ZOOM);
    let view = canvas.size() / OPEN_ZOOM;
    let x = match graph.width() <= view.x {
        true => graph.center().x,
        false => graph.max.x - view.x / 2.0,
    };
    let y = match graph.height() <= view.y {
        true => graph.center().y,
        false => {
            // The nodes the view shows (across its width), centred.
            let band = egui::Rangef::new(x - view.x / 2.0, x + view.x / 2.0);
            let shown = nodes
                .iter()
                .filter(|r| r.x_range().intersects(band))
                .fold(Rect::NOTHING, |a, r| a.union(*r));
            shown
                .center()
                .y
                .clamp(graph.min.y + view.y / 2.0, graph.max.y - view.y / 2.0)
        }
    };
    Some(centred(egui::pos2(x, y), canvas, OPEN_ZOOM))
}

/// The transform at `scale` that puts canvas point `at` at the centre of `canvas`.
pub fn centred(at: egui::Pos2, canvas: Rect, scale: f32) -> TSTransform {
    let translation: Vec2 = canvas.center().to_vec2() - at.to_vec2() * scale;
    TSTransform::new(translation, scale)
}

/// `to_screen` zoomed to `scale` about the centre of `canvas` (the canvas point there
/// stays there).
pub fn zoomed(to_screen: TSTransform, canvas: Rect, scale: f32) -> TSTransform {
    let at = to_screen.inverse() * canvas.center();
    centred(at, canvas, scale)
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::{pos2, vec2};

    fn canvas() -> Rect {
        Rect::from_min_size(pos2(0.0, 20.0), vec2(1000.0, 800.0))
    }

    #[test]
    fn a_graph_that_fits_opens_centred_at_1x() {
        let nodes = [
            Rect::from_min_size(pos2(100.0, 100.0), vec2(200.0, 300.0)),
            Rect::from_min_size(pos2(400.0, 100.0), vec2(100.0, 100.0)),
        ];
        let t = opening(&nodes, canvas()).unwrap();
        assert_eq!(t.scaling, 1.0);
        assert_eq!(t * pos2(300.0, 250.0), canvas().center());
        assert_eq!(opening(&[], canvas()), None);
    }

    #[test]
    fn a_large_graph_opens_at_1x_on_its_outputs_end() {
        // 3000 × 2000 canvas points: the right end at the right edge, the nodes there
        // (y 900–1100) centred vertically.
        let nodes = [
            Rect::from_min_size(pos2(0.0, 0.0), vec2(200.0, 2000.0)),
            Rect::from_min_size(pos2(2500.0, 900.0), vec2(200.0, 100.0)),
            Rect::from_min_size(pos2(2800.0, 1000.0), vec2(200.0, 100.0)),
        ];
        let t = opening(&nodes, canvas()).unwrap();
        assert_eq!(t.scaling, 1.0);
        let right = t * pos2(3000.0, 1000.0);
        assert_eq!(right.x, canvas().max.x - MARGIN);
        assert_eq!(right.y, canvas().center().y);
        // Nodes there at the top: the view starts at the graph's top (less the margin).
        let nodes = [
            Rect::from_min_size(pos2(0.0, 0.0), vec2(200.0, 2000.0)),
            Rect::from_min_size(pos2(2800.0, 0.0), vec2(200.0, 100.0)),
        ];
        let t = opening(&nodes, canvas()).unwrap();
        assert_eq!((t * pos2(0.0, 0.0)).y, canvas().min.y + MARGIN);
    }

    #[test]
    fn frame_all_shrinks_to_fit_and_zoom_keeps_the_centre() {
        let nodes = Rect::from_min_size(pos2(0.0, 0.0), vec2(3000.0, 2000.0));
        let t = frame_all(nodes, canvas()).unwrap();
        assert!(t.scaling < 0.4, "{t:?}");
        let z = zoomed(t, canvas(), 2.0);
        assert_eq!(z.scaling, 2.0);
        let c = canvas().center();
        assert!(((z * (t.inverse() * c)) - c).length() < 1e-3);
    }
}
