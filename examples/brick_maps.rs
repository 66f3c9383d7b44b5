//! The texture maps of `graphs/brick_wall.json`, made here rather than downloaded: a tileable
//! 512 × 512 running-bond brick wall (4 bricks across, 8 courses; every other course offset
//! by half a brick), written to `graphs/textures/brick/`:
//!
//! - `albedo.png`: sRGB colour; each brick its own red-brown (a seeded hash per brick) with
//!   fired speckles, the mortar a warm light grey.
//! - `roughness.png`: data (linear grey): bricks 0.75–0.9, mortar 0.95.
//! - `height.png`: data: bricks 1 with bevelled edges (a smoothstep over 6 texels) and a
//!   slight per-brick tilt, mortar 0.
//! - `normal.png`: data, tangent space: from the height by central differences (wrapping, so
//!   it tiles), `n = normalize(−k ∂h/∂x, −k ∂h/∂y, 1)` with x along u (right) and y along v
//!   (down the image: matgraph's uv, row 0 at v = 0), stored as `n / 2 + ½`: green along the
//!   direction in which v grows, the `normal_map` node's `opengl` convention.
//!
//! `cargo run --release --example brick_maps` rewrites them (same bytes every run).

use std::path::Path;

/// Pixels a side.
const SIZE: usize = 512;
/// Courses (rows of bricks) and bricks per course.
const COURSES: usize = 8;
const BRICKS: usize = 4;
/// Mortar joint width and bevel, pixels.
const JOINT: f64 = 6.0;
const BEVEL: f64 = 6.0;
/// Bump strength of the normal map: height units per texel slope.
const BUMP: f64 = 3.0;

/// A 32-bit integer hash (Wang-style mix) to [0, 1).
fn hash(mut x: u32) -> f64 {
    x = (x ^ 61) ^ (x >> 16);
    x = x.wrapping_mul(9);
    x ^= x >> 4;
    x = x.wrapping_mul(0x27d4_eb2d);
    x ^= x >> 15;
    x as f64 / 4_294_967_296.0
}

fn hash2(a: usize, b: usize, salt: u32) -> f64 {
    hash((a as u32).wrapping_mul(73_856_093) ^ (b as u32).wrapping_mul(19_349_663) ^ salt)
}

fn smoothstep(e0: f64, e1: f64, x: f64) -> f64 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// At pixel (x, y): the brick's (column, course) and the distance to the nearest joint.
fn brick_at(x: f64, y: f64) -> (usize, usize, f64) {
    let (bw, bh) = ((SIZE / BRICKS) as f64, (SIZE / COURSES) as f64);
    let course = (y / bh).floor() as usize % COURSES;
    let shift = if course % 2 == 1 { 0.5 * bw } else { 0.0 };
    let xs = (x + shift).rem_euclid(SIZE as f64);
    let col = (xs / bw).floor() as usize % BRICKS;
    let (fx, fy) = (xs - col as f64 * bw, y - course as f64 * bh);
    // Half a joint on each side of a brick's edges.
    let d = fx.min(bw - fx).min(fy).min(bh - fy) - 0.5 * JOINT;
    (col, course, d)
}

/// Height in [0, 1] at pixel (x, y).
fn height(x: f64, y: f64) -> f64 {
    let (col, course, d) = brick_at(x, y);
    if d <= 0.0 {
        return 0.0;
    }
    let tilt = (hash2(col, course, 7) - 0.5) * 0.1 * (x / SIZE as f64 - 0.5);
    let pits = if hash2(x as usize, y as usize, 11) > 0.985 {
        -0.15
    } else {
        0.0
    };
    (smoothstep(0.0, BEVEL, d) * (0.9 + tilt) + pits).clamp(0.0, 1.0)
}

/// Linear albedo at pixel (x, y).
fn albedo(x: f64, y: f64) -> [f64; 3] {
    let (col, course, d) = brick_at(x, y);
    if d <= 0.0 {
        let g = 0.55 + 0.05 * hash2(x as usize, y as usize, 3);
        return [g, g * 0.97, g * 0.92];
    }
    let v = hash2(col, course, 1);
    let base = [
        0.38 + 0.18 * v,
        0.12 + 0.07 * v,
        0.07 + 0.04 * hash2(col, course, 2),
    ];
    let speckle = 0.8 + 0.4 * hash2(x as usize, y as usize, 5);
    base.map(|c| c * speckle)
}

fn roughness(x: f64, y: f64) -> f64 {
    let (col, course, d) = brick_at(x, y);
    if d <= 0.0 {
        0.95
    } else {
        0.75 + 0.15 * hash2(col, course, 9)
    }
}

/// Linear [0, 1] to 8-bit sRGB.
fn srgb8(c: f64) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

fn unorm8(c: f64) -> u8 {
    (c.clamp(0.0, 1.0) * 255.0).round() as u8
}

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/textures/brick");
    std::fs::create_dir_all(&dir).unwrap();
    let n = SIZE as u32;
    let centre = |i: usize| i as f64 + 0.5;
    let heights: Vec<f64> = (0..SIZE * SIZE)
        .map(|k| height(centre(k % SIZE), centre(k / SIZE)))
        .collect();
    let h = |x: usize, y: usize| heights[(y % SIZE) * SIZE + x % SIZE];
    let mut albedo_img = image::RgbImage::new(n, n);
    let mut normal_img = image::RgbImage::new(n, n);
    let mut rough_img = image::GrayImage::new(n, n);
    let mut height_img = image::GrayImage::new(n, n);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let (px, py) = (centre(x), centre(y));
            let a = albedo(px, py);
            albedo_img.put_pixel(x as u32, y as u32, image::Rgb(a.map(srgb8)));
            rough_img.put_pixel(x as u32, y as u32, image::Luma([unorm8(roughness(px, py))]));
            height_img.put_pixel(x as u32, y as u32, image::Luma([unorm8(h(x, y))]));
            let dx = (h(x + 1, y) - h(x + SIZE - 1, y)) / 2.0;
            let dy = (h(x, y + 1) - h(x, y + SIZE - 1)) / 2.0;
            let (nx, ny, nz) = (-BUMP * dx, -BUMP * dy, 1.0);
            let l = (nx * nx + ny * ny + nz * nz).sqrt();
            let rgb = [nx / l, ny / l, nz / l].map(|c| unorm8(c * 0.5 + 0.5));
            normal_img.put_pixel(x as u32, y as u32, image::Rgb(rgb));
        }
    }
    albedo_img.save(dir.join("albedo.png")).unwrap();
    normal_img.save(dir.join("normal.png")).unwrap();
    rough_img.save(dir.join("roughness.png")).unwrap();
    height_img.save(dir.join("height.png")).unwrap();
    println!(
        "wrote {}/{{albedo,normal,roughness,height}}.png",
        dir.display()
    );
}
