//! Scalar, vector and colour math. Generic nodes work on float, vec2, vec3, vec4 and
//! colour (`T`); a float input linked to a vector port is broadcast.
//!
//! Division, powers, normalisation and the edges of smoothstep and remap are made safe the
//! way Blender's math nodes are: `x / 0 = 0`, `pow(negative, non-integer) = 0`,
//! `normalize(0) = 0`, and a zero-width smoothstep or remap is a step.
//!
//! Finiteness: for finite inputs every node gives a finite output wherever the exact result
//! is within f32's range (|x| ≤ 3.4·10³⁸). A result beyond it (`div 10 / 2e-38`,
//! `pow 1e-20^-2`, a remap through a 1e-40 wide range) overflows to ±inf, as IEEE arithmetic
//! does: the nodes do not clamp. Where only an intermediate would overflow or underflow —
//! `cross`, `length` and `normalize` of vectors with components beyond 10¹⁸ or below 10⁻¹⁸,
//! `mix` of values of opposite sign near the limit — the node rescales first, so the
//! representable result comes out. The exception is `dot`, kept bare for speed: a product
//! aᵢbᵢ beyond f32's range overflows, so the sum can be ±inf, or NaN where such products of
//! opposite signs meet.

use crate::node::{Category, In, NodeType, Out};
use crate::precision::{self, sqrt};
use crate::types::SocketType::{self, *};
use crate::value::Value;
use glam::{Vec2, Vec3, Vec4};
use std::ops::{Add, Div, Mul, Sub};

/// Component-wise access shared by f32 and glam's vectors.
pub trait Components:
    crate::kernel::Lane
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
{
    /// The resolved generic type this implements.
    const TYPE: SocketType;
    /// Every component set to `x`.
    fn splat(x: f32) -> Self;
    /// Applies `f` to each component.
    fn map(self, f: impl Fn(f32) -> f32) -> Self;
    /// Applies `f` to each pair of components.
    fn zip(self, o: Self, f: impl Fn(f32, f32) -> f32) -> Self;
    /// Applies `f` to each triple of components.
    fn zip3(self, b: Self, c: Self, f: impl Fn(f32, f32, f32) -> f32) -> Self;
}

impl Components for f32 {
    const TYPE: SocketType = Float;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        x
    }
    #[inline(always)]
    fn map(self, f: impl Fn(f32) -> f32) -> Self {
        f(self)
    }
    #[inline(always)]
    fn zip(self, o: Self, f: impl Fn(f32, f32) -> f32) -> Self {
        f(self, o)
    }
    #[inline(always)]
    fn zip3(self, b: Self, c: Self, f: impl Fn(f32, f32, f32) -> f32) -> Self {
        f(self, b, c)
    }
}

macro_rules! impl_components {
    ($t:ty, $ty:expr, $($c:ident),+) => {
        impl Components for $t {
            const TYPE: SocketType = $ty;
            #[inline(always)]
            fn splat(x: f32) -> Self {
                <$t>::splat(x)
            }
            #[inline(always)]
            fn map(self, f: impl Fn(f32) -> f32) -> Self {
                <$t>::new($(f(self.$c)),+)
            }
            #[inline(always)]
            fn zip(self, o: Self, f: impl Fn(f32, f32) -> f32) -> Self {
                <$t>::new($(f(self.$c, o.$c)),+)
            }
            #[inline(always)]
            fn zip3(self, b: Self, c: Self, f: impl Fn(f32, f32, f32) -> f32) -> Self {
                <$t>::new($(f(self.$c, b.$c, c.$c)),+)
            }
        }
    };
}
impl_components!(Vec2, Vec2, x, y);
impl_components!(Vec3, Vec3, x, y, z);
impl_components!(Vec4, Vec4, x, y, z, w);

