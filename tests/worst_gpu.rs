//! The node and graph parity suites against the least accurate GPU the WGSL specification
//! allows: the CPU executor in its worst-conformant-GPU mode (`matgraph::precision`), where
//! every builtin the kernels call is moved by the full error WGSL allows it (up, down, and a
//! seeded choice per call), subnormals are flushed and `cross` is contracted. Each result must
//! stay within the parity bound its node or graph has on a real GPU (tests/common/parity.rs),
//! so a pass here predicts a pass on every conformant GPU, not only on lavapipe, whose
//! builtins are as accurate as the CPU's. Needs no GPU.
//!
//! The mode exists only with the `worst-gpu` feature (it would cost every other build 60% of
//! the executor's speed): `cargo test --features worst-gpu --test worst_gpu`, as .ci/run does.
//! Without it the two suites print a `SKIPPED` line, and fail instead when
//! `MATGRAPH_REQUIRE_WORST_GPU` is set (.ci/run sets it for that run). The check that no node's
//! WGSL calls a builtin the mode does not model runs in every build.
//!
//! The mode is process-global, so the suites hold [`LOCK`] while they run. Run with
//! `-- --nocapture` to see each node's and graph's worst error.

mod common;

use common::parity::*;
use matgraph::precision::{self, Direction, Mode};
use matgraph::{OutputBatch, ParamValues, Registry, SocketType};
use std::fmt::Write as _;
use std::sync::{Mutex, MutexGuard};

/// Held by each suite while it switches the process-global mode.
static LOCK: Mutex<()> = Mutex::new(());

/// The lock on the mode, or `None` after printing why `test` is skipped: this build has no
/// worst-GPU mode (no `worst-gpu` feature). Panics instead when `MATGRAPH_REQUIRE_WORST_GPU`
/// is set, so the run that CI means to check never skips.
fn worst_gpu(test: &str) -> Option<MutexGuard<'static, ()>> {
    if !precision::AVAILABLE {
        let why =
            "built without the worst-gpu feature: cargo test --features worst-gpu --test worst_gpu";
        if std::env::var_os("MATGRAPH_REQUIRE_WORST_GPU").is_some() {
            panic!("{test}: MATGRAPH_REQUIRE_WORST_GPU is set and the mode is missing: {why}");
        }
        common::print_skip(test, why);
        return None;
    }
    Some(LOCK.lock().unwrap_or_else(|e| e.into_inner()))
}

/// The worst-GPU directions each suite runs: every result up, every result down, and a
/// seeded mix (which moves the two sides of a difference apart).
const DIRECTIONS: [Direction; 3] = [
    Direction::Up,
    Direction::Down,
    Direction::Mixed(0x5eed_0f32),
];

/// Runs `f` in `mode`, then returns to the exact mode.
fn in_mode<R>(mode: Mode, f: impl FnOnce() -> R) -> R {
    precision::set_mode(mode).expect("the suites run only where the mode is available");
    let r = f();
    precision::set_mode(Mode::Exact).unwrap();
    r
}

