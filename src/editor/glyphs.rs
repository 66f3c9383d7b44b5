//! Which characters the editor's fonts ([`super::fonts`]) cannot draw.
//!
//! egui draws a character no font of its family has as a replacement box (◻); the issue's
//! `geometry.view □ dot.b` was an arrow before Hack joined the proportional family.
//! egui 0.36's `has_glyph` cannot tell: it compares the font face that owns a character
//! with the face of the replacement box, so every character of that face (all of Hack's,
//! for the monospace family) reads as missing. [`missing`] lays each character out instead
//! and compares its glyph with the one drawn for a code point no font has.

use egui::{Color32, Context, FontFamily, FontId};

/// A code point no font has (the last of the supplementary private use area B).
const NO_GLYPH: char = '\u{10FFFD}';

/// The characters of `chars` (whitespace and control characters aside) that `family` in
/// `ctx`'s fonts draws as the replacement box, in order, each once.
pub fn missing(
    ctx: &Context,
    family: FontFamily,
    chars: impl IntoIterator<Item = char>,
) -> Vec<char> {
    let id = FontId::new(14.0, family);
    let glyph = |c: char| {
        ctx.fonts_mut(|f| {
            let g = f.layout_no_wrap(c.to_string(), id.clone(), Color32::WHITE);
            let first = g.rows.first()?.row.glyphs.first()?;
            Some(first.uv_rect)
        })
    };
    let replacement = glyph(NO_GLYPH);
    let mut out: Vec<char> = Vec::new();
    for c in chars {
        if c.is_whitespace() || c.is_control() || c == NO_GLYPH || out.contains(&c) {
            continue;
        }
        if glyph(c) == replacement {
            out.push(c);
        }
    }
    out
}
