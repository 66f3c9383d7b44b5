//! Times matgraph's `noise_texture` (3D fBm, detail 8) and `voronoi_texture` (3D F1) against a WGSL transcription of Blender 4.x's GLSL on one wgpu adapter, with naga expression counts, a value cross-check and the CPU executor's cost; run: `cargo run --release --example texture_speed`.
//!
//! "Ours" is the graph file `examples/texture_speed/{noise,voronoi}.json` (position →
//! texture node → outputs; scale, detail, roughness and lacunarity are graph parameters, so
//! uniforms), compiled by `matgraph::wgsl::generate` with `Entry::Library`; the baseline is
//! `examples/texture_speed/blender_{noise,voronoi}.wgsl`. Both get the same compute entry point
//! appended (one invocation per point of a 1024 × 1024 grid, outputs interleaved in a storage
//! buffer at group 1), and are dispatched alternately on a device of our own on the adapter
//! `GpuContext` picks, timed with timestamp queries where the adapter has them (else the wall
//! clock around submit and wait). Everything but the timings is deterministic. With
//! `-- --dump DIR` the four modules (harness included) are also written to DIR.

use matgraph::gpu::GpuContext;
use matgraph::wgsl::{Binding, Entry, ShaderModule, TextureMode, WgslOptions, generate};
use matgraph::{Attribute, Graph, ParamValues, Plan, PlanOptions, Registry, SampleBatch};
use std::error::Error;
use std::path::Path;
use std::sync::mpsc;
use std::time::Instant;

/// Points per side of the grid.
const SIDE: u32 = 1024;
/// Grid spacing: positions (x, y) · STEP over [0, 2)², exact in f32.
const STEP: f32 = 1.0 / 512.0;
/// The grid's z.
const Z: f32 = 0.74;
/// Workgroup edge of the harness entry (8 × 8 invocations).
const GROUP: u32 = 8;
/// Dispatches run before timing, per module.
const WARMUP: usize = 2;
/// Timed dispatches per module.
const RUNS: usize = 15;
/// Timed CPU executions per case.
const CPU_RUNS: usize = 5;

/// One benchmark case: our graph and Blender's transcription of the same node settings.
struct Case {
    name: &'static str,
    graph: &'static str,
    blender: &'static str,
    /// The values of the baseline's `NodeUniforms` block, in member order.
    blender_uniforms: [f32; 8],
    /// Output names and widths, in the order they are stored per sample.
    outputs: &'static [(&'static str, usize)],
}

const CASES: &[Case] = &[
    Case {
        name: "noise_texture 3D fBm, detail 8",
        graph: "examples/texture_speed/noise.json",
        blender: include_str!("texture_speed/blender_noise.wgsl"),
        // scale, detail, roughness, lacunarity, offset, gain, distortion, w
        blender_uniforms: [5.0, 8.0, 0.5, 2.0, 0.0, 1.0, 0.0, 0.0],
        outputs: &[("fac", 1), ("color", 3)],
    },
    Case {
        name: "voronoi_texture 3D F1, euclidean",
        graph: "examples/texture_speed/voronoi.json",
        blender: include_str!("texture_speed/blender_voronoi.wgsl"),
        // scale, detail, roughness, lacunarity, smoothness, exponent, randomness, w
        blender_uniforms: [5.0, 0.0, 0.5, 2.0, 1.0, 0.5, 1.0, 0.0],
        outputs: &[("distance", 1), ("color", 3), ("position", 3)],
    },
];

/// Our own device on the adapter `GpuContext` would pick, with timestamp queries if offered.
struct Gpu {
    _instance: wgpu::Instance,
    adapter: wgpu::Adapter,
    device: wgpu::Device,
    queue: wgpu::Queue,
    timestamps: bool,
}

