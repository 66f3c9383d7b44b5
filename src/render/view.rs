//! A scene's view as an app draws it with the render module (`matgraph bake-env SOURCE
//! --view WxH`): the camera as a WebGPU `view_proj`, the lights as `MgLight` records and the
//! material mesh in the contract's vertex layout, so that an app in any language draws what
//! `matgraph render` shows (docs/integration.md, "A scene's view"). Schema `matgraph-view/1`.

use crate::scene::Scene;
use glam::{Mat4, Vec4};
use serde::Serialize;

/// The schema name written in every view file.
pub const VIEW_SCHEMA: &str = "matgraph-view/1";

/// The far plane of [`SceneView::view_proj`], metres: far beyond every preset scene.
pub const VIEW_FAR: f32 = 1000.0;

/// The file name of the mesh beside `view.json`.
pub const MESH_FILE: &str = "mesh.bin";

/// The file name of the scene's depth beside `view.json` ([`depth_bytes`]).
pub const DEPTH_FILE: &str = "depth.r32f";

/// One light as the lights buffer's record (`MgLight`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ViewLight {
    /// Direction towards a directional light, or a point light's position (m).
    pub vector: [f32; 3],
    /// 0 directional, 1 point (the contract's `lights.directional`, `lights.point`).
    pub kind: u32,
    /// Radiance (directional) or radiance at 1 m (point), linear RGB.
    pub color: [f32; 3],
}

/// Where the mesh is and how it is laid out.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ViewMesh {
    /// The file beside `view.json`.
    pub file: String,
    /// Vertices, each 32 bytes: position (3 f32), normal (3 f32), uv (2 f32), as the
    /// contract's `vertex_buffer`.
    pub vertices: u32,
    /// `u32` indices after the vertices, three per triangle, counter-clockwise seen from
    /// outside.
    pub indices: u32,
    /// Byte offset of the indices in the file (`32 · vertices`).
    pub index_offset: u64,
    /// Byte offset of the tangents (4 f32 per vertex: the MikkTSpace tangent and bitangent
    /// sign, the contract's `tangent_buffer`) after the indices.
    pub tangent_offset: u64,
}

/// The view of one scene at one image size.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SceneView {
    /// Always [`VIEW_SCHEMA`].
    pub schema: String,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// World → clip, column-major (16 numbers as WGSL reads `mat4x4<f32>`): the camera's
    /// perspective in WebGPU's clip space, depth 0 at `near` to 1 at [`VIEW_FAR`]; pixel
    /// centres project where `matgraph render` casts its rays.
    pub view_proj: [f32; 16],
    /// The near plane's distance, m.
    pub near: f32,
    /// The far plane's distance, m.
    pub far: f32,
    /// The eye, world space.
    pub camera_position: [f32; 3],
    /// The lights, in the scene's order.
    pub lights: Vec<ViewLight>,
    /// The scene's time in seconds (the parameter block's `time`).
    pub time: f32,
    /// The material mesh (undisplaced: the render module's `mg_vertex` displaces).
    pub mesh: ViewMesh,
    /// The file of the rest of the scene's depth ([`depth_bytes`]): `width · height`
    /// little-endian f32, rows from the top, each the depth (as `view_proj` gives it, 0 at
    /// `near` to 1 at `far`) of the nearest surface other than the material at the pixel's
    /// centre, 1 where there is none. Load it into the depth buffer before drawing the
    /// material: what is in front of the material hides it.
    pub depth: String,
}

impl SceneView {
    /// The view of `scene` at `width × height`.
    pub fn of(scene: &Scene, width: u32, height: u32) -> SceneView {
        let cam = scene.camera.frame(width, height);
        let (sx, sy) = (1.0 / (cam.tan_half_y * cam.aspect), 1.0 / cam.tan_half_y);
        let (r, u, f, o) = (cam.right, cam.up, cam.forward, cam.origin);
        let (n, far) = (cam.near, VIEW_FAR);
        // Rows: x and y over tan(fov/2) (x also over the aspect), w the view depth d, and
        // z = (d − n) · far / (far − n) so that z / w runs from 0 at d = n to 1 at d = far.
        let a = far / (far - n);
        let rows = [
            Vec4::new(r.x * sx, r.y * sx, r.z * sx, -r.dot(o) * sx),
            Vec4::new(u.x * sy, u.y * sy, u.z * sy, -u.dot(o) * sy),
            Vec4::new(f.x * a, f.y * a, f.z * a, (-f.dot(o) - n) * a),
            Vec4::new(f.x, f.y, f.z, -f.dot(o)),
        ];
        let view_proj = Mat4::from_cols(rows[0], rows[1], rows[2], rows[3]).transpose();
        let mesh = scene.material_mesh();
        let lights = scene
            .lights
            .iter()
            .map(|l| match crate::material::Light::from_scene(l) {
                crate::material::Light::Directional {
                    direction,
                    radiance,
                } => ViewLight {
                    vector: direction,
                    kind: crate::wgsl::render::LIGHT_DIRECTIONAL,
                    color: radiance,
                },
                crate::material::Light::Point { position, radiance } => ViewLight {
                    vector: position,
                    kind: crate::wgsl::render::LIGHT_POINT,
                    color: radiance,
                },
            })
            .collect();
        SceneView {
            schema: VIEW_SCHEMA.into(),
            width,
            height,
            view_proj: view_proj.to_cols_array(),
            near: n,
            far,
            camera_position: o.to_array(),
            lights,
            time: scene.time,
            depth: DEPTH_FILE.into(),
            mesh: ViewMesh {
                file: MESH_FILE.into(),
                vertices: mesh.positions.len() as u32,
                indices: 3 * mesh.indices.len() as u32,
                index_offset: 32 * mesh.positions.len() as u64,
                tangent_offset: 32 * mesh.positions.len() as u64 + 12 * mesh.indices.len() as u64,
            },
        }
    }

