//! Registry-driven stability, documentation, determinism and plan-compiler tests.
//!
//! Every test here walks `Registry::builtin().types()`, so a node type added to the library
//! is covered without editing this file. Node inputs are drawn over their declared ranges
//! (the soft range when set, else the hard range, else [-10, 10]; enum inputs over their
//! choices, bools both ways, vectors per component), and every generic node is evaluated
//! for every generic type it accepts.
//!

use matgraph::node::{Evaluation, InputDecl, NodeType, PortType, Range, is_snake_case};
use matgraph::plan::Operand;
use matgraph::types::SocketType;
use matgraph::{
    Attribute, EvalError, Graph, OutputBatch, ParamValues, Plan, PlanOptions, Registry,
    SampleBatch, Value,
};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestCaseError, TestError, TestRunner};
use serde_json::{Value as J, json};
use std::collections::{BTreeMap, BTreeSet};

// ---------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------

fn registry() -> &'static Registry {
    Registry::builtin()
}

/// Random cases per (node type, generic type) in the stability property.
const STABILITY_CASES: u32 = 256;

/// The generic types a node is evaluated for: every accepted one, or `None` once.
fn type_variants(t: &NodeType) -> Vec<Option<SocketType>> {
    if t.is_generic() {
        t.generic_types().into_iter().map(Some).collect()
    } else {
        vec![None]
    }
}

fn t_name(g: Option<SocketType>) -> &'static str {
    g.map(|t| t.name()).unwrap_or("-")
}

/// The concrete type of an input once `T` is `g`.
fn port_type(decl: &InputDecl, g: Option<SocketType>) -> SocketType {
    decl.ty.resolve(g.unwrap_or(SocketType::Float))
}

/// The range random values are drawn from: soft, else hard, else [-10, 10].
fn sample_range(decl: &InputDecl) -> Range {
    decl.soft.or(decl.hard).unwrap_or(Range {
        min: -10.0,
        max: 10.0,
    })
}

fn json_f32(x: f32) -> J {
    json!(x)
}

/// A JSON literal of type `ty` with every float component from `f`.
fn literal(ty: SocketType, mut f: impl FnMut() -> f32) -> J {
    match ty.width() {
        1 => json_f32(f()),
        w => J::Array((0..w).map(|_| json_f32(f())).collect()),
    }
}

/// The JSON literal of `v` for input `decl` of concrete type `ty` (enum choices by name).
fn value_json(decl: &InputDecl, ty: SocketType, v: Value) -> Result<J, String> {
    let v = v
        .convert(ty)
        .ok_or_else(|| format!("{}: a {} does not convert to {ty}", decl.name, v.ty()))?;
    if let Some(name) = usize::try_from(v.as_i32())
        .ok()
        .and_then(|i| decl.choices.get(i))
        .filter(|_| ty == SocketType::Int)
    {
        return Ok(J::String((*name).to_owned()));
    }
    Ok(v.to_json())
}

/// The key texture nodes sample in these tests.
const TEST_TEXTURE: &str = "test:gradient";

/// A batch of `n` samples with [`TEST_TEXTURE`] bound: an 8 × 8 RGBA gradient with mips.
fn new_batch(n: usize) -> SampleBatch {
    use matgraph::texture::{Image, Texture, TextureSet};
    static SET: std::sync::LazyLock<std::sync::Arc<TextureSet>> = std::sync::LazyLock::new(|| {
        let image = Image::from_fn(8, 8, |x, y| {
            [x as f32 / 7.0, y as f32 / 7.0, 0.25, 1.0 - x as f32 / 14.0]
        });
        let mut set = TextureSet::new();
        set.insert(TEST_TEXTURE, Texture::new(image, true).unwrap())
            .unwrap();
        std::sync::Arc::new(set)
    });
    let mut batch = SampleBatch::new(n);
    batch.set_textures(SET.clone());
    batch
}

/// A one-node graph of type `t` with `T = g`. Built with `Graph::single_node` (T inferred
/// from the literals' shapes); colour, which no literal shape selects, is pinned with
/// `data_type` in a one-node document. Checks the resolved `T`.
fn build(
    t: &NodeType,
    g: Option<SocketType>,
    inputs: BTreeMap<String, J>,
) -> Result<Graph, String> {
    let graph = if t.evaluation() == Evaluation::Texture {
        // Texture nodes sample TEST_TEXTURE, which every batch of this file binds.
        let outputs: Vec<J> = t
            .outputs()
            .iter()
            .map(|o| json!({ "name": o.name, "from": format!("node.{}", o.name) }))
            .collect();
        let doc = json!({
            "version": 2,
            "name": t.name(),
            "nodes": [{ "id": "node", "type": t.name(), "texture": TEST_TEXTURE, "inputs": inputs }],
            "outputs": outputs,
        });
        Graph::from_json(&doc.to_string(), registry())
    } else if g == Some(SocketType::Color) {
        let outputs: Vec<J> = t
            .outputs()
            .iter()
            .map(|o| json!({ "name": o.name, "from": format!("node.{}", o.name) }))
            .collect();
        let doc = json!({
            "version": 2,
            "name": t.name(),
            "nodes": [{ "id": "node", "type": t.name(), "data_type": "color", "inputs": inputs }],
            "outputs": outputs,
        });
        Graph::from_json(&doc.to_string(), registry())
    } else {
        Graph::single_node(registry(), t.name(), inputs)
    }
    .map_err(|e| format!("graph rejected: {e:?}"))?;
    let resolved = graph.nodes()[0].generic;
    if let Some(g) = g
        && resolved != g
    {
        return Err(format!("T resolved to {resolved}, expected {g}"));
    }
    Ok(graph)
}

/// Compiles every graph output and evaluates a batch of `n` samples.
fn evaluate(graph: &Graph, n: usize) -> Result<OutputBatch, String> {
    let plan = Plan::compile(graph, &PlanOptions::default()).map_err(|e| e.to_string())?;
    plan.execute(&new_batch(n), &plan.default_parameters())
        .map_err(|e| e.to_string())
}

/// The first non-finite output value, as "output[sample] = value".
fn first_non_finite(out: &OutputBatch) -> Option<String> {
    for (k, name) in out.names().iter().enumerate() {
        for i in 0..out.len() {
            let v = out.value(k, i);
            if !v.is_finite() {
                return Some(format!("{name}[{i}] = {v}"));
            }
        }
    }
    None
}

