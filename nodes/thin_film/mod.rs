//! Thin-film interference (docs/models/thin_film.md): a dielectric film of index `n_f` and
//! thickness `d` between an outside medium `n_1` and a substrate `n_3` (a soap bubble is the
//! free film `n_1 = n_3 = 1`), reflected and transmitted colour in linear sRGB by four
//! methods: the spectral reference, Belcour & Barla 2017's analytic integration, three
//! wavelengths, and the Airy sum's Fourier series integrated through a table of the spectral
//! weights' cosine transform.
//!
//! Airy summation per polarisation (Born & Wolf, *Principles of Optics*, 7th ed., §1.6.4 "A
//! homogeneous dielectric film" and §7.6.1), with Fresnel amplitudes in Hecht's convention
//! (*Optics*, 4th ed., eqs. 4.42–4.45):
//! `r = (r12 + r23 E) / (1 + r12 r23 E)`, `t = t12 t23 E^½ / (1 + r12 r23 E)`,
//! `E = e^{iδ}`, `δ = 2π · 2 n_f d cosθ_f / λ`, `R = |r|²`,
//! `T = n3 Re(cosθ3) / (n1 cosθ1) · |t|²`, averaged over s and p. Under total internal
//! reflection at either face the cosine beyond it is imaginary (`cosθ = i√(−cos²θ)`, the
//! decaying wave), so the same formulas give frustrated TIR through the film and `R = 1`,
//! `T = 0` at a TIR exit.

#[rustfmt::skip]
mod cie_tables;

pub use cie_tables::{
    CMF_1931_2DEG, D65, LAMBDA_MIN_NM, LEN, RGB3_INV_NM, RGB3_NM, SRGB_COS, SRGB_COS_LEN,
    SRGB_COS_STEP_NM, SRGB_WEIGHTS,
};

use crate::node::{Category, In, NodeType, Out, WgslChoice, WgslTable};
use crate::nodes::optics::{COS2_T_WGSL, cos2_transmitted};
use crate::nodes::precise::{SIN_COS_WGSL, sin_cos};
use crate::precision::{exp, sqrt};
use crate::value::Value;
use glam::Vec3;
use std::f32::consts::{PI, TAU};

/// Largest film thickness accepted (nm); larger linked values are clamped to it.
pub const THICKNESS_MAX_NM: f32 = 10_000.0;
/// Smallest index of refraction accepted; linked values below are clamped to it.
pub const IOR_MIN: f32 = 1.0;
/// Largest index of refraction accepted; linked values above are clamped to it.
pub const IOR_MAX: f32 = 4.0;

/// |cos θ| below this counts as exactly grazing (R = 1, T = 0, every method). What it costs:
/// below it the true T is O(cos θ) < 1e-11 and R is 1 to f32's precision, except on
/// interference resonances narrower (~cos θ in phase) than an f32 phase resolves, where a
/// free film's R dips to 0; the f32 terms of the Airy sum are O(cos² θ) and underflow from
/// about 1e-19 on (denormal cosines gave NaN).
pub const GRAZING_COS: f32 = 1e-12;

/// Names of the `method` choices, in index order.
pub const METHOD_NAMES: &[&str] = &["spectral", "belcour_barla", "rgb3", "table"];
/// `method` choice: the spectral reference.
pub const SPECTRAL: i32 = 0;
/// `method` choice: Belcour & Barla 2017.
pub const BELCOUR_BARLA: i32 = 1;
/// `method` choice: three wavelengths.
pub const RGB3: i32 = 2;
/// `method` choice: the Fourier series through the cosine table ([`table`]).
pub const TABLE: i32 = 3;

/// The table method stops summing harmonics once the rest of the series is bounded by this
/// (in R, for each polarisation's half of the average).
pub const TABLE_TAIL: f32 = 5e-6;
/// The most harmonics the table method sums (reached only within a few degrees of grazing).
pub const TABLE_HARMONICS: u32 = 64;
/// The optical path difference (nm) of [`SRGB_COS`]'s last row; the transform is taken as 0
/// from there on.
pub const TABLE_OPD_END_NM: f32 = SRGB_COS_STEP_NM * (SRGB_COS_LEN - 1) as f32;

/// A complex number, for the Fresnel amplitudes and the film's phase factor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct C {
    /// Real part.
    pub re: f32,
    /// Imaginary part.
    pub im: f32,
}

impl C {
    const ZERO: C = C { re: 0.0, im: 0.0 };
    const ONE: C = C { re: 1.0, im: 0.0 };
    fn add(self, b: C) -> C {
        C {
            re: self.re + b.re,
            im: self.im + b.im,
        }
    }
    fn sub(self, b: C) -> C {
        C {
            re: self.re - b.re,
            im: self.im - b.im,
        }
    }
    fn mul(self, b: C) -> C {
        C {
            re: self.re * b.re - self.im * b.im,
            im: self.re * b.im + self.im * b.re,
        }
    }
    fn scale(self, k: f32) -> C {
        C {
            re: self.re * k,
            im: self.im * k,
        }
    }
    /// |z|².
    fn norm2(self) -> f32 {
        self.re * self.re + self.im * self.im
    }
    fn div(self, b: C) -> C {
        let d = b.norm2();
        C {
            re: (self.re * b.re + self.im * b.im) / d,
            im: (self.im * b.re - self.re * b.im) / d,
        }
    }
}

/// The cosine of the angle in a medium from Snell's law, `cos²θ = (1 − η)(1 + η) + (η cosθi)²`
/// ([`cos2_transmitted`]), `η = n_i / n`: real, or `i√(−cos²θ)` (a decaying wave) past the
/// critical angle.
fn cos_in(cos_i: f32, eta: f32) -> C {
    let k = cos2_transmitted(cos_i, eta);
    if k >= 0.0 {
        C {
            re: sqrt(k),
            im: 0.0,
        }
    } else {
        C {
            re: 0.0,
            im: sqrt(-k),
        }
    }
}

/// A face's `1 − |r|²` from its pair (see [`faces`]): `4 Re(x ȳ) / |x + y|²`, which keeps its
/// relative precision where `|r| → 1` (grazing, where `1 − |r|²` by subtraction is 0 or
/// negative in f32); 0 under total internal reflection (`x ȳ` imaginary).
fn face_t(x: C, y: C) -> f32 {
    4.0 * (x.re * y.re + x.im * y.im) / x.add(y).norm2()
}

/// One polarisation of one face, from medium a (index `na`, cosine `ca`) into b, as the pair
/// `(x, y)` with `r = (x − y)/(x + y)` and `t = 2 na ca/(x + y)` (Hecht, *Optics* eqs.
/// 4.42–4.45): s `(na ca, nb cb)`, p `(nb ca, na cb)`.
fn faces(na: f32, ca: C, nb: f32, cb: C) -> [(C, C); 2] {
    [(ca.scale(na), cb.scale(nb)), (ca.scale(nb), cb.scale(na))]
}

