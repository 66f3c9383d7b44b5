//! CPU/GPU parity: every node type's WGSL against its CPU kernel, every shipped graph's
//! generated module against the CPU plan, parameter changes without recompiling, the
//! backend switch, and batch sizes around the workgroup size.
//!
//! The tests run on any wgpu adapter, Mesa's lavapipe (a CPU Vulkan driver) included. They
//! never skip silently: without an adapter each prints `SKIPPED: no GPU adapter: ...` to
//! stderr, and fails instead when `MATGRAPH_REQUIRE_GPU` is set (CI sets it).
//!
//! Bound: |cpu − gpu| ≤ 1e-5 + 1e-4·|cpu| per component; a NaN on one side must be a NaN on
//! the other and infinities must match exactly. Looser bounds are listed in [`LOOSE`], each
//! with its reason. Run with `-- --nocapture` to see the measured errors.

use crate::common;

use common::gpu_context as context;
use common::parity::*;

use matgraph::gpu::{self, Backend, GpuContext, GpuHarness, GpuPlan};
use matgraph::node::{Evaluation, NodeType};
use matgraph::wgsl::{ShaderError, node_choice_harness, node_constant_harness, node_harness};
use matgraph::{
    Attribute, EvalError, Graph, OutputBatch, Plan, PlanOptions, Registry, SampleBatch, SocketType,
    Value,
};
use std::collections::BTreeMap;
use std::fmt::Write as _;

// ------------------------------------------------------------------------------------------
// a) Node parity
// ------------------------------------------------------------------------------------------

/// Packs planar input columns into the harness's per-sample layout.
fn pack(t: &NodeType, generic: SocketType, s: &NodeSamples, width: usize) -> Vec<f32> {
    let mut packed = vec![0.0f32; width * s.n];
    let mut at = 0;
    for (k, d) in t.inputs().iter().enumerate() {
        let w = d.ty.resolve(generic).width();
        for i in 0..s.n {
            for c in 0..w {
                packed[i * width + at + c] = s.columns[k][c * s.n + i];
            }
        }
        at += w;
    }
    packed
}

/// Runs `samples` through the CPU kernel and `harness` and compares every output component
/// within `bound`; the first three misses are added to `failures` (as a failed run is).
fn run_and_compare(
    t: &NodeType,
    generic: SocketType,
    harness: &GpuHarness,
    samples: &NodeSamples,
    bound: (f64, f64),
    label: &str,
    failures: &mut Vec<String>,
) -> Option<Errors> {
    let cpu = run_cpu(t, generic, samples);
    let gpu = match harness.run(&pack(t, generic, samples, harness.input_width()), samples.n) {
        Ok(g) => g,
        Err(e) => {
            failures.push(format!("{label}: GPU run failed: {e}"));
            return None;
        }
    };
    // The harness's per-sample rows, as planar columns per output.
    let ow = harness.output_width();
    let mut at = 0;
    let gpu: Vec<Vec<f32>> = t
        .outputs()
        .iter()
        .map(|d| {
            let w = d.ty.resolve(generic).width();
            let col = (0..w)
                .flat_map(|c| (0..samples.n).map(move |i| (i, c)))
                .map(|(i, c)| gpu[i * ow + at + c])
                .collect();
            at += w;
            col
        })
        .collect();
    let mut errors = Errors::default();
    compare_node_outputs(
        t,
        generic,
        samples,
        (&cpu, &gpu),
        bound,
        label,
        ("cpu", "gpu"),
        &mut errors,
        failures,
    );
    Some(errors)
}

#[test]
fn every_node_type_matches_its_cpu_kernel() {
    let Some(ctx) = context("every_node_type_matches_its_cpu_kernel") else {
        return;
    };
    let started = std::time::Instant::now();
    eprintln!("adapter: {}", ctx.describe());
    let mut missing: Vec<String> = Vec::new();
    let mut failures: Vec<String> = Vec::new();
    let mut table = String::new();
    let mut harnesses: BTreeMap<(String, SocketType), GpuHarness> = BTreeMap::new();
    for NodeCase {
        t,
        generic,
        label,
        seed,
    } in node_cases()
    {
        let bound = bound_for(t.name());
        // Colour runs the vec3 harness (and the vec3 CPU variant).
        let harness_type = if generic == SocketType::Color {
            SocketType::Vec3
        } else {
            generic
        };
        let key = (t.name().to_owned(), harness_type);
        if !harnesses.contains_key(&key) {
            let module = match node_harness(t, harness_type) {
                Ok(m) => m,
                Err(ShaderError::MissingWgsl { .. }) => {
                    let name = if t.is_generic() {
                        format!("{} ({harness_type})", t.name())
                    } else {
                        t.name().to_owned()
                    };
                    if !missing.contains(&name) {
                        missing.push(name);
                    }
                    continue;
                }
                Err(e) => {
                    failures.push(format!(
                        "{} ({generic}): harness does not validate: {e}",
                        t.name()
                    ));
                    continue;
                }
            };
            match GpuHarness::new(ctx, &module) {
                Ok(h) => harnesses.insert(key.clone(), h),
                Err(e) => {
                    failures.push(format!(
                        "{} ({generic}): the driver rejected the harness: {e}\n{}",
                        t.name(),
                        module.source
                    ));
                    continue;
                }
            };
        }
        let harness = &harnesses[&key];
        let samples = node_samples(t, generic, seed);
        let Some(errors) =
            run_and_compare(t, generic, harness, &samples, bound, &label, &mut failures)
        else {
            continue;
        };
        let _ = writeln!(
            table,
            "  {label:<32} {:>6} samples  max abs {:9.3e}  max rel {:9.3e}  {:5.1}% of bound  {:>4} by conditioning",
            samples.n,
            errors.max_abs,
            errors.max_rel,
            errors.worst * 100.0,
            errors.conditioned
        );
    }
    eprintln!("node parity (bound {ABS:e} + {REL:e}·|cpu|):\n{table}");
    eprintln!("node parity took {:.1?}", started.elapsed());
    let mut report = String::new();
    if !missing.is_empty() {
        let _ = writeln!(
            report,
            "{} node types (generic variants) have no WGSL: {}",
            missing.len(),
            missing.join(", ")
        );
    }
    for f in &failures {
        let _ = writeln!(report, "{f}");
    }
    assert!(report.is_empty(), "node parity failed:\n{report}");
}

