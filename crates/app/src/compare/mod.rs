//! Comparing a candidate image with a reference: what `raytracer compare`
//! reports and what `raytracer grade` judges each student image by.
//!
//! Images are read by content, whatever their names say ([`read`]): PPM
//! (P3 or P6, any maxval), PNG or JPEG, through the image decoder of
//! [`raytracer_scene::texture`] ([`texture::load_image`]: any image
//! `render` can write, not only what a texture may be), and kept as 8-bit
//! RGB. Three measures are taken, each
//! reported on its own ([`metrics`]): the perceptual error ꟻLIP, RMSE with
//! its PSNR, and the coverage of the two images' non-black pixels. The
//! [`Thresholds`] turn them into a [`Verdict`]: a different size, a
//! coverage below its bound (which pixels show something differs) and a
//! ꟻLIP mean above its bound (only the appearance differs) are each a
//! reason of their own. These are pixel measures, blind to the scene:
//! `grade` (and `compare --scene`) judge by aspect instead
//! ([`crate::grade::aspects`]).

pub mod heatmap;
pub mod metrics;

use std::io::Write;
use std::path::Path;

use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder};

use schemars::JsonSchema;
use serde::Serialize;

pub use metrics::{FlipStats, Metrics};
use raytracer_scene::texture::{self, TextureFormat};

/// An image to compare: 8-bit RGB, row 0 at the top.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Picture {
    pub width: u32,
    pub height: u32,
    /// `width × height × 3` bytes, row-major.
    pub rgb: Vec<u8>,
}

impl Picture {
    /// A decoded image's texels, each channel scaled to 8 bits
    /// (`round(v · 255)`).
    pub fn from_texels(width: u32, height: u32, texels: &[[f32; 3]]) -> Picture {
        let rgb = texels
            .iter()
            .flatten()
            .map(|&v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
            .collect();
        Picture { width, height, rgb }
    }

    /// The size as `[width, height]`, for reports.
    pub fn size(&self) -> [u32; 2] {
        [self.width, self.height]
    }

    /// Pixel `k`, counted row by row from the top left.
    pub fn pixel(&self, k: usize) -> [u8; 3] {
        [self.rgb[3 * k], self.rgb[3 * k + 1], self.rgb[3 * k + 2]]
    }
}

/// Why an image could not be read: the file's path and the reason.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct ReadImageError(pub texture::TextureError);

/// Read the image at `path`, recognising PPM, PNG and JPEG by their bytes.
/// Channels of any depth are scaled to 8 bits (`round(v · 255)`).
pub fn read(path: &Path) -> Result<(Picture, TextureFormat), ReadImageError> {
    let image = texture::load_image(path).map_err(ReadImageError)?;
    let picture = Picture {
        width: image.width,
        height: image.height,
        rgb: image.rgb,
    };
    Ok((picture, image.format))
}

/// The bounds a candidate must keep to match its reference.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, JsonSchema)]
pub struct Thresholds {
    /// The least intersection over union of the non-black masks.
    pub min_coverage: f64,
    /// The largest mean ꟻLIP error.
    pub max_flip: f64,
    /// A pixel is black when none of its channels exceeds this (0–255).
    pub black_level: u8,
}

/// The default bound on coverage.
pub const DEFAULT_MIN_COVERAGE: f64 = 0.99;
/// The default bound on the mean ꟻLIP error.
pub const DEFAULT_MAX_FLIP: f64 = 0.05;
/// The default black level: values up to 2 of 255 count as black, so a
/// lossy encoder's noise in the background is not coverage.
pub const DEFAULT_BLACK_LEVEL: u8 = 2;

impl Default for Thresholds {
    fn default() -> Self {
        Thresholds {
            min_coverage: DEFAULT_MIN_COVERAGE,
            max_flip: DEFAULT_MAX_FLIP,
            black_level: DEFAULT_BLACK_LEVEL,
        }
    }
}

/// What a comparison concluded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Within every threshold.
    Match,
    /// The images have different sizes; nothing else was measured.
    Size,
    /// The coverage is below its bound: which pixels show something
    /// differs. Told pixel by pixel, without the scene: it is not grade's
    /// `geometry`.
    Coverage,
    /// The coverage holds but the ꟻLIP mean is above its bound: only the
    /// appearance (shading, colours) differs.
    Appearance,
}

impl Verdict {
    /// The verdict in the words of the reports.
    pub fn describe(self) -> &'static str {
        match self {
            Verdict::Match => "match",
            Verdict::Size => "differs: size",
            Verdict::Coverage => "differs: coverage (which pixels show something)",
            Verdict::Appearance => "differs: appearance",
        }
    }
}

/// The outcome of [`compare`].
#[derive(Clone, Debug)]
pub struct Comparison {
    pub verdict: Verdict,
    /// `None` when the sizes differ.
    pub metrics: Option<Metrics>,
    /// The ꟻLIP error of each pixel, in `[0, 1]`; empty when the sizes differ.
    pub error_map: Vec<f32>,
}

/// Compare `candidate` with `reference` and judge it by `thresholds`.
pub fn compare(reference: &Picture, candidate: &Picture, thresholds: &Thresholds) -> Comparison {
    if reference.size() != candidate.size() {
        return Comparison {
            verdict: Verdict::Size,
            metrics: None,
            error_map: Vec::new(),
        };
    }
    let (metrics, error_map) = metrics::measure(reference, candidate, thresholds.black_level);
    let verdict = if metrics.coverage_iou < thresholds.min_coverage {
        Verdict::Coverage
    } else if f64::from(metrics.flip.mean) > thresholds.max_flip {
        Verdict::Appearance
    } else {
        Verdict::Match
    };
    Comparison {
        verdict,
        metrics: Some(metrics),
        error_map,
    }
}

/// Encode `picture` as PNG.
pub fn encode_png(picture: &Picture, out: &mut dyn Write) -> std::io::Result<()> {
    PngEncoder::new(out)
        .write_image(
            &picture.rgb,
            picture.width,
            picture.height,
            ExtendedColorType::Rgb8,
        )
        .map_err(std::io::Error::other)
}
