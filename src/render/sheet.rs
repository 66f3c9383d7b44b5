//! A contact sheet: several renders in one image, each with its label underneath, drawn
//! with the public-domain 8×8 bitmap font of the `font8x8` crate at twice its size.

use font8x8::UnicodeFonts;

/// An 8-bit sRGB image, row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Rgb8Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixels, `width × height`.
    pub pixels: Vec<[u8; 3]>,
}

impl Rgb8Image {
    /// An image filled with one colour.
    pub fn filled(width: u32, height: u32, c: [u8; 3]) -> Rgb8Image {
        Rgb8Image {
            width,
            height,
            pixels: vec![c; (width * height) as usize],
        }
    }
    /// Copies `src` with its top-left corner at (`x`, `y`), clipped to this image.
    pub fn blit(&mut self, src: &Rgb8Image, x: u32, y: u32) {
        for sy in 0..src.height.min(self.height.saturating_sub(y)) {
            for sx in 0..src.width.min(self.width.saturating_sub(x)) {
                self.pixels[((y + sy) * self.width + x + sx) as usize] =
                    src.pixels[(sy * src.width + sx) as usize];
            }
        }
    }
    /// Draws `text` at (`x`, `y`) in colour `c`, 16 px high; characters outside Basic Latin
    /// draw as '?'. Returns the width drawn.
    pub fn draw_text(&mut self, text: &str, x: u32, y: u32, c: [u8; 3]) -> u32 {
        const SCALE: u32 = 2;
        let mut pen = x;
        for ch in text.chars() {
            let glyph = font8x8::BASIC_FONTS
                .get(ch)
                .or_else(|| font8x8::BASIC_FONTS.get('?'))
                .unwrap_or([0; 8]);
            for (row, bits) in glyph.iter().enumerate() {
                for col in 0..8 {
                    if bits & (1 << col) == 0 {
                        continue;
                    }
                    for dy in 0..SCALE {
                        for dx in 0..SCALE {
                            let (px, py) = (pen + col * SCALE + dx, y + row as u32 * SCALE + dy);
                            if px < self.width && py < self.height {
                                self.pixels[(py * self.width + px) as usize] = c;
                            }
                        }
                    }
                }
            }
            pen += 8 * SCALE;
        }
        pen - x
    }
}

/// Height of the label strip under each tile.
pub const LABEL_HEIGHT: u32 = 24;

/// Lays out `tiles` (all the same size) in a near-square grid with their labels, on a dark
/// grey background. Labels longer than a tile are cut.
pub fn contact_sheet(tiles: &[(String, Rgb8Image)]) -> Rgb8Image {
    let n = tiles.len().max(1) as u32;
    let cols = (n as f32).sqrt().ceil() as u32;
    let rows = n.div_ceil(cols);
    let (tw, th) = tiles
        .first()
        .map(|(_, t)| (t.width, t.height))
        .unwrap_or((1, 1));
    let gap = 8;
    let width = cols * tw + (cols + 1) * gap;
    let height = rows * (th + LABEL_HEIGHT) + (rows + 1) * gap;
    let mut sheet = Rgb8Image::filled(width, height, [24, 24, 24]);
    for (k, (label, tile)) in tiles.iter().enumerate() {
        let (c, r) = (k as u32 % cols, k as u32 / cols);
        let x = gap + c * (tw + gap);
        let y = gap + r * (th + LABEL_HEIGHT + gap);
        sheet.blit(tile, x, y);
        let max_chars = (tw / 16) as usize;
        let text: String = label.chars().take(max_chars).collect();
        sheet.draw_text(&text, x, y + th + 4, [230, 230, 230]);
    }
    sheet
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sheet_lays_out_tiles_and_labels() {
        let tile = Rgb8Image::filled(64, 32, [200, 0, 0]);
        let sheet = contact_sheet(&[
            ("a".into(), tile.clone()),
            ("b".into(), tile.clone()),
            ("c".into(), tile),
        ]);
        // 3 tiles → 2 columns × 2 rows.
        assert_eq!(
            (sheet.width, sheet.height),
            (2 * 64 + 3 * 8, 2 * (32 + LABEL_HEIGHT) + 3 * 8)
        );
        assert_eq!(sheet.pixels[(8 * sheet.width + 8) as usize], [200, 0, 0]);
        // The label 'a' puts light pixels in the strip under the first tile.
        let strip = (8 + 32)..(8 + 32 + LABEL_HEIGHT);
        let lit = strip
            .flat_map(|y| (8..24).map(move |x| (x, y)))
            .filter(|&(x, y)| sheet.pixels[(y * sheet.width + x) as usize] == [230, 230, 230])
            .count();
        assert!(lit > 10, "label pixels: {lit}");
    }
}
