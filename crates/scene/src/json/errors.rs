//! Problems in a JSON scene's text and shape, found before any meaning is
//! attached to it: one variant per problem, each with a stable code under
//! `json::`, a label on the offending JSON text and the JSON Pointer
//! (RFC 6901, such as `/objects/2/normal`) of the value in its message.
//!
//! What the values mean (ranges, geometry, textures) is the check pass's
//! job, so those problems keep their `scene::` codes for JSON input too.

use miette::{Diagnostic, SourceSpan};
use thiserror::Error;

/// A problem in the text or the shape of a JSON scene.
#[derive(Clone, Debug, Error, Diagnostic, PartialEq, Eq, strum::VariantNames)]
#[strum(serialize_all = "snake_case")]
pub enum JsonError {
    /// Fires when the text is not valid JSON (RFC 8259): a missing comma or
    /// quote, a comment, a trailing comma, `NaN`, an empty file.
    #[error("invalid JSON: {message}")]
    #[diagnostic(
        code(json::syntax),
        help("JSON scenes are strict JSON: no comments, no trailing commas, numbers like `1`, `-0.5` or `1e3`")
    )]
    Syntax {
        message: String,
        #[label("here")]
        span: SourceSpan,
    },

    /// Fires when `format` names a layout version this build does not read.
    #[error("expected `{expected}` at `/format`, found `{found}`")]
    #[diagnostic(
        code(json::unsupported_format),
        help("this build reads scenes of format `{expected}` only; convert the scene with the version that wrote it")
    )]
    UnsupportedFormat {
        expected: String,
        found: String,
        #[label("unsupported format")]
        span: SourceSpan,
    },

    /// Fires when an object lacks required fields; one diagnostic per object
    /// lists them all.
    #[error("missing {names} at {place}")]
    #[diagnostic(code(json::missing_field))]
    MissingField {
        /// "`center`", "`center` and `radius`".
        names: String,
        /// "`/objects/0`", "the top level".
        place: String,
        #[label("this object needs {names}")]
        span: SourceSpan,
        #[help]
        help: String,
    },

    /// Fires on a field the object does not take.
    #[error("unknown field `{found}` at {place}")]
    #[diagnostic(code(json::unknown_field))]
    UnknownField {
        found: String,
        place: String,
        #[label("not a field of this object")]
        span: SourceSpan,
        #[help]
        help: String,
    },

    /// Fires when an object gives the same field twice (JSON allows it; the
    /// scene model does not).
    #[error("field `{name}` is given twice at {place}")]
    #[diagnostic(
        code(json::duplicate_field),
        help("remove one of the two `{name}` fields")
    )]
    DuplicateField {
        name: String,
        place: String,
        #[label("first given here")]
        first: SourceSpan,
        #[label("given again here")]
        second: SourceSpan,
    },

    /// Fires when a value has the wrong JSON type or length for its place in
    /// the schema: a string where a number belongs, two numbers where a
    /// vector needs three, an object `type` other than `sphere` or `plane`.
    #[error("expected {expected} at {place}, found {found}")]
    #[diagnostic(code(json::schema))]
    Schema {
        /// "a number", "an array of 3 numbers".
        expected: String,
        place: String,
        /// "a string", "an array of 2 values".
        found: String,
        #[label("not {expected}")]
        span: SourceSpan,
        #[help]
        help: String,
    },
}

impl JsonError {
    /// Every code this enum can produce: `json::` and each variant's name
    /// in snake case, which is what each variant's `code(...)` says (the
    /// UI fixtures, one per code, check that).
    pub fn codes() -> Vec<String> {
        use strum::VariantNames;
        Self::VARIANTS
            .iter()
            .map(|v| format!("json::{v}"))
            .collect()
    }
}
