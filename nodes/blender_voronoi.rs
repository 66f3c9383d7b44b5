//! Blender's Voronoi Texture node (Blender 4.x), its definition as Blender's sources state it
//! (`intern/cycles/kernel/svm/voronoi.h`), written again here: Worley's cellular noise with
//! one jittered point per unit cell (jitter by the lookup3 hash of the cell, scaled by
//! `randomness`), the features F1, F2, smooth F1 (Quilez's smooth minimum), distance to edge
//! (Quilez's exact cell borders) and n-sphere radius, four metrics, and Blender 4's fractal
//! octaves (detail, roughness, lacunarity, normalize).
//!
//! Every point is a vec4 with the dimension count, as in [`super::blender_noise`]; cells are
//! visited in Blender's order (w outermost, x innermost), which matters for ties and for the
//! smooth minimum's running blend. tests/models/blender_textures.rs holds the node to values
//! Blender 4.2 computed.

use super::blender_noise::{DIMENSIONS, hash_floats, hash_floats3};
use crate::node::{Category, In, NodeType, Out};
use crate::value::Value;
use glam::{Vec3, Vec4};

/// The choices of the `feature` input (Blender's order).
pub const FEATURES: &[&str] = &[
    "f1",
    "f2",
    "smooth_f1",
    "distance_to_edge",
    "n_sphere_radius",
];
/// The choices of the `metric` input (Blender's order and spelling).
pub const METRICS: &[&str] = &["euclidean", "manhattan", "chebychev", "minkowski"];

/// What a Voronoi evaluation needs besides the point.
#[derive(Clone, Copy)]
struct Params {
    dims: usize,
    metric: usize,
    exponent: f32,
    randomness: f32,
    smoothness: f32,
}

/// The distance of `a` and `b` in the metric (1D: |b − a| whatever the metric).
///
/// Source: Blender's `voronoi_distance`.
fn distance(a: Vec4, b: Vec4, p: &Params) -> f32 {
    if p.dims == 1 {
        return (b.x - a.x).abs();
    }
    let d = a - b;
    let n = p.dims;
    match p.metric {
        1 => (0..n).fold(0.0, |s, k| s + d[k].abs()),
        2 => (0..n).fold(0.0f32, |s, k| s.max(d[k].abs())),
        3 => (0..n)
            .fold(0.0, |s, k| s + d[k].abs().powf(p.exponent))
            .powf(1.0 / p.exponent),
        _ => (0..n).fold(0.0, |s, k| s + d[k] * d[k]).sqrt(),
    }
}

/// The jitter of the point in cell `c` (its coordinates as floats), in [0, 1) per used
/// component: Blender's `hash_floatN_to_floatN`.
fn jitter(c: Vec4, dims: usize) -> Vec4 {
    let h = hash_floats;
    match dims {
        1 => Vec4::new(h(&[c.x]), 0.0, 0.0, 0.0),
        2 => Vec4::new(h(&[c.x, c.y]), h(&[c.x, c.y, 1.0]), 0.0, 0.0),
        3 => hash_floats3(&[c.x, c.y, c.z]).extend(0.0),
        _ => Vec4::new(
            h(&[c.x, c.y, c.z, c.w]),
            h(&[c.w, c.x, c.y, c.z]),
            h(&[c.z, c.w, c.x, c.y]),
            h(&[c.y, c.z, c.w, c.x]),
        ),
    }
}

/// The colour of cell `c`: Blender's `hash_floatN_to_float3`.
fn cell_color(c: Vec4, dims: usize) -> Vec3 {
    hash_floats3(&[c.x, c.y, c.z, c.w][..dims])
}

/// The cell offsets within `r` cells, in Blender's order (w outermost, x innermost).
fn offsets(dims: usize, r: i32) -> impl Iterator<Item = Vec4> {
    let span = move |k: usize| if k < dims { -r..=r } else { 0..=0 };
    span(3).flat_map(move |u| {
        span(2).flat_map(move |k| {
            span(1).flat_map(move |j| {
                span(0).map(move |i| Vec4::new(i as f32, j as f32, k as f32, u as f32))
            })
        })
    })
}

/// The point of the cell at offset `o` from `cell`: the offset plus the cell's jitter times
/// the randomness (relative to `cell`).
fn point(p: &Params, cell: Vec4, o: Vec4) -> Vec4 {
    o + jitter(cell + o, p.dims) * p.randomness
}

/// `a + t·(b − a)` (Cycles' `mix`).
fn mix(a: f32, b: f32, t: f32) -> f32 {
    a + t * (b - a)
}

