//! The report folder `grade` writes: `index.html` ([`html`]), read from
//! `file://` with no network; `summary.json`, the [`Summary`] (its JSON
//! Schema is docs/grade-summary.schema.json); `results.json` in
//! Gradescope's autograder format ([`gradescope`]); and `images/`, which
//! [`super::grade_scene`] fills.

pub mod gradescope;
pub mod html;

use std::path::Path;

use schemars::JsonSchema;
use serde::Serialize;

use super::aspects::AspectThresholds;
use super::{SceneResult, Status};
use crate::compare::Thresholds;

/// summary.json: the grading of one tracer on one suite.
#[derive(Clone, Debug, Serialize, JsonSchema)]
pub struct Summary {
    /// The `--tracer` command, as given.
    pub tracer: String,
    /// Points earned over every scene.
    pub score: f64,
    /// Points the suite is worth.
    pub max_score: f64,
    pub thresholds: Thresholds,
    /// The bounds of each aspect's measure.
    pub aspect_thresholds: AspectThresholds,
    pub sandbox: SandboxSummary,
    /// The student's build (`build.txt`), when there was one; when it
    /// failed, every scene is `crashed` and no scene was run.
    pub build: Option<BuildSummary>,
    /// One entry per scene, worst first.
    pub scenes: Vec<SceneResult>,
}

/// How the build command ran.
#[derive(Clone, Debug, Serialize, JsonSchema)]
pub struct BuildSummary {
    /// The command line of `build.txt`.
    pub command: String,
    /// It exited 0.
    pub ok: bool,
    /// How it failed (`exit code 2`, a signal, a limit), `null` when `ok`.
    pub reason: Option<String>,
    pub seconds: f64,
    pub exit_code: Option<i32>,
    pub signal: Option<i32>,
    /// The first bytes of its stdout and stderr.
    pub stdout: String,
    pub stderr: String,
}

/// The limits the programs ran under.
#[derive(Clone, Debug, Serialize, JsonSchema)]
pub struct SandboxSummary {
    pub timeout_seconds: u32,
    pub cpu_seconds: u32,
    pub address_space_mib: u32,
    pub max_file_size_mib: u32,
    pub max_processes: u32,
    pub max_output_kib: u32,
    /// The programs had a network namespace of their own (no network).
    pub network_isolated: bool,
    /// The uid the programs ran as, when `grade` ran as root.
    pub user: Option<u32>,
    /// The programs ran in a box: PID, mount, IPC, UTS and network
    /// namespaces and a root holding only the system folders and the
    /// run's working folder (docs/grading.md, "The sandbox").
    pub boxed: bool,
    /// The mechanisms that held for every run of this report, by name:
    /// `pid_namespace`, `mount_namespace`, `ipc_namespace`,
    /// `user_namespace`, `network_namespace`, `uid`, `cgroup`, `landlock`
    /// and `seccomp` (without a box), `rlimits`, `no_new_privs`.
    pub mechanisms: Vec<String>,
}

impl Summary {
    /// Put the scenes worst first: by status, then by ꟻLIP error, then by name.
    pub fn sort(&mut self) {
        self.scenes.sort_by(|a, b| {
            a.status
                .cmp(&b.status)
                .then(
                    b.flip_mean
                        .unwrap_or(0.0)
                        .total_cmp(&a.flip_mean.unwrap_or(0.0)),
                )
                .then(a.scene.cmp(&b.scene))
        });
    }

    /// True when every scene matches.
    pub fn all_match(&self) -> bool {
        self.scenes.iter().all(|s| s.status == Status::Match)
    }
}

/// The JSON Schema of summary.json.
pub fn schema() -> String {
    serde_json::to_string_pretty(&schemars::schema_for!(Summary)).expect("a schema is JSON") + "\n"
}

/// Write index.html, summary.json and results.json into `folder`.
pub fn write(folder: &Path, summary: &Summary) -> std::io::Result<()> {
    let files = [
        ("index.html", html::page(summary)),
        ("summary.json", pretty(summary)),
        ("results.json", pretty(&gradescope::results(summary))),
    ];
    for (name, text) in files {
        raytracer_render::output::write_atomically(&folder.join(name), |out| {
            out.write_all(text.as_bytes())
        })?;
    }
    Ok(())
}

/// Pretty JSON with a final newline.
fn pretty(value: &impl Serialize) -> String {
    serde_json::to_string_pretty(value).expect("plain data") + "\n"
}

/// A scene's outcome as lines of text (results.json's `output`): status
/// and reason, the metrics, the time and exit, and the stderr excerpt.
pub fn outcome_lines(scene: &SceneResult) -> Vec<String> {
    let mut lines = vec![match &scene.reason {
        Some(reason) => format!("status: {} ({reason})", status_name(scene.status)),
        None => format!("status: {}", status_name(scene.status)),
    }];
    if scene.robustness {
        lines.push(robustness_words(scene));
    }
    if let (Some(iou), Some(flip), Some(rmse)) = (scene.coverage_iou, scene.flip, scene.rmse) {
        lines.push(format!(
            "coverage IoU {iou:.4}; ꟻLIP mean {:.4}, p99 {:.4}; RMSE {rmse:.5}",
            flip.mean, flip.p99
        ));
    }
    for aspect in &scene.aspects {
        // An aspect not judged shows what there was too little of, and
        // no points.
        lines.push(match (aspect.judged, aspect.pass) {
            (false, _) => format!("{} not judged: {}", aspect.aspect.name(), aspect.detail),
            (true, pass) => format!(
                "{} {} ({} / {} points): {}",
                aspect.aspect.name(),
                if pass { "passes" } else { "FAILS" },
                aspect.score,
                aspect.points,
                aspect.detail
            ),
        });
    }
    if let Some(reading) = &scene.reading {
        lines.push(reading.clone());
    }
    let ended = match (scene.exit_code, scene.signal) {
        (Some(code), _) => format!("exit code {code}"),
        (None, Some(signal)) => format!("signal {signal}"),
        (None, None) => "killed or not started".into(),
    };
    lines.push(format!("ran {:.2} s, {ended}", scene.seconds));
    if !scene.stderr.trim().is_empty() {
        lines.push(format!("stderr:\n{}", scene.stderr.trim_end()));
    }
    lines
}

/// What a robustness scene is, in words.
pub fn robustness_words(scene: &SceneResult) -> String {
    if scene.points > 0.0 {
        "robustness: beyond what the assignment asks; this course gives it points".to_string()
    } else {
        "robustness: beyond what the assignment asks, judged and reported for no points".to_string()
    }
}

/// A status as summary.json spells it.
pub fn status_name(status: Status) -> &'static str {
    match status {
        Status::Timeout => "timeout",
        Status::Crashed => "crashed",
        Status::BadImage => "bad_image",
        Status::NoImage => "no_image",
        Status::Differs => "differs",
        Status::Match => "match",
    }
}
