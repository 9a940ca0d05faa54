//! Texture images: a file's [`Header`] (what the check pass validates), the
//! decoded [`Texture`] (what the IR carries), and the two
//! [`TextureLoader`]s through which files reach the check pass:
//! [`HeaderReader`] reads only headers (`raytracer check`, the language
//! server), [`Decoder`] decodes each image in full and keeps it (`render`,
//! `convert`), from files or, for a caller without a file system (the
//! WebAssembly playground), from bytes in memory ([`Decoder::in_memory`]).
//!
//! Only a regular file is opened: the path's type is checked before opening
//! (a folder, a FIFO or a device is refused without touching it, so a FIFO
//! cannot block the check), and again on the opened file, which is opened
//! non-blocking so a path swapped for a FIFO in between cannot block either.
//!
//! Decoding goes through the `image` crate (PNM P1–P7 at any maxval, PNG
//! at any depth, JPEG; tests/textures.rs checks the texels of each). An
//! image without texels (a 0 × N header) and one whose data ends early are
//! refused with their own reasons. Only the header is read before the size is judged against
//! [`crate::limits`], so a hostile header (a 100000 × 100000 PPM) is refused
//! before any pixel is allocated; the decoders' own allocations are capped
//! by the crate's [`Limits`] as well.

use std::collections::HashMap;
use std::fs::File;
use std::io::{BufRead, BufReader, Cursor, Seek};
use std::path::Path;

use image::{DynamicImage, ImageDecoder, ImageFormat, ImageReader, Limits};
use serde::{Deserialize, Serialize};

use crate::failure::FileError;
use crate::limits::{MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE, MAX_TEXTURE_SIDE, MAX_TEXTURE_TEXELS};

/// What a texture file's header says: enough to validate it without
/// reading a texel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Header {
    /// The resolved path it was read from, for messages.
    pub path: String,
    /// What the file is (whatever its name says).
    pub format: TextureFormat,
    pub width: u32,
    pub height: u32,
}

/// How texture files reach the check pass, which does no I/O of its own:
/// the caller passes one ([`crate::check::SceneCheck::with_sink`]).
pub trait TextureLoader {
    /// The header of the image at `path`, refusing one of more than
    /// `max_texels` texels (or beyond [`MAX_TEXTURE_TEXELS`]); a loader
    /// that decodes does so only after the header passed.
    fn load(&mut self, path: &Path, max_texels: u64) -> Result<Header, TextureError>;

    /// The names of the entries of `folder` (at most a few thousand), for
    /// the "did you mean" of a texture that is not found; none for a
    /// loader without a file system to look in.
    fn entries(&mut self, folder: &Path) -> Vec<String> {
        let _ = folder;
        Vec::new()
    }
}

/// The names in `folder`, at most 4096, for [`TextureLoader::entries`].
pub fn folder_entries(folder: &Path) -> Vec<String> {
    // A scene named without a folder is in the working one.
    let folder = if folder.as_os_str().is_empty() {
        Path::new(".")
    } else {
        folder
    };
    std::fs::read_dir(folder)
        .map(|entries| {
            entries
                .filter_map(Result::ok)
                .take(4096)
                .filter_map(|e| e.file_name().into_string().ok())
                .collect()
        })
        .unwrap_or_default()
}

/// Reads headers only: validating a scene costs a few bytes per texture,
/// whatever its size.
#[derive(Debug, Default)]
pub struct HeaderReader;

impl TextureLoader for HeaderReader {
    fn load(&mut self, path: &Path, max_texels: u64) -> Result<Header, TextureError> {
        let header = read_header(path)?;
        if !fits(header.width, header.height, max_texels) {
            return Err(TextureError::TooLarge {
                path: header.path,
                width: header.width,
                height: header.height,
            });
        }
        Ok(header)
    }

    fn entries(&mut self, folder: &Path) -> Vec<String> {
        folder_entries(folder)
    }
}

/// Decodes each image in full ([`load`]) and keeps it, keyed by the path
/// it was loaded from, for [`Decoder::take`] once the check is done.
#[derive(Debug, Default)]
pub struct Decoder {
    decoded: HashMap<String, Texture>,
    /// The files of [`Decoder::in_memory`], by name; `None` reads the
    /// file system.
    files: Option<HashMap<String, Vec<u8>>>,
}

impl TextureLoader for Decoder {
    fn load(&mut self, path: &Path, max_texels: u64) -> Result<Header, TextureError> {
        let texture = match &self.files {
            None => load(path, max_texels)?,
            Some(files) => load_in_memory(files, path, max_texels)?,
        };
        let header = texture.header();
        self.decoded.insert(header.path.clone(), texture);
        Ok(header)
    }

    fn entries(&mut self, folder: &Path) -> Vec<String> {
        folder_entries(folder)
    }
}

