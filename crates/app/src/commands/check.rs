//! `raytracer check`: the linter. Checks every scene given or found in the
//! folders given ([`crate::discover`]), names every file a walk skipped
//! with the reason, prints every diagnostic in the chosen format (the
//! first `--max-errors` of each file in the formats read by people, then
//! how many more there are), over several files a total line, and exits 0
//! (clean or warnings only), 1 (errors, or warnings with
//! `--deny-warnings`) or 2 (a scene could not be read; the others are
//! still checked).
//!
//! Diagnostics are the command's output, so they go to stdout (as for other
//! linters); only failures that are not the scene's fault go to stderr.
//!
//! With `--fix`, each file is checked, gets the safe fixes its diagnostics
//! carry (with `--unsafe-fixes`, the unsafe ones too; see [`raytracer_scene::fix`]),
//! written atomically (a temporary file beside it, then a rename), and is
//! checked again, so the report shows what remains, and a last line counts
//! the unsafe fixes left for `--unsafe-fixes` (which implies `--fix`).
//! Fixes replace single
//! numbers or words, so they apply to JSON scenes as they do to scene text.

use std::io::Write;
use std::path::Path;

use miette::Diagnostic;

use super::Outcome;
use crate::ci::{self, github, sarif, Finding};
use crate::cli::{CheckArgs, Format};
use crate::discover::{discover, Found};
use raytracer_render::ir::Effects;
use raytracer_render::output;
use raytracer_scene::check::Summary;
use raytracer_scene::diagnostic::{
    terminal_width, use_color, write_json, BoxedDiagnostic, FileError, JsonDiagnostic, Report,
};
use raytracer_scene::escape::escape;
use raytracer_scene::fix::{self, Applicability};
use raytracer_scene::frontend::{load_summary, Loaded};

