//! `matgraph render`: render graphs in a scene to PNG (and EXR).

use super::{CliResult, count, graph_textures, load_graph_with, path_policy};
use matgraph::image_io::SaveFormat;
use std::path::{Path, PathBuf};

/// Bytes per pixel the command holds besides the render itself: the 8-bit image (3) and
/// its encoded file (3, an upper bound for PNG and JPEG of rendered images); with EXR, the
/// RGBA f32 image (16) and its encoding (16).
fn output_bytes_per_pixel(exr: bool) -> u64 {
    6 + if exr { 32 } else { 0 }
}

/// Help text after the options of `matgraph render`.
pub const AFTER_HELP: &str = "With several graphs, -o OUT.png writes one labelled contact sheet; --out-dir writes \
    one PNG per graph (named after the file) plus contact_sheet.png. Without either, --out-dir renders.\n\
    A graph's `color` output is lit (evaluated per light and summed); `emission` is added once; `alpha` \
    blends over the background; `displacement` (vec3) moves the surface. A graph without `color` or \
    `emission` shows its first output unlit.\n\
    --frames N renders frame k at --time + k/FPS (the scene's time when --time is absent): \
    NAME_0000.png … and NAME.png as an animated PNG (APNG) of them.";

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
    /// Scene: a preset (ball, plane, water, bubble) or a scene JSON file; default: the graph's own scene,
    /// else ball. A forced scene keeps the lights and environment the graph's own scene writes
    /// out (its time of day), except those the scene file writes itself.
    #[arg(long)]
    pub scene: Option<String>,
    /// Scene time in seconds (the scene's own time by default); a finite number.
    #[arg(long, value_parser = super::flags::finite_f32, allow_negative_numbers = true, allow_hyphen_values = true)]
    pub time: Option<f32>,
    /// Samples per pixel (stratified, box-filtered).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub samples: u32,
    /// Render on the GPU (wgpu render pipelines; any adapter, lavapipe included); the
    /// adapter is named on stderr (`adapter: NAME (BACKEND)`).
    #[arg(long, conflicts_with_all = ["cpu", "gpu_compute"])]
    pub gpu: bool,
    /// Rasterise on the CPU and shade the G-buffer on the GPU (the hybrid path); the adapter
    /// is named on stderr as with --gpu.
    #[arg(long, conflicts_with = "cpu")]
    pub gpu_compute: bool,
    /// How --gpu binds the material's textures: texture_2d + samplers with mips (hardware, the
    /// GPU's own filtering) or storage buffers filtered as on the CPU, bit for bit (exact).
    #[arg(long, default_value = "hardware", value_parser = ["hardware", "exact"])]
    pub textures: String,
    /// Evaluate the material on the CPU (the default).
    #[arg(long)]
    pub cpu: bool,
    /// Also write the linear HDR image as OpenEXR next to each PNG.
    #[arg(long)]
    pub exr: bool,
    /// Exposure in stops applied before tone mapping, -64 to 64.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, allow_hyphen_values = true,
          value_parser = super::flags::exposure)]
    pub exposure: f32,
    /// Override a parameter: NAME=VALUE.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub sets: Vec<String>,
    #[command(flatten)]
    pub variant: super::shared::VariantFlags,
    /// Render N frames at --time + k/FPS: numbered stills NAME_0000.png … and NAME.png as
    /// an animated PNG (APNG) of all of them.
    #[arg(
        long,
        value_name = "N",
        allow_negative_numbers = true,
        allow_hyphen_values = true
    )]
    pub frames: Option<u32>,
    /// Frames per second of --frames [default: 24].
    #[arg(
        long,
        value_name = "FPS",
        requires = "frames",
        allow_negative_numbers = true, allow_hyphen_values = true,
        value_parser = super::flags::finite_f32
    )]
    pub fps: Option<f32>,
    /// Read textures, scene files and environment images outside the graph's folder.
    #[arg(long)]
    pub allow_outside_paths: bool,
    /// Memory each graph's render may use: its images, environment, scene meshes, frame
    /// and output images (bytes, or with a unit: 512MiB, 4GiB); an input that does not fit
    /// is refused before it is allocated, and the frame is rendered in bands that fit.
    #[arg(long, value_name = "SIZE", default_value = "2GiB", value_parser = super::flags::memory_budget)]
    pub memory_budget: u64,
    /// Compile each graph against its scene first and print the rewrites
    /// (docs/specialise.md): `exact` folds what the scene fixes; `approx` also applies the
    /// threshold rewrites (a thick film's incoherent limit).
    #[arg(long, value_name = "MODE", num_args = 0..=1, default_missing_value = "exact",
          value_parser = ["exact", "approx"])]
    pub specialise: Option<String>,
}

