//! Blender's Noise Texture node (Blender 4.x, shader and geometry nodes), as its definition
//! reads in Blender's sources (`intern/cycles/kernel/svm/noise.h`, `fractal_noise.h`,
//! `noisetex.h`; blenlib's `noise.cc` for geometry nodes), written again here.
//!
//! - **Hash**: Bob Jenkins' lookup3 final mix of 1–4 u32 (the lattice cell's integer
//!   coordinates, or a float's bits for the seed offsets).
//! - **Perlin noise** in 1–4 D: Perlin 2002's quintic fade and OSL's gradient sets (1D: ±1…8;
//!   2D: 8 directions with a 2× component; 3D: the 12 cube edges; 4D: 32), scaled to about
//!   [−1, 1] by OSL's factors 0.25, 0.6616, 0.9820, 0.8344. Coordinates wrap every 100 000
//!   (`fmod`) against float precision, as Blender does.
//! - **Fractals** (F. K. Musgrave, "Texturing & Modeling", ch. 16): fBm (normalised to [0, 1]
//!   or not), multifractal, hybrid multifractal, ridged multifractal, heterogeneous terrain;
//!   detail (octaves − 1, fractional detail blends in the last octave) clamped to [0, 15],
//!   roughness to ≥ 0, as Blender clamps them.
//! - **Distortion** adds a signed noise at seeded offsets to the coordinates; **colour** is the
//!   fractal at the coordinates offset by two more seeds.
//!
//! Every point is a vec4 with the node's dimension count: the unused components are carried
//! but never read. The CPU and WGSL versions run the same float operations in the same
//! order; tests/models/blender_textures.rs holds both to values Blender 4.2 itself computed.

use crate::node::{Category, In, NodeType, Out, WgslChoice};
use crate::value::Value;
use glam::{Vec3, Vec4};

/// The choices of the `dimensions` input.
pub const DIMENSIONS: &[&str] = &["1d", "2d", "3d", "4d"];
/// The choices of the `type` input (Blender's noise types).
pub const TYPES: &[&str] = &[
    "multifractal",
    "ridged_multifractal",
    "hybrid_multifractal",
    "fbm",
    "hetero_terrain",
];

/// lookup3's rotation.
#[inline]
fn rot(x: u32, k: u32) -> u32 {
    x.rotate_left(k)
}

/// lookup3's `final(a, b, c)`: returns c.
#[inline]
fn jenkins_final(mut a: u32, mut b: u32, mut c: u32) -> u32 {
    c ^= b;
    c = c.wrapping_sub(rot(b, 14));
    a ^= c;
    a = a.wrapping_sub(rot(c, 11));
    b ^= a;
    b = b.wrapping_sub(rot(a, 25));
    c ^= b;
    c = c.wrapping_sub(rot(b, 16));
    a ^= c;
    a = a.wrapping_sub(rot(c, 4));
    b ^= a;
    b = b.wrapping_sub(rot(a, 14));
    c ^= b;
    c.wrapping_sub(rot(b, 24))
}

/// lookup3's `mix(a, b, c)`.
#[inline]
fn jenkins_mix(a: &mut u32, b: &mut u32, c: &mut u32) {
    *a = a.wrapping_sub(*c);
    *a ^= rot(*c, 4);
    *c = c.wrapping_add(*b);
    *b = b.wrapping_sub(*a);
    *b ^= rot(*a, 6);
    *a = a.wrapping_add(*c);
    *c = c.wrapping_sub(*b);
    *c ^= rot(*b, 8);
    *b = b.wrapping_add(*a);
    *a = a.wrapping_sub(*c);
    *a ^= rot(*c, 16);
    *c = c.wrapping_add(*b);
    *b = b.wrapping_sub(*a);
    *b ^= rot(*a, 19);
    *a = a.wrapping_add(*c);
    *c = c.wrapping_sub(*b);
    *c ^= rot(*b, 4);
    *b = b.wrapping_add(*a);
}

/// lookup3 hash of `k` (1 to 4 words): the initial state `0xdeadbeef + 4n + 13`, the words
/// added to a, b, c (a fourth after one mix), then the final mix.
///
/// Source: B. Jenkins, lookup3.c (2006); Blender's `hash_uint`…`hash_uint4`.
pub fn jenkins(k: &[u32]) -> u32 {
    let init = 0xdead_beefu32
        .wrapping_add((k.len() as u32) << 2)
        .wrapping_add(13);
    let (mut a, mut b, mut c) = (init, init, init);
    match *k {
        [x] => a = a.wrapping_add(x),
        [x, y] => {
            b = b.wrapping_add(y);
            a = a.wrapping_add(x);
        }
        [x, y, z] => {
            c = c.wrapping_add(z);
            b = b.wrapping_add(y);
            a = a.wrapping_add(x);
        }
        [x, y, z, w] => {
            a = a.wrapping_add(x);
            b = b.wrapping_add(y);
            c = c.wrapping_add(z);
            jenkins_mix(&mut a, &mut b, &mut c);
            a = a.wrapping_add(w);
        }
        _ => {}
    }
    jenkins_final(a, b, c)
}

/// A hash in [0, 1]: `h / (2³² − 1)` in f32 (Blender's `uint_to_float_01`).
#[inline]
fn unit(h: u32) -> f32 {
    h as f32 / 4_294_967_295.0f32
}

/// Blender's `hash_floatN_to_float`: the lookup3 hash of the floats' bits, in [0, 1].
pub fn hash_floats(k: &[f32]) -> f32 {
    // At most four words, on the stack: Voronoi hashes a cell dozens of times a sample.
    let mut bits = [0u32; 4];
    let n = k.len().min(4);
    for (b, x) in bits.iter_mut().zip(k) {
        *b = x.to_bits();
    }
    unit(jenkins(&bits[..n]))
}

/// Blender's `hash_floatN_to_float3`: three decorrelated hashes of `k` in [0, 1].
pub fn hash_floats3(k: &[f32]) -> Vec3 {
    let h = hash_floats;
    match *k {
        [x] => Vec3::new(h(&[x]), h(&[x, 1.0]), h(&[x, 2.0])),
        [x, y] => Vec3::new(h(&[x, y]), h(&[x, y, 1.0]), h(&[x, y, 2.0])),
        [x, y, z] => Vec3::new(h(&[x, y, z]), h(&[x, y, z, 1.0]), h(&[x, y, z, 2.0])),
        [x, y, z, w] => Vec3::new(h(&[x, y, z, w]), h(&[z, x, w, y]), h(&[w, z, y, x])),
        _ => Vec3::ZERO,
    }
}

