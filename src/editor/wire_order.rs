//! A fixed painting order for egui-snarl's wires.
//!
//! egui-snarl 0.12 keeps its wires in a `HashSet` whose hasher ahash seeds at random (once
//! per process, and again per set) and paints them in that set's order. Where two
//! anti-aliased wires cross, the one painted last blends over the other, so the same graph
//! was drawn differently from run to run: two screenshots of `pbr_gold` differed at 73 of
//! 1.26 M pixels, by up to 66/255, where the wires from `geo` cross. And as the editor hands
//! egui-snarl a new partial graph each frame ([`super::handoff`]), the crossings could
//! change from one frame to the next.
//!
//! egui-snarl paints all its wires as one `Shape::Vec`, added to its layer right after
//! `SnarlViewer::draw_background` returns. [`Slot::before_wires`], called at the end of
//! `draw_background`, notes the index that shape will take; [`Slot::sort`], once
//! `SnarlWidget::show` returned, sorts the wires in it by their end points.

use egui::layers::ShapeIdx;
use egui::{Context, LayerId, Painter, Pos2, Shape};
use std::cmp::Ordering;

/// Where egui-snarl's wires will be painted this frame: a layer and an index in it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slot {
    layer: LayerId,
    index: ShapeIdx,
}

impl Slot {
    /// The index of the next shape `painter` adds: egui-snarl's wires, when called last in
    /// `SnarlViewer::draw_background`.
    pub fn before_wires(painter: &Painter) -> Slot {
        let layer = painter.layer_id();
        let index = painter.ctx().graphics_mut(|g| g.entry(layer).next_idx());
        Slot { layer, index }
    }

    /// The layer egui-snarl paints in (the canvas'), and the index of its wires in it.
    pub fn place(&self) -> (LayerId, ShapeIdx) {
        (self.layer, self.index)
    }

    /// Sorts the wires painted at this slot ([`compare`]); how many there were (0 where
    /// the slot holds no `Shape::Vec`: nothing is changed then).
    pub fn sort(&self, ctx: &Context) -> usize {
        ctx.graphics_mut(|g| {
            let mut n = 0;
            if let Some(list) = g.get_mut(self.layer) {
                list.mutate_shape(self.index, |clipped| {
                    if let Shape::Vec(wires) = &mut clipped.shape {
                        wires.sort_by(compare);
                        n = wires.len();
                    }
                });
            }
            n
        })
    }
}

/// The order wires are painted in: by the first point, then the last (a wire's end points
/// fix its curve, and no two wires join the same pins), then by the bounding box for shapes
/// other than a line.
pub fn compare(a: &Shape, b: &Shape) -> Ordering {
    // The bounding box (a walk over the points) only where the ends tie.
    lexical(&ends(a), &ends(b)).then_with(|| {
        let (ra, rb) = (a.visual_bounding_rect(), b.visual_bounding_rect());
        lexical(
            &[ra.min.x, ra.min.y, ra.max.x, ra.max.y],
            &[rb.min.x, rb.min.y, rb.max.x, rb.max.y],
        )
    })
}

/// A wire's first and last points (x, y each); zero for a shape other than a line.
fn ends(s: &Shape) -> [f32; 4] {
    let ends: Option<(Pos2, Pos2)> = match s {
        Shape::Path(p) => p.points.first().zip(p.points.last()).map(|(a, b)| (*a, *b)),
        Shape::LineSegment { points, .. } => Some((points[0], points[1])),
        _ => None,
    };
    let (a, b) = ends.unwrap_or((Pos2::ZERO, Pos2::ZERO));
    [a.x, a.y, b.x, b.y]
}

/// Lexical order of two keys, by `f32::total_cmp`.
fn lexical(a: &[f32; 4], b: &[f32; 4]) -> Ordering {
    a.iter()
        .zip(b)
        .map(|(x, y)| x.total_cmp(y))
        .find(|o| o.is_ne())
        .unwrap_or(Ordering::Equal)
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::{Color32, Stroke, pos2};

    /// Wires painted in a shuffled order come out ordered by first point, then last point;
    /// a slot that holds no `Shape::Vec` is left as it is.
    #[test]
    fn the_wires_are_painted_in_the_order_of_their_end_points() {
        let ctx = Context::default();
        let line = |a: (f32, f32), b: (f32, f32)| {
            Shape::line(
                vec![pos2(a.0, a.1), pos2((a.0 + b.0) / 2.0, a.1), pos2(b.0, b.1)],
                Stroke::new(2.0, Color32::YELLOW),
            )
        };
        // The order wanted, by hand: first x, then first y, then last x, then last y.
        let wanted = [
            line((10.0, 50.0), (200.0, 20.0)),
            line((10.0, 50.0), (200.0, 90.0)),
            line((10.0, 80.0), (150.0, 10.0)),
            line((40.0, 5.0), (90.0, 5.0)),
            Shape::line_segment([pos2(40.0, 5.0), pos2(95.0, 0.0)], (1.0, Color32::RED)),
            line((300.0, -20.0), (400.0, 60.0)),
        ];
        let mut out = ctx.run_ui(egui::RawInput::default(), |ui| {
            let painter = ui.painter().clone();
            let slot = Slot::before_wires(&painter);
            let mut shuffled = wanted.to_vec();
            shuffled.swap(0, 5);
            shuffled.swap(1, 3);
            shuffled.swap(2, 4);
            painter.add(Shape::Vec(shuffled));
            assert_eq!(slot.sort(ui.ctx()), wanted.len());
            let painted = ctx.graphics(|g| {
                let entry = g.get(slot.layer).unwrap().all_entries().nth(slot.index.0);
                entry.unwrap().shape.clone()
            });
            let Shape::Vec(painted) = painted else {
                panic!("not the wires: {painted:?}");
            };
            assert_eq!(painted, wanted);
            // Not a Vec: nothing to sort, nothing changed.
            let other = Slot::before_wires(&painter);
            painter.add(line((1.0, 1.0), (2.0, 2.0)));
            assert_eq!(other.sort(ui.ctx()), 0);
        });
        // No renderer takes the font atlas (epaint asserts it is taken).
        out.textures_delta.clear();
    }
}
