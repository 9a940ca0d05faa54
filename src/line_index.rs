//! Where a text's lines start, so a byte offset's line and column are
//! found by a binary search instead of a scan from the start of the text.
//!
//! Every diagnostic shows a line and column; finding them by counting from
//! the start makes a report over many problems cost the number of
//! problems times the size of the file. A [`LineIndex`] is built once per
//! text (one pass) and answers each lookup in logarithmic time, and a
//! column in characters with a scan of at most [`CHECKPOINT_BYTES`].
//! Lines end at `\n` (a `\r\n` ending is one line end), as in the human
//! renderer's snippets.

use crate::span::floor_char_boundary;

/// Bytes between the checkpoints that count the characters before them.
const CHECKPOINT_BYTES: usize = 4096;

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
    /// Index `text` in one pass.
    pub fn new(text: &str) -> LineIndex {
        let bytes = text.as_bytes();
        let mut starts = vec![0];
        starts.extend(
            bytes
                .iter()
                .enumerate()
                .filter(|&(_, &b)| b == b'\n')
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
