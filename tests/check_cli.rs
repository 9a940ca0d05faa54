//! `raytracer check` end to end: exit codes, the three formats, several
//! files in one run, `--deny-warnings`, `--fix` and `--unsafe-fixes`.

use std::process::Output;

use crate::support::{run, write};

const CLEAN: &str = "camera 4\nsphere\n  dimension 1\n  center 0 0 -5\n  reflectivity .5\nlight location 0 5 0 color 1 1 1\n";
const WARNS: &str = "camera 4\nplane\n\tdimension 4 4\n\tcenter 0 -1 -5\n\tnormal 0 -1 -1   # tilted\n\theadup 0 1 0\nlight location 0 5 0 color 1 1 1\n";
const ERRORS: &str = "camera 4\nsphere\n  dimension -1\n  center 0 -5\n";

fn check(args: &[&str]) -> Output {
    run(&[&["check"], args].concat())
}

fn stdout(output: &Output) -> String {
    String::from_utf8(output.stdout.clone()).unwrap()
}

#[test]
fn exit_codes_follow_the_spec() {
    let dir = tempfile::tempdir().unwrap();
    let clean = write(dir.path(), "clean.txt", CLEAN);
    let warns = write(dir.path(), "warns.txt", WARNS);
    let errors = write(dir.path(), "errors.txt", ERRORS);
    let missing = dir.path().join("missing.txt").display().to_string();

    assert_eq!(check(&[&clean]).status.code(), Some(0));
    assert_eq!(check(&[&warns]).status.code(), Some(0));
    assert_eq!(check(&[&warns, "--deny-warnings"]).status.code(), Some(1));
    assert_eq!(check(&[&errors, &clean]).status.code(), Some(1));
    // An unreadable file is exit 2, and the others are still checked.
    let output = check(&[&missing, &errors]);
    assert_eq!(output.status.code(), Some(2));
    assert!(stdout(&output).contains("errors.txt: 2 errors, 0 warnings"));
    assert!(String::from_utf8_lossy(&output.stderr).contains("cannot read scene"));
    assert_eq!(check(&["--format", "yaml", &clean]).status.code(), Some(2));
}

#[test]
fn a_folder_with_a_scene_that_cannot_be_read_exits_1_and_names_it() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "clean.txt", CLEAN);
    // Over the size limit (sparse, so nothing is written): found by the
    // walk, it cannot be read as a scene.
    let big = std::fs::File::create(dir.path().join("big.txt")).unwrap();
    big.set_len(raytracer_scene::limits::MAX_SCENE_BYTES + 1)
        .unwrap();
    let folder = dir.path().display().to_string();
    for command in ["check", "fmt"] {
        let output = run(&[command, &folder]);
        assert_eq!(output.status.code(), Some(1), "{command}: {output:?}");
        let said = String::from_utf8_lossy(&output.stderr);
        assert!(said.contains("big.txt"), "{command}: {said}");
    }
    let output = check(&["--format", "json", &folder]);
    assert_eq!(output.status.code(), Some(1));
    assert!(stdout(&output).contains("big.txt"), "{output:?}");
    // Named on the command line, the same file is the caller's mistake.
    let named = dir.path().join("big.txt").display().to_string();
    assert_eq!(check(&[&named]).status.code(), Some(2));
}

#[test]
fn human_output_ends_with_a_summary_and_the_effects_used() {
    let dir = tempfile::tempdir().unwrap();
    let clean = write(dir.path(), "clean.txt", CLEAN);
    let warns = write(dir.path(), "warns.txt", WARNS);
    let out = stdout(&check(&[&clean, &warns]));
    assert!(
        out.contains("clean.txt: ok; effects: shadows, reflection\n"),
        "{out}"
    );
    assert!(out.contains("scene::headup_not_perpendicular"), "{out}");
    assert!(
        out.contains("warns.txt: 0 errors, 1 warning; effects: shadows\n"),
        "{out}"
    );
    // Not a terminal: no colour codes.
    assert!(!out.contains('\u{1b}'), "{out}");
}

#[test]
fn short_output_is_one_line_per_diagnostic() {
    let dir = tempfile::tempdir().unwrap();
    let errors = write(dir.path(), "errors.txt", ERRORS);
    let out = stdout(&check(&["--format", "short", &errors]));
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 3, "{out}");
    assert!(lines[0].ends_with("errors.txt:3:13: error[scene::dimension_not_positive]: the radius must be greater than 0, found `-1`"), "{out}");
    assert!(
        lines[1].contains(":4:3: error[scene::wrong_value_count]"),
        "{out}"
    );
}

