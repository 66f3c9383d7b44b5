//! File → Open (issue 35, item 8): the in-app file browser (`src/editor/browser.rs`), with
//! the recent files on top, folders and graph files with their names and docs, filtered by
//! typing; a graph opened through keys alone and through clicks alone.
#![cfg(feature = "editor")]

use egui::accesskit::Role;
use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use matgraph::Registry;
use matgraph::editor::browser::{Browser, EntryKind, Outcome, describe};
use matgraph::editor::files::Recent;
use matgraph::editor::state::Dialog;
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

/// A fresh folder under the target directory.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("editor-browser")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A small valid graph file named `name` with `doc`.
fn graph_file(path: &Path, name: &str, doc: &str) {
    let text = serde_json::json!({
        "version": 1,
        "name": name,
        "doc": doc,
        "nodes": [{ "id": "geo", "type": "geometry", "position": [0.0, 0.0] }],
        "outputs": [{ "name": "preview", "from": "geo.normal" }]
    });
    std::fs::write(path, serde_json::to_string_pretty(&text).unwrap()).unwrap();
}

/// `work/` holds `alpha.json`, `beta.json`, `notes.txt`, `.hidden.json`, `alpha.json.autosave`
/// and `sub/gamma.json`; `elsewhere/recent.json` is a recent file.
fn folders(name: &str) -> (PathBuf, PathBuf) {
    let dir = scratch(name);
    let work = dir.join("work");
    std::fs::create_dir_all(work.join("sub")).unwrap();
    std::fs::create_dir_all(dir.join("elsewhere")).unwrap();
    graph_file(
        &work.join("alpha.json"),
        "alpha",
        "The first graph. It has a second sentence.",
    );
    graph_file(&work.join("beta.json"), "beta", "");
    graph_file(&work.join("sub").join("gamma.json"), "gamma", "Third.");
    graph_file(
        &dir.join("elsewhere").join("recent.json"),
        "recent_one",
        "Opened before.",
    );
    std::fs::write(work.join("notes.txt"), "not a graph").unwrap();
    std::fs::write(work.join(".hidden.json"), "{}").unwrap();
    std::fs::write(work.join("alpha.json.autosave"), "{}").unwrap();
    (dir, work)
}

fn labels(b: &Browser) -> Vec<(EntryKind, String)> {
    b.entries().into_iter().map(|e| (e.kind, e.label)).collect()
}

/// The rows: recent files first (whole paths), `..`, folders, then graph files by name, with
/// each graph's name and first sentence; other files, hidden ones and autosaves are left
/// out. Typing filters (a folder or a doc's words too), Enter enters a folder, Backspace on
/// an empty filter goes up, a typed path opens, Escape cancels.
#[test]
fn the_browser_lists_recent_files_folders_and_graphs_and_filters_by_typing() {
    let (dir, work) = folders("rows");
    let recent = dir.join("elsewhere").join("recent.json");
    let gone = dir.join("gone.json");
    let mut b = Browser::graphs(&work, &[recent.clone(), gone]);
    assert_eq!(
        labels(&b),
        [
            (EntryKind::Recent, recent.display().to_string()),
            (EntryKind::Parent, "..".into()),
            (EntryKind::Folder, "sub/".into()),
            (EntryKind::File, "alpha.json".into()),
            (EntryKind::File, "beta.json".into()),
        ],
        "a recent file that no longer exists is left out"
    );
    let notes: Vec<String> = b.entries().into_iter().map(|e| e.note).collect();
    assert_eq!(notes[0], "recent_one: Opened before.");
    assert_eq!(notes[3], "The first graph.", "the name is the file's");
    assert_eq!(notes[4], "");
    assert_eq!(describe(&work.join("notes.txt")), "");
    // Typing filters by label and note, any case; the parent goes while typing.
    b.query = "ALP".into();
    assert_eq!(labels(&b), [(EntryKind::File, "alpha.json".into())]);
    b.query = "ALPHA: the".into();
    assert_eq!(labels(&b), [], "a name that is the file's is not repeated");
    b.query = "second".into();
    assert_eq!(
        labels(&b),
        [],
        "only the first sentence is shown and searched"
    );
    b.query = "opened".into();
    assert_eq!(labels(&b)[0].0, EntryKind::Recent);
    // Enter on a folder enters it; Backspace on the empty filter goes back up.
    b.query = "sub".into();
    b.selected = 0;
    assert_eq!(b.key(Key::Enter), None);
    assert_eq!(b.dir(), work.join("sub"));
    assert_eq!(labels(&b)[2], (EntryKind::File, "gamma.json".into()));
    b.key(Key::Backspace);
    assert_eq!(b.dir(), work);
    // Down, Down, Enter: the second row after the recent file's.
    b.key(Key::ArrowDown);
    b.key(Key::ArrowDown);
    b.key(Key::ArrowDown);
    assert_eq!(
        b.key(Key::Enter),
        Some(Outcome::Open(work.join("alpha.json")))
    );
    // A typed path that no row matches: a folder is entered, a file opened.
    b.query = "sub/../sub".into();
    assert_eq!(b.key(Key::Enter), None);
    assert_eq!(b.dir(), work.join("sub"));
    b.query = "../beta.json".into();
    assert_eq!(
        b.key(Key::Enter),
        Some(Outcome::Open(work.join("beta.json")))
    );
    assert_eq!(b.key(Key::Escape), Some(Outcome::Cancel));
    // Kept inside a folder: no parent row there, no recent file outside it, no typed
    // path out of it.
    let mut inside = Browser::graphs(&work.join("sub"), &[recent]).within(&work);
    inside.key(Key::Backspace);
    assert_eq!(inside.dir(), work);
    assert!(
        labels(&inside)
            .iter()
            .all(|(k, _)| *k != EntryKind::Parent && *k != EntryKind::Recent)
    );
    inside.query = "../elsewhere/recent.json".into();
    assert_eq!(inside.key(Key::Enter), None);
    assert!(inside.error.as_deref().unwrap().contains("is outside"));
}

