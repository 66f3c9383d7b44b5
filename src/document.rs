//! The JSON graph file format, versions 1 and 2: the serde model, parsing with located
//! errors, and deterministic pretty saving. Version 2 adds node groups (`groups`, nodes of
//! type `group`), `reroute` nodes, `muted` nodes and `frames` (see [`crate::group`]); a
//! version-1 file that uses one of them is refused with the version it needs.
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
pub const FORMAT_VERSION: u32 = 2;

/// The version that brought node groups, reroutes, muted nodes and frames.
pub const GROUPS_VERSION: u32 = 2;

/// A graph file (format version 1 or 2).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(title = "matgraph graph", extend("$id" = "https://matgraph.dev/graph.schema.json"))]
#[serde(expecting = "a graph object { \"version\", \"name\", \"nodes\", \"outputs\", … }")]
pub struct GraphDocument<N = NodeDocument> {
    /// Format version; this build reads versions 1 and 2 and saves a file in its own.
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
    /// Named choices between alternative implementations, resolved at compile time by the
    /// `switch` nodes that name them (see [`crate::variant`]).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub variants: BTreeMap<String, VariantDocument>,
    /// Node groups (version 2): subgraphs with their own interface, used by nodes of type
    /// `group` (see [`crate::group`]).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub groups: BTreeMap<String, GroupDocument>,
    /// Frames (version 2): labelled boxes around nodes in the editor; layout only.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub frames: Vec<FrameDocument>,
    /// The scene the graph is previewed in: a preset name (`"ball"`, `"water"`) or a scene
    /// object (see `matgraph::scene`); `matgraph render --scene` overrides it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "Option<serde_json::Value>")]
    pub scene: Option<serde_json::Value>,
}

/// One node of a graph file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[serde(expecting = "a node object { \"id\", \"type\", \"inputs\", … }")]
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
    /// For `switch` nodes: the variant whose choice picks the input passed on.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub variant: Option<String>,
    /// For `group` nodes (version 2): the group used, `NAME` (a group of this file),
    /// `PATH#NAME` (a group of another file) or `PATH` (a whole graph file), paths relative
    /// to the file that names them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub group: Option<String>,
    /// Muted (version 2): each output passes through the node's first input of the same
    /// type, else gives its type's zero (Blender's rule).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub muted: bool,
    /// Input values and links by input name; absent inputs take their defaults.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    #[schemars(with = "BTreeMap<String, InputSchema>")]
    pub inputs: BTreeMap<String, serde_json::Value>,
    /// For texture nodes: the image, a path relative to the graph file (PNG, JPEG, HDR,
    /// EXR), a list of paths for a custom mip chain (level 0 first), or a scene texture
    /// (`scene:refraction`, `scene:reflection`, `scene:background`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture: Option<TextureSource>,
    /// For texture nodes naming image files (version 2): how the image's values are read:
    /// `srgb` (decoded to linear light), `linear` or `data` (unchanged; `data` for maps that
    /// are not colour: roughness, height, normals, masks). Absent: by the file type, sRGB for
    /// PNG and JPEG, linear for HDR and EXR.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color_space: Option<crate::color_space::ColorSpace>,
    /// Position in the node editor.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        serialize_with = "shortest_pair"
    )]
    pub position: Option<[f32; 2]>,
}

/// The image a texture node samples.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
#[serde(expecting = "an image path, a list of image paths (a mip chain) or \"scene:NAME\"")]
pub enum TextureSource {
    /// One image (mips generated by a box filter), or a `scene:` texture.
    Image(String),
    /// A custom mip chain: one image per level, each half the size of the one before.
    MipChain(Vec<String>),
}

impl TextureSource {
    /// The prefix of scene textures.
    pub const SCENE: &'static str = "scene:";
    /// The scene textures a renderer supplies (`scene:NAME`): the scene's passes, and the
    /// environment map with its image-based-lighting tables.
    pub const SCENE_TEXTURES: [&'static str; 7] = [
        "background",
        "refraction",
        "reflection",
        "environment",
        "environment_ggx",
        "brdf_lut",
        "environment_sh",
    ];

