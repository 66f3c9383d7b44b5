//! Flags several commands take, declared once and flattened into each (`#[command(flatten)]`):
//! which variant choices to compile (`eval`, `render`, `wgsl`) and which outputs (`eval`,
//! `wgsl`).

/// Which choice of each variant set a command uses.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct VariantFlags {
    /// Pick a variant's choice: NAME=CHOICE (repeatable; others take their defaults).
    #[arg(long = "variant", value_name = "NAME=CHOICE")]
    pub variants: Vec<String>,
    /// For each variant set, pick the cheapest choice whose node-space max abs error against
    /// the set's default is within E (measured on the spot; said on stderr).
    #[arg(long, value_name = "E", value_parser = super::flags::max_error)]
    pub max_error: Option<f64>,
}

/// Which outputs a command computes.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct OutputFlags {
    /// Outputs to compute (graph output names or NODE.OUTPUT); default: the graph's outputs.
    #[arg(long = "output", value_name = "NODE.OUTPUT")]
    pub outputs: Vec<String>,
}
