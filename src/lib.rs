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
//!
//! # The library
//!
//! The command line, the language server and what only they need (clap,
//! the progress bar, the charts, the folder walk, signal handling, the
//! preview server, image comparison and grading) are the
//! `cli` feature, on by default; with `default-features = false` the crate
//! is the front end ([`frontend`], [`syntax`], [`json`], [`check`],
//! [`diagnostic`], [`fix`]), the scene model and its conversions
//! ([`model`], [`convert`], [`format`]), the render IR ([`ir`]) and the
//! renderer ([`render`], [`output`], [`tile`]). A scene from text to pixels,
//! with the fix `check` offers applied on the way:
//!
//! ```
//! use std::path::Path;
//! use std::time::Instant;
//! use raytracer::fix::{self, Applicability};
//! use raytracer::{frontend, ir, render};
//!
//! let text = "camera 4\nsphere\n  dimension 1\n  centre 0 0 -5\n";
//! let loaded = frontend::load_bytes("scene.txt", Path::new("."), text.as_bytes(), Instant::now());
//! assert_eq!(loaded.report.error_count(), 1); // `centre`: did you mean `center`?
//!
//! let (fixed, _) = fix::apply(text, loaded.report.fixes_up_to(Applicability::Unsafe));
//! assert_eq!(fixed, "camera 4\nsphere\n  dimension 1\n  center 0 0 -5\n");
//!
//! let loaded = frontend::load_bytes("scene.txt", Path::new("."), fixed.as_bytes(), Instant::now());
//! let scene = ir::lower(loaded.checked.expect("the fixed scene checks"));
//! let (image, _) = render::render::<f64>(&scene, &render::Options::default(), &|| ());
//! assert_eq!(image.rgb.len(), 4 * 4 * 3);
//! ```

#[cfg(feature = "cli")]
pub(crate) mod accuracy;
pub mod ast;
pub mod check;
#[cfg(feature = "cli")]
pub(crate) mod ci;
#[cfg(feature = "cli")]
pub mod cli;
#[cfg(feature = "cli")]
pub mod commands;
#[cfg(feature = "cli")]
pub mod compare;
pub mod convert;
pub mod diagnostic;
#[cfg(feature = "cli")]
pub mod discover;
pub mod encoding;
pub mod escape;
pub mod fix;
pub mod format;
pub mod frontend;
pub mod geometry;
#[cfg(all(unix, feature = "cli"))]
pub mod grade;
pub mod ir;
pub mod json;
pub mod language;
pub mod limits;
pub mod line_index;
#[cfg(feature = "cli")]
pub mod lsp;
pub mod model;
pub mod output;
#[cfg(feature = "cli")]
pub mod plot;
#[cfg(feature = "cli")]
pub mod preview;
pub mod render;
pub mod span;
pub(crate) mod suggest;
pub mod syntax;
pub mod texture;
pub mod tile;
