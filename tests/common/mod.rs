//! Helpers shared by the integration tests (each test binary uses some of them).
#![allow(dead_code)]

use matgraph::EvalError;
use matgraph::gpu::GpuContext;
use std::io::Write as _;
use std::path::{Path, PathBuf};

pub mod parity;
pub mod rng;
pub mod scenes;
pub mod tint;

/// Every bundled graph (`graphs/*.json`), sorted; fails if there is none.
pub fn bundled_graphs() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    v.sort();
    assert!(!v.is_empty(), "no graphs/*.json");
    v
}

/// Prints `SKIPPED {test}: {why}` so that it shows without `--nocapture`.
pub fn print_skip(test: &str, why: &str) {
    // Written to the stream itself: the test harness captures `eprintln!` of passing
    // tests, and a skip must show without `--nocapture`.
    let _ = writeln!(std::io::stderr(), "SKIPPED {test}: {why}");
}

/// Prints `WARNING {test}: {what}` so that it shows without `--nocapture`.
pub fn print_warning(test: &str, what: &str) {
    let _ = writeln!(std::io::stderr(), "WARNING {test}: {what}");
}

/// `Some(tool)` when it is available; otherwise prints why the calling test is skipped and
/// returns `None`, or panics when `MATGRAPH_REQUIRE_TOOLS` is set (CI), so the external-tool
/// tests never skip silently there.
pub fn tool_or_skip<T>(test: &str, tool: Result<T, String>) -> Option<T> {
    match tool {
        Ok(t) => Some(t),
        Err(why) => {
            if std::env::var_os("MATGRAPH_REQUIRE_TOOLS").is_some() {
                panic!("{test}: MATGRAPH_REQUIRE_TOOLS is set and a tool is missing: {why}");
            }
            print_skip(test, &why);
            None
        }
    }
}

/// The shared GPU context, or `None` after printing why the calling test is skipped; panics
/// instead when `MATGRAPH_REQUIRE_GPU` is set (CI), so GPU tests never skip silently there.
///
/// With `MATGRAPH_EXPECT_BACKEND` set (`vulkan`, `gl`, `metal`, `dx12`; CI runs the parity
/// suite on Vulkan and on GL) it also panics when the adapter is on another backend.
pub fn gpu_context(test: &str) -> Option<&'static GpuContext> {
    match GpuContext::shared() {
        Ok(ctx) => {
            if let Some(want) = std::env::var_os("MATGRAPH_EXPECT_BACKEND") {
                let got = ctx.adapter_info().backend;
                assert!(
                    want.to_string_lossy().eq_ignore_ascii_case(got.to_str()),
                    "{test}: MATGRAPH_EXPECT_BACKEND is {want:?} but the adapter is {}",
                    ctx.describe()
                );
            }
            Some(ctx)
        }
        Err(e) => {
            let why = match &e {
                EvalError::Gpu(m) => m.clone(),
                e => e.to_string(),
            };
            if std::env::var_os("MATGRAPH_REQUIRE_GPU").is_some() {
                panic!("{test}: MATGRAPH_REQUIRE_GPU is set and the GPU is unavailable: {why}");
            }
            print_skip(test, &why);
            None
        }
    }
}