/// Vectors: the generic types with a length.
pub trait Vector: Components {
    /// Dot product.
    fn dot_(self, o: Self) -> f32;
    /// Components padded to four with zeros.
    fn xyzw(self) -> [f32; 4];
}
impl Vector for Vec2 {
    fn dot_(self, o: Self) -> f32 {
        self.dot(o)
    }
    fn xyzw(self) -> [f32; 4] {
        [self.x, self.y, 0.0, 0.0]
    }
}
impl Vector for Vec3 {
    fn dot_(self, o: Self) -> f32 {
        self.dot(o)
    }
    fn xyzw(self) -> [f32; 4] {
        [self.x, self.y, self.z, 0.0]
    }
}
impl Vector for Vec4 {
    fn dot_(self, o: Self) -> f32 {
        self.dot(o)
    }
    fn xyzw(self) -> [f32; 4] {
        self.to_array()
    }
}

/// `a / b`, 0 where `b` is 0 (Blender's safe divide).
#[inline(always)]
pub fn safe_div(a: f32, b: f32) -> f32 {
    if b == 0.0 { 0.0 } else { a / b }
}

/// `a^b` made total, so the CPU and GPU agree where IEEE `pow` and WGSL `pow` differ:
/// a negative base with an integer exponent keeps its sign (`(-2)^3 = -8`), with a
/// fractional exponent gives 0 (Blender's safe power); `0^0 = 1`; and `0^b = 0` for `b < 0`
/// (`1 / 0^|b|` through the safe divide).
#[inline(always)]
pub fn safe_pow(a: f32, b: f32) -> f32 {
    if a > 0.0 {
        precision::pow(a, b)
    } else if a == 0.0 {
        if b == 0.0 { 1.0 } else { 0.0 }
    } else if b.fract() != 0.0 || !b.is_finite() {
        0.0
    } else {
        let m = precision::pow(-a, b);
        if (b * 0.5).fract() != 0.0 { -m } else { m }
    }
}

/// Hermite smoothstep, a step at `e0` when the edges coincide.
#[inline(always)]
pub fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    if e0 == e1 {
        return if x < e0 { 0.0 } else { 1.0 };
    }
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

fn add<T: Components>(a: T, b: T) -> T {
    a + b
}
fn sub<T: Components>(a: T, b: T) -> T {
    a - b
}
fn mul<T: Components>(a: T, b: T) -> T {
    a * b
}
fn div<T: Components>(a: T, b: T) -> T {
    a.zip(b, safe_div)
}
fn pow<T: Components>(a: T, b: T) -> T {
    a.zip(b, safe_pow)
}
fn exp<T: Components>(x: T) -> T {
    x.map(precision::exp)
}
fn mix<T: Components>(a: T, b: T, t: f32) -> T {
    a.zip(b, |a, b| {
        let d = b - a;
        if d.abs() <= f32::MAX {
            a + d * t
        } else {
            // b − a overflows (opposite signs near the limit): the two-product form.
            a * (1.0 - t) + b * t
        }
    })
}
fn clamp<T: Components>(x: T, lo: T, hi: T) -> T {
    x.zip(lo, f32::max).zip(hi, f32::min)
}
fn saturate<T: Components>(x: T) -> T {
    x.map(|c| c.clamp(0.0, 1.0))
}
fn smoothstep_t<T: Components>(e0: T, e1: T, x: T) -> T {
    e0.zip3(e1, x, smoothstep)
}
fn step<T: Components>(edge: T, x: T) -> T {
    edge.zip(x, |e, x| if x < e { 0.0 } else { 1.0 })
}
fn remap<T: Components>(x: T, from_min: T, from_max: T, to_min: T, to_max: T, clamp: bool) -> T {
    let t = x.zip3(from_min, from_max, |x, a, b| {
        if a == b {
            if x < a { 0.0 } else { 1.0 }
        } else {
            (x - a) / (b - a)
        }
    });
    let t = if clamp { saturate(t) } else { t };
    to_min + (to_max - to_min) * t
}
/// Components beyond this (or below [`SCALE_BELOW`]) are rescaled before squaring.
const SCALE_ABOVE: f32 = 1e18;
/// See [`SCALE_ABOVE`].
const SCALE_BELOW: f32 = 1e-18;

