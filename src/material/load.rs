//! Loading a material from a graph file: the one part of [`super`] that reads files (through
//! [`crate::io`] and [`crate::image_io`], which confine paths to the graph's folder).

use super::{Material, MaterialOptions};
use crate::texture::TextureSet;
use std::path::Path;

/// Why a graph file could not be loaded as a material; the message names the file.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The graph file could not be read or is invalid.
    #[error(transparent)]
    Graph(#[from] crate::GraphErrors),
    /// An image the graph names could not be loaded.
    #[error(transparent)]
    Texture(#[from] crate::texture::TextureError),
    /// The graph cannot be made into a material.
    #[error("{}: {source}", file.display())]
    Material {
        /// The graph file.
        file: std::path::PathBuf,
        /// Why.
        source: Box<super::MaterialError>,
    },
}

impl Material {
    /// Loads the graph file at `path` and the image files its texture nodes name (not the
    /// `scene:` textures, which the app renders), and compiles the material, with the
    /// texture sizes recorded for the contract.
    pub fn from_path(
        path: &Path,
        options: &MaterialOptions,
    ) -> Result<(Material, TextureSet), LoadError> {
        let graph = crate::io::load_graph(path, crate::Registry::builtin())?;
        let textures = crate::image_io::load_graph_textures(&graph, path)?;
        let mut material =
            Material::new(&graph, options).map_err(|source| LoadError::Material {
                file: path.to_owned(),
                source: Box::new(source),
            })?;
        material.bind_textures(&textures);
        Ok((material, textures))
    }
}
