//! CPU/GPU parity of texture sampling: `matgraph::texture::SAMPLE_WGSL` run by wgpu (on
//! lavapipe in CI) against `Texture::sample` over random and hand-picked (uv, lod, wrap,
//! filter) samples of several textures, generated and custom mip chains included.
//!
//! Bound: |cpu − gpu| ≤ 1e-5 + 1e-4·|cpu| per component (the node parity bound). Without an
//! adapter the test prints `SKIPPED ...` to stderr, and fails instead when
//! `MATGRAPH_REQUIRE_GPU` is set. Run with `-- --nocapture` to see the measured errors.

use crate::common;

use common::gpu_context as context;
use common::rng::Rng;

use glam::{Vec2, Vec4};
use matgraph::gpu::{GpuContext, GpuPlan};
use matgraph::texture::{
    Filter, Image, SAMPLE_WGSL, Texture, TexturePack, TextureSet, Wrap, sample_bindings_wgsl,
};
use matgraph::wgsl::{WgslOptions, generate};
use matgraph::{Attribute, EvalError, Graph, Plan, PlanOptions, Registry, SampleBatch};
use wgpu::util::DeviceExt as _;

/// Absolute part of the bound.
const ABS: f64 = 1e-5;
/// Relative part of the bound.
const REL: f64 = 1e-4;
/// Random samples compared.
const RANDOM_SAMPLES: usize = 20_000;

/// The draws these tests make from the shared seeded generator.
impl Rng {
    /// Uniform in [lo, hi].
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        let u = (self.next() >> 40) as f64 / (1u64 << 24) as f64;
        (lo as f64 + (hi as f64 - lo as f64) * u) as f32
    }
    /// Uniform integer in [0, n).
    fn below(&mut self, n: u32) -> u32 {
        (self.next() % n as u64) as u32
    }
}

/// A random image with colour in [0, 1] and, where `hdr`, values up to 100.
fn random_image(rng: &mut Rng, w: u32, h: u32, hdr: bool) -> Image {
    let top = if hdr { 100.0 } else { 1.0 };
    Image::from_fn(w, h, |_, _| {
        [
            rng.range(0.0, top),
            rng.range(0.0, 1.0),
            rng.range(0.0, top),
            rng.range(0.0, 1.0),
        ]
    })
}

/// The textures compared: small, odd, HDR, single-level and seed 002's custom chain.
fn texture_set() -> TextureSet {
    let mut rng = Rng(0x7e47);
    let mut set = TextureSet::new();
    let mut add = |name: &str, t: Texture| {
        set.insert(name, t).unwrap();
    };
    add(
        "two_by_two",
        Texture::new(random_image(&mut rng, 2, 2, false), true).unwrap(),
    );
    add(
        "odd_mips",
        Texture::new(random_image(&mut rng, 13, 7, false), true).unwrap(),
    );
    add(
        "hdr_single_level",
        Texture::new(random_image(&mut rng, 16, 16, true), false).unwrap(),
    );
    let grey = |w: u32, v: f32| Image::filled(w, w, [v, v, v, 1.0]);
    add(
        "sunshine_chain",
        Texture::from_levels(vec![
            grey(16, 0.0),
            grey(8, 0.6),
            grey(4, 1.0),
            grey(2, 0.6),
            grey(1, 0.0),
        ])
        .unwrap(),
    );
    add("one_texel", Texture::new(grey(1, 0.25), true).unwrap());
    add(
        "wide",
        Texture::new(random_image(&mut rng, 64, 3, true), true).unwrap(),
    );
    set
}

/// One sample: texture index, uv, lod, wrap and filter indices.
#[derive(Clone, Copy, Debug)]
struct Query {
    tex: u32,
    uv: Vec2,
    lod: f32,
    wrap: u32,
    filter: u32,
}

