//! A program that uses `raytracer` as a library, built without its command
//! line (`default-features = false`): it checks a scene held in memory,
//! applies the fix the check offers, lowers and renders the fixed scene,
//! and prints it as JSON. `make test` builds and runs it
//! (scripts/library_user.sh), so the public API stays usable on its own.

use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use raytracer::fix::{self, Applicability};
use raytracer::{convert, frontend, ir, render};

/// A misspelt attribute name: `check` offers a fix.
const SCENE: &str =
    "camera 8\nsphere\n  dimension 1\n  centre 0 0 -5\nlight\n  location 0 5 0\n  color 1 1 1\n";

fn main() -> ExitCode {
    let loaded = frontend::load_bytes(
        "scene.txt",
        Path::new("."),
        SCENE.as_bytes(),
        Instant::now(),
    );
    if loaded.checked.is_some() {
        eprintln!("expected `centre` to be reported");
        return ExitCode::FAILURE;
    }
    let fixes = loaded.report.fixes_up_to(Applicability::Unsafe);
    let (fixed, applied) = fix::apply(SCENE, fixes);
    if applied.is_empty() {
        eprintln!("expected a fix for `centre`");
        return ExitCode::FAILURE;
    }
    let loaded = frontend::load_bytes(
        "scene.txt",
        Path::new("."),
        fixed.as_bytes(),
        Instant::now(),
    );
    let Some(checked) = loaded.checked else {
        eprint!("{}", loaded.report.render_short());
        return ExitCode::FAILURE;
    };
    let json = convert::json::to_json(&checked.scene);
    let scene = ir::lower(checked);
    let (image, counters) = render::render::<f64>(&scene, &render::Options::default(), &|| ());
    if image.rgb.len() != 8 * 8 * 3 || counters.primary_rays != 64 {
        eprintln!("expected an 8×8 image from 64 camera rays");
        return ExitCode::FAILURE;
    }
    println!("{json}");
    ExitCode::SUCCESS
}
