//! Source files and the diagnostics reported against them.
//!
//! Every stage reports problems as `miette::Diagnostic` values with spans
//! into one [`SourceFile`]. A [`Report`] owns that source and the list of
//! diagnostics (the kdl-rs shape: one owner, many related problems) and
//! renders them in the three formats of `raytracer check`: human (miette's
//! graphical handler), short (`file:line:col: severity[code]: message`) and
//! JSON (docs/cli.md). The first two are for terminals and show scene text
//! and file names through [`shown`], which escapes what a terminal would
//! obey; JSON carries them exactly.

mod shown;

use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

use miette::{Diagnostic, GraphicalReportHandler, GraphicalTheme, Severity};
use serde::Serialize;

use crate::escape::escape;
use crate::fix::{Applicability, Fix};
use crate::line_index::LineIndex;
use crate::span::Span;
use crate::syntax::SyntaxError;

pub use crate::failure::{io_reason, lowercase_first, FileError};
pub use shown::{Shown, ShownSource};

/// A diagnostic of any stage, boxed so syntax and check problems share a
/// list; also how a command fails for a reason not the scene's (usage, I/O or
/// internal: exit 2).
pub type BoxedDiagnostic = Box<dyn Diagnostic + Send + Sync + 'static>;

/// Diagnostics of one type, boxed to be reported with others.
pub fn boxed<D: Diagnostic + Send + Sync + 'static>(diagnostics: Vec<D>) -> Vec<BoxedDiagnostic> {
    diagnostics
        .into_iter()
        .map(|d| Box::new(d) as BoxedDiagnostic)
        .collect()
}

/// Scene text with the name to show for it and the folder texture paths
/// resolve against.
#[derive(Clone, Debug)]
pub struct SourceFile {
    /// As given on the command line (`-` shows as `<stdin>`).
    pub name: String,
    /// Shared with the diagnostics' snippets; an `Arc<String>` so the
    /// buffer a file was read into becomes the text without a copy.
    pub text: Arc<String>,
    /// The scene file's folder (the working directory for stdin).
    pub dir: PathBuf,
    /// Where `text`'s lines start, built on the first lookup (a file
    /// without problems never needs it).
    lines: Arc<OnceLock<LineIndex>>,
}

impl SourceFile {
    /// Decode `bytes` read from `name`. Invalid UTF-8 is replaced with
    /// U+FFFD and reported at the first bad byte, so parsing can continue.
    pub fn from_bytes(name: &str, dir: &Path, bytes: &[u8]) -> (SourceFile, Option<SyntaxError>) {
        // Valid text (the usual case) is validated once, and only invalid
        // text goes through the lossy decoder.
        SourceFile::from_vec(name, dir, bytes.to_vec())
    }

    /// [`SourceFile::from_bytes`], taking the buffer: valid UTF-8 (the
    /// usual case) is validated once and becomes the text as it is. A file
    /// that is not text at all ([`crate::encoding::sniff`]) becomes an
    /// empty text and one [`SyntaxError::NotText`], and is not parsed
    /// (see [`crate::frontend`]).
    pub fn from_vec(name: &str, dir: &Path, bytes: Vec<u8>) -> (SourceFile, Option<SyntaxError>) {
        let (text, error) = match crate::encoding::sniff(&bytes) {
            Some(not_text) => (
                String::new(),
                Some(SyntaxError::NotText {
                    found: not_text.found(),
                    help: not_text.help(),
                }),
            ),
            None => match String::from_utf8(bytes) {
                Ok(text) => (text, None),
                Err(e) => {
                    let (bytes, e) = (e.as_bytes(), e.utf8_error());
                    let len = e.error_len().unwrap_or(bytes.len() - e.valid_up_to());
                    let error = SyntaxError::InvalidUtf8 {
                        span: Span::new(e.valid_up_to(), e.valid_up_to() + len).into(),
                    };
                    (String::from_utf8_lossy(bytes).into_owned(), Some(error))
                }
            },
        };
        let file = SourceFile {
            name: name.to_string(),
            text: Arc::new(text),
            dir: dir.to_path_buf(),
            lines: Arc::default(),
        };
        (file, error)
    }

    /// 1-based line and column (in characters) of a byte offset. Lines end
    /// at `\n`, as in the human renderer. Logarithmic in the text's size
    /// (see [`LineIndex`]), so a report costs no more per problem in a
    /// large file than in a small one.
    pub fn line_col(&self, offset: usize) -> (usize, usize) {
        self.lines
            .get_or_init(|| LineIndex::new(&self.text))
            .line_col(&self.text, offset)
    }
}