/// Blender's White Noise Texture: `(value, color)`, hashes of the coordinates' bits.
///
/// Source: Blender 4.x `svm_node_tex_white_noise` (`hash_floatN_to_float`,
/// `hash_floatN_to_float3`); 1D reads w, 2D vector.xy, 3D vector, 4D vector and w.
pub fn white_noise(vector: Vec3, w: f32, dimensions: i32) -> (f32, Vec3) {
    let all = [vector.x, vector.y, vector.z, w];
    let k: &[f32] = match dimensions.clamp(0, 3) {
        0 => &all[3..],
        1 => &all[..2],
        2 => &all[..3],
        _ => &all,
    };
    (hash_floats(k), hash_floats3(k))
}

/// The choices of the gradient texture's `type` (Blender's order).
pub const GRADIENTS: &[&str] = &[
    "linear",
    "quadratic",
    "easing",
    "diagonal",
    "spherical",
    "quadratic_sphere",
    "radial",
];

/// Blender's Gradient Texture: `(color, fac)`, fac the gradient of `kind` at `p` clamped to
/// [0, 1] and color its grey.
///
/// Source: Blender 4.x `svm_gradient` (linear x; quadratic max(x, 0)²; easing 3t² − 2t³ of
/// x in [0, 1]; diagonal (x + y)/2; spherical max(0.999999 − |p|, 0), squared for quadratic
/// sphere; radial atan2(y, x)/2π + ½, with `atan2(0, 0) = 0` as the `atan2` node), then
/// clamped to [0, 1] as the shader node clamps it (`svm_node_tex_gradient`; Blender's
/// geometry-nodes version leaves it unclamped).
pub fn gradient_texture(p: Vec3, kind: i32) -> (Vec3, f32) {
    let (x, y) = (p.x, p.y);
    let f = match GRADIENTS
        .get(kind.max(0) as usize)
        .copied()
        .unwrap_or("linear")
    {
        "quadratic" => {
            let r = x.max(0.0);
            r * r
        }
        "easing" => {
            let r = x.clamp(0.0, 1.0);
            let t = r * r;
            3.0 * t - 2.0 * t * r
        }
        "diagonal" => (x + y) * 0.5,
        "radial" => crate::nodes::math_scalar::atan2_total(y, x) / std::f32::consts::TAU + 0.5,
        // Blender biases 1 to 0.999999 so that a unit vector gives exactly 0.
        "spherical" => (0.999_999 - p.length()).max(0.0),
        "quadratic_sphere" => {
            let r = (0.999_999 - p.length()).max(0.0);
            r * r
        }
        _ => x,
    };
    let f = f.clamp(0.0, 1.0);
    (Vec3::splat(f), f)
}

/// The offset Blender adds to the coordinates for seed `seed`, component `k`:
/// `100 + 100 · hash(bits(seed), bits(k)) / (2³² − 1)` (`random_floatN_offset`).
pub fn seed_offset(seed: f32, k: f32) -> f32 {
    100.0 + hash_floats(&[seed, k]) * 100.0
}

/// Perlin's quintic fade `6t⁵ − 15t⁴ + 10t³`.
#[inline]
fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

#[inline]
fn negate_if(v: f32, c: u32) -> f32 {
    if c != 0 { -v } else { v }
}

/// `x − ⌊x⌋` and ⌊x⌋ as an integer (Blender's `floorfrac`).
#[inline]
fn floorfrac(x: f32) -> (f32, i32) {
    let f = x.floor();
    (x - f, f as i32)
}

#[inline]
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    (1.0 - t) * a + t * b
}

fn grad1(h: u32, x: f32) -> f32 {
    let h = h & 15;
    let g = (1 + (h & 7)) as f32;
    negate_if(g, h & 8) * x
}

fn grad2(h: u32, x: f32, y: f32) -> f32 {
    let h = h & 7;
    let u = if h < 4 { x } else { y };
    let v = 2.0 * if h < 4 { y } else { x };
    negate_if(u, h & 1) + negate_if(v, h & 2)
}

fn grad3(h: u32, x: f32, y: f32, z: f32) -> f32 {
    let h = h & 15;
    let u = if h < 8 { x } else { y };
    let vt = if h == 12 || h == 14 { x } else { z };
    let v = if h < 4 { y } else { vt };
    negate_if(u, h & 1) + negate_if(v, h & 2)
}

fn grad4(h: u32, x: f32, y: f32, z: f32, w: f32) -> f32 {
    let h = h & 31;
    let u = if h < 24 { x } else { y };
    let v = if h < 16 { y } else { z };
    let s = if h < 8 { z } else { w };
    negate_if(u, h & 1) + negate_if(v, h & 2) + negate_if(s, h & 4)
}

/// Perlin noise in `dims` dimensions of the first components of `p` (unscaled).
///
/// Source: K. Perlin, "Improving Noise", SIGGRAPH 2002, with OSL's gradient sets.
fn perlin(p: Vec4, dims: usize) -> f32 {
    let (fx, x) = floorfrac(p.x);
    let (fy, y) = floorfrac(p.y);
    let (fz, z) = floorfrac(p.z);
    let (fw, w) = floorfrac(p.w);
    let c = |i: i32| i as u32;
    let i1 = |i: i32| i.wrapping_add(1) as u32;
    match dims {
        1 => {
            let u = fade(fx);
            lerp(
                grad1(jenkins(&[c(x)]), fx),
                grad1(jenkins(&[i1(x)]), fx - 1.0),
                u,
            )
        }
        2 => {
            let (u, v) = (fade(fx), fade(fy));
            let g = |dx: u32, dy: u32| {
                let h = jenkins(&[c(x).wrapping_add(dx), c(y).wrapping_add(dy)]);
                grad2(h, fx - dx as f32, fy - dy as f32)
            };
            let x1 = 1.0 - u;
            (1.0 - v) * (g(0, 0) * x1 + g(1, 0) * u) + v * (g(0, 1) * x1 + g(1, 1) * u)
        }
        3 => perlin3(fx, fy, fz, [c(x), c(y), c(z)], None),
        _ => {
            let s = fade(fw);
            let a = perlin3(fx, fy, fz, [c(x), c(y), c(z)], Some((c(w), fw)));
            let b = perlin3(fx, fy, fz, [c(x), c(y), c(z)], Some((i1(w), fw - 1.0)));
            lerp(a, b, s)
        }
    }
}

