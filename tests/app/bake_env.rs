//! `matgraph bake-env` (issue 38 item 1): every scene texture an app must bind, at the sizes
//! the manifest states, with the values closed forms give for a constant environment.

use std::path::Path;
use std::process::Command;

fn bake(source: &str, out: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args(["bake-env", source, "--out"])
        .arg(out)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("matgraph runs")
}

fn manifest(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("manifest.json")).expect("manifest written");
    serde_json::from_str(&text).expect("manifest is JSON")
}

/// The texels of `file` in `dir` as RGBA f32.
fn texels(dir: &Path, file: &str) -> Vec<[f32; 4]> {
    let bytes = std::fs::read(dir.join(file)).expect("level file written");
    bytes
        .chunks_exact(16)
        .map(|t| {
            std::array::from_fn(|c| f32::from_le_bytes(t[4 * c..4 * c + 4].try_into().unwrap()))
        })
        .collect()
}

/// The texture named `name` in a manifest.
fn entry<'a>(m: &'a serde_json::Value, name: &str) -> &'a serde_json::Value {
    m["textures"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| t["name"] == name)
        .unwrap_or_else(|| panic!("{name} in the manifest"))
}

#[test]
fn a_preset_bakes_every_scene_texture_at_the_documented_sizes_deterministically() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    for dir in [&a, &b] {
        let out = bake("ball", dir);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let m = manifest(&a);
    assert_eq!(m["schema"], "matgraph-environment/1");
    // (name, width, height, levels): docs/integration.md "Scene textures".
    for (name, w, h, levels) in [
        ("scene:environment", 512, 256, 10),
        ("scene:environment_ggx", 256, 128, 6),
        ("scene:brdf_lut", 32, 32, 1),
        ("scene:environment_sh", 9, 1, 1),
    ] {
        let t = entry(&m, name);
        assert_eq!(
            (t["width"].as_u64(), t["height"].as_u64()),
            (Some(w), Some(h)),
            "{name}"
        );
        assert_eq!(t["mip_levels"].as_u64(), Some(levels), "{name}");
        let list = t["levels"].as_array().unwrap();
        assert_eq!(list.len() as u64, levels, "{name}");
        let (mut lw, mut lh) = (w, h);
        for level in list {
            let file = level["file"].as_str().unwrap();
            assert_eq!(
                (level["width"].as_u64(), level["height"].as_u64()),
                (Some(lw), Some(lh))
            );
            let bytes = std::fs::read(a.join(file)).unwrap();
            assert_eq!(bytes.len() as u64, lw * lh * 16, "{file}");
            assert_eq!(
                bytes,
                std::fs::read(b.join(file)).unwrap(),
                "{file} differs between runs"
            );
            (lw, lh) = ((lw / 2).max(1), (lh / 2).max(1));
        }
    }
    assert_eq!(
        std::fs::read(a.join("manifest.json")).unwrap(),
        std::fs::read(b.join("manifest.json")).unwrap()
    );
}

#[test]
fn a_constant_environment_bakes_to_its_closed_forms() {
    // A seeded constant radiance besides a round one: every level of the map and of its GGX
    // prefilter is that radiance, and its irradiance is band 0 alone, L00 = c·∫Y00 dω =
    // c·0.282095·4π (times Â0/π = 1), so that E(n)/π = L00·Y00 = c.
    let mut state = 0x5eed_0038u64;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        // f32-exact values in [0.05, 4).
        (((state >> 40) as u32 % 3951) + 50) as f32 / 1000.0
    };
    for c in [[0.25f32, 0.5, 2.0], [next(), next(), next()]] {
        let tmp = tempfile::tempdir().unwrap();
        let hdr = tmp.path().join("constant.exr");
        image::Rgb32FImage::from_pixel(64, 32, image::Rgb(c))
            .save(&hdr)
            .unwrap();
        let out_dir = tmp.path().join("baked");
        let out = bake(hdr.to_str().unwrap(), &out_dir);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let m = manifest(&out_dir);
        for name in ["scene:environment", "scene:environment_ggx"] {
            for level in entry(&m, name)["levels"].as_array().unwrap() {
                let file = level["file"].as_str().unwrap();
                for t in texels(&out_dir, file) {
                    for k in 0..3 {
                        let err = (t[k] as f64 - c[k] as f64).abs() / c[k] as f64;
                        assert!(err < 1e-5, "{file}: {t:?} against {c:?}");
                    }
                    assert_eq!(t[3], 1.0, "{file}: alpha");
                }
            }
        }
        let sh = texels(&out_dir, "environment_sh_0.rgba32f");
        let l00 = 0.282095f64 * 4.0 * std::f64::consts::PI;
        for k in 0..3 {
            let want = c[k] as f64 * l00;
            let err = (sh[0][k] as f64 - want).abs() / want;
            // The projection sums 128 × 64 texels by the midpoint rule: (π/64)²/24 ≈ 1e-4.
            assert!(err < 1e-3, "SH band 0 {:?} against {want} ({c:?})", sh[0]);
            for (j, coefficient) in sh.iter().enumerate().skip(1) {
                assert!(
                    coefficient[k].abs() < 1e-3 * c[k],
                    "SH coefficient {j} of a constant environment: {coefficient:?}"
                );
            }
        }
    }
}

