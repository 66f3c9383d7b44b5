//! Which group instances a module calls as one WGSL function each, and the bodies of those
//! functions.
//!
//! The CPU plan sees a grouped graph with its groups inlined ([`crate::group`]), and so does
//! constant folding. The WGSL keeps a group's body once: the instances of one group whose
//! used outputs are the same share one function `mg_group_K`, each instance a call to it, so
//! that a module with 50 instances of a group is not 50 times the size of one.
//!
//! An instance is **specialised** (its nodes emitted inline, folded as the plan folded them)
//! where that pays, **called** otherwise:
//! - its used outputs all fold to constants: nothing of it is emitted (the plan folded it);
//! - it is the only instance of its group (and of its used outputs) at its depth, and no
//!   function for them exists yet: inlined, so constants fold through it as through any
//!   node, and no call is paid for;
//! - a node of its body is a `parameter` (each instance has its own uniform): inlined;
//! - it lies in a called instance: part of that function's body;
//! - otherwise it is called. Its literal inputs are arguments: the driver's compiler folds
//!   them after inlining the call, which is what specialising it would have bought.

use crate::graph::{Graph, InputSource, NodeIndex, OutputRef};
use crate::node::{Attribute, Evaluation};
use crate::plan::Plan;
use crate::types::SocketType;
use std::collections::{HashMap, HashSet};

/// One called instance.
pub(super) struct GroupCall {
    /// Index of its function in [`GroupPlan::functions`].
    pub function: usize,
    /// The nodes carrying its inputs, in the group's input order.
    pub inputs: Vec<NodeIndex>,
    /// Its path, for the call's variable name.
    pub path: String,
    /// Whether its body reads the light (so the call is in the lit part of a render
    /// module).
    pub reads_light: bool,
}

/// One group function.
pub(super) struct GroupFunction {
    /// Its WGSL name.
    pub name: String,
    /// The name of its result struct.
    pub out_struct: String,
    /// The group as written on the instance it was made from.
    pub label: String,
    /// The instance whose nodes are its body.
    pub rep: usize,
    /// The result members: name, type, and the output reroute of the representative.
    pub members: Vec<(String, SocketType, NodeIndex)>,
    /// The body's calls, in graph order.
    pub body: Vec<NodeIndex>,
    /// The nodes of the body whose values depend on the instance's inputs (not folded in
    /// the body even where the representative's plan folded them).
    pub varying: HashSet<NodeIndex>,
    /// Per input: the argument every call passes alike, written into the body instead.
    pub baked: Vec<Option<String>>,
}

/// What the module does with the graph's instances.
#[derive(Default)]
pub(super) struct GroupPlan {
    /// The calls, by the node that stands for each: its first used output's reroute.
    pub calls: HashMap<NodeIndex, GroupCall>,
    /// For each used output reroute of a called instance: the call's node and the member.
    pub out_of: HashMap<NodeIndex, (NodeIndex, usize)>,
    /// The nodes inside called instances (emitted in the functions, not in the material).
    pub hidden: HashSet<NodeIndex>,
    /// The functions, in first-use order.
    pub functions: Vec<GroupFunction>,
    /// The calls of every function body.
    pub body_calls: HashSet<NodeIndex>,
}

