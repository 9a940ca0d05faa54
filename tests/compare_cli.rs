//! `raytracer compare` on images made here: the same picture in several
//! encodings, one shifted, one darker, another size, a truncated file and
//! a file that is no image; the verdicts, metrics, heat map and exit codes.

use std::path::{Path, PathBuf};

use image::{ImageFormat, RgbImage};
use serde_json::Value;

use crate::support::run;

/// A lit disc on black, 64 × 64 (or `size`), moved right by `shift`
/// pixels, its colours times `gain`.
fn disc(size: u32, shift: i32, gain: f64) -> RgbImage {
    RgbImage::from_fn(size, size, |x, y| {
        let (dx, dy) = (x as f64 - 32.0 - f64::from(shift), y as f64 - 32.0);
        if dx * dx + dy * dy < 16.0 * 16.0 {
            let v = |c: f64| (c * gain).round() as u8;
            image::Rgb([v(200.0 + dx * 3.0), v(120.0 + dy * 3.0), v(90.0)])
        } else {
            image::Rgb([0, 0, 0])
        }
    })
}

fn save(image: &RgbImage, path: &Path, format: ImageFormat) -> String {
    image.save_with_format(path, format).expect("save image");
    path.display().to_string()
}

/// `image` saved as PNG to `dir/name`.
fn png(dir: &Path, name: &str, image: &RgbImage) -> String {
    save(image, &dir.join(name), ImageFormat::Png)
}

/// A P3 file with maxval 65535 of `image`.
fn p3_16bit(image: &RgbImage, path: &Path) -> String {
    let mut text = format!("P3\n{} {}\n65535\n", image.width(), image.height());
    for p in image.pixels() {
        for c in p.0 {
            text.push_str(&format!("{} ", u32::from(c) * 257));
        }
        text.push('\n');
    }
    std::fs::write(path, text).unwrap();
    path.display().to_string()
}

fn json(args: &[&str]) -> (i32, Value) {
    let mut all = vec!["compare", "--format", "json"];
    all.extend_from_slice(args);
    let output = run(&all);
    let code = output.status.code().unwrap();
    let value = serde_json::from_slice(&output.stdout).unwrap_or(Value::Null);
    (code, value)
}

#[test]
fn the_same_picture_in_three_encodings_matches_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let image = disc(64, 0, 1.0);
    // Named .png but P6 inside: read by content.
    let p6 = save(&image, &dir.path().join("p6.png"), ImageFormat::Pnm);
    let png = save(&image, &dir.path().join("ref.ppm"), ImageFormat::Png);
    let p3 = p3_16bit(&image, &dir.path().join("wide.ppm"));
    for candidate in [&p6, &p3] {
        let (code, value) = json(&[&png, candidate]);
        assert_eq!(code, 0, "{value}");
        assert_eq!(value["verdict"], "match");
        assert_eq!(value["metrics"]["flip"]["max"], 0.0);
        assert_eq!(value["metrics"]["rmse"], 0.0);
        assert_eq!(value["metrics"]["psnr"], Value::Null);
        assert_eq!(value["metrics"]["coverage_iou"], 1.0);
    }
    let (_, value) = json(&[&png, &p6]);
    assert_eq!(value["reference"]["format"], "png");
    assert_eq!(value["candidate"]["format"], "ppm");
    let human = run(&["compare", &png, &p3]);
    let text = String::from_utf8(human.stdout).unwrap();
    assert!(text.starts_with("verdict: match\n"), "{text}");
}

#[test]
fn a_shift_is_a_coverage_difference_and_a_darker_image_an_appearance_one() {
    let dir = tempfile::tempdir().unwrap();
    let reference = png(dir.path(), "r.png", &disc(64, 0, 1.0));
    let shifted = png(dir.path(), "s.png", &disc(64, 4, 1.0));
    let darker = png(dir.path(), "d.png", &disc(64, 0, 0.5));

    let (code, value) = json(&[&reference, &shifted]);
    assert_eq!(code, 1);
    assert_eq!(value["verdict"], "coverage");
    let iou = value["metrics"]["coverage_iou"].as_f64().unwrap();
    assert!(iou > 0.6 && iou < 0.9, "{iou}");

    let (code, value) = json(&[&reference, &darker]);
    assert_eq!(code, 1);
    assert_eq!(value["verdict"], "appearance");
    assert_eq!(value["metrics"]["coverage_iou"], 1.0);
    let flip = value["metrics"]["flip"]["mean"].as_f64().unwrap();
    assert!(flip > 0.05, "{flip}");
    let psnr = value["metrics"]["psnr"].as_f64().unwrap();
    assert!(psnr > 5.0 && psnr < 40.0, "{psnr}");

    // The thresholds are options: a looser bound on ꟻLIP lets it match.
    let (code, value) = json(&["--max-flip", "0.9", &reference, &darker]);
    assert_eq!((code, &value["verdict"]), (0, &Value::from("match")));
    let (code, _) = json(&["--min-coverage", "0.5", &reference, &shifted]);
    assert_eq!(code, 1, "the shift still fails on ꟻLIP");
}

