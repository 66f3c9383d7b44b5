//! Reading and writing texture images with the `image` crate: the I/O side of
//! [`crate::texture`] (which does none).
//!
//! Colour conventions: each image is read in a colour space ([`crate::color_space`]): a
//! graph's texture node may name it (`"color_space": "srgb" | "linear" | "data"`), else it is
//! the file type's: PNG and JPEG files are sRGB-encoded colour (any bit depth) and are
//! decoded to linear light with the IEC 61966-2-1 transfer function; Radiance HDR and
//! OpenEXR files are linear and are read unchanged. `linear` and `data` images are read
//! unchanged whatever their type. Alpha is linear and kept as is.
//! Greyscale images are expanded to RGB; images without alpha get alpha 1. Saving mirrors
//! this: [`save_png`] clamps to [0, 1] and sRGB-encodes to 8 bits, [`save_exr`] writes linear
//! f32 RGBA exactly. Saves are atomic (temporary file in the same folder, synced, renamed)
//! and deterministic (the same image gives the same bytes).
//!
//! Texture files are referenced from a graph by a path relative to the graph file, confined
//! to its folder unless the caller allows any path ([`load_graph_textures_with`]): each is
//! opened once, checked as opened ([`crate::io::open_reference`]) and decoded from that
//! handle, never reopened by path. Loading reads an image's header first and reserves its
//! memory in a [`MemoryBudget`] before decoding ([`load_opened_image`]); texels that are
//! NaN, infinite or beyond [`crate::texture::MAX_TEXEL`] are refused, as are mip chains
//! longer than [`crate::texture::MAX_MIP_LEVELS`] or than their image halves into. Saved
//! images are encoded by extension ([`SaveFormat`]). Every error names the file at fault.

use crate::budget::MemoryBudget;
use crate::color_space::ColorSpace;
use crate::texture::{Image, Texture, TextureError};
use image::{ImageEncoder, ImageFormat};
use std::path::{Path, PathBuf};

/// sRGB-encoded value to linear light: `c/12.92` for c ≤ 0.04045, else `((c + 0.055)/1.055)^2.4`.
///
/// Source: IEC 61966-2-1:1999 (sRGB), the inverse transfer function.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear light to sRGB encoding: `12.92 c` for c ≤ 0.0031308, else `1.055 c^(1/2.4) − 0.055`.
///
/// Source: IEC 61966-2-1:1999 (sRGB), the transfer function.
pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// The path of a texture referenced as `reference` from the graph file `graph_file`:
/// relative references are taken from the graph file's folder, absolute ones kept.
pub fn resolve_relative(graph_file: &Path, reference: &Path) -> PathBuf {
    if reference.is_absolute() {
        return reference.to_owned();
    }
    match graph_file.parent() {
        Some(dir) => dir.join(reference),
        None => reference.to_owned(),
    }
}

/// A [`TextureError::File`] naming `path`.
fn file_error(path: &Path, message: impl std::fmt::Display) -> TextureError {
    TextureError::File {
        path: path.to_owned(),
        message: message.to_string(),
    }
}

/// Reads an image file (PNG, JPEG, Radiance HDR or OpenEXR, recognised by content, else by
/// extension) as linear RGBA, in its file type's default colour space; see the module doc
/// for the colour conventions.
pub fn load_image(path: &Path) -> Result<Image, TextureError> {
    load_image_as(path, None)
}

/// Reads an image file as [`load_image`] does, its values read in `space`
/// ([`crate::color_space`]): `srgb` decodes them from sRGB to linear light, `linear` and
/// `data` keep them as stored; `None` takes the default of the file's type (recognised by
/// content: sRGB for PNG and JPEG, linear for HDR and EXR). Within a budget of its own of
/// [`crate::budget::DEFAULT_MEMORY_BUDGET`] ([`load_opened_image`]).
pub fn load_image_as(path: &Path, space: Option<ColorSpace>) -> Result<Image, TextureError> {
    let file = std::fs::File::open(path)
        .map_err(|e| file_error(path, format_args!("cannot read: {e}")))?;
    load_opened_image(path, file, space, &MemoryBudget::default())
}

