//! Selecting and moving nodes with the pointer, as Blender does: a plain click on a node
//! selects it (only it), Shift+click adds it (or, on the active node, deselects it),
//! Ctrl+click toggles it, a click on empty canvas deselects everything; a left-drag on empty
//! canvas draws a box that selects the nodes it touches (Shift adds, Ctrl subtracts);
//! dragging a selected node moves the whole selection, dragging another selects it first;
//! copies made by Shift+D follow the pointer until a click drops them (Escape or a
//! right-click puts them back where they were made). Panning is the middle (or right)
//! drag and the scroll wheel; Ctrl+scroll zooms.
//!
//! The selection is the editor's, by node id ([`super::selection`]). egui-snarl 0.12 keeps
//! its own by slab key and offers no way to set it, so it is kept empty: Shift, the only
//! modifier with which egui-snarl adds to its selection (Shift+click, Shift+drag box), is
//! hidden from it while it reads the frame's modifiers ([`SelectTool::hide_shift`], put
//! back by [`super::viewer::Viewer`] before any node is drawn); Ctrl, which only removes
//! from it, stays, so that Ctrl+drag from an input pin still moves its wire. egui-snarl's
//! background drag pans with every button; while a box is drawn the canvas is held where it
//! was ([`SelectTool::held_view`]).

use super::outputs::OUTPUT_NODE;
use super::selection::Pick;
use super::state::EditorState;
use egui::emath::TSTransform;
use egui::{Context, Modifiers, PointerButton, Pos2, Rect};
use egui_snarl::NodeId;

/// The undo key of a duplicate and the moves of its copies until they are dropped: one
/// undo step.
pub const GRAB_KEY: &str = "grab";

/// Canvas points between a duplicate and its original where it is made.
pub const DUPLICATE_OFFSET: [f32; 2] = [40.0, 40.0];

/// Copies following the pointer.
#[derive(Clone, Debug)]
struct Grab {
    /// The copies, by id.
    ids: Vec<String>,
    /// Where each was made (canvas).
    made: Vec<[f32; 2]>,
    /// The pointer's canvas position when they started following it (set on the first
    /// frame the pointer is known).
    anchor: Option<Pos2>,
}

/// The pointer's selection tools on the canvas, across frames.
#[derive(Debug, Default)]
pub struct SelectTool {
    /// The canvas background's widget id (egui-snarl's response), from the last frame.
    background: Option<egui::Id>,
    /// The box selection under way: where it started (canvas) and the view it holds.
    boxing: Option<(Pos2, TSTransform)>,
    /// Copies following the pointer.
    grab: Option<Grab>,
    /// A button whose press ended a grab: its release is not a click.
    swallow: Option<PointerButton>,
}

impl SelectTool {
    /// Hides Shift from egui-snarl for the modifiers it reads when it starts drawing the
    /// canvas; returns the modifiers to put back (before any node is drawn: value editors
    /// use Shift).
    pub fn hide_shift(ctx: &Context) -> Option<Modifiers> {
        let modifiers = ctx.input(|i| i.modifiers);
        if !modifiers.shift {
            return None;
        }
        ctx.input_mut(|i| i.modifiers.shift = false);
        Some(modifiers)
    }

    /// Puts back the modifiers [`SelectTool::hide_shift`] changed.
    pub fn restore(ctx: &Context, modifiers: Option<Modifiers>) {
        if let Some(m) = modifiers {
            ctx.input_mut(|i| i.modifiers = m);
        }
    }

    /// Before the canvas is drawn: starts a box selection when a primary drag began on the
    /// background; the view to hold this frame while a box is drawn (egui-snarl's
    /// background drag would pan it).
    pub fn held_view(&mut self, ctx: &Context, to_screen: TSTransform) -> Option<TSTransform> {
        let (primary, origin) = ctx.input(|i| (i.pointer.primary_down(), i.pointer.press_origin()));
        if self.boxing.is_none()
            && self.grab.is_none()
            && self.swallow.is_none()
            && primary
            && self.background.is_some()
            && ctx.dragged_id() == self.background
            && let Some(origin) = origin
        {
            self.boxing = Some((to_screen.inverse() * origin, to_screen));
        }
        self.boxing.map(|(_, view)| view)
    }

    /// Whether copies are following the pointer.
    pub fn grabbing(&self) -> bool {
        self.grab.is_some()
    }

    /// Whether a box selection is being drawn.
    pub fn boxing(&self) -> bool {
        self.boxing.is_some()
    }

