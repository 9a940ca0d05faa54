//! The scene language: from bytes to a checked scene, with every problem
//! found on the way.
//!
//! [`syntax`] reads scene text into the lossless tree of [`ast`], with
//! every syntax error; [`json`] reads JSON scenes into the same tree.
//! [`check`] validates a tree against the rule registry of [`language`]
//! and builds the [`model`] scene, reading texture headers or images
//! through [`texture`]. [`frontend`] drives those stages for every caller.
//! Problems are [`diagnostic`]s, many with a [`fix`] (edits as data);
//! [`format`] lays scene text out with its comments kept, and [`convert`]
//! prints a model as JSON, canonical scene text or POV-Ray.
//!
//! Nothing here draws a pixel, parses a command line or serves a
//! protocol: the renderer (`raytracer-render`) and the applications
//! (`raytracer-app`) build on this crate, never the other way round.
//!
//! ```
//! use std::path::Path;
//! use raytracer_scene::fix::{self, Applicability};
//! use raytracer_scene::frontend;
//!
//! let text = "camera 4\nsphere\n  dimension 1\n  centre 0 0 -5\n";
//! let loaded = frontend::load_bytes("scene.txt", Path::new("."), text.as_bytes());
//! assert_eq!(loaded.report.error_count(), 1); // `centre`: did you mean `center`?
//!
//! let (fixed, _) = fix::apply(text, loaded.report.fixes_up_to(Applicability::Unsafe));
//! assert_eq!(fixed, "camera 4\nsphere\n  dimension 1\n  center 0 0 -5\n");
//! ```

#![forbid(unsafe_code)]

pub mod ast;
pub mod check;
pub mod convert;
pub mod diagnostic;
pub mod encoding;
pub mod escape;
pub mod failure;
pub mod fix;
pub mod folder;
pub mod format;
pub mod frontend;
pub mod geometry;
pub mod json;
pub mod language;
pub mod limits;
pub mod line_index;
pub mod model;
pub mod span;
pub mod suggest;
pub mod syntax;
pub mod texture;
