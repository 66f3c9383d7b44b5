//! The live preview: the graph rendered in its scene (ball, water, bubble) by
//! [`crate::render`] on the GPU rasteriser (`Backend::Gpu`, the process-wide
//! [`GpuContext`]), or by the CPU renderer when there is no adapter, off the UI thread. The
//! pixels are uploaded as an egui texture.
//!
//! A render is keyed by what it shows ([`Request`]): the graph's *structure* (the document
//! without node positions and without the values of exposed parameters), the parameter
//! values, the orbit camera, the time and the size. The graph a slot renders (its
//! *program*) is rebuilt only when the structure changes ([`Preview::compiles`] counts the
//! rebuilds); a parameter change renders the same program with new [`crate::ParamValues`],
//! which the GPU path writes into the parameter uniform of the pipeline it already has
//! (cached by its shader source) and the CPU path passes to the executor.
//!
//! Besides the main swatch, any node can have a swatch of its own ([`Preview::toggle_node`],
//! as in Blender): the graph cut at the node's first output ([`cut_at`]).
//!
//! **Drafts.** Where any of the main swatch's last [`LATENCY_WINDOW`] full renders took
//! longer than fits in the frame after an edit ([`DRAFT_BUDGET`], half a 60 Hz frame:
//! [`drafts_edits`]), an edit (a parameter, a value, a wire,
//! the orbit) is first rendered as a draft at a lower mesh detail ([`draft_detail`]), shown
//! scaled up in the swatch, and the full swatch follows. The first draft is [`DRAFT_SIZE`]²; each later one is sized
//! from the last ([`draft_side`]) to fit [`DRAFT_BUDGET`], down to [`MIN_DRAFT_SIZE`]², as a
//! game's dynamic resolution follows its frame time. While a slider is dragged each new value
//! gets a draft, and the full render comes when the value rests, as Blender's viewport
//! renders at a coarser pixel size while the view changes. Time alone (playing) does not
//! draft. Once such a swatch shows a new structure, orbit or time, one draft of it is
//! rendered unseen, so that the first edit's draft finds its mesh, scene pass and targets
//! made (as a game warms its pipelines before they are needed).
//!
//! **Stand-ins.** A structure the GPU has not drawn for the main swatch (the graph just
//! opened, an edit that changes the shader) compiles its pipelines first: 50–300 ms on
//! lavapipe. It is first drawn on the CPU renderer instead, a [`STAND_IN_SIZE`]² draft on a
//! worker of its own (1.7–7.7 ms for the bundled graphs, the environment's tables and the
//! scene passes made once), shown until the GPU's render replaces it; the GPU's job waits
//! for it, so that it has the cores to itself ([`Preview::stand_ins`]). A structure the GPU
//! drew lately ([`GPU_DRAWN`]) has its pipelines and gets none. The texture shows the
//! newest request put on it, so a render that ends after a newer one leaves it.

use super::model::EditorDoc;
use crate::document::{GraphDocument, OutputDocument};
use crate::gpu::{Backend, GpuContext};
use crate::graph::Graph;
use crate::node::Attribute;
use crate::plan::{Plan, PlanOptions};
use crate::registry::Registry;
use crate::render::{RenderOptions, graph_scene, render_timed};
use crate::scene::{Camera, Scene, SceneKind};
use crate::value::Value;
use glam::Vec3;
use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::path::PathBuf;
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Side of the main swatch in pixels.
pub const SIZE: u32 = 128;

/// Side of a node's swatch in pixels.
pub const NODE_SIZE: u32 = 64;

/// Side of the main swatch's first (and largest) draft in pixels.
pub const DRAFT_SIZE: u32 = 48;

/// Side of the smallest draft in pixels (2.7× the swatch's pixel size: a colour and shape
/// still read).
pub const MIN_DRAFT_SIZE: u32 = 24;

/// Side of a stand-in in pixels ([`Preview::stand_ins`]). One side for all of them: the
/// stand-in drawn when a graph opens makes the CPU's scene textures at it, and the later
/// ones find them (measured on water_toon_day: a first 24² stand-in after a 48² one took
/// 37 ms, a 48² one 7 ms).
pub const STAND_IN_SIZE: u32 = DRAFT_SIZE;

/// Request-to-pixels time a draft is sized for, and over which a full render drafts its
/// edits: half a 60 Hz frame, the other half being the editor's frames that queue the
/// draft and show it ([`FRAME`] / 2).
pub const DRAFT_BUDGET: Duration = Duration::from_micros(8_333);

/// A frame at 60 Hz.
pub const FRAME: Duration = Duration::from_micros(16_667);

/// Full renders of a swatch whose times decide whether its edits draft ([`drafts_edits`]).
pub const LATENCY_WINDOW: usize = 8;

/// Whether a swatch whose last full renders took `latencies` (request to pixels) drafts its
/// edits: when any of them took over [`DRAFT_BUDGET`]. One render's time is not enough to
/// go by: on lavapipe a swatch's full render varies by 2× from one to the next (`skin`'s
/// 128², measured on a 2-core VM: 8–15 ms), so deciding by the last one alone left the edit
/// after a quick render undrafted, and its slow full render missed the next frame (5 of 400
/// parameter changes over five graphs; none once decided on the last eight). Drafting when
/// it was not needed costs the edit a draft's time (2–4 ms) before its full swatch.
pub fn drafts_edits(latencies: &VecDeque<Duration>) -> bool {
    latencies.iter().any(|l| *l > DRAFT_BUDGET)
}

/// The graph output a node swatch shows: `color` (lit, summed over the scene's lights)
/// when the cut graph reads `light` or `light_color`, else this name (shown unlit).
pub const CUT_OUTPUT: &str = "preview";

/// The orbit camera: yaw and pitch about the scene camera's target, and a distance factor,
/// relative to the scene's own camera (the default shows it unchanged).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orbit {
    /// Rotation about the vertical axis through the target, degrees.
    pub yaw_deg: f32,
    /// Elevation added to the camera's, degrees.
    pub pitch_deg: f32,
    /// Distance to the target over the scene camera's.
    pub zoom: f32,
}

impl Default for Orbit {
    fn default() -> Self {
        Orbit {
            yaw_deg: 0.0,
            pitch_deg: 0.0,
            zoom: 1.0,
        }
    }
}

/// Elevation limit of the orbit, degrees (the camera stays off the poles).
pub const MAX_ELEVATION_DEG: f32 = 85.0;

/// Distance factor limits of the orbit.
pub const ZOOM_RANGE: (f32, f32) = (0.25, 4.0);

