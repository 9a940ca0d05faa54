//! Punctuation around values and keywords in another case, as students
//! bring them from other languages: `dimension = 1`, `center (0, 0, -5)`,
//! `color [1, 0, 0]`, `location 0 5 0;`, `normal: 0 1 0`, `Camera 400`,
//! `SPHERE`. The parser reads the values and keywords as meant and
//! reports each line once, with a fix that keeps every value as written,
//! so none of the follow-on diagnostics (unknown attribute `(0,`, a
//! missing camera, too few values) appear.

use crate::ast::{AttrName, SectionKind};
use crate::fix::{Applicability, Fix};
use crate::language;
use crate::span::Span;

use super::errors::SyntaxError;
use super::number;

/// Marks that open a list of values: `(`, `[`, `{`.
fn is_opening(c: char) -> bool {
    matches!(c, '(' | '[' | '{')
}

/// Marks that close a list of values or end a statement.
fn is_closing(c: char) -> bool {
    matches!(c, ')' | ']' | '}' | ';' | ':' | '=')
}

/// True for a word made only of punctuation a value line may hold: `=`,
/// `:`, `(`, `)`, `[`, `]`, `{`, `}`, `;`, `,`.
pub fn is_only_punctuation(word: &str) -> bool {
    !word.is_empty()
        && word
            .chars()
            .all(|c| is_opening(c) || is_closing(c) || c == ',')
}

/// A number, whole and finite.
fn is_value(piece: &str) -> bool {
    matches!(number(piece), Ok(("", _))) && piece.parse::<f64>().is_ok_and(f64::is_finite)
}

/// A word such as `(0,`, `-5)`, `[1,0,0]` or `0;`: numbers with brackets
/// or a semicolon around them. Returns the spans of its punctuation and of
/// each number in it, offset by `start` (where the word is in the
/// source); `None` for a word without such marks, or whose rest is not
/// numbers separated by commas.
pub fn bracketed(word: &str, start: usize) -> Option<(Vec<Span>, Vec<Span>)> {
    let lead = word.len() - word.trim_start_matches(is_opening).len();
    let inner_end = word
        .trim_end_matches(|c: char| is_closing(c) || c == ',')
        .len();
    if inner_end <= lead {
        return None;
    }
    let trail = &word[inner_end..];
    // A trailing comma alone is a comma between values, which the comma
    // rules read; brackets, `;`, `:` or `=` make it punctuation.
    if lead == 0 && trail.chars().all(|c| c == ',') {
        return None;
    }
    let inner = &word[lead..inner_end];
    let mut marks = Vec::new();
    if lead > 0 {
        marks.push(Span::new(start, start + lead));
    }
    let mut values = Vec::new();
    let mut at = start + lead;
    for piece in inner.split(',') {
        if !is_value(piece) {
            return None;
        }
        values.push(Span::new(at, at + piece.len()));
        at += piece.len();
        if at < start + inner_end {
            marks.push(Span::new(at, at + 1));
            at += 1;
        }
    }
    if !trail.is_empty() {
        marks.push(Span::new(start + inner_end, start + word.len()));
    }
    Some((marks, values))
}

/// How an attribute name was written with punctuation or in another case:
/// `dimension=1`, `center:`, `Color`.
pub struct Name {
    pub name: AttrName,
    /// The bytes of the name itself.
    pub len: usize,
    /// The bytes of the `=` or `:` after it (0 for none).
    pub marks: usize,
    /// Whether it was written in another case than the keyword's.
    pub case: bool,
}

/// The attribute `word` names with `=` or `:` after it, or in another
/// case; `None` when it names none that way.
pub fn attribute_name(word: &str) -> Option<Name> {
    let len = word.find(['=', ':']).unwrap_or(word.len());
    let after = &word[len..];
    let marks = after.len() - after.trim_start_matches(['=', ':']).len();
    let written = &word[..len];
    if let Some(name) = AttrName::known(written) {
        return (marks > 0).then_some(Name {
            name,
            len,
            marks,
            case: false,
        });
    }
    let name = AttrName::known(&written.to_ascii_lowercase())?;
    Some(Name {
        name,
        len,
        marks,
        case: true,
    })
}

/// How a section keyword was written with `=` or `:` after it, or in
/// another case: `camera=400`, `Camera:`, `SPHERE`.
pub struct Keyword {
    pub kind: SectionKind,
    /// The bytes of the keyword itself.
    pub len: usize,
    /// The bytes of the `=` or `:` after it (0 for none).
    pub marks: usize,
    /// Whether it was written in another case than the keyword's.
    pub case: bool,
}

/// The section keyword `word` names with `=` or `:` after it, or in
/// another case; `None` when it names none that way.
pub fn keyword(word: &str) -> Option<Keyword> {
    let len = word.find(['=', ':']).unwrap_or(word.len());
    let after = &word[len..];
    let marks = after.len() - after.trim_start_matches(['=', ':']).len();
    let written = &word[..len];
    if let Some(kind) = SectionKind::known(written) {
        return (marks > 0).then_some(Keyword {
            kind,
            len,
            marks,
            case: false,
        });
    }
    let kind = SectionKind::known(&written.to_ascii_lowercase())?;
    Some(Keyword {
        kind,
        len,
        marks,
        case: true,
    })
}

