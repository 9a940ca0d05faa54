//! The playground (docs/playground.md) in a real browser: Debian's
//! `chromium`, headless, driven over the DevTools protocol by
//! tests/support/browser.rs, on the page `make web` built in
//! target/web/site, opened from `file://`. Typing a misspelt attribute
//! shows its diagnostic at its line within 500 ms; its quick fix, clicked,
//! changes the text, and the image the page then renders (and downloads
//! as PNG) is `raytracer render`'s, pixel for pixel; a dropped texture is
//! used; `camera 16384` leaves the page answering and typing checked; a
//! share link restores the scene; the menu opens a suite scene and the
//! file picker a scene file. The WebAssembly module is fed the
//! hostile-input set of the CLI tests (under node, which CI installs) and
//! reports what the native front end reports.
//!
//! A test binary of its own (`make test-web`, after `make web`), apart from
//! `make test`: without the built page, or without Chromium or node, each
//! test fails under CI and prints `SKIPPED` otherwise.
//! `RAYTRACER_PLAYGROUND_FIGURES=FILE` appends the figures measured on the
//! way (docs/playground.md) to FILE.

mod support;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use support::browser::{chromium_available, Browser, PATIENCE};
use support::{bin, skipped, tool_available, under_ci};

/// One browser at a time: the latency a test asserts is not another's.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

fn repository() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The page `make web` built, when it is there; under CI its absence is a
/// failure.
fn site(test: &str) -> Option<PathBuf> {
    let page = repository().join("target/web/site/index.html");
    if page.is_file() {
        return Some(page);
    }
    assert!(
        !under_ci(),
        "{} is missing, and CI must run {test}: `make web` builds it",
        page.display()
    );
    skipped(&format!("{test}: the playground is not built (`make web`)"));
    None
}

/// A scratch folder inside the repository's target folder.
fn scratch() -> tempfile::TempDir {
    let dir = repository().join("target/web/test");
    std::fs::create_dir_all(&dir).expect("target/web/test");
    tempfile::tempdir_in(dir).expect("scratch folder")
}

/// The page loaded in a fresh browser, its downloads going to `downloads`,
/// once it has shown the diagnostics of its first scene.
fn open(page: &Path, fragment: &str, downloads: &Path) -> Browser {
    let mut browser = Browser::start(1200, 900);
    browser.call(
        "Browser.setDownloadBehavior",
        json!({"behavior": "allow", "downloadPath": downloads.display().to_string()}),
    );
    browser.navigate(&format!("file://{}{fragment}", page.display()));
    browser.wait_for(
        "document.body.dataset.ready === 'true' && document.getElementById('status').dataset.checkedSeq",
        "true",
    );
    browser
}

/// Focus the editor and put the cursor at the end of its text.
fn cursor_to_end(browser: &mut Browser) {
    browser.eval("document.querySelector('.cm-content').focus()");
    for kind in ["keyDown", "keyUp"] {
        browser.call(
            "Input.dispatchKeyEvent",
            json!({"type": kind, "key": "End", "code": "End", "windowsVirtualKeyCode": 35,
                   "modifiers": 2}),
        );
    }
}

/// Type `text` a character at a time, as a keyboard would; a line break
/// goes with the character before it (Chromium's `Input.insertText` of a
/// lone line break at the end of an editable element inserts two).
fn type_text(browser: &mut Browser, text: &str) {
    for key in keystrokes(text) {
        browser.call("Input.insertText", json!({ "text": key }));
    }
}

/// `text` as [`type_text`] sends it.
fn keystrokes(text: &str) -> Vec<String> {
    let mut keys: Vec<String> = Vec::new();
    for c in text.chars() {
        match keys.last_mut() {
            Some(last) if c == '\n' && !last.ends_with('\n') => last.push(c),
            _ => keys.push(c.to_string()),
        }
    }
    keys
}

/// Replace the whole text, as a paste over a selection would.
fn replace_text(browser: &mut Browser, text: &str) {
    browser.eval("document.querySelector('.cm-content').focus()");
    for kind in ["keyDown", "keyUp"] {
        browser.call(
            "Input.dispatchKeyEvent",
            json!({"type": kind, "key": "a", "code": "KeyA", "windowsVirtualKeyCode": 65,
                   "modifiers": 2}),
        );
    }
    browser.call("Input.insertText", json!({"text": text}));
}

