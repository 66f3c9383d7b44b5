//! Search-to-add: fuzzy matching of a query on node types' names, categories and docs, and
//! the filter of nodes that can take a wire of a given type.

use crate::node::{NodeType, PortType};
use crate::registry::Registry;
use crate::types::SocketType;
use std::sync::Arc;

/// How well `query` matches `text` as a subsequence (case-insensitive): `None` when some
/// query character is missing; higher for matches at word starts and in runs, and for
/// shorter texts.
pub fn fuzzy_score(query: &str, text: &str) -> Option<i32> {
    let q: Vec<char> = query
        .to_lowercase()
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect();
    if q.is_empty() {
        return Some(0);
    }
    let t: Vec<char> = text.to_lowercase().chars().collect();
    let mut score = 0;
    let mut qi = 0;
    let mut prev: Option<usize> = None;
    for (ti, &c) in t.iter().enumerate() {
        if qi < q.len() && c == q[qi] {
            let word_start = ti == 0 || !t[ti - 1].is_alphanumeric();
            score += 1;
            if word_start {
                score += 8;
            }
            if prev == Some(ti.wrapping_sub(1)) {
                score += 5;
            }
            prev = Some(ti);
            qi += 1;
        }
    }
    (qi == q.len()).then(|| score * 4 - (t.len() as i32).min(200) / 10)
}

/// A node type's score for `query`: its name counts most, then its category, then its
/// summary and long doc.
pub fn type_score(t: &NodeType, query: &str) -> Option<i32> {
    [
        fuzzy_score(query, t.name()).map(|s| s * 3 + 1000),
        fuzzy_score(query, t.category().name()).map(|s| s * 2 + 500),
        fuzzy_score(query, t.summary()),
        fuzzy_score(query, t.source_doc()).map(|s| s / 2),
    ]
    .into_iter()
    .flatten()
    .max()
}

/// What a dropped wire needs of the node it creates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WireFilter {
    /// An input that accepts a value of this type (the wire came from an output).
    InputAccepting(SocketType),
    /// An output whose value an input of this type accepts (the wire came from an input).
    OutputFeeding(SocketType),
}

/// The port of `t` a wire of `filter` connects to: an input (or output) index.
pub fn compatible_port(t: &NodeType, filter: WireFilter) -> Option<usize> {
    let generic = t.generic_types();
    let fits = |port: PortType, test: &dyn Fn(SocketType) -> bool| match port {
        PortType::Fixed(p) => test(p),
        PortType::Generic => generic.iter().any(|&g| test(g)),
    };
    match filter {
        WireFilter::InputAccepting(from) => t
            .inputs()
            .iter()
            .position(|i| fits(i.ty, &|p| from.conversion_to(p).is_some())),
        WireFilter::OutputFeeding(to) => t
            .outputs()
            .iter()
            .position(|o| fits(o.ty, &|p| p.conversion_to(to).is_some())),
    }
}

/// The node types matching `query` (all of them for an empty query, in registry order),
/// best first, keeping only those with a port for `filter`.
pub fn search(registry: &Registry, query: &str, filter: Option<WireFilter>) -> Vec<Arc<NodeType>> {
    let mut hits: Vec<(i32, usize, &Arc<NodeType>)> = registry
        .types()
        .iter()
        .enumerate()
        .filter(|(_, t)| filter.is_none_or(|f| compatible_port(t, f).is_some()))
        .filter_map(|(k, t)| type_score(t, query).map(|s| (s, k, t)))
        .collect();
    // Best score first; registry order between equals, so results are deterministic.
    hits.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
    hits.into_iter().map(|(_, _, t)| t.clone()).collect()
}

/// One result of the add-node search: a node type, or the Material Output node
/// ([`super::outputs`]).
#[derive(Clone, Debug)]
pub enum Hit {
    /// A registered node type.
    Type(Arc<NodeType>),
    /// The Material Output node (the graph's outputs).
    Output,
}

/// The Material Output node's score for `query`, scored as a type's name ("Material
/// Output", "output") and summary.
pub fn output_score(query: &str) -> Option<i32> {
    [
        fuzzy_score(query, super::outputs::OUTPUT_TITLE).map(|s| s * 3 + 1000),
        fuzzy_score(query, "output").map(|s| s * 3 + 1000),
        fuzzy_score(query, "graph outputs: color emission alpha displacement"),
    ]
    .into_iter()
    .flatten()
    .max()
}

/// [`search`]'s node types and the Material Output node, best first (after the types
/// that score as well). A wire dropped from an output may end on it (it takes any type);
/// one dropped from an input may not (it has no outputs).
pub fn search_all(registry: &Registry, query: &str, filter: Option<WireFilter>) -> Vec<Hit> {
    let mut hits: Vec<(i32, usize, Hit)> = registry
        .types()
        .iter()
        .enumerate()
        .filter(|(_, t)| filter.is_none_or(|f| compatible_port(t, f).is_some()))
        .filter_map(|(k, t)| type_score(t, query).map(|s| (s, k, Hit::Type(t.clone()))))
        .collect();
    if !matches!(filter, Some(WireFilter::OutputFeeding(_)))
        && let Some(s) = output_score(query)
    {
        hits.push((s, usize::MAX, Hit::Output));
    }
    hits.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
    hits.into_iter().map(|(_, _, h)| h).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn output_finds_the_material_output_node_first() {
        let r = Registry::builtin();
        assert!(matches!(search_all(r, "output", None)[0], Hit::Output));
        assert!(matches!(
            search_all(r, "material out", None)[0],
            Hit::Output
        ));
        let from_input = Some(WireFilter::OutputFeeding(SocketType::Float));
        assert!(
            !search_all(r, "output", from_input)
                .iter()
                .any(|h| matches!(h, Hit::Output))
        );
    }

    #[test]
    fn subsequences_match_and_others_do_not() {
        assert!(fuzzy_score("frd", "fresnel_dielectric").is_some());
        assert!(fuzzy_score("xyz", "fresnel_dielectric").is_none());
        // Word starts beat scattered letters.
        assert!(fuzzy_score("fd", "fresnel_dielectric") > fuzzy_score("fd", "offside"));
    }

    #[test]
    fn an_exact_name_comes_first() {
        let r = Registry::builtin();
        let hits = search(r, "dot", None);
        assert_eq!(hits[0].name(), "dot");
        let fresnel = search(r, "fresnel diel", None);
        assert_eq!(fresnel[0].name(), "fresnel_dielectric");
    }

    #[test]
    fn a_vec2_wire_only_offers_vec2_vector_or_generic_inputs() {
        // src/types.rs: a vec2 converts to itself, and to a vec3 or colour as (x, y, 0).
        let r = Registry::builtin();
        let f = WireFilter::InputAccepting(SocketType::Vec2);
        assert!(!search(r, "", Some(f)).is_empty());
        let offered = search(r, "", Some(f));
        assert!(offered.iter().any(|t| t.name() == "mapping"));
        assert!(!offered.iter().any(|t| t.name() == "hg_phase"));
        for t in offered {
            let k = compatible_port(&t, f).unwrap();
            let ty = t.inputs()[k].ty;
            assert!(
                matches!(
                    ty,
                    PortType::Fixed(SocketType::Vec2 | SocketType::Vec3 | SocketType::Color)
                ) || ty == PortType::Generic,
                "{} input {} is {ty}",
                t.name(),
                t.inputs()[k].name
            );
        }
    }
}
