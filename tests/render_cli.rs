//! `raytracer render` end to end: every corpus scene renders (but the one
//! docs/language.md calls wrong), the statistics prove that only the effects a
//! scene calls for are simulated, the image is the same for any number of
//! threads, and the output is what its extension says.

use crate::support;

use std::path::Path;

use crate::support::{corpus_copy, listing, lower, render, run};
use raytracer_render::render::Precision;
use serde_json::Value;

/// Render `scene` (text) with `--stats-json` and return the statistics.
fn stats_of(scene: &str) -> Value {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("scene.txt");
    std::fs::write(&path, scene).expect("write scene");
    let out = dir.path().join("out.ppm");
    let json = dir.path().join("stats.json");
    let output = run(&[
        "render",
        path.to_str().unwrap(),
        out.to_str().unwrap(),
        "--stats-json",
        json.to_str().unwrap(),
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    serde_json::from_slice(&std::fs::read(json).expect("stats written")).expect("stats JSON")
}

const SPHERE: &str = "camera 32\nsphere dimension 1 center 0 0 -4 color .5 .5 .5\n";
const PLANE: &str = "plane dimension 9 9 center 0 -1 -4 normal 0 1 0 headup 0 0 1\n";
const LIGHT: &str = "light location 2 3 0 color 1 1 1\n";

#[test]
fn stats_count_only_the_effects_the_scene_calls_for() {
    let plain = stats_of(&format!("{SPHERE}{PLANE}"));
    assert_eq!(plain["primary_rays"], 32 * 32);
    assert_eq!(plain["shadow_rays"], 0, "no lights, no shadow rays");
    assert_eq!(plain["reflection_rays"], 0, "nothing reflects");
    assert_eq!(plain["texture_lookups"], 0);
    assert_eq!(plain["effects"]["shadows"], false);
    for stage in ["parse", "check", "lower", "render", "write"] {
        assert!(plain["seconds"][stage].as_f64().is_some(), "{stage}");
    }
    assert!(plain["threads"].as_u64().is_some_and(|t| t >= 1));

    let lit = stats_of(&format!("{SPHERE}{PLANE}{LIGHT}"));
    assert!(lit["shadow_rays"].as_u64().unwrap() > 0);
    assert_eq!(lit["reflection_rays"], 0);

    let mirror = stats_of(&format!("{SPHERE}{PLANE}reflectivity .5\n"));
    let reflections = mirror["reflection_rays"].as_u64().unwrap();
    assert!(reflections > 0);
    assert_eq!(mirror["shadow_rays"], 0);
    assert_eq!(mirror["effects"]["reflection"], true);
}

#[test]
fn textures_are_read_only_where_a_textured_object_is_hit() {
    let wood = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/wood_tex.ppm");
    let scene = format!(
        "{SPHERE}{PLANE}texture \"{}\"\n",
        wood.display().to_string().replace('\\', "\\\\")
    );
    let stats = stats_of(&scene);
    let lookups = stats["texture_lookups"].as_u64().unwrap();
    // Only camera rays that hit the plane read a texel: fewer than all.
    assert!(lookups > 0 && lookups < 32 * 32, "{lookups}");
    assert_eq!(stats["effects"]["textures"], true);
}

#[test]
fn the_image_is_the_same_for_any_number_of_threads() {
    let (_dir, scenes) = corpus_copy();
    let scene = scenes
        .iter()
        .find(|s| s.ends_with("christmas_ornaments.txt"))
        .expect("christmas_ornaments.txt");
    let text = std::fs::read_to_string(scene).expect("read");
    let ir = lower(&text.replace("camera 1000", "camera 200"));
    let with = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| render(&ir))
    };
    let (one, one_counters) = with(1);
    let (two, two_counters) = with(2);
    assert!(one.rgb == two.rgb, "images differ between 1 and 2 threads");
    assert_eq!(one_counters, two_counters);
}

#[test]
fn every_corpus_scene_renders() {
    let (dir, scenes) = corpus_copy();
    for scene in &scenes {
        let name = scene.file_name().unwrap().to_string_lossy().to_string();
        let out = dir.path().join(format!("{name}.ppm"));
        let output = run(&[
            scene.to_str().unwrap(),
            out.to_str().unwrap(),
            "--threads",
            "2",
        ]);
        assert_eq!(
            output.status.code(),
            Some(0),
            "{name}: {}",
            String::from_utf8_lossy(&output.stderr)
        );
        let bytes = std::fs::read(&out).expect("image written");
        assert!(bytes.starts_with(b"P6"), "{name}: not a binary PPM");
        let image = image::load_from_memory(&bytes).expect("decodes");
        assert_eq!((image.width(), image.height()), (1000, 1000), "{name}");
    }
}

