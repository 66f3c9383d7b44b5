//! Large graphs: long chains and wide fan-in trees load, validate, save, plan, evaluate and
//! compile to WGSL (naga-validated) without deep recursion; cycles of any length are
//! reported; error locations and error lists of huge files stay linear and capped; a split
//! WGSL material function maps bytes to nodes and is deterministic.
//!
//! Values are checked against closed forms: the chain adds 1 per node to `c = normal·view`,
//! the fan-in tree doubles `c + 1` per level (see `examples/scale.rs`).

#[path = "../../examples/scale.rs"]
#[allow(dead_code)]
mod scale;

use matgraph::error::{GraphError, GraphErrors, MAX_SHOWN};
use matgraph::exec::SampleBatch;
use matgraph::node::Attribute;
use matgraph::plan::{Plan, PlanOptions};
use matgraph::wgsl::{WgslOptions, generate};
use matgraph::{Graph, Registry};
use std::fmt::Write;

/// Normal and view pairs: round ones and seeded pseudo-random unit vectors.
fn geometry(count: usize) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut unit = || {
        let v = [next(), next(), next()];
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt().max(1e-3);
        v.map(|x| (x / l) as f32)
    };
    let mut normals = vec![[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]];
    let mut views = vec![[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]];
    while normals.len() < count {
        normals.push(unit());
        views.push(unit());
    }
    (normals, views)
}

/// `normal · view` in f64.
fn dot(a: [f32; 3], b: [f32; 3]) -> f64 {
    (0..3).map(|k| a[k] as f64 * b[k] as f64).sum()
}

/// Evaluates `graph`'s one output at the samples of [`geometry`].
fn evaluate(graph: &Graph, count: usize) -> (Vec<f64>, Vec<f32>) {
    let plan = Plan::compile(graph, &PlanOptions::default()).unwrap();
    let (normals, views) = geometry(count);
    let mut batch = SampleBatch::new(count);
    batch.set_values(Attribute::Normal, &normals).unwrap();
    batch.set_values(Attribute::View, &views).unwrap();
    let out = plan.execute(&batch, &plan.default_parameters()).unwrap();
    let cos = (0..count).map(|i| dot(normals[i], views[i])).collect();
    let got = (0..count).map(|i| out.value(0, i).as_f32()).collect();
    (cos, got)
}

#[test]
fn a_100k_chain_loads_saves_plans_and_evaluates() {
    let n = 100_000;
    let text = scale::chain(n);
    let graph = Graph::from_json(&text, Registry::builtin()).unwrap();
    assert_eq!(graph.nodes().len(), n + 2);
    // Saving and reloading gives the same bytes.
    let saved = graph.to_json();
    let again = Graph::from_json(&saved, Registry::builtin()).unwrap();
    assert_eq!(again.to_json(), saved);
    // c + n, exactly representable for integral steps (rounded once at the end here).
    let (cos, got) = evaluate(&graph, 16);
    for (c, g) in cos.iter().zip(&got) {
        let want = c + n as f64;
        assert!(
            (*g as f64 - want).abs() <= 1e-7 * want.abs() + 0.05,
            "{g} vs {want}"
        );
    }
    assert_eq!(got[0], (n + 1) as f32);
    assert_eq!(got[1], (n - 1) as f32);
}

#[test]
fn a_60k_chain_compiles_to_valid_wgsl() {
    // Past the 55,000 nodes that overflowed the stack before, and split into parts.
    let n = 60_000;
    let graph = Graph::from_json(&scale::chain(n), Registry::builtin()).unwrap();
    let m = generate(&graph, &WgslOptions::default()).unwrap();
    assert!(
        m.source.contains("fn mg_part_0("),
        "split past the threshold"
    );
    assert!(
        m.source.contains("fn mg_parts_1_0("),
        "parts are sequenced by a tree"
    );
    // The last node's call maps back to it.
    let last = format!("a{}", n - 1);
    let at = m.source.find(&format!("_{last} = mg_add_f32(")).unwrap();
    assert_eq!(m.node_at(at), Some(last.as_str()));
}

