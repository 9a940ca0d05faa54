//! A fix never makes a file worse: for every row of the rule registry and
//! every mistake students bring from other languages (`=`, brackets,
//! semicolons, colons, another case, commas, a value missing or one too
//! many), applying every fix the check offers, safe and unsafe, gives a
//! file whose re-check has fewer problems, no code it did not have, and
//! every line the student wrote that the fixes are not about. Where the
//! mistake is only punctuation or case, the fixed file is the scene as
//! meant, value for value. Generated exhaustively from the registry, so a
//! new attribute is covered when it is added. The same holds for JSON
//! scenes, each row's rule broken in its JSON fields, whose help lines
//! show JSON.

use std::collections::BTreeSet;
use std::path::Path;

use serde_json::{json, Value};

use raytracer_scene::ast::SectionKind;
use raytracer_scene::convert::json::to_json;
use raytracer_scene::fix::{self, Applicability};
use raytracer_scene::frontend::load_bytes;
use raytracer_scene::language::{self, Arity, Key};

/// The folder the scenes are checked in: the shipped scenes', which holds
/// `wood_tex.ppm`.
fn dir() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes"))
}

/// A valid scene made of the registry's example lines, each section with
/// every attribute (the sphere with its texture instead of its colour when
/// `textured`), as (section keyword, lines).
fn base(textured: bool) -> Vec<(String, Vec<String>)> {
    let mut sections = vec![("camera".to_string(), Vec::new())];
    for (kind, spec) in language::rows() {
        let Key::Attribute(name) = &spec.name else {
            continue;
        };
        let wanted = match (kind.clone(), name.as_str()) {
            (SectionKind::Sphere, "texture") => textured,
            (SectionKind::Sphere, "color") => !textured,
            (_, "texture") => false,
            _ => true,
        };
        if !wanted {
            continue;
        }
        if sections.last().map(|(k, _)| k.as_str()) != Some(kind.as_str()) {
            sections.push((kind.as_str().to_string(), Vec::new()));
        }
        let mut line = spec.example.to_string();
        // The light above the objects, not inside the sphere.
        if kind == SectionKind::Plane && name.as_str() == "center" {
            line = "center 0 -1 -5".into();
        }
        sections.last_mut().expect("pushed").1.push(line);
    }
    sections
}

fn text_of(sections: &[(String, Vec<String>)], camera: &str) -> String {
    let mut out = String::new();
    for (keyword, lines) in sections {
        if keyword == "camera" {
            out.push_str(camera);
            out.push('\n');
            continue;
        }
        out.push_str(keyword);
        out.push('\n');
        for line in lines {
            out.push_str("  ");
            out.push_str(line);
            out.push('\n');
        }
    }
    out
}

/// The mistakes, each a name and how it rewrites `name v1 v2 …`; the flag
/// says the mistake is only punctuation or case, so the fix must give the
/// line back as meant.
/// How a mistake rewrites an attribute's name and values.
type Rewrite = fn(&str, &[&str]) -> String;

const MISTAKES: [(&str, bool, Rewrite); 13] = [
    ("equals", true, |n, v| format!("{n} = {}", v.join(" "))),
    ("equals, tight", true, |n, v| format!("{n}={}", v.join(" "))),
    ("parentheses", true, |n, v| {
        format!("{n} ({})", v.join(", "))
    }),
    ("brackets", true, |n, v| format!("{n} [{}]", v.join(", "))),
    ("brackets, tight", true, |n, v| {
        format!("{n} [{}]", v.join(","))
    }),
    ("semicolon", true, |n, v| format!("{n} {};", v.join(" "))),
    ("colon", true, |n, v| format!("{n}: {}", v.join(" "))),
    ("upper case", true, |n, v| {
        format!("{} {}", n.to_uppercase(), v.join(" "))
    }),
    ("capitalised", true, |n, v| {
        format!("{}{} {}", n[..1].to_uppercase(), &n[1..], v.join(" "))
    }),
    ("commas", false, |n, v| format!("{n} {}", v.join(", "))),
    ("missing value", false, |n, v| {
        format!("{n} {}", v[..v.len() - 1].join(" "))
    }),
    ("extra value", false, |n, v| {
        format!("{n} {} 7", v.join(" "))
    }),
    ("case and colon", true, |n, v| {
        format!("{}: {}", n.to_uppercase(), v.join(" "))
    }),
];

