//! The material surface's shaders: the graph's generated module (its `mg_material`
//! function, parameters and textures in bind group 0) with the rasteriser's entry points
//! appended — the displacement compute pass, and the vertex and fragment stages with the
//! light loop.

use crate::node::Attribute;
use crate::types::SocketType;
use crate::wgsl::ShaderModule;

/// The `MgOutputs` members of a generated module, in output order.
pub(super) fn output_fields(shader: &ShaderModule) -> Vec<String> {
    let src = &shader.source;
    let Some(start) = src.find("struct MgOutputs {") else {
        return Vec::new();
    };
    src[start..]
        .lines()
        .skip(1)
        .take_while(|l| l.trim() != "}")
        .filter_map(|l| l.trim().split(':').next().map(str::to_owned))
        .collect()
}

/// WGSL of an output member as RGB (a float, int or bool as grey), as `render::rgb` reads it.
fn rgb(e: &str, ty: SocketType) -> String {
    match ty {
        SocketType::Vec3 | SocketType::Color => e.to_owned(),
        SocketType::Float => format!("vec3<f32>({e})"),
        SocketType::Int => format!("vec3<f32>(f32({e}))"),
        SocketType::Bool => format!("vec3<f32>(select(0.0, 1.0, {e}))"),
        SocketType::Vec2 => format!("vec3<f32>({e}.x)"),
        SocketType::Vec4 => format!("{e}.xyz"),
    }
}

/// WGSL of an output member as a float.
fn float(e: &str, ty: SocketType) -> String {
    match ty {
        SocketType::Float => e.to_owned(),
        SocketType::Int => format!("f32({e})"),
        SocketType::Bool => format!("select(0.0, 1.0, {e})"),
        _ => format!("{e}.x"),
    }
}

/// A WGSL literal of an attribute's default value.
fn default_literal(a: Attribute) -> String {
    let lanes: Vec<String> = a
        .default_value()
        .lanes()
        .iter()
        .map(|v| format!("{v:?}"))
        .collect();
    match lanes.len() {
        1 => lanes[0].clone(),
        n => format!("vec{n}<f32>({})", lanes.join(", ")),
    }
}

/// The graph's roles in the fragment module: (member, type) of color, emission, alpha.
pub(super) struct FragmentRoles {
    pub color: Option<(String, SocketType)>,
    pub emission: Option<(String, SocketType)>,
    pub alpha: Option<(String, SocketType)>,
}