impl Decoder {
    /// A decoder that reads no file: a texture path names one of `files`
    /// by the whole path or, failing that, by its last component (so a
    /// scene written for `textures/wood.ppm` finds a `wood.ppm` given on
    /// its own). A path that names none fails as a missing file does.
    pub fn in_memory(files: HashMap<String, Vec<u8>>) -> Decoder {
        Decoder {
            decoded: HashMap::new(),
            files: Some(files),
        }
    }

    /// The texture decoded from the file `header` describes.
    pub fn take(&mut self, header: &Header) -> Option<Texture> {
        self.decoded.remove(&header.path)
    }
}

/// [`load`] from `files` (see [`Decoder::in_memory`]) instead of the file
/// system.
fn load_in_memory(
    files: &HashMap<String, Vec<u8>>,
    path: &Path,
    max_texels: u64,
) -> Result<Texture, TextureError> {
    let shown = path.display().to_string();
    let bytes = files
        .get(&shown)
        .or_else(|| {
            let name = path.file_name()?.to_str()?;
            files.get(name)
        })
        .ok_or_else(|| {
            TextureError::Io(FileError::with_reason(
                "read",
                path,
                "no file of this name was given".to_string(),
            ))
        })?;
    decoded_texture(shown, Cursor::new(bytes), max_texels)
}

/// A decoded image, row 0 at the top, channels scaled to [0, 1].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Texture {
    /// The resolved path it was loaded from, for messages.
    pub path: String,
    /// What the file decoded as (whatever its name says).
    pub format: TextureFormat,
    pub width: u32,
    pub height: u32,
    /// `width × height` texels, row-major.
    pub texels: Vec<[f32; 3]>,
}

impl Texture {
    /// Its header, without the texels.
    pub fn header(&self) -> Header {
        Header {
            path: self.path.clone(),
            format: self.format,
            width: self.width,
            height: self.height,
        }
    }
}

/// The file formats a texture decodes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TextureFormat {
    /// PPM, P3 or P6.
    Ppm,
    Png,
    Jpeg,
}

/// The most bytes a decoder may allocate for one texture: the largest
/// accepted texture at 16-bit RGBA, with room for the decoder's own buffers.
const MAX_DECODER_BYTES: u64 = MAX_TEXTURE_TEXELS * 8 * 2;

/// Why a texture could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum TextureError {
    #[error(transparent)]
    Io(FileError),
    #[error("`{path}` is not a regular file")]
    NotAFile { path: String },
    #[error("`{path}` does not decode as an image: {source}")]
    Decode {
        path: String,
        source: image::ImageError,
    },
    #[error("`{path}` is {width} × {height} texels, too large to read")]
    TooLarge {
        path: String,
        width: u32,
        height: u32,
    },
    #[error("`{path}` ends before its last texel")]
    Truncated { path: String },
    #[error("`{path}` is {width} × {height} texels, and a texture needs at least one")]
    Empty {
        path: String,
        width: u32,
        height: u32,
    },
}

/// Why image bytes did not decode ([`decode`]).
#[derive(Debug, thiserror::Error)]
pub enum DecodeError {
    #[error(transparent)]
    Image(#[from] image::ImageError),
    #[error("{width} × {height} texels is too large")]
    TooLarge { width: u32, height: u32 },
    /// The header gives a width or height of 0.
    #[error("{width} × {height} texels: an image has at least one")]
    Empty { width: u32, height: u32 },
}

/// Load and decode the image at `path`, refusing more than `max_texels`
/// (at most [`MAX_TEXTURE_TEXELS`]) before decoding its pixels.
pub fn load(path: &Path, max_texels: u64) -> Result<Texture, TextureError> {
    let (shown, file) = open(path)?;
    decoded_texture(shown, BufReader::new(file), max_texels)
}

/// The texture `shown` decoded from `reader`, refusing more than
/// `max_texels` before decoding its pixels.
fn decoded_texture(
    shown: String,
    reader: impl BufRead + Seek,
    max_texels: u64,
) -> Result<Texture, TextureError> {
    let decoded = decode_image(reader, max_texels).map_err(|error| texture_error(&shown, error))?;
    Ok(Texture {
        path: shown,
        format: decoded.format,
        width: decoded.width,
        height: decoded.height,
        texels: decoded.texels,
    })
}

/// A whole image decoded to 8-bit RGB, row 0 at the top: what `compare`
/// reads, up to the largest image `render` writes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    pub format: TextureFormat,
    pub width: u32,
    pub height: u32,
    /// `width × height × 3` bytes, row-major.
    pub rgb: Vec<u8>,
}

