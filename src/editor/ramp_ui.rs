//! The ramp-and-curve widget in the body of a `color_ramp`, `float_curve` or `rgb_curves`
//! node, as Blender draws it: a colour strip with its stops under it (drag a stop; click
//! the strip to add one with the ramp's colour there; right-click a stop, or Delete while the
//! pointer is on the strip, to remove it; the selected stop's colour picker below), or a
//! square plot of the curve with its points (drag, click to add, right-click to remove) and,
//! for RGB Curves, the tabs C, R, G, B. The interpolation stays the node's own drop-down.
//! Edits are [`super::ramps::Edits`]; one drag is one undo step (its key).

use super::model::EditorDoc;
use super::ramps::{self, CurvePoints, Edits, Ramp};
use egui::{Color32, Pos2, Rect, Sense, Shape, Stroke, Ui, vec2};

/// The strip's and the plot's width, canvas points.
pub const WIDTH: f32 = 180.0;
/// The colour strip's height.
pub const STRIP: f32 = 20.0;
/// The stop markers' row under the strip.
pub const MARKS: f32 = 12.0;
/// The curve plot's height.
const PLOT: f32 = 120.0;
/// How near (points) the pointer must be to a stop or point to pick it.
const PICK: f32 = 7.0;

/// The widget's height below a node's pins for a node of type `ty` (for the layout's
/// estimate of a node's size), `None` for other types.
pub fn height(ty: &str) -> Option<f32> {
    match ty {
        "color_ramp" => Some(STRIP + MARKS + 30.0),
        "float_curve" => Some(PLOT + 8.0),
        "rgb_curves" => Some(PLOT + 30.0),
        _ => None,
    }
}

/// An edit the widget asks for: the inputs to write and its undo key (`Some` while a drag
/// goes on, so that the drag is one step).
pub type WidgetEdit = (Edits, Option<String>);

/// What the widget keeps between frames, per node.
#[derive(Clone, Copy, Debug, Default)]
struct Memory {
    /// The selected stop or point.
    selected: Option<usize>,
    /// The curve tab shown (0 = C for RGB Curves).
    channel: usize,
}

/// Draws the widget of node `id` (of type `ty`); returns the edit made, if any, and the
/// rect of the strip with its markers' row under it, or of the plot (canvas points: where
/// Delete goes to the widget, and for tests).
pub fn show(ui: &mut Ui, doc: &EditorDoc, id: &str, ty: &str) -> (Option<WidgetEdit>, Rect) {
    let mem_id = egui::Id::new(("ramp_widget", id));
    let mut mem: Memory = ui.data(|d| d.get_temp(mem_id)).unwrap_or_default();
    let out = if ty == "color_ramp" {
        ramp_widget(ui, doc, id, &mut mem)
    } else {
        curve_widget(ui, doc, id, ty, &mut mem)
    };
    ui.data_mut(|d| d.insert_temp(mem_id, mem));
    out
}

/// Where the pointer was pressed, in the widget's (the canvas layer's) coordinates.
fn press_origin(ui: &Ui) -> Option<Pos2> {
    let at = ui.input(|i| i.pointer.press_origin())?;
    let from_global = ui.ctx().layer_transform_from_global(ui.layer_id());
    Some(from_global.map_or(at, |t| t * at))
}

/// A linear RGB colour as egui's (sRGB-encoded) one.
fn shown(c: [f32; 4]) -> Color32 {
    egui::Rgba::from_rgb(c[0].max(0.0), c[1].max(0.0), c[2].max(0.0)).into()
}

/// The stop of `stops` (positions) nearest to `x` within [`PICK`] points on `rect`.
fn nearest(rect: Rect, positions: impl Iterator<Item = f32>, x: f32) -> Option<usize> {
    positions
        .enumerate()
        .map(|(k, p)| (k, (rect.left() + p * rect.width() - x).abs()))
        .filter(|&(_, d)| d <= PICK)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(k, _)| k)
}

