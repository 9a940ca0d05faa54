//! Writing rendered images: the format from OUT's extension, and the file
//! whole or not at all.
//!
//! `.ppm` is binary P6 and `.png` is PNG; any other extension is refused
//! before rendering starts ([`Format::from_path`]), and so is an OUT that
//! is a folder, is in a folder where no file can be created
//! ([`check_writable`]), or is one of the scene's inputs ([`check_not_input`]).
//! The image is encoded into a temporary file beside OUT, flushed to disk
//! and renamed over OUT, so a failure at any point leaves no partial or
//! truncated OUT (the temporary file is removed when it is dropped).
//!
//! Every temporary file being written is listed, so a Ctrl-C handler can
//! call [`abandon`]: it removes them and stops any rename from happening
//! afterwards, and the process can exit leaving nothing half-written.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

use image::codecs::png::PngEncoder;
use image::codecs::pnm::{PnmEncoder, PnmSubtype, SampleEncoding};
use image::{ExtendedColorType, ImageEncoder};
use miette::Diagnostic;

use crate::render::Image;
use raytracer_scene::diagnostic::FileError;

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

    /// OUT is the scene file or a texture it uses.
    #[error("the output `{path}` is an input of the render: `{input}`")]
    #[diagnostic(
        code(io::output_is_input),
        help("name another output file; the inputs are never overwritten")
    )]
    OutputIsInput { path: String, input: String },

    /// OUT names an existing folder.
    #[error("the output `{path}` is a folder")]
    #[diagnostic(
        code(io::output_is_folder),
        help("name a file, such as `{path}/out.png`")
    )]
    OutputIsFolder { path: String },

    /// Creating, writing or renaming the file failed.
    #[error(transparent)]
    #[diagnostic(
        code(io::write_image),
        help("no image was written; check that the folder exists and is writable")
    )]
    Write(FileError),
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

/// Refuse an OUT that is one of `inputs` (the scene file, a texture),
/// through any symbolic link or relative path (checked before rendering, so
/// the mistake costs nothing).
pub fn check_not_input<'a>(
    out: &Path,
    inputs: impl IntoIterator<Item = &'a Path>,
) -> Result<(), OutputError> {
    let Ok(out_resolved) = out.canonicalize() else {
        // OUT does not exist yet, so it is no input.
        return Ok(());
    };
    for input in inputs {
        if input.canonicalize().is_ok_and(|i| i == out_resolved) {
            return Err(OutputError::OutputIsInput {
                path: out.display().to_string(),
                input: input.display().to_string(),
            });
        }
    }
    Ok(())
}

/// Refuse an OUT that is a folder or whose folder is missing or not
/// writable, by creating (and removing) a temporary file beside it: checked
/// before rendering, so the render is not wasted.
pub fn check_writable(out: &Path) -> Result<(), OutputError> {
    if out.is_dir() {
        return Err(OutputError::OutputIsFolder {
            path: out.display().to_string(),
        });
    }
    temp_builder()
        .tempfile_in(folder_of(out))
        .map(drop)
        .map_err(FileError::writing(out))
        .map_err(OutputError::Write)
}

/// Encode `image` as `format` and put it at `path` atomically.
pub fn write(image: &Image, format: Format, path: &Path) -> Result<(), OutputError> {
    write_with(path, |out| encode(image, format, out))
}

/// Put the bytes `encode` writes at `path` atomically, as an image: a
/// failure is an [`OutputError::Write`] naming `path`.
pub fn write_with(
    path: &Path,
    encode: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), OutputError> {
    write_atomically(path, encode)
        .map_err(FileError::writing(path))
        .map_err(OutputError::Write)
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
    let mut temp = {
        // Created and listed under the lock, so `abandon` sees every file.
        let mut pending = pending()?;
        let temp = temp_builder().tempfile_in(folder_of(path))?;
        pending.push(temp.path().to_path_buf());
        temp
    };
    let listed = Listed(temp.path().to_path_buf());
    {
        let mut writer = BufWriter::new(temp.as_file_mut());
        body(&mut writer)?;
        writer.flush()?;
    }
    if let Some(permissions) = existing {
        temp.as_file().set_permissions(permissions)?;
    }
    temp.as_file().sync_all()?;
    // Renamed under the lock, so it happens before `abandon` or never.
    let _pending = pending()?;
    temp.persist(path).map_err(|e| e.error)?;
    drop(_pending);
    drop(listed);
    Ok(())
}

/// Temporary files being written: what [`abandon`] removes.
static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Set by [`abandon`]: no temporary file is created or renamed after it.
static ABANDONED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// The list of temporary files, locked; an error once [`abandon`] ran.
fn pending() -> std::io::Result<MutexGuard<'static, Vec<PathBuf>>> {
    let list = PENDING.lock().unwrap_or_else(PoisonError::into_inner);
    if ABANDONED.load(std::sync::atomic::Ordering::SeqCst) {
        return Err(std::io::Error::new(
            std::io::ErrorKind::Interrupted,
            "interrupted",
        ));
    }
    Ok(list)
}

/// Removes its path from [`PENDING`] when the write is over, either way.
struct Listed(PathBuf);

impl Drop for Listed {
    fn drop(&mut self) {
        let mut list = PENDING.lock().unwrap_or_else(PoisonError::into_inner);
        list.retain(|p| *p != self.0);
    }
}

/// Remove every temporary file being written and make every write still
/// running fail instead of renaming: what a Ctrl-C handler calls before
/// the process exits. Returns how many files it removed.
pub fn abandon() -> usize {
    let mut list = PENDING.lock().unwrap_or_else(PoisonError::into_inner);
    ABANDONED.store(true, std::sync::atomic::Ordering::SeqCst);
    list.drain(..)
        .filter(|p| std::fs::remove_file(p).is_ok())
        .count()
}

/// Temporary files named `.raytracer-XXXXXX.tmp`, created `0666` less the
/// umask (as a plain new file would be).
fn temp_builder() -> tempfile::Builder<'static, 'static> {
    let mut builder = tempfile::Builder::new();
    builder.prefix(".raytracer-").suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    builder
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
    raytracer_scene::folder::folder_of(path).to_path_buf()
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
