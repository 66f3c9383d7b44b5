//! Blender's Float Curve and RGB Curves nodes (`float_curve`, `rgb_curves`): a value, or each
//! channel of a colour, mapped through a curve of up to 16 points, mixed with the input by a
//! factor.
//!
//! The nodes are Blender's (source/blender/nodes/shader/nodes/node_shader_curves.cc):
//! Float Curve gives `(1 − factor)·value + factor·curve(value)`; RGB Curves maps each channel
//! through the combined curve C and then its own (R, G or B), as
//! `BKE_curvemapping_evaluateRGBF` does (blenkernel/intern/colortools.cc), and mixes the
//! same way. Beyond the first and last points a curve goes on along its end tangent
//! (`extend` = `extrapolated`, Blender 4.2's default for both nodes) or stays at the end
//! point's y (`horizontal`), as Blender's `curvemap_calc_extend`; an extrapolated value is
//! clamped to ±[`EXTRAPOLATION_LIMIT`] (it would overflow past it).
//!
//! **The curve differs from Blender's.** Blender draws a Bézier through the points with
//! automatic handles, samples it into a 256-segment table (`CM_TABLE`) and interpolates that
//! table linearly. This is a monotone cubic Hermite spline through the points (Fritsch &
//! Carlson 1980, "Monotone Piecewise Cubic Interpolation", SIAM J. Numer. Anal. 17(2),
//! 238–246), evaluated exactly: it passes through every point (as Blender's), is C¹, and is
//! monotone wherever the points are, so it never overshoots them (Blender's Auto handles can;
//! its Auto-Clamped ones cannot at extrema but may between); between the points the two
//! curves differ in shape. The tangents:
//!
//! - secants `d_k = (y_{k+1} − y_k)/(x_{k+1} − x_k)` of the segments at least
//!   [`NARROW`] wide;
//! - at a point between two such segments, the mean of their secants where they have the same
//!   sign, else 0; at an end, or beside a narrower segment, the one secant it has;
//! - per segment, Fritsch–Carlson's limit: where `m_k² + m_{k+1}² > 9 d_k²` both are scaled by
//!   `3|d_k| / √(m_k² + m_{k+1}²)` (computed scale-free so that nothing overflows).
//!
//! Points are sorted by x (equal x keep their index order): at an x two points share, the
//! curve jumps from the earlier's segment to the later's. A segment narrower than [`NARROW`]
//! is a straight line (its slope would pass 10⁸ over the ±100 the points may span).

use super::wide::{Wide, WideFn};
use crate::kernel::Shape;
use crate::node::{Category, In, NodeType, Out};
use crate::precision;
use crate::value::Value;
use glam::{Vec2, Vec3};

/// The most points a curve holds.
pub const MAX_POINTS: usize = 16;

/// The fewest points a curve holds (Blender keeps two).
pub const MIN_POINTS: i32 = 2;

/// Segments narrower than this in x (2⁻²⁰) are straight lines.
pub const NARROW: f32 = 1.0 / 1_048_576.0;

/// The largest |x| or |y| a point may have (Blender's clipping rectangle spans at most ±100).
pub const POINT_LIMIT: f32 = 100.0;

/// The choices of the `extend` input: beyond the end points, the end point's y or the line
/// along the end tangent (Blender's Extend Horizontal and Extend Extrapolated).
pub const EXTENDS: &[&str] = &["horizontal", "extrapolated"];

/// Index of `extrapolated` in [`EXTENDS`] (the default, Blender's).
pub const EXTRAPOLATED: i32 = 1;

/// The largest |value| an extrapolated curve gives (a point's tangent reaches 6·10⁸ and a
/// value 10³⁰ is accepted: their product would overflow).
pub const EXTRAPOLATION_LIMIT: f32 = 1.0e30;

/// The names of `float_curve`'s point inputs.
pub const POINTS: [&str; MAX_POINTS] = [
    "point_0", "point_1", "point_2", "point_3", "point_4", "point_5", "point_6", "point_7",
    "point_8", "point_9", "point_10", "point_11", "point_12", "point_13", "point_14", "point_15",
];