/// A film at one angle: everything of the Airy sum that does not depend on the wavelength.
///
/// Besides `r12`, `r23` and `p = r12 r23` it keeps `q = 1 + r12 r23` and `n0 = r12 + r23` in
/// the cancellation-free forms `q = 2(x1 x2 + y1 y2)/((x1 + y1)(x2 + y2))` and
/// `n0 = 2(x1 x2 − y1 y2)/((x1 + y1)(x2 + y2))` (from `r = (x − y)/(x + y)` per face), and the
/// sum is evaluated as `r = (n0 + r23 (E − 1)) / (q + p (E − 1))` with
/// `E − 1 = 2i sin(δ/2) e^{iδ/2}`: near grazing `|r12| → 1` and `1 + r12 r23 E` would cancel.
#[derive(Clone, Copy, Debug)]
pub struct Film {
    /// Outside → film amplitudes, s and p.
    pub r12: [C; 2],
    /// Film → substrate amplitudes, s and p.
    pub r23: [C; 2],
    /// `r12 r23`, s and p.
    pub p: [C; 2],
    /// `1 + r12 r23`, s and p.
    pub q: [C; 2],
    /// `r12 + r23`, s and p.
    pub n0: [C; 2],
    /// `n3 Re(cosθ3) / (n1 cosθ1) · |t12 t23|²`, s and p.
    pub tau: [f32; 2],
    /// `1 − |r12|²` without cancellation ([`face_t`]), s and p.
    pub t12: [f32; 2],
    /// `1 − |r23|²` without cancellation ([`face_t`]), s and p.
    pub t23: [f32; 2],
    /// Optical path difference `2 n_f d cosθ_f` in nm; imaginary when the film is beyond
    /// its critical angle (the wave in it decays).
    pub opd: C,
    /// Light arrives grazing (`|cosθ| <` [`GRAZING_COS`], 0 included): all of it is
    /// reflected, at every λ (the other fields are those of `|cosθ| =` [`GRAZING_COS`]).
    pub grazing: bool,
    /// The film is beyond its critical angle (its cosine is imaginary: the wave in it
    /// decays), also at thickness 0 where `opd` is 0.
    pub evanescent: bool,
}

impl Film {
    /// The film for `cos_theta` in the outside medium; `cos_theta < 0` is light arriving from
    /// the substrate side (the outside and substrate indices swap, as in
    /// [`fresnel_dielectric`](crate::nodes::optics::fresnel_dielectric)). The thickness is
    /// clamped to [0, [`THICKNESS_MAX_NM`]], the indices to [[`IOR_MIN`], [`IOR_MAX`]]; below
    /// [`GRAZING_COS`] the light is grazing. A face between equal indices is no interface
    /// (`r = 0`, `t = 1`).
    pub fn new(
        cos_theta: f32,
        thickness_nm: f32,
        film_ior: f32,
        outside_ior: f32,
        substrate_ior: f32,
    ) -> Film {
        let d = thickness_nm.clamp(0.0, THICKNESS_MAX_NM);
        let nf = film_ior.clamp(IOR_MIN, IOR_MAX);
        let no = outside_ior.clamp(IOR_MIN, IOR_MAX);
        let ns = substrate_ior.clamp(IOR_MIN, IOR_MAX);
        let (n1, n3, c) = if cos_theta >= 0.0 {
            (no, ns, cos_theta.min(1.0))
        } else {
            (ns, no, (-cos_theta).min(1.0))
        };
        let grazing = c < GRAZING_COS;
        let c = c.max(GRAZING_COS);
        let c1 = C { re: c, im: 0.0 };
        let cf = cos_in(c, n1 / nf);
        let c3 = cos_in(c, n1 / n3);
        let f12 = faces(n1, c1, nf, cf);
        let f23 = faces(nf, cf, n3, c3);
        // |t12|² ∝ cos²θ1: the quotient is finite down to the smallest normal cosine.
        let k = n3 * c3.re / (n1 * c);
        let mut film = Film {
            r12: [C::ZERO; 2],
            r23: [C::ZERO; 2],
            p: [C::ZERO; 2],
            q: [C::ONE; 2],
            n0: [C::ZERO; 2],
            tau: [0.0; 2],
            t12: [1.0; 2],
            t23: [1.0; 2],
            opd: cf.scale(2.0 * nf * d),
            grazing,
            evanescent: cf.im != 0.0,
        };
        for j in 0..2 {
            let ((x1, y1), (x2, y2)) = (f12[j], f23[j]);
            let (d1, d2) = (x1.add(y1), x2.add(y2));
            let (r12, t12) = if n1 == nf {
                (C::ZERO, C::ONE)
            } else {
                (x1.sub(y1).div(d1), c1.scale(2.0 * n1).div(d1))
            };
            let (r23, t23) = if nf == n3 {
                (C::ZERO, C::ONE)
            } else {
                (x2.sub(y2).div(d2), cf.scale(2.0 * nf).div(d2))
            };
            let (q, n0) = if n1 == nf {
                (C::ONE, r23)
            } else if nf == n3 {
                (C::ONE, r12)
            } else {
                let dd = d1.mul(d2);
                let (u, v) = (x1.mul(x2), y1.mul(y2));
                (u.add(v).scale(2.0).div(dd), u.sub(v).scale(2.0).div(dd))
            };
            film.r12[j] = r12;
            film.r23[j] = r23;
            film.p[j] = r12.mul(r23);
            film.q[j] = q;
            film.n0[j] = n0;
            film.tau[j] = k * (t12.norm2() * t23.norm2());
            if n1 != nf {
                film.t12[j] = face_t(x1, y1);
            }
            if nf != n3 {
                film.t23[j] = face_t(x2, y2);
            }
        }
        film
    }

    /// Unpolarised `(R, T)` at the wavelength `1 / inv_lambda_nm`. The half phase is reduced
    /// to [−π/2, π/2] in cycles (`δ/2π = opd/λ`) before the sine, so GPUs (whose `sin` is
    /// only specified on [−π, π]) and the CPU agree for thick films. `R` is capped at 1 and `T`
    /// at `1 − R`, which moves them by f32 rounding only (the exact sum has `R + T = 1`).
    #[inline]
    pub fn at(&self, inv_lambda_nm: f32) -> (f32, f32) {
        let cycles = self.opd.re * inv_lambda_nm;
        let half = PI * (cycles - (cycles + 0.5).floor());
        let (decay, em1) = if self.opd.im == 0.0 {
            let (s, c) = sin_cos(half);
            (
                1.0,
                C {
                    re: -2.0 * (s * s),
                    im: 2.0 * (s * c),
                },
            )
        } else {
            let decay = exp(-TAU * (self.opd.im * inv_lambda_nm));
            (
                decay,
                C {
                    re: decay - 1.0,
                    im: 0.0,
                },
            )
        };
        let mut r = 0.0;
        let mut t = 0.0;
        for k in 0..2 {
            let num = self.n0[k].add(self.r23[k].mul(em1));
            let den = self.q[k].add(self.p[k].mul(em1)).norm2();
            r += num.norm2() / den;
            t += self.tau[k] * decay / den;
        }
        let r = (0.5 * r).min(1.0);
        (r, (0.5 * t).min(1.0 - r))
    }
}

