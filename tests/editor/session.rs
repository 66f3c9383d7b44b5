//! The node editor (`src/editor/`), driven through egui_kittest: adding a node through the
//! search, wires checked as they are made, values edited with undo and redo, saving in
//! canonical form, recovery from an autosave, and a headless snapshot of a bundled graph.
#![cfg(feature = "editor")]

use crate::common;

use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use matgraph::Registry;
use matgraph::editor::{EditorApp, EditorState, files, model::EditorDoc, preview, state::Dialog};
use std::path::{Path, PathBuf};

/// The editor on `state`, its nodes framed whole (Home) rather than at 1× on the outputs'
/// end as a graph opens (`editor::first_view`, tests/editor/readable.rs): these tests see
/// (and cull, hand over, snapshot) the whole graph.
fn framed_whole(state: EditorState) -> EditorApp {
    let mut app = EditorApp::new(state);
    app.frame_all();
    app
}

/// A harness without a renderer (logic and accessibility tree only), preview off.
fn harness(mut state: EditorState) -> Harness<'static, EditorApp> {
    state.preview.enabled = false;
    Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        // Overlapping nodes appear one per frame (deterministic stacking).
        .with_max_steps(64)
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), framed_whole(state))
}

fn untitled() -> EditorState {
    let mut s = EditorState::untitled(Registry::builtin());
    // A recovery file another run left in the temporary folder is not this test's.
    s.dialog = None;
    s
}

/// A fresh folder under the target directory.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("editor")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn node_types(s: &EditorState) -> Vec<String> {
    s.doc
        .doc()
        .nodes
        .iter()
        .map(|n| n.node_type.clone())
        .collect()
}

#[test]
fn shift_a_opens_the_search_and_enter_adds_the_best_match() {
    let mut h = harness(untitled());
    h.run();
    h.key_press_modifiers(Modifiers::SHIFT, Key::A);
    h.run();
    assert!(h.state().state.search.is_some(), "Shift+A opens the search");
    h.event(egui::Event::Text("fresnel diel".into()));
    h.run();
    // The best match is listed, with its category.
    h.get_by_label("fresnel_dielectric   (optics)");
    h.key_press(Key::Enter);
    h.run();
    let s = &h.state().state;
    assert!(s.search.is_none(), "the search closes on Enter");
    assert_eq!(node_types(s), ["fresnel_dielectric"]);
    assert_eq!(s.doc.doc().nodes[0].id, "fresnel_dielectric");
    assert!(s.dirty());
}

/// The side panel shows the node just added; once Ctrl+Z removes it, the panel says the
/// node is gone instead of showing its bare id, and Ctrl+Shift+Z (which egui's logical
/// matching once gave to undo) brings it back with its documentation.
#[test]
fn the_side_panel_says_when_its_node_was_undone_away() {
    let mut h = harness(untitled());
    h.run();
    h.key_press_modifiers(Modifiers::SHIFT, Key::A);
    h.run();
    h.event(egui::Event::Text("fresnel diel".into()));
    h.run();
    h.key_press(Key::Enter);
    h.run();
    h.get_by_label("Exact unpolarised Fresnel reflectance of a dielectric.");
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    assert!(node_types(&h.state().state).is_empty(), "undone");
    h.get_by_label(
        "Node 'fresnel_dielectric' is no longer in the graph. Click a node's title to see its documentation.",
    );
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    h.run();
    assert_eq!(node_types(&h.state().state), ["fresnel_dielectric"]);
    h.get_by_label("Exact unpolarised Fresnel reflectance of a dielectric.");
}

#[test]
fn a_click_on_a_result_adds_it_and_escape_closes() {
    let mut h = harness(untitled());
    h.run();
    h.key_press(Key::Tab);
    h.run();
    h.event(egui::Event::Text("geometry".into()));
    h.run();
    h.get_by_label("geometry   (geometry)").click();
    h.run();
    assert_eq!(node_types(&h.state().state), ["geometry"]);
    h.key_press(Key::Tab);
    h.run();
    h.key_press(Key::Escape);
    h.run();
    assert!(h.state().state.search.is_none());
    assert_eq!(node_types(&h.state().state), ["geometry"]);
}

#[test]
fn connecting_a_vec3_into_a_generic_node_infers_its_type() {
    let mut s = untitled();
    s.add_node("geometry", [0.0, 0.0]).unwrap();
    s.add_node("add", [250.0, 0.0]).unwrap();
    assert_eq!(s.doc.generic("add").map(|t| t.name()), Some("float"));
    s.connect("geometry", "normal", "add", "a").unwrap();
    assert_eq!(s.doc.link("add", "a"), Some("geometry.normal"));
    // Re-inferred from the link: T = vec3, and the canvas has the wire.
    assert_eq!(s.doc.generic("add").map(|t| t.name()), Some("vec3"));
    assert_eq!(s.snarl.wires().count(), 1);
    // A float into the other input is broadcast: T stays vec3.
    s.add_node("constant", [0.0, 200.0]).unwrap();
    let out = s.doc.node_type("constant").unwrap().outputs()[0].name;
    s.connect("constant", out, "add", "b").unwrap();
    assert_eq!(s.doc.generic("add").map(|t| t.name()), Some("vec3"));
    let mut h = harness(s);
    h.run();
    h.get_by_label("add");
}

#[test]
fn a_link_with_no_implicit_conversion_is_refused_with_the_loaders_message() {
    let mut s = untitled();
    s.add_node("geometry", [0.0, 0.0]).unwrap();
    s.add_node("fresnel_dielectric", [250.0, 0.0]).unwrap();
    let before = s.doc.doc().clone();
    let err = s
        .connect("geometry", "normal", "fresnel_dielectric", "cos_theta")
        .unwrap_err();
    let expected = "node 'fresnel_dielectric': input 'cos_theta': cannot connect 'geometry.normal' (vec3) \
                    to 'fresnel_dielectric.cos_theta' (float): no implicit conversion";
    assert_eq!(err, expected);
    assert_eq!(s.doc.doc(), &before, "a refused link changes nothing");
    // The message is shown in the editor.
    let mut h = harness(s);
    h.run();
    h.get_by_label(expected);
    // A refused link is no undo step: one undo removes the node added last.
    h.state_mut().state.undo();
    assert_eq!(node_types(&h.state().state), ["geometry"]);
}

#[test]
fn a_link_that_closes_a_cycle_is_refused() {
    let mut s = untitled();
    s.add_node("add", [0.0, 0.0]).unwrap();
    s.add_node("mul", [250.0, 0.0]).unwrap();
    s.connect("add", "result", "mul", "a").unwrap();
    let err = s.connect("mul", "result", "add", "a").unwrap_err();
    assert!(err.starts_with("cycle through nodes "), "{err}");
    assert!(err.contains("add") && err.contains("mul"), "{err}");
    assert_eq!(s.doc.link("add", "a"), None);
}

#[test]
fn a_slider_drag_is_one_undo_step_and_redo_restores_it() {
    let mut s = untitled();
    s.add_node("fresnel_dielectric", [0.0, 0.0]).unwrap();
    // A drag: three values with one key, then released (sealed).
    for v in [1.6, 1.7, 1.8] {
        s.set_input(
            "fresnel_dielectric",
            "ior_inside",
            serde_json::json!(v),
            Some("value:fresnel_dielectric.ior_inside"),
        );
    }
    s.history.seal();
    s.set_input(
        "fresnel_dielectric",
        "ior_outside",
        serde_json::json!(1.33),
        Some("value:fresnel_dielectric.ior_outside"),
    );
    let value = |s: &EditorState, input: &str| {
        s.doc
            .node("fresnel_dielectric")
            .unwrap()
            .inputs
            .get(input)
            .cloned()
    };
    assert_eq!(value(&s, "ior_inside"), Some(serde_json::json!(1.8)));
    s.undo();
    assert_eq!(value(&s, "ior_outside"), None);
    assert_eq!(value(&s, "ior_inside"), Some(serde_json::json!(1.8)));
    s.undo();
    assert_eq!(
        value(&s, "ior_inside"),
        None,
        "the whole drag is undone at once"
    );
    s.undo();
    assert!(s.doc.doc().nodes.is_empty(), "then the node's creation");
    s.redo();
    s.redo();
    assert_eq!(value(&s, "ior_inside"), Some(serde_json::json!(1.8)));
    s.redo();
    assert_eq!(value(&s, "ior_outside"), Some(serde_json::json!(1.33)));
    // Ctrl+Z in the editor undoes too.
    let mut h = harness(s);
    h.run();
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    assert_eq!(value(&h.state().state, "ior_outside"), None);
}

#[test]
fn delete_and_duplicate_keep_links_consistent() {
    let mut s = untitled();
    s.add_node("geometry", [0.0, 0.0]).unwrap();
    s.add_node("dot", [250.0, 0.0]).unwrap();
    s.connect("geometry", "normal", "dot", "a").unwrap();
    let copies = s.duplicate(&["dot".to_owned()]);
    assert_eq!(copies, ["dot_2"]);
    // The copy keeps its link from the node that was not copied, 40 units away.
    assert_eq!(s.doc.link("dot_2", "a"), Some("geometry.normal"));
    assert_eq!(s.doc.node("dot_2").unwrap().position, Some([290.0, 40.0]));
    s.remove_nodes(&["geometry".to_owned()]);
    assert_eq!(s.doc.link("dot", "a"), None);
    assert_eq!(s.doc.link("dot_2", "a"), None);
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
}

#[test]
fn a_saved_graph_is_canonical_and_matches_the_expected_file() {
    let dir = scratch("save");
    let mut s = untitled();
    s.add_node("geometry", [0.0, 0.0]).unwrap();
    s.add_node("dot", [250.0, 0.0]).unwrap();
    s.add_node("fresnel_dielectric", [500.0, 0.0]).unwrap();
    s.connect("geometry", "normal", "dot", "a").unwrap();
    s.connect("geometry", "view", "dot", "b").unwrap();
    s.connect("dot", "result", "fresnel_dielectric", "cos_theta")
        .unwrap();
    s.set_input(
        "fresnel_dielectric",
        "ior_inside",
        serde_json::json!(1.33),
        None,
    );
    s.move_nodes(&[("geometry".to_owned(), [-20.5, 10.25])]);
    let out = dir.join("saved.json");
    s.save_as(&out).unwrap();
    assert!(!s.dirty());
    let text = std::fs::read_to_string(&out).unwrap();
    let expected = std::fs::read_to_string("tests/editor/saved.json").unwrap();
    assert_eq!(text, expected);
    // `matgraph fmt --check` agrees that it is canonical: formatting it changes nothing.
    let g = matgraph::Graph::from_json(&text, Registry::builtin()).unwrap();
    assert_eq!(g.to_json(), text);
}

#[test]
fn an_autosave_is_offered_back_after_a_crash() {
    let dir = scratch("recover");
    let file = dir.join("g.json");
    std::fs::write(
        &file,
        "{\n  \"version\": 1,\n  \"name\": \"g\",\n  \"nodes\": [{ \"id\": \"fr\", \"type\": \"fresnel_dielectric\", \"position\": [0.0, 0.0] }]\n}\n",
    )
    .unwrap();
    {
        let mut s = EditorState::open(&file, Registry::builtin()).unwrap();
        assert!(s.dialog.is_none(), "no recovery file yet");
        s.set_input("fr", "ior_inside", serde_json::json!(2.42), None);
        s.tick(10.0);
        s.tick(10.0 + matgraph::editor::state::AUTOSAVE_AFTER);
        assert!(files::recovery_path(Some(&file)).exists(), "autosaved");
        // Dropped without saving: the crash.
    }
    let s = EditorState::open(&file, Registry::builtin()).unwrap();
    assert!(matches!(s.dialog, Some(Dialog::Recover { .. })));
    let mut h = harness(s);
    h.run();
    h.get_by_label("Recover").click();
    h.run();
    let s = &h.state().state;
    assert!(s.dialog.is_none());
    assert_eq!(
        s.doc.node("fr").unwrap().inputs.get("ior_inside"),
        Some(&serde_json::json!(2.42))
    );
    assert!(s.dirty(), "recovered changes are not saved yet");
    h.state_mut().state.save().unwrap();
    assert!(
        !files::recovery_path(Some(&file)).exists(),
        "a save removes the recovery file"
    );
    assert!(
        std::fs::read_to_string(&file)
            .unwrap()
            .contains("\"ior_inside\": 2.42")
    );
}

#[test]
fn closing_with_unsaved_changes_asks_first() {
    let mut s = untitled();
    s.add_node("geometry", [0.0, 0.0]).unwrap();
    let mut h = harness(s);
    h.run();
    h.input_mut()
        .viewports
        .entry(egui::ViewportId::ROOT)
        .or_default()
        .events
        .push(egui::ViewportEvent::Close);
    h.run();
    assert!(matches!(
        h.state().state.dialog,
        Some(Dialog::Discard { .. })
    ));
    h.get_by_label("Cancel").click();
    h.run();
    assert!(h.state().state.dialog.is_none());
    assert_eq!(node_types(&h.state().state), ["geometry"]);
}