/// The names of `rgb_curves`' combined curve's point inputs.
pub const C_POINTS: [&str; MAX_POINTS] = [
    "c_0", "c_1", "c_2", "c_3", "c_4", "c_5", "c_6", "c_7", "c_8", "c_9", "c_10", "c_11", "c_12",
    "c_13", "c_14", "c_15",
];
/// The names of `rgb_curves`' red curve's point inputs.
pub const R_POINTS: [&str; MAX_POINTS] = [
    "r_0", "r_1", "r_2", "r_3", "r_4", "r_5", "r_6", "r_7", "r_8", "r_9", "r_10", "r_11", "r_12",
    "r_13", "r_14", "r_15",
];
/// The names of `rgb_curves`' green curve's point inputs.
pub const G_POINTS: [&str; MAX_POINTS] = [
    "g_0", "g_1", "g_2", "g_3", "g_4", "g_5", "g_6", "g_7", "g_8", "g_9", "g_10", "g_11", "g_12",
    "g_13", "g_14", "g_15",
];
/// The names of `rgb_curves`' blue curve's point inputs.
pub const B_POINTS: [&str; MAX_POINTS] = [
    "b_0", "b_1", "b_2", "b_3", "b_4", "b_5", "b_6", "b_7", "b_8", "b_9", "b_10", "b_11", "b_12",
    "b_13", "b_14", "b_15",
];

/// `rgb_curves`' curves, in port order: C (every channel, first), then R, G and B, each as
/// (count input, point inputs).
pub const RGB_CURVES: [(&str, [&str; MAX_POINTS]); 4] = [
    ("c_count", C_POINTS),
    ("r_count", R_POINTS),
    ("g_count", G_POINTS),
    ("b_count", B_POINTS),
];

/// A curve ready to evaluate: its points sorted by x and their tangents.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Curve {
    /// The points' x, ascending.
    pub x: [f32; MAX_POINTS],
    /// The points' y.
    pub y: [f32; MAX_POINTS],
    /// The tangents dy/dx at the points.
    pub m: [f32; MAX_POINTS],
    /// The slopes of the extrapolated lines below the first point and above the last
    /// ([`extrapolation_slopes`]).
    pub ext: [f32; 2],
    /// How many points it has (at least 1).
    pub n: usize,
}

/// Blender's automatic Bézier handles of point `p` between `prev` and `next` (a missing
/// neighbour mirrored through `p`): `calchandle_curvemap` (blenkernel/intern/colortools.cc),
/// t = (p − prev)/|p − prev| + (next − p)/|next − p|, handles p ∓ t·|·|/(2.5614·|t|).
pub fn auto_handles(prev: Vec2, p: Vec2, next: Vec2) -> (Vec2, Vec2) {
    let (a, b) = (p - prev, next - p);
    let la = match a.length() {
        0.0 => 1.0,
        l => l,
    };
    let lb = match b.length() {
        0.0 => 1.0,
        l => l,
    };
    let t = b / lb + a / la;
    let len = t.length() * 2.5614;
    if len == 0.0 {
        return (p, p);
    }
    (p - t * (la / len), p + t * (lb / len))
}

/// The slopes Blender extrapolates a curve with below its first point and above its last
/// (Extend Extrapolated), from `curvemap_make_table`: with two points the line through them;
/// with more, the direction from the end point to its neighbour's nearer automatic handle
/// ([`auto_handles`]), that handle's x kept on the curve's side of the end. Where that
/// direction is vertical (Blender then adds a constant 10⁴ · its unit y) this gives 0.
pub fn extrapolation_slopes(x: &[f32], y: &[f32]) -> [f32; 2] {
    let n = x.len();
    let p = |k: usize| Vec2::new(x[k], y[k]);
    let slope = |v: Vec2| if v.x != 0.0 { v.y / v.x } else { 0.0 };
    if n < 2 {
        return [0.0; 2];
    }
    if n == 2 {
        let s = slope(p(1) - p(0));
        return [s, s];
    }
    let next = |k: usize| {
        if k + 1 < n {
            p(k + 1)
        } else {
            2.0 * p(k) - p(k - 1)
        }
    };
    let (h1, _) = auto_handles(p(0), p(1), next(1));
    let mut lo = h1 - p(0);
    lo.x = lo.x.max(0.0);
    let (_, h2) = auto_handles(p(n - 3), p(n - 2), p(n - 1));
    let mut hi = h2 - p(n - 1);
    hi.x = hi.x.min(0.0);
    // Blender keeps the uncorrected handle (along the secant) for a handle of length ≤ ε.
    let eps = f32::EPSILON;
    let lo = if lo.length() > eps { lo } else { p(1) - p(0) };
    let hi = if hi.length() > eps {
        hi
    } else {
        p(n - 2) - p(n - 1)
    };
    [slope(lo), slope(hi)]
}

