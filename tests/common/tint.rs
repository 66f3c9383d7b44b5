//! Tint, the WGSL compiler of Chrome and Dawn, run through `tests/tint/check.mjs` (node and
//! the npm package `webgpu`, Dawn's node bindings: `npm ci --prefix tests/tint`).

use std::path::{Path, PathBuf};
use std::process::Command;

/// How to install what the checker needs.
pub const INSTALL: &str = "apt-get install nodejs npm && npm ci --prefix tests/tint";

/// One diagnostic from Tint or from Dawn's pipeline checks.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    /// The file it is about.
    pub file: PathBuf,
    /// 1-based line and column (0 for a whole-pipeline message).
    pub line: u32,
    /// 1-based column.
    pub column: u32,
    /// `error` or `warning`.
    pub severity: String,
    /// Tint's or Dawn's message.
    pub message: String,
}

impl std::fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}:{}:{}: {}: {}",
            self.file.display(),
            self.line,
            self.column,
            self.severity,
            self.message
        )
    }
}

/// The checker: a node binary and the script.
pub struct Tint {
    node: PathBuf,
    script: PathBuf,
}

impl Tint {
    /// The checker, or why it cannot run here (no node, or `tests/tint/node_modules` not
    /// installed).
    pub fn find() -> Result<Tint, String> {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/tint");
        let node = PathBuf::from(std::env::var_os("MATGRAPH_NODE").unwrap_or("node".into()));
        let version = Command::new(&node).arg("--version").output();
        if !version.is_ok_and(|o| o.status.success()) {
            return Err(format!("Tint: `{}` not found ({INSTALL})", node.display()));
        }
        let package = dir.join("node_modules/webgpu/package.json");
        if !package.is_file() {
            return Err(format!(
                "Tint: {} is missing ({INSTALL})",
                package.display()
            ));
        }
        Ok(Tint {
            node,
            script: dir.join("check.mjs"),
        })
    }

    /// Compiles `files` with Tint; every error and warning, or why the checker did not run.
    pub fn check(&self, files: &[PathBuf]) -> Result<Vec<Diagnostic>, String> {
        let out = Command::new(&self.node)
            .arg(&self.script)
            .args(files)
            .output()
            .map_err(|e| format!("{}: {e}", self.node.display()))?;
        let stdout = String::from_utf8_lossy(&out.stdout);
        let summary = stdout.lines().rev().find(|l| l.starts_with("tint: "));
        let failed_to_start = match out.status.code() {
            Some(0 | 1) => summary.is_none(),
            _ => true,
        };
        if failed_to_start {
            return Err(format!(
                "the Tint checker did not run ({}):\n{stdout}{}",
                out.status,
                String::from_utf8_lossy(&out.stderr)
            ));
        }
        let diagnostics: Vec<Diagnostic> = stdout
            .lines()
            .filter_map(|l| parse_line(l, files))
            .collect();
        let errors = diagnostics.iter().filter(|d| d.severity == "error").count();
        // The exit status and the summary must agree with the lines read.
        let want = format!(" {errors} errors,");
        if (out.status.code() == Some(1)) != (errors > 0) || !summary.unwrap().contains(&want) {
            return Err(format!(
                "the Tint checker's output does not add up ({}):\n{stdout}",
                out.status
            ));
        }
        Ok(diagnostics)
    }
}

/// `FILE:LINE:COL: SEVERITY: MESSAGE` for one of `files`.
fn parse_line(line: &str, files: &[PathBuf]) -> Option<Diagnostic> {
    let file = files
        .iter()
        .find(|f| line.starts_with(&format!("{}:", f.display())))?;
    let rest = &line[file.display().to_string().len() + 1..];
    let mut parts = rest.splitn(4, ':');
    let line_no = parts.next()?.trim().parse().ok()?;
    let column = parts.next()?.trim().parse().ok()?;
    let severity = parts.next()?.trim().to_owned();
    let message = parts.next()?.trim().to_owned();
    matches!(severity.as_str(), "error" | "warning").then(|| Diagnostic {
        file: file.clone(),
        line: line_no,
        column,
        severity,
        message,
    })
}
