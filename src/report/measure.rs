//! What the report measures of one variant: its cost (naga's expression count, CPU
//! nanoseconds per sample on the executor) and its error against a reference, in node space
//! (the graph's radiance at seeded samples) and in render space (RMSE and CIEDE2000 over the
//! pixels of a render).

use super::ciede2000::{delta_e_2000, srgb_to_lab};
use crate::exec::SampleBatch;
use crate::node::Attribute;
use crate::plan::{EvalError, Plan, PlanOptions};
use crate::render::HdrImage;
use crate::render::tonemap::{pbr_neutral, srgb_encode};
use crate::texture::TextureSet;
use crate::wgsl::{Entry, ShaderError, WgslOptions, generate};
use crate::{Graph, SocketType};
use glam::Vec3;
use std::sync::Arc;
use std::time::Instant;

/// naga's expression count of the graph's compute module (every function and entry point,
/// all outputs): a portable proxy of its GPU cost.
pub fn expression_count(graph: &Graph) -> Result<usize, ShaderError> {
    let shader = generate(
        graph,
        &WgslOptions {
            plan: PlanOptions::default(),
            entry: Entry::Compute,
            ..Default::default()
        },
    )?;
    let m = &shader.module;
    Ok(m.functions
        .iter()
        .map(|(_, f)| f.expressions.len())
        .sum::<usize>()
        + m.entry_points
            .iter()
            .map(|e| e.function.expressions.len())
            .sum::<usize>())
}

/// SplitMix64 (Steele, Lea & Flood 2014): the seeded stream of the report's samples (and of
/// the crate's unit tests that draw random points).
pub(crate) struct SplitMix(pub(crate) u64);

impl SplitMix {
    /// The next 64 random bits.
    pub(crate) fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1), an f32 with 24 random bits.
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
    /// Uniform on the unit sphere (Archimedes: z uniform in [−1, 1], φ uniform).
    fn sphere(&mut self) -> Vec3 {
        let z = 2.0 * self.unit() - 1.0;
        let phi = std::f32::consts::TAU * self.unit();
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }
    /// Uniform on the hemisphere around `n` (so `cos θ = n·d` is uniform in [0, 1]).
    fn hemisphere(&mut self, n: Vec3) -> Vec3 {
        let d = self.sphere();
        if d.dot(n) < 0.0 {
            d - 2.0 * d.dot(n) * n
        } else {
            d
        }
    }
}

/// The time every report sample is taken at, in seconds.
pub const SAMPLE_TIME: f32 = 1.0;

/// `n` seeded samples of every geometry attribute, the domain of the node-space error: a unit
/// normal uniform on the sphere, view and light uniform on its hemisphere (so N·V and N·L
/// are uniform in [0, 1]), position in [−1, 1]³, uv and screen uv in [0, 1]², depth in
/// [0, 5] m, white light, uv derivatives of a 256-pixel-wide texture, time [`SAMPLE_TIME`].
pub fn node_samples(n: usize, seed: u64) -> SampleBatch {
    let mut rng = SplitMix(seed);
    let (mut normal, mut view, mut light) = (Vec::new(), Vec::new(), Vec::new());
    let (mut position, mut uv, mut screen, mut depth) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for _ in 0..n {
        let nrm = rng.sphere();
        normal.push(nrm.to_array());
        view.push(rng.hemisphere(nrm).to_array());
        light.push(rng.hemisphere(nrm).to_array());
        position.push([0, 1, 2].map(|_| 2.0 * rng.unit() - 1.0));
        uv.push([rng.unit(), rng.unit(), 0.0]);
        screen.push([rng.unit(), rng.unit(), 0.0]);
        depth.push([5.0 * rng.unit(), 0.0, 0.0]);
    }
    let mut batch = SampleBatch::new(n);
    let set = |b: &mut SampleBatch, a: Attribute, v: &[[f32; 3]]| {
        b.set_values(a, v).expect("one value per sample")
    };
    set(&mut batch, Attribute::Normal, &normal);
    set(&mut batch, Attribute::View, &view);
    set(&mut batch, Attribute::Light, &light);
    set(&mut batch, Attribute::Position, &position);
    set(&mut batch, Attribute::Uv, &uv);
    set(&mut batch, Attribute::ScreenUv, &screen);
    set(&mut batch, Attribute::Depth, &depth);
    set(&mut batch, Attribute::LightColor, &vec![[1.0; 3]; n]);
    set(
        &mut batch,
        Attribute::UvDx,
        &vec![[1.0 / 256.0, 0.0, 0.0]; n],
    );
    set(
        &mut batch,
        Attribute::UvDy,
        &vec![[0.0, -1.0 / 256.0, 0.0]; n],
    );
    batch.set_time(SAMPLE_TIME);
    batch
}