#[test]
fn the_heat_map_is_the_inputs_size_and_black_where_they_agree() {
    let dir = tempfile::tempdir().unwrap();
    let reference = png(dir.path(), "r.png", &disc(64, 0, 1.0));
    let shifted = png(dir.path(), "s.png", &disc(64, 4, 1.0));
    let heat = dir.path().join("heat.png");
    let (code, value) = json(&["--heatmap", heat.to_str().unwrap(), &reference, &shifted]);
    assert_eq!(code, 1);
    assert_eq!(value["heatmap"], heat.to_str().unwrap());
    let map = image::open(&heat).unwrap().into_rgb8();
    assert_eq!(map.dimensions(), (64, 64));
    // A corner far from both discs has no error: magma's first colour.
    let corner = map.get_pixel(0, 0).0;
    assert!(corner.iter().all(|&c| c < 8), "{corner:?}");
    // The disc's leading edge differs: a bright colour.
    let edge = map.get_pixel(32 + 17, 32).0;
    assert!(
        edge.iter().map(|&c| u32::from(c)).sum::<u32>() > 200,
        "{edge:?}"
    );
}

#[test]
fn another_size_is_a_verdict_not_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let reference = png(dir.path(), "r.png", &disc(64, 0, 1.0));
    let small = save(
        &disc(48, 0, 1.0),
        &dir.path().join("small.ppm"),
        ImageFormat::Pnm,
    );
    let heat = dir.path().join("heat.png");
    let (code, value) = json(&["--heatmap", heat.to_str().unwrap(), &reference, &small]);
    assert_eq!(code, 1);
    assert_eq!(value["verdict"], "size");
    assert_eq!(value["metrics"], Value::Null);
    assert_eq!(value["candidate"]["width"], 48);
    assert!(!heat.exists());
    let text = String::from_utf8(run(&["compare", &reference, &small]).stdout).unwrap();
    assert!(
        text.contains("expected 64 × 64 (reference), found 48 × 48"),
        "{text}"
    );
}

#[test]
fn unreadable_files_exit_2_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let reference = png(dir.path(), "r.png", &disc(64, 0, 1.0));
    let full = std::fs::read(save(
        &disc(64, 0, 1.0),
        &dir.path().join("full.ppm"),
        ImageFormat::Pnm,
    ))
    .unwrap();
    let truncated = dir.path().join("cut.ppm");
    std::fs::write(&truncated, &full[..full.len() / 2]).unwrap();
    let text = dir.path().join("notes.png");
    std::fs::write(&text, "these are not pixels\n").unwrap();
    let missing = dir.path().join("missing.ppm");
    for (path, says) in [
        (&truncated, "ends before its last texel"),
        (&text, "does not decode as an image"),
        (&missing, "cannot read"),
    ] {
        let output = run(&["compare", &reference, path.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains(says), "{stderr}");
        assert!(output.stdout.is_empty());
        // The reason once, not again as a cause; the formats only for a
        // file that is there and does not decode.
        assert_eq!(stderr.matches(says).count(), 1, "{stderr}");
        assert_eq!(stderr.contains("reads PPM"), path != &missing, "{stderr}");
    }
    let bad_threshold = run(&["compare", "--max-flip", "2", &reference, &reference]);
    assert_eq!(bad_threshold.status.code(), Some(2));
}

#[test]
fn compare_reads_every_image_render_writes_and_no_larger() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("big.txt");
    std::fs::write(
        &scene,
        "camera 4097\nsphere\ncenter 0 0 -5\ndimension 1\nlight\nlocation 0 5 0\ncolor 1 1 1\n",
    )
    .unwrap();
    let image = dir.path().join("big.png");
    let rendered = run(&["render", scene.to_str().unwrap(), image.to_str().unwrap()]);
    assert!(rendered.status.success(), "{rendered:?}");
    let image = image.to_str().unwrap();
    let (code, value) = json(&[image, image]);
    assert_eq!(
        (code, &value["verdict"]),
        (0, &Value::from("match")),
        "{value}"
    );
    assert_eq!(value["candidate"]["width"], 4097);

    let wide = dir.path().join("wide.ppm");
    std::fs::write(&wide, "P6\n16385 1\n255\n").unwrap();
    let output = run(&["compare", image, wide.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.matches("16385 × 1").count(), 1, "{stderr}");
    assert!(!stderr.contains("texture"), "{stderr}");
    assert!(stderr.contains("up to 16384 × 16384 pixels"), "{stderr}");
}

