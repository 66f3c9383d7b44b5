//! The generator of seed 002's wave textures (shared by `examples/sunshine_waves` and
//! `tests/models/sunshine.rs`, which checks that the committed PNGs are its output byte for byte).
//!
//! A wave texture is a sum of cosines on the torus: every wave vector is a whole number of
//! cycles across the image, so the texture tiles exactly. With `s(x, y) = Σ aᵢ cos(2π(kxᵢ·x +
//! kyᵢ·y)/N + φᵢ)` divided by its largest |s| over the image (so s ∈ [−1, 1]), the texel is
//! `(1 − |s|)⁶`: thin bright crests where `s`
//! crosses zero, dark troughs elsewhere (white bright, black transparent, as in the post).
//! Wave vectors, amplitudes (∝ 1/|k|) and phases come from a seeded SplitMix64, in f64, so
//! the same seed gives the same texels on every machine.
//!
//! The custom mip chain (the band) is the texture's own box-filtered chain
//! (`matgraph::texture::downsample`) with level k scaled so that its brightest texel is
//! [`BAND`]`[k]`: levels 0 and 5–7 black, 1–4 lit, level 2 (the third) the brightest, its
//! crests full white.

use matgraph::texture::{Image, downsample};

/// Side of the wave textures in texels (8 mip levels: 128, 64, …, 1).
pub const SIZE: u32 = 128;

/// Brightness of each level of the band chain, level 0 (largest) first: the smallest and
/// largest levels black, the middle ones lit, the third level (index 2) the brightest.
pub const BAND: [f32; 8] = [0.0, 0.6, 1.0, 0.6, 0.25, 0.0, 0.0, 0.0];

/// The two textures: (file stem, seed, mean direction of the wave vectors in radians).
pub const WAVES: [(&str, u64, f64); 2] = [("wave1", 2002, 0.35), ("wave2", 1985, 2.0)];

/// Exponent sharpening the crests: `(1 − |s|)^CREST`.
const CREST: i32 = 6;

/// Cosines summed per texture.
const TERMS: usize = 24;

/// A seeded SplitMix64 step: the next 64 random bits.
fn splitmix(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Uniform in [0, 1) from 53 random bits.
fn unit(state: &mut u64) -> f64 {
    (splitmix(state) >> 11) as f64 / (1u64 << 53) as f64
}

/// The greyscale wave texture of `seed`, its crests running across `direction` (radians,
/// the mean angle of the wave vectors, spread ±0.6 rad), [`SIZE`] × [`SIZE`], linear.
pub fn wave(seed: u64, direction: f64) -> Image {
    let mut state = seed;
    let mut terms = Vec::with_capacity(TERMS);
    while terms.len() < TERMS {
        let angle = direction + (unit(&mut state) - 0.5) * 1.2;
        let cycles = 2.0 + unit(&mut state) * 10.0;
        let (kx, ky) = (
            (cycles * angle.cos()).round(),
            (cycles * angle.sin()).round(),
        );
        let phase = unit(&mut state) * std::f64::consts::TAU;
        if kx == 0.0 && ky == 0.0 {
            continue;
        }
        terms.push((kx, ky, 1.0 / kx.hypot(ky), phase));
    }
    let n = SIZE as f64;
    let sum: Vec<f64> = (0..SIZE * SIZE)
        .map(|i| {
            let (x, y) = ((i % SIZE) as f64, (i / SIZE) as f64);
            terms
                .iter()
                .map(|&(kx, ky, a, phase)| {
                    a * (std::f64::consts::TAU * (kx * x + ky * y) / n + phase).cos()
                })
                .sum()
        })
        .collect();
    let peak = sum.iter().fold(0.0f64, |m, s| m.max(s.abs()));
    Image::from_fn(SIZE, SIZE, |x, y| {
        let s = sum[(y * SIZE + x) as usize] / peak;
        let v = (1.0 - s.abs()).powi(CREST) as f32;
        [v, v, v, 1.0]
    })
}

/// The band chain of `image`: its box-filtered mip levels, level k scaled so that its
/// brightest texel is [`BAND`]`[k]` (alpha kept at 1).
pub fn band_chain(image: &Image) -> Vec<Image> {
    let mut levels = vec![image.clone()];
    while levels.len() < BAND.len() {
        let next = downsample(levels.last().expect("at least one level"));
        levels.push(next);
    }
    levels
        .into_iter()
        .zip(BAND)
        .map(|(mut level, brightness)| {
            let peak = level.data.iter().fold(0.0f32, |m, t| m.max(t[0]));
            let k = if peak > 0.0 { brightness / peak } else { 0.0 };
            for t in &mut level.data {
                for c in &mut t[..3] {
                    *c *= k;
                }
            }
            level
        })
        .collect()
}

/// Every file the generator writes, with its image: `NAME.png` (level 0, for the distortion;
/// its mips are generated on load) and `NAME_band_K.png` (level K of the band chain).
pub fn files() -> Vec<(String, Image)> {
    let mut out = Vec::new();
    for (name, seed, direction) in WAVES {
        let image = wave(seed, direction);
        for (k, level) in band_chain(&image).into_iter().enumerate() {
            out.push((format!("{name}_band_{k}.png"), level));
        }
        out.push((format!("{name}.png"), image));
    }
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}
