//! The safe fixes of `raytracer check --fix`: rewrites that leave the
//! rendered image unchanged and have exactly one right answer.
//!
//! - a plane's `headup` that is not perpendicular to its normal becomes its
//!   projection onto the plane (what the renderer uses anyway);
//! - a plane's non-unit `normal` becomes unit length (the renderer
//!   normalises it anyway).
//!
//! Each fix is a set of [`Edit`]s, one per number, so only those bytes
//! change: comments, tabs and the spacing between values stay as they were.
//! Planes with a problem in these attributes (a duplicate, a wrong count, a
//! zero or parallel vector) are left alone: their fix is the author's call.

use crate::ast::{AttrName, Attribute, File, SectionKind, Value};
use crate::span::Span;

use super::format;
use crate::geometry::{self, Headup};

/// A normal counts as unit length when `| |n| − 1 | ≤ UNIT`: closer than
/// that, rewriting it would change only rounding digits.
const UNIT: f64 = 1e-9;

/// Replace the bytes of `span` with `replacement`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Edit {
    pub span: Span,
    pub replacement: String,
}

/// One fix: what it does, where, and its edits.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Fix {
    /// "projected `headup` onto the plane".
    pub description: String,
    /// The attribute's name, for "line N" in messages.
    pub at: Span,
    pub edits: Vec<Edit>,
}

/// Every safe fix in `file`, in source order.
pub fn fixes(file: &File) -> Vec<Fix> {
    let mut fixes = Vec::new();
    for section in file
        .sections
        .iter()
        .filter(|s| *s.kind == SectionKind::Plane)
    {
        let normal = single_vector(&section.attributes, &AttrName::Normal);
        let headup = single_vector(&section.attributes, &AttrName::Headup);
        let Some((normal_line, n)) = normal else {
            continue;
        };
        let Some(unit) = geometry::unit(n) else {
            continue;
        };
        if let Some((headup_line, h)) = headup {
            if let Some(Headup::Projected(projected)) = geometry::classify_headup(n, h) {
                fixes.push(Fix {
                    description: "projected `headup` onto the plane".to_string(),
                    at: headup_line.name.span,
                    edits: edits(headup_line, projected),
                });
            }
        }
        let length = glam::DVec3::from_array(n).length();
        if (length - 1.0).abs() > UNIT {
            fixes.push(Fix {
                description: "normalised `normal`".to_string(),
                at: normal_line.name.span,
                edits: edits(normal_line, unit.to_array()),
            });
        }
    }
    fixes.sort_by_key(|f| f.at.start());
    fixes
}

/// Apply `fixes` to `text`. Edits never overlap (each number is edited at
/// most once), so they apply back to front without shifting each other.
pub fn apply(text: &str, fixes: &[Fix]) -> String {
    let mut edits: Vec<&Edit> = fixes.iter().flat_map(|f| &f.edits).collect();
    edits.sort_by_key(|e| std::cmp::Reverse(e.span.start()));
    let mut out = text.to_string();
    for edit in edits {
        out.replace_range(edit.span.start()..edit.span.end(), &edit.replacement);
    }
    out
}

/// The attribute `name` with its three numbers, when it is given exactly
/// once and has exactly three numbers.
fn single_vector<'a>(
    attributes: &'a [Attribute],
    name: &AttrName,
) -> Option<(&'a Attribute, [f64; 3])> {
    let mut matching = attributes.iter().filter(|a| *a.name == *name);
    let attribute = matching.next()?;
    if matching.next().is_some() {
        return None;
    }
    match &*attribute.values {
        [x, y, z] => match (&x.value, &y.value, &z.value) {
            (Value::Number(x), Value::Number(y), Value::Number(z)) => {
                Some((attribute, [*x, *y, *z]))
            }
            _ => None,
        },
        _ => None,
    }
}

/// One edit per value of `attribute` whose text changes.
fn edits(attribute: &Attribute, to: [f64; 3]) -> Vec<Edit> {
    attribute
        .values
        .iter()
        .zip(to)
        .filter(|(value, new)| {
            value.as_number() != Some(format::number(*new).parse().unwrap_or(*new))
        })
        .map(|(value, new)| Edit {
            span: value.span,
            replacement: format::number(new),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax::parse;

    fn fix(text: &str) -> String {
        let parsed = parse(text);
        apply(text, &fixes(&parsed.file))
    }

    #[test]
    fn projects_headup_and_keeps_layout_and_comments() {
        let text = "plane\n\tnormal 0 .5 1 # tilted\n\theadup\t0  1 0   # up\n";
        assert_eq!(
            fix(text),
            "plane\n\tnormal 0 0.4472135955 0.894427191 # tilted\n\theadup\t0  0.8 -0.4   # up\n"
        );
    }

    #[test]
    fn leaves_good_and_hopeless_planes_alone() {
        for text in [
            "plane normal 0 1 0 headup 0 0 1",
            "plane normal 0 1 0 headup 0 2 0",
            "plane normal 0 0 0 headup 0 1 0",
            "plane normal 0 1 0 normal 0 1 0 headup 0 1 1",
            "sphere normal 0 2 0",
        ] {
            assert_eq!(fix(text), text);
        }
    }

    #[test]
    fn fixed_text_has_nothing_left_to_fix() {
        let once = fix("plane normal 1 2 3 headup 3 -1 7");
        assert_eq!(fixes(&parse(&once).file), []);
    }
}