/// The file shortcuts of Blender and most editors: Ctrl+Shift+S asks where to save (the
/// file's own path to start with) and does not save; Ctrl+O asks for a file; Ctrl+N with
/// unsaved changes asks first, then starts an empty graph in the same session: the preview
/// stays as it was (off here; File → New used to turn it back on) and so do the recent
/// files (File → New used to drop them).
#[test]
fn ctrl_shift_s_ctrl_o_and_ctrl_n_ask_as_the_file_menu_does() {
    let dir = scratch("shortcuts");
    let file = dir.join("shortcuts.json");
    std::fs::copy("graphs/pbr_gold.json", &file).unwrap();
    let mut state = EditorState::open(&file, Registry::builtin()).unwrap();
    state.dialog = None;
    state.recent = Some(files::Recent::load(&dir.join("recent.json")));
    state.save_as(&file).unwrap();
    let before = std::fs::read(&file).unwrap();
    let mut h = harness(state);
    h.run();
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::S);
    h.run();
    match &h.state().state.dialog {
        Some(Dialog::SaveAs { path }) => assert_eq!(Path::new(path), file.as_path()),
        other => panic!("Ctrl+Shift+S: {other:?}"),
    }
    assert_eq!(std::fs::read(&file).unwrap(), before, "nothing saved yet");
    h.state_mut().state.dialog = None;
    h.key_press_modifiers(Modifiers::COMMAND, Key::O);
    h.run();
    assert!(
        matches!(h.state().state.dialog, Some(Dialog::Open { .. })),
        "Ctrl+O: {:?}",
        h.state().state.dialog
    );
    h.state_mut().state.dialog = None;
    h.state_mut()
        .state
        .add_node("geometry", [0.0, 0.0])
        .unwrap();
    h.key_press_modifiers(Modifiers::COMMAND, Key::N);
    h.run();
    assert!(
        matches!(h.state().state.dialog, Some(Dialog::Discard { .. })),
        "Ctrl+N with unsaved changes: {:?}",
        h.state().state.dialog
    );
    h.get_by_label("Discard").click();
    h.run();
    let s = &h.state().state;
    assert!(node_types(s).is_empty(), "a new, empty graph");
    assert!(s.path.is_none());
    assert!(!s.preview.enabled, "the preview stays off");
    assert_eq!(
        s.recent.as_ref().map(|r| r.files.clone()),
        Some(vec![file.canonicalize().unwrap()])
    );
    files::discard_recovery(Some(&file));
}

/// Pixels of 1.26 M that an editor snapshot may differ by (beyond egui_kittest's per-pixel
/// threshold). On one machine the snapshots are now the same in every run: 48 runs of both
/// matched with none allowed, 8 of them with both cores kept busy. They were not before:
/// egui-snarl's wires crossed in a random order (73 pixels; `editor::wire_order`), and in
/// `toon_ball` the nodes `spec_band` and `lit`, laid out 4 points apart as the estimate of a
/// generic slider was short, stacked in a random order (113 pixels; the flake of session
/// 15). The slack is for another CPU's lavapipe, whose rounding may move a few pixels of the
/// preview; a wire order or a stacking gone random again (70–140), a moved node or a lost
/// swatch (thousands) still fail.
const SNAPSHOT_SLACK: usize = 20;

/// Whether the GPU snapshot can run here; panics when `MATGRAPH_REQUIRE_GPU` is set and not.
fn gpu_or_skip(test: &str) -> bool {
    if matgraph::editor::headless::adapter_available() {
        return true;
    }
    if std::env::var_os("MATGRAPH_REQUIRE_GPU").is_some() {
        panic!("{test}: MATGRAPH_REQUIRE_GPU is set and there is no GPU adapter");
    }
    println!("SKIPPED {test}: no GPU adapter");
    false
}

#[test]
fn snapshot_of_the_editor_on_pbr_gold() {
    if !gpu_or_skip("snapshot_of_the_editor_on_pbr_gold") {
        return;
    }
    let mut state =
        EditorState::open(Path::new("graphs/pbr_gold.json"), Registry::builtin()).unwrap();
    state.dialog = None;
    state.focus = Some("brdf".into());
    let app = framed_whole(state);
    let mut h = matgraph::editor::headless::harness(app, [1400, 900]);
    h.run_steps(4);
    let start = std::time::Instant::now();
    while !(h.state().state.preview.settled() && h.state().settled())
        && start.elapsed().as_secs() < 120
    {
        std::thread::sleep(std::time::Duration::from_millis(50));
        h.step();
    }
    assert!(
        h.state().state.preview.texture().is_some(),
        "{:?}",
        h.state().state.preview.message()
    );
    h.run_steps(2);
    let options = egui_kittest::SnapshotOptions::new().max_failed_pixels(SNAPSHOT_SLACK);
    h.snapshot_options("editor_pbr_gold", &options);
}

#[test]
fn snapshot_of_the_editor_on_toon_ball_with_node_previews() {
    if !gpu_or_skip("snapshot_of_the_editor_on_toon_ball_with_node_previews") {
        return;
    }
    let mut state =
        EditorState::open(Path::new("graphs/toon_ball.json"), Registry::builtin()).unwrap();
    state.dialog = None;
    state.focus = Some("bands".into());
    // Node swatches on the checker albedo (unlit) and the toon bands (lit: they read N·L).
    state.preview.toggle_node("albedo");
    state.preview.toggle_node("bands");
    // View → Arrange leaves room for the swatches.
    state.arrange();
    // No autosave of that edit beside the bundled file.
    state.unsaved_since = None;
    let app = framed_whole(state);
    let mut h = matgraph::editor::headless::harness(app, [1400, 900]);
    h.run_steps(4);
    let start = std::time::Instant::now();
    while !(h.state().state.preview.settled() && h.state().settled())
        && start.elapsed().as_secs() < 120
    {
        std::thread::sleep(std::time::Duration::from_millis(50));
        h.state_mut().state.unsaved_since = None;
        h.step();
    }
    let p = &h.state().state.preview;
    assert!(p.texture().is_some(), "{:?}", p.message());
    for id in ["albedo", "bands"] {
        assert!(
            p.node_texture(id).is_some(),
            "{id}: {:?}",
            p.node_message(id)
        );
    }
    h.run_steps(2);
    let options = egui_kittest::SnapshotOptions::new().max_failed_pixels(SNAPSHOT_SLACK);
    h.snapshot_options("editor_toon_ball", &options);
}

#[test]
fn a_wire_dropped_in_empty_space_offers_compatible_nodes_and_connects_the_pick() {
    use matgraph::SocketType;
    use matgraph::editor::search::WireFilter;
    use matgraph::editor::search_ui::SearchState;
    let mut s = untitled();
    s.add_node("geometry", [0.0, 0.0]).unwrap();
    // What the canvas does when the wire from geometry.uv (vec2) is dropped at (300, 40).
    s.search = Some(SearchState {
        query: String::new(),
        pos: [300.0, 40.0],
        wire: Some((
            "geometry".into(),
            "uv".into(),
            WireFilter::InputAccepting(SocketType::Vec2),
        )),
        selected: 0,
    });
    let mut h = harness(s);
    h.run();
    h.get_by_label("nodes with an input taking vec2");
    // fresnel_dielectric has only float inputs, which a vec2 cannot feed (src/types.rs).
    h.event(egui::Event::Text("fresnel_dielectric".into()));
    h.run();
    h.get_by_label("no node matches");
    for _ in 0.."fresnel_dielectric".len() {
        h.key_press(Key::Backspace);
    }
    h.event(egui::Event::Text("checker".into()));
    h.run();
    h.key_press(Key::Enter);
    h.run();
    let s = &h.state().state;
    assert_eq!(node_types(s), ["geometry", "checker"]);
    assert_eq!(s.doc.link("checker", "uv"), Some("geometry.uv"));
    assert_eq!(s.doc.node("checker").unwrap().position, Some([300.0, 40.0]));
}

#[test]
fn without_a_display_edit_says_so() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args(["edit", "graphs/toon_ball.json"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("no display") && err.contains("--screenshot"),
        "{err}"
    );
}

#[test]
fn the_code_panel_highlights_the_focused_nodes_wgsl() {
    use matgraph::editor::code::{generate_code, node_lines};
    use matgraph::wgsl::Target;
    let s = EditorState::open(Path::new("graphs/fresnel_glass.json"), Registry::builtin()).unwrap();
    let g = generate_code(s.doc.graph(), Target::Wgsl);
    let text = g.text.as_ref().unwrap();
    let lines = node_lines(text, &g.spans, "exact");
    assert!(!lines.is_empty());
    // The node's lines call its function (fresnel_dielectric's WGSL) and nothing else's.
    let all: Vec<&str> = text.lines().collect();
    assert!(
        lines.iter().any(|&k| all[k].contains("fresnel")),
        "{:?}",
        lines.iter().map(|&k| all[k]).collect::<Vec<_>>()
    );
    for target in [Target::Glsl, Target::Msl, Target::Hlsl] {
        let code = generate_code(s.doc.graph(), target);
        assert!(
            code.text.as_ref().is_ok_and(|t| !t.is_empty()),
            "{target}: {:?}",
            code.text
        );
    }
}

/// A harness without a renderer, preview on (renders on the GPU where there is an adapter,
/// else on the CPU).
fn preview_harness(mut state: EditorState) -> Harness<'static, EditorApp> {
    state.dialog = None;
    state.preview.enabled = true;
    Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .with_max_steps(64)
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), framed_whole(state))
}

/// A primary click at screen position `pos`.
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

#[test]
fn orbiting_rotates_the_camera_about_its_target() {
    use matgraph::editor::preview::Orbit;
    use matgraph::scene::Scene;
    let base = Scene::preset("ball").unwrap().camera;
    // The default orbit is the scene's camera, bit for bit.
    assert_eq!(Orbit::default().camera(&base), base);
    // Yaw θ about +y through the target: x' = x cos θ + z sin θ, z' = −x sin θ + z cos θ
    // (the rotation matrix, in f64), y unchanged; zoom scales the offset.
    let mut rng = common::rng::Rng(0x2545_f491);
    // A uniform f32 in [0, 1) (24 bits: f32-exact).
    let mut next = || (rng.next() >> 40) as f32 / (1u64 << 24) as f32;
    let mut cases = vec![(90.0f32, 1.0f32), (180.0, 1.0), (-45.0, 2.0)];
    for _ in 0..8 {
        cases.push((next() * 720.0 - 360.0, 0.25 + next() * 3.75));
    }
    for (yaw, zoom) in cases {
        let o = Orbit {
            yaw_deg: yaw,
            pitch_deg: 0.0,
            zoom,
        };
        let c = o.camera(&base);
        let (t, p) = (base.target, base.position);
        let (x, y, z) = (
            (p[0] - t[0]) as f64,
            (p[1] - t[1]) as f64,
            (p[2] - t[2]) as f64,
        );
        let th = (yaw as f64).to_radians();
        let k = zoom as f64;
        let want = [
            t[0] as f64 + k * (x * th.cos() + z * th.sin()),
            t[1] as f64 + k * y,
            t[2] as f64 + k * (-x * th.sin() + z * th.cos()),
        ];
        for a in 0..3 {
            assert!(
                (c.position[a] as f64 - want[a]).abs() < 2e-5 * (1.0 + k * 5.1),
                "yaw {yaw} zoom {zoom}: {:?} vs {want:?}",
                c.position
            );
        }
        assert_eq!((c.target, c.fov_y_deg), (base.target, base.fov_y_deg));
    }
    // Pitch raises the elevation by its angle and keeps the distance; it stops at 85°.
    let r = |c: &matgraph::scene::Camera| {
        let d: Vec<f64> = (0..3)
            .map(|a| (c.position[a] - c.target[a]) as f64)
            .collect();
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        (len, (d[1] / len).asin().to_degrees())
    };
    let (r0, e0) = r(&base);
    let (r1, e1) = r(&Orbit {
        pitch_deg: 30.0,
        ..Default::default()
    }
    .camera(&base));
    assert!(
        (r1 - r0).abs() < 1e-5 && (e1 - e0 - 30.0).abs() < 1e-4,
        "{e0} {e1}"
    );
    let (_, e2) = r(&Orbit {
        pitch_deg: 170.0,
        ..Default::default()
    }
    .camera(&base));
    assert!((e2 - 85.0).abs() < 1e-4, "{e2}");
}

/// How many bytes of two swatches' pixels differ.
fn differing_bytes(a: &[u8], b: &[u8]) -> usize {
    a.iter().zip(b).filter(|(a, b)| a != b).count()
}

/// The editor with its preview on a copy of bundled graph `graph` in scratch folder `dir`
/// (so that the autosave of the edits lands there), once the preview settled.
fn settled_copy(dir: &str, graph: &str) -> Harness<'static, EditorApp> {
    let file = scratch(dir).join(graph);
    std::fs::copy(Path::new("graphs").join(graph), &file).unwrap();
    let state = EditorState::open(&file, Registry::builtin()).unwrap();
    let mut h = preview_harness(state);
    settle(&mut h);
    h
}