/// A scale of `v`: a quarter of the sum of its components' magnitudes, between
/// max|vᵢ|/4 and max|vᵢ| (no overflow); the same formula as the WGSL.
#[inline(always)]
fn magnitude<T: Vector>(v: T) -> f32 {
    v.map(f32::abs).dot_(T::splat(0.25))
}

/// Whether a vector of magnitude `s` must be rescaled before its squares are taken.
#[inline(always)]
fn needs_rescale(s: f32) -> bool {
    s > SCALE_ABOVE || (s < SCALE_BELOW && s > 0.0)
}

// The CPU takes the plain formula and rescales only when its result shows an overflow or an
// underflow (one comparison on the common path, the slow path out of line); the GPU, where
// WGSL does not promise infinities, decides from the inputs' magnitudes first. Both give the
// representable result. `dot` stays bare: it is the most used node, and a check costs the
// skin benchmark ~20% (docs/benchmarks.md).

fn dot<T: Vector>(a: T, b: T) -> f32 {
    a.dot_(b)
}
fn length<T: Vector>(v: T) -> f32 {
    let l = sqrt(v.dot_(v));
    if l.is_finite() && l >= SCALE_BELOW {
        l
    } else {
        length_rescaled(v, l)
    }
}
/// [`length`] where the squares overflow or underflow; `l` is the plain result.
#[cold]
#[inline(never)]
fn length_rescaled<T: Vector>(v: T, l: f32) -> f32 {
    let s = magnitude(v);
    if needs_rescale(s) {
        let u = v.map(|x| x / s);
        sqrt(u.dot_(u)) * s
    } else {
        l
    }
}
/// `v / |v|`, rescaled where the squares overflow or underflow; 0 for a zero vector.
pub fn normalize<T: Vector>(v: T) -> T {
    let l = sqrt(v.dot_(v));
    if l.is_finite() && l >= SCALE_BELOW {
        v * T::splat(1.0 / l)
    } else {
        normalize_rescaled(v)
    }
}
/// [`normalize`] where the squares overflow or underflow, or of a zero vector.
#[cold]
#[inline(never)]
fn normalize_rescaled<T: Vector>(v: T) -> T {
    let s = magnitude(v);
    let v = if needs_rescale(s) {
        v.map(|x| x / s)
    } else {
        v
    };
    let l = sqrt(v.dot_(v));
    if l > 0.0 && l <= f32::MAX {
        v * T::splat(1.0 / l)
    } else {
        T::splat(0.0)
    }
}

/// `a × b`, rescaled when the products overflow, so that a representable result comes out
/// (parallel vectors give 0).
fn cross(a: Vec3, b: Vec3) -> Vec3 {
    let c = precision::cross(a, b);
    if c.is_finite() {
        c
    } else {
        cross_rescaled(a, b)
    }
}
/// [`cross`] of vectors whose products overflow: the cross product of the rescaled vectors
/// `u`, `v` (components at most 4), with each component whose magnitude is within the
/// rounding of its two products (2⁻²¹ · max|uᵢ| · max|vᵢ|) set to 0 before scaling back.
/// A GPU may fuse one product into the subtraction (WGSL §15.7.5), which turns the 0 of
/// parallel vectors into that rounding error, and scaling it back by |a||b| ≥ 10¹⁸ gives ±∞
/// (found on an NVIDIA H200: `cross([1e30]³, [1e30]³)` was ∞). The cost: a component below
/// 2⁻²¹ of |a||b| is returned as 0, in this path only (vectors beyond 10¹⁸).
#[cold]
#[inline(never)]
fn cross_rescaled(a: Vec3, b: Vec3) -> Vec3 {
    let (sa, sb) = (magnitude(a), magnitude(b));
    let (u, v) = (a / sa, b / sb);
    let c = precision::cross(u, v);
    let noise = CROSS_NOISE * u.abs().max_element() * v.abs().max_element();
    let c = Vec3::select(c.abs().cmple(Vec3::splat(noise)), Vec3::ZERO, c);
    (c * sa) * sb
}

