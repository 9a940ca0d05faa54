//! Every size limit in one place, so no input can exhaust memory or time
//! before it gets a diagnostic: the scene file's size, the number of
//! objects and lights, and the size of each texture and of all of them.
//!
//! The camera resolution (its row in [`crate::language`]) is checked by the
//! check pass and `--max-depth` (0 to 64) by the command line; docs/reliability.md
//! lists all of them with the reasons for each value.

/// The largest scene file read, in bytes (256 MiB). A scene at the object
/// limit, written one attribute a line with a colour and a reflectivity
/// each, takes about 120 MiB.
pub const MAX_SCENE_BYTES: u64 = 256 << 20;

/// The most spheres and planes in one scene (2²⁰). The BVH keeps the work
/// per ray near logarithmic in the count, so this bounds memory: about a
/// gigabyte for checking and rendering a scene at the limit.
pub const MAX_OBJECTS: usize = 1 << 20;

/// The most lights in one scene. Every hit casts one shadow ray per light.
pub const MAX_LIGHTS: usize = 1_000;

/// The largest texture width or height, in texels.
pub const MAX_TEXTURE_SIDE: u32 = 16_384;

/// The most texels in one texture (2²⁴, e.g. 4096 × 4096 or 8192 × 2048).
/// A texel is stored as three `f32`s (12 bytes), and decoding needs the
/// file's own pixels beside them, so one texture peaks below 500 MiB.
pub const MAX_TEXTURE_TEXELS: u64 = 1 << 24;

/// The largest side of an image `render` writes, in pixels: the camera's
/// largest resolution. `compare` (and `grade`, for a student's image)
/// reads any image up to this side, so it accepts every image `render`
/// can write; decoded as 8-bit RGB, one such image takes 768 MiB.
pub const MAX_IMAGE_SIDE: u32 = crate::language::CAMERA.max_whole();

/// The most pixels of an image `compare` reads (16384², the largest square
/// `render` writes).
pub const MAX_IMAGE_PIXELS: u64 = MAX_IMAGE_SIDE as u64 * MAX_IMAGE_SIDE as u64;

/// The most texels in all of a scene's textures together (2²⁶, 768 MiB
/// as stored for rendering).
pub const MAX_SCENE_TEXELS: u64 = 1 << 26;
