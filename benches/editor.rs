//! Editor speed (issue 15, item 12), a `harness = false` main: the frame time of the
//! editor with a 300-node graph, the time from a parameter change to the new preview, and
//! from a structural edit (a literal baked into the shader) to the new preview, for the
//! bundled graphs: to the first pixels that show the edit (the draft, where the preview
//! drafts: `editor::preview`'s module doc) and to the full swatch. `cargo bench --bench editor` measures; `cargo test` runs it once on a
//! small graph and one bundled graph (a check that it still works, no figures).
//!
//! The editor runs in egui_kittest's harness without a renderer: a frame is egui's pass
//! (layout of the panels and the canvas, the snarl viewer, the validation and code
//! generation the frame asks for), without tessellation and painting. The preview renders
//! on the process-wide GPU context (lavapipe here) as in the window.

use egui_kittest::Harness;
use matgraph::Registry;
use matgraph::document::GraphDocument;
use matgraph::editor::{EditorApp, EditorState, preview_ui};
use std::path::Path;
use std::time::{Duration, Instant};

/// A graph of `n` nodes: geometry, then `n − 1` generic `mul`/`add` nodes, each reading
/// the one before and one of the eight before it (a wide, deep canvas with many wires),
/// its last node the `emission` output.
fn synthetic(n: usize) -> GraphDocument {
    let mut nodes = vec![serde_json::json!({"id": "n0", "type": "geometry"})];
    for k in 1..n {
        let a = if k == 1 {
            "n0.uv".to_owned()
        } else {
            format!("n{}.result", k - 1)
        };
        let b = if k > 8 && k % 3 == 0 {
            serde_json::json!({"link": format!("n{}.result", k - 8)})
        } else {
            serde_json::json!(0.5 + (k % 7) as f64 * 0.0625)
        };
        nodes.push(serde_json::json!({
            "id": format!("n{k}"),
            "type": if k % 2 == 0 { "add" } else { "mul" },
            "inputs": {"a": {"link": a}, "b": b},
        }));
    }
    let doc = serde_json::json!({
        "version": matgraph::FORMAT_VERSION,
        "name": format!("synthetic_{n}"),
        "nodes": nodes,
        "outputs": [{"name": "emission", "from": format!("n{}.result", n - 1)}],
    });
    GraphDocument::parse(&doc.to_string()).expect("the synthetic graph parses")
}

fn harness(state: EditorState) -> Harness<'static, EditorApp> {
    Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .with_max_steps(4)
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), EditorApp::new(state))
}

/// Steps until `done` holds after a step; the wall time it took.
fn step_until(
    h: &mut Harness<'static, EditorApp>,
    limit: Duration,
    done: impl Fn(&EditorApp) -> bool,
) -> Duration {
    let start = Instant::now();
    h.step();
    while !done(h.state()) {
        assert!(start.elapsed() < limit, "not done after {limit:?}");
        std::thread::sleep(Duration::from_micros(500));
        h.step();
    }
    start.elapsed()
}

/// Steps until the canvas and the preview are settled (the full swatch shown).
fn settle(h: &mut Harness<'static, EditorApp>, limit: Duration) -> Duration {
    step_until(h, limit, |a| a.state.preview.settled() && a.settled())
}

