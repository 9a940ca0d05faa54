//! Every scene of the exported built-in suite is in the course's own
//! format, read here by a minimal reader written from the course's
//! assignment alone, the way a student would: one keyword or attribute per
//! line, its values separated by spaces, no comments. Sections are
//! `camera N`, `sphere`, `plane` and `light`; attributes are `dimension`,
//! `center`, `color`, `reflectivity`, `texture` (a file name), `normal`,
//! `headup` and `location`; numbers are written as the assignment writes
//! them (`1`, `-5`, `.7`, `1.0`). Read again as whitespace-separated words
//! (a token parser), each scene gives the same sections.

use std::collections::BTreeSet;

use serde_json::Value;

use crate::support::run;

/// A number as the assignment writes one: an optional minus, digits with
/// an optional fraction, or a fraction alone.
fn assignment_number(word: &str) -> bool {
    let digits = word.strip_prefix('-').unwrap_or(word);
    let (whole, fraction) = digits.split_once('.').unwrap_or((digits, ""));
    !(whole.is_empty() && fraction.is_empty())
        && whole.chars().all(|c| c.is_ascii_digit())
        && fraction.chars().all(|c| c.is_ascii_digit())
        && !(digits.contains('.') && fraction.is_empty())
}

/// How many values each line's first word takes, or `None` for a word
/// the assignment does not have.
fn arity(word: &str) -> Option<usize> {
    Some(match word {
        "sphere" | "plane" | "light" => 0,
        "camera" | "reflectivity" | "texture" => 1,
        "center" | "color" | "normal" | "headup" | "location" => 3,
        "dimension" => 0, // 1 for a sphere, 2 for a plane: checked below
        _ => return None,
    })
}

/// The sections of `text`, read line by line; panics on anything the
/// assignment's format does not have.
fn read_lines(name: &str, text: &str) -> Vec<String> {
    let mut sections = Vec::new();
    let mut current = String::new();
    for (number, line) in text.lines().enumerate() {
        let at = format!("{name}:{}", number + 1);
        assert!(!line.contains('#'), "{at}: a comment");
        let words: Vec<&str> = line.split_whitespace().collect();
        let Some((&first, values)) = words.split_first() else {
            continue;
        };
        let wanted = arity(first).unwrap_or_else(|| panic!("{at}: `{first}` is no keyword"));
        let wanted = match first {
            "dimension" if current == "sphere" => 1,
            "dimension" if current == "plane" => 2,
            "dimension" => panic!("{at}: a dimension outside an object"),
            _ => wanted,
        };
        assert_eq!(values.len(), wanted, "{at}: `{line}`");
        if first == "texture" {
            assert!(values[0].ends_with(".ppm"), "{at}: `{line}`");
        } else {
            for value in values {
                assert!(assignment_number(value), "{at}: `{value}`");
            }
        }
        if matches!(first, "camera" | "sphere" | "plane" | "light") {
            assert!(
                first == "camera" || sections.first().is_some_and(|s| s == "camera"),
                "{at}: the camera comes first"
            );
            current = first.to_string();
            sections.push(current.clone());
        }
    }
    sections
}

/// The sections of `text` read as a stream of words.
fn read_words(text: &str) -> Vec<String> {
    text.split_whitespace()
        .filter(|w| matches!(*w, "camera" | "sphere" | "plane" | "light"))
        .map(str::to_string)
        .collect()
}

#[test]
fn every_suite_scene_is_in_the_assignments_format() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(&["grade", "--export-suite", dir.path().to_str().unwrap()]);
    assert!(out.status.success(), "{out:?}");
    let manifest: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("suite.json")).unwrap())
            .unwrap();
    let scenes = manifest["scenes"].as_array().unwrap();
    assert!(scenes.len() >= 20);
    let mut lit = 0;
    for entry in scenes {
        let name = entry["scene"].as_str().unwrap();
        assert!(!entry["description"].as_str().unwrap().is_empty(), "{name}");
        let text = std::fs::read_to_string(dir.path().join(name)).unwrap();
        let sections = read_lines(name, &text);
        assert_eq!(
            sections.iter().filter(|s| *s == "camera").count(),
            1,
            "{name}"
        );
        assert_eq!(sections, read_words(&text), "{name}");
        lit += usize::from(sections.iter().any(|s| s == "light"));
    }
    // Every scene has a light: none judges the ambient term alone.
    assert_eq!(lit, scenes.len());
}

#[test]
fn the_reader_refuses_what_the_format_does_not_have() {
    let read = |text: &str| std::panic::catch_unwind(|| read_lines("t", text)).is_ok();
    assert!(read("camera 4\nsphere\ndimension .5\ncenter 0 0 -5\n"));
    assert!(!read("camera 4\n# a comment\n"));
    assert!(!read("camera 4\nsphere\ndimension 1e-3\n"));
    assert!(!read("camera 4\nsphere\n  dimension 1 center 0 0 -5\n"));
    assert!(!read("camera 4\ncube\n"));
}

/// A scene as its lines' words, comments dropped and numbers read, so
/// `.7` and `0.7` agree.
fn values(text: &str) -> Vec<(String, Vec<String>)> {
    text.lines()
        .map(|line| line.split('#').next().unwrap_or(""))
        .filter_map(|line| {
            let mut words = line.split_whitespace().map(|w| match w.parse::<f64>() {
                Ok(number) => format!("{number}"),
                Err(_) => w.to_string(),
            });
            let keyword = words.next()?;
            Some((keyword, words.collect()))
        })
        .collect()
}

/// A line of a scene: its keyword and its values.
type Line = (String, Vec<String>);

/// The sections of a scene in order, each its keyword line and its
/// attributes in a set: the same scene whatever order the attributes of a
/// section are written in (`fmt` writes the language's order).
fn sections(text: &str) -> Vec<(Line, BTreeSet<Line>)> {
    let mut sections: Vec<(Line, BTreeSet<Line>)> = Vec::new();
    for line in values(text) {
        if ["camera", "sphere", "plane", "light"].contains(&line.0.as_str()) {
            sections.push((line, BTreeSet::new()));
        } else {
            sections
                .last_mut()
                .expect("an attribute after a section")
                .1
                .insert(line);
        }
    }
    sections
}

/// The suite's sample and scenes/sample.txt are the assignment's sample
/// scene, both lights and all. The lines below are the assignment's
/// sample scene file, value for value.
#[test]
fn the_sample_is_the_assignments_sample_scene() {
    let assignment = "camera 400
        sphere
        dimension 1
        center 0 1 -5
        reflectivity .7
        color .3 .3 .3
        plane
        dimension 4 4
        center 0 -1 -5
        normal 0 1 0
        headup 0 0 1
        texture wood_tex.ppm
        light
        location -1 2 -2
        color 1 .7 .7
        light
        location 1 0 -6
        color .3 .3 1";
    let dir = tempfile::tempdir().unwrap();
    let out = run(&["grade", "--export-suite", dir.path().to_str().unwrap()]);
    assert!(out.status.success(), "{out:?}");
    let suite = std::fs::read_to_string(dir.path().join("sample.txt")).unwrap();
    let shipped =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/sample.txt")).unwrap();
    assert_eq!(sections(&suite), sections(assignment), "the suite's sample");
    assert_eq!(
        sections(&shipped),
        sections(assignment),
        "scenes/sample.txt"
    );
}