/// Load and decode the image at `path` as 8-bit RGB (16-bit samples and
/// PPM maxvals other than 255 rounded to the nearest of 0–255, as
/// `round(v · 255)` of the texture's texels), refusing an image larger than
/// [`MAX_IMAGE_SIDE`] on a side before decoding its pixels. Unlike [`load`],
/// it accepts every image `render` can write, and keeps a byte a channel.
pub fn load_image(path: &Path) -> Result<Image, TextureError> {
    let (shown, file) = open(path)?;
    let reader = BufReader::new(file);
    let (format, decoder, width, height) = sized_decoder(
        reader,
        MAX_IMAGE_SIDE,
        MAX_IMAGE_PIXELS,
        MAX_IMAGE_PIXELS * 8 * 2,
    )
    .map_err(|error| texture_error(&shown, error))?;
    let rgb = DynamicImage::from_decoder(decoder)
        .map_err(|error| texture_error(&shown, error.into()))?
        .into_rgb8()
        .into_raw();
    Ok(Image {
        format,
        width,
        height,
        rgb,
    })
}

/// Read the header of the image at `path`: its format and size, and no
/// texel.
pub fn read_header(path: &Path) -> Result<Header, TextureError> {
    let (shown, file) = open(path)?;
    let (format, width, height) =
        read_dimensions(BufReader::new(file)).map_err(|error| texture_error(&shown, error))?;
    Ok(Header {
        path: shown,
        format,
        width,
        height,
    })
}

/// The path as messages show it, and the file opened for reading if it is
/// a regular file.
fn open(path: &Path) -> Result<(String, File), TextureError> {
    let shown = path.display().to_string();
    let io = |error| TextureError::Io(FileError::new("read", path, &error));
    if !std::fs::metadata(path).map_err(io)?.is_file() {
        return Err(TextureError::NotAFile { path: shown });
    }
    let file = open_nonblocking(path).map_err(io)?;
    if !file.metadata().map_err(io)?.is_file() {
        return Err(TextureError::NotAFile { path: shown });
    }
    Ok((shown, file))
}

/// A decoding error of the file shown as `shown`, as a [`TextureError`].
fn texture_error(shown: &str, error: DecodeError) -> TextureError {
    let shown = shown.to_string();
    match error {
        DecodeError::Image(image::ImageError::IoError(source))
            if source.kind() == std::io::ErrorKind::UnexpectedEof =>
        {
            TextureError::Truncated { path: shown }
        }
        DecodeError::Image(image::ImageError::IoError(source)) => {
            TextureError::Io(FileError::new("read", Path::new(&shown), &source))
        }
        DecodeError::Image(source) => TextureError::Decode {
            path: shown,
            source,
        },
        DecodeError::TooLarge { width, height } => TextureError::TooLarge {
            path: shown,
            width,
            height,
        },
        DecodeError::Empty { width, height } => TextureError::Empty {
            path: shown,
            width,
            height,
        },
    }
}

/// An image decoded by [`decode_image`].
struct Decoded {
    format: TextureFormat,
    width: u32,
    height: u32,
    texels: Vec<[f32; 3]>,
}

/// Decode image bytes to RGB texels in [0, 1], row 0 at the top:
/// `(width, height, texels)`, `width × height` texels, at least one. The size is judged from the header against the side limit
/// and `max_texels` (at most [`MAX_TEXTURE_TEXELS`]), before any pixel is
/// allocated. Every bit depth decodes to the same scale (16-bit samples
/// and PPM maxvals other than 255 are divided by their maximum); gray is
/// spread to the three channels, and alpha is dropped.
pub fn decode(
    reader: impl BufRead + Seek,
    max_texels: u64,
) -> Result<(u32, u32, Vec<[f32; 3]>), DecodeError> {
    decode_image(reader, max_texels).map(|d| (d.width, d.height, d.texels))
}

/// The format and size an image's header gives, read without decoding
/// any texel.
fn read_dimensions(reader: impl BufRead + Seek) -> Result<(TextureFormat, u32, u32), DecodeError> {
    let (format, reader) = recognise(reader)?;
    let (width, height) = reader.into_dimensions()?;
    if width == 0 || height == 0 {
        return Err(DecodeError::Empty { width, height });
    }
    Ok((format, width, height))
}

/// A reader for the image format the bytes begin with.
fn recognise<R: BufRead + Seek>(reader: R) -> Result<(TextureFormat, ImageReader<R>), DecodeError> {
    let reader = ImageReader::new(reader)
        .with_guessed_format()
        .map_err(image::ImageError::IoError)?;
    let format = match reader.format() {
        Some(ImageFormat::Png) => TextureFormat::Png,
        Some(ImageFormat::Jpeg) => TextureFormat::Jpeg,
        _ => TextureFormat::Ppm,
    };
    Ok((format, reader))
}

