//! Byte-level fast paths for the common case of the lexical rules.
//!
//! A large scene is almost all ASCII: short runs of spaces and newlines,
//! attribute names and plain decimal numbers. The nom rules of the parent
//! module decode every character and test it against Unicode's White_Space
//! property, which costs more than the rest of the front end together. Each
//! function here reads bytes instead and answers only while the text stays
//! inside a subset it can decide exactly; at the first byte outside it (any
//! non-ASCII byte, an exponent) it stops and says how far it got, and the
//! caller hands the rest to the general nom rule. So the grammar is still
//! defined by the nom rules alone, and the tests in `parity.rs` check that
//! both routes give the same tree, spans and errors.

/// True for an ASCII byte that is a `space_char` (`char::is_whitespace`
/// on ASCII: tab, line feed, vertical tab, form feed, carriage return and
/// space).
fn is_ascii_space(b: u8) -> bool {
    matches!(b, b'\t' | b'\n' | 0x0b | 0x0c | b'\r' | b' ')
}

/// How many leading bytes of `text` are trivia made only of ASCII: spaces
/// and comments whose line ends in `\n` or `\r` (or the input). It stops at
/// the first byte that starts a token, and before a comment holding any
/// non-ASCII byte (its line may end at U+0085, U+2028 or U+2029), or at a
/// non-ASCII space, which the general rule then reads.
pub fn ascii_trivia(text: &[u8]) -> usize {
    let mut at = 0;
    while let Some(&b) = text.get(at) {
        if is_ascii_space(b) {
            at += 1;
        } else if b == b'#' {
            let line = &text[at..];
            let end = line
                .iter()
                .position(|&b| matches!(b, b'\n' | b'\r') || !b.is_ascii())
                .unwrap_or(line.len());
            if line.get(end).is_some_and(|b| !b.is_ascii()) {
                break;
            }
            at += end;
        } else {
            break;
        }
    }
    at
}

/// The length of the `word` at the start of `text` when it is all ASCII
/// and ends at an ASCII byte (or the input); `None` when it is empty or
/// meets a non-ASCII byte, which may be a word or a space character.
pub fn ascii_word(text: &[u8]) -> Option<usize> {
    let end = text
        .iter()
        .position(|&b| is_ascii_space(b) || matches!(b, b'#' | b'"') || !b.is_ascii())
        .unwrap_or(text.len());
    let stops_on_ascii = text.get(end).is_none_or(u8::is_ascii);
    (end > 0 && stops_on_ascii).then_some(end)
}

/// True when `word` is a plain decimal number, `[sign] digits [. digits]`
/// with either digit run possibly empty but not both: the common case of
/// the `number` rule, without an exponent. False says nothing (the word
/// may still be a number with an exponent, or no number at all).
pub fn is_plain_decimal(word: &[u8]) -> bool {
    let unsigned = match word {
        [b'+' | b'-', rest @ ..] => rest,
        _ => word,
    };
    let int = unsigned.iter().take_while(|b| b.is_ascii_digit()).count();
    let frac = match &unsigned[int..] {
        [] => return int > 0,
        [b'.', digits @ ..] => digits,
        _ => return false,
    };
    frac.iter().all(u8::is_ascii_digit) && int + frac.len() > 0
}

/// The value of a plain decimal (see [`is_plain_decimal`]), or `None`
/// when the fast parser declines or the value is beyond `f64`'s range (a
/// plain decimal of over 308 digits parses to infinity): the caller then
/// asks `str::parse` and reports the number out of range.
///
/// `fast_float2` implements the algorithm `str::parse` itself is built on
/// (Clinger's exact path, then Eisel–Lemire), so the value is bit for bit
/// the same; it skips the general parser's checks of forms a plain
/// decimal cannot take, which a scene of a million spheres pays ten
/// million times.
pub fn plain_decimal_value(word: &[u8]) -> Option<f64> {
    fast_float2::parse(word)
        .ok()
        .filter(|value: &f64| value.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trivia_stops_at_tokens_and_before_non_ascii() {
        assert_eq!(ascii_trivia(b"  \t\n# note\r\nsphere"), 12);
        assert_eq!(ascii_trivia(b" # caf\xc3\xa9\nx"), 1);
        assert_eq!(ascii_trivia(b" \xc2\xa0x"), 1);
        assert_eq!(ascii_trivia(b"# to the end"), 12);
        assert_eq!(ascii_trivia(b"\"s\""), 0);
    }

    #[test]
    fn words_end_at_ascii_delimiters_only() {
        assert_eq!(ascii_word(b"center 0"), Some(6));
        assert_eq!(ascii_word(b"a#b"), Some(1));
        assert_eq!(ascii_word(b"x\"y"), Some(1));
        assert_eq!(ascii_word(b"tex"), Some(3));
        assert_eq!(ascii_word(b"caf\xc3\xa9 x"), None);
        assert_eq!(ascii_word(b" x"), None);
    }

    proptest::proptest! {
        /// The fast parser answers every plain decimal, bit for bit as
        /// `str::parse` does, for up to 20 digits, any sign and any place
        /// of the point.
        #[test]
        fn plain_decimal_values_equal_std(
            sign in proptest::sample::select(vec!["", "-", "+"]),
            digits in "[0-9]{0,20}",
            point in proptest::option::of(0usize..21),
        ) {
            let mut word = digits.clone();
            if let Some(at) = point {
                word.insert(at.min(digits.len()), '.');
            }
            let word = format!("{sign}{word}");
            if is_plain_decimal(word.as_bytes()) {
                let std = word.parse::<f64>().unwrap();
                match plain_decimal_value(word.as_bytes()) {
                    Some(fast) => proptest::prop_assert_eq!(fast.to_bits(), std.to_bits(), "{}", word),
                    None => proptest::prop_assert!(false, "the fast parser declined {}", word),
                }
            }
        }
    }

    #[test]
    fn plain_decimal_values_at_the_edges() {
        for word in [
            "-0",
            "-0.0",
            "+0.",
            ".000000000000001",
            "999999999999999",
            "0.1",
            "-.035",
        ] {
            let fast = plain_decimal_value(word.as_bytes()).unwrap();
            assert_eq!(
                fast.to_bits(),
                word.parse::<f64>().unwrap().to_bits(),
                "{word}"
            );
        }
        let past_the_range = format!("1{}", "0".repeat(400));
        assert!(is_plain_decimal(past_the_range.as_bytes()));
        assert_eq!(plain_decimal_value(past_the_range.as_bytes()), None);
    }

    #[test]
    fn plain_decimals() {
        for yes in ["0", "-1", "+2", ".5", "-.5", "1.", "12.25"] {
            assert!(is_plain_decimal(yes.as_bytes()), "{yes}");
        }
        for no in ["", "+", ".", "-.", "1e3", "1.2.3", "1-", "inf", "0x1"] {
            assert!(!is_plain_decimal(no.as_bytes()), "{no}");
        }
    }
}
