//! Component-wise functions of Blender's Math and Vector Math nodes that `math` lacks:
//! trigonometry, rounding, floored modulo, roots and logarithms, comparison and selection.
//! Every node is generic (float, vec2, vec3, vec4, colour) and acts per component.
//!
//! Invalid arguments are made total the way Blender's safe math is, so that every finite
//! input gives a finite output: `asin`/`acos` clamp their argument to [-1, 1], `sqrt` of a
//! negative is 0, `inverse_sqrt` and `log` of x ≤ 0 are 0, `floored_modulo` by 0 is 0 and
//! `atan2(0, 0)` is 0. Each node's doc states its rule and what it costs.
//!
//! GPU accuracy: the WGSL uses the builtins `sin`, `cos`, `sqrt`, `log`. The WGSL
//! specification bounds `sin`/`cos` only on [-π, π] (absolute error 2⁻¹¹); beyond it a
//! driver's range reduction may lose digits, so the soft ranges stay within a few periods
//! and docs/models/math.md lists what lavapipe measures. `asin`, `acos` and `atan2` are
//! written out (Cephes' `asinf` and `atanf` polynomials, relative error ~1e-7) because the
//! WGSL builtins are specified only loosely and lavapipe's `atan` is off by 3e-6.

use super::math::Components;
use crate::node::{Category, In, NodeType, Out};
use crate::nodes::precise::{self, SIN_COS_WGSL, sin_cos};
use crate::precision;
use crate::types::SocketType::*;
use crate::value::Value;
use glam::{Vec2, Vec3, Vec4};
use std::cell::Cell;

/// Registers `f::<T>` for float, vec2, vec3 and vec4 (colour uses the vec3 variant).
macro_rules! all_types {
    ($t:expr, $f:ident) => {
        $t.variant(Float, $f::<f32>)
            .variant(Vec2, $f::<Vec2>)
            .variant(Vec3, $f::<Vec3>)
            .variant(Vec4, $f::<Vec4>)
    };
}

/// Quotients at or beyond this magnitude leave `floored_modulo` no integer part to take:
/// adjacent f32 values of `a` are then more than |b| apart.
pub const MODULO_QUOTIENT_LIMIT: f32 = 16_777_216.0;

/// Blender's Compare: the smallest epsilon used, f32's machine epsilon.
pub const COMPARE_MIN_EPSILON: f32 = f32::EPSILON;

/// `atan2(y, x)` with Blender's rule `atan2(0, 0) = 0`, and a zero of either sign read as
/// +0, so that the result does not depend on the sign of a zero (which GPUs may drop):
/// `atan2(±0, x < 0) = π`. Built from `atan` of the smaller over the larger magnitude, so no
/// quotient overflows; the WGSL takes the same steps.
#[inline(always)]
pub fn atan2_total(y: f32, x: f32) -> f32 {
    let (ay, ax) = (y.abs(), x.abs());
    let (lo, hi) = if ay > ax { (ax, ay) } else { (ay, ax) };
    if hi == 0.0 {
        return 0.0;
    }
    let t = (lo / hi).atan();
    let a = if ay > ax {
        std::f32::consts::FRAC_PI_2 - t
    } else {
        t
    };
    let a = if x < 0.0 { std::f32::consts::PI - a } else { a };
    if y < 0.0 { -a } else { a }
}

/// The floored modulo `a − b·⌊a/b⌋` (Blender's Floored Modulo), total and in the period:
/// 0 for b = 0; the result lies in [0, b) for b > 0 and (b, 0] for b < 0 (one correction
/// step where ⌊a/b⌋ rounds across an integer; a result that rounds to the period itself is
/// returned as 0, the same point of the cycle); 0 where |a/b| ≥ 2²⁴
/// ([`MODULO_QUOTIENT_LIMIT`]).
#[inline(always)]
pub fn floored_modulo(a: f32, b: f32) -> f32 {
    if b == 0.0 {
        return 0.0;
    }
    let q = a / b;
    if q.is_nan() || q.abs() >= MODULO_QUOTIENT_LIMIT {
        return 0.0;
    }
    let mut r = a - q.floor() * b;
    if b > 0.0 {
        if r < 0.0 {
            r += b;
        }
        if r >= b {
            r -= b;
        }
    } else {
        if r > 0.0 {
            r += b;
        }
        if r <= b {
            r -= b;
        }
    }
    r
}

