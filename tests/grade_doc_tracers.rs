//! Every `raytracer grade --tracer …` command line that README.md and
//! docs/grading.md show, run as written (in code blocks and in inline
//! code) in a folder holding what they name: the exported suite as
//! `suite/`, the course's options as `course.json`, and the student's
//! program as `./mytracer` (`/path/to/student/tracer` is replaced by its
//! path). Each must grade, with no scene `crashed`: the program started
//! on every scene. The forms a `--tracer` cannot take (a script beside
//! the program) are refused with the `--student` form in
//! tests/grade_cli.rs (`usage_errors_exit_2`).

use std::os::unix::fs::PermissionsExt;
use std::path::Path;

use serde_json::Value;

use crate::support;

/// The `raytracer grade --tracer` command lines of `doc`: whole lines of
/// its code blocks, and inline code spans.
fn command_lines(doc: &str) -> Vec<String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(doc);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("read {doc}: {e}"));
    let mut lines = Vec::new();
    let mut in_block = false;
    for line in text.lines() {
        if line.starts_with("```") {
            in_block = !in_block;
            continue;
        }
        if in_block {
            if line.starts_with("raytracer grade --tracer") {
                lines.push(line.to_string());
            }
            continue;
        }
        for (i, span) in line.split('`').enumerate() {
            if i % 2 == 1 && span.starts_with("raytracer grade --tracer") {
                lines.push(span.to_string());
            }
        }
    }
    lines
}

#[test]
fn every_documented_tracer_command_grades() {
    let lines: Vec<String> = ["README.md", "docs/grading.md"]
        .iter()
        .flat_map(|doc| command_lines(doc))
        .collect();
    assert!(lines.len() >= 5, "{lines:?}");
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    assert!(
        support::run(&["grade", "--export-suite", d.join("suite").to_str().unwrap()])
            .status
            .success()
    );
    support::write(d, "course.json", "{}");
    // A tracer that writes an image of the wrong size: every scene
    // differs, none crashes.
    let tracer = support::write(
        d,
        "mytracer",
        "#!/bin/sh\nprintf 'P3\\n1 1\\n255\\n0 0 0\\n' > \"$2\"\n",
    );
    std::fs::set_permissions(&tracer, std::fs::Permissions::from_mode(0o755)).unwrap();
    for line in &lines {
        let script = line
            .replace("/path/to/student/tracer", &tracer)
            .replace("/tmp/warm", "warm");
        // One cache for all: each line renders no reference again.
        let script = if script.contains("--cache") {
            script
        } else {
            script.replacen("raytracer grade", "raytracer grade --cache cache", 1)
        };
        let output = support::run_recipe(d, &script);
        let stderr = String::from_utf8_lossy(&output.stderr);
        let expected = if script.contains("|| [ $? -eq 1 ]") {
            0
        } else {
            1
        };
        assert_eq!(output.status.code(), Some(expected), "{line}: {stderr}");
        // The report folder: the word after `-o` (no documented one is quoted).
        let words: Vec<&str> = script.split_whitespace().collect();
        let report = words[words.iter().position(|w| *w == "-o").unwrap() + 1];
        let summary: Value = serde_json::from_str(
            &std::fs::read_to_string(d.join(report).join("summary.json")).unwrap(),
        )
        .unwrap();
        let scenes = summary["scenes"].as_array().unwrap();
        assert!(!scenes.is_empty(), "{line}");
        for scene in scenes {
            assert_ne!(scene["status"], "crashed", "{line}: {scene}");
        }
        std::fs::remove_dir_all(d.join(report)).unwrap();
    }
}
