//! The material surface as an app of the documented contract ([`crate::material::Material`],
//! docs/integration.md): the render module's `mg_vertex` and `mg_fragment` with the scene's
//! hooks (shadows from the scene's casters, the water depth), its group 0 (parameters,
//! `MgFrame`, lights, textures in either mode), and the library module's `mg_material`
//! called from a compute pass that displaces the vertices once per frame (the CPU's order:
//! displacement at the vertices, then the welded normals of `normals.wgsl`).

use super::{COLOR, DEPTH};
use crate::gpu::device::DeviceState;
use crate::material::{Frame, Light, Material};
use crate::node::Attribute;
use crate::scene::{CameraFrame, Scene, Viewport};
use glam::{Mat4, Vec4};

/// The scene's definitions of the contract's hooks, with `scene.wgsl` (group 1) that they
/// read: a light is visible where none of the scene's own casters stands between
/// (columns.rs light_at), the `depth` attribute is the water depth, `generated` the
/// position in the surface's texture space (`Scene::generated`) and `camera` in the camera's
/// frame (as the CPU G-buffer); for a scene with
/// `features`.
pub(super) fn hooks(features: &crate::scene::SceneFeatures) -> String {
    format!(
        "{}\n\
         fn mg_light_visibility(index: u32, position: vec3<f32>, to_light: vec3<f32>, distance: f32) -> f32 {{\n\
         \x20   let count = mgr_frame.counts.z;\n\
         \x20   if (count == 0u || mgr_lit(count, 0xffffffffu, position, vec3<f32>(0.0), to_light, distance)) {{\n\
         \x20       return 1.0;\n\
         \x20   }}\n\
         \x20   return 0.0;\n\
         }}\n\n\
         fn mg_surface_depth(position: vec3<f32>) -> f32 {{\n\
         \x20   return mgr_water_depth(position);\n\
         }}\n\n\
         fn mg_generated(position: vec3<f32>) -> vec3<f32> {{\n\
         \x20   return vec3<f32>(0.5) + (position - mgr_frame.tex_center.xyz) / (2.0 * mgr_frame.tex_half.xyz);\n\
         }}\n\n\
         fn mg_camera(position: vec3<f32>) -> vec3<f32> {{\n\
         \x20   let d = position - mgr_frame.origin;\n\
         \x20   return vec3<f32>(dot(d, mgr_frame.right), dot(d, mgr_frame.up), dot(d, mgr_frame.forward));\n\
         }}\n",
        super::scene_source(features)
    )
}

/// The header of the contract's fragment entry, as generated.
const FRAGMENT_HEADER: &str =
    "@fragment\nfn mg_fragment(v: MgVertexOut) -> @location(0) vec4<f32> {";

