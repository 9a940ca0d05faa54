//! Fuzz target: the formatter (`raytracer fmt`, the language server's
//! formatting) on any scene text, with the properties tests/format.rs
//! asserts on its fixtures, the corpus and generated scenes:
//!
//! - formatting never panics, and refuses exactly the texts that have
//!   syntax errors (returning the parser's errors);
//! - formatting is idempotent: the formatted text formats to itself;
//! - formatting changes only layout: the same syntax tree, every comment
//!   kept in order, the same diagnostics (code, severity, message, help and
//!   the text each label points at, with comments dropped and whitespace
//!   collapsed, since a message may quote the source) and the same checked
//!   scene (as JSON). Texture paths resolve in `tests/ui/scene`.

#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use raytracer_scene::format::format;
use raytracer_scene::frontend::load_bytes;
use raytracer_scene::syntax::{self, trivia};

fuzz_target!(|bytes: &[u8]| {
    let Ok(text) = std::str::from_utf8(bytes) else {
        return;
    };
    let parsed = syntax::parse(text);
    let once = match format(text) {
        Ok(once) => once,
        Err(errors) => {
            assert!(!errors.is_empty(), "refused without an error");
            assert_eq!(errors, parsed.errors, "refused with other errors");
            return;
        }
    };
    assert!(
        parsed.errors.is_empty(),
        "formatted text with syntax errors"
    );
    assert_eq!(format(&once).as_ref(), Ok(&once), "not idempotent");
    assert_eq!(parsed.file, syntax::parse(&once).file, "the tree changed");
    assert_eq!(comments(text), comments(&once), "the comments changed");
    assert_eq!(meaning(text), meaning(&once), "the meaning changed");
});

/// Each comment's text, trailing whitespace dropped (the formatter trims it).
fn comments(text: &str) -> Vec<String> {
    trivia::comments(text)
        .iter()
        .map(|s| text[s.start()..s.end()].trim_end().to_string())
        .collect()
}

/// What the toolchain makes of `text`: its diagnostics and checked scene.
fn meaning(text: &str) -> (Vec<String>, Option<String>) {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/ui/scene"));
    let loaded = load_bytes("fuzz.txt", dir, text.as_bytes());
    let comments = comments(text);
    // Text with comments and whitespace taken out: the formatter puts one
    // space between the values of a line, also where the file wrote none
    // (`"a""b"` is two values and becomes `"a" "b"`), so a label over
    // several values covers other whitespace after formatting. The trees
    // are equal (checked above), so the labels cover the same tokens.
    let plain = |s: &str| {
        let mut s = s.to_string();
        for comment in &comments {
            s = s.replace(comment.as_str(), " ");
        }
        s.split_whitespace().collect::<String>()
    };
    let diagnostics = loaded
        .report
        .entries()
        .map(|e| {
            let at: Vec<String> = e
                .labels
                .iter()
                .map(|l| plain(&text[l.byte_offset..l.byte_offset + l.byte_length]))
                .collect();
            let help = e.help.as_deref().map(plain);
            format!(
                "{} {} {} {help:?} {at:?}",
                e.code,
                e.severity,
                plain(&e.message)
            )
        })
        .collect();
    let scene = loaded
        .checked
        .map(|c| raytracer_scene::convert::json::to_json(&c.scene));
    (diagnostics, scene)
}