/// Steps until the swatch shows the edit (its draft, or the full swatch), then until it is
/// settled: (first pixels, full swatch).
fn edit_to_preview(h: &mut Harness<'static, EditorApp>, limit: Duration) -> (f64, f64) {
    let first = step_until(h, limit, |a| a.state.preview.current());
    let rest = match h.state().state.preview.settled() && h.state().settled() {
        true => Duration::ZERO,
        false => settle(h, limit),
    };
    (ms(first), ms(first + rest))
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Frame time with an `n`-node graph, all nodes on screen (framed): the median of `frames`.
fn frame_time(n: usize, frames: usize) {
    let mut state = EditorState::new(synthetic(n), None, Registry::builtin());
    state.dialog = None;
    state.preview.enabled = false;
    let mut h = harness(state);
    settle(&mut h, Duration::from_secs(600));
    let mut times = Vec::new();
    for _ in 0..frames {
        let t = Instant::now();
        h.step();
        times.push(ms(t.elapsed()));
    }
    println!(
        "frame, {n} nodes framed: median {:.2} ms, max {:.2} ms ({frames} frames)",
        median(times.clone()),
        times.iter().copied().fold(0.0, f64::max)
    );
}

/// Frame time as in a window: the editor's egui pass on a plain `egui::Context` (no
/// accessibility tree: eframe builds one only for a screen reader, where egui_kittest
/// always does, at about a third of its frame) plus the tessellation of what it drew, for
/// an `n`-node graph framed; the median of `frames`. Painting (the GPU's part) is left out.
fn window_frame_time(n: usize, frames: usize) {
    let mut state = EditorState::new(synthetic(n), None, Registry::builtin());
    state.dialog = None;
    state.preview.enabled = false;
    let mut app = EditorApp::new(state);
    let ctx = egui::Context::default();
    let mut time = 0.0;
    let mut frame = |app: &mut EditorApp| {
        time += 1.0 / 60.0;
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(
                egui::Pos2::ZERO,
                egui::vec2(1400.0, 900.0),
            )),
            time: Some(time),
            ..Default::default()
        };
        let mut out = ctx.run_ui(input, |ui| app.ui(ui));
        // No renderer takes the font atlas' updates (epaint asserts they are taken).
        out.textures_delta.clear();
        let shapes = std::mem::take(&mut out.shapes);
        std::hint::black_box(ctx.tessellate(shapes, out.pixels_per_point));
    };
    let start = Instant::now();
    while !app.settled() {
        assert!(start.elapsed() < Duration::from_secs(600), "not settled");
        frame(&mut app);
    }
    for _ in 0..4 {
        frame(&mut app);
    }
    let mut times = Vec::new();
    for _ in 0..frames {
        let t = Instant::now();
        frame(&mut app);
        times.push(ms(t.elapsed()));
    }
    println!(
        "frame as in a window (egui pass + tessellation, no accessibility tree), {n} nodes framed: median {:.2} ms, max {:.2} ms ({frames} frames)",
        median(times.clone()),
        times.iter().copied().fold(0.0, f64::max)
    );
}

/// The first numeric literal of a node that is not a `parameter`: (node, input, value).
fn literals(doc: &GraphDocument) -> Vec<(String, String, f64)> {
    doc.nodes
        .iter()
        .filter(|n| n.node_type != "parameter")
        .flat_map(|n| {
            n.inputs
                .iter()
                .filter_map(|(k, v)| Some((n.id.clone(), k.clone(), v.as_f64()?)))
        })
        .collect()
}

