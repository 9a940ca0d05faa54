//! Syntax errors: problems found while reading tokens, before any meaning is
//! attached to them. One variant per problem; each has a stable code under
//! `syntax::` and a label on the offending bytes (but for a file that is not
//! text at all).

use miette::{Diagnostic, SourceSpan};
use thiserror::Error;

use crate::fix::Fix;

/// A problem in the token stream of a scene file.
#[derive(Clone, Debug, Error, Diagnostic, PartialEq, Eq, strum::VariantNames)]
#[strum(serialize_all = "snake_case")]
pub enum SyntaxError {
    /// Fires when the file's bytes are not UTF-8; the parser continues on a
    /// lossy decoding so later problems are still reported.
    #[error("the file is not valid UTF-8")]
    #[diagnostic(
        code(syntax::invalid_utf8),
        help("save the file as UTF-8; the invalid bytes were read as `\u{FFFD}`")
    )]
    InvalidUtf8 {
        #[label("invalid byte sequence")]
        span: SourceSpan,
    },

    /// Fires when the file is not text in UTF-8 (see [`crate::encoding`]):
    /// UTF-16 or UTF-32 text, or a binary file. The file is not parsed, so
    /// this is its only diagnostic; it is about the whole file and has no
    /// label.
    #[error("expected scene text in UTF-8, found {found}")]
    #[diagnostic(code(syntax::not_text), help("{help}"))]
    NotText { found: String, help: &'static str },

    /// Fires when a token starts like a number (a digit, a sign or a `.`) but
    /// is not one, such as `1.2.3`, `1,5` or `-x`.
    #[error("expected a number, found `{found}`")]
    #[diagnostic(
        code(syntax::invalid_number),
        help("numbers look like `1`, `-1`, `.5`, `1.`, `+2`, `1e3` or `1.5E-2`")
    )]
    InvalidNumber {
        found: String,
        #[label("not a number")]
        span: SourceSpan,
    },

    /// Fires on `nan`, `inf`, `infinity` (any case, any sign) in value position.
    #[error("expected a finite number, found `{found}`")]
    #[diagnostic(
        code(syntax::non_finite_number),
        help("scene values must be finite numbers")
    )]
    NonFiniteNumber {
        found: String,
        #[label("not finite")]
        span: SourceSpan,
    },

    /// Fires when a well-formed number is too large for a 64-bit float, such
    /// as `1e400`.
    #[error("number `{found}` is out of range")]
    #[diagnostic(
        code(syntax::number_out_of_range),
        help("the largest finite value is about `1.7976931348623157e308`")
    )]
    NumberOutOfRange {
        found: String,
        #[label("overflows a 64-bit float")]
        span: SourceSpan,
    },

    /// Fires when a `"` opens a string that no `"` closes on the same line.
    #[error("unterminated string")]
    #[diagnostic(
        code(syntax::unterminated_string),
        help("close the string with `\"` before the end of the line")
    )]
    UnterminatedString {
        #[label("string starts here")]
        span: SourceSpan,
    },

    /// Fires when values appear before the first section keyword.
    #[error("expected a section keyword, found `{found}`")]
    #[diagnostic(
        code(syntax::value_outside_section),
        help("start a section first: `camera`, `sphere`, `plane` or `light`")
    )]
    ValueOutsideSection {
        found: String,
        #[label("not inside any section")]
        span: SourceSpan,
    },

    /// Fires on numbers joined by commas where the attribute takes that
    /// many values, such as `center 0,0,-5`: values are separated by spaces.
    #[error("expected values separated by spaces, found `{found}`")]
    #[diagnostic(code(syntax::comma_separated_values))]
    CommaSeparatedValues {
        found: String,
        #[label("separated by commas")]
        span: SourceSpan,
        #[help]
        help: String,
        /// The values separated by spaces (safe: the arity says so).
        fix: Option<Box<Fix>>,
    },

    /// Fires on a number written with a decimal comma where the attribute's
    /// arity rules out two values, such as `reflectivity 0,5`.
    #[error("expected a decimal point, found a decimal comma in `{found}`")]
    #[diagnostic(code(syntax::decimal_comma))]
    DecimalComma {
        found: String,
        #[label("decimal comma")]
        span: SourceSpan,
        #[help]
        help: String,
        /// The number with a decimal point (safe: the arity says so).
        fix: Option<Box<Fix>>,
    },

    /// Fires on punctuation around an attribute's values, as other
    /// languages write them: `dimension = 1`, `center (0, 0, -5)`,
    /// `color [1, 0, 0]`, `location 0 5 0;`, `normal: 0 1 0`. The values
    /// are read as meant, so nothing else is reported about the line.
    #[error("expected values separated by spaces, found {found}")]
    #[diagnostic(code(syntax::punctuation))]
    Punctuation {
        /// The punctuation, each mark once, in backticks.
        found: String,
        #[label("not part of the scene language")]
        span: SourceSpan,
        #[help]
        help: String,
        /// The values as written, separated by spaces (safe: each value
        /// is kept, only the punctuation goes).
        fix: Option<Box<Fix>>,
    },

    /// Fires on a keyword written in another case, such as `Camera 400`
    /// or `SPHERE`: keywords are lowercase. The word is read as the
    /// keyword, so nothing else is reported about it.
    #[error("expected `{expected}`, found `{found}`")]
    #[diagnostic(code(syntax::keyword_case))]
    KeywordCase {
        found: String,
        expected: String,
        #[label("keywords are lowercase")]
        span: SourceSpan,
        #[help]
        help: String,
        /// The keyword in lowercase (safe: it is the only keyword the
        /// word can be).
        fix: Option<Box<Fix>>,
    },
}

impl SyntaxError {
    /// The structured fix this diagnostic carries, if any.
    pub fn fix(&self) -> Option<&Fix> {
        match self {
            SyntaxError::CommaSeparatedValues { fix, .. }
            | SyntaxError::DecimalComma { fix, .. }
            | SyntaxError::Punctuation { fix, .. }
            | SyntaxError::KeywordCase { fix, .. } => fix.as_deref(),
            _ => None,
        }
    }

    /// Every code this enum can produce: `syntax::` and each variant's name
    /// in snake case, which is what each variant's `code(...)` says (the
    /// UI fixtures, one per code, check that).
    pub fn codes() -> Vec<String> {
        use strum::VariantNames;
        Self::VARIANTS
            .iter()
            .map(|v| format!("syntax::{v}"))
            .collect()
    }
}
