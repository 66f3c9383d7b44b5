//! The parity suites' shared parts: the bounds, the seeded node samples, the graph sample
//! grid, and the comparison. tests/gpu/gpu_parity.rs runs them against a GPU; tests/worst_gpu.rs
//! against the CPU executor in its worst-conformant-GPU mode (`matgraph::precision`).

use super::rng::Rng;
use matgraph::node::{Evaluation, NodeType};
use matgraph::{
    Attribute, Graph, OutputBatch, ParamValues, Plan, PlanOptions, Registry, SampleBatch,
    SocketType, Value,
};
use std::path::PathBuf;

/// Absolute part of the default bound.
pub const ABS: f64 = 1e-5;
/// Relative part of the default bound.
pub const REL: f64 = 1e-4;

/// Node types allowed a looser bound: (type name, absolute, relative, why).
pub const LOOSE: &[(&str, f64, f64, &str)] = &[
    (
        "fresnel_dielectric",
        3e-4,
        1e-3,
        "near a critical angle cos²θt = (1 − η)(1 + η) + (η cosθ)² cancels, and backends round \
         its terms differently (llvmpipe's GL contracts them into FMAs): the square root \
         amplifies a 1-ulp difference to up to 3e-4 there (docs/models/optics.md)",
    ),
    (
        "skin_efresnel",
        3e-4,
        1e-3,
        "the same cos²θt as fresnel_dielectric, in its Fresnel term and its refracted direction",
    ),
    (
        "gerstner_waves",
        1e-4,
        1e-3,
        "the phase θ = k D·x − ω t + φ spans up to |x|/λ + t/T ≈ 10³ cycles over the hard ranges \
         (|x| ≤ 50 m, λ ≥ 0.1 m), where one ulp is 6e-5 cycles; backends round D·x and t·f \
         differently (contraction into FMAs), and sin/cos turn that into offset errors of Q·a·δθ \
         (Q·a up to 100 m) and normal errors of δθ; measured 2.1e-4 at most, 62% of this bound (docs/models/toon_water.md)",
    ),
    (
        "wave_texture",
        2e-3,
        1e-4,
        "the phase n (20 rad a unit of vector·scale, plus phase_offset and distortion·fBm) \
         reaches 1.7e4 rad over the soft ranges, where one ULP of it is 2e-3 rad; a GPU fusing \
         a product into its sums (20·p + phase_offset, distortion·fBm + n, the rings' squares; \
         WGSL §15.7.5) moves n by an ULP each time, and each ULP moves the sine by up to 1e-3 \
         and the saw and triangle by ULP/2π and ULP/π: CPU − GPU differences come in whole \
         ULPs of n (lavapipe: 3e-5 to 1e-3), two allowed; the hard ranges' larger phases are \
         its CONDITIONED entry's",
    ),
    (
        "bubble_underwater",
        1e-5,
        3e-4,
        "(N·L)^sharpness has the relative condition number sharpness (≤ 256, the hard range):          the 4 ULP WGSL allows the sqrt that normalises N and L (4.8e-7 relative) become          256 × 4.8e-7 = 1.2e-4 of the streak; the worst-GPU mode measures 2.3e-4 relative          (docs/precision.md)",
    ),
];

/// Node types whose relative condition number is an input: (type name, input, k, why). The
/// relative part of such a node's bound grows by |input| · k · 2⁻²⁴ at each sample (the
/// condition number times the relative error the GPU may make in the quantity it amplifies).
pub const SCALED: &[(&str, &str, f64, &str)] = &[(
    "toon_water_shade",
    "shininess",
    32.0,
    "(N·H)^shininess has the relative condition number shininess (to 10⁴ over the hard range): \
     N·H comes from four normalised vectors (N, L, V and H), each within sqrt's 4 ULP \
     (8·2⁻²⁴ relative) of unit length on a GPU, and N and H scale it directly; the dot and the \
     sum L + V add a few roundings: 32·2⁻²⁴ in all",
)];

/// `t`'s [`SCALED`] entries as (input index, k), resolved once per node type.
fn scaled_inputs(t: &NodeType) -> Vec<(usize, f64)> {
    SCALED
        .iter()
        .filter(|s| s.0 == t.name())
        .map(|&(_, input, k, _)| {
            let j = t
                .input_index(input)
                .unwrap_or_else(|| panic!("SCALED: {} has no input '{input}'", t.name()));
            (j, k)
        })
        .collect()
}

/// `bound` at sample `i`, its relative part grown by |input| · k · 2⁻²⁴ for each of
/// `scaled` ([`scaled_inputs`]).
fn scaled_bound(
    scaled: &[(usize, f64)],
    samples: &NodeSamples,
    i: usize,
    (abs, rel): (f64, f64),
) -> (f64, f64) {
    scaled.iter().fold((abs, rel), |(abs, rel), &(j, k)| {
        let x = samples.columns[j][i].abs() as f64;
        (abs, rel + x * k * 2f64.powi(-24))
    })
}

