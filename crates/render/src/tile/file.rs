//! Tile files: 8-bit RGB PNG images whose `iTXt` chunk named
//! [`super::KEYWORD`] holds their [`TileInfo`] as JSON.
//!
//! The chunk is written before the image data, so reading a tile's
//! metadata ([`read_info`]) decodes no pixels: `stitch` judges every part
//! before it reads any image. The decoder's allocations are capped at the
//! largest frame the scene language allows.

use std::fs::File;
use std::io::{BufReader, Write};
use std::path::Path;

use miette::Diagnostic;

use super::{TileInfo, KEYWORD};
use raytracer_scene::diagnostic::FileError;

/// The largest frame's side: the camera's limit, from its row in the
/// registry. A tile claiming a larger frame is refused before any pixel is
/// allocated.
const MAX_SIDE: u64 = raytracer_scene::language::CAMERA.max_whole() as u64;

/// Why a file is not a tile that can be read.
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum ReadTileError {
    /// The file cannot be opened or read (exit 2).
    #[error(transparent)]
    #[diagnostic(code(io::read_tile))]
    Io(FileError),

    /// The file is readable but no tile of this renderer (exit 1).
    #[error("`{path}` is not a tile: {reason}")]
    #[diagnostic(
        code(stitch::not_a_tile),
        help("parts are the PNG files that `raytracer render SCENE PART.png --tile K/N` writes")
    )]
    NotATile { path: String, reason: String },
}

impl ReadTileError {
    /// True when the file could not be read at all (an I/O failure, exit
    /// 2), false when it was read and is no tile (exit 1).
    pub fn is_io(&self) -> bool {
        matches!(self, ReadTileError::Io(_))
    }
}

/// Write `rgb` (the pixels of `info.region`, 3 bytes each, top row first)
/// to `out` as a tile PNG.
pub fn encode(info: &TileInfo, rgb: &[u8], out: &mut dyn Write) -> std::io::Result<()> {
    let json = serde_json::to_string(info).map_err(std::io::Error::other)?;
    let mut encoder = png::Encoder::new(out, info.region.width, info.region.height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder
        .add_itxt_chunk(KEYWORD.to_string(), json)
        .map_err(std::io::Error::other)?;
    let mut writer = encoder.write_header().map_err(std::io::Error::other)?;
    writer
        .write_image_data(rgb)
        .map_err(std::io::Error::other)?;
    writer.finish().map_err(std::io::Error::other)
}

/// A PNG decoder for `path`, its header and text chunks read.
fn open(path: &Path) -> Result<png::Reader<BufReader<File>>, ReadTileError> {
    let file = File::open(path).map_err(|e| ReadTileError::Io(FileError::new("read", path, &e)))?;
    let mut decoder = png::Decoder::new(BufReader::new(file));
    decoder.set_limits(png::Limits {
        bytes: (MAX_SIDE * MAX_SIDE * 3 + (1 << 20)) as usize,
    });
    decoder.read_info().map_err(|e| match e {
        png::DecodingError::IoError(e) if e.kind() != std::io::ErrorKind::UnexpectedEof => {
            ReadTileError::Io(FileError::new("read", path, &e))
        }
        other => ReadTileError::NotATile {
            path: path.display().to_string(),
            reason: format!("expected a PNG image, found a file it cannot decode ({other})"),
        },
    })
}

/// The [`TileInfo`] of the tile at `path`, read without decoding pixels.
pub fn read_info(path: &Path) -> Result<TileInfo, ReadTileError> {
    let reader = open(path)?;
    info_of(path, &reader)
}

fn info_of(path: &Path, reader: &png::Reader<BufReader<File>>) -> Result<TileInfo, ReadTileError> {
    let not_a_tile = |reason: String| ReadTileError::NotATile {
        path: path.display().to_string(),
        reason,
    };
    let chunk = reader
        .info()
        .utf8_text
        .iter()
        .find(|chunk| chunk.keyword == KEYWORD)
        .ok_or_else(|| not_a_tile(format!("expected a `{KEYWORD}` text chunk, found none")))?;
    let text = chunk
        .get_text()
        .map_err(|e| not_a_tile(format!("its `{KEYWORD}` chunk cannot be read: {e}")))?;
    let info: TileInfo = serde_json::from_str(&text)
        .map_err(|e| not_a_tile(format!("its `{KEYWORD}` chunk is not tile metadata: {e}")))?;
    if info.version != super::FORMAT_VERSION {
        return Err(not_a_tile(format!(
            "expected tile format version {}, found {}",
            super::FORMAT_VERSION,
            info.version
        )));
    }
    let side = u64::from(info.width);
    if info.width != info.height || !(1..=MAX_SIDE).contains(&side) {
        return Err(not_a_tile(format!(
            "expected a square frame of 1 to {MAX_SIDE} pixels a side, found {}×{}",
            info.width, info.height
        )));
    }
    Ok(info)
}

/// Decode the pixels of the tile at `path` into `rows` (its region's
/// pixels, 3 bytes each, top row first), checking that the image is what
/// its metadata `expected` says: the same metadata, 8-bit RGB, the region's
/// size.
pub fn read_pixels(path: &Path, expected: &TileInfo, rows: &mut [u8]) -> Result<(), ReadTileError> {
    let mut reader = open(path)?;
    let not_a_tile = |reason: String| ReadTileError::NotATile {
        path: path.display().to_string(),
        reason,
    };
    if info_of(path, &reader)? != *expected {
        return Err(not_a_tile(
            "its metadata changed while the parts were read".to_string(),
        ));
    }
    let header = reader.info();
    let (width, height) = (header.width, header.height);
    let (color, depth) = (header.color_type, header.bit_depth);
    let region = expected.region;
    if (color, depth) != (png::ColorType::Rgb, png::BitDepth::Eight) {
        return Err(not_a_tile(format!(
            "expected 8-bit RGB pixels, found {color:?} at {} bits",
            depth as u8
        )));
    }
    if (width, height) != (region.width, region.height) {
        return Err(not_a_tile(format!(
            "expected {}×{} pixels (its region), found {width}×{height}",
            region.width, region.height
        )));
    }
    reader.next_frame(rows).map(drop).map_err(|e| match e {
        png::DecodingError::IoError(e) if e.kind() != std::io::ErrorKind::UnexpectedEof => {
            ReadTileError::Io(FileError::new("read", path, &e))
        }
        other => not_a_tile(format!("its pixels cannot be decoded ({other})")),
    })
}
