//! WGSL generation without a GPU: every node's WGSL validates under naga, every bundled graph
//! generates valid modules for both entry points and translates to every naga backend,
//! output is deterministic, errors name their node, and the uniform layout comes from naga.

use crate::common;
use common::bundled_graphs;

use matgraph::node::Evaluation;
use matgraph::wgsl::{Binding, Entry, ShaderError, Target, WgslOptions, generate, node_harness};
use matgraph::{Graph, PlanOptions, Registry, SocketType};
use std::path::Path;

fn load(path: &Path) -> Graph {
    matgraph::io::load_graph(path, Registry::builtin()).unwrap_or_else(|e| panic!("{e}"))
}

fn types_of(t: &matgraph::NodeType) -> Vec<SocketType> {
    if t.is_generic() {
        t.generic_types()
    } else {
        vec![SocketType::Float]
    }
}

#[test]
fn every_computed_node_has_wgsl_that_validates() {
    let mut missing = Vec::new();
    for t in Registry::builtin().types() {
        if t.evaluation() != Evaluation::Compute {
            continue;
        }
        for g in types_of(t) {
            match node_harness(t, g) {
                Ok(h) => {
                    let w_in: usize = t.inputs().iter().map(|i| i.ty.resolve(g).width()).sum();
                    assert_eq!(h.input_width, w_in, "{} ({g})", t.name());
                }
                Err(ShaderError::MissingWgsl { .. }) => missing.push(format!("{} ({g})", t.name())),
                Err(e) => panic!("{} ({g}): {e}", t.name()),
            }
        }
    }
    assert!(missing.is_empty(), "node types without WGSL: {missing:?}");
}

#[test]
fn bundled_graphs_generate_and_translate_to_every_target() {
    for path in bundled_graphs() {
        let graph = load(&path);
        for entry in [Entry::Compute, Entry::Fragment] {
            let m = generate(
                &graph,
                &WgslOptions {
                    entry,
                    ..Default::default()
                },
            )
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            for target in Target::ALL {
                let bytes = m
                    .translate(target)
                    .unwrap_or_else(|e| panic!("{} {entry:?}: {e}", path.display()));
                assert!(!bytes.is_empty());
                if target == Target::SpirV {
                    assert_eq!(&bytes[..4], &0x0723_0203u32.to_le_bytes(), "SPIR-V magic");
                }
            }
        }
    }
}

#[test]
fn generation_is_deterministic() {
    for path in bundled_graphs() {
        for target in Target::ALL {
            let once = || {
                let m = generate(&load(&path), &WgslOptions::default()).unwrap();
                m.translate(target).unwrap()
            };
            assert_eq!(once(), once(), "{} {target}", path.display());
        }
    }
}

#[test]
fn only_used_functions_are_emitted() {
    let graph = load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/fresnel_glass.json"));
    // Asking for the specular only keeps ior_to_f0 and f0_to_specular: no Fresnel, no dot.
    let options = WgslOptions {
        plan: PlanOptions {
            outputs: vec!["specular".into()],
            ..Default::default()
        },
        ..Default::default()
    };
    let m = generate(&graph, &options).unwrap();
    assert!(m.source.contains("fn mg_ior_to_f0("), "{}", m.source);
    assert!(m.source.contains("fn mg_f0_to_specular("));
    assert!(!m.source.contains("mg_fresnel_dielectric"), "{}", m.source);
    assert!(!m.source.contains("fn mg_dot_"));
    assert!(m.attributes.is_empty(), "the specular reads no geometry");
}

