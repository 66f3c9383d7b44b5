//! Variants in the node editor (issue 35, item 4): variant sets declared, their choices
//! added, renamed, reordered and removed, the default set, a set deleted; `switch` nodes bound
//! to a set with one input per choice, kept in step with the set; and the drop-down that
//! previews a choice, re-rendering the preview without changing the file.
#![cfg(feature = "editor")]

use egui::Key;
use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::{By, Queryable};
use matgraph::Registry;
use matgraph::editor::outputs::OUTPUT_NODE;
use matgraph::editor::variants::VARIANTS_PANEL;
use matgraph::editor::{EditorApp, EditorState};
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

/// A harness without a renderer, preview on (the GPU where there is an adapter, else the
/// CPU).
fn preview_harness(mut state: EditorState) -> Harness<'static, EditorApp> {
    state.dialog = None;
    state.preview.enabled = true;
    Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .with_max_steps(64)
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), EditorApp::new(state))
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

fn untitled() -> EditorState {
    let mut s = EditorState::untitled(Registry::builtin());
    // A recovery file another run left in the temporary folder is not this test's.
    s.dialog = None;
    s
}

/// A fresh folder under the target directory.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("editor-variants")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The saved form of `s`'s document, as JSON.
fn saved_json(s: &EditorState) -> serde_json::Value {
    serde_json::from_str(&s.doc.canonical_json()).unwrap()
}

/// The input pins the editor draws on node `id`.
fn input_pins(s: &EditorState, id: &str) -> Vec<String> {
    s.doc
        .ports(id)
        .unwrap()
        .inputs
        .iter()
        .map(|p| p.name.to_string())
        .collect()
}

/// The preview's display level of a grey of linear radiance `v`, written out from the
/// published formulas rather than taken from the renderer: the swatch's exposure of +1 EV
/// (`render_swatch`: `to_srgb8(1.0)`, ×2), Khronos PBR Neutral (below its compression start
/// 0.76 it only subtracts a black offset: x − 6.25x² under 0.08, else 0.04) and the sRGB
/// transfer function (IEC 61966-2-1).
fn display_level(v: f64) -> f64 {
    let v = 2.0 * v;
    let offset = if v < 0.08 { v - 6.25 * v * v } else { 0.04 };
    let x = v - offset;
    assert!(x < 0.76, "the hand formula covers the linear part only");
    let e = if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    e * 255.0
}

/// Two constants, 0.1 (`dark`) and 0.3 (`bright`), as unlisted `parameter` nodes, and the
/// graph output `value` (unconnected: its error is hidden while a switch is unwired).
fn two_constants() -> EditorState {
    let mut s = untitled();
    for (id, v, y) in [("dark", 0.1, 0.0), ("bright", 0.3, 150.0)] {
        let got = s.add_node("parameter", [0.0, y]).unwrap();
        s.edit(None, true, |d| {
            let mut doc = d.doc().clone();
            let n = doc.nodes.iter_mut().find(|n| n.id == got).unwrap();
            n.id = id.to_owned();
            n.inputs.insert("value".to_owned(), serde_json::json!(v));
            d.replace(doc);
            Ok(())
        })
        .unwrap();
    }
    s.add_output("value").unwrap();
    s
}

