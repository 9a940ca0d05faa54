//! The playground's WebAssembly module: the front end and the renderer
//! behind a C ABI of a few functions, for the page's Web Workers
//! (`web/src/worker.js`).
//!
//! Bytes cross the boundary through two buffers the module owns, so no
//! function takes a pointer from the caller: the caller asks for an input
//! buffer of a length ([`web_input`]), writes into it, and calls a
//! function that reads it; a function with something to return leaves it
//! in the output buffer, which the caller reads at [`web_output`] for
//! [`web_output_len`] bytes before its next call.
//!
//! - [`web_texture`] and [`web_forget_textures`]: the texture files a
//!   scene may name, given as bytes (a dropped or picked file).
//! - [`web_language`]: the section and attribute names, which the editor
//!   highlights.
//! - [`web_check`]: the scene's diagnostics, as `check --format json`
//!   prints them, with their fixes.
//! - [`web_load`] then [`web_render`]: the scene checked and lowered once,
//!   then rendered a band of rows at a time at any resolution, so the page
//!   can show a coarse image first and stop between bands.
//!
//! Nothing here reads a clock (the page times what it wants) or panics on
//! any input: the module is built with `panic = "abort"`, where a panic
//! would end the worker.

use std::cell::RefCell;
use std::collections::HashMap;

use raytracer_render::ir;
use raytracer_render::render::{render_rows, Options, Precision};
use raytracer_scene::ast::{AttrName, SectionKind};
use raytracer_scene::diagnostic::JsonDiagnostic;
use raytracer_scene::frontend::{self, Language, Loaded};
use serde::Serialize;

/// What the module holds between calls.
#[derive(Default)]
struct State {
    input: Vec<u8>,
    output: Vec<u8>,
    /// Texture files by name.
    files: HashMap<String, Vec<u8>>,
    /// The scene [`web_load`] lowered last, if it was valid.
    scene: Option<ir::Scene>,
}

thread_local! {
    // A module instance runs on one thread (its worker's).
    static STATE: RefCell<State> = RefCell::new(State::default());
}

fn with_state<T>(f: impl FnOnce(&mut State) -> T) -> T {
    STATE.with(|state| f(&mut state.borrow_mut()))
}

/// The largest image side [`web_render`] renders: 2048 × 2048 pixels are
/// 16 MiB of RGBA in the page's canvas, which the page draws and scales
/// down to its box as the bands arrive; at 4096 that work alone kept the
/// page's thread busy for half a second at a time on a loaded machine.
pub const MAX_SIZE: u32 = 2048;

/// The input buffer, resized to `len` bytes, for the caller to fill.
#[no_mangle]
pub extern "C" fn web_input(len: usize) -> *mut u8 {
    with_state(|state| {
        state.input.clear();
        state.input.resize(len, 0);
        state.input.as_mut_ptr()
    })
}

/// Where the output of the last call starts.
#[no_mangle]
pub extern "C" fn web_output() -> *const u8 {
    with_state(|state| state.output.as_ptr())
}

/// How many bytes of output the last call left.
#[no_mangle]
pub extern "C" fn web_output_len() -> usize {
    with_state(|state| state.output.len())
}

/// Keep a texture file: the input holds its name (`name_len` bytes of
/// UTF-8) and then its bytes. A file of the same name is replaced.
/// Returns 0, or 1 when the name is not UTF-8 (nothing is kept).
#[no_mangle]
pub extern "C" fn web_texture(name_len: usize) -> u32 {
    with_state(|state| {
        let input = std::mem::take(&mut state.input);
        let Some((name, bytes)) = split_name(&input, name_len) else {
            return 1;
        };
        state.files.insert(name.to_string(), bytes.to_vec());
        0
    })
}

/// Forget every texture file.
#[no_mangle]
pub extern "C" fn web_forget_textures() {
    with_state(|state| state.files.clear());
}