/// Builds and evaluates one case over `n` samples; `Err` describes a failure.
fn check_finite(
    t: &NodeType,
    g: Option<SocketType>,
    inputs: &BTreeMap<String, J>,
    n: usize,
) -> Result<(), String> {
    let graph = build(t, g, inputs.clone())?;
    let out = evaluate(&graph, n)?;
    if out.len() != n || out.names().len() != t.outputs().len() {
        return Err(format!(
            "expected {} outputs × {n} samples, got {} × {}",
            t.outputs().len(),
            out.names().len(),
            out.len()
        ));
    }
    match first_non_finite(&out) {
        None => Ok(()),
        Some(bad) => Err(format!("non-finite output {bad}")),
    }
}

/// FNV-1a of `key`: a seed stable across runs and platforms.
fn seed(key: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in key.bytes() {
        h = (h ^ b as u64).wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// A runner with a fixed seed per (test, node, type), unless PROPTEST_RNG_SEED picks one.
fn runner(cases: u32, key: &str) -> TestRunner {
    let mut config = Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    };
    if matches!(config.rng_seed, RngSeed::Random) {
        config.rng_seed = RngSeed::Fixed(seed(key));
    }
    TestRunner::new(config)
}

/// A float over `r`: mostly uniform, sometimes exactly an end of the range.
fn float_in(r: Range) -> BoxedStrategy<f32> {
    if r.min == r.max {
        return Just(r.min).boxed();
    }
    prop_oneof![
        14 => r.min..=r.max,
        1 => Just(r.min),
        1 => Just(r.max),
    ]
    .boxed()
}

/// A random JSON literal for input `decl` of concrete type `ty`.
fn input_strategy(decl: &InputDecl, ty: SocketType) -> BoxedStrategy<J> {
    if !decl.choices.is_empty() {
        let choices = decl.choices;
        return (0..choices.len())
            .prop_map(move |i| J::String(choices[i].to_owned()))
            .boxed();
    }
    match ty {
        SocketType::Bool => any::<bool>().prop_map(J::Bool).boxed(),
        SocketType::Int => {
            let r = sample_range(decl);
            let (lo, hi) = (r.min.ceil() as i32, r.max.floor() as i32);
            (lo..=hi).prop_map(|i| json!(i)).boxed()
        }
        _ => {
            let r = sample_range(decl);
            proptest::collection::vec(float_in(r), ty.width())
                .prop_map(move |xs| {
                    let mut it = xs.into_iter();
                    literal(ty, || it.next().unwrap_or(0.0))
                })
                .boxed()
        }
    }
}

/// Random inputs (every input set) for a node with `T = g`.
fn inputs_strategy(t: &NodeType, g: Option<SocketType>) -> BoxedStrategy<BTreeMap<String, J>> {
    let names: Vec<String> = t.inputs().iter().map(|i| i.name.to_owned()).collect();
    let parts: Vec<BoxedStrategy<J>> = t
        .inputs()
        .iter()
        .map(|d| input_strategy(d, port_type(d, g)))
        .collect();
    parts
        .prop_map(move |values| names.iter().cloned().zip(values).collect())
        .boxed()
}

/// Runs `check` over random inputs for every (node type, generic type); returns failures.
fn for_each_node_random(
    cases: u32,
    label: &str,
    check: impl Fn(&NodeType, Option<SocketType>, &BTreeMap<String, J>) -> Result<(), String>,
) -> Vec<String> {
    let mut failures = Vec::new();
    for t in registry().types() {
        for g in type_variants(t) {
            let key = format!("{label}/{}/{}", t.name(), t_name(g));
            let mut r = runner(cases, &key);
            let result = r.run(&inputs_strategy(t, g), |inputs| {
                check(t, g, &inputs).map_err(TestCaseError::fail)
            });
            match result {
                Ok(()) => {}
                Err(TestError::Fail(why, inputs)) => failures.push(format!(
                    "{} (T = {}): {why}\n    minimal inputs: {}",
                    t.name(),
                    t_name(g),
                    J::Object(inputs.into_iter().collect())
                )),
                Err(e) => failures.push(format!("{} (T = {}): {e}", t.name(), t_name(g))),
            }
        }
    }
    failures
}

fn assert_no_failures(what: &str, failures: &[String]) {
    assert!(
        failures.is_empty(),
        "{what}: {} failure(s):\n{}",
        failures.len(),
        failures.join("\n")
    );
}

// ---------------------------------------------------------------------------------------
// 1. Stability: random in-range inputs give finite outputs
// ---------------------------------------------------------------------------------------

#[test]
fn random_in_range_inputs_give_finite_outputs() {
    let failures = for_each_node_random(STABILITY_CASES, "stability", |t, g, inputs| {
        check_finite(t, g, inputs, 8)
    });
    assert_no_failures("stability over declared ranges", &failures);
}

/// The values an input is tried at in the exhaustive edge test: the ends of its soft and
/// hard ranges, and 0 when inside them.
fn edge_values(decl: &InputDecl, ty: SocketType) -> Vec<J> {
    if !decl.choices.is_empty() {
        return decl
            .choices
            .iter()
            .map(|c| J::String((*c).to_owned()))
            .collect();
    }
    if ty == SocketType::Bool {
        return vec![J::Bool(false), J::Bool(true)];
    }
    let mut xs: Vec<f32> = Vec::new();
    let ranges: Vec<Range> = [decl.soft, decl.hard].into_iter().flatten().collect();
    let ranges = if ranges.is_empty() {
        vec![sample_range(decl)]
    } else {
        ranges
    };
    for r in &ranges {
        xs.extend([r.min, r.max]);
    }
    let outer = decl.hard.unwrap_or(ranges[0]);
    if (outer.min..=outer.max).contains(&0.0) {
        xs.push(0.0);
    }
    if ty == SocketType::Int {
        xs = xs.iter().map(|x| x.round()).collect();
    }
    xs.sort_by(f32::total_cmp);
    xs.dedup();
    xs.into_iter()
        .map(|x| {
            if ty == SocketType::Int {
                json!(x as i32)
            } else {
                literal(ty, || x)
            }
        })
        .collect()
}

/// Every combination of range ends (soft and hard) and 0, vectors splatted: where stable
/// formulas usually break (g → ±1, 0^negative, grazing angles).
#[test]
fn range_edges_give_finite_outputs() {
    const MAX_COMBINATIONS: usize = 4096;
    let mut failures = Vec::new();
    let mut evaluated = 0;
    for t in registry().types() {
        for g in type_variants(t) {
            let per_input: Vec<Vec<J>> = t
                .inputs()
                .iter()
                .map(|d| edge_values(d, port_type(d, g)))
                .collect();
            // Every combination, or evenly spaced ones when there are too many.
            // Saturating: a node of 70 inputs has more combinations than a u128 counts.
            let total: u128 = per_input
                .iter()
                .fold(1u128, |p, v| p.saturating_mul(v.len() as u128));
            let picks = total.min(MAX_COMBINATIONS as u128);
            for i in 0..picks {
                let mut idx = i
                    .checked_mul(total)
                    .map_or(i * (total / picks), |p| p / picks);
                let mut inputs = BTreeMap::new();
                for (d, values) in t.inputs().iter().zip(&per_input) {
                    let n = values.len() as u128;
                    inputs.insert(d.name.to_owned(), values[(idx % n) as usize].clone());
                    idx /= n;
                }
                evaluated += 1;
                if let Err(e) = check_finite(t, g, &inputs, 2) {
                    failures.push(format!(
                        "{} (T = {}): {e}\n    inputs: {}",
                        t.name(),
                        t_name(g),
                        J::Object(inputs.into_iter().collect())
                    ));
                }
            }
        }
    }
    assert!(evaluated > registry().types().len(), "nothing evaluated");
    assert_no_failures("stability at range edges", &failures);
}

// ---------------------------------------------------------------------------------------
// 2. Hard cases
// ---------------------------------------------------------------------------------------

/// The inputs of a hard case for `T = g`: the case's values, and every generic input's
/// default written out so that its shape selects `T`.
fn hard_case_inputs(
    t: &NodeType,
    g: Option<SocketType>,
    values: &[(&'static str, Value)],
) -> Result<BTreeMap<String, J>, String> {
    let mut inputs = BTreeMap::new();
    for (k, d) in t.inputs().iter().enumerate() {
        let ty = port_type(d, g);
        if let Some((_, v)) = values.iter().find(|(n, _)| *n == d.name) {
            inputs.insert(d.name.to_owned(), value_json(d, ty, *v)?);
        } else if d.ty == PortType::Generic {
            let v = t.default_for(k, g.unwrap_or(SocketType::Float));
            inputs.insert(d.name.to_owned(), value_json(d, ty, v)?);
        }
    }
    for (name, _) in values {
        if t.input_index(name).is_none() {
            return Err(format!("sets unknown input {name}"));
        }
    }
    Ok(inputs)
}

#[test]
fn hard_cases_give_finite_outputs() {
    let mut failures = Vec::new();
    let mut cases = 0;
    for t in registry().types() {
        for case in t.hard_cases() {
            for g in type_variants(t) {
                cases += 1;
                let result = hard_case_inputs(t, g, &case.values).and_then(|inputs| {
                    check_finite(t, g, &inputs, 4).map_err(|e| format!("{e}; inputs {inputs:?}"))
                });
                if let Err(e) = result {
                    failures.push(format!(
                        "{} (T = {}) hard case '{}': {e}",
                        t.name(),
                        t_name(g),
                        case.why
                    ));
                }
            }
        }
    }
    assert!(cases > 0, "the registry declares no hard cases");
    assert_no_failures("hard cases", &failures);
}

#[test]
fn every_node_is_stable_at_its_defaults() {
    let mut failures = Vec::new();
    for t in registry().types() {
        for g in type_variants(t) {
            let result =
                hard_case_inputs(t, g, &[]).and_then(|inputs| check_finite(t, g, &inputs, 3));
            if let Err(e) = result {
                failures.push(format!("{} (T = {}): {e}", t.name(), t_name(g)));
            }
        }
    }
    assert_no_failures("defaults", &failures);
}

// ---------------------------------------------------------------------------------------
// 3. Documentation and declarations
// ---------------------------------------------------------------------------------------

#[test]
fn registry_check_is_clean() {
    let problems = registry().check();
    assert!(problems.is_empty(), "{problems:#?}");
}

#[test]
fn node_type_names_are_unique_and_all_registered() {
    // `Registry::register` silently replaces a type of the same name, so look at the
    // library's list itself.
    let library = matgraph::nodes::all();
    let mut seen = BTreeSet::new();
    let dups: Vec<&str> = library
        .iter()
        .map(|t| t.name())
        .filter(|n| !seen.insert(*n))
        .collect();
    assert!(dups.is_empty(), "duplicate node type names: {dups:?}");
    let registered: Vec<&str> = registry().types().iter().map(|t| t.name()).collect();
    let listed: Vec<&str> = library.iter().map(|t| t.name()).collect();
    assert_eq!(
        registered, listed,
        "the builtin registry differs from nodes::all()"
    );
    for name in registered {
        assert_eq!(registry().get(name).map(|t| t.name()), Some(name));
    }
}

#[test]
fn every_node_type_is_documented() {
    let mut problems = Vec::new();
    for t in registry().types() {
        let n = t.name();
        if !is_snake_case(n) {
            problems.push(format!("{n}: type name is not snake_case"));
        }
        if t.summary().trim().is_empty() {
            problems.push(format!("{n}: empty summary"));
        }
        if t.source_doc().trim().is_empty() {
            problems.push(format!("{n}: empty source doc"));
        }
        if t.variants().is_empty() {
            problems.push(format!("{n}: no compute"));
        }
        if t.outputs().is_empty() {
            problems.push(format!("{n}: no outputs"));
        }
        let mut ports = BTreeSet::new();
        for d in t.inputs() {
            if !ports.insert(("in", d.name)) {
                problems.push(format!("{n}.{}: duplicate input", d.name));
            }
        }
        for o in t.outputs() {
            if !ports.insert(("out", o.name)) {
                problems.push(format!("{n}.{}: duplicate output", o.name));
            }
            if !is_snake_case(o.name) {
                problems.push(format!("{n}.{}: output name is not snake_case", o.name));
            }
            if o.doc.trim().is_empty() {
                problems.push(format!("{n}.{}: output has no doc", o.name));
            }
        }
        for (k, d) in t.inputs().iter().enumerate() {
            let p = format!("{n}.{}", d.name);
            if !is_snake_case(d.name) {
                problems.push(format!("{p}: input name is not snake_case"));
            }
            if d.doc.trim().is_empty() {
                problems.push(format!("{p}: input has no doc"));
            }
            for (what, r) in [("soft", d.soft), ("hard", d.hard)] {
                let Some(r) = r else { continue };
                if !(r.min.is_finite() && r.max.is_finite() && r.min <= r.max) {
                    problems.push(format!("{p}: bad {what} range [{}, {}]", r.min, r.max));
                }
                if !r.contains(&d.default) {
                    problems.push(format!(
                        "{p}: default {} outside {what} range [{}, {}]",
                        d.default, r.min, r.max
                    ));
                }
            }
            if let (Some(s), Some(h)) = (d.soft, d.hard)
                && (s.min < h.min || s.max > h.max)
            {
                problems.push(format!(
                    "{p}: soft range [{}, {}] leaves hard range [{}, {}]",
                    s.min, s.max, h.min, h.max
                ));
            }
            if !d.choices.is_empty() {
                let unique: BTreeSet<_> = d.choices.iter().collect();
                if unique.len() != d.choices.len() || d.choices.iter().any(|c| c.is_empty()) {
                    problems.push(format!("{p}: choices must be unique and non-empty"));
                }
                let i = d.default.as_i32();
                if d.default.ty() != SocketType::Int || i < 0 || i as usize >= d.choices.len() {
                    problems.push(format!("{p}: default {} is not a choice", d.default));
                }
            }
            // The default must be usable for every accepted T.
            for g in type_variants(t) {
                let ty = port_type(d, g);
                let v = t.default_for(k, g.unwrap_or(SocketType::Float));
                if v.ty() != ty || !v.is_finite() {
                    problems.push(format!(
                        "{p}: default {v} is not a finite {ty} for T = {}",
                        t_name(g)
                    ));
                }
            }
        }
        for case in t.hard_cases() {
            if case.why.trim().is_empty() {
                problems.push(format!("{n}: hard case without a reason"));
            }
            if case.values.is_empty() {
                problems.push(format!("{n}: hard case '{}' sets no input", case.why));
            }
        }
    }
    assert!(problems.is_empty(), "{problems:#?}");
}

// ---------------------------------------------------------------------------------------
// 4. Determinism
// ---------------------------------------------------------------------------------------

/// Bit equality, with every NaN equal to every NaN.
fn same_bits(a: f32, b: f32) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

fn compare_batches(a: &OutputBatch, b: &OutputBatch) -> Result<(), String> {
    if a.names() != b.names() || a.len() != b.len() {
        return Err(format!("shapes differ: {:?} vs {:?}", a.names(), b.names()));
    }
    for k in 0..a.names().len() {
        for (j, (x, y)) in a.planar(k).iter().zip(b.planar(k)).enumerate() {
            if !same_bits(*x, *y) {
                return Err(format!("{}: lane {j}: {x:?} vs {y:?}", a.names()[k]));
            }
        }
    }
    Ok(())
}

#[test]
fn evaluation_is_bit_reproducible() {
    let failures = for_each_node_random(8, "determinism", |t, g, inputs| {
        // Two independent builds and compiles, and the same plan run twice.
        let g1 = build(t, g, inputs.clone())?;
        let g2 = build(t, g, inputs.clone())?;
        let p1 = Plan::compile(&g1, &PlanOptions::default()).map_err(|e| e.to_string())?;
        let p2 = Plan::compile(&g2, &PlanOptions::default()).map_err(|e| e.to_string())?;
        let batch = new_batch(5);
        let run = |p: &Plan| {
            p.execute(&batch, &p.default_parameters())
                .map_err(|e| e.to_string())
        };
        let a = run(&p1)?;
        compare_batches(&a, &run(&p1)?)?;
        compare_batches(&a, &run(&p2)?)?;
        // Every sample of the batch agrees with a one-sample evaluation.
        let one = p1
            .execute(&new_batch(1), &p1.default_parameters())
            .map_err(|e| e.to_string())?;
        for k in 0..a.names().len() {
            for i in 0..a.len() {
                let (x, y) = (a.value(k, i), one.value(k, 0));
                if !x
                    .lanes()
                    .iter()
                    .zip(y.lanes())
                    .all(|(p, q)| same_bits(*p, *q))
                {
                    return Err(format!(
                        "{}[{i}] = {x} but one sample gives {y}",
                        a.names()[k]
                    ));
                }
            }
        }
        Ok(())
    });
    assert_no_failures("bit reproducibility", &failures);
}

/// Tiny deterministic generator for attribute columns.
struct XorShift(u64);

impl XorShift {
    fn next_f32(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
    fn in_range(&mut self, r: Range) -> f32 {
        r.min + (r.max - r.min) * self.next_f32()
    }
}

/// Where a per-sample value of type `ty` comes from in [`linked_graph`]: the geometry's
/// view (vec3) directly, or built from its components.
fn varying_source(ty: SocketType) -> Option<&'static str> {
    match ty {
        SocketType::Float => Some("sv.x"),
        SocketType::Vec2 => Some("c.vec2"),
        SocketType::Vec3 => Some("geo.view"),
        SocketType::Vec4 => Some("c.vec4"),
        SocketType::Color => Some("c.color"),
        SocketType::Int | SocketType::Bool => None,
    }
}

/// A graph where input `k` of node `t` (with `T = g`) is linked from per-sample geometry
/// (`view`, and `position.x` for a fourth component); the other inputs keep their defaults.
fn linked_graph(t: &NodeType, g: Option<SocketType>, k: usize) -> Result<Graph, String> {
    let d = &t.inputs()[k];
    let src = varying_source(port_type(d, g)).ok_or("input cannot be linked")?;
    let mut node = json!({
        "id": "n",
        "type": t.name(),
        "inputs": { d.name: { "link": src } },
    });
    if let Some(g) = g {
        node["data_type"] = json!(g.name());
    }
    if t.evaluation() == Evaluation::Texture {
        node["texture"] = json!(TEST_TEXTURE);
    }
    let outputs: Vec<J> = t
        .outputs()
        .iter()
        .map(|o| json!({ "name": o.name, "from": format!("n.{}", o.name) }))
        .collect();
    let doc = json!({
        "version": 2,
        "name": format!("linked_{}", t.name()),
        "nodes": [
            { "id": "geo", "type": "geometry" },
            { "id": "sv", "type": "split", "inputs": { "v": { "link": "geo.view" } } },
            { "id": "sp", "type": "split", "inputs": { "v": { "link": "geo.position" } } },
            { "id": "c", "type": "combine", "inputs": {
                "x": { "link": "sv.x" }, "y": { "link": "sv.y" },
                "z": { "link": "sv.z" }, "w": { "link": "sp.x" } } },
            node,
        ],
        "outputs": outputs,
    });
    Graph::from_json(&doc.to_string(), registry()).map_err(|e| format!("graph rejected: {e:?}"))
}

/// N samples over several tiles (256 each) with a partial last tile.
const BATCH: usize = 1000;

/// The outputs of sample `i` as bits, for comparing and counting distinct results.
fn sample_bits(out: &OutputBatch, i: usize) -> Vec<[u32; 4]> {
    (0..out.names().len())
        .map(|o| out.value(o, i).raw().map(f32::to_bits))
        .collect()
}

/// Inputs whose link from per-sample geometry has no effect by the node's definition, with
/// why; the test links the next input instead.
const NO_EFFECT_ALONE: &[(&str, &str, &str)] = &[
    ("bump", "height", BUMP_TILT),
    ("bump", "distance", BUMP_TILT),
    ("bump", "strength", BUMP_TILT),
];

/// Why the bump's height, distance and strength have no effect here.
const BUMP_TILT: &str = "they act through the tilt, which needs the position's derivatives: \
     the test's batch has none (position_dx = position_dy = 0), so the node returns its normal \
     (its `normal` input is linked instead)";

/// Batch evaluation equals one-sample evaluations, for every node type (and `T`) with an
/// input that can be linked from per-sample geometry: tiles never mix samples, and the
/// partial last tile is right. The batch's outputs must also be finite (the per-sample
/// path of the stability property) and must vary from sample to sample.
#[test]
fn batch_equals_one_sample_evaluations() {
    let mut failures = Vec::new();
    let mut checked = 0;
    for t in registry().types() {
        // A parameter's value is a literal (links are rejected), so it never varies.
        if t.evaluation() == Evaluation::Parameter {
            continue;
        }
        for g in type_variants(t) {
            let Some(k) = t.inputs().iter().position(|d| {
                varying_source(port_type(d, g)).is_some()
                    && !NO_EFFECT_ALONE
                        .iter()
                        .any(|&(ty, input, _)| ty == t.name() && input == d.name)
            }) else {
                continue;
            };
            let key = format!("{}/{}", t.name(), t_name(g));
            let result = (|| -> Result<(), String> {
                let graph = linked_graph(t, g, k)?;
                let plan =
                    Plan::compile(&graph, &PlanOptions::default()).map_err(|e| e.to_string())?;
                // A reroute is no step: its consumers read its source (which is per sample).
                if plan.stats().per_sample_steps == 0 && t.name() != matgraph::group::REROUTE {
                    return Err("the linked node was not evaluated per sample".into());
                }
                let r = sample_range(&t.inputs()[k]);
                let mut rng = XorShift(seed(&key) | 1);
                let view: Vec<[f32; 3]> = (0..BATCH)
                    .map(|_| [rng.in_range(r), rng.in_range(r), rng.in_range(r)])
                    .collect();
                let position: Vec<[f32; 3]> =
                    (0..BATCH).map(|_| [rng.in_range(r), 0.0, 0.0]).collect();
                let mut batch = new_batch(BATCH);
                batch
                    .set_values(Attribute::View, &view)
                    .map_err(|e| e.to_string())?;
                batch
                    .set_values(Attribute::Position, &position)
                    .map_err(|e| e.to_string())?;
                let params = plan.default_parameters();
                let all = plan.execute(&batch, &params).map_err(|e| e.to_string())?;
                if all.len() != BATCH {
                    return Err(format!("{} samples back for {BATCH}", all.len()));
                }
                if let Some(bad) = first_non_finite(&all) {
                    return Err(format!("non-finite per-sample output {bad}"));
                }
                let distinct: BTreeSet<_> = (0..BATCH).map(|i| sample_bits(&all, i)).collect();
                if distinct.len() < 2 {
                    return Err("every sample gave the same outputs: the link had no effect".into());
                }
                for i in 0..BATCH {
                    let mut one = new_batch(1);
                    one.set_values(Attribute::View, &view[i..=i])
                        .map_err(|e| e.to_string())?;
                    one.set_values(Attribute::Position, &position[i..=i])
                        .map_err(|e| e.to_string())?;
                    let single = plan.execute(&one, &params).map_err(|e| e.to_string())?;
                    for o in 0..all.names().len() {
                        let (x, y) = (all.value(o, i), single.value(o, 0));
                        if !x
                            .lanes()
                            .iter()
                            .zip(y.lanes())
                            .all(|(p, q)| same_bits(*p, *q))
                        {
                            return Err(format!(
                                "{}[{i}]: batch gives {x}, one sample gives {y} (view {:?})",
                                all.names()[o],
                                view[i]
                            ));
                        }
                    }
                }
                Ok(())
            })();
            checked += 1;
            if let Err(e) = result {
                failures.push(format!("{key}, input {} linked: {e}", t.inputs()[k].name));
            }
        }
    }
    assert!(checked >= 5, "only {checked} node types could be linked");
    assert_no_failures("batch vs one-sample evaluation", &failures);
}

// ---------------------------------------------------------------------------------------
// 5. Plan compiler
// ---------------------------------------------------------------------------------------

fn graph(text: &str) -> Graph {
    Graph::from_json(text, registry()).unwrap_or_else(|e| panic!("{e:?}\n{text}"))
}

fn close(a: f32, b: f32, tol: f32) -> bool {
    (a - b).abs() <= tol * (1.0 + b.abs())
}

#[test]
fn dead_nodes_are_dropped() {
    let g = graph(
        r#"{
          "version": 1, "name": "dead",
          "nodes": [
            { "id": "geo", "type": "geometry" },
            { "id": "live", "type": "mul", "inputs": { "a": { "link": "geo.view" }, "b": 2.0 } },
            { "id": "dead1", "type": "exp", "inputs": { "x": { "link": "geo.position" } } },
            { "id": "dead2", "type": "add", "inputs": { "a": { "link": "dead1.result" }, "b": { "link": "live.result" } } },
            { "id": "dead3", "type": "hg_phase", "inputs": { "g": 0.3 } }
          ],
          "outputs": [ { "name": "out", "from": "live.result" } ]
        }"#,
    );
    let plan = Plan::compile(&g, &PlanOptions::default()).unwrap();
    let s = plan.stats();
    assert_eq!(s.graph_nodes, 5);
    assert_eq!(s.live_nodes, 2, "{s:?}");
    assert_eq!(s.per_sample_steps, 1, "{s:?}");
    assert_eq!(s.folded, 0, "{s:?}");
    assert!(plan.attributes().contains(&Attribute::View));
    // Exactly [View] once unread geometry outputs are dropped: see
    // bug_plan_attributes_lists_unread_geometry_outputs.

    // Asking for the dead branch brings it back to life.
    let plan = Plan::compile(
        &g,
        &PlanOptions {
            outputs: vec!["dead2.result".into()],
            ..PlanOptions::default()
        },
    )
    .unwrap();
    assert_eq!(plan.stats().live_nodes, 4, "{:?}", plan.stats());
    assert!(
        plan.attributes().contains(&Attribute::Position)
            && plan.attributes().contains(&Attribute::View),
        "{:?}",
        plan.attributes()
    );
    assert_eq!(plan.stats().per_sample_steps, 3, "{:?}", plan.stats());

    // The live output is right: 2 · view.
    let mut batch = new_batch(3);
    batch
        .set_values(
            Attribute::View,
            &[[1.0, 2.0, 3.0], [-0.5, 0.0, 0.25], [0.0, 1.0, 0.0]],
        )
        .unwrap();
    let plan = Plan::compile(&g, &PlanOptions::default()).unwrap();
    let out = plan.execute(&batch, &plan.default_parameters()).unwrap();
    assert_eq!(out.value(0, 0), Value::vec3([2.0, 4.0, 6.0]));
    assert_eq!(out.value(0, 1), Value::vec3([-1.0, 0.0, 0.5]));
}

#[test]
fn literal_only_nodes_are_folded() {
    let g = graph(
        r#"{
          "version": 1, "name": "fold",
          "nodes": [
            { "id": "a", "type": "add", "inputs": { "a": 1.5, "b": 2.25 } },
            { "id": "b", "type": "mul", "inputs": { "a": { "link": "a.result" }, "b": 2.0 } },
            { "id": "f", "type": "fresnel_dielectric", "inputs": { "cos_theta": 1.0, "ior_inside": 1.5 } }
          ],
          "outputs": [
            { "name": "x", "from": "b.result" },
            { "name": "r", "from": "f.reflectance" }
          ]
        }"#,
    );
    let plan = Plan::compile(&g, &PlanOptions::default()).unwrap();
    let s = plan.stats();
    assert_eq!(s.live_nodes, 3, "{s:?}");
    assert_eq!(s.folded, 3, "{s:?}");
    assert_eq!(s.hoisted, 0, "{s:?}");
    assert_eq!(s.per_sample_steps, 0, "{s:?}");
    // Folded to constants at compile time, with the right values.
    match plan.outputs()[0].operand {
        Operand::Const(v) => assert_eq!(v, Value::float(7.5)),
        other => panic!("b.result not folded: {other:?}"),
    }
    match plan.outputs()[1].operand {
        // ((1 - 1.5) / (1 + 1.5))^2 = 0.04
        Operand::Const(v) => assert!(close(v.as_f32(), 0.04, 1e-5), "{v}"),
        other => panic!("f.reflectance not folded: {other:?}"),
    }
    let out = plan
        .execute(&new_batch(300), &plan.default_parameters())
        .unwrap();
    assert!((0..300).all(|i| out.value(0, i) == Value::float(7.5)));
}

const HOIST_GRAPH: &str = r#"{
  "version": 1, "name": "hoist",
  "nodes": [
    { "id": "geo", "type": "geometry" },
    { "id": "gain", "type": "parameter", "inputs": { "value": 2.0 } },
    { "id": "tm", "type": "time" },
    { "id": "h", "type": "mul", "inputs": { "a": { "link": "gain.value" }, "b": { "link": "tm.time" } } },
    { "id": "v", "type": "mul", "inputs": { "a": { "link": "h.result" }, "b": { "link": "geo.uv" } } }
  ],
  "outputs": [
    { "name": "h", "from": "h.result" },
    { "name": "v", "from": "v.result" }
  ],
  "parameters": [ { "name": "gain", "node": "gain", "doc": "Scale." } ]
}"#;

