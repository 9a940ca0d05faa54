//! `raytracer check`: the linter. Checks every scene given, prints every
//! diagnostic in the chosen format, and exits 0 (clean or warnings only),
//! 1 (errors, or warnings with `--deny-warnings`) or 2 (a scene could not be
//! read; the others are still checked).
//!
//! Diagnostics are the command's output, so they go to stdout (as for other
//! linters); only failures that are not the scene's fault go to stderr.
//!
//! With `--fix`, each file is checked, gets the safe fixes its diagnostics
//! carry (with `--unsafe-fixes`, the unsafe ones too; see [`crate::fix`]),
//! written atomically (a temporary file beside it, then a rename), and is
//! checked again, so the report shows what remains. Fixes replace single
//! numbers or words, so they apply to JSON scenes as they do to scene text.

use std::io::Write;
use std::path::Path;

use miette::Diagnostic;

use super::{Outcome, WriteStdoutError};
use crate::cli::{CheckArgs, Format};
use crate::diagnostic::BoxedDiagnostic;
use crate::diagnostic::{terminal_width, use_color, JsonDiagnostic};
use crate::escape::escape;
use crate::fix::{self, Applicability};
use crate::frontend::{load, Loaded, ReadSceneError};
use crate::output;

/// Run `raytracer check`.
pub fn run(args: CheckArgs) -> Result<Outcome, BoxedDiagnostic> {
    let mut out = Output::new(args.format);
    let mut unreadable = false;
    let mut failed = false;
    for path in &args.scenes {
        if args.fix {
            let applicability = if args.unsafe_fixes {
                Applicability::Unsafe
            } else {
                Applicability::Safe
            };
            match fix_in_place(path, applicability) {
                Ok(fixed) => out.fixed(&fixed),
                Err(error) => {
                    unreadable = true;
                    eprintln!("error: {}", escape(&error.to_string()));
                }
            }
        }
        match load(path) {
            Ok(loaded) => {
                let report = &loaded.report;
                failed |=
                    report.error_count() > 0 || (args.deny_warnings && report.warning_count() > 0);
                out.scene(&loaded);
            }
            Err(error) => {
                unreadable = true;
                out.unreadable(path, error);
            }
        }
    }
    out.finish()?;
    if unreadable {
        // The reasons are already printed; exit 2 without another message.
        return Ok(Outcome::InputErrors);
    }
    Ok(if failed {
        Outcome::SceneErrors
    } else {
        Outcome::Success
    })
}

/// Where results go, per format.
struct Output {
    format: Format,
    color: bool,
    width: usize,
    json: Vec<JsonDiagnostic>,
}

impl Output {
    fn new(format: Format) -> Output {
        Output {
            format,
            color: use_color(&std::io::stdout()),
            width: terminal_width(),
            json: Vec::new(),
        }
    }

    fn scene(&mut self, loaded: &Loaded) {
        let report = &loaded.report;
        match self.format {
            Format::Human => {
                print!("{}", report.render_human(self.width, self.color));
                println!("{}", summary(loaded));
            }
            Format::Short => {
                print!("{}", report.render_short());
                println!("{}", summary(loaded));
            }
            Format::Json => self.json.extend(report.entries()),
        }
    }

    /// Say what `--fix` changed: on stdout with the diagnostics, or on
    /// stderr when stdout is JSON.
    fn fixed(&self, fixed: &[String]) {
        for line in fixed {
            let line = escape(line);
            if self.format == Format::Json {
                eprintln!("{line}");
            } else {
                println!("{line}");
            }
        }
    }

    fn unreadable(&mut self, path: &Path, error: ReadSceneError) {
        if self.format == Format::Json {
            self.json.push(JsonDiagnostic {
                code: error.code().map(|c| c.to_string()).unwrap_or_default(),
                severity: "error",
                message: error.to_string(),
                help: error.help().map(|h| h.to_string()),
                file: path.display().to_string(),
                labels: Vec::new(),
                fix: None,
            });
        }
        eprintln!("error: {}", escape(&error.to_string()));
        if let Some(help) = error.help() {
            eprintln!("  help: {}", escape(&help.to_string()));
        }
    }