#[test]
fn a_fan_in_tree_compiles_deterministically_and_evaluates() {
    let (text, depth) = scale::fan_in_depth(5_000);
    let graph = Graph::from_json(&text, Registry::builtin()).unwrap();
    let (cos, got) = evaluate(&graph, 16);
    let scale = (1u64 << depth) as f64;
    for (c, g) in cos.iter().zip(&got) {
        let want = (c + 1.0) * scale;
        assert!((*g as f64 - want).abs() <= 1e-5 * scale, "{g} vs {want}");
    }
    let a = generate(&graph, &WgslOptions::default()).unwrap();
    let b = generate(&graph, &WgslOptions::default()).unwrap();
    assert_eq!(a.source, b.source);
    // Calls are placed depth-first, so few values cross a part: far fewer state slots
    // than nodes (leaves first in file order would make every leaf one).
    let state = &a.source[a
        .source
        .find("struct MgState {\n    f: array<f32, ")
        .unwrap()..];
    let slots: usize = state["struct MgState {\n    f: array<f32, ".len()..]
        .split('>')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(slots * 20 < graph.nodes().len(), "{slots} state slots");
    // Each byte of a node's call maps to that node.
    for id in ["l0", "l2499", "t0_0", "t3_100"] {
        let at = a.source.find(&format!("_{id} = mg_add_f32(")).unwrap();
        assert_eq!(a.node_at(at), Some(id), "{id}");
    }
}

#[test]
fn small_graphs_keep_one_material_function() {
    let graph = Graph::from_json(&scale::chain(200), Registry::builtin()).unwrap();
    let m = generate(&graph, &WgslOptions::default()).unwrap();
    assert!(!m.source.contains("mg_part_"));
    assert!(!m.source.contains("MgState"));
}

