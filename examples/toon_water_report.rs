//! Measurements of seed 004's cartoon water for docs/models/toon_water.md:
//! the angular error of GPU Gems' normal against the exact one over steepness 0…1, the
//! colour difference between the paper's depth colour and Beer–Lambert over the paper's
//! depth series, and the quadtree grid's vertex count and height error against the uniform
//! grid. `cargo run --release --example toon_water_report`.

use glam::{Vec2, Vec3};
use matgraph::nodes::toon_water::{DEFAULT_WAVES, Wave, depth_color, gerstner};
use matgraph::scene::WaterLod;
use std::f32::consts::TAU;

/// The scene's wave set with steepness scaled so that Σ Qᵢ kᵢ aᵢ = `s` (GPU Gems' Qᵢ =
/// s / (kᵢ aᵢ · N), s = 1 the fold threshold).
fn waves_at(s: f32) -> Vec<Wave> {
    let n = DEFAULT_WAVES.len() as f32;
    DEFAULT_WAVES
        .iter()
        .map(|w| {
            let ka = TAU / w.wavelength * w.amplitude;
            Wave {
                steepness: s / (ka * n),
                ..*w
            }
        })
        .collect()
}

fn normal_error() {
    println!(
        "## GPU Gems normal vs exact (scene wave set, 200 x 200 points over 80 m x 80 m, t = 0, 5, 10 s)"
    );
    println!("| Σ Q k a | mean (deg) | max (deg) |");
    println!("|---|---|---|");
    for s in [0.0, 0.1, 0.25, 0.5, 0.75, 0.9, 1.0] {
        let waves = waves_at(s);
        let (mut sum, mut max, mut n) = (0.0f64, 0.0f64, 0usize);
        for t in [0.0, 5.0, 10.0] {
            for i in 0..200 {
                for j in 0..200 {
                    let p = Vec3::new(-40.0 + 0.4 * i as f32, 0.0, -40.0 + 0.4 * j as f32);
                    let g = gerstner(p, t, &waves);
                    let a = (g.normal.angle_between(g.normal_gems) as f64).to_degrees();
                    sum += a;
                    max = max.max(a);
                    n += 1;
                }
            }
        }
        println!("| {s:.2} | {:.3} | {:.3} |", sum / n as f64, max);
    }
}

fn depth_difference() {
    println!("\n## paper exp(-sqrt(k d)) vs Beer-Lambert exp(-k d), half-lives (2, 12, 90) m");
    println!(
        "| depth (m) | paper RGB | Beer-Lambert RGB | max abs diff | CIE76 ΔE (linear RGB → Lab) |"
    );
    println!("|---|---|---|---|---|");
    let h = Vec3::new(2.0, 12.0, 90.0);
    for d in [3.0f32, 35.0, 85.0, 135.0, 156.0, 185.0] {
        let p = depth_color(d, h, 0);
        let b = depth_color(d, h, 1);
        let diff = (p - b).abs().max_element();
        println!(
            "| {d} | ({:.3}, {:.3}, {:.3}) | ({:.3}, {:.3}, {:.3}) | {diff:.3} | {:.1} |",
            p.x,
            p.y,
            p.z,
            b.x,
            b.y,
            b.z,
            delta_e(p, b)
        );
    }
}

/// CIE76 ΔE between two linear sRGB colours (D65).
fn delta_e(a: Vec3, b: Vec3) -> f32 {
    (lab(a) - lab(b)).length()
}

fn lab(c: Vec3) -> Vec3 {
    let x = 0.4124 * c.x + 0.3576 * c.y + 0.1805 * c.z;
    let y = 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
    let z = 0.0193 * c.x + 0.1192 * c.y + 0.9505 * c.z;
    let f = |t: f32| {
        if t > 0.008856 {
            t.cbrt()
        } else {
            7.787 * t + 16.0 / 116.0
        }
    };
    let (fx, fy, fz) = (f(x / 0.95047), f(y), f(z / 1.08883));
    Vec3::new(116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz))
}

