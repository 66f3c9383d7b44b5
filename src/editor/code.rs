//! The generated-code panel: the current graph's WGSL (fragment entry), or GLSL, MSL or
//! HLSL through naga, with the focused node's lines highlighted; copy and export.

use crate::graph::Graph;
use crate::wgsl::{Entry, Target, WgslOptions, generate};
use std::ops::Range;

/// The languages the panel shows.
pub const TARGETS: [Target; 4] = [Target::Wgsl, Target::Glsl, Target::Msl, Target::Hlsl];

/// The panel's state: the language and the code generated for the current document.
#[derive(Clone, Debug, Default)]
pub struct CodeState {
    /// Whether the panel is shown.
    pub open: bool,
    /// The language (index in [`TARGETS`]).
    pub target: usize,
    /// The node the view was last scrolled to.
    pub scrolled_for: Option<String>,
    /// The generated code, regenerated when the document or the language changes.
    cache: Option<Generated>,
}

/// Code generated for one document and language.
#[derive(Clone, Debug)]
pub struct Generated {
    /// The language.
    pub target: Target,
    /// The text, or the error that stopped it (naga's, mapped to a node where known).
    pub text: Result<String, String>,
    /// Node of the error, when the error names one.
    pub error_node: Option<String>,
    /// WGSL byte ranges per node id (for WGSL only: the other languages are rewritten by
    /// naga, so no node map survives).
    pub spans: Vec<(Range<usize>, String)>,
}

impl CodeState {
    /// Forgets the code (the document changed).
    pub fn invalidate(&mut self) {
        self.cache = None;
    }

    /// The code of `graph` in the chosen language, generated on first use.
    pub fn generated(&mut self, graph: Option<&Graph>) -> &Generated {
        let target = TARGETS[self.target.min(TARGETS.len() - 1)];
        if self.cache.as_ref().is_none_or(|g| g.target != target) {
            self.cache = Some(generate_code(graph, target));
        }
        self.cache.as_ref().expect("just set")
    }
}

/// Generates the code of `graph` (its fragment entry) in `target`.
pub fn generate_code(graph: Option<&Graph>, target: Target) -> Generated {
    let Some(graph) = graph else {
        return Generated {
            target,
            text: Err("the graph has errors (see Problems)".into()),
            error_node: None,
            spans: Vec::new(),
        };
    };
    let options = WgslOptions {
        entry: Entry::Fragment,
        ..Default::default()
    };
    match generate(graph, &options) {
        Err(e) => Generated {
            target,
            error_node: match &e {
                crate::wgsl::ShaderError::Naga { node, .. } => node.clone(),
                crate::wgsl::ShaderError::MissingWgsl { node, .. } => Some(node.clone()),
                _ => None,
            },
            text: Err(e.to_string()),
            spans: Vec::new(),
        },
        Ok(m) => {
            let text = m
                .translate(target)
                .map(|b| String::from_utf8_lossy(&b).into_owned())
                .map_err(|e| e.to_string());
            Generated {
                target,
                spans: if target == Target::Wgsl {
                    m.spans.clone()
                } else {
                    Vec::new()
                },
                text,
                error_node: None,
            }
        }
    }
}

/// The 0-based line numbers of `text` that lie in the spans generated for node `id` (for a
/// group instance, those of the nodes inlined from it, `id/…`).
pub fn node_lines(text: &str, spans: &[(Range<usize>, String)], id: &str) -> Vec<usize> {
    let mut lines = Vec::new();
    let mut start = 0;
    for (k, line) in text.split_inclusive('\n').enumerate() {
        let r = start..start + line.len();
        if spans
            .iter()
            .any(|(s, n)| super::model::owner(n) == id && s.start < r.end && r.start < s.end)
        {
            lines.push(k);
        }
        start = r.end;
    }
    lines
}

/// The file extension of code in `target`.
pub fn extension(target: Target) -> &'static str {
    match target {
        Target::Wgsl => "wgsl",
        Target::SpirV => "spv",
        Target::Glsl => "frag",
        Target::Msl => "metal",
        Target::Hlsl => "hlsl",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_overlapping_a_span_are_the_nodes() {
        let text = "a\nbb\nccc\n";
        // "bb\n" is bytes 2..5; a span 3..4 lies in line 1 only.
        let spans = vec![(3..4, "n".to_owned()), (6..7, "m".to_owned())];
        assert_eq!(node_lines(text, &spans, "n"), vec![1]);
        assert_eq!(node_lines(text, &spans, "m"), vec![2]);
        assert!(node_lines(text, &spans, "x").is_empty());
    }
}
