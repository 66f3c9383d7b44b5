//! The editor's frame: menu bar, canvas, side panel (preview, node docs), problems list,
//! generated code, dialogs and shortcuts. [`EditorApp::ui`] draws one frame into any egui
//! `Ui`, so the same code runs in the window (eframe), headless and under egui_kittest.

use super::code::{TARGETS, extension, node_lines};
use super::first_view;
use super::handoff;
use super::outputs::{OUTPUT_NODE, OUTPUT_TITLE, STANDARD};
use super::ports::Kind;
use super::search_ui::{self, SearchState};
use super::select_ui::{SelectTool, View};
use super::stand_in::Looks;
use super::state::{Dialog, EditorState, Pending};
use super::viewer::{Action, Places, Swatch, Viewer};
use egui::{Color32, Key, KeyboardShortcut, Modifiers, Ui};
use egui_snarl::NodeId;
use egui_snarl::ui::{SnarlStyle, SnarlWidget};

/// A typical node's size on the canvas (the view is fitted to the nodes' estimated sizes,
/// [`super::layout::node_size`]).
pub const NODE_EXTENT: egui::Vec2 = egui::vec2(200.0, 140.0);

/// The canvas widget's id (its selection is read through it).
pub fn canvas_id() -> egui::Id {
    egui::Id::new("matgraph-canvas")
}

/// The editor application.
pub struct EditorApp {
    /// Everything edited and shown.
    pub state: EditorState,
    /// Canvas → screen transform of the last frame (for placing nodes at the pointer).
    to_screen: egui::emath::TSTransform,
    /// The canvas rect of the last frame.
    canvas_rect: egui::Rect,
    /// The nodes' bounding box of the last frame, in canvas coordinates.
    nodes_rect: egui::Rect,
    /// Each node's rect (its estimated size) in the last frame, in canvas coordinates.
    node_rects: Vec<egui::Rect>,
    /// Frames until the view is fitted to the nodes (0: no fit pending).
    frame_in: u8,
    /// How many of the document's nodes the canvas shows yet (see
    /// [`super::view::reveal_until`]).
    revealed: usize,
    /// Whether the last frame drew (and measured) every node.
    nodes_measured: bool,
    /// How egui-snarl last drew each node in the overview ([`super::stand_in`]).
    looks: Looks,
    /// Picking, box-selecting and moving nodes with the pointer ([`super::select_ui`]).
    select: SelectTool,
    /// Whether egui-snarl may be handed only some nodes ([`super::handoff`]).
    hand_off: bool,
    /// How many nodes the last frame handed egui-snarl (`None`: all).
    handed: Option<usize>,
    /// The last frame's [`Viewer::drawn`].
    drawn: Vec<(usize, egui::Rect)>,
    /// The last frame's [`Viewer::widgets`].
    widgets: Vec<(String, egui::Rect)>,
    /// How the pending fit frames the nodes: as a graph opens ([`first_view::opening`],
    /// 1×) or whole (Home, [`first_view::frame_all`]).
    fit_whole: bool,
    /// A zoom to set about the canvas' centre on the next frame ([`Self::zoom_to`]).
    zoom_to: Option<f32>,
    /// The canvas' text laid out at its zoom ([`super::crisp_text`]).
    crisp: super::crisp_text::CrispText,
    /// The values refused on the canvas, with why ([`super::entry`]).
    pub rejections: super::entry::Rejections,
    /// The instances entered when the last frame was drawn: a change shows the new
    /// level's nodes afresh.
    level: Vec<String>,
    /// Lines drawn with the right button: cutting wires, adding reroutes
    /// ([`super::line_tool`]).
    line: super::line_tool::LineGesture,
}

impl EditorApp {
    /// The editor on `state`.
    pub fn new(state: EditorState) -> EditorApp {
        EditorApp {
            state,
            to_screen: egui::emath::TSTransform::IDENTITY,
            canvas_rect: egui::Rect::NOTHING,
            nodes_rect: egui::Rect::NOTHING,
            node_rects: Vec::new(),
            // Once every node is shown and measured, the view is fitted to them.
            frame_in: 1,
            revealed: 0,
            nodes_measured: false,
            looks: Looks::default(),
            select: SelectTool::default(),
            hand_off: true,
            handed: None,
            drawn: Vec::new(),
            widgets: Vec::new(),
            fit_whole: false,
            zoom_to: None,
            crisp: Default::default(),
            rejections: Default::default(),
            level: Vec::new(),
            line: Default::default(),
        }
    }

    /// The canvas widget's id at the current level: each group entered has its own (egui-snarl
    /// keeps its view by it), the graph's top [`canvas_id`].
    pub fn canvas_key(&self) -> egui::Id {
        match &self.state.scope {
            None => canvas_id(),
            Some(s) => s
                .levels
                .iter()
                .fold(canvas_id(), |id, l| id.with(&l.instance)),
        }
    }

    /// The one group instance selected (nothing selected: the focused one), if so.
    fn selected_instance(&self, ctx: &egui::Context) -> Option<String> {
        let selected = self.selected(ctx);
        let is_instance = |id: &str| {
            self.state
                .doc
                .node(id)
                .is_some_and(|n| n.node_type == crate::group::GROUP)
        };
        match selected.as_slice() {
            [one] if is_instance(one) => Some(one.clone()),
            [] => self.state.focus.clone().filter(|f| is_instance(f)),
            _ => None,
        }
    }

    /// Groups the selected nodes (nothing selected: the focused one, as a node's menu
    /// offers it); the new instance is then the selection.
    fn group_selected(&mut self, ctx: &egui::Context) {
        self.select.end_grab(&mut self.state);
        let mut selected = self.selected(ctx);
        if selected.is_empty()
            && let Some(f) = self.state.focus.clone()
        {
            selected.push(f);
        }
        let _ = self.state.group_selection(&selected);
    }

    /// Runs a group command ([`super::group_ui::GroupCommand`]) on the selection.
    fn group_command(&mut self, c: super::group_ui::GroupCommand, ctx: &egui::Context) {
        use super::group_ui::GroupCommand;
        match c {
            GroupCommand::Group => {
                let selected = self.selected(ctx);
                let _ = self.state.group_selection(&selected);
            }
            GroupCommand::Ungroup => match self.selected_instance(ctx) {
                Some(id) => {
                    let _ = self.state.ungroup(&id);
                }
                None => {
                    self.state.status = Some("select one group instance to ungroup (Alt+G)".into());
                }
            },
            GroupCommand::Enter => match self.selected_instance(ctx) {
                Some(id) => {
                    let _ = self.state.enter_group(&id);
                }
                None => {
                    self.state.status = Some("select one group instance to enter it (Tab)".into());
                }
            },
            GroupCommand::Leave => {
                self.state.leave_group();
            }
        }
    }

    /// Whether every node of the document is on the canvas (it shows a file's nodes one
    /// per frame) and the view is fitted.
    pub fn settled(&self) -> bool {
        self.revealed >= self.state.doc.doc().nodes.len() && self.frame_in == 0
    }

    /// Arranges the nodes (View → Arrange) and frames them.
    pub fn arrange(&mut self) {
        self.state.arrange();
        self.frame_all();
    }

    /// The canvas → screen transform of the last frame (accessibility rects of canvas
    /// widgets are in canvas coordinates).
    pub fn to_screen(&self) -> egui::emath::TSTransform {
        self.to_screen
    }

    /// Lets egui-snarl be handed only the nodes it must lay out ([`super::handoff`]), or
    /// (`false`) every node each frame, as before the hand-off (for comparison).
    pub fn set_hand_off(&mut self, on: bool) {
        self.hand_off = on;
    }

    /// How many nodes the last frame handed egui-snarl; `None` when it was handed all.
    pub fn handed(&self) -> Option<usize> {
        self.handed
    }