/// A structure the GPU has not drawn (a new shader to compile) is drawn first on the CPU,
/// once; a structure it has drawn is not. The full swatch replaces the stand-in.
#[test]
fn a_new_structure_is_drawn_first_on_the_cpu() {
    let mut h = settled_copy("stand-in", "pbr_gold.json");
    let (gpu, first) = {
        let p = &h.state().state.preview;
        assert!(p.message().is_none(), "{:?}", p.message());
        (p.backend().starts_with("GPU"), p.pixels().unwrap().to_vec())
    };
    // Opening: the GPU has drawn nothing yet.
    assert_eq!(h.state().state.preview.stand_ins(), gpu as usize);
    // A literal baked into the shader: a new structure.
    h.state_mut()
        .state
        .set_input("brdf", "metallic", serde_json::json!(0.5), None);
    settle(&mut h);
    {
        let p = &h.state().state.preview;
        assert_eq!(p.stand_ins(), 2 * gpu as usize);
        assert!(!p.stand_in_running());
        assert_eq!(p.texture().unwrap().size(), [preview::SIZE as usize; 2]);
        let changed = differing_bytes(&first, p.pixels().unwrap());
        assert!(changed > 1000, "half-metal gold differs: {changed} bytes");
    }
    // Back to the structure the GPU drew: its pipelines are made, no stand-in.
    h.state_mut().state.undo();
    settle(&mut h);
    let p = &h.state().state.preview;
    assert_eq!(p.stand_ins(), 2 * gpu as usize);
    assert_eq!(p.texture().unwrap().size(), [preview::SIZE as usize; 2]);
    assert_eq!(
        p.pixels().unwrap(),
        &first[..],
        "the same graph, the same pixels"
    );
}

#[test]
fn a_parameter_change_re_renders_without_recompiling() {
    let mut h = settled_copy("parameter", "pbr_gold.json");
    // The parameters panel lists the graph's exposed parameter (the canvas has the node
    // and the roughness inputs of brdf, env_spec and env_brdf).
    h.get_by_label("Parameters");
    assert_eq!(h.get_all_by_label("roughness").count(), 5);
    let (compiles, renders, before) = {
        let p = &h.state().state.preview;
        assert!(p.message().is_none(), "{:?}", p.message());
        (p.compiles(), p.renders(), p.pixels().unwrap().to_vec())
    };
    assert_eq!(compiles, 1, "one program for the main swatch");
    // A swatch slower than half a 60 Hz frame (lavapipe, a debug build) drafts the edit
    // first.
    let slow = h.state().state.preview.drafts_next_edit();
    let drafts = h.state().state.preview.drafts();
    matgraph::editor::preview_ui::set_parameter(
        &mut h.state_mut().state,
        "roughness",
        "roughness",
        serde_json::json!(0.9),
    );
    // The first step whose swatch shows the new value: the draft, the full render queued.
    h.step();
    let start = std::time::Instant::now();
    while !h.state().state.preview.current() && start.elapsed().as_secs() < 120 {
        std::thread::sleep(std::time::Duration::from_millis(2));
        h.step();
    }
    {
        let p = &h.state().state.preview;
        assert!(p.current());
        let side = p.texture().unwrap().size();
        match slow {
            true => {
                assert_eq!(side, [preview::DRAFT_SIZE as usize; 2]);
                assert!(!p.settled(), "the full swatch follows the draft");
            }
            false => assert_eq!(side, [preview::SIZE as usize; 2]),
        }
    }
    settle(&mut h);
    {
        let p = &h.state().state.preview;
        assert_eq!(p.drafts(), drafts + slow as usize);
        // A drafting swatch warmed its draft unseen before the edit, and not after it (the
        // edit's draft was drawn at the same orbit and time).
        assert_eq!(p.warmups(), slow as usize);
        assert_eq!(p.texture().unwrap().size(), [preview::SIZE as usize; 2]);
        assert_eq!(
            p.compiles(),
            compiles,
            "a parameter change must not recompile"
        );
        assert_eq!(p.renders(), renders + 1);
        let after = p.pixels().unwrap();
        let changed = differing_bytes(&before, after);
        assert!(
            changed > 1000,
            "a rougher gold ball looks different: {changed} bytes"
        );
    }
    // The document holds the new value (saved with the file, undoable).
    assert_eq!(
        h.state().state.doc.node("roughness").unwrap().inputs["value"],
        serde_json::json!(0.9)
    );
    // Orbiting and time re-render the same program too.
    h.state_mut().state.preview.orbit.yaw_deg = 40.0;
    h.state_mut().state.preview.clock.time = 1.5;
    settle(&mut h);
    assert_eq!(h.state().state.preview.compiles(), compiles);
    // ▶ plays: the time advances with the frames; ⏸ stops it.
    h.get_by_label("▶").click();
    h.run_steps(3);
    assert!(h.state().state.preview.clock.playing);
    let t = h.state().state.preview.clock.time;
    assert!(t > 1.5, "{t}");
    h.get_by_label("⏸").click();
    h.run();
    assert!(!h.state().state.preview.clock.playing);
    settle(&mut h);
    assert_eq!(h.state().state.preview.compiles(), compiles);
    // A structural edit (a literal baked into the shader) rebuilds it.
    h.state_mut()
        .state
        .set_input("brdf", "metallic", serde_json::json!(0.5), None);
    settle(&mut h);
    assert_eq!(h.state().state.preview.compiles(), compiles + 1);
}

#[test]
fn a_node_preview_is_toggled_on_the_node_and_shows_the_graph_cut_there() {
    use matgraph::editor::preview::{CUT_OUTPUT, cut_at};
    let state = EditorState::open(Path::new("graphs/pbr_gold.json"), Registry::builtin()).unwrap();
    // The cut graphs: the brdf reads the light, so its swatch is lit (`color`); N·V
    // does not (unlit).
    let doc = state.doc.doc().clone();
    let lit = cut_at(&doc, "brdf", Registry::builtin()).unwrap();
    assert_eq!(lit.outputs().len(), 1);
    assert_eq!(lit.outputs()[0].name, "color");
    let unlit = cut_at(&doc, "n_dot_v", Registry::builtin()).unwrap();
    assert_eq!(unlit.outputs()[0].name, CUT_OUTPUT);
    assert!(cut_at(&doc, "nope", Registry::builtin()).is_err());

    let mut h = preview_harness(state);
    settle(&mut h);
    assert_eq!(h.state().state.preview.nodes_on().count(), 0);
    // Each node header has a toggle; click the one of the first node (geo, file order).
    let rects: Vec<egui::Rect> = h.get_all_by_label("👁").map(|n| n.rect()).collect();
    assert_eq!(rects.len(), 13, "one toggle per node");
    // Accessibility rects of canvas widgets are in canvas coordinates.
    let pos = h.state().to_screen() * rects[0].center();
    click_at(&mut h, pos);
    let on: Vec<String> = h
        .state()
        .state
        .preview
        .nodes_on()
        .map(str::to_owned)
        .collect();
    assert_eq!(on.len(), 1, "{on:?}");
    settle(&mut h);
    let p = &h.state().state.preview;
    assert!(
        p.node_texture(&on[0]).is_some(),
        "{:?}",
        p.node_message(&on[0])
    );
    // Toggled off again from the state (the node menu does the same).
    let id = on[0].clone();
    h.state_mut().state.preview.toggle_node(&id);
    h.run();
    assert!(h.state().state.preview.node_texture(&id).is_none());
}

#[test]
fn recent_files_are_kept_newest_first_and_open_from_the_menu() {
    use matgraph::editor::files::{RECENT_MAX, Recent};
    let dir = scratch("recent");
    let store = dir.join("config").join("recent.json");
    let mut s = untitled();
    s.recent = Some(Recent::load(&store));
    assert!(s.recent.as_ref().unwrap().files.is_empty());
    s.add_node("geometry", [0.0, 0.0]).unwrap();
    let (a, b) = (dir.join("a.json"), dir.join("b.json"));
    s.save_as(&a).unwrap();
    s.save_as(&b).unwrap();
    s.save_as(&a).unwrap();
    // Newest first, once each, absolute; and on disk.
    let want = vec![a.clone(), b.clone()];
    assert_eq!(s.recent.as_ref().unwrap().files, want);
    assert_eq!(Recent::load(&store).files, want);
    // At most RECENT_MAX.
    let mut r = Recent::load(&dir.join("other.json"));
    for k in 0..RECENT_MAX + 3 {
        r.push(&dir.join(format!("g{k}.json"))).unwrap();
    }
    assert_eq!(r.files.len(), RECENT_MAX);
    assert_eq!(r.files[0], dir.join(format!("g{}.json", RECENT_MAX + 2)));
    // File → Open Recent → b.json opens it.
    s.recent = Some(Recent::load(&store));
    let mut h = harness(s);
    h.run();
    h.get_by_label("File").click();
    h.run();
    h.get_by_label("Open Recent ⏵").click();
    h.run();
    h.get_by_label(b.display().to_string().as_str()).click();
    h.run();
    assert_eq!(h.state().state.path.as_deref(), Some(b.as_path()));
    assert_eq!(
        Recent::load(&store).files[..2],
        [b.clone(), a.clone()],
        "opening puts it first"
    );
}

/// Sets `path`'s modification time `secs` seconds ahead (file systems with coarse times).
fn touch_ahead(path: &Path, secs: u64) {
    let f = std::fs::File::options().write(true).open(path).unwrap();
    f.set_modified(std::time::SystemTime::now() + std::time::Duration::from_secs(secs))
        .unwrap();
}

#[test]
fn a_file_changed_on_disk_is_reloaded_or_asked_about() {
    use matgraph::editor::state::DISK_POLL;
    let dir = scratch("reload");
    let file = dir.join("g.json");
    let mut s = untitled();
    s.add_node("geometry", [0.0, 0.0]).unwrap();
    s.save_as(&file).unwrap();
    let mut now = 10.0;
    assert!(!s.check_disk(now), "unchanged");
    // Another program writes the file: reloaded, no question (nothing unsaved).
    let mut other = untitled();
    other.add_node("geometry", [0.0, 0.0]).unwrap();
    other.add_node("checker", [300.0, 0.0]).unwrap();
    other.save_as(&file).unwrap();
    touch_ahead(&file, 5);
    now += DISK_POLL / 2.0;
    assert!(!s.check_disk(now), "not polled again this soon");
    now += DISK_POLL;
    assert!(s.check_disk(now));
    assert_eq!(node_types(&s), ["geometry", "checker"]);
    assert!(!s.dirty());
    // With unsaved changes it asks; "Keep mine" keeps them.
    s.remove_nodes(&["checker".to_owned()]);
    touch_ahead(&file, 10);
    now += DISK_POLL;
    assert!(!s.check_disk(now));
    assert!(matches!(s.dialog, Some(Dialog::Changed { .. })));
    let mut h = harness(s);
    h.run();
    h.get_by_label("Keep mine").click();
    h.run();
    assert!(h.state().state.dialog.is_none());
    assert_eq!(node_types(&h.state().state), ["geometry"]);
    // Asked once per change: no new question until the file changes again.
    let s = &mut h.state_mut().state;
    assert!(!s.check_disk(now + 2.0 * DISK_POLL) && s.dialog.is_none());
    touch_ahead(&file, 20);
    s.check_disk(now + 4.0 * DISK_POLL);
    assert!(matches!(s.dialog, Some(Dialog::Changed { .. })));
    h.run();
    h.get_by_label("Reload (drop my changes)").click();
    h.run();
    assert_eq!(node_types(&h.state().state), ["geometry", "checker"]);
    assert!(!h.state().state.dirty());
}

#[test]
fn overlapping_nodes_are_arranged_in_columns_by_link_depth() {
    use matgraph::editor::layout::{ROW_GAP, depths, needs_arranging, node_height};
    let registry = Registry::builtin();
    let file = matgraph::editor::files::open(Path::new("graphs/pbr_gold.json")).unwrap();
    // The bundled file has overlapping nodes (its columns are 200 apart; brdf is ~260 wide).
    let sizes =
        |d: &matgraph::GraphDocument| EditorDoc::new(d.clone(), registry).node_sizes().to_vec();
    assert!(needs_arranging(&file, &sizes(&file)));
    let s = EditorState::open(Path::new("graphs/pbr_gold.json"), registry).unwrap();
    let doc = s.doc.doc();
    assert!(
        !needs_arranging(doc, s.doc.node_sizes()),
        "arranged on open"
    );
    assert!(!s.dirty(), "the layout alone does not make the graph dirty");
    assert!(s.status.as_deref().unwrap().contains("arranged"));
    // Longest-path depths of pbr_gold, by hand from its links: geo, roughness 0; brdf,
    // incident, n_dot_v, env_diff 1; radiance, mirror, env_brdf 2; env_spec,
    // spec_multiple 3; spec_single 4; reflection 5.
    let want = [
        ("geo", 0),
        ("roughness", 0),
        ("brdf", 1),
        ("radiance", 2),
        ("incident", 1),
        ("mirror", 2),
        ("n_dot_v", 1),
        ("env_spec", 3),
        ("env_brdf", 2),
        ("env_diff", 1),
        ("spec_single", 4),
        ("spec_multiple", 3),
        ("reflection", 5),
    ];
    let depth = depths(doc);
    let mut column_x = [f32::NAN; 6];
    for (id, d) in want {
        let k = s.doc.index(id).unwrap();
        assert_eq!(depth[k], d, "{id}");
        // One x per column, left to right by depth.
        let [x, _] = doc.nodes[k].position.unwrap();
        if column_x[d].is_nan() {
            column_x[d] = x;
        }
        assert_eq!(x, column_x[d], "{id}");
    }
    assert_eq!(column_x[0], 0.0);
    assert!(
        column_x.windows(2).all(|w| w[0] + 160.0 < w[1]),
        "{column_x:?}"
    );
    // A column stacks its nodes with the gap: the two sources, geo (10 outputs) above
    // roughness (first in file order, same barycentre rule).
    let y = |id: &str| s.doc.node(id).unwrap().position.unwrap()[1];
    let outputs = registry.get("geometry").unwrap().outputs().len();
    assert_eq!(outputs, 10);
    assert_eq!(y("geo"), 0.0);
    assert_eq!(y("roughness"), 30.0 + 18.0 * 10.0 + ROW_GAP);
    assert_eq!(node_height(0, 10), 210.0);
    // View → Arrange on a graph with no positions is one undoable edit.
    let mut u = untitled();
    u.add_node("geometry", [0.0, 0.0]).unwrap();
    u.add_node("dot", [0.0, 0.0]).unwrap();
    u.connect("geometry", "normal", "dot", "a").unwrap();
    u.arrange();
    let [x, y] = u.doc.node("dot").unwrap().position.unwrap();
    assert!(x >= 160.0 + 60.0 && y == 0.0, "{x} {y}");
    assert_eq!(u.doc.node("geometry").unwrap().position, Some([0.0, 0.0]));
    u.undo();
    assert_eq!(u.doc.node("dot").unwrap().position, Some([0.0, 0.0]));
}

