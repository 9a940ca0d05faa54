//! A diagnostic as a terminal is shown it: every piece of text that may come
//! from the user escaped with [`crate::escape`].
//!
//! [`Shown`] copies a diagnostic's message, help, labels, related
//! diagnostics and cause chain with their hidden characters escaped, and
//! carries the source to draw snippets from as a [`ShownSource`]: the file
//! name escaped, and the text escaped with every label's span moved onto the
//! escaped copy, so a label still points at its characters; the
//! `file:line:column` over a snippet still gives the column in the file.
//! miette then renders it as it would the original.

use std::fmt;
use std::sync::Arc;

use miette::{
    Diagnostic, LabeledSpan, MietteError, MietteSpanContents, NamedSource, Severity, SourceCode,
    SourceSpan, SpanContents,
};

use crate::escape::{escape, EscapedSource};
use crate::line_index::LineIndex;
use crate::span::floor_char_boundary;

/// A source file as snippets show it.
pub struct ShownSource {
    named: NamedSource<Arc<String>>,
    /// The offset map when the text had something to escape.
    escaped: Option<EscapedSource>,
    /// The lines of the shown text.
    lines: LineIndex,
}

/// The most bytes of a snippet's lines handed to the renderer: a label on
/// a longer line (a minified scene, a binary file) shows this much of the
/// line around it, not all of it.
const MAX_SNIPPET_BYTES: usize = 4096;

/// How much of a long line a clipped snippet shows on each side of its
/// label.
const CLIPPED_CONTEXT_BYTES: usize = 120;

impl ShownSource {
    /// `text` named `name`, both escaped.
    pub fn new(name: &str, text: &Arc<String>) -> ShownSource {
        let escaped = EscapedSource::new(text);
        let shown_text = match &escaped {
            Some(escaped) => Arc::new(escaped.text().to_string()),
            None => text.clone(),
        };
        ShownSource {
            lines: LineIndex::new(&shown_text),
            named: NamedSource::new(escape(name), shown_text),
            escaped,
        }
    }

    /// `span` of the original text moved onto the shown text.
    fn span(&self, span: &SourceSpan) -> SourceSpan {
        match &self.escaped {
            None => *span,
            Some(escaped) => {
                let start = escaped.offset(span.offset());
                let end = escaped.offset(span.offset() + span.len());
                SourceSpan::new(start.into(), end - start)
            }
        }
    }

    /// The column miette shows for byte `at` of the shown text: bytes from
    /// the start of its line in the original file.
    fn column(&self, at: usize) -> usize {
        let line_start = self.lines.start(self.lines.line(at)).unwrap_or(0);
        match &self.escaped {
            None => at - line_start,
            Some(escaped) => escaped.original(at) - escaped.original(line_start),
        }
    }

    /// The part of the shown text that holds `start..end` with `before`
    /// lines before and `after` lines after it (and one more line, which
    /// the renderer does not use), or, when those lines are longer than
    /// [`MAX_SNIPPET_BYTES`], a clip of the label's own lines around it.
    /// Also whether it was clipped.
    fn window(
        &self,
        start: usize,
        end: usize,
        before: usize,
        after: usize,
    ) -> (usize, usize, bool) {
        let text = self.named.inner().as_str();
        let (first, last) = (self.lines.line(start), self.lines.line(end));
        let line_start = |line: usize| self.lines.start(line).unwrap_or(text.len());
        let from = line_start(first.saturating_sub(before));
        let to = line_start(last + after + 2);
        if to - from <= MAX_SNIPPET_BYTES {
            return (from, to, false);
        }
        let from = floor_char_boundary(
            text,
            start
                .saturating_sub(CLIPPED_CONTEXT_BYTES)
                .max(line_start(first)),
        );
        let line_end = line_start(last + 1);
        let to = ceil_char_boundary(text, (end + CLIPPED_CONTEXT_BYTES).min(line_end));
        // Stop before the line's end, so the clip is one line.
        let to = if to == line_end && to > end {
            text[..to].trim_end_matches(['\n', '\r']).len().max(end)
        } else {
            to
        };
        (from, to, true)
    }
}

/// The smallest character boundary of `text` at or after `offset`
/// (clamped to the text).
fn ceil_char_boundary(text: &str, offset: usize) -> usize {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset += 1;
    }
    offset
}

