//! The Blender math operations of `nodes/math_scalar.rs` and `nodes/math_vector.rs` against
//! f64 references written here (the std f64 functions, a quaternion for `rotate`), at seeded
//! random f32-exact points (uniform over the soft range and log-uniform over many decades),
//! at round points, and at the hard cases the node docs state (clamps, zeros, huge values).
//!
//! Each input is an f32 and the reference takes it widened to f64, so what is measured is the
//! node's own arithmetic. The bounds are in ulps of the result (`ULP` = 2⁻²⁴ relative, half
//! the f32 spacing at 1) unless a check says otherwise. Random points run through the CPU
//! kernels of every generic variant (float, vec2, vec3, vec4), one point per component;
//! round points and hard cases run through the graph pipeline from JSON literals.
//!
//! `cargo test --test models math_ops:: -- --nocapture` prints the largest error per node.

use crate::common;

use common::rng::Rng;

use matgraph::{Graph, Plan, PlanOptions, Registry, SampleBatch, SocketType};
use serde_json::json;
use std::collections::BTreeMap;
use std::f64::consts::{FRAC_PI_2, PI};

/// Half the f32 spacing at 1: the relative rounding error of one correctly rounded step.
const ULP: f64 = 5.960_464_477_539_063e-8;
/// Random points per node and generic type.
const N: usize = 4000;
/// The generic types every component-wise node is checked for.
const GENERICS: [SocketType; 4] = [
    SocketType::Float,
    SocketType::Vec2,
    SocketType::Vec3,
    SocketType::Vec4,
];

// ------------------------------------------------------------------------------------------
// Harness
// ------------------------------------------------------------------------------------------

/// The draws these tests make from the shared seeded generator.
impl Rng {
    /// Log-uniform magnitude in [lo, hi] (lo > 0) with a random sign, rounded to f32.
    fn signed_log(&mut self, lo: f64, hi: f64) -> f32 {
        let m = (lo.ln() + (hi.ln() - lo.ln()) * self.unit()).exp();
        (if self.next() & 1 == 1 { -m } else { m }) as f32
    }
    /// Half the time uniform in [lo, hi], half the time log-uniform over [tiny, huge].
    fn mixed(&mut self, (lo, hi): (f64, f64), (tiny, huge): (f64, f64)) -> f32 {
        if self.next() & 1 == 0 {
            self.f(lo, hi)
        } else {
            self.signed_log(tiny, huge)
        }
    }
}

/// The spacing of f32 values at |x|.
fn ulp_at(x: f32) -> f64 {
    let a = x.abs();
    (f32::from_bits(a.to_bits() + 1) as f64) - a as f64
}

/// Largest errors of one node, and the failures.
struct Check {
    node: &'static str,
    count: usize,
    worst: f64,
    worst_at: String,
    failures: Vec<String>,
}

impl Check {
    fn new(node: &'static str) -> Check {
        Check {
            node,
            count: 0,
            worst: 0.0,
            worst_at: String::new(),
            failures: Vec::new(),
        }
    }
    /// Records `err` against `tol`; `at` describes the point.
    fn record(&mut self, err: f64, tol: f64, at: impl Fn() -> String) {
        self.count += 1;
        let ratio = if err == 0.0 { 0.0 } else { err / tol };
        if ratio > self.worst || ratio.is_nan() {
            self.worst = if ratio.is_nan() { f64::INFINITY } else { ratio };
            self.worst_at = at();
        }
        if (err.is_nan() || err > tol) && self.failures.len() < 20 {
            self.failures
                .push(format!("{}: error {err:.3e} > {tol:.3e}", at()));
        }
    }
    /// `got` within `abs + rel·|want|` of `want`.
    fn near(&mut self, got: f32, want: f64, abs: f64, rel: f64, at: impl Fn() -> String) {
        let err = if got.is_finite() {
            (got as f64 - want).abs()
        } else {
            f64::INFINITY
        };
        self.record(err, abs + rel * want.abs(), || {
            format!("{} (got {got:e}, want {want:e})", at())
        });
    }
    /// Reports and asserts.
    fn finish(self) {
        eprintln!(
            "[{}] {} checks, worst {:.2} of the bound at {}",
            self.node, self.count, self.worst, self.worst_at
        );
        assert!(self.count > 0, "{}: nothing checked", self.node);
        assert!(
            self.failures.is_empty(),
            "{}: {} failures:\n{}",
            self.node,
            self.failures.len(),
            self.failures.join("\n")
        );
    }
}

/// Outputs of a kernel run: `[output][sample][component]`.
type Outs = Vec<Vec<Vec<f32>>>;

