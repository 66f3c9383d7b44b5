//! Rendering: CPU and GPU renders of every bundled graph agree, the light loop sums lights,
//! alpha composites over the background, displacement moves the surface, renders are
//! deterministic, and the `render` command writes what it says.

use crate::common;
use common::bundled_graphs;
use common::scenes::{graph, render_options, scene_of};

use matgraph::gpu::Backend;
use matgraph::render::{RenderOptions, render};
use matgraph::scene::Scene;
use matgraph::{Attribute, Registry};
use std::path::Path;

/// CPU and GPU renders of every bundled graph agree on the 8-bit output: per-pixel max |Δ| ≤
/// 2/255 and RMSE ≤ 0.5/255 over every pixel, on the hybrid path (`Backend::GpuCompute`):
/// both backends shade the same CPU G-buffer, so the mask of excluded pixels is empty. The
/// GPU rasteriser (`Backend::Gpu`) is compared in tests/gpu/gpu_render.rs, with the measured
/// silhouette-edge mask.
#[test]
fn cpu_and_gpu_renders_agree() {
    if common::gpu_context("cpu_and_gpu_renders_agree").is_none() {
        return;
    }
    for path in bundled_graphs() {
        let graph = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        let scene = scene_of(&graph);
        let cpu = render(
            &graph,
            &scene,
            &render_options(128, Backend::Cpu, &graph, &path),
        )
        .unwrap()
        .to_srgb8(0.0);
        let gpu = render(
            &graph,
            &scene,
            &render_options(128, Backend::GpuCompute, &graph, &path),
        )
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
/// environment radiance in that direction: on the ball without its backdrop (with it, the
/// map shows the room: tests/models/ibl.rs), looking up the sky along the normal,
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
    let scene = Scene::from_json(r#"{ "kind": { "ball": { "backdrop": { "enabled": false } } } }"#)
        .unwrap();
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

// ---------------------------------------------------------------------------------------
// Memory: bands of rows, the budget planner, refusals.
// ---------------------------------------------------------------------------------------

/// Rendering band by band is bit-exact: every bundled graph (the water scene's scene
/// textures and reflections, displacement, alpha, image textures included) rendered in
/// bands of 1, 3 and 7 rows equals its one-band render, float for float, at 4 spp.
#[test]
fn banded_renders_equal_the_whole_frame_bit_for_bit() {
    let bits = |img: &matgraph::render::HdrImage| -> Vec<[u32; 3]> {
        img.pixels.iter().map(|p| p.map(f32::to_bits)).collect()
    };
    for path in bundled_graphs() {
        let graph = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        let scene = scene_of(&graph);
        let mut o = render_options(0, Backend::Cpu, &graph, &path);
        (o.width, o.height, o.samples) = (29, 23, 4);
        o.band_rows = Some(23);
        let whole = render(&graph, &scene, &o).unwrap();
        assert_eq!(whole.pixels.len(), 29 * 23);
        for rows in [1, 3, 7] {
            o.band_rows = Some(rows);
            let banded = render(&graph, &scene, &o).unwrap();
            assert!(
                bits(&banded) == bits(&whole),
                "{}: bands of {rows} rows differ from one band",
                graph.name
            );
        }
    }
}

/// The planner's arithmetic, checked against the byte counts written out: the image is
/// 12 B/px, scene textures 112 B/texel at most 2048 on a side, samples 256 B each.
#[test]
fn the_memory_planner_fits_the_budget() {
    use matgraph::render::{MEMORY_BUDGET, plan_memory, scene_texture_size};
    const GIB: u64 = 1 << 30;
    assert_eq!(MEMORY_BUDGET, 2 * GIB);
    assert_eq!(scene_texture_size(512, 256), (512, 256));
    assert_eq!(scene_texture_size(8192, 4096), (2048, 1024));
    assert_eq!(scene_texture_size(16384, 3), (2048, 1));
    // 2048² × 64 spp: image 48 MiB, one row 2048·64·256 = 32 MiB: (2 GiB − 48 MiB) / 32 MiB
    // = 62.5 → 62 rows per band, 34 bands.
    let p = plan_memory(2048, 2048, 64, false, MEMORY_BUDGET).unwrap();
    assert_eq!(p.fixed_bytes, 2048 * 2048 * 12);
    assert_eq!((p.band_rows, p.bands), (62, 34));
    assert_eq!(p.band_bytes, 62 * 2048 * 64 * 256);
    assert!(p.fixed_bytes + p.band_bytes <= MEMORY_BUDGET);
    // With scene textures, 2048² × 112 B = 448 MiB more: (2048 − 48 − 448) / 32 = 48.5.
    let p = plan_memory(2048, 2048, 64, true, MEMORY_BUDGET).unwrap();
    assert_eq!(p.band_rows, 48);
    // 8192² × 64 spp, the issue's panic: bands of ≤ 2^32 / (8192·64) = 8192 rows by index,
    // (2 GiB − 768 MiB) / 128 MiB = 10 rows by memory.
    let p = plan_memory(8192, 8192, 64, false, MEMORY_BUDGET).unwrap();
    assert_eq!((p.band_rows, p.bands), (10, 820));
    // A small image is one band.
    let p = plan_memory(64, 48, 1, true, MEMORY_BUDGET).unwrap();
    assert_eq!((p.band_rows, p.bands), (48, 1));
    // Every allowed size and sample count either fits or is refused; nothing is allocated.
    for side in [1u32, 7, 512, 4096, 8192, 12000, 16384] {
        for spp in [1u32, 8, 64] {
            for scene in [false, true] {
                match plan_memory(side, side, spp, scene, MEMORY_BUDGET) {
                    Ok(p) => {
                        assert!(
                            p.fixed_bytes + p.band_bytes <= MEMORY_BUDGET,
                            "{side} {spp}"
                        );
                        assert!(side as u64 * p.band_rows as u64 * spp as u64 <= u32::MAX as u64);
                        assert_eq!(p.bands, side.div_ceil(p.band_rows));
                    }
                    Err(e) => assert!(side >= 12000, "{side}² × {spp}: {e}"),
                }
            }
        }
    }
}

/// A render that cannot fit is refused before anything is allocated, with an error naming
/// the budget: 16384² needs 3 GiB for its HDR image alone.
#[test]
fn an_oversized_render_is_refused_naming_the_budget() {
    use matgraph::render::RenderError;
    let e = matgraph::render::plan_memory(16384, 16384, 64, false, 2 << 30).unwrap_err();
    assert!(
        matches!(e, RenderError::Memory { needed, budget, .. } if needed == 16384 * 16384 * 12 + 16384 * 64 * 256 && budget == 2 << 30),
        "{e:?}"
    );
    let msg = e.to_string();
    assert!(
        msg.contains("16384x16384 at 64 spp")
            && msg.contains("3072 MiB image")
            && msg.contains("memory budget of 2048 MiB"),
        "{msg}"
    );
    // Through render(), with a tiny budget: refused, nothing rendered.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/toon_ball.json");
    let g = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
    let o = RenderOptions {
        width: 64,
        height: 64,
        memory_budget: 64 * 64 * 12 + 1000,
        ..RenderOptions::default()
    };
    let e = render(&g, &scene_of(&g), &o).unwrap_err();
    // The one budget (src/budget.rs) refuses the first thing that does not fit.
    assert!(
        e.to_string().contains("over the memory budget of 49.0 KiB"),
        "{e}"
    );
    // The command refuses 16384² up front: the output images alone exceed the budget.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args([
            "render",
            "graphs/toon_ball.json",
            "--size",
            "16384x16384",
            "--samples",
            "64",
            "-o",
        ])
        .arg(tempfile::tempdir().unwrap().path().join("big.png"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("16384x16384") && stderr.contains("memory budget of 2048 MiB"),
        "{stderr}"
    );
}