/// The language's keywords: the output is the JSON object
/// `{"sections": [...], "attributes": [...]}`.
#[no_mangle]
pub extern "C" fn web_language() {
    let keywords = serde_json::json!({
        "sections": SectionKind::KEYWORDS,
        "attributes": AttrName::KEYWORDS,
    });
    with_state(|state| state.output = keywords.to_string().into_bytes());
}

/// Check a scene: the input holds its file name (`name_len` bytes of
/// UTF-8; a name ending in `.json` is read as JSON) and then its bytes.
/// The output is the JSON of [`Checked`]. Returns the number of errors
/// (`u32::MAX` when the name is not UTF-8).
#[no_mangle]
pub extern "C" fn web_check(name_len: usize) -> u32 {
    with_state(|state| {
        let Some(loaded) = load(state, name_len) else {
            return u32::MAX;
        };
        let checked = Checked::of(&loaded);
        state.output = serde_json::to_vec(&checked).unwrap_or_default();
        checked.errors
    })
}

/// Check and lower a scene (the input as for [`web_check`]) and keep it
/// for [`web_render`]. Returns its resolution, or 0 when it has errors
/// (or its name is not UTF-8) and nothing is kept.
#[no_mangle]
pub extern "C" fn web_load(name_len: usize) -> u32 {
    with_state(|state| {
        state.scene = load(state, name_len)
            .and_then(|loaded| loaded.checked)
            .map(ir::lower);
        state.scene.as_ref().map_or(0, |scene| scene.resolution)
    })
}

/// Render rows `start..end` of the scene [`web_load`] kept, in a frame
/// `size` pixels on a side (the scene's own camera sees the same view at
/// any size; 0 is the scene's resolution) and the default options of
/// `raytracer render`: the output is `size × (end − start)` RGB pixels,
/// top row first, as that command computes them. Returns the number of
/// rows rendered: 0 when no scene is kept, `size` exceeds [`MAX_SIZE`] or
/// the rows are not within the frame.
#[no_mangle]
pub extern "C" fn web_render(size: u32, start: u32, end: u32) -> u32 {
    with_state(|state| {
        state.output.clear();
        let Some(scene) = state.scene.as_mut() else {
            return 0;
        };
        if size != 0 {
            scene.resolution = size;
        }
        let size = scene.resolution;
        if size > MAX_SIZE || start >= end || end > size {
            return 0;
        }
        let (rgb, _) = render_rows(
            Precision::F64,
            scene,
            &Options::default(),
            start..end,
            &|| (),
        );
        state.output = rgb;
        end - start
    })
}

/// The name and the bytes after it, when the first `name_len` bytes of
/// `input` are UTF-8.
fn split_name(input: &[u8], name_len: usize) -> Option<(&str, &[u8])> {
    let (name, rest) = input.split_at_checked(name_len)?;
    Some((std::str::from_utf8(name).ok()?, rest))
}

/// The scene in the input through the front end, its textures from the
/// files given.
fn load(state: &mut State, name_len: usize) -> Option<Loaded> {
    let input = std::mem::take(&mut state.input);
    let (name, bytes) = split_name(&input, name_len)?;
    let language = Language::of_name(std::path::Path::new(name));
    Some(frontend::load_bytes_in_memory(
        language,
        name,
        bytes,
        state.files.clone(),
    ))
}

/// What [`web_check`] returns.
#[derive(Serialize)]
struct Checked {
    errors: u32,
    warnings: u32,
    /// The camera's resolution when the scene has no error.
    resolution: Option<u32>,
    /// As `check --format json` prints them.
    diagnostics: Vec<JsonDiagnostic>,
}

