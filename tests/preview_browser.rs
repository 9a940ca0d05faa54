//! `raytracer preview` in a real browser: Debian's `chromium`, headless,
//! driven over the DevTools protocol (JSON over a WebSocket). The page
//! loads, an edit to the scene file swaps the `<img>` for the new render
//! without reloading the page, and a broken edit shows the diagnostics
//! beside the last good image marked stale; a screenshot of that is taken.
//!
//! Chromium is a Debian package that .ci/run installs; without it the test
//! fails when `CI` is set and prints `SKIPPED` visibly otherwise (as
//! tests/pov.rs does for POV-Ray).
//!
//! `preview_latency` (ignored by default; `make preview-latency`) measures
//! the time from saving the scene to the page's `<img>` loading the new
//! render, and writes the table of docs/preview.md.

use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use serde_json::Value;

use crate::preview::{save, Server};
use crate::support::browser::{chromium_available, Browser};

const SAMPLE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/sample.txt");
const WOOD: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/wood_tex.ppm");

/// scenes/sample.txt at `size`² with the sphere's colour `color`, and its
/// texture, in a fresh folder.
fn sample_scene(size: u32) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::copy(WOOD, dir.path().join("wood_tex.ppm")).expect("copy the texture");
    let scene = dir.path().join("sample.txt");
    std::fs::write(&scene, sample_text(size, "0.3 0.3 0.3")).expect("write the scene");
    (dir, scene)
}

fn sample_text(size: u32, color: &str) -> String {
    std::fs::read_to_string(SAMPLE)
        .expect("read scenes/sample.txt")
        .replace("camera 400", &format!("camera {size}"))
        .replace("color 0.3 0.3 0.3", &format!("color {color}"))
}

/// The colour of the image's centre pixel, as the page's `<img>` shows it.
const CENTRE_PIXEL: &str = "(() => {
    const image = document.getElementById('image');
    const canvas = document.createElement('canvas');
    canvas.width = image.naturalWidth;
    canvas.height = image.naturalHeight;
    const context = canvas.getContext('2d');
    context.drawImage(image, 0, 0);
    const half = Math.floor(image.naturalWidth / 2);
    return Array.from(context.getImageData(half, Math.floor(half / 2), 1, 1).data.slice(0, 3));
})()";

/// The page shows the full render of the latest update.
const SHOWS_LATEST: &str = "document.body.dataset.phase === 'ok' \
    && document.body.dataset.image === document.body.dataset.wanted";

/// The side of the image in the browser test.
const SIDE: u32 = 400;

#[test]
fn chromium_shows_edits_without_reloading_and_errors_beside_the_stale_image() {
    if !chromium_available(
        "chromium_shows_edits_without_reloading_and_errors_beside_the_stale_image",
    ) {
        return;
    }
    let (dir, scene) = sample_scene(SIDE);
    // Started in the scene's folder, so the page names it `sample.txt`.
    let server = Server::start_in(
        dir.path(),
        Path::new("sample.txt"),
        &["--docs", "https://course.example/docs/diagnostics.md"],
    );
    let mut browser = Browser::start(1100, 640);
    browser.navigate(&format!("http://{}/", server.address));
    let first = browser.wait_for(SHOWS_LATEST, "document.body.dataset.image");
    assert_eq!(
        browser.eval("document.getElementById('image').naturalWidth"),
        SIDE
    );
    let grey = browser.eval(CENTRE_PIXEL);
    // A reload would drop this.
    browser.eval("window.notReloaded = true");

    save(&scene, &sample_text(SIDE, ".9 .1 .1"));
    let edited = browser.wait_for(
        &format!(
            "{SHOWS_LATEST} && document.body.dataset.image !== '{}'",
            first.as_str().expect("a version")
        ),
        "document.body.dataset.image",
    );
    assert_ne!(edited, first);
    assert_eq!(
        browser.eval("window.notReloaded === true"),
        true,
        "the page reloaded"
    );
    let red = browser.eval(CENTRE_PIXEL);
    assert_ne!(red, grey, "the <img> shows the new render");
    assert!(red[0].as_u64() > red[1].as_u64(), "a red sphere: {red}");

    let misspelt = sample_text(SIDE, ".9 .1 .1").replace("reflectivity 0.7", "reflectivty 0.7");
    let line = 1 + misspelt
        .lines()
        .position(|l| l.contains("reflectivty"))
        .expect("the misspelt line");
    save(&scene, &misspelt);
    let shown = browser.wait_for(
        "document.body.dataset.phase === 'errors' \
         && document.getElementById('figure').classList.contains('stale')",
        "Array.from(document.querySelectorAll('#diagnostics li')).map((li) => \
           [li.className, li.querySelector('.code').textContent, \
            li.querySelector('.code').getAttribute('href'), li.querySelector('.where').textContent])",
    );
    let entry = &shown[0];
    assert_eq!(entry[0], "error");
    assert_eq!(entry[1], "scene::unknown_attribute");
    assert!(
        entry[2].as_str().is_some_and(|href| href
            == "https://course.example/docs/diagnostics/scene.md#sceneunknown_attribute"),
        "{entry}"
    );
    assert!(
        entry[3]
            .as_str()
            .is_some_and(|w| w.ends_with(&format!("sample.txt:{line}:3"))),
        "{entry}"
    );
    assert_eq!(browser.eval(CENTRE_PIXEL), red, "the last good image stays");
    assert_eq!(browser.eval("window.notReloaded === true"), true);

    let screenshot = browser.screenshot();
    let image = image::load_from_memory(&screenshot).expect("a PNG screenshot");
    assert_eq!((image.width(), image.height()), (1100, 640));
    std::fs::write(
        Path::new(env!("CARGO_TARGET_TMPDIR")).join("preview.png"),
        &screenshot,
    )
    .expect("write the screenshot");
    // `make preview-screenshot` keeps it for docs/preview.md.
    if let Some(path) = std::env::var_os("RAYTRACER_PREVIEW_SCREENSHOT") {
        std::fs::write(path, &screenshot).expect("write the screenshot");
    }
}

