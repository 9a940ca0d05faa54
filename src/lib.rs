//! `raytracer`: a Whitted ray tracer and a compiler-grade toolchain for its
//! scene language.
//!
//! The pipeline, one module per stage:
//! [`syntax`] (text → [`ast`], with every syntax error) →
//! [`check`] (AST → validated [`model`] scene, with every diagnostic) →
//! [`ir`] (model → render IR; lowering cannot fail) →
//! [`render`] (IR → image and statistics) → [`output`] (image → file).
//! [`commands`] runs them for the command line defined in [`cli`].

pub mod ast;
pub mod check;
pub mod cli;
pub mod commands;
pub mod diagnostic;
pub mod ir;
pub mod limits;
pub mod model;
pub mod output;
pub mod render;
pub mod span;
pub mod suggest;
pub mod syntax;
pub mod texture;
