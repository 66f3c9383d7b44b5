//! The textures a material expects: names, formats, sizes and mips, and uploading a
//! [`TextureSet`] for either texture mode.
//!
//! **Formats (hardware mode).** By source and colour space ([`crate::color_space`]): PNG and
//! JPEG read as `srgb` (their default) → `rgba8unorm-srgb`, so the hardware decodes sRGB
//! before filtering, as the CPU filters in linear light; PNG and JPEG read as `linear` or
//! `data` → `rgba8unorm`, the stored bytes unchanged (a 16-bit PNG is rounded to 8 bits in
//! this mode, as for `srgb`; the exact mode keeps every bit); Radiance HDR (8-bit shared-exponent) and scene textures (rendered HDR
//! radiance) → `rgba16float`; OpenEXR (32-bit float) → `rgba32float` when the device has
//! `FLOAT32_FILTERABLE` ([`super::MaterialOptions::float32_filterable`]), else `rgba16float`:
//! WebGPU cannot filter `rgba32float` without that feature, and a non-filtering sampler would
//! lose bilinear and trilinear filtering, so 16-bit float (11 significant bits, range ±65504)
//! is the default. Every mip level of the [`crate::texture::Texture`] is uploaded (the CPU's
//! box-filtered levels, or a custom chain), never regenerated on the GPU.

use super::MaterialError;
use crate::texture::{Filter, Image, TextureSet, Wrap};
use crate::wgsl::{Binding, ShaderModule};

/// Where a texture's texels come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextureSource {
    /// An image file (or a custom mip chain of files) the graph names.
    File,
    /// A `scene:` texture the app renders (refraction, reflection, background, environment).
    Scene,
}

/// One texture slot of a material.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureInfo {
    /// Slot index (`tex` argument of `mg_sample_texture`).
    pub slot: u32,
    /// The key it is bound under: the path as the graph writes it, a chain's paths joined by
    /// `|`, or `scene:NAME`.
    pub name: String,
    /// File or scene texture.
    pub source: TextureSource,
    /// How the image's values are read (scene textures: linear).
    pub color_space: crate::color_space::ColorSpace,
    /// The texture format of the hardware mode.
    pub format: wgpu::TextureFormat,
    /// Binding of its `texture_2d<f32>` in the hardware mode (`None` in the exact mode).
    pub binding: Option<u32>,
    /// Size of level 0 and number of mip levels, once known ([`super::Material::bind_textures`]).
    pub size: Option<(u32, u32, u32)>,
}

/// The colour space of texture `key` (scene textures: linear).
fn space_of(key: &str) -> crate::color_space::ColorSpace {
    if key.starts_with(crate::document::TextureSource::SCENE) {
        return crate::color_space::ColorSpace::Linear;
    }
    crate::color_space::ColorSpace::of_key(key).1
}

/// The hardware format for texture `key`.
pub(super) fn format_for(key: &str, float32_filterable: bool) -> wgpu::TextureFormat {
    use wgpu::TextureFormat as F;
    if key.starts_with(crate::document::TextureSource::SCENE) {
        return F::Rgba16Float;
    }
    let (path, space) = crate::color_space::ColorSpace::of_key(key);
    let first = path.split('|').next().unwrap_or(path).to_ascii_lowercase();
    let ext = first.rsplit('.').next().unwrap_or("");
    match ext {
        "png" | "jpg" | "jpeg" if space.decodes_srgb() => F::Rgba8UnormSrgb,
        "png" | "jpg" | "jpeg" => F::Rgba8Unorm,
        "exr" if float32_filterable => F::Rgba32Float,
        _ => F::Rgba16Float,
    }
}

/// The contract name of a texture format.
pub fn format_name(f: wgpu::TextureFormat) -> &'static str {
    use wgpu::TextureFormat as F;
    match f {
        F::Rgba8UnormSrgb => "rgba8unorm-srgb",
        F::Rgba8Unorm => "rgba8unorm",
        F::Rgba16Float => "rgba16float",
        F::Rgba32Float => "rgba32float",
        _ => "unsupported",
    }
}

/// The slots of `module`'s textures.
pub(super) fn infos(module: &ShaderModule, float32_filterable: bool) -> Vec<TextureInfo> {
    module
        .textures
        .iter()
        .enumerate()
        .map(|(k, name)| TextureInfo {
            slot: k as u32,
            name: name.clone(),
            source: if name.starts_with(crate::document::TextureSource::SCENE) {
                TextureSource::Scene
            } else {
                TextureSource::File
            },
            color_space: space_of(name),
            format: format_for(name, float32_filterable),
            binding: module
                .bindings
                .iter()
                .find(|(_, b)| *b == Binding::Texture(k as u32))
                .map(|(b, _)| *b),
            size: None,
        })
        .collect()
}

