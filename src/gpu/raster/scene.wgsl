// The scene side of the GPU rasteriser: camera, environment, shadow casters, built-in
// shading. Every function is a line-by-line port of the CPU function named in its comment
// (src/scene/), so that the GPU render agrees with the CPU reference.

struct MgrFrame {
    origin: vec3<f32>,
    near: f32,
    right: vec3<f32>,
    tan_half_y: f32,
    up: vec3<f32>,
    aspect: f32,
    forward: vec3<f32>,
    width: f32,
    // The eye built-in shading sees from (the mirrored origin in a reflection pass).
    eye: vec3<f32>,
    height: f32,
    sun: vec3<f32>,
    // cos(sun_radius_deg), computed on the CPU as Sky::radiance does.
    sun_cos: f32,
    zenith: vec3<f32>,
    sun_intensity: f32,
    horizon: vec3<f32>,
    halo: f32,
    ground: vec3<f32>,
    // 1 in a pass mirrored about y = 0.
    mirror: f32,
    sun_color: vec3<f32>,
    // 1 for the water scene.
    water: f32,
    // Keep n·p + d >= 0 when counts.w is 1.
    clip: vec4<f32>,
    ambient: array<vec4<f32>, 6>,
    // Lights, casters of built-in shading, casters of the material's light (the first
    // ones), clip on.
    counts: vec4<u32>,
    // depth_min, depth_max, slope (clamped), size_z (≥ MIN_POSITIVE).
    seabed: vec4<f32>,
    // The seed phase of each bump, rem_euclid(TAU) on the CPU.
    seabed_phase: vec4<f32>,
    // The bumps (amplitude, k_x, k_z, phase) of src/scene/kind.rs BUMPS.
    bumps: array<vec4<f32>, 4>,
    // The tile of the frame this pass draws (packed.rs Viewport): clip-space scale and
    // offset (sx, tx, sy, ty) taking the whole frame's clip x and y to the tile's.
    tile_clip: vec4<f32>,
    // The frame position of the tile's fragment (0, 0) minus (0.5, 0.5) plus the sample's
    // sub-pixel offset in a jittered pass (xy), and the tile's first pixel (zw).
    tile_offset: vec4<f32>,
    // The environment: x 0 the sky, 1 the default sky scaled by w (an image environment
    // without its image), 2 the image (scene texture slots.x) scaled by w, seen turned by
    // the angle whose cosine and sine are y and z.
    env: vec4<f32>,
    // Scene texture slots: x the environment image, y the bubble backdrop's first map.
    slots: vec4<u32>,
    // The material surface's texture space (Scene::texture_space): centre and half size.
    tex_center: vec4<f32>,
    tex_half: vec4<f32>,
}

// Prepared light (src/scene/shade.rs Prepared): kind.x 0 directional, 1 point;
// a.xyz the unit direction or the position; b.xyz the radiance scale.
struct MgrLight {
    kind: vec4<u32>,
    a: vec4<f32>,
    b: vec4<f32>,
}

// Shape (src/scene/objects.rs): kind.x 0 sphere (a = centre, radius), 1 box (a.xyz min,
// b.xyz max), 2 cylinder (a = x, z, radius, y0; b.x = y1).
struct MgrCaster {
    kind: vec4<u32>,
    a: vec4<f32>,
    b: vec4<f32>,
}

@group(1) @binding(0) var<uniform> mgr_frame: MgrFrame;
@group(1) @binding(1) var<storage, read> mgr_lights: array<MgrLight>;
@group(1) @binding(2) var<storage, read> mgr_casters: array<MgrCaster>;
// The MGR_HAS_* constants (packed.rs SceneFeatures::wgsl) are prepended with the sampler:
// each leaves out the code of a feature the scene does not have.
// Bindings 3–5: the scene's textures (the bubble backdrop's maps, the environment image),
// sampled by mgs_sample_texture (texture.rs SAMPLE_WGSL, prefixed mgs_), prepended by
// mod.rs scene_source.

