//! matgraph: a node-graph material host.
//!
//! Shading models are nodes with typed ports and a one-sample compute ([`node`]); graphs of
//! them are saved as versioned JSON ([`document`]), validated into a typed DAG ([`graph`]),
//! compiled into a plan ([`plan`]) and evaluated over tiles on the CPU ([`exec`]).
//! The core does no I/O: files live in [`io`], the command line in the binary.

#![warn(missing_docs)]

pub mod budget;
pub mod bump;
pub mod color_space;
pub mod document;
#[cfg(feature = "editor")]
pub mod editor;
pub mod error;
pub mod exec;
pub mod gpu;
pub mod graph;
pub mod group;
pub mod image_io;
pub mod io;
pub mod kernel;
pub mod material;
pub(crate) mod memo;
pub mod node;
pub mod overrides;
pub mod parameter_info;
pub mod plan;
pub mod precision;
pub mod pretty;
pub mod registry;
pub mod render;
pub mod report;
pub mod scene;
pub mod specialise;
pub mod texture;
pub mod types;
pub mod value;
pub mod variant;
pub mod visible;
pub mod wgsl;

/// The node library (the repository's `nodes/` folder).
#[path = "../nodes/mod.rs"]
pub mod nodes;

pub use document::{FORMAT_VERSION, GraphDocument};
pub use error::{GraphError, GraphErrors};
pub use exec::{Evaluator, OutputBatch, SampleBatch};
pub use graph::Graph;
pub use node::{Attribute, NodeType};
pub use plan::{EvalError, ParamValues, Plan, PlanOptions};
pub use registry::Registry;
pub use types::SocketType;
pub use value::Value;