/// `x − ⌊x⌋` in [0, 1): where the difference rounds to 1 (x negative and within 2⁻²⁵ of an
/// integer) the result is 0, the same point of the cycle.
#[inline(always)]
pub fn fract(x: f32) -> f32 {
    let r = x - x.floor();
    if r >= 1.0 { 0.0 } else { r }
}

fn sin<T: Components>(x: T) -> T {
    x.map(|x| sin_cos(x).0)
}
fn cos<T: Components>(x: T) -> T {
    x.map(|x| sin_cos(x).1)
}
fn tan<T: Components>(x: T) -> T {
    x.map(|x| {
        let (s, c) = sin_cos(x);
        s / c
    })
}
fn asin<T: Components>(x: T) -> T {
    x.map(|x| x.clamp(-1.0, 1.0).asin())
}
fn acos<T: Components>(x: T) -> T {
    x.map(|x| x.clamp(-1.0, 1.0).acos())
}
fn atan2<T: Components>(y: T, x: T) -> T {
    y.zip(x, atan2_total)
}
fn abs<T: Components>(x: T) -> T {
    x.map(f32::abs)
}
fn sign<T: Components>(x: T) -> T {
    x.map(|x| {
        if x > 0.0 {
            1.0
        } else if x < 0.0 {
            -1.0
        } else {
            0.0
        }
    })
}
fn min<T: Components>(a: T, b: T) -> T {
    a.zip(b, f32::min)
}
fn max<T: Components>(a: T, b: T) -> T {
    a.zip(b, f32::max)
}
fn floor<T: Components>(x: T) -> T {
    x.map(f32::floor)
}
fn ceil<T: Components>(x: T) -> T {
    x.map(f32::ceil)
}
fn fract_t<T: Components>(x: T) -> T {
    x.map(fract)
}
fn modulo<T: Components>(a: T, b: T) -> T {
    a.zip(b, floored_modulo)
}
fn sqrt<T: Components>(x: T) -> T {
    x.map(|x| precision::sqrt(x.max(0.0)))
}
fn inverse_sqrt<T: Components>(x: T) -> T {
    x.map(|x| {
        if x > 0.0 {
            1.0 / precision::sqrt(x)
        } else {
            0.0
        }
    })
}
fn log<T: Components>(x: T) -> T {
    x.map(|x| if x > 0.0 { precision::log(x) } else { 0.0 })
}
fn log_base<T: Components>(x: T, base: T) -> T {
    x.zip(base, |x, b| {
        if x > 0.0 && b > 0.0 {
            super::math::safe_div(precise::log2_exact(x), precise::log2_exact(b))
        } else {
            0.0
        }
    })
}
fn negate<T: Components>(x: T) -> T {
    x.map(|x| -x)
}
fn one_minus<T: Components>(x: T) -> T {
    x.map(|x| 1.0 - x)
}
fn compare<T: Components>(a: T, b: T, epsilon: f32) -> (T, bool) {
    let eps = epsilon.max(COMPARE_MIN_EPSILON);
    let all = Cell::new(true);
    let r = a.zip(b, |a, b| {
        if a == b || (a - b).abs() <= eps {
            1.0
        } else {
            all.set(false);
            0.0
        }
    });
    (r, all.get())
}
fn select<T: Components>(condition: bool, if_false: T, if_true: T) -> T {
    if condition { if_true } else { if_false }
}

/// WGSL of [`atan2_total`] as a helper, `mg_math_atan2(y, x)`: the same steps, with Cephes' `atanf`
/// (S. Moshier; relative error ~1e-7) for the builtin `atan`. WGSL bounds its own `atan2` only
/// loosely (4096 ULP) and only where `y` is normal and `x` is in [2⁻¹²⁶, 2¹²⁶], so a zero
/// (straight along an axis, at a pole) is undefined there; here every input has its value.
/// Shared by the `atan2` node and the equirectangular lookups (`equirect_uv`, the IBL nodes).
pub const ATAN2_HELPER_WGSL: &str = r#"
fn mg_math_atan2(y: f32, x: f32) -> f32 {
    let ay = abs(y);
    let ax = abs(x);
    let steep = ay > ax;
    let lo = select(ay, ax, steep);
    let hi = select(ax, ay, steep);
    // Cephes' atanf on [0, 1]: reduced by tan(π/8), then an odd polynomial.
    let r = lo / select(hi, 1.0, hi == 0.0);
    let wide = r > 0.41421356237309503;
    let u = select(r, (r - 1.0) / (r + 1.0), wide);
    let z = u * u;
    let t = select(0.0, 0.7853981633974483, wide)
        + (((8.05374449538e-2 * z - 1.38776856032e-1) * z + 1.99777106478e-1) * z
        - 3.33329491539e-1) * z * u + u;
    var a = select(t, 1.5707963267948966 - t, steep);
    a = select(a, 3.141592653589793 - a, x < 0.0);
    a = select(a, -a, y < 0.0);
    return select(a, 0.0, hi == 0.0);
}
"#;

