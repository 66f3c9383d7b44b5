//! The `bump` node (Blender's Bump; Mikkelsen 2010, eq. 2–4) against an f64 reference
//! written here, on the CPU and the GPU: the node alone at round and seeded points (its
//! shifted heights and offsets supplied), and the compiler's shifted evaluations
//! (`matgraph::bump`) against closed forms: a height linear in the position tilts the normal
//! by the height's tangential gradient whatever the pixel offsets, and a height of the uv is
//! differenced at the uv moved by its derivatives.
//!
//! Per-sample inputs ride on geometry attributes.

use crate::common;

use common::rng::Rng;
use glam::{DVec3, Vec2, Vec3};
use matgraph::{Attribute, Graph, OutputBatch, Plan, PlanOptions, Registry, SampleBatch};

/// One evaluation of the node.
#[derive(Clone, Copy, Debug)]
struct Case {
    height: f32,
    height_dx: f32,
    height_dy: f32,
    distance: f32,
    strength: f32,
    n: Vec3,
    dpdx: Vec3,
    dpdy: Vec3,
}

/// Mikkelsen's surface gradient (Blender's node_bump), in f64: `Rx = dPdy × N`,
/// `Ry = N × dPdx`, `det = dPdx · Rx`, `∇s = (h_x − h) Rx + (h_y − h) Ry`,
/// `N' = normalize(|det| N − d sign(det) ∇s)`, `normalize(N + (N' − N) s)`.
fn reference(c: Case, invert: bool) -> DVec3 {
    let n = c.n.as_dvec3().normalize();
    let (dx, dy) = (c.dpdx.as_dvec3(), c.dpdy.as_dvec3());
    let rx = dy.cross(n);
    let ry = n.cross(dx);
    let det = dx.dot(rx);
    let h = c.height as f64;
    let grad = rx * (c.height_dx as f64 - h) + ry * (c.height_dy as f64 - h);
    let d = if invert { -c.distance } else { c.distance } as f64;
    let tilted = (n * det.abs() - grad * (d * det.signum())).normalize();
    (n + (tilted - n) * c.strength as f64).normalize()
}

/// The node with every input linked: heights from position, distance from depth, strength
/// from uv.x, offsets from the position derivatives.
fn node_graph(invert: bool) -> Graph {
    let text = serde_json::json!({
        "version": 1, "name": "bump",
        "nodes": [
            { "id": "geo", "type": "geometry" },
            { "id": "d", "type": "position_derivatives" },
            { "id": "h", "type": "split", "inputs": { "v": { "link": "geo.position" } } },
            { "id": "uv", "type": "split", "inputs": { "v": { "link": "geo.uv" } } },
            { "id": "b", "type": "bump", "inputs": {
                "height": { "link": "h.x" }, "height_dx": { "link": "h.y" },
                "height_dy": { "link": "h.z" }, "distance": { "link": "geo.depth" },
                "strength": { "link": "uv.x" }, "invert": invert,
                "normal": { "link": "geo.normal" },
                "position_dx": { "link": "d.position_dx" }, "position_dy": { "link": "d.position_dy" } } }
        ],
        "outputs": [ { "name": "normal", "from": "b.normal" } ]
    });
    Graph::from_json(&text.to_string(), Registry::builtin()).unwrap_or_else(|e| panic!("{e:?}"))
}

/// The CPU's outputs, then the GPU's where an adapter is present.
fn run(g: &Graph, b: &SampleBatch, what: &str) -> Vec<OutputBatch> {
    let plan = Plan::compile(g, &PlanOptions::default()).unwrap();
    let params = plan.default_parameters();
    let mut outs = vec![plan.execute(b, &params).unwrap()];
    if let Some(ctx) = common::gpu_context(what) {
        let gpu = matgraph::gpu::GpuPlan::compile(ctx, g, &PlanOptions::default()).unwrap();
        outs.push(gpu.execute(b, &params).unwrap());
    }
    outs
}

