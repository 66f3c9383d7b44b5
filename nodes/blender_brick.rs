//! Blender's Brick Texture node (Blender 4.x), its definition as Blender's sources state it
//! (`intern/cycles/kernel/svm/brick.h`; geometry nodes' `node_shader_tex_brick.cc`), written
//! again here: rows of `row_height`, bricks of `brick_width` (every `squash_frequency`-th row's
//! bricks `squash` times as wide, every `offset_frequency`-th row shifted by `offset` of a
//! brick), each brick's tint from Blender's integer hash of its row and brick numbers, and
//! mortar where the nearest brick edge is closer than `mortar_size`.
//!
//! Row and brick edges are discontinuities: the tint jumps there, and any rounding may put a
//! point on either side. Everything else is integer arithmetic or continuous.

use crate::node::{Category, In, NodeType, Out};
use crate::value::Value;
use glam::Vec3;

/// The bound on |coordinate · scale|, so that infinite coordinates stay finite (row and brick
/// numbers saturate at ±2³¹ long before it).
const COORD_LIMIT: f32 = 1.0e12;

/// Blender's `brick_noise`: an integer hash of `n` in [0, 1).
///
/// Source: Blender's `brick_noise` (brick.h): `n = (n + 1013) & 0x7fffffff;
/// n ^= n >> 13; nn = (n·(n²·60493 + 19990303) + 1376312589) & 0x7fffffff;
/// ½ · nn / 2³⁰`, all in wrapping u32. nn has 31 bits, more than an f32 holds: it is converted
/// as `2¹⁶·hi + lo` (both exact, one correctly rounded sum), which is C's rounding of
/// `(float)nn` and leaves a GPU no choice (WGSL lets `f32(u32)` round either way).
pub fn brick_noise(n: u32) -> f32 {
    let n = n.wrapping_add(1013) & 0x7fff_ffff;
    let n = (n >> 13) ^ n;
    let nn = n
        .wrapping_mul(
            n.wrapping_mul(n)
                .wrapping_mul(60493)
                .wrapping_add(19_990_303),
        )
        .wrapping_add(1_376_312_589)
        & 0x7fff_ffff;
    let f = (nn >> 16) as f32 * 65536.0 + (nn & 0xffff) as f32;
    0.5 * (f * (1.0 / 1_073_741_824.0))
}

/// Blender's `svm_brick`: `(tint, mortar)` at `p` (already scaled).
///
/// Source: Blender 4.x `svm_brick` (brick.h) and geometry nodes' `BrickFunction::brick`.
#[allow(clippy::too_many_arguments)]
fn brick(
    p: Vec3,
    mortar_size: f32,
    mortar_smooth: f32,
    bias: f32,
    mut brick_width: f32,
    row_height: f32,
    offset_amount: f32,
    offset_frequency: i32,
    squash_amount: f32,
    squash_frequency: i32,
) -> (f32, f32) {
    let rownum = (p.y / row_height).floor() as i32;
    // Blender's fields hold both frequencies in [1, 99], so its `if (frequencies)` is true.
    if rownum % squash_frequency == 0 {
        brick_width *= squash_amount;
    }
    let offset = if rownum % offset_frequency == 0 {
        brick_width * offset_amount
    } else {
        0.0
    };
    let bricknum = ((p.x + offset) / brick_width).floor() as i32;
    let x = (p.x + offset) - brick_width * bricknum as f32;
    let y = p.y - row_height * rownum as f32;
    let key = ((rownum as u32) << 16).wrapping_add(bricknum as u32 & 0xffff);
    let tint = (brick_noise(key) + bias).clamp(0.0, 1.0);
    let min_dist = x.min(y).min((brick_width - x).min(row_height - y));
    let mortar = if min_dist >= mortar_size {
        0.0
    } else if mortar_smooth == 0.0 || mortar_size <= 0.0 {
        // mortar_size 0: Blender's 1 − d/0 is +∞ here (d < 0), past the smooth edge.
        1.0
    } else {
        let m = 1.0 - min_dist / mortar_size;
        if m < mortar_smooth {
            let t = m / mortar_smooth;
            let tt = t * t;
            3.0 * tt - 2.0 * tt * t
        } else {
            1.0
        }
    };
    (tint, mortar)
}

