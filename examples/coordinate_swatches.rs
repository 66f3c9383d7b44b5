//! Pictures of `texture_coordinate` and `triplanar` on the ball, for
//! docs/models/coordinates.md: each graph's emission rendered by the CPU reference renderer
//! (192 × 192, 4 samples per pixel, the ball seen from above and to the right so that every
//! axis shows), written as an 8-bit sRGB PNG.
//!
//! `cargo run --release --example coordinate_swatches` writes docs/models/coordinates/*.png.

use matgraph::render::{RenderOptions, render_timed};
use matgraph::scene::Scene;
use matgraph::{Graph, Registry};
use serde_json::{Value, json};
use std::path::Path;

/// Pixels a side.
const SIZE: u32 = 192;

/// Emission `tc.{output}` · scale + offset.
fn coordinate(output: &str, scale: [f32; 3], offset: [f32; 3]) -> Value {
    json!({
        "nodes": [
            { "id": "tc", "type": "texture_coordinate" },
            { "id": "s", "type": "mul", "inputs": { "a": { "link": format!("tc.{output}") }, "b": scale } },
            { "id": "o", "type": "add", "inputs": { "a": { "link": "s.result" }, "b": offset } }
        ],
        "from": "o.result"
    })
}

/// Triplanar of a checker per axis, each fed the position projected along its axis.
fn triplanar_checkers(blend: f32) -> Value {
    let checker = |id: &str, uv: &str, a: [f32; 3], b: [f32; 3]| {
        json!({ "id": id, "type": "checker", "inputs": {
            "uv": { "link": format!("{uv}.vec2") }, "scale": 4.0, "color_a": a, "color_b": b } })
    };
    let pair = |id: &str, u: &str, v: &str| {
        json!({ "id": id, "type": "combine", "inputs": {
            "x": { "link": format!("p.{u}") }, "y": { "link": format!("p.{v}") } } })
    };
    json!({
        "nodes": [
            { "id": "geo", "type": "geometry" },
            { "id": "p", "type": "split", "inputs": { "v": { "link": "geo.position" } } },
            pair("yz", "y", "z"), pair("xz", "x", "z"), pair("xy", "x", "y"),
            checker("cx", "yz", [0.8, 0.1, 0.1], [0.95, 0.8, 0.8]),
            checker("cy", "xz", [0.1, 0.6, 0.1], [0.8, 0.95, 0.8]),
            checker("cz", "xy", [0.1, 0.2, 0.8], [0.8, 0.85, 0.95]),
            { "id": "t", "type": "triplanar", "inputs": {
                "x": { "link": "cx.color" }, "y": { "link": "cy.color" }, "z": { "link": "cz.color" },
                "normal": { "link": "geo.normal" }, "blend": blend } }
        ],
        "from": "t.color"
    })
}

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/models/coordinates");
    std::fs::create_dir_all(&dir).unwrap();
    let mut scene = Scene::preset("ball").unwrap();
    scene.camera.position = [1.3, 0.9, 2.6];
    let swatches = [
        ("tc_generated", coordinate("generated", [1.0; 3], [0.0; 3])),
        (
            "tc_camera",
            coordinate("camera", [0.4, 0.4, 0.15], [0.5, 0.5, 0.0]),
        ),
        (
            "tc_reflection",
            coordinate("reflection", [0.5; 3], [0.5; 3]),
        ),
        ("tc_window", coordinate("window", [1.0; 3], [0.0; 3])),
        ("triplanar_blend1", triplanar_checkers(1.0)),
        ("triplanar_blend8", triplanar_checkers(8.0)),
    ];
    for (name, g) in swatches {
        let text = json!({
            "version": 1, "name": name, "nodes": g["nodes"],
            "outputs": [ { "name": "emission", "from": g["from"] } ]
        });
        let graph = Graph::from_json(&text.to_string(), Registry::builtin()).unwrap();
        let options = RenderOptions {
            width: SIZE,
            height: SIZE,
            samples: 4,
            ..RenderOptions::default()
        };
        let (image, _) = render_timed(&graph, &scene, &options).unwrap();
        let rgb = image.to_srgb8(0.0);
        let file = dir.join(format!("{name}.png"));
        matgraph::image_io::save_png_rgb8(&file, rgb.width, rgb.height, &rgb.pixels).unwrap();
        println!("{}", file.display());
    }
}
