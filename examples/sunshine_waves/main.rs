//! Writes seed 002's wave textures and their custom mip chains (see `gen.rs`) as PNGs.
//!
//! Run: `cargo run --release --example sunshine_waves [DIR]` (default
//! `graphs/textures/sunshine`). The output is deterministic: `tests/models/sunshine.rs` checks that
//! the committed files are these bytes.

#[path = "gen.rs"]
mod generator;

use std::error::Error;
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn Error>> {
    let dir = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/graphs/textures/sunshine"
            ))
        });
    std::fs::create_dir_all(&dir)?;
    for (name, image) in generator::files() {
        let path = dir.join(&name);
        matgraph::image_io::save_png(&path, &image)?;
        println!("{}", path.display());
    }
    Ok(())
}
