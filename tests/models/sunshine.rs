//! Seed 002, Super Mario Sunshine's water (`graphs/water_sunshine*.json`): the committed wave
//! textures are the generator's bytes; the authored mip chain is black, lit and brightest
//! where the post says; the G-buffer's uv derivatives match finite differences of the camera
//! rays; the bright band sits where the mip-level formula puts it and moves as the camera
//! rises; the alpha test drops the fraction of texels its thresholds imply; CPU and GPU pick
//! the same mip level and agree; renders are the same bytes on every run.

use crate::common;

#[path = "../../examples/sunshine_waves/gen.rs"]
#[allow(dead_code)]
mod generator;

use matgraph::gpu::{Backend, GpuPlan};
use matgraph::render::{RenderOptions, render};
use matgraph::scene::Scene;
use matgraph::texture::{Texture, TextureSet};
use matgraph::{Attribute, Graph, Plan, PlanOptions, Registry, SampleBatch};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The three bundled graphs of seed 002.
const GRAPHS: [&str; 3] = [
    "water_sunshine",
    "water_sunshine_sunset",
    "water_sunshine_fresnel",
];

/// Side of the water plane in metres (the water scene's default `size`).
const PLANE: f64 = 80.0;

fn graph_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("graphs")
        .join(format!("{name}.json"))
}

fn texture_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/textures/sunshine")
}

fn load(name: &str) -> Graph {
    matgraph::io::load_graph(&graph_path(name), Registry::builtin())
        .unwrap_or_else(|e| panic!("{e}"))
}

/// `name`'s graph with its outputs replaced and, when given, its scene: edited as JSON, so
/// every node stays as the file has it.
fn variant(name: &str, outputs: &[(&str, &str)], scene: Option<serde_json::Value>) -> Graph {
    let text = std::fs::read_to_string(graph_path(name)).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    doc["outputs"] = outputs
        .iter()
        .map(|(n, f)| serde_json::json!({ "name": n, "from": f }))
        .collect();
    if let Some(scene) = scene {
        doc["scene"] = scene;
    }
    Graph::from_json(&doc.to_string(), Registry::builtin()).unwrap_or_else(|e| panic!("{e:?}"))
}

fn textures_of(graph: &Graph, name: &str) -> TextureSet {
    matgraph::image_io::load_graph_textures(graph, &graph_path(name)).unwrap()
}

/// The texture that node `id` of `graph` samples.
fn texture_of<'a>(graph: &Graph, set: &'a TextureSet, id: &str) -> &'a Texture {
    let node = &graph.nodes()[graph.node_index(id).unwrap()];
    let key = node.texture.as_ref().unwrap().key();
    set.get(set.index_of(&key).unwrap()).unwrap()
}

/// The default value of float parameter `name` of `graph`.
fn parameter(graph: &Graph, name: &str) -> f32 {
    let plan = Plan::compile(graph, &PlanOptions::default()).unwrap();
    plan.default_parameters().get(name).unwrap().as_f32()
}

