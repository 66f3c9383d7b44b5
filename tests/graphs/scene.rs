//! The scene module: JSON descriptions, meshes, the rasterizer's G-buffer against analytic
//! expectations, lights, scene textures, determinism and speed.

use glam::{Vec2, Vec3};
use matgraph::Attribute;
use matgraph::scene::{
    Camera, Environment, GBuffer, ImageEnvironment, LIGHT_PRESETS, Light, Mesh, SCENE_PRESETS,
    Scene, SceneError, SceneKind, Sky, equirect_uv, sample_offsets, sun_direction,
};

/// Component `c` of sample `i` of a planar attribute column.
fn at(g: &GBuffer, attr: Attribute, i: usize) -> Vec3 {
    let col = g.batch.column(attr).expect("attribute set");
    let n = g.samples.len();
    let w = attr.ty().width();
    let get = |c: usize| if c < w { col[c * n + i] } else { 0.0 };
    Vec3::new(get(0), get(1), get(2))
}

fn parse(text: &str) -> Scene {
    Scene::from_json(text).unwrap_or_else(|e| panic!("{e}"))
}

fn json_error(text: &str) -> (usize, usize, String) {
    match Scene::from_json(text) {
        Err(SceneError::Json {
            line,
            column,
            message,
        }) => (line, column, message),
        other => panic!("expected a JSON error, got {other:?}"),
    }
}

fn invalid_field(text: &str) -> String {
    match Scene::from_json(text) {
        Err(SceneError::Invalid { field, .. }) => field,
        other => panic!("expected a validation error, got {other:?}"),
    }
}

// ---- Description -------------------------------------------------------------------------

#[test]
fn presets_round_trip_through_json_byte_for_byte() {
    for name in SCENE_PRESETS {
        let scene = Scene::preset(name).unwrap();
        let text = scene.to_json();
        let back = Scene::from_json(&text).unwrap();
        assert_eq!(back, scene, "{name}");
        assert_eq!(back.to_json(), text, "{name}: save → load → save differs");
        assert!(text.ends_with("}\n"));
    }
    assert!(Scene::preset("teapot").is_none());
}

