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
//! built-in suite out.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use miette::Diagnostic;
use rayon::prelude::*;

use super::Outcome;
use crate::cli::{GradeArgs, SandboxArgs};
use crate::compare::Picture;
use crate::grade::aspects::AspectThresholds;
use crate::grade::class::{self, ClassError};
use crate::grade::reference::{self, Cache};
use crate::grade::report::{self, SandboxSummary, Summary};
use crate::grade::student::{self, Student, StudentError};
use crate::grade::suite::{self, SuiteError, SuiteScene};
use crate::grade::workdir::{Template, TemplateError};
use crate::grade::{self, Plan, Programs};
use raytracer_box::run::{become_subreaper, reap_orphans};
use raytracer_box::uids::{self, Lease};
use raytracer_box::{jail, Confinement, Limits};
use raytracer_render::render::probe::{self, Buffers};
use raytracer_scene::diagnostic::{io_reason, BoxedDiagnostic, FileError};

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

    #[error("the tracer's command names `{word}`, a file beside it, but a `--tracer` program runs without the files beside it")]
    #[diagnostic(
        code(usage::tracer_files),
        help("grade the folder that holds it as a student: put `{command}` in its `tracer.txt` and run `raytracer grade --student FOLDER -o REPORT` (docs/grading.md, \"A whole class\")")
    )]
    LocalFile { word: String, command: String },

    #[error(transparent)]
    #[diagnostic(code(io::grade))]
    File(#[from] FileError),

    #[error(transparent)]
    #[diagnostic(transparent)]
    Threads(#[from] super::ThreadsError),

    #[error("{} student folder{} cannot be graded", errors.len(), if errors.len() == 1 { "" } else { "s" })]
    #[diagnostic(code(grade::student))]
    Students {
        #[related]
        errors: Vec<StudentError>,
    },

    #[error(transparent)]
    #[diagnostic(transparent)]
    Class(#[from] ClassError),

    #[error("no box can be had here for the students' programs: {reason}")]
    #[diagnostic(
        code(grade::sandbox),
        help("the box needs mount and PID namespaces: run `grade` as root, or allow unprivileged user namespaces (docs/grading.md, \"The sandbox\"); `--unprotected` grades without one")
    )]
    NoBox { reason: String },

    #[error("cannot use `{path}` as the reference's options: {reason}")]
    #[diagnostic(
        code(usage::reference_options),
        help("a JSON object with any of `ambient`, `diffuse`, `specular`, `exponent` (numbers), `pixel` (`\"centre\"` or `\"corner\"`), `reflection` (`\"added\"` or `\"blended\"`) and `depth` (docs/grading.md)")
    )]
    ReferenceOptions { path: String, reason: String },

    #[error("no folder for the reference cache: neither `XDG_CACHE_HOME` nor `HOME` is set")]
    #[diagnostic(code(usage::no_cache), help("give one with `--cache DIR`"))]
    NoCache,
}

/// One tracer to grade: the command, where a relative program is taken
/// from, the student (for a build) and the report folder.
struct Job<'a> {
    tracer: String,
    template: Template,
    cwd: PathBuf,
    student: Option<&'a Student>,
    report: PathBuf,
}

