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
//! edits. [`WITH_FIX`] and [`WITHOUT_FIX`] say per code what its fix does
//! or why it has none: the table of fixes in docs/diagnostics.md.

use serde::Serialize;

use crate::span::Span;

/// The codes whose diagnostics carry no fix, each with the reason: no
/// edit of the scene has one right answer or a likely one. Every other
/// code carries a fix where its remedy is mechanical (tests/ui.rs holds the
/// two lists to every code, and docs/diagnostics.md states each reason).
pub const WITHOUT_FIX: &[(&str, &str)] = &[
    (
        "syntax::invalid_utf8",
        "the bytes are in another encoding, which the scene does not name",
    ),
    (
        "syntax::not_text",
        "the file is not text, so no edit of its text repairs it",
    ),
    (
        "syntax::invalid_number",
        "which number the malformed word stands for is unknown",
    ),
    (
        "syntax::non_finite_number",
        "no finite number stands for an infinite or undefined one",
    ),
    (
        "syntax::number_out_of_range",
        "which finite number was meant is unknown",
    ),
    (
        "syntax::unterminated_string",
        "where the string was meant to end is unknown",
    ),
    (
        "syntax::value_outside_section",
        "which section or attribute the values belong to is unknown",
    ),
    (
        "json::syntax",
        "what the broken JSON was meant to say is unknown",
    ),
    (
        "json::unsupported_format",
        "another format version's layout is not translated field by field",
    ),
    (
        "json::missing_field",
        "the values of the missing fields are the author's",
    ),
    (
        "json::unknown_field",
        "JSON diagnostics carry no structured fixes yet; the help names the field to rename it to",
    ),
    (
        "json::duplicate_field",
        "which of the two fields is meant is unknown, and removing one would leave the commas to mend",
    ),
    (
        "json::schema",
        "the value's shape is wrong, and what it was meant to hold is unknown",
    ),
    (
        "scene::texture_not_a_file",
        "the file the path was meant to name is unknown",
    ),
    (
        "scene::texture_not_an_image",
        "the remedy is a new image file, not an edit of the scene",
    ),
    (
        "scene::texture_too_large",
        "the remedy is a smaller image file, not an edit of the scene",
    ),
    (
        "scene::too_many_objects",
        "which objects to drop is a choice about the picture, not a correction",
    ),
    (
        "scene::nothing_in_view",
        "where the objects belong, or where the camera was meant to look, is the author's call",
    ),
    (
        "scene::light_inside_sphere",
        "where the light belongs is the author's call",
    ),
];

/// What the fix of a code does: a row of [`WITH_FIX`].
#[derive(Debug)]
pub struct FixRule {
    pub code: &'static str,
    /// The applicability of each fix the code may carry.
    pub applicability: &'static [Applicability],
    /// Whether a diagnostic on a JSON scene carries it too (else it is
    /// offered on scene text only).
    pub json: bool,
    /// What applying it does, as a phrase: "removes the second line".
    pub does: &'static str,
}

const SAFE: &[Applicability] = &[Applicability::Safe];
const UNSAFE: &[Applicability] = &[Applicability::Unsafe];

