//! The editor readable at every zoom (issue 35, item 6), driven through egui_kittest: output
//! pin labels whole inside their node, a tooltip on every pin with its port's type, unit,
//! ranges and doc, the sign of a negative value drawn at every zoom, every character the
//! editor prints in its fonts, a graph opening at 1× (and File → New going back to 1×), and a
//! typed value that is not a number or is outside its input's hard range refused, with the
//! reason under the input and in the status line.
#![cfg(feature = "editor")]

use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use matgraph::Registry;
use matgraph::editor::{EditorApp, EditorState, entry, glyphs};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// A harness without a renderer on `file`, preview off, once its nodes are drawn and the
/// view fitted.
fn open(file: &Path) -> Harness<'static, EditorApp> {
    open_at(file, [1400.0, 900.0])
}

/// [`open`] in a window of `size` points.
fn open_at(file: &Path, size: [f32; 2]) -> Harness<'static, EditorApp> {
    let mut state = EditorState::open(file, Registry::builtin()).unwrap();
    state.dialog = None;
    state.preview.enabled = false;
    let mut h = Harness::builder()
        .with_size(egui::vec2(size[0], size[1]))
        .with_max_steps(64)
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), EditorApp::new(state));
    settle(&mut h);
    h
}

/// Steps `h` until its canvas is settled (at most a minute), and two frames more.
fn settle(h: &mut Harness<'static, EditorApp>) {
    let start = std::time::Instant::now();
    h.step();
    while !h.state().settled() && start.elapsed().as_secs() < 60 {
        h.step();
    }
    h.step();
    h.step();
}

/// A fresh folder under the target directory.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("editor_readable")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `nodes` (a JSON array) as a graph file in a fresh folder `name`.
fn graph_file(name: &str, nodes: serde_json::Value) -> PathBuf {
    let path = scratch(name).join("g.json");
    let doc = serde_json::json!({ "version": 1, "name": name, "nodes": nodes, "outputs": [] });
    std::fs::write(&path, serde_json::to_string_pretty(&doc).unwrap()).unwrap();
    path
}

/// The frame node `id` was drawn with in the last frame (canvas points).
fn frame_of(h: &Harness<'static, EditorApp>, id: &str) -> egui::Rect {
    h.state()
        .drawn_frames()
        .into_iter()
        .find(|(n, _)| *n == id)
        .unwrap_or_else(|| panic!("{id} not drawn"))
        .1
}

/// The rects (canvas points: egui-snarl's layer transform is not applied to them) of the
/// labels reading `text` whose centre lies in `frame`.
fn labels_in(h: &Harness<'static, EditorApp>, text: &str, frame: egui::Rect) -> Vec<egui::Rect> {
    h.query_all_by_label(text)
        .map(|n| n.rect())
        .filter(|r| frame.contains(r.center()))
        .collect()
}

/// Every output pin of every node of the bundled graphs `pbr_gold` (whose `geo` showed
/// `positio`, `norm`, a sliver of `view` and nothing of `light`, `uv`, `light_color`,
/// `screen_uv`, `depth`) and `toon_ball` has its whole label inside its node, clear of the
/// pin on the frame's right edge. Before the fix each output row pushed the next label a
/// pin's width further right (egui-snarl's inside placement), past the frame: `depth` began
/// 25 points right of `position`'s end.
#[test]
fn output_pin_labels_are_whole_inside_their_node() {
    let registry = Registry::builtin();
    let mut checked = 0;
    for file in ["graphs/pbr_gold.json", "graphs/toon_ball.json"] {
        // Wide enough for the whole graph at 1×, every node drawn.
        let h = open_at(Path::new(file), [3000.0, 1600.0]);
        let doc = h.state().state.doc.doc().clone();
        for n in &doc.nodes {
            let frame = frame_of(&h, &n.id);
            let Some(t) = registry.get(&n.node_type) else {
                continue;
            };
            for o in t.outputs() {
                let labels = labels_in(&h, o.name, frame);
                // An output label is right-aligned: right of the frame's centre.
                let label = labels
                    .iter()
                    .find(|r| r.max.x > frame.center().x)
                    .unwrap_or_else(|| {
                        panic!("{file}: {}.{}: no label in {frame:?}", n.id, o.name)
                    });
                // Whole inside the frame, and ending left of the pin (half of it inside
                // the frame, 10.8 points wide).
                assert!(
                    frame.contains_rect(*label) && label.max.x <= frame.max.x - 5.0,
                    "{file}: {}.{} label at {label:?}, frame {frame:?}",
                    n.id,
                    o.name
                );
                checked += 1;
            }
        }
    }
    assert!(checked >= 30, "{checked} labels");
}

