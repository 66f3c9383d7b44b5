//! Blender's Color Ramp, Float Curve and RGB Curves (nodes/color_ramp.rs, nodes/curves.rs)
//! against references written here in f64: the ramp re-derived from Blender's definition in
//! another form (an extended stop list, the cardinal spline as a Hermite curve with tangents
//! 0.71·(P₊ − P₋), the B-spline from its kernel), Fritsch & Carlson's monotone cubic in its
//! published α/β form, and hand-computed values; at round points and at seeded random
//! f32-exact ones. The nodes' CPU kernels run through `NodeType`'s kernel (the adapter and
//! the lane layout included); the loader's errors through a registry holding the three.

use crate::common;
use common::parity::{NodeSamples, node_samples, run_cpu};
use common::rng::Rng;
use common::tint::Tint;
use common::tool_or_skip;
use matgraph::error::GraphError;
use matgraph::node::NodeType;
use matgraph::nodes::color_ramp::{self, INTERPOLATIONS, MAX_STOPS};
use matgraph::nodes::curves::{self, Curve, MAX_POINTS};
use matgraph::wgsl::node_harness;
use matgraph::{Graph, Registry, SocketType, Value};
use serde_json::json;

// ------------------------------------------------------------------------------------------
// Running a node's CPU kernel on chosen inputs
// ------------------------------------------------------------------------------------------

/// One sample per row: each row the node's defaults with `set` applied.
pub(crate) fn samples(t: &NodeType, rows: &[Vec<(&str, Value)>]) -> NodeSamples {
    let n = rows.len();
    let columns = t
        .inputs()
        .iter()
        .enumerate()
        .map(|(k, d)| {
            let w = d.default.ty().width();
            let mut col = vec![0.0f32; w * n];
            for (i, row) in rows.iter().enumerate() {
                let v = row
                    .iter()
                    .find(|(name, _)| *name == d.name)
                    .map_or(t.default_for(k, SocketType::Float), |(_, v)| *v);
                for c in 0..w {
                    col[c * n + i] = v.raw()[c];
                }
            }
            col
        })
        .collect();
    NodeSamples { n, columns }
}

/// Output `o` of sample `i`, all its components.
pub(crate) fn output(out: &[Vec<f32>], o: usize, width: usize, n: usize, i: usize) -> Vec<f32> {
    (0..width).map(|c| out[o][c * n + i]).collect()
}

// ------------------------------------------------------------------------------------------
// The ramp's reference
// ------------------------------------------------------------------------------------------

/// A stop in f64.
#[derive(Clone, Copy, Debug)]
struct RefStop {
    pos: f64,
    c: [f64; 4],
}

/// Blender's ramp (`BKE_colorband_evaluate`, RGB mode) at `x`, re-derived: the stops sorted
/// (stably) and framed by copies of the first at 0 and the last at 1; the segment from the
/// last entry at or below `x`; the spline through the four entries around it (indices
/// clamped to the list), parameter u from left to right.
fn ramp_reference(stops: &[(f32, [f32; 4])], count: i32, x: f64, mode: &str) -> [f64; 4] {
    let n = (count.clamp(1, 16) as usize).min(stops.len());
    let mut s: Vec<RefStop> = stops[..n]
        .iter()
        .map(|(p, c)| RefStop {
            pos: (*p as f64).clamp(0.0, 1.0),
            c: c.map(f64::from),
        })
        .collect();
    s.sort_by(|a, b| a.pos.total_cmp(&b.pos));
    if n == 1 {
        return s[0].c;
    }
    let spline = matches!(mode, "cardinal" | "b_spline");
    if !spline && x <= s[0].pos {
        return s[0].c;
    }
    // Stops at or below x (sorted: the index of the first above it).
    let a = s.iter().filter(|t| t.pos <= x).count();
    if !spline && a == n {
        return s[n - 1].c;
    }
    let mut e = vec![RefStop {
        pos: 0.0,
        c: s[0].c,
    }];
    e.extend(&s);
    e.push(RefStop {
        pos: 1.0,
        c: s[n - 1].c,
    });
    let (l, r) = (e[a], e[a + 1]);
    if mode == "constant" {
        return l.c;
    }
    let u = if r.pos > l.pos {
        (x - l.pos) / (r.pos - l.pos)
    } else if a == n {
        0.0
    } else {
        1.0
    };
    let mix = |u: f64| std::array::from_fn(|k| l.c[k] + (r.c[k] - l.c[k]) * u);
    match mode {
        "linear" => mix(u),
        "ease" => mix(u * u * (3.0 - 2.0 * u)),
        _ => {
            let u = u.clamp(0.0, 1.0);
            let p0 = e[a.saturating_sub(1)];
            let p3 = e[(a + 2).min(n + 1)];
            let v: [f64; 4] = if mode == "cardinal" {
                // Hermite from l to r, tangents 0.71·(next − previous).
                let (h00, h10, h01, h11) = (
                    2.0 * u.powi(3) - 3.0 * u * u + 1.0,
                    u.powi(3) - 2.0 * u * u + u,
                    -2.0 * u.powi(3) + 3.0 * u * u,
                    u.powi(3) - u * u,
                );
                std::array::from_fn(|k| {
                    h00 * l.c[k]
                        + h10 * 0.71 * (r.c[k] - p0.c[k])
                        + h01 * r.c[k]
                        + h11 * 0.71 * (p3.c[k] - l.c[k])
                })
            } else {
                // The uniform cubic B-spline kernel, centred on each control point.
                let b = |t: f64| {
                    let t = t.abs();
                    if t < 1.0 {
                        2.0 / 3.0 - t * t + t.powi(3) / 2.0
                    } else if t < 2.0 {
                        (2.0 - t).powi(3) / 6.0
                    } else {
                        0.0
                    }
                };
                std::array::from_fn(|k| {
                    b(u + 1.0) * p0.c[k]
                        + b(u) * l.c[k]
                        + b(u - 1.0) * r.c[k]
                        + b(u - 2.0) * p3.c[k]
                })
            };
            v.map(|c| c.clamp(0.0, 1.0))
        }
    }
}

