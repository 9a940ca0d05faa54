//! The summarising check (`raytracer check`) against the collecting one
//! (`render`, `convert`): on every scene of the repository and on generated
//! scenes, the same report, and a summary equal to the summary of the model
//! the collecting check builds.

use std::path::{Path, PathBuf};

use proptest::prelude::*;

use super::*;

/// Both checks of `bytes` named `name` in `dir`: the same human report,
/// and the same summary of a valid scene.
fn assert_same(name: &str, dir: &Path, bytes: &[u8]) {
    let collected = check::<Collect>(name, dir, bytes);
    let summarised = check::<Summarise>(name, dir, bytes);
    assert_eq!(
        summarised.report.render_human(100, false),
        collected.report.render_human(100, false),
        "{name}"
    );
    assert_eq!(
        summarised.checked,
        collected.checked.map(|c| Summary::of(&c.scene)),
        "{name}"
    );
}

/// `bytes` through the front end, each valid object handed to a sink of
/// kind `S`.
fn check<S: Sink>(name: &str, dir: &Path, bytes: &[u8]) -> Loaded<S::Scene> {
    let language = Language::of(Path::new(name), bytes);
    let (source, utf8_error) = SourceFile::from_bytes(name, dir, bytes);
    load_source::<S>(source, utf8_error, language, &mut HeaderReader, None).0
}

/// The scene files under `dir`, recursively.
pub(super) fn scenes_under(dir: &Path, found: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .expect("test folder readable")
        .map(|e| e.expect("test folder entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            scenes_under(&path, found);
        } else if path
            .extension()
            .is_some_and(|e| e == "txt" || e == "json" || e == "scene")
        {
            found.push(path);
        }
    }
}

#[test]
fn both_checks_agree_on_every_scene_in_the_repository() {
    let mut scenes = Vec::new();
    for dir in ["scenes", "tests/corpus/field", "tests/ui"] {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../..")
            .join(dir);
        scenes_under(&dir, &mut scenes);
    }
    assert!(scenes.len() > 40, "found {}", scenes.len());
    for path in &scenes {
        let bytes = std::fs::read(path).expect("scene readable");
        let dir = path.parent().expect("a scene has a folder");
        assert_same(&path.display().to_string(), dir, &bytes);
    }
}

/// A section of a small scene, valid or not: values drawn from a few small
/// numbers so that lights fall inside spheres, objects behind the camera,
/// and colors out of range often enough.
fn section() -> impl Strategy<Value = String> {
    let n = || prop::sample::select(vec!["0", "1", "-1", "2", "-5", "0.5", "1.5", "x"]);
    let v = move || (n(), n(), n()).prop_map(|(a, b, c)| format!("{a} {b} {c}"));
    prop_oneof![
        n().prop_map(|r| format!("camera {r}")),
        (
            n(),
            v(),
            prop::option::of(n()),
            any::<bool>(),
            prop::option::of(v())
        )
            .prop_map(|(r, c, reflect, textured, color)| {
                let mut s = format!("sphere dimension {r} center {c}");
                if let Some(reflect) = reflect {
                    s += &format!(" reflectivity {reflect}");
                }
                if textured {
                    s += " texture wood_tex.ppm";
                }
                if let Some(color) = color {
                    s += &format!(" color {color}");
                }
                s
            }),
        (v(), v(), v(), n()).prop_map(|(c, normal, headup, reflect)| format!(
            "plane dimension 1 1 center {c} normal {normal} headup {headup} reflectivity {reflect}"
        )),
        (v(), v()).prop_map(|(l, c)| format!("light location {l} color {c}")),
        Just("sphre dimension 1".to_string()),
    ]
}

proptest! {
    #[test]
    fn both_checks_agree_on_generated_scenes(
        sections in prop::collection::vec(section(), 0..12),
        camera_first in any::<bool>(),
    ) {
        let mut text = sections.join("\n");
        if camera_first {
            text = format!("camera 4\n{text}");
        }
        assert_same("t.txt", Path::new("scenes"), text.as_bytes());
    }
}
