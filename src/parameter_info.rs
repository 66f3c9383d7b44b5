//! What an exposed parameter is to the person or app that sets it: its kind (a colour, a
//! direction, a scalar…), unit, soft range (a slider's) and hard range (what the CPU accepts
//! and the GPU clamps to), derived from the file's `parameters` entry and the declarations of
//! the inputs the parameter feeds. Written into the app contract (docs/integration.md, "The
//! parameter block") and read by the WGSL emitter's clamp.

use crate::graph::{Graph, GraphParameter, InputSource};
use crate::node::{InputDecl, PortType, Range};
use crate::types::{Conversion, SocketType};

/// What a parameter's value means, for choosing a widget or checking a value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParameterKind {
    /// One number.
    Scalar,
    /// A dimensionless linear (scene-referred) RGB value: a reflectance, a tint. An RGB
    /// quantity with a unit (an absorption coefficient in 1/m) is a [`ParameterKind::Vector`].
    Color,
    /// A unit vector (a normal, a light or view direction, an axis).
    Direction,
    /// A position in metres.
    Point,
    /// Any other vector.
    Vector,
    /// An integer.
    Integer,
    /// An integer naming one of [`ParameterInfo::choices`] by index.
    Choice,
    /// A boolean.
    Bool,
}

impl ParameterKind {
    /// The contract's spelling: `scalar`, `color`, `direction`, `point`, `vector`,
    /// `integer`, `choice` or `bool`.
    pub const fn name(self) -> &'static str {
        match self {
            ParameterKind::Scalar => "scalar",
            ParameterKind::Color => "color",
            ParameterKind::Direction => "direction",
            ParameterKind::Point => "point",
            ParameterKind::Vector => "vector",
            ParameterKind::Integer => "integer",
            ParameterKind::Choice => "choice",
            ParameterKind::Bool => "bool",
        }
    }
}

/// One exposed parameter as its user sees it.
#[derive(Clone, Debug, PartialEq)]
pub struct ParameterInfo {
    /// The name it is set by.
    pub name: String,
    /// Its type.
    pub ty: SocketType,
    /// What its value means.
    pub kind: ParameterKind,
    /// Its physical unit, when the inputs it feeds state one and agree ("" otherwise).
    pub unit: &'static str,
    /// The range a slider covers: the fed inputs' soft ranges, within the hard range (the
    /// hard range where no fed input has one), widened to hold the file's value.
    pub soft: Option<Range>,
    /// The range every component must lie in: the file's `range` and the hard range of every
    /// input it feeds whole (each component reaches the input: links with no conversion, a
    /// float broadcast, a vector truncated). The CPU refuses a value outside it; the render,
    /// library and compute modules clamp to it ([`crate::wgsl::ParameterClamp`]).
    pub hard: Option<Range>,
    /// The names of a choice parameter's values, from the input it feeds.
    pub choices: &'static [&'static str],
    /// The file's doc.
    pub doc: String,
    /// The file's group.
    pub group: Option<String>,
}

/// The inputs a parameter node's value reaches unchanged in meaning: links from its output,
/// and through forwarding nodes (reroutes, muted nodes) links from theirs. Each is the fed
/// input's declaration and the link's conversion.
fn fed_inputs<'g>(
    graph: &'g Graph,
    uses: &[Vec<(usize, usize, Conversion)>],
    p: usize,
) -> Vec<(&'g InputDecl, Conversion)> {
    let nodes = graph.nodes();
    let mut out = Vec::new();
    let mut stack = vec![p];
    while let Some(i) = stack.pop() {
        for &(n, k, c) in &uses[i] {
            if nodes[n].forwards() {
                stack.push(n);
            } else {
                out.push((&nodes[n].node_type.inputs()[k], c));
            }
        }
    }
    out
}

fn intersect(a: Option<Range>, b: Range) -> Option<Range> {
    Some(match a {
        None => b,
        Some(a) => Range {
            min: a.min.max(b.min),
            max: a.max.min(b.max),
        },
    })
}

/// Whether an input of vec3 type holds a direction: its doc says it is a unit vector, or its
/// name is one every node uses for a direction.
fn is_direction(decl: &InputDecl) -> bool {
    let doc = decl.doc.to_ascii_lowercase();
    doc.starts_with("unit ")
        || doc.contains(" unit vector")
        || doc.contains("direction")
        || matches!(
            decl.name,
            "normal" | "view" | "light" | "direction" | "axis" | "tangent"
        )
}