/// One source file and every diagnostic reported against it, sorted by
/// position (errors before warnings at the same position, then a point
/// before a longer label, so the order does not depend on layout: a
/// diagnostic about the whole file, placed at its start, stays first when
/// formatting moves the first token there), each with the fix it carries,
/// if any.
pub struct Report {
    pub source: SourceFile,
    pub diagnostics: Vec<BoxedDiagnostic>,
    /// `fixes[i]` is the fix of `diagnostics[i]`.
    pub fixes: Vec<Option<Fix>>,
}

impl Report {
    /// Collect diagnostics for `source`, ordered by their first label.
    pub fn new(source: SourceFile, diagnostics: Vec<BoxedDiagnostic>) -> Report {
        Report::with_fixes(source, diagnostics.into_iter().map(|d| (d, None)).collect())
    }

    /// [`Report::new`] for diagnostics that may carry fixes.
    pub fn with_fixes(
        source: SourceFile,
        mut fixed: Vec<(BoxedDiagnostic, Option<Fix>)>,
    ) -> Report {
        fixed.sort_by_key(|(d, _)| {
            let (offset, length) = first_label(d.as_ref());
            (offset, severity_rank(d.as_ref()), length)
        });
        let (diagnostics, fixes) = fixed.into_iter().unzip();
        Report {
            source,
            diagnostics,
            fixes,
        }
    }

    /// The fixes of at most `applicability` (safe, or safe and unsafe), in
    /// source order.
    pub fn fixes_up_to(&self, applicability: Applicability) -> Vec<&Fix> {
        let mut fixes: Vec<&Fix> = self
            .fixes
            .iter()
            .flatten()
            .filter(|f| f.applicability <= applicability)
            .collect();
        fixes.sort_by_key(|f| f.edits.first().map(|e| e.span.start()));
        fixes
    }

    /// How many diagnostics are errors.
    pub fn error_count(&self) -> usize {
        self.count(Severity::Error)
    }

    /// How many diagnostics are warnings.
    pub fn warning_count(&self) -> usize {
        self.count(Severity::Warning)
    }

    fn count(&self, severity: Severity) -> usize {
        self.diagnostics
            .iter()
            .filter(|d| severity_of(d.as_ref()) == severity)
            .count()
    }

    /// miette's graphical rendering of every diagnostic, `width` columns
    /// wide, with colour or with the plain Unicode theme, its text escaped.
    pub fn render_human(&self, width: usize, color: bool) -> String {
        self.render_human_at_most(usize::MAX, width, color)
    }

    /// [`Report::render_human`] of the first `max` diagnostics. Each costs
    /// the same wherever it is in the file (snippets are read through a
    /// line index, [`ShownSource`]), so a report is linear in the number
    /// shown.
    pub fn render_human_at_most(&self, max: usize, width: usize, color: bool) -> String {
        let theme = if color {
            GraphicalTheme::unicode()
        } else {
            GraphicalTheme::unicode_nocolor()
        };
        if self.diagnostics.is_empty() || max == 0 {
            // No snippet to show: the source is not escaped (a scan of all
            // of a large scene's text).
            return String::new();
        }
        let handler = GraphicalReportHandler::new_themed(theme).with_width(width);
        let source = ShownSource::new(&self.source.name, &self.source.text);
        let mut out = String::new();
        for diagnostic in self.diagnostics.iter().take(max) {
            let shown = Shown::new(diagnostic.as_ref(), Some(&source));
            // Writing to a String cannot fail.
            let _ = handler.render_report(&mut out, &shown);
            out.push('\n');
        }
        out
    }

    /// One line per diagnostic: `file:line:col: severity[code]: message`,
    /// its text escaped.
    pub fn render_short(&self) -> String {
        self.render_short_at_most(usize::MAX)
    }

    /// [`Report::render_short`] of the first `max` diagnostics.
    pub fn render_short_at_most(&self, max: usize) -> String {
        self.entries()
            .take(max)
            .map(|e| {
                let (line, column) = e.labels.first().map_or((1, 1), |l| (l.line, l.column));
                format!(
                    "{}:{line}:{column}: {}[{}]: {}\n",
                    escape(&e.file),
                    e.severity,
                    e.code,
                    escape(&e.message)
                )
            })
            .collect()
    }