#[test]
fn json_is_one_array_for_every_file() {
    let dir = tempfile::tempdir().unwrap();
    let warns = write(dir.path(), "warns.txt", WARNS);
    let errors = write(dir.path(), "errors.txt", ERRORS);
    let output = check(&["--format", "json", &warns, &errors]);
    assert_eq!(output.status.code(), Some(1));
    let json: serde_json::Value =
        serde_json::from_slice(&output.stdout).expect("one JSON document");
    let entries = json.as_array().expect("an array");
    assert_eq!(entries.len(), 3);
    let first = &entries[0];
    assert_eq!(first["code"], "scene::headup_not_perpendicular");
    assert_eq!(first["severity"], "warning");
    assert_eq!(first["file"], warns.as_str());
    assert_eq!(
        first["help"],
        "the renderer projects it onto the plane: write `headup 0 0.5 -0.5`"
    );
    let label = &first["labels"][0];
    assert_eq!(label["line"], 5);
    assert_eq!(label["column"], 9);
    assert_eq!(label["byte_offset"], 54);
    assert_eq!(label["byte_length"], 7);
    assert_eq!(entries[1]["severity"], "error");
    assert_eq!(entries[2]["file"], errors.as_str());
}

#[test]
fn fix_rewrites_only_the_fixed_values_and_rechecks() {
    let dir = tempfile::tempdir().unwrap();
    let warns = write(dir.path(), "warns.txt", WARNS);
    let output = check(&["--fix", &warns]);
    assert_eq!(output.status.code(), Some(0));
    let out = stdout(&output);
    // A non-unit normal is valid and stays as written (issue 14): no
    // diagnostic, so no fix.
    assert!(!out.contains("normal`"), "{out}");
    assert!(
        out.contains("warns.txt:6:11: applied: project `headup` onto the plane"),
        "{out}"
    );
    assert!(out.contains("warns.txt: ok; effects: shadows"), "{out}");
    assert_eq!(
        std::fs::read_to_string(&warns).unwrap(),
        "camera 4\nplane\n\tdimension 4 4\n\tcenter 0 -1 -5\n\tnormal 0 -1 -1   # tilted\n\theadup 0 0.5 -0.5\nlight location 0 5 0 color 1 1 1\n"
    );
    // Nothing is left to fix, and no temporary file is left behind.
    let again = stdout(&check(&["--fix", &warns]));
    assert!(!again.contains("applied"), "{again}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

/// `--fix` applies the safe fixes and counts the unsafe ones it left;
/// `--unsafe-fixes` alone applies both (issue 56: it was a usage error).
#[test]
fn fix_counts_the_unsafe_fixes_left_and_unsafe_fixes_implies_fix() {
    let dir = tempfile::tempdir().unwrap();
    let text = "camera 4\nsphere\n  dimension 1\n  center 0 0 -5\n  colour 1 0 0\n  reflectivity 70\nlight location 0 5 0 color 1 1 1\n";
    let scene = write(dir.path(), "s.txt", text);
    let out = stdout(&check(&["--fix", &scene]));
    assert!(
        out.ends_with("2 more fixes can be applied with `--unsafe-fixes` (review them: each is a likely intent, not a certainty)\n"),
        "{out}"
    );
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), text);
    let output = check(&["--unsafe-fixes", &scene]);
    assert_eq!(output.status.code(), Some(0), "{output:?}");
    let out = stdout(&output);
    assert!(
        out.contains("s.txt:5:3: applied: replace `colour` with `color`"),
        "{out}"
    );
    assert!(!out.contains("--unsafe-fixes"), "{out}");
    assert_eq!(
        std::fs::read_to_string(&scene).unwrap(),
        text.replace("colour", "color").replace("70", "0.7")
    );
}

#[test]
fn fix_leaves_files_without_safe_fixes_untouched() {
    let dir = tempfile::tempdir().unwrap();
    let errors = write(dir.path(), "errors.txt", ERRORS);
    let output = check(&["--fix", &errors]);
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(std::fs::read_to_string(&errors).unwrap(), ERRORS);
}

