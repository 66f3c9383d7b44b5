//! The JSON graph file format, version 1: the serde model, parsing with located errors,
//! and deterministic pretty saving.
//!
//! ```json
//! {
//!   "version": 1,
//!   "name": "fresnel_demo",
//!   "doc": "Exact Fresnel reflectance of glass.",
//!   "nodes": [
//!     { "id": "geo", "type": "geometry", "position": [0.0, 0.0] },
//!     { "id": "cos", "type": "dot", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "geo.view" } } },
//!     { "id": "ior", "type": "parameter", "inputs": { "value": 1.5 } },
//!     { "id": "fr", "type": "fresnel_dielectric",
//!       "inputs": { "cos_theta": { "link": "cos.result" }, "ior_inside": { "link": "ior.value" } } }
//!   ],
//!   "outputs": [ { "name": "reflectance", "from": "fr.reflectance" } ],
//!   "parameters": [ { "name": "ior", "node": "ior", "doc": "Index of refraction of the glass." } ]
//! }
//! ```
//!
//! An input is a literal (a number, an array of 2–4 numbers, a bool, or an enum choice's
//! name) or a link `{ "link": "node_id.output" }`. Inputs left out take their defaults.
//! Unknown fields are errors. Saving writes keys in a fixed order and inputs sorted by name,
//! with the shortest decimal that reads back to the same `f32`, so load → save → load is
//! byte-identical.

use crate::error::GraphError;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The newest graph file format version this build reads, and the one it writes.
pub const FORMAT_VERSION: u32 = 1;

/// A graph file (format version 1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(title = "matgraph graph", extend("$id" = "https://matgraph.dev/graph.schema.json"))]
pub struct GraphDocument<N = NodeDocument> {
    /// Format version; this build reads versions up to 1.
    pub version: u32,
    /// The graph's name.
    pub name: String,
    /// What the graph computes and where it comes from.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub doc: String,
    /// The nodes, in the order the author wrote them.
    pub nodes: Vec<N>,
    /// The values the graph produces for its caller.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub outputs: Vec<OutputDocument>,
    /// The parameter nodes exposed to the caller (material settings).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub parameters: Vec<ParameterDocument>,
}

/// One node of a graph file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NodeDocument {
    /// Stable id, unique in the graph: letters, digits, `_` and `-`.
    #[schemars(regex(pattern = r"^[A-Za-z0-9_-]+$"))]
    pub id: String,
    /// The node type's registered name (see `matgraph nodes`).
    #[serde(rename = "type")]
    pub node_type: String,
    /// For generic nodes: the data type `T` (float, vec2, vec3, vec4, color); inferred from
    /// the inputs when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub data_type: Option<String>,
    /// Input values and links by input name; absent inputs take their defaults.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    #[schemars(with = "BTreeMap<String, InputSchema>")]
    pub inputs: BTreeMap<String, serde_json::Value>,
    /// Position in the node editor.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        serialize_with = "shortest_pair"
    )]
    pub position: Option<[f32; 2]>,
}

/// One output of the graph.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OutputDocument {
    /// The name callers ask for.
    pub name: String,
    /// The node output it reads, written `node_id.output`.
    #[schemars(regex(pattern = r"^[A-Za-z0-9_-]+\.[a-z0-9_]+$"))]
    pub from: String,
}

/// One exposed parameter of the graph.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ParameterDocument {
    /// The name callers set it by.
    pub name: String,
    /// The id of the `parameter` node it exposes.
    pub node: String,
    /// What the parameter means, with its unit.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub doc: String,
    /// The group it is shown in (for example "sebum", "epidermis", "dermis").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub group: Option<String>,
}

/// Schema of one input entry: a literal or a link.
#[derive(JsonSchema)]
#[serde(untagged)]
#[allow(dead_code)]
enum InputSchema {
    /// A link to another node's output.
    Link(LinkSchema),
    /// A float or int.
    Number(f64),
    /// A vector or colour.
    Vector(#[schemars(length(min = 2, max = 4))] Vec<f64>),
    /// A bool.
    Bool(bool),
    /// An enum choice by name.
    Choice(String),
}

/// Schema of a link.
#[derive(JsonSchema)]
#[serde(deny_unknown_fields)]
#[allow(dead_code)]
struct LinkSchema {
    /// The source, written `node_id.output`.
    #[schemars(regex(pattern = r"^[A-Za-z0-9_-]+\.[a-z0-9_]+$"))]
    link: String,
}

/// The JSON Schema of the graph format, as pretty JSON (the text of `docs/graph.schema.json`).
pub fn json_schema() -> String {
    let schema = schemars::schema_for!(GraphDocument);
    let mut text = serde_json::to_string_pretty(&schema).unwrap_or_default();
    text.push('\n');
    text
}

impl GraphDocument {
    /// Parses a graph file's text. Errors carry line and column, and the node id when the
    /// problem is inside a node's entry. Never panics.
    pub fn parse(text: &str) -> Result<GraphDocument, Vec<GraphError>> {
        let raw: serde_json::Value = serde_json::from_str(text).map_err(|e| {
            vec![GraphError::Syntax {
                line: e.line(),
                column: e.column(),
                message: strip_location(&e),
            }]
        })?;
        check_version(&raw)?;
        serde_json::from_str::<GraphDocument>(text).map_err(|e| structure_errors(text, &e))
    }