#[test]
fn uniform_layout_comes_from_naga_with_vec3_padding() {
    let text = r#"{
      "version": 1, "name": "layout",
      "nodes": [
        { "id": "k", "type": "parameter", "inputs": { "value": 0.5 } },
        { "id": "tint", "type": "parameter", "data_type": "color", "inputs": { "value": [1.0, 0.5, 0.25] } },
        { "id": "s", "type": "parameter", "inputs": { "value": 2.0 } },
        { "id": "t", "type": "time" },
        { "id": "m", "type": "mul", "inputs": { "a": { "link": "tint.value" }, "b": { "link": "k.value" } } },
        { "id": "n", "type": "mul", "inputs": { "a": { "link": "m.result" }, "b": { "link": "s.value" } } },
        { "id": "o", "type": "mul", "inputs": { "a": { "link": "n.result" }, "b": { "link": "t.time" } } }
      ],
      "outputs": [ { "name": "c", "from": "o.result" } ],
      "parameters": [
        { "name": "k", "node": "k" }, { "name": "tint", "node": "tint" }, { "name": "s", "node": "s" }
      ]
    }"#;
    let graph = Graph::from_json(text, Registry::builtin()).unwrap();
    let m = generate(&graph, &WgslOptions::default()).unwrap();
    let offsets: Vec<(String, u32)> = m
        .uniforms
        .fields
        .iter()
        .map(|f| (f.field.clone(), f.offset))
        .collect();
    // WGSL layout rules: f32 at 0; vec3<f32> aligned to 16; f32 right after the vec3 at 28;
    // then time at 32; struct size rounded up to the 16-byte alignment of the vec3.
    assert_eq!(
        offsets,
        vec![
            ("k".into(), 0),
            ("tint".into(), 16),
            ("s".into(), 28),
            ("time".into(), 32)
        ]
    );
    assert_eq!(m.uniforms.size, 48);
    let mut params = matgraph::Plan::compile(&graph, &PlanOptions::default())
        .unwrap()
        .default_parameters();
    params.set("s", matgraph::Value::float(3.0)).unwrap();
    let bytes = m.uniforms.pack(&params, 1.5);
    let f = |at: usize| f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    assert_eq!(
        (f(0), f(16), f(20), f(24), f(28), f(32)),
        (0.5, 1.0, 0.5, 0.25, 3.0, 1.5)
    );
    assert_eq!(m.bindings[0], (0, Binding::Params));
}

#[test]
fn baking_folds_parameters_into_constants() {
    let graph = load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/fresnel_glass.json"));
    let baked = WgslOptions {
        plan: PlanOptions {
            bake_parameters: true,
            ..Default::default()
        },
        ..Default::default()
    };
    let m = generate(&graph, &baked).unwrap();
    assert!(m.uniforms.fields.is_empty());
    assert!(!m.source.contains("MgParams"));
    // R0 of glass 1.52 folded: 0.0425799...
    assert!(
        m.source
            .contains("mg_fresnel_schlick_f32(n1_cos, 0.04257999)"),
        "{}",
        m.source
    );
}

#[test]
fn naga_errors_name_the_node() {
    use matgraph::node::{Category, In, NodeType, Out};
    let mut registry = Registry::default();
    for t in matgraph::nodes::all() {
        registry.register(t);
    }
    registry.register(
        NodeType::new(
            "broken",
            Category::Math,
            "A node whose WGSL does not type-check.",
        )
        .source("Test fixture.")
        .input(In::float("x", 0.0).doc("Input."))
        .output(Out::float("y").doc("Output."))
        .compute(|x: f32| x)
        .wgsl("fn $fn(x: f32) -> f32 { return vec2<f32>(x, x); }"),
    );
    let text = r#"{"version": 1, "name": "b", "nodes": [
        {"id": "geo", "type": "geometry"},
        {"id": "len", "type": "length", "inputs": {"v": {"link": "geo.view"}}},
        {"id": "bad", "type": "broken", "inputs": {"x": {"link": "len.result"}}}],
        "outputs": [{"name": "y", "from": "bad.y"}]}"#;
    let graph = Graph::from_json(text, &registry).unwrap();
    match generate(&graph, &WgslOptions::default()) {
        Err(ShaderError::Naga { node, message }) => {
            assert_eq!(node.as_deref(), Some("bad"), "{message}");
            assert!(message.contains("return"), "{message}");
        }
        other => panic!("expected a naga error, got {other:?}"),
    }
}

