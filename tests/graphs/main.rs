//! Graph documents and what is built from them: the format's errors, groups, variants,
//! colour spaces, frames, specialisation, textures, scenes and scaling.
//!
//! One test binary per concern (each links wgpu, naga and egui): run one module with
//! `cargo test --test graphs MODULE::`.

#[path = "../common/mod.rs"]
mod common;

mod color_space;
mod document_errors;
mod frames;
mod fuzz;
mod group_library;
mod groups;
mod param_ranges;
mod scale;
mod scene;
mod specialise;
mod texture;
mod texture_keys;
mod variants;
