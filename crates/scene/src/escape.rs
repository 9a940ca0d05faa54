//! Showing untrusted text on a terminal.
//!
//! Scene text, file names and texture paths come from the user (or from
//! whoever wrote the scene), and a terminal obeys some characters instead
//! of showing them: `ESC [2J` clears the screen, `ESC ] 0;… BEL` retitles the
//! window, a lone carriage return overwrites the line, and the Unicode
//! text-direction controls reorder what is shown so that it reads unlike
//! what it is ("Trojan Source", CVE-2021-42574). [`escape`] turns each such
//! character into a visible `\u{…}` escape; every piece of such text that
//! reaches a terminal goes through it (the JSON output, read by programs,
//! stays exact).
//!
//! [`EscapedSource`] does the same to a whole scene text for the source
//! snippets of diagnostics and maps byte offsets into the escaped copy, so
//! labels stay under the characters they point at.

use std::borrow::Cow;
use std::fmt::Write;

/// True for a character a terminal may act on instead of showing: C0
/// controls other than tab and newline, DEL, C1 controls, and the
/// text-direction controls.
pub fn is_hidden(c: char) -> bool {
    (c.is_control() && c != '\t' && c != '\n') || is_text_direction_control(c)
}

/// True for the Unicode bidirectional embedding, override and isolate
/// controls (U+202A–U+202E, U+2066–U+2069), which reorder the text shown
/// around them.
pub fn is_text_direction_control(c: char) -> bool {
    matches!(c, '\u{202A}'..='\u{202E}' | '\u{2066}'..='\u{2069}')
}

/// `text` with every [hidden](is_hidden) character written as `\u{…}`
/// (lowercase hexadecimal, as Rust writes it); borrowed when there is none.
pub fn escape(text: &str) -> Cow<'_, str> {
    if !text.chars().any(is_hidden) {
        return Cow::Borrowed(text);
    }
    let mut escaped = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        push_shown(&mut escaped, c);
    }
    Cow::Owned(escaped)
}

fn push_shown(out: &mut String, c: char) {
    if is_hidden(c) {
        // Writing to a String cannot fail.
        let _ = write!(out, "\\u{{{:x}}}", u32::from(c));
    } else {
        out.push(c);
    }
}

/// A source text with its hidden characters escaped, and how to find an
/// offset of the original in it and back. A carriage return just before a
/// newline is a line ending, not a hidden character, and is kept; a lone
/// carriage return and U+0085, which end a line in scene text, are shown
/// escaped and followed by a newline, so snippets keep the file's lines.
#[derive(Clone, Debug)]
pub struct EscapedSource {
    text: String,
    shifts: Vec<Shift>,
}

/// One escaped character: its bytes in the original, and how many bytes
/// longer the escaped text is up to and including it.
#[derive(Clone, Copy, Debug)]
struct Shift {
    start: usize,
    end: usize,
    extra: usize,
}

impl EscapedSource {
    /// The escaped copy of `text`, or `None` when nothing needs escaping
    /// (the usual case, which then costs one scan and no copy).
    pub fn new(text: &str) -> Option<EscapedSource> {
        let hidden = |i: usize, c: char| {
            is_hidden(c) && !(c == '\r' && text.as_bytes().get(i + 1) == Some(&b'\n'))
        };
        if !text.char_indices().any(|(i, c)| hidden(i, c)) {
            return None;
        }
        let mut escaped = String::with_capacity(text.len() + 64);
        let mut shifts: Vec<Shift> = Vec::new();
        for (i, c) in text.char_indices() {
            if !hidden(i, c) {
                escaped.push(c);
                continue;
            }
            let before = escaped.len();
            push_shown(&mut escaped, c);
            if matches!(c, '\r' | '\u{85}') {
                escaped.push('\n');
            }
            let extra = shifts.last().map_or(0, |s| s.extra);
            shifts.push(Shift {
                start: i,
                end: i + c.len_utf8(),
                extra: extra + (escaped.len() - before) - c.len_utf8(),
            });
        }
        Some(EscapedSource {
            text: escaped,
            shifts,
        })
    }