/// 2⁻²¹: the relative rounding [`cross_rescaled`] treats as zero (a product's rounding is at
/// most 2⁻²⁴ of it; two products and the subtraction, with room).
const CROSS_NOISE: f32 = 1.0 / 2_097_152.0;
fn split<T: Vector>(v: T) -> (f32, f32, f32, f32) {
    let [x, y, z, w] = v.xyzw();
    (x, y, z, w)
}

/// WGSL of [`div`]: the safe divide.
const DIV_WGSL: &str =
    "fn $fn(a: $T, b: $T) -> $T { return select(a / b, $T(0.0), b == $T(0.0)); }";

/// WGSL of [`safe_pow`], component-wise with selects.
const POW_WGSL: &str = r#"
fn $fn(a: $T, b: $T) -> $T {
    let zero = $T(0.0);
    let one = $T(1.0);
    // pow(|a|, b) with the zero base replaced, so the builtin never sees 0.
    let mag = pow(select(abs(a), one, a == zero), b);
    let is_int = fract(b) == zero;
    let odd = fract(b * 0.5) != zero;
    let negative_base = select(zero, select(mag, -mag, odd), is_int);
    var r = select(mag, negative_base, a < zero);
    r = select(r, select(zero, one, b == zero), a == zero);
    return r;
}
"#;

/// WGSL of [`smoothstep`] (explicit, since WGSL's builtin is undefined for equal edges).
const SMOOTHSTEP_WGSL: &str = r#"
fn $fn(edge0: $T, edge1: $T, x: $T) -> $T {
    let same = edge0 == edge1;
    let t = min(max((x - edge0) / select(edge1 - edge0, $T(1.0), same), $T(0.0)), $T(1.0));
    let s = t * t * (3.0 - 2.0 * t);
    return select(s, select($T(1.0), $T(0.0), x < edge0), same);
}
"#;

/// WGSL of [`remap`].
const REMAP_WGSL: &str = r#"
fn $fn(x: $T, from_min: $T, from_max: $T, to_min: $T, to_max: $T, clamp_t: bool) -> $T {
    let same = from_min == from_max;
    let linear = (x - from_min) / select(from_max - from_min, $T(1.0), same);
    var t = select(linear, select($T(1.0), $T(0.0), x < from_min), same);
    if (clamp_t) {
        t = min(max(t, $T(0.0)), $T(1.0));
    }
    return to_min + (to_max - to_min) * t;
}
"#;

/// WGSL of [`normalize`]: rescaled like the Rust; zero for a zero or non-finite length. The
/// largest f32 is written in hex: the decimal 3.4028235e38 exceeds it as an abstract float.
const NORMALIZE_WGSL: &str = r#"
fn $fn(v0: $T) -> $T {
    let s = dot(abs(v0), $T(0.25));
    var v = v0;
    if (s > 1e18 || (s < 1e-18 && s > 0.0)) {
        v = v0 / s;
    }
    let l = sqrt(dot(v, v));
    if (l > 0.0 && l <= 0x1.fffffep+127f) {
        return v * (1.0 / l);
    }
    return $T(0.0);
}
"#;

/// [`normalize`] of a vec3 as a WGSL helper, `mg_normalize3`, for nodes that normalise inside
/// their own function (the same rescaling and zero rule as the `normalize` node).
pub const NORMALIZE3_WGSL: &str = r#"
fn mg_normalize3(v0: vec3<f32>) -> vec3<f32> {
    let s = dot(abs(v0), vec3<f32>(0.25));
    var v = v0;
    if (s > 1e18 || (s < 1e-18 && s > 0.0)) {
        v = v0 / s;
    }
    let l = sqrt(dot(v, v));
    if (l > 0.0 && l <= 0x1.fffffep+127f) {
        return v * (1.0 / l);
    }
    return vec3<f32>(0.0);
}
"#;