#[test]
fn parameter_and_time_nodes_are_hoisted_and_overridable() {
    let g = graph(HOIST_GRAPH);
    let plan = Plan::compile(&g, &PlanOptions::default()).unwrap();
    let s = plan.stats();
    assert_eq!(s.live_nodes, 5, "{s:?}");
    assert_eq!(s.hoisted, 1, "{s:?}");
    assert_eq!(s.folded, 0, "{s:?}");
    assert_eq!(s.per_sample_steps, 1, "only v runs per sample: {s:?}");
    assert!(matches!(plan.outputs()[0].operand, Operand::Uniform(_)));
    assert!(matches!(plan.outputs()[1].operand, Operand::Reg(_)));
    assert!(plan.uses_time());

    let mut batch = new_batch(2);
    batch
        .set_values(Attribute::Uv, &[[1.0, 0.5, 0.0], [-2.0, 0.25, 0.0]])
        .unwrap();
    batch.set_time(3.0);
    let mut params: ParamValues = plan.default_parameters();
    assert_eq!(params.get("gain"), Some(Value::float(2.0)));
    let out = plan.execute(&batch, &params).unwrap();
    assert_eq!(out.value(0, 0), Value::float(6.0));
    assert_eq!(out.value(1, 1), Value::vec2([-12.0, 1.5]));

    // Same plan, new parameter value: no recompilation.
    params.set("gain", Value::float(5.0)).unwrap();
    let out = plan.execute(&batch, &params).unwrap();
    assert_eq!(out.value(0, 1), Value::float(15.0));
    assert_eq!(out.value(1, 0), Value::vec2([15.0, 7.5]));

    // And a new time.
    batch.set_time(-0.5);
    let out = plan.execute(&batch, &params).unwrap();
    assert_eq!(out.value(0, 0), Value::float(-2.5));

    // Parameter errors name the parameter and suggest.
    assert!(matches!(
        params.set("gian", Value::float(1.0)),
        Err(EvalError::UnknownParameter { suggestion: Some(ref s), .. }) if s == "gain"
    ));
    assert!(matches!(
        params.set(
            "gain",
            Value::boolean(true).convert(SocketType::Vec2).unwrap()
        ),
        Err(EvalError::ParameterType { .. })
    ));

    // Baking folds the parameter instead.
    let baked = Plan::compile(
        &g,
        &PlanOptions {
            bake_parameters: true,
            ..PlanOptions::default()
        },
    )
    .unwrap();
    assert_eq!(baked.stats().folded, 1, "{:?}", baked.stats());
    assert_eq!(baked.stats().hoisted, 1, "{:?}", baked.stats());
}

