//! Values typed into an input's editor, checked before they reach the graph: text that is
//! not a number, and a number outside the input's hard range (the range the loader rejects
//! a literal outside of, [`crate::node::InputDecl::hard`]), are refused with the reason,
//! which the canvas shows under the input ([`Rejections`]) and the status line repeats.
//! egui's `DragValue` otherwise drops text it cannot parse without a word, and took any
//! number.

use super::ports::Port;
use crate::node::Range;
use std::collections::BTreeMap;

/// `x` as the editor prints it: egui's minus sign (U+2212) for a negative number, ∞ for an
/// infinite bound, at most 6 significant digits.
pub fn number(x: f64) -> String {
    if x.is_infinite() {
        return if x < 0.0 { "−∞" } else { "∞" }.to_owned();
    }
    let s = format!("{}", (x as f32));
    match s.strip_prefix('-') {
        Some(rest) => format!("−{rest}"),
        None => s,
    }
}

/// `r` as the editor prints it: `min … max`.
pub fn range(r: &Range) -> String {
    format!("{} … {}", number(r.min.into()), number(r.max.into()))
}

/// Reads `text` typed into the editor of `what` (an input's name, a lane's `name.x`) of
/// port `port`: the number, or why it is refused. Whitespace is ignored and egui's minus
/// sign (U+2212) read as `-`, as egui's own parser does.
pub fn check(port: &Port, what: &str, text: &str) -> Result<f64, String> {
    let plain: String = text
        .chars()
        .filter(|c| !c.is_whitespace())
        .map(|c| if c == '−' { '-' } else { c })
        .collect();
    let shown = text.trim();
    let x = match plain.parse::<f64>() {
        Ok(x) if x.is_finite() => x,
        _ if shown.is_empty() => return Err(format!("{what}: a value is needed")),
        _ => return Err(format!("{what}: \"{shown}\" is not a number")),
    };
    if let Some(h) = port.hard {
        let (lo, hi) = (f64::from(h.min), f64::from(h.max));
        if x < lo {
            return Err(format!(
                "{what}: {} is below the hard range {}",
                number(x),
                range(&h)
            ));
        }
        if x > hi {
            return Err(format!(
                "{what}: {} is above the hard range {}",
                number(x),
                range(&h)
            ));
        }
    }
    Ok(x)
}

/// `x` read for `what`, an integer input: refused where it is not a whole number.
pub fn whole(what: &str, x: f64) -> Result<f64, String> {
    match x.fract() == 0.0 {
        true => Ok(x),
        false => Err(format!("{what}: {} is not a whole number", number(x))),
    }
}

/// The values refused on the canvas, by node id and input name, each with its reason;
/// kept until the input gets a value or the graph is replaced.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Rejections {
    by_input: BTreeMap<(String, String), String>,
}

impl Rejections {
    /// Records that a value typed into `node`.`input` was refused, and why.
    pub fn reject(&mut self, node: &str, input: &str, why: String) {
        self.by_input
            .insert((node.to_owned(), input.to_owned()), why);
    }

    /// Forgets the refusal at `node`.`input` (it got a value).
    pub fn accept(&mut self, node: &str, input: &str) {
        self.by_input.remove(&(node.to_owned(), input.to_owned()));
    }

    /// Why the last value typed into `node`.`input` was refused, if it was.
    pub fn get(&self, node: &str, input: &str) -> Option<&str> {
        self.by_input
            .get(&(node.to_owned(), input.to_owned()))
            .map(String::as_str)
    }

    /// Forgets every refusal (another graph).
    pub fn clear(&mut self) {
        self.by_input.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::value::Value;
    use std::borrow::Cow;

    fn port(hard: Option<(f32, f32)>) -> Port {
        Port {
            name: Cow::Borrowed("f0"),
            ty: crate::node::PortType::Fixed(crate::types::SocketType::Float),
            default: Value::float(0.04),
            soft: Some(Range { min: 0.0, max: 0.2 }),
            hard: hard.map(|(min, max)| Range { min, max }),
            unit: Cow::Borrowed(""),
            doc: Cow::Borrowed(""),
            choices: &[],
        }
    }

    #[test]
    fn typed_text_is_read_as_egui_reads_it_and_refused_with_the_reason() {
        let p = port(Some((0.0, 1.0)));
        assert_eq!(check(&p, "f0", " 0.5 "), Ok(0.5));
        assert_eq!(check(&p, "f0", "1"), Ok(1.0));
        assert_eq!(check(&p, "f0", "−0"), Ok(0.0));
        assert_eq!(
            check(&p, "f0", "-5"),
            Err("f0: −5 is below the hard range 0 … 1".into())
        );
        assert_eq!(
            check(&p, "f0", "1.5"),
            Err("f0: 1.5 is above the hard range 0 … 1".into())
        );
        assert_eq!(
            check(&p, "f0", "abc"),
            Err("f0: \"abc\" is not a number".into())
        );
        assert_eq!(
            check(&p, "f0", "inf"),
            Err("f0: \"inf\" is not a number".into())
        );
        assert_eq!(check(&p, "f0", "  "), Err("f0: a value is needed".into()));
        // Beyond the soft range (the slider's) but inside the hard one: taken.
        assert_eq!(check(&p, "f0", "0.9"), Ok(0.9));
        // No hard range: any number.
        assert_eq!(check(&port(None), "f0", "-5"), Ok(-5.0));
        let open = port(Some((0.0, f32::INFINITY)));
        assert_eq!(
            check(&open, "n.y", "-1e-3"),
            Err("n.y: −0.001 is below the hard range 0 … ∞".into())
        );
    }

    #[test]
    fn a_refusal_is_kept_per_input_until_it_gets_a_value() {
        let mut r = Rejections::default();
        r.reject("brdf", "metallic", "metallic: −5 is below".into());
        r.reject(
            "brdf",
            "roughness",
            "roughness: \"x\" is not a number".into(),
        );
        assert_eq!(r.get("brdf", "metallic"), Some("metallic: −5 is below"));
        r.accept("brdf", "metallic");
        assert_eq!(r.get("brdf", "metallic"), None);
        assert!(r.get("brdf", "roughness").is_some());
        r.clear();
        assert_eq!(r, Rejections::default());
    }
}