impl Gpu {
    fn open() -> Result<Gpu, Box<dyn Error>> {
        // GpuContext::new's search: WGPU_BACKEND, else the primary backends, then the rest.
        let attempts = match wgpu::Backends::from_env() {
            Some(b) => vec![b],
            None => vec![wgpu::Backends::PRIMARY, wgpu::Backends::SECONDARY],
        };
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
            let Ok(adapter) = pollster::block_on(instance.request_adapter(&options)) else {
                continue;
            };
            let features = adapter.features() & wgpu::Features::TIMESTAMP_QUERY;
            let (device, queue) =
                pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
                    label: Some("texture_speed"),
                    required_features: features,
                    required_limits: adapter.limits(),
                    ..Default::default()
                }))?;
            return Ok(Gpu {
                _instance: instance,
                adapter,
                device,
                queue,
                timestamps: !features.is_empty(),
            });
        }
        Err("no GPU adapter".into())
    }

    fn describe(&self) -> String {
        let i = self.adapter.get_info();
        format!(
            "{} ({:?}, {:?}, {} {})",
            i.name, i.device_type, i.backend, i.driver, i.driver_info
        )
    }

    fn buffer(&self, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
        self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: size.max(16).next_multiple_of(16),
            usage,
            mapped_at_creation: false,
        })
    }

    fn wait(&self) {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .expect("waiting for the GPU");
    }

    /// The bytes of a MAP_READ buffer.
    fn read(&self, buffer: &wgpu::Buffer) -> Vec<u8> {
        let slice = buffer.slice(..);
        let (tx, rx) = mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.wait();
        rx.recv().expect("map callback").expect("mapping a buffer");
        let bytes = slice.get_mapped_range().expect("mapped range").to_vec();
        buffer.unmap();
        bytes
    }
}

/// A module compiled into a pipeline with its buffers.
struct Prepared {
    pipeline: wgpu::ComputePipeline,
    groups: Vec<wgpu::BindGroup>,
    out: wgpu::Buffer,
    bytes: u64,
}

/// Timestamp queries and their readback.
struct Stamps {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    staging: wgpu::Buffer,
}

/// What one dispatch took: the wall clock around submit and wait, and the GPU's timestamps.
#[derive(Clone, Copy)]
struct Timing {
    wall_ms: f64,
    gpu_ms: Option<f64>,
}

fn prepare(gpu: &Gpu, label: &str, source: &str, uniforms: &[u8], width: usize) -> Prepared {
    let module = gpu
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
    let pipeline = gpu
        .device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(label),
            layout: None,
            module: &module,
            entry_point: Some("ts_main"),
            compilation_options: Default::default(),
            cache: None,
        });
    let bytes = u64::from(SIDE * SIDE) * width as u64 * 4;
    let out = gpu.buffer(
        "ts_out",
        bytes,
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
    );
    let mut groups = Vec::new();
    if !uniforms.is_empty() {
        let ubo = gpu.buffer(
            "uniforms",
            uniforms.len() as u64,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        gpu.queue.write_buffer(&ubo, 0, uniforms);
        groups.push(gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("group 0"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: ubo.as_entire_binding(),
            }],
        }));
    } else {
        groups.push(gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("group 0 (empty)"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[],
        }));
    }
    groups.push(gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("group 1"),
        layout: &pipeline.get_bind_group_layout(1),
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: out.as_entire_binding(),
        }],
    }));
    Prepared {
        pipeline,
        groups,
        out,
        bytes,
    }
}

/// One dispatch over the grid, submitted alone and waited for.
fn dispatch(gpu: &Gpu, p: &Prepared, stamps: Option<&Stamps>) -> Timing {
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("texture_speed"),
        });
    {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("texture_speed"),
            timestamp_writes: stamps.map(|s| wgpu::ComputePassTimestampWrites {
                query_set: &s.set,
                beginning_of_pass_write_index: Some(0),
                end_of_pass_write_index: Some(1),
            }),
        });
        pass.set_pipeline(&p.pipeline);
        for (k, g) in p.groups.iter().enumerate() {
            pass.set_bind_group(k as u32, g, &[]);
        }
        pass.dispatch_workgroups(SIDE / GROUP, SIDE / GROUP, 1);
    }
    if let Some(s) = stamps {
        encoder.resolve_query_set(&s.set, 0..2, &s.resolve, 0);
        encoder.copy_buffer_to_buffer(&s.resolve, 0, &s.staging, 0, 16);
    }
    let start = Instant::now();
    gpu.queue.submit([encoder.finish()]);
    gpu.wait();
    let wall_ms = start.elapsed().as_secs_f64() * 1e3;
    let gpu_ms = stamps.map(|s| {
        let b = gpu.read(&s.staging);
        let t0 = u64::from_le_bytes(b[0..8].try_into().unwrap());
        let t1 = u64::from_le_bytes(b[8..16].try_into().unwrap());
        t1.wrapping_sub(t0) as f64 * f64::from(gpu.queue.get_timestamp_period()) / 1e6
    });
    Timing { wall_ms, gpu_ms }
}

