//! `raytracer compare REFERENCE CANDIDATE...`: read the images (by
//! content), measure each candidate against the reference with
//! [`crate::compare`], print the findings (human or JSON), write the ꟻLIP
//! heat map when asked (of one candidate), and exit 0 when every candidate
//! matches, 1 when one differs (a different size included), 2 when an
//! image cannot be read or the heat map cannot be written. Without a scene
//! the verdict is pixel by pixel, and says so; with `--scene`, it is
//! `grade`'s, aspect by aspect ([`crate::grade::aspects`]) against what our
//! renderer sees at each pixel of that scene, probed once for every
//! candidate.

use std::io::Write;

use miette::Diagnostic;
use serde::Serialize;

use super::{Outcome, WriteStdoutError};
use crate::cli::{CompareArgs, CompareFormat};
use crate::compare::{self, heatmap, Metrics, Thresholds, Verdict};
use raytracer_render::output;
use raytracer_scene::diagnostic::BoxedDiagnostic;
use raytracer_scene::limits::MAX_IMAGE_SIDE;
use raytracer_scene::texture::TextureError;

/// Why `compare` could not judge.
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum CompareError {
    /// An image could not be read or decoded. Its message is the reason,
    /// once (not again as a cause); the formats `compare` reads are named
    /// only when the file was there and did not decode.
    #[error("{error}")]
    #[diagnostic(code(io::read_image))]
    Read {
        error: compare::ReadImageError,
        #[help]
        help: Option<String>,
    },

    /// The heat map could not be written.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Heatmap(#[from] output::OutputError),

    /// `--heatmap` was given with more than one candidate.
    #[error("`--heatmap` writes the heat map of one candidate, found {0} candidates")]
    #[diagnostic(
        code(compare::heatmap),
        help("compare one candidate at a time to write its heat map")
    )]
    HeatmapOfMany(usize),

    /// `--scene` could not be read or checked, or names a texture outside
    /// its folder.
    #[error(transparent)]
    #[diagnostic(
        code(compare::scene),
        help("`--scene` takes the scene file both images were rendered from")
    )]
    Scene(#[from] crate::grade::suite::SuiteError),
}

impl CompareError {
    /// The failure to read an image, with the formats in its help when the
    /// file was read and did not decode, and the largest size when it is
    /// too large.
    fn read(error: compare::ReadImageError) -> CompareError {
        let help = match error.0 {
            TextureError::Decode { .. }
            | TextureError::Truncated { .. }
            | TextureError::Empty { .. } => Some(
                "`compare` reads PPM (P3 or P6), PNG and JPEG, recognised by their bytes".into(),
            ),
            TextureError::TooLarge { .. } => Some(format!(
                "`compare` reads images up to {MAX_IMAGE_SIDE} × {MAX_IMAGE_SIDE} pixels, the largest `render` writes"
            )),
            TextureError::Io { .. } | TextureError::NotAFile { .. } => None,
        };
        CompareError::Read { error, help }
    }
}

/// What `--format json` prints.
#[derive(Serialize)]
struct Report<'a> {
    verdict: Verdict,
    reference: Side<'a>,
    candidate: Side<'a>,
    /// `null` when the sizes differ.
    metrics: Option<Metrics>,
    thresholds: Thresholds,
    /// The heat map written, if any.
    heatmap: Option<String>,
    /// How the verdict was reached: `"pixels"` (no scene) or `"aspects"`
    /// (`--scene`, grade's judge).
    judged_by: &'static str,
    /// With `--scene`: each aspect's verdict, as grade's summary.json
    /// gives it (points shared as for a scene worth 1).
    aspects: Option<Vec<crate::grade::aspects::AspectResult>>,
    /// With `--scene`: the whole-image transform that explains a failed
    /// geometry, and the pixel reading the image fits, when they tell.
    transform: Option<&'static str>,
    reading: Option<String>,
}

/// One of the two images.
#[derive(Serialize)]
struct Side<'a> {
    path: String,
    format: &'a str,
    width: u32,
    height: u32,
}

