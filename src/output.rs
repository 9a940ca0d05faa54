//! Writing rendered images: the format from OUT's extension, and the file
//! whole or not at all.
//!
//! `.ppm` is binary P6 and `.png` is PNG; any other extension is refused
//! before rendering starts ([`Format::from_path`]). The image is encoded
//! into a temporary file beside OUT, flushed to disk and renamed over OUT,
//! so a failure at any point leaves no partial or truncated OUT (the
//! temporary file is removed when it is dropped). OUT may not be the scene
//! file itself.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use image::codecs::png::PngEncoder;
use image::codecs::pnm::{PnmEncoder, PnmSubtype, SampleEncoding};
use image::{ExtendedColorType, ImageEncoder};
use miette::Diagnostic;

use crate::render::Image;

/// An image file format the renderer writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Binary PPM (P6, maxval 255).
    Ppm,
    Png,
}

/// Why an image could not be written.
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum OutputError {
    /// OUT's extension names no format the renderer writes.
    #[error("cannot tell the image format of `{path}`")]
    #[diagnostic(
        code(io::output_format),
        help("end the output name in `.ppm` (binary P6) or `.png`")
    )]
    UnknownFormat { path: String },

    /// OUT is the scene file being rendered.
    #[error("the output `{path}` is the scene file itself")]
    #[diagnostic(code(io::output_is_scene), help("name another output file"))]
    OutputIsScene { path: String },

    /// Creating, writing or renaming the file failed.
    #[error("cannot write `{path}`: {source}")]
    #[diagnostic(
        code(io::write_image),
        help("no image was written; check that the folder exists and is writable")
    )]
    Write {
        path: String,
        #[source]
        source: std::io::Error,
    },
}

impl Format {
    /// The format OUT's extension asks for (case-insensitive).
    pub fn from_path(path: &Path) -> Result<Format, OutputError> {
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match extension.as_deref() {
            Some("ppm") => Ok(Format::Ppm),
            Some("png") => Ok(Format::Png),
            _ => Err(OutputError::UnknownFormat {
                path: path.display().to_string(),
            }),
        }
    }
}

/// Refuse an OUT that is the scene file (checked before rendering, so the
/// mistake costs nothing).
pub fn check_not_scene(out: &Path, scene: &Path) -> Result<(), OutputError> {
    let same = match (out.canonicalize(), scene.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if same {
        return Err(OutputError::OutputIsScene {
            path: out.display().to_string(),
        });
    }
    Ok(())
}

/// Encode `image` as `format` and put it at `path` atomically.
pub fn write(image: &Image, format: Format, path: &Path) -> Result<(), OutputError> {
    write_atomically(path, |out| encode(image, format, out)).map_err(|source| OutputError::Write {
        path: path.display().to_string(),
        source,
    })
}

/// Put what `body` writes at `path`, whole or not at all: it goes to a
/// temporary file in the same folder, which is flushed to disk and renamed
/// over `path`. A file replaced keeps its permissions; a new one gets the
/// usual `0666` less the umask. On any error `path` is untouched and the
/// temporary file is removed.
pub fn write_atomically(
    path: &Path,
    body: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let existing = std::fs::metadata(path).ok().map(|m| m.permissions());
    let mut builder = tempfile::Builder::new();
    builder.prefix(".raytracer-").suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut temp = builder.tempfile_in(folder_of(path))?;
    {
        let mut writer = BufWriter::new(temp.as_file_mut());
        body(&mut writer)?;
        writer.flush()?;
    }
    if let Some(permissions) = existing {
        temp.as_file().set_permissions(permissions)?;
    }
    temp.as_file().sync_all()?;
    temp.persist(path).map_err(|e| e.error)?;
    Ok(())
}

/// The encoded bytes of `image`.
pub fn encode(image: &Image, format: Format, out: &mut dyn Write) -> std::io::Result<()> {
    let (w, h) = (image.size, image.size);
    let result = match format {
        Format::Ppm => PnmEncoder::new(out)
            .with_subtype(PnmSubtype::Pixmap(SampleEncoding::Binary))
            .write_image(&image.rgb, w, h, ExtendedColorType::Rgb8),
        Format::Png => PngEncoder::new(out).write_image(&image.rgb, w, h, ExtendedColorType::Rgb8),
    };
    result.map_err(|e| match e {
        image::ImageError::IoError(io) => io,
        other => std::io::Error::other(other),
    })
}

/// The folder a file is in (`.` for a bare name).
fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_by_extension() {
        assert_eq!(Format::from_path(Path::new("a.PPM")).unwrap(), Format::Ppm);
        assert_eq!(
            Format::from_path(Path::new("d/a.png")).unwrap(),
            Format::Png
        );
        assert!(Format::from_path(Path::new("a.bmp")).is_err());
        assert!(Format::from_path(Path::new("ppm")).is_err());
    }

    #[test]
    fn ppm_is_binary_p6() {
        let image = Image {
            size: 1,
            rgb: vec![1, 2, 3],
        };
        let mut bytes = Vec::new();
        encode(&image, Format::Ppm, &mut bytes).unwrap();
        assert_eq!(bytes, b"P6\n1 1 255\n\x01\x02\x03");
    }
}
