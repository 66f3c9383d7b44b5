//! The render entries of [`super::Entry::Render`]: `mg_vertex`, which evaluates the graph's
//! `displacement` output on the GPU and rebuilds the normal, and `mg_fragment`, which runs the
//! light loop over the lights buffer and writes premultiplied colour and alpha. The layout
//! they bind (group 0) and the structs they declare are the app contract, specified in
//! docs/integration.md; [`crate::material`] wraps it in a Rust API.
//!
//! **Normals.** A vertex stage sees one vertex, so the displaced surface's normal is rebuilt
//! from the displacement itself: `P(x) = x + D(x)` is evaluated at the vertex and at
//! `x ± h·T`, `x ± h·B` (T, B the orthonormal tangent frame of the normal N by Duff et al.
//! 2017, "Building an Orthonormal Basis, Revisited"), with `h = MG_NORMAL_STEP · max(1, |x|∞)`
//! metres, and `N' = normalize((P(x + hT) − P(x − hT)) × (P(x + hB) − P(x − hB)))`: central
//! differences, truncation error O(h²·|D'''|), rounding error about ε₃₂·|x|/h ≈ 1e-4 rad.
//! The normal and uv inputs of `D` are held at the vertex's, so the rebuilt normal is exact to
//! that order for a displacement of position and time, and misses the variation of D with
//! normal and uv along the surface (O(h) where D depends on them).

use super::emit::{convert, literal};
use super::{Binding, ShaderOutput};
use crate::node::Attribute;
use crate::types::SocketType;
use std::fmt::Write;

/// Binding of the parameter block `mg_params` (`MgParams`, uniform), when the graph has one.
pub const PARAMS_BINDING: u32 = 0;
/// Binding of the per-draw uniform `mg_frame` (`MgFrame`).
pub const FRAME_BINDING: u32 = 1;
/// Binding of the lights buffer `mg_lights` (read-only storage `array<MgLight>`).
pub const LIGHTS_BINDING: u32 = 2;
/// The first texture binding (exact: three storage buffers; hardware: samplers, then textures).
pub const FIRST_TEXTURE_BINDING: u32 = 3;
/// Relative step of the normal rebuild's central differences (see the module doc).
pub const NORMAL_STEP: f32 = 1e-3;
/// Bytes of `MgFrame` (naga's layout; checked by a test).
pub const FRAME_SIZE: u32 = 224;
/// Bytes per `MgLight` in the lights buffer (naga's array stride; checked by a test).
pub const LIGHT_STRIDE: u32 = 32;
/// `MgLight.kind` of a directional light: `vector` is the direction towards the light.
pub const LIGHT_DIRECTIONAL: u32 = 0;
/// `MgLight.kind` of a point light: `vector` is its position, radiance falls off as 1/d².
pub const LIGHT_POINT: u32 = 1;
/// Distance below which a point light's falloff is clamped (m), as on the CPU.
pub const LIGHT_MIN_DISTANCE: f32 = 1e-3;

/// The per-draw uniform and the light record, as WGSL.
pub const FRAME_WGSL: &str = "\
struct MgFrame {
    view_proj: mat4x4<f32>,
    model: mat4x4<f32>,
    normal_model: mat4x4<f32>,
    camera_position: vec3<f32>,
    light_count: u32,
    viewport: vec2<f32>,
    pad0: f32,
    pad1: f32,
}

struct MgLight {
    vector: vec3<f32>,
    kind: u32,
    color: vec3<f32>,
    pad: f32,
}
";

/// The default hooks: a module may replace this text with its own definitions of the four
/// functions (same signatures), e.g. shadows and the water depth of a scene, and the
/// `generated` and `camera` attributes (the surface's texture space, the camera's frame),
/// which the defaults leave at the attributes' defaults.
pub const DEFAULT_HOOKS_WGSL: &str = "\
// mg-hooks: begin
fn mg_light_visibility(index: u32, position: vec3<f32>, to_light: vec3<f32>, distance: f32) -> f32 {
    return 1.0;
}

fn mg_surface_depth(position: vec3<f32>) -> f32 {
    return 0.0;
}

fn mg_generated(position: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(0.5);
}

fn mg_camera(position: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(0.0, 0.0, 1.0);
}
// mg-hooks: end
";