impl Curve {
    /// The curve through the first `count` of `points` (`count` clamped to [2, 16]).
    pub fn new(points: &[Vec2], count: i32) -> Curve {
        let n = (count.clamp(MIN_POINTS, MAX_POINTS as i32) as usize)
            .min(points.len())
            .max(1);
        let mut c = Curve {
            x: [0.0; MAX_POINTS],
            y: [0.0; MAX_POINTS],
            m: [0.0; MAX_POINTS],
            ext: [0.0; 2],
            n,
        };
        for (k, p) in points[..n].iter().enumerate() {
            c.x[k] = p.x;
            c.y[k] = p.y;
        }
        // A stable insertion sort by x (the WGSL's steps).
        for i in 1..n {
            let (kx, ky) = (c.x[i], c.y[i]);
            let mut j = i;
            while j > 0 && c.x[j - 1] > kx {
                c.x[j] = c.x[j - 1];
                c.y[j] = c.y[j - 1];
                j -= 1;
            }
            c.x[j] = kx;
            c.y[j] = ky;
        }
        c.tangents();
        c.ext = extrapolation_slopes(&c.x[..n], &c.y[..n]);
        c
    }

    /// Fritsch–Carlson tangents (see the module's doc).
    fn tangents(&mut self) {
        let n = self.n;
        let mut d = [0.0f32; MAX_POINTS];
        let mut wide = [false; MAX_POINTS];
        for k in 0..n - 1 {
            let h = self.x[k + 1] - self.x[k];
            wide[k] = h >= NARROW;
            if wide[k] {
                d[k] = (self.y[k + 1] - self.y[k]) / h;
            }
        }
        for k in 0..n {
            let left = k > 0 && wide[k - 1];
            let right = k + 1 < n && wide[k];
            self.m[k] = match (left, right) {
                (true, true) => {
                    let (a, b) = (d[k - 1], d[k]);
                    if (a > 0.0 && b > 0.0) || (a < 0.0 && b < 0.0) {
                        (a + b) * 0.5
                    } else {
                        0.0
                    }
                }
                (true, false) => d[k - 1],
                (false, true) => d[k],
                (false, false) => 0.0,
            };
        }
        for k in 0..n - 1 {
            if !wide[k] {
                continue;
            }
            if d[k] == 0.0 {
                self.m[k] = 0.0;
                self.m[k + 1] = 0.0;
                continue;
            }
            let r = self.m[k].abs().max(self.m[k + 1].abs());
            if r > 0.0 {
                let (a, b) = (self.m[k] / r, self.m[k + 1] / r);
                let q = r * precision::sqrt(a * a + b * b);
                let limit = 3.0 * d[k].abs();
                if q > limit {
                    let tau = limit / q;
                    self.m[k] *= tau;
                    self.m[k + 1] *= tau;
                }
            }
        }
    }

    /// The curve at `x`: beyond the ends the end point's y, or (`extrapolate`) the line along
    /// the end tangent clamped to ±[`EXTRAPOLATION_LIMIT`]; between, the cubic Hermite (a line
    /// on a narrow segment). A NaN gives the first point's y.
    pub fn eval(&self, x: f32, extrapolate: bool) -> f32 {
        let n = self.n;
        let limit = EXTRAPOLATION_LIMIT;
        if x >= self.x[n - 1] {
            let (x1, y1) = (self.x[n - 1], self.y[n - 1]);
            return match extrapolate {
                true => (y1 + self.ext[1] * (x - x1).min(limit)).clamp(-limit, limit),
                false => y1,
            };
        }
        // Below the first point, or a NaN.
        if x < self.x[0] || x.is_nan() {
            let (x0, y0) = (self.x[0], self.y[0]);
            return match extrapolate && !x.is_nan() {
                true => (y0 + self.ext[0] * (x - x0).max(-limit)).clamp(-limit, limit),
                false => y0,
            };
        }
        let mut k = 0;
        for j in 1..n {
            if self.x[j] <= x {
                k = j;
            }
        }
        let x0 = self.x[k];
        let h = self.x[k + 1] - x0;
        let t = (x - x0) / h;
        let (y0, y1) = (self.y[k], self.y[k + 1]);
        if h < NARROW {
            return y0 + (y1 - y0) * t;
        }
        let u = 1.0 - t;
        let h00 = (1.0 + 2.0 * t) * u * u;
        let h10 = t * u * u;
        let h01 = t * t * (3.0 - 2.0 * t);
        let h11 = t * t * (t - 1.0);
        h00 * y0 + h01 * y1 + h * (h10 * self.m[k] + h11 * self.m[k + 1])
    }
}

/// WGSL of [`Curve::new`] and [`Curve::eval`].
pub const CURVE_HELPER_WGSL: &str = r#"
struct MgCurve {
    x: array<f32, 16>,
    y: array<f32, 16>,
    m: array<f32, 16>,
    ext: vec2<f32>,
    n: i32,
}