#[test]
fn edit_arrange_rewrites_the_file_arranged_and_canonical() {
    let dir = scratch("arrange");
    let file = dir.join("pbr_gold.json");
    std::fs::copy("graphs/pbr_gold.json", &file).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args(["edit", "--arrange"])
        .arg(&file)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&file).unwrap();
    let doc = matgraph::GraphDocument::parse(&text).unwrap();
    let sizes = EditorDoc::new(doc.clone(), Registry::builtin());
    assert!(!matgraph::editor::layout::needs_arranging(
        &doc,
        sizes.node_sizes()
    ));
    let g = matgraph::Graph::from_json(&text, Registry::builtin()).unwrap();
    assert_eq!(g.to_json(), text, "canonical");
}

#[test]
fn the_cpu_fallback_renders_says_so_and_takes_parameters_without_recompiling() {
    let file = scratch("cpu_preview").join("pbr_gold.json");
    std::fs::copy("graphs/pbr_gold.json", &file).unwrap();
    let mut state = EditorState::open(&file, Registry::builtin()).unwrap();
    // What a machine without an adapter gets.
    state.preview.cpu_only = true;
    let mut h = preview_harness(state);
    settle(&mut h);
    let (compiles, before) = {
        let p = &h.state().state.preview;
        assert!(p.message().is_none(), "{:?}", p.message());
        assert_eq!(p.backend(), "CPU");
        (p.compiles(), p.pixels().unwrap().to_vec())
    };
    // The panel drawn after the render arrived names the backend.
    h.run();
    h.get_by_label("CPU");
    matgraph::editor::preview_ui::set_parameter(
        &mut h.state_mut().state,
        "roughness",
        "roughness",
        serde_json::json!(0.9),
    );
    settle(&mut h);
    let p = &h.state().state.preview;
    assert_eq!(p.compiles(), compiles);
    let changed = differing_bytes(&before, p.pixels().unwrap());
    assert!(changed > 1000, "{changed}");
}

/// A graph of `n` nodes in rows of 20, 300 × 220 canvas points apart (the layout leaves
/// them as placed): geometry, then generic `mul`/`add` nodes each reading the one before
/// and, every third, the one eight before (benches/editor.rs's grid).
fn grid_graph(n: usize) -> matgraph::GraphDocument {
    let place = |k: usize| serde_json::json!([(k % 20) as f64 * 300.0, (k / 20) as f64 * 220.0]);
    let mut nodes = vec![serde_json::json!({"id": "n0", "type": "geometry", "position": place(0)})];
    for k in 1..n {
        let a = match k {
            1 => "n0.uv".to_owned(),
            _ => format!("n{}.result", k - 1),
        };
        let b = match k > 8 && k % 3 == 0 {
            true => serde_json::json!({"link": format!("n{}.result", k - 8)}),
            false => serde_json::json!(0.5),
        };
        nodes.push(serde_json::json!({
            "id": format!("n{k}"),
            "type": if k % 2 == 0 { "add" } else { "mul" },
            "inputs": {"a": {"link": a}, "b": b},
            "position": place(k),
        }));
    }
    let doc = serde_json::json!({
        "version": matgraph::FORMAT_VERSION,
        "name": "grid",
        "nodes": nodes,
        "outputs": [{"name": "emission", "from": format!("n{}.result", n - 1)}],
    });
    matgraph::GraphDocument::parse(&doc.to_string()).unwrap()
}

#[test]
fn culling_keeps_the_nodes_near_the_view_and_the_pins_their_wires_need() {
    use egui::{Rect, pos2, vec2};
    use matgraph::editor::cull::{Culling, MARGIN};
    let view = Rect::from_min_max(pos2(0.0, 0.0), pos2(1000.0, 800.0));
    let at = |x: f32, y: f32| Rect::from_min_size(pos2(x, y), vec2(100.0, 100.0));
    let nodes = [
        (0, at(100.0, 100.0)),                // on screen
        (1, at(1000.0 + MARGIN - 50.0, 0.0)), // in the margin
        (2, at(1300.0, 0.0)),                 // 100 past the margin
        (3, at(-2000.0, 0.0)),
        (4, at(5000.0, 5000.0)),
        // An id written twice: drawn in full if either copy is near.
        (5, at(9000.0, 0.0)),
        (5, at(500.0, 500.0)),
    ];
    let wires = [
        (2, 1, 0, 3), // culled 2's output 1 feeds drawn 0: 2 keeps outputs 0–1
        (0, 0, 3, 2), // drawn 0 feeds culled 3's input 2: 3 keeps inputs 0–2
        (2, 0, 3, 0), // between two culled nodes: nothing kept for it
        (4, 9, 9, 9), // an end out of range: ignored
    ];
    let c = Culling::new(view, 6, nodes, wires);
    let shown: Vec<bool> = (0..6).map(|k| !c.is_culled(k)).collect();
    assert_eq!(shown, [true, true, false, false, false, true]);
    // (inputs, outputs) shown of 4 and 3.
    let pins = |k| (c.inputs(k, 4), c.outputs(k, 3));
    assert_eq!(pins(0), (4, 3));
    assert_eq!(pins(2), (0, 2));
    assert_eq!(pins(3), (3, 0));
    assert_eq!(pins(4), (0, 0));
    // Never more pins than the node has; an unknown index is drawn in full.
    assert_eq!(c.outputs(2, 1), 1);
    assert!(!c.is_culled(17));
    assert_eq!(Culling::default().inputs(3, 5), 5);

    // Seeded cases against what culling promises: a node on screen is drawn in full, one
    // farther than MARGIN from the view is culled, and a culled node shows every pin that
    // a wire to a drawn node needs.
    let mut rng = common::rng::Rng(0x5eed_c011);
    let mut next = |n: u64| (rng.next() % n) as usize;
    for case in 0..200 {
        let count = 2 + next(40);
        let nodes: Vec<(usize, Rect)> = (0..count)
            .map(|k| {
                let (x, y) = (next(6000) as f32 - 2500.0, next(5000) as f32 - 2000.0);
                (
                    k,
                    Rect::from_min_size(pos2(x, y), vec2(50.0 + next(300) as f32, 80.0)),
                )
            })
            .collect();
        let wires: Vec<(usize, usize, usize, usize)> = (0..next(80))
            .map(|_| (next(count as u64), next(4), next(count as u64), next(6)))
            .collect();
        let c = Culling::new(view, count, nodes.iter().copied(), wires.iter().copied());
        for &(k, r) in &nodes {
            if r.intersects(view) {
                assert!(
                    !c.is_culled(k),
                    "case {case}: node {k} at {r:?} is on screen"
                );
            }
            if !r.intersects(view.expand(MARGIN)) {
                assert!(c.is_culled(k), "case {case}: node {k} at {r:?} is far");
            }
        }
        for &(a, out, b, inp) in &wires {
            if c.is_culled(b) && !c.is_culled(a) {
                assert!(
                    c.inputs(b, 6) > inp,
                    "case {case}: wire into culled {b}.{inp}"
                );
            }
            if c.is_culled(a) && !c.is_culled(b) {
                assert!(
                    c.outputs(a, 4) > out,
                    "case {case}: wire out of culled {a}.{out}"
                );
            }
        }
    }
}

#[test]
fn overview_wires_join_the_pins_along_a_cubic() {
    use egui::{Rect, Shape, Stroke, pos2};
    use matgraph::editor::layout::{INPUT_ROW, OUTPUT_ROW};
    use matgraph::editor::overview::{Body, wire_segments, wire_shape};
    let body = Body(Rect::from_min_max(pos2(10.0, 20.0), pos2(110.0, 120.0)));
    // Row k's centre: top + (k + ½) · row.
    assert_eq!(body.input(0), pos2(10.0, 20.0 + 0.5 * INPUT_ROW));
    assert_eq!(body.input(2), pos2(10.0, 20.0 + 2.5 * INPUT_ROW));
    assert_eq!(body.output(1), pos2(110.0, 20.0 + 1.5 * OUTPUT_ROW));
    let points = |s: Shape| match s {
        Shape::Path(p) => p.points,
        other => panic!("not a path: {other:?}"),
    };
    // Forward, handles half the run (50 > frame 32): the Bézier's midpoint is
    // (P0 + 3 P1 + 3 P2 + P3) / 8 = ((0 + 150 + 150 + 100) / 8, (0 + 0 + 150 + 50) / 8).
    let p = points(wire_shape(
        pos2(0.0, 0.0),
        pos2(100.0, 50.0),
        32.0,
        4,
        Stroke::NONE,
    ));
    assert_eq!(p.len(), 5);
    assert_eq!((p[0], p[4]), (pos2(0.0, 0.0), pos2(100.0, 50.0)));
    assert!((p[2] - pos2(50.0, 25.0)).length() < 1e-4, "{:?}", p[2]);
    // t = ¼: (27 P0 + 27 P1 + 9 P2 + P3) / 64 with P1 = (50, 0), P2 = (50, 50).
    let quarter = pos2(
        (27.0 * 50.0 + 9.0 * 50.0 + 100.0) / 64.0,
        (9.0 * 50.0 + 50.0) / 64.0,
    );
    assert!(
        (p[1] - quarter).length() < 1e-4,
        "{:?} vs {quarter:?}",
        p[1]
    );
    // Backwards, the handles keep the frame: P1 = (100 + 50, 0), P2 = (0 − 50, 0); the
    // midpoint is (100 + 450 − 150 + 0) / 8 = 50 and loops nowhere below y = 0.
    let p = points(wire_shape(
        pos2(100.0, 0.0),
        pos2(0.0, 0.0),
        32.0,
        2,
        Stroke::NONE,
    ));
    assert_eq!(p, [pos2(100.0, 0.0), pos2(50.0, 0.0), pos2(0.0, 0.0)]);
    // Short runs keep the frame: run 10, handles 32 → P1 = (32, 0), P2 = (10 − 32, 0);
    // midpoint x = (0 + 96 − 66 + 10) / 8 = 5.
    let p = points(wire_shape(
        pos2(0.0, 0.0),
        pos2(10.0, 0.0),
        32.0,
        2,
        Stroke::NONE,
    ));
    assert!((p[1] - pos2(5.0, 0.0)).length() < 1e-5, "{:?}", p[1]);
    // One segment per 12 px of the control polygon (2 × max(run, frame) + rise), 2 to 24.
    let (a, b) = (pos2(0.0, 0.0), pos2(100.0, 60.0));
    assert_eq!(wire_segments(a, b, 32.0, 1.0), 22); // 260 / 12 = 21.7
    assert_eq!(wire_segments(a, b, 32.0, 0.2), 5); // 52 / 12 = 4.3
    assert_eq!(wire_segments(a, b, 32.0, 0.05), 2);
    assert_eq!(wire_segments(a, pos2(900.0, 0.0), 32.0, 1.0), 24);
}

