// Blender 4.x's EEVEE GLSL for the Noise Texture node, 3D fBm path (node_noise_tex_fbm_3d),
// transcribed into WGSL for examples/texture_speed.rs: the baseline matgraph's noise_texture is
// timed against. Only the functions that path calls, one WGSL function per GLSL function;
// GLSL overloads by dimension get a `_3d` suffix (WGSL has no overloading), macros are
// written out where the preprocessor expands them, `out` parameters are pointers, and the
// ternaries on `normalize` are if/else (WGSL's `select` would evaluate both sides). The
// node's socket values are read from a uniform block, as EEVEE reads unlinked sockets from the
// material's UBO; `normalize` is a node property, passed as a literal as EEVEE does.

// source/blender/gpu/shaders/common/gpu_shader_common_hash.glsl: hash_uint2 (lookup3's
// `final` macro expanded in place).
fn hash_uint2(kx: u32, ky: u32) -> u32 {
    var a = 0xdeadbeefu + (2u << 2u) + 13u;
    var b = a;
    var c = a;

    b += ky;
    a += kx;
    c ^= b; c -= (b << 14u) | (b >> 18u);
    a ^= c; a -= (c << 11u) | (c >> 21u);
    b ^= a; b -= (a << 25u) | (a >> 7u);
    c ^= b; c -= (b << 16u) | (b >> 16u);
    a ^= c; a -= (c << 4u) | (c >> 28u);
    b ^= a; b -= (a << 14u) | (a >> 18u);
    c ^= b; c -= (b << 24u) | (b >> 8u);
    return c;
}

// gpu_shader_common_hash.glsl: hash_uint3 (`final` expanded in place).
fn hash_uint3(kx: u32, ky: u32, kz: u32) -> u32 {
    var a = 0xdeadbeefu + (3u << 2u) + 13u;
    var b = a;
    var c = a;

    c += kz;
    b += ky;
    a += kx;
    c ^= b; c -= (b << 14u) | (b >> 18u);
    a ^= c; a -= (c << 11u) | (c >> 21u);
    b ^= a; b -= (a << 25u) | (a >> 7u);
    c ^= b; c -= (b << 16u) | (b >> 16u);
    a ^= c; a -= (c << 4u) | (c >> 28u);
    b ^= a; b -= (a << 14u) | (a >> 18u);
    c ^= b; c -= (b << 24u) | (b >> 8u);
    return c;
}

// gpu_shader_common_hash.glsl: hash_int3.
fn hash_int3(kx: i32, ky: i32, kz: i32) -> u32 {
    return hash_uint3(u32(kx), u32(ky), u32(kz));
}

// gpu_shader_common_hash.glsl: hash_uint2_to_float.
fn hash_uint2_to_float(kx: u32, ky: u32) -> f32 {
    return f32(hash_uint2(kx, ky)) / f32(0xFFFFFFFFu);
}

// gpu_shader_common_hash.glsl: hash_vec2_to_float.
fn hash_vec2_to_float(k: vec2<f32>) -> f32 {
    return hash_uint2_to_float(bitcast<u32>(k.x), bitcast<u32>(k.y));
}

// gpu_shader_common_math_utils.glsl / gpu_shader_math_base_lib.glsl: compatible_mod (float).
fn compatible_mod(a: f32, b: f32) -> f32 {
    if (b != 0.0) {
        let N = i32(a / b);
        return a - f32(N) * b;
    }
    return 0.0;
}

// gpu_shader_math_vector_safe_lib.glsl: compatible_mod (float3, float).
fn compatible_mod_3d(a: vec3<f32>, b: f32) -> vec3<f32> {
    return vec3<f32>(compatible_mod(a.x, b), compatible_mod(a.y, b), compatible_mod(a.z, b));
}

// source/blender/gpu/shaders/material/gpu_shader_material_noise.glsl: tri_mix.
fn tri_mix(v0: f32, v1: f32, v2: f32, v3: f32, v4: f32, v5: f32, v6: f32, v7: f32,
           x: f32, y: f32, z: f32) -> f32 {
    let x1 = 1.0 - x;
    let y1 = 1.0 - y;
    let z1 = 1.0 - z;
    return z1 * (y1 * (v0 * x1 + v1 * x) + y * (v2 * x1 + v3 * x)) +
           z * (y1 * (v4 * x1 + v5 * x) + y * (v6 * x1 + v7 * x));
}