struct Checked {
    codes: Vec<String>,
    fixed: String,
    /// How many fixes were applied.
    applied: usize,
}

fn check(text: &str) -> Checked {
    let loaded = load_bytes("scene.txt", dir(), text.as_bytes());
    let codes = loaded.report.entries().map(|e| e.code).collect();
    let fixes = loaded.report.fixes_up_to(Applicability::Unsafe);
    let (fixed, applied) = fix::apply(text, fixes);
    Checked {
        codes,
        fixed,
        applied: applied.len(),
    }
}

/// Lines with their blanks trimmed, blank lines left out.
fn lines(text: &str) -> Vec<String> {
    text.lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>().join(" "))
        .filter(|l| !l.is_empty())
        .collect()
}

#[test]
fn every_fix_leaves_a_better_file() {
    let mut cases = 0;
    let mut failures = Vec::new();
    for textured in [false, true] {
        let sections = base(textured);
        let camera = language::CAMERA.example;
        let meant = text_of(&sections, camera);
        assert!(
            check(&meant).codes.is_empty(),
            "the base scene is valid:\n{meant}{:?}",
            check(&meant).codes
        );
        // Every line of every section, and the camera's.
        let mut targets: Vec<(usize, Option<usize>)> = vec![(0, None)];
        for (s, (_, lines)) in sections.iter().enumerate() {
            targets.extend((0..lines.len()).map(|l| (s, Some(l))));
        }
        for (s, l) in targets {
            let original = match l {
                Some(l) => sections[s].1[l].clone(),
                None => camera.to_string(),
            };
            let mut words = original.split_whitespace();
            let name = words.next().expect("a name");
            let values: Vec<&str> = words.collect();
            let is_path = language::rows()
                .any(|(_, spec)| spec.name.as_str() == name && spec.arity == Arity::Path);
            for (mistake, only_marks, write) in MISTAKES {
                // A path takes only marks; one value, no commas.
                if (is_path && !only_marks) || (mistake == "commas" && values.len() < 2) {
                    continue;
                }
                cases += 1;
                let wrong = write(name, &values);
                let mut mutated = sections.clone();
                let mut camera_line = camera.to_string();
                match l {
                    Some(l) => mutated[s].1[l] = wrong.clone(),
                    None => camera_line = wrong.clone(),
                }
                let text = text_of(&mutated, &camera_line);
                let before = check(&text);
                let after = check(&before.fixed);
                let context = format!("`{original}` as `{wrong}` ({mistake})");
                if before.codes.is_empty() {
                    failures.push(format!("{context}: nothing reported"));
                    continue;
                }
                if only_marks && before.codes.len() > 2 {
                    failures.push(format!(
                        "{context}: one mistake, several diagnostics: {:?}",
                        before.codes
                    ));
                }
                // A mistake without a fix (a value missing, which only
                // the student knows) leaves the file as it was.
                if before.applied > 0 && after.codes.len() >= before.codes.len() {
                    failures.push(format!(
                        "{context}: {:?} before the fixes, {:?} after",
                        before.codes, after.codes
                    ));
                }
                let known: BTreeSet<&String> = before.codes.iter().collect();
                let new: Vec<&String> = after.codes.iter().filter(|c| !known.contains(c)).collect();
                if !new.is_empty() {
                    failures.push(format!("{context}: the fixes brought {new:?}"));
                }
                // Every other line as written.
                let fixed_lines = lines(&before.fixed);
                for line in lines(&text)
                    .iter()
                    .filter(|line| **line != lines(&wrong)[0])
                {
                    if !fixed_lines.contains(line) {
                        failures.push(format!("{context}: the fixes lost `{line}`"));
                    }
                }
                if only_marks && lines(&before.fixed) != lines(&meant) {
                    failures.push(format!(
                        "{context}: fixed to\n{}\nnot to the scene as meant",
                        before.fixed
                    ));
                }
            }
        }
    }
    assert!(cases > 100, "{cases} cases");
    assert!(
        failures.is_empty(),
        "{} of {cases} cases:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn a_section_in_braces_is_read_as_meant() {
    let meant = text_of(&base(false), language::CAMERA.example);
    let braced = meant
        .replace("sphere\n", "sphere {\n")
        .replace("plane\n", "} plane {\n")
        .replace("light\n", "}\nlight {\n")
        + "}\n";
    let before = check(&braced);
    assert!(
        before.codes.iter().all(|c| c == "syntax::punctuation"),
        "{:?}",
        before.codes
    );
    assert_eq!(lines(&before.fixed), lines(&meant), "{}", before.fixed);
}

/// The JSON object of the first `kind` section of a JSON scene.
fn section_mut<'a>(scene: &'a mut Value, kind: &SectionKind) -> Option<&'a mut Value> {
    match kind {
        SectionKind::Camera => scene.get_mut("camera"),
        SectionKind::Light => scene.get_mut("lights")?.get_mut(0),
        _ => scene
            .get_mut("objects")?
            .as_array_mut()?
            .iter_mut()
            .find(|object| object["type"] == kind.as_str()),
    }
}