/// [`decode`], with the format the bytes were recognised as.
fn decode_image(reader: impl BufRead + Seek, max_texels: u64) -> Result<Decoded, DecodeError> {
    let max_texels = max_texels.min(MAX_TEXTURE_TEXELS);
    let (format, decoder, width, height) =
        sized_decoder(reader, MAX_TEXTURE_SIDE, max_texels, MAX_DECODER_BYTES)?;
    let rgb = DynamicImage::from_decoder(decoder)?.into_rgb32f();
    Ok(Decoded {
        format,
        width,
        height,
        texels: rgb.pixels().map(|p| p.0).collect(),
    })
}

/// The decoder for `reader` with its format and size, once the header
/// shows at least one pixel, at most `max_side` on a side and `max_pixels`
/// in all; the decoder may allocate at most `max_alloc` bytes.
fn sized_decoder<'a, R: BufRead + Seek + 'a>(
    reader: R,
    max_side: u32,
    max_pixels: u64,
    max_alloc: u64,
) -> Result<(TextureFormat, impl ImageDecoder + 'a, u32, u32), DecodeError> {
    let (format, mut reader) = recognise(reader)?;
    let mut limits = Limits::default();
    limits.max_alloc = Some(max_alloc);
    reader.limits(limits);
    let decoder = reader.into_decoder()?;
    let (width, height) = decoder.dimensions();
    if width == 0 || height == 0 {
        return Err(DecodeError::Empty { width, height });
    }
    if width > max_side || height > max_side || u64::from(width) * u64::from(height) > max_pixels {
        return Err(DecodeError::TooLarge { width, height });
    }
    Ok((format, decoder, width, height))
}

/// True when a `width × height` texture is within the side limit and has
/// at most `max_texels` (and [`MAX_TEXTURE_TEXELS`]) texels.
pub fn fits(width: u32, height: u32, max_texels: u64) -> bool {
    width <= MAX_TEXTURE_SIDE
        && height <= MAX_TEXTURE_SIDE
        && u64::from(width) * u64::from(height) <= max_texels.min(MAX_TEXTURE_TEXELS)
}

/// Open for reading without blocking on a FIFO (reads from a regular file
/// are unaffected by the flag).
fn open_nonblocking(path: &Path) -> std::io::Result<File> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    options.open(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_huge_header_is_refused_before_decoding() {
        let header = b"P6\n100000 100000\n255\n\x01\x02\x03";
        match decode(Cursor::new(&header[..]), MAX_TEXTURE_TEXELS) {
            Err(DecodeError::TooLarge { width, height }) => {
                assert_eq!((width, height), (100_000, 100_000))
            }
            other => panic!("expected too large, found {other:?}"),
        }
    }

    #[test]
    fn sides_and_area_are_both_limited() {
        let max = MAX_TEXTURE_TEXELS;
        assert!(fits(4096, 4096, max));
        assert!(fits(16384, 1024, max));
        assert!(!fits(16385, 1, max));
        assert!(!fits(8192, 4096, max));
        assert!(!fits(2, 2, 3));
    }

    #[test]
    fn an_image_is_limited_by_the_largest_render_not_by_textures() {
        assert_eq!(MAX_IMAGE_SIDE, 16384);
        assert!(!fits(4097, 4097, MAX_TEXTURE_TEXELS));
        let dir = std::env::temp_dir().join(format!("raytracer-image-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("wide.ppm");
        std::fs::write(&path, b"P6\n1 1\n65535\n\x80\x00\xff\xff\x00\x00").unwrap();
        let image = load_image(&path).unwrap();
        assert_eq!(
            (image.width, image.height, image.rgb),
            (1, 1, vec![128, 255, 0])
        );
        std::fs::write(&path, b"P6\n16385 1\n255\n").unwrap();
        assert!(matches!(
            load_image(&path),
            Err(TextureError::TooLarge { .. })
        ));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_small_p3_decodes_with_row_zero_on_top() {
        let ppm = b"P3\n1 2\n255\n255 0 0\n0 0 255\n";
        let (width, height, texels) = decode(Cursor::new(&ppm[..]), 2).unwrap();
        assert_eq!((width, height), (1, 2));
        assert_eq!(texels, vec![[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]);
    }

    #[test]
    fn an_in_memory_decoder_finds_a_file_by_path_or_by_name() {
        let ppm = b"P3\n1 1\n255\n0 255 0\n".to_vec();
        let mut decoder = Decoder::in_memory(HashMap::from([("wood.ppm".to_string(), ppm)]));
        for path in ["wood.ppm", "textures/wood.ppm"] {
            let header = decoder.load(Path::new(path), 4).unwrap();
            assert_eq!((header.width, header.height), (1, 1), "{path}");
            assert_eq!(decoder.take(&header).unwrap().texels, vec![[0.0, 1.0, 0.0]]);
        }
        assert!(matches!(
            decoder.load(Path::new("stone.ppm"), 4),
            Err(TextureError::Io(_))
        ));
    }
}
