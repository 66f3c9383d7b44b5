//! User text made safe to print (issue 37): node ids, output, parameter, file and graph
//! names reach messages, the editor's Problems list and generated WGSL comments, and a
//! control character in them (an ANSI escape, NUL, BEL, a line break) or a bidirectional
//! override (U+202E) would act on the terminal or reorder the line instead of showing.
//! Every message passes through [`visible`] or [`visible_lines`].

use std::borrow::Cow;
use std::fmt::Write as _;

/// Whether `c` must not reach a terminal or a log raw: C0 and C1 controls and DEL, the
/// Unicode bidirectional marks, embeddings, overrides and isolates, and the line and
/// paragraph separators.
pub fn is_hidden(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            '\u{061c}'
                | '\u{200e}'
                | '\u{200f}'
                | '\u{202a}'..='\u{202e}'
                | '\u{2066}'..='\u{2069}'
                | '\u{2028}'
                | '\u{2029}'
        )
}

/// `s` with every [`is_hidden`] character written as Rust escapes it (`\n`, `\r`, `\t`,
/// `\u{1b}`, `\u{202e}`, `\u{0}`): one line, shown as it is spelt.
pub fn visible(s: &str) -> Cow<'_, str> {
    escape(s, |_| true)
}

/// [`visible`] for text of several lines: line breaks and tabs are kept, every other
/// hidden character escaped (a message's own line breaks separate its errors; user text
/// inside each is escaped by [`visible`] where it is put together).
pub fn visible_lines(s: &str) -> Cow<'_, str> {
    escape(s, |c| c != '\n' && c != '\t')
}

/// `s` with the hidden characters for which `escape_it` holds escaped.
fn escape(s: &str, escape_it: impl Fn(char) -> bool) -> Cow<'_, str> {
    let bad = |c: char| is_hidden(c) && escape_it(c);
    if !s.chars().any(bad) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if bad(c) {
            let _ = write!(out, "{}", c.escape_default());
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hidden_characters_are_spelt_out() {
        assert_eq!(visible("a\u{1b}[31mb"), "a\\u{1b}[31mb");
        assert_eq!(visible("x\0y\u{7}z"), "x\\u{0}y\\u{7}z");
        assert_eq!(visible("l\u{202e}r"), "l\\u{202e}r");
        assert_eq!(visible("one\ntwo\rthree"), "one\\ntwo\\rthree");
        assert_eq!(visible_lines("one\ntwo\r\u{85}"), "one\ntwo\\r\\u{85}");
        assert!(matches!(visible("plain 'text' ü"), Cow::Borrowed(_)));
    }
}
