//! The VS Code extension in `editors/vscode/`: its `npm test` (the TextMate
//! grammar against the annotated scenes of `editors/vscode/test/` with
//! vscode-tmgrammar-test, on VS Code's own TextMate engine, and the `.txt`
//! detection under node's test runner) passes, and `vsce package` builds a
//! `.vsix` holding the manifest, the grammar, the client and the language
//! client library it runs.
//!
//! The npm packages come from `npm ci` in `editors/vscode/` (.ci/run and
//! `make vsix` run it). Without npm, or without those packages, the test
//! prints that it was skipped, and fails under CI (`support::under_ci`).

use std::path::Path;
use std::process::{Command, Output};

use crate::support;

const EXTENSION: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/editors/vscode");

/// Skip (or fail under CI) when the tools are missing; true when present.
fn ready() -> bool {
    let npm = Command::new("npm")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    let installed = Path::new(EXTENSION)
        .join("node_modules/.bin/vscode-tmgrammar-test")
        .exists();
    let missing = match (npm, installed) {
        (false, _) => "npm is not installed",
        (true, false) => "the npm packages are not installed (`npm ci` in editors/vscode)",
        (true, true) => return true,
    };
    assert!(
        !support::under_ci(),
        "{missing}, and CI must run this test (.ci/run installs them)"
    );
    support::skipped(&format!("VS Code extension test: {missing}"));
    false
}

fn npm(args: &[&str]) -> Output {
    let output = Command::new("npm")
        .args(args)
        .current_dir(EXTENSION)
        .output()
        .expect("run npm");
    eprintln!(
        "npm {}:\n{}\n{}",
        args.join(" "),
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

#[test]
fn the_grammar_tests_pass() {
    if !ready() {
        return;
    }
    let output = npm(&["test"]);
    assert!(output.status.success());
    let stdout = String::from_utf8_lossy(&output.stdout);
    // Each annotated scene ran (the runner names the ones that passed).
    let scenes: Vec<String> = std::fs::read_dir(Path::new(EXTENSION).join("test"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".scene"))
        .collect();
    assert!(scenes.len() >= 2, "{scenes:?}");
    for scene in &scenes {
        assert!(
            stdout.contains(&format!("test/{scene} run successfuly")),
            "{scene} did not pass:\n{stdout}"
        );
    }
    assert!(stdout.contains("# fail 0"), "{stdout}");
}

#[test]
fn the_extension_packages_to_a_vsix() {
    if !ready() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let vsix = dir.path().join("raytracer-scene.vsix");
    let vsix_arg = vsix.display().to_string();
    let output = npm(&["run", "package", "--", "--out", &vsix_arg]);
    assert!(output.status.success());
    let bytes = std::fs::read(&vsix).expect("the .vsix was written");
    // A zip archive: its entries' names are stored as they are.
    assert!(bytes.starts_with(b"PK\x03\x04"));
    for entry in [
        "extension.vsixmanifest",
        "extension/package.json",
        "extension/extension.js",
        "extension/detect.js",
        "extension/language-configuration.json",
        "extension/syntaxes/raytracer.tmLanguage.json",
        "extension/node_modules/vscode-languageclient/package.json",
    ] {
        let found = bytes
            .windows(entry.len())
            .any(|window| window == entry.as_bytes());
        assert!(found, "{entry} is not in the .vsix");
    }
    let tests = b"extension/test/";
    assert!(
        !bytes.windows(tests.len()).any(|window| window == tests),
        "the tests were packaged"
    );
}
