//! The GPU rasteriser (`render --gpu`) against the CPU reference renderer: every bundled
//! graph at 1 and 4 samples per pixel in both texture modes (exact within the issue's bound,
//! hardware within its stated bound), a
//! displaced graph at 1 and 4 (displacement and normals on the
//! GPU), the proof that the GPU path does not use the CPU rasteriser, determinism, and the
//! sample counts it draws or falls back from.
//!
//! Metrics on the 8-bit sRGB images: RMSE over all pixels (≤ 1/255), the fraction of
//! pixels within 2/255 in every channel outside the silhouette-edge mask (≥ 99.9 %), and the
//! mask's share of the frame (≤ 1 %), at 256². The mask is measured from a 16-sample CPU
//! G-buffer: the pixels whose samples see the material surface only in part. Run with
//! `-- --nocapture` to see the figures.
//!
//! Like tests/gpu_parity.rs these never skip silently: without an adapter each prints
//! `SKIPPED …`, and fails instead when `MATGRAPH_REQUIRE_GPU` is set (CI sets it).

mod common;
use common::{bundled_graphs, gpu_context};

use matgraph::gpu::Backend;
use matgraph::render::{HdrImage, RenderOptions, render_timed};
use matgraph::scene::{Mesh, Scene, cpu_raster_frames};
use matgraph::wgsl::TextureMode;
use matgraph::{Graph, Registry};
use std::path::Path;
use std::sync::Arc;

const SIZE: u32 = 256;

/// Samples per pixel of the G-buffer the edge mask is measured on.
const MASK_SPP: u32 = 16;

fn scene_of(graph: &Graph) -> Scene {
    matgraph::render::graph_scene(graph)
        .unwrap()
        .unwrap_or_else(|| Scene::preset("ball").unwrap())
}

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
/// outside edges), stated in docs/integration.md and docs/rendering.md.
const HARDWARE_BOUND: (f64, f64) = (1.0, 0.999);

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

/// The words of the note the GPU rasteriser gives for a scene it leaves to the hybrid
/// path, if it does: the bubble scene (its backdrop shader is not ported).
fn falls_back(scene: &Scene) -> Option<&'static str> {
    matches!(scene.kind, matgraph::scene::SceneKind::Bubble(_)).then_some("the bubble scene")
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
            match falls_back(&scene) {
                Some(why) => assert!(
                    t.fallback.as_deref().is_some_and(|f| f.contains(why)),
                    "{}: {:?}",
                    graph.name,
                    t.fallback
                ),
                None => assert_eq!(t.fallback, None, "{}: fell back", graph.name),
            }
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

#[test]
fn the_gpu_path_does_not_rasterise_on_the_cpu() {
    if gpu_context("the_gpu_path_does_not_rasterise_on_the_cpu").is_none() {
        return;
    }
    // water_demo samples scene:refraction and scene:reflection; wobble is displaced.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/water_demo.json");
    let water = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
    for (graph, p) in [(water, Some(path.as_path())), (wobble(), None)] {
        let scene = scene_of(&graph);
        let before = cpu_raster_frames();
        let (_, t) = render_timed(&graph, &scene, &options(&graph, p, 4, Backend::Gpu)).unwrap();
        assert_eq!(t.fallback, None);
        assert_eq!(
            cpu_raster_frames(),
            before,
            "{}: the GPU path used the CPU rasteriser",
            graph.name
        );
        // The counter counts: the hybrid path rasterises the frame (and its scene textures).
        render_timed(&graph, &scene, &options(&graph, p, 1, Backend::GpuCompute)).unwrap();
        assert!(
            cpu_raster_frames() > before,
            "{}: the counter did not move",
            graph.name
        );
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
    let bytes = |i: &HdrImage| {
        i.pixels
            .iter()
            .flatten()
            .map(|v| v.to_bits())
            .collect::<Vec<_>>()
    };
    assert_eq!(bytes(&a), bytes(&b));
}

#[test]
fn sample_counts_draw_on_msaa_or_fall_back_with_a_reason() {
    let Some(ctx) = gpu_context("sample_counts_draw_on_msaa_or_fall_back_with_a_reason") else {
        return;
    };
    let graph = wobble();
    let scene = Scene::preset("ball").unwrap();
    for spp in [1u32, 2, 3, 4, 8] {
        let (img, t) =
            render_timed(&graph, &scene, &options(&graph, None, spp, Backend::Gpu)).unwrap();
        assert_eq!(img.pixels.len(), (SIZE * SIZE) as usize);
        println!(
            "{spp} spp on {}: {}",
            ctx.describe(),
            t.fallback.as_deref().unwrap_or("MSAA")
        );
        match spp {
            // Every device draws 1 sample, and WebGPU guarantees 4-sample targets.
            1 | 4 => assert_eq!(t.fallback, None, "{spp} spp"),
            // 3 has no standard pattern: the hybrid path, and a line saying so.
            3 => assert!(
                t.fallback
                    .as_deref()
                    .is_some_and(|f| f.contains("3 samples")),
                "{:?}",
                t.fallback
            ),
            _ => {}
        }
    }
}