/// Per-wavelength unpolarised reflectance and transmittance `(R, T)` of the film at `lambda_nm`
/// (see [`Film::new`] for the inputs' conventions); grazing light gives (1, 0).
pub fn airy(
    cos_theta: f32,
    lambda_nm: f32,
    thickness_nm: f32,
    film_ior: f32,
    outside_ior: f32,
    substrate_ior: f32,
) -> (f32, f32) {
    let film = Film::new(
        cos_theta,
        thickness_nm,
        film_ior,
        outside_ior,
        substrate_ior,
    );
    if film.grazing {
        return (1.0, 0.0);
    }
    film.at(1.0 / lambda_nm)
}

/// [`SRGB_WEIGHTS`]' channel sums as [`spectral`]'s loop adds them in f32 (1 ± 1e-6; the f64
/// weights sum to 1), so that a flat spectrum divided by them is exactly that value.
pub const SRGB_WEIGHT_SUMS: [f32; 3] = weight_sums();

/// [`SRGB_WEIGHT_SUMS`], summed in [`spectral`]'s order.
const fn weight_sums() -> [f32; 3] {
    let mut s = [0.0f32; 3];
    let mut k = 0;
    while k < LEN {
        s[0] += SRGB_WEIGHTS[k][0];
        s[1] += SRGB_WEIGHTS[k][1];
        s[2] += SRGB_WEIGHTS[k][2];
        k += 1;
    }
    s
}

/// The spectral reference: `Σ_λ w(λ) R(λ)` over 360–830 nm at 1 nm with the linear sRGB
/// weights of D65 × CIE 1931 2° ([`SRGB_WEIGHTS`], each channel summing to 1), likewise `T`,
/// divided by the f32 sums of the weights ([`SRGB_WEIGHT_SUMS`]) so that a flat R of 1 (a
/// grazing or totally reflecting film) is exactly white, not 1 + 1e-6.
pub fn spectral(film: &Film) -> (Vec3, Vec3) {
    let mut r = Vec3::ZERO;
    let mut t = Vec3::ZERO;
    for w in &SRGB_WEIGHTS {
        let (rl, tl) = film.at(w[3]);
        let wv = Vec3::new(w[0], w[1], w[2]);
        r += wv * rl;
        t += wv * tl;
    }
    let sums = Vec3::from(SRGB_WEIGHT_SUMS);
    (r / sums, t / sums)
}

/// Three wavelengths, one per channel ([`RGB3_NM`]: 600.2, 539.1, 453.4 nm, each channel's
/// mean wavelength over the positive lobe of its spectral weight).
pub fn rgb3(film: &Film) -> (Vec3, Vec3) {
    let [r0, r1, r2] = RGB3_INV_NM.map(|k| film.at(k));
    (Vec3::new(r0.0, r1.0, r2.0), Vec3::new(r0.1, r1.1, r2.1))
}

/// Belcour & Barla's Gaussian fit of the CIE 1931 XYZ matching functions in wavenumber
/// (their supplemental code, `evalSensitivity`), per lobe (x̄, ȳ, z̄, x̄'s second lobe):
/// amplitude `val √(2π var) / 1.0685e-7`.
const BB_AMP: [f32; 4] = [0.84659, 1.0002219, 1.0011225, 0.1538683];
/// The lobes' centres `pos` × 1e-9: cycles per nm of optical path difference.
const BB_POS_NM: [f32; 4] = [0.001681, 0.0017953, 0.0022084, 0.0022399];
/// The lobes' widths `var (2π · 1e-9)²`: the exponent per nm² of optical path difference.
const BB_VAR_NM: [f32; 4] = [1.708547e-7, 3.6733088e-7, 2.6103525e-7, 1.7876617e-7];
/// IEC 61966-2-1 XYZ → linear sRGB, each row divided by its product with the fit's white
/// `S(0) = (1.00046, 1.00022, 1.00112)` (rows of the matrix, applied as `row · xyz`), so that
/// a flat reflectance of 1 gives (1, 1, 1).
const BB_XYZ_TO_RGB: [[f32; 3]; 3] = [
    [2.688437, -1.2752778, -0.41364397],
    [-1.0215951, 1.9778183, 0.043757043],
    [0.061217755, -0.22420866, 1.1617086],
];

/// Belcour & Barla's sensitivity `S(m·opd, 0)` in XYZ for m = 0…3 (the Fourier transform of
/// the matching functions, evaluated with their Gaussian fit): per lobe
/// `amp cos(2π m pos·opd) exp(−var (m·opd)²)`. One cosine and one exponential per lobe: the
/// cycles `pos·opd` are reduced to [−½, ½] before the cosine, `cos(m x)` follows by Chebyshev's
/// recurrence (`cos 2x = 2c² − 1`, `cos 3x = c (4c² − 3)`), and `exp(−var (m opd)²) = e^{m²}`.
/// A phase shift φ = π multiplies harmonic m by (−1)^m, which the caller applies.
#[inline]
fn bb_sensitivities(opd_nm: f32) -> [Vec3; 4] {
    let o2 = opd_nm * opd_nm;
    let lobe = |k: usize| {
        let cycles = BB_POS_NM[k] * opd_nm;
        let c = sin_cos(TAU * (cycles - (cycles + 0.5).floor())).1;
        let c2 = 2.0 * (c * c) - 1.0;
        let c3 = c * (4.0 * (c * c) - 3.0);
        let e = exp(-BB_VAR_NM[k] * o2);
        let e4 = (e * e) * (e * e);
        let a = BB_AMP[k];
        [a, a * c * e, a * c2 * e4, a * c3 * (e4 * e4 * e)]
    };
    let (x, x2, y, z) = (lobe(0), lobe(3), lobe(1), lobe(2));
    [0, 1, 2, 3].map(|m| Vec3::new(x[m] + x2[m], y[m], z[m]))
}

/// One polarisation's Airy reflectance as the Fourier series in the phase δ (Belcour & Barla
/// 2017, eq. 9): `R(δ) = c0 + 2 Σ_{m≥1} c · root^m cos(m δ)`, with `c0 = R12 + Rs`,
/// `c = Rs − T121`, `Rs = T121² R23 / (1 − R12 R23)`, `T121 = 1 − R12`, the differences
/// taken from the faces' cancellation-free `1 − R` ([`Film::t12`], [`Film::t23`]:
/// `1 − R12 R23 = T12 + R12 T23`, which near grazing is 0 by subtraction), and
/// `root = ±√(R12 R23)`: the phase φ = arg(r21 r23) = arg(−r12 r23) is π when r12 r23 > 0,
/// which turns harmonic m by (−1)^m (the sign of `root`).
#[derive(Clone, Copy, Debug)]
struct AirySeries {
    c0: f32,
    c: f32,
    root: f32,
}

