//! Mutations of version-2 graphs (node groups): declared groups added, removed and renamed;
//! instances of own groups, of other files' groups (`lib/x.json#NAME`), of whole files and
//! of names that do not resolve; nesting, self-recursion and recursion through files;
//! chains of groups that use the next twice (exponential inlining); interface inputs of
//! every type, default and range; instance inputs set to literals, links and `@in` reads;
//! group outputs renamed and re-targeted; the graph mutations of [`super::mutate_graph`]
//! applied inside group bodies.

use super::mutate_graph::{NAMES, mutate, number, value};
use super::rng::Rng;
use serde_json::{Value as J, json};

/// Group references a case may write: own groups, the library's groups and files, the top
/// file (recursion through files), and references that do not resolve.
fn reference(rng: &mut Rng, doc: &J, libs: &[(String, J)], from_lib: bool) -> String {
    let own: Vec<String> = doc["groups"]
        .as_object()
        .map(|m| m.keys().cloned().collect())
        .unwrap_or_default();
    let up = if from_lib { "../" } else { "" };
    match rng.below(10) {
        0..=3 if !own.is_empty() => rng.pick(&own).clone(),
        0..=5 if !libs.is_empty() => {
            let (path, lib) = rng.pick(libs);
            let names: Vec<String> = lib["groups"]
                .as_object()
                .map(|m| m.keys().cloned().collect())
                .unwrap_or_default();
            let name = if names.is_empty() || rng.one_in(8) {
                rng.pick(NAMES).to_string()
            } else {
                rng.pick(&names).clone()
            };
            format!("{up}{path}#{name}")
        }
        6 if !libs.is_empty() => format!("{up}{}", rng.pick(libs).0),
        7 => format!(
            "{up}{}#{}",
            super::files::TOP,
            own.first().map_or("g", |s| s)
        ),
        8 => format!("{up}{}", super::files::TOP),
        _ => rng
            .pick(&[
                "missing.json#g",
                "../outside.json#g",
                "/abs.json",
                "lib/",
                "#",
                "lib/fresnel.json#",
                "a#b#c",
                "",
                "é.json",
            ])
            .to_string(),
    }
}

/// A random interface input declaration.
fn interface_input(rng: &mut Rng) -> J {
    let name = if rng.one_in(6) {
        rng.pick(NAMES).to_string()
    } else {
        format!("x{}", rng.below(4))
    };
    let ty = *rng.pick(&[
        "float", "float", "vec2", "vec3", "vec4", "color", "int", "bool", "matrix", "",
    ]);
    let mut decl = json!({ "name": name, "type": ty });
    if rng.one_in(2) {
        decl["default"] = match rng.below(4) {
            0 => number(rng),
            1 => J::Array((0..rng.below(5)).map(|_| number(rng)).collect()),
            2 => json!(true),
            _ => json!("linear"),
        };
    }
    for range in ["hard_range", "soft_range"] {
        if rng.one_in(3) {
            decl[range] = match rng.below(4) {
                0 => json!([number(rng), number(rng)]),
                1 => json!([0.0, 1.0]),
                2 => json!([1.0, 0.0]),
                _ => json!([number(rng)]),
            };
        }
    }
    decl
}

/// A small body: a `negate` of the group's first input, or a few random nodes.
fn body(rng: &mut Rng, inputs: &[J]) -> (Vec<J>, Vec<J>) {
    let first = inputs
        .first()
        .and_then(|i| i["name"].as_str())
        .unwrap_or("x")
        .to_owned();
    let nodes = vec![
        json!({ "id": "n", "type": "negate", "inputs": { "x": { "link": format!("@in.{first}") } } }),
    ];
    let outputs =
        vec![json!({ "name": if rng.one_in(8) { "é" } else { "y" }, "from": "n.result" })];
    (nodes, outputs)
}

/// Instance node `id` of group `reference`, its inputs a few random entries.
fn instance(rng: &mut Rng, doc: &J, id: &str, reference: String) -> J {
    let mut inputs = serde_json::Map::new();
    for _ in 0..rng.below(3) {
        let name = if rng.one_in(4) {
            rng.pick(NAMES).to_string()
        } else {
            format!("x{}", rng.below(4))
        };
        let v = match rng.below(4) {
            0 => json!({ "link": format!("@in.x{}", rng.below(3)) }),
            _ => value(rng, doc),
        };
        inputs.insert(name, v);
    }
    json!({ "id": id, "type": "group", "group": reference, "inputs": inputs })
}

