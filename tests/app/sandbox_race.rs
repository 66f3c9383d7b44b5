//! Issue 37 item 1: the folder sandbox cannot be raced. A thread swaps a symlink inside the
//! graph's folder between an inside file and an outside one while the loader reads it; a
//! read must never return the outside file's contents (the loader opens once and checks the
//! file it opened, then reads that handle). Each read is either the inside file or a
//! refusal naming the path as outside.

use matgraph::io::{PathError, PathPolicy};
use matgraph::texture::Image;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Trials per surface.
const TRIALS: usize = 10_000;

/// The swapped link as referenced: `s/../` 400 times, then `link.EXT`. The long prefix makes
/// each resolution of the path take a while (800 components), which widens the window
/// between a check of the path and a later open of it: with the old check-then-open, about
/// one read in five returned the outside file; without the prefix, often none in 10,000.
fn reference(ext: &str) -> String {
    format!("{}link.{ext}", "s/../".repeat(400))
}

/// `root/graph/` holding the graph, `inside.*` and the swapped link `link.*`, and
/// `root/outside/secret.*`.
struct Fixture {
    _root: tempfile::TempDir,
    graph_dir: PathBuf,
    graph: PathBuf,
}

/// Colours of the inside and outside images (exact in 8-bit sRGB: 0 and 1).
const INSIDE: [f32; 4] = [0.0, 1.0, 0.0, 1.0];
const OUTSIDE: [f32; 4] = [1.0, 0.0, 0.0, 1.0];

fn fixture() -> Fixture {
    let root = tempfile::tempdir().unwrap();
    let graph_dir = root.path().join("graph");
    let outside = root.path().join("outside");
    std::fs::create_dir_all(graph_dir.join("s")).unwrap();
    std::fs::create_dir_all(&outside).unwrap();
    let save = |p: &Path, c: [f32; 4]| {
        matgraph::image_io::save_png(p, &Image::new(1, 1, vec![c]).unwrap()).unwrap()
    };
    save(&graph_dir.join("inside.png"), INSIDE);
    save(&outside.join("secret.png"), OUTSIDE);
    std::fs::write(graph_dir.join("inside.json"), "inside").unwrap();
    std::fs::write(outside.join("secret.json"), "SECRET").unwrap();
    std::os::unix::fs::symlink("inside.png", graph_dir.join("link.png")).unwrap();
    std::os::unix::fs::symlink("inside.json", graph_dir.join("link.json")).unwrap();
    let graph = graph_dir.join("g.json");
    std::fs::write(
        &graph,
        r#"{ "version": 1, "name": "t", "nodes": [
          { "id": "geo", "type": "geometry" },
          { "id": "tex", "type": "image_texture", "texture": "REFERENCE", "inputs": { "uv": { "link": "geo.uv" } } } ],
          "outputs": [{ "name": "c", "from": "tex.color" }] }"#
            .replace("REFERENCE", &reference("png")),
    )
    .unwrap();
    Fixture {
        _root: root,
        graph_dir,
        graph,
    }
}

/// Swaps `dir/link.EXT` between `inside.EXT` and `../outside/secret.EXT` until `stop`: the
/// link and a second link `other.EXT` to the other target are exchanged atomically
/// (`renameat2(RENAME_EXCHANGE)`, one system call per swap, so the link always exists and
/// swaps come as fast as the kernel allows).
fn swapper(dir: PathBuf, ext: &'static str, stop: Arc<AtomicBool>) -> std::thread::JoinHandle<u64> {
    std::thread::spawn(move || {
        use std::os::unix::ffi::OsStrExt;
        let other = dir.join(format!("other.{ext}"));
        std::os::unix::fs::symlink(format!("../outside/secret.{ext}"), &other).unwrap();
        let c = |p: PathBuf| std::ffi::CString::new(p.as_os_str().as_bytes()).unwrap();
        let (a, b) = (c(dir.join(format!("link.{ext}"))), c(other));
        let mut swaps = 0u64;
        while !stop.load(Ordering::Relaxed) {
            // SAFETY: two valid NUL-terminated paths; the call only renames.
            let r = unsafe {
                libc::renameat2(
                    libc::AT_FDCWD,
                    a.as_ptr(),
                    libc::AT_FDCWD,
                    b.as_ptr(),
                    libc::RENAME_EXCHANGE,
                )
            };
            assert_eq!(r, 0, "renameat2: {}", std::io::Error::last_os_error());
            swaps += 1;
        }
        swaps
    })
}

/// Tallies of a race: reads of the inside file, and refusals as outside.
#[derive(Debug, Default)]
struct Tally {
    inside: usize,
    refused: usize,
}

