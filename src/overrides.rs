//! Overrides written `NAME=VALUE` (the command line's `--set`): a node input
//! (`NODE.INPUT=VALUE`), a geometry attribute (`view=[0.8,0,0.6]`) or a graph parameter
//! (`ior=2.42`). Values are JSON (`0.5`, `[0.1,0.2]`, `true`) or a bare enum choice's name.
//! Every number is checked against the f32 range as written, before any use, so `1e39` is
//! refused as beyond that range and `NaN` or `inf` as not finite, never as "the wrong
//! type". Errors name the override as the user wrote it.

use crate::document::GraphDocument;
use crate::node::Attribute;
use crate::plan::{ParamValues, Plan};
use crate::value::Value;

/// One `NAME=VALUE` override, its value parsed and its numbers checked.
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    /// The name before `=`, trimmed (`ior`, `exact.ior_outside`).
    pub name: String,
    /// The value as written after `=`, trimmed.
    pub text: String,
    /// The value: JSON, or a string holding a bare word.
    pub value: serde_json::Value,
}

/// What an override sets, by its name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target<'a> {
    /// `NODE.INPUT`: an input of a node of the graph.
    Input {
        /// The node's id.
        node: &'a str,
        /// The input's name.
        input: &'a str,
    },
    /// A geometry attribute (`position`, `normal`, `view`, `light`, `uv`, `time`, …).
    Attribute(Attribute),
    /// Any other name: a graph parameter.
    Parameter(&'a str),
}

/// Why an override cannot be used; each names the override as written.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum OverrideError {
    /// No `=`, or nothing before it.
    #[error("--set '{text}': expected NAME=VALUE")]
    Malformed {
        /// The whole override as written.
        text: String,
    },
    /// A number beyond ±[`f32::MAX`] (`1e39`, `-4e38`, `1e400`).
    #[error(
        "--set {name}={text}: {number} is beyond the f32 range of ±{max:e} (values are f32s)",
        max = f32::MAX
    )]
    OutOfRange {
        /// The name.
        name: String,
        /// The value as written.
        text: String,
        /// The number at fault, as written.
        number: String,
    },
    /// NaN or an infinity written as a word (`NaN`, `inf`, `-infinity`).
    #[error(
        "--set {name}={text}: {number} is not a finite number (NaN and infinities are refused)"
    )]
    NotFinite {
        /// The name.
        name: String,
        /// The value as written.
        text: String,
        /// The word at fault, as written.
        number: String,
    },
    /// `NODE.INPUT` where the graph has no node `NODE`.
    #[error("--set {name}: no node '{node}'")]
    NoNode {
        /// The name.
        name: String,
        /// The node id it names.
        node: String,
    },
    /// A value of the wrong shape for what it sets (`view=[1,2]` for a vec3).
    #[error("--set {name}: expected a {expected} value, found {text}")]
    WrongType {
        /// The name.
        name: String,
        /// The type expected, in the user's words (`float`, `vec3`).
        expected: String,
        /// The value as written.
        text: String,
    },
    /// A name that is not a node input, parameter or attribute of the graph.
    #[error("--set {name}: {message} (not a node input, parameter or attribute)")]
    Unknown {
        /// The name.
        name: String,
        /// Why, with the nearest parameter's name when there is one.
        message: String,
    },
    /// A parameter's value that the graph refuses (outside the hard range of an input it
    /// feeds).
    #[error("--set {name}: {message}")]
    Refused {
        /// The name.
        name: String,
        /// Why, naming the node and input.
        message: String,
    },
}

impl Override {
    /// Parses `NAME=VALUE`: the name and value trimmed, the value as JSON or else a bare
    /// word, every number in it within the f32 range and finite.
    pub fn parse(text: &str) -> Result<Override, OverrideError> {
        let (name, value) = text
            .split_once('=')
            .filter(|(name, _)| !name.trim().is_empty())
            .ok_or_else(|| OverrideError::Malformed {
                text: text.to_owned(),
            })?;
        let (name, text) = (name.trim().to_owned(), value.trim().to_owned());
        if let Some((number, value)) = bad_number(&text) {
            let number = number.to_owned();
            return Err(
                if value.is_nan() || !number.bytes().any(|b| b.is_ascii_digit()) {
                    OverrideError::NotFinite { name, text, number }
                } else {
                    OverrideError::OutOfRange { name, text, number }
                },
            );
        }
        let value =
            serde_json::from_str(&text).unwrap_or_else(|_| serde_json::Value::String(text.clone()));
        Ok(Override { name, text, value })
    }

    /// What the override sets, read from its name.
    pub fn target(&self) -> Target<'_> {
        if let Some((node, input)) = self.name.split_once('.') {
            Target::Input { node, input }
        } else if let Some(a) = Attribute::from_name(&self.name) {
            Target::Attribute(a)
        } else {
            Target::Parameter(&self.name)
        }
    }

    /// The value as a `ty` value (`WrongType` when it has another shape).
    pub fn typed(&self, ty: crate::types::SocketType) -> Result<Value, OverrideError> {
        Value::from_json(ty, &self.value).ok_or_else(|| self.wrong_type(ty.name()))
    }

    /// The value with its type read from its shape: a number is a float, an array of 2–4
    /// numbers a vector, a bool a bool (for overrides applied to graphs whose parameters
    /// are not known yet).
    pub fn inferred(&self) -> Result<Value, OverrideError> {
        Value::infer_json(&self.value)
            .ok_or_else(|| self.wrong_type("number, an array of 2-4 numbers or a bool"))
    }

    fn wrong_type(&self, expected: &str) -> OverrideError {
        OverrideError::WrongType {
            name: self.name.clone(),
            expected: expected.to_owned(),
            text: self.text.clone(),
        }
    }
}