/// A chain of `n` `add` nodes, each adding the geometry's view to the previous result.
fn chain(n: usize) -> String {
    let mut nodes = vec![
        json!({ "id": "geo", "type": "geometry" }),
        json!({ "id": "n1", "type": "add", "inputs": { "a": { "link": "geo.view" }, "b": { "link": "geo.view" } } }),
    ];
    for k in 2..=n {
        nodes.push(json!({
            "id": format!("n{k}"),
            "type": "add",
            "inputs": { "a": { "link": format!("n{}.result", k - 1) }, "b": { "link": "geo.view" } },
        }));
    }
    json!({
        "version": 1,
        "name": "chain",
        "nodes": nodes,
        "outputs": [ { "name": "out", "from": format!("n{n}.result") } ],
    })
    .to_string()
}

#[test]
fn registers_are_reused_along_a_chain() {
    const N: usize = 30;
    let g = graph(&chain(N));
    let plan = Plan::compile(&g, &PlanOptions::default()).unwrap();
    let s = plan.stats();
    assert_eq!(s.live_nodes, N + 1, "{s:?}");
    assert_eq!(s.per_sample_steps, N, "{s:?}");
    // The attribute registers, the output, and two that alternate along the chain.
    let limit = plan.attributes().len() + 3;
    assert!(
        s.registers <= limit && s.registers < N / 3,
        "{N} values in {} registers (limit {limit}): {s:?}",
        s.registers
    );

    // Reuse must not clobber live values: the result is (N + 1) · view, across tiles.
    let mut rng = XorShift(7);
    let view: Vec<[f32; 3]> = (0..BATCH)
        .map(|_| [rng.next_f32() * 2.0 - 1.0, rng.next_f32(), -rng.next_f32()])
        .collect();
    let mut batch = new_batch(BATCH);
    batch.set_values(Attribute::View, &view).unwrap();
    let out = plan.execute(&batch, &plan.default_parameters()).unwrap();
    for (i, v) in view.iter().enumerate() {
        let got = out.value(0, i);
        for (c, (&x, &vc)) in got.lanes().iter().zip(v).enumerate() {
            let want = (N + 1) as f32 * vc;
            assert!(
                close(x, want, 1e-5),
                "sample {i} component {c}: {x} vs {want}"
            );
        }
    }
}

