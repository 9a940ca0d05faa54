//! `raytracer convert`: load a scene (text or JSON), and print its checked
//! model as JSON, canonical scene text or POV-Ray to stdout or, with `-o`,
//! to a file written whole or not at all. Texture paths are rewritten to
//! resolve from the output's folder (stdout: the working directory).
//!
//! A scene with errors converts to nothing: its diagnostics go to stderr and
//! the command exits 1 without writing. Warnings go to stderr too, and the
//! conversion goes ahead.

use std::io::Write;
use std::path::Path;

use super::Outcome;
use crate::cli::{ConvertArgs, Target};
use raytracer_render::output::{check_not_input, write_atomically};
use raytracer_scene::convert::{json, paths, pov, scene_text};
use raytracer_scene::diagnostic::{terminal_width, use_color};
use raytracer_scene::diagnostic::{BoxedDiagnostic, FileError};
use raytracer_scene::frontend::load;

/// `-o PATH` could not be written.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
#[error(transparent)]
#[diagnostic(code(io::write_output))]
pub struct WriteOutputError(FileError);

/// Run `raytracer convert`.
pub fn run(args: ConvertArgs) -> Result<Outcome, BoxedDiagnostic> {
    let loaded = match load(&args.scene) {
        Ok(loaded) => loaded,
        Err(error) => return Err(Box::new(error)),
    };
    let report = &loaded.report;
    if !report.diagnostics.is_empty() {
        let stderr = std::io::stderr();
        say!(
            "{}",
            report.render_human(terminal_width(), use_color(&stderr))
        );
    }
    let Some(mut checked) = loaded.checked else {
        return Ok(Outcome::SceneErrors);
    };
    // Texture paths resolve from the output's folder (the working directory
    // for stdout), wherever the scene was.
    let destination = args
        .output
        .as_deref()
        .map_or(Path::new("."), raytracer_scene::folder::folder_of);
    paths::rebase_textures(&mut checked, destination);
    let checked = &checked;
    // The command line made sure a target is given or inferred.
    let text = match args.target().unwrap_or(Target::Json) {
        Target::Json => json::to_json(&checked.scene),
        Target::Scene => {
            scene_text::to_scene_text(&checked.scene).map_err(|e| Box::new(e) as BoxedDiagnostic)?
        }
        Target::Pov => pov::to_pov(checked),
    };
    match &args.output {
        Some(path) => {
            // Rewriting the scene in place would lose its comments and layout.
            let scene = (args.scene != Path::new("-")).then_some(args.scene.as_path());
            let textures = checked.textures.values().map(|t| Path::new(&t.path));
            check_not_input(path, scene.into_iter().chain(textures))?;
            write_atomically(path, |out| out.write_all(text.as_bytes())).map_err(|error| {
                Box::new(WriteOutputError(FileError::written("write", path, &error)))
                    as BoxedDiagnostic
            })?
        }
        None => {
            let mut stdout = std::io::stdout().lock();
            stdout
                .write_all(text.as_bytes())
                .and_then(|()| stdout.flush())
                .map_err(super::stdout_error)?;
        }
    }
    Ok(Outcome::Success)
}