/// One octave: (distance, colour, position).
struct Octave {
    distance: f32,
    color: Vec3,
    position: Vec4,
}

/// F1 (the nearest point) or, with `second`, F2 (the second nearest). Source: Blender's
/// `voronoi_f1` and `voronoi_f2`, one scan (F2's keeps F1's nearest as its first).
fn nearest(p: &Params, coord: Vec4, second: bool) -> Octave {
    let cell = coord.floor();
    let local = coord - cell;
    let (mut d1, mut d2) = (f32::MAX, f32::MAX);
    let (mut o1, mut p1, mut o2, mut p2) = (Vec4::ZERO, Vec4::ZERO, Vec4::ZERO, Vec4::ZERO);
    for o in offsets(p.dims, 1) {
        let point = point(p, cell, o);
        let d = distance(point, local, p);
        if d < d1 {
            d2 = d1;
            d1 = d;
            o2 = o1;
            o1 = o;
            p2 = p1;
            p1 = point;
        } else if d < d2 {
            d2 = d;
            o2 = o;
            p2 = point;
        }
    }
    let (d, o, pos) = if second { (d2, o2, p2) } else { (d1, o1, p1) };
    Octave {
        distance: d,
        color: cell_color(cell + o, p.dims),
        position: pos + cell,
    }
}

/// Smooth F1: the smooth minimum over a 5-cell window. Source: Blender's
/// `voronoi_smooth_f1` (Quilez 2014, "Voronoise"/smooth Voronoi).
fn smooth_f1(p: &Params, coord: Vec4) -> Octave {
    let cell = coord.floor();
    let local = coord - cell;
    let (mut sd, mut sc, mut sp) = (0.0f32, Vec3::ZERO, Vec4::ZERO);
    let mut h = -1.0f32;
    for o in offsets(p.dims, 2) {
        let point = point(p, cell, o);
        let d = distance(point, local, p);
        h = if h == -1.0 {
            1.0
        } else {
            smoothstep(0.5 + 0.5 * (sd - d) / p.smoothness)
        };
        let mut correction = p.smoothness * h * (1.0 - h);
        sd = mix(sd, d, h) - correction;
        correction /= 1.0 + 3.0 * p.smoothness;
        let c = cell_color(cell + o, p.dims);
        sc = sc + h * (c - sc) - Vec3::splat(correction);
        // The position has only the used components (Blender's floatN).
        let on = |k: usize| if p.dims > k { correction } else { 0.0 };
        let used = Vec4::new(on(0), on(1), on(2), on(3));
        sp = sp + h * (point - sp) - used;
    }
    Octave {
        distance: sd,
        color: sc,
        position: cell + sp,
    }
}

/// Cycles' `smoothstep(0, 1, x)`: 0 below 0, 1 from 1, else (3 − 2t)·t².
fn smoothstep(x: f32) -> f32 {
    if x < 0.0 {
        0.0
    } else if x >= 1.0 {
        1.0
    } else {
        (3.0 - 2.0 * x) * (x * x)
    }
}

/// The distance to the nearest cell border. Source: Blender's `voronoi_distance_to_edge`
/// (Quilez, "Voronoi - distances", 2012; 1D by the midpoints of the cell's point and its
/// neighbours').
fn distance_to_edge(p: &Params, coord: Vec4) -> f32 {
    let cell = coord.floor();
    let local = coord - cell;
    if p.dims == 1 {
        let h = |x: f32| hash_floats(&[x]) * p.randomness;
        let mid = h(cell.x);
        let left = -1.0 + h(cell.x - 1.0);
        let right = 1.0 + h(cell.x + 1.0);
        let to_left = ((mid + left) / 2.0 - local.x).abs();
        let to_right = ((mid + right) / 2.0 - local.x).abs();
        return to_left.min(to_right);
    }
    let dot = |a: Vec4, b: Vec4| (0..p.dims).fold(0.0, |s, k| s + a[k] * b[k]);
    let mut closest = Vec4::ZERO;
    let mut best = f32::MAX;
    for o in offsets(p.dims, 1) {
        let v = point(p, cell, o) - local;
        let d = dot(v, v);
        if d < best {
            best = d;
            closest = v;
        }
    }
    best = f32::MAX;
    for o in offsets(p.dims, 1) {
        let v = point(p, cell, o) - local;
        let perp = v - closest;
        if dot(perp, perp) > 0.0001 {
            let n = perp / dot(perp, perp).sqrt();
            best = best.min(dot((closest + v) / 2.0, n));
        }
    }
    best
}