/// Bytes per texel a loaded image keeps: linear RGBA f32.
pub const TEXEL_BYTES: u64 = 16;

/// Bytes a `width × height` image holds at the peak of its loading: the decoder's buffer
/// (`decoded` bytes, from the header) and two RGBA f32 copies (the decoder's conversion and
/// the linear texels made from it; [`TEXEL_BYTES`] each).
pub fn decode_peak_bytes(width: u32, height: u32, decoded: u64) -> u64 {
    decoded.saturating_add(2 * TEXEL_BYTES * width as u64 * height as u64)
}

/// Bytes of the mip levels below a `width × height` level 0 ([`Texture::new`]'s box mips,
/// down to 1 × 1), at [`TEXEL_BYTES`] per texel.
pub fn mip_bytes(width: u32, height: u32) -> u64 {
    let (mut w, mut h, mut total) = (width, height, 0u64);
    while w > 1 || h > 1 {
        (w, h) = crate::texture::mip_size(w, h);
        total += TEXEL_BYTES * w as u64 * h as u64;
    }
    total
}

/// Reads the image in `file` (opened from `path`, which names it in errors and gives the
/// format when the content does not), as [`load_image_as`] does, and never reopens `path`.
///
/// The header is read first: the image's peak ([`decode_peak_bytes`]) is reserved in
/// `budget` before the decoder allocates anything, so an image that does not fit is refused
/// naming its size and the budget; the [`TEXEL_BYTES`] per texel it keeps stay reserved.
/// Texels that are NaN, infinite or beyond [`crate::texture::MAX_TEXEL`] are refused,
/// naming the first one ([`crate::texture::check_texels`]).
pub fn load_opened_image(
    path: &Path,
    file: std::fs::File,
    space: Option<ColorSpace>,
    budget: &MemoryBudget,
) -> Result<Image, TextureError> {
    use image::ImageDecoder;
    let mut reader = image::ImageReader::new(std::io::BufReader::new(file));
    if let Ok(format) = ImageFormat::from_path(path) {
        reader.set_format(format);
    }
    let mut reader = reader
        .with_guessed_format()
        .map_err(|e| file_error(path, format_args!("cannot read: {e}")))?;
    let default = match reader.format() {
        Some(ImageFormat::Png | ImageFormat::Jpeg) => ColorSpace::Srgb,
        Some(ImageFormat::Hdr | ImageFormat::OpenExr) => ColorSpace::Linear,
        Some(f) => {
            return Err(file_error(
                path,
                format_args!("unsupported image format {f:?} (PNG, JPEG, HDR or EXR expected)"),
            ));
        }
        None => {
            return Err(file_error(
                path,
                "unknown image format (PNG, JPEG, HDR or EXR expected)",
            ));
        }
    };
    // The decoder's own allocation limit follows the budget (its default is 512 MiB).
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(budget.remaining());
    reader.limits(limits);
    let srgb = space.unwrap_or(default).decodes_srgb();
    let decoder = reader
        .into_decoder()
        .map_err(|e| file_error(path, format_args!("cannot decode: {}", decode_reason(&e))))?;
    let (width, height) = decoder.dimensions();
    let peak = decode_peak_bytes(width, height, decoder.total_bytes());
    budget
        .reserve(|| format!("a {width}×{height} image"), peak)
        .map_err(|e| file_error(path, e))?;
    let kept = TEXEL_BYTES * width as u64 * height as u64;
    let loaded = decode_reserved(path, decoder, srgb);
    budget.release(match loaded {
        Ok(_) => peak - kept,
        Err(_) => peak,
    });
    loaded
}