fn evaluate(cases: &[Case], invert: bool) -> Vec<OutputBatch> {
    let n = cases.len();
    let mut b = SampleBatch::new(n);
    let col = |f: &dyn Fn(&Case) -> [f32; 3]| cases.iter().map(f).collect::<Vec<_>>();
    b.set_values(
        Attribute::Position,
        &col(&|c| [c.height, c.height_dx, c.height_dy]),
    )
    .unwrap();
    b.set_values(Attribute::Normal, &col(&|c| c.n.to_array()))
        .unwrap();
    b.set_values(Attribute::PositionDx, &col(&|c| c.dpdx.to_array()))
        .unwrap();
    b.set_values(Attribute::PositionDy, &col(&|c| c.dpdy.to_array()))
        .unwrap();
    let strength: Vec<f32> = cases.iter().map(|c| c.strength).collect();
    b.set_planar(Attribute::Uv, [strength, vec![0.0; n]].concat())
        .unwrap();
    b.set_planar(Attribute::Depth, cases.iter().map(|c| c.distance).collect())
        .unwrap();
    run(&node_graph(invert), &b, "bump (GPU half)")
}

fn unit(r: &mut Rng) -> Vec3 {
    loop {
        let v = Vec3::new(r.f(-1.0, 1.0), r.f(-1.0, 1.0), r.f(-1.0, 1.0));
        if v.length() > 0.2 && v.length() <= 1.0 {
            return v.normalize();
        }
    }
}

/// Two offsets in the plane of `n` a pixel apart, of `scale` metres, in a seeded direction
/// (either handedness).
fn offsets(r: &mut Rng, n: Vec3, scale: f32) -> (Vec3, Vec3) {
    let t = (unit(r) - n * n.dot(unit(r))).normalize();
    let t = (t - n * n.dot(t)).normalize();
    let b = n.cross(t);
    let flip = if r.next() & 1 == 0 { 1.0 } else { -1.0 };
    (
        t * scale * r.f(0.5, 2.0),
        (b * flip + t * r.f(-0.3, 0.3)) * scale * r.f(0.5, 2.0),
    )
}

/// Round cases (a flat plane facing +z seen straight on, the slopes of 45°), then seeded
/// ones: random normals, offsets from 10 µm to 1 cm per pixel, heights, distances and
/// strengths.
fn cases() -> Vec<Case> {
    let flat = |hx: f32, hy: f32, distance: f32, strength: f32| Case {
        height: 0.0,
        height_dx: hx,
        height_dy: hy,
        distance,
        strength,
        n: Vec3::Z,
        dpdx: Vec3::new(0.001, 0.0, 0.0),
        dpdy: Vec3::new(0.0, -0.001, 0.0),
    };
    let mut v = vec![
        flat(0.0, 0.0, 1.0, 1.0),
        flat(0.001, 0.0, 1.0, 1.0),
        flat(0.0, 0.001, 1.0, 1.0),
        flat(0.001, 0.0, 0.5, 0.5),
        flat(-0.002, 0.001, 1.0, 0.25),
    ];
    let mut rng = Rng(0xb0_3b);
    for _ in 0..400 {
        let n = unit(&mut rng);
        let scale = 10f32.powf(rng.f(-5.0, -2.0));
        let (dpdx, dpdy) = offsets(&mut rng, n, scale);
        let h = rng.f(-1.0, 1.0);
        v.push(Case {
            height: h,
            height_dx: h + rng.f(-1.0, 1.0) * scale,
            height_dy: h + rng.f(-1.0, 1.0) * scale,
            distance: rng.f(0.0, 2.0),
            strength: rng.f(0.0, 1.0),
            n,
            dpdx,
            dpdy,
        });
    }
    v
}

fn vec3_at(out: &OutputBatch, n: usize, i: usize) -> DVec3 {
    DVec3::new(
        out.planar(0)[i] as f64,
        out.planar(0)[n + i] as f64,
        out.planar(0)[2 * n + i] as f64,
    )
}

/// The node against the f64 reference, inverted and not, on each backend. The bound: the
/// heights' differences are formed in f32 from heights up to 1 with steps down to 10⁻⁵, so a
/// slope carries up to ~2⁻²⁴/10⁻⁵ ≈ 6e-3 relative error of its own (the reference differences
/// the same f32 heights, so that part is shared); the rest is a few roundings of the cross
/// products and the two normalisations.
#[test]
fn bump_matches_an_f64_reference() {
    let cases = cases();
    let n = cases.len();
    for invert in [false, true] {
        let mut worst = 0.0f64;
        for (b, out) in evaluate(&cases, invert).iter().enumerate() {
            for (i, c) in cases.iter().enumerate() {
                let want = reference(*c, invert);
                let got = vec3_at(out, n, i);
                let err = (got - want).length();
                worst = worst.max(err);
                assert!(
                    err < 4e-6,
                    "invert {invert} backend {b} case {i} {c:?}: {got} want {want}"
                );
            }
        }
        println!("bump invert {invert}: worst {worst:.1e}");
    }
}

