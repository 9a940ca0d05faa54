//! Fuzz target: JSON scenes (`.json`, `convert`) through the JSON reader,
//! the check pass, lowering and a render of at most 4 × 4 pixels, and
//! back out through every `convert` writer.

#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use raytracer_scene::frontend::load_bytes;
use raytracer_scene::convert;
use raytracer_render::ir;
use raytracer_render::render;

fuzz_target!(|bytes: &[u8]| {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/ui/scene"));
    let loaded = load_bytes("fuzz.json", dir, bytes);
    let report = &loaded.report;
    let _ = report.render_human(80, false);
    let _ = report.render_short();
    if let Some(checked) = loaded.checked {
        let _ = convert::scene_text::to_scene_text(&checked.scene);
        let _ = convert::json::to_json(&checked.scene);
        let _ = convert::pov::to_pov(&checked);
        let mut scene = ir::lower(checked);
        scene.resolution = scene.resolution.min(4);
        let _ = render::render(render::Precision::F64, &scene, &render::Options::default(), &|| {});
    }
});
