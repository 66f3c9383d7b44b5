//! Editor speed (issue 15, item 12), a `harness = false` main: the frame time of the
//! editor with a 300-node graph, the time from a parameter change to the new preview, and
//! from a structural edit (a literal baked into the shader) to the new preview, for the
//! bundled graphs: to the first pixels that show the edit (the draft, where the preview
//! drafts: `editor::preview`'s module doc) and to the full swatch. `cargo bench --bench
//! editor` measures; `cargo test` runs it once on a small graph and one bundled graph (a
//! check that it still works, no figures).
//!
//! The editor runs as in a window ([`Window`]: egui's pass on a plain `egui::Context` and
//! the tessellation of what it drew, without painting), and once more in egui_kittest's
//! harness for the frame time with the accessibility tree that the harness always builds.
//! The preview renders on the process-wide GPU context (lavapipe here) as in the window.

use egui_kittest::Harness;
use matgraph::Registry;
use matgraph::document::GraphDocument;
use matgraph::editor::{EditorApp, EditorState, preview_ui};
use std::path::Path;
use std::time::{Duration, Instant};

/// How the synthetic graph's nodes are placed.
#[derive(Clone, Copy, PartialEq)]
enum Placing {
    /// No positions: the editor lays them out by link depth, one column per node (a chain
    /// 300 columns wide; framed at egui-snarl's least zoom, 0.2×, about 25 are on screen).
    Arranged,
    /// In rows of [`GRID_COLUMNS`], 300 × 220 canvas points apart: framed at 0.2×, all 300
    /// are on screen.
    Grid,
}

/// Nodes per row of [`Placing::Grid`].
const GRID_COLUMNS: usize = 20;

/// A graph of `n` nodes: geometry, then `n − 1` generic `mul`/`add` nodes, each reading
/// the one before and one of the eight before it (a wide, deep canvas with many wires),
/// its last node the `emission` output.
fn synthetic(n: usize, placing: Placing) -> GraphDocument {
    let place = |k: usize| match placing {
        Placing::Arranged => serde_json::Value::Null,
        Placing::Grid => serde_json::json!([
            (k % GRID_COLUMNS) as f64 * 300.0,
            (k / GRID_COLUMNS) as f64 * 220.0
        ]),
    };
    let mut nodes = vec![serde_json::json!({"id": "n0", "type": "geometry", "position": place(0)})];
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
            "position": place(k),
        }));
    }
    let mut doc = serde_json::json!({
        "version": matgraph::FORMAT_VERSION,
        "name": format!("synthetic_{n}"),
        "nodes": nodes,
        "outputs": [{"name": "emission", "from": format!("n{}.result", n - 1)}],
    });
    if placing == Placing::Arranged {
        for node in doc["nodes"].as_array_mut().expect("nodes") {
            node.as_object_mut().expect("node").remove("position");
        }
    }
    GraphDocument::parse(&doc.to_string()).expect("the synthetic graph parses")
}

fn harness(state: EditorState) -> Harness<'static, EditorApp> {
    Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .with_max_steps(4)
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), framed(state))
}

/// The editor on `state`, framed whole (Home) as the figures were measured before a graph
/// opened at 1× (src/editor/first_view.rs): every node on the canvas.
fn framed(state: EditorState) -> EditorApp {
    let mut app = EditorApp::new(state);
    app.frame_all();
    app
}

/// The editor as in a window: its egui pass on a plain `egui::Context` (no accessibility
/// tree: eframe builds one only for a screen reader, where egui_kittest always does, at
/// about a third of its frame) plus the tessellation of what it drew, 1400 × 900 points at
/// 60 Hz of input time. Painting (the GPU's part) is left out.
struct Window {
    app: EditorApp,
    ctx: egui::Context,
    time: f64,
    /// The clock of the 60 Hz ticks.
    epoch: Instant,
    /// Frames 0.5 ms apart instead of at the ticks (`--unpaced`).
    unpaced: bool,
    /// Input events for the next frame.
    events: Vec<egui::Event>,
}

