//! A material made in the editor from an empty graph (issue 35's test): graphs/fresnel_glass.json
//! built through the editor's own actions — nodes added by Shift+A and typing, as a user adds
//! them; wires, the exposed `ior` and the Material Output's pins through the editor's action
//! API, the calls its canvas and menus make — saved with Ctrl+S's code path, and rendered to
//! the same pixels as the bundled file.
#![cfg(feature = "editor")]

use crate::common;

use common::scenes::{render_options, scene_of};
use egui::{Key, Modifiers};
use egui_kittest::Harness;
use matgraph::Registry;
use matgraph::editor::{EditorApp, EditorState};
use matgraph::gpu::Backend;
use matgraph::render::render;
use std::path::Path;

/// A harness without a renderer, preview off, on an empty graph.
fn harness() -> Harness<'static, EditorApp> {
    let mut state = EditorState::untitled(Registry::builtin());
    state.dialog = None;
    state.preview.enabled = false;
    Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .with_max_steps(64)
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), EditorApp::new(state))
}

/// Adds a node as a user does: Shift+A, the type's name typed, Enter.
fn search_add(h: &mut Harness<'static, EditorApp>, type_name: &str) {
    h.key_press_modifiers(Modifiers::SHIFT, Key::A);
    h.run();
    h.event(egui::Event::Text(type_name.into()));
    h.run();
    h.key_press(Key::Enter);
    h.run();
    let s = &h.state().state;
    assert!(s.search.is_none(), "the search closes on Enter");
    assert!(
        s.doc.doc().nodes.iter().any(|n| n.node_type == type_name),
        "{type_name} was not added: {:?}",
        s.doc
            .doc()
            .nodes
            .iter()
            .map(|n| &n.node_type)
            .collect::<Vec<_>>()
    );
}

#[test]
fn fresnel_glass_built_from_an_empty_graph_renders_as_the_bundled_file() {
    let mut h = harness();
    h.run();
    for t in [
        "geometry",
        "dot",
        "fresnel_dielectric",
        "ior_to_f0",
        "f0_to_specular",
        "fresnel_schlick",
    ] {
        search_add(&mut h, t);
    }
    {
        let s = &mut h.state_mut().state;
        for (from, out, to, input) in [
            ("geometry", "normal", "dot", "a"),
            ("geometry", "view", "dot", "b"),
            ("dot", "result", "fresnel_dielectric", "cos_theta"),
            ("dot", "result", "fresnel_schlick", "cos_theta"),
            ("ior_to_f0", "f0", "fresnel_schlick", "f0"),
            ("ior_to_f0", "f0", "f0_to_specular", "f0"),
        ] {
            s.connect(from, out, to, input)
                .unwrap_or_else(|e| panic!("{from}.{out} → {to}.{input}: {e}"));
        }
        // The glass's IOR typed on the node, then exposed as the parameter `ior` (right-click →
        // Expose as parameter), which feeds the F0 node too.
        s.set_input("fresnel_dielectric", "ior_inside", 1.52.into(), None);
        let name = s
            .expose_input("fresnel_dielectric", "ior_inside", Some("ior"))
            .unwrap();
        assert_eq!(name, "ior");
        s.connect("ior", "value", "ior_to_f0", "ior_inside")
            .unwrap();
        s.set_parameter_doc("ior", "Index of refraction of the glass (589 nm).")
            .unwrap();
        // The Material Output node (Shift+A → "output") and its three pins.
        s.add_output_node([800.0, 0.0]);
        for (name, from, out) in [
            ("reflectance", "fresnel_dielectric", "reflectance"),
            ("schlick", "fresnel_schlick", "reflectance"),
            ("specular", "f0_to_specular", "specular"),
        ] {
            s.add_output(name).unwrap();
            s.connect(from, out, "@outputs", name).unwrap();
        }
        assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    }
    h.run();
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("glass.json");
    h.state_mut().state.save_as(&file).unwrap();
    assert!(!h.state().state.dirty());

    // The saved file loads, has the bundled file's outputs and parameter, and renders to the
    // same pixels (CPU renderer, the ball scene both use).
    let bundled_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/fresnel_glass.json");
    let built = matgraph::io::load_graph(&file, Registry::builtin()).unwrap();
    let bundled = matgraph::io::load_graph(&bundled_path, Registry::builtin()).unwrap();
    let names = |g: &matgraph::Graph| -> Vec<String> {
        g.outputs().iter().map(|o| o.name.clone()).collect()
    };
    assert_eq!(names(&built), names(&bundled));
    assert_eq!(built.parameters()[0].name, "ior");
    assert_eq!(built.parameters()[0].default.as_f32(), 1.52);
    let picture = |g: &matgraph::Graph, p: &Path| {
        render(g, &scene_of(g), &render_options(96, Backend::Cpu, g, p))
            .unwrap()
            .to_srgb8(0.0)
    };
    let (a, b) = (picture(&built, &file), picture(&bundled, &bundled_path));
    assert_eq!(a.pixels.len(), b.pixels.len());
    let differing = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(x, y)| x != y)
        .count();
    assert_eq!(
        differing,
        0,
        "{differing} of {} pixels differ",
        a.pixels.len()
    );
    // Not a blank picture: the glass's Fresnel rim is brighter than its centre.
    let distinct: std::collections::HashSet<_> = a.pixels.iter().collect();
    assert!(distinct.len() > 50, "{} distinct colours", distinct.len());
}

/// Exposing an input of a generic node while the graph does not compile (an error on another
/// node, as while a material is being made) keeps the value written on it: a colour f0
/// becomes a colour parameter holding that colour (before the fix the node's type was taken
/// as float, the colour did not parse, and the parameter got the default 0.04).
#[test]
fn exposing_a_generic_input_while_the_graph_does_not_compile_keeps_its_value() {
    let mut s = EditorState::untitled(Registry::builtin());
    let id = s.add_node("fresnel_schlick", [0.0, 0.0]).unwrap();
    s.set_input(&id, "f0", serde_json::json!([0.95, 0.64, 0.54]), None);
    let other = s.add_node("fresnel_dielectric", [0.0, 200.0]).unwrap();
    s.set_input(&other, "ior_inside", serde_json::json!(0.0), None);
    assert!(s.doc.graph().is_none(), "the graph must not compile here");
    let name = s.expose_input(&id, "f0", Some("tint")).unwrap();
    let p = s
        .doc
        .doc()
        .nodes
        .iter()
        .find(|n| n.id == name)
        .expect("the parameter node");
    assert_eq!(p.inputs["value"], serde_json::json!([0.95, 0.64, 0.54]));
}