/// An image size `WxH`, each side 1 to 16384.
pub(super) fn parse_size(s: &str) -> Result<(u32, u32), String> {
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

/// Every file the render of one graph to `target` writes: the image (or, with `frames`,
/// the numbered stills and the animation), and with `exr` (or an `.exr` target) the EXR
/// beside each still.
fn written_files(
    target: &Path,
    frames: Option<&matgraph::render::frames::Frames>,
    exr: bool,
) -> Result<Vec<PathBuf>, String> {
    use matgraph::render::frames::Frames;
    let stills: Vec<PathBuf> = match frames {
        Some(f) => (0..f.count).map(|k| Frames::numbered(target, k)).collect(),
        None => vec![target.to_owned()],
    };
    let mut out = Vec::new();
    for still in stills {
        let format = SaveFormat::from_path(&still).map_err(|e| e.to_string())?;
        if format != SaveFormat::Exr {
            out.push(still.clone());
        }
        if exr || format == SaveFormat::Exr {
            out.push(still.with_extension("exr"));
        }
    }
    if frames.is_some() {
        out.push(target.to_owned());
    }
    Ok(out)
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
    use matgraph::render::frames::{Apng, Frames};
    use matgraph::render::{RenderOptions, render_timed, sheet};
    let policy = path_policy(args.allow_outside_paths);
    let forced = args
        .scene
        .as_deref()
        .map(|spec| super::scene::forced_scene(spec).map(|s| (spec, s)))
        .transpose()?;
    let mut parameters = Vec::new();
    for s in &args.sets {
        let o = matgraph::overrides::Override::parse(s).map_err(|e| e.to_string())?;
        let v = o.inferred().map_err(|e| e.to_string())?;
        parameters.push((o.name, v));
    }
    let several = args.files.len() > 1;
    let (out_dir, sheet_path) = match (&args.out, &args.out_dir) {
        // One graph: its image; several: their contact sheet.
        (Some(o), _) => (None, Some(o.clone())),
        (None, Some(d)) => (
            Some(d.clone()),
            several.then(|| d.join("contact_sheet.png")),
        ),
        (None, None) => {
            let d = PathBuf::from("renders");
            (
                Some(d.clone()),
                several.then(|| d.join("contact_sheet.png")),
            )
        }
    };
    // The format of -o, by its extension, before anything is rendered.
    let out_format = match &args.out {
        Some(o) => Some(SaveFormat::from_path(o).map_err(|e| e.to_string())?),
        None => None,
    };
    if several && out_format == Some(SaveFormat::Exr) {
        return Err("a contact sheet is 8-bit: -o must end in .png, .jpg or .jpeg".to_owned());
    }
    let frames = match args.frames {
        Some(n) => Some(Frames::new(n, args.fps.unwrap_or(24.0)).map_err(|e| e.to_string())?),
        None => None,
    };
    if frames.is_some() {
        if out_format.is_some_and(|f| f != SaveFormat::Png) {
            return Err("--frames writes an animated PNG: -o must end in .png".to_owned());
        }
        if several && args.out.is_some() {
            return Err(
                "--frames with several graphs writes one sequence per graph: use --out-dir"
                    .to_owned(),
            );
        }
    }
    let frame_count = frames.map_or(1, |f| f.count);
    // Memory: what this command holds besides each render, then the render's own plan.
    let (w, h) = (args.size.0 as u64, args.size.1 as u64);
    let exr = args.exr || out_format == Some(SaveFormat::Exr);
    let mut reserve = w * h * output_bytes_per_pixel(exr);
    if frames.is_some() {
        // The animation, built in memory: at most its frames' raw RGB.
        reserve += w * h * 3 * frame_count as u64;
    }
    if several && sheet_path.is_some() {
        // The 8-bit renders kept for the contact sheet, then the sheet and its file.
        reserve += w * h * 3 * args.files.len() as u64 + w * h * 6;
    }
    if reserve >= args.memory_budget {
        return Err(format!(
            "{}x{}: the output images alone need {} MiB, over the memory budget of {} MiB; \
             render a smaller size{}",
            args.size.0,
            args.size.1,
            reserve.div_ceil(1 << 20),
            args.memory_budget >> 20,
            if several {
                " or fewer graphs at once"
            } else {
                ""
            }
        ));
    }
    // Where each graph's image goes, and nothing written over an input or written twice.
    let targets: Vec<Option<PathBuf>> = args
        .files
        .iter()
        .map(|file| {
            let stem = file.file_stem().and_then(|s| s.to_str()).unwrap_or("graph");
            let single = if several { None } else { sheet_path.clone() };
            single.or_else(|| out_dir.as_ref().map(|d| d.join(format!("{stem}.png"))))
        })
        .collect();
    let mut files = super::outputs::Files::default();
    for file in &args.files {
        files.input(file, format!("the input graph {}", file.display()))?;
    }
    if let Some((spec, forced)) = &forced
        && matgraph::scene::Scene::preset(spec).is_none()
    {
        files.input(Path::new(spec), format!("the --scene file {spec}"))?;
        if let matgraph::scene::Environment::Image(img) = &forced.scene.environment {
            let path = matgraph::image_io::resolve_relative(Path::new(spec), Path::new(&img.path));
            files.input(
                &path,
                format!("the environment image {} of {spec}", img.path),
            )?;
        }
    }
    for (file, target) in args.files.iter().zip(&targets) {
        let Some(target) = target else { continue };
        for p in written_files(target, frames.as_ref(), args.exr)? {
            let what = if args.out.is_some() && &p == target {
                "-o output".to_owned()
            } else {
                format!("output of {}", file.display())
            };
            files.output(&p, what)?;
        }
    }
    if several && let Some(sheet) = &sheet_path {
        files.output(sheet, "contact sheet")?;
    }
    if let Some(d) = &out_dir {
        super::out_dir::make_out_dir("--out-dir", d)?;
    }
    let backend = if args.gpu {
        matgraph::gpu::Backend::Gpu
    } else if args.gpu_compute {
        matgraph::gpu::Backend::GpuCompute
    } else {
        matgraph::gpu::Backend::Cpu
    };
    // The adapter that ran, said once on stderr after the first render that used it.
    let adapter_said = std::cell::Cell::new(backend == matgraph::gpu::Backend::Cpu);
    let progress = delayed_progress();
    progress.set_length(args.files.len() as u64 * frame_count as u64);
    let mut tiles = Vec::new();
    let mut failures = Vec::new();
    for (file, target) in args.files.iter().zip(&targets) {
        progress.set_message(file.display().to_string());
        let result = (|| -> Result<(String, sheet::Rgb8Image), String> {
            let graph = load_graph_with(file, &args.variant.variants)?;
            files.graph_inputs(&graph, file)?;
            let graph = super::report::apply_max_error(
                graph,
                file,
                &args.variant.variants,
                args.variant.max_error,
                policy,
            )?;
            // One budget per graph: its output images, then what it loads, then the frame
            // (and the scene's meshes, reserved by the render) in what is left.
            let budget = matgraph::budget::MemoryBudget::new(args.memory_budget);
            budget
                .reserve(|| "the output images".to_owned(), reserve)
                .map_err(|e| e.to_string())?;
            let textures = graph_textures(&graph, file, policy, &budget)?;
            let forced = forced.as_ref().map(|(spec, s)| (*spec, s));
            let (mut scene, environment) =
                super::scene::resolve(&graph, file, forced, policy, &budget)?;
            // The scene's own time-dependent parts (the bubble's motion, its backdrop) follow
            // --time as the material does.
            if let Some(t) = args.time {
                scene.time = t;
            }
            let graph = match args.specialise.as_deref() {
                None => graph,
                Some(mode) => {
                    // Animated frames keep time live; a still fixes it.
                    let time = frames.is_none().then(|| args.time.unwrap_or(scene.time));
                    let s = matgraph::specialise::for_scene(&graph, &scene, time, mode == "approx")
                        .map_err(|e| format!("{}: {e}", file.display()))?;
                    progress.suspend(|| err!("{}", s.listing()));
                    s.graph
                }
            };
            let mut options = RenderOptions {
                width: args.size.0,
                height: args.size.1,
                samples: args.samples,
                time: args.time,
                backend,
                parameters: parameters.clone(),
                textures: Some(std::sync::Arc::new(textures)),
                environment,
                memory_budget: budget.remaining(),
                band_rows: None,
                texture_mode: matgraph::wgsl::TextureMode::from_name(&args.textures)
                    .unwrap_or_default(),
            };
            // One still at --time, or frame k at t0 + k/fps.
            let times: Vec<Option<f32>> = match &frames {
                None => vec![args.time],
                Some(f) => f
                    .times(args.time.unwrap_or(scene.time))
                    .map_err(|e| e.to_string())?
                    .into_iter()
                    .map(Some)
                    .collect(),
            };
            let target = target.clone();
            let mut animation = match (&frames, &target) {
                (Some(f), Some(_)) => {
                    Some(Apng::new(args.size.0, args.size.1, f).map_err(|e| e.to_string())?)
                }
                _ => None,
            };
            let mut first = None;
            for (k, time) in times.into_iter().enumerate() {
                options.time = time;
                if let Some(t) = time {
                    scene.time = t;
                }
                let start = std::time::Instant::now();
                let (hdr, timings) = render_timed(&graph, &scene, &options)
                    .map_err(|e| {
                        e.with_reserve(budget.used(), "output and loaded images", budget.limit())
                    })
                    .map_err(|e| format!("{}: {e}", file.display()))?;
                if k == 0
                    && let Some(why) = &timings.fallback
                {
                    progress.suspend(|| errln!("note: {}: {why}", file.display()));
                }
                if !adapter_said.replace(true)
                    && let Ok(ctx) = matgraph::gpu::GpuContext::shared()
                {
                    let info = ctx.adapter_info();
                    progress
                        .suspend(|| errln!("adapter: {} ({})", info.name, info.backend.to_str()));
                }
                let elapsed = start.elapsed();
                let image = hdr.to_srgb8(args.exposure);
                let still = match (&frames, &target) {
                    (Some(_), Some(t)) => Some(Frames::numbered(t, k as u32)),
                    _ => target.clone(),
                };
                if let Some(out) = &still {
                    let format = SaveFormat::from_path(out).map_err(|e| e.to_string())?;
                    let mut written = Vec::new();
                    if format != SaveFormat::Exr {
                        matgraph::image_io::save_rgb8(
                            out,
                            image.width,
                            image.height,
                            &image.pixels,
                        )
                        .map_err(|e| e.to_string())?;
                        written.push(out.clone());
                    }
                    if args.exr || format == SaveFormat::Exr {
                        let exr = out.with_extension("exr");
                        let data = hdr.pixels.iter().map(|c| [c[0], c[1], c[2], 1.0]).collect();
                        let img = matgraph::texture::Image::new(hdr.width, hdr.height, data)
                            .map_err(|e| e.to_string())?;
                        matgraph::image_io::save_exr(&exr, &img).map_err(|e| e.to_string())?;
                        written.push(exr);
                    }
                    let names: Vec<String> =
                        written.iter().map(|p| p.display().to_string()).collect();
                    let at = time
                        .map(|t| format!(", t = {t} s"))
                        .filter(|_| frames.is_some());
                    progress.suspend(|| {
                        outln!(
                            "{} -> {} ({}x{}, {} spp, {}, {:.2} s{})",
                            file.display(),
                            names.join(" + "),
                            image.width,
                            image.height,
                            args.samples,
                            match (args.gpu, args.gpu_compute, timings.fallback.is_some()) {
                                (true, _, false) => "gpu",
                                (true, _, true) | (_, true, _) => "gpu-compute",
                                _ => "cpu",
                            },
                            elapsed.as_secs_f64(),
                            at.unwrap_or_default()
                        )
                    })?;
                }
                if let Some(a) = &mut animation {
                    a.push(&image).map_err(|e| e.to_string())?;
                }
                if first.is_none() {
                    first = Some(image);
                }
                if frames.is_some() {
                    progress.inc(1);
                }
            }
            if let (Some(a), Some(out), Some(f)) = (animation, &target, &frames) {
                let bytes = a.finish().map_err(|e| e.to_string())?;
                matgraph::io::write_atomic(out, &bytes)
                    .map_err(|e| super::out_dir::write_error(out, &e))?;
                progress.suspend(|| {
                    outln!(
                        "{} -> {} (animated PNG, {}, {} fps)",
                        file.display(),
                        out.display(),
                        count(f.count as usize, "frame"),
                        f.fps
                    )
                })?;
            }
            let image = first.ok_or("no frame rendered")?;
            Ok((graph.name.clone(), image))
        })();
        match result {
            Ok(tile) => tiles.push(tile),
            // Standard output failed (closed, full): stop, with its message only (see `out`).
            Err(e) if super::out::stdout_failed() => {
                progress.finish_and_clear();
                return Err(e);
            }
            Err(e) => {
                progress.suspend(|| errln!("{e}"));
                failures.push(file.display().to_string());
            }
        }
        if frames.is_none() {
            progress.inc(1);
        }
    }
    progress.finish_and_clear();
    if several
        && let Some(path) = &sheet_path
        && !tiles.is_empty()
    {
        let sheet = sheet::contact_sheet(&tiles);
        matgraph::image_io::save_rgb8(path, sheet.width, sheet.height, &sheet.pixels)
            .map_err(|e| e.to_string())?;
        outln!(
            "contact sheet of {} -> {}",
            count(tiles.len(), "graph"),
            path.display()
        )?;
    }
    if failures.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{} of {} failed",
            failures.len(),
            count(args.files.len(), "graph")
        ))
    }
}
