//! `raytracer accuracy` end to end: the table has a row per setting, the
//! numbers follow from the scene (an image without edges has no sampling
//! error), assets are written when asked, and bad input gets its exit code.

use std::process::Output;

use crate::support::{run, write};

const BALL: &str = "camera 16\nsphere dimension 1 center 0 0 -4 color .5 .5 .5\n\
                    light location 2 3 0 color 1 1 1\n";
/// The camera inside an ambient-lit sphere: one colour everywhere.
const FLAT: &str = "camera 8\nsphere dimension 50 center 0 0 0 color .5 .3 .2\n";

/// The stdout of a run that must succeed (its stderr shown when not).
fn succeeded(output: &Output) -> String {
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// Assert that `report` contains `part`, showing the report when not.
fn says(report: &str, part: &str) {
    assert!(report.contains(part), "no `{part}` in\n{report}");
}

fn accuracy(scene: &str, extra: &[&str]) -> Output {
    let mut args = vec!["accuracy", scene, "--reps", "1", "--reference-spp", "16"];
    args.extend_from_slice(extra);
    run(&args)
}

#[test]
fn the_report_has_every_setting_and_its_findings() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = write(dir.path(), "ball.txt", BALL);
    let assets = dir.path().join("assets");
    let output = accuracy(&scene, &["--assets", assets.to_str().unwrap()]);
    let stdout = succeeded(&output);
    for row in [
        "| default (f64, 1 spp, depth 8) | 1.00",
        "| f32 |",
        "| --no-skip |",
        "| depth 0 |",
        "| depth 64 |",
        "| uniform 64 spp |",
        "| adaptive 16 spp |",
    ] {
        says(&stdout, row);
    }
    assert!(
        stdout.contains("at 144×144 (9 × its own 16, the smallest odd multiple"),
        "a 16-px scene is measured at 144 px: {stdout}"
    );
    says(&stdout, "**Sampling**: the RMSE falls as N^-");
    // One repetition is singular, and a share is never shown as `0.0%`.
    says(&stdout, "1 repetition, the settings");
    assert!(!stdout.contains("0.0%"), "{stdout}");
    // stderr is a pipe here, not a terminal: each step still says so, in
    // plain lines.
    let stderr = String::from_utf8_lossy(&output.stderr);
    for step in [
        "ball: reference at depth 8\n",
        "ball: reference at depth 64\n",
        "ball: repetition 1 of 1\n",
    ] {
        says(&stderr, step);
    }
    assert!(!stderr.contains('\r'), "{stderr}");
    says(&stdout, "**Adaptive**");
    let sampling = std::fs::read_to_string(assets.join("ball.sampling.csv")).expect("csv");
    assert!(
        sampling.starts_with("series,spp,rmse\nuniform (slope -"),
        "{sampling}"
    );
    assert!(sampling.contains("\nN^-1/2,64,"), "{sampling}");
    let pareto = std::fs::read_to_string(assets.join("ball.pareto.csv")).expect("csv");
    assert!(pareto.contains("\nadaptive,"), "{pareto}");
    let map = std::fs::read(assets.join("ball.f32_f64.png")).expect("map");
    assert!(map.starts_with(b"\x89PNG"));
    for chart in ["ball.sampling.png", "ball.pareto.png"] {
        let png = std::fs::read(assets.join(chart)).expect(chart);
        let image = image::load_from_memory(&png).expect(chart);
        assert_eq!((image.width(), image.height()), (480, 340), "{chart}");
    }
}

#[test]
fn an_image_without_edges_has_no_sampling_error() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = write(dir.path(), "flat.txt", FLAT);
    let assets = dir.path().join("assets");
    let output = accuracy(
        &scene,
        &["--size", "6", "--assets", assets.to_str().unwrap()],
    );
    let stdout = succeeded(&output);
    says(&stdout, "at 6×6 (`--size`; its own is 8×8)");
    says(&stdout, "the RMSE is 0 at every jittered sample count");
    says(&stdout, "**f32 is enough here**");
    // No pixel has an edge to refine: the findings say none, not 0.0%.
    says(
        &stdout,
        "none of the pixels took all 64 samples and none took 4 samples",
    );
    let row = stdout
        .lines()
        .find(|line| line.starts_with("| adaptive 64 spp |"))
        .expect("the adaptive 64 spp row");
    assert!(
        row.contains("| 49 | 0.000 |"),
        "a flat 6×6 image takes its 7×7 corner samples at any adaptive N: {row}"
    );
    // A log axis cannot show RMSE 0: no empty chart is drawn.
    assert!(assets.join("flat.sampling.csv").exists());
    assert!(!assets.join("flat.sampling.png").exists());
}