/// Node types whose outputs are ill-conditioned or discontinuous somewhere in their ranges:
/// (type name, k, why). A component outside the bound around the CPU's value still passes when
/// it is within the bound of the range the CPU's own output spans over the sample's inputs
/// moved by at most k·2⁻²⁴ relative (the mixed forward–backward error of numerical analysis:
/// the GPU computed the right function of inputs that differ from the given ones by a few
/// roundings; [`envelope`]). The CPU's own f32 result is no closer than that to the exact
/// function there. Nodes not listed are held to the forward bound alone.
pub const CONDITIONED: &[(&str, f64, &str)] = &[
    (
        "toon_water_shade",
        4.0,
        "the ramp's bands are a step function of N·L: at a band edge (the hard case N = (1, 0, \
         0), L = (0.8, 0.6, 0), 5 steps) any rounding of the normalised vectors picks either \
         band (the highlight's amplification is its SCALED entry)",
    ),
    (
        "transmission_sphere",
        4.0,
        "from a denser outside, at the critical angle of the entry, the TIR flag and the outputs \
         it selects flip under any rounding, and near it cosθt = √(1 − η² sin²θi) has the \
         condition number 1/cos²θt",
    ),
    (
        "transmission_slab",
        8.0,
        "as transmission_sphere: the entry's TIR flag at its critical angle, and 1/cos²θt near \
         it in the path d/cosθt and the Fresnel terms. k = 8, not 4: from a denser outside the \
         path follows sin²θi = |N × V|² of the normalised vectors, whose inverseSqrt (2 ULP) \
         and products a GPU may round by more than 4 ULP of the inputs explain (seed 0x5eed0 \
         + 16·index: a sample at 1 − η² sin²θi = 5.6e-4 missed by 25% at k = 4)",
    ),
    (
        "pbr_brdf",
        4.0,
        "the GGX peak D = α²/(π(|N×H|² + α²(N·H)²)²) at roughness 0.02 (α² = 1.6e-7): one \
         rounding of N×H's components (a GPU may fuse one product, WGSL §15.7.5) moves |N×H|² by \
         a part in 10⁴ of α², and D by twice that; so do the inputs' own roundings",
    ),
    (
        "gerstner_waves",
        16.0,
        "the phase k D·x − ω t + φ reaches 10³ cycles over the hard ranges, where its own f32 \
         rounding is 1.2e-4 rad, and the offsets are Q·a (to 90 m) times its error: sqrt's 4 \
         ULP in the frequency √(g/2πλ) are λ moved by 8 ULP (16·2⁻²⁴ at most), and a fused product in the \
         phase is an ULP of t or x",
    ),
    (
        "voronoi_texture",
        64.0,
        "Worley noise is discontinuous at every cell border (F1's colour and position, F2's \
         distance past a third point, distance to edge at a vertex): where two candidate points \
         lie within a few roundings of each other either may win, and a fused product in the \
         jitter (o + hash·randomness, WGSL §15.7.5) is such a rounding; over detail octaves the \
         coordinates grow by lacunarity^detail, so the borders come closer in ULPs",
    ),
    (
        "wave_texture",
        64.0,
        "past the soft ranges the phase n reaches 3.5e5 rad (scale 1000), where an ULP is \
         0.03 rad (its LOOSE entry holds the soft ranges' 2e-3); the saw jumps at every whole \
         cycle; and the distortion's fBm reads octaves at p·detail_scale·2^detail, up to 10⁹ \
         cells, where an ULP of p moves an octave by a large part of a cell",
    ),
    (
        "rgb_curves",
        64.0,
        "a curve's points reach ±100 over the hard ranges and its monotone-cubic slopes are \
         quotients of their differences (a GPU's division is 2.5 ULP, WGSL §15.7.4), then \
         multiplied by the span between points: the worst conformant GPU moves a channel by \
         1.3e-4 of 0.5 (measured, tests/worst_gpu.rs), as a few ULPs of the points do",
    ),
    (
        "brick_texture",
        8.0,
        "the tint jumps at every row and brick edge, and the mortar at its edge where \
         mortar_smooth is 0: there a quotient (p.y/row_height, (p.x + shift)/brick_width: \
         2.5 ULP on a GPU, WGSL §15.7.4) or a product fused into x − width·brick picks either \
         side (lavapipe matches the CPU bit for bit; other GPUs need not)",
    ),
    (
        "magic_texture",
        64.0,
        "each of up to 10 rounds multiplies the colour's sensitivity to rounding by about 1.4 \
         at |distortion| 2 (the hard range's edge): at depth 10, 4 ULPs of the coordinates (a \
         product the GPU fuses into the next round's sum is one) move the colour by 6e-4 \
         typically and 0.18 at worst (f64, 20 000 samples); and the first sines' arguments reach 1.5e5 rad over the hard \
         ranges (scale 1000), where an ULP is 0.016 rad",
    ),
    (
        "thin_film",
        4.0,
        "films of 6–10 µm are 100 cycles of phase thick at 453 nm: sqrt's 4 ULP in the film's \
         cosθf move the phase by 1e-4 rad and the reflectance by its slope times that; an ULP \
         of the thickness or the angle does the same",
    ),
];

/// The relative input perturbation, in units of 2⁻²⁴, within which `node`'s outputs are
/// judged by their conditioning ([`CONDITIONED`]), if it is listed.
pub fn conditioning_for(node: &str) -> Option<f64> {
    CONDITIONED.iter().find(|c| c.0 == node).map(|c| c.1)
}

/// Seeded random perturbations [`envelope`] adds to its corners.
pub const RANDOM_PERTURBATIONS: usize = 16;

