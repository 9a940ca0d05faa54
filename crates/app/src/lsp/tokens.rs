//! Semantic tokens: what each piece of a scene is, for the client to colour.
//!
//! The tokens come from the syntax tree the formatter lays out (section
//! keywords, attribute names, values) and the comments [`syntax::trivia`]
//! finds beside it, so the colours follow the parser exactly: a word is a
//! keyword only where the parser read a section from it. The legend uses
//! the protocol's standard token types (`keyword`, `property`, `number`,
//! `string`, `comment`), which themes colour without configuration, and one
//! modifier of its own, `invalid`, on every token that an error's primary
//! label covers (an unknown attribute, a number out of range, an
//! unterminated string): the same errors the diagnostics show.
//!
//! Positions are the protocol's: lines and UTF-16 columns through
//! [`Positions`]. No token spans lines (comments, words and strings end at
//! a line end), so each is one `(line, column, length)`.

use lsp_types::{
    Position, Range, SemanticToken, SemanticTokenModifier, SemanticTokenType, SemanticTokens,
    SemanticTokensLegend,
};

use super::position::Positions;
use raytracer_scene::ast::Value;
use raytracer_scene::span::Span;
use raytracer_scene::syntax;

/// What a token is, in the order of [`legend`]'s token types.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Keyword,
    Property,
    Number,
    Str,
    Comment,
}

const TYPES: [SemanticTokenType; 5] = [
    SemanticTokenType::KEYWORD,
    SemanticTokenType::PROPERTY,
    SemanticTokenType::NUMBER,
    SemanticTokenType::STRING,
    SemanticTokenType::COMMENT,
];

/// The modifier on tokens an error points at (bit 0 of the modifier set).
const INVALID: SemanticTokenModifier = SemanticTokenModifier::new("invalid");

/// The token types and modifiers the server's tokens index into.
pub fn legend() -> SemanticTokensLegend {
    SemanticTokensLegend {
        token_types: TYPES.to_vec(),
        token_modifiers: vec![INVALID],
    }
}

/// The tokens of `text` within `within` (the whole text when `None`), delta
/// encoded as the protocol wants. `errors` are the ranges errors point at.
pub fn tokens(text: &str, errors: &[Range], within: Option<Range>) -> SemanticTokens {
    let index = Positions::new(text);
    let mut data = Vec::new();
    let mut previous = Position::new(0, 0);
    for (span, kind) in classify(text) {
        let range = index.range(span);
        let outside = within.is_some_and(|w| range.end <= w.start || range.start >= w.end);
        if outside || range.start.line != range.end.line {
            continue;
        }
        let invalid = errors
            .iter()
            .any(|e| e.start <= range.start && range.end <= e.end);
        let delta_line = range.start.line - previous.line;
        let delta_start = if delta_line == 0 {
            range.start.character - previous.character
        } else {
            range.start.character
        };
        data.push(SemanticToken {
            delta_line,
            delta_start,
            length: range.end.character - range.start.character,
            token_type: kind as u32,
            token_modifiers_bitset: u32::from(invalid),
        });
        previous = range.start;
    }
    SemanticTokens {
        result_id: None,
        data,
    }
}

/// Every token of `text` with what it is, in source order.
fn classify(text: &str) -> Vec<(Span, Kind)> {
    let value_kind = |value: &Value, span: Span| match value {
        Value::Number(_) => Kind::Number,
        Value::Text(_) => Kind::Str,
        // A malformed number or an unterminated string, kept in place.
        Value::Invalid if text[span.start()..].starts_with('"') => Kind::Str,
        Value::Invalid => Kind::Number,
    };
    let mut found = Vec::new();
    for section in syntax::parse(text).file.sections {
        found.push((section.kind.span, Kind::Keyword));
        found.extend(section.args.iter().map(|v| (v.span, value_kind(v, v.span))));
        for attribute in &section.attributes {
            found.push((attribute.name.span, Kind::Property));
            found.extend(
                attribute
                    .values
                    .iter()
                    .map(|v| (v.span, value_kind(v, v.span))),
            );
        }
    }
    found.extend(
        syntax::trivia::comments(text)
            .into_iter()
            .map(|span| (span, Kind::Comment)),
    );
    found.sort_by_key(|(span, _)| span.start());
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tokens as absolute `line:column:length type`, with ` invalid`
    /// where the modifier is set, separated by commas.
    fn listed(text: &str, errors: &[Range]) -> String {
        let mut line = 0;
        let mut column = 0;
        let listed: Vec<String> = tokens(text, errors, None)
            .data
            .iter()
            .map(|t| {
                if t.delta_line > 0 {
                    column = 0;
                }
                line += t.delta_line;
                column += t.delta_start;
                let kind = &TYPES[t.token_type as usize];
                let invalid = if t.token_modifiers_bitset == 1 {
                    " invalid"
                } else {
                    ""
                };
                format!("{line}:{column}:{} {}{invalid}", t.length, kind.as_str())
            })
            .collect();
        listed.join(", ")
    }

    #[test]
    fn keywords_properties_values_and_comments_in_order() {
        let text = "# top\nsphere center 0 0 -5 # c\n  texture \"a b.ppm\" texture wood.ppm\n";
        assert_eq!(
            listed(text, &[]),
            "0:0:5 comment, 1:0:6 keyword, 1:7:6 property, 1:14:1 number, 1:16:1 number, \
             1:18:2 number, 1:21:3 comment, 2:2:7 property, 2:10:9 string, 2:20:7 property, \
             2:28:8 string"
        );
    }

    #[test]
    fn malformed_values_keep_their_kind_and_errors_mark_what_they_cover() {
        let text = "sphere center 1e999 \"open\n";
        let error = Range::new(Position::new(0, 14), Position::new(0, 19));
        assert_eq!(
            listed(text, &[error]),
            "0:0:6 keyword, 0:7:6 property, 0:14:5 number invalid, 0:20:5 string"
        );
    }

    #[test]
    fn a_range_keeps_the_tokens_that_touch_it() {
        let text = "camera 4\nsphere center 0 0 0\nlight\n";
        let within = Range::new(Position::new(1, 3), Position::new(1, 15));
        let kept = tokens(text, &[], Some(within)).data;
        // `sphere`, `center` and the first `0`, the first relative to 0:0.
        let starts: Vec<_> = kept.iter().map(|t| (t.delta_line, t.delta_start)).collect();
        assert_eq!(starts, [(1, 0), (0, 7), (0, 7)]);
    }
}
