//! The front end as a library: from a scene's bytes (scene text or JSON) to
//! its checked scene and every diagnostic, for every command, test, fuzz
//! target and example.
//!
//! [`load`] reads a file (or stdin) and [`load_bytes`] takes bytes already
//! in memory; both decode the text, pick the [`Language`], and stream the
//! sections the parser (or the JSON reader) yields through the one check
//! pass, [`SceneCheck`], a batch at a time: neither language ever holds a
//! large scene's whole syntax tree. They decode the scene's textures
//! ([`Decoder`]) for the renderer. [`load_summary`] and [`check_bytes_as`]
//! validate only: they keep a [`Summary`] of a valid scene, never its
//! model, and read only the headers of its textures ([`HeaderReader`]),
//! for callers that want the diagnostics and the effects (`raytracer
//! check`, the language server). [`parse`] stops after parsing, for callers
//! that want the tree itself. This module reads the files; the stages it
//! drives do no I/O of their own. Nothing here knows about the command
//! line, and nothing here reads a clock: [`load_timed`] splits the time
//! between parsing and checking by a clock its caller passes (std's
//! `Instant` panics on targets without one, such as wasm32).

mod read;
#[cfg(test)]
mod summary_parity;

use std::collections::HashMap;
use std::path::Path;
use std::time::Duration;

pub use read::{read_scene, ReadSceneError};

use crate::ast::{self, Section};
use crate::check::{Checked, Collect, SceneCheck, Sink, Summarise, Summary, Valid};
use crate::diagnostic::{boxed, BoxedDiagnostic, FileError, Report, SourceFile};
use crate::fix::Fix;
pub use crate::language::Language;
use crate::texture::{Decoder, HeaderReader, TextureLoader};
use crate::{json, syntax};

/// A scene run through the front end: every diagnostic, and what was kept
/// of the scene (its [`Checked`] model, or a [`Summary`]) when there were no
/// errors.
pub struct Loaded<T = Checked> {
    pub report: Report,
    pub checked: Option<T>,
}

/// A clock the caller reads the time from: the time since any fixed
/// moment (`|| start.elapsed()` with std's `Instant`).
pub type Clock<'a> = &'a dyn Fn() -> Duration;

/// Where [`load_timed`]'s time went.
#[derive(Clone, Copy, Debug, Default)]
pub struct Timings {
    /// Reading and parsing the file.
    pub parse: Duration,
    /// The check pass, texture decoding included.
    pub check: Duration,
}

/// Parse `text` in `language` into a whole syntax tree (`None` when there
/// is nothing to check: a JSON text that is not a scene of this format),
/// with every problem found on the way. The commands do not build the whole
/// tree; this is for callers that want it.
pub fn parse(language: Language, text: &str) -> (Option<ast::File>, Vec<BoxedDiagnostic>) {
    match language {
        Language::Text => {
            let parsed = syntax::parse(text);
            (Some(parsed.file), boxed(parsed.errors))
        }
        Language::Json => {
            let parsed = json::parse(text);
            (parsed.file, boxed(parsed.errors))
        }
    }
}

/// Read `path` (`-` is stdin), parse it as scene text or JSON (see
/// [`Language::of`]) and check it.
pub fn load(path: &Path) -> Result<Loaded, ReadSceneError> {
    let mut decoder = Decoder::default();
    let (loaded, _) = load_into::<Collect>(path, &mut decoder, None)?;
    Ok(decoded(loaded, decoder))
}

/// [`load`], with the time spent parsing and checking read from `clock`.
pub fn load_timed(path: &Path, clock: Clock) -> Result<(Loaded, Timings), ReadSceneError> {
    let mut decoder = Decoder::default();
    let (loaded, timings) = load_into::<Collect>(path, &mut decoder, Some(clock))?;
    Ok((decoded(loaded, decoder), timings))
}

/// [`load`], keeping only the [`Summary`] of a valid scene (each object is
/// summarised and dropped as soon as it is checked) and reading only the
/// headers of its textures.
pub fn load_summary(path: &Path) -> Result<Loaded<Summary>, ReadSceneError> {
    let (loaded, _) = load_into::<Summarise>(path, &mut HeaderReader, None)?;
    Ok(loaded)
}