/// A ball over a floor, lit from above and to the right, 48 × 48.
const BALL_ON_A_FLOOR: &str = "camera 48\nsphere\ndimension 1\ncenter 0 .3 -5\ncolor .9 .6 .3\n\
     plane\ndimension 8 8\ncenter 0 -1 -6\nnormal 0 1 0\nheadup 0 0 -1\ncolor .8 .8 .8\n\
     light\nlocation 3 4 -3\ncolor 1 1 1\n";

/// Scene `text` written to `dir` as ball.txt, and our render of it
/// (ours.png): the scene's path, the image's, and the image.
fn ours_of(dir: &Path, text: &str) -> (PathBuf, PathBuf, RgbImage) {
    let scene = dir.join("ball.txt");
    std::fs::write(&scene, text).unwrap();
    let ours = dir.join("ours.png");
    let out = run(&["render", scene.to_str().unwrap(), ours.to_str().unwrap()]);
    assert!(out.status.success(), "{out:?}");
    let image = image::open(&ours).unwrap().to_rgb8();
    (scene, ours, image)
}

/// `compare --scene` gives grade's verdict, aspect by aspect; without a
/// scene, compare judges pixels and says so. A right image on a
/// background of its own (6, 6, 6) is no coverage difference either way,
/// and an image upside down fails geometry alone, named.
#[test]
fn with_a_scene_compare_is_grades_judge_and_without_it_says_it_judges_pixels() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (scene, ours, image) = ours_of(d, BALL_ON_A_FLOOR);
    let grey = RgbImage::from_fn(48, 48, |x, y| {
        let p = *image.get_pixel(x, y);
        if p.0 == [0, 0, 0] {
            image::Rgb([6, 6, 6])
        } else {
            p
        }
    });
    let grey = png(d, "grey.png", &grey);
    let flipped = png(d, "flipped.png", &image::imageops::flip_vertical(&image));
    let (ours, scene) = (ours.to_str().unwrap(), scene.to_str().unwrap());

    let human = run(&["compare", ours, &grey]);
    let text = String::from_utf8(human.stdout).unwrap();
    assert!(text.contains("judged pixel by pixel"), "{text}");
    assert!(!text.contains("geometry"), "{text}");
    let (_, value) = json(&[ours, &grey]);
    assert_eq!(value["metrics"]["coverage_iou"], 1.0, "{value}");
    assert_eq!(value["judged_by"], "pixels");

    let (code, value) = json(&["--scene", scene, ours, &grey]);
    assert_eq!(code, 0, "{value}");
    assert_eq!(value["judged_by"], "aspects");
    assert!(value["aspects"]
        .as_array()
        .unwrap()
        .iter()
        .all(|a| a["pass"] == true));

    let (code, value) = json(&["--scene", scene, ours, &flipped]);
    assert_eq!(code, 1, "{value}");
    let failed: Vec<&Value> = value["aspects"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|a| a["pass"] == false)
        .map(|a| &a["aspect"])
        .collect();
    assert_eq!(failed, ["geometry"], "{value}");
    assert!(value["transform"].as_str().unwrap().contains("upside down"));
    let human = run(&["compare", "--scene", scene, ours, &flipped]);
    let text = String::from_utf8(human.stdout).unwrap();
    assert!(text.starts_with("verdict: differs: geometry"), "{text}");
}

