//! The wgpu device state shared by a context and what is compiled on it: error scopes that
//! turn driver errors into [`EvalError::Gpu`], pipelines, buffers and one dispatch.

use crate::plan::EvalError;
use crate::wgsl::{Entry, WORKGROUP_SIZE};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// Device state shared by a context and everything compiled on it.
pub(super) struct DeviceState {
    pub(super) device: wgpu::Device,
    pub(super) queue: wgpu::Queue,
    /// Errors no error scope caught (wgpu's default handler would panic on them).
    pub(super) uncaptured: Arc<Mutex<Vec<String>>>,
    /// Why the device was lost, once it was.
    pub(super) lost: Arc<Mutex<Option<String>>>,
    /// Compute pipelines created on this device.
    pub(super) pipelines: AtomicUsize,
    /// What the GPU rasteriser made on this device (pipelines, layouts, generated materials,
    /// packed textures), by what it was made from, so that frames after the first compile
    /// nothing; bounded, so that an editing session that compiles a material per structural
    /// edit does not grow it without bound (see `raster::cached`).
    pub(super) cache: crate::memo::Memo<String, Arc<dyn std::any::Any + Send + Sync>, 64>,
    /// The materials' textures as uploaded for the last few frames, so that frames with the
    /// same textures (an animation, the editor's parameter changes) upload none; few, as
    /// each can hold a frame-sized scene texture and its mips.
    pub(super) uploads: crate::memo::Memo<UploadKey, Arc<crate::material::GpuTextures>, 4>,
    /// [`DeviceState::uploads`] of materials whose textures are all small (at most
    /// [`SMALL_UPLOAD_TEXELS`] each, as the editor's swatches bind): more of them, since an
    /// editing session goes back and forth between a few structures at a few sizes (the
    /// full swatch, its draft), and with four the edits of `bubble_iridescent` uploaded its
    /// textures again each time (8–19 ms of a 24² draft on lavapipe).
    pub(super) small_uploads: crate::memo::Memo<UploadKey, Arc<crate::material::GpuTextures>, 16>,
    /// The frames' targets and read-back buffers, lent to one frame at a time.
    pub(super) pool: super::pool::Pool,
    /// The buffers of the last few material meshes, by mesh: frames of the same scene
    /// (parameter changes, the editor's swatches) upload no mesh.
    pub(super) meshes: crate::memo::Memo<
        crate::memo::Same<crate::scene::Mesh>,
        Arc<super::raster::MeshBuffers>,
        4,
    >,
    /// The buffers of the last few packed scenes, by scene.
    pub(super) scenes: crate::memo::Memo<
        crate::memo::Same<crate::scene::PackedScene>,
        Arc<super::raster::SceneBuffers>,
        4,
    >,
    /// The scene passes of the last few small frames, drawn ([`super::raster`]'s
    /// `DrawnScene`): frames that change only the material (the editor's parameter changes
    /// and structural edits) draw no scene.
    pub(super) drawn_scenes:
        crate::memo::Memo<super::raster::DrawnSceneKey, Arc<super::raster::DrawnScene>, 4>,
    /// On wgpu's GL backend, held by the thread inside [`DeviceState::scoped`], so that the
    /// device's work runs one thread at a time; `None` on the other backends, which are
    /// thread-safe. wgpu's GL backend makes the one GL context current per call and panics
    /// ("Could not lock adapter context") when a thread waits 6 s for it: one long call (a big
    /// shader's compile on llvmpipe) made every other thread's next call panic. Re-entrant,
    /// since a scoped section may open another.
    pub(super) serial: Option<parking_lot::ReentrantMutex<()>>,
}

/// Texels of the largest texture an upload kept in [`DeviceState::small_uploads`] may have
/// (512², 4 MiB at RGBA32F: the environment map is 512 × 256).
pub(super) const SMALL_UPLOAD_TEXELS: u64 = 512 * 512;

