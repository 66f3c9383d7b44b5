// Blender 4.x's EEVEE GLSL for the Voronoi Texture node, 3D F1 path (node_tex_voronoi_f1_3d),
// transcribed into WGSL for examples/texture_speed.rs: the baseline matgraph's voronoi_texture
// is timed against. Only the functions that path calls, one WGSL function per GLSL function:
// fractal_voronoi_x_fx picks the octave function by the runtime `params.feature`, so F2 and
// smooth F1 are called from it and are transcribed too (EEVEE's shader holds them; the driver
// may fold them away once the constant feature is inlined). GLSL overloads by dimension get a
// `_3d` suffix (WGSL has no overloading), lookup3's `mix`/`final` macros are written out where
// the preprocessor expands them, `out` parameters are pointers. Socket values come from a
// uniform block, as EEVEE reads unlinked sockets from the material's UBO; `metric` and
// `normalize` are node properties, passed as literals as EEVEE does.
//
// This is the 4.x definition, whose cells are hashed by lookup3 of their float coordinates
// (hash_vec3_to_vec3), as matgraph's node and its Blender 4.2 reference values are; Blender's
// main branch has since moved Voronoi to the PCG integer hash (hash_int3_to_vec3), not
// transcribed here.

const FLT_MAX: f32 = 3.402823466e+38;

const SHD_VORONOI_EUCLIDEAN: i32 = 0;
const SHD_VORONOI_MANHATTAN: i32 = 1;
const SHD_VORONOI_CHEBYCHEV: i32 = 2;
const SHD_VORONOI_MINKOWSKI: i32 = 3;

const SHD_VORONOI_F1: i32 = 0;
const SHD_VORONOI_F2: i32 = 1;
const SHD_VORONOI_SMOOTH_F1: i32 = 2;

// source/blender/gpu/shaders/common/gpu_shader_common_hash.glsl: hash_uint3 (lookup3's
// `final` macro expanded in place).
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

// gpu_shader_common_hash.glsl: hash_uint4 (`mix` and `final` expanded in place).
fn hash_uint4(kx: u32, ky: u32, kz: u32, kw: u32) -> u32 {
    var a = 0xdeadbeefu + (4u << 2u) + 13u;
    var b = a;
    var c = a;

    a += kx;
    b += ky;
    c += kz;
    a -= c; a ^= (c << 4u) | (c >> 28u); c += b;
    b -= a; b ^= (a << 6u) | (a >> 26u); a += c;
    c -= b; c ^= (b << 8u) | (b >> 24u); b += a;
    a -= c; a ^= (c << 16u) | (c >> 16u); c += b;
    b -= a; b ^= (a << 19u) | (a >> 13u); a += c;
    c -= b; c ^= (b << 4u) | (b >> 28u); b += a;

    a += kw;
    c ^= b; c -= (b << 14u) | (b >> 18u);
    a ^= c; a -= (c << 11u) | (c >> 21u);
    b ^= a; b -= (a << 25u) | (a >> 7u);
    c ^= b; c -= (b << 16u) | (b >> 16u);
    a ^= c; a -= (c << 4u) | (c >> 28u);
    b ^= a; b -= (a << 14u) | (a >> 18u);
    c ^= b; c -= (b << 24u) | (b >> 8u);
    return c;
}

// gpu_shader_common_hash.glsl: hash_uint3_to_float.
fn hash_uint3_to_float(kx: u32, ky: u32, kz: u32) -> f32 {
    return f32(hash_uint3(kx, ky, kz)) / f32(0xFFFFFFFFu);
}

// gpu_shader_common_hash.glsl: hash_uint4_to_float.
fn hash_uint4_to_float(kx: u32, ky: u32, kz: u32, kw: u32) -> f32 {
    return f32(hash_uint4(kx, ky, kz, kw)) / f32(0xFFFFFFFFu);
}

// gpu_shader_common_hash.glsl: hash_vec3_to_float.
fn hash_vec3_to_float(k: vec3<f32>) -> f32 {
    return hash_uint3_to_float(bitcast<u32>(k.x), bitcast<u32>(k.y), bitcast<u32>(k.z));
}

// gpu_shader_common_hash.glsl: hash_vec4_to_float.
fn hash_vec4_to_float(k: vec4<f32>) -> f32 {
    return hash_uint4_to_float(bitcast<u32>(k.x), bitcast<u32>(k.y), bitcast<u32>(k.z),
                               bitcast<u32>(k.w));
}

