//! Issue 38: the WebGPU page `examples/web/` (plain HTML and JavaScript) binds six bundled
//! graphs of different families from their contract, `bake-env`'s scene textures and view
//! alone, draws them in headless Chromium on SwiftShader (`examples/web/run.mjs`), and its
//! linear pixels match `matgraph render --exr` of the same view inside the material's
//! silhouette. Needs `chromium` (or `$CHROMIUM`) and `node`; skipped with a line when either
//! is missing, a failure when `MATGRAPH_REQUIRE_BROWSER` is set (CI sets it).

use crate::common;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Image side of the comparisons.
const SIZE: u32 = 96;

/// The graphs drawn: the metal and the dielectric PBR models, the two skin models, the toon
/// shader and the textured brick wall (file textures, a normal map read through the
/// tangent buffer), with a parameter set through the page on one; each with the share of
/// its inside pixels that must lie within the bound. The glass refracts the room's checker
/// pattern through a magnifying sphere: a direction a few ulps apart on the two sides
/// lands on the other square at a checker edge, so its bound holds on fewer pixels (and
/// its mean on all of them).
const CASES: [(&str, Option<&str>, f64); 7] = [
    ("pbr_gold", None, 0.99),
    ("pbr_gold", Some("roughness=0.6"), 0.99),
    ("pbr_glass", None, 0.80),
    ("skin", None, 0.99),
    ("skin_dipole", None, 0.99),
    ("toon_ball", None, 0.99),
    ("brick_wall", None, 0.99),
];

/// The mean |web − render| over every inside pixel and channel, for every case.
const MEAN: f64 = 5e-3;

fn repo() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn matgraph(args: &[&std::ffi::OsStr]) {
    let out = Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "matgraph {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Whether `program --version` runs.
fn runs(program: &str) -> bool {
    Command::new(program)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Little-endian f32s of base64 `text`.
fn f32s_of_base64(text: &str) -> Vec<f32> {
    let value = |c: u8| -> u32 {
        match c {
            b'A'..=b'Z' => (c - b'A') as u32,
            b'a'..=b'z' => (c - b'a') as u32 + 26,
            b'0'..=b'9' => (c - b'0') as u32 + 52,
            b'+' => 62,
            b'/' => 63,
            _ => panic!("not base64: {c}"),
        }
    };
    let mut bytes = Vec::with_capacity(text.len() * 3 / 4);
    for chunk in text.as_bytes().chunks(4) {
        let n = chunk.iter().filter(|&&c| c != b'=').count();
        let v = chunk[..n]
            .iter()
            .enumerate()
            .fold(0u32, |v, (k, &c)| v | value(c) << (18 - 6 * k));
        bytes.extend(&v.to_be_bytes()[1..n]);
    }
    bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect()
}

/// What one case measured: pixels compared, worst and mean |web − render| over RGB, and
/// the share within the bound.
struct Measured {
    pixels: usize,
    worst: f32,
    mean: f64,
    within: f64,
}

/// Per channel: |web − render| ≤ ABS + REL · |render| (linear radiance).
const ABS: f32 = 4e-3;
const REL: f32 = 1e-2;

fn compare(web: &[f32], reference: &[f32], w: usize, h: usize) -> Measured {
    let alpha = |x: usize, y: usize| web[4 * (y * w + x) + 3];
    let (mut pixels, mut worst, mut sum, mut ok) = (0usize, 0f32, 0f64, 0usize);
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            // Inside the silhouette: the pixel and its eight neighbours fully covered.
            if (0..9).any(|k| alpha(x + k % 3 - 1, y + k / 3 - 1) < 0.999) {
                continue;
            }
            pixels += 1;
            let i = 4 * (y * w + x);
            let mut good = true;
            for c in 0..3 {
                let (a, b) = (web[i + c], reference[i + c]);
                let d = (a - b).abs();
                worst = worst.max(d);
                sum += f64::from(d);
                good &= d <= ABS + REL * b.abs();
            }
            ok += usize::from(good);
        }
    }
    Measured {
        pixels,
        worst,
        mean: sum / (3 * pixels.max(1)) as f64,
        within: ok as f64 / pixels.max(1) as f64,
    }
}

