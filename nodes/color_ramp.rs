//! Blender's Color Ramp node (`color_ramp`): a colour with alpha looked up from up to 16
//! stops by a factor, with Blender's five interpolations.
//!
//! The definition is Blender's `BKE_colorband_evaluate`
//! (source/blender/blenkernel/intern/colorband.cc) in RGB colour mode, written again here:
//!
//! - The stops are taken in order of position. Below the first stop (and at it) constant,
//!   linear and ease give the first stop's colour, at and above the last the last's.
//! - Between them, `left` is the last stop at or below the factor and `right` the first above
//!   it; `w = (fac − p_right)/(p_left − p_right)` is the weight of `left`. **constant** gives
//!   `left`; **linear** `(1 − w)·right + w·left`; **ease** the same with `w ← 3w² − 2w³`.
//! - **cardinal** and **b_spline** weigh four stops (the stop beyond `right`, `right`,
//!   `left`, the stop before `left`; each replaced by its neighbour at the ends) with the
//!   weights of `key_curve_position_weights` (blenkernel/intern/key.cc): a cardinal spline
//!   of tension 0.71 (`KEY_CARDINAL`) or the uniform cubic B-spline (`KEY_BSPLINE`), with `w`
//!   clamped to [0, 1] as the spline parameter. Past the first and last stops they run to
//!   copies of those stops at 0 and 1. The result is clamped to [0, 1] (Blender's
//!   `clamp_v4`).
//! - Equal positions: at and above the position the stop later in order wins, except at the
//!   first stop's position, where constant, linear and ease give the first stop (Blender's
//!   `in <= first` test comes first). Where `p_left = p_right` (only at the ends' copies),
//!   `w` is 1 past the last stop and 0 before the first, as Blender sets it.

use super::wide::{Wide, WideFn};
use crate::kernel::Shape;
use crate::node::{Category, In, NodeType, Out};
use crate::value::Value;
use glam::Vec4;

/// The most stops a ramp holds (Blender's `MAXCOLORBAND`, 32, is more; 16 is the issue's).
pub const MAX_STOPS: usize = 16;

/// The choices of the `interpolation` input.
pub const INTERPOLATIONS: &[&str] = &["constant", "linear", "ease", "cardinal", "b_spline"];

/// Index of `constant` in [`INTERPOLATIONS`].
pub const CONSTANT: i32 = 0;
/// Index of `linear`.
pub const LINEAR: i32 = 1;
/// Index of `ease`.
pub const EASE: i32 = 2;
/// Index of `cardinal`.
pub const CARDINAL: i32 = 3;
/// Index of `b_spline`.
pub const B_SPLINE: i32 = 4;

/// Blender's cardinal-spline constant (`fc` of `KEY_CARDINAL`; Catmull–Rom is 0.5).
pub const CARDINAL_TENSION: f32 = 0.71;

/// The names of the position inputs, stop by stop.
pub const POSITIONS: [&str; MAX_STOPS] = [
    "pos_0", "pos_1", "pos_2", "pos_3", "pos_4", "pos_5", "pos_6", "pos_7", "pos_8", "pos_9",
    "pos_10", "pos_11", "pos_12", "pos_13", "pos_14", "pos_15",
];

/// The names of the colour inputs (RGBA), stop by stop.
pub const COLORS: [&str; MAX_STOPS] = [
    "color_0", "color_1", "color_2", "color_3", "color_4", "color_5", "color_6", "color_7",
    "color_8", "color_9", "color_10", "color_11", "color_12", "color_13", "color_14", "color_15",
];

/// One stop of a ramp.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stop {
    /// Position, in [0, 1].
    pub pos: f32,
    /// Linear RGB and alpha.
    pub color: Vec4,
}

/// `x` clamped to [0, 1], a NaN to 0 (where `f32::clamp` keeps it), as the WGSL's
/// `min(max(x, 0.0), 1.0)` does on a GPU that returns the non-NaN operand.
#[allow(clippy::manual_clamp)]
fn clamp01(x: f32) -> f32 {
    x.max(0.0).min(1.0)
}