// CameraFrame::to_view, then the projection of CameraFrame::project_view as a clip-space
// position whose depth is near / w (1/w up to the scale: larger is nearer, as the CPU
// z-buffer on 1/w), so that z / w in [0, 1] clips at the near plane.
fn mgr_clip_position(p: vec3<f32>) -> vec4<f32> {
    let f = mgr_frame;
    let d = p - f.origin;
    let v = vec3<f32>(dot(d, f.right), dot(d, f.up), -dot(d, f.forward));
    let w = -v.z;
    let x = v.x / (f.tan_half_y * f.aspect);
    let y = v.y / f.tan_half_y;
    // The tile: an affine map of the frame's normalised coordinates, exact (scale 1,
    // offset 0) for a whole frame.
    let t = f.tile_clip;
    return vec4<f32>(x * t.x + w * t.y, y * t.z + w * t.w, f.near, w);
}

// The frame's pixel coordinates of a fragment position in the tile (and, in a jittered
// pass, at the sample's offset).
fn mgr_frame_xy(frag: vec2<f32>) -> vec2<f32> {
    return frag + mgr_frame.tile_offset.xy;
}

// The frame's `screen_uv` at a fragment (gbuffer.rs: ((x + jx) / width, (y + jy) / height)).
fn mgr_screen_uv(frag: vec2<f32>) -> vec2<f32> {
    let xy = mgr_frame_xy(frag);
    return vec2<f32>(xy.x / mgr_frame.width, xy.y / mgr_frame.height);
}

// mgr_ray at a fragment position of the tile.
fn mgr_ray(frag: vec2<f32>) -> vec3<f32> {
    return mgr_ray_frame(mgr_frame_xy(frag));
}

// CameraFrame::ray_direction through the frame's pixel coordinates xy (top-left origin),
// unnormalised (its forward component is 1).
fn mgr_ray_frame(xy: vec2<f32>) -> vec3<f32> {
    let f = mgr_frame;
    let ndc_x = 2.0 * xy.x / f.width - 1.0;
    let ndc_y = 1.0 - 2.0 * xy.y / f.height;
    return f.forward + f.right * (ndc_x * f.tan_half_y * f.aspect) + f.up * (ndc_y * f.tan_half_y);
}

// CameraFrame::ray_direction at a fragment position of the tile.
fn mgr_ray_direction(frag: vec2<f32>) -> vec3<f32> {
    return normalize(mgr_ray(frag));
}

// The perspective-correct barycentrics (b1, b2) of the triangle (a, b, c), as drawn, at
// the sample at fragment position xy of the tile, clamped to [0, 1] as the CPU rasteriser's
// (raster.rs rasterize_rows): where the eye ray through the sample meets the triangle's
// plane, a + b1 (b − a) + b2 (c − a) (Möller and Trumbore, "Fast, minimum storage
// ray-triangle intersection", JGT 1997). Computed from the whole triangle, so clipping does
// not change it.
fn mgr_barycentrics(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>, xy: vec2<f32>) -> vec2<f32> {
    let d = mgr_ray(xy);
    let e1 = b - a;
    let e2 = c - a;
    let pv = cross(d, e2);
    let inv = 1.0 / dot(e1, pv);
    let tv = mgr_frame.origin - a;
    let u = dot(tv, pv) * inv;
    let v = dot(d, cross(tv, e1)) * inv;
    return clamp(vec2<f32>(u, v), vec2<f32>(0.0), vec2<f32>(1.0));
}

// environment.rs smoothstep.
fn mgr_smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// glam's Vec3::lerp: self * (1 - s) + rhs * s.
fn mgr_lerp(a: vec3<f32>, b: vec3<f32>, s: f32) -> vec3<f32> {
    return a * (1.0 - s) + b * s;
}