    /// The key the texture is bound under in a [`crate::texture::TextureSet`]: the path as
    /// written, or the paths of a chain joined by `|`.
    pub fn key(&self) -> String {
        match self {
            TextureSource::Image(p) => p.clone(),
            TextureSource::MipChain(v) => v.join("|"),
        }
    }
    /// The scene texture's name (`refraction`, ...), if this is one.
    pub fn scene_name(&self) -> Option<&str> {
        match self {
            TextureSource::Image(p) => p.strip_prefix(Self::SCENE),
            TextureSource::MipChain(_) => None,
        }
    }
    /// The image files, in level order (none for a scene texture).
    pub fn files(&self) -> Vec<&str> {
        match self {
            TextureSource::Image(p) if p.starts_with(Self::SCENE) => Vec::new(),
            TextureSource::Image(p) => vec![p.as_str()],
            TextureSource::MipChain(v) => v.iter().map(String::as_str).collect(),
        }
    }
}

/// A node group (version 2): a subgraph used as a node, with its own interface.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[serde(expecting = "a group object { \"inputs\", \"nodes\", \"outputs\", … }")]
pub struct GroupDocument {
    /// What the group computes and where it comes from.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub doc: String,
    /// The group's inputs, read inside it by links to `@in.NAME`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub inputs: Vec<GroupInputDocument>,
    /// The nodes inside the group, as in a graph.
    pub nodes: Vec<NodeDocument>,
    /// The group's outputs, as a graph's.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub outputs: Vec<OutputDocument>,
}

/// One input of a group's interface.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[serde(expecting = "a group input object { \"name\", \"type\", … }")]
pub struct GroupInputDocument {
    /// The name instances set it by and the group reads it by (`@in.NAME`).
    pub name: String,
    /// Its type: float, vec2, vec3, vec4 or color.
    #[serde(rename = "type")]
    pub ty: String,
    /// Its value where an instance leaves it unset (the type's zero when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "Option<InputSchema>")]
    pub default: Option<serde_json::Value>,
    /// The range a slider offers, `[min, max]`.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        serialize_with = "shortest_array"
    )]
    pub soft_range: Option<[f32; 2]>,
    /// The range a literal on an instance must lie in, `[min, max]`.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        serialize_with = "shortest_array"
    )]
    pub hard_range: Option<[f32; 2]>,
    /// Its unit, as the node reference writes units ("nm", "rad", "1/m").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
    /// What it means.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub doc: String,
}

/// A frame (version 2): a labelled box around nodes in the editor. Layout only.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[serde(expecting = "a frame object { \"id\", \"label\", \"nodes\", … }")]
pub struct FrameDocument {
    /// Stable id, unique among the frames.
    pub id: String,
    /// The text shown on the frame.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub label: String,
    /// The ids of the (top-level) nodes it holds.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub nodes: Vec<String>,
    /// Its colour, sRGB components in [0, 1].
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        serialize_with = "shortest_array"
    )]
    pub color: Option<[f32; 3]>,
}

/// One output of the graph.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[serde(expecting = "an output object { \"name\", \"from\" }")]
pub struct OutputDocument {
    /// The name callers ask for.
    pub name: String,
    /// The node output it reads, written `node_id.output` (inside a group also
    /// `@in.NAME`).
    #[schemars(regex(pattern = r"^(@in|[A-Za-z0-9_-]+)\.[A-Za-z0-9_]+$"))]
    pub from: String,
}

/// One exposed parameter of the graph.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[serde(expecting = "a parameter object { \"name\", \"node\", … }")]
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
    /// The values it accepts, `[min, max]` (every component, for a vector): the file's
    /// value must lie in it, and a value set later (`--set`, the editor, the app API) outside
    /// it is refused.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        serialize_with = "shortest_array"
    )]
    pub range: Option<[f32; 2]>,
}

