//! The `normal_map` node (Blender's Normal Map) against an f64 reference written here from
//! the frame (T, B = s N × T, N) and the strength blend, at round texels (flat, ±x, ±y,
//! mirrored, DirectX) and seeded random ones with random orthonormal frames, in every space,
//! on the CPU and on the GPU. Per-sample inputs ride on geometry attributes: color =
//! position, normal = normal, tangent = light, sign = depth, strength = uv.x.

use crate::common;

use common::rng::Rng;
use glam::{DVec3, Vec3};
use matgraph::{Attribute, Graph, OutputBatch, Plan, PlanOptions, Registry, SampleBatch};

#[derive(Clone, Copy, Debug)]
struct Case {
    color: [f32; 3],
    strength: f32,
    n: Vec3,
    t: Vec3,
    sign: f32,
}

/// The f64 expectation.
fn reference(c: Case, space: &str, convention: &str) -> DVec3 {
    let mut col = Vec3::from(c.color)
        .as_dvec3()
        .clamp(DVec3::ZERO, DVec3::ONE);
    if convention == "directx" {
        col.y = 1.0 - col.y;
    }
    let m = col * 2.0 - DVec3::ONE;
    let (n, t) = (c.n.as_dvec3(), c.t.as_dvec3());
    let mapped = match space {
        "tangent" => {
            let b = n.cross(t) * if c.sign >= 0.0 { 1.0 } else { -1.0 };
            t * m.x + b * m.y + n * m.z
        }
        _ => m,
    };
    let u = mapped.normalize();
    (n + (u - n) * c.strength.max(0.0) as f64).normalize()
}

fn graph(space: &str, convention: &str) -> Graph {
    let text = serde_json::json!({
        "version": 1, "name": "normal_map",
        "nodes": [
            { "id": "geo", "type": "geometry" },
            { "id": "uv", "type": "split", "inputs": { "v": { "link": "geo.uv" } } },
            { "id": "nm", "type": "normal_map", "inputs": {
                "color": { "link": "geo.position" }, "strength": { "link": "uv.x" },
                "normal": { "link": "geo.normal" }, "tangent": { "link": "geo.light" },
                "bitangent_sign": { "link": "geo.depth" },
                "space": space, "convention": convention } }
        ],
        "outputs": [ { "name": "normal", "from": "nm.normal" } ]
    });
    Graph::from_json(&text.to_string(), Registry::builtin()).unwrap_or_else(|e| panic!("{e:?}"))
}

fn evaluate(space: &str, convention: &str, cases: &[Case]) -> Vec<OutputBatch> {
    let n = cases.len();
    let mut b = SampleBatch::new(n);
    let col = |f: fn(&Case) -> [f32; 3]| cases.iter().map(f).collect::<Vec<_>>();
    b.set_values(Attribute::Position, &col(|c| c.color))
        .unwrap();
    b.set_values(Attribute::Normal, &col(|c| c.n.to_array()))
        .unwrap();
    b.set_values(Attribute::Light, &col(|c| c.t.to_array()))
        .unwrap();
    let strength: Vec<f32> = cases.iter().map(|c| c.strength).collect();
    b.set_planar(Attribute::Uv, [strength, vec![0.0; n]].concat())
        .unwrap();
    b.set_planar(Attribute::Depth, cases.iter().map(|c| c.sign).collect())
        .unwrap();
    let g = graph(space, convention);
    let plan = Plan::compile(&g, &PlanOptions::default()).unwrap();
    let params = plan.default_parameters();
    let mut outs = vec![plan.execute(&b, &params).unwrap()];
    if let Some(ctx) = common::gpu_context("normal_map (GPU half)") {
        let gpu = matgraph::gpu::GpuPlan::compile(ctx, &g, &PlanOptions::default()).unwrap();
        outs.push(gpu.execute(&b, &params).unwrap());
    }
    outs
}

fn unit(r: &mut Rng) -> Vec3 {
    loop {
        let v = Vec3::new(r.f(-1.0, 1.0), r.f(-1.0, 1.0), r.f(-1.0, 1.0));
        if v.length() > 0.2 && v.length() <= 1.0 {
            return v.normalize();
        }
    }
}

