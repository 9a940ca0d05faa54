//! Parity of the fast paths with the nom rules: on generated scenes, and
//! on those scenes mutated character by character, both routes give the
//! same sections, values, spans and syntax errors.

use proptest::prelude::*;

use super::*;

/// Everything the parser produced, spans included (the tree's equality
/// ignores spans, so it is compared through this dump).
fn dump(text: &str, route: Route) -> String {
    let mut sections = sections_by(text, route);
    let mut out = String::new();
    let values = |out: &mut String, values: &[Spanned<Value>]| {
        for v in values {
            out.push_str(&format!(" {:?}@{:?}", v.value, v.span));
        }
    };
    for section in sections.by_ref() {
        out.push_str(&format!(
            "{:?}@{:?} {:?}:",
            section.kind.value, section.kind.span, section.span
        ));
        values(&mut out, &section.args);
        for attribute in section.attributes.iter() {
            out.push_str(&format!(
                "\n  {:?}@{:?} {:?}:",
                attribute.name.value, attribute.name.span, attribute.span
            ));
            values(&mut out, &attribute.values);
        }
        out.push('\n');
    }
    out.push_str(&format!("{:?}", sections.into_errors()));
    out
}

/// Tokens of every kind the lexical rules tell apart, the unusual ones
/// (non-ASCII spaces and line ends, exponents, bad numbers, strings)
/// included.
fn token() -> impl Strategy<Value = String> {
    let fixed = prop::sample::select(vec![
        "camera",
        "sphere",
        "plane",
        "light",
        "sphre",
        "dimension",
        "center",
        "color",
        "reflectivity",
        "texture",
        "normal",
        "headup",
        "location",
        "colr",
        "wood_tex.ppm",
        "café",
        "1e3",
        "-2.5E-2",
        "1e",
        "1.2.3",
        "+",
        ".",
        "-.",
        "inf",
        "-NaN",
        "Infinity",
        "1e999",
        "\"a b\"",
        "\"esc \\\" q\"",
        "\"open",
        "#",
        "# note",
        "# café",
        "\u{a0}",
        "\u{85}",
        "\u{2028}",
        "\u{2029}",
        "\u{feff}",
        "\r",
        "\r\n",
        "\t",
        "a#b",
        "x\"y",
    ])
    .prop_map(str::to_string);
    let number = (any::<i32>(), 0u32..1000, 0u8..4).prop_map(|(int, frac, form)| match form {
        0 => int.to_string(),
        1 => format!("{int}.{frac}"),
        2 => format!(".{frac}"),
        _ => format!("+{}.", int.unsigned_abs()),
    });
    prop_oneof![3 => fixed, 2 => number]
}

/// A scene: tokens, each followed by a separator.
fn scene() -> impl Strategy<Value = String> {
    let separator = prop::sample::select(vec![" ", "\n", "  ", "\n  ", "\t", ""]);
    prop::collection::vec((token(), separator), 0..40).prop_map(|parts| {
        parts
            .into_iter()
            .map(|(token, separator)| token + separator)
            .collect()
    })
}

/// `text` with characters deleted, replaced or inserted at `edits`
/// (positions taken modulo the character count).
fn mutate(text: &str, edits: &[(usize, u8, char)]) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    for &(at, kind, c) in edits {
        let at = if chars.is_empty() {
            0
        } else {
            at % chars.len()
        };
        match kind % 3 {
            0 if !chars.is_empty() => {
                chars.remove(at);
            }
            1 if !chars.is_empty() => chars[at] = c,
            _ => chars.insert(at, c),
        }
    }
    chars.into_iter().collect()
}

fn mutation_char() -> impl Strategy<Value = char> {
    prop_oneof![
        prop::sample::select(vec![
            ' ', '\n', '\r', '#', '"', '\\', '.', '-', '+', 'e', '0', '7', '\u{85}', '\u{a0}',
            '\u{2028}', 'é',
        ]),
        any::<char>(),
    ]
}

proptest! {
    #[test]
    fn generated_scenes_parse_alike_by_both_routes(text in scene()) {
        prop_assert_eq!(dump(&text, Route::Fast), dump(&text, Route::General));
    }

    #[test]
    fn mutated_scenes_parse_alike_by_both_routes(
        text in scene(),
        edits in prop::collection::vec((any::<usize>(), any::<u8>(), mutation_char()), 1..8),
    ) {
        let text = mutate(&text, &edits);
        prop_assert_eq!(dump(&text, Route::Fast), dump(&text, Route::General));
    }

    #[test]
    fn plain_decimals_are_numbers_of_the_grammar(word in "[-+]?[0-9]{0,4}(\\.[0-9]{0,4})?") {
        let grammar = matches!(number(&word), Ok(("", _)));
        let read = fast::plain_decimal(word.as_bytes());
        prop_assert_eq!(read.is_some_and(|(len, _)| len == word.len()), grammar, "{}", word);
    }

    /// Whatever the word, the fast route reads a value only when the
    /// grammar reads all of it as a number without an exponent.
    #[test]
    fn the_fast_route_reads_plain_decimals_only(word in "[-+.0-9eEa-z]{1,8}") {
        if let Some((len, _)) = fast::plain_decimal(word.as_bytes()) {
            let text = &word[..len];
            prop_assert!(matches!(number(text), Ok(("", _))), "{}", text);
            prop_assert!(!text.contains(['e', 'E']), "{}", text);
        }
    }
}

#[test]
fn the_corpus_parses_alike_by_both_routes() {
    let corpus = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/corpus"))
        .to_path_buf();
    let mut seen = 0;
    let mut folders = vec![corpus];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).expect("the corpus folder reads") {
            let path = entry.expect("a corpus entry reads").path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "txt") {
                let text =
                    String::from_utf8_lossy(&std::fs::read(&path).expect("reads")).into_owned();
                assert_eq!(
                    dump(&text, Route::Fast),
                    dump(&text, Route::General),
                    "{}",
                    path.display()
                );
                seen += 1;
            }
        }
    }
    assert!(seen > 10, "only {seen} corpus scenes found");
}
