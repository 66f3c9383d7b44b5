//! `--set` overrides as users type them: names of the graph's parameters, its nodes'
//! inputs (`NODE.INPUT`), the geometry attributes and names that are none of those; values
//! that are numbers at and past the edges of f32 in every spelling (`1e39`, `1e400`,
//! `NaN`, `-inf`, `3.4028236e38`), arrays of every length, bools, enum names, links,
//! quoted words and malformed text, with stray spaces and `=` signs.

use super::mutate_graph::NAMES;
use super::rng::Rng;
use matgraph::Registry;
use matgraph::node::ALL_ATTRIBUTES;
use serde_json::Value as J;

/// Values at the edges, as typed.
const VALUES: &[&str] = &[
    "0.5",
    "1",
    "-0",
    "2.42",
    "1e39",
    "-1e39",
    "1e400",
    "3.4028235e38",
    "3.4028236e38",
    "-3.5e38",
    "1e-46",
    "NaN",
    "nan",
    "inf",
    "-inf",
    "+inf",
    "Infinity",
    "-infinity",
    "[0.1,0.2]",
    "[1,2,3]",
    "[0.866, 0, 0.5]",
    "[1,2,3,4]",
    "[1,2,3,4,5]",
    "[]",
    "[1e39,0,0]",
    "[0.5,1e400]",
    "[NaN,0,0]",
    "[0.5,\"a\"]",
    "true",
    "false",
    "linear",
    "phase_form",
    "\"inf\"",
    "{\"link\":\"geo.normal\"}",
    "{\"link\":\"nope.x\"}",
    "",
    "  ",
    "[",
    "]",
    "=",
    "é",
    "0x10",
    "1_000",
    "+1",
    ".5",
    "5.",
    "1e",
    "2147483648",
    "-2147483649",
    "7",
    "\u{0}",
];

/// A name: a parameter, a node's input, an attribute, or something else.
fn name(rng: &mut Rng, doc: &J) -> String {
    let registry = Registry::builtin();
    match rng.below(6) {
        0 | 1 => doc["parameters"]
            .as_array()
            .filter(|p| !p.is_empty())
            .and_then(|p| p[rng.below(p.len())]["name"].as_str().map(str::to_owned))
            .unwrap_or_else(|| "ior".into()),
        2 | 3 => {
            let nodes = doc["nodes"].as_array().cloned().unwrap_or_default();
            if nodes.is_empty() {
                return "n.x".into();
            }
            let n = rng.pick(&nodes);
            let id = n["id"].as_str().unwrap_or("x");
            let input = match registry.get(n["type"].as_str().unwrap_or("")) {
                Some(t) if !t.inputs().is_empty() && !rng.one_in(8) => {
                    t.inputs()[rng.below(t.inputs().len())].name.to_owned()
                }
                _ => rng.pick(NAMES).to_string(),
            };
            format!("{id}.{input}")
        }
        4 => rng.pick(&ALL_ATTRIBUTES).name().to_owned(),
        _ => rng.pick(NAMES).to_string(),
    }
}

/// A value as typed: from the edge list, or a random number in a random spelling.
fn value(rng: &mut Rng) -> String {
    if rng.one_in(3) {
        let x = (rng.unit() * 2.0 - 1.0) * 10f64.powi(rng.below(90) as i32 - 45);
        match rng.below(3) {
            0 => format!("{x}"),
            1 => format!("{x:e}"),
            _ => format!("[{x},{x:e},0]"),
        }
    } else {
        rng.pick(VALUES).to_string()
    }
}

/// One to four `--set` texts for the graph `doc`.
pub fn overrides(rng: &mut Rng, doc: &J) -> Vec<String> {
    (0..1 + rng.below(4))
        .map(|_| {
            let (n, v) = (name(rng, doc), value(rng));
            match rng.below(10) {
                0 => format!(" {n} = {v} "),
                1 => n,
                2 => format!("{n}={v}={v}"),
                3 => format!("={v}"),
                _ => format!("{n}={v}"),
            }
        })
        .collect()
}
