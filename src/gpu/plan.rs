//! A graph compiled to a WGSL compute pipeline, evaluating batches like the CPU plan.

use super::context::GpuContext;
use super::device::{DeviceState, Held, dispatch_shape, gpu_err};
use crate::exec::{Evaluator, OutputBatch, SampleBatch};
use crate::graph::Graph;
use crate::plan::{EvalError, ParamValues, Plan, PlanOptions};
use crate::wgsl::{self, Binding, Entry, ShaderError, ShaderModule, WgslOptions};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

fn shader_error(e: ShaderError) -> EvalError {
    match e {
        ShaderError::Plan(e) => e,
        e => EvalError::Gpu(format!("WGSL generation: {e}")),
    }
}

/// Buffers of one [`GpuPlan`], kept between evaluations and grown when a batch is larger.
struct Buffers {
    /// Samples the storage buffers hold.
    capacity: usize,
    params: Option<wgpu::Buffer>,
    dispatch: wgpu::Buffer,
    /// `mg_geometry`: every attribute, planar ([`wgsl::geometry_layout`]); none when the
    /// graph reads no attribute.
    geometry: Option<wgpu::Buffer>,
    output: wgpu::Buffer,
    staging: wgpu::Buffer,
}

/// A graph compiled to a WGSL compute pipeline: evaluates batches like [`Plan`], with the
/// parameters in a uniform buffer so changing them never recompiles.
pub struct GpuPlan {
    state: Arc<DeviceState>,
    shader: ShaderModule,
    layout: Held<wgpu::BindGroupLayout>,
    pipeline: Held<wgpu::ComputePipeline>,
    defaults: ParamValues,
    max_groups_x: u32,
    max_binding_bytes: u64,
    compilations: AtomicUsize,
    buffers: Held<Mutex<Option<Buffers>>>,
}

impl GpuPlan {
    /// Generates the graph's compute module and creates its shader module, bind group layout
    /// and pipeline, once.
    pub fn compile(
        ctx: &GpuContext,
        graph: &Graph,
        options: &PlanOptions,
    ) -> Result<GpuPlan, EvalError> {
        let defaults = Plan::compile(graph, options)?.default_parameters();
        let shader = wgsl::generate(
            graph,
            &WgslOptions {
                plan: options.clone(),
                entry: Entry::Compute,
                ..Default::default()
            },
        )
        .map_err(shader_error)?;
        let state = ctx.state.clone();
        let label = format!("matgraph '{}'", graph.name);
        let entries: Vec<(u32, wgpu::BufferBindingType)> = shader
            .bindings
            .iter()
            .map(|(b, kind)| {
                let ty = match kind {
                    Binding::Params | Binding::Dispatch => wgpu::BufferBindingType::Uniform,
                    Binding::Geometry => wgpu::BufferBindingType::Storage { read_only: true },
                    Binding::Output => wgpu::BufferBindingType::Storage { read_only: false },
                    Binding::TextureTexels | Binding::TextureLevels | Binding::TextureTable => {
                        wgpu::BufferBindingType::Storage { read_only: true }
                    }
                    // Only the render and library modules bind these; a compute module never does.
                    Binding::Frame
                    | Binding::Lights
                    | Binding::Sampler(..)
                    | Binding::Texture(_) => wgpu::BufferBindingType::Storage { read_only: true },
                };
                (*b, ty)
            })
            .collect();
        let (layout, pipeline) = state.scoped(&format!("compiling {label}"), || {
            let layout = state.layout(&label, &entries);
            let pipeline = state.pipeline(&label, &shader.source, &layout);
            Ok((layout, pipeline))
        })?;
        let limits = state.device.limits();
        Ok(GpuPlan {
            max_groups_x: limits.max_compute_workgroups_per_dimension,
            max_binding_bytes: limits
                .max_storage_buffer_binding_size
                .min(limits.max_buffer_size),
            shader,
            layout: Held::new(&state, layout),
            pipeline: Held::new(&state, pipeline),
            defaults,
            compilations: AtomicUsize::new(1),
            buffers: Held::new(&state, Mutex::new(None)),
            state,
        })
    }

    /// Limits the workgroups per dispatch row (normally the device's per-dimension limit), so
    /// the two-dimensional split of large batches can be exercised with small ones.
    pub fn with_max_workgroups_per_row(mut self, max: u32) -> GpuPlan {
        self.max_groups_x = max.clamp(
            1,
            self.state
                .device
                .limits()
                .max_compute_workgroups_per_dimension,
        );
        self
    }

    /// Limits the bytes of one storage binding (normally the device's), so the split of a
    /// batch into chunks whose `mg_geometry` and `mg_out` fit can be exercised with small
    /// batches.
    pub fn with_max_binding_bytes(mut self, max: u64) -> GpuPlan {
        self.max_binding_bytes = max.clamp(4, self.max_binding_bytes);
        *self.buffers.get_mut().unwrap_or_else(|p| p.into_inner()) = None;
        self
    }