/// Moves the pointer onto the pin of the row whose label is `label` (canvas rect) of the
/// node drawn at `frame`: on the frame's left edge for an input, its right edge for an
/// output, level with the label; then lets the tooltip's delay pass.
fn hover_pin(
    h: &mut Harness<'static, EditorApp>,
    frame: egui::Rect,
    label: egui::Rect,
    input: bool,
) {
    let x = if input { frame.min.x } else { frame.max.x };
    let at = h.state().to_screen() * egui::pos2(x, label.center().y);
    h.event(egui::Event::PointerMoved(at));
    for _ in 0..4 {
        h.step();
    }
}

/// Hovering a pin (not only its label) shows its port's type, unit, ranges and doc, as the
/// registry declares them: `brdf.metallic` (an input: slider range and hard range) and
/// `geo.view` (an output) of `pbr_gold`. Before the fix a pin had no tooltip.
#[test]
fn every_pin_has_a_tooltip_with_its_ports_type_unit_ranges_and_doc() {
    let mut h = open_at(Path::new("graphs/pbr_gold.json"), [3000.0, 1600.0]);
    let registry = Registry::builtin();
    let brdf = registry.get("pbr_brdf").unwrap();
    let metallic = &brdf.inputs()[brdf.input_index("metallic").unwrap()];
    let frame = frame_of(&h, "brdf");
    let label = labels_in(&h, "metallic", frame)[0];
    hover_pin(&mut h, frame, label, true);
    let tip = h
        .query_by_label_contains(metallic.doc)
        .map(|n| n.accesskit_node().value().unwrap_or_default())
        .expect("no tooltip on brdf.metallic's pin");
    for part in [
        "metallic".to_owned(),
        "float".to_owned(),
        entry::range(&metallic.soft.unwrap()),
        entry::range(&metallic.hard.unwrap()),
    ] {
        assert!(tip.contains(&part), "{part:?} not in {tip:?}");
    }
    // An output, with a unit: thin_film's reflectance has none, so geo.view (a vec3
    // direction) and the Material Output's pin.
    let geometry = registry.get("geometry").unwrap();
    let view = &geometry.outputs()[geometry.output_index("view").unwrap()];
    let frame = frame_of(&h, "geo");
    let label = labels_in(&h, "view", frame)[0];
    hover_pin(&mut h, frame, label, false);
    let tip = h
        .query_by_label_contains(view.doc)
        .map(|n| n.accesskit_node().value().unwrap_or_default())
        .expect("no tooltip on geo.view's pin");
    assert!(tip.contains("vec3") && tip.contains("output"), "{tip:?}");
}

/// Whether the GPU renderer can run here; panics when `MATGRAPH_REQUIRE_GPU` is set and not.
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

