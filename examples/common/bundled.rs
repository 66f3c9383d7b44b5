//! The bundled graphs the timing examples run over.

use matgraph::scene::Scene;
use matgraph::texture::TextureSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The bundled graph files (`graphs/*.json`), sorted; with `only`, those whose file stem it
/// names.
pub fn graph_files(only: Option<&[String]>) -> Vec<PathBuf> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .filter(|p| {
            only.is_none_or(|names| {
                let stem = p.file_stem().unwrap_or_default().to_string_lossy();
                names.iter().any(|n| *n == stem)
            })
        })
        .collect();
    files.sort();
    files
}

/// A bundled graph, its scene (the ball where it names none) and its images.
pub fn load(path: &Path) -> (matgraph::Graph, Scene, Arc<TextureSet>) {
    let graph = matgraph::io::load_graph(path, matgraph::Registry::builtin()).unwrap();
    let scene = matgraph::render::graph_scene(&graph)
        .unwrap()
        .unwrap_or_else(|| Scene::preset("ball").unwrap());
    let textures = Arc::new(matgraph::image_io::load_graph_textures(&graph, path).unwrap());
    (graph, scene, textures)
}
