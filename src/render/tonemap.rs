//! From linear scene radiance to display pixels: exposure, the Khronos PBR Neutral tone
//! mapper, and the sRGB transfer function.
//!
//! Khronos PBR Neutral (Khronos 3D Commerce, 2024) keeps base colours under moderate light
//! exactly as they are (below a peak of 0.76 only a tiny black offset is removed) and rolls
//! highlights off smoothly, so a material's albedo reads true in previews. Source:
//! <https://github.com/KhronosGroup/ToneMapping/blob/main/PBR_Neutral/README.md>.

/// Where highlight compression starts: 0.8 − F90 (0.04).
const START_COMPRESSION: f32 = 0.8 - 0.04;
/// Desaturation of compressed highlights.
const DESATURATION: f32 = 0.15;

/// Khronos PBR Neutral tone mapping of a linear RGB colour (values ≥ 0) into [0, 1].
pub fn pbr_neutral(c: [f32; 3]) -> [f32; 3] {
    let [mut r, mut g, mut b] = c.map(|x| if x.is_finite() { x.max(0.0) } else { 0.0 });
    let x = r.min(g).min(b);
    let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
    r -= offset;
    g -= offset;
    b -= offset;
    let peak = r.max(g).max(b);
    if peak < START_COMPRESSION {
        return [r, g, b];
    }
    let d = 1.0 - START_COMPRESSION;
    let new_peak = 1.0 - d * d / (peak + d - START_COMPRESSION);
    let scale = new_peak / peak;
    let (r, g, b) = (r * scale, g * scale, b * scale);
    let t = 1.0 - 1.0 / (DESATURATION * (peak - new_peak) + 1.0);
    [
        r + (new_peak - r) * t,
        g + (new_peak - g) * t,
        b + (new_peak - b) * t,
    ]
}