/// The width of the text in the number fields of the graph in `file` as drawn at `zoom`
/// (reached with a pinch from the 1× a small graph opens at), summed over the fields, in
/// pixels: the columns from the first to the last that hold a pixel lighter than the
/// field's darkest by at least 30 % of its lightest's lead (a faded stroke is not text).
fn text_width_at(file: &Path, zoom: f32) -> f32 {
    let mut state = EditorState::open(file, Registry::builtin()).unwrap();
    state.dialog = None;
    state.preview.enabled = false;
    let mut h = matgraph::editor::headless::harness(EditorApp::new(state), [900, 500]);
    settle(&mut h);
    // About the fields' centre, which stays in view.
    let t = h.state().to_screen();
    let fields = h
        .get_all_by_role(egui::accesskit::Role::SpinButton)
        .fold(egui::Rect::NOTHING, |r, n| r.union(t * n.rect()));
    h.event(egui::Event::PointerMoved(fields.center()));
    h.event(egui::Event::Zoom(zoom / h.state().to_screen().scaling));
    h.step();
    // Out of the picture (kittest draws the pointer).
    h.event(egui::Event::PointerGone);
    settle(&mut h);
    let t = h.state().to_screen();
    assert!((t.scaling / zoom - 1.0).abs() < 1e-3, "{t:?} for {zoom}");
    let fields: Vec<egui::Rect> = h
        .get_all_by_role(egui::accesskit::Role::SpinButton)
        .map(|n| (t * n.rect()).shrink(2.0))
        .collect();
    assert!(!fields.is_empty());
    let image = h.render().unwrap();
    let (w, hh) = image.dimensions();
    let lum = |x: u32, y: u32| {
        let p = image.get_pixel(x, y).0;
        0.2126 * f32::from(p[0]) + 0.7152 * f32::from(p[1]) + 0.0722 * f32::from(p[2])
    };
    let mut width = 0.0;
    for rect in fields {
        let xs = (rect.min.x.ceil().max(0.0) as u32)..(rect.max.x.floor().min(w as f32) as u32);
        let ys = (rect.min.y.ceil().max(0.0) as u32)..(rect.max.y.floor().min(hh as f32) as u32);
        // Each column's lightest pixel.
        let columns: Vec<f32> = xs
            .map(|x| ys.clone().map(|y| lum(x, y)).fold(0.0, f32::max))
            .collect();
        let floor = ys
            .clone()
            .flat_map(|y| {
                (rect.min.x.ceil() as u32..rect.max.x.floor() as u32).map(move |x| (x, y))
            })
            .map(|(x, y)| lum(x, y))
            .fold(f32::MAX, f32::min);
        let top = columns.iter().copied().fold(0.0, f32::max);
        let inked = |c: &f32| c - floor >= 0.3 * (top - floor);
        let first = columns.iter().position(inked).unwrap();
        let last = columns.iter().rposition(inked).unwrap();
        width += (last - first + 1) as f32;
    }
    width
}

/// `−1.00` keeps its sign at every zoom: the text of the number fields of a node with two
/// values of −1 is wider than that of the same node with values of 1 (by the two minus
/// signs), at each zoom by at least half of what it is at 1× scaled by the zoom. Before the
/// fix the canvas' glyphs were rasterised at 1× and scaled as images: at 0.5× and 0.68× the
/// minus (one texel high) was sampled between texels and faded or vanished
/// (`docs/editor.png`, at the 0.68× pbr_gold was framed at, showed `incident.b` as
/// `1.00 1.00 1.00`).
#[test]
fn a_negative_value_keeps_its_sign_at_every_zoom() {
    if !gpu_or_skip("a_negative_value_keeps_its_sign_at_every_zoom") {
        return;
    }
    let node = |v: f32| serde_json::json!([{ "id": "m", "type": "mul", "inputs": { "a": v, "b": v }, "position": [0.0, 0.0] }]);
    let minus = graph_file("sign_minus", node(-1.0));
    let plus = graph_file("sign_plus", node(1.0));
    let sign = |zoom: f32| text_width_at(&minus, zoom) - text_width_at(&plus, zoom);
    let at_1 = sign(1.0);
    assert!(
        at_1 >= 8.0,
        "two minus signs at 1× widen the text by only {at_1} pixels"
    );
    let mut report = Vec::new();
    for zoom in [0.5f32, 0.68, 0.8, 1.5, 2.0] {
        let ratio = sign(zoom) / (at_1 * zoom);
        report.push(format!("{zoom}×: {ratio:.2}"));
        assert!(ratio > 0.5, "the minus signs fade at {zoom}×: {report:?}");
    }
    println!("minus signs' width relative to 1×: {report:?}");
}

