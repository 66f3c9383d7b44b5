//! Writes the bubble scene's six procedural maps (`scene::bubble_maps()`: base, light
//! shafts, seabed, two normal maps, alpha) as one labelled contact sheet, to look at them.
//! The maps are linear; the sheet shows them sRGB-encoded, without tone mapping.
//!
//! Run: `cargo run --release --example bubble_maps [OUT.png]` (default `bubble_maps.png`).

use matgraph::render::{sheet, tonemap};
use std::error::Error;

fn main() -> Result<(), Box<dyn Error>> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "bubble_maps.png".to_owned());
    let maps = matgraph::scene::bubble_maps();
    let tiles: Vec<(String, sheet::Rgb8Image)> = maps
        .named()
        .iter()
        .map(|(name, texture)| {
            let image = &texture.levels()[0];
            let encode = |x: f32| (tonemap::srgb_encode(x.clamp(0.0, 1.0)) * 255.0).round() as u8;
            let pixels = image
                .data
                .iter()
                .map(|c| [encode(c[0]), encode(c[1]), encode(c[2])])
                .collect();
            let tile = sheet::Rgb8Image {
                width: image.width,
                height: image.height,
                pixels,
            };
            (name.to_string(), tile)
        })
        .collect();
    let contact = sheet::contact_sheet(&tiles);
    matgraph::image_io::save_rgb8(
        std::path::Path::new(&out),
        contact.width,
        contact.height,
        &contact.pixels,
    )?;
    println!(
        "{out}: {} maps of {} × {}",
        tiles.len(),
        matgraph::scene::BUBBLE_MAP_SIZE,
        matgraph::scene::BUBBLE_MAP_SIZE
    );
    Ok(())
}