/// The output buffer of `p`, read back as floats.
fn read_out(gpu: &Gpu, p: &Prepared) -> Vec<f32> {
    let staging = gpu.buffer(
        "staging",
        p.bytes,
        wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
    );
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
    encoder.copy_buffer_to_buffer(&p.out, 0, &staging, 0, p.bytes);
    gpu.queue.submit([encoder.finish()]);
    gpu.read(&staging)[..p.bytes as usize]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

/// The compute entry appended to both modules: `body` binds `o` from the point `p`; the
/// outputs of `o` are stored interleaved, `width` floats a sample.
fn harness(body: &str, fields: &[(String, usize)]) -> String {
    let width: usize = fields.iter().map(|(_, w)| w).sum();
    let mut stores = String::new();
    let mut k = 0;
    for (field, w) in fields {
        for c in 0..*w {
            let access = if *w == 1 {
                format!("o.{field}")
            } else {
                format!("o.{field}.{}", ["x", "y", "z", "w"][c])
            };
            stores.push_str(&format!("    ts_out[base + {k}u] = {access};\n"));
            k += 1;
        }
    }
    format!(
        "\n// --- examples/texture_speed.rs harness (appended) ---\n\
         @group(1) @binding(0) var<storage, read_write> ts_out: array<f32>;\n\n\
         @compute @workgroup_size({GROUP}, {GROUP}, 1)\n\
         fn ts_main(@builtin(global_invocation_id) id: vec3<u32>) {{\n    \
         if (id.x >= {SIDE}u || id.y >= {SIDE}u) {{\n        return;\n    }}\n    \
         let p = vec3<f32>(f32(id.x) * {STEP:?}, f32(id.y) * {STEP:?}, {Z:?});\n    \
         let base = (id.y * {SIDE}u + id.x) * {width}u;\n\
         {body}{stores}}}\n"
    )
}

/// Our module's harness body and output fields.
fn our_entry(shader: &ShaderModule, case: &Case) -> Result<String, Box<dyn Error>> {
    let mut body = String::new();
    if shader.attributes.is_empty() {
        body.push_str("    let o = mg_material();\n");
    } else {
        body.push_str("    var geom: MgGeometry;\n");
        for a in &shader.attributes {
            if *a == Attribute::Position {
                body.push_str(&format!("    geom.{} = p;\n", a.name()));
            }
        }
        body.push_str("    let o = mg_material(geom);\n");
    }
    let mut fields = Vec::new();
    for (name, w) in case.outputs {
        let o = shader
            .outputs
            .iter()
            .find(|o| o.name == *name)
            .ok_or_else(|| format!("our module has no output '{name}'"))?;
        fields.push((o.field.clone(), *w));
    }
    Ok(harness(&body, &fields))
}

/// naga's view of a module: total expressions over functions and entry points, the
/// function count (entry points apart), and the same two over the functions the entry
/// points reach through calls (a module with no entry point reaches nothing).
struct NagaCount {
    expressions: usize,
    functions: usize,
    reached_expressions: usize,
    reached_functions: usize,
}

/// The functions `block` calls, pushed on `out`.
fn calls(block: &naga::Block, out: &mut Vec<naga::Handle<naga::Function>>) {
    for statement in block.iter() {
        match statement {
            naga::Statement::Call { function, .. } => out.push(*function),
            naga::Statement::Block(b) => calls(b, out),
            naga::Statement::If { accept, reject, .. } => {
                calls(accept, out);
                calls(reject, out);
            }
            naga::Statement::Switch { cases, .. } => {
                for case in cases {
                    calls(&case.body, out);
                }
            }
            naga::Statement::Loop {
                body, continuing, ..
            } => {
                calls(body, out);
                calls(continuing, out);
            }
            _ => {}
        }
    }
}

fn naga_count(label: &str, source: &str) -> Result<NagaCount, Box<dyn Error>> {
    let module = naga::front::wgsl::parse_str(source)
        .map_err(|e| format!("{label}: {}", e.emit_to_string(source)))?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| format!("{label}: {}", e.emit_to_string(source)))?;
    let expressions = module
        .functions
        .iter()
        .map(|(_, f)| f.expressions.len())
        .chain(
            module
                .entry_points
                .iter()
                .map(|e| e.function.expressions.len()),
        )
        .sum();
    let mut reached = std::collections::BTreeSet::new();
    let mut todo = Vec::new();
    for e in &module.entry_points {
        calls(&e.function.body, &mut todo);
    }
    while let Some(f) = todo.pop() {
        if reached.insert(f) {
            calls(&module.functions[f].body, &mut todo);
        }
    }
    let entry_expressions: usize = module
        .entry_points
        .iter()
        .map(|e| e.function.expressions.len())
        .sum();
    Ok(NagaCount {
        expressions,
        functions: module.functions.len(),
        reached_expressions: entry_expressions
            + reached
                .iter()
                .map(|f| module.functions[*f].expressions.len())
                .sum::<usize>(),
        reached_functions: reached.len(),
    })
}

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    if n % 2 == 1 {
        s[n / 2]
    } else {
        (s[n / 2 - 1] + s[n / 2]) / 2.0
    }
}