/// The scenes every job is graded on, with our reference images.
struct Graded<'a> {
    scenes: &'a [SuiteScene],
    references: &'a [(Picture, bool)],
    /// What our renderer sees at each pixel of each scene.
    buffers: &'a [Buffers],
    confinement: Confinement,
    pool: &'a rayon::ThreadPool,
}

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
    let Some(report_folder) = &args.report else {
        unreachable!("clap requires -o without --export-suite and --merge")
    };
    let here = std::env::current_dir()
        .map_err(FileError::reading(Path::new(".")))
        .map_err(GradeError::from)?;
    let students = match (&args.student, &args.class) {
        (Some(folder), _) => {
            vec![Student::read(folder).map_err(|e| GradeError::Students { errors: vec![e] })?]
        }
        (_, Some(folder)) => {
            student::class(folder).map_err(|errors| GradeError::Students { errors })?
        }
        _ => Vec::new(),
    };
    let jobs: Vec<Job> = match &args.tracer {
        Some(tracer) => vec![Job {
            tracer: tracer.clone(),
            template: tracer_template(tracer, &here)?,
            cwd: here,
            student: None,
            report: report_folder.clone(),
        }],
        None => students
            .iter()
            .map(|student| Job {
                tracer: student.tracer.clone(),
                template: student.template.clone(),
                cwd: here.join(&student.folder),
                student: Some(student),
                report: if args.class.is_some() {
                    report_folder.join(class::report_folder(&student.name))
                } else {
                    report_folder.clone()
                },
            })
            .collect(),
    };
    let cache_folder = match &args.cache {
        Some(folder) => folder.clone(),
        None => reference::default_folder().ok_or(GradeError::NoCache)?,
    };
    std::fs::create_dir_all(report_folder)
        .map_err(FileError::writing(report_folder))
        .map_err(GradeError::from)?;
    let options = match &args.reference_options {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .map_err(FileError::reading(path))
                .map_err(GradeError::from)?;
            let options = crate::grade::options::read_options(&text).map_err(|reason| {
                GradeError::ReferenceOptions {
                    path: path.display().to_string(),
                    reason,
                }
            })?;
            Some(options)
        }
        None => None,
    };
    let cache = Cache::open(&cache_folder)
        .map_err(FileError::writing(&cache_folder))
        .map_err(GradeError::from)?;

    // The built-in suite is graded from a copy, like any folder.
    let built_in = if args.suite.is_empty() {
        let dir = tempfile::tempdir()
            .map_err(FileError::writing(&std::env::temp_dir()))
            .map_err(GradeError::from)?;
        suite::export(dir.path()).map_err(GradeError::from)?;
        Some(dir)
    } else {
        None
    };
    let paths: Vec<PathBuf> = match &built_in {
        Some(dir) => vec![dir.path().to_path_buf()],
        None => args.suite.clone(),
    };
    let suite = suite::load(&paths).map_err(GradeError::from)?;
    // `--reference-options` over a suite.json's `reference`.
    let options = match options {
        Some(options) => options,
        None => suite
            .reference_options()
            .map_err(GradeError::from)?
            .unwrap_or_default(),
    };
    let scenes = suite.scenes;
    let cache = cache.with_options(options);

    let confinement = Confinement::new(limits(&args.sandbox));
    if !confinement.boxed && !args.sandbox.unprotected {
        return Err(GradeError::NoBox {
            reason: "this kernel or container refuses a mount or PID namespace to this user".into(),
        }
        .into());
    }
    become_subreaper();
    let instructor = match &args.reference_tracer {
        Some(command) => Some((
            command,
            Template::tracer(command).map_err(GradeError::from)?,
        )),
        None => None,
    };
    let cwd = std::env::current_dir()
        .map_err(FileError::reading(Path::new(".")))
        .map_err(GradeError::from)?;
    let source = match (&args.references, &instructor) {
        (Some(folder), _) => reference::Source::Folder(folder),
        (None, Some((command, template))) => reference::Source::Tracer {
            command,
            template,
            cwd: &cwd,
            confinement,
        },
        (None, None) => reference::Source::Ours,
    };
    let references = scenes
        .par_iter()
        .map(|scene| cache.reference_from(scene, &source))
        .collect::<Result<Vec<_>, _>>()
        .map_err(FileError::writing(&cache_folder))
        .map_err(GradeError::from)?;
    let buffers: Vec<Buffers> = scenes
        .par_iter()
        .map(|scene| probe::buffers(&scene.scene, options.max_depth, options.model))
        .collect();
    let rendered = references.iter().filter(|(_, fresh)| *fresh).count();
    if rendered > 0 {
        let images = if rendered == 1 { "image" } else { "images" };
        eprintln!(
            "rendered {rendered} reference {images} into `{}`",
            cache_folder.display()
        );
    }

    let pool = super::thread_pool(Some(args.jobs as usize), "grading").map_err(GradeError::from)?;
    let graded = Graded {
        scenes: &scenes,
        references: &references,
        buffers: &buffers,
        confinement,
        pool: &pool,
    };
    // A uid of its own for each student when root, held until `grade`
    // exits, so no other student of this run or of a `grade` running
    // beside it has it.
    let leases = jobs
        .iter()
        .map(|_| {
            graded
                .confinement
                .root()
                .then(|| Lease::take(&args.sandbox.uids))
                .transpose()
        })
        .collect::<Result<Vec<_>, _>>()
        .map_err(FileError::writing(Path::new(uids::FOLDER)))
        .map_err(GradeError::from)?;
    let mut all_match = true;
    for (index, (job, lease)) in jobs.iter().zip(&leases).enumerate() {
        let graded = Graded {
            confinement: graded.confinement.with_user(lease.as_ref()),
            ..graded
        };
        let summary = grade_job(job, &graded, &args);
        jail::remove_staging_if(index + 1 == jobs.len());
        let summary = summary?;
        all_match &= summary.all_match();
        let matched = summary
            .scenes
            .iter()
            .filter(|s| s.status == grade::Status::Match)
            .count();
        let who = match (job.student, &args.class) {
            (Some(student), Some(_)) => format!("{}: ", shown(&student.name.to_string_lossy())),
            _ => String::new(),
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
            shown(&job.report.join("index.html").display().to_string())
        );
    }
    if args.class.is_some() {
        let class = class::merge(report_folder).map_err(GradeError::from)?;
        print_class(report_folder, &class);
    }
    Ok(if all_match {
        Outcome::Success
    } else {
        Outcome::Differs
    })
}

