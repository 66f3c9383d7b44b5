//! Metallic–roughness PBR (seed 003; docs/models/pbr.md): the GGX
//! normal distribution, height-correlated Smith visibility, F0 from Unreal's Specular input or
//! from the base colour for metals, Schlick or exact Fresnel, and Lambert diffuse, as in
//! glTF 2.0 (Appendix B), Unreal (Karis 2013) and Filament.
//!
//! Conventions: `n` is the unit normal, `v` the unit direction to the eye, `l` the unit
//! direction to the light, `h = normalize(l + v)`. Perceptual `roughness` is squared to the
//! GGX width `α = roughness²` (Burley 2012, Karis 2013) and clamped below at
//! [`MIN_ROUGHNESS`] (see there for what that costs). IOR ↔ F0 ↔ Specular conversions are the
//! optics nodes `ior_to_f0`, `f0_to_ior`, `f0_to_specular` and `specular_to_f0`.
//!
//! Numerics (docs/models/pbr.md "Numerics"): in [`brdf`], `1 − (N·H)²` is computed as
//! `|N × H|²`, since N·H rounds to 1 in f32 while the lobe at low roughness is `α²/2` wide
//! (as Filament does); the visibility is multiplied by N·L before D, so nothing overflows at
//! grazing angles.

use crate::node::{Category, In, NodeType, Out, WgslChoice};
use crate::precision::{cross, sqrt};
use crate::value::Value;
use glam::Vec3;
use std::f32::consts::PI;

use super::optics::{f0_to_ior, fresnel_dielectric, fresnel_schlick, specular_to_f0};

/// The smallest perceptual roughness used (α = 4·10⁻⁴, peak 1/(π α²) ≈ 2·10⁶).
///
/// What it costs: a smoother surface (roughness < 0.02, down to a mirror) is shaded with this
/// lobe, about 5·10⁻⁴ rad wide, instead of a narrower one: its highlight from a point light is
/// wider and lower than the true one (a mirror's is a delta). Below it, the lobe is narrower
/// than the direction error of f32 unit vectors (~6·10⁻⁸ rad) can resolve: at roughness
/// 0.02 that error already moves D by up to ~10⁻³ relative on the lobe's flank (measured in
/// tests/models/physics_pointwise.rs). Filament uses 0.045 for half-float reasons.
pub const MIN_ROUGHNESS: f32 = 0.02;

/// The smallest cosine the visibility term sees: cosines in (0, 1e-30) are taken as 1e-30,
/// so the term stays finite; it moves V·N·L by less than 1e-27 absolute.
pub const MIN_COS: f32 = 1e-30;

/// `α² = roughness⁴` with roughness clamped to [[`MIN_ROUGHNESS`], 1].
#[inline]
pub(crate) fn alpha2(roughness: f32) -> f32 {
    let r = roughness.clamp(MIN_ROUGHNESS, 1.0);
    let a = r * r;
    a * a
}

/// `v / |v|`, or 0 for a (near) zero vector.
#[inline]
pub fn safe_normalize(v: Vec3) -> Vec3 {
    let l2 = v.dot(v);
    if l2 > 1e-20 { v / sqrt(l2) } else { Vec3::ZERO }
}

/// GGX / Trowbridge–Reitz normal distribution
/// `D = α² / (π ((N·H)² (α² − 1) + 1)²)`, α = roughness² (Walter et al. 2007 eq. 33;
/// Karis 2013 eq. 3). The denominator is written `sin²θh + cos²θh α²` with
/// `sin²θh = (1 − c)(1 + c)`, the same and without cancellation at `c → 1`. `D = 0` for
/// `N·H ≤ 0`.
#[inline]
pub fn ggx_d(n_dot_h: f32, roughness: f32) -> f32 {
    if n_dot_h <= 0.0 {
        return 0.0;
    }
    let c = n_dot_h.min(1.0);
    ggx_d_sin2(c, (1.0 - c) * (1.0 + c), alpha2(roughness))
}

