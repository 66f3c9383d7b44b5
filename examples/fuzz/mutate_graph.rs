//! Mutations of graph JSON (format version 1, and the node lists of any version): node
//! deletion, duplication (same id or a fresh one), swaps, type changes to any registered
//! type, `data_type` changes, inputs removed, added (known and unknown names) or set to huge,
//! tiny, negative, zero, wrong-typed, wrong-length, enum-name, unicode or link values (to
//! valid, missing, self and random outputs), textures on any node, output and parameter
//! renames (unicode, `_`, WGSL keywords), re-targets, duplications and deletions, top-level
//! field changes, and raw byte edits of the text.

use super::rng::Rng;
use matgraph::Registry;
use serde_json::{Value as J, json};

/// Names that stress identifiers: unicode, `_`, WGSL keywords and reserved words.
pub const NAMES: &[&str] = &[
    "é",
    "_",
    "__x",
    "",
    "fn",
    "let",
    "struct",
    "NULL",
    "await",
    "vec3",
    "f32",
    "mg_params",
    "geom",
    "s",
    "x y",
    "1a",
    "日本語",
    "\u{0}",
    "a\rb",
    "a.b",
    "normal",
    "time",
    "ior",
    "out",
    "p__",
];

/// Numbers at and past the edges of f32.
pub const NUMBERS: &[f64] = &[
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.5,
    1e-45,
    1e-40,
    -1e-40,
    1e-7,
    3.4e38,
    -3.4e38,
    3.5e38,
    1e39,
    -1e300,
    1e300,
    2147483648.0,
    -2147483649.0,
    16777217.0,
    100.0,
    1e6,
    0.001,
];

/// A random JSON number, from the edge list or uniformly scaled.
pub fn number(rng: &mut Rng) -> J {
    if rng.one_in(2) {
        json!(*rng.pick(NUMBERS))
    } else {
        let x = (rng.bits() >> 11) as f64 / (1u64 << 53) as f64;
        let e = rng.below(80) as i32 - 40;
        json!((x * 2.0 - 1.0) * 10f64.powi(e))
    }
}

/// A random input value: literals of every shape, or links.
pub fn value(rng: &mut Rng, doc: &J) -> J {
    match rng.below(10) {
        0 | 1 => number(rng),
        2 => J::Array((0..rng.below(6)).map(|_| number(rng)).collect()),
        3 => json!(rng.one_in(2)),
        4 => json!(*rng.pick(NAMES)),
        5 => json!(rng.pick(&[
            "linear",
            "nearest",
            "repeat",
            "clamp",
            "mirror",
            "phase_form",
            "pharr"
        ])),
        6 => J::Null,
        7 => json!({ "link": random_output(rng, doc) }),
        8 => json!({ "link": random_output(rng, doc), "extra": 1 }),
        _ => json!({ "link": format!("{}.{}", rng.pick(NAMES), rng.pick(NAMES)) }),
    }
}

/// `id.output` of a random node of `doc` and a random output of its type (or a random name).
pub fn random_output(rng: &mut Rng, doc: &J) -> String {
    let nodes = doc["nodes"].as_array().cloned().unwrap_or_default();
    if nodes.is_empty() {
        return "x.y".into();
    }
    let n = rng.pick(&nodes);
    let id = n["id"].as_str().unwrap_or("x").to_owned();
    let ty = n["type"].as_str().unwrap_or("");
    let out = match Registry::builtin().get(ty) {
        Some(t) if !t.outputs().is_empty() && !rng.one_in(8) => {
            t.outputs()[rng.below(t.outputs().len())].name.to_owned()
        }
        _ => rng.pick(NAMES).to_string(),
    };
    format!("{id}.{out}")
}

