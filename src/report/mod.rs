//! Speed against error: the data of `matgraph report` and what it writes.
//!
//! Each material family ([`family::FAMILIES`]) has variants, one of them the reference.
//! For each variant the command measures ([`measure`]) its cost (naga's expression count,
//! CPU ns per sample on the executor, GPU time per frame where an adapter exists) and its
//! error against the reference in node space (the radiance at seeded samples) and in render
//! space (RMSE and CIEDE2000 over the pixels of the family's scene), collects them in a
//! [`FamilyReport`], and writes its table ([`markdown`]) and plot ([`plot`]). This module
//! does no I/O: the command (`src/cli/report.rs`) loads the graphs and writes the files.

pub mod ciede2000;
pub mod family;
pub mod measure;
pub mod pareto;
pub mod pick;
pub mod plot;

use measure::{AbsError, ImageError};
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;

/// One variant's row of a family's table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VariantRow {
    /// Variant name.
    pub name: String,
    /// What it models.
    pub doc: String,
    /// Graph file (relative to the graphs folder).
    pub graph: String,
    /// Variant choices and input overrides, `thin_film=rgb3`, `ss.three_lobe=true`.
    pub selection: Vec<String>,
    /// Whether this is the family's reference.
    pub reference: bool,
    /// naga's expression count of the compute module.
    pub expressions: usize,
    /// CPU nanoseconds per sample on the executor (best of the repeats), when timed.
    pub cpu_ns: Option<f64>,
    /// GPU milliseconds per frame (best of the repeats), when timed on an adapter.
    pub gpu_ms: Option<f64>,
    /// Node-space error of the radiance at the seeded samples.
    pub node: AbsError,
    /// Render-space error of the family's scene.
    pub image: ImageError,
    /// Whether the variant is on the Pareto front of (cost, mean ΔE00).
    pub front: bool,
}

/// How a report was measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    /// Render size in pixels.
    pub width: u32,
    /// Render height in pixels.
    pub height: u32,
    /// Samples of the node-space error and of the CPU timing.
    pub samples: usize,
    /// Their seed.
    pub seed: u64,
    /// Repeats of each timing (best taken); `None` when not timed.
    pub repeats: Option<u32>,
    /// The machine of the CPU timing, `None` when not timed.
    pub machine: Option<String>,
    /// The GPU adapter of the GPU timing, `None` when not timed on a GPU.
    pub gpu: Option<String>,
}

/// A family's measured variants.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FamilyReport {
    /// Family name.
    pub name: String,
    /// Title.
    pub title: String,
    /// What the family is.
    pub doc: String,
    /// Reference variant.
    pub reference: String,
    /// How it was measured.
    pub settings: Settings,
    /// The variants, in the family's order.
    pub rows: Vec<VariantRow>,
    /// Variants not written yet: `(name, what will fill it)`.
    pub pending: Vec<(String, String)>,
}

impl FamilyReport {
    /// Whether every row has a CPU time (then the cost axis is time, else expressions).
    pub fn timed(&self) -> bool {
        !self.rows.is_empty() && self.rows.iter().all(|r| r.cpu_ns.is_some())
    }

    /// A row's cost on the plot: CPU ns per sample at 2 significant figures when timed, else
    /// the expression count.
    pub fn cost(&self, row: &VariantRow) -> f64 {
        match row.cpu_ns {
            Some(t) if self.timed() => round_sig(t, 2),
            _ => row.expressions as f64,
        }
    }

    /// Marks the Pareto front of (cost, mean ΔE00).
    pub fn mark_front(&mut self) {
        let points: Vec<(f64, f64)> = self
            .rows
            .iter()
            .map(|r| (self.cost(r), r.image.de_mean))
            .collect();
        for (row, on) in self.rows.iter_mut().zip(pareto::front(&points)) {
            row.front = on;
        }
    }

    /// What the plot draws.
    pub fn plot_spec(&self) -> plot::PlotSpec {
        let x_label = if self.timed() {
            format!(
                "CPU ns per sample (best of {})",
                self.settings.repeats.unwrap_or(1)
            )
        } else {
            "naga expressions".to_owned()
        };
        plot::PlotSpec {
            title: format!("{}: cost against error", self.title),
            x_label,
            y_label: format!("mean CIEDE2000 vs {}", self.reference),
            points: self
                .rows
                .iter()
                .map(|r| plot::PlotPoint {
                    label: r.name.clone(),
                    cost: self.cost(r),
                    error: r.image.de_mean,
                    front: r.front,
                })
                .collect(),
        }
    }
}

/// `x` rounded to `digits` significant figures.
pub fn round_sig(x: f64, digits: i32) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powi(digits - 1 - x.abs().log10().floor() as i32);
    (x * scale).round() / scale
}

/// An error for the table: 0, or three significant figures.
fn err(x: f64) -> String {
    if x == 0.0 {
        "0".to_owned()
    } else if !x.is_finite() {
        "∞".to_owned()
    } else if (1e-3..1e4).contains(&x.abs()) {
        let s = round_sig(x, 3);
        let decimals = (2 - s.abs().log10().floor() as i32).max(0) as usize;
        format!("{s:.decimals$}")
    } else {
        format!("{x:.2e}")
    }
}