/// Declaring a set, editing its choices, its default, its doc and its name: each one undo
/// step, the saved `variants` what the loader reads back, and every name the loader would
/// refuse refused first, with the reason in the status line.
#[test]
fn variant_sets_are_declared_edited_and_undone_as_the_loader_reads_them() {
    let dir = scratch("declare");
    let mut s = untitled();
    let empty = s.doc.canonical_json();
    assert_eq!(
        s.add_variant_set(Some("tone"), &["dark", "bright"]),
        Ok("tone".into())
    );
    let declared = s.doc.canonical_json();
    assert_eq!(
        saved_json(&s)["variants"],
        serde_json::json!({ "tone": { "choices": ["dark", "bright"], "default": "dark" } })
    );
    // Refused: bad and taken names, bad and repeated choices; nothing changes.
    for (name, choices, why) in [
        ("tone", &["x"][..], "already has a variant set 'tone'"),
        ("a b", &[][..], "use letters, digits"),
        ("t2", &["ok", "no way"][..], "'no way' cannot be a choice"),
        ("t2", &["x", "x"][..], "choice 'x' is repeated"),
    ] {
        let e = s.add_variant_set(Some(name), choices).unwrap_err();
        assert!(e.contains(why), "{name}: {e}");
        assert_eq!(s.status.as_deref(), Some(e.as_str()));
    }
    assert_eq!(s.doc.canonical_json(), declared);
    // Choices: add, rename (the default follows), reorder, remove; the default; the doc.
    assert_eq!(s.add_variant_choice("tone", Some("mid")), Ok("mid".into()));
    assert!(
        s.add_variant_choice("tone", Some("mid"))
            .unwrap_err()
            .contains("already has a choice")
    );
    assert!(s.add_variant_choice("tone", Some("m.d")).is_err());
    assert!(
        s.add_variant_choice("nope", Some("x"))
            .unwrap_err()
            .contains("no variant set")
    );
    s.rename_variant_choice("tone", "dark", "shade").unwrap();
    assert!(
        s.rename_variant_choice("tone", "shade", "bright").is_err(),
        "taken"
    );
    assert!(s.rename_variant_choice("tone", "shade", "").is_err());
    s.move_variant_choice("tone", "mid", true).unwrap();
    s.set_variant_default("tone", "mid").unwrap();
    s.set_variant_doc("tone", "How light the ball is.").unwrap();
    s.rename_variant_set("tone", "lightness").unwrap();
    assert!(s.rename_variant_set("lightness", "1 2").is_err());
    s.remove_variant_choice("lightness", "bright").unwrap();
    let edited = s.doc.canonical_json();
    assert_eq!(
        saved_json(&s)["variants"],
        serde_json::json!({ "lightness": {
            "choices": ["shade", "mid"], "default": "mid", "doc": "How light the ball is."
        } })
    );
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    // The last choice cannot go.
    s.remove_variant_choice("lightness", "shade").unwrap();
    let last = s.remove_variant_choice("lightness", "mid").unwrap_err();
    assert!(last.contains("only choice"), "{last}");
    s.undo();
    assert_eq!(s.doc.canonical_json(), edited);
    // The file loads and the graph lists the set.
    let file = dir.join("declared.json");
    s.save_as(&file).unwrap();
    let g = matgraph::io::load_graph(&file, Registry::builtin()).expect("loads");
    let v = &g.variants()["lightness"];
    assert_eq!(
        (v.choices.clone(), v.default.as_str()),
        (vec!["shade".into(), "mid".into()], "mid")
    );
    // One undo step per edit: remove, rename set, doc, default, move, rename, add — then
    // the declaration.
    for _ in 0..7 {
        s.undo();
    }
    assert_eq!(s.doc.canonical_json(), declared);
    s.undo();
    assert_eq!(s.doc.canonical_json(), empty);
    s.redo();
    assert_eq!(s.doc.canonical_json(), declared);
}

/// A switch added for a set has one pin per choice; wiring them (the last one although
/// the graph's unconnected output then shows up among the errors), the switch's pins and
/// links follow renamed, added and removed choices, and deleting the set replaces the
/// switch by its default choice.
#[test]
fn a_switch_has_a_pin_per_choice_and_follows_the_set() {
    let mut s = two_constants();
    s.add_variant_set(Some("tone"), &["dark", "bright"])
        .unwrap();
    let before = s.doc.canonical_json();
    let id = s.add_switch("tone", [300.0, 60.0]).unwrap();
    assert_eq!(id, "tone");
    assert_eq!(s.focus.as_deref(), Some("tone"), "the side panel shows it");
    assert_eq!(input_pins(&s, "tone"), ["dark", "bright"]);
    assert_eq!(s.doc.ports("tone").unwrap().outputs[0].name, "result");
    let n = s.doc.node("tone").unwrap();
    assert_eq!(
        (n.node_type.as_str(), n.variant.as_deref()),
        ("switch", Some("tone"))
    );
    // Unwired, the loader says what is missing.
    let errors = s.doc.node_errors("tone");
    assert!(
        errors
            .iter()
            .any(|e| e.contains("needs a link for each of its choices")),
        "{errors:?}"
    );
    s.connect("dark", "value", "tone", "dark").unwrap();
    // Before the fix this wire was refused with the output's "must be written
    // node_id.output": the loader checks the rest of the graph only once every switch
    // choice is wired.
    s.connect("bright", "value", "tone", "bright").unwrap();
    s.connect("tone", "result", OUTPUT_NODE, "value").unwrap();
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    // The switch's pins are typed by what its choices read.
    let ty = s.doc.ports("tone").unwrap().inputs[0].ty;
    assert_eq!(
        s.doc.port_type("tone", ty),
        Some(matgraph::SocketType::Float)
    );
    let wired = s.doc.canonical_json();
    assert_eq!(
        saved_json(&s)["nodes"][2],
        serde_json::json!({
            "id": "tone", "type": "switch", "variant": "tone",
            "inputs": { "bright": { "link": "bright.value" }, "dark": { "link": "dark.value" } },
            "position": [300.0, 60.0]
        })
    );
    // A renamed choice keeps its wire; a new one reads the default's; a removed one goes.
    s.rename_variant_choice("tone", "bright", "light").unwrap();
    assert_eq!(input_pins(&s, "tone"), ["dark", "light"]);
    assert_eq!(s.doc.link("tone", "light"), Some("bright.value"));
    s.add_variant_choice("tone", Some("mid")).unwrap();
    assert_eq!(input_pins(&s, "tone"), ["dark", "light", "mid"]);
    assert_eq!(s.doc.link("tone", "mid"), Some("dark.value"));
    s.move_variant_choice("tone", "mid", true).unwrap();
    assert_eq!(input_pins(&s, "tone"), ["dark", "mid", "light"]);
    s.remove_variant_choice("tone", "mid").unwrap();
    assert_eq!(input_pins(&s, "tone"), ["dark", "light"]);
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    // A wire that gives the choices two types is refused, with the loader's message.
    s.add_node("geometry", [0.0, 300.0]).unwrap();
    let e = s
        .connect("geometry", "normal", "tone", "light")
        .unwrap_err();
    assert!(e.contains("every choice of a switch has one type"), "{e}");
    assert_eq!(s.doc.link("tone", "light"), Some("bright.value"));
    // Deleting the set: what read the switch reads its default (dark), the switch goes.
    s.set_variant_default("tone", "light").unwrap();
    s.remove_variant_set("tone").unwrap();
    assert!(s.doc.node("tone").is_none());
    assert!(s.doc.doc().variants.is_empty());
    assert_eq!(s.doc.link(OUTPUT_NODE, "value"), Some("bright.value"));
    assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    assert!(
        s.status
            .as_deref()
            .unwrap()
            .contains("switch 'tone' replaced by bright.value"),
        "{:?}",
        s.status
    );
    // One undo step each: delete the set, the default, the geometry node, remove, move,
    // add and rename the choice; then the three wires and the switch.
    for _ in 0..7 {
        s.undo();
    }
    assert_eq!(s.doc.canonical_json(), wired);
    for _ in 0..4 {
        s.undo();
    }
    assert_eq!(s.doc.canonical_json(), before, "the switch was one step");
}