/// WGSL of [`length`], rescaled like the Rust.
const LENGTH_WGSL: &str = r#"
fn $fn(v: $T) -> f32 {
    let s = dot(abs(v), $T(0.25));
    if (s > 1e18 || (s < 1e-18 && s > 0.0)) {
        let u = v / s;
        return sqrt(dot(u, u)) * s;
    }
    return sqrt(dot(v, v));
}
"#;

/// WGSL of [`cross`], rescaled like the Rust.
const CROSS_WGSL: &str = r#"
fn $fn(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    let sa = dot(abs(a), vec3<f32>(0.25));
    let sb = dot(abs(b), vec3<f32>(0.25));
    if (sa > 1e18 || sb > 1e18) {
        let u = a / sa;
        let v = b / sb;
        let c = cross(u, v);
        let noise = 0x1p-21f * max(max(abs(u.x), abs(u.y)), abs(u.z)) * max(max(abs(v.x), abs(v.y)), abs(v.z));
        return (select(c, vec3<f32>(0.0), abs(c) <= vec3<f32>(noise)) * sa) * sb;
    }
    return cross(a, b);
}
"#;

/// WGSL of [`mix`], component-wise: the two-product form where `b − a` overflows.
const MIX_WGSL: &str = r#"
fn $fn(a: $T, b: $T, t: f32) -> $T {
    let d = b - a;
    return select(a + d * t, a * (1.0 - t) + b * t, abs(d) > $T(0x1.fffffep+127f));
}
"#;

/// WGSL of the `combine` node.
const COMBINE_WGSL: &str = r#"
fn $fn(x: f32, y: f32, z: f32, w: f32) -> $out {
    return $out(vec2<f32>(x, y), vec3<f32>(x, y, z), vec4<f32>(x, y, z, w), vec3<f32>(x, y, z));
}
"#;

/// Registers `f::<T>` for float, vec2, vec3 and vec4 (colour uses the vec3 variant).
macro_rules! all_types {
    ($t:expr, $f:ident) => {
        $t.variant(Float, $f::<f32>)
            .variant(Vec2, $f::<Vec2>)
            .variant(Vec3, $f::<Vec3>)
            .variant(Vec4, $f::<Vec4>)
    };
}

/// Registers `f::<T>` for vec2, vec3 and vec4 (colour uses the vec3 variant).
macro_rules! vector_types {
    ($t:expr, $f:ident) => {
        $t.variant(Vec3, $f::<Vec3>)
            .variant(Vec2, $f::<Vec2>)
            .variant(Vec4, $f::<Vec4>)
    };
}

const CLOSED_FORM: &str = "Closed form, component-wise.";

fn binary(
    name: &'static str,
    summary: &'static str,
    a: f32,
    b: f32,
    wgsl: &'static str,
) -> NodeType {
    NodeType::new(name, Category::Math, summary)
        .input(In::generic("a", a).range(-10.0, 10.0).doc("First operand."))
        .input(
            In::generic("b", b)
                .range(-10.0, 10.0)
                .doc("Second operand."),
        )
        .output(Out::generic("result").doc("The result, component-wise."))
        .wgsl(wgsl)
}