/// Random queries over every texture (and one index past the end), uv in [−3, 3], lod in
/// [−1, 6], then hand-picked ones: texel centres and edges, integral and half lods, huge uv.
fn queries(set: &TextureSet) -> Vec<Query> {
    let mut rng = Rng(0x5a3_91e);
    let n = set.len() as u32;
    let mut out = Vec::new();
    for _ in 0..RANDOM_SAMPLES {
        out.push(Query {
            tex: rng.below(n + 1),
            uv: Vec2::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0)),
            lod: rng.range(-1.0, 6.0),
            wrap: rng.below(3),
            filter: rng.below(2),
        });
    }
    for tex in 0..n {
        let t = set.get(tex).unwrap();
        let (w, h) = (t.width() as f32, t.height() as f32);
        for wrap in 0..3 {
            for filter in 0..2 {
                for (i, j) in [(0, 0), (1, 0), (0, 1), (3, 2), (-1, -1), (-3, 5)] {
                    for lod in [0.0, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 10.0, -0.0] {
                        // Texel corners and centres of level 0.
                        for off in [0.0, 0.5] {
                            out.push(Query {
                                tex,
                                uv: Vec2::new((i as f32 + off) / w, (j as f32 + off) / h),
                                lod,
                                wrap,
                                filter,
                            });
                        }
                    }
                }
                for uv in [
                    Vec2::new(0.0, 0.0),
                    Vec2::new(1.0, 1.0),
                    Vec2::new(-0.25, 1.25),
                    Vec2::new(1.0e6 + 0.3, -1.0e6 - 0.7),
                    Vec2::new(3.0e9, -3.0e9),
                    Vec2::new(1.0e30, -1.0e30),
                ] {
                    out.push(Query {
                        tex,
                        uv,
                        lod: 1.25,
                        wrap,
                        filter,
                    });
                }
            }
        }
    }
    out
}

/// Runs `SAMPLE_WGSL` over `queries` on the GPU; returns one RGBA per query.
fn run_gpu(ctx: &GpuContext, pack: &TexturePack, queries: &[Query]) -> Vec<Vec4> {
    let source = format!(
        "{bindings}\n{SAMPLE_WGSL}\n\
         @group(0) @binding(3) var<storage, read> mg_queries: array<f32>;\n\
         @group(0) @binding(4) var<storage, read_write> mg_results: array<vec4<f32>>;\n\
         @compute @workgroup_size(64)\n\
         fn main(@builtin(global_invocation_id) id: vec3<u32>) {{\n\
         \x20   let i = id.x + id.y * 64u * 1024u;\n\
         \x20   if (i >= arrayLength(&mg_results)) {{ return; }}\n\
         \x20   let b = i * 6u;\n\
         \x20   mg_results[i] = mg_sample_texture(u32(mg_queries[b]), vec2<f32>(mg_queries[b + 1u], mg_queries[b + 2u]), mg_queries[b + 3u], u32(mg_queries[b + 4u]), u32(mg_queries[b + 5u]));\n\
         }}\n",
        bindings = sample_bindings_wgsl(0, 0)
    );
    let device = ctx.device();
    let queue = ctx.queue();
    let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("texture parity"),
        source: wgpu::ShaderSource::Wgsl(source.as_str().into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("texture parity"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let flat: Vec<f32> = queries
        .iter()
        .flat_map(|q| {
            [
                q.tex as f32,
                q.uv.x,
                q.uv.y,
                q.lod,
                q.wrap as f32,
                q.filter as f32,
            ]
        })
        .collect();
    let storage = |label: &str, bytes: &[u8]| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytes,
            usage: wgpu::BufferUsages::STORAGE,
        })
    };
    let texels = storage("mg_texels", pack.texel_bytes());
    let levels = storage("mg_levels", pack.level_bytes());
    let textures = storage("mg_textures", pack.texture_bytes());
    let input = storage("mg_queries", bytemuck::cast_slice(&flat));
    let bytes = (queries.len() * 16) as u64;
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("mg_results"),
        size: bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("mg_results staging"),
        size: bytes,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let layout = pipeline.get_bind_group_layout(0);
    let entries: Vec<wgpu::BindGroupEntry> = [&texels, &levels, &textures, &input, &output]
        .iter()
        .enumerate()
        .map(|(k, b)| wgpu::BindGroupEntry {
            binding: k as u32,
            resource: b.as_entire_binding(),
        })
        .collect();
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("texture parity"),
        layout: &layout,
        entries: &entries,
    });
    let groups = (queries.len() as u32).div_ceil(64);
    let (gx, gy) = (groups.min(1024), groups.div_ceil(1024));
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("texture parity"),
    });
    {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("texture parity"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(gx, gy, 1);
    }
    encoder.copy_buffer_to_buffer(&output, 0, &staging, 0, bytes);
    queue.submit([encoder.finish()]);
    if let Some(e) = pollster::block_on(validation.pop()) {
        panic!("the texture parity pipeline is invalid: {e}\n{source}");
    }
    let slice = staging.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("waiting for the GPU");
    rx.recv().unwrap().expect("mapping the results");
    let view = slice.get_mapped_range().expect("reading the results");
    let floats: Vec<f32> = view
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    drop(view);
    staging.unmap();
    floats.chunks_exact(4).map(Vec4::from_slice).collect()
}