#[test]
fn empty_object_is_the_ball_and_a_kind_name_takes_its_defaults() {
    assert_eq!(parse("{}"), Scene::preset("ball").unwrap());
    assert_eq!(parse("{}"), Scene::default());
    assert_eq!(
        parse(r#"{"kind": "water"}"#),
        Scene::preset("water").unwrap()
    );
    assert_eq!(
        parse(r#"{"kind": {"water": {}}}"#),
        Scene::preset("water").unwrap()
    );
    // A camera field left out takes the kind's default camera's.
    let s = parse(r#"{"kind": "water", "camera": {"fov_y_deg": 30}}"#);
    let water = Scene::preset("water").unwrap();
    assert_eq!(s.camera.position, water.camera.position);
    assert_eq!(s.camera.fov_y_deg, 30.0);
    // An explicit empty light list means no light.
    assert!(parse(r#"{"lights": []}"#).lights.is_empty());
}

#[test]
fn unknown_fields_and_names_are_rejected_with_their_location() {
    let (line, column, message) = json_error("{\n  \"camera\": {\n    \"fov\": 30\n  }\n}");
    assert_eq!(line, 3, "{message}");
    assert!(column > 4, "{column}");
    assert!(message.contains("unknown field `fov`"), "{message}");
    assert!(
        message.contains("fov_y_deg"),
        "lists the known fields: {message}"
    );

    let (_, _, message) = json_error(r#"{"kind": {"water": {"sise": [1, 2]}}}"#);
    assert!(message.contains("unknown field `sise`"), "{message}");
    let (_, _, message) = json_error(r#"{"kind": "lake"}"#);
    assert!(
        message.contains("lake") && message.contains("water"),
        "{message}"
    );
    let (_, _, message) = json_error(r#"{"lights": ["noon"]}"#);
    assert!(
        message.contains("noon") && message.contains("sunset"),
        "{message}"
    );
    let (_, _, message) = json_error(r#"{"scene": 1}"#);
    assert!(message.contains("unknown field `scene`"), "{message}");
    let (line, _, message) = json_error("{\n\"time\": \"noon\"}");
    assert_eq!(line, 2, "{message}");
    let err = Scene::from_json(r#"{"kind": "lake"}"#)
        .unwrap_err()
        .to_string();
    assert!(err.starts_with("scene JSON at line 1, column "), "{err}");
}

#[test]
fn module_doc_example_parses() {
    let s = parse(
        r#"{
  "kind": "water",
  "camera": { "position": [0, 3, 18], "target": [0, 0, 0], "fov_y_deg": 50 },
  "lights": ["sunset", { "point": { "position": [2, 3, 4], "color": [1, 0.9, 0.7], "intensity": 20 } }],
  "environment": "sunset",
  "time": 1.5
}"#,
    );
    assert_eq!(s.kind.name(), "water");
    assert_eq!(s.lights.len(), 2);
    assert_eq!(s.time, 1.5);
    let g = s.gbuffer(&s.material_mesh(), 16, 12, 1);
    assert_eq!(g.batch.time(), 1.5);
}

#[test]
fn out_of_range_values_name_their_field() {
    assert_eq!(
        invalid_field(r#"{"camera": {"fov_y_deg": 0}}"#),
        "camera.fov_y_deg"
    );
    assert_eq!(
        invalid_field(r#"{"camera": {"fov_y_deg": 180}}"#),
        "camera.fov_y_deg"
    );
    assert_eq!(
        invalid_field(r#"{"camera": {"position": [0, 1, 0], "target": [0, 1, 0]}}"#),
        "camera.target"
    );
    assert_eq!(
        invalid_field(r#"{"kind": {"ball": {"radius": -1}}}"#),
        "kind.ball.radius"
    );
    assert_eq!(
        invalid_field(r#"{"kind": {"water": {"seabed": {"depth_min": 3, "depth_max": 2}}}}"#),
        "kind.water.seabed.depth_max"
    );
    assert_eq!(
        invalid_field(r#"{"lights": ["day", {"point": {"intensity": -2}}]}"#),
        "lights[1].intensity"
    );
    assert_eq!(
        invalid_field(r#"{"kind": {"water": {"objects": [{"pole": {"bottom": 1, "top": 0}}]}}}"#),
        "kind.water.objects[0].top"
    );
    let err = Scene::from_json(r#"{"camera": {"near": 0}}"#)
        .unwrap_err()
        .to_string();
    assert!(err.contains("`camera.near`"), "{err}");
}

#[test]
fn light_presets_are_seed_004_colours_at_documented_elevations() {
    let s = parse(r#"{"lights": ["sunrise", "day", "sunset", "night"]}"#);
    let expected = [
        ([0.8, 0.3, 0.0], 8.0),
        ([0.7, 0.7, 0.7], 50.0),
        ([0.8, 0.3, 0.0], 8.0),
        ([0.25, 0.25, 0.25], 35.0),
    ];
    assert_eq!(s.lights.len(), 4);
    for ((light, (color, elevation)), name) in s.lights.iter().zip(expected).zip(LIGHT_PRESETS) {
        let Light::Directional(d) = light else {
            panic!("{name} is not directional")
        };
        assert_eq!(d.color, color, "{name}");
        assert_eq!(d.intensity, 1.0, "{name}");
        let dir = Vec3::from(d.direction);
        assert!((dir.length() - 1.0).abs() < 1e-6, "{name}");
        let el = dir.y.asin().to_degrees();
        assert!((el - elevation).abs() < 1e-3, "{name}: elevation {el}");
        assert_eq!(Some(*light), Light::preset(name));
    }
    // Sunrise in the east (+x), sunset in the west (-x).
    let east = |l: &Light| match l {
        Light::Directional(d) => d.direction[0],
        Light::Point(_) => unreachable!(),
    };
    assert!(east(&s.lights[0]) > 0.5 && east(&s.lights[2]) < -0.5);
    let n = sun_direction(0.0, 0.0);
    assert!(
        (n - Vec3::NEG_Z).length() < 1e-6,
        "azimuth 0 is north, -z: {n}"
    );
}

// ---- Meshes ------------------------------------------------------------------------------

#[test]
fn generated_meshes_wind_outwards_with_unit_normals() {
    let meshes = [
        (
            "sphere",
            Mesh::uv_sphere(Vec3::new(1.0, 2.0, 3.0), 2.0, 32, 16),
        ),
        ("box", Mesh::cuboid(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0))),
        ("pole", Mesh::cylinder(Vec3::ZERO, 3.0, 0.5, 16)),
        ("grid", Mesh::grid(Vec3::ZERO, Vec2::new(4.0, 2.0), [8, 4])),
    ];
    for (name, m) in &meshes {
        assert!(m.is_consistent(), "{name}");
        for n in &m.normals {
            assert!(
                (n.length() - 1.0).abs() < 1e-5,
                "{name}: |n| = {}",
                n.length()
            );
        }
        for t in &m.indices {
            let [a, b, c] = t.map(|i| i as usize);
            let p = &m.positions;
            let face = (p[b] - p[a]).cross(p[c] - p[a]);
            let n = m.normals[a] + m.normals[b] + m.normals[c];
            assert!(face.dot(n) > 0.0, "{name}: triangle {t:?} winds inwards");
        }
    }
    let sphere = &meshes[0].1;
    for (p, n) in sphere.positions.iter().zip(&sphere.normals) {
        let r = *p - Vec3::new(1.0, 2.0, 3.0);
        assert!((r.length() - 2.0).abs() < 1e-5);
        assert!((r / 2.0 - *n).length() < 1e-5);
    }
}

#[test]
fn displaced_mesh_recomputes_smooth_welded_normals() {
    let sphere = Mesh::uv_sphere(Vec3::ZERO, 1.0, 64, 32);
    // No displacement: the recomputed normals stay close to the exact ones.
    let same = sphere.displaced(&vec![Vec3::ZERO; sphere.vertex_count()]);
    assert_eq!(same.positions, sphere.positions);
    for (a, b) in same.normals.iter().zip(&sphere.normals) {
        assert!(a.dot(*b) > 0.999, "{a} vs {b}");
    }
    // Seam copies (u = 0 and u = 1) and pole copies share their normals exactly.
    for (i, p) in sphere.positions.iter().enumerate() {
        for (j, q) in sphere.positions.iter().enumerate().skip(i + 1) {
            if p == q {
                assert_eq!(same.normals[i], same.normals[j], "welded {i} and {j}");
            }
        }
    }
    // Pushing every vertex out by 0.5 along its normal keeps a sphere of radius 1.5.
    let offsets: Vec<Vec3> = sphere.normals.iter().map(|n| *n * 0.5).collect();
    let big = sphere.displaced(&offsets);
    for (p, n) in big.positions.iter().zip(&big.normals) {
        assert!((p.length() - 1.5).abs() < 1e-5);
        assert!(n.dot(p.normalize()) > 0.999);
    }
    // A bump tilts the normals around it.
    let grid = Mesh::grid(Vec3::ZERO, Vec2::new(2.0, 2.0), [2, 2]);
    let mut offsets = vec![Vec3::ZERO; grid.vertex_count()];
    offsets[4] = Vec3::new(0.0, 1.0, 0.0); // the centre vertex
    let bumped = grid.displaced(&offsets);
    assert!(
        (bumped.normals[4] - Vec3::Y).length() < 1e-6,
        "the top stays level"
    );
    assert!(
        bumped.normals[3].x < -0.1,
        "left of the bump leans left: {}",
        bumped.normals[3]
    );
    assert!(
        bumped.normals[5].x > 0.1,
        "right of it leans right: {}",
        bumped.normals[5]
    );
}

#[test]
#[should_panic(expected = "offsets for")]
fn displaced_checks_the_offset_count() {
    let grid = Mesh::grid(Vec3::ZERO, Vec2::ONE, [1, 1]);
    grid.displaced(&[Vec3::ZERO]);
}

// ---- Rasterizer --------------------------------------------------------------------------

/// A scene with only the material (no backdrop) seen by `camera`.
fn bare(camera: Camera) -> Scene {
    let mut s = parse(r#"{"kind": {"ball": {"backdrop": {"enabled": false}}}}"#);
    s.camera = camera;
    s
}

#[test]
fn sphere_silhouette_covers_its_projected_disc() {
    // Sphere of radius 1 at distance 5 on the optical axis: a disc of angular radius
    // asin(1/5), of radius tan(asin(1/5)) / tan(fov/2) · (height/2) pixels on the image.
    let camera = Camera {
        position: [0.0, 1.0, 5.0],
        target: [0.0, 1.0, 0.0],
        fov_y_deg: 40.0,
        near: 0.05,
    };
    let scene = bare(camera);
    let mesh = scene.material_mesh();
    let (w, h) = (400u32, 300u32);
    let g = scene.gbuffer(&mesh, w, h, 1);
    let alpha = (1.0f64 / 5.0).asin();
    let radius_px = alpha.tan() / 20f64.to_radians().tan() * (h as f64 / 2.0);
    let expected = std::f64::consts::PI * radius_px * radius_px;
    let found = g.samples.len() as f64;
    assert!(
        (found - expected).abs() / expected < 0.01,
        "{found} samples for an expected area of {expected:.1} px²"
    );
    // Centred: the centroid of the covered pixels is the image centre.
    let (mut sx, mut sy) = (0.0, 0.0);
    for &i in &g.samples {
        let (x, y, _) = g.sample_coords(i);
        sx += x as f64 + 0.5;
        sy += y as f64 + 0.5;
    }
    assert!((sx / found - w as f64 / 2.0).abs() < 0.05);
    assert!((sy / found - h as f64 / 2.0).abs() < 0.05);
    // With 4 samples per pixel the covered fraction is the same area.
    let g4 = scene.gbuffer(&mesh, w, h, 4);
    let found4 = g4.samples.len() as f64 / 4.0;
    assert!(
        (found4 - expected).abs() / expected < 0.01,
        "{found4} vs {expected}"
    );
}

#[test]
fn facing_plane_gives_analytic_positions_uvs_and_screen_uvs() {
    let camera = Camera {
        position: [0.0, 0.0, 5.0],
        target: [0.0, 0.0, 0.0],
        fov_y_deg: 60.0,
        near: 0.05,
    };
    let scene = bare(camera);
    // A 4 m square in the plane z = 0 facing the camera, uv (0, 0) at its lower left.
    let quad = Mesh::parallelogram(
        Vec3::new(-2.0, -2.0, 0.0),
        Vec3::new(4.0, 0.0, 0.0),
        Vec3::new(0.0, 4.0, 0.0),
        [3, 3],
    );
    let (w, h) = (64u32, 48u32);
    let g = scene.gbuffer(&quad, w, h, 1);
    let tan_half = 30f64.to_radians().tan();
    let aspect = w as f64 / h as f64;
    let mut checked = 0;
    for (k, &i) in g.samples.iter().enumerate() {
        let (x, y, _) = g.sample_coords(i);
        let ndc_x = 2.0 * (x as f64 + 0.5) / w as f64 - 1.0;
        let ndc_y = 1.0 - 2.0 * (y as f64 + 0.5) / h as f64;
        let p = Vec3::new(
            (5.0 * ndc_x * tan_half * aspect) as f32,
            (5.0 * ndc_y * tan_half) as f32,
            0.0,
        );
        let pos = at(&g, Attribute::Position, k);
        assert!((pos - p).length() < 1e-4, "pixel ({x}, {y}): {pos} vs {p}");
        let uv = at(&g, Attribute::Uv, k);
        assert!((uv.x - (p.x + 2.0) / 4.0).abs() < 1e-5);
        assert!((uv.y - (p.y + 2.0) / 4.0).abs() < 1e-5);
        let suv = at(&g, Attribute::ScreenUv, k);
        assert_eq!(suv.x, (x as f32 + 0.5) / w as f32);
        assert_eq!(suv.y, (y as f32 + 0.5) / h as f32);
        assert!((at(&g, Attribute::Normal, k) - Vec3::Z).length() < 1e-6);
        assert_eq!(
            at(&g, Attribute::Depth, k).x,
            0.0,
            "no water in the ball scene"
        );
        checked += 1;
    }
    // The square spans ±2 m at 5 m: |ndc| ≤ 2 / (5 tan 30°) = 0.69 vertically.
    let rows = (0..h)
        .filter(|y| (1.0 - 2.0 * (*y as f64 + 0.5) / h as f64).abs() * 5.0 * tan_half < 2.0)
        .count();
    let cols = (0..w)
        .filter(|x| {
            (2.0 * (*x as f64 + 0.5) / w as f64 - 1.0).abs() * 5.0 * tan_half * aspect < 2.0
        })
        .count();
    assert_eq!(checked, rows * cols);
}

#[test]
fn oblique_floor_is_interpolated_perspective_correctly() {
    // One quad (two triangles) of floor seen at a grazing angle: linear screen-space
    // interpolation would be off by metres; perspective-correct is exact.
    let camera = Camera {
        position: [0.0, 1.5, 6.0],
        target: [0.0, 0.0, -4.0],
        fov_y_deg: 50.0,
        near: 0.05,
    };
    let scene = bare(camera);
    let floor = Mesh::grid(Vec3::ZERO, Vec2::new(20.0, 20.0), [1, 1]);
    let (w, h) = (80u32, 60u32);
    let g = scene.gbuffer(&floor, w, h, 1);
    let frame = camera.frame(w, h);
    assert!(g.samples.len() > 1000);
    for (k, &i) in g.samples.iter().enumerate() {
        let (x, y, _) = g.sample_coords(i);
        let d = frame.ray_direction(x as f32 + 0.5, y as f32 + 0.5);
        let t = -1.5 / d.y;
        let p = Vec3::new(0.0, 1.5, 6.0) + d * t;
        let pos = at(&g, Attribute::Position, k);
        assert!(
            (pos - p).length() < 1e-4 * t.max(1.0),
            "({x}, {y}): {pos} vs {p}"
        );
        let uv = at(&g, Attribute::Uv, k);
        assert!((uv.x - (p.x + 10.0) / 20.0).abs() < 1e-5);
        assert!((uv.y - (10.0 - p.z) / 20.0).abs() < 1e-5, "v runs along -z");
    }
}

#[test]
fn triangles_behind_the_camera_are_clipped_at_the_near_plane() {
    // A camera 1 m above a huge floor looking at the horizon: the floor's corners lie
    // behind it. Every pixel whose ray goes down hits the floor, the others do not.
    let camera = Camera {
        position: [0.0, 1.0, 0.0],
        target: [0.0, 1.0, -10.0],
        fov_y_deg: 60.0,
        near: 0.05,
    };
    let scene = bare(camera);
    let floor = Mesh::grid(Vec3::ZERO, Vec2::new(10_000.0, 10_000.0), [2, 2]);
    let (w, h) = (64u32, 64u32);
    let g = scene.gbuffer(&floor, w, h, 1);
    let frame = camera.frame(w, h);
    let mut hit = vec![false; (w * h) as usize];
    for &i in &g.samples {
        hit[i as usize] = true;
    }
    for y in 0..h {
        for x in 0..w {
            let d = frame.ray_direction(x as f32 + 0.5, y as f32 + 0.5);
            // Rays close to the horizon reach past the floor's edge; skip them.
            if d.y.abs() < 2e-3 {
                continue;
            }
            assert_eq!(hit[(y * w + x) as usize], d.y < 0.0, "pixel ({x}, {y})");
        }
    }
}

#[test]
fn ball_normals_and_views_are_unit_and_face_the_camera() {
    let scene = Scene::preset("ball").unwrap();
    let g = scene.gbuffer(&scene.material_mesh(), 96, 80, 2);
    assert_eq!(g.batch.len(), g.samples.len());
    assert!(g.samples.len() > 2000);
    let eye = Vec3::from(scene.camera.position);
    let center = Vec3::new(0.0, 1.0, 0.0);
    for k in 0..g.samples.len() {
        let n = at(&g, Attribute::Normal, k);
        let v = at(&g, Attribute::View, k);
        let p = at(&g, Attribute::Position, k);
        assert!((n.length() - 1.0).abs() < 1e-5, "|n| = {}", n.length());
        assert!((v.length() - 1.0).abs() < 1e-5, "|v| = {}", v.length());
        assert!(
            v.dot((eye - p).normalize()) > 1.0 - 1e-6,
            "view points to the eye"
        );
        assert!(n.dot(v) > -0.02, "visible side: n·v = {}", n.dot(v));
        assert!(
            (n - (p - center).normalize()).length() < 2e-3,
            "sphere normal"
        );
        assert!(((p - center).length() - 1.0).abs() < 1e-3, "on the sphere");
    }
    assert!(g.samples.windows(2).all(|w| w[0] < w[1]), "ascending");
    assert_eq!(g.background.len(), g.sample_count());
    assert_eq!(g.batch.time(), scene.time);
}

#[test]
fn sample_pattern_is_stratified_and_centred_for_one_sample() {
    assert_eq!(sample_offsets(1), vec![[0.5, 0.5]]);
    for spp in [2u32, 4, 8, 16] {
        let offs = sample_offsets(spp);
        assert_eq!(offs.len(), spp as usize);
        for (s, o) in offs.iter().enumerate() {
            assert!((0.0..1.0).contains(&o[0]) && (0.0..1.0).contains(&o[1]));
            // One sample per column stratum along x.
            assert_eq!((o[0] * spp as f32) as usize, s);
        }
        // And, for powers of two, one per row stratum along y.
        let mut rows: Vec<usize> = offs.iter().map(|o| (o[1] * spp as f32) as usize).collect();
        rows.sort();
        assert_eq!(rows, (0..spp as usize).collect::<Vec<_>>(), "spp {spp}");
        let mean = offs.iter().map(|o| o[1]).sum::<f32>() / spp as f32;
        assert!((mean - 0.5).abs() < 1e-6, "spp {spp}: mean jy {mean}");
    }
}

// ---- Water -------------------------------------------------------------------------------

#[test]
fn water_depth_is_the_seabed_formula() {
    // slope 1: depth = min + (max - min) · smoothstep((size_z/2 - z) / size_z), no bumps.
    let scene = parse(
        r#"{"kind": {"water": {"size": [40, 40], "objects": [],
            "seabed": {"slope": 1, "depth_min": 0.5, "depth_max": 5}}}}"#,
    );
    let SceneKind::Water(water) = &scene.kind else {
        unreachable!()
    };
    let g = scene.gbuffer(&scene.material_mesh(), 64, 48, 1);
    assert!(g.samples.len() > 1000);
    for k in 0..g.samples.len() {
        let p = at(&g, Attribute::Position, k);
        let d = at(&g, Attribute::Depth, k).x;
        let t = ((20.0 - p.z) / 40.0).clamp(0.0, 1.0);
        let expected = 0.5 + 4.5 * t * t * (3.0 - 2.0 * t);
        assert!(
            (d - expected).abs() < 1e-4,
            "z = {}: {d} vs {expected}",
            p.z
        );
        assert!((d - water.seabed_depth(p.x, p.z)).abs() < 1e-4);
    }
    // The default seabed (bumps and shelf) stays between its bounds and spans most of them.
    let scene = Scene::preset("water").unwrap();
    let SceneKind::Water(water) = &scene.kind else {
        unreachable!()
    };
    let (mut lo, mut hi) = (f32::MAX, f32::MIN);
    for i in 0..=80 {
        for j in 0..=80 {
            let d = water.seabed_depth(i as f32 - 40.0, j as f32 - 40.0);
            lo = lo.min(d);
            hi = hi.max(d);
        }
    }
    assert!(lo >= 0.5 && hi <= 5.0, "{lo}..{hi}");
    assert!(lo < 1.2 && hi > 4.0, "spans ~0.5 to ~5 m: {lo}..{hi}");
    let g = scene.gbuffer(&scene.material_mesh(), 64, 48, 1);
    for k in 0..g.samples.len() {
        let p = at(&g, Attribute::Position, k);
        let d = at(&g, Attribute::Depth, k).x;
        assert!((d - (p.y + water.seabed_depth(p.x, p.z)).max(0.0)).abs() < 1e-4);
        assert_eq!(d, scene.water_depth(p));
    }
}

#[test]
fn objects_in_front_of_the_water_hide_it() {
    let scene = parse(
        r#"{"kind": {"water": {"objects": [{"box": {"center": [0, 1, 0], "size": [2, 2, 2],
            "color": [0.9, 0.1, 0.1]}}]}},
            "camera": {"position": [0, 3, 10], "target": [0, 0, 0]}}"#,
    );
    let (w, h) = (64u32, 64u32);
    let g = scene.gbuffer(&scene.material_mesh(), w, h, 1);
    let frame = scene.camera.frame(w, h);
    let pixel = |p: Vec3| {
        let (x, y) = frame.project(p).unwrap();
        (y as u32 * w + x as u32) as usize
    };
    let in_samples = |i: usize| g.samples.binary_search(&(i as u32)).is_ok();
    // The box's front face above the water hides the water behind it.
    let front = pixel(Vec3::new(0.0, 1.0, 1.0));
    assert!(!in_samples(front));
    let c = g.background[front];
    assert!(
        c[0] > 2.0 * c[1],
        "the red box is in the background layer: {c:?}"
    );
    // Open water in front of the box is material.
    assert!(in_samples(pixel(Vec3::new(0.0, 0.0, 4.0))));
    // The sky is neither.
    assert!(!in_samples(pixel(Vec3::new(0.0, 30.0, -100.0))));
}

#[test]
fn scene_textures_show_seabed_below_and_mirror_image_above() {
    let scene = parse(
        r#"{"kind": {"water": {"objects": [{"sphere": {"center": [0, 1.5, 0], "radius": 1,
            "color": [0.9, 0.1, 0.1]}}]}},
            "camera": {"position": [0, 2, 12], "target": [0, 0, 0]}, "lights": ["day"]}"#,
    );
    let (w, h) = (96u32, 72u32);
    let tex = scene.scene_textures(w, h);
    let frame = scene.camera.frame(w, h);
    let texel = |img: &matgraph::scene::SceneImage, p: Vec3| {
        let (x, y) = frame.project(p).unwrap();
        Vec3::from(img.get(x as u32, y as u32))
    };
    // Where the water would show the sphere's mirror image (below its centre's mirror
    // point), the reflection is red; the refraction there is sand.
    let mirror = Vec3::new(0.0, -1.5, 0.0);
    let r = texel(&tex.reflection, mirror);
    assert!(
        r.x > 2.0 * r.y && r.x > 2.0 * r.z,
        "reflection of the red ball: {r}"
    );
    let sand = texel(&tex.refraction, mirror);
    assert!(sand.x > sand.y && sand.y > sand.z, "sand below: {sand}");
    // The real ball is above the water: in the background, not in the refraction map.
    let ball = texel(&tex.background, Vec3::new(0.0, 1.5, 1.0));
    assert!(ball.x > 2.0 * ball.y);
    let under = texel(&tex.refraction, Vec3::new(0.0, 1.5, 1.0));
    assert!(
        under.x < 2.0 * under.y,
        "no above-water object in the refraction: {under}"
    );
    // Away from the ball, the reflection is the environment in the mirrored direction.
    let (x, y) = (5u32, h - 3);
    let mut d = frame.ray_direction(x as f32 + 0.5, y as f32 + 0.5);
    assert!(d.y < 0.0);
    d.y = -d.y;
    let expected = scene.environment_radiance(d, None);
    let found = Vec3::from(tex.reflection.get(x, y));
    assert!(
        (found - expected).length() < 1e-5,
        "{found} vs sky {expected}"
    );
    // The ball scene's refraction and reflection are its background.
    let ball = Scene::preset("ball").unwrap().scene_textures(32, 24);
    assert_eq!(ball.refraction, ball.background);
    assert_eq!(ball.reflection, ball.background);
}

#[test]
fn gbuffer_background_is_the_frame_without_the_material() {
    let scene = Scene::preset("water").unwrap();
    let (w, h) = (48u32, 36u32);
    let g = scene.gbuffer(&scene.material_mesh(), w, h, 1);
    let tex = scene.scene_textures(w, h);
    for (a, b) in g.background.iter().zip(&tex.background.data) {
        assert!((Vec3::from(*a) - Vec3::from(*b)).length() < 1e-6);
    }
    // Resolving with a constant material colour gives it exactly where the water is seen.
    let red = vec![[1.0, 0.0, 0.0]; g.samples.len()];
    let frame = g.resolve(&red);
    for (i, c) in frame.data.iter().enumerate() {
        if g.samples.binary_search(&(i as u32)).is_ok() {
            assert_eq!(*c, [1.0, 0.0, 0.0]);
        } else {
            assert_eq!(*c, g.background[i]);
        }
    }
}

// ---- Lights and environment --------------------------------------------------------------

#[test]
fn point_light_falls_off_with_the_inverse_square() {
    let scene = parse(
        r#"{"lights": [{"point": {"position": [0, 2, 0], "color": [1, 0.5, 0.25], "intensity": 8}},
                       {"directional": {"direction": [0, 2, 0], "color": [0.5, 0.5, 0.5], "intensity": 2}}]}"#,
    );
    // Points at distances 2, 4 and 1 from the light: planar x | y | z.
    let positions = [0.0, 0.0, 0.0, 0.0, -2.0, 1.0, 0.0, 0.0, 0.0];
    let (dir, color) = scene.light_columns(&scene.lights[0], &positions, 3);
    let expected = [8.0 / 4.0, 8.0 / 16.0, 8.0 / 1.0];
    for (i, e) in expected.iter().enumerate() {
        assert!(
            (color[i] - e).abs() < 1e-6 * e,
            "red {i}: {} vs {e}",
            color[i]
        );
        assert!((color[3 + i] - 0.5 * e).abs() < 1e-6 * e);
        assert!((color[6 + i] - 0.25 * e).abs() < 1e-6 * e);
        assert!((dir[3 + i] - 1.0).abs() < 1e-6, "straight up to the light");
        assert!(dir[i].abs() < 1e-6 && dir[6 + i].abs() < 1e-6);
    }
    // A directional light is the same everywhere, its direction normalised.
    let (dir, color) = scene.light_columns(&scene.lights[1], &positions, 3);
    assert!(dir[3..6].iter().all(|y| (*y - 1.0).abs() < 1e-6));
    assert!(color.iter().all(|c| (*c - 1.0).abs() < 1e-6));
}

#[test]
fn objects_shadow_the_water_in_the_light_columns() {
    let scene = parse(
        r#"{"kind": {"water": {"objects": [{"box": {"center": [0, 2, 0], "size": [1, 1, 1]}}]}},
            "lights": [{"directional": {"direction": [0, 1, 0]}}]}"#,
    );
    // (0, 0, 0), (3, 0, 0), (0, 3, 0), planar x | y | z.
    let positions = [0.0, 3.0, 0.0, 0.0, 0.0, 3.0, 0.0, 0.0, 0.0];
    let (_, color) = scene.light_columns(&scene.lights[0], &positions, 3);
    assert_eq!(color[0], 0.0, "under the box");
    assert_eq!(color[1], 1.0, "beside it");
    assert_eq!(color[2], 1.0, "above it");
    // The G-buffer's light columns are the first light's, the same values.
    let g = scene.gbuffer(&scene.material_mesh(), 40, 30, 1);
    let n = g.samples.len();
    let pos = g.batch.column(Attribute::Position).unwrap().to_vec();
    let (dir, color) = scene.light_columns(&scene.lights[0], &pos, n);
    assert_eq!(g.batch.column(Attribute::Light).unwrap(), &dir[..]);
    assert_eq!(g.batch.column(Attribute::LightColor).unwrap(), &color[..]);
}