impl Orbit {
    /// `base` moved on the sphere about its target: spherical coordinates (azimuth about
    /// +y, elevation, radius) of `position − target`, the yaw and pitch added (elevation
    /// within ±[`MAX_ELEVATION_DEG`]), the radius scaled by `zoom`. The default orbit
    /// returns `base` unchanged.
    pub fn camera(&self, base: &Camera) -> Camera {
        if *self == Orbit::default() {
            return *base;
        }
        let target = Vec3::from(base.target);
        let offset = Vec3::from(base.position) - target;
        let r = offset.length();
        if r <= 0.0 || !r.is_finite() {
            return *base;
        }
        let azimuth = offset.x.atan2(offset.z) + self.yaw_deg.to_radians();
        let limit = MAX_ELEVATION_DEG.to_radians();
        let elevation = ((offset.y / r).clamp(-1.0, 1.0).asin() + self.pitch_deg.to_radians())
            .clamp(-limit, limit);
        let d = r * self.zoom;
        let dir = Vec3::new(
            elevation.cos() * azimuth.sin(),
            elevation.sin(),
            elevation.cos() * azimuth.cos(),
        );
        Camera {
            position: (target + d * dir).to_array(),
            ..*base
        }
    }

    /// Applies a pointer drag of `dx, dy` points (half a degree per point; dragging right
    /// turns the scene right, dragging down looks from higher up).
    pub fn drag(&mut self, dx: f32, dy: f32) {
        self.yaw_deg = (self.yaw_deg - 0.5 * dx) % 360.0;
        self.pitch_deg = (self.pitch_deg + 0.5 * dy).clamp(-180.0, 180.0);
    }

    /// Applies a scroll of `dy` points (up zooms in: the distance × e^(−dy/200)), within
    /// [`ZOOM_RANGE`].
    pub fn scroll(&mut self, dy: f32) {
        self.zoom = (self.zoom * (-dy / 200.0).exp()).clamp(ZOOM_RANGE.0, ZOOM_RANGE.1);
    }
}

/// What one render shows; a slot re-renders when its wanted request differs from the one
/// shown.
#[derive(Clone, Debug, PartialEq)]
pub struct Request {
    /// The structure key ([`structure_key`]), shared with the document's.
    pub structure: Arc<str>,
    /// Exposed parameter values.
    pub params: Vec<(String, Value)>,
    /// The orbit camera.
    pub orbit: Orbit,
    /// Scene time, seconds.
    pub time: f32,
    /// Side in pixels.
    pub size: u32,
}

/// A document the swatches render in place of the edited one, and its graph
/// ([`without_unread_switches`]).
type Lenient = (GraphDocument, Graph);

/// A slot: `None` is the main swatch, `Some(id)` node `id`'s.
type Slot = Option<String>;

/// One render for the worker.
struct Job {
    slot: Slot,
    request: Request,
    /// Rendered as a draft ([`draft_detail`]).
    draft: bool,
    /// A draft rendered to warm the caches its edits use, not shown ([`Preview::poll`]).
    warm: bool,
    /// A stand-in: a draft on the CPU while the GPU compiles (module doc).
    stand_in: bool,
    /// Side in pixels: the request's, or the draft's ([`draft_side`]).
    side: u32,
    /// Order of queueing, all slots and workers (the texture shows the newest).
    seq: u64,
    graph: Arc<Graph>,
    file: Option<PathBuf>,
    cpu_only: bool,
    queued: Instant,
    /// The job the next worker renders once this one is done (a stand-in's main job).
    then: Option<Box<Job>>,
}

/// A finished render.
struct Done {
    slot: Slot,
    request: Request,
    draft: bool,
    warm: bool,
    stand_in: bool,
    side: u32,
    seq: u64,
    result: Result<Rendered, String>,
    latency: Duration,
}

/// The pixels of a finished render and where they were drawn.
struct Rendered {
    rgba: Vec<u8>,
    size: u32,
    backend: String,
}

impl Rendered {
    /// The pixels as an egui image.
    fn image(&self) -> egui::ColorImage {
        let n = self.size as usize;
        egui::ColorImage::from_rgba_unmultiplied([n, n], &self.rgba)
    }
}

/// The state of one swatch.
#[derive(Default)]
struct SlotState {
    /// Structure key and the graph built for it.
    program: Option<(Arc<str>, Arc<Graph>)>,
    /// The request being rendered.
    running: Option<Request>,
    /// The request shown (rendered, or failed with `message`).
    shown: Option<Request>,
    /// The request whose draft the texture shows, until its full render replaces it.
    draft: Option<Request>,
    /// The request last asked for.
    wanted: Option<Request>,
    texture: Option<egui::TextureHandle>,
    /// The RGBA8 pixels of the texture.
    rgba: Vec<u8>,
    message: Option<String>,
    backend: String,
    /// Request to pixels of the last [`LATENCY_WINDOW`] full renders, oldest first (the
    /// last full render's is [`Preview::latency`]): whether edits draft ([`drafts_edits`]).
    latencies: VecDeque<Duration>,
    /// The last draft's side and request-to-pixels time.
    last_draft: Option<(u32, Duration)>,
    /// Whether the last draft was the first at its side (its time then counts the mesh,
    /// scene pass and targets made for that side).
    draft_cold: bool,
    /// The structure, orbit and time whose draft was last warmed (or drawn).
    warmed: Option<(Arc<str>, Orbit, f32)>,
    /// The structure of the last stand-in queued (one per structure).
    stand_in: Option<Arc<str>>,
    /// Whether a stand-in is being rendered.
    stand_in_running: bool,
    /// The [`Job::seq`] of the render the texture shows.
    texture_seq: u64,
}

impl SlotState {
    /// Records a full render's request-to-pixels time.
    fn record_latency(&mut self, latency: Duration) {
        self.latencies.push_back(latency);
        if self.latencies.len() > LATENCY_WINDOW {
            self.latencies.pop_front();
        }
    }

    /// Puts `r` on the swatch's texture (made on the first render).
    fn show(&mut self, ctx: &egui::Context, slot: &Slot, r: &Rendered) {
        let image = r.image();
        match &mut self.texture {
            Some(t) => t.set(image, egui::TextureOptions::LINEAR),
            None => {
                let name = match slot {
                    None => "matgraph-preview".to_owned(),
                    Some(id) => format!("matgraph-preview-{id}"),
                };
                self.texture = Some(ctx.load_texture(name, image, egui::TextureOptions::LINEAR));
            }
        }
    }

    /// The side of the next draft: [`draft_side`] of the last, which keeps its side when it
    /// was the first at it (a cold draft's time would shrink the next one, and the smaller
    /// side be cold in turn; measured, a 48² water draft at 10 ms went to 40² at 33 ms,
    /// then 32² at 44 ms, where warm drafts took 4–6 ms).
    fn next_draft_side(&self) -> u32 {
        match self.last_draft {
            Some((side, _)) if self.draft_cold => side,
            last => draft_side(last),
        }
    }
}

/// The preview's time: a slider, and play/pause.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Clock {
    /// Scene time, seconds.
    pub time: f32,
    /// Whether time advances with the wall clock.
    pub playing: bool,
    last: Option<f64>,
}

/// The end of the time slider, seconds (playing wraps to 0 there).
pub const TIME_SPAN: f32 = 20.0;

impl Clock {
    /// Advances the time to egui time `now` (seconds) while playing; whether it moved.
    pub fn advance(&mut self, now: f64) -> bool {
        let last = self.last.replace(now);
        if !self.playing {
            return false;
        }
        let dt = last.map_or(0.0, |l| (now - l).max(0.0)) as f32;
        self.time = (self.time + dt) % TIME_SPAN;
        dt > 0.0
    }
}