/// The corpus plane whose headup equals its normal renders exactly as it
/// does with the stand-in headup its warning tells the user to write.
#[test]
fn a_parallel_headup_renders_as_its_stand_in() {
    let (dir, _) = corpus_copy();
    let scene = dir.path().join("reflection_91b7c2f_headup010.txt");
    let text = std::fs::read_to_string(&scene).expect("read");
    let fixed = dir.path().join("fixed.txt");
    assert!(text.contains("headup 0 1 0"));
    std::fs::write(&fixed, text.replace("headup 0 1 0", "headup 0 0 1")).expect("write");
    let render = |scene: &Path, name: &str| {
        let out = dir.path().join(name);
        let output = run(&["render", scene.to_str().unwrap(), out.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&output.stderr).to_string();
        assert_eq!(output.status.code(), Some(0), "{stderr}");
        (std::fs::read(&out).expect("image written"), stderr)
    };
    let (original, warned) = render(&scene, "original.ppm");
    let (stand_in, quiet) = render(&fixed, "stand_in.ppm");
    assert!(warned.contains("headup_parallel_to_normal"), "{warned}");
    assert!(warned.contains("`headup 0 0 1`"), "{warned}");
    assert!(!quiet.contains("headup_parallel_to_normal"), "{quiet}");
    assert!(
        original == stand_in,
        "the stand-in headup renders differently"
    );
}

#[test]
fn png_output_decodes_to_the_same_pixels_as_ppm() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = dir.path().join("s.txt");
    std::fs::write(&scene, format!("{SPHERE}{PLANE}{LIGHT}")).expect("write");
    let decoded = |name: &str| {
        let out = dir.path().join(name);
        let output = run(&["render", scene.to_str().unwrap(), out.to_str().unwrap()]);
        assert!(output.status.success());
        image::open(&out).expect("decodes").to_rgb8()
    };
    let (ppm, png) = (decoded("a.ppm"), decoded("a.png"));
    assert_eq!(ppm.dimensions(), (32, 32));
    assert!(ppm == png, "PNG and PPM differ");
}

#[test]
fn refused_outputs_cost_nothing_and_write_nothing() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = dir.path().join("s.txt");
    std::fs::write(&scene, SPHERE).expect("write");
    let s = scene.to_str().unwrap();

    let bmp = dir.path().join("out.bmp");
    let output = run(&["render", s, bmp.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("io::output_format"));
    assert!(!bmp.exists());

    let output = run(&["render", s, s]);
    assert_eq!(output.status.code(), Some(2), "rendering over the scene");
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), SPHERE);

    let output = run(&["render", s, "x.ppm", "--spp", "5"]);
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("expected a square number"), "{stderr}");
    assert!(stderr.contains("try 4 or 9"), "{stderr}");

    let missing = dir.path().join("no/such/folder/out.ppm");
    let output = run(&["render", s, missing.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("cannot write"));

    assert_eq!(listing(dir.path()), ["s.txt"]);
}

#[test]
fn scene_errors_exit_1_and_write_no_image() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = dir.path().join("s.txt");
    std::fs::write(&scene, "camera 16\nsphere dimension -1 center 0 0 -4\n").expect("write");
    let out = dir.path().join("out.ppm");
    let output = run(&[scene.to_str().unwrap(), out.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&output.stderr).contains("scene::dimension_not_positive"));
    assert!(!out.exists());
}

#[test]
fn skipping_work_that_cannot_show_leaves_the_image_unchanged() {
    let (_dir, scenes) = corpus_copy();
    let mut skipped_any = false;
    for scene in scenes
        .iter()
        .filter(|s| !s.ends_with("reflection_91b7c2f_headup010.txt"))
    {
        let text = std::fs::read_to_string(scene).expect("read");
        let ir = support::lower_in(&text, scene.parent().expect("folder"), Some(120));
        let with = |skip| {
            let options = raytracer_render::render::Options {
                skip,
                ..Default::default()
            };
            raytracer_render::render::render(Precision::F64, &ir, &options, &|| {})
        };
        let ((skipping, fewer), (full, all)) = (with(true), with(false));
        assert!(
            skipping.rgb == full.rgb,
            "{}: skipping changed the image",
            scene.display()
        );
        assert_eq!(all.shadow_rays_skipped, 0);
        assert_eq!(all.paths_saturated, 0);
        assert!(fewer.shadow_rays + fewer.reflection_rays <= all.shadow_rays + all.reflection_rays);
        skipped_any |= fewer.shadow_rays_skipped > 0 || fewer.paths_saturated > 0;
    }
    assert!(
        skipped_any,
        "no scene skipped anything: the test proves nothing"
    );
}
