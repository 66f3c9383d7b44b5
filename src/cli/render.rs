//! `matgraph render`: render graphs in a scene to PNG (and EXR).

use super::{CliResult, registry, split_set};
use matgraph::Value;
use std::path::{Path, PathBuf};

/// Help text after the options of `matgraph render`.
pub const AFTER_HELP: &str = "With several graphs, -o OUT.png writes one labelled contact sheet; --out-dir writes \
    one PNG per graph (named after the file) plus contact_sheet.png. Without either, --out-dir renders.\n\
    A graph's `color` output is lit (evaluated per light and summed); `emission` is added once; `alpha` \
    blends over the background; `displacement` (vec3) moves the surface. A graph without `color` or \
    `emission` shows its first output unlit.";

/// Options of `matgraph render`.
#[derive(clap::Args)]
pub struct Args {
    /// Graph files.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Output PNG (one graph), or the contact sheet of several.
    #[arg(short = 'o', long = "out", conflicts_with = "out_dir")]
    pub out: Option<PathBuf>,
    /// Folder for one PNG per graph and a contact sheet.
    #[arg(long)]
    pub out_dir: Option<PathBuf>,
    /// Image size, WxH.
    #[arg(long, default_value = "512x512", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Scene: a preset (ball, water) or a scene JSON file; default: the graph's own scene,
    /// else ball.
    #[arg(long)]
    pub scene: Option<String>,
    /// Scene time in seconds (the scene's own time by default).
    #[arg(long)]
    pub time: Option<f32>,
    /// Samples per pixel (stratified, box-filtered).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub samples: u32,
    /// Evaluate the material on the GPU (wgpu; any adapter, lavapipe included).
    #[arg(long, conflicts_with = "cpu")]
    pub gpu: bool,
    /// Evaluate the material on the CPU (the default).
    #[arg(long)]
    pub cpu: bool,
    /// Also write the linear HDR image as OpenEXR next to each PNG.
    #[arg(long)]
    pub exr: bool,
    /// Exposure in stops applied before tone mapping.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
    /// Override a parameter: NAME=VALUE.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub sets: Vec<String>,
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or("expected WxH, for example 512x512")?;
    let parse = |v: &str| v.trim().parse::<u32>().map_err(|e| format!("'{v}': {e}"));
    let (w, h) = (parse(w)?, parse(h)?);
    if w == 0 || h == 0 || w > 16384 || h > 16384 {
        return Err(format!("{w}x{h}: each side must be 1 to 16384"));
    }
    Ok((w, h))
}

/// Loads the scene named by `--scene`: a preset name or a scene file.
fn load_scene(spec: &str) -> Result<matgraph::scene::Scene, String> {
    if let Some(scene) = matgraph::scene::Scene::preset(spec) {
        return Ok(scene);
    }
    let path = Path::new(spec);
    if !path.exists() {
        return Err(format!(
            "--scene {spec}: not a preset ({}) nor a file",
            matgraph::scene::SCENE_PRESETS.join(", ")
        ));
    }
    let text = std::fs::read_to_string(path).map_err(|e| format!("{spec}: cannot read: {e}"))?;
    matgraph::scene::Scene::from_json(&text).map_err(|e| format!("{spec}: {e}"))
}

/// The image of an image environment, loaded relative to `base` (the file the scene was
/// written in); `None` for a sky.
fn environment_image(
    scene: &matgraph::scene::Scene,
    base: &Path,
) -> Result<Option<std::sync::Arc<matgraph::texture::Texture>>, String> {
    let matgraph::scene::Environment::Image(img) = &scene.environment else {
        return Ok(None);
    };
    let path = matgraph::image_io::resolve_relative(base, Path::new(&img.path));
    let texture = matgraph::image_io::load_texture(&[path], false)
        .map_err(|e| format!("environment: {e}"))?;
    Ok(Some(std::sync::Arc::new(texture)))
}