/// The hooked render module `source` for MSAA: `mg_fragment`'s body as a function
/// `mg_shade(v: MgVertexOut) -> vec4<f32>` (the same shading), called by an entry that
/// rebuilds the varyings at each sample from the CPU's barycentrics (`mgr_barycentrics`: the
/// eye ray through the sample meets the triangle), reading the vertex buffer and the indices
/// as storage (group 2). Lavapipe's `@interpolate(perspective, sample)` at 4 samples misses
/// the sample positions (measured: toon_ball's ramp steps move, 99.1 % of pixels within
/// 2/255 against the 99.9 % required), so the contract's interpolation serves 1 sample only.
pub(super) fn sample_source(source: &str) -> Option<String> {
    if !source.contains(FRAGMENT_HEADER) {
        return None;
    }
    // The uv derivatives as the CPU's G-buffer computes them (mgr_uv_derivatives): the
    // hardware's fine derivatives under per-sample shading are not the 2 × 2 quad's of pixel
    // centres (measured on lavapipe: water_sunshine at 4 samples, RMSE 15/255).
    let shade = source
        .replacen(
            FRAGMENT_HEADER,
            "var<private> mgr_uv_d: vec4<f32>;\n\nfn mg_shade(v: MgVertexOut) -> vec4<f32> {",
            1,
        )
        .replace("dpdxFine(v.uv)", "mgr_uv_d.xy")
        .replace("dpdyFine(v.uv)", "mgr_uv_d.zw");
    // The position's derivatives likewise (the bump node's offsets), where the module reads them.
    let positions =
        shade.contains("dpdxFine(v.position)") || shade.contains("dpdyFine(v.position)");
    let shade = if positions {
        shade
            .replacen(
                "fn mg_shade(",
                "var<private> mgr_p_d: MgrPositionDerivatives;\n\nfn mg_shade(",
                1,
            )
            .replace("dpdxFine(v.position)", "mgr_p_d.dx")
            .replace("dpdyFine(v.position)", "mgr_p_d.dy")
    } else {
        shade
    };
    let tangents = reads_tangents(source);
    let entry = format!(
        "enable primitive_index;\n{shade}\n{}",
        r#"
// The material's vertex buffer (8 floats per vertex: position, normal, uv) and indices.
@group(2) @binding(0) var<storage, read> mgr_mesh: array<f32>;
@group(2) @binding(1) var<storage, read> mgr_mesh_indices: array<u32>;

fn mgr_mesh_vec3(i: u32, at: u32) -> vec3<f32> {
    return vec3<f32>(mgr_mesh[8u * i + at], mgr_mesh[8u * i + at + 1u], mgr_mesh[8u * i + at + 2u]);
}

// A sample of the material: the G-buffer sample (gbuffer.rs material_batch: raster.rs
// interpolate at the CPU's barycentrics), shaded by the contract's mg_shade.
@fragment
fn mgr_material_sample_fs(
    @builtin(position) xy: vec4<f32>,
    @builtin(sample_index) sample: u32,
    @builtin(primitive_index) prim: u32,
) -> @location(0) vec4<f32> {
    let i0 = mgr_mesh_indices[3u * prim];
    let i1 = mgr_mesh_indices[3u * prim + 1u];
    let i2 = mgr_mesh_indices[3u * prim + 2u];
    let p0 = mgr_mesh_vec3(i0, 0u);
    let p1 = mgr_mesh_vec3(i1, 0u);
    let p2 = mgr_mesh_vec3(i2, 0u);
    let bc = mgr_barycentrics(p0, p1, p2, xy.xy);
    let b0 = 1.0 - bc.x - bc.y;
    var v: MgVertexOut;
    v.clip = xy;
    v.position = p0 * b0 + p1 * bc.x + p2 * bc.y;
    v.normal = mgr_mesh_vec3(i0, 3u) * b0 + mgr_mesh_vec3(i1, 3u) * bc.x + mgr_mesh_vec3(i2, 3u) * bc.y;
    let uv0 = vec2<f32>(mgr_mesh[8u * i0 + 6u], mgr_mesh[8u * i0 + 7u]);
    let uv1 = vec2<f32>(mgr_mesh[8u * i1 + 6u], mgr_mesh[8u * i1 + 7u]);
    let uv2 = vec2<f32>(mgr_mesh[8u * i2 + 6u], mgr_mesh[8u * i2 + 7u]);
    v.uv = uv0 * b0 + uv1 * bc.x + uv2 * bc.y;
    mgr_uv_d = mgr_uv_derivatives(p0, p1, p2, uv0, uv1, uv2, vec2<u32>(xy.xy));
    // mgr-positions
    // mgr-tangent
    return mg_shade(v) + vec4<f32>(f32(sample) * 0.0);
}
"#
    );
    let entry = if positions {
        entry.replacen(
            "    // mgr-positions",
            "    mgr_p_d = mgr_position_derivatives(p0, p1, p2, vec2<u32>(xy.xy));",
            1,
        )
    } else {
        entry
    };
    if !tangents {
        return Some(entry);
    }
    // The tangent frame (world space: the material mesh is): the undisplaced mesh's
    // MikkTSpace tangents, interpolated as the varying would be.
    Some(entry.replacen(
        "    // mgr-tangent",
        "    v.tangent = mgr_mesh_tangents[i0] * b0 + mgr_mesh_tangents[i1] * bc.x + mgr_mesh_tangents[i2] * bc.y;",
        1,
    ) + "\n@group(2) @binding(2) var<storage, read> mgr_mesh_tangents: array<vec4<f32>>;\n")
}