    /// The ramp-and-curve widgets drawn in the last frame: node id, the strip's or plot's
    /// rect in canvas points ([`super::ramp_ui`]).
    pub fn drawn_widgets(&self) -> &[(String, egui::Rect)] {
        &self.widgets
    }

    /// Whether the pointer is on a ramp-and-curve widget drawn in the last frame.
    fn pointer_on_widget(&self, ctx: &egui::Context) -> bool {
        let Some(at) = ctx.input(|i| i.pointer.hover_pos()) else {
            return false;
        };
        let at = self.to_screen.inverse() * at;
        self.widgets.iter().any(|(_, r)| r.contains(at))
    }

    /// The frames of the nodes egui-snarl drew in full in the last frame, by node id, in
    /// canvas points (culled and withheld nodes left out).
    pub fn drawn_frames(&self) -> Vec<(&str, egui::Rect)> {
        let nodes = &self.state.doc.doc().nodes;
        self.drawn
            .iter()
            .filter_map(|&(k, r)| Some((nodes.get(k)?.id.as_str(), r)))
            .collect()
    }

    /// Fits the view to every node (View → Frame all, Home), on the next frame.
    pub fn frame_all(&mut self) {
        self.frame_in = 1;
        self.fit_whole = true;
    }

    /// Frames the nodes as a graph opens ([`first_view::opening`]: 1×; an empty graph at
    /// 1× about the canvas' origin), once they are drawn and measured.
    fn frame_opening(&mut self) {
        self.frame_in = 1;
        self.fit_whole = false;
        // The last frame measured the graph before.
        self.nodes_measured = false;
        self.node_rects.clear();
    }

    /// Zooms the canvas to `scaling` about the centre of its rect (View → Zoom 1:1), on
    /// the next frame.
    pub fn zoom_to(&mut self, scaling: f32) {
        self.zoom_to = Some(scaling);
    }

    /// The canvas → screen transform that shows `nodes` (canvas) whole in `canvas` (screen),
    /// with a margin, at most at scale 1 ([`first_view::frame_all`]).
    pub fn fit(nodes: egui::Rect, canvas: egui::Rect) -> Option<egui::emath::TSTransform> {
        first_view::frame_all(nodes, canvas)
    }

    /// Draws one frame and applies what the user did in it.
    pub fn ui(&mut self, ui: &mut Ui) {
        let ctx = ui.ctx().clone();
        self.close_request(&ctx);
        self.shortcuts(&ctx);
        self.menu_bar(ui);
        self.bottom_panel(ui);
        self.side_panel(ui);
        if self.state.code.open {
            self.code_panel(ui);
        }
        let actions = egui::CentralPanel::default()
            .frame(egui::Frame::NONE)
            .show(ui, |ui| self.canvas(ui))
            .inner;
        self.apply(actions, &ctx);
        self.search_window(&ctx);
        self.dialogs(&ctx);
        // Copies following the pointer (Shift+D) stay one undo step until dropped.
        if !ctx.input(|i| i.pointer.any_down()) && !self.select.grabbing() {
            self.state.history.seal();
        }
        let now = ctx.input(|i| i.time);
        self.state.tick(now);
        if self.state.check_disk(now) {
            // The reloaded file's nodes are shown again, in steps ([`super::view::reveal_until`]).
            self.revealed = 0;
        }
        if self.state.path.is_some() {
            ctx.request_repaint_after(std::time::Duration::from_secs_f64(super::state::DISK_POLL));
        }
        if self.state.unsaved_since.is_some() {
            ctx.request_repaint_after(std::time::Duration::from_millis(500));
        }
        if self.state.preview.clock.advance(now) {
            ctx.request_repaint();
        }
        super::group_ui::breadcrumb(&ctx, &mut self.state, self.canvas_rect);
        let s = &mut self.state;
        // Inside a group the preview shows the whole graph, the group's edits in it.
        let root = match &s.scope {
            Some(scope) => &scope.root,
            None => &s.doc,
        };
        s.preview.poll(&ctx, root, s.path.as_ref());
    }

    /// The window title: the graph's name, its file and a star when unsaved.
    pub fn title(&self) -> String {
        let file = self
            .state
            .path
            .as_ref()
            .map_or("untitled".to_owned(), |p| p.display().to_string());
        format!(
            "{}{} — {} — matgraph",
            if self.state.dirty() { "* " } else { "" },
            self.state.doc.doc().name,
            file
        )
    }