#[test]
fn sky_gradient_sun_disc_and_image_environment() {
    let sky = Sky::preset("day").unwrap();
    let sun = sun_direction(30.0, 90.0);
    let rad = |d: Vec3| sky.radiance(d, sun, true);
    let z = Vec3::from(sky.zenith_color);
    assert!((rad(Vec3::Y) - z).length() < 1e-3, "zenith (halo is far)");
    let horizon = sky.radiance(Vec3::NEG_X, sun, false);
    assert!((horizon - Vec3::from(sky.horizon_color)).length() < 1e-6);
    let ground = sky.radiance(Vec3::NEG_Y, sun, false);
    assert!((ground - Vec3::from(sky.ground_color)).length() < 1e-6);
    let disc = rad(sun);
    assert!(
        disc.x > sky.sun_intensity * sky.sun_color[0],
        "the sun disc: {disc}"
    );
    assert!(
        rad(sun_direction(30.0, 95.0)).x < 2.0,
        "5° off the sun is sky"
    );

    // Image environment: the caller's lookup, turned by rotation_deg about +y, scaled.
    let env = Environment::Image(ImageEnvironment {
        path: "studio.hdr".into(),
        intensity: 2.0,
        rotation_deg: 90.0,
        ..Default::default()
    });
    let lookup = |d: Vec3| d + Vec3::splat(2.0);
    let out = env.radiance(Vec3::X, Vec3::Y, Some(&lookup));
    // Turned by -90°: +x reads the image at +z... (x' = cos a x + sin a z, z' = -sin a x + cos a z, a = -90°).
    assert!(
        (out - 2.0 * (Vec3::Z + Vec3::splat(2.0))).length() < 1e-5,
        "{out}"
    );
    let fallback = env.radiance(Vec3::Y, Vec3::Y, None);
    assert!(fallback.length() > 0.0, "default sky without a lookup");
    let uv = equirect_uv(Vec3::NEG_Z);
    assert!((uv - Vec2::new(0.5, 0.5)).length() < 1e-6);
    assert!((equirect_uv(Vec3::X).x - 0.75).abs() < 1e-6);
    assert!(equirect_uv(Vec3::Y).y.abs() < 1e-6);
    // Parsed from JSON, with a sky preset by name.
    let s = parse(r#"{"environment": "sunset"}"#);
    assert_eq!(
        s.environment,
        Environment::Sky(Sky::preset("sunset").unwrap())
    );
    let s = parse(r#"{"environment": {"image": {"path": "a.exr", "rotation_deg": 45}}}"#);
    let Environment::Image(img) = &s.environment else {
        panic!()
    };
    assert_eq!(
        (img.path.as_str(), img.intensity, img.rotation_deg),
        ("a.exr", 1.0, 45.0)
    );
    // The sky's sun follows the first directional light by default.
    let s = parse(r#"{"lights": ["sunset"]}"#);
    let Light::Directional(d) = s.lights[0] else {
        panic!()
    };
    assert!((s.sun_direction() - Vec3::from(d.direction)).length() < 1e-6);
    let s = parse(
        r#"{"environment": {"sky": {"sun": {"angles": {"elevation_deg": 90, "azimuth_deg": 0}}}}}"#,
    );
    assert!((s.sun_direction() - Vec3::Y).length() < 1e-6);
}

// ---- Determinism and speed ---------------------------------------------------------------

fn bits(g: &GBuffer) -> Vec<u32> {
    let mut out: Vec<u32> = g.samples.clone();
    for attr in [
        Attribute::Position,
        Attribute::Normal,
        Attribute::View,
        Attribute::Uv,
        Attribute::ScreenUv,
        Attribute::Depth,
        Attribute::Light,
        Attribute::LightColor,
    ] {
        out.extend(g.batch.column(attr).unwrap().iter().map(|v| v.to_bits()));
    }
    out.extend(g.background.iter().flatten().map(|v| v.to_bits()));
    out
}

#[test]
fn output_is_identical_across_runs_and_thread_counts() {
    for name in SCENE_PRESETS {
        let scene = Scene::preset(name).unwrap();
        let mesh = scene.material_mesh();
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                (
                    bits(&scene.gbuffer(&mesh, 50, 40, 2)),
                    scene.scene_textures(50, 40),
                )
            })
        };
        let (a, ta) = run(1);
        let (b, tb) = run(3);
        let (c, _) = run(3);
        assert!(a == b && b == c, "{name}: G-buffers differ");
        assert_eq!(ta, tb, "{name}: textures differ");
    }
}

