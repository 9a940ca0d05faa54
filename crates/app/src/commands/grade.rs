//! `raytracer grade --tracer 'CMD {scene} {out}' [SUITE...] -o REPORT`:
//! load the suite (the built-in one when none is given), render or find
//! our reference of each scene, run the tracer on each scene in the
//! box of [`raytracer_box`] (`--jobs` at once, a progress bar
//! on a terminal), and write the report. Exit 0 when every scene matches,
//! 1 otherwise, 2 for usage errors and a suite or report that cannot be
//! read or written. `--student DIR` takes the command (and a build) from
//! a student's folder ([`crate::grade::student`]); `--class DIR` grades
//! each student folder in DIR into REPORT/<student>/ against the same
//! references, then merges the class overview ([`crate::grade::class`]),
//! which `--merge REPORT` does alone. `--export-suite DIR` writes the
//! built-in suite out. The grading itself is a [`Session`], built here
//! from the parsed arguments; this module parses and prints.

use std::io::IsTerminal;
use std::path::Path;
use std::sync::Mutex;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::Outcome;
use crate::cli::{GradeArgs, SandboxArgs};
use crate::grade::class;
use crate::grade::session::{Done, GradeError, Graded, Options, ReferenceSource, Session, Watcher};
use crate::grade::{suite, Status};
use raytracer_box::Limits;
use raytracer_scene::diagnostic::BoxedDiagnostic;

/// Run `raytracer grade`.
pub fn run(args: GradeArgs) -> Result<Outcome, BoxedDiagnostic> {
    if let Some(dir) = &args.export_suite {
        suite::export(dir).map_err(GradeError::from)?;
        eprintln!("wrote the built-in suite to `{}`", dir.display());
        return Ok(Outcome::Success);
    }
    if let Some(report) = &args.merge {
        let class = class::merge(report).map_err(GradeError::from)?;
        print_class(report, &class);
        return Ok(Outcome::Success);
    }
    let Some(report) = args.report.clone() else {
        unreachable!("clap requires -o without --export-suite and --merge")
    };
    let graded = match (args.tracer, args.student, args.class) {
        (Some(tracer), _, _) => Graded::Tracer(tracer),
        (None, Some(folder), _) => Graded::Student(folder),
        (None, None, Some(folder)) => Graded::Class(folder),
        (None, None, None) => unreachable!("clap requires one of the modes"),
    };
    let references = match (args.references, args.reference_tracer) {
        (Some(folder), _) => ReferenceSource::Folder(folder),
        (None, Some(command)) => ReferenceSource::Tracer(command),
        (None, None) => ReferenceSource::Ours,
    };
    let session = Session::new(Options {
        graded,
        report: report.clone(),
        cache: args.cache,
        references,
        reference_options: args.reference_options,
        suite: args.suite,
        pool: super::thread_pool(Some(args.jobs as usize), "grading")?,
        thresholds: args.thresholds.thresholds(),
        limits: limits(&args.sandbox),
        unprotected: args.sandbox.unprotected,
        uids: args.sandbox.uids,
    })?;
    let (made, cache) = session.references_made();
    if made > 0 {
        let images = if made == 1 { "image" } else { "images" };
        eprintln!(
            "rendered {made} reference {images} into `{}`",
            cache.display()
        );
    }
    let finished = session.grade(&Terminal::new())?;
    if let Some(class) = &finished.class {
        print_class(&report, class);
    }
    Ok(if finished.all_match {
        Outcome::Success
    } else {
        Outcome::Differs
    })
}

/// What the terminal is told as a session grades: a bar of the scenes of
/// the job being graded (drawn only on a terminal), and a line per job.
struct Terminal {
    bar: Mutex<ProgressBar>,
}

impl Terminal {
    fn new() -> Terminal {
        Terminal {
            bar: Mutex::new(ProgressBar::hidden()),
        }
    }

    fn bar(&self) -> ProgressBar {
        self.bar.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }
}

impl Watcher for Terminal {
    fn job_started(&self, scenes: usize) {
        *self.bar.lock().unwrap_or_else(|e| e.into_inner()) = progress_bar(scenes);
    }

    fn scene_started(&self, name: &str) {
        self.bar().set_message(name.to_string());
    }

    fn scene_done(&self) {
        self.bar().inc(1);
    }

    fn scenes_done(&self) {
        self.bar().finish_and_clear();
    }

    fn job_done(&self, done: &Done) {
        let summary = done.summary;
        let matched = summary
            .scenes
            .iter()
            .filter(|s| s.status == Status::Match)
            .count();
        let who = match done.student {
            Some(name) => format!("{}: ", shown(&name.to_string_lossy())),
            None => String::new(),
        };
        let build = match &summary.build {
            Some(build) if !build.ok => " (the build failed)",
            _ => "",
        };
        println!(
            "{who}{matched} of {} scenes match, {} of {} points{build}; report: {}",
            summary.scenes.len(),
            summary.score,
            summary.max_score,
            shown(&done.report.join("index.html").display().to_string())
        );
    }
}

/// Say where the class overview is.
fn print_class(report: &Path, class: &class::Class) {
    println!(
        "class of {}: {} and {}",
        class.students.len(),
        shown(&report.join(class::HTML).display().to_string()),
        shown(&report.join(class::CSV).display().to_string())
    );
}

/// A name from a student's folder as the terminal may show it: every
/// control character (an escape sequence, a line break) and text
/// direction control written as Rust writes it (`\u{1b}`, `\n`), so no
/// folder name can move the cursor, recolour or forge a line.
fn shown(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_control() || raytracer_scene::escape::is_text_direction_control(c) {
                c.escape_default().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
}

/// The sandbox limits of the options.
fn limits(args: &SandboxArgs) -> Limits {
    const MIB: u64 = 1 << 20;
    Limits {
        timeout: Duration::from_secs(args.timeout.into()),
        cpu_seconds: args.cpu.into(),
        address_space: u64::from(args.memory) * MIB,
        file_size: u64::from(args.max_file_size) * MIB,
        processes: args.max_processes.into(),
        output: args.max_output as usize * 1024,
        disk: u64::from(args.disk) * MIB,
    }
}

/// A bar of scenes graded, drawn only on a terminal.
fn progress_bar(scenes: usize) -> ProgressBar {
    let target = if std::io::stderr().is_terminal() {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    };
    let bar = ProgressBar::with_draw_target(Some(scenes as u64), target);
    bar.set_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} scenes  {msg}")
            .expect("a valid template"),
    );
    bar
}
