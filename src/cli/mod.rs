//! The commands of the `matgraph` binary, one file each, and what they share.

pub mod check;
pub mod eval;
pub mod fmt;
pub mod nodes;
pub mod render;
pub mod schema;
pub mod wgsl;

use matgraph::Registry;

/// What a command returns: `Err` holds the message printed on stderr (exit status 1).
pub type CliResult = Result<(), String>;

/// The built-in node registry.
pub fn registry() -> &'static Registry {
    Registry::builtin()
}

/// Parses a command-line value: JSON (`0.5`, `[0.1,0.2]`, `true`), else a bare enum choice name.
pub fn parse_value(text: &str) -> serde_json::Value {
    serde_json::from_str(text).unwrap_or_else(|_| serde_json::Value::String(text.to_owned()))
}

/// Splits `--set NAME=VALUE` into the name and the parsed value.
pub fn split_set(s: &str) -> Result<(&str, serde_json::Value), String> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| format!("--set '{s}': expected NAME=VALUE"))?;
    Ok((name.trim(), parse_value(value.trim())))
}