/// A progress spinner on stderr that appears only once the work has taken a second.
fn delayed_progress() -> indicatif::ProgressBar {
    let bar =
        indicatif::ProgressBar::with_draw_target(None, indicatif::ProgressDrawTarget::hidden());
    bar.set_style(
        indicatif::ProgressStyle::with_template("{spinner} [{elapsed}] {pos}/{len} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
    );
    let shown = bar.clone();
    std::thread::spawn(move || {
        std::thread::sleep(std::time::Duration::from_secs(1));
        if !shown.is_finished() {
            shown.set_draw_target(indicatif::ProgressDrawTarget::stderr());
            shown.enable_steady_tick(std::time::Duration::from_millis(120));
        }
    });
    bar
}

/// Renders every graph and writes the images.
pub fn run(args: &Args) -> CliResult {
    use matgraph::render::{RenderOptions, render_timed, sheet};
    let forced = args.scene.as_deref().map(load_scene).transpose()?;
    let mut parameters = Vec::new();
    for s in &args.sets {
        let (name, json) = split_set(s)?;
        let v = Value::infer_json(&json).ok_or_else(|| {
            format!("--set {s}: expected a number, an array of 2-4 numbers or a bool")
        })?;
        parameters.push((name.to_owned(), v));
    }
    let (out_dir, sheet_path) = match (&args.out, &args.out_dir) {
        // One graph: its image; several: their contact sheet.
        (Some(o), _) => (None, Some(o.clone())),
        (None, Some(d)) => (
            Some(d.clone()),
            (args.files.len() > 1).then(|| d.join("contact_sheet.png")),
        ),
        (None, None) => {
            let d = PathBuf::from("renders");
            (
                Some(d.clone()),
                (args.files.len() > 1).then(|| d.join("contact_sheet.png")),
            )
        }
    };
    if let Some(d) = &out_dir {
        std::fs::create_dir_all(d).map_err(|e| format!("{}: {e}", d.display()))?;
    }
    let backend = if args.gpu {
        matgraph::gpu::Backend::Gpu
    } else {
        matgraph::gpu::Backend::Cpu
    };
    let progress = delayed_progress();
    progress.set_length(args.files.len() as u64);
    let mut tiles = Vec::new();
    let mut failures = Vec::new();
    for file in &args.files {
        progress.set_message(file.display().to_string());
        let result = (|| -> Result<(String, sheet::Rgb8Image), String> {
            let graph = matgraph::io::load_graph(file, registry()).map_err(|e| e.to_string())?;
            let textures = matgraph::image_io::load_graph_textures(&graph, file)
                .map_err(|e| format!("{}: {e}", file.display()))?;
            // Paths inside a scene (an environment image) are relative to where it was written.
            let scene_base = match (&args.scene, &graph.scene) {
                (Some(spec), _) => PathBuf::from(spec),
                (None, Some(serde_json::Value::String(name))) => {
                    matgraph::image_io::resolve_relative(file, Path::new(name))
                }
                _ => file.clone(),
            };
            let scene = match (&forced, &graph.scene) {
                (Some(s), _) => s.clone(),
                (None, Some(serde_json::Value::String(name)))
                    if matgraph::scene::Scene::preset(name).is_none() =>
                {
                    // A scene file, relative to the graph file.
                    load_scene(&scene_base.display().to_string())
                        .map_err(|e| format!("{}: scene: {e}", file.display()))?
                }
                (None, _) => matgraph::render::graph_scene(&graph)
                    .map_err(|e| format!("{}: scene: {e}", file.display()))?
                    .unwrap_or_else(|| {
                        matgraph::scene::Scene::preset("ball").expect("the ball preset exists")
                    }),
            };
            let options = RenderOptions {
                width: args.size.0,
                height: args.size.1,
                samples: args.samples,
                time: args.time,
                backend,
                parameters: parameters.clone(),
                textures: Some(std::sync::Arc::new(textures)),
                environment: environment_image(&scene, &scene_base)
                    .map_err(|e| format!("{}: {e}", file.display()))?,
            };
            let start = std::time::Instant::now();
            let (hdr, _) = render_timed(&graph, &scene, &options)
                .map_err(|e| format!("{}: {e}", file.display()))?;
            let elapsed = start.elapsed();
            let image = hdr.to_srgb8(args.exposure);
            let stem = file
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or("graph")
                .to_owned();
            let single = if args.files.len() == 1 {
                sheet_path.clone()
            } else {
                None
            };
            let target = single.or_else(|| out_dir.as_ref().map(|d| d.join(format!("{stem}.png"))));
            if let Some(png) = &target {
                matgraph::image_io::save_png_rgb8(png, image.width, image.height, &image.pixels)
                    .map_err(|e| e.to_string())?;
                if args.exr {
                    let exr = png.with_extension("exr");
                    let data = hdr.pixels.iter().map(|c| [c[0], c[1], c[2], 1.0]).collect();
                    let img = matgraph::texture::Image::new(hdr.width, hdr.height, data)
                        .map_err(|e| e.to_string())?;
                    matgraph::image_io::save_exr(&exr, &img).map_err(|e| e.to_string())?;
                }
                progress.suspend(|| {
                    println!(
                        "{} -> {} ({}x{}, {} spp, {}, {:.2} s)",
                        file.display(),
                        png.display(),
                        image.width,
                        image.height,
                        args.samples,
                        if args.gpu { "gpu" } else { "cpu" },
                        elapsed.as_secs_f64()
                    )
                });
            }
            Ok((graph.name.clone(), image))
        })();
        match result {
            Ok(tile) => tiles.push(tile),
            Err(e) => {
                progress.suspend(|| eprintln!("{e}"));
                failures.push(file.display().to_string());
            }
        }
        progress.inc(1);
    }
    progress.finish_and_clear();
    if args.files.len() > 1
        && let Some(path) = &sheet_path
        && !tiles.is_empty()
    {
        let sheet = sheet::contact_sheet(&tiles);
        matgraph::image_io::save_png_rgb8(path, sheet.width, sheet.height, &sheet.pixels)
            .map_err(|e| e.to_string())?;
        println!(
            "contact sheet of {} graphs -> {}",
            tiles.len(),
            path.display()
        );
    }
    if failures.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{} of {} graphs failed",
            failures.len(),
            args.files.len()
        ))
    }
}
