//! Blender's Bump node: a shading normal tilted by the slope of a height field, from the
//! height re-evaluated one pixel over, and the position derivatives it needs.
//!
//! Source: Blender 4.x Bump (Cycles `svm_node_set_bump` and `svm_node_bump`,
//! kernel/svm/bump.h; EEVEE `node_bump`, gpu_shader_material_bump.glsl), after Mikkelsen,
//! "Bump Mapping Unparametrized Surfaces on the GPU" (2010), eq. 2–4: with the position's
//! screen derivatives `dPdx`, `dPdy` and the unit normal `N`,
//! `Rx = dPdy × N`, `Ry = N × dPdx`, `det = dPdx · Rx`,
//! `∇s = (h(P + dPdx) − h) Rx + (h(P + dPdy) − h) Ry`,
//! `N' = normalize(|det| N − d · sign(det) ∇s)`, then `normalize(mix(N, N', strength))`.
//!
//! How the shifted heights are found is the compiler's: [`crate::bump`] evaluates the
//! subgraph under `height` a second and a third time with the positions and uvs moved by
//! their one-pixel derivatives (Cycles' approach), the same on the CPU and the GPU.

use super::math::{NORMALIZE3_WGSL, normalize};
use crate::node::{Attribute, Category, In, NodeType, Out};
use crate::precision::cross;
use crate::value::Value;
use glam::Vec3;

/// Above this `|d · h / |dP||` the `|det| N` term is below an ulp of the slope term: the
/// tilt is taken from the slope alone, so that no product overflows.
const SLOPE_ONLY: f32 = 1e30;

/// Above this height magnitude the heights are scaled down before they are differenced.
const HEIGHT_RESCALE: f32 = 1e18;

/// Blender's Bump (Mikkelsen 2010, eq. 2–4; see the module doc): `normal` (normalised) tilted
/// by the surface gradient of the height field, whose values one pixel to the right and one
/// down are `height_dx` and `height_dy` at the offsets `position_dx`, `position_dy`, scaled
/// by `distance` (negated by `invert`), blended from the normal by `strength` (clamped to
/// [0, 1], Blender's range). The products are formed over the offsets scaled to at most 1
/// (and heights beyond 10¹⁸ scaled to at most 1): a common positive factor of both terms, so
/// the direction is the equation's and no product overflows. Where there is no tilt to take
/// (offsets zero or parallel: `det = 0`, no scene) or no normal, the normalised `normal` is
/// returned (Blender's GLSL gives NaN there).
#[allow(clippy::too_many_arguments)]
pub fn bump(
    height: f32,
    distance: f32,
    strength: f32,
    invert: bool,
    normal: Vec3,
    height_dx: f32,
    height_dy: f32,
    position_dx: Vec3,
    position_dy: Vec3,
) -> Vec3 {
    let n = normalize(normal);
    let k = position_dx.abs().max(position_dy.abs()).max_element();
    if n == Vec3::ZERO || !(k > 0.0 && k <= f32::MAX) {
        return n;
    }
    let (a, b) = (position_dx / k, position_dy / k);
    let rx = cross(b, n);
    let ry = cross(n, a);
    let det = a.dot(rx);
    let hm = height.abs().max(height_dx.abs()).max(height_dy.abs());
    let s = if hm > HEIGHT_RESCALE { hm } else { 1.0 };
    let grad = rx * (height_dx / s - height / s) + ry * (height_dy / s - height / s);
    let d = if invert { -distance } else { distance };
    let c = d / k * s;
    let sign = if det > 0.0 {
        1.0
    } else if det < 0.0 {
        -1.0
    } else {
        0.0
    };
    let tilted = if c.abs() > SLOPE_ONLY {
        grad * -(sign * c.signum())
    } else {
        n * det.abs() - grad * (c * sign)
    };
    let t = normalize(tilted);
    if t == Vec3::ZERO {
        return n;
    }
    let out = normalize(n + (t - n) * strength.clamp(0.0, 1.0));
    if out == Vec3::ZERO { n } else { out }
}

