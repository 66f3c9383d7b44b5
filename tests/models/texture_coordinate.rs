//! The `texture_coordinate` node's attributes (Blender's Texture Coordinate) as the CPU
//! G-buffer supplies them, against references written here in f64 from the scene's own
//! definition: the camera frame rebuilt from its position and target, the sphere's box from
//! its centre and radius (and the built mesh's box), `2 (N · V) N − V`, and Blender's window
//! convention; and a check that ties two of them together independently — the camera-space
//! position projected through the pinhole lands on the sample's screen position. The GPU's
//! values are held to the CPU's by tests/gpu/gpu_render.rs (render parity) and the registry
//! parity suite; `eval` without a scene by `defaults_without_a_scene`.

use glam::DVec3;
use matgraph::scene::{Scene, SceneKind};
use matgraph::{Attribute, Graph, Plan, PlanOptions, Registry, SampleBatch};

fn column3(b: &SampleBatch, a: Attribute, i: usize) -> DVec3 {
    let c = b.column(a).unwrap_or_else(|| panic!("{a:?} missing"));
    let n = b.len();
    DVec3::new(c[i] as f64, c[n + i] as f64, c[2 * n + i] as f64)
}

/// The ball scene, its camera moved off-axis (above, to the right) so that every camera
/// axis matters, at a non-square size so that the aspect does.
fn scene() -> Scene {
    let mut s = Scene::preset("ball").unwrap();
    s.camera.position = [1.3, 0.9, 2.6];
    s
}

/// The camera frame in f64 from the scene's position and target (up hint +y).
fn frame(s: &Scene) -> [DVec3; 4] {
    let o = DVec3::from(s.camera.position.map(f64::from));
    let f = (DVec3::from(s.camera.target.map(f64::from)) - o).normalize();
    let r = f.cross(DVec3::Y).normalize();
    [o, r, r.cross(f), f]
}

#[test]
fn the_gbuffer_supplies_blenders_coordinates() {
    let s = scene();
    let (w, h) = (96u32, 64u32);
    let mesh = s.material_mesh();
    let g = s.gbuffer(&mesh, w, h, 1);
    let b = &g.batch;
    assert!(b.len() > 1000, "{} samples", b.len());
    let SceneKind::Ball(ball) = &s.kind else {
        unreachable!()
    };
    let c = DVec3::from(ball.center.map(f64::from));
    let r = ball.radius as f64;
    let [o, right, up, fwd] = frame(&s);
    let tan = ((s.camera.fov_y_deg as f64).to_radians() * 0.5).tan();
    let aspect = w as f64 / h as f64;
    let su = b.column(Attribute::ScreenUv).unwrap();
    let n_s = b.len();
    let (mut worst_gen, mut worst_cam, mut worst_proj, mut worst_ref) = (0f64, 0f64, 0f64, 0f64);
    let (mut lo, mut hi) = (DVec3::splat(1.0), DVec3::splat(0.0));
    for i in 0..n_s {
        let p = column3(b, Attribute::Position, i);
        let n = column3(b, Attribute::Normal, i);
        let v = column3(b, Attribute::View, i);
        // generated: the sphere's box.
        let gen_want = DVec3::splat(0.5) + (p - c) / (2.0 * r);
        let generated = column3(b, Attribute::Generated, i);
        worst_gen = worst_gen.max((generated - gen_want).abs().max_element());
        lo = lo.min(generated);
        hi = hi.max(generated);
        // camera: the position in the (right, up, forward) frame.
        let d = p - o;
        let cam_want = DVec3::new(d.dot(right), d.dot(up), d.dot(fwd));
        let cam = column3(b, Attribute::Camera, i);
        worst_cam = worst_cam.max((cam - cam_want).abs().max_element() / cam_want.length());
        // ... which projects through the pinhole onto the sample's screen position.
        let (sx, sy) = (su[i] as f64, su[n_s + i] as f64);
        let px = 0.5 + 0.5 * cam.x / (cam.z * tan * aspect);
        let py = 0.5 - 0.5 * cam.y / (cam.z * tan);
        worst_proj = worst_proj.max((px - sx).abs().max((py - sy).abs()));
        // window: Blender's, (0, 0) at the bottom left.
        let win = column3(b, Attribute::Window, i);
        assert_eq!(win, DVec3::new(sx, 1.0 - sy, 0.0), "sample {i}");
        // reflection: 2 (N · V) N − V.
        let refl = column3(b, Attribute::Reflection, i);
        let refl_want = 2.0 * n.dot(v) * n - v;
        worst_ref = worst_ref.max((refl - refl_want).abs().max_element());
    }
    println!(
        "texture_coordinate: generated {worst_gen:.1e}, camera {worst_cam:.1e} (relative), \
         projection {worst_proj:.1e}, reflection {worst_ref:.1e}; generated spans {lo} .. {hi}"
    );
    assert!(worst_gen < 1e-6, "generated {worst_gen}");
    assert!(worst_cam < 1e-6, "camera {worst_cam}");
    // Screen positions within 1e-5 (a 64-px-high frame: well below a pixel's 1.6e-2).
    assert!(worst_proj < 1e-5, "projection {worst_proj}");
    assert!(worst_ref < 1e-6, "reflection {worst_ref}");
    // The visible part of the sphere reaches near its box's faces towards the camera.
    assert!(
        hi.max_element() > 0.95 && lo.min_element() < 0.2,
        "{lo} {hi}"
    );
}