/// What a material's uploaded textures were made from: the material (compared by identity,
/// and kept so that its address is not reused), which of its modules (the render module or
/// the library's), and each texture it binds, by identity.
#[derive(Clone)]
pub(super) struct UploadKey {
    pub(super) material: Arc<dyn std::any::Any + Send + Sync>,
    pub(super) library: bool,
    pub(super) textures: Vec<crate::memo::Same<crate::texture::Texture>>,
}

impl PartialEq for UploadKey {
    fn eq(&self, other: &UploadKey) -> bool {
        Arc::ptr_eq(&self.material, &other.material)
            && self.library == other.library
            && self.textures == other.textures
    }
}

/// Device objects (pipelines, layouts, buffers) that are dropped under
/// [`DeviceState::serial`], as wgpu's GL backend destroys each with a call that waits for the
/// GL context like any other; dereferences to the objects.
pub(super) struct Held<T> {
    state: Arc<DeviceState>,
    value: std::mem::ManuallyDrop<T>,
}

impl<T> std::ops::Deref for Held<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.value
    }
}

impl<T> std::ops::DerefMut for Held<T> {
    fn deref_mut(&mut self) -> &mut T {
        &mut self.value
    }
}

impl<T> Drop for Held<T> {
    fn drop(&mut self) {
        let _serial = self.state.serial.as_ref().map(|m| m.lock());
        // SAFETY: `value` is dropped here once and never used again.
        unsafe { std::mem::ManuallyDrop::drop(&mut self.value) }
    }
}

impl<T> Held<T> {
    /// Keeps `value`, created on `state`'s device, until it is dropped under `state`'s lock.
    pub(super) fn new(state: &Arc<DeviceState>, value: T) -> Held<T> {
        Held {
            state: state.clone(),
            value: std::mem::ManuallyDrop::new(value),
        }
    }
}

pub(super) fn gpu_err(context: &str, e: impl std::fmt::Display) -> EvalError {
    EvalError::Gpu(format!("{context}: {e}"))
}

impl DeviceState {
    /// Runs `f` inside validation, out-of-memory and internal error scopes and turns anything
    /// they caught, an uncaptured error or a lost device into [`EvalError::Gpu`].
    pub(super) fn scoped<T>(
        &self,
        what: &str,
        f: impl FnOnce() -> Result<T, EvalError>,
    ) -> Result<T, EvalError> {
        let _serial = self.serial.as_ref().map(|m| m.lock());
        self.check_lost()?;
        let internal = self.device.push_error_scope(wgpu::ErrorFilter::Internal);
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let result = f();
        let errors: Vec<String> = [validation.pop(), oom.pop(), internal.pop()]
            .into_iter()
            .filter_map(pollster::block_on)
            .map(|e| e.to_string())
            .collect();
        let uncaptured: Vec<String> =
            std::mem::take(&mut *self.uncaptured.lock().unwrap_or_else(|p| p.into_inner()));
        self.check_lost()?;
        if let Some(first) = errors.into_iter().chain(uncaptured).next() {
            return Err(EvalError::Gpu(format!("{what}: {first}")));
        }
        result
    }

    pub(super) fn check_lost(&self) -> Result<(), EvalError> {
        match &*self.lost.lock().unwrap_or_else(|p| p.into_inner()) {
            Some(why) => Err(EvalError::Gpu(format!("device lost: {why}"))),
            None => Ok(()),
        }
    }

