//! The renderer: a checked scene lowered to the render IR, traced into an
//! image, and the image written to a file.
//!
//! [`ir`] lowers the scene model of `raytracer-scene` into what the
//! tracer needs (lowering cannot fail); [`render`] traces it, one ray per
//! pixel (or adaptively more), one shadow ray per light and recursive
//! mirror reflection, in f32 or f64; [`output`] writes the image whole or
//! not at all; [`tile`] cuts a frame into parts rendered apart and
//! stitches them back.
//!
//! This crate knows no command line: a program that renders scenes
//! depends on it and on `raytracer-scene` only.
//!
//! ```
//! use std::path::Path;
//! use raytracer_scene::frontend;
//! use raytracer_render::{ir, render};
//!
//! let text = "camera 4\nsphere\n  dimension 1\n  center 0 0 -5\n";
//! let loaded = frontend::load_bytes("scene.txt", Path::new("."), text.as_bytes());
//! let scene = ir::lower(loaded.checked.expect("the scene checks"));
//! let (image, _) = render::render(render::Precision::F64, &scene, &render::Options::default(), &|| ());
//! assert_eq!(image.rgb.len(), 4 * 4 * 3);
//! ```

pub mod ir;
pub mod output;
pub mod render;
pub mod tile;
