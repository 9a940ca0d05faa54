//! The Vim syntax of `editors/vim/` in real editors: headless Neovim
//! (Debian's 0.7, which has no semantic tokens) and Vim each run
//! tests/editors/syntax.vim with only `editors/vim/` and their own runtime
//! on the runtime path. A `.txt` scene must be detected by its first word,
//! in any case (`Camera`), and a `.txt` note must not; the highlight group under the cursor at a
//! comment, a section keyword, an attribute, a number, a string and a
//! texture path must be ours, link to the standard group, and end where
//! the standard group ends (`synIDattr(synIDtrans(synID(…)))`).
//!
//! Without the editor on PATH a test prints that it was skipped, and fails
//! under CI (`support::under_ci`) (.ci/run installs Debian's `neovim` and `vim`).

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::support;

const SCRIPT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/editors/syntax.vim");
const RUNTIME: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/editors/vim");

/// A header comment, then the section keyword that makes a `.txt` a scene;
/// a string with a `#` in it, a bare path, an unterminated string.
const SCENE: &str = "# a scène\ncamera 40\nsphere dimension 1 center 0 0 -5.5e1\n  texture \"wood #22.ppm\" # a path\nplane texture wood.ppm\n  color \"open # x\nsphere1 -1x\n";

/// The probes (line:column, columns in bytes as Vim counts them) and what
/// each must show: our group, the standard group it links to, and the end
/// of the links in the editor's default colours.
const EXPECTED: [&str; 11] = [
    "1:1 raytracerComment Comment Comment",
    "2:1 raytracerSection Keyword Statement",
    "2:8 raytracerNumber Number Constant",
    "3:8 raytracerAttribute Identifier Identifier",
    "3:31 raytracerNumber Number Constant",
    "4:11 raytracerString String Constant",
    "4:26 raytracerComment Comment Comment",
    "5:15 raytracerPath String Constant",
    "6:9 raytracerStringError Error Error",
    // A word that only starts like a keyword or a number is neither.
    "7:1 - - -",
    "7:9 - - -",
];

/// Run the script in `editor` (with `args` before it) and return its report.
fn report(editor: &str, args: &[&str], dir: &Path) -> String {
    let scene = support::write(dir, "scene.txt", SCENE);
    let plain = support::write(dir, "notes.txt", "Some notes\nsphere of influence\n");
    // A scene whose first keyword is in another case is still a scene (the
    // parser reads it, with a `syntax::keyword_case` fix).
    let capital = support::write(dir, "hw1.txt", "Camera 40\nsphere dimension 1\n");
    let out = dir.join(format!("{editor}.out"));
    let probes: Vec<&str> = EXPECTED
        .iter()
        .map(|line| line.split(' ').next().unwrap())
        .collect();
    let mut child = Command::new(editor)
        .args(args)
        .args(["-S", SCRIPT])
        .env("RAYTRACER_VIM", RUNTIME)
        .env("SCENE", &scene)
        .env("PLAIN", &plain)
        .env("CAPITAL", &capital)
        .env("PROBES", probes.join(" "))
        .env("OUT", &out)
        .env("HOME", dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("start {editor}: {e}"));
    let deadline = Instant::now() + Duration::from_secs(30);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("{editor} did not finish within 30 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let output = child.wait_with_output().unwrap();
    let report = std::fs::read_to_string(&out).unwrap_or_default();
    eprintln!(
        "{editor} report:\n{report}\n{editor} stderr:\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert_eq!(output.status.code(), Some(0), "{report}");
    report
}

fn check(editor: &str, args: &[&str]) {
    let test = format!("the {editor} syntax test");
    if !support::tool_available(editor, &test, &format!("apt-get install {editor}")) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let report = report(editor, args, dir.path());
    let mut expected = vec![
        "plain filetype text",
        "capital filetype raytracer",
        "scene filetype raytracer",
        "commentstring # %s",
    ];
    expected.extend(EXPECTED);
    assert_eq!(report.lines().collect::<Vec<_>>(), expected);
}

#[test]
fn neovim_highlights_a_scene_with_the_vim_syntax() {
    check("nvim", &["--headless", "-u", "NONE", "-i", "NONE", "-n"]);
}

#[test]
fn vim_highlights_a_scene_with_the_vim_syntax() {
    check("vim", &["-N", "-u", "NONE", "-i", "NONE", "-n", "-es"]);
}