/// The inputs of a ramp node: `fac`, the mode, and the stops.
pub(crate) fn ramp_row(
    stops: &[(f32, [f32; 4])],
    count: i32,
    fac: f32,
    mode: &str,
) -> Vec<(&'static str, Value)> {
    let m = INTERPOLATIONS.iter().position(|c| *c == mode).unwrap() as i32;
    let mut row = vec![
        ("fac", Value::float(fac)),
        ("interpolation", Value::int(m)),
        ("count", Value::int(count)),
    ];
    for (k, (p, c)) in stops.iter().enumerate() {
        row.push((color_ramp::POSITIONS[k], Value::float(*p)));
        row.push((color_ramp::COLORS[k], Value::vec4(*c)));
    }
    row
}

/// A ramp's stops: (position, RGBA).
pub(crate) type Stops = Vec<(f32, [f32; 4])>;

/// Runs the node's kernel on `rows` (stops, count, fac, mode); returns RGBA per row.
fn ramp_kernel(rows: &[(Stops, i32, f32, &str)]) -> Vec<[f32; 4]> {
    let t = color_ramp::color_ramp_type();
    let rows: Vec<Vec<(&str, Value)>> = rows
        .iter()
        .map(|(s, n, x, m)| ramp_row(s, *n, *x, m))
        .collect();
    let s = samples(&t, &rows);
    let out = run_cpu(&t, SocketType::Float, &s);
    (0..s.n)
        .map(|i| {
            let c = output(&out, 0, 3, s.n, i);
            [c[0], c[1], c[2], out[1][i]]
        })
        .collect()
}

const BLACK: [f32; 4] = [0.0, 0.0, 0.0, 1.0];
const WHITE: [f32; 4] = [1.0, 1.0, 1.0, 1.0];

