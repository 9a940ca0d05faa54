//! The commands and what they share: loading a scene through the
//! front end, and mapping outcomes to the exit codes of docs/cli.md.

pub mod accuracy;
pub mod check;
pub mod convert;
pub mod discover;
pub mod render;
pub mod stitch;

use std::io::Read;
use std::path::Path;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use miette::Diagnostic;

use crate::ast;
use crate::check::Checked;
use crate::cli::{Cli, Command};
use crate::diagnostic::{boxed, io_reason, BoxedDiagnostic, Report, Shown, SourceFile};
use crate::limits::MAX_SCENE_BYTES;
use crate::{check as checker, json, syntax};

/// How a command ended, when it ran to completion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Exit 0: done (warnings allowed).
    Success,
    /// Exit 1: a scene has errors (or warnings, with `--deny-warnings`), or
    /// the parts given to `stitch` do not make one frame.
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
        Command::Stitch(args) => stitch::run(args),
        Command::Accuracy(args) => accuracy::run(args),
    };
    match result {
        Ok(Outcome::Success) => ExitCode::SUCCESS,
        Ok(Outcome::SceneErrors) => ExitCode::from(1),
        Ok(Outcome::InputErrors) => ExitCode::from(2),
        Err(failure) => {
            // Paths in the message are escaped like scene text.
            let shown = Shown::new(failure.as_ref(), None);
            eprintln!("{:?}", miette::Report::new(shown));
            ExitCode::from(2)
        }
    }
}

/// The process got Ctrl-C (SIGINT), SIGTERM or SIGHUP.
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error("interrupted; no output file was left half-written")]
#[diagnostic(
    code(io::interrupted),
    help("an image appears whole (when its rename came before the signal) or not at all")
)]
pub struct Interrupted;

/// The exit code after an interruption: 128 + SIGINT, as shells report a
/// program that Ctrl-C stopped.
pub const INTERRUPTED_EXIT_CODE: i32 = 130;

/// What the binary's signal handler runs: remove every temporary output
/// file being written (no rename can follow), say so, and exit.
pub fn interrupt() -> ! {
    crate::output::abandon();
    eprintln!("\n{:?}", miette::Report::new(Interrupted));
    std::process::exit(INTERRUPTED_EXIT_CODE)
}

/// The scene file could not be read.
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum ReadSceneError {
    /// Opening or reading failed.
    #[error("cannot read scene `{path}`: {reason}")]
    #[diagnostic(code(io::read_scene))]
    Io {
        path: String,
        /// The I/O error, as [`io_reason`] words it.
        reason: String,
    },
    /// The file is larger than [`MAX_SCENE_BYTES`]; only that much was read.
    #[error("cannot read scene `{path}`: expected at most {limit} bytes, found more")]
    #[diagnostic(
        code(io::scene_too_large),
        help("a scene at the object limit takes about 120 MiB; is this the scene file?")
    )]
    TooLarge { path: String, limit: u64 },
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
    /// The scene language of docs/language.md.
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
    let bytes = read_scene(path)?;
    let (name, dir) = if path == Path::new("-") {
        let cwd = std::env::current_dir().map_err(|source| ReadSceneError::Io {
            path: path.display().to_string(),
            reason: io_reason(&source),
        })?;
        ("<stdin>".to_string(), cwd)
    } else {
        let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
        (path.display().to_string(), dir)
    };
    let language = Language::of(path, &bytes);
    let (source, utf8_error) = SourceFile::from_bytes(&name, &dir, &bytes);
    // The text lives on in `source`: one copy of a large scene, not two,
    // while its syntax tree and model are built.
    drop(bytes);
    Ok(load_source(source, utf8_error, language, start))
}

/// The bytes of the scene at `path` (`-` is stdin), refusing a file larger
/// than [`MAX_SCENE_BYTES`] after reading one byte more than that, so an
/// endless input (`/dev/zero`, a pipe) cannot exhaust memory.
pub fn read_scene(path: &Path) -> Result<Vec<u8>, ReadSceneError> {
    let shown = path.display().to_string();
    let read_error = |source| ReadSceneError::Io {
        path: shown.clone(),
        reason: io_reason(&source),
    };
    let input: Box<dyn Read> = if path == Path::new("-") {
        Box::new(std::io::stdin().lock())
    } else {
        Box::new(std::fs::File::open(path).map_err(read_error)?)
    };
    let mut bytes = Vec::new();
    input
        .take(MAX_SCENE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(read_error)?;
    if bytes.len() as u64 > MAX_SCENE_BYTES {
        return Err(ReadSceneError::TooLarge {
            path: shown,
            limit: MAX_SCENE_BYTES,
        });
    }
    Ok(bytes)
}

/// Parse and check scene bytes named `name` (scene text, or JSON when the
/// name ends in `.json`), whose texture paths resolve against `dir`;
/// `start` is when reading began, for the parse timing.
pub fn load_bytes(name: &str, dir: &Path, bytes: &[u8], start: Instant) -> Loaded {
    let (source, utf8_error) = SourceFile::from_bytes(name, dir, bytes);
    load_source(
        source,
        utf8_error,
        Language::of(Path::new(name), bytes),
        start,
    )
}

/// Sections parsed before they are checked (and dropped).
const CHECK_BATCH: usize = 1024;

/// Parse and check decoded scene text in a given language. Scene text is
/// checked [`CHECK_BATCH`] sections at a time as it is parsed, each section
/// dropped once checked: a scene of 100,000 spheres never holds its whole syntax tree
/// (docs/performance.md). The diagnostics come in the same order as from
/// [`parse`] then [`checker::check`]: syntax errors, then the check's.
fn load_source(
    source: SourceFile,
    utf8_error: Option<syntax::SyntaxError>,
    language: Language,
    start: Instant,
) -> Loaded {
    let mut diagnostics: Vec<BoxedDiagnostic> = Vec::new();
    diagnostics.extend(utf8_error.map(|e| Box::new(e) as BoxedDiagnostic));
    let mut checking = Duration::ZERO;
    let checked = match language {
        Language::Text => {
            let mut check = checker::SceneCheck::new(&source);
            let mut sections = syntax::sections(&source.text);
            // A batch at a time, so the clock is read twice a batch, not
            // twice a section (a million readings cost 1 % of the time).
            let mut batch = Vec::with_capacity(CHECK_BATCH);
            loop {
                batch.extend(sections.by_ref().take(CHECK_BATCH));
                if batch.is_empty() {
                    break;
                }
                let started = Instant::now();
                for section in batch.drain(..) {
                    check.section(&section);
                }
                checking += started.elapsed();
            }
            diagnostics.extend(boxed(sections.into_errors()));
            let started = Instant::now();
            let (checked, problems) = check.finish();
            diagnostics.extend(boxed(problems));
            checking += started.elapsed();
            checked
        }
        Language::Json => {
            let (file, parse_diagnostics) = parse(language, &source.text);
            diagnostics.extend(parse_diagnostics);
            let started = Instant::now();
            let checked = file.and_then(|file| {
                let (checked, check_diagnostics) = checker::check(&file, &source);
                diagnostics.extend(check_diagnostics);
                checked
            });
            checking += started.elapsed();
            checked
        }
    };
    let parsing = start.elapsed().saturating_sub(checking);
    let report = Report::new(source, diagnostics);
    let checked = checked.filter(|_| report.error_count() == 0);
    Loaded {
        report,
        checked,
        parse_seconds: parsing.as_secs_f64(),
        check_seconds: checking.as_secs_f64(),
    }
}
