//! Evaluating graphs on a GPU with wgpu: a headless device ([`GpuContext`]), compiled
//! material pipelines that evaluate batches like the CPU plan ([`GpuPlan`]), the one-argument
//! CPU/GPU switch ([`compile`]) and a runner for single-node harness modules ([`GpuHarness`]).
//!
//! Any adapter wgpu finds is used, software ones included (Mesa's lavapipe runs the compute
//! shaders on the CPU), so the GPU path can be tested on machines without a GPU. Every
//! failure (no adapter, a shader the driver rejects, a lost device) is an
//! [`EvalError::Gpu`] that callers can fall back from; nothing here panics on them.

use crate::exec::{Evaluator, OutputBatch, SampleBatch};
use crate::graph::Graph;
use crate::plan::{EvalError, ParamValues, Plan, PlanOptions};
use crate::wgsl::{
    self, Binding, Entry, HarnessModule, ShaderError, ShaderModule, WORKGROUP_SIZE, WgslOptions,
};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

/// Which evaluator [`compile`] builds.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Backend {
    /// The batched CPU executor ([`Plan`]).
    #[default]
    Cpu,
    /// Generated WGSL run by wgpu ([`GpuPlan`] on [`GpuContext::shared`]).
    Gpu,
}

/// Compiles `graph` for `backend`; the evaluators agree to within float rounding.
pub fn compile(
    graph: &Graph,
    options: &PlanOptions,
    backend: Backend,
) -> Result<Box<dyn Evaluator>, EvalError> {
    Ok(match backend {
        Backend::Cpu => Box::new(Plan::compile(graph, options)?),
        Backend::Gpu => Box::new(GpuPlan::compile(GpuContext::shared()?, graph, options)?),
    })
}

/// The parameter values from the graph file, valid for the evaluators of every backend.
pub fn default_parameters(graph: &Graph, options: &PlanOptions) -> Result<ParamValues, EvalError> {
    Ok(Plan::compile(graph, options)?.default_parameters())
}

/// Device state shared by a context and everything compiled on it.
struct DeviceState {
    device: wgpu::Device,
    queue: wgpu::Queue,
    /// Errors no error scope caught (wgpu's default handler would panic on them).
    uncaptured: Arc<Mutex<Vec<String>>>,
    /// Why the device was lost, once it was.
    lost: Arc<Mutex<Option<String>>>,
    /// Compute pipelines created on this device.
    pipelines: AtomicUsize,
}

fn gpu_err(context: &str, e: impl std::fmt::Display) -> EvalError {
    EvalError::Gpu(format!("{context}: {e}"))
}