/// Every string and character literal of the Rust sources under `dir` (comments and
/// doc comments skipped), escapes decoded.
fn literals(dir: &Path, out: &mut BTreeSet<char>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            literals(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            lex(&std::fs::read_to_string(&p).unwrap(), out);
        }
    }
}

/// The characters of the string and character literals of Rust source `src`.
fn lex(src: &str, out: &mut BTreeSet<char>) {
    let s: Vec<char> = src.chars().collect();
    let mut i = 0;
    // An escape at `s[i]` (after the backslash): the character, and where it ends.
    let escape = |i: usize| -> (Option<char>, usize) {
        match s[i] {
            'n' | 't' | 'r' | '0' | '\\' | '\'' | '"' => (None, i + 1),
            'x' => (None, i + 3),
            'u' => {
                let end = (i..s.len()).find(|&k| s[k] == '}').unwrap();
                let hex: String = s[i + 2..end].iter().collect();
                (
                    char::from_u32(u32::from_str_radix(&hex, 16).unwrap()),
                    end + 1,
                )
            }
            // A line continuation: the newline and the next line's indentation.
            _ => (
                None,
                (i..s.len())
                    .find(|&k| !s[k].is_whitespace())
                    .unwrap_or(s.len()),
            ),
        }
    };
    while i < s.len() {
        match s[i] {
            '/' if s.get(i + 1) == Some(&'/') => {
                i = (i..s.len()).find(|&k| s[k] == '\n').unwrap_or(s.len());
            }
            '/' if s.get(i + 1) == Some(&'*') => {
                let mut depth = 0;
                while i < s.len() {
                    if s[i] == '/' && s.get(i + 1) == Some(&'*') {
                        depth += 1;
                        i += 2;
                    } else if s[i] == '*' && s.get(i + 1) == Some(&'/') {
                        depth -= 1;
                        i += 2;
                        if depth == 0 {
                            break;
                        }
                    } else {
                        i += 1;
                    }
                }
            }
            'r' if matches!(s.get(i + 1), Some('"' | '#'))
                && (i == 0 || !(s[i - 1].is_alphanumeric() || s[i - 1] == '_')) =>
            {
                let hashes = (i + 1..s.len()).take_while(|&k| s[k] == '#').count();
                let start = i + 1 + hashes + 1;
                let close: String = std::iter::once('"')
                    .chain(std::iter::repeat_n('#', hashes))
                    .collect();
                let rest: String = s[start..].iter().collect();
                let len = rest.find(&close).unwrap();
                out.extend(rest[..len].chars());
                i = start + rest[..len].chars().count() + close.len();
            }
            '"' => {
                i += 1;
                while s[i] != '"' {
                    if s[i] == '\\' {
                        let (c, next) = escape(i + 1);
                        out.extend(c);
                        i = next;
                    } else {
                        out.insert(s[i]);
                        i += 1;
                    }
                }
                i += 1;
            }
            '\'' if s.get(i + 1) == Some(&'\\') => {
                let (c, next) = escape(i + 2);
                out.extend(c);
                i = next + 1;
            }
            '\'' if s.get(i + 2) == Some(&'\'') => {
                out.insert(s[i + 1]);
                i += 3;
            }
            _ => i += 1,
        }
    }
}

