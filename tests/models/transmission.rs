//! Transmission through solid dielectrics (docs/models/transmission.md): the sphere path
//! against an independent f64 ray trace written here (the quadratic ray–sphere intersection,
//! Snell in its sine form on the tangent plane, Fresnel's amplitude coefficients), at round and
//! seeded random f32 points; Beer–Lambert and the slab's series against their closed forms;
//! energy R + T ≤ 1; the Sellmeier indices against tabulated measurements; the four graphs.

use glam::Vec3;
use matgraph::Registry;
use matgraph::nodes::transmission::{
    RGB_WAVELENGTHS_NM, sellmeier_ior, transmission_combine, transmission_slab, transmission_sphere,
};

/// A seeded SplitMix64 generator.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [lo, hi], an f32.
    fn range(&mut self, lo: f64, hi: f64) -> f32 {
        let u = (self.next() >> 11) as f64 / (1u64 << 53) as f64;
        (lo + (hi - lo) * u) as f32
    }
    /// A unit f32 vector within `max_deg` of `axis` (uniform in solid angle), rounded to f32.
    fn around(&mut self, axis: D3, max_deg: f64) -> Vec3 {
        let cos_max = max_deg.to_radians().cos();
        let c = 1.0 - (1.0 - cos_max) * self.range(0.0, 1.0) as f64;
        let phi = 2.0 * std::f64::consts::PI * self.range(0.0, 1.0) as f64;
        let s = (1.0 - c * c).max(0.0).sqrt();
        let (u, w) = axis.basis();
        axis.scale(c)
            .add(u.scale(s * phi.cos()))
            .add(w.scale(s * phi.sin()))
            .unit()
            .f32()
    }
}

/// An f64 vector for the reference.
#[derive(Clone, Copy, Debug)]
struct D3(f64, f64, f64);

impl D3 {
    fn of(v: Vec3) -> D3 {
        D3(v.x as f64, v.y as f64, v.z as f64)
    }
    fn f32(self) -> Vec3 {
        Vec3::new(self.0 as f32, self.1 as f32, self.2 as f32)
    }
    fn add(self, o: D3) -> D3 {
        D3(self.0 + o.0, self.1 + o.1, self.2 + o.2)
    }
    fn sub(self, o: D3) -> D3 {
        D3(self.0 - o.0, self.1 - o.1, self.2 - o.2)
    }
    fn scale(self, s: f64) -> D3 {
        D3(self.0 * s, self.1 * s, self.2 * s)
    }
    fn dot(self, o: D3) -> f64 {
        self.0 * o.0 + self.1 * o.1 + self.2 * o.2
    }
    fn norm(self) -> f64 {
        self.dot(self).sqrt()
    }
    fn unit(self) -> D3 {
        self.scale(1.0 / self.norm())
    }
    /// Two unit vectors perpendicular to `self` (unit) and to each other.
    fn basis(self) -> (D3, D3) {
        let a = if self.0.abs() < 0.9 {
            D3(1.0, 0.0, 0.0)
        } else {
            D3(0.0, 1.0, 0.0)
        };
        let u = a.sub(self.scale(a.dot(self))).unit();
        let w = D3(
            self.1 * u.2 - self.2 * u.1,
            self.2 * u.0 - self.0 * u.2,
            self.0 * u.1 - self.1 * u.0,
        );
        (u, w)
    }
}

/// Unpolarised Fresnel reflectance from the amplitude coefficients, light going from index
/// `n1` to `n2` at incidence cosine `ci` (Hecht eq. 4.34, 4.40); 1 under TIR.
fn fresnel_ref(ci: f64, n1: f64, n2: f64) -> f64 {
    let si = (1.0 - ci * ci).max(0.0).sqrt();
    let st = n1 / n2 * si;
    if st >= 1.0 {
        return 1.0;
    }
    let ct = (1.0 - st * st).sqrt();
    let rs = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct);
    let rp = (n2 * ci - n1 * ct) / (n2 * ci + n1 * ct);
    0.5 * (rs * rs + rp * rp)
}

