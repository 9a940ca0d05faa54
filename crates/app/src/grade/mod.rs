//! Grading a ray tracer: run a student's program on each scene of a suite
//! in a sandbox, judge its image against our reference, and keep what the
//! report needs.
//!
//! [`suite`] gives the scenes; [`reference`] renders (or finds in its
//! cache) our image of each; [`workdir`] prepares the folder and argument
//! vector; the box of [`raytracer_box`] runs the program under limits and
//! captures its output; [`judge`] turns the run and the image into a
//! [`Status`], judging each aspect with [`aspects`] against what our
//! renderer's probe sees at each pixel; [`student`] reads a student's folder (its command, its
//! build) for `--student` and `--class`; [`class`] merges the students'
//! summaries into the class overview; [`report`] writes the HTML report, summary.json and
//! Gradescope's results.json; [`session`] drives them all for a whole
//! `grade` run, from its options to the class overview.

pub mod aspects;
pub mod class;
pub mod judge;
pub mod options;
pub mod reference;
pub mod report;
pub mod session;
pub mod student;
pub mod student_image;
pub mod suite;
pub mod workdir;

use std::path::{Path, PathBuf};

use schemars::JsonSchema;
use serde::Serialize;

use crate::compare::{self, heatmap, FlipStats, Picture, Thresholds};
use aspects::{AspectResult, AspectThresholds};
pub use judge::Status;
use raytracer_box::folder::RunFolder;
use raytracer_box::{run::run, Confinement, Scratch, Share};
use raytracer_render::render::probe::Buffers;
use suite::SuiteScene;
use workdir::Template;

/// The stylesheet of the report pages (`index.html`, `class.html`),
/// inlined in each so a page works offline from `file://`.
pub const STYLE: &str = include_str!("report.css");

/// The grade of one scene: summary.json's entries.
#[derive(Clone, Debug, Serialize, JsonSchema)]
pub struct SceneResult {
    /// The scene's path inside its suite.
    pub scene: String,
    /// What the scene tests.
    pub description: String,
    pub status: Status,
    /// Which aspects failed (`geometry, shadows`), a size that differs (`size: …`), how it
    /// crashed (`exit code 3`, `signal 11 (SIGSEGV)`), which limit stopped
    /// it, or why its image is bad.
    pub reason: Option<String>,
    /// The points the scene is worth.
    pub points: f64,
    /// A robustness scene (suite.json's `robustness`): beyond what the
    /// assignment asks, worth points only where the suite opts in.
    pub robustness: bool,
    /// The points earned: those of every aspect that passed, none when
    /// no image of the scene's size was judged.
    pub score: f64,
    /// Each aspect's verdict, with its points and numbers; empty when the
    /// image was not judged.
    pub aspects: Vec<AspectResult>,
    /// Which pixel reading the image fits, when the image tells.
    pub reading: Option<String>,
    pub coverage_iou: Option<f64>,
    pub flip_mean: Option<f32>,
    pub flip: Option<FlipStats>,
    pub rmse: Option<f64>,
    /// `null` when identical, or not compared.
    pub psnr: Option<f64>,
    /// Wall-clock seconds the student's program ran.
    pub seconds: f64,
    pub exit_code: Option<i32>,
    pub signal: Option<i32>,
    /// The first bytes of the program's stdout and stderr.
    pub stdout: String,
    pub stderr: String,
    /// The report's images, relative to the report folder.
    pub images: Images,
}

/// A scene's images in the report.
#[derive(Clone, Debug, Serialize, JsonSchema)]
pub struct Images {
    pub reference: String,
    pub student: Option<String>,
    pub heatmap: Option<String>,
}

/// What grading needs besides the scenes.
pub struct Plan<'a> {
    pub template: &'a Template,
    pub confinement: Confinement,
    pub thresholds: Thresholds,
    pub aspects: AspectThresholds,
    /// The report folder; images go to its `images/`.
    pub report: &'a Path,
    /// Where the program comes from.
    pub programs: Programs<'a>,
    /// When set, no scene runs: each is `crashed` for this reason (the
    /// student's build failed).
    pub skip: Option<String>,
}

