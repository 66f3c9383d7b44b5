//! What apps and users call: the command line, the report and the app contract.
//!
//! One test binary per concern (each links wgpu, naga and egui): run one module with
//! `cargo test --test app MODULE::`.

#[path = "../common/mod.rs"]
mod common;

mod app_contract;
mod atomic_writes;
mod bake_env;
mod cli;
mod cli_params;
mod memory_budget;
mod messages;
mod module_contract;
mod numeric_flags;
mod output_paths;
mod parameter_clamp;
mod readme;
mod report;
mod sandbox_race;
mod stdout_errors;
mod tangent_contract;
mod texel_checks;
mod web_example;
mod wgsl_options;