/// A node's constant table is a member of `MgParams` under its fixed name (a parameter that
/// wants the name gets a suffix), packed at naga's offset: thin_film's CIE weights, checked
/// against closed forms (the fourth lane is 1/λ at λ = 360 + k nm; each colour channel of a
/// flat spectrum sums to 1).
#[test]
fn constant_tables_are_uniform_members_packed_at_naga_offsets() {
    let text = r#"{
      "version": 1, "name": "tables",
      "nodes": [
        { "id": "mg_tf_w", "type": "parameter", "inputs": { "value": 400.0 } },
        { "id": "film", "type": "thin_film",
          "inputs": { "thickness_nm": { "link": "mg_tf_w.value" }, "method": "spectral" } }
      ],
      "outputs": [ { "name": "c", "from": "film.reflectance" } ],
      "parameters": [ { "name": "mg_tf_w", "node": "mg_tf_w" } ]
    }"#;
    let graph = Graph::from_json(text, Registry::builtin()).unwrap();
    let m = generate(&graph, &WgslOptions::default()).unwrap();
    let fields: Vec<(String, u32, String)> = m
        .uniforms
        .fields
        .iter()
        .map(|f| (f.field.clone(), f.offset, f.wgsl_type()))
        .collect();
    assert_eq!(
        fields,
        vec![
            ("mg_tf_w_2".into(), 0, "f32".into()),
            ("mg_tf_w".into(), 16, "array<vec4<f32>, 471>".into()),
        ]
    );
    assert_eq!(m.uniforms.size, 16 + 471 * 16);
    assert!(m.source.contains("mg_params.mg_tf_w[k]"));
    assert!(
        !m.source.contains("array<vec4<f32>, 471>("),
        "no table in the text"
    );
    let params = matgraph::Plan::compile(&graph, &PlanOptions::default())
        .unwrap()
        .default_parameters();
    let bytes = m.uniforms.pack(&params, 0.0);
    let f = |at: usize| f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    assert_eq!(f(0), 400.0);
    let mut sums = [0.0f64; 3];
    for k in 0..471 {
        let at = 16 + 16 * k;
        assert_eq!(f(at + 12), (1.0 / (360.0 + k as f64)) as f32, "row {k}");
        for (c, s) in sums.iter_mut().enumerate() {
            *s += f(at + 4 * c) as f64;
        }
    }
    for s in sums {
        assert!((s - 1.0).abs() < 1e-5, "channel sum {s}");
    }
}