#[test]
fn a_large_graph_draws_an_overview_zoomed_out_and_culls_what_is_off_screen() {
    use matgraph::editor::viewer::LOW_DETAIL_ZOOM;
    let mut state = EditorState::new(grid_graph(300), None, Registry::builtin());
    state.dialog = None;
    let mut h = harness(state);
    h.run();
    assert!(h.state().settled());
    // Framed whole, the canvas is an overview: no node title or pin label is a widget.
    let scale = h.state().to_screen().scaling;
    assert!(scale < LOW_DETAIL_ZOOM, "framed at {scale}");
    for label in ["n5", "n150", "result", "b"] {
        assert!(
            h.query_by_label(label).is_none(),
            "{label} is a widget at {scale}×"
        );
    }
    // Zoomed in to 1× about the canvas' centre: the nodes there are drawn in full (title,
    // pin labels, value editors); those far off screen are empty frames.
    let centre = egui::pos2(500.0, 450.0);
    h.input_mut().events.push(egui::Event::PointerMoved(centre));
    h.input_mut().events.push(egui::Event::Zoom(1.0 / scale));
    h.run();
    let t = h.state().to_screen();
    assert!((t.scaling - 1.0).abs() < 1e-3, "zoomed to {}", t.scaling);
    let on_screen = |k: usize| {
        let p = t * egui::pos2((k % 20) as f32 * 300.0, (k / 20) as f32 * 220.0);
        (0.0..900.0).contains(&p.x) && (40.0..800.0).contains(&p.y)
    };
    let near: Vec<usize> = (0..300).filter(|&k| on_screen(k)).collect();
    assert!((4..40).contains(&near.len()), "{near:?}");
    for &k in &near {
        assert!(
            h.query_by_label(&format!("n{k}")).is_some(),
            "n{k} is on screen"
        );
    }
    assert!(h.query_all_by_label("result").count() >= near.len());
    for k in [0, 19, 280, 299] {
        assert!(!on_screen(k));
        assert!(
            h.query_by_label(&format!("n{k}")).is_none(),
            "n{k} is far off screen"
        );
    }
}

#[test]
fn a_partial_canvas_keeps_the_node_ids_and_the_wires_between_kept_nodes() {
    use egui_snarl::{InPinId, NodeId, OutPinId, Snarl};
    use matgraph::editor::handoff::{partial, write_back};
    use matgraph::editor::view::NodeView;
    let mut full = Snarl::new();
    for k in 0..7 {
        let id = full.insert_node(
            egui::pos2(k as f32 * 10.0, 1.0),
            NodeView {
                id: format!("n{k}"),
            },
        );
        assert_eq!(id, NodeId(k));
    }
    // A node removed by an edit leaves a hole in the ids.
    full.remove_node(NodeId(2));
    let wire = |a: usize, o: usize, b: usize, i: usize| {
        (
            OutPinId {
                node: NodeId(a),
                output: o,
            },
            InPinId {
                node: NodeId(b),
                input: i,
            },
        )
    };
    let wires = [
        wire(0, 0, 1, 0),
        wire(1, 0, 3, 1),
        wire(3, 0, 4, 0),
        wire(4, 1, 6, 2),
        wire(0, 0, 5, 0),
    ];
    for (from, to) in wires {
        full.connect(from, to);
    }
    let keep = [true, false, false, true, true, false, true];
    let mut part = partial(&full, &keep).expect("ids line up");
    let ids: Vec<(usize, String)> = part.node_ids().map(|(n, v)| (n.0, v.id.clone())).collect();
    assert_eq!(
        ids,
        [
            (0, "n0".into()),
            (3, "n3".into()),
            (4, "n4".into()),
            (6, "n6".into())
        ]
    );
    let mut got: Vec<_> = part.wires().collect();
    got.sort_by_key(|(f, t)| (f.node.0, t.node.0));
    assert_eq!(got, [wire(3, 0, 4, 0), wire(4, 1, 6, 2)]);
    // Moves made on the partial canvas reach the whole one; the others stay.
    part.get_node_info_mut(NodeId(3)).unwrap().pos = egui::pos2(-5.0, 7.0);
    write_back(&mut full, &part);
    assert_eq!(
        full.get_node_info(NodeId(3)).unwrap().pos,
        egui::pos2(-5.0, 7.0)
    );
    assert_eq!(
        full.get_node_info(NodeId(1)).unwrap().pos,
        egui::pos2(10.0, 1.0)
    );
    assert_eq!(full.wires().count(), 5);
}

#[test]
fn the_predicted_zoom_keeps_the_point_under_the_pointer_and_the_zoom_range() {
    use egui::emath::TSTransform;
    use matgraph::editor::handoff::{ZOOM_RANGE, predict};
    let canvas = egui::Rect::from_min_size(egui::pos2(0.0, 30.0), egui::vec2(1000.0, 800.0));
    let mut rng = fastrand_like(0x5eed);
    for case in 0..200 {
        let scale = 0.2 + 1.8 * rng();
        let last = TSTransform::new(
            egui::vec2(rng() * 400.0 - 200.0, rng() * 400.0 - 200.0),
            scale,
        );
        let zoom = if case % 4 == 0 {
            1.0
        } else {
            0.25 + 2.0 * rng()
        };
        let scroll = egui::vec2(rng() * 60.0 - 30.0, rng() * 60.0 - 30.0);
        let pointer = egui::pos2(rng() * 1000.0, 30.0 + rng() * 800.0);
        let t = predict(last, zoom, scroll, Some(pointer), canvas);
        // Closed form: the scale is the last one times the zoom, within egui-snarl's range;
        // the canvas point under the pointer stays under it, then the view moves by the scroll.
        let expect = (scale as f64 * zoom as f64).clamp(ZOOM_RANGE.0 as f64, ZOOM_RANGE.1 as f64);
        assert!(
            (t.scaling as f64 - expect).abs() < 1e-5 * expect,
            "case {case}: {} vs {expect}",
            t.scaling
        );
        let under = last.inverse() * pointer;
        let now = t * under;
        assert!(
            (now - (pointer + scroll)).length() < 2e-2,
            "case {case}: {now:?} vs {:?}",
            pointer + scroll
        );
        // Off the canvas nothing moves.
        let outside = egui::pos2(1100.0, 400.0);
        assert_eq!(predict(last, zoom, scroll, Some(outside), canvas), last);
    }
}

/// A seeded uniform [0, 1) generator (xorshift64*), f32-exact outputs.
fn fastrand_like(seed: u64) -> impl FnMut() -> f32 {
    let mut s = seed;
    move || {
        s ^= s >> 12;
        s ^= s << 25;
        s ^= s >> 27;
        let v = s.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (v >> 40) as f32 / (1u64 << 24) as f32
    }
}

#[test]
fn the_overview_hands_egui_snarl_few_nodes_and_keeps_a_selection_among_stand_ins() {
    let mut state = EditorState::new(grid_graph(300), None, Registry::builtin());
    state.dialog = None;
    let mut h = harness(state);
    h.run();
    let t = h.state().to_screen();
    // The pointer on node n45 (row 2, column 5): a few nodes near it are handed over, the
    // rest painted as stand-ins.
    let p = t * egui::pos2(5.0 * 300.0 + 60.0, 2.0 * 220.0 + 40.0);
    h.input_mut().events.push(egui::Event::PointerMoved(p));
    h.run_steps(6);
    let handed = h.state().handed().expect("a partial canvas");
    assert!((1..20).contains(&handed), "{handed} handed");
    // Shift-click selects it; with the pointer far away it stays selected (egui-snarl drops
    // selected nodes missing from its graph, so a selected node is always handed over).
    h.input_mut()
        .events
        .push(egui::Event::ModifiersChanged(Modifiers::SHIFT));
    for pressed in [true, false] {
        h.input_mut().events.push(egui::Event::PointerButton {
            pos: p,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: Modifiers::SHIFT,
        });
        h.run_steps(1);
    }
    h.input_mut()
        .events
        .push(egui::Event::ModifiersChanged(Modifiers::NONE));
    let away = t * egui::pos2(15.0 * 300.0, 12.0 * 220.0);
    h.input_mut().events.push(egui::Event::PointerMoved(away));
    h.run_steps(6);
    assert!(h.state().handed().is_some_and(|k| k < 20));
    assert_eq!(h.state().selected(&h.ctx), ["n45"]);
}

/// Every bundled graph draws each node within its estimated rect and the reveal's margin
/// (`editor::layout::node_size`, `editor::view::REVEAL_MARGIN`), as it opens. egui-snarl
/// stacks the nodes shown in one frame in a random order, so `editor::view::reveal_until`
/// shows at once only nodes whose estimated rects (with the margin and the frame's shadow)
/// are apart; a node drawn beyond its estimate could reach another shown with it, and the
/// canvas look different from run to run. Before the estimate followed a generic port's
/// inferred type, `toon_ball`'s `spec_band` (a step whose float `edge` is a slider) was
/// drawn 50 points wider than estimated, 4 points from `lit`, and the editor's screenshot
/// changed from run to run at 113 pixels.
#[test]
fn bundled_graphs_draw_each_node_within_its_estimated_rect() {
    use matgraph::editor::view::REVEAL_MARGIN;
    let mut files: Vec<PathBuf> = std::fs::read_dir("graphs")
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    assert!(files.len() >= 20, "{files:?}");
    let (mut checked, mut beyond) = (0, Vec::new());
    for file in files {
        let mut state = EditorState::open(&file, Registry::builtin()).unwrap();
        state.dialog = None;
        let n = state.doc.doc().nodes.len();
        // Wider than `harness`: the Material Output node, right of the rightmost node,
        // widens the framed canvas, and at 1400 points bubble_iridescent was framed at
        // 0.295×, in the overview (under 0.3×), where nodes are not drawn in full.
        state.preview.enabled = false;
        let mut h = Harness::builder()
            .with_size(egui::vec2(1700.0, 900.0))
            .with_max_steps(64)
            .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), framed_whole(state));
        let start = std::time::Instant::now();
        h.step();
        while !h.state().settled() && start.elapsed().as_secs() < 60 {
            h.step();
        }
        h.step();
        let app = h.state();
        let frames = app.drawn_frames();
        assert_eq!(frames.len(), n, "{}: every node drawn", file.display());
        for (id, drawn) in frames {
            let doc = &app.state.doc;
            let k = doc.index(id).unwrap();
            let [x, y] = doc.doc().nodes[k].position.unwrap();
            let (w, h) = doc.node_sizes()[k];
            let estimate = egui::Rect::from_min_size(egui::pos2(x, y), egui::vec2(w, h));
            if !estimate.expand(REVEAL_MARGIN).contains_rect(drawn) {
                beyond.push(format!(
                    "{}: {id} drawn at {drawn:?}, estimated {estimate:?}",
                    file.display()
                ));
            }
            checked += 1;
        }
    }
    assert!(beyond.is_empty(), "{}", beyond.join("\n"));
    assert!(checked > 300, "{checked} nodes");
}

/// The editor draws a graph alike however egui-snarl's hash sets are seeded: two editors on
/// one graph in one process, where each canvas' wire set gets its own seed, render to the
/// same bytes; `pbr_gold` (whose wires from `geo` cross) at full detail, and a 300-node
/// grid framed whole, in the overview (whose wires the editor paints). Before
/// `editor::wire_order` the first differed where anti-aliased wires cross (94–203 bytes in
/// three runs).
#[test]
fn two_editors_on_one_graph_render_the_same_pixels() {
    if !gpu_or_skip("two_editors_on_one_graph_render_the_same_pixels") {
        return;
    }
    let render = |state: fn() -> EditorState| {
        let mut state = state();
        state.dialog = None;
        state.preview.enabled = false;
        let mut h = matgraph::editor::headless::harness(framed_whole(state), [1400, 900]);
        h.run_steps(4);
        while !h.state().settled() {
            h.step();
        }
        h.run_steps(2);
        (h.state().to_screen().scaling, h.render().unwrap())
    };
    let pbr_gold =
        || EditorState::open(Path::new("graphs/pbr_gold.json"), Registry::builtin()).unwrap();
    let grid = || EditorState::new(grid_graph(300), None, Registry::builtin());
    for (name, state) in [
        ("pbr_gold", pbr_gold as fn() -> EditorState),
        ("grid", grid),
    ] {
        let ((scale, a), (_, b)) = (render(state), render(state));
        if name == "grid" {
            let low = matgraph::editor::viewer::LOW_DETAIL_ZOOM;
            assert!(scale < low, "the grid framed at {scale}×: not the overview");
        }
        assert_eq!(a.dimensions(), b.dimensions());
        // Text rasterised at the canvas' zoom (src/editor/crisp_text.rs) shares egui's font
        // atlas, whose packing order leaves a rare glyph edge one or two levels apart (3–6
        // bytes of pbr_gold in half the runs, measured); the wires, which the test is about,
        // differed by 94–203 bytes and up to 66 levels.
        let differ = differing_bytes(a.as_raw(), b.as_raw());
        let most = a
            .as_raw()
            .iter()
            .zip(b.as_raw())
            .map(|(x, y)| x.abs_diff(*y))
            .max()
            .unwrap_or(0);
        assert!(
            differ <= 24 && most <= 2,
            "{name}: {differ} bytes differ, by up to {most} levels"
        );
    }
}

/// Format version 2 in the editor (issue 34): a graph with an inline group, a group of
/// another file (`lib/layers.json#scale`), a reroute, a muted node and a frame, written
/// compact (not canonical) into `dir`, with its library.
fn v2_folder(name: &str) -> PathBuf {
    let dir = scratch(name);
    std::fs::create_dir_all(dir.join("lib")).unwrap();
    let lib = serde_json::json!({
        "version": 2, "name": "layers", "nodes": [],
        "groups": { "scale": {
            "doc": "x times k.",
            "inputs": [
                { "name": "x", "type": "float", "default": 1.0 },
                { "name": "k", "type": "float", "default": 2.0, "soft_range": [0.0, 4.0], "doc": "The factor." }
            ],
            "nodes": [ { "id": "m", "type": "mul", "inputs": { "a": { "link": "@in.x" }, "b": { "link": "@in.k" } } } ],
            "outputs": [ { "name": "y", "from": "m.result" } ]
        } }
    });
    std::fs::write(dir.join("lib/layers.json"), lib.to_string()).unwrap();
    std::fs::write(dir.join("v2.json"), v2_graph().to_string()).unwrap();
    dir
}

