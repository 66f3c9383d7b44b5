//! Textures in the editor (issue 35, item 3; `src/editor/textures.rs`, `textures_ui.rs`,
//! `thumbnails.rs`): an image picked through the in-app browser by keys and by clicks,
//! written relative to the graph file and shown by the preview; the colour space (`data`
//! read unchanged, the sRGB curve otherwise) moving a version-1 file to version 2; a missing
//! or undecodable file shown on the node; the picker kept inside the graph's folder; the
//! thumbnail cache; and a textured material built from an empty graph through editor
//! actions, rendered equal to a hand-written file.
#![cfg(feature = "editor")]

use egui::accesskit::Role;
use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::{By, Queryable};
use matgraph::Registry;
use matgraph::color_space::ColorSpace;
use matgraph::document::TextureSource;
use matgraph::editor::browser::{Browser, EntryKind};
use matgraph::editor::outputs::OUTPUT_NODE;
use matgraph::editor::state::Dialog;
use matgraph::editor::textures;
use matgraph::editor::thumbnails::{Status, THUMB_SIDE, Thumbnails};
use matgraph::editor::{EditorApp, EditorState};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// A fresh folder under the target directory.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("editor-textures")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A harness without a renderer; the preview on or off.
fn harness(mut state: EditorState, preview: bool) -> Harness<'static, EditorApp> {
    state.dialog = None;
    state.preview.enabled = preview;
    Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .with_max_steps(64)
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), EditorApp::new(state))
}

/// Steps `h` until `done` holds (at most two minutes).
fn step_until(
    h: &mut Harness<'static, EditorApp>,
    what: &str,
    done: impl Fn(&Harness<'static, EditorApp>) -> bool,
) {
    let start = Instant::now();
    h.step();
    while !done(h) {
        assert!(start.elapsed().as_secs() < 120, "waited for {what}");
        std::thread::sleep(Duration::from_millis(20));
        h.step();
    }
}

/// Steps `h` until the canvas and the preview are settled.
fn settle(h: &mut Harness<'static, EditorApp>) {
    step_until(h, "the preview", |h| {
        h.state().state.preview.settled() && h.state().settled()
    });
}

/// The colour stored in the test image (8-bit sRGB codes): dark enough that both readings,
/// decoded and as data, stay in the tone mapper's linear part at the preview's exposure.
const STORED: [u8; 3] = [90, 60, 30];

/// A `w` × `h` PNG of `f(x, y)`'s 8-bit RGB codes, stored as given.
fn png(path: &Path, w: u32, h: u32, f: impl Fn(u32, u32) -> [u8; 3]) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    let pixels: Vec<[u8; 3]> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| f(x, y))
        .collect();
    matgraph::image_io::save_png_rgb8(path, w, h, &pixels).unwrap();
}

