//! Fuzz target: texture bytes through the decoder with the size limits of
//! `raytracer_scene::limits`: any header is judged before pixels are allocated,
//! and nothing panics or aborts.

#![no_main]

use std::io::Cursor;

use libfuzzer_sys::fuzz_target;
use raytracer_scene::limits::MAX_TEXTURE_TEXELS;
use raytracer_scene::texture;

fuzz_target!(|bytes: &[u8]| {
    if let Ok((width, height, texels)) = texture::decode(Cursor::new(bytes), MAX_TEXTURE_TEXELS) {
        assert_eq!(texels.len() as u64, u64::from(width) * u64::from(height));
        assert!(texture::fits(width, height, MAX_TEXTURE_TEXELS));
    }
});
