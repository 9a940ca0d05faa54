//! Helpers shared by the integration tests: running the binary, writing
//! and listing files, scene text to IR and to pixels in-process, and the
//! corpus copied beside a wood texture; headless Chromium (`browser`) and
//! the hostile-input set (`hostile`); the grading tests' set-up
//! (`grading`); a command run where no namespace can be had
//! (`namespaces`).

#![allow(dead_code)] // each test file uses its own subset

pub mod browser;
pub mod grading;
pub mod hostile;
pub mod namespaces;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use raytracer_render::ir;
use raytracer_render::render::Precision;
use raytracer_render::render::{self, Counters, Image, Options};
use raytracer_scene::frontend::load_bytes;

/// Whether the tests run under CI: `CI` set, and not empty, `0` or
/// `false` (in any case). Every test that needs a tool CI installs asks
/// this before it may skip: under CI a missing tool is a failure.
pub fn under_ci() -> bool {
    std::env::var_os("CI").is_some_and(|ci| {
        let ci = ci.to_string_lossy();
        let ci = ci.trim();
        !(ci.is_empty() || ci == "0" || ci.eq_ignore_ascii_case("false"))
    })
}

/// Whether the tests run as root.
pub fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| o.stdout.trim_ascii() == b"0")
}

/// Say a test was skipped where `cargo test` shows it: libtest captures
/// `eprintln!` of a passing test, not a write to the stderr handle.
pub fn skipped(why: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "SKIPPED {why}");
}

/// Whether `program --version` (or `program version`) runs. When it does
/// not, the test that asked (`test`) fails under CI, which installs every
/// program the tests drive (`.ci/run`, with `install`), and otherwise says
/// it was skipped.
pub fn tool_available(program: &str, test: &str, install: &str) -> bool {
    // `--version`, or `version` for the programs that take a command
    // (Go).
    let found = ["--version", "version"].iter().any(|flag| {
        Command::new(program)
            .arg(flag)
            .output()
            .is_ok_and(|o| o.status.success())
    });
    if !found {
        assert!(
            !under_ci(),
            "`{program}` is not installed, and CI must run {test}: .ci/run installs it ({install})"
        );
        skipped(&format!("{test}: `{program}` is not installed ({install})"));
    }
    found
}

/// The first `sh` block after the heading line `heading` (with its `#`s)
/// in `doc`, a path under docs/.
pub fn doc_recipe(doc: &str, heading: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(doc);
    let docs = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("read {doc}: {e}"));
    let section = &docs[docs
        .find(&format!("\n{heading}\n"))
        .unwrap_or_else(|| panic!("{doc} has no `{heading}`"))..];
    let block = &section[section.find("```sh\n").expect("an sh block") + 6..];
    block[..block.find("```").expect("closing fence")].to_string()
}

/// Every `sh` block of the section under the heading line `heading` (with
/// its `#`s) in `doc`, a path under docs/, in order: the section ends at
/// the next heading of its level or above.
pub fn doc_recipes(doc: &str, heading: &str) -> Vec<String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(doc);
    let docs = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("read {doc}: {e}"));
    let start = docs
        .find(&format!("\n{heading}\n"))
        .unwrap_or_else(|| panic!("{doc} has no `{heading}`"))
        + heading.len()
        + 2;
    let level = heading.bytes().take_while(|&b| b == b'#').count();
    let mut blocks = Vec::new();
    let mut block: Option<String> = None;
    for line in docs[start..].lines() {
        match &mut block {
            Some(text) if line == "```" => {
                blocks.push(std::mem::take(text));
                block = None;
            }
            Some(text) => {
                text.push_str(line);
                text.push('\n');
            }
            None if line == "```sh" => block = Some(String::new()),
            None => {
                let hashes = line.bytes().take_while(|&b| b == b'#').count();
                if (1..=level).contains(&hashes) && line[hashes..].starts_with(' ') {
                    break;
                }
            }
        }
    }
    blocks
}

/// Run `script` (a recipe from the docs) with bash in `dir`, the folder of
/// the binary under test first on PATH so the recipe's `raytracer` is this
/// build.
pub fn run_recipe(dir: &Path, script: &str) -> Output {
    recipe_command(dir, script).output().expect("run bash")
}