/// Every per-choice WGSL (`NodeType::wgsl_choice`, used where an enum input is a literal)
/// against the CPU kernel at that choice: the node's samples with the input set to it.
#[test]
fn every_literal_choice_matches_its_cpu_kernel() {
    let Some(ctx) = context("every_literal_choice_matches_its_cpu_kernel") else {
        return;
    };
    let mut failures: Vec<String> = Vec::new();
    let mut checked = 0;
    for (seed, t) in Registry::builtin().types().iter().enumerate() {
        // Texture nodes have no harness (no texture bindings): their choices are checked in
        // graphs (`the_monte_carlo_variant_matches_the_cpu_plan` sets both Fresnel choices).
        if t.evaluation() != Evaluation::Compute {
            continue;
        }
        let Some(choices) = t.wgsl_choices() else {
            continue;
        };
        for choice in &choices.choices {
            let generic = SocketType::Float;
            let label = format!("{} [{}={}]", t.name(), choices.input, choice.choice);
            let module = match node_choice_harness(t, generic, choice) {
                Ok(m) => m,
                Err(e) => {
                    failures.push(format!("{label}: harness does not validate: {e}"));
                    continue;
                }
            };
            let harness = match GpuHarness::new(ctx, &module) {
                Ok(h) => h,
                Err(e) => {
                    failures.push(format!("{label}: the driver rejected the harness: {e}"));
                    continue;
                }
            };
            let k = t.input_index(choices.input).unwrap();
            // An enum's choice by index; a bool's "false" / "true" as 0 / 1.
            let value = match t.inputs()[k]
                .choices
                .iter()
                .position(|c| *c == choice.choice)
            {
                Some(i) => i as f32,
                None => f32::from(u8::from(choice.choice == "true")),
            };
            let mut samples = node_samples(t, generic, 0x0c40_1ce0 + seed as u64);
            samples.columns[k].fill(value);
            let bound = bound_for(t.name());
            let Some(errors) =
                run_and_compare(t, generic, &harness, &samples, bound, &label, &mut failures)
            else {
                continue;
            };
            checked += 1;
            eprintln!(
                "  {label:<40} {:>6} samples  max abs {:9.3e}  {:5.1}% of bound  {:>4} by conditioning",
                samples.n,
                errors.max_abs,
                errors.worst * 100.0,
                errors.conditioned
            );
        }
    }
    assert!(
        checked >= 10,
        "thin_film, pbr_brdf, toon_water_depth_color and skin_single_scattering have \
         per-choice WGSL ({checked} checked)"
    );
    assert!(
        failures.is_empty(),
        "per-choice parity failed:\n{}",
        failures.join("\n")
    );
}

/// The values a constant input is checked at: every choice of an enum, both of a bool, and
/// the integers of an int's hard range (its two ends and default past 16 of them).
fn constant_values(t: &NodeType, k: usize) -> Vec<Value> {
    let d = &t.inputs()[k];
    if !d.choices.is_empty() {
        return (0..d.choices.len() as i32).map(Value::int).collect();
    }
    if d.ty.resolve(SocketType::Float) == SocketType::Bool {
        return vec![Value::boolean(false), Value::boolean(true)];
    }
    let (lo, hi) = d.hard.map_or((-2, 2), |r| (r.min as i32, r.max as i32));
    if hi - lo < 16 {
        (lo..=hi).map(Value::int).collect()
    } else {
        vec![Value::int(lo), d.default, Value::int(hi)]
    }
}

/// The float a harness column carries for a constant's value (ints and bools as floats).
fn column_value(v: Value) -> f32 {
    match v.ty() {
        SocketType::Bool => f32::from(u8::from(v.as_bool())),
        _ => v.as_i32() as f32,
    }
}

