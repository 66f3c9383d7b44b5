//! Node groups in the editor (issue 35, item 7): Ctrl+G groups the selection into an inline
//! group and one instance, Alt+G ungroups an instance, Tab enters a group (Group Input and
//! Group Output nodes, a breadcrumb) and leaves it, and the side panel edits a group's
//! interface. Grouping and ungrouping leave the graph's values bit for bit (the CPU plan's
//! outputs over the shared sample grid and seeded random samples, before and after); every
//! command is one undo step; refusals say why; the saved file loads.
#![cfg(feature = "editor")]

use crate::common;

use common::parity::grid_batch;
use common::rng::Rng;
use egui::accesskit::Role;
use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::{By, Queryable};
use matgraph::editor::interface;
use matgraph::editor::model::EditorDoc;
use matgraph::editor::outputs::OUTPUT_NODE;
use matgraph::editor::scope::{GROUP_PANEL, INPUT_NODE};
use matgraph::editor::{EditorApp, EditorState};
use matgraph::plan::{Plan, PlanOptions};
use matgraph::types::SocketType;
use matgraph::{Attribute, SampleBatch};
use matgraph::{Graph, GraphDocument, Registry};
use serde_json::json;
use std::path::{Path, PathBuf};

/// A harness without a renderer (logic and accessibility tree only), preview off.
fn harness(mut state: EditorState) -> Harness<'static, EditorApp> {
    state.preview.enabled = false;
    state.dialog = None;
    Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .with_max_steps(64)
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), EditorApp::new(state))
}

