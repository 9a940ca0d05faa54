//! The check pass on whole scenes: every problem in one run, the model it
//! builds, and the rules whose edges the UI fixtures do not pin down.

use std::path::Path;

use raytracer_scene::ast::File;
use raytracer_scene::check::{CheckError, SceneCheck, Valid};
use raytracer_scene::diagnostic::SourceFile;
use raytracer_scene::model::Shape;
use raytracer_scene::syntax::parse;
use raytracer_scene::texture::Decoder;

/// The check pass over every section of a parsed file.
fn check_file(file: &File, source: &SourceFile) -> (Option<Valid>, Vec<CheckError>) {
    let mut decoder = Decoder::default();
    let mut check = SceneCheck::new(source, &mut decoder);
    for section in &file.sections {
        check.section(section);
    }
    check.finish()
}

/// Parse and check `text` as if it were a file in `dir`.
fn check_in(dir: &Path, text: &str) -> (Option<Valid>, Vec<String>) {
    let (source, _) = SourceFile::from_bytes("scene.txt", dir, text.as_bytes());
    let parsed = parse(&source.text);
    assert!(parsed.errors.is_empty(), "{:?}", parsed.errors);
    let (checked, problems) = check_file(&parsed.file, &source);
    let codes = problems
        .iter()
        .map(|p| miette::Diagnostic::code(p).unwrap().to_string())
        .filter(|code| !PICTURE.contains(&code.as_str()))
        .collect();
    (checked, codes)
}

/// The warnings about the picture as a whole, which most scenes here (an
/// object or two, no light, to test one rule) carry; they are left out of
/// the codes the other tests compare, and tested on their own by
/// [`scenes_that_render_black_warn`].
const PICTURE: [&str; 2] = ["scene::no_light", "scene::nothing_in_view"];

/// Every code `text` gives, the picture warnings too.
fn all_codes(text: &str) -> Vec<String> {
    let (source, _) = SourceFile::from_bytes("scene.txt", Path::new("."), text.as_bytes());
    let parsed = parse(&source.text);
    let (_, problems) = check_file(&parsed.file, &source);
    problems
        .iter()
        .map(|p| miette::Diagnostic::code(p).unwrap().to_string())
        .collect()
}

#[test]
fn scenes_that_render_black_warn() {
    let light = "light location 0 5 0 color 1 1 1\n";
    // The camera alone: nothing to see, nothing to light it.
    assert_eq!(
        all_codes("camera 100\n"),
        ["scene::no_light", "scene::nothing_in_view"]
    );
    // No light: the ambient tenth of each colour.
    assert_eq!(
        all_codes("camera 4\nsphere dimension 1 center 0 0 -5\n"),
        ["scene::no_light"]
    );
    // Every object out of view: beside, above, beyond the pyramid's sides.
    for center in ["10 0 -5", "0 10 -5", "-10 0 -5", "0 -4 -5"] {
        let text = format!("camera 4\nsphere dimension 1 center {center}\n{light}");
        assert_eq!(all_codes(&text), ["scene::nothing_in_view"], "{center}");
    }
    // At the edge of the view, or partly in it: seen, so no warning.
    for center in ["2.5 0 -5", "0 3 -5", "3 3 -5"] {
        let text = format!("camera 4\nsphere dimension 1 center {center}\n{light}");
        assert_eq!(all_codes(&text), Vec::<String>::new(), "{center}");
    }
    // A plane seen edge-on from the side, and one wholly to the left.
    let plane = |center: &str| {
        format!("camera 4\nplane dimension 2 2 center {center} normal 0 0 1 headup 0 1 0\n{light}")
    };
    assert_eq!(all_codes(&plane("0 0 -5")), Vec::<String>::new());
    assert_eq!(all_codes(&plane("-10 0 -5")), ["scene::nothing_in_view"]);
    // Wholly behind the camera: that warning, and no second one.
    assert_eq!(
        all_codes(&format!(
            "camera 4\nsphere dimension 1 center 0 0 5\n{light}"
        )),
        ["scene::object_behind_camera"]
    );
    // Another error first: the picture is not yet the scene's.
    assert_eq!(
        all_codes("camera 4\nsphere dimension 0 center 0 0 -5\n"),
        ["scene::dimension_not_positive"]
    );
}

