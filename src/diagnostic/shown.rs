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

/// A source file as snippets show it.
pub struct ShownSource {
    named: NamedSource<Arc<String>>,
    original: Arc<String>,
    /// The offset map when the text had something to escape.
    escaped: Option<EscapedSource>,
}

impl ShownSource {
    /// `text` named `name`, both escaped.
    pub fn new(name: &str, text: &Arc<String>) -> ShownSource {
        let escaped = EscapedSource::new(text);
        let shown_text = match &escaped {
            Some(escaped) => Arc::new(escaped.text().to_string()),
            None => text.clone(),
        };
        ShownSource {
            named: NamedSource::new(escape(name), shown_text),
            original: text.clone(),
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
}

impl SourceCode for ShownSource {
    fn read_span<'a>(
        &'a self,
        span: &SourceSpan,
        context_lines_before: usize,
        context_lines_after: usize,
    ) -> Result<Box<dyn SpanContents<'a> + 'a>, MietteError> {
        let contents = self
            .named
            .read_span(span, context_lines_before, context_lines_after)?;
        // Without lines before, the contents start at the span, and miette
        // takes the column it shows from them: count it in the original.
        let Some(escaped) = self.escaped.as_ref().filter(|_| context_lines_before == 0) else {
            return Ok(contents);
        };
        let at = escaped.original(span.offset());
        let line_start = self.original[..at]
            .rfind(['\n', '\r', '\u{85}'])
            .map_or(0, |i| {
                i + self.original[i..].chars().next().map_or(1, char::len_utf8)
            });
        Ok(Box::new(MietteSpanContents::new_named(
            contents.name().unwrap_or_default().to_string(),
            contents.data(),
            *contents.span(),
            contents.line(),
            at - line_start,
            contents.line_count(),
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
