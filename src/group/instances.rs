//! Where each group instance lies in a validated graph: the nodes of its body, the nodes that
//! carry its inputs and outputs. The WGSL emitter reads it to call one function per group.

use crate::graph::{Graph, NodeIndex};
use std::collections::HashMap;

/// One group instance of a graph (its groups inlined, see [`crate::group`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    /// Its path in the flat graph (`g`, `g/h`).
    pub path: String,
    /// The group reference as written on it.
    pub group: String,
    /// The unique key of its group: instances with one key have one body.
    pub def: String,
    /// How many instances it lies in.
    pub depth: usize,
    /// The nodes holding what it passes to each input, in the group's input order.
    pub inputs: Vec<(String, NodeIndex)>,
    /// The `reroute` nodes of its outputs (`g/@out:NAME`), in the group's output order.
    pub outputs: Vec<(String, NodeIndex)>,
    /// Every node of its body, nested instances' included, in graph order (its outputs'
    /// reroutes included, its inputs' nodes not).
    pub members: Vec<NodeIndex>,
}

/// The instances of a graph, outermost first.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Instances {
    /// The instances, by depth then path.
    pub list: Vec<Instance>,
}

impl Instances {
    /// Reads them from the flat graph's ids and the expansion's tables.
    pub(crate) fn new(graph: &Graph, x: &super::Expanded) -> Instances {
        let mut list: Vec<Instance> = x
            .scopes
            .iter()
            .map(|(path, group)| Instance {
                path: path.clone(),
                group: group.clone(),
                def: x.defs.get(path).cloned().unwrap_or_default(),
                depth: path.matches('/').count(),
                inputs: Vec::new(),
                outputs: Vec::new(),
                members: Vec::new(),
            })
            .collect();
        list.sort_by(|a, b| (a.depth, &a.path).cmp(&(b.depth, &b.path)));
        let index: HashMap<&str, usize> = list
            .iter()
            .enumerate()
            .map(|(k, i)| (i.path.as_str(), k))
            .collect();
        let mut inputs: Vec<Vec<(String, NodeIndex)>> = vec![Vec::new(); list.len()];
        let mut outputs: Vec<Vec<(String, NodeIndex)>> = vec![Vec::new(); list.len()];
        let mut members: Vec<Vec<NodeIndex>> = vec![Vec::new(); list.len()];
        for (i, n) in graph.nodes().iter().enumerate() {
            let id = n.id.as_str();
            let carried = x.inputs.get(id);
            if let Some((path, name)) = carried
                && let Some(&k) = index.get(path.as_str())
            {
                inputs[k].push((name.clone(), i));
            }
            if let Some((path, name)) = id.rsplit_once("/@out:")
                && let Some(&k) = index.get(path)
            {
                outputs[k].push((name.to_owned(), i));
            }
            // Every instance whose path is a prefix of the id holds the node, except the
            // instance whose input it carries.
            for (end, _) in id.match_indices('/') {
                let path = &id[..end];
                if let Some(&k) = index.get(path)
                    && carried.is_none_or(|(p, _)| p != path)
                {
                    members[k].push(i);
                }
            }
        }
        for (k, inst) in list.iter_mut().enumerate() {
            inst.inputs = std::mem::take(&mut inputs[k]);
            inst.outputs = std::mem::take(&mut outputs[k]);
            inst.members = std::mem::take(&mut members[k]);
        }
        Instances { list }
    }
}
