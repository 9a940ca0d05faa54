//! `class.html`: one page (styles inline, no script, no network) with a
//! row per student and a column per scene; each cell is the scene's
//! status, linked to the scene's row in that student's report
//! (`STUDENT/index.html#scene-…`), with its reason as a tooltip. The
//! student's name links to their report; the last row counts the matches
//! of each scene. Every name is escaped, and each link percent-encodes
//! the student's folder name, so a name may hold any character.

use std::fmt::Write;
use std::os::unix::ffi::OsStrExt;

use percent_encoding::{percent_encode, AsciiSet, NON_ALPHANUMERIC};

use super::{status_name, Class, Student};
use crate::grade::report::html::{anchor, escape};
use crate::grade::{Status, STYLE};

/// Characters kept as they are in a link's path segment.
const SEGMENT: &AsciiSet = &NON_ALPHANUMERIC
    .remove(b'-')
    .remove(b'.')
    .remove(b'_')
    .remove(b'~');

/// The page for `class`.
pub fn page(class: &Class) -> String {
    let mut html = String::new();
    let _ = write!(
        html,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
<title>raytracer grade: class of {n}</title><style>{STYLE}</style></head><body>\n\
<h1>Class of {n}</h1>\n<p>{n} students, {scenes} scenes. Each cell links to the scene in the student's report; \
a scene that differs names the aspects that failed: <b>geom</b> geometry, <b>shad</b> shadows, \
<b>refl</b> reflection, <b>tex</b> textures, <b>col</b> shading (colours).</p>\n\
<table class=\"class\">\n<tr><th>student</th><th>score</th><th>build</th>",
        n = class.students.len(),
        scenes = class.scenes.len(),
    );
    for scene in &class.scenes {
        let _ = write!(html, "<th class=\"scene\">{}</th>", escape(scene));
    }
    html.push_str("</tr>\n");
    for student in &class.students {
        row(&mut html, class, student);
    }
    html.push_str("<tr><th>matches</th><td></td><td></td>");
    for scene in &class.scenes {
        let matched = class
            .students
            .iter()
            .filter(|s| s.scene(scene).is_some_and(|s| s.status == Status::Match))
            .count();
        let _ = write!(html, "<td>{matched} / {}</td>", class.students.len());
    }
    html.push_str("</tr>\n</table>\n</body></html>\n");
    html
}

/// One student's row.
fn row(html: &mut String, class: &Class, student: &Student) {
    let report = format!("{}/index.html", folder_link(student));
    let summary = &student.summary;
    let build = match &summary.build {
        None => String::new(),
        Some(build) if build.ok => "ok".into(),
        Some(build) => format!(
            "<a class=\"status failed\" href=\"{report}#build\" title=\"{}\">failed</a>",
            escape(build.reason.as_deref().unwrap_or(""))
        ),
    };
    let _ = write!(
        html,
        "<tr class=\"student\"><td><a href=\"{report}\">{}</a></td><td>{} / {}</td><td>{build}</td>",
        escape(&student.name()),
        summary.score,
        summary.max_score,
    );
    for scene in &class.scenes {
        match student.scene(scene) {
            Some(result) => {
                let name = status_name(result.status);
                let _ = write!(
                    html,
                    "<td><a class=\"status {name}\" href=\"{report}#{}\" title=\"{}\">{}</a></td>",
                    anchor(scene),
                    escape(result.reason.as_deref().unwrap_or("")),
                    cell_text(result.status, result.reason.as_deref()),
                );
            }
            None => html.push_str("<td class=\"missing\">not graded</td>"),
        }
    }
    html.push_str("</tr>\n");
}

/// What a cell says: the status, or for a scene that differs in some
/// aspects, those aspects in short (`geom`, `shad`, `refl`, `tex`, `col`),
/// so the table stays narrow with many scenes.
fn cell_text(status: Status, reason: Option<&str>) -> String {
    let short = |aspect: &str| match aspect {
        "geometry" => Some("geom"),
        "shadows" => Some("shad"),
        "reflection" => Some("refl"),
        "textures" => Some("tex"),
        "shading" => Some("col"),
        _ => None,
    };
    if status == Status::Differs {
        if let Some(aspects) = reason
            .map(|r| r.split(", ").map(short).collect::<Option<Vec<_>>>())
            .and_then(|a| a.filter(|a| !a.is_empty()))
        {
            return aspects.join(" ");
        }
    }
    status_name(status).to_string()
}

/// The student's folder as a relative link: every byte of its name that
/// could end or change the link percent-encoded.
fn folder_link(student: &Student) -> String {
    percent_encode(student.folder.as_bytes(), SEGMENT).to_string()
}