/// The sRGB decoding of an 8-bit code, IEC 61966-2-1, in f64.
fn srgb_decode(code: u8) -> f64 {
    let c = code as f64 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The sRGB encoding of a linear value, IEC 61966-2-1, in f64.
fn srgb_encode(x: f64) -> f64 {
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// The display level (0–255, unrounded) of linear radiance `c` in the preview: exposure 1
/// (×2), Khronos PBR Neutral in its linear part (the black offset of the least channel; no
/// compression below a peak of 0.76), sRGB.
fn display(c: [f64; 3]) -> [f64; 3] {
    let c = c.map(|v| 2.0 * v);
    let x = c[0].min(c[1]).min(c[2]);
    let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
    let c = c.map(|v| v - offset);
    assert!(
        c.iter().all(|&v| v < 0.76),
        "the hand formula covers the linear part only: {c:?}"
    );
    c.map(|v| 255.0 * srgb_encode(v))
}

/// The preview's centre pixel (on the ball).
fn centre(h: &Harness<'static, EditorApp>) -> [u8; 3] {
    let p = h.state().state.preview.pixels().expect("a swatch").to_vec();
    let n = matgraph::editor::preview::SIZE as usize;
    let k = (n / 2 * n + n / 2) * 4;
    [p[k], p[k + 1], p[k + 2]]
}

/// Whether `got` is `want` within 1.5 levels a channel.
fn near(got: [u8; 3], want: [f64; 3]) -> bool {
    got.iter()
        .zip(want)
        .all(|(&g, w)| (g as f64 - w).abs() <= 1.5)
}

/// `dir/graph.json` (format `version`): geometry → `img` (an image_texture of `texture`,
/// if any) → the graph's `emission` (unlit, so the preview shows the image's values);
/// `dir/textures/` holds `orange.png` (4×4 of [`STORED`]), `blue.png` (2×2 blue) and a
/// `notes.txt`.
fn textured_folder(name: &str, version: u32, texture: Option<&str>) -> (PathBuf, PathBuf) {
    let dir = scratch(name);
    png(&dir.join("textures/orange.png"), 4, 4, |_, _| STORED);
    png(&dir.join("textures/blue.png"), 2, 2, |_, _| [10, 20, 200]);
    std::fs::write(dir.join("textures/notes.txt"), "not an image").unwrap();
    let mut img = serde_json::json!({
        "id": "img", "type": "image_texture",
        "inputs": { "uv": { "link": "geo.uv" } },
        "position": [260.0, 0.0]
    });
    if let Some(t) = texture {
        img["texture"] = serde_json::json!(t);
    }
    let graph = serde_json::json!({
        "version": version,
        "name": name,
        "nodes": [
            { "id": "geo", "type": "geometry", "position": [0.0, 0.0] },
            img
        ],
        "outputs": [{ "name": "emission", "from": "img.color" }]
    });
    let file = dir.join("graph.json");
    std::fs::write(&file, serde_json::to_string_pretty(&graph).unwrap()).unwrap();
    (dir, file)
}

/// The saved file's node `id`.
fn saved_node(file: &Path, id: &str) -> serde_json::Value {
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap();
    v["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|n| n["id"] == id)
        .cloned()
        .unwrap_or_else(|| panic!("no node '{id}' in {v}"))
}

/// Keys alone: the node's "pick an image…" button opens the picker in the graph's folder;
/// "tex", Enter enters `textures/`, Down Down passes `..` and `blue.png`, Enter picks
/// `orange.png`. The node's `texture` is `textures/orange.png` (relative to the graph file,
/// one undo step), the saved file says so, and the preview shows the image's colour: the
/// stored codes decoded by the sRGB curve (f64, here) and shown through the tone mapper.
/// Then clicks alone pick `blue.png` (its row, Pick).
#[test]
fn an_image_picked_by_keys_is_saved_relative_and_previewed() {
    let (dir, file) = textured_folder("pick-keys", 1, None);
    let state = EditorState::open(&file, Registry::builtin()).unwrap();
    let mut h = harness(state, true);
    settle(&mut h);
    assert!(
        h.state().state.preview.message().is_some(),
        "no image yet: the loader's error"
    );
    h.get_by_label("pick an image…").click_accesskit();
    h.run();
    match &h.state().state.dialog {
        Some(Dialog::PickTexture { node, browser }) => {
            assert_eq!(node, "img");
            assert_eq!(browser.dir(), dir);
            assert!(
                browser
                    .entries()
                    .iter()
                    .all(|e| e.kind != EntryKind::Parent),
                "no way up out of the graph's folder"
            );
        }
        other => panic!("the picker: {other:?}"),
    }
    h.get_by_label("Pick an image for 'img'");
    h.event(egui::Event::Text("tex".into()));
    h.run();
    h.key_press(Key::Enter);
    h.run();
    // The images' thumbnails and sizes fill in; the text file is not listed.
    step_until(&mut h, "the thumbnails", |h| {
        h.query_by_label("4×4").is_some() && h.query_by_label("2×2").is_some()
    });
    assert!(h.query_by_label("notes.txt").is_none());
    for _ in 0..2 {
        h.key_press(Key::ArrowDown);
        h.run();
    }
    h.key_press(Key::Enter);
    h.run();
    {
        let s = &h.state().state;
        assert!(s.dialog.is_none(), "{:?}", s.dialog);
        assert_eq!(
            s.doc.node("img").unwrap().texture,
            Some(TextureSource::Image("textures/orange.png".into()))
        );
        assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    }
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run();
    assert_eq!(saved_node(&file, "img")["texture"], "textures/orange.png");
    settle(&mut h);
    assert_eq!(h.state().state.preview.message(), None);
    let want = display(STORED.map(srgb_decode));
    let got = centre(&h);
    assert!(near(got, want), "the preview {got:?}, want {want:?}");
    // One undo step: undo takes the image away, redo brings it back.
    h.state_mut().state.undo();
    assert_eq!(h.state().state.doc.node("img").unwrap().texture, None);
    h.state_mut().state.redo();
    assert!(h.state().state.doc.node("img").unwrap().texture.is_some());
    // Clicks alone: the node's button (now the file's name), the folder's row, then the
    // image's row and Pick.
    h.get_by_label("orange.png").click_accesskit();
    h.run();
    match &h.state().state.dialog {
        Some(Dialog::PickTexture { browser, .. }) => {
            assert_eq!(browser.dir(), dir.join("textures"), "where its image is");
            let highlighted = &browser.entries()[browser.selected];
            assert_eq!(highlighted.label, "orange.png", "its row highlighted");
        }
        other => panic!("the picker: {other:?}"),
    }
    h.get_by_role_and_label(Role::Button, "blue.png").click();
    h.run();
    h.get_by_role_and_label(Role::Button, "Pick").click();
    h.run();
    let s = &h.state().state;
    assert!(s.dialog.is_none(), "{:?}", s.dialog);
    assert_eq!(
        s.doc.node("img").unwrap().texture,
        Some(TextureSource::Image("textures/blue.png".into()))
    );
}

/// The colour space from the node's drop-down: `data` reads the stored codes unchanged, so
/// the previewed level follows code/255 where the default followed the sRGB curve (both
/// written out here in f64). Choosing it moves the version-1 file to version 2; the saved
/// file has `"color_space": "data"` and reads back; undo restores version 1 and the field's
/// absence. "auto (srgb)" removes the field.
#[test]
fn the_data_colour_space_reads_codes_unchanged_and_moves_the_file_to_version_2() {
    let (_, file) = textured_folder("color-space", 1, Some("textures/orange.png"));
    let state = EditorState::open(&file, Registry::builtin()).unwrap();
    let mut h = harness(state, true);
    settle(&mut h);
    let decoded = display(STORED.map(srgb_decode));
    let srgb = centre(&h);
    assert!(near(srgb, decoded), "{srgb:?} vs {decoded:?}");
    h.get(By::new().role(Role::ComboBox).value("auto (srgb)"))
        .click_accesskit();
    h.run();
    h.get_by_role_and_label(Role::Button, "data").click();
    h.run();
    {
        let s = &h.state().state;
        let n = s.doc.node("img").unwrap();
        assert_eq!(n.color_space, Some(ColorSpace::Data));
        assert_eq!(s.doc.doc().version, 2, "color_space is a version-2 field");
        assert!(
            s.status.as_deref().unwrap().contains("format version 2"),
            "{:?}",
            s.status
        );
        assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    }
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run();
    assert_eq!(saved_node(&file, "img")["color_space"], "data");
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.contains("\"version\": 2"), "{text}");
    let g = matgraph::io::load_graph(&file, Registry::builtin()).expect("reads back");
    let img = &g.nodes()[g.node_index("img").unwrap()];
    assert_eq!(
        img.texture_key().as_deref(),
        Some("textures/orange.png#data")
    );
    settle(&mut h);
    let as_data = display(STORED.map(|c| c as f64 / 255.0));
    let data = centre(&h);
    assert!(near(data, as_data), "data: {data:?} vs {as_data:?}");
    assert!(
        data.iter().zip(srgb).all(|(d, s)| *d > s + 20),
        "data reads brighter than decoded: {data:?} vs {srgb:?}"
    );
    // Back to auto through the drop-down: the field goes (the version stays 2).
    h.get(By::new().role(Role::ComboBox).value("data"))
        .click_accesskit();
    h.run();
    h.get_by_role_and_label(Role::Button, "auto (srgb)").click();
    h.run();
    assert_eq!(h.state().state.doc.node("img").unwrap().color_space, None);
    // Undo twice: version 1 without the field, as opened.
    h.state_mut().state.undo();
    h.state_mut().state.undo();
    let s = &h.state().state;
    assert_eq!(s.doc.doc().version, 1);
    assert_eq!(s.doc.node("img").unwrap().color_space, None);
}

/// A primary click at what the accessibility tree puts at `rect` on the canvas (its rects
/// are in canvas coordinates there).
fn click_on_canvas(h: &mut Harness<'static, EditorApp>, rect: egui::Rect) {
    let at = h.state().to_screen() * rect.center();
    h.event(egui::Event::PointerMoved(at));
    h.run();
    for pressed in [true, false] {
        h.event(egui::Event::PointerButton {
            pos: at,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: Modifiers::default(),
        });
    }
    h.run();
}

/// The wrap and filter choices of a texture node are chosen on the node, as every enum
/// input is: a click on the drop-down, a click on the choice. (Before, the input's context
/// menu, attached to the drop-down's response, shared its popup's id and closed the list
/// as it opened: no enum could be chosen on the canvas.)
#[test]
fn wrap_and_filter_are_chosen_on_the_node() {
    let (_, file) = textured_folder("wrap", 1, Some("textures/orange.png"));
    let state = EditorState::open(&file, Registry::builtin()).unwrap();
    let mut h = harness(state, false);
    h.run();
    for (shown, pick, input) in [
        ("repeat", "clamp", "wrap"),
        ("bilinear", "nearest", "filter"),
    ] {
        let rect = h.get(By::new().role(Role::ComboBox).value(shown)).rect();
        click_on_canvas(&mut h, rect);
        h.get_by_role_and_label(Role::Button, pick).click();
        h.run();
        assert_eq!(h.state().state.doc.node("img").unwrap().inputs[input], pick);
    }
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run();
    let saved = saved_node(&file, "img");
    assert_eq!(
        (&saved["inputs"]["wrap"], &saved["inputs"]["filter"]),
        (&"clamp".into(), &"nearest".into())
    );
}

/// A texture whose file is missing shows "missing: PATH" in red on the node (inside its
/// drawn frame), one that is not an image shows its decode error, one outside the graph's
/// folder says so; a scene texture shows no image row at all.
#[test]
fn a_missing_or_undecodable_image_shows_on_the_node() {
    let dir = scratch("missing");
    std::fs::create_dir_all(dir.join("textures")).unwrap();
    std::fs::write(dir.join("textures/bad.png"), "not a png at all").unwrap();
    let node = |id: &str, x: f32, texture: &str| {
        serde_json::json!({
            "id": id, "type": "image_texture", "texture": texture, "position": [x, 0.0]
        })
    };
    let graph = serde_json::json!({
        "version": 2, "name": "missing",
        "nodes": [
            node("gone", 0.0, "textures/gone.png"),
            node("bad", 320.0, "textures/bad.png"),
            node("away", 640.0, "../away.png"),
            node("refr", 960.0, "scene:refraction")
        ]
    });
    let file = dir.join("graph.json");
    std::fs::write(&file, serde_json::to_string_pretty(&graph).unwrap()).unwrap();
    let state = EditorState::open(&file, Registry::builtin()).unwrap();
    let mut h = harness(state, false);
    step_until(&mut h, "the decode error", |h| {
        h.query_by_label_contains("textures/bad.png:").is_some()
    });
    h.run();
    let frame = |h: &Harness<'static, EditorApp>, id: &str| {
        h.state()
            .drawn_frames()
            .into_iter()
            .find(|(n, _)| *n == id)
            .map(|(_, r)| r)
            .unwrap_or_else(|| panic!("{id} is drawn"))
    };
    let on_node = |h: &Harness<'static, EditorApp>, text: &str, id: &str| {
        let r = h.get_by_label(text).rect();
        let f = frame(h, id);
        assert!(
            f.contains_rect(r),
            "'{text}' {r:?} inside {id}'s frame {f:?}"
        );
    };
    on_node(&h, "missing: textures/gone.png", "gone");
    on_node(&h, "outside the graph's folder: ../away.png", "away");
    let bad = h.get_by_label_contains("textures/bad.png:").rect();
    assert!(frame(&h, "bad").contains_rect(bad), "on its node");
    assert!(
        h.query_by_label_contains("textures/bad.png: cannot decode")
            .or(h.query_by_label_contains("textures/bad.png: unknown image format"))
            .is_some(),
        "the decode error"
    );
    // The scene texture's node has no image row (no button, no colour drop-down): three
    // drop-downs of colour space for the three file textures.
    let spaces = h
        .query_all(By::new().role(Role::ComboBox).value("auto (srgb)"))
        .count();
    assert_eq!(spaces, 3);
    // The same, from the library: the status of each node.
    let s = &h.state().state;
    let p = |id| textures::problem(&s.doc, Some(&file), id, |_| None);
    assert_eq!(p("gone").as_deref(), Some("missing: textures/gone.png"));
    assert_eq!(p("refr"), None);
    assert!(
        textures::problem(&s.doc, None, "gone", |_| None)
            .unwrap()
            .starts_with("untitled:")
    );
}

