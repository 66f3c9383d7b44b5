// The `scene:environment` map: src/render/mod.rs environment_map, texel centres mapped to
// directions by the inverse of scene::equirect_uv, each the sky's radiance
// (Environment::radiance of a procedural sky). Needs scene.wgsl.

@group(0) @binding(0) var<storage, read_write> mgr_texels: array<vec4<f32>>;

@compute @workgroup_size(8, 8)
fn mgr_environment(@builtin(global_invocation_id) id: vec3<u32>) {
    let w = u32(mgr_frame.width);
    let h = u32(mgr_frame.height);
    if (id.x >= w || id.y >= h) {
        return;
    }
    let tau = 6.2831855;
    let pi = 3.1415927;
    let phi = ((f32(id.x) + 0.5) / f32(w) - 0.5) * tau;
    let theta = (f32(id.y) + 0.5) / f32(h) * pi;
    let d = vec3<f32>(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
    mgr_texels[id.y * w + id.x] = vec4<f32>(mgr_sky(d, true), 1.0);
}
