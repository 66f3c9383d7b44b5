// Composite and resolve (src/render/mod.rs shade_band, stage 4): per sample
// `alpha · radiance + (1 − alpha) · background` where the material is nearest (the material
// target holds mg_fragment's premultiplied `(alpha · radiance, alpha)`, alpha ≥ 0 there; it
// is cleared to alpha −1), the background elsewhere; the samples
// of a pixel summed in the CPU's sample order and divided by their count.

@group(0) @binding(0) var mgr_scene: MGR_TEXTURE;
@group(0) @binding(1) var mgr_material: MGR_TEXTURE;
@group(0) @binding(2) var<storage, read_write> mgr_pixels: array<f32>;
// Width, height, samples; then the hardware sample index of each CPU sample.
@group(0) @binding(3) var<uniform> mgr_resolve: array<vec4<u32>, 5>;

@compute @workgroup_size(8, 8)
fn mgr_resolve_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let dims = mgr_resolve[0];
    if (id.x >= dims.x || id.y >= dims.y) {
        return;
    }
    let xy = vec2<i32>(id.xy);
    var sum = vec3<f32>(0.0);
    for (var s = 0u; s < dims.z; s++) {
        let hw = i32(mgr_resolve[1u + s / 4u][s % 4u]);
        let bg = textureLoad(mgr_scene, xy, hw).xyz;
        let m = textureLoad(mgr_material, xy, hw);
        var c = bg;
        if (m.w >= 0.0) {
            c = m.xyz + bg * (1.0 - m.w);
        }
        sum += c;
    }
    let px = sum / f32(dims.z);
    let i = 3u * (id.y * dims.x + id.x);
    mgr_pixels[i] = px.x;
    mgr_pixels[i + 1u] = px.y;
    mgr_pixels[i + 2u] = px.z;
}
