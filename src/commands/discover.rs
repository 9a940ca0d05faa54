//! Which files `raytracer check` checks: the files it is given, and the
//! scene files found by walking the folders it is given.
//!
//! Folders are walked with the `ignore` crate (ripgrep's walker): hidden
//! files and folders are skipped, and `.gitignore` and `.ignore` files are
//! honoured, inside a git repository or not, but not the user's global
//! gitignore, so a walk finds the same files on every machine. Entries are
//! visited in byte order of their names, folder by folder, so the order of
//! the report is deterministic. Symbolic links are not followed.
//!
//! A file named on the command line is always checked. A file found by a
//! walk is checked when it looks like a scene (see [`looks_like_scene`]):
//! a folder of submissions may hold a `README.txt` or a `package.json`,
//! and those are counted as skipped rather than reported as a wall of
//! errors. docs/cli.md states the rule for users.

use std::io::Read;
use std::path::{Path, PathBuf};

use miette::Diagnostic;

use crate::ast::SectionKind;

/// How much of a found file is read to decide whether it is a scene.
const SNIFF_BYTES: u64 = 64 * 1024;

/// What `check`'s arguments expand to.
#[derive(Debug, Default)]
pub struct Discovered {
    /// The files to check, in order: each argument in turn, a folder
    /// replaced by the scenes found in it.
    pub scenes: Vec<PathBuf>,
    /// Files found by walks that are not scenes.
    pub skipped: usize,
    /// Whether any argument was a folder.
    pub walked: bool,
    /// Entries a walk could not read.
    pub errors: Vec<WalkError>,
}

/// A folder entry that a walk could not read.
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error("cannot read folder entry `{path}`: {reason}")]
#[diagnostic(code(io::read_folder))]
pub struct WalkError {
    pub path: String,
    pub reason: String,
}

/// Expand `args` into the files to check. `-` (stdin) and anything that is
/// not a folder is kept as given, even when it does not exist: loading it
/// reports why it cannot be read.
pub fn discover(args: &[PathBuf]) -> Discovered {
    let mut found = Discovered::default();
    for arg in args {
        if arg != Path::new("-") && arg.is_dir() {
            found.walked = true;
            walk(arg, &mut found);
        } else {
            found.scenes.push(arg.clone());
        }
    }
    found
}

fn walk(folder: &Path, found: &mut Discovered) {
    let walker = ignore::WalkBuilder::new(folder)
        .git_global(false)
        .require_git(false)
        .sort_by_file_name(|a, b| a.cmp(b))
        .build();
    for entry in walker {
        let entry = match entry {
            Ok(entry) => entry,
            Err(error) => {
                found.errors.push(walk_error(folder, &error));
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
        // A file that cannot be read is kept: checking it says why.
        let is_scene = sniff(&path).is_none_or(|head| looks_like_scene(kind, &head));
        if is_scene {
            found.scenes.push(path);
        } else {
            found.skipped += 1;
        }
    }
}

fn walk_error(folder: &Path, error: &ignore::Error) -> WalkError {
    let path = match error {
        ignore::Error::WithPath { path, .. } => path.clone(),
        _ => folder.to_path_buf(),
    };
    let reason = match error.io_error() {
        Some(io) => crate::diagnostic::io_reason(io),
        None => crate::diagnostic::lowercase_first(&error.to_string()),
    };
    WalkError {
        path: path.display().to_string(),
        reason,
    }
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

/// The first [`SNIFF_BYTES`] of `path`, or `None` if it cannot be read.
fn sniff(path: &Path) -> Option<Vec<u8>> {
    let mut head = Vec::new();
    std::fs::File::open(path)
        .and_then(|file| file.take(SNIFF_BYTES).read_to_end(&mut head))
        .ok()?;
    Some(head)
}

/// Whether a file found by a walk, starting with `head`, is a scene:
/// - `.scene`: always;
/// - `.txt`: when its first word (after whitespace and `#` comments) is a
///   section keyword in any case, as every scene's is;
/// - `.json`: when it names the scene layout, `"raytracer-scene/`, the
///   start of the `format` value every JSON scene begins with.
pub fn looks_like_scene(kind: Kind, head: &[u8]) -> bool {
    let text = String::from_utf8_lossy(head);
    match kind {
        Kind::Scene => true,
        Kind::Text => first_word(&text).is_some_and(|word| {
            SectionKind::KEYWORDS
                .iter()
                .any(|keyword| keyword.eq_ignore_ascii_case(word))
        }),
        Kind::Json => text.contains("\"raytracer-scene/"),
    }
}

/// The first word of scene text: skip whitespace (any Unicode whitespace and
/// the byte-order mark) and `#` comments, then take characters up to the
/// next whitespace, `#` or `"`.
fn first_word(text: &str) -> Option<&str> {
    let is_space = |c: char| c.is_whitespace() || c == '\u{feff}';
    let is_line_end = |c: char| matches!(c, '\n' | '\r' | '\u{85}' | '\u{2028}' | '\u{2029}');
    let mut rest = text;
    loop {
        rest = rest.trim_start_matches(is_space);
        match rest.strip_prefix('#') {
            Some(comment) => rest = comment.trim_start_matches(|c| !is_line_end(c)),
            None => break,
        }
    }
    let end = rest
        .find(|c: char| is_space(c) || c == '#' || c == '"')
        .unwrap_or(rest.len());
    (end > 0).then(|| &rest[..end])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_word_skips_whitespace_and_comments() {
        assert_eq!(first_word("camera 400"), Some("camera"));
        assert_eq!(
            first_word("\u{feff}# a scene\r\n  # more\u{2028}sphere#x"),
            Some("sphere")
        );
        assert_eq!(first_word("  \n# only a comment"), None);
        assert_eq!(first_word(""), None);
        assert_eq!(first_word("\"quoted\" rest"), None);
    }

    #[test]
    fn text_is_a_scene_when_it_starts_with_a_section() {
        let text = |s: &str| looks_like_scene(Kind::Text, s.as_bytes());
        assert!(text("camera 400\nsphere dimension 1"));
        assert!(text("# course file\nLight location 0 0 0"));
        assert!(text("\u{2028}plane\tdimension 1 1"));
        assert!(!text("This folder holds the submissions.\ncamera 400"));
        assert!(!text("400\nsphere"));
        assert!(!text(""));
        assert!(looks_like_scene(Kind::Scene, b"anything"));
    }

    #[test]
    fn json_is_a_scene_when_it_names_the_layout() {
        let json = |s: &str| looks_like_scene(Kind::Json, s.as_bytes());
        assert!(json(r#"{"format": "raytracer-scene/1", "camera": {}}"#));
        assert!(json(r#"{"format": "raytracer-scene/99"}"#));
        assert!(!json(r#"{"name": "submissions", "version": "1.0.0"}"#));
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