    /// Duplicates the nodes `ids` ([`DUPLICATE_OFFSET`] away), selects the copies (only
    /// them) and makes them follow the pointer until a click: one undo step
    /// ([`GRAB_KEY`]). Returns the copies' ids.
    pub fn duplicate(&mut self, state: &mut EditorState, ids: &[String]) -> Vec<String> {
        self.end_grab(state);
        let ids: Vec<String> = ids.iter().filter(|i| *i != OUTPUT_NODE).cloned().collect();
        if ids.is_empty() {
            return Vec::new();
        }
        let copies = state
            .edit(Some(GRAB_KEY), true, |d| {
                Ok(d.duplicate(&ids, DUPLICATE_OFFSET))
            })
            .unwrap_or_default();
        if copies.is_empty() {
            return copies;
        }
        let made = copies
            .iter()
            .map(|c| {
                state
                    .doc
                    .node(c)
                    .and_then(|n| n.position)
                    .unwrap_or_default()
            })
            .collect();
        state.selection.set(copies.iter().cloned());
        state.focus = copies.last().cloned();
        state.status = Some(format!(
            "duplicated {} node{}: move the pointer, click to drop (Escape or right-click: leave them where they were made)",
            copies.len(),
            if copies.len() == 1 { "" } else { "s" }
        ));
        self.grab = Some(Grab {
            ids: copies.clone(),
            made,
            anchor: None,
        });
        copies
    }

    /// Drops the copies following the pointer where they are (the undo step ends).
    pub fn end_grab(&mut self, state: &mut EditorState) {
        if self.grab.take().is_some() {
            state.history.seal();
        }
    }

    /// Puts the copies following the pointer back where they were made and stops (still
    /// one undo step with their duplication).
    pub fn cancel_grab(&mut self, state: &mut EditorState) {
        if let Some(g) = self.grab.take() {
            let back: Vec<(String, [f32; 2])> = g.ids.into_iter().zip(g.made).collect();
            place(state, &back);
            state.history.seal();
            state.status = Some("duplicate kept where it was made".into());
        }
    }

    /// After the canvas is drawn: the grab follows the pointer (or ends), a box selection
    /// grows or ends, a click picks, and a node egui-snarl dragged takes the selection
    /// with it. `background` is egui-snarl's response, `drawn` the nodes it drew (id and
    /// frame, canvas points, in drawing order: the last on top), `rects` every node's
    /// rect for a box (drawn or estimated) and `to_screen` the view it drew with.
    /// Returns whether a right-click ended a grab this frame (its menu is not wanted).
    pub fn after_canvas(
        &mut self,
        ctx: &Context,
        state: &mut EditorState,
        background: &egui::Response,
        view: View<'_>,
    ) -> bool {
        self.background = Some(background.id);
        let (pointer, modifiers, primary_pressed, secondary_pressed, escape) = ctx.input(|i| {
            (
                i.pointer.hover_pos(),
                i.modifiers,
                i.pointer.button_pressed(PointerButton::Primary),
                i.pointer.button_pressed(PointerButton::Secondary),
                i.key_pressed(egui::Key::Escape),
            )
        });
        let at = pointer.map(|p| view.to_screen.inverse() * p);
        if let Some(b) = self.swallow {
            // The release of the press that ended a grab: no click, no menu.
            if !ctx.input(|i| i.pointer.button_down(b)) {
                self.swallow = None;
            }
            return b == PointerButton::Secondary;
        }
        if self.grab.is_some() {
            if secondary_pressed || escape {
                self.cancel_grab(state);
                self.swallow = secondary_pressed.then_some(PointerButton::Secondary);
            } else {
                self.follow(state, at);
                if primary_pressed {
                    let n = self.grab.as_ref().map_or(0, |g| g.ids.len());
                    self.end_grab(state);
                    self.swallow = Some(PointerButton::Primary);
                    state.status = Some(format!(
                        "placed {n} cop{}",
                        if n == 1 { "y" } else { "ies" }
                    ));
                }
            }
            return false;
        }
        if let Some((from, _)) = self.boxing {
            let to = at.unwrap_or(from);
            let rect = Rect::from_two_pos(from, to);
            if ctx.input(|i| i.pointer.primary_down()) {
                paint_box(ctx, view.canvas, view.to_screen * rect);
            } else {
                let caught: Vec<String> = view
                    .rects
                    .iter()
                    .filter(|(_, r)| r.intersects(rect))
                    .map(|(id, _)| id.clone())
                    .collect();
                state.selection.boxed(&caught, Pick::of_box(modifiers));
                self.boxing = None;
            }
            return false;
        }
        self.drag_selection(state, modifiers);
        self.click(ctx, state, view.drawn, view.to_screen, view.canvas);
        false
    }

    /// Moves the grabbed copies with the pointer (canvas position `at`).
    fn follow(&mut self, state: &mut EditorState, at: Option<Pos2>) {
        let Some(g) = &mut self.grab else {
            return;
        };
        let Some(at) = at else {
            return;
        };
        let anchor = *g.anchor.get_or_insert(at);
        let delta = at - anchor;
        let moves: Vec<(String, [f32; 2])> = (g.ids.iter().zip(&g.made))
            .map(|(id, p)| (id.clone(), [p[0] + delta.x, p[1] + delta.y]))
            .collect();
        place(state, &moves);
    }

