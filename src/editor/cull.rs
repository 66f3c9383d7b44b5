//! Which nodes the canvas draws in full in a frame: those near the viewport. egui-snarl 0.12
//! lays out every node of its graph each frame, on screen or not: a 300-node graph viewed
//! at 0.6× drew all 300 with their labels and value editors, 18 ms a frame
//! (benches/editor.rs). A node off screen (a culled node) is drawn as an empty frame
//! instead, with only the pins its wires to drawn nodes need, so those wires still run
//! off the edge of the screen to it.

use egui::Rect;

/// Canvas points around the viewport within which a node counts as on screen: room for
/// the error of its estimated size ([`super::layout::node_size`], about 10 %), its preview
/// swatch and a frame's pan, so a node is drawn in full before it comes into view.
pub const MARGIN: f32 = 200.0;

/// How much of each node a frame draws, by document index.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Culling {
    /// `None`: drawn in full; `Some((inputs, outputs))`: culled, with that many pins.
    culled: Vec<Option<(usize, usize)>>,
}

/// A wire between two nodes, by document index: (source node, output, target node, input).
pub type Wire = (usize, usize, usize, usize);

impl Culling {
    /// The culling of a frame showing `viewport` (canvas points): `nodes` are the
    /// document index and estimated rect of each node on the canvas (an index given twice,
    /// for an id written twice, is drawn in full if either node is near the viewport),
    /// `count` the number of document nodes. A culled node keeps input pins up to the last
    /// that a wire from a drawn node reaches, and output pins up to the last that feeds a
    /// drawn node.
    pub fn new(
        viewport: Rect,
        count: usize,
        nodes: impl IntoIterator<Item = (usize, Rect)>,
        wires: impl IntoIterator<Item = Wire>,
    ) -> Culling {
        let near = viewport.expand(MARGIN);
        let mut shown = vec![false; count];
        for (k, rect) in nodes {
            if let Some(s) = shown.get_mut(k) {
                *s |= near.intersects(rect);
            }
        }
        let mut culled: Vec<Option<(usize, usize)>> =
            shown.iter().map(|&s| (!s).then_some((0, 0))).collect();
        for (from, output, to, input) in wires {
            let (Some(&a), Some(&b)) = (shown.get(from), shown.get(to)) else {
                continue;
            };
            if a && !b
                && let Some((inputs, _)) = &mut culled[to]
            {
                *inputs = (*inputs).max(input + 1);
            }
            if b && !a
                && let Some((_, outputs)) = &mut culled[from]
            {
                *outputs = (*outputs).max(output + 1);
            }
        }
        Culling { culled }
    }

    /// Whether document node `k` is culled (an index out of range is drawn in full).
    pub fn is_culled(&self, k: usize) -> bool {
        self.culled.get(k).is_some_and(Option::is_some)
    }

    /// The input pins document node `k` shows, of its `all`.
    pub fn inputs(&self, k: usize, all: usize) -> usize {
        match self.culled.get(k) {
            Some(Some((inputs, _))) => (*inputs).min(all),
            _ => all,
        }
    }

    /// The output pins document node `k` shows, of its `all`.
    pub fn outputs(&self, k: usize, all: usize) -> usize {
        match self.culled.get(k) {
            Some(Some((_, outputs))) => (*outputs).min(all),
            _ => all,
        }
    }
}