    fn canvas(&mut self, ui: &mut Ui) -> Vec<Action> {
        let level: Vec<String> = self
            .state
            .scope
            .as_ref()
            .map(|s| s.levels.iter().map(|l| l.instance.clone()).collect())
            .unwrap_or_default();
        if level != self.level {
            // Another level (a group entered or left): its nodes appear afresh; a group
            // entered is framed as a graph opens (1×), the level left keeps its view
            // (egui-snarl's, by [`Self::canvas_key`]).
            let entered = level.len() > self.level.len();
            self.revealed = 0;
            self.looks = Looks::default();
            self.drawn.clear();
            self.nodes_measured = false;
            self.frame_in = u8::from(entered);
            self.fit_whole = false;
            self.select.end_grab(&mut self.state);
        }
        self.level = level;
        self.prune_selection();
        let held = self.select.held_view(ui.ctx(), self.to_screen);
        // The Blender keymap's right-drag lines and wheel zoom (super::keymap).
        let busy = self.select.grabbing() || held.is_some();
        let line = (self.line).begin(
            ui.ctx(),
            &mut self.state,
            self.to_screen,
            self.canvas_rect,
            busy,
        );
        let keymap = self.state.settings.keymap();
        let tool_view = line
            .or_else(|| super::wheel::zoomed(ui.ctx(), keymap, self.to_screen, self.canvas_rect));
        let n = self.state.doc.doc().nodes.len();
        if self.revealed < n {
            // egui-snarl's node frame is the window frame (its shadow).
            let shadow = ui.style().visuals.window_shadow;
            self.revealed = super::view::reveal_until(&self.state.doc, self.revealed, shadow);
            self.state.snarl = super::view::build_snarl_prefix(&self.state.doc, self.revealed);
            ui.ctx().request_repaint();
        } else {
            // Edits rebuild the whole canvas; nothing left to reveal.
            self.revealed = n;
        }
        let hard = ui.input(|i| i.modifiers.ctrl || i.modifiers.command);
        let key = self.canvas_key();
        let shader_error = self.shader_problem();
        let selected = self.selected_node_ids();
        let mut viewer = Viewer {
            file: self.state.path.as_deref(),
            doc: &self.state.doc,
            hard,
            actions: Vec::new(),
            to_screen: None,
            // A node inlined from a group instance (`g/f`) is shown on the instance.
            shader_error: shader_error
                .and_then(|(n, m)| Some((super::model::owner(&n?).to_owned(), m))),
            set_transform: None,
            swatches: self.node_swatches(),
            overview: Default::default(),
            canvas: ui.max_rect(),
            culling: Default::default(),
            places: Places::of(&self.state.snarl, &self.state.doc),
            handed: None,
            looks: &mut self.looks,
            wires: None,
            drawn: Vec::new(),
            widgets: Vec::new(),
            selection: &self.state.selection,
            restore: None,
            pin_rows: Default::default(),
            rejections: &self.rejections,
            pins: Default::default(),
            collapsed: &self.state.collapsed,
        };
        let fit = if self.frame_in == 1 && self.revealed >= n && self.nodes_measured {
            let fit = match self.fit_whole {
                true => Self::fit(self.nodes_rect, self.canvas_rect),
                // An empty graph: 1×, the canvas' origin (where the Material Output node
                // goes) in the middle.
                false => first_view::opening(&self.node_rects, self.canvas_rect).or_else(|| {
                    (self.canvas_rect.is_positive()).then(|| {
                        let origin = egui::Pos2::ZERO;
                        first_view::centred(origin, self.canvas_rect, first_view::OPEN_ZOOM)
                    })
                }),
            };
            if fit.is_none() {
                // Nothing to frame.
                self.frame_in = 0;
            }
            fit
        } else {
            None
        };
        // A zoom asked for (View → Zoom 1:1), once no fit is pending.
        let zoom = match (fit, self.frame_in, self.canvas_rect.is_positive()) {
            (None, 0, true) => self
                .zoom_to
                .take()
                .map(|z| first_view::zoomed(self.to_screen, self.canvas_rect, z)),
            _ => None,
        };
        let fit = fit.or(zoom);
        if fit.is_some() {
            self.zoom_to = None;
        }
        // While a box is drawn the view holds (egui-snarl's background drag pans).
        viewer.set_transform = fit.or(held).or(tool_view);
        let canvas = ui.max_rect();
        let style = SnarlStyle {
            collapsible: Some(false),
            pin_placement: Some(super::pin_tips::PLACEMENT),
            ..SnarlStyle::new()
        };
        // egui-snarl is handed only the nodes it must lay out (super::handoff), except
        // while the file's nodes are revealed, the view is fitted or a menu is open (a
        // node's menu belongs to its frame). The selection, the box selection included,
        // is the editor's (super::select_ui): it needs no node of egui-snarl's.
        let whole = !self.hand_off
            || n > self.revealed
            || !self.nodes_measured
            || fit.is_some()
            || egui::Popup::is_any_open(ui.ctx());
        let mut part = None;
        if !whole {
            let (zoom, scroll, pointer) = ui.input(|i| {
                (
                    i.zoom_delta(),
                    i.smooth_scroll_delta(),
                    i.pointer.latest_pos(),
                )
            });
            let next = tool_view
                .unwrap_or_else(|| handoff::predict(self.to_screen, zoom, scroll, pointer, canvas));
            let mut keep = viewer.hand_over(next, &selected, pointer);
            // The Material Output node is no document node: in the overview it is handed
            // over only while selected (egui-snarl drawing it beside the stand-ins made
            // their pixels vary from run to run).
            if let Some(out) = super::view::output_node_id(&self.state.snarl) {
                if keep.len() <= out.0 {
                    keep.resize(out.0 + 1, true);
                }
                keep[out.0] =
                    next.scaling >= super::viewer::LOW_DETAIL_ZOOM || selected.contains(&out);
            }
            part = handoff::partial(&self.state.snarl, &keep);
            viewer.handed = part.as_ref().map(|_| keep);
        }
        self.handed = viewer
            .handed
            .as_ref()
            .map(|keep| keep.iter().filter(|&&k| k).count());
        let shown = part.as_mut().unwrap_or(&mut self.state.snarl);
        super::collapse::apply(shown, &self.state.doc, &self.state.collapsed);
        // egui-snarl must not see Shift (its own selection stays empty, super::select_ui);
        // the viewer gives it back before any node is drawn.
        let hidden = SelectTool::hide_shift(ui.ctx());
        viewer.restore = hidden.map(|m| (ui.ctx().clone(), m));
        let background = SnarlWidget::new()
            .id(key)
            .style(style)
            .show(shown, &mut viewer, ui);
        if let Some((ctx, m)) = viewer.restore.take() {
            SelectTool::restore(&ctx, Some(m));
        }
        if let Some(wires) = viewer.wires {
            wires.sort(ui.ctx());
        }
        if let Some(part) = &part {
            handoff::write_back(&mut self.state.snarl, part);
        }
        viewer.paint_overview(&self.state.snarl, ui.style());
        if let (Some(wires), Some(t)) = (viewer.wires, viewer.to_screen) {
            // Everything egui-snarl and the overview painted, the background's frame labels included.
            let (layer, _) = wires.place();
            let from = egui::layers::ShapeIdx(0);
            self.crisp.apply(ui.ctx(), layer, from, t.scaling);
        }
        self.drawn = std::mem::take(&mut viewer.drawn);
        self.widgets = std::mem::take(&mut viewer.widgets);
        // The fit is done once the canvas drew a frame with it (egui may rerun a pass).
        if fit.is_some() && viewer.to_screen == fit {
            self.frame_in = 0;
        }
        self.canvas_rect = canvas;
        // Node positions are their top-left corners; a node's extent is its estimated
        // size (the layout's); the Material Output node's, its title's width (egui-snarl
        // draws it 125 points wide) and a row per output.
        let outputs = self.state.doc.doc().outputs.len().max(1) as f32;
        let output_extent = egui::vec2(
            130.0,
            super::layout::HEADER_HEIGHT + super::layout::OUTPUT_ROW * outputs,
        );
        let sizes = self.state.doc.node_sizes();
        self.node_rects = self
            .state
            .snarl
            .nodes_pos_ids()
            .map(|(k, p, _)| {
                let size = sizes
                    .get(k.0)
                    .map_or(output_extent, |&(w, h)| egui::vec2(w, h));
                egui::Rect::from_min_size(p, size)
            })
            .collect();
        self.nodes_rect = (self.node_rects.iter()).fold(egui::Rect::NOTHING, |a, r| a.union(*r));
        // The fit uses the rects of a frame that drew every node.
        self.nodes_measured = self.revealed >= n;
        if let Some(t) = viewer
            .to_screen
            .filter(|t| t.scaling.is_finite() && t.scaling > 0.0)
        {
            self.to_screen = t;
        }
        let wire_slot = viewer.wires;
        let pins = viewer.pins.pins();
        let mut actions = viewer.actions;
        // Clicks, a box selection, the selection dragged along, copies following the
        // pointer: before the moves below are written.
        let drawn = self.drawn_ids();
        let rects = match self.select.boxing() {
            true => self.node_rects(&drawn),
            false => Vec::new(),
        };
        let view = View {
            drawn: &drawn,
            rects: &rects,
            to_screen: self.to_screen,
            canvas,
        };
        if self
            .select
            .after_canvas(ui.ctx(), &mut self.state, &background, view)
        {
            // A right-click cancelled copies following the pointer: not a menu.
            actions.retain(|a| !matches!(a, Action::Search { .. }));
            egui::Popup::close_all(ui.ctx());
        }
        let lined = super::line_tool::Drawn {
            wires: wire_slot,
            pins: &pins,
            canvas,
        };
        if self.line.after_canvas(ui.ctx(), &mut self.state, lined) {
            // The line's release is no right-click: no menu.
            actions.retain(|a| !matches!(a, Action::Search { .. }));
            egui::Popup::close_all(ui.ctx());
        }
        super::frames_ui::click(ui.ctx(), &mut self.state, &drawn, self.to_screen, canvas);
        // Node moves (a drag is one undo step). While a file's nodes are being revealed the
        // laid-out places of nodes without a position wait for the last one: written one
        // per frame, each revalidated the document and regenerated its code (a 300-node
        // graph without positions took 4.1 s to open, 1.9–2.4 s since; benches/editor.rs).
        let revealing = self.revealed < n;
        let moves: Vec<(String, [f32; 2])> = self
            .state
            .snarl
            .nodes_pos_ids()
            .filter_map(|(k, pos, n)| {
                let doc_pos = self.state.doc.doc().nodes.get(k.0)?.position;
                let laid_out = revealing && doc_pos.is_none();
                (!laid_out && doc_pos != Some([pos.x, pos.y]))
                    .then(|| (n.id.clone(), [pos.x, pos.y]))
            })
            .collect();
        if !moves.is_empty() {
            self.state.move_nodes(&moves);
        }
        // The Material Output node's place is the editor's, not the file's.
        if let Some(out) = super::view::output_node_id(&self.state.snarl)
            && let Some(info) = self.state.snarl.get_node_info(out)
        {
            let pos = [info.pos.x, info.pos.y];
            if self.state.doc.output_node() != Some(pos) {
                self.state.move_output_node(pos);
            }
        }
        // So is the Group Input node's, inside a group.
        if let Some(inp) = super::view::input_node_id(&self.state.snarl)
            && let Some(info) = self.state.snarl.get_node_info(inp)
        {
            let pos = [info.pos.x, info.pos.y];
            if self.state.doc.input_node() != Some(pos) {
                self.state.doc.set_input_node(Some(pos));
            }
        }
        // Ctrl+Shift+click on a node shows its output in the main preview (Blender's node
        // wrangler); on the same node again, the graph's outputs.
        let (clicked, ctrl_shift, at) = ui.input(|i| {
            (
                i.pointer.primary_clicked(),
                i.modifiers.command && i.modifiers.shift,
                i.pointer.interact_pos(),
            )
        });
        if clicked
            && ctrl_shift
            && let Some(at) = at.filter(|p| canvas.contains(*p))
        {
            let p = self.to_screen.inverse() * at;
            let nodes = &self.state.doc.doc().nodes;
            let hit = self
                .drawn
                .iter()
                .rev()
                .find(|(_, r)| r.contains(p))
                .and_then(|&(k, _)| nodes.get(k))
                .map(|n| n.id.clone());
            if let Some(id) = hit {
                let again = self.state.preview.main_output() == Some(id.as_str());
                actions.push(Action::PreviewOutput((!again).then_some(id)));
            }
        }
        actions
    }

