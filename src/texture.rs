//! Loading texture images into [`crate::ir::Texture`].
//!
//! Decoding goes through the `image` crate (PPM P3/P6 at any maxval, PNG,
//! JPEG) with limits set before any pixel is allocated, so a hostile header
//! cannot exhaust memory. The check pass calls [`load`] so a texture that is
//! missing or does not decode is a diagnostic, never a render failure.

use std::path::Path;

use image::{ImageReader, Limits};

use crate::ir::Texture;

/// The largest texture width or height accepted.
pub const MAX_TEXTURE_SIDE: u32 = 16384;

/// Why a texture could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum TextureError {
    #[error("cannot read `{path}`: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("`{path}` is not a regular file")]
    NotAFile { path: String },
    #[error("`{path}` does not decode as an image: {source}")]
    Decode {
        path: String,
        source: image::ImageError,
    },
}

/// Load and decode the image at `path`.
pub fn load(path: &Path) -> Result<Texture, TextureError> {
    let shown = path.display().to_string();
    let metadata = std::fs::metadata(path).map_err(|source| TextureError::Io {
        path: shown.clone(),
        source,
    })?;
    if !metadata.is_file() {
        return Err(TextureError::NotAFile { path: shown });
    }
    let mut reader = ImageReader::open(path)
        .and_then(|r| r.with_guessed_format())
        .map_err(|source| TextureError::Io {
            path: shown.clone(),
            source,
        })?;
    let mut limits = Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIDE);
    limits.max_image_height = Some(MAX_TEXTURE_SIDE);
    reader.limits(limits);
    let image = reader.decode().map_err(|source| TextureError::Decode {
        path: shown.clone(),
        source,
    })?;
    let rgb = image.to_rgb32f();
    Ok(Texture {
        path: shown,
        width: rgb.width(),
        height: rgb.height(),
        texels: rgb.pixels().map(|p| p.0).collect(),
    })
}