/// The texture space is the built mesh's bounding box (the sphere's, and the water plane's
/// with its flat axis at ½ as Blender's size-1 texture space there).
#[test]
fn the_texture_space_is_the_surfaces_box() {
    for name in ["ball", "water", "bubble"] {
        let s = Scene::preset(name).unwrap();
        let mesh = s.material_mesh();
        let (mut lo, mut hi) = (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN));
        for p in &mesh.positions {
            lo = lo.min(p.as_dvec3());
            hi = hi.max(p.as_dvec3());
        }
        let (lo_g, hi_g) = (s.generated(lo.as_vec3()), s.generated(hi.as_vec3()));
        for k in 0..3 {
            if hi[k] - lo[k] > 1e-6 {
                assert!(
                    (lo_g[k] as f64).abs() < 1e-5 && (hi_g[k] as f64 - 1.0).abs() < 1e-5,
                    "{name} axis {k}: {lo_g} {hi_g}"
                );
            } else {
                assert_eq!((lo_g[k], hi_g[k]), (0.5, 0.5), "{name} flat axis {k}");
            }
        }
    }
}

/// Without a scene (matgraph eval) each output is its attribute's stated default.
#[test]
fn defaults_without_a_scene() {
    let text = serde_json::json!({
        "version": 1, "name": "tc",
        "nodes": [ { "id": "tc", "type": "texture_coordinate" } ],
        "outputs": [
            { "name": "uv", "from": "tc.uv" }, { "name": "object", "from": "tc.object" },
            { "name": "world", "from": "tc.world" }, { "name": "generated", "from": "tc.generated" },
            { "name": "reflection", "from": "tc.reflection" }, { "name": "window", "from": "tc.window" },
            { "name": "camera", "from": "tc.camera" }
        ]
    });
    let g = Graph::from_json(&text.to_string(), Registry::builtin()).unwrap();
    let plan = Plan::compile(&g, &PlanOptions::default()).unwrap();
    let out = plan
        .execute(&SampleBatch::new(1), &plan.default_parameters())
        .unwrap();
    let want: [&[f32]; 7] = [
        &[0.5, 0.5],
        &[0.0, 0.0, 0.0],
        &[0.0, 0.0, 0.0],
        &[0.5, 0.5, 0.5],
        &[0.0, 0.0, 1.0],
        &[0.5, 0.5, 0.0],
        &[0.0, 0.0, 1.0],
    ];
    for (k, w) in want.iter().enumerate() {
        assert_eq!(out.planar(k), *w, "output {k}");
    }
}
