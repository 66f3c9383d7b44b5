//! The `triplanar` node against an f64 reference written here from the GPU Gems 3 ch. 1 blend
//! `w = |N|^blend / Σ |N|^blend` (the plain form, not the node's max-scaled one), at round
//! normals (along an axis, diagonal, in a plane, zero) and seeded random normals, colours and
//! sharpnesses, on the CPU and on the GPU. Per-sample inputs ride on geometry attributes:
//! x = position, y = light, z = light_color, normal = normal, blend = uv.x.

use crate::common;

use common::rng::Rng;
use glam::{DVec3, Vec3};
use matgraph::{Attribute, Graph, OutputBatch, Plan, PlanOptions, Registry, SampleBatch};

#[derive(Clone, Copy, Debug)]
struct Case {
    x: [f32; 3],
    y: [f32; 3],
    z: [f32; 3],
    n: [f32; 3],
    blend: f32,
}

/// The f64 expectation: ⅓ each for a zero normal, `0⁰ = 1` (f64 `powf`).
fn reference(c: Case) -> DVec3 {
    let a = Vec3::from(c.n).as_dvec3().abs();
    let w = if a == DVec3::ZERO {
        DVec3::splat(1.0 / 3.0)
    } else {
        let p = c.blend as f64;
        let t = DVec3::new(a.x.powf(p), a.y.powf(p), a.z.powf(p));
        t / (t.x + t.y + t.z)
    };
    let col = |v: [f32; 3]| Vec3::from(v).as_dvec3();
    col(c.x) * w.x + col(c.y) * w.y + col(c.z) * w.z
}

fn graph() -> Graph {
    let text = serde_json::json!({
        "version": 1, "name": "triplanar",
        "nodes": [
            { "id": "geo", "type": "geometry" },
            { "id": "uv", "type": "split", "inputs": { "v": { "link": "geo.uv" } } },
            { "id": "tp", "type": "triplanar", "inputs": {
                "x": { "link": "geo.position" }, "y": { "link": "geo.light" },
                "z": { "link": "geo.light_color" }, "normal": { "link": "geo.normal" },
                "blend": { "link": "uv.x" } } }
        ],
        "outputs": [ { "name": "color", "from": "tp.color" } ]
    });
    Graph::from_json(&text.to_string(), Registry::builtin()).unwrap_or_else(|e| panic!("{e:?}"))
}

fn evaluate(cases: &[Case]) -> Vec<OutputBatch> {
    let n = cases.len();
    let mut b = SampleBatch::new(n);
    let col = |f: fn(&Case) -> [f32; 3]| cases.iter().map(f).collect::<Vec<_>>();
    b.set_values(Attribute::Position, &col(|c| c.x)).unwrap();
    b.set_values(Attribute::Light, &col(|c| c.y)).unwrap();
    b.set_values(Attribute::LightColor, &col(|c| c.z)).unwrap();
    b.set_values(Attribute::Normal, &col(|c| c.n)).unwrap();
    let blend: Vec<f32> = cases.iter().map(|c| c.blend).collect();
    b.set_planar(Attribute::Uv, [blend, vec![0.0; n]].concat())
        .unwrap();
    let g = graph();
    let plan = Plan::compile(&g, &PlanOptions::default()).unwrap();
    let params = plan.default_parameters();
    let mut outs = vec![plan.execute(&b, &params).unwrap()];
    if let Some(ctx) = common::gpu_context("triplanar (GPU half)") {
        let gpu = matgraph::gpu::GpuPlan::compile(ctx, &g, &PlanOptions::default()).unwrap();
        outs.push(gpu.execute(&b, &params).unwrap());
    }
    outs
}

const R: [f32; 3] = [1.0, 0.0, 0.0];
const G: [f32; 3] = [0.0, 1.0, 0.0];
const B: [f32; 3] = [0.0, 0.0, 1.0];

/// Round normals with the axes' colours red, green, blue (the output is then the weights),
/// then seeded colours, normals of seeded length (10⁻³ to 10³) and sharpness in [0, 16].
fn cases() -> Vec<Case> {
    let round = |n: [f32; 3], blend: f32| Case {
        x: R,
        y: G,
        z: B,
        n,
        blend,
    };
    let mut v = vec![
        round([0.0, 0.0, 1.0], 4.0),
        round([0.0, -1.0, 0.0], 4.0),
        round([1.0, 1.0, 1.0], 4.0),
        round([1.0, 2.0, 0.0], 1.0),
        round([1.0, 2.0, 0.0], 2.0),
        round([-3.0, 0.5, 0.25], 0.0),
        round([0.0, 0.0, 0.0], 4.0),
        round([0.5, -0.5, 0.0], 16.0),
    ];
    let mut rng = Rng(0x7819_a4a1);
    for _ in 0..400 {
        let c = |r: &mut Rng| [r.f(0.0, 1.0), r.f(0.0, 1.0), r.f(0.0, 1.0)];
        let (x, y, z) = (c(&mut rng), c(&mut rng), c(&mut rng));
        let s = 10f64.powf(rng.unit() * 6.0 - 3.0);
        let n = [rng.f(-s, s), rng.f(-s, s), rng.f(-s, s)];
        v.push(Case {
            x,
            y,
            z,
            n,
            blend: rng.f(0.0, 16.0),
        });
    }
    v
}

fn got(out: &OutputBatch, n: usize, i: usize) -> DVec3 {
    let p = out.planar(0);
    DVec3::new(p[i] as f64, p[n + i] as f64, p[2 * n + i] as f64)
}

/// Every case on each backend within 3e-6 of the f64 reference (colours in [0, 1]: the
/// power's few ULP, the division and the weighted sum).
#[test]
fn triplanar_matches_an_f64_reference() {
    let cases = cases();
    let n = cases.len();
    let mut worst = 0.0f64;
    for (b, out) in evaluate(&cases).iter().enumerate() {
        for (i, c) in cases.iter().enumerate() {
            let (got, want) = (got(out, n, i), reference(*c));
            let err = (got - want).abs().max_element();
            worst = worst.max(err);
            assert!(err < 3e-6, "backend {b} case {i} {c:?}: {got} want {want}");
        }
    }
    println!("triplanar: worst {worst:.1e}");
}

/// The closed forms: N along an axis gives that axis's colour; the diagonal gives the
/// average; (1, 2, 0) at blend 1 weights ⅓, ⅔, 0 and at blend 2 ⅕, ⅘, 0; blend 0 averages
/// even with a zero component; a zero normal gives ⅓ each, not NaN.
#[test]
fn the_weights_read_as_closed_forms() {
    let cases = cases();
    let n = cases.len();
    let t = 1.0 / 3.0;
    let want = [
        [0.0, 0.0, 1.0],
        [0.0, 1.0, 0.0],
        [t, t, t],
        [t, 2.0 * t, 0.0],
        [0.2, 0.8, 0.0],
        [t, t, t],
        [t, t, t],
        [0.5, 0.5, 0.0],
    ];
    for out in evaluate(&cases) {
        for (i, w) in want.iter().enumerate() {
            let got = got(&out, n, i);
            assert!(
                (got - DVec3::from(*w)).abs().max_element() < 1e-6,
                "case {i}: {got} want {w:?}"
            );
        }
    }
}
