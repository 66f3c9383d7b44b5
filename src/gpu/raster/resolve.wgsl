// Composite and resolve (src/render/mod.rs shade_band, stage 4): per sample
// `alpha · radiance + (1 − alpha) · background` where the material is nearest (the material
// target holds mg_fragment's premultiplied `(alpha · radiance, alpha)`, alpha ≥ 0 there; it
// is cleared to alpha −1), the background elsewhere; the samples
// of a pixel summed in the CPU's sample order and divided by their count.

@group(0) @binding(0) var mgr_scene: MGR_TEXTURE;
@group(0) @binding(1) var mgr_material: MGR_TEXTURE;
@group(0) @binding(2) var<storage, read_write> mgr_pixels: array<f32>;
// Width, height, samples (and in mgr_accumulate_main the pass); then the hardware sample
// index of each CPU sample.
@group(0) @binding(3) var<uniform> mgr_resolve: array<vec4<u32>, 5>;

// One sample's composite: the material's premultiplied radiance over the background where
// the material is (alpha ≥ 0), the background elsewhere.
fn mgr_composite(bg: vec3<f32>, m: vec4<f32>) -> vec3<f32> {
    if (m.w >= 0.0) {
        return m.xyz + bg * (1.0 - m.w);
    }
    return bg;
}

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
        sum += mgr_composite(textureLoad(mgr_scene, xy, hw).xyz, textureLoad(mgr_material, xy, hw));
    }
    let px = sum / f32(dims.z);
    let i = 3u * (id.y * dims.x + id.x);
    mgr_pixels[i] = px.x;
    mgr_pixels[i + 1u] = px.y;
    mgr_pixels[i + 2u] = px.z;
}

// One jittered pass (mod.rs accumulate): its one sample per pixel composited as above and
// added to the pixel's sum (pass 0 stores it), the sum divided by the sample count after
// the last pass: mgr_resolve_main's arithmetic, in the CPU's sample order.
@compute @workgroup_size(8, 8)
fn mgr_accumulate_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let dims = mgr_resolve[0];
    if (id.x >= dims.x || id.y >= dims.y) {
        return;
    }
    let xy = vec2<i32>(id.xy);
    let c = mgr_composite(textureLoad(mgr_scene, xy, 0).xyz, textureLoad(mgr_material, xy, 0));
    let i = 3u * (id.y * dims.x + id.x);
    var sum = c;
    if (dims.w > 0u) {
        sum = vec3<f32>(mgr_pixels[i], mgr_pixels[i + 1u], mgr_pixels[i + 2u]) + c;
    }
    if (dims.w + 1u == dims.z) {
        sum = sum / f32(dims.z);
    }
    mgr_pixels[i] = sum.x;
    mgr_pixels[i + 1u] = sum.y;
    mgr_pixels[i + 2u] = sum.z;
}
