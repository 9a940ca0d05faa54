//! `raytracer fmt`: rewrite scene text files in the canonical layout of
//! [`crate::format`], each written atomically, or with `--check` list the
//! files that would change and write nothing.
//!
//! Folders are searched (recursively) for `.txt` and `.scene` files; `-`
//! formats stdin to stdout. A file with syntax errors is never rewritten:
//! its diagnostics go to stderr and the command exits 1. JSON scenes have
//! no layout of ours to impose and are refused (exit 2), as are files that
//! cannot be read.

use std::io::Write;
use std::path::{Path, PathBuf};

use miette::Diagnostic;

use super::Outcome;
use crate::cli::FmtArgs;
use crate::diagnostic::BoxedDiagnostic;
use crate::diagnostic::{boxed, terminal_width, use_color, Report, SourceFile};
use crate::escape::escape;
use crate::format::format;
use crate::frontend::{read_scene, Language};
use crate::output::write_atomically;

/// A path `fmt` cannot format.
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum FmtError {
    #[error("cannot format `{path}`: expected scene text, found a JSON scene")]
    #[diagnostic(
        code(io::fmt_json),
        help("`fmt` lays out scene text; `convert --to json` prints JSON scenes")
    )]
    Json { path: String },
    #[error("cannot read `{path}`: {reason}")]
    #[diagnostic(code(io::fmt_read))]
    Read { path: String, reason: String },
    #[error("cannot write `{path}` (it is unchanged): {reason}")]
    #[diagnostic(code(io::fmt_write))]
    Write { path: String, reason: String },
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
    let mut unreadable = false;
    for path in files(&args.paths, &mut unreadable) {
        match format_file(&path, args.check) {
            Ok(Formatted::Unchanged) => {}
            Ok(Formatted::Changed) => {
                if args.check {
                    println!("{}", shown(&path));
                    failed = true;
                }
            }
            Ok(Formatted::SyntaxErrors) => failed = true,
            Err(error) => {
                unreadable = true;
                eprintln!("{:?}", miette::Report::new(error));
            }
        }
    }
    Ok(if unreadable {
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

/// The files named, with folders expanded to the scene text files under
/// them (sorted, so the output order is stable).
fn files(paths: &[PathBuf], unreadable: &mut bool) -> Vec<PathBuf> {
    let mut found = Vec::new();
    for path in paths {
        if path.is_dir() {
            let mut under = Vec::new();
            if let Err(error) = walk(path, &mut under) {
                *unreadable = true;
                eprintln!("{:?}", miette::Report::new(error));
            }
            under.sort();
            found.extend(under);
        } else {
            found.push(path.clone());
        }
    }
    found
}

fn walk(dir: &Path, found: &mut Vec<PathBuf>) -> Result<(), FmtError> {
    let read_error = |error: std::io::Error| FmtError::Read {
        path: shown(dir),
        reason: crate::diagnostic::io_reason(&error),
    };
    for entry in std::fs::read_dir(dir).map_err(read_error)? {
        let path = entry.map_err(read_error)?.path();
        if path.is_dir() {
            walk(&path, found)?;
        } else if path.extension().is_some_and(|e| e == "txt" || e == "scene") {
            found.push(path);
        }
    }
    Ok(())
}

/// Format one file (or stdin to stdout), or with `check` only compare.
fn format_file(path: &Path, check: bool) -> Result<Formatted, FmtError> {
    let stdin = path == Path::new("-");
    let name = shown(path);
    let bytes = read_scene(path).map_err(|error| FmtError::Read {
        path: name.clone(),
        reason: match error {
            crate::frontend::ReadSceneError::Io { reason, .. } => reason,
            other => escape(&other.to_string()).into_owned(),
        },
    })?;
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
        Ok(formatted) => formatted,
        Err(errors) => {
            let report = Report::new(source, boxed(errors));
            let stderr = std::io::stderr();
            eprint!(
                "{}",
                report.render_human(terminal_width(), use_color(&stderr))
            );
            eprintln!("{name}: not formatted: fix the syntax errors first");
            return Ok(Formatted::SyntaxErrors);
        }
    };
    let changed = *formatted != *source.text;
    if stdin && !check {
        let mut stdout = std::io::stdout().lock();
        stdout
            .write_all(formatted.as_bytes())
            .and_then(|()| stdout.flush())
            .map_err(|error| FmtError::Write {
                path: name.clone(),
                reason: crate::diagnostic::io_reason(&error),
            })?;
    } else if changed && !check {
        write_atomically(path, |out| out.write_all(formatted.as_bytes())).map_err(|error| {
            FmtError::Write {
                path: name.clone(),
                reason: crate::diagnostic::io_reason(&error),
            }
        })?;
    }
    Ok(if changed {
        Formatted::Changed
    } else {
        Formatted::Unchanged
    })
}