/// The swatches' state and the render worker.
pub struct Preview {
    /// Whether previews are rendered at all (off in tests that do not look at them).
    pub enabled: bool,
    /// Render on the CPU even where a GPU adapter exists.
    pub cpu_only: bool,
    /// The orbit camera of the main swatch.
    pub orbit: Orbit,
    /// The time of the main swatch and the node swatches.
    pub clock: Clock,
    /// Nodes whose swatch is on.
    nodes: BTreeSet<String>,
    /// The node the main swatch shows instead of the graph's outputs ("Preview this
    /// output", Ctrl+Shift+click): the graph cut there ([`cut_at`]); the file is unchanged.
    main_output: Option<String>,
    /// The choice each variant set is previewed at, where it is not the file's default
    /// (the drop-downs of [`super::variants_ui`]): the swatches render the graph at it
    /// ([`Graph::select`]); the file is unchanged.
    variants: BTreeMap<String, String>,
    slots: BTreeMap<Slot, SlotState>,
    /// Programs built so far (structure changes), all slots.
    compiles: usize,
    /// Full renders finished so far, all slots.
    renders: usize,
    /// Drafts finished so far.
    drafts: usize,
    /// Unseen drafts that warmed the caches, finished so far.
    warmups: usize,
    /// Stand-ins finished so far.
    stand_ins: usize,
    /// Jobs queued so far (the last [`Job::seq`]).
    queued: u64,
    /// The structures the GPU drew last for the main swatch (their pipelines are made),
    /// oldest first, at most [`GPU_DRAWN`].
    gpu_drawn: VecDeque<Arc<str>>,
    jobs: Option<mpsc::Sender<Job>>,
    /// The stand-ins' worker.
    stand_in_jobs: Option<mpsc::Sender<Job>>,
    /// [`without_unread_switches`] of the document whose structure key it holds.
    lenient: Option<(Arc<str>, Option<Arc<Lenient>>)>,
    done: Arc<Mutex<Vec<Done>>>,
}

impl Preview {
    /// A preview with nothing rendered yet.
    pub fn new() -> Preview {
        Preview {
            enabled: true,
            cpu_only: false,
            orbit: Orbit::default(),
            clock: Clock::default(),
            nodes: BTreeSet::new(),
            main_output: None,
            variants: BTreeMap::new(),
            slots: BTreeMap::new(),
            compiles: 0,
            renders: 0,
            drafts: 0,
            warmups: 0,
            stand_ins: 0,
            queued: 0,
            gpu_drawn: VecDeque::new(),
            jobs: None,
            stand_in_jobs: None,
            lenient: None,
            done: Arc::new(Mutex::new(Vec::new())),
        }
    }

    /// Whether every swatch shows what it should (nothing is rendering or due).
    pub fn settled(&self) -> bool {
        !self.enabled
            || self
                .slots
                .values()
                .all(|s| s.running.is_none() && !s.stand_in_running && s.shown.is_some())
                && self.slots.contains_key(&None)
                && self
                    .nodes
                    .iter()
                    .all(|n| self.slots.contains_key(&Some(n.clone())))
    }

    /// Programs built so far: one per structural change of the graph, per swatch. A
    /// parameter, camera or time change renders the program already built.
    pub fn compiles(&self) -> usize {
        self.compiles
    }

    /// Full renders finished so far (drafts not counted).
    pub fn renders(&self) -> usize {
        self.renders
    }

    /// Drafts finished so far (the unseen warm-ups not counted).
    pub fn drafts(&self) -> usize {
        self.drafts
    }

    /// Unseen drafts rendered to warm the caches of the next edit's draft, finished so far.
    pub fn warmups(&self) -> usize {
        self.warmups
    }

    /// Turns node `id`'s swatch on or off.
    pub fn toggle_node(&mut self, id: &str) {
        if !self.nodes.remove(id) {
            self.nodes.insert(id.to_owned());
        }
    }

    /// Shows node `id`'s output in the main swatch (the graph cut there, as a node's
    /// swatch), or (`None`) the graph's own outputs again. The document is unchanged.
    pub fn preview_output(&mut self, id: Option<&str>) {
        self.main_output = id.map(str::to_owned);
    }

    /// The node the main swatch shows instead of the graph's outputs, if any.
    pub fn main_output(&self) -> Option<&str> {
        self.main_output.as_deref()
    }

    /// Previews variant set `set` at `choice` (`None`: the file's default again); the
    /// document is unchanged.
    pub fn set_variant(&mut self, set: &str, choice: Option<&str>) {
        match choice {
            Some(c) => self.variants.insert(set.to_owned(), c.to_owned()),
            None => self.variants.remove(set),
        };
    }

    /// The choice variant set `set` is previewed at, when one was picked.
    pub fn variant(&self, set: &str) -> Option<&str> {
        self.variants.get(set).map(String::as_str)
    }

    /// Follows a renamed variant set.
    pub fn rename_variant_set(&mut self, old: &str, new: &str) {
        if let Some(c) = self.variants.remove(old) {
            self.variants.insert(new.to_owned(), c);
        }
    }

    /// Forgets every picked choice (another file was opened).
    pub fn clear_variants(&mut self) {
        self.variants.clear();
    }

    /// The selection the swatches render `doc` at: each picked choice that `doc` declares
    /// and that is not its set's default (a choice undone away, or the default, selects
    /// nothing, so that it shares the default's program).
    pub fn selection(&self, doc: &GraphDocument) -> Vec<(String, String)> {
        self.variants
            .iter()
            .filter(|(set, c)| {
                doc.variants
                    .get(*set)
                    .is_some_and(|v| v.default != **c && v.choices.contains(c))
            })
            .map(|(s, c)| (s.clone(), c.clone()))
            .collect()
    }

    /// Whether node `id`'s swatch is on.
    pub fn node_on(&self, id: &str) -> bool {
        self.nodes.contains(id)
    }

    /// The nodes whose swatch is on.
    pub fn nodes_on(&self) -> impl Iterator<Item = &str> {
        self.nodes.iter().map(String::as_str)
    }

    /// The main swatch's texture, once a render finished.
    pub fn texture(&self) -> Option<&egui::TextureHandle> {
        self.slots.get(&None)?.texture.as_ref()
    }

    /// The main swatch's RGBA8 pixels ([`SIZE`]² rows from the top), once rendered.
    pub fn pixels(&self) -> Option<&[u8]> {
        let s = self.slots.get(&None)?;
        (!s.rgba.is_empty()).then_some(s.rgba.as_slice())
    }

    /// Node `id`'s swatch texture, once a render finished.
    pub fn node_texture(&self, id: &str) -> Option<&egui::TextureHandle> {
        self.slots.get(&Some(id.to_owned()))?.texture.as_ref()
    }

    /// Why the main swatch could not be rendered, if it could not.
    pub fn message(&self) -> Option<&str> {
        self.slots.get(&None)?.message.as_deref()
    }

    /// Why node `id`'s swatch could not be rendered, if it could not.
    pub fn node_message(&self, id: &str) -> Option<&str> {
        self.slots.get(&Some(id.to_owned()))?.message.as_deref()
    }