#[test]
fn ramp_hand_computed_values() {
    let bw = vec![(0.0, BLACK), (1.0, WHITE)];
    // (stops, fac, mode, grey expected): linear and ease at 1/4 (3·(1/4)² − 2·(1/4)³ =
    // 0.15625); the cardinal and B-spline from black to white at 1/4, with the end copies
    // black and white: 0.71·(h10 + h11) + h01 = 0.71·0.09375 + 0.15625 = 0.2228125 and
    // (−2u³ + 3u² + 3u + 1)/6 = 1.90625/6.
    let cases: &[(Stops, f32, &str, f64)] = &[
        (bw.clone(), 0.25, "linear", 0.25),
        (bw.clone(), 0.25, "ease", 0.15625),
        (bw.clone(), 0.25, "cardinal", 0.2228125),
        (bw.clone(), 0.25, "b_spline", 1.90625 / 6.0),
        (bw.clone(), 0.75, "constant", 0.0),
        (bw.clone(), 1.0, "constant", 1.0),
        (bw.clone(), -1.0, "linear", 0.0),
        (bw.clone(), 2.0, "ease", 1.0),
        // Equal positions: the later stop from there on, the earlier below; at the first
        // stop's position the first stop (Blender tests `fac <= first` before anything).
        (
            vec![(0.0, BLACK), (0.5, BLACK), (0.5, WHITE)],
            0.5,
            "linear",
            1.0,
        ),
        (
            vec![(0.0, BLACK), (0.5, BLACK), (0.5, WHITE)],
            0.499_999_97,
            "linear",
            0.0,
        ),
        (vec![(0.5, BLACK), (0.5, WHITE)], 0.5, "linear", 0.0),
        (
            vec![(0.5, BLACK), (0.5, WHITE)],
            0.500_000_06,
            "linear",
            1.0,
        ),
        // Out of order: sorted first.
        (vec![(1.0, WHITE), (0.0, BLACK)], 0.25, "linear", 0.25),
    ];
    let rows: Vec<_> = cases
        .iter()
        .map(|(s, x, m, _)| (s.clone(), s.len() as i32, *x, *m))
        .collect();
    for ((stops, x, mode, want), got) in cases.iter().zip(ramp_kernel(&rows)) {
        let reference = ramp_reference(stops, stops.len() as i32, *x as f64, mode);
        assert!(
            (reference[0] - want).abs() < 1e-12,
            "reference {mode} at {x}: {reference:?}, hand {want}"
        );
        assert!(
            (got[0] as f64 - want).abs() < 2e-7,
            "kernel {mode} at {x}: {got:?}, hand {want}"
        );
    }
}

impl Rng {
    /// A ramp's stops for the random tests: `n` of them, positions in [0, 1] with one in four a
    /// copy of an earlier one (duplicates), colours in [0, 1], one ramp in four up to 50.
    fn ramp_stops(&mut self, n: usize) -> Vec<(f32, [f32; 4])> {
        let hdr = self.next().is_multiple_of(4);
        let top = if hdr { 50.0 } else { 1.0 };
        let mut s: Vec<(f32, [f32; 4])> = Vec::new();
        for k in 0..n {
            let pos = if k > 0 && self.next().is_multiple_of(4) {
                s[(self.next() % k as u64) as usize].0
            } else {
                self.f32(0.0, 1.0)
            };
            s.push((pos, std::array::from_fn(|_| self.f32(0.0, top))));
        }
        s
    }
}

#[test]
fn ramp_matches_the_reference_at_seeded_points() {
    let mut rng = Rng(0x7a3e_0005);
    let mut rows = Vec::new();
    for _ in 0..6000 {
        let n = 1 + (rng.next() % MAX_STOPS as u64) as usize;
        let stops = rng.ramp_stops(n);
        // Sometimes a count past the stops given: those take the defaults then, so give
        // them all and let count pick.
        let mode = INTERPOLATIONS[(rng.next() % 5) as usize];
        // Half the factors on a stop (the comparisons' edge), the rest in [−0.5, 1.5].
        let x = if rng.next().is_multiple_of(2) {
            stops[(rng.next() % n as u64) as usize].0
        } else {
            rng.f32(-0.5, 1.5)
        };
        rows.push((stops, n as i32, x, mode));
    }
    let got = ramp_kernel(&rows);
    let mut worst = 0.0f64;
    for ((stops, n, x, mode), got) in rows.iter().zip(&got) {
        let want = ramp_reference(stops, *n, *x as f64, mode);
        let scale = want.iter().fold(1.0f64, |m, c| m.max(c.abs()));
        for k in 0..4 {
            let err = (got[k] as f64 - want[k]).abs() / scale;
            worst = worst.max(err);
            assert!(
                err <= 1e-6,
                "{mode}, {n} stops {stops:?}, fac {x}: channel {k} {} against {}",
                got[k],
                want[k]
            );
        }
    }
    eprintln!("color_ramp: worst error {worst:.2e} of the larger of 1 and the colour");
}

#[test]
fn ramp_count_is_clamped_and_the_rest_ignored() {
    let stops: Vec<(f32, [f32; 4])> = vec![(0.0, BLACK), (1.0, WHITE), (0.5, [1.0, 0.0, 0.0, 1.0])];
    let got = ramp_kernel(&[
        (stops.clone(), 2, 0.5, "linear"),
        (stops.clone(), 0, 0.5, "linear"),
        (stops.clone(), -7, 0.9, "linear"),
        (stops.clone(), 3, 0.5, "linear"),
    ]);
    // Two stops: grey; count 0 and −7 read as 1: black; three: the red stop at 0.5.
    assert_eq!(got[0], [0.5, 0.5, 0.5, 1.0]);
    assert_eq!(got[1], BLACK);
    assert_eq!(got[2], BLACK);
    assert_eq!(got[3], [1.0, 0.0, 0.0, 1.0]);
}

