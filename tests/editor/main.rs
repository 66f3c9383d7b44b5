//! The node editor (`src/editor/`), driven through egui_kittest as a user drives it.
//!
//! One test binary per concern (each links wgpu, naga and egui): run one module with
//! `cargo test --test editor MODULE::`.

#[path = "../common/mod.rs"]
mod common;

mod browser;
mod build;
mod drive;
mod groups;
mod keymap;
mod node_states;
mod ramps;
mod readable;
mod scene_problems;
mod selection;
mod session;
mod textures;
mod variants;