impl AirySeries {
    /// The series of the faces with amplitudes `r12`, `r23` and `1 − |r|²` `t12`, `t23`.
    #[inline]
    fn new(r12: C, r23: C, t12: f32, t23: f32) -> AirySeries {
        let big_r12 = r12.norm2();
        let big_r23 = r23.norm2();
        let t121 = t12;
        let r123 = big_r12 * big_r23;
        let den = t12 + big_r12 * t23;
        let rs = if den > 0.0 {
            t121 * t121 * big_r23 / den
        } else {
            0.0
        };
        let root = if r12.re * r23.re > 0.0 {
            -sqrt(r123)
        } else {
            sqrt(r123)
        };
        AirySeries {
            c0: big_r12 + rs,
            c: rs - t121,
            root,
        }
    }
}

/// One polarisation of [`belcour_barla`]: `C0 S(0) + Σ_{m=1..3} 2 Cm S(m·opd)` in XYZ.
#[inline]
fn bb_polarisation(film: &Film, j: usize, s: &[Vec3; 4]) -> Vec3 {
    let a = AirySeries::new(film.r12[j], film.r23[j], film.t12[j], film.t23[j]);
    let mut cm = a.c;
    let mut xyz = a.c0 * s[0];
    for sm in &s[1..] {
        cm *= a.root;
        xyz += (2.0 * cm) * *sm;
    }
    xyz
}

/// Belcour & Barla 2017 (ACM TOG 36(4), "A Practical Extension to Microfacet Theory for the
/// Modeling of Varying Iridescence"), as in the authors' supplemental shader (`Airy`,
/// `evalSensitivity`; restated in Khronos' KHR_materials_iridescence): the
/// Airy reflectance written as the Fourier series `R(δ) = C0 + 2 Σ_m Cm cos(m (δ + φ))`,
/// `C0 = R12 + Rs`, `Cm = (Rs − T121) (√(R12 R23))^m`, `Rs = T121² R23 / (1 − R12 R23)`,
/// `T121 = 1 − R12`, φ the phase of `r21 r23` (0 or π for real amplitudes), each term
/// integrated against the matching functions analytically, `m ≤ 3`. XYZ → linear sRGB with
/// [`BB_XYZ_TO_RGB`] (their fit is of the bare matching functions, illuminant E, so the
/// white is balanced to (1, 1, 1); the reference uses D65). Returns reflectance; the film is
/// lossless, so transmittance is `1 − R`. Limits, stated: beyond the film's critical angle
/// it returns R = 1 (no tunnelling through the film: the model has `T121 = 0` there), and
/// the series is cut at m = 3, which costs about 2 |Rs − T121| (R12 R23)² of the d → 0 limit:
/// 3e-7 for water, but 5.3e-3 for a film of index 3 between air and 1.0587 (R = 6.09e-3 at
/// d = 0 where the interface alone gives 8.13e-4; measured with `matgraph eval`).
pub fn belcour_barla(film: &Film) -> Vec3 {
    if film.evanescent {
        return Vec3::ONE;
    }
    let s = bb_sensitivities(film.opd.re);
    let mut xyz = Vec3::ZERO;
    xyz += bb_polarisation(film, 0, &s);
    xyz += bb_polarisation(film, 1, &s);
    let xyz = 0.5 * xyz;
    Vec3::new(
        Vec3::from(BB_XYZ_TO_RGB[0]).dot(xyz),
        Vec3::from(BB_XYZ_TO_RGB[1]).dot(xyz),
        Vec3::from(BB_XYZ_TO_RGB[2]).dot(xyz),
    )
}

/// [`SRGB_COS`] at `x` nm of optical path difference (`x ≥ 0`), linearly interpolated between
/// its rows; 0 from [`TABLE_OPD_END_NM`] on.
#[inline]
fn srgb_cos(x: f32) -> Vec3 {
    let u = x / SRGB_COS_STEP_NM;
    if u.is_nan() || u >= (SRGB_COS_LEN - 1) as f32 {
        return Vec3::ZERO;
    }
    let i = u as usize;
    let f = u - i as f32;
    let a = Vec3::from_slice(&SRGB_COS[i][..3]);
    let b = Vec3::from_slice(&SRGB_COS[i + 1][..3]);
    a + (b - a) * f
}

/// The Airy sum's Fourier series ([`AirySeries`], as [`belcour_barla`]) with each harmonic
/// integrated against the spectral method's own weights: since `Σ_λ w(λ) = 1` and
/// `cos(m δ) = cos(2π m·opd/λ)`, `Σ_λ w(λ) R(λ) = ½ Σ_{s,p} [c0 + 2 Σ_m c root^m T(m·opd)]`
/// exactly, with `T(x) = Σ_λ w(λ) cos(2π x/λ)` the weights' cosine transform, tabulated in
/// [`SRGB_COS`] (every 5 nm to 10 235 nm, f64 sums by nodes/thin_film/gen_cie_tables.py) and
/// read linearly. The same D65 × CIE 1931 weights as the reference, so no Gaussian fit and
/// no white balance; what it leaves out, stated: harmonics past the point where the rest of
/// the series is below [`TABLE_TAIL`] per polarisation or past [`TABLE_HARMONICS`] (only
/// within a few degrees of grazing), `T` beyond 10 235 nm (|T| < 0.012 there, times the
/// harmonic's |2 c root^m| ≤ 0.04 for soap at normal incidence), the linear interpolation
/// (|ΔT| < 6e-4), and, as Belcour & Barla, tunnelling: beyond the film's critical angle it
/// returns R = 1. Returns reflectance; the film is lossless, so transmittance is `1 − R`.
pub fn table(film: &Film) -> Vec3 {
    if film.evanescent {
        return Vec3::ONE;
    }
    let s = AirySeries::new(film.r12[0], film.r23[0], film.t12[0], film.t23[0]);
    let p = AirySeries::new(film.r12[1], film.r23[1], film.t12[1], film.t23[1]);
    let mut rgb = Vec3::splat(0.5 * (s.c0 + p.c0));
    let (mut cs, mut cp) = (s.c, p.c);
    for m in 1..=TABLE_HARMONICS {
        cs *= s.root;
        cp *= p.root;
        let x = m as f32 * film.opd.re;
        if x >= TABLE_OPD_END_NM {
            break;
        }
        rgb += (cs + cp) * srgb_cos(x);
        // What is left of each polarisation's half: |c root^m| |root| / (1 − |root|).
        let done_s = (cs * s.root).abs() <= TABLE_TAIL * (1.0 - s.root.abs());
        let done_p = (cp * p.root).abs() <= TABLE_TAIL * (1.0 - p.root.abs());
        if done_s && done_p {
            break;
        }
    }
    rgb
}