    /// Where the main swatch was drawn ("GPU: adapter" or "CPU: why"), once rendered.
    pub fn backend(&self) -> &str {
        self.slots.get(&None).map_or("", |s| s.backend.as_str())
    }

    /// Time from the request to the pixels of the main swatch's last full render.
    pub fn latency(&self) -> Option<Duration> {
        self.slots.get(&None)?.latencies.back().copied()
    }

    /// Whether the main swatch drafts its next edit: [`drafts_edits`] of its last full
    /// renders.
    pub fn drafts_next_edit(&self) -> bool {
        self.slots
            .get(&None)
            .is_some_and(|s| drafts_edits(&s.latencies))
    }

    /// The main swatch's last draft: its side in pixels and its request-to-pixels time.
    pub fn last_draft(&self) -> Option<(u32, Duration)> {
        self.slots.get(&None)?.last_draft
    }

    /// Whether the main swatch shows the graph as last asked for, as a draft or in full
    /// (the full render may still be due: see [`Preview::settled`]).
    pub fn current(&self) -> bool {
        !self.enabled
            || self
                .slots
                .get(&None)
                .is_some_and(|s| s.wanted.is_some() && (s.shown == s.wanted || s.draft == s.wanted))
    }

    /// Collects finished renders, and queues the renders due for `edited` (its graph
    /// `None` while it has errors), its file `file` (for its images).
    pub fn poll(&mut self, ctx: &egui::Context, edited: &EditorDoc, file: Option<&PathBuf>) {
        if self
            .main_output
            .as_deref()
            .is_some_and(|id| edited.index(id).is_none())
        {
            // Its node was deleted: the graph's outputs again.
            self.main_output = None;
        }
        if !self.enabled {
            return;
        }
        self.collect(ctx);
        // A switch just added (nothing reads it yet) does not stop the preview while it is
        // wired: the swatches render the document without it.
        let lenient = match edited.graph() {
            Some(_) => None,
            None => self.lenient_for(edited),
        };
        let (doc, graph) = match lenient.as_deref() {
            Some((d, g)) => (d, Some(g)),
            None => (edited.doc(), edited.graph()),
        };
        let registry = edited.registry();
        // A variant choice picked for the preview is part of what the swatches compile.
        let selection = self.selection(doc);
        let structure: Arc<str> = match selection.is_empty() {
            true => edited.structure_key(),
            false => {
                let picked: Vec<String> =
                    selection.iter().map(|(s, c)| format!("{s}={c}")).collect();
                format!("{}\n@variants:{}", edited.structure_key(), picked.join(",")).into()
            }
        };
        // The main swatch's structure names the node it is cut at, if any.
        let main_structure: Arc<str> = match &self.main_output {
            Some(id) => format!("{structure}\n@preview:{id}").into(),
            None => structure.clone(),
        };
        let params: Vec<(String, Value)> = graph
            .map(|g| {
                g.parameters()
                    .iter()
                    .map(|p| (p.name.clone(), p.default))
                    .collect()
            })
            .unwrap_or_default();
        self.slots
            .retain(|k, _| k.as_ref().is_none_or(|id| self.nodes.contains(id)));
        let mut wanted: Vec<(Slot, Request)> = vec![(
            None,
            Request {
                structure: main_structure,
                params: params.clone(),
                orbit: self.orbit,
                time: self.clock.time,
                size: SIZE,
            },
        )];
        for id in &self.nodes {
            wanted.push((
                Some(id.clone()),
                Request {
                    structure: structure.clone(),
                    params: params.clone(),
                    orbit: Orbit::default(),
                    time: self.clock.time,
                    size: NODE_SIZE,
                },
            ));
        }
        let playing = self.clock.playing;
        for (slot, request) in wanted {
            let structure = request.structure.clone();
            // Where the swatch shows the graph cut at a node (a node's swatch, or the main
            // one's "Preview this output"); a cut replaces the outputs, so an output not
            // wired yet does not stop it.
            let cut = match &slot {
                Some(id) => Some(id.clone()),
                None => self.main_output.clone(),
            };
            let state = self.slots.entry(slot.clone()).or_default();
            state.wanted = Some(request.clone());
            let shown = state.shown.as_ref() == Some(&request);
            // A stand-in on the CPU for a structure the GPU has not drawn (module doc).
            let stand_in = slot.is_none()
                && !self.cpu_only
                && !shown
                && !state.stand_in_running
                && state.draft.as_ref() != Some(&request)
                && state.stand_in.as_ref() != Some(&structure)
                && !state.backend.starts_with("CPU")
                && !self.gpu_drawn.contains(&structure);
            // Once the main swatch shows a request whose render drafts its edits, a draft of
            // it is rendered unseen: its first edit's draft then finds the draft's mesh, scene
            // pass and targets made (cold, a 48² draft took 30–36 ms; warm, 3–6 ms).
            let warm_key = (request.structure.clone(), request.orbit, request.time);
            let warm = shown
                && slot.is_none()
                && !playing
                && graph.is_some()
                && state.message.is_none()
                && drafts_edits(&state.latencies)
                && state.warmed.as_ref() != Some(&warm_key);
            // The main worker's job is due: it is free, and the request is not shown (or is,
            // and its draft is to be warmed).
            let due = state.running.is_none() && (!shown || warm);
            if !stand_in && !due {
                continue;
            }
            if graph.is_none() && !cut.as_deref().is_some_and(|id| cuttable(edited, id)) {
                if state.running.is_none() {
                    state.shown = Some(request);
                    state.message = Some("the graph has errors".into());
                }
                continue;
            }
            if state.program.as_ref().map(|p| &p.0) != Some(&structure) {
                let built = match (&cut, graph) {
                    (Some(id), _) => {
                        cut_at_selecting(doc, id, registry, edited.files().cloned(), &selection)
                    }
                    (None, Some(graph)) if selection.is_empty() => Ok(graph.clone()),
                    (None, Some(_)) => {
                        build_selected(doc, registry, edited.files().cloned(), &selection)
                    }
                    (None, None) => Err("the graph has errors".into()),
                };
                self.compiles += 1;
                match built {
                    Ok(g) => state.program = Some((structure.clone(), Arc::new(g))),
                    Err(e) => {
                        state.program = None;
                        state.shown = Some(request);
                        state.message = Some(e);
                        continue;
                    }
                }
            }
            let Some(program) = state.program.as_ref().map(|p| p.1.clone()) else {
                continue;
            };
            let job = |stand_in: bool, warm: bool, draft: bool, side: u32, seq: u64| Job {
                slot: slot.clone(),
                request: request.clone(),
                draft,
                warm,
                stand_in,
                side,
                seq,
                graph: program.clone(),
                file: file.cloned(),
                cpu_only: stand_in || self.cpu_only,
                queued: Instant::now(),
                then: None,
            };
            // The stand-in is older than its main job: the full render replaces it.
            let stand_in_seq = stand_in.then(|| {
                self.queued += 1;
                self.queued
            });
            let mut main = None;
            if due {
                // A draft first where a full render takes over a frame (module doc); a
                // stand-in is the draft of a new structure.
                let draft = warm
                    || slot.is_none()
                        && !stand_in
                        && !playing
                        && drafts_edits(&state.latencies)
                        && state.draft.as_ref() != Some(&request);
                let side = match draft {
                    true => state.next_draft_side(),
                    false => request.size,
                };
                if draft {
                    state.warmed = Some(warm_key);
                }
                state.running = Some(request.clone());
                self.queued += 1;
                main = Some(job(false, warm, draft, side, self.queued));
            }
            // The stand-in goes first, and the main worker's job after it: alone on the
            // CPU's cores it shows in the next frame, where beside the pipelines' compile
            // it took two or three.
            let (worker, first) = match stand_in_seq {
                Some(seq) => {
                    state.stand_in = Some(structure.clone());
                    state.stand_in_running = true;
                    let mut first = job(true, false, true, STAND_IN_SIZE, seq);
                    first.then = main.map(Box::new);
                    (Worker::Cpu, first)
                }
                None => match main {
                    Some(main) => (Worker::Main, main),
                    None => continue,
                },
            };
            let done = &self.done;
            let main_tx = self
                .jobs
                .get_or_insert_with(|| spawn_worker(ctx, done.clone(), Worker::Main, None))
                .clone();
            let tx = match worker {
                Worker::Main => main_tx,
                Worker::Cpu => self
                    .stand_in_jobs
                    .get_or_insert_with(|| {
                        spawn_worker(ctx, done.clone(), Worker::Cpu, Some(main_tx))
                    })
                    .clone(),
            };
            if let Err(mpsc::SendError(job)) = tx.send(first) {
                // The worker died (a panic in a render): say so on the swatch.
                let state = self.slots.entry(job.slot).or_default();
                state.running = None;
                state.stand_in_running = false;
                match worker {
                    Worker::Main => {
                        state.shown = Some(job.request);
                        state.message = Some("the preview worker stopped".into());
                        self.jobs = None;
                    }
                    // Its main job is queued again at the next poll, without a stand-in.
                    Worker::Cpu => self.stand_in_jobs = None,
                }
            }
        }
    }

