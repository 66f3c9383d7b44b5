//! Refusing to write a command's output over one of its inputs (`matgraph wgsl g.json -o
//! g.json`) or over another of its outputs (`--contract X -o X`): paths are compared as
//! files ([`matgraph::io::file_identity`]), so a symlink or a hard link to an input is that
//! input. `fmt` (and `edit --arrange`) rewrite their inputs in place by design and do not
//! use this.

use matgraph::Graph;
use matgraph::io::{FileIdentity, file_identity};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Whether a file is read or written by the command.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Role {
    Input,
    Output,
}

/// The files a command reads and writes, each with what it is in the user's words
/// ("the input graph g.json", "the -o output").
#[derive(Default)]
pub struct Files {
    seen: HashMap<FileIdentity, (Role, String)>,
}

impl Files {
    /// Records one file; refuses one already recorded as an output, or an output already
    /// recorded as anything.
    fn add(&mut self, path: &Path, role: Role, what: String) -> Result<(), String> {
        let id = file_identity(path);
        match self.seen.get(&id) {
            None => {
                self.seen.insert(id, (role, what));
                Ok(())
            }
            // Reading one file twice is fine.
            Some((Role::Input, _)) if role == Role::Input => Ok(()),
            Some((Role::Input, input)) => Err(format!(
                "{}: the {what} would overwrite {input} (the same file); refusing to write it: \
                 choose another output file",
                path.display()
            )),
            Some((Role::Output, output)) if role == Role::Input => Err(format!(
                "{}: the {output} would overwrite {what} (the same file); refusing to write it: \
                 choose another output file",
                path.display()
            )),
            Some((Role::Output, other)) => Err(format!(
                "{}: the {what} and the {other} are the same file; refusing to write one over \
                 the other: give each its own file",
                path.display()
            )),
        }
    }

    /// Records a file the command reads, `what` it is ("the input graph g.json").
    pub fn input(&mut self, path: &Path, what: impl Into<String>) -> Result<(), String> {
        self.add(path, Role::Input, what.into())
    }

    /// Records a file the command writes, `what` it is ("-o output").
    pub fn output(&mut self, path: &Path, what: impl Into<String>) -> Result<(), String> {
        self.add(path, Role::Output, what.into())
    }

    /// Records the files graph `graph`, read from `file`, names: its textures, its scene
    /// file and environment image, and the files of the groups its own nodes use (the files
    /// those files name in turn are not followed). Paths that cannot be resolved are left to
    /// the loaders, which report them.
    pub fn graph_inputs(&mut self, graph: &Graph, file: &Path) -> Result<(), String> {
        let folder = match file.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_owned(),
            _ => PathBuf::from("."),
        };
        let at = file.display();
        for node in graph.nodes() {
            let Some(source) = &node.texture else {
                continue;
            };
            for f in source.files() {
                self.input(
                    &folder.join(f),
                    format!("the image {f} of node '{}' in {at}", node.id),
                )?;
            }
        }
        for node in &graph.to_document().nodes {
            let Some(reference) = &node.group else {
                continue;
            };
            let path = match reference.split_once('#') {
                Some((p, _)) if !p.is_empty() => p,
                None if reference.ends_with(".json") => reference.as_str(),
                _ => continue,
            };
            self.input(
                &folder.join(path),
                format!("the group file {path} of node '{}' in {at}", node.id),
            )?;
        }
        let mut scene_base = file.to_owned();
        let mut environment = None;
        match &graph.scene {
            Some(serde_json::Value::String(name))
                if matgraph::scene::Scene::preset(name).is_none() =>
            {
                let path = folder.join(name);
                self.input(&path, format!("the scene file {name} of {at}"))?;
                if let Some(scene) = matgraph::io::read_text(&path)
                    .ok()
                    .and_then(|t| matgraph::scene::Scene::from_json(&t).ok())
                {
                    environment = Some(scene.environment);
                }
                scene_base = path;
            }
            _ => {
                environment = matgraph::render::graph_scene(graph)
                    .ok()
                    .flatten()
                    .map(|s| s.environment);
            }
        }
        if let Some(matgraph::scene::Environment::Image(img)) = environment {
            let path = matgraph::image_io::resolve_relative(&scene_base, Path::new(&img.path));
            self.input(&path, format!("the environment image {} of {at}", img.path))?;
        }
        Ok(())
    }
}