/// Snell in its sine form: the direction `d` (unit, towards the surface) refracted through a
/// surface of unit normal `nrm` facing the incoming side, from index `n1` to `n2`: the tangential
/// part scales by n1/n2, the normal part is what keeps the result unit. None under TIR.
fn snell_ref(d: D3, nrm: D3, n1: f64, n2: f64) -> Option<D3> {
    let along = d.dot(nrm); // < 0
    let tangent = d.sub(nrm.scale(along)).scale(n1 / n2);
    let s2 = tangent.dot(tangent);
    if s2 >= 1.0 {
        return None;
    }
    Some(tangent.sub(nrm.scale((1.0 - s2).sqrt())))
}

/// The reference trace of one channel: (exit direction, R at entry, transmittance, chord, TIR).
struct RefPath {
    exit: Option<D3>,
    reflectance: f64,
    transmittance: f64,
    length: f64,
    /// Cosine of the exit angle outside (1 where nothing leaves): f32 evaluates cos²θ there
    /// as a difference of terms near η², so its conditioning sets the tolerances below.
    cos_exit: f64,
}

/// Ray trace in f64: enter at `p` (on the sphere) through shading normal `n`, intersect the
/// sphere `|x − c| = r` by the quadratic, leave through the geometric normal there.
#[allow(clippy::too_many_arguments)]
fn trace_ref(p: D3, n: D3, v: D3, c: D3, r: f64, ior: f64, outside: f64, sigma: f64) -> RefPath {
    let d = v.scale(-1.0);
    let ci = v.dot(n).clamp(0.0, 1.0);
    let reflectance = fresnel_ref(ci, outside, ior);
    let Some(t) = snell_ref(d, n, outside, ior) else {
        return RefPath {
            exit: None,
            reflectance,
            transmittance: 0.0,
            length: 0.0,
            cos_exit: 1.0,
        };
    };
    // |p + s t − c|² = r²: s² + 2 s t·(p − c) + |p − c|² − r² = 0, the far root.
    let o = p.sub(c);
    let b = t.dot(o);
    let cc = o.dot(o) - r * r;
    let disc = (b * b - cc).max(0.0);
    let length = (-b + disc.sqrt()).max(0.0);
    let q = p.add(t.scale(length));
    let m = q.sub(c).unit();
    let cos_exit = t.dot(m);
    let r_out = fresnel_ref(cos_exit, ior, outside);
    let exit = snell_ref(t, m.scale(-1.0), ior, outside);
    let transmittance = if exit.is_some() {
        (1.0 - reflectance) * (1.0 - r_out) * (-sigma * length).exp()
    } else {
        0.0
    };
    let cos_exit = exit.map_or(1.0, |e| e.dot(m));
    RefPath {
        exit,
        reflectance,
        transmittance,
        length,
        cos_exit,
    }
}

fn close(what: &str, got: f64, want: f64, abs: f64, rel: f64) {
    let err = (got - want).abs();
    assert!(
        err <= abs + rel * want.abs(),
        "{what}: got {got}, want {want} (error {err:e})"
    );
}

/// The ball scene's sphere.
const CENTER: Vec3 = Vec3::new(0.0, 1.0, 0.0);