/// Wait until the page has rendered its current text; the render's time
/// in milliseconds, as the page measured it. The newest text must have
/// been checked too: until its check returns, the status still shows the
/// last text's render as done (its render starts when the check does).
fn rendered(browser: &mut Browser) -> f64 {
    let ms = browser.wait_for(
        "(() => { const s = document.getElementById('status').dataset;
                  return s.state === 'rendered' && s.checkedSeq === s.seq; })()",
        "Number(document.getElementById('status').dataset.renderMs)",
    );
    ms.as_f64().expect("a number")
}

/// Click the element `selector`.
fn click(browser: &mut Browser, selector: &str) {
    let clicked = browser.eval(&format!(
        "(() => {{ const e = document.querySelector({selector:?}); if (!e) return false; e.click(); return true; }})()"
    ));
    assert_eq!(clicked, true, "no {selector} to click");
}

/// The file `name` once the browser has written it to `folder`.
fn downloaded(folder: &Path, name: &str) -> Vec<u8> {
    let path = folder.join(name);
    let start = Instant::now();
    loop {
        let partial = std::fs::read_dir(folder)
            .expect("downloads")
            .flatten()
            .any(|e| e.file_name().to_string_lossy().ends_with(".crdownload"));
        if path.is_file() && !partial {
            return std::fs::read(&path).expect("read the download");
        }
        assert!(start.elapsed() < PATIENCE, "{name} was not downloaded");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The RGB bytes of a PNG.
fn png_rgb(bytes: &[u8]) -> (u32, Vec<u8>) {
    let image = image::load_from_memory(bytes).expect("a PNG").into_rgb8();
    (image.width(), image.into_raw())
}

/// `raytracer render` of `text` in `dir` (with the wood texture beside
/// it, and `extra` files): its pixels.
fn native_render(dir: &Path, text: &str, extra: &[(&str, &[u8])]) -> (u32, Vec<u8>) {
    std::fs::copy(
        repository().join("scenes/wood_tex.ppm"),
        dir.join("wood_tex.ppm"),
    )
    .expect("copy the texture");
    for (name, bytes) in extra {
        std::fs::write(dir.join(name), bytes).expect("write a texture");
    }
    std::fs::write(dir.join("native.txt"), text).expect("write the scene");
    let output = Command::new(bin())
        .args(["render", "native.txt", "native.png", "--quiet"])
        .current_dir(dir)
        .output()
        .expect("run raytracer");
    assert!(output.status.success(), "{output:?}");
    png_rgb(&std::fs::read(dir.join("native.png")).expect("native.png"))
}

/// The canvas's pixels as RGB.
fn canvas_rgb(browser: &mut Browser) -> (u32, Vec<u8>) {
    let value = browser.eval(
        "(() => { const c = document.getElementById('image');
                  const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
                  const rgb = []; for (let i = 0; i < d.length; i += 4) rgb.push(d[i], d[i + 1], d[i + 2]);
                  return [c.width, rgb]; })()",
    );
    let size = value[0].as_u64().expect("a width") as u32;
    let rgb = value[1]
        .as_array()
        .expect("pixels")
        .iter()
        .map(|v| v.as_u64().expect("a byte") as u8)
        .collect();
    (size, rgb)
}

/// Append a line of measured figures to `$RAYTRACER_PLAYGROUND_FIGURES`.
fn record(line: &str) {
    if let Some(file) = std::env::var_os("RAYTRACER_PLAYGROUND_FIGURES") {
        use std::io::Write;
        let mut out = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(file)
            .expect("the figures file");
        writeln!(out, "{line}").expect("write the figures");
    }
}

fn sample() -> String {
    std::fs::read_to_string(repository().join("scenes/sample.txt")).expect("the sample")
}

/// The most the module may weigh gzipped (`gzip -9`, as a web server
/// compresses it), which docs/playground.md promises: 400 KiB.
const MODULE_GZIPPED_BUDGET: usize = 400 * 1024;

/// The module `make web` built, after `wasm-opt -Oz`, is within
/// [`MODULE_GZIPPED_BUDGET`] once gzipped.
#[test]
fn the_module_is_at_most_400_kib_gzipped() {
    if site("the_module_is_at_most_400_kib_gzipped").is_none() {
        return;
    }
    let module = repository().join("target/web/raytracer.wasm");
    let bytes = std::fs::metadata(&module).expect("the module").len();
    let gzip = Command::new("gzip")
        .arg("-9c")
        .arg(&module)
        .output()
        .expect("run gzip");
    assert!(gzip.status.success(), "gzip -9c {}", module.display());
    let gzipped = gzip.stdout.len();
    record(&format!(
        "the module: {bytes} bytes, {gzipped} bytes gzipped (gzip -9)"
    ));
    assert!(
        gzipped <= MODULE_GZIPPED_BUDGET,
        "the module is {gzipped} bytes gzipped, over the {MODULE_GZIPPED_BUDGET} \
         docs/playground.md promises"
    );
}

