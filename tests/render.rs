//! Rendering: CPU and GPU renders of every bundled graph agree, the light loop sums lights,
//! alpha composites over the background, displacement moves the surface, renders are
//! deterministic, and the `render` command writes what it says.

mod common;
use common::bundled_graphs;

use matgraph::gpu::Backend;
use matgraph::render::{RenderOptions, render};
use matgraph::scene::Scene;
use matgraph::{Attribute, Graph, Registry};
use std::path::Path;
use std::sync::Arc;

/// The scene a graph names (ball by default), as `matgraph render` picks it.
fn scene_of(graph: &Graph) -> Scene {
    matgraph::render::graph_scene(graph)
        .unwrap()
        .unwrap_or_else(|| Scene::preset("ball").unwrap())
}

fn options(size: u32, backend: Backend, graph: &Graph, path: &Path) -> RenderOptions {
    let textures = matgraph::image_io::load_graph_textures(graph, path).unwrap();
    RenderOptions {
        width: size,
        height: size,
        samples: 1,
        backend,
        textures: Some(Arc::new(textures)),
        ..RenderOptions::default()
    }
}

/// CPU and GPU renders of every bundled graph agree on the 8-bit output: per-pixel max |Δ| ≤
/// 2/255 and RMSE ≤ 0.5/255 over every pixel. The mask of excluded pixels is empty: both
/// backends shade the same CPU G-buffer, so silhouettes are identical by construction.
#[test]
fn cpu_and_gpu_renders_agree() {
    if common::gpu_context("cpu_and_gpu_renders_agree").is_none() {
        return;
    }
    for path in bundled_graphs() {
        let graph = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        let scene = scene_of(&graph);
        let cpu = render(&graph, &scene, &options(128, Backend::Cpu, &graph, &path))
            .unwrap()
            .to_srgb8(0.0);
        let gpu = render(&graph, &scene, &options(128, Backend::Gpu, &graph, &path))
            .unwrap()
            .to_srgb8(0.0);
        let (mut max, mut sum2) = (0i32, 0.0f64);
        for (a, b) in cpu.pixels.iter().zip(&gpu.pixels) {
            for c in 0..3 {
                let d = a[c] as i32 - b[c] as i32;
                max = max.max(d.abs());
                sum2 += (d * d) as f64;
            }
        }
        let rmse = (sum2 / (cpu.pixels.len() * 3) as f64).sqrt();
        eprintln!("{}: max |Δ| = {max}/255, RMSE = {rmse:.4}/255", graph.name);
        assert!(max <= 2, "{}: max |Δ| = {max}/255", graph.name);
        assert!(rmse <= 0.5, "{}: RMSE = {rmse}/255", graph.name);
    }
}

fn graph(text: &str) -> Graph {
    Graph::from_json(text, Registry::builtin()).unwrap_or_else(|e| panic!("{e:?}"))
}