/// Where a tracer's program is found.
pub enum Programs<'a> {
    /// `--tracer`: a relative program path is taken from this folder, the
    /// one `grade` runs in.
    Here(PathBuf),
    /// A student's prepared folder, copied into each scene's working
    /// folder, where the program starts.
    Folder(&'a Path),
}

/// Each aspect's result, with the picture of where it differs (written
/// by `write_png` at `image(aspect)`) for those that failed; and the
/// pixel reading the image fits.
fn aspect_pictures(
    judged: Option<aspects::Judged>,
    reference: &Picture,
    image: &dyn Fn(&str) -> String,
    write_png: &dyn Fn(&str, &Picture) -> std::io::Result<()>,
) -> std::io::Result<(Vec<AspectResult>, Option<String>)> {
    let Some(found) = judged else {
        return Ok((Vec::new(), None));
    };
    let mut results = Vec::with_capacity(found.results.len());
    for (mut result, map) in found.results.into_iter().zip(found.maps) {
        if result.judged && !result.pass {
            let relative = image(result.aspect.name());
            write_png(&relative, &aspects::map_picture(reference, &map))?;
            result.image = Some(relative);
        }
        results.push(result);
    }
    Ok((results, found.reading))
}

/// `reason` with the run's full disk (of `disk` bytes) told after it.
pub(crate) fn with_full_disk(reason: Option<String>, disk: u64) -> String {
    let full = format!("the run's disk space ({} MiB) was full", disk >> 20);
    match reason {
        Some(reason) => format!("{reason}; {full}"),
        None => full,
    }
}

/// Grade one scene against its `reference`; `index` names its images.
pub fn grade_scene(
    plan: &Plan,
    index: usize,
    scene: &SuiteScene,
    reference: &Picture,
    buffers: &Buffers,
) -> std::io::Result<SceneResult> {
    let stem = format!("{index:02}-{}", slug(&scene.name));
    let image = |kind: &str| format!("images/{stem}.{kind}.png");
    let write_png = |relative: &str, picture: &Picture| {
        raytracer_render::output::write_atomically(&plan.report.join(relative), |out| {
            compare::encode_png(picture, out)
        })
    };
    let reference_image = image("reference");
    write_png(&reference_image, reference)?;
    if let Some(reason) = &plan.skip {
        return Ok(not_run(scene, reference_image, reason));
    }
    let against = judge::Against {
        reference,
        buffers,
        thresholds: &plan.thresholds,
        aspects: &plan.aspects,
        points: &scene.aspects,
    };
    let (run, mut judged) = match run_and_judge(plan, scene, &against) {
        Ok(done) => done,
        Err(reason) => return Ok(not_run(scene, reference_image, &reason)),
    };
    let mut images = Images {
        reference: reference_image,
        student: None,
        heatmap: None,
    };
    let metrics = match &judged.compared {
        Some((picture, comparison)) => {
            student_pictures(picture, comparison, &image, &write_png, &mut images)?
        }
        None => None,
    };
    let (aspect_results, reading) =
        aspect_pictures(judged.aspects.take(), reference, &image, &write_png)?;
    let score = suite::round_points(aspect_results.iter().map(|r| r.score).sum());
    let (exit_code, signal) = judge::exit_code_and_signal(&run.ended);
    Ok(SceneResult {
        scene: scene.name.clone(),
        description: scene.description.clone(),
        status: judged.status,
        reason: judged.reason,
        points: scene.points,
        robustness: scene.robustness,
        score,
        aspects: aspect_results,
        reading,
        coverage_iou: metrics.map(|m| m.coverage_iou),
        flip_mean: metrics.map(|m| m.flip.mean),
        flip: metrics.map(|m| m.flip),
        rmse: metrics.map(|m| m.rmse),
        psnr: metrics.and_then(|m| m.psnr),
        seconds: run.seconds,
        exit_code,
        signal,
        stdout: run.stdout.text(),
        stderr: run.stderr.text(),
        images,
    })
}

