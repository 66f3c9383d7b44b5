//! Procedural textures: value and gradient noise with fBm, a checker and a 1D toon ramp.
//!
//! The noises hash integer lattice coordinates with PCG3D (Jarzynski & Olano 2020) in
//! wrapping u32 arithmetic, never `fract(sin(...))` (whose result depends on the GPU's `sin`),
//! so the CPU and WGSL versions pick the same lattice values bit for bit. A lattice
//! coordinate is ⌊x⌋ clamped to ±2147483520 (the largest f32 below 2³¹), converted to i32 and
//! reinterpreted as u32 (`as u32` in Rust, `bitcast<u32>` in WGSL). Both sides run the same
//! float operations in the same order; they differ at most by fused multiply-adds on the GPU.

use crate::node::{Category, In, NodeType, Out};
use crate::value::Value;
use glam::{Vec2, Vec3};

/// The most octaves an fBm sums (the `octaves` input is clamped to [1, this]).
pub const MAX_OCTAVES: i32 = 16;

/// The largest f32 below 2³¹: lattice coordinates are clamped to ± this before `as i32`.
const CELL_LIMIT: f32 = 2_147_483_520.0;

/// Per-octave seed step (2³² / φ), added to the hashed x coordinate so octaves differ.
const OCTAVE_SEED: u32 = 0x9E37_79B9;

/// PCG3D, a 3 × u32 → 3 × u32 hash: an LCG step per component, then two rounds of
/// cross-component multiply-adds around a xor-shift, all wrapping.
///
/// Source: Jarzynski & Olano 2020, "Hash Functions for GPU Rendering", JCGT 9(3), `pcg3d`.
#[inline]
pub fn pcg3d(v: [u32; 3]) -> [u32; 3] {
    let [mut x, mut y, mut z] = v.map(|c| c.wrapping_mul(1_664_525).wrapping_add(1_013_904_223));
    x = x.wrapping_add(y.wrapping_mul(z));
    y = y.wrapping_add(z.wrapping_mul(x));
    z = z.wrapping_add(x.wrapping_mul(y));
    x ^= x >> 16;
    y ^= y >> 16;
    z ^= z >> 16;
    x = x.wrapping_add(y.wrapping_mul(z));
    y = y.wrapping_add(z.wrapping_mul(x));
    z = z.wrapping_add(x.wrapping_mul(y));
    [x, y, z]
}

/// WGSL of [`pcg3d`] (u32 arithmetic wraps in WGSL).
const PCG3D_WGSL: &str = r#"
fn mg_pcg3d(p: vec3<u32>) -> vec3<u32> {
    var v = p * 1664525u + 1013904223u;
    v.x = v.x + v.y * v.z;
    v.y = v.y + v.z * v.x;
    v.z = v.z + v.x * v.y;
    v = v ^ (v >> vec3<u32>(16u));
    v.x = v.x + v.y * v.z;
    v.y = v.y + v.z * v.x;
    v.z = v.z + v.x * v.y;
    return v;
}
"#;

/// The lattice coordinate of an integral-valued float: clamped to ±2147483520, as i32.
#[inline]
pub fn cell(x: f32) -> i32 {
    x.clamp(-CELL_LIMIT, CELL_LIMIT) as i32
}

/// WGSL of [`cell`].
const CELL_WGSL: &str = r#"
fn mg_noise_cell(x: f32) -> i32 {
    return i32(clamp(x, -2147483520.0, 2147483520.0));
}
"#;

/// The PCG3D hash of lattice point (x, y, z) for octave seed `seed` (added to x, wrapping).
#[inline]
fn lattice(x: i32, y: i32, z: i32, seed: u32) -> [u32; 3] {
    pcg3d([(x as u32).wrapping_add(seed), y as u32, z as u32])
}

/// Perlin's quintic fade `6t⁵ − 15t⁴ + 10t³`, written `t·t·t·(t·(t·6 − 15) + 10)`.
///
/// Source: Perlin 2002, "Improving Noise", SIGGRAPH (the fade curve).
#[inline]
pub fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// `a + (b − a)·t`, the interpolation both sides spell out.
#[inline]
fn lerp(a: Vec3, b: Vec3, t: f32) -> Vec3 {
    a + (b - a) * t
}