/// A Lambert graph summed over the scene's lights equals Lambert computed here from the
/// G-buffer and the scene's light columns, pixel for pixel.
#[test]
fn the_light_loop_sums_every_light() {
    let g = graph(
        r#"{ "version": 1, "name": "lambert", "nodes": [
          { "id": "geo", "type": "geometry" },
          { "id": "ndl", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.light" } } },
          { "id": "cos", "type": "saturate", "inputs": { "x": { "link": "ndl.result" } } },
          { "id": "c", "type": "mul", "inputs": { "a": { "link": "geo.light_color" }, "b": { "link": "cos.result" } } } ],
          "outputs": [{ "name": "color", "from": "c.result" }] }"#,
    );
    let scene = Scene::preset("ball").unwrap();
    assert!(
        scene.lights.len() >= 2,
        "the ball preset has several lights"
    );
    let size = 48;
    let img = render(
        &g,
        &scene,
        &RenderOptions {
            width: size,
            height: size,
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let gb = scene.gbuffer(&scene.material_mesh(), size, size, 1);
    let n = gb.samples.len();
    assert!(n > 200, "the ball covers part of the frame");
    let pos = gb.batch.column(Attribute::Position).unwrap();
    let nrm = gb.batch.column(Attribute::Normal).unwrap();
    let mut want = vec![[0.0f32; 3]; n];
    for light in &scene.lights {
        let (dir, col) = scene.light_columns(light, pos, n);
        for (i, w) in want.iter_mut().enumerate() {
            let cos: f32 = (0..3)
                .map(|c| nrm[c * n + i] * dir[c * n + i])
                .sum::<f32>()
                .clamp(0.0, 1.0);
            for c in 0..3 {
                w[c] += col[c * n + i] * cos;
            }
        }
    }
    for (k, &s) in gb.samples.iter().enumerate() {
        let got = img.pixels[s as usize];
        for c in 0..3 {
            assert!(
                (got[c] - want[k][c]).abs() <= 1e-5 * (1.0 + want[k][c]),
                "pixel {s}: {got:?} vs {:?}",
                want[k]
            );
        }
    }
}

/// `alpha` blends `emission` over the background: 0.25 · 1 + 0.75 · background.
#[test]
fn alpha_composites_over_the_background() {
    let g = graph(
        r#"{ "version": 1, "name": "veil", "nodes": [
          { "id": "white", "type": "constant", "inputs": { "value": [1.0, 1.0, 1.0] } },
          { "id": "a", "type": "constant", "inputs": { "value": 0.25 } } ],
          "outputs": [{ "name": "emission", "from": "white.value" }, { "name": "alpha", "from": "a.value" }] }"#,
    );
    let scene = Scene::preset("ball").unwrap();
    let size = 40;
    let img = render(
        &g,
        &scene,
        &RenderOptions {
            width: size,
            height: size,
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let gb = scene.gbuffer(&scene.material_mesh(), size, size, 1);
    for &s in &gb.samples {
        let bg = gb.background[s as usize];
        let got = img.pixels[s as usize];
        for c in 0..3 {
            let want = 0.25 + 0.75 * bg[c];
            assert!(
                (got[c] - want).abs() < 1e-6,
                "pixel {s}: {} vs {want}",
                got[c]
            );
        }
    }
    // Pixels the ball does not cover are the background itself.
    let covered: std::collections::BTreeSet<u32> = gb.samples.iter().copied().collect();
    for (s, bg) in gb.background.iter().enumerate() {
        if !covered.contains(&(s as u32)) {
            assert_eq!(&img.pixels[s], bg);
        }
    }
}

/// A `displacement` of 0.25 × the normal on the unit ball grows its silhouette: the covered
/// area scales by (1.25)² within a few per cent, on a frame where the ball stays inside.
#[test]
fn displacement_moves_the_surface() {
    let text = |d: f32| {
        format!(
            r#"{{ "version": 1, "name": "puff", "nodes": [
              {{ "id": "geo", "type": "geometry" }},
              {{ "id": "d", "type": "mul", "inputs": {{ "a": {{ "link": "geo.normal" }}, "b": {d} }} }},
              {{ "id": "white", "type": "constant", "inputs": {{ "value": 1.0 }} }} ],
              "outputs": [{{ "name": "emission", "from": "white.value" }}, {{ "name": "displacement", "from": "d.result" }}] }}"#
        )
    };
    let scene = Scene::preset("ball").unwrap();
    let covered = |d: f32| {
        let g = graph(&text(d));
        let img = render(
            &g,
            &scene,
            &RenderOptions {
                width: 160,
                height: 160,
                ..RenderOptions::default()
            },
        )
        .unwrap();
        img.pixels.iter().filter(|p| **p == [1.0, 1.0, 1.0]).count() as f64
    };
    let (a, b) = (covered(0.0), covered(0.25));
    let ratio = b / a;
    assert!(
        (ratio - 1.5625).abs() < 0.08,
        "area ratio {ratio} (covered {a} → {b})"
    );
}

#[test]
fn renders_are_deterministic() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/toon_ball.json");
    let g = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
    let scene = scene_of(&g);
    let once = || {
        render(
            &g,
            &scene,
            &RenderOptions {
                width: 64,
                height: 64,
                samples: 4,
                ..RenderOptions::default()
            },
        )
        .unwrap()
    };
    assert_eq!(once(), once());
}