#[test]
fn a_source_that_is_nothing_known_is_refused_by_name() {
    let tmp = tempfile::tempdir().unwrap();
    let out = bake("nowhere.txt", &tmp.path().join("x"));
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("nowhere.txt") && err.contains("scene preset"),
        "{err}"
    );
    assert!(!tmp.path().join("x").exists(), "nothing written");
}

/// `--view`: the screen-space passes join the manifest at the frame's size, and the rest of
/// the scene's depth unprojects, through view.json's own `view_proj`, onto the ball scene's
/// floor (y = 0) or back wall (z = −4 m) or is 1 where neither is hit: closed forms of the
/// backdrop's two planes, in f64. The ball itself, the material, is not in it.
#[test]
fn a_view_bakes_the_screen_space_passes_and_the_scene_depth() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("v");
    let out = Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args(["bake-env", "ball", "--view", "64x48", "--out"])
        .arg(&dir)
        .output()
        .expect("matgraph runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let m = manifest(&dir);
    assert_eq!(m["textures"].as_array().unwrap().len(), 7);
    for name in ["scene:background", "scene:refraction", "scene:reflection"] {
        let t = entry(&m, name);
        assert_eq!(
            (t["width"].as_u64(), t["height"].as_u64()),
            (Some(64), Some(48))
        );
        // 64 × 48 → 32 × 24 → … → 1 × 1: 7 levels.
        assert_eq!(t["mip_levels"], 7, "{name}");
        let file = t["levels"][0]["file"].as_str().unwrap();
        assert_eq!(texels(&dir, file).len(), 64 * 48, "{name}");
    }
    // The ball scene has no water: refraction and reflection are the background.
    let background = texels(&dir, "background_0.rgba32f");
    assert_eq!(texels(&dir, "refraction_0.rgba32f"), background);
    assert_eq!(texels(&dir, "reflection_0.rgba32f"), background);
    assert!(
        background
            .iter()
            .all(|t| t[3] == 1.0 && t[..3].iter().all(|c| c.is_finite()))
    );

    let view: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("view.json")).unwrap()).unwrap();
    assert_eq!(view["depth"], "depth.r32f");
    let bytes = std::fs::read(dir.join("depth.r32f")).unwrap();
    assert_eq!(bytes.len(), 64 * 48 * 4);
    let depth: Vec<f64> = bytes
        .chunks_exact(4)
        .map(|b| f64::from(f32::from_le_bytes(b.try_into().unwrap())))
        .collect();
    let cols: Vec<f64> = view["view_proj"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let inverse = glam::DMat4::from_cols_slice(&cols).inverse();
    let (mut floor, mut wall, mut none) = (0, 0, 0);
    for y in 0..48 {
        for x in 0..64 {
            let z = depth[y * 64 + x];
            assert!((0.0..=1.0).contains(&z), "({x}, {y}): {z}");
            if z == 1.0 {
                none += 1;
                continue;
            }
            // The pixel centre in WebGPU's clip space (y up), at the stored depth.
            let ndc = glam::DVec4::new(
                (x as f64 + 0.5) / 32.0 - 1.0,
                1.0 - (y as f64 + 0.5) / 24.0,
                z,
                1.0,
            );
            let p = inverse * ndc;
            let p = p.truncate() / p.w;
            // f32 depth near 1 holds the distance to about 2⁻²⁴·far/(1 − z)² relative.
            let tol = 2e-3 * p.length().max(1.0);
            if p.y.abs() <= tol && p.z >= -4.0 - tol {
                floor += 1;
            } else if (p.z + 4.0).abs() <= tol && p.y >= -tol {
                wall += 1;
            } else {
                panic!("({x}, {y}) at depth {z} unprojects to {p:?}: neither floor nor wall");
            }
        }
    }
    assert!(
        floor > 200 && wall > 200,
        "floor {floor}, wall {wall}, none {none}"
    );
    // The ball stands at the centre: every pixel above landed on a backdrop plane, so
    // the material is not in the depth; the centre pixel sees the backdrop behind it.
    assert!(depth[24 * 64 + 32] < 1.0);
}