fn check(text: &str) -> (Option<Valid>, Vec<String>) {
    check_in(Path::new("."), text)
}

fn codes(text: &str) -> Vec<String> {
    check(text).1
}

#[test]
fn five_mistakes_give_five_diagnostics_in_one_run() {
    let text = "camera 400
sphere
  dimension 0
  centre 0 0 -5
  color 1 1
plane
  dimension 4 4
  center 0 -1 -5
  normal 0 1 0
  reflectivity 2
light
  location 0 5 0
  color 1 1 1
";
    let (checked, mut codes) = check(text);
    codes.sort();
    assert_eq!(
        codes,
        [
            "scene::dimension_not_positive",
            "scene::missing_attribute",
            "scene::reflectivity_out_of_range",
            "scene::unknown_attribute",
            "scene::wrong_value_count",
        ]
    );
    assert!(checked.is_none());
}

#[test]
fn builds_the_model_with_defaults_and_values_as_written() {
    let text = "light color 1 1 1 location 0 5 0
plane
  dimension 4 2
  center 0 -1 -5
  normal 0 2 0      # not unit: kept as written
  headup 0 0 -1
  reflectivity .25
sphere dimension 1.5 center 0 0 -5
camera 64";
    let (checked, codes) = check(text);
    assert_eq!(codes, Vec::<String>::new());
    let scene = checked.expect("a scene").scene;
    assert_eq!(scene.camera.resolution, 64);
    assert_eq!(scene.objects.len(), 2);
    assert_eq!(
        scene.objects[0].shape,
        Shape::Plane {
            center: [0.0, -1.0, -5.0],
            width: 4.0,
            height: 2.0,
            normal: [0.0, 2.0, 0.0],
            headup: [0.0, 0.0, -1.0],
        }
    );
    assert_eq!(scene.objects[0].material.reflectivity, 0.25);
    assert_eq!(
        scene.objects[1].shape,
        Shape::Sphere {
            center: [0.0, 0.0, -5.0],
            radius: 1.5
        }
    );
    assert_eq!(scene.objects[1].material, Default::default());
    assert_eq!(scene.lights[0].location, [0.0, 5.0, 0.0]);
}

#[test]
fn empty_file_needs_only_a_camera() {
    assert_eq!(codes(""), ["scene::missing_camera"]);
    assert_eq!(codes("camera 1"), Vec::<String>::new());
    assert_eq!(codes("camera 16384"), Vec::<String>::new());
    assert_eq!(codes("camera 1e3"), Vec::<String>::new());
    assert_eq!(codes("camera"), ["scene::wrong_value_count"]);
    assert_eq!(codes("camera 4 4"), ["scene::wrong_value_count"]);
    assert_eq!(codes("camera -3"), ["scene::resolution_out_of_range"]);
    assert_eq!(codes("camera 0.5"), ["scene::resolution_not_integer"]);
    assert_eq!(
        codes("camera 4 dimension 1"),
        ["scene::misplaced_attribute"]
    );
}

#[test]
fn range_edges_are_inclusive_where_the_spec_says_so() {
    let sphere = |attrs: &str| {
        codes(&format!(
            "camera 4 sphere dimension 1 center 0 0 -5 {attrs}"
        ))
    };
    assert_eq!(sphere("color 0 1 0.5 reflectivity 0"), Vec::<String>::new());
    assert_eq!(sphere("reflectivity 1"), Vec::<String>::new());
    assert_eq!(
        sphere("reflectivity -0.01"),
        ["scene::reflectivity_out_of_range"]
    );
    assert_eq!(sphere("color 1.01 0 0"), ["scene::color_out_of_range"]);
    assert_eq!(sphere("color -1 0 0"), ["scene::color_out_of_range"]);
    let light = |color: &str| codes(&format!("camera 4 light location 0 5 0 color {color}"));
    assert_eq!(light("0 0 0"), Vec::<String>::new());
    assert_eq!(light("1 1 1"), Vec::<String>::new());
    assert_eq!(light("1.5 0 0"), ["scene::light_color_above_one"]);
    assert_eq!(light("-1 -2 0"), ["scene::negative_light_color"]);
}