/// The radius of the largest n-sphere about the nearest point that touches no other:
/// half the distance from the nearest point to its own nearest. Source: Blender's
/// `voronoi_n_sphere_radius` (Euclidean whatever the metric).
fn n_sphere_radius(p: &Params, coord: Vec4) -> f32 {
    let cell = coord.floor();
    let local = coord - cell;
    let e = Params { metric: 0, ..*p };
    let (mut closest, mut closest_off, mut best) = (Vec4::ZERO, Vec4::ZERO, f32::MAX);
    for o in offsets(p.dims, 1) {
        let point = point(p, cell, o);
        let d = distance(point, local, &e);
        if d < best {
            best = d;
            closest = point;
            closest_off = o;
        }
    }
    best = f32::MAX;
    let mut other = Vec4::ZERO;
    for o in offsets(p.dims, 1) {
        if o == Vec4::ZERO {
            continue;
        }
        let off = o + closest_off;
        let point = point(p, cell, off);
        let d = distance(closest, point, &e);
        if d < best {
            best = d;
            other = point;
        }
    }
    distance(other, closest, &e) / 2.0
}

/// Blender's Voronoi Texture: `(distance, color, position, w, radius)`.
///
/// Source: Blender 4.x `svm_node_tex_voronoi`, `fractal_voronoi_x_fx`,
/// `fractal_voronoi_distance_to_edge` (octaves summed as fBm, positions lerped).
#[allow(clippy::too_many_arguments)]
pub fn voronoi_texture(
    vector: Vec3,
    w: f32,
    scale: f32,
    detail: f32,
    roughness: f32,
    lacunarity: f32,
    smoothness: f32,
    exponent: f32,
    randomness: f32,
    dimensions: i32,
    feature: i32,
    metric: i32,
    normalize: bool,
) -> (f32, Vec3, Vec3, f32, f32) {
    let dims = (dimensions.clamp(0, 3) + 1) as usize;
    let feature = FEATURES[feature.clamp(0, FEATURES.len() as i32 - 1) as usize];
    let detail = detail.clamp(0.0, 15.0);
    let roughness = roughness.clamp(0.0, 1.0);
    let randomness = randomness.clamp(0.0, 1.0);
    let p = Params {
        dims,
        metric: metric.clamp(0, 3) as usize,
        exponent,
        randomness,
        smoothness: (smoothness / 2.0).clamp(0.0, 0.5),
    };
    let v = vector * scale;
    let w = w * scale;
    let coord = match dims {
        1 => Vec4::new(w, 0.0, 0.0, 0.0),
        2 => Vec4::new(v.x, v.y, 0.0, 0.0),
        3 => v.extend(0.0),
        _ => v.extend(w),
    };
    let zero_input = detail == 0.0 || roughness == 0.0;
    let octaves = detail.ceil() as i32;
    match feature {
        "n_sphere_radius" => (0.0, Vec3::ZERO, Vec3::ZERO, 0.0, n_sphere_radius(&p, coord)),
        "distance_to_edge" => {
            let max_distance = 0.5 + 0.5 * randomness;
            let (mut amplitude, mut max_amplitude, mut s, mut dist) =
                (1.0f32, max_distance, 1.0f32, 8.0f32);
            for i in 0..=octaves {
                let od = distance_to_edge(&p, coord * s);
                if zero_input {
                    dist = od;
                    break;
                }
                if i as f32 <= detail {
                    max_amplitude = mix(max_amplitude, max_distance / s, amplitude);
                    dist = mix(dist, dist.min(od / s), amplitude);
                    s *= lacunarity;
                    amplitude *= roughness;
                } else {
                    let rmd = detail - detail.floor();
                    if rmd != 0.0 {
                        let la = mix(max_amplitude, max_distance / s, amplitude);
                        max_amplitude = mix(max_amplitude, la, rmd);
                        let ld = mix(dist, dist.min(od / s), amplitude);
                        dist = mix(dist, dist.min(ld), rmd);
                    }
                }
            }
            if normalize {
                dist /= max_amplitude;
            }
            (dist, Vec3::ZERO, Vec3::ZERO, 0.0, 0.0)
        }
        _ => {
            let f2_factor = if feature == "f2" { 2.0 } else { 1.0 };
            let max_distance = if dims == 1 {
                (0.5 + 0.5 * randomness) * f2_factor
            } else {
                let corner = Vec4::splat(0.5 + 0.5 * randomness);
                distance(Vec4::ZERO, corner, &p) * f2_factor
            };
            let (mut amplitude, mut max_amplitude, mut s) = (1.0f32, 0.0f32, 1.0f32);
            let mut out = Octave {
                distance: 0.0,
                color: Vec3::ZERO,
                position: Vec4::ZERO,
            };
            for i in 0..=octaves {
                let q = coord * s;
                let o = match feature {
                    "f2" => nearest(&p, q, true),
                    "smooth_f1" if p.smoothness != 0.0 => smooth_f1(&p, q),
                    _ => nearest(&p, q, false),
                };
                if zero_input {
                    max_amplitude = 1.0;
                    out = o;
                    break;
                }
                if i as f32 <= detail {
                    max_amplitude += amplitude;
                    out.distance += o.distance * amplitude;
                    out.color += o.color * amplitude;
                    out.position = out.position + amplitude * (o.position / s - out.position);
                    s *= lacunarity;
                    amplitude *= roughness;
                } else {
                    let rmd = detail - detail.floor();
                    if rmd != 0.0 {
                        max_amplitude = mix(max_amplitude, max_amplitude + amplitude, rmd);
                        out.distance =
                            mix(out.distance, out.distance + o.distance * amplitude, rmd);
                        let with = out.color + o.color * amplitude;
                        out.color = out.color + rmd * (with - out.color);
                        let lerped = out.position + amplitude * (o.position / s - out.position);
                        out.position = out.position + rmd * (lerped - out.position);
                    }
                }
            }
            if normalize {
                out.distance /= max_amplitude * max_distance;
                out.color /= max_amplitude;
            }
            let position = if scale != 0.0 {
                out.position / scale
            } else {
                Vec4::ZERO
            };
            // 1D keeps its coordinate in w (Blender's voronoi_position(float)).
            let position = if dims == 1 {
                Vec4::new(0.0, 0.0, 0.0, position.x)
            } else {
                position
            };
            (
                out.distance,
                out.color,
                position.truncate(),
                position.w,
                0.0,
            )
        }
    }
}

