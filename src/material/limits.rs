//! The device limits a module needs (the contract's `limits`), and which of them a downlevel
//! device (WebGL2, GLES 3.0: `wgpu::Limits::downlevel_webgl2_defaults`) lacks, for
//! `matgraph wgsl --downlevel`'s refusal.

use super::layout::StageCounts;
use crate::wgsl::{Entry, ShaderModule};
use serde::{Deserialize, Serialize};

/// The limits a module needs, each named as its `wgpu::Limits` field (WebGPU's
/// `GPUSupportedLimits` in snake case): a device whose limits are at least these can bind it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModuleLimits {
    /// The largest uniform buffer bound, in bytes (the parameter block rounded up to 16, or
    /// `MgFrame`).
    pub max_uniform_buffer_binding_size: u64,
    /// Uniform buffers per stage.
    pub max_uniform_buffers_per_shader_stage: u32,
    /// Storage buffers per stage (the render module's lights, the compute entry's
    /// buffers, the exact texture mode's buffers).
    pub max_storage_buffers_per_shader_stage: u32,
    /// Sampled textures per stage.
    pub max_sampled_textures_per_shader_stage: u32,
    /// Samplers per stage.
    pub max_samplers_per_shader_stage: u32,
    /// Varyings passed from the vertex to the fragment stage (render module), else absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_inter_stage_shader_variables: Option<u32>,
    /// Invocations per compute workgroup (compute entry), else absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_compute_invocations_per_workgroup: Option<u32>,
}

impl ModuleLimits {
    /// The limits `module` needs.
    pub fn of(module: &ShaderModule) -> ModuleLimits {
        let counts = StageCounts::of(module);
        let uniform = module
            .bindings
            .iter()
            .filter_map(|(_, b)| super::layout::min_binding_size(module, b))
            .max()
            .unwrap_or(0);
        ModuleLimits {
            max_uniform_buffer_binding_size: uniform,
            max_uniform_buffers_per_shader_stage: counts.uniform_buffers,
            max_storage_buffers_per_shader_stage: counts.storage_buffers,
            max_sampled_textures_per_shader_stage: counts.sampled_textures,
            max_samplers_per_shader_stage: counts.samplers,
            max_inter_stage_shader_variables: matches!(module.entry, Entry::Render(_))
                .then(|| inter_stage_variables(&module.module)),
            max_compute_invocations_per_workgroup: (module.entry == Entry::Compute)
                .then_some(crate::wgsl::WORKGROUP_SIZE),
        }
    }

    /// Each need above `limits`, in words naming the limit, the need and what uses it.
    pub fn unmet(&self, limits: &wgpu::Limits) -> Vec<String> {
        let optional = |n: Option<u32>| n.map(u64::from);
        [
            (
                "max_uniform_buffer_binding_size",
                Some(self.max_uniform_buffer_binding_size),
                limits.max_uniform_buffer_binding_size,
                "bytes of its largest uniform block",
            ),
            (
                "max_uniform_buffers_per_shader_stage",
                Some(self.max_uniform_buffers_per_shader_stage.into()),
                limits.max_uniform_buffers_per_shader_stage.into(),
                "uniform blocks",
            ),
            (
                "max_storage_buffers_per_shader_stage",
                Some(self.max_storage_buffers_per_shader_stage.into()),
                limits.max_storage_buffers_per_shader_stage.into(),
                "storage buffers: the lights, the compute entry's data, the exact texture mode's texels",
            ),
            (
                "max_sampled_textures_per_shader_stage",
                Some(self.max_sampled_textures_per_shader_stage.into()),
                limits.max_sampled_textures_per_shader_stage.into(),
                "textures",
            ),
            (
                "max_samplers_per_shader_stage",
                Some(self.max_samplers_per_shader_stage.into()),
                limits.max_samplers_per_shader_stage.into(),
                "samplers",
            ),
            (
                "max_inter_stage_shader_variables",
                optional(self.max_inter_stage_shader_variables),
                limits.max_inter_stage_shader_variables.into(),
                "varyings",
            ),
            (
                "max_compute_invocations_per_workgroup",
                optional(self.max_compute_invocations_per_workgroup),
                limits.max_compute_invocations_per_workgroup.into(),
                "a compute entry",
            ),
        ]
        .into_iter()
        .filter_map(|(name, need, have, what)| {
            let need = need?;
            (need > have).then(|| format!("{name} {have}, the module needs {need} ({what})"))
        })
        .collect()
    }
}

/// The `@location` inputs of the module's fragment entry point (its varyings).
fn inter_stage_variables(module: &naga::Module) -> u32 {
    let Some(ep) = module
        .entry_points
        .iter()
        .find(|e| e.stage == naga::ShaderStage::Fragment)
    else {
        return 0;
    };
    let mut n = 0;
    for arg in &ep.function.arguments {
        match (&arg.binding, &module.types[arg.ty].inner) {
            (Some(naga::Binding::Location { .. }), _) => n += 1,
            (None, naga::TypeInner::Struct { members, .. }) => {
                n += members
                    .iter()
                    .filter(|m| matches!(m.binding, Some(naga::Binding::Location { .. })))
                    .count() as u32;
            }
            _ => {}
        }
    }
    n
}