/// Run `raytracer compare`.
pub fn run(args: CompareArgs) -> Result<Outcome, BoxedDiagnostic> {
    if args.heatmap.is_some() && args.candidates.len() > 1 {
        return Err(CompareError::HeatmapOfMany(args.candidates.len()).into());
    }
    let thresholds = args.thresholds.thresholds();
    let (reference, reference_format) =
        compare::read(&args.reference).map_err(CompareError::read)?;
    let candidates = args
        .candidates
        .iter()
        .map(|path| compare::read(path).map_err(CompareError::read))
        .collect::<Result<Vec<_>, _>>()?;
    let mut probed = None;
    let mut reports = Vec::new();
    for (path, (candidate, candidate_format)) in args.candidates.iter().zip(&candidates) {
        let comparison = compare::compare(&reference, candidate, &thresholds);
        let heatmap = match (&args.heatmap, comparison.metrics.is_some()) {
            (Some(out), true) => {
                let picture =
                    heatmap::colour(reference.width, reference.height, &comparison.error_map);
                output::check_not_input(out, [args.reference.as_path(), path.as_path()])
                    .map_err(CompareError::from)?;
                output::write_with(out, |file| compare::encode_png(&picture, file))
                    .map_err(CompareError::from)?;
                Some(out.display().to_string())
            }
            _ => None,
        };
        let judged = match &args.scene {
            Some(scene) if comparison.metrics.is_some() => {
                if probed.is_none() {
                    probed = Some(probe(scene, &reference)?);
                }
                let (buffers, through_corners, aspects) = probed.as_ref().expect("probed above");
                Some(crate::grade::aspects::judge(
                    buffers,
                    through_corners,
                    &reference,
                    candidate,
                    &crate::grade::aspects::AspectThresholds::default(),
                    aspects,
                ))
            }
            _ => None,
        };
        let (aspects, transform, reading) = match judged {
            Some(j) => (Some(j.results), j.transform, j.reading),
            None => (None, None, None),
        };
        reports.push(Report {
            verdict: comparison.verdict,
            reference: side(&args.reference, reference_format, &reference),
            candidate: side(path, *candidate_format, candidate),
            metrics: comparison.metrics,
            thresholds,
            heatmap,
            judged_by: if args.scene.is_some() {
                "aspects"
            } else {
                "pixels"
            },
            aspects,
            transform,
            reading,
        });
    }
    let text = match (args.format, reports.as_slice()) {
        (CompareFormat::Json, [one]) => json(one),
        (CompareFormat::Json, many) => json(&many),
        (CompareFormat::Human, [one]) => human(one, args.heatmap.is_some()),
        (CompareFormat::Human, many) => many
            .iter()
            .map(|report| {
                format!(
                    "candidate: {}\n{}",
                    report.candidate.path,
                    human(report, false)
                )
            })
            .collect::<Vec<_>>()
            .join("\n"),
    };
    std::io::stdout()
        .write_all(text.as_bytes())
        .map_err(WriteStdoutError::from)?;
    let matches = |report: &Report| match &report.aspects {
        Some(results) => results.iter().all(|r| r.pass),
        None => report.verdict == Verdict::Match,
    };
    Ok(if reports.iter().all(matches) {
        Outcome::Success
    } else {
        Outcome::Differs
    })
}

/// `value` as pretty JSON, one line after it.
fn json(value: &impl Serialize) -> String {
    serde_json::to_string_pretty(value).expect("plain data") + "\n"
}

/// One image as the report names it.
fn side<'a>(
    path: &std::path::Path,
    format: raytracer_scene::texture::TextureFormat,
    picture: &compare::Picture,
) -> Side<'a> {
    Side {
        path: path.display().to_string(),
        format: format_name(format),
        width: picture.width,
        height: picture.height,
    }
}

