//! Reading a scene's bytes from a file or stdin, bounded by
//! [`MAX_SCENE_BYTES`] so an endless input cannot exhaust memory.

use std::io::Read;
use std::path::Path;

use miette::Diagnostic;

use crate::diagnostic::FileError;
use crate::limits::MAX_SCENE_BYTES;

/// The scene file could not be read.
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum ReadSceneError {
    /// Opening or reading failed.
    #[error(transparent)]
    #[diagnostic(code(io::read_scene))]
    Io(FileError),
    /// The file is larger than [`MAX_SCENE_BYTES`]; only that much was read.
    #[error("cannot read scene `{path}`: expected at most {limit} bytes, found more")]
    #[diagnostic(
        code(io::scene_too_large),
        help("a scene at the object limit takes about 120 MiB; is this the scene file?")
    )]
    TooLarge { path: String, limit: u64 },
}

/// The bytes of the scene at `path` (`-` is stdin), refusing a file larger
/// than [`MAX_SCENE_BYTES`] after reading one byte more than that, so an
/// endless input (`/dev/zero`, a pipe) cannot exhaust memory.
pub fn read_scene(path: &Path) -> Result<Vec<u8>, ReadSceneError> {
    let read_error = |error| ReadSceneError::Io(FileError::new("read scene", path, &error));
    // A file's buffer is allocated at its size, so the text is read into
    // exactly the memory it keeps (no doubling while it grows).
    let (input, size): (Box<dyn Read>, u64) = if path == Path::new("-") {
        (Box::new(std::io::stdin().lock()), 0)
    } else {
        let file = std::fs::File::open(path).map_err(read_error)?;
        let size = file.metadata().map_or(0, |m| m.len());
        (Box::new(file), size)
    };
    let mut bytes = Vec::with_capacity(usize::try_from(size.min(MAX_SCENE_BYTES)).unwrap_or(0));
    input
        .take(MAX_SCENE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(read_error)?;
    if bytes.len() as u64 > MAX_SCENE_BYTES {
        return Err(ReadSceneError::TooLarge {
            path: path.display().to_string(),
            limit: MAX_SCENE_BYTES,
        });
    }
    Ok(bytes)
}