/// The text of a graph whose `n` add nodes form one cycle.
fn ring(n: usize) -> String {
    let mut s = String::from(r#"{"version": 1, "name": "ring", "nodes": ["#);
    for k in 0..n {
        if k > 0 {
            s.push(',');
        }
        let prev = (k + n - 1) % n;
        let _ = write!(
            s,
            r#"{{"id": "r{k}", "type": "add", "inputs": {{"a": {{"link": "r{prev}.result"}}}}}}"#
        );
    }
    s.push_str("]}");
    s
}

#[test]
fn a_100k_cycle_is_reported_once_with_a_capped_message() {
    let n = 100_000;
    let errors = Graph::from_json(&ring(n), Registry::builtin()).unwrap_err();
    assert_eq!(errors.len(), 1);
    let GraphError::Cycle { nodes } = &errors[0] else {
        panic!("{:?}", errors[0]);
    };
    // r0 -> r1 -> ... -> r(n-1) -> r0.
    assert_eq!(nodes.len(), n + 1);
    assert_eq!(nodes[0], "r0");
    assert_eq!(nodes[1], "r1");
    assert_eq!(nodes[n - 1], format!("r{}", n - 1));
    assert_eq!(nodes[n], "r0");
    let text = errors[0].to_string();
    assert!(
        text.starts_with("cycle through nodes r0 -> r1 -> r2"),
        "{text}"
    );
    assert!(
        text.contains(&format!("-> … ({} more) ->", n + 1 - 2 * MAX_SHOWN)),
        "{text}"
    );
    assert!(text.ends_with(&format!("r{} -> r0", n - 1)), "{text}");
    assert!(text.len() < 2_000, "{}", text.len());
}

#[test]
fn huge_files_of_bad_nodes_are_located_and_capped() {
    // 200,000 entries that are not objects, one per line: each error is located exactly.
    let n = 200_000;
    let mut text = String::from("{\n\"version\": 1,\n\"name\": \"bad\",\n\"nodes\": [\n");
    for k in 0..n {
        let _ = writeln!(text, "  {k}{}", if k + 1 < n { "," } else { "" });
    }
    text.push_str("]\n}\n");
    let errors = Graph::from_json(&text, Registry::builtin()).unwrap_err();
    assert_eq!(errors.len(), n);
    for k in [0, 1, 77_777, n - 1] {
        let GraphError::Structure {
            node, line, column, ..
        } = &errors[k]
        else {
            panic!("{:?}", errors[k]);
        };
        assert_eq!(node.as_deref(), Some(format!("#{k}").as_str()));
        // Entry k is on line 5 + k; serde reports the column just after the number.
        assert_eq!(*line, 5 + k, "entry {k}");
        assert_eq!(*column, 2 + k.to_string().len(), "entry {k}");
    }
    let shown = GraphErrors {
        source: "bad.json".into(),
        errors,
    }
    .to_string();
    let lines: Vec<&str> = shown.lines().collect();
    assert_eq!(lines.len(), MAX_SHOWN + 1);
    assert!(
        lines[0].starts_with("bad.json: node '#0': "),
        "{}",
        lines[0]
    );
    assert_eq!(
        lines[MAX_SHOWN],
        format!("bad.json: … and {} more errors", n - MAX_SHOWN)
    );
}

#[test]
fn many_dangling_links_stay_fast_and_suggest_for_the_first_ones() {
    // Every node links to a missing one: suggestions are searched for the first errors
    // only, so this is linear (it took minutes when each searched all 50,000 ids).
    let n = 50_000;
    let mut s = String::from(r#"{"version": 1, "name": "dangling", "nodes": ["#);
    for k in 0..n {
        if k > 0 {
            s.push(',');
        }
        let _ = write!(
            s,
            r#"{{"id": "d{k}", "type": "add", "inputs": {{"a": {{"link": "e{k}.result"}}}}}}"#
        );
    }
    s.push_str("]}");
    let errors = Graph::from_json(&s, Registry::builtin()).unwrap_err();
    assert_eq!(errors.len(), n);
    assert!(
        errors[0].to_string().contains("did you mean 'd0'?"),
        "{}",
        errors[0]
    );
    assert_eq!(
        errors[n - 1].to_string(),
        format!(
            "node 'd{}': input 'a': link to missing node 'e{}'",
            n - 1,
            n - 1
        )
    );
}

/// A graph of `n` outputs over `nodes` `add` nodes (`a{k} = uv + k`): output `o{j}` reads
/// node `j % nodes` when `j` is even, the geometry's uv when odd (one source for half).
fn many_outputs(n: usize, nodes: usize) -> String {
    let mut adds = Vec::new();
    for k in 0..nodes {
        adds.push(format!(
            r#"{{"id":"a{k}","type":"add","inputs":{{"a":{{"link":"geo.uv"}},"b":{k}.0}}}}"#
        ));
    }
    let outputs: Vec<String> = (0..n)
        .map(|j| match j % 2 {
            0 => format!(r#"{{"name":"o{j}","from":"a{}.result"}}"#, j % nodes),
            _ => format!(r#"{{"name":"o{j}","from":"geo.uv"}}"#),
        })
        .collect();
    format!(
        r#"{{"version":1,"name":"many","nodes":[{{"id":"geo","type":"geometry"}},{}],"outputs":[{}]}}"#,
        adds.join(","),
        outputs.join(",")
    )
}

/// The work naga's front end does on a module, as issue 37 measured it: the most
/// expressions in one function (its type resolution walks them for each new one: E²) and
/// the most members in one struct (each member access searches them).
fn naga_work(m: &matgraph::wgsl::ShaderModule) -> (usize, usize) {
    let functions = m
        .module
        .functions
        .iter()
        .map(|(_, f)| f.expressions.len())
        .chain(
            m.module
                .entry_points
                .iter()
                .map(|e| e.function.expressions.len()),
        )
        .max()
        .unwrap_or(0);
    let members = m
        .module
        .types
        .iter()
        .map(|(_, t)| match &t.inner {
            naga::TypeInner::Struct { members, .. } => members.len(),
            _ => 0,
        })
        .max()
        .unwrap_or(0);
    (functions, members)
}

#[test]
fn many_outputs_compile_with_bounded_functions_and_structs() {
    // Issue 37: 16k outputs took 2.8 s and 200k over 300 s, as the entry (7 expressions per
    // stored component) and the material's return grew with the outputs. Now every
    // function and struct stays below a bound whatever the count: 4× the outputs, the same
    // largest function and struct, so naga's work grows linearly. A few nodes (one
    // material function) and 600 (a split one), on both sides of the chunk size.
    for nodes in [3, 600] {
        let mut seen = Vec::new();
        for n in [1200, 4800] {
            let graph = Graph::from_json(&many_outputs(n, nodes), Registry::builtin()).unwrap();
            for entry in [
                matgraph::wgsl::Entry::Compute,
                matgraph::wgsl::Entry::Fragment,
            ] {
                let options = WgslOptions {
                    entry,
                    ..WgslOptions::default()
                };
                let m = generate(&graph, &options).unwrap();
                let (functions, members) = naga_work(&m);
                seen.push((n, functions, members));
                assert!(
                    functions <= 4000 && members <= 256,
                    "{nodes} nodes, {n} outputs, {entry:?}: {functions} expressions in one function, {members} members in one struct"
                );
            }
        }
        eprintln!(
            "{nodes} nodes: (outputs, most expressions in a function, most struct members) {seen:?}"
        );
        // 4× the outputs: the largest function within a tenth (the per-chunk calls).
        assert!(seen[2].1 <= seen[0].1 + seen[0].1 / 10 + 64, "{seen:?}");
    }
}