fn mg_curve_handles(prev: vec2<f32>, p: vec2<f32>, next: vec2<f32>) -> array<vec2<f32>, 2> {
    let a = p - prev;
    let b = next - p;
    var la = sqrt(dot(a, a));
    if (la == 0.0) { la = 1.0; }
    var lb = sqrt(dot(b, b));
    if (lb == 0.0) { lb = 1.0; }
    let t = b / lb + a / la;
    let len = sqrt(dot(t, t)) * 2.5614;
    if (len == 0.0) { return array<vec2<f32>, 2>(p, p); }
    return array<vec2<f32>, 2>(p - t * (la / len), p + t * (lb / len));
}

fn mg_curve_slope(v: vec2<f32>) -> f32 {
    if (v.x != 0.0) { return v.y / v.x; }
    return 0.0;
}

fn mg_curve_ext(c: MgCurve) -> vec2<f32> {
    let n = c.n;
    let p0 = vec2<f32>(c.x[0], c.y[0]);
    let p1 = vec2<f32>(c.x[1], c.y[1]);
    if (n == 2) {
        let s = mg_curve_slope(p1 - p0);
        return vec2<f32>(s, s);
    }
    let p2 = vec2<f32>(c.x[2], c.y[2]);
    var lo = mg_curve_handles(p0, p1, p2)[0] - p0;
    lo.x = max(lo.x, 0.0);
    let q0 = vec2<f32>(c.x[n - 3], c.y[n - 3]);
    let q1 = vec2<f32>(c.x[n - 2], c.y[n - 2]);
    let q2 = vec2<f32>(c.x[n - 1], c.y[n - 1]);
    var hi = mg_curve_handles(q0, q1, q2)[1] - q2;
    hi.x = min(hi.x, 0.0);
    let eps = 1.1920929e-7;
    if (!(sqrt(dot(lo, lo)) > eps)) { lo = p1 - p0; }
    if (!(sqrt(dot(hi, hi)) > eps)) { hi = q1 - q2; }
    return vec2<f32>(mg_curve_slope(lo), mg_curve_slope(hi));
}

fn mg_curve_build(pts: array<vec2<f32>, 16>, count: i32) -> MgCurve {
    var c: MgCurve;
    let n = clamp(count, 2, 16);
    c.n = n;
    for (var k = 0; k < n; k = k + 1) {
        c.x[k] = pts[k].x;
        c.y[k] = pts[k].y;
    }
    for (var i = 1; i < n; i = i + 1) {
        let kx = c.x[i];
        let ky = c.y[i];
        var j = i;
        loop {
            if (j == 0) { break; }
            if (!(c.x[j - 1] > kx)) { break; }
            c.x[j] = c.x[j - 1];
            c.y[j] = c.y[j - 1];
            j = j - 1;
        }
        c.x[j] = kx;
        c.y[j] = ky;
    }
    var d: array<f32, 16>;
    var wide: array<bool, 16>;
    for (var k = 0; k < n - 1; k = k + 1) {
        let h = c.x[k + 1] - c.x[k];
        wide[k] = h >= 9.5367431640625e-7;
        if (wide[k]) {
            d[k] = (c.y[k + 1] - c.y[k]) / h;
        }
    }
    for (var k = 0; k < n; k = k + 1) {
        let left = k > 0 && wide[max(k - 1, 0)];
        let right = k + 1 < n && wide[k];
        var m = 0.0;
        if (left && right) {
            let a = d[k - 1];
            let b = d[k];
            if ((a > 0.0 && b > 0.0) || (a < 0.0 && b < 0.0)) {
                m = (a + b) * 0.5;
            }
        } else if (left) {
            m = d[k - 1];
        } else if (right) {
            m = d[k];
        }
        c.m[k] = m;
    }
    for (var k = 0; k < n - 1; k = k + 1) {
        if (!wide[k]) { continue; }
        if (d[k] == 0.0) {
            c.m[k] = 0.0;
            c.m[k + 1] = 0.0;
            continue;
        }
        let r = max(abs(c.m[k]), abs(c.m[k + 1]));
        if (r > 0.0) {
            let a = c.m[k] / r;
            let b = c.m[k + 1] / r;
            let q = r * sqrt(a * a + b * b);
            let limit = 3.0 * abs(d[k]);
            if (q > limit) {
                let tau = limit / q;
                c.m[k] = c.m[k] * tau;
                c.m[k + 1] = c.m[k + 1] * tau;
            }
        }
    }
    c.ext = mg_curve_ext(c);
    return c;
}

