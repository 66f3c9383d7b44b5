//! Moving an error found in the flat document back into the groups it comes from.

use crate::error::GraphError;
use std::collections::HashMap;

/// `e`, found in a flat document, as the author sees it: an error on node `g/h/f` becomes
/// `node 'g' (group G) → node 'h' (group H) → node 'f': …`, and one on the node holding an
/// instance's input (`g/@in:x`) an error on input `x` of instance `g`. `scopes` and
/// `inputs` are [`super::Expanded`]'s.
pub(crate) fn relocate(
    mut e: GraphError,
    scopes: &HashMap<String, String>,
    inputs: &HashMap<String, (String, String)>,
) -> GraphError {
    let Some(mut flat) = e.node_mut().map(|n| n.clone()) else {
        return e;
    };
    if let Some((instance, input)) = inputs.get(&flat) {
        if let Some(n) = e.node_mut() {
            n.clone_from(instance);
        }
        if let Some(i) = e.input_mut() {
            i.clone_from(input);
        }
        flat.clone_from(instance);
    }
    if !flat.contains('/') {
        return e;
    }
    // The instances on the path, outermost first.
    let parts: Vec<&str> = flat.split('/').collect();
    let mut levels: Vec<(String, String)> = Vec::new();
    let mut inner_start = 0;
    let mut path = String::new();
    for (k, part) in parts.iter().enumerate().take(parts.len() - 1) {
        if k > 0 {
            path.push('/');
        }
        path.push_str(part);
        if let Some(group) = scopes.get(&path) {
            levels.push(((*part).to_owned(), group.clone()));
            inner_start = k + 1;
        }
    }
    if levels.is_empty() {
        return e;
    }
    let prefix = format!("{}/", parts[..inner_start].join("/"));
    if let Some(n) = e.node_mut() {
        *n = parts[inner_start..].join("/");
    }
    if let Some(t) = e.target_mut()
        && let Some(rest) = t.strip_prefix(&prefix)
    {
        *t = rest.to_owned();
    }
    for (node, group) in levels.into_iter().rev() {
        e = GraphError::InGroup {
            node,
            group,
            error: Box::new(e),
        };
    }
    e
}