#[test]
fn every_constant_input_matches_its_cpu_kernel() {
    let Some(ctx) = context("every_constant_input_matches_its_cpu_kernel") else {
        return;
    };
    let mut failures: Vec<String> = Vec::new();
    let mut checked = 0;
    for (seed, t) in Registry::builtin().types().iter().enumerate() {
        if t.wgsl_constants().is_empty() {
            continue;
        }
        let inputs: Vec<usize> = t
            .wgsl_constants()
            .iter()
            .map(|name| t.input_index(name).unwrap())
            .collect();
        // Each value of each constant input alone (the others stay run-time arguments),
        // then every constant input at once at a seeded combination.
        let mut forms: Vec<Vec<(usize, Value)>> = inputs
            .iter()
            .flat_map(|&k| constant_values(t, k).into_iter().map(move |v| vec![(k, v)]))
            .collect();
        let mut rng = (seed as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ 0x51ec;
        forms.push(
            inputs
                .iter()
                .map(|&k| {
                    let values = constant_values(t, k);
                    rng = rng.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                    (k, values[(rng >> 33) as usize % values.len()])
                })
                .collect(),
        );
        for constants in &forms {
            let generic = SocketType::Float;
            let written: Vec<String> = constants
                .iter()
                .map(|(k, v)| format!("{}={}", t.inputs()[*k].name, column_value(*v)))
                .collect();
            let label = format!("{} [{}]", t.name(), written.join(", "));
            let module = match node_constant_harness(t, generic, constants) {
                Ok(m) => m,
                Err(e) => {
                    failures.push(format!("{label}: harness does not validate: {e}"));
                    continue;
                }
            };
            let harness = match GpuHarness::new(ctx, &module) {
                Ok(h) => h,
                Err(e) => {
                    failures.push(format!("{label}: the driver rejected the harness: {e}"));
                    continue;
                }
            };
            let mut samples = node_samples(t, generic, 0xc0_257a + seed as u64);
            for (k, v) in constants {
                samples.columns[*k].fill(column_value(*v));
            }
            // The bound any conformant GPU meets: these samples differ from the node test's,
            // and wave_texture's hard-range phases reach the worst GPU's ULPs on lavapipe too
            // (1.2e-2 measured, its WORST_GPU_LOOSE entry; the unspecialised function gives
            // the same on these samples).
            let bound = worst_gpu_bound_for(t.name());
            let Some(errors) =
                run_and_compare(t, generic, &harness, &samples, bound, &label, &mut failures)
            else {
                continue;
            };
            checked += 1;
            eprintln!(
                "  {label:<70} {:>6} samples  max abs {:9.3e}  {:5.1}% of bound",
                samples.n,
                errors.max_abs,
                errors.worst * 100.0,
            );
        }
    }
    // noise 11 + 1, voronoi 15 + 1, wave 13 + 1, magic 11 + 1, white noise 4 + 1, gradient 7 + 1.
    assert!(checked >= 66, "{checked} constant forms checked");
    assert!(
        failures.is_empty(),
        "constant-input parity failed:\n{}",
        failures.join("\n")
    );
}

// ------------------------------------------------------------------------------------------
// b) Graph parity
// ------------------------------------------------------------------------------------------

#[test]
fn every_shipped_graph_matches_the_cpu_plan() {
    let Some(ctx) = context("every_shipped_graph_matches_the_cpu_plan") else {
        return;
    };
    let mut failures = Vec::new();
    for GraphCase {
        name,
        graph,
        plan,
        batch,
    } in shipped_graph_cases()
    {
        let gpu = match GpuPlan::compile(ctx, &graph, &PlanOptions::default()) {
            Ok(g) => g,
            Err(e) => {
                failures.push(format!("{name}: {e}"));
                continue;
            }
        };
        // The file's values, then every float parameter scaled by 1.1 (no recompile).
        for (round, params) in parameter_rounds(&plan).iter().enumerate() {
            let want = plan.execute(&batch, params).unwrap();
            let got = match gpu.execute(&batch, params) {
                Ok(g) => g,
                Err(e) => {
                    failures.push(format!("{name}: {e}"));
                    break;
                }
            };
            let (errors, bad) = compare_batches(&want, &got);
            for (output, e) in errors {
                eprintln!(
                    "  {name:<20} round {round} {output:<14} {:>6} values  max abs {:9.3e}  max rel {:9.3e}  {:5.1}% of bound",
                    e.compared,
                    e.max_abs,
                    e.max_rel,
                    e.worst * 100.0
                );
            }
            failures.extend(
                bad.into_iter()
                    .map(|b| format!("{name} round {round}: {b}")),
            );
        }
        assert_eq!(gpu.pipelines_created(), 1);
    }
    assert!(
        failures.is_empty(),
        "graph parity failed:\n{}",
        failures.join("\n")
    );
}

/// Issue 37: every bundled graph's parameters swept over their ranges (the points of
/// tests/graphs/param_ranges.rs, [`parameter_sweep`]) and denormal and tiny normals and views
/// ([`degenerate_geometry_batch`], where a GPU flushes denormals to 0) give finite outputs on
/// the GPU too, one pipeline per graph.
#[test]
fn every_parameter_over_its_range_gives_finite_outputs_on_the_gpu() {
    let Some(ctx) = context("every_parameter_over_its_range_gives_finite_outputs_on_the_gpu")
    else {
        return;
    };
    let mut failures = Vec::new();
    let mut points = 0;
    for case in shipped_graph_cases() {
        let gpu = match GpuPlan::compile(ctx, &case.graph, &PlanOptions::default()) {
            Ok(g) => g,
            Err(e) => {
                failures.push(format!("{}: {e}", case.name));
                continue;
            }
        };
        let mut odd = degenerate_geometry_batch();
        if let Some(t) = case.batch.textures() {
            odd.set_textures(std::sync::Arc::new(t.clone()));
        }
        let mut runs = vec![(
            "degenerate geometry".to_owned(),
            &odd,
            case.plan.default_parameters(),
        )];
        runs.extend(
            parameter_sweep(&case.plan)
                .into_iter()
                .map(|(what, p)| (what, &case.batch, p)),
        );
        for (what, batch, params) in runs {
            points += 1;
            match gpu.execute(batch, &params) {
                Ok(out) => {
                    if let Some(bad) = first_non_finite(&out) {
                        failures.push(format!("{} {what}: {bad}", case.name));
                    }
                }
                Err(e) => failures.push(format!("{} {what}: {e}", case.name)),
            }
        }
        assert_eq!(gpu.pipelines_created(), 1, "{}", case.name);
    }
    eprintln!("{points} sweep points on the GPU");
    assert!(
        failures.is_empty(),
        "non-finite GPU outputs:\n{}",
        failures.join("\n")
    );
}

/// The Monte Carlo variant of pbr_glass (`ibl` = `monte_carlo`: env_ggx_monte_carlo's loop
/// of 64 filtered environment reads), which the default-variant graph parity above leaves
/// out, with either Fresnel, over a 512 × 256 stand-in environment (the renderer's size,
/// so the filtered lookups use several mip levels) with structure at every scale.
#[test]
fn the_monte_carlo_variant_matches_the_cpu_plan() {
    let Some(ctx) = context("the_monte_carlo_variant_matches_the_cpu_plan") else {
        return;
    };
    let mut failures = Vec::new();
    for fresnel in ["schlick", "exact"] {
        let GraphCase {
            graph, plan, batch, ..
        } = monte_carlo_case(fresnel);
        let gpu = GpuPlan::compile(ctx, &graph, &PlanOptions::default()).unwrap();
        let params = plan.default_parameters();
        let want = plan.execute(&batch, &params).unwrap();
        let got = gpu.execute(&batch, &params).unwrap();
        let (errors, bad) = compare_batches_within(&want, &got, graph_bound(&graph));
        for (output, e) in errors {
            eprintln!(
                "  pbr_glass ibl=monte_carlo fresnel={fresnel} {output:<10} {:>6} values  max abs {:9.3e}  max rel {:9.3e}  {:5.1}% of bound",
                e.compared,
                e.max_abs,
                e.max_rel,
                e.worst * 100.0
            );
        }
        failures.extend(bad.into_iter().map(|b| format!("fresnel {fresnel}: {b}")));
    }
    assert!(
        failures.is_empty(),
        "Monte Carlo parity failed:\n{}",
        failures.join("\n")
    );
}

// ------------------------------------------------------------------------------------------
// c) d) e) Runtime behaviour, on a graph of node types that had WGSL first
// ------------------------------------------------------------------------------------------

/// Fresnel of a dielectric with a float, a vec3 and the time in the uniform block.
const TEST_GRAPH: &str = r#"{
  "version": 1,
  "name": "gpu_runtime",
  "nodes": [
    { "id": "geo", "type": "geometry" },
    { "id": "cos", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.view" } } },
    { "id": "ior", "type": "parameter", "inputs": { "value": 1.52 } },
    { "id": "tint", "type": "parameter", "inputs": { "value": [0.2, 0.4, 0.6] } },
    { "id": "clock", "type": "time" },
    {
      "id": "exact",
      "type": "fresnel_dielectric",
      "inputs": { "cos_theta": { "link": "cos.result" }, "ior_inside": { "link": "ior.value" } }
    }
  ],
  "outputs": [
    { "name": "reflectance", "from": "exact.reflectance" },
    { "name": "transmittance", "from": "exact.transmittance" },
    { "name": "cos", "from": "cos.result" },
    { "name": "tint", "from": "tint.value" },
    { "name": "time", "from": "clock.time" },
    { "name": "uv", "from": "geo.uv" }
  ],
  "parameters": [
    { "name": "ior", "node": "ior" },
    { "name": "tint", "node": "tint" }
  ]
}"#;

fn test_graph() -> Graph {
    Graph::from_json(TEST_GRAPH, Registry::builtin()).unwrap_or_else(|e| panic!("{e:?}"))
}

/// `n` view directions sweeping 0°..180° from the normal (the back half is inside).
fn sweep(n: usize) -> SampleBatch {
    let views: Vec<[f32; 3]> = (0..n)
        .map(|i| {
            let t = (i as f32 + 0.5) / n.max(1) as f32 * std::f32::consts::PI;
            [t.sin(), 0.0, t.cos()]
        })
        .collect();
    let mut batch = SampleBatch::new(n);
    batch.set_values(Attribute::View, &views).unwrap();
    batch.set_time(2.5);
    batch
}

fn assert_parity(graph: &Graph, cpu: &OutputBatch, gpu: &OutputBatch, what: &str) {
    let (_, bad) = compare_batches_within(cpu, gpu, graph_bound(graph));
    assert!(bad.is_empty(), "{what}:\n{}", bad.join("\n"));
}

#[test]
fn changing_a_parameter_reuses_the_pipeline() {
    if context("changing_a_parameter_reuses_the_pipeline").is_none() {
        return;
    }
    // A private context, so its pipeline counter sees no other test.
    let ctx = GpuContext::new().expect("a second device on the same adapter");
    let graph = test_graph();
    let options = PlanOptions::default();
    let cpu = Plan::compile(&graph, &options).unwrap();
    let plan = GpuPlan::compile(&ctx, &graph, &options).unwrap();
    assert_eq!((plan.pipelines_created(), ctx.pipelines_created()), (1, 1));
    let batch = sweep(1000);
    let mut params = plan.default_parameters();
    assert_eq!(params, cpu.default_parameters());
    let glass = plan.execute(&batch, &params).unwrap();
    assert_parity(
        &graph,
        &cpu.execute(&batch, &params).unwrap(),
        &glass,
        "ior 1.52",
    );

    params.set("ior", Value::float(2.42)).unwrap();
    params.set("tint", Value::color([0.9, 0.5, 0.1])).unwrap();
    let diamond = plan.execute(&batch, &params).unwrap();
    assert_parity(
        &graph,
        &cpu.execute(&batch, &params).unwrap(),
        &diamond,
        "ior 2.42",
    );
    let r = glass.index("reflectance").unwrap();
    // At normal incidence R = ((n − 1)/(n + 1))²: 0.04258 for glass, 0.17239 for diamond.
    assert!(
        (glass.value(r, 0).as_f32() - 0.04258).abs() < 1e-4,
        "{:?}",
        glass.value(r, 0)
    );
    assert!(
        (diamond.value(r, 0).as_f32() - 0.17239).abs() < 1e-4,
        "{:?}",
        diamond.value(r, 0)
    );
    let tint = diamond.index("tint").unwrap();
    assert_eq!(diamond.value(tint, 999), Value::vec3([0.9, 0.5, 0.1]));
    let time = diamond.index("time").unwrap();
    assert_eq!(diamond.value(time, 7).as_f32(), 2.5);

    let mut later = sweep(1000);
    later.set_time(7.0);
    let moved = plan.execute(&later, &params).unwrap();
    assert_eq!(moved.value(time, 0).as_f32(), 7.0);
    assert_eq!(
        (plan.pipelines_created(), ctx.pipelines_created()),
        (1, 1),
        "a parameter change recompiled"
    );
}

#[test]
fn the_backend_switch_gives_the_same_results() {
    if context("the_backend_switch_gives_the_same_results").is_none() {
        return;
    }
    let graph = test_graph();
    let options = PlanOptions {
        outputs: vec!["reflectance".into(), "tint".into()],
        ..Default::default()
    };
    let cpu = gpu::compile(&graph, &options, Backend::Cpu).unwrap();
    let gpu = gpu::compile(&graph, &options, Backend::Gpu).unwrap();
    let mut params = gpu::default_parameters(&graph, &options).unwrap();
    params.set("ior", Value::float(1.33)).unwrap();
    let batch = sweep(777);
    let (a, b) = (
        cpu.evaluate(&batch, &params).unwrap(),
        gpu.evaluate(&batch, &params).unwrap(),
    );
    assert_eq!(a.names(), ["reflectance", "tint"]);
    assert_parity(&graph, &a, &b, "Backend::Cpu vs Backend::Gpu");
}

#[test]
fn batch_sizes_around_the_workgroup_size() {
    let Some(ctx) = context("batch_sizes_around_the_workgroup_size") else {
        return;
    };
    let graph = test_graph();
    let options = PlanOptions::default();
    let cpu = Plan::compile(&graph, &options).unwrap();
    let plan = GpuPlan::compile(ctx, &graph, &options).unwrap();
    let params = plan.default_parameters();
    for n in [0, 1, 65, 64, 100_000, 3] {
        let batch = sweep(n);
        let got = plan.execute(&batch, &params).unwrap();
        assert_eq!(got.len(), n);
        for k in 0..got.names().len() {
            assert_eq!(got.planar(k).len(), got.ty(k).width() * n);
        }
        assert_parity(
            &graph,
            &cpu.execute(&batch, &params).unwrap(),
            &got,
            &format!("n = {n}"),
        );
    }
    // 100,000 samples over rows of 7 workgroups (224 rows) exercise the 2-D dispatch.
    let rows = GpuPlan::compile(ctx, &graph, &options)
        .unwrap()
        .with_max_workgroups_per_row(7);
    let batch = sweep(100_000);
    assert_parity(
        &graph,
        &cpu.execute(&batch, &params).unwrap(),
        &rows.execute(&batch, &params).unwrap(),
        "2-D dispatch",
    );
    // A batch larger than one storage binding holds runs in chunks (here of 1000 samples:
    // mg_geometry's and mg_out's lanes of 1000 samples fit 1000 · 4 · widest bytes).
    let lanes = matgraph::wgsl::geometry_lanes(&plan.shader().attributes) as u64;
    let widest = lanes.max(plan.shader().output_columns() as u64);
    let chunked = GpuPlan::compile(ctx, &graph, &options)
        .unwrap()
        .with_max_binding_bytes(1000 * 4 * widest);
    for n in [999, 1000, 1001, 4321] {
        // Every attribute the graph reads varies, so a lane read from another chunk shows.
        let mut batch = sweep(n);
        let normals: Vec<[f32; 3]> = (0..n)
            .map(|i| {
                let t = i as f32 * 0.37;
                [t.sin() * 0.6, 0.8, t.cos() * 0.6]
            })
            .collect();
        batch.set_values(Attribute::Normal, &normals).unwrap();
        let uvs: Vec<[f32; 3]> = (0..n)
            .map(|i| [i as f32 / n as f32, (i % 17) as f32 / 17.0, 0.0])
            .collect();
        batch.set_values(Attribute::Uv, &uvs).unwrap();
        assert_parity(
            &graph,
            &cpu.execute(&batch, &params).unwrap(),
            &chunked.execute(&batch, &params).unwrap(),
            &format!("{n} samples in chunks of 1000"),
        );
    }
    // Attributes the batch lacks take their defaults (normal = +z, uv = (0.5, 0.5)).
    let bare = SampleBatch::new(5);
    let got = plan.execute(&bare, &params).unwrap();
    assert_parity(
        &graph,
        &cpu.execute(&bare, &params).unwrap(),
        &got,
        "default attributes",
    );
    assert_eq!(
        got.value(got.index("uv").unwrap(), 4),
        Value::vec2([0.5, 0.5])
    );
}

#[test]
fn errors_are_reported_not_panics() {
    let Some(ctx) = context("errors_are_reported_not_panics") else {
        return;
    };
    let graph = test_graph();
    let plan = GpuPlan::compile(ctx, &graph, &PlanOptions::default()).unwrap();
    // Parameter values of another plan (one parameter instead of two).
    let other_graph = Graph::from_json(NON_FINITE_GRAPH, Registry::builtin()).unwrap();
    let other = gpu::default_parameters(&other_graph, &PlanOptions::default()).unwrap();
    assert!(plan.execute(&sweep(4), &other).is_err());
    let unknown = GpuPlan::compile(
        ctx,
        &graph,
        &PlanOptions {
            outputs: vec!["reflectanse".into()],
            ..Default::default()
        },
    );
    assert!(
        matches!(unknown, Err(EvalError::UnknownOutput { .. })),
        "{:?}",
        unknown.err()
    );
    let dot = Registry::builtin().get("dot").unwrap();
    let module = node_harness(dot, SocketType::Vec3).unwrap();
    let h = GpuHarness::new(ctx, &module).unwrap();
    assert!(matches!(h.run(&[1.0; 5], 1), Err(EvalError::Gpu(_))));
    assert_eq!(h.run(&[], 0).unwrap(), Vec::<f32>::new());
    // WGSL the driver rejects is an error, not a panic: a missing entry point, bad syntax.
    let mut broken = module.clone();
    broken.source = broken.source.replace("fn mg_compute", "fn mg_elsewhere");
    let e = GpuHarness::new(ctx, &broken).err().expect("no entry point");
    assert!(
        matches!(&e, EvalError::Gpu(m) if m.contains("compiling")),
        "{e}"
    );
    eprintln!("driver error as reported: {e}");
    broken.source = format!("{}\nfn {{", module.source);
    assert!(matches!(
        GpuHarness::new(ctx, &broken),
        Err(EvalError::Gpu(_))
    ));
    // The device is still usable afterwards.
    assert_eq!(
        h.run(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0], 1).unwrap(),
        vec![32.0]
    );
}

