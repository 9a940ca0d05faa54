//! Texture files: each distinct path is resolved against the scene file's
//! folder and loaded once with [`crate::texture::load`]; a failure becomes a
//! diagnostic at every line that names the file. The textures of a scene
//! share one budget of texels ([`MAX_SCENE_TEXELS`]), judged from each
//! file's header before its pixels are decoded.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::diagnostic::{io_reason, lowercase_first};
use crate::limits::{MAX_SCENE_TEXELS, MAX_TEXTURE_SIDE, MAX_TEXTURE_TEXELS};
use crate::span::Spanned;
use crate::texture::{self, Texture, TextureError};

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
#[derive(Debug)]
pub struct Textures {
    dir: PathBuf,
    loaded: BTreeMap<String, Texture>,
    failed: BTreeMap<String, Failure>,
    /// Texels of every texture in `loaded`.
    texels: u64,
}

impl Textures {
    /// An empty set resolving paths against `dir`.
    pub fn new(dir: &Path) -> Textures {
        Textures {
            dir: dir.to_path_buf(),
            loaded: BTreeMap::new(),
            failed: BTreeMap::new(),
            texels: 0,
        }
    }

    /// These textures, then those `later` loaded on its own from the
    /// lines after these: true when that is what loading them all in
    /// order would have given, so the two are joined; false (and the
    /// caller loads in one run) when the shared texel budget makes the
    /// order matter: a texture too large in either, or more texels in all
    /// than the budget holds. A path that failed or loaded in both did the
    /// same in each, so either result stands.
    pub fn then(&mut self, later: Textures) -> bool {
        let too_large = |textures: &Textures| {
            textures
                .failed
                .values()
                .any(|f| matches!(f, Failure::TooLarge { .. }))
        };
        if too_large(self) || too_large(&later) {
            return false;
        }
        let added: u64 = later
            .loaded
            .iter()
            .filter(|(path, _)| !self.loaded.contains_key(*path))
            .map(|(_, t)| u64::from(t.width) * u64::from(t.height))
            .sum();
        if self.texels + added > MAX_SCENE_TEXELS {
            return false;
        }
        self.texels += added;
        for (path, texture) in later.loaded {
            self.loaded.entry(path).or_insert(texture);
        }
        for (path, failure) in later.failed {
            self.failed.entry(path).or_insert(failure);
        }
        true
    }

    /// Load `path` (as written) unless already done; the diagnostic when it
    /// does not load.
    pub fn load(&mut self, path: Spanned<&str>) -> Result<(), CheckError> {
        let written = path.value;
        if self.loaded.contains_key(written) {
            return Ok(());
        }
        let resolved = self.dir.join(written);
        let failure = match self.failed.get(written) {
            Some(failure) => failure.clone(),
            None => match texture::load(&resolved, MAX_SCENE_TEXELS - self.texels) {
                Ok(texture) => {
                    self.texels += u64::from(texture.width) * u64::from(texture.height);
                    self.loaded.insert(written.to_string(), texture);
                    return Ok(());
                }
                Err(error) => {
                    let failure = match error {
                        TextureError::Io { source, .. } => Failure::Unreadable(io_reason(&source)),
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
        let span = path.span.into();
        let path = written.to_string();
        Err(match failure {
            Failure::Unreadable(reason) => CheckError::TextureNotFound {
                path,
                reason,
                span,
                help: format!(
                    "looked for `{shown}`; paths are relative to the scene file's folder"
                ),
            },
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
        })
    }

    /// Every texture that loaded, keyed by its path as written.
    pub fn into_loaded(self) -> BTreeMap<String, Texture> {
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
