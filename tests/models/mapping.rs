//! The `mapping` node (Blender's Mapping) against an f64 reference written here from three
//! axis rotations composed as matrices (not the node's expanded Euler formula), at round and
//! seeded random f32 points for every type, and its rotation against Blender's own: Vector
//! Rotate's Euler XYZ mode evaluated by Blender 4.2 (tests/blender/mapping_reference.py),
//! which turns by the same matrix as Mapping. Evaluated through a graph on the CPU, and on the
//! GPU where there is one; the per-sample inputs ride on geometry attributes so that one graph
//! covers every case.

use crate::common;

use common::rng::Rng;
use matgraph::{Attribute, Graph, OutputBatch, Plan, PlanOptions, Registry, SampleBatch};
use serde_json::Value as J;

/// One case: vector, location, rotation, scale.
#[derive(Clone, Copy, Debug)]
struct Case {
    v: [f32; 3],
    t: [f32; 3],
    r: [f32; 3],
    s: [f32; 3],
}

type M3 = [[f64; 3]; 3];

fn mul(a: M3, b: M3) -> M3 {
    let mut m = [[0.0; 3]; 3];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    m
}

/// A right-handed turn by `a` radians about axis `k` (0 = x, 1 = y, 2 = z).
fn turn(k: usize, a: f64) -> M3 {
    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
    let mut m = [[0.0; 3]; 3];
    m[k][k] = 1.0;
    m[i][i] = a.cos();
    m[j][j] = a.cos();
    m[j][i] = a.sin();
    m[i][j] = -a.sin();
    m
}

/// Euler XYZ: x turned first, then y, then z, about the fixed axes.
fn euler(r: [f32; 3]) -> M3 {
    mul(
        turn(2, r[2] as f64),
        mul(turn(1, r[1] as f64), turn(0, r[0] as f64)),
    )
}

fn apply(m: M3, v: [f64; 3], transposed: bool) -> [f64; 3] {
    [0, 1, 2].map(|i| {
        (0..3)
            .map(|j| if transposed { m[j][i] } else { m[i][j] } * v[j])
            .sum()
    })
}

fn f64s(a: [f32; 3]) -> [f64; 3] {
    a.map(|x| x as f64)
}

/// The expected output in f64 and, per component, the magnitude its f32 rounding scales
/// with (the sum of the terms' absolute values).
fn reference(kind: &str, c: Case) -> ([f64; 3], [f64; 3]) {
    let m = euler(c.r);
    let abs_m = m.map(|row| row.map(f64::abs));
    let (v, t, s) = (f64s(c.v), f64s(c.t), f64s(c.s));
    let div = |a: f64, b: f64| if b != 0.0 { a / b } else { 0.0 };
    match kind {
        "point" | "vector" => {
            let vs = [0, 1, 2].map(|i| v[i] * s[i]);
            let mut out = apply(m, vs, false);
            let mut mag = apply(abs_m, vs.map(f64::abs), false);
            if kind == "point" {
                for i in 0..3 {
                    out[i] += t[i];
                    mag[i] += t[i].abs();
                }
            }
            (out, mag)
        }
        "texture" => {
            let p = [0, 1, 2].map(|i| v[i] - t[i]);
            let q = apply(m, p, true);
            let pm = [0, 1, 2].map(|i| v[i].abs() + t[i].abs());
            let qm = apply(abs_m, pm, true);
            (
                [0, 1, 2].map(|i| div(q[i], s[i])),
                [0, 1, 2].map(|i| div(qm[i], s[i]).abs()),
            )
        }
        _ => {
            let q = apply(m, [0, 1, 2].map(|i| div(v[i], s[i])), false);
            let l = q.iter().map(|x| x * x).sum::<f64>().sqrt();
            (q.map(|x| x / l), [1.0; 3])
        }
    }
}

/// The graph: `mapping` of type `kind` with vector = position, location = normal,
/// rotation = view and scale = light (attributes as per-sample inputs).
fn graph(kind: &str) -> Graph {
    let text = serde_json::json!({
        "version": 1, "name": "mapping",
        "nodes": [
            { "id": "geo", "type": "geometry" },
            { "id": "m", "type": "mapping", "inputs": {
                "vector": { "link": "geo.position" }, "location": { "link": "geo.normal" },
                "rotation": { "link": "geo.view" }, "scale": { "link": "geo.light" },
                "type": kind } }
        ],
        "outputs": [ { "name": "vector", "from": "m.vector" } ]
    });
    Graph::from_json(&text.to_string(), Registry::builtin()).unwrap_or_else(|e| panic!("{e:?}"))
}

