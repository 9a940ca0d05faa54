//! The commands and what they share: mapping outcomes to the exit
//! codes of docs/cli.md, and writing to stdout and stderr without
//! panicking. Each command loads its scenes through [`raytracer_scene::frontend`]
//! and only handles arguments and printing.
//!
//! Output goes through [`out!`], [`say!`] and [`sayln!`], never `print!` or
//! `eprint!`, which panic when the stream is a pipe whose reader has gone
//! (`raytracer check scenes/ | head -1`). A closed stdout ends the command
//! quietly with exit 0, as ripgrep does: the reader took what it wanted. A
//! message stderr cannot take is dropped: there is no one left to tell.

/// `print!` to stdout, returning `Err(BoxedDiagnostic)` when stdout cannot
/// be written ([`stdout_error`]) instead of panicking.
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::commands::write_stdout(format_args!($($arg)*))
    };
}

/// `eprint!` that drops what stderr cannot take instead of panicking.
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::commands::write_stderr(format_args!($($arg)*))
    };
}

/// `eprintln!` that drops what stderr cannot take instead of panicking.
macro_rules! sayln {
    ($($arg:tt)*) => {
        $crate::commands::write_stderr(format_args!("{}\n", format_args!($($arg)*)))
    };
}

pub mod accuracy;
pub mod check;
pub mod compare;
pub mod convert;
pub mod fmt;
#[cfg(unix)]
pub mod grade;
pub mod lsp;
pub mod preview;
pub mod render;
pub mod stats;
pub mod stitch;

use std::io::Write;
use std::path::Path;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};

use miette::Diagnostic;

use crate::cli::{Cli, Command};
use raytracer_scene::diagnostic::{BoxedDiagnostic, FileError, Shown};

/// How a command ended, when it ran to completion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Exit 0: done (warnings allowed).
    Success,
    /// Exit 1: a scene has errors (or warnings, with `--deny-warnings`), or
    /// the parts given to `stitch` do not make one frame.
    SceneErrors,
    /// Exit 1: images differ (`compare`), or a graded scene did not match
    /// (`grade`).
    Differs,
    /// Exit 2: an input could not be read; the command already said why
    /// and still processed the other inputs.
    InputErrors,
}

/// Writing a command's output to stdout failed (a closed pipe, a full disk).
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error(transparent)]
#[diagnostic(code(io::write_stdout))]
pub struct WriteStdoutError(FileError);

/// Stdout is a pipe whose reader has gone: the command stops quietly.
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error("stdout was closed")]
#[diagnostic(code(io::closed_stdout))]
pub struct ClosedStdout;

/// A failed write to stdout as the command's failure: [`ClosedStdout`]
/// for a closed pipe, which ends the command quietly, else a
/// [`WriteStdoutError`].
pub fn stdout_error(error: std::io::Error) -> BoxedDiagnostic {
    if error.kind() == std::io::ErrorKind::BrokenPipe {
        Box::new(ClosedStdout)
    } else {
        Box::new(WriteStdoutError::from(error))
    }
}

fn is_closed_stdout(failure: &(dyn Diagnostic + Send + Sync + 'static)) -> bool {
    let failure: &(dyn std::error::Error + 'static) = failure;
    failure.is::<ClosedStdout>()
}

/// What [`out!`] runs.
pub fn write_stdout(text: std::fmt::Arguments) -> Result<(), BoxedDiagnostic> {
    std::io::stdout().write_fmt(text).map_err(stdout_error)
}

/// What [`say!`] runs.
pub fn write_stderr(text: std::fmt::Arguments) {
    let _ = std::io::stderr().write_fmt(text);
}

impl From<std::io::Error> for WriteStdoutError {
    fn from(error: std::io::Error) -> WriteStdoutError {
        WriteStdoutError(FileError::new("write to", Path::new("stdout"), &error))
    }
}

/// Write generated text (a completion script, the man page) to stdout.
fn print_bytes(bytes: &[u8]) -> Result<Outcome, BoxedDiagnostic> {
    let mut stdout = std::io::stdout().lock();
    stdout
        .write_all(bytes)
        .and_then(|()| stdout.flush())
        .map_err(stdout_error)?;
    Ok(Outcome::Success)
}

/// The worker threads of a command could not be started.
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error("cannot start {threads} {purpose} threads: {reason}")]
#[diagnostic(code(io::threads))]
pub struct ThreadsError {
    threads: usize,
    purpose: &'static str,
    reason: String,
}

/// A pool of `threads` workers (all cores without a number), for
/// `purpose` ("render", "grading"), as render, preview, accuracy and grade
/// build theirs.
pub(crate) fn thread_pool(
    threads: Option<usize>,
    purpose: &'static str,
) -> Result<rayon::ThreadPool, ThreadsError> {
    let threads = threads.unwrap_or_else(rayon::current_num_threads);
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| ThreadsError {
            threads,
            purpose,
            reason: e.to_string(),
        })
}

