#!/usr/bin/env python3
"""Generates nodes/thin_film/cie_tables.rs: the CIE tables of the `thin_film` node.

Source: the `colour-science` Python package (https://www.colour-science.org, version printed
in the header), which ships
  - the CIE 1931 2° standard observer at 1 nm over 360–830 nm
    (`colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]`, from CIE 015:2018 / the CIE
    data file "CIE_xyz_1931_2deg"), and
  - CIE standard illuminant D65 at 5 nm over 300–780 nm (`colour.SDS_ILLUMINANTS["D65"]`,
    from the CIE 15:2004 tables), with the CIE daylight basis S0, S1, S2 at 5 nm over
    300–830 nm (`SDS_BASIS_FUNCTIONS_CIE_ILLUMINANT_D_SERIES`).
D65 above 780 nm (785–830 nm, where ȳ < 1.1e-4) is S0 + M1 S1 + M2 S2 (CIE 015:2018 §4.1.2)
with M1, M2 fitted by least squares to the tabulated D65 over 300–780 nm (the script checks
the fit reproduces the table within 0.002); D65 is brought to 1 nm by linear interpolation, as
CIE 015 recommends for the daylight series.

Weights: XYZ -> linear sRGB with the IEC 61966-2-1 matrix, each channel's weights
w_c(λ) = Σ_j M_cj S(λ) cmf_j(λ), divided by Σ_λ w_c(λ), so that a spectrally flat reflectance
of 1 gives (1, 1, 1) exactly (in f64; the f32 sum is 1 within 1e-6).

Run: pip install colour-science && python3 nodes/thin_film/gen_cie_tables.py
"""

import math
import os
import struct
import sys
import warnings

warnings.filterwarnings("ignore")
import colour  # noqa: E402
from colour.colorimetry.datasets.illuminants.sds_d_illuminant_series import (  # noqa: E402
    SDS_BASIS_FUNCTIONS_CIE_ILLUMINANT_D_SERIES as BASIS,
)

LO, HI = 360, 830
N = HI - LO + 1

# The table method's spectral cosine transform: rows at x = k * COS_STEP_NM of optical path
# difference, k < COS_LEN (0 to 10 235 nm).
COS_STEP_NM = 5
COS_LEN = 2048

# IEC 61966-2-1:1999, XYZ (D65, Y = 1) -> linear sRGB.
M_SRGB = [
    [3.2406, -1.5372, -0.4986],
    [-0.9689, 1.8758, 0.0415],
    [0.0557, -0.2040, 1.0570],
]