fn ramp_widget(
    ui: &mut Ui,
    doc: &EditorDoc,
    id: &str,
    mem: &mut Memory,
) -> (Option<WidgetEdit>, Rect) {
    let Some(ramp) = Ramp::read(doc, id) else {
        return (None, Rect::NOTHING);
    };
    let (rect, resp) = ui.allocate_exact_size(vec2(WIDTH, STRIP + MARKS), Sense::click_and_drag());
    let strip = Rect::from_min_size(rect.min, vec2(WIDTH, STRIP));
    let painter = ui.painter_at(rect);
    // The gradient, 90 columns, on a checker for alpha.
    let columns = 90;
    for c in 0..columns {
        let x0 = strip.left() + strip.width() * c as f32 / columns as f32;
        let x1 = strip.left() + strip.width() * (c + 1) as f32 / columns as f32;
        let col = ramp.at((c as f32 + 0.5) / columns as f32);
        let r = Rect::from_x_y_ranges(x0..=x1 + 0.5, strip.y_range());
        painter.rect_filled(r, 0.0, shown(col));
    }
    painter.rect_stroke(
        strip,
        0.0,
        Stroke::new(1.0, Color32::BLACK),
        egui::StrokeKind::Inside,
    );
    for (k, &(p, c)) in ramp.stops.iter().enumerate() {
        let x = strip.left() + p.clamp(0.0, 1.0) * strip.width();
        let top = strip.bottom();
        let tri = vec![
            Pos2::new(x, top),
            Pos2::new(x - 5.0, top + MARKS - 1.0),
            Pos2::new(x + 5.0, top + MARKS - 1.0),
        ];
        let edge = match mem.selected == Some(k) {
            true => Color32::WHITE,
            false => Color32::BLACK,
        };
        painter.add(Shape::convex_polygon(tri, shown(c), Stroke::new(1.5, edge)));
    }
    let mut edit = None;
    let pointer = resp.interact_pointer_pos().or(resp.hover_pos());
    let pos_at = |x: f32| ((x - strip.left()) / strip.width()).clamp(0.0, 1.0);
    let positions = || ramp.stops.iter().map(|s| s.0.clamp(0.0, 1.0));
    // A drag picks the stop where it was pressed (egui starts it some points further on).
    let origin = press_origin(ui);
    if resp.drag_started()
        && let Some(p) = origin.or(pointer)
    {
        mem.selected = nearest(strip, positions(), p.x);
    }
    if resp.dragged()
        && let (Some(k), Some(p)) = (mem.selected, pointer)
        && k < ramp.stops.len()
    {
        let key = format!("widget:{id}:{}", crate::nodes::color_ramp::POSITIONS[k]);
        edit = Some((ramp.move_stop(k, pos_at(p.x)), Some(key)));
    }
    if resp.clicked()
        && let Some(p) = pointer
    {
        match nearest(strip, positions(), p.x) {
            Some(k) => mem.selected = Some(k),
            None => {
                if let Some(e) = ramp.add_stop(pos_at(p.x)) {
                    mem.selected = Some(ramp.stops.len());
                    edit = Some((e, None));
                }
            }
        }
    }
    if resp.secondary_clicked()
        && let Some(p) = pointer
    {
        mem.selected = nearest(strip, positions(), p.x);
    }
    if removal_asked(ui, &resp, "Remove stop", mem.selected.is_some())
        && let Some(k) = mem.selected
        && let Some(e) = ramp.remove_stop(k)
    {
        mem.selected = None;
        edit = Some((e, None));
    }
    // The selected stop's position and colour.
    if let Some(k) = mem.selected.filter(|&k| k < ramp.stops.len()) {
        ui.horizontal(|ui| {
            ui.label(format!("stop {k}"));
            let c = ramp.stops[k].1;
            let mut rgba = egui::Rgba::from_rgba_unmultiplied(c[0], c[1], c[2], c[3]);
            if egui::color_picker::color_edit_button_rgba(
                ui,
                &mut rgba,
                egui::color_picker::Alpha::OnlyBlend,
            )
            .changed()
            {
                let [r, g, b, a] = rgba.to_rgba_unmultiplied();
                let key = format!("widget:{id}:{}", crate::nodes::color_ramp::COLORS[k]);
                edit = Some((ramp.set_color(k, [r, g, b, a]), Some(key)));
            }
        });
    }
    (edit, rect)
}

