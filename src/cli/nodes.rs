//! `matgraph nodes`: list every node type with its ports.

use super::{CliResult, registry};
use matgraph::node::{NodeType, PortType};

/// Options of `matgraph nodes`.
#[derive(clap::Args)]
pub struct Args {
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Prints every node type, as text or JSON.
pub fn run(args: &Args) -> CliResult {
    let json = args.json;
    let types = registry().types();
    if json {
        let list: Vec<serde_json::Value> = types.iter().map(|t| node_json(t)).collect();
        out!(
            "{}",
            matgraph::pretty::to_string(&serde_json::Value::Array(list))
        )?;
        return Ok(());
    }
    for t in types {
        outln!("{} [{}] — {}", t.name(), t.category(), t.summary())?;
        outln!("    {}", t.source_doc())?;
        if t.is_generic() {
            let ts: Vec<&str> = t.generic_types().iter().map(|t| t.name()).collect();
            outln!("    T ∈ {{{}}}", ts.join(", "))?;
        }
        for i in t.inputs() {
            let mut extra = String::new();
            if let Some(r) = i.soft {
                extra += &format!(" soft [{}, {}]", r.min, r.max);
            }
            if let Some(r) = i.hard {
                extra += &format!(" hard [{}, {}]", r.min, r.max);
            }
            if !i.unit.is_empty() {
                extra += &format!(" ({})", i.unit);
            }
            if !i.choices.is_empty() {
                extra += &format!(" choices: {}", i.choices.join(", "));
            }
            outln!(
                "    in  {:<14} {:<6} = {:<18}{extra} — {}",
                i.name,
                i.ty.to_string(),
                i.default.to_string(),
                i.doc
            )?;
        }
        for o in t.outputs() {
            let unit = if o.unit.is_empty() {
                String::new()
            } else {
                format!(" ({})", o.unit)
            };
            outln!(
                "    out {:<14} {:<6}{unit} — {}",
                o.name,
                o.ty.to_string(),
                o.doc
            )?;
        }
        outln!("    muted: {}", t.muted_rule())?;
        outln!()?;
    }
    Ok(())
}

fn port_type(t: PortType) -> String {
    t.to_string()
}

fn node_json(t: &NodeType) -> serde_json::Value {
    use serde_json::json;
    let range = |r: Option<matgraph::node::Range>| r.map(|r| json!([r.min, r.max]));
    json!({
        "name": t.name(),
        "category": t.category().name(),
        "summary": t.summary(),
        "source": t.source_doc(),
        "generic_types": if t.is_generic() { json!(t.generic_types().iter().map(|t| t.name()).collect::<Vec<_>>()) } else { json!(null) },
        "inputs": t.inputs().iter().map(|i| json!({
            "name": i.name,
            "type": port_type(i.ty),
            "default": i.default.to_json(),
            "soft_range": range(i.soft),
            "hard_range": range(i.hard),
            "unit": i.unit,
            "choices": i.choices,
            "doc": i.doc,
        })).collect::<Vec<_>>(),
        "outputs": t.outputs().iter().map(|o| json!({
            "name": o.name,
            "type": port_type(o.ty),
            "unit": o.unit,
            "doc": o.doc,
        })).collect::<Vec<_>>(),
        "muted": t.muted_rule(),
    })
}