#[test]
fn outputs_can_be_requested_by_node_id() {
    let g = graph(&chain(5));
    let plan = Plan::compile(
        &g,
        &PlanOptions {
            outputs: vec!["n3.result".into(), "out".into()],
            ..PlanOptions::default()
        },
    )
    .unwrap();
    assert_eq!(plan.outputs()[0].name, "n3.result");
    assert_eq!(plan.outputs()[0].ty, SocketType::Vec3);
    let mut batch = new_batch(1);
    batch
        .set_values(Attribute::View, &[[1.0, -2.0, 0.5]])
        .unwrap();
    let out = plan.execute(&batch, &plan.default_parameters()).unwrap();
    assert_eq!(out.names(), &["n3.result".to_owned(), "out".to_owned()]);
    assert_eq!(out.value(0, 0), Value::vec3([4.0, -8.0, 2.0]));
    assert_eq!(out.value(1, 0), Value::vec3([6.0, -12.0, 3.0]));

    // Only what reaches n3 is live.
    let only = Plan::compile(
        &g,
        &PlanOptions {
            outputs: vec!["n3.result".into()],
            ..PlanOptions::default()
        },
    )
    .unwrap();
    assert_eq!(only.stats().live_nodes, 4, "{:?}", only.stats());

    // Unknown outputs error with a suggestion.
    let err = Plan::compile(
        &g,
        &PlanOptions {
            outputs: vec!["n3.reslt".into()],
            ..PlanOptions::default()
        },
    )
    .err()
    .expect("unknown output accepted");
    assert_eq!(
        err,
        EvalError::UnknownOutput {
            name: "n3.reslt".into(),
            suggestion: Some("n3.result".into()),
        }
    );
    assert!(
        err.to_string().contains("did you mean 'n3.result'"),
        "{err}"
    );
    let err = Plan::compile(
        &g,
        &PlanOptions {
            outputs: vec!["zzzz.qqqq".into()],
            ..PlanOptions::default()
        },
    )
    .err()
    .expect("unknown output accepted");
    assert!(
        matches!(
            err,
            EvalError::UnknownOutput {
                suggestion: None,
                ..
            }
        ),
        "{err:?}"
    );
}

