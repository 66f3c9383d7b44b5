//! The preview swatch: the graph rendered in its scene on the CPU ([`crate::render`]) at low
//! resolution, off the UI thread, until the GPU preview lands. One render runs at a time; a
//! change during it starts the next render when it finishes, with the newest document.

use crate::graph::Graph;
use crate::render::{RenderOptions, graph_scene, render};
use crate::scene::Scene;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

/// Side of the swatch in pixels.
pub const SIZE: u32 = 128;

/// A finished render: the revision it shows, and its sRGB pixels or why it failed.
type Finished = (u64, Result<Vec<[u8; 3]>, String>);

/// The swatch's state.
pub struct Preview {
    /// Whether previews are rendered at all (off in tests that do not look at them).
    pub enabled: bool,
    /// Incremented by every document change.
    revision: u64,
    /// The revision of the render in flight, if any.
    running: Option<u64>,
    /// The revision shown.
    shown: Option<u64>,
    done: Arc<Mutex<Option<Finished>>>,
    texture: Option<egui::TextureHandle>,
    /// The last render's error, if it failed.
    pub message: Option<String>,
}

impl Preview {
    /// A preview with nothing rendered yet.
    pub fn new() -> Preview {
        Preview {
            enabled: true,
            revision: 1,
            running: None,
            shown: None,
            done: Arc::new(Mutex::new(None)),
            texture: None,
            message: None,
        }
    }

    /// Marks the swatch out of date.
    pub fn invalidate(&mut self) {
        self.revision += 1;
    }

    /// Whether the swatch shows the current document (nothing is rendering or due).
    pub fn settled(&self) -> bool {
        !self.enabled || (self.running.is_none() && self.shown == Some(self.revision))
    }

    /// Collects a finished render and starts the next one when due.
    pub fn poll(&mut self, ctx: &egui::Context, graph: Option<&Graph>, file: Option<&PathBuf>) {
        if !self.enabled {
            return;
        }
        let finished = self.done.lock().map(|mut d| d.take()).unwrap_or(None);
        if let Some((rev, result)) = finished {
            self.running = None;
            self.shown = Some(rev);
            match result {
                Ok(pixels) => {
                    let rgba: Vec<u8> = pixels
                        .iter()
                        .flat_map(|p| [p[0], p[1], p[2], 255])
                        .collect();
                    let image = egui::ColorImage::from_rgba_unmultiplied(
                        [SIZE as usize, SIZE as usize],
                        &rgba,
                    );
                    self.texture = Some(ctx.load_texture(
                        "matgraph-preview",
                        image,
                        egui::TextureOptions::LINEAR,
                    ));
                    self.message = None;
                }
                Err(e) => self.message = Some(e),
            }
        }
        if self.running.is_some() || self.shown == Some(self.revision) {
            return;
        }
        let Some(graph) = graph.cloned() else {
            self.shown = Some(self.revision);
            self.message = Some("the graph has errors".into());
            return;
        };
        let rev = self.revision;
        self.running = Some(rev);
        let done = self.done.clone();
        let ctx = ctx.clone();
        let file = file.cloned();
        std::thread::spawn(move || {
            let result = render_swatch(&graph, file.as_ref());
            if let Ok(mut d) = done.lock() {
                *d = Some((rev, result));
            }
            ctx.request_repaint();
        });
    }

    /// The swatch texture, once one render finished.
    pub fn texture(&self) -> Option<&egui::TextureHandle> {
        self.texture.as_ref()
    }
}

impl Default for Preview {
    fn default() -> Self {
        Preview::new()
    }
}

/// Renders `graph` in its scene (the ball when it names none) at [`SIZE`]², 1 sample.
pub fn render_swatch(graph: &Graph, file: Option<&PathBuf>) -> Result<Vec<[u8; 3]>, String> {
    let scene = graph_scene(graph)
        .ok()
        .flatten()
        .or_else(|| Scene::preset("ball"))
        .ok_or("no scene")?;
    let textures = match file {
        Some(f) => Some(Arc::new(
            crate::image_io::load_graph_textures_with(
                graph,
                f,
                crate::io::PathPolicy::InsideGraphFolder,
            )
            .map_err(|e| e.to_string())?,
        )),
        None => None,
    };
    let options = RenderOptions {
        width: SIZE,
        height: SIZE,
        samples: 1,
        textures,
        ..Default::default()
    };
    let hdr = render(graph, &scene, &options).map_err(|e| e.to_string())?;
    Ok(hdr.to_srgb8(1.0).pixels)
}