/// The unit direction from the surface to the eye (the `view` attribute), `n` where the eye
/// is on the surface.
const VIEW_WGSL: &str = "select(n, normalize(mg_frame.camera_position - v.position), \
     dot(mg_frame.camera_position - v.position, mg_frame.camera_position - v.position) > 0.0)";

/// The `reflection` attribute: the view mirrored about the normal (Cycles' tex_coord).
const REFLECTION_WGSL: &str = "\
fn mg_reflection(n: vec3<f32>, view: vec3<f32>) -> vec3<f32> {
    return 2.0 * dot(n, view) * n - view;
}

";

/// The `window` attribute from the screen position: Blender's window, (0, 0) bottom left.
const WINDOW_WGSL: &str = "\
fn mg_window(s: vec2<f32>) -> vec3<f32> {
    return vec3<f32>(s.x, 1.0 - s.y, 0.0);
}

";

/// `MgVertexOut`, the varyings of `mg_vertex` → `mg_fragment`: interpolated at the pixel
/// (or where the rasteriser chooses within its covered samples).
pub const VERTEX_OUT_WGSL: &str = "\
struct MgVertexOut {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
}

";

/// [`VERTEX_OUT_WGSL`] of a graph that reads the tangent frame: the world-space tangent
/// (`xyz`) and bitangent sign (`w`) of the vertex, interpolated.
pub const VERTEX_OUT_TANGENT_WGSL: &str = "\
struct MgVertexOut {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
}

";

/// [`VERTEX_OUT_TANGENT_WGSL`] with per-sample interpolation.
pub const VERTEX_OUT_TANGENT_SAMPLE_WGSL: &str = "\
struct MgVertexOut {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) @interpolate(perspective, sample) position: vec3<f32>,
    @location(1) @interpolate(perspective, sample) normal: vec3<f32>,
    @location(2) @interpolate(perspective, sample) uv: vec2<f32>,
    @location(3) @interpolate(perspective, sample) tangent: vec4<f32>,
}

";

/// The tangent of the frame at a fragment, as `scene::orthonormal_tangent`: the interpolated
/// tangent `t` made orthogonal to the unit normal `n` (Gram–Schmidt), else the tangent of
/// Duff et al.'s orthonormal basis of `n` (2017).
pub const TANGENT_WGSL: &str = "\
fn mg_tangent(n: vec3<f32>, t: vec3<f32>) -> vec3<f32> {
    let o = t - n * dot(n, t);
    let l = length(o);
    if (l > 1e-6 * length(t) && l > 0.0 && l <= MG_F32_MAX) {
        return o / l;
    }
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    return vec3<f32>(1.0 + s * n.x * n.x * a, s * n.x * n.y * a, -s * n.x);
}

";

/// `MgVertexOut` with per-sample interpolation (`@interpolate(perspective, sample)`): under
/// MSAA the fragment entry runs once per covered sample, at the sample's position.
pub const VERTEX_OUT_SAMPLE_WGSL: &str = "\
struct MgVertexOut {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) @interpolate(perspective, sample) position: vec3<f32>,
    @location(1) @interpolate(perspective, sample) normal: vec3<f32>,
    @location(2) @interpolate(perspective, sample) uv: vec2<f32>,
}

";

