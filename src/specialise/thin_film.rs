//! The thin film's incoherent limit: a film thicker than the light's coherence length shows
//! no interference colours, only the sum of the intensities of the Airy series.
//!
//! Light of mean wavelength λ̄ and bandwidth Δλ interferes with itself only over path
//! differences below its coherence length `l_c = λ̄²/Δλ` (Hecht, *Optics*, 4th ed., §7.4.3
//! and ch. 12; Born & Wolf, *Principles of Optics*, 7th ed., §7.5.8). A film of index `n_f`
//! and thickness `d` delays each internal round trip by the optical path difference
//! `Δ = 2 n_f d cosθ_f`; once `Δ ≫ l_c` the phase of the Airy sum averages out over the
//! band and the reflectance is the incoherent sum of the reflected intensities (Born &
//! Wolf §7.6.1 with the phase term dropped), per polarisation:
//!
//! `R = R12 + T12² R23 / (1 − R12 R23)`, `T = T12 T23 / (1 − R12 R23)`.
//!
//! For a free film (the same medium on both sides, a soap bubble) `R23 = R12` (Stokes), so
//! `R = 2 R12 / (1 + R12)` and `T = (1 − R12)/(1 + R12)`, averaged over s and p; the result
//! is the same at every wavelength (no dispersion), a grey in linear sRGB (the thin_film
//! node's D65 weights sum to 1 per channel).
//!
//! The rewrite builds that sum out of registry math nodes in place of a `thin_film` node
//! whose indices and thickness are constant, whose outside and substrate indices are equal,
//! and whose smallest optical path difference over its whole domain (grazing incidence,
//! unless `cos_theta` is constant) is at least the coherence length.

use super::{Rewrite, RewriteKind};
use crate::document::{GraphDocument, NodeDocument};
use crate::graph::{Graph, InputSource};
use serde_json::{Value as J, json};
use std::collections::BTreeMap;

/// Mean wavelength of D65 light seen through the CIE 1931 photopic response: the peak of
/// V(λ), 555 nm.
pub const D65_MEAN_WAVELENGTH_NM: f32 = 555.0;
/// Bandwidth of that response: the full width at half maximum of V(λ), 510–610 nm
/// (CIE 1931 2° observer).
pub const D65_BANDWIDTH_NM: f32 = 100.0;
/// The coherence length of white (D65) light as the eye sees it, `λ̄²/Δλ` = 555²/100 ≈
/// 3080 nm; beyond it the rewrite replaces a film by its incoherent limit.
pub const COHERENCE_LENGTH_D65_NM: f32 =
    D65_MEAN_WAVELENGTH_NM * D65_MEAN_WAVELENGTH_NM / D65_BANDWIDTH_NM;

/// The incoherent reflectance and transmittance of a free, non-absorbing film of index
/// `film_ior` in a medium of index `outside_ior` at incidence cosine `cos_theta` (either
/// side), averaged over s and p; the same sum as the nodes the rewrite builds.
pub fn incoherent_free_film(cos_theta: f32, film_ior: f32, outside_ior: f32) -> (f32, f32) {
    let c = cos_theta.abs();
    let eta = outside_ior / film_ior;
    let cf = (1.0 - eta * eta * (1.0 - c * c)).clamp(0.0, 1.0).sqrt();
    let (mut r, mut t) = (0.0, 0.0);
    for (x, y) in [
        (outside_ior * c, film_ior * cf),
        (film_ior * c, outside_ior * cf),
    ] {
        let den = x + y;
        let a = if den != 0.0 { (x - y) / den } else { 0.0 };
        let r12 = a * a;
        r += 0.5 * (2.0 * r12 / (1.0 + r12));
        t += 0.5 * ((1.0 - r12) / (1.0 + r12));
    }
    (r, t)
}

/// The smallest optical path difference `2 n_f d cosθ_f` (nm) of a film over incidence
/// cosines: at `cos_theta` when it is known, else at grazing incidence.
pub fn min_path_difference_nm(
    thickness_nm: f32,
    film_ior: f32,
    outside_ior: f32,
    cos_theta: Option<f32>,
) -> f32 {
    let c = cos_theta.map_or(0.0, f32::abs);
    let eta = outside_ior / film_ior;
    let cf2 = 1.0 - eta * eta * (1.0 - c * c);
    2.0 * film_ior * thickness_nm * cf2.max(0.0).sqrt()
}