/// Whether a vec3 parameter holds a colour: it feeds a colour input, or its name says so
/// (a colour multiplied into another goes through generic math nodes).
fn is_color(p: &GraphParameter, fed: &[(&InputDecl, Conversion)]) -> bool {
    let name = p.name.to_ascii_lowercase();
    p.ty == SocketType::Color
        || fed
            .iter()
            .any(|(d, _)| d.ty == PortType::Fixed(SocketType::Color))
        || ["color", "colour", "tint", "albedo"]
            .iter()
            .any(|w| name.contains(w))
}

/// The info of one parameter.
fn info(
    graph: &Graph,
    uses: &[Vec<(usize, usize, Conversion)>],
    p: &GraphParameter,
) -> ParameterInfo {
    let fed = fed_inputs(graph, uses, p.node);
    let whole = |c: Conversion| {
        matches!(
            c,
            Conversion::Identity | Conversion::Broadcast | Conversion::Truncate
        )
    };
    let mut hard = p.range;
    let mut soft: Option<Range> = None;
    for (decl, c) in &fed {
        if !whole(*c) {
            continue;
        }
        if let Some(r) = decl.hard {
            hard = intersect(hard, r);
        }
        if let Some(r) = decl.soft {
            soft = intersect(soft, r);
        }
    }
    // The slider stays inside what is accepted; an empty overlap falls back to the hard range.
    let soft = match (soft, hard) {
        (Some(s), Some(h)) => {
            let s = Range {
                min: s.min.max(h.min),
                max: s.max.min(h.max),
            };
            Some(if s.min <= s.max { s } else { h })
        }
        (s, h) => s.or(h),
    };
    // A slider holds the file's value (water_sunshine's `tiling` of 12 over a soft 0..10).
    let soft = soft.map(|r| {
        p.default.lanes().iter().fold(r, |r, &x| Range {
            min: r.min.min(x),
            max: r.max.max(x),
        })
    });
    let units: Vec<&'static str> = fed
        .iter()
        .map(|(d, _)| d.unit)
        .filter(|u| !u.is_empty())
        .collect();
    let unit = match units.first() {
        Some(u) if units.iter().all(|v| v == u) => *u,
        _ => "",
    };
    let choices = fed
        .iter()
        .find(|(d, _)| !d.choices.is_empty())
        .map_or(&[][..], |(d, _)| d.choices);
    let kind = match p.ty {
        SocketType::Bool => ParameterKind::Bool,
        SocketType::Int if !choices.is_empty() => ParameterKind::Choice,
        SocketType::Int => ParameterKind::Integer,
        SocketType::Color | SocketType::Vec3 if unit.is_empty() && is_color(p, &fed) => {
            ParameterKind::Color
        }
        SocketType::Float => ParameterKind::Scalar,
        SocketType::Vec3 if unit == "m" => ParameterKind::Point,
        SocketType::Color => ParameterKind::Vector,
        SocketType::Vec3 if !fed.is_empty() && fed.iter().all(|(d, _)| is_direction(d)) => {
            ParameterKind::Direction
        }
        SocketType::Vec2 | SocketType::Vec3 | SocketType::Vec4 => ParameterKind::Vector,
    };
    ParameterInfo {
        name: p.name.clone(),
        ty: p.ty,
        kind,
        unit,
        soft,
        hard,
        choices,
        doc: p.doc.clone(),
        group: p.group.clone(),
    }
}

/// The info of every exposed parameter of `graph`, in the file's order.
pub fn parameter_info(graph: &Graph) -> Vec<ParameterInfo> {
    let nodes = graph.nodes();
    let mut uses: Vec<Vec<(usize, usize, Conversion)>> = vec![Vec::new(); nodes.len()];
    for (n, node) in nodes.iter().enumerate() {
        for (k, src) in node.inputs.iter().enumerate() {
            if let InputSource::Link(r, c) = src {
                uses[r.node].push((n, k, *c));
            }
        }
    }
    graph
        .parameters()
        .iter()
        .map(|p| info(graph, &uses, p))
        .collect()
}
