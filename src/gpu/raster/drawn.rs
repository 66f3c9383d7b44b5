//! The scene pass of a small frame kept on the device once drawn: frames that change only
//! the material (the editor's parameter changes and structural edits, a node swatch beside
//! the main one) draw the sky and the built-in surfaces once and copy their depth.
//!
//! A kept pass is drawn without the opaque material's depth under it (`SceneGpu::record`'s
//! `prepass`), as it must serve every material: it shades the samples an opaque material
//! hides, which the composite weighs by 0, once; and at a sample where the material's
//! depth equals the scene's exactly, the scene's surface is the nearer (the depth test is
//! `Greater`), where the prepass order keeps the material's.

use super::{COLOR, DEPTH, DeviceState, SceneGpu, target_descriptor};
use crate::memo::Same;
use crate::scene::{PackedScene, ScenePass};
use std::sync::Arc;

/// Largest frame, in pixels times samples, whose scene pass is kept: 256² at 4 samples
/// (5 MB of colour and depth). The editor's swatches (128² and 64² at 1 sample) and drafts
/// fit; a larger frame (`matgraph render`) is drawn once and keeps nothing.
pub(super) const MAX_SAMPLES: u64 = 256 * 256 * 4;

/// What a drawn scene pass depends on: the packed scene (the environment image with it),
/// the pass's frame uniform (camera, frame and tile, sky, ambient), the tile's size and
/// samples, and whether the backdrop's maps are textures (with the samples, which pipelines
/// drew it).
#[derive(Clone, PartialEq)]
pub(in crate::gpu) struct DrawnSceneKey {
    packed: Same<PackedScene>,
    frame: Vec<u8>,
    size: [u32; 3],
    map_textures: bool,
}

/// A scene pass drawn into textures of its own: the colour the resolve reads, and the
/// depth copied into each frame's depth target before the material is drawn over it.
pub(in crate::gpu) struct DrawnScene {
    /// The colour, as the resolve reads it.
    pub(super) color: wgpu::TextureView,
    /// The depth (`near / w`), copied from.
    pub(super) depth: wgpu::Texture,
    _color: wgpu::Texture,
}

impl DrawnScene {
    /// The scene pass of `gpu` for the frame uniform `frame` (bound as `group`) over a tile
    /// `[w, h]` of `spp` samples: kept on the device from an earlier frame, or drawn now
    /// (submitted before the frame's own work, which the queue runs after it).
    pub(super) fn of(
        s: &DeviceState,
        gpu: &SceneGpu,
        (frame, group): (&[u8], &wgpu::BindGroup),
        [w, h, spp]: [u32; 3],
    ) -> Arc<DrawnScene> {
        let key = DrawnSceneKey {
            packed: Same(Some(gpu.packed.clone())),
            frame: frame.to_vec(),
            size: [w, h, spp],
            map_textures: gpu.map_textures,
        };
        s.drawn_scenes.get_or(key, || {
            let texture = |label, format, copy| {
                s.device
                    .create_texture(&target_descriptor(label, (w, h, spp), format, copy))
            };
            let color = texture("mgr kept scene", COLOR, wgpu::TextureUsages::empty());
            let depth = texture("mgr kept depth", DEPTH, wgpu::TextureUsages::COPY_SRC);
            let view = color.create_view(&Default::default());
            let mut enc = s.device.create_command_encoder(&Default::default());
            gpu.record(
                &mut enc,
                group,
                ScenePass::Background,
                &view,
                &depth.create_view(&Default::default()),
                false,
            );
            s.queue.submit([enc.finish()]);
            Arc::new(DrawnScene {
                color: view,
                depth,
                _color: color,
            })
        })
    }

    /// Records the copy of the kept depth into `target` (the tile's depth target, of the
    /// same size and samples).
    pub(super) fn copy_depth(&self, enc: &mut wgpu::CommandEncoder, target: &wgpu::Texture) {
        enc.copy_texture_to_texture(
            self.depth.as_image_copy(),
            target.as_image_copy(),
            self.depth.size(),
        );
    }
}