/// [`load`] with each valid object handed to a sink of kind `S`, and
/// texture files read through `textures`; timed by `clock` when given.
fn load_into<S: Sink>(
    path: &Path,
    textures: &mut dyn TextureLoader,
    clock: Option<Clock>,
) -> Result<(Loaded<S::Scene>, Timings), ReadSceneError> {
    let start = clock.map(|clock| clock());
    let bytes = read_scene(path)?;
    let (name, dir) = if path == Path::new("-") {
        let cwd = std::env::current_dir()
            .map_err(|error| ReadSceneError::Io(FileError::new("read scene", path, &error)))?;
        ("<stdin>".to_string(), cwd)
    } else {
        let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
        (path.display().to_string(), dir)
    };
    let language = Language::of(path, &bytes);
    // The buffer read becomes the text: one copy of a large scene, never
    // two.
    let (source, utf8_error) = SourceFile::from_vec(&name, &dir, bytes);
    let loaded = load_source::<S>(source, utf8_error, language, textures, clock);
    let timings = match (clock, start) {
        (Some(clock), Some(start)) => Timings {
            parse: (clock() - start).saturating_sub(loaded.1),
            check: loaded.1,
        },
        _ => Timings::default(),
    };
    Ok((loaded.0, timings))
}

/// A valid scene with the textures `decoder` decoded while checking it.
fn decoded(loaded: Loaded<Valid>, mut decoder: Decoder) -> Loaded {
    let Loaded { report, checked } = loaded;
    let checked = checked.map(|Valid { scene, textures }| Checked {
        scene,
        textures: textures
            .into_iter()
            .filter_map(|(written, header)| Some((written, decoder.take(&header)?)))
            .collect(),
    });
    Loaded { report, checked }
}

/// Parse and check scene bytes named `name` (scene text, or JSON when the
/// name ends in `.json`), whose texture paths resolve against `dir`.
///
/// ```
/// use std::path::Path;
///
/// let text = "camera 4\nsphere\n  dimension 0\n  center 0 0 -5\n";
/// let loaded = raytracer_scene::frontend::load_bytes("a.txt", Path::new("."), text.as_bytes());
/// assert!(loaded.checked.is_none());
/// let codes: Vec<String> = loaded.report.entries().map(|e| e.code).collect();
/// assert!(codes.iter().any(|c| c.starts_with("scene::")), "{codes:?}");
/// ```
pub fn load_bytes(name: &str, dir: &Path, bytes: &[u8]) -> Loaded {
    load_bytes_as(Language::of(Path::new(name), bytes), name, dir, bytes)
}

/// [`load_bytes`] in an explicit language, whatever the name says.
pub fn load_bytes_as(language: Language, name: &str, dir: &Path, bytes: &[u8]) -> Loaded {
    let (source, utf8_error) = SourceFile::from_bytes(name, dir, bytes);
    let mut decoder = Decoder::default();
    let (loaded, _) = load_source::<Collect>(source, utf8_error, language, &mut decoder, None);
    decoded(loaded, decoder)
}

/// [`load_bytes_as`] with the scene's textures read from `files` (by
/// path as written, or by file name: [`Decoder::in_memory`]) rather than
/// from the file system, for a caller that has none (the WebAssembly
/// playground).
pub fn load_bytes_in_memory(
    language: Language,
    name: &str,
    bytes: &[u8],
    files: HashMap<String, Vec<u8>>,
) -> Loaded {
    let (source, utf8_error) = SourceFile::from_bytes(name, Path::new(""), bytes);
    let mut decoder = Decoder::in_memory(files);
    let (loaded, _) = load_source::<Collect>(source, utf8_error, language, &mut decoder, None);
    decoded(loaded, decoder)
}

/// [`load_bytes_as`] validating only: the diagnostics and the [`Summary`]
/// of a valid scene, reading only the headers of its textures (the
/// language server's check after an edit).
pub fn check_bytes_as(language: Language, name: &str, dir: &Path, bytes: &[u8]) -> Loaded<Summary> {
    let (source, utf8_error) = SourceFile::from_bytes(name, dir, bytes);
    let (loaded, _) =
        load_source::<Summarise>(source, utf8_error, language, &mut HeaderReader, None);
    loaded
}

