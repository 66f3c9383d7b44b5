//! The WGSL builtins as the CPU kernels call them, and the executor's worst-conformant-GPU
//! mode.
//!
//! WGSL promises each builtin only the accuracy its specification states (WGSL §15.7.4
//! "Floating Point Accuracy": `sin`/`cos` 2⁻¹¹ absolute inside [−π, π] and nothing outside,
//! `exp`/`exp2` 3 + 2|x| ULP, `log`/`log2` 2⁻²¹ absolute inside [0.5, 2] and 3 ULP outside,
//! `pow` inherited from `exp2(y·log2 x)`, …; docs/precision.md has the whole table), and real
//! GPUs use that room. Every CPU kernel calls the builtins its WGSL calls through the
//! functions of this module, so the CPU can run as the least accurate GPU the specification
//! allows: [`set_mode`] with [`Mode::WorstGpu`] moves each result by the full error its builtin
//! is allowed (up, down, or a seeded choice per call), flushes subnormal arguments and results
//! to zero as GPUs may, and fuses one product of `cross` as a contracting compiler may. The
//! parity suites run the node and graph plans in that mode (tests/worst_gpu.rs), so CI on a
//! software driver predicts what a real GPU may do.
//!
//! The module holds the builtins node WGSL calls whose results WGSL does not fix: `exp`,
//! `exp2`, `log`, `log2`, `pow`, `sqrt` and `cross`. Nodes compute `sin` and `cos`
//! themselves (`nodes/precise.rs`: WGSL promises 2⁻¹¹ absolute on [−π, π] and nothing beyond),
//! and tests/worst_gpu.rs fails if a node's WGSL calls a builtin with a stated error that this
//! module does not model.
//!
//! In [`Mode::Exact`] (the default) each function is the plain correctly rounded or libm
//! result the kernels always computed: renders and `eval` do not change. The worst-GPU modes
//! exist only in builds with the `worst-gpu` feature ([`AVAILABLE`]): there each call tests
//! the mode, which keeps the tile loops from vectorising (the executor runs 60% longer), so
//! the default build leaves the test out and costs nothing.
//!
//! Not modelled (stated in docs/precision.md): the 2.5 ULP of `x / y` (the CPU divides
//! correctly rounded), contraction of `a·b + c` anywhere but [`cross`], and subnormal flushing
//! in plain arithmetic.

use glam::Vec3;
use std::sync::atomic::{AtomicU64, Ordering};

/// How the builtins of this module compute.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// The correctly rounded (or libm) result: the CPU executor's normal mode.
    Exact,
    /// The least accurate result the WGSL specification allows, in `direction`.
    WorstGpu(Direction),
}

/// Which way [`Mode::WorstGpu`] moves each builtin's result.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// Every result moved up (towards +∞) by its allowed error.
    Up,
    /// Every result moved down (towards −∞).
    Down,
    /// Up or down per call, from a hash of the seed, the builtin and its arguments: the same
    /// call gives the same result, as on a GPU.
    Mixed(u32),
}

/// The mode, packed: 0 exact, 1 up, 2 down, 3 mixed with the seed in the high 32 bits.
static MODE: AtomicU64 = AtomicU64::new(0);

/// Whether this build has the worst-GPU mode: the `worst-gpu` feature. Without it every
/// builtin is the plain function, with no test of the mode (the test costs the executor 60%:
/// it keeps LLVM from vectorising the tile loops; docs/benchmarks.md).
pub const AVAILABLE: bool = cfg!(feature = "worst-gpu");

/// [`set_mode`] of a worst-GPU mode in a build without the `worst-gpu` feature.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the worst-conformant-GPU mode needs matgraph built with the `worst-gpu` feature")]
pub struct Unavailable;

/// Sets the mode for the whole process (every thread, the executor's pool included).
/// [`Mode::Exact`] is always available; the worst-GPU modes only where [`AVAILABLE`].
pub fn set_mode(mode: Mode) -> Result<(), Unavailable> {
    if !AVAILABLE && mode != Mode::Exact {
        return Err(Unavailable);
    }
    MODE.store(pack(mode), Ordering::Relaxed);
    Ok(())
}