/// The first `count` (clamped to [1, 16]) of `stops`, positions clamped to [0, 1] (a NaN to
/// 0), sorted by position; equal positions keep their order (a stable insertion sort, the
/// same steps as the WGSL's).
pub fn sorted(stops: &[Stop], count: i32) -> ([Stop; MAX_STOPS], usize) {
    let n = (count.clamp(1, MAX_STOPS as i32) as usize).min(stops.len());
    let mut s = [Stop {
        pos: 0.0,
        color: Vec4::ZERO,
    }; MAX_STOPS];
    for (d, src) in s.iter_mut().zip(&stops[..n]) {
        *d = Stop {
            pos: clamp01(src.pos),
            color: src.color,
        };
    }
    for i in 1..n {
        let key = s[i];
        let mut j = i;
        while j > 0 && s[j - 1].pos > key.pos {
            s[j] = s[j - 1];
            j -= 1;
        }
        s[j] = key;
    }
    (s, n)
}

/// The cardinal spline's weights at parameter `t` ∈ [0, 1], for (far right, right, left, far
/// left): `t = 0` is `right`, `t = 1` is `left`.
///
/// Source: Blender's `key_curve_position_weights`, `KEY_CARDINAL` (blenkernel/intern/key.cc),
/// factored: −c·t(1−t)², 1 + t²((2−c)t + c − 3), t(c + t((3 − 2c) + (c − 2)t)), c·t²(t − 1).
pub fn cardinal_weights(t: f32) -> Vec4 {
    let c = CARDINAL_TENSION;
    let u = 1.0 - t;
    Vec4::new(
        -c * t * u * u,
        1.0 + t * t * ((2.0 - c) * t + (c - 3.0)),
        t * (c + t * ((3.0 - 2.0 * c) + (c - 2.0) * t)),
        c * t * t * (t - 1.0),
    )
}