/// Run `raytracer check`.
pub fn run(args: CheckArgs) -> Result<Outcome, BoxedDiagnostic> {
    let discovered = discover(&args.scenes);
    let max_problems = (args.max_errors > 0).then_some(args.max_errors);
    let mut out = Output::new(args.format, max_problems);
    let mut totals = Totals::default();
    let mut failed = false;
    // A file named on the command line that cannot be read: exit 2.
    let mut named_unreadable = false;
    let several = discovered.walked || discovered.found.len() > 1;
    // `--unsafe-fixes` alone means `--fix --unsafe-fixes`.
    let fixing = args.fix || args.unsafe_fixes;
    // After safe fixes, the unsafe fixes the checked files still carry.
    let mut unsafe_left = 0;
    for found in &discovered.found {
        let (path, named) = match found {
            Found::Scene { path, named } => (path, *named),
            Found::Skipped { path, reason } => {
                totals.skipped += 1;
                out.skipped(path, reason)?;
                continue;
            }
            Found::Unreadable(error) => {
                totals.unreadable += 1;
                failed = true;
                out.unreadable(Path::new(error.path()), error)?;
                continue;
            }
        };
        if fixing {
            let applicability = if args.unsafe_fixes {
                Applicability::Unsafe
            } else {
                Applicability::Safe
            };
            match fix_in_place(path, applicability) {
                Ok(fixed) => out.fixed(&fixed)?,
                Err(error) => {
                    totals.unreadable += 1;
                    failed = true;
                    named_unreadable |= named;
                    sayln!("error: {}", escape(&error.to_string()));
                }
            }
        }
        match load_summary(path) {
            Ok(loaded) => {
                let report = &loaded.report;
                failed |=
                    report.error_count() > 0 || (args.deny_warnings && report.warning_count() > 0);
                totals.add(report);
                if fixing && !args.unsafe_fixes {
                    unsafe_left += report
                        .fixes_up_to(Applicability::Unsafe)
                        .iter()
                        .filter(|f| f.applicability == Applicability::Unsafe)
                        .count();
                }
                out.scene(&loaded)?;
            }
            Err(error) => {
                totals.unreadable += 1;
                failed = true;
                named_unreadable |= named;
                out.unreadable(path, &error)?;
            }
        }
    }
    if several {
        out.total(&totals)?;
    }
    if unsafe_left > 0 {
        let fixes = if unsafe_left == 1 { "fix" } else { "fixes" };
        out.note(&format!(
            "{unsafe_left} more {fixes} can be applied with `--unsafe-fixes` (review them: each is a likely intent, not a certainty)"
        ))?;
    }
    out.finish()?;
    if named_unreadable {
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

/// The code of the entry the machine formats give a file a walk skipped.
const SKIPPED_CODE: &str = "io::skipped";

/// Where results go, per format.
struct Output {
    format: Format,
    color: bool,
    width: usize,
    /// The most diagnostics the human and short formats show per file.
    max_problems: Option<usize>,
    json: Vec<JsonDiagnostic>,
    sarif: Vec<Finding>,
}

impl Output {
    fn new(format: Format, max_problems: Option<usize>) -> Output {
        Output {
            format,
            color: use_color(&std::io::stdout()),
            width: terminal_width(),
            max_problems,
            json: Vec::new(),
            sarif: Vec::new(),
        }
    }

    fn scene(&mut self, loaded: &Loaded<Summary>) -> Result<(), BoxedDiagnostic> {
        let report = &loaded.report;
        let shown = self.max_problems.unwrap_or(usize::MAX);
        match self.format {
            Format::Human => {
                out!(
                    "{}",
                    report.render_human_at_most(shown, self.width, self.color)
                )?;
                self.not_shown(report)?;
                out!("{}\n", summary(loaded))?;
            }
            Format::Short => {
                out!("{}", report.render_short_at_most(shown))?;
                self.not_shown(report)?;
                out!("{}\n", summary(loaded))?;
            }
            Format::Json => self.json.extend(report.entries()),
            Format::Sarif => self.sarif.extend(ci::findings(report)),
            Format::Github => {
                for finding in ci::findings(report) {
                    out!("{}\n", github::command(&finding))?;
                }
            }
        }
        Ok(())
    }

    /// `scene.txt: 9980 more problems not shown (…)`, after the first
    /// `--max-errors` of a file's diagnostics.
    fn not_shown(&self, report: &Report) -> Result<(), BoxedDiagnostic> {
        let Some(max) = self.max_problems else {
            return Ok(());
        };
        let hidden = report.diagnostics.len().saturating_sub(max);
        if hidden == 0 {
            return Ok(());
        }
        out!(
            "{}: {} not shown (`--max-errors 0` shows every one)\n",
            escape(&report.source.name),
            plural(hidden, "more problem")
        )
    }

    /// Say what `--fix` changed: on stdout with the diagnostics, or on
    /// stderr when stdout is for machines.
    fn fixed(&self, fixed: &[String]) -> Result<(), BoxedDiagnostic> {
        for line in fixed {
            self.note(&escape(line))?;
        }
        Ok(())
    }

    /// A line for people about the run, not a diagnostic: on stdout with
    /// the diagnostics, or on stderr when stdout is for machines.
    fn note(&self, line: &str) -> Result<(), BoxedDiagnostic> {
        if self.format_is_for_machines() {
            sayln!("{line}");
            Ok(())
        } else {
            out!("{line}\n")
        }
    }

    /// A file a walk found and did not check, named with the reason: a
    /// line in the formats read by people, a note in the others.
    fn skipped(&mut self, path: &Path, reason: &str) -> Result<(), BoxedDiagnostic> {
        let name = path.display().to_string();
        let entry = JsonDiagnostic {
            code: SKIPPED_CODE.to_string(),
            severity: "advice",
            message: format!("not checked: not a scene: {reason}"),
            help: None,
            file: name.clone(),
            labels: Vec::new(),
            fix: None,
        };
        match self.format {
            Format::Human | Format::Short => {
                out!(
                    "{}: skipped, not a scene: {}\n",
                    escape(&name),
                    escape(reason)
                )
            }
            Format::Json => {
                self.json.push(entry);
                Ok(())
            }
            Format::Sarif => {
                self.sarif.push(Finding::without_source(entry));
                Ok(())
            }
            Format::Github => out!("{}\n", github::command(&Finding::without_source(entry))),
        }
    }

    /// The closing line of a run over several files or a folder, in the
    /// formats read by people.
    fn total(&self, totals: &Totals) -> Result<(), BoxedDiagnostic> {
        if matches!(self.format, Format::Human | Format::Short) {
            out!("{}\n", totals.line())?;
        }
        Ok(())
    }

    fn format_is_for_machines(&self) -> bool {
        matches!(self.format, Format::Json | Format::Sarif | Format::Github)
    }

    fn unreadable(&mut self, path: &Path, error: &dyn Diagnostic) -> Result<(), BoxedDiagnostic> {
        let entry = JsonDiagnostic::unreadable(path, error);
        match self.format {
            Format::Human | Format::Short => {}
            Format::Json => self.json.push(entry),
            Format::Sarif => self.sarif.push(Finding::without_source(entry)),
            Format::Github => out!("{}\n", github::command(&Finding::without_source(entry)))?,
        }
        sayln!("error: {}", escape(&error.to_string()));
        if let Some(help) = error.help() {
            sayln!("  help: {}", escape(&help.to_string()));
        }
        Ok(())
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
            .map_err(super::stdout_error)
    }
}

/// `--fix` could not rewrite a scene file.
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error(transparent)]
#[diagnostic(code(io::write_fix), help("the file is unchanged"))]
pub struct WriteFixError(FileError);

/// Apply the fixes of at most `applicability` that the diagnostics of the
/// scene at `path` carry, in place, returning one `file:line:column:
/// applied: …` line per fix (the fix's message, in the imperative:
/// "applied: write `normal 0 1 0`"). Stdin, unreadable files (the check reports them)
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
    output::write_atomically(path, |out| out.write_all(fixed.as_bytes()))
        .map_err(|error| WriteFixError(FileError::written("write fixes to", path, &error)))?;
    Ok(applied
        .iter()
        .map(|f| {
            let at = f.edits.first().map_or(0, |e| e.span.start());
            let (line, column) = report.source.line_col(at);
            format!("{name}:{line}:{column}: applied: {}", f.message)
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
