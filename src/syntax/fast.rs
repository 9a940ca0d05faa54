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

/// What kind of byte each byte is, as bits ([`CLASSES`]): the word and
/// trivia scanners look a byte up once and learn everything they ask.
const SPACE: u8 = 1;
/// `#` and `"`: not word characters, and not trivia either.
const DELIMITER: u8 = 2;
/// Any byte of a non-ASCII character: the general rule decides.
const WIDE: u8 = 4;
const DIGIT: u8 = 8;
const POINT: u8 = 16;
const SIGN: u8 = 32;
/// Every other ASCII word character.
const OTHER: u8 = 64;
/// The classes that end an ASCII word.
const WORD_END: u8 = SPACE | DELIMITER | WIDE;

/// The class of every byte. The ASCII spaces are those of
/// `char::is_whitespace` on ASCII: tab, line feed, vertical tab, form feed,
/// carriage return and space.
static CLASSES: [u8; 256] = {
    let mut classes = [OTHER; 256];
    let mut b = 0;
    while b < 256 {
        classes[b] = match b as u8 {
            b'\t' | b'\n' | 0x0b | 0x0c | b'\r' | b' ' => SPACE,
            b'#' | b'"' => DELIMITER,
            b'0'..=b'9' => DIGIT,
            b'.' => POINT,
            b'+' | b'-' => SIGN,
            0x80..=0xff => WIDE,
            _ => OTHER,
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

/// An all-ASCII `word` found by [`ascii_word`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AsciiWord {
    pub len: usize,
    /// True when the word is a plain decimal number, `[sign] digits [.
    /// digits]` with either digit run possibly empty but not both: the
    /// common case of the `number` rule, without an exponent. False says
    /// nothing (the word may still be a number with an exponent, or no
    /// number at all).
    pub plain_decimal: bool,
}

/// The `word` at the start of `text` when it is all ASCII and ends at an
/// ASCII byte (or the input), read in one pass that also tells whether it
/// is a plain decimal; `None` when it is empty or meets a non-ASCII byte,
/// which may be a word or a space character.
pub fn ascii_word(text: &[u8]) -> Option<AsciiWord> {
    let first = class(*text.first()?);
    if first & WORD_END != 0 {
        return None;
    }
    // The classes seen after the first byte, and the points among them.
    let mut after_first = 0;
    let mut points = u32::from(first == POINT);
    let mut len = 1;
    while let Some(&b) = text.get(len) {
        let class = class(b);
        if class & WORD_END != 0 {
            if class == WIDE {
                return None;
            }
            break;
        }
        after_first |= class;
        points += u32::from(class == POINT);
        len += 1;
    }
    let plain_decimal = first & (DIGIT | POINT | SIGN) != 0
        && after_first & !(DIGIT | POINT) == 0
        && points <= 1
        && (first | after_first) & DIGIT != 0;
    Some(AsciiWord { len, plain_decimal })
}

/// The value of a plain decimal (see [`AsciiWord::plain_decimal`]), or `None`
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

    /// True when all of `word` is one word the scanner calls a plain
    /// decimal.
    fn is_plain_decimal(word: &[u8]) -> bool {
        ascii_word(word).is_some_and(|found| found.len == word.len() && found.plain_decimal)
    }

    fn word_len(text: &[u8]) -> Option<usize> {
        ascii_word(text).map(|word| word.len)
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
        assert_eq!(word_len(b"center 0"), Some(6));
        assert_eq!(word_len(b"a#b"), Some(1));
        assert_eq!(word_len(b"x\"y"), Some(1));
        assert_eq!(word_len(b"tex"), Some(3));
        assert_eq!(word_len(b"caf\xc3\xa9 x"), None);
        assert_eq!(word_len(b" x"), None);
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
        for no in [
            "", "+", ".", "-.", "1e3", "1.2.3", "1-", "inf", "0x1", "+-1", "1+", "..5", "-1.5x",
        ] {
            assert!(!is_plain_decimal(no.as_bytes()), "{no}");
        }
    }
}