    /// The parameter values from the graph file, ready to be overridden.
    pub fn default_parameters(&self) -> ParamValues {
        self.defaults.clone()
    }

    /// The generated module the pipeline runs.
    pub fn shader(&self) -> &ShaderModule {
        &self.shader
    }

    /// Pipelines this plan created: 1, however many evaluations and parameter changes.
    pub fn pipelines_created(&self) -> usize {
        self.compilations.load(Ordering::Relaxed)
    }

    /// Evaluates every output for every sample of `batch` on the GPU.
    pub fn execute(
        &self,
        batch: &SampleBatch,
        params: &ParamValues,
    ) -> Result<OutputBatch, EvalError> {
        if params.values().len() != self.defaults.values().len() {
            return Err(EvalError::UnknownParameter {
                name: "(parameter set of another plan)".into(),
                suggestion: None,
            });
        }
        let n = batch.len();
        let outputs = &self.shader.outputs;
        let names = outputs.iter().map(|o| o.name.clone()).collect();
        let types = outputs.iter().map(|o| o.ty).collect();
        if n == 0 {
            return Ok(OutputBatch::from_columns(
                0,
                names,
                types,
                outputs.iter().map(|_| Vec::new()).collect(),
            ));
        }
        let columns = self.shader.output_columns() as usize;
        let lanes = wgsl::geometry_lanes(&self.shader.attributes) as usize;
        // mg_geometry holds `lanes` floats per sample and mg_out `columns`: a batch larger
        // than the device's storage binding allows runs in chunks that fit.
        let widest = columns.max(lanes).max(1);
        let fits = (self.max_binding_bytes / (widest as u64 * 4)) as usize;
        let fits = fits.min(u32::MAX as usize / 4);
        if fits == 0 {
            return Err(EvalError::Gpu(format!(
                "one sample needs {}-byte buffers, above the device's storage binding limit of {} bytes",
                widest * 4,
                self.max_binding_bytes
            )));
        }
        let chunk = n.min(fits);
        let mut full: Vec<f32> = if chunk == n {
            Vec::new()
        } else {
            vec![0.0; columns * n]
        };
        let mut data = Vec::new();

        let mut guard = self.buffers.lock().unwrap_or_else(|p| p.into_inner());
        self.state.scoped("evaluating on the GPU", || {
            if guard.as_ref().is_none_or(|b| b.capacity < chunk) {
                *guard = None;
                // Room to grow, within the binding limit.
                *guard = Some(self.buffers(chunk.next_power_of_two().min(fits).max(chunk)));
            }
            let b = guard.as_ref().expect("allocated above");
            let queue = &self.state.queue;
            if let Some(p) = &b.params {
                queue.write_buffer(p, 0, &pad4(self.shader.uniforms.pack(params, batch.time())));
            }
            let textures = self.texture_buffers(batch)?;
            let bind_group = self.bind_group(b, textures.as_ref());
            for first in (0..n).step_by(chunk) {
                let len = chunk.min(n - first);
                let (gx, gy, row) = dispatch_shape(len as u32, self.max_groups_x);
                let mut dispatch = [0u8; 8];
                dispatch[..4].copy_from_slice(&(len as u32).to_le_bytes());
                dispatch[4..].copy_from_slice(&row.to_le_bytes());
                queue.write_buffer(&b.dispatch, 0, &dispatch);
                // Each attribute's planar lanes of the chunk at its offset in mg_geometry
                // (wgsl::geometry_layout: lane c of sample i at (offset + c) * len + i).
                if let Some(buf) = &b.geometry {
                    for (a, k) in wgsl::geometry_layout(&self.shader.attributes) {
                        let column = batch.column(a);
                        for (c, &default) in a.default_value().lanes().iter().enumerate() {
                            let at = (k as u64 + c as u64) * len as u64 * 4;
                            match column {
                                Some(col) => {
                                    let lane = &col[c * n + first..c * n + first + len];
                                    queue.write_buffer(buf, at, bytemuck::cast_slice(lane));
                                }
                                None => {
                                    let lane = vec![default; len];
                                    queue.write_buffer(buf, at, bytemuck::cast_slice(&lane));
                                }
                            }
                        }
                    }
                }
                data = self.state.dispatch_and_read(
                    &self.pipeline,
                    &bind_group,
                    (gx, gy),
                    &b.output,
                    &b.staging,
                    (columns * len * 4) as u64,
                )?;
                if chunk < n {
                    for c in 0..columns {
                        full[c * n + first..c * n + first + len]
                            .copy_from_slice(&data[c * len..(c + 1) * len]);
                    }
                }
            }
            Ok(())
        })?;
        drop(guard);
        if chunk < n {
            data = full;
        }

        let planar = outputs
            .iter()
            .map(|o| {
                let start = o.column as usize * n;
                data[start..start + o.ty.width() * n].to_vec()
            })
            .collect();
        Ok(OutputBatch::from_columns(n, names, types, planar))
    }