/// The command [`run_recipe`] runs, for a test that adds to its
/// environment.
pub fn recipe_command(dir: &Path, script: &str) -> Command {
    let bin_dir = Path::new(bin()).parent().expect("bin folder");
    let path = std::env::join_paths(std::iter::once(bin_dir.to_path_buf()).chain(
        std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default()),
    ))
    .expect("PATH");
    let mut command = Command::new("bash");
    command
        .args(["-euo", "pipefail", "-c", script])
        .current_dir(dir)
        .env("PATH", &path)
        .env_remove("COLUMNS");
    command
}

/// The `raytracer` binary under test: cargo builds it from the current
/// source before it builds these tests, and names it here.
pub fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_raytracer")
}

/// The binary with `args`, diagnostics at their default width (no
/// `$COLUMNS`). `output()` closes its stdin.
pub fn command(args: &[&str]) -> Command {
    let mut command = Command::new(bin());
    command.args(args).env_remove("COLUMNS");
    command
}

/// Run the binary with `args` and collect its output.
pub fn run(args: &[&str]) -> Output {
    command(args).output().expect("run raytracer")
}

/// Write `text` to `dir/name` (creating its folders) and return the path
/// as a string.
pub fn write(dir: &Path, name: &str, text: impl AsRef<[u8]>) -> String {
    let path = dir.join(name);
    std::fs::create_dir_all(path.parent().expect("a folder")).expect("create folders");
    std::fs::write(&path, text).expect("write file");
    path.display().to_string()
}

/// The names in `dir`, sorted (no `.raytracer-*.tmp` may be among them).
pub fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("read folder")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// The scene text checked and lowered (textures resolve against `dir`),
/// optionally at another resolution. Panics with the diagnostics when the
/// scene has errors.
pub fn lower_in(text: &str, dir: &Path, resolution: Option<u32>) -> ir::Scene {
    let loaded = load_bytes("test.txt", dir, text.as_bytes());
    let Some(mut checked) = loaded.checked else {
        panic!(
            "scene has errors:\n{}",
            loaded.report.render_human(80, false)
        );
    };
    if let Some(resolution) = resolution {
        checked.scene.camera.resolution = resolution;
    }
    ir::lower(checked)
}

/// [`lower_in`] for scenes without textures.
pub fn lower(text: &str) -> ir::Scene {
    lower_in(text, Path::new("."), None)
}

/// Render with default options in f64.
pub fn render(scene: &ir::Scene) -> (Image, Counters) {
    render::render(Precision::F64, scene, &Options::default(), &|| {})
}

/// The pixel at column `i`, row `j`.
pub fn pixel(image: &Image, i: u32, j: u32) -> [u8; 3] {
    let at = 3 * (j * image.size + i) as usize;
    [image.rgb[at], image.rgb[at + 1], image.rgb[at + 2]]
}

/// `round(clamp(c)·255)` per channel, as docs/rendering.md writes pixels.
pub fn quantized(c: [f64; 3]) -> [u8; 3] {
    c.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8)
}

/// The course corpus, kept in the repository (`tests/corpus/field`, whose
/// `SOURCE.txt` says where each file comes from).
pub fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/corpus/field")
}

/// The corpus scene files copied into a temporary folder with the
/// corpus's `wood_tex.ppm` beside them.
pub fn corpus_copy() -> (tempfile::TempDir, Vec<PathBuf>) {
    let source = corpus_dir();
    assert!(
        source.is_dir(),
        "the scene corpus is missing: {}",
        source.display()
    );
    let dir = tempfile::tempdir().expect("temp dir");
    let mut scenes = Vec::new();
    for entry in std::fs::read_dir(&source).expect("read corpus") {
        let path = entry.expect("entry").path();
        let name = path.file_name().expect("name").to_string_lossy();
        let is_scene = name.ends_with(".txt") || name.ends_with(".scene");
        if !is_scene || name == "SOURCE.txt" {
            continue;
        }
        let copy = dir.path().join(path.file_name().expect("name"));
        std::fs::copy(&path, &copy).expect("copy scene");
        scenes.push(copy);
    }
    scenes.sort();
    std::fs::copy(source.join("wood_tex.ppm"), dir.path().join("wood_tex.ppm"))
        .expect("copy texture");
    (dir, scenes)
}
