//! Muting (M), collapsing (H) and framing (Ctrl+J, Alt+P) nodes in the editor (issue 35,
//! item 7), through key presses and clicks as a user gives them: the document each changes,
//! undo, what a save writes, and what a muted node computes on the CPU against the core's
//! rule (each output passes the node's first input of its type, else is zero), with values
//! worked out here.
#![cfg(feature = "editor")]

use crate::common::rng::Rng;
use crate::drive::{
    H, click_button, frame, harness, header, material, node_ids, scratch, screen, select,
};
use egui::{Key, Modifiers, PointerButton};
use egui_kittest::kittest::{By, Queryable};
use matgraph::editor::EditorState;
use matgraph::editor::settings::Settings;
use matgraph::{GraphDocument, Plan, PlanOptions, Registry};
use serde_json::json;

fn muted(h: &H) -> Vec<String> {
    let doc = h.state().state.doc.doc();
    doc.nodes
        .iter()
        .filter(|n| n.muted)
        .map(|n| n.id.clone())
        .collect()
}

fn undo(h: &mut H) {
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
}

fn redo(h: &mut H) {
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    h.run();
}

/// `state` saved to a new file in a scratch folder (its settings kept in that folder too);
/// the file's path.
fn saved_in(name: &str, state: &mut EditorState) -> std::path::PathBuf {
    let dir = scratch(name);
    state.settings = Settings::load(&dir.join("editor.json"));
    let path = dir.join("g.json");
    state.save_as(&path).unwrap();
    state.history.clear();
    path
}

