//! The GPU rasteriser (`render --gpu`) against the CPU reference renderer: every bundled
//! graph (the bubble scene's backdrop included) at 1 and 4 samples per pixel in both texture
//! modes (exact within the issue's bound, hardware within its stated bound), a displaced
//! graph at 1 and 4 (displacement and normals on the GPU), every sample count 1, 2, 3, 4,
//! 8 (MSAA where the device has it, jittered passes elsewhere), an image environment, a
//! frame drawn in tiles under a forced tile limit, the proof that the GPU path never uses
//! the CPU rasteriser (every bundled graph × {1, 2, 4, 8} spp, and an image environment),
//! and determinism.
//!
//! Metrics on the 8-bit sRGB images: RMSE over all pixels (≤ 1/255), the fraction of
//! pixels within 2/255 in every channel outside the silhouette-edge mask (≥ 99.9 %), and the
//! mask's share of the frame (≤ 1 %), at 256². The mask is measured from a 16-sample CPU
//! G-buffer: the pixels whose samples see the material surface only in part. Run with
//! `-- --nocapture` to see the figures.
//!
//! Like tests/gpu/gpu_parity.rs these never skip silently: without an adapter each prints
//! `SKIPPED …`, and fails instead when `MATGRAPH_REQUIRE_GPU` is set (CI sets it).

use crate::common;
use common::scenes::scene_of;
use common::{bundled_graphs, gpu_context};

use matgraph::gpu::Backend;
use matgraph::render::{HdrImage, RenderOptions, render_timed};
use matgraph::scene::{Mesh, Scene, cpu_raster_frames};
use matgraph::texture::{Image, Texture};
use matgraph::wgsl::TextureMode;
use matgraph::{Graph, Registry};
use std::path::Path;
use std::sync::Arc;

const SIZE: u32 = 256;

/// Samples per pixel of the G-buffer the edge mask is measured on.
const MASK_SPP: u32 = 16;

fn options(graph: &Graph, path: Option<&Path>, spp: u32, backend: Backend) -> RenderOptions {
    options_in(graph, path, spp, backend, TextureMode::Exact)
}

/// [`options`] with the GPU rasteriser's texture mode.
fn options_in(
    graph: &Graph,
    path: Option<&Path>,
    spp: u32,
    backend: Backend,
    texture_mode: TextureMode,
) -> RenderOptions {
    let textures = match path {
        Some(p) => matgraph::image_io::load_graph_textures(graph, p).unwrap(),
        None => Default::default(),
    };
    RenderOptions {
        width: SIZE,
        height: SIZE,
        samples: spp,
        backend,
        textures: Some(Arc::new(textures)),
        texture_mode,
        ..RenderOptions::default()
    }
}

/// The silhouette-edge mask of `mesh` in `scene`: the pixels that the material surface
/// covers in part, measured on a CPU G-buffer of [`MASK_SPP`] samples per pixel.
fn edge_mask(scene: &Scene, mesh: &Mesh) -> Vec<bool> {
    let g = scene.gbuffer(mesh, SIZE, SIZE, MASK_SPP);
    let mut covered = vec![0u32; (SIZE * SIZE) as usize];
    for &s in &g.samples {
        covered[(s / MASK_SPP) as usize] += 1;
    }
    covered.iter().map(|&k| k > 0 && k < MASK_SPP).collect()
}

/// (RMSE in 1/255, fraction within 2/255 outside the mask, mask fraction).
fn parity(cpu: &HdrImage, gpu: &HdrImage, mask: &[bool]) -> (f64, f64, f64) {
    let (a, b) = (cpu.to_srgb8(0.0), gpu.to_srgb8(0.0));
    let (mut sq, mut inside, mut ok) = (0.0f64, 0usize, 0usize);
    for (k, (p, q)) in a.pixels.iter().zip(&b.pixels).enumerate() {
        let d: Vec<i32> = (0..3).map(|c| p[c] as i32 - q[c] as i32).collect();
        sq += d.iter().map(|v| (v * v) as f64).sum::<f64>();
        if !mask[k] {
            inside += 1;
            ok += d.iter().all(|v| v.abs() <= 2) as usize;
        }
    }
    let n = a.pixels.len();
    let edges = mask.iter().filter(|m| **m).count();
    (
        (sq / (3 * n) as f64).sqrt(),
        ok as f64 / inside.max(1) as f64,
        edges as f64 / n as f64,
    )
}

fn assert_parity(name: &str, spp: u32, cpu: &HdrImage, gpu: &HdrImage, mask: &[bool]) {
    assert_parity_within(name, spp, cpu, gpu, mask, (1.0, 0.999));
}

/// The hardware texture mode's bound against the CPU (RMSE in 1/255, fraction within 2/255
/// outside edges), stated in docs/integration.md and docs/rendering.md: 8-bit and 16-bit
/// float texels and the samplers' 8-bit filter weights flip alpha-tested sparkles (measured
/// on lavapipe: water_sunshine RMSE 1.12/255 at 1 spp, 99.897 % within 2/255 at 4 spp; the
/// smooth materials at most RMSE 0.11/255, every pixel within 2/255).
const HARDWARE_BOUND: (f64, f64) = (2.0, 0.995);

