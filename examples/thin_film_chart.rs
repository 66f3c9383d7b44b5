//! Writes docs/renders/thin_film_chart.png: the `thin_film` node's reflected colour of a free
//! soap film (n = 1.33 in air) over thickness 0–2000 nm (left to right, 4 nm a column) and
//! angle 0–89° (top to bottom, 1° a row), one panel per method: spectral, belcour_barla, rgb3.
//! Reflectance is shown ×6 (a film reflects at most ~16%), clamped to [0, 1], sRGB-encoded.
//!
//! Run: `cargo run --release --example thin_film_chart [out.png]`.

use matgraph::nodes::thin_film::{BELCOUR_BARLA, RGB3, SPECTRAL, thin_film};

const COLUMNS: u32 = 501;
const ROWS: u32 = 90;
const GAP: u32 = 6;
const EXPOSURE: f32 = 6.0;

/// The sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1], as a byte.
fn encode(x: f32) -> u8 {
    let x = x.clamp(0.0, 1.0);
    let v = if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    (v * 255.0 + 0.5) as u8
}

fn main() {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "docs/renders/thin_film_chart.png".to_owned());
    let methods = [SPECTRAL, BELCOUR_BARLA, RGB3];
    let height = ROWS * methods.len() as u32 + GAP * (methods.len() as u32 - 1);
    let mut img = image::RgbImage::from_pixel(COLUMNS, height, image::Rgb([255, 255, 255]));
    for (m, &method) in methods.iter().enumerate() {
        let top = m as u32 * (ROWS + GAP);
        for row in 0..ROWS {
            let cos = (row as f32).to_radians().cos();
            for col in 0..COLUMNS {
                let d = 4.0 * col as f32;
                let (r, _) = thin_film(cos, d, 1.33, 1.0, 1.0, method);
                let c = r * EXPOSURE;
                img.put_pixel(
                    col,
                    top + row,
                    image::Rgb([encode(c.x), encode(c.y), encode(c.z)]),
                );
            }
        }
    }
    img.save(&out)
        .unwrap_or_else(|e| panic!("writing {out}: {e}"));
    eprintln!("wrote {out} ({COLUMNS} × {height})");
}