/// Two wide mirrors facing each other, the eye between them, and a ball:
/// paths reflect past depth 8.
const MIRRORS: &str = "camera 16\n\
    plane dimension 400 400 center 0 0 -6 normal 0 0 1 headup 0 1 0 reflectivity .9 color .2 .2 .2\n\
    plane dimension 400 400 center 0 0 2 normal 0 0 -1 headup 0 1 0 reflectivity .9 color .2 .2 .2\n\
    sphere dimension .5 center 1.5 1 -4 color 1 .5 .2\n\
    light location 2 3 0 color 1 1 1\n";

#[test]
fn the_sampling_fit_and_the_references_are_stated() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = write(dir.path(), "mirrors.txt", MIRRORS);
    let output = accuracy(&scene, &["--size", "16"]);
    let stdout = succeeded(&output);
    // The fit leaves out 1 spp, the pixel centre, and says so.
    says(
        &stdout,
        "(least squares over 4–64 spp, jittered counts only)",
    );
    // Depth truncation is its own source, against the depth-64 reference.
    says(&stdout, "at depth 8 (");
    says(&stdout, "**Depth truncation**, a source of its own: the depth-8 reference against the depth-64 one differs by RMSE ");
    // The default renders at depth 8, as its reference does: its error is
    // sampling alone, and depth 8's truncation shows only in the split.
    let truncation: f64 = stdout
        .split("the depth-8 reference against the depth-64 one differs by RMSE ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|n| n.parse().ok())
        .expect("the truncation RMSE");
    assert!(
        truncation > 0.0,
        "the mirrors reflect past depth 8: {stdout}"
    );
}

#[test]
fn the_tuning_set_chooses_and_the_held_out_scenes_are_judged_apart() {
    let dir = tempfile::tempdir().expect("temp dir");
    let ball = write(dir.path(), "ball.txt", BALL);
    let flat = write(dir.path(), "flat.txt", FLAT);
    let held = write(dir.path(), "held/ball.txt", BALL);
    let assets = dir.path().join("assets");
    let output = run(&[
        "accuracy",
        &ball,
        &flat,
        "--held-out",
        &held,
        "--aa-threshold",
        "0.5,2",
        "--reps",
        "3",
        "--reference-spp",
        "16",
        "--size",
        "12",
        "--assets",
        assets.to_str().unwrap(),
    ]);
    let stdout = succeeded(&output);
    says(&stdout, "## Choosing the threshold on the tuning set");
    says(&stdout, &format!("The tuning set: `{ball}`, `{flat}`."));
    let picked: f64 = stdout
        .split("It picks **")
        .nth(1)
        .and_then(|rest| rest.split("**").next())
        .and_then(|n| n.parse().ok())
        .expect("the picked threshold");
    assert!([0.5, 2.0].contains(&picked), "{picked}");
    // Both candidates in the tuning table; the tuning scenes measured at
    // both, the held-out one at the pick only.
    says(&stdout, "| 0.5 | ");
    says(&stdout, "| 2 | ");
    let held_out = stdout
        .split("the held-out scenes\n")
        .nth(1)
        .expect("a held-out section");
    says(
        held_out,
        &format!("measured after it at the chosen threshold only: `{held}`."),
    );
    for spp in [4, 16, 64] {
        let row = format!("| `{held}` | {spp} | ");
        says(held_out, &row);
    }
    says(
        &stdout,
        "Meet the target (RMSE ≤ 1.25× uniform's in ≤ 0.5× its time",
    );
    let sections: Vec<&str> = stdout.split("\n### `").skip(1).collect();
    assert_eq!(sections.len(), 3, "{stdout}");
    says(sections[0], "| adaptive 16 spp, threshold 0.5 |");
    says(sections[0], "| adaptive 16 spp, threshold 2 |");
    says(sections[2], "| adaptive 16 spp |");
    assert!(!sections[2].contains("threshold 2 |") || picked == 2.0);
    // Two scenes named ball: their assets are told apart by folder.
    assert!(assets.join("held-ball.sampling.csv").exists());
    assert!(assets
        .join(format!(
            "{}-ball.sampling.csv",
            dir.path().file_name().unwrap().to_string_lossy()
        ))
        .exists());
    says(&stdout, "](assets/held-ball.f32_f64.png)");
}

#[test]
fn bad_input_gets_its_exit_code() {
    let dir = tempfile::tempdir().expect("temp dir");
    let broken = write(dir.path(), "broken.txt", "camera 8\nsphere dimension -1\n");
    assert_eq!(accuracy(&broken, &[]).status.code(), Some(1));
    let scene = write(dir.path(), "flat.txt", FLAT);
    let output = run(&["accuracy", &scene, "--reference-spp", "10"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("try 9 or 16"));
    let missing = dir.path().join("missing.txt");
    assert_eq!(
        accuracy(missing.to_str().unwrap(), &[]).status.code(),
        Some(2)
    );
}
