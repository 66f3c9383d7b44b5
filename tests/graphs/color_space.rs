//! Colour spaces of image references (`"color_space": "srgb" | "linear" | "data"`): what a
//! texel's stored value reads as, against the IEC 61966-2-1 transfer function in f64, and
//! the errors of bad references.

use glam::Vec2;
use matgraph::color_space::ColorSpace;
use matgraph::texture::{Filter, Wrap};
use matgraph::{Attribute, Plan, PlanOptions, Registry, SampleBatch};
use std::path::Path;

/// sRGB-encoded `c` in [0, 1] to linear light, in f64 (IEC 61966-2-1:1999, the inverse
/// transfer function), written out independently of `image_io::srgb_to_linear`.
fn srgb_decode(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// A small seeded generator (LCG), so the bytes are the same in every run.
fn bytes(seed: u32, n: usize) -> Vec<u8> {
    let mut state = seed;
    (0..n)
        .map(|_| {
            state = state.wrapping_mul(1_103_515_245).wrapping_add(12_345);
            (state >> 16) as u8
        })
        .collect()
}

/// The texels of a 16 × 2 RGBA8 PNG: round values first, then seeded random ones.
fn texels() -> Vec<u8> {
    let mut v: Vec<u8> = [0u8, 1, 10, 11, 64, 128, 200, 255]
        .iter()
        .flat_map(|&b| [b, b, b, 255])
        .collect();
    v.extend(bytes(0x5eed, 16 * 2 * 4 - v.len()));
    v
}

/// A graph reading `probe.png` at texel centres (nearest, level 0) in each colour space:
/// three image nodes, without `color_space` (the default), `data` and `linear`.
const GRAPH: &str = r#"{
  "version": 2, "name": "spaces",
  "nodes": [
    { "id": "geo", "type": "geometry" },
    { "id": "plain", "type": "image_texture", "texture": "probe.png",
      "inputs": { "uv": { "link": "geo.uv" }, "filter": "nearest" } },
    { "id": "data", "type": "image_texture", "texture": "probe.png", "color_space": "data",
      "inputs": { "uv": { "link": "geo.uv" }, "filter": "nearest" } },
    { "id": "lin", "type": "image_texture", "texture": "probe.png", "color_space": "linear",
      "inputs": { "uv": { "link": "geo.uv" }, "filter": "nearest" } }
  ],
  "outputs": [
    { "name": "plain", "from": "plain.color" },
    { "name": "data", "from": "data.color" },
    { "name": "linear", "from": "lin.color" },
    { "name": "alpha", "from": "data.alpha" }
  ]
}"#;

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn a_data_map_reads_its_stored_bytes_and_the_default_stays_srgb() {
    let (w, h) = (16u32, 2u32);
    let rgba = texels();
    let dir = tempfile::tempdir().unwrap();
    image::save_buffer(
        dir.path().join("probe.png"),
        &rgba,
        w,
        h,
        image::ColorType::Rgba8,
    )
    .unwrap();
    let file = write(dir.path(), "g.json", GRAPH);
    let graph = matgraph::io::load_graph(&file, Registry::builtin()).unwrap();
    let set = matgraph::image_io::load_graph_textures(&graph, &file).unwrap();
    // Two textures: the PNG read as sRGB (the default, keyed by its path as before) and as
    // data (`linear` reads the same numbers and shares no key with it).
    let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
    assert_eq!(
        plan.textures(),
        &["probe.png", "probe.png#data", "probe.png#linear"].map(String::from)
    );
    // Every texel at its centre.
    let n = (w * h) as usize;
    let uv: Vec<[f32; 2]> = (0..n)
        .map(|i| {
            let (x, y) = ((i as u32 % w) as f32, (i as u32 / w) as f32);
            [(x + 0.5) / w as f32, (y + 0.5) / h as f32]
        })
        .collect();
    let mut batch = SampleBatch::new(n);
    batch
        .set_planar(
            Attribute::Uv,
            (0..2).flat_map(|c| uv.iter().map(move |p| p[c])).collect(),
        )
        .unwrap();
    batch.set_textures(std::sync::Arc::new(set));
    let out = plan.execute(&batch, &plan.default_parameters()).unwrap();
    let (plain, data, linear, alpha) = (
        out.index("plain").unwrap(),
        out.index("data").unwrap(),
        out.index("linear").unwrap(),
        out.index("alpha").unwrap(),
    );
    for i in 0..n {
        let stored = &rgba[i * 4..i * 4 + 4];
        for (c, &b) in stored[..3].iter().enumerate() {
            let byte = b as f64 / 255.0;
            let at = |k: usize| out.planar(k)[c * n + i] as f64;
            // Data and linear: the byte over 255, to f32 rounding.
            assert!(
                (at(data) - byte).abs() <= 1e-7,
                "texel {i} c{c}: data {} vs {byte}",
                at(data)
            );
            assert!(
                (at(linear) - byte).abs() <= 1e-7,
                "texel {i} c{c}: linear {}",
                at(linear)
            );
            // The default: sRGB-decoded, as every PNG was before.
            let want = srgb_decode(byte);
            assert!(
                (at(plain) - want).abs() <= 1e-6,
                "texel {i} c{c}: srgb {} vs {want}",
                at(plain)
            );
        }
        // Alpha is never transformed.
        let a = out.planar(alpha)[i] as f64;
        assert!(
            (a - stored[3] as f64 / 255.0).abs() <= 1e-7,
            "texel {i} alpha {a}"
        );
    }
    // The round values: 128 reads 0.50196 as data and 0.21586 as sRGB.
    let k = 5; // texel 5 holds 128
    assert!((out.planar(data)[k] - 128.0 / 255.0).abs() < 1e-7);
    assert!((out.planar(plain)[k] - 0.215_861).abs() < 1e-6);
}