/// The saved file's JSON.
fn file_json(path: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

// ---- M ----

/// M flips each selected node's mute (Blender XORs each one), the header says "muted", one
/// undo step per press; a node's right-click menu mutes too; the save writes `"muted": true`
/// on the muted nodes only (the version raised to 2).
#[test]
fn m_mutes_each_selected_node_undo_restores_and_save_writes_muted() {
    let mut doc = material().doc.doc().clone();
    doc.version = 1;
    let mut s = EditorState::new(doc, None, Registry::builtin());
    s.dialog = None;
    let path = saved_in("mute", &mut s);
    assert_eq!(
        file_json(&path)["version"],
        1,
        "a version-1 graph to start with"
    );
    let mut h = harness(s);
    select(&mut h, &["dot", "add"]);
    h.key_press(Key::M);
    h.run();
    assert_eq!(muted(&h), ["dot", "add"]);
    assert_eq!(
        h.query_all_by_label("muted").count(),
        2,
        "both headers say so"
    );
    select(&mut h, &["dot"]);
    h.key_press(Key::M);
    h.run();
    assert_eq!(muted(&h), ["add"]);
    undo(&mut h);
    assert_eq!(muted(&h), ["dot", "add"]);
    undo(&mut h);
    assert!(muted(&h).is_empty());
    redo(&mut h);
    redo(&mut h);
    assert_eq!(muted(&h), ["add"]);
    // The node's menu: Mute on geometry (not selected: it alone).
    let at = header(&h, "geometry");
    click_button(&mut h, at, PointerButton::Secondary, Modifiers::NONE);
    h.get_by_label("Mute  (M)").click();
    h.run();
    assert_eq!(muted(&h), ["geometry", "add"]);
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run();
    let saved = file_json(&path);
    assert_eq!(saved["version"], 2);
    let flags: std::collections::BTreeMap<String, bool> = saved["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| {
            (
                n["id"].as_str().unwrap().to_owned(),
                n["muted"] == json!(true),
            )
        })
        .collect();
    let expected: std::collections::BTreeMap<String, bool> = [
        ("geometry", true),
        ("dot", false),
        ("fresnel_schlick", false),
        ("add", true),
    ]
    .into_iter()
    .map(|(id, m)| (id.to_owned(), m))
    .collect();
    assert_eq!(flags, expected);
    // The saved file reads back muted.
    let back = GraphDocument::parse(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let back_muted: Vec<&str> = back
        .nodes
        .iter()
        .filter(|n| n.muted)
        .map(|n| n.id.as_str())
        .collect();
    assert_eq!(back_muted, ["geometry", "add"]);
}

/// `x` (a constant) → `m = mul(x, b)` → output `r`; `d = dot(u, v)` of two vec3 literals
/// → output `s`.
fn arithmetic(a: f32, b: f32, u: [f32; 3], v: [f32; 3]) -> EditorState {
    let text = json!({
        "version": 2, "name": "mute",
        "nodes": [
            { "id": "x", "type": "constant", "inputs": { "value": a }, "position": [0, 0] },
            { "id": "m", "type": "mul", "inputs": { "a": { "link": "x.value" }, "b": b },
              "position": [300, 0] },
            { "id": "d", "type": "dot", "inputs": { "a": u, "b": v }, "position": [300, 250] }
        ],
        "outputs": [ { "name": "r", "from": "m.result" }, { "name": "s", "from": "d.result" } ]
    });
    let doc = GraphDocument::parse(&text.to_string()).unwrap();
    let mut s = EditorState::new(doc, None, Registry::builtin());
    s.dialog = None;
    s
}

/// The editor's graph evaluated on the CPU at one sample: outputs `r` and `s`.
fn evaluate(h: &H) -> (f32, f32) {
    let g = h.state().state.doc.graph().expect("the graph is valid");
    let plan = Plan::compile(g, &PlanOptions::default()).unwrap();
    let batch = matgraph::SampleBatch::new(1);
    let out = plan.execute(&batch, &plan.default_parameters()).unwrap();
    let get = |name: &str| out.planar(out.index(name).unwrap())[0];
    (get("r"), get("s"))
}

/// Muting through M changes what the graph computes as the core's rule says: a muted `mul`
/// passes its first input of the output's type (`a`) on, so `r` is exactly `x`; a muted
/// `dot` of two vec3 has no float input for its float output, so `s` is 0. Unmuted, `r` is
/// x·b rounded once to f32 (exact in f64) and `s` the f64 dot product within f32 rounding.
/// At round values and seeded random ones.
#[test]
fn muting_a_multiply_passes_its_first_input_on_and_a_dot_gives_zero_on_the_cpu() {
    let mut rng = Rng(0x35_07);
    let mut cases = vec![(0.5f32, 2.0f32, [1.0f32, 0.0, 0.0], [0.25f32, 1.0, 1.0])];
    for _ in 0..3 {
        let a = rng.f(-4.0, 4.0);
        let b = rng.f(-4.0, 4.0);
        let u = [rng.f(-1.0, 1.0), rng.f(-1.0, 1.0), rng.f(-1.0, 1.0)];
        let v = [rng.f(-1.0, 1.0), rng.f(-1.0, 1.0), rng.f(-1.0, 1.0)];
        cases.push((a, b, u, v));
    }
    for (a, b, u, v) in cases {
        let mut h = harness(arithmetic(a, b, u, v));
        let product = (a as f64 * b as f64) as f32;
        let dot: f64 = (0..3).map(|k| u[k] as f64 * v[k] as f64).sum();
        let (r, s) = evaluate(&h);
        assert_eq!(r, product, "unmuted: x·b ({a} × {b})");
        assert!(
            (s as f64 - dot).abs() <= 1e-6 * (1.0 + dot.abs()),
            "unmuted dot: {s} vs {dot}"
        );
        select(&mut h, &["m", "d"]);
        h.key_press(Key::M);
        h.run();
        assert_eq!(muted(&h), ["m", "d"]);
        let (r, s) = evaluate(&h);
        assert_eq!(r, a, "muted mul passes a = {a} on");
        assert_eq!(s, 0.0, "muted dot: no float input, zero");
        undo(&mut h);
        assert_eq!(evaluate(&h).0, product, "undone");
    }
}

/// The preview re-renders a node muted with M (a new program; other pixels), and again
/// when it is unmuted (the first pixels back).
#[test]
fn the_preview_re_renders_when_a_node_is_muted() {
    let text = json!({
        "version": 2, "name": "mute_preview",
        "nodes": [
            { "id": "c", "type": "constant", "inputs": { "value": [0.8, 0.3, 0.1] }, "position": [0, 0] },
            { "id": "m", "type": "mul", "inputs": { "a": { "link": "c.value" }, "b": [0.25, 0.25, 0.25] },
              "position": [300, 0] }
        ],
        "outputs": [ { "name": "emission", "from": "m.result" } ]
    });
    let doc = GraphDocument::parse(&text.to_string()).unwrap();
    let mut s = EditorState::new(doc, None, Registry::builtin());
    s.dialog = None;
    s.preview.cpu_only = true;
    let mut h = harness(s);
    h.state_mut().state.preview.enabled = true;
    let settle = |h: &mut H| {
        let start = std::time::Instant::now();
        h.step();
        while !h.state().state.preview.settled() && start.elapsed().as_secs() < 120 {
            std::thread::sleep(std::time::Duration::from_millis(20));
            h.step();
        }
        assert!(
            h.state().state.preview.settled(),
            "the preview did not finish"
        );
    };
    settle(&mut h);
    let p = &h.state().state.preview;
    let (compiles, first) = (p.compiles(), p.pixels().unwrap().to_vec());
    select(&mut h, &["m"]);
    h.key_press(Key::M);
    h.run();
    settle(&mut h);
    let p = &h.state().state.preview;
    assert!(p.compiles() > compiles, "a new program");
    assert_ne!(
        p.pixels().unwrap(),
        first.as_slice(),
        "the muted node passes c on: brighter"
    );
    h.key_press(Key::M);
    h.run();
    settle(&mut h);
    assert_eq!(h.state().state.preview.pixels().unwrap(), first.as_slice());
}

// ---- H ----

/// H collapses the selection (Blender's rule: a mixed selection collapses, an all-collapsed
/// one expands); a collapsed node is drawn as its header; undo gives back the collapse
/// state; a save keeps it in the settings file under the graph's path, and the graph
/// opened again comes back collapsed.
#[test]
fn h_collapses_by_blenders_rule_undo_restores_and_a_save_keeps_it() {
    let mut s = material();
    let path = saved_in("collapse", &mut s);
    let store = s.settings.store.clone().unwrap();
    let mut h = harness(s);
    let open_height = frame(&h, "dot").height();
    select(&mut h, &["dot"]);
    h.key_press(Key::H);
    h.run();
    assert!(h.state().state.is_collapsed("dot"));
    assert!(h.state().state.dirty(), "a collapse is an unsaved change");
    let closed = frame(&h, "dot").height();
    assert!(
        closed < 40.0 && open_height > 80.0,
        "{closed} (was {open_height})"
    );
    assert_eq!(
        h.state().state.doc.link("dot", "a"),
        Some("geometry.normal"),
        "wires kept"
    );
    // dot collapsed, geometry not: H collapses both; again: expands both.
    select(&mut h, &["dot", "geometry"]);
    h.key_press(Key::H);
    h.run();
    let collapsed = |h: &H| -> Vec<&str> {
        ["geometry", "dot", "fresnel_schlick", "add"]
            .into_iter()
            .filter(|id| h.state().state.is_collapsed(id))
            .collect()
    };
    assert_eq!(collapsed(&h), ["geometry", "dot"]);
    h.key_press(Key::H);
    h.run();
    assert!(collapsed(&h).is_empty());
    assert!(frame(&h, "dot").height() > 80.0, "drawn whole again");
    undo(&mut h);
    assert_eq!(collapsed(&h), ["geometry", "dot"]);
    undo(&mut h);
    assert_eq!(collapsed(&h), ["dot"]);
    undo(&mut h);
    assert!(collapsed(&h).is_empty());
    assert!(!h.state().state.dirty(), "back to the file");
    redo(&mut h);
    assert_eq!(collapsed(&h), ["dot"]);
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run();
    assert!(!h.state().state.dirty());
    let kept = Settings::load(&store);
    assert_eq!(
        kept.collapsed_of(&path).into_iter().collect::<Vec<_>>(),
        ["dot"]
    );
    // Opened again (as the window does: its settings read from their file).
    let mut again = EditorState::open(&path, Registry::builtin()).unwrap();
    again.dialog = None;
    again.use_settings(Settings::load(&store));
    assert!(again.is_collapsed("dot") && !again.is_collapsed("geometry"));
    let h = harness(again);
    assert!(frame(&h, "dot").height() < 40.0, "drawn collapsed");
}

// ---- Frames ----

/// Ctrl+J puts the selection in a new frame (shown in the side panel), renamed there by
/// typing; undo and redo; the save writes `frames`; a click on the frame's label shows its
/// panel; Alt+P takes nodes out (the frame goes once empty); "Remove frame" keeps the nodes.
#[test]
fn ctrl_j_frames_the_selection_which_is_renamed_saved_and_removed_keeping_its_nodes() {
    let mut s = material();
    let path = saved_in("frames", &mut s);
    let mut h = harness(s);
    select(&mut h, &["geometry", "dot"]);
    h.key_press_modifiers(Modifiers::COMMAND, Key::J);
    h.run();
    let frames = |h: &H| -> Vec<(String, String, Vec<String>)> {
        let doc = h.state().state.doc.doc();
        doc.frames
            .iter()
            .map(|f| (f.id.clone(), f.label.clone(), f.nodes.clone()))
            .collect()
    };
    let two = vec!["geometry".to_owned(), "dot".to_owned()];
    assert_eq!(
        frames(&h),
        [("frame".to_owned(), "Frame".to_owned(), two.clone())]
    );
    assert_eq!(h.state().state.focus.as_deref(), Some("@frame:frame"));
    h.get_by_label("Frame frame");
    // Renamed in the side panel.
    let field = || {
        By::new()
            .role(egui::accesskit::Role::TextInput)
            .value("Frame")
    };
    h.get(field()).focus();
    h.run();
    h.key_press_modifiers(Modifiers::COMMAND, Key::A);
    h.run();
    h.get(field()).type_text("Inputs");
    h.run();
    h.key_press(Key::Enter);
    h.run();
    assert_eq!(frames(&h)[0].1, "Inputs");
    undo(&mut h);
    assert_eq!(frames(&h)[0].1, "Frame");
    redo(&mut h);
    assert_eq!(frames(&h)[0].1, "Inputs");
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run();
    let saved = file_json(&path);
    assert_eq!(saved["version"], 2);
    assert_eq!(
        saved["frames"],
        json!([{ "id": "frame", "label": "Inputs", "nodes": ["geometry", "dot"] }])
    );
    // A click on the label strip, above geometry, shows the frame's panel.
    h.state_mut().state.focus = None;
    h.run();
    let g = frame(&h, "geometry");
    let strip = screen(&h, egui::pos2(g.left() + 20.0, g.top() - 26.0));
    click_button(&mut h, strip, PointerButton::Primary, Modifiers::NONE);
    assert_eq!(h.state().state.focus.as_deref(), Some("@frame:frame"));
    // Alt+P: dot leaves; then geometry, and the empty frame goes.
    select(&mut h, &["dot"]);
    h.key_press_modifiers(Modifiers::ALT, Key::P);
    h.run();
    assert_eq!(frames(&h)[0].2, ["geometry"]);
    select(&mut h, &["geometry"]);
    h.key_press_modifiers(Modifiers::ALT, Key::P);
    h.run();
    assert!(frames(&h).is_empty());
    undo(&mut h);
    assert_eq!(frames(&h)[0].2, ["geometry"]);
    // Remove frame, from its panel: the nodes stay.
    h.state_mut().state.focus = Some("@frame:frame".into());
    h.run();
    h.get_by_label("Remove frame").click();
    h.run();
    assert!(frames(&h).is_empty());
    assert_eq!(node_ids(&h), ["geometry", "dot", "fresnel_schlick", "add"]);
}