fn min(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}

/// How one output (`col`..`col + w` of `width`-float samples) of `a` differs from `b`.
struct Diff {
    /// Largest |a − b|, at sample `at` component `component`.
    max: f32,
    at: usize,
    component: usize,
    /// Values whose bits differ.
    differing: usize,
}

fn diff(a: &[f32], b: &[f32], width: usize, col: usize, w: usize) -> Diff {
    let mut d = Diff {
        max: 0.0,
        at: 0,
        component: 0,
        differing: 0,
    };
    for i in 0..a.len() / width {
        for c in 0..w {
            let (x, y) = (a[i * width + col + c], b[i * width + col + c]);
            d.differing += usize::from(x.to_bits() != y.to_bits());
            let e = if x.is_nan() && y.is_nan() {
                0.0
            } else if x.is_nan() || y.is_nan() {
                f32::INFINITY
            } else {
                (x - y).abs()
            };
            if e > d.max {
                (d.max, d.at, d.component) = (e, i, c);
            }
        }
    }
    d
}

/// The smallest and largest value of one output, NaNs apart.
fn span(v: &[f32], width: usize, col: usize, w: usize) -> (f32, f32) {
    (0..v.len() / width)
        .flat_map(|i| (0..w).map(move |c| v[i * width + col + c]))
        .filter(|x| !x.is_nan())
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), x| {
            (lo.min(x), hi.max(x))
        })
}

/// Per-case results for the table.
struct Row {
    name: &'static str,
    ours: NagaCount,
    ours_library: NagaCount,
    blender: NagaCount,
    gpu_ours: f64,
    gpu_blender: f64,
    /// Per output: largest |ours − Blender| on the GPU, and the values not bit-identical.
    worst: Vec<(&'static str, f32, usize)>,
    cpu_ns: f64,
}

fn main() -> Result<(), Box<dyn Error>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    // `--dump DIR`: also write both modules of each case (harness included) to DIR.
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dump = match args.as_slice() {
        [] => None,
        [flag, dir] if flag == "--dump" => Some(std::path::PathBuf::from(dir)),
        _ => return Err("usage: texture_speed [--dump DIR]".into()),
    };
    let n = (SIDE * SIDE) as usize;
    let points: Vec<[f32; 3]> = (0..n)
        .map(|i| {
            let (x, y) = (i as u32 % SIDE, i as u32 / SIDE);
            [x as f32 * STEP, y as f32 * STEP, Z]
        })
        .collect();
    let mut batch = SampleBatch::new(n);
    batch.set_values(Attribute::Position, &points)?;

