//! `matgraph check`: validate graph files.

use super::{CliResult, count, read_graph_text, registry};
use matgraph::Graph;
use matgraph::error::GraphErrors;
use std::path::{Path, PathBuf};

/// Options of `matgraph check`.
#[derive(clap::Args)]
pub struct Args {
    /// Graph files (JSON).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
}

/// Validates every file: one line per file on stdout, the errors on stderr. A graph
/// without outputs is an error here as in `render` and `eval`, which have nothing to show.
pub fn run(args: &Args) -> CliResult {
    let files = &args.files;
    let mut failed = 0;
    for f in files {
        let text = match read_graph_text(f) {
            Ok(t) => t,
            Err(e) => {
                failed += 1;
                outln!("{}: 1 error", f.display())?;
                errln!("{e}");
                continue;
            }
        };
        let files = matgraph::io::group_files(f, matgraph::io::PathPolicy::InsideGraphFolder);
        let library = matgraph::GraphDocument::parse(&text)
            .ok()
            .filter(|d| !d.groups.is_empty());
        let result = Graph::from_json_in(&text, registry(), files.clone()).map(|g| {
            let mut errors = Vec::new();
            if let Some(doc) = &library {
                errors = group_errors(doc, &files);
            }
            (g, errors)
        });
        match result {
            Ok((g, errors)) if !errors.is_empty() => {
                failed += 1;
                outln!("{}: {}", f.display(), count(errors.len(), "error"))?;
                let _ = g;
                for e in errors {
                    errln!("{}: {e}", f.display());
                }
            }
            Ok((g, _)) if g.outputs().is_empty() && g.nodes().is_empty() && library.is_some() => {
                let groups = library.as_ref().map_or(0, |d| d.groups.len());
                outln!(
                    "{}: ok (a library of {})",
                    f.display(),
                    count(groups, "group")
                )?;
            }
            Ok((g, _)) if g.outputs().is_empty() => {
                failed += 1;
                outln!("{}: 1 error", f.display())?;
                errln!(
                    "{}: the graph has no outputs: add one to \"outputs\" (render and eval need one)",
                    f.display()
                );
            }
            Ok((g, _)) => match as_run(&g, f) {
                Ok(()) => outln!(
                    "{}: ok ({}, {})",
                    f.display(),
                    count(g.nodes().len(), "node"),
                    count(g.outputs().len(), "output")
                )?,
                Err(e) => {
                    failed += 1;
                    outln!("{}: 1 error", f.display())?;
                    errln!("{e}");
                }
            },
            Err(errors) => {
                failed += 1;
                let e = GraphErrors {
                    source: f.clone(),
                    errors,
                };
                outln!("{}: {}", f.display(), count(e.errors.len(), "error"))?;
                errln!("{e}");
            }
        }
    }
    if failed > 0 {
        Err(format!("{failed} of {} failed", count(files.len(), "file")))
    } else {
        Ok(())
    }
}

/// What `eval` and `render` check after loading, with their messages: the plan (the file's
/// parameter values against the hard ranges they reach through hoisted nodes), the images
/// the graph samples, and its scene with its environment image (issue 37: `check` passed
/// graphs those commands refuse).
fn as_run(g: &Graph, f: &Path) -> Result<(), String> {
    matgraph::Plan::compile(g, &matgraph::PlanOptions::default())
        .map_err(|e| format!("{}: {e}", f.display()))?;
    let policy = matgraph::io::PathPolicy::InsideGraphFolder;
    let budget = matgraph::budget::MemoryBudget::new(matgraph::budget::DEFAULT_MEMORY_BUDGET);
    super::graph_textures(g, f, policy, &budget)?;
    super::scene::resolve(g, f, None, policy, &budget)?;
    Ok(())
}

/// The problems inside each group `doc` declares, used or not: each is validated as one
/// instance at its defaults, its outputs the graph's (`group 'NAME' → node 'f': …`).
fn group_errors(
    doc: &matgraph::GraphDocument,
    files: &std::sync::Arc<dyn matgraph::group::GroupFiles>,
) -> Vec<String> {
    let mut out = Vec::new();
    for (name, group) in &doc.groups {
        let mut probe = doc.clone();
        probe.nodes = vec![matgraph::document::NodeDocument {
            id: "probe".into(),
            node_type: matgraph::group::GROUP.into(),
            data_type: None,
            variant: None,
            group: Some(name.clone()),
            muted: false,
            inputs: Default::default(),
            texture: None,
            color_space: None,
            position: None,
        }];
        probe.outputs = group
            .outputs
            .iter()
            .map(|o| matgraph::document::OutputDocument {
                name: o.name.clone(),
                from: format!("probe.{}", o.name),
            })
            .collect();
        probe.parameters.clear();
        probe.frames.clear();
        if let Err(errors) = Graph::from_document_in(&probe, registry(), files.clone()) {
            for e in errors {
                out.push(match e {
                    matgraph::GraphError::InGroup { error, .. } => {
                        format!("group '{name}' → {error}")
                    }
                    e => format!(
                        "group '{name}': {}",
                        e.to_string().replace("node 'probe': ", "")
                    ),
                });
            }
        }
    }
    out
}
