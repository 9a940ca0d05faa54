//! A grading session: everything `raytracer grade` does between parsing
//! its arguments and printing its lines, so the command only does those.
//!
//! [`Session::new`] sets the session up once for every tracer it grades:
//! the jobs (the `--tracer` command, the `--student`, or each folder of a
//! `--class`), the suite (the built-in one copied out when none is given),
//! the private reference cache with the course's constants, the box (or
//! the refusal to grade without one unless `--unprotected`), the grader as
//! the subreaper of whatever a program leaves, a uid of its own for the
//! instructor's `--reference-tracer` when root, and the reference images
//! and probes of every scene. [`Session::grade`] then grades each job with
//! a uid leased for it when root, writes its report, tells a [`Watcher`]
//! as it goes (the command draws and prints), and merges the class
//! overview after the last student of a class.

use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};

use miette::Diagnostic;
use rayon::prelude::*;

use super::aspects::AspectThresholds;
use super::class::{self, Class, ClassError};
use super::reference::{self, Cache};
use super::report::{self, SandboxSummary, Summary};
use super::student::{self, Student, StudentError};
use super::suite::{self, SuiteError, SuiteScene};
use super::workdir::{Template, TemplateError};
use super::{Plan, Programs};
use crate::compare::{Picture, Thresholds};
use raytracer_box::run::{become_subreaper, reap_orphans};
use raytracer_box::uids::{self, Lease};
use raytracer_box::{jail, Confinement, Limits};
use raytracer_render::render::probe::{self, Buffers};
use raytracer_scene::diagnostic::{io_reason, FileError};

/// Why a session could not grade.
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

/// Which tracers a session grades.
pub enum Graded {
    /// `--tracer CMD`: one command, its relative program taken from the
    /// folder `grade` runs in.
    Tracer(String),
    /// `--student DIR`: one student's folder.
    Student(PathBuf),
    /// `--class DIR`: each student folder in DIR, into a report folder of
    /// its own, then the class overview.
    Class(PathBuf),
}

/// Where the reference images come from.
pub enum ReferenceSource {
    /// Our renderer's, cached.
    Ours,
    /// `--references DIR`: the instructor's images.
    Folder(PathBuf),
    /// `--reference-tracer CMD`: the instructor's own tracer, boxed.
    Tracer(String),
}

/// What a session is asked to do: the command's arguments, parsed.
pub struct Options {
    pub graded: Graded,
    /// The report folder (a folder per student in it for a class).
    pub report: PathBuf,
    /// The reference cache's folder; the default one when not given.
    pub cache: Option<PathBuf>,
    pub references: ReferenceSource,
    /// `--reference-options FILE`, over a suite.json's `reference`.
    pub reference_options: Option<PathBuf>,
    /// The suite's files and folders; the built-in suite when empty.
    pub suite: Vec<PathBuf>,
    /// The pool the scenes of a job are graded on (`--jobs` workers).
    pub pool: rayon::ThreadPool,
    pub thresholds: Thresholds,
    pub limits: Limits,
    /// Grade without a box where none can be had.
    pub unprotected: bool,
    /// The uids a root grader leases, one per student and one for the
    /// reference tracer.
    pub uids: RangeInclusive<u32>,
}

/// What a session tells as it grades: the command draws a progress bar
/// and prints a line per job. Called from the grading threads.
pub trait Watcher: Sync {
    /// A job of `scenes` scenes starts.
    fn job_started(&self, scenes: usize);
    /// The scene `name` starts.
    fn scene_started(&self, name: &str);
    /// A scene is graded.
    fn scene_done(&self);
    /// The job's scenes are graded; its report comes next.
    fn scenes_done(&self);
    /// A job is graded and its report written.
    fn job_done(&self, done: &Done);
}

/// One graded tracer, as the command prints it.
pub struct Done<'a> {
    /// The student's folder name, in a class.
    pub student: Option<&'a std::ffi::OsStr>,
    pub summary: &'a Summary,
    /// The job's report folder.
    pub report: &'a Path,
}

