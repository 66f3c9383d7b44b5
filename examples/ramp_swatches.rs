//! Pictures of `color_ramp`, `float_curve` and `rgb_curves` for docs/models/ramps.md, each
//! evaluated on the CPU through a graph over a grid of positions in [0, 1]², written as 8-bit
//! sRGB PNGs:
//!
//! - `ramps.png`: one ramp of five stops (one a 50 % alpha that the picture ignores), read at
//!   x, with each interpolation in a band, top to bottom: constant, linear, ease, cardinal,
//!   b_spline;
//! - `float_curve.png`: an S-curve of four points plotted (white below it), the points as dots;
//! - `rgb_curves.png`: the colours (x, y, 0.5) through a contrast S-curve on C and a red lift,
//!   input on the left half, output on the right.
//!
//! `cargo run --release --example ramp_swatches` writes docs/models/ramps/*.png.

use matgraph::texture::Image;
use matgraph::{Attribute, Graph, Plan, PlanOptions, Registry, SampleBatch};
use serde_json::{Value, json};
use std::path::Path;

/// Pixels a side.
const SIZE: u32 = 256;

/// The ramp's stops: (position, RGBA).
const STOPS: [(f32, [f32; 4]); 5] = [
    (0.05, [0.02, 0.02, 0.1, 1.0]),
    (0.3, [0.8, 0.05, 0.05, 1.0]),
    (0.5, [1.0, 0.6, 0.0, 0.5]),
    (0.7, [0.05, 0.5, 0.1, 1.0]),
    (0.95, [0.9, 0.9, 1.0, 1.0]),
];

/// The float curve's points (an S-curve).
const S_CURVE: [[f32; 2]; 4] = [[0.0, 0.0], [0.3, 0.15], [0.7, 0.85], [1.0, 1.0]];

/// Evaluates `node` (its `link` input taking `geo.position`, split into x, y, z as `sp`) at
/// `points` and returns output `out` as RGB per point.
fn run(points: &[[f32; 3]], node: Value, out: &str) -> Vec<[f32; 3]> {
    let n = points.len();
    let mut batch = SampleBatch::new(n);
    batch.set_values(Attribute::Position, points).unwrap();
    let text = json!({
        "version": 1, "name": "swatch",
        "nodes": [ { "id": "geo", "type": "geometry" },
                   { "id": "sp", "type": "split", "inputs": { "v": { "link": "geo.position" } } },
                   node ],
        "outputs": [ { "name": "out", "from": format!("n.{out}") } ]
    });
    let graph = Graph::from_json(&text.to_string(), Registry::builtin()).unwrap();
    let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
    let o = plan.execute(&batch, &plan.default_parameters()).unwrap();
    let v = o.planar(0);
    let width = v.len() / n;
    (0..n)
        .map(|i| std::array::from_fn(|k| v[k.min(width - 1) * n + i]))
        .collect()
}

/// The grid's positions, y up, pixel centres.
fn grid(w: u32, h: u32) -> Vec<[f32; 3]> {
    (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32, (i / w) as f32);
            [(x + 0.5) / w as f32, 1.0 - (y + 0.5) / h as f32, 0.5]
        })
        .collect()
}