/// Runs the CPU kernel of `node` for generic type `g` over `n` samples; `input(k, i, c)` is
/// component `c` of input `k` at sample `i`.
fn run_kernel(
    node: &str,
    g: SocketType,
    n: usize,
    mut input: impl FnMut(usize, usize, usize) -> f32,
) -> Outs {
    let t = Registry::builtin().get(node).expect("a registered node");
    let variant = t.variant_for(g).expect("a variant");
    let columns: Vec<Vec<f32>> = t
        .inputs()
        .iter()
        .enumerate()
        .map(|(k, d)| {
            let w = d.ty.resolve(g).width();
            let mut col = vec![0.0f32; w * n];
            for i in 0..n {
                for c in 0..w {
                    col[c * n + i] = input(k, i, c);
                }
            }
            col
        })
        .collect();
    let widths: Vec<usize> = t
        .outputs()
        .iter()
        .map(|o| o.ty.resolve(g).width())
        .collect();
    let mut outs: Vec<Vec<f32>> = widths.iter().map(|w| vec![0.0; w * n]).collect();
    let ins: Vec<&[f32]> = columns.iter().map(Vec::as_slice).collect();
    let mut refs: Vec<&mut [f32]> = outs.iter_mut().map(Vec::as_mut_slice).collect();
    variant.kernel.run(&ins, &mut refs, n, n);
    outs.iter()
        .zip(&widths)
        .map(|(col, w)| {
            (0..n)
                .map(|i| (0..*w).map(|c| col[c * n + i]).collect())
                .collect()
        })
        .collect()
}

/// The outputs of one node evaluated through the graph pipeline from JSON literals.
fn eval(node: &str, inputs: serde_json::Value) -> BTreeMap<String, Vec<f32>> {
    let map: BTreeMap<String, serde_json::Value> =
        serde_json::from_value(inputs).expect("an object of inputs");
    let graph = Graph::single_node(Registry::builtin(), node, map)
        .unwrap_or_else(|e| panic!("{node}: {e:?}"));
    let plan = Plan::compile(&graph, &PlanOptions::default()).expect("compiles");
    let out = plan
        .execute(&SampleBatch::new(1), &plan.default_parameters())
        .expect("evaluates");
    out.names()
        .iter()
        .enumerate()
        .map(|(k, name)| (name.to_string(), out.value(k, 0).lanes().to_vec()))
        .collect()
}

/// The `result` output of [`eval`].
fn result(node: &str, inputs: serde_json::Value) -> Vec<f32> {
    eval(node, inputs)
        .remove("result")
        .expect("a result output")
}

/// Checks a component-wise one-input node at random points drawn by `draw` (and the
/// `specials`) against `reference`, within `abs + rel·|want|`, for every generic type.
fn unary(
    node: &'static str,
    draw: impl Fn(&mut Rng) -> f32,
    specials: &[f32],
    reference: impl Fn(f64) -> f64,
    (abs, rel): (f64, f64),
) {
    let mut check = Check::new(node);
    for (s, g) in GENERICS.into_iter().enumerate() {
        let w = g.width();
        let mut rng = Rng(0x6d61_7468 + s as u64);
        let mut xs: Vec<f32> = specials.to_vec();
        while xs.len() < N * w {
            xs.push(draw(&mut rng));
        }
        let n = xs.len().div_ceil(w);
        let pick = |i: usize, c: usize| xs[(i * w + c) % xs.len()];
        let out = run_kernel(node, g, n, |_, i, c| pick(i, c));
        for (i, sample) in out[0].iter().enumerate() {
            for (c, &got) in sample.iter().enumerate() {
                let x = pick(i, c);
                check.near(got, reference(x as f64), abs, rel, || {
                    format!("{g} x = {x:e}")
                });
            }
        }
    }
    check.finish();
}

/// Checks a component-wise two-input node like [`unary`].
fn binary(
    node: &'static str,
    draw: impl Fn(&mut Rng) -> (f32, f32),
    specials: &[(f32, f32)],
    reference: impl Fn(f64, f64) -> f64,
    (abs, rel): (f64, f64),
) {
    let mut check = Check::new(node);
    for (s, g) in GENERICS.into_iter().enumerate() {
        let w = g.width();
        let mut rng = Rng(0x6269_6e61 + s as u64);
        let mut xs: Vec<(f32, f32)> = specials.to_vec();
        while xs.len() < N * w {
            xs.push(draw(&mut rng));
        }
        let n = xs.len().div_ceil(w);
        let pick = |i: usize, c: usize| xs[(i * w + c) % xs.len()];
        let out = run_kernel(node, g, n, |k, i, c| {
            let p = pick(i, c);
            if k == 0 { p.0 } else { p.1 }
        });
        for (i, sample) in out[0].iter().enumerate() {
            for (c, &got) in sample.iter().enumerate() {
                let (a, b) = pick(i, c);
                check.near(got, reference(a as f64, b as f64), abs, rel, || {
                    format!("{g} ({a:e}, {b:e})")
                });
            }
        }
    }
    check.finish();
}