/// WGSL of the `atan2` node at widths 1–4: [`ATAN2_HELPER_WGSL`] per component.
const ATAN2_WGSL: [&str; 4] = [
    "fn $fn(y: f32, x: f32) -> f32 { return mg_math_atan2(y, x); }",
    "fn $fn(y: vec2<f32>, x: vec2<f32>) -> vec2<f32> { return vec2<f32>(mg_math_atan2(y.x, x.x), mg_math_atan2(y.y, x.y)); }",
    "fn $fn(y: vec3<f32>, x: vec3<f32>) -> vec3<f32> { return vec3<f32>(mg_math_atan2(y.x, x.x), mg_math_atan2(y.y, x.y), mg_math_atan2(y.z, x.z)); }",
    "fn $fn(y: vec4<f32>, x: vec4<f32>) -> vec4<f32> { return vec4<f32>(mg_math_atan2(y.x, x.x), mg_math_atan2(y.y, x.y), mg_math_atan2(y.z, x.z), mg_math_atan2(y.w, x.w)); }",
];

/// WGSL of asin, Cephes' `asinf` (S. Moshier): an odd polynomial in x on |x| ≤ 1/2, and
/// `π/2 − 2·asin(√((1 − |x|)/2))` above; the argument is clamped to [-1, 1] first.
const ASIN_WGSL: &str = r#"
fn $fn(x0: $T) -> $T {
    let x = min(max(x0, $T(-1.0)), $T(1.0));
    let a = abs(x);
    let high = a > $T(0.5);
    let z = select(a * a, 0.5 * (1.0 - a), high);
    let s = select(a, sqrt(z), high);
    let p = ((((4.2163199048e-2 * z + 2.4181311049e-2) * z + 4.5470025998e-2) * z
        + 7.4953002686e-2) * z + 1.6666752422e-1) * z * s + s;
    let r = select(p, $T(1.5707963267948966) - 2.0 * p, high);
    return select(r, -r, x < $T(0.0));
}
"#;

/// WGSL of acos, Cephes' `acosf`: `2·asin(√((1 − x)/2))` above 1/2, `π − 2·asin(√((1 + x)/2))`
/// below −1/2 (both keep their relative accuracy near ±1), `π/2 − asin(x)` between; the
/// argument is clamped to [-1, 1] first.
const ACOS_WGSL: &str = r#"
fn $fn(x0: $T) -> $T {
    let x = min(max(x0, $T(-1.0)), $T(1.0));
    let a = abs(x);
    let high = a > $T(0.5);
    let z = select(a * a, 0.5 * (1.0 - a), high);
    let s = select(a, sqrt(z), high);
    let p = ((((4.2163199048e-2 * z + 2.4181311049e-2) * z + 4.5470025998e-2) * z
        + 7.4953002686e-2) * z + 1.6666752422e-1) * z * s + s;
    let mid = $T(1.5707963267948966) - select(p, -p, x < $T(0.0));
    let side = select(2.0 * p, $T(3.141592653589793) - 2.0 * p, x < $T(0.0));
    return select(mid, side, high);
}
"#;

/// WGSL of [`floored_modulo`]: the same steps with selects.
const MODULO_WGSL: &str = r#"
fn $fn(a: $T, b: $T) -> $T {
    let zero = $T(0.0);
    let q = a / select(b, $T(1.0), b == zero);
    var r = a - floor(q) * b;
    let pos = b > zero;
    r = select(r, r + b, select(r > zero, r < zero, pos));
    r = select(r, r - b, select(r <= b, r >= b, pos));
    return select(r, zero, (b == zero) | !(abs(q) < $T(16777216.0)));
}
"#;

/// WGSL of [`fract`].
const FRACT_WGSL: &str = r#"
fn $fn(x: $T) -> $T {
    let r = x - floor(x);
    return select(r, $T(0.0), r >= $T(1.0));
}
"#;