impl DeviceState {
    /// Runs `f` inside validation, out-of-memory and internal error scopes and turns anything
    /// they caught, an uncaptured error or a lost device into [`EvalError::Gpu`].
    fn scoped<T>(
        &self,
        what: &str,
        f: impl FnOnce() -> Result<T, EvalError>,
    ) -> Result<T, EvalError> {
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

    fn check_lost(&self) -> Result<(), EvalError> {
        match &*self.lost.lock().unwrap_or_else(|p| p.into_inner()) {
            Some(why) => Err(EvalError::Gpu(format!("device lost: {why}"))),
            None => Ok(()),
        }
    }

    /// A bind group layout with one buffer entry per binding, visible to compute.
    fn layout(
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
    fn pipeline(
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

    fn buffer(&self, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
        self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: aligned_size(size),
            usage,
            mapped_at_creation: false,
        })
    }

    /// Records one dispatch of `pipeline` over `count` invocations and the copy of `out` into
    /// `staging`, submits it and reads `bytes` bytes back.
    fn dispatch_and_read(
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
fn aligned_size(size: u64) -> u64 {
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

/// A headless wgpu device and queue, on any adapter (hardware, or a software fallback such
/// as lavapipe).
pub struct GpuContext {
    _instance: wgpu::Instance,
    adapter: wgpu::Adapter,
    state: Arc<DeviceState>,
}

impl std::fmt::Debug for GpuContext {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuContext")
            .field("adapter", &self.adapter_info())
            .finish_non_exhaustive()
    }
}

impl GpuContext {
    /// Opens the first usable adapter (Vulkan, Metal or DX12 first, then OpenGL) and creates a
    /// device with the adapter's limits; `EvalError::Gpu("no GPU adapter: ...")` if none.
    ///
    /// `WGPU_BACKEND` (e.g. `vulkan`, `gl`) restricts the backends tried.
    pub fn new() -> Result<GpuContext, EvalError> {
        let attempts: Vec<wgpu::Backends> = match wgpu::Backends::from_env() {
            Some(b) => vec![b],
            None => vec![wgpu::Backends::PRIMARY, wgpu::Backends::SECONDARY],
        };
        let mut why = Vec::new();
        for backends in attempts {
            let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
            desc.backends = backends;
            let instance = wgpu::Instance::new(desc);
            let options = wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: None,
                apply_limit_buckets: false,
            };
            match pollster::block_on(instance.request_adapter(&options)) {
                Ok(adapter) => return GpuContext::open(instance, adapter),
                Err(e) => why.push(format!("{backends:?}: {e}")),
            }
        }
        Err(EvalError::Gpu(format!(
            "no GPU adapter: {}",
            why.join("; ")
        )))
    }

    fn open(instance: wgpu::Instance, adapter: wgpu::Adapter) -> Result<GpuContext, EvalError> {
        let info = adapter.get_info();
        let desc = wgpu::DeviceDescriptor {
            label: Some("matgraph"),
            required_features: wgpu::Features::empty(),
            required_limits: adapter.limits(),
            ..Default::default()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&desc)).map_err(|e| {
            EvalError::Gpu(format!(
                "no GPU adapter: {} ({:?}) refused a device: {e}",
                info.name, info.backend
            ))
        })?;
        let uncaptured = Arc::new(Mutex::new(Vec::new()));
        let sink = uncaptured.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            sink.lock()
                .unwrap_or_else(|p| p.into_inner())
                .push(e.to_string());
        }));
        let lost = Arc::new(Mutex::new(None));
        let flag = lost.clone();
        device.set_device_lost_callback(move |reason, message| {
            *flag.lock().unwrap_or_else(|p| p.into_inner()) =
                Some(format!("{reason:?}: {message}"));
        });
        let state = Arc::new(DeviceState {
            device,
            queue,
            uncaptured,
            lost,
            pipelines: AtomicUsize::new(0),
        });
        Ok(GpuContext {
            _instance: instance,
            adapter,
            state,
        })
    }

    /// The process-wide context, created on first use (creating devices is slow); the error
    /// is remembered too, so a machine without an adapter is probed once.
    pub fn shared() -> Result<&'static GpuContext, EvalError> {
        static SHARED: OnceLock<Result<GpuContext, EvalError>> = OnceLock::new();
        SHARED
            .get_or_init(GpuContext::new)
            .as_ref()
            .map_err(Clone::clone)
    }

    /// The adapter's name, type, backend and driver.
    pub fn adapter_info(&self) -> wgpu::AdapterInfo {
        self.adapter.get_info()
    }

    /// One line describing the adapter, for reports: `name (type, backend, driver info)`.
    pub fn describe(&self) -> String {
        let i = self.adapter_info();
        format!(
            "{} ({:?}, {:?}, {} {})",
            i.name, i.device_type, i.backend, i.driver, i.driver_info
        )
    }

    /// The device's limits.
    pub fn limits(&self) -> wgpu::Limits {
        self.state.device.limits()
    }

    /// The wgpu device.
    pub fn device(&self) -> &wgpu::Device {
        &self.state.device
    }

    /// The wgpu queue.
    pub fn queue(&self) -> &wgpu::Queue {
        &self.state.queue
    }

    /// Compute pipelines created on this context so far, by every plan and harness.
    pub fn pipelines_created(&self) -> usize {
        self.state.pipelines.load(Ordering::Relaxed)
    }
}

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
    /// One per attribute binding, in binding order.
    attributes: Vec<wgpu::Buffer>,
    output: wgpu::Buffer,
    staging: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
}

/// A graph compiled to a WGSL compute pipeline: evaluates batches like [`Plan`], with the
/// parameters in a uniform buffer so changing them never recompiles.
pub struct GpuPlan {
    state: Arc<DeviceState>,
    shader: ShaderModule,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
    defaults: ParamValues,
    max_groups_x: u32,
    max_binding_bytes: u64,
    compilations: AtomicUsize,
    buffers: Mutex<Option<Buffers>>,
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
                    Binding::Attribute(_) => wgpu::BufferBindingType::Storage { read_only: true },
                    Binding::Output => wgpu::BufferBindingType::Storage { read_only: false },
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
            state,
            shader,
            layout,
            pipeline,
            defaults,
            compilations: AtomicUsize::new(1),
            buffers: Mutex::new(None),
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
        let widest = columns.max(3);
        if n > u32::MAX as usize / 4 || (widest * n * 4) as u64 > self.max_binding_bytes {
            return Err(EvalError::Gpu(format!(
                "a batch of {n} samples needs {}-byte buffers, above the device's storage binding limit of {} bytes; split it",
                widest * n * 4,
                self.max_binding_bytes
            )));
        }
        let (gx, gy, row) = dispatch_shape(n as u32, self.max_groups_x);
        let out_bytes = (columns * n * 4) as u64;