// ------------------------------------------------------------------------------------------
// Trigonometry
// ------------------------------------------------------------------------------------------

/// Round angles: multiples of π/4 rounded to f32, and small integers.
const ROUND_ANGLES: [f32; 12] = [
    0.0,
    std::f32::consts::FRAC_PI_4,
    std::f32::consts::FRAC_PI_2,
    -std::f32::consts::FRAC_PI_2,
    std::f32::consts::PI,
    -std::f32::consts::PI,
    std::f32::consts::TAU,
    1.0,
    -2.0,
    10.0,
    1000.0,
    -1e-20,
];

#[test]
fn sin_cos_tan_match_f64() {
    let draw = |r: &mut Rng| r.mixed((-10.0, 10.0), (1e-20, 1e4));
    // The nodes' own sin/cos (Cody–Waite reduction, Cephes polynomials; nodes/precise.rs) are
    // within 2 ulps of the result over these draws (|x| ≤ 1e4).
    unary("sin", draw, &ROUND_ANGLES, f64::sin, (1e-45, 2.0 * ULP));
    unary("cos", draw, &ROUND_ANGLES, f64::cos, (1e-45, 2.0 * ULP));
    // tan everywhere, the poles' neighbourhoods (1.5707963 gives −2.3e7) included.
    // The f32s either side of π/2 (1.5707963, 1.5707964), 1.57 and 3π/2.
    let below = f32::from_bits(std::f32::consts::FRAC_PI_2.to_bits() - 1);
    let near_pole = [below, std::f32::consts::FRAC_PI_2, 1.57, -below, 4.712_389];
    // The node forms tan as its own sine over its own cosine (nodes/precise.rs): 4 ulps; at a
    // pole the cosine is the sine of a reduced argument near 0, whose three-part π/2 leaves
    // 2e-6 relative at 3π/2 (the node's soft range stops at ±1.5).
    unary("tan", draw, &ROUND_ANGLES, f64::tan, (1e-45, 4.0 * ULP));
    unary("tan", draw, &near_pole, f64::tan, (1e-45, 2e-6));
    assert_eq!(result("sin", json!({ "x": 0.0 })), [0.0]);
    assert_eq!(result("cos", json!({ "x": 0.0 })), [1.0]);
    let t = result("tan", json!({ "x": std::f32::consts::FRAC_PI_2 }))[0];
    assert!(t < -2.2e7 && t > -2.4e7, "tan of the f32 nearest π/2: {t}");
}

#[test]
fn asin_acos_match_f64_and_clamp_beyond_one() {
    let draw = |r: &mut Rng| {
        if r.next().is_multiple_of(4) {
            // Within 1e-7 … 1e-1 of ±1, where the derivative blows up.
            let d = r.signed_log(1e-7, 1e-1);
            (if d < 0.0 { -1.0 - d } else { 1.0 - d }).clamp(-1.0, 1.0)
        } else {
            r.f(-1.5, 1.5)
        }
    };
    let specials = [
        0.0f32,
        0.5,
        -0.5,
        1.0,
        -1.0,
        0.999_999_94,
        -0.999_999_94,
        2.0,
        -3.0,
    ];
    let clamp = |x: f64| x.clamp(-1.0, 1.0);
    unary(
        "asin",
        draw,
        &specials,
        |x| clamp(x).asin(),
        (1e-45, 2.0 * ULP),
    );
    unary(
        "acos",
        draw,
        &specials,
        |x| clamp(x).acos(),
        (1e-45, 2.0 * ULP),
    );
    // The documented clamp: beyond ±1 the values at ±1.
    let half_pi = FRAC_PI_2 as f32;
    assert_eq!(
        result("asin", json!({ "x": [1.5, -3.0, 1.0] })),
        [half_pi, -half_pi, half_pi]
    );
    assert_eq!(
        result("acos", json!({ "x": [1.5, -3.0, 0.0] })),
        [0.0, PI as f32, half_pi]
    );
}

#[test]
fn atan2_matches_f64_with_zeros_read_as_plus_zero() {
    let draw = |r: &mut Rng| {
        (
            r.mixed((-10.0, 10.0), (1e-30, 1e30)),
            r.mixed((-10.0, 10.0), (1e-30, 1e30)),
        )
    };
    let specials = [
        (0.0f32, 0.0f32),
        (0.0, -1.0),
        (-0.0, -1.0),
        (1.0, 0.0),
        (-1.0, -0.0),
        (1.0, 1.0),
        (-1.0, -1.0),
        (1e30, -1e-30),
        (3e38, 3e38),
        (-1e-38, 2e-38),
    ];
    // The reference is C's atan2 with each zero made +0 (−0 + 0 = +0), the node's rule.
    // Error: the quotient's rounding, atan's, and π/2 − t or π − a: within 4 ulps.
    binary(
        "atan2",
        draw,
        &specials,
        |y, x| (y + 0.0).atan2(x + 0.0),
        (1e-45, 4.0 * ULP),
    );
    let pi = PI as f32;
    assert_eq!(result("atan2", json!({ "y": 0.0, "x": 0.0 })), [0.0]);
    assert_eq!(result("atan2", json!({ "y": -0.0, "x": -1.0 })), [pi]);
    assert_eq!(
        result(
            "atan2",
            json!({ "y": [0.0, 1.0, -1.0], "x": [-1.0, 0.0, 0.0] })
        ),
        [pi, FRAC_PI_2 as f32, -FRAC_PI_2 as f32]
    );
}

