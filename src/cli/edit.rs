//! `matgraph edit`: the node editor on a graph file, in a window or, with `--screenshot`,
//! rendered headless to a PNG.

use super::CliResult;
use std::path::PathBuf;

/// Options of `matgraph edit`.
#[derive(clap::Args)]
pub struct Args {
    /// Graph file (JSON); created on the first save when it does not exist.
    pub file: Option<PathBuf>,
    /// Render the editor with the graph to this PNG without opening a window.
    #[arg(long, value_name = "OUT.png")]
    pub screenshot: Option<PathBuf>,
    /// Size of the screenshot in pixels.
    #[arg(long, default_value = "1400x900", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Show the generated-code panel (WGSL) in the screenshot, the code of this node highlighted.
    #[arg(long, value_name = "NODE")]
    pub code: Option<String>,
    /// Arrange the file's nodes (layered by link depth, left to right, as View → Arrange)
    /// and write it back in canonical form, without opening a window.
    #[arg(long, conflicts_with = "screenshot")]
    pub arrange: bool,
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or("expected WxH, for example 1400x900")?;
    let parse = |v: &str| v.trim().parse::<u32>().map_err(|e| format!("'{v}': {e}"));
    let (w, h) = (parse(w)?, parse(h)?);
    if !(64..=8192).contains(&w) || !(64..=8192).contains(&h) {
        return Err(format!("{w}x{h}: each side must be 64 to 8192"));
    }
    Ok((w, h))
}

/// Opens the editor window, or writes the screenshot.
pub fn run(args: &Args) -> CliResult {
    use matgraph::editor;
    if args.arrange {
        let file = args
            .file
            .as_ref()
            .ok_or("matgraph edit --arrange: give the graph file")?;
        let registry = matgraph::Registry::builtin();
        let files = editor::model::EditorDoc::files_of(file);
        let doc =
            editor::model::EditorDoc::with_files(editor::files::open(file)?, registry, Some(files));
        let arranged = editor::layout::arranged(doc.doc(), doc.node_sizes());
        let group_files =
            matgraph::io::group_files(file, matgraph::io::PathPolicy::InsideGraphFolder);
        let graph = matgraph::Graph::from_document_in(&arranged, registry, group_files).map_err(
            |errors| {
                matgraph::error::GraphErrors {
                    source: file.clone(),
                    errors,
                }
                .to_string()
            },
        )?;
        editor::files::save(file, &graph.to_json())?;
        outln!(
            "{}: arranged {} nodes",
            file.display(),
            doc.doc().nodes.len()
        )?;
        return Ok(());
    }
    let Some(out) = &args.screenshot else {
        return editor::run_window(args.file.as_deref()).map_err(|e| e.to_string());
    };
    let mut files = super::outputs::Files::default();
    if let Some(file) = &args.file {
        files.input(file, format!("the graph {}", file.display()))?;
    }
    files.output(out, "--screenshot output")?;
    let mut state = editor::state_for(args.file.as_deref()).map_err(|e| e.to_string())?;
    // A screenshot shows the file as it is: no recovery prompt.
    state.dialog = None;
    if let Some(node) = &args.code {
        state.code.open = true;
        state.focus = Some(node.clone());
    }
    let app = editor::EditorApp::new(state);
    let (w, h, rgba) = editor::headless::screenshot(app, [args.size.0, args.size.1])
        .map_err(|e| format!("matgraph edit --screenshot: {e}"))?;
    let rgb: Vec<[u8; 3]> = rgba.chunks_exact(4).map(|p| [p[0], p[1], p[2]]).collect();
    matgraph::image_io::save_rgb8(out, w, h, &rgb).map_err(|e| e.to_string())?;
    outln!(
        "{} -> {} ({w}x{h})",
        args.file
            .as_ref()
            .map_or("untitled".into(), |f| f.display().to_string()),
        out.display()
    )?;
    Ok(())
}
