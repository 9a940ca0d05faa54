//! `raytracer`: a Whitted ray tracer and a compiler-grade toolchain for its
//! scene language.
//!
//! The pipeline, one module per stage:
//! [`syntax`] (text → [`ast`], with every syntax error; [`json`] reads JSON
//! scenes into the same tree) →
//! [`check`] (AST → validated [`model`] scene, with every diagnostic) →
//! [`ir`] (model → render IR; lowering cannot fail) →
//! [`render`] (IR → image and statistics) → [`output`] (image → file).
//! [`convert`] prints a checked model as JSON, canonical scene text or
//! POV-Ray; [`format`] lays out scene text with its comments. [`tile`]
//! cuts a frame into parts rendered apart and stitches them back.
//! [`compare`] measures how an image differs from a reference, and
//! [`grade`] runs a student's tracer on a suite of scenes against ours.
//! [`accuracy`] measures what each accuracy setting of the renderer costs
//! and buys for a scene. [`ci`] lays diagnostics out for CI services
//! (SARIF, GitHub workflow commands). [`frontend`] drives the stages from
//! bytes to a checked scene for every caller; [`lsp`] serves them to
//! editors and [`preview`] to a browser page; [`commands`] runs them for
//! the command line defined in [`cli`], and nothing below that layer
//! imports it.

pub mod accuracy;
pub mod ast;
pub mod check;
pub(crate) mod ci;
pub mod cli;
pub mod commands;
pub mod compare;
pub mod convert;
pub mod diagnostic;
pub mod discover;
pub mod encoding;
pub mod escape;
pub mod fix;
pub mod format;
pub mod frontend;
pub mod geometry;
#[cfg(unix)]
pub mod grade;
pub mod ir;
pub mod json;
pub mod language;
pub mod limits;
pub mod line_index;
pub mod lsp;
pub mod model;
pub mod output;
pub mod plot;
pub mod preview;
pub mod render;
pub mod span;
pub(crate) mod suggest;
pub mod syntax;
pub mod texture;
pub mod tile;
