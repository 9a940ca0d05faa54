//! `raytracer convert` end to end, and `.json` scenes through `check` and
//! `render`: output to stdout and to `-o`, exit codes, nothing written for
//! a bad scene, diagnostics with JSON line and column.

use std::path::Path;
use std::process::{Output, Stdio};

use crate::support::command;

const SCENE: &str = "camera 4\nsphere\n  dimension 1\n  center 0 0 -5\n  color .5 .25 1\n\
                     light location 0 5 0 color 1 1 1\n";
const CANONICAL: &str =
    "camera 4\n\nsphere\n  dimension 1\n  center 0 0 -5\n  color 0.5 0.25 1\n\n\
                         light\n  location 0 5 0\n  color 1 1 1\n";

fn raytracer(args: &[&str], dir: &Path) -> Output {
    command(args)
        .current_dir(dir)
        .output()
        .expect("run raytracer")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8(bytes.to_vec()).unwrap()
}

#[test]
fn converts_to_stdout_and_back() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.txt"), SCENE).unwrap();
    let json = raytracer(&["convert", "s.txt", "--to", "json"], dir.path());
    assert_eq!(json.status.code(), Some(0), "{}", text(&json.stderr));
    assert!(text(&json.stdout).starts_with("{\n  \"format\": \"raytracer-scene/1\",\n"));
    std::fs::write(dir.path().join("s.json"), &json.stdout).unwrap();
    let back = raytracer(&["convert", "s.json", "--to", "scene"], dir.path());
    assert_eq!(back.status.code(), Some(0), "{}", text(&back.stderr));
    assert_eq!(text(&back.stdout), CANONICAL);
    let pov = raytracer(&["convert", "s.json", "--to", "pov"], dir.path());
    assert_eq!(pov.status.code(), Some(0));
    assert!(text(&pov.stdout).contains("sphere {\n  <0, 0, 5>, 1\n"));
}

#[test]
fn json_flag_is_short_for_to_json() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.txt"), SCENE).unwrap();
    let long = raytracer(&["convert", "s.txt", "--to", "json"], dir.path());
    let short = raytracer(&["convert", "--json", "s.txt"], dir.path());
    assert_eq!(short.status.code(), Some(0), "{}", text(&short.stderr));
    assert_eq!(text(&short.stdout), text(&long.stdout));

    let both = raytracer(&["convert", "s.txt", "--json", "--to", "pov"], dir.path());
    assert_eq!(both.status.code(), Some(2));
    assert!(text(&both.stderr).contains("cannot be used with"));
    let neither = raytracer(&["convert", "s.txt"], dir.path());
    assert_eq!(neither.status.code(), Some(2));
    assert!(text(&neither.stderr).contains("expected `--to json`, `--to scene` or `--to pov`"));
}

/// `-o` names the output language by its extension when `--to` does not
/// (issue 56: `-o x.json` still demanded `--to`), and an extension that
/// names none is a usage error that writes nothing.
#[test]
fn the_output_extension_picks_the_language() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.txt"), SCENE).unwrap();
    for (output, starts) in [
        ("x.json", "{\n  \"format\": \"raytracer-scene/1\","),
        ("x.scene", "camera 4\n"),
        ("x.pov", "// "),
    ] {
        let run = raytracer(&["convert", "s.txt", "-o", output], dir.path());
        assert_eq!(
            run.status.code(),
            Some(0),
            "{output}: {}",
            text(&run.stderr)
        );
        let written = std::fs::read_to_string(dir.path().join(output)).unwrap();
        assert!(written.starts_with(starts), "{output}: {written}");
    }
    let unknown = raytracer(&["convert", "s.txt", "-o", "x.png"], dir.path());
    assert_eq!(unknown.status.code(), Some(2));
    assert!(
        text(&unknown.stderr).contains("cannot tell the output language from `x.png`"),
        "{}",
        text(&unknown.stderr)
    );
    assert!(!dir.path().join("x.png").exists());
}

#[test]
fn json_scenes_check_and_render_like_scene_text() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.txt"), SCENE).unwrap();
    let json = raytracer(
        &["convert", "s.txt", "--to", "json", "-o", "s.json"],
        dir.path(),
    );
    assert_eq!(json.status.code(), Some(0), "{}", text(&json.stderr));
    assert!(json.stdout.is_empty());
    let check = raytracer(&["check", "s.json"], dir.path());
    assert_eq!(check.status.code(), Some(0), "{}", text(&check.stdout));
    assert_eq!(text(&check.stdout), "s.json: ok; effects: shadows\n");
    for scene in ["s.txt", "s.json"] {
        let out = format!("{scene}.ppm");
        let render = raytracer(&["render", scene, &out, "--quiet"], dir.path());
        assert_eq!(render.status.code(), Some(0), "{}", text(&render.stderr));
    }
    let from_text = std::fs::read(dir.path().join("s.txt.ppm")).unwrap();
    let from_json = std::fs::read(dir.path().join("s.json.ppm")).unwrap();
    assert_eq!(from_text, from_json);
}