/// The graph of [`v2_folder`]: geo → d → inl (inline group `fres`) → lib (group of
/// `lib/layers.json`) → rr (reroute) → mu (muted sqrt) → emission; frame `fr` holds geo
/// and d.
fn v2_graph() -> serde_json::Value {
    serde_json::json!({
        "version": 2, "name": "v2",
        "nodes": [
            { "id": "geo", "type": "geometry", "position": [0, 0] },
            { "id": "d", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.view" } },
              "position": [300, 0] },
            { "id": "inl", "type": "group", "group": "fres", "inputs": { "c": { "link": "d.result" } },
              "position": [600, 0] },
            { "id": "lib", "type": "group", "group": "lib/layers.json#scale",
              "inputs": { "x": { "link": "inl.r" } }, "position": [900, 0] },
            { "id": "rr", "type": "reroute", "inputs": { "input": { "link": "lib.y" } }, "position": [1250, 0] },
            { "id": "mu", "type": "sqrt", "muted": true, "inputs": { "x": { "link": "rr.output" } },
              "position": [1500, 0] }
        ],
        "outputs": [ { "name": "emission", "from": "mu.result" } ],
        "groups": { "fres": {
            "doc": "Schlick's Fresnel.",
            "inputs": [
                { "name": "c", "type": "float", "default": 1.0 },
                { "name": "f0", "type": "float", "default": 0.04, "soft_range": [0.0, 1.0] }
            ],
            "nodes": [ { "id": "f", "type": "fresnel_schlick",
                "inputs": { "cos_theta": { "link": "@in.c" }, "f0": { "link": "@in.f0" } } } ],
            "outputs": [ { "name": "r", "from": "f.reflectance" } ]
        } },
        "frames": [ { "id": "fr", "label": "Inputs", "nodes": ["geo", "d"], "color": [0.2, 0.4, 0.6] } ]
    })
}

/// What `matgraph fmt` writes for the graph file at `path`.
fn fmt_text(path: &Path) -> String {
    matgraph::io::load_graph(path, Registry::builtin())
        .unwrap()
        .to_json()
}

/// Runs `h` until its canvas shows every node, fitted (at most 60 s).
fn settle_all(h: &mut Harness<'static, EditorApp>) {
    let start = std::time::Instant::now();
    h.step();
    while !h.state().settled() && start.elapsed().as_secs() < 60 {
        h.step();
    }
    h.run_steps(3);
}

/// A version-2 file opens valid (its group of another file read from its folder), draws
/// each group instance as one node whose pins are its group's interface (inputs with their
/// value editors, outputs typed by the validated graph), its title followed by the group
/// it uses, the muted node marked, every node within its estimated rect, and saves
/// unedited as `matgraph fmt` writes it, byte for byte, again after a reload.
#[test]
fn a_version_2_file_draws_groups_as_one_node_and_saves_as_fmt_writes_it() {
    use matgraph::editor::ports::Kind;
    use matgraph::editor::view::REVEAL_MARGIN;
    use matgraph::node::PortType;
    use matgraph::types::SocketType;
    let dir = v2_folder("v2_open");
    let file = dir.join("v2.json");
    let mut s = EditorState::open(&file, Registry::builtin()).unwrap();
    s.dialog = None;
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    assert!(s.status.is_none(), "not arranged: {:?}", s.status);
    let names = |ports: &[matgraph::editor::ports::Port]| -> Vec<String> {
        ports.iter().map(|p| p.name.to_string()).collect()
    };
    // The inline group's interface, from the document's `groups`.
    let inl = s.doc.ports("inl").unwrap();
    assert!(
        matches!(&inl.kind, Kind::Group { reference, interface: true, .. } if reference == "fres")
    );
    assert_eq!(names(&inl.inputs), ["c", "f0"]);
    assert_eq!(names(&inl.outputs), ["r"]);
    assert_eq!(inl.inputs[1].soft.map(|r| (r.min, r.max)), Some((0.0, 1.0)));
    // The other file's, read through the graph file's folder; its output typed by the
    // validated graph.
    let lib = s.doc.ports("lib").unwrap();
    assert!(
        matches!(&lib.kind, Kind::Group { reference, interface: true, doc }
            if reference == "lib/layers.json#scale" && doc == "x times k.")
    );
    assert_eq!(names(&lib.inputs), ["x", "k"]);
    assert_eq!(names(&lib.outputs), ["y"]);
    assert_eq!(lib.outputs[0].ty, PortType::Fixed(SocketType::Float));
    assert_eq!(lib.inputs[1].doc, "The factor.");
    // A node preview of an instance cuts the graph at its group's first output.
    let files = s.doc.files().cloned();
    preview::cut_at_in(s.doc.doc(), "lib", Registry::builtin(), files).unwrap();
    // The reroute is a registered type.
    assert!(matches!(s.doc.ports("rr").unwrap().kind, Kind::Type(_)));
    // One canvas node per document node and the Material Output node, and a wire per link
    // (geo→d twice, d→inl, inl→lib, lib→rr, rr→mu) and the output's (mu→emission).
    assert_eq!(s.snarl.nodes().count(), 7);
    assert_eq!(s.snarl.wires().count(), 7);

    let mut h = harness(s);
    settle_all(&mut h);
    {
        let app = h.state();
        let frames = app.drawn_frames();
        let mut ids: Vec<&str> = frames.iter().map(|(id, _)| *id).collect();
        ids.sort_unstable();
        assert_eq!(
            ids,
            ["d", "geo", "inl", "lib", "mu", "rr"],
            "each instance is one node"
        );
        let doc = &app.state.doc;
        for (id, drawn) in frames {
            let k = doc.index(id).unwrap();
            let [x, y] = doc.doc().nodes[k].position.unwrap();
            let (w, ht) = doc.node_sizes()[k];
            let estimate = egui::Rect::from_min_size(egui::pos2(x, y), egui::vec2(w, ht));
            assert!(
                estimate.expand(REVEAL_MARGIN).contains_rect(drawn),
                "{id} drawn at {drawn:?}, estimated {estimate:?}"
            );
        }
    }
    // The headers: each instance's group after its id, the muted node marked.
    h.get_by_label("lib");
    h.get_by_label("lib/layers.json#scale");
    h.get_by_label("inl");
    h.get_by_label("fres");
    h.get_by_label("muted");
    // The interface pins, once each (the groups' inner nodes are not drawn).
    for pin in ["c", "f0", "r", "k", "y"] {
        assert_eq!(h.query_all_by_label(pin).count(), 1, "pin {pin}");
    }
    // No unsaved change, and saving writes what `matgraph fmt` writes.
    let expected = fmt_text(&file);
    assert_ne!(
        std::fs::read_to_string(&file).unwrap(),
        expected,
        "written compact"
    );
    assert!(!h.state().state.dirty());
    h.state_mut().state.save().unwrap();
    let saved = std::fs::read_to_string(&file).unwrap();
    assert_eq!(saved, expected);
    for key in [
        "\"groups\"",
        "\"frames\"",
        "\"muted\": true",
        "\"version\": 2",
    ] {
        assert!(saved.contains(key), "{key}");
    }
    // Reopened and saved again: the same bytes.
    let mut again = EditorState::open(&file, Registry::builtin()).unwrap();
    again.dialog = None;
    assert!(!again.dirty());
    again.save().unwrap();
    assert_eq!(std::fs::read_to_string(&file).unwrap(), expected);
}

/// A value edited on an instance's interface input is written on the instance, and a
/// wire between instances is checked as any other; removing a node takes it out of the
/// frames that hold it, so the saved file loads.
#[test]
fn edits_on_group_instances_and_removals_keep_a_version_2_file_valid() {
    let dir = v2_folder("v2_edit");
    let file = dir.join("v2.json");
    let mut s = EditorState::open(&file, Registry::builtin()).unwrap();
    s.dialog = None;
    s.set_input("lib", "k", serde_json::json!(3.0), None);
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    assert_eq!(
        s.doc.node("lib").unwrap().inputs.get("k"),
        Some(&serde_json::json!(3.0))
    );
    // A vec3 into the instance's float input: the loader's message, nothing changed.
    let err = s.connect("geo", "normal", "lib", "k").unwrap_err();
    assert!(err.contains("lib"), "{err}");
    s.connect("d", "result", "lib", "k").unwrap();
    assert_eq!(s.doc.link("lib", "k"), Some("d.result"));
    s.remove_nodes(&["d".to_owned()]);
    assert_eq!(s.doc.doc().frames[0].nodes, ["geo"]);
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    assert_eq!(s.doc.link("inl", "c"), None);
    s.save().unwrap();
    let g = matgraph::io::load_graph(&file, Registry::builtin()).unwrap();
    assert_eq!(g.to_json(), std::fs::read_to_string(&file).unwrap());
    // Undone: d is back in its frame.
    s.undo();
    assert_eq!(s.doc.doc().frames[0].nodes, ["geo", "d"]);
}

/// An error inside a group is shown on the instance that uses it (the loader reports it
/// as `node 'inl' (group fres) → …`), not on any other node, and drawn there (⚠).
#[test]
fn an_error_inside_a_group_is_shown_on_its_instance() {
    let dir = v2_folder("v2_error");
    let mut graph = v2_graph();
    graph["groups"]["fres"]["nodes"][0]["inputs"]["cos_theta"] =
        serde_json::json!({ "link": "nowhere.value" });
    let file = dir.join("v2.json");
    std::fs::write(&file, graph.to_string()).unwrap();
    let mut s = EditorState::open(&file, Registry::builtin()).unwrap();
    s.dialog = None;
    assert_eq!(s.doc.errors().len(), 1, "{:?}", s.doc.errors());
    let e = &s.doc.errors()[0];
    assert!(matches!(e, matgraph::GraphError::InGroup { .. }), "{e:?}");
    assert_eq!(e.node(), Some("inl"));
    let on = s.doc.node_errors("inl");
    assert_eq!(on.len(), 1);
    assert!(on[0].starts_with("node 'inl' (group fres) → "), "{}", on[0]);
    assert!(on[0].contains("nowhere"), "{}", on[0]);
    for other in ["geo", "d", "lib", "rr", "mu"] {
        assert!(s.doc.node_errors(other).is_empty(), "{other}");
    }
    // The instance is still drawn with its interface, marked.
    assert_eq!(s.doc.ports("inl").unwrap().inputs.len(), 2);
    let mut h = harness(s);
    settle_all(&mut h);
    assert_eq!(h.state().drawn_frames().len(), 6);
    assert_eq!(h.query_all_by_label("⚠").count(), 1);
    // Saving a graph with errors writes the document as written.
    h.state_mut().state.save().unwrap();
    let text = std::fs::read_to_string(&file).unwrap();
    assert_eq!(
        text,
        matgraph::GraphDocument::parse(&graph.to_string())
            .unwrap()
            .to_json_pretty()
    );
    // A malformed interface (the loader names the group, `v2.json#fres`, not a node) is
    // shown on the instances that use the group too.
    let mut bad = v2_graph();
    bad["groups"]["fres"]["inputs"][1]["type"] = serde_json::json!("mat4");
    let doc = matgraph::GraphDocument::parse(&bad.to_string()).unwrap();
    let files = EditorDoc::files_of(&file);
    let d = EditorDoc::with_files(doc, Registry::builtin(), Some(files));
    let on = d.node_errors("inl");
    assert!(
        on.iter()
            .any(|e| e.contains("input 'f0'") && e.contains("mat4")),
        "{on:?} of {:?}",
        d.errors()
    );
    assert!(d.node_errors("lib").is_empty());
}

/// Without a file, a group of another file cannot be read: the instance is an error, drawn
/// with the pins its links use; saved into the library's folder, the document reads it from
/// there, and the pins become the group's interface.
#[test]
fn a_group_of_another_file_resolves_once_the_graph_has_a_file() {
    use matgraph::editor::ports::Kind;
    let dir = v2_folder("v2_untitled");
    let doc: matgraph::GraphDocument = serde_json::from_value(v2_graph()).unwrap();
    let mut s = EditorState::new(doc, None, Registry::builtin());
    s.dialog = None;
    assert_eq!(s.doc.node_errors("lib").len(), 1, "{:?}", s.doc.errors());
    let lib = s.doc.ports("lib").unwrap();
    assert!(matches!(
        lib.kind,
        Kind::Group {
            interface: false,
            ..
        }
    ));
    let names = |p: &[matgraph::editor::ports::Port]| -> Vec<String> {
        p.iter().map(|p| p.name.to_string()).collect()
    };
    assert_eq!(names(&lib.inputs), ["x"]);
    assert_eq!(names(&lib.outputs), ["y"]);
    // The wires through it stay (and the output's, mu→emission).
    assert_eq!(s.snarl.wires().count(), 7);
    let mut h = harness(s);
    settle_all(&mut h);
    assert_eq!(h.state().drawn_frames().len(), 6);
    let out = dir.join("saved_here.json");
    h.state_mut().state.save_as(&out).unwrap();
    let s = &h.state().state;
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    assert_eq!(names(&s.doc.ports("lib").unwrap().inputs), ["x", "k"]);
    assert!(!s.dirty());
    assert_eq!(std::fs::read_to_string(&out).unwrap(), fmt_text(&out));
}