fn lod() {
    println!("\n## quadtree LOD grid vs uniform 256 x 256 grid (80 m, camera (0, 3, 18))");
    let size = Vec2::new(80.0, 80.0);
    let eye = Vec3::new(0.0, 3.0, 18.0);
    let uniform_vertices = 257 * 257;
    println!(
        "| split_distance | vertices | triangles | of uniform | height RMS (mm) | height max (mm) | max within 10 m of the camera (mm) |"
    );
    println!("|---|---|---|---|---|---|---|");
    let waves = waves_at(0.59);
    for split in [1.0f32, 1.5, 2.0, 3.0] {
        let lod = WaterLod {
            levels: 5,
            block: 8,
            split_distance: split,
        };
        let mesh = lod.mesh(size, eye);
        // Heights of the waves at the LOD vertices, interpolated over its triangles at
        // every vertex of the uniform grid (where the uniform grid is exact).
        let cells = 256i64;
        let key = |p: Vec3| {
            (
                ((p.x + 40.0) / 80.0 * cells as f32).round() as i64,
                ((40.0 - p.z) / 80.0 * cells as f32).round() as i64,
            )
        };
        let height = |i: i64, j: i64| {
            let p = Vec3::new(
                -40.0 + 80.0 * i as f32 / cells as f32,
                0.0,
                40.0 - 80.0 * j as f32 / cells as f32,
            );
            gerstner(p, 2.0, &waves).offset.y as f64
        };
        let hv: Vec<f64> = mesh
            .positions
            .iter()
            .map(|&p| {
                let (i, j) = key(p);
                height(i, j)
            })
            .collect();
        let mut interp = vec![f64::NAN; ((cells + 1) * (cells + 1)) as usize];
        for t in &mesh.indices {
            let v = t.map(|k| key(mesh.positions[k as usize]));
            let h = t.map(|k| hv[k as usize]);
            let (x0, x1) = (
                v.iter().map(|p| p.0).min().unwrap(),
                v.iter().map(|p| p.0).max().unwrap(),
            );
            let (y0, y1) = (
                v.iter().map(|p| p.1).min().unwrap(),
                v.iter().map(|p| p.1).max().unwrap(),
            );
            let area = ((v[1].0 - v[0].0) * (v[2].1 - v[0].1)
                - (v[2].0 - v[0].0) * (v[1].1 - v[0].1)) as f64;
            for j in y0..=y1 {
                for i in x0..=x1 {
                    let w = |a: (i64, i64), b: (i64, i64)| {
                        ((b.0 - a.0) * (j - a.1) - (i - a.0) * (b.1 - a.1)) as f64 / area
                    };
                    let (w0, w1, w2) = (w(v[1], v[2]), w(v[2], v[0]), w(v[0], v[1]));
                    if w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0 {
                        interp[(j * (cells + 1) + i) as usize] = w0 * h[0] + w1 * h[1] + w2 * h[2];
                    }
                }
            }
        }
        let (mut sq, mut max, mut near, mut n) = (0.0f64, 0.0f64, 0.0f64, 0usize);
        for j in 0..=cells {
            for i in 0..=cells {
                let e = (interp[(j * (cells + 1) + i) as usize] - height(i, j)).abs();
                assert!(e.is_finite(), "uncovered lattice point ({i}, {j})");
                sq += e * e;
                max = max.max(e);
                let (x, z) = (
                    -40.0 + 80.0 * i as f32 / 256.0,
                    40.0 - 80.0 * j as f32 / 256.0,
                );
                if ((x - eye.x).powi(2) + (z - eye.z).powi(2)).sqrt() < 10.0 {
                    near = near.max(e);
                }
                n += 1;
            }
        }
        println!(
            "| {split} | {} | {} | {:.1}% | {:.1} | {:.1} | {:.1} |",
            mesh.vertex_count(),
            mesh.triangle_count(),
            100.0 * mesh.vertex_count() as f64 / uniform_vertices as f64,
            1e3 * (sq / n as f64).sqrt(),
            1e3 * max,
            1e3 * near
        );
    }
}

/// Render timings of the paper's water and both baselines (release build; median of
/// `runs` after one warm-up), whole render and per stage.
fn cost() {
    use matgraph::gpu::Backend;
    use matgraph::render::{RenderOptions, graph_scene, render_timed};
    let runs = 5;
    println!("\n## render cost, 640 x 480, 1 spp, median of {runs} (after one warm-up)");
    println!(
        "| graph | backend | total (ms) | fps | displace (ms) | gbuffer + maps (ms) | shade (ms) | vs paper's water |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs");
    for backend in [Backend::Cpu, Backend::Gpu] {
        let mut paper_ms = 0.0;
        for name in ["water_toon_day", "water_toon_eden", "water_toon_you"] {
            let graph = matgraph::io::load_graph(
                &dir.join(format!("{name}.json")),
                matgraph::Registry::builtin(),
            )
            .expect("bundled graph");
            let scene = graph_scene(&graph).unwrap().unwrap();
            let options = RenderOptions {
                width: 640,
                height: 480,
                time: Some(1.0),
                backend,
                ..RenderOptions::default()
            };
            if let Err(e) = render_timed(&graph, &scene, &options) {
                println!("| {name} | {backend:?} | skipped: {e} | | | | | |");
                continue;
            }
            let mut all = Vec::new();
            for _ in 0..runs {
                let start = std::time::Instant::now();
                let (_, t) = render_timed(&graph, &scene, &options).unwrap();
                all.push((start.elapsed().as_secs_f64() * 1e3, t));
            }
            all.sort_by(|a, b| a.0.total_cmp(&b.0));
            let (ms, t) = all.swap_remove(runs / 2);
            if name == "water_toon_day" {
                paper_ms = ms;
            }
            println!(
                "| {name} | {backend:?} | {ms:.0} | {:.2} | {:.0} | {:.0} | {:.0} | {:+.0}% |",
                1e3 / ms,
                t.displace.as_secs_f64() * 1e3,
                t.gbuffer.as_secs_f64() * 1e3,
                t.shade.as_secs_f64() * 1e3,
                100.0 * (paper_ms / ms - 1.0)
            );
        }
    }
}

fn main() {
    normal_error();
    depth_difference();
    lod();
    cost();
}
