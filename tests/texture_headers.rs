//! The analysis reads only the headers of textures: `raytracer check` (and
//! the language server, through the same front-end call) validates a
//! texture's format and size without decoding it, and `render` decodes.
//! Measured as the peak resident memory of the process, by GNU time.

use std::process::Command;

use image::{Rgb, RgbImage};

use crate::support::{bin, write};

/// The most a check of a scene with a 4096 × 4096 texture may take.
const CHECK_PEAK_KB: i64 = 64 * 1024;

/// Run the binary with `args` to completion under GNU time; whether it
/// succeeded and its peak resident memory in KiB. (The resource usage a
/// parent gets for its own child counts the parent's peak too, since the
/// child starts as a copy of it; GNU time's child starts from the small
/// `time` process.) `None` without GNU time, which .ci/run installs.
fn peak_kb(args: &[&str]) -> Option<(bool, i64)> {
    let gnu_time = std::path::Path::new("/usr/bin/time");
    if !gnu_time.exists() {
        assert!(
            !crate::support::under_ci(),
            "/usr/bin/time (GNU time) is missing; .ci/run installs it"
        );
        crate::support::skipped("the peak memory check: /usr/bin/time (GNU time) is missing");
        return None;
    }
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("time");
    let status = Command::new(gnu_time)
        .args(["-f", "%M", "-o"])
        .arg(&report)
        .arg(bin())
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .unwrap();
    let text = std::fs::read_to_string(&report).unwrap();
    let peak = text.lines().last().unwrap().trim().parse().unwrap();
    Some((status.success(), peak))
}

#[test]
fn checking_a_scene_with_a_4096_texture_reads_only_its_header() {
    let dir = tempfile::tempdir().unwrap();
    RgbImage::from_pixel(4096, 4096, Rgb([200, 100, 50]))
        .save(dir.path().join("big.png"))
        .unwrap();
    let scene = write(
        dir.path(),
        "scene.txt",
        "camera 4\nsphere\n  dimension 1\n  center 0 0 -5\n  texture big.png\nlight\n  location 0 5 0\n  color 1 1 1\n",
    );
    let Some((checked, check_peak)) = peak_kb(&["check", &scene]) else {
        return;
    };
    assert!(checked, "check failed");
    assert!(
        check_peak < CHECK_PEAK_KB,
        "check peaked at {check_peak} KiB, expected under {CHECK_PEAK_KB}"
    );
    // The measurement sees decoding: rendering the same scene decodes the
    // 16 M texels (192 MiB as f32 RGB).
    let out = dir.path().join("out.png");
    let Some((rendered, render_peak)) =
        peak_kb(&["render", &scene, out.to_str().unwrap(), "--quiet"])
    else {
        return;
    };
    assert!(rendered, "render failed");
    assert!(
        render_peak > 2 * CHECK_PEAK_KB,
        "render peaked at {render_peak} KiB: the texture was not decoded?"
    );
}

#[test]
fn check_refuses_a_texture_by_its_header_and_render_by_its_texels() {
    let dir = tempfile::tempdir().unwrap();
    // A valid header whose texels end early: only decoding can tell.
    write(dir.path(), "short.ppm", "P3 2 2 255 1 2 3");
    write(dir.path(), "empty.ppm", "P3 0 2 255");
    let scene = |texture: &str| {
        write(
            dir.path(),
            "scene.txt",
            format!("camera 4\nsphere\n  dimension 1\n  center 0 0 -5\n  texture {texture}\n"),
        )
    };
    let run = |args: &[&str]| {
        let output = Command::new(bin()).args(args).output().unwrap();
        let shown = [output.stdout, output.stderr].concat();
        (
            output.status.code(),
            String::from_utf8_lossy(&shown).to_string(),
        )
    };
    let path = scene("empty.ppm");
    let (code, stderr) = run(&["check", &path]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("scene::texture_not_an_image"), "{stderr}");

    let path = scene("short.ppm");
    let (code, stderr) = run(&["check", &path]);
    assert_eq!(code, Some(0), "{stderr}");
    let out = dir.path().join("out.png");
    let (code, stderr) = run(&["render", &path, out.to_str().unwrap()]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("scene::texture_not_an_image"), "{stderr}");
    assert!(!out.exists());
}
