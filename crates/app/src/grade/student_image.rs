//! Reading the image a student's program wrote (`{out}`) safely and within
//! a budget.
//!
//! The file lies in a folder the student's program could write, so the
//! grader never follows a link to it: the whole path is resolved with
//! `openat2(RESOLVE_NO_SYMLINKS)` (a link in any component fails), the
//! last component with `O_NOFOLLOW | O_NONBLOCK` (a FIFO cannot block),
//! and what was opened must be a regular file with one name, owned by the
//! owner of the folder it is in (the user the program ran as): a hard link
//! to a file of someone else's is refused, not read. Before any pixel is
//! allocated the file's size is checked against a byte budget and its
//! header's size against the scene's camera: an image larger than the
//! reference on either side is not decoded at all ([`Read::TooLarge`],
//! judged `size`), so neither the grader's memory nor the report's copy of
//! the image can grow past the camera's size.

use std::fs::File;
use std::io::{BufReader, Read as _, Seek};
use std::os::fd::{FromRawFd, OwnedFd};
use std::os::unix::ffi::OsStrExt;
use std::os::unix::fs::MetadataExt;
use std::path::Path;

use image::ImageReader;

use crate::compare::Picture;
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

/// Open `path` for reading without following a link anywhere on it.
pub fn open_no_links(path: &Path) -> std::io::Result<File> {
    let name = std::ffi::CString::new(path.as_os_str().as_bytes())
        .map_err(|_| std::io::Error::from(std::io::ErrorKind::InvalidInput))?;
    // SAFETY: `open_how` is plain integers, for which zero is valid.
    let mut how: libc::open_how = unsafe { std::mem::zeroed() };
    how.flags = (libc::O_RDONLY | libc::O_NOFOLLOW | libc::O_NONBLOCK | libc::O_CLOEXEC) as u64;
    how.resolve = libc::RESOLVE_NO_SYMLINKS | libc::RESOLVE_NO_MAGICLINKS;
    // SAFETY: `name` is a NUL-terminated string and `how` a valid
    // `open_how` of the size passed; the returned descriptor is ours.
    let fd = unsafe {
        libc::syscall(
            libc::SYS_openat2,
            libc::AT_FDCWD,
            name.as_ptr(),
            &how as *const libc::open_how,
            std::mem::size_of::<libc::open_how>(),
        )
    };
    if fd < 0 {
        return Err(std::io::Error::last_os_error());
    }
    // SAFETY: a descriptor just opened, owned by nothing else.
    Ok(File::from(unsafe { OwnedFd::from_raw_fd(fd as i32) }))
}

/// Read the image at `out`, compared with `reference`'s size.
pub fn read(out: &Path, reference: &Picture) -> Read {
    let bad = |reason: String| Read::Bad(reason);
    let folder_owner = match out.parent().map(open_no_links) {
        Some(Ok(folder)) => match folder.metadata() {
            Ok(m) => m.uid(),
            Err(error) => return bad(io_reason(&error)),
        },
        Some(Err(error)) if error.raw_os_error() == Some(libc::ENOENT) => return Read::Missing,
        Some(Err(error)) => {
            return bad(format!(
                "its folder cannot be opened: {}",
                io_reason(&error)
            ))
        }
        None => return Read::Missing,
    };
    let mut file = match open_no_links(out) {
        Ok(file) => file,
        Err(error) if error.raw_os_error() == Some(libc::ENOENT) => return Read::Missing,
        Err(error) if error.raw_os_error() == Some(libc::ELOOP) => {
            return bad("the image is a symbolic link, or is reached through one: not read".into())
        }
        Err(error) => return bad(format!("cannot open the image: {}", io_reason(&error))),
    };
    let meta = match file.metadata() {
        Ok(meta) => meta,
        Err(error) => return bad(io_reason(&error)),
    };
    if !meta.is_file() {
        return bad("the image is not a regular file: not read".into());
    }
    if meta.nlink() != 1 || meta.uid() != folder_owner {
        return bad(
            "the image is a link to a file the program did not write (another owner, or more than one name): not read"
                .into(),
        );
    }
    let pixels = u64::from(reference.width) * u64::from(reference.height);
    let budget = byte_budget(pixels);
    if meta.len() > budget {
        return bad(format!(
            "the image file has {} bytes, more than the {budget} a {} × {} image may take",
            meta.len(),
            reference.width,
            reference.height
        ));
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    if let Err(error) = (&mut file).take(budget + 1).read_to_end(&mut bytes) {
        return bad(io_reason(&error));
    }
    if bytes.len() as u64 > budget {
        return bad("the image file grew past its byte budget while it was read".into());
    }
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