/// The characters of every string in the JSON files under `dir`.
fn json_strings(dir: &Path, out: &mut BTreeSet<char>) {
    fn walk(v: &serde_json::Value, out: &mut BTreeSet<char>) {
        match v {
            serde_json::Value::String(s) => out.extend(s.chars()),
            serde_json::Value::Array(a) => a.iter().for_each(|v| walk(v, out)),
            serde_json::Value::Object(o) => o.iter().for_each(|(k, v)| {
                out.extend(k.chars());
                walk(v, out)
            }),
            _ => {}
        }
    }
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            json_strings(&p, out);
        } else if p.extension().is_some_and(|x| x == "json") {
            let v: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
            walk(&v, out);
        }
    }
}

/// Every character the editor can print: the literals of the sources (its labels, menus and
/// messages, the loader's and shader generator's messages it shows), every node type's
/// name, category, docs, muted rule, port names, units, docs and choices from the registry,
/// and the strings of the bundled graphs (ids, names, docs, parameter docs).
fn printed_chars() -> BTreeSet<char> {
    let mut chars = BTreeSet::new();
    literals(Path::new("src"), &mut chars);
    for t in Registry::builtin().types() {
        let muted = t.muted_rule();
        for s in [
            t.name(),
            t.category().name(),
            t.summary(),
            t.source_doc(),
            &muted,
        ] {
            chars.extend(s.chars());
        }
        for i in t.inputs() {
            for s in [i.name, i.unit, i.doc]
                .into_iter()
                .chain(i.choices.iter().copied())
            {
                chars.extend(s.chars());
            }
        }
        for o in t.outputs() {
            for s in [o.name, o.unit, o.doc] {
                chars.extend(s.chars());
            }
        }
    }
    json_strings(Path::new("graphs"), &mut chars);
    chars
}

/// Runs one frame of a bare context with `fonts` (so that they are loaded).
fn context_with(fonts: egui::FontDefinitions) -> egui::Context {
    let ctx = egui::Context::default();
    ctx.set_fonts(fonts);
    let mut out = ctx.run_ui(egui::RawInput::default(), |_| {});
    // No renderer takes the font atlas (epaint asserts it is taken).
    out.textures_delta.clear();
    ctx
}

/// Every character the editor prints has a glyph in its fonts (proportional, and monospace
/// for the generated code), none drawn as egui's replacement box. Before the fix the
/// registry's docs `Σ aᵢbᵢ` (dot), `Bₖ` (sellmeier) and `gainᵏ` (noise) had none; and
/// egui's default fonts alone lack the arrows and relations the messages use (→, ←, ∈),
/// which made `geometry.view □ dot.b`. The check fails where it should: '字' has no glyph.
#[test]
fn every_character_the_editor_prints_has_a_glyph() {
    let chars = printed_chars();
    let non_ascii: String = chars.iter().filter(|c| !c.is_ascii()).collect();
    for c in ['→', '−', '…', '∞', 'η', 'θ', '×', '▶', '⏸', '👁', '⚠'] {
        assert!(
            chars.contains(&c),
            "{c} not found among the printed characters {non_ascii}"
        );
    }
    let ctx = context_with(matgraph::editor::fonts());
    for family in [egui::FontFamily::Proportional, egui::FontFamily::Monospace] {
        let missing = glyphs::missing(&ctx, family.clone(), chars.iter().copied());
        assert!(
            missing.is_empty(),
            "{family:?} lacks {missing:?} (of {non_ascii})"
        );
    }
    let proportional = egui::FontFamily::Proportional;
    assert_eq!(
        glyphs::missing(&ctx, proportional.clone(), ['字', 'a']),
        ['字']
    );
    let bare = context_with(egui::FontDefinitions::default());
    let missing = glyphs::missing(&bare, proportional, chars.iter().copied());
    for c in ['→', '←', '∈', 'ᵢ', 'ₖ', 'ᵏ'] {
        assert!(
            missing.contains(&c),
            "egui's default fonts have {c}: {missing:?}"
        );
    }
}