fn assert_parity_within(
    name: &str,
    spp: u32,
    cpu: &HdrImage,
    gpu: &HdrImage,
    mask: &[bool],
    (max_rmse, min_within): (f64, f64),
) {
    let (rmse, within, edges) = parity(cpu, gpu, mask);
    println!(
        "{name:>16} {spp} spp: RMSE {rmse:.3}/255, {:.3} % within 2/255 outside edges, edges {:.2} %",
        within * 100.0,
        edges * 100.0
    );
    assert!(rmse <= max_rmse, "{name} at {spp} spp: RMSE {rmse:.3}/255");
    assert!(
        within >= min_within,
        "{name} at {spp} spp: {within} within 2/255"
    );
    assert!(edges <= 0.01, "{name} at {spp} spp: edge mask {edges}");
}

#[test]
fn every_bundled_graph_renders_alike_on_the_gpu_rasteriser() {
    if gpu_context("every_bundled_graph_renders_alike_on_the_gpu_rasteriser").is_none() {
        return;
    }
    // Masks by scene (many graphs share one).
    let mut masks: std::collections::HashMap<String, Vec<bool>> = Default::default();
    for path in bundled_graphs() {
        let graph = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        let scene = scene_of(&graph);
        for spp in [1, 4] {
            let (cpu, _) = render_timed(
                &graph,
                &scene,
                &options(&graph, Some(&path), spp, Backend::Cpu),
            )
            .unwrap();
            let (gpu, t) = render_timed(
                &graph,
                &scene,
                &options(&graph, Some(&path), spp, Backend::Gpu),
            )
            .unwrap();
            assert_eq!(t.fallback, None, "{}: fell back", graph.name);
            let key = serde_json::to_string(&scene).unwrap();
            let mask = masks
                .entry(key)
                .or_insert_with(|| edge_mask(&scene, &scene.material_mesh()));
            assert_parity(&graph.name, spp, &cpu, &gpu, mask);
            // The default texture mode, within its stated bound.
            let (hw, _) = render_timed(
                &graph,
                &scene,
                &options_in(
                    &graph,
                    Some(&path),
                    spp,
                    Backend::Gpu,
                    TextureMode::Hardware,
                ),
            )
            .unwrap();
            let name = format!("{} (hardware)", graph.name);
            assert_parity_within(&name, spp, &cpu, &hw, mask, HARDWARE_BOUND);
        }
    }
}

/// pbr_glass with its declared variant `ibl` = `monte_carlo` (env_ggx_monte_carlo's 64
/// filtered reads of the environment, which the bundled default leaves out), exact and
/// hardware texture modes, within the same bounds as the bundled graphs.
#[test]
fn the_monte_carlo_variant_renders_alike_on_the_gpu_rasteriser() {
    if gpu_context("the_monte_carlo_variant_renders_alike_on_the_gpu_rasteriser").is_none() {
        return;
    }
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/pbr_glass.json");
    let text = std::fs::read_to_string(&path).unwrap();
    let doc = matgraph::GraphDocument::parse(&text).unwrap();
    let selection = [("ibl".to_owned(), "monte_carlo".to_owned())];
    let graph = Graph::with_variants(&doc, Registry::builtin(), &selection).unwrap();
    let scene = scene_of(&graph);
    let mask = edge_mask(&scene, &scene.material_mesh());
    let cpu = render_timed(
        &graph,
        &scene,
        &options(&graph, Some(&path), 1, Backend::Cpu),
    )
    .unwrap()
    .0;
    let (gpu, t) = render_timed(
        &graph,
        &scene,
        &options(&graph, Some(&path), 1, Backend::Gpu),
    )
    .unwrap();
    assert_eq!(t.fallback, None, "fell back");
    assert_parity("pbr_glass ibl=monte_carlo", 1, &cpu, &gpu, &mask);
    let hw = options_in(&graph, Some(&path), 1, Backend::Gpu, TextureMode::Hardware);
    let hw = render_timed(&graph, &scene, &hw).unwrap().0;
    assert_parity_within(
        "pbr_glass ibl=monte_carlo (hardware)",
        1,
        &cpu,
        &hw,
        &mask,
        HARDWARE_BOUND,
    );
}

/// A wobbly, lit graph: displacement `N · (p · (0.3, 0.2, 0.1)) · 0.5`, colour `N·L` per
/// light (so the rebuilt normals and the light loop both show).
const WOBBLE: &str = r#"{ "version": 1, "name": "wobble", "nodes": [
  { "id": "geo", "type": "geometry" },
  { "id": "h", "type": "dot", "inputs": { "a": { "link": "geo.position" }, "b": [0.15, 0.1, 0.05] } },
  { "id": "d", "type": "mul", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "h.result" } } },
  { "id": "ndl", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.light" } } },
  { "id": "lit", "type": "mul", "inputs": { "a": { "link": "ndl.result" }, "b": { "link": "geo.light_color" } } } ],
  "outputs": [{ "name": "color", "from": "lit.result" }, { "name": "displacement", "from": "d.result" }] }"#;

