// The bubble scene's backdrop (src/scene/bubble.rs BackdropShader::radiance): unlit, the
// camera blend of the maps with the underwater quad's shimmer over it, each step a port of
// the node function it names (nodes/bubble.rs) and the maps sampled as the CPU samples them
// (bilinear, level 0; base, layers and alpha clamped, the normal maps repeating). Needs
// scene.wgsl and `mgr_backdrop_map(k, uv, wrap)`, map k in BubbleMaps::named order, from
// backdrop_exact.wgsl (the scene textures' storage buffers, as the CPU samples) or
// backdrop_hardware.wgsl (a texture array and the hardware's bilinear filter).

// BubbleBackdrop and the time (bubble.rs; packed.rs backdrop_words).
struct MgrBackdrop {
    // size (w, h), intensity_a, intensity_b.
    a: vec4<f32>,
    // mix, amount, tiles, time.
    b: vec4<f32>,
    // velocity_a, velocity_b.
    velocity: vec4<f32>,
    // light, strength.
    light: vec4<f32>,
    // tint, sharpness.
    tint: vec4<f32>,
    // opacity.
    c: vec4<f32>,
}

@group(1) @binding(6) var<storage, read> mgr_backdrop: MgrBackdrop;

// nodes/bubble.rs safe_unit: v / |v|, or +z where |v| is 0 or not finite.
fn mgr_backdrop_unit(v: vec3<f32>) -> vec3<f32> {
    let l2 = dot(v, v);
    if (l2 > 0.0 && l2 <= 0x1.fffffep+127f) {
        return v / sqrt(l2);
    }
    return vec3<f32>(0.0, 0.0, 1.0);
}

// BackdropShader::radiance at world point p.
fn mgr_backdrop_radiance(p: vec3<f32>) -> vec3<f32> {
    let b = mgr_backdrop;
    // BackdropShader::uv.
    let uv = vec2<f32>(p.x / b.a.x + 0.5, 0.5 - p.y / b.a.y);
    // camera_blend(base, layer_a, layer_b, …) (seed 000 eq. 12).
    let base = mgr_backdrop_map(0u, uv, 1u).xyz;
    let la = b.a.z * mgr_backdrop_map(1u, uv, 1u).xyz;
    let lb = b.a.w * mgr_backdrop_map(2u, uv, 1u).xyz;
    let layers = la + (lb - la) * b.b.x;
    let blend = base + (layers - base) * b.b.y;
    // underwater_uv(tiles · uv, time, velocity_a, velocity_b).
    let tuv = uv * b.b.z;
    let va = b.velocity.xy * b.b.w;
    let vb = b.velocity.zw * b.b.w;
    let uv_a = tuv + (va - floor(va));
    let uv_b = tuv + (vb - floor(vb));
    // underwater(normal_a(uv_a), normal_b(uv_b), alpha(uv).x, light, tint, …).
    let na = mgr_backdrop_map(3u, uv_a, 0u).xyz;
    let nb = mgr_backdrop_map(4u, uv_b, 0u).xyz;
    let alpha_map = mgr_backdrop_map(5u, uv, 1u).x;
    let n = mgr_backdrop_unit((2.0 * na - vec3<f32>(1.0)) + (2.0 * nb - vec3<f32>(1.0)));
    let l = mgr_backdrop_unit(b.light.xyz);
    let c = min(max(dot(n, l), 0.0), 1.0);
    let sharpness = b.tint.w;
    let lit = select(pow(select(c, 1.0, c == 0.0), sharpness), select(0.0, 1.0, sharpness == 0.0), c == 0.0);
    let shimmer = b.tint.xyz * (b.light.w * lit);
    let alpha = min(max(alpha_map * b.c.x, 0.0), 1.0);
    return blend + alpha * shimmer;
}