// ------------------------------------------------------------------------------------------
// The curve's reference
// ------------------------------------------------------------------------------------------

/// Fritsch & Carlson's monotone cubic (SIAM J. Numer. Anal. 17(2), 1980) in f64 as published:
/// secants δₖ; mₖ the mean of same-signed neighbouring secants (else 0), the one secant at an
/// end; per segment αₖ = mₖ/δₖ, βₖ = mₖ₊₁/δₖ, and where αₖ² + βₖ² > 9 both scaled by
/// τ = 3/√(αₖ² + βₖ²); the cubic Hermite between the points, constant beyond. Points must
/// have distinct x, sorted.
fn fritsch_carlson(points: &[(f64, f64)], x: f64) -> f64 {
    fritsch_carlson_extended(points, x, false)
}

/// Blender's extrapolation slopes (`curvemap_make_table` after `calchandle_curvemap`), in
/// f64: with two points the secant; with more, from an end point towards its neighbour's
/// automatic handle, h = q ∓ t·|q − q∓|/(2.5614·|t|), t the sum of the unit vectors along the
/// neighbour's two segments, the handle's x kept on the curve's side; vertical gives 0.
fn blender_slopes(p: &[(f64, f64)]) -> [f64; 2] {
    let n = p.len();
    let slope = |dx: f64, dy: f64| if dx != 0.0 { dy / dx } else { 0.0 };
    if n == 2 {
        let s = slope(p[1].0 - p[0].0, p[1].1 - p[0].1);
        return [s, s];
    }
    // The handle of point q (between a and b) on the side of a (`toward_a`) or of b.
    let handle = |a: (f64, f64), q: (f64, f64), b: (f64, f64), toward_a: bool| {
        let (ax, ay) = (q.0 - a.0, q.1 - a.1);
        let (bx, by) = (b.0 - q.0, b.1 - q.1);
        let la = match ax.hypot(ay) {
            0.0 => 1.0,
            l => l,
        };
        let lb = match bx.hypot(by) {
            0.0 => 1.0,
            l => l,
        };
        let (tx, ty) = (bx / lb + ax / la, by / lb + ay / la);
        let len = tx.hypot(ty) * 2.5614;
        match (len == 0.0, toward_a) {
            (true, _) => q,
            (false, true) => (q.0 - tx * la / len, q.1 - ty * la / len),
            (false, false) => (q.0 + tx * lb / len, q.1 + ty * lb / len),
        }
    };
    let h = handle(p[0], p[1], p[2], true);
    let lo = slope((h.0 - p[0].0).max(0.0), h.1 - p[0].1);
    let h = handle(p[n - 3], p[n - 2], p[n - 1], false);
    let hi = slope((h.0 - p[n - 1].0).min(0.0), h.1 - p[n - 1].1);
    [lo, hi]
}

/// [`fritsch_carlson`], beyond the ends (`extrapolate`) along Blender's extrapolation
/// slopes ([`blender_slopes`]).
fn fritsch_carlson_extended(points: &[(f64, f64)], x: f64, extrapolate: bool) -> f64 {
    let n = points.len();
    let (xs, ys): (Vec<f64>, Vec<f64>) = points.iter().copied().unzip();
    let delta: Vec<f64> = (0..n - 1)
        .map(|k| (ys[k + 1] - ys[k]) / (xs[k + 1] - xs[k]))
        .collect();
    let mut m: Vec<f64> = (0..n)
        .map(|k| {
            if k == 0 {
                delta[0]
            } else if k == n - 1 {
                delta[n - 2]
            } else if delta[k - 1] * delta[k] > 0.0 {
                (delta[k - 1] + delta[k]) / 2.0
            } else {
                0.0
            }
        })
        .collect();
    for k in 0..n - 1 {
        if delta[k] == 0.0 {
            m[k] = 0.0;
            m[k + 1] = 0.0;
            continue;
        }
        let (a, b) = (m[k] / delta[k], m[k + 1] / delta[k]);
        let s = a * a + b * b;
        if s > 9.0 {
            let tau = 3.0 / s.sqrt();
            m[k] = tau * a * delta[k];
            m[k + 1] = tau * b * delta[k];
        }
    }
    let ext = blender_slopes(points);
    let beyond = |k: usize, s: f64| match extrapolate {
        true => ys[k] + s * (x - xs[k]),
        false => ys[k],
    };
    if x <= xs[0] {
        return beyond(0, ext[0]);
    }
    if x >= xs[n - 1] {
        return beyond(n - 1, ext[1]);
    }
    let k = (0..n - 1).rfind(|&k| xs[k] <= x).unwrap();
    let h = xs[k + 1] - xs[k];
    let t = (x - xs[k]) / h;
    let (t2, t3) = (t * t, t * t * t);
    (2.0 * t3 - 3.0 * t2 + 1.0) * ys[k]
        + (t3 - 2.0 * t2 + t) * h * m[k]
        + (-2.0 * t3 + 3.0 * t2) * ys[k + 1]
        + (t3 - t2) * h * m[k + 1]
}