/// The outputs of `kind` at `cases`: the CPU's, then the GPU's where there is one.
fn evaluate(kind: &str, cases: &[Case]) -> Vec<OutputBatch> {
    let mut b = SampleBatch::new(cases.len());
    let col = |f: fn(&Case) -> [f32; 3]| cases.iter().map(f).collect::<Vec<_>>();
    b.set_values(Attribute::Position, &col(|c| c.v)).unwrap();
    b.set_values(Attribute::Normal, &col(|c| c.t)).unwrap();
    b.set_values(Attribute::View, &col(|c| c.r)).unwrap();
    b.set_values(Attribute::Light, &col(|c| c.s)).unwrap();
    let g = graph(kind);
    let plan = Plan::compile(&g, &PlanOptions::default()).unwrap();
    let params = plan.default_parameters();
    let mut outs = vec![plan.execute(&b, &params).unwrap()];
    if let Some(ctx) = common::gpu_context("mapping (GPU half)") {
        let gpu = matgraph::gpu::GpuPlan::compile(ctx, &g, &PlanOptions::default()).unwrap();
        outs.push(gpu.execute(&b, &params).unwrap());
    }
    outs
}

fn output(out: &OutputBatch, n: usize, i: usize) -> [f32; 3] {
    [0, 1, 2].map(|k| out.planar(0)[k * n + i])
}

/// Round cases (quarter turns, unit axes, a zero scale component) and seeded random ones.
fn cases() -> Vec<Case> {
    let h = std::f32::consts::FRAC_PI_2;
    let mut v = vec![
        Case {
            v: [1.0, 0.0, 0.0],
            t: [0.0; 3],
            r: [0.0, 0.0, h],
            s: [1.0; 3],
        },
        Case {
            v: [0.0, 1.0, 0.0],
            t: [0.5, 0.0, -1.0],
            r: [h, 0.0, 0.0],
            s: [2.0, 2.0, 2.0],
        },
        Case {
            v: [0.0, 0.0, 1.0],
            t: [0.0; 3],
            r: [0.0, h, 0.0],
            s: [1.0, 1.0, 3.0],
        },
        Case {
            v: [1.0, 2.0, 3.0],
            t: [1.0; 3],
            r: [h, h, 0.0],
            s: [0.5, -1.0, 4.0],
        },
        Case {
            v: [1.0, 2.0, 3.0],
            t: [0.0; 3],
            r: [0.3, -1.2, 2.5],
            s: [0.0, 1.0, 2.0],
        },
    ];
    let mut rng = Rng(0x3a99_1265);
    for _ in 0..400 {
        let pi = std::f64::consts::PI;
        let mut s = [0; 3].map(|_| rng.f(0.25, 4.0));
        for x in &mut s {
            if rng.next() & 3 == 0 {
                *x = -*x;
            }
        }
        v.push(Case {
            v: [0; 3].map(|_| rng.f(-2.0, 2.0)),
            t: [0; 3].map(|_| rng.f(-2.0, 2.0)),
            r: [0; 3].map(|_| rng.f(-pi, pi)),
            s,
        });
    }
    v
}

/// Each type on each backend within a few f32 roundings of the f64 reference (8 ε of the
/// magnitude of the terms summed; normals 8 ε absolute: they are unit).
#[test]
fn every_type_matches_an_f64_reference_at_round_and_seeded_points() {
    let cases = cases();
    let n = cases.len();
    let eps = f32::EPSILON as f64;
    let mut failed = Vec::new();
    for kind in ["point", "texture", "vector", "normal"] {
        for (b, out) in evaluate(kind, &cases).iter().enumerate() {
            let mut worst = (0.0f64, String::new());
            for (i, c) in cases.iter().enumerate() {
                let (want, mag) = reference(kind, *c);
                let got = output(out, n, i);
                for k in 0..3 {
                    let err = (got[k] as f64 - want[k]).abs();
                    let rel = err / (8.0 * eps * mag[k].max(1e-30));
                    if !(rel <= 1.0) {
                        failed.push(format!(
                            "{kind} (backend {b}) case {i} {c:?}[{k}]: got {} want {} ({rel:.2} of the bound)",
                            got[k], want[k]
                        ));
                    }
                    if rel > worst.0 {
                        worst = (rel, format!("case {i}"));
                    }
                }
            }
            println!(
                "mapping {kind} backend {b}: worst {:.3} of the bound ({})",
                worst.0, worst.1
            );
        }
    }
    assert!(
        failed.is_empty(),
        "{}",
        failed[..failed.len().min(12)].join("\n")
    );
}