/// Every kind of value the code generator moves: float, vec2 and colour uniforms, time,
/// colour → float (luminance), bool → float and float → vec3 conversions on links, a folded
/// constant, several outputs of one node, a bool link and a bool output. (Parameters are
/// float or vectors: a bool uniform cannot be declared.)
const COVERAGE_GRAPH: &str = r#"{
  "version": 1,
  "name": "gpu_coverage",
  "nodes": [
    { "id": "geo", "type": "geometry" },
    { "id": "clock", "type": "time" },
    { "id": "tint", "type": "parameter", "data_type": "color", "inputs": { "value": [0.8, 0.3, 0.1] } },
    { "id": "gain", "type": "parameter", "inputs": { "value": 2.0 } },
    { "id": "offset", "type": "parameter", "inputs": { "value": [0.25, -0.5] } },
    { "id": "ndotl", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.light" } } },
    {
      "id": "refr",
      "type": "refract",
      "inputs": { "i": { "link": "geo.view" }, "n": { "link": "geo.normal" }, "eta": { "link": "gain.value" } }
    },
    {
      "id": "blend",
      "type": "mix",
      "data_type": "float",
      "inputs": { "a": { "link": "tint.value" }, "b": { "link": "ndotl.result" }, "t": { "link": "refr.tir" } }
    },
    {
      "id": "scaled",
      "type": "mul",
      "data_type": "vec3",
      "inputs": { "a": { "link": "geo.position" }, "b": { "link": "gain.value" } }
    },
    {
      "id": "ranged",
      "type": "remap",
      "data_type": "float",
      "inputs": {
        "x": { "link": "ndotl.result" },
        "from_min": -0.5,
        "from_max": 0.5,
        "to_max": { "link": "gain.value" },
        "clamp": { "link": "refr.tir" }
      }
    },
    { "id": "uvs", "type": "add", "data_type": "vec2", "inputs": { "a": { "link": "geo.uv" }, "b": { "link": "offset.value" } } },
    { "id": "twelve", "type": "mul", "data_type": "float", "inputs": { "a": 3.0, "b": 4.0 } },
    { "id": "later", "type": "add", "data_type": "float", "inputs": { "a": { "link": "twelve.result" }, "b": { "link": "clock.time" } } },
    {
      "id": "parts",
      "type": "combine",
      "inputs": { "x": { "link": "ndotl.result" }, "y": { "link": "later.result" }, "z": 1.0, "w": { "link": "ranged.result" } }
    },
    { "id": "unit", "type": "normalize", "data_type": "vec4", "inputs": { "v": { "link": "parts.vec4" } } },
    { "id": "powered", "type": "pow", "data_type": "float", "inputs": { "a": { "link": "ranged.result" }, "b": { "link": "gain.value" } } },
    { "id": "tinted", "type": "add", "data_type": "color", "inputs": { "a": { "link": "tint.value" }, "b": { "link": "parts.color" } } }
  ],
  "outputs": [
    { "name": "blend", "from": "blend.result" },
    { "name": "scaled", "from": "scaled.result" },
    { "name": "ranged", "from": "ranged.result" },
    { "name": "uvs", "from": "uvs.result" },
    { "name": "later", "from": "later.result" },
    { "name": "unit", "from": "unit.result" },
    { "name": "powered", "from": "powered.result" },
    { "name": "tinted", "from": "tinted.result" },
    { "name": "tir", "from": "refr.tir" },
    { "name": "refracted", "from": "refr.t" },
    { "name": "twelve", "from": "twelve.result" }
  ],
  "parameters": [
    { "name": "tint", "node": "tint" },
    { "name": "gain", "node": "gain" },
    { "name": "offset", "node": "offset" }
  ]
}"#;