impl Window {
    fn new(state: EditorState) -> Window {
        Window {
            app: framed(state),
            ctx: egui::Context::default(),
            time: 0.0,
            epoch: Instant::now(),
            unpaced: std::env::args().any(|a| a == "--unpaced"),
            events: Vec::new(),
        }
    }

    /// One frame.
    fn frame(&mut self) {
        self.time += 1.0 / 60.0;
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(
                egui::Pos2::ZERO,
                egui::vec2(1400.0, 900.0),
            )),
            time: Some(self.time),
            events: std::mem::take(&mut self.events),
            ..Default::default()
        };
        let app = &mut self.app;
        let mut out = self.ctx.run_ui(input, |ui| app.ui(ui));
        // No renderer takes the font atlas' updates (epaint asserts they are taken).
        out.textures_delta.clear();
        let shapes = std::mem::take(&mut out.shapes);
        std::hint::black_box(self.ctx.tessellate(shapes, out.pixels_per_point));
    }

    /// Sleeps until the next 60 Hz tick of the window's clock: a window with vsync starts
    /// a frame there, the first after the last frame ended.
    fn next_tick(&self) {
        if self.unpaced {
            // As fast as the machine runs frames (the loop of earlier figures).
            std::thread::sleep(Duration::from_micros(500));
            return;
        }
        let now = self.epoch.elapsed();
        let ticks = (now.as_secs_f64() / FRAME.as_secs_f64()).floor() as u32 + 1;
        std::thread::sleep((FRAME * ticks).saturating_sub(now));
    }

    /// Frames at the ticks until `done` holds after one: the wall time from the first
    /// frame's start to the end of that frame.
    fn frames_until(&mut self, limit: Duration, done: impl Fn(&EditorApp) -> bool) -> Duration {
        self.next_tick();
        let start = Instant::now();
        self.frame();
        while !done(&self.app) {
            assert!(start.elapsed() < limit, "not done after {limit:?}");
            self.next_tick();
            self.frame();
        }
        start.elapsed()
    }

    /// Frames until the canvas and the preview are settled (the full swatch shown).
    fn settle(&mut self, limit: Duration) -> Duration {
        self.frames_until(limit, |a| a.state.preview.settled() && a.settled())
    }

    /// Frames at the ticks from the one that takes an edit made before it, until the
    /// swatch shows the edit (its draft, or the full swatch) and then until it is settled:
    /// (first pixels, full swatch), each as the time from the edit's frame's start to the
    /// end of the frame that shows it, in ms, and that frame's number (1: the next frame
    /// after the edit's).
    fn edit_to_preview(&mut self, limit: Duration) -> [(f64, u32); 2] {
        self.next_tick();
        let start = Instant::now();
        let mut first = None;
        let mut k = 0;
        loop {
            self.frame();
            let now = (ms(start.elapsed()), k);
            if first.is_none() && self.app.state.preview.current() {
                first = Some(now);
            }
            if let Some(first) = first
                && self.app.state.preview.settled()
                && self.app.settled()
            {
                return [first, now];
            }
            assert!(start.elapsed() < limit, "not shown after {limit:?}");
            self.next_tick();
            k += 1;
        }
    }
}

/// A 60 Hz display's frame.
const FRAME: Duration = Duration::from_micros(16_667);