fn wobble() -> Graph {
    Graph::from_json(WOBBLE, Registry::builtin()).unwrap_or_else(|e| panic!("{e:?}"))
}

#[test]
fn displacement_and_normals_on_the_gpu_match_the_cpu() {
    if gpu_context("displacement_and_normals_on_the_gpu_match_the_cpu").is_none() {
        return;
    }
    let graph = wobble();
    let scene = Scene::preset("ball").unwrap();
    // The CPU's displaced mesh, for the edge mask.
    let mesh = scene.material_mesh();
    let offsets: Vec<glam::Vec3> = mesh
        .positions
        .iter()
        .zip(&mesh.normals)
        .map(|(p, n)| *n * p.dot(glam::Vec3::new(0.15, 0.1, 0.05)))
        .collect();
    let displaced = mesh.displaced(&offsets);
    for spp in [1, 4] {
        let (cpu, _) =
            render_timed(&graph, &scene, &options(&graph, None, spp, Backend::Cpu)).unwrap();
        let (gpu, t) =
            render_timed(&graph, &scene, &options(&graph, None, spp, Backend::Gpu)).unwrap();
        assert_eq!(t.fallback, None);
        // (Were the GPU not to displace, its smaller silhouette would differ in a ring of
        // pixels outside the displaced mesh's edge mask.)
        let mask = edge_mask(&scene, &displaced);
        assert_parity("wobble", spp, &cpu, &gpu, &mask);
    }
}

/// An equirectangular environment image: a smooth sky-to-ground gradient with a bright
/// warm spot at u = 0.3 (so a rotation shows), 64 × 32 texels, level 0 only.
fn environment_image() -> Arc<Texture> {
    let img = Image::from_fn(64, 32, |x, y| {
        let (u, v) = ((x as f32 + 0.5) / 64.0, (y as f32 + 0.5) / 32.0);
        let spot = (-((u - 0.3).powi(2) + (v - 0.35).powi(2)) * 200.0).exp();
        [
            0.2 + 0.6 * (1.0 - v) + 3.0 * spot,
            0.3 + 0.4 * (1.0 - v) + 2.0 * spot,
            0.9 - 0.7 * v + 0.5 * spot,
            1.0,
        ]
    });
    Arc::new(Texture::new(img, false).unwrap())
}

/// The ball scene with its backdrop off (the environment seen behind the ball) under an
/// image environment turned by 40°.
fn image_scene() -> Scene {
    Scene::from_json(
        r#"{ "kind": { "ball": { "backdrop": { "enabled": false } } },
             "environment": { "image": { "path": "sky.png", "intensity": 1.5, "rotation_deg": 40 } } }"#,
    )
    .unwrap()
}

#[test]
fn image_environments_render_alike_on_the_gpu_rasteriser() {
    if gpu_context("image_environments_render_alike_on_the_gpu_rasteriser").is_none() {
        return;
    }
    let scene = image_scene();
    let mask = edge_mask(&scene, &scene.material_mesh());
    // pbr_gold samples scene:environment (the map drawn from the image); wobble is lit by
    // the ambient cube of the image only through the backdrop-free frame.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/pbr_gold.json");
    let gold = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
    for (graph, p) in [(gold, Some(path.as_path())), (wobble(), None)] {
        let mut o = options(&graph, p, 1, Backend::Cpu);
        o.environment = Some(environment_image());
        let (cpu, _) = render_timed(&graph, &scene, &o).unwrap();
        o.backend = Backend::Gpu;
        let (gpu, t) = render_timed(&graph, &scene, &o).unwrap();
        assert_eq!(t.fallback, None);
        assert_parity(&format!("{} (image)", graph.name), 1, &cpu, &gpu, &mask);
        // The image shows: the frame is not the default sky's.
        o.environment = None;
        let (sky, _) = render_timed(&graph, &scene, &o).unwrap();
        let (rmse, _, _) = parity(&sky, &gpu, &mask);
        assert!(
            rmse > 5.0,
            "{}: the image changed nothing ({rmse})",
            graph.name
        );
    }
}

#[test]
fn the_gpu_path_does_not_rasterise_on_the_cpu() {
    if gpu_context("the_gpu_path_does_not_rasterise_on_the_cpu").is_none() {
        return;
    }
    let small = |graph: &Graph, p: Option<&Path>, spp: u32| {
        let mut o = options(graph, p, spp, Backend::Gpu);
        o.width = 48;
        o.height = 32;
        o
    };
    let mut cases: Vec<(Graph, Option<std::path::PathBuf>, Scene, bool)> = bundled_graphs()
        .into_iter()
        .map(|path| {
            let graph = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
            let scene = scene_of(&graph);
            (graph, Some(path), scene, false)
        })
        .collect();
    cases.push((wobble(), None, image_scene(), true));
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/pbr_gold.json");
    let gold = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
    cases.push((gold, Some(path), image_scene(), true));
    for (graph, p, scene, image) in &cases {
        for spp in [1, 2, 4, 8] {
            let mut o = small(graph, p.as_deref(), spp);
            if *image {
                o.environment = Some(environment_image());
            }
            let before = cpu_raster_frames();
            let (_, t) = render_timed(graph, scene, &o).unwrap();
            assert_eq!(t.fallback, None, "{} at {spp} spp", graph.name);
            assert_eq!(
                cpu_raster_frames(),
                before,
                "{} at {spp} spp: the GPU path used the CPU rasteriser",
                graph.name
            );
        }
    }
    // The counter counts: the hybrid path rasterises the frame (and its scene textures).
    let (graph, p, scene, _) = &cases[0];
    let before = cpu_raster_frames();
    let mut o = small(graph, p.as_deref(), 1);
    o.backend = Backend::GpuCompute;
    render_timed(graph, scene, &o).unwrap();
    assert!(
        cpu_raster_frames() > before,
        "{}: the counter did not move",
        graph.name
    );
}