/// The codes of diagnostics on a JSON scene whose fix is not as the fix
/// registry says: carried though it says scene text only, or missing
/// though it says JSON scenes get it (a missing texture gets its fix only
/// when a near path names a file, on either language).
fn unlike_the_registry(loaded: &raytracer_scene::frontend::Loaded) -> Vec<String> {
    loaded
        .report
        .entries()
        .filter(|e| {
            let sometimes = e.code == "scene::texture_not_found" && e.fix.is_none();
            fix::WITH_FIX
                .iter()
                .find(|rule| rule.code == e.code)
                .is_some_and(|rule| rule.json != e.fix.is_some() && !sometimes)
        })
        .map(|e| e.code)
        .collect()
}

/// What checking a JSON scene gives: its codes and help lines, and the
/// file with every fix applied. Every fix is as the fix registry says.
fn check_json(text: &str) -> (Vec<String>, Vec<String>, String) {
    let loaded = load_bytes("scene.json", dir(), text.as_bytes());
    let unlike = unlike_the_registry(&loaded);
    assert!(
        unlike.is_empty(),
        "fix::WITH_FIX says otherwise of {unlike:?}:\n{text}"
    );
    let codes = loaded.report.entries().map(|e| e.code).collect();
    let helps = loaded.report.entries().filter_map(|e| e.help).collect();
    let (fixed, _) = fix::apply(text, loaded.report.fixes_up_to(Applicability::Unsafe));
    (codes, helps, fixed)
}

