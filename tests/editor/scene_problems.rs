//! An environment image or scene file the editor does not read is a Problem with its path
//! and why (issue 37: the preview fell back to the default room and Problems said (0)).
#![cfg(feature = "editor")]

use crate::drive::{harness, scratch};
use egui_kittest::kittest::Queryable;
use matgraph::Registry;
use matgraph::editor::EditorState;

/// A graph in `dir` whose scene is `scene` (JSON).
fn graph_with_scene(dir: &std::path::Path, scene: &str) -> std::path::PathBuf {
    let text = format!(
        r#"{{ "version": 1, "name": "t", "scene": {scene},
  "nodes": [ {{ "id": "k", "type": "parameter", "inputs": {{ "value": 1.0 }} }} ],
  "outputs": [ {{ "name": "o", "from": "k.value" }} ] }}"#
    );
    let file = dir.join("g.json");
    std::fs::write(&file, text).unwrap();
    file
}

#[test]
fn an_environment_outside_the_graphs_folder_is_a_problem() {
    let dir = scratch("scene-problems-outside");
    let inner = dir.join("graph");
    std::fs::create_dir_all(&inner).unwrap();
    let file = graph_with_scene(
        &inner,
        r#"{ "kind": "ball", "environment": { "image": { "path": "../away.hdr" } } }"#,
    );
    let mut s = EditorState::open(&file, Registry::builtin()).unwrap();
    s.dialog = None;
    let h = harness(s);
    h.get_by_label("Problems (1)");
    h.get_by_label_contains("environment image: path '../away.hdr' resolves to");
    h.get_by_label_contains("outside the graph's folder");
    h.get_by_label_contains("the preview shows the default room instead");
}

#[test]
fn a_scene_files_environment_and_a_missing_scene_file_are_problems() {
    let dir = scratch("scene-problems-file");
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    std::fs::write(
        dir.join("sub/scene.json"),
        r#"{ "kind": "ball", "environment": { "image": { "path": "../sky.hdr" } } }"#,
    )
    .unwrap();
    let file = graph_with_scene(&dir, r#""sub/scene.json""#);
    let mut s = EditorState::open(&file, Registry::builtin()).unwrap();
    s.dialog = None;
    let h = harness(s);
    h.get_by_label("Problems (1)");
    h.get_by_label_contains("outside the scene's folder");
    drop(h);
    let file = graph_with_scene(&dir, r#""nowhere.json""#);
    let mut s = EditorState::open(&file, Registry::builtin()).unwrap();
    s.dialog = None;
    let h = harness(s);
    h.get_by_label("Problems (1)");
    h.get_by_label_contains("scene: path 'nowhere.json'");
    // An environment inside the folder is no problem (it need not be read to be allowed).
    let file = graph_with_scene(&dir, r#"{ "kind": "ball", "environment": "sunset" }"#);
    let mut s = EditorState::open(&file, Registry::builtin()).unwrap();
    s.dialog = None;
    let h = harness(s);
    h.get_by_label("Problems (0)");
}