// ------------------------------------------------------------------------------------------
// Sign, rounding, min and max
// ------------------------------------------------------------------------------------------

#[test]
fn abs_sign_negate_one_minus_floor_ceil_are_exact() {
    let draw = |r: &mut Rng| r.mixed((-10.0, 10.0), (1e-30, 1e30));
    let specials = [
        0.0f32, -0.0, 0.5, -0.5, 1.0, -1.0, 2.5, -2.5, 8388608.5, -1e30, 3e38,
    ];
    unary("abs", draw, &specials, f64::abs, (0.0, 0.0));
    let sign = |x: f64| {
        if x > 0.0 {
            1.0
        } else if x < 0.0 {
            -1.0
        } else {
            0.0
        }
    };
    unary("sign", draw, &specials, sign, (0.0, 0.0));
    unary("negate", draw, &specials, |x| -x, (0.0, 0.0));
    // 1 − x is one correctly rounded subtraction.
    unary("one_minus", draw, &specials, |x| 1.0 - x, (0.0, ULP));
    unary("floor", draw, &specials, f64::floor, (0.0, 0.0));
    unary("ceil", draw, &specials, f64::ceil, (0.0, 0.0));
    assert_eq!(
        result("floor", json!({ "x": [-1e30, 2.5, -2.5] })),
        [-1e30, 2.0, -3.0]
    );
    assert_eq!(
        result("ceil", json!({ "x": [1e30, 2.5, -2.5] })),
        [1e30, 3.0, -2.0]
    );
    assert_eq!(
        result("sign", json!({ "x": [-0.0, 1e-30, -7.0] })),
        [0.0, 1.0, -1.0]
    );
}

#[test]
fn min_max_are_exact() {
    let draw = |r: &mut Rng| (r.f(-10.0, 10.0), r.mixed((-10.0, 10.0), (1e-30, 1e30)));
    let specials = [(1.0f32, 2.0f32), (-1.0, -2.0), (3.0, 3.0), (-3e38, 3e38)];
    binary("min", draw, &specials, f64::min, (0.0, 0.0));
    binary("max", draw, &specials, f64::max, (0.0, 0.0));
}

/// The distance between `got` and `want` around a cycle of length `period`.
fn cyclic_error(got: f32, want: f64, period: f64) -> f64 {
    let d = (got as f64 - want).abs() % period;
    d.min(period - d)
}

#[test]
fn fract_matches_f64_and_stays_below_one() {
    let mut check = Check::new("fract");
    let mut rng = Rng(0xf4ac);
    let mut xs = vec![
        0.0f32, -0.0, 0.5, -0.5, 1.0, -1.0, 1e30, -1e30, -1e-10, -3.0, 8388607.5,
    ];
    while xs.len() < N {
        xs.push(rng.mixed((-10.0, 10.0), (1e-12, 1e10)));
    }
    let out = run_kernel("fract", SocketType::Float, xs.len(), |_, i, _| xs[i]);
    for (i, &x) in xs.iter().enumerate() {
        let got = out[0][i][0];
        let want = x as f64 - (x as f64).floor(); // exact in f64
        // In [0, 1), within half an ulp of 1 around the cycle (x + 1 rounds for x ∈ (−1, 0)).
        let err = if (0.0..1.0).contains(&got) {
            cyclic_error(got, want, 1.0)
        } else {
            f64::INFINITY
        };
        check.record(err, ULP, || {
            format!("x = {x:e} (got {got:e}, want {want:e})")
        });
    }
    check.finish();
    assert_eq!(
        result("fract", json!({ "x": [1e30, -1e-10, -2.75] })),
        [0.0, 0.0, 0.25]
    );
}

/// The floored modulo in f64 from the exact remainder (`%` is fmod, exact), moved into the
/// sign of b.
fn ref_floored_mod(a: f64, b: f64) -> f64 {
    let r = a % b;
    if r != 0.0 && (r < 0.0) != (b < 0.0) {
        r + b
    } else {
        r
    }
}