/// What our renderer sees at each pixel of `scene`, through pixel
/// centres and through their corners, and the aspects its suite entry
/// judges, with `grade`'s default constants: probed once for every
/// candidate, after checking that `reference` is the scene's size.
fn probe(
    scene: &std::path::Path,
    reference: &compare::Picture,
) -> Result<
    (
        raytracer_render::render::probe::Buffers,
        raytracer_render::render::probe::Buffers,
        crate::grade::aspects::AspectPoints,
    ),
    CompareError,
> {
    let suite = crate::grade::suite::load(&[scene.to_path_buf()])?;
    let options = suite.reference_options()?.unwrap_or_default();
    let scene = &suite.scenes[0];
    let buffers =
        raytracer_render::render::probe::buffers(&scene.scene, options.max_depth, options.model);
    if buffers.size != reference.width || reference.width != reference.height {
        return Err(CompareError::Scene(
            crate::grade::suite::SuiteError::Manifest {
                path: scene.name.clone(),
                reason: format!(
                    "the scene is {0} × {0} pixels, the images {1} × {2}",
                    buffers.size, reference.width, reference.height
                ),
            },
        ));
    }
    let through_corners = buffers.through_corners();
    Ok((buffers, through_corners, scene.aspects.clone()))
}

/// A format's name in reports.
pub fn format_name(format: raytracer_scene::texture::TextureFormat) -> &'static str {
    match format {
        raytracer_scene::texture::TextureFormat::Ppm => "ppm",
        raytracer_scene::texture::TextureFormat::Png => "png",
        raytracer_scene::texture::TextureFormat::Jpeg => "jpeg",
    }
}

/// The findings as lines for a person.
fn human(report: &Report, heatmap_asked: bool) -> String {
    let mut lines = match &report.aspects {
        Some(aspects) => {
            let failed: Vec<&str> = aspects
                .iter()
                .filter(|a| !a.pass)
                .map(|a| a.aspect.name())
                .collect();
            let mut lines = vec![if failed.is_empty() {
                "verdict: match (grade's aspects)".to_string()
            } else {
                format!("verdict: differs: {} (grade's aspects)", failed.join(", "))
            }];
            for a in aspects {
                lines.push(if a.judged {
                    format!(
                        "{} {}: {}",
                        a.aspect.name(),
                        if a.pass { "passes" } else { "FAILS" },
                        a.detail
                    )
                } else {
                    format!("{} not judged: {}", a.aspect.name(), a.detail)
                });
            }
            if let Some(words) = report.transform {
                lines.push(format!("the image is likely {words}"));
            }
            if let Some(reading) = &report.reading {
                lines.push(reading.clone());
            }
            lines.push("pixel measures (shown, not judged):".into());
            lines
        }
        None => vec![
            format!("verdict: {}", report.verdict.describe()),
            "judged pixel by pixel: without the scene, a background colour of your own, other constants or rays through pixel corners can differ here and still be right; `--scene SCENE` gives grade's verdict, aspect by aspect".into(),
        ],
    };
    let t = &report.thresholds;
    match &report.metrics {
        None => {
            lines.push(format!(
                "size: expected {} × {} (reference), found {} × {}",
                report.reference.width,
                report.reference.height,
                report.candidate.width,
                report.candidate.height
            ));
            if heatmap_asked {
                lines.push("heat map: not written (the sizes differ)".into());
            }
        }
        Some(m) => {
            lines.push(format!(
                "coverage IoU: {:.4} (at least {})",
                m.coverage_iou, t.min_coverage
            ));
            lines.push(format!(
                "ꟻLIP: mean {:.4} (at most {}), median {:.4}, p90 {:.4}, p99 {:.4}, max {:.4}",
                m.flip.mean, t.max_flip, m.flip.median, m.flip.p90, m.flip.p99, m.flip.max
            ));
            let psnr = m
                .psnr
                .map_or("∞ (identical)".into(), |p| format!("{p:.2} dB"));
            lines.push(format!("RMSE: {:.5}, PSNR: {psnr}", m.rmse));
            if let Some(path) = &report.heatmap {
                lines.push(format!("heat map: {path}"));
            }
        }
    }
    lines.join("\n") + "\n"
}