/// The packed form of `mode` (see [`MODE`]).
fn pack(mode: Mode) -> u64 {
    match mode {
        Mode::Exact => 0,
        Mode::WorstGpu(Direction::Up) => 1,
        Mode::WorstGpu(Direction::Down) => 2,
        Mode::WorstGpu(Direction::Mixed(seed)) => 3 | (u64::from(seed) << 32),
    }
}

/// The current mode.
pub fn mode() -> Mode {
    unpack(MODE.load(Ordering::Relaxed))
}

/// The mode packed by [`pack`].
fn unpack(packed: u64) -> Mode {
    match packed & 3 {
        0 => Mode::Exact,
        1 => Mode::WorstGpu(Direction::Up),
        2 => Mode::WorstGpu(Direction::Down),
        _ => Mode::WorstGpu(Direction::Mixed((packed >> 32) as u32)),
    }
}

/// The packed mode when it is not exact (the slow path's entry test); always `None`
/// without the `worst-gpu` feature, so the builtins compile to the plain functions.
#[inline(always)]
fn worst() -> Option<u64> {
    if !AVAILABLE {
        return None;
    }
    match MODE.load(Ordering::Relaxed) {
        0 => None,
        m => Some(m),
    }
}

/// The builtins whose results [`Mode::WorstGpu`] moves, for the per-call hash.
#[derive(Clone, Copy)]
enum Builtin {
    Exp = 1,
    Exp2,
    Log,
    Log2,
    Sqrt,
    Cross,
}

/// Whether the result of `builtin` at `args` moves up under the packed mode `m`.
fn moves_up(m: u64, builtin: Builtin, args: &[f32]) -> bool {
    match m & 3 {
        1 => true,
        2 => false,
        _ => {
            // SplitMix64's finaliser over the seed, the builtin and the argument bits.
            let mut h = (m >> 32) ^ ((builtin as u64) << 56);
            for a in args {
                h = h.rotate_left(23) ^ u64::from(a.to_bits());
                h ^= h >> 30;
                h = h.wrapping_mul(0xbf58_476d_1ce4_e5b9);
                h ^= h >> 27;
                h = h.wrapping_mul(0x94d0_49bb_1331_11eb);
                h ^= h >> 31;
            }
            h & 1 == 1
        }
    }
}

/// Zero for a subnormal `x` (sign kept), as a GPU may flush it (WGSL §15.7.2); else `x`.
#[inline]
fn flush(x: f32) -> f32 {
    if x != 0.0 && x.abs() < f32::MIN_POSITIVE {
        0.0f32.copysign(x)
    } else {
        x
    }
}

/// `r` moved by `n` ULP up (towards +∞) or down, saturating at ±`f32::MAX` and at zero
/// (a move never crosses zero); non-finite values stay.
fn move_ulps(r: f32, n: u32, up: bool) -> f32 {
    if !r.is_finite() || n == 0 {
        return r;
    }
    let mag = r.abs().to_bits();
    let grow = up == (r > 0.0) || r == 0.0 && up;
    let bits = if grow {
        mag.saturating_add(n).min(f32::MAX.to_bits())
    } else {
        mag.saturating_sub(n)
    };
    let out = f32::from_bits(bits);
    if r < 0.0 || (r == 0.0 && !up) {
        -out
    } else {
        out
    }
}

/// `r` moved by `e` (absolute) up or down, rounded to f32.
fn move_abs(r: f32, e: f64, up: bool) -> f32 {
    if !r.is_finite() {
        return r;
    }
    (r as f64 + if up { e } else { -e }) as f32
}

/// 2⁻²¹: the absolute error WGSL allows `log` and `log2` inside [0.5, 2].
pub const LOG_ABS: f64 = 1.0 / 2_097_152.0;
/// The ULP a worst GPU's `sqrt` may be off: inherited from `1.0 / inverseSqrt(x)`, 2 ULP of
/// `inverseSqrt` and 2.5 of the division, rounded down to whole ULP.
pub const SQRT_ULPS: u32 = 4;

/// The ULP WGSL allows `exp(x)` and `exp2(x)`: 3 + 2|x|.
fn exp_ulps(x: f32) -> u32 {
    (3.0 + 2.0 * x.abs()).min(1e9) as u32
}

/// `exp` or `exp2` of a worst GPU: 3 + 2|x| ULP.
#[cold]
fn exp_worst(m: u64, x: f32, builtin: Builtin) -> f32 {
    let x = flush(x);
    let exact = match builtin {
        Builtin::Exp => x.exp(),
        _ => x.exp2(),
    };
    flush(move_ulps(exact, exp_ulps(x), moves_up(m, builtin, &[x])))
}

