//! `matgraph wgsl`: compile a graph to WGSL or, through naga, another shading language; with
//! `--contract`, write the app contract (docs/integration.md) beside it.

use super::CliResult;
use matgraph::PlanOptions;
use std::path::PathBuf;

/// Options of `matgraph wgsl`.
#[derive(clap::Args)]
pub struct Args {
    /// Graph file.
    pub file: PathBuf,
    /// Output language.
    #[arg(long, default_value = "wgsl", value_parser = ["wgsl", "spirv", "glsl", "msl", "hlsl"])]
    pub target: String,
    /// Entry points: batch evaluation (compute), a per-pixel preview (fragment), the app
    /// contract's vertex and fragment entries (render), or `mg_material` alone for an app's own
    /// shader (library). Default: compute, or render with --contract or a render option
    /// (--sample-shading, --displaced-vertices, --derived-tangents).
    #[arg(long, value_parser = ["compute", "fragment", "render", "library"])]
    pub entry: Option<String>,
    /// How render and library modules bind textures: texture_2d + samplers (hardware) or
    /// storage buffers bit-identical with the CPU (exact).
    #[arg(long, default_value = "hardware", value_parser = ["hardware", "exact"])]
    pub textures: String,
    /// Fold parameters into constants instead of a uniform buffer.
    #[arg(long)]
    pub bake: bool,
    #[command(flatten)]
    pub variant: super::shared::VariantFlags,
    #[command(flatten)]
    pub output: super::shared::OutputFlags,
    /// Output file; standard output when absent (SPIR-V is binary).
    #[arg(short = 'o', long = "out")]
    pub out: Option<PathBuf>,
    /// Also write the module's contract as JSON (schema matgraph-contract/1): for the render
    /// module bindings, vertex layout, parameter block, lights, textures; for the library and
    /// compute modules (with --entry) bindings, geometry and output layout, parameter block,
    /// textures.
    #[arg(long, value_name = "FILE.json")]
    pub contract: Option<PathBuf>,
    /// Read each parameter as the app writes it: no clamp to its hard range (the default
    /// clamps, so a value the CPU would refuse renders as the nearest accepted one).
    #[arg(long)]
    pub no_clamp: bool,
    /// Check the module against a downlevel device's limits (WebGL2, GLES 3.0: wgpu's
    /// downlevel_webgl2_defaults) and refuse, naming each limit it needs beyond them, when
    /// it does not fit (the render module's lights are a storage buffer, which those lack).
    #[arg(long)]
    pub downlevel: bool,
    /// Render module: the varyings are interpolated per sample (`@interpolate(perspective,
    /// sample)`), so under MSAA `mg_fragment` runs once per covered sample
    /// (MaterialOptions::sample_shading; docs/integration.md, "Options for renderers").
    #[arg(long)]
    pub sample_shading: bool,
    /// Render module: the vertex buffer holds displaced positions and their normals already,
    /// and `mg_vertex` transforms them without displacing (MaterialOptions::displaced_vertices).
    #[arg(long)]
    pub displaced_vertices: bool,
    /// Render module: the app binds no tangent buffer; a graph that reads the tangent frame
    /// gets it from screen-space derivatives in `mg_fragment` (MaterialOptions::derived_tangents).
    #[arg(long)]
    pub derived_tangents: bool,
    /// Compile against the graph's own scene at its time (docs/specialise.md) and print the
    /// rewrites on standard error: `exact` folds what the scene fixes; `approx` also applies
    /// the threshold rewrites.
    #[arg(long, value_name = "MODE", num_args = 0..=1, default_missing_value = "exact",
          value_parser = ["exact", "approx"])]
    pub specialise: Option<String>,
    /// Memory the command may use for the images it loads to bind (bytes, or with a unit:
    /// 512MiB, 4GiB); each is refused before it is allocated when it does not fit.
    #[arg(long, value_name = "SIZE", default_value = "2GiB", value_parser = super::flags::memory_budget)]
    pub memory_budget: u64,
}

/// `graph` (loaded from `file`), specialised for its own scene when `mode` is set.
pub fn specialised(
    graph: matgraph::Graph,
    file: &std::path::Path,
    mode: Option<&str>,
) -> Result<matgraph::Graph, String> {
    let Some(mode) = mode else {
        return Ok(graph);
    };
    let budget = matgraph::budget::MemoryBudget::default();
    let (scene, _) = super::scene::resolve(&graph, file, None, super::path_policy(false), &budget)?;
    let s = matgraph::specialise::for_scene(&graph, &scene, Some(scene.time), mode == "approx")
        .map_err(|e| format!("{}: {e}", file.display()))?;
    err!("{}", s.listing());
    Ok(s.graph)
}

/// The parameter clamp `--no-clamp` asks for.
fn clamp_option(no_clamp: bool) -> matgraph::wgsl::ParameterClamp {
    if no_clamp {
        matgraph::wgsl::ParameterClamp::None
    } else {
        matgraph::wgsl::ParameterClamp::HardRange
    }
}

/// With `--downlevel`: an error naming every WebGL2/GLES 3.0 limit `module` needs more of.
fn downlevel(check: bool, module: &matgraph::wgsl::ShaderModule) -> Result<(), String> {
    if !check {
        return Ok(());
    }
    let limits = wgpu::Limits::downlevel_webgl2_defaults();
    let mut unmet = matgraph::material::ModuleLimits::of(module).unmet(&limits);
    if module.entry == matgraph::wgsl::Entry::Compute {
        unmet.insert(0, "WebGL2 and GLES 3.0 run no compute shaders".into());
    }
    if unmet.is_empty() {
        return Ok(());
    }
    Err(format!(
        "the {} module does not fit a downlevel device (WebGL2, GLES 3.0; wgpu's downlevel_webgl2_defaults):\n  - {}\nmatgraph emits no downlevel variant: bind it on a WebGPU, Vulkan, Metal or DX12 device (its contract's `limits` says what it needs){}",
        module.entry.name(),
        unmet.join("\n  - "),
        if matches!(module.entry, matgraph::wgsl::Entry::Render(_)) {
            ", or call the library module (--entry library --downlevel) from a shader of your own that passes lights as uniforms"
        } else {
            ""
        }
    ))
}