/// Per output, per component, the range `(lo, hi)` of the CPU kernel's results at sample `i`
/// with every float input lane moved by a relative `δ`, `|δ| ≤ k·2⁻²⁴` (integer, boolean and
/// choice inputs kept): the extremes of the kernel linearised over that box, found as in
/// interval arithmetic's corner method (one lane moved at a time gives the sign of each
/// output's slope in each lane; then, per output component, the two corners where every lane
/// moves with, and against, that slope), plus [`RANDOM_PERTURBATIONS`] seeded points of the
/// box for what is not linear. At a discontinuity (a band edge, a TIR flag) the slope test
/// sees the jump, and the corners reach both sides. NaN results are left out of the range.
pub fn envelope(
    t: &NodeType,
    generic: SocketType,
    samples: &NodeSamples,
    i: usize,
    k: f64,
) -> Vec<Vec<(f32, f32)>> {
    let scale = k * 2f64.powi(-24);
    let types: Vec<SocketType> = t.inputs().iter().map(|d| d.ty.resolve(generic)).collect();
    // The sample's float lanes: (input, component, value).
    let lanes: Vec<(usize, usize, f32)> = types
        .iter()
        .enumerate()
        .filter(|(_, ty)| !matches!(ty, SocketType::Int | SocketType::Bool))
        .flat_map(|(input, ty)| {
            (0..ty.width()).map(move |c| (input, c, samples.columns[input][c * samples.n + i]))
        })
        .collect();
    // Runs the kernel at the sample moved by `deltas[r][lane]`, row by row.
    let run = |deltas: &[Vec<f64>]| {
        let n = deltas.len();
        let mut columns: Vec<Vec<f32>> = types
            .iter()
            .enumerate()
            .map(|(input, ty)| {
                (0..ty.width())
                    .flat_map(|c| std::iter::repeat_n(samples.columns[input][c * samples.n + i], n))
                    .collect()
            })
            .collect();
        for (r, row) in deltas.iter().enumerate() {
            for (&(input, c, x), d) in lanes.iter().zip(row) {
                columns[input][c * n + r] = (x as f64 * (1.0 + d)) as f32;
            }
        }
        (n, run_cpu(t, generic, &NodeSamples { n, columns }))
    };
    let widths: Vec<usize> = t
        .outputs()
        .iter()
        .map(|d| d.ty.resolve(generic).width())
        .collect();
    let mut rows: Vec<Vec<f64>> = vec![vec![0.0; lanes.len()]];
    for j in 0..lanes.len() {
        let mut row = vec![0.0; lanes.len()];
        row[j] = scale;
        rows.push(row);
    }
    let mut rng = Rng(0xe7e1_0b0e ^ i as u64);
    for _ in 0..RANDOM_PERTURBATIONS {
        rows.push(
            (0..lanes.len())
                .map(|_| scale * (2.0 * rng.draw(0.0, 1.0) as f64 - 1.0))
                .collect(),
        );
    }
    let (n, first) = run(&rows);
    // Per output component, the two corners along the signs of its slopes.
    let mut corners: Vec<Vec<f64>> = Vec::new();
    for (o, &w) in widths.iter().enumerate() {
        for c in 0..w {
            let at = |r: usize| first[o][c * n + r];
            let signs: Vec<f64> = (0..lanes.len())
                .map(|j| {
                    let d = at(j + 1) - at(0);
                    if d > 0.0 {
                        1.0
                    } else if d < 0.0 {
                        -1.0
                    } else {
                        0.0
                    }
                })
                .collect();
            for s in [scale, -scale] {
                corners.push(signs.iter().map(|g| g * s).collect());
            }
        }
    }
    let (m, second) = run(&corners);
    let mut at_corner = 0;
    widths
        .iter()
        .enumerate()
        .map(|(o, &w)| {
            (0..w)
                .map(|c| {
                    let own = [at_corner, at_corner + 1];
                    at_corner += 2;
                    first[o][c * n..(c + 1) * n]
                        .iter()
                        .chain(own.iter().map(|&r| &second[o][c * m + r]))
                        .filter(|v| !v.is_nan())
                        .fold((f32::NAN, f32::NAN), |(lo, hi), &v| (v.min(lo), v.max(hi)))
                })
                .collect()
        })
        .collect()
}

/// Random samples per node type and generic type.
pub const RANDOM_SAMPLES: usize = 10_000;

/// The bound for a node type: the default or its [`LOOSE`] entry.
pub fn bound_for(node: &str) -> (f64, f64) {
    LOOSE
        .iter()
        .find(|l| l.0 == node)
        .map(|l| (l.1, l.2))
        .unwrap_or((ABS, REL))
}

/// Bounds that hold on a worst conformant GPU (tests/worst_gpu.rs) only past a node's
/// [`LOOSE`] one: (node, absolute, relative, why).
pub const WORST_GPU_LOOSE: &[(&str, f64, f64, &str)] = &[(
    "wave_texture",
    0.02,
    1e-4,
    "inside its hard ranges (scale to 1000, detail_scale to 1000 at detail 15) the phase \
     reaches 10⁵ rad, where one f32 ULP is 0.0078 rad and the triangle's slope is 1/π a \
     radian: the worst GPU's few ULPs move it by up to 0.01, and at the profile's minimum the \
     conditioned envelope (linearised corners) cannot reach below the exact value; measured \
     (session 47): 10 samples of 15 000, |Δ| ≤ 0.012 (the saw's taken on its cycle)",
)];