/// The uniform cubic B-spline's weights at `t` ∈ [0, 1], in [`cardinal_weights`]' order:
/// (1−t)³/6, (3t³ − 6t² + 4)/6, (−3t³ + 3t² + 3t + 1)/6, t³/6.
///
/// Source: Blender's `key_curve_position_weights`, `KEY_BSPLINE` (blenkernel/intern/key.cc).
pub fn b_spline_weights(t: f32) -> Vec4 {
    let u = 1.0 - t;
    let t2 = t * t;
    let t3 = t2 * t;
    Vec4::new(
        u * u * u / 6.0,
        (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0,
        (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0,
        t3 / 6.0,
    )
}

/// The ramp at `fac` over `s[..n]`, sorted by position (see [`sorted`]), `n` ≥ 1, for
/// interpolation `mode` (an index of [`INTERPOLATIONS`], clamped).
pub fn evaluate(s: &[Stop], n: usize, fac: f32, mode: i32) -> Vec4 {
    let mode = mode.clamp(CONSTANT, B_SPLINE);
    let spline = mode >= CARDINAL;
    if n == 1 || (!spline && fac <= s[0].pos) {
        return s[0].color;
    }
    // The first stop above fac (n when there is none).
    let a = s[..n].iter().position(|x| x.pos > fac).unwrap_or(n);
    let (left, right) = if a == n {
        let last = s[n - 1];
        (
            last,
            Stop {
                pos: 1.0,
                color: last.color,
            },
        )
    } else if a == 0 {
        let first = s[0];
        (
            Stop {
                pos: 0.0,
                color: first.color,
            },
            first,
        )
    } else {
        (s[a - 1], s[a])
    };
    if mode == CONSTANT || (a == n && !spline) {
        return left.color;
    }
    let mut w = if left.pos != right.pos {
        (fac - right.pos) / (left.pos - right.pos)
    } else if a == n {
        1.0
    } else {
        0.0
    };
    if spline {
        let far_right = if a + 1 >= n { right } else { s[a + 1] };
        let far_left = if a < 2 { left } else { s[a - 2] };
        let t = clamp01(w);
        let k = if mode == CARDINAL {
            cardinal_weights(t)
        } else {
            b_spline_weights(t)
        };
        let v = k.w * far_left.color + k.z * left.color + k.y * right.color + k.x * far_right.color;
        return v.clamp(Vec4::ZERO, Vec4::ONE);
    }
    if mode == EASE {
        let w2 = w * w;
        w = 3.0 * w2 - 2.0 * w2 * w;
    }
    (1.0 - w) * right.color + w * left.color
}

/// The node's math: the first `count` of `stops` sorted ([`sorted`]), then [`evaluate`].
pub fn color_ramp(stops: &[Stop], count: i32, fac: f32, mode: i32) -> Vec4 {
    let (s, n) = sorted(stops, count);
    evaluate(&s, n, fac, mode)
}

/// The CPU kernel: lanes `fac, interpolation, count`, then per stop `pos, r, g, b, a`.
#[derive(Clone, Copy)]
struct Kernel;

impl WideFn for Kernel {
    const INPUTS: &'static [Shape] = &{
        let mut s = [Shape::Scalar; 3 + 2 * MAX_STOPS];
        s[1] = Shape::Int;
        s[2] = Shape::Int;
        let mut k = 0;
        while k < MAX_STOPS {
            s[4 + 2 * k] = Shape::Vec4;
            k += 1;
        }
        s
    };
    const OUTPUTS: &'static [Shape] = &[Shape::Vec3, Shape::Scalar];
    fn sample(ins: &[f32], outs: &mut [f32]) {
        let mut stops = [Stop {
            pos: 0.0,
            color: Vec4::ZERO,
        }; MAX_STOPS];
        for (k, s) in stops.iter_mut().enumerate() {
            let at = 3 + 5 * k;
            *s = Stop {
                pos: ins[at],
                color: Vec4::from_slice(&ins[at + 1..at + 5]),
            };
        }
        let c = color_ramp(&stops, ins[2] as i32, ins[0], ins[1] as i32);
        outs[..4].copy_from_slice(&c.to_array());
    }
}

/// WGSL of [`cardinal_weights`], [`b_spline_weights`], [`sorted`] and [`evaluate`].
pub const COLOR_RAMP_HELPER_WGSL: &str = r#"
fn mg_ramp_cardinal(t: f32) -> vec4<f32> {
    let c = 0.71;
    let u = 1.0 - t;
    return vec4<f32>(
        -c * t * u * u,
        1.0 + t * t * ((2.0 - c) * t + (c - 3.0)),
        t * (c + t * ((3.0 - 2.0 * c) + (c - 2.0) * t)),
        c * t * t * (t - 1.0));
}

fn mg_ramp_b_spline(t: f32) -> vec4<f32> {
    let u = 1.0 - t;
    let t2 = t * t;
    let t3 = t2 * t;
    return vec4<f32>(
        u * u * u / 6.0,
        (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0,
        (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0,
        t3 / 6.0);
}

fn mg_ramp_eval(fac: f32, mode0: i32, count: i32, p0: array<f32, 16>, c0: array<vec4<f32>, 16>) -> vec4<f32> {
    let n = clamp(count, 1, 16);
    let mode = clamp(mode0, 0, 4);
    var p = p0;
    var c = c0;
    for (var i = 0; i < n; i = i + 1) {
        p[i] = min(max(p[i], 0.0), 1.0);
    }
    for (var i = 1; i < n; i = i + 1) {
        let kp = p[i];
        let kc = c[i];
        var j = i;
        loop {
            if (j == 0) { break; }
            if (!(p[j - 1] > kp)) { break; }
            p[j] = p[j - 1];
            c[j] = c[j - 1];
            j = j - 1;
        }
        p[j] = kp;
        c[j] = kc;
    }
    let spline = mode >= 3;
    if (n == 1 || (!spline && fac <= p[0])) {
        return c[0];
    }
    var a = n;
    for (var k = 0; k < n; k = k + 1) {
        if (p[k] > fac) {
            a = k;
            break;
        }
    }
    var lp: f32;
    var lc: vec4<f32>;
    var rp: f32;
    var rc: vec4<f32>;
    if (a == n) {
        lp = p[n - 1];
        lc = c[n - 1];
        rp = 1.0;
        rc = lc;
    } else if (a == 0) {
        rp = p[0];
        rc = c[0];
        lp = 0.0;
        lc = rc;
    } else {
        lp = p[a - 1];
        lc = c[a - 1];
        rp = p[a];
        rc = c[a];
    }
    if (mode == 0 || (a == n && !spline)) {
        return lc;
    }
    var w: f32;
    if (lp != rp) {
        w = (fac - rp) / (lp - rp);
    } else if (a == n) {
        w = 1.0;
    } else {
        w = 0.0;
    }
    if (spline) {
        var far_right = rc;
        if (a + 1 < n) { far_right = c[a + 1]; }
        var far_left = lc;
        if (a >= 2) { far_left = c[a - 2]; }
        let t = min(max(w, 0.0), 1.0);
        var k: vec4<f32>;
        if (mode == 3) { k = mg_ramp_cardinal(t); } else { k = mg_ramp_b_spline(t); }
        let v = k.w * far_left + k.z * lc + k.y * rc + k.x * far_right;
        return clamp(v, vec4<f32>(0.0), vec4<f32>(1.0));
    }
    if (mode == 2) {
        let w2 = w * w;
        w = 3.0 * w2 - 2.0 * w2 * w;
    }
    return (1.0 - w) * rc + w * lc;
}
"#;

/// The node's WGSL: the stops into arrays, then [`COLOR_RAMP_HELPER_WGSL`].
const COLOR_RAMP_WGSL: &str = r#"
fn $fn(fac: f32, interpolation: i32, count: i32, pos_0: f32, color_0: vec4<f32>, pos_1: f32, color_1: vec4<f32>, pos_2: f32, color_2: vec4<f32>, pos_3: f32, color_3: vec4<f32>, pos_4: f32, color_4: vec4<f32>, pos_5: f32, color_5: vec4<f32>, pos_6: f32, color_6: vec4<f32>, pos_7: f32, color_7: vec4<f32>, pos_8: f32, color_8: vec4<f32>, pos_9: f32, color_9: vec4<f32>, pos_10: f32, color_10: vec4<f32>, pos_11: f32, color_11: vec4<f32>, pos_12: f32, color_12: vec4<f32>, pos_13: f32, color_13: vec4<f32>, pos_14: f32, color_14: vec4<f32>, pos_15: f32, color_15: vec4<f32>) -> $out {
    let p = array<f32, 16>(pos_0, pos_1, pos_2, pos_3, pos_4, pos_5, pos_6, pos_7, pos_8, pos_9, pos_10, pos_11, pos_12, pos_13, pos_14, pos_15);
    let c = array<vec4<f32>, 16>(color_0, color_1, color_2, color_3, color_4, color_5, color_6, color_7, color_8, color_9, color_10, color_11, color_12, color_13, color_14, color_15);
    let v = mg_ramp_eval(fac, interpolation, count, p, c);
    return $out(v.xyz, v.w);
}
"#;

/// The default position of stop `k`: 0 and 1 for the first two (Blender's new ramp), 0.5
/// for the others (Blender's `BKE_colorband_init` for the unused ones).
const fn default_pos(k: usize) -> f32 {
    match k {
        0 => 0.0,
        1 => 1.0,
        _ => 0.5,
    }
}

/// The default colour of stop `k`: opaque black and white for the first two (a shader
/// node's new ramp), opaque mid grey for the others (`BKE_colorband_init`).
const fn default_color(k: usize) -> [f32; 4] {
    match k {
        0 => [0.0, 0.0, 0.0, 1.0],
        1 => [1.0, 1.0, 1.0, 1.0],
        _ => [0.5, 0.5, 0.5, 1.0],
    }
}

/// The Color Ramp node type.
pub fn color_ramp_type() -> NodeType {
    let f = Value::float;
    let i = Value::int;
    let c4 = Value::vec4;
    let mut t = NodeType::new(
        "color_ramp",
        Category::Color,
        "Blender's Color Ramp: a colour and alpha from up to 16 stops by a factor (constant, linear, ease, cardinal, b-spline).",
    )
    .source(
        "Blender's Color Ramp node in RGB mode as BKE_colorband_evaluate defines it \
         (source/blender/blenkernel/intern/colorband.cc), with the spline weights of \
         key_curve_position_weights (blenkernel/intern/key.cc): cardinal of tension 0.71, \
         uniform cubic B-spline; docs/models/ramps.md. The stops are inputs count, pos_k and \
         color_k (RGBA), sorted by position on evaluation (equal positions keep their index \
         order; a position outside [0, 1] from a link is clamped to it). Deviations: HSV and \
         HSL colour modes are not offered; Blender's renderers (Cycles, EEVEE) read the ramp \
         from a 257-entry table and interpolate it linearly, this evaluates the definition \
         exactly (as Blender's geometry nodes do).",
    )
    .input(
        In::float("fac", 0.5)
            .range(0.0, 1.0)
            .doc("Where to read the ramp (Blender's Fac): 0 at its left end, 1 at its right."),
    )
    .input(
        In::choice("interpolation", INTERPOLATIONS, LINEAR as usize)
            .doc("Between stops: constant (steps), linear, ease (smoothstep), cardinal or b_spline (through 4 stops)."),
    )
    .input(
        In::int("count", 2)
            .range(1.0, MAX_STOPS as f32)
            .hard(1.0, MAX_STOPS as f32)
            .doc("How many stops the ramp uses (1 to 16): pos_k and color_k for k < count."),
    );
    for k in 0..MAX_STOPS {
        t = t
            .input(
                In::float(POSITIONS[k], default_pos(k))
                    .range(0.0, 1.0)
                    .hard(0.0, 1.0)
                    .doc("A stop's position (stop k: pos_k), in [0, 1]; used when k < count."),
            )
            .input(
                In::vec4(COLORS[k], default_color(k))
                    .range(0.0, 1.0)
                    .hard(0.0, f32::MAX)
                    .doc(
                        "A stop's linear RGB colour and alpha (stop k: color_k); ≥ 0 as Blender's.",
                    ),
            );
    }
    t.output(Out::color("color").doc("The ramp's colour at fac (linear RGB)."))
        .output(Out::float("alpha").doc("The ramp's alpha at fac."))
        .wgsl(COLOR_RAMP_WGSL)
        .wgsl_uses(&[COLOR_RAMP_HELPER_WGSL])
        .hard_case("one stop", &[("count", i(1))])
        .hard_case(
            "sixteen stops at one position, b-spline",
            &[
                ("count", i(16)),
                ("interpolation", i(B_SPLINE)),
                ("pos_0", f(0.5)),
                ("pos_1", f(0.5)),
            ],
        )
        .hard_case(
            "two stops at one position (a jump), read there",
            &[("count", i(2)), ("pos_0", f(0.5)), ("pos_1", f(0.5))],
        )
        .hard_case(
            "stops out of order, cardinal",
            &[
                ("count", i(3)),
                ("interpolation", i(CARDINAL)),
                ("pos_0", f(1.0)),
                ("pos_1", f(0.0)),
                ("pos_2", f(0.25)),
                ("fac", f(0.125)),
            ],
        )
        .hard_case(
            "factor past both ends, b-spline",
            &[("interpolation", i(B_SPLINE)), ("fac", f(-3.0))],
        )
        .hard_case(
            "factor past the last stop at 1, cardinal",
            &[("interpolation", i(CARDINAL)), ("fac", f(7.0))],
        )
        .hard_case(
            "huge colours, cardinal (overflow before the clamp)",
            &[
                ("interpolation", i(CARDINAL)),
                ("count", i(3)),
                ("pos_2", f(0.25)),
                ("color_1", c4([f32::MAX, f32::MAX, 0.0, f32::MAX])),
                ("color_2", c4([f32::MAX, 0.0, f32::MAX, 1.0])),
                ("fac", f(0.6)),
            ],
        )
        .hard_case(
            "ease between stops a few ULP apart",
            &[
                ("interpolation", i(EASE)),
                ("pos_0", f(0.5)),
                ("pos_1", f(0.500_000_06)),
                ("fac", f(0.500_000_03)),
            ],
        )
        .compute(Wide::<Kernel>::new())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stop(pos: f32, c: f32) -> Stop {
        Stop {
            pos,
            color: Vec4::splat(c),
        }
    }

    #[test]
    fn sorting_is_stable_and_clamps_positions() {
        let (s, n) = sorted(
            &[
                stop(0.5, 1.0),
                stop(-2.0, 2.0),
                stop(0.5, 3.0),
                stop(0.25, 4.0),
            ],
            4,
        );
        assert_eq!(n, 4);
        let got: Vec<(f32, f32)> = s[..n].iter().map(|s| (s.pos, s.color.x)).collect();
        assert_eq!(got, [(0.0, 2.0), (0.25, 4.0), (0.5, 1.0), (0.5, 3.0)]);
    }

    #[test]
    fn both_spline_weights_sum_to_one() {
        for k in 0..=16 {
            let t = k as f32 / 16.0;
            for w in [cardinal_weights(t), b_spline_weights(t)] {
                assert!((w.element_sum() - 1.0).abs() < 1e-6, "{t}: {w}");
            }
        }
    }

    #[test]
    fn the_declaration_is_clean() {
        assert_eq!(color_ramp_type().check(), Vec::<String>::new());
    }
}
