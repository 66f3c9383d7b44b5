//! Issue 38: the WebGPU page `examples/web/` (plain HTML and JavaScript) binds eight bundled
//! graphs of different families (the ball scene's PBR, skin and toon graphs, the textured
//! brick wall, the Sunshine water and the soap bubble) from their contract, `bake-env`'s
//! scene textures, view and depth alone, draws them in headless Chromium on SwiftShader
//! (`examples/web/run.mjs`), and its linear pixels match `matgraph render --exr` of the same
//! view within each case's stated bound. Needs `chromium` (or `$CHROMIUM`) and `node`; skipped with a line when either
//! is missing, a failure when `MATGRAPH_REQUIRE_BROWSER` is set (CI sets it).

use crate::common;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Image side of the comparisons.
const SIZE: u32 = 96;

/// What a case must meet.
#[derive(Clone, Copy)]
enum Bound {
    /// At least this share of the compared pixels within `ABS + REL·|render|` per channel,
    /// and a mean |web − render| ≤ [`MEAN`].
    Pixels(f64),
    /// For a material with a discontinuity that any difference in a filtered texel flips
    /// (an alpha test), or whose normals the render module rebuilds otherwise than the
    /// renderer: the sRGB RMSE at most this (1/255), and at least this share of the
    /// compared pixels within 2/255 in sRGB.
    Srgb(f64, f64),
}

/// The graphs drawn (graph, `set` values separated by `;`, bound, translucent, displaced in
/// a compute pass): the metal and the dielectric PBR models, the two skin models, the toon
/// shader and the textured brick wall (file textures, a normal map read through the
/// tangent buffer), with a parameter set through the page on one; the Sunshine water and
/// the fast soap bubble, translucent or reading the screen-space scene textures, drawn
/// over the rest of the scene's depth (`view.json`'s `depth`) and composited over the
/// baked `scene:background`. Each with its bound:
///
/// - the glass refracts the room's checker pattern through a magnifying sphere: a
///   direction a few ulps apart on the two sides lands on the other square at a checker
///   edge, so its bound holds on fewer pixels (and its mean on all of them);
/// - the water with its alpha test and sparkle off (`alpha_low=1;alpha_high=0;band_tint=0`)
///   is the screen-space refraction and reflection, distorted by the wave textures, alone:
///   held to the per-pixel bound;
/// - the water as the paper draws it keeps a pixel where the sum of two 128² band
///   textures lies outside [0.15, 1]: a step, which any difference in the filtered band
///   value flips (the bilinear weights' precision, which WebGPU leaves to the device, and
///   the band level chosen from the quad's uv derivatives), so it is held to an RMSE;
/// - the bubble's wobble displaces along the normal, `D(n, t)`, and the render module's
///   `mg_vertex` rebuilds normals from `D` at offset positions with the normal held,
///   which misses that slope (docs/integration.md, "What the vertex stage does"), where
///   the renderer shades the displaced mesh's welded normals; the thin film's colour
///   follows the normal, so drawn so it is held to an RMSE (the same graph without its
///   wobble measured RMSE 0.93/255, 99.1 % within 2/255). Drawn as the docs say for
///   those normals (the last case: `--displaced-vertices`, the library module displacing
///   in a compute pass, the normals rebuilt from the displaced mesh in the page), it is
///   held to the per-pixel bound.
const CASES: [(&str, Option<&str>, Bound, bool, bool); 11] = [
    ("pbr_gold", None, Bound::Pixels(0.99), false, false),
    (
        "pbr_gold",
        Some("roughness=0.6"),
        Bound::Pixels(0.99),
        false,
        false,
    ),
    ("pbr_glass", None, Bound::Pixels(0.80), false, false),
    ("skin", None, Bound::Pixels(0.99), false, false),
    ("skin_dipole", None, Bound::Pixels(0.99), false, false),
    ("toon_ball", None, Bound::Pixels(0.99), false, false),
    ("brick_wall", None, Bound::Pixels(0.99), false, false),
    (
        "water_sunshine",
        Some("alpha_low=1;alpha_high=0;band_tint=0"),
        Bound::Pixels(0.98),
        true,
        false,
    ),
    ("water_sunshine", None, Bound::Srgb(12.0, 0.75), true, false),
    (
        "bubble_iridescent_fast",
        None,
        Bound::Srgb(6.0, 0.45),
        true,
        false,
    ),
    (
        "bubble_iridescent_fast",
        None,
        Bound::Pixels(0.98),
        true,
        true,
    ),
];