    /// Allocates the buffers and bind group for batches of up to `capacity` samples.
    fn buffers(&self, capacity: usize) -> Buffers {
        use wgpu::BufferUsages as U;
        let s = &self.state;
        let params = self
            .shader
            .bindings
            .iter()
            .any(|(_, k)| *k == Binding::Params)
            .then(|| {
                s.buffer(
                    "MgParams",
                    (self.shader.uniforms.size as u64)
                        .next_multiple_of(16)
                        .max(16),
                    U::UNIFORM | U::COPY_DST,
                )
            });
        let dispatch = s.buffer("MgDispatch", 16, U::UNIFORM | U::COPY_DST);
        let lanes = wgsl::geometry_lanes(&self.shader.attributes) as u64;
        let geometry = self
            .shader
            .bindings
            .iter()
            .any(|(_, k)| *k == Binding::Geometry)
            .then(|| {
                s.buffer(
                    "mg_geometry",
                    lanes * capacity as u64 * 4,
                    U::STORAGE | U::COPY_DST,
                )
            });
        let out_bytes = (self.shader.output_columns() as usize * capacity * 4) as u64;
        let output = s.buffer("mg_out", out_bytes, U::STORAGE | U::COPY_SRC);
        let staging = s.buffer("mg_out staging", out_bytes, U::MAP_READ | U::COPY_DST);
        Buffers {
            capacity,
            params,
            dispatch,
            geometry,
            output,
            staging,
        }
    }

    /// The textures the module samples, packed in slot order and uploaded.
    fn texture_buffers(&self, batch: &SampleBatch) -> Result<Option<[wgpu::Buffer; 3]>, EvalError> {
        use wgpu::BufferUsages as U;
        if self.shader.textures.is_empty() {
            return Ok(None);
        }
        let missing = |name: &str| EvalError::MissingTexture {
            name: name.to_owned(),
        };
        let set = batch
            .textures()
            .ok_or_else(|| missing(&self.shader.textures[0]))?;
        let pack = set
            .pack_selection(&self.shader.textures)
            .map_err(|e| match e {
                crate::texture::TextureError::Missing(name) => missing(&name),
                e => gpu_err("packing textures", e),
            })?;
        let s = &self.state;
        let upload = |label: &str, bytes: &[u8]| {
            let b = s.buffer(label, bytes.len() as u64, U::STORAGE | U::COPY_DST);
            s.queue.write_buffer(&b, 0, &pad4(bytes.to_vec()));
            b
        };
        Ok(Some([
            upload("mg_texels", pack.texel_bytes()),
            upload("mg_levels", pack.level_bytes()),
            upload("mg_textures", pack.texture_bytes()),
        ]))
    }

    /// The bind group of one evaluation: the plan's buffers and, when it samples textures,
    /// this batch's texture buffers.
    fn bind_group(&self, b: &Buffers, textures: Option<&[wgpu::Buffer; 3]>) -> wgpu::BindGroup {
        let entries: Vec<wgpu::BindGroupEntry> = self
            .shader
            .bindings
            .iter()
            .filter_map(|(binding, k)| {
                let buffer = match k {
                    Binding::Params => b.params.as_ref()?,
                    Binding::Dispatch => &b.dispatch,
                    Binding::Geometry => b.geometry.as_ref()?,
                    Binding::Output => &b.output,
                    Binding::TextureTexels => &textures?[0],
                    Binding::TextureLevels => &textures?[1],
                    Binding::TextureTable => &textures?[2],
                    Binding::Frame
                    | Binding::Lights
                    | Binding::Sampler(..)
                    | Binding::Texture(_) => {
                        return None;
                    }
                };
                Some(wgpu::BindGroupEntry {
                    binding: *binding,
                    resource: buffer.as_entire_binding(),
                })
            })
            .collect();
        self.state
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("matgraph"),
                layout: &self.layout,
                entries: &entries,
            })
    }
}

/// Pads bytes with zeros to a multiple of 4 (what `write_buffer` requires).
fn pad4(mut bytes: Vec<u8>) -> Vec<u8> {
    bytes.resize(bytes.len().next_multiple_of(4), 0);
    bytes
}

impl Evaluator for GpuPlan {
    fn evaluate(
        &self,
        batch: &SampleBatch,
        params: &ParamValues,
    ) -> Result<OutputBatch, EvalError> {
        self.execute(batch, params)
    }
}