// gpu_shader_common_hash.glsl: hash_vec3_to_vec3.
fn hash_vec3_to_vec3(k: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(hash_vec3_to_float(k),
                     hash_vec4_to_float(vec4<f32>(k, 1.0)),
                     hash_vec4_to_float(vec4<f32>(k, 2.0)));
}

// gpu_shader_math_vector_safe_lib.glsl: safe_divide (float4, float).
fn safe_divide_4(a: vec4<f32>, b: f32) -> vec4<f32> {
    if (b != 0.0) {
        return a / b;
    }
    return vec4<f32>(0.0);
}

// source/blender/gpu/shaders/material/gpu_shader_material_voronoi.glsl: VoronoiParams.
struct VoronoiParams {
    scale: f32,
    detail: f32,
    roughness: f32,
    lacunarity: f32,
    smoothness: f32,
    exponent: f32,
    randomness: f32,
    max_distance: f32,
    normalize: bool,
    feature: i32,
    metric: i32,
}

// gpu_shader_material_voronoi.glsl: VoronoiOutput.
struct VoronoiOutput {
    Distance: f32,
    Color: vec3<f32>,
    Position: vec4<f32>,
}

// gpu_shader_material_voronoi.glsl: voronoi_distance (float3, float3, VoronoiParams).
fn voronoi_distance_3d(a: vec3<f32>, b: vec3<f32>, params: VoronoiParams) -> f32 {
    if (params.metric == SHD_VORONOI_EUCLIDEAN) {
        return distance(a, b);
    } else if (params.metric == SHD_VORONOI_MANHATTAN) {
        return abs(a.x - b.x) + abs(a.y - b.y) + abs(a.z - b.z);
    } else if (params.metric == SHD_VORONOI_CHEBYCHEV) {
        return max(abs(a.x - b.x), max(abs(a.y - b.y), abs(a.z - b.z)));
    } else if (params.metric == SHD_VORONOI_MINKOWSKI) {
        return pow(pow(abs(a.x - b.x), params.exponent) + pow(abs(a.y - b.y), params.exponent) +
                       pow(abs(a.z - b.z), params.exponent),
                   1.0 / params.exponent);
    } else {
        return 0.0;
    }
}

// gpu_shader_material_voronoi.glsl: voronoi_position (float3).
fn voronoi_position_3d(coord: vec3<f32>) -> vec4<f32> {
    return vec4<f32>(coord.x, coord.y, coord.z, 0.0);
}

// gpu_shader_material_voronoi.glsl: voronoi_f1 (VoronoiParams, float3).
fn voronoi_f1_3d(params: VoronoiParams, coord: vec3<f32>) -> VoronoiOutput {
    let cellPosition = floor(coord);
    let localPosition = coord - cellPosition;

    var minDistance = FLT_MAX;
    var targetOffset = vec3<f32>(0.0);
    var targetPosition = vec3<f32>(0.0);
    for (var k = -1; k <= 1; k++) {
        for (var j = -1; j <= 1; j++) {
            for (var i = -1; i <= 1; i++) {
                let cellOffset = vec3<f32>(f32(i), f32(j), f32(k));
                let pointPosition = cellOffset +
                    hash_vec3_to_vec3(cellPosition + cellOffset) * params.randomness;
                let distanceToPoint = voronoi_distance_3d(pointPosition, localPosition, params);
                if (distanceToPoint < minDistance) {
                    targetOffset = cellOffset;
                    minDistance = distanceToPoint;
                    targetPosition = pointPosition;
                }
            }
        }
    }

    var octave: VoronoiOutput;
    octave.Distance = minDistance;
    octave.Color = hash_vec3_to_vec3(cellPosition + targetOffset);
    octave.Position = voronoi_position_3d(targetPosition + cellPosition);
    return octave;
}