// ---------------------------------------------------------------------------------------
// Pass-through nodes
// ---------------------------------------------------------------------------------------

/// `constant` and `parameter` give back their value for every type they accept.
fn passes_through(type_name: &str) -> Vec<String> {
    let t = registry().get(type_name).expect("node type");
    let mut failures = Vec::new();
    for g in type_variants(t) {
        let ty = g.unwrap_or(SocketType::Float);
        let mut x = 0.25f32;
        let lit = literal(ty, || {
            x += 0.5;
            x
        });
        let want = Value::from_json(ty, &lit).unwrap();
        let inputs = BTreeMap::from([("value".to_owned(), lit)]);
        let got = build(t, g, inputs)
            .and_then(|gr| evaluate(&gr, 2))
            .map(|out| out.value(0, 1));
        match got {
            Ok(v) if v.lanes() == want.lanes() => {}
            other => failures.push(format!(
                "{type_name} (T = {ty}): want {want}, got {other:?}"
            )),
        }
    }
    failures
}

#[test]
fn constant_passes_its_value_through() {
    assert_no_failures("constant", &passes_through("constant"));
}

#[test]
fn parameter_passes_its_file_value_through() {
    // Unexposed parameters keep the file's value (they are not listed in `parameters`).
    assert_no_failures("parameter", &passes_through("parameter"));
}