/// WGSL of the sign node (WGSL's `sign` is the same, written out for clarity at 0).
const SIGN_WGSL: &str = "fn $fn(x: $T) -> $T { return select(select($T(0.0), $T(-1.0), x < $T(0.0)), $T(1.0), x > $T(0.0)); }";

/// WGSL of the inverse square root: `1/√x` (not the builtin `inverseSqrt`, specified to
/// 2 ulp and approximated by some drivers), 0 for x ≤ 0.
const INVERSE_SQRT_WGSL: &str = r#"
fn $fn(x: $T) -> $T {
    let pos = x > $T(0.0);
    return select($T(0.0), 1.0 / sqrt(select($T(1.0), x, pos)), pos);
}
"#;

/// WGSL of the natural log, 0 for x ≤ 0.
const LOG_WGSL: &str = r#"
fn $fn(x: $T) -> $T {
    let pos = x > $T(0.0);
    return select($T(0.0), log(select($T(1.0), x, pos)), pos);
}
"#;

/// WGSL of Blender's Logarithm as a helper, `mg_math_log_base(x, base)`: `log2 x / log2 base` with
/// [`precise::LOG2_EXACT_WGSL`] through the safe divide, 0 unless both are positive.
const LOG_BASE_HELPER_WGSL: &str = r#"
fn mg_math_log_base(x: f32, base: f32) -> f32 {
    let ok = (x > 0.0) && (base > 0.0);
    let lx = mg_log2_exact(select(1.0, x, ok));
    let lb = mg_log2_exact(select(1.0, base, ok));
    return select(0.0, lx / select(lb, 1.0, lb == 0.0), ok && (lb != 0.0));
}
"#;

/// WGSL of the `log_base` node at widths 1–4: [`LOG_BASE_HELPER_WGSL`] per component.
const LOG_BASE_WGSL: [&str; 4] = [
    "fn $fn(x: f32, base: f32) -> f32 { return mg_math_log_base(x, base); }",
    "fn $fn(x: vec2<f32>, base: vec2<f32>) -> vec2<f32> { return vec2<f32>(mg_math_log_base(x.x, base.x), mg_math_log_base(x.y, base.y)); }",
    "fn $fn(x: vec3<f32>, base: vec3<f32>) -> vec3<f32> { return vec3<f32>(mg_math_log_base(x.x, base.x), mg_math_log_base(x.y, base.y), mg_math_log_base(x.z, base.z)); }",
    "fn $fn(x: vec4<f32>, base: vec4<f32>) -> vec4<f32> { return vec4<f32>(mg_math_log_base(x.x, base.x), mg_math_log_base(x.y, base.y), mg_math_log_base(x.z, base.z), mg_math_log_base(x.w, base.w)); }",
];

/// WGSL of Blender's Compare, component-wise, and whether every component compares equal.
const COMPARE_WGSL: &str = r#"
fn $fn(a: $T, b: $T, epsilon: f32) -> $out {
    let e = (a == b) | (abs(a - b) <= $T(max(epsilon, 1.1920929e-7)));
    return $out(select($T(0.0), $T(1.0), e), all(e));
}
"#;

/// WGSL of a component-wise node at widths 1–4 whose value at each component is `$e`, an
/// expression of `sc = mg_prec_sincos(x)` (that component's sine and cosine).
macro_rules! per_width {
    ($e:literal) => {
        [
            concat!("fn $fn(x: f32) -> f32 { let sc = mg_prec_sincos(x); return ", $e, "; }"),
            concat!(
                "fn $fn(x: vec2<f32>) -> vec2<f32> { var r: vec2<f32>; for (var i = 0u; i < 2u; i++) { let sc = mg_prec_sincos(x[i]); r[i] = ",
                $e,
                "; } return r; }"
            ),
            concat!(
                "fn $fn(x: vec3<f32>) -> vec3<f32> { var r: vec3<f32>; for (var i = 0u; i < 3u; i++) { let sc = mg_prec_sincos(x[i]); r[i] = ",
                $e,
                "; } return r; }"
            ),
            concat!(
                "fn $fn(x: vec4<f32>) -> vec4<f32> { var r: vec4<f32>; for (var i = 0u; i < 4u; i++) { let sc = mg_prec_sincos(x[i]); r[i] = ",
                $e,
                "; } return r; }"
            ),
        ]
    };
}