/// Several candidates in one run are each judged as alone: JSON gives an
/// array of the reports one candidate at a time gives, in order, people
/// get each block headed by its file, and the exit code is 1 when any
/// differs. A heat map is one candidate's, so `--heatmap` with two is
/// refused (exit 2) and writes nothing.
#[test]
fn a_whole_class_of_candidates_is_judged_in_one_run_each_as_alone() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (scene, ours, image) = ours_of(d, BALL_ON_A_FLOOR);
    let same = png(d, "same.png", &image);
    let flipped = png(d, "flipped.png", &image::imageops::flip_vertical(&image));
    let (ours, scene) = (ours.to_str().unwrap(), scene.to_str().unwrap());

    let (code, value) = json(&["--scene", scene, ours, &same, &flipped]);
    assert_eq!(code, 1, "{value}");
    let reports = value.as_array().expect("an array of reports");
    for (report, alone) in reports.iter().zip([&same, &flipped]) {
        let (_, one) = json(&["--scene", scene, ours, alone]);
        assert_eq!(report, &one);
    }
    assert_eq!(reports.len(), 2);
    assert_eq!(reports[0]["candidate"]["path"], same.as_str());
    assert!(reports[1]["aspects"]
        .as_array()
        .unwrap()
        .iter()
        .any(|a| a["pass"] == false));
    let (code, _) = json(&["--scene", scene, ours, &same, &same]);
    assert_eq!(code, 0);

    let human = run(&["compare", "--scene", scene, ours, &same, &flipped]);
    let text = String::from_utf8(human.stdout).unwrap();
    assert!(
        text.starts_with(&format!("candidate: {same}\nverdict: match")),
        "{text}"
    );
    assert!(
        text.contains(&format!(
            "\ncandidate: {flipped}\nverdict: differs: geometry"
        )),
        "{text}"
    );

    let map = d.join("map.png");
    let out = run(&[
        "compare",
        "--heatmap",
        map.to_str().unwrap(),
        ours,
        &same,
        &flipped,
    ]);
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("found 2 candidates"), "{stderr}");
    assert!(out.stdout.is_empty() && !map.exists());
}

/// The assignment names no background, so a sky that changes with the
/// ray's direction is one (white at the horizon to blue overhead, as
/// many students' first tracer draws it), and so is a gradient by the
/// angle from the view's axis (a smooth step from bluish grey ahead to
/// dark blue in the corners): `compare --scene` passes our image with its
/// empty pixels turned to either, and fails geometry on it with the ball
/// left out, the background drawn where the ball was.
#[test]
fn a_background_graded_by_the_rays_direction_is_one_and_a_missing_ball_still_differs() {
    // Each background by the ray's direction `(u, v, −1)` through a pixel.
    type Background = fn(f64, f64) -> [f64; 3];
    fn sky(u: f64, v: f64) -> [f64; 3] {
        let t = 0.5 * (v / (u * u + v * v + 1.0).sqrt() + 1.0);
        [1.0 - 0.5 * t, 1.0 - 0.3 * t, 1.0]
    }
    fn radial(u: f64, v: f64) -> [f64; 3] {
        let corner = 1.0 / 1.5f64.sqrt();
        let f = ((1.0 - 1.0 / (u * u + v * v + 1.0).sqrt()) / (1.0 - corner)).clamp(0.0, 1.0);
        let f = f * f * (3.0 - 2.0 * f);
        let (ahead, aside) = ([0.25, 0.3, 0.4], [0.05, 0.05, 0.1]);
        [0, 1, 2].map(|c| ahead[c] * (1.0 - f) + aside[c] * f)
    }
    let backgrounds: [(&str, Background); 2] = [("sky", sky), ("radial", radial)];
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (scene, ours, image) = ours_of(
        d,
        "camera 64\nsphere\ndimension .8\ncenter .4 .1 -5\ncolor .9 .6 .3\n\
         plane\ndimension 3 3\ncenter -.5 -1 -6\nnormal 0 1 0\nheadup 0 0 -1\ncolor .8 .8 .8\n\
         light\nlocation 3 4 -3\ncolor 1 1 1\n",
    );
    let (ours, scene) = (ours.to_str().unwrap(), scene.to_str().unwrap());
    for (name, background) in backgrounds {
        let at = |x: u32, y: u32| {
            let (u, v) = (
                (f64::from(x) + 0.5) / 64.0 - 0.5,
                0.5 - (f64::from(y) + 0.5) / 64.0,
            );
            image::Rgb(background(u, v).map(|c| (c * 255.0).round() as u8))
        };
        let under = |ball: bool| {
            RgbImage::from_fn(64, 64, |x, y| {
                let p = *image.get_pixel(x, y);
                let orange = p.0[0] > p.0[2] + 20;
                if p.0 == [0, 0, 0] || (!ball && orange) {
                    at(x, y)
                } else {
                    p
                }
            })
        };
        let with_ball = png(d, &format!("{name}.png"), &under(true));
        let without = png(d, &format!("{name}_no_ball.png"), &under(false));

        let (code, value) = json(&["--scene", scene, ours, &with_ball]);
        assert_eq!(code, 0, "{name}: {value}");
        let (code, value) = json(&["--scene", scene, ours, &without]);
        assert_eq!(code, 1, "{name}: {value}");
        let geometry = value["aspects"]
            .as_array()
            .unwrap()
            .iter()
            .find(|a| a["aspect"] == "geometry")
            .unwrap();
        assert_eq!(geometry["pass"], false, "{name}: {value}");
    }
}
