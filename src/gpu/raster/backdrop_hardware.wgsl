// The bubble backdrop's maps in the hardware texture mode: one rgba16float layer per map
// (BubbleMaps::named order, all MAP_SIZE²), level 0 only, filtered by the sampler (bilinear)
// on the objects' group 0. Bounded against the exact mode by the raster module's test
// `backdrop_hardware_maps_match_the_exact_sampler` (src/gpu/raster/mod.rs).

@group(0) @binding(5) var mgr_backdrop_maps: texture_2d_array<f32>;
@group(0) @binding(6) var mgr_backdrop_repeat: sampler;
@group(0) @binding(7) var mgr_backdrop_clamp: sampler;

// Map k at uv: level 0, bilinear, repeating where `wrap` is 0 (texture.rs Wrap index), else
// clamped (the backdrop uses no mirror).
fn mgr_backdrop_map(k: u32, uv: vec2<f32>, wrap: u32) -> vec4<f32> {
    if (wrap == 0u) {
        return textureSampleLevel(mgr_backdrop_maps, mgr_backdrop_repeat, uv, k, 0.0);
    }
    return textureSampleLevel(mgr_backdrop_maps, mgr_backdrop_clamp, uv, k, 0.0);
}