// gpu_shader_material_noise.glsl: fade.
fn fade(t: f32) -> f32 {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

// gpu_shader_material_noise.glsl: negate_if.
fn negate_if(value: f32, condition: u32) -> f32 {
    return select(value, -value, condition != 0u);
}

// gpu_shader_material_noise.glsl: noise_grad (uint, float, float, float).
fn noise_grad_3d(hash: u32, x: f32, y: f32, z: f32) -> f32 {
    let h = hash & 15u;
    let u = select(y, x, h < 8u);
    let vt = select(z, x, (h == 12u) || (h == 14u));
    let v = select(vt, y, h < 4u);
    return negate_if(u, h & 1u) + negate_if(v, h & 2u);
}

// gpu_shader_material_noise.glsl: noise_perlin (float3), FLOORFRAC expanded.
fn noise_perlin_3d(v_in: vec3<f32>) -> f32 {
    let x_floor = floor(v_in.x);
    let X = i32(x_floor);
    let fx = v_in.x - x_floor;
    let y_floor = floor(v_in.y);
    let Y = i32(y_floor);
    let fy = v_in.y - y_floor;
    let z_floor = floor(v_in.z);
    let Z = i32(z_floor);
    let fz = v_in.z - z_floor;

    let u = fade(fx);
    let v = fade(fy);
    let w = fade(fz);

    let r = tri_mix(noise_grad_3d(hash_int3(X, Y, Z), fx, fy, fz),
                    noise_grad_3d(hash_int3(X + 1, Y, Z), fx - 1.0, fy, fz),
                    noise_grad_3d(hash_int3(X, Y + 1, Z), fx, fy - 1.0, fz),
                    noise_grad_3d(hash_int3(X + 1, Y + 1, Z), fx - 1.0, fy - 1.0, fz),
                    noise_grad_3d(hash_int3(X, Y, Z + 1), fx, fy, fz - 1.0),
                    noise_grad_3d(hash_int3(X + 1, Y, Z + 1), fx - 1.0, fy, fz - 1.0),
                    noise_grad_3d(hash_int3(X, Y + 1, Z + 1), fx, fy - 1.0, fz - 1.0),
                    noise_grad_3d(hash_int3(X + 1, Y + 1, Z + 1), fx - 1.0, fy - 1.0, fz - 1.0),
                    u,
                    v,
                    w);

    return r;
}

// gpu_shader_material_noise.glsl: noise_scale3.
fn noise_scale3(result: f32) -> f32 {
    return 0.9820 * result;
}

// gpu_shader_material_noise.glsl: snoise (float3).
fn snoise_3d(p0: vec3<f32>) -> f32 {
    let precision_correction = 0.5 * vec3<f32>(select(0.0, 1.0, abs(p0.x) >= 1000000.0),
                                               select(0.0, 1.0, abs(p0.y) >= 1000000.0),
                                               select(0.0, 1.0, abs(p0.z) >= 1000000.0));
    let p = compatible_mod_3d(p0, 100000.0) + precision_correction;

    return noise_scale3(noise_perlin_3d(p));
}

// gpu_shader_material_fractal_noise.glsl: noise_fbm (float3), the NOISE_FBM(float3) macro.
fn noise_fbm_3d(co: vec3<f32>, detail: f32, roughness: f32, lacunarity: f32, offset: f32,
                gain: f32, normalize: bool) -> f32 {
    let p = co;
    var fscale = 1.0;
    var amp = 1.0;
    var maxamp = 0.0;
    var sum = 0.0;

    for (var i = 0; i <= i32(detail); i++) {
        let t = snoise_3d(fscale * p);
        sum += t * amp;
        maxamp += amp;
        amp *= roughness;
        fscale *= lacunarity;
    }
    let rmd = detail - floor(detail);
    if (rmd != 0.0) {
        let t = snoise_3d(fscale * p);
        let sum2 = sum + t * amp;
        if (normalize) {
            return mix(0.5 * sum / maxamp + 0.5, 0.5 * sum2 / (maxamp + amp) + 0.5, rmd);
        }
        return mix(sum, sum2, rmd);
    } else {
        if (normalize) {
            return 0.5 * sum / maxamp + 0.5;
        }
        return sum;
    }
}

// gpu_shader_material_tex_noise.glsl: random_vec3_offset.
fn random_vec3_offset(seed: f32) -> vec3<f32> {
    return vec3<f32>(100.0 + hash_vec2_to_float(vec2<f32>(seed, 0.0)) * 100.0,
                     100.0 + hash_vec2_to_float(vec2<f32>(seed, 1.0)) * 100.0,
                     100.0 + hash_vec2_to_float(vec2<f32>(seed, 2.0)) * 100.0);
}

// gpu_shader_material_tex_noise.glsl: node_noise_tex_fbm_3d (NOISE_FRACTAL_DISTORTED_3D
// expanded).
fn node_noise_tex_fbm_3d(co: vec3<f32>, w: f32, scale: f32, detail0: f32, roughness0: f32,
                         lacunarity: f32, offset: f32, gain: f32, distortion: f32,
                         normalize: f32, value: ptr<function, f32>,
                         color: ptr<function, vec4<f32>>) {
    let detail = clamp(detail0, 0.0, 15.0);
    let roughness = max(roughness0, 0.0);

    var p = co * scale;

    if (distortion != 0.0) {
        p += vec3<f32>(snoise_3d(p + random_vec3_offset(0.0)) * distortion,
                       snoise_3d(p + random_vec3_offset(1.0)) * distortion,
                       snoise_3d(p + random_vec3_offset(2.0)) * distortion);
    }

    *value = noise_fbm_3d(p, detail, roughness, lacunarity, offset, gain, normalize != 0.0);
    *color = vec4<f32>(*value,
                       noise_fbm_3d(p + random_vec3_offset(3.0), detail, roughness, lacunarity,
                                    offset, gain, normalize != 0.0),
                       noise_fbm_3d(p + random_vec3_offset(4.0), detail, roughness, lacunarity,
                                    offset, gain, normalize != 0.0),
                       1.0);
}

// The material: what EEVEE's generated code does for a Noise Texture fed the position,
// with its unlinked sockets in the material UBO.
struct NodeUniforms {
    scale: f32,
    detail: f32,
    roughness: f32,
    lacunarity: f32,
    offset: f32,
    gain: f32,
    distortion: f32,
    w: f32,
}

@group(0) @binding(0) var<uniform> node_uniforms: NodeUniforms;

struct TsOutputs {
    fac: f32,
    color: vec3<f32>,
}

fn ts_material(position: vec3<f32>) -> TsOutputs {
    var value: f32;
    var color: vec4<f32>;
    node_noise_tex_fbm_3d(position, node_uniforms.w, node_uniforms.scale, node_uniforms.detail,
                          node_uniforms.roughness, node_uniforms.lacunarity,
                          node_uniforms.offset, node_uniforms.gain, node_uniforms.distortion,
                          1.0, &value, &color);
    return TsOutputs(value, color.xyz);
}