/// The mean |web − render| over every compared pixel and channel, for every case held to
/// [`Bound::Pixels`].
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
    /// The RMSE of the sRGB-encoded values (clamped to [0, 1]), in 1/255.
    rmse_srgb: f64,
    /// The share of pixels whose sRGB-encoded channels are all within 2/255.
    within_2_255: f64,
}

/// sRGB encoding of a linear value clamped to [0, 1] (IEC 61966-2-1), in 1/255.
fn srgb255(l: f32) -> f64 {
    let l = f64::from(l.clamp(0.0, 1.0));
    255.0
        * if l <= 0.003_130_8 {
            12.92 * l
        } else {
            1.055 * l.powf(1.0 / 2.4) - 0.055
        }
}

/// Per channel: |web − render| ≤ ABS + REL · |render| (linear radiance).
const ABS: f32 = 4e-3;
const REL: f32 = 1e-2;

/// Compares what the page drew (`drawn`: its radiance, composited over `background` for a
/// translucent material, and the material's alpha) with the render. An opaque material is
/// compared inside its silhouette (the pixel and its eight neighbours at alpha 1); a
/// translucent one wherever either side shows it: the page drew it (alpha > 0) or the
/// render differs from the background there.
fn compare(
    drawn: &[f32],
    reference: &[f32],
    background: Option<&[f32]>,
    w: usize,
    h: usize,
) -> Measured {
    let alpha = |x: usize, y: usize| drawn[4 * (y * w + x) + 3];
    let (mut pixels, mut worst, mut sum, mut ok) = (0usize, 0f32, 0f64, 0usize);
    let (mut squares, mut ok_255) = (0f64, 0usize);
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let i = 4 * (y * w + x);
            let outside = match background {
                Some(bg) => alpha(x, y) <= 0.0 && (0..3).all(|c| reference[i + c] == bg[i + c]),
                None => (0..9).any(|k| alpha(x + k % 3 - 1, y + k / 3 - 1) < 0.999),
            };
            if outside {
                continue;
            }
            pixels += 1;
            let mut good = true;
            let mut good_255 = true;
            for c in 0..3 {
                let (a, b) = (drawn[i + c], reference[i + c]);
                let d = (a - b).abs();
                worst = worst.max(d);
                sum += f64::from(d);
                good &= d <= ABS + REL * b.abs();
                let e = srgb255(a) - srgb255(b);
                squares += e * e;
                good_255 &= e.abs() <= 2.0;
            }
            ok += usize::from(good);
            ok_255 += usize::from(good_255);
        }
    }
    Measured {
        pixels,
        worst,
        mean: sum / (3 * pixels.max(1)) as f64,
        within: ok as f64 / pixels.max(1) as f64,
        rmse_srgb: (squares / (3 * pixels.max(1)) as f64).sqrt(),
        within_2_255: ok_255 as f64 / pixels.max(1) as f64,
    }
}