#[test]
fn floored_modulo_matches_f64_within_the_period() {
    let mut check = Check::new("floored_modulo");
    let mut rng = Rng(0x6d6f64);
    let mut pairs = vec![
        (7.5f32, 2.0f32),
        (-7.5, 2.0),
        (7.5, -2.0),
        (-7.5, -2.0),
        (-6.0, 3.0),
        (0.3, 0.1),
        (-1e-10, 1.0),
        (1e-10, -1.0),
        (5.0, 1e-3),
    ];
    while pairs.len() < N {
        let a = rng.mixed((-10.0, 10.0), (1e-6, 1e6));
        let b = rng.mixed((-10.0, 10.0), (1e-3, 1e3));
        pairs.push((a, b));
    }
    for g in GENERICS {
        let w = g.width();
        let n = pairs.len().div_ceil(w);
        let pick = |i: usize, c: usize| pairs[(i * w + c) % pairs.len()];
        let out = run_kernel("floored_modulo", g, n, |k, i, c| {
            let p = pick(i, c);
            if k == 0 { p.0 } else { p.1 }
        });
        for (i, sample) in out[0].iter().enumerate() {
            for (c, &got) in sample.iter().enumerate() {
                let (a, b) = pick(i, c);
                let (a64, b64) = (a as f64, b as f64);
                let q = (a64 / b64).abs();
                let limit = 16_777_216.0;
                if (q - limit).abs() < limit * 1e-6 {
                    continue; // f32 and f64 quotients may fall either side of the limit.
                }
                let at = || format!("{g} ({a:e}, {b:e}) got {got:e}");
                if q >= limit || b == 0.0 {
                    check.record((got as f64).abs(), 0.0, at); // documented: 0
                    continue;
                }
                let want = ref_floored_mod(a64, b64);
                let inside = if b > 0.0 {
                    (0.0..b).contains(&got)
                } else {
                    got <= 0.0 && got > b
                };
                // About an ulp of a and of b, around the cycle (a − b⌊a/b⌋ jumps at multiples).
                let err = if inside {
                    cyclic_error(got, want, b64.abs())
                } else {
                    f64::INFINITY
                };
                check.record(err, 2.0 * (ulp_at(a) + ulp_at(b)), at);
            }
        }
    }
    check.finish();
    assert_eq!(
        result(
            "floored_modulo",
            json!({ "a": [3.0, 7.5, -7.5], "b": [0.0, -2.0, 2.0] })
        ),
        [0.0, -0.5, 0.5]
    );
    assert_eq!(
        result(
            "floored_modulo",
            json!({ "a": [-1e-10, 1e30, -6.0], "b": [1.0, 3.0, 3.0] })
        ),
        [0.0, 0.0, 0.0]
    );
}

// ------------------------------------------------------------------------------------------
// Roots and logarithms
// ------------------------------------------------------------------------------------------

#[test]
fn sqrt_and_inverse_sqrt_match_f64_and_are_zero_below() {
    let draw = |r: &mut Rng| {
        let m = r.signed_log(1e-37, 1e37);
        if r.next().is_multiple_of(4) {
            m
        } else {
            m.abs()
        }
    };
    let specials = [0.0f32, -0.0, 1.0, 4.0, 2.0, -4.0, 1e-30, 3e38, 1.2e-38];
    let sqrt = |x: f64| if x < 0.0 { 0.0 } else { x.sqrt() };
    unary("sqrt", draw, &specials, sqrt, (0.0, ULP));
    // 1/√x: two correctly rounded steps.
    let inv = |x: f64| if x > 0.0 { 1.0 / x.sqrt() } else { 0.0 };
    unary("inverse_sqrt", draw, &specials, inv, (0.0, 3.0 * ULP));
    assert_eq!(
        result("sqrt", json!({ "x": [-4.0, 9.0, 0.0] })),
        [0.0, 3.0, 0.0]
    );
    assert_eq!(
        result("inverse_sqrt", json!({ "x": [0.0, -1.0, 4.0] })),
        [0.0, 0.0, 0.5]
    );
    assert_eq!(result("inverse_sqrt", json!({ "x": 1e-30 })), [1e15]);
}

