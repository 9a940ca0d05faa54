//! The three commands and what they share: loading a scene through the
//! front end, and mapping outcomes to the exit codes of SPEC.md §3.

pub mod check;
pub mod convert;
pub mod render;

use std::io::Read;
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use miette::Diagnostic;

use crate::ast;
use crate::check::Checked;
use crate::cli::{Cli, Command};
use crate::diagnostic::{BoxedDiagnostic, Report, SourceFile};
use crate::{check as checker, json, syntax};

/// How a command ended, when it ran to completion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Exit 0: done (warnings allowed).
    Success,
    /// Exit 1: a scene has errors (or warnings, with `--deny-warnings`).
    SceneErrors,
    /// Exit 2: an input could not be read; the command already said why
    /// and still processed the other inputs.
    InputErrors,
}

/// A failure that is not the scene's fault: usage, I/O or internal (exit 2).
pub type Failure = Box<dyn Diagnostic + Send + Sync + 'static>;

/// Run a parsed command line and return the process exit code.
pub fn run(cli: Cli) -> ExitCode {
    let result = match cli.command {
        Command::Render(args) => render::run(args),
        Command::Check(args) => check::run(args),
        Command::Convert(args) => convert::run(args),
    };
    match result {
        Ok(Outcome::Success) => ExitCode::SUCCESS,
        Ok(Outcome::SceneErrors) => ExitCode::from(1),
        Ok(Outcome::InputErrors) => ExitCode::from(2),
        Err(failure) => {
            eprintln!("{:?}", miette::Report::new_boxed(failure));
            ExitCode::from(2)
        }
    }
}

/// The scene file could not be read.
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error("cannot read scene `{path}`: {source}")]
#[diagnostic(code(io::read_scene))]
pub struct ReadSceneError {
    pub path: String,
    #[source]
    pub source: std::io::Error,
}

/// A scene run through the front end: every diagnostic, and the checked
/// scene when there were no errors.
pub struct Loaded {
    pub report: Report,
    pub checked: Option<Checked>,
    /// Seconds spent reading and parsing the file.
    pub parse_seconds: f64,
    /// Seconds spent in the check pass (including texture decoding).
    pub check_seconds: f64,
}

/// The languages a scene can be written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Language {
    /// The scene language of SPEC.md §1.
    Text,
    /// The JSON layout of [`crate::model::Scene`].
    Json,
}

impl Language {
    /// JSON for a path ending in `.json` (any case), and for stdin whose
    /// first non-blank character is `{` (which no scene file starts with);
    /// scene text otherwise.
    pub fn of(path: &Path, bytes: &[u8]) -> Language {
        let json = if path == Path::new("-") {
            bytes.trim_ascii_start().starts_with(b"{")
        } else {
            path.extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("json"))
        };
        if json {
            Language::Json
        } else {
            Language::Text
        }
    }
}

/// Parse `text` in `language` into the syntax tree the check pass reads
/// (`None` when there is nothing to check: a JSON text that is not a scene
/// of this format), with every problem found on the way.
pub fn parse(language: Language, text: &str) -> (Option<ast::File>, Vec<BoxedDiagnostic>) {
    fn boxed<D: miette::Diagnostic + Send + Sync + 'static>(
        errors: Vec<D>,
    ) -> Vec<BoxedDiagnostic> {
        errors
            .into_iter()
            .map(|e| Box::new(e) as BoxedDiagnostic)
            .collect()
    }
    match language {
        Language::Text => {
            let parsed = syntax::parse(text);
            (Some(parsed.file), boxed(parsed.errors))
        }
        Language::Json => {
            let parsed = json::parse(text);
            (parsed.file, boxed(parsed.errors))
        }
    }
}

/// Read `path` (`-` is stdin), parse it as scene text or JSON (see
/// [`Language::of`]) and check it.
pub fn load(path: &Path) -> Result<Loaded, ReadSceneError> {
    let start = Instant::now();
    let read_error = |source| ReadSceneError {
        path: path.display().to_string(),
        source,
    };
    let (name, dir, bytes) = if path == Path::new("-") {
        let mut bytes = Vec::new();
        std::io::stdin()
            .read_to_end(&mut bytes)
            .map_err(read_error)?;
        let cwd = std::env::current_dir().map_err(read_error)?;
        ("<stdin>".to_string(), cwd, bytes)
    } else {
        let bytes = std::fs::read(path).map_err(read_error)?;
        let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
        (path.display().to_string(), dir, bytes)
    };
    let language = Language::of(path, &bytes);
    Ok(load_source(&name, &dir, &bytes, language, start))
}

/// Parse and check scene bytes named `name` (scene text, or JSON when the
/// name ends in `.json`), whose texture paths resolve against `dir`;
/// `start` is when reading began, for the parse timing.
pub fn load_bytes(name: &str, dir: &Path, bytes: &[u8], start: Instant) -> Loaded {
    load_source(
        name,
        dir,
        bytes,
        Language::of(Path::new(name), bytes),
        start,
    )
}

/// [`load_bytes`] in a given language.
fn load_source(name: &str, dir: &Path, bytes: &[u8], language: Language, start: Instant) -> Loaded {
    let (source, utf8_error) = SourceFile::from_bytes(name, dir, bytes);
    let mut diagnostics: Vec<BoxedDiagnostic> = Vec::new();
    diagnostics.extend(utf8_error.map(|e| Box::new(e) as BoxedDiagnostic));
    let (file, parse_diagnostics) = parse(language, &source.text);
    diagnostics.extend(parse_diagnostics);
    let parse_seconds = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let checked = file.and_then(|file| {
        let (checked, check_diagnostics) = checker::check(&file, &source);
        diagnostics.extend(check_diagnostics);
        checked
    });
    let report = Report::new(source, diagnostics);
    let checked = checked.filter(|_| report.error_count() == 0);
    Loaded {
        report,
        checked,
        parse_seconds,
        check_seconds: start.elapsed().as_secs_f64(),
    }
}
