//! Rendering the editor without a window: egui_kittest drives frames of [`EditorApp`] and its
//! wgpu renderer (lavapipe, or any adapter) draws the last one to an image.

use super::EditorApp;
use egui_kittest::Harness;

/// Frames run before the screenshot, so that layout and fonts settle.
pub const SETTLE_FRAMES: usize = 6;

/// Longest wait for the preview swatch before the screenshot is taken anyway.
pub const PREVIEW_WAIT: std::time::Duration = std::time::Duration::from_secs(60);

/// Whether a wgpu adapter exists (the screenshot renderer needs one).
pub fn adapter_available() -> bool {
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default())).is_ok()
}

/// A harness of `app` at `size` (points = pixels), rendering with wgpu.
pub fn harness(app: EditorApp, size: [u32; 2]) -> Harness<'static, EditorApp> {
    let h = Harness::builder()
        .with_size(egui::vec2(size[0] as f32, size[1] as f32))
        .wgpu()
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), app);
    h.ctx.set_fonts(super::fonts());
    h
}

/// Renders `app` at `size` to RGBA8 pixels (row-major, top row first), after the preview
/// finished (or [`PREVIEW_WAIT`]).
pub fn screenshot(app: EditorApp, size: [u32; 2]) -> Result<(u32, u32, Vec<u8>), String> {
    if !adapter_available() {
        return Err(
            "no GPU adapter (install Mesa's lavapipe: apt-get install mesa-vulkan-drivers)".into(),
        );
    }
    let mut h = harness(app, size);
    h.run_steps(SETTLE_FRAMES);
    let start = std::time::Instant::now();
    while !(h.state().state.preview.settled() && h.state().settled())
        && start.elapsed() < PREVIEW_WAIT
    {
        std::thread::sleep(std::time::Duration::from_millis(50));
        h.step();
    }
    h.run_steps(2);
    let image = h.render()?;
    Ok((image.width(), image.height(), image.into_raw()))
}