/// WGSL of [`bump`], the same operations in the same order.
const BUMP_WGSL: &str = r#"
fn $fn(height: f32, distance: f32, strength: f32, invert: bool, normal: vec3<f32>, height_dx: f32, height_dy: f32, position_dx: vec3<f32>, position_dy: vec3<f32>) -> vec3<f32> {
    let n = mg_normalize3(normal);
    let m = max(abs(position_dx), abs(position_dy));
    let k = max(max(m.x, m.y), m.z);
    if (all(n == vec3<f32>(0.0)) || !(k > 0.0 && k <= 0x1.fffffep+127f)) {
        return n;
    }
    let a = position_dx / k;
    let b = position_dy / k;
    let rx = cross(b, n);
    let ry = cross(n, a);
    let det = dot(a, rx);
    let hm = max(max(abs(height), abs(height_dx)), abs(height_dy));
    let s = select(1.0, hm, hm > 1e18);
    let grad = rx * (height_dx / s - height / s) + ry * (height_dy / s - height / s);
    let d = select(distance, -distance, invert);
    let c = d / k * s;
    let sg = select(select(0.0, -1.0, det < 0.0), 1.0, det > 0.0);
    var tilted = n * abs(det) - grad * (c * sg);
    if (abs(c) > 1e30) {
        tilted = grad * -(sg * sign(c));
    }
    let t = mg_normalize3(tilted);
    if (all(t == vec3<f32>(0.0))) {
        return n;
    }
    let o = mg_normalize3(n + (t - n) * clamp(strength, 0.0, 1.0));
    return select(o, n, all(o == vec3<f32>(0.0)));
}
"#;