#[test]
fn misplaced_and_unknown_attributes_name_the_right_section() {
    let problems = |text: &str| {
        let (source, _) = SourceFile::from_bytes("s", Path::new("."), text.as_bytes());
        check_file(&parse(text).file, &source).1
    };
    let p = problems("camera 4 sphere dimension 1 center 0 0 -5 headup 0 1 0");
    assert!(
        matches!(&p[0], CheckError::MisplacedAttribute { name, section, .. } if name == "headup" && section == "sphere"),
        "{p:?}"
    );
    let p = problems("camera 4 light location 0 0 0 color 1 1 1 locaton 1 1 1");
    assert!(
        matches!(&p[0], CheckError::UnknownAttribute { help, .. } if help == "did you mean `location`?"),
        "{p:?}"
    );
    let p = problems("camera 4\n  dimension 1\nsphere dimension 1 center 0 0 -5");
    assert!(
        matches!(&p[0], CheckError::MisplacedAttribute { help, .. } if help.ends_with("is a `sphere` or `plane` line missing?")),
        "{p:?}"
    );
    // `reflectvity` is nearest `reflectivity`, which lights do not take.
    let p = problems("camera 4 light location 0 0 0 color 1 1 1 reflectvity 1");
    assert!(
        matches!(&p[0], CheckError::UnknownAttribute { help, .. } if help.starts_with("`reflectivity` is an attribute of `sphere` or `plane`")),
        "{p:?}"
    );
}

#[test]
fn duplicates_are_reported_once_and_missing_ones_are_listed_together() {
    assert_eq!(
        codes("camera 4 sphere dimension 1 dimension 2 center 0 0 -5"),
        ["scene::duplicate_attribute"]
    );
    assert_eq!(codes("camera 4 plane"), ["scene::missing_attribute"]);
    assert_eq!(codes("camera 4 light"), ["scene::missing_attribute"]);
}

#[test]
fn headup_thresholds() {
    let plane = |headup: &str| {
        codes(&format!(
            "camera 4 plane dimension 1 1 center 0 0 -5 normal 0 0 1 headup {headup}"
        ))
    };
    assert_eq!(plane("0 1 0"), Vec::<String>::new());
    assert_eq!(plane("0 1 1e-7"), Vec::<String>::new());
    assert_eq!(plane("0 1 1e-5"), ["scene::headup_not_perpendicular"]);
    assert_eq!(plane("0 1e-8 1"), ["scene::headup_not_perpendicular"]);
    assert_eq!(plane("0 1e-10 1"), ["scene::headup_parallel_to_normal"]);
    assert_eq!(plane("0 0 -3"), ["scene::headup_parallel_to_normal"]);
    assert_eq!(plane("0 0 0"), ["scene::zero_headup"]);
}

#[test]
fn behind_the_camera_means_every_point_at_z_at_least_0() {
    let sphere = |center: &str| codes(&format!("camera 4 sphere dimension 1 center {center}"));
    assert_eq!(sphere("0 0 0.999"), Vec::<String>::new());
    assert_eq!(sphere("0 0 1"), ["scene::object_behind_camera"]);
    assert_eq!(sphere("0 0 -5"), Vec::<String>::new());
    let plane = |center: &str, normal: &str| {
        codes(&format!(
            "camera 4 plane dimension 2 2 center {center} normal {normal} headup 0 1 0"
        ))
    };
    // Facing the camera at z = 0: every point has z = 0.
    assert_eq!(plane("0 0 0", "0 0 1"), ["scene::object_behind_camera"]);
    // Tilted about x: corners at z = 1 ± 1·sin 45°, all positive.
    assert_eq!(
        plane("0 0 1", "0 1 1"),
        [
            "scene::object_behind_camera",
            "scene::headup_not_perpendicular"
        ]
        .iter()
        .rev()
        .map(|s| s.to_string())
        .collect::<Vec<_>>()
    );
    // A floor reaching from behind the camera to in front of it.
    assert_eq!(
        plane("0 -1 0", "0 1 0"),
        ["scene::headup_parallel_to_normal"]
    );
    assert_eq!(
        codes("camera 4 plane dimension 2 4 center 0 -1 0 normal 0 1 0 headup 0 0 -1"),
        Vec::<String>::new()
    );
}

