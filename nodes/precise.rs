//! `sin`, `cos`, `log2` and `pow` computed from the operations WGSL rounds correctly (`+`,
//! `−`, `×`, `floor`, `frexp`), for the nodes that need more accuracy than WGSL's builtins
//! promise (docs/precision.md): `sin`/`cos` are specified to 2⁻¹¹ absolute inside [−π, π] and
//! not at all outside, `log2` to 2⁻²¹ absolute near 1, and `pow` inherits both from
//! `exp2(y · log2 x)`. Each function here is written once in Rust and once in WGSL with the
//! same operations and the same f32 constants (hex literals in the WGSL, which every compiler
//! reads exactly), so the CPU and every conformant GPU agree to a few ULP: a GPU may fuse a
//! product into an add, which changes a result by at most an ULP or two of its terms.
//!
//! `sin_cos` has its WGSL (`mg_sincos`) and is used by the nodes. `log2` and `pow` are the CPU
//! halves of the fix still open for `pow` with large exponents (toon_water_shade,
//! bubble_underwater; tests/worst_gpu.rs): their WGSL lands with the nodes that use them, so
//! that it is validated and parity-tested there.
//!
//! Not guarded against: a compiler that reassociates the Cody–Waite reduction (WGSL permits
//! reassociation; no Vulkan, Metal or D3D compiler we know does it without fast-math flags).

use crate::precision;

/// 2/π rounded to f32.
const TWO_OVER_PI: f32 = 0.636_619_75;
/// π/2 split in three (Cody & Waite 1980): `C1` has 8 significant bits and `C2` 11, so `k·C1`
/// and `k·C2` are exact for |k| < 2¹³ (|x| < 1.2 × 10⁴), and `C1 + C2 + C3` is π/2 to
/// 1.8 × 10⁻¹⁵.
const PIO2_1: f32 = 1.570_312_5;
/// See [`PIO2_1`].
const PIO2_2: f32 = 4.837_513e-4;
/// See [`PIO2_1`].
const PIO2_3: f32 = 7.549_79e-8;

/// `(sin x, cos x)` to a few ULP for |x| < 1.2 × 10⁴ (the reduction is exact there), and to
/// within the argument's own rounding beyond (at |x| = 10⁶ one ULP of x is 0.06 rad); NaN
/// for a non-finite x.
///
/// Reduction `x = k·π/2 + r`, |r| ≤ π/4, with the three-part π/2 of Cody & Waite (1980), then
/// the minimax polynomials of Cephes `sinf`/`cosf` (Moshier 1989, max error 1 ULP on
/// [−π/4, π/4]) and the quadrant `k mod 4`.
#[inline]
pub fn sin_cos(x: f32) -> (f32, f32) {
    let k = (x * TWO_OVER_PI + 0.5).floor();
    let r = ((x - k * PIO2_1) - k * PIO2_2) - k * PIO2_3;
    let z = r * r;
    let s = ((-1.951_529_6e-4 * z + 8.332_161e-3) * z - 1.666_665_5e-1) * z * r + r;
    let c = ((2.443_315_7e-5 * z - 1.388_731_6e-3) * z + 4.166_664_6e-2) * z * z - 0.5 * z + 1.0;
    // k mod 4 in floats (exact for |k| < 2²⁴), so no integer conversion can overflow.
    let q = k - 4.0 * (k * 0.25).floor();
    if q == 0.0 {
        (s, c)
    } else if q == 1.0 {
        (c, -s)
    } else if q == 2.0 {
        (-s, -c)
    } else {
        (-c, s)
    }
}

/// WGSL of [`sin_cos`], `mg_sincos(x) -> vec2<f32>` (sin, cos): the same operations.
pub const SIN_COS_WGSL: &str = r#"
fn mg_sincos(x: f32) -> vec2<f32> {
    let k = floor(x * 0x1.45f306p-1f + 0.5);
    let r = ((x - k * 0x1.92p0f) - k * 0x1.fb4p-12f) - k * 0x1.4442d2p-24f;
    let z = r * r;
    let s = ((-0x1.9943f2p-13f * z + 0x1.11073cp-7f) * z - 0x1.555546p-3f) * z * r + r;
    let c = ((0x1.99eb9cp-16f * z - 0x1.6c0c34p-10f) * z + 0x1.55554ap-5f) * z * z - 0.5 * z + 1.0;
    let q = k - 4.0 * floor(k * 0.25);
    if (q == 0.0) {
        return vec2<f32>(s, c);
    }
    if (q == 1.0) {
        return vec2<f32>(c, -s);
    }
    if (q == 2.0) {
        return vec2<f32>(-s, -c);
    }
    return vec2<f32>(-c, s);
}
"#;

/// √2 / 2 rounded to f32: mantissas above it are halved into [√½, √2).
const SQRT_HALF: f32 = 0.707_106_77;

/// `log2 x` to a few ULP relative for every positive normal x (so `log2` near 1 keeps its
/// relative precision, where WGSL promises only 2⁻²¹ absolute); −∞ at 0, NaN below.
///
/// `x = m · 2ᵉ` with m in [√½, √2) (`frexp`, exact), then `ln m = 2 atanh s` with
/// `s = (m − 1)/(m + 1)`, |s| ≤ 0.172: `2 (s + s³/3 + … + s¹³/13)`, whose first omitted term is
/// below 2⁻³⁴ (Abramowitz & Stegun 4.1.27).
#[inline]
pub fn log2(x: f32) -> f32 {
    if !(x > 0.0) || x.is_infinite() {
        // 0 → −∞, negative or NaN → NaN, +∞ → +∞: as WGSL's log2 would give where defined.
        return if x == 0.0 {
            f32::NEG_INFINITY
        } else {
            x.log2()
        };
    }
    let (mut m, mut e) = frexp(x);
    if m < SQRT_HALF {
        m *= 2.0;
        e -= 1;
    }
    let s = (m - 1.0) / (m + 1.0);
    let s2 = s * s;
    let series = ((((((s2 * (1.0 / 13.0) + 1.0 / 11.0) * s2 + 1.0 / 9.0) * s2 + 1.0 / 7.0) * s2
        + 1.0 / 5.0)
        * s2
        + 1.0 / 3.0)
        * s2
        + 1.0)
        * s;
    e as f32 + series * (2.0 * std::f32::consts::LOG2_E)
}