// Environment::radiance: the sky (its sun disc and halo with with_sun), or an image
// environment turned into the image's frame and looked up as render/mod.rs
// environment_lookup does (equirect_uv, bilinear, repeat, level 0).
fn mgr_sky(d: vec3<f32>, with_sun: bool) -> vec3<f32> {
    let e = mgr_frame.env;
    if (MGR_HAS_ENV_IMAGE && e.x == 2.0) {
        // image_or_default: rotation about +y by −rotation_deg.
        let r = vec3<f32>(e.y * d.x + e.z * d.z, d.y, -e.z * d.x + e.y * d.z);
        let uv = vec2<f32>(0.5 + atan2(r.x, -r.z) / 6.2831855, acos(clamp(r.y, -1.0, 1.0)) / 3.1415927);
        return e.w * mgs_sample_texture(mgr_frame.slots.x, uv, 0.0, 0u, 1u).xyz;
    }
    let c = mgr_sky_gradient(d, with_sun);
    if (e.x == 1.0) {
        return e.w * c;
    }
    return c;
}

// Sky::radiance(d, sun, with_sun).
fn mgr_sky_gradient(d: vec3<f32>, with_sun: bool) -> vec3<f32> {
    let f = mgr_frame;
    if (d.y < 0.0) {
        let t = mgr_smoothstep(0.0, 0.1, -d.y);
        return mgr_lerp(f.horizon, f.ground, t);
    }
    var c = mgr_lerp(f.horizon, f.zenith, sqrt(d.y));
    if (with_sun) {
        let cs = dot(d, f.sun);
        if (cs >= f.sun_cos) {
            c += f.sun_color * f.sun_intensity;
        }
        // powi(64) by six squarings, as LLVM expands it.
        let x1 = max(cs, 0.0);
        let x2 = x1 * x1;
        let x4 = x2 * x2;
        let x8 = x4 * x4;
        let x16 = x8 * x8;
        let x32 = x16 * x16;
        let x64 = x32 * x32;
        c += f.sun_color * (f.halo * x64);
    }
    return c;
}

// AmbientCube::eval.
fn mgr_ambient(n: vec3<f32>) -> vec3<f32> {
    let f = mgr_frame;
    let sq = n * n;
    let fx = select(f.ambient[1].xyz, f.ambient[0].xyz, n.x >= 0.0);
    let fy = select(f.ambient[3].xyz, f.ambient[2].xyz, n.y >= 0.0);
    let fz = select(f.ambient[5].xyz, f.ambient[4].xyz, n.z >= 0.0);
    return sq.x * fx + sq.y * fy + sq.z * fz;
}

// Shape::occludes: whether the ray o + t d meets caster k for some t in (0, t_max).
fn mgr_occludes(k: u32, o: vec3<f32>, d: vec3<f32>, t_max: f32) -> bool {
    let s = mgr_casters[k];
    if (MGR_HAS_SPHERES && s.kind.x == 0u) {
        let oc = o - s.a.xyz;
        let b = dot(oc, d);
        let c = dot(oc, oc) - s.a.w * s.a.w;
        if (c > 0.0 && b > 0.0) {
            return false;
        }
        let disc = b * b - c;
        if (disc < 0.0) {
            return false;
        }
        let q = sqrt(disc);
        let t0 = -b - q;
        let t1 = -b + q;
        return (t0 > 0.0 && t0 < t_max) || (t1 > 0.0 && t1 < t_max);
    }
    if (MGR_HAS_BOXES && s.kind.x == 1u) {
        let inv = 1.0 / d;
        let t0 = (s.a.xyz - o) * inv;
        let t1 = (s.b.xyz - o) * inv;
        let lo = min(t0, t1);
        let hi = max(t0, t1);
        let near = max(lo.x, max(lo.y, lo.z));
        let far = min(hi.x, min(hi.y, hi.z));
        return far >= max(near, 0.0) && near < t_max && far > 0.0;
    }
    if (!MGR_HAS_CYLINDERS) {
        return false;
    }
    let r = s.a.z;
    let y0 = s.a.w;
    let y1 = s.b.x;
    let ox = o.x - s.a.x;
    let oz = o.z - s.a.y;
    let a = d.x * d.x + d.z * d.z;
    if (a > 1e-12) {
        let b = ox * d.x + oz * d.z;
        let c = ox * ox + oz * oz - r * r;
        let disc = b * b - a * c;
        if (disc >= 0.0) {
            let q = sqrt(disc);
            for (var i = 0; i < 2; i++) {
                let t = select((-b + q) / a, (-b - q) / a, i == 0);
                let y = o.y + t * d.y;
                if (t > 0.0 && t < t_max && y >= y0 && y <= y1) {
                    return true;
                }
            }
        }
    }
    if (abs(d.y) > 1e-12) {
        for (var i = 0; i < 2; i++) {
            let yc = select(y1, y0, i == 0);
            let t = (yc - o.y) / d.y;
            let px = ox + t * d.x;
            let pz = oz + t * d.z;
            if (t > 0.0 && t < t_max && px * px + pz * pz <= r * r) {
                return true;
            }
        }
    }
    return false;
}

