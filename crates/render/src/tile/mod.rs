//! Tiles: one frame rendered as separate parts on separate machines, then
//! stitched together (`render --tile K/N`, `stitch`; docs/distributed.md).
//!
//! The frame is cut into `N` horizontal bands of whole rows, as evenly as
//! the row count allows: band `K` (counted from 1) holds rows
//! `[⌊(K−1)·H/N⌋, ⌊K·H/N⌋)` of a frame `H` rows high, so bands differ by at
//! most one row and every row is in exactly one band. A band is rendered by
//! the same row loop as the whole frame ([`crate::render::render_rows`]), and
//! every pixel depends only on the scene, the options and its own position,
//! so a band's pixels are those of the whole render, byte for byte.
//!
//! A tile records where it belongs in a [`TileInfo`]: the full frame's size,
//! its region, `K` and `N`, and two hashes that tell whether parts belong
//! together. The scene hash is SHA-256 of the checked scene as JSON
//! followed by every texture's decoded texels, so a
//! scene reformatted or rendered from another folder or machine has the
//! same hash, and one whose texture file changed does not. The options hash
//! is SHA-256 of [`PixelOptions`] as JSON: every option that can change a
//! pixel, and no other (not `--threads`, not `--accel`).
//!
//! [`file`] reads and writes tiles as PNG files that carry their
//! [`TileInfo`]; [`stitch`] checks that parts cover a frame exactly once and
//! puts them together.

pub mod file;
pub mod stitch;

use std::io::{BufWriter, Write};
use std::ops::Range;
use std::str::FromStr;

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::render::{Options, Precision};
use raytracer_scene::check::Checked;

/// The version of the [`TileInfo`] layout; `stitch` accepts only its own.
pub const FORMAT_VERSION: u32 = 1;

/// The keyword of the PNG text chunk that holds a tile's [`TileInfo`].
pub const KEYWORD: &str = "raytracer-tile";

/// Band `k` of `n` (`1 ≤ k ≤ n`), as `--tile K/N` writes it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Band {
    pub k: u32,
    pub n: u32,
}

impl FromStr for Band {
    type Err = String;

    /// `K/N` with whole numbers `1 ≤ K ≤ N`.
    fn from_str(text: &str) -> Result<Band, String> {
        let expected = format!("expected `K/N` with whole numbers 1 ≤ K ≤ N, found `{text}`");
        let (k, n) = text.split_once('/').ok_or_else(|| expected.clone())?;
        let (Ok(k), Ok(n)) = (k.parse::<u32>(), n.parse::<u32>()) else {
            return Err(expected);
        };
        if k == 0 || k > n {
            return Err(expected);
        }
        Ok(Band { k, n })
    }
}

impl std::fmt::Display for Band {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

impl Band {
    /// The rows of a frame `height` rows high that this band holds (empty
    /// when `n > height`, which `render --tile` refuses).
    pub fn rows(self, height: u32) -> Range<u32> {
        let edge = |k: u32| (u64::from(k) * u64::from(height) / u64::from(self.n)) as u32;
        edge(self.k - 1)..edge(self.k)
    }
}

/// Every render option that can change a pixel, hashed as a whole: an
/// option joins the options hash by being a field of [`Options`] (whose
/// serialisation leaves out `accel`, which never changes the image) or of
/// this struct. The precision is here because it is a type parameter of the
/// tracer, not a field of [`Options`].
#[derive(Clone, Debug, Serialize)]
pub struct PixelOptions<'a> {
    pub precision: Precision,
    #[serde(flatten)]
    pub render: &'a Options,
}

impl PixelOptions<'_> {
    /// The options as a JSON value (recorded in each tile, for messages).
    pub fn to_value(&self) -> serde_json::Value {
        // Strings, numbers and booleans only: serialising cannot fail.
        serde_json::to_value(self).unwrap_or_default()
    }
}

/// The SHA-256 of `value`'s compact JSON, in hex.
pub fn options_hash(options: &serde_json::Value) -> String {
    hex(&Sha256::digest(options.to_string().as_bytes()))
}

