//! Unit tests of the parser: values, lexical corner cases and recovery.

use super::*;

fn num(n: f64) -> Spanned<Value> {
    Spanned::new(0..0, Value::Number(n))
}

fn attr(name: &str, values: Vec<Spanned<Value>>) -> Attribute {
    Attribute {
        name: Spanned::new(0..0, AttrName::from_word(name)),
        values: values.into(),
        span: Span::default(),
    }
}

fn codes(errors: &[SyntaxError]) -> Vec<String> {
    use miette::Diagnostic;
    errors
        .iter()
        .map(|e| e.code().unwrap().to_string())
        .collect()
}

#[test]
fn parses_the_spec_example() {
    let parsed = parse(
        "camera 400\n\nsphere\n  dimension 1  # radius\n  center 0 1 -5\n\
         plane\n  texture wood_tex.ppm\nlight\n  location -1 2 -2\n  color 1 .7 .7",
    );
    assert!(parsed.errors.is_empty(), "{:?}", parsed.errors);
    let s = &parsed.file.sections;
    assert_eq!(s.len(), 4);
    assert_eq!(*s[0].kind, SectionKind::Camera);
    assert_eq!(*s[0].args, [num(400.0)]);
    assert_eq!(
        s[1].attributes,
        vec![
            attr("dimension", vec![num(1.0)]),
            attr("center", vec![num(0.0), num(1.0), num(-5.0)])
        ]
    );
    assert_eq!(
        *s[2].attributes[0].values,
        [Spanned::new(0..0, Value::Text("wood_tex.ppm".into()))]
    );
    assert_eq!(
        s[3].attributes[1],
        attr("color", vec![num(1.0), num(0.7), num(0.7)])
    );
}

#[test]
fn accepts_every_number_form_of_the_spec() {
    let text = "light location 1 -1 .5 -.5 1. +2 1e3 1.5E-2";
    let parsed = parse(text);
    assert!(parsed.errors.is_empty());
    let values: Vec<f64> = parsed.file.sections[0].attributes[0]
        .values
        .iter()
        .map(|v| v.as_number().unwrap())
        .collect();
    assert_eq!(values, [1.0, -1.0, 0.5, -0.5, 1.0, 2.0, 1e3, 1.5e-2]);
}

#[test]
fn unicode_separators_tabs_and_missing_newline() {
    let text = "camera 10\u{2028}sphere\u{2028}\tdimension .5\u{2029}\u{2028}center 0 2 -10";
    let parsed = parse(text);
    assert!(parsed.errors.is_empty());
    assert_eq!(parsed.file.sections[1].attributes.len(), 2);
}

#[test]
fn spans_are_byte_offsets() {
    let text = "\u{2028}camera  400";
    let parsed = parse(text);
    let camera = &parsed.file.sections[0];
    assert_eq!(camera.kind.span, Span::new(3, 9));
    assert_eq!(camera.args[0].span, Span::new(11, 14));
    assert_eq!(camera.span, Span::new(3, 14));
}

#[test]
fn quoted_path_with_spaces_and_escapes() {
    let parsed = parse(r#"sphere texture "my \"wood\" tex.ppm""#);
    assert!(parsed.errors.is_empty());
    assert_eq!(
        *parsed.file.sections[0].attributes[0].values[0],
        Value::Text(r#"my "wood" tex.ppm"#.into())
    );
}

#[test]
fn misspelt_section_starts_a_section_and_misspelt_attribute_does_not() {
    let parsed = parse("sphre\n dimension 1\n colr 1 1 1");
    let s = &parsed.file.sections;
    assert_eq!(s.len(), 1);
    assert_eq!(*s[0].kind, SectionKind::Unknown("sphre".into()));
    assert_eq!(*s[0].attributes[1].name, AttrName::Unknown("colr".into()));
}

#[test]
fn reports_every_error_in_one_run() {
    let text = "1 2\ncamera 1.2.3\nsphere\n center nan 1e400 \"open\n color 1 1 1";
    let parsed = parse(text);
    assert_eq!(
        codes(&parsed.errors),
        [
            "syntax::value_outside_section",
            "syntax::invalid_number",
            "syntax::non_finite_number",
            "syntax::number_out_of_range",
            "syntax::unterminated_string",
        ]
    );
    // Recovery keeps the rest of the file.
    let sphere = &parsed.file.sections[1];
    assert_eq!(sphere.attributes[1], attr("color", vec![num(1.0); 3]));
}

#[test]
fn a_plain_decimal_past_the_range_of_f64_is_out_of_range() {
    let text = format!("sphere dimension 1{}", "0".repeat(400));
    let parsed = parse(&text);
    assert_eq!(codes(&parsed.errors), ["syntax::number_out_of_range"]);
}

#[test]
fn comment_ends_a_word() {
    let parsed = parse("camera 400#res\nsphere");
    assert!(parsed.errors.is_empty());
    assert_eq!(parsed.file.sections.len(), 2);
}

#[test]
fn numbers_and_comments_at_the_end_of_input() {
    // nom 8.0.0's `digit0`/`take_till` mis-report their remainder at the end
    // of input; these would read as `1.` and give a wrong span.
    for (text, value) in [("1.5", 1.5), ("400.5", 400.5), ("-2.25", -2.25)] {
        let parsed = parse(&format!("camera {text}"));
        assert_eq!(*parsed.file.sections[0].args, [num(value)], "{text}");
    }
    let parsed = parse("light texture \"open");
    assert_eq!(
        parsed.errors[0],
        SyntaxError::UnterminatedString {
            span: (14, 5).into()
        }
    );
    let parsed = parse("camera 1 # end");
    assert!(parsed.errors.is_empty());
    assert_eq!(parsed.file.sections[0].span, Span::new(0, 8));
}
