//! Texture files: each distinct path is resolved against the scene file's
//! folder and loaded once through the caller's
//! [`TextureLoader`] (the check itself does no I/O); a failure becomes a
//! diagnostic at every line that names the file. The textures of a scene
//! share one budget of texels ([`MAX_SCENE_TEXELS`]), judged from each
//! file's header before a loader may decode its pixels.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::diagnostic::lowercase_first;
use crate::limits::{MAX_SCENE_TEXELS, MAX_TEXTURE_SIDE, MAX_TEXTURE_TEXELS};
use crate::span::Spanned;
use crate::texture::{self, Header, TextureError, TextureLoader};

use super::errors::CheckError;

/// Why a texture did not load, kept so later lines naming the same file get
/// the same diagnostic without reading it again.
#[derive(Clone, Debug)]
enum Failure {
    Unreadable(String),
    NoFile,
    Undecodable(String),
    /// `width × height` texels, and the texels of the textures loaded before
    /// it when it was the scene's budget that it broke.
    TooLarge {
        width: u32,
        height: u32,
        before: Option<u64>,
    },
}

/// The textures loaded so far, and the paths that failed.
pub struct Textures<'a> {
    dir: PathBuf,
    /// The scene's text, to quote a fixed path as it was written.
    text: &'a str,
    loader: &'a mut dyn TextureLoader,
    loaded: BTreeMap<String, Header>,
    failed: BTreeMap<String, Failure>,
    /// Texels of every texture in `loaded`.
    texels: u64,
}