        let mut guard = self.buffers.lock().unwrap_or_else(|p| p.into_inner());
        let data = self.state.scoped("evaluating on the GPU", || {
            if guard.as_ref().is_none_or(|b| b.capacity < n) {
                *guard = None;
                // Room to grow, within the binding limit checked above for `n`.
                let fits = (self.max_binding_bytes / (widest as u64 * 4)) as usize;
                *guard = Some(self.buffers(n.next_power_of_two().min(fits).max(n)));
            }
            let b = guard.as_ref().expect("allocated above");
            let queue = &self.state.queue;
            if let Some(p) = &b.params {
                queue.write_buffer(p, 0, &pad4(self.shader.uniforms.pack(params, batch.time())));
            }
            let mut dispatch = [0u8; 8];
            dispatch[..4].copy_from_slice(&(n as u32).to_le_bytes());
            dispatch[4..].copy_from_slice(&row.to_le_bytes());
            queue.write_buffer(&b.dispatch, 0, &dispatch);
            let attributes = self.shader.bindings.iter().filter_map(|(_, k)| match k {
                Binding::Attribute(a) => Some(*a),
                _ => None,
            });
            for (a, buf) in attributes.zip(&b.attributes) {
                match batch.column(a) {
                    Some(col) => queue.write_buffer(buf, 0, bytemuck::cast_slice(col)),
                    None => {
                        let v = a.default_value();
                        let planar: Vec<f32> = v
                            .lanes()
                            .iter()
                            .flat_map(|&x| std::iter::repeat_n(x, n))
                            .collect();
                        queue.write_buffer(buf, 0, bytemuck::cast_slice(&planar));
                    }
                }
            }
            self.state.dispatch_and_read(
                &self.pipeline,
                &b.bind_group,
                (gx, gy),
                &b.output,
                &b.staging,
                out_bytes,
            )
        })?;
        drop(guard);

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
        let mut attributes = Vec::new();
        for (_, k) in &self.shader.bindings {
            if let Binding::Attribute(a) = k {
                let bytes = (a.ty().width() * capacity * 4) as u64;
                attributes.push(s.buffer(a.name(), bytes, U::STORAGE | U::COPY_DST));
            }
        }
        let out_bytes = (self.shader.output_columns() as usize * capacity * 4) as u64;
        let output = s.buffer("mg_out", out_bytes, U::STORAGE | U::COPY_SRC);
        let staging = s.buffer("mg_out staging", out_bytes, U::MAP_READ | U::COPY_DST);
        let mut next_attribute = attributes.iter();
        let entries: Vec<wgpu::BindGroupEntry> = self
            .shader
            .bindings
            .iter()
            .map(|(binding, k)| {
                let buffer = match k {
                    Binding::Params => params.as_ref().expect("created for the Params binding"),
                    Binding::Dispatch => &dispatch,
                    Binding::Attribute(_) => next_attribute
                        .next()
                        .expect("one buffer per attribute binding"),
                    Binding::Output => &output,
                };
                wgpu::BindGroupEntry {
                    binding: *binding,
                    resource: buffer.as_entire_binding(),
                }
            })
            .collect();
        let bind_group = s.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("matgraph"),
            layout: &self.layout,
            entries: &entries,
        });
        Buffers {
            capacity,
            params,
            dispatch,
            attributes,
            output,
            staging,
            bind_group,
        }
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

/// A compiled [`HarnessModule`]: runs one node type's WGSL function over packed samples.
pub struct GpuHarness {
    state: Arc<DeviceState>,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
    input_width: usize,
    output_width: usize,
    max_groups_x: u32,
}

impl GpuHarness {
    /// Creates the harness's pipeline on `ctx`.
    pub fn new(ctx: &GpuContext, harness: &HarnessModule) -> Result<GpuHarness, EvalError> {
        use wgpu::BufferBindingType as T;
        let state = ctx.state.clone();
        let entries = [
            (0, T::Storage { read_only: true }),
            (1, T::Storage { read_only: false }),
            (2, T::Uniform),
        ];
        let (layout, pipeline) = state.scoped("compiling a node harness", || {
            let layout = state.layout("matgraph harness", &entries);
            let pipeline = state.pipeline("matgraph harness", &harness.source, &layout);
            Ok((layout, pipeline))
        })?;
        let max_groups_x = state.device.limits().max_compute_workgroups_per_dimension;
        Ok(GpuHarness {
            state,
            layout,
            pipeline,
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
            let bind_group = s.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("matgraph harness"),
                layout: &self.layout,
                entries: &[
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
                ],
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