/// A reroute added to a version-1 file raises it to version 2 (a version-1 file with a
/// reroute does not load), so the file saved opens again.
#[test]
fn a_reroute_added_to_a_version_1_file_makes_it_version_2() {
    let dir = scratch("v1_reroute");
    let file = dir.join("v1.json");
    std::fs::write(
        &file,
        r#"{ "version": 1, "name": "v1", "nodes": [ { "id": "geo", "type": "geometry", "position": [0, 0] } ] }"#,
    )
    .unwrap();
    let mut s = EditorState::open(&file, Registry::builtin()).unwrap();
    s.dialog = None;
    s.add_node("dot", [300.0, 0.0]).unwrap();
    assert_eq!(s.doc.doc().version, 1, "a version-1 node keeps the version");
    s.add_node("reroute", [300.0, 200.0]).unwrap();
    assert_eq!(s.doc.doc().version, 2);
    s.connect("geo", "normal", "reroute", "input").unwrap();
    s.save().unwrap();
    let mut again = EditorState::open(&file, Registry::builtin()).unwrap();
    again.dialog = None;
    assert!(again.doc.errors().is_empty(), "{:?}", again.doc.errors());
    assert_eq!(again.doc.link("reroute", "input"), Some("geo.normal"));
    assert_eq!(std::fs::read_to_string(&file).unwrap(), fmt_text(&file));
}

// ---- The Material Output node (issue 35, item 1) ----

use matgraph::editor::outputs::{OUTPUT_NODE, OUTPUT_TITLE};

/// File → New, then geometry → dot → fresnel_schlick built through the editor's own edits.
fn fresnel_material() -> EditorState {
    let mut s = untitled();
    s.add_node("geometry", [0.0, 0.0]).unwrap();
    s.add_node("dot", [250.0, 0.0]).unwrap();
    s.add_node("fresnel_schlick", [500.0, 0.0]).unwrap();
    s.connect("geometry", "normal", "dot", "a").unwrap();
    s.connect("geometry", "view", "dot", "b").unwrap();
    s.connect("dot", "result", "fresnel_schlick", "cos_theta")
        .unwrap();
    s
}

/// The graph outputs of `s` as (name, from) pairs.
fn outputs_of(s: &EditorState) -> Vec<(String, String)> {
    s.doc
        .doc()
        .outputs
        .iter()
        .map(|o| (o.name.clone(), o.from.clone()))
        .collect()
}

/// A new graph gets an output through the Material Output node: the node is added, a
/// "color" pin added (unconnected: an error until wired), fresnel_schlick.reflectance
/// wired into it, and the saved file has that output, in canonical form, and loads.
#[test]
fn a_new_graph_gets_its_output_through_the_material_output_node() {
    let dir = scratch("material-output");
    let mut s = fresnel_material();
    assert!(s.doc.doc().outputs.is_empty());
    assert!(matgraph::editor::view::output_node_id(&s.snarl).is_none());
    let before = s.doc.canonical_json();
    assert_eq!(s.add_output_node([800.0, 0.0]), OUTPUT_NODE);
    let out = matgraph::editor::view::output_node_id(&s.snarl).expect("the node is on the canvas");
    assert_eq!(s.snarl[out].id, OUTPUT_NODE);
    assert_eq!(
        s.doc.canonical_json(),
        before,
        "the node alone changes nothing in the file"
    );
    s.add_output("color").unwrap();
    assert_eq!(outputs_of(&s), [("color".into(), String::new())]);
    assert_eq!(
        matgraph::editor::outputs::note(&s.doc, 0).as_deref(),
        Some("unconnected")
    );
    // What the canvas does for a wire dropped on the pin.
    s.connect("fresnel_schlick", "reflectance", OUTPUT_NODE, "color")
        .unwrap();
    assert_eq!(
        outputs_of(&s),
        [("color".into(), "fresnel_schlick.reflectance".into())]
    );
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    assert_eq!(
        s.snarl.wires().count(),
        4,
        "three links and the output's wire"
    );
    let file = dir.join("fresnel.json");
    s.save_as(&file).unwrap();
    let g = matgraph::io::load_graph(&file, Registry::builtin()).expect("loads without errors");
    let saved: Vec<(&str, String)> = g
        .outputs()
        .iter()
        .map(|o| (o.name.as_str(), g.output_name(o.source)))
        .collect();
    assert_eq!(saved, [("color", "fresnel_schlick.reflectance".to_owned())]);
    let text = std::fs::read_to_string(&file).unwrap();
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(
        doc["outputs"],
        serde_json::json!([{ "name": "color", "from": "fresnel_schlick.reflectance" }])
    );
    assert!(!text.contains(OUTPUT_NODE), "the node's place is not saved");
    assert_eq!(g.to_json(), text, "canonical");
    // Dragging the wire off keeps the entry, unconnected.
    s.clear_input(OUTPUT_NODE, "color");
    assert_eq!(outputs_of(&s), [("color".into(), String::new())]);
    assert_eq!(s.doc.link(OUTPUT_NODE, "color"), None);
}

/// Deleting the node an output reads keeps the output, marked on its pin; undo brings the
/// wire back, and a new node does not take the deleted one's id.
#[test]
fn deleting_the_node_an_output_reads_keeps_the_output_marked_and_undo_restores_it() {
    let mut s = fresnel_material();
    s.add_output("color").unwrap();
    s.connect("fresnel_schlick", "reflectance", OUTPUT_NODE, "color")
        .unwrap();
    let wires = s.snarl.wires().count();
    s.remove_nodes(&["fresnel_schlick".to_owned()]);
    assert_eq!(
        outputs_of(&s),
        [("color".into(), "fresnel_schlick.reflectance".into())],
        "the output is kept"
    );
    assert_eq!(
        matgraph::editor::outputs::note(&s.doc, 0).as_deref(),
        Some("reads deleted node 'fresnel_schlick'")
    );
    assert!(!s.doc.errors().is_empty(), "the loader reports it");
    assert!(matgraph::editor::view::output_node_id(&s.snarl).is_some());
    // The node is drawn with its pin marked.
    let mut h = harness(s);
    h.run();
    h.get_by_label(OUTPUT_TITLE);
    h.get_by_label("color");
    h.get_by_label("reads deleted node 'fresnel_schlick'");
    // A node added now gets a fresh id: it does not silently become the output.
    let id = h
        .state_mut()
        .state
        .add_node("fresnel_schlick", [500.0, 0.0])
        .unwrap();
    assert_eq!(id, "fresnel_schlick_2");
    h.state_mut().state.undo();
    h.state_mut().state.undo();
    h.run();
    let s = &h.state().state;
    assert!(s.doc.node("fresnel_schlick").is_some(), "undone");
    assert_eq!(
        outputs_of(s),
        [("color".into(), "fresnel_schlick.reflectance".into())]
    );
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    assert_eq!(s.snarl.wires().count(), wires, "the output's wire is back");
    assert!(
        h.query_by_label("reads deleted node 'fresnel_schlick'")
            .is_none()
    );
}

/// A file with outputs shows the Material Output node right of its rightmost node, with
/// a pin per output; the search finds it ("output"), and adding it again focuses the one
/// there.
#[test]
fn the_material_output_node_is_drawn_and_found_by_the_search() {
    let mut s = fresnel_material();
    s.add_output("color").unwrap();
    s.add_output("alpha").unwrap();
    s.connect("fresnel_schlick", "reflectance", OUTPUT_NODE, "color")
        .unwrap();
    let dir = scratch("material-output-drawn");
    let file = dir.join("g.json");
    s.save_as(&file).unwrap();
    let mut opened = EditorState::open(&file, Registry::builtin()).unwrap();
    opened.dialog = None;
    let out = matgraph::editor::view::output_node_id(&opened.snarl).expect("shown on open");
    let rightmost = opened
        .doc
        .doc()
        .nodes
        .iter()
        .map(|n| n.position.unwrap()[0])
        .fold(f32::MIN, f32::max);
    assert!(opened.snarl.get_node_info(out).unwrap().pos.x > rightmost);
    let mut h = harness(opened);
    h.run();
    h.get_by_label(OUTPUT_TITLE);
    h.get_by_label("color");
    h.get_by_label("alpha");
    h.get_by_label("unconnected");

    // The search of a new graph finds it.
    let mut h = harness(fresnel_material());
    h.run();
    h.key_press_modifiers(Modifiers::SHIFT, Key::A);
    h.run();
    h.event(egui::Event::Text("output".into()));
    h.run();
    h.get_by_label(&format!("{OUTPUT_TITLE}   (output)"));
    h.key_press(Key::Enter);
    h.run();
    {
        let s = &h.state().state;
        assert!(s.search.is_none());
        assert!(matgraph::editor::view::output_node_id(&s.snarl).is_some());
        assert_eq!(s.focus.as_deref(), Some(OUTPUT_NODE));
        assert_eq!(node_types(s), ["geometry", "dot", "fresnel_schlick"]);
    }
    // On the canvas and, focused, as the side panel's heading.
    assert_eq!(h.query_all_by_label(OUTPUT_TITLE).count(), 2);
    // The side panel offers the standard outputs.
    h.get_by_label("+ color").click();
    h.run();
    assert_eq!(
        outputs_of(&h.state().state),
        [("color".into(), String::new())]
    );
    // Again: the one node is focused, not a second one added.
    h.key_press_modifiers(Modifiers::SHIFT, Key::A);
    h.run();
    h.event(egui::Event::Text("output".into()));
    h.run();
    h.key_press(Key::Enter);
    h.run();
    let s = &h.state().state;
    let outs = s
        .snarl
        .node_ids()
        .filter(|(_, v)| v.id == OUTPUT_NODE)
        .count();
    assert_eq!(outs, 1);
    assert_eq!(s.focus.as_deref(), Some(OUTPUT_NODE));
}

/// Pins are renamed (keeping the wire) and removed; invalid or taken names are refused.
#[test]
fn material_output_pins_are_renamed_and_removed() {
    let mut s = fresnel_material();
    s.add_output_node([800.0, 0.0]);
    s.add_output("color").unwrap();
    s.add_output("my-mask_2").unwrap();
    assert!(s.add_output("bad name").is_err());
    assert!(s.add_output("color").is_err(), "taken");
    s.connect("fresnel_schlick", "reflectance", OUTPUT_NODE, "color")
        .unwrap();
    s.rename_output("color", "emission").unwrap();
    assert_eq!(
        outputs_of(&s),
        [
            ("emission".into(), "fresnel_schlick.reflectance".into()),
            ("my-mask_2".into(), String::new())
        ]
    );
    assert!(s.rename_output("emission", "my-mask_2").is_err(), "taken");
    assert!(s.rename_output("emission", "a.b").is_err(), "invalid");
    s.remove_output("my-mask_2");
    assert_eq!(
        outputs_of(&s),
        [("emission".into(), "fresnel_schlick.reflectance".into())]
    );
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    // Through the side panel: rename by typing, remove with ×.
    s.focus = Some(OUTPUT_NODE.to_owned());
    let mut h = harness(s);
    h.run();
    h.get_by_label("emission ← fresnel_schlick.reflectance");
    h.get_by_label("add output…");
    h.get_by_label("×").click();
    h.run();
    assert!(outputs_of(&h.state().state).is_empty());
    // The node stays, empty: it was added.
    assert!(matgraph::editor::view::output_node_id(&h.state().state.snarl).is_some());
    h.state_mut().state.undo();
    h.run();
    assert_eq!(
        outputs_of(&h.state().state),
        [("emission".into(), "fresnel_schlick.reflectance".into())]
    );
}

/// "Preview this output" shows a node's output in the main preview, without changing the
/// file; cut there even while an output is not wired yet.
#[test]
fn preview_this_output_changes_the_preview_not_the_file() {
    let mut s = fresnel_material();
    s.add_output("color").unwrap();
    let before = s.doc.canonical_json();
    s.preview_output(Some("dot"));
    assert_eq!(s.preview.main_output(), Some("dot"));
    assert_eq!(s.doc.canonical_json(), before);
    s.remove_nodes(&["dot".to_owned()]);
    let mut h = harness(s);
    h.run();
    assert_eq!(
        h.state().state.preview.main_output(),
        None,
        "its node is gone"
    );
}

