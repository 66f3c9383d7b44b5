//! The `bump` node's heights one pixel over: the subgraph under its `height` input evaluated
//! a second and a third time with the positions and uvs moved by their screen derivatives
//! (Cycles' bump evaluation, `svm_node_enter_bump_eval` and the `*_bump_dx/dy` texture
//! coordinate nodes), written into the graph as ordinary nodes so that the CPU plan and the
//! WGSL emitter compile the same thing.
//!
//! For each `bump` node whose `height_dx`/`height_dy` are unlinked, the nodes under `height`
//! that depend on a position or a uv (a `geometry.position`, `geometry.uv` or
//! `texture_coordinate` output) are copied twice; in the copies, each read of such an output
//! `a` becomes `a + ∂a/∂x` (resp. `∂a/∂y`) through an `add` node fed by
//! `position_derivatives` or `uv_derivatives`; `height_dx`, `height_dy` are linked to the
//! copies' `height`. Nodes under `height` that depend on neither (parameters, constants,
//! textures of a fixed coordinate) are shared, not copied. Unlinked `position_dx`,
//! `position_dy` are linked to `position_derivatives` and an unlinked `normal` to
//! `geometry.normal` (Blender's default, the shading normal). Other coordinates are not moved
//! (stated on the node). A graph without `bump` nodes is returned as it is.
//!
//! The copies keep the ids of the nodes they copy, so a message about one names the node the
//! user wrote; the graph as saved ([`Graph::to_document`]) is unchanged: only plans and shaders
//! see the copies.

use std::borrow::Cow;
use std::collections::HashMap;

use crate::graph::{Graph, InputSource, Node, NodeIndex, OutputRef};
use crate::node::{Attribute, Evaluation, NodeType};
use crate::registry::Registry;
use crate::types::{Conversion, SocketType};

/// The bump node type's name.
pub const BUMP: &str = "bump";

// The bump node's inputs, in port order (nodes/bump.rs).
const HEIGHT: usize = 0;
const NORMAL: usize = 4;
const HEIGHT_DX: usize = 5;
const HEIGHT_DY: usize = 6;
const POSITION_DX: usize = 7;
const POSITION_DY: usize = 8;

/// `graph` with every `bump` node's unlinked `height_dx`, `height_dy`, `position_dx`,
/// `position_dy` and `normal` filled (see the module doc); borrowed when there is none to fill.
pub fn expand(graph: &Graph) -> Cow<'_, Graph> {
    let pending = |g: &Graph| -> Vec<NodeIndex> {
        g.order()
            .iter()
            .copied()
            .filter(|&i| {
                let n = &g.nodes()[i];
                n.node_type.name() == BUMP
                    && !n.muted
                    && [HEIGHT_DX, HEIGHT_DY, POSITION_DX, POSITION_DY, NORMAL]
                        .iter()
                        .any(|&k| matches!(n.inputs[k], InputSource::Default(_)))
            })
            .collect()
    };
    let bumps = pending(graph);
    if bumps.is_empty() {
        return Cow::Borrowed(graph);
    }
    let mut g = graph.clone();
    for b in bumps {
        Expansion::new(&mut g, b).run();
    }
    Cow::Owned(g)
}

/// The attribute an output of an attribute node reads, when it is one the shifted
/// evaluations move, with the derivative node type that moves it.
fn moved(node: &Node, output: usize) -> Option<(Attribute, &'static str)> {
    let Evaluation::Attributes(attrs) = node.node_type.evaluation() else {
        return None;
    };
    match attrs.get(output)? {
        Attribute::Position => Some((Attribute::Position, "position_derivatives")),
        Attribute::Uv => Some((Attribute::Uv, "uv_derivatives")),
        _ => None,
    }
}

/// One bump node's expansion: the nodes it adds go into the order just before it.
struct Expansion<'g> {
    g: &'g mut Graph,
    bump: NodeIndex,
    id: String,
    added: Vec<NodeIndex>,
    /// The derivative and geometry nodes added, by type name.
    sources: HashMap<&'static str, NodeIndex>,
    /// `a + ∂a` per (attribute output read, axis).
    sums: HashMap<(OutputRef, usize), NodeIndex>,
}