#[test]
fn log_and_log_base_match_f64_and_are_zero_where_undefined() {
    let draw = |r: &mut Rng| {
        let m = r.signed_log(1e-37, 1e37);
        if r.next().is_multiple_of(8) {
            m
        } else if r.next().is_multiple_of(2) {
            r.f(0.5, 2.0) // around 1, where ln x → 0
        } else {
            m.abs()
        }
    };
    let specials = [
        0.0f32,
        -1.0,
        1.0,
        std::f32::consts::E,
        0.999_999_94,
        1.000_000_1,
        1e-30,
        3e38,
    ];
    let ln = |x: f64| if x > 0.0 { x.ln() } else { 0.0 };
    unary("log", draw, &specials, ln, (1e-45, 2.0 * ULP));
    let draw2 = |r: &mut Rng| {
        let x = draw(r);
        let b = if r.next() & 1 == 0 {
            r.f(1.5, 16.0)
        } else {
            r.f(0.05, 0.9)
        };
        (x, b)
    };
    let specials2 = [
        (8.0f32, 2.0f32),
        (100.0, 10.0),
        (8.0, 0.5),
        (5.0, 1.0),
        (0.0, 10.0),
        (2.0, -2.0),
        (-2.0, 2.0),
        (2.0, 0.0),
    ];
    let log_b = |x: f64, b: f64| {
        if x > 0.0 && b > 0.0 && b != 1.0 {
            x.ln() / b.ln()
        } else {
            0.0
        }
    };
    // Two logs and a quotient; ln b ≥ 0.1 in magnitude here, so no conditioning is added.
    // Each log is the node's own log2 (nodes/precise.rs log2_exact, within 2⁻²¹ = 8 ulps
    // relative, the same bits on every GPU), so the quotient is within 2 · 8 ulps.
    binary("log_base", draw2, &specials2, log_b, (1e-45, 16.0 * ULP));
    assert_eq!(
        result("log", json!({ "x": [0.0, -1.0, 1.0] })),
        [0.0, 0.0, 0.0]
    );
    assert_eq!(
        result(
            "log_base",
            json!({ "x": [8.0, 100.0, 5.0], "base": [2.0, 10.0, 1.0] })
        ),
        [3.0, 2.0, 0.0]
    );
    assert_eq!(result("log_base", json!({ "x": 8.0, "base": 0.5 })), [-3.0]);
}

// ------------------------------------------------------------------------------------------
// Compare and select
// ------------------------------------------------------------------------------------------