#[test]
fn scene_rules_apply_to_json_with_labels_on_the_json_text() {
    let dir = tempfile::tempdir().unwrap();
    let json = r#"{
  "format": "raytracer-scene/1",
  "camera": {"resolution": 4},
  "objects": [{"type": "sphere", "center": [0, 0, -5], "radius": -1}]
}
"#;
    std::fs::write(dir.path().join("bad.json"), json).unwrap();
    let check = raytracer(&["check", "bad.json", "--format", "short"], dir.path());
    assert_eq!(check.status.code(), Some(1));
    assert_eq!(
        text(&check.stdout),
        "bad.json:4:66: error[scene::dimension_not_positive]: the radius must be greater than 0, \
         found `-1`\nbad.json: 1 error, 0 warnings\n"
    );
}

#[test]
fn a_scene_with_errors_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("bad.json"),
        "{\"format\": \"raytracer-scene/1\",}",
    )
    .unwrap();
    let out = raytracer(
        &["convert", "bad.json", "--to", "scene", "-o", "out.txt"],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("json::syntax"),
        "{}",
        text(&out.stderr)
    );
    assert!(
        text(&out.stderr).contains("bad.json:1:31"),
        "{}",
        text(&out.stderr)
    );
    assert!(!dir.path().join("out.txt").exists());
    assert!(out.stdout.is_empty());
}

#[test]
fn unreadable_input_and_unwritable_output_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let missing = raytracer(&["convert", "missing.txt", "--to", "json"], dir.path());
    assert_eq!(missing.status.code(), Some(2));
    assert!(text(&missing.stderr).contains("io::read_scene"));

    std::fs::write(dir.path().join("s.txt"), SCENE).unwrap();
    let nowhere = raytracer(
        &[
            "convert",
            "s.txt",
            "--to",
            "json",
            "-o",
            "no/such/dir/s.json",
        ],
        dir.path(),
    );
    assert_eq!(nowhere.status.code(), Some(2));
    assert!(text(&nowhere.stderr).contains("io::write_output"));
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);

    let usage = raytracer(&["convert", "s.txt", "--to", "yaml"], dir.path());
    assert_eq!(usage.status.code(), Some(2));
}

#[test]
fn stdin_json_is_recognised_by_its_brace() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.txt"), SCENE).unwrap();
    let json = raytracer(&["convert", "s.txt", "--to", "json"], dir.path()).stdout;
    let mut child = command(&["convert", "-", "--to", "scene"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::io::Write::write_all(&mut child.stdin.take().unwrap(), &json).unwrap();
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout), CANONICAL);
}

#[test]
fn fix_rewrites_json_numbers_in_place() {
    let dir = tempfile::tempdir().unwrap();
    let json = r#"{"format": "raytracer-scene/1", "camera": {"resolution": 4},
  "objects": [{"type": "plane", "center": [0, -1, -5], "width": 4, "height": 4,
               "normal": [0, 2, 0], "headup": [0, 1, 1]}],
  "lights": [{"location": [0, 5, 0], "color": [1, 1, 1]}]}
"#;
    std::fs::write(dir.path().join("p.json"), json).unwrap();
    let fix = raytracer(&["check", "p.json", "--fix"], dir.path());
    assert_eq!(fix.status.code(), Some(0), "{}", text(&fix.stdout));
    let fixed = std::fs::read_to_string(dir.path().join("p.json")).unwrap();
    assert!(
        fixed.contains(r#""normal": [0, 2, 0], "headup": [0, 0, 1]"#),
        "{fixed}"
    );
    assert!(
        text(&fix.stdout).contains("p.json: ok"),
        "{}",
        text(&fix.stdout)
    );
}

/// A textured plane and sphere, naming their texture from a sibling folder.
const TEXTURED: &str = "camera 16\n\
    sphere dimension 1 center 0.5 0 -4 texture tex/wood.ppm\n\
    plane dimension 4 4 center 0 -1 -5 normal 0 1 0 headup 0 0 -1 texture \"tex/wood.ppm\"\n\
    light location 0 4 0 color 1 1 1\n";

/// `root/scenes/s.txt` naming `root/scenes/tex/wood.ppm`.
fn textured_tree() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    std::fs::create_dir_all(scenes.join("tex")).unwrap();
    let wood = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/wood_tex.ppm");
    std::fs::copy(wood, scenes.join("tex/wood.ppm")).unwrap();
    std::fs::write(scenes.join("s.txt"), TEXTURED).unwrap();
    dir
}

