//! Mutations of scene JSON: any value of the tree replaced by numbers at the edges of f32
//! and of the mesh counts (`segments`, `grid`, `lod`), words of the format (kinds, light
//! and environment names), arrays of the wrong length, null, objects; keys deleted, added
//! or grafted from another scene (a water scene's `lod` on a ball); raw byte edits.

use super::mutate_graph::{NAMES, number};
use super::rng::Rng;
use serde_json::{Value as J, json};

/// Counts at and past what a mesh may hold.
const COUNTS: &[f64] = &[
    0.0,
    1.0,
    2.0,
    3.0,
    64.0,
    4096.0,
    4097.0,
    65536.0,
    1e6,
    4294967295.0,
    4294967296.0,
    -1.0,
    1e30,
    0.5,
];

/// Words the scene format uses.
const WORDS: &[&str] = &[
    "ball",
    "plane",
    "water",
    "bubble",
    "sphere",
    "sky",
    "image",
    "directional",
    "point",
    "follow_light",
    "data",
    "srgb",
    "linear",
    "",
    "é",
];

/// Every path (object keys and array indices) of `v`, parents before children.
fn paths(v: &J, at: &mut Vec<J>, out: &mut Vec<Vec<J>>) {
    out.push(at.clone());
    match v {
        J::Object(m) => {
            for (k, child) in m {
                at.push(json!(k));
                paths(child, at, out);
                at.pop();
            }
        }
        J::Array(items) => {
            for (i, child) in items.iter().enumerate() {
                at.push(json!(i));
                paths(child, at, out);
                at.pop();
            }
        }
        _ => {}
    }
}

/// The value at `path` in `v`.
fn at_mut<'a>(v: &'a mut J, path: &[J]) -> Option<&'a mut J> {
    let mut cur = v;
    for step in path {
        cur = match step {
            J::String(k) => cur.as_object_mut()?.get_mut(k)?,
            J::Number(i) => cur.as_array_mut()?.get_mut(i.as_u64()? as usize)?,
            _ => return None,
        };
    }
    Some(cur)
}

/// A replacement value.
fn replacement(rng: &mut Rng, old: &J) -> J {
    match rng.below(10) {
        0 | 1 => json!(*rng.pick(COUNTS)),
        2 | 3 => number(rng),
        4 => json!([*rng.pick(COUNTS), *rng.pick(COUNTS)]),
        5 => J::Array((0..rng.below(5)).map(|_| number(rng)).collect()),
        6 => json!(*rng.pick(WORDS)),
        7 => match old {
            J::Array(items) if !items.is_empty() => J::Array(items[1..].to_vec()),
            J::Object(_) => json!({}),
            _ => J::Null,
        },
        8 => json!(rng.pick(NAMES)),
        _ => json!(rng.one_in(2)),
    }
}

/// Applies one random mutation to scene `doc`; `others` are the other seed scenes (grafts).
pub fn mutate_scene(rng: &mut Rng, doc: &mut J, others: &[J]) {
    let mut all = Vec::new();
    paths(doc, &mut Vec::new(), &mut all);
    let path = rng.pick(&all).clone();
    match rng.below(8) {
        0..=3 => {
            if let Some(v) = at_mut(doc, &path) {
                *v = replacement(rng, v);
            }
        }
        4 => {
            // Delete the key or element.
            if let Some((last, parent)) = path.split_last()
                && let Some(p) = at_mut(doc, parent)
            {
                match (p, last) {
                    (J::Object(m), J::String(k)) => {
                        m.remove(k);
                    }
                    (J::Array(a), J::Number(i)) => {
                        a.remove(i.as_u64().unwrap_or(0) as usize);
                    }
                    _ => {}
                }
            }
        }
        5 => {
            // An unknown key, or a known key at the wrong place.
            if let Some(J::Object(m)) = at_mut(doc, &path) {
                let key = *rng.pick(&["segments", "grid", "lod", "extra", "kind", "time", "é"]);
                m.insert(key.to_owned(), replacement(rng, &J::Null));
            }
        }
        6 if !others.is_empty() => {
            // A subtree of another scene at the same path, or that scene's kind here.
            let other = rng.pick(others).clone();
            let mut from = other.clone();
            let graft = at_mut(&mut from, &path)
                .cloned()
                .unwrap_or(other["kind"].clone());
            if let Some(v) = at_mut(doc, &path) {
                *v = graft;
            }
        }
        _ => {
            // Lights: many, none, or one of each kind with random fields.
            let light = json!({ *rng.pick(&["directional", "point", "spot"]): {
                "direction": [number(rng), number(rng), number(rng)],
                "position": [number(rng), number(rng), number(rng)],
                "color": [1.0, 1.0, 1.0], "intensity": number(rng) } });
            let lights = match rng.below(3) {
                0 => json!([]),
                1 => J::Array(vec![light; 1 + rng.below(40)]),
                _ => json!([light]),
            };
            if let Some(m) = doc.as_object_mut() {
                m.insert("lights".into(), lights);
            }
        }
    }
}
