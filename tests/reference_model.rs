//! The default render against the render model of docs/rendering.md.
//!
//! [`reference`] is an independent float64 evaluation of that model that
//! also says which pixels are within a rounding step of a discontinuity (silhouettes,
//! edges, shadow boundaries). Every corpus scene and every scene in
//! scenes/ is rendered at the default settings; every other pixel must
//! agree to within 1/255. A few small scenes are also checked, from scene
//! text to pixel, against values worked out by hand.

use std::path::Path;

use crate::reference::assert_renders_match_reference;
use crate::support::{corpus_copy, lower, lower_in, pixel, quantized, render};
use raytracer_render::render::Options;

#[test]
fn corpus_and_project_scenes_match_the_reference_model() {
    let (_dir, mut scenes) = corpus_copy();
    scenes.retain(|s| !s.ends_with("reflection_91b7c2f_headup010.txt"));
    let project = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    for entry in std::fs::read_dir(project).expect("scenes/") {
        let path = entry.expect("entry").path();
        if path.extension().is_some_and(|e| e == "txt") {
            scenes.push(path);
        }
    }
    assert!(scenes.len() >= 11, "found only {} scenes", scenes.len());
    for path in &scenes {
        let text = std::fs::read_to_string(path).expect("read scene");
        let scene = lower_in(&text, path.parent().expect("folder"), Some(160));
        let ours = render(&scene);
        let name = path.display().to_string();
        assert_renders_match_reference(
            &name,
            &scene,
            &Options::default(),
            1e-3,
            [("f64", ours.0, ours.1)],
        );
    }
}

// Pixel values worked out by hand. Resolution 1 puts the only pixel's ray
// straight down −z; resolution 2 aims the pixels at (±0.25, ±0.25, −1).

const LIT_PLANE: &str = "camera 1
plane dimension 2 2 center 0 0 -5 normal 0 0 1 headup 0 1 0 color .5 .5 .5
light location 0 0 0 color .4 .4 .4";

#[test]
fn a_lit_plane_is_ambient_plus_lambert() {
    // N·L̂ = 1: 0.1·0.5 + 0.5·0.4·1 = 0.25 → round(63.75) = 64.
    let (image, _) = render(&lower(LIT_PLANE));
    assert_eq!(pixel(&image, 0, 0), [64, 64, 64]);
}

#[test]
fn a_shadowed_point_keeps_only_ambient() {
    let off_axis = "camera 1
plane dimension 20 20 center 0 0 -5 normal 0 0 1 headup 0 1 0 color .5 .5 .5
light location 0 4 -1 color .4 .4 .4
sphere dimension .5 center 0 2 -3";
    // The camera ray misses the sphere; the shadow ray from (0,0,−5) to
    // the light at (0,4,−1) passes its centre (0,2,−3): only ambient is
    // left, 0.1·0.5 = 0.05 → round(12.75) = 13.
    let (image, counters) = render(&lower(off_axis));
    assert_eq!(pixel(&image, 0, 0), [13, 13, 13]);
    assert_eq!(counters.shadow_rays, 1);
}

#[test]
fn a_mirror_shows_the_sphere_behind_the_camera() {
    let scene = "camera 1
plane dimension 2 2 center 0 0 -5 normal 0 0 1 headup 0 1 0 color .2 .2 .2 reflectivity .5
sphere dimension 1 center 0 0 5 color 1 0 0
light location 0 0 2 color .5 .5 .5";
    // Mirror: 0.1·0.2 + 0.2·0.5·1 = 0.12. The reflected ray meets the
    // sphere at (0,0,4), lit head-on: 0.1·(1,0,0) + (1,0,0)·0.5 = (0.6,0,0).
    // Pixel: 0.12 + 0.5·(0.6,0,0) = (0.42, 0.12, 0.12) → (107, 31, 31).
    let (image, counters) = render(&lower(scene));
    assert_eq!(pixel(&image, 0, 0), [107, 31, 31]);
    assert_eq!(counters.reflection_rays, 1);
}

#[test]
fn each_pixel_reads_its_own_texel() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(
        dir.path().join("t.ppm"),
        "P3 2 2 255  200 0 0  0 200 0  0 0 200  100 100 100",
    )
    .expect("write texture");
    let scene = "camera 2
plane dimension 4 4 center 0 0 -5 normal 0 0 1 headup 0 1 0 texture t.ppm
light location 0 0 0 color 1 1 1";
    let (image, counters) = render(&lower_in(scene, dir.path(), None));
    // Pixel (0,0) hits (−1.25, 1.25, −5): u = 0.1875, v = 0.8125, so texel
    // x = ⌊0.375⌋ = 0, y = ⌊0.375⌋ = 0 (top left), and so on. N·L̂ is the
    // same for all four: 5/√(1.25² + 1.25² + 5²).
    let cos = 5.0 / (1.25f64 * 1.25 * 2.0 + 25.0).sqrt();
    let lit = |texel: [f64; 3]| quantized(texel.map(|c| c / 255.0 * (0.1 + cos)));
    assert_eq!(pixel(&image, 0, 0), lit([200.0, 0.0, 0.0]));
    assert_eq!(pixel(&image, 1, 0), lit([0.0, 200.0, 0.0]));
    assert_eq!(pixel(&image, 0, 1), lit([0.0, 0.0, 200.0]));
    assert_eq!(pixel(&image, 1, 1), lit([100.0, 100.0, 100.0]));
    assert_eq!(counters.texture_lookups, 4);
}