#[test]
fn folders_are_walked_in_order_and_non_scenes_skipped() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    // Written out of order: the report must be in name order anyway.
    write(root, "z_last.scene", ERRORS);
    write(root, "sub/b.txt", WARNS);
    write(root, "a.txt", CLEAN);
    write(
        root,
        "README.txt",
        "Submissions for part 4.\nOne scene per student.\n",
    );
    write(root, "package.json", r#"{"name": "submissions"}"#);
    write(
        root,
        "c.json",
        r#"{"format": "raytracer-scene/1", "camera": {"resolution": 4}}"#,
    );
    write(root, "texture.ppm", "P3 1 1 255 0 0 0\n");
    write(root, ".gitignore", "ignored/\n");
    write(root, "ignored/broken.txt", ERRORS);
    write(root, ".hidden/broken.txt", ERRORS);

    let output = check(&["--format", "short", &root.display().to_string()]);
    assert_eq!(output.status.code(), Some(1));
    let out = stdout(&output);
    let summaries: Vec<&str> = out
        .lines()
        .filter(|l| !l.contains("]: "))
        .map(|l| l.strip_prefix(&format!("{}/", root.display())).unwrap_or(l))
        .collect();
    assert_eq!(
        summaries,
        [
            "README.txt: skipped, not a scene: its first word `Submissions` is not a section keyword",
            "a.txt: ok; effects: shadows, reflection",
            "c.json: 0 errors, 2 warnings; effects: none",
            "package.json: skipped, not a scene: a JSON file without `\"raytracer-scene/` in its first 64 KiB",
            "sub/b.txt: 0 errors, 1 warning; effects: shadows",
            "z_last.scene: 2 errors, 0 warnings",
            "checked 4 files: 2 errors, 3 warnings; 2 files skipped (not a scene)",
        ],
        "{out}"
    );
    // The same run twice gives the same bytes.
    let again = check(&["--format", "short", &root.display().to_string()]);
    assert_eq!(stdout(&again), out);
}

#[test]
fn a_file_named_explicitly_is_always_checked() {
    let dir = tempfile::tempdir().unwrap();
    let readme = write(dir.path(), "README.txt", "Submissions for part 4.\n");
    let output = check(&["--format", "short", &readme]);
    assert_eq!(output.status.code(), Some(1));
    assert!(stdout(&output).contains("error[scene::unknown_section]"));
}

#[test]
fn a_folder_and_a_file_together_get_one_total() {
    let dir = tempfile::tempdir().unwrap();
    let clean = write(dir.path(), "one/clean.txt", CLEAN);
    write(dir.path(), "two/warns.txt", WARNS);
    let two = dir.path().join("two").display().to_string();
    let output = check(&[&clean, &two]);
    assert_eq!(output.status.code(), Some(0));
    let out = stdout(&output);
    assert!(
        out.ends_with(
            "warns.txt: 0 errors, 1 warning; effects: shadows\nchecked 2 files: 0 errors, 1 warning\n"
        ),
        "{out}"
    );
    let empty = tempfile::tempdir().unwrap();
    let output = check(&[&empty.path().display().to_string()]);
    assert_eq!(output.status.code(), Some(0));
    assert_eq!(stdout(&output), "checked 0 files: 0 errors, 0 warnings\n");
}

/// `raytracer check scenes/` says nothing but the warnings that are a
/// scene's point, each named (`scene::no_light`) in the scene's leading
/// comment (issue 56: six warnings, said nowhere to be meant).
#[test]
fn shipped_scenes_warn_only_where_their_comment_says_so() {
    let scenes = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut folders = vec![scenes];
    let mut checked = 0;
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
                continue;
            }
            if path.extension().is_none_or(|e| e != "txt") {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            let header: String = text
                .lines()
                .take_while(|l| l.starts_with('#'))
                .collect::<Vec<_>>()
                .join(" ");
            let loaded = raytracer_scene::frontend::load(&path).unwrap();
            for entry in loaded.report.entries() {
                assert!(
                    entry.severity == "warning" && header.contains(&format!("`{}`", entry.code)),
                    "{}: `{}` ({}) is not named in its leading comment as the scene's point",
                    path.display(),
                    entry.code,
                    entry.severity
                );
            }
            checked += 1;
        }
    }
    assert!(checked >= 15, "{checked} scenes");
}