/// The outputs whose sum is a graph's radiance in node space: `color` (lit, with white
/// light) and `emission` where the graph has either, else its first output.
pub fn radiance_outputs(graph: &Graph) -> Vec<String> {
    use crate::render::outputs::{COLOR, EMISSION};
    let names: Vec<String> = graph
        .outputs()
        .iter()
        .filter(|o| o.name == COLOR || o.name == EMISSION)
        .map(|o| o.name.clone())
        .collect();
    if names.is_empty() {
        graph
            .outputs()
            .iter()
            .take(1)
            .map(|o| o.name.clone())
            .collect()
    } else {
        names
    }
}

/// The graph compiled for its radiance outputs ([`radiance_outputs`]).
pub fn radiance_plan(graph: &Graph) -> Result<Plan, EvalError> {
    Plan::compile(
        graph,
        &PlanOptions {
            outputs: radiance_outputs(graph),
            bake_parameters: false,
        },
    )
}

/// The graph's radiance at every sample of `batch`: the sum of its radiance outputs, a
/// float output broadcast to the three channels. `textures` are bound when given.
pub fn radiance(
    graph: &Graph,
    batch: &SampleBatch,
    textures: Option<Arc<TextureSet>>,
) -> Result<Vec<[f32; 3]>, EvalError> {
    let plan = radiance_plan(graph)?;
    let mut batch = batch.clone();
    if let Some(t) = textures {
        batch.set_textures(t);
    }
    let out = plan.execute(&batch, &plan.default_parameters())?;
    let n = batch.len();
    let mut sum = vec![[0.0f32; 3]; n];
    for k in 0..out.names().len() {
        let data = out.planar(k);
        let width = out.ty(k).width();
        if out.ty(k) != SocketType::Float && width < 3 {
            continue;
        }
        for (i, s) in sum.iter_mut().enumerate() {
            for (c, v) in s.iter_mut().enumerate() {
                *v += data[if width == 1 { 0 } else { c } * n + i];
            }
        }
    }
    Ok(sum)
}

/// The best of `repeats` wall-clock times of evaluating `plan` over `batch`, in nanoseconds
/// per sample.
pub fn cpu_ns_per_sample(plan: &Plan, batch: &SampleBatch, repeats: u32) -> Result<f64, EvalError> {
    let params = plan.default_parameters();
    plan.execute(batch, &params)?; // warm-up
    let mut best = f64::INFINITY;
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        let out = plan.execute(batch, &params)?;
        let t = start.elapsed().as_secs_f64();
        std::hint::black_box(out);
        best = best.min(t);
    }
    Ok(best * 1e9 / batch.len().max(1) as f64)
}

/// Max and mean absolute error over samples and channels.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct AbsError {
    /// Largest absolute difference.
    pub max: f64,
    /// Mean absolute difference.
    pub mean: f64,
}

/// The absolute error of `values` against `reference`, channel by channel (NaN or infinite
/// differences count as infinite).
pub fn abs_error(reference: &[[f32; 3]], values: &[[f32; 3]]) -> AbsError {
    let (mut max, mut sum, mut n) = (0.0f64, 0.0f64, 0usize);
    for (r, v) in reference.iter().zip(values) {
        for c in 0..3 {
            let d = (f64::from(v[c]) - f64::from(r[c])).abs();
            let d = if d.is_finite() { d } else { f64::INFINITY };
            max = max.max(d);
            sum += d;
            n += 1;
        }
    }
    AbsError {
        max,
        mean: if n == 0 { 0.0 } else { sum / n as f64 },
    }
}

