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

/// What kind of byte each byte is, as bits ([`CLASSES`]): the word,
/// number and trivia scanners look a byte up once and learn what they ask.
const SPACE: u8 = 1;
/// `#` and `"`: not word characters, and not trivia either.
const DELIMITER: u8 = 2;
/// Any byte of a non-ASCII character: the general rule decides.
const WIDE: u8 = 4;
/// Every ASCII word character.
const WORD: u8 = 8;
/// The classes that end an ASCII word.
const WORD_END: u8 = SPACE | DELIMITER | WIDE;

/// The class of every byte. The ASCII spaces are those of
/// `char::is_whitespace` on ASCII: tab, line feed, vertical tab, form feed,
/// carriage return and space.
static CLASSES: [u8; 256] = {
    let mut classes = [WORD; 256];
    let mut b = 0;
    while b < 256 {
        classes[b] = match b as u8 {
            b'\t' | b'\n' | 0x0b | 0x0c | b'\r' | b' ' => SPACE,
            b'#' | b'"' => DELIMITER,
            0x80..=0xff => WIDE,
            _ => WORD,
        };
        b += 1;
    }
    classes
};

fn class(b: u8) -> u8 {
    CLASSES[usize::from(b)]
}

/// How many leading bytes of `text` are trivia made only of ASCII: spaces
/// and comments whose line ends in `\n` or `\r` (or the input). It stops at
/// the first byte that starts a token, and before a comment holding any
/// non-ASCII byte (its line may end at U+0085, U+2028 or U+2029), or at a
/// non-ASCII space, which the general rule then reads.
pub fn ascii_trivia(text: &[u8]) -> usize {
    let mut at = 0;
    while let Some(&b) = text.get(at) {
        if class(b) == SPACE {
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
    if class(*text.first()?) & WORD_END != 0 {
        return None;
    }
    let mut len = 1;
    while let Some(&b) = text.get(len) {
        let class = class(b);
        if class & WORD_END != 0 {
            if class == WIDE {
                return None;
            }
            break;
        }
        len += 1;
    }
    Some(len)
}

/// The most digits whose value is exact in an `f64` mantissa whatever
/// they are (10^15 < 2^53).
const EXACT_DIGITS: usize = 15;

/// 10^0 to 10^15, each exact in an `f64`.
const POWERS_OF_TEN: [f64; EXACT_DIGITS + 1] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
];

/// The word at the start of `text` when it is a plain decimal number,
/// `[sign] digits [. digits]` with either digit run possibly empty but not
/// both (the common case of the `number` rule, without an exponent), of
/// finite value, ending where an ASCII word ends (an ASCII space, `#`, `"`
/// or the input): its length and value, read in one pass. `None` for any
/// other word, and for a plain decimal beyond `f64`'s range (over 308
/// digits): the caller then reads the word by the general rules, which
/// say why it is not a number.
///
/// The digits are read into an integer as they are scanned. Up to 15 of
/// them, the value is that integer divided by a power of ten, both exact
/// in an `f64`, so the one division rounds correctly (Clinger's fast path,
/// which `str::parse` takes for these too): bit for bit `str::parse`'s
/// value. A longer number goes to `fast_float2`, the algorithm
/// `str::parse` is built on without its checks of forms a plain decimal
/// cannot take. Inlined into the cursor's loop over values, its one
/// caller: most of a large scene's bytes pass through it.
#[inline]
pub fn plain_decimal(text: &[u8]) -> Option<(usize, f64)> {
    let (negative, mut len) = match text.first() {
        Some(b'-') => (true, 1),
        Some(b'+') => (false, 1),
        _ => (false, 0),
    };
    let mut mantissa: u64 = 0;
    let mut digits = 0;
    // How many digits came before the point, once it came.
    let mut point = None;
    while let Some(&b) = text.get(len) {
        let digit = b.wrapping_sub(b'0');
        if digit < 10 {
            // Wraps only past 19 digits, which take the general path.
            mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(digit));
            digits += 1;
        } else if b == b'.' && point.is_none() {
            point = Some(digits);
        } else if class(b) & (SPACE | DELIMITER) != 0 {
            break;
        } else {
            return None;
        }
        len += 1;
    }
    if digits == 0 {
        return None;
    }
    if digits > EXACT_DIGITS {
        return fast_float2::parse(&text[..len])
            .ok()
            .filter(|value: &f64| value.is_finite())
            .map(|value| (len, value));
    }
    let fraction_digits = point.map_or(0, |before| digits - before);
    // Exact integer over exact power: one correctly rounded division.
    let magnitude = mantissa as f64 / POWERS_OF_TEN[fraction_digits];
    Some((len, if negative { -magnitude } else { magnitude }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The value of `word` when all of it is one plain decimal.
    fn plain_decimal_value(word: &[u8]) -> Option<f64> {
        plain_decimal(word)
            .filter(|&(len, _)| len == word.len())
            .map(|(_, value)| value)
    }

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

    #[test]
    fn plain_decimals_end_where_ascii_words_end() {
        assert_eq!(plain_decimal(b"1.5 2"), Some((3, 1.5)));
        assert_eq!(plain_decimal(b"-2\n"), Some((2, -2.0)));
        assert_eq!(plain_decimal(b"7#note"), Some((1, 7.0)));
        assert_eq!(plain_decimal(b"3\"x\""), Some((1, 3.0)));
        assert_eq!(plain_decimal(b"1e3 "), None);
        assert_eq!(plain_decimal(b"12x"), None);
        assert_eq!(plain_decimal(b"1\xc2\xa0"), None);
        assert_eq!(plain_decimal(b"1,2"), None);
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
            if matches!(super::super::number(&word), Ok(("", _))) {
                let std = word.parse::<f64>().unwrap();
                match plain_decimal_value(word.as_bytes()) {
                    Some(fast) => proptest::prop_assert_eq!(fast.to_bits(), std.to_bits(), "{}", word),
                    None => proptest::prop_assert!(false, "the fast parser declined {}", word),
                }
            }
        }

        /// On any word of signs, points and digits, the fast parser
        /// answers exactly when the grammar reads a number, and then
        /// with `str::parse`'s value.
        #[test]
        fn plain_decimal_values_only_for_numbers(word in "[-+.0-9]{0,24}") {
            let grammar = matches!(super::super::number(&word), Ok(("", _)));
            match plain_decimal_value(word.as_bytes()) {
                Some(fast) => {
                    proptest::prop_assert!(grammar, "{}", word);
                    proptest::prop_assert_eq!(fast.to_bits(), word.parse::<f64>().unwrap().to_bits(), "{}", word);
                }
                None => proptest::prop_assert!(!grammar, "the fast parser declined {}", word),
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
        assert_eq!(plain_decimal_value(past_the_range.as_bytes()), None);
    }

    #[test]
    fn plain_decimals() {
        for yes in ["0", "-1", "+2", ".5", "-.5", "1.", "12.25"] {
            assert!(plain_decimal_value(yes.as_bytes()).is_some(), "{yes}");
        }
        for no in [
            "", "+", ".", "-.", "1e3", "1.2.3", "1-", "inf", "0x1", "+-1", "1+", "..5", "-1.5x",
        ] {
            assert_eq!(plain_decimal_value(no.as_bytes()), None, "{no}");
        }
    }
}