/// The drop-down under the preview picks the choice the preview renders: the ball turns
/// from the default's 0.1 to 0.3, as the display levels written out from the tone mapper's
/// and sRGB's formulas say; the file and its default are unchanged. The switch's
/// inspector marks the previewed choice.
#[test]
fn the_drop_down_previews_a_choice_without_changing_the_file() {
    let mut s = two_constants();
    s.add_variant_set(Some("tone"), &["dark", "bright"])
        .unwrap();
    s.add_switch("tone", [300.0, 60.0]).unwrap();
    s.connect("dark", "value", "tone", "dark").unwrap();
    s.connect("bright", "value", "tone", "bright").unwrap();
    s.connect("tone", "result", OUTPUT_NODE, "value").unwrap();
    s.history.seal();
    let file = s.doc.canonical_json();
    let mut h = preview_harness(s);
    settle(&mut h);
    let centre = |h: &Harness<'static, EditorApp>| {
        let p = h.state().state.preview.pixels().expect("a swatch").to_vec();
        let n = matgraph::editor::preview::SIZE as usize;
        let k = (n / 2 * n + n / 2) * 4;
        [p[k], p[k + 1], p[k + 2]]
    };
    let near = |got: [u8; 3], v: f64| {
        let want = display_level(v);
        got.iter().all(|&c| (c as f64 - want).abs() <= 1.5)
    };
    let dark = centre(&h);
    assert!(
        near(dark, 0.1),
        "default 'dark': {dark:?}, want {:.1}",
        display_level(0.1)
    );
    let compiles = h.state().state.preview.compiles();
    // The drop-down shows the default; open it and pick 'bright'.
    h.get_by_label("Variants");
    h.get(By::new().role(Role::ComboBox).value("dark (default)"))
        .click();
    h.run();
    h.get_by_role_and_label(Role::Button, "bright").click();
    h.run();
    settle(&mut h);
    let bright = centre(&h);
    eprintln!(
        "DEBUG {} {:?} {:?} {:?}",
        h.state().state.preview.compiles(),
        h.state().state.preview.selection(h.state().state.doc.doc()),
        h.state().state.preview.message(),
        h.state().state.preview.backend()
    );
    assert!(
        near(bright, 0.3),
        "picked 'bright': {bright:?}, want {:.1}",
        display_level(0.3)
    );
    let s = &h.state().state;
    assert_eq!(s.preview.variant("tone"), Some("bright"));
    assert_eq!(s.preview.compiles(), compiles + 1, "another program");
    assert_eq!(s.doc.canonical_json(), file, "the file is unchanged");
    assert_eq!(s.doc.doc().variants["tone"].default, "dark");
    assert!(
        s.status
            .as_deref()
            .unwrap()
            .contains("default stays 'dark'")
    );
    // The switch's inspector marks the previewed choice.
    h.state_mut().state.focus = Some("tone".into());
    h.run();
    h.get_by_label("▶ bright ← bright.value");
    h.get_by_label("dark (default) ← dark.value");
    // A second switch, unwired and read by nothing, does not stop the preview (before,
    // "the graph has errors": the loader checks no further while a switch lacks a choice).
    h.state_mut()
        .state
        .add_switch("tone", [300.0, 300.0])
        .unwrap();
    settle(&mut h);
    assert!(!h.state().state.doc.errors().is_empty());
    assert_eq!(h.state().state.preview.message(), None);
    assert!(near(centre(&h), 0.3));
    h.state_mut().state.undo();
    // Picking the default again renders the first program's pixels.
    h.get(By::new().role(Role::ComboBox).value("bright"))
        .click();
    h.run();
    h.get_by_role_and_label(Role::Button, "dark (default)")
        .click();
    h.run();
    settle(&mut h);
    assert!(near(centre(&h), 0.1));
    assert_eq!(
        h.state().state.preview.selection(h.state().state.doc.doc()),
        []
    );
}

