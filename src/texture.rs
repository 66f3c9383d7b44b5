//! Textures: linear RGBA images, mip chains and filtered sampling at an explicit level of
//! detail, with the same arithmetic on the CPU ([`Texture::sample`]) and in WGSL
//! ([`SAMPLE_WGSL`] over a [`TexturePack`]). Core: no I/O (files live in [`crate::image_io`]).
//!
//! Conventions, shared bit for bit by the CPU and the WGSL sampler:
//!
//! - **Orientation.** uv (0, 0) is the top-left corner of the image and (1, 1) the
//!   bottom-right; u grows to the right, v downwards; row 0 of [`Image::data`] is the top row.
//! - **Texel centres.** Texel (i, j) of a w × h level has its centre at ((i + 0.5)/w, (j + 0.5)/h).
//! - **Nearest** reads texel (floor(u·w), floor(v·h)).
//! - **Bilinear** reads the four texels around (x, y) = (u·w − 0.5, v·h − 0.5), i0 = floor(x),
//!   tx = x − i0 (likewise y), and blends `top = c00 + (c10 − c00)·tx`, `bottom = c01 + (c11 − c01)·tx`,
//!   `top + (bottom − top)·ty`, in that order.
//! - **Wrap** applies to the integer texel indices, so it is exact: [`Wrap::Repeat`] takes
//!   i mod w, [`Wrap::Clamp`] clamps to [0, w − 1] (clamp to edge), [`Wrap::Mirror`] mirrors with
//!   period 2w, repeating the edge texel (GL's `MIRRORED_REPEAT`). Before the conversion to an
//!   integer a texel coordinate is clamped to ±2147483520 (the largest f32 below 2³¹) so that
//!   the conversion is defined on both sides; the bilinear coordinate is clamped so before its
//!   fraction is taken, so a uv beyond f32's range (5e37 × 128 texels is ∞) reads the texel
//!   at the limit with fraction 0 instead of NaN. The cost: none below 2³¹ texels, where f32
//!   has no fraction left anyway.
//! - **Level of detail.** Level 0 is the full-size image. `lod` is clamped to [0, levels − 1]
//!   (a NaN lod reads level 0). [`Filter::Bilinear`] blends the levels ⌊lod⌋ and ⌊lod⌋ + 1 as
//!   `a + (b − a)·(lod − ⌊lod⌋)` (trilinear filtering; level ⌊lod⌋ alone when the fraction is 0);
//!   [`Filter::Nearest`] reads the single level ⌈lod + 0.5⌉ − 1 (nearest, ties to the lower level).
//! - **Finite inputs.** The CPU and GPU agree for finite uv and lod with |u·w|, |v·h| finite.
//!   A NaN lod reads level 0 on the CPU (and on GPUs whose `max` returns the non-NaN operand);
//!   a NaN uv reads an unspecified texel of the level on the GPU, never outside it.
//!
//! Sources: OpenGL 4.6 core profile specification §8.14 (texel selection, `REPEAT`,
//! `CLAMP_TO_EDGE`, `MIRRORED_REPEAT`, `NEAREST_MIPMAP_NEAREST`, `LINEAR_MIPMAP_LINEAR`);
//! Williams 1983, "Pyramidal Parametrics" (mip maps); seed 002 (custom mip chains).

use glam::{Vec2, Vec4};
use std::path::PathBuf;

/// An error building, packing or loading a texture; each names the image, level or file at fault.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TextureError {
    /// A texture asked for by name that the set does not hold.
    #[error("no texture '{0}' in the set")]
    Missing(String),
    /// An image has no texels.
    #[error("image is {width}×{height}: an image needs at least one texel")]
    EmptyImage {
        /// Width in texels.
        width: u32,
        /// Height in texels.
        height: u32,
    },
    /// An image's data does not hold `width × height` texels.
    #[error("image is {width}×{height} but its data holds {len} texels")]
    DataLength {
        /// Width in texels.
        width: u32,
        /// Height in texels.
        height: u32,
        /// Number of texels in the data.
        len: usize,
    },
    /// A custom mip chain has no level.
    #[error("a mip chain needs at least one level")]
    NoLevels,
    /// A level of a custom mip chain is not half the size of the level before it.
    #[error(
        "mip level {level} is {found_width}×{found_height}, expected {expected_width}×{expected_height} (half of level {}, rounded down, at least 1)",
        level - 1
    )]
    LevelSize {
        /// Index of the level at fault (≥ 1).
        level: usize,
        /// Expected width.
        expected_width: u32,
        /// Expected height.
        expected_height: u32,
        /// Width found.
        found_width: u32,
        /// Height found.
        found_height: u32,
    },
    /// A level of a mip chain is invalid.
    #[error("mip level {level}: {source}")]
    Level {
        /// Index of the level at fault.
        level: usize,
        /// What is wrong with it.
        source: Box<TextureError>,
    },
    /// Two textures of a [`TextureSet`] have the same name.
    #[error("texture '{0}' is already in the set")]
    DuplicateName(String),
    /// The textures of a set hold too many texels to be indexed with u32 on the GPU.
    #[error("the texture set holds {texels} texels; at most {max} can be packed for the GPU")]
    TooLarge {
        /// Texels in the set.
        texels: u64,
        /// The most that can be packed.
        max: u64,
    },
    /// A custom mip chain has more levels than its level 0 halves into (down to 1 × 1).
    #[error(
        "a mip chain of {levels} levels: a {width}×{height} image has {max} (halved down to 1×1); remove the levels from {max} on"
    )]
    TooManyLevels {
        /// Levels in the chain.
        levels: usize,
        /// Width of level 0.
        width: u32,
        /// Height of level 0.
        height: u32,
        /// The most it can have ([`mip_level_count`]).
        max: usize,
    },
    /// A texel holds NaN, an infinity or a value beyond [`MAX_TEXEL`] ([`check_texels`]).
    #[error(
        "texel ({x}, {y}) (from the top left) has {value:e} in its {channel} channel: image values must be finite and at most 2^64 (1.8e19) in magnitude"
    )]
    BadTexel {
        /// Column, from the left.
        x: u32,
        /// Row, from the top.
        y: u32,
        /// `red`, `green`, `blue` or `alpha`.
        channel: &'static str,
        /// The value.
        value: f32,
    },
    /// A file could not be read, decoded or written.
    #[error("{}: {message}", path.display())]
    File {
        /// The file at fault.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// A file decoded to an invalid image or level.
    #[error("{}: {source}", path.display())]
    InFile {
        /// The file at fault.
        path: PathBuf,
        /// What is wrong with its image.
        source: Box<TextureError>,
    },
}

/// A linear-light RGBA image, row-major with row 0 at the top (uv v = 0).
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// `width × height` texels, row by row from the top, each linear RGBA.
    pub data: Vec<[f32; 4]>,
}

impl Image {
    /// An image from its texels, checked by [`Image::validate`].
    pub fn new(width: u32, height: u32, data: Vec<[f32; 4]>) -> Result<Image, TextureError> {
        let image = Image {
            width,
            height,
            data,
        };
        image.validate()?;
        Ok(image)
    }