/// A decoder's error in words: the PNG decoder writes a chunk's type as a Rust debug
/// struct (`ChunkType { type: IHDR, critical: true, … }`), cut here to its name (`IHDR`).
fn decode_reason(e: &image::ImageError) -> String {
    let mut text = e.to_string();
    const OPEN: &str = "ChunkType { type: ";
    while let Some(start) = text.find(OPEN) {
        let rest = &text[start + OPEN.len()..];
        let name_end = rest.find([',', ' ', '}']).unwrap_or(rest.len());
        let name = rest[..name_end].to_owned();
        let close = rest
            .find('}')
            .map_or(text.len(), |k| start + OPEN.len() + k + 1);
        text.replace_range(start..close, &name);
    }
    text
}

/// The decoding part of [`load_opened_image`], its memory reserved.
fn decode_reserved(
    path: &Path,
    decoder: impl image::ImageDecoder,
    srgb: bool,
) -> Result<Image, TextureError> {
    let decoded = image::DynamicImage::from_decoder(decoder)
        .map_err(|e| file_error(path, format_args!("cannot decode: {}", decode_reason(&e))))?;
    let rgba = decoded.to_rgba32f();
    drop(decoded);
    let (width, height) = rgba.dimensions();
    let data = rgba
        .pixels()
        .map(|p| {
            let [r, g, b, a] = p.0;
            if srgb {
                [srgb_to_linear(r), srgb_to_linear(g), srgb_to_linear(b), a]
            } else {
                [r, g, b, a]
            }
        })
        .collect();
    drop(rgba);
    let in_file = |e| TextureError::InFile {
        path: path.to_owned(),
        source: Box::new(e),
    };
    let image = Image::new(width, height, data).map_err(in_file)?;
    crate::texture::check_texels(&image).map_err(in_file)?;
    Ok(image)
}

/// Reads a texture: one path gives that image, with generated mip levels when `mips` is
/// true; several paths give a custom mip chain, largest level first (`mips` is then
/// ignored), each level half the size of the one before ([`Texture::from_levels`]). Errors
/// name the file at fault.
pub fn load_texture(paths: &[PathBuf], mips: bool) -> Result<Texture, TextureError> {
    load_texture_as(paths, mips, None)
}

