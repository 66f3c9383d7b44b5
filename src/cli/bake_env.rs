//! `matgraph bake-env`: write every image-based-lighting texture a graph can ask for, with
//! their manifest, for apps that bind the contract themselves (docs/integration.md "Scene
//! textures").

use super::CliResult;
use matgraph::scene::{Environment, ImageEnvironment, SCENE_PRESETS, Scene};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Options of `matgraph bake-env`.
#[derive(clap::Args)]
pub struct Args {
    /// What to bake: a graph file (`.json`: the environment its scene gives, as `matgraph
    /// render` binds it), a scene preset (ball, plane, water, bubble), or an equirectangular
    /// image (`.hdr`, `.exr`, `.png`, `.jpg`: that image alone, no room around it).
    pub source: String,
    /// The folder to write `manifest.json` and the texel files into (made if missing).
    #[arg(long)]
    pub out: PathBuf,
    /// Read a scene file or environment image outside the graph's folder.
    #[arg(long)]
    pub allow_outside_paths: bool,
    /// Also write the scene's view at this image size, WxH: `view.json` (camera as a
    /// WebGPU view_proj, lights as MgLight records, time), `mesh.bin` (the material mesh
    /// in the contract's vertex layout, then u32 indices), `depth.r32f` (the rest of the
    /// scene's depth, to load into the depth buffer first) and the screen-space scene
    /// textures of that frame (scene:background, scene:refraction, scene:reflection, in the
    /// manifest), to draw what `matgraph render` shows (docs/integration.md, "A scene's
    /// view").
    #[arg(long, value_name = "WxH", value_parser = super::render::parse_size)]
    pub view: Option<(u32, u32)>,
}

/// The scene and environment image `source` names, and how the manifest calls it.
fn source_scene(args: &Args) -> Result<(Scene, Option<Arc<matgraph::texture::Texture>>), String> {
    if let Some(scene) = Scene::preset(&args.source) {
        return Ok((scene, None));
    }
    let path = Path::new(&args.source);
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("json") => {
            let graph = super::load_graph_with(path, &[])?;
            super::scene::resolve(
                &graph,
                path,
                None,
                super::path_policy(args.allow_outside_paths),
                &matgraph::budget::MemoryBudget::default(),
            )
        }
        Some("hdr" | "exr" | "png" | "jpg" | "jpeg") => {
            let texture = matgraph::image_io::load_texture(&[path.to_owned()], false)
                .map_err(|e| format!("{}: {e}", path.display()))?;
            // The image alone: a water scene's map is its environment, with no room in it.
            let mut scene = Scene::preset("water").expect("the water preset exists");
            scene.environment = Environment::Image(ImageEnvironment {
                path: args.source.clone(),
                ..ImageEnvironment::default()
            });
            Ok((scene, Some(Arc::new(texture))))
        }
        _ => Err(format!(
            "bake-env {}: not a scene preset ({}), a graph file (.json) nor an image (.hdr, \
             .exr, .png, .jpg)",
            matgraph::visible::visible(&args.source),
            SCENE_PRESETS.join(", ")
        )),
    }
}

/// Bakes and writes the textures and the manifest.
pub fn run(args: &Args) -> CliResult {
    let (scene, image) = source_scene(args)?;
    let baked = matgraph::render::bake::bake_environment(&scene, image, &args.source, args.view)
        .map_err(|e| format!("bake-env {}: {e}", matgraph::visible::visible(&args.source)))?;
    super::out_dir::make_out_dir("--out", &args.out)?;
    let files = baked.files();
    let mut bytes = 0u64;
    for (name, data) in &files {
        let path = args.out.join(name);
        matgraph::io::write_atomic(&path, data)
            .map_err(|e| super::out_dir::write_error(&path, &e))?;
        bytes += data.len() as u64;
    }
    if let Some((w, h)) = args.view {
        use matgraph::render::view::{DEPTH_FILE, MESH_FILE, SceneView, depth_bytes, mesh_bytes};
        let view = SceneView::of(&scene, w, h);
        for (name, data) in [
            ("view.json", view.to_json().into_bytes()),
            (MESH_FILE, mesh_bytes(&scene)),
            (DEPTH_FILE, depth_bytes(&scene, &view)),
        ] {
            let path = args.out.join(name);
            matgraph::io::write_atomic(&path, &data)
                .map_err(|e| super::out_dir::write_error(&path, &e))?;
        }
        eprintln!(
            "view {w} × {h}: {} lights, mesh of {} vertices and {} triangles",
            view.lights.len(),
            view.mesh.vertices,
            view.mesh.indices / 3
        );
    }
    for t in &baked.manifest.textures {
        eprintln!(
            "{}: {} × {}, {}",
            t.name,
            t.width,
            t.height,
            super::count(t.mip_levels as usize, "level")
        );
    }
    eprintln!(
        "wrote {} ({:.1} MiB) and {} to {}",
        super::count(files.len() - 1, "texel file"),
        bytes as f64 / (1 << 20) as f64,
        matgraph::render::bake::MANIFEST_FILE,
        args.out.display()
    );
    Ok(())
}