/// The node's compute: `(reflectance, transmittance)` in linear sRGB by `method`
/// ([`SPECTRAL`], [`BELCOUR_BARLA`], [`RGB3`], [`TABLE`]; any other value is spectral).
pub fn thin_film(
    cos_theta: f32,
    thickness_nm: f32,
    film_ior: f32,
    outside_ior: f32,
    substrate_ior: f32,
    method: i32,
) -> (Vec3, Vec3) {
    let film = Film::new(
        cos_theta,
        thickness_nm,
        film_ior,
        outside_ior,
        substrate_ior,
    );
    if film.grazing {
        return (Vec3::ONE, Vec3::ZERO);
    }
    match method {
        BELCOUR_BARLA => {
            let r = belcour_barla(&film);
            (r, Vec3::ONE - r)
        }
        RGB3 => rgb3(&film),
        TABLE => {
            let r = table(&film);
            (r, Vec3::ONE - r)
        }
        _ => spectral(&film),
    }
}

/// WGSL of the complex helpers, [`cos_in`], [`faces`], [`Film`] and [`Film::at`]: the
/// same steps. Complex numbers are `vec2<f32>` (re, im).
const FILM_WGSL: &str = r#"
fn mg_tf_mul(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
}
fn mg_tf_norm2(a: vec2<f32>) -> f32 {
    return a.x * a.x + a.y * a.y;
}
fn mg_tf_div(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    let d = mg_tf_norm2(b);
    return vec2<f32>((a.x * b.x + a.y * b.y) / d, (a.y * b.x - a.x * b.y) / d);
}
fn mg_tf_cos_in(cos_i: f32, eta: f32) -> vec2<f32> {
    let k = mg_opth_cos2_t(cos_i, eta);
    if (k >= 0.0) {
        return vec2<f32>(sqrt(k), 0.0);
    }
    return vec2<f32>(0.0, sqrt(-k));
}
struct MgTfFilm {
    r12s: vec2<f32>,
    r12p: vec2<f32>,
    r23s: vec2<f32>,
    r23p: vec2<f32>,
    ps: vec2<f32>,
    pp: vec2<f32>,
    qs: vec2<f32>,
    qp: vec2<f32>,
    n0s: vec2<f32>,
    n0p: vec2<f32>,
    tau: vec2<f32>,
    t12: vec2<f32>,
    t23: vec2<f32>,
    opd: vec2<f32>,
    grazing: bool,
    evanescent: bool,
}
struct MgTfRt {
    r: vec3<f32>,
    t: vec3<f32>,
}
struct MgTfPol {
    r12: vec2<f32>,
    r23: vec2<f32>,
    q: vec2<f32>,
    n0: vec2<f32>,
    tau: f32,
    t12: f32,
    t23: f32,
}
fn mg_tf_face_t(x: vec2<f32>, y: vec2<f32>) -> f32 {
    return 4.0 * (x.x * y.x + x.y * y.y) / mg_tf_norm2(x + y);
}
fn mg_tf_pol(x1: vec2<f32>, y1: vec2<f32>, x2: vec2<f32>, y2: vec2<f32>, c1: vec2<f32>, cf: vec2<f32>, n1: f32, nf: f32, n3: f32, k: f32) -> MgTfPol {
    let d1 = x1 + y1;
    let d2 = x2 + y2;
    var r12 = vec2<f32>(0.0);
    var t12 = vec2<f32>(1.0, 0.0);
    var u12 = 1.0;
    if (n1 != nf) {
        r12 = mg_tf_div(x1 - y1, d1);
        t12 = mg_tf_div(c1 * (2.0 * n1), d1);
        u12 = mg_tf_face_t(x1, y1);
    }
    var r23 = vec2<f32>(0.0);
    var t23 = vec2<f32>(1.0, 0.0);
    var u23 = 1.0;
    if (nf != n3) {
        r23 = mg_tf_div(x2 - y2, d2);
        t23 = mg_tf_div(cf * (2.0 * nf), d2);
        u23 = mg_tf_face_t(x2, y2);
    }
    var q = vec2<f32>(1.0, 0.0);
    var n0 = r12;
    if (n1 == nf) {
        n0 = r23;
    } else if (nf != n3) {
        let dd = mg_tf_mul(d1, d2);
        let u = mg_tf_mul(x1, x2);
        let v = mg_tf_mul(y1, y2);
        q = mg_tf_div((u + v) * 2.0, dd);
        n0 = mg_tf_div((u - v) * 2.0, dd);
    }
    return MgTfPol(r12, r23, q, n0, k * (mg_tf_norm2(t12) * mg_tf_norm2(t23)), u12, u23);
}
fn mg_tf_film(cos_theta: f32, thickness_nm: f32, film_ior: f32, outside_ior: f32, substrate_ior: f32) -> MgTfFilm {
    let d = min(max(thickness_nm, 0.0), 10000.0);
    let nf = min(max(film_ior, 1.0), 4.0);
    let no = min(max(outside_ior, 1.0), 4.0);
    let ns = min(max(substrate_ior, 1.0), 4.0);
    var n1 = no;
    var n3 = ns;
    var c0 = min(cos_theta, 1.0);
    if (cos_theta < 0.0) {
        n1 = ns;
        n3 = no;
        c0 = min(-cos_theta, 1.0);
    }
    let c = max(c0, 1e-12);
    let c1 = vec2<f32>(c, 0.0);
    let cf = mg_tf_cos_in(c, n1 / nf);
    let c3 = mg_tf_cos_in(c, n1 / n3);
    let k = n3 * c3.x / (n1 * c);
    let s = mg_tf_pol(c1 * n1, cf * nf, cf * nf, c3 * n3, c1, cf, n1, nf, n3, k);
    let p = mg_tf_pol(c1 * nf, cf * n1, cf * n3, c3 * nf, c1, cf, n1, nf, n3, k);
    return MgTfFilm(s.r12, p.r12, s.r23, p.r23, mg_tf_mul(s.r12, s.r23), mg_tf_mul(p.r12, p.r23), s.q, p.q, s.n0, p.n0, vec2<f32>(s.tau, p.tau), vec2<f32>(s.t12, p.t12), vec2<f32>(s.t23, p.t23), cf * (2.0 * nf * d), c0 < 1e-12, cf.y != 0.0);
}
fn mg_tf_at(f: MgTfFilm, inv_lambda_nm: f32) -> vec2<f32> {
    let cycles = f.opd.x * inv_lambda_nm;
    let half = 3.14159265358979324 * (cycles - floor(cycles + 0.5));
    var decay = 1.0;
    var em1: vec2<f32>;
    if (f.opd.y == 0.0) {
        let sc = mg_prec_sincos(half);
        let s = sc.x;
        let c = sc.y;
        em1 = vec2<f32>(-2.0 * (s * s), 2.0 * (s * c));
    } else {
        decay = exp(-6.28318530717958648 * (f.opd.y * inv_lambda_nm));
        em1 = vec2<f32>(decay - 1.0, 0.0);
    }
    let num_s = f.n0s + mg_tf_mul(f.r23s, em1);
    let den_s = mg_tf_norm2(f.qs + mg_tf_mul(f.ps, em1));
    let num_p = f.n0p + mg_tf_mul(f.r23p, em1);
    let den_p = mg_tf_norm2(f.qp + mg_tf_mul(f.pp, em1));
    let r = min(0.5 * (mg_tf_norm2(num_s) / den_s + mg_tf_norm2(num_p) / den_p), 1.0);
    let t = min(0.5 * (f.tau.x * decay / den_s + f.tau.y * decay / den_p), 1.0 - r);
    return vec2<f32>(r, t);
}
"#;