/// A family's page: what it is, how it was measured, the table, the plot.
pub fn markdown(r: &FamilyReport) -> String {
    let s = &r.settings;
    let mut out = String::new();
    let _ = writeln!(out, "# {}\n\n{}\n", r.title, r.doc);
    let _ = writeln!(
        out,
        "Reference: **{}**. Written by `matgraph report` (src/cli/report.rs); do not edit.\n",
        r.reference
    );
    let _ = writeln!(
        out,
        "Node space: the radiance (`color` with white light + `emission`) at {} seeded samples \
         (seed {:#x}; normal uniform on the sphere, view and light on its hemisphere; \
         `report::measure::node_samples`). Render space: the family's scene at {}×{}, 1 sample \
         per pixel, CPU, tone-mapped (PBR Neutral) and compared as displayed: RMSE of the sRGB \
         values in [0, 1], CIEDE2000 ΔE00 per pixel.",
        s.samples, s.seed, s.width, s.height
    );
    match (&s.machine, s.repeats) {
        (Some(m), Some(n)) => {
            let _ = writeln!(
                out,
                "\nTimes: best of {n} runs over the {} samples on {m}{}. Times vary run to run; \
                 every other column is the same on every run.",
                s.samples,
                s.gpu
                    .as_ref()
                    .map(|g| format!("; GPU time per frame (`render --gpu`: the passes submitted and waited for, or the G-buffer's shading where the scene takes the hybrid path; pipeline compilation left out) on {g}"))
                    .unwrap_or_default()
            );
        }
        _ => {
            let _ = writeln!(
                out,
                "\nNot timed (`--no-timing`): the cost is naga's expression count; the page is the same on every run."
            );
        }
    }
    let _ = writeln!(
        out,
        "\n| variant | graph | naga expressions | CPU ns/sample | GPU ms/frame | node max | node mean | RMSE | ΔE00 mean | ΔE00 max | Pareto |"
    );
    let _ = writeln!(
        out,
        "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | :---: |"
    );
    for row in &r.rows {
        let name = if row.reference {
            format!("**{}** (reference)", row.name)
        } else {
            row.name.clone()
        };
        let graph = if row.selection.is_empty() {
            format!("`{}`", row.graph)
        } else {
            format!("`{}` {}", row.graph, row.selection.join(", "))
        };
        let _ = writeln!(
            out,
            "| {name} | {graph} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            row.expressions,
            row.cpu_ns.map(err).unwrap_or_else(|| "–".into()),
            row.gpu_ms.map(err).unwrap_or_else(|| "–".into()),
            err(row.node.max),
            err(row.node.mean),
            err(row.image.rmse),
            err(row.image.de_mean),
            err(row.image.de_max),
            if row.front { "●" } else { "" }
        );
    }
    let mut counts: Vec<usize> = r.rows.iter().map(|row| row.expressions).collect();
    counts.sort_unstable();
    if counts.windows(2).any(|w| w[0] == w[1]) {
        let _ = writeln!(
            out,
            "\nVariants with the same expression count differ only in a node's enum or bool \
             input: that node's one WGSL function holds every method and takes the choice as an \
             argument, so the count cannot tell them apart; their CPU times can."
        );
    }
    let _ = writeln!(out, "\nVariants:\n");
    for row in &r.rows {
        let _ = writeln!(out, "- `{}`: {}.", row.name, row.doc);
    }
    for (name, what) in &r.pending {
        let _ = writeln!(out, "- `{name}` (to fill): {what}.");
    }
    let _ = writeln!(
        out,
        "\n![{0}: cost against error]({0}.svg)\n\nThe Pareto front (red) joins the variants no \
         other beats on both cost and mean ΔE00. PNG: [{0}.png]({0}.png); data: [{0}.json]({0}.json).",
        r.name
    );
    out
}

/// The report's index `README.md` (docs/report/README.md): the families, their references
/// and variants, and the command.
pub fn index(reports: &[FamilyReport]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# Speed against error\n\nEach material family has variants, one of them the reference \
         (its most accurate model); every variant's cost and error against the reference are \
         measured by one command:\n\n```sh\ncargo run --release -- report --out docs/report   # these pages, \
         timed (default: target/report)\nmatgraph report --quick --out target/report-ci   # what CI runs: small, few samples\n\
         matgraph report --no-timing              # cost = naga expressions: same bytes every run\n```\n\n\
         The families and their variants are the table `FAMILIES` in \
         [src/report/family.rs](../../src/report/family.rs). A variant is a bundled graph, \
         with a choice of its declared `variants` (a `switch` in the graph) or a node input \
         override.\n"
    );
    let _ = writeln!(out, "| family | reference | variants | page |");
    let _ = writeln!(out, "| --- | --- | --- | --- |");
    for r in reports {
        let mut names: Vec<String> = r
            .rows
            .iter()
            .map(|v| {
                let graph = if v.selection.is_empty() {
                    format!("`{}`", v.graph)
                } else {
                    format!("`{}` {}", v.graph, v.selection.join(", "))
                };
                format!("{} ({graph})", v.name)
            })
            .collect();
        names.extend(r.pending.iter().map(|(n, _)| format!("{n} (to fill)")));
        let _ = writeln!(
            out,
            "| {} | {} | {} | [{}.md]({}.md) |",
            r.title,
            r.reference,
            names.join("; "),
            r.name,
            r.name
        );
    }
    let _ = writeln!(
        out,
        "\n`matgraph render|wgsl|eval --max-error E` picks, for each variant set declared in a \
         graph, the cheapest choice (naga expressions) whose node-space max abs error against \
         the set's default is within E, measured on the spot (`report::pick`)."
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_and_error_text() {
        assert_eq!(round_sig(123.456, 2), 120.0);
        assert_eq!(round_sig(0.0012345, 3), 0.00123);
        assert_eq!(err(0.0), "0");
        assert_eq!(err(0.012345), "0.0123");
        assert_eq!(err(12.345), "12.3");
        assert_eq!(err(1.5e-5), "1.50e-5");
    }
}