impl<'a> Textures<'a> {
    /// An empty set resolving paths against `dir`, reading files through
    /// `loader`.
    pub fn new(dir: &Path, text: &'a str, loader: &'a mut dyn TextureLoader) -> Textures<'a> {
        Textures {
            dir: dir.to_path_buf(),
            text,
            loader,
            loaded: BTreeMap::new(),
            failed: BTreeMap::new(),
            texels: 0,
        }
    }

    /// The fix that writes `near` in place of the path at `span`: quoted
    /// as the path was (a scene-text string and a JSON string escape
    /// alike), or bare.
    fn path_fix(&self, near: &str, span: crate::span::Span) -> Box<crate::fix::Fix> {
        let quoted = self
            .text
            .get(span.start()..)
            .is_some_and(|t| t.starts_with('"'))
            || near.contains(|c: char| c.is_whitespace() || c == '#');
        let content = if quoted {
            serde_json::to_string(near).unwrap_or_else(|_| near.to_string())
        } else {
            near.to_string()
        };
        crate::fix::Fix::boxed(
            format!("write `{near}`"),
            crate::fix::Applicability::Unsafe,
            span,
            &content,
        )
    }

    /// The entry of `folder` (relative to the scene's folder, with `/`,
    /// empty for the scene's own) named `name`, or else one that names it
    /// in another case, as a path from the scene's folder.
    fn entry(&mut self, folder: &str, name: &str) -> Option<String> {
        if name.is_empty() {
            return None;
        }
        let entries = self.loader.entries(&self.dir.join(folder));
        let found = entries
            .iter()
            .find(|e| *e == name)
            .or_else(|| entries.iter().find(|e| e.eq_ignore_ascii_case(name)))?;
        Some(if folder.is_empty() {
            found.clone()
        } else {
            format!("{folder}/{found}")
        })
    }

    /// A path near `written` that names a file where it does not: with
    /// `/` for `\`, without curly or straight quotes, in the case the
    /// folder has it; else the file's name beside the scene (whatever
    /// folder, even another drive, was written before it); else the same
    /// name in a folder of the scene's folder, beside it, or in a folder
    /// beside it, the shortest such path. Each is a path from the scene's
    /// folder. `None` when there is none, or `written` is absolute and
    /// its name is nowhere near the scene.
    fn near(&mut self, written: &str) -> Option<String> {
        let quotes: &[char] = &['\u{201C}', '\u{201D}', '\u{2018}', '\u{2019}', '"', '\''];
        let plain = written.replace('\\', "/");
        let plain = plain.trim_matches(quotes).to_string();
        let (folder, name) = plain.rsplit_once('/').unwrap_or(("", plain.as_str()));
        let absolute = plain.starts_with('/') || folder.contains(':');
        if !absolute {
            if let Some(near) = self.entry(folder, name).filter(|near| near != written) {
                return Some(near);
            }
        }
        if let Some(beside) = self.entry("", name).filter(|near| near != written) {
            return Some(beside);
        }
        let mut folders: Vec<String> = self.loader.entries(&self.dir);
        folders.sort();
        let mut siblings: Vec<String> = self.loader.entries(&self.dir.join(".."));
        siblings.sort();
        let folders = folders
            .into_iter()
            .take(64)
            .chain(std::iter::once("..".to_string()))
            .chain(siblings.into_iter().take(64).map(|s| format!("../{s}")));
        let mut found: Vec<String> = folders
            .filter_map(|folder| self.entry(&folder, name))
            .collect();
        found.sort_by_key(|path| (path.len(), path.clone()));
        found.into_iter().next()
    }

    /// Load `path` (as written) unless already done; the diagnostic when it
    /// does not load (boxed: it is a large value on a path taken rarely).
    pub fn load(&mut self, path: Spanned<&str>) -> Result<(), Box<CheckError>> {
        let written = path.value;
        if self.loaded.contains_key(written) {
            return Ok(());
        }
        let resolved = self.dir.join(written);
        let failure = match self.failed.get(written) {
            Some(failure) => failure.clone(),
            None => match self.loader.load(&resolved, MAX_SCENE_TEXELS - self.texels) {
                Ok(header) => {
                    self.texels += u64::from(header.width) * u64::from(header.height);
                    self.loaded.insert(written.to_string(), header);
                    return Ok(());
                }
                Err(error) => {
                    let failure = match error {
                        TextureError::Io(error) => Failure::Unreadable(error.reason().to_string()),
                        TextureError::NotAFile { .. } => Failure::NoFile,
                        TextureError::Decode { source, .. } => {
                            Failure::Undecodable(decode_reason(&source))
                        }
                        TextureError::Truncated { .. } => Failure::Undecodable(
                            "the file ends before its last texel (truncated?)".to_string(),
                        ),
                        TextureError::Empty { width, height, .. } => Failure::Undecodable(format!(
                            "{width} × {height} texels: an image has at least one"
                        )),
                        TextureError::TooLarge { width, height, .. } => Failure::TooLarge {
                            width,
                            height,
                            before: texture::fits(width, height, MAX_TEXTURE_TEXELS)
                                .then_some(self.texels),
                        },
                    };
                    self.failed.insert(written.to_string(), failure.clone());
                    failure
                }
            },
        };
        let shown = resolved.display();
        let path_span = path.span;
        let span = path.span.into();
        let path = written.to_string();
        Err(Box::new(match failure {
            Failure::Unreadable(reason) => {
                let near = self.near(written);
                let help = match &near {
                    Some(near) => format!("did you mean `{near}`?"),
                    None => format!(
                        "looked for `{shown}`; paths are relative to the scene file's folder"
                    ),
                };
                CheckError::TextureNotFound {
                    path,
                    reason,
                    span,
                    help,
                    fix: near.map(|near| self.path_fix(&near, path_span)),
                }
            }
            Failure::NoFile => CheckError::TextureNotAFile {
                path,
                span,
                help: format!("`{shown}` is a folder or a special file; name an image file"),
            },
            Failure::Undecodable(reason) => CheckError::TextureNotAnImage {
                path,
                reason: lowercase_first(&reason),
                span,
                help: format!(
                    "looked at `{shown}`; textures are PPM (P3 or P6), PNG or JPEG images"
                ),
            },
            Failure::TooLarge {
                width,
                height,
                before,
            } => CheckError::TextureTooLarge {
                path,
                expected: match before {
                    None => format!(
                        "at most {MAX_TEXTURE_TEXELS} texels and {MAX_TEXTURE_SIDE} on a side"
                    ),
                    Some(_) => format!("at most {MAX_SCENE_TEXELS} texels in all textures"),
                },
                found: match before {
                    None => format!("{width} × {height}"),
                    Some(before) => format!("{width} × {height} after {before}"),
                },
                span,
                help: format!(
                    "looked at `{shown}`; scale the image down, such as to 4096 × 4096 \
                     ({MAX_TEXTURE_TEXELS} texels)"
                ),
            },
        }))
    }

    /// The header of every texture that loaded, keyed by its path as
    /// written.
    pub fn into_loaded(self) -> BTreeMap<String, Header> {
        self.loaded
    }
}

/// Why an image did not decode, without the decoder's internals.
fn decode_reason(error: &image::ImageError) -> String {
    match error {
        image::ImageError::Unsupported(_) => "not a PPM, PNG or JPEG file".to_string(),
        other => lowercase_first(&other.to_string()),
    }
}