/// The sRGB opto-electronic transfer function (IEC 61966-2-1) of a linear value in [0, 1].
pub fn srgb_encode(x: f32) -> f32 {
    let x = x.clamp(0.0, 1.0);
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// The inverse of [`srgb_encode`].
pub fn srgb_decode(v: f32) -> f32 {
    let v = v.clamp(0.0, 1.0);
    if v <= 0.040_45 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// A display pixel from linear radiance: `2^exposure` scale, PBR Neutral, sRGB, 8 bits
/// (rounded to nearest).
pub fn to_srgb8(c: [f32; 3], exposure: f32) -> [u8; 3] {
    scaled_to_srgb8(c, exposure.exp2())
}

/// [`to_srgb8`] with the exposure's scale `2^exposure` already computed (an image's pixels
/// share it).
pub(crate) fn scaled_to_srgb8(c: [f32; 3], scale: f32) -> [u8; 3] {
    pbr_neutral(c.map(|x| x * scale)).map(srgb8_encode)
}

/// The 8-bit sRGB code of a linear value: `round(255 · srgb_encode(x))`, found in the table
/// of the 255 linear values where the code steps up ([`srgb8_thresholds`]). The encode, the
/// scale and the rounding are each monotone in `x`, so the code is the number of thresholds
/// at or below `x`: the same byte as the formula for every `f32` (NaN and negatives give 0),
/// at 8 comparisons instead of a `powf`.
pub fn srgb8_encode(x: f32) -> u8 {
    srgb8_thresholds().partition_point(|&t| t <= x) as u8
}

/// `round(255 · srgb_encode(x))` evaluated as written (the definition [`srgb8_encode`]
/// tabulates).
fn srgb8_formula(x: f32) -> u8 {
    (srgb_encode(x) * 255.0).round() as u8
}

/// For each code `k` in 1..=255, the least `f32` in [0, 1] whose [`srgb8_formula`] code is
/// at least `k`: bisection over the bit patterns of [0, 1], which order as the values do.
/// Built once (255 × 30 evaluations).
fn srgb8_thresholds() -> &'static [f32; 255] {
    static TABLE: std::sync::OnceLock<[f32; 255]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        std::array::from_fn(|i| {
            let k = i as u8 + 1;
            let (mut lo, mut hi) = (0u32, 1.0f32.to_bits());
            // Invariant: code(lo) < k ≤ code(hi) (code(0) = 0, code(1) = 255).
            while hi - lo > 1 {
                let mid = lo + (hi - lo) / 2;
                if srgb8_formula(f32::from_bits(mid)) >= k {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            f32::from_bits(hi)
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base_colours_below_the_knee_pass_through() {
        // Above the 0.08 toe the only change is the 0.04 offset.
        let c = pbr_neutral([0.5, 0.3, 0.2]);
        for (got, want) in c.iter().zip([0.46, 0.26, 0.16]) {
            assert!((got - want).abs() < 1e-6, "{c:?}");
        }
    }

    #[test]
    fn highlights_are_compressed_below_one() {
        for peak in [1.0f32, 4.0, 100.0, 1e6] {
            let c = pbr_neutral([peak, peak * 0.5, 0.1]);
            assert!(c.iter().all(|&x| (0.0..=1.0).contains(&x)), "{peak}: {c:?}");
        }
        // Monotonic in brightness.
        let a = pbr_neutral([2.0, 2.0, 2.0])[0];
        let b = pbr_neutral([3.0, 3.0, 3.0])[0];
        assert!(b > a);
    }

    #[test]
    fn srgb_round_trips_and_hits_reference_points() {
        assert!((srgb_encode(0.5) - 0.735_356_6).abs() < 1e-6);
        assert!((srgb_encode(0.002) - 0.02584).abs() < 1e-6);
        for i in 0..=100 {
            let x = i as f32 / 100.0;
            assert!((srgb_decode(srgb_encode(x)) - x).abs() < 1e-5);
        }
        assert_eq!(to_srgb8([0.0; 3], 0.0), [0, 0, 0]);
        // NaN and negative radiance show as black; a huge highlight desaturates to white.
        assert_eq!(to_srgb8([f32::NAN, -1.0, 0.0], 0.0), [0, 0, 0]);
        assert_eq!(to_srgb8([1e9, 0.0, 0.0], 0.0), [255, 255, 255]);
    }

    /// The sRGB curve in f64 (IEC 61966-2-1), the independent reference of the 8-bit table.
    fn encode_f64(x: f64) -> f64 {
        let x = x.clamp(0.0, 1.0);
        if x <= 0.003_130_8 {
            12.92 * x
        } else {
            1.055 * x.powf(1.0 / 2.4) - 0.055
        }
    }

    #[test]
    fn srgb8_table_gives_the_formulas_byte() {
        // Each code's threshold and the float just below it, then seeded random f32 points
        // in [0, 1] (bit patterns, so that small values are as dense as f32 makes them) and
        // out of it.
        let mut points: Vec<f32> = vec![0.0, -0.0, 1.0, -1.0, 2.0, f32::NAN, f32::INFINITY];
        for &t in srgb8_thresholds() {
            points.extend([t, f32::from_bits(t.to_bits() - 1)]);
        }
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..200_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            points.push(f32::from_bits(
                (state % (1.0f32.to_bits() as u64 + 1)) as u32,
            ));
            points.push((state >> 40) as f32 / (1u64 << 24) as f32);
        }
        for x in points {
            assert_eq!(srgb8_encode(x), srgb8_formula(x), "x = {x:e}");
        }
    }

    #[test]
    fn srgb8_codes_match_the_f64_curve() {
        // Against the curve in f64: the same code wherever the f64 value lies more than
        // 1e-4 of a code from a rounding tie (f32's powf may round the other way there).
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut checked = 0;
        for i in 0..100_000u64 {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let x = match i {
                0..=255 => srgb_decode(i as f32 / 255.0),
                _ => (state >> 40) as f32 / (1u64 << 24) as f32,
            };
            let v = encode_f64(x as f64) * 255.0;
            if (v - v.floor() - 0.5).abs() < 1e-4 {
                continue;
            }
            assert_eq!(
                srgb8_encode(x) as f64,
                v.round(),
                "x = {x:e}, 255·encode = {v}"
            );
            checked += 1;
        }
        assert!(checked > 99_000);
        // Code k's threshold decodes near (k − ½)/255.
        for (i, &t) in srgb8_thresholds().iter().enumerate() {
            let v = encode_f64(t as f64) * 255.0;
            assert!((v - (i as f64 + 0.5)).abs() < 1e-3, "code {}: {v}", i + 1);
        }
    }
}