    /// A primary click on the canvas: the node under the pointer (the topmost drawn), or
    /// empty canvas, picked as the modifiers say. Ctrl+Shift+click is the preview's.
    fn click(
        &mut self,
        ctx: &Context,
        state: &mut EditorState,
        drawn: &[(String, Rect)],
        to_screen: TSTransform,
        canvas: Rect,
    ) {
        let (clicked, at, modifiers) = ctx.input(|i| {
            (
                i.pointer.primary_clicked(),
                i.pointer.interact_pos(),
                i.modifiers,
            )
        });
        let Some(at) = at.filter(|p| clicked && canvas.contains(*p)) else {
            return;
        };
        if modifiers.command && modifiers.shift {
            return;
        }
        // Not a click on a window or popup over the canvas.
        if ctx
            .layer_id_at(at)
            .is_some_and(|l| l.order != egui::Order::Background)
        {
            return;
        }
        let p = to_screen.inverse() * at;
        let hit = drawn.iter().rev().find(|(_, r)| r.contains(p));
        let id = hit.map(|(id, _)| id.as_str());
        state.selection.click(id, Pick::of_click(modifiers));
        if let Some(id) = id.filter(|id| state.selection.contains(id)) {
            state.focus = Some(id.to_owned());
        }
    }

    /// egui-snarl moved the node it drags (only that one: its own selection is empty):
    /// the rest of the selection follows it; a node dragged that was not selected is
    /// selected first (only it; with Shift, added).
    fn drag_selection(&mut self, state: &mut EditorState, modifiers: Modifiers) {
        let moved: Vec<(NodeId, String, egui::Vec2)> = state
            .snarl
            .nodes_pos_ids()
            .filter_map(|(n, pos, v)| {
                let known = known_place(state, &v.id)?;
                let delta = pos - egui::pos2(known[0], known[1]);
                (delta != egui::Vec2::ZERO).then(|| (n, v.id.clone(), delta))
            })
            .collect();
        let [(_, id, delta)] = moved.as_slice() else {
            return;
        };
        if !state.selection.contains(id) {
            let pick = match modifiers.shift {
                true => Pick::Extend,
                false => Pick::Replace,
            };
            state.selection.click(Some(id), pick);
            return;
        }
        let others: Vec<NodeId> = state
            .snarl
            .node_ids()
            .filter(|(_, v)| v.id != *id && state.selection.contains(&v.id))
            .map(|(n, _)| n)
            .collect();
        for n in others {
            if let Some(info) = state.snarl.get_node_info_mut(n) {
                info.pos += *delta;
            }
        }
    }
}

/// What [`SelectTool::after_canvas`] reads of the canvas drawn this frame.
pub struct View<'a> {
    /// The nodes egui-snarl drew in full (id, frame in canvas points), the topmost last.
    pub drawn: &'a [(String, Rect)],
    /// Every node on the canvas (id, rect in canvas points) while a box selection is drawn
    /// (its end selects among them).
    pub rects: &'a [(String, Rect)],
    /// The canvas → screen transform of the frame.
    pub to_screen: TSTransform,
    /// The canvas' rect on screen.
    pub canvas: Rect,
}

/// Where node `id` is kept: its document position, or the Material Output node's place;
/// `None` for a node laid out and not placed yet.
fn known_place(state: &EditorState, id: &str) -> Option<[f32; 2]> {
    match id == OUTPUT_NODE {
        true => state.doc.output_node(),
        false => state.doc.node(id)?.position,
    }
}

/// Moves nodes to `moves` in the document (as part of the grab's undo step) and on the
/// canvas.
fn place(state: &mut EditorState, moves: &[(String, [f32; 2])]) {
    let _ = state.edit(Some(GRAB_KEY), false, |d| {
        d.set_positions(moves);
        Ok(())
    });
    for (id, p) in moves {
        if let Some(k) = state.doc.index(id)
            && let Some(info) = state.snarl.get_node_info_mut(NodeId(k))
        {
            info.pos = egui::pos2(p[0], p[1]);
        }
    }
}

/// Paints the box selection `rect` (screen) over the canvas.
fn paint_box(ctx: &Context, canvas: Rect, rect: Rect) {
    let painter = ctx
        .layer_painter(egui::LayerId::new(
            egui::Order::Foreground,
            egui::Id::new("matgraph-box-select"),
        ))
        .with_clip_rect(canvas);
    let visuals = &ctx.global_style().visuals;
    painter.rect(
        rect,
        0.0,
        visuals.selection.bg_fill.gamma_multiply(0.25),
        egui::Stroke::new(1.0, visuals.selection.stroke.color),
        egui::StrokeKind::Inside,
    );
}