#[test]
fn empty_frames_are_empty() {
    let scene = Scene::preset("water").unwrap();
    let g = scene.gbuffer(&scene.material_mesh(), 0, 10, 1);
    assert!(g.samples.is_empty() && g.background.is_empty() && g.batch.is_empty());
    let t = scene.scene_textures(7, 0);
    assert!(t.background.data.is_empty() && t.reflection.data.is_empty());
    assert_eq!(t.refraction.sample(Vec2::splat(0.5)), Vec3::ZERO);
}

// ---- The plane preset ---------------------------------------------------------------------

#[test]
fn the_plane_preset_is_a_card_facing_the_camera_with_the_spheres_uv_convention() {
    let plane = Scene::preset("plane").unwrap();
    assert_eq!(parse(r#"{"kind": "plane"}"#), plane);
    assert_eq!(
        parse(r#"{"kind": {"ball": {"shape": "plane", "segments": [32, 32]}}}"#),
        plane
    );
    // The sphere is the default and is left out of saved scenes (their bytes are unchanged).
    assert!(!Scene::preset("ball").unwrap().to_json().contains("shape"));
    assert!(plane.to_json().contains("\"shape\": \"plane\""));
    let field = match Scene::from_json(r#"{"kind": {"ball": {"shape": "cube"}}}"#) {
        Err(SceneError::Json { message, .. }) => message,
        other => panic!("expected a JSON error, got {other:?}"),
    };
    assert!(field.contains("cube") && field.contains("plane"), "{field}");

    // A 2 m card centred at (0, 1, 0) in the plane z = 0: uv (0, 0) at its lower left
    // corner, u along +x and v along +y; normal +z and tangent +x everywhere.
    let mesh = plane.material_mesh();
    assert_eq!(mesh.vertex_count(), 33 * 33);
    assert_eq!(mesh.triangle_count(), 2 * 32 * 32);
    let tangents = mesh.tangents();
    for (i, p) in mesh.positions.iter().enumerate() {
        assert_eq!(p.z, 0.0);
        assert!(p.x.abs() <= 1.0 && (p.y - 1.0).abs() <= 1.0, "{p}");
        let uv = mesh.uvs[i];
        assert!((uv.x - (p.x + 1.0) / 2.0).abs() < 1e-6, "{p} {uv}");
        assert!((uv.y - p.y / 2.0).abs() < 1e-6, "{p} {uv}");
        assert_eq!(mesh.normals[i], Vec3::Z);
        assert!((tangents[i].truncate() - Vec3::X).length() < 1e-6);
        assert_eq!(tangents[i].w, 1.0);
    }
    // Every triangle winds towards +z (front faces seen by the camera at z = 5).
    for t in &mesh.indices {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        assert!((b - a).cross(c - a).z > 0.0);
    }

    // The G-buffer covers the card's projection: the f64 pinhole image of its four
    // corners (shoelace area), within 1 %, and every sample's uv follows its position.
    let (w, h) = (160u32, 120u32);
    let g = plane.gbuffer(&mesh, w, h, 1);
    let cam = &plane.camera;
    let eye = Vec3::from(cam.position).as_dvec3();
    let forward = (Vec3::from(cam.target).as_dvec3() - eye).normalize();
    let right = forward.cross(glam::DVec3::Y).normalize();
    let up = right.cross(forward);
    let tan_half = (cam.fov_y_deg as f64 / 2.0).to_radians().tan();
    let pixel = |p: glam::DVec3| {
        let v = p - eye;
        let (x, y, z) = (v.dot(right), v.dot(up), v.dot(forward));
        let ndc = (x / z / (tan_half * w as f64 / h as f64), y / z / tan_half);
        (
            (ndc.0 + 1.0) * w as f64 / 2.0,
            (1.0 - ndc.1) * h as f64 / 2.0,
        )
    };
    let corners = [(-1.0, 0.0), (1.0, 0.0), (1.0, 2.0), (-1.0, 2.0)]
        .map(|(x, y)| pixel(glam::DVec3::new(x, y, 0.0)));
    let area = 0.5
        * (0..4)
            .map(|i| {
                let (a, b) = (corners[i], corners[(i + 1) % 4]);
                a.0 * b.1 - b.0 * a.1
            })
            .sum::<f64>()
            .abs();
    let found = g.samples.len() as f64;
    assert!(
        (found - area).abs() / area < 0.01,
        "{found} samples for a projected area of {area:.1} px²"
    );
    for k in 0..g.samples.len() {
        let (p, uv) = (at(&g, Attribute::Position, k), at(&g, Attribute::Uv, k));
        assert!(p.z.abs() < 1e-5, "{p}");
        assert!((uv.x - (p.x + 1.0) / 2.0).abs() < 1e-4 && (uv.y - p.y / 2.0).abs() < 1e-4);
    }
}