#[test]
fn light_inside_a_sphere_is_strictly_inside() {
    let scene = |location: &str| {
        codes(&format!(
            "camera 4 sphere dimension 1 center 0 0 -5 light location {location} color 1 1 1"
        ))
    };
    assert_eq!(scene("0 0 -5"), ["scene::light_inside_sphere"]);
    assert_eq!(scene("0 0.99 -5"), ["scene::light_inside_sphere"]);
    assert_eq!(scene("0 1 -5"), Vec::<String>::new());
    assert_eq!(scene("0 5 -5"), Vec::<String>::new());
}

#[test]
fn textures_load_relative_to_the_scene_folder() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("t.ppm"), "P3 1 1 255 10 20 30").unwrap();
    std::fs::write(dir.path().join("bad.ppm"), "P3 1 1 255 10 20").unwrap();
    let scene = |texture: &str| {
        check_in(
            dir.path(),
            &format!("camera 4 sphere dimension 1 center 0 0 -5 texture {texture}"),
        )
    };
    let (checked, codes) = scene("t.ppm");
    assert_eq!(codes, Vec::<String>::new());
    let checked = checked.unwrap();
    assert_eq!(checked.textures["t.ppm"].width, 1);
    assert_eq!(
        checked.scene.objects[0].material.texture.as_deref(),
        Some("t.ppm")
    );
    assert!(raytracer_render::ir::Effects::of(&checked.scene).textures);
    assert_eq!(scene("\"missing one.ppm\"").1, ["scene::texture_not_found"]);
    assert_eq!(scene("bad.ppm").1, ["scene::texture_not_an_image"]);
    assert_eq!(scene(".").1, ["scene::texture_not_a_file"]);
}

#[test]
fn checking_section_by_section_as_parsed_equals_checking_the_tree() {
    // What the commands do (each section checked as the parser yields it,
    // then dropped) against parsing the whole tree first: the same
    // diagnostics in the same order, and the same scene.
    let texts = [
        "camera 4\nsphere dimension 1 center 0 0 -5 color 0.5 0.5 0.5\nlight location 0 5 0 color 1 1 1",
        "camera 0\nsphere dimension 0\n centre 0 0 -5\nsphere\ncamera 4\nsphre\nlight location 0 0 -5 color 2 0 0\nsphere dimension 1 center 0 0 -5\n1 2 3",
    ];
    for (text, problems) in texts.into_iter().zip([0, 8]) {
        let (source, _) = SourceFile::from_bytes("scene.txt", Path::new("."), text.as_bytes());
        let parsed = parse(text);
        let (tree_scene, tree_problems) = check_file(&parsed.file, &source);
        let mut sections = raytracer_scene::syntax::sections(text);
        let mut decoder = Decoder::default();
        let mut check = SceneCheck::new(&source, &mut decoder);
        for section in sections.by_ref() {
            check.section(&section);
        }
        let syntax_errors = sections.into_errors();
        let (streamed_scene, streamed_problems) = check.finish();
        assert_eq!(
            syntax_errors.len() + tree_problems.len(),
            problems,
            "{text}: {syntax_errors:?} {tree_problems:?}"
        );
        assert_eq!(tree_scene.is_some(), problems == 0);
        assert_eq!(format!("{syntax_errors:?}"), format!("{:?}", parsed.errors));
        assert_eq!(
            format!("{streamed_problems:?}"),
            format!("{tree_problems:?}")
        );
        assert_eq!(
            streamed_scene.map(|c| c.scene),
            tree_scene.map(|c| c.scene),
            "{text}"
        );
    }
}
