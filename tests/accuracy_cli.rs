//! `raytracer accuracy` end to end: the table has a row per setting, the
//! numbers follow from the scene (an image without edges has no sampling
//! error), assets are written when asked, and bad input gets its exit code.

use crate::support::{run, write};

const BALL: &str = "camera 16\nsphere dimension 1 center 0 0 -4 color .5 .5 .5\n\
                    light location 2 3 0 color 1 1 1\n";
/// The camera inside an ambient-lit sphere: one colour everywhere.
const FLAT: &str = "camera 8\nsphere dimension 50 center 0 0 0 color .5 .3 .2\n";

fn accuracy(scene: &str, extra: &[&str]) -> std::process::Output {
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
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    for row in [
        "| default (f64, 1 spp, depth 8) | 1.00",
        "| f32 |",
        "| --no-skip |",
        "| depth 0 |",
        "| depth 64 |",
        "| uniform 64 spp |",
        "| adaptive 16 spp |",
    ] {
        assert!(stdout.contains(row), "no `{row}` in\n{stdout}");
    }
    assert!(
        stdout.contains("at 144×144 (9 × its own 16, the smallest odd multiple"),
        "a 16-px scene is measured at 144 px: {stdout}"
    );
    assert!(
        stdout.contains("**Sampling**: the RMSE falls as N^-"),
        "{stdout}"
    );
    assert!(stdout.contains("**Adaptive**"), "{stdout}");
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
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success());
    assert!(
        stdout.contains("at 6×6 (`--size`; its own is 8×8)"),
        "{stdout}"
    );
    assert!(
        stdout.contains("the RMSE is 0 at every sample count"),
        "{stdout}"
    );
    assert!(stdout.contains("**f32 is enough here**"), "{stdout}");
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