/// The bound for a node type on a worst conformant GPU: its [`WORST_GPU_LOOSE`] entry, else
/// [`bound_for`].
pub fn worst_gpu_bound_for(node: &str) -> (f64, f64) {
    WORST_GPU_LOOSE
        .iter()
        .find(|l| l.0 == node)
        .map(|l| (l.1, l.2))
        .unwrap_or_else(|| bound_for(node))
}

/// Whether sample `i` of `t` outputs a point of a cycle, where 0 and 1 are one value: the
/// saw profile of `wave_texture` (its `profile` input 1), compared as
/// tests/models/blender_textures.rs compares it with Blender's, modulo 1.
fn on_cycle(t: &NodeType, s: &NodeSamples, i: usize) -> bool {
    t.name() == "wave_texture"
        && t.inputs()
            .iter()
            .position(|d| d.name == "profile")
            .is_some_and(|k| s.columns[k][i] == 1.0)
}

/// Largest errors seen over a set of comparisons.
#[derive(Clone, Copy, Debug, Default)]
pub struct Errors {
    /// Components compared.
    pub compared: usize,
    /// Largest |cpu − gpu|.
    pub max_abs: f64,
    /// Largest |cpu − gpu| / |cpu| where |cpu| ≥ 1e-6.
    pub max_rel: f64,
    /// Largest error as a fraction of the bound (≤ 1 passes); for a component that passed by
    /// its conditioning ([`CONDITIONED`]), its distance from the CPU's range as that fraction.
    pub worst: f64,
    /// Components outside the bound around the CPU's value that passed by their conditioning:
    /// within the bound of the range the CPU's output spans over inputs within k·2⁻²⁴.
    pub conditioned: usize,
}

impl Errors {
    /// Compares one component; returns false when it is out of bound.
    pub fn check(&mut self, cpu: f32, gpu: f32, bound: (f64, f64)) -> bool {
        let ratio = self.measure(cpu, gpu, bound);
        self.worst = self.worst.max(ratio);
        ratio <= 1.0
    }

    /// Counts one component and its absolute and relative errors; returns |cpu − gpu| as a
    /// fraction of the bound (0 or ∞ where either side is NaN or infinite), without
    /// recording it in [`Errors::worst`].
    fn measure(&mut self, cpu: f32, gpu: f32, (abs, rel): (f64, f64)) -> f64 {
        self.compared += 1;
        if cpu.is_nan() || gpu.is_nan() {
            return if cpu.is_nan() && gpu.is_nan() {
                0.0
            } else {
                f64::INFINITY
            };
        }
        if cpu.is_infinite() || gpu.is_infinite() {
            return if cpu == gpu { 0.0 } else { f64::INFINITY };
        }
        let err = (cpu as f64 - gpu as f64).abs();
        let c = (cpu as f64).abs();
        self.max_abs = self.max_abs.max(err);
        if c >= 1e-6 {
            self.max_rel = self.max_rel.max(err / c);
        }
        err / (abs + rel * c)
    }
}

/// The distance of `gpu` from the range `[lo, hi]` as a fraction of the bound at the nearer
/// end (0 inside the range, ∞ for a NaN or an infinity outside it).
pub fn range_ratio(gpu: f32, (lo, hi): (f32, f32), (abs, rel): (f64, f64)) -> f64 {
    if gpu.is_nan() || lo.is_nan() || hi.is_nan() {
        return f64::INFINITY;
    }
    if lo <= gpu && gpu <= hi {
        return 0.0;
    }
    let end = if gpu < lo { lo } else { hi };
    if gpu.is_infinite() || end.is_infinite() {
        return f64::INFINITY;
    }
    (gpu as f64 - end as f64).abs() / (abs + rel * (end as f64).abs())
}

/// The draws these suites make from the shared seeded generator (a trait, so test binaries
/// with inherent draws of their own on [`Rng`] still build).
pub trait Draws {
    /// Uniform in [lo, hi].
    fn draw(&mut self, lo: f32, hi: f32) -> f32;
    /// Over a hard range (see the impl).
    fn draw_hard(&mut self, lo: f32, hi: f32) -> f32;
}

impl Draws for Rng {
    fn draw(&mut self, lo: f32, hi: f32) -> f32 {
        let u = (self.next() >> 40) as f64 / (1u64 << 24) as f64;
        (lo as f64 + (hi as f64 - lo as f64) * u) as f32
    }
    /// Over a hard range: uniform half the time; otherwise, where the range spans more than
    /// three decades, a log-uniform magnitude (signed where the range allows it), so that
    /// 1e-6 and 1e4 are both drawn from [0, 1e6].
    fn draw_hard(&mut self, lo: f32, hi: f32) -> f32 {
        let span = hi.abs().max(lo.abs());
        if self.next() & 1 == 0 || span < 1e3 {
            return self.draw(lo, hi);
        }
        let mag = (self.draw((span * 1e-9).ln(), span.ln())).exp();
        let x = if lo < 0.0 && self.next() & 1 == 1 {
            -mag
        } else {
            mag
        };
        x.clamp(lo, hi)
    }
}

/// Inputs of one node instance: per input, planar columns (`width × n`).
#[derive(Clone, Debug)]
pub struct NodeSamples {
    /// Samples.
    pub n: usize,
    /// Per input, planar columns.
    pub columns: Vec<Vec<f32>>,
}

/// The range random values of an input are drawn from: soft, else hard, else [-10, 10].
pub fn input_range(t: &NodeType, k: usize) -> (f32, f32) {
    let d = &t.inputs()[k];
    d.soft
        .or(d.hard)
        .map(|r| (r.min, r.max))
        .unwrap_or((-10.0, 10.0))
}