/// Ctrl+O opens the browser in the graph's folder with the recent files on top; keys alone
/// open a graph from it (type a filter, Enter into the folder, Down, Enter), and clicks alone
/// open a recent file (click its row, click Open). Escape closes it.
#[test]
fn ctrl_o_opens_a_graph_through_keys_alone_and_a_recent_file_through_clicks() {
    let (dir, work) = folders("keys");
    let recent = dir.join("elsewhere").join("recent.json");
    let mut state = EditorState::open(&work.join("beta.json"), Registry::builtin()).unwrap();
    state.recent = Some(Recent::load(&dir.join("config").join("recent.json")));
    state.recent.as_mut().unwrap().push(&recent).unwrap();
    let mut h = harness(state);
    h.run();
    h.key_press_modifiers(Modifiers::COMMAND, Key::O);
    h.run();
    match &h.state().state.dialog {
        Some(Dialog::Open { browser }) => assert_eq!(browser.dir(), work),
        other => panic!("Ctrl+O: {other:?}"),
    }
    // The rows, the recent file on top, each graph's name and doc beside it.
    h.get_by_label(recent.display().to_string().as_str());
    h.get_by_label("recent_one: Opened before.");
    h.get_by_label("sub/");
    h.get_by_label("The first graph.");
    assert!(h.query_by_label("notes.txt").is_none());
    // Keys alone: "su", Enter (into sub/), Down past the recent file and `..`, Enter
    // opens gamma.json.
    h.get_by_role(Role::TextInput).type_text("su");
    h.run();
    h.key_press(Key::Enter);
    h.run();
    for _ in 0..2 {
        h.key_press(Key::ArrowDown);
        h.run();
    }
    h.key_press(Key::Enter);
    h.run();
    let s = &h.state().state;
    assert!(s.dialog.is_none(), "{:?}", s.dialog);
    assert_eq!(
        s.path.as_deref(),
        Some(work.join("sub").join("gamma.json").as_path())
    );
    assert_eq!(s.doc.doc().name, "gamma");
    // Clicks alone: File → Open…, the recent file's row, Open.
    h.get_by_label("File").click();
    h.run();
    h.get_by_label("Open…  (Ctrl+O)").click();
    h.run();
    h.get_by_label(recent.display().to_string().as_str())
        .click();
    h.run();
    h.get_by_label("Open").click();
    h.run();
    let s = &h.state().state;
    assert!(s.dialog.is_none(), "{:?}", s.dialog);
    assert_eq!(s.path.as_deref(), Some(recent.as_path()));
    assert_eq!(s.doc.doc().name, "recent_one");
    // Escape closes it without opening anything.
    h.key_press_modifiers(Modifiers::COMMAND, Key::O);
    h.run();
    assert!(matches!(h.state().state.dialog, Some(Dialog::Open { .. })));
    h.key_press(Key::Escape);
    h.run();
    assert!(h.state().state.dialog.is_none());
    assert_eq!(h.state().state.path.as_deref(), Some(recent.as_path()));
}
