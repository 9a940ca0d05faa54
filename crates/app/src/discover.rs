//! Which files a command that takes folders works on (`check`, `fmt`): the
//! files it is given, and the scene files found by walking the folders it
//! is given, with one rule, [`classify`], for what is a scene.
//!
//! Folders are walked with the `ignore` crate (ripgrep's walker): hidden
//! files and folders are skipped, and `.gitignore` and `.ignore` files are
//! honoured, inside a git repository or not, but not the user's global
//! gitignore, so a walk finds the same files on every machine. Entries are
//! visited in byte order of their names, folder by folder, so the order of
//! a report is deterministic. Symbolic links are not followed.
//!
//! A file named on the command line is always a scene. A `.txt`, `.scene`
//! or `.json` file found by a walk is a scene or is skipped with the reason
//! why (a folder of submissions may hold a `README.txt` or a
//! `package.json`); nothing is dropped unnamed. A file that is not text
//! (UTF-16, a binary) or cannot be read counts as a scene, so the command
//! reports it. docs/cli.md states the rule for users.

use std::io::Read;
use std::path::{Path, PathBuf};

use miette::Diagnostic;

use raytracer_scene::ast::SectionKind;
use raytracer_scene::diagnostic::{io_reason, lowercase_first, FileError};

/// How much of a found file is read to decide whether it is a scene.
const SNIFF_BYTES: u64 = 64 * 1024;

/// One file (or unreadable folder entry) a command's arguments expand to.
#[derive(Debug)]
pub enum Found {
    /// A scene to work on: a file named on the command line (or `-`), or
    /// a file a walk classified as a scene.
    Scene { path: PathBuf, named: bool },
    /// A file a walk found that is not a scene, and why.
    Skipped { path: PathBuf, reason: String },
    /// A folder entry a walk could not read.
    Unreadable(WalkError),
}

/// What a command's path arguments expand to.
#[derive(Debug, Default)]
pub struct Discovered {
    /// Each argument in turn, a folder replaced by what was found in it.
    pub found: Vec<Found>,
    /// Whether any argument was a folder.
    pub walked: bool,
}

/// A folder entry that a walk could not read.
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error(transparent)]
#[diagnostic(code(io::read_folder))]
pub struct WalkError(FileError);

impl WalkError {
    /// The entry that could not be read.
    pub fn path(&self) -> &str {
        self.0.path()
    }
}

/// Expand `args` into the files to work on. `-` (stdin) and anything that
/// is not a folder is kept as given, even when it does not exist: loading
/// it reports why it cannot be read.
pub fn discover(args: &[PathBuf]) -> Discovered {
    let mut discovered = Discovered::default();
    for arg in args {
        if arg != Path::new("-") && arg.is_dir() {
            discovered.walked = true;
            walk(arg, &mut discovered.found);
        } else {
            discovered.found.push(Found::Scene {
                path: arg.clone(),
                named: true,
            });
        }
    }
    discovered
}

fn walk(folder: &Path, found: &mut Vec<Found>) {
    let walker = ignore::WalkBuilder::new(folder)
        .git_global(false)
        .require_git(false)
        .sort_by_file_name(|a, b| a.cmp(b))
        .build();
    for entry in walker {
        let entry = match entry {
            Ok(entry) => entry,
            Err(error) => {
                found.push(Found::Unreadable(walk_error(folder, &error)));
                continue;
            }
        };
        if !entry.file_type().is_some_and(|t| t.is_file()) {
            continue;
        }
        let path = entry.into_path();
        let Some(kind) = Kind::of(&path) else {
            continue;
        };
        // A file that cannot be read is a scene: working on it says why.
        let verdict = sniff(&path).map_or(Verdict::Scene, |head| classify(kind, &head));
        found.push(match verdict {
            Verdict::Scene => Found::Scene { path, named: false },
            Verdict::Skip(reason) => Found::Skipped { path, reason },
        });
    }
}

fn walk_error(folder: &Path, error: &ignore::Error) -> WalkError {
    let path = match error {
        ignore::Error::WithPath { path, .. } => path.clone(),
        _ => folder.to_path_buf(),
    };
    let reason = match error.io_error() {
        Some(io) => io_reason(io),
        None => lowercase_first(&error.to_string()),
    };
    WalkError(FileError::with_reason("read folder entry", &path, reason))
}

/// The kinds of file a walk considers, by extension (any case).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// `.txt`: scene text, the course's extension, shared with every other
    /// text file.
    Text,
    /// `.scene`: scene text by its own extension.
    Scene,
    /// `.json`: a JSON scene, or any other JSON document.
    Json,
}

impl Kind {
    /// The kind of `path`, or `None` for a file a walk ignores.
    pub fn of(path: &Path) -> Option<Kind> {
        let extension = path.extension()?.to_str()?.to_ascii_lowercase();
        match extension.as_str() {
            "txt" => Some(Kind::Text),
            "scene" => Some(Kind::Scene),
            "json" => Some(Kind::Json),
            _ => None,
        }
    }
}

