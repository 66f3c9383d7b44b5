//! `sin`, `cos`, `log2` and `pow` computed from the operations WGSL rounds correctly (`+`,
//! `−`, `×`, `floor`, bit casts), for the nodes that need more accuracy than WGSL's builtins
//! promise (docs/precision.md): `sin`/`cos` are specified to 2⁻¹¹ absolute inside [−π, π] and
//! not at all outside, `log2` to 2⁻²¹ absolute near 1, and `pow` inherits both from
//! `exp2(y · log2 x)`. Each function here is written once in Rust and once in WGSL with the
//! same operations and the same f32 constants (hex literals in the WGSL, which every compiler
//! reads exactly), so the CPU and every conformant GPU agree to a few ULP: a GPU may fuse a
//! product into an add, which changes a result by at most an ULP or two of its terms.
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

/// WGSL of [`sin_cos`], `mg_prec_sincos(x) -> vec2<f32>` (sin, cos): the same operations.
pub const SIN_COS_WGSL: &str = r#"
fn mg_prec_sincos(x: f32) -> vec2<f32> {
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

/// Coefficients `c1 … c8` of `log2(1 + x) ≈ x·(c1 + x·(c2 + … + x·c8))` on
/// x ∈ [√½ − 1, √2 − 1]: a least-squares fit on 4000 Chebyshev nodes (ours, in f64, rounded
/// to f32). Evaluated by Horner's rule in f32, the error is below 1e-7 over the interval.
pub const LOG2_COEFFS: [f32; 8] = [
    1.442_694_8,
    -0.721_357_6,
    0.480_932_3,
    -0.360_064_66,
    0.286_885_1,
    -0.250_497_34,
    0.235_715_54,
    -0.143_023_82,
];

/// log2 of a positive normal f32, from its bits: `x = m · 2^e` with m ∈ [√½, √2),
/// `log2 x = e + log2(m)`, the second term by the polynomial [`LOG2_COEFFS`] in `m − 1`
/// (exact by Sterbenz's lemma). Absolute error below 1e-7 + ulp(e); written with integer
/// operations, multiplies and adds only so that WGSL gives the same bits.
#[inline]
pub fn log2_exact(x: f32) -> f32 {
    let bits = x.to_bits();
    let mut e = (bits >> 23) as i32 - 127;
    let mut m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000);
    if m > std::f32::consts::SQRT_2 {
        m *= 0.5;
        e += 1;
    }
    let t = m - 1.0;
    let c = LOG2_COEFFS;
    let mut p = c[7];
    for k in (0..7).rev() {
        p = p * t + c[k];
    }
    e as f32 + p * t
}

/// WGSL of [`log2_exact`], the same operations in the same order.
pub const LOG2_EXACT_WGSL: &str = r#"
fn mg_log2_exact(x: f32) -> f32 {
    let bits = bitcast<u32>(x);
    var e = i32(bits >> 23u) - 127;
    var m = bitcast<f32>((bits & 0x007fffffu) | 0x3f800000u);
    if (m > 1.4142135) {
        m = m * 0.5;
        e = e + 1;
    }
    let t = m - 1.0;
    var p = -0.14302382;
    p = p * t + 0.23571554;
    p = p * t + -0.25049734;
    p = p * t + 0.2868851;
    p = p * t + -0.36006466;
    p = p * t + 0.4809323;
    p = p * t + -0.7213576;
    p = p * t + 1.4426948;
    return f32(e) + p * t;
}
"#;

/// `x^y = exp2(y · log2 x)` for positive normal x with [`log2_exact`] in place of WGSL's
/// `log2`: the exponent keeps its relative precision (8 ULP), so the result is within WGSL's
/// `exp2` error (3 + 2|y log2 x| ULP, below 2⁻¹⁶ relative wherever the result is a normal f32)
/// and 8 ULP of the exponent, however large y is. WGSL's own `pow` adds |y| · 2⁻²¹ · ln 2
/// relative near x = 1: 3.3 × 10⁻⁴ at y = 1000.
#[inline]
pub fn pow(x: f32, y: f32) -> f32 {
    precision::exp2(y * log2_exact(x))
}

/// WGSL of [`pow`], `mg_prec_pow(x, y)` for positive normal x. Needs [`LOG2_EXACT_WGSL`].
pub const POW_WGSL: &str = r#"
fn mg_prec_pow(x: f32, y: f32) -> f32 {
    return exp2(y * mg_log2_exact(x));
}
"#;

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
            0.0f32,
            0.5,
            1.0,
            std::f32::consts::FRAC_PI_2,
            std::f32::consts::PI,
            -2.0,
            10.0,
            100.0,
            1000.0,
            8000.0,
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
    fn log2_exact_against_f64() {
        // Powers of two are exact.
        for k in -126..=127 {
            let x = 2f32.powi(k);
            assert_eq!(log2_exact(x), k as f32, "2^{k}");
        }
        // Seeded random normal floats over the whole exponent range.
        let mut s = SplitMix(7);
        let mut worst = 0.0f64;
        for _ in 0..200_000 {
            let bits = (s.next() as u32 % (0x7f00_0000 - 0x0080_0000)) + 0x0080_0000;
            let x = f32::from_bits(bits);
            let want = (x as f64).log2();
            let got = log2_exact(x) as f64;
            // The error budget: the polynomial's 1e-7 plus rounding of the sum e + p.
            let err = (got - want).abs();
            let budget = 1.2e-7 + f32::EPSILON as f64 * want.abs();
            assert!(err <= budget, "log2({x:e}) = {got}, want {want}");
            worst = worst.max(err / budget);
        }
        assert!(worst > 0.0);
    }

    #[test]
    fn log2_exact_keeps_its_relative_precision_near_one() {
        // pow relies on it: log2 x is near 0 there, where WGSL's log2 promises only 2⁻²¹
        // absolute. Within 2⁻²¹ relative (8 ULP of the result) of f64, at the f32s next to 1
        // and at seeded random points within 1e-3 of it.
        let mut rng = Rng(SplitMix(0x1092));
        let next = (1..=64).flat_map(|k| {
            [
                f32::from_bits(1.0f32.to_bits() + k),
                f32::from_bits(1.0f32.to_bits() - k),
            ]
        });
        let random = (0..20_000).map(|_| (1.0 + (rng.unit() - 0.5) * 2e-3) as f32);
        for x in next.chain(random).filter(|x| *x != 1.0) {
            let want = (x as f64).log2();
            let rel = ((log2_exact(x) as f64 - want) / want).abs();
            assert!(rel < 2f64.powi(-21), "log2({x}) rel {rel:e}");
        }
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
            // exp2 is correctly rounded on the CPU; log2_exact's 8 ULP (2⁻²¹ relative) and
            // the exponent's rounding become |t| · (2⁻²¹ + 2⁻²⁴) · ln 2 relative, and exp2's
            // rounding an ULP.
            let rel = ((pow(x, y) as f64 - want) / want).abs();
            assert!(
                rel < (t * 0.7 * (2f64.powi(-21) + 2f64.powi(-24))) + 2f64.powi(-23),
                "pow({x}, {y}) rel {rel:e}"
            );
        }
    }
}