    /// [`without_unread_switches`] of `edited`, made once per structure.
    fn lenient_for(&mut self, edited: &EditorDoc) -> Option<Arc<Lenient>> {
        let key = edited.structure_key();
        match &self.lenient {
            Some((k, made)) if Arc::ptr_eq(k, &key) || *k == key => made.clone(),
            _ => {
                let made = without_unread_switches(edited).map(Arc::new);
                self.lenient = Some((key, made.clone()));
                made
            }
        }
    }

    fn collect(&mut self, ctx: &egui::Context) {
        let finished = std::mem::take(&mut *self.done.lock().unwrap_or_else(|p| p.into_inner()));
        for d in finished {
            match (d.stand_in, d.warm, d.draft) {
                (true, ..) => self.stand_ins += 1,
                (_, true, _) => self.warmups += 1,
                (_, false, true) => self.drafts += 1,
                (_, false, false) => self.renders += 1,
            }
            if !d.stand_in
                && d.slot.is_none()
                && d.result
                    .as_ref()
                    .is_ok_and(|r| r.backend.starts_with("GPU"))
                && !self.gpu_drawn.contains(&d.request.structure)
            {
                self.gpu_drawn.push_back(d.request.structure.clone());
                if self.gpu_drawn.len() > GPU_DRAWN {
                    self.gpu_drawn.pop_front();
                }
            }
            let Some(state) = self.slots.get_mut(&d.slot) else {
                continue;
            };
            // The texture shows the newest request put on it: an older render that ends
            // after a stand-in of a newer one leaves it.
            let newest = d.seq > state.texture_seq;
            if d.stand_in {
                state.stand_in_running = false;
                if newest
                    && state.shown.as_ref() != Some(&d.request)
                    && let Ok(r) = d.result
                {
                    state.texture_seq = d.seq;
                    state.draft = Some(d.request);
                    state.show(ctx, &d.slot, &r);
                }
                continue;
            }
            state.running = None;
            if d.warm {
                continue;
            }
            if d.draft {
                // Shown until its full render replaces it; a failed draft leaves the
                // swatch as it was, and the full render reports the error.
                state.draft_cold = state.last_draft.is_none_or(|l| l.0 != d.side);
                state.last_draft = Some((d.side, d.latency));
                // Marked drafted even when it failed, so that its full render comes next; an
                // older draft than the texture's leaves the newer stand-in's mark.
                if newest {
                    state.draft = Some(d.request);
                    if let Ok(r) = d.result {
                        state.texture_seq = d.seq;
                        state.show(ctx, &d.slot, &r);
                    }
                }
                continue;
            }
            state.record_latency(d.latency);
            state.shown = Some(d.request);
            if newest {
                state.draft = None;
            }
            match d.result {
                Ok(r) if newest => {
                    state.texture_seq = d.seq;
                    state.show(ctx, &d.slot, &r);
                    state.message = None;
                    state.backend = r.backend;
                    state.rgba = r.rgba;
                }
                Ok(r) => state.backend = r.backend,
                Err(e) => state.message = Some(e),
            }
        }
    }

    /// Stand-ins rendered so far: CPU drafts of a structure the GPU had not drawn.
    pub fn stand_ins(&self) -> usize {
        self.stand_ins
    }

    /// Whether a stand-in is being rendered.
    pub fn stand_in_running(&self) -> bool {
        self.slots.values().any(|s| s.stand_in_running)
    }
}
impl Default for Preview {
    fn default() -> Self {
        Preview::new()
    }
}

/// The structures of the main swatch the GPU drew that [`Preview`] remembers: their
/// pipelines are cached (the device keeps 64 pipelines and materials), so their edits need
/// no stand-in.
pub const GPU_DRAWN: usize = 16;

/// The render workers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Worker {
    /// The swatches' renders, one at a time on the shared GPU context.
    Main,
    /// The stand-ins, on the CPU beside the main worker.
    Cpu,
}

/// Starts a render worker: one thread rendering its jobs in order (the main worker's
/// swatches share the GPU context one render at a time). A job's follow-up
/// ([`Job::then`]) goes to `next` once it is done.
fn spawn_worker(
    ctx: &egui::Context,
    done: Arc<Mutex<Vec<Done>>>,
    worker: Worker,
    next: Option<mpsc::Sender<Job>>,
) -> mpsc::Sender<Job> {
    let (tx, rx) = mpsc::channel::<Job>();
    let ctx = ctx.clone();
    let name = match worker {
        Worker::Main => "matgraph-preview",
        Worker::Cpu => "matgraph-preview-cpu",
    };
    let finished = move |job: Job, result: Result<Rendered, String>| Done {
        slot: job.slot,
        request: job.request,
        draft: job.draft,
        warm: job.warm,
        stand_in: job.stand_in,
        side: job.side,
        seq: job.seq,
        result,
        latency: job.queued.elapsed(),
    };
    std::thread::Builder::new()
        .name(name.into())
        .spawn(move || {
            for mut job in rx {
                let result = render_job(&job);
                let then = job.then.take();
                let mut out = vec![finished(job, result)];
                if let Some(then) = then {
                    let lost = match &next {
                        Some(n) => n.send(*then).err().map(|e| e.0),
                        None => Some(*then),
                    };
                    if let Some(lost) = lost {
                        out.push(finished(lost, Err("the preview worker stopped".into())));
                    }
                }
                done.lock().unwrap_or_else(|p| p.into_inner()).extend(out);
                ctx.request_repaint();
            }
        })
        .expect("spawning the preview thread");
    tx
}