/// The trilinear blend of the 8 corner gradients of a 3D cell, or of the 8 of a 4D cell
/// at one w (`four`: the w cell and fraction).
fn perlin3(fx: f32, fy: f32, fz: f32, [x, y, z]: [u32; 3], four: Option<(u32, f32)>) -> f32 {
    let (u, v, t) = (fade(fx), fade(fy), fade(fz));
    let g = |dx: u32, dy: u32, dz: u32| {
        let (hx, hy, hz) = (x.wrapping_add(dx), y.wrapping_add(dy), z.wrapping_add(dz));
        let (gx, gy, gz) = (fx - dx as f32, fy - dy as f32, fz - dz as f32);
        match four {
            Some((w, fw)) => grad4(jenkins(&[hx, hy, hz, w]), gx, gy, gz, fw),
            None => grad3(jenkins(&[hx, hy, hz]), gx, gy, gz),
        }
    };
    let (x1, y1, z1) = (1.0 - u, 1.0 - v, 1.0 - t);
    z1 * (y1 * (g(0, 0, 0) * x1 + g(1, 0, 0) * u) + v * (g(0, 1, 0) * x1 + g(1, 1, 0) * u))
        + t * (y1 * (g(0, 0, 1) * x1 + g(1, 0, 1) * u) + v * (g(0, 1, 1) * x1 + g(1, 1, 1) * u))
}

/// Signed noise in about [−1, 1]: Perlin noise of `p` wrapped every 100 000, times OSL's
/// factor for the dimension (Blender's `snoise_Nd`).
pub fn snoise(p: Vec4, dims: usize) -> f32 {
    let q = Vec4::new(
        p.x % 100_000.0,
        p.y % 100_000.0,
        p.z % 100_000.0,
        p.w % 100_000.0,
    );
    let scale = [0.25, 0.6616, 0.9820, 0.8344][dims - 1];
    scale * perlin(q, dims)
}

/// The fractal of `kind` (an index into [`TYPES`]) at `p`.
///
/// Source: Musgrave, "Texturing & Modeling" ch. 16; Blender's `fractal_noise.h`.
#[allow(clippy::too_many_arguments)]
pub fn fractal(
    mut p: Vec4,
    dims: usize,
    detail: f32,
    roughness: f32,
    lacunarity: f32,
    offset: f32,
    gain: f32,
    kind: usize,
    normalize: bool,
) -> f32 {
    let n = detail as i32;
    let rmd = detail - detail.floor();
    match TYPES.get(kind).copied().unwrap_or("fbm") {
        "multifractal" => {
            let (mut value, mut pwr) = (1.0f32, 1.0f32);
            for _ in 0..=n {
                value *= pwr * snoise(p, dims) + 1.0;
                pwr *= roughness;
                p *= lacunarity;
            }
            if rmd != 0.0 {
                value *= rmd * pwr * snoise(p, dims) + 1.0;
            }
            value
        }
        "ridged_multifractal" => {
            let mut pwr = roughness;
            let mut signal = offset - snoise(p, dims).abs();
            signal *= signal;
            let mut value = signal;
            for _ in 1..=n {
                p *= lacunarity;
                let weight = (signal * gain).clamp(0.0, 1.0);
                signal = offset - snoise(p, dims).abs();
                signal *= signal;
                signal *= weight;
                value += signal * pwr;
                pwr *= roughness;
            }
            value
        }
        "hybrid_multifractal" => {
            let (mut pwr, mut value, mut weight) = (1.0f32, 0.0f32, 1.0f32);
            let mut i = 0;
            while weight > 0.001 && i <= n {
                weight = weight.min(1.0);
                let signal = (snoise(p, dims) + offset) * pwr;
                pwr *= roughness;
                value += weight * signal;
                weight *= gain * signal;
                p *= lacunarity;
                i += 1;
            }
            if rmd != 0.0 && weight > 0.001 {
                weight = weight.min(1.0);
                let signal = (snoise(p, dims) + offset) * pwr;
                value += rmd * weight * signal;
            }
            value
        }
        "hetero_terrain" => {
            let mut pwr = roughness;
            let mut value = offset + snoise(p, dims);
            p *= lacunarity;
            for _ in 1..=n {
                let increment = (snoise(p, dims) + offset) * pwr * value;
                value += increment;
                pwr *= roughness;
                p *= lacunarity;
            }
            if rmd != 0.0 {
                let increment = (snoise(p, dims) + offset) * pwr * value;
                value += rmd * increment;
            }
            value
        }
        _ => {
            let (mut fscale, mut amp, mut maxamp, mut sum) = (1.0f32, 1.0f32, 0.0f32, 0.0f32);
            for _ in 0..=n {
                let t = snoise(p * fscale, dims);
                sum += t * amp;
                maxamp += amp;
                amp *= roughness;
                fscale *= lacunarity;
            }
            if rmd != 0.0 {
                let t = snoise(p * fscale, dims);
                let sum2 = sum + t * amp;
                if normalize {
                    let a = 0.5 * sum / maxamp + 0.5;
                    let b = 0.5 * sum2 / (maxamp + amp) + 0.5;
                    a + rmd * (b - a)
                } else {
                    sum + rmd * (sum2 - sum)
                }
            } else if normalize {
                0.5 * sum / maxamp + 0.5
            } else {
                sum
            }
        }
    }
}

/// The seed offset vector of `seed` for `dims` dimensions (Blender's
/// `random_floatN_offset`; 1D uses the one-float hash).
fn offset_vec(seed: f32, dims: usize) -> Vec4 {
    if dims == 1 {
        return Vec4::new(100.0 + hash_floats(&[seed]) * 100.0, 0.0, 0.0, 0.0);
    }
    let mut o = Vec4::ZERO;
    for k in 0..dims {
        o[k] = seed_offset(seed, k as f32);
    }
    o
}