/// Runs the node with one index and absorption for all channels; checks every channel
/// against the reference and returns the reference of the first.
#[allow(clippy::too_many_arguments)]
fn check_sphere(
    what: &str,
    p: Vec3,
    n: Vec3,
    v: Vec3,
    r: f32,
    ior: Vec3,
    outside: f32,
    sigma: Vec3,
) {
    let out = transmission_sphere(p, n, v, CENTER, r, ior, outside, sigma);
    let exits = [out.0, out.1, out.2];
    let mut any_tir = false;
    for k in 0..3 {
        let want = trace_ref(
            D3::of(p),
            D3::of(n).unit(),
            D3::of(v).unit(),
            D3::of(CENTER),
            r as f64,
            ior[k] as f64,
            outside as f64,
            sigma[k] as f64,
        );
        let w = format!("{what}, channel {k}");
        close(
            &format!("{w}: R"),
            out.3[k] as f64,
            want.reflectance,
            2e-6,
            1e-5,
        );
        // cos²θ at the exit carries an absolute f32 error of about 1e-6 (two ulps of η² ≤ 6.8:
        // its terms cancel), which T ∝ cosθ near grazing feels relatively as 1e-6/cos²θ.
        let ill = 1.0 / want.cos_exit.max(1e-4).powi(2);
        close(
            &format!("{w}: T"),
            out.4[k] as f64,
            want.transmittance,
            2e-6,
            1e-4 + 1e-6 * ill,
        );
        match want.exit {
            Some(e) => {
                // The chord is 2r cosθc; near the entry's critical angle cos²θt = 1 − η² sin²θi
                // carries an ULP or two of η² sin²θi ≈ 1 (1.2e-7 absolute), which cosθt feels
                // relatively as 1.2e-7 / (2 cos²θt).
                let cos_c = want.length / (2.0 * r as f64);
                close(
                    &format!("{w}: chord"),
                    out.5[k] as f64,
                    want.length,
                    2e-6 * r as f64,
                    1e-5 + 6e-8 / cos_c.max(1e-4).powi(2),
                );
                let got = D3::of(exits[k]);
                let err = got.sub(e).norm();
                // The exit direction's normal part is √(cos²θ), cos²θ = (1 − η²) + (η cosθc)²
                // with η² up to 6.8 here: two of its ulps (4.8e-7 each) give 5e-7/cosθ.
                let tol = 2e-5 + 1e-6 / want.cos_exit.max(1e-6);
                assert!(
                    err < tol,
                    "{w}: exit {:?}, want {e:?} (error {err:e} > {tol:e})",
                    exits[k]
                );
            }
            None => {
                any_tir = true;
                assert_eq!(out.4[k], 0.0, "{w}: trapped light has T = 0");
            }
        }
    }
    assert_eq!(out.6, any_tir, "{what}: tir flag");
}

#[test]
fn normal_incidence_goes_straight_through_a_chord_of_2r() {
    for (ior, r, sigma) in [
        (1.5168f32, 1.0f32, 0.0f32),
        (2.4175, 0.5, 0.3),
        (1.309, 2.0, 1.7),
    ] {
        let p = CENTER + Vec3::new(0.0, 0.0, r);
        let out = transmission_sphere(
            p,
            Vec3::Z,
            Vec3::Z,
            CENTER,
            r,
            Vec3::splat(ior),
            1.0,
            Vec3::splat(sigma),
        );
        let r0 = ((ior as f64 - 1.0) / (ior as f64 + 1.0)).powi(2);
        for k in 0..3 {
            close("R0", out.3[k] as f64, r0, 1e-7, 1e-6);
            close("chord", out.5[k] as f64, 2.0 * r as f64, 1e-6, 0.0);
            close(
                "T",
                out.4[k] as f64,
                (1.0 - r0).powi(2) * (-2.0 * (r * sigma) as f64).exp(),
                1e-7,
                1e-6,
            );
        }
        for e in [out.0, out.1, out.2] {
            assert!((e - Vec3::NEG_Z).length() < 1e-6, "exit {e}");
        }
        assert!(!out.6);
    }
}

#[test]
fn seeded_points_match_the_f64_ray_trace() {
    let mut rng = Rng(0x7ea5_0011);
    for case in 0..2000 {
        // Entry points on the half of the sphere facing +z (the camera side), views within 89°
        // of the normal there, indices from ice to beyond diamond.
        let g = rng.around(D3(0.0, 0.0, 1.0), 80.0);
        let r = rng.range(0.2, 3.0);
        let p = CENTER + r * g;
        let v = rng.around(D3::of(g).unit(), 89.0);
        let ior = Vec3::new(
            rng.range(1.0, 2.6),
            rng.range(1.0, 2.6),
            rng.range(1.0, 2.6),
        );
        let sigma = Vec3::new(
            rng.range(0.0, 3.0),
            rng.range(0.0, 3.0),
            rng.range(0.0, 3.0),
        );
        check_sphere(&format!("case {case}"), p, g, v, r, ior, 1.0, sigma);
    }
}