fn render_job(job: &Job) -> Result<Rendered, String> {
    let (backend, note) = if job.cpu_only {
        (Backend::Cpu, "CPU".to_owned())
    } else {
        match GpuContext::shared() {
            Ok(ctx) => (Backend::Gpu, format!("GPU: {}", ctx.adapter_info().name)),
            // Shown as "CPU — no GPU adapter", the error on hover.
            Err(e) => (Backend::Cpu, format!("CPU — no GPU adapter ({e})")),
        }
    };
    let r = &job.request;
    let size = job.side;
    let (pixels, fallback) = render_swatch(
        &job.graph,
        job.file.as_ref(),
        &SwatchOptions {
            size,
            draft: job.draft,
            backend,
            orbit: r.orbit,
            time: r.time,
            params: r.params.clone(),
        },
    )?;
    let rgba = pixels
        .iter()
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect();
    Ok(Rendered {
        rgba,
        size,
        backend: match fallback {
            Some(why) => format!("{note}; {why}"),
            None => note,
        },
    })
}

/// How [`render_swatch`] renders.
#[derive(Clone, Debug)]
pub struct SwatchOptions {
    /// Side in pixels.
    pub size: u32,
    /// A draft: the mesh at [`draft_detail`] instead of [`swatch_detail`].
    pub draft: bool,
    /// Where the material is evaluated (`Gpu`: the GPU rasteriser).
    pub backend: Backend,
    /// The orbit camera.
    pub orbit: Orbit,
    /// Scene time, seconds.
    pub time: f32,
    /// Parameter values replacing the graph's.
    pub params: Vec<(String, Value)>,
}

impl Default for SwatchOptions {
    fn default() -> Self {
        SwatchOptions {
            size: SIZE,
            draft: false,
            backend: Backend::Cpu,
            orbit: Orbit::default(),
            time: 0.0,
            params: Vec::new(),
        }
    }
}

/// Renders `graph` in its scene (the ball when it names none), 1 sample per pixel, to sRGB
/// pixels; also why a GPU render fell back to the hybrid path, if it did.
pub fn render_swatch(
    graph: &Graph,
    file: Option<&PathBuf>,
    o: &SwatchOptions,
) -> Result<(Vec<[u8; 3]>, Option<String>), String> {
    let mut scene = graph_scene(graph)
        .ok()
        .flatten()
        .or_else(|| Scene::preset("ball"))
        .ok_or("no scene")?;
    scene.camera = o.orbit.camera(&scene.camera);
    match o.draft {
        false => swatch_detail(&mut scene, o.size),
        true => draft_detail(&mut scene),
    }
    let textures = match file {
        Some(f) => Some(graph_textures(graph, f)?),
        None => None,
    };
    let options = RenderOptions {
        width: o.size,
        height: o.size,
        samples: 1,
        time: Some(o.time),
        backend: o.backend,
        parameters: o.params.clone(),
        textures,
        ..Default::default()
    };
    let (hdr, t) = render_timed(graph, &scene, &options).map_err(|e| e.to_string())?;
    Ok((hdr.to_srgb8(1.0).pixels, t.fallback))
}

/// What a graph's images were loaded from: the graph file, and each texture's key with
/// the length and modification time of each of its files (so that an image saved again is
/// read again).
type TextureStamp = (
    PathBuf,
    Vec<(String, Vec<Option<(u64, std::time::SystemTime)>>)>,
);

/// The images `graph`'s texture nodes name, next to `file`, loaded once per
/// [`TextureStamp`]: a swatch reads and decodes them only when they change, and the GPU
/// path, which keeps a material's uploads while its textures are the same `Arc`s, uploads
/// them once. Measured on lavapipe, `water_sunshine`'s 48² draft (its wave maps read,
/// decoded and uploaded per render before): 22–25 → 13–14 ms.
fn graph_textures(
    graph: &Graph,
    file: &std::path::Path,
) -> Result<Arc<crate::texture::TextureSet>, String> {
    static LOADED: crate::memo::Memo<TextureStamp, Arc<crate::texture::TextureSet>, 4> =
        crate::memo::Memo::new();
    let folder = file.parent().unwrap_or(std::path::Path::new("."));
    let mut sources: Vec<_> = graph
        .nodes()
        .iter()
        .filter_map(|n| Some((n.texture.as_ref()?, n.texture_key()?)))
        .filter(|(t, _)| t.scene_name().is_none())
        .map(|(t, key)| {
            let stamps = t
                .files()
                .iter()
                .map(|f| {
                    let m = std::fs::metadata(folder.join(f)).ok()?;
                    Some((m.len(), m.modified().ok()?))
                })
                .collect();
            (key, stamps)
        })
        .collect();
    sources.sort();
    sources.dedup();
    LOADED.get_or_make((file.to_owned(), sources), || {
        crate::image_io::load_graph_textures_with(
            graph,
            file,
            crate::io::PathPolicy::InsideGraphFolder,
        )
        .map(Arc::new)
        .map_err(|e| e.to_string())
    })
}

/// The mesh detail of a swatch `size` pixels wide: at [`SIZE`] or less the ball has half
/// its segments and rings and the water half its grid cells each way (none below 16; a
/// quadtree level of detail is left as it is); the bubble keeps its own. The scene's
/// 256 × 128 ball puts about six triangles on each pixel of a 128² swatch, and on lavapipe
/// their vertices and set-up, not the pixels, were most of a preview frame. Measured at 128² on the GPU path against
/// the full mesh (sRGB, 8 bits): fresnel_glass RMSE 0.14/255 (max 2/255 on the rim), 56 →
/// 17 ms; pbr_gold 0.12/255, 43 → 15 ms; water_sunshine 0.008/255, 126 → 90 ms. Halving
/// again moves silhouette pixels by up to 68/255, and the bubble's wobbling film by 175/255
/// already at half.
pub fn swatch_detail(scene: &mut Scene, size: u32) {
    if size > SIZE {
        return;
    }
    let half = |n: u32| n.min((n / 2).max(16));
    match &mut scene.kind {
        SceneKind::Ball(b) => b.segments = b.segments.map(half),
        SceneKind::Water(w) => w.grid = w.grid.map(half),
        SceneKind::Bubble(_) => {}
    }
}