/// A path with marks around it: `(wood.ppm)`, `[wood.ppm]`, `wood.ppm;`.
/// Returns the spans of the marks and of the path, offset by `start`;
/// `None` for a path without them. Brackets count only in pairs, as a
/// file's name may start or end with one.
pub fn marked_path(word: &str, start: usize) -> Option<(Vec<Span>, Span)> {
    let trail = word.len() - word.trim_end_matches([';', ',']).len();
    let body = &word[..word.len() - trail];
    let paired = ["()", "[]", "{}"].iter().any(|pair| {
        let (open, close) = pair.split_at(1);
        body.len() > 2 && body.starts_with(open) && body.ends_with(close)
    });
    let (lead, inner_end) = if paired {
        (1, body.len() - 1)
    } else {
        (0, body.len())
    };
    if (lead == 0 && trail == 0) || inner_end <= lead {
        return None;
    }
    let mut marks = Vec::new();
    if lead > 0 {
        marks.push(Span::new(start, start + 1));
    }
    if word.len() > inner_end {
        marks.push(Span::new(start + inner_end, start + word.len()));
    }
    Some((marks, Span::new(start + lead, start + inner_end)))
}

/// The diagnostic for a keyword written in another case.
pub fn keyword_case(found: &str, expected: &str, span: Span) -> SyntaxError {
    let fix = Fix::boxed(
        format!("write `{expected}`"),
        Applicability::Safe,
        span,
        expected,
    );
    SyntaxError::KeywordCase {
        found: found.to_string(),
        expected: expected.to_string(),
        span: span.into(),
        help: fix.message.clone(),
        fix: Some(fix),
    }
}

/// The one diagnostic for the punctuation `marks` of a line whose values
/// are at `values` (spans into `src`), after the name ending at
/// `name_end` (`name` as written in the fix's message). The fix, when
/// every value could be read, writes the values as they were written,
/// separated by spaces.
pub fn diagnostic(
    src: &str,
    name: &str,
    name_end: usize,
    marks: &[Span],
    values: &[Span],
    readable: bool,
) -> Option<SyntaxError> {
    let mut marks = marks.to_vec();
    marks.sort_by_key(|s| s.start());
    let marks = &marks[..];
    let first = marks.iter().map(|s| s.start()).min()?;
    let last = marks.iter().map(|s| s.end()).max()?;
    let mut found: Vec<&str> = Vec::new();
    for mark in marks {
        for (i, c) in src[mark.start()..mark.end()].char_indices() {
            let c = &src[mark.start() + i..mark.start() + i + c.len_utf8()];
            if !found.contains(&c) {
                found.push(c);
            }
        }
    }
    let label = Span::new(first, last);
    let written: Vec<&str> = values
        .iter()
        .map(|value| &src[value.start()..value.end()])
        .collect();
    let start = values
        .iter()
        .map(|s| s.start())
        .min()
        .unwrap_or(first)
        .min(first);
    let end = values
        .iter()
        .map(|s| s.end())
        .max()
        .unwrap_or(last)
        .max(last);
    // Without values, the blanks before the marks go too (`light {`).
    let start = if values.is_empty() {
        name_end
    } else {
        start.max(name_end)
    };
    let line = written.join(" ");
    let spaced = src[..start].ends_with([' ', '\t']) || line.is_empty();
    let mut content = if spaced {
        line.clone()
    } else {
        format!(" {line}")
    };
    // A closing mark on a later line (`}` under the last attribute): the
    // line break stays.
    if src[start..end].contains('\n') {
        content.push('\n');
    }
    let shown = if line.is_empty() {
        name.to_string()
    } else {
        format!("{name} {line}")
    };
    let fix = readable.then(|| {
        Fix::boxed(
            format!("write `{shown}`"),
            Applicability::Safe,
            Span::new(start, end),
            &content,
        )
    });
    let help = match &fix {
        Some(fix) => fix.message.clone(),
        None => format!(
            "separate values with spaces only, as in `{}`",
            example(name)
        ),
    };
    Some(SyntaxError::Punctuation {
        found: language::list(&found),
        span: label.into(),
        help,
        fix,
    })
}

/// The registry's example line for an attribute or section named `name`.
fn example(name: &str) -> &'static str {
    language::rows()
        .find(|(_, spec)| spec.name.as_str() == name)
        .map_or("center 0 0 -5", |(_, spec)| spec.example)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brackets_and_semicolons_are_marks_around_numbers() {
        let (marks, values) = bracketed("(0,", 10).unwrap();
        assert_eq!(marks, [Span::new(10, 11), Span::new(12, 13)]);
        assert_eq!(values, [Span::new(11, 12)]);
        let (marks, values) = bracketed("[1,0,-5];", 0).unwrap();
        assert_eq!(marks.len(), 4);
        assert_eq!(values.len(), 3);
        assert!(bracketed("0,", 0).is_none());
        assert!(bracketed("1.2.3)", 0).is_none());
        assert!(bracketed("-5", 0).is_none());
    }

    #[test]
    fn names_with_marks_or_in_another_case() {
        let name = attribute_name("dimension=1").unwrap();
        assert_eq!((name.len, name.marks, name.case), (9, 1, false));
        let name = attribute_name("Center:").unwrap();
        assert_eq!((name.len, name.marks, name.case), (6, 1, true));
        assert!(attribute_name("center").is_none());
        assert!(attribute_name("colr").is_none());
        assert_eq!(keyword("Camera").unwrap().kind, SectionKind::Camera);
        assert_eq!(keyword("camera=400").unwrap().marks, 1);
        assert!(keyword("camera").is_none());
        let (marks, path) = marked_path("[wood.ppm];", 0).unwrap();
        assert_eq!((marks.len(), path), (2, Span::new(1, 9)));
        assert!(marked_path("wood(1).ppm", 0).is_none());
    }
}
