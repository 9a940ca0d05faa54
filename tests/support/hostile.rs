//! The hostile-input set: files a class produces (a line past 65535
//! columns, a file past 65535 lines, a binary, random bytes, UTF-16 and
//! UTF-32 with and without a byte-order mark, an empty file), which
//! tests/hostile_inputs.rs runs every command over and tests/playground.rs
//! feeds the WebAssembly module.

/// A scene with one warning (the light inside the sphere is not the
/// point; any diagnostic would do) at its end.
pub const SCENE: &str =
    "camera 4\nsphere\n  dimension 1\n  center 0 0 -5\nlight\n  location 0 0 0\n  color 1 1 1\n";

/// Bytes from a fixed linear congruential sequence.
fn noise(len: usize) -> Vec<u8> {
    let mut state = 0x2545_f491_u32;
    (0..len)
        .map(|_| {
            state = state.wrapping_mul(1_103_515_245).wrapping_add(12_345);
            (state >> 16) as u8
        })
        .collect()
}

fn utf16(text: &str, little_endian: bool, bom: bool) -> Vec<u8> {
    let units = bom.then_some(0xFEFF).into_iter().chain(text.encode_utf16());
    units
        .flat_map(|u| {
            if little_endian {
                u.to_le_bytes()
            } else {
                u.to_be_bytes()
            }
        })
        .collect()
}

fn utf32(text: &str, little_endian: bool, bom: bool) -> Vec<u8> {
    let chars = bom.then_some('\u{feff}').into_iter().chain(text.chars());
    chars
        .flat_map(|c| {
            if little_endian {
                u32::from(c).to_le_bytes()
            } else {
                u32::from(c).to_be_bytes()
            }
        })
        .collect()
}

/// A scene on one line of more than 65535 columns, with an error at its
/// end (a sphere of dimension 0), as a minified scene would have.
pub fn long_line() -> Vec<u8> {
    let mut text = "camera 4 ".to_string();
    while text.len() < 100_000 {
        text += "sphere dimension 1 center 0 0 -5 ";
    }
    text += "sphere dimension 0 center 0 0 -5";
    text.into_bytes()
}

/// A JSON scene on one line of more than 65535 columns with an error at
/// its end.
fn long_json_line() -> Vec<u8> {
    let sphere = r#"{"type": "sphere", "center": [0, 0, -5], "radius": 1}"#;
    let mut objects = vec![sphere; 1500];
    objects.push(r#"{"type": "sphere", "center": [0, 0, -5], "radius": 0}"#);
    format!(
        r#"{{"format": "raytracer-scene/1", "camera": {{"resolution": 4}}, "objects": [{}], "lights": []}}"#,
        objects.join(", ")
    )
    .into_bytes()
}

/// A scene past line 65535, with an error on its last line.
fn many_lines() -> Vec<u8> {
    let mut text = "camera 4\n".to_string();
    text += &"# a comment\n".repeat(70_000);
    text += "sphere\n  dimension 0\n  center 0 0 -5\n";
    text.into_bytes()
}

/// Every hostile input: a name, its file name and bytes, and whether it is
/// text the parser reads (the others are one `syntax::not_text`).
pub fn inputs() -> Vec<(&'static str, &'static str, Vec<u8>, bool)> {
    let mut binary = b"\x7fELF\x02\x01\x01\0\0\0\0\0\0\0\0\0".to_vec();
    binary.extend(noise(200_000));
    vec![
        ("long line", "long.txt", long_line(), true),
        ("long JSON line", "long.json", long_json_line(), true),
        ("many lines", "many.txt", many_lines(), true),
        ("binary", "program.txt", binary, false),
        ("random bytes", "noise.txt", noise(1 << 20), false),
        (
            "UTF-16LE with BOM",
            "u16le_bom.txt",
            utf16(SCENE, true, true),
            false,
        ),
        (
            "UTF-16BE with BOM",
            "u16be_bom.txt",
            utf16(SCENE, false, true),
            false,
        ),
        ("UTF-16LE", "u16le.txt", utf16(SCENE, true, false), false),
        ("UTF-16BE", "u16be.txt", utf16(SCENE, false, false), false),
        (
            "UTF-32LE with BOM",
            "u32le_bom.txt",
            utf32(SCENE, true, true),
            false,
        ),
        (
            "UTF-32BE with BOM",
            "u32be_bom.txt",
            utf32(SCENE, false, true),
            false,
        ),
        ("UTF-32LE", "u32le.txt", utf32(SCENE, true, false), false),
        ("UTF-32BE", "u32be.txt", utf32(SCENE, false, false), false),
        ("empty", "empty.txt", Vec::new(), true),
    ]
}