/// How a session ended: whether every scene of every job matched, and
/// the class overview of a class.
pub struct Finished {
    pub all_match: bool,
    pub class: Option<Class>,
}

/// One tracer to grade: the command, where a relative program is taken
/// from, the student (for a build) and the report folder.
struct Job {
    tracer: String,
    template: Template,
    cwd: PathBuf,
    student: Option<Student>,
    report: PathBuf,
}

/// A session set up: the jobs, the scenes with their references and
/// probes, the box, and the leases it holds until dropped.
pub struct Session {
    jobs: Vec<Job>,
    class: bool,
    report: PathBuf,
    scenes: Vec<SuiteScene>,
    references: Vec<(Picture, bool)>,
    /// What our renderer sees at each pixel of each scene.
    buffers: Vec<Buffers>,
    confinement: Confinement,
    pool: rayon::ThreadPool,
    thresholds: Thresholds,
    uids: RangeInclusive<u32>,
    cache_folder: PathBuf,
    /// The reference tracer's uid, held as long as the session.
    _reference_lease: Option<Lease>,
    /// The built-in suite's copy, removed with the session.
    _built_in: Option<tempfile::TempDir>,
}

impl Session {
    /// Set the session up: read the students, load the suite, open the
    /// cache, decide the box, and make or find every scene's reference.
    pub fn new(options: Options) -> Result<Session, GradeError> {
        let here = std::env::current_dir().map_err(FileError::reading(Path::new(".")))?;
        let jobs = jobs(&options.graded, &options.report, &here)?;
        let cache_folder = match &options.cache {
            Some(folder) => folder.clone(),
            None => reference::default_folder().ok_or(GradeError::NoCache)?,
        };
        std::fs::create_dir_all(&options.report).map_err(FileError::writing(&options.report))?;
        let given = options
            .reference_options
            .as_deref()
            .map(reference_options)
            .transpose()?;
        let cache = Cache::open(&cache_folder).map_err(FileError::writing(&cache_folder))?;
        let (suite, built_in) = load_suite(&options.suite)?;
        // `--reference-options` over a suite.json's `reference`.
        let render = match given {
            Some(given) => given,
            None => suite.reference_options()?.unwrap_or_default(),
        };
        let cache = cache.with_options(render);

        let confinement = Confinement::new(options.limits);
        if !confinement.boxed && !options.unprotected {
            return Err(GradeError::NoBox {
                reason: "this kernel or container refuses a mount or PID namespace to this user"
                    .into(),
            });
        }
        become_subreaper();
        let (source, reference_lease) =
            reference_source(&options.references, confinement, &options.uids, &here)?;
        let scenes = suite.scenes;
        let references = scenes
            .par_iter()
            .map(|scene| cache.reference_from(scene, &source))
            .collect::<Result<Vec<_>, _>>()
            .map_err(FileError::writing(&cache_folder))?;
        let buffers = scenes
            .par_iter()
            .map(|scene| probe::buffers(&scene.scene, render.max_depth, render.model))
            .collect();
        Ok(Session {
            jobs,
            class: matches!(options.graded, Graded::Class(_)),
            report: options.report,
            scenes,
            references,
            buffers,
            confinement,
            pool: options.pool,
            thresholds: options.thresholds,
            uids: options.uids,
            cache_folder,
            _reference_lease: reference_lease,
            _built_in: built_in,
        })
    }

    /// How many reference images were made now (rendered, or the
    /// reference tracer run) rather than found in the cache, and the
    /// cache's folder.
    pub fn references_made(&self) -> (usize, &Path) {
        let made = self.references.iter().filter(|(_, fresh)| *fresh).count();
        (made, &self.cache_folder)
    }

