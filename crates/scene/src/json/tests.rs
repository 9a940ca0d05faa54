//! Unit tests of the JSON reader: each error, its span and its code.

use super::*;

fn codes(text: &str) -> Vec<&'static str> {
    parse(text)
        .errors
        .iter()
        .map(|e| match e {
            JsonError::Syntax { .. } => "syntax",
            JsonError::UnsupportedFormat { .. } => "unsupported_format",
            JsonError::MissingField { .. } => "missing_field",
            JsonError::UnknownField { .. } => "unknown_field",
            JsonError::DuplicateField { .. } => "duplicate_field",
            JsonError::Schema { .. } => "schema",
        })
        .collect()
}

const SPHERE: &str = r#"{"format": "raytracer-scene/1", "camera": {"resolution": 4},
  "objects": [{"type": "sphere", "center": [0, 0, -5], "radius": 1.5}]}"#;

#[test]
fn builds_the_tree_with_spans_on_the_json_values() {
    let parsed = parse(SPHERE);
    assert_eq!(parsed.errors, []);
    let expected = crate::syntax::parse("camera 4 sphere dimension 1.5 center 0 0 -5").file;
    let file = parsed.file.unwrap();
    assert_eq!(file, expected);
    let sphere = &file.sections[1];
    let text = |span: Span| &SPHERE[span.start()..span.end()];
    assert_eq!(text(sphere.kind.span), "\"sphere\"");
    assert_eq!(text(sphere.attributes[0].name.span), "\"radius\"");
    assert_eq!(text(sphere.attributes[0].values[0].span), "1.5");
    assert_eq!(text(sphere.attributes[1].values[2].span), "-5");
}

#[test]
fn syntax_errors_point_into_the_text() {
    for (text, at) in [
        ("", 0),
        ("{\"format\": 1,}", 12),
        ("{\"a\": [1, 2 3]}", 11),
        ("{\"a\": NaN}", 6),
        ("{\"a\": 1e400}", 10),
        ("{\"a\": \"x\ty\"}", 8),
        ("// c\n{}", 0),
    ] {
        let errors = parse(text).errors;
        let [JsonError::Syntax { span, .. }] = errors.as_slice() else {
            panic!("{text:?}: {errors:?}")
        };
        assert_eq!(span.offset(), at, "{text:?}: {errors:?}");
    }
}

#[test]
fn shape_errors_name_the_json_pointer() {
    let text = r#"{"format": "raytracer-scene/1", "camera": {"resolution": 4},
      "objects": [{"type": "plane", "center": [0, 0], "width": "4", "height": 4,
                   "normal": [0, 1, 0], "headup": [0, 0, 1], "colour": [1, 1, 1]}]}"#;
    // In the order they were found; the report sorts them by position.
    let mut messages: Vec<String> = parse(text).errors.iter().map(|e| e.to_string()).collect();
    messages.sort();
    assert_eq!(
        messages,
        [
            "expected a number at `/objects/0/width`, found the string `\"4\"`",
            "expected an array of 3 numbers at `/objects/0/center`, found an array of 2 values",
            "unknown field `colour` at `/objects/0`",
        ]
    );
}

#[test]
fn missing_and_repeated_fields_are_reported_once() {
    assert_eq!(
        codes(r#"{"format": "raytracer-scene/1"}"#),
        ["missing_field"]
    );
    assert_eq!(
        codes(
            r#"{"format": "raytracer-scene/1", "camera": {"resolution": 4}, "lights": [{"color": [1, 1, 1]}],
                "objects": [{"type": "sphere", "radius": 1, "radius": 2}, {"center": [0, 0, 0]}]}"#
        ),
        [
            "duplicate_field",
            "missing_field",
            "missing_field",
            "missing_field"
        ]
    );
}

#[test]
fn another_format_stops_reading() {
    assert_eq!(
        codes(r#"{"format": "raytracer-scene/2", "cameras": 1}"#),
        ["unsupported_format"]
    );
    assert_eq!(codes("[]"), ["schema"]);
    assert_eq!(
        codes(
            r#"{"format": "raytracer-scene/1", "camera": {"resolution": 4}, "objects": [{"type": "cube"}]}"#
        ),
        ["schema"]
    );
}

#[test]
fn null_texture_is_no_texture() {
    let text = r#"{"format": "raytracer-scene/1", "camera": {"resolution": 4},
      "objects": [{"type": "sphere", "center": [0, 0, -5], "radius": 1, "texture": null}]}"#;
    let parsed = parse(text);
    assert_eq!(parsed.errors, []);
    assert_eq!(parsed.file.unwrap().sections[1].attributes.len(), 2);
}

/// The fields and examples come from the language table; an object made of
/// every field's example is a valid scene object with nothing to report.
#[test]
fn an_object_of_every_example_reads_cleanly() {
    for kind in [SectionKind::Sphere, SectionKind::Plane, SectionKind::Light] {
        let fields = super::fields_of(&kind);
        let members: Vec<String> = fields
            .iter()
            .map(|f| format!("\"{}\": {}", f.name, f.example.text()))
            .collect();
        let list = if kind == SectionKind::Light {
            "lights"
        } else {
            "objects"
        };
        let text = format!(
            r#"{{"format": "raytracer-scene/1", "camera": {{"resolution": 4}}, "{list}": [{{{}}}]}}"#,
            members.join(", ")
        );
        let parsed = parse(&text);
        assert_eq!(parsed.errors, [], "{text}");
        let section = &parsed.file.expect("a scene").sections[1];
        assert_eq!(section.kind.value, kind, "{text}");
        assert_eq!(
            section.attributes.len(),
            crate::language::attributes_of(&kind).len(),
            "{text}"
        );
    }
}