/// Random samples per node type over the hard ranges.
pub const HARD_SAMPLES: usize = 5_000;

/// The hard range of an input, if it declares one.
pub fn hard_range(t: &NodeType, k: usize) -> Option<(f32, f32)> {
    t.inputs()[k].hard.map(|r| (r.min, r.max))
}

/// Seeded random samples over the declared soft ranges, then over the hard ranges (inputs
/// without one keep their soft range), then the defaults, each input at both ends of its
/// range (others at defaults) and every hard case.
pub fn node_samples(t: &NodeType, generic: SocketType, seed: u64) -> NodeSamples {
    let inputs = t.inputs();
    let types: Vec<SocketType> = inputs.iter().map(|d| d.ty.resolve(generic)).collect();
    let defaults: Vec<Value> = (0..inputs.len())
        .map(|k| t.default_for(k, generic))
        .collect();
    let mut rows: Vec<Vec<Value>> = Vec::new();
    let mut rng = Rng(seed);
    for i in 0..RANDOM_SAMPLES + HARD_SAMPLES {
        let hard = i >= RANDOM_SAMPLES;
        let row = (0..inputs.len())
            .map(|k| {
                let ty = types[k];
                match ty {
                    SocketType::Bool => {
                        Value::boolean(if i < 2 { i == 1 } else { rng.next() & 1 == 1 })
                    }
                    SocketType::Int if !inputs[k].choices.is_empty() => {
                        let m = inputs[k].choices.len() as u64;
                        Value::int(if (i as u64) < m {
                            i as i32
                        } else {
                            (rng.next() % m) as i32
                        })
                    }
                    SocketType::Int => {
                        let (lo, hi) = input_range(t, k);
                        Value::int(rng.draw(lo, hi).round() as i32)
                    }
                    _ => {
                        let lanes: Vec<f32> = match hard_range(t, k) {
                            Some((lo, hi)) if hard => {
                                (0..ty.width()).map(|_| rng.draw_hard(lo, hi)).collect()
                            }
                            _ => {
                                let (lo, hi) = input_range(t, k);
                                (0..ty.width()).map(|_| rng.draw(lo, hi)).collect()
                            }
                        };
                        Value::from_lanes(ty, &lanes)
                    }
                }
            })
            .collect();
        rows.push(row);
    }
    rows.push(defaults.clone());
    for k in 0..inputs.len() {
        if matches!(types[k], SocketType::Bool) || !inputs[k].choices.is_empty() {
            continue;
        }
        let (lo, hi) = input_range(t, k);
        for x in [lo, hi] {
            let mut row = defaults.clone();
            row[k] = Value::float(x).convert(types[k]).unwrap_or(row[k]);
            if types[k] == SocketType::Int {
                row[k] = Value::int(x.round() as i32);
            }
            rows.push(row);
        }
    }
    for case in t.hard_cases() {
        let mut row = defaults.clone();
        for (name, v) in &case.values {
            let k = t.input_index(name).unwrap_or_else(|| {
                panic!(
                    "{}: hard case '{}' names no input '{name}'",
                    t.name(),
                    case.why
                )
            });
            row[k] = v.convert(types[k]).unwrap_or(*v);
        }
        rows.push(row);
    }
    let n = rows.len();
    let columns = types
        .iter()
        .enumerate()
        .map(|(k, ty)| {
            let w = ty.width();
            let mut col = vec![0.0f32; w * n];
            for (i, row) in rows.iter().enumerate() {
                for c in 0..w {
                    col[c * n + i] = row[k].raw()[c];
                }
            }
            col
        })
        .collect();
    NodeSamples { n, columns }
}

/// Runs the node's CPU kernel; returns per output planar columns.
pub fn run_cpu(t: &NodeType, generic: SocketType, s: &NodeSamples) -> Vec<Vec<f32>> {
    let variant = t
        .variant_for(generic)
        .unwrap_or_else(|| panic!("{}: no CPU variant for {generic}", t.name()));
    let ins: Vec<&[f32]> = s.columns.iter().map(Vec::as_slice).collect();
    let mut outs: Vec<Vec<f32>> = t
        .outputs()
        .iter()
        .map(|d| vec![0.0; d.ty.resolve(generic).width() * s.n])
        .collect();
    let mut out_refs: Vec<&mut [f32]> = outs.iter_mut().map(Vec::as_mut_slice).collect();
    variant.kernel.run(&ins, &mut out_refs, s.n, s.n);
    outs
}

/// The inputs of sample `i`, for failure messages.
pub fn describe_inputs(t: &NodeType, generic: SocketType, s: &NodeSamples, i: usize) -> String {
    t.inputs()
        .iter()
        .enumerate()
        .map(|(k, d)| {
            let w = d.ty.resolve(generic).width();
            let lanes: Vec<String> = (0..w)
                .map(|c| format!("{:e}", s.columns[k][c * s.n + i]))
                .collect();
            format!("{}=[{}]", d.name, lanes.join(", "))
        })
        .collect::<Vec<_>>()
        .join(" ")
}

pub fn normalize(v: [f32; 3]) -> [f32; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / l, v[1] / l, v[2] / l]
}