/// WGSL of the Voronoi helpers (on [`super::blender_noise::BLENDER_NOISE_WGSL`]'s hash).
const VORONOI_WGSL: &str = r#"
fn mg_bv_distance(a: vec4<f32>, b: vec4<f32>, dims: i32, metric: i32, e: f32) -> f32 {
    if (dims == 1) {
        return abs(b.x - a.x);
    }
    let d = a - b;
    var s = 0.0;
    for (var k = 0; k < dims; k = k + 1) {
        let x = d[k];
        if (metric == 1) {
            s = s + abs(x);
        } else if (metric == 2) {
            s = max(s, abs(x));
        } else if (metric == 3) {
            s = s + pow(abs(x), e);
        } else {
            s = s + x * x;
        }
    }
    if (metric == 3) {
        return pow(s, 1.0 / e);
    }
    if (metric == 0) {
        return sqrt(s);
    }
    return s;
}

fn mg_bv_jitter(c: vec4<f32>, dims: i32) -> vec4<f32> {
    if (dims == 1) {
        return vec4<f32>(mg_bn_hf1(c.x), 0.0, 0.0, 0.0);
    }
    if (dims == 2) {
        return vec4<f32>(mg_bn_hf2(c.x, c.y), mg_bn_hf3(c.x, c.y, 1.0), 0.0, 0.0);
    }
    if (dims == 3) {
        return vec4<f32>(mg_bn_hf3(c.x, c.y, c.z), mg_bn_hf4(c.x, c.y, c.z, 1.0), mg_bn_hf4(c.x, c.y, c.z, 2.0), 0.0);
    }
    return vec4<f32>(mg_bn_hf4(c.x, c.y, c.z, c.w), mg_bn_hf4(c.w, c.x, c.y, c.z), mg_bn_hf4(c.z, c.w, c.x, c.y), mg_bn_hf4(c.y, c.z, c.w, c.x));
}

fn mg_bv_color(c: vec4<f32>, dims: i32) -> vec3<f32> {
    if (dims == 1) {
        return vec3<f32>(mg_bn_hf1(c.x), mg_bn_hf2(c.x, 1.0), mg_bn_hf2(c.x, 2.0));
    }
    if (dims == 2) {
        return vec3<f32>(mg_bn_hf2(c.x, c.y), mg_bn_hf3(c.x, c.y, 1.0), mg_bn_hf3(c.x, c.y, 2.0));
    }
    if (dims == 3) {
        return vec3<f32>(mg_bn_hf3(c.x, c.y, c.z), mg_bn_hf4(c.x, c.y, c.z, 1.0), mg_bn_hf4(c.x, c.y, c.z, 2.0));
    }
    return vec3<f32>(mg_bn_hf4(c.x, c.y, c.z, c.w), mg_bn_hf4(c.z, c.x, c.w, c.y), mg_bn_hf4(c.w, c.z, c.y, c.x));
}