// ---------------------------------------------------------------------------------------
// Regressions for bugs found by these tests.
// ---------------------------------------------------------------------------------------

fn single(type_name: &str, inputs: J) -> OutputBatch {
    let inputs: BTreeMap<String, J> = serde_json::from_value(inputs).unwrap();
    let g = Graph::single_node(registry(), type_name, inputs).unwrap();
    evaluate(&g, 1).unwrap()
}

#[test]
fn pow_is_total_and_finite_at_its_edges() {
    // Regression: pow(0, b < 0) was +inf inside the declared ranges. It is now defined as
    // 1 / 0^|b| through the safe divide (0); negative bases with integer exponents keep
    // their sign; fractional ones give 0; 0^0 = 1.
    for (a, b, want) in [
        (0.0f32, -4.0f32, 0.0f32),
        (0.0, -0.5, 0.0),
        (0.0, 0.0, 1.0),
        (0.0, 2.0, 0.0),
        (-2.0, 3.0, -8.0),
        (-2.0, 2.0, 4.0),
        (-2.0, -1.0, -0.5),
        (-2.0, 0.5, 0.0),
        (2.0, 0.5, std::f32::consts::SQRT_2),
    ] {
        let out = single("pow", json!({ "a": a, "b": b }));
        let r = out.value(0, 0).as_f32();
        assert!(
            (r - want).abs() <= 1e-6 * want.abs().max(1.0),
            "pow({a}, {b}) = {r}, want {want}"
        );
    }
}