/// Blender's readings of the node: a height rising to the right (+x on a +z plane seen
/// straight on) tilts the normal to the left; a slope of 1 at distance 1 is 45°; invert and
/// a negative slope are the same tilt; strength 0 is the normal; no offsets (no scene) keep
/// the normal.
#[test]
fn the_tilt_reads_as_blenders() {
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let flat = |hx: f32, dpdx: Vec3, strength: f32| Case {
        height: 0.0,
        height_dx: hx,
        height_dy: 0.0,
        distance: 1.0,
        strength,
        n: Vec3::Z,
        dpdx,
        dpdy: Vec3::new(0.0, -0.001, 0.0),
    };
    let px = Vec3::new(0.001, 0.0, 0.0);
    let cases = [
        flat(0.001, px, 1.0),
        flat(-0.001, px, 1.0),
        flat(0.001, px, 0.0),
        flat(0.5, Vec3::ZERO, 1.0),
    ];
    let want = [
        DVec3::new(-s, 0.0, s),
        DVec3::new(s, 0.0, s),
        DVec3::Z,
        DVec3::Z,
    ];
    for invert in [false, true] {
        for out in evaluate(&cases, invert) {
            for (i, w) in want.iter().enumerate() {
                let w = if invert && i < 2 {
                    DVec3::new(-w.x, w.y, w.z)
                } else {
                    *w
                };
                let got = vec3_at(&out, cases.len(), i);
                assert!(
                    (got - w).length() < 1e-6,
                    "invert {invert} case {i}: {got} want {w}"
                );
            }
        }
    }
}

/// A height linear in the position, `h = g · P`, on any surface: the shifted evaluations
/// difference it exactly (up to rounding), so the bump is `normalize(N − d (g − (g·N) N))`,
/// the tilt by the height's gradient along the surface, whatever the pixel offsets (the
/// offsets cancel out of Mikkelsen's formula for a linear field). The heights and their
/// one-pixel shifts are made by the compiler (`height_dx`, `height_dy`, `normal` unlinked).
#[test]
fn a_linear_height_tilts_by_its_surface_gradient() {
    let g = DVec3::new(0.3, -0.7, 0.45);
    let distance = 0.8;
    let text = serde_json::json!({
        "version": 1, "name": "bump_linear",
        "nodes": [
            { "id": "geo", "type": "geometry" },
            { "id": "h", "type": "dot", "inputs": { "a": { "link": "geo.position" }, "b": [g.x, g.y, g.z] } },
            { "id": "b", "type": "bump", "inputs": { "height": { "link": "h.result" }, "distance": distance } }
        ],
        "outputs": [ { "name": "normal", "from": "b.normal" } ]
    });
    let graph = Graph::from_json(&text.to_string(), Registry::builtin()).unwrap();
    let mut rng = Rng(0x11_4ea2);
    let m = 300;
    let (mut p, mut nn, mut dx, mut dy) = (vec![], vec![], vec![], vec![]);
    for _ in 0..m {
        let n = unit(&mut rng);
        let (a, b) = offsets(&mut rng, n, 0.01);
        p.push([rng.f(-1.0, 1.0), rng.f(-1.0, 1.0), rng.f(-1.0, 1.0)]);
        nn.push(n.to_array());
        dx.push(a.to_array());
        dy.push(b.to_array());
    }
    let mut batch = SampleBatch::new(m);
    batch.set_values(Attribute::Position, &p).unwrap();
    batch.set_values(Attribute::Normal, &nn).unwrap();
    batch.set_values(Attribute::PositionDx, &dx).unwrap();
    batch.set_values(Attribute::PositionDy, &dy).unwrap();
    let mut worst = 0.0f64;
    for out in run(&graph, &batch, "bump linear height (GPU half)") {
        for (i, &normal) in nn.iter().enumerate() {
            let n = Vec3::from(normal).as_dvec3();
            let want = (n - (g - n * g.dot(n)) * distance).normalize();
            let got = vec3_at(&out, m, i);
            let err = (got - want).length();
            worst = worst.max(err);
            // g · P is rounded at |h| ≤ 1.5 (2⁻²⁴ · 1.5) and differenced over steps of
            // 5 mm to 2 cm: a slope error up to ~2e-5 relative, times |d g| ≈ 0.7.
            assert!(err < 1e-4, "sample {i}: {got} want {want}");
        }
    }
    println!("linear height: worst {worst:.1e}");
}