#[test]
fn the_web_page_draws_six_graph_families_as_matgraph_render_does() {
    const TEST: &str = "the_web_page_draws_six_graph_families_as_matgraph_render_does";
    let chromium = std::env::var("CHROMIUM").unwrap_or_else(|_| "chromium".into());
    if !runs(&chromium) || !runs("node") {
        let why = format!("needs {chromium} and node");
        if std::env::var_os("MATGRAPH_REQUIRE_BROWSER").is_some() {
            panic!("{TEST}: MATGRAPH_REQUIRE_BROWSER is set: {why}");
        }
        common::print_skip(TEST, &why);
        return;
    }
    let shots = repo().join("target/web-example");
    std::fs::create_dir_all(&shots).unwrap();
    let mut report = Vec::new();
    for (graph, set, share) in CASES {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let file: PathBuf = repo().join(format!("graphs/{graph}.json"));
        let size = format!("{SIZE}x{SIZE}");
        matgraph(&[
            "bake-env".as_ref(),
            file.as_os_str(),
            "--out".as_ref(),
            d.as_os_str(),
            "--view".as_ref(),
            size.as_ref(),
        ]);
        let wgsl = d.join(format!("{graph}.wgsl"));
        let contract = d.join(format!("{graph}.contract.json"));
        matgraph(&[
            "wgsl".as_ref(),
            file.as_os_str(),
            "-o".as_ref(),
            wgsl.as_os_str(),
            "--contract".as_ref(),
            contract.as_os_str(),
        ]);
        let png = d.join("render.png");
        let mut render: Vec<&std::ffi::OsStr> = vec![
            "render".as_ref(),
            file.as_os_str(),
            "--size".as_ref(),
            size.as_ref(),
            "--exr".as_ref(),
            "-o".as_ref(),
            png.as_os_str(),
        ];
        if let Some(s) = set {
            render.extend([std::ffi::OsStr::new("--set"), std::ffi::OsStr::new(s)]);
        }
        matgraph(&render);
        let mut query = format!(
            "dir=file://{}/&graph={graph}&textures=file://{}/graphs/",
            d.display(),
            repo().display()
        );
        if let Some(s) = set {
            query += &format!("&set={s}");
        }
        let out = Command::new("node")
            .arg(repo().join("examples/web/run.mjs"))
            .arg(&query)
            .env("CHROMIUM", &chromium)
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        let result: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap_or_else(|e| {
            let head: String = stdout.chars().take(400).collect();
            panic!(
                "{graph}: {e}: {head} {}",
                String::from_utf8_lossy(&out.stderr)
            )
        });
        assert_eq!(result["status"], "ok", "{graph}: {}", result["message"]);
        let web = f32s_of_base64(result["pixels"].as_str().unwrap());
        let n = (SIZE * SIZE) as usize;
        assert_eq!(web.len(), 4 * n, "{graph}");
        let reference = image::open(d.join("render.exr"))
            .unwrap_or_else(|e| panic!("{graph}: render.exr: {e}"))
            .to_rgba32f();
        let m = compare(&web, reference.as_raw(), SIZE as usize, SIZE as usize);
        // What the page drew, tone mapped as the page shows it, to look at.
        let shown: Vec<u8> = web
            .chunks_exact(4)
            .flat_map(|p| {
                let enc = |l: f32| {
                    let l = l.clamp(0.0, 1.0);
                    let s = if l <= 0.003_130_8 {
                        12.92 * l
                    } else {
                        1.055 * l.powf(1.0 / 2.4) - 0.055
                    };
                    (s * 255.0).round() as u8
                };
                [
                    enc(p[0]),
                    enc(p[1]),
                    enc(p[2]),
                    (p[3].clamp(0.0, 1.0) * 255.0).round() as u8,
                ]
            })
            .collect();
        let tag = set.map_or(String::new(), |s| format!("_{}", s.replace('=', "_")));
        image::save_buffer(
            shots.join(format!("{graph}{tag}.png")),
            &shown,
            SIZE,
            SIZE,
            image::ColorType::Rgba8,
        )
        .unwrap();
        std::fs::copy(&png, shots.join(format!("{graph}{tag}_render.png"))).unwrap();
        // |web − render| × 25 per channel, to see where they differ.
        let diff: Vec<u8> = web
            .chunks_exact(4)
            .zip(reference.as_raw().chunks_exact(4))
            .flat_map(|(a, b)| {
                let d = |c: usize| ((a[c] - b[c]).abs() * 25.0 * 255.0).min(255.0) as u8;
                [d(0), d(1), d(2), 255]
            })
            .collect();
        image::save_buffer(
            shots.join(format!("{graph}{tag}_diff.png")),
            &diff,
            SIZE,
            SIZE,
            image::ColorType::Rgba8,
        )
        .unwrap();
        report.push(format!(
            "{graph}{tag} ({}): {} pixels inside, worst {:.2e}, mean {:.2e}, {:.2} % within {ABS:e} + {REL:e}·|render|",
            result["adapter"].as_str().unwrap_or(""),
            m.pixels,
            m.worst,
            m.mean,
            100.0 * m.within
        ));
        assert!(
            m.pixels > n / 8,
            "{graph}: the material covers {} pixels",
            m.pixels
        );
        assert!(
            m.within >= share && m.mean <= MEAN,
            "{graph}{tag}: expected ≥ {:.1} % within and a mean ≤ {MEAN:e}\n{}",
            100.0 * share,
            report.join("\n")
        );
    }
    common::print_warning(TEST, &format!("measured:\n{}", report.join("\n")));
}