#[test]
fn frames_over_the_tile_limit_are_drawn_in_tiles() {
    if gpu_context("frames_over_the_tile_limit_are_drawn_in_tiles").is_none() {
        return;
    }
    // water_demo samples the scene textures and uv derivatives (1 and 4 spp: MSAA);
    // wobble at 2 spp (jittered passes where the device has no 2-sample MSAA). 256² in
    // tiles of 96² (partial tiles at the right and bottom).
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/water_demo.json");
    let water = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
    for (graph, p, counts) in [
        (water, Some(path.as_path()), &[1, 4][..]),
        (wobble(), None, &[2][..]),
    ] {
        let scene = scene_of(&graph);
        let mask = edge_mask(&scene, &scene.material_mesh());
        for &spp in counts {
            let (cpu, _) =
                render_timed(&graph, &scene, &options(&graph, p, spp, Backend::Cpu)).unwrap();
            let o = options(&graph, p, spp, Backend::Gpu);
            let (whole, _) = render_timed(&graph, &scene, &o).unwrap();
            let (tiled, t) = matgraph::gpu::raster::with_tile_limit(96, || {
                render_timed(&graph, &scene, &o).unwrap()
            });
            assert_eq!(t.fallback, None);
            assert_parity(&format!("{} (tiles)", graph.name), spp, &cpu, &tiled, &mask);
            // Tiles change nothing but rounding at triangle edges: a sample on the line where
            // the displaced ball meets the floor may flip between the two (the material's clip
            // position goes through the contract's view_proj, the floor's through the scene's
            // own arithmetic). One such pixel at 256² is 0.63/255 of RMSE on its own, so the
            // whole-vs-tiled bound is the issue's parity bound, as against the CPU above.
            let (rmse, within, _) = parity(&whole, &tiled, &mask);
            println!(
                "{} {spp} spp: tiled vs whole RMSE {rmse:.4}/255, {within}",
                graph.name
            );
            assert!(
                rmse <= 1.0 && within >= 0.9999,
                "{}: {rmse} {within}",
                graph.name
            );
        }
    }
}

#[test]
fn gpu_renders_are_deterministic() {
    if gpu_context("gpu_renders_are_deterministic").is_none() {
        return;
    }
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/water_demo.json");
    let graph = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
    let scene = scene_of(&graph);
    let o = options(&graph, Some(&path), 4, Backend::Gpu);
    let a = render_timed(&graph, &scene, &o).unwrap().0;
    let b = render_timed(&graph, &scene, &o).unwrap().0;
    assert_eq!(bits(&a), bits(&b));
}

/// The bits of every channel of every pixel.
fn bits(image: &HdrImage) -> Vec<u32> {
    image.pixels.iter().flatten().map(|v| v.to_bits()).collect()
}

/// The scene textures, IBL tables and packed scenes that frames reuse follow the scene:
/// the bubble (whose backdrop moves with time, and whose material samples it) drawn at
/// t = 0, then 2 s, then 0 again: the second frame matches the CPU at 2 s, the third is the
/// first bit for bit, and the two times differ.
#[test]
fn frames_at_other_times_redraw_their_scene_textures() {
    if gpu_context("frames_at_other_times_redraw_their_scene_textures").is_none() {
        return;
    }
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/bubble.json");
    let graph = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
    let scene = scene_of(&graph);
    let at = |time: f32, backend| {
        let o = RenderOptions {
            time: Some(time),
            ..options(&graph, Some(&path), 1, backend)
        };
        render_timed(&graph, &scene, &o).unwrap().0
    };
    let first = at(0.0, Backend::Gpu);
    let later = at(2.0, Backend::Gpu);
    let again = at(0.0, Backend::Gpu);
    assert_eq!(bits(&first), bits(&again), "the same time, the same frame");
    let moved = first
        .pixels
        .iter()
        .zip(&later.pixels)
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        moved > first.pixels.len() / 10,
        "{moved} pixels changed in 2 s"
    );
    let mask = edge_mask(&scene, &scene.material_mesh());
    assert_parity("bubble at 2 s", 1, &at(2.0, Backend::Cpu), &later, &mask);
}

