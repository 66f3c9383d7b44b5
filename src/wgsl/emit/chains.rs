//! Runs of calls that each pass the last one's result on, emitted as one loop.
//!
//! A group stacked on itself (a coat over a coat, a wave set displacing the last one's
//! offset, a ramp re-banding the last ramp's colour), or a node on itself, is a chain of
//! calls of one function whose arguments are the same but for one, which reads (a member
//! of) the previous call's result:
//!
//! ```wgsl
//! let g1 = f(geom, x0);  let g2 = f(geom, g1.color);  …  let g50 = f(geom, g49.color);
//! ```
//!
//! Where no other call and no output reads the calls before the last, the run is written
//!
//! ```wgsl
//! var g50 = f(geom, x0);
//! for (var mg_k = 1u; mg_k < 50u; mg_k += 1u) { g50 = f(geom, g50.color); }
//! ```
//!
//! The same function on the same arguments in the same order: the values are those of the
//! unrolled calls, and the module grows by one loop instead of a line per instance. The
//! driver's compiler unrolls it or not as it judges; a loop of [`MIN_RUN`] calls or more is
//! made (shorter runs cost less as lines).

use super::{Emitter, NodeFunction};
use crate::graph::{NodeIndex, OutputRef};
use crate::types::SocketType;
use std::collections::{HashMap, HashSet};
use std::fmt::Write;

/// The fewest calls a run must have to become a loop.
pub(super) const MIN_RUN: usize = 3;

/// A run of calls written as a loop, kept by its last call (whose variable ends holding
/// the run's result).
pub(super) struct Run {
    /// The run's first call: its arguments start the loop.
    pub head: NodeIndex,
    /// How many calls the run has.
    pub len: usize,
    /// The written argument that takes the previous result.
    pub arg: usize,
    /// The member of the previous result it takes (`None`: the whole, a one-output node).
    pub member: Option<String>,
}

impl Emitter<'_> {
    /// Finds the runs among `calls` (the calls of one straight-line material function, in
    /// order), records them in `self.runs` and drops from `calls` every call of a run
    /// but its last, which emits the loop ([`Self::emit_run`]).
    pub(super) fn fold_group_runs(
        &mut self,
        calls: &mut Vec<NodeIndex>,
        functions: &[(String, NodeFunction, String)],
        outputs: &[(String, SocketType, OutputRef)],
    ) {
        // Every call's written arguments, and how often each variable is read anywhere.
        let mut args: HashMap<NodeIndex, Vec<String>> = HashMap::new();
        let mut reads: HashMap<String, usize> = HashMap::new();
        let mut reader: HashMap<String, NodeIndex> = HashMap::new();
        for &c in calls.iter() {
            let a = self.call_args(c, functions);
            for text in &a {
                for token in identifiers(text) {
                    *reads.entry(token.to_owned()).or_default() += 1;
                    reader.insert(token.to_owned(), c);
                }
            }
            args.insert(c, a);
        }
        for (_, ty, r) in outputs {
            for token in identifiers(&self.source_expr(*r, *ty)) {
                *reads.entry(token.to_owned()).or_default() += 1;
            }
        }
        let name = |e: &Emitter, c: NodeIndex| e.var(c).name.clone();
        let function = |e: &Emitter, c: NodeIndex| e.var(c).function;
        // The call that reads `c` alone, once, as one argument `c.member` with the others
        // equal to `c`'s: (that call, the argument, the member).
        let next = |e: &Emitter, c: NodeIndex| -> Option<(NodeIndex, usize, Option<String>)> {
            let v = name(e, c);
            if reads.get(&v) != Some(&1) {
                return None;
            }
            let n = *reader.get(&v)?;
            let (a, b) = (args.get(&c)?, args.get(&n)?);
            if function(e, n) != function(e, c) || a.len() != b.len() {
                return None;
            }
            let mut differ = (0..a.len()).filter(|&k| a[k] != b[k]);
            let k = differ.next()?;
            if differ.next().is_some() {
                return None;
            }
            // The argument is the previous value, or one of its members.
            let rest = b[k].strip_prefix(&v)?;
            let member = match rest.strip_prefix('.') {
                Some(m) if e.call_members(c).iter().any(|x| x == m) => Some(m.to_owned()),
                None if rest.is_empty() && e.call_members(c).is_empty() => None,
                _ => return None,
            };
            Some((n, k, member))
        };
        let mut taken: HashSet<NodeIndex> = HashSet::new();
        for &head in calls.iter() {
            if taken.contains(&head) || !args.contains_key(&head) {
                continue;
            }
            let mut run = vec![head];
            let mut link: Option<(usize, Option<String>)> = None;
            while let Some((n, k, member)) = next(self, *run.last().expect("a run")) {
                if link.as_ref().is_some_and(|l| *l != (k, member.clone())) {
                    break;
                }
                link = Some((k, member));
                run.push(n);
            }
            let Some((arg, member)) = link else { continue };
            if run.len() < MIN_RUN {
                continue;
            }
            let last = *run.last().expect("a run");
            taken.extend(run[..run.len() - 1].iter().copied());
            self.runs.insert(
                last,
                Run {
                    head,
                    len: run.len(),
                    arg,
                    member,
                },
            );
        }
        calls.retain(|c| !taken.contains(c));
    }

    /// The text of run `run` ending at call `last`: the first call into a `var`, then the
    /// loop of the others.
    pub(super) fn emit_run(
        &self,
        last: NodeIndex,
        run: &Run,
        functions: &[(String, NodeFunction, String)],
    ) -> String {
        let var = &self.var(last).name;
        let f = &functions[self.var(last).function].1.name;
        let first = self.call_args(run.head, functions);
        let mut each = self.call_args(last, functions);
        each[run.arg] = match &run.member {
            Some(m) => format!("{var}.{m}"),
            None => var.clone(),
        };
        let mut text = format!("    var {var} = {f}({});\n", first.join(", "));
        let _ = writeln!(
            text,
            "    for (var mg_k = 1u; mg_k < {}u; mg_k += 1u) {{\n        {var} = {f}({});\n    }}",
            run.len,
            each.join(", ")
        );
        text
    }
}

impl Emitter<'_> {
    /// The members of call `c`'s result struct (none for a node of one output).
    fn call_members(&self, c: NodeIndex) -> Vec<String> {
        if let Some(g) = self.groups.calls.get(&c) {
            let f = &self.groups.functions[g.function];
            return f.members.iter().map(|(m, _, _)| m.clone()).collect();
        }
        let t = &self.graph.nodes()[c].node_type;
        if t.outputs().len() < 2 {
            return Vec::new();
        }
        (0..t.outputs().len())
            .map(|k| super::output_member(t, k))
            .collect()
    }
}

/// The identifiers in a WGSL expression (`g3_a.color * n4_b` → `g3_a`, `color`, `n4_b`).
fn identifiers(text: &str) -> impl Iterator<Item = &str> {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|t| t.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_'))
}