    /// Grade every job in turn, each with a uid leased for it when root
    /// (held until the session ends, so no other student of this run or
    /// of a `grade` running beside it has it), telling `watcher`; then
    /// merge a class's overview.
    pub fn grade(&self, watcher: &dyn Watcher) -> Result<Finished, GradeError> {
        let leases = self
            .jobs
            .iter()
            .map(|_| self.lease())
            .collect::<Result<Vec<_>, _>>()?;
        let mut all_match = true;
        for (index, (job, lease)) in self.jobs.iter().zip(&leases).enumerate() {
            let confinement = self.confinement.with_user(lease.as_ref());
            let summary = self.grade_job(job, confinement, watcher);
            jail::remove_staging_if(index + 1 == self.jobs.len());
            let summary = summary?;
            all_match &= summary.all_match();
            watcher.job_done(&Done {
                student: job
                    .student
                    .as_ref()
                    .filter(|_| self.class)
                    .map(|s| s.name.as_os_str()),
                summary: &summary,
                report: &job.report,
            });
        }
        let class = if self.class {
            Some(class::merge(&self.report)?)
        } else {
            None
        };
        Ok(Finished { all_match, class })
    }

    /// A uid of its own when the grader is root.
    fn lease(&self) -> Result<Option<Lease>, GradeError> {
        lease(self.confinement, &self.uids)
    }

    /// Build the job's student, if any, grade every scene, and write the
    /// report.
    fn grade_job(
        &self,
        job: &Job,
        confinement: Confinement,
        watcher: &dyn Watcher,
    ) -> Result<Summary, GradeError> {
        let images = job.report.join("images");
        std::fs::create_dir_all(&images).map_err(FileError::writing(&images))?;
        let (prepared, build, skip) = prepare(job.student.as_ref(), confinement);
        let plan = Plan {
            template: &job.template,
            confinement,
            thresholds: self.thresholds,
            aspects: AspectThresholds::default(),
            report: &job.report,
            programs: match &prepared {
                Some(folder) => Programs::Folder(folder.path()),
                None => Programs::Here(job.cwd.clone()),
            },
            skip,
        };
        watcher.job_started(self.scenes.len());
        let results = self.pool.install(|| {
            self.scenes
                .par_iter()
                .zip(&self.references)
                .zip(&self.buffers)
                .enumerate()
                .map(|(index, ((scene, (reference, _)), buffers))| {
                    watcher.scene_started(&scene.name);
                    let result = super::grade_scene(&plan, index, scene, reference, buffers);
                    watcher.scene_done();
                    result
                })
                .collect::<Result<Vec<_>, _>>()
        });
        reap_orphans(None);
        watcher.scenes_done();
        let results = results.map_err(FileError::writing(&job.report))?;

        let mut summary = Summary {
            tracer: job.tracer.clone(),
            score: suite::round_points(results.iter().map(|r| r.score).sum()),
            max_score: suite::round_points(self.scenes.iter().map(|s| s.points).sum()),
            thresholds: plan.thresholds,
            aspect_thresholds: plan.aspects,
            sandbox: sandbox_summary(&confinement),
            build,
            scenes: results,
        };
        summary.sort();
        if let Some(folder) = prepared {
            super::remove_reporting(folder, "the student's prepared folder");
        }
        report::write(&job.report, &summary).map_err(FileError::writing(&job.report))?;
        Ok(summary)
    }
}