#[test]
fn every_sample_count_draws_on_the_gpu_and_matches_the_cpu() {
    let Some(ctx) = gpu_context("every_sample_count_draws_on_the_gpu_and_matches_the_cpu") else {
        return;
    };
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/toon_ball.json");
    let toon = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
    let bubble_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/bubble.json");
    let bubble = matgraph::io::load_graph(&bubble_path, Registry::builtin()).unwrap();
    for (graph, p) in [
        (wobble(), None),
        (toon, Some(path.as_path())),
        (bubble, Some(bubble_path.as_path())),
    ] {
        let scene = scene_of(&graph);
        let mask = edge_mask(&scene, &scene.material_mesh());
        for spp in [2u32, 3, 8] {
            let (cpu, _) =
                render_timed(&graph, &scene, &options(&graph, p, spp, Backend::Cpu)).unwrap();
            let (gpu, t) =
                render_timed(&graph, &scene, &options(&graph, p, spp, Backend::Gpu)).unwrap();
            assert_eq!(t.fallback, None, "{spp} spp");
            let how = if matgraph::gpu::raster::draws_msaa(ctx, spp) {
                "MSAA"
            } else {
                "jittered passes"
            };
            println!("{spp} spp on {}: {how}", ctx.describe());
            assert_parity(&graph.name, spp, &cpu, &gpu, &mask);
        }
    }
}

/// Every light casts its shadow (issue 11 item 4), on the CPU and the GPU: a ball of radius
/// 1 at (0, 1, 0) over a grey floor (albedo 0.5, no ambient) under a directional light
/// towards (−1, 0.6, 0.2) and a point light of intensity 20 at (2, 3, −1), seen from above. Every
/// floor pixel is checked against an f64 reference written here: the camera ray through the
/// pixel centre meets the floor at p, and
/// `L = 0.5 · Σ_l vis_l · cos_l · E_l` with the sphere's visibility in closed form (the ray
/// from p towards the light passes the centre at more than the radius, or the sphere lies
/// behind), `E = 1` for the directional light, `20 / d²` for the point light. The closed-form
/// shadow centres — `c − l · c_y / l_y` for the directional light, `q + (c − q) · q_y / (q_y −
/// c_y)` for the point light — lie in their shadows, and each shadow covers many pixels.
#[test]
fn every_light_casts_its_shadow() {
    use glam::DVec3;
    const N: u32 = 128;
    let scene = Scene::from_json(
        r#"{ "kind": { "ball": { "backdrop": { "colors": [[0.5, 0.5, 0.5], [0.5, 0.5, 0.5]] } } },
             "camera": { "position": [0, 8, 5], "target": [0, 0, -0.3], "fov_y_deg": 60 },
             "lights": [
               { "directional": { "direction": [-1, 0.6, 0.2], "color": [1, 1, 1], "intensity": 1 } },
               { "point": { "position": [2, 3, -1], "color": [1, 1, 1], "intensity": 20 } } ],
             "environment": { "sky": { "ambient": 0 } } }"#,
    )
    .unwrap();
    let (c, r) = (DVec3::new(0.0, 1.0, 0.0), 1.0);
    let l_dir = DVec3::new(-1.0, 0.6, 0.2).normalize();
    let q = DVec3::new(2.0, 3.0, -1.0);
    // Margin of the visibility test: the ray passes the centre at r ± MARGIN (skipped).
    const MARGIN: f64 = 0.02;
    // Some(occluded) of the ray from p along unit d up to t_max, None near the silhouette.
    let occluded = |p: DVec3, d: DVec3, t_max: f64| -> Option<bool> {
        let t = (c - p).dot(d);
        if t <= 0.0 || t >= t_max {
            return Some(false);
        }
        let m = (p + d * t - c).length();
        ((m - r).abs() >= MARGIN).then_some(m < r)
    };
    // The camera, in f64: pinhole through pixel centres, y up, as the scene file says.
    let eye = DVec3::new(0.0, 8.0, 5.0);
    let fwd = (DVec3::new(0.0, 0.0, -0.3) - eye).normalize();
    let right = fwd.cross(DVec3::Y).normalize();
    let up = right.cross(fwd);
    let tan = (30.0f64).to_radians().tan();
    let ray = |x: f64, y: f64| {
        let nx = 2.0 * x / N as f64 - 1.0;
        let ny = 1.0 - 2.0 * y / N as f64;
        (fwd + right * (nx * tan) + up * (ny * tan)).normalize()
    };
    // The pixel nearest a floor point (by its ray).
    let pixel_of = |p: DVec3| {
        let v = (p - eye).normalize();
        let (vx, vy, vz) = (v.dot(right), v.dot(up), v.dot(fwd));
        let x = ((vx / vz / tan + 1.0) * 0.5 * N as f64).floor() as u32;
        let y = ((1.0 - vy / vz / tan) * 0.5 * N as f64).floor() as u32;
        (x, y)
    };
    let dir_centre = c - l_dir * (c.y / l_dir.y);
    let point_centre = q + (c - q) * (q.y / (q.y - c.y));
    let centres = [pixel_of(dir_centre), pixel_of(point_centre)];
    // Any undisplaced material: the ball's pixels are not checked.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/toon_ball.json");
    let graph = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
    let mut backends = vec![Backend::Cpu];
    if gpu_context("every_light_casts_its_shadow").is_some() {
        backends.push(Backend::Gpu);
    }
    for backend in backends {
        let mut o = options(&graph, Some(&path), 1, backend);
        o.width = N;
        o.height = N;
        let (img, _) = render_timed(&graph, &scene, &o).unwrap();
        // Pixels in the shadow of the directional light only, of the point light only.
        let (mut in_dir, mut in_point, mut checked) = (0, 0, 0);
        let mut centre_kind = [None, None];
        for y in 0..N {
            for x in 0..N {
                let d = ray(x as f64 + 0.5, y as f64 + 0.5);
                // Off the floor, or on the ball (with a margin): not checked.
                let t = -eye.y / d.y;
                let p = eye + d * t;
                if d.y >= 0.0 || p.x.abs() > 8.0 || p.z < -4.0 || p.z > 10.0 {
                    continue;
                }
                let tc = (c - eye).dot(d);
                if (eye + d * tc - c).length() < r + MARGIN {
                    continue;
                }
                let to = q - p;
                let dist = to.length();
                let (Some(sd), Some(sp)) = (
                    occluded(p, l_dir, f64::INFINITY),
                    occluded(p, to / dist, dist),
                ) else {
                    continue;
                };
                let e_dir = if sd { 0.0 } else { l_dir.y };
                let e_point = if sp {
                    0.0
                } else {
                    to.y / dist * 20.0 / (dist * dist)
                };
                let want = 0.5 * (e_dir + e_point);
                let got = img.pixels[(y * N + x) as usize];
                for ch in got {
                    assert!(
                        (ch as f64 - want).abs() <= 1e-4 + 1e-4 * want,
                        "{backend:?} pixel ({x}, {y}) at {p:?}: {got:?}, want {want} (shadowed: directional {sd}, point {sp})"
                    );
                }
                checked += 1;
                in_dir += (sd && !sp) as u32;
                in_point += (sp && !sd) as u32;
                for (k, &(cx, cy)) in centres.iter().enumerate() {
                    if (x, y) == (cx, cy) {
                        centre_kind[k] = Some((sd, sp));
                    }
                }
            }
        }
        println!(
            "{backend:?}: {checked} floor pixels checked, {in_dir} in the directional light's shadow, {in_point} in the point light's"
        );
        assert!(checked > 4000, "{checked}");
        assert!(in_dir > 150 && in_point > 150, "{in_dir} {in_point}");
        assert_eq!(
            centre_kind[0],
            Some((true, false)),
            "directional shadow centre"
        );
        assert_eq!(centre_kind[1], Some((false, true)), "point shadow centre");
    }
}

