//! Parsers and bounds of the numeric command-line flags: every float flag refuses NaN, the
//! infinities and values beyond the f32 range (`1e39`), and every count has a largest
//! accepted value, so no flag can turn into a black image, an endless run or an abort.
//! clap prints the refusals as `invalid value 'V' for '--FLAG <…>': WHY`.

/// Largest `matgraph report --samples`: 2^18 node-space samples, 16× the default. Each
/// sample holds 84 bytes of attributes plus, per step of the radiance plan, 12 bytes per
/// register, so the largest families stay within a few hundred MiB.
pub const MAX_REPORT_SAMPLES: u64 = 1 << 18;

/// Largest `matgraph report --repeats`: each repeat times every variant once more.
pub const MAX_REPORT_REPEATS: u32 = 1000;

/// Largest magnitude of `--exposure` in stops: 2^±64 is a finite, normal f32 scale factor.
pub const MAX_EXPOSURE: f32 = 64.0;

/// Why `x`, parsed from `text`, is not a usable f32 (or `None` where it is).
fn not_finite(text: &str, x: f64) -> Option<String> {
    if x.is_nan() || x.is_infinite() {
        Some(format!(
            "{text} is not a finite number (NaN and infinities are refused)"
        ))
    } else if x.abs() > f32::MAX as f64 {
        Some(format!("{text} is beyond the f32 range of ±{:e}", f32::MAX))
    } else {
        None
    }
}

/// A finite f32 (`--time`, `--fps`).
pub fn finite_f32(text: &str) -> Result<f32, String> {
    let x: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("{text} is not a number"))?;
    match not_finite(text, x) {
        Some(why) => Err(why),
        None => Ok(x as f32),
    }
}

/// `--exposure`: a finite number of stops within ±[`MAX_EXPOSURE`].
pub fn exposure(text: &str) -> Result<f32, String> {
    let x = finite_f32(text)?;
    if x.abs() > MAX_EXPOSURE {
        return Err(format!(
            "{text} stops: the exposure must be from -{MAX_EXPOSURE} to {MAX_EXPOSURE} stops"
        ));
    }
    Ok(x)
}

/// `--max-error`: a finite error bound of at least 0.
pub fn max_error(text: &str) -> Result<f64, String> {
    let x: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("{text} is not a number"))?;
    if !x.is_finite() {
        return Err(format!(
            "{text} is not a finite number (NaN and infinities are refused)"
        ));
    }
    if x < 0.0 {
        return Err(format!("{text}: an error bound must be 0 or more"));
    }
    Ok(x)
}

/// What is wrong with the numbers of a `--set` value, for its message: NaN or an infinity
/// written as a word (`NaN`, `inf`), or a number beyond the f32 range; empty where its
/// numbers are fine.
pub fn set_value_hint(value: &serde_json::Value) -> String {
    use serde_json::Value as J;
    match value {
        J::String(s) if s.trim().parse::<f64>().is_ok_and(|x| !x.is_finite()) => {
            format!(" ({s} is not a finite number: NaN and infinities are refused)")
        }
        J::Number(n) => n
            .as_f64()
            .and_then(|x| not_finite(&n.to_string(), x))
            .map(|why| format!(" ({why})"))
            .unwrap_or_default(),
        J::Array(items) => items
            .iter()
            .map(set_value_hint)
            .find(|h| !h.is_empty())
            .unwrap_or_default(),
        _ => String::new(),
    }
}