    /// Forgets selected nodes that are gone (deleted, undone away, another file opened).
    fn prune_selection(&mut self) {
        let s = &mut self.state;
        let output = s.doc.shows_output_node();
        let doc = &s.doc;
        s.selection
            .retain(|id| doc.index(id).is_some() || (id == OUTPUT_NODE && output));
    }

    /// The selected nodes' ids on the canvas.
    fn selected_node_ids(&self) -> Vec<NodeId> {
        let snarl = &self.state.snarl;
        self.state
            .selection
            .ids()
            .iter()
            .filter_map(|id| match id == OUTPUT_NODE {
                true => super::view::output_node_id(snarl),
                false => self.state.doc.index(id).map(NodeId),
            })
            .collect()
    }

    /// The nodes egui-snarl drew in full in the last frame, by id, in drawing order.
    fn drawn_ids(&self) -> Vec<(String, egui::Rect)> {
        let nodes = &self.state.doc.doc().nodes;
        self.drawn
            .iter()
            .filter_map(|&(k, r)| match k {
                super::viewer::OUTPUT_DRAWN => Some((OUTPUT_NODE.to_owned(), r)),
                k => Some((nodes.get(k)?.id.clone(), r)),
            })
            .collect()
    }

    /// Every node on the canvas with its rect (canvas points) for a box selection: as
    /// drawn this frame, else its estimated size at its place (the Material Output node
    /// only where drawn).
    fn node_rects(&self, drawn: &[(String, egui::Rect)]) -> Vec<(String, egui::Rect)> {
        let doc = &self.state.doc;
        let sizes = doc.node_sizes();
        self.state
            .snarl
            .nodes_pos_ids()
            .filter_map(|(_, pos, v)| {
                if let Some((_, r)) = drawn.iter().find(|(id, _)| *id == v.id) {
                    return Some((v.id.clone(), *r));
                }
                let (w, h) = *sizes.get(doc.index(&v.id)?)?;
                Some((
                    v.id.clone(),
                    egui::Rect::from_min_size(pos, egui::vec2(w, h)),
                ))
            })
            .collect()
    }

    /// The swatches of the nodes whose preview is on.
    fn node_swatches(&self) -> std::collections::BTreeMap<String, Swatch> {
        if self.state.in_group() {
            // The swatches are the graph's nodes' (ids inside a group are the group's own).
            return Default::default();
        }
        let p = &self.state.preview;
        p.nodes_on()
            .map(|id| {
                let s = match (p.node_message(id), p.node_texture(id)) {
                    (Some(m), _) => Swatch::Message(m.to_owned()),
                    (None, Some(t)) => Swatch::Image(t.id()),
                    (None, None) => Swatch::Pending,
                };
                (id.to_owned(), s)
            })
            .collect()
    }

    /// The shader generator's error (with its node, when known) while the graph validates.
    fn shader_problem(&mut self) -> Option<(Option<String>, String)> {
        let graph = self.state.doc.graph()?;
        let generated = self.state.code.generated(Some(graph));
        generated
            .text
            .as_ref()
            .err()
            .map(|e| (generated.error_node.clone(), e.clone()))
    }

    /// The ids of the nodes selected on the canvas (the active one last).
    pub fn selected(&self, _ctx: &egui::Context) -> Vec<String> {
        self.state.selection.ids().to_vec()
    }

    /// Whether copies made by Shift+D follow the pointer (until a click drops them).
    pub fn grabbing(&self) -> bool {
        self.select.grabbing()
    }

    /// The canvas position under the pointer (or the canvas centre).
    fn pointer_canvas_pos(&self, ctx: &egui::Context) -> [f32; 2] {
        let screen = ctx
            .input(|i| i.pointer.hover_pos())
            .filter(|p| self.canvas_rect.contains(*p))
            .unwrap_or(if self.canvas_rect.is_positive() {
                self.canvas_rect.center()
            } else {
                egui::pos2(200.0, 200.0)
            });
        let p = self.to_screen.inverse() * screen;
        if p.x.is_finite() && p.y.is_finite() {
            [p.x, p.y]
        } else {
            [0.0, 0.0]
        }
    }

    /// The canvas position at the middle of the view (where a switch added from the side
    /// panel goes).
    fn view_centre(&self) -> [f32; 2] {
        let screen = match self.canvas_rect.is_positive() {
            true => self.canvas_rect.center(),
            false => egui::pos2(200.0, 200.0),
        };
        let p = self.to_screen.inverse() * screen;
        match p.x.is_finite() && p.y.is_finite() {
            true => [p.x, p.y],
            false => [0.0, 0.0],
        }
    }

    /// Opens the add-node search at the pointer.
    pub fn open_search(&mut self, ctx: &egui::Context) {
        self.state.search = Some(SearchState {
            query: String::new(),
            pos: self.pointer_canvas_pos(ctx),
            wire: None,
            selected: 0,
        });
    }