/// WGSL of `sin` at widths 1–4: [`sin_cos`](crate::nodes::precise::sin_cos)'s sine.
const SIN_WGSL: [&str; 4] = per_width!("sc.x");
/// WGSL of `cos` at widths 1–4.
const COS_WGSL: [&str; 4] = per_width!("sc.y");
/// WGSL of `tan` at widths 1–4: sine over cosine.
const TAN_WGSL: [&str; 4] = per_width!("sc.x / sc.y");

/// A one-input component-wise node.
fn unary(
    name: &'static str,
    summary: &'static str,
    source: &'static str,
    x: (f32, f32, f32),
    out_doc: &'static str,
    wgsl: &'static str,
) -> NodeType {
    NodeType::new(name, Category::Math, summary)
        .source(source)
        .input(In::generic("x", x.0).range(x.1, x.2).doc("Value."))
        .output(Out::generic("result").doc(out_doc))
        .wgsl(wgsl)
}

/// A two-input component-wise node on `a` and `b`.
fn binary(
    name: &'static str,
    summary: &'static str,
    source: &'static str,
    defaults: (f32, f32),
    out_doc: &'static str,
    wgsl: &'static str,
) -> NodeType {
    NodeType::new(name, Category::Math, summary)
        .source(source)
        .input(
            In::generic("a", defaults.0)
                .range(-10.0, 10.0)
                .doc("First operand."),
        )
        .input(
            In::generic("b", defaults.1)
                .range(-10.0, 10.0)
                .doc("Second operand."),
        )
        .output(Out::generic("result").doc(out_doc))
        .wgsl(wgsl)
}