#[test]
fn under_water_and_round_angles_match_the_ray_trace() {
    let p = CENTER + Vec3::Z;
    for deg in [0.0f64, 15.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.0] {
        let v = Vec3::new(
            deg.to_radians().sin() as f32,
            0.0,
            deg.to_radians().cos() as f32,
        );
        for (ior, outside) in [
            (1.5168f32, 1.0f32),
            (2.4175, 1.0),
            (1.5168, 1.333),
            (1.309, 1.0),
        ] {
            check_sphere(
                &format!("{deg}° n {ior}/{outside}"),
                p,
                Vec3::Z,
                v,
                1.0,
                Vec3::splat(ior),
                outside,
                Vec3::splat(0.5),
            );
        }
    }
}

#[test]
fn grazing_entry_passes_almost_nothing() {
    let p = CENTER + Vec3::X;
    // cosθi = 1e-4 and exactly 0.
    let v = Vec3::new(1e-4, 0.0, 1.0).normalize();
    check_sphere(
        "grazing",
        p,
        Vec3::X,
        v,
        1.0,
        Vec3::splat(2.4175),
        1.0,
        Vec3::ZERO,
    );
    let out = transmission_sphere(
        p,
        Vec3::X,
        Vec3::Z,
        CENTER,
        1.0,
        Vec3::splat(1.5),
        1.0,
        Vec3::ZERO,
    );
    assert_eq!(out.3, Vec3::ONE, "R = 1 at exactly grazing incidence");
    assert_eq!(out.4, Vec3::ZERO, "T = 0 at exactly grazing incidence");
    // The sphere's own normal: the internal angle at the exit equals θt, below the critical
    // angle however grazing the entry, so a sphere never traps light by itself.
    let v = Vec3::new(1.0, 0.0, 1e-3).normalize();
    let out = transmission_sphere(
        CENTER + Vec3::Z,
        Vec3::Z,
        v,
        CENTER,
        1.0,
        Vec3::splat(2.4175),
        1.0,
        Vec3::ZERO,
    );
    assert!(!out.6 && out.4.x > 0.0, "{out:?}");
}

/// With the sphere's own normal the exit meets the surface at the entry's angle (a chord's
/// symmetry), so no entry is trapped however grazing: cos²θe is taken from the entry, where
/// `1 − η'² sin²θc` cancelled to rounding and flipped the TIR flag at grazing. Grazing entries
/// at cosθi = 10⁻²…10⁻⁶ and 0, and entries from a much denser outside within 0.1°–3° of the
/// critical angle (the hard ranges' 97 | 6.6, and water | ice), against the f64 ray trace.
#[test]
fn the_sphere_s_own_normal_never_traps_and_the_denser_outside_matches_the_ray_trace() {
    let p = CENTER + Vec3::X;
    for k in 2..=6 {
        let c = 10f64.powi(-k);
        let v = Vec3::new(c as f32, 0.0, (1.0 - c * c).sqrt() as f32);
        for ior in [1.0001f32, 1.5168, 2.4175] {
            let what = format!("grazing cos {c:e}, n {ior}");
            check_sphere(&what, p, Vec3::X, v, 1.0, Vec3::splat(ior), 1.0, Vec3::ZERO);
            let out = transmission_sphere(
                p,
                Vec3::X,
                v,
                CENTER,
                1.0,
                Vec3::splat(ior),
                1.0,
                Vec3::ZERO,
            );
            assert!(!out.6, "{what}: trapped");
        }
    }
    let out = transmission_sphere(
        p,
        Vec3::X,
        Vec3::Z,
        CENTER,
        1.0,
        Vec3::splat(1.5),
        1.0,
        Vec3::ZERO,
    );
    assert!(!out.6, "exactly grazing: trapped");
    for (ior, outside) in [(6.6f32, 97.0f32), (1.309, 1.333)] {
        let crit = (ior as f64 / outside as f64).asin();
        for delta_deg in [-3.0f64, -1.0, -0.3, -0.1, 0.1, 0.3, 1.0, 3.0] {
            let theta = crit + delta_deg.to_radians();
            let v = Vec3::new(theta.sin() as f32, 0.0, theta.cos() as f32);
            check_sphere(
                &format!("{delta_deg}° from critical, n {ior} in {outside}"),
                CENTER + Vec3::Z,
                Vec3::Z,
                v,
                1.0,
                Vec3::splat(ior),
                outside,
                Vec3::splat(0.5),
            );
        }
    }
}