/// `x = m · 2ᵉ` with m in [0.5, 1), as WGSL's `frexp`, for a positive normal finite x.
#[inline]
fn frexp(x: f32) -> (f32, i32) {
    let bits = x.to_bits();
    let e = ((bits >> 23) & 0xff) as i32 - 126;
    (f32::from_bits((bits & 0x807f_ffff) | (126 << 23)), e)
}

/// `x^y = exp2(y · log2 x)` for x > 0 with [`log2`] in place of WGSL's: the exponent keeps its
/// relative precision, so the result is within WGSL's `exp2` error (3 + 2|y log2 x| ULP,
/// below 2⁻¹⁶ relative wherever the result is a normal f32) however large y is. WGSL's own
/// `pow` adds |y| · 2⁻²¹ · ln 2 relative near x = 1: 3.3 × 10⁻⁴ at y = 1000.
#[inline]
pub fn pow(x: f32, y: f32) -> f32 {
    precision::exp2(y * log2(x))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::measure::SplitMix;

    /// The report's seeded SplitMix64, drawing uniform f64 in [0, 1).
    struct Rng(SplitMix);
    impl Rng {
        fn unit(&mut self) -> f64 {
            (self.0.next() >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// |got − want| in ULP of `want` (at least the ULP of 2⁻²⁴, so zeros compare absolutely).
    fn ulps(got: f32, want: f64) -> f64 {
        let ulp = (want.abs().max(2f64.powi(-24)) as f32).to_bits();
        let one = f32::from_bits(ulp + 1) as f64 - f32::from_bits(ulp) as f64;
        (got as f64 - want).abs() / one
    }

    #[test]
    fn sin_cos_is_within_a_few_ulp_of_f64() {
        let mut rng = Rng(SplitMix(0x5eed_51c0));
        let round = [
            0.0f32, 0.5, 1.0, 1.5707964, 3.1415927, -2.0, 10.0, 100.0, 1000.0, 8000.0,
        ];
        let random = (0..20_000).map(|_| ((rng.unit() * 2.0 - 1.0) * 10_000.0) as f32);
        let mut worst = 0.0f64;
        for x in round.into_iter().chain(random) {
            let (s, c) = sin_cos(x);
            // Absolute error near a zero of sin/cos, relative elsewhere: 2 ULP of max(|f|, 2⁻²⁴)
            // plus the argument's own rounding is not involved (x is f32-exact).
            let (ws, wc) = ((x as f64).sin(), (x as f64).cos());
            let e = ulps(s, ws).max(ulps(c, wc));
            worst = worst.max(e);
            assert!(
                (s as f64 - ws).abs() < 3e-7 && (c as f64 - wc).abs() < 3e-7,
                "x = {x}: ({s}, {c}) vs ({ws}, {wc})"
            );
        }
        assert!(worst < 8.0, "worst {worst} ULP");
    }

    #[test]
    fn log2_keeps_its_relative_precision_near_one() {
        let mut rng = Rng(SplitMix(0x1092));
        let round = [
            1.0f32, 2.0, 0.5, 1.0000001, 0.99999994, 3.0, 1e-30, 1e30, 0.7071067,
        ];
        let random = (0..20_000).map(|_| (2f64.powf(rng.unit() * 200.0 - 100.0)) as f32);
        for x in round.into_iter().chain(random) {
            let want = (x as f64).log2();
            let got = log2(x);
            assert!(
                ulps(got, want) < 4.0,
                "log2({x:e}) = {got:e}, want {want:e}"
            );
        }
        assert_eq!(log2(0.0), f32::NEG_INFINITY);
        assert!(log2(-1.0).is_nan());
        // Near 1 the relative precision holds where WGSL allows 2⁻²¹ absolute:
        // log2(1 + 2⁻²³) = 1.7198e-7 (f64).
        let x = 1.0f32 + f32::EPSILON;
        let want = (x as f64).log2();
        assert!(((log2(x) as f64 - want) / want).abs() < 3e-7, "{}", log2(x));
    }

    #[test]
    fn pow_is_within_its_stated_error() {
        let mut rng = Rng(SplitMix(0x90f));
        for _ in 0..20_000 {
            let x = rng.unit() as f32;
            let y = (rng.unit() * 2000.0) as f32;
            let want = (x as f64).powf(y as f64);
            if want < f32::MIN_POSITIVE as f64 {
                continue;
            }
            let t = (y as f64 * (x as f64).log2()).abs();
            // exp2 is correctly rounded on the CPU; log2's few ULP and the exponent's rounding
            // each add about |t| · 2⁻²³ relative, and exp2 a few ULP.
            let rel = ((pow(x, y) as f64 - want) / want).abs();
            assert!(
                rel < (2.0 * t + 8.0) * 2f64.powi(-23),
                "pow({x}, {y}) rel {rel:e}"
            );
        }
    }
}
