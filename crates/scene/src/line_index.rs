//! Where a text's lines start, so a byte offset's line and column are
//! found by a binary search instead of a scan from the start of the text;
//! the one line index of every caller (diagnostics, the language server).
//!
//! Every diagnostic shows a line and column; finding them by counting from
//! the start makes a report over many problems cost the number of
//! problems times the size of the file. A [`LineIndex`] is built once per
//! text (one pass) and answers each lookup in logarithmic time, and a
//! column in characters with a scan of at most [`CHECKPOINT_BYTES`].
//! Which bytes end a line is the caller's choice ([`LineEnds`]): `\n`
//! alone (a `\r\n` ending is one line end), as in the human renderer's
//! snippets, or also a lone `\r`, as the Language Server Protocol counts;
//! columns come in characters or in UTF-16 code units (the protocol's).

use crate::span::floor_char_boundary;

/// Bytes between the checkpoints that count the characters before them.
const CHECKPOINT_BYTES: usize = 4096;

/// Which bytes end a line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LineEnds {
    /// `\n` (so `\r\n` too): diagnostics' lines.
    Newline,
    /// `\n`, `\r\n` and a lone `\r`: the Language Server Protocol's.
    Any,
}

/// The line starts of a text and the number of characters before every
/// [`CHECKPOINT_BYTES`]-th byte.
#[derive(Clone, Debug)]
pub struct LineIndex {
    /// The byte offset of every line's first byte; `starts[0] == 0`.
    starts: Vec<usize>,
    /// `chars[k]`: how many characters start before byte `k *
    /// CHECKPOINT_BYTES`.
    chars: Vec<usize>,
}

impl LineIndex {
    /// Index `text` in one pass, lines ended by `\n`.
    pub fn new(text: &str) -> LineIndex {
        LineIndex::with_line_ends(text, LineEnds::Newline)
    }

    /// Index `text` in one pass, lines ended as `ends` says.
    pub fn with_line_ends(text: &str, ends: LineEnds) -> LineIndex {
        let bytes = text.as_bytes();
        let mut starts = vec![0];
        starts.extend(
            bytes
                .iter()
                .enumerate()
                .filter(|&(i, &b)| {
                    b == b'\n'
                        || ends == LineEnds::Any && b == b'\r' && bytes.get(i + 1) != Some(&b'\n')
                })
                .map(|(i, _)| i + 1),
        );
        let mut chars = Vec::with_capacity(bytes.len() / CHECKPOINT_BYTES + 1);
        let mut before = 0;
        for chunk in bytes.chunks(CHECKPOINT_BYTES) {
            chars.push(before);
            before += char_starts(chunk);
        }
        chars.push(before);
        LineIndex { starts, chars }
    }

    /// The 0-based line holding byte `offset` (the last line for an
    /// offset past the end).
    pub fn line(&self, offset: usize) -> usize {
        self.starts.partition_point(|&start| start <= offset) - 1
    }

    /// The first byte of 0-based `line`, or `None` past the last line.
    pub fn start(&self, line: usize) -> Option<usize> {
        self.starts.get(line).copied()
    }

    /// 1-based line and column (in characters) of byte `offset` of `text`,
    /// the text this index was built from.
    pub fn line_col(&self, text: &str, offset: usize) -> (usize, usize) {
        let offset = floor_char_boundary(text, offset);
        let line = self.line(offset);
        let column = self.chars_before(text, offset) - self.chars_before(text, self.starts[line]);
        (line + 1, column + 1)
    }

    /// 0-based line and column in UTF-16 code units of byte `offset` of
    /// `text` (clamped to it, and back to a character boundary).
    pub fn utf16_position(&self, text: &str, offset: usize) -> (usize, usize) {
        let offset = floor_char_boundary(text, offset);
        let line = self.line(offset);
        (line, text[self.starts[line]..offset].encode_utf16().count())
    }

    /// The byte offset of 0-based `line` and UTF-16 `column` of `text`: a
    /// line past the end is the end of the text, a column past its line's
    /// end is that end (before its line end), and a column inside a
    /// surrogate pair is the end of that character.
    pub fn utf16_offset(&self, text: &str, line: usize, column: usize) -> usize {
        let Some(&start) = self.starts.get(line) else {
            return text.len();
        };
        let end = self.starts.get(line + 1).copied().unwrap_or(text.len());
        let mut units = 0;
        for (i, c) in text[start..end].char_indices() {
            if units >= column || c == '\n' || c == '\r' {
                return start + i;
            }
            units += c.len_utf16();
        }
        end
    }

    /// How many characters of `text` start before byte `offset` (a
    /// character boundary).
    fn chars_before(&self, text: &str, offset: usize) -> usize {
        let checkpoint = offset / CHECKPOINT_BYTES;
        let from = checkpoint * CHECKPOINT_BYTES;
        self.chars[checkpoint] + char_starts(&text.as_bytes()[from..offset])
    }
}

/// How many characters start in `bytes`: the bytes that are not UTF-8
/// continuation bytes.
fn char_starts(bytes: &[u8]) -> usize {
    bytes.iter().filter(|&&b| b & 0xC0 != 0x80).count()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The scan the index replaces.
    fn scanned(text: &str, offset: usize) -> (usize, usize) {
        let before = &text[..floor_char_boundary(text, offset)];
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        (
            before.matches('\n').count() + 1,
            before[line_start..].chars().count() + 1,
        )
    }

    #[test]
    fn lines_and_columns_match_a_scan_from_the_start() {
        let long = "é".repeat(5000);
        let texts = [
            String::new(),
            "camera 4\nsphere\r\n  dimension 1\n".to_string(),
            format!("a\n{long}x\n\u{2028}b\n"),
            "\n\n\n".to_string(),
        ];
        for text in &texts {
            let index = LineIndex::new(text);
            for offset in 0..=text.len() + 2 {
                assert_eq!(
                    index.line_col(text, offset),
                    scanned(text, offset),
                    "{offset}"
                );
            }
        }
    }

    #[test]
    fn line_starts() {
        let index = LineIndex::new("ab\ncd\n");
        assert_eq!(index.line(0), 0);
        assert_eq!(index.line(3), 1);
        assert_eq!(index.line(6), 2);
        assert_eq!(index.line(99), 2);
        assert_eq!(index.start(1), Some(3));
        assert_eq!(index.start(3), None);
    }
}