#[test]
fn tilted_normals_inside_diamond_give_total_internal_reflection() {
    // A shading normal tilted from the sphere's own (a bump, a coarse mesh): the internal ray
    // meets the far side beyond diamond's critical angle (24.4°) and is trapped.
    let mut rng = Rng(0xd1a_3011d);
    let mut trapped = 0;
    for case in 0..2000 {
        let g = rng.around(D3(0.0, 0.0, 1.0), 60.0);
        let n = rng.around(D3::of(g), 50.0);
        let v = rng.around(D3::of(n), 80.0);
        let p = CENTER + g;
        check_sphere(
            &format!("tilted {case}"),
            p,
            n,
            v,
            1.0,
            Vec3::splat(2.4175),
            1.0,
            Vec3::splat(0.1),
        );
        trapped += transmission_sphere(p, n, v, CENTER, 1.0, Vec3::splat(2.4175), 1.0, Vec3::ZERO).6
            as usize;
    }
    assert!(
        trapped > 100,
        "only {trapped} of 2000 tilted cases were trapped"
    );
    // A round one: the normal tilted 53° from the sphere's at the front, looking along it.
    let n = Vec3::new(0.8, 0.0, 0.6);
    let out = transmission_sphere(
        CENTER + Vec3::Z,
        n,
        n,
        CENTER,
        1.0,
        Vec3::splat(2.42),
        1.0,
        Vec3::ZERO,
    );
    assert!(out.6);
    assert_eq!(out.4, Vec3::ZERO);
    // ... and the denser medium outside: nothing enters past the critical angle.
    let v = Vec3::new(0.8, 0.0, 0.6);
    let out = transmission_sphere(
        CENTER + Vec3::Z,
        Vec3::Z,
        v,
        CENTER,
        1.0,
        Vec3::ONE,
        1.5,
        Vec3::ZERO,
    );
    assert!(out.6);
    assert_eq!(out.3, Vec3::ONE);
    assert_eq!(out.4, Vec3::ZERO);
}

#[test]
fn beer_lambert_matches_its_closed_form() {
    // T / (T_in T_out) = exp(−σ L): at normal incidence L = 2r; at θ the chord is 2 r cosθt.
    let mut rng = Rng(0xbee7);
    for _ in 0..500 {
        let sigma = Vec3::new(
            rng.range(0.0, 5.0),
            rng.range(0.0, 5.0),
            rng.range(0.0, 5.0),
        );
        let r = rng.range(0.1, 2.0);
        let deg = rng.range(0.0, 80.0) as f64;
        let ior = rng.range(1.2, 2.5) as f64;
        let v = Vec3::new(
            deg.to_radians().sin() as f32,
            0.0,
            deg.to_radians().cos() as f32,
        );
        let clear = transmission_sphere(
            CENTER + r * Vec3::Z,
            Vec3::Z,
            v,
            CENTER,
            r,
            Vec3::splat(ior as f32),
            1.0,
            Vec3::ZERO,
        );
        let out = transmission_sphere(
            CENTER + r * Vec3::Z,
            Vec3::Z,
            v,
            CENTER,
            r,
            Vec3::splat(ior as f32),
            1.0,
            sigma,
        );
        let sin_t = deg.to_radians().sin() / ior;
        let chord = 2.0 * r as f64 * (1.0 - sin_t * sin_t).sqrt();
        for k in 0..3 {
            close("chord 2r cosθt", out.5[k] as f64, chord, 1e-6, 1e-6);
            let want = (-(sigma[k] as f64) * chord).exp();
            close(
                "Beer–Lambert",
                (out.4[k] / clear.4[k]) as f64,
                want,
                1e-6,
                1e-5,
            );
        }
    }
}