#[test]
fn compare_is_blenders_with_a_floor_on_epsilon() {
    let mut rng = Rng(0xc0de);
    let mut failures = Vec::new();
    for g in GENERICS {
        let w = g.width();
        // Per sample: epsilon, then per component (a, b) either clearly apart or within it.
        let mut rows: Vec<(f32, Vec<(f32, f32)>)> = Vec::new();
        for i in 0..N {
            let eps = if i % 5 == 0 { 0.0 } else { rng.f(0.0, 1.0) };
            let pairs = (0..w)
                .map(|_| {
                    let a = rng.f(-10.0, 10.0);
                    let e = (eps as f64).max(f32::EPSILON as f64);
                    let d = match rng.next() % 3 {
                        0 => e * rng.f(0.0, 0.999) as f64,
                        1 => e * rng.f(1.001, 3.0) as f64 + 1e-5,
                        _ => 0.0,
                    };
                    let sign = if rng.next() & 1 == 1 { -1.0 } else { 1.0 };
                    (a, (a as f64 + sign * d) as f32)
                })
                .collect();
            rows.push((eps, pairs));
        }
        let out = run_kernel("compare", g, rows.len(), |k, i, c| match k {
            0 => rows[i].1[c].0,
            1 => rows[i].1[c].1,
            _ => rows[i].0,
        });
        for (i, (eps, pairs)) in rows.iter().enumerate() {
            let e = (*eps as f64).max(f32::EPSILON as f64);
            let want: Vec<f32> = pairs
                .iter()
                .map(|&(a, b)| {
                    let (a, b) = (a as f64, b as f64);
                    if a == b || (a - b).abs() <= e {
                        1.0
                    } else {
                        0.0
                    }
                })
                .collect();
            let all = if want.iter().all(|&x| x == 1.0) {
                1.0
            } else {
                0.0
            };
            if out[0][i] != want || out[1][i] != [all] {
                failures.push(format!(
                    "{g} eps {eps:e} {pairs:?}: got {:?} {:?}, want {want:?} {all}",
                    out[0][i], out[1][i]
                ));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{}",
        failures[..failures.len().min(10)].join("\n")
    );
    let r = eval(
        "compare",
        json!({ "a": [1.0, 1.0, 3e38], "b": [1.5, 1.0, -3e38], "epsilon": 0.5 }),
    );
    assert_eq!(r["result"], [1.0, 1.0, 0.0]);
    assert_eq!(r["equal"], [0.0]);
    // The smallest epsilon is f32's machine epsilon: 1 and 1 + 2⁻²³ compare equal at 0.
    let r = eval(
        "compare",
        json!({ "a": 1.0, "b": 1.000_000_1, "epsilon": -1.0 }),
    );
    assert_eq!((r["result"][0], r["equal"][0]), (1.0, 1.0));
    let r = eval(
        "compare",
        json!({ "a": 1.0, "b": 1.000_000_3, "epsilon": 0.0 }),
    );
    assert_eq!((r["result"][0], r["equal"][0]), (0.0, 0.0));
}

#[test]
fn select_passes_on_the_chosen_input() {
    for (c, want) in [(false, [1.0, 2.0, 3.0]), (true, [-4.0, 5.0, -6.0])] {
        let got = result(
            "select",
            json!({ "condition": c, "if_false": [1.0, 2.0, 3.0], "if_true": [-4.0, 5.0, -6.0] }),
        );
        assert_eq!(got, want, "condition {c}");
    }
    // Linked from compare's bool, through a two-node graph.
    let doc = json!({
        "version": 1, "name": "pick",
        "nodes": [
            { "id": "cmp", "type": "compare", "inputs": { "a": 2.0, "b": 2.25, "epsilon": 0.5 } },
            { "id": "sel", "type": "select", "inputs": {
                "condition": { "link": "cmp.equal" }, "if_false": 7.0, "if_true": 9.0 } }
        ],
        "outputs": [{ "name": "out", "from": "sel.result" }]
    });
    let graph = Graph::from_json(&doc.to_string(), Registry::builtin()).unwrap();
    let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
    let out = plan
        .execute(&SampleBatch::new(1), &plan.default_parameters())
        .unwrap();
    assert_eq!(out.value(0, 0).lanes(), [9.0]);
}

// ------------------------------------------------------------------------------------------
// Vectors: scale, project, rotate
// ------------------------------------------------------------------------------------------

type D3 = [f64; 3];
fn dot(a: D3, b: D3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn norm(a: D3) -> f64 {
    dot(a, a).sqrt()
}

#[test]
fn scale_matches_f64() {
    let mut check = Check::new("scale");
    let mut rng = Rng(0x5ca1e);
    for g in [SocketType::Vec2, SocketType::Vec3, SocketType::Vec4] {
        let w = g.width();
        let rows: Vec<(Vec<f32>, f32)> = (0..N)
            .map(|_| {
                let v = (0..w)
                    .map(|_| rng.mixed((-2.0, 2.0), (1e-20, 1e20)))
                    .collect();
                (v, rng.mixed((-10.0, 10.0), (1e-10, 1e10)))
            })
            .collect();
        let out = run_kernel(
            "scale",
            g,
            N,
            |k, i, c| {
                if k == 0 { rows[i].0[c] } else { rows[i].1 }
            },
        );
        for (i, (v, s)) in rows.iter().enumerate() {
            for c in 0..w {
                let want = v[c] as f64 * *s as f64;
                check.near(out[0][i][c], want, 0.0, ULP, || {
                    format!("{g} {v:?} × {s:e}")
                });
            }
        }
    }
    check.finish();
}

#[test]
fn project_matches_f64_and_is_zero_onto_zero() {
    let mut check = Check::new("project");
    let mut rng = Rng(0x9e0);
    for g in [SocketType::Vec2, SocketType::Vec3, SocketType::Vec4] {
        let w = g.width();
        let mut rows: Vec<(Vec<f32>, Vec<f32>)> = Vec::new();
        for _ in 0..N {
            let a: Vec<f32> = (0..w).map(|_| rng.f(-2.0, 2.0)).collect();
            // b of any magnitude from 1e-30 to 1e30: only its direction matters.
            let m = rng.signed_log(1e-30, 1e30).abs();
            let b: Vec<f32> = (0..w).map(|_| rng.f(-1.0, 1.0) * m).collect();
            rows.push((a, b));
        }
        rows.push((vec![1.0; w], vec![0.0; w]));
        let out = run_kernel("project", g, rows.len(), |k, i, c| {
            if k == 0 { rows[i].0[c] } else { rows[i].1[c] }
        });
        for (i, (a, b)) in rows.iter().enumerate() {
            let a64: Vec<f64> = a.iter().map(|x| *x as f64).collect();
            let b64: Vec<f64> = b.iter().map(|x| *x as f64).collect();
            let bb: f64 = b64.iter().map(|x| x * x).sum();
            let ab: f64 = a64.iter().zip(&b64).map(|(x, y)| x * y).sum();
            let la: f64 = a64.iter().map(|x| x * x).sum::<f64>().sqrt();
            for c in 0..w {
                // b (a·b)/(b·b); 0 onto a zero b (Blender's rule).
                let want = if bb > 0.0 { b64[c] * ab / bb } else { 0.0 };
                // Normalising b and the dot product: a few ulps of |a|.
                check.near(out[0][i][c], want, 8.0 * ULP * la, 0.0, || {
                    format!("{g} a {a:?} b {b:?}")
                });
            }
        }
    }
    check.finish();
    assert_eq!(
        result(
            "project",
            json!({ "a": [1.0, 2.0, 3.0], "b": [0.0, 0.0, 0.0] })
        ),
        [0.0; 3]
    );
    assert_eq!(
        result(
            "project",
            json!({ "a": [1.0, 2.0, 3.0], "b": [0.0, 1e30, 0.0] })
        ),
        [0.0, 2.0, 0.0]
    );
    assert_eq!(
        result(
            "project",
            json!({ "a": [1.0, 2.0, 3.0], "b": [0.0, 0.0, -1e-30] })
        ),
        [0.0, 0.0, 3.0]
    );
}

/// `v` rotated by `angle` about the unit `axis` as the quaternion product q v q*, q =
/// (cos θ/2, sin θ/2 · axis): a different route from Rodrigues' formula.
fn quaternion_rotate(v: D3, axis: D3, angle: f64) -> D3 {
    let (s, w) = ((angle / 2.0).sin(), (angle / 2.0).cos());
    let q = [axis[0] * s, axis[1] * s, axis[2] * s];
    let cross = |a: D3, b: D3| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    // v' = v + 2w (q × v) + 2 q × (q × v)
    let t = cross(q, v);
    let u = cross(q, t);
    [
        v[0] + 2.0 * w * t[0] + 2.0 * u[0],
        v[1] + 2.0 * w * t[1] + 2.0 * u[1],
        v[2] + 2.0 * w * t[2] + 2.0 * u[2],
    ]
}

#[test]
fn rotate_matches_a_quaternion_rotation() {
    let mut check = Check::new("rotate");
    let mut rng = Rng(0x207a7e);
    let mut rows: Vec<[[f32; 3]; 3]> = Vec::new();
    let mut angles: Vec<f32> = Vec::new();
    for _ in 0..N {
        let v = [rng.f(-2.0, 2.0), rng.f(-2.0, 2.0), rng.f(-2.0, 2.0)];
        let c = [rng.f(-2.0, 2.0), rng.f(-2.0, 2.0), rng.f(-2.0, 2.0)];
        // Axes of any length from 1e-30 to 1e30.
        let m = rng.signed_log(1e-30, 1e30);
        let axis = [
            rng.f(-1.0, 1.0) * m,
            rng.f(-1.0, 1.0) * m,
            rng.f(-1.0, 1.0) * m,
        ];
        rows.push([v, c, axis]);
        angles.push(rng.f(-2.0 * PI, 2.0 * PI));
    }
    let out = run_kernel("rotate", SocketType::Float, N, |k, i, c| {
        if k == 3 { angles[i] } else { rows[i][k][c] }
    });
    for (i, [v, c, axis]) in rows.iter().enumerate() {
        let f = |x: [f32; 3]| x.map(|y| y as f64);
        let (v64, c64, a64) = (f(*v), f(*c), f(*axis));
        let la = norm(a64);
        let k = a64.map(|x| x / la);
        let p = [v64[0] - c64[0], v64[1] - c64[1], v64[2] - c64[2]];
        let r = quaternion_rotate(p, k, angles[i] as f64);
        // A few ulps of |p| and of |center| (the final addition).
        let tol = 8.0 * ULP * (norm(p) + norm(c64));
        for j in 0..3 {
            check.near(out[0][i][j], r[j] + c64[j], tol, 0.0, || {
                format!("v {v:?} c {c:?} axis {axis:?} angle {}", angles[i])
            });
        }
    }
    check.finish();
    // Round cases: a quarter turn about z takes x to y (cos(π/2 in f32) = −4.4e-8).
    let got = result(
        "rotate",
        json!({ "v": [1.0, 0.0, 0.0], "axis": [0.0, 0.0, 2.0], "angle": 1.570_796_4 }),
    );
    assert!(
        got[0].abs() < 1e-7 && (got[1] - 1.0).abs() < 1e-7 && got[2] == 0.0,
        "{got:?}"
    );
    // About the axis through (1, 1, 0): the point (2, 1, 5) turns half a turn to (0, 1, 5).
    let got = result(
        "rotate",
        json!({ "v": [2.0, 1.0, 5.0], "center": [1.0, 1.0, 0.0], "axis": [0.0, 0.0, 1.0], "angle": PI as f32 }),
    );
    assert!(
        (got[0] - 0.0).abs() < 1e-6 && (got[1] - 1.0).abs() < 1e-6 && got[2] == 5.0,
        "{got:?}"
    );
    // A zero axis leaves v as it is (Blender's rule); huge and tiny axes keep their direction.
    let v = [0.3f32, -0.7, 1.9];
    assert_eq!(
        result(
            "rotate",
            json!({ "v": v, "axis": [0.0, 0.0, 0.0], "angle": 1.0 })
        ),
        v
    );
    let unit = result(
        "rotate",
        json!({ "v": v, "axis": [1.0, 0.0, 1.0], "angle": 2.0 }),
    );
    for axis in [[1e30f32, 0.0, 1e30], [1e-30, 0.0, 1e-30]] {
        let got = result("rotate", json!({ "v": v, "axis": axis, "angle": 2.0 }));
        for j in 0..3 {
            assert!(
                (got[j] - unit[j]).abs() <= 4e-7,
                "axis {axis:?}: {got:?} vs {unit:?}"
            );
        }
    }
}