/// Blender's rotation: Vector Rotate (Euler XYZ) forwards is `vector` at unit scale, and
/// inverted is `texture` at zero location and unit scale, within 1e-6 of Blender's f32.
#[test]
fn rotation_matches_blender() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/blender/mapping.json");
    let r: J = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    assert_eq!(r["blender"], "4.2.0");
    let vec3 = |p: &J| [0, 1, 2].map(|k| p[k].as_f64().unwrap() as f32);
    let points: Vec<[f32; 3]> = r["points"].as_array().unwrap().iter().map(vec3).collect();
    let (mut cases, mut forward, mut inverse) = (Vec::new(), Vec::new(), Vec::new());
    for rot in r["rotations"].as_array().unwrap() {
        for (i, p) in points.iter().enumerate() {
            cases.push(Case {
                v: *p,
                t: [0.0; 3],
                r: vec3(&rot["rotation"]),
                s: [1.0; 3],
            });
            forward.push(vec3(&rot["forward"][i]));
            inverse.push(vec3(&rot["inverse"][i]));
        }
    }
    let n = cases.len();
    assert!(n >= 300, "{n} cases");
    let mut worst = 0.0f32;
    for (kind, want) in [("vector", &forward), ("texture", &inverse)] {
        for (b, out) in evaluate(kind, &cases).iter().enumerate() {
            for i in 0..n {
                let got = output(out, n, i);
                for k in 0..3 {
                    let d = (got[k] - want[i][k]).abs();
                    worst = worst.max(d);
                    assert!(
                        d <= 1e-6,
                        "{kind} (backend {b}) {:?}: ours {got:?}, Blender {:?}",
                        cases[i],
                        want[i]
                    );
                }
            }
        }
    }
    println!("mapping vs Blender's Vector Rotate: worst {worst:.1e}");
}

/// The degenerate cases Blender defines: a zero scale component gives 0 in the texture type
/// (safe_divide), a zero vector stays 0 as a normal, and `texture` undoes `point`.
#[test]
fn zero_scales_and_zero_normals_give_zero_and_texture_undoes_point() {
    let c = Case {
        v: [1.0, 2.0, 3.0],
        t: [0.5, 0.5, 0.5],
        r: [0.0; 3],
        s: [0.0, 2.0, 0.0],
    };
    let z = Case {
        v: [0.0; 3],
        t: [0.0; 3],
        r: [0.4, 0.5, 0.6],
        s: [1.0; 3],
    };
    for out in evaluate("texture", &[c]) {
        assert_eq!(output(&out, 1, 0), [0.0, 0.75, 0.0]);
    }
    for out in evaluate("normal", &[z]) {
        assert_eq!(output(&out, 1, 0), [0.0, 0.0, 0.0]);
    }
    let mut rng = Rng(0x0dd_ba11);
    let cases: Vec<Case> = (0..64)
        .map(|_| Case {
            v: [0; 3].map(|_| rng.f(-2.0, 2.0)),
            t: [0; 3].map(|_| rng.f(-2.0, 2.0)),
            r: [0; 3].map(|_| rng.f(-3.0, 3.0)),
            s: [0; 3].map(|_| rng.f(0.5, 2.0)),
        })
        .collect();
    let moved = evaluate("point", &cases);
    let back: Vec<Case> = cases
        .iter()
        .enumerate()
        .map(|(i, c)| Case {
            v: output(&moved[0], 64, i),
            ..*c
        })
        .collect();
    for out in evaluate("texture", &back) {
        for (i, c) in cases.iter().enumerate() {
            let got = output(&out, 64, i);
            for k in 0..3 {
                assert!((got[k] - c.v[k]).abs() < 2e-5, "{c:?}: back to {got:?}");
            }
        }
    }
}