#[test]
fn slab_sums_every_bounce_in_closed_form() {
    // Normal incidence: T = (1 − R)² a / (1 − R² a²), a = exp(−σ d) (the incoherent plate);
    // with no absorption T = (1 − R)/(1 + R).
    for (ior, d, sigma) in [
        (1.5168f32, 0.01f32, 0.0f32),
        (2.4175, 0.2, 0.0),
        (1.5, 0.5, 2.0),
        (1.309, 3.0, 0.4),
    ] {
        let out = transmission_slab(
            Vec3::Z,
            Vec3::Z,
            d,
            Vec3::splat(ior),
            1.0,
            Vec3::splat(sigma),
        );
        let r = ((ior as f64 - 1.0) / (ior as f64 + 1.0)).powi(2);
        let a = (-(sigma * d) as f64).exp();
        let want = (1.0 - r).powi(2) * a / (1.0 - r * r * a * a);
        close("slab T", out.2.x as f64, want, 1e-7, 1e-6);
        if sigma == 0.0 {
            close(
                "slab T, clear",
                out.2.y as f64,
                (1.0 - r) / (1.0 + r),
                1e-7,
                1e-6,
            );
        }
        assert_eq!(out.0, Vec3::NEG_Z);
    }
    // Oblique: path d / cosθt, against Snell's sine form.
    let mut rng = Rng(0x51ab);
    for _ in 0..500 {
        let deg = rng.range(0.0, 85.0) as f64;
        let ior = rng.range(1.1, 2.5) as f64;
        let d = rng.range(0.001, 2.0) as f64;
        let v = Vec3::new(
            deg.to_radians().sin() as f32,
            0.0,
            deg.to_radians().cos() as f32,
        );
        let out = transmission_slab(
            Vec3::Z,
            v,
            d as f32,
            Vec3::splat(ior as f32),
            1.0,
            Vec3::ZERO,
        );
        let cos_i = D3::of(v).unit().2;
        let sin_t = (1.0 - cos_i * cos_i).sqrt() / ior;
        close(
            "slab path",
            out.3.x as f64,
            d / (1.0 - sin_t * sin_t).sqrt(),
            1e-6,
            1e-5,
        );
        let r = fresnel_ref(cos_i, 1.0, ior);
        close(
            "slab T oblique",
            out.2.x as f64,
            (1.0 - r) / (1.0 + r),
            2e-6,
            1e-5,
        );
    }
}

#[test]
fn reflected_plus_transmitted_never_exceeds_one() {
    let mut rng = Rng(0xe7e7);
    for _ in 0..20_000 {
        let g = rng.around(D3(0.0, 0.0, 1.0), 90.0);
        let n = rng.around(D3::of(g), 40.0);
        let v = rng.around(D3::of(n), 90.0);
        let ior = Vec3::new(
            rng.range(1.0, 3.0),
            rng.range(1.0, 3.0),
            rng.range(1.0, 3.0),
        );
        let sigma = Vec3::new(rng.range(0.0, 2.0), 0.0, rng.range(0.0, 2.0));
        let out = transmission_sphere(CENTER + g, n, v, CENTER, 1.0, ior, 1.0, sigma);
        let slab = transmission_slab(n, v, rng.range(0.0, 2.0), ior, 1.0, sigma);
        for k in 0..3 {
            for (what, r, t) in [
                ("sphere", out.3[k], out.4[k]),
                ("slab", slab.1[k], slab.2[k]),
            ] {
                assert!(
                    r >= 0.0 && t >= 0.0 && r + t <= 1.0 + 1e-6,
                    "{what}: R {r} + T {t} at {g} {n} {v} {ior}"
                );
            }
        }
    }
}