/// The jobs of `graded`, reported into `report`, from the folder `here`.
fn jobs(graded: &Graded, report: &Path, here: &Path) -> Result<Vec<Job>, GradeError> {
    let students = match graded {
        Graded::Tracer(tracer) => {
            return Ok(vec![Job {
                tracer: tracer.clone(),
                template: tracer_template(tracer, here)?,
                cwd: here.to_path_buf(),
                student: None,
                report: report.to_path_buf(),
            }])
        }
        Graded::Student(folder) => {
            vec![Student::read(folder).map_err(|e| GradeError::Students { errors: vec![e] })?]
        }
        Graded::Class(folder) => {
            student::class(folder).map_err(|errors| GradeError::Students { errors })?
        }
    };
    let class = matches!(graded, Graded::Class(_));
    Ok(students
        .into_iter()
        .map(|student| Job {
            tracer: student.tracer.clone(),
            template: student.template.clone(),
            cwd: here.join(&student.folder),
            report: if class {
                report.join(class::report_folder(&student.name))
            } else {
                report.to_path_buf()
            },
            student: Some(student),
        })
        .collect())
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

/// The options of a `--reference-options` file.
fn reference_options(path: &Path) -> Result<raytracer_render::render::Options, GradeError> {
    let text = std::fs::read_to_string(path).map_err(FileError::reading(path))?;
    super::options::read_options(&text).map_err(|reason| GradeError::ReferenceOptions {
        path: path.display().to_string(),
        reason,
    })
}

/// The suite of `paths`; with none, the built-in suite, graded from a
/// copy like any folder (the copy returned to be kept while it is used).
fn load_suite(paths: &[PathBuf]) -> Result<(suite::Suite, Option<tempfile::TempDir>), GradeError> {
    if !paths.is_empty() {
        return Ok((suite::load(paths)?, None));
    }
    let dir = tempfile::tempdir().map_err(FileError::writing(&std::env::temp_dir()))?;
    suite::export(dir.path())?;
    let suite = suite::load(&[dir.path().to_path_buf()])?;
    Ok((suite, Some(dir)))
}

/// Where the references come from, and the reference tracer's lease: as
/// root, the instructor's program runs as a uid of its own, leased as a
/// student's is, so no student's run ever shares its uid.
fn reference_source<'a>(
    references: &'a ReferenceSource,
    confinement: Confinement,
    uids: &RangeInclusive<u32>,
    here: &'a Path,
) -> Result<(reference::Source<'a>, Option<Lease>), GradeError> {
    Ok(match references {
        ReferenceSource::Ours => (reference::Source::Ours, None),
        ReferenceSource::Folder(folder) => (reference::Source::Folder(folder), None),
        ReferenceSource::Tracer(command) => {
            let lease = lease(confinement, uids)?;
            let source = reference::Source::Tracer {
                command,
                template: Template::tracer(command)?,
                cwd: here,
                confinement: confinement.with_user(lease.as_ref()),
            };
            (source, lease)
        }
    })
}

/// A uid of `uids` leased for one program when the grader is root (the
/// confinement then names a user), none otherwise.
fn lease(
    confinement: Confinement,
    uids: &RangeInclusive<u32>,
) -> Result<Option<Lease>, GradeError> {
    confinement
        .root()
        .then(|| Lease::take(uids))
        .transpose()
        .map_err(FileError::writing(Path::new(uids::FOLDER)))
        .map_err(GradeError::from)
}

/// A student's prepared folder (copied, and built), the build's record,
/// and why no scene runs: a folder that cannot be copied is that
/// student's failure, and the rest of a class is still graded.
fn prepare(
    student: Option<&Student>,
    confinement: Confinement,
) -> (
    Option<raytracer_box::folder::RunFolder>,
    Option<report::BuildSummary>,
    Option<String>,
) {
    match student.map(|s| s.prepare(confinement)) {
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
    }
}

/// summary.json's sandbox: the limits, in the units the options give
/// them, and the mechanisms that held.
fn sandbox_summary(confinement: &Confinement) -> SandboxSummary {
    const MIB: u64 = 1 << 20;
    let limits = &confinement.limits;
    let small = |value: u64| u32::try_from(value).unwrap_or(u32::MAX);
    SandboxSummary {
        timeout_seconds: small(limits.timeout.as_secs()),
        cpu_seconds: small(limits.cpu_seconds),
        address_space_mib: small(limits.address_space / MIB),
        max_file_size_mib: small(limits.file_size / MIB),
        max_processes: small(limits.processes),
        max_output_kib: small(limits.output as u64 / 1024),
        network_isolated: confinement.isolate_network,
        user: confinement.user,
        boxed: confinement.boxed,
        mechanisms: confinement.mechanisms(),
    }
}
