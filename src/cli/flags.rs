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

/// Smallest `--memory-budget`: 16 MiB (the scenes' fixed meshes alone are reserved at
/// [`matgraph::scene::FIXED_MESH_BYTES`]).
pub const MIN_MEMORY_BUDGET: u64 = 16 << 20;

/// Largest `--memory-budget`: 1 TiB (`u64` byte counts cannot overflow below it).
pub const MAX_MEMORY_BUDGET: u64 = 1 << 40;

/// `--memory-budget`: a byte count, a number with a binary unit (`512MiB`, `2GiB`, `1.5G`;
/// `K`, `M`, `G`, `T` with or without `iB` are powers of 1024; `B` or none, bytes), from
/// [`MIN_MEMORY_BUDGET`] to [`MAX_MEMORY_BUDGET`].
pub fn memory_budget(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let split = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(t.len());
    let (number, unit) = t.split_at(split);
    let scale: u64 = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 1,
        "k" | "kib" | "kb" => 1 << 10,
        "m" | "mib" | "mb" => 1 << 20,
        "g" | "gib" | "gb" => 1 << 30,
        "t" | "tib" | "tb" => 1 << 40,
        other => {
            return Err(format!(
                "{text}: unknown unit '{other}' (use bytes or K, M, G, T: 512MiB, 2GiB)"
            ));
        }
    };
    let x: f64 = number
        .parse()
        .map_err(|_| format!("{text} is not a size (use bytes or K, M, G, T: 512MiB, 2GiB)"))?;
    let bytes = x * scale as f64;
    if !(bytes >= MIN_MEMORY_BUDGET as f64 && bytes <= MAX_MEMORY_BUDGET as f64) {
        return Err(format!(
            "{text}: the memory budget must be from {} to {}",
            matgraph::budget::format_bytes(MIN_MEMORY_BUDGET),
            matgraph::budget::format_bytes(MAX_MEMORY_BUDGET)
        ));
    }
    Ok(bytes as u64)
}