/// Blender's Noise Texture: `(fac, color)` at `vector` (and `w`) for the node's inputs.
///
/// Source: Blender 4.x `svm_node_tex_noise` / `noise_texture_{1,2,3,4}d` (the coordinates
/// scaled, distorted by signed noise at seeds 0…dims−1, the fractal; colour channels 2 and 3
/// at the coordinates offset by the next two seeds).
#[allow(clippy::too_many_arguments)]
pub fn noise_texture(
    vector: Vec3,
    w: f32,
    scale: f32,
    detail: f32,
    roughness: f32,
    lacunarity: f32,
    offset: f32,
    gain: f32,
    distortion: f32,
    dimensions: i32,
    kind: i32,
    normalize: bool,
) -> (f32, Vec3) {
    let dims = (dimensions.clamp(0, 3) + 1) as usize;
    let detail = detail.clamp(0.0, 15.0);
    let roughness = roughness.max(0.0);
    let v = vector * scale;
    let w = w * scale;
    let mut p = match dims {
        1 => Vec4::new(w, 0.0, 0.0, 0.0),
        2 => Vec4::new(v.x, v.y, 0.0, 0.0),
        3 => v.extend(0.0),
        _ => v.extend(w),
    };
    if distortion != 0.0 {
        let mut d = Vec4::ZERO;
        for k in 0..dims {
            d[k] = snoise(p + offset_vec(k as f32, dims), dims) * distortion;
        }
        p += d;
    }
    let kind = kind.clamp(0, TYPES.len() as i32 - 1) as usize;
    let f = |q: Vec4| {
        fractal(
            q, dims, detail, roughness, lacunarity, offset, gain, kind, normalize,
        )
    };
    let value = f(p);
    // Colour seeds: 1, 2 (1D); 2, 3 (2D); 3, 4 (3D); 4, 5 (4D).
    let s = dims as f32;
    let color = Vec3::new(
        value,
        f(p + offset_vec(s, dims)),
        f(p + offset_vec(s + 1.0, dims)),
    );
    (value, color)
}

/// WGSL of the hash, Perlin noise and fractals (every point a vec4 and its dimension count).
pub const BLENDER_NOISE_WGSL: &str = r#"
fn mg_bn_final(a0: u32, b0: u32, c0: u32) -> u32 {
    var a = a0;
    var b = b0;
    var c = c0;
    c = c ^ b; c = c - ((b << 14u) | (b >> 18u));
    a = a ^ c; a = a - ((c << 11u) | (c >> 21u));
    b = b ^ a; b = b - ((a << 25u) | (a >> 7u));
    c = c ^ b; c = c - ((b << 16u) | (b >> 16u));
    a = a ^ c; a = a - ((c << 4u) | (c >> 28u));
    b = b ^ a; b = b - ((a << 14u) | (a >> 18u));
    c = c ^ b; c = c - ((b << 24u) | (b >> 8u));
    return c;
}

fn mg_bn_hash1(x: u32) -> u32 {
    let i = 0xdeadbeefu + (1u << 2u) + 13u;
    return mg_bn_final(i + x, i, i);
}

fn mg_bn_hash2(x: u32, y: u32) -> u32 {
    let i = 0xdeadbeefu + (2u << 2u) + 13u;
    return mg_bn_final(i + x, i + y, i);
}

fn mg_bn_hash3(x: u32, y: u32, z: u32) -> u32 {
    let i = 0xdeadbeefu + (3u << 2u) + 13u;
    return mg_bn_final(i + x, i + y, i + z);
}

fn mg_bn_hash4(x: u32, y: u32, z: u32, w: u32) -> u32 {
    let i = 0xdeadbeefu + (4u << 2u) + 13u;
    var a = i + x;
    var b = i + y;
    var c = i + z;
    a = a - c; a = a ^ ((c << 4u) | (c >> 28u)); c = c + b;
    b = b - a; b = b ^ ((a << 6u) | (a >> 26u)); a = a + c;
    c = c - b; c = c ^ ((b << 8u) | (b >> 24u)); b = b + a;
    a = a - c; a = a ^ ((c << 16u) | (c >> 16u)); c = c + b;
    b = b - a; b = b ^ ((a << 19u) | (a >> 13u)); a = a + c;
    c = c - b; c = c ^ ((b << 4u) | (b >> 28u)); b = b + a;
    return mg_bn_final(a + w, b, c);
}