/// Run the tracer on `scene` in a working folder of its own (removed
/// after) and judge what it wrote `against` the reference, with a full
/// disk told; why it could not run when its folder cannot be prepared.
fn run_and_judge(
    plan: &Plan,
    scene: &SuiteScene,
    against: &judge::Against,
) -> Result<(raytracer_box::Run, judge::Judgement), String> {
    let (folder, cwd) = match &plan.programs {
        Programs::Here(cwd) => (None, Some(cwd.as_path())),
        Programs::Folder(folder) => (Some(*folder), None),
    };
    // A folder that cannot be prepared is this scene's failure, not the
    // whole grading's: the student's folder may be what it cannot copy.
    let dir = workdir::prepare(scene, folder, &plan.confinement).map_err(|error| {
        format!(
            "cannot prepare the scene's working folder: {}",
            raytracer_scene::diagnostic::io_reason(&error)
        )
    })?;
    let argv = plan.template.argv(&dir.scene_file, workdir::OUT, cwd);
    let share = Share {
        read_write: vec![dir.root.clone()],
        read_only: match &plan.programs {
            Programs::Here(_) => program_files(&argv),
            Programs::Folder(_) => Vec::new(),
        },
        scratch: Some(Scratch {
            folder: dir.root.clone(),
            keep: dir.keep(),
        }),
        home: None,
    };
    let run = run(&argv, &dir.start, &share, plan.confinement);
    let mut judged = judge::judge(&run.ended, &dir.out(), against);
    remove_reporting(dir.folder, "the scene's working folder");
    if run.disk_full {
        judged.reason = Some(with_full_disk(
            judged.reason.take(),
            plan.confinement.limits.disk,
        ));
    }
    Ok((run, judged))
}

/// The student's `picture` and, when it was compared, its ꟻLIP heat map
/// (written by `write_png` at `image(kind)`, named in `images`); the
/// comparison's metrics.
fn student_pictures(
    picture: &Picture,
    comparison: &compare::Comparison,
    image: &dyn Fn(&str) -> String,
    write_png: &dyn Fn(&str, &Picture) -> std::io::Result<()>,
    images: &mut Images,
) -> std::io::Result<Option<compare::Metrics>> {
    let student = image("student");
    write_png(&student, picture)?;
    images.student = Some(student);
    let Some(metrics) = comparison.metrics else {
        return Ok(None);
    };
    let flip = image("flip");
    let map = heatmap::colour(picture.width, picture.height, &comparison.error_map);
    write_png(&flip, &map)?;
    images.heatmap = Some(flip);
    Ok(Some(metrics))
}

/// The files a `--tracer` command names by an absolute path (its program,
/// a script it runs), which a box holds read-only at their paths; never
/// the grader's own executable.
pub(crate) fn program_files(argv: &[std::ffi::OsString]) -> Vec<PathBuf> {
    let exe = std::env::current_exe().and_then(std::fs::canonicalize).ok();
    argv.iter()
        .map(Path::new)
        .filter(|path| path.is_absolute())
        .filter_map(|path| std::fs::canonicalize(path).ok())
        .filter(|path| path.is_file() && Some(path) != exe.as_ref())
        .collect()
}

/// Remove a run's `folder` (`what`, for the warning): what cannot be
/// removed is said on stderr, and grading goes on.
pub(crate) fn remove_reporting(folder: RunFolder, what: &str) {
    let path = folder.path().display().to_string();
    if let Err(error) = folder.remove() {
        eprintln!(
            "warning: cannot remove {what} `{path}`: {}",
            raytracer_scene::diagnostic::io_reason(&error)
        );
    }
}

/// A scene that did not run because of `reason`.
fn not_run(scene: &SuiteScene, reference_image: String, reason: &str) -> SceneResult {
    SceneResult {
        scene: scene.name.clone(),
        description: scene.description.clone(),
        status: Status::Crashed,
        reason: Some(reason.to_string()),
        points: scene.points,
        robustness: scene.robustness,
        score: 0.0,
        aspects: Vec::new(),
        reading: None,
        coverage_iou: None,
        flip_mean: None,
        flip: None,
        rmse: None,
        psnr: None,
        seconds: 0.0,
        exit_code: None,
        signal: None,
        stdout: String::new(),
        stderr: String::new(),
        images: Images {
            reference: reference_image,
            student: None,
            heatmap: None,
        },
    }
}

/// A file-name-safe form of a scene's path.
pub fn slug(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '.' {
                c
            } else {
                '_'
            }
        })
        .collect()
}
