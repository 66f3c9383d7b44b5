//! Seed 002 (Super Mario Sunshine's water): the mip level chosen explicitly from the
//! screen-space derivatives of uv, so the custom mip chain's bright band sits at the same
//! place on every path, and the alpha test that breaks the band into highlights.
//!
//! Both nodes run the same f32 operations in the same order on the CPU and in WGSL, with no
//! built-in transcendental: `mip_level` takes its logarithm from the float's exponent bits
//! and a polynomial ([`log2_exact`](super::precise::log2_exact)), so the two paths give the same bits wherever the GPU
//! backend does not contract a multiply and an add into a fused multiply-add (Vulkan on
//! lavapipe does not; llvmpipe's GL may, and then differs by an ulp).

use super::precise::{LOG2_EXACT_WGSL, log2_exact};
use crate::node::{Category, In, NodeType, Out};
use crate::value::Value;
use glam::Vec2;

/// The smallest footprint² [`mip_level`] uses (2⁻¹²⁶, the least normal f32): lod ≥ −63.
const MIN_RHO2: f32 = f32::MIN_POSITIVE;
/// The largest footprint² [`mip_level`] uses (2¹²⁶): lod ≤ 63.
const MAX_RHO2: f32 = 8.507_059e37;

/// The mip level of a footprint: with the derivatives in texels, `a = uv_dx · size`,
/// `b = uv_dy · size`, `ρ² = max(|a|², |b|²)` clamped to [2⁻¹²⁶, 2¹²⁶], and
/// `λ = ½ log2 ρ² + bias` (= log2 ρ + bias).
///
/// Source: OpenGL 4.6 core profile, §8.14.1 "Scale Factor and Level of Detail" (ρ the larger
/// of the lengths of the footprint's two sides in texels, λ = log2 ρ + bias); the Vulkan
/// specification's "Scale Factor Operation, Level-of-Detail Operation and Image Level(s)
/// Selection" (ρ_max = max(ρ_x, ρ_y), λ_base = log2 ρ_max) is the same formula.
#[inline]
pub fn mip_level(uv_dx: Vec2, uv_dy: Vec2, size: Vec2, bias: f32) -> f32 {
    let a = uv_dx * size;
    let b = uv_dy * size;
    let rho2 = (a.x * a.x + a.y * a.y)
        .max(b.x * b.x + b.y * b.y)
        .clamp(MIN_RHO2, MAX_RHO2);
    0.5 * log2_exact(rho2) + bias
}

const MIP_LEVEL_WGSL: &str = r#"
fn $fn(uv_dx: vec2<f32>, uv_dy: vec2<f32>, size: vec2<f32>, bias: f32) -> f32 {
    let a = uv_dx * size;
    let b = uv_dy * size;
    let rho2 = clamp(max(a.x * a.x + a.y * a.y, b.x * b.x + b.y * b.y), 1.1754944e-38, 8.507059e37);
    return 0.5 * mg_log2_exact(rho2) + bias;
}
"#;

fn mip_level_node() -> NodeType {
    NodeType::new(
        "mip_level",
        Category::Texture,
        "The mip level of a texture footprint, from the screen-space derivatives of uv.",
    )
    .source(
        "λ = log2 ρ + bias with ρ = max(|uv_dx · size|, |uv_dy · size|), the footprint's \
         longer side in texels of level 0: the level-of-detail formula of OpenGL 4.6 §8.14.1 \
         and of Vulkan's \"Level-of-Detail Operation\" (isotropic, no anisotropy). Computed \
         as ½·log2 ρ² with log2 taken from the exponent bits and a degree-8 polynomial \
         (error < 1e-7), so the CPU and the GPU pick the same level bit for bit. ρ² is \
         clamped to [2⁻¹²⁶, 2¹²⁶], so λ ∈ [−63, 63] + bias: a zero footprint (no derivatives \
         supplied) reads level 0, which the sampler's clamp to [0, levels − 1] does anyway. \
         Scale the derivatives by the uv's tiling first (the chain rule). Seed 002 uses it to \
         place the custom mip chain's bright band.",
    )
    .input(
        In::vec2("uv_dx", [0.0, 0.0])
            .range(-0.05, 0.05)
            .doc("∂uv/∂x: uv change per pixel to the right (uv_derivatives)."),
    )
    .input(
        In::vec2("uv_dy", [0.0, 0.0])
            .range(-0.05, 0.05)
            .doc("∂uv/∂y: uv change per pixel downwards (uv_derivatives)."),
    )
    .input(
        In::vec2("size", [256.0, 256.0])
            .range(1.0, 4096.0)
            .hard(0.0, 1.0e9)
            .unit("texel")
            .doc("Width and height of the texture's level 0, in texels."),
    )
    .input(
        In::float("bias", 0.0)
            .range(-4.0, 4.0)
            .doc("Added to the level (positive: blurrier)."),
    )
    .output(Out::float("lod").doc("Mip level: 0 is full resolution, each +1 halves it."))
    .hard_case(
        "no footprint: ρ² clamped up to 2⁻¹²⁶",
        &[
            ("uv_dx", Value::vec2([0.0, 0.0])),
            ("uv_dy", Value::vec2([0.0, 0.0])),
        ],
    )
    .hard_case(
        "a footprint of 1e19 texels: ρ² clamped down to 2¹²⁶",
        &[
            ("uv_dx", Value::vec2([2.5e15, 0.0])),
            ("uv_dy", Value::vec2([0.0, 0.0])),
            ("size", Value::vec2([4096.0, 4096.0])),
        ],
    )
    .hard_case(
        "one texel per pixel, exactly λ = 0",
        &[
            ("uv_dx", Value::vec2([0.0078125, 0.0])),
            ("uv_dy", Value::vec2([0.0, 0.0078125])),
            ("size", Value::vec2([128.0, 128.0])),
        ],
    )
    .wgsl(MIP_LEVEL_WGSL)
    .wgsl_uses(&[LOG2_EXACT_WGSL])
    .compute(mip_level)
}