/// Runs `trial` [`TRIALS`] times while `link.EXT` is swapped; `trial` returns whether it
/// read the inside file (`Ok(true)`), was refused as outside (`Ok(false)`), or read the
/// outside file (`Err`, with what it read).
fn race(fx: &Fixture, ext: &'static str, mut trial: impl FnMut() -> Result<bool, String>) -> Tally {
    let stop = Arc::new(AtomicBool::new(false));
    let swaps = swapper(fx.graph_dir.clone(), ext, stop.clone());
    let mut tally = Tally::default();
    let mut escapes = Vec::new();
    for _ in 0..TRIALS {
        match trial() {
            Ok(true) => tally.inside += 1,
            Ok(false) => tally.refused += 1,
            Err(what) => escapes.push(what),
        }
    }
    stop.store(true, Ordering::Relaxed);
    let swaps = swaps.join().unwrap();
    eprintln!("{ext}: {tally:?}, {swaps} swaps, {} escapes", escapes.len());
    assert!(
        escapes.is_empty(),
        "{} of {TRIALS} reads returned the outside file while the link was swapped; first: {}",
        escapes.len(),
        escapes[0]
    );
    // The race was run: the link was swapped throughout, and both outcomes were seen.
    assert!(swaps > 100, "only {swaps} swaps");
    assert!(tally.inside > 0 && tally.refused > 0, "{tally:?}");
    tally
}

#[test]
fn a_swapped_texture_link_never_reads_outside() {
    let fx = fixture();
    let graph = matgraph::io::load_graph(&fx.graph, matgraph::Registry::builtin()).unwrap();
    race(
        &fx,
        "png",
        || match matgraph::image_io::load_graph_textures_with(
            &graph,
            &fx.graph,
            PathPolicy::InsideGraphFolder,
        ) {
            Ok(set) => {
                let texel = set.get(0).unwrap().levels()[0].texel(0, 0);
                match texel {
                    t if t == INSIDE => Ok(true),
                    t => Err(format!("texel {t:?}")),
                }
            }
            Err(matgraph::image_io::GraphTextureError::Path(PathError::Outside { .. })) => {
                Ok(false)
            }
            Err(e) => panic!("unexpected error: {e}"),
        },
    );
}

#[test]
fn a_swapped_scene_file_link_never_reads_outside() {
    // Scene files, environment images and group files are opened by the same function.
    let fx = fixture();
    race(&fx, "json", || {
        match matgraph::io::open_reference(
            &fx.graph,
            "scene",
            &reference("json"),
            PathPolicy::InsideGraphFolder,
        ) {
            Ok(opened) => {
                let text = matgraph::io::read_opened_text(&opened.path, &opened.file).unwrap();
                match text.as_str() {
                    "inside" => Ok(true),
                    t => Err(format!("text {t:?}")),
                }
            }
            Err(PathError::Outside { .. }) => Ok(false),
            Err(e) => panic!("unexpected error: {e}"),
        }
    });
}

#[test]
fn static_escapes_are_still_refused_and_inside_links_read() {
    let fx = fixture();
    let open = |r: &str| {
        matgraph::io::open_reference(&fx.graph, "node 't'", r, PathPolicy::InsideGraphFolder)
    };
    std::os::unix::fs::symlink("../outside/secret.png", fx.graph_dir.join("escape.png")).unwrap();
    std::os::unix::fs::symlink("inside.png", fx.graph_dir.join("alias.png")).unwrap();
    std::os::unix::fs::symlink("alias.png", fx.graph_dir.join("alias2.png")).unwrap();
    std::fs::create_dir(fx.graph_dir.join("sub")).unwrap();
    let secret = fx.graph_dir.join("../outside/secret.png");
    let absolute = std::fs::canonicalize(&secret).unwrap();
    for escape in [
        "../outside/secret.png",
        "sub/../../outside/secret.png",
        absolute.to_str().unwrap(),
        "escape.png",
        "../outside/missing.png",
    ] {
        match open(escape) {
            Err(PathError::Outside { resolved, .. }) => {
                let outside = absolute.parent().unwrap();
                assert!(
                    resolved.starts_with(outside),
                    "{escape}: {}",
                    resolved.display()
                )
            }
            other => panic!("{escape}: {other:?}"),
        }
    }
    for inside in ["inside.png", "alias.png", "alias2.png", "sub/../inside.png"] {
        let opened = open(inside).unwrap_or_else(|e| panic!("{inside}: {e}"));
        let image = matgraph::image_io::load_opened_image(
            &opened.path,
            opened.file,
            None,
            &matgraph::budget::MemoryBudget::default(),
        )
        .unwrap();
        assert_eq!(image.data, vec![INSIDE], "{inside}");
    }
    // A folder and a FIFO are refused as what they are, and the FIFO's open does not block.
    let e = open("sub").unwrap_err().to_string();
    assert!(e.ends_with("is a directory"), "{e}");
    let fifo = fx.graph_dir.join("pipe.png");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if made.is_ok_and(|s| s.success()) {
        let e = open("pipe.png").unwrap_err().to_string();
        assert!(e.ends_with("not a regular file (a FIFO)"), "{e}");
    }
    // Anywhere: the same escapes are read.
    let any = matgraph::io::open_reference(&fx.graph, "x", "escape.png", PathPolicy::Anywhere);
    assert!(any.is_ok());
}