/// Compiles the graph and prints or writes the shader (and the contract).
pub fn run(args: &Args) -> CliResult {
    use matgraph::material::{Material, MaterialOptions};
    use matgraph::wgsl::{Entry, Target, TextureMode, WgslOptions, generate};
    let file = args.file.as_path();
    let at = |e: &dyn std::fmt::Display| format!("{}: {e}", file.display());
    let textures = TextureMode::from_name(&args.textures).unwrap_or_default();
    // The renderer options of the render module (docs/integration.md, "Options for renderers").
    let render_flags: Vec<&str> = [
        (args.sample_shading, "--sample-shading"),
        (args.displaced_vertices, "--displaced-vertices"),
        (args.derived_tangents, "--derived-tangents"),
    ]
    .into_iter()
    .filter_map(|(on, flag)| on.then_some(flag))
    .collect();
    let entry = match args.entry.as_deref() {
        None if args.contract.is_some() || !render_flags.is_empty() => Entry::Render(textures),
        None | Some("compute") => Entry::Compute,
        Some("fragment") => Entry::Fragment,
        Some("library") => Entry::Library(textures),
        Some(_) => Entry::Render(textures),
    };
    let target = Target::from_name(&args.target)
        .ok_or_else(|| format!("unknown target '{}'", args.target))?;
    // Nothing is written over the graph, the files it names, or the other output.
    let mut files = super::outputs::Files::default();
    files.input(file, format!("the input graph {}", file.display()))?;
    if let Some(p) = &args.out {
        files.output(p, "-o output")?;
    }
    if let Some(p) = &args.contract {
        files.output(p, "--contract output")?;
    }
    if !render_flags.is_empty() && !matches!(entry, Entry::Render(_)) {
        return Err(at(&format!(
            "{} edit the render module's vertex and fragment entries: use --entry render (the {} module has none)",
            render_flags.join(", "),
            entry.name()
        )));
    }
    let bytes = if let Entry::Render(_) = entry {
        if args.bake || !args.output.outputs.is_empty() {
            return Err(at(
                &"--entry render takes the outputs by role (color, emission, alpha, displacement) with parameters as uniforms: drop --bake and --output",
            ));
        }
        let options = MaterialOptions {
            textures,
            sample_shading: args.sample_shading,
            displaced_vertices: args.displaced_vertices,
            derived_tangents: args.derived_tangents,
            clamp: clamp_option(args.no_clamp),
            ..MaterialOptions::default()
        };
        let graph = super::load_graph_with(file, &args.variant.variants)?;
        let graph = super::report::apply_max_error(
            graph,
            file,
            &args.variant.variants,
            args.variant.max_error,
            super::path_policy(false),
        )?;
        files.graph_inputs(&graph, file)?;
        let graph = specialised(graph, file, args.specialise.as_deref())?;
        let budget = matgraph::budget::MemoryBudget::new(args.memory_budget);
        let textures = matgraph::image_io::load_graph_textures_within(
            &graph,
            file,
            super::path_policy(false),
            &budget,
        )
        .map_err(|e| match e {
            matgraph::image_io::GraphTextureError::Texture { source, .. } => source.to_string(),
            e => format!("{}: {e}", file.display()),
        })?;
        let mut material = Material::new(&graph, &options).map_err(|e| at(&e))?;
        material.bind_textures(&textures);
        if let Some(path) = &args.contract {
            matgraph::io::write_atomic(path, material.contract().to_json().as_bytes())
                .map_err(|e| super::out_dir::write_error(path, &e))?;
        }
        downlevel(args.downlevel, material.render_module()).map_err(|e| at(&e))?;
        material
            .render_module()
            .translate(target)
            .map_err(|e| at(&e))?
    } else {
        if args.contract.is_some() && entry == Entry::Fragment {
            return Err(at(
                &"--contract describes a module an app binds: use it with --entry render, library or compute (the fragment entry is the editor's preview)",
            ));
        }
        let graph = super::load_graph_with(file, &args.variant.variants)?;
        let graph = super::report::apply_max_error(
            graph,
            file,
            &args.variant.variants,
            args.variant.max_error,
            super::path_policy(false),
        )?;
        files.graph_inputs(&graph, file)?;
        let graph = specialised(graph, file, args.specialise.as_deref())?;
        let options = WgslOptions {
            plan: PlanOptions {
                outputs: args.output.outputs.clone(),
                bake_parameters: args.bake,
            },
            entry,
            clamp: clamp_option(args.no_clamp),
        };
        let shader = generate(&graph, &options).map_err(|e| at(&e))?;
        downlevel(args.downlevel, &shader).map_err(|e| at(&e))?;
        if let Some(path) = &args.contract {
            let contract = matgraph::material::ModuleContract::new(&graph, &shader, options.clamp);
            matgraph::io::write_atomic(path, contract.to_json().as_bytes())
                .map_err(|e| super::out_dir::write_error(path, &e))?;
        }
        shader.translate(target).map_err(|e| at(&e))?
    };
    match args.out.as_deref() {
        Some(p) => {
            matgraph::io::write_atomic(p, &bytes).map_err(|e| super::out_dir::write_error(p, &e))
        }
        None => super::out::stdout_bytes(&bytes),
    }
}