/// Henyey–Greenstein in f64, `(1 − g²)/(4π (1 + g² − 2g c)^1.5)`, its base formed from the
/// exact identity `1 + g² − 2gc = (1 ∓ g)² ± 2g(1 ∓ c)` with non-negative terms (the textbook
/// sum loses 2e-6 relative in f64 at |g| = 1 − 2⁻¹⁷). |g| = 1, a delta, is evaluated at
/// 1 − 2⁻²⁴ as the node's doc states.
fn hg_reference(c: f64, g: f64) -> f64 {
    let h = 1.0 - 2f64.powi(-24);
    let g = if g.abs() >= 1.0 { g.signum() * h } else { g };
    let base = if g >= 0.0 {
        (1.0 - g).powi(2) + 2.0 * g * (1.0 - c)
    } else {
        (1.0 + g).powi(2) - 2.0 * g * (1.0 + c)
    };
    (1.0 - g) * (1.0 + g) / (4.0 * std::f64::consts::PI * base.powf(1.5))
}

/// Regression: hg_phase(-1, -1) was +inf and 23% low at g = -0.999 before the base was
/// evaluated through the symmetry p(cos, g) = p(-cos, -g).
#[test]
fn hg_phase_backward_peak_is_accurate() {
    for (c, g) in [
        (-1.0f32, -1.0f32),
        (-1.0, -0.9999),
        (-1.0, -0.999),
        (-1.0, -0.995),
        (-1.0, -(1.0 - 2f32.powi(-20))),
        (-0.2655, -(1.0 - 2f32.powi(-20))),
    ] {
        let out = single("hg_phase", json!({ "cos_theta": c, "g": g }));
        let p = out.value(0, 0).as_f32();
        let want = hg_reference(c as f64, g as f64);
        assert!(p.is_finite(), "hg_phase({c}, {g}) = {p}, want {want:e}");
        let rel = ((p as f64 - want) / want).abs();
        assert!(
            rel < 1e-5,
            "hg_phase({c}, {g}) = {p:e}, want {want:e} (rel. error {rel:.3e})"
        );
    }
}

#[test]
fn hg_phase_forward_peak_is_accurate() {
    // The counterpart of the bug above: the precision rewrite does work for g -> +1.
    for (c, g) in [
        (1.0f32, 1.0f32),
        (1.0, 0.9999),
        (1.0, 0.999),
        (1.0, 0.995),
        (0.5, 0.8),
        (1.0, 1.0 - 2f32.powi(-17)),
        (0.999, 1.0 - 2f32.powi(-17)),
    ] {
        let out = single("hg_phase", json!({ "cos_theta": c, "g": g }));
        let p = out.value(0, 0).as_f32();
        let want = hg_reference(c as f64, g as f64);
        let rel = ((p as f64 - want) / want).abs();
        assert!(
            rel < 1e-5,
            "hg_phase({c}, {g}) = {p:e}, want {want:e} (rel. error {rel:.3e})"
        );
    }
}

/// Regression: every geometry output used to get a register and a per-tile copy.
#[test]
fn plan_reads_only_the_attributes_it_uses() {
    let g = graph(
        r#"{
          "version": 1, "name": "view_only",
          "nodes": [
            { "id": "geo", "type": "geometry" },
            { "id": "m", "type": "mul", "inputs": { "a": { "link": "geo.view" }, "b": 2.0 } }
          ],
          "outputs": [ { "name": "out", "from": "m.result" } ]
        }"#,
    );
    let plan = Plan::compile(&g, &PlanOptions::default()).unwrap();
    assert_eq!(plan.attributes(), &[Attribute::View]);
    // view, the constant 2 and the output.
    assert!(plan.stats().registers <= 3, "{:?}", plan.stats());
}
