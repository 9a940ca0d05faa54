//! What the preview shows, shared between the thread that rebuilds it and
//! the threads that serve it: the last good image as PNG bytes, the
//! diagnostics as `check --format json` prints them, and the page's view of
//! both (an [`Update`]), which every open event stream is sent whenever it
//! changes.
//!
//! The image is replaced only by a render of a valid scene: while the scene
//! has errors, cannot be read or is gone, the last good image stays and the
//! update marks it stale.

use std::io::Write;
use std::sync::{Arc, Mutex, MutexGuard};

use serde::Serialize;

use raytracer_scene::diagnostic::{write_json, JsonDiagnostic};

/// Where the scene stands, as the page shows it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Phase {
    /// Not read yet.
    Starting,
    /// Valid; its image is being rendered (the image shown is older).
    Rendering,
    /// Valid and rendered: the image is this version of the scene.
    Ok,
    /// The scene has errors: the image is the last good one.
    Errors,
    /// The scene file could not be read.
    Unreadable,
    /// The scene file is gone.
    Deleted,
}

/// What a render took, for the page's statistics line.
#[derive(Clone, Debug, Serialize)]
pub struct RenderStats {
    /// The side of the image rendered.
    pub resolution: u32,
    /// The scene camera's side (larger than `resolution` under `--max-size`).
    pub scene_resolution: u32,
    /// Seconds to read and check the scene, to render it and to encode the PNG.
    pub check_seconds: f64,
    pub render_seconds: f64,
    pub encode_seconds: f64,
    pub primary_rays: u64,
    pub shadow_rays: u64,
    pub reflection_rays: u64,
    pub spp: u32,
    pub precision: &'static str,
    pub threads: usize,
}

/// The state of the page: what `/events` sends, as one JSON object.
#[derive(Clone, Debug, Serialize)]
pub struct Update {
    /// Counts every update, so a client can tell a new one from a repeat.
    pub version: u64,
    /// The scene as given on the command line.
    pub scene: String,
    /// docs/diagnostics.md, beside which each diagnostic's code links to
    /// its section in docs/diagnostics/ (`--docs`), if anywhere.
    pub docs: Option<String>,
    pub phase: Phase,
    /// Counts the images rendered: `/image.png?v=N` names the image of
    /// update `N` (`None` before the first).
    pub image: Option<u64>,
    /// The image was rendered from an older version of the scene.
    pub stale: bool,
    /// The image is the quick low-resolution pass; the full one follows.
    pub coarse: bool,
    /// The statistics of the image's render.
    pub stats: Option<RenderStats>,
    pub errors: usize,
    pub warnings: usize,
    /// The same entries as `/diagnostics`.
    pub diagnostics: Vec<JsonDiagnostic>,
}

/// The state shared by the rebuilding thread and the server.
pub struct State {
    shown: Mutex<Shown>,
    /// The open event streams; a stream whose write fails is dropped.
    streams: Mutex<Vec<Box<dyn Write + Send>>>,
}

/// The latest update and the bytes served with it.
struct Shown {
    update: Update,
    png: Option<Arc<Vec<u8>>>,
    diagnostics: Arc<Vec<u8>>,
}

impl State {
    /// Nothing read yet, for the scene named `scene`, with codes linked
    /// to sections of `docs`.
    pub fn new(scene: String, docs: Option<String>) -> State {
        State {
            shown: Mutex::new(Shown {
                update: Update {
                    version: 0,
                    scene,
                    docs,
                    phase: Phase::Starting,
                    image: None,
                    stale: false,
                    coarse: false,
                    stats: None,
                    errors: 0,
                    warnings: 0,
                    diagnostics: Vec::new(),
                },
                png: None,
                diagnostics: Arc::new(json(&Vec::<JsonDiagnostic>::new())),
            }),
            streams: Mutex::new(Vec::new()),
        }
    }

    /// The latest good image as PNG, if there is one.
    pub fn png(&self) -> Option<Arc<Vec<u8>>> {
        lock(&self.shown).png.clone()
    }

    /// The diagnostics as `check --format json` prints them.
    pub fn diagnostics(&self) -> Arc<Vec<u8>> {
        lock(&self.shown).diagnostics.clone()
    }

    /// The latest update.
    pub fn update(&self) -> Update {
        lock(&self.shown).update.clone()
    }

    /// The scene was read: it is in `phase` (not [`Phase::Ok`], which only
    /// an image brings) with these diagnostics; the image shown is stale.
    pub fn diagnosed(&self, phase: Phase, diagnostics: Vec<JsonDiagnostic>) {
        self.change(|shown| {
            shown.diagnostics = Arc::new(json(&diagnostics));
            let update = &mut shown.update;
            update.phase = phase;
            update.stale = update.image.is_some();
            update.errors = count(&diagnostics, "error");
            update.warnings = count(&diagnostics, "warning");
            update.diagnostics = diagnostics;
        });
    }

    /// A render of the scene last diagnosed finished: `png` is its image,
    /// the full one or (`coarse`) the quick pass before it.
    pub fn rendered(&self, png: Vec<u8>, coarse: bool, stats: RenderStats) {
        self.change(|shown| {
            shown.png = Some(Arc::new(png));
            let update = &mut shown.update;
            update.image = Some(update.version + 1);
            update.phase = if coarse { Phase::Rendering } else { Phase::Ok };
            update.stale = false;
            update.coarse = coarse;
            update.stats = Some(stats);
        });
    }

    /// Open an event stream on `stream` (the response head is not yet
    /// written): send the head and the latest update.
    pub fn subscribe(&self, mut stream: Box<dyn Write + Send>) {
        // The lock on the streams is taken before the update is read, so no
        // update can come between this one and the next broadcast.
        let mut streams = lock(&self.streams);
        let event = event(&self.update());
        let head = "HTTP/1.1 200 OK\r\n\
                    Content-Type: text/event-stream\r\n\
                    Cache-Control: no-store\r\n\
                    Connection: close\r\n\r\n";
        let sent = stream
            .write_all(head.as_bytes())
            .and_then(|()| stream.write_all(&event))
            .and_then(|()| stream.flush());
        if sent.is_ok() {
            streams.push(stream);
        }
    }

    /// Apply `edit` to what is shown, count it as a new version, and send
    /// it to every open stream.
    fn change(&self, edit: impl FnOnce(&mut Shown)) {
        let update = {
            let mut shown = lock(&self.shown);
            edit(&mut shown);
            shown.update.version += 1;
            shown.update.clone()
        };
        let event = event(&update);
        lock(&self.streams).retain_mut(|stream| {
            stream
                .write_all(&event)
                .and_then(|()| stream.flush())
                .is_ok()
        });
    }
}

/// A Server-Sent Event `update` carrying `update` as JSON (one line: JSON
/// escapes line breaks inside strings).
fn event(update: &Update) -> Vec<u8> {
    let mut event = b"event: update\ndata: ".to_vec();
    // Serialising plain data into memory cannot fail.
    let _ = serde_json::to_writer(&mut event, update);
    event.extend_from_slice(b"\n\n");
    event
}

/// The diagnostics in the layout of `check --format json`.
fn json(diagnostics: &Vec<JsonDiagnostic>) -> Vec<u8> {
    let mut out = Vec::new();
    // Writing to memory cannot fail.
    let _ = write_json(&mut out, diagnostics);
    out
}

fn count(diagnostics: &[JsonDiagnostic], severity: &str) -> usize {
    diagnostics
        .iter()
        .filter(|d| d.severity == severity)
        .count()
}

/// The lock, even if a thread panicked holding it (the data is whole: every
/// edit is a few assignments).
fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}