    /// A `width × height` image of one colour (not validated: a zero size is caught on use).
    pub fn filled(width: u32, height: u32, rgba: [f32; 4]) -> Image {
        Image {
            width,
            height,
            data: vec![rgba; width as usize * height as usize],
        }
    }

    /// A `width × height` image whose texel (x, y) is `f(x, y)`, row by row from the top.
    pub fn from_fn(width: u32, height: u32, mut f: impl FnMut(u32, u32) -> [f32; 4]) -> Image {
        let mut data = Vec::with_capacity(width as usize * height as usize);
        for y in 0..height {
            for x in 0..width {
                data.push(f(x, y));
            }
        }
        Image {
            width,
            height,
            data,
        }
    }

    /// Checks that the image has at least one texel and that `data` holds `width × height`.
    pub fn validate(&self) -> Result<(), TextureError> {
        if self.width == 0 || self.height == 0 {
            return Err(TextureError::EmptyImage {
                width: self.width,
                height: self.height,
            });
        }
        if self.data.len() as u64 != self.width as u64 * self.height as u64 {
            return Err(TextureError::DataLength {
                width: self.width,
                height: self.height,
                len: self.data.len(),
            });
        }
        Ok(())
    }

    /// Texel (x, y), x from the left and y from the top; panics outside the image.
    pub fn texel(&self, x: u32, y: u32) -> [f32; 4] {
        assert!(
            x < self.width && y < self.height,
            "texel ({x}, {y}) outside the image"
        );
        self.data[y as usize * self.width as usize + x as usize]
    }
}

/// How texel indices outside [0, size − 1] are brought back in (enum order fixed: 0, 1, 2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum Wrap {
    /// Tile: index i reads i mod size.
    #[default]
    Repeat = 0,
    /// Clamp to edge: the edge texels extend outwards.
    Clamp = 1,
    /// Mirrored repeat with period 2 × size, the edge texel repeated (GL `MIRRORED_REPEAT`).
    Mirror = 2,
}

impl Wrap {
    /// Every mode, in index order.
    pub const ALL: [Wrap; 3] = [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror];
    /// The choice names of an enum input, in index order.
    pub const NAMES: &'static [&'static str] = &["repeat", "clamp", "mirror"];
    /// The mode's index (its value in WGSL and in enum inputs).
    pub const fn index(self) -> u32 {
        self as u32
    }
    /// The mode's name.
    pub const fn name(self) -> &'static str {
        Wrap::NAMES[self as usize]
    }
    /// The mode with index `i`, as the WGSL reads it: 0 repeat, 1 clamp, anything else mirror.
    pub const fn from_index(i: u32) -> Wrap {
        match i {
            0 => Wrap::Repeat,
            1 => Wrap::Clamp,
            _ => Wrap::Mirror,
        }
    }
}

/// How texels are filtered within and across mip levels (enum order fixed: 0, 1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum Filter {
    /// The nearest texel of the nearest level.
    Nearest = 0,
    /// Bilinear within a level, linear between the two nearest levels (trilinear).
    #[default]
    Bilinear = 1,
}

impl Filter {
    /// Every filter, in index order.
    pub const ALL: [Filter; 2] = [Filter::Nearest, Filter::Bilinear];
    /// The choice names of an enum input, in index order.
    pub const NAMES: &'static [&'static str] = &["nearest", "bilinear"];
    /// The filter's index (its value in WGSL and in enum inputs).
    pub const fn index(self) -> u32 {
        self as u32
    }
    /// The filter's name.
    pub const fn name(self) -> &'static str {
        Filter::NAMES[self as usize]
    }
    /// The filter with index `i`, as the WGSL reads it: 0 nearest, anything else bilinear.
    pub const fn from_index(i: u32) -> Filter {
        match i {
            0 => Filter::Nearest,
            _ => Filter::Bilinear,
        }
    }
}

/// The most mip levels any chain may list: a side of up to 2^32 − 1 texels halves 31 times
/// to 1, so 32 levels. Graphs listing more are refused at load.
pub const MAX_MIP_LEVELS: usize = 32;

/// The number of levels of the full mip chain of a `width × height` image: level 0 and each
/// [`mip_size`] down to 1 × 1 (`⌊log2 max(width, height)⌋ + 1`; 1 for an empty size).
pub const fn mip_level_count(width: u32, height: u32) -> usize {
    let side = if width > height { width } else { height };
    if side == 0 {
        1
    } else {
        (u32::BITS - side.leading_zeros()) as usize
    }
}

/// The largest magnitude a loaded texel may hold: 2^64 (1.8e19), so that its square (in a
/// dot product, a length) stays finite in f32. NaN and infinities are refused, and so are
/// the huge values that stand for them in formats without them: Radiance RGBE cannot hold
/// NaN or infinity, and writers turn them into its largest exponent (up to 1.7e38). The
/// cost: no texture can hold a value beyond 1.8e19 (the sun's disc is about 1.6e9 cd/m²).
pub const MAX_TEXEL: f32 = 18_446_744_073_709_551_616.0;

/// The first texel of `image` (row by row from the top left, channels in order) holding
/// NaN, an infinity or a value beyond ±[`MAX_TEXEL`], as the error naming it.
pub fn check_texels(image: &Image) -> Result<(), TextureError> {
    let width = image.width.max(1) as usize;
    for (i, t) in image.data.iter().enumerate() {
        if let Some(c) = t.iter().position(|v| v.is_nan() || v.abs() > MAX_TEXEL) {
            return Err(TextureError::BadTexel {
                x: (i % width) as u32,
                y: (i / width) as u32,
                channel: ["red", "green", "blue", "alpha"][c],
                value: t[c],
            });
        }
    }
    Ok(())
}

/// The size of the mip level below a `width × height` one: each side halved, rounded down,
/// at least 1.
pub const fn mip_size(width: u32, height: u32) -> (u32, u32) {
    let w = width / 2;
    let h = height / 2;
    (if w == 0 { 1 } else { w }, if h == 0 { 1 } else { h })
}

/// The source texels and weights of destination texel `i` when a side of `src` texels is
/// reduced to `dst` = max(1, ⌊src/2⌋): the exact box (area) filter. Even sizes average two
/// texels; an odd size 2n + 1 → n averages three with weights (n − i, n, i + 1)/(2n + 1),
/// which is the area each covers of the destination texel's footprint; a size of 1 is copied.
fn box_taps(src: u32, dst: u32, i: u32) -> ([u32; 3], [f64; 3], usize) {
    if src == 1 {
        ([0, 0, 0], [1.0, 0.0, 0.0], 1)
    } else if src.is_multiple_of(2) {
        ([2 * i, 2 * i + 1, 0], [0.5, 0.5, 0.0], 2)
    } else {
        let n = dst as f64;
        let d = src as f64;
        let fi = i as f64;
        (
            [2 * i, 2 * i + 1, 2 * i + 2],
            [(n - fi) / d, n / d, (fi + 1.0) / d],
            3,
        )
    }
}