/// The material's vertex and fragment stages, appended to its generated module: group 1 is
/// the scene (`scene.wgsl`), group 2 the mesh (displaced positions, rebuilt normals, uvs).
pub(super) fn fragment_source(shader: &ShaderModule, roles: &FragmentRoles) -> String {
    let mut s = format!("enable primitive_index;\n{}\n", shader.source);
    s.push_str(&super::scene_source());
    s.push_str(
        r#"
@group(2) @binding(0) var<storage, read> mgr_mesh_positions: array<vec4<f32>>;
@group(2) @binding(1) var<storage, read> mgr_mesh_normals: array<vec4<f32>>;
@group(2) @binding(2) var<storage, read> mgr_mesh_uvs: array<vec2<f32>>;
@group(2) @binding(3) var<storage, read> mgr_mesh_indices: array<u32>;

@vertex
fn mgr_material_vs(@builtin(vertex_index) k: u32) -> @builtin(position) vec4<f32> {
    return mgr_clip_position(mgr_mesh_positions[k].xyz);
}

// The G-buffer sample (gbuffer.rs material_batch: raster.rs interpolate at the CPU's
// barycentrics), the light loop and the composite's radiance and alpha (render/mod.rs
// shade_band): radiance in rgb, alpha in a. Per sample (sample_index is read).
@fragment
fn mgr_material_fs(
    @builtin(position) xy: vec4<f32>,
    @builtin(sample_index) sample: u32,
    @builtin(primitive_index) prim: u32,
) -> @location(0) vec4<f32> {
    let i0 = mgr_mesh_indices[3u * prim];
    let i1 = mgr_mesh_indices[3u * prim + 1u];
    let i2 = mgr_mesh_indices[3u * prim + 2u];
    let p0 = mgr_mesh_positions[i0].xyz;
    let p1 = mgr_mesh_positions[i1].xyz;
    let p2 = mgr_mesh_positions[i2].xyz;
    let bc = mgr_barycentrics(p0, p1, p2, xy.xy);
    let b0 = 1.0 - bc.x - bc.y;
    let p = p0 * b0 + p1 * bc.x + p2 * bc.y;
    let n0 = mgr_mesh_normals[i0].xyz;
    var n = n0 * b0 + mgr_mesh_normals[i1].xyz * bc.x + mgr_mesh_normals[i2].xyz * bc.y;
    let len2 = dot(n, n);
    if (len2 > 0.0) {
        n = n * inverseSqrt(len2);
    } else {
        n = n0;
    }
    let uv0 = mgr_mesh_uvs[i0];
    let uv = uv0 * b0 + mgr_mesh_uvs[i1] * bc.x + mgr_mesh_uvs[i2] * bc.y;
    let screen_uv = mgr_screen_uv(xy.xy) + vec2<f32>(f32(sample) * 0.0);
    var view = mgr_frame.origin - p;
    let vl2 = dot(view, view);
    if (vl2 > 0.0) {
        view = view * inverseSqrt(vl2);
    } else {
        view = n;
    }
    let lights = mgr_frame.counts.x;
    var light = vec3<f32>(0.0, 1.0, 0.0);
    var light_color = vec3<f32>(0.0);
    if (lights > 0u) {
        let first = mgr_light_at(0u, p);
        light = first.l;
        light_color = first.radiance;
    }
"#,
    );
    let has = |a: Attribute| shader.attributes.contains(&a);
    if has(Attribute::UvDx) || has(Attribute::UvDy) {
        s.push_str(
            "    let uv_d = mgr_uv_derivatives(p0, p1, p2, uv0, mgr_mesh_uvs[i1], mgr_mesh_uvs[i2], vec2<u32>(xy.xy));\n",
        );
    }
    let call = if shader.attributes.is_empty() {
        "mg_material()"
    } else {
        "mg_material(geom)"
    };
    if !shader.attributes.is_empty() {
        s.push_str("    var geom: MgGeometry;\n");
    }
    for a in &shader.attributes {
        let e = match a {
            Attribute::Position => "p".to_owned(),
            Attribute::Normal => "n".to_owned(),
            Attribute::View => "view".to_owned(),
            Attribute::Uv => "uv".to_owned(),
            Attribute::ScreenUv => "screen_uv".to_owned(),
            Attribute::Depth => "mgr_water_depth(p)".to_owned(),
            Attribute::Light => "light".to_owned(),
            Attribute::LightColor => "light_color".to_owned(),
            Attribute::UvDx => "uv_d.xy".to_owned(),
            Attribute::UvDy => "uv_d.zw".to_owned(),
            a => default_literal(*a),
        };
        s.push_str(&format!("    geom.{} = {e};\n", a.name()));
    }
    s.push_str("    var c = vec3<f32>(0.0);\n    var o: MgOutputs;\n");
    let unlit = roles.emission.is_some() || roles.alpha.is_some();
    if let Some((f, ty)) = &roles.color {
        s.push_str("    for (var i = 0u; i < lights; i++) {\n");
        s.push_str("        let inc = mgr_light_at(i, p);\n");
        if has(Attribute::Light) {
            s.push_str("        geom.light = inc.l;\n");
        }
        if has(Attribute::LightColor) {
            s.push_str("        geom.light_color = inc.radiance;\n");
        }
        s.push_str(&format!("        o = {call};\n"));
        s.push_str(&format!(
            "        c += {};\n    }}\n",
            rgb(&format!("o.{f}"), *ty)
        ));
        if unlit {
            // The unlit outputs see the last light's columns, as on the CPU.
            s.push_str(&format!(
                "    if (lights == 0u) {{\n        o = {call};\n    }}\n"
            ));
        }
    } else if unlit {
        s.push_str(&format!("    o = {call};\n"));
    }
    if let Some((f, ty)) = &roles.emission {
        s.push_str(&format!("    c += {};\n", rgb(&format!("o.{f}"), *ty)));
    }
    s.push_str("    var alpha = 1.0;\n");
    if let Some((f, ty)) = &roles.alpha {
        s.push_str(&format!(
            "    let a = {};\n    alpha = select(0.0, clamp(a, 0.0, 1.0), mgr_finite(a));\n",
            float(&format!("o.{f}"), *ty)
        ));
    }
    s.push_str(
        "    if (!(mgr_finite(c.x) && mgr_finite(c.y) && mgr_finite(c.z))) {\n        c = vec3<f32>(0.0);\n    }\n",
    );
    s.push_str("    return vec4<f32>(c, alpha);\n}\n");
    s
}

/// The displacement pass, appended to the module generated for the `displacement` output:
/// every vertex moved by the graph's offset at its position, normal and uv (the other
/// attributes at their defaults), as `render::render_timed` stage 1 does on the CPU.
pub(super) fn displacement_source(shader: &ShaderModule, member: &str) -> String {
    let mut s = shader.source.clone();
    s.push_str(
        r#"
// Per vertex: (position, u) and (normal, v).
@group(1) @binding(0) var<storage, read> mgr_vertices: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read_write> mgr_displaced: array<vec4<f32>>;
// Vertices, invocations per dispatch row.
@group(1) @binding(2) var<uniform> mgr_count: vec4<u32>;

@compute @workgroup_size(64)
fn mgr_displace(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x + id.y * mgr_count.y;
    if (i >= mgr_count.x) {
        return;
    }
    let a = mgr_vertices[2u * i];
    let b = mgr_vertices[2u * i + 1u];
"#,
    );
    let call = if shader.attributes.is_empty() {
        "mg_material()"
    } else {
        s.push_str("    var geom: MgGeometry;\n");
        "mg_material(geom)"
    };
    for a in &shader.attributes {
        let e = match a {
            Attribute::Position => "a.xyz".to_owned(),
            Attribute::Normal => "b.xyz".to_owned(),
            Attribute::Uv => "vec2<f32>(a.w, b.w)".to_owned(),
            a => default_literal(*a),
        };
        s.push_str(&format!("    geom.{} = {e};\n", a.name()));
    }
    s.push_str(&format!(
        "    let o = {call};\n    mgr_displaced[i] = vec4<f32>(a.xyz + o.{member}, 1.0);\n}}\n"
    ));
    s
}