/// Blender's Brick Texture: `(color, fac)`, fac the mortar's weight and color the brick's
/// tint of color1 → color2 under the mortar.
///
/// Source: Blender 4.x `svm_node_tex_brick` (brick.h), geometry nodes' `BrickFunction`:
/// `color = mix(color1, color2, tint)` unless fac is 1, then `color·(1 − fac) + mortar·fac`.
/// The frequencies are clamped to [1, 99], brick_width, row_height and squash to ≥ 0.01
/// (Blender's field limits but squash's, which is 0: 0 would divide by zero), |vector·scale|
/// to 10¹².
#[allow(clippy::too_many_arguments)]
pub fn brick_texture(
    vector: Vec3,
    color1: Vec3,
    color2: Vec3,
    mortar: Vec3,
    scale: f32,
    mortar_size: f32,
    mortar_smooth: f32,
    bias: f32,
    brick_width: f32,
    row_height: f32,
    offset: f32,
    offset_frequency: i32,
    squash: f32,
    squash_frequency: i32,
) -> (Vec3, f32) {
    let p = (vector * scale).clamp(Vec3::splat(-COORD_LIMIT), Vec3::splat(COORD_LIMIT));
    let (tint, f) = brick(
        p,
        mortar_size,
        mortar_smooth,
        bias,
        brick_width.max(0.01),
        row_height.max(0.01),
        offset,
        offset_frequency.clamp(1, 99),
        squash.max(0.01),
        squash_frequency.clamp(1, 99),
    );
    let c = if f != 1.0 {
        color1 * (1.0 - tint) + color2 * tint
    } else {
        color1
    };
    (c * (1.0 - f) + mortar * f, f)
}

/// WGSL of [`brick_noise`].
const BRICK_NOISE_WGSL: &str = r#"
fn mg_bb_noise(n0: u32) -> f32 {
    var n = (n0 + 1013u) & 0x7fffffffu;
    n = (n >> 13u) ^ n;
    let nn = (n * (n * n * 60493u + 19990303u) + 1376312589u) & 0x7fffffffu;
    let f = f32(nn >> 16u) * 65536.0 + f32(nn & 0xffffu);
    return 0.5 * (f * (1.0 / 1073741824.0));
}
"#;

/// WGSL of the i32 → f32 conversion rounded to nearest, as Rust's `as f32` and C's: WGSL
/// lets `f32(i)` round either way past 2²⁴, so it is `2¹⁶·hi + lo`, both exact, one sum.
const EXACT_F32_WGSL: &str = r#"
fn mg_bb_f32(i: i32) -> f32 {
    return f32(i >> 16u) * 65536.0 + f32(i & 0xffff);
}
"#;

/// WGSL of [`brick_texture`].
const BRICK_TEXTURE_WGSL: &str = r#"
fn $fn(vector: vec3<f32>, color1: vec3<f32>, color2: vec3<f32>, mortar_color: vec3<f32>, scale: f32, mortar_size: f32, mortar_smooth: f32, bias: f32, brick_width0: f32, row_height0: f32, offset_amount: f32, offset_frequency0: i32, squash_amount0: f32, squash_frequency0: i32) -> $out {
    let p = clamp(vector * scale, vec3<f32>(-1e12), vec3<f32>(1e12));
    var brick_width = max(brick_width0, 0.01);
    let row_height = max(row_height0, 0.01);
    let squash_amount = max(squash_amount0, 0.01);
    let offset_frequency = clamp(offset_frequency0, 1, 99);
    let squash_frequency = clamp(squash_frequency0, 1, 99);
    let rownum = i32(floor(p.y / row_height));
    // Whether rownum is a multiple, from |rownum|: GLSL leaves % of a negative operand
    // undefined, and naga's GLSL keeps WGSL's % as is.
    let row_abs = bitcast<u32>(select(rownum, -rownum, rownum < 0));
    if (row_abs % u32(squash_frequency) == 0u) {
        brick_width = brick_width * squash_amount;
    }
    var offset = 0.0;
    if (row_abs % u32(offset_frequency) == 0u) {
        offset = brick_width * offset_amount;
    }
    let bricknum = i32(floor((p.x + offset) / brick_width));
    let x = (p.x + offset) - brick_width * mg_bb_f32(bricknum);
    let y = p.y - row_height * mg_bb_f32(rownum);
    let key = (bitcast<u32>(rownum) << 16u) + (bitcast<u32>(bricknum) & 0xffffu);
    let tint = clamp(mg_bb_noise(key) + bias, 0.0, 1.0);
    let min_dist = min(min(x, y), min(brick_width - x, row_height - y));
    var f = 0.0;
    if (min_dist >= mortar_size) {
        f = 0.0;
    } else if (mortar_smooth == 0.0 || mortar_size <= 0.0) {
        f = 1.0;
    } else {
        let m = 1.0 - min_dist / mortar_size;
        if (m < mortar_smooth) {
            let t = m / mortar_smooth;
            let tt = t * t;
            f = 3.0 * tt - 2.0 * tt * t;
        } else {
            f = 1.0;
        }
    }
    var c = color1;
    if (f != 1.0) {
        c = color1 * (1.0 - tint) + color2 * tint;
    }
    return $out(c * (1.0 - f) + mortar_color * f, f);
}
"#;