/// The end of `mg_vertex` for a graph with `displacement`: the displaced position and the
/// rebuilt normal (see the module doc).
pub const DISPLACE_VERTEX_WGSL: &str = "    let q = mg_displaced(p, n, v.uv);
    // Tangent frame of n (Duff et al. 2017), right-handed: t × b = n.
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let c = n.x * n.y * a;
    let t = vec3<f32>(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    let b = vec3<f32>(c, s + n.y * n.y * a, -n.y);
    let h = MG_NORMAL_STEP * max(1.0, max(abs(p.x), max(abs(p.y), abs(p.z))));
    let dt = mg_displaced(p + h * t, n, v.uv) - mg_displaced(p - h * t, n, v.uv);
    let db = mg_displaced(p + h * b, n, v.uv) - mg_displaced(p - h * b, n, v.uv);
    let m = cross(dt, db);
    let ok = dot(m, m) > 0.0 && dot(m, m) < 3.0e38;
    o.position = q;
    o.normal = select(n, normalize(m), ok);
";

/// The end of `mg_vertex` without displacement (or for vertices displaced already): the
/// transformed position and normal.
pub const PASS_VERTEX_WGSL: &str = "    o.position = p;\n    o.normal = n;\n";

/// The render module `source` (as generated) with per-sample varyings when `sample_shading`
/// ([`VERTEX_OUT_SAMPLE_WGSL`]) and, when `displaced_vertices`, `mg_vertex` passing the
/// vertex buffer's positions and normals through ([`PASS_VERTEX_WGSL`]: the mesh was
/// displaced already, by the app or by `mg_material(g).displacement` of the library module).
pub fn variant(source: &str, sample_shading: bool, displaced_vertices: bool) -> String {
    let mut s = source.to_owned();
    if sample_shading {
        s = s.replacen(VERTEX_OUT_WGSL, VERTEX_OUT_SAMPLE_WGSL, 1);
        s = s.replacen(VERTEX_OUT_TANGENT_WGSL, VERTEX_OUT_TANGENT_SAMPLE_WGSL, 1);
    }
    if displaced_vertices {
        s = s.replacen(DISPLACE_VERTEX_WGSL, PASS_VERTEX_WGSL, 1);
    }
    s
}

/// The render module `source` (as generated, reading the tangent buffer) for an app that
/// binds no tangent buffer: `mg_vertex` reads no location 3, and `mg_fragment` builds the
/// frame from screen-space derivatives of the position and uv instead (Mikkelsen 2010,
/// "Bump Mapping Unparametrized Surfaces on the GPU"; Schüler 2013, "Normal Mapping Without
/// Precomputed Tangents"): per pixel rather than MikkTSpace's per-vertex average, so the
/// frame is faceted with the triangles (it follows each triangle's uv mapping exactly) and a
/// normal map baked against MikkTSpace is off by the difference, which is largest where the
/// uvs stretch unevenly across a triangle. `source` unchanged when it reads no tangents.
pub fn derived_tangents(source: &str) -> String {
    const VERTEX_READ: &str = "    o.tangent = vec4<f32>((mg_frame.model * vec4<f32>(v.tangent.xyz, 0.0)).xyz, v.tangent.w);\n";
    if !source.contains(VERTEX_READ) {
        return source.to_owned();
    }
    source
        // The first is MgVertexIn's (MgVertexOut's follows it).
        .replacen("    @location(3) tangent: vec4<f32>,\n", "", 1)
        .replacen(VERTEX_READ, "    o.tangent = vec4<f32>(0.0);\n", 1)
        .replacen(
            TANGENT_WGSL,
            &format!("{TANGENT_WGSL}{DERIVED_TANGENT_WGSL}"),
            1,
        )
        .replacen(
            "mg_tangent(n, v.tangent.xyz)",
            "mg_derived_frame(n, v.position, v.uv).xyz",
            1,
        )
        .replacen(
            "select(-1.0, 1.0, v.tangent.w >= 0.0)",
            "mg_derived_frame(n, v.position, v.uv).w",
            1,
        )
}

/// The frame of [`derived_tangents`]: the tangent (xyz) and bitangent sign (w) from the fine
/// derivatives of position and uv across the pixel quad.
const DERIVED_TANGENT_WGSL: &str = "\
fn mg_derived_frame(n: vec3<f32>, p: vec3<f32>, uv: vec2<f32>) -> vec4<f32> {
    let dp1 = dpdxFine(p);
    let dp2 = dpdyFine(p);
    let duv1 = dpdxFine(uv);
    let duv2 = dpdyFine(uv);
    let dp2perp = cross(dp2, n);
    let dp1perp = cross(n, dp1);
    let t = dp2perp * duv1.x + dp1perp * duv2.x;
    let b = dp2perp * duv1.y + dp1perp * duv2.y;
    return vec4<f32>(mg_tangent(n, t), select(-1.0, 1.0, dot(cross(n, t), b) >= 0.0));
}

";

/// Which plan outputs play which role (indices into the module's outputs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Roles {
    /// `color`: radiance per light, summed over the lights.
    pub color: Option<usize>,
    /// `emission`, or the first output when there is neither `color` nor `emission`.
    pub emission: Option<usize>,
    /// `alpha`: coverage in [0, 1].
    pub alpha: Option<usize>,
    /// `displacement`: world-space vertex offset (vec3).
    pub displacement: Option<usize>,
}

