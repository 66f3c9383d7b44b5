//! Issue 37 item 13: images with NaN, infinite or absurdly large texels, and mip chains of
//! more levels than the image halves into, are refused at load with the file, the node and
//! the texel or level named (they were accepted: an HDR's stand-in for NaN evaluated to
//! 1.69e38; chains of 100 levels or 50,000 entries loaded silently).

use matgraph::image_io::{load_image, save_exr};
use matgraph::texture::{Image, MAX_TEXEL, TextureError};
use std::path::Path;
use std::process::Command;

/// Runs matgraph with `args` in `dir`: exit 1, stderr holding every fragment of `expect`.
fn fails(dir: &Path, args: &[&str], expect: &[&str]) {
    let out = Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        out.status.code(),
        Some(1),
        "{args:?}: {:?}\n{stderr}",
        out.status
    );
    for e in expect {
        assert!(
            stderr.contains(e),
            "{args:?}: stderr lacks {e:?}:\n{stderr}"
        );
    }
}

/// A 4 × 3 EXR at `path`, every texel 0.5 but texel (x, y)'s channel `c`, which is `v`.
fn exr_with(path: &Path, (x, y, c): (u32, u32, usize), v: f32) {
    let mut img = Image::filled(4, 3, [0.5; 4]);
    img.data[(y * 4 + x) as usize][c] = v;
    save_exr(path, &img).unwrap();
}

/// A Radiance HDR file of `w × 1` RGBE texels (flat, not run-length encoded: `w` < 8).
fn hdr(path: &Path, rgbe: &[[u8; 4]]) {
    let mut bytes = format!(
        "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X {}\n",
        rgbe.len()
    )
    .into_bytes();
    bytes.extend(rgbe.iter().flatten());
    std::fs::write(path, bytes).unwrap();
}

/// A graph `g.json` in `dir` sampling `texture` (JSON) on node `tex`.
fn graph(dir: &Path, texture: &str) {
    std::fs::write(
        dir.join("g.json"),
        format!(
            r#"{{ "version": 1, "name": "t", "nodes": [
              {{ "id": "geo", "type": "geometry" }},
              {{ "id": "tex", "type": "image_texture", "texture": {texture}, "inputs": {{ "uv": {{ "link": "geo.uv" }} }} }} ],
              "outputs": [{{ "name": "c", "from": "tex.color" }}] }}"#
        ),
    )
    .unwrap();
}

#[test]
fn non_finite_exr_texels_are_refused_naming_the_texel() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("t.exr");
    // Seeded positions and channels, each value in turn.
    let mut s = 0x9E37_79B9u32;
    for (k, (v, said)) in [
        (f32::NAN, "NaN"),
        (f32::INFINITY, "inf"),
        (f32::NEG_INFINITY, "-inf"),
        (1e30, "1e30"),
        (-2.0 * MAX_TEXEL, "-3.689349e19"),
    ]
    .into_iter()
    .enumerate()
    {
        s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        let (x, y, c) = ((s >> 8) % 4, (s >> 12) % 3, ((s >> 16) % 4) as usize);
        exr_with(&p, (x, y, c), v);
        let e = load_image(&p).unwrap_err();
        let channel = ["red", "green", "blue", "alpha"][c];
        assert_eq!(
            e.to_string(),
            format!(
                "{}: texel ({x}, {y}) (from the top left) has {said} in its {channel} channel: image values must be finite and at most 2^64 (1.8e19) in magnitude",
                p.display()
            ),
            "case {k}"
        );
        assert!(matches!(e, TextureError::InFile { .. }), "{e:?}");
    }
    // The largest magnitude is accepted, exactly.
    exr_with(&p, (3, 2, 0), -MAX_TEXEL);
    assert_eq!(load_image(&p).unwrap().data[11][0], -MAX_TEXEL);
    // Through the command line: the graph, the node, the file and the texel.
    exr_with(&p, (1, 2, 1), f32::NAN);
    graph(dir.path(), r#""t.exr""#);
    fails(
        dir.path(),
        &["eval", "g.json"],
        &[
            "g.json: node 'tex': ./t.exr: texel (1, 2) (from the top left) has NaN in its green channel",
        ],
    );
}

#[test]
fn an_hdr_texel_at_the_largest_exponent_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("t.hdr");
    // RGBE (128, 64, 32, 129) = (1, 0.5, 0.25): read exactly.
    hdr(&p, &[[128, 64, 32, 129], [128, 128, 128, 128]]);
    let img = load_image(&p).unwrap();
    assert_eq!(img.data[0], [1.0, 0.5, 0.25, 1.0]);
    assert_eq!(img.data[1], [0.5, 0.5, 0.5, 1.0]);
    // RGBE (255, 255, 255, 255): 255 · 2^(255 − 136) = 1.6947e38, what a writer makes of a
    // NaN or an infinity (RGBE has neither); it evaluated to 1.69e38.
    hdr(&p, &[[128, 64, 32, 129], [255, 255, 255, 255]]);
    let want = 255.0 * 2f64.powi(255 - 136);
    let e = load_image(&p).unwrap_err().to_string();
    assert!(
        e.ends_with(&format!(
            "t.hdr: texel (1, 0) (from the top left) has {:e} in its red channel: image values must be finite and at most 2^64 (1.8e19) in magnitude",
            want as f32
        )),
        "{e}"
    );
}

#[test]
fn mip_chains_longer_than_the_image_halves_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let save = |n: &str, w, h| save_exr(&d.join(n), &Image::filled(w, h, [0.25; 4])).unwrap();
    save("l0.exr", 4, 2);
    save("l1.exr", 2, 1);
    save("l2.exr", 1, 1);
    // The full chain of a 4 × 2 image is 3 levels (4×2, 2×1, 1×1): it loads.
    graph(d, r#"["l0.exr", "l1.exr", "l2.exr"]"#);
    let out = Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args(["eval", "g.json"])
        .current_dir(d)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // A fourth 1 × 1 level is [`mip_size`] of the third, but past the end of the chain.
    graph(d, r#"["l0.exr", "l1.exr", "l2.exr", "l2.exr"]"#);
    fails(
        d,
        &["eval", "g.json"],
        &[
            "g.json: node 'tex': ./l2.exr: a mip chain of 4 levels: a 4×2 image has 3 (halved down to 1×1); remove the levels from 3 on",
        ],
    );
    // 100 levels and 50,000 entries: refused at load (check too), before any file is read.
    for n in [100usize, 50_000] {
        let chain: Vec<String> = (0..n)
            .map(|k| format!("\"{}\"", ["l0.exr", "l1.exr", "l2.exr"][k.min(2)]))
            .collect();
        graph(d, &format!("[{}]", chain.join(",")));
        let start = std::time::Instant::now();
        for cmd in ["check", "eval"] {
            fails(
                d,
                &[cmd, "g.json"],
                &[&format!(
                    "node 'tex': a mip chain of {n} levels: a chain has at most 32"
                )],
            );
        }
        assert!(start.elapsed().as_secs() < 20, "{:?}", start.elapsed());
    }
    // The library refuses them too, before opening a file.
    let many: Vec<_> = (0..33).map(|_| d.join("missing.exr")).collect();
    let e = matgraph::image_io::load_texture(&many, false)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("33 levels listed; a chain has at most 32"),
        "{e}"
    );
}
