//! Trivia the syntax tree leaves out: the spans of comments.
//!
//! The parser skips comments (they mean nothing), so the tree has no place
//! for them. A tool that rewrites the text (the formatter) needs them back,
//! as rust-analyzer and ruff keep them: [`comments`] lexes the text with the
//! same token rules the parser uses and returns every comment's span, in
//! order, to be attached beside the nodes of the tree by position.

use nom::Offset;

use super::{comment, rest_of_line, string, whitespace, word};
use crate::span::Span;

/// The span of every comment in `text` (from `#` to the end of its line,
/// without the line end), in source order. A `#` inside a string is no
/// comment, as for the parser.
pub fn comments(text: &str) -> Vec<Span> {
    let mut found = Vec::new();
    let mut rest = text;
    while !rest.is_empty() {
        let start = text.offset(rest);
        rest = if let Ok((after, _)) = whitespace(rest) {
            after
        } else if let Ok((after, _)) = comment(rest) {
            found.push(Span::new(start, text.offset(after)));
            after
        } else {
            match string(rest) {
                Ok((after, _)) => after,
                // An unterminated string runs to the end of its line.
                Err(nom::Err::Failure(_)) => rest_of_line(rest).map_or("", |(after, _)| after),
                Err(_) => match word(rest) {
                    Ok((after, _)) => after,
                    Err(_) => &rest[rest.chars().next().map_or(rest.len(), char::len_utf8)..],
                },
            }
        };
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(text: &str) -> Vec<&str> {
        comments(text)
            .iter()
            .map(|s| &text[s.start()..s.end()])
            .collect()
    }

    #[test]
    fn finds_comments_but_not_hashes_in_strings() {
        let text = "# head\ncamera 4 # four\nsphere texture \"a#b.ppm\" #tail\r\n\"open # x\n#last";
        assert_eq!(texts(text), ["# head", "# four", "#tail", "#last"]);
    }
}