/// WGSL of [`AirySeries`]: the same steps.
const SERIES_WGSL: &str = r#"
struct MgTfSeries {
    c0: f32,
    c: f32,
    root: f32,
}
fn mg_tf_series(r12: vec2<f32>, r23: vec2<f32>, t12: f32, t23: f32) -> MgTfSeries {
    let big_r12 = mg_tf_norm2(r12);
    let big_r23 = mg_tf_norm2(r23);
    let t121 = t12;
    let r123 = big_r12 * big_r23;
    let den = t12 + big_r12 * t23;
    var rs = 0.0;
    if (den > 0.0) {
        rs = t121 * t121 * big_r23 / den;
    }
    let root = select(sqrt(r123), -sqrt(r123), r12.x * r23.x > 0.0);
    return MgTfSeries(big_r12 + rs, rs - t121, root);
}
"#;

/// WGSL of [`table`] and [`srgb_cos`] (the `MgParams` table `mg_tf_cos`): the same steps and
/// constants; `mg_tf_method_table` is the node's method at `table`.
const TABLE_WGSL: &str = r#"
fn mg_tf_cos_at(x: f32) -> vec3<f32> {
    let u = x / 5.0;
    if (!(u < 2047.0)) {
        return vec3<f32>(0.0);
    }
    let i = u32(u);
    let f = u - f32(i);
    let a = mg_params.mg_tf_cos[i].xyz;
    let b = mg_params.mg_tf_cos[i + 1u].xyz;
    return a + (b - a) * f;
}
fn mg_tf_table(f: MgTfFilm) -> vec3<f32> {
    if (f.evanescent) {
        return vec3<f32>(1.0);
    }
    let s = mg_tf_series(f.r12s, f.r23s, f.t12.x, f.t23.x);
    let p = mg_tf_series(f.r12p, f.r23p, f.t12.y, f.t23.y);
    var rgb = vec3<f32>(0.5 * (s.c0 + p.c0));
    var cs = s.c;
    var cp = p.c;
    for (var m = 1u; m <= 64u; m++) {
        cs *= s.root;
        cp *= p.root;
        let x = f32(m) * f.opd.x;
        if (x >= 10235.0) {
            break;
        }
        rgb += (cs + cp) * mg_tf_cos_at(x);
        let done_s = abs(cs * s.root) <= 5e-6 * (1.0 - abs(s.root));
        let done_p = abs(cp * p.root) <= 5e-6 * (1.0 - abs(p.root));
        if (done_s && done_p) {
            break;
        }
    }
    return rgb;
}
fn mg_tf_method_table(f: MgTfFilm, method: i32) -> MgTfRt {
    let r = mg_tf_table(f);
    return MgTfRt(r, vec3<f32>(1.0) - r);
}
"#;

/// WGSL of [`belcour_barla`] and its sensitivity: the same steps and constants;
/// `mg_tf_method_belcour_barla` is the node's method at `belcour_barla`.
const BELCOUR_BARLA_WGSL: &str = r#"
struct MgTfBbS {
    s0: vec3<f32>,
    s1: vec3<f32>,
    s2: vec3<f32>,
    s3: vec3<f32>,
}
fn mg_tf_bb_lobe(amp: f32, pos: f32, var_nm: f32, opd_nm: f32, o2: f32) -> vec4<f32> {
    let cycles = pos * opd_nm;
    let c = mg_prec_sincos(6.28318530717958648 * (cycles - floor(cycles + 0.5))).y;
    let c2 = 2.0 * (c * c) - 1.0;
    let c3 = c * (4.0 * (c * c) - 3.0);
    let e = exp(-var_nm * o2);
    let e4 = (e * e) * (e * e);
    return vec4<f32>(amp, amp * c * e, amp * c2 * e4, amp * c3 * (e4 * e4 * e));
}
fn mg_tf_bb_sensitivities(opd_nm: f32) -> MgTfBbS {
    let o2 = opd_nm * opd_nm;
    let x = mg_tf_bb_lobe(0.84659, 0.001681, 1.708547e-7, opd_nm, o2);
    let x2 = mg_tf_bb_lobe(0.1538683, 0.0022399, 1.7876617e-7, opd_nm, o2);
    let y = mg_tf_bb_lobe(1.0002219, 0.0017953, 3.6733088e-7, opd_nm, o2);
    let z = mg_tf_bb_lobe(1.0011225, 0.0022084, 2.6103525e-7, opd_nm, o2);
    let xs = x + x2;
    return MgTfBbS(vec3<f32>(xs.x, y.x, z.x), vec3<f32>(xs.y, y.y, z.y), vec3<f32>(xs.z, y.z, z.z), vec3<f32>(xs.w, y.w, z.w));
}
fn mg_tf_bb_pol(r12: vec2<f32>, r23: vec2<f32>, t12: f32, t23: f32, s: MgTfBbS) -> vec3<f32> {
    let a = mg_tf_series(r12, r23, t12, t23);
    var cm = a.c;
    var xyz = a.c0 * s.s0;
    cm *= a.root;
    xyz += (2.0 * cm) * s.s1;
    cm *= a.root;
    xyz += (2.0 * cm) * s.s2;
    cm *= a.root;
    xyz += (2.0 * cm) * s.s3;
    return xyz;
}
fn mg_tf_belcour_barla(f: MgTfFilm) -> vec3<f32> {
    if (f.evanescent) {
        return vec3<f32>(1.0);
    }
    let s = mg_tf_bb_sensitivities(f.opd.x);
    var xyz = vec3<f32>(0.0);
    xyz += mg_tf_bb_pol(f.r12s, f.r23s, f.t12.x, f.t23.x, s);
    xyz += mg_tf_bb_pol(f.r12p, f.r23p, f.t12.y, f.t23.y, s);
    xyz = 0.5 * xyz;
    return vec3<f32>(
        dot(vec3<f32>(2.688437, -1.2752778, -0.41364397), xyz),
        dot(vec3<f32>(-1.0215951, 1.9778183, 0.043757043), xyz),
        dot(vec3<f32>(0.061217755, -0.22420866, 1.1617086), xyz),
    );
}
fn mg_tf_method_belcour_barla(f: MgTfFilm, method: i32) -> MgTfRt {
    let r = mg_tf_belcour_barla(f);
    return MgTfRt(r, vec3<f32>(1.0) - r);
}
"#;