/// A diagnostic with the fix it carries.
type Fixable = (BoxedDiagnostic, Option<Fix>);

/// Syntax errors with the fixes they carry.
fn with_fixes(errors: Vec<syntax::SyntaxError>) -> impl Iterator<Item = Fixable> {
    errors.into_iter().map(|e| {
        let fix = e.fix().cloned();
        (Box::new(e) as BoxedDiagnostic, fix)
    })
}

/// Sections parsed before they are checked (and dropped). Few, so that
/// the blocks a batch frees fit the allocator's per-thread cache (glibc's
/// tcache keeps 7 blocks of each size) and the next batch reuses them
/// while they are hot.
const CHECK_BATCH: usize = 3;

/// The check pass fed a batch of sections at a time, so the clock (when
/// there is one) is read twice a batch, not twice a section.
struct Batches<'a, S: Sink> {
    check: SceneCheck<'a, S>,
    batch: Vec<Section>,
    clock: Option<Clock<'a>>,
    checking: Duration,
}

impl<'a, S: Sink> Batches<'a, S> {
    fn new(
        source: &'a SourceFile,
        textures: &'a mut dyn TextureLoader,
        language: Language,
        clock: Option<Clock<'a>>,
    ) -> Batches<'a, S> {
        let check = SceneCheck::with_sink(source, S::default(), textures);
        Batches {
            check: match language {
                Language::Text => check.fed_from_scene_text(),
                Language::Json => check,
            },
            batch: Vec::with_capacity(CHECK_BATCH),
            clock,
            checking: Duration::ZERO,
        }
    }

    fn push(&mut self, section: Section) {
        self.batch.push(section);
        if self.batch.len() == CHECK_BATCH {
            self.flush();
        }
    }

    fn flush(&mut self) {
        let started = now(self.clock);
        for section in self.batch.drain(..) {
            self.check.section(&section);
        }
        self.checking += now(self.clock) - started;
    }

    /// The whole-file checks; the checked scene and the check's
    /// diagnostics with their fixes, and the time spent checking.
    fn finish(mut self) -> (Option<S::Scene>, Vec<Fixable>, Duration) {
        self.flush();
        let started = now(self.clock);
        let (checked, problems) = self.check.finish();
        let checking = self.checking + (now(self.clock) - started);
        let problems = problems
            .into_iter()
            .map(|p| {
                let fix = p.fix().cloned();
                (Box::new(p) as BoxedDiagnostic, fix)
            })
            .collect();
        (checked, problems, checking)
    }
}

/// The time on `clock`, or zero without one.
fn now(clock: Option<Clock>) -> Duration {
    clock.map_or(Duration::ZERO, |clock| clock())
}