#[test]
fn gpu_sampling_matches_the_cpu() {
    let Some(ctx) = context("gpu_sampling_matches_the_cpu") else {
        return;
    };
    eprintln!("adapter: {}", ctx.describe());
    let set = texture_set();
    let pack = set.pack().unwrap();
    let queries = queries(&set);
    assert!(queries.len() > RANDOM_SAMPLES);
    let gpu = run_gpu(ctx, &pack, &queries);
    assert_eq!(gpu.len(), queries.len());
    let (mut max_abs, mut max_rel, mut worst, mut nonzero) = (0.0f64, 0.0f64, 0.0f64, 0);
    let mut exact = 0usize;
    let mut failures = Vec::new();
    for (q, g) in queries.iter().zip(&gpu) {
        let cpu = set.sample(
            q.tex,
            q.uv,
            q.lod,
            Wrap::from_index(q.wrap),
            Filter::from_index(q.filter),
        );
        // The packed CPU sampler is the GPU's twin: it must agree with the texture exactly.
        assert_eq!(
            cpu,
            pack.sample(q.tex, q.uv, q.lod, q.wrap, q.filter),
            "{q:?}"
        );
        if cpu == *g {
            exact += 1;
        }
        if cpu != Vec4::ZERO {
            nonzero += 1;
        }
        for c in 0..4 {
            let (a, b) = (cpu[c] as f64, g[c] as f64);
            // Finite uv and lod never give NaN or infinities; one would fail here.
            let finite = a.is_finite() && b.is_finite();
            let err = (a - b).abs();
            max_abs = max_abs.max(err);
            if a.abs() >= 1e-6 {
                max_rel = max_rel.max(err / a.abs());
            }
            let ratio = err / (ABS + REL * a.abs());
            worst = worst.max(ratio);
            if (!finite || ratio > 1.0) && failures.len() < 5 {
                failures.push(format!("{q:?}: cpu {cpu} gpu {g}"));
            }
        }
    }
    eprintln!(
        "texture sampling parity: {} samples ({exact} bit-identical), max abs {max_abs:.3e}, \
         max rel {max_rel:.3e}, {:.1}% of the bound {ABS:e} + {REL:e}·|cpu|",
        queries.len(),
        worst * 100.0
    );
    assert!(
        nonzero > queries.len() / 2,
        "most samples should be non-zero"
    );
    assert!(
        failures.is_empty(),
        "GPU sampling differs:\n{}",
        failures.join("\n")
    );
}

