//! The tangent frame (issue 36 item 2): MikkTSpace tangents of the meshes the renderer builds
//! against closed forms (a plane's tangent is its u edge; a sphere's is ∂P/∂φ normalised;
//! mirrored uvs flip the sign; degenerate uvs fall back to a valid frame), and the per-sample
//! Gram–Schmidt against an f64 reference at round and seeded points.

use crate::common;

use common::rng::Rng;
use glam::{Vec2, Vec3};
use matgraph::scene::{Mesh, orthonormal_tangent};

/// The angle between two directions, degrees (f64).
fn angle_deg(a: Vec3, b: Vec3) -> f64 {
    let (a, b) = (a.as_dvec3().normalize(), b.as_dvec3().normalize());
    a.dot(b).clamp(-1.0, 1.0).acos().to_degrees()
}

/// A plane's tangent is its u edge and its sign +1 (v grows along N × T); with u mirrored the
/// tangent turns round and the sign is −1, at every vertex, for skewed and scaled edges.
#[test]
fn a_planes_tangent_is_its_u_edge_and_mirrored_uvs_flip_the_sign() {
    let mut rng = Rng(0x7a_4e47);
    let mut cases = vec![
        (Vec3::X, Vec3::Y),
        (Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -3.0)),
    ];
    for _ in 0..8 {
        let e = |r: &mut Rng| Vec3::new(r.f(-2.0, 2.0), r.f(-2.0, 2.0), r.f(-2.0, 2.0));
        cases.push((e(&mut rng), e(&mut rng)));
    }
    for (eu, ev) in cases {
        if eu.cross(ev).length() < 0.1 * eu.length() * ev.length() {
            continue;
        }
        let mut m = Mesh::parallelogram(Vec3::ZERO, eu, ev, [3, 2]);
        // v grows along the component of ev orthogonal to eu; N × T points there.
        for t in m.tangents() {
            assert!(angle_deg(t.truncate(), eu) < 1e-3, "{eu} {ev}: {t}");
            assert_eq!(t.w, 1.0, "{eu} {ev}");
        }
        for uv in &mut m.uvs {
            *uv = Vec2::new(1.0 - uv.x, uv.y);
        }
        for t in m.tangents() {
            assert!(
                angle_deg(t.truncate(), -eu) < 1e-3,
                "mirrored {eu} {ev}: {t}"
            );
            assert_eq!(t.w, -1.0, "mirrored {eu} {ev}");
        }
    }
}

/// On the UV sphere (u = φ/2π around, v up) the tangent is ∂P/∂φ normalised,
/// (−cos φ, 0, sin φ), and the sign +1, away from the poles (where every direction is a
/// tangent of the pole's fan): within 0.05° between the seams, within half a segment at them.
#[test]
fn a_spheres_tangent_runs_around_it() {
    let (segs, rings) = (64u32, 32u32);
    let m = Mesh::uv_sphere(Vec3::ZERO, 1.0, segs, rings);
    let t = m.tangents();
    let mut worst = 0.0f64;
    for i in 2..rings - 1 {
        for j in 0..=segs {
            let k = (i * (segs + 1) + j) as usize;
            let phi = 2.0 * std::f64::consts::PI * (j % segs) as f64 / segs as f64;
            let want = Vec3::new(-phi.cos() as f32, 0.0, phi.sin() as f32);
            let a = angle_deg(t[k].truncate(), want);
            // The seam's vertices see the faces of one side only: their average leans by
            // up to half a segment (180°/segments).
            let seam = j == 0 || j == segs;
            let bound = if seam { 180.0 / segs as f64 } else { 0.05 };
            if !seam {
                worst = worst.max(a);
            }
            assert!(a < bound, "ring {i} segment {j}: {} vs {want}", t[k]);
            assert_eq!(t[k].w, 1.0);
        }
    }
    println!("sphere tangents: worst {worst:.2e}° off ∂P/∂φ between the seams");
    // Every vertex, poles included: unit, finite, orthogonal to its normal.
    for (t, n) in t.iter().zip(&m.normals) {
        assert!((t.truncate().length() - 1.0).abs() < 1e-5 && t.truncate().dot(*n).abs() < 1e-3);
    }
}

/// Degenerate uvs (every vertex at one uv) give MikkTSpace no direction: each vertex gets a
/// unit tangent orthogonal to its normal and sign +1, never NaN.
#[test]
fn degenerate_uvs_give_a_valid_frame() {
    let mut m = Mesh::uv_sphere(Vec3::ZERO, 1.0, 8, 4);
    m.uvs.iter_mut().for_each(|uv| *uv = Vec2::splat(0.25));
    for (t, n) in m.tangents().iter().zip(&m.normals) {
        assert!(t.is_finite(), "{t}");
        assert!((t.truncate().length() - 1.0).abs() < 1e-5, "{t}");
        assert!(t.truncate().dot(*n).abs() < 1e-5, "{t} against {n}");
        assert_eq!(t.w, 1.0);
    }
}

/// The per-sample tangent: the interpolated tangent minus its normal component, normalised
/// (f64 reference), at round and seeded random points; a tangent along the normal (or zero)
/// falls back to a unit vector orthogonal to it.
#[test]
fn the_sample_tangent_is_gram_schmidt_of_the_interpolated_one() {
    let mut rng = Rng(0x6a_5c41);
    let mut cases = vec![
        (Vec3::Z, Vec3::new(1.0, 0.0, 0.5)),
        (Vec3::Y, Vec3::new(0.3, 0.2, -1.0)),
    ];
    for _ in 0..500 {
        let n = Vec3::new(rng.f(-1.0, 1.0), rng.f(-1.0, 1.0), rng.f(-1.0, 1.0)).normalize();
        let t = Vec3::new(rng.f(-2.0, 2.0), rng.f(-2.0, 2.0), rng.f(-2.0, 2.0));
        cases.push((n, t));
    }
    let mut worst = 0.0f64;
    for (n, t) in cases {
        let (nd, td) = (n.as_dvec3(), t.as_dvec3());
        let o = td - nd * nd.dot(td);
        if o.length() < 1e-3 * td.length() {
            continue;
        }
        let want = o / o.length();
        let got = orthonormal_tangent(n, t).as_dvec3();
        let err = (got - want).length();
        worst = worst.max(err);
        assert!(
            err < 1e-5 * td.length() / o.length(),
            "{n} {t}: {got} want {want}"
        );
    }
    println!("Gram–Schmidt: worst {worst:.1e}");
    for (n, t) in [
        (Vec3::Z, Vec3::Z * 2.0),
        (Vec3::X, Vec3::ZERO),
        (Vec3::NEG_Z, Vec3::NEG_Z),
    ] {
        let got = orthonormal_tangent(n, t);
        assert!(
            (got.length() - 1.0).abs() < 1e-6 && got.dot(n).abs() < 1e-6,
            "{n} {t}: {got}"
        );
    }
}