#[test]
fn conversions_uniform_types_and_plan_options() {
    let Some(ctx) = context("conversions_uniform_types_and_plan_options") else {
        return;
    };
    let graph =
        Graph::from_json(COVERAGE_GRAPH, Registry::builtin()).unwrap_or_else(|e| panic!("{e:?}"));
    let batch = grid_batch();
    let option_sets = [
        PlanOptions::default(),
        PlanOptions {
            bake_parameters: true,
            ..Default::default()
        },
        PlanOptions {
            outputs: vec![
                "ndotl.result".into(),
                "tir".into(),
                "parts.vec2".into(),
                "tinted".into(),
            ],
            ..Default::default()
        },
    ];
    let mut failures = Vec::new();
    for options in &option_sets {
        let cpu = Plan::compile(&graph, options).unwrap();
        let gpu = match GpuPlan::compile(ctx, &graph, options) {
            Ok(g) => g,
            Err(e) => {
                failures.push(format!("{options:?}: {e}"));
                continue;
            }
        };
        let mut params = cpu.default_parameters();
        for round in 0..2 {
            if round == 1 && !options.bake_parameters {
                params.set("tint", Value::color([0.1, 0.9, 0.4])).unwrap();
                params.set("gain", Value::float(0.6)).unwrap();
                params.set("offset", Value::vec2([-1.0, 3.0])).unwrap();
            }
            let want = cpu.execute(&batch, &params).unwrap();
            let got = match gpu.execute(&batch, &params) {
                Ok(g) => g,
                Err(e) => {
                    failures.push(format!("{options:?} round {round}: {e}"));
                    break;
                }
            };
            let (errors, bad) = compare_batches(&want, &got);
            for (output, e) in errors {
                eprintln!(
                    "  bake={} round {round} {output:<14} max abs {:9.3e}  max rel {:9.3e}  {:5.1}% of bound",
                    options.bake_parameters,
                    e.max_abs,
                    e.max_rel,
                    e.worst * 100.0
                );
            }
            failures.extend(
                bad.into_iter()
                    .map(|b| format!("{:?} round {round}: {b}", options.outputs)),
            );
        }
    }
    assert!(
        failures.is_empty(),
        "coverage graph parity failed:\n{}",
        failures.join("\n")
    );
}