fn mg_curve_eval(c0: MgCurve, x: f32, extrapolate: bool) -> f32 {
    var c = c0;
    let n = c.n;
    if (x >= c.x[n - 1]) {
        if (extrapolate) {
            return clamp(c.y[n - 1] + c.ext.y * min(x - c.x[n - 1], 1.0e30), -1.0e30, 1.0e30);
        }
        return c.y[n - 1];
    }
    if (!(x >= c.x[0])) {
        if (extrapolate && x == x) {
            return clamp(c.y[0] + c.ext.x * max(x - c.x[0], -1.0e30), -1.0e30, 1.0e30);
        }
        return c.y[0];
    }
    var k = 0;
    for (var j = 1; j < n; j = j + 1) {
        if (c.x[j] <= x) { k = j; }
    }
    let x0 = c.x[k];
    let h = c.x[k + 1] - x0;
    let t = (x - x0) / h;
    let y0 = c.y[k];
    let y1 = c.y[k + 1];
    if (h < 9.5367431640625e-7) {
        return y0 + (y1 - y0) * t;
    }
    let u = 1.0 - t;
    let h00 = (1.0 + 2.0 * t) * u * u;
    let h10 = t * u * u;
    let h01 = t * t * (3.0 - 2.0 * t);
    let h11 = t * t * (t - 1.0);
    return h00 * y0 + h01 * y1 + h * (h10 * c.m[k] + h11 * c.m[k + 1]);
}
"#;

/// The Float Curve node's math: `(1 − factor)·value + factor·curve(value)`, the curve
/// extrapolated beyond its ends where `extend` is [`EXTRAPOLATED`].
pub fn float_curve(points: &[Vec2], count: i32, extend: i32, factor: f32, value: f32) -> f32 {
    let v = Curve::new(points, count).eval(value, extend == EXTRAPOLATED);
    (1.0 - factor) * value + factor * v
}

/// The RGB Curves node's math: each channel through C then its own curve, mixed with the
/// input by `fac`. `curves` are C, R, G, B: (points, count); `extend` as [`float_curve`]'s.
pub fn rgb_curves(curves: [(&[Vec2], i32); 4], extend: i32, fac: f32, color: Vec3) -> Vec3 {
    let [c, r, g, b] = curves.map(|(p, n)| Curve::new(p, n));
    let e = extend == EXTRAPOLATED;
    let o = Vec3::new(
        r.eval(c.eval(color.x, e), e),
        g.eval(c.eval(color.y, e), e),
        b.eval(c.eval(color.z, e), e),
    );
    (1.0 - fac) * color + fac * o
}

/// Reads `MAX_POINTS` points from `lanes` (x, y pairs).
fn points_at(lanes: &[f32]) -> [Vec2; MAX_POINTS] {
    let mut p = [Vec2::ZERO; MAX_POINTS];
    for (k, v) in p.iter_mut().enumerate() {
        *v = Vec2::new(lanes[2 * k], lanes[2 * k + 1]);
    }
    p
}

/// `float_curve`'s CPU kernel: lanes `value, factor, extend, count`, then 16 × (x, y).
#[derive(Clone, Copy)]
struct FloatKernel;

impl WideFn for FloatKernel {
    const INPUTS: &'static [Shape] = &{
        let mut s = [Shape::Vec2; 4 + MAX_POINTS];
        s[0] = Shape::Scalar;
        s[1] = Shape::Scalar;
        s[2] = Shape::Int;
        s[3] = Shape::Int;
        s
    };
    const OUTPUTS: &'static [Shape] = &[Shape::Scalar];
    fn sample(ins: &[f32], outs: &mut [f32]) {
        let p = points_at(&ins[4..]);
        outs[0] = float_curve(&p, ins[3] as i32, ins[2] as i32, ins[1], ins[0]);
    }
}

/// Lanes of one of `rgb_curves`' curves: its count, then 16 × (x, y).
const CURVE_LANES: usize = 1 + 2 * MAX_POINTS;

/// `rgb_curves`' CPU kernel: lanes `r, g, b, fac, extend`, then per curve (C, R, G, B) its count and
/// 16 × (x, y).
#[derive(Clone, Copy)]
struct RgbKernel;

impl WideFn for RgbKernel {
    const INPUTS: &'static [Shape] = &{
        let mut s = [Shape::Vec2; 3 + 4 * (1 + MAX_POINTS)];
        s[0] = Shape::Vec3;
        s[1] = Shape::Scalar;
        s[2] = Shape::Int;
        let mut c = 0;
        while c < 4 {
            s[3 + c * (1 + MAX_POINTS)] = Shape::Int;
            c += 1;
        }
        s
    };
    const OUTPUTS: &'static [Shape] = &[Shape::Vec3];
    fn sample(ins: &[f32], outs: &mut [f32]) {
        let curve = |c: usize| {
            let at = 5 + c * CURVE_LANES;
            (ins[at] as i32, points_at(&ins[at + 1..]))
        };
        let [(nc, pc), (nr, pr), (ng, pg), (nb, pb)] = [0, 1, 2, 3].map(curve);
        let o = rgb_curves(
            [(&pc, nc), (&pr, nr), (&pg, ng), (&pb, nb)],
            ins[4] as i32,
            ins[3],
            Vec3::new(ins[0], ins[1], ins[2]),
        );
        outs[..3].copy_from_slice(&o.to_array());
    }
}

