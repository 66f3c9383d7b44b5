//! CIEDE2000 colour difference (Sharma, Wu & Dalal 2005, "The CIEDE2000 Color-Difference
//! Formula: Implementation Notes, Supplementary Test Data, and Mathematical Observations",
//! Color Res. Appl. 30(1), eqs. 1–17), and linear sRGB → CIELAB (IEC 61966-2-1 inverse
//! matrix; CIE 015:2018 eqs. 8.1–8.3, white D65 = the matrix's image of (1, 1, 1)).
//! Used by the report's render-space error; tested against Sharma et al.'s Table 1 in
//! tests/models/thin_film.rs.

/// CIEDE2000 ΔE00 between two CIELAB colours, kL = kC = kH = 1.
pub fn delta_e_2000(lab1: [f64; 3], lab2: [f64; 3]) -> f64 {
    use std::f64::consts::PI;
    let deg = PI / 180.0;
    let [l1, a1, b1] = lab1;
    let [l2, a2, b2] = lab2;
    // Eqs. 2–3: C*ab, mean, G.
    let c1 = a1.hypot(b1);
    let c2 = a2.hypot(b2);
    let cm = 0.5 * (c1 + c2);
    let cm7 = cm.powi(7);
    let g = 0.5 * (1.0 - (cm7 / (cm7 + 25f64.powi(7))).sqrt());
    // Eqs. 4–7: a', C', h'.
    let a1p = (1.0 + g) * a1;
    let a2p = (1.0 + g) * a2;
    let c1p = a1p.hypot(b1);
    let c2p = a2p.hypot(b2);
    let hue = |b: f64, a: f64| {
        if a == 0.0 && b == 0.0 {
            0.0
        } else {
            let h = b.atan2(a) / deg;
            if h < 0.0 { h + 360.0 } else { h }
        }
    };
    let h1p = hue(b1, a1p);
    let h2p = hue(b2, a2p);
    // Eqs. 8–12: differences.
    let dlp = l2 - l1;
    let dcp = c2p - c1p;
    let dhp = if c1p * c2p == 0.0 {
        0.0
    } else {
        let d = h2p - h1p;
        if d > 180.0 {
            d - 360.0
        } else if d < -180.0 {
            d + 360.0
        } else {
            d
        }
    };
    let dhhp = 2.0 * (c1p * c2p).sqrt() * (0.5 * dhp * deg).sin();
    // Eqs. 13–17: means, weights, rotation.
    let lpm = 0.5 * (l1 + l2);
    let cpm = 0.5 * (c1p + c2p);
    let hpm = if c1p * c2p == 0.0 {
        h1p + h2p
    } else if (h1p - h2p).abs() <= 180.0 {
        0.5 * (h1p + h2p)
    } else if h1p + h2p < 360.0 {
        0.5 * (h1p + h2p + 360.0)
    } else {
        0.5 * (h1p + h2p - 360.0)
    };
    let t = 1.0 - 0.17 * ((hpm - 30.0) * deg).cos()
        + 0.24 * ((2.0 * hpm) * deg).cos()
        + 0.32 * ((3.0 * hpm + 6.0) * deg).cos()
        - 0.20 * ((4.0 * hpm - 63.0) * deg).cos();
    let dtheta = 30.0 * (-((hpm - 275.0) / 25.0).powi(2)).exp();
    let cpm7 = cpm.powi(7);
    let rc = 2.0 * (cpm7 / (cpm7 + 25f64.powi(7))).sqrt();
    let l50 = (lpm - 50.0).powi(2);
    let sl = 1.0 + 0.015 * l50 / (20.0 + l50).sqrt();
    let sc = 1.0 + 0.045 * cpm;
    let sh = 1.0 + 0.015 * cpm * t;
    let rt = -(2.0 * dtheta * deg).sin() * rc;
    let (x, y, z) = (dlp / sl, dcp / sc, dhhp / sh);
    (x * x + y * y + z * z + rt * y * z).sqrt()
}

/// Linear sRGB → CIE XYZ (IEC 61966-2-1 inverse matrix), Y = 1 for (1, 1, 1).
pub fn srgb_to_xyz(rgb: [f64; 3]) -> [f64; 3] {
    const M: [[f64; 3]; 3] = [
        [0.4124, 0.3576, 0.1805],
        [0.2126, 0.7152, 0.0722],
        [0.0193, 0.1192, 0.9505],
    ];
    M.map(|row| row[0] * rgb[0] + row[1] * rgb[1] + row[2] * rgb[2])
}

/// Linear sRGB → CIELAB with the white (1, 1, 1) (CIE 015:2018 eqs. 8.1–8.3; negative
/// tristimulus values, out of the sRGB gamut, use the linear branch).
pub fn srgb_to_lab(rgb: [f64; 3]) -> [f64; 3] {
    let white = srgb_to_xyz([1.0; 3]);
    let xyz = srgb_to_xyz(rgb);
    let d: f64 = 6.0 / 29.0;
    let f = |t: f64| {
        if t > d * d * d {
            t.cbrt()
        } else {
            t / (3.0 * d * d) + 4.0 / 29.0
        }
    };
    let [fx, fy, fz] = [0, 1, 2].map(|k| f(xyz[k] / white[k]));
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}