/// GGX `D = α² / (π (sin²θh + cos²θh α²)²)` from `cos θh`, `sin² θh` and `α²` (Walter et al.
/// 2007 eq. 33), for callers that know `sin² θh` more precisely than `1 − cos²` (a cross
/// product).
#[inline]
pub fn ggx_d_sin2(cos: f32, sin2: f32, a2: f32) -> f32 {
    let k = sin2 + cos * cos * a2;
    a2 / (PI * k * k)
}

/// Height-correlated Smith visibility `V = G₂ / (4 N·L N·V)`
/// `= 0.5 / (N·L √((N·V)²(1 − α²) + α²) + N·V √((N·L)²(1 − α²) + α²))`
/// (Heitz 2014 eq. 99; Filament's `V_SmithGGXCorrelated`). 0 when either cosine is ≤ 0;
/// otherwise both are clamped to [[`MIN_COS`], 1]. Symmetric in its two cosines.
#[inline]
pub fn smith_visibility(n_dot_v: f32, n_dot_l: f32, roughness: f32) -> f32 {
    if n_dot_v <= 0.0 || n_dot_l <= 0.0 {
        return 0.0;
    }
    let nv = n_dot_v.clamp(MIN_COS, 1.0);
    let nl = n_dot_l.clamp(MIN_COS, 1.0);
    smith_visibility_n_dot_l(nv, nl, alpha2(roughness)) / nl
}

/// `V · N·L` of [`smith_visibility`] for cosines in [[`MIN_COS`], 1]:
/// `0.5 / (√((N·V)²(1 − α²) + α²) + (N·V/N·L) √((N·L)²(1 − α²) + α²))`, at most `0.5/α`.
#[inline]
pub(crate) fn smith_visibility_n_dot_l(nv: f32, nl: f32, a2: f32) -> f32 {
    let gv = sqrt(nv * nv * (1.0 - a2) + a2);
    let gl = (nv / nl) * sqrt(nl * nl * (1.0 - a2) + a2);
    0.5 / (gv + gl)
}

/// F0 of the metallic–roughness model: `mix(0.08 · specular, base_color, metallic)`
/// (Unreal: dielectrics F0 = 0.08 · Specular, 0.5 ↔ 4%; metals F0 = base colour). `metallic`
/// is clamped to [0, 1], `specular` to [0, 12.5] (F0 ≤ 1).
#[inline]
pub fn f0(metallic: f32, base_color: Vec3, specular: f32) -> Vec3 {
    let m = metallic.clamp(0.0, 1.0);
    let d = specular_to_f0(specular.clamp(0.0, 12.5));
    Vec3::splat(d * (1.0 - m)) + base_color * m
}

/// Fresnel choice of [`brdf`]: Schlick.
pub const FRESNEL_SCHLICK: i32 = 0;
/// Fresnel choice of [`brdf`]: exact dielectric Fresnel per channel.
pub const FRESNEL_EXACT: i32 = 1;
/// Names of the `fresnel` choices, in index order.
pub const FRESNEL_NAMES: &[&str] = &["schlick", "exact"];

/// Fresnel of one channel: Schlick `F0 + (1 − F0)(1 − V·H)⁵`, or the exact unpolarised
/// dielectric Fresnel from air into the index `f0_to_ior(F0)` (for a metal an approximation:
/// the extinction coefficient is ignored; F0 = 1 gives R = 1).
#[inline]
pub(crate) fn fresnel(v_dot_h: f32, f0: f32, mode: i32) -> f32 {
    if mode == FRESNEL_EXACT {
        fresnel_dielectric(v_dot_h, 1.0, f0_to_ior(f0)).0
    } else {
        fresnel_schlick(v_dot_h, f0)
    }
}