/// The math-family node types.
pub fn all() -> Vec<NodeType> {
    let v = |x: f32| Value::float(x);
    vec![
        all_types!(binary("add", "a + b.", 0.0, 0.0, "fn $fn(a: $T, b: $T) -> $T { return a + b; }").source(CLOSED_FORM), add),
        all_types!(binary("sub", "a − b.", 0.0, 0.0, "fn $fn(a: $T, b: $T) -> $T { return a - b; }").source(CLOSED_FORM), sub),
        all_types!(binary("mul", "a · b, component-wise.", 1.0, 1.0, "fn $fn(a: $T, b: $T) -> $T { return a * b; }").source(CLOSED_FORM), mul),
        all_types!(
            binary("div", "a / b, component-wise; 0 where b is 0.", 1.0, 1.0, DIV_WGSL)
                .source(
                    "Closed form with Blender's safe divide: x / 0 = 0. A quotient beyond f32's range \
                     (|x| > 3.4e38) overflows to ±inf, as in IEEE arithmetic.",
                )
                .hard_case("divide by zero", &[("a", v(1.0)), ("b", v(0.0))])
                .hard_case("tiny divisor", &[("a", v(1.0)), ("b", v(1e-30))]),
            div
        ),
        all_types!(
            NodeType::new("pow", Category::Math, "a raised to b, component-wise.")
                .source(
                    "Total power: a^b for a > 0; a negative base with an integer exponent keeps its \
                     sign, with a fractional one gives 0 (Blender's safe power); 0^0 = 1 and \
                     0^b = 0 for b < 0 (1/0 through the safe divide). A power beyond f32's range \
                     overflows to ±inf.",
                )
                .input(In::generic("a", 1.0).range(-4.0, 4.0).doc("Base."))
                .input(In::generic("b", 1.0).range(-4.0, 8.0).doc("Exponent."))
                .output(Out::generic("result").doc("a^b."))
                .wgsl(POW_WGSL)
                .hard_case("negative base, fractional exponent", &[("a", v(-2.0)), ("b", v(0.5))])
                .hard_case("zero to the zero", &[("a", v(0.0)), ("b", v(0.0))])
                .hard_case("zero to a negative power", &[("a", v(0.0)), ("b", v(-4.0))])
                .hard_case("negative base, odd exponent", &[("a", v(-2.0)), ("b", v(3.0))]),
            pow
        ),
        all_types!(
            NodeType::new("exp", Category::Math, "e raised to x, component-wise.")
                .source(CLOSED_FORM)
                .input(In::generic("x", 0.0).range(-20.0, 20.0).doc("Exponent."))
                .output(Out::generic("result").doc("e^x."))
                .wgsl("fn $fn(x: $T) -> $T { return exp(x); }")
                .hard_case("underflow", &[("x", v(-80.0))]),
            exp
        ),
        all_types!(
            NodeType::new("mix", Category::Math, "Linear interpolation a + (b − a)·t.")
                .source("GLSL/WGSL mix, a + (b − a)·t; t is not clamped. Where b − a overflows, a(1 − t) + b·t.")
                .input(In::generic("a", 0.0).range(-10.0, 10.0).doc("Value at t = 0."))
                .input(In::generic("b", 1.0).range(-10.0, 10.0).doc("Value at t = 1."))
                .input(In::float("t", 0.5).range(0.0, 1.0).doc("Blend factor."))
                .output(Out::generic("result").doc("The blend."))
                .wgsl(MIX_WGSL)
                .hard_case("opposite signs near the limit", &[("a", v(-3e38)), ("b", v(3e38))]),
            mix
        ),
        all_types!(
            NodeType::new("clamp", Category::Math, "x limited to [min, max], component-wise.")
                .source("min(max(x, lo), hi), as WGSL clamp; a NaN x gives lo.")
                .input(In::generic("x", 0.0).range(-10.0, 10.0).doc("Value."))
                .input(In::generic("min", 0.0).range(-10.0, 10.0).doc("Lower bound."))
                .input(In::generic("max", 1.0).range(-10.0, 10.0).doc("Upper bound."))
                .output(Out::generic("result").doc("The clamped value."))
                .wgsl("fn $fn(x: $T, lo: $T, hi: $T) -> $T { return min(max(x, lo), hi); }"),
            clamp
        ),
        all_types!(
            NodeType::new("saturate", Category::Math, "x limited to [0, 1], component-wise.")
                .source(CLOSED_FORM)
                .input(In::generic("x", 0.0).range(-10.0, 10.0).doc("Value."))
                .output(Out::generic("result").doc("clamp(x, 0, 1)."))
                .wgsl("fn $fn(x: $T) -> $T { return min(max(x, $T(0.0)), $T(1.0)); }"),
            saturate
        ),
        all_types!(
            NodeType::new("smoothstep", Category::Math, "Hermite step from edge0 to edge1.")
                .source("t = clamp((x − e0)/(e1 − e0), 0, 1), t²(3 − 2t); a step at e0 when e0 = e1.")
                .input(In::generic("edge0", 0.0).range(-2.0, 2.0).doc("Where the result starts to rise."))
                .input(In::generic("edge1", 1.0).range(-2.0, 2.0).doc("Where the result reaches 1."))
                .input(In::generic("x", 0.5).range(-2.0, 2.0).doc("Value."))
                .output(Out::generic("result").doc("Smooth 0 → 1 transition."))
                .wgsl(SMOOTHSTEP_WGSL)
                .hard_case("coincident edges", &[("edge0", v(0.5)), ("edge1", v(0.5)), ("x", v(0.5))]),
            smoothstep_t
        ),
        all_types!(
            NodeType::new("step", Category::Math, "0 where x < edge, else 1.")
                .source("GLSL/WGSL step(edge, x).")
                .input(In::generic("edge", 0.5).range(-2.0, 2.0).doc("Threshold."))
                .input(In::generic("x", 0.0).range(-2.0, 2.0).doc("Value."))
                .output(Out::generic("result").doc("0 or 1."))
                .wgsl("fn $fn(edge: $T, x: $T) -> $T { return select($T(1.0), $T(0.0), x < edge); }"),
            step
        ),
        all_types!(
            NodeType::new("remap", Category::Math, "Maps x from [from_min, from_max] to [to_min, to_max].")
                .source(
                    "Blender's Map Range (linear): t = (x − a)/(b − a), to_min + (to_max − to_min)·t; a \
                     step when a = b. A result beyond f32's range (a tiny source range) overflows to ±inf.",
                )
                .input(In::generic("x", 0.5).range(-2.0, 2.0).doc("Value."))
                .input(In::generic("from_min", 0.0).range(-2.0, 2.0).doc("Start of the source range."))
                .input(In::generic("from_max", 1.0).range(-2.0, 2.0).doc("End of the source range."))
                .input(In::generic("to_min", 0.0).range(-2.0, 2.0).doc("Start of the target range."))
                .input(In::generic("to_max", 1.0).range(-2.0, 2.0).doc("End of the target range."))
                .input(In::boolean("clamp", false).doc("Clamp t to [0, 1]."))
                .output(Out::generic("result").doc("The remapped value."))
                .wgsl(REMAP_WGSL)
                .hard_case("empty source range", &[("from_min", v(0.3)), ("from_max", v(0.3))]),
            remap
        ),
        vector_types!(
            NodeType::new("dot", Category::Vector, "Dot product a · b.")
                .source(
                    "Closed form. Kept bare for speed: a product beyond f32's range (|aᵢbᵢ| > \
                     3.4e38) overflows, so the sum can be ±inf, or NaN where such products of \
                     opposite signs meet.",
                )
                .input(In::generic("a", 0.0).range(-2.0, 2.0).doc("First vector."))
                .input(In::generic("b", 0.0).range(-2.0, 2.0).doc("Second vector."))
                .output(Out::float("result").doc("Σ aᵢbᵢ."))
                .wgsl("fn $fn(a: $T, b: $T) -> f32 { return dot(a, b); }"),
            dot
        ),
        NodeType::new("cross", Category::Vector, "Cross product a × b.")
            .source(CLOSED_FORM)
            .input(In::vec3("a", [1.0, 0.0, 0.0]).range(-2.0, 2.0).doc("First vector."))
            .input(In::vec3("b", [0.0, 1.0, 0.0]).range(-2.0, 2.0).doc("Second vector."))
            .output(Out::vec3("result").doc("a × b."))
            .wgsl(CROSS_WGSL)
            .hard_case("huge parallel vectors", &[("a", Value::vec3([1e30, 1e30, 1e30])), ("b", Value::vec3([1e30, 1e30, 1e30]))])
            .compute(cross),
        vector_types!(
            NodeType::new("normalize", Category::Vector, "v scaled to unit length; 0 for a zero vector.")
                .source("v / |v|, with normalize(0) = 0 instead of NaN; vectors beyond 1e18 or below 1e-18 are rescaled first.")
                .input(In::generic("v", 1.0).range(-2.0, 2.0).doc("Vector."))
                .output(Out::generic("result").doc("Unit vector along v."))
                .wgsl(NORMALIZE_WGSL)
                .hard_case("zero vector", &[("v", v(0.0))])
                .hard_case("tiny vector", &[("v", v(1e-30))])
                .hard_case("huge vector", &[("v", v(1e30))]),
            normalize
        ),
        vector_types!(
            NodeType::new("length", Category::Vector, "Euclidean length |v|.")
                .source(CLOSED_FORM)
                .input(In::generic("v", 0.0).range(-2.0, 2.0).doc("Vector."))
                .output(Out::float("result").doc("|v|."))
                .wgsl(LENGTH_WGSL)
                .hard_case("huge vector", &[("v", v(1e30))])
                .hard_case("tiny vector", &[("v", v(1e-30))]),
            length
        ),
        vector_types!(
            NodeType::new("split", Category::Vector, "The components of a vector or colour.")
                .source("Components past the input's width are 0.")
                .input(In::generic("v", 0.0).range(-2.0, 2.0).doc("Vector or colour."))
                .output(Out::float("x").doc("First component (red)."))
                .output(Out::float("y").doc("Second component (green)."))
                .output(Out::float("z").doc("Third component (blue); 0 for a vec2."))
                .output(Out::float("w").doc("Fourth component; 0 below vec4."))
                .wgsl_variant(Vec2, "fn $fn(v: vec2<f32>) -> $out { return $out(v.x, v.y, 0.0, 0.0); }")
                .wgsl_variant(Vec3, "fn $fn(v: vec3<f32>) -> $out { return $out(v.x, v.y, v.z, 0.0); }")
                .wgsl_variant(Vec4, "fn $fn(v: vec4<f32>) -> $out { return $out(v.x, v.y, v.z, v.w); }"),
            split
        ),
        NodeType::new("combine", Category::Vector, "Builds vectors and a colour from components.")
            .source("vec2 (x, y), vec3 (x, y, z), vec4 (x, y, z, w), color (x, y, z).")
            .input(In::float("x", 0.0).range(-2.0, 2.0).doc("First component (red)."))
            .input(In::float("y", 0.0).range(-2.0, 2.0).doc("Second component (green)."))
            .input(In::float("z", 0.0).range(-2.0, 2.0).doc("Third component (blue)."))
            .input(In::float("w", 0.0).range(-2.0, 2.0).doc("Fourth component."))
            .output(Out::vec2("vec2").doc("(x, y)."))
            .output(Out::vec3("vec3").doc("(x, y, z)."))
            .output(Out::vec4("vec4").doc("(x, y, z, w)."))
            .output(Out::color("color").doc("(x, y, z) as linear RGB."))
            .wgsl(COMBINE_WGSL)
            .compute(|x: f32, y: f32, z: f32, w: f32| {
                (Vec2::new(x, y), Vec3::new(x, y, z), Vec4::new(x, y, z, w), Vec3::new(x, y, z))
            }),
    ]
}
