//! Pictures of the procedural texture nodes over a plane, for docs/models/textures.md:
//! each node evaluated on the CPU over a 256 × 256 grid of positions (x, y, 0) in [0, 1]²,
//! its `color` output (or `fac` as grey) written as an 8-bit sRGB PNG.
//!
//! `cargo run --release --example texture_swatches` writes docs/models/textures/*.png.

use matgraph::{Attribute, Graph, Plan, PlanOptions, Registry, SampleBatch};
use std::path::Path;

/// Pixels a side.
const SIZE: u32 = 256;

/// (file name, node type, node inputs as JSON, output shown).
const SWATCHES: &[(&str, &str, &str, &str)] = &[
    (
        "noise_fbm",
        "noise_texture",
        r#"{ "scale": 5.0, "detail": 2.0 }"#,
        "fac",
    ),
    (
        "noise_fbm_detail8",
        "noise_texture",
        r#"{ "scale": 5.0, "detail": 8.0, "roughness": 0.6 }"#,
        "fac",
    ),
    (
        "noise_color_distorted",
        "noise_texture",
        r#"{ "scale": 3.0, "detail": 4.0, "distortion": 1.5 }"#,
        "color",
    ),
    (
        "noise_ridged",
        "noise_texture",
        r#"{ "scale": 3.0, "detail": 6.0, "type": "ridged_multifractal", "offset": 1.0, "gain": 2.0 }"#,
        "fac",
    ),
    (
        "noise_hetero",
        "noise_texture",
        r#"{ "scale": 3.0, "detail": 5.0, "type": "hetero_terrain", "offset": 0.5 }"#,
        "fac",
    ),
    (
        "white_noise",
        "white_noise",
        r#"{ "dimensions": "2d" }"#,
        "color",
    ),
    (
        "gradient_easing",
        "gradient_texture",
        r#"{ "type": "easing" }"#,
        "fac",
    ),
    // Centred: the radial gradient turns about the origin.
    (
        "gradient_radial",
        "gradient_texture",
        r#"{ "type": "radial", "centred": true }"#,
        "fac",
    ),
    (
        "gradient_quadratic_sphere",
        "gradient_texture",
        r#"{ "type": "quadratic_sphere", "centred": true }"#,
        "fac",
    ),
    (
        "voronoi_f1_color",
        "voronoi_texture",
        r#"{ "scale": 6.0 }"#,
        "color",
    ),
    (
        "voronoi_f1_distance",
        "voronoi_texture",
        r#"{ "scale": 6.0 }"#,
        "distance",
    ),
    (
        "voronoi_edge",
        "voronoi_texture",
        r#"{ "scale": 6.0, "feature": "distance_to_edge" }"#,
        "distance",
    ),
    (
        "voronoi_smooth_octaves",
        "voronoi_texture",
        r#"{ "scale": 4.0, "feature": "smooth_f1", "detail": 3.0, "normalize": true }"#,
        "distance",
    ),
    ("wave_bands", "wave_texture", r#"{ "scale": 5.0 }"#, "fac"),
    (
        "wave_rings_distorted",
        "wave_texture",
        r#"{ "scale": 1.5, "type": "rings", "rings_direction": "spherical", "distortion": 6.0, "detail": 3.0, "centred": true }"#,
        "fac",
    ),
    (
        "wave_saw_diagonal",
        "wave_texture",
        r#"{ "scale": 3.0, "bands_direction": "diagonal", "profile": "saw", "distortion": 2.0, "detail_scale": 2.0 }"#,
        "fac",
    ),
    ("brick_default", "brick_texture", r#"{}"#, "color"),
    (
        "brick_coloured_squashed",
        "brick_texture",
        r#"{ "scale": 3.0, "color1": [0.6, 0.12, 0.05], "color2": [0.3, 0.06, 0.03], "mortar": [0.7, 0.7, 0.65], "mortar_size": 0.03, "mortar_smooth": 0.3, "offset": 0.25, "offset_frequency": 3, "squash": 0.5, "squash_frequency": 2 }"#,
        "color",
    ),
    ("magic_default", "magic_texture", r#"{}"#, "color"),
    (
        "magic_depth10",
        "magic_texture",
        r#"{ "scale": 2.0, "depth": 10, "distortion": 1.5 }"#,
        "color",
    ),
];

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/models/textures");
    std::fs::create_dir_all(&dir).unwrap();
    let n = (SIZE * SIZE) as usize;
    let points: Vec<[f32; 3]> = (0..n)
        .map(|i| {
            let (x, y) = ((i as u32 % SIZE) as f32, (i as u32 / SIZE) as f32);
            [(x + 0.5) / SIZE as f32, 1.0 - (y + 0.5) / SIZE as f32, 0.0]
        })
        .collect();
    let mut batch = SampleBatch::new(n);
    batch.set_values(Attribute::Position, &points).unwrap();
    for (name, node_type, inputs, output) in SWATCHES {
        let mut inputs: serde_json::Value = serde_json::from_str(inputs).unwrap();
        // "centred": positions over [−1, 1]² instead of [0, 1]² (Blender's Map Range, `remap`).
        let centred = inputs.as_object_mut().unwrap().remove("centred").is_some();
        inputs["vector"] =
            serde_json::json!({ "link": if centred { "c.result" } else { "geo.position" } });
        let text = serde_json::json!({
            "version": 1, "name": name,
            "nodes": [ { "id": "geo", "type": "geometry" },
                       { "id": "c", "type": "remap", "data_type": "vec3",
                         "inputs": { "x": { "link": "geo.position" }, "to_min": [-1.0, -1.0, 0.0], "to_max": [1.0, 1.0, 1.0] } },
                       { "id": "n", "type": node_type, "inputs": inputs } ],
            "outputs": [ { "name": "out", "from": format!("n.{output}") } ]
        });
        let graph = Graph::from_json(&text.to_string(), Registry::builtin()).unwrap();
        let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
        let out = plan.execute(&batch, &plan.default_parameters()).unwrap();
        let v = out.planar(0);
        let width = v.len() / n;
        let data: Vec<[f32; 4]> = (0..n)
            .map(|i| {
                // The colour space of the PNG is sRGB: the node's values are shown as Blender's
                // viewer shows a colour, encoded from linear.
                let c = |k: usize| v[k.min(width - 1) * n + i];
                [c(0), c(1), c(2), 1.0]
            })
            .collect();
        let image = matgraph::texture::Image::new(SIZE, SIZE, data).unwrap();
        let file = dir.join(format!("{name}.png"));
        matgraph::image_io::save_png(&file, &image).unwrap();
        println!("{}", file.display());
    }
}
