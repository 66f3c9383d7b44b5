//! The tangent frame in the app contract (issue 36 item 2): a graph that reads
//! `geometry.tangent` or `bitangent_sign` takes a second vertex buffer (slot 1, location 3,
//! `float32x4`: MikkTSpace tangent and sign) and says so in its contract; an app without one
//! asks for `derived_tangents` and gets a module that builds the frame from screen-space
//! derivatives and reads no location 3; a graph that reads neither is unchanged. Both modules
//! validate in naga (Material::new) and compile in Tint.

use crate::common;

use common::tint::Tint;
use matgraph::material::{Material, MaterialOptions};
use matgraph::{Graph, Registry};

/// A material reading the tangent frame: emission = sign · T.
const FRAME: &str = r#"{
  "version": 1, "name": "frame",
  "nodes": [
    { "id": "geo", "type": "geometry" },
    { "id": "s", "type": "scale", "inputs": {
        "v": { "link": "geo.tangent" }, "scale": { "link": "geo.bitangent_sign" } } }
  ],
  "outputs": [ { "name": "emission", "from": "s.result" } ]
}"#;

fn material(text: &str, derived: bool) -> Material {
    let graph = Graph::from_json(text, Registry::builtin()).unwrap();
    let options = MaterialOptions {
        derived_tangents: derived,
        ..MaterialOptions::default()
    };
    Material::new(&graph, &options).unwrap_or_else(|e| panic!("{e}"))
}

/// The `MgVertexIn` struct of a render module.
fn vertex_in(source: &str) -> &str {
    let start = source.find("struct MgVertexIn {").unwrap();
    &source[start..start + source[start..].find('}').unwrap()]
}

#[test]
fn a_graph_reading_the_tangent_frame_takes_a_tangent_buffer_and_says_so() {
    let m = material(FRAME, false);
    assert!(m.uses_tangents());
    let layouts = m.vertex_buffer_layouts();
    assert_eq!(layouts.len(), 2);
    assert_eq!(layouts[1].array_stride, 16);
    assert_eq!(layouts[1].attributes[0].shader_location, 3);
    assert_eq!(
        layouts[1].attributes[0].format,
        wgpu::VertexFormat::Float32x4
    );
    let c = m.contract();
    let t = c
        .tangent_buffer
        .as_ref()
        .expect("a tangent_buffer in the contract");
    assert_eq!((t.array_stride, t.attributes.len()), (16, 1));
    assert_eq!(t.attributes[0].name, "tangent");
    assert_eq!(t.attributes[0].shader_location, 3);
    assert_eq!(t.attributes[0].format, "float32x4");
    assert!(c.to_json().contains("\"tangent_buffer\""));
    assert!(vertex_in(m.wgsl()).contains("@location(3) tangent: vec4<f32>"));
}

#[test]
fn an_app_without_tangents_gets_them_from_derivatives() {
    let m = material(FRAME, true);
    assert!(!m.uses_tangents());
    assert_eq!(m.vertex_buffer_layouts().len(), 1);
    assert!(m.contract().tangent_buffer.is_none());
    let source = m.wgsl();
    assert!(
        !vertex_in(source).contains("tangent"),
        "{}",
        vertex_in(source)
    );
    assert!(source.contains("mg_derived_frame(n, v.position, v.uv)"));
    assert!(!source.contains("v.tangent.xyz"));
}

#[test]
fn graphs_that_read_no_tangent_are_unchanged() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/graphs/fresnel_glass.json");
    let text = std::fs::read_to_string(path).unwrap();
    for derived in [false, true] {
        let m = material(&text, derived);
        assert!(!m.uses_tangents());
        assert!(!m.contract().to_json().contains("tangent"));
        assert!(!vertex_in(m.wgsl()).contains("location(3)"));
    }
    assert_eq!(material(&text, false).wgsl(), material(&text, true).wgsl());
}

#[test]
fn both_tangent_modules_compile_in_tint() {
    let Some(tint) = common::tool_or_skip("both_tangent_modules_compile_in_tint", Tint::find())
    else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let files: Vec<_> = [false, true]
        .iter()
        .map(|&derived| {
            let file = dir.path().join(format!("frame_{derived}.wgsl"));
            std::fs::write(&file, material(FRAME, derived).wgsl()).unwrap();
            file
        })
        .collect();
    let found = tint.check(&files).unwrap_or_else(|e| panic!("{e}"));
    let errors: Vec<_> = found.iter().filter(|d| d.severity == "error").collect();
    assert!(errors.is_empty(), "{errors:?}");
}