    /// The escaped text.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// Where byte `offset` of the original lands in the escaped text: an
    /// offset at an escaped character lands at the start of its escape, one
    /// just after it at the escape's end.
    pub fn offset(&self, offset: usize) -> usize {
        match self.shifts.partition_point(|s| s.start < offset) {
            0 => offset,
            n => offset + self.shifts[n - 1].extra,
        }
    }

    /// The byte of the original that byte `offset` of the escaped text
    /// shows (an offset inside an escape gives the escaped character).
    pub fn original(&self, offset: usize) -> usize {
        let done = self.shifts.partition_point(|s| s.end + s.extra <= offset);
        let original = match done {
            0 => offset,
            n => offset - self.shifts[n - 1].extra,
        };
        match self.shifts.get(done) {
            Some(next) => original.min(next.start),
            None => original,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn controls_and_direction_marks_are_escaped_and_others_kept() {
        assert_eq!(escape("a\x1b[2Jb"), "a\\u{1b}[2Jb");
        assert_eq!(escape("\x1b]0;title\x07"), "\\u{1b}]0;title\\u{7}");
        assert_eq!(escape("x\u{202e}y\u{2066}z"), "x\\u{202e}y\\u{2066}z");
        assert_eq!(
            escape("\u{7f}\u{85}\u{9b}\r"),
            "\\u{7f}\\u{85}\\u{9b}\\u{d}"
        );
        // Tab, newline and ordinary Unicode (including the left-to-right
        // mark, which reorders nothing by itself) are shown as they are.
        let plain = "tab\there\nnew line, café, 球, \u{200e}, \u{fffd}";
        assert!(matches!(escape(plain), Cow::Borrowed(_)));
        assert_eq!(escape(plain), plain);
    }

    #[test]
    fn every_hidden_character_is_escaped_and_nothing_else() {
        for code in 0..=0x10FFFF_u32 {
            let Some(c) = char::from_u32(code) else {
                continue;
            };
            let shown = escape(c.encode_utf8(&mut [0; 4])).into_owned();
            let expected_hidden = (code < 0x20 && c != '\t' && c != '\n')
                || (0x7F..=0x9F).contains(&code)
                || (0x202A..=0x202E).contains(&code)
                || (0x2066..=0x2069).contains(&code);
            if expected_hidden {
                assert_eq!(shown, format!("\\u{{{code:x}}}"));
            } else {
                assert_eq!(shown, c.to_string());
            }
        }
    }

    #[test]
    fn offsets_map_onto_the_escaped_source_and_back() {
        let text = "ab\x1bcd\u{202e}ef\r\ng\rh\u{85}i";
        let escaped = EscapedSource::new(text).unwrap();
        assert_eq!(
            escaped.text(),
            "ab\\u{1b}cd\\u{202e}ef\r\ng\\u{d}\nh\\u{85}\ni"
        );
        // Every character not escaped is found at its mapped offset, and
        // maps back to where it was.
        for (i, c) in text.char_indices().filter(|&(_, c)| c.is_alphabetic()) {
            let at = escaped.offset(i);
            assert_eq!(escaped.text()[at..].chars().next(), Some(c));
            assert_eq!(escaped.original(at), i);
        }
        // An escaped character maps to its escape, start to end, and every
        // byte of the escape maps back to it.
        let rlo = text.find('\u{202e}').unwrap();
        let (start, end) = (escaped.offset(rlo), escaped.offset(rlo + 3));
        assert_eq!(&escaped.text()[start..end], "\\u{202e}");
        for at in start..end {
            assert_eq!(escaped.original(at), rlo);
        }
        assert_eq!(escaped.offset(text.len()), escaped.text().len());
        assert_eq!(escaped.original(escaped.text().len()), text.len());
        assert!(EscapedSource::new("plain\r\ntext\n").is_none());
    }
}
