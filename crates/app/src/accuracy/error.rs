//! How far one rendered image is from another: on the linear radiance
//! before quantization (RMSE and largest difference, in units of 1/255 so
//! they read against an 8-bit step) and on the 8-bit output (RMSE in
//! steps, and the share of pixels whose 8-bit value changed).

use glam::DVec3;

use raytracer_render::render::{Image, Radiance};

/// The difference between two renders of the same size.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Error {
    /// Root mean square over every channel of every pixel, linear, ×255.
    pub rmse: f64,
    /// The largest channel difference, linear, ×255.
    pub max: f64,
    /// Root mean square of the 8-bit values' differences, in steps.
    pub rmse_8bit: f64,
    /// Share of pixels whose 8-bit value differs in some channel.
    pub changed: f64,
}

/// The error of `image` against `reference`.
pub fn compare(image: &Radiance, reference: &Radiance) -> Error {
    assert_eq!(image.size, reference.size, "images of different sizes");
    let (ours, theirs) = (image.quantize(), reference.quantize());
    let pixels = image.pixels.len().max(1) as f64;
    let mut squares = 0.0;
    let mut max: f64 = 0.0;
    for (a, b) in image.pixels.iter().zip(&reference.pixels) {
        let d = (*a - *b) * 255.0;
        squares += d.length_squared();
        max = max.max(d.abs().max_element());
    }
    let mut squares_8bit = 0.0;
    let mut changed = 0usize;
    for (a, b) in ours.rgb.chunks_exact(3).zip(theirs.rgb.chunks_exact(3)) {
        let d: Vec<f64> = a
            .iter()
            .zip(b)
            .map(|(&x, &y)| f64::from(x) - f64::from(y))
            .collect();
        squares_8bit += d.iter().map(|d| d * d).sum::<f64>();
        changed += usize::from(a != b);
    }
    Error {
        rmse: (squares / (3.0 * pixels)).sqrt(),
        max,
        rmse_8bit: (squares_8bit / (3.0 * pixels)).sqrt(),
        changed: changed as f64 / pixels,
    }
}

/// The per-pixel mean of two renders of the same size.
pub fn average(a: &Radiance, b: &Radiance) -> Radiance {
    Radiance {
        size: a.size,
        pixels: a
            .pixels
            .iter()
            .zip(&b.pixels)
            .map(|(x, y)| (*x + *y) * 0.5)
            .collect(),
    }
}

/// A grey map of the largest channel difference per pixel on an absolute
/// scale: black where the images are equal, white where they differ by
/// `white` (linear) or more, grey in proportion between. One scale for
/// every scene, so a map's brightness reads the same everywhere.
pub fn difference_map(a: &Radiance, b: &Radiance, white: f64) -> Image {
    let map = Radiance {
        size: a.size,
        pixels: a
            .pixels
            .iter()
            .zip(&b.pixels)
            .map(|(x, y)| DVec3::splat(((*x - *y).abs().max_element() / white).min(1.0)))
            .collect(),
    };
    map.quantize()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(values: &[f64]) -> Radiance {
        Radiance {
            size: 1,
            pixels: values.iter().map(|&v| DVec3::splat(v)).collect(),
        }
    }

    #[test]
    fn an_image_has_no_error_against_itself() {
        let a = image(&[0.25]);
        assert_eq!(compare(&a, &a), Error::default());
    }

    #[test]
    fn errors_are_in_units_of_an_8bit_step() {
        // One pixel 2/255 brighter in every channel: linear RMSE 2, max 2,
        // 8-bit values 2 steps apart, the pixel changed.
        let a = image(&[10.0 / 255.0]);
        let b = image(&[12.0 / 255.0]);
        let error = compare(&a, &b);
        assert!((error.rmse - 2.0).abs() < 1e-9, "{error:?}");
        assert!((error.max - 2.0).abs() < 1e-9, "{error:?}");
        assert!((error.rmse_8bit - 2.0).abs() < 1e-9, "{error:?}");
        assert_eq!(error.changed, 1.0);
    }

    #[test]
    fn a_difference_below_rounding_changes_no_8bit_value() {
        let a = image(&[10.0 / 255.0]);
        let b = image(&[10.2 / 255.0]);
        let error = compare(&a, &b);
        assert!(error.rmse > 0.19 && error.rmse < 0.21, "{error:?}");
        assert_eq!((error.rmse_8bit, error.changed), (0.0, 0.0));
    }

    #[test]
    fn the_difference_map_has_an_absolute_scale() {
        let map = difference_map(&image(&[0.5, 0.5, 0.5]), &image(&[1.0, 0.625, 0.5]), 0.25);
        // Twice the scale is white, half of it mid grey, none black.
        assert_eq!(map.rgb[..3], [255, 255, 255]);
        assert_eq!(map.rgb[3..6], [128, 128, 128]);
        assert_eq!(map.rgb[6..], [0, 0, 0]);
    }
}