    fn apply(&mut self, actions: Vec<Action>, ctx: &egui::Context) {
        let mut grouping = false;
        let mut commands = Vec::new();
        let s = &mut self.state;
        for a in actions {
            match a {
                Action::Connect {
                    from,
                    output,
                    to,
                    input,
                } => {
                    if s.connect(&from, &output, &to, &input).is_ok() {
                        let to = match to.as_str() {
                            super::outputs::OUTPUT_NODE => super::outputs::OUTPUT_TITLE,
                            node => node,
                        };
                        s.status = Some(format!("linked {from}.{output} → {to}.{input}"));
                    }
                }
                Action::Disconnect { node, input } => s.clear_input(&node, &input),
                Action::SetInputs { node, values, key } => {
                    s.set_inputs(&node, &values, key.as_deref());
                }
                Action::SetInput { node, input, value } => {
                    let key = format!("value:{node}.{input}");
                    s.set_input(&node, &input, value, Some(&key));
                    self.rejections.accept(&node, &input);
                }
                Action::Reject { node, input, why } => {
                    s.status = Some(format!("{node}.{why} (refused; the graph is unchanged)"));
                    self.rejections.reject(&node, &input, why);
                }
                Action::Search { pos, wire } => {
                    s.search = Some(SearchState {
                        query: String::new(),
                        pos,
                        wire,
                        selected: 0,
                    })
                }
                Action::Focus(id) => s.focus = Some(id),
                Action::Remove(ids) => s.remove_nodes(&ids),
                Action::TogglePreview(id) => s.preview.toggle_node(&id),
                Action::PreviewOutput(id) => s.preview_output(id.as_deref()),
                Action::AddOutput(name) => {
                    let _ = s.add_output(&name);
                }
                Action::RenameOutput { old, new } => {
                    let _ = s.rename_output(&old, &new);
                }
                Action::RemoveOutput(name) => s.remove_output(&name),
                Action::Expose { node, input, name } => {
                    let _ = s.expose_input(&node, &input, name.as_deref());
                }
                Action::Unexpose(name) => {
                    let _ = s.unexpose_parameter(&name);
                }
                Action::ListParameter(id) => {
                    let _ = s.list_parameter_node(&id);
                }
                Action::Texture(a) => super::textures::apply(s, a),
                Action::Duplicate(ids) => {
                    self.select.duplicate(s, &ids);
                }
                Action::EnterGroup(id) => {
                    let _ = s.enter_group(&id);
                }
                Action::Ungroup(id) => {
                    let _ = s.ungroup(&id);
                }
                Action::GroupSelected => {
                    grouping = true;
                }
                Action::Command(c, id) => commands.push((c, id)),
            }
        }
        for (c, id) in commands {
            let ids = super::node_commands::targets(&self.state, &id);
            self.state.run_node_command(c, &ids);
        }
        if grouping {
            self.group_selected(ctx);
        }
    }

    fn shortcuts(&mut self, ctx: &egui::Context) {
        let cmd = |k| KeyboardShortcut::new(Modifiers::COMMAND, k);
        let cmd_shift = |k| KeyboardShortcut::new(Modifiers::COMMAND | Modifiers::SHIFT, k);
        // egui matches shortcuts logically (a Shift the pattern lacks is ignored), so Ctrl+Z
        // would take Ctrl+Shift+Z too: the shortcuts with Shift are consumed first.
        let (redo, undo, save_as, save, open, new) = ctx.input_mut(|i| {
            (
                i.consume_shortcut(&cmd_shift(Key::Z)) || i.consume_shortcut(&cmd(Key::Y)),
                i.consume_shortcut(&cmd(Key::Z)),
                i.consume_shortcut(&cmd_shift(Key::S)),
                i.consume_shortcut(&cmd(Key::S)),
                i.consume_shortcut(&cmd(Key::O)),
                i.consume_shortcut(&cmd(Key::N)),
            )
        });
        if save {
            let _ = self.state.save();
        }
        if self.state.dialog.is_none() && self.state.search.is_none() {
            if save_as {
                self.ask_save_as();
            }
            if open {
                self.ask_open();
            }
            if new {
                self.new_graph(ctx);
            }
        }
        let typing = ctx.egui_wants_keyboard_input();
        if typing || self.state.dialog.is_some() || self.state.search.is_some() {
            return;
        }
        if undo || redo {
            // Copies following the pointer are dropped first: their step ends.
            self.select.end_grab(&mut self.state);
        }
        if undo {
            self.state.undo();
        }
        if redo {
            self.state.redo();
        }
        if self.select.grabbing() {
            // Escape and clicks end it (super::select_ui); nothing else meanwhile.
            return;
        }
        // M, H, Ctrl+J, Alt+P on the selection (super::keymap).
        for c in super::keymap::node_commands(ctx) {
            let ids = self.selected(ctx);
            self.state.run_node_command(c, &ids);
        }
        // Delete over a ramp-and-curve widget removes its stop or point (super::ramp_ui),
        // not the selected nodes.
        let on_widget = self.pointer_on_widget(ctx);
        let (search, tab, delete, duplicate) = ctx.input_mut(|i| {
            (
                i.consume_key(Modifiers::SHIFT, Key::A),
                i.consume_key(Modifiers::NONE, Key::Tab),
                !on_widget
                    && (i.consume_key(Modifiers::NONE, Key::Delete)
                        || i.consume_key(Modifiers::NONE, Key::X)),
                i.consume_key(Modifiers::SHIFT, Key::D),
            )
        });
        // Groups (Blender's keys): Ctrl+G groups the selection, Alt+G ungroups, Tab enters
        // the selected instance (nothing selected: the focused one, the active node) or
        // leaves the group (at the top without one, Tab opens the add-node search as
        // before).
        let (make, ungroup) = ctx.input_mut(|i| {
            (
                i.consume_shortcut(&cmd(Key::G)),
                i.consume_key(Modifiers::ALT, Key::G),
            )
        });
        if make {
            self.group_command(super::group_ui::GroupCommand::Group, ctx);
        }
        if ungroup {
            self.group_command(super::group_ui::GroupCommand::Ungroup, ctx);
        }
        if tab {
            // The Tab is the canvas' (egui would also move the keyboard focus to the next
            // widget, a text field of the panel the group shows).
            ctx.memory_mut(|m| m.move_focus(egui::FocusDirection::None));
            if let Some(id) = self.selected_instance(ctx) {
                let _ = self.state.enter_group(&id);
            } else if self.state.in_group() {
                self.state.leave_group();
            } else {
                self.open_search(ctx);
            }
        }
        if search {
            self.open_search(ctx);
        }
        if ctx.input_mut(|i| i.consume_key(Modifiers::NONE, Key::Home)) {
            self.frame_all();
        }
        let selected = self.selected(ctx);
        if delete {
            // The Material Output node is the graph's outputs: Delete leaves it.
            let ids: Vec<String> = selected
                .iter()
                .filter(|i| *i != OUTPUT_NODE)
                .cloned()
                .collect();
            self.state.remove_nodes(&ids);
            self.prune_selection();
        }
        if duplicate {
            self.select.duplicate(&mut self.state, &selected);
        }
        self.clipboard(ctx);
    }

    /// Ctrl+C copies the selected nodes as graph JSON to the system clipboard, Ctrl+V
    /// pastes graph JSON from it at the pointer ([`super::clipboard`]); egui delivers them
    /// as events, which a text field being typed in takes instead.
    fn clipboard(&mut self, ctx: &egui::Context) {
        let (copy, paste) = ctx.input(|i| {
            let copy = i.events.iter().any(|e| matches!(e, egui::Event::Copy));
            let paste = i.events.iter().find_map(|e| match e {
                egui::Event::Paste(text) => Some(text.clone()),
                _ => None,
            });
            (copy, paste)
        });
        if copy && let Some(text) = self.state.copy_selection() {
            ctx.copy_text(text);
        }
        if let Some(text) = paste {
            let at = self.pointer_canvas_pos(ctx);
            let _ = self.state.paste_text(&text, at);
        }
    }

    /// File → New: a new graph, once unsaved changes are saved or discarded.
    fn new_graph(&mut self, ctx: &egui::Context) {
        if let Some(p) = self.state.request(Pending::New) {
            self.run_pending(p, ctx);
        }
    }

    /// File → Open…: the file browser ([`super::browser`]), in the graph's folder (else
    /// the newest recent file's, else the working folder), the recent files on top.
    fn ask_open(&mut self) {
        let recent = self
            .state
            .recent
            .as_ref()
            .map(|r| r.files.clone())
            .unwrap_or_default();
        let dir = self
            .state
            .path
            .as_deref()
            .or(recent.first().map(|p| p.as_path()))
            .and_then(|p| p.parent())
            .filter(|d| d.is_dir())
            .map_or_else(|| std::path::PathBuf::from("."), |d| d.to_owned());
        self.state.dialog = Some(Dialog::Open {
            browser: Box::new(super::browser::Browser::graphs(&dir, &recent)),
        });
    }

    /// File → Save as…: asks for the path, the file's own to start with.
    fn ask_save_as(&mut self) {
        self.state.dialog = Some(Dialog::SaveAs {
            path: self
                .state
                .path
                .as_ref()
                .map_or("untitled.json".into(), |p| p.display().to_string()),
        });
    }

