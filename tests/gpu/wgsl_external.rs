//! The Khronos validators on naga's output for every bundled graph: `spirv-val` on SPIR-V and
//! `glslangValidator` on GLSL (Debian packages spirv-tools, glslang-tools), and insta snapshots
//! of the generated WGSL. With `MATGRAPH_REQUIRE_TOOLS` set (CI sets it) a missing validator
//! fails; elsewhere the test says loudly that it skipped.

use crate::common;
use common::{bundled_graphs, tool_or_skip};

use matgraph::Registry;
use matgraph::wgsl::{Entry, Target, WgslOptions, generate};
use std::path::Path;
use std::process::Command;

/// Whether `tool` runs; otherwise the calling test prints `SKIPPED ...` (visible without
/// `--nocapture`), or fails when `MATGRAPH_REQUIRE_TOOLS` is set.
fn have(test: &str, tool: &str) -> bool {
    let ok = Command::new(tool)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    let found = if ok {
        Ok(())
    } else {
        Err(format!(
            "{tool} not found (apt-get install spirv-tools glslang-tools)"
        ))
    };
    tool_or_skip(test, found).is_some()
}

fn validate_with(tool: &str, args: &[&str], file: &Path) {
    let out = Command::new(tool).args(args).arg(file).output().unwrap();
    assert!(
        out.status.success(),
        "{tool} rejected {}:\n{}{}",
        file.display(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn spirv_val_accepts_every_bundled_graph() {
    if !have("spirv_val_accepts_every_bundled_graph", "spirv-val") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for path in bundled_graphs() {
        let graph = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        for entry in [Entry::Compute, Entry::Fragment] {
            let m = generate(
                &graph,
                &WgslOptions {
                    entry,
                    ..Default::default()
                },
            )
            .unwrap();
            let file = dir.path().join(format!("{}.{entry:?}.spv", graph.name));
            std::fs::write(&file, m.translate(Target::SpirV).unwrap()).unwrap();
            validate_with("spirv-val", &[], &file);
        }
    }
}

#[test]
fn glslang_accepts_every_bundled_graph() {
    if !have("glslang_accepts_every_bundled_graph", "glslangValidator") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for path in bundled_graphs() {
        let graph = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        for (entry, ext) in [(Entry::Compute, "comp"), (Entry::Fragment, "frag")] {
            let m = generate(
                &graph,
                &WgslOptions {
                    entry,
                    ..Default::default()
                },
            )
            .unwrap();
            let file = dir.path().join(format!("{}.{ext}", graph.name));
            std::fs::write(&file, m.translate(Target::Glsl).unwrap()).unwrap();
            validate_with("glslangValidator", &[], &file);
        }
    }
}

#[test]
fn wgsl_snapshots_of_bundled_graphs() {
    for path in bundled_graphs() {
        let graph = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        for entry in [Entry::Compute, Entry::Fragment] {
            let m = generate(
                &graph,
                &WgslOptions {
                    entry,
                    ..Default::default()
                },
            )
            .unwrap();
            let name = format!("{}_{}", graph.name, entry.function());
            insta::assert_snapshot!(name, m.source);
        }
    }
}