/// The codes whose diagnostics carry a fix, with what it does: the one
/// source of the table of fixes in docs/diagnostics.md ([`markdown_table`]),
/// and held to what the check does by tests/ui.rs (each fixture's fix) and
/// tests/fix_never_worse.rs (JSON scenes).
pub const WITH_FIX: &[FixRule] = &[
    FixRule {
        code: "syntax::comma_separated_values",
        applicability: SAFE,
        json: false,
        does: "writes the values separated by spaces",
    },
    FixRule {
        code: "syntax::decimal_comma",
        applicability: SAFE,
        json: false,
        does: "writes the decimal comma as a point",
    },
    FixRule {
        code: "syntax::punctuation",
        applicability: SAFE,
        json: false,
        does: "removes the marks, every value kept as written",
    },
    FixRule {
        code: "syntax::keyword_case",
        applicability: SAFE,
        json: false,
        does: "writes the keyword in lowercase",
    },
    FixRule {
        code: "scene::unknown_section",
        applicability: UNSAFE,
        json: false,
        does: "writes the nearest keyword",
    },
    FixRule {
        code: "scene::unknown_attribute",
        applicability: &[Applicability::Safe, Applicability::Unsafe],
        json: false,
        does:
            "writes the scene-text name of a JSON field name (safe), or the nearest name (unsafe)",
    },
    FixRule {
        code: "scene::misplaced_attribute",
        applicability: UNSAFE,
        json: false,
        does: "removes the line",
    },
    FixRule {
        code: "scene::wrong_value_count",
        applicability: UNSAFE,
        json: false,
        does: "drops the extra values, or writes the example values on a line with none",
    },
    FixRule {
        code: "scene::not_a_number",
        applicability: SAFE,
        json: false,
        does: "removes the quotes around a number",
    },
    FixRule {
        code: "scene::duplicate_attribute",
        applicability: UNSAFE,
        json: false,
        does: "removes the second line",
    },
    FixRule {
        code: "scene::missing_attribute",
        applicability: UNSAFE,
        json: false,
        does: "adds the example line of each missing attribute",
    },
    FixRule {
        code: "scene::missing_camera",
        applicability: UNSAFE,
        json: false,
        does: "adds `camera 400` before the first section",
    },
    FixRule {
        code: "scene::repeated_camera",
        applicability: UNSAFE,
        json: false,
        does: "removes the repeated `camera` line",
    },
    FixRule {
        code: "scene::resolution_not_integer",
        applicability: UNSAFE,
        json: true,
        does: "writes the nearest whole number",
    },
    FixRule {
        code: "scene::resolution_out_of_range",
        applicability: UNSAFE,
        json: true,
        does: "writes the nearest valid resolution",
    },
    FixRule {
        code: "scene::section_values",
        applicability: UNSAFE,
        json: false,
        does: "removes the values after the keyword",
    },
    FixRule {
        code: "scene::dimension_not_positive",
        applicability: UNSAFE,
        json: true,
        does: "writes the sizes made positive (0 becomes 1)",
    },
    FixRule {
        code: "scene::color_out_of_range",
        applicability: UNSAFE,
        json: true,
        does: "converts from 0–255, or clamps each channel to [0, 1]",
    },
    FixRule {
        code: "scene::reflectivity_out_of_range",
        applicability: UNSAFE,
        json: true,
        does: "reads a whole number up to 100 as a percentage, or clamps to [0, 1]",
    },
    FixRule {
        code: "scene::negative_light_color",
        applicability: UNSAFE,
        json: true,
        does: "sets the negative channels to 0",
    },
    FixRule {
        code: "scene::zero_normal",
        applicability: UNSAFE,
        json: true,
        does: "writes `0 0 1`, a plane facing the camera, turned perpendicular to a valid `headup` (`0 1 0` across `0 0 -1`)",
    },
    FixRule {
        code: "scene::zero_headup",
        applicability: UNSAFE,
        json: true,
        does: "writes a direction perpendicular to the normal",
    },
    FixRule {
        code: "scene::headup_parallel_to_normal",
        applicability: SAFE,
        json: true,
        does: "writes the stand-in headup the renderer uses",
    },
    FixRule {
        code: "scene::headup_not_perpendicular",
        applicability: SAFE,
        json: true,
        does: "writes `headup` projected onto the plane, as the renderer uses it",
    },
    FixRule {
        code: "scene::object_behind_camera",
        applicability: UNSAFE,
        json: true,
        does: "negates the z of a centre with z > 0",
    },
    FixRule {
        code: "scene::texture_not_found",
        applicability: UNSAFE,
        json: true,
        does: "writes a near path that names a file, as a path from the scene's folder: `/` for a backslash, without quotes, in the folder's case, or the same name beside the scene (first) or in a folder near it",
    },
    FixRule {
        code: "scene::no_light",
        applicability: UNSAFE,
        json: false,
        does: "adds a white light at `0 5 0` at the end of the file",
    },
    FixRule {
        code: "scene::color_with_texture",
        applicability: SAFE,
        json: false,
        does: "removes the `color` line",
    },
    FixRule {
        code: "scene::light_color_above_one",
        applicability: UNSAFE,
        json: true,
        does: "divides by the brightest channel, keeping the hue",
    },
    FixRule {
        code: "scene::text_direction_control",
        applicability: UNSAFE,
        json: true,
        does: "deletes the control",
    },
];

/// Where `code` is documented, relative to docs/: the page of its prefix
/// under docs/diagnostics/ (`syntax.md`, `json.md`, `scene.md`) and its
/// section's anchor, the code without its colons
/// (`diagnostics/scene.md#sceneunknown_attribute`). docs/diagnostics.md,
/// beside that folder, lists every code.
pub fn documentation(code: &str) -> String {
    let prefix = code.split("::").next().unwrap_or(code);
    format!("diagnostics/{prefix}.md#{}", code.replace("::", ""))
}

