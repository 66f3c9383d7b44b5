//! A picture of the scene without the material (the screen-space scene textures), and the
//! clears the frame's targets start from.

use super::*;

/// A picture of the scene without the material (`pass`) at `w × h`, one sample per pixel
/// at the pixel centre, linear RGB; `environment` is the image of an image environment,
/// `mode` how the bubble backdrop's maps are sampled.
pub(crate) fn render_scene_pass(
    ctx: &GpuContext,
    scene: &Scene,
    environment: Option<&Arc<Texture>>,
    (w, h): (u32, u32),
    pass: ScenePass,
    mode: TextureMode,
) -> Result<Vec<[f32; 3]>, EvalError> {
    let s = &*ctx.state;
    s.scoped("drawing a scene texture on the GPU", || {
        let gpu = SceneGpu::new(s, scene, 1, environment, mode)?;
        let view = Viewport::whole(w, h);
        let frame = gpu.frame_group(s, &scene.frame_uniform(&gpu.packed, w, h, pass, &view));
        let color = target(
            s,
            "mgr scene",
            (w, h, 1),
            COLOR,
            wgpu::TextureUsages::empty(),
        );
        let depth = target(
            s,
            "mgr depth",
            (w, h, 1),
            DEPTH,
            wgpu::TextureUsages::empty(),
        );
        let material = target(
            s,
            "mgr no material",
            (w, h, 1),
            COLOR,
            wgpu::TextureUsages::empty(),
        );
        let mut enc = s.device.create_command_encoder(&Default::default());
        gpu.record(&mut enc, &frame, pass, &color, &depth, false);
        clear(&mut enc, &material);
        let bytes = w as u64 * h as u64 * 12;
        let out = pixels_buffer(s, bytes);
        resolve(
            s,
            &mut enc,
            (&color, &material),
            &out,
            (w, h, 1),
            Samples::Whole,
        );
        let st = staging(s, bytes);
        enc.copy_buffer_to_buffer(&out, 0, &st, 0, bytes);
        submit_and_wait(s, enc)?;
        let data = read_back(s, st, bytes)?;
        Ok(data.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
    })
}

/// The clear colour of a material target: "no material here" (alpha −1).
pub(super) const NO_MATERIAL: wgpu::Color = wgpu::Color {
    r: 0.0,
    g: 0.0,
    b: 0.0,
    a: -1.0,
};

/// Clears a material target to [`NO_MATERIAL`].
pub(super) fn clear(enc: &mut wgpu::CommandEncoder, view: &wgpu::TextureView) {
    enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("mgr clear"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(NO_MATERIAL),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
}