/// Applies one random mutation to `doc`.
pub fn mutate(rng: &mut Rng, doc: &mut J) {
    let registry = Registry::builtin();
    let len = doc["nodes"].as_array().map_or(0, Vec::len);
    let k = rng.below(len.max(1));
    // Entries that are objects can be edited in place (serde_json panics on indexing others).
    let node_obj = len > 0 && doc["nodes"][k].is_object();
    match rng.below(22) {
        0 if len > 0 => {
            doc["nodes"].as_array_mut().unwrap().remove(k);
        }
        1 if len > 0 => {
            let mut n = doc["nodes"][k].clone();
            if n.is_object() && rng.one_in(2) {
                n["id"] = json!(format!("dup{}", rng.below(1000)));
            }
            doc["nodes"].as_array_mut().unwrap().push(n);
        }
        2 if len > 1 => {
            let j = rng.below(len);
            doc["nodes"].as_array_mut().unwrap().swap(j, k);
        }
        3 if node_obj => {
            let t = rng.pick(registry.types());
            doc["nodes"][k]["type"] = json!(t.name());
        }
        4 if node_obj => {
            doc["nodes"][k]["data_type"] =
                json!(rng.pick(&["float", "vec2", "vec3", "vec4", "color", "int", "bool", "é"]));
        }
        5..=9 if node_obj => {
            // Set an input the type has (most of the time) to a random value.
            let ty = doc["nodes"][k]["type"].as_str().unwrap_or("").to_owned();
            let name = match registry.get(&ty) {
                Some(t) if !t.inputs().is_empty() && !rng.one_in(6) => {
                    t.inputs()[rng.below(t.inputs().len())].name.to_owned()
                }
                _ => rng.pick(NAMES).to_string(),
            };
            let v = value(rng, doc);
            if !doc["nodes"][k]["inputs"].is_object() {
                doc["nodes"][k]["inputs"] = json!({});
            }
            doc["nodes"][k]["inputs"][name] = v;
        }
        10 if node_obj => {
            if let Some(m) = doc["nodes"][k]["inputs"].as_object_mut()
                && !m.is_empty()
            {
                let key = m.keys().nth(rng.below(m.len())).cloned().unwrap();
                m.remove(&key);
            }
        }
        11 if node_obj => {
            // A link to itself or to a later node: cycles.
            let id = doc["nodes"][k]["id"].as_str().unwrap_or("x").to_owned();
            let j = rng.below(len);
            let ty = doc["nodes"][j]["type"].as_str().unwrap_or("").to_owned();
            if let Some(t) = registry.get(&ty)
                && !t.inputs().is_empty()
                && doc["nodes"][j].is_object()
            {
                let input = t.inputs()[rng.below(t.inputs().len())].name;
                let out = registry
                    .get(doc["nodes"][k]["type"].as_str().unwrap_or(""))
                    .and_then(|t| t.outputs().first().map(|o| o.name))
                    .unwrap_or("result");
                if !doc["nodes"][j]["inputs"].is_object() {
                    doc["nodes"][j]["inputs"] = json!({});
                }
                doc["nodes"][j]["inputs"][input] = json!({ "link": format!("{id}.{out}") });
            }
        }
        12 if node_obj => {
            doc["nodes"][k]["texture"] = match rng.below(4) {
                0 => json!("scene:refraction"),
                1 => json!(""),
                2 => json!([]),
                _ => json!(["a.png", "b.png"]),
            };
        }
        13 if node_obj => {
            doc["nodes"][k]["position"] = json!([number(rng), number(rng)]);
        }
        14 if node_obj => {
            doc["nodes"][k]["id"] = json!(rng.pick(NAMES));
        }
        15 => {
            // Outputs: rename, re-target, duplicate, delete, add.
            if !doc["outputs"].is_array() {
                doc["outputs"] = json!([]);
            }
            let target = random_output(rng, doc);
            let outs = doc["outputs"].as_array_mut().unwrap();
            match rng.below(4) {
                0 if !outs.is_empty() => {
                    let j = rng.below(outs.len());
                    if outs[j].is_object() {
                        outs[j]["name"] = json!(rng.pick(NAMES));
                    }
                }
                1 if !outs.is_empty() => {
                    let j = rng.below(outs.len());
                    let o = outs[j].clone();
                    outs.push(o);
                }
                2 if !outs.is_empty() => {
                    let j = rng.below(outs.len());
                    outs.remove(j);
                }
                _ => outs.push(json!({ "name": rng.pick(NAMES), "from": target })),
            }
        }
        16 => {
            // Parameters: rename, re-point, duplicate, add.
            if !doc["parameters"].is_array() {
                doc["parameters"] = json!([]);
            }
            let node = doc["nodes"]
                .as_array()
                .and_then(|n| (!n.is_empty()).then(|| n[rng.below(n.len())]["id"].clone()))
                .unwrap_or(json!("x"));
            let params = doc["parameters"].as_array_mut().unwrap();
            match rng.below(3) {
                0 if !params.is_empty() => {
                    let j = rng.below(params.len());
                    if params[j].is_object() {
                        params[j]["name"] = json!(rng.pick(NAMES));
                    }
                }
                1 if !params.is_empty() => {
                    let j = rng.below(params.len());
                    let p = params[j].clone();
                    params.push(p);
                }
                _ => params.push(json!({ "name": rng.pick(NAMES), "node": node })),
            }
        }
        17 => {
            let field = *rng.pick(&[
                "version",
                "name",
                "doc",
                "scene",
                "nodes",
                "outputs",
                "parameters",
                "extra",
            ]);
            doc[field] = match rng.below(5) {
                0 => number(rng),
                1 => json!(rng.pick(NAMES)),
                2 => J::Null,
                3 => json!([]),
                _ => json!({ "k": [1, 2, {"deep": [[[[]]]]}] }),
            };
        }
        18 if len > 0 => {
            // A parameter node with a random value feeding a random node.
            let id = format!("pz{}", rng.below(100));
            let v = number(rng);
            doc["nodes"]
                .as_array_mut()
                .unwrap()
                .push(json!({ "id": id, "type": "parameter", "inputs": { "value": v } }));
            if !doc["parameters"].is_array() {
                doc["parameters"] = json!([]);
            }
            doc["parameters"]
                .as_array_mut()
                .unwrap()
                .push(json!({ "name": id, "node": id }));
        }
        19 if len > 0 => {
            // A whole random node of a random type with random inputs.
            let t = rng.pick(registry.types());
            let mut inputs = serde_json::Map::new();
            for i in t.inputs() {
                if rng.one_in(2) {
                    inputs.insert(i.name.to_owned(), value(rng, doc));
                }
            }
            let id = format!("z{}", rng.below(10_000));
            doc["nodes"]
                .as_array_mut()
                .unwrap()
                .push(json!({ "id": id, "type": t.name(), "inputs": inputs }));
            if rng.one_in(2)
                && let Some(o) = t.outputs().first()
            {
                if !doc["outputs"].is_array() {
                    doc["outputs"] = json!([]);
                }
                doc["outputs"]
                    .as_array_mut()
                    .unwrap()
                    .push(json!({ "name": id, "from": format!("{id}.{}", o.name) }));
            }
        }
        20 if len > 0 => {
            doc["nodes"][k] = match rng.below(4) {
                0 => number(rng),
                1 => json!(rng.pick(NAMES)),
                2 => json!({ "id": 5, "type": [] }),
                _ => J::Null,
            };
        }
        _ => {
            doc["name"] = json!(rng.pick(NAMES));
        }
    }
}

/// Raw edits of the text: byte flips, insertions, deletions, truncation.
pub fn mutate_text(rng: &mut Rng, text: &mut Vec<u8>) {
    for _ in 0..1 + rng.below(4) {
        if text.is_empty() {
            return;
        }
        let at = rng.below(text.len());
        match rng.below(4) {
            0 => text[at] = rng.bits() as u8,
            1 => text.insert(at, *rng.pick(b"{}[],:\"\\0123456789e-.")),
            2 => {
                text.remove(at);
            }
            _ => text.truncate(at),
        }
    }
}