    /// Saves as pretty JSON with a trailing newline; the same document gives the same bytes.
    pub fn to_json_pretty(&self) -> String {
        // Fields serialise in declaration order and inputs are a BTreeMap, so output is stable.
        let value = serde_json::to_value(self).unwrap_or_default();
        crate::pretty::to_string(&value)
    }
}

/// Serialises an editor position with the shortest decimals that read back to the same f32s.
fn shortest_pair<S: serde::Serializer>(p: &Option<[f32; 2]>, s: S) -> Result<S::Ok, S::Error> {
    let shortest = |x: f32| format!("{x:?}").parse::<f64>().unwrap_or(x as f64);
    match p {
        Some([x, y]) => [shortest(*x), shortest(*y)].serialize(s),
        None => s.serialize_none(),
    }
}

fn check_version(raw: &serde_json::Value) -> Result<(), Vec<GraphError>> {
    let Some(obj) = raw.as_object() else {
        return Err(vec![GraphError::Structure {
            node: None,
            line: 1,
            column: 1,
            message: "a graph file must be a JSON object".into(),
        }]);
    };
    match obj.get("version") {
        None => Err(vec![GraphError::MissingVersion {
            supported: FORMAT_VERSION,
        }]),
        Some(v) => match v.as_u64() {
            Some(found) if found > FORMAT_VERSION as u64 => {
                Err(vec![GraphError::UnsupportedVersion {
                    found,
                    supported: FORMAT_VERSION,
                }])
            }
            Some(_) => Ok(()),
            None => Err(vec![GraphError::Structure {
                node: None,
                line: 1,
                column: 1,
                message: format!("\"version\" must be a non-negative integer, found {v}"),
            }]),
        },
    }
}

/// Turns a typed-parse failure into errors: one per malformed node entry (named by its id
/// and located exactly), plus a malformed top level, located.
fn structure_errors(text: &str, e: &serde_json::Error) -> Vec<GraphError> {
    #[derive(Deserialize)]
    struct RawNodes<'a> {
        #[serde(borrow, default)]
        nodes: Vec<&'a serde_json::value::RawValue>,
    }
    let mut errors = Vec::new();
    // The top level alone, with node entries skipped.
    if let Err(top) = serde_json::from_str::<GraphDocument<serde::de::IgnoredAny>>(text) {
        errors.push(GraphError::Structure {
            node: None,
            line: top.line(),
            column: top.column(),
            message: strip_location(&top),
        });
    }
    if let Ok(raw) = serde_json::from_str::<RawNodes>(text) {
        for (i, node) in raw.nodes.iter().enumerate() {
            let slice = node.get();
            if let Err(ne) = serde_json::from_str::<NodeDocument>(slice) {
                let id = serde_json::from_str::<serde_json::Value>(slice)
                    .ok()
                    .and_then(|v| v.get("id").and_then(|id| id.as_str()).map(str::to_owned));
                let offset = slice.as_ptr() as usize - text.as_ptr() as usize;
                let (line, column) = offset_location(text, offset, ne.line(), ne.column());
                errors.push(GraphError::Structure {
                    node: Some(id.unwrap_or_else(|| format!("#{i}"))),
                    line,
                    column,
                    message: strip_location(&ne),
                });
            }
        }
    }
    if errors.is_empty() {
        errors.push(GraphError::Structure {
            node: None,
            line: e.line(),
            column: e.column(),
            message: strip_location(e),
        });
    }
    errors
}

/// The 1-based line and column in `text` of a position given relative to a slice starting
/// at byte `offset`.
fn offset_location(text: &str, offset: usize, line: usize, column: usize) -> (usize, usize) {
    let before = &text[..offset];
    let base_line = before.matches('\n').count() + 1;
    let base_column = before.len() - before.rfind('\n').map_or(0, |i| i + 1);
    if line <= 1 {
        (base_line, base_column + column)
    } else {
        (base_line + line - 1, column)
    }
}

/// serde_json's message without its trailing " at line L column C".
fn strip_location(e: &serde_json::Error) -> String {
    let text = e.to_string();
    match text.rfind(" at line ") {
        Some(i) if e.line() > 0 => text[..i].to_owned(),
        _ => text,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn syntax_errors_have_line_and_column() {
        let err = GraphDocument::parse("{\n  \"version\": 1,\n  \"name\": }").unwrap_err();
        assert!(
            matches!(
                err[0],
                GraphError::Syntax {
                    line: 3,
                    column: 11,
                    ..
                }
            ),
            "{err:?}"
        );
    }

    #[test]
    fn newer_versions_are_rejected_before_anything_else() {
        let err = GraphDocument::parse(r#"{"version": 2, "future": true}"#).unwrap_err();
        assert_eq!(
            err,
            vec![GraphError::UnsupportedVersion {
                found: 2,
                supported: 1
            }]
        );
    }

    #[test]
    fn unknown_node_fields_name_the_node() {
        let text =
            r#"{"version": 1, "name": "g", "nodes": [{"id": "a", "type": "add", "colour": 1}]}"#;
        let err = GraphDocument::parse(text).unwrap_err();
        assert_eq!(err.len(), 1);
        assert_eq!(err[0].node(), Some("a"));
        assert!(
            err[0].to_string().contains("unknown field `colour`"),
            "{}",
            err[0]
        );
    }
}