/// A fresh folder under the target directory.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("editor_groups")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// 256 seeded random samples: unit normals, views and lights, uv and positions.
fn random_batch() -> SampleBatch {
    let mut rng = Rng(0x67_726f_7570);
    let unit = |rng: &mut Rng| {
        let mut v = [0.0f32; 3];
        for x in &mut v {
            *x = (rng.next() >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0;
        }
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt().max(1e-3);
        [v[0] / l, v[1] / l, v[2] / l]
    };
    let n = 256;
    let (mut nor, mut view, mut light, mut uv, mut pos) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for _ in 0..n {
        nor.push(unit(&mut rng));
        view.push(unit(&mut rng));
        light.push(unit(&mut rng));
        let u = unit(&mut rng);
        uv.push([u[0] * 0.5 + 0.5, u[1] * 0.5 + 0.5, 0.0]);
        pos.push([u[0] * 4.0, u[1] * 4.0, u[2]]);
    }
    let mut batch = SampleBatch::new(n);
    batch.set_values(Attribute::Normal, &nor).unwrap();
    batch.set_values(Attribute::View, &view).unwrap();
    batch.set_values(Attribute::Light, &light).unwrap();
    batch.set_values(Attribute::Uv, &uv).unwrap();
    batch.set_values(Attribute::Position, &pos).unwrap();
    batch.set_time(0.75);
    batch
}

/// Every output of `graph` (by name) over the sample grid and the random samples, as bits.
fn bits(graph: &Graph) -> Vec<(String, Vec<u32>)> {
    let plan = Plan::compile(graph, &PlanOptions::default()).unwrap();
    let mut all = Vec::new();
    for batch in [grid_batch(), random_batch()] {
        let out = plan.execute(&batch, &plan.default_parameters()).unwrap();
        for (k, name) in out.names().iter().enumerate() {
            all.push((
                name.clone(),
                out.planar(k).iter().map(|x| x.to_bits()).collect(),
            ));
        }
    }
    all.sort_by(|a, b| a.0.cmp(&b.0));
    all
}

/// The bits of the editor document `d` (validated).
fn doc_bits(d: &EditorDoc) -> Vec<(String, Vec<u32>)> {
    let g = d
        .graph()
        .unwrap_or_else(|| panic!("not valid: {:?}", d.errors()));
    bits(g)
}

fn state_of(graph: serde_json::Value) -> EditorState {
    let doc: GraphDocument = serde_json::from_value(graph).unwrap();
    let mut s = EditorState::new(doc, None, Registry::builtin());
    s.dialog = None;
    s
}

/// A version-1 graph: geometry → n·v and n·l → Fresnel (Schlick, f0 from an exposed IOR)
/// mixed with a Lambert term into a colour; a float into vec3 and colour ports (broadcast),
/// a colour into a float port (luminance), a generic `mix` and `mul`, a source feeding two
/// nodes, and two graph outputs.
fn shading() -> serde_json::Value {
    json!({
        "version": 1, "name": "shading",
        "nodes": [
            { "id": "geo", "type": "geometry", "position": [0, 0] },
            { "id": "ndv", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.view" } }, "position": [250, 0] },
            { "id": "ndl", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.light" } }, "position": [250, 160] },
            { "id": "ior", "type": "parameter", "inputs": { "value": 1.45 }, "position": [250, 320] },
            { "id": "f0", "type": "ior_to_f0", "inputs": { "ior_inside": { "link": "ior.value" } }, "position": [500, 320] },
            { "id": "fr", "type": "fresnel_schlick", "inputs": { "cos_theta": { "link": "ndv.result" }, "f0": { "link": "f0.f0" } }, "position": [750, 0] },
            { "id": "lam", "type": "saturate", "inputs": { "x": { "link": "ndl.result" } }, "position": [500, 160] },
            { "id": "tint", "type": "mul", "data_type": "color",
              "inputs": { "a": { "link": "lam.result" }, "b": [0.8, 0.5, 0.3] }, "position": [750, 160] },
            { "id": "blend", "type": "mix", "inputs": { "a": { "link": "tint.result" }, "b": { "link": "fr.reflectance" }, "t": { "link": "tint.result" } }, "position": [1000, 80] },
            { "id": "glow", "type": "mul", "inputs": { "a": { "link": "fr.reflectance" }, "b": { "link": "ndv.result" } }, "position": [1000, 260] }
        ],
        "outputs": [
            { "name": "color", "from": "blend.result" },
            { "name": "emission", "from": "glow.result" }
        ],
        "parameters": [ { "name": "ior", "node": "ior", "doc": "Index of refraction." } ]
    })
}

fn shading_doc() -> GraphDocument {
    serde_json::from_value(shading()).unwrap()
}

fn ids(list: &[&str]) -> Vec<String> {
    list.iter().map(|s| s.to_string()).collect()
}

/// Ctrl+G on the middle of the shading graph: one instance in place of the nodes, an
/// interface input per outside source (by the type of the input it feeds), an output per
/// value read outside; the file becomes version 2; the CPU plan's outputs are the same bits;
/// undo and redo are one step each; the saved file loads and is the expected JSON.
#[test]
fn grouping_a_selection_keeps_every_bit_and_is_one_undo_step() {
    let mut s = state_of(shading());
    let before = doc_bits(&s.doc);
    let original = s.doc.doc().clone();
    let inst = s
        .group_selection(&ids(&["fr", "lam", "tint", "f0"]))
        .unwrap();
    assert_eq!(inst, "group");
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    assert_eq!(doc_bits(&s.doc), before, "the same bits after grouping");
    let doc = s.doc.doc();
    assert_eq!(doc.version, 2, "a version-1 file becomes version 2");
    let g = &doc.groups["group"];
    let names = |v: Vec<&str>| v.into_iter().map(str::to_owned).collect::<Vec<_>>();
    // Inputs in node order: f0's ior_inside (the parameter), fr's cos_theta (n·v), lam's x
    // (n·l); each typed by the input it feeds, with its default, ranges and doc.
    assert_eq!(
        g.inputs.iter().map(|i| i.name.clone()).collect::<Vec<_>>(),
        names(vec!["ior_inside", "cos_theta", "x"])
    );
    let ior = &g.inputs[0];
    assert_eq!(ior.ty, "float");
    assert_eq!(ior.default, Some(json!(1.5)));
    assert_eq!(ior.hard_range, Some([0.001, 100.0]));
    assert_eq!(ior.soft_range, Some([1.0, 3.0]));
    assert_eq!(ior.doc, "Index of refraction inside.");
    // Outputs: what is read outside (fr.reflectance by blend and glow, tint.result by blend).
    assert_eq!(
        g.outputs
            .iter()
            .map(|o| (o.name.clone(), o.from.clone()))
            .collect::<Vec<_>>(),
        vec![
            ("reflectance".to_owned(), "fr.reflectance".to_owned()),
            ("result".to_owned(), "tint.result".to_owned())
        ]
    );
    let node = s.doc.node("group").unwrap();
    assert_eq!(node.group.as_deref(), Some("group"));
    assert_eq!(node.inputs["cos_theta"], json!({ "link": "ndv.result" }));
    assert_eq!(node.inputs["ior_inside"], json!({ "link": "ior.value" }));
    assert_eq!(s.doc.link("glow", "a"), Some("group.reflectance"));
    assert_eq!(s.doc.link("blend", "a"), Some("group.result"));
    assert_eq!(s.doc.link("blend", "t"), Some("group.result"));
    // Placed at the centre of the nodes it holds.
    assert_eq!(node.position, Some([625.0, 160.0]));
    // One undo step each way.
    s.undo();
    assert_eq!(s.doc.doc(), &original);
    s.redo();
    assert_eq!(s.doc.node("group").map(|n| n.id.as_str()), Some("group"));
    assert_eq!(doc_bits(&s.doc), before);
    // Saved, it loads with the library's loader and is what the editor holds.
    let dir = scratch("group_save");
    let file = dir.join("shading.json");
    s.save_as(&file).unwrap();
    let loaded = matgraph::io::load_graph(&file, Registry::builtin()).unwrap();
    assert_eq!(bits(&loaded), before);
    let saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    assert_eq!(
        saved["groups"]["group"],
        json!({
            "inputs": [
                { "name": "ior_inside", "type": "float", "default": 1.5, "soft_range": [1.0, 3.0],
                  "hard_range": [0.001, 100.0], "doc": "Index of refraction inside." },
                { "name": "cos_theta", "type": "float", "default": 1.0, "soft_range": [0.0, 1.0],
                  "doc": "Cosine of the angle of incidence (use cosθt from the dense side)." },
                { "name": "x", "type": "float", "soft_range": [-10.0, 10.0], "doc": "Value." }
            ],
            "nodes": [
                { "id": "f0", "type": "ior_to_f0", "inputs": { "ior_inside": { "link": "@in.ior_inside" } }, "position": [500.0, 320.0] },
                { "id": "fr", "type": "fresnel_schlick", "inputs": { "cos_theta": { "link": "@in.cos_theta" }, "f0": { "link": "f0.f0" } }, "position": [750.0, 0.0] },
                { "id": "lam", "type": "saturate", "inputs": { "x": { "link": "@in.x" } }, "position": [500.0, 160.0] },
                { "id": "tint", "type": "mul", "data_type": "color", "inputs": { "a": { "link": "lam.result" }, "b": [0.8, 0.5, 0.3] }, "position": [750.0, 160.0] }
            ],
            "outputs": [
                { "name": "reflectance", "from": "fr.reflectance" },
                { "name": "result", "from": "tint.result" }
            ]
        })
    );
    assert_eq!(
        saved["nodes"][4],
        json!({ "id": "group", "type": "group", "group": "group",
                "inputs": { "cos_theta": { "link": "ndv.result" }, "ior_inside": { "link": "ior.value" }, "x": { "link": "ndl.result" } },
                "position": [625.0, 160.0] })
    );
}

/// Alt+G on the instance just made: the nodes come back (their ids free again, so the
/// same), wired as before, the group removed (no other instance), the same bits; one undo
/// step each way.
#[test]
fn ungrouping_brings_the_nodes_back_with_the_same_bits() {
    let mut s = state_of(shading());
    let before = doc_bits(&s.doc);
    s.group_selection(&ids(&["fr", "lam", "tint", "f0", "glow"]))
        .unwrap();
    assert_eq!(doc_bits(&s.doc), before);
    let grouped = s.doc.doc().clone();
    let back = s.ungroup("group").unwrap();
    assert_eq!(back, ids(&["f0", "fr", "lam", "tint", "glow"]));
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    assert!(s.doc.doc().groups.is_empty(), "the group is removed");
    assert_eq!(doc_bits(&s.doc), before, "the same bits after ungrouping");
    // Wired as before; no reroute was needed (every source's type is its input's).
    assert_eq!(s.doc.link("fr", "cos_theta"), Some("ndv.result"));
    assert_eq!(s.doc.link("f0", "ior_inside"), Some("ior.value"));
    assert_eq!(s.doc.link("blend", "b"), Some("fr.reflectance"));
    assert_eq!(s.doc.doc().outputs[1].from, "glow.result");
    assert!(s.doc.doc().nodes.iter().all(|n| n.node_type != "reroute"));
    // Placed around the instance (the box's centre where it was): where they were.
    for id in &back {
        let was = shading_doc()
            .nodes
            .iter()
            .find(|n| &n.id == id)
            .unwrap()
            .position;
        assert_eq!(s.doc.node(id).unwrap().position, was, "{id}");
    }
    s.undo();
    assert_eq!(s.doc.doc(), &grouped);
    s.redo();
    assert_eq!(doc_bits(&s.doc), before);
}

/// Two instances of one group: ungrouping one keeps the group (the other uses it), the ids
/// of the copies are made unique; the instance passes a literal, a colour into a float input
/// (luminance at the interface) and nothing (the default), so the copies read them through
/// typed reroutes where a direct link would convert differently; bits unchanged.
#[test]
fn ungrouping_one_of_two_instances_keeps_the_group_and_every_conversion() {
    let graph = json!({
        "version": 2, "name": "two",
        "nodes": [
            { "id": "geo", "type": "geometry", "position": [0, 0] },
            { "id": "c", "type": "combine", "inputs": { "x": 0.25, "y": 0.5, "z": 1.0 }, "position": [0, 200] },
            { "id": "a", "type": "group", "group": "shade",
              "inputs": { "k": { "link": "c.color" }, "v": { "link": "geo.view" } }, "position": [300, 0] },
            { "id": "b", "type": "group", "group": "shade", "inputs": { "k": 2.0 }, "position": [300, 200] },
            { "id": "sum", "type": "add", "inputs": { "a": { "link": "a.out" }, "b": { "link": "b.out" } }, "position": [600, 100] }
        ],
        "outputs": [ { "name": "color", "from": "sum.result" }, { "name": "k", "from": "a.k_out" } ],
        "groups": { "shade": {
            "inputs": [
                { "name": "k", "type": "float", "default": 0.5 },
                { "name": "v", "type": "vec3", "default": [0.0, 0.0, 1.0] }
            ],
            "nodes": [
                { "id": "geo", "type": "geometry" },
                { "id": "d", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "@in.v" } } },
                { "id": "m", "type": "mul", "data_type": "vec3", "inputs": { "a": { "link": "@in.k" }, "b": { "link": "@in.v" } } },
                { "id": "s", "type": "add", "inputs": { "a": { "link": "d.result" }, "b": { "link": "@in.k" } } },
                { "id": "o", "type": "mix", "data_type": "vec3", "inputs": { "a": { "link": "m.result" }, "b": { "link": "s.result" }, "t": { "link": "@in.k" } } }
            ],
            "outputs": [ { "name": "out", "from": "o.result" }, { "name": "k_out", "from": "@in.k" } ]
        } }
    });
    let mut s = state_of(graph);
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    let before = doc_bits(&s.doc);
    let made = s.ungroup("a").unwrap();
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    assert_eq!(doc_bits(&s.doc), before, "the same bits");
    assert!(s.doc.doc().groups.contains_key("shade"), "b still uses it");
    // geo is taken: its copy is geo_2; k (colour passed into a float) goes through a float
    // reroute, v (vec3 into vec3) links directly.
    assert!(made.contains(&"geo_2".to_owned()), "{made:?}");
    let k = s
        .doc
        .doc()
        .nodes
        .iter()
        .find(|n| n.node_type == "reroute")
        .expect("a reroute for k")
        .clone();
    assert_eq!(k.data_type.as_deref(), Some("float"));
    assert_eq!(k.inputs["input"], json!({ "link": "c.color" }));
    assert_eq!(s.doc.link("d", "b"), Some("geo.view"));
    assert_eq!(
        s.doc.link("m", "a"),
        Some(format!("{}.output", k.id).as_str())
    );
    assert_eq!(s.doc.doc().outputs[1].from, format!("{}.output", k.id));
    // The other instance, passing a literal and leaving v at its default.
    let made = s.ungroup("b").unwrap();
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    assert_eq!(doc_bits(&s.doc), before, "the same bits");
    assert!(
        s.doc.doc().groups.is_empty(),
        "the last instance removes the group"
    );
    // k (2.0) feeds the vec3 `mul` through a float reroute (broadcast there, as inside the
    // group); the other readers of k and v take the literal directly (their types are k's
    // and v's, and each node infers the type it had).
    assert_eq!(made.len(), 5 + 1, "{made:?}");
    assert_eq!(s.doc.node("s_2").unwrap().inputs["b"], json!(2.0));
    assert_eq!(
        s.doc.node("d_2").unwrap().inputs["b"],
        json!([0.0, 0.0, 1.0])
    );
}

/// Every output of `graph` over the random samples (each image it samples a stand-in
/// gradient), as bits; `None` where the CPU plan cannot run it.
fn try_bits(graph: &Graph) -> Option<Vec<(String, Vec<u32>)>> {
    let plan = Plan::compile(graph, &PlanOptions::default()).ok()?;
    let mut batch = random_batch();
    // Each image the plan samples (files, scene textures): one stand-in gradient.
    let mut set = matgraph::texture::TextureSet::new();
    for key in plan.textures() {
        let image = matgraph::texture::Image::from_fn(32, 16, |x, y| {
            [x as f32 / 31.0, y as f32 / 15.0, 0.5, 1.0]
        });
        let texture = matgraph::texture::Texture::new(image, true).ok()?;
        set.insert(key.clone(), texture).ok()?;
    }
    batch.set_textures(std::sync::Arc::new(set));
    let out = plan.execute(&batch, &plan.default_parameters()).ok()?;
    let mut all: Vec<(String, Vec<u32>)> = out
        .names()
        .iter()
        .enumerate()
        .map(|(k, n)| {
            (
                n.clone(),
                out.planar(k).iter().map(|x| x.to_bits()).collect(),
            )
        })
        .collect();
    all.sort_by(|a, b| a.0.cmp(&b.0));
    Some(all)
}

/// The nodes of `doc` by id (order aside), for comparing a document with its round trip.
fn by_id(
    doc: &GraphDocument,
) -> std::collections::BTreeMap<String, matgraph::document::NodeDocument> {
    doc.nodes
        .iter()
        .map(|n| (n.id.clone(), n.clone()))
        .collect()
}

/// Every bundled graph, 8 seeded selections each (a random node grown along its links to
/// 2–7 nodes, exposed parameters left out): grouped, the CPU plan's outputs are the same
/// bits; ungrouped, again, and where no reroute was needed the document is the original
/// (same nodes, links, positions; outputs, frames). Refusals are counted and must name
/// their reason.
#[test]
fn every_bundled_graph_groups_and_ungroups_to_the_same_bits() {
    let mut rng = Rng(35_07);
    let (mut grouped, mut exact, mut refused) = (0, 0, 0);
    for path in common::bundled_graphs() {
        let mut s = EditorState::open(&path, Registry::builtin()).unwrap();
        s.dialog = None;
        let Some(before) = s.doc.graph().and_then(try_bits) else {
            println!(
                "skipped {}: not valid, or the CPU cannot run it",
                path.display()
            );
            continue;
        };
        let original = s.doc.doc().clone();
        let exposed: Vec<String> = original.parameters.iter().map(|p| p.node.clone()).collect();
        let candidates: Vec<String> = original
            .nodes
            .iter()
            .map(|n| n.id.clone())
            .filter(|id| !exposed.contains(id))
            .collect();
        for _ in 0..8 {
            // A random node, grown along links (either way) to a connected selection.
            let want = 2 + (rng.next() % 6) as usize;
            let mut sel = vec![candidates[(rng.next() % candidates.len() as u64) as usize].clone()];
            for _ in 0..4 * want {
                if sel.len() >= want {
                    break;
                }
                let at = &sel[(rng.next() % sel.len() as u64) as usize];
                let mut near: Vec<String> = Vec::new();
                for n in &original.nodes {
                    for v in n.inputs.values() {
                        let Some(src) = matgraph::editor::model::link_of(v)
                            .and_then(|l| l.split_once('.'))
                            .map(|(s, _)| s.to_owned())
                        else {
                            continue;
                        };
                        if &n.id == at {
                            near.push(src);
                        } else if &src == at {
                            near.push(n.id.clone());
                        }
                    }
                }
                near.retain(|n| candidates.contains(n) && !sel.contains(n));
                if !near.is_empty() {
                    sel.push(near[(rng.next() % near.len() as u64) as usize].clone());
                }
            }
            let name = path.file_name().unwrap().to_string_lossy();
            let inst = match s.group_selection(&sel) {
                Ok(i) => i,
                Err(e) => {
                    assert!(e.starts_with("cannot group: "), "{name} {sel:?}: {e}");
                    refused += 1;
                    continue;
                }
            };
            grouped += 1;
            let after = s.doc.graph().and_then(try_bits);
            assert_eq!(after.as_ref(), Some(&before), "{name}: grouped {sel:?}");
            s.ungroup(&inst).unwrap();
            let back = s.doc.graph().and_then(try_bits);
            assert_eq!(back.as_ref(), Some(&before), "{name}: ungrouped {sel:?}");
            let d = s.doc.doc();
            if d.nodes.len() == original.nodes.len() {
                exact += 1;
                assert_eq!(by_id(d), by_id(&original), "{name}: {sel:?}");
                assert_eq!(d.outputs, original.outputs);
                assert_eq!(d.parameters, original.parameters);
                assert!(d.groups == original.groups, "{name}: the group is removed");
            }
            // Back to the file for the next selection (two undo steps).
            s.undo();
            s.undo();
            assert_eq!(s.doc.doc(), &original, "{name}: undone");
        }
    }
    println!("{grouped} selections grouped ({exact} back exactly), {refused} refused");
    assert!(grouped >= 100, "{grouped} grouped");
}

/// What cannot be grouped is refused with the reason in the status line, the document
/// unchanged and no undo step: nothing selected, the Material Output node, an exposed
/// parameter, a bool input fed from outside (a group's inputs are float, vec2, vec3, vec4
/// or color); Alt+G on a node that is not an instance.
#[test]
fn refusals_say_why_and_change_nothing() {
    let graph = json!({
        "version": 2, "name": "refusals",
        "nodes": [
            { "id": "geo", "type": "geometry", "position": [0, 0] },
            { "id": "ndv", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.view" } }, "position": [250, 0] },
            { "id": "eq", "type": "compare", "inputs": { "a": { "link": "ndv.result" }, "b": 1.0 }, "position": [500, 0] },
            { "id": "pick", "type": "select", "inputs": { "condition": { "link": "eq.equal" }, "if_true": 1.0, "if_false": { "link": "ndv.result" } }, "position": [750, 0] },
            { "id": "ior", "type": "parameter", "inputs": { "value": 1.5 }, "position": [250, 200] },
            { "id": "f0", "type": "ior_to_f0", "inputs": { "ior_inside": { "link": "ior.value" } }, "position": [500, 200] }
        ],
        "outputs": [ { "name": "color", "from": "pick.result" }, { "name": "alpha", "from": "f0.f0" } ],
        "parameters": [ { "name": "ior", "node": "ior" } ]
    });
    let mut s = state_of(graph);
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    let original = s.doc.doc().clone();
    let cases: [(Vec<String>, &str); 4] = [
        (vec![], "nothing selected"),
        (
            ids(&["ndv", OUTPUT_NODE]),
            "the Material Output node is the graph's outputs",
        ),
        (ids(&["ior", "f0"]), "'ior' is the graph's parameter 'ior'"),
        (ids(&["pick"]), "input 'condition' of 'pick' is bool"),
    ];
    for (sel, why) in cases {
        let e = s.group_selection(&sel).unwrap_err();
        assert!(e.contains(why), "{sel:?}: {e}");
        assert_eq!(s.status.as_deref(), Some(e.as_str()));
        assert_eq!(s.doc.doc(), &original);
        assert!(!s.history.can_undo(), "{sel:?}: no undo step");
    }
    // The comparison and the select together: the bool stays inside.
    s.group_selection(&ids(&["eq", "pick"])).unwrap();
    assert_eq!(
        s.doc.doc().groups["group"].inputs.len(),
        1,
        "ndv.result, once"
    );
    let e = s.ungroup("geo").unwrap_err();
    assert!(e.contains("not a group instance"), "{e}");
}

/// Format version 2 with a library: `graph.json` uses `lib/layers.json#scale` (x·k) and an
/// inline group `fres`; written into a fresh folder.
fn library_folder(name: &str) -> PathBuf {
    let dir = scratch(name);
    std::fs::create_dir_all(dir.join("lib")).unwrap();
    let lib = json!({
        "version": 2, "name": "layers", "nodes": [],
        "groups": {
            "scale": {
                "doc": "x times k.",
                "inputs": [
                    { "name": "x", "type": "float", "default": 1.0 },
                    { "name": "k", "type": "float", "default": 2.0, "soft_range": [0.0, 4.0], "doc": "The factor." }
                ],
                "nodes": [ { "id": "m", "type": "mul", "inputs": { "a": { "link": "@in.x" }, "b": { "link": "@in.k" } }, "position": [0, 0] },
                           { "id": "h", "type": "group", "group": "half", "inputs": { "v": { "link": "m.result" } }, "position": [200, 0] } ],
                "outputs": [ { "name": "y", "from": "h.r" } ]
            },
            "half": {
                "inputs": [ { "name": "v", "type": "float" } ],
                "nodes": [ { "id": "q", "type": "mul", "inputs": { "a": { "link": "@in.v" }, "b": 0.5 } } ],
                "outputs": [ { "name": "r", "from": "q.result" } ]
            }
        }
    });
    std::fs::write(dir.join("lib/layers.json"), lib.to_string()).unwrap();
    let graph = json!({
        "version": 2, "name": "graph",
        "nodes": [
            { "id": "geo", "type": "geometry", "position": [0, 0] },
            { "id": "d", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.view" } }, "position": [250, 0] },
            { "id": "inl", "type": "group", "group": "fres", "inputs": { "c": { "link": "d.result" } }, "position": [500, 0] },
            { "id": "lib", "type": "group", "group": "lib/layers.json#scale", "inputs": { "x": { "link": "inl.r" } }, "position": [750, 0] }
        ],
        "outputs": [ { "name": "emission", "from": "lib.y" } ],
        "groups": { "fres": {
            "doc": "Schlick's Fresnel.",
            "inputs": [
                { "name": "c", "type": "float", "default": 1.0 },
                { "name": "f0", "type": "float", "default": 0.04, "soft_range": [0.0, 1.0], "hard_range": [0.0, 1.0] }
            ],
            "nodes": [ { "id": "f", "type": "fresnel_schlick", "position": [0, 0],
                "inputs": { "cos_theta": { "link": "@in.c" }, "f0": { "link": "@in.f0" } } } ],
            "outputs": [ { "name": "r", "from": "f.reflectance" } ]
        } }
    });
    std::fs::write(dir.join("graph.json"), graph.to_string()).unwrap();
    dir
}

fn open(file: &Path) -> EditorState {
    let mut s = EditorState::open(file, Registry::builtin()).unwrap();
    s.dialog = None;
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    s
}

/// Alt+G on an instance of a group of another file copies its nodes in (its own nested
/// group reference rebased to `lib/layers.json#half`), the same bits; the saved file loads.
#[test]
fn a_library_group_ungroups_with_its_references_rebased() {
    let dir = library_folder("lib_ungroup");
    let file = dir.join("graph.json");
    let mut s = open(&file);
    let before = doc_bits(&s.doc);
    let made = s.ungroup("lib").unwrap();
    assert_eq!(made, ids(&["m", "h"]));
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    assert_eq!(doc_bits(&s.doc), before);
    assert_eq!(
        s.doc.node("h").unwrap().group.as_deref(),
        Some("lib/layers.json#half")
    );
    assert_eq!(s.doc.link("m", "a"), Some("inl.r"));
    assert_eq!(
        s.doc.node("m").unwrap().inputs["b"],
        json!(2.0),
        "k's default"
    );
    assert_eq!(s.doc.doc().outputs[0].from, "h.r");
    s.save().unwrap();
    let loaded = matgraph::io::load_graph(&file, Registry::builtin()).unwrap();
    assert_eq!(bits(&loaded), before);
}

/// Tab on a selected instance enters its group: the canvas shows the group's nodes, a Group
/// Input node (an output pin per interface input) and a Group Output node, and a breadcrumb
/// "graph › fres"; Tab leaves. Inside, adding a node and wiring it from the Group Input node
/// and into the Group Output node changes the group's definition (the whole document the
/// preview renders), one undo step each, undone from inside; the saved file loads.
#[test]
fn tab_enters_a_group_and_edits_inside_change_its_definition() {
    let dir = library_folder("enter");
    let file = dir.join("graph.json");
    let mut s = open(&file);
    s.focus = Some("inl".into());
    let top_key = s.root().structure_key();
    let mut h = harness(s);
    h.run();
    // The instance's side panel shows its group's interface.
    h.get_by_label("Group 'fres'");
    // Nothing selected, the instance focused (its title clicked): Tab enters.
    h.key_press(Key::Tab);
    h.run();
    {
        let s = &h.state().state;
        assert_eq!(s.breadcrumb(), ["graph", "fres"]);
        assert_eq!(s.focus.as_deref(), Some(GROUP_PANEL));
        let ids: Vec<&str> = s.snarl.nodes().map(|n| n.id.as_str()).collect();
        assert_eq!(ids, ["f", OUTPUT_NODE, INPUT_NODE]);
        // Wires: @in.c → f.cos_theta, @in.f0 → f.f0, f.reflectance → Group Output.
        assert_eq!(s.snarl.wires().count(), 3);
        assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    }
    h.run_steps(4);
    h.get_by_label("Group Input");
    h.get_by_label("Group Output");
    h.get_by_label("graph");
    // The interface panel (the side panel inside a group).
    h.get_by_label("Group 'fres'");
    h.get_by_label("Inputs (2)");
    // Edits inside: a node, wired from the Group Input node and into a new group output.
    let s = &mut h.state_mut().state;
    let steps = |s: &EditorState| s.history.can_undo();
    assert!(!steps(s));
    let add = s.add_node("add", [200.0, 100.0]).unwrap();
    s.connect(INPUT_NODE, "f0", &add, "a").unwrap();
    s.connect("f", "reflectance", &add, "b").unwrap();
    s.edit_interface(|d| interface::add_output(d, "fres", Some("sum")))
        .unwrap();
    s.connect(&add, "result", OUTPUT_NODE, "sum").unwrap();
    let g = &s.root().doc().groups["fres"];
    assert_eq!(g.nodes.len(), 2);
    assert_eq!(g.nodes[1].inputs["a"], json!({ "link": "@in.f0" }));
    assert_eq!(g.outputs[1].from, format!("{add}.result"));
    assert!(s.root().errors().is_empty(), "{:?}", s.root().errors());
    assert_ne!(
        s.root().structure_key(),
        top_key,
        "the preview's document changed"
    );
    assert_eq!(s.doc.doc().nodes.len(), 2, "the body shows it");
    // A value edited inside.
    s.set_input("f", "cos_theta", json!(0.5), None);
    assert_eq!(s.doc.link("f", "cos_theta"), None);
    assert_eq!(
        s.root().doc().groups["fres"].nodes[0].inputs["cos_theta"],
        json!(0.5)
    );
    // Undone from inside: one step per edit (the value, the output's wire, the output, the
    // two wires, the node).
    for _ in 0..6 {
        s.undo();
    }
    assert_eq!(s.root().doc().groups["fres"].nodes.len(), 1);
    assert_eq!(
        s.doc.doc().nodes.len(),
        1,
        "still inside, the body made again"
    );
    assert!(s.in_group());
    for _ in 0..6 {
        s.redo();
    }
    assert_eq!(s.root().doc().groups["fres"].outputs.len(), 2);
    // Tab leaves (nothing selected inside); the instance has the new output.
    h.run();
    assert!(
        !h.ctx.egui_wants_keyboard_input(),
        "Tab moved no focus to a field"
    );
    h.key_press(Key::Tab);
    h.run();
    let s = &h.state().state;
    assert!(!s.in_group());
    assert_eq!(s.focus.as_deref(), Some("inl"));
    let outs: Vec<String> = s
        .doc
        .ports("inl")
        .unwrap()
        .outputs
        .iter()
        .map(|p| p.name.to_string())
        .collect();
    assert_eq!(outs, ["r", "sum"]);
    h.state_mut().state.save().unwrap();
    matgraph::io::load_graph(&file, Registry::builtin()).unwrap();
}

/// Ctrl+G and Alt+G through the keyboard, and Edit → Enter group; the breadcrumb leaves.
#[test]
fn ctrl_g_and_alt_g_from_the_keyboard() {
    let mut s = state_of(shading());
    s.focus = Some("lam".into());
    let original = s.doc.doc().clone();
    let mut h = harness(s);
    h.run();
    // Nothing selected: Ctrl+G says so.
    h.key_press_modifiers(Modifiers::COMMAND, Key::G);
    h.run();
    assert!(
        h.state()
            .state
            .status
            .as_deref()
            .is_some_and(|m| m.contains("nothing selected")),
        "{:?}",
        h.state().state.status
    );
    // A Shift-click on a node's header (beside its title) selects it; Ctrl+G groups it.
    let settle_start = std::time::Instant::now();
    while !h.state().settled() && settle_start.elapsed().as_secs() < 30 {
        h.step();
    }
    let drawn = h.state().drawn_frames();
    let (_, rect) = drawn.iter().find(|(id, _)| *id == "lam").unwrap();
    let at = h.state().to_screen() * egui::pos2(rect.right() - 8.0, rect.top() + 10.0);
    // (egui-snarl is handed the nodes near the pointer a frame later: super::handoff.)
    h.event(egui::Event::PointerMoved(at));
    h.run_steps(4);
    h.event(egui::Event::ModifiersChanged(Modifiers::SHIFT));
    for pressed in [true, false] {
        h.event(egui::Event::PointerButton {
            pos: at,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: Modifiers::SHIFT,
        });
        h.run_steps(1);
    }
    h.event(egui::Event::ModifiersChanged(Modifiers::NONE));
    h.run();
    assert_eq!(h.state().selected(&h.ctx), ["lam"]);
    h.key_press_modifiers(Modifiers::COMMAND, Key::G);
    h.run();
    let s = &h.state().state;
    assert_eq!(s.doc.doc().groups["group"].nodes.len(), 1, "{:?}", s.status);
    // The new instance is the selection (only it) and the focused node: Tab enters it (the
    // selection inside starts empty), Tab leaves, and the instance is selected again.
    assert_eq!(h.state().selected(&h.ctx), ["group"]);
    assert_eq!(s.focus.as_deref(), Some("group"));
    let view = h.state().to_screen();
    h.key_press(Key::Tab);
    h.run();
    assert_eq!(h.state().state.breadcrumb(), ["shading", "group"]);
    assert!(h.state().selected(&h.ctx).is_empty());
    // Inside, the view is the group's own (framed as a graph opens).
    h.run_steps(8);
    assert_ne!(h.state().to_screen(), view);
    h.key_press(Key::Tab);
    h.run_steps(4);
    // The top's view back as it was.
    assert_eq!(h.state().to_screen(), view);
    assert!(!h.state().state.in_group());
    let s = &h.state().state;
    assert!(s.doc.node("group").is_some());
    assert_eq!(h.state().selected(&h.ctx), ["group"]);
    // Alt+G on the selected instance: its node back, selected.
    h.key_press_modifiers(Modifiers::ALT, Key::G);
    h.run();
    assert!(h.state().state.doc.node("group").is_none());
    assert_eq!(h.state().state.doc.doc().nodes.len(), original.nodes.len());
    assert_eq!(h.state().selected(&h.ctx), ["lam"]);
    // Alt+G with nothing selected acts on the focused instance.
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    h.state_mut().state.selection.clear();
    h.state_mut().state.focus = Some("group".into());
    h.key_press_modifiers(Modifiers::ALT, Key::G);
    h.run();
    assert!(h.state().state.doc.node("group").is_none());
    assert_eq!(h.state().selected(&h.ctx), ["lam"]);
    // Edit → Enter group, for the focused instance.
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    h.state_mut().state.focus = Some("group".into());
    h.run();
    h.get_by_label("Edit").click();
    h.run();
    h.get_by_label("Enter group  (Tab)").click();
    h.run();
    assert_eq!(h.state().state.breadcrumb(), ["shading", "group"]);
    // The breadcrumb's first crumb leaves.
    h.get_by_label("shading").click();
    h.run();
    assert!(!h.state().state.in_group());
}

/// The interface, edited from inside the group (as the side panel does): add, rename,
/// reorder, type, default, ranges, unit, doc of inputs; add, rename, reorder, remove of
/// outputs; remove of inputs. Renames follow on the instance and inside; each edit is one
/// undo step; what the loader refuses (a name taken or malformed, a default outside the hard
/// range, a type the links inside cannot take) is refused with its message and changes
/// nothing; the file saved loads.
#[test]
fn the_interface_is_edited_as_the_loader_checks_it() {
    let dir = library_folder("interface");
    let file = dir.join("graph.json");
    let mut s = open(&file);
    let before = doc_bits(&s.doc);
    s.enter_group("inl").unwrap();
    let g = |s: &EditorState| s.root().doc().groups["fres"].clone();
    let mut steps = 0;
    // An edit applied: one more undo step, the whole document still valid.
    fn ok(s: &EditorState, r: Result<(), String>) -> usize {
        r.unwrap();
        assert!(s.root().errors().is_empty(), "{:?}", s.root().errors());
        1
    }
    // Rename c → cos: the link inside and the instance's entry follow.
    let r = s.edit_interface(|d| interface::rename_input(d, "fres", "c", "cos"));
    steps += ok(&s, r);
    assert_eq!(g(&s).inputs[0].name, "cos");
    assert_eq!(
        g(&s).nodes[0].inputs["cos_theta"],
        json!({ "link": "@in.cos" })
    );
    assert_eq!(
        s.root().node("inl").unwrap().inputs["cos"],
        json!({ "link": "d.result" })
    );
    assert_eq!(
        s.doc.link("f", "cos_theta"),
        Some("@in.cos"),
        "the body follows"
    );
    assert_eq!(doc_bits(s.root()), before, "a rename changes no value");
    // Refused: a taken name, a malformed one.
    for (name, why) in [
        ("f0", "already has an input 'f0'"),
        ("a b", "letters, digits"),
    ] {
        let e = s
            .edit_interface(|d| interface::rename_input(d, "fres", "cos", name))
            .unwrap_err();
        assert!(e.contains(why), "{e}");
        assert_eq!(s.status.as_deref(), Some(e.as_str()));
    }
    // Default outside the hard range [0, 1]: the loader's message; inside: kept.
    let e = s
        .edit_interface(|d| {
            interface::set_input_default(d, "fres", "f0", Some(matgraph::Value::float(1.5)))
        })
        .unwrap_err();
    assert!(e.contains("outside its hard_range"), "{e}");
    let r = s.edit_interface(|d| {
        interface::set_input_default(d, "fres", "f0", Some(matgraph::Value::float(0.08)))
    });
    steps += ok(&s, r);
    assert_eq!(g(&s).inputs[1].default, Some(json!(0.08)));
    // Ranges, unit, doc.
    let r =
        s.edit_interface(|d| interface::set_input_range(d, "fres", "f0", false, Some([0.0, 0.5])));
    steps += ok(&s, r);
    let e = s
        .edit_interface(|d| interface::set_input_range(d, "fres", "f0", true, Some([0.5, 0.1])))
        .unwrap_err();
    assert!(e.contains("min ≤ max"), "{e}");
    let r = s.edit_interface(|d| interface::set_input_range(d, "fres", "f0", true, None));
    steps += ok(&s, r);
    let r = s.edit_interface(|d| interface::set_input_unit(d, "fres", "f0", "1"));
    steps += ok(&s, r);
    let r = s.edit_interface(|d| {
        interface::set_input_doc(d, "fres", "f0", "Reflectance at normal incidence.")
    });
    steps += ok(&s, r);
    let r = s.edit_interface(|d| interface::set_group_doc(d, "fres", "Schlick (1994)."));
    steps += ok(&s, r);
    let i = &g(&s).inputs[1];
    assert_eq!(
        (
            i.soft_range,
            i.hard_range,
            i.unit.as_deref(),
            i.doc.as_str()
        ),
        (
            Some([0.0, 0.5]),
            None,
            Some("1"),
            "Reflectance at normal incidence."
        )
    );
    // Reorder; the instance's pins follow.
    let r = s.edit_interface(|d| interface::move_input(d, "fres", "f0", true));
    steps += ok(&s, r);
    let pins: Vec<String> = s
        .root()
        .ports("inl")
        .unwrap()
        .inputs
        .iter()
        .map(|p| p.name.to_string())
        .collect();
    assert_eq!(pins, ["f0", "cos"]);
    // Type: cos as a vec3 cannot feed fresnel_schlick's float cos_theta (no conversion
    // from vec3 to float): refused; f0 as a colour can (f0 is generic), its default
    // converted.
    let e = s
        .edit_interface(|d| interface::set_input_type(d, "fres", "cos", SocketType::Vec3))
        .unwrap_err();
    assert!(e.contains("cos_theta"), "{e}");
    let r = s.edit_interface(|d| interface::set_input_type(d, "fres", "f0", SocketType::Color));
    steps += ok(&s, r);
    assert_eq!(g(&s).inputs[0].ty, "color");
    assert_eq!(g(&s).inputs[0].default, Some(json!([0.08, 0.08, 0.08])));
    // Inputs added and removed; outputs added, renamed, moved, removed.
    let name = s
        .edit_interface(|d| interface::add_input(d, "fres", None, SocketType::Float))
        .unwrap();
    steps += 1;
    assert_eq!(name, "input");
    let r = s.edit_interface(|d| interface::remove_input(d, "fres", "input"));
    steps += ok(&s, r);
    let out = s
        .edit_interface(|d| interface::add_output(d, "fres", None))
        .unwrap();
    steps += 1;
    assert_eq!(out, "output");
    s.connect("f", "reflectance", OUTPUT_NODE, "output")
        .unwrap();
    steps += 1;
    let r = s.edit_interface(|d| interface::rename_output(d, "fres", "r", "refl"));
    steps += ok(&s, r);
    assert_eq!(
        s.root().node("lib").unwrap().inputs["x"],
        json!({ "link": "inl.refl" })
    );
    let r = s.edit_interface(|d| interface::move_output(d, "fres", "output", true));
    steps += ok(&s, r);
    assert_eq!(g(&s).outputs[0].name, "output");
    let r = s.edit_interface(|d| interface::remove_output(d, "fres", "output"));
    steps += ok(&s, r);
    // Each edit one undo step: undone all, the file's group again.
    let file_doc: GraphDocument =
        serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    for _ in 0..steps {
        assert!(s.history.can_undo());
        s.undo();
    }
    assert!(!s.history.can_undo());
    assert_eq!(s.root().doc().groups, file_doc.groups);
    for _ in 0..steps {
        s.redo();
    }
    assert_eq!(g(&s).outputs.len(), 1);
    assert_eq!(g(&s).doc, "Schlick (1994).");
    s.save().unwrap();
    let loaded = matgraph::io::load_graph(&file, Registry::builtin()).unwrap();
    assert_eq!(loaded.to_json(), std::fs::read_to_string(&file).unwrap());
}

/// A group of another file is entered read-only: its nodes and interface shown, every
/// edit refused with the reason (and no undo step); its own nested group can be entered
/// too, and the breadcrumb leaves.
#[test]
fn a_library_group_is_read_only_inside() {
    let dir = library_folder("read_only");
    let mut s = open(&dir.join("graph.json"));
    s.enter_group("lib").unwrap();
    assert_eq!(s.breadcrumb(), ["graph", "lib/layers.json#scale"]);
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    let ids: Vec<&str> = s.snarl.nodes().map(|n| n.id.as_str()).collect();
    assert_eq!(ids, ["m", "h", OUTPUT_NODE, INPUT_NODE]);
    let why = s.doc.read_only().unwrap().to_owned();
    assert!(
        why.contains("read-only here (open lib/layers.json to edit it)"),
        "{why}"
    );
    assert!(s.add_node("add", [0.0, 0.0]).is_err());
    assert!(s.connect(INPUT_NODE, "k", "m", "a").is_err());
    s.set_input("m", "b", json!(3.0), None);
    assert!(s.group_selection(&ids_of(&["m"])).is_err());
    assert!(s.ungroup("h").is_err());
    assert!(
        s.edit_interface(|d| interface::rename_input(d, "scale", "x", "y"))
            .is_err()
    );
    assert_eq!(s.status.as_deref(), Some(why.as_str()));
    assert!(!s.history.can_undo());
    // Its own group, nested: read-only too.
    s.enter_group("h").unwrap();
    assert_eq!(s.breadcrumb(), ["graph", "lib/layers.json#scale", "half"]);
    assert!(s.doc.read_only().is_some());
    assert_eq!(s.doc.doc().nodes[0].id, "q");
    // Its interface panel shows the library's group.
    let mut h = harness(s);
    h.run_steps(4);
    h.get_by_label("Group 'half'");
    h.get_by_label("read-only");
    // Back to the top through the breadcrumb.
    h.get_by_label("graph").click();
    h.run();
    assert!(!h.state().state.in_group());
}

fn ids_of(list: &[&str]) -> Vec<String> {
    ids(list)
}

/// Replaces the text of the field showing `now` by `text` and presses Enter.
fn type_into(h: &mut Harness<'static, EditorApp>, now: &str, text: &str) {
    let field = || By::new().role(Role::TextInput).value(now);
    h.get(field()).focus();
    h.run();
    h.key_press_modifiers(Modifiers::COMMAND, Key::A);
    h.run();
    h.get(field()).type_text(text);
    h.run();
    h.key_press(Key::Enter);
    h.run();
}

/// The interface panel from its fields and buttons: an input renamed by typing (a bad name
/// refused, the status line says why), an input and an output added; clicking the Group
/// Input node's title shows the panel.
#[test]
fn the_interface_panel_works_from_its_fields_and_buttons() {
    let dir = library_folder("panel");
    let mut s = open(&dir.join("graph.json"));
    s.enter_group("inl").unwrap();
    s.focus = None;
    let mut h = harness(s);
    h.run_steps(4);
    // Nothing focused inside a group: the panel shows the interface.
    h.get_by_label("Inputs (2)");
    type_into(&mut h, "c", "no way");
    assert!(
        h.state()
            .state
            .status
            .as_deref()
            .unwrap()
            .contains("letters, digits"),
        "{:?}",
        h.state().state.status
    );
    type_into(&mut h, "c", "cos");
    let s = &h.state().state;
    assert_eq!(s.root().doc().groups["fres"].inputs[0].name, "cos");
    assert_eq!(
        s.root().node("inl").unwrap().inputs["cos"],
        json!({ "link": "d.result" })
    );
    h.get_by_label("add input").click();
    h.run();
    h.get_by_label("add output").click();
    h.run();
    let g = h.state().state.root().doc().groups["fres"].clone();
    assert_eq!(g.inputs.len(), 3);
    assert_eq!(g.outputs.len(), 2);
    h.get_by_label("Inputs (3)");
    h.get_by_label("output: unconnected");
    // Three steps undone.
    for _ in 0..3 {
        h.state_mut().state.undo();
    }
    h.run();
    assert_eq!(
        h.state().state.root().doc().groups["fres"].inputs[0].name,
        "c"
    );
    // The Group Input node's title focuses the panel.
    h.state_mut().state.focus = Some("f".into());
    h.run();
    // Accessibility rects of canvas widgets are in canvas coordinates.
    let at = h.state().to_screen() * h.get_by_label("Group Input").rect().center();
    click_at(&mut h, at);
    assert_eq!(h.state().state.focus.as_deref(), Some(GROUP_PANEL));
}

/// A click at screen position `pos`.
fn click_at(h: &mut Harness<'static, EditorApp>, pos: egui::Pos2) {
    h.event(egui::Event::PointerMoved(pos));
    h.run();
    for pressed in [true, false] {
        h.event(egui::Event::PointerButton {
            pos,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: Modifiers::default(),
        });
    }
    h.run();
}

/// Steps `h` until the canvas and every preview swatch are settled (at most two minutes).
fn settle(h: &mut Harness<'static, EditorApp>) {
    let start = std::time::Instant::now();
    h.step();
    while !(h.state().state.preview.settled() && h.state().settled())
        && start.elapsed().as_secs() < 120
    {
        std::thread::sleep(std::time::Duration::from_millis(20));
        h.step();
    }
    assert!(
        h.state().state.preview.settled(),
        "the preview did not finish"
    );
}

/// Inside a group the preview shows the whole graph: entering compiles nothing new, an edit
/// inside re-renders it with the group's new definition (a new program), and leaving
/// compiles nothing either.
#[test]
fn the_preview_shows_the_whole_graph_with_the_edits_inside() {
    let dir = library_folder("preview");
    let mut s = open(&dir.join("graph.json"));
    s.preview.enabled = true;
    let mut h = Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .with_max_steps(64)
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), EditorApp::new(s));
    settle(&mut h);
    let compiles = h.state().state.preview.compiles();
    let pixels = h.state().state.preview.pixels().map(<[u8]>::to_vec);
    assert!(pixels.is_some());
    h.state_mut().state.enter_group("inl").unwrap();
    settle(&mut h);
    assert_eq!(
        h.state().state.preview.compiles(),
        compiles,
        "entering changes nothing"
    );
    // f0 = 1: a mirror; the emission changes.
    h.state_mut().state.set_input("f", "f0", json!(1.0), None);
    settle(&mut h);
    assert_eq!(h.state().state.preview.compiles(), compiles + 1);
    let after = h.state().state.preview.pixels().map(<[u8]>::to_vec);
    assert_ne!(after, pixels, "the preview shows the edit inside");
    h.state_mut().state.leave_group();
    settle(&mut h);
    assert_eq!(
        h.state().state.preview.compiles(),
        compiles + 1,
        "leaving changes nothing"
    );
}

/// The Group Input node's pin names are readable: each ends the same gap left of its pin
/// (egui-snarl 0.12 placed the first one apart from the rest, and drew a pin over the end of
/// each name after the first: a one-letter name vanished).
#[test]
fn the_group_input_names_its_pins_in_line() {
    let dir = library_folder("input_labels");
    let mut s = open(&dir.join("graph.json"));
    s.enter_group("inl").unwrap();
    for name in ["gain", "k"] {
        s.edit_interface(|d| interface::add_input(d, "fres", Some(name), SocketType::Float))
            .unwrap();
    }
    let mut h = harness(s);
    h.run_steps(8);
    let rights: Vec<f32> = ["c", "gain", "k"]
        .iter()
        .map(|l| h.get_by_label(l).rect().right())
        .collect();
    for r in &rights {
        assert!((r - rights[0]).abs() < 0.5, "{rights:?}");
    }
}