/// Error of a render against the reference render, on the displayed image: each linear
/// pixel tone-mapped (`tonemap::pbr_neutral`, exposure 0) and clamped to [0, 1].
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ImageError {
    /// Root-mean-square difference of the sRGB-encoded values in [0, 1], over pixels and
    /// channels.
    pub rmse: f64,
    /// Mean CIEDE2000 ΔE00 over the pixels (CIELAB of the displayed linear sRGB).
    pub de_mean: f64,
    /// Largest CIEDE2000 ΔE00 of a pixel.
    pub de_max: f64,
}

/// The displayed linear value of a rendered pixel.
fn displayed(c: [f32; 3]) -> [f64; 3] {
    pbr_neutral(c).map(|v| f64::from(if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) }))
}

/// The error of `image` against `reference` (same size; `None` otherwise).
pub fn image_error(reference: &HdrImage, image: &HdrImage) -> Option<ImageError> {
    if (reference.width, reference.height) != (image.width, image.height) {
        return None;
    }
    let (mut sq, mut de_sum, mut de_max) = (0.0f64, 0.0f64, 0.0f64);
    for (r, p) in reference.pixels.iter().zip(&image.pixels) {
        let (r, p) = (displayed(*r), displayed(*p));
        for c in 0..3 {
            let d = f64::from(srgb_encode(p[c] as f32)) - f64::from(srgb_encode(r[c] as f32));
            sq += d * d;
        }
        let de = delta_e_2000(srgb_to_lab(r), srgb_to_lab(p));
        de_sum += de;
        de_max = de_max.max(de);
    }
    let n = reference.pixels.len().max(1) as f64;
    Some(ImageError {
        rmse: (sq / (3.0 * n)).sqrt(),
        de_mean: de_sum / n,
        de_max,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hemisphere_cosines_are_uniform() {
        // E[cos] = 1/2 and E[cos²] = 1/3 for cos uniform in [0, 1].
        let b = node_samples(20000, 7);
        let (n, v) = (
            b.column(Attribute::Normal).unwrap(),
            b.column(Attribute::View).unwrap(),
        );
        let len = b.len();
        let cos: Vec<f64> = (0..len)
            .map(|i| {
                (0..3)
                    .map(|c| f64::from(n[c * len + i] * v[c * len + i]))
                    .sum()
            })
            .collect();
        assert!(cos.iter().all(|&c| c >= -1e-6));
        let m1 = cos.iter().sum::<f64>() / len as f64;
        let m2 = cos.iter().map(|c| c * c).sum::<f64>() / len as f64;
        assert!((m1 - 0.5).abs() < 0.01, "{m1}");
        assert!((m2 - 1.0 / 3.0).abs() < 0.01, "{m2}");
    }

    #[test]
    fn abs_error_by_hand() {
        let e = abs_error(
            &[[0.0, 1.0, 2.0], [1.0; 3]],
            &[[0.5, 1.0, 2.0], [1.0, 1.0, 4.0]],
        );
        // Differences 0.5, 0, 0 and 0, 0, 3.
        assert_eq!(e.max, 3.0);
        assert!((e.mean - 3.5 / 6.0).abs() < 1e-12);
    }

    #[test]
    fn image_error_of_grey_levels() {
        // A black image against white: every channel differs by 1 (RMSE 1), and ΔE00 between
        // L* = 0 and L* = 100 (a* = b* = 0) is ΔL'/S_L with L̄' = 50: S_L = 1, so 100.
        let black = HdrImage {
            width: 2,
            height: 1,
            pixels: vec![[0.0; 3]; 2],
        };
        let white = HdrImage {
            pixels: vec![[1e6; 3]; 2],
            ..black.clone()
        };
        let e = image_error(&black, &white).unwrap();
        assert!((e.rmse - 1.0).abs() < 1e-4, "{e:?}");
        assert!((e.de_mean - 100.0).abs() < 1e-3, "{e:?}");
        let same = image_error(&white, &white).unwrap();
        assert_eq!(same, ImageError::default());
    }
}