/// Declared group `g` of `doc` when it is an object (`IndexMut` panics on other values).
fn group_mut<'a>(doc: &'a mut J, g: &str) -> Option<&'a mut serde_json::Map<String, J>> {
    doc.get_mut("groups")?.get_mut(g)?.as_object_mut()
}

/// Sets declared group `name` of `doc` when `groups` is an object.
fn set_group(doc: &mut J, name: String, group: J) {
    if let Some(m) = doc.get_mut("groups").and_then(J::as_object_mut) {
        m.insert(name, group);
    }
}

/// The names of `doc`'s declared groups.
fn group_names(doc: &J) -> Vec<String> {
    doc["groups"]
        .as_object()
        .map(|m| m.keys().cloned().collect())
        .unwrap_or_default()
}

/// Applies one random group mutation to `doc` (the top graph when `!from_lib`, else a
/// library file); `libs` are the library files by path.
pub fn mutate_groups(rng: &mut Rng, doc: &mut J, libs: &[(String, J)], from_lib: bool) {
    if !doc["groups"].is_object() && !rng.one_in(16) {
        doc["groups"] = json!({});
    }
    let names = group_names(doc);
    match rng.below(16) {
        0 => {
            // A new declared group.
            let inputs: Vec<J> = (0..1 + rng.below(3))
                .map(|_| interface_input(rng))
                .collect();
            let (nodes, outputs) = body(rng, &inputs);
            let name = format!("g{}", rng.below(8));
            set_group(
                doc,
                name,
                json!({ "inputs": inputs, "nodes": nodes, "outputs": outputs }),
            );
        }
        1 | 2 => {
            // An instance at the top, feeding an output.
            let r = reference(rng, doc, libs, from_lib);
            let id = format!("i{}", rng.below(100));
            let node = instance(rng, doc, &id, r);
            if let Some(nodes) = doc["nodes"].as_array_mut() {
                nodes.push(node);
            }
            if !doc["outputs"].is_array() {
                doc["outputs"] = json!([]);
            }
            let from = format!("{id}.{}", if rng.one_in(6) { "zz" } else { "y" });
            if let Some(outs) = doc["outputs"].as_array_mut() {
                outs.push(json!({ "name": format!("o{}", rng.below(5)), "from": from }));
            }
        }
        3 | 4 if !names.is_empty() => {
            // An instance inside a group: nesting, or recursion when it names itself.
            let g = rng.pick(&names).clone();
            let r = if rng.one_in(3) {
                g.clone()
            } else {
                reference(rng, doc, libs, from_lib)
            };
            let id = format!("h{}", rng.below(10));
            let node = instance(rng, doc, &id, r);
            if let Some(nodes) = group_mut(doc, &g)
                .and_then(|m| m.get_mut("nodes"))
                .and_then(J::as_array_mut)
            {
                nodes.push(node);
            }
        }
        5 => {
            // A chain of groups each using the next twice: 2^levels copies once inlined.
            // Up to 2^8 (1 800 nodes), or from 2^20 (past the cap, refused before any
            // copy); the sizes between are graphs of 3 000 to 460 000 nodes that load in
            // time linear in their size (tests/graphs/groups.rs loads 300 000), seconds
            // each, which would only slow the run.
            let levels = if rng.one_in(2) {
                1 + rng.below(8)
            } else {
                20 + rng.below(21)
            };
            let x = json!({ "name": "x", "type": "float" });
            for k in 0..levels {
                let next = format!("d{}", k + 1);
                let group = if k + 1 == levels {
                    json!({ "inputs": [x], "nodes": [
                        { "id": "n", "type": "negate", "inputs": { "x": { "link": "@in.x" } } } ],
                        "outputs": [ { "name": "y", "from": "n.result" } ] })
                } else {
                    json!({ "inputs": [x], "nodes": [
                        { "id": "a", "type": "group", "group": next, "inputs": { "x": { "link": "@in.x" } } },
                        { "id": "b", "type": "group", "group": next, "inputs": { "x": { "link": "a.y" } } } ],
                        "outputs": [ { "name": "y", "from": "b.y" } ] })
                };
                set_group(doc, format!("d{k}"), group);
            }
            if let Some(nodes) = doc["nodes"].as_array_mut() {
                nodes.push(
                    json!({ "id": "dd", "type": "group", "group": "d0", "inputs": { "x": 0.5 } }),
                );
            }
            if let Some(outs) = doc["outputs"].as_array_mut() {
                outs.push(json!({ "name": "color", "from": "dd.y" }));
            }
        }
        6 if !names.is_empty() => {
            // Remove or rename a group: its instances dangle.
            let g = rng.pick(&names).clone();
            if let Some(m) = doc["groups"].as_object_mut() {
                let old = m.remove(&g);
                if rng.one_in(2)
                    && let Some(old) = old
                {
                    m.insert(rng.pick(NAMES).to_string(), old);
                }
            }
        }
        7 if !names.is_empty() => {
            // An interface input changed, added or duplicated.
            let g = rng.pick(&names).clone();
            let decl = interface_input(rng);
            if let Some(inputs) = group_mut(doc, &g)
                .and_then(|m| m.get_mut("inputs"))
                .and_then(J::as_array_mut)
            {
                if !inputs.is_empty() && rng.one_in(2) {
                    let k = rng.below(inputs.len());
                    inputs[k] = decl;
                } else {
                    inputs.push(decl);
                }
            }
        }
        8 if !names.is_empty() => {
            // Group outputs renamed, re-targeted, removed or added.
            let g = rng.pick(&names).clone();
            let from = match rng.below(4) {
                0 => format!("@in.x{}", rng.below(3)),
                1 => "n.result".to_owned(),
                2 => "missing.y".to_owned(),
                _ => rng.pick(NAMES).to_string(),
            };
            if let Some(outs) = group_mut(doc, &g)
                .and_then(|m| m.get_mut("outputs"))
                .and_then(J::as_array_mut)
            {
                match rng.below(3) {
                    0 if !outs.is_empty() => {
                        outs.remove(rng.below(outs.len()));
                    }
                    1 if !outs.is_empty() => {
                        let k = rng.below(outs.len());
                        if let Some(o) = outs[k].as_object_mut() {
                            o.insert("from".into(), json!(from));
                        }
                    }
                    _ => outs.push(json!({ "name": rng.pick(NAMES), "from": from })),
                }
            }
        }
        9 | 10 if !names.is_empty() => {
            // The graph mutations inside a group's body.
            let g = rng.pick(&names).clone();
            let mut group = doc["groups"][&g].clone();
            if group.is_object() {
                mutate(rng, &mut group);
                set_group(doc, g, group);
            }
        }
        11 => {
            // Instance inputs: links to `@in` outside a group, unknown names, wrong types.
            let nodes = doc["nodes"].as_array().map_or(0, Vec::len);
            if nodes > 0 {
                let k = rng.below(nodes);
                if doc["nodes"][k].is_object() {
                    if !doc["nodes"][k]["inputs"].is_object() {
                        doc["nodes"][k]["inputs"] = json!({});
                    }
                    let name = format!("x{}", rng.below(3));
                    doc["nodes"][k]["inputs"][name] = match rng.below(3) {
                        0 => json!({ "link": "@in.x" }),
                        _ => value(rng, &doc.clone()),
                    };
                }
            }
        }
        12 => {
            // The `group` field: missing, not a string, or on a node that is not a group.
            let nodes = doc["nodes"].as_array().map_or(0, Vec::len);
            if nodes > 0 {
                let k = rng.below(nodes);
                if doc["nodes"][k].is_object() {
                    doc["nodes"][k]["group"] = match rng.below(4) {
                        0 => json!(5),
                        1 => json!(["g"]),
                        2 => J::Null,
                        _ => json!(reference(rng, doc, libs, from_lib)),
                    };
                    if rng.one_in(2) {
                        doc["nodes"][k]["type"] = json!("group");
                    }
                }
            }
        }
        13 => {
            doc["version"] = json!(*rng.pick(&[1, 2, 3, 0]));
        }
        14 => {
            // A whole group replaced by something that is not one.
            let g = if names.is_empty() {
                "g0".to_owned()
            } else {
                rng.pick(&names).clone()
            };
            let group = match rng.below(4) {
                0 => json!([]),
                1 => json!({ "nodes": 1 }),
                2 => json!({ "inputs": [], "nodes": [], "outputs": [] }),
                _ => json!({ "extra": true }),
            };
            set_group(doc, g, group);
        }
        _ => mutate(rng, doc),
    }
}