/// One generic node type used at vec3 and at colour in the same graph (both map to the
/// same WGSL function).
const VEC3_AND_COLOR_GRAPH: &str = r#"{
  "version": 1,
  "name": "vec3_and_color",
  "nodes": [
    { "id": "geo", "type": "geometry" },
    { "id": "tint", "type": "parameter", "data_type": "color", "inputs": { "value": [0.8, 0.3, 0.1] } },
    { "id": "scaled", "type": "mul", "data_type": "vec3", "inputs": { "a": { "link": "geo.position" }, "b": 2.0 } },
    { "id": "tinted", "type": "mul", "data_type": "color", "inputs": { "a": { "link": "tint.value" }, "b": { "link": "geo.normal" } } }
  ],
  "outputs": [
    { "name": "scaled", "from": "scaled.result" },
    { "name": "tinted", "from": "tinted.result" }
  ],
  "parameters": [{ "name": "tint", "node": "tint" }]
}"#;

#[test]
fn a_node_type_used_at_vec3_and_at_color() {
    let Some(ctx) = context("a_node_type_used_at_vec3_and_at_color") else {
        return;
    };
    let graph = Graph::from_json(VEC3_AND_COLOR_GRAPH, Registry::builtin())
        .unwrap_or_else(|e| panic!("{e:?}"));
    let options = PlanOptions::default();
    let cpu = Plan::compile(&graph, &options).unwrap();
    let gpu = GpuPlan::compile(ctx, &graph, &options).unwrap_or_else(|e| panic!("{e}"));
    let batch = grid_batch();
    let params = cpu.default_parameters();
    assert_parity(
        &graph,
        &cpu.execute(&batch, &params).unwrap(),
        &gpu.execute(&batch, &params).unwrap(),
        "vec3 and color",
    );
}

/// Blender's textures with their choices written, at the top level and inside a group used
/// twice: each node's function is compiled at its written choices (`wgsl_constant_inputs`).
const WRITTEN_CHOICES_GRAPH: &str = r#"{
  "version": 2,
  "name": "written_choices",
  "groups": {
    "grain": {
      "inputs": [ { "name": "p", "type": "vec3" }, { "name": "scale", "type": "float", "default": 4.0 } ],
      "nodes": [
        { "id": "n", "type": "noise_texture", "inputs": { "vector": { "link": "@in.p" }, "scale": { "link": "@in.scale" },
          "detail": 3.5, "dimensions": "4d", "type": "ridged_multifractal", "normalize": false } },
        { "id": "v", "type": "voronoi_texture", "inputs": { "vector": { "link": "@in.p" }, "scale": { "link": "@in.scale" },
          "feature": "distance_to_edge", "metric": "manhattan" } },
        { "id": "s", "type": "add", "inputs": { "a": { "link": "n.fac" }, "b": { "link": "v.distance" } } }
      ],
      "outputs": [ { "name": "y", "from": "s.result" } ]
    }
  },
  "nodes": [
    { "id": "geo", "type": "geometry" },
    { "id": "noise", "type": "noise_texture", "inputs": { "vector": { "link": "geo.view" }, "scale": 5.0, "detail": 8.0, "dimensions": "3d", "type": "fbm" } },
    { "id": "noise2", "type": "noise_texture", "inputs": { "vector": { "link": "geo.view" }, "scale": 2.0, "dimensions": "2d", "type": "hetero_terrain" } },
    { "id": "cells", "type": "voronoi_texture", "inputs": { "vector": { "link": "geo.view" }, "scale": 5.0, "feature": "f2", "metric": "chebychev" } },
    { "id": "wave", "type": "wave_texture", "inputs": { "vector": { "link": "geo.view" }, "type": "rings", "rings_direction": "z", "profile": "tri" } },
    { "id": "magic", "type": "magic_texture", "inputs": { "vector": { "link": "geo.view" }, "depth": 5 } },
    { "id": "white", "type": "white_noise", "inputs": { "vector": { "link": "geo.view" }, "dimensions": "3d" } },
    { "id": "ramp", "type": "gradient_texture", "inputs": { "vector": { "link": "geo.view" }, "type": "spherical" } },
    { "id": "g1", "type": "group", "group": "grain", "inputs": { "p": { "link": "geo.view" } } },
    { "id": "g2", "type": "group", "group": "grain", "inputs": { "p": { "link": "geo.normal" }, "scale": 9.0 } }
  ],
  "outputs": [
    { "name": "noise", "from": "noise.color" },
    { "name": "noise2", "from": "noise2.fac" },
    { "name": "cells", "from": "cells.distance" },
    { "name": "wave", "from": "wave.fac" },
    { "name": "magic", "from": "magic.color" },
    { "name": "white", "from": "white.color" },
    { "name": "ramp", "from": "ramp.fac" },
    { "name": "g1", "from": "g1.y" },
    { "name": "g2", "from": "g2.y" }
  ]
}"#;