fn mg_bn_fade(t: f32) -> f32 {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

fn mg_bn_neg(v: f32, c: u32) -> f32 {
    return select(v, -v, c != 0u);
}

fn mg_bn_lerp(a: f32, b: f32, t: f32) -> f32 {
    return (1.0 - t) * a + t * b;
}

fn mg_bn_grad3(h0: u32, x: f32, y: f32, z: f32) -> f32 {
    let h = h0 & 15u;
    let u = select(y, x, h < 8u);
    let vt = select(z, x, h == 12u || h == 14u);
    let v = select(vt, y, h < 4u);
    return mg_bn_neg(u, h & 1u) + mg_bn_neg(v, h & 2u);
}

fn mg_bn_grad4(h0: u32, x: f32, y: f32, z: f32, w: f32) -> f32 {
    let h = h0 & 31u;
    let u = select(y, x, h < 24u);
    let v = select(z, y, h < 16u);
    let s = select(w, z, h < 8u);
    return mg_bn_neg(u, h & 1u) + mg_bn_neg(v, h & 2u) + mg_bn_neg(s, h & 4u);
}

fn mg_bn_corner(four: bool, x: u32, y: u32, z: u32, w: u32, gx: f32, gy: f32, gz: f32, gw: f32) -> f32 {
    if (four) {
        return mg_bn_grad4(mg_bn_hash4(x, y, z, w), gx, gy, gz, gw);
    }
    return mg_bn_grad3(mg_bn_hash3(x, y, z), gx, gy, gz);
}

fn mg_bn_perlin3(f: vec3<f32>, c: vec3<u32>, w: u32, fw: f32, four: bool) -> f32 {
    let u = mg_bn_fade(f.x);
    let v = mg_bn_fade(f.y);
    let t = mg_bn_fade(f.z);
    let x1 = 1.0 - u;
    let y1 = 1.0 - v;
    let z1 = 1.0 - t;
    let g000 = mg_bn_corner(four, c.x, c.y, c.z, w, f.x, f.y, f.z, fw);
    let g100 = mg_bn_corner(four, c.x + 1u, c.y, c.z, w, f.x - 1.0, f.y, f.z, fw);
    let g010 = mg_bn_corner(four, c.x, c.y + 1u, c.z, w, f.x, f.y - 1.0, f.z, fw);
    let g110 = mg_bn_corner(four, c.x + 1u, c.y + 1u, c.z, w, f.x - 1.0, f.y - 1.0, f.z, fw);
    let g001 = mg_bn_corner(four, c.x, c.y, c.z + 1u, w, f.x, f.y, f.z - 1.0, fw);
    let g101 = mg_bn_corner(four, c.x + 1u, c.y, c.z + 1u, w, f.x - 1.0, f.y, f.z - 1.0, fw);
    let g011 = mg_bn_corner(four, c.x, c.y + 1u, c.z + 1u, w, f.x, f.y - 1.0, f.z - 1.0, fw);
    let g111 = mg_bn_corner(four, c.x + 1u, c.y + 1u, c.z + 1u, w, f.x - 1.0, f.y - 1.0, f.z - 1.0, fw);
    return z1 * (y1 * (g000 * x1 + g100 * u) + v * (g010 * x1 + g110 * u))
        + t * (y1 * (g001 * x1 + g101 * u) + v * (g011 * x1 + g111 * u));
}

fn mg_bn_perlin(p: vec4<f32>, dims: i32) -> f32 {
    let fl = floor(p);
    let f = p - fl;
    let c = bitcast<vec4<u32>>(vec4<i32>(fl));
    if (dims == 1) {
        let h = mg_bn_hash1(c.x) & 15u;
        let h1 = mg_bn_hash1(c.x + 1u) & 15u;
        let g0 = mg_bn_neg(f32(1u + (h & 7u)), h & 8u) * f.x;
        let g1 = mg_bn_neg(f32(1u + (h1 & 7u)), h1 & 8u) * (f.x - 1.0);
        return mg_bn_lerp(g0, g1, mg_bn_fade(f.x));
    }
    if (dims == 2) {
        let u = mg_bn_fade(f.x);
        let v = mg_bn_fade(f.y);
        var g: array<f32, 4>;
        for (var k = 0u; k < 4u; k = k + 1u) {
            let dx = k & 1u;
            let dy = k >> 1u;
            let h = mg_bn_hash2(c.x + dx, c.y + dy) & 7u;
            let gx = f.x - f32(dx);
            let gy = f.y - f32(dy);
            let a = select(gy, gx, h < 4u);
            let b = 2.0 * select(gx, gy, h < 4u);
            g[k] = mg_bn_neg(a, h & 1u) + mg_bn_neg(b, h & 2u);
        }
        let x1 = 1.0 - u;
        return (1.0 - v) * (g[0] * x1 + g[1] * u) + v * (g[2] * x1 + g[3] * u);
    }
    if (dims == 3) {
        return mg_bn_perlin3(f.xyz, c.xyz, 0u, 0.0, false);
    }
    let a = mg_bn_perlin3(f.xyz, c.xyz, c.w, f.w, true);
    let b = mg_bn_perlin3(f.xyz, c.xyz, c.w + 1u, f.w - 1.0, true);
    return mg_bn_lerp(a, b, mg_bn_fade(f.w));
}

// fmod(x, 100000) exactly, as C's fmod (the sign of x): WGSL's `%` is x − y·trunc(x/y),
// whose rounding moves a huge x to another cell. Long division by 100000·2^k, k = 110…0:
// each subtraction is exact (Sterbenz: m ≤ r < 2m).
fn mg_bn_fmod(x: f32) -> f32 {
    var r = abs(x);
    if (r < 100000.0) {
        return x;
    }
    for (var k = 110; k >= 0; k = k - 1) {
        let m = ldexp(100000.0, k);
        if (r >= m) {
            r = r - m;
        }
    }
    return select(r, -r, x < 0.0);
}

fn mg_bn_snoise(p: vec4<f32>, dims: i32) -> f32 {
    let q = vec4<f32>(mg_bn_fmod(p.x), mg_bn_fmod(p.y), mg_bn_fmod(p.z), mg_bn_fmod(p.w));
    var s = 0.8344;
    if (dims == 1) { s = 0.25; }
    if (dims == 2) { s = 0.6616; }
    if (dims == 3) { s = 0.9820; }
    return s * mg_bn_perlin(q, dims);
}

// Musgrave's fractals, one function per Blender noise type (each takes `kind`, unused, so
// that the node's one call text serves the dispatch and a written type alike; see
// `WgslChoices`). Blender's multifractal.
fn mg_bn_fractal_multifractal(p0: vec4<f32>, dims: i32, detail: f32, roughness: f32, lacunarity: f32, offset: f32, gain: f32, kind: i32, normalize: bool) -> f32 {
    var p = p0;
    let n = i32(detail);
    let rmd = detail - floor(detail);
    var value = 1.0;
    var pwr = 1.0;
    for (var i = 0; i <= n; i = i + 1) {
        value = value * (pwr * mg_bn_snoise(p, dims) + 1.0);
        pwr = pwr * roughness;
        p = p * lacunarity;
    }
    if (rmd != 0.0) {
        value = value * (rmd * pwr * mg_bn_snoise(p, dims) + 1.0);
    }
    return value;
}

// Blender's ridged multifractal.
fn mg_bn_fractal_ridged_multifractal(p0: vec4<f32>, dims: i32, detail: f32, roughness: f32, lacunarity: f32, offset: f32, gain: f32, kind: i32, normalize: bool) -> f32 {
    var p = p0;
    let n = i32(detail);
    var pwr = roughness;
    var signal = offset - abs(mg_bn_snoise(p, dims));
    signal = signal * signal;
    var value = signal;
    for (var i = 1; i <= n; i = i + 1) {
        p = p * lacunarity;
        let weight = clamp(signal * gain, 0.0, 1.0);
        signal = offset - abs(mg_bn_snoise(p, dims));
        signal = signal * signal;
        signal = signal * weight;
        value = value + signal * pwr;
        pwr = pwr * roughness;
    }
    return value;
}

// Blender's hybrid multifractal.
fn mg_bn_fractal_hybrid_multifractal(p0: vec4<f32>, dims: i32, detail: f32, roughness: f32, lacunarity: f32, offset: f32, gain: f32, kind: i32, normalize: bool) -> f32 {
    var p = p0;
    let n = i32(detail);
    let rmd = detail - floor(detail);
    var pwr = 1.0;
    var value = 0.0;
    var weight = 1.0;
    for (var i = 0; weight > 0.001 && i <= n; i = i + 1) {
        weight = min(weight, 1.0);
        let signal = (mg_bn_snoise(p, dims) + offset) * pwr;
        pwr = pwr * roughness;
        value = value + weight * signal;
        weight = weight * gain * signal;
        p = p * lacunarity;
    }
    if (rmd != 0.0 && weight > 0.001) {
        weight = min(weight, 1.0);
        let signal = (mg_bn_snoise(p, dims) + offset) * pwr;
        value = value + rmd * weight * signal;
    }
    return value;
}

// Blender's hetero terrain.
fn mg_bn_fractal_hetero_terrain(p0: vec4<f32>, dims: i32, detail: f32, roughness: f32, lacunarity: f32, offset: f32, gain: f32, kind: i32, normalize: bool) -> f32 {
    var p = p0;
    let n = i32(detail);
    let rmd = detail - floor(detail);
    var pwr = roughness;
    var value = offset + mg_bn_snoise(p, dims);
    p = p * lacunarity;
    for (var i = 1; i <= n; i = i + 1) {
        let increment = (mg_bn_snoise(p, dims) + offset) * pwr * value;
        value = value + increment;
        pwr = pwr * roughness;
        p = p * lacunarity;
    }
    if (rmd != 0.0) {
        let increment = (mg_bn_snoise(p, dims) + offset) * pwr * value;
        value = value + rmd * increment;
    }
    return value;
}

// Blender's fBm (normalised: to [0, 1]).
fn mg_bn_fractal_fbm(p: vec4<f32>, dims: i32, detail: f32, roughness: f32, lacunarity: f32, offset: f32, gain: f32, kind: i32, normalize: bool) -> f32 {
    let n = i32(detail);
    let rmd = detail - floor(detail);
    var fscale = 1.0;
    var amp = 1.0;
    var maxamp = 0.0;
    var sum = 0.0;
    for (var i = 0; i <= n; i = i + 1) {
        let t = mg_bn_snoise(p * fscale, dims);
        sum = sum + t * amp;
        maxamp = maxamp + amp;
        amp = amp * roughness;
        fscale = fscale * lacunarity;
    }
    if (rmd != 0.0) {
        let t = mg_bn_snoise(p * fscale, dims);
        let sum2 = sum + t * amp;
        if (normalize) {
            let a = 0.5 * sum / maxamp + 0.5;
            let b = 0.5 * sum2 / (maxamp + amp) + 0.5;
            return a + rmd * (b - a);
        }
        return sum + rmd * (sum2 - sum);
    }
    if (normalize) {
        return 0.5 * sum / maxamp + 0.5;
    }
    return sum;
}

// The type chosen at run time (`kind`: the index in TYPES).
fn mg_bn_fractal(p: vec4<f32>, dims: i32, detail: f32, roughness: f32, lacunarity: f32, offset: f32, gain: f32, kind: i32, normalize: bool) -> f32 {
    switch kind {
        case 0: { return mg_bn_fractal_multifractal(p, dims, detail, roughness, lacunarity, offset, gain, kind, normalize); }
        case 1: { return mg_bn_fractal_ridged_multifractal(p, dims, detail, roughness, lacunarity, offset, gain, kind, normalize); }
        case 2: { return mg_bn_fractal_hybrid_multifractal(p, dims, detail, roughness, lacunarity, offset, gain, kind, normalize); }
        case 4: { return mg_bn_fractal_hetero_terrain(p, dims, detail, roughness, lacunarity, offset, gain, kind, normalize); }
        default: { return mg_bn_fractal_fbm(p, dims, detail, roughness, lacunarity, offset, gain, kind, normalize); }
    }
}

"#;

/// WGSL of Blender's float hashes (`hash_floatN_to_float`) and seed offsets.
pub const HASH_FLOATS_WGSL: &str = r#"
fn mg_bn_unit(h: u32) -> f32 {
    return f32(h) / 4294967295.0;
}
fn mg_bn_hf1(x: f32) -> f32 {
    return mg_bn_unit(mg_bn_hash1(bitcast<u32>(x)));
}
fn mg_bn_hf2(x: f32, y: f32) -> f32 {
    return mg_bn_unit(mg_bn_hash2(bitcast<u32>(x), bitcast<u32>(y)));
}
fn mg_bn_hf3(x: f32, y: f32, z: f32) -> f32 {
    return mg_bn_unit(mg_bn_hash3(bitcast<u32>(x), bitcast<u32>(y), bitcast<u32>(z)));
}
fn mg_bn_hf4(x: f32, y: f32, z: f32, w: f32) -> f32 {
    return mg_bn_unit(mg_bn_hash4(bitcast<u32>(x), bitcast<u32>(y), bitcast<u32>(z), bitcast<u32>(w)));
}

// Blender's `random_floatN_offset(seed)`: 100 + 100·hash per component (1D: one float's hash).
fn mg_bn_offset(seed: f32, dims: i32) -> vec4<f32> {
    if (dims == 1) {
        return vec4<f32>(100.0 + mg_bn_hf1(seed) * 100.0, 0.0, 0.0, 0.0);
    }
    var o = vec4<f32>(0.0);
    for (var k = 0; k < dims; k = k + 1) {
        o[k] = 100.0 + mg_bn_hf2(seed, f32(k)) * 100.0;
    }
    return o;
}
"#;

/// WGSL of [`white_noise`].
const WHITE_NOISE_WGSL: &str = r#"
fn $fn(v: vec3<f32>, w: f32, dimensions: i32) -> $out {
    let d = clamp(dimensions, 0, 3);
    if (d == 0) {
        let c = vec3<f32>(mg_bn_hf1(w), mg_bn_hf2(w, 1.0), mg_bn_hf2(w, 2.0));
        return $out(c.x, c);
    }
    if (d == 1) {
        let c = vec3<f32>(mg_bn_hf2(v.x, v.y), mg_bn_hf3(v.x, v.y, 1.0), mg_bn_hf3(v.x, v.y, 2.0));
        return $out(c.x, c);
    }
    if (d == 2) {
        let c = vec3<f32>(mg_bn_hf3(v.x, v.y, v.z), mg_bn_hf4(v.x, v.y, v.z, 1.0), mg_bn_hf4(v.x, v.y, v.z, 2.0));
        return $out(c.x, c);
    }
    let c = vec3<f32>(mg_bn_hf4(v.x, v.y, v.z, w), mg_bn_hf4(v.z, v.x, w, v.y), mg_bn_hf4(w, v.z, v.y, v.x));
    return $out(c.x, c);
}
"#;

/// WGSL of [`gradient_texture`].
const GRADIENT_TEXTURE_WGSL: &str = r#"
fn $fn(p: vec3<f32>, kind: i32) -> $out {
    let x = p.x;
    let y = p.y;
    var f = x;
    if (kind == 1) {
        let r = max(x, 0.0);
        f = r * r;
    } else if (kind == 2) {
        let r = clamp(x, 0.0, 1.0);
        let t = r * r;
        f = 3.0 * t - 2.0 * t * r;
    } else if (kind == 3) {
        f = (x + y) * 0.5;
    } else if (kind == 6) {
        f = mg_math_atan2(y, x) / 6.2831855 + 0.5;
    } else if (kind == 4 || kind == 5) {
        let r = max(0.999999 - sqrt(x * x + y * y + p.z * p.z), 0.0);
        f = select(r, r * r, kind == 5);
    }
    let c = clamp(f, 0.0, 1.0);
    return $out(vec3<f32>(c), c);
}
"#;

/// WGSL of [`noise_texture`].
const NOISE_TEXTURE_WGSL: &str = r#"
fn $fn(vector: vec3<f32>, w0: f32, scale: f32, detail0: f32, roughness0: f32, lacunarity: f32, offset: f32, gain: f32, distortion: f32, dimensions: i32, kind0: i32, normalize: bool) -> $out {
    let dims = clamp(dimensions, 0, 3) + 1;
    let detail = clamp(detail0, 0.0, 15.0);
    let roughness = max(roughness0, 0.0);
    let v = vector * scale;
    let w = w0 * scale;
    var p = vec4<f32>(v, 0.0);
    if (dims == 1) { p = vec4<f32>(w, 0.0, 0.0, 0.0); }
    if (dims == 2) { p = vec4<f32>(v.xy, 0.0, 0.0); }
    if (dims == 4) { p = vec4<f32>(v, w); }
    if (distortion != 0.0) {
        var d = vec4<f32>(0.0);
        for (var k = 0; k < dims; k = k + 1) {
            d[k] = mg_bn_snoise(p + mg_bn_offset(f32(k), dims), dims) * distortion;
        }
        p = p + d;
    }
    let kind = clamp(kind0, 0, 4);
    let value = mg_bn_fractal${type}(p, dims, detail, roughness, lacunarity, offset, gain, kind, normalize);
    let s = f32(dims);
    let g = mg_bn_fractal${type}(p + mg_bn_offset(s, dims), dims, detail, roughness, lacunarity, offset, gain, kind, normalize);
    let b = mg_bn_fractal${type}(p + mg_bn_offset(s + 1.0, dims), dims, detail, roughness, lacunarity, offset, gain, kind, normalize);
    return $out(value, vec3<f32>(value, g, b));
}
"#;

/// The Blender-compatible texture node types.
pub fn all() -> Vec<NodeType> {
    let f = Value::float;
    let v3 = Value::vec3;
    let i = Value::int;
    vec![
        NodeType::new(
            "noise_texture",
            Category::Texture,
            "Blender's Noise Texture: fractal Perlin noise in 1–4 D (fBm, multifractal, hybrid, ridged, hetero terrain).",
        )
        .source(
            "Blender 4.x Noise Texture (intern/cycles/kernel/svm/noisetex.h, fractal_noise.h, \
             noise.h): Perlin noise (Perlin 2002, OSL's gradients and range factors) on a lookup3 \
             hash (Jenkins 2006) of the cell, coordinates wrapped every 100 000; Musgrave's \
             fractals (Texturing & Modeling, ch. 16); distortion and colour by seeded offsets. \
             Matches Blender 4.2 within 1e-4 (tests/models/blender_textures.rs, values from Blender \
             itself). Deviations: none in the definition; `vector` defaults to the origin \
             (Blender: the object's generated coordinates), so link geometry.position or uv. \
             Limits: the hard ranges are narrower than Blender's fields (roughness ≤ 1, \
             lacunarity ≤ 16, |offset| ≤ 4, |gain| ≤ 16, |scale| ≤ 1000) so that 15 octaves \
             stay finite in f32 (Blender overflows to inf or NaN past them); coordinates past \
             100 000 wrap (Blender's own precision guard), so scale·lacunarity^detail·|vector| \
             beyond about 1e7 reads noise from coarsely rounded coordinates.",
        )
        .input(
            In::vec3("vector", [0.0, 0.0, 0.0])
                .range(-10.0, 10.0)
                .doc("Where to evaluate (link geometry.position, or uv through a combine)."),
        )
        .input(
            In::float("w", 0.0)
                .range(-10.0, 10.0)
                .doc("The fourth coordinate (1D: the only one; 4D: animates the noise)."),
        )
        .input(
            In::float("scale", 5.0)
                .range(0.0, 50.0)
                .hard(-1.0e3, 1.0e3)
                .doc("Multiplies vector and w."),
        )
        .input(
            In::float("detail", 2.0)
                .range(0.0, 15.0)
                .hard(0.0, 15.0)
                .doc("Octaves beyond the first; a fraction blends in the last octave (Blender clamps it to [0, 15])."),
        )
        .input(
            In::float("roughness", 0.5)
                .range(0.0, 1.0)
                .hard(0.0, 1.0)
                .doc("Amplitude ratio between octaves (Blender allows more; see the node's limits)."),
        )
        .input(
            In::float("lacunarity", 2.0)
                .range(0.0, 5.0)
                .hard(0.0, 16.0)
                .doc("Frequency ratio between octaves."),
        )
        .input(
            In::float("offset", 0.0)
                .range(-1.0, 4.0)
                .hard(-4.0, 4.0)
                .doc("Added to each octave (ridged, hybrid and hetero terrain only)."),
        )
        .input(
            In::float("gain", 1.0)
                .range(0.0, 10.0)
                .hard(-16.0, 16.0)
                .doc("Weight feedback between octaves (ridged and hybrid only)."),
        )
        .input(
            In::float("distortion", 0.0)
                .range(-10.0, 10.0)
                .hard(-1.0e4, 1.0e4)
                .doc("Strength of the noise added to the coordinates first."),
        )
        .input(In::choice("dimensions", DIMENSIONS, 2).doc("1D (w), 2D (vector.xy), 3D (vector) or 4D (vector, w)."))
        .input(In::choice("type", TYPES, 3).doc("Blender's noise types; fbm is the default."))
        .input(In::boolean("normalize", true).doc("fBm only: remap to [0, 1] (else about [−1, 1] summed)."))
        .output(Out::float("fac").doc("The fractal noise (fBm normalised: in [0, 1], 0.5 on average)."))
        .output(Out::color("color").doc("fac and two more channels at seeded offsets."))
        .wgsl(NOISE_TEXTURE_WGSL)
        .wgsl_constant_inputs(&["dimensions", "type", "normalize"])
        // The written type calls its fractal alone (the others are left out of the module).
        .wgsl_per_choice(
            "type",
            &[],
            TYPES.iter().map(|&choice| WgslChoice {
                choice,
                helpers: &[],
                tables: &[],
            }),
        )
        .wgsl_uses(&[BLENDER_NOISE_WGSL, HASH_FLOATS_WGSL])
        .hard_case("lattice points", &[("vector", v3([1.0, 2.0, 3.0])), ("scale", f(1.0))])
        .hard_case("negative coordinates", &[("vector", v3([-7.3, -0.5, -9.9])), ("scale", f(3.7))])
        .hard_case(
            "past the 100 000 wrap",
            &[("vector", v3([99_999.5, -123_456.7, 3.0])), ("scale", f(1.0))],
        )
        .hard_case("huge scale", &[("vector", v3([0.3, 0.7, -0.2])), ("scale", f(1000.0)), ("detail", f(15.0))])
        .hard_case("zero scale", &[("scale", f(0.0))])
        .hard_case("roughness 0", &[("vector", v3([0.3, 0.7, -0.2])), ("roughness", f(0.0)), ("detail", f(8.0))])
        .hard_case(
            "ridged, every option at its edge",
            &[("vector", v3([0.3, 0.7, -0.2])), ("type", i(1)), ("detail", f(15.0)), ("gain", f(16.0)), ("offset", f(4.0))],
        )
        .hard_case(
            "hetero terrain, large offset",
            &[("vector", v3([0.3, 0.7, -0.2])), ("type", i(4)), ("detail", f(15.0)), ("offset", f(4.0)), ("roughness", f(1.0))],
        )
        .hard_case("4D, strong distortion", &[("dimensions", i(3)), ("w", f(-3.3)), ("distortion", f(1.0e4))])
        .compute(noise_texture),
        NodeType::new(
            "white_noise",
            Category::Texture,
            "Blender's White Noise Texture: a random value and colour per input value, no interpolation.",
        )
        .source(
            "Blender 4.x White Noise Texture (svm_node_tex_white_noise): the lookup3 hash (Jenkins \
             2006) of the coordinates' float bits, as hash_floatN_to_float and \
             hash_floatN_to_float3. Equal inputs give equal outputs bit for bit on the CPU and \
             the GPU; −0 and +0 differ (their bits do), as in Blender.",
        )
        .input(In::vec3("vector", [0.0, 0.0, 0.0]).range(-10.0, 10.0).doc("The coordinates hashed (2D: x, y)."))
        .input(In::float("w", 0.0).range(-10.0, 10.0).doc("The fourth coordinate (1D: the only one)."))
        .input(In::choice("dimensions", DIMENSIONS, 2).doc("1D (w), 2D (vector.xy), 3D (vector) or 4D (vector, w)."))
        .output(Out::float("value").doc("A random value in [0, 1]."))
        .output(Out::color("color").doc("Three random values in [0, 1] (the first is value)."))
        .wgsl(WHITE_NOISE_WGSL)
        .wgsl_constant_inputs(&["dimensions"])
        .wgsl_uses(&[BLENDER_NOISE_WGSL, HASH_FLOATS_WGSL])
        .hard_case("zero", &[("vector", v3([0.0, 0.0, 0.0]))])
        .hard_case("negative zero", &[("vector", v3([-0.0, 0.0, -0.0]))])
        .hard_case("4D, huge", &[("vector", v3([3.0e38, -3.0e38, 1.0e-38])), ("w", f(-1.0e30)), ("dimensions", i(3))])
        .compute(white_noise),
        NodeType::new(
            "gradient_texture",
            Category::Texture,
            "Blender's Gradient Texture: linear, quadratic, easing, diagonal, spherical, quadratic sphere or radial ramps of the coordinates.",
        )
        .source(
            "Blender 4.x Gradient Texture (svm_gradient): linear x; quadratic max(x, 0)²; easing \
             3t² − 2t³ of x clamped to [0, 1]; diagonal (x + y)/2; spherical max(1 − |p|, 0) and \
             its square (quadratic sphere; 0.999999 as Blender, so that a unit vector gives 0); \
             radial atan2(y, x)/2π + ½ (atan2(0, 0) = 0, the atan2 node's rule); the result \
             clamped to [0, 1] as Blender's shader node clamps it.",
        )
        .input(In::vec3("vector", [0.0, 0.0, 0.0]).range(-2.0, 2.0).doc("The coordinates (link geometry.position or uv)."))
        .input(In::choice("type", GRADIENTS, 0).doc("The gradient's shape."))
        .output(Out::color("color").doc("fac as a grey."))
        .output(Out::float("fac").doc("The gradient in [0, 1]."))
        .wgsl(GRADIENT_TEXTURE_WGSL)
        .wgsl_constant_inputs(&["type"])
        .wgsl_uses(&[crate::nodes::math_scalar::ATAN2_HELPER_WGSL])
        .hard_case("radial at the origin", &[("type", i(6))])
        .hard_case("radial on the negative x axis", &[("vector", v3([-1.0, 0.0, 0.0])), ("type", i(6))])
        .hard_case("spherical at the origin", &[("type", i(4))])
        .hard_case("huge", &[("vector", v3([3.0e38, 3.0e38, 3.0e38])), ("type", i(5))])
        .compute(gradient_texture),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// lookup3's published check: hashword of one word 0 from initval 0 is not what we
    /// compute (Blender seeds with the length), so check the structure instead: the 3-word
    /// hash of (0, 0, 0) against the final mix written out step by step.
    #[test]
    fn the_hash_is_lookup3_final_on_blenders_initial_state() {
        let i = 0xdead_beefu32.wrapping_add(3 << 2).wrapping_add(13);
        assert_eq!(jenkins(&[0, 0, 0]), jenkins_final(i, i, i));
        assert_ne!(jenkins(&[1, 0, 0]), jenkins(&[0, 1, 0]));
    }

    #[test]
    fn lattice_points_are_zero() {
        for dims in 1..=4 {
            assert_eq!(snoise(Vec4::new(3.0, -2.0, 7.0, 1.0), dims), 0.0, "{dims}D");
        }
    }
}