/// 64 × 64 view directions over the upper hemisphere × three normals (up, tilted, down),
/// lights circling the normal, a uv grid and positions on a plane.
pub fn grid_batch() -> SampleBatch {
    let normals = [
        [0.0, 0.0, 1.0],
        normalize([0.3, -0.2, 0.9]),
        [0.0, 0.0, -1.0],
    ];
    let (mut pos, mut nor, mut view, mut light, mut uv) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for nrm in normals {
        for a in 0..64 {
            for b in 0..64 {
                let theta = (a as f32 + 0.5) / 64.0 * std::f32::consts::FRAC_PI_2;
                let phi = b as f32 / 64.0 * std::f32::consts::TAU;
                view.push([
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                ]);
                let lt = (b as f32 + 0.5) / 64.0 * std::f32::consts::FRAC_PI_2;
                let lp = a as f32 / 64.0 * std::f32::consts::TAU;
                light.push([lt.sin() * lp.cos(), lt.sin() * lp.sin(), lt.cos()]);
                nor.push(nrm);
                uv.push([(a as f32 + 0.5) / 64.0, (b as f32 + 0.5) / 64.0, 0.0]);
                pos.push([a as f32 * 0.1 - 3.2, b as f32 * 0.1 - 3.2, 0.0]);
            }
        }
    }
    let mut batch = SampleBatch::new(view.len());
    batch.set_values(Attribute::Position, &pos).unwrap();
    batch.set_values(Attribute::Normal, &nor).unwrap();
    batch.set_values(Attribute::View, &view).unwrap();
    batch.set_values(Attribute::Light, &light).unwrap();
    batch.set_values(Attribute::Uv, &uv).unwrap();
    batch.set_time(1.25);
    batch
}

/// Compares two output batches with the default bound; returns the errors per output and
/// up to three mismatches.
pub fn compare_batches(
    cpu: &OutputBatch,
    gpu: &OutputBatch,
) -> (Vec<(String, Errors)>, Vec<String>) {
    compare_batches_within(cpu, gpu, (ABS, REL))
}

/// The bound for a graph's outputs: the loosest [`LOOSE`] entry among its node types (their
/// reasons hold for whatever they feed), else the default.
pub fn graph_bound(graph: &Graph) -> (f64, f64) {
    graph
        .nodes()
        .iter()
        .map(|n| bound_for(n.node_type.name()))
        .fold((ABS, REL), |a, b| (a.0.max(b.0), a.1.max(b.1)))
}

/// [`compare_batches`] under `bound`.
pub fn compare_batches_within(
    cpu: &OutputBatch,
    gpu: &OutputBatch,
    bound: (f64, f64),
) -> (Vec<(String, Errors)>, Vec<String>) {
    assert_eq!(cpu.names(), gpu.names());
    assert_eq!(cpu.len(), gpu.len());
    let mut per_output = Vec::new();
    let mut bad = Vec::new();
    for (k, name) in cpu.names().iter().enumerate() {
        assert_eq!(cpu.ty(k), gpu.ty(k), "output {name}");
        let mut e = Errors::default();
        let w = cpu.ty(k).width();
        for i in 0..cpu.len() {
            for c in 0..w {
                let (a, b) = (
                    cpu.planar(k)[c * cpu.len() + i],
                    gpu.planar(k)[c * cpu.len() + i],
                );
                if !e.check(a, b, bound) && bad.len() < 3 {
                    bad.push(format!(
                        "output {name}[{c}] sample {i}: cpu {a:e} gpu {b:e}"
                    ));
                }
            }
        }
        per_output.push((name.clone(), e));
    }
    (per_output, bad)
}

/// One graph of the graph parity suites: a bundled file at its defaults or at one other
/// choice of a declared variant, with the sample grid and its textures.
pub struct GraphCase {
    /// `file.json`, or `file.json variant=choice`.
    pub name: String,
    /// The graph.
    pub graph: Graph,
    /// Its CPU plan (default options).
    pub plan: Plan,
    /// [`grid_batch`] with the graph's images and a stand-in for each scene texture.
    pub batch: SampleBatch,
}

/// Every bundled graph at its defaults, then at each other choice of its declared variants.
pub fn shipped_graph_cases() -> Vec<GraphCase> {
    let mut graphs: Vec<(String, PathBuf, Graph)> = Vec::new();
    for path in super::bundled_graphs() {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let graph =
            matgraph::io::load_graph(&path, Registry::builtin()).unwrap_or_else(|e| panic!("{e}"));
        let at = graphs.len();
        for (variant, v) in &graph.variants() {
            for choice in v.choices.iter().filter(|c| **c != v.default) {
                let selection = vec![(variant.clone(), choice.clone())];
                // Through the loaded graph, which reads the files its groups name.
                let g = graph
                    .select(Registry::builtin(), &selection)
                    .unwrap_or_else(|e| panic!("{name} {variant}={choice}: {e:?}"));
                graphs.push((format!("{name} {variant}={choice}"), path.clone(), g));
            }
        }
        graphs.insert(at, (name.clone(), path.clone(), graph));
    }
    graphs
        .into_iter()
        .map(|(name, path, graph)| {
            let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
            let batch = textured_grid_batch(&graph, &plan, &path);
            GraphCase {
                name,
                graph,
                plan,
                batch,
            }
        })
        .collect()
}