/// Whether a render module `source` reads the tangent vertex buffer (its varyings carry the
/// tangent frame).
pub(super) fn reads_tangents(source: &str) -> bool {
    source.contains("@location(3) tangent: vec4<f32>")
}

/// World → clip of the camera as the scene passes project (`mgr_clip_position`): x and y
/// over `tan(fov/2)` (times the aspect for x), z the constant `near`, w the view depth, so
/// that the depth `near / w` grows towards the eye and `z ≤ w` clips at the near plane.
pub(super) fn view_proj(cam: &CameraFrame) -> Mat4 {
    let (sx, sy) = (1.0 / (cam.tan_half_y * cam.aspect), 1.0 / cam.tan_half_y);
    let (r, u, f, o) = (cam.right, cam.up, cam.forward, cam.origin);
    // Rows of the matrix, as columns of its transpose.
    Mat4::from_cols(
        Vec4::new(r.x * sx, r.y * sx, r.z * sx, -r.dot(o) * sx),
        Vec4::new(u.x * sy, u.y * sy, u.z * sy, -u.dot(o) * sy),
        Vec4::new(0.0, 0.0, 0.0, cam.near),
        Vec4::new(f.x, f.y, f.z, -f.dot(o)),
    )
    .transpose()
}

/// [`view_proj`] for the tile (and jittered sample) `view` of a `w × h` frame: rows 0 and 1
/// replaced by `sx·row0 + tx·row3` and `sy·row1 + ty·row3` ([`Viewport::tile_clip`]), the
/// affine map that `mgr_clip_position` applies to the scene's clip positions.
pub(super) fn tile_view_proj(cam: &CameraFrame, view: &Viewport, w: u32, h: u32) -> Mat4 {
    let [sx, tx, sy, ty] = view.tile_clip(w, h);
    let m = view_proj(cam);
    let (r0, r1, r2, r3) = (m.row(0), m.row(1), m.row(2), m.row(3));
    Mat4::from_cols(r0 * sx + r3 * tx, r1 * sy + r3 * ty, r2, r3).transpose()
}

/// The contract's per-draw uniform of the pass `view` of `scene` at `w × h`, and the
/// lights. `viewport` stays the whole frame's; the tile's offset is added to `screen_uv` by
/// the hooked module (`mgr_screen_uv`).
pub(super) fn frame_and_lights(
    scene: &Scene,
    w: u32,
    h: u32,
    view: &Viewport,
) -> (Vec<u8>, Vec<u8>) {
    let cam = scene.camera.frame(w, h);
    let lights: Vec<Light> = scene.lights.iter().map(Light::from_scene).collect();
    let frame = Frame {
        view_proj: tile_view_proj(&cam, view, w, h),
        model: Mat4::IDENTITY,
        camera_position: cam.origin,
        viewport: [w as f32, h as f32],
    };
    (
        frame.bytes(lights.len() as u32),
        crate::material::lights_bytes(&lights),
    )
}