/// `float_curve`'s WGSL.
const FLOAT_CURVE_WGSL: &str = r#"
fn $fn(value: f32, factor: f32, extend: i32, count: i32, point_0: vec2<f32>, point_1: vec2<f32>, point_2: vec2<f32>, point_3: vec2<f32>, point_4: vec2<f32>, point_5: vec2<f32>, point_6: vec2<f32>, point_7: vec2<f32>, point_8: vec2<f32>, point_9: vec2<f32>, point_10: vec2<f32>, point_11: vec2<f32>, point_12: vec2<f32>, point_13: vec2<f32>, point_14: vec2<f32>, point_15: vec2<f32>) -> f32 {
    let c = mg_curve_build(array<vec2<f32>, 16>(point_0, point_1, point_2, point_3, point_4, point_5, point_6, point_7, point_8, point_9, point_10, point_11, point_12, point_13, point_14, point_15), count);
    let v = mg_curve_eval(c, value, extend == 1);
    return (1.0 - factor) * value + factor * v;
}
"#;

/// `rgb_curves`' WGSL.
const RGB_CURVES_WGSL: &str = r#"
fn $fn(color: vec3<f32>, fac: f32, extend: i32, c_count: i32, c_0: vec2<f32>, c_1: vec2<f32>, c_2: vec2<f32>, c_3: vec2<f32>, c_4: vec2<f32>, c_5: vec2<f32>, c_6: vec2<f32>, c_7: vec2<f32>, c_8: vec2<f32>, c_9: vec2<f32>, c_10: vec2<f32>, c_11: vec2<f32>, c_12: vec2<f32>, c_13: vec2<f32>, c_14: vec2<f32>, c_15: vec2<f32>, r_count: i32, r_0: vec2<f32>, r_1: vec2<f32>, r_2: vec2<f32>, r_3: vec2<f32>, r_4: vec2<f32>, r_5: vec2<f32>, r_6: vec2<f32>, r_7: vec2<f32>, r_8: vec2<f32>, r_9: vec2<f32>, r_10: vec2<f32>, r_11: vec2<f32>, r_12: vec2<f32>, r_13: vec2<f32>, r_14: vec2<f32>, r_15: vec2<f32>, g_count: i32, g_0: vec2<f32>, g_1: vec2<f32>, g_2: vec2<f32>, g_3: vec2<f32>, g_4: vec2<f32>, g_5: vec2<f32>, g_6: vec2<f32>, g_7: vec2<f32>, g_8: vec2<f32>, g_9: vec2<f32>, g_10: vec2<f32>, g_11: vec2<f32>, g_12: vec2<f32>, g_13: vec2<f32>, g_14: vec2<f32>, g_15: vec2<f32>, b_count: i32, b_0: vec2<f32>, b_1: vec2<f32>, b_2: vec2<f32>, b_3: vec2<f32>, b_4: vec2<f32>, b_5: vec2<f32>, b_6: vec2<f32>, b_7: vec2<f32>, b_8: vec2<f32>, b_9: vec2<f32>, b_10: vec2<f32>, b_11: vec2<f32>, b_12: vec2<f32>, b_13: vec2<f32>, b_14: vec2<f32>, b_15: vec2<f32>) -> vec3<f32> {
    let cc = mg_curve_build(array<vec2<f32>, 16>(c_0, c_1, c_2, c_3, c_4, c_5, c_6, c_7, c_8, c_9, c_10, c_11, c_12, c_13, c_14, c_15), c_count);
    let cr = mg_curve_build(array<vec2<f32>, 16>(r_0, r_1, r_2, r_3, r_4, r_5, r_6, r_7, r_8, r_9, r_10, r_11, r_12, r_13, r_14, r_15), r_count);
    let cg = mg_curve_build(array<vec2<f32>, 16>(g_0, g_1, g_2, g_3, g_4, g_5, g_6, g_7, g_8, g_9, g_10, g_11, g_12, g_13, g_14, g_15), g_count);
    let cb = mg_curve_build(array<vec2<f32>, 16>(b_0, b_1, b_2, b_3, b_4, b_5, b_6, b_7, b_8, b_9, b_10, b_11, b_12, b_13, b_14, b_15), b_count);
    let e = extend == 1;
    let o = vec3<f32>(
        mg_curve_eval(cr, mg_curve_eval(cc, color.x, e), e),
        mg_curve_eval(cg, mg_curve_eval(cc, color.y, e), e),
        mg_curve_eval(cb, mg_curve_eval(cc, color.z, e), e));
    return (1.0 - fac) * color + fac * o;
}
"#;