// shade.rs lit: whether the ray from p (moved off the surface along n by SHADOW_BIAS)
// towards l reaches the light at dist, past the first `count` casters but `skip`.
fn mgr_lit(count: u32, skip: u32, p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, dist: f32) -> bool {
    let o = p + n * 1e-3;
    for (var k = 0u; k < count; k++) {
        if (k != skip && mgr_occludes(k, o, l, dist)) {
            return false;
        }
    }
    return true;
}

struct MgrIncident {
    l: vec3<f32>,
    radiance: vec3<f32>,
    dist: f32,
}

// Prepared::incident: direction, radiance scale and distance of light i at p.
fn mgr_incident(i: u32, p: vec3<f32>) -> MgrIncident {
    let light = mgr_lights[i];
    if (light.kind.x == 0u) {
        // f32::INFINITY, built at run time: a constant expression would overflow, and Tint
        // rejects even the bitcast of a constant (naga folds it), so the bits are added to
        // the light's kind, which is 0 here.
        let inf = bitcast<f32>(0x7f800000u + light.kind.x);
        return MgrIncident(light.a.xyz, light.b.xyz, inf);
    }
    let to = light.a.xyz - p;
    let d2 = dot(to, to);
    let dist = sqrt(d2);
    var dir = vec3<f32>(0.0, 1.0, 0.0);
    if (dist > 0.0) {
        dir = to / dist;
    }
    let d2c = max(d2, 1e-6);
    return MgrIncident(dir, light.b.xyz / d2c, dist);
}

// columns.rs light_at: the material's light i at p, zeroed where one of the scene's own
// casters (not the material's) stands between.
fn mgr_light_at(i: u32, p: vec3<f32>) -> MgrIncident {
    let inc = mgr_incident(i, p);
    let count = mgr_frame.counts.z;
    if (count == 0u || mgr_lit(count, 0xffffffffu, p, vec3<f32>(0.0), inc.l, inc.dist)) {
        return inc;
    }
    return MgrIncident(inc.l, vec3<f32>(0.0), inc.dist);
}

// WaterSetup::seabed_depth (BUMPS and SEED_PHASE of src/scene/kind.rs).
fn mgr_seabed_depth(x: f32, z: f32) -> f32 {
    let s = mgr_frame.seabed;
    var ph = array<f32, 4>(mgr_frame.seabed_phase.x, mgr_frame.seabed_phase.y, mgr_frame.seabed_phase.z, mgr_frame.seabed_phase.w);
    var sum = 0.0;
    var norm = 0.0;
    for (var i = 0; i < 4; i++) {
        let k = mgr_frame.bumps[i];
        sum += k.x * sin(k.y * x + k.z * z + k.w + ph[i]);
        norm += k.x;
    }
    let b = sum / norm;
    let size_z = s.w;
    let r = mgr_smoothstep(0.0, 1.0, (0.5 * size_z - z) / size_z);
    let slope = s.z;
    let t = slope * r + (1.0 - slope) * 0.5 * (1.0 + b);
    return s.x + (s.y - s.x) * t;
}

