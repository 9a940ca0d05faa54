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

/// Powers of ten that `f64` holds exactly: 10⁰ to 10²².
const EXACT_POWERS_OF_TEN: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// The value of a plain decimal (see [`is_plain_decimal`]) when it has at
/// most 15 digits, else `None` (the caller then asks `str::parse`).
///
/// This is Clinger's fast path, the first step of Rust's own parser: the
/// digits without the point are an integer below 10¹⁵ < 2⁵³, so exact as
/// an `f64`, and so is 10ᵏ for the k ≤ 15 digits after the point; one
/// IEEE division of two exact values is correctly rounded, so the result
/// is bit for bit what `str::parse::<f64>` returns (the sign, `-0`
/// included, is applied exactly). It skips the general parser's
/// bookkeeping, which a scene of a million spheres pays ten million times.
pub fn plain_decimal_value(word: &[u8]) -> Option<f64> {
    let (negative, unsigned) = match word {
        [b'-', rest @ ..] => (true, rest),
        [b'+', rest @ ..] => (false, rest),
        _ => (false, word),
    };
    let mut digits: u64 = 0;
    let mut count = 0;
    let mut after_point = None;
    for (at, &b) in unsigned.iter().enumerate() {
        if b == b'.' {
            after_point = Some(unsigned.len() - at - 1);
            continue;
        }
        digits = digits * 10 + u64::from(b - b'0');
        count += 1;
        if count > 15 {
            return None;
        }
    }
    let magnitude = digits as f64 / EXACT_POWERS_OF_TEN[after_point.unwrap_or(0)];
    Some(if negative { -magnitude } else { magnitude })
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
        /// Bit for bit what `str::parse` gives, on plain decimals of up to
        /// 20 digits (beyond 15 the fast path must decline), any sign and
        /// any place of the point.
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
                    None => proptest::prop_assert!(digits.len() > 15, "{}", word),
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
        assert_eq!(plain_decimal_value(b"1234567890123456"), None);
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
