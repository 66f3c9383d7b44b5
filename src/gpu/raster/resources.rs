//! The wgpu pieces every stage of the rasteriser builds with: cached device objects,
//! buffers, bind group layouts and groups, shader modules and pipelines, render targets,
//! submission and read-back.

use super::*;

/// The value cached on the device under `key`, made by `make` the first time (and again
/// after the bounded cache dropped it).
pub(super) fn cached<T: Send + Sync + 'static>(
    s: &DeviceState,
    key: &str,
    make: impl FnOnce() -> T,
) -> Arc<T> {
    let mut make = Some(make);
    let value = s.cache.get_or(key.to_owned(), || {
        let made = make.take().expect("made once")();
        Arc::new(made) as Arc<dyn std::any::Any + Send + Sync>
    });
    match value.downcast::<T>() {
        Ok(v) => v,
        // A key is only ever used with one type; were it not, this value is not kept.
        Err(_) => Arc::new(make.take().expect("not made: the key held another type")()),
    }
}

/// A storage buffer holding `bytes` (padded to at least `min` bytes).
pub(super) fn storage(s: &DeviceState, label: &str, bytes: &[u8], min: usize) -> wgpu::Buffer {
    let mut data = bytes.to_vec();
    data.resize(data.len().max(min).next_multiple_of(16), 0);
    s.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: &data,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        })
}

pub(super) fn uniform(s: &DeviceState, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    let mut data = bytes.to_vec();
    data.resize(data.len().max(16).next_multiple_of(16), 0);
    s.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: &data,
            usage: wgpu::BufferUsages::UNIFORM,
        })
}

/// Binding types of a layout.
#[derive(Clone, Copy)]
pub(super) enum Kind {
    Uniform,
    Storage,
    StorageRw,
    Texture { multisampled: bool },
}

pub(super) fn layout(
    s: &DeviceState,
    label: &str,
    entries: &[(u32, wgpu::ShaderStages, Kind)],
) -> wgpu::BindGroupLayout {
    layout_with(s, label, entries, &[])
}

/// [`layout`] with `more` entries after those of `entries`.
pub(super) fn layout_with(
    s: &DeviceState,
    label: &str,
    entries: &[(u32, wgpu::ShaderStages, Kind)],
    more: &[wgpu::BindGroupLayoutEntry],
) -> wgpu::BindGroupLayout {
    let entries: Vec<wgpu::BindGroupLayoutEntry> = entries
        .iter()
        .map(|&(binding, visibility, kind)| wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty: match kind {
                Kind::Uniform => wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                Kind::Storage | Kind::StorageRw => wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage {
                        read_only: matches!(kind, Kind::Storage),
                    },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                Kind::Texture { multisampled } => wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled,
                },
            },
            count: None,
        })
        .chain(more.iter().cloned())
        .collect();
    s.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries: &entries,
        })
}

pub(super) fn bind(
    s: &DeviceState,
    layout: &wgpu::BindGroupLayout,
    resources: &[wgpu::BindingResource],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = resources
        .iter()
        .enumerate()
        .map(|(i, r)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: r.clone(),
        })
        .collect();
    s.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout,
        entries: &entries,
    })
}

/// A bind group of `layout` with each resource at its own binding number.
pub(super) fn bind_entries(
    s: &DeviceState,
    layout: &wgpu::BindGroupLayout,
    resources: &[(u32, wgpu::BindingResource)],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = resources
        .iter()
        .map(|(binding, r)| wgpu::BindGroupEntry {
            binding: *binding,
            resource: r.clone(),
        })
        .collect();
    s.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout,
        entries: &entries,
    })
}

pub(super) fn module(s: &DeviceState, label: &str, source: &str) -> wgpu::ShaderModule {
    s.device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}

pub(super) fn pipeline_layout(
    s: &DeviceState,
    layouts: &[&wgpu::BindGroupLayout],
) -> wgpu::PipelineLayout {
    let layouts: Vec<Option<&wgpu::BindGroupLayout>> = layouts.iter().map(|l| Some(*l)).collect();
    s.device
        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &layouts,
            immediate_size: 0,
        })
}

pub(super) fn compute_pipeline(
    s: &DeviceState,
    label: &str,
    module: &wgpu::ShaderModule,
    entry: &str,
    layout: &wgpu::PipelineLayout,
) -> wgpu::ComputePipeline {
    s.device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(label),
            layout: Some(layout),
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        })
}

/// A render pipeline drawing triangle lists from storage buffers into one colour target,
/// with the `near / w` depth test (`test` false: always passes, depth not written).
#[allow(clippy::too_many_arguments)]
pub(super) fn render_pipeline(
    s: &DeviceState,
    label: &str,
    module: &wgpu::ShaderModule,
    vs: &str,
    fs: &str,
    layout: &wgpu::PipelineLayout,
    samples: u32,
    test: bool,
) -> wgpu::RenderPipeline {
    let depth = if test {
        (wgpu::CompareFunction::Greater, true)
    } else {
        (wgpu::CompareFunction::Always, false)
    };
    render_pipeline_depth(s, label, (module, vs, Some(fs)), layout, samples, depth)
}

