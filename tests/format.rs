//! The formatter (`raytracer_scene::format` and `raytracer fmt`):
//!
//! - before/after fixtures: each file in tests/format/ and its formatted
//!   text as an insta snapshot;
//! - properties over the corpus (tests/corpus/field), scenes/ and generated
//!   scenes with comments and odd spacing: formatting is idempotent, keeps
//!   every comment, and never changes meaning (the same syntax tree but
//!   for the attributes' order, the same diagnostics, the same checked
//!   scene);
//! - one canonical form: over the corpus and scenes/, `convert --to scene`
//!   prints what `fmt` does, but for what the model does not keep;
//! - the command: `--check` lists and writes nothing, files are rewritten in
//!   place, syntax errors refuse, stdin goes to stdout, JSON is refused.

use crate::support;

use std::path::{Path, PathBuf};

use crate::support::{run, write};
use proptest::prelude::*;
use raytracer_scene::convert::scene_text::to_scene_text;
use raytracer_scene::format::{self as formatter, format};
use raytracer_scene::frontend::load_bytes;
use raytracer_scene::language::attributes_of;
use raytracer_scene::syntax::{self, trivia};

const FIXTURES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/format");
const CORPUS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/corpus/field");
const SCENES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes");

fn scene_files(dir: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "txt" || e == "scene"))
        .collect();
    files.sort();
    files
}

/// What a scene means to the toolchain: its diagnostics (code, message,
/// help and the text each label points at, each without comments and with
/// its whitespace collapsed, since a message may quote the source) and its
/// checked scene as JSON.
fn meaning(text: &str, dir: &Path) -> (Vec<String>, Option<String>) {
    let loaded = load_bytes("scene.txt", dir, text.as_bytes());
    // Longest first, so no comment's removal breaks a longer one.
    let mut comments = comments(text);
    comments.sort_by_key(|c| std::cmp::Reverse(c.len()));
    let plain = |s: &str| {
        let mut s = s.to_string();
        for comment in &comments {
            s = s.replace(comment.as_str(), " ");
        }
        s.split_whitespace()
            .map(canonical_number)
            .collect::<Vec<_>>()
            .join(" ")
    };
    let diagnostics = loaded
        .report
        .entries()
        .map(|e| {
            let at: Vec<String> = e
                .labels
                .iter()
                .map(|l| plain(&text[l.byte_offset..l.byte_offset + l.byte_length]))
                .collect();
            let help = e.help.as_deref().map(plain);
            format!("{} {} {help:?} {at:?}", e.code, plain(&e.message))
        })
        .collect();
    // Attributes move into the table's order, and their diagnostics with
    // them.
    let mut diagnostics: Vec<String> = diagnostics;
    diagnostics.sort();
    let scene = loaded
        .checked
        .map(|c| raytracer_scene::convert::json::to_json(&c.scene));
    (diagnostics, scene)
}

/// A word that quotes a number (`5e2`, `` `.5` ``) with the number as the
/// formatter spells it, its quotes and punctuation kept.
fn canonical_number(word: &str) -> String {
    let marks: &[char] = &['`', '"', '\'', '(', ')', ',', ':', ';', '?'];
    let core = word.trim_matches(marks);
    match core.parse::<f64>() {
        Ok(x) if x.is_finite() && core.chars().any(|c| c.is_ascii_digit()) => {
            word.replacen(core, &formatter::number(x), 1)
        }
        _ => word.to_string(),
    }
}

/// The syntax tree with each section's attributes in the language table's
/// order, as the formatter puts them (stable, what a section does not take
/// last).
fn in_table_order(text: &str) -> Vec<raytracer_scene::ast::Section> {
    let mut sections = syntax::parse(text).file.sections;
    for section in &mut sections {
        let table = attributes_of(&section.kind);
        section.attributes.sort_by_key(|a| {
            table
                .iter()
                .position(|spec| spec.attr_name() == *a.name)
                .unwrap_or(table.len())
        });
    }
    sections
}

fn comments(text: &str) -> Vec<String> {
    trivia::comments(text)
        .iter()
        .map(|s| text[s.start()..s.end()].trim_end().to_string())
        .collect()
}

/// Format `text` and assert the properties; returns the formatted text.
fn assert_formats_well(text: &str, dir: &Path, what: &str) -> String {
    let once = format(text).unwrap_or_else(|e| panic!("{what}: syntax errors {e:?}"));
    assert_eq!(format(&once).unwrap(), once, "{what}: not idempotent");
    assert_eq!(
        in_table_order(text),
        syntax::parse(&once).file.sections,
        "{what}: the tree changed\n{once}"
    );
    assert_eq!(meaning(text, dir), meaning(&once, dir), "{what}: meaning");
    // Every comment is kept; one moves with the attribute it stands by.
    let sorted = |text: &str| {
        let mut comments = comments(text);
        comments.sort();
        comments
    };
    assert_eq!(sorted(text), sorted(&once), "{what}: comments");
    once
}