/// The CPU time of this thread so far (user and system, in Linux's 10 ms clock ticks),
/// where /proc has it: a sum over many frames that other work on the machine does not
/// inflate as it does their wall time.
fn thread_cpu_time() -> Option<Duration> {
    let stat = std::fs::read_to_string("/proc/thread-self/stat").ok()?;
    // The fields after the command name: state is the first, utime the 12th, stime the 13th.
    let fields: Vec<&str> = stat.rsplit_once(')')?.1.split_whitespace().collect();
    let ticks: u64 = fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?;
    Some(Duration::from_millis(ticks * 10))
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
    let mut state = EditorState::new(synthetic(n, Placing::Arranged), None, Registry::builtin());
    state.dialog = None;
    state.preview.enabled = false;
    let mut h = harness(state);
    let start = Instant::now();
    h.step();
    while !(h.state().state.preview.settled() && h.state().settled()) {
        assert!(start.elapsed() < Duration::from_secs(600), "not settled");
        h.step();
    }
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

/// Frame time as in a window ([`Window`]) with an `n`-node graph placed by `placing`,
/// framed, then (given `zoom`) zoomed about the canvas' centre to that scale, its preview
/// on (settled: each frame asks it what is due), the pointer resting on the canvas' centre:
/// the median of `frames`, back to back. `whole`: egui-snarl is handed every node each
/// frame (`EditorApp::set_hand_off(false)`, the editor before the hand-off).
fn window_frame_time(n: usize, placing: Placing, zoom: Option<f32>, whole: bool, frames: usize) {
    let mut state = EditorState::new(synthetic(n, placing), None, Registry::builtin());
    state.dialog = None;
    let mut w = Window::new(state);
    w.app.set_hand_off(!whole);
    let open = w.settle(Duration::from_secs(600));
    let what = match placing {
        Placing::Arranged => "laid out",
        Placing::Grid => "in a grid",
    };
    if zoom.is_none() {
        println!(
            "open as in a window at 60 Hz, {n} nodes {what} (shown, framed, the preview rendered): {:.0} ms",
            ms(open)
        );
    }
    // The canvas spans x 0–1090 of the window; egui-snarl zooms about the pointer.
    w.events = vec![egui::Event::PointerMoved(egui::pos2(545.0, 450.0))];
    for _ in 0..4 {
        w.frame();
    }
    if let Some(zoom) = zoom {
        w.events = vec![egui::Event::Zoom(zoom / w.app.to_screen().scaling)];
        for _ in 0..4 {
            w.frame();
        }
    }
    let scale = w.app.to_screen().scaling;
    let mut times = Vec::new();
    let cpu = thread_cpu_time();
    for _ in 0..frames {
        let t = Instant::now();
        w.frame();
        times.push(ms(t.elapsed()));
    }
    let cpu = match (cpu, thread_cpu_time()) {
        (Some(a), Some(b)) => format!(", CPU {:.2} ms per frame", ms(b - a) / frames as f64),
        _ => String::new(),
    };
    let handed = match w.app.handed() {
        Some(k) => format!("{k} handed to egui-snarl"),
        None => "all handed to egui-snarl".to_owned(),
    };
    println!(
        "frame as in a window (egui pass + tessellation, no accessibility tree), {n} nodes {what} at {scale:.1}× ({handed}): median {:.2} ms, max {:.2} ms{cpu} ({frames} frames)",
        median(times.clone()),
        times.iter().copied().fold(0.0, f64::max)
    );
}

/// [`window_frame_time`] for the views of an `n`-node graph: laid out and framed; in a
/// grid framed whole (every node on screen); that grid zoomed in to 1× (a few nodes on
/// screen, in full detail); and the grid framed whole with every node handed to
/// egui-snarl, as before the hand-off.
fn window_views(n: usize, frames: usize) {
    window_frame_time(n, Placing::Arranged, None, false, frames);
    window_frame_time(n, Placing::Grid, None, false, frames);
    window_frame_time(n, Placing::Grid, Some(1.0), false, frames);
    window_frame_time(n, Placing::Grid, None, true, frames);
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
    let mut w = Window::new(state);
    let first = w.settle(Duration::from_secs(600));
    let backend = w.app.state.preview.backend().to_owned();
    if let Some(m) = w.app.state.preview.message() {
        println!("{name}: preview failed: {m}");
        return;
    }
    // Parameter change → new pixels: the same program, new uniforms.
    let mut param = Vec::new();
    if let Some((pname, node, default)) = params.first() {
        let v = default.as_f64().unwrap_or(0.0);
        let compiles = w.app.state.preview.compiles();
        for r in 0..reps {
            let value = if r % 2 == 0 { v * 0.97 } else { v };
            preview_ui::set_parameter(&mut w.app.state, pname, node, serde_json::json!(value));
            param.push(w.edit_to_preview(Duration::from_secs(120)));
        }
        assert_eq!(
            w.app.state.preview.compiles(),
            compiles,
            "{name}: a parameter change recompiled"
        );
    }
    // Structural edit → new pixels: a literal changed by 1 % (the first that keeps the
    // graph valid), a new program and pipeline.
    let mut structural = Vec::new();
    let doc = w.app.state.doc.doc().clone();
    for (node, input, v) in literals(&doc) {
        let compiles = w.app.state.preview.compiles();
        w.app
            .state
            .set_input(&node, &input, serde_json::json!(v * 0.99), None);
        if w.app.state.doc.graph().is_none() {
            w.app.state.undo();
            w.settle(Duration::from_secs(120));
            continue;
        }
        structural.push(w.edit_to_preview(Duration::from_secs(120)));
        assert!(w.app.state.preview.compiles() > compiles);
        for r in 1..reps {
            let value = if r % 2 == 0 { v * 0.99 } else { v };
            w.app
                .state
                .set_input(&node, &input, serde_json::json!(value), None);
            structural.push(w.edit_to_preview(Duration::from_secs(120)));
        }
        break;
    }
    // Medians of the first pixels and of the full swatch, and the most frames it took; the
    // first edit's time where it differs (a structural edit's new shader compiles its
    // pipelines, which the edits back and forth then reuse).
    let show = |v: &[[(f64, u32); 2]]| {
        let cell = |i: usize| {
            let m = median(v.iter().map(|p| p[i].0).collect());
            let first = match v.first() {
                Some(p) if (p[i].0 - m).abs() > 0.25 * m => format!(" (first {:.0} ms)", p[i].0),
                _ => String::new(),
            };
            // Where some edits took more than the next frame: how many of them did not.
            let next = v.iter().filter(|p| p[i].1 <= 1).count();
            let share = match next {
                n if n == v.len() || n == 0 => String::new(),
                n => format!(", {n} of {} in 1 f", v.len()),
            };
            format!(
                "{m:.0} ms, {} f{first}{share}",
                v.iter().map(|p| p[i].1).max().unwrap_or(0)
            )
        };
        match v.is_empty() {
            true => "- | -".to_owned(),
            false => format!("{} | {}", cell(0), cell(1)),
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
    // `--graphs a,b` (file stems) narrow a run; `--reps N` makes each kind of edit N times
    // per graph; `--nodes N --window-only` runs 400 window frames and nothing else (for a
    // profiler; `--grid` places the nodes in a grid, `--zoom Z` zooms to Z, `--whole` hands
    // egui-snarl every node).
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
        (Some(n), _) if args.iter().any(|a| a == "--window-only") => {
            let placing = match args.iter().any(|a| a == "--grid") {
                true => Placing::Grid,
                false => Placing::Arranged,
            };
            let zoom = value("--zoom").and_then(|z| z.parse().ok());
            let whole = args.iter().any(|a| a == "--whole");
            window_frame_time(n, placing, zoom, whole, 400);
            return;
        }
        (Some(n), _) => {
            frame_time(n, 20);
            window_views(n, 20);
        }
        (None, true) => {
            frame_time(300, 60);
            window_views(300, 60);
            frame_time(40, 60);
            window_frame_time(40, Placing::Arranged, None, false, 60);
        }
        (None, false) => {
            frame_time(30, 3);
            window_views(30, 3);
        }
    }
    println!(
        "Frames paced at 60 Hz. Each edit: the median time from the start of the frame that takes it to the end of the frame that shows it, and the most frames after that frame it took (1 f: the next frame).\n\n| graph | preview on | open → first preview | parameter change → first pixels | → full swatch | structural edit → first pixels | → full swatch |"
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
    // Edits per graph: `--reps N`, else 3 (1 in the quick check).
    let reps = value("--reps")
        .and_then(|v| v.parse().ok())
        .unwrap_or(if full || only.is_some() { 3 } else { 1 });
    for f in &files {
        graph_edits(f, reps);
    }
}