/// A curve's points as the nodes take them.
fn vec2s(points: &[(f32, f32)]) -> Vec<glam::Vec2> {
    points.iter().map(|&(x, y)| glam::Vec2::new(x, y)).collect()
}

#[test]
fn curve_hand_computed_values() {
    // A peak: (0, 0), (½, ½), (1, 0). m₁ = 0 (the secants change sign), m₀ = 1, m₂ = −1, no
    // limit (α² + β² = 1). At ¼: t = ½, h = ½: ½·½ + ½·(⅛·1 − ⅛·0) = 0.3125; ¾ mirrors it.
    let c = Curve::new(&vec2s(&[(0.0, 0.0), (0.5, 0.5), (1.0, 0.0)]), 3);
    assert_eq!(c.eval(0.25, false), 0.3125);
    assert_eq!(c.eval(0.75, false), 0.3125);
    assert_eq!(c.eval(0.5, false), 0.5);
    assert_eq!(c.eval(-3.0, false), 0.0);
    assert_eq!(c.eval(9.0, false), 0.0);
    // Points on a line, given out of order: the line, everywhere between them.
    let c = Curve::new(
        &vec2s(&[(0.8, 0.62), (0.1, 0.34), (0.5, 0.5), (0.3, 0.42)]),
        4,
    );
    for k in 0..=70 {
        let x = 0.1 + k as f64 / 100.0;
        let want = 0.3 + 0.4 * x;
        assert!(
            (c.eval(x as f32, false) as f64 - want).abs() < 3e-7,
            "{x}: {}",
            c.eval(x as f32, false)
        );
    }
    // A limited segment: (0, 0), (0.1, 1), (1, 1.05). δ = 10, 0.0556; m₁ = 5.03 gives
    // α = 90 on the second segment, so τ = 3/√(α² + β²) scales m₁ and m₂: the curve stays
    // under 1.05 and rises.
    let c = Curve::new(&vec2s(&[(0.0, 0.0), (0.1, 1.0), (1.0, 1.05)]), 3);
    let pts = [(0.0, 0.0), (0.1, 1.0), (1.0, 1.05)];
    for k in 0..=100 {
        let x = k as f64 / 100.0;
        let got = c.eval(x as f32, false) as f64;
        let want = fritsch_carlson(&pts, x);
        assert!((got - want).abs() < 1e-6, "{x}: {got} against {want}");
        assert!(got <= 1.05 + 1e-7, "{x}: {got} overshoots 1.05");
    }
}

#[test]
fn equal_x_make_a_jump() {
    // (0, 0), (½, 0.2), (½, 0.8), (1, 1): below ½ the curve of the first two points (a
    // line: both tangents there are the one secant 0.4), from ½ on the last two's.
    let c = Curve::new(&vec2s(&[(0.0, 0.0), (0.5, 0.8), (0.5, 0.2), (1.0, 1.0)]), 4);
    // Sorted stably: (½, 0.8) stays before (½, 0.2).
    assert_eq!(c.eval(0.5, false), 0.2);
    assert!((c.eval(0.499_999_97, false) - 0.8).abs() < 1e-6);
    assert!(
        (c.eval(0.25, false) - 0.4).abs() < 1e-6,
        "{}",
        c.eval(0.25, false)
    );
    assert!(
        (c.eval(0.75, false) - 0.6).abs() < 1e-6,
        "{}",
        c.eval(0.75, false)
    );
}

