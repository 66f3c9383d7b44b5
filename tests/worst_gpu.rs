//! The node and graph parity suites against the least accurate GPU the WGSL specification
//! allows: the CPU executor in its worst-conformant-GPU mode (`matgraph::precision`), where
//! every builtin the kernels call is moved by the full error WGSL allows it (up, down, and a
//! seeded choice per call), subnormals are flushed, `sin`/`cos` arguments beyond [−π, π] are
//! reduced in plain f32 and `cross` is contracted. Each result must stay within the parity
//! bound its node or graph has on a real GPU (tests/common/parity.rs), so a pass here
//! predicts a pass on every conformant GPU, not only on lavapipe, whose builtins are as
//! accurate as the CPU's. Needs no GPU: it runs everywhere `cargo test` does.
//!
//! The mode is process-global, so the tests of this binary hold [`LOCK`] while they run.
//! Run with `-- --nocapture` to see each node's and graph's worst error.

mod common;

use common::parity::*;
use matgraph::node::Evaluation;
use matgraph::precision::{self, Direction, Mode};
use matgraph::{OutputBatch, Plan, PlanOptions, Registry, SocketType, Value};
use std::fmt::Write as _;
use std::sync::Mutex;

/// Held by each test while it switches the process-global mode.
static LOCK: Mutex<()> = Mutex::new(());

/// The worst-GPU directions each suite runs: every result up, every result down, and a
/// seeded mix (which moves the two sides of a difference apart).
const DIRECTIONS: [Direction; 3] = [
    Direction::Up,
    Direction::Down,
    Direction::Mixed(0x5eed_0f32),
];

/// Runs `f` in `mode`, then returns to the exact mode.
fn in_mode<R>(mode: Mode, f: impl FnOnce() -> R) -> R {
    precision::set_mode(mode);
    let r = f();
    precision::set_mode(Mode::Exact);
    r
}

/// Compares planar output columns of one node: `exact` against `worst`, per component.
#[allow(clippy::too_many_arguments)]
fn compare_columns(
    t: &matgraph::NodeType,
    generic: SocketType,
    samples: &NodeSamples,
    exact: &[Vec<f32>],
    worst: &[Vec<f32>],
    bound: (f64, f64),
    label: &str,
    errors: &mut Errors,
    failures: &mut Vec<String>,
) {
    let mut shown = 0;
    for (k, d) in t.outputs().iter().enumerate() {
        let w = d.ty.resolve(generic).width();
        for i in 0..samples.n {
            for c in 0..w {
                let (a, b) = (exact[k][c * samples.n + i], worst[k][c * samples.n + i]);
                if !errors.check(a, b, bound) && shown < 3 {
                    shown += 1;
                    failures.push(format!(
                        "{label}: output {}[{c}] exact {a:e} worst GPU {b:e} at {}",
                        d.name,
                        describe_inputs(t, generic, samples, i)
                    ));
                }
            }
        }
    }
}

#[test]
fn every_node_type_stays_within_its_bound_on_a_worst_gpu() {
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let mut failures: Vec<String> = Vec::new();
    let mut table = String::new();
    let mut checked = 0;
    for (seed, t) in Registry::builtin().types().iter().enumerate() {
        if t.evaluation() != Evaluation::Compute {
            continue;
        }
        let generics = if t.is_generic() {
            t.generic_types()
        } else {
            vec![SocketType::Float]
        };
        let bound = bound_for(t.name());
        for generic in generics {
            let label = if t.is_generic() {
                format!("{} ({generic})", t.name())
            } else {
                t.name().to_owned()
            };
            // The seeds of tests/gpu_parity.rs: the same samples a GPU is checked at.
            let samples = node_samples(t, generic, 0x5eed_0000 + seed as u64 * 16 + generic as u64);
            let exact = run_cpu(t, generic, &samples);
            let mut errors = Errors::default();
            for direction in DIRECTIONS {
                let worst = in_mode(Mode::WorstGpu(direction), || run_cpu(t, generic, &samples));
                let label = format!("{label} [{direction:?}]");
                compare_columns(
                    t,
                    generic,
                    &samples,
                    &exact,
                    &worst,
                    bound,
                    &label,
                    &mut errors,
                    &mut failures,
                );
            }
            checked += 1;
            let _ = writeln!(
                table,
                "  {label:<32} {:>6} samples  max abs {:9.3e}  max rel {:9.3e}  {:7.1}% of bound",
                samples.n,
                errors.max_abs,
                errors.max_rel,
                errors.worst * 100.0
            );
        }
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

/// Executes `plan` over `case`'s batch at `params` in `mode`.
fn execute(
    plan: &Plan,
    case: &GraphCase,
    params: &matgraph::ParamValues,
    mode: Mode,
) -> OutputBatch {
    in_mode(mode, || plan.execute(&case.batch, params).unwrap())
}

#[test]
fn every_shipped_graph_stays_within_its_bound_on_a_worst_gpu() {
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let mut failures = Vec::new();
    let mut cases = shipped_graph_cases();
    cases.push(monte_carlo_case("schlick"));
    cases.push(monte_carlo_case("exact"));
    assert!(cases.len() > 25, "{} graphs", cases.len());
    for case in &cases {
        let plan = Plan::compile(&case.graph, &PlanOptions::default()).unwrap();
        let bound = graph_bound(&case.graph);
        let mut params = plan.default_parameters();
        // The file's values, then every float parameter scaled by 1.1, as on the GPU.
        for round in 0..2 {
            if round == 1 {
                for p in plan.parameters() {
                    let v = params.get(&p.name).unwrap();
                    if v.ty() == SocketType::Float {
                        params.set(&p.name, Value::float(v.as_f32() * 1.1)).unwrap();
                    }
                }
            }
            let exact = execute(&plan, case, &params, Mode::Exact);
            for direction in DIRECTIONS {
                let worst = execute(&plan, case, &params, Mode::WorstGpu(direction));
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