/// A `method` written in the file emits only that method (its per-choice template, helpers
/// and tables); the node's harness has all four. Counted on the generated text and in naga's
/// expressions, which must now differ per method.
#[test]
fn a_literal_method_emits_only_that_method() {
    let graph = |method: &str| {
        let text = format!(
            r#"{{
          "version": 1, "name": "one_method",
          "nodes": [
            {{ "id": "geo", "type": "geometry" }},
            {{ "id": "cos", "type": "dot", "inputs": {{ "a": {{ "link": "geo.normal" }}, "b": {{ "link": "geo.view" }} }} }},
            {{ "id": "film", "type": "thin_film", "inputs": {{ "cos_theta": {{ "link": "cos.result" }}, {method} }} }}
          ],
          "outputs": [ {{ "name": "c", "from": "film.reflectance" }} ]
        }}"#
        );
        Graph::from_json(&text, Registry::builtin()).unwrap_or_else(|e| panic!("{e:?}"))
    };
    // (method, what it must contain, what it must not, MgParams size in bytes)
    let cases = [
        (
            "spectral",
            "mg_tf_method_spectral",
            ["mg_tf_bb_", "mg_tf_cos:", "MG_TF_RGB3_INV"],
            471 * 16,
        ),
        (
            "belcour_barla",
            "mg_tf_bb_pol",
            ["mg_tf_w:", "mg_tf_cos:", "mg_tf_method_spectral"],
            0,
        ),
        (
            "rgb3",
            "MG_TF_RGB3_INV",
            ["mg_tf_w:", "mg_tf_cos:", "mg_tf_bb_"],
            0,
        ),
        (
            "table",
            "mg_tf_cos_at",
            ["mg_tf_w:", "mg_tf_bb_", "mg_tf_method_spectral"],
            2048 * 16,
        ),
    ];
    let mut counts = Vec::new();
    for (method, has, lacks, size) in cases {
        let m = generate(
            &graph(&format!(r#""method": "{method}""#)),
            &WgslOptions::default(),
        )
        .unwrap();
        assert!(m.source.contains(has), "{method}: no {has}");
        for l in lacks {
            assert!(!m.source.contains(l), "{method}: holds {l}");
        }
        assert!(m.source.contains(&format!("fn mg_thin_film_is_{method}(")));
        assert_eq!(m.uniforms.size as usize, size, "{method}");
        let n: usize = m
            .module
            .functions
            .iter()
            .map(|(_, f)| f.expressions.len())
            .sum();
        counts.push(n);
    }
    counts.sort();
    counts.dedup();
    assert_eq!(counts.len(), 4, "expression counts tie: {counts:?}");
    // No node outputs an int, so an enum input is always written in the file; the general
    // function (every method, both tables) is what the node's parity harness runs.
    let t = Registry::builtin().get("thin_film").unwrap();
    let h = node_harness(t, SocketType::Float).unwrap();
    for f in [
        "fn mg_thin_film(",
        "mg_tf_method_spectral",
        "mg_tf_bb_pol",
        "mg_tf_cos_at",
        "MG_TF_RGB3_INV",
    ] {
        assert!(h.source.contains(f), "harness: no {f}");
    }
}

/// The render module evaluates what does not depend on the light once per fragment, before
/// the light loop, and the rest once per light: no call is in both functions, every call
/// reading `light` or `light_color` (or such a call) is in the lit one; the library module
/// has the same split.
#[test]
fn render_modules_hoist_light_independent_calls_out_of_the_light_loop() {
    let graph = load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/pbr_gold.json"));
    let options = WgslOptions {
        plan: PlanOptions::default(),
        entry: Entry::Render(matgraph::wgsl::TextureMode::Exact),
        ..Default::default()
    };
    let m = generate(&graph, &options).unwrap();
    let body = |name: &str| -> String {
        let start = m
            .source
            .find(&format!("fn {name}("))
            .unwrap_or_else(|| panic!("no {name}"));
        let end = m.source[start..].find("\n}\n").unwrap();
        m.source[start..start + end].to_owned()
    };
    let (unlit, lit) = (body("mg_material_unlit"), body("mg_material_lit"));
    for f in [
        "mg_env_specular(",
        "mg_env_brdf(",
        "mg_env_diffuse(",
        "mg_reflect(",
    ] {
        assert!(
            unlit.contains(f) && !lit.contains(f),
            "{f} is light-independent"
        );
    }
    assert!(lit.contains("mg_pbr_brdf_is_schlick(") && !unlit.contains("geom.light"));
    let fragment = body("mg_fragment");
    let hoist = fragment
        .find("let u = mg_material_unlit(g);")
        .expect("hoisted call");
    let lo = fragment.find("for (var i = 0u;").unwrap();
    assert!(hoist < lo, "the unlit part runs before the loop");
    assert_eq!(
        fragment.matches("mg_material_lit(g, u)").count(),
        2,
        "{fragment}"
    );
    assert!(!fragment.contains("mg_material(g)"), "{fragment}");
    // The library module has the same split for an app's own light loop, and
    // `mg_material`; a compute module (one evaluation per sample) is not split.
    let library = WgslOptions {
        plan: PlanOptions::default(),
        entry: Entry::Library(matgraph::wgsl::TextureMode::Exact),
        ..Default::default()
    };
    let l = generate(&graph, &library).unwrap();
    for f in [
        "fn mg_material_unlit(",
        "fn mg_material_lit(",
        "fn mg_material(",
    ] {
        assert!(l.source.contains(f), "library: no {f}");
    }
    let c = generate(&graph, &WgslOptions::default()).unwrap();
    assert!(!c.source.contains("mg_material_unlit"));
}

/// No node's WGSL declares a large array constant: naga's SPIR-V backend stores a `const`
/// array into a temporary at every run-time index, and lavapipe took 263 s to compile one
/// loop over a 471-entry one (thin_film's former table; tables are `WgslTable`s now).
#[test]
fn node_wgsl_declares_no_large_array_constants() {
    let mut large = Vec::new();
    for t in Registry::builtin().types() {
        let templates = types_of(t).into_iter().filter_map(|g| t.wgsl_for(g));
        for text in t.wgsl_helpers_for(None).into_iter().chain(templates) {
            for (at, _) in text.match_indices("array<") {
                // The text up to the `>` that closes this `array<`.
                let mut depth = 0;
                let inner = text[at..]
                    .char_indices()
                    .find_map(|(k, c)| {
                        depth += (c == '<') as i32 - (c == '>') as i32;
                        (c == '>' && depth == 0).then(|| &text[at..at + k])
                    })
                    .unwrap_or(&text[at..]);
                let count = inner
                    .rsplit(',')
                    .next()
                    .and_then(|n| n.trim().parse::<u32>().ok());
                if count.is_some_and(|n| n > 16) {
                    large.push(format!("{}: {inner}>", t.name()));
                }
            }
        }
    }
    assert!(large.is_empty(), "large WGSL arrays: {large:?}");
}