/// Milliseconds since the epoch, as the page's `Date.now()` counts.
fn now_ms() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .expect("after 1970")
        .as_secs_f64()
        * 1000.0
}

#[test]
#[ignore = "a measurement: `make preview-latency`"]
fn preview_latency() {
    assert!(
        chromium_available("preview_latency"),
        "the measurement needs chromium"
    );
    const SAVES: usize = 7;
    let mut table = String::from(
        "| scene | side | saves | first image (coarse pass), median ms | full image, median ms | full image, min–max ms |\n\
         |---|---|---|---|---|---|\n",
    );
    for size in [400, 1000] {
        let (_dir, scene) = sample_scene(size);
        let server = Server::start(&scene, &["--max-size", "1000"]);
        let mut browser = Browser::start(1100, 1100);
        browser.navigate(&format!("http://{}/", server.address));
        browser.wait_for(SHOWS_LATEST, "0");
        let (mut first, mut full) = (Vec::new(), Vec::new());
        for save_number in 0..SAVES {
            let color = if save_number % 2 == 0 {
                ".9 .1 .1"
            } else {
                ".1 .1 .9"
            };
            let loads_before = browser.eval("window.previewLoads.length");
            let saved = now_ms();
            save(&scene, &sample_text(size, color));
            let loads = browser.wait_for(
                &format!("{SHOWS_LATEST} && window.previewLoads.length > {loads_before}"),
                &format!("window.previewLoads.slice({loads_before})"),
            );
            let loads = loads.as_array().expect("loads");
            let at = |load: &Value| load["at"].as_f64().expect("a time") - saved;
            first.push(at(&loads[0]));
            full.push(at(loads.last().expect("a load")));
            std::thread::sleep(Duration::from_millis(200));
        }
        let median = |times: &mut Vec<f64>| {
            times.sort_by(f64::total_cmp);
            times[times.len() / 2]
        };
        let (min, max) = (
            full.iter().copied().fold(f64::INFINITY, f64::min),
            full.iter().copied().fold(0.0, f64::max),
        );
        table += &format!(
            "| scenes/sample.txt | {size}² | {SAVES} | {:.0} | {:.0} | {min:.0}–{max:.0} |\n",
            median(&mut first),
            median(&mut full),
        );
    }
    println!("{table}");
    if let Some(path) = std::env::var_os("RAYTRACER_PREVIEW_LATENCY") {
        let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
        let section = format!(
            "{LATENCY_BEGIN}\n\n\
             Measured by `make preview-latency` (tests/preview_browser.rs, release build) on\n\
             {} logical CPUs, load average {} when it ended: {SAVES} saves of each size,\n\
             alternating the sphere's colour, `--max-size 1000`, all cores.\n\n{table}\n{LATENCY_END}",
            std::thread::available_parallelism().map_or(0, usize::from),
            load.split_whitespace().take(3).collect::<Vec<_>>().join(" "),
        );
        let doc = std::fs::read_to_string(&path).expect("read the document");
        let (before, rest) = doc.split_once(LATENCY_BEGIN).expect("the begin marker");
        let (_, after) = rest.split_once(LATENCY_END).expect("the end marker");
        std::fs::write(&path, format!("{before}{section}{after}")).expect("write the table");
    }
}

/// The markers of the section of docs/preview.md that `preview_latency`
/// writes.
const LATENCY_BEGIN: &str =
    "<!-- preview-latency:begin: written by `make preview-latency`; edit the test, not this section -->";
const LATENCY_END: &str = "<!-- preview-latency:end -->";