/// Two graphs that differ only in an exposed parameter's value share one compiled material
/// on the device (kept by `Graph::structure_key`), and each frame draws its own value:
/// pbr_gold at roughness 0.3 and at 0.8, drawn one after the other, each matches the CPU at
/// its roughness, and the two differ.
#[test]
fn graphs_differing_in_a_parameter_value_draw_their_own() {
    if gpu_context("graphs_differing_in_a_parameter_value_draw_their_own").is_none() {
        return;
    }
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/pbr_gold.json");
    let text = std::fs::read_to_string(&path).unwrap();
    let written = r#""id": "roughness", "type": "parameter", "inputs": { "value": 0.3 }"#;
    assert!(text.contains(written));
    let rougher = text.replace(written, &written.replace("0.3", "0.8"));
    let smooth = Graph::from_json(&text, Registry::builtin()).unwrap();
    let rough = Graph::from_json(&rougher, Registry::builtin()).unwrap();
    assert_eq!(smooth.structure_key(), rough.structure_key());
    assert_ne!(smooth.key(), rough.key());
    let scene = scene_of(&smooth);
    let mask = edge_mask(&scene, &scene.material_mesh());
    let draw = |g: &Graph, backend| {
        render_timed(g, &scene, &options(g, Some(&path), 1, backend))
            .unwrap()
            .0
    };
    let gpu_smooth = draw(&smooth, Backend::Gpu);
    let gpu_rough = draw(&rough, Backend::Gpu);
    assert_parity(
        "gold at 0.3",
        1,
        &draw(&smooth, Backend::Cpu),
        &gpu_smooth,
        &mask,
    );
    assert_parity(
        "gold at 0.8",
        1,
        &draw(&rough, Backend::Cpu),
        &gpu_rough,
        &mask,
    );
    let (rmse, _, _) = parity(&gpu_smooth, &gpu_rough, &mask);
    assert!(
        rmse > 5.0,
        "roughness 0.3 and 0.8 look alike: RMSE {rmse:.2}/255"
    );
}

/// A graph whose emission is the tangent frame: (sign · T) / 2 + ½.
const TANGENT_FRAME: &str = r#"{
  "version": 1, "name": "tangent_frame",
  "nodes": [
    { "id": "geo", "type": "geometry" },
    { "id": "signed", "type": "scale", "inputs": {
        "v": { "link": "geo.tangent" }, "scale": { "link": "geo.bitangent_sign" } } },
    { "id": "half", "type": "mul", "inputs": { "a": { "link": "signed.result" }, "b": [0.5, 0.5, 0.5] } },
    { "id": "shift", "type": "add", "inputs": { "a": { "link": "half.result" }, "b": [0.5, 0.5, 0.5] } }
  ],
  "outputs": [ { "name": "emission", "from": "shift.result" } ]
}"#;