    fn menu_bar(&mut self, ui: &mut Ui) {
        egui::Panel::top("matgraph-menu").show(ui, |ui| {
            egui::MenuBar::new().ui(ui, |ui| {
                ui.menu_button("File", |ui| {
                    if ui.button("New  (Ctrl+N)").clicked() {
                        self.new_graph(ui.ctx());
                    }
                    if ui.button("Open…  (Ctrl+O)").clicked() {
                        self.ask_open();
                    }
                    let recent = self
                        .state
                        .recent
                        .as_ref()
                        .map(|r| r.files.clone())
                        .unwrap_or_default();
                    ui.add_enabled_ui(!recent.is_empty(), |ui| {
                        ui.menu_button("Open Recent", |ui| {
                            for f in recent {
                                if ui.button(f.display().to_string()).clicked() {
                                    ui.close();
                                    if let Some(p) = self.state.request(Pending::Open(f)) {
                                        self.run_pending(p, ui.ctx());
                                    }
                                }
                            }
                        });
                    });
                    if ui.button("Save  (Ctrl+S)").clicked() {
                        let _ = self.state.save();
                    }
                    if ui.button("Save as…  (Ctrl+Shift+S)").clicked() {
                        self.ask_save_as();
                    }
                });
                let instance = self.selected_instance(ui.ctx());
                let mut asked = None;
                let mut command = None;
                ui.menu_button("Edit", |ui| {
                    if ui
                        .add_enabled(
                            self.state.history.can_undo(),
                            egui::Button::new("Undo  (Ctrl+Z)"),
                        )
                        .clicked()
                    {
                        self.state.undo();
                    }
                    if ui
                        .add_enabled(
                            self.state.history.can_redo(),
                            egui::Button::new("Redo  (Ctrl+Shift+Z)"),
                        )
                        .clicked()
                    {
                        self.state.redo();
                    }
                    ui.separator();
                    if ui.button("Copy  (Ctrl+C)").clicked()
                        && let Some(text) = self.state.copy_selection()
                    {
                        ui.ctx().copy_text(text);
                    }
                    if ui.button("Paste  (Ctrl+V)").clicked() {
                        // The clipboard's text comes back as a paste event.
                        ui.ctx()
                            .send_viewport_cmd(egui::ViewportCommand::RequestPaste);
                    }
                    if ui.button("Duplicate  (Shift+D)").clicked() {
                        let ids = self.state.selection.ids().to_vec();
                        self.select.duplicate(&mut self.state, &ids);
                    }
                    ui.separator();
                    if ui.button("Add node…  (Shift+A)").clicked() {
                        let ctx = ui.ctx().clone();
                        self.open_search(&ctx);
                    }
                    if ui.button("Variant sets…").clicked() {
                        self.state.focus = Some(super::variants::VARIANTS_PANEL.to_owned());
                        ui.close();
                    }
                    ui.separator();
                    asked = super::group_ui::menu(ui, &self.state, instance.as_deref());
                    ui.separator();
                    command = super::node_commands::menu(ui, &self.state);
                });
                if let Some(c) = asked {
                    let ctx = ui.ctx().clone();
                    self.group_command(c, &ctx);
                }
                if let Some(c) = command {
                    let ids = self.state.selection.ids().to_vec();
                    self.state.run_node_command(c, &ids);
                }
                ui.menu_button("View", |ui| {
                    if ui.button("Frame all  (Home)").clicked() {
                        self.frame_all();
                    }
                    if ui
                        .button("Zoom 1:1")
                        .on_hover_text("text is sharpest at 1×, where a graph opens")
                        .clicked()
                    {
                        self.zoom_to(first_view::OPEN_ZOOM);
                    }
                    if ui.button("Arrange").clicked() {
                        self.arrange();
                        ui.close();
                    }
                    ui.checkbox(&mut self.state.code.open, "Generated code");
                    ui.checkbox(&mut self.state.preview.enabled, "Preview");
                    super::node_commands::keymap_menu(ui, &mut self.state);
                });
                ui.separator();
                ui.label(self.title());
            });
        });
    }

    fn bottom_panel(&mut self, ui: &mut Ui) {
        egui::Panel::bottom("matgraph-problems")
            .resizable(true)
            .default_size(110.0)
            .show(ui, |ui| {
                if let Some(s) = &self.state.status {
                    ui.label(egui::RichText::new(s).color(Color32::from_rgb(230, 200, 120)));
                }
                let mut errors: Vec<(Option<String>, String)> = self
                    .state
                    .doc
                    .errors()
                    .iter()
                    .map(|e| {
                        let node = match e {
                            crate::GraphError::Cycle { nodes } => nodes.first().cloned(),
                            e => e.node().map(str::to_owned),
                        };
                        // A node inlined from a group instance (`g/f`): the instance.
                        let node = node.map(|n| super::model::owner(&n).to_owned());
                        (node, crate::visible::visible(&e.to_string()).into_owned())
                    })
                    .collect();
                let scene = super::scene_problems::scene_problems(
                    self.state.doc.doc().scene.as_ref(),
                    self.state.path.as_deref(),
                );
                let clean = errors.is_empty();
                errors.extend(
                    scene
                        .into_iter()
                        .map(|p| (None, crate::visible::visible(&p).into_owned())),
                );
                let shader = if clean {
                    let graph = self.state.doc.graph();
                    let generated = self.state.code.generated(graph);
                    generated.text.as_ref().err().map(|e| {
                        let node = generated.error_node.as_deref().map(super::model::owner);
                        (
                            node.map(str::to_owned),
                            crate::visible::visible(e).into_owned(),
                        )
                    })
                } else {
                    None
                };
                ui.strong(format!(
                    "Problems ({})",
                    errors.len() + usize::from(shader.is_some())
                ));
                egui::ScrollArea::vertical().show(ui, |ui| {
                    for (node, message) in errors.iter().chain(shader.iter()) {
                        let r = ui.selectable_label(
                            node.is_some() && node == &self.state.focus,
                            egui::RichText::new(message).color(Color32::from_rgb(255, 120, 110)),
                        );
                        if r.clicked() && node.is_some() {
                            self.state.focus = node.clone();
                        }
                    }
                });
            });
    }

    fn side_panel(&mut self, ui: &mut Ui) {
        egui::Panel::right("matgraph-side")
            .resizable(true)
            .default_size(300.0)
            .show(ui, |ui| {
                super::preview_ui::preview_panel(ui, &mut self.state);
                let hard = ui.input(|i| i.modifiers.ctrl || i.modifiers.command);
                ui.separator();
                // Inside a group the graph's variant sets and parameters are still the whole
                // document's (the preview's).
                let sets = self
                    .state
                    .with_root(|s| super::variants_ui::variants_panel(ui, s));
                if sets {
                    ui.separator();
                }
                self.state
                    .with_root(|s| super::preview_ui::parameters_panel(ui, s, hard));
                ui.separator();
                egui::ScrollArea::vertical().show(ui, |ui| self.inspector(ui));
            });
    }