#[test]
fn a_misspelt_attribute_is_shown_at_its_line_and_its_fix_renders_the_native_image() {
    let test = "a_misspelt_attribute_is_shown_at_its_line_and_its_fix_renders_the_native_image";
    let Some(page) = site(test) else { return };
    if !chromium_available(test) {
        return;
    }
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let dir = scratch();
    let mut browser = open(&page, "", dir.path());
    let first =
        browser.eval("Number(document.getElementById('status').dataset.firstDiagnosticsMs)");
    let sample_ms = rendered(&mut browser);
    let rows = browser.eval("document.querySelectorAll('#problems li').length");
    assert_eq!(rows, 0, "the sample has no problems");

    cursor_to_end(&mut browser);
    let mut keys = keystrokes("sphere\n  dimenson 1\n  center 0 0 -3\n");
    let last = keys.pop().expect("keys");
    for key in keys {
        browser.call("Input.insertText", json!({ "text": key }));
    }
    // The diagnostics of the text after the last keystroke (the page
    // numbers each version of the text) are there within 500 ms of it.
    let before = browser.eval("Number(document.getElementById('status').dataset.seq)");
    let started = Instant::now();
    browser.call("Input.insertText", json!({ "text": last }));
    let shown = browser.wait_for(
        &format!("Number(document.getElementById('status').dataset.checkedSeq) > {before}"),
        "[document.querySelector('#problems li').dataset.line, document.querySelector('#problems li').textContent, Number(document.getElementById('status').dataset.latencyMs)]",
    );
    let waited = started.elapsed();
    let rows = browser.eval("document.querySelectorAll('#problems li').length");
    assert_eq!(rows, 1, "{shown}");
    // The misspelt line is the second of the sphere typed after the
    // sample's last line.
    let line = sample().lines().count() + 2;
    assert_eq!(shown[0], line.to_string().as_str(), "{shown}");
    let text = shown[1].as_str().unwrap();
    assert!(
        text.contains("unknown attribute `dimenson` in `sphere`"),
        "{text}"
    );
    assert!(text.contains(&format!("{line}:3")), "{text}");
    assert!(
        waited < Duration::from_millis(500),
        "the diagnostic took {waited:?}"
    );
    // The editor marks the span too.
    let marked = browser.eval("document.querySelectorAll('.cm-lintRange-error').length");
    assert!(marked.as_u64() > Some(0), "no inline mark: {marked}");

    // The quick fix, clicked, changes the text; the scene then renders as
    // `raytracer render` renders it.
    click(&mut browser, "#problems li button.fix");
    browser.wait_for(
        "document.querySelectorAll('#problems li.error').length === 0",
        "true",
    );
    let render_ms = rendered(&mut browser);
    click(&mut browser, "#download-scene");
    let fixed = String::from_utf8(downloaded(dir.path(), "sample.txt")).expect("UTF-8");
    assert_eq!(
        fixed,
        format!("{}sphere\n  dimension 1\n  center 0 0 -3\n", sample())
    );
    click(&mut browser, "#download-png");
    let page_png = png_rgb(&downloaded(dir.path(), "sample.png"));
    let native = native_render(dir.path(), &fixed, &[]);
    assert_eq!(page_png.0, 400);
    assert!(
        page_png == native,
        "the page's PNG differs from `raytracer render`'s"
    );
    assert!(canvas_rgb(&mut browser) == native, "the canvas differs");
    record(&format!(
        "first diagnostics {first} ms after navigation; keystroke to diagnostics {waited:?} \
         (page: {} ms); the sample at 400² rendered in {sample_ms} ms, with one more sphere \
         in {render_ms} ms",
        shown[2]
    ));

    if let Some(path) = std::env::var_os("RAYTRACER_PLAYGROUND_SCREENSHOT") {
        // The misspelling again, for the screenshot of docs/playground.md.
        cursor_to_end(&mut browser);
        type_text(&mut browser, "light\n  locaton 2 2 0\n");
        browser.wait_for(
            "document.querySelector(\"#problems li[data-code='scene::unknown_attribute']\")",
            "true",
        );
        std::fs::write(path, browser.screenshot()).expect("write the screenshot");
    }
}

