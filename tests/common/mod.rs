//! Helpers shared by the integration tests (each test binary uses some of them).
#![allow(dead_code)]

use matgraph::EvalError;
use matgraph::gpu::GpuContext;
use std::io::Write as _;
use std::path::{Path, PathBuf};

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

/// The shared GPU context, or `None` after printing why the calling test is skipped; panics
/// instead when `MATGRAPH_REQUIRE_GPU` is set (CI), so GPU tests never skip silently there.
pub fn gpu_context(test: &str) -> Option<&'static GpuContext> {
    match GpuContext::shared() {
        Ok(ctx) => Some(ctx),
        Err(e) => {
            let why = match &e {
                EvalError::Gpu(m) => m.clone(),
                e => e.to_string(),
            };
            if std::env::var_os("MATGRAPH_REQUIRE_GPU").is_some() {
                panic!("{test}: MATGRAPH_REQUIRE_GPU is set and the GPU is unavailable: {why}");
            }
            // Written to the stream itself: the test harness captures `eprintln!` of passing
            // tests, and a skip must show without `--nocapture`.
            let _ = writeln!(std::io::stderr(), "SKIPPED {test}: {why}");
            None
        }
    }
}