/// The scalar-math node types.
pub fn all() -> Vec<NodeType> {
    let v = |x: f32| Value::float(x);
    vec![
        all_types!(
            unary(
                "sin",
                "Sine of x (radians), component-wise.",
                "Computed by the node, not by WGSL's sin (specified only to 2⁻¹¹ absolute on [−π, π] \
                 and not at all beyond, docs/precision.md): Cody–Waite reduction by π/2 and Cephes' \
                 sinf/cosf polynomials, the same f32 steps on the CPU and the GPU \
                 (nodes/precise.rs). A few ULP for |x| < 1.2e4; beyond, the argument's own \
                 rounding dominates (one ULP of x is 0.06 rad at 1e6).",
                (0.0, -10.0, 10.0),
                "sin x.",
                SIN_WGSL[0],
            )
            .wgsl_variant(Vec2, SIN_WGSL[1])
            .wgsl_variant(Vec3, SIN_WGSL[2])
            .wgsl_variant(Vec4, SIN_WGSL[3])
            .wgsl_uses(&[SIN_COS_WGSL])
            .hard_case("large argument", &[("x", v(1000.0))]),
            sin
        ),
        all_types!(
            unary(
                "cos",
                "Cosine of x (radians), component-wise.",
                "Computed by the node as sin is (nodes/precise.rs): a few ULP for |x| < 1.2e4 on \
                 the CPU and on every GPU.",
                (0.0, -10.0, 10.0),
                "cos x.",
                COS_WGSL[0],
            )
            .wgsl_variant(Vec2, COS_WGSL[1])
            .wgsl_variant(Vec3, COS_WGSL[2])
            .wgsl_variant(Vec4, COS_WGSL[3])
            .wgsl_uses(&[SIN_COS_WGSL])
            .hard_case("large argument", &[("x", v(1000.0))]),
            cos
        ),
        all_types!(
            unary(
                "tan",
                "Tangent of x (radians), component-wise.",
                "Closed form, no clamp: tan is finite at every f32 (none is exactly π/2; at the \
                 nearest, 1.5707964, it is −2.3e7). Near a pole tan is ill-conditioned (relative \
                 condition number 2x/sin 2x: 21 at x = 1.5, 2000 at 1.57), so the soft range stops at ±1.5. \
                 Formed as sin/cos from the node's own sine and cosine (nodes/precise.rs), not \
                 WGSL's.",
                (0.0, -1.5, 1.5),
                "tan x.",
                TAN_WGSL[0],
            )
            .wgsl_variant(Vec2, TAN_WGSL[1])
            .wgsl_variant(Vec3, TAN_WGSL[2])
            .wgsl_variant(Vec4, TAN_WGSL[3])
            .wgsl_uses(&[SIN_COS_WGSL])
            .hard_case("steep", &[("x", v(1.5))]),
            tan
        ),
        all_types!(
            unary(
                "asin",
                "Arcsine of x in radians, x clamped to [-1, 1].",
                "Blender's safe asin: the argument is clamped to [-1, 1], so |x| > 1 gives ±π/2 \
                 (the cost: no error is reported for such x). The GPU evaluates Cephes' asinf \
                 polynomial (relative error ~1e-7).",
                (0.0, -1.0, 1.0),
                "asin x, in [-π/2, π/2].",
                ASIN_WGSL,
            )
            .hard_case("beyond 1", &[("x", v(1.5))])
            .hard_case("beyond -1", &[("x", v(-3.0))])
            .hard_case("just below 1", &[("x", v(0.99999994))]),
            asin
        ),
        all_types!(
            unary(
                "acos",
                "Arccosine of x in radians, x clamped to [-1, 1].",
                "Blender's safe acos: the argument is clamped to [-1, 1], so x > 1 gives 0 and \
                 x < −1 gives π (the cost: no error is reported for such x). The GPU evaluates \
                 Cephes' acosf (relative error ~1e-7, also near ±1).",
                (0.0, -1.0, 1.0),
                "acos x, in [0, π].",
                ACOS_WGSL,
            )
            .hard_case("beyond 1", &[("x", v(1.5))])
            .hard_case("beyond -1", &[("x", v(-3.0))])
            .hard_case("just below 1", &[("x", v(0.99999994))])
            .hard_case("just above -1", &[("x", v(-0.99999994))]),
            acos
        ),
        all_types!(
            NodeType::new(
                "atan2",
                Category::Math,
                "Angle of the point (x, y) in radians, component-wise."
            )
            .source(
                "C's atan2(y, x), in [-π, π], with Blender's atan2(0, 0) = 0. A zero of either \
                 sign is read as +0 (GPUs may drop the sign of a zero), so atan2(±0, x < 0) = π, \
                 never −π. Formed as atan(min/max) of the magnitudes with the quadrant from the \
                 signs, so no quotient overflows.",
            )
            .input(In::generic("y", 0.0).range(-10.0, 10.0).doc("Ordinate."))
            .input(In::generic("x", 1.0).range(-10.0, 10.0).doc("Abscissa."))
            .output(Out::generic("result").doc("atan2(y, x), in [-π, π]."))
            .wgsl(ATAN2_WGSL[0])
            .wgsl_variant(Vec2, ATAN2_WGSL[1])
            .wgsl_variant(Vec3, ATAN2_WGSL[2])
            .wgsl_variant(Vec4, ATAN2_WGSL[3])
            .wgsl_uses(&[ATAN2_HELPER_WGSL])
            .hard_case("origin", &[("y", v(0.0)), ("x", v(0.0))])
            .hard_case("negative axis", &[("y", v(0.0)), ("x", v(-1.0))])
            .hard_case("far apart magnitudes", &[("y", v(1e30)), ("x", v(-1e-30))]),
            atan2
        ),
        all_types!(
            unary(
                "abs",
                "Absolute value |x|, component-wise.",
                "Closed form.",
                (0.0, -10.0, 10.0),
                "|x|.",
                "fn $fn(x: $T) -> $T { return abs(x); }",
            ),
            abs
        ),
        all_types!(
            unary(
                "sign",
                "Sign of x: −1, 0 or 1, component-wise.",
                "Blender's sign: 1 for x > 0, −1 for x < 0, 0 for ±0.",
                (0.0, -10.0, 10.0),
                "−1, 0 or 1.",
                SIGN_WGSL,
            ),
            sign
        ),
        all_types!(
            binary(
                "min",
                "The smaller of a and b, component-wise.",
                "Closed form.",
                (0.0, 1.0),
                "min(a, b).",
                "fn $fn(a: $T, b: $T) -> $T { return min(a, b); }",
            ),
            min
        ),
        all_types!(
            binary(
                "max",
                "The larger of a and b, component-wise.",
                "Closed form.",
                (0.0, 1.0),
                "max(a, b).",
                "fn $fn(a: $T, b: $T) -> $T { return max(a, b); }",
            ),
            max
        ),
        all_types!(
            unary(
                "floor",
                "The largest integer ≤ x, component-wise.",
                "Closed form; exact for every f32 (|x| ≥ 2²³ is already an integer).",
                (0.0, -10.0, 10.0),
                "⌊x⌋.",
                "fn $fn(x: $T) -> $T { return floor(x); }",
            )
            .hard_case("huge value", &[("x", v(-1e30))]),
            floor
        ),
        all_types!(
            unary(
                "ceil",
                "The smallest integer ≥ x, component-wise.",
                "Closed form; exact for every f32 (|x| ≥ 2²³ is already an integer).",
                (0.0, -10.0, 10.0),
                "⌈x⌉.",
                "fn $fn(x: $T) -> $T { return ceil(x); }",
            )
            .hard_case("huge value", &[("x", v(1e30))]),
            ceil
        ),
        all_types!(
            unary(
                "fract",
                "The fractional part x − ⌊x⌋, in [0, 1), component-wise.",
                "Blender's Fraction, x − ⌊x⌋ (the subtraction is exact for |x| ≥ 1). Where it \
                 rounds to 1 (x negative within 2⁻²⁵ of an integer, e.g. −1e-10) the node \
                 returns 0, the same point of the cycle, so the result stays in [0, 1); the \
                 cost is a jump of 1 − 6e-8 there. |x| ≥ 2²³ gives 0.",
                (0.0, -10.0, 10.0),
                "x − ⌊x⌋, in [0, 1).",
                FRACT_WGSL,
            )
            .hard_case("huge value", &[("x", v(1e30))])
            .hard_case("tiny negative", &[("x", v(-1e-10))]),
            fract_t
        ),
        all_types!(
            binary(
                "floored_modulo",
                "a modulo b with the sign of b (floored), component-wise; 0 where b is 0.",
                "Blender's Floored Modulo, a − b·⌊a/b⌋, made total: 0 for b = 0 (Blender's safe \
                 rule); the result lies in [0, b) for b > 0 and in (b, 0] for b < 0 — one \
                 correction step where a/b rounds across an integer, and a result that rounds to \
                 b itself is returned as 0, the same point of the cycle. Error about 1 ulp of a. \
                 Where |a/b| ≥ 2²⁴ adjacent f32 values of a are more than |b| apart, so no f32 a \
                 carries a remainder: the node returns 0 there (the cost: the exact remainder of \
                 that float is not formed).",
                (0.0, 1.0),
                "a − b·⌊a/b⌋, in [0, b) or (b, 0].",
                MODULO_WGSL,
            )
            .hard_case("modulo by zero", &[("a", v(3.0)), ("b", v(0.0))])
            .hard_case("tiny negative", &[("a", v(-1e-10)), ("b", v(1.0))])
            .hard_case("negative divisor", &[("a", v(7.5)), ("b", v(-2.0))])
            .hard_case("exact multiple", &[("a", v(-6.0)), ("b", v(3.0))])
            .hard_case("huge quotient", &[("a", v(1e30)), ("b", v(3.0))]),
            modulo
        ),
        all_types!(
            unary(
                "sqrt",
                "Square root of x, 0 for negative x, component-wise.",
                "Blender's safe sqrt: √max(x, 0), so a negative x gives 0 (the cost: no error is \
                 reported for it).",
                (1.0, 0.0, 10.0),
                "√x.",
                "fn $fn(x: $T) -> $T { return sqrt(max(x, $T(0.0))); }",
            )
            .hard_case("negative", &[("x", v(-4.0))])
            .hard_case("tiny", &[("x", v(1e-30))]),
            sqrt
        ),
        all_types!(
            unary(
                "inverse_sqrt",
                "1/√x, 0 for x ≤ 0, component-wise.",
                "Blender's inversesqrt: 1/√x for x > 0, else 0 (instead of +inf at 0 and NaN \
                 below; the cost: a jump from large values to 0 at x = 0). Finite for every \
                 positive normal f32 (at most 9.2e18).",
                (1.0, 0.0, 10.0),
                "1/√x.",
                INVERSE_SQRT_WGSL,
            )
            .hard_case("zero", &[("x", v(0.0))])
            .hard_case("negative", &[("x", v(-1.0))])
            .hard_case("tiny", &[("x", v(1e-30))]),
            inverse_sqrt
        ),
        all_types!(
            unary(
                "log",
                "Natural logarithm of x, 0 for x ≤ 0, component-wise.",
                "ln x, with Blender's safe rule: 0 for x ≤ 0 (instead of −inf at 0 and NaN below; \
                 the cost: a jump from −87 at the smallest normal f32 to 0 at x = 0). GPUs may \
                 flush subnormal x (< 1.2e-38) to 0, giving 0 where the CPU gives ln x.",
                (1.0, 0.0, 10.0),
                "ln x.",
                LOG_WGSL,
            )
            .hard_case("zero", &[("x", v(0.0))])
            .hard_case("negative", &[("x", v(-1.0))])
            .hard_case("tiny", &[("x", v(1e-30))])
            .hard_case("huge", &[("x", v(3e38))]),
            log
        ),
        all_types!(
            NodeType::new(
                "log_base",
                Category::Math,
                "Logarithm of x to a base, component-wise (Blender's Logarithm)."
            )
            .source(
                "Blender's safe log: ln x / ln base, 0 unless x > 0 and base > 0, and 0 for base \
                 1 (the safe divide). Near base 1 the quotient is ill-conditioned (ln base → 0), \
                 so the soft range of base starts at 1.5; base < 1 is valid and gives the \
                 negated log to 1/base. Computed as log2 x / log2 base with the node's own log2 \
                 (nodes/precise.rs log2_exact, 8 ULP relative), not WGSL's log, which may be 2⁻²¹ \
                 off near 1: log(1) need not be 0 on a GPU, and base 1 would give 1, not 0.",
            )
            .input(In::generic("x", 1.0).range(0.0, 10.0).doc("Value."))
            .input(In::generic("base", 10.0).range(1.5, 16.0).doc("Base."))
            .output(Out::generic("result").doc("log_base x."))
            .wgsl(LOG_BASE_WGSL[0])
            .wgsl_variant(Vec2, LOG_BASE_WGSL[1])
            .wgsl_variant(Vec3, LOG_BASE_WGSL[2])
            .wgsl_variant(Vec4, LOG_BASE_WGSL[3])
            .wgsl_uses(&[precise::LOG2_EXACT_WGSL, LOG_BASE_HELPER_WGSL])
            .hard_case("base one", &[("base", v(1.0))])
            .hard_case("base below one", &[("x", v(8.0)), ("base", v(0.5))])
            .hard_case("zero", &[("x", v(0.0))])
            .hard_case("negative base", &[("x", v(2.0)), ("base", v(-2.0))]),
            log_base
        ),
        all_types!(
            unary(
                "negate",
                "−x, component-wise.",
                "Closed form.",
                (0.0, -10.0, 10.0),
                "−x.",
                "fn $fn(x: $T) -> $T { return -x; }",
            ),
            negate
        ),
        all_types!(
            unary(
                "one_minus",
                "1 − x, component-wise (Blender's Invert at factor 1).",
                "Closed form.",
                (0.0, -10.0, 10.0),
                "1 − x.",
                "fn $fn(x: $T) -> $T { return 1.0 - x; }",
            ),
            one_minus
        ),
        all_types!(
            NodeType::new(
                "compare",
                Category::Math,
                "1 where a and b are equal within epsilon, else 0, component-wise."
            )
            .source(
                "Blender's Compare: a = b or |a − b| ≤ max(epsilon, 1.19e-7) (f32's machine \
                 epsilon is the smallest epsilon used). `equal` is true where every component \
                 compares equal; link it to select's condition.",
            )
            .input(In::generic("a", 0.0).range(-10.0, 10.0).doc("First value."))
            .input(In::generic("b", 0.0).range(-10.0, 10.0).doc("Second value."))
            .input(
                In::float("epsilon", 0.5)
                    .range(0.0, 1.0)
                    .doc("Largest difference that compares equal (Blender's default 0.5)."),
            )
            .output(Out::generic("result").doc("1 or 0 per component."))
            .output(Out::boolean("equal").doc("Whether every component compares equal."))
            .wgsl(COMPARE_WGSL)
            .hard_case(
                "opposite signs near the limit",
                &[("a", v(3e38)), ("b", v(-3e38)), ("epsilon", v(1.0))],
            )
            .hard_case("negative epsilon", &[("a", v(1.0)), ("b", v(1.0)), ("epsilon", v(-1.0))]),
            compare
        ),
        all_types!(
            NodeType::new(
                "select",
                Category::Math,
                "if_true where condition holds, else if_false (Blender's Switch)."
            )
            .source("WGSL select(if_false, if_true, condition); a mix by a bool.")
            .input(In::boolean("condition", false).doc("Which input to pass on."))
            .input(
                In::generic("if_false", 0.0)
                    .range(-10.0, 10.0)
                    .doc("Passed on when condition is false."),
            )
            .input(
                In::generic("if_true", 1.0)
                    .range(-10.0, 10.0)
                    .doc("Passed on when condition is true."),
            )
            .output(Out::generic("result").doc("The chosen input."))
            .wgsl(
                "fn $fn(condition: bool, if_false: $T, if_true: $T) -> $T { return select(if_false, if_true, condition); }",
            ),
            select
        ),
    ]
}