#[test]
fn every_node_type_stays_within_its_bound_on_a_worst_gpu() {
    let Some(_guard) = worst_gpu("every_node_type_stays_within_its_bound_on_a_worst_gpu") else {
        return;
    };
    let mut failures: Vec<String> = Vec::new();
    let mut table = String::new();
    let mut checked = 0;
    for NodeCase {
        t,
        generic,
        label,
        seed,
    } in node_cases()
    {
        let bound = worst_gpu_bound_for(t.name());
        // The seeds of tests/gpu/gpu_parity.rs: the same samples a GPU is checked at.
        let samples = node_samples(t, generic, seed);
        let exact = run_cpu(t, generic, &samples);
        let mut errors = Errors::default();
        let mut misses = Vec::new();
        for direction in DIRECTIONS {
            let worst = in_mode(Mode::WorstGpu(direction), || run_cpu(t, generic, &samples));
            let label = format!("{label} [{direction:?}]");
            compare_node_outputs(
                t,
                generic,
                &samples,
                (&exact, &worst),
                bound,
                &label,
                ("exact", "worst GPU"),
                &mut errors,
                &mut misses,
            );
        }
        failures.extend(misses);
        checked += 1;
        let _ = writeln!(
            table,
            "  {label:<32} {:>6} samples  max abs {:9.3e}  max rel {:9.3e}  {:7.1}% of bound  {:>4} by conditioning",
            samples.n,
            errors.max_abs,
            errors.max_rel,
            errors.worst * 100.0,
            errors.conditioned
        );
    }
    eprintln!("node parity on a worst conformant GPU (up, down, mixed):\n{table}");
    assert!(
        checked > 100,
        "only {checked} node types and generics checked"
    );
    assert!(
        failures.is_empty(),
        "{} misses on a worst conformant GPU:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// Executes `case`'s plan over its batch at `params` in `mode`.
fn execute(case: &GraphCase, params: &ParamValues, mode: Mode) -> OutputBatch {
    in_mode(mode, || case.plan.execute(&case.batch, params).unwrap())
}

#[test]
fn every_shipped_graph_stays_within_its_bound_on_a_worst_gpu() {
    let Some(_guard) = worst_gpu("every_shipped_graph_stays_within_its_bound_on_a_worst_gpu")
    else {
        return;
    };
    let mut failures = Vec::new();
    let mut cases = shipped_graph_cases();
    cases.push(monte_carlo_case("schlick"));
    cases.push(monte_carlo_case("exact"));
    assert!(cases.len() > 25, "{} graphs", cases.len());
    for case in &cases {
        let bound = graph_bound(&case.graph);
        // The file's values, then every float parameter scaled by 1.1, as on the GPU.
        for (round, params) in parameter_rounds(&case.plan).iter().enumerate() {
            let exact = execute(case, params, Mode::Exact);
            for direction in DIRECTIONS {
                let worst = execute(case, params, Mode::WorstGpu(direction));
                let (errors, bad) = compare_batches_within(&exact, &worst, bound);
                for (output, e) in errors {
                    eprintln!(
                        "  {:<44} round {round} {direction:>24?} {output:<14} max abs {:9.3e}  max rel {:9.3e}  {:7.1}% of bound",
                        case.name,
                        e.max_abs,
                        e.max_rel,
                        e.worst * 100.0
                    );
                }
                failures.extend(
                    bad.into_iter()
                        .map(|b| format!("{} round {round} [{direction:?}]: {b}", case.name)),
                );
            }
        }
    }
    assert!(
        failures.is_empty(),
        "graph parity on a worst conformant GPU failed:\n{}",
        failures.join("\n")
    );
}

/// WGSL builtins with an error the specification states that the worst-GPU mode does not
/// model (`matgraph::precision` holds the ones it does: exp, exp2, log, log2, pow, sqrt,
/// cross). A node whose WGSL called one of these would differ on a real GPU in a way
/// this suite cannot see: such a node computes the function itself (`mg_prec_sincos`), or the
/// builtin joins `matgraph::precision` and its CPU kernel calls it there.
const UNMODELLED: &[&str] = &[
    "sin",
    "cos",
    "tan",
    "asin",
    "acos",
    "atan",
    "atan2",
    "sinh",
    "cosh",
    "tanh",
    "asinh",
    "acosh",
    "atanh",
    "inverseSqrt",
    "length",
    "normalize",
    "distance",
    "refract",
    "faceForward",
    "smoothstep",
    "dpdx",
    "dpdy",
    "fwidth",
];

/// The builtins of [`UNMODELLED`] that `wgsl` calls (comments skipped; a call is a name not
/// preceded by `.` or an identifier character, then `(`).
fn unmodelled_calls(wgsl: &str) -> Vec<&'static str> {
    let mut found = Vec::new();
    for line in wgsl.lines() {
        let code = line.split("//").next().unwrap_or("");
        let bytes = code.as_bytes();
        let ident = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
        let mut i = 0;
        while i < bytes.len() {
            if !ident(bytes[i]) || (i > 0 && (ident(bytes[i - 1]) || bytes[i - 1] == b'.')) {
                i += 1;
                continue;
            }
            let start = i;
            while i < bytes.len() && ident(bytes[i]) {
                i += 1;
            }
            let name = &code[start..i];
            let call = code[i..].trim_start().starts_with('(');
            if let Some(b) = UNMODELLED.iter().find(|b| **b == name)
                && call
                && !found.contains(b)
            {
                found.push(*b);
            }
        }
    }
    found
}

#[test]
fn no_node_calls_a_builtin_the_worst_gpu_mode_does_not_model() {
    // The scanner itself, on WGSL it must and must not flag.
    assert_eq!(
        unmodelled_calls("let a = sin(x) + v.length(); // cos(y)\nlet b = mg_prec_sincos(x).x;"),
        ["sin"]
    );
    assert_eq!(
        unmodelled_calls("fn f() { return normalize (v) * inverseSqrt(l); }"),
        ["normalize", "inverseSqrt"]
    );
    assert!(unmodelled_calls("let n = mg_tw_normalize_or(v, n); let s = sqrt(x);").is_empty());
    let mut offenders = Vec::new();
    let mut scanned = 0;
    for t in Registry::builtin().types() {
        let generics = if t.is_generic() {
            t.generic_types()
        } else {
            vec![SocketType::Float]
        };
        let mut texts: Vec<&str> = generics.iter().filter_map(|g| t.wgsl_for(*g)).collect();
        texts.extend(t.wgsl_helpers_for(None));
        for text in texts {
            scanned += 1;
            for b in unmodelled_calls(text) {
                offenders.push(format!("{} calls {b}", t.name()));
            }
        }
    }
    offenders.dedup();
    assert!(scanned > 150, "only {scanned} WGSL texts scanned");
    assert!(
        offenders.is_empty(),
        "node WGSL calls builtins the worst-GPU mode does not model:\n{}",
        offenders.join("\n")
    );
}

/// The conditioned comparison ([`CONDITIONED`], [`envelope`]) admits the other side of a
/// discontinuity and nothing else: at toon_water_shade's band edge (N = (1, 0, 0),
/// L = (0.8, 0.6, 0), 5 steps: N·L is the edge), the value of the neighbouring band, which the
/// forward bound refuses, passes; the same band moved by 100 bounds does not, and neither does
/// a 1% error at the node's defaults, far from any edge. Needs no GPU and no mode (it holds
/// [`LOCK`], so the suites cannot switch the mode under it).
#[test]
fn the_conditioned_comparison_admits_a_band_edge_and_nothing_more() {
    // The kernels run in the process-global mode, which the suites switch: hold it exact.
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let registry = Registry::builtin();
    let t = registry.get("toon_water_shade").unwrap();
    let g = SocketType::Float;
    let index = |name: &str| t.input_index(name).unwrap();
    // Two samples: the node's own "on a band edge" hard case, and the defaults.
    let edge = t
        .hard_cases()
        .iter()
        .find(|h| h.why == "on a band edge")
        .expect("toon_water_shade's band-edge hard case");
    let columns = t
        .inputs()
        .iter()
        .enumerate()
        .map(|(k, d)| {
            let ty = d.ty.resolve(g);
            let default = t.default_for(k, g);
            let at_edge = edge
                .values
                .iter()
                .find(|(name, _)| *name == d.name)
                .map_or(default, |(_, v)| v.convert(ty).unwrap_or(*v));
            (0..ty.width())
                .flat_map(|c| [at_edge.raw()[c], default.raw()[c]])
                .collect()
        })
        .collect();
    let samples = NodeSamples { n: 2, columns };
    let want = run_cpu(t, g, &samples);
    let ramp = t.outputs().iter().position(|o| o.name == "ramp").unwrap();
    // The neighbouring band: light.x a few ULP down puts N·L just below the edge.
    let mut below = samples.clone();
    below.columns[index("light")][0] = f32::from_bits(0.8f32.to_bits() - 4);
    let other = run_cpu(t, g, &below);
    assert_ne!(
        want[ramp][0], other[ramp][0],
        "the hard case is not on a band edge"
    );
    let bound = bound_for(t.name());
    let compare = |got: &[Vec<f32>]| {
        let (mut errors, mut misses) = (Errors::default(), Vec::new());
        compare_node_outputs(
            t,
            g,
            &samples,
            (&want, got),
            bound,
            "toon_water_shade",
            ("cpu", "got"),
            &mut errors,
            &mut misses,
        );
        (errors, misses)
    };
    let mut got = want.clone();
    got[ramp][0] = other[ramp][0];
    assert!(!Errors::default().check(want[ramp][0], got[ramp][0], bound));
    let (errors, misses) = compare(&got);
    assert!(misses.is_empty(), "{misses:?}");
    assert_eq!(errors.conditioned, 1);
    got[ramp][0] = other[ramp][0] - (100.0 * (bound.0 + bound.1)) as f32;
    assert!(!compare(&got).1.is_empty());
    let mut got = want.clone();
    got[ramp][1] *= 1.01;
    assert!(!compare(&got).1.is_empty());
}
