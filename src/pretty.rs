//! A deterministic, diff-friendly JSON printer: two-space indents, and any array or object
//! whose one-line form fits within the line width kept on one line
//! (`"position": [400.0, 100.0]`, `{ "link": "cos.result" }`).

use serde_json::Value;

/// Line width the printer keeps one-line forms within.
pub const WIDTH: usize = 100;

/// Prints `value` with a trailing newline.
pub fn to_string(value: &Value) -> String {
    let mut out = String::new();
    write(value, 0, 0, &mut out);
    out.push('\n');
    out
}

fn write(value: &Value, indent: usize, prefix: usize, out: &mut String) {
    let inline = one_line(value);
    if indent + prefix + inline.len() <= WIDTH
        || !matches!(value, Value::Array(_) | Value::Object(_))
    {
        out.push_str(&inline);
        return;
    }
    let pad = " ".repeat(indent + 2);
    match value {
        Value::Array(items) => {
            out.push_str("[\n");
            for (k, item) in items.iter().enumerate() {
                out.push_str(&pad);
                write(item, indent + 2, 0, out);
                out.push_str(if k + 1 < items.len() { ",\n" } else { "\n" });
            }
        }
        Value::Object(map) => {
            out.push_str("{\n");
            for (k, (key, item)) in map.iter().enumerate() {
                let key = Value::String(key.clone()).to_string();
                out.push_str(&pad);
                out.push_str(&key);
                out.push_str(": ");
                write(item, indent + 2, key.len() + 2, out);
                out.push_str(if k + 1 < map.len() { ",\n" } else { "\n" });
            }
        }
        _ => unreachable!(),
    }
    out.push_str(&" ".repeat(indent));
    out.push(if value.is_array() { ']' } else { '}' });
}

/// The one-line form: `[a, b]`, `{ "k": v }`, `[]`, `{}`.
fn one_line(value: &Value) -> String {
    match value {
        Value::Array(items) if !items.is_empty() => {
            let parts: Vec<String> = items.iter().map(one_line).collect();
            format!("[{}]", parts.join(", "))
        }
        Value::Object(map) if !map.is_empty() => {
            let parts: Vec<String> = map
                .iter()
                .map(|(k, v)| format!("{}: {}", Value::String(k.clone()), one_line(v)))
                .collect();
            format!("{{ {} }}", parts.join(", "))
        }
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn short_collections_stay_on_one_line() {
        let v = json!({ "a": [1.0, 2.0], "b": { "link": "x.y" } });
        assert_eq!(
            to_string(&v),
            "{ \"a\": [1.0, 2.0], \"b\": { \"link\": \"x.y\" } }\n"
        );
    }

    #[test]
    fn long_collections_break_one_item_a_line() {
        let long = "x".repeat(120);
        let v = json!({ "a": [long.clone()], "b": 1 });
        assert_eq!(
            to_string(&v),
            format!("{{\n  \"a\": [\n    \"{long}\"\n  ],\n  \"b\": 1\n}}\n")
        );
    }
}