/// WGSL of [`spectral`], the node's method at `spectral`: `(R, T)` as `MgTfRt`.
const SPECTRAL_WGSL: &str = r#"
const MG_TF_W_SUMS = vec3<f32>(1.0, 1.000001, 1.0000006);
fn mg_tf_method_spectral(f: MgTfFilm, method: i32) -> MgTfRt {
    var r = vec3<f32>(0.0);
    var t = vec3<f32>(0.0);
    for (var k = 0u; k < 471u; k++) {
        let w = mg_params.mg_tf_w[k];
        let rt = mg_tf_at(f, w.w);
        r += w.xyz * rt.x;
        t += w.xyz * rt.y;
    }
    return MgTfRt(r / MG_TF_W_SUMS, t / MG_TF_W_SUMS);
}
"#;

/// WGSL of [`rgb3`], the node's method at `rgb3`: `(R, T)` as `MgTfRt`.
const RGB3_FN_WGSL: &str = r#"
fn mg_tf_method_rgb3(f: MgTfFilm, method: i32) -> MgTfRt {
    let a = mg_tf_at(f, MG_TF_RGB3_INV.x);
    let b = mg_tf_at(f, MG_TF_RGB3_INV.y);
    let c = mg_tf_at(f, MG_TF_RGB3_INV.z);
    return MgTfRt(vec3<f32>(a.x, b.x, c.x), vec3<f32>(a.y, b.y, c.y));
}
"#;

/// WGSL of [`thin_film`] (the node): the film, exactly grazing light, then the method
/// (`mg_tf_method_<choice>` where `method` is written, else [`METHOD_WGSL`]'s pick).
const THIN_FILM_WGSL: &str = r#"
fn $fn(cos_theta: f32, thickness_nm: f32, film_ior: f32, outside_ior: f32, substrate_ior: f32, method: i32) -> $out {
    let f = mg_tf_film(cos_theta, thickness_nm, film_ior, outside_ior, substrate_ior);
    if (f.grazing) {
        return $out(vec3<f32>(1.0), vec3<f32>(0.0));
    }
    let rt = mg_tf_method${method}(f, method);
    return $out(rt.r, rt.t);
}
"#;

/// WGSL of the `method` chosen at run time (any other value is spectral, as on the CPU).
const METHOD_WGSL: &str = r#"
fn mg_tf_method(f: MgTfFilm, method: i32) -> MgTfRt {
    if (method == 1) {
        return mg_tf_method_belcour_barla(f, method);
    }
    if (method == 2) {
        return mg_tf_method_rgb3(f, method);
    }
    if (method == 3) {
        return mg_tf_method_table(f, method);
    }
    return mg_tf_method_spectral(f, method);
}
"#;

/// [`SRGB_WEIGHTS`] as the `MgParams` table `mg_tf_w` that the spectral method's WGSL loop
/// reads (a uniform array: as a WGSL `const` it took lavapipe minutes to compile).
pub static SRGB_WEIGHTS_TABLE: WgslTable = WgslTable {
    field: "mg_tf_w",
    rows: &SRGB_WEIGHTS,
};

/// [`SRGB_COS`] as the `MgParams` table `mg_tf_cos` that the table method's WGSL reads.
pub static SRGB_COS_TABLE: WgslTable = WgslTable {
    field: "mg_tf_cos",
    rows: &SRGB_COS,
};

/// The tables of the spectral and of the table method.
static SPECTRAL_TABLES: [&WgslTable; 1] = [&SRGB_WEIGHTS_TABLE];
static TABLE_TABLES: [&WgslTable; 1] = [&SRGB_COS_TABLE];

/// Each method's helpers and tables, besides the film's.
fn method_choices() -> [WgslChoice; 4] {
    [
        WgslChoice {
            choice: "spectral",
            helpers: &[SPECTRAL_WGSL],
            tables: &SPECTRAL_TABLES,
        },
        WgslChoice {
            choice: "belcour_barla",
            helpers: &[SERIES_WGSL, BELCOUR_BARLA_WGSL],
            tables: &[],
        },
        WgslChoice {
            choice: "rgb3",
            helpers: &[cie_tables::RGB3_WGSL, RGB3_FN_WGSL],
            tables: &[],
        },
        WgslChoice {
            choice: "table",
            helpers: &[SERIES_WGSL, TABLE_WGSL],
            tables: &TABLE_TABLES,
        },
    ]
}