#[test]
fn sellmeier_indices_match_the_tables() {
    // (B, C in µm², [(λ nm, measured n, tolerance)], source)
    let bk7 = (
        [1.039_612, 0.231_792_35, 1.010_469_6],
        [0.006_000_699, 0.020_017_914, 103.560_65],
    );
    let silica = (
        [0.696_166_3, 0.407_942_6, 0.897_479_4],
        [0.004_679_148, 0.013_512_063, 97.934_0],
    );
    let sapphire = (
        [1.431_349_3, 0.650_547_15, 5.341_402],
        [0.005_279_926, 0.014_238_265, 325.017_82],
    );
    let diamond = ([0.3306, 4.3356, 0.0], [0.030_625, 0.011_236, 0.0]);
    // (glass, Sellmeier (B, C), [(wavelength nm, reference n, tolerance)]).
    type Case<'a> = (&'a str, ([f32; 3], [f32; 3]), &'a [(f32, f64, f64)]);
    let cases: [Case; 4] = [
        // SCHOTT N-BK7 data sheet: n_d, n_F, n_C (5 decimals).
        (
            "BK7",
            bk7,
            &[
                (587.56, 1.51680, 2e-5),
                (486.13, 1.52238, 2e-5),
                (656.27, 1.51432, 2e-5),
            ],
        ),
        // Malitson 1965, J. Opt. Soc. Am. 55, 1205, Table I: n at 0.58756 µm and 0.48613 µm.
        (
            "fused silica",
            silica,
            &[(587.56, 1.45846, 3e-5), (486.13, 1.46313, 3e-5)],
        ),
        // Malitson & Dodge 1972: sapphire ordinary ray n_o(589.3 nm) = 1.7681 (GIA: 1.762–1.770).
        ("sapphire", sapphire, &[(589.29, 1.7681, 2e-4)]),
        // Diamond n_D = 2.4175 (CRC Handbook; Peter 1923 fit within 3e-4).
        ("diamond", diamond, &[(589.29, 2.4175, 3e-4)]),
    ];
    for (name, (b, c), rows) in cases {
        for &(l, want, tol) in rows {
            let got = sellmeier_ior(Vec3::from(b), Vec3::from(c), l) as f64;
            close(&format!("{name} at {l} nm"), got, want, tol, 0.0);
        }
    }
    // Gemmologists' dispersion n(430.8 nm) − n(686.7 nm), the B–G "fire" figure (GIA Gem
    // Reference Guide): diamond 0.044, sapphire 0.018, against which diamond has 2.4× the fire.
    for (name, (b, c), want) in [("diamond", diamond, 0.044), ("sapphire", sapphire, 0.018)] {
        let (b, c) = (Vec3::from(b), Vec3::from(c));
        let fire = (sellmeier_ior(b, c, 430.8) - sellmeier_ior(b, c, 686.7)) as f64;
        close(&format!("{name} B–G dispersion"), fire, want, 6e-4, 0.0);
    }
    assert_eq!(RGB_WAVELENGTHS_NM, [630.0, 532.0, 465.0]);
}

#[test]
fn combine_takes_each_channel_from_its_own_ray() {
    let c = transmission_combine(
        Vec3::new(2.0, 9.0, 9.0),
        Vec3::new(9.0, 3.0, 9.0),
        Vec3::new(9.0, 9.0, 4.0),
        Vec3::new(0.5, 0.25, 0.125),
    );
    assert_eq!(c, Vec3::new(1.0, 0.75, 0.5));
}

#[test]
fn the_four_dielectric_graphs_transmit_and_differ() {
    let reg = Registry::builtin();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs");
    let mut seen = Vec::new();
    for name in ["pbr_glass", "pbr_ice", "pbr_sapphire", "pbr_diamond"] {
        let path = dir.join(format!("{name}.json"));
        matgraph::io::load_graph(&path, reg).unwrap_or_else(|e| panic!("{name}: {e}"));
        let doc: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let nodes = doc["nodes"].as_array().unwrap();
        let sphere = nodes
            .iter()
            .find(|n| n["type"] == "transmission_sphere")
            .unwrap_or_else(|| panic!("{name} has no transmission_sphere"));
        assert!(
            nodes.iter().any(|n| n["type"] == "transmission_combine"),
            "{name}: no transmission_combine"
        );
        let emission = doc["outputs"]
            .as_array()
            .unwrap()
            .iter()
            .find(|o| o["name"] == "emission")
            .unwrap();
        assert_eq!(
            emission["from"], "emission_mix.result",
            "{name}: emission is reflection + transmission"
        );
        // Each input's value, or the inputs of the node it links to.
        let resolve = |input: &str| {
            let v = &sphere["inputs"][input];
            match v["link"].as_str() {
                Some(link) => {
                    let id = link.split('.').next().unwrap();
                    nodes.iter().find(|n| n["id"] == id).unwrap()["inputs"].to_string()
                }
                None => v.to_string(),
            }
        };
        let key = (resolve("absorption"), resolve("ior"));
        assert!(
            !seen.contains(&key),
            "{name} has the same ior and absorption as another"
        );
        seen.push(key);
    }
}
