//! Byte offsets in a document and the positions of the Language Server
//! Protocol: zero-based lines (ended by `\n`, `\r\n` or `\r`, as the
//! protocol says) and columns in UTF-16 code units (its default encoding).

use lsp_types::{Position, Range};

use crate::span::{floor_char_boundary, Span};

/// Where each line of a text starts, for converting both ways.
pub struct LineIndex<'a> {
    text: &'a str,
    starts: Vec<usize>,
}

impl<'a> LineIndex<'a> {
    pub fn new(text: &'a str) -> LineIndex<'a> {
        let mut starts = vec![0];
        let bytes = text.as_bytes();
        for (i, &b) in bytes.iter().enumerate() {
            let ends_line = b == b'\n' || (b == b'\r' && bytes.get(i + 1) != Some(&b'\n'));
            if ends_line {
                starts.push(i + 1);
            }
        }
        LineIndex { text, starts }
    }

    /// The position of byte `offset` (clamped to the text, and back to a
    /// character boundary).
    pub fn position(&self, offset: usize) -> Position {
        let offset = floor_char_boundary(self.text, offset);
        let line = self.starts.partition_point(|&s| s <= offset) - 1;
        let start = self.starts[line];
        let column = self.text[start..offset].encode_utf16().count();
        Position::new(line as u32, column as u32)
    }

    pub fn range(&self, span: Span) -> Range {
        Range::new(self.position(span.start()), self.position(span.end()))
    }

    /// The byte offset of `position`; a line past the end is the end of the
    /// text, a column past its line's end is that end (before its line
    /// end), and a column inside a surrogate pair is the end of that
    /// character.
    pub fn offset(&self, position: Position) -> usize {
        let Some(&start) = self.starts.get(position.line as usize) else {
            return self.text.len();
        };
        let end = self
            .starts
            .get(position.line as usize + 1)
            .copied()
            .unwrap_or(self.text.len());
        let mut units = 0;
        for (i, c) in self.text[start..end].char_indices() {
            if units >= position.character as usize || c == '\n' || c == '\r' {
                return start + i;
            }
            units += c.len_utf16();
        }
        end
    }

    /// The position just past the end of the text.
    pub fn end(&self) -> Position {
        self.position(self.text.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utf16_columns_and_every_line_end() {
        let text = "a\r\nb😀c\rd\ne";
        let index = LineIndex::new(text);
        assert_eq!(index.position(4), Position::new(1, 1));
        assert_eq!(index.position(8), Position::new(1, 3));
        assert_eq!(index.position(10), Position::new(2, 0));
        assert_eq!(index.position(12), Position::new(3, 0));
        for offset in [0, 3, 4, 8, 10, 12, text.len()] {
            assert_eq!(index.offset(index.position(offset)), offset);
        }
        assert_eq!(index.offset(Position::new(0, 99)), 1);
        assert_eq!(index.offset(Position::new(99, 0)), text.len());
        // Inside the surrogate pair: the character's start.
        assert_eq!(index.position(6), Position::new(1, 1));
        // A column inside the surrogate pair: the character's end.
        assert_eq!(index.offset(Position::new(1, 2)), 8);
    }
}