/// The tangent frame (MikkTSpace tangents, the second vertex buffer, the per-sample
/// Gram–Schmidt) draws alike on the GPU rasteriser, at 1 sample (varyings) and 4 (varyings
/// rebuilt from storage), and reads as the closed form: on the ball's equator facing the
/// camera T ≈ +x, so the emission there is about (1, ½, ½), and it turns towards the limbs.
#[test]
fn the_tangent_frame_draws_alike_on_the_gpu_rasteriser() {
    if gpu_context("the_tangent_frame_draws_alike_on_the_gpu_rasteriser").is_none() {
        return;
    }
    let graph = Graph::from_json(TANGENT_FRAME, Registry::builtin()).unwrap();
    let scene = Scene::preset("ball").unwrap();
    let mask = edge_mask(&scene, &scene.material_mesh());
    for spp in [1, 4] {
        let (cpu, _) =
            render_timed(&graph, &scene, &options(&graph, None, spp, Backend::Cpu)).unwrap();
        let (gpu, t) =
            render_timed(&graph, &scene, &options(&graph, None, spp, Backend::Gpu)).unwrap();
        assert_eq!(t.fallback, None);
        assert_parity("tangent_frame", spp, &cpu, &gpu, &mask);
        // The ball's silhouette centre column: the tangent there is along +x (u grows to the
        // right as seen from the front), so red is near 1 and green, blue near ½.
        let at = |x: u32| cpu.pixels[(SIZE / 2 * SIZE + x) as usize];
        let centre = at(SIZE / 2);
        assert!(
            centre[0] > 0.95 && (centre[1] - 0.5).abs() < 0.06 && (centre[2] - 0.5).abs() < 0.06,
            "{centre:?}"
        );
        // Towards the limbs T turns about the vertical: towards the eye on the left (blue up),
        // away on the right (blue down), where the default frame (+x everywhere) would stay ½.
        let (left, right) = (at(SIZE / 2 - 60), at(SIZE / 2 + 60));
        assert!(
            left[2] > 0.8 && right[2] < 0.2,
            "left {left:?} right {right:?}"
        );
    }
}

/// A graph whose emission is `texture_coordinate.{output}` · `scale` + `offset`.
fn texture_coordinate_graph(output: &str, scale: [f32; 3], offset: [f32; 3]) -> Graph {
    let text = serde_json::json!({
        "version": 1, "name": format!("tc_{output}"),
        "nodes": [
            { "id": "tc", "type": "texture_coordinate" },
            { "id": "s", "type": "mul", "inputs": { "a": { "link": format!("tc.{output}") }, "b": scale } },
            { "id": "o", "type": "add", "inputs": { "a": { "link": "s.result" }, "b": offset } }
        ],
        "outputs": [ { "name": "emission", "from": "o.result" } ]
    });
    Graph::from_json(&text.to_string(), Registry::builtin()).unwrap()
}

/// texture_coordinate's scene-derived outputs (generated from the texture space in
/// `MgrFrame`, camera from its frame, reflection from N and V, window from the frame's
/// screen position) draw alike on the GPU rasteriser at 1 and 4 samples, mapped into [0, 1].
#[test]
fn texture_coordinates_draw_alike_on_the_gpu_rasteriser() {
    if gpu_context("texture_coordinates_draw_alike_on_the_gpu_rasteriser").is_none() {
        return;
    }
    let mut scene = Scene::preset("ball").unwrap();
    scene.camera.position = [1.3, 0.9, 2.6];
    let mask = edge_mask(&scene, &scene.material_mesh());
    let cases = [
        ("generated", [1.0; 3], [0.0; 3]),
        ("camera", [0.4, 0.4, 0.15], [0.5, 0.5, 0.0]),
        ("reflection", [0.5; 3], [0.5; 3]),
        ("window", [1.0; 3], [0.0; 3]),
    ];
    for (output, scale, offset) in cases {
        let graph = texture_coordinate_graph(output, scale, offset);
        for spp in [1, 4] {
            let (cpu, _) =
                render_timed(&graph, &scene, &options(&graph, None, spp, Backend::Cpu)).unwrap();
            let (gpu, t) =
                render_timed(&graph, &scene, &options(&graph, None, spp, Backend::Gpu)).unwrap();
            assert_eq!(t.fallback, None);
            assert_parity(output, spp, &cpu, &gpu, &mask);
        }
    }
}

