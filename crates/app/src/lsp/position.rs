//! Byte offsets in a document and the positions of the Language Server
//! Protocol: zero-based lines (ended by `\n`, `\r\n` or `\r`, as the
//! protocol says) and columns in UTF-16 code units (its default encoding),
//! through the language's one [`LineIndex`].

use lsp_types::{Position, Range};

use raytracer_scene::line_index::{LineEnds, LineIndex};
use raytracer_scene::span::Span;

/// A text's [`LineIndex`] with the protocol's line ends, for converting
/// both ways.
pub struct Positions<'a> {
    text: &'a str,
    index: LineIndex,
}

impl<'a> Positions<'a> {
    pub fn new(text: &'a str) -> Positions<'a> {
        Positions {
            text,
            index: LineIndex::with_line_ends(text, LineEnds::Any),
        }
    }

    /// The position of byte `offset` (clamped to the text, and back to a
    /// character boundary).
    pub fn position(&self, offset: usize) -> Position {
        let (line, column) = self.index.utf16_position(self.text, offset);
        Position::new(line as u32, column as u32)
    }

    pub fn range(&self, span: Span) -> Range {
        Range::new(self.position(span.start()), self.position(span.end()))
    }

    /// The byte offset of `position` ([`LineIndex::utf16_offset`] says
    /// where one past a line or the text lands).
    pub fn offset(&self, position: Position) -> usize {
        self.index.utf16_offset(
            self.text,
            position.line as usize,
            position.character as usize,
        )
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
        let index = Positions::new(text);
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