/// The table of fixes in docs/diagnostics.md: each code that carries a
/// fix with what it does, how it is applied and whether JSON scenes get it
/// ([`WITH_FIX`]), then each code without one with its reason
/// ([`WITHOUT_FIX`]).
pub fn markdown_table() -> String {
    let link = |code: &str| format!("[`{code}`]({})", documentation(code));
    let mut out =
        String::from("| code | its fix | applied by | on JSON scenes |\n|---|---|---|---|\n");
    for rule in WITH_FIX {
        let applied: Vec<&str> = rule
            .applicability
            .iter()
            .map(|a| match a {
                Applicability::Safe => "`--fix` (safe)",
                Applicability::Unsafe => "`--fix --unsafe-fixes` (unsafe)",
            })
            .collect();
        let json = if rule.json { "yes" } else { "no" };
        out.push_str(&format!(
            "| {} | {} | {} | {json} |\n",
            link(rule.code),
            rule.does,
            applied.join(", ")
        ));
    }
    for (code, reason) in WITHOUT_FIX {
        out.push_str(&format!("| {} | none: {reason} | — | — |\n", link(code)));
    }
    out
}

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
    /// What applying it does, in the imperative (an editor's quick fix
    /// is titled with it): "project `headup` onto the plane".
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

/// The edit that adds `items` (attribute lines such as `normal 0 1 0`)
/// after `last`, the span of a section's last element. When `last` starts
/// its line and nothing but a comment follows it there, each item goes on a
/// line of its own after that line, indented as `last` is (one level more
/// when `nested`, as attributes are under a keyword alone on its line);
/// otherwise the items follow `last` on its line, separated by spaces.
pub fn insertion(text: &str, last: Span, nested: bool, items: &[&str]) -> Edit {
    let is_blank = |c: char| c == ' ' || c == '\t';
    let end = last.end().min(text.len());
    let start = last.start().min(end);
    let line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
    let indent = &text[line_start..start];
    let line_end = text[end..].find('\n').map_or(text.len(), |i| end + i);
    let crlf = text[..line_end].ends_with('\r') && line_end < text.len();
    let line_end = if crlf { line_end - 1 } else { line_end };
    let rest = text[end..line_end].trim_start_matches(is_blank);
    if indent.chars().all(is_blank) && (rest.is_empty() || rest.starts_with('#')) {
        let newline = if crlf { "\r\n" } else { "\n" };
        let deeper = if nested { "  " } else { "" };
        Edit {
            span: Span::point(line_end),
            content: items
                .iter()
                .map(|item| format!("{newline}{indent}{deeper}{item}"))
                .collect(),
        }
    } else {
        Edit {
            span: Span::point(end),
            content: items.iter().map(|item| format!(" {item}")).collect(),
        }
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
    // Back to front, so no edit shifts the bytes of another; an insertion
    // (an empty span) at the start of a replacement goes after it, so it
    // lands before the replaced bytes.
    edits.sort_by_key(|e| std::cmp::Reverse((e.span.start(), e.span.end())));
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
    fn insertions_follow_the_layout_of_the_last_element() {
        let insert = |text: &str, last: &str, nested: bool| {
            let start = text.find(last).unwrap();
            let span = Span::new(start, start + last.len());
            let edit = insertion(text, span, nested, &["normal 0 1 0", "headup 0 0 -1"]);
            apply(
                text,
                &[Fix {
                    message: "m".to_string(),
                    applicability: Applicability::Unsafe,
                    edits: vec![edit],
                }],
            )
            .0
        };
        assert_eq!(
            insert(
                "plane\n  center 0 0 -5 # c\r\nlight\n",
                "center 0 0 -5",
                false
            ),
            "plane\n  center 0 0 -5 # c\r\n  normal 0 1 0\r\n  headup 0 0 -1\r\nlight\n"
        );
        assert_eq!(
            insert("\tplane", "plane", true),
            "\tplane\n\t  normal 0 1 0\n\t  headup 0 0 -1"
        );
        assert_eq!(
            insert("plane center 0 0 -5 light", "center 0 0 -5", false),
            "plane center 0 0 -5 normal 0 1 0 headup 0 0 -1 light"
        );
    }

    #[test]
    fn an_insertion_at_the_start_of_a_replacement_goes_before_it() {
        for fixes in [
            [fix(0, 0, "camera 4\n"), fix(0, 5, "sphere")],
            [fix(0, 5, "sphere"), fix(0, 0, "camera 4\n")],
        ] {
            assert_eq!(apply("sphre 1", &fixes).0, "camera 4\nsphere 1");
        }
    }

    #[test]
    fn edits_outside_the_text_or_inside_a_character_are_skipped() {
        let fixes = [fix(1, 2, "x"), fix(0, 9, "y")];
        let (text, applied) = apply("é", &fixes);
        assert_eq!(text, "é");
        assert!(applied.is_empty());
    }
}