/// The next mip level of `image`: [`mip_size`], each texel the exact area average of the
/// texels it covers, accumulated in f64 in a fixed order: a 2 × 2 box for even sizes; along an
/// odd side 2n + 1 → n, destination texel i averages source texels 2i, 2i + 1, 2i + 2 with
/// weights (n − i, n, i + 1)/(2n + 1). Channels are averaged independently (straight alpha),
/// in linear light. `image` must be valid.
///
/// Source: Williams 1983, "Pyramidal Parametrics" (box-filtered pyramid), generalised to odd
/// sizes by exact area coverage.
pub fn downsample(image: &Image) -> Image {
    let (w, h) = mip_size(image.width, image.height);
    Image::from_fn(w, h, |x, y| {
        let (xs, wx, nx) = box_taps(image.width, w, x);
        let (ys, wy, ny) = box_taps(image.height, h, y);
        let mut acc = [0.0f64; 4];
        for j in 0..ny {
            for i in 0..nx {
                let t = image.texel(xs[i], ys[j]);
                let weight = wx[i] * wy[j];
                for c in 0..4 {
                    acc[c] += weight * t[c] as f64;
                }
            }
        }
        acc.map(|a| a as f32)
    })
}

/// A mip chain of images: level 0 full size, each next level half the size of the one above
/// (rounded down, at least 1). See the module doc for the sampling conventions.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    levels: Vec<Image>,
}

impl Texture {
    /// A texture of `image`, with its mip levels down to 1 × 1 generated by [`downsample`]
    /// when `mips` is true, else the single level.
    pub fn new(image: Image, mips: bool) -> Result<Texture, TextureError> {
        image.validate().map_err(|e| TextureError::Level {
            level: 0,
            source: Box::new(e),
        })?;
        let mut levels = vec![image];
        if mips {
            loop {
                let last = &levels[levels.len() - 1];
                if last.width == 1 && last.height == 1 {
                    break;
                }
                let next = downsample(last);
                levels.push(next);
            }
        }
        Ok(Texture { levels })
    }

    /// A texture of a custom mip chain (seed 002's black–white–black chain): every level
    /// valid, each [`mip_size`] of the one before; the chain may stop before 1 × 1 but not go
    /// on after it (at most [`mip_level_count`] levels: a second 1 × 1 level is refused,
    /// where [`mip_size`] alone would accept it).
    pub fn from_levels(levels: Vec<Image>) -> Result<Texture, TextureError> {
        if levels.is_empty() {
            return Err(TextureError::NoLevels);
        }
        let (width, height) = (levels[0].width, levels[0].height);
        let max = mip_level_count(width, height);
        if levels.len() > max {
            return Err(TextureError::TooManyLevels {
                levels: levels.len(),
                width,
                height,
                max,
            });
        }
        for (k, level) in levels.iter().enumerate() {
            level.validate().map_err(|e| TextureError::Level {
                level: k,
                source: Box::new(e),
            })?;
            if k > 0 {
                let (ew, eh) = mip_size(levels[k - 1].width, levels[k - 1].height);
                if (level.width, level.height) != (ew, eh) {
                    return Err(TextureError::LevelSize {
                        level: k,
                        expected_width: ew,
                        expected_height: eh,
                        found_width: level.width,
                        found_height: level.height,
                    });
                }
            }
        }
        Ok(Texture { levels })
    }

    /// The mip levels, largest first.
    pub fn levels(&self) -> &[Image] {
        &self.levels
    }

    /// Number of mip levels (at least 1).
    pub fn level_count(&self) -> usize {
        self.levels.len()
    }

    /// Width of level 0 in texels.
    pub fn width(&self) -> u32 {
        self.levels[0].width
    }

    /// Height of level 0 in texels.
    pub fn height(&self) -> u32 {
        self.levels[0].height
    }

    /// The filtered colour at `uv` and level of detail `lod` (conventions in the module doc).
    pub fn sample(&self, uv: Vec2, lod: f32, wrap: Wrap, filter: Filter) -> Vec4 {
        let levels = &self.levels;
        sample_chain(
            levels.len() as u32,
            |k| (levels[k as usize].width, levels[k as usize].height),
            |k, x, y| Vec4::from_array(levels[k as usize].texel(x, y)),
            uv,
            lod,
            wrap.index(),
            filter.index(),
        )
    }
}

/// `i mod n` in [0, n − 1] for n ≥ 1 (Euclidean), with `%` only on non-negative operands
/// (GLSL leaves `%` of negative numbers undefined): `n − 1 − ((−(i + 1)) % n)` for i < 0.
/// The same steps as `mg_tex_mod` in [`SAMPLE_WGSL`].
#[inline]
fn euclid_mod(i: i32, n: i32) -> i32 {
    if i >= 0 {
        i % n
    } else {
        (n - 1) - (-(i + 1)) % n
    }
}

/// Brings texel index `i` into [0, n − 1] with wrap mode `wrap` (0 repeat, 1 clamp, else
/// mirror); the same integer steps as `mg_tex_wrap` in [`SAMPLE_WGSL`].
#[inline]
fn wrap_index(i: i32, n: i32, wrap: u32) -> i32 {
    match wrap {
        0 => euclid_mod(i, n),
        1 => i.clamp(0, n - 1),
        _ => {
            let p = 2 * n;
            let m = euclid_mod(i, p);
            if m >= n { p - 1 - m } else { m }
        }
    }
}

/// The largest f32 below 2³¹: texel coordinates are clamped to ± this before `as i32`.
const COORD_LIMIT: f32 = 2_147_483_520.0;

/// An integral-valued texel coordinate as i32, clamped to ±[`COORD_LIMIT`] first.
#[inline]
fn to_index(x: f32) -> i32 {
    x.clamp(-COORD_LIMIT, COORD_LIMIT) as i32
}

/// Samples one level of size `(w, h)` through `fetch(x, y)` (`filter` 0 nearest, else bilinear).
#[inline]
fn sample_level(
    (w, h): (u32, u32),
    fetch: impl Fn(u32, u32) -> Vec4,
    uv: Vec2,
    wrap: u32,
    filter: u32,
) -> Vec4 {
    let (wi, hi) = (w as i32, h as i32);
    let (fw, fh) = (w as f32, h as f32);
    if filter == 0 {
        let x = wrap_index(to_index((uv.x * fw).floor()), wi, wrap);
        let y = wrap_index(to_index((uv.y * fh).floor()), hi, wrap);
        return fetch(x as u32, y as u32);
    }
    // Clamped like the indices, so that a coordinate beyond f32's range (uv 5e37 × 128
    // texels) gives the fraction 0, not ∞ − ∞ = NaN (issue 37).
    let px = (uv.x * fw - 0.5).clamp(-COORD_LIMIT, COORD_LIMIT);
    let py = (uv.y * fh - 0.5).clamp(-COORD_LIMIT, COORD_LIMIT);
    let fx = px.floor();
    let fy = py.floor();
    let tx = px - fx;
    let ty = py - fy;
    let ix = to_index(fx);
    let iy = to_index(fy);
    let x0 = wrap_index(ix, wi, wrap) as u32;
    let x1 = wrap_index(ix + 1, wi, wrap) as u32;
    let y0 = wrap_index(iy, hi, wrap) as u32;
    let y1 = wrap_index(iy + 1, hi, wrap) as u32;
    let c00 = fetch(x0, y0);
    let c10 = fetch(x1, y0);
    let c01 = fetch(x0, y1);
    let c11 = fetch(x1, y1);
    let top = c00 + (c10 - c00) * tx;
    let bottom = c01 + (c11 - c01) * tx;
    top + (bottom - top) * ty
}