/// Whether a found file is a scene.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Verdict {
    Scene,
    /// Not a scene, for this reason ("its first word `Notes` is not a
    /// section keyword").
    Skip(String),
}

/// The first [`SNIFF_BYTES`] of `path`, or `None` if it cannot be read.
fn sniff(path: &Path) -> Option<Vec<u8>> {
    let mut head = Vec::new();
    std::fs::File::open(path)
        .and_then(|file| file.take(SNIFF_BYTES).read_to_end(&mut head))
        .ok()?;
    Some(head)
}

/// Whether a file found by a walk, of `kind` and starting with `head`, is
/// a scene:
/// - a file that is not UTF-8 text ([`raytracer_scene::encoding::sniff`]: UTF-16, a
///   binary): yes, so the command reports it instead of passing over it;
/// - `.scene`: always;
/// - `.txt`: when its first word, as the parser reads it (after
///   whitespace and `#` comments), is a section keyword in any case, as
///   every scene's is, or a near miss of one (`camra`), which checking then
///   reports;
/// - `.json`: when it names the scene layout, `"raytracer-scene/`, the
///   start of the `format` value every JSON scene begins with.
pub fn classify(kind: Kind, head: &[u8]) -> Verdict {
    if raytracer_scene::encoding::sniff(head).is_some() {
        return Verdict::Scene;
    }
    let text = String::from_utf8_lossy(head);
    let keywords = SectionKind::KEYWORDS;
    match kind {
        Kind::Scene => Verdict::Scene,
        Kind::Text => match raytracer_scene::syntax::first_word(&text) {
            Some(word)
                if keywords.iter().any(|k| k.eq_ignore_ascii_case(word))
                    || raytracer_scene::suggest::nearest(word, &keywords).is_some() =>
            {
                Verdict::Scene
            }
            Some(word) => Verdict::Skip(format!(
                "its first word `{}` is not a section keyword",
                shortened(word)
            )),
            None => Verdict::Skip("it holds no words (empty, or only comments)".to_string()),
        },
        Kind::Json if text.contains("\"raytracer-scene/") => Verdict::Scene,
        Kind::Json => Verdict::Skip(format!(
            "a JSON file without `\"raytracer-scene/` in its first {} KiB",
            SNIFF_BYTES / 1024
        )),
    }
}

/// `word`, cut to its first 40 characters for a message.
fn shortened(word: &str) -> String {
    match word.char_indices().nth(40) {
        Some((end, _)) => format!("{}…", &word[..end]),
        None => word.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(s: &str) -> Verdict {
        classify(Kind::Text, s.as_bytes())
    }

    #[test]
    fn text_is_a_scene_when_it_starts_with_a_section_or_a_near_miss() {
        assert_eq!(text("camera 400\nsphere dimension 1"), Verdict::Scene);
        assert_eq!(text("# course file\nLight location 0 0 0"), Verdict::Scene);
        assert_eq!(text("\u{2028}plane\tdimension 1 1"), Verdict::Scene);
        assert_eq!(text("\u{feff}camra 400\nsphere"), Verdict::Scene);
        assert_eq!(
            text("This folder holds the submissions.\ncamera 400"),
            Verdict::Skip("its first word `This` is not a section keyword".to_string())
        );
        assert!(matches!(text("400\nsphere"), Verdict::Skip(_)));
        assert!(matches!(text(""), Verdict::Skip(_)));
        assert!(matches!(text("# only a comment"), Verdict::Skip(_)));
        assert_eq!(classify(Kind::Scene, b"anything"), Verdict::Scene);
    }

    #[test]
    fn files_that_are_not_text_are_scenes_so_they_are_reported() {
        let utf16: Vec<u8> = "\u{feff}camera 4"
            .encode_utf16()
            .flat_map(u16::to_le_bytes)
            .collect();
        assert_eq!(classify(Kind::Text, &utf16), Verdict::Scene);
        assert_eq!(classify(Kind::Text, b"\x7fELF\x02\x01\0\0"), Verdict::Scene);
        assert_eq!(classify(Kind::Json, b"\x7fELF\x02\x01\0\0"), Verdict::Scene);
    }

    #[test]
    fn json_is_a_scene_when_it_names_the_layout() {
        let json = |s: &str| classify(Kind::Json, s.as_bytes());
        assert_eq!(
            json(r#"{"format": "raytracer-scene/1", "camera": {}}"#),
            Verdict::Scene
        );
        assert!(matches!(
            json(r#"{"name": "submissions", "version": "1.0.0"}"#),
            Verdict::Skip(_)
        ));
    }

    #[test]
    fn kinds_by_extension() {
        assert_eq!(Kind::of(Path::new("a/b.TXT")), Some(Kind::Text));
        assert_eq!(Kind::of(Path::new("b.scene")), Some(Kind::Scene));
        assert_eq!(Kind::of(Path::new("b.Json")), Some(Kind::Json));
        assert_eq!(Kind::of(Path::new("wood_tex.ppm")), None);
        assert_eq!(Kind::of(Path::new("Makefile")), None);
    }
}