/// Reads a texture as [`load_texture`] does, every level's values read in `space`
/// ([`load_image_as`]), within a budget of its own of [`crate::budget::DEFAULT_MEMORY_BUDGET`].
pub fn load_texture_as(
    paths: &[PathBuf],
    mips: bool,
    space: Option<ColorSpace>,
) -> Result<Texture, TextureError> {
    check_chain_length(paths.len())?;
    let files = paths
        .iter()
        .map(|p| {
            std::fs::File::open(p)
                .map(|file| crate::io::OpenedReference {
                    path: p.clone(),
                    file,
                })
                .map_err(|e| file_error(p, format_args!("cannot read: {e}")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    load_opened_texture(files, mips, space, &MemoryBudget::default())
}

/// Refuses a custom mip chain of more than [`crate::texture::MAX_MIP_LEVELS`] files before
/// any is opened.
fn check_chain_length(levels: usize) -> Result<(), TextureError> {
    let max = crate::texture::MAX_MIP_LEVELS;
    if levels > max {
        return Err(TextureError::File {
            path: PathBuf::from("mip chain"),
            message: format!("{levels} levels listed; a chain has at most {max}"),
        });
    }
    Ok(())
}

/// Reads a texture as [`load_texture_as`] does from files already opened (and checked:
/// [`crate::io::open_reference`]), never reopening their paths, every image and the
/// generated mips reserved in `budget` before they are allocated ([`load_opened_image`],
/// [`mip_bytes`]).
pub fn load_opened_texture(
    files: Vec<crate::io::OpenedReference>,
    mips: bool,
    space: Option<ColorSpace>,
    budget: &MemoryBudget,
) -> Result<Texture, TextureError> {
    check_chain_length(files.len())?;
    let mut files = files;
    match files.len() {
        0 => Err(TextureError::NoLevels),
        1 => {
            let one = files.remove(0);
            let image = load_opened_image(&one.path, one.file, space, budget)?;
            if mips {
                let (w, h) = (image.width, image.height);
                budget
                    .reserve(
                        || format!("the mip levels of a {w}×{h} image"),
                        mip_bytes(w, h),
                    )
                    .map_err(|e| file_error(&one.path, e))?;
            }
            Texture::new(image, mips).map_err(|e| TextureError::InFile {
                path: one.path.clone(),
                source: Box::new(e),
            })
        }
        _ => {
            let paths: Vec<PathBuf> = files.iter().map(|f| f.path.clone()).collect();
            let levels = files
                .into_iter()
                .map(|f| load_opened_image(&f.path, f.file, space, budget))
                .collect::<Result<Vec<_>, _>>()?;
            Texture::from_levels(levels).map_err(|e| {
                let at = match &e {
                    TextureError::LevelSize { level, .. } | TextureError::Level { level, .. } => {
                        *level
                    }
                    TextureError::TooManyLevels { max, .. } => *max,
                    _ => 0,
                };
                TextureError::InFile {
                    path: paths[at.min(paths.len() - 1)].clone(),
                    source: Box::new(e),
                }
            })
        }
    }
}

/// Checks `image` before it is saved to `path`.
fn check(path: &Path, image: &Image) -> Result<(), TextureError> {
    image.validate().map_err(|e| TextureError::InFile {
        path: path.to_owned(),
        source: Box::new(e),
    })
}

/// The 8-bit value of `x` in [0, 1] (clamped; NaN gives 0), rounded to nearest.
fn to_u8(x: f32) -> u8 {
    (x.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// Encodes `image` as an 8-bit RGBA PNG, colour sRGB-encoded, alpha linear.
fn encode_png(image: &Image) -> Result<Vec<u8>, String> {
    image.validate().map_err(|e| e.to_string())?;
    let bytes: Vec<u8> = image
        .data
        .iter()
        .flat_map(|&[r, g, b, a]| {
            [
                to_u8(linear_to_srgb(r.clamp(0.0, 1.0))),
                to_u8(linear_to_srgb(g.clamp(0.0, 1.0))),
                to_u8(linear_to_srgb(b.clamp(0.0, 1.0))),
                to_u8(a),
            ]
        })
        .collect();
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new(&mut out)
        .write_image(
            &bytes,
            image.width,
            image.height,
            image::ExtendedColorType::Rgba8,
        )
        .map_err(|e| e.to_string())?;
    Ok(out)
}

/// Encodes `image` as a linear f32 RGBA OpenEXR file.
fn encode_exr(image: &Image) -> Result<Vec<u8>, String> {
    image.validate().map_err(|e| e.to_string())?;
    let mut out = std::io::Cursor::new(Vec::new());
    image::codecs::openexr::OpenExrEncoder::new(&mut out)
        .write_image(
            bytemuck::cast_slice(&image.data),
            image.width,
            image.height,
            image::ExtendedColorType::Rgba32F,
        )
        .map_err(|e| e.to_string())?;
    Ok(out.into_inner())
}

/// Saves `image` as an 8-bit RGBA PNG, colour clamped to [0, 1] and sRGB-encoded, alpha
/// clamped and linear, atomically.
pub fn save_png(path: &Path, image: &Image) -> Result<(), TextureError> {
    check(path, image)?;
    let bytes =
        encode_png(image).map_err(|e| file_error(path, format_args!("cannot encode: {e}")))?;
    crate::io::write_atomic(path, &bytes)
        .map_err(|e| file_error(path, format_args!("cannot write: {e}")))
}

/// Refuses a pixel buffer whose length is not `width × height`, or an empty image.
fn check_rgb8_size(
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[[u8; 3]],
) -> Result<(), TextureError> {
    if pixels.len() != (width as usize) * (height as usize) || width == 0 || height == 0 {
        return Err(file_error(
            path,
            format_args!("{width}×{height} image with {} pixels", pixels.len()),
        ));
    }
    Ok(())
}

/// Saves display-ready 8-bit sRGB pixels (row-major, top row first) as an RGB PNG,
/// atomically. The bytes depend only on the pixels (no time stamps).
pub fn save_png_rgb8(
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[[u8; 3]],
) -> Result<(), TextureError> {
    use image::ImageEncoder;
    check_rgb8_size(path, width, height, pixels)?;
    let mut out = std::io::Cursor::new(Vec::new());
    image::codecs::png::PngEncoder::new(&mut out)
        .write_image(
            pixels.as_flattened(),
            width,
            height,
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| file_error(path, format_args!("cannot encode: {e}")))?;
    crate::io::write_atomic(path, out.into_inner())
        .map_err(|e| file_error(path, format_args!("cannot write: {e}")))
}

/// Saves `image` as a linear f32 RGBA OpenEXR file (exact), atomically.
pub fn save_exr(path: &Path, image: &Image) -> Result<(), TextureError> {
    check(path, image)?;
    let bytes =
        encode_exr(image).map_err(|e| file_error(path, format_args!("cannot encode: {e}")))?;
    crate::io::write_atomic(path, &bytes)
        .map_err(|e| file_error(path, format_args!("cannot write: {e}")))
}

/// Loads every image the graph's texture nodes name, keyed as the plan expects
/// ([`crate::document::TextureSource::key`]): [`load_graph_textures_with`] confined to the
/// graph file's folder ([`crate::io::PathPolicy::InsideGraphFolder`]), errors as text.
pub fn load_graph_textures(
    graph: &crate::Graph,
    graph_file: &Path,
) -> Result<crate::texture::TextureSet, TextureError> {
    load_graph_textures_with(graph, graph_file, crate::io::PathPolicy::InsideGraphFolder).map_err(
        |e| match e {
            GraphTextureError::Texture { source, .. } => source,
            e @ GraphTextureError::Path(_) => file_error(graph_file, e),
        },
    )
}

/// Why a graph's images could not be loaded, naming the graph file and the node.
#[derive(Debug, thiserror::Error)]
pub enum GraphTextureError {
    /// A path is outside the graph's folder, missing or not a regular file.
    #[error(transparent)]
    Path(#[from] crate::io::PathError),
    /// An image could not be read or decoded.
    #[error("{}: node '{node}': {source}", file.display())]
    Texture {
        /// The graph file.
        file: PathBuf,
        /// The texture node.
        node: String,
        /// The error, naming the image file.
        source: TextureError,
    },
}

/// Loads every image the graph's texture nodes name (paths relative to `graph_file`, each
/// opened once and checked against `policy` as opened, [`crate::io::open_reference`]; custom
/// mip chains as listed), keyed as the plan expects, within a budget of its own of
/// [`crate::budget::DEFAULT_MEMORY_BUDGET`]. Scene textures (`scene:…`) are left to the renderer.
pub fn load_graph_textures_with(
    graph: &crate::Graph,
    graph_file: &Path,
    policy: crate::io::PathPolicy,
) -> Result<crate::texture::TextureSet, GraphTextureError> {
    load_graph_textures_within(graph, graph_file, policy, &MemoryBudget::default())
}

/// [`load_graph_textures_with`] with every image and mip chain reserved in `budget` before
/// it is allocated ([`load_opened_texture`]).
pub fn load_graph_textures_within(
    graph: &crate::Graph,
    graph_file: &Path,
    policy: crate::io::PathPolicy,
    budget: &MemoryBudget,
) -> Result<crate::texture::TextureSet, GraphTextureError> {
    let mut set = crate::texture::TextureSet::new();
    for node in graph.nodes() {
        let Some(source) = &node.texture else {
            continue;
        };
        let key = node.texture_key().unwrap_or_default();
        if source.scene_name().is_some() || set.index_of(&key).is_some() {
            continue;
        }
        let by = format!("node '{}'", node.id);
        let wrap = |source| GraphTextureError::Texture {
            file: graph_file.to_owned(),
            node: node.id.clone(),
            source,
        };
        let files = source.files();
        check_chain_length(files.len()).map_err(wrap)?;
        let opened = files
            .iter()
            .map(|f| crate::io::open_reference(graph_file, &by, f, policy))
            .collect::<Result<Vec<_>, _>>()?;
        let texture = load_opened_texture(opened, true, node.color_space, budget).map_err(wrap)?;
        set.insert(key, texture).map_err(wrap)?;
    }
    Ok(set)
}

/// The image file formats [`save_rgb8`] and [`save_hdr`] write, chosen by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SaveFormat {
    /// `.png`: 8-bit sRGB.
    Png,
    /// `.jpg`, `.jpeg`: 8-bit sRGB, quality [`JPEG_QUALITY`].
    Jpeg,
    /// `.exr`: linear f32 RGBA.
    Exr,
}

/// The extensions [`SaveFormat::from_path`] accepts.
pub const SAVE_EXTENSIONS: [&str; 4] = ["png", "jpg", "jpeg", "exr"];

/// JPEG quality (1–100) of [`SaveFormat::Jpeg`] files.
pub const JPEG_QUALITY: u8 = 95;

impl SaveFormat {
    /// The format of `path`'s extension (case-insensitive); an error listing the supported
    /// extensions otherwise.
    pub fn from_path(path: &Path) -> Result<SaveFormat, TextureError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("png") => Ok(SaveFormat::Png),
            Some("jpg" | "jpeg") => Ok(SaveFormat::Jpeg),
            Some("exr") => Ok(SaveFormat::Exr),
            other => Err(file_error(
                path,
                format_args!(
                    "{}: cannot choose an image format; use one of .{}",
                    match other {
                        Some(e) => format!("unsupported extension '.{e}'"),
                        None => "no extension".to_owned(),
                    },
                    SAVE_EXTENSIONS.join(", .")
                ),
            )),
        }
    }
}

/// Saves display-ready 8-bit sRGB pixels as PNG or JPEG by `path`'s extension
/// ([`SaveFormat::from_path`]); `.exr` is refused here (it needs linear data: [`save_exr`]).
pub fn save_rgb8(
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[[u8; 3]],
) -> Result<(), TextureError> {
    match SaveFormat::from_path(path)? {
        SaveFormat::Png => save_png_rgb8(path, width, height, pixels),
        SaveFormat::Jpeg => save_jpeg_rgb8(path, width, height, pixels),
        SaveFormat::Exr => Err(file_error(
            path,
            "an 8-bit image cannot be saved as EXR (linear data needed)",
        )),
    }
}

/// Saves display-ready 8-bit sRGB pixels (row-major, top row first) as a baseline JPEG of
/// quality [`JPEG_QUALITY`], atomically.
pub fn save_jpeg_rgb8(
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[[u8; 3]],
) -> Result<(), TextureError> {
    check_rgb8_size(path, width, height, pixels)?;
    let mut out = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut out, JPEG_QUALITY)
        .write_image(
            pixels.as_flattened(),
            width,
            height,
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| file_error(path, format_args!("cannot encode: {e}")))?;
    crate::io::write_atomic(path, out)
        .map_err(|e| file_error(path, format_args!("cannot write: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic test image: colours spanning [0, 1] and a little beyond, alpha in [0, 1].
    fn test_image(w: u32, h: u32) -> Image {
        let mut s = 12345u32;
        Image::from_fn(w, h, |_, _| {
            let mut next = || {
                s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                (s >> 8) as f32 / 16_777_216.0
            };
            [next(), next() * next(), next(), next()]
        })
    }

    #[test]
    fn srgb_transfer_functions_invert_each_other() {
        for i in 0..=1000 {
            let x = i as f32 / 1000.0;
            assert!((srgb_to_linear(linear_to_srgb(x)) - x).abs() < 1e-6, "{x}");
        }
        // Reference values (IEC 61966-2-1): sRGB 0.5 ↔ linear 0.214041.
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-6);
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn png_round_trips_within_one_step_of_255() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.png");
        let img = test_image(7, 5);
        save_png(&path, &img).unwrap();
        let back = load_image(&path).unwrap();
        assert_eq!((back.width, back.height), (7, 5));
        for (a, b) in img.data.iter().zip(&back.data) {
            for c in 0..3 {
                let (ea, eb) = (linear_to_srgb(a[c]), linear_to_srgb(b[c]));
                assert!((ea - eb).abs() <= 0.5 / 255.0 + 1e-5, "{a:?} → {b:?}");
            }
            assert!(
                (a[3] - b[3]).abs() <= 0.5 / 255.0 + 1e-6,
                "alpha {a:?} → {b:?}"
            );
        }
        // Deterministic bytes, and no temporary file left behind.
        let first = std::fs::read(&path).unwrap();
        save_png(&path, &img).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), first);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn png_is_decoded_as_srgb_and_out_of_range_values_clamp() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("grey.png");
        let grey = srgb_to_linear(128.0 / 255.0);
        let mut img = Image::filled(2, 1, [grey, grey, grey, 0.5]);
        img.data[1] = [-1.0, 2.0, f32::NAN, 7.0];
        save_png(&path, &img).unwrap();
        // The file holds sRGB code 128 and alpha 128 (0.5 · 255 rounded).
        let raw = image::open(&path).unwrap().to_rgba8();
        assert_eq!(raw.get_pixel(0, 0).0, [128, 128, 128, 128]);
        assert_eq!(raw.get_pixel(1, 0).0, [0, 255, 0, 255]);
        let back = load_image(&path).unwrap();
        let want = srgb_to_linear(128.0 / 255.0);
        assert!((back.data[0][0] - want).abs() < 1e-6, "{:?}", back.data[0]);
        assert!(
            (back.data[0][3] - 128.0 / 255.0).abs() < 1e-6,
            "alpha stays linear"
        );
    }

    #[test]
    fn exr_round_trips_exactly() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.exr");
        let mut img = test_image(9, 4);
        img.data[0] = [1e-30, 65504.0, 3.0e6, -2.5];
        save_exr(&path, &img).unwrap();
        let back = load_image(&path).unwrap();
        assert_eq!((back.width, back.height), (9, 4));
        for (a, b) in img.data.iter().zip(&back.data) {
            assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits));
        }
        let first = std::fs::read(&path).unwrap();
        save_exr(&path, &img).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), first, "deterministic bytes");
    }

    #[test]
    fn hdr_is_linear_and_jpeg_is_srgb() {
        let dir = tempfile::tempdir().unwrap();
        // Radiance HDR: 0.5 and 4.0 are exact in RGBE and must not be sRGB-decoded.
        let hdr = dir.path().join("t.hdr");
        let pixels = vec![image::Rgb([0.5f32, 4.0, 0.25]); 6];
        let mut bytes = Vec::new();
        image::codecs::hdr::HdrEncoder::new(&mut bytes)
            .encode(&pixels, 3, 2)
            .unwrap();
        std::fs::write(&hdr, bytes).unwrap();
        let img = load_image(&hdr).unwrap();
        assert_eq!((img.width, img.height), (3, 2));
        assert_eq!(img.data[4], [0.5, 4.0, 0.25, 1.0]);
        // JPEG of a flat sRGB 128 grey: decoded to linear (JPEG may be off by a code value).
        let jpg = dir.path().join("t.jpg");
        let mut bytes = Vec::new();
        image::codecs::jpeg::JpegEncoder::new_with_quality(&mut bytes, 95)
            .write_image(&[128u8; 8 * 8 * 3], 8, 8, image::ExtendedColorType::Rgb8)
            .unwrap();
        std::fs::write(&jpg, bytes).unwrap();
        let img = load_image(&jpg).unwrap();
        let want = srgb_to_linear(128.0 / 255.0);
        for t in &img.data {
            assert!((t[0] - want).abs() < 0.005, "{t:?} vs {want}");
            assert_eq!(t[3], 1.0);
        }
    }

    #[test]
    fn load_texture_generates_or_reads_mip_chains() {
        let dir = tempfile::tempdir().unwrap();
        let p = |n: &str| dir.path().join(n);
        save_exr(&p("l0.exr"), &Image::filled(4, 2, [0.0, 0.0, 0.0, 1.0])).unwrap();
        save_exr(&p("l1.exr"), &Image::filled(2, 1, [1.0, 1.0, 1.0, 1.0])).unwrap();
        save_exr(&p("l2.exr"), &Image::filled(1, 1, [0.0, 0.0, 0.0, 1.0])).unwrap();
        save_exr(&p("bad.exr"), &Image::filled(2, 2, [0.0; 4])).unwrap();
        let t = load_texture(&[p("l0.exr")], true).unwrap();
        assert_eq!(t.level_count(), 3);
        let t = load_texture(&[p("l0.exr")], false).unwrap();
        assert_eq!(t.level_count(), 1);
        let t = load_texture(&[p("l0.exr"), p("l1.exr"), p("l2.exr")], false).unwrap();
        assert_eq!(t.level_count(), 3);
        assert_eq!(t.levels()[1].texel(1, 0), [1.0; 4]);
        let e = load_texture(&[p("l0.exr"), p("bad.exr")], true).unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.contains("bad.exr") && msg.contains("mip level 1 is 2×2, expected 2×1"),
            "{msg}"
        );
        assert_eq!(load_texture(&[], true).unwrap_err(), TextureError::NoLevels);
    }

    #[test]
    fn errors_name_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("missing.png");
        let msg = load_image(&missing).unwrap_err().to_string();
        assert!(
            msg.contains("missing.png") && msg.contains("cannot read"),
            "{msg}"
        );
        let junk = dir.path().join("junk.png");
        std::fs::write(&junk, b"\x89PNG\r\n\x1a\nnot really").unwrap();
        let msg = load_image(&junk).unwrap_err().to_string();
        assert!(
            msg.contains("junk.png") && msg.contains("cannot decode"),
            "{msg}"
        );
        let text = dir.path().join("notes.txt");
        std::fs::write(&text, b"hello").unwrap();
        let msg = load_image(&text).unwrap_err().to_string();
        assert!(msg.contains("notes.txt") && msg.contains("format"), "{msg}");
        let e = load_texture(&[dir.path().join("a.exr"), missing.clone()], true).unwrap_err();
        assert!(e.to_string().contains("a.exr"), "{e}");
        // Saving into a folder that does not exist names the file, leaves nothing behind.
        let nowhere = dir.path().join("no/such/dir/out.png");
        let msg = save_png(&nowhere, &Image::filled(1, 1, [0.0; 4]))
            .unwrap_err()
            .to_string();
        assert!(
            msg.contains("out.png") && msg.contains("cannot write"),
            "{msg}"
        );
        // An invalid image is refused before anything is written.
        let bad = Image {
            width: 2,
            height: 2,
            data: vec![],
        };
        let out = dir.path().join("bad.exr");
        let msg = save_exr(&out, &bad).unwrap_err().to_string();
        assert!(
            msg.contains("bad.exr") && msg.contains("data holds 0 texels"),
            "{msg}"
        );
        assert!(!out.exists());
    }

    #[test]
    fn references_resolve_from_the_graph_folder() {
        let g = Path::new("graphs/water.json");
        assert_eq!(
            resolve_relative(g, Path::new("textures/wave.png")),
            Path::new("graphs/textures/wave.png")
        );
        assert_eq!(
            resolve_relative(Path::new("water.json"), Path::new("wave.png")),
            Path::new("wave.png")
        );
        let abs = std::env::temp_dir().join("wave.png");
        assert_eq!(resolve_relative(g, &abs), abs);
    }
}
