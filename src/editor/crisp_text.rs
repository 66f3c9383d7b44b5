//! The canvas' text rasterised at the zoom it is shown at.
//!
//! egui-snarl zooms the canvas with a layer transform, and egui lays text out (and
//! rasterises its glyphs) at the context's pixels per point, so a zoomed canvas showed its
//! glyphs as images scaled by the zoom. Scaled down without mipmaps, a stroke one texel
//! thick is sampled between texels or missed: at 0.5× and 0.68× the minus sign of −1.00
//! (and the decimal point) vanished and `-1.00` read `1.00`; scaled up, text blurred.
//!
//! [`CrispText::apply`] runs once egui-snarl has painted: every text shape of the canvas'
//! layer gets its galley laid out again from the same job at `pixels_per_point × zoom`, so
//! its glyphs are rasterised at the size they take on screen, one texel per pixel. The
//! galley's size in points stays the same (the layer transform scales it as before), so
//! nothing moves; its glyphs are sharp. The zoom is rounded to [`STEPS_PER_OCTAVE`] steps
//! per octave so that zooming does not fill the font atlas with every size on the way (a
//! glyph is then scaled by at most 2.2 %, which no stroke vanishes in); at 1× nothing is
//! laid out again.

use egui::epaint::text::{Galley, LayoutJob};
use egui::layers::ShapeIdx;
use egui::{Context, LayerId, Shape};
use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::sync::Arc;

/// Zoom steps per doubling at which text is rasterised.
pub const STEPS_PER_OCTAVE: f32 = 16.0;

/// `zoom` rounded to [`STEPS_PER_OCTAVE`] steps per octave (1 stays 1).
pub fn raster_zoom(zoom: f32) -> f32 {
    if !(zoom.is_finite() && zoom > 0.0) {
        return 1.0;
    }
    ((zoom.log2() * STEPS_PER_OCTAVE).round() / STEPS_PER_OCTAVE).exp2()
}

/// The galleys laid out at the canvas' zoom, kept from one frame to the next.
#[derive(Default)]
pub struct CrispText {
    /// Galleys by their job, raster zoom and pixels per point ([`key`]).
    cache: HashMap<u64, Arc<Galley>>,
    /// The keys used this frame (the others are dropped after it).
    used: HashMap<u64, Arc<Galley>>,
    /// The font atlas' fill after the last pass: less at the next one means egui
    /// recreated its fonts (its atlas full, or new font definitions), and the galleys kept
    /// point at glyphs no longer there.
    fill: f32,
}

impl CrispText {
    /// Lays out again, at `zoom`, the text shapes that layer `layer` holds from index
    /// `from` on; how many were laid out again (0 at a raster zoom of 1).
    pub fn apply(&mut self, ctx: &Context, layer: LayerId, from: ShapeIdx, zoom: f32) -> usize {
        let zoom = raster_zoom(zoom);
        let ppp = ctx.pixels_per_point();
        let fill = ctx.fonts(|f| f.font_atlas_fill_ratio());
        if fill < self.fill {
            self.cache.clear();
        }
        if zoom == 1.0 {
            self.cache.clear();
            self.fill = fill;
            return 0;
        }
        let mut shapes = Vec::new();
        let end = ctx.graphics(|g| g.get(layer).map_or(0, |l| l.next_idx().0));
        ctx.graphics(|g| {
            if let Some(list) = g.get(layer) {
                for (k, c) in list.all_entries().enumerate().skip(from.0) {
                    if has_text(&c.shape) {
                        shapes.push((k, c.shape.clone()));
                    }
                }
            }
        });
        let mut n = 0;
        for (_, shape) in &mut shapes {
            n += self.relayout(ctx, shape, ppp, zoom);
        }
        ctx.graphics_mut(|g| {
            if let Some(list) = g.get_mut(layer) {
                for (k, shape) in shapes {
                    if k < end {
                        list.mutate_shape(ShapeIdx(k), |c| c.shape = shape);
                    }
                }
            }
        });
        self.cache = std::mem::take(&mut self.used);
        self.fill = ctx.fonts(|f| f.font_atlas_fill_ratio());
        n
    }

    /// Lays out the text of `shape` (and of the shapes it holds) at `ppp × zoom`.
    fn relayout(&mut self, ctx: &Context, shape: &mut Shape, ppp: f32, zoom: f32) -> usize {
        match shape {
            Shape::Text(t) => {
                t.galley = self.galley(ctx, &t.galley.job, ppp, zoom);
                1
            }
            Shape::Vec(v) => v.iter_mut().map(|s| self.relayout(ctx, s, ppp, zoom)).sum(),
            _ => 0,
        }
    }

    /// `job` laid out at `ppp × zoom`, marked as laid out at `ppp` (the tessellator's, which
    /// it checks); from the cache where it was laid out before.
    fn galley(&mut self, ctx: &Context, job: &Arc<LayoutJob>, ppp: f32, zoom: f32) -> Arc<Galley> {
        let key = key(job, ppp, zoom);
        if let Some(g) = self.used.get(&key).or_else(|| self.cache.get(&key)) {
            let g = g.clone();
            self.used.insert(key, g.clone());
            return g;
        }
        let mut galley =
            ctx.fonts_mut(|f| egui::epaint::text::layout(f.fonts, ppp * zoom, job.clone()));
        galley.pixels_per_point = ppp;
        let galley = Arc::new(galley);
        self.used.insert(key, galley.clone());
        galley
    }
}

/// Whether `shape` is or holds text.
fn has_text(shape: &Shape) -> bool {
    match shape {
        Shape::Text(_) => true,
        Shape::Vec(v) => v.iter().any(has_text),
        _ => false,
    }
}

/// The cache key of `job` laid out at `ppp × zoom`.
fn key(job: &LayoutJob, ppp: f32, zoom: f32) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    job.hash(&mut h);
    ppp.to_bits().hash(&mut h);
    zoom.to_bits().hash(&mut h);
    h.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_raster_zoom_is_the_zoom_in_sixteenth_octaves() {
        assert_eq!(raster_zoom(1.0), 1.0);
        assert_eq!(raster_zoom(0.5), 0.5);
        assert_eq!(raster_zoom(2.0), 2.0);
        for z in [0.3f32, 0.43, 0.68, 0.99, 1.01, 1.7] {
            let r = raster_zoom(z);
            assert!((r / z - 1.0).abs() <= 0.022, "{z} → {r}");
        }
        assert_eq!(raster_zoom(1.01), 1.0);
        assert_eq!(raster_zoom(f32::NAN), 1.0);
    }
}
