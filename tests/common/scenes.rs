//! Scenes and render options as `matgraph render` picks them, and graphs from JSON text.

use matgraph::gpu::Backend;
use matgraph::render::RenderOptions;
use matgraph::scene::Scene;
use matgraph::{Graph, Registry};
use std::path::Path;
use std::sync::Arc;

/// The scene a graph names (ball by default), as `matgraph render` picks it.
pub fn scene_of(graph: &Graph) -> Scene {
    matgraph::render::graph_scene(graph)
        .unwrap()
        .unwrap_or_else(|| Scene::preset("ball").unwrap())
}

/// A `size`² render at 1 sample per pixel on `backend`, with the images of `graph`'s file
/// at `path`.
pub fn render_options(size: u32, backend: Backend, graph: &Graph, path: &Path) -> RenderOptions {
    let textures = matgraph::image_io::load_graph_textures(graph, path).unwrap();
    RenderOptions {
        width: size,
        height: size,
        samples: 1,
        backend,
        textures: Some(Arc::new(textures)),
        ..RenderOptions::default()
    }
}

/// The graph in `text`, loaded with the built-in registry (panics with the errors).
pub fn graph(text: &str) -> Graph {
    Graph::from_json(text, Registry::builtin()).unwrap_or_else(|e| panic!("{e:?}"))
}