/// Ctrl+Shift+click on a node shows it in the main preview (the file unchanged); again on
/// it, the graph's outputs.
#[test]
fn ctrl_shift_click_previews_a_node_and_again_goes_back() {
    let mut s = fresnel_material();
    s.add_output("color").unwrap();
    s.connect("fresnel_schlick", "reflectance", OUTPUT_NODE, "color")
        .unwrap();
    let before = s.doc.canonical_json();
    let mut h = harness(s);
    h.run();
    let (rect, to_screen) = {
        let app = h.state();
        let (_, r) = *app
            .drawn_frames()
            .iter()
            .find(|(id, _)| *id == "dot")
            .expect("dot is drawn");
        (r, app.to_screen())
    };
    let at = to_screen * (rect.min + egui::vec2(rect.width() / 2.0, 6.0));
    let ctrl_shift = Modifiers::COMMAND | Modifiers::SHIFT;
    let click = |h: &mut Harness<'static, EditorApp>| {
        h.event(egui::Event::PointerMoved(at));
        h.event(egui::Event::ModifiersChanged(ctrl_shift));
        h.run();
        for pressed in [true, false] {
            h.event(egui::Event::PointerButton {
                pos: at,
                button: egui::PointerButton::Primary,
                pressed,
                modifiers: ctrl_shift,
            });
        }
        h.run();
        h.event(egui::Event::ModifiersChanged(Modifiers::default()));
        h.run();
    };
    click(&mut h);
    assert_eq!(h.state().state.preview.main_output(), Some("dot"));
    assert_eq!(
        h.state().state.doc.canonical_json(),
        before,
        "the file is unchanged"
    );
    click(&mut h);
    assert_eq!(h.state().state.preview.main_output(), None);
}

// ---- Parameters (issue 35, item 2) ----

use matgraph::editor::params::PARAMETERS_PANEL;

/// geometry → dot → fresnel_dielectric, its reflectance the graph's `color`, and
/// `ior_inside` written 1.7 (not its default, 1.5).
fn dielectric_material() -> EditorState {
    let mut s = untitled();
    s.add_node("geometry", [0.0, 0.0]).unwrap();
    s.add_node("dot", [250.0, 0.0]).unwrap();
    s.add_node("fresnel_dielectric", [500.0, 0.0]).unwrap();
    s.connect("geometry", "normal", "dot", "a").unwrap();
    s.connect("geometry", "view", "dot", "b").unwrap();
    s.connect("dot", "result", "fresnel_dielectric", "cos_theta")
        .unwrap();
    s.add_output("color").unwrap();
    s.connect("fresnel_dielectric", "reflectance", OUTPUT_NODE, "color")
        .unwrap();
    s.set_input(
        "fresnel_dielectric",
        "ior_inside",
        serde_json::json!(1.7),
        None,
    );
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    s
}

/// The saved form of `s`'s document, as JSON.
fn saved_json(s: &EditorState) -> serde_json::Value {
    serde_json::from_str(&s.doc.canonical_json()).unwrap()
}

/// The names in `s`'s `parameters`, in order.
fn parameter_names(s: &EditorState) -> Vec<String> {
    s.doc
        .doc()
        .parameters
        .iter()
        .map(|p| p.name.clone())
        .collect()
}

/// Exposing `ior_inside` makes a parameter node holding its value, links it in and lists it
/// in `parameters` (the port's doc); the saved file loads, and the plan and the app contract
/// list the parameter. One undo step takes it all back; names the loader refuses, and an
/// input already linked, are refused. The input's right-click menu does the same.
#[test]
fn exposing_an_input_makes_a_linked_parameter_node_listed_in_parameters() {
    let dir = scratch("expose-parameter");
    let mut s = dielectric_material();
    let before = s.doc.canonical_json();
    assert_eq!(
        s.expose_input("fresnel_dielectric", "ior_inside", None),
        Ok("ior_inside".to_owned())
    );
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    let json = saved_json(&s);
    let node = json["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|n| n["id"] == "ior_inside")
        .expect("a parameter node");
    assert_eq!(node["type"], "parameter");
    assert_eq!(node["inputs"], serde_json::json!({ "value": 1.7 }));
    assert_eq!(
        s.doc.link("fresnel_dielectric", "ior_inside"),
        Some("ior_inside.value")
    );
    assert_eq!(
        json["parameters"],
        serde_json::json!([{
            "name": "ior_inside",
            "node": "ior_inside",
            "doc": "Index of refraction behind the surface."
        }])
    );
    let after = s.doc.canonical_json();
    let file = dir.join("exposed.json");
    s.save_as(&file).unwrap();
    let g = matgraph::io::load_graph(&file, Registry::builtin()).expect("loads");
    let p = &g.parameters()[0];
    assert_eq!((p.name.as_str(), p.default.as_f32()), ("ior_inside", 1.7));
    assert_eq!(p.feeds.len(), 1, "it feeds the ranged input");
    let plan = matgraph::Plan::compile(&g, &Default::default()).unwrap();
    let names: Vec<&str> = plan.parameters().iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["ior_inside"]);
    let m = matgraph::material::Material::new(&g, &Default::default()).unwrap();
    assert!(
        m.contract()
            .parameters
            .members
            .iter()
            .any(|m| m.parameter.as_deref() == Some("ior_inside")),
        "{:?}",
        m.contract().parameters
    );

    // Refused: a linked input, a name taken, an attribute's name, a bad name.
    assert!(
        s.expose_input("fresnel_dielectric", "ior_inside", None)
            .unwrap_err()
            .contains("linked")
    );
    let taken = s
        .expose_input("fresnel_dielectric", "ior_outside", Some("ior_inside"))
        .unwrap_err();
    assert!(taken.contains("already has a parameter"), "{taken}");
    let attribute = s
        .expose_input("fresnel_dielectric", "ior_outside", Some("normal"))
        .unwrap_err();
    assert!(attribute.contains("geometry attribute"), "{attribute}");
    assert!(
        s.expose_input("fresnel_dielectric", "ior_outside", Some("a b"))
            .is_err()
    );
    assert_eq!(s.doc.canonical_json(), after, "refusals change nothing");

    // One undo step, and redo.
    s.undo();
    assert_eq!(s.doc.canonical_json(), before);
    s.redo();
    assert_eq!(s.doc.canonical_json(), after);

    // A value outside the hard range is refused (the loader would report the parameter).
    s.set_input(
        "fresnel_dielectric",
        "ior_outside",
        serde_json::json!(500.0),
        None,
    );
    let out = s
        .expose_input("fresnel_dielectric", "ior_outside", None)
        .unwrap_err();
    assert!(out.contains("ior_outside"), "{out}");
    s.undo();

    // A colour input: a `color` parameter node; int inputs are refused.
    let mut c = untitled();
    let id = c.add_node("ramp", [0.0, 0.0]).unwrap();
    c.expose_input(&id, "color_light", None).unwrap();
    assert_eq!(
        c.doc.node("color_light").unwrap().data_type.as_deref(),
        Some("color")
    );
    assert!(c.doc.errors().is_empty(), "{:?}", c.doc.errors());
    assert!(c.expose_input(&id, "steps", None).is_err(), "an int input");

    // Through the input's right-click menu: a default name made unique.
    let mut h = harness(s);
    h.run();
    // The label's rect is in canvas coordinates: the click goes where it is on screen.
    let rect = h.get_by_label("ior_outside").rect();
    let at = h.state().to_screen() * rect.center();
    h.event(egui::Event::PointerMoved(at));
    h.run();
    for pressed in [true, false] {
        h.event(egui::Event::PointerButton {
            pos: at,
            button: egui::PointerButton::Secondary,
            pressed,
            modifiers: Modifiers::default(),
        });
    }
    h.run();
    h.get_by_label("Expose as parameter").click();
    h.run();
    let s = &h.state().state;
    assert_eq!(parameter_names(s), ["ior_inside", "ior_outside"]);
    assert_eq!(
        s.doc.link("fresnel_dielectric", "ior_outside"),
        Some("ior_outside.value")
    );
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    // The sliders list both.
    h.get_by_label("Parameters");
    assert!(h.query_all_by_label("ior_outside").count() >= 2);
}

/// Renaming, grouping, documenting and reordering write the saved `parameters` (and the
/// plan's order); each is one undo step. Through the parameters' editor too.
#[test]
fn renaming_and_reordering_parameters_change_the_saved_parameters() {
    let dir = scratch("rename-parameter");
    let mut s = dielectric_material();
    s.expose_input("fresnel_dielectric", "ior_inside", None)
        .unwrap();
    s.expose_input("fresnel_dielectric", "ior_outside", None)
        .unwrap();
    let exposed = s.doc.canonical_json();
    s.rename_parameter("ior_inside", "ior").unwrap();
    assert!(s.rename_parameter("ior", "ior_outside").is_err(), "taken");
    let e = s.rename_parameter("ior", "position").unwrap_err();
    assert!(e.contains("geometry attribute"), "{e}");
    assert!(s.rename_parameter("ior", "").is_err());
    assert_eq!(parameter_names(&s), ["ior", "ior_outside"]);
    assert_eq!(
        s.doc.link("fresnel_dielectric", "ior_inside"),
        Some("ior_inside.value"),
        "the node keeps its id"
    );
    let renamed = s.doc.canonical_json();
    s.move_parameter("ior_outside", true).unwrap();
    assert_eq!(parameter_names(&s), ["ior_outside", "ior"]);
    s.set_parameter_group("ior", "glass").unwrap();
    s.set_parameter_doc("ior", "Index of the glass.").unwrap();
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    let file = dir.join("renamed.json");
    s.save_as(&file).unwrap();
    let text: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    assert_eq!(
        text["parameters"],
        serde_json::json!([
            { "name": "ior_outside", "node": "ior_outside", "doc": "Index of refraction on the normal's side." },
            { "name": "ior", "node": "ior_inside", "doc": "Index of the glass.", "group": "glass" }
        ])
    );
    let g = matgraph::io::load_graph(&file, Registry::builtin()).unwrap();
    let plan = matgraph::Plan::compile(&g, &Default::default()).unwrap();
    let names: Vec<&str> = plan.parameters().iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["ior_outside", "ior"]);
    // Undo: doc, group, move, rename, one step each.
    for _ in 0..3 {
        s.undo();
    }
    assert_eq!(s.doc.canonical_json(), renamed);
    s.undo();
    assert_eq!(s.doc.canonical_json(), exposed);
    s.redo();
    assert_eq!(s.doc.canonical_json(), renamed);

    // The parameters' editor: a click on the Parameters heading, then "down" on the first.
    let mut h = harness(s);
    h.run();
    h.get_by_label("Parameters").click();
    h.run();
    assert_eq!(h.state().state.focus.as_deref(), Some(PARAMETERS_PANEL));
    h.query_all_by_label("down").next().unwrap().click();
    h.run();
    assert_eq!(parameter_names(&h.state().state), ["ior_outside", "ior"]);
    h.get_by_label("add parameter").click();
    h.run();
    let s = &h.state().state;
    assert_eq!(parameter_names(s), ["ior_outside", "ior", "param"]);
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    assert_eq!(s.doc.node("param").unwrap().node_type, "parameter");
}

/// Un-exposing writes the parameter's value (as last set) on every input it fed, removes
/// the entry and the node; one undo step brings them back. In the editor with ×.
#[test]
fn un_exposing_keeps_the_value_on_the_inputs_it_fed() {
    let mut s = dielectric_material();
    let before = s.doc.canonical_json();
    s.expose_input("fresnel_dielectric", "ior_inside", None)
        .unwrap();
    // The panel's slider writes the parameter node's value.
    s.set_input("ior_inside", "value", serde_json::json!(2.25), None);
    // It feeds a second input too.
    s.connect("ior_inside", "value", "fresnel_dielectric", "ior_outside")
        .unwrap();
    let exposed = s.doc.canonical_json();
    s.unexpose_parameter("ior_inside").unwrap();
    let n = s.doc.node("fresnel_dielectric").unwrap();
    assert_eq!(n.inputs["ior_inside"], serde_json::json!(2.25));
    assert_eq!(n.inputs["ior_outside"], serde_json::json!(2.25));
    assert!(s.doc.doc().parameters.is_empty());
    assert!(s.doc.node("ior_inside").is_none(), "nothing reads it");
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    let unexposed = s.doc.canonical_json();
    s.undo();
    assert_eq!(s.doc.canonical_json(), exposed, "one step");
    s.redo();
    assert_eq!(s.doc.canonical_json(), unexposed);

    // A node a graph output reads stays, unlisted.
    let mut s = dielectric_material();
    s.expose_input("fresnel_dielectric", "ior_inside", None)
        .unwrap();
    s.add_output("ior").unwrap();
    s.connect("ior_inside", "value", OUTPUT_NODE, "ior")
        .unwrap();
    s.unexpose_parameter("ior_inside").unwrap();
    assert!(s.doc.node("ior_inside").is_some());
    assert_eq!(
        s.doc.node("fresnel_dielectric").unwrap().inputs["ior_inside"],
        serde_json::json!(1.7)
    );

    // In the parameters' editor: ×.
    let mut s = dielectric_material();
    s.expose_input("fresnel_dielectric", "ior_inside", None)
        .unwrap();
    s.focus = Some(PARAMETERS_PANEL.to_owned());
    let mut h = harness(s);
    h.run();
    h.get_by_label("×").click();
    h.run();
    let s = &h.state().state;
    assert!(s.doc.doc().parameters.is_empty());
    assert_eq!(s.doc.canonical_json(), before, "as before it was exposed");
}