fn save(dir: &Path, name: &str, w: u32, h: u32, rgb: Vec<[f32; 3]>) {
    let data = rgb.into_iter().map(|c| [c[0], c[1], c[2], 1.0]).collect();
    let file = dir.join(format!("{name}.png"));
    matgraph::image_io::save_png(&file, &Image::new(w, h, data).unwrap()).unwrap();
    println!("{}", file.display());
}

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/models/ramps");
    std::fs::create_dir_all(&dir).unwrap();
    // Ramps: five bands of 40 rows.
    let (w, band) = (SIZE, 40);
    let modes = ["constant", "linear", "ease", "cardinal", "b_spline"];
    let xs = grid(w, 1);
    let mut rows = Vec::new();
    for mode in modes {
        let mut inputs = json!({ "fac": { "link": "sp.x" }, "interpolation": mode, "count": 5 });
        for (k, (p, c)) in STOPS.iter().enumerate() {
            inputs[format!("pos_{k}")] = json!(p);
            inputs[format!("color_{k}")] = json!(c);
        }
        let line = run(
            &xs,
            json!({ "id": "n", "type": "color_ramp", "inputs": inputs }),
            "color",
        );
        for r in 0..band {
            // A dark row between bands.
            rows.extend(
                line.iter()
                    .map(|c| if r == band - 1 { [0.0; 3] } else { *c }),
            );
        }
    }
    save(&dir, "ramps", w, band * modes.len() as u32, rows);

    // The float curve, plotted.
    let mut inputs = json!({ "value": { "link": "sp.x" }, "count": 4 });
    for (k, p) in S_CURVE.iter().enumerate() {
        inputs[format!("point_{k}")] = json!(p);
    }
    let ys = run(
        &xs,
        json!({ "id": "n", "type": "float_curve", "inputs": inputs }),
        "value",
    );
    let plot: Vec<[f32; 3]> = grid(SIZE, SIZE)
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let y = ys[i % SIZE as usize][0];
            let near_point = S_CURVE
                .iter()
                .any(|q| (q[0] - p[0]).hypot(q[1] - p[1]) < 0.02);
            match (near_point, p[1] <= y) {
                (true, _) => [1.0, 0.3, 0.0],
                (false, true) => [0.8; 3],
                (false, false) => [0.05; 3],
            }
        })
        .collect();
    save(&dir, "float_curve", SIZE, SIZE, plot);

    // RGB curves: left the input, right the output.
    let pts = grid(SIZE, SIZE);
    let colors: Vec<[f32; 3]> = pts
        .iter()
        .map(|p| [(2.0 * p[0]).fract(), p[1], 0.5])
        .collect();
    let mut inputs = json!({ "color": { "link": "c.color" }, "c_count": 4, "r_count": 3 });
    for (k, p) in S_CURVE.iter().enumerate() {
        inputs[format!("c_{k}")] = json!(p);
    }
    inputs["r_2"] = json!([0.4, 0.6]);
    let node = json!({ "id": "n", "type": "rgb_curves", "inputs": inputs });
    let shown = run_colors(&pts, &colors, node);
    let out: Vec<[f32; 3]> = (0..pts.len())
        .map(|i| if pts[i][0] < 0.5 { colors[i] } else { shown[i] })
        .collect();
    save(&dir, "rgb_curves", SIZE, SIZE, out);
}

/// [`run`] with the colour computed in the graph from the position: ((2x) mod 1, y, 0.5).
fn run_colors(points: &[[f32; 3]], _colors: &[[f32; 3]], node: Value) -> Vec<[f32; 3]> {
    let n = points.len();
    let mut batch = SampleBatch::new(n);
    batch.set_values(Attribute::Position, points).unwrap();
    let text = json!({
        "version": 1, "name": "swatch",
        "nodes": [ { "id": "geo", "type": "geometry" },
                   { "id": "sp", "type": "split", "inputs": { "v": { "link": "geo.position" } } },
                   { "id": "x2", "type": "mul", "inputs": { "a": { "link": "sp.x" }, "b": 2.0 } },
                   { "id": "fx", "type": "fract", "inputs": { "x": { "link": "x2.result" } } },
                   { "id": "c", "type": "combine", "inputs": {
                       "x": { "link": "fx.result" }, "y": { "link": "sp.y" }, "z": 0.5 } },
                   node ],
        "outputs": [ { "name": "out", "from": "n.color" } ]
    });
    let graph = Graph::from_json(&text.to_string(), Registry::builtin()).unwrap();
    let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
    let o = plan.execute(&batch, &plan.default_parameters()).unwrap();
    let v = o.planar(0);
    (0..n)
        .map(|i| std::array::from_fn(|k| v[k * n + i]))
        .collect()
}