/// Parameter change → preview, and structural edit → preview, for one graph file.
fn graph_edits(file: &Path, reps: usize) {
    let name = file.file_stem().unwrap().to_string_lossy().into_owned();
    let mut state = match EditorState::open(file, Registry::builtin()) {
        Ok(s) => s,
        Err(e) => {
            println!("{name}: {e}");
            return;
        }
    };
    state.dialog = None;
    let params: Vec<(String, String, serde_json::Value)> = state
        .doc
        .graph()
        .map(|g| {
            g.parameters()
                .iter()
                .filter(|p| p.ty == matgraph::SocketType::Float)
                .map(|p| {
                    let node = g.nodes()[p.node].id.clone();
                    (
                        p.name.clone(),
                        node,
                        serde_json::json!(p.default.lanes()[0]),
                    )
                })
                .collect()
        })
        .unwrap_or_default();
    let mut h = harness(state);
    let first = settle(&mut h, Duration::from_secs(600));
    let backend = h.state().state.preview.backend().to_owned();
    if let Some(m) = h.state().state.preview.message() {
        println!("{name}: preview failed: {m}");
        return;
    }
    // Parameter change → new pixels: the same program, new uniforms.
    let mut param = Vec::new();
    if let Some((pname, node, default)) = params.first() {
        let v = default.as_f64().unwrap_or(0.0);
        let compiles = h.state().state.preview.compiles();
        for r in 0..reps {
            let value = if r % 2 == 0 { v * 0.97 } else { v };
            preview_ui::set_parameter(
                &mut h.state_mut().state,
                pname,
                node,
                serde_json::json!(value),
            );
            param.push(edit_to_preview(&mut h, Duration::from_secs(120)));
        }
        assert_eq!(
            h.state().state.preview.compiles(),
            compiles,
            "{name}: a parameter change recompiled"
        );
    }
    // Structural edit → new pixels: a literal changed by 1 % (the first that keeps the
    // graph valid), a new program and pipeline.
    let mut structural = Vec::new();
    let doc = h.state().state.doc.doc().clone();
    for (node, input, v) in literals(&doc) {
        let compiles = h.state().state.preview.compiles();
        h.state_mut()
            .state
            .set_input(&node, &input, serde_json::json!(v * 0.99), None);
        if h.state().state.doc.graph().is_none() {
            h.state_mut().state.undo();
            settle(&mut h, Duration::from_secs(120));
            continue;
        }
        structural.push(edit_to_preview(&mut h, Duration::from_secs(120)));
        assert!(h.state().state.preview.compiles() > compiles);
        for r in 1..reps {
            let value = if r % 2 == 0 { v * 0.99 } else { v };
            h.state_mut()
                .state
                .set_input(&node, &input, serde_json::json!(value), None);
            structural.push(edit_to_preview(&mut h, Duration::from_secs(120)));
        }
        break;
    }
    // Medians of the first pixels and of the full swatch.
    let show = |v: &[(f64, f64)]| {
        if v.is_empty() {
            "- | -".to_owned()
        } else {
            format!(
                "{:.0} ms | {:.0} ms",
                median(v.iter().map(|p| p.0).collect()),
                median(v.iter().map(|p| p.1).collect())
            )
        }
    };
    // The edits' autosave is not the bundled file's.
    matgraph::editor::files::discard_recovery(Some(file));
    println!(
        "| {name} | {} | {:.0} ms | {} | {} |",
        backend.split(" (").next().unwrap_or(&backend),
        ms(first),
        show(&param),
        show(&structural)
    );
}

fn main() {
    // `cargo bench` passes --bench; `cargo test` runs the quick check. `--nodes N` and
    // `--graphs a,b` (file stems) narrow a run.
    let args: Vec<String> = std::env::args().collect();
    let full = args.iter().any(|a| a == "--bench");
    let value = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|k| args.get(k + 1).cloned())
    };
    let nodes: Option<usize> = value("--nodes").and_then(|v| v.parse().ok());
    let only: Option<Vec<String>> =
        value("--graphs").map(|v| v.split(',').map(str::to_owned).collect());
    match (nodes, full) {
        (Some(n), _) => {
            frame_time(n, 20);
            window_frame_time(n, 20);
        }
        (None, true) => {
            frame_time(300, 60);
            window_frame_time(300, 60);
            frame_time(40, 60);
            window_frame_time(40, 60);
        }
        (None, false) => {
            frame_time(30, 3);
            window_frame_time(30, 3);
        }
    }
    println!(
        "| graph | preview on | open → first preview | parameter change → first pixels | → full swatch | structural edit → first pixels | → full swatch |"
    );
    println!("| --- | --- | ---: | ---: | ---: | ---: | ---: |");
    let mut files: Vec<_> = std::fs::read_dir("graphs")
        .expect("run from the repository root")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    match &only {
        Some(names) => files.retain(|f| {
            f.file_stem()
                .is_some_and(|s| names.iter().any(|n| s.to_string_lossy() == n.as_str()))
        }),
        None if !full => files.retain(|f| f.ends_with("pbr_gold.json")),
        None => {}
    }
    for f in &files {
        graph_edits(f, if full || only.is_some() { 3 } else { 1 });
    }
}