/// The thin-film node type.
pub fn all() -> Vec<NodeType> {
    let f = Value::float;
    vec![
        NodeType::new("thin_film", Category::Optics, "Thin-film interference colour (soap bubbles, oil slicks, coatings).")
            .source(
                "Airy summation of a dielectric film per polarisation with complex Fresnel amplitudes: \
                 r = (r12 + r23 e^{iδ})/(1 + r12 r23 e^{iδ}), δ = 4π n_f d cosθ_f/λ, R = |r|², T = n3 cosθ3/(n1 cosθ1)|t|², \
                 averaged over s and p (Born & Wolf, Principles of Optics §1.6.4, §7.6.1; Fresnel amplitudes Hecht eqs. 4.42–4.45; docs/models/thin_film.md); TIR at either face \
                 through complex cosines (frustrated TIR through the film; R = 1 at a TIR exit). \
                 method spectral (the reference): Σ over 360–830 nm at 1 nm of R(λ) with D65 × CIE 1931 2° → linear sRGB \
                 weights (IEC 61966-2-1), each channel normalised so a flat R = 1 gives (1, 1, 1); tables from \
                 colour-science by nodes/thin_film/gen_cie_tables.py. belcour_barla: Belcour & Barla 2017 (ACM TOG 36(4)) \
                 (their supplemental shader; KHR_materials_iridescence), the Fourier series of the Airy sum integrated analytically against their Gaussian fit of the \
                 XYZ matching functions (m ≤ 3; illuminant E balanced to white; R = 1 beyond the film's critical angle, no \
                 tunnelling), T = 1 − R. Cutting the series at m = 3 costs about 2|Rs − T121|(R12 R23)², most at d → 0, \
                 where every harmonic is in phase: between air and 1.0587 at normal incidence, R at d = 0 is 8.131e-4 for a \
                 film of 1.33 (the interface alone: 8.130e-4), 1.01e-3 for 2.0, 6.09e-3 for 3.0 (7.5×) and 2.28e-2 for 4.0 \
                 (28×), and up to 7% off at 100–200 nm for 3.0; use spectral or table for high-index films. table: the same Fourier series with each harmonic integrated against the spectral method's own \
                 weights through their tabulated cosine transform T(x) = Σ_λ w(λ) cos(2π x/λ) (every 5 nm of optical path to 10 235 nm, linear; 0 beyond, \
                 where |T| < 0.012), harmonics until the rest of the series is below 1e-5 (at most 64); R = 1 beyond the film's critical angle, T = 1 − R. rgb3: R at 600.2, 539.1, 453.4 nm (each channel's mean wavelength over its \
                 weight's positive lobe); wrong for films thicker than ~500 nm, where it aliases. cos_theta < 0: light from \
                 the substrate side (indices swap); grazing (|cos_theta| < 1e-12, denormals and 0 included) gives R = 1, T = 0: \
                 the true T there is below 1e-11 and R is 1 to f32 except on resonances narrower than an f32 phase resolves (below ~1e-19 \
                 the Airy terms underflow). Per wavelength R is capped at 1 and T at 1 − R (f32 rounding only); spectral divides by the \
                 f32 sums of its weights, so a flat spectrum is exactly white. Thickness is clamped to [0, 10000] nm and \
                 the indices to [1, 4]. Colours may leave [0, 1] where the film's colour is outside the sRGB gamut. \
                 f32 limits: the phase is good to ~1.5e-6 rad per cycle of 2 n_f d cosθ_f/λ (1e-5 in R at 10 µm); 1 + r12 r23 e^{iδ} is \
                 evaluated without cancellation near grazing (docs/models/thin_film.md).",
            )
            .input(In::float("cos_theta", 1.0).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Cosine of the angle of incidence in the outside medium; < 0 from the substrate side."))
            .input(In::float("thickness_nm", 400.0).range(0.0, 2000.0).hard(0.0, THICKNESS_MAX_NM).unit("nm").doc("Film thickness."))
            .input(In::float("film_ior", 1.33).range(1.0, 2.5).hard(IOR_MIN, IOR_MAX).doc("Index of refraction of the film (1.33: soapy water)."))
            .input(In::float("outside_ior", 1.0).range(1.0, 2.5).hard(IOR_MIN, IOR_MAX).doc("Index of refraction of the medium the light arrives from."))
            .input(In::float("substrate_ior", 1.0).range(1.0, 2.5).hard(IOR_MIN, IOR_MAX).doc("Index of refraction behind the film (1.0: a free film, a bubble)."))
            .input(In::choice("method", METHOD_NAMES, 0).doc("spectral: the 471-wavelength reference; belcour_barla: analytic (Belcour & Barla 2017); rgb3: three wavelengths; table: the Fourier series through the tabulated spectral weights."))
            .output(Out::color("reflectance").doc("Reflected colour for white (D65) light, linear sRGB."))
            .output(Out::color("transmittance").doc("Transmitted colour for white (D65) light, linear sRGB."))
            .wgsl(THIN_FILM_WGSL)
            .wgsl_uses(&[COS2_T_WGSL, SIN_COS_WGSL, FILM_WGSL])
            .wgsl_per_choice("method", &[METHOD_WGSL], method_choices())
            .hard_case("black film (d = 0)", &[("thickness_nm", f(0.0))])
            .hard_case("thickest film", &[("thickness_nm", f(THICKNESS_MAX_NM))])
            .hard_case("exactly grazing", &[("cos_theta", f(0.0))])
            .hard_case("very grazing", &[("cos_theta", f(1e-6))])
            .hard_case("denormal cosine, thick high-index film", &[("cos_theta", f(1e-45)), ("thickness_nm", f(2000.0)), ("film_ior", f(2.5))])
            .hard_case("denormal cosine, thick high-index film, table", &[("cos_theta", f(1e-45)), ("thickness_nm", f(2000.0)), ("film_ior", f(2.5)), ("method", Value::int(TABLE))])
            .hard_case("denormal cosine, belcour_barla", &[("cos_theta", f(-1e-40)), ("thickness_nm", f(2000.0)), ("film_ior", f(2.5)), ("method", Value::int(BELCOUR_BARLA))])
            .hard_case("just below the grazing cut", &[("cos_theta", f(9e-13)), ("thickness_nm", f(0.0))])
            .hard_case("just above the grazing cut, black film", &[("cos_theta", f(2e-12)), ("thickness_nm", f(0.0))])
            .hard_case("1e-7 from grazing, thick high-index film, table", &[("cos_theta", f(1e-7)), ("thickness_nm", f(2000.0)), ("film_ior", f(2.5)), ("method", Value::int(TABLE))])
            .hard_case("beyond the film's critical angle (frustrated TIR)", &[("cos_theta", f(0.3)), ("outside_ior", f(1.5)), ("film_ior", f(1.0)), ("substrate_ior", f(1.5)), ("thickness_nm", f(100.0))])
            .hard_case("no film beyond its critical angle, belcour_barla", &[("cos_theta", f(0.5)), ("outside_ior", f(1.96)), ("film_ior", f(1.05)), ("substrate_ior", f(1.94)), ("thickness_nm", f(0.0)), ("method", Value::int(BELCOUR_BARLA))])
            .hard_case("no film beyond its critical angle, table", &[("cos_theta", f(0.5)), ("outside_ior", f(1.96)), ("film_ior", f(1.05)), ("substrate_ior", f(1.94)), ("thickness_nm", f(0.0)), ("method", Value::int(TABLE))])
            .hard_case("TIR at the substrate", &[("cos_theta", f(0.3)), ("outside_ior", f(1.5)), ("film_ior", f(1.6)), ("substrate_ior", f(1.0))])
            .hard_case("from the substrate side", &[("cos_theta", f(-0.7)), ("substrate_ior", f(1.5))])
            .hard_case("index-matched film", &[("film_ior", f(1.0))])
            .hard_case("film matched to the substrate", &[("film_ior", f(1.5)), ("substrate_ior", f(1.5))])
            .compute(thin_film),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The WGSL's `MG_TF_W_SUMS` are the CPU's [`SRGB_WEIGHT_SUMS`], bit for bit.
    #[test]
    fn wgsl_weight_sums_are_the_cpu_ones() {
        let line = SPECTRAL_WGSL
            .lines()
            .find(|l| l.starts_with("const MG_TF_W_SUMS"))
            .unwrap();
        let inner = &line[line.find('(').unwrap() + 1..line.rfind(')').unwrap()];
        let wgsl: Vec<f32> = inner
            .split(',')
            .map(|v| v.trim().parse().unwrap())
            .collect();
        assert_eq!(wgsl, SRGB_WEIGHT_SUMS.to_vec());
        assert!(SRGB_WEIGHT_SUMS.iter().all(|s| (s - 1.0).abs() < 2e-6));
    }
}