#[test]
fn a_dropped_texture_is_used() {
    let test = "a_dropped_texture_is_used";
    let Some(page) = site(test) else { return };
    if !chromium_available(test) {
        return;
    }
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let dir = scratch();
    let mut browser = open(&page, "", dir.path());
    let scene =
        "camera 40\nplane\n  dimension 2 2\n  center 0 0 -3\n  normal 0 0 1\n  headup 0 1 0\n  \
                 texture checks.ppm\n";
    replace_text(&mut browser, scene);
    browser.wait_for(
        "document.querySelector(\"#problems li[data-code='scene::texture_not_found']\")",
        "true",
    );
    // A 2 × 2 texture of blue and yellow checks, dropped on the page.
    let checks = b"P3\n2 2\n255\n0 0 255 255 255 0\n255 255 0 0 0 255\n";
    let bytes: Vec<u8> = checks.to_vec();
    browser.eval(&format!(
        "(() => {{ const data = new DataTransfer();
                  data.items.add(new File([new Uint8Array({bytes:?})], 'checks.ppm'));
                  document.body.dispatchEvent(new DragEvent('drop', {{ dataTransfer: data, bubbles: true, cancelable: true }}));
                  return true; }})()"
    ));
    browser.wait_for(
        "document.querySelectorAll('#problems li.error').length === 0",
        "true",
    );
    rendered(&mut browser);
    let listed = browser.eval("document.getElementById('textures').textContent");
    assert!(listed.as_str().unwrap().contains("checks.ppm"), "{listed}");
    let native = native_render(dir.path(), scene, &[("checks.ppm", checks)]);
    let shown = canvas_rgb(&mut browser);
    assert!(
        shown == native,
        "the page's image differs from `raytracer render`'s"
    );
    assert!(
        shown.1.chunks(3).any(|p| p[2] > p[0]) && shown.1.chunks(3).any(|p| p[0] > p[2]),
        "no blue and yellow checks"
    );
}

