// The bubble backdrop's maps in the exact texture mode: scene textures from slot
// mgr_frame.slots.y on (BubbleMaps::named order), sampled as the CPU samples them.

// Map k at uv: level 0, bilinear, `wrap` (texture.rs Wrap index).
fn mgr_backdrop_map(k: u32, uv: vec2<f32>, wrap: u32) -> vec4<f32> {
    return mgs_sample_texture(mgr_frame.slots.y + k, uv, 0.0, wrap, 1u);
}