/// Round texels in the canonical frame, then seeded texels in seeded orthonormal frames.
fn cases() -> Vec<Case> {
    let (z, x) = (Vec3::Z, Vec3::X);
    let round = |color: [f32; 3], strength: f32, sign: f32| Case {
        color,
        strength,
        n: z,
        t: x,
        sign,
    };
    let mut v = vec![
        round([0.5, 0.5, 1.0], 1.0, 1.0),
        round([1.0, 0.5, 0.5], 1.0, 1.0),
        round([0.5, 1.0, 0.5], 1.0, 1.0),
        round([0.5, 1.0, 0.5], 1.0, -1.0),
        round([0.0, 0.0, 1.0], 0.5, 1.0),
        round([0.75, 0.25, 0.9], 2.0, -1.0),
    ];
    let mut rng = Rng(0x4e_0a11);
    for _ in 0..400 {
        let n = unit(&mut rng);
        let t = (unit(&mut rng) - n * n.dot(unit(&mut rng))).normalize();
        let t = (t - n * n.dot(t)).normalize();
        if !t.is_finite() {
            continue;
        }
        v.push(Case {
            color: [rng.f(0.0, 1.0), rng.f(0.0, 1.0), rng.f(0.55, 1.0)],
            strength: rng.f(0.0, 2.0),
            n,
            t,
            sign: if rng.next() & 1 == 0 { 1.0 } else { -1.0 },
        });
    }
    v
}

/// Every space and convention on each backend within 4e-6 of the f64 reference (a unit
/// vector: a few f32 roundings of the frame, the two normalisations and the GPU's division).
#[test]
fn normal_map_matches_an_f64_reference_in_every_space_and_convention() {
    let cases = cases();
    let n = cases.len();
    for space in ["tangent", "object", "world"] {
        for convention in ["opengl", "directx"] {
            let mut worst = 0.0f64;
            for (b, out) in evaluate(space, convention, &cases).iter().enumerate() {
                for (i, c) in cases.iter().enumerate() {
                    let want = reference(*c, space, convention);
                    if !want.is_finite() {
                        continue;
                    }
                    let got = DVec3::new(
                        out.planar(0)[i] as f64,
                        out.planar(0)[n + i] as f64,
                        out.planar(0)[2 * n + i] as f64,
                    );
                    let err = (got - want).length();
                    worst = worst.max(err);
                    assert!(
                        err < 4e-6,
                        "{space} {convention} backend {b} case {i} {c:?}: {got} want {want}"
                    );
                }
            }
            println!("normal_map {space} {convention}: worst {worst:.1e}");
        }
    }
}

/// The closed forms users check a normal map by: the flat texel gives N, (1, ½, ½) gives T,
/// (½, 1, ½) gives B = N × T in OpenGL's convention and −B in DirectX's (and a mirrored sign
/// flips it), strength 0 gives N, and a grey texel (no direction) keeps N.
#[test]
fn the_frame_reads_as_blenders() {
    let (n, t) = (Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 0.0, -1.0));
    let b = n.cross(t);
    let c = |color: [f32; 3], strength: f32, sign: f32| Case {
        color,
        strength,
        n,
        t,
        sign,
    };
    let cases = [
        c([0.5, 0.5, 1.0], 1.0, 1.0),
        c([1.0, 0.5, 0.5], 1.0, 1.0),
        c([0.5, 1.0, 0.5], 1.0, 1.0),
        c([0.5, 1.0, 0.5], 1.0, -1.0),
        c([1.0, 0.0, 0.5], 0.0, 1.0),
        c([0.5, 0.5, 0.5], 1.0, 1.0),
    ];
    for (convention, green) in [("opengl", b), ("directx", -b)] {
        let want = [n, t, green, -green, n, n];
        for out in evaluate("tangent", convention, &cases) {
            for (i, w) in want.iter().enumerate() {
                let got = Vec3::new(
                    out.planar(0)[i],
                    out.planar(0)[6 + i],
                    out.planar(0)[12 + i],
                );
                assert!(
                    (got - *w).length() < 1e-6,
                    "{convention} case {i}: {got} want {w}"
                );
            }
        }
    }
}