#[test]
fn a_camera_of_16384_does_not_freeze_the_page() {
    let test = "a_camera_of_16384_does_not_freeze_the_page";
    let Some(page) = site(test) else { return };
    if !chromium_available(test) {
        return;
    }
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let dir = scratch();
    let mut browser = open(&page, "", dir.path());
    rendered(&mut browser);
    // The first render's coarse frame is gone from the status once it
    // has rendered, so the wait below finds the next render's.
    let stale = browser.eval("'coarse' in document.getElementById('status').dataset");
    assert_eq!(stale.as_bool(), Some(false), "{stale}");
    replace_text(
        &mut browser,
        &sample().replace("camera 400", "camera 16384"),
    );
    // The coarse image comes first, while the full one renders.
    browser.wait_for(
        "document.getElementById('status').dataset.coarse === '100'",
        "true",
    );
    let status = browser.eval("document.getElementById('status').textContent");
    assert!(
        status.as_str().unwrap().contains("Rendering 2048 × 2048"),
        "{status}"
    );
    // The page answers, again and again, while the full image renders (a
    // page whose thread rendered would answer nothing before the render
    // ended); the bound leaves room for a loaded machine.
    let mut slowest = Duration::ZERO;
    let mut while_rendering = 0;
    for _ in 0..20 {
        let started = Instant::now();
        let state = browser.eval("document.getElementById('status').dataset.state");
        slowest = slowest.max(started.elapsed());
        if state == "rendering" {
            while_rendering += 1;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    assert!(
        while_rendering > 0,
        "the render ended before the first call"
    );
    assert!(
        slowest < Duration::from_millis(500),
        "the page took {slowest:?} to answer"
    );
    record(&format!(
        "camera 16384: {while_rendering} of 20 calls answered while rendering 2048², the \
         slowest in {slowest:?}"
    ));
    // Typing is still checked at once, and the edit stops the render.
    cursor_to_end(&mut browser);
    let started = Instant::now();
    type_text(&mut browser, "sphere\n  dimension -1\n");
    browser.wait_for("document.querySelector('#problems li.error')", "true");
    assert!(
        started.elapsed() < Duration::from_millis(1500),
        "typing was checked after {:?}",
        started.elapsed()
    );
    let state = browser.eval("document.getElementById('status').dataset.state");
    assert_eq!(state, "errors");
}

#[test]
fn a_share_link_restores_the_scene() {
    let test = "a_share_link_restores_the_scene";
    let Some(page) = site(test) else { return };
    if !chromium_available(test) {
        return;
    }
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let dir = scratch();
    let mut browser = open(&page, "", dir.path());
    let scene =
        "# Ünïcode survives the link.\ncamera 20\nsphere\n  dimension 1\n  center 0 0 -4\n  \
                 color 1 .5 0\nlight\n  location 0 3 0\n  color 1 1 1\n";
    replace_text(&mut browser, scene);
    rendered(&mut browser);
    click(&mut browser, "#share");
    let link = browser.wait_for(
        "document.getElementById('share-link').value.includes('#scene=')",
        "document.getElementById('share-link').value",
    );
    let link = link.as_str().expect("a link").to_string();
    drop(browser);
    let fragment = &link[link.find('#').expect("a fragment")..];
    let mut browser = open(&page, fragment, dir.path());
    rendered(&mut browser);
    click(&mut browser, "#download-scene");
    let restored = String::from_utf8(downloaded(dir.path(), "sample.txt")).expect("UTF-8");
    assert_eq!(restored, scene);
}

/// What the module reports for each hostile input equals the native front
/// end's diagnostics (codes and offsets), and it never aborts.
#[test]
fn the_module_reports_every_hostile_input_as_the_command_line_does() {
    let test = "the_module_reports_every_hostile_input_as_the_command_line_does";
    let wasm = repository().join("target/web/raytracer.wasm");
    if site(test).is_none() || !tool_available("node", test, "apt-get install nodejs") {
        return;
    }
    let dir = scratch();
    let mut names = Vec::new();
    for (what, name, bytes, _) in support::hostile::inputs() {
        std::fs::write(dir.path().join(name), &bytes).expect("write an input");
        names.push((what, name, bytes));
    }
    let output = Command::new("node")
        .arg(repository().join("web/test/hostile.mjs"))
        .arg(&wasm)
        .args(names.iter().map(|(_, name, _)| dir.path().join(name)))
        .output()
        .expect("run node");
    assert!(
        output.status.success(),
        "the module failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let results: Vec<Value> = String::from_utf8(output.stdout)
        .expect("UTF-8")
        .lines()
        .map(|line| serde_json::from_str(line).expect("a JSON line"))
        .collect();
    assert_eq!(results.len(), names.len());
    for ((what, name, bytes), result) in names.iter().zip(&results) {
        let native = raytracer_scene::frontend::load_bytes(name, Path::new(""), bytes);
        let expected: Vec<Value> = native
            .report
            .entries()
            .map(|e| json!([e.code, e.labels.first().map(|l| l.byte_offset)]))
            .collect();
        let found: Vec<Value> = result["diagnostics"]
            .as_array()
            .expect("diagnostics")
            .iter()
            .map(|d| json!([d["code"], d["labels"][0]["byte_offset"]]))
            .collect();
        assert_eq!(found, expected, "{what}");
        assert_eq!(
            result["rendered"],
            native.checked.is_some(),
            "{what}: rendered"
        );
    }
}

#[test]
fn the_menu_opens_a_suite_scene_and_the_file_picker_a_scene_file() {
    let test = "the_menu_opens_a_suite_scene_and_the_file_picker_a_scene_file";
    let Some(page) = site(test) else { return };
    if !chromium_available(test) {
        return;
    }
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let dir = scratch();
    let mut browser = open(&page, "", dir.path());
    rendered(&mut browser);
    let chosen = browser.eval(
        "(() => { const menu = document.getElementById('scene-picker');
                  const i = [...menu.options].findIndex((o) => o.textContent === 'suite: shadows.txt');
                  menu.value = String(i); menu.dispatchEvent(new Event('change')); return i; })()",
    );
    assert!(
        chosen.as_i64() > Some(0),
        "no suite scene in the menu: {chosen}"
    );
    browser.wait_for(
        "document.getElementById('scene-name').textContent === 'shadows.txt'",
        "true",
    );
    rendered(&mut browser);
    click(&mut browser, "#download-scene");
    let suite = std::fs::read(repository().join("suite/shadows.txt")).expect("the suite scene");
    assert_eq!(downloaded(dir.path(), "shadows.txt"), suite);

    let reflection = repository().join("scenes/reflection.txt");
    let root = browser.call("DOM.getDocument", json!({}));
    let input = browser.call(
        "DOM.querySelector",
        json!({"nodeId": root["root"]["nodeId"], "selector": "#files"}),
    );
    browser.call(
        "DOM.setFileInputFiles",
        json!({"nodeId": input["nodeId"], "files": [reflection.display().to_string()]}),
    );
    browser.wait_for(
        "document.getElementById('scene-name').textContent === 'reflection.txt'",
        "true",
    );
    rendered(&mut browser);
    let text = std::fs::read_to_string(&reflection).expect("scenes/reflection.txt");
    let native = native_render(dir.path(), &text, &[]);
    assert!(
        canvas_rgb(&mut browser) == native,
        "the page's image differs from `raytracer render`'s"
    );
}