fn render_bytes(scene: &Path, cwd: &Path) -> Vec<u8> {
    let out = cwd.join("rendered.ppm");
    let scene = scene.display().to_string();
    let render = raytracer(&["render", &scene, "rendered.ppm", "--quiet"], cwd);
    assert_eq!(
        render.status.code(),
        Some(0),
        "{scene}: {}",
        text(&render.stderr)
    );
    let bytes = std::fs::read(&out).unwrap();
    std::fs::remove_file(out).unwrap();
    bytes
}

/// The texture paths a converted file names, in order: `texture PATH` or
/// `texture "PATH"` (scene text), `"texture": "PATH"` (JSON),
/// `image_map { ppm "PATH" … }` (POV-Ray).
fn texture_paths(converted: &str) -> Vec<String> {
    converted
        .lines()
        .map(str::trim)
        .filter_map(|line| {
            let quoted = |n| line.split('"').nth(n).map(str::to_string);
            if line.starts_with("\"texture\": ") {
                quoted(3)
            } else if line.contains("image_map") {
                quoted(1)
            } else {
                // Not POV-Ray's `texture {` blocks.
                let path = line.strip_prefix("texture ").filter(|p| *p != "{")?;
                quoted(1).or_else(|| Some(path.to_string()))
            }
        })
        .collect()
}

#[test]
fn converted_scenes_find_their_textures_from_any_folder() {
    let tree = textured_tree();
    let root = tree.path();
    let original = render_bytes(Path::new("scenes/s.txt"), root);
    for (folder, expected) in [
        ("out/a/b", "../../../scenes/tex/wood.ppm"),
        ("", "scenes/tex/wood.ppm"),
        ("scenes", "tex/wood.ppm"),
    ] {
        for (target, name) in [("json", "c.json"), ("scene", "c.txt"), ("pov", "c.pov")] {
            std::fs::create_dir_all(root.join(folder)).unwrap();
            let out = Path::new(folder).join(name).display().to_string();
            let convert = raytracer(
                &["convert", "scenes/s.txt", "--to", target, "-o", &out],
                root,
            );
            assert_eq!(convert.status.code(), Some(0), "{}", text(&convert.stderr));
            let written = std::fs::read_to_string(root.join(&out)).unwrap();
            let paths = texture_paths(&written);
            assert_eq!(
                paths,
                [expected, expected],
                "{target} in `{folder}`:\n{written}"
            );
            assert!(root.join(folder).join(expected).is_file());
            if target != "pov" {
                // Rendered from another working directory, the converted
                // scene is the same picture.
                assert_eq!(
                    render_bytes(&root.join(&out), root.join(folder).as_path()),
                    original,
                    "{out}"
                );
            }
        }
    }
}

#[test]
fn stdout_paths_are_relative_to_the_working_directory() {
    let tree = textured_tree();
    let root = tree.path();
    let deeper = root.join("scenes/tex");
    for (cwd, scene, expected) in [
        (root.to_path_buf(), "scenes/s.txt", "scenes/tex/wood.ppm"),
        (deeper.clone(), "../s.txt", "wood.ppm"),
    ] {
        let convert = raytracer(&["convert", scene, "--to", "scene"], &cwd);
        assert_eq!(convert.status.code(), Some(0), "{}", text(&convert.stderr));
        assert_eq!(texture_paths(&text(&convert.stdout)), [expected, expected]);
    }
    // Absolute paths stay as written.
    let absolute = root.join("scenes/tex/wood.ppm").display().to_string();
    let scene = TEXTURED.replace("tex/wood.ppm", &absolute);
    std::fs::write(root.join("abs.txt"), scene).unwrap();
    let convert = raytracer(&["convert", "../../abs.txt", "--json"], &deeper);
    assert_eq!(convert.status.code(), Some(0), "{}", text(&convert.stderr));
    assert_eq!(
        texture_paths(&text(&convert.stdout)),
        [absolute.clone(), absolute]
    );
}

/// `-o` into a folder that does not exist: the message names the folder,
/// not the temporary file the output was to be written to first.
#[test]
fn output_into_a_missing_folder_names_the_folder() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("s.txt"),
        "camera 4\nsphere dimension 1 center 0 0 -5\nlight location 0 5 0 color 1 1 1\n",
    )
    .unwrap();
    let output = raytracer(
        &["convert", "s.txt", "--to", "json", "-o", "missing/s.json"],
        dir.path(),
    );
    assert_eq!(output.status.code(), Some(2));
    let stderr = text(&output.stderr);
    assert!(
        stderr.contains("cannot write `missing/s.json`: the folder `missing` does not exist"),
        "{stderr}"
    );
    assert!(
        !stderr.contains(".tmp") && !stderr.contains(".raytracer-"),
        "{stderr}"
    );
}