/// WGSL `exp(x)`.
#[inline]
pub fn exp(x: f32) -> f32 {
    match worst() {
        None => x.exp(),
        Some(m) => exp_worst(m, x, Builtin::Exp),
    }
}

/// WGSL `exp2(x)`.
#[inline]
pub fn exp2(x: f32) -> f32 {
    match worst() {
        None => x.exp2(),
        Some(m) => exp_worst(m, x, Builtin::Exp2),
    }
}

/// `log` or `log2` of a worst GPU: 2⁻²¹ absolute inside [0.5, 2], 3 ULP outside.
#[cold]
fn log_worst(m: u64, x: f32, builtin: Builtin) -> f32 {
    let x = flush(x);
    let exact = match builtin {
        Builtin::Log => x.ln(),
        _ => x.log2(),
    };
    let up = moves_up(m, builtin, &[x]);
    flush(if (0.5..=2.0).contains(&x) {
        move_abs(exact, LOG_ABS, up)
    } else {
        move_ulps(exact, 3, up)
    })
}

/// WGSL `log(x)` (natural).
#[inline]
pub fn log(x: f32) -> f32 {
    match worst() {
        None => x.ln(),
        Some(m) => log_worst(m, x, Builtin::Log),
    }
}

/// WGSL `log2(x)`.
#[inline]
pub fn log2(x: f32) -> f32 {
    match worst() {
        None => x.log2(),
        Some(m) => log_worst(m, x, Builtin::Log2),
    }
}

/// WGSL `pow(x, y)`: inherited from `exp2(y · log2(x))`, so undefined (NaN here) for
/// `x < 0`, and for `x = 0` with `y ≤ 0`.
#[inline]
pub fn pow(x: f32, y: f32) -> f32 {
    match worst() {
        None => x.powf(y),
        Some(m) => pow_worst(m, x, y),
    }
}

/// [`pow`] of a worst GPU, composed as the specification defines it.
#[cold]
fn pow_worst(m: u64, x: f32, y: f32) -> f32 {
    exp_worst(m, flush(y) * log_worst(m, x, Builtin::Log2), Builtin::Exp2)
}

/// WGSL `sqrt(x)`: inherited from `1.0 / inverseSqrt(x)` ([`SQRT_ULPS`]).
#[inline]
pub fn sqrt(x: f32) -> f32 {
    match worst() {
        None => x.sqrt(),
        Some(m) => sqrt_worst(m, x),
    }
}

/// [`sqrt`] of a worst GPU.
#[cold]
fn sqrt_worst(m: u64, x: f32) -> f32 {
    let x = flush(x);
    flush(move_ulps(
        x.sqrt(),
        SQRT_ULPS,
        moves_up(m, Builtin::Sqrt, &[x]),
    ))
}

/// WGSL `cross(a, b)`: inherited from `a[i]·b[j] − a[j]·b[i]`, which a compiler may contract
/// into a fused multiply-add: a worst GPU fuses one of the two products of each component
/// (the one chosen by the direction), so the difference of two equal products is the
/// rounding error of one of them rather than 0.
#[inline]
pub fn cross(a: Vec3, b: Vec3) -> Vec3 {
    match worst() {
        None => a.cross(b),
        Some(m) => cross_worst(m, a, b),
    }
}

/// [`cross`] of a worst GPU.
#[cold]
fn cross_worst(m: u64, a: Vec3, b: Vec3) -> Vec3 {
    let component = |p: f32, q: f32, r: f32, s: f32| {
        // p·q − r·s with one product exact.
        if moves_up(m, Builtin::Cross, &[p, q, r, s]) {
            p.mul_add(q, -(r * s))
        } else {
            -(r.mul_add(s, -(p * q)))
        }
    };
    Vec3::new(
        component(a.y, b.z, a.z, b.y),
        component(a.z, b.x, a.x, b.z),
        component(a.x, b.y, a.y, b.x),
    )
}

#[cfg(test)]
mod tests {
    //! The mode is process-global and other unit tests run beside these, so these call the
    //! worst-GPU paths with a packed mode of their own and never set it.
    use super::*;

    const UP: u64 = 1;
    const DOWN: u64 = 2;

