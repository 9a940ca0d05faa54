//! Fuzz target: scene text through the whole front end and a tiny render.
//!
//! Any bytes go through UTF-8 decoding, the parser, the check pass (texture
//! paths resolve in `tests/ui/scene`, which holds a small PPM), every
//! diagnostic format, lowering and a render of at most 4 × 4 pixels, so
//! hostile numbers reach the tracer too. A panic, an abort or a sanitizer
//! report is a finding; diagnostics are the expected outcome.

#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use raytracer_scene::frontend::load_bytes;
use raytracer_render::{ir, render};

fuzz_target!(|bytes: &[u8]| {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/ui/scene"));
    let loaded = load_bytes("fuzz.txt", dir, bytes);
    let report = &loaded.report;
    let _ = report.render_human(80, false);
    let _ = report.render_short();
    let _ = serde_json::to_string(&report.entries().collect::<Vec<_>>());
    if let Some(checked) = loaded.checked {
        let mut scene = ir::lower(checked);
        scene.resolution = scene.resolution.min(4);
        let options = render::Options::default();
        let _ = render::render(render::Precision::F64, &scene, &options, &|| {});
        let _ = render::render(render::Precision::F32, &scene, &options, &|| {});
    }
});