#[test]
fn written_choices_compile_into_the_functions_and_match_the_cpu_plan() {
    let Some(ctx) = context("written_choices_compile_into_the_functions_and_match_the_cpu_plan")
    else {
        return;
    };
    let graph = Graph::from_json(WRITTEN_CHOICES_GRAPH, Registry::builtin())
        .unwrap_or_else(|e| panic!("{e:?}"));
    let options = PlanOptions::default();
    let cpu = Plan::compile(&graph, &options).unwrap();
    let gpu = GpuPlan::compile(ctx, &graph, &options).unwrap_or_else(|e| panic!("{e}"));
    let wgsl = &gpu.shader().source;
    for name in [
        "fn mg_noise_texture_dimensions_3d_type_fbm_normalize_true(",
        "fn mg_noise_texture_dimensions_2d_type_hetero_terrain_normalize_true(",
        "fn mg_noise_texture_dimensions_4d_type_ridged_multifractal_normalize_false(",
        "fn mg_voronoi_texture_dimensions_3d_feature_distance_to_edge_metric_manhattan_normalize_false(",
        "fn mg_voronoi_texture_dimensions_3d_feature_f2_metric_chebychev_normalize_false(",
        "fn mg_magic_texture_depth_5(",
        "fn mg_white_noise_dimensions_3d(",
        "fn mg_gradient_texture_type_spherical(",
    ] {
        assert!(wgsl.contains(name), "no `{name}` in:\n{wgsl}");
    }
    assert!(
        !wgsl.contains("fn mg_noise_texture("),
        "an unspecialised noise function"
    );
    let batch = grid_batch();
    let params = cpu.default_parameters();
    assert_parity(
        &graph,
        &cpu.execute(&batch, &params).unwrap(),
        &gpu.execute(&batch, &params).unwrap(),
        "written choices",
    );
}

/// Constants folded to ±inf and NaN (written as bit patterns in WGSL), and a material that
/// reads no attribute at all.
const NON_FINITE_GRAPH: &str = r#"{
  "version": 1,
  "name": "non_finite",
  "nodes": [
    { "id": "gain", "type": "parameter", "inputs": { "value": 0.5 } },
    { "id": "clock", "type": "time" },
    { "id": "huge", "type": "exp", "data_type": "float", "inputs": { "x": 100.0 } },
    { "id": "minus_huge", "type": "mul", "data_type": "float", "inputs": { "a": { "link": "huge.result" }, "b": -1.0 } },
    { "id": "nan", "type": "add", "data_type": "float", "inputs": { "a": { "link": "huge.result" }, "b": { "link": "minus_huge.result" } } },
    { "id": "scaled", "type": "mul", "data_type": "float", "inputs": { "a": { "link": "huge.result" }, "b": { "link": "gain.value" } } },
    { "id": "moving", "type": "mul", "data_type": "float", "inputs": { "a": { "link": "clock.time" }, "b": { "link": "gain.value" } } }
  ],
  "outputs": [
    { "name": "inf", "from": "huge.result" },
    { "name": "minus_inf", "from": "minus_huge.result" },
    { "name": "nan", "from": "nan.result" },
    { "name": "scaled", "from": "scaled.result" },
    { "name": "moving", "from": "moving.result" }
  ],
  "parameters": [{ "name": "gain", "node": "gain" }]
}"#;

#[test]
fn non_finite_constants_and_attribute_free_materials() {
    let Some(ctx) = context("non_finite_constants_and_attribute_free_materials") else {
        return;
    };
    let graph =
        Graph::from_json(NON_FINITE_GRAPH, Registry::builtin()).unwrap_or_else(|e| panic!("{e:?}"));
    let options = PlanOptions::default();
    let cpu = Plan::compile(&graph, &options).unwrap();
    let gpu = GpuPlan::compile(ctx, &graph, &options).unwrap_or_else(|e| panic!("{e}"));
    let mut batch = SampleBatch::new(70);
    batch.set_time(3.0);
    let mut params = cpu.default_parameters();
    for gain in [0.5, -2.0] {
        params.set("gain", Value::float(gain)).unwrap();
        let want = cpu.execute(&batch, &params).unwrap();
        let got = gpu.execute(&batch, &params).unwrap();
        assert_parity(&graph, &want, &got, &format!("gain {gain}"));
        assert_eq!(
            got.value(got.index("inf").unwrap(), 69).as_f32(),
            f32::INFINITY
        );
        assert!(got.value(got.index("nan").unwrap(), 0).as_f32().is_nan());
        assert_eq!(
            got.value(got.index("moving").unwrap(), 1).as_f32(),
            3.0 * gain
        );
    }
}

/// Parameter and output names that WGSL reserves or that collide once made identifiers.
const AWKWARD_NAMES_GRAPH: &str = r#"{
  "version": 1,
  "name": "awkward names",
  "nodes": [
    { "id": "geo", "type": "geometry" },
    { "id": "clock", "type": "time" },
    { "id": "p-in", "type": "parameter", "inputs": { "value": 0.25 } },
    { "id": "p-fn", "type": "parameter", "inputs": { "value": [1.0, 2.0, 3.0] } },
    { "id": "sum", "type": "add", "data_type": "float", "inputs": { "a": { "link": "clock.time" }, "b": { "link": "p-in.value" } } },
    { "id": "lit", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "p-fn.value" } } }
  ],
  "outputs": [
    { "name": "fn", "from": "sum.result" },
    { "name": "a-b", "from": "lit.result" },
    { "name": "a_b", "from": "sum.result" },
    { "name": "time", "from": "p-fn.value" }
  ],
  "parameters": [
    { "name": "in", "node": "p-in" },
    { "name": "fn", "node": "p-fn" }
  ]
}"#;