    /// Pretty JSON, newline-terminated: the same bytes for the same scene and size.
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).expect("a view serialises");
        s.push('\n');
        s
    }
}

/// The bytes of [`DEPTH_FILE`] for `scene` seen as `view` ([`SceneView::of`] the same
/// scene): per pixel, rows from the top, the depth `far/(far − near) · (1 − near/w)` that
/// `view_proj` gives the nearest surface of the scene without the material
/// ([`Scene::background_inv_depth`]), `w` its view depth; 1 where there is none.
/// Little-endian f32.
pub fn depth_bytes(scene: &Scene, view: &SceneView) -> Vec<u8> {
    let (n, a) = (view.near, view.far / (view.far - view.near));
    scene
        .background_inv_depth(view.width, view.height)
        .into_iter()
        .flat_map(|inv_w| {
            let depth = if inv_w > 0.0 {
                (a * (1.0 - n * inv_w)).clamp(0.0, 1.0)
            } else {
                1.0
            };
            depth.to_le_bytes()
        })
        .collect()
}

/// The bytes of [`MESH_FILE`] for `scene`: its material mesh's vertices (32 bytes each,
/// little-endian f32 position, normal, uv), its indices (little-endian u32), then its
/// MikkTSpace tangents (16 bytes each, as `matgraph render` computes them).
pub fn mesh_bytes(scene: &Scene) -> Vec<u8> {
    let mesh = scene.material_mesh();
    let mut b = Vec::with_capacity(32 * mesh.positions.len() + 12 * mesh.indices.len());
    for ((p, n), uv) in mesh.positions.iter().zip(&mesh.normals).zip(&mesh.uvs) {
        for x in p
            .to_array()
            .into_iter()
            .chain(n.to_array())
            .chain(uv.to_array())
        {
            b.extend(x.to_le_bytes());
        }
    }
    for t in &mesh.indices {
        for i in t {
            b.extend(i.to_le_bytes());
        }
    }
    for t in mesh.tangents() {
        for x in t.to_array() {
            b.extend(x.to_le_bytes());
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DMat4, DVec4, Vec3};

    /// `view_proj` puts seeded points where the CPU camera projects them (pixel
    /// coordinates, f64 reference), with depth 0 at the near plane and 1 at the far one.
    #[test]
    fn view_proj_projects_as_the_renderers_camera() {
        let scene = Scene::preset("ball").unwrap();
        let (w, h) = (160, 96);
        let view = SceneView::of(&scene, w, h);
        let m = DMat4::from_cols_array(&view.view_proj.map(f64::from));
        let cam = scene.camera.frame(w, h);
        let mut state = 0x1234_5678u32;
        let mut rnd = || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / 16_777_216.0 * 4.0 - 2.0
        };
        for _ in 0..200 {
            let p = Vec3::new(rnd(), rnd() + 1.0, rnd());
            let Some((px, py)) = cam.project(p) else {
                continue;
            };
            let c = m * DVec4::new(p.x as f64, p.y as f64, p.z as f64, 1.0);
            let (x, y) = (c.x / c.w, c.y / c.w);
            let (gx, gy) = ((x + 1.0) / 2.0 * w as f64, (1.0 - y) / 2.0 * h as f64);
            assert!(
                (gx - px).abs() < 1e-3 && (gy - py).abs() < 1e-3,
                "{p}: {gx},{gy} vs {px},{py}"
            );
            assert!(
                (0.0..=1.0).contains(&(c.z / c.w)),
                "{p}: depth {}",
                c.z / c.w
            );
        }
        // The near and far planes along the view direction.
        let o = Vec3::from(view.camera_position);
        for (d, want) in [(view.near, 0.0), (view.far, 1.0)] {
            let p = o + cam.forward * d;
            let c = m * DVec4::new(p.x as f64, p.y as f64, p.z as f64, 1.0);
            assert!((c.z / c.w - want).abs() < 1e-4, "{d}: {}", c.z / c.w);
        }
    }

    /// The mesh file holds what `view.json` says where it says, and the same bytes twice.
    #[test]
    fn the_mesh_file_is_laid_out_as_the_view_says() {
        let scene = Scene::preset("plane").unwrap();
        let view = SceneView::of(&scene, 64, 64);
        let bytes = mesh_bytes(&scene);
        let m = &view.mesh;
        assert_eq!(
            bytes.len() as u64,
            m.tangent_offset + 16 * m.vertices as u64
        );
        assert_eq!(m.index_offset, 32 * m.vertices as u64);
        assert_eq!(bytes, mesh_bytes(&scene));
        // Every index names a vertex; the card's normals face +z (unit, in the file).
        let f = |at: usize| f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
        for k in 0..m.indices as usize {
            let at = m.index_offset as usize + 4 * k;
            assert!(u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) < m.vertices);
        }
        for v in 0..m.vertices as usize {
            assert_eq!(
                [f(32 * v + 12), f(32 * v + 16), f(32 * v + 20)],
                [0.0, 0.0, 1.0]
            );
        }
    }
}