// gpu_shader_material_voronoi.glsl: voronoi_smooth_f1 (VoronoiParams, float3).
fn voronoi_smooth_f1_3d(params: VoronoiParams, coord: vec3<f32>) -> VoronoiOutput {
    let cellPosition = floor(coord);
    let localPosition = coord - cellPosition;

    var smoothDistance = 0.0;
    var smoothColor = vec3<f32>(0.0);
    var smoothPosition = vec3<f32>(0.0);
    var h = -1.0;
    for (var k = -2; k <= 2; k++) {
        for (var j = -2; j <= 2; j++) {
            for (var i = -2; i <= 2; i++) {
                let cellOffset = vec3<f32>(f32(i), f32(j), f32(k));
                let pointPosition = cellOffset +
                    hash_vec3_to_vec3(cellPosition + cellOffset) * params.randomness;
                let distanceToPoint = voronoi_distance_3d(pointPosition, localPosition, params);
                if (h == -1.0) {
                    h = 1.0;
                } else {
                    h = smoothstep(0.0, 1.0,
                                   0.5 + 0.5 * (smoothDistance - distanceToPoint) / params.smoothness);
                }
                var correctionFactor = params.smoothness * h * (1.0 - h);
                smoothDistance = mix(smoothDistance, distanceToPoint, h) - correctionFactor;
                correctionFactor /= 1.0 + 3.0 * params.smoothness;
                let cellColor = hash_vec3_to_vec3(cellPosition + cellOffset);
                smoothColor = mix(smoothColor, cellColor, vec3<f32>(h)) - correctionFactor;
                smoothPosition = mix(smoothPosition, pointPosition, vec3<f32>(h)) - correctionFactor;
            }
        }
    }

    var octave: VoronoiOutput;
    octave.Distance = smoothDistance;
    octave.Color = smoothColor;
    octave.Position = voronoi_position_3d(cellPosition + smoothPosition);
    return octave;
}

// gpu_shader_material_voronoi.glsl: voronoi_f2 (VoronoiParams, float3).
fn voronoi_f2_3d(params: VoronoiParams, coord: vec3<f32>) -> VoronoiOutput {
    let cellPosition = floor(coord);
    let localPosition = coord - cellPosition;

    var distanceF1 = FLT_MAX;
    var distanceF2 = FLT_MAX;
    var offsetF1 = vec3<f32>(0.0);
    var positionF1 = vec3<f32>(0.0);
    var offsetF2 = vec3<f32>(0.0);
    var positionF2 = vec3<f32>(0.0);
    for (var k = -1; k <= 1; k++) {
        for (var j = -1; j <= 1; j++) {
            for (var i = -1; i <= 1; i++) {
                let cellOffset = vec3<f32>(f32(i), f32(j), f32(k));
                let pointPosition = cellOffset +
                    hash_vec3_to_vec3(cellPosition + cellOffset) * params.randomness;
                let distanceToPoint = voronoi_distance_3d(pointPosition, localPosition, params);
                if (distanceToPoint < distanceF1) {
                    distanceF2 = distanceF1;
                    distanceF1 = distanceToPoint;
                    offsetF2 = offsetF1;
                    offsetF1 = cellOffset;
                    positionF2 = positionF1;
                    positionF1 = pointPosition;
                } else if (distanceToPoint < distanceF2) {
                    distanceF2 = distanceToPoint;
                    offsetF2 = cellOffset;
                    positionF2 = pointPosition;
                }
            }
        }
    }

    var octave: VoronoiOutput;
    octave.Distance = distanceF2;
    octave.Color = hash_vec3_to_vec3(cellPosition + offsetF2);
    octave.Position = voronoi_position_3d(positionF2 + cellPosition);
    return octave;
}