// The span of cell offsets along axis `k` for `dims` dimensions and reach `r`.
fn mg_bv_span(k: i32, dims: i32, r: i32) -> i32 {
    return select(0, r, k < dims);
}

struct MgVoronoiOctave {
    distance: f32,
    color: vec3<f32>,
    position: vec4<f32>,
}

// F1 (kind 0), F2 (kind 1) or smooth F1 (kind 2) of one octave.
fn mg_bv_octave(coord: vec4<f32>, dims: i32, metric: i32, e: f32, randomness: f32, smoothness: f32, kind: i32) -> MgVoronoiOctave {
    let cell = floor(coord);
    let local = coord - cell;
    let r = select(1, 2, kind == 2);
    let rw = mg_bv_span(3, dims, r);
    let rz = mg_bv_span(2, dims, r);
    let ry = mg_bv_span(1, dims, r);
    var d1 = 3.4028234e38;
    var d2 = 3.4028234e38;
    var o1 = vec4<f32>(0.0);
    var o2 = vec4<f32>(0.0);
    var p1 = vec4<f32>(0.0);
    var p2 = vec4<f32>(0.0);
    var sd = 0.0;
    var sc = vec3<f32>(0.0);
    var sp = vec4<f32>(0.0);
    var h = -1.0;
    for (var u = -rw; u <= rw; u = u + 1) {
        for (var k = -rz; k <= rz; k = k + 1) {
            for (var j = -ry; j <= ry; j = j + 1) {
                for (var i = -r; i <= r; i = i + 1) {
                    let o = vec4<f32>(f32(i), f32(j), f32(k), f32(u));
                    let point = o + mg_bv_jitter(cell + o, dims) * randomness;
                    let d = mg_bv_distance(point, local, dims, metric, e);
                    if (kind == 2) {
                        if (h == -1.0) {
                            h = 1.0;
                        } else {
                            let x = 0.5 + 0.5 * (sd - d) / smoothness;
                            h = select(select((3.0 - 2.0 * x) * (x * x), 1.0, x >= 1.0), 0.0, x < 0.0);
                        }
                        var correction = smoothness * h * (1.0 - h);
                        sd = sd + h * (d - sd) - correction;
                        correction = correction / (1.0 + 3.0 * smoothness);
                        let c = mg_bv_color(cell + o, dims);
                        sc = sc + h * (c - sc) - vec3<f32>(correction);
                        let used = vec4<f32>(1.0, select(0.0, 1.0, dims > 1), select(0.0, 1.0, dims > 2), select(0.0, 1.0, dims > 3));
                        sp = sp + h * (point - sp) - used * correction;
                    } else if (d < d1) {
                        d2 = d1;
                        d1 = d;
                        o2 = o1;
                        o1 = o;
                        p2 = p1;
                        p1 = point;
                    } else if (d < d2) {
                        d2 = d;
                        o2 = o;
                        p2 = point;
                    }
                }
            }
        }
    }
    if (kind == 2) {
        return MgVoronoiOctave(sd, sc, cell + sp);
    }
    if (kind == 1) {
        return MgVoronoiOctave(d2, mg_bv_color(cell + o2, dims), p2 + cell);
    }
    return MgVoronoiOctave(d1, mg_bv_color(cell + o1, dims), p1 + cell);
}

fn mg_bv_edge(coord: vec4<f32>, dims: i32, randomness: f32) -> f32 {
    let cell = floor(coord);
    let local = coord - cell;
    if (dims == 1) {
        let mid = mg_bn_hf1(cell.x) * randomness;
        let left = -1.0 + mg_bn_hf1(cell.x - 1.0) * randomness;
        let right = 1.0 + mg_bn_hf1(cell.x + 1.0) * randomness;
        let to_left = abs((mid + left) / 2.0 - local.x);
        let to_right = abs((mid + right) / 2.0 - local.x);
        return min(to_left, to_right);
    }
    let rw = mg_bv_span(3, dims, 1);
    let rz = mg_bv_span(2, dims, 1);
    let ry = mg_bv_span(1, dims, 1);
    var closest = vec4<f32>(0.0);
    var best = 3.4028234e38;
    for (var u = -rw; u <= rw; u = u + 1) {
        for (var k = -rz; k <= rz; k = k + 1) {
            for (var j = -ry; j <= ry; j = j + 1) {
                for (var i = -1; i <= 1; i = i + 1) {
                    let o = vec4<f32>(f32(i), f32(j), f32(k), f32(u));
                    let v = o + mg_bv_jitter(cell + o, dims) * randomness - local;
                    let d = mg_bv_dot(v, v, dims);
                    if (d < best) {
                        best = d;
                        closest = v;
                    }
                }
            }
        }
    }
    best = 3.4028234e38;
    for (var u = -rw; u <= rw; u = u + 1) {
        for (var k = -rz; k <= rz; k = k + 1) {
            for (var j = -ry; j <= ry; j = j + 1) {
                for (var i = -1; i <= 1; i = i + 1) {
                    let o = vec4<f32>(f32(i), f32(j), f32(k), f32(u));
                    let v = o + mg_bv_jitter(cell + o, dims) * randomness - local;
                    let perp = v - closest;
                    let pp = mg_bv_dot(perp, perp, dims);
                    if (pp > 0.0001) {
                        let n = perp / sqrt(pp);
                        best = min(best, mg_bv_dot((closest + v) / 2.0, n, dims));
                    }
                }
            }
        }
    }
    return best;
}

