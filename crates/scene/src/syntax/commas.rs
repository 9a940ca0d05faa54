//! Commas in numbers, as students write them: `center 0,0,-5` (values
//! separated by commas) and `0,5` (a decimal comma). The parser reads
//! such a token as an invalid number; when the attribute's arity in the
//! registry says which of the two the author meant, the error is replaced
//! by one that names it, with a fix that writes the values as the language
//! reads them.

use crate::fix::{Applicability, Fix};
use crate::span::Span;

use super::errors::SyntaxError;
use super::number;

/// A token with a comma that the parser could not read as a number.
pub struct CommaToken<'a> {
    /// Where its `InvalidNumber` error is in the parser's list.
    pub error: usize,
    /// Where it is among the attribute's values.
    pub index: usize,
    pub span: Span,
    pub text: &'a str,
}

/// What the commas of an attribute's tokens were meant as.
#[derive(Debug, PartialEq, Eq)]
enum Reading {
    Separators,
    DecimalCommas,
}

/// The pieces of `text` between commas, without the empty one a trailing
/// comma leaves (`0,` is `0`), when each is a number.
fn pieces(text: &str) -> Option<Vec<&str>> {
    let text = text.strip_suffix(',').unwrap_or(text);
    let pieces: Vec<&str> = text.split(',').collect();
    pieces
        .iter()
        .all(|p| matches!(number(p), Ok(("", _))))
        .then_some(pieces)
}

/// True for `1,5` and `-0,25`: digits, one comma, digits.
fn is_decimal_comma(text: &str) -> bool {
    let unsigned = text.trim_start_matches(['+', '-']);
    match unsigned.split_once(',') {
        Some((whole, fraction)) => {
            !whole.is_empty()
                && !fraction.is_empty()
                && whole.bytes().all(|b| b.is_ascii_digit())
                && fraction.bytes().all(|b| b.is_ascii_digit())
        }
        None => false,
    }
}

/// The reading that gives the attribute `expected` values, given its
/// `found` value tokens of which `tokens` hold commas; `None` when neither
/// or both would.
fn reading(tokens: &[CommaToken<'_>], found: usize, expected: usize) -> Option<Reading> {
    let mut separated = found - tokens.len();
    for token in tokens {
        separated += pieces(token.text)?.len();
    }
    let decimal = found == expected && tokens.iter().all(|t| is_decimal_comma(t.text));
    match (separated == expected, decimal) {
        (true, false) => Some(Reading::Separators),
        (false, true) => Some(Reading::DecimalCommas),
        _ => None,
    }
}

/// Replace the `InvalidNumber` errors of `tokens` in `errors` with the
/// comma diagnostic the attribute's arity points to: `found` is how many
/// value tokens the attribute had, `expected` how many numbers it takes.
/// True when the commas separate values: each token then stands for as
/// many values as it has pieces ([`piece_count`]).
pub fn explain(
    tokens: &[CommaToken<'_>],
    found: usize,
    expected: Option<usize>,
    errors: &mut [SyntaxError],
) -> bool {
    let Some(reading) = expected.and_then(|expected| reading(tokens, found, expected)) else {
        return false;
    };
    for token in tokens {
        let Some(error) = errors.get_mut(token.error) else {
            continue;
        };
        let found = token.text.to_string();
        let span = token.span;
        *error = match reading {
            Reading::Separators => {
                let written = pieces(token.text).unwrap_or_default().join(" ");
                let fix = Fix::boxed(
                    format!("write `{written}`"),
                    Applicability::Safe,
                    span,
                    &written,
                );
                SyntaxError::CommaSeparatedValues {
                    found,
                    span: span.into(),
                    help: fix.message.clone(),
                    fix: Some(fix),
                }
            }
            Reading::DecimalCommas => {
                let written = token.text.replace(',', ".");
                let fix = Fix::boxed(
                    format!("write `{written}`"),
                    Applicability::Safe,
                    span,
                    &written,
                );
                SyntaxError::DecimalComma {
                    found,
                    span: span.into(),
                    help: fix.message.clone(),
                    fix: Some(fix),
                }
            }
        };
    }
    reading == Reading::Separators
}

/// How many values a token of values separated by commas stands for.
pub fn piece_count(text: &str) -> usize {
    pieces(text).map_or(1, |pieces| pieces.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn token(text: &str) -> CommaToken<'_> {
        CommaToken {
            error: 0,
            index: 0,
            span: Span::new(0, text.len()),
            text,
        }
    }

    #[test]
    fn the_arity_decides_between_separators_and_decimal_commas() {
        let read = |texts: &[&str], found, expected| {
            let tokens: Vec<_> = texts.iter().map(|t| token(t)).collect();
            reading(&tokens, found, expected)
        };
        assert_eq!(read(&["0,0,-5"], 1, 3), Some(Reading::Separators));
        assert_eq!(read(&["0,", "0,"], 3, 3), Some(Reading::Separators));
        assert_eq!(read(&["4,4"], 1, 2), Some(Reading::Separators));
        assert_eq!(read(&["0,5"], 1, 1), Some(Reading::DecimalCommas));
        assert_eq!(read(&["1,5", "2,5"], 3, 3), Some(Reading::DecimalCommas));
        assert_eq!(read(&["1,5"], 2, 2), Some(Reading::DecimalCommas));
        // `1,5 2` for four values: neither reading gives that many.
        assert_eq!(read(&["1,5"], 2, 4), None);
        assert_eq!(read(&["1,x"], 1, 2), None);
    }
}
