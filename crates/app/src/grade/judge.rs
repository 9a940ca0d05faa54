//! A scene's status from how the program ended and what it wrote: the
//! process first (a timeout, a crash, a start that failed), then the
//! image (missing, undecodable), then the comparison with our reference:
//! its size, then each aspect ([`super::aspects`]). A scene matches when
//! no aspect fails; otherwise the reason names the aspects that failed.

use std::path::Path;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::aspects::{self, AspectPoints, AspectThresholds, Judged};
use super::student_image;
use crate::compare::{self, Comparison, Picture, Thresholds, Verdict};
use raytracer_box::Ended;
use raytracer_render::render::probe::Buffers;

/// Where a scene ended.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize, JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// Killed at the wall-clock timeout, or stopped at the CPU limit.
    Timeout,
    /// Ended by a signal or with a non-zero exit code, or could not start.
    Crashed,
    /// Wrote something that is not a PPM, PNG or JPEG image.
    BadImage,
    /// Exited 0 without writing the image.
    NoImage,
    /// Wrote an image that differs from ours in some aspect (the reason
    /// names them).
    Differs,
    Match,
}

/// A judged scene: its status, the reason, and the comparison when one was made.
pub struct Judgement {
    pub status: Status,
    pub reason: Option<String>,
    /// The student's image and its comparison, when it was read.
    pub compared: Option<(Picture, Comparison)>,
    /// Each aspect's verdict, when the image has the scene's size.
    pub aspects: Option<Judged>,
}

/// What a student's image is judged against.
pub struct Against<'a> {
    pub reference: &'a Picture,
    /// What our reference sees at each pixel.
    pub buffers: &'a Buffers,
    pub thresholds: &'a Thresholds,
    pub aspects: &'a AspectThresholds,
    /// The points of each aspect on this scene.
    pub points: &'a AspectPoints,
}

/// Judge a run that `ended` so, with its image at `out`.
pub fn judge(ended: &Ended, out: &Path, against: &Against) -> Judgement {
    let reference = against.reference;
    let plain = |status, reason: String| Judgement {
        status,
        reason: Some(reason),
        compared: None,
        aspects: None,
    };
    if let Some((status, reason)) = failure(ended) {
        return plain(status, reason);
    }
    let picture = match super::student_image::read(out, reference) {
        student_image::Read::Picture(picture) => picture,
        student_image::Read::Missing => {
            return plain(
                Status::NoImage,
                format!("no `{}` was written", super::workdir::OUT),
            )
        }
        student_image::Read::TooLarge { width, height } => {
            return plain(
                Status::Differs,
                format!(
                    "size: expected {} × {}, found {width} × {height} (not decoded: larger than the camera)",
                    reference.width, reference.height
                ),
            )
        }
        student_image::Read::Bad(reason) => return plain(Status::BadImage, reason),
    };
    let comparison = compare::compare(reference, &picture, against.thresholds);
    let judged = (comparison.verdict != Verdict::Size).then(|| {
        aspects::judge(
            against.buffers,
            &against.buffers.through_corners(),
            reference,
            &picture,
            against.aspects,
            against.points,
        )
    });
    let (status, reason) = match &judged {
        None => (
            Status::Differs,
            Some(format!(
                "size: expected {} × {}, found {} × {}",
                reference.width, reference.height, picture.width, picture.height
            )),
        ),
        Some(judged) => {
            let failed: Vec<&str> = judged
                .results
                .iter()
                .filter(|r| !r.pass)
                .map(|r| r.aspect.name())
                .collect();
            match (failed.is_empty(), judged.transform) {
                (true, _) => (Status::Match, None),
                (false, None) => (Status::Differs, Some(failed.join(", "))),
                (false, Some(words)) => (
                    Status::Differs,
                    Some(format!(
                        "{}; the image is likely {words}",
                        failed.join(", ")
                    )),
                ),
            }
        }
    };
    Judgement {
        status,
        reason,
        compared: Some((picture, comparison)),
        aspects: judged,
    }
}

/// How a run that did not exit 0 failed: its status and reason; `None`
/// for an exit 0.
pub fn failure(ended: &Ended) -> Option<(Status, String)> {
    Some(match ended {
        Ended::TimedOut => (Status::Timeout, "wall-clock time limit".into()),
        Ended::Signalled(signal) if *signal == libc::SIGXCPU => {
            (Status::Timeout, "CPU time limit (SIGXCPU)".into())
        }
        Ended::Signalled(signal) => (Status::Crashed, signal_reason(*signal)),
        Ended::Exited(0) => return None,
        Ended::Exited(code) => (Status::Crashed, format!("exit code {code}")),
        Ended::NotStarted(reason) => (Status::Crashed, format!("cannot start: {reason}")),
    })
}

/// The exit code or the signal a run ended with, as a report gives them.
pub fn exit_code_and_signal(ended: &Ended) -> (Option<i32>, Option<i32>) {
    match *ended {
        Ended::Exited(code) => (Some(code), None),
        Ended::Signalled(signal) => (None, Some(signal)),
        Ended::TimedOut | Ended::NotStarted(_) => (None, None),
    }
}

/// "signal N (NAME)", with what the sandbox's signals mean.
fn signal_reason(signal: i32) -> String {
    let name = match signal {
        libc::SIGSEGV => "SIGSEGV",
        libc::SIGABRT => "SIGABRT",
        libc::SIGKILL => "SIGKILL",
        libc::SIGBUS => "SIGBUS",
        libc::SIGFPE => "SIGFPE",
        libc::SIGILL => "SIGILL",
        libc::SIGXFSZ => "SIGXFSZ: file size limit",
        libc::SIGPIPE => "SIGPIPE",
        libc::SIGTERM => "SIGTERM",
        _ => return format!("signal {signal}"),
    };
    format!("signal {signal} ({name})")
}