/// The JSON arm: the base scenes as JSON, each registry row's rule broken
/// in its JSON fields. Applying every fix gives a file that is still JSON,
/// whose re-check has fewer problems and no new code, with every value the
/// student wrote kept but the broken ones; and every help line that shows
/// what to write shows JSON fields, not scene text.
#[test]
fn every_fix_leaves_a_better_json_file() {
    let mut cases = 0;
    let mut failures = Vec::new();
    for textured in [false, true] {
        let text = text_of(&base(textured), language::CAMERA.example);
        let loaded = load_bytes("scene.txt", dir(), text.as_bytes());
        let scene = loaded.checked.expect("the base scene is valid").scene;
        let json = to_json(&scene);
        assert_eq!(check_json(&json).0, Vec::<String>::new(), "{json}");
        let meant: Value = serde_json::from_str(&json).unwrap();
        for (kind, spec) in language::rows() {
            for values in super::registry::breaking(spec) {
                let mut broken = meant.clone();
                let Some(object) = section_mut(&mut broken, &kind) else {
                    continue;
                };
                if spec.json.iter().any(|field| object.get(field).is_none()) {
                    continue;
                }
                for (i, field) in spec.json.iter().enumerate() {
                    object[field] = if spec.json.len() == values.len() {
                        json!(values[i])
                    } else if values.len() == 1 {
                        json!(values[0])
                    } else {
                        json!(values)
                    };
                }
                cases += 1;
                let context = format!("{} {:?} = {values:?}", kind.as_str(), spec.json);
                let text = serde_json::to_string_pretty(&broken).unwrap();
                let (codes, helps, fixed) = check_json(&text);
                let (after, _, _) = check_json(&fixed);
                if codes.is_empty() {
                    failures.push(format!("{context}: nothing reported"));
                    continue;
                }
                if after.len() >= codes.len() {
                    failures.push(format!(
                        "{context}: {codes:?} before the fixes, {after:?} after"
                    ));
                }
                let new: Vec<&String> = after.iter().filter(|c| !codes.contains(c)).collect();
                if !new.is_empty() {
                    failures.push(format!("{context}: the fixes brought {new:?}"));
                }
                for help in &helps {
                    let scene_text = format!("`{} ", spec.name.as_str());
                    let shows_json = help
                        .split("write `")
                        .skip(1)
                        .all(|shown| shown.starts_with('"'));
                    if help.contains(&scene_text) || !shows_json {
                        failures.push(format!("{context}: help in scene text: {help}"));
                    }
                }
                // Every value the student wrote, but the broken fields.
                let Ok(mut kept) = serde_json::from_str::<Value>(&fixed) else {
                    failures.push(format!("{context}: the fixed file is not JSON:\n{fixed}"));
                    continue;
                };
                for scene in [&mut kept, &mut broken] {
                    let object = section_mut(scene, &kind).expect("the section");
                    for field in spec.json {
                        object.as_object_mut().unwrap().remove(*field);
                    }
                }
                if kept != broken {
                    failures.push(format!(
                        "{context}: the fixes changed other values:\n{fixed}"
                    ));
                }
            }
        }
    }
    assert!(cases >= 14, "{cases} cases");
    assert!(
        failures.is_empty(),
        "{} of {cases} cases:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// Help lines on a JSON scene show JSON, not scene text: each rule
/// between attributes and each whole-scene warning that says what to
/// write.
#[test]
fn help_lines_on_a_json_scene_are_json() {
    let scene = |objects: &str| {
        format!(
            r#"{{"format": "raytracer-scene/1", "camera": {{"resolution": 64}}, "objects": [{objects}], "lights": [{{"location": [0, 5, 0], "color": [1, 1, 1]}}]}}"#
        )
    };
    let plane = r#"{"type": "plane", "center": [0, -1, -5], "width": 4, "height": 4, "normal": [0, 1, 0], "headup": [0, 1, 1]}"#;
    for (text, code, help) in [
        (
            scene(plane),
            "scene::headup_not_perpendicular",
            r#"the renderer projects it onto the plane: write `"headup": [0, 0, 1]`"#,
        ),
        (
            scene(r#"{"type": "sphere", "center": [0, 0, 5], "radius": 1}"#),
            "scene::object_behind_camera",
            r#"the camera looks down −z; did you mean `"center": [0, 0, -5]`?"#,
        ),
        (
            scene(r#"{"type": "sphere", "center": [100, 0, -5], "radius": 1}"#),
            "scene::nothing_in_view",
            r#"the camera is at the origin looking down −z and sees x and y within ±z/2; put an object there, as in `"center": [0, 0, -5]`"#,
        ),
        (
            scene(
                r#"{"type": "sphere", "center": [0, 0, -5], "radius": 1, "color": [1, 0, 0], "texture": "wood_tex.ppm"}"#,
            ),
            "scene::color_with_texture",
            "remove the `color` field; the texture sets the surface colour",
        ),
        (
            scene(r#"{"type": "sphere", "center": [0, 0, -5], "radius": -1}"#),
            "scene::dimension_not_positive",
            r#"write `"radius": 1`"#,
        ),
        (
            scene(plane).replace("64", "99999"),
            "scene::resolution_out_of_range",
            r#"the image is N × N pixels with N from 1 to 16384: write `"resolution": 16384`"#,
        ),
        (
            scene(
                r#"{"type": "sphere", "center": [0, 0, -5], "radius": 1, "texture": "wood_tex.ppm"}"#,
            )
            .replace("wood_", "wood\u{202e}_"),
            "scene::text_direction_control",
            "",
        ),
    ] {
        let loaded = load_bytes("scene.json", dir(), text.as_bytes());
        let unlike = unlike_the_registry(&loaded);
        assert!(
            unlike.is_empty(),
            "fix::WITH_FIX says otherwise of {unlike:?}:\n{text}"
        );
        let entry = loaded
            .report
            .entries()
            .find(|e| e.code == code)
            .unwrap_or_else(|| panic!("no `{code}` for {text}"));
        if !help.is_empty() {
            assert_eq!(entry.help.as_deref(), Some(help), "{code}");
        }
    }
}