impl Rng {
    /// `n` points with distinct x at least 2⁻¹⁰ apart in [0, 1], y in [−2, 2], shuffled.
    fn curve_points(&mut self, n: usize) -> Vec<(f32, f32)> {
        let mut xs: Vec<f32> = Vec::new();
        while xs.len() < n {
            let x = (self.f32(0.0, 1.0) * 1024.0).round() / 1024.0;
            if !xs.contains(&x) {
                xs.push(x);
            }
        }
        xs.into_iter().map(|x| (x, self.f32(-2.0, 2.0))).collect()
    }
}

#[test]
fn curve_matches_fritsch_carlson_and_keeps_its_properties() {
    let mut rng = Rng(0x000c_04e5_0005);
    let mut worst = 0.0f64;
    for case in 0..400u32 {
        let n = 2 + (rng.next() % 15) as usize;
        let pts = rng.curve_points(n);
        // One case in four monotone: the same points with y sorted along x.
        let pts = if case.is_multiple_of(4) {
            let mut xs: Vec<f32> = pts.iter().map(|p| p.0).collect();
            let mut ys: Vec<f32> = pts.iter().map(|p| p.1).collect();
            xs.sort_by(f32::total_cmp);
            ys.sort_by(f32::total_cmp);
            xs.into_iter().zip(ys).collect()
        } else {
            pts
        };
        let c = Curve::new(&vec2s(&pts), n as i32);
        let mut sorted: Vec<(f64, f64)> = pts.iter().map(|&(x, y)| (x as f64, y as f64)).collect();
        sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
        // Through every point.
        for &(x, y) in &sorted {
            assert_eq!(c.eval(x as f32, false) as f64, y, "case {case}: at {x}");
        }
        for w in sorted.windows(2) {
            let ((x0, y0), (x1, y1)) = (w[0], w[1]);
            let (lo, hi) = (y0.min(y1), y0.max(y1));
            let tol = 1e-6 * (1.0 + hi.abs().max(lo.abs()));
            let mut last = y0;
            for j in 0..=32 {
                let x = (x0 + (x1 - x0) * j as f64 / 32.0) as f32;
                let got = c.eval(x, false) as f64;
                let want = fritsch_carlson(&sorted, x as f64);
                worst = worst.max((got - want).abs());
                assert!(
                    (got - want).abs() <= tol,
                    "case {case} {sorted:?}: at {x} {got} against {want}"
                );
                // No overshoot, and monotone within the segment.
                assert!(
                    got >= lo - tol && got <= hi + tol,
                    "case {case}: {got} at {x} leaves [{lo}, {hi}]"
                );
                if y1 >= y0 {
                    assert!(got >= last - tol, "case {case}: falls at {x}");
                } else {
                    assert!(got <= last + tol, "case {case}: rises at {x}");
                }
                last = got;
            }
        }
        // Beyond the ends: the end points' values.
        assert_eq!(c.eval(-5.0, false) as f64, sorted[0].1);
        assert_eq!(c.eval(5.0, false) as f64, sorted[n - 1].1);
    }
    eprintln!("curve: worst |cpu − f64 Fritsch–Carlson| {worst:.2e}");
}

/// The inputs of a float curve node.
pub(crate) fn float_curve_row(
    points: &[(f32, f32)],
    factor: f32,
    value: f32,
) -> Vec<(&'static str, Value)> {
    let mut row = vec![
        ("factor", Value::float(factor)),
        ("value", Value::float(value)),
        ("count", Value::int(points.len() as i32)),
    ];
    for (k, &(x, y)) in points.iter().enumerate() {
        row.push((curves::POINTS[k], Value::vec2([x, y])));
    }
    row
}

