//! The applications over the scene language and the renderer: the
//! command line ([`cli`] defines it, [`commands`] runs it), the language
//! server ([`lsp`]), the live preview ([`preview`], opened in a browser by
//! [`browser`]), image comparison
//! ([`compare`]), grading students' tracers ([`grade`]), the accuracy
//! report ([`accuracy`], with [`plot`]'s charts), the CI formats ([`ci`])
//! and the folder walk of `check DIR` ([`discover`]).
//!
//! Only this crate depends on argument parsing, servers, terminals and
//! the C++ of ꟻLIP; the `raytracer` binary is a thin `main` over it.
//! Grading's system calls are the box's ([`raytracer_box`]): this crate
//! has no `unsafe` code.

#![forbid(unsafe_code)]

pub mod accuracy;
pub mod browser;
pub mod ci;
pub mod cli;
pub mod commands;
pub mod compare;
pub mod discover;
#[cfg(unix)]
pub mod grade;
pub mod lsp;
pub mod plot;
pub mod preview;
