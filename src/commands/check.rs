//! `raytracer check`: the linter. Checks every scene given, prints every
//! diagnostic in the chosen format, and exits 0 (clean or warnings only),
//! 1 (errors, or warnings with `--deny-warnings`) or 2 (a scene could not be
//! read; the others are still checked).
//!
//! Diagnostics are the command's output, so they go to stdout (as for other
//! linters); only failures that are not the scene's fault go to stderr.

use std::io::{IsTerminal, Write};
use std::path::Path;

use super::{load, Failure, Loaded, Outcome, ReadSceneError};
use crate::cli::{CheckArgs, Format};
use crate::diagnostic::JsonDiagnostic;

/// Run `raytracer check`.
pub fn run(args: CheckArgs) -> Result<Outcome, Failure> {
    let mut out = Output::new(args.format);
    let mut unreadable = false;
    let mut failed = false;
    for path in &args.scenes {
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
        let width = std::env::var("COLUMNS")
            .ok()
            .and_then(|c| c.parse().ok())
            .filter(|&w: &usize| w >= 40)
            .unwrap_or(100);
        Output {
            format,
            color: std::io::stdout().is_terminal() && std::env::var_os("NO_COLOR").is_none(),
            width,
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

    fn unreadable(&mut self, path: &Path, error: ReadSceneError) {
        if self.format == Format::Json {
            self.json.push(JsonDiagnostic {
                code: "io::read_scene".to_string(),
                severity: "error",
                message: error.to_string(),
                help: None,
                file: path.display().to_string(),
                labels: Vec::new(),
            });
        }
        eprintln!("{:?}", miette::Report::new(error));
    }

    fn finish(self) -> Result<(), Failure> {
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
            .map_err(|e| miette::miette!("cannot write to stdout: {e}").into())
    }
}

/// `scene.txt: 2 errors, 1 warning`, or for a scene without errors
/// `scene.txt: ok; effects: shadows, reflection`.
fn summary(loaded: &Loaded) -> String {
    let report = &loaded.report;
    let (errors, warnings) = (report.error_count(), report.warning_count());
    let name = &report.source.name;
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
            let effects = checked.effects();
            let used: Vec<&str> = [
                (effects.shadows, "shadows"),
                (effects.reflection, "reflection"),
                (effects.textures, "textures"),
            ]
            .into_iter()
            .filter_map(|(on, name)| on.then_some(name))
            .collect();
            let used = if used.is_empty() {
                "none".to_string()
            } else {
                used.join(", ")
            };
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
