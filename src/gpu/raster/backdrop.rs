//! The bubble backdrop's maps on the device, in either texture mode.
//!
//! `backdrop.wgsl` reads map `k` through `mgr_backdrop_map(k, uv, wrap)`. In the exact mode
//! (`backdrop_exact.wgsl`) that is the scene textures' storage buffers and the CPU's bilinear
//! filter, bit for bit; in the hardware mode (`backdrop_hardware.wgsl`) a six-layer
//! `rgba16float` texture array, level 0, and the hardware's bilinear filter (a repeating and a
//! clamping sampler) on the objects pipeline's group 0, bindings [`MAPS_BINDING`] to
//! [`MAPS_BINDING`] + 2. llvmpipe runs the exact sampler's 16 scalar storage loads per map
//! as one gather per lane; its texture unit filters eight lanes at once. Measured on lavapipe
//! at 1024² (`gpu_render_stages`): `bubble` drawn in 195 ms with the exact maps, 133 ms with
//! the backdrop not drawn at all, 135 ms with the hardware maps; the hardware mode's
//! difference from the exact mode is bounded by `backdrop_hardware_maps_match_the_exact_sampler`
//! (the raster module's tests).

use super::{DeviceState, cached};
use crate::material::{sampler_descriptor, texel_bytes};
use crate::scene::{BUBBLE_MAP_SIZE as MAP_SIZE, bubble_maps};
use crate::texture::{Filter, Wrap};
use crate::wgsl::TextureMode;
use std::sync::Arc;

/// Binding of the maps' texture array on the objects' group 0 (then the repeating sampler,
/// then the clamping one).
pub(super) const MAPS_BINDING: u32 = 5;

/// Format of the hardware mode's maps (as the material's scene textures:
/// [`crate::material::TextureInfo::format`]).
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Whether a scene with the backdrop (`has_backdrop`) reads its maps through textures in
/// texture mode `mode`.
pub(super) fn uses_textures(has_backdrop: bool, mode: TextureMode) -> bool {
    has_backdrop && mode == TextureMode::Hardware
}

/// `backdrop.wgsl` with the map reader of its mode ([`uses_textures`]).
pub(super) fn source(textures: bool) -> String {
    let reader = match textures {
        true => include_str!("backdrop_hardware.wgsl"),
        false => include_str!("backdrop_exact.wgsl"),
    };
    format!("{reader}\n{}", include_str!("backdrop.wgsl"))
}

/// The layout entries of the maps' bindings, for the fragment stage.
pub(super) fn layout_entries() -> [wgpu::BindGroupLayoutEntry; 3] {
    let f = wgpu::ShaderStages::FRAGMENT;
    let sampler = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: f,
        ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
        count: None,
    };
    [
        wgpu::BindGroupLayoutEntry {
            binding: MAPS_BINDING,
            visibility: f,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: true },
                view_dimension: wgpu::TextureViewDimension::D2Array,
                multisampled: false,
            },
            count: None,
        },
        sampler(MAPS_BINDING + 1),
        sampler(MAPS_BINDING + 2),
    ]
}

/// The maps' texture array and samplers on the device, uploaded once per device.
pub(super) struct MapTextures {
    view: wgpu::TextureView,
    repeat: wgpu::Sampler,
    clamp: wgpu::Sampler,
}

impl MapTextures {
    /// The device's maps (uploaded on first use).
    pub(super) fn of(s: &DeviceState) -> Arc<MapTextures> {
        cached(s, "backdrop maps/hardware", || MapTextures::upload(s))
    }

    fn upload(s: &DeviceState) -> MapTextures {
        let maps = bubble_maps().named();
        let size = wgpu::Extent3d {
            width: MAP_SIZE,
            height: MAP_SIZE,
            depth_or_array_layers: maps.len() as u32,
        };
        let texture = s.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("mgr backdrop maps"),
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let bpp = FORMAT.block_copy_size(None).unwrap_or(8);
        for (layer, (_, map)) in maps.iter().enumerate() {
            let level = &map.levels()[0];
            debug_assert_eq!((level.width, level.height), (MAP_SIZE, MAP_SIZE));
            s.queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d {
                        x: 0,
                        y: 0,
                        z: layer as u32,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                &texel_bytes(level, FORMAT),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(MAP_SIZE * bpp),
                    rows_per_image: Some(MAP_SIZE),
                },
                wgpu::Extent3d {
                    depth_or_array_layers: 1,
                    ..size
                },
            );
        }
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        // Level 0 only: the samplers' mip filter never applies.
        let sampler = |wrap| {
            s.device
                .create_sampler(&sampler_descriptor(wrap, Filter::Bilinear))
        };
        MapTextures {
            view,
            repeat: sampler(Wrap::Repeat),
            clamp: sampler(Wrap::Clamp),
        }
    }

    /// The bind group entries of [`layout_entries`].
    pub(super) fn entries(&self) -> [(u32, wgpu::BindingResource<'_>); 3] {
        [
            (MAPS_BINDING, wgpu::BindingResource::TextureView(&self.view)),
            (
                MAPS_BINDING + 1,
                wgpu::BindingResource::Sampler(&self.repeat),
            ),
            (
                MAPS_BINDING + 2,
                wgpu::BindingResource::Sampler(&self.clamp),
            ),
        ]
    }
}