fn mg_bv_dot(a: vec4<f32>, b: vec4<f32>, dims: i32) -> f32 {
    var s = 0.0;
    for (var k = 0; k < dims; k = k + 1) {
        s = s + a[k] * b[k];
    }
    return s;
}

fn mg_bv_radius(coord: vec4<f32>, dims: i32, randomness: f32) -> f32 {
    let cell = floor(coord);
    let local = coord - cell;
    let rw = mg_bv_span(3, dims, 1);
    let rz = mg_bv_span(2, dims, 1);
    let ry = mg_bv_span(1, dims, 1);
    var closest = vec4<f32>(0.0);
    var closest_off = vec4<f32>(0.0);
    var best = 3.4028234e38;
    for (var u = -rw; u <= rw; u = u + 1) {
        for (var k = -rz; k <= rz; k = k + 1) {
            for (var j = -ry; j <= ry; j = j + 1) {
                for (var i = -1; i <= 1; i = i + 1) {
                    let o = vec4<f32>(f32(i), f32(j), f32(k), f32(u));
                    let point = o + mg_bv_jitter(cell + o, dims) * randomness;
                    let d = mg_bv_distance(point, local, dims, 0, 1.0);
                    if (d < best) {
                        best = d;
                        closest = point;
                        closest_off = o;
                    }
                }
            }
        }
    }
    best = 3.4028234e38;
    var other = vec4<f32>(0.0);
    for (var u = -rw; u <= rw; u = u + 1) {
        for (var k = -rz; k <= rz; k = k + 1) {
            for (var j = -ry; j <= ry; j = j + 1) {
                for (var i = -1; i <= 1; i = i + 1) {
                    if (i == 0 && j == 0 && k == 0 && u == 0) {
                        continue;
                    }
                    let off = vec4<f32>(f32(i), f32(j), f32(k), f32(u)) + closest_off;
                    let point = off + mg_bv_jitter(cell + off, dims) * randomness;
                    let d = mg_bv_distance(closest, point, dims, 0, 1.0);
                    if (d < best) {
                        best = d;
                        other = point;
                    }
                }
            }
        }
    }
    return mg_bv_distance(other, closest, dims, 0, 1.0) / 2.0;
}
"#;

