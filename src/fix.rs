//! Structured fixes, in ruff's model: a diagnostic may carry a [`Fix`], a
//! message and the [`Edit`]s (byte range and replacement) that make the
//! change, with an [`Applicability`] that says whether applying it without
//! looking is safe.
//!
//! A safe fix leaves the rendered image unchanged and has exactly one right
//! answer (projecting a `headup` onto the plane, which the renderer does
//! anyway); `raytracer check --fix` applies those. An unsafe fix is a
//! likely intent, not a certainty ("did you mean `color`?"); it is offered
//! in `check --format json` and applied only with `--unsafe-fixes`. Every
//! fix belongs to a diagnostic, so whatever `--fix` changes, `check` has
//! reported, and any consumer of the JSON (an editor) can apply the same
//! edits.

use serde::Serialize;

use crate::span::Span;

/// Whether a fix may be applied without review.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Applicability {
    /// Keeps the image and the author's intent: `--fix` applies it.
    Safe,
    /// A likely intent that may be wrong: applied only with `--unsafe-fixes`.
    Unsafe,
}

/// Replace the bytes of `span` with `content`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Edit {
    pub span: Span,
    pub content: String,
}

/// A change that resolves a diagnostic.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Fix {
    /// What applying it does: "projected `headup` onto the plane".
    pub message: String,
    pub applicability: Applicability,
    /// Non-overlapping edits, in source order.
    pub edits: Vec<Edit>,
}

impl Fix {
    /// A fix of one edit.
    pub fn replace(
        message: String,
        applicability: Applicability,
        span: Span,
        content: &str,
    ) -> Fix {
        Fix {
            message,
            applicability,
            edits: vec![Edit {
                span,
                content: content.to_string(),
            }],
        }
    }

    /// [`Fix::replace`], boxed as a diagnostic carries it (a fix is larger
    /// than most diagnostics).
    pub fn boxed(
        message: String,
        applicability: Applicability,
        span: Span,
        content: &str,
    ) -> Box<Fix> {
        Box::new(Fix::replace(message, applicability, span, content))
    }
}

/// The bytes to delete to remove `span` from `text`: the blanks before it
/// too, and, when nothing but blanks is left on its line, the whole line
/// with its line break (so removing an attribute line leaves no blank
/// line behind).
pub fn removal(text: &str, span: Span) -> Span {
    let is_blank = |c: char| c == ' ' || c == '\t';
    let before = &text[..span.start().min(text.len())];
    let start = before.trim_end_matches(is_blank).len();
    let after = &text[span.end().min(text.len())..];
    let rest_of_line = after.len() - after.trim_start_matches(is_blank).len();
    let at_line_start = start == 0 || before[..start].ends_with('\n');
    let line_break = match &after[rest_of_line..] {
        rest if rest.starts_with("\r\n") => Some(2),
        rest if rest.starts_with('\n') => Some(1),
        "" => Some(0),
        _ => None,
    };
    match line_break {
        Some(n) if at_line_start => Span::new(start, span.end() + rest_of_line + n),
        _ => Span::new(start, span.end()),
    }
}

/// Apply `fixes` to `text`, skipping a fix whose edits overlap one applied
/// before it (each is applied whole or not at all). The fixes applied, in
/// the order given, and the new text.
pub fn apply<'f>(text: &str, fixes: impl IntoIterator<Item = &'f Fix>) -> (String, Vec<&'f Fix>) {
    let mut taken: Vec<Span> = Vec::new();
    let mut applied = Vec::new();
    for fix in fixes {
        let overlaps = fix.edits.iter().any(|e| {
            taken
                .iter()
                .any(|t| e.span.start() < t.end() && t.start() < e.span.end())
                || e.span.end() > text.len()
                || !text.is_char_boundary(e.span.start())
                || !text.is_char_boundary(e.span.end())
        });
        if !overlaps {
            taken.extend(fix.edits.iter().map(|e| e.span));
            applied.push(fix);
        }
    }
    let mut edits: Vec<&Edit> = applied.iter().flat_map(|f| &f.edits).collect();
    // Back to front, so no edit shifts the bytes of another.
    edits.sort_by_key(|e| std::cmp::Reverse(e.span.start()));
    let mut out = text.to_string();
    for edit in edits {
        out.replace_range(edit.span.start()..edit.span.end(), &edit.content);
    }
    (out, applied)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fix(start: usize, end: usize, content: &str) -> Fix {
        Fix::replace(
            "m".to_string(),
            Applicability::Safe,
            Span::new(start, end),
            content,
        )
    }

    #[test]
    fn edits_apply_back_to_front_and_overlaps_are_skipped() {
        let fixes = [fix(0, 3, "abcd"), fix(4, 5, "X"), fix(2, 4, "no")];
        let (text, applied) = apply("foo bar", &fixes);
        assert_eq!(text, "abcd Xar");
        assert_eq!(applied, [&fixes[0], &fixes[1]]);
    }

    #[test]
    fn a_removal_takes_its_line_when_it_is_alone_on_it() {
        let text = "sphere\n  color 1 0 0  \n  center 0 0 -5\n";
        let start = text.find("color").unwrap();
        let span = Span::new(start, start + "color 1 0 0".len());
        let (removed, _) = apply(text, &[fix_of(removal(text, span))]);
        assert_eq!(removed, "sphere\n  center 0 0 -5\n");
        let text = "sphere dimension 1 color 1 0 0 center 0 0 -5";
        let start = text.find("color").unwrap();
        let span = Span::new(start, start + "color 1 0 0".len());
        let (removed, _) = apply(text, &[fix_of(removal(text, span))]);
        assert_eq!(removed, "sphere dimension 1 center 0 0 -5");
    }

    fn fix_of(span: Span) -> Fix {
        fix(span.start(), span.end(), "")
    }

    #[test]
    fn edits_outside_the_text_or_inside_a_character_are_skipped() {
        let fixes = [fix(1, 2, "x"), fix(0, 9, "y")];
        let (text, applied) = apply("é", &fixes);
        assert_eq!(text, "é");
        assert!(applied.is_empty());
    }
}
