//! Diagnostics for CI services: the SARIF log that code-scanning services
//! ingest ([`sarif`]) and the workflow commands that GitHub Actions turns
//! into annotations ([`github`]), the `sarif` and `github` formats of
//! `raytracer check`.
//!
//! Both need more than the JSON entry of a diagnostic: where each label ends
//! and where it lies counted in characters. A [`Finding`] is that entry
//! with one [`Region`] per label, computed from the scene's text.

pub mod github;
pub mod sarif;

use raytracer_scene::diagnostic::{JsonDiagnostic, Report, SourceFile};

/// A diagnostic with the extent of each of its labels.
#[derive(Clone, Debug)]
pub struct Finding {
    pub diagnostic: JsonDiagnostic,
    /// One per entry of `diagnostic.labels`, in the same order.
    pub regions: Vec<Region>,
    /// One per edit of `diagnostic.fix`, in the same order.
    pub fix_regions: Vec<Region>,
}

/// Where a label lies: lines and columns are 1-based, columns and the
/// offset count Unicode characters (code points), as the JSON format's do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Region {
    pub start: (usize, usize),
    /// The position just after the label (the start, for an empty label).
    pub end: (usize, usize),
    /// The position of the label's last character (the start, for an empty
    /// label).
    pub last: (usize, usize),
    pub char_offset: usize,
    pub char_length: usize,
}

impl Finding {
    /// A diagnostic that has no text to point into (a file that could not be
    /// read).
    pub fn without_source(diagnostic: JsonDiagnostic) -> Finding {
        Finding {
            regions: Vec::new(),
            fix_regions: Vec::new(),
            diagnostic,
        }
    }
}

/// Every diagnostic of `report` with the regions of its labels and of
/// its fix's edits.
pub fn findings(report: &Report) -> Vec<Finding> {
    let source = &report.source;
    report
        .entries()
        .map(|diagnostic| {
            let regions = diagnostic
                .labels
                .iter()
                .map(|l| region(source, l.byte_offset, l.byte_length, (l.line, l.column)))
                .collect();
            let fix_regions = diagnostic
                .fix
                .iter()
                .flat_map(|fix| &fix.edits)
                .map(|e| region(source, e.byte_offset, e.byte_length, (e.line, e.column)))
                .collect();
            Finding {
                diagnostic,
                regions,
                fix_regions,
            }
        })
        .collect()
}

/// The region of `length` bytes at byte `offset` of `source`, which starts
/// at `start` (line and column).
fn region(source: &SourceFile, offset: usize, length: usize, start: (usize, usize)) -> Region {
    let text = &*source.text;
    let end_byte = offset + length;
    let last_byte = if length == 0 { offset } else { end_byte - 1 };
    let char_offset = chars_before(text, offset);
    Region {
        start,
        end: source.line_col(end_byte),
        last: source.line_col(last_byte),
        char_offset,
        char_length: chars_before(text, end_byte) - char_offset,
    }
}

/// How many characters of `text` start before byte `offset`.
fn chars_before(text: &str, offset: usize) -> usize {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    text[..offset].chars().count()
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use miette::{LabeledSpan, MietteDiagnostic};

    use super::*;
    use raytracer_scene::diagnostic::BoxedDiagnostic;

    /// A report on `text` with one diagnostic labelling each byte range.
    pub fn report(text: &str, labels: &[std::ops::Range<usize>]) -> Report {
        let (source, _) = SourceFile::from_bytes("s.txt", Path::new(""), text.as_bytes());
        let diagnostic = MietteDiagnostic::new("unknown attribute `céntre` in `sphere`")
            .with_code("scene::unknown_attribute")
            .with_labels(
                labels
                    .iter()
                    .map(|r| LabeledSpan::at(r.clone(), "not an attribute")),
            );
        Report::new(source, vec![Box::new(diagnostic) as BoxedDiagnostic])
    }

    #[test]
    fn regions_count_characters() {
        let text = "camera 4\nsphere\n  dimension 1\n  céntre 0 0 -5\n";
        let start = text.find("céntre").unwrap();
        let end = start + "céntre".len();
        let found = findings(&report(text, &[start..end, end..end]));
        let [region, empty] = found[0].regions[..] else {
            panic!("two regions")
        };
        assert_eq!(region.start, (4, 3));
        assert_eq!(region.end, (4, 9));
        assert_eq!(region.last, (4, 8));
        assert_eq!(region.char_offset, 32);
        assert_eq!(region.char_length, 6);
        assert_eq!(
            (empty.start, empty.end, empty.last),
            ((4, 9), (4, 9), (4, 9))
        );
        assert_eq!(empty.char_length, 0);
    }
}