/// Replaces the text of the field showing `now` by `text` and presses Enter.
fn type_into(h: &mut Harness<'static, EditorApp>, now: &str, text: &str) {
    let field = || By::new().role(Role::TextInput).value(now);
    h.get(field()).focus();
    h.run();
    h.key_press_modifiers(egui::Modifiers::COMMAND, Key::A);
    h.run();
    h.get(field()).type_text(text);
    h.run();
    h.key_press(Key::Enter);
    h.run();
}

/// The variants editor through its buttons and fields alone: Edit → Variant sets…, a set
/// added, a switch added for it, a choice renamed by typing (a bad name refused, the field
/// showing the name again), the default moved, and undo.
#[test]
fn the_variants_editor_works_from_its_buttons_and_fields() {
    let mut h = harness(untitled());
    h.run();
    h.get_by_label("Edit").click();
    h.run();
    h.get_by_label("Variant sets…").click();
    h.run();
    assert_eq!(h.state().state.focus.as_deref(), Some(VARIANTS_PANEL));
    h.get_by_label("add variant set").click();
    h.run();
    let v = h.state().state.doc.doc().variants["variant"].clone();
    assert_eq!(
        (v.choices, v.default.as_str()),
        (vec!["a".into(), "b".into()], "a")
    );
    // The side panel lists it with its drop-down.
    h.get_by_label("Variants");
    h.get_by_label("add switch").click();
    h.run();
    let s = &h.state().state;
    assert_eq!(s.focus.as_deref(), Some("variant"), "the switch is shown");
    assert_eq!(input_pins(s, "variant"), ["a", "b"]);
    // Back in the editor: rename choice 'b' by typing.
    h.state_mut().state.focus = Some(VARIANTS_PANEL.into());
    h.run();
    type_into(&mut h, "b", "no way");
    let s = &h.state().state;
    assert!(
        s.status.as_deref().unwrap().contains("cannot be a choice"),
        "{:?}",
        s.status
    );
    assert_eq!(s.doc.doc().variants["variant"].choices, ["a", "b"]);
    h.run();
    type_into(&mut h, "b", "fast");
    let s = &h.state().state;
    assert_eq!(s.doc.doc().variants["variant"].choices, ["a", "fast"]);
    assert_eq!(input_pins(s, "variant"), ["a", "fast"]);
    // The second 'default' radio makes 'fast' the default.
    h.query_all_by_label("default").nth(1).unwrap().click();
    h.run();
    assert_eq!(
        h.state().state.doc.doc().variants["variant"].default,
        "fast"
    );
    // Undo: default, rename, switch, set.
    for _ in 0..4 {
        h.state_mut().state.undo();
    }
    assert!(h.state().state.doc.doc().variants.is_empty());
    assert!(h.state().state.doc.doc().nodes.is_empty());
}

/// The bundled fresnel_variants graph: its switch is drawn with a pin per choice of
/// `fresnel`, in the set's order, typed by the Fresnel nodes' outputs.
#[test]
fn the_bundled_switch_is_drawn_with_its_sets_choices() {
    let s = EditorState::open(
        Path::new("graphs/fresnel_variants.json"),
        Registry::builtin(),
    )
    .unwrap();
    assert!(s.doc.errors().is_empty());
    assert_eq!(input_pins(&s, "fresnel"), ["schlick", "exact"]);
    let p = s.doc.ports("fresnel").unwrap();
    assert_eq!(p.switch(), Some("fresnel"));
    assert_eq!(
        s.doc.port_type("fresnel", p.outputs[0].ty),
        Some(matgraph::SocketType::Float)
    );
    let mut h = harness(s);
    h.run();
    h.get_by_value("exact (default)");
}