/// Parse and check decoded scene text in a given language, each section
/// checked as the parser yields it and dropped once checked: a scene of
/// 100,000 spheres never holds its whole syntax tree (docs/performance.md).
/// The diagnostics come in the same order as from [`parse`] then the check
/// pass: syntax (or JSON) errors, then the check's. With the time spent
/// checking, read from `clock` (zero without one).
fn load_source<'a, S: Sink>(
    source: SourceFile,
    utf8_error: Option<syntax::SyntaxError>,
    language: Language,
    textures: &'a mut dyn TextureLoader,
    clock: Option<Clock<'a>>,
) -> (Loaded<S::Scene>, Duration) {
    let mut diagnostics: Vec<Fixable> = Vec::new();
    let not_text = matches!(utf8_error, Some(syntax::SyntaxError::NotText { .. }));
    let unfixed = |d: Vec<BoxedDiagnostic>| d.into_iter().map(|d| (d, None));
    diagnostics.extend(unfixed(
        utf8_error
            .into_iter()
            .map(|e| Box::new(e) as BoxedDiagnostic)
            .collect(),
    ));
    if not_text {
        // One diagnostic for a file that is not text: nothing to parse.
        let report = Report::with_fixes(source, diagnostics);
        return (
            Loaded {
                report,
                checked: None,
            },
            Duration::ZERO,
        );
    }
    let (mut batches, is_scene) = match language {
        Language::Text => {
            let mut batches = Batches::<S>::new(&source, textures, language, clock);
            let mut sections = syntax::sections(&source.text);
            for section in sections.by_ref() {
                batches.push(section);
            }
            diagnostics.extend(with_fixes(sections.into_errors()));
            (batches, true)
        }
        Language::Json => {
            let mut batches = Batches::<S>::new(&source, textures, language, clock);
            let read = json::read(&source.text, |section| batches.push(section));
            diagnostics.extend(unfixed(boxed(read.errors)));
            (batches, read.is_scene)
        }
    };
    let (checked, checking) = if is_scene {
        if diagnostics
            .iter()
            .any(|(d, _)| crate::diagnostic::severity_of(d.as_ref()) == miette::Severity::Error)
        {
            batches.check.after_errors();
        }
        let (checked, problems, checking) = batches.finish();
        diagnostics.extend(problems);
        (checked, checking)
    } else {
        (None, batches.checking)
    };
    let report = Report::with_fixes(source, diagnostics);
    let checked = checked.filter(|_| report.error_count() == 0);
    (Loaded { report, checked }, checking)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What [`load_bytes`] reports, as `code@offset` strings, and whether
    /// the scene checked.
    fn streamed(name: &str, text: &str) -> (Vec<String>, bool) {
        let loaded = load_bytes(name, Path::new("."), text.as_bytes());
        let codes = loaded.report.entries().map(|e| coded(&e)).collect();
        (codes, loaded.checked.is_some())
    }

    /// The whole tree parsed first, then checked section by section.
    fn whole(name: &str, text: &str) -> (Vec<String>, bool) {
        let (source, _) = SourceFile::from_bytes(name, Path::new("."), text.as_bytes());
        let language = Language::of(Path::new(name), text.as_bytes());
        let (file, mut diagnostics) = parse(language, text);
        let mut checked = None;
        if let Some(file) = file {
            let mut headers = HeaderReader;
            let mut check = SceneCheck::new(&source, &mut headers);
            if diagnostics
                .iter()
                .any(|d| crate::diagnostic::severity_of(d.as_ref()) == miette::Severity::Error)
            {
                check.after_errors();
            }
            for section in &file.sections {
                check.section(section);
            }
            let (scene, problems) = check.finish();
            diagnostics.extend(boxed(problems));
            checked = scene;
        }
        let report = Report::new(source, diagnostics);
        let codes = report.entries().map(|e| coded(&e)).collect();
        (codes, checked.is_some() && report.error_count() == 0)
    }

    fn coded(entry: &crate::diagnostic::JsonDiagnostic) -> String {
        let at = entry.labels.first().map_or(0, |l| l.byte_offset);
        format!("{}@{at}", entry.code)
    }

    #[test]
    fn streaming_either_language_equals_checking_the_whole_tree() {
        for (name, text, problems) in [
            ("a.txt", "camera 4\nsphere dimension 1 center 0 0 -5", 1),
            ("b.txt", "camera 0\nsphere dimension 0\nsphre\n1 2 3", 4),
            (
                "c.json",
                r#"{"format": "raytracer-scene/1", "camera": {"resolution": 4},
                  "objects": [{"type": "sphere", "center": [0, 0, -5], "radius": 1}],
                  "lights": [{"location": [0, 0, -5], "color": [2, 0, 0]}]}"#,
                2,
            ),
            (
                "d.json",
                r#"{"format": "raytracer-scene/1", "camera": {"resolution": 0},
                  "objects": [{"type": "sphear"}, {"type": "plane", "center": [0, 0, -5],
                  "width": 1, "height": 1, "normal": [0, 0, 0], "headup": [0, 1, 0]}]}"#,
                3,
            ),
            ("e.json", r#"{"format": "raytracer-scene/9"}"#, 1),
            ("f.json", "[1, 2]", 1),
        ] {
            let streamed = streamed(name, text);
            assert_eq!(streamed, whole(name, text), "{name}");
            assert_eq!(streamed.0.len(), problems, "{name}: {:?}", streamed.0);
        }
    }
}
