//! Issue 37 item 4: one memory budget for everything a command loads or builds. Each
//! hostile input of the issue (a small PNG declaring 16384², scenes the validator accepts
//! whose meshes take gigabytes) exits with a clear error naming the input, its size and the
//! budget, quickly, and never aborts under a 4 GiB address-space limit (`ulimit -v`), where
//! each of them used to abort (SIGABRT) after 10–97 s.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

/// The address-space limit of the issue: 4 GiB, in KiB for `ulimit -v`.
const ULIMIT_KIB: u64 = 4 << 20;

/// Longest a refusal may take (a debug build on a loaded 2-core machine; each takes well
/// under a second here).
const QUICK: Duration = Duration::from_secs(20);

/// Runs matgraph with `args` in `dir` under `ulimit -v` [`ULIMIT_KIB`], and how long it took.
fn run_limited(dir: &Path, args: &[&str]) -> (Output, Duration) {
    let start = Instant::now();
    let out = Command::new("bash")
        .arg("-c")
        .arg(format!("ulimit -v {ULIMIT_KIB}; exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_matgraph"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("bash runs");
    (out, start.elapsed())
}

/// Runs `args` under the limit: exit status 1 (never a signal: an abort is 134 from bash's
/// exec, a signal in the status), within [`QUICK`], stderr holding every fragment of
/// `expect`. Returns stderr.
fn refused(dir: &Path, args: &[&str], expect: &[&str]) -> String {
    let (out, took) = run_limited(dir, args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(
        out.status.code(),
        Some(1),
        "matgraph {args:?}: status {:?} after {took:?}\n{stderr}",
        out.status
    );
    assert!(took < QUICK, "matgraph {args:?} took {took:?}\n{stderr}");
    for fragment in expect {
        assert!(
            stderr.contains(fragment),
            "matgraph {args:?}: stderr lacks {fragment:?}:\n{stderr}"
        );
    }
    stderr
}

/// CRC-32 (ISO 3309, as PNG uses), bit by bit.
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= b as u32;
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// Deflate's bit order: values least significant bit first, Huffman codes most
/// significant bit first.
#[derive(Default)]
struct Bits {
    out: Vec<u8>,
    used: u32,
}

impl Bits {
    fn bit(&mut self, b: u32) {
        if self.used % 8 == 0 {
            self.out.push(0);
        }
        *self.out.last_mut().unwrap() |= ((b & 1) as u8) << (self.used % 8);
        self.used += 1;
    }
    fn value(&mut self, v: u32, n: u32) {
        (0..n).for_each(|i| self.bit(v >> i));
    }
    fn code(&mut self, c: u32, n: u32) {
        (0..n).rev().for_each(|i| self.bit(c >> i));
    }
}

/// A valid 8-bit greyscale PNG of `side`² black texels, small on disk: its zlib stream is
/// one fixed-Huffman block of a literal 0 and then matches of 258 bytes at distance 1
/// (13 bits per 258 zero bytes: 1.7 MB for 16384²).
fn black_png(side: u32) -> Vec<u8> {
    let n = (side as u64 + 1) * side as u64; // every row's filter byte 0, then its texels
    let mut bits = Bits::default();
    bits.value(1, 1); // final block
    bits.value(1, 2); // fixed Huffman codes
    bits.code(0x30, 8); // literal 0
    let mut left = n - 1;
    while left >= 258 {
        bits.code(0xC5, 8); // length 258 (symbol 285)
        bits.code(0, 5); // distance 1
        left -= 258;
    }
    for _ in 0..left {
        bits.code(0x30, 8);
    }
    bits.code(0, 7); // end of block
    let mut zlib = vec![0x78, 0x01];
    zlib.extend(bits.out);
    let adler = ((n % 65521) as u32) << 16 | 1;
    zlib.extend(adler.to_be_bytes());
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut chunk = |kind: &[u8], data: &[u8]| {
        png.extend((data.len() as u32).to_be_bytes());
        let mut body = kind.to_vec();
        body.extend(data);
        png.extend(&body);
        png.extend(crc32(&body).to_be_bytes());
    };
    let mut ihdr = side.to_be_bytes().to_vec();
    ihdr.extend(side.to_be_bytes());
    ihdr.extend([8, 0, 0, 0, 0]); // 8-bit greyscale, deflate, no filter method, progressive
    chunk(b"IHDR", &ihdr);
    chunk(b"IDAT", &zlib);
    chunk(b"IEND", &[]);
    png
}

/// A graph in `dir` (`g.json`) whose color is a texture of `texture`, with `scene`.
fn graph(dir: &Path, texture: Option<&str>, scene: &str) -> PathBuf {
    let (nodes, color) = match texture {
        Some(t) => (
            format!(
                r#"{{ "id": "tex", "type": "image_texture", "texture": "{t}", "inputs": {{ "uv": {{ "link": "geo.uv" }} }} }},"#
            ),
            "tex.color",
        ),
        None => (String::new(), "geo.normal"),
    };
    let path = dir.join("g.json");
    std::fs::write(
        &path,
        format!(
            r#"{{ "version": 1, "name": "t", "nodes": [ {nodes} {{ "id": "geo", "type": "geometry" }} ],
  "outputs": [{{ "name": "color", "from": "{color}" }}], "scene": {scene} }}"#
        ),
    )
    .unwrap();
    path
}

#[test]
fn the_png_generator_makes_a_valid_image() {
    // The generator is checked against the PNG decoder on a small side, every texel 0.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("b.png");
    std::fs::write(&path, black_png(300)).unwrap();
    let image = matgraph::image_io::load_image(&path).unwrap();
    assert_eq!((image.width, image.height), (300, 300));
    assert!(image.data.iter().all(|t| *t == [0.0, 0.0, 0.0, 1.0]));
}

#[test]
fn a_small_png_declaring_16384_squared_is_refused_before_decoding() {
    let dir = tempfile::tempdir().unwrap();
    let png = black_png(16384);
    assert!(png.len() < 2 << 20, "{} bytes", png.len());
    std::fs::write(dir.path().join("huge.png"), &png).unwrap();
    graph(dir.path(), Some("huge.png"), r#""ball""#);
    // 16384² greyscale: the decoder's 256 MiB and two RGBA f32 copies of 4 GiB each.
    let expect = [
        "g.json: node 'tex': ",
        "/huge.png: a 16384×16384 image needs 8.2 GiB, over the memory budget of 2.0 GiB",
        "--memory-budget",
    ];
    refused(dir.path(), &["eval", "g.json", "--json"], &expect);
    refused(
        dir.path(),
        &["render", "g.json", "--size", "8x8", "-o", "o.png"],
        &expect,
    );
    refused(
        dir.path(),
        &["wgsl", "g.json", "-o", "o.wgsl", "--entry", "render"],
        &expect[1..],
    );
}

#[test]
fn scenes_whose_meshes_take_gigabytes_are_refused_before_building() {
    let dir = tempfile::tempdir().unwrap();
    for (kind, expect) in [
        (
            r#"{"ball": {"segments": [4096, 4096]}}"#,
            "kind.ball.segments [4096, 4096]: a UV sphere of 16785409 vertices needs 7.0 GiB, over the memory budget of 2.0 GiB",
        ),
        (
            r#"{"bubble": {"segments": [4096, 4096]}}"#,
            "kind.bubble.segments [4096, 4096]: a UV sphere of 16785409 vertices needs 7.0 GiB",
        ),
        (
            r#"{"water": {"grid": [4096, 4096]}}"#,
            "kind.water.grid [4096, 4096]: a grid of 16785409 vertices needs 7.0 GiB",
        ),
        (
            r#"{"water": {"seabed": {"grid": [4096, 4096]}}}"#,
            "kind.water.seabed.grid [4096, 4096]: a grid of 16785409 vertices needs 7.0 GiB",
        ),
        (
            r#"{"water": {"lod": {"levels": 10, "block": 8, "split_distance": 1e30}}}"#,
            "kind.water.lod {levels: 10, block: 8, split_distance: 1e30}: a grid of 1048576 blocks, 118489088 vertices needs 58.2 GiB",
        ),
    ] {
        graph(dir.path(), None, &format!(r#"{{"kind": {kind}}}"#));
        let args = ["render", "g.json", "--size", "8x8", "-o", "o.png"];
        refused(dir.path(), &args, &["g.json: ", expect, "--memory-budget"]);
        refused(
            dir.path(),
            &["render", "g.json", "--gpu", "--size", "8x8", "-o", "o.png"],
            &[expect],
        );
    }
    // eval binds the scene textures of a graph that samples them: the same refusal.
    std::fs::write(dir.path().join("g.json"), r#"{ "version": 1, "name": "t", "nodes": [
        { "id": "geo", "type": "geometry" },
        { "id": "tex", "type": "image_texture", "texture": "scene:background", "inputs": { "uv": { "link": "geo.uv" } } } ],
      "outputs": [{ "name": "color", "from": "tex.color" }],
      "scene": {"kind": {"ball": {"segments": [4096, 4096]}}} }"#).unwrap();
    refused(
        dir.path(),
        &["eval", "g.json", "--json"],
        &["kind.ball.segments [4096, 4096]"],
    );
}

#[test]
fn the_budget_is_one_and_the_flag_sets_it() {
    let dir = tempfile::tempdir().unwrap();
    // A 2048² image: 2048² · (1 + 32) bytes at its peak (132 MiB), then 16 bytes a texel and
    // a third more for its mips (85.3 MiB kept).
    std::fs::write(dir.path().join("big.png"), black_png(2048)).unwrap();
    graph(dir.path(), Some("big.png"), r#""ball""#);
    let eval = |budget: &str| {
        run_limited(
            dir.path(),
            &["eval", "g.json", "--json", "--memory-budget", budget],
        )
    };
    let (ok, _) = eval("2GiB");
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    refused(
        dir.path(),
        &["eval", "g.json", "--json", "--memory-budget", "100MiB"],
        &["big.png: a 2048×2048 image needs 132.0 MiB, over the memory budget of 100.0 MiB"],
    );
    // The image and its mips fit 200 MiB. A render holds its output images (6 bytes a
    // pixel: 24 MiB at 2048²), the image (85.3 MiB with mips, after a 132 MiB peak), the
    // scene's meshes (30.1 MiB) and its frame (48 MiB at 2048²) in one budget: 180 MiB fits
    // each load but not the frame, which is refused naming all of it.
    let (ok, _) = eval("200MiB");
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    let stderr = refused(
        dir.path(),
        &[
            "render",
            "g.json",
            "--size",
            "2048x2048",
            "--memory-budget",
            "180MiB",
            "-o",
            "o.png",
        ],
        &[
            "2048x2048 at 1 spp needs at least 188 MiB (48 MiB image, 1 MiB per row of samples, 31 MiB scene meshes, 110 MiB output and loaded images), over the memory budget of 180 MiB",
        ],
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    // Bad values are refused by the flag's parser (exit 2).
    for bad in ["0", "1MiB", "2XB", "NaN", "2TiB", "1e999"] {
        let (out, _) = eval(bad);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{bad}: {stderr}");
        assert!(stderr.contains("--memory-budget"), "{bad}: {stderr}");
    }
}

#[test]
fn report_samples_stay_bounded_under_the_limit() {
    let (out, took) = run_limited(
        Path::new(env!("CARGO_MANIFEST_DIR")),
        &["report", "--samples", "4294967295"],
    );
    assert_eq!(
        out.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(took < QUICK);
}
