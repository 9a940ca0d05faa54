//! Hostile text on the way to a terminal: scene text, file names, texture
//! paths and arguments holding terminal escapes (`ESC [2J` clears the
//! screen, `ESC ] 0;… BEL` retitles the window), C1 controls, DEL, a lone
//! carriage return, and text-direction controls ("Trojan Source"). Every
//! terminal format shows them as `\u{…}` escapes with labels still under
//! their characters (snapshots); JSON keeps them exactly.

use std::ffi::OsStr;
use std::os::unix::ffi::OsStrExt;
use std::path::Path;
use std::process::{Command, Output};

use crate::support::bin;
use raytracer_scene::frontend::load_bytes;

/// A scene whose comments, attribute names and texture path hold every kind
/// of hidden character.
const SCENE: &str = "# \x1b[2J clears the screen\n\
camera 4\n\
sphere\n\
  dimension 1 \x1b]0;pwned\x07\n\
  center 0 0 -5 # \u{9b}31m and \x7f and \r overwrite\n\
  texture \"wood\u{202e}txt.ppm\"\n";

/// A file name holding an escape sequence and a right-to-left override.
const NAME: &[u8] = b"evil\x1b[31m\xe2\x80\xae.txt";

/// Every hidden character a test scene holds, none of which may reach a
/// terminal raw.
const HIDDEN: [&str; 6] = ["\x1b", "\x07", "\u{9b}", "\x7f", "\r", "\u{202e}"];

fn assert_no_hidden(text: &str) {
    for hidden in HIDDEN {
        assert!(
            !text.contains(hidden),
            "{hidden:?} reached the terminal raw:\n{text}"
        );
    }
}

/// Run the binary in `dir` with uncoloured output at the default width.
fn run_in(dir: &Path, args: &[&OsStr]) -> Output {
    Command::new(bin())
        .args(args)
        .current_dir(dir)
        .env_remove("COLUMNS")
        .env("NO_COLOR", "1")
        .output()
        .expect("run raytracer")
}

fn scene_dir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(dir.path().join(OsStr::from_bytes(NAME)), SCENE).expect("write scene");
    dir
}

fn snapshot(name: &str, text: &str) {
    insta::with_settings!({
        snapshot_path => "snapshots",
        prepend_module_to_snapshot => false,
        omit_expression => true,
    }, {
        insta::assert_snapshot!(name, text);
    });
}

#[test]
fn human_diagnostics_escape_scene_text_and_file_names_with_labels_aligned() {
    let dir = scene_dir();
    let check: &OsStr = "check".as_ref();
    let output = run_in(dir.path(), &[check, OsStr::from_bytes(NAME)]);
    assert_eq!(output.status.code(), Some(1), "{output:?}");
    let stdout = String::from_utf8(output.stdout).expect("UTF-8");
    assert_no_hidden(&stdout);
    // The label under the attribute spans its escaped text exactly: the
    // `┬` line starts where the escaped name starts on the line above.
    let lines: Vec<&str> = stdout.lines().collect();
    let source_line = lines
        .iter()
        .position(|l| l.contains("dimension 1 \\u{1b}]0;pwned\\u{7}"))
        .expect("escaped source line");
    let underline = lines[source_line + 1];
    let name_column = lines[source_line].find("\\u{1b}").expect("escape");
    let mark_column = underline.find('─').expect("underline");
    assert_eq!(
        lines[source_line][..name_column].chars().count(),
        underline[..mark_column].chars().count(),
        "the label is not under the escaped text:\n{stdout}"
    );
    snapshot("hostile_text-human", &stdout);
}

#[test]
fn short_diagnostics_escape_and_json_keeps_the_text_exactly() {
    let dir = scene_dir();
    let args = |format: &str| {
        let output = run_in(
            dir.path(),
            &[
                "check".as_ref(),
                "--format".as_ref(),
                format.as_ref(),
                OsStr::from_bytes(NAME),
            ],
        );
        assert_eq!(output.status.code(), Some(1), "{output:?}");
        String::from_utf8(output.stdout).expect("UTF-8")
    };
    let short = args("short");
    assert_no_hidden(&short);
    snapshot("hostile_text-short", &short);

    let json: serde_json::Value = serde_json::from_str(&args("json")).expect("JSON");
    let diagnostics = json.as_array().expect("array");
    let name = std::str::from_utf8(NAME).expect("UTF-8 name");
    assert!(diagnostics.iter().all(|d| d["file"] == name), "{json:#}");
    let message = |code: &str| {
        diagnostics
            .iter()
            .find(|d| d["code"] == code)
            .unwrap_or_else(|| panic!("no {code} in {json:#}"))["message"]
            .as_str()
            .expect("message")
            .to_string()
    };
    assert_eq!(
        message("scene::unknown_attribute"),
        "unknown attribute `\x1b]0;pwned\x07` in `sphere`"
    );
    assert_eq!(
        message("scene::texture_not_found"),
        "cannot read texture `wood\u{202e}txt.ppm`"
    );
    assert!(message("scene::text_direction_control").contains("U+202E"));
}