#[test]
fn render_command_writes_pngs_a_contact_sheet_and_exr() {
    let dir = tempfile::tempdir().unwrap();
    let root = env!("CARGO_MANIFEST_DIR");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .current_dir(root)
        .args([
            "render",
            "graphs/toon_ball.json",
            "graphs/fresnel_glass.json",
            "--size",
            "48x32",
            "--exr",
            "--out-dir",
        ])
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for f in [
        "toon_ball.png",
        "toon_ball.exr",
        "fresnel_glass.png",
        "contact_sheet.png",
    ] {
        assert!(dir.path().join(f).is_file(), "{f} missing");
    }
    let png = image::open(dir.path().join("toon_ball.png")).unwrap();
    assert_eq!((png.width(), png.height()), (48, 32));
    // A bad graph fails with its file named and a non-zero exit; the good one still renders.
    let bad = dir.path().join("bad.json");
    std::fs::write(
        &bad,
        r#"{"version": 1, "name": "bad", "nodes": [{"id": "x", "type": "nope"}]}"#,
    )
    .unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .current_dir(root)
        .args([
            "render",
            "graphs/fresnel_glass.json",
            "--size",
            "16x16",
            "--out-dir",
        ])
        .arg(dir.path())
        .arg(&bad)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("bad.json") && stderr.contains("unknown node type 'nope'"),
        "{stderr}"
    );
}

/// An image environment is loaded relative to the scene file and lights the sky: with a
/// uniform equirectangular image of radiance c, the sky pixels of the water scene's linear
/// EXR output are exactly c.
#[test]
fn image_environments_are_loaded_and_seen() {
    use matgraph::texture::Image;
    let dir = tempfile::tempdir().unwrap();
    let c = [0.25f32, 0.5, 0.75];
    let env = Image::filled(16, 8, [c[0], c[1], c[2], 1.0]);
    matgraph::image_io::save_exr(&dir.path().join("sky.exr"), &env).unwrap();
    std::fs::write(
        dir.path().join("scene.json"),
        r#"{ "kind": "water", "environment": { "image": { "path": "sky.exr" } } }"#,
    )
    .unwrap();
    let out = dir.path().join("out.png");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args([
            "render",
            "graphs/fresnel_glass.json",
            "--size",
            "32x32",
            "--exr",
            "--scene",
        ])
        .arg(dir.path().join("scene.json"))
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let img = matgraph::image_io::load_image(&out.with_extension("exr")).unwrap();
    let top_left = img.data[0];
    for k in 0..3 {
        assert!(
            (top_left[k] - c[k]).abs() < 1e-5,
            "sky pixel {top_left:?}, environment {c:?}"
        );
    }
    // A missing image is an error that names it.
    std::fs::write(
        dir.path().join("bad.json"),
        r#"{ "environment": { "image": { "path": "nope.exr" } } }"#,
    )
    .unwrap();
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args([
            "render",
            "graphs/fresnel_glass.json",
            "--size",
            "8x8",
            "--scene",
        ])
        .arg(dir.path().join("bad.json"))
        .arg("-o")
        .arg(dir.path().join("bad.png"))
        .output()
        .unwrap();
    assert!(!status.status.success());
    assert!(String::from_utf8_lossy(&status.stderr).contains("nope.exr"));
}

/// `scene:environment` read through `equirect_uv` in a direction gives the scene's own
/// environment radiance in that direction: on the ball, looking up the sky along the normal,
/// the mean relative error over covered pixels is below 1% (bilinear filtering of a
/// 512 × 256 map; the sun's disc is the only sharp feature).
#[test]
fn scene_environment_matches_the_environment() {
    let g = graph(
        r#"{ "version": 1, "name": "env", "nodes": [
          { "id": "geo", "type": "geometry" },
          { "id": "uv", "type": "equirect_uv", "inputs": { "direction": { "link": "geo.normal" } } },
          { "id": "env", "type": "image_texture", "texture": "scene:environment", "inputs": { "uv": { "link": "uv.uv" } } } ],
          "outputs": [{ "name": "emission", "from": "env.color" }] }"#,
    );
    let scene = Scene::preset("ball").unwrap();
    let size = 64;
    let img = render(
        &g,
        &scene,
        &RenderOptions {
            width: size,
            height: size,
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let gb = scene.gbuffer(&scene.material_mesh(), size, size, 1);
    let n = gb.samples.len();
    let nrm = gb.batch.column(Attribute::Normal).unwrap();
    let mut sum = 0.0f64;
    for (k, &s) in gb.samples.iter().enumerate() {
        let d = glam::Vec3::new(nrm[k], nrm[n + k], nrm[2 * n + k]);
        let want = scene.environment_radiance(d, None);
        let got = img.pixels[s as usize];
        let rel = ((got[0] - want.x).abs() + (got[1] - want.y).abs() + (got[2] - want.z).abs())
            / (want.x + want.y + want.z).max(1e-3);
        sum += rel as f64;
    }
    let mean = sum / n as f64;
    assert!(mean < 0.01, "mean relative error {mean}");
}