/// The picker stays inside the graph's folder: no `..` at its root, Backspace there stays,
/// a typed path out of it is refused, and a file reached through a symbolic link to a
/// folder outside is refused with the loader's message (nothing written). An untitled graph
/// has no folder: the picker asks for it to be saved first.
#[test]
fn the_picker_refuses_paths_outside_the_graphs_folder() {
    let (dir, file) = textured_folder("outside", 2, None);
    let outside = dir.parent().unwrap().join("outside-images");
    let _ = std::fs::remove_dir_all(&outside);
    png(&outside.join("far.png"), 2, 2, |_, _| [1, 2, 3]);
    let mut b = Browser::images(&dir, &dir, "img");
    assert!(b.entries().iter().all(|e| e.kind != EntryKind::Parent));
    b.key(Key::Backspace);
    assert_eq!(b.dir(), dir);
    b.query = "../outside-images/far.png".into();
    assert_eq!(b.key(Key::Enter), None);
    assert!(
        b.error.as_deref().unwrap().contains("is outside"),
        "{:?}",
        b.error
    );
    // Kept inside from its start: no `..` at the root (before, a browser made at its root
    // listed `..`, a way out).
    let graphs = Browser::graphs(&dir, &[]).within(&dir);
    assert!(graphs.entries().iter().all(|e| e.kind != EntryKind::Parent));
    // A folder outside the root is not entered either: the browser starts at the root.
    assert_eq!(Browser::images(&outside, &dir, "img").dir(), dir);
    // The reference of a file outside, and one through a link out of the folder.
    assert!(textures::reference_of(&file, "img", &outside.join("far.png")).is_err());
    assert_eq!(
        textures::reference_of(&file, "img", &dir.join("textures/./orange.png")),
        Ok("textures/orange.png".to_owned())
    );
    let mut s = EditorState::open(&file, Registry::builtin()).unwrap();
    s.dialog = None;
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(&outside, dir.join("linked")).unwrap();
        let before = s.doc.canonical_json();
        let why = textures::pick(&mut s, "img", &dir.join("linked/far.png")).unwrap_err();
        assert!(why.contains("outside the graph's folder"), "{why}");
        assert_eq!(s.doc.canonical_json(), before, "nothing written");
        // Through the dialog: the refusal is shown in the browser, which stays open.
        let mut h = harness(s, false);
        textures::open_picker(&mut h.state_mut().state, "img");
        h.run();
        h.event(egui::Event::Text("linked/far.png".into()));
        h.run();
        h.key_press(Key::Enter);
        h.run();
        assert!(matches!(
            h.state().state.dialog,
            Some(Dialog::PickTexture { .. })
        ));
        h.get_by_label_contains("outside the graph's folder");
        assert_eq!(h.state().state.doc.node("img").unwrap().texture, None);
    }
    // An untitled graph: no picker, the status line says why.
    let mut u = EditorState::untitled(Registry::builtin());
    u.dialog = None;
    let id = u.add_node("image_texture", [0.0, 0.0]).unwrap();
    textures::open_picker(&mut u, &id);
    assert!(u.dialog.is_none());
    assert!(
        u.status
            .as_deref()
            .unwrap()
            .contains("save the graph first")
    );
}