/// The first number of `text` beyond the f32 range (one that rounds to an f32 infinity, as
/// [`Value::from_json`] reads it) or not finite, as written, with its value. Numbers are the runs between JSON's punctuation and spaces that Rust reads as an
/// `f64` (which takes `NaN`, `inf` and `infinity` in any case); quoted strings are skipped.
fn bad_number(text: &str) -> Option<(&str, f64)> {
    let mut quoted = false;
    let mut escaped = false;
    let mut start = None;
    let bytes = text.as_bytes();
    for i in 0..=bytes.len() {
        let b = bytes.get(i).copied();
        if quoted {
            match b {
                _ if escaped => escaped = false,
                Some(b'\\') => escaped = true,
                Some(b'"') => quoted = false,
                _ => {}
            }
            continue;
        }
        let separator = match b {
            None => true,
            Some(c) => b"[]{},:\"".contains(&c) || c.is_ascii_whitespace(),
        };
        if !separator {
            start.get_or_insert(i);
            continue;
        }
        if let Some(s) = start.take() {
            let token = &text[s..i];
            if let Ok(x) = token.parse::<f64>()
                && !(x as f32).is_finite()
            {
                return Some((token, x));
            }
        }
        if b == Some(b'"') {
            quoted = true;
        }
    }
    None
}

/// Parses every override.
pub fn parse_all<S: AsRef<str>>(texts: &[S]) -> Result<Vec<Override>, OverrideError> {
    texts.iter().map(|t| Override::parse(t.as_ref())).collect()
}

/// The overrides of one node alone (`matgraph eval --node`): each name is an input.
pub fn node_inputs(
    overrides: &[Override],
) -> std::collections::BTreeMap<String, serde_json::Value> {
    overrides
        .iter()
        .map(|o| (o.name.clone(), o.value.clone()))
        .collect()
}

/// What is left of a graph's overrides once the node inputs are written into its document.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Remaining {
    /// The geometry attributes and their values, in the order given.
    pub attributes: Vec<(Attribute, Value)>,
    /// The parameter overrides, to set with [`set_parameters`] once the graph is planned.
    pub parameters: Vec<Override>,
}

/// Writes the `NODE.INPUT` overrides into `doc` (checked with the rest of the graph when it
/// is loaded), types the attribute overrides, and returns those and the parameters.
pub fn apply_to_document(
    doc: &mut GraphDocument,
    overrides: &[Override],
) -> Result<Remaining, OverrideError> {
    let mut rest = Remaining::default();
    for o in overrides {
        match o.target() {
            Target::Input { node, input } => {
                let n = doc.nodes.iter_mut().find(|n| n.id == node).ok_or_else(|| {
                    OverrideError::NoNode {
                        name: o.name.clone(),
                        node: node.to_owned(),
                    }
                })?;
                n.inputs.insert(input.to_owned(), o.value.clone());
            }
            Target::Attribute(a) => rest.attributes.push((a, o.typed(a.ty())?)),
            Target::Parameter(_) => rest.parameters.push(o.clone()),
        }
    }
    Ok(rest)
}

/// Sets each parameter override in `values`, typed by `plan`'s parameter of that name.
pub fn set_parameters(
    plan: &Plan,
    values: &mut ParamValues,
    parameters: &[Override],
) -> Result<(), OverrideError> {
    for o in parameters {
        let unknown = |values: &mut ParamValues| OverrideError::Unknown {
            name: o.name.clone(),
            message: values
                .set(&o.name, Value::float(0.0))
                .err()
                .map(|e| e.to_string())
                .unwrap_or_else(|| format!("unknown parameter '{}'", o.name)),
        };
        let Some(p) = plan.parameters().iter().find(|p| p.name == o.name) else {
            return Err(unknown(values));
        };
        let v = o.typed(p.ty)?;
        values.set(&o.name, v).map_err(|e| OverrideError::Refused {
            name: o.name.clone(),
            message: e.to_string(),
        })?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        Override::parse(text).unwrap_err().to_string()
    }

    #[test]
    fn numbers_past_f32_are_refused_as_written() {
        assert_eq!(
            err("ior=1e39"),
            "--set ior=1e39: 1e39 is beyond the f32 range of ±3.4028235e38 (values are f32s)"
        );
        assert!(err("uv = [0.5, -4e38]").starts_with("--set uv=[0.5, -4e38]: -4e38 is beyond"));
        assert!(err("x=1e400").contains("1e400 is beyond the f32 range"));
        assert!(err("x=NaN").contains("NaN is not a finite number"));
        assert!(err("x=[1,-inf]").contains("-inf is not a finite number"));
        assert!(err("x=Infinity").contains("Infinity is not a finite number"));
        assert_eq!(err("x"), "--set 'x': expected NAME=VALUE");
        assert_eq!(err(" =1"), "--set ' =1': expected NAME=VALUE");
        // f32::MAX itself, words in quotes and enum names are fine.
        for ok in [
            "a=3.4028235e38",
            "a=\"inf\"",
            "a=phase_form",
            "a={\"link\":\"n.x\"}",
        ] {
            Override::parse(ok).unwrap();
        }
    }

    #[test]
    fn targets_follow_the_name() {
        let t = |s: &str| Override::parse(s).unwrap();
        assert_eq!(
            t("exact.ior=2").target(),
            Target::Input {
                node: "exact",
                input: "ior"
            }
        );
        assert_eq!(
            t("view=[0,0,1]").target(),
            Target::Attribute(Attribute::View)
        );
        assert_eq!(t("ior=2").target(), Target::Parameter("ior"));
        assert_eq!(t("x=linear").value, serde_json::json!("linear"));
    }
}