// source/blender/gpu/shaders/material/gpu_shader_material_fractal_voronoi.glsl:
// fractal_voronoi_x_fx (VoronoiParams, float3).
fn fractal_voronoi_x_fx_3d(params: VoronoiParams, coord: vec3<f32>) -> VoronoiOutput {
    var amplitude = 1.0;
    var max_amplitude = 0.0;
    var scale = 1.0;

    var Output: VoronoiOutput;
    Output.Distance = 0.0;
    Output.Color = vec3<f32>(0.0, 0.0, 0.0);
    Output.Position = vec4<f32>(0.0, 0.0, 0.0, 0.0);
    let zero_input = params.detail == 0.0 || params.roughness == 0.0;

    for (var i = 0; f32(i) <= ceil(params.detail); i++) {
        var octave: VoronoiOutput;
        if (params.feature == SHD_VORONOI_F2) {
            octave = voronoi_f2_3d(params, coord * scale);
        } else if (params.feature == SHD_VORONOI_SMOOTH_F1 && params.smoothness != 0.0) {
            octave = voronoi_smooth_f1_3d(params, coord * scale);
        } else {
            octave = voronoi_f1_3d(params, coord * scale);
        }

        if (zero_input) {
            max_amplitude = 1.0;
            Output = octave;
            break;
        } else if (f32(i) <= params.detail) {
            max_amplitude += amplitude;
            Output.Distance += octave.Distance * amplitude;
            Output.Color += octave.Color * amplitude;
            Output.Position = mix(Output.Position, octave.Position / scale, vec4<f32>(amplitude));
            scale *= params.lacunarity;
            amplitude *= params.roughness;
        } else {
            let remainder = params.detail - floor(params.detail);
            if (remainder != 0.0) {
                max_amplitude = mix(max_amplitude, max_amplitude + amplitude, remainder);
                Output.Distance = mix(Output.Distance, Output.Distance + octave.Distance * amplitude,
                                      remainder);
                Output.Color = mix(Output.Color, Output.Color + octave.Color * amplitude,
                                   vec3<f32>(remainder));
                Output.Position = mix(Output.Position,
                                      mix(Output.Position, octave.Position / scale,
                                          vec4<f32>(amplitude)),
                                      vec4<f32>(remainder));
            }
        }
    }

    if (params.normalize) {
        Output.Distance /= max_amplitude * params.max_distance;
        Output.Color /= max_amplitude;
    }

    Output.Position = safe_divide_4(Output.Position, params.scale);

    return Output;
}

// source/blender/gpu/shaders/material/gpu_shader_material_tex_voronoi.glsl:
// node_tex_voronoi_f1_3d (INITIALIZE_VORONOIPARAMS(SHD_VORONOI_F1) expanded).
fn node_tex_voronoi_f1_3d(coord0: vec3<f32>, w: f32, scale: f32, detail: f32, roughness: f32,
                          lacunarity: f32, smoothness: f32, exponent: f32, randomness: f32,
                          metric: f32, normalize: f32, outDistance: ptr<function, f32>,
                          outColor: ptr<function, vec4<f32>>,
                          outPosition: ptr<function, vec3<f32>>, outW: ptr<function, f32>,
                          outRadius: ptr<function, f32>) {
    var params: VoronoiParams;

    params.feature = SHD_VORONOI_F1;
    params.metric = i32(metric);
    params.scale = scale;
    params.detail = clamp(detail, 0.0, 15.0);
    params.roughness = clamp(roughness, 0.0, 1.0);
    params.lacunarity = lacunarity;
    params.smoothness = clamp(smoothness / 2.0, 0.0, 0.5);
    params.exponent = exponent;
    params.randomness = clamp(randomness, 0.0, 1.0);
    params.max_distance = 0.0;
    params.normalize = normalize != 0.0;

    let coord = coord0 * scale;

    params.max_distance = voronoi_distance_3d(vec3<f32>(0.0),
                                              vec3<f32>(0.5 + 0.5 * params.randomness), params);
    let Output = fractal_voronoi_x_fx_3d(params, coord);
    *outDistance = Output.Distance;
    *outColor = vec4<f32>(Output.Color, 1.0);
    *outPosition = Output.Position.xyz;
}

// The material: what EEVEE's generated code does for a Voronoi Texture fed the position, with
// its unlinked sockets in the material UBO.
struct NodeUniforms {
    scale: f32,
    detail: f32,
    roughness: f32,
    lacunarity: f32,
    smoothness: f32,
    exponent: f32,
    randomness: f32,
    w: f32,
}

@group(0) @binding(0) var<uniform> node_uniforms: NodeUniforms;

struct TsOutputs {
    distance: f32,
    color: vec3<f32>,
    position: vec3<f32>,
}

fn ts_material(position: vec3<f32>) -> TsOutputs {
    var dist: f32;
    var color: vec4<f32>;
    var pos: vec3<f32>;
    var w: f32;
    var radius: f32;
    node_tex_voronoi_f1_3d(position, node_uniforms.w, node_uniforms.scale, node_uniforms.detail,
                           node_uniforms.roughness, node_uniforms.lacunarity,
                           node_uniforms.smoothness, node_uniforms.exponent,
                           node_uniforms.randomness, 0.0, 0.0, &dist, &color, &pos, &w,
                           &radius);
    return TsOutputs(dist, color.xyz, pos);
}
