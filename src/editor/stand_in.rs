//! The overview's stand-ins: nodes egui-snarl was not handed this frame
//! ([`super::handoff`]), painted as it last drew them: their frame, header, title and body
//! relative to the node's position, kept per node while the node's look (its estimated
//! size, title, colours) stays the same. A node egui-snarl has not drawn twice alike with
//! its current look is handed over, and drawn by it, until it has.

use super::overview::Body;
use egui::{Color32, Galley, Pos2, Rect, Shape, Stroke, StrokeKind, Vec2};
use std::collections::HashMap;
use std::sync::Arc;

/// What a node's overview look depends on: its estimated full-detail size, its title (with
/// its error mark), its header's fill and its frame's outline.
#[derive(Clone, Debug, PartialEq)]
pub struct LookKey {
    /// Estimated size, canvas points.
    pub size: (f32, f32),
    /// The header's text.
    pub title: String,
    /// The header's fill.
    pub fill: Color32,
    /// The frame's outline.
    pub stroke: Stroke,
}

/// How egui-snarl drew a node in the overview, relative to the node's position.
#[derive(Clone, Debug)]
struct Look {
    key: LookKey,
    frame: Rect,
    header: Rect,
    title: (Vec2, Arc<Galley>),
    body: Rect,
    /// Whether egui-snarl drew it so twice in a row: it sizes a node's frame by what the
    /// node's content measured the frame before, so a node's first frame in the overview
    /// still has its full-detail width.
    settled: bool,
}

impl Look {
    /// Whether `self` and `other` place everything alike.
    fn same_place(&self, other: &Look) -> bool {
        self.key == other.key
            && self.frame == other.frame
            && self.header == other.header
            && self.title.0 == other.title.0
            && self.body == other.body
    }
}

/// The parts of a look recorded while egui-snarl draws a node.
#[derive(Clone, Debug, Default)]
struct Parts {
    header: Option<Rect>,
    title: Option<(Pos2, Arc<Galley>)>,
    body: Option<Rect>,
}

/// The looks of the nodes egui-snarl drew in the overview, by document index.
#[derive(Debug, Default)]
pub struct Looks {
    looks: HashMap<usize, Look>,
    parts: HashMap<usize, Parts>,
}

impl Looks {
    /// Records node `k`'s header content rect (canvas) and its title's galley at `at`.
    pub fn header(&mut self, k: usize, content: Rect, at: Pos2, galley: Arc<Galley>) {
        let p = self.parts.entry(k).or_default();
        p.header = Some(content);
        p.title = Some((at, galley));
    }

    /// Records node `k`'s body rect (canvas).
    pub fn body(&mut self, k: usize, body: Rect) {
        self.parts.entry(k).or_default().body = Some(body);
    }

    /// Records node `k`'s frame rect (canvas) at position `pos`, with the look `key`: its
    /// look is kept if its header and body were recorded since its last frame.
    pub fn frame(&mut self, k: usize, pos: Pos2, frame: Rect, key: LookKey) {
        let Some(Parts {
            header: Some(header),
            title: Some((at, galley)),
            body: Some(body),
        }) = self.parts.remove(&k)
        else {
            return;
        };
        let o = pos.to_vec2();
        let look = Look {
            key,
            frame: frame.translate(-o),
            header: header.translate(-o),
            title: (at - pos, galley),
            body: body.translate(-o),
            settled: false,
        };
        let settled = self.looks.get(&k).is_some_and(|l| l.same_place(&look));
        self.looks.insert(k, Look { settled, ..look });
    }

    /// Whether node `k` has a settled look recorded for `key`.
    pub fn has(&self, k: usize, key: &LookKey) -> bool {
        self.looks
            .get(&k)
            .is_some_and(|l| l.settled && &l.key == key)
    }

    /// Node `k`'s frame rect at `pos` (canvas), when it has a look.
    pub fn frame_at(&self, k: usize, pos: Pos2) -> Option<Rect> {
        self.looks.get(&k).map(|l| l.frame.translate(pos.to_vec2()))
    }

    /// Node `k` at `pos` as egui-snarl drew it in the overview: its frame (filled with
    /// `window`, the node frame's fill) with its header and title, and its body (where the
    /// caller paints its pins). The header's fill spans the frame's width and the header
    /// content with the frame's margin above and below it, as egui-snarl's header frame
    /// (the node frame without its shadow) does.
    pub fn paint(
        &self,
        k: usize,
        pos: Pos2,
        window: Color32,
        out: &mut Vec<Shape>,
    ) -> Option<Body> {
        let l = self.looks.get(&k)?;
        let o = pos.to_vec2();
        let frame = l.frame.translate(o);
        let content = l.header.translate(o);
        let margin = content.top() - frame.top();
        let header = Rect::from_min_max(
            frame.min,
            egui::pos2(frame.right(), content.bottom() + margin),
        );
        out.push(Shape::rect_filled(frame, 0.0, window));
        out.push(Shape::rect_filled(header, 0.0, l.key.fill));
        if l.key.stroke != Stroke::NONE {
            out.push(Shape::rect_stroke(
                frame,
                0.0,
                l.key.stroke,
                StrokeKind::Inside,
            ));
        }
        let (at, galley) = &l.title;
        out.push(Shape::galley(pos + *at, galley.clone(), Color32::WHITE));
        Some(Body(l.body.translate(o)))
    }
}