/// The default of point `k`: (0, 0) and (1, 1) for the first two (Blender's new curve, the
/// identity), (0.5, 0.5) on it for the others.
const fn default_point(k: usize) -> [f32; 2] {
    match k {
        0 => [0.0, 0.0],
        1 => [1.0, 1.0],
        _ => [0.5, 0.5],
    }
}

/// The `extend` input (Blender's Extend menu of the curve's tools).
fn extend_input() -> In {
    In::choice("extend", EXTENDS, EXTRAPOLATED as usize).doc(
        "Beyond the end points: horizontal (the end point's y) or extrapolated (along the end tangent, Blender's default).",
    )
}

/// A curve's count input.
fn count_input(name: &'static str, doc: &'static str) -> In {
    In::int(name, 2)
        .range(MIN_POINTS as f32, MAX_POINTS as f32)
        .hard(MIN_POINTS as f32, MAX_POINTS as f32)
        .doc(doc)
}

/// A curve's point input.
fn point_input(name: &'static str, k: usize, doc: &'static str) -> In {
    In::vec2(name, default_point(k))
        .range(0.0, 1.0)
        .hard(-POINT_LIMIT, POINT_LIMIT)
        .doc(doc)
}

/// What the curves' source docs share: the curve and its limits (a macro, for `concat!`).
macro_rules! curve_source {
    () => {
        " The curve is a monotone cubic Hermite spline through the points \
     (Fritsch & Carlson 1980), where Blender's CurveMapping \
     draws a Bézier with automatic handles and samples it into a 256-segment table: both pass \
     through the points, this one never overshoots them, and between points the shapes \
     differ (docs/models/ramps.md). Points are sorted by x on evaluation (equal x keep their \
     index order and make a jump); a count from a link is clamped to [2, 16]; segments under \
     2⁻²⁰ wide in x are straight lines; points lie in [−100, 100]² (Blender's clipping \
     rectangle's limit). Beyond the ends (input extend): the end point's y, or Blender's default \
     the line along the end tangent, clamped to ±1e30."
    };
}

/// The Float Curve node type.
pub fn float_curve_type() -> NodeType {
    let f = Value::float;
    let i = Value::int;
    let v2 = Value::vec2;
    let mut t = NodeType::new(
        "float_curve",
        Category::Math,
        "Blender's Float Curve: a value mapped through a curve of up to 16 points, mixed with it by a factor.",
    )
    .source(concat!(
        "Blender's Float Curve node (source/blender/nodes/shader/nodes/node_shader_curves.cc): \
         (1 − factor)·value + factor·curve(value). The points are the inputs point 0 to 15 \
         (x, y), the first count of them used.",
        curve_source!()
    ))
    .input(
        In::float("value", 1.0)
            .range(0.0, 1.0)
            .doc("The value mapped (Blender's Value)."),
    )
    .input(
        In::float("factor", 1.0)
            .range(0.0, 1.0)
            .hard(0.0, 1.0)
            .doc("How much of the curve to use: 0 passes value through, 1 gives curve(value)."),
    )
    .input(extend_input())
    .input(count_input(
        "count",
        "How many points the curve has (2 to 16): point_k for k < count.",
    ));
    for (k, name) in POINTS.iter().enumerate() {
        t = t.input(point_input(
            name,
            k,
            "A point (x, y) of the curve (point k: point_k); used when k < count.",
        ));
    }
    t.output(Out::float("value").doc("The mapped value, mixed with the input by factor."))
        .wgsl(FLOAT_CURVE_WGSL)
        .wgsl_uses(&[CURVE_HELPER_WGSL])
        .hard_case(
            "points out of order",
            &[
                ("count", i(4)),
                ("point_0", v2([1.0, 0.0])),
                ("point_1", v2([0.0, 1.0])),
                ("point_2", v2([0.75, 0.9])),
                ("point_3", v2([0.25, 0.1])),
                ("value", f(0.6)),
            ],
        )
        .hard_case(
            "two points at one x (a jump), read there",
            &[
                ("count", i(3)),
                ("point_1", v2([0.5, 1.0])),
                ("point_2", v2([0.5, 0.0])),
                ("value", f(0.5)),
            ],
        )
        .hard_case(
            "a segment one ULP wide beside steep ones",
            &[
                ("count", i(4)),
                ("point_1", v2([0.5, -100.0])),
                ("point_2", v2([0.500_000_06, 100.0])),
                ("point_3", v2([1.0, -100.0])),
                ("value", f(0.500_000_03)),
            ],
        )
        .hard_case(
            "a segment just over 2⁻²⁰ wide, steep",
            &[
                ("count", i(3)),
                ("point_0", v2([-100.0, -100.0])),
                ("point_1", v2([0.0, 100.0])),
                ("point_2", v2([0.000_001, -100.0])),
                ("value", f(0.000_000_5)),
            ],
        )
        .hard_case("value beyond both ends", &[("value", f(-1.0e30))])
        .hard_case(
            "extrapolated far along a steep end",
            &[
                ("count", i(3)),
                ("point_1", v2([0.000_001, 100.0])),
                ("point_2", v2([1.0, -100.0])),
                ("value", f(f32::MAX)),
            ],
        )
        .hard_case(
            "horizontal beyond the ends",
            &[("extend", i(0)), ("value", f(1.0e30))],
        )
        .hard_case(
            "sixteen points",
            &[
                ("count", i(16)),
                ("point_2", v2([0.25, 0.75])),
                ("point_3", v2([0.75, 0.25])),
                ("value", f(0.4)),
            ],
        )
        .compute(Wide::<FloatKernel>::new())
}