/// The alpha test: 1 (kept) where `value ≤ low` or `value ≥ high`, 0 (discarded) where
/// `low < value < high`. With `low ≥ high` nothing is discarded; a NaN value is discarded.
///
/// Source: seed 002 — "after all the computation, an alpha test skips the points of middle
/// brightness and draws only those in the more extreme ranges".
#[inline]
pub fn alpha_test(value: f32, low: f32, high: f32) -> f32 {
    if value <= low || value >= high {
        1.0
    } else {
        0.0
    }
}

fn alpha_test_node() -> NodeType {
    NodeType::new(
        "alpha_test",
        Category::Color,
        "The alpha test: discards mid values, keeps the extremes.",
    )
    .source(
        "alpha = 1 where value ≤ low or value ≥ high, else 0 (Super Mario Sunshine's water, \
         seed 002: after everything else, texels of middle brightness are not drawn, so the \
         bright band breaks into highlights and the water looks more transparent). Drive the \
         graph's `alpha` output with it: a discarded sample shows what lies behind the \
         surface. With low ≥ high nothing is discarded; a NaN value is discarded.",
    )
    .input(
        In::float("value", 0.0)
            .range(0.0, 2.0)
            .doc("The brightness tested."),
    )
    .input(
        In::float("low", 0.25)
            .range(0.0, 2.0)
            .doc("Values at or below it are kept."),
    )
    .input(
        In::float("high", 1.0)
            .range(0.0, 2.0)
            .doc("Values at or above it are kept."),
    )
    .output(Out::float("alpha").doc("1 kept, 0 discarded."))
    .hard_case(
        "on the thresholds: kept",
        &[
            ("value", Value::float(0.25)),
            ("low", Value::float(0.25)),
            ("high", Value::float(0.25)),
        ],
    )
    .hard_case(
        "empty interval (low > high): kept",
        &[
            ("value", Value::float(0.5)),
            ("low", Value::float(1.0)),
            ("high", Value::float(0.0)),
        ],
    )
    .wgsl(
        "fn $fn(value: f32, low: f32, high: f32) -> f32 { \
         return select(0.0, 1.0, value <= low || value >= high); }",
    )
    .compute(alpha_test)
}

/// The seed 002 node types.
pub fn all() -> Vec<NodeType> {
    vec![mip_level_node(), alpha_test_node()]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A seeded SplitMix64 generator.
    fn splitmix(state: &mut u64) -> u64 {
        *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = *state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    #[test]
    fn mip_level_against_the_closed_form() {
        // 4 texels per pixel along x, 2 along y → ρ = 4, λ = 2.
        let l = mip_level(
            Vec2::new(4.0 / 128.0, 0.0),
            Vec2::new(0.0, -2.0 / 128.0),
            Vec2::splat(128.0),
            0.0,
        );
        assert_eq!(l, 2.0);
        // A diagonal footprint: |(3, 4)| = 5 texels → log2 5.
        let l = mip_level(
            Vec2::new(3.0 / 64.0, 4.0 / 32.0),
            Vec2::new(0.0, 0.0),
            Vec2::new(64.0, 32.0),
            0.5,
        );
        assert!((l as f64 - (5f64.log2() + 0.5)).abs() < 2e-7, "{l}");
        // Random footprints against f64.
        let mut s = 99u64;
        let mut r = |lo: f64, hi: f64| {
            lo + (hi - lo) * (splitmix(&mut s) >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..20_000 {
            let dx = Vec2::new(r(-0.05, 0.05) as f32, r(-0.05, 0.05) as f32);
            let dy = Vec2::new(r(-0.05, 0.05) as f32, r(-0.05, 0.05) as f32);
            let size = Vec2::new(r(1.0, 4096.0).round() as f32, r(1.0, 4096.0).round() as f32);
            let f = |v: Vec2| {
                ((v.x as f64 * size.x as f64).powi(2) + (v.y as f64 * size.y as f64).powi(2)).sqrt()
            };
            let rho = f(dx).max(f(dy));
            if rho == 0.0 {
                continue;
            }
            let want = rho.log2();
            let got = mip_level(dx, dy, size, 0.0) as f64;
            assert!(
                (got - want).abs() < 1e-6 + 1e-6 * want.abs(),
                "{dx} {dy} {size}: {got} vs {want}"
            );
        }
        // Clamps.
        assert_eq!(
            mip_level(Vec2::ZERO, Vec2::ZERO, Vec2::splat(256.0), 0.0),
            -63.0
        );
        assert_eq!(
            mip_level(Vec2::splat(1e30), Vec2::ZERO, Vec2::splat(1e9), 1.0),
            64.0
        );
    }

    #[test]
    fn alpha_test_keeps_the_extremes() {
        assert_eq!(alpha_test(0.1, 0.25, 1.0), 1.0);
        assert_eq!(alpha_test(0.25, 0.25, 1.0), 1.0);
        assert_eq!(alpha_test(0.26, 0.25, 1.0), 0.0);
        assert_eq!(alpha_test(0.99, 0.25, 1.0), 0.0);
        assert_eq!(alpha_test(1.0, 0.25, 1.0), 1.0);
        assert_eq!(alpha_test(1.7, 0.25, 1.0), 1.0);
        assert_eq!(alpha_test(0.5, 1.0, 0.0), 1.0);
        assert_eq!(alpha_test(f32::NAN, 0.25, 1.0), 0.0);
    }
}