/// Replaces every qualifying `thin_film` node of `doc` (validated as `g`) by its incoherent
/// limit; returns whether any was replaced.
pub(super) fn rewrite(
    doc: &mut GraphDocument,
    g: &Graph,
    coherence_length_nm: f32,
    rewrites: &mut Vec<Rewrite>,
) -> bool {
    let mut changed = false;
    for n in g.nodes() {
        if n.node_type.name() != "thin_film" {
            continue;
        }
        let constant = |name: &str| -> Option<f32> {
            let k = n.node_type.input_index(name)?;
            match &n.inputs[k] {
                InputSource::Default(v) | InputSource::Value { value: v, .. } => Some(v.as_f32()),
                InputSource::Link(..) => None,
            }
        };
        let clamp_ior = |x: f32| {
            x.clamp(
                crate::nodes::thin_film::IOR_MIN,
                crate::nodes::thin_film::IOR_MAX,
            )
        };
        let (Some(d), Some(nf), Some(n1), Some(n3)) = (
            constant("thickness_nm"),
            constant("film_ior").map(clamp_ior),
            constant("outside_ior").map(clamp_ior),
            constant("substrate_ior").map(clamp_ior),
        ) else {
            continue;
        };
        if n1 != n3 {
            continue;
        }
        let d = d.clamp(0.0, crate::nodes::thin_film::THICKNESS_MAX_NM);
        let opd = min_path_difference_nm(d, nf, n1, constant("cos_theta"));
        if opd < coherence_length_nm {
            continue;
        }
        let Some(pos) = doc.nodes.iter().position(|x| x.id == n.id) else {
            continue;
        };
        let cos = doc.nodes[pos]
            .inputs
            .get("cos_theta")
            .cloned()
            .unwrap_or(json!(1.0));
        let nodes = incoherent_nodes(&n.id, cos, nf, n1);
        if nodes.iter().any(|m| doc.nodes.iter().any(|x| x.id == m.id)) {
            continue;
        }
        doc.nodes.splice(pos..=pos, nodes);
        relink(doc, &n.id);
        rewrites.push(Rewrite {
            node: n.id.clone(),
            kind: RewriteKind::IncoherentFilm,
            reason: format!(
                "free film (n = {n1}, n_f = {nf}, d = {d} nm): optical path difference ≥ {opd:.0} nm ≥ coherence length {coherence_length_nm:.0} nm; replaced by its incoherent limit 2R/(1+R) per polarisation"
            ),
        });
        changed = true;
    }
    changed
}

/// Points the links to the film's outputs at the nodes that replace it.
fn relink(doc: &mut GraphDocument, id: &str) {
    let map = |l: &str| -> Option<String> {
        match l.strip_prefix(id)?.strip_prefix('.')? {
            "reflectance" => Some(format!("{id}__reflectance.color")),
            "transmittance" => Some(format!("{id}__transmittance.color")),
            _ => None,
        }
    };
    for node in &mut doc.nodes {
        for json in node.inputs.values_mut() {
            let to = json.get("link").and_then(J::as_str).and_then(map);
            if let Some(to) = to {
                *json = json!({ "link": to });
            }
        }
    }
    for o in &mut doc.outputs {
        if let Some(to) = map(&o.from) {
            o.from = to;
        }
    }
}

/// The nodes of the incoherent sum for film `id` (see the module docs), `cos` the film's
/// `cos_theta` entry as written, lanes (s, p) in vec2s.
fn incoherent_nodes(id: &str, cos: J, nf: f32, n: f32) -> Vec<NodeDocument> {
    let eta = n / nf;
    let node = |name: &str, ty: &str, data_type: Option<&str>, inputs: &[(&str, J)]| NodeDocument {
        id: format!("{id}__{name}"),
        node_type: ty.to_owned(),
        data_type: data_type.map(str::to_owned),
        variant: None,
        group: None,
        muted: false,
        inputs: inputs
            .iter()
            .map(|(k, v)| ((*k).to_owned(), v.clone()))
            .collect::<BTreeMap<_, _>>(),
        texture: None,
        color_space: None,
        position: None,
    };
    let l = |name: &str, out: &str| json!({ "link": format!("{id}__{name}.{out}") });
    let r = |name: &str| l(name, "result");
    let f = crate::value::json_f32;
    let v2 = |a: f32, b: f32| json!([f(a), f(b)]);
    let float = Some("float");
    let vec2 = Some("vec2");
    vec![
        node("cos", "abs", float, &[("x", cos)]),
        node("cos2", "mul", float, &[("a", r("cos")), ("b", r("cos"))]),
        node("sin2", "one_minus", float, &[("x", r("cos2"))]),
        node(
            "sin2_f",
            "mul",
            float,
            &[("a", r("sin2")), ("b", f(eta * eta))],
        ),
        node("cos2_f", "one_minus", float, &[("x", r("sin2_f"))]),
        node("cos2_f_tir", "saturate", float, &[("x", r("cos2_f"))]),
        node("cos_f", "sqrt", float, &[("x", r("cos2_f_tir"))]),
        node("x", "mul", vec2, &[("a", r("cos")), ("b", v2(n, nf))]),
        node("y", "mul", vec2, &[("a", r("cos_f")), ("b", v2(nf, n))]),
        node("num", "sub", vec2, &[("a", r("x")), ("b", r("y"))]),
        node("den", "add", vec2, &[("a", r("x")), ("b", r("y"))]),
        node("r12", "div", vec2, &[("a", r("num")), ("b", r("den"))]),
        node("rr12", "mul", vec2, &[("a", r("r12")), ("b", r("r12"))]),
        node("one_plus", "add", vec2, &[("a", r("rr12")), ("b", f(1.0))]),
        node("two_r", "mul", vec2, &[("a", r("rr12")), ("b", f(2.0))]),
        node(
            "r_sp",
            "div",
            vec2,
            &[("a", r("two_r")), ("b", r("one_plus"))],
        ),
        node("t12", "one_minus", vec2, &[("x", r("rr12"))]),
        node(
            "t_sp",
            "div",
            vec2,
            &[("a", r("t12")), ("b", r("one_plus"))],
        ),
        node("r", "dot", vec2, &[("a", r("r_sp")), ("b", v2(0.5, 0.5))]),
        node("t", "dot", vec2, &[("a", r("t_sp")), ("b", v2(0.5, 0.5))]),
        node(
            "reflectance",
            "combine",
            None,
            &[("x", r("r")), ("y", r("r")), ("z", r("r"))],
        ),
        node(
            "transmittance",
            "combine",
            None,
            &[("x", r("t")), ("y", r("t")), ("z", r("t"))],
        ),
    ]
}
