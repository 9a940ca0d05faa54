//! `raytracer grade --tracer 'CMD {scene} {out}' [SUITE...] -o REPORT`:
//! load the suite (the built-in one when none is given), render or find
//! our reference of each scene, run the tracer on each scene in the
//! sandbox of [`crate::grade::sandbox`] (`--jobs` at once, a progress bar
//! on a terminal), and write the report. Exit 0 when every scene matches,
//! 1 otherwise, 2 for usage errors and a suite or report that cannot be
//! read or written. `--export-suite DIR` writes the built-in suite out.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use miette::Diagnostic;
use rayon::prelude::*;

use super::Outcome;
use crate::cli::{GradeArgs, SandboxArgs};
use crate::diagnostic::{io_reason, BoxedDiagnostic};
use crate::grade::reference::{self, Cache};
use crate::grade::report::{self, SandboxSummary, Summary};
use crate::grade::sandbox::{self, Confinement, Limits};
use crate::grade::suite::{self, SuiteError, SuiteScene};
use crate::grade::workdir::{Template, TemplateError};
use crate::grade::{self, Plan};

/// Why `grade` could not grade.
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum GradeError {
    #[error(transparent)]
    #[diagnostic(
        code(grade::suite),
        help("a suite is scene files, or folders of them with an optional suite.json (see docs/grading.md)")
    )]
    Suite(#[from] SuiteError),

    #[error(transparent)]
    #[diagnostic(
        code(usage::tracer),
        help("give the command as one argument, e.g. `--tracer './mytracer {{scene}} {{out}}'`")
    )]
    Template(#[from] TemplateError),

    #[error("cannot write `{path}`: {reason}")]
    #[diagnostic(code(io::grade))]
    Io { path: String, reason: String },

    #[error("no folder for the reference cache: neither `XDG_CACHE_HOME` nor `HOME` is set")]
    #[diagnostic(code(usage::no_cache), help("give one with `--cache DIR`"))]
    NoCache,
}

fn io_error(path: &Path) -> impl Fn(std::io::Error) -> GradeError + '_ {
    move |error| GradeError::Io {
        path: path.display().to_string(),
        reason: io_reason(&error),
    }
}

/// Run `raytracer grade`.
pub fn run(args: GradeArgs) -> Result<Outcome, BoxedDiagnostic> {
    if let Some(dir) = &args.export_suite {
        suite::export(dir).map_err(GradeError::from)?;
        eprintln!("wrote the built-in suite to `{}`", dir.display());
        return Ok(Outcome::Success);
    }
    let (Some(tracer), Some(report_folder)) = (&args.tracer, &args.report) else {
        unreachable!("clap requires --tracer and -o without --export-suite")
    };
    let template = Template::parse(tracer).map_err(GradeError::from)?;
    let cache_folder = match &args.cache {
        Some(folder) => folder.clone(),
        None => reference::default_folder().ok_or(GradeError::NoCache)?,
    };
    let images = report_folder.join("images");
    std::fs::create_dir_all(&images).map_err(io_error(&images))?;
    let cache = Cache::open(&cache_folder).map_err(io_error(&cache_folder))?;

    // The built-in suite is graded from a copy, like any folder.
    let built_in = if args.suite.is_empty() {
        let dir = tempfile::tempdir().map_err(io_error(&std::env::temp_dir()))?;
        suite::export(dir.path()).map_err(GradeError::from)?;
        Some(dir)
    } else {
        None
    };
    let paths: Vec<PathBuf> = match &built_in {
        Some(dir) => vec![dir.path().to_path_buf()],
        None => args.suite.clone(),
    };
    let scenes = suite::load(&paths).map_err(GradeError::from)?;

    let references = scenes
        .par_iter()
        .map(|scene| cache.reference(scene))
        .collect::<Result<Vec<_>, _>>()
        .map_err(io_error(&cache_folder))?;
    let rendered = references.iter().filter(|(_, fresh)| *fresh).count();
    if rendered > 0 {
        let images = if rendered == 1 { "image" } else { "images" };
        eprintln!(
            "rendered {rendered} reference {images} into `{}`",
            cache_folder.display()
        );
    }

    let confinement = Confinement::new(limits(&args.sandbox));
    sandbox::become_subreaper();
    let plan = Plan {
        template: &template,
        confinement,
        thresholds: args.thresholds.thresholds(),
        report: report_folder,
        cwd: std::env::current_dir().map_err(io_error(Path::new(".")))?,
    };
    let progress = progress_bar(scenes.len());
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.jobs as usize)
        .build()
        .map_err(|e| GradeError::Io {
            path: "threads".into(),
            reason: e.to_string(),
        })?;
    let results = pool.install(|| {
        scenes
            .par_iter()
            .zip(&references)
            .enumerate()
            .map(|(index, (scene, (reference, _)))| {
                progress.set_message(scene.name.clone());
                let result = grade::grade_scene(&plan, index, scene, reference);
                progress.inc(1);
                result
            })
            .collect::<Result<Vec<_>, _>>()
    });
    sandbox::reap_orphans(None);
    progress.finish_and_clear();
    let results = results.map_err(io_error(report_folder))?;

    let mut summary = Summary {
        tracer: tracer.clone(),
        score: results.iter().map(|r| r.score).sum(),
        max_score: scenes.iter().map(|s: &SuiteScene| s.points).sum(),
        thresholds: plan.thresholds,
        sandbox: sandbox_summary(&args.sandbox, &confinement),
        scenes: results,
    };
    summary.sort();
    report::write(report_folder, &summary).map_err(io_error(report_folder))?;
    let matched = summary
        .scenes
        .iter()
        .filter(|s| s.status == grade::Status::Match)
        .count();
    println!(
        "{matched} of {} scenes match, {} of {} points; report: {}",
        summary.scenes.len(),
        summary.score,
        summary.max_score,
        report_folder.join("index.html").display()
    );
    Ok(if summary.all_match() {
        Outcome::Success
    } else {
        Outcome::Differs
    })
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
    }
}

fn sandbox_summary(args: &SandboxArgs, confinement: &Confinement) -> SandboxSummary {
    SandboxSummary {
        timeout_seconds: args.timeout,
        cpu_seconds: args.cpu,
        address_space_mib: args.memory,
        max_file_size_mib: args.max_file_size,
        max_processes: args.max_processes,
        max_output_kib: args.max_output,
        network_isolated: confinement.isolate_network,
        user: confinement.user,
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
