//! The device limits a module needs (the contract's `limits`), and which of them a downlevel
//! device (WebGL2, GLES 3.0: `wgpu::Limits::downlevel_webgl2_defaults`) lacks, for
//! `matgraph wgsl --downlevel`'s refusal.

use super::layout::StageCounts;
use crate::wgsl::{Binding, Entry, ShaderModule};
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
            .filter_map(|(_, b)| match b {
                Binding::Params => Some((module.uniforms.size as u64).next_multiple_of(16).max(16)),
                Binding::Frame => Some(crate::wgsl::render::FRAME_SIZE as u64),
                Binding::Dispatch => Some(8),
                _ => None,
            })
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
        let mut out = Vec::new();
        let mut check = |name: &str, need: u64, have: u64, what: &str| {
            if need > have {
                out.push(format!("{name} {have}, the module needs {need} ({what})"));
            }
        };
        check(
            "max_uniform_buffer_binding_size",
            self.max_uniform_buffer_binding_size,
            limits.max_uniform_buffer_binding_size,
            "bytes of its largest uniform block",
        );
        check(
            "max_uniform_buffers_per_shader_stage",
            self.max_uniform_buffers_per_shader_stage.into(),
            limits.max_uniform_buffers_per_shader_stage.into(),
            "uniform blocks",
        );
        check(
            "max_storage_buffers_per_shader_stage",
            self.max_storage_buffers_per_shader_stage.into(),
            limits.max_storage_buffers_per_shader_stage.into(),
            "storage buffers: the lights, the compute entry's data, the exact texture mode's texels",
        );
        check(
            "max_sampled_textures_per_shader_stage",
            self.max_sampled_textures_per_shader_stage.into(),
            limits.max_sampled_textures_per_shader_stage.into(),
            "textures",
        );
        check(
            "max_samplers_per_shader_stage",
            self.max_samplers_per_shader_stage.into(),
            limits.max_samplers_per_shader_stage.into(),
            "samplers",
        );
        if let Some(n) = self.max_inter_stage_shader_variables {
            check(
                "max_inter_stage_shader_variables",
                n.into(),
                limits.max_inter_stage_shader_variables.into(),
                "varyings",
            );
        }
        if let Some(n) = self.max_compute_invocations_per_workgroup {
            check(
                "max_compute_invocations_per_workgroup",
                n.into(),
                limits.max_compute_invocations_per_workgroup.into(),
                "a compute entry",
            );
        }
        out
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