/// A height of the uv, `h = sin(a·u) · cos(b·v)`: the shifted evaluations read it at
/// `uv + ∂uv/∂x` and `uv + ∂uv/∂y` (the uv derivatives the caller supplies), the f64
/// reference differences the same function there, and the result follows Mikkelsen's
/// formula with the position offsets.
#[test]
fn a_height_of_the_uv_is_differenced_at_the_moved_uv() {
    let (a, bf) = (7.0f64, 5.0f64);
    let text = serde_json::json!({
        "version": 1, "name": "bump_uv",
        "nodes": [
            { "id": "geo", "type": "geometry" },
            { "id": "uv", "type": "split", "inputs": { "v": { "link": "geo.uv" } } },
            { "id": "au", "type": "mul", "inputs": { "a": { "link": "uv.x" }, "b": a } },
            { "id": "bv", "type": "mul", "inputs": { "a": { "link": "uv.y" }, "b": bf } },
            { "id": "s", "type": "sin", "inputs": { "x": { "link": "au.result" } } },
            { "id": "c", "type": "cos", "inputs": { "x": { "link": "bv.result" } } },
            { "id": "h", "type": "mul", "inputs": { "a": { "link": "s.result" }, "b": { "link": "c.result" } } },
            { "id": "b", "type": "bump", "inputs": { "height": { "link": "h.result" }, "distance": 0.05 } }
        ],
        "outputs": [ { "name": "normal", "from": "b.normal" } ]
    });
    let graph = Graph::from_json(&text.to_string(), Registry::builtin()).unwrap();
    let mut rng = Rng(0x0b_0fe5);
    let m = 300;
    let (mut uv, mut duvx, mut duvy, mut dx, mut dy) = (vec![], vec![], vec![], vec![], vec![]);
    for _ in 0..m {
        uv.push([rng.f(0.0, 1.0), rng.f(0.0, 1.0), 0.0]);
        duvx.push([rng.f(0.002, 0.01), rng.f(-0.002, 0.002), 0.0]);
        duvy.push([rng.f(-0.002, 0.002), -rng.f(0.002, 0.01), 0.0]);
        let (p, q) = offsets(&mut rng, Vec3::Z, 0.01);
        dx.push(p.to_array());
        dy.push(q.to_array());
    }
    let mut batch = SampleBatch::new(m);
    batch.set_values(Attribute::Uv, &uv).unwrap();
    batch.set_values(Attribute::UvDx, &duvx).unwrap();
    batch.set_values(Attribute::UvDy, &duvy).unwrap();
    batch.set_values(Attribute::PositionDx, &dx).unwrap();
    batch.set_values(Attribute::PositionDy, &dy).unwrap();
    let h = |u: Vec2| ((a * u.x as f64).sin() * (bf * u.y as f64).cos()) as f32;
    let mut worst = 0.0f64;
    for (backend, out) in run(&graph, &batch, "bump uv height (GPU half)")
        .iter()
        .enumerate()
    {
        for i in 0..m {
            let u = Vec2::new(uv[i][0], uv[i][1]);
            let c = Case {
                height: h(u),
                height_dx: h(u + Vec2::new(duvx[i][0], duvx[i][1])),
                height_dy: h(u + Vec2::new(duvy[i][0], duvy[i][1])),
                distance: 0.05,
                strength: 1.0,
                n: Vec3::Z,
                dpdx: Vec3::from(dx[i]),
                dpdy: Vec3::from(dy[i]),
            };
            let want = reference(c, false);
            let got = vec3_at(out, m, i);
            let err = (got - want).length();
            worst = worst.max(err);
            // The sin and cos nodes are the node's own polynomials on both backends (a few
            // ULP, nodes/precise.rs); 2e-4 covers the heights' f32 differences over steps of
            // ≥ 0.014.
            let bound = 2e-4;
            assert!(
                err < bound,
                "backend {backend} sample {i}: {got} want {want}"
            );
        }
    }
    println!("uv height: worst {worst:.1e}");
}
