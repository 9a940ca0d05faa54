//! Printing a checked scene ([`crate::model::Scene`]) in the other
//! languages `raytracer convert` writes: the versioned JSON layout and its
//! JSON Schema ([`json`]), canonical scene text ([`scene_text`]) and a
//! POV-Ray 3.7 scene that renders the same picture ([`pov`]). Texture
//! paths are first rebased onto the output's folder ([`paths`]).
//!
//! Reading goes the other way through the front end (scene text through
//! [`crate::syntax`], JSON through [`crate::json`], both then through the
//! check pass), so a converted scene is always a checked one.

pub mod json;
pub mod paths;
pub mod pov;
pub mod scene_text;

use miette::Diagnostic;
use thiserror::Error;

/// A texture path that scene text has no way to write: it holds a line
/// break, which neither a bare path nor a quoted string may contain.
#[derive(Clone, Debug, Error, Diagnostic, PartialEq, Eq)]
#[error("texture path {path:?} cannot be written as scene text")]
#[diagnostic(
    code(convert::unprintable_path),
    help("scene text cannot hold a line break in a path; rename the image file")
)]
pub struct UnprintablePath {
    pub path: String,
}