    let context = GpuContext::shared()?;
    println!("adapter (GpuContext::shared): {}", context.describe());
    let gpu = Gpu::open()?;
    println!("adapter (this benchmark's device): {}", gpu.describe());
    println!(
        "timing: {}",
        if gpu.timestamps {
            "GPU timestamp queries around the compute pass"
        } else {
            "wall clock around submit + poll(wait) (no TIMESTAMP_QUERY)"
        }
    );
    let stamps = gpu.timestamps.then(|| Stamps {
        set: gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("texture_speed"),
            ty: wgpu::QueryType::Timestamp,
            count: 2,
        }),
        resolve: gpu.buffer(
            "resolve",
            16,
            wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
        ),
        staging: gpu.buffer(
            "stamps",
            16,
            wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        ),
    });
    println!(
        "grid: {SIDE} × {SIDE} points p = (x/512, y/512, {Z}); {WARMUP} warm-up and {RUNS} timed \
         dispatches per module, alternating; CPU: {CPU_RUNS} runs on {} rayon threads\n",
        rayon::current_num_threads()
    );

    let mut rows = Vec::new();
    for case in CASES {
        println!("## {}", case.name);
        let graph: Graph = matgraph::io::load_graph(&root.join(case.graph), Registry::builtin())?;
        let options = WgslOptions {
            entry: Entry::Library(TextureMode::Exact),
            ..Default::default()
        };
        let shader = generate(&graph, &options)?;
        let plan_start = Instant::now();
        let plan = Plan::compile(&graph, &PlanOptions::default())?;
        let compile_ms = plan_start.elapsed().as_secs_f64() * 1e3;
        let params: ParamValues = plan.default_parameters();
        let our_uniforms = if shader.bindings.iter().any(|(_, b)| *b == Binding::Params) {
            shader.uniforms.pack(&params, 0.0)
        } else {
            Vec::new()
        };
        let ours_source = format!("{}{}", shader.source, our_entry(&shader, case)?);
        let blender_fields: Vec<(String, usize)> = case
            .outputs
            .iter()
            .map(|(name, w)| (name.to_string(), *w))
            .collect();
        let blender_source = format!(
            "{}{}",
            case.blender,
            harness("    let o = ts_material(p);\n", &blender_fields)
        );
        if let Some(dir) = &dump {
            std::fs::create_dir_all(dir)?;
            let stem = case
                .graph
                .rsplit('/')
                .next()
                .unwrap_or("case")
                .replace(".json", "");
            std::fs::write(dir.join(format!("{stem}_ours.wgsl")), &ours_source)?;
            std::fs::write(dir.join(format!("{stem}_blender.wgsl")), &blender_source)?;
        }
        let ours = naga_count("ours", &ours_source)?;
        let ours_library = naga_count("ours (library)", &shader.source)?;
        let blender = naga_count("Blender", &blender_source)?;
        println!(
            "WGSL: ours {} bytes ({} lines; library alone {} bytes), Blender transcription {} \
             bytes ({} lines), harness included",
            ours_source.len(),
            ours_source.lines().count(),
            shader.source.len(),
            blender_source.len(),
            blender_source.lines().count()
        );
        println!(
            "naga: ours {} expressions in {} functions + entry (library alone: {} in {}); \
             Blender {} expressions in {} functions + entry",
            ours.expressions,
            ours.functions,
            ours_library.expressions,
            ours_library.functions,
            blender.expressions,
            blender.functions
        );
        println!(
            "naga, reached from the entry: ours {} expressions in {} functions + entry; \
             Blender {} in {} + entry",
            ours.reached_expressions,
            ours.reached_functions,
            blender.reached_expressions,
            blender.reached_functions
        );
        println!(
            "our uniforms: {} bytes ({})",
            our_uniforms.len(),
            shader
                .uniforms
                .fields
                .iter()
                .map(|f| f.field.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        );

        let width: usize = case.outputs.iter().map(|(_, w)| w).sum();
        let blender_uniforms: Vec<u8> = case
            .blender_uniforms
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let start = Instant::now();
        let p_ours = prepare(&gpu, "ours", &ours_source, &our_uniforms, width);
        let p_blender = prepare(&gpu, "blender", &blender_source, &blender_uniforms, width);
        for _ in 0..WARMUP {
            dispatch(&gpu, &p_ours, stamps.as_ref());
            dispatch(&gpu, &p_blender, stamps.as_ref());
        }
        println!(
            "pipelines and warm-up: {:.1} s",
            start.elapsed().as_secs_f64()
        );
        let (mut t_ours, mut t_blender) = (Vec::new(), Vec::new());
        for _ in 0..RUNS {
            t_ours.push(dispatch(&gpu, &p_ours, stamps.as_ref()));
            t_blender.push(dispatch(&gpu, &p_blender, stamps.as_ref()));
        }
        let pick = |t: &[Timing]| -> Vec<f64> {
            t.iter().map(|t| t.gpu_ms.unwrap_or(t.wall_ms)).collect()
        };
        let walls = |t: &[Timing]| -> Vec<f64> { t.iter().map(|t| t.wall_ms).collect() };
        let (ours_ms, blender_ms) = (pick(&t_ours), pick(&t_blender));
        for (who, ms, wall) in [
            ("ours   ", &ours_ms, walls(&t_ours)),
            ("Blender", &blender_ms, walls(&t_blender)),
        ] {
            println!(
                "GPU {who}: median {:.2} ms, min {:.2} ms ({:.1} ns/sample); wall clock median {:.2} ms",
                median(ms),
                min(ms),
                median(ms) * 1e6 / n as f64,
                median(&wall)
            );
        }
        println!(
            "ratio ours/Blender: {:.3} (median), {:.3} (min)",
            median(&ours_ms) / median(&blender_ms),
            min(&ours_ms) / min(&blender_ms)
        );

        // Values: ours on the GPU against the transcription, and the CPU executor against it.
        let v_ours = read_out(&gpu, &p_ours);
        let v_blender = read_out(&gpu, &p_blender);
        let mut cpu_ms = Vec::new();
        let mut cpu_out = None;
        for _ in 0..CPU_RUNS {
            let start = Instant::now();
            let out = plan.execute(&batch, &params)?;
            cpu_ms.push(start.elapsed().as_secs_f64() * 1e3);
            cpu_out = Some(out);
        }
        let cpu_out = cpu_out.expect("CPU_RUNS > 0");
        let mut v_cpu = vec![0.0f32; n * width];
        let mut col = 0;
        for (name, w) in case.outputs {
            let k = cpu_out
                .names()
                .iter()
                .position(|x| x == name)
                .ok_or_else(|| format!("the CPU plan has no output '{name}'"))?;
            let planar = cpu_out.planar(k);
            for i in 0..n {
                for c in 0..*w {
                    v_cpu[i * width + col + c] = planar[c * n + i];
                }
            }
            col += w;
        }
        let mut worst_row = Vec::new();
        let mut col = 0;
        for (name, w) in case.outputs {
            let g = diff(&v_ours, &v_blender, width, col, *w);
            let c = diff(&v_cpu, &v_blender, width, col, *w);
            let (lo, hi) = span(&v_blender, width, col, *w);
            let at = |d: &Diff, v: &[f32]| {
                format!(
                    "{:.3e} at ({}, {}).{} ({} vs {}), {} of {} values not bit-identical",
                    d.max,
                    d.at as u32 % SIDE,
                    d.at as u32 / SIDE,
                    d.component,
                    v[d.at * width + col + d.component],
                    v_blender[d.at * width + col + d.component],
                    d.differing,
                    n * w
                )
            };
            println!("{name} (Blender's values in [{lo}, {hi}]):");
            println!("  max |ours − Blender| GPU: {}", at(&g, &v_ours));
            println!("  max |ours − Blender| CPU: {}", at(&c, &v_cpu));
            worst_row.push((*name, g.max, g.differing));
            col += w;
        }
        let cpu_median = median(&cpu_ms);
        println!(
            "CPU executor: plan compile {compile_ms:.2} ms; execute median {cpu_median:.1} ms, min \
             {:.1} ms ({:.1} ns/sample on {} threads)\n",
            min(&cpu_ms),
            cpu_median * 1e6 / n as f64,
            rayon::current_num_threads()
        );
        rows.push(Row {
            name: case.name,
            ours,
            ours_library,
            blender,
            gpu_ours: median(&ours_ms),
            gpu_blender: median(&blender_ms),
            worst: worst_row,
            cpu_ns: cpu_median * 1e6 / n as f64,
        });
    }

    println!("adapter: {}", context.describe());
    println!(
        "\n| case | naga expressions ours / Blender (ours: library alone; reached from the entry) | GPU ms median ours / Blender / ratio | worst \\|ours − Blender\\| (GPU) | CPU ns/sample ({} threads) |",
        rayon::current_num_threads()
    );
    println!("|---|---|---|---|---:|");
    for r in &rows {
        println!(
            "| {} | {} / {} ({}; {}) | {:.1} / {:.1} / {:.2} | {} | {:.0} |",
            r.name,
            r.ours.expressions,
            r.blender.expressions,
            r.ours_library.expressions,
            r.ours.reached_expressions,
            r.gpu_ours,
            r.gpu_blender,
            r.gpu_ours / r.gpu_blender,
            r.worst
                .iter()
                .map(|(name, d, differing)| match differing {
                    0 => format!("{name} 0 (bit-identical)"),
                    _ => format!("{name} {d:.1e}"),
                })
                .collect::<Vec<_>>()
                .join(", "),
            r.cpu_ns
        );
    }
    Ok(())
}