/// The material's render pipeline: `mg_vertex` over the contract's vertex buffer and
/// `fragment` into the material target (none: depth only, the pre-pass), the depth test
/// `(compare, write)` on `near / w` (greater is nearer) against the scene's depth, no
/// blending (the resolve composites).
pub(super) fn pipeline(
    s: &DeviceState,
    module: &wgpu::ShaderModule,
    fragment: Option<&str>,
    layout: &wgpu::PipelineLayout,
    samples: u32,
    (compare, write): (wgpu::CompareFunction, bool),
    tangents: bool,
) -> wgpu::RenderPipeline {
    let vertex = Material::vertex_buffer_layout();
    let tangent = crate::material::tangent_buffer_layout();
    let buffers = [Some(vertex), Some(tangent)];
    let buffers = if tangents {
        &buffers[..]
    } else {
        &buffers[..1]
    };
    let targets = [Some(wgpu::ColorTargetState {
        format: COLOR,
        blend: None,
        write_mask: wgpu::ColorWrites::ALL,
    })];
    s.device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("mgr material"),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some("mg_vertex"),
                compilation_options: Default::default(),
                buffers,
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH,
                depth_write_enabled: Some(write),
                depth_compare: Some(compare),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState {
                count: samples,
                mask: !0,
                alpha_to_coverage_enabled: false,
            },
            fragment: fragment.map(|fs| wgpu::FragmentState {
                module,
                entry_point: Some(fs),
                compilation_options: Default::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        })
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

/// The displacement pass, appended to the library module (`mg_material` over every output,
/// group 0): every vertex moved by the graph's `displacement` (member `field`) at its
/// position, normal and uv (the other attributes at their defaults), as
/// `render::render_timed` stage 1 does on the CPU.
pub(super) fn displacement_source(library: &str, attributes: &[Attribute], field: &str) -> String {
    let mut s = library.to_owned();
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
    let call = if attributes.is_empty() {
        "mg_material()"
    } else {
        s.push_str("    var geom: MgGeometry;\n");
        "mg_material(geom)"
    };
    for a in attributes {
        let e = match a {
            Attribute::Position => "a.xyz".to_owned(),
            Attribute::Normal => "b.xyz".to_owned(),
            Attribute::Uv => "vec2<f32>(a.w, b.w)".to_owned(),
            a => default_literal(*a),
        };
        s.push_str(&format!("    geom.{} = {e};\n", a.name()));
    }
    s.push_str(&format!(
        "    let o = {call};\n    mgr_displaced[i] = vec4<f32>(a.xyz + o.{field}, 1.0);\n}}\n"
    ));
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Camera;
    use glam::Vec3;

    /// SplitMix64 (Steele, Lea & Flood 2014): seeded draws in [lo, hi).
    struct Rng(u64);
    impl Rng {
        fn uniform(&mut self, lo: f32, hi: f32) -> f32 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            lo + (hi - lo) * ((z >> 40) as f32 / (1u64 << 24) as f32)
        }
    }

    /// The matrix projects as the CPU's `CameraFrame::project` (f64) does, to pixels, and its
    /// depth `z / w` is `near / view depth`: preset cameras and seeded ones, at seeded points
    /// in front of the camera and at round ones.
    #[test]
    fn view_proj_projects_as_the_cpu_camera() {
        let mut rng = Rng(0x5eed_0010);
        let mut cameras: Vec<Camera> = ["ball", "water"]
            .iter()
            .map(|p| crate::scene::Scene::preset(p).unwrap().camera)
            .collect();
        for _ in 0..8 {
            cameras.push(Camera {
                position: [0; 3].map(|_| rng.uniform(-4.0, 4.0)),
                target: [0; 3].map(|_| rng.uniform(-1.0, 1.0)),
                fov_y_deg: rng.uniform(20.0, 90.0),
                near: rng.uniform(0.01, 0.2),
            });
        }
        for cam in cameras {
            let (w, h) = (640, 360);
            let f = cam.frame(w, h);
            let m = view_proj(&f);
            let mut points: Vec<Vec3> = vec![Vec3::ZERO, Vec3::new(0.5, 0.25, -0.5)];
            for _ in 0..64 {
                points.push(Vec3::new(
                    rng.uniform(-2.0, 2.0),
                    rng.uniform(-2.0, 2.0),
                    rng.uniform(-2.0, 2.0),
                ));
            }
            for p in points {
                let depth = (p - f.origin).dot(f.forward);
                let Some((px, py)) = f.project(p) else {
                    continue;
                };
                let c = m * p.extend(1.0);
                let (x, y) = (
                    (0.5 + 0.5 * (c.x / c.w) as f64) * w as f64,
                    (0.5 - 0.5 * (c.y / c.w) as f64) * h as f64,
                );
                // Pixels: the matrix rounds in f32 (|p|, |origin| up to 7 m).
                let tol = 1e-4 * (1.0 + px.abs().max(py.abs()));
                assert!(
                    (x - px).abs() < tol && (y - py).abs() < tol,
                    "{cam:?} {p}: ({x}, {y}) against ({px}, {py})"
                );
                let want = cam.near as f64 / depth as f64;
                assert!(
                    ((c.z / c.w) as f64 - want).abs() <= 1e-5 * want,
                    "{cam:?} {p}: depth {} against {want}",
                    c.z / c.w
                );
            }
        }
    }
}