    /// The diagnostics in the JSON shape of docs/cli.md.
    pub fn entries(&self) -> impl Iterator<Item = JsonDiagnostic> + '_ {
        self.diagnostics.iter().zip(&self.fixes).map(|(d, fix)| {
            let d = d.as_ref();
            JsonDiagnostic {
                code: d.code().map(|c| c.to_string()).unwrap_or_default(),
                severity: severity_name(severity_of(d)),
                message: d.to_string(),
                help: d.help().map(|h| h.to_string()),
                file: self.source.name.clone(),
                labels: d
                    .labels()
                    .into_iter()
                    .flatten()
                    .map(|l| {
                        let (line, column) = self.source.line_col(l.offset());
                        JsonLabel {
                            label: l.label().map(str::to_string),
                            byte_offset: l.offset(),
                            byte_length: l.len(),
                            line,
                            column,
                        }
                    })
                    .collect(),
                fix: fix.as_ref().map(|fix| JsonFix {
                    message: fix.message.clone(),
                    applicability: fix.applicability,
                    edits: fix
                        .edits
                        .iter()
                        .map(|e| {
                            let (line, column) = self.source.line_col(e.span.start());
                            JsonEdit {
                                byte_offset: e.span.start(),
                                byte_length: e.span.end() - e.span.start(),
                                line,
                                column,
                                content: e.content.clone(),
                            }
                        })
                        .collect(),
                }),
            }
        })
    }
}

/// A diagnostic as `check --format json` prints it.
#[derive(Clone, Debug, Serialize)]
pub struct JsonDiagnostic {
    pub code: String,
    pub severity: &'static str,
    pub message: String,
    pub help: Option<String>,
    pub file: String,
    pub labels: Vec<JsonLabel>,
    /// Omitted when the diagnostic carries no fix.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fix: Option<JsonFix>,
}

impl JsonDiagnostic {
    /// A file that could not be read, as `check --format json` reports it:
    /// the error's code, message and help, and no labels.
    pub fn unreadable(path: &Path, error: &dyn Diagnostic) -> JsonDiagnostic {
        JsonDiagnostic {
            code: error.code().map(|c| c.to_string()).unwrap_or_default(),
            severity: "error",
            message: error.to_string(),
            help: error.help().map(|h| h.to_string()),
            file: path.display().to_string(),
            labels: Vec::new(),
            fix: None,
        }
    }
}

/// `value` as the pretty JSON of `check --format json` and a line break.
pub fn write_json(out: &mut impl std::io::Write, value: &impl Serialize) -> std::io::Result<()> {
    serde_json::to_writer_pretty(&mut *out, value).map_err(std::io::Error::from)?;
    writeln!(out)
}

/// A [`Fix`] as `check --format json` prints it (ruff's shape, with byte
/// offsets).
#[derive(Clone, Debug, Serialize)]
pub struct JsonFix {
    pub message: String,
    pub applicability: Applicability,
    pub edits: Vec<JsonEdit>,
}

/// One edit of a [`JsonFix`]: replace `byte_length` bytes at `byte_offset`
/// (1-based `line` and `column`) with `content`.
#[derive(Clone, Debug, Serialize)]
pub struct JsonEdit {
    pub byte_offset: usize,
    pub byte_length: usize,
    pub line: usize,
    pub column: usize,
    pub content: String,
}

/// One labelled span of a [`JsonDiagnostic`]; line and column are 1-based.
#[derive(Clone, Debug, Serialize)]
pub struct JsonLabel {
    pub label: Option<String>,
    pub byte_offset: usize,
    pub byte_length: usize,
    pub line: usize,
    pub column: usize,
}

/// The width to render diagnostics at: `$COLUMNS` when it is at least 40,
/// else 100.
pub fn terminal_width() -> usize {
    std::env::var("COLUMNS")
        .ok()
        .and_then(|c| c.parse().ok())
        .filter(|&w: &usize| w >= 40)
        .unwrap_or(100)
}

/// Colour on `stream` when it is a terminal and `NO_COLOR` is unset.
pub fn use_color(stream: &impl std::io::IsTerminal) -> bool {
    stream.is_terminal() && std::env::var_os("NO_COLOR").is_none()
}

/// A diagnostic's severity, defaulting to error as miette does.
pub fn severity_of(d: &dyn Diagnostic) -> Severity {
    d.severity().unwrap_or(Severity::Error)
}

fn severity_name(severity: Severity) -> &'static str {
    match severity {
        Severity::Error => "error",
        Severity::Warning => "warning",
        Severity::Advice => "advice",
    }
}

fn severity_rank(d: &dyn Diagnostic) -> u8 {
    match severity_of(d) {
        Severity::Error => 0,
        Severity::Warning => 1,
        Severity::Advice => 2,
    }
}

/// The offset and length of the first label (a point at 0 when none).
fn first_label(d: &dyn Diagnostic) -> (usize, usize) {
    d.labels()
        .and_then(|mut labels| labels.next())
        .map_or((0, 0), |l| (l.offset(), l.len()))
}
