//! `class.csv`: one row per student (`student`, `score`, `max_score`,
//! `build`: empty, `ok` or `failed`; when the suite has robustness
//! scenes, `robustness_matched` and `robustness_scenes`: how many of
//! those the student's image matched, of how many graded, whatever their
//! points), then one column per scene with the
//! points the student earned on it, empty when the student was not graded
//! on it. A text cell that a spreadsheet would take for a formula (it
//! starts with `=`, `+`, `-`, `@`, a tab or a carriage return) is written
//! with a `'` before it.

use super::Class;

/// The table of `class`.
pub fn csv(class: &Class) -> String {
    let mut writer = csv::Writer::from_writer(Vec::new());
    let mut header = vec![
        "student".to_string(),
        "score".into(),
        "max_score".into(),
        "build".into(),
    ];
    let robust = class
        .students
        .iter()
        .any(|s| s.summary.scenes.iter().any(|scene| scene.robustness));
    if robust {
        header.extend(["robustness_matched".into(), "robustness_scenes".into()]);
    }
    header.extend(class.scenes.iter().map(|scene| text(scene)));
    let mut rows = vec![header];
    for student in &class.students {
        let summary = &student.summary;
        let build = match &summary.build {
            None => "",
            Some(build) if build.ok => "ok",
            Some(_) => "failed",
        };
        let mut row = vec![
            text(&student.name()),
            summary.score.to_string(),
            summary.max_score.to_string(),
            build.to_string(),
        ];
        if robust {
            let scenes = summary.scenes.iter().filter(|s| s.robustness);
            let matched = scenes
                .clone()
                .filter(|s| s.status == crate::grade::Status::Match)
                .count();
            row.extend([matched.to_string(), scenes.count().to_string()]);
        }
        row.extend(class.scenes.iter().map(|scene| {
            student
                .scene(scene)
                .map_or_else(String::new, |s| s.score.to_string())
        }));
        rows.push(row);
    }
    for row in rows {
        writer
            .write_record(&row)
            .expect("writing to memory cannot fail");
    }
    String::from_utf8(writer.into_inner().expect("writing to memory cannot fail"))
        .expect("the cells are UTF-8")
}

/// A text cell, never read as a formula: one whose first character, or
/// first after white space, starts a formula in a spreadsheet (`=`, `+`,
/// `-`, `@`, or their fullwidth forms, which some spreadsheets fold to
/// them), or that starts with a tab or a carriage return, is quoted.
fn text(cell: &str) -> String {
    const STARTS: [char; 8] = ['=', '+', '-', '@', '＝', '＋', '－', '＠'];
    if cell.starts_with(['\t', '\r']) || cell.trim_start().starts_with(STARTS) {
        format!("'{cell}")
    } else {
        cell.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::{csv, text};
    use crate::grade::class::{Class, Student, StudentSummary};

    #[test]
    fn robustness_scenes_are_counted_apart() {
        let summary: StudentSummary = serde_json::from_value(serde_json::json!({
            "score": 1.0, "max_score": 1.0, "build": null,
            "scenes": [
                {"scene": "a.txt", "status": "match", "reason": null, "score": 1.0},
                {"scene": "b.txt", "status": "match", "reason": null, "score": 0.0, "robustness": true},
                {"scene": "c.txt", "status": "differs", "reason": "shadows", "score": 0.0, "robustness": true}
            ]
        }))
        .unwrap();
        let class = Class {
            students: vec![Student {
                folder: "alice".into(),
                summary,
            }],
            scenes: vec!["a.txt".into(), "b.txt".into(), "c.txt".into()],
        };
        assert_eq!(
            csv(&class),
            "student,score,max_score,build,robustness_matched,robustness_scenes,a.txt,b.txt,c.txt\n\
             alice,1,1,,1,2,1,0,0\n"
        );
    }

    #[test]
    fn a_formula_is_not_a_formula() {
        assert_eq!(text("=HYPERLINK(\"x\")"), "'=HYPERLINK(\"x\")");
        assert_eq!(text(" =1+1"), "' =1+1");
        assert_eq!(text("\u{3000}=1+1"), "'\u{3000}=1+1");
        assert_eq!(text("＝1+1"), "'＝1+1");
        assert_eq!(text("alice"), "alice");
        assert_eq!(text("alice = bob"), "alice = bob");
    }
}
