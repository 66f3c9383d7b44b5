//! The mouse wheel in the Blender keymap: it zooms the canvas about the pointer, as
//! Blender's node editor does (egui, and the classic keymap, pan with it and zoom with
//! Ctrl+wheel). egui turns the wheel into a smoothed scroll delta spread over a few frames;
//! each frame's delta becomes a zoom of `exp(scroll_zoom_speed × delta)`, the factor egui
//! gives Ctrl+wheel, and the scroll is taken from egui-snarl so that it does not also pan.
//! The wheel with a modifier keeps egui's meaning (Ctrl zooms, Shift pans sideways).

use super::keymap::Keymap;
use egui::emath::TSTransform;
use egui::{Context, Rect, Vec2};

/// This frame's view when the plain wheel zooms (`keymap`'s choice) and turned over the
/// canvas `canvas` (screen), from the last frame's `to_screen`; `None` otherwise (the
/// scroll is then left to egui-snarl).
pub fn zoomed(
    ctx: &Context,
    keymap: Keymap,
    to_screen: TSTransform,
    canvas: Rect,
) -> Option<TSTransform> {
    if !keymap.wheel_zooms() || !canvas.is_positive() {
        return None;
    }
    let (scroll, modifiers, pointer) =
        ctx.input(|i| (i.smooth_scroll_delta, i.modifiers, i.pointer.hover_pos()));
    if scroll == Vec2::ZERO || modifiers.any() {
        return None;
    }
    let pointer = pointer.filter(|p| canvas.contains(*p))?;
    // Not over a window or popup above the canvas.
    if ctx
        .layer_id_at(pointer)
        .is_some_and(|l| l.order != egui::Order::Background)
    {
        return None;
    }
    let speed = ctx.options(|o| o.input_options.scroll_zoom_speed);
    let factor = (speed * (scroll.x + scroll.y)).exp();
    ctx.input_mut(|i| i.smooth_scroll_delta = Vec2::ZERO);
    Some(super::handoff::predict(
        to_screen,
        factor,
        Vec2::ZERO,
        Some(pointer),
        canvas,
    ))
}
