//! Parsing and validating generated WGSL with naga, mapping errors back to nodes.

use super::ShaderError;
use std::ops::Range;

/// Parses and validates `source`; a failure names the node whose text it points into.
pub(super) fn validate(
    source: &str,
    spans: &[(Range<usize>, String)],
) -> Result<(naga::Module, naga::valid::ModuleInfo), ShaderError> {
    let node_at = |offset: usize| {
        spans
            .iter()
            .find(|(r, _)| r.contains(&offset))
            .map(|(_, id)| id.clone())
    };
    let module = naga::front::wgsl::parse_str(source).map_err(|e| ShaderError::Naga {
        node: e
            .labels()
            .find_map(|(span, _)| span.to_range().and_then(|r| node_at(r.start))),
        message: e.emit_to_string(source),
    })?;
    let info = validator()
        .validate(&module)
        .map_err(|e| ShaderError::Naga {
            node: e
                .spans()
                .find_map(|(span, _)| span.to_range().and_then(|r| node_at(r.start))),
            message: e.emit_to_string(source),
        })?;
    Ok((module, info))
}

/// The validator used for every generated module: all checks, no optional capabilities.
pub(super) fn validator() -> naga::valid::Validator {
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
}
