//! The `thin_film` node's methods: CPU time per sample, and (printed once, before the timings)
//! their colour error against the spectral reference in CIEDE2000 over thickness 0–2000 nm ×
//! angle 0–89° for a free soap film (n = 1.33 in air). Run with `cargo bench --bench
//! thin_film`; the figures are in docs/models/thin_film.md.

#[path = "../tests/thin_film/ciede2000.rs"]
mod ciede2000;

use ciede2000::{delta_e_2000, srgb_to_lab};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use matgraph::nodes::thin_film::{BELCOUR_BARLA, METHOD_NAMES, RGB3, SPECTRAL, TABLE, thin_film};
use std::hint::black_box;

/// Samples per timed batch: thickness and angle on a 32 × 32 grid over the measured domain.
fn samples() -> Vec<(f32, f32)> {
    let mut v = Vec::new();
    for i in 0..32 {
        for j in 0..32 {
            let d = 2000.0 * i as f32 / 31.0;
            let cos = (89.0f32 * j as f32 / 31.0).to_radians().cos();
            v.push((cos, d));
        }
    }
    v
}

fn v3(v: glam::Vec3) -> [f64; 3] {
    [v.x as f64, v.y as f64, v.z as f64]
}

/// Prints mean, 95th percentile and max ΔE00 of each cheap method's reflectance (and the
/// mean for transmittance) against spectral, over d = 0, 2, …, 2000 nm × θ = 0, 1, …, 89°.
fn error_table() {
    println!("thin_film ΔE00 against spectral, d 0–2000 nm step 2, θ 0–89° step 1, n 1.33 in air");
    for (method, name) in [
        (BELCOUR_BARLA, "belcour_barla"),
        (RGB3, "rgb3"),
        (TABLE, "table"),
    ] {
        for (label, max_deg) in [("θ ≤ 89°", 89), ("θ ≤ 60°", 60)] {
            let mut er = Vec::new();
            let mut et = 0.0;
            let mut worst = (0.0, 0.0, 0);
            for i in 0..=1000 {
                let d = 2.0 * i as f32;
                for deg in 0..=max_deg {
                    let cos = (deg as f32).to_radians().cos();
                    let (rs, ts) = thin_film(cos, d, 1.33, 1.0, 1.0, SPECTRAL);
                    let (rm, tm) = thin_film(cos, d, 1.33, 1.0, 1.0, method);
                    let e = delta_e_2000(srgb_to_lab(v3(rs)), srgb_to_lab(v3(rm)));
                    if e > worst.0 {
                        worst = (e, d, deg);
                    }
                    er.push(e);
                    et += delta_e_2000(srgb_to_lab(v3(ts)), srgb_to_lab(v3(tm)));
                }
            }
            er.sort_by(f64::total_cmp);
            let n = er.len();
            let mean = er.iter().sum::<f64>() / n as f64;
            println!(
                "  {name:<14} {label}: R mean {mean:.3}  p95 {:.3}  max {:.3} (d {} nm, θ {}°)  T mean {:.3}  ({n} samples)",
                er[n * 95 / 100],
                worst.0,
                worst.1,
                worst.2,
                et / n as f64
            );
        }
    }
}

fn bench(c: &mut Criterion) {
    error_table();
    let samples = samples();
    let mut group = c.benchmark_group("thin_film_cpu");
    group.throughput(Throughput::Elements(samples.len() as u64));
    for method in [SPECTRAL, BELCOUR_BARLA, RGB3, TABLE] {
        group.bench_with_input(
            BenchmarkId::new("method", METHOD_NAMES[method as usize]),
            &samples,
            |b, s| {
                b.iter(|| {
                    for &(cos, d) in s {
                        black_box(thin_film(
                            black_box(cos),
                            black_box(d),
                            1.33,
                            1.0,
                            1.0,
                            method,
                        ));
                    }
                })
            },
        );
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