/// The bump family: `position_derivatives` and `bump`.
pub fn all() -> Vec<NodeType> {
    let f = Value::float;
    let v3 = Value::vec3;
    vec![
        NodeType::new(
            "position_derivatives",
            Category::Geometry,
            "Screen-space derivatives of the surface position, per pixel.",
        )
        .source(
            "position_dx = ∂P/∂x and position_dy = ∂P/∂y in metres per pixel, x the pixel column \
             growing to the right and y the row growing downwards: what dpdxFine(position) and \
             dpdyFine(position) give a fragment shader. The CPU G-buffer supplies the fine \
             derivatives' values, the differences of the positions on the plane of the triangle \
             hit under the centres of the pixel's 2 × 2 quad (crate::node::Attribute::PositionDx), \
             as uv_derivatives does the uv's. The bump node's one-pixel offsets (Cycles' dP.dx, \
             dP.dy). Without a scene (matgraph eval) both are 0.",
        )
        .output(
            Out::vec3("position_dx")
                .unit("m")
                .doc("∂P/∂x: position change per pixel to the right."),
        )
        .output(
            Out::vec3("position_dy")
                .unit("m")
                .doc("∂P/∂y: position change per pixel downwards."),
        )
        .attributes(&[Attribute::PositionDx, Attribute::PositionDy])
        .compute(|| (Vec3::ZERO, Vec3::ZERO)),
        NodeType::new(
            "bump",
            Category::Vector,
            "Blender's Bump: a shading normal tilted by the slope of a height field.",
        )
        .source(
            "Blender 4.x Bump (Cycles svm_node_set_bump/svm_node_bump, EEVEE node_bump), after \
             Mikkelsen 2010 eq. 2–4: Rx = dPdy × N, Ry = N × dPdx, \
             det = dPdx · Rx, ∇s = (h_x − h) Rx + (h_y − h) Ry, N' = normalize(|det| N − d · \
             sign(det) ∇s), then normalize(mix(N, N', strength)). The heights one pixel over \
             (h_x, h_y) come from the subgraph under `height` evaluated again with positions and \
             uvs moved by their fine derivatives (Cycles' re-evaluation, on the CPU and the GPU \
             alike; EEVEE differentiates the height with dFdx instead); the other coordinates \
             (generated, window, camera, screen uv, water depth) are not moved, so a height made \
             from them alone bumps nothing. `height_dx`, `height_dy`, `position_dx` and \
             `position_dy` are filled by the compiler when left unlinked, and `normal` unlinked \
             is the surface's shading normal (Blender's default). Deviations: Blender 4.3's \
             Filter Width (default 0.1 pixel) is not offered: the offset is one pixel, as in \
             Blender up to 4.2; no back-face flip (matgraph shades the side the normal faces); \
             strength is clamped to [0, 1] (Blender's range); where there is no tilt (no \
             scene: zero derivatives) or no normal, the normal is returned where Blender's GLSL \
             gives NaN. The products are formed over offsets scaled to at most 1 (heights \
             beyond 1e18 likewise), a common factor that leaves the direction unchanged and \
             keeps every product finite.",
        )
        .input(
            In::float("height", 1.0)
                .range(0.0, 1.0)
                .hard(-1e18, 1e18)
                .unit("m")
                .doc("The height field, linked (a literal bumps nothing)."),
        )
        .input(
            In::float("distance", 1.0)
                .range(0.0, 1.0)
                .hard(0.0, 1000.0)
                .doc("Multiplier of the height: how far 1 unit of height displaces."),
        )
        .input(
            In::float("strength", 1.0)
                .range(0.0, 1.0)
                .hard(0.0, 1.0)
                .doc("0: the surface's normal; 1: the full bump."),
        )
        .input(In::boolean("invert", false).doc("Negate the distance: dents for bumps."))
        .input(
            In::vec3("normal", [0.0, 0.0, 1.0])
                .range(-1.0, 1.0)
                .doc("The normal to tilt; unlinked, the surface's shading normal."),
        )
        .input(
            In::float("height_dx", 1.0)
                .range(0.0, 1.0)
                .hard(-1e18, 1e18)
                .unit("m")
                .doc("The height one pixel to the right; filled by the compiler when unlinked."),
        )
        .input(
            In::float("height_dy", 1.0)
                .range(0.0, 1.0)
                .hard(-1e18, 1e18)
                .unit("m")
                .doc("The height one pixel down; filled by the compiler when unlinked."),
        )
        .input(
            In::vec3("position_dx", [0.0, 0.0, 0.0])
                .range(-0.01, 0.01)
                .unit("m")
                .doc("∂P/∂x; filled by the compiler (position_derivatives) when unlinked."),
        )
        .input(
            In::vec3("position_dy", [0.0, 0.0, 0.0])
                .range(-0.01, 0.01)
                .unit("m")
                .doc("∂P/∂y; filled by the compiler (position_derivatives) when unlinked."),
        )
        .output(Out::vec3("normal").doc("The tilted unit world-space shading normal."))
        .wgsl(BUMP_WGSL)
        .wgsl_uses(&[NORMALIZE3_WGSL])
        .hard_case(
            "no derivatives (no scene)",
            &[("height_dx", f(2.0)), ("height_dy", f(3.0))],
        )
        .hard_case(
            "parallel derivatives",
            &[
                ("position_dx", v3([1e-3, 0.0, 0.0])),
                ("position_dy", v3([2e-3, 0.0, 0.0])),
                ("height_dx", f(2.0)),
            ],
        )
        .hard_case(
            "zero normal",
            &[
                ("normal", v3([0.0, 0.0, 0.0])),
                ("position_dx", v3([1e-3, 0.0, 0.0])),
                ("position_dy", v3([0.0, -1e-3, 0.0])),
                ("height_dx", f(2.0)),
            ],
        )
        .hard_case(
            "huge slope",
            &[
                ("position_dx", v3([1e-30, 0.0, 0.0])),
                ("position_dy", v3([0.0, -1e-30, 0.0])),
                ("height_dx", f(1e18)),
                ("height", f(-1e18)),
                ("distance", f(1000.0)),
            ],
        )
        .hard_case(
            "denormal derivatives",
            &[
                ("position_dx", v3([1e-45, 0.0, 0.0])),
                ("position_dy", v3([0.0, -1e-45, 0.0])),
                ("height_dx", f(1.5)),
            ],
        )
        .hard_case(
            "huge derivatives",
            &[
                ("position_dx", v3([3e38, 0.0, 0.0])),
                ("position_dy", v3([0.0, -3e38, 0.0])),
                ("height_dx", f(-1e18)),
            ],
        )
        .hard_case(
            "inverted, strength 0",
            &[
                ("position_dx", v3([1e-3, 0.0, 0.0])),
                ("position_dy", v3([0.0, -1e-3, 0.0])),
                ("height_dx", f(1.5)),
                ("invert", Value::boolean(true)),
                ("strength", f(0.0)),
            ],
        )
        .hard_case(
            "normal along an offset",
            &[
                ("normal", v3([1.0, 0.0, 0.0])),
                ("position_dx", v3([1e-3, 0.0, 0.0])),
                ("position_dy", v3([0.0, -1e-3, 0.0])),
                ("height_dy", f(0.0)),
            ],
        )
        .compute(bump),
    ]
}
