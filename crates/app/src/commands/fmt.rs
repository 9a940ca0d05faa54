//! `raytracer fmt`: rewrite scene text files in the canonical layout of
//! [`raytracer_scene::format`], each written atomically, or with `--check` list the
//! files that would change and write nothing.
//!
//! Folders are walked as `check` walks them ([`crate::discover`]): only
//! the files classified as scenes are formatted, and every other file is
//! named on stderr with the reason it was skipped, so prose beside the
//! scenes is never rewritten. `-` formats stdin to stdout. A file with
//! syntax errors (or that is not text) is never rewritten: its diagnostics
//! go to stderr and the command exits 1. A rewritten file keeps its
//! byte-order mark and `\r\n` line ends. JSON scenes have no layout of
//! ours to impose: one named is refused (exit 2), one found in a folder is
//! skipped; files that cannot be read exit 2.

use std::io::Write;
use std::path::Path;

use miette::Diagnostic;

use super::Outcome;
use crate::cli::FmtArgs;
use crate::discover::{discover, Found, Kind};
use raytracer_render::output::write_atomically;
use raytracer_scene::diagnostic::BoxedDiagnostic;
use raytracer_scene::diagnostic::{
    boxed, terminal_width, use_color, FileError, Report, Shown, SourceFile,
};
use raytracer_scene::escape::escape;
use raytracer_scene::format::format;
use raytracer_scene::frontend::{read_scene, Language, ReadSceneError};

/// A path `fmt` cannot format.
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum FmtError {
    #[error("cannot format `{path}`: expected scene text, found a JSON scene")]
    #[diagnostic(
        code(io::fmt_json),
        help("`fmt` lays out scene text; `convert --to json` prints JSON scenes")
    )]
    Json { path: String },
    #[error(transparent)]
    #[diagnostic(transparent)]
    Read(#[from] ReadSceneError),
    #[error(transparent)]
    #[diagnostic(code(io::fmt_write), help("the file is unchanged"))]
    Write(FileError),
    #[error(transparent)]
    #[diagnostic(code(io::write_stdout))]
    Stdout(FileError),
}

/// What formatting one file came to.
enum Formatted {
    Unchanged,
    Changed,
    SyntaxErrors,
}

/// Run `raytracer fmt`.
pub fn run(args: FmtArgs) -> Result<Outcome, BoxedDiagnostic> {
    let mut failed = false;
    // A file named on the command line that cannot be read: exit 2.
    let mut named_unreadable = false;
    for found in discover(&args.paths).found {
        let (path, named) = match found {
            Found::Scene { path, named } => (path, named),
            Found::Skipped { path, reason } => {
                sayln!(
                    "{}: skipped, not a scene: {}",
                    shown(&path),
                    escape(&reason)
                );
                continue;
            }
            Found::Unreadable(error) => {
                failed = true;
                sayln!("{:?}", miette::Report::new(Shown::new(&error, None)));
                continue;
            }
        };
        // A JSON scene a walk found has no layout of ours; one named on
        // the command line is refused below.
        if !named && Kind::of(&path) == Some(Kind::Json) {
            sayln!(
                "{}: skipped, a JSON scene (`fmt` lays out scene text)",
                shown(&path)
            );
            continue;
        }
        match format_file(&path, args.check) {
            Ok(Formatted::Unchanged) => {}
            Ok(Formatted::Changed) => {
                if args.check {
                    out!("{}\n", shown(&path))?;
                    failed = true;
                }
            }
            Ok(Formatted::SyntaxErrors) => failed = true,
            Err(error) => {
                failed = true;
                named_unreadable |= named;
                sayln!("{:?}", miette::Report::new(Shown::new(&error, None)));
            }
        }
    }
    Ok(if named_unreadable {
        Outcome::InputErrors
    } else if failed {
        Outcome::SceneErrors
    } else {
        Outcome::Success
    })
}

/// The path as messages show it, escaped for the terminal.
fn shown(path: &Path) -> String {
    if path == Path::new("-") {
        "<stdin>".to_string()
    } else {
        escape(&path.display().to_string()).into_owned()
    }
}

/// `formatted` with the conventions of `original` the layout does not
/// carry: a leading byte-order mark, and `\r\n` line ends when the
/// original's first line ends so (the formatter writes `\n`).
fn keep_conventions(original: &str, formatted: String) -> String {
    let crlf = original
        .find('\n')
        .is_some_and(|at| original[..at].ends_with('\r'));
    let formatted = if crlf {
        formatted.replace('\n', "\r\n")
    } else {
        formatted
    };
    if original.starts_with('\u{feff}') && !formatted.starts_with('\u{feff}') {
        format!("\u{feff}{formatted}")
    } else {
        formatted
    }
}

/// Format one file (or stdin to stdout), or with `check` only compare.
fn format_file(path: &Path, check: bool) -> Result<Formatted, FmtError> {
    let stdin = path == Path::new("-");
    let name = shown(path);
    let bytes = read_scene(path)?;
    if Language::of(path, &bytes) == Language::Json {
        return Err(FmtError::Json { path: name });
    }
    let dir = path.parent().unwrap_or(Path::new(""));
    let (source, utf8_error) = SourceFile::from_bytes(&name, dir, &bytes);
    let result = match utf8_error {
        Some(error) => Err(vec![error]),
        None => format(&source.text),
    };
    let formatted = match result {
        Ok(formatted) => keep_conventions(&source.text, formatted),
        Err(errors) => {
            let report = Report::new(source, boxed(errors));
            let stderr = std::io::stderr();
            say!(
                "{}",
                report.render_human(terminal_width(), use_color(&stderr))
            );
            sayln!("{name}: not formatted: fix the syntax errors first");
            return Ok(Formatted::SyntaxErrors);
        }
    };
    let changed = *formatted != *source.text;
    if stdin && !check {
        let mut stdout = std::io::stdout().lock();
        stdout
            .write_all(formatted.as_bytes())
            .and_then(|()| stdout.flush())
            .map_err(|error| {
                FmtError::Stdout(FileError::new("write to", Path::new("stdout"), &error))
            })?;
    } else if changed && !check {
        write_atomically(path, |out| out.write_all(formatted.as_bytes()))
            .map_err(FileError::writing(path))
            .map_err(FmtError::Write)?;
    }
    Ok(if changed {
        Formatted::Changed
    } else {
        Formatted::Unchanged
    })
}
