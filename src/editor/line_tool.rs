//! Lines drawn with the right button in the Blender keymap ([`super::keymap::LineTool`]):
//! Ctrl+right-drag cuts the wires the line crosses, Shift+right-drag adds a reroute on
//! them ([`super::link_edits`]), on release, as Blender's gesture lines do. egui-snarl pans
//! on a right-drag of its background; while a line is drawn the view is held where it was.
//! A line shorter than a click (6 points) does nothing, and the right-click's menu opens as
//! before; Escape drops the line. Below the overview's zoom ([`super::viewer::LOW_DETAIL_ZOOM`])
//! wires are not egui-snarl's to cross, and no line is begun (as wires are made zoomed in).

use super::keymap::LineTool;
use super::link_edits::Crossed;
use super::outputs::OUTPUT_NODE;
use super::state::EditorState;
use super::wires::{PinAt, crossed, painted};
use egui::emath::TSTransform;
use egui::{Context, PointerButton, Pos2, Rect};
use egui_snarl::{InPinId, OutPinId};

/// Screen points a line must run (its length) to be a line and not a click.
pub const MIN_LENGTH: f32 = 6.0;

/// A line being drawn.
#[derive(Clone, Debug)]
struct Line {
    tool: LineTool,
    /// Its points, canvas points.
    points: Vec<Pos2>,
    /// The view it holds (canvas → screen).
    view: TSTransform,
    /// Its length so far, screen points.
    length: f32,
}

/// The line tool across frames.
#[derive(Clone, Debug, Default)]
pub struct LineGesture {
    line: Option<Line>,
}

/// What [`LineGesture::after_canvas`] reads of the canvas drawn this frame.
pub struct Drawn<'a> {
    /// Where egui-snarl painted its wires ([`super::wire_order::Slot`]).
    pub wires: Option<super::wire_order::Slot>,
    /// The pins it drew ([`super::wires::PinPlaces`]).
    pub pins: &'a [PinAt],
    /// The canvas' rect on screen.
    pub canvas: Rect,
}

impl LineGesture {
    /// Whether a line is being drawn.
    pub fn drawing(&self) -> bool {
        self.line.is_some()
    }

    /// Before the canvas is drawn: begins a line on a right press over the canvas with the
    /// keymap's modifier held (not while `busy`: another pointer tool is on); the view to
    /// hold while one is drawn.
    pub fn begin(
        &mut self,
        ctx: &Context,
        state: &mut EditorState,
        to_screen: TSTransform,
        canvas: Rect,
        busy: bool,
    ) -> Option<TSTransform> {
        if self.line.is_none() && !busy {
            let (pressed, origin, modifiers) = ctx.input(|i| {
                (
                    i.pointer.button_pressed(PointerButton::Secondary),
                    i.pointer.press_origin(),
                    i.modifiers,
                )
            });
            let over_canvas = origin.filter(|p| canvas.contains(*p)).is_some_and(|p| {
                ctx.layer_id_at(p)
                    .is_none_or(|l| l.order == egui::Order::Background)
            });
            if let Some(tool) = state.settings.keymap().line_tool(modifiers)
                && pressed
                && over_canvas
                && let Some(origin) = origin
            {
                if to_screen.scaling < super::viewer::LOW_DETAIL_ZOOM {
                    state.status = Some("zoom in to cut wires or add reroutes".into());
                } else {
                    self.line = Some(Line {
                        tool,
                        points: vec![to_screen.inverse() * origin],
                        view: to_screen,
                        length: 0.0,
                    });
                }
            }
        }
        self.line.as_ref().map(|l| l.view)
    }

    /// After the canvas is drawn: the line follows the pointer and is painted; on release
    /// it cuts or reroutes the wires it crossed (one undo step). Returns whether a line
    /// ended or was dropped this frame (its release is no click: no menu).
    pub fn after_canvas(
        &mut self,
        ctx: &Context,
        state: &mut EditorState,
        drawn: Drawn<'_>,
    ) -> bool {
        let Some(line) = &mut self.line else {
            return false;
        };
        let (down, pointer, escape) = ctx.input(|i| {
            (
                i.pointer.button_down(PointerButton::Secondary),
                i.pointer.latest_pos(),
                i.key_pressed(egui::Key::Escape),
            )
        });
        if escape {
            self.line = None;
            state.status = Some("line dropped".into());
            return true;
        }
        if let Some(p) = pointer {
            let last = line.view * *line.points.last().expect("a line has a point");
            let step = (p - last).length();
            if step >= 1.0 {
                line.points.push(line.view.inverse() * p);
                line.length += step;
            }
        }
        if down {
            paint(ctx, drawn.canvas, line);
            return false;
        }
        let line = self.line.take().expect("a line is drawn");
        if line.length < MIN_LENGTH {
            return false;
        }
        let wires: Vec<(OutPinId, InPinId)> = state.snarl.wires().collect();
        let painted = drawn.wires.map(|s| painted(ctx, s)).unwrap_or_default();
        let hits: Vec<Crossed> = crossed(&line.points, &wires, drawn.pins, &painted)
            .into_iter()
            .filter_map(|(from, to, at)| named(state, from, to, at))
            .collect();
        if hits.is_empty() {
            state.status = Some("the line crossed no wire".into());
            return true;
        }
        match line.tool {
            LineTool::Cut => state.cut_links(&hits),
            LineTool::Reroute => {
                let _ = state.add_reroutes(&hits);
            }
        }
        true
    }
}

/// The wire from `from` to `to` crossed at `at`, by its nodes' ids and its ports' names.
fn named(state: &EditorState, from: OutPinId, to: InPinId, at: Pos2) -> Option<Crossed> {
    let doc = &state.doc;
    let source = state.snarl.get_node(from.node)?.id.clone();
    let target = state.snarl.get_node(to.node)?.id.clone();
    let output = doc
        .ports(&source)?
        .outputs
        .get(from.output)?
        .name
        .to_string();
    let input = match target == OUTPUT_NODE {
        true => doc.doc().outputs.get(to.input)?.name.clone(),
        false => doc.ports(&target)?.inputs.get(to.input)?.name.to_string(),
    };
    Some(Crossed {
        from: source,
        output,
        to: target,
        input,
        at: [at.x, at.y],
    })
}

/// Paints `line` over the canvas: dashed for a cut, solid for reroutes.
fn paint(ctx: &Context, canvas: Rect, line: &Line) {
    let painter = ctx
        .layer_painter(egui::LayerId::new(
            egui::Order::Foreground,
            egui::Id::new("matgraph-line-tool"),
        ))
        .with_clip_rect(canvas);
    let points: Vec<Pos2> = line.points.iter().map(|p| line.view * *p).collect();
    let cut = line.tool == LineTool::Cut;
    let stroke = egui::Stroke::new(2.0, super::wires::line_color(cut));
    match cut {
        true => {
            painter.extend(egui::Shape::dashed_line(&points, stroke, 6.0, 4.0));
        }
        false => {
            painter.add(egui::Shape::line(points, stroke));
        }
    }
}