    fn finish(self) -> Result<(), BoxedDiagnostic> {
        let mut stdout = std::io::stdout().lock();
        let written = if self.format == Format::Json {
            serde_json::to_writer_pretty(&mut stdout, &self.json)
                .map_err(std::io::Error::from)
                .and_then(|()| writeln!(stdout))
        } else {
            Ok(())
        };
        written
            .and_then(|()| stdout.flush())
            .map_err(|e| Box::new(WriteStdoutError::from(e)) as BoxedDiagnostic)
    }
}

/// `--fix` could not rewrite a scene file.
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error("cannot write fixes to `{path}` (it is unchanged): {reason}")]
#[diagnostic(code(io::write_fix))]
pub struct WriteFixError {
    pub path: String,
    pub reason: std::io::Error,
}

/// Apply the fixes of at most `applicability` that the diagnostics of the
/// scene at `path` carry, in place, returning one `file:line:column:
/// fixed: …` line per fix. Stdin, unreadable files (the check reports them)
/// and files that are not UTF-8 (rewriting would replace their bad bytes)
/// are left alone.
fn fix_in_place(path: &Path, applicability: Applicability) -> Result<Vec<String>, WriteFixError> {
    if path == Path::new("-") {
        return Ok(vec![
            "<stdin>: not fixed: `--fix` rewrites files, not stdin".to_string(),
        ]);
    }
    let Ok(loaded) = load(path) else {
        return Ok(Vec::new());
    };
    let report = &loaded.report;
    let name = &report.source.name;
    if report
        .diagnostics
        .iter()
        .any(|d| is_invalid_utf8(d.as_ref()))
    {
        return Ok(vec![format!(
            "{name}: not fixed: the file is not valid UTF-8"
        )]);
    }
    let (fixed, applied) = fix::apply(&report.source.text, report.fixes_up_to(applicability));
    if applied.is_empty() {
        return Ok(Vec::new());
    }
    output::write_atomically(path, |out| out.write_all(fixed.as_bytes())).map_err(|reason| {
        WriteFixError {
            path: name.clone(),
            reason,
        }
    })?;
    Ok(applied
        .iter()
        .map(|f| {
            let at = f.edits.first().map_or(0, |e| e.span.start());
            let (line, column) = report.source.line_col(at);
            format!("{name}:{line}:{column}: fixed: {}", f.message)
        })
        .collect())
}

/// Whether `diagnostic` says the file is not UTF-8.
fn is_invalid_utf8(diagnostic: &dyn Diagnostic) -> bool {
    diagnostic
        .code()
        .is_some_and(|code| code.to_string() == "syntax::invalid_utf8")
}

/// `scene.txt: 2 errors, 1 warning`, or for a scene without errors
/// `scene.txt: ok; effects: shadows, reflection` (the name escaped).
fn summary(loaded: &Loaded) -> String {
    let report = &loaded.report;
    let (errors, warnings) = (report.error_count(), report.warning_count());
    let name = escape(&report.source.name);
    let counts = match (errors, warnings) {
        (0, 0) => "ok".to_string(),
        _ => format!(
            "{}, {}",
            plural(errors, "error"),
            plural(warnings, "warning")
        ),
    };
    match &loaded.checked {
        Some(checked) => {
            let used = checked.effects().summary();
            format!("{name}: {counts}; effects: {used}")
        }
        None => format!("{name}: {counts}"),
    }
}

fn plural(n: usize, word: &str) -> String {
    format!("{n} {word}{}", if n == 1 { "" } else { "s" })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plurals() {
        assert_eq!(plural(1, "error"), "1 error");
        assert_eq!(plural(0, "warning"), "0 warnings");
    }
}