/// Every procedural texture node in one graph: their WGSL helpers are shared (emitted once).
const PROCEDURAL_GRAPH: &str = r#"{
  "version": 1,
  "name": "procedural_textures",
  "nodes": [
    { "id": "geo", "type": "geometry" },
    { "id": "value", "type": "noise_value", "inputs": { "p": { "link": "geo.position" }, "scale": 3.0, "octaves": 5 } },
    { "id": "perlin", "type": "noise_gradient", "inputs": { "p": { "link": "geo.position" }, "scale": 1.7, "octaves": 3 } },
    { "id": "board", "type": "checker", "inputs": { "uv": { "link": "geo.uv" }, "scale": 10.0 } },
    { "id": "toon", "type": "ramp", "inputs": { "x": { "link": "perlin.value" }, "steps": 4, "softness": 0.2 } }
  ],
  "outputs": [
    { "name": "value", "from": "value.color" },
    { "name": "perlin", "from": "perlin.value" },
    { "name": "board", "from": "board.color" },
    { "name": "mask", "from": "board.mask" },
    { "name": "toon", "from": "toon.color" }
  ]
}"#;

#[test]
fn procedural_nodes_share_helpers_and_match_on_the_gpu() {
    let graph =
        Graph::from_json(PROCEDURAL_GRAPH, Registry::builtin()).unwrap_or_else(|e| panic!("{e:?}"));
    // One module, naga-validated, each helper defined once.
    let module = generate(&graph, &WgslOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    for helper in ["fn mg_pcg3d(", "fn mg_noise_cell(", "fn mg_noise_fade("] {
        assert_eq!(module.source.matches(helper).count(), 1, "{helper}");
    }
    let Some(ctx) = context("procedural_nodes_share_helpers_and_match_on_the_gpu") else {
        return;
    };
    let n = 64 * 64;
    let mut pos = Vec::with_capacity(n);
    let mut uv = Vec::with_capacity(n);
    for k in 0..n {
        let (a, b) = ((k % 64) as f32, (k / 64) as f32);
        pos.push([a * 0.37 - 11.0, b * 0.29 - 9.0, (a - b) * 0.11]);
        uv.push([a / 32.0 - 1.0, b / 32.0 - 0.5, 0.0]);
    }
    let mut batch = SampleBatch::new(n);
    batch.set_values(Attribute::Position, &pos).unwrap();
    batch.set_values(Attribute::Uv, &uv).unwrap();
    let options = PlanOptions::default();
    let plan = Plan::compile(&graph, &options).unwrap();
    let params = plan.default_parameters();
    let cpu = plan.execute(&batch, &params).unwrap();
    let gpu = GpuPlan::compile(ctx, &graph, &options)
        .unwrap_or_else(|e| panic!("{e}"))
        .execute(&batch, &params)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(cpu.names(), gpu.names());
    let mut max_abs = 0.0f64;
    for k in 0..cpu.names().len() {
        let (a, b) = (cpu.planar(k), gpu.planar(k));
        assert_eq!(a.len(), b.len());
        // The outputs vary over the batch (a constant output would hide a broken node).
        let first = a[0];
        assert!(
            a[..n].iter().any(|&x| x != first),
            "{} is constant",
            cpu.names()[k]
        );
        for (x, y) in a.iter().zip(b) {
            let err = (*x as f64 - *y as f64).abs();
            max_abs = max_abs.max(err);
            assert!(
                x.is_finite() && err <= ABS + REL * (*x as f64).abs(),
                "{}: cpu {x} gpu {y}",
                cpu.names()[k]
            );
        }
    }
    eprintln!("procedural graph parity: {n} samples, max abs {max_abs:.3e}");
}

/// The `image_texture` node through the whole pipeline: a graph whose two texture nodes
/// sample different images of a set (bound out of order), with uv from the geometry and a
/// varying lod, on the CPU plan and the GPU plan; plus the error for an unbound texture.
#[test]
fn image_texture_node_matches_on_cpu_and_gpu() {
    let set = std::sync::Arc::new(texture_set());
    let text = r#"{
      "version": 1, "name": "textured",
      "nodes": [
        { "id": "geo", "type": "geometry" },
        { "id": "lod", "type": "split", "inputs": { "v": { "link": "geo.position" } } },
        { "id": "a", "type": "image_texture", "texture": "odd_mips",
          "inputs": { "uv": { "link": "geo.uv" }, "lod": { "link": "lod.x" }, "wrap": "mirror" } },
        { "id": "b", "type": "image_texture", "texture": "sunshine_chain",
          "inputs": { "uv": { "link": "geo.uv" }, "lod": { "link": "lod.y" }, "filter": "nearest" } },
        { "id": "sum", "type": "add", "inputs": { "a": { "link": "a.color" }, "b": { "link": "b.color" } } }
      ],
      "outputs": [ { "name": "c", "from": "sum.result" }, { "name": "alpha", "from": "a.alpha" } ]
    }"#;
    let graph = Graph::from_json(text, Registry::builtin()).unwrap();
    let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
    assert_eq!(
        plan.textures(),
        &["odd_mips".to_owned(), "sunshine_chain".to_owned()]
    );

    let n = 4096;
    let mut rng = Rng(0x51de);
    let uv: Vec<[f32; 3]> = (0..n)
        .map(|_| [rng.range(-2.0, 3.0), rng.range(-2.0, 3.0), 0.0])
        .collect();
    let pos: Vec<[f32; 3]> = (0..n)
        .map(|_| [rng.range(0.0, 3.0), rng.range(0.0, 4.0), 0.0])
        .collect();
    let mut batch = SampleBatch::new(n);
    batch
        .set_planar(
            Attribute::Uv,
            (0..2).flat_map(|c| uv.iter().map(move |p| p[c])).collect(),
        )
        .unwrap();
    batch.set_values(Attribute::Position, &pos).unwrap();

    // Unbound textures are an error, not zeros.
    let err = plan
        .execute(&batch, &plan.default_parameters())
        .unwrap_err();
    assert_eq!(
        err,
        EvalError::MissingTexture {
            name: "odd_mips".into()
        }
    );

    batch.set_textures(set.clone());
    let cpu = plan.execute(&batch, &plan.default_parameters()).unwrap();
    // The CPU node agrees with Texture::sample directly.
    let odd = set.get(set.index_of("odd_mips").unwrap()).unwrap();
    for i in (0..n).step_by(97) {
        let want = odd.sample(
            Vec2::new(uv[i][0], uv[i][1]),
            pos[i][0],
            Wrap::Mirror,
            Filter::Bilinear,
        );
        assert_eq!(cpu.value(1, i).as_f32(), want.w, "alpha at {i}");
    }
    let Some(ctx) = context("image_texture_node_matches_on_cpu_and_gpu") else {
        return;
    };
    let gpu = GpuPlan::compile(ctx, &graph, &PlanOptions::default()).unwrap();
    let got = gpu.execute(&batch, &plan.default_parameters()).unwrap();
    let mut worst = 0.0f32;
    for k in 0..2 {
        for (c, g) in cpu.planar(k).iter().zip(got.planar(k)) {
            let err = (c - g).abs();
            assert!(err <= 1e-5 + 1e-4 * c.abs(), "output {k}: cpu {c} gpu {g}");
            worst = worst.max(err);
        }
    }
    eprintln!("image_texture graph: max |cpu - gpu| = {worst:e}");
    let unbound = GpuPlan::compile(ctx, &graph, &PlanOptions::default())
        .unwrap()
        .execute(&SampleBatch::new(4), &plan.default_parameters());
    assert_eq!(
        unbound.unwrap_err(),
        EvalError::MissingTexture {
            name: "odd_mips".into()
        }
    );
}