impl Checked {
    fn of(loaded: &Loaded) -> Checked {
        let count = |n: usize| u32::try_from(n).unwrap_or(u32::MAX);
        Checked {
            errors: count(loaded.report.error_count()),
            warnings: count(loaded.report.warning_count()),
            resolution: loaded
                .checked
                .as_ref()
                .map(|checked| checked.scene.camera.resolution),
            diagnostics: loaded.report.entries().collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Put `name` and `bytes` in the input buffer; the name's length.
    fn give(name: &str, bytes: &[u8]) -> usize {
        let mut input = name.as_bytes().to_vec();
        input.extend_from_slice(bytes);
        let at = web_input(input.len());
        with_state(|state| {
            assert_eq!(at, state.input.as_mut_ptr());
            state.input.copy_from_slice(&input);
        });
        name.len()
    }

    fn output() -> Vec<u8> {
        with_state(|state| state.output.clone())
    }

    const SCENE: &str = "camera 8\nsphere\n  dimension 1\n  center 0 0 -3\n  color 1 0 0\n\
                         light\n  location 0 0 0\n  color 1 1 1\n";

    #[test]
    fn a_check_returns_what_check_format_json_prints() {
        let text = "camera 8\nsphere\n  dimenson 1\n  center 0 0 -3\n";
        let errors = web_check(give("a.txt", text.as_bytes()));
        let json: serde_json::Value = serde_json::from_slice(&output()).unwrap();
        assert_eq!(json["errors"], errors);
        let loaded = frontend::load_bytes("a.txt", std::path::Path::new(""), text.as_bytes());
        let expected = serde_json::to_value(loaded.report.entries().collect::<Vec<_>>()).unwrap();
        assert_eq!(json["diagnostics"], expected);
        assert!(errors > 0);
    }

    #[test]
    fn bands_at_any_size_equal_the_whole_render() {
        assert_eq!(web_load(give("a.txt", SCENE.as_bytes())), 8);
        let loaded = frontend::load_bytes("a.txt", std::path::Path::new(""), SCENE.as_bytes());
        let scene = ir::lower(loaded.checked.unwrap());
        let (image, _) =
            raytracer_render::render::render(Precision::F64, &scene, &Options::default(), &|| ());
        let mut bands = Vec::new();
        for (start, end) in [(0, 3), (3, 8)] {
            assert_eq!(web_render(0, start, end), end - start);
            bands.extend(output());
        }
        assert_eq!(bands, image.rgb);
        assert_eq!(web_render(4, 0, 4), 4);
        assert_eq!(output().len(), 4 * 4 * 3);
        assert_eq!(web_render(MAX_SIZE + 1, 0, 1), 0);
        assert_eq!(web_render(4, 3, 5), 0);
    }

    #[test]
    fn a_texture_given_as_bytes_is_used() {
        let scene = "camera 2\nplane\n  dimension 4 4\n  center 0 0 -2\n  normal 0 0 1\n  \
                     headup 0 1 0\n  texture tex.ppm\nlight\n  location 0 0 0\n  color 1 1 1\n";
        web_forget_textures();
        assert_eq!(web_check(give("a.txt", scene.as_bytes())), 1);
        assert_eq!(web_texture(give("tex.ppm", b"P3\n1 1\n255\n0 0 255\n")), 0);
        assert_eq!(web_load(give("a.txt", scene.as_bytes())), 2);
        assert_eq!(web_render(0, 0, 2), 2);
        assert!(
            output().chunks(3).all(|p| p[0] == 0 && p[2] > 0),
            "{:?}",
            output()
        );
    }

    #[test]
    fn the_keywords_are_the_language_s() {
        web_language();
        let json: serde_json::Value = serde_json::from_slice(&output()).unwrap();
        assert_eq!(json["sections"][1], "sphere");
        assert!(json["attributes"]
            .as_array()
            .unwrap()
            .contains(&"reflectivity".into()));
    }

    #[test]
    fn a_name_that_is_not_utf8_is_refused() {
        assert_ne!(web_check(give("", b"\xff")), u32::MAX);
        let len = web_input(1);
        assert!(!len.is_null());
        with_state(|state| state.input[0] = 0xff);
        assert_eq!(web_check(1), u32::MAX);
        assert_eq!(web_load(give("", b"")), 0);
        assert_eq!(web_render(0, 0, 1), 0);
    }
}
