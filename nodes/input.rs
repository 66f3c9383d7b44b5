//! Constants, exposed parameters, and the per-sample geometry the caller supplies.

use crate::node::{Attribute, Category, In, NodeType, Out};
use crate::types::SocketType::*;
use glam::{Vec2, Vec3, Vec4};

/// Adds an identity compute for every value type, so `value` passes through.
fn identity_variants(t: NodeType) -> NodeType {
    t.wgsl("fn $fn(value: $T) -> $T { return value; }")
        .variant(Float, |x: f32| x)
        .variant(Vec2, |x: Vec2| x)
        .variant(Vec3, |x: Vec3| x)
        .variant(Vec4, |x: Vec4| x)
}

/// The input-family node types.
pub fn all() -> Vec<NodeType> {
    vec![
        constant(),
        parameter(),
        geometry(),
        time(),
        uv_derivatives(),
        reroute(),
    ]
}

/// Blender's Reroute: a wire's elbow. The CPU plan and the WGSL read its source in its
/// place, so it costs nothing.
fn reroute() -> NodeType {
    identity_variants(
        NodeType::new(
            crate::group::REROUTE,
            Category::Input,
            "Passes its input on unchanged (a wire's elbow).",
        )
        .source(
            "Blender's Reroute node. Its type is that of what is connected; the plan and the \
             WGSL read the source in its place (no step, no call).",
        )
        .input(In::generic("input", 0.0).doc("The value passed on."))
        .output(Out::generic("output").doc("The same value.")),
    )
}

fn constant() -> NodeType {
    identity_variants(
        NodeType::new("constant", Category::Input, "A fixed value of any type.")
            .source("Folded into the plan at compile time (and into literals in WGSL).")
            .input(
                In::generic("value", 0.0)
                    .doc("The value; its JSON shape sets the type (0.5, [x, y, z], ...)."),
            )
            .output(Out::generic("value").doc("The same value.")),
    )
}

fn parameter() -> NodeType {
    identity_variants(
        NodeType::new(
            "parameter",
            Category::Input,
            "A material setting exposed to the caller.",
        )
        .source(
            "The file's value is the default; callers override it per evaluation without \
                 recompiling (a uniform on the GPU). List it in the graph's `parameters` to give \
                 it a name, doc and group.",
        )
        .input(In::generic("value", 0.0).doc("Default value; its JSON shape sets the type."))
        .output(Out::generic("value").doc("The value set by the caller, or the default."))
        .parameter(),
    )
}

fn geometry() -> NodeType {
    use Attribute::*;
    NodeType::new(
        "geometry",
        Category::Geometry,
        "Per-sample geometry supplied by the caller.",
    )
    .source(
        "Conventions (docs/models/README.md): N points out of the surface, V from the surface \
             to the eye, L from the surface to the light; all unit length. I = -V. When a scene \
             has several lights the renderer evaluates the graph once per light (light and \
             light_color change) and sums the `color` outputs.",
    )
    .output(Out::vec3("position").unit("m").doc("World-space position."))
    .output(Out::vec3("normal").doc("Unit surface normal N."))
    .output(Out::vec3("view").doc("Unit direction V from the surface to the eye."))
    .output(Out::vec3("light").doc("Unit direction L from the surface to the light."))
    .output(Out::vec2("uv").doc("Texture coordinates."))
    .output(
        Out::color("light_color")
            .doc("Radiance arriving from the light: colour × intensity × falloff."),
    )
    .output(Out::vec2("screen_uv").doc("Screen position, (0, 0) top left to (1, 1) bottom right."))
    .output(
        Out::float("depth")
            .unit("m")
            .doc("Depth below the water surface (0 above it)."),
    )
    .output(
        Out::vec3("tangent").doc("Unit tangent T: where u grows (MikkTSpace), orthogonal to N."),
    )
    .output(
        Out::float("bitangent_sign")
            .doc("±1: v grows along bitangent_sign · (N × T); −1 where uvs are mirrored."),
    )
    .attributes(&[
        Position,
        Normal,
        View,
        Light,
        Uv,
        LightColor,
        ScreenUv,
        Depth,
        Tangent,
        BitangentSign,
    ])
    .compute(|| {
        (
            Vec3::ZERO,
            Vec3::Z,
            Vec3::Z,
            Vec3::Z,
            Vec2::splat(0.5),
            Vec3::ONE,
            Vec2::splat(0.5),
            0.0f32,
            Vec3::X,
            1.0f32,
        )
    })
}

fn time() -> NodeType {
    NodeType::new(
        "time",
        Category::Geometry,
        "The time of the evaluation, in seconds.",
    )
    .source("The same for every sample of a batch; hoisted out of the per-sample work.")
    .output(Out::float("time").unit("s").doc("Time in seconds."))
    .attributes(&[Attribute::Time])
    .compute(|| 0.0f32)
}

fn uv_derivatives() -> NodeType {
    NodeType::new(
        "uv_derivatives",
        Category::Geometry,
        "Screen-space derivatives of the surface uv, per pixel.",
    )
    .source(
        "uv_dx = ∂uv/∂x and uv_dy = ∂uv/∂y, x the pixel column growing to the right and y the \
         pixel row growing downwards (WGSL framebuffer coordinates), in uv units per pixel: what \
         dpdx(uv) and dpdy(uv) give a fragment shader. The CPU G-buffer supplies the fine \
         derivatives' values, the differences of uv across the pixel's 2 × 2 quad, computed \
         from the camera rays on the plane of the triangle hit (crate::node::Attribute::UvDx). Feed them to mip_level to choose a mip level the same \
         way on every path.",
    )
    .output(Out::vec2("uv_dx").doc("∂uv/∂x: uv change per pixel to the right."))
    .output(Out::vec2("uv_dy").doc("∂uv/∂y: uv change per pixel downwards."))
    .attributes(&[Attribute::UvDx, Attribute::UvDy])
    .compute(|| (Vec2::ZERO, Vec2::ZERO))
}