/// Waits for the cache's decode of `path` and returns the thumbnail's size and texels.
fn ready(t: &mut Thumbnails, path: &Path) -> ([usize; 2], [u32; 2], Vec<u8>) {
    let start = Instant::now();
    loop {
        match t.get(path) {
            Status::Ready(th) => return (th.size, [th.width, th.height], th.rgba.clone()),
            Status::Failed(why) => panic!("{}: {why}", path.display()),
            Status::Pending => {
                assert!(
                    start.elapsed().as_secs() < 60,
                    "decoding {}",
                    path.display()
                );
                std::thread::sleep(Duration::from_millis(5));
            }
        }
    }
}

/// The thumbnail cache: a 96×48 image becomes a 48×24 thumbnail whose texels are the mean
/// of each 2×2 block in linear light, re-encoded to sRGB (written out here in f64); asking
/// again decodes nothing; the file saved again (a new length and time) is decoded again; a
/// missing file fails at once, without a decode; a file that is not an image fails with
/// its decode error.
#[test]
fn thumbnails_are_box_filtered_and_decoded_once_per_file_version() {
    let dir = scratch("thumbnails");
    let path = dir.join("wide.png");
    let code = |x: u32, y: u32| [(x * 2 + y) as u8, (255 - x) as u8, ((x * y) % 256) as u8];
    png(&path, 96, 48, code);
    let mut t = Thumbnails::new();
    assert!(matches!(t.get(&path), Status::Pending));
    let (size, dims, rgba) = ready(&mut t, &path);
    assert_eq!((size, dims), ([THUMB_SIDE as usize, 24], [96, 48]));
    for ty in 0..24u32 {
        for tx in 0..48u32 {
            for c in 0..3 {
                let mean = [(0, 0), (1, 0), (0, 1), (1, 1)]
                    .iter()
                    .map(|(dx, dy)| srgb_decode(code(2 * tx + dx, 2 * ty + dy)[c]))
                    .sum::<f64>()
                    / 4.0;
                let want = (255.0 * srgb_encode(mean)).round();
                let got = rgba[((ty * 48 + tx) * 4) as usize + c] as f64;
                assert!(
                    (got - want).abs() <= 1.0,
                    "({tx}, {ty}) channel {c}: {got} vs {want}"
                );
            }
            assert_eq!(rgba[((ty * 48 + tx) * 4 + 3) as usize], 255);
        }
    }
    assert_eq!(t.decodes(), 1);
    for _ in 0..3 {
        assert!(matches!(t.get(&path), Status::Ready(_)));
    }
    assert_eq!(t.decodes(), 1, "the same file version is decoded once");
    // Saved again: another size and a later time.
    png(&path, 20, 10, |_, _| [255, 0, 0]);
    let later = std::time::SystemTime::now() + Duration::from_secs(5);
    std::fs::File::options()
        .write(true)
        .open(&path)
        .unwrap()
        .set_modified(later)
        .unwrap();
    let (size, dims, rgba) = ready(&mut t, &path);
    assert_eq!((size, dims), ([20, 10], [20, 10]));
    assert_eq!(&rgba[..4], &[255, 0, 0, 255]);
    assert_eq!(t.decodes(), 2);
    // Missing: at once, no decode.
    assert!(matches!(
        t.get(&dir.join("nope.png")),
        Status::Failed("missing")
    ));
    assert_eq!(t.decodes(), 2);
    std::fs::write(dir.join("bad.png"), "text").unwrap();
    let start = Instant::now();
    let why = loop {
        match t.get(&dir.join("bad.png")) {
            Status::Failed(why) => break why.to_owned(),
            Status::Ready(_) => panic!("text decoded as an image"),
            Status::Pending => {
                assert!(start.elapsed().as_secs() < 60);
                std::thread::sleep(Duration::from_millis(5));
            }
        }
    };
    assert!(
        why.contains("unknown image format") || why.contains("cannot decode"),
        "{why}"
    );
}