impl<'g> Expansion<'g> {
    fn new(g: &'g mut Graph, bump: NodeIndex) -> Expansion<'g> {
        let id = g.nodes()[bump].id.clone();
        Expansion {
            g,
            bump,
            id,
            added: Vec::new(),
            sources: HashMap::new(),
            sums: HashMap::new(),
        }
    }

    fn run(mut self) {
        let inputs = self.g.nodes()[self.bump].inputs.clone();
        let unlinked = |k: usize| matches!(inputs[k], InputSource::Default(_));
        if unlinked(NORMAL) {
            let geometry = self.source("geometry");
            let normal = Attribute::Normal;
            let k = self.attribute_output(geometry, normal);
            self.set_input(NORMAL, link(geometry, k));
        }
        for (port, axis) in [(POSITION_DX, 0), (POSITION_DY, 1)] {
            if unlinked(port) {
                let d = self.source("position_derivatives");
                self.set_input(port, link(d, axis));
            }
        }
        for (port, axis) in [(HEIGHT_DX, 0), (HEIGHT_DY, 1)] {
            if unlinked(port) {
                let shifted = self.shifted(&inputs[HEIGHT], axis);
                self.set_input(port, shifted);
            }
        }
        // The added nodes go just before the bump, in the order they were made: each reads
        // only nodes before the bump or added before it.
        let mut order = self.g.order().to_vec();
        let at = order
            .iter()
            .position(|&i| i == self.bump)
            .expect("bump in order");
        order.splice(at..at, self.added.iter().copied());
        self.g.set_order(order);
    }

    /// `height`'s source with the positions and uvs under it moved one pixel along `axis`.
    fn shifted(&mut self, height: &InputSource, axis: usize) -> InputSource {
        let InputSource::Link(r, c) = height else {
            return height.clone();
        };
        let (r, c) = (*r, *c);
        // The nodes under `height` that read a moved attribute, in evaluation order.
        let mut depends: HashMap<NodeIndex, bool> = HashMap::new();
        self.depends(r.node, &mut depends);
        if moved(&self.g.nodes()[r.node], r.output).is_some() {
            let sum = self.sum(r, axis);
            return InputSource::Link(
                OutputRef {
                    node: sum,
                    output: 0,
                },
                c,
            );
        }
        if !depends[&r.node] {
            return height.clone();
        }
        let position: HashMap<NodeIndex, usize> = self
            .g
            .order()
            .iter()
            .enumerate()
            .map(|(k, &i)| (i, k))
            .collect();
        let mut copied: Vec<NodeIndex> = depends
            .iter()
            .filter(|&(_, &d)| d)
            .map(|(&i, _)| i)
            .collect();
        copied.sort_by_key(|i| position.get(i).copied().unwrap_or(usize::MAX));
        let mut copies: HashMap<NodeIndex, NodeIndex> = HashMap::new();
        for i in copied {
            let mut node = self.g.nodes()[i].clone();
            for k in 0..node.inputs.len() {
                let InputSource::Link(src, conv) = node.inputs[k].clone() else {
                    continue;
                };
                if moved(&self.g.nodes()[src.node], src.output).is_some() {
                    let sum = self.sum(src, axis);
                    node.inputs[k] = InputSource::Link(
                        OutputRef {
                            node: sum,
                            output: 0,
                        },
                        conv,
                    );
                } else if let Some(&copy) = copies.get(&src.node) {
                    node.inputs[k] = InputSource::Link(
                        OutputRef {
                            node: copy,
                            output: src.output,
                        },
                        conv,
                    );
                }
            }
            let copy = self.push(node);
            copies.insert(i, copy);
        }
        InputSource::Link(
            OutputRef {
                node: copies[&r.node],
                output: r.output,
            },
            c,
        )
    }

    /// Whether node `i` reads a moved attribute output, directly or through its inputs,
    /// memoised in `memo` for every node under it.
    fn depends(&self, i: NodeIndex, memo: &mut HashMap<NodeIndex, bool>) -> bool {
        if let Some(&d) = memo.get(&i) {
            return d;
        }
        // Iterative: graphs may be deep chains.
        let mut stack = vec![(i, false)];
        while let Some((n, expanded)) = stack.pop() {
            if memo.contains_key(&n) {
                continue;
            }
            let node = &self.g.nodes()[n];
            let links = node.used_inputs().filter_map(|s| match s {
                InputSource::Link(r, _) => Some(*r),
                _ => None,
            });
            if !expanded {
                stack.push((n, true));
                for r in links {
                    if !memo.contains_key(&r.node) {
                        stack.push((r.node, false));
                    }
                }
                continue;
            }
            let d = links.into_iter().any(|r| {
                moved(&self.g.nodes()[r.node], r.output).is_some()
                    || memo.get(&r.node).copied().unwrap_or(false)
            });
            memo.insert(n, d);
        }
        memo[&i]
    }

    /// The `add` node giving attribute output `r` moved one pixel along `axis`.
    fn sum(&mut self, r: OutputRef, axis: usize) -> NodeIndex {
        if let Some(&s) = self.sums.get(&(r, axis)) {
            return s;
        }
        let (attribute, derivatives) =
            moved(&self.g.nodes()[r.node], r.output).expect("a moved attribute");
        let d = self.source(derivatives);
        let ty = attribute.ty();
        let add = builtin("add");
        let node = Node {
            id: self.id.clone(),
            node_type: add,
            data_type: Some(ty),
            generic: ty,
            inputs: vec![
                InputSource::Link(r, conversion(self.g.output_type(r), ty)),
                InputSource::Link(
                    OutputRef {
                        node: d,
                        output: axis,
                    },
                    Conversion::Identity,
                ),
            ],
            texture: None,
            color_space: None,
            position: None,
            muted: false,
        };
        let s = self.push(node);
        self.sums.insert((r, axis), s);
        s
    }

    /// The added node of type `name` without inputs (a geometry or derivative node).
    fn source(&mut self, name: &'static str) -> NodeIndex {
        if let Some(&i) = self.sources.get(name) {
            return i;
        }
        let node = Node {
            id: self.id.clone(),
            node_type: builtin(name),
            data_type: None,
            generic: SocketType::Float,
            inputs: Vec::new(),
            texture: None,
            color_space: None,
            position: None,
            muted: false,
        };
        let i = self.push(node);
        self.sources.insert(name, i);
        i
    }

    /// The output of attribute node `node` that reads `a`.
    fn attribute_output(&self, node: NodeIndex, a: Attribute) -> usize {
        match self.g.nodes()[node].node_type.evaluation() {
            Evaluation::Attributes(attrs) => attrs.iter().position(|&x| x == a),
            _ => None,
        }
        .expect("the geometry node reads the attribute")
    }

    fn push(&mut self, node: Node) -> NodeIndex {
        let i = self.g.push_node(node);
        self.added.push(i);
        i
    }

    fn set_input(&mut self, k: usize, source: InputSource) {
        self.g.node_mut(self.bump).inputs[k] = source;
    }
}

/// A link from output `output` of `node`, of the type the bump's port has.
fn link(node: NodeIndex, output: usize) -> InputSource {
    InputSource::Link(OutputRef { node, output }, Conversion::Identity)
}

/// The conversion of a link from `from` to `to` where the two differ only as a colour and a
/// vec3 do (the attribute outputs are of their attribute's type).
fn conversion(from: SocketType, to: SocketType) -> Conversion {
    from.conversion_to(to).unwrap_or(Conversion::Identity)
}

/// A built-in node type the expansion adds (registered by `nodes::all`).
fn builtin(name: &str) -> std::sync::Arc<NodeType> {
    Registry::builtin()
        .get(name)
        .unwrap_or_else(|| panic!("built-in node type '{name}'"))
        .clone()
}
