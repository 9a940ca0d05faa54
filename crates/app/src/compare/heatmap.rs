//! The ꟻLIP error map as a picture: each pixel's error through ꟻLIP's own
//! colour map (magma: black for no error, through purple and orange, to
//! pale yellow for the most).

use super::Picture;

/// The error map of a `width × height` comparison in ꟻLIP's colour map.
pub fn colour(width: u32, height: u32, error_map: &[f32]) -> Picture {
    let errors = nv_flip::FlipImageFloat::with_data(width, height, error_map);
    let rgb = errors.apply_color_lut(&nv_flip::magma_lut()).to_vec();
    Picture { width, height, rgb }
}
