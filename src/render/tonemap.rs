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
    let k = exposure.exp2();
    pbr_neutral(c.map(|x| x * k)).map(|x| (srgb_encode(x) * 255.0).round() as u8)
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
}