/// The Done-when's second test (issue 35): a textured material built from an empty graph
/// through editor actions alone. The search adds `geometry` (Shift+A, typing, Enter); wires
/// dropped from `geometry.uv` and from the new `mapping`'s vector add `mapping` (Blender's
/// Mapping: the uv enters as `(u, v, 0)`) and `image_texture` (which reads the vector's
/// `xy`), connected; `mapping.scale` is set to (3, 2, 1) and exposed as the parameter
/// `tiling`; the image is
/// picked through the browser (keys); the Material Output node is added through the search
/// and `image_texture.color` wired into its `color`. The saved file renders exactly as a
/// hand-written equivalent (other ids' order and positions, written out below), and a
/// different tiling renders differently.
#[test]
fn a_textured_material_built_from_an_empty_graph_renders_as_the_hand_written_file() {
    use matgraph::SocketType;
    use matgraph::editor::search::WireFilter;
    use matgraph::editor::search_ui::SearchState;
    let dir = scratch("material");
    // A 4×4 checker of two colours, so that the tiling shows.
    png(&dir.join("textures/checker.png"), 4, 4, |x, y| {
        match (x + y) % 2 {
            0 => [220, 180, 40],
            _ => [30, 60, 150],
        }
    });
    let file = dir.join("material.json");
    let state = matgraph::editor::state_for(Some(&file)).unwrap();
    let mut h = harness(state, false);
    h.run();
    let search = |h: &mut Harness<'static, EditorApp>, text: &str| {
        h.event(egui::Event::Text(text.into()));
        h.run();
        h.key_press(Key::Enter);
        h.run();
    };
    h.key_press_modifiers(Modifiers::SHIFT, Key::A);
    h.run();
    search(&mut h, "geometry");
    // What the canvas does with a wire dropped in empty space (its search, filtered).
    let drop_wire = |h: &mut Harness<'static, EditorApp>,
                     node: &str,
                     port: &str,
                     at: [f32; 2],
                     ty: SocketType| {
        h.state_mut().state.search = Some(SearchState {
            query: String::new(),
            pos: at,
            wire: Some((node.into(), port.into(), WireFilter::InputAccepting(ty))),
            selected: 0,
        });
        h.run();
    };
    drop_wire(&mut h, "geometry", "uv", [260.0, 0.0], SocketType::Vec2);
    search(&mut h, "mapping");
    drop_wire(&mut h, "mapping", "vector", [520.0, 0.0], SocketType::Vec3);
    search(&mut h, "image_texture");
    {
        let s = &h.state().state;
        assert_eq!(s.doc.link("mapping", "vector"), Some("geometry.uv"));
        assert_eq!(s.doc.link("image_texture", "uv"), Some("mapping.vector"));
    }
    // The image, through the picker (keys).
    h.get_by_label("pick an image…").click_accesskit();
    h.run();
    search(&mut h, "textures");
    search(&mut h, "checker");
    assert!(h.state().state.dialog.is_none());
    // The tiling: a value edited on the node, then exposed (its right-click menu).
    h.state_mut()
        .state
        .set_input("mapping", "scale", serde_json::json!([3.0, 2.0, 1.0]), None);
    assert_eq!(
        h.state_mut()
            .state
            .expose_input("mapping", "scale", Some("tiling")),
        Ok("tiling".into())
    );
    // The output: the Material Output node from the search, a color pin, the wire.
    h.key_press_modifiers(Modifiers::SHIFT, Key::A);
    h.run();
    search(&mut h, "output");
    {
        let s = &mut h.state_mut().state;
        s.add_output("color").unwrap();
        s.connect("image_texture", "color", OUTPUT_NODE, "color")
            .unwrap();
        assert!(s.doc.errors().is_empty(), "{:?}", s.doc.errors());
    }
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run();
    assert!(!h.state().state.dirty(), "{:?}", h.state().state.status);
    let saved = matgraph::io::load_graph(&file, Registry::builtin()).expect("the saved file loads");
    assert_eq!(
        saved_node(&file, "image_texture")["texture"],
        "textures/checker.png"
    );
    let hand = |tiling: [f32; 3]| {
        serde_json::json!({
            "version": 1,
            "name": "hand-written",
            "nodes": [
                { "id": "tex", "type": "image_texture", "texture": "textures/checker.png",
                  "inputs": { "uv": { "link": "map.vector" } } },
                { "id": "map", "type": "mapping",
                  "inputs": { "vector": { "link": "g.uv" }, "scale": { "link": "tile.value" } } },
                { "id": "tile", "type": "parameter", "inputs": { "value": tiling } },
                { "id": "g", "type": "geometry" }
            ],
            "outputs": [{ "name": "color", "from": "tex.color" }],
            "parameters": [{ "name": "tiling", "node": "tile" }]
        })
    };
    let render = |text: &serde_json::Value, name: &str| {
        let path = dir.join(name);
        std::fs::write(&path, serde_json::to_string_pretty(text).unwrap()).unwrap();
        let g = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        pixels(&g, &path)
    };
    let ours = pixels(&saved, &file);
    assert!(
        ours == render(&hand([3.0, 2.0, 1.0]), "hand.json"),
        "the same material: {}",
        std::fs::read_to_string(&file).unwrap()
    );
    assert!(
        ours != render(&hand([1.0, 1.0, 1.0]), "hand_untiled.json"),
        "the tiling shows"
    );
    let distinct: std::collections::BTreeSet<[u8; 3]> = ours.iter().copied().collect();
    assert!(
        distinct.len() > 20,
        "a textured, lit ball: {} colours",
        distinct.len()
    );
}

/// `graph` (next to `file`) rendered on the CPU at 64×64 in the ball scene.
fn pixels(graph: &matgraph::Graph, file: &Path) -> Vec<[u8; 3]> {
    use matgraph::render::{RenderOptions, render};
    let scene = matgraph::scene::Scene::preset("ball").unwrap();
    let textures = matgraph::image_io::load_graph_textures(graph, file).unwrap();
    let options = RenderOptions {
        width: 64,
        height: 64,
        textures: Some(std::sync::Arc::new(textures)),
        ..Default::default()
    };
    render(graph, &scene, &options)
        .unwrap()
        .to_srgb8(0.0)
        .pixels
}