/// The scene hash: SHA-256 of the checked scene as compact JSON (serde's,
/// in the model's field order), then of each texture's width, height and
/// decoded texels (little-endian), in the order of their paths, in hex.
/// Streamed into the hasher: no JSON text or value is built, which for
/// 100,000 spheres would cost more than rendering a tile.
pub fn scene_hash(checked: &Checked) -> String {
    let mut hasher = Sha256::new();
    {
        let mut out = BufWriter::with_capacity(1 << 16, &mut hasher);
        // Writing into a hasher cannot fail, nor can serialising the model
        // (strings, numbers, arrays, maps with string keys).
        let _ = serde_json::to_writer(&mut out, &checked.scene);
        for texture in checked.textures.values() {
            let _ = out.write_all(&texture.width.to_le_bytes());
            let _ = out.write_all(&texture.height.to_le_bytes());
            for channel in texture.texels.iter().flatten() {
                let _ = out.write_all(&channel.to_le_bytes());
            }
        }
        let _ = out.flush();
    }
    hex(&hasher.finalize())
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// A rectangle of the frame, in pixels from the top left.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Region {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

/// Where a tile belongs: what its PNG text chunk holds, and what
/// `render --stats-json` adds under `tile`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TileInfo {
    /// [`FORMAT_VERSION`].
    pub version: u32,
    /// The whole frame's width and height.
    pub width: u32,
    pub height: u32,
    /// The pixels this tile holds.
    pub region: Region,
    /// `K` of `--tile K/N`.
    pub tile: u32,
    /// `N` of `--tile K/N`.
    pub tiles: u32,
    /// See [`scene_hash`].
    pub scene_hash: String,
    /// See [`options_hash`].
    pub options_hash: String,
    /// The options hashed, for people and for messages.
    pub options: serde_json::Value,
}

impl TileInfo {
    /// Band `band` of a `size × size` frame of the scene whose hash is
    /// `scene_hash`, rendered with `options`.
    pub fn new(band: Band, size: u32, scene_hash: String, options: &PixelOptions) -> TileInfo {
        let rows = band.rows(size);
        let options = options.to_value();
        TileInfo {
            version: FORMAT_VERSION,
            width: size,
            height: size,
            region: Region {
                x: 0,
                y: rows.start,
                width: size,
                height: rows.end - rows.start,
            },
            tile: band.k,
            tiles: band.n,
            scene_hash,
            options_hash: options_hash(&options),
            options,
        }
    }

    /// The band as `K/N`.
    pub fn band(&self) -> Band {
        Band {
            k: self.tile,
            n: self.tiles,
        }
    }

    /// The rows this tile covers.
    pub fn rows(&self) -> Range<u32> {
        self.region.y..self.region.y.saturating_add(self.region.height)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_parse_as_k_of_n() {
        assert_eq!("2/3".parse(), Ok(Band { k: 2, n: 3 }));
        assert_eq!("1/1".parse(), Ok(Band { k: 1, n: 1 }));
        for bad in [
            "0/3", "4/3", "x", "1/0", "1/", "/3", "1/3/4", "-1/3", "1.5/3", "",
        ] {
            assert!(bad.parse::<Band>().is_err(), "{bad}");
        }
    }

    #[test]
    fn bands_cover_every_row_once_and_differ_by_at_most_one_row() {
        for height in [1, 2, 7, 32, 100, 16384] {
            for n in (1..=height.min(40)).chain([height]) {
                let mut next = 0;
                let mut sizes = Vec::new();
                for k in 1..=n {
                    let rows = Band { k, n }.rows(height);
                    assert_eq!(rows.start, next, "{k}/{n} of {height}");
                    next = rows.end;
                    sizes.push(rows.len());
                }
                assert_eq!(next, height, "{n} bands of {height}");
                let (min, max) = (sizes.iter().min(), sizes.iter().max());
                assert!(
                    max.unwrap() - min.unwrap() <= 1,
                    "{n} of {height}: {sizes:?}"
                );
                assert!(*min.unwrap() >= 1);
            }
        }
        assert_eq!(Band { k: 1, n: 3 }.rows(10), 0..3);
        assert_eq!(Band { k: 2, n: 3 }.rows(10), 3..6);
        assert_eq!(Band { k: 3, n: 3 }.rows(10), 6..10);
    }

    #[test]
    fn the_options_hash_leaves_out_what_cannot_change_a_pixel() {
        let hash = |precision, options: &Options| {
            options_hash(
                &PixelOptions {
                    precision,
                    render: options,
                }
                .to_value(),
            )
        };
        let default = Options::default();
        let brute = Options {
            accel: crate::render::Accel::Brute,
            ..default
        };
        assert_eq!(hash(Precision::F64, &default), hash(Precision::F64, &brute));
        assert_ne!(
            hash(Precision::F64, &default),
            hash(Precision::F32, &default)
        );
        for changed in [
            Options { spp: 4, ..default },
            Options {
                max_depth: 2,
                ..default
            },
            Options {
                skip: false,
                ..default
            },
        ] {
            assert_ne!(
                hash(Precision::F64, &default),
                hash(Precision::F64, &changed),
                "{changed:?}"
            );
        }
    }
}