def f32(x):
    """x rounded to f32."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def f32_rust(x):
    """A Rust f32 literal that reads back as f32(x) exactly (a round-tripping decimal)."""
    v = f32(x)
    for digits in range(1, 18):
        s = f"{v:.{digits}e}"
        if f32(float(s)) == v:
            return s
    raise AssertionError(x)


def wgsl_hex(x):
    """A WGSL hex float literal of f32(x), exact by construction."""
    v = f32(x)
    if v == 0.0:
        return "0.0f"
    h = float.hex(v)  # e.g. 0x1.2345600000000p-3
    mant, exp = h.split("p")
    mant = mant.rstrip("0")
    if mant.endswith("."):
        mant += "0"
    return f"{mant}p{exp}f"


def main():
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    assert cmfs.shape.start == LO and cmfs.shape.end == HI and cmfs.shape.interval == 1
    cmf = [[float(v) for v in cmfs[float(l)]] for l in range(LO, HI + 1)]

    d65_tab = colour.SDS_ILLUMINANTS["D65"]
    s0, s1, s2 = (BASIS[k] for k in ("S0", "S1", "S2"))
    # D65's coordinates in the daylight basis, by least squares over the tabulated 300–780 nm
    # (the CIE's own M1, M2 for D65 are not recoverable from eq. 4.7-4.8 at its xy to better
    # than 0.01; the fit reproduces the table within 0.05 of 100).
    ls = range(300, 781, 5)
    a11 = math.fsum(float(s1[l]) ** 2 for l in ls)
    a12 = math.fsum(float(s1[l]) * float(s2[l]) for l in ls)
    a22 = math.fsum(float(s2[l]) ** 2 for l in ls)
    b1 = math.fsum(float(s1[l]) * (float(d65_tab[l]) - float(s0[l])) for l in ls)
    b2 = math.fsum(float(s2[l]) * (float(d65_tab[l]) - float(s0[l])) for l in ls)
    det = a11 * a22 - a12 * a12
    m1 = (b1 * a22 - b2 * a12) / det
    m2 = (a11 * b2 - a12 * b1) / det
    d65_5nm = {}
    worst = 0.0
    for l in range(300, 831, 5):
        basis = float(s0[l]) + m1 * float(s1[l]) + m2 * float(s2[l])
        if l <= 780:
            d65_5nm[l] = float(d65_tab[l])
            worst = max(worst, abs(basis - d65_5nm[l]))
        else:
            d65_5nm[l] = basis
    assert worst < 0.002, worst

    def d65(l):
        a = (l // 5) * 5
        if a == l:
            return d65_5nm[l]
        t = (l - a) / 5.0
        return d65_5nm[a] * (1.0 - t) + d65_5nm[a + 5] * t

    spd = [d65(l) for l in range(LO, HI + 1)]

    weights = []
    for c in range(3):
        w = [sum(M_SRGB[c][j] * spd[k] * cmf[k][j] for j in range(3)) for k in range(N)]
        total = math.fsum(w)
        weights.append([v / total for v in w])

    # rgb3: each sRGB channel's weight-weighted mean wavelength over its positive lobe.
    rgb3 = []
    for c in range(3):
        pos = [max(v, 0.0) for v in weights[c]]
        rgb3.append(math.fsum((LO + k) * p for k, p in enumerate(pos)) / math.fsum(pos))

    # The weights' cosine transform T_c(x) = sum_l w_c(l) cos(2 pi x / l): the spectral
    # integral of one harmonic cos(m delta) of the film's Airy series at x = m * opd.
    cos_rows = []
    for k in range(COS_LEN):
        x = COS_STEP_NM * k
        cos_l = [math.cos(2.0 * math.pi * x / (LO + j)) for j in range(N)]
        cos_rows.append([math.fsum(weights[c][j] * cos_l[j] for j in range(N)) for c in range(3)])

    out = []
    out.append("//! CIE tables of the `thin_film` node. GENERATED by nodes/thin_film/gen_cie_tables.py")
    out.append(f"//! from the colour-science package {colour.__version__} (CIE 1931 2° observer at 1 nm, CIE 15:2004")
    out.append("//! D65 at 5 nm extended past 780 nm by the CIE daylight basis and linearly interpolated to")
    out.append("//! 1 nm). Do not edit; rerun the script.")
    out.append("")
    out.append("/// First wavelength of the tables, nm.")
    out.append(f"pub const LAMBDA_MIN_NM: u32 = {LO};")
    out.append("/// Number of 1 nm samples, 360..=830 nm.")
    out.append(f"pub const LEN: usize = {N};")
    out.append("")
    out.append("/// CIE 1931 2° colour-matching functions x̄, ȳ, z̄ at 360 + k nm.")
    out.append(f"pub const CMF_1931_2DEG: [[f64; 3]; LEN] = [")
    for row in cmf:
        out.append("    [" + ", ".join(repr(v) for v in row) + "],")
    out.append("];")
    out.append("")
    out.append("/// CIE D65 relative spectral power at 360 + k nm (100 at 560 nm).")
    out.append("pub const D65: [f64; LEN] = [")
    for k in range(0, N, 6):
        out.append("    " + ", ".join(repr(v) for v in spd[k : k + 6]) + ",")
    out.append("];")
    out.append("")
    out.append("/// Per wavelength 360 + k nm: the linear sRGB weights (IEC 61966-2-1 matrix times D65 × CMF,")
    out.append("/// each channel normalised to sum 1; f64, then rounded to f32) and 1/λ in 1/nm.")
    out.append("pub const SRGB_WEIGHTS: [[f32; 4]; LEN] = [")
    for k in range(N):
        vals = [weights[c][k] for c in range(3)] + [1.0 / (LO + k)]
        out.append("    [" + ", ".join(f32_rust(v) for v in vals) + "],")
    out.append("];")
    out.append("")
    out.append("/// Spacing of [`SRGB_COS`] in nm of optical path difference.")
    out.append(f"pub const SRGB_COS_STEP_NM: f32 = {COS_STEP_NM:.1f};")
    out.append("/// Rows of [`SRGB_COS`]: optical path differences 0 to")
    out.append(f"/// {COS_STEP_NM * (COS_LEN - 1)} nm.")
    out.append(f"pub const SRGB_COS_LEN: usize = {COS_LEN};")
    out.append("")
    out.append("/// The cosine transform of [`SRGB_WEIGHTS`] at x = k · [`SRGB_COS_STEP_NM`] nm of optical path")
    out.append("/// difference: `T_c(x) = Σ_λ w_c(λ) cos(2π x/λ)` per linear sRGB channel (f64 weights,")
    out.append("/// exact sums, then rounded to f32), fourth component 0. `T_c(0) = 1`.")
    out.append("pub static SRGB_COS: [[f32; 4]; SRGB_COS_LEN] = [")
    for row in cos_rows:
        out.append("    [" + ", ".join(f32_rust(v) for v in row) + ", 0.0],")
    out.append("];")
    out.append("")
    out.append("/// The rgb3 method's wavelengths (nm): each channel's mean wavelength over the positive")
    out.append(f"/// lobe of its weight, {rgb3[0]:.2f}, {rgb3[1]:.2f}, {rgb3[2]:.2f} nm, rounded to 0.1 nm.")
    rgb3 = [round(v, 1) for v in rgb3]
    out.append("pub const RGB3_NM: [f32; 3] = [" + ", ".join(f"{v:.1f}" for v in rgb3) + "];")
    out.append("/// 1 / [`RGB3_NM`] in 1/nm.")
    out.append("pub const RGB3_INV_NM: [f32; 3] = [" + ", ".join(f32_rust(1.0 / v) for v in rgb3) + "];")
    out.append("")
    out.append("/// WGSL of [`RGB3_INV_NM`] as the module constant `MG_TF_RGB3_INV` (exact hex f32 literals).")
    out.append("/// [`SRGB_WEIGHTS`] reaches the GPU as a uniform table, not as WGSL text.")
    out.append('pub const RGB3_WGSL: &str = "')
    out.append("const MG_TF_RGB3_INV = vec3<f32>(" + ", ".join(wgsl_hex(1.0 / v) for v in rgb3) + ");")
    out.append('";')
    out.append("")
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "cie_tables.rs")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(out))
    print(f"wrote {path}: M1 {m1} M2 {m2}, basis vs table {worst:.2e}, rgb3 {rgb3}", file=sys.stderr)


if __name__ == "__main__":
    main()