    fn inspector(&mut self, ui: &mut Ui) {
        let focus = self.state.focus.clone();
        // Inside a group, its Group Input and Group Output nodes show its interface.
        let interface = match focus.as_deref() {
            None | Some(super::scope::GROUP_PANEL) | Some(super::scope::INPUT_NODE) => {
                self.state.doc.body().map(|b| b.group.clone())
            }
            Some(OUTPUT_NODE) => self.state.doc.body().map(|b| b.group.clone()),
            _ => None,
        };
        if let Some(group) = interface {
            super::group_ui::interface_panel(ui, &mut self.state, &group);
            return;
        }
        let Some(id) = focus else {
            ui.weak("Click a node's title to see its documentation.");
            return;
        };
        if let Some(frame) = super::frames::focused(&id) {
            super::frames_ui::panel(ui, &mut self.state, frame);
            return;
        }
        if id == OUTPUT_NODE {
            self.outputs_inspector(ui);
            return;
        }
        if id == super::params::PARAMETERS_PANEL {
            self.state
                .with_root(|s| super::preview_ui::parameters_editor(ui, s));
            return;
        }
        let centre = self.view_centre();
        if id == super::variants::VARIANTS_PANEL {
            self.state
                .with_root(|s| super::variants_ui::variants_editor(ui, s, centre));
            return;
        }
        if super::variants::is_switch(&self.state.doc, &id) {
            super::variants_ui::switch_inspector(ui, &mut self.state, &id, centre);
            return;
        }
        let doc = &self.state.doc;
        let (Some(n), Some(ports)) = (doc.node(&id), doc.ports(&id)) else {
            ui.weak(format!(
                "Node '{id}' is no longer in the graph. Click a node's title to see its documentation."
            ));
            return;
        };
        let t = match &ports.kind {
            Kind::Type(t) => Some(t.clone()),
            Kind::Group { .. } => None,
            Kind::Switch { .. } | Kind::Unknown => {
                // Of a type the registry lacks.
                ui.weak(format!("node '{id}': unknown type '{}'", n.node_type));
                for e in doc.node_errors(&id) {
                    ui.colored_label(Color32::from_rgb(255, 120, 110), e);
                }
                return;
            }
        };
        ui.heading(&id);
        match (&t, &ports.kind) {
            (Some(t), _) => {
                ui.label(format!("{} · {}", t.name(), t.category()));
                if let Some(g) = doc.generic(&id).filter(|_| t.is_generic()) {
                    ui.label(format!("T = {g}"));
                }
            }
            (
                None,
                Kind::Group {
                    reference,
                    interface,
                    ..
                },
            ) => {
                ui.label(format!("group · {reference}"));
                if !interface {
                    ui.weak("its interface could not be read: the pins are its links'");
                }
            }
            _ => {}
        }
        if n.muted {
            ui.label("muted: each output passes on the first input of its type");
        }
        for e in doc.node_errors(&id) {
            ui.colored_label(Color32::from_rgb(255, 120, 110), e);
        }
        let texture = match super::textures::is_texture_node(doc, &id) {
            true => super::textures_ui::inspector_section(ui, &self.state, &id),
            false => None,
        };
        match (&t, &ports.kind) {
            (Some(t), _) => {
                ui.label(t.summary());
                if !t.source_doc().is_empty() {
                    ui.separator();
                    ui.label(t.source_doc());
                }
            }
            (None, Kind::Group { doc: text, .. }) if !text.is_empty() => {
                ui.label(text);
            }
            _ => {}
        }
        ui.separator();
        let ty_of = |p: &super::ports::Port| {
            doc.port_type(&id, p.ty)
                .map_or("T".into(), |t| t.name().to_owned())
        };
        for i in &ports.inputs {
            let unit = if i.unit.is_empty() {
                String::new()
            } else {
                format!(" [{}]", i.unit)
            };
            ui.label(egui::RichText::new(format!("{} : {}{unit}", i.name, ty_of(i))).strong());
            if !i.doc.is_empty() {
                ui.label(i.doc.as_ref());
            }
        }
        for o in &ports.outputs {
            ui.label(egui::RichText::new(format!("out {} : {}", o.name, ty_of(o))).strong());
            if !o.doc.is_empty() {
                ui.label(o.doc.as_ref());
            }
        }
        if let Some(a) = texture {
            super::textures::apply(&mut self.state, a);
        }
        // An instance of a group of this file: its interface, editable (Tab enters it).
        if let Some(group) = self.state.interface_group(Some(&id)) {
            ui.separator();
            super::group_ui::interface_panel(ui, &mut self.state, &group);
        }
    }

    /// The side panel of the Material Output node: each graph output (rename, remove, what
    /// it reads or why it reads nothing), and the standard and any-name outputs to add.
    fn outputs_inspector(&mut self, ui: &mut Ui) {
        ui.heading(OUTPUT_TITLE);
        ui.label("The graph's outputs: wire a node output into a pin to set what it reads.");
        ui.separator();
        let outputs = self.state.doc.doc().outputs.clone();
        let mut rename = None;
        let mut remove = None;
        for (k, o) in outputs.iter().enumerate() {
            let key = egui::Id::new("matgraph-inspector-output").with(k);
            let mut text = ui.data_mut(|d| d.get_temp::<String>(key).unwrap_or(o.name.clone()));
            ui.horizontal(|ui| {
                let edit = ui.add(egui::TextEdit::singleline(&mut text).desired_width(110.0));
                if edit.lost_focus() && text != o.name {
                    rename = Some((o.name.clone(), text.clone()));
                }
                if ui
                    .small_button("×")
                    .on_hover_text(format!("remove output '{}'", o.name))
                    .clicked()
                {
                    remove = Some(o.name.clone());
                }
            });
            match super::outputs::note(&self.state.doc, k) {
                Some(n) => {
                    ui.colored_label(Color32::from_rgb(255, 120, 110), format!("{}: {n}", o.name));
                }
                None => {
                    ui.weak(format!("{} ← {}", o.name, o.from));
                }
            }
            ui.data_mut(|d| d.insert_temp(key, text));
        }
        ui.separator();
        ui.horizontal_wrapped(|ui| {
            for s in STANDARD {
                if ui
                    .add_enabled(
                        !outputs.iter().any(|o| o.name == s),
                        egui::Button::new(format!("+ {s}")),
                    )
                    .clicked()
                {
                    let _ = self.state.add_output(s);
                }
            }
        });
        let key = egui::Id::new("matgraph-inspector-add-output");
        let mut text = ui.data_mut(|d| d.get_temp::<String>(key).unwrap_or_default());
        ui.horizontal(|ui| {
            ui.add(
                egui::TextEdit::singleline(&mut text)
                    .hint_text("name")
                    .desired_width(110.0),
            );
            if ui.button("add output…").clicked() && self.state.add_output(&text).is_ok() {
                text.clear();
            }
        });
        ui.data_mut(|d| d.insert_temp(key, text));
        let changed = rename.is_some() || remove.is_some();
        if let Some((old, new)) = rename {
            // Refused (a name taken or invalid): the status line says why.
            let _ = self.state.rename_output(&old, &new);
        }
        if let Some(name) = remove {
            self.state.remove_output(&name);
        }
        if changed {
            // The fields show the outputs' names again.
            for k in 0..outputs.len() {
                let key = egui::Id::new("matgraph-inspector-output").with(k);
                ui.data_mut(|d| d.remove::<String>(key));
            }
        }
    }

