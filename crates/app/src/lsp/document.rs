//! An open document: its text, version and language, where its texture
//! paths resolve from, and its diagnostics through the library front end
//! (the same [`raytracer_scene::frontend`] call as `raytracer check`, so the editor
//! shows exactly what the command prints).

use std::path::{Path, PathBuf};

use lsp_types::{
    CodeDescription, Diagnostic, DiagnosticRelatedInformation, DiagnosticSeverity, Location,
    NumberOrString, TextDocumentContentChangeEvent, Url,
};

use super::position::Positions;
use raytracer_scene::diagnostic::severity_of;
use raytracer_scene::fix::Fix;
use raytracer_scene::frontend::{check_bytes_as, Language};
use raytracer_scene::span::Span;

/// An open document.
pub struct Document {
    pub uri: Url,
    pub text: String,
    pub version: i32,
    pub language: Language,
    /// The document's folder: texture paths resolve from here.
    pub dir: PathBuf,
    /// The last check and the version it was of: code actions, semantic
    /// tokens and the published diagnostics of one version share it.
    checked: Option<Checked>,
    /// How many times this document was checked: what tests count to see
    /// that a request was answered from the last check.
    #[cfg(test)]
    pub checks: usize,
}

/// The diagnostics of one version of a document, each with its fix.
struct Checked {
    version: i32,
    diagnostics: Vec<(Diagnostic, Option<Fix>)>,
}

impl Document {
    pub fn new(uri: Url, text: String, version: i32, language_id: &str) -> Document {
        let path = uri.to_file_path().ok();
        // The client's language id, where it says JSON, else the name.
        let language = if language_id == "json" {
            Language::Json
        } else {
            Language::of_name(Path::new(uri.path()))
        };
        // A document that is no file (an untitled buffer) resolves from the
        // server's working directory, as stdin does for `check`.
        let dir = path
            .as_deref()
            .and_then(Path::parent)
            .map(Path::to_path_buf)
            .unwrap_or_else(|| std::env::current_dir().unwrap_or_default());
        Document {
            uri,
            text,
            version,
            language,
            dir,
            checked: None,
            #[cfg(test)]
            checks: 0,
        }
    }

    /// Apply the changes of a `didChange`: a whole new text, or a range
    /// replaced (clamped to the text as [`Positions::offset`] says, and an
    /// end before the start taken as the start, so no edit can fail).
    pub fn apply(&mut self, changes: Vec<TextDocumentContentChangeEvent>, version: i32) {
        for change in changes {
            match change.range {
                None => self.text = change.text,
                Some(range) => {
                    let index = Positions::new(&self.text);
                    let start = index.offset(range.start);
                    let end = index.offset(range.end).max(start);
                    self.text.replace_range(start..end, &change.text);
                }
            }
        }
        self.version = version;
        // Also when a client repeats a version: the text is new.
        self.checked = None;
    }

    /// The name diagnostics and `check` show for this document.
    pub fn name(&self) -> String {
        match self.uri.to_file_path() {
            Ok(path) => path.display().to_string(),
            Err(()) => self.uri.to_string(),
        }
    }

    /// Check this version, unless the last check was of it. `docs` is the
    /// address of docs/diagnostics.md, beside which each code's section
    /// (in docs/diagnostics/) is linked from its diagnostic.
    pub fn check_if_changed(&mut self, docs: Option<&Url>) {
        let version = self.version;
        if self.checked.as_ref().is_none_or(|c| c.version != version) {
            #[cfg(test)]
            {
                self.checks += 1;
            }
            let diagnostics = self.check(docs);
            self.checked = Some(Checked {
                version,
                diagnostics,
            });
        }
    }

    /// The diagnostics of the last check, each with the fix it carries
    /// (none before [`Document::check_if_changed`]).
    pub fn diagnostics(&self) -> &[(Diagnostic, Option<Fix>)] {
        self.checked.as_ref().map_or(&[], |c| &c.diagnostics)
    }

    /// Every diagnostic of the front end, as the protocol's diagnostics,
    /// each with the fix it carries.
    fn check(&self, docs: Option<&Url>) -> Vec<(Diagnostic, Option<Fix>)> {
        let loaded = check_bytes_as(self.language, &self.name(), &self.dir, self.text.as_bytes());
        let index = Positions::new(&self.text);
        let report = loaded.report;
        report
            .diagnostics
            .iter()
            .zip(report.fixes)
            .map(|(d, fix)| (self.convert(d.as_ref(), &index, docs), fix))
            .collect()
    }

    fn convert(
        &self,
        d: &dyn miette::Diagnostic,
        index: &Positions,
        docs: Option<&Url>,
    ) -> Diagnostic {
        let labels: Vec<_> = d.labels().into_iter().flatten().collect();
        let span = |l: &miette::LabeledSpan| Span::new(l.offset(), l.offset() + l.len());
        let range = labels
            .first()
            .map_or_else(|| index.range(Span::point(0)), |l| index.range(span(l)));
        let code = d.code().map(|c| c.to_string());
        let mut message = d.to_string();
        if let Some(help) = d.help() {
            message.push_str(&format!("\nhelp: {help}"));
        }
        let mut related: Vec<DiagnosticRelatedInformation> = labels
            .iter()
            .filter_map(|l| {
                Some(DiagnosticRelatedInformation {
                    location: Location::new(self.uri.clone(), index.range(span(l))),
                    message: l.label()?.to_string(),
                })
            })
            .collect();
        for other in d.related().into_iter().flatten() {
            let at = other
                .labels()
                .and_then(|mut l| l.next())
                .map_or(Span::point(0), |l| span(&l));
            related.push(DiagnosticRelatedInformation {
                location: Location::new(self.uri.clone(), index.range(at)),
                message: other.to_string(),
            });
        }
        Diagnostic {
            range,
            severity: Some(match severity_of(d) {
                miette::Severity::Error => DiagnosticSeverity::ERROR,
                miette::Severity::Warning => DiagnosticSeverity::WARNING,
                miette::Severity::Advice => DiagnosticSeverity::HINT,
            }),
            code_description: code
                .as_deref()
                .zip(docs)
                .and_then(|(code, docs)| documentation(docs, code)),
            code: code.map(NumberOrString::String),
            source: Some("raytracer".to_string()),
            message,
            related_information: (!related.is_empty()).then_some(related),
            tags: None,
            data: None,
        }
    }
}

/// The section about `code`, on its page of docs/diagnostics/, beside
/// `docs`, the address of docs/diagnostics.md.
fn documentation(docs: &Url, code: &str) -> Option<CodeDescription> {
    let href = docs.join(&raytracer_scene::fix::documentation(code)).ok()?;
    Some(CodeDescription { href })
}