/// [`grid_batch`] with the images of `graph` (read from beside `path`) and a stand-in for
/// each scene texture `plan` samples.
pub fn textured_grid_batch(graph: &Graph, plan: &Plan, path: &std::path::Path) -> SampleBatch {
    let mut batch = grid_batch();
    let mut textures = matgraph::image_io::load_graph_textures(graph, path).unwrap();
    for key in plan.textures() {
        if textures.index_of(key).is_none() {
            let image = matgraph::texture::Image::from_fn(32, 16, |x, y| {
                [x as f32 / 31.0, y as f32 / 15.0, 0.5, 1.0]
            });
            let texture = matgraph::texture::Texture::new(image, true).unwrap();
            textures.insert(key.clone(), texture).unwrap();
        }
    }
    batch.set_textures(std::sync::Arc::new(textures));
    batch
}

/// pbr_glass at `ibl` = `monte_carlo` (env_ggx_monte_carlo's loop of 64 filtered environment
/// reads) with the Fresnel choice `fresnel` on both of its nodes, over a 512 × 256 stand-in
/// environment (the renderer's size, so the filtered lookups use several mip levels) with
/// structure at every scale.
pub fn monte_carlo_case(fresnel: &str) -> GraphCase {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/graphs/pbr_glass.json");
    let text = std::fs::read_to_string(path).unwrap();
    let image = matgraph::texture::Image::from_fn(512, 256, |x, y| {
        let checker = ((x / 16 + y / 16) % 2) as f32;
        [
            0.2 + 0.6 * checker,
            y as f32 / 255.0,
            0.5 + 0.4 * (x as f32 * 0.05).sin(),
            1.0,
        ]
    });
    let env = matgraph::texture::Texture::new(image, true).unwrap();
    let mut doc = matgraph::GraphDocument::parse(&text).unwrap();
    for n in doc
        .nodes
        .iter_mut()
        .filter(|n| n.id == "brdf" || n.id == "env_mc")
    {
        n.inputs.insert("fresnel".into(), fresnel.into());
    }
    let selection = [("ibl".to_owned(), "monte_carlo".to_owned())];
    let graph = Graph::with_variants(&doc, Registry::builtin(), &selection).unwrap();
    let plan = Plan::compile(&graph, &PlanOptions::default()).unwrap();
    let mut batch = grid_batch();
    // Every scene texture the plan samples gets the stand-in.
    let mut set = matgraph::texture::TextureSet::new();
    for key in plan.textures() {
        set.insert(key.clone(), env.clone()).unwrap();
    }
    batch.set_textures(std::sync::Arc::new(set));
    GraphCase {
        name: format!("pbr_glass.json ibl=monte_carlo fresnel={fresnel}"),
        graph,
        plan,
        batch,
    }
}

/// The parameter values each graph is checked at: the file's, then every float parameter
/// scaled by 1.1, or by 0.9 where 1.1 leaves the parameter's range (on a GPU, without
/// recompiling).
pub fn parameter_rounds(plan: &Plan) -> [ParamValues; 2] {
    let file = plan.default_parameters();
    let mut scaled = file.clone();
    for p in plan.parameters() {
        let v = scaled.get(&p.name).unwrap();
        if v.ty() == SocketType::Float {
            let up = v.as_f32() * 1.1;
            let x = match p.range {
                Some(r) if !(r.min..=r.max).contains(&up) => v.as_f32() * 0.9,
                _ => up,
            };
            scaled.set(&p.name, Value::float(x)).unwrap();
        }
    }
    [file, scaled]
}

/// One node type at one of its generic types, as the node parity suites check it.
pub struct NodeCase {
    /// The node type.
    pub t: &'static NodeType,
    /// The generic type (`Float` for a node that is not generic).
    pub generic: SocketType,
    /// `name`, or `name (generic)`.
    pub label: String,
    /// The seed of its samples ([`node_samples`]): the same in every suite, so a GPU and the
    /// worst-GPU mode are checked at the same points.
    pub seed: u64,
}

/// Every compute node type of the built-in registry at each of its generic types.
pub fn node_cases() -> Vec<NodeCase> {
    let mut cases = Vec::new();
    for (index, t) in Registry::builtin().types().iter().enumerate() {
        if t.evaluation() != Evaluation::Compute {
            continue;
        }
        let generics = if t.is_generic() {
            t.generic_types()
        } else {
            vec![SocketType::Float]
        };
        for generic in generics {
            let label = if t.is_generic() {
                format!("{} ({generic})", t.name())
            } else {
                t.name().to_owned()
            };
            let seed = 0x5eed_0000 + index as u64 * 16 + generic as u64;
            cases.push(NodeCase {
                t: t.as_ref(),
                generic,
                label,
                seed,
            });
        }
    }
    cases
}