    fn code_panel(&mut self, ui: &mut Ui) {
        egui::Panel::right("matgraph-code")
            .resizable(true)
            .default_size(460.0)
            .show(ui, |ui| {
                let mut export = false;
                ui.horizontal(|ui| {
                    ui.strong("Generated code");
                    for (k, t) in TARGETS.iter().enumerate() {
                        ui.selectable_value(
                            &mut self.state.code.target,
                            k,
                            t.name().to_uppercase(),
                        );
                    }
                });
                let graph = self.state.doc.graph();
                let focus = self.state.focus.clone();
                let generated = self.state.code.generated(graph).clone();
                let text = match &generated.text {
                    Ok(t) => t.clone(),
                    Err(e) => {
                        ui.colored_label(Color32::from_rgb(255, 120, 110), e);
                        return;
                    }
                };
                ui.horizontal(|ui| {
                    if ui.button("Copy").clicked() {
                        ui.ctx().copy_text(text.clone());
                        self.state.status = Some("code copied".into());
                    }
                    export = ui.button("Export").clicked();
                });
                if export {
                    let base = self
                        .state
                        .path
                        .clone()
                        .unwrap_or_else(|| "untitled.json".into());
                    let out = base.with_extension(extension(generated.target));
                    self.state.status = Some(match super::files::save(&out, &text) {
                        Ok(()) => format!("exported {}", out.display()),
                        Err(e) => e,
                    });
                }
                let lines = focus
                    .as_deref()
                    .map(|f| node_lines(&text, &generated.spans, f))
                    .unwrap_or_default();
                let mut job = egui::text::LayoutJob::default();
                let mono = egui::FontId::monospace(11.0);
                for (k, line) in text.split_inclusive('\n').enumerate() {
                    let on = lines.binary_search(&k).is_ok();
                    job.append(
                        line,
                        0.0,
                        egui::TextFormat {
                            font_id: mono.clone(),
                            color: if on {
                                Color32::WHITE
                            } else {
                                Color32::from_gray(170)
                            },
                            background: if on {
                                Color32::from_rgb(60, 70, 120)
                            } else {
                                Color32::TRANSPARENT
                            },
                            ..Default::default()
                        },
                    );
                }
                let mut area = egui::ScrollArea::both();
                if focus != self.state.code.scrolled_for
                    && let Some(&first) = lines.first()
                {
                    let row = ui.ctx().fonts_mut(|f| f.row_height(&mono));
                    area = area.vertical_scroll_offset((first as f32 - 3.0).max(0.0) * row);
                    self.state.code.scrolled_for = focus.clone();
                }
                area.show(ui, |ui| {
                    ui.add(egui::Label::new(job).selectable(true));
                });
            });
    }

    fn search_window(&mut self, ctx: &egui::Context) {
        let Some(mut search) = self.state.search.take() else {
            return;
        };
        let screen = Some(self.to_screen * egui::pos2(search.pos[0], search.pos[1]))
            .filter(|p| p.x.is_finite() && p.y.is_finite())
            .unwrap_or(egui::pos2(200.0, 200.0));
        let mut result = None;
        egui::Window::new("Add node")
            .id(egui::Id::new("matgraph-search"))
            .collapsible(false)
            .resizable(false)
            .default_pos(screen)
            .show(ctx, |ui| {
                result = search_ui::show(ui, &mut search, self.state.doc.registry());
            });
        match result {
            None => self.state.search = Some(search),
            Some(Err(())) => {}
            Some(Ok(pick)) if pick.type_name == OUTPUT_NODE => {
                self.state.add_output_node(search.pos);
                // A wire dropped from an output: a new pin for it.
                if let Some((node, port, super::search::WireFilter::InputAccepting(_))) =
                    &search.wire
                {
                    let name = super::outputs::fresh_name(&self.state.doc, Some(port));
                    if self.state.add_output(&name).is_ok() {
                        let _ = self.state.connect(node, port, OUTPUT_NODE, &name);
                    }
                }
            }
            Some(Ok(pick)) => {
                if let Ok(id) = self.state.add_node(&pick.type_name, search.pos)
                    && let (Some((node, port, filter)), Some(k)) = (&search.wire, pick.port)
                    && let Some(ports) = self.state.doc.ports(&id).cloned()
                {
                    let _ = match filter {
                        super::search::WireFilter::InputAccepting(_) => {
                            self.state.connect(node, port, &id, &ports.inputs[k].name)
                        }
                        super::search::WireFilter::OutputFeeding(_) => {
                            self.state.connect(&id, &ports.outputs[k].name, node, port)
                        }
                    };
                }
            }
        }
    }

    fn dialogs(&mut self, ctx: &egui::Context) {
        let Some(mut dialog) = self.state.dialog.take() else {
            return;
        };
        let mut keep = true;
        let mut run = None;
        let mut reload = false;
        egui::Modal::new(egui::Id::new("matgraph-dialog")).show(ctx, |ui| match &mut dialog {
            Dialog::Recover { path, doc } => {
                ui.heading("Recover unsaved changes?");
                ui.label(format!(
                    "{} holds changes that were not saved.",
                    path.display()
                ));
                ui.horizontal(|ui| {
                    if ui.button("Recover").clicked() {
                        self.state.recover((**doc).clone());
                        keep = false;
                    }
                    if ui.button("Discard").clicked() {
                        let _ = std::fs::remove_file(&*path);
                        keep = false;
                    }
                });
            }
            Dialog::Discard { then } => {
                ui.heading("Unsaved changes");
                ui.label("Save the changes to this graph first?");
                ui.horizontal(|ui| {
                    if ui.button("Save").clicked()
                        && self.state.path.is_some()
                        && self.state.save().is_ok()
                    {
                        run = Some(then.clone());
                        keep = false;
                    }
                    if ui.button("Discard").clicked() {
                        super::files::discard_recovery(self.state.path.as_deref());
                        run = Some(then.clone());
                        keep = false;
                    }
                    if ui.button("Cancel").clicked() {
                        keep = false;
                    }
                });
            }
            Dialog::Changed { path } => {
                ui.heading("Changed on disk");
                ui.label(format!(
                    "{} changed on disk, and this graph has unsaved changes.",
                    path.display()
                ));
                ui.horizontal(|ui| {
                    if ui.button("Reload (drop my changes)").clicked() {
                        reload = true;
                        keep = false;
                    }
                    if ui.button("Keep mine").clicked() {
                        keep = false;
                    }
                });
            }
            Dialog::Open { browser } => match browser.show(ui) {
                Some(super::browser::Outcome::Open(path)) => {
                    run = Some(Pending::Open(path));
                    keep = false;
                }
                Some(super::browser::Outcome::Cancel) => keep = false,
                None => {}
            },
            Dialog::PickTexture { node, browser } => {
                keep = super::textures_ui::picker(ui, &mut self.state, node, browser);
            }
            Dialog::SaveAs { path } => {
                ui.label("File:");
                ui.text_edit_singleline(path);
                ui.horizontal(|ui| {
                    if ui.button("OK").clicked() || ui.input(|i| i.key_pressed(Key::Enter)) {
                        run = Some(Pending::Open(std::path::PathBuf::from(path.as_str())));
                        keep = false;
                    }
                    if ui.button("Cancel").clicked() {
                        keep = false;
                    }
                });
            }
        });
        // Save as answers with the path as an Open does; tell them apart here.
        if let (Some(Pending::Open(p)), Dialog::SaveAs { .. }) = (&run, &dialog) {
            let _ = self.state.save_as(p);
            run = None;
        }
        if reload {
            self.state.reload();
            self.revealed = 0;
        } else if keep {
            self.state.dialog = Some(dialog);
        } else if let Some(p) = run {
            match (&dialog, p) {
                (Dialog::Open { .. }, Pending::Open(path)) => {
                    if let Some(p) = self.state.request(Pending::Open(path)) {
                        self.run_pending(p, ctx);
                    }
                }
                (_, p) => self.run_pending(p, ctx),
            }
        }
    }

    fn run_pending(&mut self, p: Pending, ctx: &egui::Context) {
        match p {
            Pending::Close => {
                self.state.allow_close = true;
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
            Pending::Open(path) => {
                if self.state.load(&path).is_ok() {
                    self.rejections.clear();
                    self.frame_opening();
                    self.revealed = 0;
                }
            }
            Pending::New => {
                self.state.start_new();
                self.rejections.clear();
                self.frame_opening();
                self.revealed = 0;
            }
        }
    }

    fn close_request(&mut self, ctx: &egui::Context) {
        if ctx.input(|i| i.viewport().close_requested()) && !self.state.allow_close {
            if self.state.dirty() {
                ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
                self.state.dialog = Some(Dialog::Discard {
                    then: Pending::Close,
                });
            } else {
                super::files::discard_recovery(self.state.path.as_deref());
            }
        }
    }
}
