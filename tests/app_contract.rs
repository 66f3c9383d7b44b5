//! The app contract (`matgraph::material`, docs/integration.md): every bundled graph's render
//! and library modules in both texture modes, the contract JSON, the parameter writer, and
//! the example's image against the CPU executor on the same geometry.

mod common;
use common::bundled_graphs;

use matgraph::material::{Material, MaterialOptions};
use matgraph::wgsl::TextureMode;
use matgraph::Registry;

fn load(path: &std::path::Path) -> matgraph::Graph {
    matgraph::io::load_graph(path, Registry::builtin()).unwrap()
}

fn options(textures: TextureMode) -> MaterialOptions {
    MaterialOptions {
        textures,
        ..MaterialOptions::default()
    }
}

#[test]
fn every_bundled_graph_makes_a_material_within_webgpu_default_limits() {
    for path in bundled_graphs() {
        let graph = load(&path);
        for mode in [TextureMode::Hardware, TextureMode::Exact] {
            let m = Material::new(&graph, &options(mode))
                .unwrap_or_else(|e| panic!("{}: {mode:?}: {e}", path.display()));
            let c = m.contract();
            assert!(
                c.per_stage.storage_buffers <= 8,
                "{}: {c:?}",
                path.display()
            );
            assert!(c.per_stage.uniform_buffers <= 12);
            assert!(c.per_stage.sampled_textures <= 16);
            assert!(c.per_stage.samplers <= 16);
            assert!(m.wgsl().contains("fn mg_vertex(") && m.wgsl().contains("fn mg_fragment("));
            assert!(m.library_wgsl().contains("fn mg_material("));
            assert!(!m.library_wgsl().contains("@fragment"));
        }
    }
}