#[test]
fn a_sixteen_bit_data_png_keeps_sixteen_bits() {
    // A 16-bit greyscale height map: 2 × 1 texels, 0x3039 and 0xfedc.
    let dir = tempfile::tempdir().unwrap();
    let values: [u16; 2] = [12345, 65244];
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_be_bytes()).collect();
    let file = std::fs::File::create(dir.path().join("h.png")).unwrap();
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), 2, 1);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(png::BitDepth::Sixteen);
    enc.write_header()
        .unwrap()
        .write_image_data(&bytes)
        .unwrap();
    let texture = matgraph::image_io::load_texture_as(
        &[dir.path().join("h.png")],
        false,
        Some(ColorSpace::Data),
    )
    .unwrap();
    for (k, v) in values.iter().enumerate() {
        let got = texture.sample(
            Vec2::new((k as f32 + 0.5) / 2.0, 0.5),
            0.0,
            Wrap::Clamp,
            Filter::Nearest,
        );
        let want = *v as f64 / 65535.0;
        assert!((got.x as f64 - want).abs() < 1e-7, "{} vs {want}", got.x);
    }
}

#[test]
fn bad_colour_spaces_are_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    image::save_buffer(
        dir.path().join("probe.png"),
        &texels(),
        16,
        2,
        image::ColorType::Rgba8,
    )
    .unwrap();
    let load = |text: &str| {
        let file = write(dir.path(), "bad.json", text);
        matgraph::io::load_graph(&file, Registry::builtin())
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    // An unknown space: the file, the node and the choices.
    let e =
        load(&GRAPH.replace(r#""color_space": "data""#, r#""color_space": "raw""#)).unwrap_err();
    assert!(e.contains("bad.json"), "{e}");
    assert!(e.contains("node 'data'"), "{e}");
    assert!(e.contains("unknown variant `raw`"), "{e}");
    assert!(e.contains("srgb") && e.contains("linear"), "{e}");
    // On a node that samples no image.
    let e = load(
        r#"{ "version": 2, "name": "g", "nodes": [ { "id": "a", "type": "add", "color_space": "data" } ],
            "outputs": [ { "name": "x", "from": "a.result" } ] }"#,
    )
    .unwrap_err();
    assert!(
        e.contains("node 'a': a 'add' node samples no image: remove \"color_space\""),
        "{e}"
    );
    // On a scene texture (the renderer supplies it, in linear light).
    let e = load(
        r#"{ "version": 2, "name": "g", "nodes": [ { "id": "geo", "type": "geometry" },
            { "id": "bg", "type": "image_texture", "texture": "scene:background", "color_space": "srgb",
              "inputs": { "uv": { "link": "geo.uv" } } } ],
            "outputs": [ { "name": "color", "from": "bg.color" } ] }"#,
    )
    .unwrap_err();
    assert!(
        e.contains("node 'bg'") && e.contains("scene texture"),
        "{e}"
    );
    // In a version-1 file: the feature and the version it needs.
    let e = load(&GRAPH.replace("\"version\": 2", "\"version\": 1")).unwrap_err();
    assert!(
        e.contains("\"color_space\" on texture nodes need format version 2"),
        "{e}"
    );
}

#[test]
fn an_environment_image_is_never_data() {
    let scene = r#"{ "environment": { "image": { "path": "sky.hdr", "color_space": "data" } } }"#;
    let e = matgraph::scene::Scene::from_json(scene)
        .unwrap_err()
        .to_string();
    assert!(e.contains("environment.image.color_space"), "{e}");
    let ok = scene.replace("\"data\"", "\"linear\"");
    matgraph::scene::Scene::from_json(&ok).unwrap();
}