/// The metallic–roughness BRDF times the cosine:
/// `(base (1 − metallic)(1 − F(N·L))(1 − F(N·V))/π + F D V) · N·L`, with `D` = [`ggx_d`],
/// `V` = [`smith_visibility`], `F` at V·H from F0 = [`f0`] for the specular lobe; the diffuse
/// lobe is weighted by the Fresnel transmittance into and out of the surface, which keeps it
/// reciprocal and the total at most 1 (Shirley et al. 1997). Returns (total, diffuse, specular),
/// each already multiplied by N·L: the factor to multiply the light's radiance by.
///
/// The vectors are normalised here (a zero vector gives 0); N·L ≤ 0 gives 0; N·V < 0 (a view
/// just past the silhouette, with interpolated normals) is shaded as grazing, N·V = 0.
/// `1 − (N·H)²` is `|N × H|²` (no cancellation at the peak). `fresnel`: 0 Schlick, 1 exact.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn brdf(
    normal: Vec3,
    view: Vec3,
    light: Vec3,
    base_color: Vec3,
    metallic: f32,
    roughness: f32,
    specular: f32,
    fresnel_mode: i32,
) -> (Vec3, Vec3, Vec3) {
    let n = safe_normalize(normal);
    let v = safe_normalize(view);
    let l = safe_normalize(light);
    let nl = n.dot(l);
    if nl <= 0.0 {
        return (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
    }
    let nl = nl.clamp(MIN_COS, 1.0);
    let nv = n.dot(v).clamp(0.0, 1.0);
    let h = safe_normalize(l + v);
    let nh = n.dot(h);
    let vh = v.dot(h).clamp(0.0, 1.0);
    let f0 = f0(metallic, base_color, specular);
    let f = Vec3::new(
        fresnel(vh, f0.x, fresnel_mode),
        fresnel(vh, f0.y, fresnel_mode),
        fresnel(vh, f0.z, fresnel_mode),
    );
    let a2 = alpha2(roughness);
    let d = if nh > 0.0 {
        ggx_d_sin2(nh.min(1.0), cross(n, h).length_squared(), a2)
    } else {
        0.0
    };
    let v_nl = smith_visibility_n_dot_l(nv.max(MIN_COS), nl, a2);
    let m = metallic.clamp(0.0, 1.0);
    // The light that enters (1 − F at N·L) and leaves (1 − F at N·V) the surface feeds the
    // diffuse lobe: reciprocal, and with the specular lobe never above 1 (Shirley et al. 1997).
    let t = |c: f32| {
        Vec3::new(
            1.0 - fresnel(c, f0.x, fresnel_mode),
            1.0 - fresnel(c, f0.y, fresnel_mode),
            1.0 - fresnel(c, f0.z, fresnel_mode),
        )
    };
    let diffuse = base_color * ((1.0 - m) / PI) * t(nl) * t(nv) * nl;
    let spec = f * (d * v_nl);
    (diffuse + spec, diffuse, spec)
}

/// The Fresnel choices of a node whose template calls `mg_pbrh_fresnel${fresnel}(…, fresnel)`
/// (`pbr_brdf`, `env_ggx_monte_carlo`): Schlick's helper, or the exact one with the optics
/// helpers it calls; [`PBR_FRESNEL_WGSL`] picks one at run time.
pub(crate) fn with_fresnel_choices(t: NodeType) -> NodeType {
    t.wgsl_per_choice(
        "fresnel",
        &[PBR_FRESNEL_WGSL],
        [
            WgslChoice {
                choice: "schlick",
                helpers: &[PBR_FRESNEL_SCHLICK_WGSL],
                tables: &[],
            },
            WgslChoice {
                choice: "exact",
                helpers: &[
                    super::optics::COS2_T_WGSL,
                    super::optics::FRESNEL_HELPER_WGSL,
                    super::optics::F0_TO_IOR_HELPER_WGSL,
                    PBR_FRESNEL_EXACT_WGSL,
                ],
                tables: &[],
            },
        ],
    )
}

/// WGSL helpers shared by the PBR nodes: the same steps as the Rust above.
pub(crate) const PBR_HELPERS_WGSL: &str = r#"
fn mg_pbrh_alpha2(roughness: f32) -> f32 {
    let r = min(max(roughness, 0.02), 1.0);
    let a = r * r;
    return a * a;
}
fn mg_pbrh_normalize(v: vec3<f32>) -> vec3<f32> {
    let l2 = dot(v, v);
    if (l2 > 1e-20) {
        return v / sqrt(l2);
    }
    return vec3<f32>(0.0);
}
fn mg_pbrh_ggx_d_sin2(c: f32, sin2: f32, a2: f32) -> f32 {
    let k = sin2 + c * c * a2;
    return a2 / (3.14159265358979 * k * k);
}
fn mg_pbrh_ggx_d(n_dot_h: f32, roughness: f32) -> f32 {
    if (n_dot_h <= 0.0) {
        return 0.0;
    }
    let c = min(n_dot_h, 1.0);
    return mg_pbrh_ggx_d_sin2(c, (1.0 - c) * (1.0 + c), mg_pbrh_alpha2(roughness));
}
fn mg_pbrh_smith_v_nl(nv: f32, nl: f32, a2: f32) -> f32 {
    let gv = sqrt(nv * nv * (1.0 - a2) + a2);
    let gl = (nv / nl) * sqrt(nl * nl * (1.0 - a2) + a2);
    return 0.5 / (gv + gl);
}
fn mg_pbrh_smith_v(n_dot_v: f32, n_dot_l: f32, roughness: f32) -> f32 {
    if (n_dot_v <= 0.0 || n_dot_l <= 0.0) {
        return 0.0;
    }
    let nv = min(max(n_dot_v, 1e-30), 1.0);
    let nl = min(max(n_dot_l, 1e-30), 1.0);
    return mg_pbrh_smith_v_nl(nv, nl, mg_pbrh_alpha2(roughness)) / nl;
}
fn mg_pbrh_f0(metallic: f32, base_color: vec3<f32>, specular: f32) -> vec3<f32> {
    let m = min(max(metallic, 0.0), 1.0);
    let d = 0.08 * min(max(specular, 0.0), 12.5);
    return vec3<f32>(d * (1.0 - m)) + base_color * m;
}
"#;

/// WGSL of [`fresnel`] at `mode` 0: Schlick (takes `mode` and ignores it).
const PBR_FRESNEL_SCHLICK_WGSL: &str = r#"
fn mg_pbrh_fresnel_schlick(v_dot_h: f32, f0_in: f32, mode: i32) -> f32 {
    let m = max(1.0 - min(max(v_dot_h, 0.0), 1.0), 0.0);
    let m2 = m * m;
    return f0_in + (1.0 - f0_in) * (m2 * m2 * m);
}
"#;

/// WGSL of [`fresnel`] at `mode` 1: the exact dielectric Fresnel with the IOR from F0.
const PBR_FRESNEL_EXACT_WGSL: &str = r#"
fn mg_pbrh_fresnel_exact(v_dot_h: f32, f0_in: f32, mode: i32) -> f32 {
    return mg_opth_fresnel(v_dot_h, 1.0, mg_opth_f0_to_ior(f0_in)).x;
}
"#;

/// WGSL of [`fresnel`] (the BRDF's per-channel Fresnel choice, chosen at run time).
const PBR_FRESNEL_WGSL: &str = r#"
fn mg_pbrh_fresnel(v_dot_h: f32, f0_in: f32, mode: i32) -> f32 {
    if (mode == 1) {
        return mg_pbrh_fresnel_exact(v_dot_h, f0_in, mode);
    }
    return mg_pbrh_fresnel_schlick(v_dot_h, f0_in, mode);
}
"#;

/// WGSL of [`brdf`].
const BRDF_WGSL: &str = r#"
fn $fn(normal: vec3<f32>, view: vec3<f32>, light: vec3<f32>, base_color: vec3<f32>, metallic: f32, roughness: f32, specular: f32, fresnel: i32) -> $out {
    let n = mg_pbrh_normalize(normal);
    let v = mg_pbrh_normalize(view);
    let l = mg_pbrh_normalize(light);
    let nl0 = dot(n, l);
    if (nl0 <= 0.0) {
        return $out(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
    }
    let nl = min(max(nl0, 1e-30), 1.0);
    let nv = min(max(dot(n, v), 0.0), 1.0);
    let h = mg_pbrh_normalize(l + v);
    let nh = dot(n, h);
    let vh = min(max(dot(v, h), 0.0), 1.0);
    let f0 = mg_pbrh_f0(metallic, base_color, specular);
    let f = vec3<f32>(mg_pbrh_fresnel${fresnel}(vh, f0.x, fresnel), mg_pbrh_fresnel${fresnel}(vh, f0.y, fresnel), mg_pbrh_fresnel${fresnel}(vh, f0.z, fresnel));
    let a2 = mg_pbrh_alpha2(roughness);
    let nxh = cross(n, h);
    var d = 0.0;
    if (nh > 0.0) {
        d = mg_pbrh_ggx_d_sin2(min(nh, 1.0), dot(nxh, nxh), a2);
    }
    let v_nl = mg_pbrh_smith_v_nl(max(nv, 1e-30), nl, a2);
    let m = min(max(metallic, 0.0), 1.0);
    let t_l = vec3<f32>(1.0) - vec3<f32>(mg_pbrh_fresnel${fresnel}(nl, f0.x, fresnel), mg_pbrh_fresnel${fresnel}(nl, f0.y, fresnel), mg_pbrh_fresnel${fresnel}(nl, f0.z, fresnel));
    let t_v = vec3<f32>(1.0) - vec3<f32>(mg_pbrh_fresnel${fresnel}(nv, f0.x, fresnel), mg_pbrh_fresnel${fresnel}(nv, f0.y, fresnel), mg_pbrh_fresnel${fresnel}(nv, f0.z, fresnel));
    let diffuse = base_color * ((1.0 - m) / 3.14159265358979) * t_l * t_v * nl;
    let spec = f * (d * v_nl);
    return $out(diffuse + spec, diffuse, spec);
}
"#;

/// The PBR node types.
pub fn all() -> Vec<NodeType> {
    let f = Value::float;
    let v3 = Value::vec3;
    vec![
        NodeType::new("pbr_ggx_d", Category::Pbr, "GGX (Trowbridge–Reitz) microfacet normal distribution.")
            .source(
                "D = α² / (π ((N·H)²(α² − 1) + 1)²) with α = roughness² (Walter, Marschner, Li & \
                 Torrance 2007, eq. 33; Karis 2013, \"Real Shading in Unreal Engine 4\", eq. 3), \
                 evaluated as α² / (π ((1 − c)(1 + c) + c²α²)²); docs/models/pbr.md. Roughness is \
                 clamped to [0.02, 1]: a smoother surface gets the 0.02 lobe (peak 2e6/sr), wider and \
                 lower than its own. D = 0 for N·H ≤ 0.",
            )
            .input(In::float("n_dot_h", 1.0).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Cosine between the normal and the half vector."))
            .input(In::float("roughness", 0.5).range(0.0, 1.0).hard(0.0, 1.0).doc("Perceptual roughness; α = roughness²."))
            .output(Out::float("d").unit("1/sr").doc("Microfacet normal density (projected area per steradian)."))
            .wgsl("fn $fn(n_dot_h: f32, roughness: f32) -> f32 { return mg_pbrh_ggx_d(n_dot_h, roughness); }")
            .wgsl_uses(&[PBR_HELPERS_WGSL])
            .hard_case("roughness 0 at the peak", &[("n_dot_h", f(1.0)), ("roughness", f(0.0))])
            .hard_case("roughness 0 off the peak", &[("n_dot_h", f(0.999)), ("roughness", f(0.0))])
            .hard_case("roughness 1", &[("roughness", f(1.0))])
            .hard_case("half vector at the horizon", &[("n_dot_h", f(0.0))])
            .compute(ggx_d),
        NodeType::new("pbr_smith_visibility", Category::Pbr, "Height-correlated Smith–GGX visibility G₂/(4 N·L N·V).")
            .source(
                "V = 0.5 / (N·L √((N·V)²(1 − α²) + α²) + N·V √((N·L)²(1 − α²) + α²)), α = roughness² \
                 (Heitz 2014, \"Understanding the Masking-Shadowing Function\", eq. 99; Filament \
                 V_SmithGGXCorrelated; docs/models/pbr.md). 0 when either cosine is ≤ 0; cosines \
                 below 1e-30 are taken as 1e-30 (keeps V finite; no measurable cost); roughness is \
                 clamped to [0.02, 1] (see pbr_ggx_d).",
            )
            .input(In::float("n_dot_v", 1.0).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Cosine between the normal and the view direction."))
            .input(In::float("n_dot_l", 1.0).range(-1.0, 1.0).hard(-1.0, 1.0).doc("Cosine between the normal and the light direction."))
            .input(In::float("roughness", 0.5).range(0.0, 1.0).hard(0.0, 1.0).doc("Perceptual roughness; α = roughness²."))
            .output(Out::float("v").doc("Visibility: Smith G₂ divided by 4 N·L N·V."))
            .wgsl("fn $fn(n_dot_v: f32, n_dot_l: f32, roughness: f32) -> f32 { return mg_pbrh_smith_v(n_dot_v, n_dot_l, roughness); }")
            .wgsl_uses(&[PBR_HELPERS_WGSL])
            .hard_case("both grazing", &[("n_dot_v", f(1e-6)), ("n_dot_l", f(1e-6)), ("roughness", f(0.0))])
            .hard_case("light below the horizon", &[("n_dot_l", f(-0.5))])
            .hard_case("roughness 1, grazing view", &[("n_dot_v", f(1e-4)), ("roughness", f(1.0))])
            .compute(smith_visibility),
        NodeType::new("pbr_f0", Category::Pbr, "Normal-incidence reflectance of the metallic–roughness model.")
            .source(
                "F0 = mix(0.08 · specular, base_color, metallic): Unreal's Specular input for \
                 dielectrics (0.5 ↔ 4%, seed 003; Karis 2013) and the base colour for metals \
                 (glTF 2.0 Appendix B). metallic is clamped to [0, 1], specular to [0, 12.5].",
            )
            .input(In::float("metallic", 0.0).range(0.0, 1.0).hard(0.0, 1.0).doc("0 dielectric, 1 metal."))
            .input(In::color("base_color", [0.8, 0.8, 0.8]).range(0.0, 1.0).doc("Albedo of dielectrics, F0 of metals (linear RGB)."))
            .input(In::float("specular", 0.5).range(0.0, 1.0).hard(0.0, 12.5).doc("Unreal Specular: dielectric F0 = 0.08 · specular."))
            .output(Out::color("f0").doc("Reflectance at normal incidence per channel."))
            .wgsl("fn $fn(metallic: f32, base_color: vec3<f32>, specular: f32) -> vec3<f32> { return mg_pbrh_f0(metallic, base_color, specular); }")
            .wgsl_uses(&[PBR_HELPERS_WGSL])
            .hard_case("diamond (specular 2.15)", &[("specular", f(2.15))])
            .hard_case("metal", &[("metallic", f(1.0))])
            .compute(f0),
        with_fresnel_choices(NodeType::new("pbr_brdf", Category::Pbr, "Metallic–roughness BRDF (GGX, Smith, Fresnel, Lambert) times N·L.")
            .source(
                "color = (base (1 − metallic)(1 − F(N·L))(1 − F(N·V))/π + F(V·H) D V) · N·L: Lambert \
                 diffuse weighted by the Fresnel transmittance in and out (Shirley et al. 1997; \
                 reciprocal, total ≤ 1), GGX D \
                 (Walter et al. 2007; Karis 2013), height-correlated Smith V (Heitz 2014 eq. 99, \
                 Filament), F at V·H from F0 = mix(0.08 · specular, base_color, metallic) (Unreal; \
                 glTF 2.0 Appendix B), either Schlick (1994) or the exact dielectric Fresnel into \
                 the index (1 + √F0)/(1 − √F0) per channel (for metals an approximation without \
                 extinction; F0 = 1 reflects everything). Multiply by the light's radiance \
                 (geometry.light_color). Vectors are normalised here; N·L ≤ 0 gives 0; N·V < 0 (past \
                 the silhouette) is shaded as grazing; 1 − (N·H)² is |N × H|². Roughness is clamped \
                 to [0.02, 1] (see pbr_ggx_d); there the f32 direction error of V and L (6e-8 rad) \
                 moves the specular lobe's flank by up to ~1e-3 relative (docs/models/pbr.md).",
            )
            .input(In::vec3("normal", [0.0, 0.0, 1.0]).range(-1.0, 1.0).doc("Surface normal N."))
            .input(In::vec3("view", [0.0, 0.0, 1.0]).range(-1.0, 1.0).doc("Direction V to the eye."))
            .input(In::vec3("light", [0.0, 0.0, 1.0]).range(-1.0, 1.0).doc("Direction L to the light."))
            .input(In::color("base_color", [0.8, 0.8, 0.8]).range(0.0, 1.0).doc("Albedo of dielectrics, F0 of metals (linear RGB)."))
            .input(In::float("metallic", 0.0).range(0.0, 1.0).hard(0.0, 1.0).doc("0 dielectric, 1 metal."))
            .input(In::float("roughness", 0.5).range(0.0, 1.0).hard(0.0, 1.0).doc("Perceptual roughness; α = roughness², clamped to ≥ 0.02."))
            .input(In::float("specular", 0.5).range(0.0, 1.0).hard(0.0, 12.5).doc("Unreal Specular: dielectric F0 = 0.08 · specular."))
            .input(In::choice("fresnel", FRESNEL_NAMES, 0).doc("schlick: Schlick's approximation; exact: dielectric Fresnel with the IOR from F0."))
            .output(Out::color("color").doc("Reflected radiance per unit incident radiance: (diffuse + specular) · N·L."))
            .output(Out::color("diffuse").doc("The Lambert term times N·L."))
            .output(Out::color("specular").doc("The GGX term times N·L."))
            .wgsl(BRDF_WGSL)
            .wgsl_uses(&[PBR_HELPERS_WGSL])
            .hard_case("grazing view", &[("view", v3([1.0, 0.0, 1e-4])), ("light", v3([-0.6, 0.0, 0.8]))])
            .hard_case("grazing light", &[("light", v3([1.0, 0.0, 1e-4]))])
            .hard_case("view past the silhouette", &[("view", v3([1.0, 0.0, -0.05]))])
            .hard_case("light below the horizon", &[("light", v3([0.0, 0.6, -0.8]))])
            .hard_case("roughness 0, mirror", &[("roughness", f(0.0))])
            .hard_case("roughness 0, mirror, exact", &[("roughness", f(0.0)), ("fresnel", Value::int(1))])
            .hard_case("roughness 0, both grazing", &[("roughness", f(0.0)), ("view", v3([1.0, 0.0, 1e-4])), ("light", v3([-1.0, 0.0, 1e-4]))])
            .hard_case("roughness 1", &[("roughness", f(1.0)), ("light", v3([0.6, 0.0, 0.8]))])
            .hard_case("light opposite the view", &[("view", v3([0.6, 0.0, 0.8])), ("light", v3([-0.6, 0.0, -0.8]))])
            .hard_case("metal, exact Fresnel", &[("metallic", f(1.0)), ("base_color", Value::color([1.0, 0.71, 0.29])), ("fresnel", Value::int(1))])
            .hard_case("diamond specular", &[("specular", f(2.15)), ("fresnel", Value::int(1))])
            .hard_case("mirror metal, exact", &[("metallic", f(1.0)), ("base_color", Value::color([1.0, 1.0, 1.0])), ("fresnel", Value::int(1))])
            .hard_case(
                "low roughness, near the peak",
                &[
                    ("view", v3([-0.645_648_4, -0.691_011_6, 0.325_024_9])),
                    ("light", v3([0.646_429_5, 0.691_630_5, 0.325_024_9])),
                    ("roughness", f(0.02)),
                    ("metallic", f(1.0)),
                    ("base_color", Value::color([1.0, 1.0, 1.0])),
                ],
            )
            .hard_case("zero normal", &[("normal", v3([0.0, 0.0, 0.0]))])
            .compute(brdf)),
    ]
}