// Scene::water_depth: max(0, p.y + seabed_depth) in the water scene, 0 on the ball.
fn mgr_water_depth(p: vec3<f32>) -> f32 {
    if (!MGR_HAS_WATER || mgr_frame.water == 0.0) {
        return 0.0;
    }
    return max(p.y + mgr_seabed_depth(p.x, p.z), 0.0);
}

// Whether f32 x is finite, from its bits (no fast-math folding).
fn mgr_finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

// gbuffer.rs surface_derivatives (there in f64): the points of the plane of the triangle
// (p0, p1, p2), relative to p0, under the centres of the pixel's 2 × 2 quad along its row
// (q[0], q[1]) and its column (q[2], q[3]) at pixel `pixel`; `ok` false where a ray is
// parallel to the plane or the triangle is degenerate.
struct MgrQuadPoints {
    q: array<vec3<f32>, 4>,
    ok: bool,
}

fn mgr_quad_points(p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, pixel: vec2<u32>) -> MgrQuadPoints {
    let f = mgr_frame;
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let n = cross(e1, e2);
    let g12 = dot(e1, e2);
    let det = dot(e1, e1) * dot(e2, e2) - g12 * g12;
    // The frame's pixel of the tile's `pixel` (tiles start on even pixels: the quads stay).
    let c = pixel + vec2<u32>(f.tile_offset.zw);
    let x0 = f32(c.x & ~1u) + 0.5;
    let y0 = f32(c.y & ~1u) + 0.5;
    let xc = f32(c.x) + 0.5;
    let yc = f32(c.y) + 0.5;
    let at = array<vec2<f32>, 4>(vec2<f32>(x0, yc), vec2<f32>(x0 + 1.0, yc), vec2<f32>(xc, y0), vec2<f32>(xc, y0 + 1.0));
    var r: MgrQuadPoints;
    r.ok = det != 0.0;
    for (var k = 0; k < 4; k++) {
        let d = mgr_ray_frame(at[k]);
        let nd = dot(n, d);
        r.ok = r.ok && nd != 0.0;
        r.q[k] = f.origin + d * (dot(n, p0 - f.origin) / nd) - p0;
    }
    return r;
}

// The position's fine differences across the quad (the bump node's offsets): zero where
// mgr_quad_points gives none.
struct MgrPositionDerivatives {
    dx: vec3<f32>,
    dy: vec3<f32>,
}

fn mgr_position_derivatives(p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, pixel: vec2<u32>) -> MgrPositionDerivatives {
    let m = mgr_quad_points(p0, p1, p2, pixel);
    var r: MgrPositionDerivatives;
    if (m.ok) {
        r.dx = m.q[1] - m.q[0];
        r.dy = m.q[3] - m.q[2];
    }
    return r;
}

// The uv's fine differences across the quad, with uvs (u0, u1, u2) at the corners, as
// dpdxFine/dpdyFine give them; (dx, dy) packed in a vec4, zero where mgr_quad_points gives
// none.
fn mgr_uv_derivatives(
    p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>,
    u0: vec2<f32>, u1: vec2<f32>, u2: vec2<f32>,
    pixel: vec2<u32>,
) -> vec4<f32> {
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let du1 = u1 - u0;
    let du2 = u2 - u0;
    let g11 = dot(e1, e1);
    let g12 = dot(e1, e2);
    let g22 = dot(e2, e2);
    let det = g11 * g22 - g12 * g12;
    let m = mgr_quad_points(p0, p1, p2, pixel);
    var uv = array<vec2<f32>, 4>();
    for (var k = 0; k < 4; k++) {
        let q = m.q[k];
        let r1 = dot(e1, q);
        let r2 = dot(e2, q);
        let a = (g22 * r1 - g12 * r2) / det;
        let b = (g11 * r2 - g12 * r1) / det;
        uv[k] = du1 * a + du2 * b;
    }
    let ok = m.ok;
    if (!ok) {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(uv[1] - uv[0], uv[3] - uv[2]);
}