/// How many misses per node and comparison a report lists: `MATGRAPH_PARITY_MISSES`, else 3.
pub fn misses_shown() -> usize {
    std::env::var("MATGRAPH_PARITY_MISSES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3)
}

/// Compares one node's outputs, planar columns per output as [`run_cpu`] returns them: `got`
/// against `want`, per component within `bound` (or, for a node in [`CONDITIONED`], within the
/// bound of its [`envelope`]), into `errors`; the first [`misses_shown`] misses are added to `failures`,
/// labelled with `sides` (what `want` and `got` are). The envelope is the CPU kernel's, so the
/// caller runs this in the exact mode.
#[allow(clippy::too_many_arguments)]
pub fn compare_node_outputs(
    t: &NodeType,
    generic: SocketType,
    samples: &NodeSamples,
    (want, got): (&[Vec<f32>], &[Vec<f32>]),
    bound: (f64, f64),
    label: &str,
    sides: (&str, &str),
    errors: &mut Errors,
    failures: &mut Vec<String>,
) {
    let conditioning = conditioning_for(t.name());
    let scaled = scaled_inputs(t);
    let max_shown = misses_shown();
    let mut envelopes = std::collections::HashMap::new();
    let mut shown = 0;
    for (k, d) in t.outputs().iter().enumerate() {
        let w = d.ty.resolve(generic).width();
        for i in 0..samples.n {
            let bound = scaled_bound(&scaled, samples, i, bound);
            for c in 0..w {
                let (a, b) = (want[k][c * samples.n + i], got[k][c * samples.n + i]);
                let b = match on_cycle(t, samples, i) {
                    true => a + ((b - a + 0.5).rem_euclid(1.0) - 0.5),
                    false => b,
                };
                let mut ratio = errors.measure(a, b, bound);
                let mut range = String::new();
                if let (true, Some(kk)) = (ratio > 1.0, conditioning) {
                    let env = envelopes
                        .entry(i)
                        .or_insert_with(|| envelope(t, generic, samples, i, kk));
                    let r = range_ratio(b, env[k][c], bound);
                    if r <= 1.0 {
                        errors.conditioned += 1;
                    }
                    ratio = r;
                    range = format!(
                        " (outside [{:e}, {:e}], the {sides0}'s range at inputs within {kk}·2⁻²⁴)",
                        env[k][c].0,
                        env[k][c].1,
                        sides0 = sides.0
                    );
                }
                errors.worst = errors.worst.max(ratio);
                if ratio > 1.0 && shown < max_shown {
                    shown += 1;
                    failures.push(format!(
                        "{label}: output {}[{c}] {} {a:e} {} {b:e}{range} at {}",
                        d.name,
                        sides.0,
                        sides.1,
                        describe_inputs(t, generic, samples, i)
                    ));
                }
            }
        }
    }
}

/// The values each parameter with a `range` is swept over (issue 37): its range's ends and
/// middle, and 0, ±1e-45 (a denormal) and ±1e-38 where they lie inside it; set one parameter
/// at a time (the others keep the file's values), every component alike for a vector.
pub fn parameter_sweep(plan: &Plan) -> Vec<(String, ParamValues)> {
    let mut points = Vec::new();
    for p in plan.parameters() {
        let Some(r) = p.range else { continue };
        let mut values = vec![r.min, r.max, 0.5 * (r.min + r.max)];
        for v in [0.0, 1e-45, -1e-45, 1.1754944e-38, -1.1754944e-38] {
            if (r.min..=r.max).contains(&v) {
                values.push(v);
            }
        }
        for v in values {
            let mut params = plan.default_parameters();
            params
                .set(&p.name, Value::float(v))
                .unwrap_or_else(|e| panic!("{} = {v:e}: {e}", p.name));
            points.push((format!("{} = {v:e}", p.name), params));
        }
    }
    points
}

/// Values outside every range a sweep covers: ±1e38, ±∞ and NaN; with each range's
/// neighbours just past its ends, [`parameter_sweep`]'s tests expect `set` to refuse them.
pub fn refused_values(min: f32, max: f32) -> Vec<f32> {
    let mut v = vec![1e38, -1e38, f32::INFINITY, f32::NEG_INFINITY, f32::NAN];
    v.push(min - min.abs().max(1.0) * 1e-3);
    v.push(max + max.abs().max(1.0) * 1e-3);
    v
}

/// A batch of degenerate geometry: denormal and tiny normals and view vectors (each
/// alone, the other unit), which a node must normalise without NaN (issue 37).
pub fn degenerate_geometry_batch() -> SampleBatch {
    let odd: [[f32; 3]; 6] = [
        [1e-45, 0.0, 0.0],
        [0.0, 0.0, 1e-45],
        [1e-40, -1e-40, 1e-40],
        [1e-20, 0.0, 1e-20],
        [0.0, 1.1754944e-38, 0.0],
        [0.0, 0.0, -1e-42],
    ];
    let unit = [0.0, 0.0, 1.0];
    let (mut nor, mut view) = (Vec::new(), Vec::new());
    for v in odd {
        nor.push(v);
        view.push(unit);
        nor.push(unit);
        view.push(v);
        nor.push(v);
        view.push(v);
    }
    let n = nor.len();
    let mut batch = SampleBatch::new(n);
    batch.set_values(Attribute::Normal, &nor).unwrap();
    batch.set_values(Attribute::View, &view).unwrap();
    batch
        .set_values(Attribute::Light, &vec![[0.0, 0.6, 0.8]; n])
        .unwrap();
    batch
        .set_values(Attribute::Uv, &vec![[0.25, 0.75, 0.0]; n])
        .unwrap();
    batch
        .set_values(Attribute::Position, &vec![[0.1, 1.0, -0.2]; n])
        .unwrap();
    batch.set_time(1.25);
    batch
}

/// The first non-finite value of `out`: `output[component] sample i = v`.
pub fn first_non_finite(out: &OutputBatch) -> Option<String> {
    for (k, name) in out.names().iter().enumerate() {
        let n = out.len();
        for (j, v) in out.planar(k).iter().enumerate() {
            if !v.is_finite() {
                return Some(format!("{name}[{}] sample {} = {v}", j / n, j % n));
            }
        }
    }
    None
}
