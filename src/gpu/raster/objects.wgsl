// The built-in surfaces (backdrop, seabed, skirts, objects) and the environment behind
// them: one pass of src/scene/shade.rs shade_frame. Needs scene.wgsl.

// A built-in surface's albedo and shadow skip (src/scene/objects.rs Object and Albedo):
// kind.x 0 constant (c0), 2 unlit (the bubble backdrop, backdrop.wgsl), 1 checker (u.xyz, v0 = u.w, v.xyz, size = v.w, colours c0 and
// c1); kind.y its own caster, skipped (0xffffffff: none); kind.z its first triangle.
struct MgrObject {
    kind: vec4<u32>,
    u: vec4<f32>,
    v: vec4<f32>,
    c0: vec4<f32>,
    c1: vec4<f32>,
}

// Vertex k: position (xyz, 1); normal (xyz, unused); the triangles (three vertex indices
// each; kind.z of an object is its first).
@group(0) @binding(0) var<storage, read> mgr_positions: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read> mgr_normals: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> mgr_objects: array<MgrObject>;
@group(0) @binding(3) var<storage, read> mgr_indices: array<u32>;
// Where the vertices are drawn: mgr_positions, or in the Snell refraction pass their
// apparent positions (snell.rs apparent_mesh); shading keeps mgr_positions.
@group(0) @binding(4) var<storage, read> mgr_drawn: array<vec4<f32>>;

// The surface's varyings, interpolated perspective-correct at each sample: where
// the surface is (mgr_positions, shaded) and where it is drawn (mgr_drawn, for the clip
// plane), the normal, and the first vertex's normal for normalize_or.
struct MgrSurface {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) object: u32,
    @location(1) @interpolate(perspective, sample) p: vec3<f32>,
    @location(2) @interpolate(perspective, sample) n: vec3<f32>,
    @location(3) @interpolate(perspective, sample) drawn: vec3<f32>,
    @location(4) @interpolate(flat) n0: vec3<f32>,
}

// One instance per object: instance_index is the object.
@vertex
fn mgr_object_vs(@builtin(vertex_index) k: u32, @builtin(instance_index) object: u32) -> MgrSurface {
    let d = mgr_drawn[k].xyz;
    var q = d;
    // DrawItem mirror_y: the geometry drawn mirrored about y = 0, shaded where it is.
    if (mgr_frame.mirror != 0.0) {
        q.y = -q.y;
    }
    let n = mgr_normals[k].xyz;
    return MgrSurface(mgr_clip_position(q), object, mgr_positions[k].xyz, n, d, n);
}

// Albedo::at.
fn mgr_albedo(o: MgrObject, p: vec3<f32>) -> vec3<f32> {
    if (o.kind.x == 0u) {
        return o.c0.xyz;
    }
    let a = i32(floor(dot(p, o.u.xyz) / o.v.w));
    let b = i32(floor((dot(p, o.v.xyz) - o.u.w) / o.v.w));
    // (a + b).rem_euclid(2) in two's complement.
    return select(o.c0.xyz, o.c1.xyz, ((a + b) & 1) == 1);
}

// Shading::surface: two-sided Lambert under the lights with hard shadows, plus ambient.
fn mgr_surface(o: MgrObject, p: vec3<f32>, n0: vec3<f32>, eye: vec3<f32>) -> vec3<f32> {
    if (MGR_HAS_BACKDROP && o.kind.x == 2u) {
        return mgr_backdrop_radiance(p);
    }
    let albedo = mgr_albedo(o, p);
    var n = n0;
    if (dot(n, eye - p) < 0.0) {
        n = -n;
    }
    var e = mgr_ambient(n);
    for (var i = 0u; i < mgr_frame.counts.x; i++) {
        let inc = mgr_incident(i, p);
        let cs = dot(n, inc.l);
        if (cs > 0.0 && mgr_lit(mgr_frame.counts.y, o.kind.y, p, n, inc.l, inc.dist)) {
            e += inc.radiance * cs;
        }
    }
    return albedo * e;
}

