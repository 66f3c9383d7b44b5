//! Evaluating graphs on a GPU with wgpu: a headless device ([`GpuContext`]), compiled
//! material pipelines that evaluate batches like the CPU plan ([`GpuPlan`]), the one-argument
//! CPU/GPU switch ([`compile`]) and a runner for single-node harness modules ([`GpuHarness`]).
//!
//! Any adapter wgpu finds is used, software ones included (Mesa's lavapipe runs the compute
//! shaders on the CPU), so the GPU path can be tested on machines without a GPU. Every
//! failure (no adapter, a shader the driver rejects, a lost device) is an
//! [`EvalError::Gpu`] that callers can fall back from; nothing here panics on them.

mod context;
mod device;
mod harness;
mod plan;
mod pool;
pub mod raster;

pub use context::GpuContext;
pub use device::dispatch_shape;
pub use harness::GpuHarness;
pub use plan::GpuPlan;

use crate::exec::Evaluator;
use crate::graph::Graph;
use crate::plan::{EvalError, ParamValues, Plan, PlanOptions};

/// Which evaluator [`compile`] builds.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Backend {
    /// The batched CPU executor ([`Plan`]).
    #[default]
    Cpu,
    /// Generated WGSL run by wgpu ([`GpuPlan`] on [`GpuContext::shared`]). A render draws
    /// the whole frame with wgpu render pipelines ([`raster`]).
    Gpu,
    /// As [`Backend::Gpu`] for evaluators; a render rasterises on the CPU and shades the
    /// G-buffer with the compute pipeline (the hybrid path, kept for comparison and as the
    /// fallback of the GPU rasteriser).
    GpuCompute,
}

/// Compiles `graph` for `backend`; the evaluators agree to within float rounding.
pub fn compile(
    graph: &Graph,
    options: &PlanOptions,
    backend: Backend,
) -> Result<Box<dyn Evaluator>, EvalError> {
    Ok(match backend {
        Backend::Cpu => Box::new(Plan::compile(graph, options)?),
        Backend::Gpu | Backend::GpuCompute => {
            Box::new(GpuPlan::compile(GpuContext::shared()?, graph, options)?)
        }
    })
}

/// The parameter values from the graph file, valid for the evaluators of every backend.
pub fn default_parameters(graph: &Graph, options: &PlanOptions) -> Result<ParamValues, EvalError> {
    Ok(Plan::compile(graph, options)?.default_parameters())
}