/// Samples a chain of `count` levels, level `k` of size `size(k)` read by `fetch(k, x, y)`:
/// the CPU twin of `mg_sample_texture` in [`SAMPLE_WGSL`], step for step.
#[inline]
fn sample_chain(
    count: u32,
    size: impl Fn(u32) -> (u32, u32),
    fetch: impl Fn(u32, u32, u32) -> Vec4,
    uv: Vec2,
    lod: f32,
    wrap: u32,
    filter: u32,
) -> Vec4 {
    if count == 0 {
        return Vec4::ZERO;
    }
    let top = (count - 1) as f32;
    let l = lod.max(0.0).min(top);
    if filter == 0 {
        let k = ((l + 0.5).ceil() - 1.0) as u32;
        return sample_level(size(k), |x, y| fetch(k, x, y), uv, wrap, 0);
    }
    let l0 = l.floor();
    let k0 = l0 as u32;
    let a = sample_level(size(k0), |x, y| fetch(k0, x, y), uv, wrap, 1);
    let f = l - l0;
    if f == 0.0 {
        return a;
    }
    let k1 = k0 + 1;
    let b = sample_level(size(k1), |x, y| fetch(k1, x, y), uv, wrap, 1);
    a + (b - a) * f
}

/// An ordered set of named textures; a texture's index is its position, the `tex` argument
/// of [`TextureSet::sample`] and of `mg_sample_texture`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TextureSet {
    /// Textures are shared, so sets built from other sets copy no texels.
    entries: Vec<(String, std::sync::Arc<Texture>)>,
}

impl TextureSet {
    /// An empty set.
    pub fn new() -> TextureSet {
        TextureSet::default()
    }

    /// Appends `texture` as `name`; returns its index. Names are unique.
    pub fn insert(
        &mut self,
        name: impl Into<String>,
        texture: Texture,
    ) -> Result<u32, TextureError> {
        self.insert_shared(name, std::sync::Arc::new(texture))
    }

    /// Appends a shared `texture` as `name`; returns its index. Names are unique.
    pub fn insert_shared(
        &mut self,
        name: impl Into<String>,
        texture: std::sync::Arc<Texture>,
    ) -> Result<u32, TextureError> {
        let name = name.into();
        if self.index_of(&name).is_some() {
            return Err(TextureError::DuplicateName(name));
        }
        self.entries.push((name, texture));
        Ok(self.entries.len() as u32 - 1)
    }

    /// Appends every texture of `other`, shared, not copied.
    pub fn extend_shared(&mut self, other: &TextureSet) -> Result<(), TextureError> {
        for (name, texture) in &other.entries {
            self.insert_shared(name.clone(), texture.clone())?;
        }
        Ok(())
    }

    /// The index of the texture called `name`.
    pub fn index_of(&self, name: &str) -> Option<u32> {
        self.entries
            .iter()
            .position(|(n, _)| n == name)
            .map(|i| i as u32)
    }

    /// The texture at `index`.
    pub fn get(&self, index: u32) -> Option<&Texture> {
        self.entries.get(index as usize).map(|(_, t)| t.as_ref())
    }

    /// The texture at `index`, shared.
    pub fn shared(&self, index: u32) -> Option<&std::sync::Arc<Texture>> {
        self.entries.get(index as usize).map(|(_, t)| t)
    }

    /// The name of the texture at `index`.
    pub fn name(&self, index: u32) -> Option<&str> {
        self.entries.get(index as usize).map(|(n, _)| n.as_str())
    }

    /// Number of textures.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether the set has no texture.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The (name, texture) pairs in index order.
    pub fn iter(&self) -> impl Iterator<Item = (&str, &Texture)> {
        self.entries.iter().map(|(n, t)| (n.as_str(), t.as_ref()))
    }

    /// Samples texture `tex` ([`Texture::sample`]); transparent black (0, 0, 0, 0) when there
    /// is no texture `tex`, as in WGSL.
    pub fn sample(&self, tex: u32, uv: Vec2, lod: f32, wrap: Wrap, filter: Filter) -> Vec4 {
        match self.get(tex) {
            Some(t) => t.sample(uv, lod, wrap, filter),
            None => Vec4::ZERO,
        }
    }

    /// Packs every level of every texture into the flat buffers [`SAMPLE_WGSL`] reads.
    ///
    /// Fails when the texels cannot be indexed with u32 floats (more than 2³⁰ − 1 texels).
    pub fn pack(&self) -> Result<TexturePack, TextureError> {
        pack_textures(self.entries.iter().map(|(_, t)| t.as_ref()))
    }

    /// Packs the textures named `keys`, in that order (slot `k` is `keys[k]`), for a module
    /// that samples only those. Errors with the first name the set does not hold.
    pub fn pack_selection(&self, keys: &[String]) -> Result<TexturePack, TextureError> {
        let textures = keys
            .iter()
            .map(|k| {
                self.index_of(k)
                    .and_then(|i| self.get(i))
                    .ok_or_else(|| TextureError::Missing(k.clone()))
            })
            .collect::<Result<Vec<_>, _>>()?;
        pack_textures(textures.into_iter())
    }
}

/// Packs textures, in order, into the three GPU tables.
fn pack_textures<'a>(
    textures: impl Iterator<Item = &'a Texture> + Clone,
) -> Result<TexturePack, TextureError> {
    let max = (u32::MAX / 4) as u64;
    let texels: u64 = textures
        .clone()
        .flat_map(|t| t.levels.iter())
        .map(|l| l.width as u64 * l.height as u64)
        .sum();
    if texels > max {
        return Err(TextureError::TooLarge { texels, max });
    }
    let mut pack = TexturePack {
        texels: Vec::with_capacity(texels as usize * 4),
        levels: Vec::new(),
        textures: Vec::new(),
    };
    for t in textures {
        pack.textures
            .push([pack.levels.len() as u32, t.levels.len() as u32]);
        for l in &t.levels {
            let offset = (pack.texels.len() / 4) as u32;
            pack.levels.push([offset, l.width, l.height, 0]);
            pack.texels.extend(l.data.iter().flatten());
        }
    }
    if pack.textures.is_empty() {
        // wgpu refuses empty bindings: one texture entry with no level, never sampled.
        pack.textures.push([0, 0]);
    }
    if pack.levels.is_empty() {
        pack.levels.push([0, 1, 1, 0]);
        pack.texels.extend([0.0; 4]);
    }
    Ok(pack)
}