#[test]
fn fixtures() {
    let files = scene_files(FIXTURES);
    assert!(files.len() >= 8, "{files:?}");
    for path in files {
        let text = std::fs::read_to_string(&path).unwrap();
        let name = path.file_stem().unwrap().to_str().unwrap().to_string();
        let formatted = assert_formats_well(&text, Path::new(FIXTURES), &name);
        insta::assert_snapshot!(name, formatted);
    }
}

#[test]
fn corpus_and_scenes_keep_their_meaning() {
    // SOURCE.txt is the corpus's provenance, in prose.
    let files: Vec<PathBuf> = [CORPUS, SCENES]
        .iter()
        .flat_map(|d| scene_files(d))
        .filter(|p| !p.ends_with("SOURCE.txt"))
        .collect();
    assert!(files.len() >= 15, "{files:?}");
    for path in files {
        let text = std::fs::read_to_string(&path).unwrap();
        let dir = path.parent().unwrap();
        assert_formats_well(&text, dir, &path.display().to_string());
    }
}

/// One canonical form (issue 56): over the corpus and scenes/, `convert
/// --to scene` prints what `fmt` does, but for what the model does not
/// keep: comments, an attribute at its default (`color 1 1 1`,
/// `reflectivity 0`) and the place of the lights (after the objects).
/// And `fmt` leaves the converted text as it is.
#[test]
fn fmt_and_convert_print_one_canonical_form() {
    let files: Vec<PathBuf> = [CORPUS, SCENES]
        .iter()
        .flat_map(|d| scene_files(d))
        .filter(|p| !p.ends_with("SOURCE.txt"))
        .collect();
    let mut compared = 0;
    for path in files {
        let text = std::fs::read_to_string(&path).unwrap();
        let loaded = load_bytes("scene.txt", path.parent().unwrap(), text.as_bytes());
        let Some(checked) = loaded.checked else {
            continue;
        };
        let converted = to_scene_text(&checked.scene).unwrap();
        assert_eq!(format(&converted).unwrap(), converted, "{}", path.display());
        let formatted = format(&text).unwrap();
        assert_eq!(
            as_the_model_keeps(&formatted),
            converted,
            "{}: fmt, without what the model does not keep, is not convert's",
            path.display()
        );
        compared += 1;
    }
    assert!(compared >= 15, "{compared} scenes compared");
}

/// Formatted scene text without what the model does not keep: comment
/// lines and trailing comments, attributes at their defaults, blank lines
/// between comments; the lights moved after the objects.
fn as_the_model_keeps(formatted: &str) -> String {
    let mut sections: Vec<Vec<String>> = Vec::new();
    for line in formatted.lines() {
        let code = line.split('#').next().unwrap_or_default().trim_end();
        if code.is_empty() {
            continue;
        }
        if matches!(code.trim(), "color 1 1 1" | "reflectivity 0")
            && sections.last().is_some_and(|s| s[0] != "light")
        {
            continue;
        }
        if code.starts_with(' ') {
            sections
                .last_mut()
                .expect("a section")
                .push(code.to_string());
        } else {
            sections.push(vec![code.to_string()]);
        }
    }
    sections.sort_by_key(|s| match s[0].as_str() {
        "light" => 2,
        code if code.starts_with("camera") => 0,
        _ => 1,
    });
    let blocks: Vec<String> = sections.iter().map(|s| s.join("\n") + "\n").collect();
    blocks.join("\n")
}

/// Found by the `format` fuzz target (fuzz/seeds/format/crash_missing_camera_order): with no
/// camera, the missing-camera error (placed at the file's start) and the
/// error at the first section came in one order before formatting and the
/// other after it, once the section moved to the start.
#[test]
fn a_file_without_camera_keeps_its_diagnostics_in_order() {
    for text in [
        "\u{feff}camerah\r ps4ere\r  dimension 1 # cr only\r\r\r# end",
        "  sphre center 0 0 -5\n",
        "\n\n# lead\nsphre\n",
    ] {
        assert_formats_well(text, Path::new(FIXTURES), &format!("{text:?}"));
    }
}

/// Whitespace between tokens: spaces, tabs, line ends of every kind, blank
/// lines, and sometimes a comment.
fn gap() -> impl Strategy<Value = String> {
    prop_oneof![
        Just(" ".to_string()),
        Just("\t".to_string()),
        Just("\n".to_string()),
        Just("\r\n  ".to_string()),
        Just("\n\n\n".to_string()),
        Just("\u{2028}".to_string()),
        "[ a-z#.]{0,8}".prop_map(|c| format!(" # {c}\n")),
        "[ a-z]{0,8}".prop_map(|c| format!("\n#{c}\n    ")),
    ]
}

fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        (-9i32..9).prop_map(|n| n.to_string()),
        (0u32..99).prop_map(|n| format!(".{n}")),
        (-5i32..5).prop_map(|n| format!("{n}.")),
        (1u32..9, -3i32..3).prop_map(|(m, e)| format!("{m}e{e}")),
        Just("+0".to_string()),
    ]
}

/// One section's tokens: a keyword (sometimes misspelt), values, and
/// attributes of any section with one to four numbers or a path.
fn section() -> impl Strategy<Value = Vec<String>> {
    let keyword = prop_oneof![
        Just("camera"),
        Just("sphere"),
        Just("plane"),
        Just("light"),
        Just("sphre")
    ];
    let name = prop_oneof![
        Just("dimension"),
        Just("center"),
        Just("color"),
        Just("reflectivity"),
        Just("normal"),
        Just("headup"),
        Just("location"),
        Just("colr"),
    ];
    let attribute = prop_oneof![
        (name, prop::collection::vec(number(), 1..4)).prop_map(|(n, v)| {
            let mut tokens = vec![n.to_string()];
            tokens.extend(v);
            tokens
        }),
        Just(vec!["texture".to_string(), "\"a #b.ppm\"".to_string()]),
        Just(vec!["texture".to_string(), "wood.ppm".to_string()]),
    ];
    (
        keyword,
        prop::collection::vec(number(), 0..2),
        prop::collection::vec(attribute, 0..5),
    )
        .prop_map(|(k, args, attributes)| {
            let mut tokens = vec![k.to_string()];
            tokens.extend(args);
            tokens.extend(attributes.into_iter().flatten());
            tokens
        })
}

fn scene() -> impl Strategy<Value = String> {
    (
        prop::collection::vec(section(), 0..5),
        prop::collection::vec(gap(), 64),
    )
        .prop_map(|(sections, gaps)| {
            let mut text = String::new();
            for (token, gap) in sections.into_iter().flatten().zip(gaps.iter().cycle()) {
                text.push_str(&token);
                text.push_str(gap);
            }
            text
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    #[test]
    fn generated_scenes_keep_their_meaning(text in scene()) {
        assert_formats_well(&text, Path::new(FIXTURES), &format!("{text:?}"));
    }
}

#[test]
fn check_lists_changed_files_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let messy = write(dir.path(), "messy.txt", "camera 4 sphere dimension 1 # r\n");
    let tidy = write(dir.path(), "tidy.scene", "camera 4\n");
    write(dir.path(), "notes.md", "camera 4 sphere");
    let output = run(&["fmt", "--check", dir.path().to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(
        String::from_utf8_lossy(&output.stdout),
        format!("{messy}\n")
    );
    assert_eq!(
        std::fs::read_to_string(&messy).unwrap(),
        "camera 4 sphere dimension 1 # r\n"
    );
    let output = run(&["fmt", &messy, &tidy]);
    assert_eq!(output.status.code(), Some(0), "{output:?}");
    assert_eq!(
        std::fs::read_to_string(&messy).unwrap(),
        "camera 4\n\nsphere\n  dimension 1 # r\n"
    );
    let output = run(&["fmt", "--check", &messy, &tidy]);
    assert_eq!(output.status.code(), Some(0), "{output:?}");
    assert!(output.stdout.is_empty());
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(names.len(), 3, "no temporary file left behind");
}

#[test]
fn syntax_errors_refuse_and_leave_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let text = "camera 1.2.3\nsphere   dimension 1\n";
    let bad = write(dir.path(), "bad.txt", text);
    let output = run(&["fmt", &bad]);
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("syntax::invalid_number"), "{stderr}");
    assert!(stderr.contains("not formatted"), "{stderr}");
    assert_eq!(std::fs::read_to_string(&bad).unwrap(), text);
    let latin1 = dir.path().join("latin1.txt");
    std::fs::write(&latin1, b"camera 4 # caf\xe9\n").unwrap();
    let output = run(&["fmt", latin1.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(std::fs::read(&latin1).unwrap(), b"camera 4 # caf\xe9\n");
}

#[test]
fn stdin_json_and_missing_files() {
    use std::io::Write;
    let mut child = support::command(&["fmt", "-"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(b"camera 4 sphere center 0 0 0")
        .unwrap();
    let output = child.wait_with_output().unwrap();
    assert_eq!(output.status.code(), Some(0));
    assert_eq!(
        String::from_utf8_lossy(&output.stdout),
        "camera 4\n\nsphere\n  center 0 0 0\n"
    );
    let dir = tempfile::tempdir().unwrap();
    let json = write(dir.path(), "s.json", "{}");
    let output = run(&["fmt", &json, "missing.txt"]);
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("io::fmt_json"), "{stderr}");
    assert!(stderr.contains("missing.txt"), "{stderr}");
}
