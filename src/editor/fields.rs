//! Number fields of a fixed size. egui sizes a `DragValue` (and a slider's value box) by the
//! text it prints, and grows the `TextEdit` it becomes while typed in with the text typed;
//! egui-snarl sizes a node by its widgets, so a node grew after a value was written
//! (`12345.68` in a vector field) and while one was typed, and ran into its neighbours.
//! Each field here takes a slot of a fixed size ([`fixed`]), and prints its number with as
//! many decimals as fit the slot ([`fit_number`]; scientific notation where the integer
//! part does not fit), the text egui would print where it fits; while typed in it shows
//! egui's text and overflows its slot without moving anything.

use egui::{Align, FontId, Layout, Rect, Response, TextStyle, Ui, UiBuilder, Vec2};
use std::ops::RangeInclusive;
use std::sync::Arc;

/// The size of a number field: egui's interact size (the canvas sets its width).
pub fn number_size(ui: &Ui) -> Vec2 {
    ui.spacing().interact_size
}

/// The size of a slider with its value box: the rail, the spacing and a number field, as
/// egui lays it out.
pub fn slider_size(ui: &Ui) -> Vec2 {
    let s = ui.spacing();
    let height = s
        .interact_size
        .y
        .max(ui.text_style_height(&TextStyle::Body));
    egui::vec2(
        s.slider_width + s.item_spacing.x + s.interact_size.x,
        height,
    )
}

/// Allocates a slot of exactly `size` in `ui` and lets `add` lay out a widget in it, with
/// the [`Fit`] of its numbers: whatever the widget draws, `ui` advances by `size`.
pub fn fixed(ui: &mut Ui, size: Vec2, add: impl FnOnce(&mut Ui, Fit) -> Response) -> Response {
    let (_, rect) = ui.allocate_space(size);
    let fit = Fit::new(ui, rect);
    let mut slot = ui.new_child(
        UiBuilder::new()
            .max_rect(rect)
            .layout(Layout::left_to_right(Align::Center)),
    );
    add(&mut slot, fit)
}

/// Adds `field`: in a slot of [`number_size`], printing what fits, when `fixed`; else as
/// egui sizes it.
pub fn drag_value(ui: &mut Ui, fixed_size: bool, field: egui::DragValue<'_>) -> Response {
    match fixed_size {
        true => fixed(ui, number_size(ui), |ui, fit| {
            ui.add(field.custom_formatter(move |x, d| fit.format(x, d)))
        }),
        false => ui.add(field),
    }
}

/// Adds `slider`: in a slot of [`slider_size`], its value box printing what fits, when
/// `fixed`; else as egui sizes it.
pub fn slider(ui: &mut Ui, fixed_size: bool, slider: egui::Slider<'_>) -> Response {
    match fixed_size {
        true => fixed(ui, slider_size(ui), |ui, fit| {
            ui.add(slider.custom_formatter(move |x, d| fit.format(x, d)))
        }),
        false => ui.add(slider),
    }
}

/// How the numbers of one field are printed to fit its slot.
#[derive(Clone)]
pub struct Fit {
    ctx: egui::Context,
    font: FontId,
    style: Arc<egui::Style>,
    /// The text's width the number box holds: its width less the button padding.
    budget: f32,
    /// Whether a widget of the slot is being typed in (it shows egui's text, in full).
    editing: bool,
}

impl Fit {
    /// The fit of the numbers of a field in `slot` of `ui` (the number box being the
    /// slot's last [`number_size`] points).
    fn new(ui: &Ui, slot: Rect) -> Fit {
        let ctx = ui.ctx().clone();
        let editing = ctx
            .memory(|m| m.focused())
            .and_then(|id| ctx.read_response(id))
            // A field typed in grows to the right from where it starts, in the slot.
            .is_some_and(|r| slot.contains(r.rect.left_center()));
        Fit {
            font: ui.style().drag_value_text_style.resolve(ui.style()),
            style: ui.style().clone(),
            budget: number_size(ui).x - 2.0 * ui.spacing().button_padding.x,
            editing,
            ctx,
        }
    }

    /// `x` printed with the decimals egui chose (`decimals`), fewer if need be to fit.
    pub fn format(&self, x: f64, decimals: RangeInclusive<usize>) -> String {
        let egui = |x: f64, d: RangeInclusive<usize>| self.style.number_formatter.format(x, d);
        if self.editing {
            return egui(x, decimals);
        }
        fit_number(x, decimals, egui, |s| self.width(s) <= self.budget)
    }

    /// The width of `text` in the field's font, points.
    fn width(&self, text: &str) -> f32 {
        self.ctx.fonts_mut(|f| {
            f.layout_no_wrap(text.to_owned(), self.font.clone(), egui::Color32::WHITE)
                .size()
                .x
        })
    }
}

/// `x` as `format` prints it with `decimals` when `fits` accepts the text; else with fewer
/// decimals, down to none; else in scientific notation with 3 to 0 decimals
/// (`1.235e4`); else `x` with no decimal in scientific notation.
pub fn fit_number(
    x: f64,
    decimals: RangeInclusive<usize>,
    format: impl Fn(f64, RangeInclusive<usize>) -> String,
    fits: impl Fn(&str) -> bool,
) -> String {
    let (lo, hi) = (*decimals.start(), *decimals.end());
    let full = format(x, decimals);
    if fits(&full) {
        return full;
    }
    for d in (0..hi).rev() {
        let s = format(x, lo.min(d)..=d);
        if fits(&s) {
            return s;
        }
    }
    for p in (0..=3).rev() {
        let s = format!("{x:.p$e}");
        if fits(&s) {
            return s;
        }
    }
    format!("{x:.0e}")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fit(x: f64, chars: usize) -> String {
        fit_number(x, 2..=4, egui::emath::format_with_decimals_in_range, |s| {
            s.chars().count() <= chars
        })
    }

    #[test]
    fn numbers_keep_egui_text_where_it_fits_and_drop_decimals_then_digits() {
        assert_eq!(fit(0.3, 5), "0.30");
        assert_eq!(fit(-1.0, 5), "-1.00");
        assert_eq!(fit(0.123456, 6), "0.1235");
        assert_eq!(fit(0.123456, 5), "0.123");
        assert_eq!(fit(-0.174, 5), "-0.17");
        assert_eq!(fit(12345.678, 8), "12345.68");
        assert_eq!(fit(12345.678, 5), "12346");
        assert_eq!(fit(1234567.0, 5), "1.2e6");
        assert_eq!(fit(-1234567.0, 5), "-1e6");
        assert_eq!(fit(-1234567.0, 2), "-1e6");
        // What fits reads back close to the value.
        let s = fit(98765.4321, 5);
        let back: f64 = s.parse().unwrap();
        assert!((back - 98765.4321).abs() / 98765.4321 < 0.01, "{s}");
    }
}