/// WGSL of [`voronoi_texture`].
const VORONOI_TEXTURE_WGSL: &str = r#"
fn $fn(vector: vec3<f32>, w0: f32, scale: f32, detail0: f32, roughness0: f32, lacunarity: f32, smoothness0: f32, exponent: f32, randomness0: f32, dimensions: i32, feature0: i32, metric0: i32, normalize: bool) -> $out {
    let dims = clamp(dimensions, 0, 3) + 1;
    let feature = clamp(feature0, 0, 4);
    let metric = clamp(metric0, 0, 3);
    let detail = clamp(detail0, 0.0, 15.0);
    let roughness = clamp(roughness0, 0.0, 1.0);
    let randomness = clamp(randomness0, 0.0, 1.0);
    let smoothness = clamp(smoothness0 / 2.0, 0.0, 0.5);
    let v = vector * scale;
    let w = w0 * scale;
    var coord = vec4<f32>(v, 0.0);
    if (dims == 1) { coord = vec4<f32>(w, 0.0, 0.0, 0.0); }
    if (dims == 2) { coord = vec4<f32>(v.xy, 0.0, 0.0); }
    if (dims == 4) { coord = vec4<f32>(v, w); }
    let zero_input = detail == 0.0 || roughness == 0.0;
    let octaves = i32(ceil(detail));
    if (feature == 4) {
        return $out(0.0, vec3<f32>(0.0), vec3<f32>(0.0), 0.0, mg_bv_radius(coord, dims, randomness));
    }
    if (feature == 3) {
        let max_distance = 0.5 + 0.5 * randomness;
        var amplitude = 1.0;
        var max_amplitude = max_distance;
        var s = 1.0;
        var dist = 8.0;
        for (var i = 0; i <= octaves; i = i + 1) {
            let od = mg_bv_edge(coord * s, dims, randomness);
            if (zero_input) {
                dist = od;
                break;
            }
            if (f32(i) <= detail) {
                max_amplitude = max_amplitude + amplitude * (max_distance / s - max_amplitude);
                dist = dist + amplitude * (min(dist, od / s) - dist);
                s = s * lacunarity;
                amplitude = amplitude * roughness;
            } else {
                let rmd = detail - floor(detail);
                if (rmd != 0.0) {
                    let la = max_amplitude + amplitude * (max_distance / s - max_amplitude);
                    max_amplitude = max_amplitude + rmd * (la - max_amplitude);
                    let ld = dist + amplitude * (min(dist, od / s) - dist);
                    dist = dist + rmd * (min(dist, ld) - dist);
                }
            }
        }
        if (normalize) {
            dist = dist / max_amplitude;
        }
        return $out(dist, vec3<f32>(0.0), vec3<f32>(0.0), 0.0, 0.0);
    }
    var f2_factor = 1.0;
    if (feature == 1) { f2_factor = 2.0; }
    var max_distance = (0.5 + 0.5 * randomness) * f2_factor;
    if (dims > 1) {
        max_distance = mg_bv_distance(vec4<f32>(0.0), vec4<f32>(0.5 + 0.5 * randomness), dims, metric, exponent) * f2_factor;
    }
    var kind = 0;
    if (feature == 1) { kind = 1; }
    if (feature == 2 && smoothness != 0.0) { kind = 2; }
    var amplitude = 1.0;
    var max_amplitude = 0.0;
    var s = 1.0;
    var out_d = 0.0;
    var out_c = vec3<f32>(0.0);
    var out_p = vec4<f32>(0.0);
    for (var i = 0; i <= octaves; i = i + 1) {
        let o = mg_bv_octave(coord * s, dims, metric, exponent, randomness, smoothness, kind);
        if (zero_input) {
            max_amplitude = 1.0;
            out_d = o.distance;
            out_c = o.color;
            out_p = o.position;
            break;
        }
        if (f32(i) <= detail) {
            max_amplitude = max_amplitude + amplitude;
            out_d = out_d + o.distance * amplitude;
            out_c = out_c + o.color * amplitude;
            out_p = out_p + amplitude * (o.position / s - out_p);
            s = s * lacunarity;
            amplitude = amplitude * roughness;
        } else {
            let rmd = detail - floor(detail);
            if (rmd != 0.0) {
                max_amplitude = max_amplitude + rmd * (max_amplitude + amplitude - max_amplitude);
                out_d = out_d + rmd * (out_d + o.distance * amplitude - out_d);
                let added = out_c + o.color * amplitude;
                out_c = out_c + rmd * (added - out_c);
                let lerped = out_p + amplitude * (o.position / s - out_p);
                out_p = out_p + rmd * (lerped - out_p);
            }
        }
    }
    if (normalize) {
        out_d = out_d / (max_amplitude * max_distance);
        out_c = out_c / max_amplitude;
    }
    var position = vec4<f32>(0.0);
    if (scale != 0.0) {
        position = out_p / scale;
    }
    if (dims == 1) {
        position = vec4<f32>(0.0, 0.0, 0.0, position.x);
    }
    return $out(out_d, out_c, position.xyz, position.w, 0.0);
}
"#;