    /// A bind group layout with one buffer entry per binding, visible to compute.
    pub(super) fn layout(
        &self,
        label: &str,
        entries: &[(u32, wgpu::BufferBindingType)],
    ) -> wgpu::BindGroupLayout {
        let entries: Vec<wgpu::BindGroupLayoutEntry> = entries
            .iter()
            .map(|&(binding, ty)| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            })
            .collect();
        self.device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &entries,
            })
    }

    /// Creates the shader module and the `mg_compute` pipeline of `source`.
    pub(super) fn pipeline(
        &self,
        label: &str,
        source: &str,
        layout: &wgpu::BindGroupLayout,
    ) -> wgpu::ComputePipeline {
        let module = self
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
        let pipeline_layout = self
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &[Some(layout)],
                immediate_size: 0,
            });
        let pipeline = self
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(Entry::Compute.function()),
                compilation_options: Default::default(),
                cache: None,
            });
        self.pipelines.fetch_add(1, Ordering::Relaxed);
        pipeline
    }

    /// A buffer of at least `size` bytes lent by the frame pool ([`DeviceState::pool`]).
    pub(super) fn lend_buffer(
        &self,
        label: &str,
        size: u64,
        usage: wgpu::BufferUsages,
    ) -> super::pool::Lent<'_, wgpu::Buffer> {
        self.pool
            .buffer(&self.device, label, aligned_size(size), usage)
    }

    pub(super) fn buffer(&self, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
        self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: aligned_size(size),
            usage,
            mapped_at_creation: false,
        })
    }

    /// Records one dispatch of `pipeline` over `count` invocations and the copy of `out` into
    /// `staging`, submits it and reads `bytes` bytes back.
    pub(super) fn dispatch_and_read(
        &self,
        pipeline: &wgpu::ComputePipeline,
        bind_group: &wgpu::BindGroup,
        groups: (u32, u32),
        out: &wgpu::Buffer,
        staging: &wgpu::Buffer,
        bytes: u64,
    ) -> Result<Vec<f32>, EvalError> {
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("matgraph"),
            });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("matgraph"),
                timestamp_writes: None,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, bind_group, &[]);
            pass.dispatch_workgroups(groups.0, groups.1, 1);
        }
        encoder.copy_buffer_to_buffer(out, 0, staging, 0, bytes);
        self.queue.submit([encoder.finish()]);
        let slice = staging.slice(0..bytes);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| gpu_err("waiting for the GPU", e))?;
        rx.recv()
            .map_err(|e| gpu_err("reading results back", e))?
            .map_err(|e| gpu_err("reading results back", e))?;
        let data = slice
            .get_mapped_range()
            .map_err(|e| gpu_err("reading results back", e))
            .map(|view| {
                view.chunks_exact(4)
                    .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                    .collect()
            });
        staging.unmap();
        data
    }
}

/// A buffer size wgpu accepts: at least 4 bytes, a multiple of 4 (zero-size bindings and
/// copies of unaligned sizes are errors).
pub(super) fn aligned_size(size: u64) -> u64 {
    size.max(4)
        .next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT.max(4))
}

/// The workgroup grid for `n` invocations: `(x, y, row)` with `row = x × 64` threads per
/// row and at most `max_x` workgroups per row (the device's per-dimension limit).
pub fn dispatch_shape(n: u32, max_x: u32) -> (u32, u32, u32) {
    let groups = n.div_ceil(WORKGROUP_SIZE);
    if groups == 0 {
        return (0, 0, 0);
    }
    let x = groups.min(max_x.max(1));
    (x, groups.div_ceil(x), x * WORKGROUP_SIZE)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dispatch_shape_covers_every_sample_once() {
        assert_eq!(dispatch_shape(0, 65535), (0, 0, 0));
        assert_eq!(dispatch_shape(1, 65535), (1, 1, 64));
        assert_eq!(dispatch_shape(65, 65535), (2, 1, 128));
        assert_eq!(dispatch_shape(100_000, 65535), (1563, 1, 1563 * 64));
        let (x, y, row) = dispatch_shape(100_000, 7);
        assert_eq!((x, row), (7, 448));
        assert!(x * y * 64 >= 100_000 && (y - 1) * row < 100_000);
    }

    #[test]
    fn buffer_sizes_are_never_zero() {
        assert_eq!(aligned_size(0), 4);
        assert_eq!(aligned_size(5), 8);
        assert_eq!(aligned_size(16), 16);
    }
}