#[test]
fn float_curve_node_mixes_by_its_factor() {
    let t = curves::float_curve_type();
    let mut rng = Rng(0xf10a_7c00);
    let mut cases = Vec::new();
    for _ in 0..500 {
        let n = 2 + (rng.next() % 15) as usize;
        let pts = rng.curve_points(n);
        cases.push((pts, rng.f32(0.0, 1.0), rng.f32(-0.5, 1.5)));
    }
    let rows: Vec<_> = cases
        .iter()
        .map(|(p, f, v)| float_curve_row(p, *f, *v))
        .collect();
    let s = samples(&t, &rows);
    let out = run_cpu(&t, SocketType::Float, &s);
    for (i, (pts, f, v)) in cases.iter().enumerate() {
        let mut sorted: Vec<(f64, f64)> = pts.iter().map(|&(x, y)| (x as f64, y as f64)).collect();
        sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (f, v) = (*f as f64, *v as f64);
        // Extrapolated beyond the ends (the default, Blender's).
        let want = (1.0 - f) * v + f * fritsch_carlson_extended(&sorted, v, true);
        let got = out[0][i] as f64;
        // Between the ends 2e-6; beyond them the extrapolated slope comes from a handle's
        // x offset, a difference that f32 rounds (measured 2.5e-6 relative): 1e-5 relative.
        let inside = v > sorted[0].0 && v < sorted[sorted.len() - 1].0;
        let tol = if inside {
            2e-6
        } else {
            1e-5 * want.abs().max(1.0)
        };
        assert!(
            (got - want).abs() < tol,
            "{pts:?} f {f} v {v}: {got} against {want}"
        );
    }
}

#[test]
fn rgb_curves_apply_the_combined_curve_first() {
    let t = curves::rgb_curves_type();
    // C squares-ish (a sagging curve), R inverts; G and B the identity.
    let c_pts = [(0.0, 0.0), (0.5, 0.2), (1.0, 1.0)];
    let r_pts = [(0.0, 1.0), (1.0, 0.0)];
    let mut row = vec![
        ("fac", Value::float(0.75)),
        ("color", Value::color([0.3, 0.6, 0.9])),
        ("c_count", Value::int(3)),
    ];
    for (k, &(x, y)) in c_pts.iter().enumerate() {
        row.push((curves::C_POINTS[k], Value::vec2([x, y])));
    }
    for (k, &(x, y)) in r_pts.iter().enumerate() {
        row.push((curves::R_POINTS[k], Value::vec2([x, y])));
    }
    let s = samples(&t, &[row]);
    let out = run_cpu(&t, SocketType::Float, &s);
    let got = output(&out, 0, 3, 1, 0);
    let c = |x: f64| fritsch_carlson(&[(0.0, 0.0), (0.5, 0.2), (1.0, 1.0)], x);
    let r = |x: f64| 1.0 - x.clamp(0.0, 1.0);
    let input = [0.3f32 as f64, 0.6f32 as f64, 0.9f32 as f64];
    let mapped = [r(c(input[0])), c(input[1]), c(input[2])];
    for k in 0..3 {
        let want = 0.25 * input[k] + 0.75 * mapped[k];
        assert!((got[k] as f64 - want).abs() < 1e-6, "channel {k}: {got:?}");
    }
    // The other order (R, then C) is far from it: the test tells them apart.
    let swapped = 0.25 * input[0] + 0.75 * c(r(input[0]));
    assert!((swapped - got[0] as f64).abs() > 0.05);
}

// ------------------------------------------------------------------------------------------
// Stability: every sample the parity suites would draw, and the hard cases
// ------------------------------------------------------------------------------------------

/// The three node types.
fn types() -> Vec<NodeType> {
    vec![
        color_ramp::color_ramp_type(),
        curves::float_curve_type(),
        curves::rgb_curves_type(),
    ]
}

#[test]
fn random_and_hard_inputs_give_finite_outputs() {
    for (k, t) in types().iter().enumerate() {
        let s = node_samples(t, SocketType::Float, 0x5eed_0005 + k as u64);
        let out = run_cpu(t, SocketType::Float, &s);
        for (o, col) in out.iter().enumerate() {
            if let Some(i) = col.iter().position(|x| !x.is_finite()) {
                let inputs: Vec<String> = t
                    .inputs()
                    .iter()
                    .enumerate()
                    .map(|(j, d)| format!("{}={}", d.name, s.columns[j][i % s.n]))
                    .collect();
                panic!(
                    "{}: output {} not finite at sample {}: {}",
                    t.name(),
                    t.outputs()[o].name,
                    i % s.n,
                    inputs.join(" ")
                );
            }
        }
    }
}

// ------------------------------------------------------------------------------------------
// Bad input at load
// ------------------------------------------------------------------------------------------

/// The builtin types and the three (not in `matgraph::nodes::all()` yet).
fn registry() -> Registry {
    let mut r = Registry::default();
    for t in matgraph::nodes::all().into_iter().chain(types()) {
        r.register(t);
    }
    r
}

/// The errors loading one node of type `ty` with `inputs`.
fn load_errors(r: &Registry, ty: &str, inputs: serde_json::Value) -> Vec<GraphError> {
    let doc = json!({
        "version": 2,
        "name": "bad",
        "nodes": [{ "id": "n1", "type": ty, "inputs": inputs }],
    });
    match Graph::from_json(&doc.to_string(), r) {
        Ok(_) => Vec::new(),
        Err(e) => e,
    }
}