/// The Voronoi node type.
pub fn all() -> Vec<NodeType> {
    let f = Value::float;
    let v3 = Value::vec3;
    let i = Value::int;
    vec![
        NodeType::new(
            "voronoi_texture",
            Category::Texture,
            "Blender's Voronoi Texture: Worley cellular noise in 1–4 D (F1, F2, smooth F1, distance to edge, n-sphere radius; four metrics; fractal octaves).",
        )
        .source(
            "Blender 4.x Voronoi Texture (intern/cycles/kernel/svm/voronoi.h): one point per unit \
             cell jittered by the lookup3 hash (Jenkins 2006) of the cell times randomness \
             (Worley 1996); F1, F2, smooth F1 (Quilez's smooth minimum), distance to edge \
             (Quilez's cell borders) and n-sphere radius; euclidean, manhattan, chebychev and \
             minkowski distances; Blender 4's octaves (distance and colour summed as fBm, \
             position lerped). Matches Blender 4.2 within 1e-4 (tests/models/blender_textures.rs). \
             Deviations: `vector` defaults to the origin (Blender: generated coordinates). \
             Limits: the minkowski exponent's hard range is [0.25, 8] (Blender: 0–32): below \
             it (Σ|d|^e)^(1/e) overflows f32 and smooth F1 turns NaN, above it |d|^e of short \
             distances falls below f32's normal range, which GPUs flush to zero. detail's hard \
             range is [0, 8] (Blender: 15): past 9 octaves smooth F1 differed between the CPU \
             and lavapipe by up to 29% at 3 of 15 000 random samples, not yet explained. Cell borders \
             are discontinuities: colour and position jump there, and any rounding may pick \
             either side (the parity suite judges the node by its conditioning).",
        )
        .input(In::vec3("vector", [0.0, 0.0, 0.0]).range(-10.0, 10.0).doc("Where to evaluate (link geometry.position or uv)."))
        .input(In::float("w", 0.0).range(-10.0, 10.0).doc("The fourth coordinate (1D: the only one)."))
        .input(In::float("scale", 5.0).range(0.0, 50.0).hard(-1.0e3, 1.0e3).doc("Multiplies vector and w."))
        .input(In::float("detail", 0.0).range(0.0, 8.0).hard(0.0, 8.0).doc("Octaves beyond the first (Blender allows 15; see the node's limits)."))
        .input(In::float("roughness", 0.5).range(0.0, 1.0).hard(0.0, 1.0).doc("Amplitude ratio between octaves."))
        .input(In::float("lacunarity", 2.0).range(0.5, 5.0).hard(0.5, 16.0).doc("Frequency ratio between octaves (Blender allows 0, which divides the position by 0)."))
        .input(In::float("smoothness", 1.0).range(0.0, 1.0).hard(0.0, 1.0).doc("Smooth F1 only: the width of the smooth minimum."))
        .input(In::float("exponent", 0.5).range(0.25, 4.0).hard(0.25, 8.0).doc("Minkowski only: the exponent of the metric (Blender allows 0–32; see the node's limits)."))
        .input(In::float("randomness", 1.0).range(0.0, 1.0).hard(0.0, 1.0).doc("How far each cell's point may stray from the cell's corner."))
        .input(In::choice("dimensions", DIMENSIONS, 2).doc("1D (w), 2D (vector.xy), 3D (vector) or 4D (vector, w)."))
        .input(In::choice("feature", FEATURES, 0).doc("What is measured."))
        .input(In::choice("metric", METRICS, 0).doc("The distance (1D: |Δ| always; n-sphere radius: euclidean always)."))
        .input(In::boolean("normalize", false).doc("Divide distance and colour so that they stay about [0, 1] over octaves."))
        .output(Out::float("distance").doc("The feature's distance (distance to edge: to the nearest border)."))
        .output(Out::color("color").doc("The hash colour of the cell found."))
        .output(Out::vec3("position").doc("The point found (in the input's space)."))
        .output(Out::float("w").doc("The point's fourth coordinate (1D and 4D)."))
        .output(Out::float("radius").doc("n-sphere radius only: half the distance from the nearest point to its own nearest."))
        .wgsl(VORONOI_TEXTURE_WGSL)
        .wgsl_constant_inputs(&["dimensions", "feature", "metric", "normalize"])
        .wgsl_uses(&[super::blender_noise::BLENDER_NOISE_WGSL, super::blender_noise::HASH_FLOATS_WGSL, VORONOI_WGSL])
        .hard_case("lattice corner", &[("vector", v3([1.0, 2.0, 3.0])), ("scale", f(1.0))])
        .hard_case("randomness 0: a regular grid", &[("vector", v3([0.5, 0.5, 0.5])), ("scale", f(1.0)), ("randomness", f(0.0)), ("feature", i(3))])
        .hard_case("smooth F1, smoothness 0", &[("vector", v3([0.3, 0.7, -0.2])), ("feature", i(2)), ("smoothness", f(0.0))])
        .hard_case("minkowski, smallest exponent", &[("vector", v3([0.3, 0.7, -0.2])), ("metric", i(3)), ("exponent", f(0.25))])
        .hard_case("4D, 8 octaves, normalised", &[("vector", v3([0.3, 0.7, -0.2])), ("dimensions", i(3)), ("detail", f(8.0)), ("normalize", Value::boolean(true))])
        .hard_case("zero scale", &[("scale", f(0.0))])
        .compute(voronoi_texture),
    ]
}