/// The side of a draft after one of side `last.0` that took `last.1` from request to
/// pixels: [`DRAFT_SIZE`] where that time scaled to it by the pixels, time × (48 / side)²,
/// fits [`DRAFT_BUDGET`], else [`MIN_DRAFT_SIZE`]; [`DRAFT_SIZE`] for the first. Two sides
/// only: each new side makes its own targets, scene pass and texture uploads once, and the
/// device keeps four of each, so drafts at every multiple of 8 between them (as before)
/// missed them in turn (a 32² draft of `bubble_iridescent` took 22 ms cold, of which 7.5
/// uploading). Lavapipe's fixed cost per frame (the scene's vertices, the passes) does not
/// shrink with the side, so a heavy scene settles at the smaller one. Measured at 48² →
/// 24² (`swatch_stages --draft`, best of 10, one sitting): `water_sunshine` 7.5 → 6.0 ms,
/// `pbr_gold` 4.8 → 3.6 ms, `water_toon_you` 12.0 → 9.0 ms, `bubble_iridescent` 20.5 →
/// 7.7 ms.
pub fn draft_side(last: Option<(u32, Duration)>) -> u32 {
    let Some((side, took)) = last else {
        return DRAFT_SIZE;
    };
    let scale = (DRAFT_SIZE as f64 / side.max(1) as f64).powi(2);
    match took.as_secs_f64() * scale <= DRAFT_BUDGET.as_secs_f64() {
        true => DRAFT_SIZE,
        false => MIN_DRAFT_SIZE,
    }
}

/// The mesh detail of a draft: a quarter of the ball's segments and rings and of the water
/// grid's and the seabed's cells each way, half the bubble's segments and rings (none below
/// 16). Measured at 48² on lavapipe against the full mesh at 48²
/// (`examples/swatch_stages.rs --draft --size 48 --compare`, docs/benchmarks.md): 4–30 ms
/// instead of 15–70 ms, RMSE 0–3.0/255 in 8-bit sRGB; the largest differences are
/// `toon_ball`'s band edges (142/255 at a few pixels), the Sunshine waters' shoreline over
/// the coarser seabed (139/255) and the faceted refraction of the PBR gems (RMSE up to 3.0).
/// The bubble at half: RMSE 0.14–0.22/255, max 8/255, its draw at 24² 7.4 → 1.0–1.9 ms
/// (`bubble`) and 9.7 → 4.2–6.5 ms (`bubble_iridescent`); at a quarter its silhouette moved
/// by up to 158/255. The full swatch replaces the draft one render later.
pub fn draft_detail(scene: &mut Scene) {
    let quarter = |n: u32| n.min((n / 4).max(16));
    let half = |n: u32| n.min((n / 2).max(16));
    match &mut scene.kind {
        SceneKind::Ball(b) => b.segments = b.segments.map(quarter),
        SceneKind::Water(w) => {
            w.grid = w.grid.map(quarter);
            w.seabed.grid = w.seabed.grid.map(quarter);
            if let Some(lod) = &mut w.lod {
                lod.block = (lod.block / 4).max(1);
            }
        }
        SceneKind::Bubble(b) => b.segments = b.segments.map(half),
    }
}

/// Whether the graph of `doc` cut at node `id` may build while the whole graph has errors:
/// every error is one of its outputs' (an output not wired yet, or reading a deleted
/// node), which the cut replaces.
fn cuttable(doc: &EditorDoc, id: &str) -> bool {
    doc.index(id).is_some()
        && doc
            .errors()
            .iter()
            .all(|e| matches!(e, crate::GraphError::BadOutput { .. }))
}

/// Where `edited`'s only errors are those of `switch` nodes that nothing reads (one just
/// added, its choices being wired: the loader checks no further while a switch lacks a
/// choice), the document without those switches and its graph, which the swatches render
/// meanwhile; else `None`.
pub fn without_unread_switches(edited: &EditorDoc) -> Option<(GraphDocument, Graph)> {
    use crate::GraphError::{BadSwitch, BadSwitchInput};
    use crate::variant::SWITCH;
    let doc = edited.doc();
    let read: BTreeSet<&str> = doc
        .nodes
        .iter()
        .flat_map(|n| n.inputs.values().filter_map(super::model::link_of))
        .chain(doc.outputs.iter().map(|o| o.from.as_str()))
        .filter_map(|l| l.split_once('.').map(|(id, _)| id))
        .collect();
    let unread: BTreeSet<&str> = doc
        .nodes
        .iter()
        .filter(|n| n.node_type == SWITCH && !read.contains(n.id.as_str()))
        .map(|n| n.id.as_str())
        .collect();
    let only_theirs = edited.errors().iter().all(|e| match e {
        BadSwitch { node, .. } | BadSwitchInput { node, .. } => unread.contains(node.as_str()),
        _ => false,
    });
    if unread.is_empty() || edited.errors().is_empty() || !only_theirs {
        return None;
    }
    let mut d = doc.clone();
    d.nodes.retain(|n| !unread.contains(n.id.as_str()));
    for f in &mut d.frames {
        f.nodes.retain(|n| !unread.contains(n.as_str()));
    }
    let graph = build_selected(&d, edited.registry(), edited.files().cloned(), &[]).ok()?;
    Some((d, graph))
}

/// The graph of `doc` at the variant choices of `selection` (the others at their
/// defaults), groups of other files read through `files`; the loader's messages joined.
///
/// A selection is resolved in the document ([`crate::variant::resolve`]: no switches, each
/// link through one going to the chosen source) rather than by [`Graph::select`]: a selected
/// graph saves as written, so its [`Graph::structure_key`] is the default's, and the GPU
/// rasteriser, which keeps each material under that key, drew the default's material for
/// any choice after the default had been drawn.
pub fn build_selected(
    doc: &GraphDocument,
    registry: &Registry,
    files: Option<Arc<dyn crate::group::GroupFiles>>,
    selection: &crate::variant::Selection,
) -> Result<Graph, String> {
    let join = |e: Vec<crate::GraphError>| {
        e.iter()
            .map(|e| e.to_string())
            .collect::<Vec<_>>()
            .join("; ")
    };
    let resolved;
    let doc = match selection.is_empty() {
        true => doc,
        false => {
            resolved = crate::variant::resolve(doc, selection).map_err(join)?;
            &resolved
        }
    };
    match files {
        Some(f) => Graph::from_document_in(doc, registry, f),
        None => Graph::from_document(doc, registry),
    }
    .map_err(join)
}

/// The structure of `doc`: its canonical JSON without node positions and without the
/// `value` of the `parameter` nodes the graph exposes (those reach the shader as uniforms).
/// Two documents with the same key compile to the same shaders.
pub fn structure_key(doc: &GraphDocument) -> String {
    let mut d = doc.clone();
    for n in &mut d.nodes {
        n.position = None;
    }
    d.remove_parameter_values();
    d.to_json_pretty()
}

/// The graph of `doc` cut at node `id`: one output reading the node's first output, named
/// `color` (lit) when it depends on `light` or `light_color`, else [`CUT_OUTPUT`] (unlit).
pub fn cut_at(doc: &GraphDocument, id: &str, registry: &Registry) -> Result<Graph, String> {
    cut_at_in(doc, id, registry, None)
}