/// The Brick node type.
pub fn all() -> Vec<NodeType> {
    let f = Value::float;
    let v3 = Value::vec3;
    let i = Value::int;
    vec![
        NodeType::new(
            "brick_texture",
            Category::Texture,
            "Blender's Brick Texture: offset rows of bricks tinted between two colours by an integer hash, with mortar.",
        )
        .source(
            "Blender 4.x Brick Texture (intern/cycles/kernel/svm/brick.h; geometry nodes' \
             node_shader_tex_brick.cc): row ⌊y/row_height⌋, every squash_frequency-th row's \
             bricks squash times as wide and every offset_frequency-th row shifted by \
             offset·brick_width, brick ⌊(x + shift)/brick_width⌋; tint = clamp(brick_noise(row·2¹⁶ \
             + brick mod 2¹⁶) + bias, 0, 1), Blender's integer hash; fac = the mortar weight, 1 \
             within mortar_size of a brick edge less Hermite smoothing over mortar_smooth of \
             it. Matches Blender 4.2 within 1e-4 away from brick edges \
             (tests/models/blender_textures.rs). Deviations: `vector` defaults to the origin \
             (Blender: generated coordinates); brick_width, row_height and squash are clamped to \
             ≥ 0.01 and the frequencies to [1, 99] (Blender's field limits, but squash's is 0, \
             which divides by zero), \
             |vector·scale| to 10¹² (so that infinite coordinates stay finite); row and brick \
             numbers saturate at ±2³¹ (C's conversion is undefined there). Row and brick edges are \
             discontinuities: colour jumps there and any rounding picks either side.",
        )
        .input(In::vec3("vector", [0.0, 0.0, 0.0]).range(-10.0, 10.0).doc("Where to evaluate (link geometry.position or uv)."))
        .input(In::color("color1", [0.8, 0.8, 0.8]).range(0.0, 1.0).doc("The colour of tint 0."))
        .input(In::color("color2", [0.2, 0.2, 0.2]).range(0.0, 1.0).doc("The colour of tint 1."))
        .input(In::color("mortar", [0.0, 0.0, 0.0]).range(0.0, 1.0).doc("The mortar's colour."))
        .input(In::float("scale", 5.0).range(0.0, 50.0).hard(-1.0e3, 1.0e3).doc("Multiplies vector."))
        .input(In::float("mortar_size", 0.02).range(0.0, 0.125).hard(0.0, 0.125).doc("Width of the mortar between bricks (0: none)."))
        .input(In::float("mortar_smooth", 0.1).range(0.0, 1.0).hard(0.0, 1.0).doc("Fraction of the mortar blended smoothly into the brick."))
        .input(In::float("bias", 0.0).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Added to each brick's random tint (±1: one colour only)."))
        .input(In::float("brick_width", 0.5).range(0.01, 2.0).hard(0.01, 100.0).doc("Width of a brick."))
        .input(In::float("row_height", 0.25).range(0.01, 2.0).hard(0.01, 100.0).doc("Height of a row."))
        .input(In::float("offset", 0.5).range(0.0, 1.0).hard(0.0, 1.0).doc("Shift of the offset rows, in brick widths."))
        .input(In::int("offset_frequency", 2).range(1.0, 99.0).hard(1.0, 99.0).doc("Every how many rows are shifted."))
        .input(In::float("squash", 1.0).range(0.01, 4.0).hard(0.01, 99.0).doc("Width factor of the squashed rows' bricks (Blender allows 0, which divides by zero)."))
        .input(In::int("squash_frequency", 2).range(1.0, 99.0).hard(1.0, 99.0).doc("Every how many rows are squashed."))
        .output(Out::color("color").doc("The brick's tint of color1 → color2, mortar where fac is 1."))
        .output(Out::float("fac").doc("The mortar's weight: 0 on a brick, 1 in the mortar."))
        .wgsl(BRICK_TEXTURE_WGSL)
        .wgsl_uses(&[BRICK_NOISE_WGSL, EXACT_F32_WGSL])
        .hard_case("a brick corner", &[("vector", v3([0.0, 0.0, 0.0]))])
        .hard_case("negative rows and bricks", &[("vector", v3([-7.3, -3.1, 0.0])), ("scale", f(3.0))])
        .hard_case("sharp mortar", &[("vector", v3([0.101, 0.05, 0.0])), ("mortar_smooth", f(0.0))])
        .hard_case("no mortar", &[("vector", v3([0.1, 0.05, 0.0])), ("mortar_size", f(0.0))])
        .hard_case("narrowest squash", &[("vector", v3([0.3, 0.0, 0.0])), ("squash", f(0.01)), ("squash_frequency", i(1))])
        .hard_case("past 2¹⁶ bricks", &[("vector", v3([9_000.0, 3.0, 0.0])), ("scale", f(1.0e3)), ("brick_width", f(0.01))])
        .hard_case("huge coordinates", &[("vector", v3([1.0e30, -1.0e30, 0.0])), ("scale", f(1.0e3))])
        .compute(brick_texture),
    ]
}

#[cfg(test)]
mod tests {

    /// The hash's float conversion is C's `(float)nn`: the split sum equals a direct
    /// round-to-nearest conversion for every bit pattern tried.
    #[test]
    fn the_split_conversion_rounds_as_c() {
        let mut x = 0x1234_5678u32;
        for _ in 0..100_000 {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            let nn = x & 0x7fff_ffff;
            let split = (nn >> 16) as f32 * 65536.0 + (nn & 0xffff) as f32;
            assert_eq!(split, nn as f32, "{nn}");
        }
    }
}