/// A [`TextureSet`] packed for the GPU: the contents of the three storage buffers that
/// [`SAMPLE_WGSL`] reads. Every array has at least one element (wgpu refuses empty
/// bindings): an empty set packs one texture entry with no levels, which samples to zero.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TexturePack {
    /// `mg_texels`: RGBA floats of every level of every texture, levels row by row from the top.
    pub texels: Vec<f32>,
    /// `mg_levels`: per level (offset in texels into `texels`, width, height, 0).
    pub levels: Vec<[u32; 4]>,
    /// `mg_textures`: per texture (index of its first level in `levels`, number of levels).
    pub textures: Vec<[u32; 2]>,
}

impl TexturePack {
    /// The bytes of `mg_texels` (little-endian f32).
    pub fn texel_bytes(&self) -> &[u8] {
        bytemuck::cast_slice(&self.texels)
    }

    /// The bytes of `mg_levels` (little-endian `vec4<u32>`).
    pub fn level_bytes(&self) -> &[u8] {
        bytemuck::cast_slice(&self.levels)
    }

    /// The bytes of `mg_textures` (little-endian `vec2<u32>`).
    pub fn texture_bytes(&self) -> &[u8] {
        bytemuck::cast_slice(&self.textures)
    }

    /// Samples texture `tex` from the packed buffers exactly as `mg_sample_texture` does
    /// (`wrap`: 0 repeat, 1 clamp, else mirror; `filter`: 0 nearest, else bilinear); zero when
    /// there is no texture `tex`. Panics if the tables point outside the buffers.
    pub fn sample(&self, tex: u32, uv: Vec2, lod: f32, wrap: u32, filter: u32) -> Vec4 {
        let Some(&[first, count]) = self.textures.get(tex as usize) else {
            return Vec4::ZERO;
        };
        let level = |k: u32| self.levels[(first + k) as usize];
        sample_chain(
            count,
            |k| {
                let l = level(k);
                (l[1], l[2])
            },
            |k, x, y| {
                let l = level(k);
                let b = ((l[0] + y * l[1] + x) * 4) as usize;
                Vec4::from_slice(&self.texels[b..b + 4])
            },
            uv,
            lod,
            wrap,
            filter,
        )
    }
}

/// WGSL of the texture sampler: `mg_sample_texture(tex, uv, lod, wrap, filt)`, the same steps
/// as [`Texture::sample`] (see the module doc), over the storage buffers `mg_texels:
/// array<f32>`, `mg_levels: array<vec4<u32>>` and `mg_textures: array<vec2<u32>>` holding a
/// [`TexturePack`], which the including module declares (see [`SAMPLE_BINDINGS_WGSL`]).
///
/// `wrap`: 0 repeat, 1 clamp, anything else mirror; `filt` (`filter` is a WGSL reserved word):
/// 0 nearest, anything else bilinear. A `tex` with no texture samples to zero. Helper
/// functions are prefixed `mg_tex_`.
pub const SAMPLE_WGSL: &str = r#"
fn mg_tex_mod(i: i32, n: i32) -> i32 {
    if (i >= 0) {
        return i % n;
    }
    return (n - 1) - (-(i + 1)) % n;
}

fn mg_tex_wrap(i: i32, n: i32, wrap: u32) -> i32 {
    if (wrap == 0u) {
        return mg_tex_mod(i, n);
    }
    if (wrap == 1u) {
        return clamp(i, 0, n - 1);
    }
    let p = 2 * n;
    let m = mg_tex_mod(i, p);
    return select(m, p - 1 - m, m >= n);
}

fn mg_tex_index(x: f32) -> i32 {
    return i32(clamp(x, -2147483520.0, 2147483520.0));
}

fn mg_tex_fetch(level: vec4<u32>, x: i32, y: i32) -> vec4<f32> {
    let b = (level.x + u32(y) * level.y + u32(x)) * 4u;
    return vec4<f32>(mg_texels[b], mg_texels[b + 1u], mg_texels[b + 2u], mg_texels[b + 3u]);
}

fn mg_tex_level(level: vec4<u32>, uv: vec2<f32>, wrap: u32, filt: u32) -> vec4<f32> {
    let wi = i32(level.y);
    let hi = i32(level.z);
    let fw = f32(level.y);
    let fh = f32(level.z);
    if (filt == 0u) {
        let x = mg_tex_wrap(mg_tex_index(floor(uv.x * fw)), wi, wrap);
        let y = mg_tex_wrap(mg_tex_index(floor(uv.y * fh)), hi, wrap);
        return mg_tex_fetch(level, x, y);
    }
    let px = clamp(uv.x * fw - 0.5, -2147483520.0, 2147483520.0);
    let py = clamp(uv.y * fh - 0.5, -2147483520.0, 2147483520.0);
    let fx = floor(px);
    let fy = floor(py);
    let tx = px - fx;
    let ty = py - fy;
    let ix = mg_tex_index(fx);
    let iy = mg_tex_index(fy);
    let x0 = mg_tex_wrap(ix, wi, wrap);
    let x1 = mg_tex_wrap(ix + 1, wi, wrap);
    let y0 = mg_tex_wrap(iy, hi, wrap);
    let y1 = mg_tex_wrap(iy + 1, hi, wrap);
    let c00 = mg_tex_fetch(level, x0, y0);
    let c10 = mg_tex_fetch(level, x1, y0);
    let c01 = mg_tex_fetch(level, x0, y1);
    let c11 = mg_tex_fetch(level, x1, y1);
    let top = c00 + (c10 - c00) * tx;
    let bottom = c01 + (c11 - c01) * tx;
    return top + (bottom - top) * ty;
}

fn mg_sample_texture(tex: u32, uv: vec2<f32>, lod: f32, wrap: u32, filt: u32) -> vec4<f32> {
    if (tex >= arrayLength(&mg_textures)) {
        return vec4<f32>(0.0);
    }
    let t = mg_textures[tex];
    if (t.y == 0u) {
        return vec4<f32>(0.0);
    }
    let top = f32(t.y - 1u);
    let l = min(max(lod, 0.0), top);
    if (filt == 0u) {
        let k = u32(ceil(l + 0.5) - 1.0);
        return mg_tex_level(mg_levels[t.x + k], uv, wrap, 0u);
    }
    let l0 = floor(l);
    let k0 = u32(l0);
    let a = mg_tex_level(mg_levels[t.x + k0], uv, wrap, 1u);
    let f = l - l0;
    if (f == 0.0) {
        return a;
    }
    let b = mg_tex_level(mg_levels[t.x + k0 + 1u], uv, wrap, 1u);
    return a + (b - a) * f;
}
"#;