/// A graph whose emission shows the `bump` node's normal (`n · ½ + ½`), its height given by
/// the nodes in `height` (JSON node list ending in a node `h` with output `result` or `fac`).
fn bump_graph(name: &str, height: serde_json::Value, from: &str, distance: f32) -> Graph {
    let mut nodes = vec![serde_json::json!({ "id": "geo", "type": "geometry" })];
    nodes.extend(height.as_array().unwrap().iter().cloned());
    nodes.extend([
        serde_json::json!({ "id": "b", "type": "bump", "inputs": { "height": { "link": from }, "distance": distance } }),
        serde_json::json!({ "id": "s", "type": "mul", "inputs": { "a": { "link": "b.normal" }, "b": 0.5 } }),
        serde_json::json!({ "id": "o", "type": "add", "inputs": { "a": { "link": "s.result" }, "b": 0.5 } }),
    ]);
    let text = serde_json::json!({
        "version": 1, "name": name, "nodes": nodes,
        "outputs": [ { "name": "emission", "from": "o.result" } ]
    });
    Graph::from_json(&text.to_string(), Registry::builtin()).unwrap()
}

/// The bump node's shifted evaluations on both renderers: the CPU's from the G-buffer's
/// position and uv differentials on the triangle's plane, the GPU's from `dpdxFine` and
/// `dpdyFine` of the varyings (at 4 samples, from the same plane-ray construction in WGSL).
/// On the plane card a height linear in the position, `h = g · P`, gives the closed form
/// `normalize(N − d (g − (g·N) N))` with N = +z at every pixel, on both; on the ball a noise
/// height of the position and one of the uv draw alike within the render parity bound, and
/// differ from the unbumped normal (the shifted heights are not the height).
#[test]
fn bump_draws_alike_on_the_gpu_rasteriser_and_as_the_closed_form() {
    if gpu_context("bump_draws_alike_on_the_gpu_rasteriser_and_as_the_closed_form").is_none() {
        return;
    }
    let g = glam::DVec3::new(0.6, -0.3, 0.2);
    let d = 0.9;
    let linear = bump_graph(
        "bump_linear",
        serde_json::json!([{ "id": "h", "type": "dot", "inputs": { "a": { "link": "geo.position" }, "b": [g.x, g.y, g.z] } }]),
        "h.result",
        d as f32,
    );
    let plane = Scene::preset("plane").unwrap();
    let n = glam::DVec3::Z;
    let want = (n - (g - n * g.dot(n)) * d).normalize() * 0.5 + glam::DVec3::splat(0.5);
    let gb = plane.gbuffer(&plane.material_mesh(), SIZE, SIZE, 1);
    let mask = edge_mask(&plane, &plane.material_mesh());
    for spp in [1, 4] {
        for backend in [Backend::Cpu, Backend::Gpu] {
            let (image, _) =
                render_timed(&linear, &plane, &options(&linear, None, spp, backend)).unwrap();
            let mut worst = 0.0f64;
            for &s in &gb.samples {
                if mask[s as usize] {
                    continue;
                }
                let p = image.pixels[s as usize];
                let got = glam::DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64);
                worst = worst.max((got - want).abs().max_element());
            }
            println!("bump linear height, {backend:?} {spp} spp: worst {worst:.1e}");
            // g · P rounded at |P| ≤ 1.5 m and differenced over ~1 cm pixels: ~1e-5 relative.
            assert!(worst < 2e-4, "{backend:?} at {spp} spp: worst {worst}");
        }
    }

    let ball = Scene::preset("ball").unwrap();
    let mask = edge_mask(&ball, &ball.material_mesh());
    let heights = [
        (
            "bump_noise",
            serde_json::json!([
                { "id": "p", "type": "mul", "inputs": { "a": { "link": "geo.position" }, "b": 3.0 } },
                { "id": "h", "type": "noise_texture", "inputs": { "vector": { "link": "p.result" }, "detail": 4.0 } }
            ]),
            "h.fac",
            0.05,
        ),
        (
            "bump_uv",
            serde_json::json!([
                { "id": "uv", "type": "split", "inputs": { "v": { "link": "geo.uv" } } },
                { "id": "a", "type": "mul", "inputs": { "a": { "link": "uv.x" }, "b": 60.0 } },
                { "id": "h", "type": "sin", "inputs": { "x": { "link": "a.result" } } }
            ]),
            "h.result",
            0.05,
        ),
    ];
    for (name, height, from, distance) in heights {
        let graph = bump_graph(name, height, from, distance);
        let flat = bump_graph("flat", serde_json::json!([]), "geo.depth", distance);
        for spp in [1, 4] {
            let (cpu, _) =
                render_timed(&graph, &ball, &options(&graph, None, spp, Backend::Cpu)).unwrap();
            let (gpu, t) =
                render_timed(&graph, &ball, &options(&graph, None, spp, Backend::Gpu)).unwrap();
            assert_eq!(t.fallback, None);
            assert_parity(name, spp, &cpu, &gpu, &mask);
            let (unbumped, _) =
                render_timed(&flat, &ball, &options(&flat, None, spp, Backend::Cpu)).unwrap();
            let (rmse, _, _) = parity(&cpu, &unbumped, &mask);
            println!("{name} {spp} spp against the unbumped normal: RMSE {rmse:.2}/255");
            assert!(
                rmse > 3.0,
                "{name}: the bump barely moved the normal ({rmse}/255)"
            );
        }
    }
}
