//! Errors found while reading and validating a graph, each naming the node and input at fault.

use crate::types::SocketType;
use std::fmt;
use std::path::PathBuf;

/// How many errors [`GraphErrors`] prints per file before "… and N more", and how many
/// nodes of a long cycle [`GraphError::Cycle`] names at each end.
pub const MAX_SHOWN: usize = 50;

/// One problem in a graph document. Every variant names the place at fault.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GraphError {
    /// The file could not be read (missing, a folder, not a regular file, an I/O error);
    /// the message names the file and why.
    #[error("{message}")]
    Unreadable {
        /// What went wrong, e.g. "cannot read x.json: no such file".
        message: String,
    },
    /// The text is not JSON.
    #[error("malformed JSON at line {line}, column {column}: {message}")]
    Syntax {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What the parser expected.
        message: String,
    },
    /// JSON that does not have the graph format's shape (unknown field, wrong kind of value).
    #[error("{}{message} at line {line}, column {column}", at_node(.node))]
    Structure {
        /// The node whose entry is malformed, when the problem is inside one.
        node: Option<String>,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// No `version` field.
    #[error("missing format version: add \"version\": {supported}")]
    MissingVersion {
        /// The version this build writes.
        supported: u32,
    },
    /// A version this build does not read.
    #[error(
        "format version {found} is newer than the newest supported ({supported}); update matgraph"
    )]
    UnsupportedVersion {
        /// The file's version.
        found: u64,
        /// The newest version this build reads.
        supported: u32,
    },
    /// A version-1 file that uses a version-2 feature.
    #[error(
        "{feature} need format version {needed}, the file says version {found}: set \"version\": {needed} (matgraph fmt --upgrade)"
    )]
    NeedsVersion {
        /// The feature, as the format names it.
        feature: String,
        /// The file's version.
        found: u32,
        /// The version the feature needs.
        needed: u32,
    },
    /// A problem inside a group instance: `node` is the instance (in the graph the error is
    /// reported for), `group` the group it uses, `error` the problem inside, itself possibly
    /// inside a nested instance.
    #[error("node '{node}' (group {group}) → {error}")]
    InGroup {
        /// The instance node.
        node: String,
        /// The group it uses, as written (`NAME`, `PATH#NAME`, `PATH`).
        group: String,
        /// The problem inside.
        error: Box<GraphError>,
    },
    /// A group node whose group cannot be found or read.
    #[error("node '{node}': group '{group}': {message}{}", did_you_mean(.suggestion))]
    BadGroup {
        /// The instance node.
        node: String,
        /// The group reference as written.
        group: String,
        /// What is wrong (no such group, the file cannot be read, ...).
        message: String,
        /// The nearest group name.
        suggestion: Option<String>,
    },
    /// A group that uses itself, directly or through other groups and files.
    #[error("group recursion: {}", .chain.join(" → "))]
    GroupRecursion {
        /// The groups from the first to its repetition, `file#name`.
        chain: Vec<String>,
    },
    /// A link that reads a group's input it has not (`@in.x`), `@in` outside a group, or an
    /// output a group node has not.
    #[error("node '{node}': input '{input}': {message}")]
    GroupLink {
        /// The node.
        node: String,
        /// The input.
        input: String,
        /// What is wrong.
        message: String,
    },
    /// Groups nested deeper than [`crate::group::MAX_DEPTH`].
    #[error("node '{node}': groups nest deeper than {max} levels (through {group})")]
    GroupTooDeep {
        /// The instance at the limit.
        node: String,
        /// The group it uses.
        group: String,
        /// The limit.
        max: usize,
    },
    /// Groups whose instances, once inlined, would make more nodes than
    /// [`crate::group::expansion_limit`] allows for the nodes written (a group using another
    /// twice, many levels deep, doubles at each level); refused before the nodes are copied.
    #[error(
        "node '{node}': group {group} makes the graph larger than {max} nodes once inlined, \
         from {written} written (each instance copies its group's nodes, so groups using \
         groups multiply; a graph may have {} nodes, or {} times the nodes written, whichever \
         is more, and never more than {})",
        crate::group::AMPLIFICATION_THRESHOLD,
        crate::group::MAX_AMPLIFICATION,
        crate::group::MAX_EXPANDED_NODES
    )]
    GroupTooLarge {
        /// The instance whose copy would pass the limit.
        node: String,
        /// The group it uses, as written on it.
        group: String,
        /// The limit for this graph.
        max: usize,
        /// The nodes written (the top graph's, each group's once).
        written: usize,
    },
    /// An input of a group's interface that is malformed (unknown type, default of the wrong
    /// type or outside its hard range, ranges the wrong way round, a repeated name).
    #[error("group '{group}': input '{input}': {message}")]
    BadGroupInput {
        /// The group.
        group: String,
        /// The interface input.
        input: String,
        /// What is wrong.
        message: String,
    },
    /// A frame that is malformed (repeated id, a node that does not exist).
    #[error("frame '{frame}': {message}")]
    BadFrame {
        /// The frame.
        frame: String,
        /// What is wrong.
        message: String,
    },
    /// Two nodes share an id.
    #[error("node '{node}': duplicate node id")]
    DuplicateId {
        /// The repeated id.
        node: String,
    },
    /// A node id that cannot be used in links.
    #[error("node '{node}': invalid node id (use letters, digits, '_' and '-', no '.')")]
    InvalidId {
        /// The id.
        node: String,
    },
    /// An editor position that is not a pair of finite f32 numbers.
    #[error("node '{node}': position must be two finite numbers within the f32 range")]
    BadPosition {
        /// The node.
        node: String,
    },
    /// A texture node without an image, or an image on a node that samples none.
    #[error("node '{node}': {message}")]
    BadTexture {
        /// The node.
        node: String,
        /// What is wrong.
        message: String,
    },
    /// The node's type is not registered.
    #[error("node '{node}': unknown node type '{type_name}'{}", did_you_mean(.suggestion))]
    UnknownNodeType {
        /// The node.
        node: String,
        /// The type it names.
        type_name: String,
        /// The nearest registered name.
        suggestion: Option<String>,
    },
    /// A `data_type` that the node does not accept.
    #[error("node '{node}': data_type '{data_type}' is not one of {allowed}")]
    BadDataType {
        /// The node.
        node: String,
        /// The data type written.
        data_type: String,
        /// The accepted types.
        allowed: String,
    },
    /// An input the node type does not have.
    #[error("node '{node}': unknown input '{input}'{}", did_you_mean(.suggestion))]
    UnknownInput {
        /// The node.
        node: String,
        /// The input named.
        input: String,
        /// The nearest input name.
        suggestion: Option<String>,
    },
    /// A literal of the wrong type for its input.
    #[error("node '{node}': input '{input}': expected {expected}, found {found}")]
    WrongValueType {
        /// The node.
        node: String,
        /// The input.
        input: String,
        /// What the input takes.
        expected: String,
        /// What the file holds.
        found: String,
    },
    /// A literal outside the input's hard range.
    #[error("node '{node}': input '{input}': value {value} is outside [{min}, {max}]")]
    OutOfRange {
        /// The node.
        node: String,
        /// The input.
        input: String,
        /// The value written.
        value: String,
        /// Lower bound.
        min: f32,
        /// Upper bound.
        max: f32,
    },
    /// A parameter's value outside the hard range of an input it feeds (see
    /// [`crate::graph::Feed`]).
    #[error(
        "parameter '{name}' (node '{node}'): value {value} is outside [{min}, {max}], the range of input '{input}' of node '{target}' it feeds"
    )]
    ParameterOutOfRange {
        /// The parameter's name (the node id when the graph does not expose it).
        name: String,
        /// The `parameter` node.
        node: String,
        /// The node whose input it feeds.
        target: String,
        /// That input.
        input: String,
        /// The value as the input sees it.
        value: String,
        /// Lower bound.
        min: f32,
        /// Upper bound.
        max: f32,
    },
    /// A link that is not written `node_id.output`.
    #[error("node '{node}': input '{input}': link '{link}' must be written \"node_id.output\"")]
    BadLink {
        /// The node.
        node: String,
        /// The input.
        input: String,
        /// The link text.
        link: String,
    },
    /// A link to a node that does not exist.
    #[error("node '{node}': input '{input}': link to missing node '{target}'{}", did_you_mean(.suggestion))]
    MissingNode {
        /// The node.
        node: String,
        /// The input.
        input: String,
        /// The node id linked to.
        target: String,
        /// The nearest node id.
        suggestion: Option<String>,
    },
    /// A link to an output the source node does not have.
    #[error("node '{node}': input '{input}': node '{target}' has no output '{output}'{}", did_you_mean(.suggestion))]
    MissingOutput {
        /// The node.
        node: String,
        /// The input.
        input: String,
        /// The source node.
        target: String,
        /// The output named.
        output: String,
        /// The nearest output name.
        suggestion: Option<String>,
    },
    /// A link between types with no implicit conversion.
    #[error(
        "node '{node}': input '{input}': cannot connect '{from}' ({from_type}) to '{node}.{input}' ({to_type}): no implicit conversion"
    )]
    TypeMismatch {
        /// The node.
        node: String,
        /// The input.
        input: String,
        /// The source, `node.output`.
        from: String,
        /// The source's type.
        from_type: SocketType,
        /// The input's type.
        to_type: SocketType,
    },
    /// The links form a cycle.
    #[error("cycle through nodes {}", cycle_text(.nodes))]
    Cycle {
        /// The nodes on the cycle, in link order.
        nodes: Vec<String>,
    },
    /// A graph output that is malformed or points at nothing.
    #[error("graph output '{name}': {message}")]
    BadOutput {
        /// The output's name.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// A graph parameter that is malformed or points at something other than a parameter node.
    #[error("parameter '{name}': {message}")]
    BadParameter {
        /// The parameter's name.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// A declared variant that is malformed (no choices, a repeated choice, a default not
    /// among its choices).
    #[error("variant '{variant}': {field}: {message}{}", did_you_mean(.suggestion))]
    BadVariant {
        /// The variant's name.
        variant: String,
        /// The field at fault (`choices`, `default`).
        field: String,
        /// What is wrong.
        message: String,
        /// The nearest choice, for a default not among them.
        suggestion: Option<String>,
    },
    /// A `switch` node naming a variant the graph does not declare (or none), or a `variant`
    /// field on a node that is not a switch.
    #[error("node '{node}': variant: {message}{}", did_you_mean(.suggestion))]
    BadSwitch {
        /// The node.
        node: String,
        /// What is wrong.
        message: String,
        /// The nearest declared variant.
        suggestion: Option<String>,
    },
    /// A `switch` input that is missing, not a link, not one of the variant's choices, or
    /// whose type differs from the other choices'.
    #[error("node '{node}': input '{input}': {message}{}", did_you_mean(.suggestion))]
    BadSwitchInput {
        /// The switch node.
        node: String,
        /// The input (a choice's name).
        input: String,
        /// What is wrong.
        message: String,
        /// The nearest choice, for an input that is not one.
        suggestion: Option<String>,
    },
    /// A variant selection (`--variant NAME=CHOICE`) naming an unknown variant or choice.
    #[error("--variant {variant}={choice}: {message}{}", did_you_mean(.suggestion))]
    BadSelection {
        /// The variant named.
        variant: String,
        /// The choice named.
        choice: String,
        /// What is wrong.
        message: String,
        /// The nearest variant or choice.
        suggestion: Option<String>,
    },
}

fn at_node(node: &Option<String>) -> String {
    node.as_ref()
        .map(|n| format!("node '{n}': "))
        .unwrap_or_default()
}

/// `a -> b -> a`; a cycle longer than twice [`MAX_SHOWN`] shows its first and last
/// `MAX_SHOWN` nodes around "-> … (N more) ->".
fn cycle_text(nodes: &[String]) -> String {
    if nodes.len() <= 2 * MAX_SHOWN {
        return nodes.join(" -> ");
    }
    format!(
        "{} -> … ({} more) -> {}",
        nodes[..MAX_SHOWN].join(" -> "),
        nodes.len() - 2 * MAX_SHOWN,
        nodes[nodes.len() - MAX_SHOWN..].join(" -> ")
    )
}

/// " (did you mean 'S'?)" for a suggestion `S`, else nothing.
pub(crate) fn did_you_mean(s: &Option<String>) -> String {
    s.as_ref()
        .map(|s| format!(" (did you mean '{s}'?)"))
        .unwrap_or_default()
}

impl GraphError {
    /// The id of the node at fault, when there is one.
    pub fn node(&self) -> Option<&str> {
        use GraphError::*;
        match self {
            Structure { node, .. } => node.as_deref(),
            DuplicateId { node }
            | InvalidId { node }
            | BadPosition { node }
            | BadTexture { node, .. }
            | UnknownNodeType { node, .. }
            | BadDataType { node, .. }
            | UnknownInput { node, .. }
            | WrongValueType { node, .. }
            | OutOfRange { node, .. }
            | ParameterOutOfRange { node, .. }
            | BadLink { node, .. }
            | MissingNode { node, .. }
            | MissingOutput { node, .. }
            | TypeMismatch { node, .. }
            | BadSwitch { node, .. }
            | BadSwitchInput { node, .. } => Some(node),
            InGroup { node, .. }
            | BadGroup { node, .. }
            | GroupTooDeep { node, .. }
            | GroupTooLarge { node, .. }
            | GroupLink { node, .. } => Some(node),
            Cycle { nodes } => nodes.first().map(String::as_str),
            _ => None,
        }
    }

    /// The other node an error names (a link's target, a mismatched link's source), to be
    /// rewritten with [`GraphError::node_mut`].
    pub(crate) fn target_mut(&mut self) -> Option<&mut String> {
        use GraphError::*;
        match self {
            MissingNode { target, .. } | MissingOutput { target, .. } => Some(target),
            TypeMismatch { from, .. } => Some(from),
            _ => None,
        }
    }

    /// The node id at fault, to be rewritten (see [`crate::group`]'s error paths).
    pub(crate) fn node_mut(&mut self) -> Option<&mut String> {
        use GraphError::*;
        match self {
            Structure { node, .. } => node.as_mut(),
            DuplicateId { node }
            | InvalidId { node }
            | BadPosition { node }
            | BadTexture { node, .. }
            | UnknownNodeType { node, .. }
            | BadDataType { node, .. }
            | UnknownInput { node, .. }
            | WrongValueType { node, .. }
            | OutOfRange { node, .. }
            | BadLink { node, .. }
            | MissingNode { node, .. }
            | MissingOutput { node, .. }
            | TypeMismatch { node, .. }
            | BadSwitch { node, .. }
            | BadSwitchInput { node, .. }
            | InGroup { node, .. }
            | BadGroup { node, .. }
            | GroupTooDeep { node, .. }
            | GroupTooLarge { node, .. }
            | GroupLink { node, .. } => Some(node),
            ParameterOutOfRange { target, .. } => Some(target),
            _ => None,
        }
    }

    /// The input at fault, when there is one.
    pub(crate) fn input_mut(&mut self) -> Option<&mut String> {
        use GraphError::*;
        match self {
            UnknownInput { input, .. }
            | WrongValueType { input, .. }
            | OutOfRange { input, .. }
            | BadLink { input, .. }
            | MissingNode { input, .. }
            | MissingOutput { input, .. }
            | TypeMismatch { input, .. }
            | BadSwitchInput { input, .. }
            | GroupLink { input, .. }
            | ParameterOutOfRange { input, .. } => Some(input),
            _ => None,
        }
    }
}

/// Every problem found in one graph, attributed to its source (a file path or a label).
#[derive(Clone, Debug, PartialEq)]
pub struct GraphErrors {
    /// Where the graph came from.
    pub source: PathBuf,
    /// The problems, in the order found.
    pub errors: Vec<GraphError>,
}

/// One error a line, each prefixed by the source; past [`MAX_SHOWN`] errors the rest are
/// counted in a last line "SOURCE: … and N more errors".
impl fmt::Display for GraphErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, e) in self.errors.iter().take(MAX_SHOWN).enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            // One line per error: its user text (ids, names, paths) spelt out, line
            // breaks included.
            let line = format!("{}: {e}", self.source.display());
            write!(f, "{}", crate::visible::visible(&line))?;
        }
        if self.errors.len() > MAX_SHOWN {
            let more = self.errors.len() - MAX_SHOWN;
            write!(
                f,
                "\n{}: … and {more} more error{}",
                self.source.display(),
                if more == 1 { "" } else { "s" }
            )?;
        }
        Ok(())
    }
}

impl std::error::Error for GraphErrors {}
