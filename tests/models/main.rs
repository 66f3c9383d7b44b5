//! Each shading model's numbers against independent references: the papers' tables, closed
//! forms and f64 re-derivations, Blender's own output, and each node's hard cases.
//!
//! One test binary per concern (each links wgpu, naga and egui): run one module with
//! `cargo test --test models MODULE::`.

#[path = "../common/mod.rs"]
mod common;

mod blender_textures;
mod bubble;
mod bump;
mod ibl;
mod mapping;
mod math_edges;
mod math_ops;
mod normal_map;
mod optics_reference;
mod param_ranges;
mod pbr;
mod physics_pointwise;
mod ramps;
mod ramps_blender;
mod registry_stability;
mod skin;
mod sunshine;
mod tangents;
mod texture_coordinate;
mod thin_film;
mod toon_water;
mod transmission;
mod triplanar;