/// [`render_pipeline`] with the depth test `(compare, write)`; without a fragment stage it
/// writes depth only (the material's depth pre-pass).
pub(super) fn render_pipeline_depth(
    s: &DeviceState,
    label: &str,
    (module, vs, fs): (&wgpu::ShaderModule, &str, Option<&str>),
    layout: &wgpu::PipelineLayout,
    samples: u32,
    (compare, write): (wgpu::CompareFunction, bool),
) -> wgpu::RenderPipeline {
    let targets = [Some(wgpu::ColorTargetState {
        format: COLOR,
        blend: None,
        write_mask: wgpu::ColorWrites::ALL,
    })];
    s.device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(label),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some(vs),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH,
                depth_write_enabled: Some(write),
                depth_compare: Some(compare),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState {
                count: samples,
                mask: !0,
                alpha_to_coverage_enabled: false,
            },
            fragment: fs.map(|fs| wgpu::FragmentState {
                module,
                entry_point: Some(fs),
                compilation_options: Default::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        })
}

/// A render target of a frame, lent by the device's pool ([`crate::gpu::pool`]) until
/// dropped; used as its view.
pub(super) struct Target<'a> {
    pub(super) view: wgpu::TextureView,
    pub(super) texture: Lent<'a, wgpu::Texture>,
}

impl std::ops::Deref for Target<'_> {
    type Target = wgpu::TextureView;
    fn deref(&self) -> &wgpu::TextureView {
        &self.view
    }
}

/// The descriptor of a `w × h` target of `spp` samples in `format`, drawn into and read in
/// a shader (and `more`).
pub(super) fn target_descriptor(
    label: &str,
    (w, h, spp): (u32, u32, u32),
    format: wgpu::TextureFormat,
    more: wgpu::TextureUsages,
) -> wgpu::TextureDescriptor<'_> {
    wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: spp,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING | more,
        view_formats: &[],
    }
}

/// A `w × h` target of `spp` samples in `format`, for drawing and then reading in a shader
/// (and copying into, as `more` usage says).
pub(super) fn target<'a>(
    s: &'a DeviceState,
    label: &str,
    size: (u32, u32, u32),
    format: wgpu::TextureFormat,
    more: wgpu::TextureUsages,
) -> Target<'a> {
    let texture = s
        .pool
        .texture(&s.device, &target_descriptor(label, size, format, more));
    Target {
        view: texture.create_view(&Default::default()),
        texture,
    }
}

/// An index buffer of `indices` (padded to four), also bound as storage for the fragment
/// stages that rebuild the CPU's barycentrics.
pub(super) fn index_buffer(s: &DeviceState, indices: &[u32]) -> wgpu::Buffer {
    let mut idx = indices.to_vec();
    idx.resize(idx.len().max(4), 0);
    s.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("mgr indices"),
            contents: bytemuck::cast_slice(&idx),
            usage: wgpu::BufferUsages::INDEX | wgpu::BufferUsages::STORAGE,
        })
}

/// Submits `enc` and waits for the device.
pub(super) fn submit_and_wait(s: &DeviceState, enc: wgpu::CommandEncoder) -> Result<(), EvalError> {
    s.queue.submit([enc.finish()]);
    s.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| gpu_err("waiting for the GPU", e))?;
    Ok(())
}

/// Maps `staging` and returns its first `bytes` bytes as floats; gives it back to the pool
/// unmapped (and drops it where the mapping failed).
pub(super) fn read_back(
    s: &DeviceState,
    staging: Lent<'_, wgpu::Buffer>,
    bytes: u64,
) -> Result<Vec<f32>, EvalError> {
    let data = map_and_read(s, &staging, bytes);
    if data.is_err() {
        staging.forget();
    }
    data
}

pub(super) fn map_and_read(
    s: &DeviceState,
    staging: &wgpu::Buffer,
    bytes: u64,
) -> Result<Vec<f32>, EvalError> {
    let slice = staging.slice(0..bytes);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    s.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| gpu_err("waiting for the GPU", e))?;
    rx.recv()
        .map_err(|e| gpu_err("reading back", e))?
        .map_err(|e| gpu_err("reading back", e))?;
    let data = slice
        .get_mapped_range()
        .map_err(|e| gpu_err("reading back", e))
        .map(|view| bytemuck::cast_slice::<u8, f32>(&view).to_vec());
    staging.unmap();
    data
}

/// A buffer of `bytes` for a frame's resolved pixels, lent by the pool.
pub(super) fn pixels_buffer(s: &DeviceState, bytes: u64) -> Lent<'_, wgpu::Buffer> {
    s.lend_buffer(
        "mgr pixels",
        bytes,
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
    )
}

/// A read-back buffer of `bytes`, lent by the pool.
pub(super) fn staging(s: &DeviceState, bytes: u64) -> Lent<'_, wgpu::Buffer> {
    s.lend_buffer(
        "mgr staging",
        bytes,
        wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
    )
}