    #[test]
    fn exact_mode_is_the_libm_result() {
        assert_eq!(mode(), Mode::Exact);
        for x in [0.3f32, 1.7, -2.9, 1000.0] {
            assert_eq!(exp(x / 100.0), (x / 100.0).exp());
            assert_eq!(exp2(x / 100.0), (x / 100.0).exp2());
            assert_eq!(sqrt(x.abs()), x.abs().sqrt());
        }
        for mode in [
            Mode::Exact,
            Mode::WorstGpu(Direction::Up),
            Mode::WorstGpu(Direction::Down),
            Mode::WorstGpu(Direction::Mixed(0xdead_beef)),
        ] {
            assert_eq!(unpack(pack(mode)), mode);
        }
    }

    #[test]
    fn worst_results_move_by_the_stated_error() {
        // log(1.5) = 0.4054651081081644 (f64), inside [0.5, 2]: moved by 2⁻²¹ either way.
        let up = log_worst(UP, 1.5, Builtin::Log) as f64;
        let down = log_worst(DOWN, 1.5, Builtin::Log) as f64;
        assert!(
            (up - (0.4054651081081644 + 1.0 / 2_097_152.0)).abs() < 3e-8,
            "{up}"
        );
        assert!(
            (down - (0.4054651081081644 - 1.0 / 2_097_152.0)).abs() < 3e-8,
            "{down}"
        );
        // exp2(10) = 1024 exactly; 3 + 20 = 23 ULP of 1024 (2⁻¹³ each) up, and below a power
        // of two the ULP halves: 1024 − 23·2⁻¹⁴.
        assert_eq!(exp_worst(UP, 10.0, Builtin::Exp2), 1024.0 + 23.0 / 8192.0);
        assert_eq!(
            exp_worst(DOWN, 10.0, Builtin::Exp2),
            1024.0 - 23.0 / 16384.0
        );
        // log2 inside [0.5, 2]: 2⁻²¹ absolute even where the result is 0; outside, 3 ULP.
        assert_eq!(log_worst(UP, 1.0, Builtin::Log2), 1.0 / 2_097_152.0);
        assert_eq!(
            log_worst(DOWN, 8.0, Builtin::Log2),
            f32::from_bits(3.0f32.to_bits() - 3)
        );
        // pow(2, 3) = exp2(3 · log2 2): log2 2 = 1 + 2⁻²¹, times 3, then 3 + 2·3 ULP up.
        let t = (3.0f64 * (1.0 + 1.0 / 2_097_152.0)) as f32;
        let want = f32::from_bits(t.exp2().to_bits() + (3.0 + 2.0 * t) as u32);
        assert_eq!(pow_worst(UP, 2.0, 3.0), want);
        // A subnormal argument is flushed: exp(−1e−40) = exp(0) = 1, then 3 ULP.
        assert_eq!(
            exp_worst(UP, -1e-40, Builtin::Exp),
            f32::from_bits(1.0f32.to_bits() + 3)
        );
        // sqrt(4) = 2, 4 ULP down (below 2 the ULP is 2⁻²³).
        assert_eq!(sqrt_worst(DOWN, 4.0), 2.0 - 4.0 / 8_388_608.0);
    }

    #[test]
    fn mixed_moves_both_ways_and_repeats_itself() {
        let mixed = pack(Mode::WorstGpu(Direction::Mixed(7)));
        let at = |k: i32| exp_worst(mixed, k as f32 * 0.01, Builtin::Exp);
        let ups = (0..256)
            .filter(|&k| at(k) > (k as f32 * 0.01).exp())
            .count();
        assert!((64..192).contains(&ups), "{ups} of 256 moved up");
        assert!((0..256).all(|k| at(k) == at(k)));
    }

    #[test]
    fn a_worst_cross_of_parallel_vectors_is_a_rounding_error_not_zero() {
        let a = Vec3::new(1.1, 1.3, 1.7);
        assert_eq!(a.cross(a), Vec3::ZERO);
        let worst = cross_worst(UP, a, a);
        assert_ne!(worst, Vec3::ZERO);
        // Each component is at most the rounding error of one product: ≤ 2⁻²⁴ · 2.21.
        assert!(
            worst.abs().max_element() <= 2.21 * 2f32.powi(-24),
            "{worst}"
        );
    }
}
