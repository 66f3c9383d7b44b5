//! Dropping the helper functions a module never calls.
//!
//! A node type declares its WGSL helpers as whole texts ([`crate::node::NodeType::wgsl_uses`]),
//! shared between node types: `voronoi_texture` takes Blender's hash from the noise helpers,
//! and with it Perlin noise and the fractals it never calls. The emitter keeps, of the
//! helpers' top-level functions, those reached from the node and group functions through
//! calls; every other item (structs, constants) is kept, and so is the text's order. As
//! naga's `compact` does for IR, but on the text an app receives.

use std::collections::{HashMap, HashSet};

/// One top-level item of a helper text: its text (with the comment lines above it) and, for
/// a function, its name.
#[derive(Debug, PartialEq)]
struct Item<'a> {
    text: &'a str,
    function: Option<&'a str>,
}

/// The top-level items of WGSL `text`, in order. An item runs from the first line after the
/// previous item to the line where its braces close (or its `;` for one without braces);
/// `//` comments are skipped when counting braces.
fn items(text: &str) -> Vec<Item<'_>> {
    let mut out = Vec::new();
    let mut start = 0;
    let mut depth = 0i32;
    let mut opened = false;
    let mut at = 0;
    for line in text.split_inclusive('\n') {
        let code = line.split("//").next().unwrap_or("");
        let trimmed = code.trim();
        for c in code.chars() {
            match c {
                '{' => {
                    depth += 1;
                    opened = true;
                }
                '}' => depth -= 1,
                _ => {}
            }
        }
        at += line.len();
        let ends = depth <= 0 && (opened || trimmed.ends_with(';'));
        if ends {
            let item = &text[start..at];
            out.push(Item {
                text: item,
                function: function_name(item),
            });
            start = at;
            depth = 0;
            opened = false;
        }
    }
    if start < text.len() && !text[start..].trim().is_empty() {
        out.push(Item {
            text: &text[start..],
            function: None,
        });
    }
    out
}

/// The name of the function an item defines: the first line of code starting `fn NAME(`.
fn function_name(item: &str) -> Option<&str> {
    let code = item
        .lines()
        .map(str::trim_start)
        .find(|l| !l.is_empty() && !l.starts_with("//"))?;
    let rest = code.strip_prefix("fn ")?;
    let end = rest.find('(')?;
    Some(rest[..end].trim())
}

/// The identifiers of WGSL text (comments included: a name in a comment only keeps more).
fn identifiers(text: &str) -> impl Iterator<Item = &str> {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|w| w.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_'))
}

/// `helpers` joined as the emitter writes them (each trimmed, a blank line after), less the
/// functions that neither `roots` (the rest of the module's code) nor a kept function calls.
pub(super) fn reachable_helpers(helpers: &[&str], roots: &[&str]) -> String {
    let items: Vec<Vec<Item>> = helpers.iter().map(|h| items(h.trim())).collect();
    let by_name: HashMap<&str, &Item> = items
        .iter()
        .flatten()
        .filter_map(|i| i.function.map(|f| (f, i)))
        .collect();
    let mut kept: HashSet<&str> = HashSet::new();
    let mut todo: Vec<&str> = Vec::new();
    let roots_and_other_items = roots.iter().copied().chain(
        items
            .iter()
            .flatten()
            .filter(|i| i.function.is_none())
            .map(|i| i.text),
    );
    for text in roots_and_other_items {
        todo.extend(identifiers(text).filter(|w| by_name.contains_key(w)));
    }
    while let Some(name) = todo.pop() {
        if kept.insert(name) {
            let item = by_name[name];
            todo.extend(
                identifiers(item.text).filter(|w| by_name.contains_key(w) && !kept.contains(w)),
            );
        }
    }
    let mut out = String::new();
    for helper in &items {
        let mut text = String::new();
        for item in helper {
            if item.function.is_none_or(|f| kept.contains(f)) {
                text.push_str(item.text);
            }
        }
        let text = text.trim();
        if !text.is_empty() {
            out.push_str(text);
            out.push_str("\n\n");
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const HELPER: &str = "\
// The hash.
fn h(x: u32) -> u32 {
    return x * 3u; // not } a brace
}

struct S {
    a: f32,
}

const K: f32 = 2.0;

// Calls h.
fn g(x: u32) -> u32 {
    return h(x) + 1u;
}

fn unused(x: f32) -> f32 {
    if (x > 0.0) {
        return x;
    }
    return -x;
}
";

    #[test]
    fn items_split_at_top_level_and_keep_their_comments() {
        let got: Vec<Option<&str>> = items(HELPER).iter().map(|i| i.function).collect();
        assert_eq!(got, [Some("h"), None, None, Some("g"), Some("unused")]);
        assert!(items(HELPER)[0].text.starts_with("// The hash.\nfn h("));
        assert!(items(HELPER)[3].text.contains("// Calls h.\nfn g("));
    }

    #[test]
    fn only_functions_reached_from_the_roots_stay() {
        let got = reachable_helpers(&[HELPER], &["fn mg_node() -> u32 { return g(1u); }"]);
        assert!(got.contains("fn h(") && got.contains("fn g("), "{got}");
        assert!(!got.contains("fn unused("), "{got}");
        assert!(got.contains("struct S") && got.contains("const K"), "{got}");
        // Nothing called: the structs and constants only.
        let none = reachable_helpers(&[HELPER], &["fn mg_node() -> f32 { return 1.0; }"]);
        assert!(!none.contains("fn "), "{none}");
        // A helper text with nothing left is not written at all.
        assert_eq!(reachable_helpers(&["fn z() {}"], &[""]), "");
    }
}