impl SourceCode for ShownSource {
    /// What miette's own `read_span` gives for the shown text, found from
    /// the line index: miette's reads a window of the lines around the
    /// span (the same answer, with offsets and lines moved back), not the
    /// text from its start, so rendering costs the same for a problem at
    /// the end of a large file as at its start.
    fn read_span<'a>(
        &'a self,
        span: &SourceSpan,
        context_lines_before: usize,
        context_lines_after: usize,
    ) -> Result<Box<dyn SpanContents<'a> + 'a>, MietteError> {
        let text = self.named.inner().as_str();
        let (start, end) = (span.offset(), span.offset() + span.len());
        if end > text.len() {
            return Err(MietteError::OutOfBounds);
        }
        let (from, to, clipped) =
            self.window(start, end, context_lines_before, context_lines_after);
        let window = &text[from..to];
        let local = SourceSpan::new((start - from).into(), span.len());
        // A clip is one line, started and ended inside it: reading it with
        // a line of context on each side makes miette show all of it.
        let (before, after) = if clipped {
            (1, 1)
        } else {
            (context_lines_before, context_lines_after)
        };
        let contents = window.read_span(&local, before, after)?;
        let lines_before = self.lines.line(from);
        // Without lines before, the contents start at the span, and miette
        // takes the column it shows from them: count it in the original.
        let column = if context_lines_before == 0 {
            self.column(start)
        } else {
            contents.column()
        };
        Ok(Box::new(MietteSpanContents::new_named(
            self.named.name().to_string(),
            contents.data(),
            SourceSpan::new(
                (contents.span().offset() + from).into(),
                contents.span().len(),
            ),
            contents.line() + lines_before,
            column,
            contents.line_count() + lines_before,
        )))
    }
}

/// A diagnostic with its text escaped, ready for miette's renderer.
pub struct Shown<'a> {
    message: String,
    code: Option<String>,
    severity: Option<Severity>,
    help: Option<String>,
    url: Option<String>,
    labels: Vec<LabeledSpan>,
    related: Vec<Shown<'a>>,
    cause: Option<Box<Cause>>,
    source: Option<&'a ShownSource>,
}

impl<'a> Shown<'a> {
    /// `diagnostic` escaped; its labels point into `source` when given.
    pub fn new(diagnostic: &dyn Diagnostic, source: Option<&'a ShownSource>) -> Shown<'a> {
        let text = |d: &dyn fmt::Display| escape(&d.to_string()).into_owned();
        let labels = diagnostic
            .labels()
            .into_iter()
            .flatten()
            .map(|label| {
                let span = source.map_or(*label.inner(), |s| s.span(label.inner()));
                let text = label.label().map(|l| escape(l).into_owned());
                if label.primary() {
                    LabeledSpan::new_primary_with_span(text, span)
                } else {
                    LabeledSpan::new_with_span(text, span)
                }
            })
            .collect();
        Shown {
            message: text(&diagnostic),
            code: diagnostic.code().map(|c| text(&c)),
            severity: diagnostic.severity(),
            help: diagnostic.help().map(|h| text(&h)),
            url: diagnostic.url().map(|u| text(&u)),
            labels,
            related: diagnostic
                .related()
                .into_iter()
                .flatten()
                .map(|r| Shown::new(r, source))
                .collect(),
            cause: diagnostic.source().map(Cause::new),
            source,
        }
    }
}

impl fmt::Debug for Shown<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl fmt::Display for Shown<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Shown<'_> {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.cause.as_deref().map(|c| c as _)
    }
}

impl Diagnostic for Shown<'_> {
    fn code<'b>(&'b self) -> Option<Box<dyn fmt::Display + 'b>> {
        self.code.as_ref().map(|c| Box::new(c) as _)
    }
    fn severity(&self) -> Option<Severity> {
        self.severity
    }
    fn help<'b>(&'b self) -> Option<Box<dyn fmt::Display + 'b>> {
        self.help.as_ref().map(|h| Box::new(h) as _)
    }
    fn url<'b>(&'b self) -> Option<Box<dyn fmt::Display + 'b>> {
        self.url.as_ref().map(|u| Box::new(u) as _)
    }
    fn source_code(&self) -> Option<&dyn SourceCode> {
        self.source.map(|s| s as _)
    }
    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        if self.labels.is_empty() {
            return None;
        }
        Some(Box::new(self.labels.iter().cloned()))
    }
    fn related<'b>(&'b self) -> Option<Box<dyn Iterator<Item = &'b dyn Diagnostic> + 'b>> {
        if self.related.is_empty() {
            return None;
        }
        Some(Box::new(self.related.iter().map(|r| r as _)))
    }
}

/// One error of a cause chain, escaped.
#[derive(Debug)]
struct Cause {
    message: String,
    next: Option<Box<Cause>>,
}

impl Cause {
    fn new(error: &dyn std::error::Error) -> Box<Cause> {
        Box::new(Cause {
            message: escape(&error.to_string()).into_owned(),
            next: error.source().map(Cause::new),
        })
    }
}

impl fmt::Display for Cause {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Cause {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.next.as_deref().map(|c| c as _)
    }
}