/// A graph opens at 1× (egui-snarl scales text as images: sharp at 1× only): `toon_ball`,
/// which was framed whole at about 0.5×, opens at 1× on its outputs' end, the Material
/// Output node in view; and File → New (Ctrl+N) after a zoom out goes back to 1× (it kept
/// the old zoom).
#[test]
fn a_graph_opens_at_1x_and_a_new_graph_resets_the_zoom() {
    let mut h = open(Path::new("graphs/toon_ball.json"));
    let t = h.state().to_screen();
    assert_eq!(t.scaling, 1.0, "{t:?}");
    // The Material Output node (right of every node) is drawn in the canvas.
    let out = h.get_by_label("Material Output").rect();
    let canvas = egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1400.0, 900.0));
    assert!(canvas.contains_rect(t * out), "{:?}", t * out);
    // Zoom out with a pinch over the canvas, then Ctrl+N.
    h.event(egui::Event::PointerMoved(egui::pos2(500.0, 400.0)));
    h.event(egui::Event::Zoom(0.5));
    h.run_steps(2);
    assert!((h.state().to_screen().scaling - 0.5).abs() < 1e-3);
    h.key_press_modifiers(Modifiers::COMMAND, Key::N);
    settle(&mut h);
    assert!(h.state().state.doc.doc().nodes.is_empty());
    let t = h.state().to_screen();
    assert_eq!(t.scaling, 1.0);
    // The canvas' origin (where the first node and the Material Output node go) in view.
    assert!(canvas.contains(t * egui::Pos2::ZERO), "{t:?}");
}

/// A value typed into an input's editor that is not a number, or outside the input's hard
/// range, is refused: the graph is unchanged and the reason shows under the input and in
/// the status line; a good value then goes in and the reason goes away. `brdf.metallic`
/// (hard range 0…1): before the fix −5 went into the graph (the slider does not clamp what
/// is typed, and the loader then refused the graph) and "abc" silently reverted.
#[test]
fn a_typed_value_outside_the_hard_range_or_not_a_number_is_refused_with_the_reason() {
    let file = graph_file(
        "typed",
        serde_json::json!([{ "id": "brdf", "type": "pbr_brdf", "inputs": { "metallic": 0.25 }, "position": [0.0, 0.0] }]),
    );
    let mut h = open(&file);
    let metallic = |h: &Harness<'static, EditorApp>| {
        h.state().state.doc.doc().nodes[0]
            .inputs
            .get("metallic")
            .cloned()
    };
    let type_into = |h: &mut Harness<'static, EditorApp>, shown: &str, text: &str| {
        field(h, shown).focus();
        h.run_steps(2);
        field(h, shown).type_text(text);
        h.run_steps(1);
        h.key_press(Key::Enter);
        h.run_steps(3);
    };
    // The slider's number field (the slider itself has the same value).
    fn field<'h>(h: &'h Harness<'static, EditorApp>, shown: &str) -> egui_kittest::Node<'h> {
        h.get_all_by_role(egui::accesskit::Role::SpinButton)
            .find(|n| n.accesskit_node().value().as_deref() == Some(shown))
            .unwrap_or_else(|| panic!("no number field shows {shown}"))
    }
    let status =
        |h: &Harness<'static, EditorApp>| h.state().state.status.clone().unwrap_or_default();
    for (text, why) in [
        ("-5", "metallic: −5 is below the hard range 0 … 1"),
        ("1.5", "metallic: 1.5 is above the hard range 0 … 1"),
        ("abc", "metallic: \"abc\" is not a number"),
    ] {
        type_into(&mut h, "0.25", text);
        assert_eq!(metallic(&h), Some(serde_json::json!(0.25)), "{text}");
        assert!(h.state().state.doc.errors().is_empty(), "{text}");
        h.get_by_label(why);
        assert!(status(&h).contains(why), "{text}: {}", status(&h));
    }
    type_into(&mut h, "0.25", "0.75");
    assert_eq!(metallic(&h), Some(serde_json::json!(0.75)));
    assert!(
        h.query_by_label("metallic: \"abc\" is not a number")
            .is_none()
    );
}