impl GroupPlan {
    /// Decides, for every instance of `graph`, whether it is called (see the module doc).
    pub(super) fn new(graph: &Graph, plan: &Plan) -> GroupPlan {
        let mut out = GroupPlan::default();
        let Some(instances) = graph.instances() else {
            return out;
        };
        let nodes = graph.nodes();
        let list = &instances.list;
        // The function of each (group, used outputs, input types), by key; `None` where the
        // group is inlined.
        type Key = (String, Vec<usize>, Vec<SocketType>);
        let mut by_key: HashMap<Key, Option<usize>> = HashMap::new();
        let mut called: HashSet<&str> = HashSet::new();
        let mut k = 0;
        while k < list.len() {
            // One depth at a time, outermost first.
            let depth = list[k].depth;
            let end = list[k..]
                .iter()
                .position(|i| i.depth != depth)
                .map_or(list.len(), |e| k + e);
            let mut candidates: Vec<(usize, Vec<usize>)> = Vec::new();
            for (j, inst) in list.iter().enumerate().take(end).skip(k) {
                // Under a called instance: part of its body.
                let inside_called = inst
                    .path
                    .match_indices('/')
                    .any(|(end, _)| called.contains(&inst.path[..end]));
                if inside_called {
                    continue;
                }
                let used: Vec<usize> = inst
                    .outputs
                    .iter()
                    .enumerate()
                    .filter(|(_, (_, o))| plan.is_live(*o))
                    .map(|(m, _)| m)
                    .collect();
                let folds = used.iter().all(|&m| {
                    let r = OutputRef {
                        node: inst.outputs[m].1,
                        output: 0,
                    };
                    plan.folded(r).is_some()
                });
                let has_parameter = inst
                    .members
                    .iter()
                    .any(|&m| nodes[m].node_type.evaluation() == Evaluation::Parameter);
                if used.is_empty() || folds || has_parameter {
                    continue;
                }
                candidates.push((j, used));
            }
            let mut count: HashMap<Key, usize> = HashMap::new();
            for (j, used) in &candidates {
                let types = list[*j]
                    .inputs
                    .iter()
                    .map(|(_, n)| nodes[*n].output_type(0))
                    .collect();
                *count
                    .entry((list[*j].def.clone(), used.clone(), types))
                    .or_default() += 1;
            }
            for (j, used) in candidates {
                let inst = &list[j];
                let types: Vec<SocketType> = inst
                    .inputs
                    .iter()
                    .map(|(_, n)| nodes[*n].output_type(0))
                    .collect();
                let key = (inst.def.clone(), used.clone(), types);
                if count[&key] < 2 && !by_key.contains_key(&key) {
                    continue;
                }
                let f = match by_key.get(&key) {
                    Some(Some(f)) => *f,
                    Some(None) => continue,
                    None => {
                        let f = function(graph, plan, j, &used, out.functions.len());
                        // A body of one call costs no more inline than a call does.
                        if f.body.len() < 2 {
                            by_key.insert(key, None);
                            continue;
                        }
                        out.functions.push(f);
                        by_key.insert(key, Some(out.functions.len() - 1));
                        out.functions.len() - 1
                    }
                };
                called.insert(inst.path.as_str());
                let c = inst.outputs[used[0]].1;
                for (member, &m) in used.iter().enumerate() {
                    out.out_of.insert(inst.outputs[m].1, (c, member));
                }
                out.hidden.extend(inst.members.iter().copied());
                let reads_light = reads_light(graph, plan, &inst.members);
                out.calls.insert(
                    c,
                    GroupCall {
                        function: f,
                        inputs: inst.inputs.iter().map(|(_, n)| *n).collect(),
                        path: inst.path.clone(),
                        reads_light,
                    },
                );
            }
            k = end;
        }
        for f in &out.functions {
            out.body_calls.extend(f.body.iter().copied());
        }
        out
    }
}

/// The function of group instance `rep` of `graph` for its outputs `used`.
fn function(graph: &Graph, plan: &Plan, rep: usize, used: &[usize], index: usize) -> GroupFunction {
    let inst = &graph.instances().expect("a grouped graph").list[rep];
    let nodes = graph.nodes();
    let members: HashSet<NodeIndex> = inst.members.iter().copied().collect();
    let inputs: HashSet<NodeIndex> = inst.inputs.iter().map(|(_, n)| *n).collect();
    // The body's nodes that depend on an input, in graph (topological) order.
    let mut varying: HashSet<NodeIndex> = HashSet::new();
    for &i in graph.order() {
        if !members.contains(&i) {
            continue;
        }
        let reads = nodes[i].inputs.iter().any(|s| match s {
            InputSource::Link(r, _) => inputs.contains(&r.node) || varying.contains(&r.node),
            _ => false,
        });
        if reads {
            varying.insert(i);
        }
    }
    let folded = |i: NodeIndex| {
        !varying.contains(&i)
            && (0..nodes[i].node_type.outputs().len())
                .all(|k| plan.folded(OutputRef { node: i, output: k }).is_some())
    };
    let body: Vec<NodeIndex> = graph
        .order()
        .iter()
        .copied()
        .filter(|&i| {
            let n = &nodes[i];
            members.contains(&i)
                && plan.is_live(i)
                && !n.forwards()
                && !matches!(
                    n.node_type.evaluation(),
                    Evaluation::Attributes(_) | Evaluation::Parameter
                )
                && !folded(i)
        })
        .collect();
    let mut names: HashSet<String> = HashSet::new();
    let members_out = used
        .iter()
        .map(|&m| {
            let (name, node) = &inst.outputs[m];
            let mut field = super::emit::ident(name);
            while !names.insert(field.clone()) {
                field.push('_');
            }
            (field, nodes[*node].output_type(0), *node)
        })
        .collect();
    GroupFunction {
        name: format!(
            "mg_group_{index}_{}",
            super::emit::ident(label_name(&inst.group))
        ),
        out_struct: format!("MgGroup{index}"),
        label: inst.group.clone(),
        rep,
        members: members_out,
        body,
        varying,
        baked: Vec::new(),
    }
}

/// The group's own name in a reference (`lib/x.json#blend` → `blend`, `lib/wet.json` →
/// `wet`).
fn label_name(reference: &str) -> &str {
    let name = reference.rsplit('#').next().unwrap_or(reference);
    let name = name.rsplit('/').next().unwrap_or(name);
    name.strip_suffix(".json").unwrap_or(name)
}

/// Whether one of `members` reads the light or its colour.
fn reads_light(graph: &Graph, plan: &Plan, members: &[NodeIndex]) -> bool {
    members
        .iter()
        .any(|&i| match graph.nodes()[i].node_type.evaluation() {
            Evaluation::Attributes(attrs) => attrs.iter().enumerate().any(|(k, a)| {
                matches!(a, Attribute::Light | Attribute::LightColor)
                    && plan
                        .node_operands
                        .contains_key(&OutputRef { node: i, output: k })
            }),
            _ => false,
        })
}
