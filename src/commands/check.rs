//! `raytracer check`: the linter. Checks every scene given or found in the
//! folders given ([`super::discover`]), prints every diagnostic in the chosen
//! format (and, over several files, a total line), and exits 0 (clean or
//! warnings only), 1 (errors, or warnings with `--deny-warnings`) or 2 (a
//! scene could not be read; the others are still checked).
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

use super::discover::discover;
use super::{Outcome, WriteStdoutError};
use crate::check::Summary;
use crate::ci::{self, github, sarif, Finding};
use crate::cli::{CheckArgs, Format};
use crate::diagnostic::{
    terminal_width, use_color, write_json, BoxedDiagnostic, JsonDiagnostic, Report,
};
use crate::escape::escape;
use crate::fix::{self, Applicability};
use crate::frontend::{load_summary, Loaded};
use crate::ir::Effects;
use crate::output;

/// Run `raytracer check`.
pub fn run(args: CheckArgs) -> Result<Outcome, BoxedDiagnostic> {
    let found = discover(&args.scenes);
    let mut out = Output::new(args.format);
    let mut totals = Totals {
        skipped: found.skipped,
        unreadable: found.errors.len(),
        ..Totals::default()
    };
    for error in &found.errors {
        out.unreadable(Path::new(&error.path), error);
    }
    let mut failed = false;
    for path in &found.scenes {
        if args.fix {
            let applicability = if args.unsafe_fixes {
                Applicability::Unsafe
            } else {
                Applicability::Safe
            };
            match fix_in_place(path, applicability) {
                Ok(fixed) => out.fixed(&fixed),
                Err(error) => {
                    totals.unreadable += 1;
                    eprintln!("error: {}", escape(&error.to_string()));
                }
            }
        }
        match load_summary(path) {
            Ok(loaded) => {
                let report = &loaded.report;
                failed |=
                    report.error_count() > 0 || (args.deny_warnings && report.warning_count() > 0);
                totals.add(report);
                out.scene(&loaded);
            }
            Err(error) => {
                totals.unreadable += 1;
                out.unreadable(path, &error);
            }
        }
    }
    if found.walked || found.scenes.len() > 1 {
        out.total(&totals);
    }
    out.finish()?;
    if totals.unreadable > 0 {
        // The reasons are already printed; exit 2 without another message.
        return Ok(Outcome::InputErrors);
    }
    Ok(if failed {
        Outcome::SceneErrors
    } else {
        Outcome::Success
    })
}

/// What the closing line of a run over several files counts.
#[derive(Debug, Default)]
struct Totals {
    files: usize,
    errors: usize,
    warnings: usize,
    skipped: usize,
    unreadable: usize,
}

impl Totals {
    fn add(&mut self, report: &Report) {
        self.files += 1;
        self.errors += report.error_count();
        self.warnings += report.warning_count();
    }

    /// `checked 3 files: 1 error, 2 warnings; 1 file skipped (not a scene)`.
    fn line(&self) -> String {
        let mut line = format!(
            "checked {}: {}, {}",
            plural(self.files, "file"),
            plural(self.errors, "error"),
            plural(self.warnings, "warning")
        );
        if self.unreadable > 0 {
            line += &format!("; {} unreadable", plural(self.unreadable, "file"));
        }
        if self.skipped > 0 {
            line += &format!("; {} skipped (not a scene)", plural(self.skipped, "file"));
        }
        line
    }
}

/// Where results go, per format.
struct Output {
    format: Format,
    color: bool,
    width: usize,
    json: Vec<JsonDiagnostic>,
    sarif: Vec<Finding>,
}

impl Output {
    fn new(format: Format) -> Output {
        Output {
            format,
            color: use_color(&std::io::stdout()),
            width: terminal_width(),
            json: Vec::new(),
            sarif: Vec::new(),
        }
    }

    fn scene(&mut self, loaded: &Loaded<Summary>) {
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
            Format::Sarif => self.sarif.extend(ci::findings(report)),
            Format::Github => {
                for finding in ci::findings(report) {
                    println!("{}", github::command(&finding));
                }
            }
        }
    }

    /// Say what `--fix` changed: on stdout with the diagnostics, or on
    /// stderr when stdout is for machines.
    fn fixed(&self, fixed: &[String]) {
        for line in fixed {
            let line = escape(line);
            if self.format_is_for_machines() {
                eprintln!("{line}");
            } else {
                println!("{line}");
            }
        }
    }

    /// The closing line of a run over several files or a folder, in the
    /// formats read by people.
    fn total(&self, totals: &Totals) {
        if matches!(self.format, Format::Human | Format::Short) {
            println!("{}", totals.line());
        }
    }

    fn format_is_for_machines(&self) -> bool {
        matches!(self.format, Format::Json | Format::Sarif | Format::Github)
    }

    fn unreadable(&mut self, path: &Path, error: &dyn Diagnostic) {
        let entry = JsonDiagnostic::unreadable(path, error);
        match self.format {
            Format::Human | Format::Short => {}
            Format::Json => self.json.push(entry),
            Format::Sarif => self.sarif.push(Finding::without_source(entry)),
            Format::Github => println!("{}", github::command(&Finding::without_source(entry))),
        }
        eprintln!("error: {}", escape(&error.to_string()));
        if let Some(help) = error.help() {
            eprintln!("  help: {}", escape(&help.to_string()));
        }
    }

    fn finish(self) -> Result<(), BoxedDiagnostic> {
        let mut stdout = std::io::stdout().lock();
        let written = match self.format {
            Format::Json => write_json(&mut stdout, &self.json),
            Format::Sarif => write_json(&mut stdout, &sarif::log(&self.sarif)),
            Format::Human | Format::Short | Format::Github => Ok(()),
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
    let Ok(loaded) = load_summary(path) else {
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
fn summary(loaded: &Loaded<Summary>) -> String {
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
        Some(summary) => {
            let used = Effects::of_summary(summary).summary();
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
