//! The GPU side: WGSL generation (naga, Tint, spirv-val), CPU/GPU parity of every node and
//! graph, and the rasteriser's renders.
//!
//! One test binary per concern (each links wgpu, naga and egui): run one module with
//! `cargo test --test gpu MODULE::`.

#[path = "../common/mod.rs"]
mod common;

mod gpu_parity;
mod gpu_render;
mod gpu_scale;
mod render;
mod wgsl_codegen;
mod wgsl_external;
mod wgsl_names;
mod wgsl_tint;