/// [`cut_at`] of a document whose groups of other files are read through `files` (a group
/// instance is cut at its group's first output).
pub fn cut_at_in(
    doc: &GraphDocument,
    id: &str,
    registry: &Registry,
    files: Option<Arc<dyn crate::group::GroupFiles>>,
) -> Result<Graph, String> {
    cut_at_selecting(doc, id, registry, files, &[])
}

/// [`cut_at_in`] with the variants of `selection` at the given choices (the others at
/// their defaults), as the preview's drop-downs pick them.
pub fn cut_at_selecting(
    doc: &GraphDocument,
    id: &str,
    registry: &Registry,
    files: Option<Arc<dyn crate::group::GroupFiles>>,
    selection: &crate::variant::Selection,
) -> Result<Graph, String> {
    let node = doc
        .nodes
        .iter()
        .find(|n| n.id == id)
        .ok_or_else(|| format!("no node '{id}'"))?;
    let ports = super::ports::ports_of(doc, node, registry, None, files.as_deref());
    if matches!(ports.kind, super::ports::Kind::Unknown) {
        return Err(format!("node '{id}': unknown type '{}'", node.node_type));
    }
    let output = ports
        .outputs
        .first()
        .ok_or_else(|| format!("node '{id}' has no output"))?
        .name
        .clone();
    let mut cut = doc.clone();
    cut.outputs = vec![OutputDocument {
        name: CUT_OUTPUT.into(),
        from: format!("{id}.{output}"),
    }];
    let build = |d: &GraphDocument| build_selected(d, registry, files.clone(), selection);
    let graph = build(&cut)?;
    let plan = Plan::compile(
        &graph,
        &PlanOptions {
            outputs: vec![CUT_OUTPUT.into()],
            bake_parameters: false,
        },
    )
    .map_err(|e| format!("node '{id}': {e}"))?;
    let lit = plan
        .attributes()
        .iter()
        .any(|a| matches!(a, Attribute::Light | Attribute::LightColor));
    if !lit {
        return Ok(graph);
    }
    cut.outputs[0].name = crate::render::outputs::COLOR.into();
    build(&cut)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Edits draft while any of the last eight full renders took over 8.333 ms: hand cases
    /// at and around the budget, and a slow render that leaves the window after eight quick
    /// ones.
    #[test]
    fn edits_draft_while_a_recent_full_render_was_slow() {
        let us = |t: u64| Duration::from_micros(t);
        let mut s = SlotState::default();
        assert!(!drafts_edits(&s.latencies), "nothing rendered yet");
        s.record_latency(us(8_333));
        assert!(!drafts_edits(&s.latencies), "exactly the budget fits");
        s.record_latency(us(8_334));
        assert!(drafts_edits(&s.latencies));
        // Seven quick renders after the slow one: it is still among the last eight.
        for k in 0..7 {
            s.record_latency(us(2_000 + 100 * k));
            assert!(drafts_edits(&s.latencies), "after {} quick ones", k + 1);
        }
        s.record_latency(us(6_000));
        assert!(!drafts_edits(&s.latencies), "the slow one left the window");
        assert_eq!(s.latencies.len(), LATENCY_WINDOW);
        assert_eq!(
            s.latencies.back(),
            Some(&us(6_000)),
            "the last render's time is kept"
        );
        // Once one render of a swatch that jitters by 2× about the budget (the skin swatch's
        // 8–15 ms) was slow, its quick ones do not stop the drafts.
        assert!(!drafts_edits(&s.latencies));
        for t in [14_700, 7_900, 7_500, 8_000, 7_800] {
            s.record_latency(us(t));
            assert!(drafts_edits(&s.latencies), "{t} µs");
        }
    }

    /// Drafts sized to the budget: hand-worked cases, then seeded random ones checked
    /// against the quadratic cost model (48² where the time scaled by the pixels,
    /// time × (48 / side)², fits 8.333 ms, else 24²).
    #[test]
    fn drafts_are_sized_to_the_budget() {
        let ms = |t: f64| Duration::from_secs_f64(t * 1e-3);
        assert_eq!(draft_side(None), 48);
        assert_eq!(draft_side(Some((48, ms(8.0)))), 48);
        assert_eq!(draft_side(Some((48, ms(8.5)))), 24);
        // 24² at 2 ms predicts 8 ms at 48²; at 2.1 ms, 8.4 ms.
        assert_eq!(draft_side(Some((24, ms(2.0)))), 48);
        assert_eq!(draft_side(Some((24, ms(2.1)))), 24);
        assert_eq!(draft_side(Some((24, ms(200.0)))), 24);
        assert_eq!(draft_side(Some((48, Duration::ZERO))), 48);
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 40) as f64 / (1u64 << 24) as f64
        };
        for _ in 0..10_000 {
            let side = [24, 48][(next() * 2.0) as usize];
            let took = ms((0.5 + 30.0 * next()) as f32 as f64);
            let r = draft_side(Some((side, took)));
            // In f64: the time at 48² predicted from the pixels.
            let predicted = took.as_secs_f64() * (48.0 / side as f64).powi(2);
            let expected = match predicted <= 8.333e-3 {
                true => 48,
                false => 24,
            };
            assert_eq!(r, expected, "{side} {took:?}");
        }
    }

    /// A swatch loads its images once, and again when a file changes on disk.
    #[test]
    fn graph_images_are_loaded_once_per_file_version() {
        let dir = std::env::temp_dir().join(format!("matgraph-preview-{}", std::process::id()));
        let images = dir.join("textures/sunshine");
        std::fs::create_dir_all(&images).unwrap();
        let from = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs");
        for e in std::fs::read_dir(from.join("textures/sunshine")).unwrap() {
            let e = e.unwrap();
            std::fs::copy(e.path(), images.join(e.file_name())).unwrap();
        }
        let file = dir.join("water_sunshine.json");
        std::fs::copy(from.join("water_sunshine.json"), &file).unwrap();
        let graph = crate::io::load_graph(&file, Registry::builtin()).unwrap();
        let texture = |set: &crate::texture::TextureSet, name: &str| {
            set.get(set.index_of(name).unwrap()).unwrap().clone()
        };
        let first = graph_textures(&graph, &file).unwrap();
        let again = graph_textures(&graph, &file).unwrap();
        assert!(
            Arc::ptr_eq(&first, &again),
            "unchanged files are not read again"
        );
        let (wave1, wave2) = (
            texture(&first, "textures/sunshine/wave1.png"),
            texture(&first, "textures/sunshine/wave2.png"),
        );
        assert_ne!(wave1, wave2);
        // wave1.png saved again with wave2's pixels (and a later time, as an editor's save).
        let target = images.join("wave1.png");
        std::fs::copy(images.join("wave2.png"), &target).unwrap();
        let later = std::time::SystemTime::now() + Duration::from_secs(5);
        std::fs::File::options()
            .write(true)
            .open(&target)
            .unwrap()
            .set_modified(later)
            .unwrap();
        let reloaded = graph_textures(&graph, &file).unwrap();
        assert!(!Arc::ptr_eq(&first, &reloaded));
        assert_eq!(texture(&reloaded, "textures/sunshine/wave1.png"), wave2);
        std::fs::remove_dir_all(&dir).ok();
    }
}