/// Refuse a sample count that is not a square number: the samples of a
/// pixel lie on a √spp×√spp grid. `option` names where the count came
/// from (`--spp`), for the message.
pub(crate) fn square_spp(spp: u32, option: &'static str) -> Result<u32, SppNotSquare> {
    let grid = spp.isqrt();
    if grid * grid == spp {
        Ok(spp)
    } else {
        Err(SppNotSquare {
            option,
            found: spp,
            below: grid * grid,
            above: (grid + 1) * (grid + 1),
        })
    }
}

/// A sample count that is not a square number.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
#[error("expected a square number of samples for `{option}`, found {found}")]
#[diagnostic(
    code(usage::spp_not_square),
    help("samples lie on a √N×√N grid: try {below} or {above}")
)]
pub struct SppNotSquare {
    pub option: &'static str,
    pub found: u32,
    pub below: u32,
    pub above: u32,
}

/// Run a parsed command line and return the process exit code.
pub fn run(cli: Cli) -> ExitCode {
    let result = match cli.command {
        Command::Render(args) => render::run(args),
        Command::Check(args) => check::run(args),
        Command::Convert(args) => convert::run(args),
        Command::Fmt(args) => fmt::run(args),
        Command::Lsp(args) => lsp::run(args),
        Command::Stitch(args) => stitch::run(args),
        Command::Accuracy(args) => accuracy::run(args),
        Command::Preview(args) => preview::run(args),
        Command::Compare(args) => compare::run(args),
        Command::Completions(args) => {
            print_bytes(&crate::cli::completions(args.shell, cli.version))
        }
        Command::Man(args) => man(args, cli.version),
        #[cfg(unix)]
        Command::Grade(args) => grade::run(*args),
        #[cfg(not(unix))]
        Command::Grade(_) => {
            Err(Box::new(GradeUnsupported) as raytracer_scene::diagnostic::BoxedDiagnostic)
        }
    };
    match result {
        Ok(Outcome::Success) => ExitCode::SUCCESS,
        Ok(Outcome::SceneErrors | Outcome::Differs) => ExitCode::from(1),
        Ok(Outcome::InputErrors) => ExitCode::from(2),
        Err(failure) if is_closed_stdout(failure.as_ref()) => ExitCode::SUCCESS,
        Err(failure) => {
            // Paths in the message are escaped like scene text.
            let shown = Shown::new(failure.as_ref(), None);
            sayln!("{:?}", miette::Report::new(shown));
            ExitCode::from(2)
        }
    }
}

/// A man page that cannot be written to `man --dir`'s folder.
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error(transparent)]
#[diagnostic(code(io::write_man))]
pub struct WriteManError(FileError);

/// `raytracer man`: print the page of `raytracer` or of one command, or
/// write every page to a folder (created), each atomically.
fn man(args: crate::cli::ManArgs, version: &'static str) -> Result<Outcome, BoxedDiagnostic> {
    let pages = crate::cli::man_pages(version);
    let Some(dir) = args.dir else {
        let name = match &args.command {
            Some(command) => format!("raytracer-{command}.1"),
            None => "raytracer.1".to_string(),
        };
        let (_, roff) = pages
            .iter()
            .find(|(file, _)| *file == name)
            .expect("clap allows only the commands that have a page");
        return print_bytes(roff);
    };
    std::fs::create_dir_all(&dir)
        .map_err(|error| WriteManError(FileError::new("create the folder", &dir, &error)))?;
    for (name, roff) in &pages {
        let path = dir.join(name);
        raytracer_render::output::write_atomically(&path, |out| out.write_all(roff))
            .map_err(|error| WriteManError(FileError::writing(&path)(error)))?;
    }
    Ok(Outcome::Success)
}

/// `grade` on a system without the Unix process controls its sandbox needs.
#[cfg(not(unix))]
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error("`grade` runs only on Unix: its sandbox needs process groups and resource limits")]
#[diagnostic(code(usage::grade_unsupported))]
pub struct GradeUnsupported;

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

/// Set by a command whose documented way to stop is Ctrl-C (`preview`
/// serving): the interruption is then the end of its work, not an error.
static INTERRUPT_STOPS: AtomicBool = AtomicBool::new(false);

/// From now on Ctrl-C is how this command stops: [`interrupt`] exits with
/// [`INTERRUPTED_EXIT_CODE`] without reporting it as an error.
pub fn interrupt_stops() {
    INTERRUPT_STOPS.store(true, Ordering::SeqCst);
}

/// What the binary's signal handler runs: remove every temporary output
/// file being written (no rename can follow), kill the programs `grade`
/// is running, say so (unless Ctrl-C is how the command stops), and exit.
pub fn interrupt() -> ! {
    raytracer_render::output::abandon();
    #[cfg(unix)]
    raytracer_box::run::kill_running();
    if !INTERRUPT_STOPS.load(Ordering::SeqCst) {
        sayln!("\n{:?}", miette::Report::new(Interrupted));
    }
    std::process::exit(INTERRUPTED_EXIT_CODE)
}
