//! `index.html`: one page that works offline from `file://` (styles inline,
//! no script, images from the report's own `images/`): the summary on top,
//! then one row per scene, worst first, with our image, the student's and
//! the ꟻLIP heat map side by side, the status, the metrics and the
//! program's stderr.

use std::fmt::Write;

use super::{status_name, Summary};
use crate::grade::{SceneResult, Status, STYLE};

/// The page for `summary`.
pub fn page(summary: &Summary) -> String {
    let mut html = String::new();
    let matched = summary
        .scenes
        .iter()
        .filter(|s| s.status == Status::Match)
        .count();
    let _ = write!(
        html,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
<title>raytracer grade: {score} / {max}</title><style>{STYLE}</style></head><body>\n\
<h1>{score} / {max} points</h1>\n<p>{matched} of {count} scenes match. Tracer: <code>{tracer}</code></p>\n",
        score = summary.score,
        max = summary.max_score,
        count = summary.scenes.len(),
        tracer = escape(&summary.tracer),
    );
    let _ = write!(html, "<p>");
    for status in [
        Status::Match,
        Status::Differs,
        Status::Crashed,
        Status::Timeout,
        Status::NoImage,
        Status::BadImage,
    ] {
        let n = summary.scenes.iter().filter(|s| s.status == status).count();
        if n > 0 {
            let name = status_name(status);
            let _ = write!(
                html,
                "<span class=\"status {name}\">{name}</span> {n} &nbsp; "
            );
        }
    }
    let s = &summary.sandbox;
    let _ = writeln!(
        html,
        "</p>\n<p>Limits: {} s wall clock, {} s CPU, {} MiB address space, {} MiB per file, \
{} processes; network {}. A scene matches when no aspect fails (geometry, shadows, reflection, \
textures, shading; see docs/grading.md); coverage IoU and ꟻLIP (bounds {} and {}) are shown, not judged.</p>",
        s.timeout_seconds,
        s.cpu_seconds,
        s.address_space_mib,
        s.max_file_size_mib,
        s.max_processes,
        if s.network_isolated {
            "isolated"
        } else {
            "not isolated"
        },
        summary.thresholds.min_coverage,
        summary.thresholds.max_flip,
    );
    let _ = writeln!(
        html,
        "<p id=\"sandbox\">Sandbox: {}; held: {}.</p>",
        if s.boxed { "a box per run" } else { "no box" },
        escape(&s.mechanisms.join(", "))
    );
    if let Some(build) = &summary.build {
        let outcome = match &build.reason {
            None => "built".to_string(),
            Some(reason) => format!(
                "<span class=\"status crashed\">build failed</span> {}",
                escape(reason)
            ),
        };
        let _ = write!(
            html,
            "<p id=\"build\">Build: <code>{}</code>, {outcome} in {:.2} s.</p>",
            escape(&build.command),
            build.seconds
        );
        if !build.ok {
            for stream in [&build.stdout, &build.stderr] {
                if !stream.trim().is_empty() {
                    let _ = write!(html, "<pre>{}</pre>", escape(stream.trim_end()));
                }
            }
        }
        html.push('\n');
    }
    html.push_str("<table>\n<tr><th>scene</th><th>status</th><th>images: ours, the student's, ꟻLIP error</th><th>metrics</th></tr>\n");
    for scene in &summary.scenes {
        row(&mut html, scene);
    }
    html.push_str("</table>\n</body></html>\n");
    html
}

/// One scene's row.
fn row(html: &mut String, scene: &SceneResult) {
    let name = status_name(scene.status);
    let _ = write!(
        html,
        "<tr class=\"scene\" id=\"{}\"><td><b>{}</b><br>{}<br>{} / {} points{}</td>\
<td><span class=\"status {name}\">{name}</span><br>{}</td><td>",
        anchor(&scene.scene),
        escape(&scene.scene),
        escape(&scene.description),
        scene.score,
        scene.points,
        if scene.robustness {
            format!("<br><i>{}</i>", escape(&super::robustness_words(scene)))
        } else {
            String::new()
        },
        escape(scene.reason.as_deref().unwrap_or("")),
    );
    // The three images side by side in one row that never wraps (its
    // width is the cell's least), then where each failed aspect differs:
    // red on our image, dimmed, wrapping as the width allows.
    html.push_str("<div class=\"figures\">");
    figure(html, Some(&scene.images.reference), "ours");
    figure(html, scene.images.student.as_deref(), "student");
    figure(html, scene.images.heatmap.as_deref(), "ꟻLIP");
    html.push_str("</div>");
    let differing: Vec<_> = scene.aspects.iter().filter(|a| a.image.is_some()).collect();
    if !differing.is_empty() {
        html.push_str("<div class=\"figures where\">");
        for aspect in differing {
            let caption = format!("where {} differs", aspect.aspect.name());
            figure(html, aspect.image.as_deref(), &caption);
        }
        html.push_str("</div>");
    }
    if !scene.aspects.is_empty() {
        html.push_str("<ul class=\"aspects\">");
        for aspect in &scene.aspects {
            let verdict = match (aspect.judged, aspect.pass) {
                (false, _) => "not judged:".to_string(),
                (true, pass) => format!(
                    "{} ({} / {} points):",
                    if pass { "passes" } else { "fails" },
                    aspect.score,
                    aspect.points
                ),
            };
            let _ = write!(
                html,
                "<li{}><b>{}</b> {verdict} {}</li>",
                if aspect.pass { "" } else { " class=\"fail\"" },
                aspect.aspect.name(),
                escape(&aspect.detail),
            );
        }
        html.push_str("</ul>");
    }
    if let Some(reading) = &scene.reading {
        let _ = write!(html, "<p>{}</p>", escape(reading));
    }
    html.push_str("</td><td>");
    if let (Some(iou), Some(flip), Some(rmse)) = (scene.coverage_iou, scene.flip, scene.rmse) {
        let psnr = scene.psnr.map_or("∞".into(), |p| format!("{p:.1} dB"));
        let _ = write!(
            html,
            "coverage IoU {iou:.4}<br>ꟻLIP mean {:.4}<br>ꟻLIP p99 {:.4}<br>RMSE {rmse:.5}<br>PSNR {psnr}<br>",
            flip.mean, flip.p99
        );
    }
    let _ = write!(html, "{:.2} s", scene.seconds);
    match (scene.exit_code, scene.signal) {
        (Some(code), _) => {
            let _ = write!(html, ", exit {code}");
        }
        (None, Some(signal)) => {
            let _ = write!(html, ", signal {signal}");
        }
        (None, None) => {}
    }
    if !scene.stderr.trim().is_empty() {
        let _ = write!(html, "<pre>{}</pre>", escape(scene.stderr.trim_end()));
    }
    html.push_str("</td></tr>\n");
}

/// The `id` of a scene's row, which class.html links to.
pub fn anchor(scene: &str) -> String {
    format!("scene-{}", crate::grade::slug(scene))
}

/// An image with its caption, or a grey box when there is none.
fn figure(html: &mut String, src: Option<&str>, caption: &str) {
    let _ = match src {
        Some(src) => write!(
            html,
            "<figure><img src=\"{}\" alt=\"{caption}\"><figcaption>{caption}</figcaption></figure>",
            escape(src)
        ),
        None => write!(
            html,
            "<figure><div class=\"none\">no image</div><figcaption>{caption}</figcaption></figure>"
        ),
    };
}

/// Text made safe inside HTML elements and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            _ => out.push(c),
        }
    }
    out
}
