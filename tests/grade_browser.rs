//! The reports of `raytracer grade` in a real browser: Debian's
//! `chromium`, headless, driven over the DevTools protocol by the
//! [`Browser`] of tests/support/browser.rs. Each student's `index.html`,
//! opened from `file://`, shows every image it names (loaded, with a
//! width) and one row per scene; `class.html` has one row per student,
//! and a cell's link opens that student's report at the scene's row; on a
//! 1920-px screen each row's three images stand side by side. A
//! screenshot of a report is taken (`make grading-screenshot` keeps it as
//! docs/grading-report.png).
//!
//! Chromium is a Debian package that .ci/run installs; without it the test
//! fails when `CI` is set and prints `SKIPPED` otherwise.

use std::path::Path;

use percent_encoding::{utf8_percent_encode, AsciiSet, NON_ALPHANUMERIC};
use serde_json::Value;

use crate::grade_class::class_folder;
use crate::support;
use crate::support::browser::{chromium_available, Browser};
use crate::support::grading::binary;

/// Every `<img>` of the page: whether it loaded, and its natural width.
const IMAGES: &str = "Array.from(document.images).map((image) => \
    [image.getAttribute('src'), image.complete, image.naturalWidth])";

/// For each scene's row: whether its first three figures share a top and
/// run left to right.
const SIDE_BY_SIDE: &str = "Array.from(document.querySelectorAll('tr.scene')).map((row) => { \
    const boxes = Array.from(row.querySelectorAll('figure')).slice(0, 3) \
      .map((figure) => figure.getBoundingClientRect()); \
    return boxes.length === 3 && boxes.every((box) => Math.abs(box.top - boxes[0].top) < 1) \
      && boxes[0].right <= boxes[1].left && boxes[1].right <= boxes[2].left; })";

/// Characters a `file://` URL keeps as they are.
const PATH: &AsciiSet = &NON_ALPHANUMERIC
    .remove(b'/')
    .remove(b'.')
    .remove(b'-')
    .remove(b'_');

/// The `file://` URL of `path`.
fn file_url(path: &Path) -> String {
    format!(
        "file://{}",
        utf8_percent_encode(&path.display().to_string(), PATH)
    )
}

#[test]
fn reports_show_every_image_and_link_the_class_to_each_scene() {
    if !chromium_available("reports_show_every_image_and_link_the_class_to_each_scene") {
        return;
    }
    let dir = class_folder();
    let d = dir.path();
    // A fourth student: right on the ball, too dark on the red ball.
    let dave = d.join("students/dave");
    std::fs::create_dir(&dave).unwrap();
    support::write(&dave, "tracer.txt", "./tracer.sh {scene} {out}\n");
    let script = format!(
        "#!/bin/sh\ncase \"$1\" in\n  red.txt) sed 's/color .9 .1 .2/color .4 .05 .1/' \"$1\" > dim.txt\n    \
         exec {bin} render dim.txt \"$2\" ;;\n  *) exec {bin} render \"$1\" \"$2\" ;;\nesac\n",
        bin = binary().display()
    );
    support::write(&dave, "tracer.sh", script);
    std::fs::set_permissions(
        dave.join("tracer.sh"),
        std::os::unix::fs::PermissionsExt::from_mode(0o755),
    )
    .unwrap();
    let output = support::command(&[
        "grade", "--class", "students", "-o", "class", "--cache", "cache", "suite",
    ])
    .current_dir(d)
    .output()
    .unwrap();
    assert_eq!(
        output.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let class = d.join("class");

    let mut browser = Browser::start(1100, 760);
    for student in ["alice", "bob", "carol \"<&>\" #1", "dave"] {
        let report = class.join(student).join("index.html");
        let summary: Value = serde_json::from_slice(
            &std::fs::read(class.join(student).join("summary.json")).unwrap(),
        )
        .unwrap();
        browser.navigate(&file_url(&report));
        let images = browser.eval(IMAGES);
        let images = images.as_array().unwrap();
        // Ours for each scene, and the student's and the heat map when it wrote one.
        let named: usize = summary["scenes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| {
                ["reference", "student", "heatmap"]
                    .iter()
                    .filter(|kind| s["images"][**kind].is_string())
                    .count()
            })
            .sum();
        assert_eq!(images.len(), named, "{student}: {images:?}");
        for image in images {
            assert_eq!(image[1], true, "{student}: {image}");
            assert!(image[2].as_u64().unwrap() > 0, "{student}: {image}");
        }
        assert_eq!(
            browser.eval("document.querySelectorAll('tr.scene').length"),
            2,
            "{student}"
        );
    }
    // The last report shown is dave's: a match and an image that differs.
    let screenshot = browser.screenshot();
    let image = image::load_from_memory(&screenshot).expect("a PNG screenshot");
    assert_eq!((image.width(), image.height()), (1100, 760));
    if let Some(path) = std::env::var_os("RAYTRACER_GRADING_SCREENSHOT") {
        std::fs::write(path, &screenshot).expect("write the screenshot");
    }

    // On a 1920-px screen each scene's three images (ours, the student's,
    // the error) stand side by side, left to right, not stacked: in each
    // student's report, and in one whose rows have a long reason and a long
    // line of stderr beside the images (a tracer that warns and writes no
    // image).
    let garbage = d.join("garbage.sh");
    let warning = "the scene reader skipped a line it did not know: ".repeat(4);
    support::write(
        d,
        "garbage.sh",
        format!("#!/bin/sh\necho \"warning: {warning}\" >&2\nprintf 'P3\\n2 2\\n0\\n' > \"$2\"\n"),
    );
    std::fs::set_permissions(
        &garbage,
        std::os::unix::fs::PermissionsExt::from_mode(0o755),
    )
    .unwrap();
    let tracer = format!("{} {{scene}} {{out}}", garbage.display());
    let output = support::command(&[
        "grade", "--tracer", &tracer, "-o", "wide", "--cache", "cache", "suite",
    ])
    .current_dir(d)
    .output()
    .unwrap();
    assert_eq!(
        output.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let mut wide = Browser::start(1920, 1080);
    for report in ["alice", "bob", "carol \"<&>\" #1", "dave"]
        .map(|student| class.join(student))
        .into_iter()
        .chain([d.join("wide")])
    {
        wide.navigate(&file_url(&report.join("index.html")));
        let rows = wide.eval(SIDE_BY_SIDE);
        assert_eq!(
            rows,
            serde_json::json!([true, true]),
            "{}",
            report.display()
        );
    }

    browser.navigate(&file_url(&class.join("class.html")));
    assert_eq!(
        browser.eval("document.querySelectorAll('tr.student').length"),
        4
    );
    let link = browser.eval(
        "Array.from(document.querySelectorAll('tr.student')).find((row) => \
           row.textContent.startsWith('dave')).querySelectorAll('a.status')[1].href",
    );
    let link = link.as_str().unwrap();
    assert!(
        link.ends_with("/class/dave/index.html#scene-red.txt"),
        "{link}"
    );
    browser.navigate(link);
    assert_eq!(
        browser.eval(
            "document.querySelector(':target').className + ' ' + \
             document.querySelector(':target b').textContent"
        ),
        "scene red.txt"
    );
}