#[test]
fn bad_counts_and_stops_are_refused_at_load_naming_node_and_input() {
    let r = registry();
    let cases = [
        ("color_ramp", json!({ "count": 0 }), "count"),
        ("color_ramp", json!({ "count": 17 }), "count"),
        ("color_ramp", json!({ "pos_3": 1.5 }), "pos_3"),
        (
            "color_ramp",
            json!({ "color_2": [0.5, -0.1, 0.0, 1.0] }),
            "color_2",
        ),
        ("float_curve", json!({ "count": 0 }), "count"),
        ("float_curve", json!({ "count": 1 }), "count"),
        ("float_curve", json!({ "count": 17 }), "count"),
        ("float_curve", json!({ "point_4": [0.5, 101.0] }), "point_4"),
        ("float_curve", json!({ "factor": 1.5 }), "factor"),
        ("rgb_curves", json!({ "g_count": 17 }), "g_count"),
        ("rgb_curves", json!({ "b_15": [-100.5, 0.0] }), "b_15"),
    ];
    for (ty, inputs, input) in cases {
        let errors = load_errors(&r, ty, inputs.clone());
        let hit = errors.iter().any(|e| {
            matches!(e, GraphError::OutOfRange { node, input: i, .. } if node == "n1" && i == input)
        });
        assert!(hit, "{ty} {inputs}: {errors:?}");
        let text = errors[0].to_string();
        assert!(text.contains("n1") && text.contains(input), "{text}");
    }
    // Unsorted and duplicate stops are not errors: they are sorted on evaluation.
    let fine = json!({ "count": 3, "pos_0": 1.0, "pos_1": 0.5, "pos_2": 0.5 });
    assert!(load_errors(&r, "color_ramp", fine).is_empty());
    // A stop's colour as a plain RGB triple is refused (it takes RGBA).
    let errors = load_errors(&r, "color_ramp", json!({ "color_0": [1.0, 0.0, 0.0] }));
    assert!(!errors.is_empty());
}

#[test]
fn a_bad_file_names_its_path() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ramp.json");
    let doc = json!({
        "version": 2,
        "name": "ramp",
        "nodes": [{ "id": "ramp", "type": "color_ramp", "inputs": { "count": 17 } }],
    });
    std::fs::write(&path, doc.to_string()).unwrap();
    let e = matgraph::io::load_graph(&path, &registry()).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("ramp.json") && text.contains("count") && text.contains("16"),
        "{text}"
    );
}

// ------------------------------------------------------------------------------------------
// WGSL: naga and Tint
// ------------------------------------------------------------------------------------------

#[test]
fn the_wgsl_validates_with_naga_and_tint() {
    const TEST: &str = "the_wgsl_validates_with_naga_and_tint";
    let modules: Vec<(String, String)> = types()
        .iter()
        .map(|t| {
            let h =
                node_harness(t, SocketType::Float).unwrap_or_else(|e| panic!("{}: {e}", t.name()));
            (t.name().to_owned(), h.source)
        })
        .collect();
    let Some(tint) = tool_or_skip(TEST, Tint::find()) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let files: Vec<_> = modules
        .iter()
        .map(|(name, source)| {
            let f = dir.path().join(format!("{name}.harness.wgsl"));
            std::fs::write(&f, source).unwrap();
            f
        })
        .collect();
    let diagnostics = tint.check(&files).unwrap_or_else(|e| panic!("{e}"));
    for d in &diagnostics {
        common::print_warning(TEST, &d.to_string());
    }
    assert!(
        diagnostics.iter().all(|d| d.severity != "error"),
        "{diagnostics:#?}"
    );
}

#[test]
fn every_curve_point_input_is_declared_once_in_order() {
    let t = curves::rgb_curves_type();
    let names: Vec<&str> = t.inputs().iter().map(|d| d.name).collect();
    assert_eq!(names.len(), 3 + 4 * (1 + MAX_POINTS));
    // The colour first: the registry suites link the first input, and with the default
    // (identity) curves only the colour changes the output.
    assert_eq!(&names[..4], ["color", "fac", "extend", "c_count"]);
    assert_eq!(names[4 + MAX_POINTS], "r_count");
    assert_eq!(names.last(), Some(&"b_15"));
}