/// The roles of `outputs`, by name (docs/rendering.md).
pub fn roles<'a>(names: impl IntoIterator<Item = &'a str>) -> Roles {
    let names: Vec<&str> = names.into_iter().collect();
    let find = |n: &str| names.iter().position(|m| *m == n);
    let mut r = Roles {
        color: find("color"),
        emission: find("emission"),
        alpha: find("alpha"),
        displacement: find("displacement"),
    };
    if r.color.is_none() && r.emission.is_none() {
        r.emission = names
            .iter()
            .position(|n| *n != "alpha" && *n != "displacement");
    }
    r
}

/// Emits the frame and light declarations, the two entries and the default hooks.
pub(super) fn emit_entries(
    out: &mut String,
    attributes: &[Attribute],
    outputs: &[ShaderOutput],
    bindings: &mut Vec<(u32, Binding)>,
    hoisted: bool,
) {
    let roles = roles(outputs.iter().map(|o| o.name.as_str()));
    let has = |a: Attribute| attributes.contains(&a);
    let call = if attributes.is_empty() {
        "mg_material()"
    } else {
        "mg_material(g)"
    };
    out.push_str(FRAME_WGSL);
    let _ = writeln!(
        out,
        "\n@group(0) @binding({FRAME_BINDING}) var<uniform> mg_frame: MgFrame;\n\
         @group(0) @binding({LIGHTS_BINDING}) var<storage, read> mg_lights: array<MgLight>;\n"
    );
    bindings.push((FRAME_BINDING, Binding::Frame));
    bindings.push((LIGHTS_BINDING, Binding::Lights));
    let tangents = uses_tangents(attributes);
    out.push_str(
        "struct MgVertexIn {\n    @location(0) position: vec3<f32>,\n    @location(1) normal: vec3<f32>,\n    @location(2) uv: vec2<f32>,\n",
    );
    if tangents {
        // The second vertex buffer (docs/integration.md): MikkTSpace tangent and sign.
        out.push_str("    @location(3) tangent: vec4<f32>,\n");
    }
    out.push_str("}\n\n");
    out.push_str(if tangents {
        VERTEX_OUT_TANGENT_WGSL
    } else {
        VERTEX_OUT_WGSL
    });
    // f32::MAX as its shortest f64 decimal (3.4028235e38 reads above f32's range in WGSL).
    let _ = writeln!(
        out,
        "const MG_NORMAL_STEP: f32 = {};\nconst MG_F32_MAX: f32 = {};\n",
        super::emit::float_literal(NORMAL_STEP),
        super::emit::float_literal(f32::MAX)
    );

    // The geometry every attribute starts from: the CPU's defaults.
    if !attributes.is_empty() {
        out.push_str("fn mg_default_geometry() -> MgGeometry {\n    var g: MgGeometry;\n");
        for &a in attributes {
            let _ = writeln!(out, "    g.{} = {};", a.name(), literal(&a.default_value()));
        }
        out.push_str("    return g;\n}\n\n");
    }

    // The displaced position of a vertex.
    if let Some(d) = roles.displacement {
        let field = &outputs[d].field;
        out.push_str("fn mg_displaced(p: vec3<f32>, n: vec3<f32>, uv: vec2<f32>) -> vec3<f32> {\n");
        if attributes.is_empty() {
            let _ = writeln!(out, "    return p + {call}.{field};\n}}\n");
        } else {
            out.push_str("    var g = mg_default_geometry();\n");
            for (a, e) in [
                (Attribute::Position, "p"),
                (Attribute::Normal, "n"),
                (Attribute::Uv, "uv"),
            ] {
                if has(a) {
                    let _ = writeln!(out, "    g.{} = {e};", a.name());
                }
            }
            let _ = writeln!(out, "    return p + {call}.{field};\n}}\n");
        }
    }

    out.push_str(
        "@vertex\nfn mg_vertex(v: MgVertexIn) -> MgVertexOut {\n\
         \x20   let p = (mg_frame.model * vec4<f32>(v.position, 1.0)).xyz;\n\
         \x20   let n0 = (mg_frame.normal_model * vec4<f32>(v.normal, 0.0)).xyz;\n\
         \x20   let n = select(vec3<f32>(0.0, 0.0, 1.0), normalize(n0), dot(n0, n0) > 0.0);\n\
         \x20   var o: MgVertexOut;\n",
    );
    if roles.displacement.is_some() {
        out.push_str(DISPLACE_VERTEX_WGSL);
    } else {
        out.push_str(PASS_VERTEX_WGSL);
    }
    if tangents {
        // A direction on the surface: the model matrix, not the normal matrix.
        out.push_str(
            "    o.tangent = vec4<f32>((mg_frame.model * vec4<f32>(v.tangent.xyz, 0.0)).xyz, v.tangent.w);\n",
        );
    }
    out.push_str(
        "    o.uv = v.uv;\n    o.clip = mg_frame.view_proj * vec4<f32>(o.position, 1.0);\n    return o;\n}\n\n",
    );
    if tangents {
        out.push_str(TANGENT_WGSL);
    }

    // The light arriving at a point: direction towards the light, radiance and distance.
    let _ = writeln!(
        out,
        "struct MgIncident {{\n    to_light: vec3<f32>,\n    radiance: vec3<f32>,\n    distance: f32,\n}}\n\n\
         fn mg_incident(light: MgLight, p: vec3<f32>) -> MgIncident {{\n\
         \x20   var r: MgIncident;\n\
         \x20   if (light.kind == {LIGHT_POINT}u) {{\n\
         \x20       let to = light.vector - p;\n\
         \x20       let dist = length(to);\n\
         \x20       r.to_light = select(vec3<f32>(0.0, 1.0, 0.0), to / dist, dist > 0.0);\n\
         \x20       let d = max(dist, {});\n\
         \x20       r.radiance = light.color / (d * d);\n\
         \x20       r.distance = dist;\n\
         \x20       return r;\n\
         \x20   }}\n\
         \x20   let l = light.vector;\n\
         \x20   r.to_light = select(vec3<f32>(0.0, 1.0, 0.0), normalize(l), dot(l, l) > 0.0);\n\
         \x20   r.radiance = light.color;\n\
         \x20   r.distance = MG_F32_MAX;\n\
         \x20   return r;\n}}\n",
        super::emit::float_literal(LIGHT_MIN_DISTANCE)
    );

    if has(Attribute::Reflection) {
        out.push_str(REFLECTION_WGSL);
    }
    if has(Attribute::Window) {
        out.push_str(WINDOW_WGSL);
    }

    // The fragment entry.
    out.push_str(
        "@fragment\nfn mg_fragment(v: MgVertexOut) -> @location(0) vec4<f32> {\n\
         \x20   let n0 = v.normal;\n\
         \x20   let n = select(vec3<f32>(0.0, 0.0, 1.0), normalize(n0), dot(n0, n0) > 0.0);\n\
         \x20   let count = min(mg_frame.light_count, arrayLength(&mg_lights));\n",
    );
    if !attributes.is_empty() {
        out.push_str("    var g = mg_default_geometry();\n");
    }
    for &a in attributes {
        let e = match a {
            Attribute::Position => "v.position".to_owned(),
            Attribute::Normal => "n".to_owned(),
            Attribute::View => VIEW_WGSL.to_owned(),
            // Without lights: towards +y, no radiance (the CPU G-buffer's convention).
            Attribute::Light => "vec3<f32>(0.0, 1.0, 0.0)".to_owned(),
            Attribute::LightColor => "vec3<f32>(0.0)".to_owned(),
            Attribute::Uv => "v.uv".to_owned(),
            Attribute::ScreenUv => "v.clip.xy / mg_frame.viewport".to_owned(),
            Attribute::Depth => "mg_surface_depth(v.position)".to_owned(),
            // The fine derivatives (the difference across the pixel's 2 × 2 quad along its row,
            // column): the same on every GPU, where `dpdx` may be coarse or fine. Uniform control
            // flow: the entry's top.
            Attribute::UvDx => "dpdxFine(v.uv)".to_owned(),
            Attribute::UvDy => "dpdyFine(v.uv)".to_owned(),
            Attribute::PositionDx => "dpdxFine(v.position)".to_owned(),
            Attribute::PositionDy => "dpdyFine(v.position)".to_owned(),
            Attribute::Tangent => "mg_tangent(n, v.tangent.xyz)".to_owned(),
            Attribute::BitangentSign => "select(-1.0, 1.0, v.tangent.w >= 0.0)".to_owned(),
            // Cycles' svm_node_tex_coord: 2 (N · V) N − V.
            Attribute::Reflection => format!("mg_reflection(n, {VIEW_WGSL})"),
            // Blender's window: (0, 0) bottom left; through the screen position's expression
            // (which the rasteriser replaces with the frame's).
            Attribute::Window => "mg_window(v.clip.xy / mg_frame.viewport)".to_owned(),
            Attribute::Generated => "mg_generated(v.position)".to_owned(),
            Attribute::Camera => "mg_camera(v.position)".to_owned(),
            Attribute::Time => continue,
        };
        let _ = writeln!(out, "    g.{} = {e};", a.name());
    }
    let set_light = |out: &mut String, index: &str| {
        let _ = writeln!(
            out,
            "        let inc = mg_incident(mg_lights[{index}], v.position);\n\
             \x20       let vis = mg_light_visibility({index}, v.position, inc.to_light, inc.distance);"
        );
        if has(Attribute::Light) {
            out.push_str("        g.light = inc.to_light;\n");
        }
        if has(Attribute::LightColor) {
            out.push_str("        g.light_color = inc.radiance * vis;\n");
        }
    };
    out.push_str("    var radiance = vec3<f32>(0.0);\n");
    if let Some(c) = roles.color {
        // Per light, summed; emission and alpha from the last light's evaluation, as on the CPU.
        // One evaluation per light, and one without any (the unlit outputs): not one more
        // before the loop, which doubled the material's cost under one light. Hoisted, the
        // calls that do not read the light run once, before the loop.
        let call = if hoisted {
            out.push_str("    let u = mg_material_unlit(g);\n");
            "mg_material_lit(g, u)"
        } else {
            call
        };
        let _ = writeln!(
            out,
            "    var o: MgOutputs;\n    if (count == 0u) {{\n        o = {call};\n    }}"
        );
        out.push_str("    for (var i = 0u; i < count; i += 1u) {\n");
        set_light(out, "i");
        let _ = writeln!(out, "        o = {call};");
        let e = format!("o.{}", outputs[c].field);
        let _ = writeln!(
            out,
            "        radiance += {};\n    }}",
            rgb(&e, outputs[c].ty)
        );
    } else {
        // Unlit: one evaluation, with the first light set (the CPU G-buffer's light).
        out.push_str("    if (count > 0u) {\n");
        set_light(out, "0u");
        out.push_str("    }\n");
        let _ = writeln!(out, "    let o = {call};");
    }
    if let Some(e) = roles.emission {
        let x = format!("o.{}", outputs[e].field);
        let _ = writeln!(out, "    radiance += {};", rgb(&x, outputs[e].ty));
    }
    match roles.alpha {
        Some(a) => {
            let x = format!("o.{}", outputs[a].field);
            let x = match outputs[a].ty.width() {
                1 => convert(&x, outputs[a].ty, SocketType::Float),
                _ => format!("{x}.x"),
            };
            // Non-finite alpha is 0, else clamped to [0, 1].
            let _ = writeln!(
                out,
                "    let a0 = {x};\n    let alpha = select(0.0, clamp(a0, 0.0, 1.0), abs(a0) <= MG_F32_MAX);"
            );
        }
        None => out.push_str("    let alpha = 1.0;\n"),
    }
    out.push_str(
        "    // Non-finite radiance counts as black.\n\
         \x20   let finite = all(abs(radiance) <= vec3<f32>(MG_F32_MAX));\n\
         \x20   let c = select(vec3<f32>(0.0), radiance, finite);\n\
         \x20   return vec4<f32>(c * alpha, alpha);\n}\n\n",
    );
    out.push_str(DEFAULT_HOOKS_WGSL);
}

/// Whether a module reading `attributes` takes the tangent vertex buffer (location 3).
pub fn uses_tangents(attributes: &[Attribute]) -> bool {
    attributes
        .iter()
        .any(|a| matches!(a, Attribute::Tangent | Attribute::BitangentSign))
}

/// `e` of type `ty` as RGB: vectors of three or more lanes by their first three, scalars grey.
fn rgb(e: &str, ty: SocketType) -> String {
    match ty.width() {
        3 => e.to_owned(),
        4 => format!("{e}.xyz"),
        2 => format!("vec3<f32>({e}.x)"),
        _ => convert(e, ty, SocketType::Color),
    }
}