// A built-in surface at 1 sample per pixel: position_normal at the pixel centre (the
// hardware's perspective-correct interpolation of the varyings), then Shading::surface.
@fragment
fn mgr_object_fs(s: MgrSurface) -> @location(0) vec4<f32> {
    let f = mgr_frame;
    let o = mgr_objects[s.object];
    // Clipping the drawn triangle to a world plane (raster.rs DrawItem clip), per sample:
    // the water scene's passes only, so that elsewhere the shader has no `discard` and the
    // depth test runs before it (no shading behind the material's depth pre-pass).
    if (MGR_HAS_WATER && f.counts.w != 0u && dot(f.clip.xyz, s.drawn) + f.clip.w < 0.0) {
        discard;
    }
    // normalize_or(n0).
    var n = s.n;
    let len2 = dot(n, n);
    if (len2 > 0.0) {
        n = n * inverseSqrt(len2);
    } else {
        n = s.n0;
    }
    return vec4<f32>(mgr_surface(o, s.p, n, f.eye), 1.0);
}

// The same under MSAA: position_normal at the CPU's barycentrics, rebuilt from the sample's
// position by mgr_barycentrics, then Shading::surface. Lavapipe's per-sample interpolation
// at 4 samples does not land on the sample positions (measured: checker edges move, RMSE
// 1.6/255 against the CPU on tests/gpu/gpu_render.rs's wobble), so the varyings serve 1 sample
// per pixel only (at the pixel centre: RMSE 0.002/255).
@fragment
fn mgr_object_sample_fs(
    s: MgrSurface,
    @builtin(sample_index) sample: u32,
    @builtin(primitive_index) prim: u32,
) -> @location(0) vec4<f32> {
    let f = mgr_frame;
    let o = mgr_objects[s.object];
    let t = o.kind.z + prim;
    let i0 = mgr_indices[3u * t];
    let i1 = mgr_indices[3u * t + 1u];
    let i2 = mgr_indices[3u * t + 2u];
    let p0 = mgr_positions[i0].xyz;
    let p1 = mgr_positions[i1].xyz;
    let p2 = mgr_positions[i2].xyz;
    var m = vec3<f32>(1.0, 1.0, 1.0);
    if (f.mirror != 0.0) {
        m.y = -1.0;
    }
    let d0 = mgr_drawn[i0].xyz;
    let d1 = mgr_drawn[i1].xyz;
    let d2 = mgr_drawn[i2].xyz;
    let bc = mgr_barycentrics(d0 * m, d1 * m, d2 * m, s.clip.xy);
    let b0 = 1.0 - bc.x - bc.y;
    let p = p0 * b0 + p1 * bc.x + p2 * bc.y;
    // Clipping the drawn triangle to a world plane (raster.rs DrawItem clip), per sample.
    let drawn = d0 * b0 + d1 * bc.x + d2 * bc.y;
    if (MGR_HAS_WATER && f.counts.w != 0u && dot(f.clip.xyz, drawn) + f.clip.w < 0.0) {
        discard;
    }
    let n0 = mgr_normals[i0].xyz;
    var n = n0 * b0 + mgr_normals[i1].xyz * bc.x + mgr_normals[i2].xyz * bc.y;
    // normalize_or(n0).
    let len2 = dot(n, n);
    if (len2 > 0.0) {
        n = n * inverseSqrt(len2);
    } else {
        n = n0;
    }
    return vec4<f32>(mgr_surface(o, p, n, f.eye), f32(sample) * 0.0 + 1.0);
}

// A triangle covering the screen.
@vertex
fn mgr_sky_vs(@builtin(vertex_index) k: u32) -> @builtin(position) vec4<f32> {
    let xy = vec2<f32>(f32((k << 1u) & 2u) * 2.0 - 1.0, f32(k & 2u) * 2.0 - 1.0);
    return vec4<f32>(xy, 0.0, 1.0);
}

// shade_frame where nothing is hit: the environment along the eye ray (mirrored in y in a
// reflection pass).
@fragment
fn mgr_sky_fs(@builtin(position) xy: vec4<f32>, @builtin(sample_index) sample: u32) -> @location(0) vec4<f32> {
    var d = mgr_ray_direction(xy.xy);
    if (mgr_frame.mirror != 0.0) {
        d.y = -d.y;
    }
    return vec4<f32>(mgr_sky(d, true), f32(sample) * 0.0 + 1.0);
}
