//! `--max-error E`: for each variant set of a graph, the cheapest choice whose error against
//! the set's reference is within `E`, measured on the spot.
//!
//! The reference of a variant set is its declared default (the bundled graphs declare the
//! most accurate choice as the default). Each choice is measured with the other sets at
//! their defaults (or at the choices the caller fixed): its error is the node-space max abs
//! error of the graph's radiance ([`super::measure::radiance`]) over [`PICK_SAMPLES`] seeded
//! samples ([`super::measure::node_samples`]), and its cost is naga's expression count of
//! the compiled module, which is deterministic. Choices with the same count (a node whose
//! one WGSL function holds every method, chosen by an argument, as `thin_film`'s) are
//! ordered by CPU ns per sample over those samples (best of [`PICK_REPEATS`]), which can
//! swap two choices within the machine's noise of each other.

use super::measure::{
    AbsError, abs_error, cpu_ns_per_sample, expression_count, node_samples, radiance, radiance_plan,
};
use crate::registry::Registry;
use crate::texture::TextureSet;
use crate::{Graph, GraphError};
use std::sync::Arc;

/// Samples of the node-space error of a pick.
pub const PICK_SAMPLES: usize = 4096;
/// Timing repeats of a tie on the expression count.
pub const PICK_REPEATS: u32 = 5;
/// Seed of those samples.
pub const PICK_SEED: u64 = 0x6d61_7467_7261_7068;

/// Why a pick failed, naming the variant and choice at fault.
#[derive(Debug, thiserror::Error)]
pub enum PickError {
    /// `E` is negative or not a number.
    #[error("--max-error {0}: expected a number ≥ 0")]
    BadBound(f64),
    /// A choice does not validate.
    #[error("variant '{variant}' = '{choice}': {}", first(.errors))]
    Graph {
        /// The variant.
        variant: String,
        /// The choice.
        choice: String,
        /// What validation said.
        errors: Vec<GraphError>,
    },
    /// A choice does not compile or evaluate.
    #[error("variant '{variant}' = '{choice}': {message}")]
    Measure {
        /// The variant.
        variant: String,
        /// The choice.
        choice: String,
        /// What failed.
        message: String,
    },
}

/// The first error of a list, for a one-line message.
fn first(errors: &[GraphError]) -> String {
    errors
        .first()
        .map(ToString::to_string)
        .unwrap_or_else(|| "invalid".to_owned())
}

/// One choice of a variant set as measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Measured {
    /// The choice.
    pub choice: String,
    /// naga's expression count of the graph with this choice.
    pub expressions: usize,
    /// Its node-space error against the reference choice.
    pub error: AbsError,
    /// CPU ns per sample, measured only where another choice has the same expression count.
    pub cpu_ns: Option<f64>,
}

/// The pick for one variant set.
#[derive(Clone, Debug, PartialEq)]
pub struct Pick {
    /// The variant set.
    pub variant: String,
    /// Its reference choice (the declared default).
    pub reference: String,
    /// The choice picked.
    pub choice: String,
    /// Every choice as measured, in declared order.
    pub measured: Vec<Measured>,
}

impl Pick {
    /// The picked choice's measurement.
    pub fn picked(&self) -> &Measured {
        self.measured
            .iter()
            .find(|m| m.choice == self.choice)
            .expect("the pick is one of the measured choices")
    }

    /// One line: what was picked and why.
    pub fn explain(&self, max_error: f64) -> String {
        let p = self.picked();
        let r = self
            .measured
            .iter()
            .find(|m| m.choice == self.reference)
            .expect("the reference is measured");
        let why = if self.choice == self.reference {
            "the reference".to_owned()
        } else {
            format!(
                "the cheapest within {max_error:e}; the reference '{}' costs {} expressions{}",
                self.reference,
                r.expressions,
                r.cpu_ns
                    .map(|t| format!(", {t:.0} CPU ns/sample"))
                    .unwrap_or_default()
            )
        };
        let time = p
            .cpu_ns
            .map(|t| format!(", {t:.0} CPU ns/sample"))
            .unwrap_or_default();
        format!(
            "--max-error: variant {}={} ({why}): {} naga expressions{time}, max abs error {:.3e} (mean {:.3e}) over {PICK_SAMPLES} samples",
            self.variant, self.choice, p.expressions, p.error.max, p.error.mean
        )
    }
}

/// Picks, for every variant set of `graph` not in `fixed`, the cheapest choice whose error is
/// within `max_error`; the sets in `fixed` keep their fixed choice. `textures` are bound to
/// the samples when given (graphs that sample images).
pub fn pick_variants(
    graph: &Graph,
    registry: &Registry,
    fixed: &[(String, String)],
    max_error: f64,
    textures: Option<Arc<TextureSet>>,
) -> Result<Vec<Pick>, PickError> {
    if max_error.is_nan() || max_error < 0.0 {
        return Err(PickError::BadBound(max_error));
    }
    let batch = node_samples(PICK_SAMPLES, PICK_SEED);
    let mut picks = Vec::new();
    for (name, decl) in graph.variants() {
        if fixed.iter().any(|(v, _)| *v == name) {
            continue;
        }
        let measure = |choice: &str| -> Result<(Graph, usize, Vec<[f32; 3]>), PickError> {
            let mut selection = fixed.to_vec();
            selection.push((name.clone(), choice.to_owned()));
            let g = graph
                .select(registry, &selection)
                .map_err(|errors| PickError::Graph {
                    variant: name.clone(),
                    choice: choice.to_owned(),
                    errors,
                })?;
            let fail = |message: String| PickError::Measure {
                variant: name.clone(),
                choice: choice.to_owned(),
                message,
            };
            let expressions = expression_count(&g).map_err(|e| fail(e.to_string()))?;
            let values = radiance(&g, &batch, textures.clone()).map_err(|e| fail(e.to_string()))?;
            Ok((g, expressions, values))
        };
        let (_, _, reference) = measure(&decl.default)?;
        let mut measured = Vec::new();
        let mut graphs = Vec::new();
        for choice in &decl.choices {
            let (g, expressions, values) = measure(choice)?;
            measured.push(Measured {
                choice: choice.clone(),
                expressions,
                error: abs_error(&reference, &values),
                cpu_ns: None,
            });
            graphs.push(g);
        }
        // Ties on the expression count are timed.
        for i in 0..measured.len() {
            if measured
                .iter()
                .enumerate()
                .any(|(j, m)| j != i && m.expressions == measured[i].expressions)
            {
                let mut b = batch.clone();
                if let Some(t) = &textures {
                    b.set_textures(t.clone());
                }
                let fail = |message: String| PickError::Measure {
                    variant: name.clone(),
                    choice: measured[i].choice.clone(),
                    message,
                };
                let plan = radiance_plan(&graphs[i]).map_err(|e| fail(e.to_string()))?;
                let ns =
                    cpu_ns_per_sample(&plan, &b, PICK_REPEATS).map_err(|e| fail(e.to_string()))?;
                measured[i].cpu_ns = Some(ns);
            }
        }
        let best = measured
            .iter()
            .filter(|m| m.error.max <= max_error || m.choice == decl.default)
            .min_by(|a, b| {
                a.expressions
                    .cmp(&b.expressions)
                    .then(a.cpu_ns.unwrap_or(0.0).total_cmp(&b.cpu_ns.unwrap_or(0.0)))
            })
            .expect("the reference is always within the bound");
        picks.push(Pick {
            variant: name.clone(),
            reference: decl.default.clone(),
            choice: best.choice.clone(),
            measured,
        });
    }
    Ok(picks)
}
