//! Running one node type's WGSL harness module on packed samples (node-level parity).

use super::context::GpuContext;
use super::device::{DeviceState, Held, dispatch_shape};
use crate::plan::EvalError;
use crate::wgsl::HarnessModule;
use std::sync::Arc;

/// A compiled [`HarnessModule`]: runs one node type's WGSL function over packed samples.
pub struct GpuHarness {
    state: Arc<DeviceState>,
    layout: Held<wgpu::BindGroupLayout>,
    pipeline: Held<wgpu::ComputePipeline>,
    input_width: usize,
    output_width: usize,
    /// `mg_params` (binding 3), the node's constant tables, written once.
    params: Held<Option<wgpu::Buffer>>,
    max_groups_x: u32,
}

impl GpuHarness {
    /// Creates the harness's pipeline on `ctx`.
    pub fn new(ctx: &GpuContext, harness: &HarnessModule) -> Result<GpuHarness, EvalError> {
        use wgpu::BufferBindingType as T;
        let state = ctx.state.clone();
        let mut entries = vec![
            (0, T::Storage { read_only: true }),
            (1, T::Storage { read_only: false }),
            (2, T::Uniform),
        ];
        if !harness.params.is_empty() {
            entries.push((3, T::Uniform));
        }
        let (layout, pipeline, params) = state.scoped("compiling a node harness", || {
            let layout = state.layout("matgraph harness", &entries);
            let pipeline = state.pipeline("matgraph harness", &harness.source, &layout);
            let params = (!harness.params.is_empty()).then(|| {
                use wgpu::BufferUsages as U;
                let size = harness.params.len() as u64;
                let b = state.buffer("MgParams", size, U::UNIFORM | U::COPY_DST);
                state.queue.write_buffer(&b, 0, &harness.params);
                b
            });
            Ok((layout, pipeline, params))
        })?;
        let max_groups_x = state.device.limits().max_compute_workgroups_per_dimension;
        Ok(GpuHarness {
            layout: Held::new(&state, layout),
            pipeline: Held::new(&state, pipeline),
            params: Held::new(&state, params),
            state,
            input_width: harness.input_width,
            output_width: harness.output_width,
            max_groups_x,
        })
    }

    /// Floats per sample of the packed inputs.
    pub fn input_width(&self) -> usize {
        self.input_width
    }

    /// Floats per sample of the packed outputs.
    pub fn output_width(&self) -> usize {
        self.output_width
    }

    /// Runs `count` samples: `inputs` holds `input_width` floats per sample (ints and bools
    /// as floats); returns `output_width` floats per sample.
    pub fn run(&self, inputs: &[f32], count: usize) -> Result<Vec<f32>, EvalError> {
        if inputs.len() != count * self.input_width {
            return Err(EvalError::Gpu(format!(
                "harness: expected {} input floats ({count} samples × {}), found {}",
                count * self.input_width,
                self.input_width,
                inputs.len()
            )));
        }
        if count == 0 || self.output_width == 0 {
            return Ok(Vec::new());
        }
        use wgpu::BufferUsages as U;
        let s = &self.state;
        let (gx, gy, row) = dispatch_shape(count as u32, self.max_groups_x);
        let out_bytes = (count * self.output_width * 4) as u64;
        s.scoped("running a node harness", || {
            let input = s.buffer("mg_in", (inputs.len() * 4) as u64, U::STORAGE | U::COPY_DST);
            let output = s.buffer("mg_out", out_bytes, U::STORAGE | U::COPY_SRC);
            let staging = s.buffer("mg_out staging", out_bytes, U::MAP_READ | U::COPY_DST);
            let dispatch = s.buffer("MgDispatch", 16, U::UNIFORM | U::COPY_DST);
            if !inputs.is_empty() {
                s.queue
                    .write_buffer(&input, 0, bytemuck::cast_slice(inputs));
            }
            let mut d = [0u8; 8];
            d[..4].copy_from_slice(&(count as u32).to_le_bytes());
            d[4..].copy_from_slice(&row.to_le_bytes());
            s.queue.write_buffer(&dispatch, 0, &d);
            let mut entries = vec![
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: input.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: output.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: dispatch.as_entire_binding(),
                },
            ];
            if let Some(p) = &*self.params {
                entries.push(wgpu::BindGroupEntry {
                    binding: 3,
                    resource: p.as_entire_binding(),
                });
            }
            let bind_group = s.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("matgraph harness"),
                layout: &self.layout,
                entries: &entries,
            });
            s.dispatch_and_read(
                &self.pipeline,
                &bind_group,
                (gx, gy),
                &output,
                &staging,
                out_bytes,
            )
        })
    }
}