#[test]
fn awkward_parameter_and_output_names() {
    let Some(ctx) = context("awkward_parameter_and_output_names") else {
        return;
    };
    let graph = Graph::from_json(AWKWARD_NAMES_GRAPH, Registry::builtin())
        .unwrap_or_else(|e| panic!("{e:?}"));
    let options = PlanOptions::default();
    let cpu = Plan::compile(&graph, &options).unwrap();
    let gpu = GpuPlan::compile(ctx, &graph, &options).unwrap_or_else(|e| panic!("{e}"));
    let mut batch = grid_batch();
    batch.set_time(10.0);
    let mut params = cpu.default_parameters();
    params.set("in", Value::float(0.5)).unwrap();
    params.set("fn", Value::vec3([0.0, 1.0, -1.0])).unwrap();
    let want = cpu.execute(&batch, &params).unwrap();
    let got = gpu.execute(&batch, &params).unwrap();
    assert_eq!(got.value(got.index("fn").unwrap(), 0).as_f32(), 10.5);
    assert_parity(&graph, &want, &got, "awkward names");
}

/// A parameter node the graph does not expose: it keeps the file's value, next to `time`.
const UNEXPOSED_PARAMETER_GRAPH: &str = r#"{
  "version": 1,
  "name": "unexposed parameter",
  "nodes": [
    { "id": "geo", "type": "geometry" },
    { "id": "clock", "type": "time" },
    { "id": "hidden", "type": "parameter", "inputs": { "value": 0.75 } },
    { "id": "lit", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.view" } } },
    { "id": "kept", "type": "mul", "data_type": "float", "inputs": { "a": { "link": "hidden.value" }, "b": { "link": "lit.result" } } }
  ],
  "outputs": [
    { "name": "hidden", "from": "hidden.value" },
    { "name": "kept", "from": "kept.result" },
    { "name": "time", "from": "clock.time" }
  ]
}"#;

#[test]
fn an_unexposed_parameter_keeps_its_value() {
    let Some(ctx) = context("an_unexposed_parameter_keeps_its_value") else {
        return;
    };
    let graph = Graph::from_json(UNEXPOSED_PARAMETER_GRAPH, Registry::builtin())
        .unwrap_or_else(|e| panic!("{e:?}"));
    let options = PlanOptions::default();
    let cpu = Plan::compile(&graph, &options).unwrap();
    let gpu = GpuPlan::compile(ctx, &graph, &options).unwrap_or_else(|e| panic!("{e}"));
    let mut batch = grid_batch();
    batch.set_time(10.0);
    let params = cpu.default_parameters();
    let want = cpu.execute(&batch, &params).unwrap();
    assert_eq!(want.value(want.index("hidden").unwrap(), 0).as_f32(), 0.75);
    assert_parity(
        &graph,
        &want,
        &gpu.execute(&batch, &params).unwrap(),
        "unexposed parameter",
    );
}

#[test]
fn the_comparison_rejects_what_it_should() {
    let mut e = Errors::default();
    let b = (ABS, REL);
    assert!(e.check(1.0, 1.0 + 1e-4, b));
    assert!(!e.check(1.0, 1.0 + 2e-4, b));
    assert!(e.check(0.0, 9e-6, b) && !e.check(0.0, 2e-5, b));
    assert!(e.check(0.0, -0.0, b));
    assert!(e.check(f32::NAN, -f32::NAN, b));
    assert!(!e.check(f32::NAN, 0.0, b) && !e.check(0.0, f32::NAN, b));
    assert!(e.check(f32::INFINITY, f32::INFINITY, b));
    assert!(!e.check(f32::INFINITY, f32::MAX, b) && !e.check(f32::MAX, f32::INFINITY, b));
    assert!(!e.check(f32::INFINITY, f32::NEG_INFINITY, b));
}

/// Blender's habit for uvs (src/types.rs): `geometry.uv` (vec2) into `mapping.vector` (vec3)
/// is `(u, v, 0)`, and `mapping.vector` into a vec2 input is its `(x, y)`. Against the closed
/// form in f64 at the grid's uvs and at seeded f32 ones, on the CPU and the GPU.
#[test]
fn uvs_extend_into_vectors_and_vectors_truncate_into_uvs_alike_on_both_backends() {
    let graph = Graph::from_json(
        r#"{
          "version": 1,
          "name": "uv_mapping",
          "nodes": [
            { "id": "g", "type": "geometry" },
            { "id": "m", "type": "mapping",
              "inputs": { "vector": { "link": "g.uv" }, "location": [0.5, 0.25, 7.0],
                          "scale": [2.0, -3.0, 4.0] } },
            { "id": "shift", "type": "add", "data_type": "vec2",
              "inputs": { "a": { "link": "m.vector" }, "b": [0.125, -0.5] } }
          ],
          "outputs": [
            { "name": "mapped", "from": "m.vector" },
            { "name": "uv", "from": "shift.result" }
          ]
        }"#,
        Registry::builtin(),
    )
    .unwrap_or_else(|e| panic!("{e:?}"));
    let mut batch = grid_batch();
    let mut rng = crate::common::rng::Rng(0x5eed_0dd5);
    let mut uvs: Vec<[f32; 3]> = (0..batch.len())
        .map(|_| [rng.f32(-4.0, 4.0), rng.f32(-4.0, 4.0), 0.0])
        .collect();
    uvs[0] = [0.0, 0.0, 0.0];
    uvs[1] = [1.0, 1.0, 0.0];
    batch.set_values(Attribute::Uv, &uvs).unwrap();
    let options = PlanOptions::default();
    let cpu = Plan::compile(&graph, &options).unwrap();
    let params = gpu::default_parameters(&graph, &options).unwrap();
    let out = cpu.execute(&batch, &params).unwrap();
    for (i, uv) in uvs.iter().enumerate() {
        let (u, v) = (uv[0] as f64, uv[1] as f64);
        let mapped = [2.0 * u + 0.5, -3.0 * v + 0.25, 7.0];
        let shifted = [mapped[0] + 0.125, mapped[1] - 0.5];
        let m = out.value(0, i).lanes().to_vec();
        let s = out.value(1, i).lanes().to_vec();
        assert_eq!(out.ty(1), SocketType::Vec2);
        for c in 0..3 {
            assert!((m[c] as f64 - mapped[c]).abs() <= 2e-6 * (1.0 + mapped[c].abs()));
        }
        for c in 0..2 {
            assert!(
                (s[c] as f64 - shifted[c]).abs() <= 2e-6 * (1.0 + shifted[c].abs()),
                "uv {uv:?}: {s:?} vs {shifted:?}"
            );
        }
    }
    let Some(ctx) = context("uvs_extend_into_vectors_and_vectors_truncate_into_uvs") else {
        return;
    };
    let on_gpu = GpuPlan::compile(ctx, &graph, &options).unwrap();
    let gpu_out = on_gpu.execute(&batch, &params).unwrap();
    assert_parity(&graph, &out, &gpu_out, "extend and truncate");
}
