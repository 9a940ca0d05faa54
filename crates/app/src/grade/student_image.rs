//! Reading the image a student's program wrote (`{out}`) safely and within
//! a budget.
//!
//! The file lies in a folder the student's program could write, so its
//! bytes are read by the box's [`raytracer_box::output::read_output`]:
//! no link followed, a regular file of the program's own, within a byte
//! budget. Before any pixel is allocated the header's size is checked
//! against the scene's camera: an image larger than the
//! reference on either side is not decoded at all ([`Read::TooLarge`],
//! judged `size`), so neither the grader's memory nor the report's copy of
//! the image can grow past the camera's size.

use std::io::{BufReader, Seek};
use std::path::Path;

use image::ImageReader;

use crate::compare::Picture;
use raytracer_box::output::{read_output, Refused};
use raytracer_scene::diagnostic::io_reason;
use raytracer_scene::texture;

/// What reading the student's image gave.
pub enum Read {
    /// Decoded, at most the reference's size on each side.
    Picture(Picture),
    /// Its header gives a size larger than the reference's: not decoded.
    TooLarge { width: u32, height: u32 },
    /// No file at that path.
    Missing,
    /// Refused or not an image: the reason, for the report.
    Bad(String),
}

/// Bytes an image of `pixels` pixels may take on disk: a text PPM spends
/// at most 12 bytes a sample ("65535 " with room to spare), and any
/// header fits in a MiB.
fn byte_budget(pixels: u64) -> u64 {
    pixels * 3 * 12 + (1 << 20)
}

/// Read the image at `out`, compared with `reference`'s size.
pub fn read(out: &Path, reference: &Picture) -> Read {
    let pixels = u64::from(reference.width) * u64::from(reference.height);
    let budget = byte_budget(pixels);
    let bad = |reason: String| Read::Bad(reason);
    let bytes = match read_output(out, budget) {
        Ok(bytes) => bytes,
        Err(Refused::Missing) => return Read::Missing,
        Err(Refused::Folder(error)) => {
            return bad(format!(
                "its folder cannot be opened: {}",
                io_reason(&error)
            ))
        }
        Err(Refused::Link) => {
            return bad("the image is a symbolic link, or is reached through one: not read".into())
        }
        Err(Refused::NotRegular) => return bad("the image is not a regular file: not read".into()),
        Err(Refused::Foreign) => {
            return bad(
                "the image is a link to a file the program did not write (another owner, or more than one name): not read"
                    .into(),
            )
        }
        Err(Refused::TooLarge { bytes, budget }) => {
            return bad(format!(
                "the image file has {bytes} bytes, more than the {budget} a {} × {} image may take",
                reference.width, reference.height
            ))
        }
        Err(Refused::Grew) => {
            return bad("the image file grew past its byte budget while it was read".into())
        }
        Err(Refused::Io(error)) => return bad(format!("cannot read the image: {}", io_reason(&error))),
    };
    let header = ImageReader::new(std::io::Cursor::new(&bytes))
        .with_guessed_format()
        .map_err(image::ImageError::IoError)
        .and_then(|reader| reader.into_dimensions());
    let (width, height) = match header {
        Ok(size) => size,
        Err(error) => return bad(format!("not a PPM, PNG or JPEG image: {error}")),
    };
    if width > reference.width || height > reference.height {
        return Read::TooLarge { width, height };
    }
    let mut cursor = std::io::Cursor::new(&bytes);
    let _ = cursor.rewind();
    match texture::decode(BufReader::new(cursor), u64::from(width) * u64::from(height)) {
        Ok((width, height, texels)) => Read::Picture(Picture::from_texels(width, height, &texels)),
        Err(texture::DecodeError::Image(image::ImageError::IoError(error)))
            if error.kind() == std::io::ErrorKind::UnexpectedEof =>
        {
            bad(format!(
                "`{}` ends before its last texel",
                out.file_name().unwrap_or_default().to_string_lossy()
            ))
        }
        Err(error) => bad(format!("cannot decode the image: {error}")),
    }
}