#[test]
fn coloured_diagnostics_hold_no_escape_but_their_own_colours() {
    let loaded = load_bytes("evil\x1b[31m.txt", Path::new("."), SCENE.as_bytes());
    let coloured = loaded.report.render_human(100, true);
    assert!(coloured.contains("\x1b["), "no colour at all:\n{coloured}");
    // Every ESC left is miette's own SGR colour sequence: `ESC [ digits;… m`.
    for (at, _) in coloured.match_indices('\x1b') {
        let rest = &coloured[at + 1..];
        let end = rest.find('m').expect("SGR end");
        assert!(
            rest.starts_with('[') && rest[1..end].chars().all(|c| c.is_ascii_digit() || c == ';'),
            "an escape that is not a colour at byte {at}: {:?}",
            &rest[..end.min(20)]
        );
    }
    let plain = loaded.report.render_human(100, false);
    assert_no_hidden(&plain);
    assert!(plain.contains("evil\\u{1b}[31m.txt"), "{plain}");
}

#[test]
fn failures_usage_errors_and_summaries_escape_paths() {
    let dir = scene_dir();
    // A failure (exit 2) naming the output path.
    let output = run_in(
        dir.path(),
        &[
            "render".as_ref(),
            OsStr::from_bytes(NAME),
            "out\x1b]0;x\x07.bmp".as_ref(),
        ],
    );
    assert_eq!(output.status.code(), Some(2), "{output:?}");
    let stderr = String::from_utf8(output.stderr).expect("UTF-8");
    assert_no_hidden(&stderr);
    assert!(stderr.contains("out\\u{1b}]0;x\\u{7}.bmp"), "{stderr}");

    // A scene that cannot be read (exit 2), in the human format.
    let output = run_in(dir.path(), &["check".as_ref(), "gone\x1b[2J.txt".as_ref()]);
    assert_eq!(output.status.code(), Some(2), "{output:?}");
    let stderr = String::from_utf8(output.stderr).expect("UTF-8");
    assert_no_hidden(&stderr);
    assert!(stderr.contains("gone\\u{1b}[2J.txt"), "{stderr}");

    // A usage error from the argument parser quoting the bad value.
    let output = run_in(
        dir.path(),
        &[
            "render".as_ref(),
            "--spp".as_ref(),
            "\u{202e}4\x1b[2J\x07".as_ref(),
            "a.txt".as_ref(),
            "b.png".as_ref(),
        ],
    );
    assert_eq!(output.status.code(), Some(2), "{output:?}");
    let stderr = String::from_utf8(output.stderr).expect("UTF-8");
    assert_no_hidden(&stderr);
    assert!(stderr.contains("invalid value '\\u{202e}4"), "{stderr}");
}

#[test]
fn render_warnings_are_escaped() {
    let dir = tempfile::tempdir().expect("temp dir");
    let name = OsStr::from_bytes(b"warn\x1b[2J.txt");
    std::fs::write(
        dir.path().join(name),
        "# \u{202e} hidden \x1b[2J\ncamera 2\nsphere\n  dimension 1\n  center 0 0 -5\n",
    )
    .expect("write scene");
    let output = run_in(dir.path(), &["render".as_ref(), name, "out.png".as_ref()]);
    assert_eq!(output.status.code(), Some(0), "{output:?}");
    let stderr = String::from_utf8(output.stderr).expect("UTF-8");
    assert_no_hidden(&stderr);
    assert!(stderr.contains("scene::text_direction_control"), "{stderr}");
    assert!(stderr.contains("# \\u{202e} hidden \\u{1b}[2J"), "{stderr}");
    assert!(stderr.contains("warn\\u{1b}[2J.txt"), "{stderr}");
    assert!(dir.path().join("out.png").is_file());
}

#[test]
fn fix_reports_escape_the_file_name() {
    let dir = tempfile::tempdir().expect("temp dir");
    let name = OsStr::from_bytes(b"fix\x1b]0;x\x07.txt");
    std::fs::write(
        dir.path().join(name),
        "camera 2\nplane\n  dimension 1 1\n  center 0 0 -5\n  normal 0 0 2\n  headup 0 1 1\n",
    )
    .expect("write scene");
    let output = run_in(dir.path(), &["check".as_ref(), "--fix".as_ref(), name]);
    assert_eq!(output.status.code(), Some(0), "{output:?}");
    let stdout = String::from_utf8(output.stdout).expect("UTF-8");
    assert_no_hidden(&stdout);
    assert!(
        // A non-unit normal is valid and stays as written (issue 14); the
        // headup projection is the fix here.
        stdout.contains("fix\\u{1b}]0;x\\u{7}.txt:6:14: applied: project `headup` onto the plane"),
        "{stdout}"
    );
}