fn curve_widget(
    ui: &mut Ui,
    doc: &EditorDoc,
    id: &str,
    ty: &str,
    mem: &mut Memory,
) -> (Option<WidgetEdit>, Rect) {
    let channels = ramps::channels(ty);
    if channels.len() > 1 {
        ui.horizontal(|ui| {
            for (k, c) in channels.iter().enumerate() {
                if ui.selectable_label(mem.channel == k, c.label).clicked() {
                    mem.channel = k;
                    mem.selected = None;
                }
            }
        });
    }
    let Some(&channel) = channels.get(mem.channel.min(channels.len().saturating_sub(1))) else {
        return (None, Rect::NOTHING);
    };
    let Some(curve) = CurvePoints::read(doc, id, channel) else {
        return (None, Rect::NOTHING);
    };
    let (rect, resp) = ui.allocate_exact_size(vec2(WIDTH, PLOT), Sense::click_and_drag());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 0.0, Color32::from_gray(40));
    for q in 1..4 {
        let t = q as f32 / 4.0;
        let grid = Stroke::new(1.0, Color32::from_gray(60));
        let x = rect.left() + t * rect.width();
        let y = rect.bottom() - t * rect.height();
        painter.line_segment(
            [Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom())],
            grid,
        );
        painter.line_segment(
            [Pos2::new(rect.left(), y), Pos2::new(rect.right(), y)],
            grid,
        );
    }
    let to_screen = |p: [f32; 2]| {
        Pos2::new(
            rect.left() + p[0] * rect.width(),
            rect.bottom() - p[1] * rect.height(),
        )
    };
    let from_screen = |p: Pos2| {
        [
            (p.x - rect.left()) / rect.width(),
            (rect.bottom() - p.y) / rect.height(),
        ]
    };
    let colour = match channel.label {
        "R" => Color32::from_rgb(230, 80, 80),
        "G" => Color32::from_rgb(80, 200, 80),
        "B" => Color32::from_rgb(90, 130, 240),
        _ => Color32::from_gray(220),
    };
    let line: Vec<Pos2> = (0..=64)
        .map(|i| {
            let x = i as f32 / 64.0;
            to_screen([x, curve.at(x)])
        })
        .collect();
    painter.add(Shape::line(line, Stroke::new(1.5, colour)));
    for (k, &p) in curve.points.iter().enumerate() {
        let fill = match mem.selected == Some(k) {
            true => Color32::WHITE,
            false => Color32::BLACK,
        };
        painter.circle(to_screen(p), 3.5, fill, Stroke::new(1.0, colour));
    }
    let near = |at: Pos2| {
        curve
            .points
            .iter()
            .enumerate()
            .map(|(k, &p)| (k, to_screen(p).distance(at)))
            .filter(|&(_, d)| d <= PICK)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(k, _)| k)
    };
    let mut edit = None;
    let pointer = resp.interact_pointer_pos().or(resp.hover_pos());
    let origin = press_origin(ui);
    if resp.drag_started()
        && let Some(p) = origin.or(pointer)
    {
        mem.selected = near(p);
    }
    if resp.dragged()
        && let (Some(k), Some(p)) = (mem.selected, pointer)
        && k < curve.points.len()
    {
        let key = format!("widget:{id}:{}", channel.points[k]);
        edit = Some((curve.move_point(k, from_screen(p)), Some(key)));
    }
    if resp.clicked()
        && let Some(p) = pointer
    {
        match near(p) {
            Some(k) => mem.selected = Some(k),
            None => {
                if let Some(e) = curve.add_point(from_screen(p)) {
                    mem.selected = Some(curve.points.len());
                    edit = Some((e, None));
                }
            }
        }
    }
    if resp.secondary_clicked()
        && let Some(p) = pointer
    {
        mem.selected = near(p);
    }
    if removal_asked(ui, &resp, "Remove point", mem.selected.is_some())
        && let Some(k) = mem.selected
        && let Some(e) = curve.remove_point(k)
    {
        mem.selected = None;
        edit = Some((e, None));
    }
    (edit, rect)
}

/// Whether the user asks to remove the selected stop or point of a widget (`resp`): its
/// right-click menu's `label` (enabled when something is selected), or Delete over it.
fn removal_asked(ui: &egui::Ui, resp: &egui::Response, label: &str, selected: bool) -> bool {
    let mut remove = false;
    resp.context_menu(|ui| {
        if ui.add_enabled(selected, egui::Button::new(label)).clicked() {
            remove = true;
            ui.close();
        }
    });
    remove || (resp.hovered() && ui.input(|i| i.key_pressed(egui::Key::Delete)))
}
