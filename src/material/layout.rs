//! The wgpu side of the contract: bind group layout entries, the vertex buffer layout, the
//! blend state and the per-stage binding counts checked against WebGPU's default limits.

use crate::wgsl::render::FRAME_SIZE;
use crate::wgsl::{Binding, ShaderModule};

/// The smallest buffer size a buffer binding takes (uniform blocks), from
/// [`binding_type`]; `None` for other bindings.
pub(super) fn min_binding_size(module: &ShaderModule, b: &Binding) -> Option<u64> {
    match binding_type(module, b) {
        wgpu::BindingType::Buffer {
            min_binding_size, ..
        } => min_binding_size.map(std::num::NonZeroU64::get),
        _ => None,
    }
}

/// What a binding of group 0 is, in wgpu terms.
pub(super) fn binding_type(module: &ShaderModule, b: &Binding) -> wgpu::BindingType {
    let buffer = |ty, min: Option<u64>| wgpu::BindingType::Buffer {
        ty,
        has_dynamic_offset: false,
        min_binding_size: min.and_then(std::num::NonZeroU64::new),
    };
    let storage = wgpu::BufferBindingType::Storage { read_only: true };
    match b {
        Binding::Params => buffer(
            wgpu::BufferBindingType::Uniform,
            Some((module.uniforms.size as u64).next_multiple_of(16).max(16)),
        ),
        Binding::Frame => buffer(wgpu::BufferBindingType::Uniform, Some(FRAME_SIZE as u64)),
        Binding::Dispatch => buffer(wgpu::BufferBindingType::Uniform, Some(8)),
        Binding::Output => buffer(wgpu::BufferBindingType::Storage { read_only: false }, None),
        Binding::Lights
        | Binding::Geometry
        | Binding::TextureTexels
        | Binding::TextureLevels
        | Binding::TextureTable => buffer(storage, None),
        Binding::Sampler(..) => wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
        Binding::Texture(_) => wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
    }
}

/// The bind group layout entries of group 0, visible to the vertex and fragment stages.
pub(super) fn entries(module: &ShaderModule) -> Vec<wgpu::BindGroupLayoutEntry> {
    let mut bindings: Vec<&(u32, Binding)> = module.bindings.iter().collect();
    bindings.sort_by_key(|(b, _)| *b);
    bindings
        .into_iter()
        .map(|(binding, b)| wgpu::BindGroupLayoutEntry {
            binding: *binding,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: binding_type(module, b),
            count: None,
        })
        .collect()
}

/// The interleaved vertex buffer the vertex entry reads: 32 bytes per vertex, `position`
/// (float32x3) at 0 → location 0, `normal` (float32x3) at 12 → location 1, `uv` (float32x2)
/// at 24 → location 2.
pub const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 3] = [
    wgpu::VertexAttribute {
        format: wgpu::VertexFormat::Float32x3,
        offset: 0,
        shader_location: 0,
    },
    wgpu::VertexAttribute {
        format: wgpu::VertexFormat::Float32x3,
        offset: 12,
        shader_location: 1,
    },
    wgpu::VertexAttribute {
        format: wgpu::VertexFormat::Float32x2,
        offset: 24,
        shader_location: 2,
    },
];

/// Bytes per vertex of the vertex buffer.
pub const VERTEX_STRIDE: u64 = 32;

/// The vertex buffer layout of `mg_vertex`.
pub fn vertex_buffer_layout() -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: VERTEX_STRIDE,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &VERTEX_ATTRIBUTES,
    }
}

/// The tangent attribute of `mg_vertex` (location 3), read by modules whose graph reads the
/// tangent frame.
pub const TANGENT_ATTRIBUTES: [wgpu::VertexAttribute; 1] = [wgpu::VertexAttribute {
    format: wgpu::VertexFormat::Float32x4,
    offset: 0,
    shader_location: 3,
}];

/// Bytes per vertex of the tangent buffer: the MikkTSpace tangent (xyz) and bitangent sign (w).
pub const TANGENT_STRIDE: u64 = 16;

/// The second vertex buffer's layout (slot 1), for modules that read the tangent frame
/// ([`crate::material::Material::uses_tangents`]).
pub fn tangent_buffer_layout() -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: TANGENT_STRIDE,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &TANGENT_ATTRIBUTES,
    }
}

/// Per-stage binding counts of a module (every binding is visible to both stages).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StageCounts {
    /// Uniform buffers.
    pub uniform_buffers: u32,
    /// Storage buffers.
    pub storage_buffers: u32,
    /// Sampled textures.
    pub sampled_textures: u32,
    /// Samplers.
    pub samplers: u32,
}

impl StageCounts {
    /// The counts of `module`'s bindings.
    pub fn of(module: &ShaderModule) -> StageCounts {
        let mut c = StageCounts::default();
        for (_, b) in &module.bindings {
            match b {
                Binding::Params | Binding::Frame | Binding::Dispatch => c.uniform_buffers += 1,
                Binding::Sampler(..) => c.samplers += 1,
                Binding::Texture(_) => c.sampled_textures += 1,
                _ => c.storage_buffers += 1,
            }
        }
        c
    }

    /// The first count above WebGPU's default limit, as (what, count, limit).
    pub fn over_default_limits(&self) -> Option<(&'static str, u32, u32)> {
        let d = wgpu::Limits::default();
        [
            (
                "uniform buffers",
                self.uniform_buffers,
                d.max_uniform_buffers_per_shader_stage,
            ),
            (
                "storage buffers",
                self.storage_buffers,
                d.max_storage_buffers_per_shader_stage,
            ),
            (
                "sampled textures",
                self.sampled_textures,
                d.max_sampled_textures_per_shader_stage,
            ),
            ("samplers", self.samplers, d.max_samplers_per_shader_stage),
        ]
        .into_iter()
        .find(|(_, n, max)| n > max)
    }
}
