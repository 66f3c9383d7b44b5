//! The registry of node types: lookup by name, listing, and near-name suggestions.

use crate::node::NodeType;
use std::collections::HashMap;
use std::sync::{Arc, LazyLock};

/// A set of node types keyed by their stable names.
#[derive(Debug, Default)]
pub struct Registry {
    types: Vec<Arc<NodeType>>,
    by_name: HashMap<&'static str, usize>,
}

static BUILTIN: LazyLock<Registry> = LazyLock::new(|| {
    let mut r = Registry::default();
    for t in crate::nodes::all() {
        r.register(t);
    }
    r
});

impl Registry {
    /// The registry of every node type shipped with matgraph.
    pub fn builtin() -> &'static Registry {
        &BUILTIN
    }

    /// Adds a node type; a type of the same name is replaced.
    pub fn register(&mut self, t: NodeType) {
        let t = Arc::new(t);
        match self.by_name.get(t.name()) {
            Some(&i) => self.types[i] = t,
            None => {
                self.by_name.insert(t.name(), self.types.len());
                self.types.push(t);
            }
        }
    }

    /// The node type called `name`.
    pub fn get(&self, name: &str) -> Option<&Arc<NodeType>> {
        self.by_name.get(name).map(|&i| &self.types[i])
    }

    /// Every node type, in registration order.
    pub fn types(&self) -> &[Arc<NodeType>] {
        &self.types
    }

    /// The registered name nearest to `name`, if one is close enough to be a likely typo.
    pub fn suggest(&self, name: &str) -> Option<&'static str> {
        nearest(name, self.types.iter().map(|t| t.name()))
    }

    /// Checks every declaration against its kernels (see [`NodeType::check`]).
    pub fn check(&self) -> Vec<String> {
        self.types.iter().flat_map(|t| t.check()).collect()
    }
}

/// The candidate nearest to `name` by edit distance, when within a third of its length
/// (at least 2 edits), or a candidate that contains `name` or is contained in it (both at
/// least 3 characters long).
pub fn nearest<'a>(name: &str, candidates: impl Iterator<Item = &'a str>) -> Option<&'a str> {
    let limit = (name.len() / 3).max(2);
    candidates
        .map(|c| {
            let d = strsim::levenshtein(name, c);
            let contained = name.len().min(c.len()) >= 3 && (c.contains(name) || name.contains(c));
            (if contained { d.min(limit) } else { d }, c)
        })
        .filter(|&(d, _)| d <= limit)
        .min()
        .map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_finds_typos() {
        let names = ["fresnel_schlick", "fresnel_dielectric", "hg_phase"];
        assert_eq!(
            nearest("fresnel_schlik", names.into_iter()),
            Some("fresnel_schlick")
        );
        assert_eq!(nearest("hg_phse", names.into_iter()), Some("hg_phase"));
        assert_eq!(nearest("banana", names.into_iter()), None);
    }

    #[test]
    fn builtin_declarations_match_their_kernels() {
        let problems = Registry::builtin().check();
        assert!(problems.is_empty(), "{problems:#?}");
    }
}