/// One declared variant: a named choice between alternative implementations.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[serde(expecting = "a variant object { \"choices\", \"default\", … }")]
pub struct VariantDocument {
    /// The choices, in the order the author wrote them.
    #[schemars(length(min = 1))]
    pub choices: Vec<String>,
    /// The choice used when none is selected; one of `choices`.
    pub default: String,
    /// What the variant trades (speed against error, a model against its reference).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub doc: String,
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
    /// The source, written `node_id.output`; inside a group `@in.NAME` reads its input.
    #[schemars(regex(pattern = r"^(@in|[A-Za-z0-9_-]+)\.[A-Za-z0-9_]+$"))]
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
    /// Removes the `value` of each `parameter` node the graph exposes: what is left
    /// compiles to the same shaders whatever those values (they reach a shader as
    /// uniforms), so it keys what is compiled.
    pub fn remove_parameter_values(&mut self) {
        let exposed: std::collections::BTreeSet<&str> =
            self.parameters.iter().map(|p| p.node.as_str()).collect();
        for n in &mut self.nodes {
            if n.node_type == "parameter" && exposed.contains(n.id.as_str()) {
                n.inputs.remove("value");
            }
        }
    }

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
        let doc =
            serde_json::from_str::<GraphDocument>(text).map_err(|e| structure_errors(text, &e))?;
        doc.check_features()?;
        Ok(doc)
    }

    /// The first version-2 feature the document uses, named as the format names it.
    pub fn newer_feature(&self) -> Option<&'static str> {
        let nodes = || {
            self.nodes
                .iter()
                .chain(self.groups.values().flat_map(|g| &g.nodes))
        };
        if !self.groups.is_empty() {
            Some("\"groups\"")
        } else if !self.frames.is_empty() {
            Some("\"frames\"")
        } else if nodes().any(|n| n.node_type == crate::group::GROUP || n.group.is_some()) {
            Some("nodes of type \"group\"")
        } else if nodes().any(|n| n.node_type == crate::group::REROUTE) {
            Some("nodes of type \"reroute\"")
        } else if nodes().any(|n| n.muted) {
            Some("\"muted\" nodes")
        } else if nodes().any(|n| n.color_space.is_some()) {
            Some("\"color_space\" on texture nodes")
        } else {
            None
        }
    }

    /// Refuses a document whose version is older than a feature it uses.
    pub fn check_features(&self) -> Result<(), Vec<GraphError>> {
        match self.newer_feature() {
            Some(feature) if self.version < GROUPS_VERSION => Err(vec![GraphError::NeedsVersion {
                feature: feature.to_owned(),
                found: self.version,
                needed: GROUPS_VERSION,
            }]),
            _ => Ok(()),
        }
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
    shortest_array(p, s)
}

/// Serialises f32 components with the shortest decimals that read back to the same f32s.
fn shortest_array<S: serde::Serializer, const N: usize>(
    p: &Option<[f32; N]>,
    s: S,
) -> Result<S::Ok, S::Error> {
    use crate::value::shortest_f64;
    match p {
        Some(v) => v.map(shortest_f64).serialize(s),
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
        let lines = LineStarts::new(text);
        for (i, node) in raw.nodes.iter().enumerate() {
            let slice = node.get();
            if let Err(ne) = serde_json::from_str::<NodeDocument>(slice) {
                let id = serde_json::from_str::<serde_json::Value>(slice)
                    .ok()
                    .and_then(|v| v.get("id").and_then(|id| id.as_str()).map(str::to_owned));
                let offset = slice.as_ptr() as usize - text.as_ptr() as usize;
                let (line, column) = lines.locate(offset, ne.line(), ne.column());
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

/// The byte offsets where the lines of a text start: built in one pass, so that locating
/// every error of a large file costs a binary search each rather than a rescan.
struct LineStarts(Vec<usize>);

impl LineStarts {
    fn new(text: &str) -> LineStarts {
        let mut starts = vec![0];
        starts.extend(
            text.bytes()
                .enumerate()
                .filter(|&(_, b)| b == b'\n')
                .map(|(i, _)| i + 1),
        );
        LineStarts(starts)
    }

    /// The 1-based line and column in the text of a position given (as serde_json gives it:
    /// 1-based line, column) relative to a slice starting at byte `offset`.
    fn locate(&self, offset: usize, line: usize, column: usize) -> (usize, usize) {
        // Lines starting at or before `offset`: the 1-based line of `offset`.
        let base_line = self.0.partition_point(|&s| s <= offset);
        let base_column = offset - self.0[base_line - 1];
        if line <= 1 {
            (base_line, base_column + column)
        } else {
            (base_line + line - 1, column)
        }
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
        let err = GraphDocument::parse(r#"{"version": 3, "future": true}"#).unwrap_err();
        assert_eq!(
            err,
            vec![GraphError::UnsupportedVersion {
                found: 3,
                supported: 2
            }]
        );
    }

    #[test]
    fn a_version_1_file_using_a_version_2_feature_names_both() {
        let text =
            r#"{"version": 1, "name": "g", "nodes": [{"id": "a", "type": "add", "muted": true}]}"#;
        let err = GraphDocument::parse(text).unwrap_err();
        assert_eq!(
            err[0].to_string(),
            "\"muted\" nodes need format version 2, the file says version 1: set \"version\": 2 (matgraph fmt --upgrade)"
        );
        assert!(GraphDocument::parse(&text.replace("\"version\": 1", "\"version\": 2")).is_ok());
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