/// The RGB Curves node type.
pub fn rgb_curves_type() -> NodeType {
    let f = Value::float;
    let i = Value::int;
    let v2 = Value::vec2;
    let c3 = Value::color;
    let mut t = NodeType::new(
        "rgb_curves",
        Category::Color,
        "Blender's RGB Curves: each channel through a combined curve C and its own R, G or B curve (up to 16 points each), mixed by a factor.",
    )
    .source(concat!(
        "Blender's RGB Curves node (source/blender/nodes/shader/nodes/node_shader_curves.cc, \
         BKE_curvemapping_evaluateRGBF): channel ← curve_channel(curve_C(channel)), then \
         (1 − fac)·color + fac·mapped. The curves' points are inputs c_count, c_k (C), r_count, \
         r_k, g_count, g_k, b_count, b_k.",
        curve_source!()
    ))
    .input(
        In::color("color", [1.0, 1.0, 1.0])
            .range(0.0, 1.0)
            .doc("The colour mapped, linear RGB (Blender's Color)."),
    )
    .input(
        In::float("fac", 1.0)
            .range(0.0, 1.0)
            .hard(0.0, 1.0)
            .doc("How much of the mapping to use: 0 passes the colour through."),
    )
    .input(extend_input());
    for (count, names) in RGB_CURVES {
        t = t.input(count_input(
            count,
            "How many points this curve has (2 to 16): its points k < count are used.",
        ));
        for (k, name) in names.iter().enumerate() {
            t = t.input(point_input(
                name,
                k,
                "A point (x, y) of curve C (applied to every channel first), R, G or B; used when k < its count.",
            ));
        }
    }
    t.output(Out::color("color").doc("The mapped colour, mixed with the input by fac."))
        .wgsl(RGB_CURVES_WGSL)
        .wgsl_uses(&[CURVE_HELPER_WGSL])
        .hard_case(
            "every curve inverted, C sharpened",
            &[
                ("c_count", i(3)),
                ("c_2", v2([0.5, 0.8])),
                ("r_0", v2([0.0, 1.0])),
                ("r_1", v2([1.0, 0.0])),
                ("g_0", v2([0.0, 1.0])),
                ("g_1", v2([1.0, 0.0])),
                ("b_0", v2([0.0, 1.0])),
                ("b_1", v2([1.0, 0.0])),
                ("color", c3([0.2, 0.5, 0.9])),
            ],
        )
        .hard_case(
            "channels beyond the curves' ends",
            &[("color", c3([-5.0, 0.5, 1.0e30]))],
        )
        .hard_case(
            "sixteen points, all at one x",
            &[
                ("c_count", i(16)),
                ("c_0", v2([0.5, 0.0])),
                ("c_1", v2([0.5, 1.0])),
                ("color", c3([0.5, 0.25, 0.75])),
            ],
        )
        .hard_case(
            "extreme points",
            &[
                ("r_0", v2([-100.0, 100.0])),
                ("r_1", v2([100.0, -100.0])),
                ("g_1", v2([-100.0, -100.0])),
                ("fac", f(0.5)),
            ],
        )
        .compute(Wide::<RgbKernel>::new())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_declarations_are_clean() {
        assert_eq!(float_curve_type().check(), Vec::<String>::new());
        assert_eq!(rgb_curves_type().check(), Vec::<String>::new());
    }

    #[test]
    fn two_points_make_a_line() {
        let c = Curve::new(&[Vec2::ZERO, Vec2::ONE], 2);
        for k in 0..=8 {
            let x = k as f32 / 8.0;
            assert!((c.eval(x, false) - x).abs() < 1e-7, "{x}");
        }
    }
}