/// Build the job's student, if any, grade every scene, and write the report.
fn grade_job(job: &Job, graded: &Graded, args: &GradeArgs) -> Result<Summary, GradeError> {
    let images = job.report.join("images");
    std::fs::create_dir_all(&images).map_err(FileError::writing(&images))?;
    // A student's folder that cannot be copied is that student's failure:
    // the rest of a class is still graded.
    let (prepared, build, skip) = match job.student.map(|s| s.prepare(graded.confinement)) {
        None => (None, None, None),
        Some(Ok(prepared)) => {
            let skip = prepared
                .build
                .as_ref()
                .and_then(|b| b.reason.as_ref())
                .map(|reason| format!("the build failed: {reason}"));
            let build = prepared.build.clone();
            (Some(prepared.folder), build, skip)
        }
        Some(Err(error)) => (
            None,
            None,
            Some(format!(
                "the student's folder cannot be copied: {}",
                io_reason(&error)
            )),
        ),
    };
    let plan = Plan {
        template: &job.template,
        confinement: graded.confinement,
        thresholds: args.thresholds.thresholds(),
        aspects: AspectThresholds::default(),
        report: &job.report,
        programs: match &prepared {
            Some(folder) => Programs::Folder(folder.path()),
            None => Programs::Here(job.cwd.clone()),
        },
        skip,
    };
    let progress = progress_bar(graded.scenes.len());
    let results = graded.pool.install(|| {
        graded
            .scenes
            .par_iter()
            .zip(graded.references)
            .zip(graded.buffers)
            .enumerate()
            .map(|(index, ((scene, (reference, _)), buffers))| {
                progress.set_message(scene.name.clone());
                let result = grade::grade_scene(&plan, index, scene, reference, buffers);
                progress.inc(1);
                result
            })
            .collect::<Result<Vec<_>, _>>()
    });
    reap_orphans(None);
    progress.finish_and_clear();
    let results = results.map_err(FileError::writing(&job.report))?;

    let mut summary = Summary {
        tracer: job.tracer.clone(),
        score: suite::round_points(results.iter().map(|r| r.score).sum()),
        max_score: suite::round_points(graded.scenes.iter().map(|s| s.points).sum()),
        thresholds: plan.thresholds,
        aspect_thresholds: plan.aspects,
        sandbox: sandbox_summary(&args.sandbox, &graded.confinement),
        build,
        scenes: results,
    };
    summary.sort();
    if let Some(folder) = prepared {
        grade::remove_reporting(folder, "the student's prepared folder");
    }
    report::write(&job.report, &summary).map_err(FileError::writing(&job.report))?;
    Ok(summary)
}

/// `--tracer`'s command, refused when it names a file beside the program
/// (a script by a relative path): the box would hold the program alone.
fn tracer_template(tracer: &str, here: &Path) -> Result<Template, GradeError> {
    let template = Template::tracer(tracer)?;
    match template.local_file(here) {
        Some(word) => Err(GradeError::LocalFile {
            word: word.to_string(),
            command: tracer.to_string(),
        }),
        None => Ok(template),
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
        boxed: confinement.boxed,
        mechanisms: confinement.mechanisms(),
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