/// sRGB code → linear, in f64 (IEC 61966-2-1), written here independently of image_io.
fn srgb_code_to_linear(code: u8) -> f64 {
    let c = code as f64 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The red channel's 8-bit codes of a PNG, decoded by the image crate directly.
fn png_codes(path: &Path) -> (u32, u32, Vec<u8>) {
    let img = image::open(path).unwrap().to_rgba8();
    let (w, h) = img.dimensions();
    (w, h, img.pixels().map(|p| p.0[0]).collect())
}

#[test]
fn committed_textures_are_the_generators_bytes() {
    let files = generator::files();
    // The generator is deterministic: a second run gives the same texels.
    assert_eq!(files, generator::files());
    let dir = tempfile::tempdir().unwrap();
    let mut names: Vec<String> = Vec::new();
    for (name, image) in &files {
        let path = dir.path().join(name);
        matgraph::image_io::save_png(&path, image).unwrap();
        let made = std::fs::read(&path).unwrap();
        let committed = std::fs::read(texture_dir().join(name))
            .unwrap_or_else(|e| panic!("{name}: {e} (run the sunshine_waves example)"));
        assert!(
            made == committed,
            "{name}: the committed PNG is not the generator's output; rerun \
             `cargo run --example sunshine_waves`"
        );
        names.push(name.clone());
    }
    // No stale file: the folder holds exactly what the generator writes.
    let mut on_disk: Vec<String> = std::fs::read_dir(texture_dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    on_disk.sort();
    names.sort();
    assert_eq!(on_disk, names);
    // They tile: the wave is a sum of whole-cycle cosines, so the texel past the right edge
    // (x = N, i.e. x = 0) continues the row as smoothly as any neighbour does.
    for (name, seed, dir) in generator::WAVES {
        let img = generator::wave(seed, dir);
        let n = img.width;
        let step = |x0: u32, x1: u32, y: u32| (img.texel(x0, y)[0] - img.texel(x1, y)[0]).abs();
        let (mut seam, mut inside) = (0.0f32, 0.0f32);
        for y in 0..n {
            seam = seam.max(step(n - 1, 0, y));
            inside = inside.max((1..n).map(|x| step(x - 1, x, y)).fold(0.0, f32::max));
        }
        assert!(
            seam <= inside,
            "{name}: seam step {seam} > largest inner step {inside}"
        );
    }
}

#[test]
fn authored_levels_are_black_lit_and_brightest_at_the_third() {
    for name in GRAPHS {
        let graph = load(name);
        let set = textures_of(&graph, name);
        for id in ["band1", "band2"] {
            let tex = texture_of(&graph, &set, id);
            let sizes: Vec<u32> = tex.levels().iter().map(|l| l.width).collect();
            assert_eq!(sizes, [128, 64, 32, 16, 8, 4, 2, 1], "{name} {id}");
            let stats: Vec<(f32, f32)> = tex
                .levels()
                .iter()
                .map(|l| {
                    let max = l
                        .data
                        .iter()
                        .map(|t| t[0].max(t[1]).max(t[2]))
                        .fold(0.0, f32::max);
                    let mean =
                        l.data.iter().map(|t| t[0] as f64).sum::<f64>() / l.data.len() as f64;
                    (max, mean as f32)
                })
                .collect();
            // The largest level and the smallest ones are black: every texel exactly 0.
            for k in [0, 5, 6, 7] {
                assert_eq!(stats[k].0, 0.0, "{name} {id}: level {k} is not black");
            }
            // The middle ones are lit, the third (index 2) the brightest, reaching white.
            for k in 1..=4 {
                assert!(
                    stats[k].1 > 0.02,
                    "{name} {id}: level {k} is dark: {stats:?}"
                );
            }
            for k in [1, 3, 4] {
                assert!(
                    stats[2].1 > stats[k].1,
                    "{name} {id}: level 2 not brightest: {stats:?}"
                );
            }
            assert_eq!(stats[2].0, 1.0, "{name} {id}: level 2 does not reach white");
            // Greyscale: r = g = b everywhere.
            assert!(
                tex.levels()
                    .iter()
                    .flat_map(|l| &l.data)
                    .all(|t| t[0] == t[1] && t[1] == t[2])
            );
        }
    }
}

/// A pinhole camera as `scene::camera` documents it, in f64: the ray direction through pixel
/// coordinates (px, py), top-left origin.
struct Cam {
    origin: [f64; 3],
    forward: [f64; 3],
    right: [f64; 3],
    up: [f64; 3],
    tan: f64,
    width: f64,
    height: f64,
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn norm(a: [f64; 3]) -> [f64; 3] {
    let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

impl Cam {
    fn new(position: [f64; 3], target: [f64; 3], fov_y_deg: f64, width: u32, height: u32) -> Cam {
        let forward = norm(sub(target, position));
        let right = norm(cross(forward, [0.0, 1.0, 0.0]));
        let up = cross(right, forward);
        Cam {
            origin: position,
            forward,
            right,
            up,
            tan: (fov_y_deg.to_radians() / 2.0).tan(),
            width: width as f64,
            height: height as f64,
        }
    }

    /// Where the ray through (px, py) meets the water plane y = 0, as water-plane uv
    /// (u = (x + 40)/80 along +x, v = (40 − z)/80 along −z), or None above the horizon.
    fn uv_on_water(&self, px: f64, py: f64) -> Option<[f64; 2]> {
        let sx = (2.0 * px / self.width - 1.0) * self.tan * self.width / self.height;
        let sy = (1.0 - 2.0 * py / self.height) * self.tan;
        let d: Vec<f64> = (0..3)
            .map(|i| self.forward[i] + self.right[i] * sx + self.up[i] * sy)
            .collect();
        if d[1] >= 0.0 {
            return None;
        }
        let t = -self.origin[1] / d[1];
        let (x, z) = (self.origin[0] + t * d[0], self.origin[2] + t * d[2]);
        Some([(x + PLANE / 2.0) / PLANE, (PLANE / 2.0 - z) / PLANE])
    }

    /// The derivatives of the uv per pixel along x and along y, by central differences over
    /// 1/64 pixel (their error, O(step²), is below 1e-6 of the value here).
    fn uv_differences(&self, px: f64, py: f64) -> Option<([f64; 2], [f64; 2])> {
        let e = 1.0 / 128.0;
        let (l, r) = (self.uv_on_water(px - e, py)?, self.uv_on_water(px + e, py)?);
        let (t, b) = (self.uv_on_water(px, py - e)?, self.uv_on_water(px, py + e)?);
        let k = 1.0 / (2.0 * e);
        Some((
            [(r[0] - l[0]) * k, (r[1] - l[1]) * k],
            [(b[0] - t[0]) * k, (b[1] - t[1]) * k],
        ))
    }

    /// The mip level of the wave textures at (px, py): log2 of the longer side of the
    /// footprint in texels, with `texels_per_uv` = tiling × texture size.
    fn lod(&self, px: f64, py: f64, texels_per_uv: f64) -> Option<f64> {
        let (dx, dy) = self.uv_differences(px, py)?;
        let len = |d: [f64; 2]| d[0].hypot(d[1]) * texels_per_uv;
        Some(len(dx).max(len(dy)).log2())
    }
}

/// A water scene without objects, seen from `(0, height, 18)` with the default camera's
/// pitch (towards `(0, height − 3, 0)`), 50° field of view.
fn water_scene(height: f64) -> serde_json::Value {
    serde_json::json!({
        "kind": { "water": { "objects": [] } },
        "camera": {
            "position": [0.0, height, 18.0],
            "target": [0.0, height - 3.0, 0.0],
            "fov_y_deg": 50.0
        }
    })
}

#[test]
fn gbuffer_uv_derivatives_are_the_quads_fine_differences() {
    let (w, h) = (160u32, 120u32);
    let scene = Scene::from_json(&water_scene(3.0).to_string()).unwrap();
    let g = scene.gbuffer(&scene.material_mesh(), w, h, 1);
    let cam = Cam::new([0.0, 3.0, 18.0], [0.0, 0.0, 0.0], 50.0, w, h);
    let n = g.samples.len();
    assert!(n > 5000, "{n} water samples");
    let (dx, dy) = (
        g.batch.column(Attribute::UvDx).unwrap(),
        g.batch.column(Attribute::UvDy).unwrap(),
    );
    let (mut worst, mut compared) = (0.0f64, 0usize);
    let mut first_order = Vec::new();
    for (k, &index) in g.samples.iter().enumerate() {
        let (x, y, _) = g.sample_coords(index);
        // dpdxFine: the uv difference between the quad's two pixel centres on this row;
        // dpdyFine: in this column.
        let (x0, y0) = ((x & !1) as f64 + 0.5, (y & !1) as f64 + 0.5);
        let (xc, yc) = (x as f64 + 0.5, y as f64 + 0.5);
        let quad = || -> Option<[f64; 4]> {
            let (a, b) = (cam.uv_on_water(x0, yc)?, cam.uv_on_water(x0 + 1.0, yc)?);
            let (c, d) = (cam.uv_on_water(xc, y0)?, cam.uv_on_water(xc, y0 + 1.0)?);
            Some([b[0] - a[0], b[1] - a[1], d[0] - c[0], d[1] - c[1]])
        };
        let Some(want) = quad() else {
            continue;
        };
        let got = [
            dx[k] as f64,
            dx[n + k] as f64,
            dy[k] as f64,
            dy[n + k] as f64,
        ];
        let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for c in 0..4 {
            // f64 on both sides; the f32 attribute rounds to 6e-8 relative.
            let err = (got[c] - want[c]).abs() / scale;
            worst = worst.max(err);
            assert!(
                err < 1e-6,
                "pixel ({x}, {y}) component {c}: {} vs {}",
                got[c],
                want[c]
            );
        }
        // Signs as documented: u grows to the right, v (along −z) decreases down the screen.
        assert!(got[0] > 0.0 && got[3] < 0.0, "pixel ({x}, {y}): {got:?}");
        // A first-order estimate of the derivative ∂v/∂y (the exact one, by f64 central
        // differences over 1/64 pixel): collected, checked below.
        let (_, ey) = cam.uv_differences(xc, yc).unwrap();
        first_order.push((got[3] - ey[1]).abs() / ey[1].abs());
        compared += 1;
    }
    assert!(compared > 5000);
    first_order.sort_by(f64::total_cmp);
    let median = first_order[first_order.len() / 2];
    let max = first_order[first_order.len() - 1];
    eprintln!(
        "uv derivatives: worst relative difference {worst:.2e} from the quad differences over \
         {compared} samples; ∂v/∂y differs from the exact derivative by {:.2}% (median), \
         {:.1}% (max, next to the horizon)",
        median * 100.0,
        max * 100.0
    );
    assert!(median < 0.05 && max < 0.5, "{median} {max}");
}

/// Per image row (top to bottom), the mean over the columns of a render of the band value,
/// and the same mean predicted from the camera rays alone: at each pixel the mip level λ of
/// the f64 footprint, and the band's expected value there, the sum over the two wave
/// textures of their level means blended linearly at λ (trilinear filtering averages to
/// that). None for rows that do not see the water well inside its far edge.
fn band_profiles(
    graph: &Graph,
    chains: &[&Texture],
    texels_per_uv: f64,
    height: f64,
    (w, h): (u32, u32),
) -> (Vec<Option<(f64, f64)>>, Cam) {
    let scene = Scene::from_json(&water_scene(height).to_string()).unwrap();
    let textures = textures_of(graph, "water_sunshine");
    let options = RenderOptions {
        width: w,
        height: h,
        samples: 1,
        backend: Backend::Cpu,
        textures: Some(Arc::new(textures)),
        ..RenderOptions::default()
    };
    let image = render(graph, &scene, &options).unwrap();
    let cam = Cam::new([0.0, height, 18.0], [0.0, height - 3.0, 0.0], 50.0, w, h);
    let means: Vec<Vec<f64>> = chains
        .iter()
        .map(|t| {
            t.levels()
                .iter()
                .map(|l| l.data.iter().map(|t| t[0] as f64).sum::<f64>() / l.data.len() as f64)
                .collect()
        })
        .collect();
    let expected = |lod: f64| -> f64 {
        means
            .iter()
            .map(|m| {
                let l = lod.clamp(0.0, (m.len() - 1) as f64);
                let k = (l.floor() as usize).min(m.len() - 2);
                m[k] + (m[k + 1] - m[k]) * (l - k as f64)
            })
            .sum()
    };
    let rows = (0..h)
        .map(|y| {
            let py = y as f64 + 0.5;
            // Only rows whose every pixel sees the plane well inside its edges.
            for px in [0.5, w as f64 - 0.5] {
                let uv = cam.uv_on_water(px, py)?;
                if uv[1] > 0.95 || !(0.05..0.95).contains(&uv[0]) {
                    return None;
                }
            }
            let (mut got, mut want) = (0.0, 0.0);
            for x in 0..w {
                got += image.pixels[(y * w + x) as usize][0] as f64;
                want += expected(cam.lod(x as f64 + 0.5, py, texels_per_uv)?);
            }
            Some((got / w as f64, want / w as f64))
        })
        .collect();
    (rows, cam)
}

/// The band's centre row (the profile's centroid, Σ y·v / Σ v) and its peak row (of the
/// profile smoothed over 13 rows, which averages out the waves' pattern).
fn band_rows(profile: &[Option<f64>]) -> (f64, usize) {
    let v: Vec<f64> = profile.iter().map(|p| p.unwrap_or(0.0)).collect();
    let total: f64 = v.iter().sum();
    let centroid = v.iter().enumerate().map(|(y, v)| y as f64 * v).sum::<f64>() / total;
    let smooth: Vec<f64> = (0..v.len())
        .map(|i| {
            let (a, b) = (i.saturating_sub(6), (i + 7).min(v.len()));
            v[a..b].iter().sum::<f64>() / (b - a) as f64
        })
        .collect();
    let peak = (0..v.len())
        .max_by(|&a, &b| smooth[a].total_cmp(&smooth[b]))
        .unwrap();
    (centroid, peak)
}

#[test]
fn the_band_sits_where_the_mip_level_puts_it_and_moves_as_the_camera_rises() {
    let graph = variant("water_sunshine", &[("band", "band.result")], None);
    let file = load("water_sunshine");
    let tiling = parameter(&file, "tiling") as f64;
    let set = textures_of(&file, "water_sunshine");
    let chains = [
        texture_of(&file, &set, "band1"),
        texture_of(&file, &set, "band2"),
    ];
    let texels_per_uv = tiling * chains[0].width() as f64;
    let size = (256u32, 192u32);
    let mut measured = Vec::new();
    for height in [3.0, 6.0] {
        let (profile, cam) = band_profiles(&graph, &chains, texels_per_uv, height, size);
        let got: Vec<Option<f64>> = profile.iter().map(|p| p.map(|p| p.0)).collect();
        let want: Vec<Option<f64>> = profile.iter().map(|p| p.map(|p| p.1)).collect();
        let (centre, peak) = band_rows(&got);
        let (want_centre, want_peak) = band_rows(&want);
        let lod = |y: usize| cam.lod(size.0 as f64 / 2.0, y as f64 + 0.5, texels_per_uv);
        // Distance along the water from below the camera to the band's peak row.
        let uv = cam
            .uv_on_water(size.0 as f64 / 2.0, peak as f64 + 0.5)
            .unwrap();
        let distance = 18.0 - (PLANE / 2.0 - uv[1] * PLANE);
        eprintln!(
            "camera {height} m: band centre row {centre:.1}, peak row {peak} (λ = {:.2} at the \
             image centre, {distance:.1} m ahead); predicted centre {want_centre:.1}, peak \
             {want_peak}",
            lod(peak).unwrap()
        );
        assert!(
            (centre - want_centre).abs() <= 3.0 && peak.abs_diff(want_peak) <= 5,
            "camera {height} m: band centre {centre:.1}, peak {peak}; the mip level puts them \
             at {want_centre:.1}, {want_peak}"
        );
        // Row by row the image follows the prediction, up to the waves' pattern.
        let peak_value = want[want_peak].unwrap();
        for (y, p) in profile.iter().enumerate() {
            if let Some((g, w)) = p {
                assert!(
                    (g - w).abs() <= 0.25 * peak_value,
                    "camera {height} m, row {y}: band {g:.3}, predicted {w:.3}"
                );
            }
        }
        // Water nearer than level 0 and farther than level 5 is clear: the band's value
        // there is below a tenth of the peak's. From 3 m both show in the image.
        let mut clear = (0, 0);
        for (y, p) in got.iter().enumerate() {
            let (Some(v), Some(l)) = (p, lod(y)) else {
                continue;
            };
            if !(0.0..=5.0).contains(&l) {
                assert!(
                    *v < peak_value / 10.0,
                    "camera {height} m, row {y} (λ = {l:.2}): {v}"
                );
                if l < 0.0 { clear.0 += 1 } else { clear.1 += 1 }
            }
        }
        if height == 3.0 {
            assert!(
                clear.0 >= 5 && clear.1 >= 5,
                "clear rows near, far: {clear:?}"
            );
        }
        measured.push((centre, peak, distance));
    }
    // Raising the camera with the same pitch moves the band farther out over the water (the
    // footprint along the view grows as (d² + h²)/h, so its level is reached farther away)
    // and down the image (it is seen at a steeper angle below the horizon).
    let ((c3, p3, d3), (c6, p6, d6)) = (measured[0], measured[1]);
    assert!(
        c6 > c3 + 10.0 && p6 > p3,
        "band rows: centre {c3:.1} → {c6:.1}, peak {p3} → {p6}"
    );
    assert!(d6 > d3 + 2.0, "band distance {d3:.1} m → {d6:.1} m");
}

#[test]
fn alpha_test_drops_the_fraction_its_thresholds_imply() {
    let file = load("water_sunshine");
    let (low, high) = (
        parameter(&file, "alpha_low") as f64,
        parameter(&file, "alpha_high") as f64,
    );
    // Over the brightest level of the band: texel i of wave 1 plus texel i shifted by
    // (11, 5) of wave 2, the sum the graph's alpha test sees when the two layers lie so.
    let level = 2;
    let (w, h, c1) = png_codes(&texture_dir().join(format!("wave1_band_{level}.png")));
    let (_, _, c2) = png_codes(&texture_dir().join(format!("wave2_band_{level}.png")));
    let pair = |i: usize| {
        let (x, y) = (i % w as usize, i / w as usize);
        let j = ((y + 5) % h as usize) * w as usize + (x + 11) % w as usize;
        (c1[i], c2[j])
    };
    let n = (w * h) as usize;
    // Expected: from the joint histogram of the 8-bit codes, decoded in f64.
    let mut hist = vec![0u32; 256 * 256];
    for i in 0..n {
        let (a, b) = pair(i);
        hist[a as usize * 256 + b as usize] += 1;
    }
    let mut expected = 0u32;
    for a in 0..256 {
        for b in 0..256 {
            let v = srgb_code_to_linear(a as u8) + srgb_code_to_linear(b as u8);
            if low < v && v < high {
                expected += hist[a * 256 + b];
            }
        }
    }
    // Counted: the graph's alpha_test node over the texels of the loaded chain.
    let set = textures_of(&file, "water_sunshine");
    let (t1, t2) = (
        texture_of(&file, &set, "band1"),
        texture_of(&file, &set, "band2"),
    );
    let (l1, l2) = (&t1.levels()[level].data, &t2.levels()[level].data);
    let values: Vec<[f32; 3]> = (0..n)
        .map(|i| {
            let (x, y) = (i % w as usize, i / w as usize);
            let j = ((y + 5) % h as usize) * w as usize + (x + 11) % w as usize;
            [l1[i][0] + l2[j][0], 0.0, 0.0]
        })
        .collect();
    let test = Graph::from_json(
        r#"{"version": 1, "name": "alpha", "nodes": [
            {"id": "geo", "type": "geometry"},
            {"id": "v", "type": "split", "inputs": {"v": {"link": "geo.position"}}},
            {"id": "low", "type": "parameter", "inputs": {"value": 0.0}},
            {"id": "high", "type": "parameter", "inputs": {"value": 0.0}},
            {"id": "test", "type": "alpha_test", "inputs": {"value": {"link": "v.x"},
              "low": {"link": "low.value"}, "high": {"link": "high.value"}}}],
          "outputs": [{"name": "alpha", "from": "test.alpha"}],
          "parameters": [{"name": "low", "node": "low"}, {"name": "high", "node": "high"}]}"#,
        Registry::builtin(),
    )
    .unwrap();
    let plan = Plan::compile(&test, &PlanOptions::default()).unwrap();
    let mut params = plan.default_parameters();
    params
        .set("low", matgraph::Value::float(low as f32))
        .unwrap();
    params
        .set("high", matgraph::Value::float(high as f32))
        .unwrap();
    let mut batch = SampleBatch::new(n);
    batch.set_values(Attribute::Position, &values).unwrap();
    let out = plan.execute(&batch, &params).unwrap();
    let dropped = out.planar(0).iter().filter(|&&a| a == 0.0).count() as u32;
    assert!(out.planar(0).iter().all(|&a| a == 0.0 || a == 1.0));
    let fraction = dropped as f64 / n as f64;
    eprintln!(
        "alpha test ({low}, {high}) over level {level}: {dropped} of {n} texels dropped \
         ({:.1}%), histogram says {expected}",
        fraction * 100.0
    );
    assert_eq!(dropped, expected);
    // Meaningful thresholds: mid values are the majority and dropped, and extremes on both
    // sides are kept.
    assert!((0.3..0.95).contains(&fraction), "{fraction}");
    assert!(values.iter().any(|v| v[0] as f64 <= low));
    assert!(values.iter().any(|v| v[0] as f64 >= high));
}

#[test]
fn cpu_and_gpu_pick_the_same_mip_level_and_agree() {
    let Some(ctx) = common::gpu_context("cpu_and_gpu_pick_the_same_mip_level_and_agree") else {
        return;
    };
    let vulkan = ctx.adapter_info().backend == wgpu::Backend::Vulkan;
    for name in GRAPHS {
        let file = load(name);
        let graph = variant(
            name,
            &[
                ("emission", "shade.result"),
                ("alpha", "alpha_test.alpha"),
                ("lod", "lod.lod"),
                ("band", "band.result"),
            ],
            None,
        );
        let scene = matgraph::render::graph_scene(&file).unwrap().unwrap();
        let (w, h) = (192u32, 144u32);
        let g = scene.gbuffer(&scene.material_mesh(), w, h, 1);
        let mut set = textures_of(&graph, name);
        let scene_set = matgraph::render::scene_texture_set(&graph, &scene, w, h, None).unwrap();
        set.extend_shared(&scene_set).unwrap();
        let mut batch = g.batch.clone();
        batch.set_textures(Arc::new(set));
        let options = PlanOptions::default();
        let plan = Plan::compile(&graph, &options).unwrap();
        let params = plan.default_parameters();
        let cpu = plan.execute(&batch, &params).unwrap();
        let gpu = GpuPlan::compile(ctx, &graph, &options)
            .unwrap()
            .execute(&batch, &params)
            .unwrap();
        let n = cpu.len();
        let lod = cpu.planar(2);
        let (lo, hi) = lod
            .iter()
            .fold((f32::MAX, f32::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        // The level selection is exercised: the water spans the chain's levels.
        assert!(lo < 0.0 && hi > 4.0, "{name}: lod {lo}..{hi}");
        let mut differing = [0usize; 4];
        let mut max_err = [0.0f64; 4];
        for k in 0..4 {
            for (a, b) in cpu.planar(k).iter().zip(gpu.planar(k)) {
                if a.to_bits() != b.to_bits() {
                    differing[k] += 1;
                }
                let err = (*a as f64 - *b as f64).abs();
                max_err[k] = max_err[k].max(err);
                assert!(
                    err <= 1e-5 + 1e-4 * a.abs() as f64,
                    "{name}: output {k}: {a} vs {b}"
                );
            }
        }
        eprintln!(
            "{name}: {n} samples, lod {lo:.2}..{hi:.2}; values differing (emission, alpha, lod, \
             band): {differing:?}, max |Δ| {max_err:?}"
        );
        if vulkan {
            // On Vulkan the same f32 operations give the same bits: the level, the band and
            // the alpha test agree exactly.
            assert_eq!(differing[2], 0, "{name}: mip levels differ");
            assert_eq!(differing[1], 0, "{name}: alpha test differs");
            assert_eq!(differing[3], 0, "{name}: band differs");
        }
    }
}

#[test]
fn renders_are_the_same_bytes_on_every_run() {
    for name in GRAPHS {
        let graph = load(name);
        let scene = matgraph::render::graph_scene(&graph).unwrap().unwrap();
        let options = RenderOptions {
            width: 96,
            height: 72,
            samples: 1,
            time: Some(1.5),
            textures: Some(Arc::new(textures_of(&graph, name))),
            ..RenderOptions::default()
        };
        let a = render(&graph, &scene, &options).unwrap().to_srgb8(0.0);
        let b = render(&graph, &scene, &options).unwrap().to_srgb8(0.0);
        assert!(a.pixels == b.pixels, "{name}: two renders differ");
        // The waves scroll: another time gives another image.
        let later = RenderOptions {
            time: Some(4.0),
            ..options.clone()
        };
        let c = render(&graph, &scene, &later).unwrap().to_srgb8(0.0);
        assert!(a.pixels != c.pixels, "{name}: time does not move the waves");
    }
}
