//! No input panics the front end: random bytes and mutated scene files (and
//! JSON scenes) go through decoding, parsing, checking, `--fix`, every
//! diagnostic format and, when they check, every `convert` target.

use std::path::Path;

use proptest::prelude::*;
use raytracer_scene::convert::{json, pov, scene_text};
use raytracer_scene::fix::{self, Applicability};
use raytracer_scene::frontend::load_bytes;
use raytracer_scene::syntax::parse;

/// Scenes to mutate: the language's example and a few fixtures that reach deep
/// into the checks (textures resolve in tests/ui/scene, where they exist).
const SEEDS: [&str; 6] = [
    include_str!("ui/scene/color_with_texture.txt"),
    include_str!("ui/scene/headup_not_perpendicular.txt"),
    include_str!("ui/scene/light_inside_sphere.txt"),
    include_str!("ui/scene/missing_attribute.txt"),
    include_str!("ui/syntax/unterminated_string.txt"),
    "camera 400\n\nsphere\n  dimension 1            # radius\n  center 0 1 -5\n  \
     reflectivity .7\n  color .3 .3 .3\n\nplane\n  dimension 4 4\n  center 0 -1 -5\n  \
     normal 0 1 0\n  headup 0 0 1\n  texture tiny.ppm\n\nlight\n  location -1 2 -2\n  \
     color 1 .7 .7",
];

/// Characters that matter to the lexer and the checks.
const INTERESTING: &[char] = &[
    '0',
    '1',
    '9',
    '.',
    '-',
    '+',
    'e',
    'E',
    '#',
    '"',
    '\\',
    ' ',
    '\t',
    '\n',
    '\r',
    '\u{2028}',
    '\u{feff}',
    'x',
    'a',
    'c',
    '\u{e9}',
    '\u{1F600}',
    '\0',
    '{',
    '}',
    '[',
    ']',
    ',',
    ':',
];

/// Run everything the `check` command runs on `bytes`.
fn front_end(bytes: &[u8]) {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/ui/scene"));
    let loaded = load_bytes("fuzz.txt", dir, bytes);
    let report = &loaded.report;
    let (fixed, _) = fix::apply(
        &report.source.text,
        report.fixes_up_to(Applicability::Unsafe),
    );
    let _ = parse(&fixed);
    let _ = report.render_human(80, false);
    let _ = report.render_short();
    let _ = serde_json::to_string(&report.entries().collect::<Vec<_>>());
}

/// JSON scenes to mutate: valid ones reaching every field, and the json::
/// fixtures.
const JSON_SEEDS: [&str; 4] = [
    r#"{"format": "raytracer-scene/1", "camera": {"resolution": 4},
  "objects": [{"type": "sphere", "center": [0, 1, -5], "radius": 1, "color": [0.3, 0.3, 0.3], "reflectivity": 0.7},
              {"type": "plane", "center": [0, -1, -5], "width": 4, "height": 4, "normal": [0, 1, 0],
               "headup": [0, 1, 1], "texture": "tiny.ppm"}],
  "lights": [{"location": [-1, 2, -2], "color": [1, 0.7, 0.7]}]}"#,
    include_str!("ui/json/schema.json"),
    include_str!("ui/json/missing_field.json"),
    include_str!("ui/json/duplicate_field.json"),
];

/// Read `bytes` as a JSON scene, check it, fix it, and convert it when it
/// checks.
fn json_front_end(bytes: &[u8]) {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/ui/scene"));
    let loaded = load_bytes("fuzz.json", dir, bytes);
    let report = &loaded.report;
    let _ = fix::apply(
        &report.source.text,
        report.fixes_up_to(Applicability::Unsafe),
    );
    if let Some(checked) = &loaded.checked {
        let _ = json::to_json(&checked.scene);
        let _ = scene_text::to_scene_text(&checked.scene);
        let _ = pov::to_pov(checked);
    }
    let _ = report.render_human(80, false);
    let _ = report.render_short();
}

#[derive(Clone, Debug)]
enum Edit {
    Insert(usize, char),
    Delete(usize),
    Replace(usize, char),
}

fn edit() -> impl Strategy<Value = Edit> {
    let ch = prop_oneof![3 => proptest::sample::select(INTERESTING), 1 => any::<char>()];
    prop_oneof![
        (any::<usize>(), ch.clone()).prop_map(|(at, c)| Edit::Insert(at, c)),
        any::<usize>().prop_map(Edit::Delete),
        (any::<usize>(), ch).prop_map(|(at, c)| Edit::Replace(at, c)),
    ]
}

/// Apply `edits` at character positions (modulo the length).
fn mutate(seed: &str, edits: &[Edit]) -> String {
    let mut chars: Vec<char> = seed.chars().collect();
    for edit in edits {
        let len = chars.len();
        match *edit {
            Edit::Insert(at, c) => chars.insert(at % (len + 1), c),
            Edit::Delete(at) if len > 0 => {
                chars.remove(at % len);
            }
            Edit::Replace(at, c) if len > 0 => chars[at % len] = c,
            _ => {}
        }
    }
    chars.into_iter().collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_do_not_panic(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        front_end(&bytes);
    }

    #[test]
    fn random_bytes_as_json_do_not_panic(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        json_front_end(&bytes);
    }

    #[test]
    fn mutated_json_scenes_do_not_panic(
        seed in 0..JSON_SEEDS.len(),
        edits in proptest::collection::vec(edit(), 1..12),
    ) {
        json_front_end(mutate(JSON_SEEDS[seed], &edits).as_bytes());
    }

    #[test]
    fn mutated_scenes_do_not_panic(
        seed in 0..SEEDS.len(),
        edits in proptest::collection::vec(edit(), 1..12),
    ) {
        front_end(mutate(SEEDS[seed], &edits).as_bytes());
    }
}