/// The top 24 bits of a hash as a float in [0, 1) (exact: `(h >> 8) · 2⁻²⁴`).
#[inline]
fn unit(h: u32) -> f32 {
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// Helpers shared by both noises: the fade and the lerp.
const FADE_WGSL: &str = r#"
fn mg_noise_fade(t: vec3<f32>) -> vec3<f32> {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

fn mg_noise_lerp(a: vec3<f32>, b: vec3<f32>, t: f32) -> vec3<f32> {
    return a + (b - a) * t;
}
"#;

/// Trilinear interpolation of eight corner values with weights `u`: along x, then y, then z.
#[inline]
fn trilinear(c: impl Fn(i32, i32, i32) -> Vec3, u: Vec3) -> Vec3 {
    let x00 = lerp(c(0, 0, 0), c(1, 0, 0), u.x);
    let x10 = lerp(c(0, 1, 0), c(1, 1, 0), u.x);
    let x01 = lerp(c(0, 0, 1), c(1, 0, 1), u.x);
    let x11 = lerp(c(0, 1, 1), c(1, 1, 1), u.x);
    let y0 = lerp(x00, x10, u.y);
    let y1 = lerp(x01, x11, u.y);
    lerp(y0, y1, u.z)
}

/// One octave of three-channel value noise at `q`: the lattice values (the three PCG3D
/// outputs as [0, 1) floats) interpolated trilinearly with the quintic fade.
///
/// Source: Perlin 1985, "An Image Synthesizer" (lattice noise), with Perlin 2002's fade.
pub fn value_octave(q: Vec3, seed: u32) -> Vec3 {
    let c = q.floor();
    let f = q - c;
    let (ix, iy, iz) = (cell(c.x), cell(c.y), cell(c.z));
    let u = Vec3::new(fade(f.x), fade(f.y), fade(f.z));
    trilinear(
        |dx, dy, dz| {
            let h = lattice(ix + dx, iy + dy, iz + dz, seed);
            Vec3::new(unit(h[0]), unit(h[1]), unit(h[2]))
        },
        u,
    )
}

/// WGSL of [`value_octave`].
const VALUE_OCTAVE_WGSL: &str = r#"
fn mg_noise_value_corner(i: vec3<i32>, seed: u32) -> vec3<f32> {
    let b = bitcast<vec3<u32>>(i);
    let h = mg_pcg3d(vec3<u32>(b.x + seed, b.y, b.z));
    return vec3<f32>(h >> vec3<u32>(8u)) * (1.0 / 16777216.0);
}

fn mg_noise_value_octave(q: vec3<f32>, seed: u32) -> vec3<f32> {
    let c = floor(q);
    let f = q - c;
    let i = vec3<i32>(mg_noise_cell(c.x), mg_noise_cell(c.y), mg_noise_cell(c.z));
    let u = mg_noise_fade(f);
    let x00 = mg_noise_lerp(mg_noise_value_corner(i, seed), mg_noise_value_corner(i + vec3<i32>(1, 0, 0), seed), u.x);
    let x10 = mg_noise_lerp(mg_noise_value_corner(i + vec3<i32>(0, 1, 0), seed), mg_noise_value_corner(i + vec3<i32>(1, 1, 0), seed), u.x);
    let x01 = mg_noise_lerp(mg_noise_value_corner(i + vec3<i32>(0, 0, 1), seed), mg_noise_value_corner(i + vec3<i32>(1, 0, 1), seed), u.x);
    let x11 = mg_noise_lerp(mg_noise_value_corner(i + vec3<i32>(0, 1, 1), seed), mg_noise_value_corner(i + vec3<i32>(1, 1, 1), seed), u.x);
    let y0 = mg_noise_lerp(x00, x10, u.y);
    let y1 = mg_noise_lerp(x01, x11, u.y);
    return mg_noise_lerp(y0, y1, u.z);
}
"#;

/// Perlin's improved gradient: the top 4 bits of `hash` pick one of the 12 cube-edge
/// directions (4 of them twice) and return its dot product with `d`.
///
/// Source: Perlin 2002, "Improving Noise", SIGGRAPH, `grad()`.
#[inline]
pub fn grad(hash: u32, d: Vec3) -> f32 {
    let h = hash >> 28;
    let u = if h < 8 { d.x } else { d.y };
    let v = if h < 4 {
        d.y
    } else if h == 12 || h == 14 {
        d.x
    } else {
        d.z
    };
    (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
}

/// One octave of three-channel gradient noise at `q`, each channel in about [−1, 1]: per
/// lattice corner, the three PCG3D outputs pick three gradients ([`grad`]) dotted with the
/// offset from the corner; interpolated trilinearly with the quintic fade.
///
/// Source: Perlin 2002, "Improving Noise", SIGGRAPH (gradients and fade), lattice hashed by
/// PCG3D instead of a permutation table.
pub fn gradient_octave(q: Vec3, seed: u32) -> Vec3 {
    let c = q.floor();
    let f = q - c;
    let (ix, iy, iz) = (cell(c.x), cell(c.y), cell(c.z));
    let u = Vec3::new(fade(f.x), fade(f.y), fade(f.z));
    trilinear(
        |dx, dy, dz| {
            let h = lattice(ix + dx, iy + dy, iz + dz, seed);
            let d = f - Vec3::new(dx as f32, dy as f32, dz as f32);
            Vec3::new(grad(h[0], d), grad(h[1], d), grad(h[2], d))
        },
        u,
    )
}

/// WGSL of [`grad`] and [`gradient_octave`].
const GRADIENT_OCTAVE_WGSL: &str = r#"
fn mg_noise_grad(hash: u32, d: vec3<f32>) -> f32 {
    let h = hash >> 28u;
    let u = select(d.y, d.x, h < 8u);
    let v = select(select(d.z, d.x, h == 12u || h == 14u), d.y, h < 4u);
    return select(-u, u, (h & 1u) == 0u) + select(-v, v, (h & 2u) == 0u);
}

fn mg_noise_gradient_corner(i: vec3<i32>, o: vec3<i32>, f: vec3<f32>, seed: u32) -> vec3<f32> {
    let b = bitcast<vec3<u32>>(i + o);
    let h = mg_pcg3d(vec3<u32>(b.x + seed, b.y, b.z));
    let d = f - vec3<f32>(o);
    return vec3<f32>(mg_noise_grad(h.x, d), mg_noise_grad(h.y, d), mg_noise_grad(h.z, d));
}

fn mg_noise_gradient_octave(q: vec3<f32>, seed: u32) -> vec3<f32> {
    let c = floor(q);
    let f = q - c;
    let i = vec3<i32>(mg_noise_cell(c.x), mg_noise_cell(c.y), mg_noise_cell(c.z));
    let u = mg_noise_fade(f);
    let x00 = mg_noise_lerp(mg_noise_gradient_corner(i, vec3<i32>(0, 0, 0), f, seed), mg_noise_gradient_corner(i, vec3<i32>(1, 0, 0), f, seed), u.x);
    let x10 = mg_noise_lerp(mg_noise_gradient_corner(i, vec3<i32>(0, 1, 0), f, seed), mg_noise_gradient_corner(i, vec3<i32>(1, 1, 0), f, seed), u.x);
    let x01 = mg_noise_lerp(mg_noise_gradient_corner(i, vec3<i32>(0, 0, 1), f, seed), mg_noise_gradient_corner(i, vec3<i32>(1, 0, 1), f, seed), u.x);
    let x11 = mg_noise_lerp(mg_noise_gradient_corner(i, vec3<i32>(0, 1, 1), f, seed), mg_noise_gradient_corner(i, vec3<i32>(1, 1, 1), f, seed), u.x);
    let y0 = mg_noise_lerp(x00, x10, u.y);
    let y1 = mg_noise_lerp(x01, x11, u.y);
    return mg_noise_lerp(y0, y1, u.z);
}
"#;

/// Fractional Brownian motion: `Σ gainᵏ · octave(p · scale · lacunarityᵏ, k) / Σ gainᵏ` over
/// k < octaves (clamped to [1, [`MAX_OCTAVES`]]); the position and amplitude are multiplied
/// up octave by octave, never raised to a power, so both sides round alike.
///
/// Source: Musgrave, in Ebert et al., "Texturing & Modeling: A Procedural Approach" (fBm).
#[inline]
fn fbm(
    p: Vec3,
    scale: f32,
    octaves: i32,
    lacunarity: f32,
    gain: f32,
    octave: fn(Vec3, u32) -> Vec3,
) -> Vec3 {
    let n = octaves.clamp(1, MAX_OCTAVES);
    let mut q = p * scale;
    let mut amp = 1.0f32;
    let mut sum = Vec3::ZERO;
    let mut total = 0.0f32;
    for o in 0..n {
        sum += octave(q, (o as u32).wrapping_mul(OCTAVE_SEED)) * amp;
        total += amp;
        q *= lacunarity;
        amp *= gain;
    }
    sum / total
}

/// fBm value noise: `(value, color)`, color three decorrelated channels in [0, 1] and value
/// its first channel. Gains are clamped to be non-negative, so the sum of weights is ≥ 1.
///
/// Source: Perlin 1985 lattice noise with Perlin 2002's quintic fade, PCG3D lattice hash
/// (Jarzynski & Olano 2020), fBm (Musgrave, Texturing & Modeling).
pub fn noise_value(p: Vec3, scale: f32, octaves: i32, lacunarity: f32, gain: f32) -> (f32, Vec3) {
    let c = fbm(p, scale, octaves, lacunarity, gain.max(0.0), value_octave)
        .clamp(Vec3::ZERO, Vec3::ONE);
    (c.x, c)
}

/// fBm gradient noise remapped to [0, 1]: `clamp(0.5 + 0.5 n, 0, 1)` per channel, n the fBm
/// of [`gradient_octave`]; returns `(value, color)`, value the first channel.
///
/// Source: Perlin 2002, "Improving Noise" (gradients and fade), PCG3D lattice hash
/// (Jarzynski & Olano 2020), fBm (Musgrave, Texturing & Modeling).
pub fn noise_gradient(
    p: Vec3,
    scale: f32,
    octaves: i32,
    lacunarity: f32,
    gain: f32,
) -> (f32, Vec3) {
    let n = fbm(
        p,
        scale,
        octaves,
        lacunarity,
        gain.max(0.0),
        gradient_octave,
    );
    let c = (Vec3::splat(0.5) + n * 0.5).clamp(Vec3::ZERO, Vec3::ONE);
    (c.x, c)
}

/// WGSL of [`noise_value`]; `$OCTAVE` is replaced by the octave function.
const NOISE_VALUE_WGSL: &str = r#"
fn $fn(p: vec3<f32>, scale: f32, octaves: i32, lacunarity: f32, gain: f32) -> $out {
    let n = clamp(octaves, 1, 16);
    let g = max(gain, 0.0);
    var q = p * scale;
    var amp = 1.0;
    var sum = vec3<f32>(0.0);
    var total = 0.0;
    for (var o = 0; o < n; o = o + 1) {
        sum = sum + mg_noise_value_octave(q, u32(o) * 0x9E3779B9u) * amp;
        total = total + amp;
        q = q * lacunarity;
        amp = amp * g;
    }
    let c = clamp(sum / total, vec3<f32>(0.0), vec3<f32>(1.0));
    return $out(c.x, c);
}
"#;

/// WGSL of [`noise_gradient`].
const NOISE_GRADIENT_WGSL: &str = r#"
fn $fn(p: vec3<f32>, scale: f32, octaves: i32, lacunarity: f32, gain: f32) -> $out {
    let n = clamp(octaves, 1, 16);
    let g = max(gain, 0.0);
    var q = p * scale;
    var amp = 1.0;
    var sum = vec3<f32>(0.0);
    var total = 0.0;
    for (var o = 0; o < n; o = o + 1) {
        sum = sum + mg_noise_gradient_octave(q, u32(o) * 0x9E3779B9u) * amp;
        total = total + amp;
        q = q * lacunarity;
        amp = amp * g;
    }
    let c = clamp(vec3<f32>(0.5) + (sum / total) * 0.5, vec3<f32>(0.0), vec3<f32>(1.0));
    return $out(c.x, c);
}
"#;

/// A checkerboard: `(color, mask)`, mask 1 (colour b) where ⌊u·scale⌋ + ⌊v·scale⌋ is odd,
/// else 0 (colour a); the cell [0, 1/scale)² holds colour a.
///
/// Source: the classic procedural checker (Ebert et al., Texturing & Modeling, ch. 2), on
/// integer cell indices (wrapping i32 sum) so both sides agree on cell edges.
pub fn checker(uv: Vec2, scale: f32, color_a: Vec3, color_b: Vec3) -> (Vec3, f32) {
    let ix = cell((uv.x * scale).floor());
    let iy = cell((uv.y * scale).floor());
    if ix.wrapping_add(iy) & 1 != 0 {
        (color_b, 1.0)
    } else {
        (color_a, 0.0)
    }
}

/// WGSL of [`checker`] (i32 addition wraps in WGSL).
const CHECKER_WGSL: &str = r#"
fn $fn(uv: vec2<f32>, scale: f32, color_a: vec3<f32>, color_b: vec3<f32>) -> $out {
    let ix = mg_noise_cell(floor(uv.x * scale));
    let iy = mg_noise_cell(floor(uv.y * scale));
    let odd = ((ix + iy) & 1) != 0;
    return $out(select(color_a, color_b, odd), select(0.0, 1.0, odd));
}
"#;

/// The most bands of a [`ramp`].
pub const MAX_STEPS: i32 = 256;

/// A 1D toon ramp: `(color, level)`. x (clamped to [0, 1]) is split into `steps` equal bands
/// (clamped to [1, 256]), band k of n flat at level k/(n − 1) between `color_dark` (level 0)
/// and `color_light` (level 1); one band is `color_light` everywhere. `softness` in [0, 1]
/// smooths each band edge with a smoothstep over that fraction of a band, centred on the edge
/// (0: hard edges, 1: edges blend across whole bands).
///
/// Source: Lake, Marshall, Harris & Blackstein 2000, "Stylized rendering techniques for
/// scalable real-time 3D animation" (NPAR; hard shading from a 1D texture indexed by N·L);
/// seed 004's toon ramp (seed 004, Environment-adaptive real-time cartoon water, 2012: `ramp(dot(n, l))`, a 1D texture of discrete steps).
pub fn ramp(x: f32, steps: i32, color_dark: Vec3, color_light: Vec3, softness: f32) -> (Vec3, f32) {
    let n = steps.clamp(1, MAX_STEPS);
    if n == 1 {
        return (color_light, 1.0);
    }
    let nf = n as f32;
    let y = x.clamp(0.0, 1.0) * nf;
    // The band edge nearest y (edges at 1 … n − 1, in band units).
    let j = (y + 0.5).floor().clamp(1.0, nf - 1.0);
    let h = 0.5 * softness.clamp(0.0, 1.0);
    let e0 = j - h;
    let e1 = j + h;
    let mut s = if y >= j { 1.0 } else { 0.0 };
    if e1 > e0 {
        let t = ((y - e0) / (e1 - e0)).clamp(0.0, 1.0);
        s = t * t * (3.0 - 2.0 * t);
    }
    let level = ((j - 1.0) + s) / (nf - 1.0);
    (color_dark + (color_light - color_dark) * level, level)
}

/// WGSL of [`ramp`].
const RAMP_WGSL: &str = r#"
fn $fn(x: f32, steps: i32, color_dark: vec3<f32>, color_light: vec3<f32>, softness: f32) -> $out {
    let n = clamp(steps, 1, 256);
    if (n == 1) {
        return $out(color_light, 1.0);
    }
    let nf = f32(n);
    let y = clamp(x, 0.0, 1.0) * nf;
    let j = clamp(floor(y + 0.5), 1.0, nf - 1.0);
    let h = 0.5 * clamp(softness, 0.0, 1.0);
    let e0 = j - h;
    let e1 = j + h;
    var s = select(0.0, 1.0, y >= j);
    if (e1 > e0) {
        let t = clamp((y - e0) / (e1 - e0), 0.0, 1.0);
        s = t * t * (3.0 - 2.0 * t);
    }
    let level = ((j - 1.0) + s) / (nf - 1.0);
    return $out(color_dark + (color_light - color_dark) * level, level);
}
"#;

/// The inputs both noise nodes share.
fn noise_inputs(t: NodeType) -> NodeType {
    t.input(
        In::vec3("p", [0.0, 0.0, 0.0])
            .range(-100.0, 100.0)
            .unit("m")
            .doc("Position to evaluate at (link geometry.position)."),
    )
    .input(
        In::float("scale", 1.0)
            .range(0.1, 20.0)
            .hard(0.0, 1000.0)
            .unit("1/m")
            .doc("Lattice cells per unit of p in the first octave."),
    )
    .input(
        In::int("octaves", 4)
            .range(1.0, 8.0)
            .hard(1.0, MAX_OCTAVES as f32)
            .doc("Number of octaves summed (fBm)."),
    )
    .input(
        In::float("lacunarity", 2.0)
            .range(1.0, 4.0)
            .hard(1.0, 8.0)
            .doc("Frequency ratio between successive octaves."),
    )
    .input(
        In::float("gain", 0.5)
            .range(0.0, 1.0)
            .hard(0.0, 1.0)
            .doc("Amplitude ratio between successive octaves."),
    )
}

/// The hard cases both noise nodes share.
fn noise_hard_cases(t: NodeType) -> NodeType {
    let f = Value::float;
    let v3 = Value::vec3;
    let i = Value::int;
    t.hard_case(
        "negative coordinates",
        &[("p", v3([-37.3, -0.5, -99.9])), ("scale", f(3.7))],
    )
    .hard_case(
        "lattice points",
        &[("p", v3([3.0, -2.0, 7.0])), ("scale", f(1.0))],
    )
    .hard_case(
        "lattice points in every octave",
        &[
            ("p", v3([-5.0, 0.0, 12.0])),
            ("scale", f(1.0)),
            ("octaves", i(8)),
        ],
    )
    .hard_case(
        "huge scale: coordinates past 2^31 clamp",
        &[
            ("p", v3([99.7, -100.0, 42.1])),
            ("scale", f(1000.0)),
            ("octaves", i(MAX_OCTAVES)),
            ("lacunarity", f(8.0)),
        ],
    )
    .hard_case(
        "zero scale",
        &[("p", v3([5.5, -3.25, 1.0])), ("scale", f(0.0))],
    )
    .hard_case(
        "gain 0: first octave only",
        &[
            ("p", v3([1.3, 2.7, -0.4])),
            ("gain", f(0.0)),
            ("octaves", i(8)),
        ],
    )
    .hard_case(
        "gain 1, lacunarity 1: equal octaves",
        &[
            ("p", v3([1.3, 2.7, -0.4])),
            ("gain", f(1.0)),
            ("lacunarity", f(1.0)),
            ("octaves", i(MAX_OCTAVES)),
        ],
    )
}

/// The texture node types.
pub fn all() -> Vec<NodeType> {
    let f = Value::float;
    let i = Value::int;
    let v2 = Value::vec2;
    vec![
        noise_hard_cases(noise_inputs(
            NodeType::new("noise_value", Category::Texture, "fBm value noise on an integer lattice hash.")
                .source(
                    "Lattice values from the PCG3D hash (Jarzynski & Olano 2020, JCGT 9(3)) of the \
                     integer cell coordinates, interpolated trilinearly with Perlin's quintic fade \
                     (Perlin 2002); fBm over octaves (Musgrave, Texturing & Modeling): \
                     Σ gainᵏ noise(p·scale·lacunarityᵏ) / Σ gainᵏ. Three decorrelated channels.",
                ),
        ))
        .output(Out::float("value").doc("Noise in [0, 1] (the colour's first channel)."))
        .output(Out::color("color").doc("Three decorrelated noise channels, each in [0, 1]."))
        .wgsl(NOISE_VALUE_WGSL)
        .wgsl_uses(&[PCG3D_WGSL, CELL_WGSL, FADE_WGSL, VALUE_OCTAVE_WGSL])
        .compute(noise_value),
        noise_hard_cases(noise_inputs(
            NodeType::new("noise_gradient", Category::Texture, "fBm Perlin gradient noise, remapped to [0, 1].")
                .source(
                    "Perlin's improved noise (Perlin 2002, \"Improving Noise\": 12 cube-edge \
                     gradients, quintic fade) with gradients picked by the PCG3D hash (Jarzynski & \
                     Olano 2020) of the integer cell coordinates; fBm over octaves (Musgrave, \
                     Texturing & Modeling); output clamp(0.5 + 0.5 n, 0, 1) per channel.",
                ),
        ))
        .output(Out::float("value").doc("Noise in [0, 1], 0.5 on average (the colour's first channel)."))
        .output(Out::color("color").doc("Three decorrelated noise channels, each in [0, 1]."))
        .wgsl(NOISE_GRADIENT_WGSL)
        .wgsl_uses(&[PCG3D_WGSL, CELL_WGSL, FADE_WGSL, GRADIENT_OCTAVE_WGSL])
        .compute(noise_gradient),
        NodeType::new("checker", Category::Texture, "A checkerboard of two colours.")
            .source(
                "mask = (⌊u·scale⌋ + ⌊v·scale⌋) mod 2 on integer cells (the classic procedural \
                 checker, Ebert et al., Texturing & Modeling); the cell [0, 1/scale)² has colour a.",
            )
            .input(In::vec2("uv", [0.5, 0.5]).range(-2.0, 2.0).doc("Texture coordinates (link geometry.uv)."))
            .input(In::float("scale", 8.0).range(0.1, 64.0).hard(0.0, 1.0e4).doc("Squares per unit of uv."))
            .input(In::color("color_a", [0.2, 0.2, 0.2]).range(0.0, 1.0).doc("Colour of the even squares."))
            .input(In::color("color_b", [0.8, 0.8, 0.8]).range(0.0, 1.0).doc("Colour of the odd squares."))
            .output(Out::color("color").doc("The square's colour."))
            .output(Out::float("mask").doc("0 on colour a's squares, 1 on colour b's."))
            .wgsl(CHECKER_WGSL)
            .wgsl_uses(&[CELL_WGSL])
            .hard_case("negative uv", &[("uv", v2([-0.3, -1.7]))])
            .hard_case("on a cell corner", &[("uv", v2([0.25, 0.5])), ("scale", f(4.0))])
            .hard_case("huge scale", &[("uv", v2([1.9, -2.0])), ("scale", f(1.0e4))])
            .hard_case("zero scale", &[("scale", f(0.0))])
            .compute(checker),
        NodeType::new("ramp", Category::Texture, "A 1D toon ramp: x quantised into flat bands from dark to light.")
            .source(
                "Hard shading from a 1D texture indexed by N·L (Lake, Marshall, Harris & Blackstein \
                 2000, \"Stylized rendering techniques for scalable real-time 3D animation\", NPAR; \
                 seed 004's ramp(dot(n, l)), the 2012 cartoon-water paper; docs/models/README.md). x ∈ [0, 1] in `steps` equal \
                 bands, band k at level k/(steps − 1); softness smoothsteps each edge over that \
                 fraction of a band; one band is colour_light.",
            )
            .input(In::float("x", 0.5).range(-1.0, 1.0).doc("Ramp coordinate, usually N·L; clamped to [0, 1]."))
            .input(In::int("steps", 3).range(1.0, 8.0).hard(1.0, MAX_STEPS as f32).doc("Number of bands."))
            .input(In::color("color_dark", [0.1, 0.1, 0.2]).range(0.0, 1.0).doc("Colour of the darkest band (x near 0)."))
            .input(In::color("color_light", [1.0, 1.0, 1.0]).range(0.0, 1.0).doc("Colour of the lightest band (x near 1)."))
            .input(In::float("softness", 0.0).range(0.0, 1.0).hard(0.0, 1.0).doc("Width of each band edge's blend, as a fraction of a band."))
            .output(Out::color("color").doc("The band's colour."))
            .output(Out::float("level").doc("The band's level in [0, 1]: 0 darkest, 1 lightest."))
            .wgsl(RAMP_WGSL)
            .hard_case("on a band edge", &[("x", f(0.5)), ("steps", i(2))])
            .hard_case("one band", &[("steps", i(1))])
            .hard_case("many bands, full softness", &[("x", f(0.3)), ("steps", i(MAX_STEPS)), ("softness", f(1.0))])
            .hard_case("tiny softness", &[("x", f(1.0 / 3.0)), ("softness", f(1e-9))])
            .hard_case("x past both ends", &[("x", f(-1.0))])
            .compute(ramp),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pcg3d_matches_the_reference_values() {
        // Computed by hand from the JCGT listing for (0, 0, 0): v = 1013904223 each, then
        // the two rounds; pinned so a change to the hash is noticed.
        let h = pcg3d([0, 0, 0]);
        let v = 1_013_904_223u32;
        let mut x = v.wrapping_add(v.wrapping_mul(v));
        let mut y = v.wrapping_add(v.wrapping_mul(x));
        let mut z = v.wrapping_add(x.wrapping_mul(y));
        x ^= x >> 16;
        y ^= y >> 16;
        z ^= z >> 16;
        x = x.wrapping_add(y.wrapping_mul(z));
        y = y.wrapping_add(z.wrapping_mul(x));
        z = z.wrapping_add(x.wrapping_mul(y));
        assert_eq!(h, [x, y, z]);
        assert_ne!(pcg3d([1, 0, 0]), pcg3d([0, 1, 0]));
        // Negative coordinates hash as their two's-complement bits.
        assert_eq!(lattice(-1, 0, 0, 0), pcg3d([u32::MAX, 0, 0]));
    }

    #[test]
    fn value_noise_interpolates_lattice_values() {
        // At a lattice point the octave is the corner's hash value.
        let h = lattice(3, -2, 7, 0);
        let at = value_octave(Vec3::new(3.0, -2.0, 7.0), 0);
        assert_eq!(at, Vec3::new(unit(h[0]), unit(h[1]), unit(h[2])));
        // Half way along x between two lattice points: their mean (fade(0.5) = 0.5).
        let a = lattice(3, -2, 7, 0);
        let b = lattice(4, -2, 7, 0);
        let mid = value_octave(Vec3::new(3.5, -2.0, 7.0), 0);
        assert!((mid.x - 0.5 * (unit(a[0]) + unit(b[0]))).abs() < 1e-6);
        // Continuity across a cell boundary.
        let l = value_octave(Vec3::new(4.0 - 1e-4, 0.3, 0.6), 0);
        let r = value_octave(Vec3::new(4.0, 0.3, 0.6), 0);
        assert!((l - r).abs().max_element() < 1e-3, "{l} vs {r}");
    }

    #[test]
    fn gradient_noise_is_zero_at_lattice_points_and_spans_its_range() {
        // One octave of gradient noise is 0 at lattice points: 0.5 after the remap.
        let (v, c) = noise_gradient(Vec3::new(3.0, -2.0, 7.0), 1.0, 1, 2.0, 0.5);
        assert_eq!(v, 0.5);
        assert_eq!(c, Vec3::splat(0.5));
        let (mut lo, mut hi, mut mean) = (1.0f32, 0.0f32, 0.0f64);
        let n = 20_000;
        for k in 0..n {
            let p = Vec3::new(
                k as f32 * 0.137,
                (k % 97) as f32 * 0.291,
                (k % 13) as f32 * 0.53,
            );
            let (v, c) = noise_gradient(p, 1.0, 1, 2.0, 0.5);
            assert_eq!(v, c.x);
            lo = lo.min(v);
            hi = hi.max(v);
            mean += v as f64;
        }
        mean /= n as f64;
        assert!(lo < 0.15 && hi > 0.85, "range [{lo}, {hi}]");
        assert!((mean - 0.5).abs() < 0.02, "mean {mean}");
    }

    #[test]
    fn value_noise_stays_in_range_and_is_not_constant() {
        let (mut lo, mut hi) = (1.0f32, 0.0f32);
        for k in 0..5000 {
            let p = Vec3::new(k as f32 * -0.173, k as f32 * 0.0311, 2.0);
            let (v, c) = noise_value(p, 2.5, 5, 2.0, 0.5);
            assert!((0.0..=1.0).contains(&v) && c.min_element() >= 0.0 && c.max_element() <= 1.0);
            lo = lo.min(v);
            hi = hi.max(v);
        }
        assert!(lo < 0.3 && hi > 0.7, "range [{lo}, {hi}]");
        // The channels differ.
        let (_, c) = noise_value(Vec3::new(0.3, 0.7, 0.1), 1.0, 1, 2.0, 0.5);
        assert!(c.x != c.y && c.y != c.z, "{c}");
        // Octaves are clamped: 100 octaves equal 16.
        let p = Vec3::new(0.31, -0.77, 5.1);
        assert_eq!(
            noise_value(p, 1.0, 100, 2.0, 0.5),
            noise_value(p, 1.0, 16, 2.0, 0.5)
        );
        assert_eq!(
            noise_value(p, 1.0, -3, 2.0, 0.5),
            noise_value(p, 1.0, 1, 2.0, 0.5)
        );
        // Gain 0 keeps the first octave only.
        assert_eq!(
            noise_value(p, 1.0, 8, 2.0, 0.0),
            noise_value(p, 1.0, 1, 2.0, 0.5)
        );
    }

    #[test]
    fn checker_alternates_and_starts_with_colour_a() {
        let a = Vec3::splat(0.0);
        let b = Vec3::splat(1.0);
        assert_eq!(checker(Vec2::new(0.1, 0.1), 4.0, a, b), (a, 0.0));
        assert_eq!(checker(Vec2::new(0.3, 0.1), 4.0, a, b), (b, 1.0));
        assert_eq!(checker(Vec2::new(0.3, 0.3), 4.0, a, b), (a, 0.0));
        // Edges belong to the cell above / to the right: u = 0.25 is cell 1.
        assert_eq!(checker(Vec2::new(0.25, 0.0), 4.0, a, b), (b, 1.0));
        // Negative cells continue the pattern: cell (−1, 0) is odd.
        assert_eq!(checker(Vec2::new(-0.1, 0.1), 4.0, a, b), (b, 1.0));
        assert_eq!(checker(Vec2::new(-0.1, -0.1), 4.0, a, b), (a, 0.0));
    }

    #[test]
    fn ramp_quantises_into_bands() {
        let d = Vec3::ZERO;
        let l = Vec3::ONE;
        let level = |x: f32, n: i32, s: f32| ramp(x, n, d, l, s).1;
        // Two bands: Lake et al.'s hard shading.
        assert_eq!(level(0.49, 2, 0.0), 0.0);
        assert_eq!(level(0.5, 2, 0.0), 1.0);
        // Three bands at 0, 0.5, 1.
        assert_eq!(level(0.0, 3, 0.0), 0.0);
        assert_eq!(level(0.2, 3, 0.0), 0.0);
        assert_eq!(level(0.4, 3, 0.0), 0.5);
        assert_eq!(level(0.6, 3, 0.0), 0.5);
        assert_eq!(level(0.7, 3, 0.0), 1.0);
        assert_eq!(level(1.0, 3, 0.0), 1.0);
        // Clamped outside [0, 1].
        assert_eq!(level(-0.5, 3, 0.0), 0.0);
        assert_eq!(level(1.5, 3, 0.0), 1.0);
        // One band: light everywhere; steps clamped to ≥ 1.
        assert_eq!(ramp(0.0, 1, d, l, 0.0), (l, 1.0));
        assert_eq!(ramp(0.0, -4, d, l, 0.0), (l, 1.0));
        // Softness: the edge at x = 0.5 (two bands) blends over x ∈ [0.25, 0.75] at s = 1,
        // half way at the edge, flat away from it.
        assert_eq!(level(0.5, 2, 1.0), 0.5);
        assert_eq!(level(0.25, 2, 1.0), 0.0);
        assert_eq!(level(0.75, 2, 1.0), 1.0);
        assert!((level(0.375, 2, 1.0) - 0.15625).abs() < 1e-6);
        assert_eq!(level(0.45, 2, 0.1), 0.0);
        // Colour follows the level.
        let (c, _) = ramp(
            0.4,
            3,
            Vec3::new(0.2, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            0.0,
        );
        assert!(
            (c - Vec3::new(0.6, 0.5, 0.0)).abs().max_element() < 1e-6,
            "{c}"
        );
        // Every level is monotone in x.
        let mut last = 0.0;
        for k in 0..=1000 {
            let v = level(k as f32 / 1000.0, 5, 0.3);
            assert!(v >= last, "not monotone at {k}");
            last = v;
        }
    }
}