/// WGSL declarations of the three read-only storage buffers [`SAMPLE_WGSL`] reads, as a
/// template: `$group` is the bind group and `$b0`, `$b1`, `$b2` the bindings of `mg_texels`,
/// `mg_levels` and `mg_textures` ([`sample_bindings_wgsl`] fills it in).
pub const SAMPLE_BINDINGS_WGSL: &str = "\
@group($group) @binding($b0) var<storage, read> mg_texels: array<f32>;
@group($group) @binding($b1) var<storage, read> mg_levels: array<vec4<u32>>;
@group($group) @binding($b2) var<storage, read> mg_textures: array<vec2<u32>>;
";

/// [`SAMPLE_BINDINGS_WGSL`] for bind group `group`, the buffers at bindings `first`,
/// `first + 1` and `first + 2` (texels, levels, textures).
pub fn sample_bindings_wgsl(group: u32, first: u32) -> String {
    SAMPLE_BINDINGS_WGSL
        .replace("$group", &group.to_string())
        .replace("$b0", &first.to_string())
        .replace("$b1", &(first + 1).to_string())
        .replace("$b2", &(first + 2).to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rgba(v: f32) -> [f32; 4] {
        [v, v, v, 1.0]
    }

    /// A 2 × 2 image: red channel 0, 1 / 2, 3 (top row first), alpha 1.
    fn two_by_two() -> Texture {
        let img = Image::new(2, 2, vec![rgba(0.0), rgba(1.0), rgba(2.0), rgba(3.0)]).unwrap();
        Texture::new(img, false).unwrap()
    }

    /// A 4 × 4 image whose red channel is x + 4 y.
    fn four_by_four() -> Image {
        Image::from_fn(4, 4, |x, y| [(x + 4 * y) as f32, x as f32, y as f32, 1.0])
    }

    fn red(t: &Texture, u: f32, v: f32, lod: f32, wrap: Wrap, filter: Filter) -> f32 {
        t.sample(Vec2::new(u, v), lod, wrap, filter).x
    }

    #[test]
    fn nearest_reads_the_texel_under_uv() {
        let t = two_by_two();
        let n = Filter::Nearest;
        assert_eq!(red(&t, 0.25, 0.25, 0.0, Wrap::Repeat, n), 0.0);
        assert_eq!(red(&t, 0.75, 0.25, 0.0, Wrap::Repeat, n), 1.0);
        assert_eq!(red(&t, 0.25, 0.75, 0.0, Wrap::Repeat, n), 2.0);
        assert_eq!(red(&t, 0.99, 0.99, 0.0, Wrap::Repeat, n), 3.0);
        // Texel boundaries belong to the texel on their right / below.
        assert_eq!(red(&t, 0.5, 0.0, 0.0, Wrap::Repeat, n), 1.0);
    }

    #[test]
    fn wrap_modes_outside_the_unit_square() {
        let t = two_by_two();
        let n = Filter::Nearest;
        // u = −0.25: texel −1. Repeat → 1, clamp → 0, mirror → 0 (as at u = 0.25).
        assert_eq!(red(&t, -0.25, 0.25, 0.0, Wrap::Repeat, n), 1.0);
        assert_eq!(red(&t, -0.25, 0.25, 0.0, Wrap::Clamp, n), 0.0);
        assert_eq!(red(&t, -0.25, 0.25, 0.0, Wrap::Mirror, n), 0.0);
        // u = 1.25: texel 2. Repeat → 0, clamp → 1, mirror → 1 (as at u = 0.75).
        assert_eq!(red(&t, 1.25, 0.25, 0.0, Wrap::Repeat, n), 0.0);
        assert_eq!(red(&t, 1.25, 0.25, 0.0, Wrap::Clamp, n), 1.0);
        assert_eq!(red(&t, 1.25, 0.25, 0.0, Wrap::Mirror, n), 1.0);
        // u = 1.75: texel 3. Repeat → 1, clamp → 1, mirror → 0 (as at u = 0.25).
        assert_eq!(red(&t, 1.75, 0.25, 0.0, Wrap::Repeat, n), 1.0);
        assert_eq!(red(&t, 1.75, 0.25, 0.0, Wrap::Mirror, n), 0.0);
        // u = −1.25: texel −3. Repeat → 1; mirror: −3 mod 4 = 1 < 2 → 1.
        assert_eq!(red(&t, -1.25, 0.25, 0.0, Wrap::Repeat, n), 1.0);
        assert_eq!(red(&t, -1.25, 0.25, 0.0, Wrap::Mirror, n), 1.0);
        // v wraps the same way: v = −0.25 reads the bottom row under repeat.
        assert_eq!(red(&t, 0.25, -0.25, 0.0, Wrap::Repeat, n), 2.0);
        assert_eq!(red(&t, 0.25, -0.25, 0.0, Wrap::Clamp, n), 0.0);
    }

    #[test]
    fn euclid_mod_matches_rem_euclid() {
        for n in [1, 2, 3, 7, 64] {
            for i in (-300..300).chain([i32::MIN, i32::MIN + 1, i32::MAX, i32::MAX - 1]) {
                assert_eq!(euclid_mod(i, n), i.rem_euclid(n), "{i} mod {n}");
            }
        }
    }

    #[test]
    fn wrap_index_sequences() {
        let seq =
            |wrap: Wrap| -> Vec<i32> { (-6..7).map(|i| wrap_index(i, 3, wrap.index())).collect() };
        assert_eq!(seq(Wrap::Repeat), [0, 1, 2, 0, 1, 2, 0, 1, 2, 0, 1, 2, 0]);
        assert_eq!(seq(Wrap::Clamp), [0, 0, 0, 0, 0, 0, 0, 1, 2, 2, 2, 2, 2]);
        assert_eq!(seq(Wrap::Mirror), [0, 1, 2, 2, 1, 0, 0, 1, 2, 2, 1, 0, 0]);
        // The extremes neither overflow nor leave the range.
        for wrap in Wrap::ALL {
            for i in [i32::MIN, i32::MIN + 1, -2147483520, 2147483520, i32::MAX] {
                let r = wrap_index(i, 5, wrap.index());
                assert!((0..5).contains(&r), "{wrap:?} {i} → {r}");
            }
        }
    }

    #[test]
    fn bilinear_at_centres_midpoints_and_edges() {
        let t = two_by_two();
        let b = Filter::Bilinear;
        // At texel centres: the texel itself.
        assert_eq!(red(&t, 0.25, 0.25, 0.0, Wrap::Clamp, b), 0.0);
        assert_eq!(red(&t, 0.75, 0.75, 0.0, Wrap::Clamp, b), 3.0);
        // Midpoint between the four centres: their mean.
        assert_eq!(red(&t, 0.5, 0.5, 0.0, Wrap::Clamp, b), 1.5);
        // Midpoint of the top row: (0 + 1) / 2.
        assert_eq!(red(&t, 0.5, 0.25, 0.0, Wrap::Clamp, b), 0.5);
        // A quarter of the way from centre 0 towards centre 1: x = 0.375·2 − 0.5 = 0.25.
        assert_eq!(red(&t, 0.375, 0.25, 0.0, Wrap::Clamp, b), 0.25);
        // At the left edge, u = 0: clamp holds texel 0; repeat blends texel 1 and 0 equally;
        // mirror blends texel 0 with itself.
        assert_eq!(red(&t, 0.0, 0.25, 0.0, Wrap::Clamp, b), 0.0);
        assert_eq!(red(&t, 0.0, 0.25, 0.0, Wrap::Repeat, b), 0.5);
        assert_eq!(red(&t, 0.0, 0.25, 0.0, Wrap::Mirror, b), 0.0);
        // u = 1.25 (x = 2, texel 2 exactly): repeat → texel 0.
        // u = 1.125 (x = 1.75): texels 1 and 2, tx = 0.75. Repeat: 2 → 0, so 1 + (0 − 1)·0.75;
        // clamp and mirror: 2 → 1, so 1.
        assert_eq!(red(&t, 1.25, 0.25, 0.0, Wrap::Repeat, b), 0.0);
        assert_eq!(red(&t, 1.125, 0.25, 0.0, Wrap::Repeat, b), 0.25);
        assert_eq!(red(&t, 1.125, 0.25, 0.0, Wrap::Clamp, b), 1.0);
        assert_eq!(red(&t, 1.125, 0.25, 0.0, Wrap::Mirror, b), 1.0);
        // u = −0.25 (x = −1): texel −1 exactly. Repeat → 1, clamp → 0, mirror → 0.
        assert_eq!(red(&t, -0.25, 0.25, 0.0, Wrap::Repeat, b), 1.0);
        assert_eq!(red(&t, -0.25, 0.25, 0.0, Wrap::Clamp, b), 0.0);
        assert_eq!(red(&t, -0.25, 0.25, 0.0, Wrap::Mirror, b), 0.0);
    }

    #[test]
    fn bilinear_on_four_by_four() {
        let t = Texture::new(four_by_four(), false).unwrap();
        let b = Filter::Bilinear;
        // Between texels (1, 1) = 5, (2, 1) = 6, (1, 2) = 9, (2, 2) = 10 at their middle.
        assert_eq!(red(&t, 0.5, 0.5, 0.0, Wrap::Repeat, b), 7.5);
        // x = 1.25 − 0.5·... : u = 0.4375 → x = 1.25, tx = 0.25; v = 0.375 → y = 1, ty = 0.
        assert_eq!(red(&t, 0.4375, 0.375, 0.0, Wrap::Repeat, b), 5.25);
        // Green (x) and blue (y) channels follow u and v linearly inside the image.
        let s = t.sample(Vec2::new(0.3, 0.6), 0.0, Wrap::Clamp, b);
        assert!((s.y - (0.3 * 4.0 - 0.5)).abs() < 1e-6, "{s}");
        assert!((s.z - (0.6 * 4.0 - 0.5)).abs() < 1e-6, "{s}");
        assert_eq!(s.w, 1.0);
    }

    #[test]
    fn mip_generation_averages() {
        let t = Texture::new(four_by_four(), true).unwrap();
        let sizes: Vec<(u32, u32)> = t.levels().iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, [(4, 4), (2, 2), (1, 1)]);
        // Level 1, texel (0, 0): mean of 0, 1, 4, 5.
        assert_eq!(t.levels()[1].texel(0, 0)[0], 2.5);
        assert_eq!(
            t.levels()[1].texel(1, 1)[0],
            (10.0 + 11.0 + 14.0 + 15.0) / 4.0
        );
        // Level 2: mean of 0..15.
        assert_eq!(t.levels()[2].texel(0, 0)[0], 7.5);
        assert_eq!(t.levels()[2].texel(0, 0)[3], 1.0);

        // Odd sizes: 5 × 3 → 2 × 1 → 1 × 1, each texel the area average.
        let img = Image::from_fn(5, 3, |x, y| [x as f32, y as f32, (x * y) as f32, 1.0]);
        let t = Texture::new(img, true).unwrap();
        let sizes: Vec<(u32, u32)> = t.levels().iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, [(5, 3), (2, 1), (1, 1)]);
        // Columns 0, 1, 2 with weights 2/5, 2/5, 1/5: 0.4 + 0.4 = 0.8; 0.2·2 + 0.4·3 + 0.4·4 = 3.2.
        let l1 = &t.levels()[1];
        assert!((l1.texel(0, 0)[0] - 0.8).abs() < 1e-6);
        assert!((l1.texel(1, 0)[0] - 3.2).abs() < 1e-6);
        // Rows 0, 1, 2 with weights 1/3: mean row 1.
        assert!((l1.texel(0, 0)[1] - 1.0).abs() < 1e-6);
        // The area average keeps the mean of every level.
        for l in t.levels() {
            let n = l.data.len() as f64;
            let mean = |c: usize| l.data.iter().map(|t| t[c] as f64).sum::<f64>() / n;
            assert!((mean(0) - 2.0).abs() < 1e-6, "{}×{}", l.width, l.height);
            assert!((mean(1) - 1.0).abs() < 1e-6);
            assert!((mean(2) - 2.0).abs() < 1e-6);
        }
        // Without mips: one level.
        assert_eq!(
            Texture::new(four_by_four(), false).unwrap().level_count(),
            1
        );
        // 1 × n: the width stays 1.
        let t = Texture::new(Image::filled(1, 8, rgba(0.5)), true).unwrap();
        let sizes: Vec<(u32, u32)> = t.levels().iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, [(1, 8), (1, 4), (1, 2), (1, 1)]);
        assert!(
            t.levels()
                .iter()
                .all(|l| l.data.iter().all(|&x| x == rgba(0.5)))
        );
    }

    /// Seed 002's chain: black, white, white, black.
    fn sunshine_chain() -> Texture {
        Texture::from_levels(vec![
            Image::filled(8, 8, rgba(0.0)),
            Image::filled(4, 4, rgba(1.0)),
            Image::filled(2, 2, rgba(1.0)),
            Image::filled(1, 1, rgba(0.0)),
        ])
        .unwrap()
    }

    #[test]
    fn lod_blends_levels_linearly() {
        let t = sunshine_chain();
        let uv = Vec2::new(0.3, 0.7);
        let b = Filter::Bilinear;
        let at = |lod: f32| t.sample(uv, lod, Wrap::Repeat, b).x;
        assert_eq!(at(0.0), 0.0);
        assert_eq!(at(0.5), 0.5);
        assert_eq!(at(0.25), 0.25);
        assert_eq!(at(1.0), 1.0);
        assert_eq!(at(1.5), 1.0);
        assert_eq!(at(2.75), 0.25);
        // Clamped to [0, 3].
        assert_eq!(at(-2.0), 0.0);
        assert_eq!(at(3.0), 0.0);
        assert_eq!(at(40.0), 0.0);
        assert_eq!(at(f32::NAN), 0.0);
        // Nearest: level ⌈lod + 0.5⌉ − 1, ties to the lower level.
        let near = |lod: f32| t.sample(uv, lod, Wrap::Repeat, Filter::Nearest).x;
        assert_eq!(near(0.5), 0.0);
        assert_eq!(near(0.51), 1.0);
        assert_eq!(near(2.5), 1.0);
        assert_eq!(near(2.51), 0.0);
        assert_eq!(near(7.0), 0.0);
        // Alpha is blended too (all 1 here).
        assert_eq!(t.sample(uv, 0.5, Wrap::Repeat, b).w, 1.0);
    }

    #[test]
    fn custom_chains_are_validated() {
        let e = Texture::from_levels(vec![]).unwrap_err();
        assert_eq!(e, TextureError::NoLevels);
        let e = Texture::from_levels(vec![
            Image::filled(8, 4, rgba(0.0)),
            Image::filled(4, 2, rgba(0.0)),
            Image::filled(2, 2, rgba(0.0)),
        ])
        .unwrap_err();
        assert_eq!(
            e,
            TextureError::LevelSize {
                level: 2,
                expected_width: 2,
                expected_height: 1,
                found_width: 2,
                found_height: 2
            }
        );
        assert_eq!(
            e.to_string(),
            "mip level 2 is 2×2, expected 2×1 (half of level 1, rounded down, at least 1)"
        );
        // Odd sizes round down; 1 stays 1.
        assert!(
            Texture::from_levels(vec![
                Image::filled(5, 1, rgba(0.0)),
                Image::filled(2, 1, rgba(0.0)),
                Image::filled(1, 1, rgba(0.0)),
            ])
            .is_ok()
        );
        let e = Texture::from_levels(vec![
            Image::filled(5, 1, rgba(0.0)),
            Image::filled(3, 1, rgba(0.0)),
        ])
        .unwrap_err();
        assert!(
            matches!(
                e,
                TextureError::LevelSize {
                    level: 1,
                    expected_width: 2,
                    ..
                }
            ),
            "{e}"
        );
        // A level whose data does not match its size names the level.
        let bad = Image {
            width: 2,
            height: 2,
            data: vec![rgba(0.0); 3],
        };
        let e = Texture::from_levels(vec![Image::filled(4, 4, rgba(0.0)), bad]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "mip level 1: image is 2×2 but its data holds 3 texels"
        );
        let e = Texture::new(Image::filled(0, 3, rgba(0.0)), true).unwrap_err();
        assert_eq!(
            e.to_string(),
            "mip level 0: image is 0×3: an image needs at least one texel"
        );
        assert!(Image::new(1, 1, vec![]).is_err());
    }

    #[test]
    fn texture_sets_pack_and_sample_like_the_textures() {
        let mut set = TextureSet::new();
        assert_eq!(set.insert("a", two_by_two()), Ok(0));
        assert_eq!(set.insert("sunshine", sunshine_chain()), Ok(1));
        assert_eq!(
            set.insert("mips", Texture::new(four_by_four(), true).unwrap()),
            Ok(2)
        );
        assert_eq!(
            set.insert("a", two_by_two()),
            Err(TextureError::DuplicateName("a".into()))
        );
        assert_eq!(set.index_of("mips"), Some(2));
        assert_eq!(set.name(1), Some("sunshine"));
        let pack = set.pack().unwrap();
        assert_eq!(pack.textures, [[0, 1], [1, 4], [5, 3]]);
        assert_eq!(pack.levels[0], [0, 2, 2, 0]);
        assert_eq!(pack.levels[1], [4, 8, 8, 0]);
        assert_eq!(pack.levels[2], [68, 4, 4, 0]);
        assert_eq!(pack.levels[4], [88, 1, 1, 0]);
        assert_eq!(pack.levels[5], [89, 4, 4, 0]);
        assert_eq!(pack.texels.len(), (89 + 16 + 4 + 1) * 4);
        assert_eq!(pack.texel_bytes().len(), pack.texels.len() * 4);
        assert_eq!(pack.level_bytes().len(), pack.levels.len() * 16);
        assert_eq!(pack.texture_bytes().len(), pack.textures.len() * 8);
        let mut state = 1u32;
        let mut rnd = |lo: f32, hi: f32| {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            lo + (hi - lo) * (state >> 8) as f32 / 16_777_216.0
        };
        for _ in 0..2000 {
            let tex = (rnd(0.0, 3.99)) as u32;
            let uv = Vec2::new(rnd(-2.0, 2.0), rnd(-2.0, 2.0));
            let lod = rnd(-1.0, 4.0);
            for wrap in Wrap::ALL {
                for filter in Filter::ALL {
                    let a = set.sample(tex, uv, lod, wrap, filter);
                    let b = pack.sample(tex, uv, lod, wrap.index(), filter.index());
                    assert_eq!(a, b, "tex {tex} uv {uv} lod {lod} {wrap:?} {filter:?}");
                }
            }
        }
        assert_eq!(
            set.sample(7, Vec2::ZERO, 0.0, Wrap::Repeat, Filter::Nearest),
            Vec4::ZERO
        );
        assert_eq!(pack.sample(7, Vec2::ZERO, 0.0, 0, 0), Vec4::ZERO);
        // An empty set still packs bindable buffers, and samples to zero.
        let empty = TextureSet::new().pack().unwrap();
        assert_eq!(empty.textures, [[0, 0]]);
        assert_eq!(empty.levels.len(), 1);
        assert_eq!(empty.texels.len(), 4);
        assert_eq!(empty.sample(0, Vec2::splat(0.5), 0.0, 0, 1), Vec4::ZERO);
    }

    #[test]
    fn enum_indices_are_fixed() {
        assert_eq!(Wrap::ALL.map(Wrap::index), [0, 1, 2]);
        assert_eq!(Filter::ALL.map(Filter::index), [0, 1]);
        assert_eq!(Wrap::ALL.map(Wrap::name), ["repeat", "clamp", "mirror"]);
        assert_eq!(Filter::ALL.map(Filter::name), ["nearest", "bilinear"]);
        assert_eq!(Wrap::from_index(7), Wrap::Mirror);
        assert_eq!(Filter::from_index(7), Filter::Bilinear);
    }

    #[test]
    fn bindings_template_fills_in() {
        let s = sample_bindings_wgsl(1, 4);
        assert!(s.contains("@group(1) @binding(4) var<storage, read> mg_texels: array<f32>;"));
        assert!(s.contains("@group(1) @binding(5) var<storage, read> mg_levels"));
        assert!(s.contains("@group(1) @binding(6) var<storage, read> mg_textures"));
        assert!(!s.contains('$'));
    }

    #[test]
    fn sample_wgsl_validates_under_naga() {
        let src = format!("{}\n{}", sample_bindings_wgsl(0, 0), SAMPLE_WGSL);
        let module = naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| {
            panic!("{}", e.emit_to_string(&src));
        });
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::empty(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{e:?}"));
    }
}