/// The texels of `image` in `format`, rows from the top, tightly packed.
pub fn texel_bytes(image: &Image, format: wgpu::TextureFormat) -> Vec<u8> {
    use wgpu::TextureFormat as F;
    match format {
        F::Rgba8UnormSrgb => image
            .data
            .iter()
            .flat_map(|&[r, g, b, a]| {
                let srgb = |c: f32| unorm8(crate::image_io::linear_to_srgb(c.clamp(0.0, 1.0)));
                [srgb(r), srgb(g), srgb(b), unorm8(a)]
            })
            .collect(),
        F::Rgba8Unorm => image
            .data
            .iter()
            .flat_map(|&[r, g, b, a]| [unorm8(r), unorm8(g), unorm8(b), unorm8(a)])
            .collect(),
        F::Rgba32Float => bytemuck::cast_slice(&image.data).to_vec(),
        _ => image
            .data
            .iter()
            .flatten()
            .flat_map(|&x| half::f16::from_f32(x).to_le_bytes())
            .collect(),
    }
}

/// `x` in [0, 1] as an 8-bit unorm, rounded to nearest (NaN → 0).
fn unorm8(x: f32) -> u8 {
    (x.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// The wgpu sampler of a (wrap, filter) pair, as the hardware mode binds it.
pub fn sampler_descriptor(wrap: Wrap, filter: Filter) -> wgpu::SamplerDescriptor<'static> {
    let address = match wrap {
        Wrap::Repeat => wgpu::AddressMode::Repeat,
        Wrap::Clamp => wgpu::AddressMode::ClampToEdge,
        Wrap::Mirror => wgpu::AddressMode::MirrorRepeat,
    };
    let (f, m) = match filter {
        Filter::Nearest => (wgpu::FilterMode::Nearest, wgpu::MipmapFilterMode::Nearest),
        Filter::Bilinear => (wgpu::FilterMode::Linear, wgpu::MipmapFilterMode::Linear),
    };
    wgpu::SamplerDescriptor {
        label: Some("matgraph sampler"),
        address_mode_u: address,
        address_mode_v: address,
        address_mode_w: address,
        mag_filter: f,
        min_filter: f,
        mipmap_filter: m,
        lod_min_clamp: 0.0,
        lod_max_clamp: 32.0,
        compare: None,
        anisotropy_clamp: 1,
        border_color: None,
    }
}

/// The GPU resources of a material's textures, made by [`super::Material::upload_textures`].
#[derive(Debug)]
pub enum GpuTextures {
    /// Exact mode: `mg_texels`, `mg_levels`, `mg_textures`.
    Exact([wgpu::Buffer; 3]),
    /// Hardware mode: one view per slot and one sampler per sampler binding, in binding order.
    Hardware {
        /// The textures (kept alive with their views).
        textures: Vec<wgpu::Texture>,
        /// One view per slot, all levels.
        views: Vec<wgpu::TextureView>,
        /// `(binding, sampler)` pairs.
        samplers: Vec<(u32, wgpu::Sampler)>,
    },
    /// The module samples no texture.
    None,
}

/// Uploads the textures `module` samples from `set`.
pub(super) fn upload(
    module: &ShaderModule,
    infos: &[TextureInfo],
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    set: &TextureSet,
) -> Result<GpuTextures, MaterialError> {
    use wgpu::util::DeviceExt;
    if infos.is_empty() {
        return Ok(GpuTextures::None);
    }
    let missing = |name: &str| MaterialError::MissingTexture(name.to_owned());
    if module.entry.texture_mode() == crate::wgsl::TextureMode::Exact {
        let pack = set.pack_selection(&module.textures).map_err(|e| match e {
            crate::texture::TextureError::Missing(n) => missing(&n),
            e => MaterialError::Texture {
                name: module.textures.join(", "),
                message: e.to_string(),
            },
        })?;
        let buffer = |label: &str, bytes: &[u8]| {
            let mut v = bytes.to_vec();
            v.resize(v.len().next_multiple_of(4).max(4), 0);
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: &v,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        return Ok(GpuTextures::Exact([
            buffer("mg_texels", pack.texel_bytes()),
            buffer("mg_levels", pack.level_bytes()),
            buffer("mg_textures", pack.texture_bytes()),
        ]));
    }
    let mut textures = Vec::new();
    let mut views = Vec::new();
    for info in infos {
        let t = set
            .index_of(&info.name)
            .and_then(|i| set.get(i))
            .ok_or_else(|| missing(&info.name))?;
        let levels = t.levels();
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some(&info.name),
            size: wgpu::Extent3d {
                width: t.width(),
                height: t.height(),
                depth_or_array_layers: 1,
            },
            mip_level_count: levels.len() as u32,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: info.format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let bpp = info.format.block_copy_size(None).unwrap_or(16);
        for (k, level) in levels.iter().enumerate() {
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &texture,
                    mip_level: k as u32,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                &texel_bytes(level, info.format),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(level.width * bpp),
                    rows_per_image: Some(level.height),
                },
                wgpu::Extent3d {
                    width: level.width,
                    height: level.height,
                    depth_or_array_layers: 1,
                },
            );
        }
        views.push(texture.create_view(&wgpu::TextureViewDescriptor::default()));
        textures.push(texture);
    }
    let samplers = module
        .bindings
        .iter()
        .filter_map(|(b, k)| match k {
            Binding::Sampler(w, f) => {
                Some((*b, device.create_sampler(&sampler_descriptor(*w, *f))))
            }
            _ => None,
        })
        .collect();
    Ok(GpuTextures::Hardware {
        textures,
        views,
        samplers,
    })
}