#[test]
fn the_web_page_draws_eight_graphs_as_matgraph_render_does() {
    const TEST: &str = "the_web_page_draws_eight_graphs_as_matgraph_render_does";
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
    for (graph, set, bound, translucent, displace) in CASES {
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
        let mut module: Vec<&std::ffi::OsStr> = vec![
            "wgsl".as_ref(),
            file.as_os_str(),
            "-o".as_ref(),
            wgsl.as_os_str(),
            "--contract".as_ref(),
            contract.as_os_str(),
        ];
        let (lib, lib_contract) = (
            d.join(format!("{graph}.lib.wgsl")),
            d.join(format!("{graph}.lib.contract.json")),
        );
        if displace {
            // The render module draws displaced vertices; the library module displaces them.
            module.push("--displaced-vertices".as_ref());
            matgraph(&[
                "wgsl".as_ref(),
                file.as_os_str(),
                "--entry".as_ref(),
                "library".as_ref(),
                "-o".as_ref(),
                lib.as_os_str(),
                "--contract".as_ref(),
                lib_contract.as_os_str(),
            ]);
        }
        matgraph(&module);
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
        for one in set.iter().flat_map(|s| s.split(';')) {
            render.extend([std::ffi::OsStr::new("--set"), std::ffi::OsStr::new(one)]);
        }
        matgraph(&render);
        let mut query = format!(
            "dir=file://{}/&graph={graph}&textures=file://{}/graphs/",
            d.display(),
            repo().display()
        );
        for one in set.iter().flat_map(|s| s.split(';')) {
            query += &format!("&set={one}");
        }
        if displace {
            query += "&displace=compute";
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
        // A translucent material over the frame without it (the baked scene:background), as
        // an app draws it: premultiplied, rgb + (1 − alpha)·background.
        let mut drawn = web.clone();
        let background: Option<Vec<f32>> = translucent.then(|| {
            let bytes = std::fs::read(d.join("background_0.rgba32f"))
                .expect("bake-env --view wrote scene:background");
            bytes
                .chunks_exact(4)
                .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
                .collect()
        });
        if let Some(bg) = &background {
            for (p, b) in drawn.chunks_exact_mut(4).zip(bg.chunks_exact(4)) {
                for c in 0..3 {
                    p[c] += (1.0 - p[3]) * b[c];
                }
            }
        }
        let m = compare(
            &drawn,
            reference.as_raw(),
            background.as_deref(),
            SIZE as usize,
            SIZE as usize,
        );
        // What the page drew, tone mapped as the page shows it, to look at.
        let shown: Vec<u8> = drawn
            .chunks_exact(4)
            .flat_map(|p| {
                let enc = |l: f32| srgb255(l).round() as u8;
                [
                    enc(p[0]),
                    enc(p[1]),
                    enc(p[2]),
                    if translucent {
                        255
                    } else {
                        (p[3].clamp(0.0, 1.0) * 255.0).round() as u8
                    },
                ]
            })
            .collect();
        let mut tag = set.map_or(String::new(), |s| {
            format!("_{}", s.replace(['=', ';'], "_"))
        });
        if displace {
            tag += "_displaced";
        }
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
        let diff: Vec<u8> = drawn
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
            "{graph}{tag} ({}): {} pixels inside, worst {:.2e}, mean {:.2e}, {:.2} % within {ABS:e} + {REL:e}·|render|; sRGB RMSE {:.2}/255, {:.2} % within 2/255",
            result["adapter"].as_str().unwrap_or(""),
            m.pixels,
            m.worst,
            m.mean,
            100.0 * m.within,
            m.rmse_srgb,
            100.0 * m.within_2_255
        ));
        eprintln!("{}", report.last().unwrap());
        assert!(
            m.pixels > n / 8,
            "{graph}: the material covers {} pixels",
            m.pixels
        );
        let (met, expected) = match bound {
            Bound::Pixels(share) => (
                m.within >= share && m.mean <= MEAN,
                format!("≥ {:.1} % within and a mean ≤ {MEAN:e}", 100.0 * share),
            ),
            Bound::Srgb(rmse, share) => (
                m.rmse_srgb <= rmse && m.within_2_255 >= share,
                format!(
                    "an sRGB RMSE ≤ {rmse}/255 and ≥ {:.1} % within 2/255",
                    100.0 * share
                ),
            ),
        };
        assert!(
            met,
            "{graph}{tag}: expected {expected}\n{}",
            report.join("\n")
        );
    }
    common::print_warning(TEST, &format!("measured:\n{}", report.join("\n")));
}
