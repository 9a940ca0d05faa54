//! Texture decoding against known texel values, for every format and bit
//! depth the `image` features enable (PNM P1–P7 at maxval 1, 255, 1000 and
//! 65535; PNG gray, gray + alpha, RGB, RGBA at 8 and 16 bits, 2-bit gray
//! and palette; baseline JPEG in colour and gray), and degenerate textures
//! (0 × N, 1 × N, huge declared sizes, truncated data) that must get a
//! diagnostic and never a panic. Every fixture is built here, by hand or
//! with an encoder. The texel lookup is checked to be total over sizes.

use crate::support;

use std::io::Cursor;

use image::codecs::jpeg::JpegEncoder;
use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder};
use proptest::prelude::*;
use raytracer_render::ir::Texture;
use raytracer_render::render::trace::texel;
use raytracer_scene::limits::MAX_TEXTURE_TEXELS;
use raytracer_scene::texture::{decode, load, DecodeError, TextureError, TextureFormat};

type Texels = Vec<[f32; 3]>;

/// How far a decoder's `sample / maximum` may be from ours: the decoders
/// scale by a reciprocal, one rounding more.
const F32_ROUNDING: f32 = 1e-6;

fn decoded(bytes: &[u8]) -> (u32, u32, Texels) {
    decode(Cursor::new(bytes), MAX_TEXTURE_TEXELS)
        .unwrap_or_else(|e| panic!("does not decode: {e}\n{:?}", &bytes[..bytes.len().min(64)]))
}

/// `actual` equals `expected` texel by texel within `tolerance`.
fn assert_texels(what: &str, actual: &[[f32; 3]], expected: &[[f32; 3]], tolerance: f32) {
    assert_eq!(actual.len(), expected.len(), "{what}: texel count");
    for (i, (a, e)) in actual.iter().zip(expected).enumerate() {
        for channel in 0..3 {
            assert!(
                (a[channel] - e[channel]).abs() <= tolerance,
                "{what}: texel {i} is {a:?}, expected {e:?} (± {tolerance})"
            );
        }
    }
}

/// Sample values spread over `0..=maxval`, including both ends.
fn samples(count: usize, maxval: u32) -> Vec<u32> {
    (0..count)
        .map(|i| match i {
            0 => 0,
            1 => maxval,
            _ => (i as u32 * 7919 + 13) % (maxval + 1),
        })
        .collect()
}

/// Texels from samples of `channels` per pixel (1 gray, 3 RGB; a fourth,
/// alpha, is dropped) over `maxval`.
fn expected_texels(samples: &[u32], channels: usize, maxval: u32) -> Texels {
    samples
        .chunks(channels)
        .map(|pixel| {
            let v = |c: usize| pixel[c] as f32 / maxval as f32;
            if channels < 3 {
                [v(0); 3]
            } else {
                [v(0), v(1), v(2)]
            }
        })
        .collect()
}

/// A PNM file: `magic` with its header, then the samples as ASCII numbers
/// or as binary big-endian bytes (two per sample above maxval 255).
fn pnm(magic: &str, width: u32, height: u32, maxval: u32, samples: &[u32]) -> Vec<u8> {
    let mut bytes =
        format!("{magic}\n# made by tests/textures.rs\n{width} {height}\n{maxval}\n").into_bytes();
    if matches!(magic, "P2" | "P3") {
        let text: Vec<String> = samples.iter().map(u32::to_string).collect();
        bytes.extend(text.join(" ").bytes());
        bytes.push(b'\n');
    } else {
        for &s in samples {
            if maxval > 255 {
                bytes.extend((s as u16).to_be_bytes());
            } else {
                bytes.push(s as u8);
            }
        }
    }
    bytes
}

#[test]
fn pnm_gray_and_rgb_decode_at_every_maxval() {
    let (width, height) = (3, 2);
    for (magic, channels) in [("P2", 1), ("P5", 1), ("P3", 3), ("P6", 3)] {
        for maxval in [1, 255, 1000, 65535] {
            let values = samples((width * height) as usize * channels, maxval);
            let (w, h, texels) = decoded(&pnm(magic, width, height, maxval, &values));
            assert_eq!((w, h), (width, height));
            // The sample over its maximum, to f32 rounding; maxval 1000 is
            // rescaled to 16 bits on the way.
            let tolerance = if maxval == 1000 { 1e-5 } else { F32_ROUNDING };
            assert_texels(
                &format!("{magic} maxval {maxval}"),
                &texels,
                &expected_texels(&values, channels, maxval),
                tolerance,
            );
        }
    }
}

#[test]
fn pnm_bitmaps_decode_with_one_as_black() {
    // Rows `1 0 1` and `0 1 0`; in a bitmap 1 is black.
    let black = [0.0; 3];
    let white = [1.0; 3];
    let expected = [black, white, black, white, black, white];
    let (w, h, texels) = decoded(b"P1\n3 2\n1 0 1\n0 1 0\n");
    assert_eq!((w, h), (3, 2));
    assert_texels("P1", &texels, &expected, 0.0);
    // P4 packs each row into whole bytes, most significant bit first.
    let (w, h, texels) = decoded(b"P4\n3 2\n\xa0\x40");
    assert_eq!((w, h), (3, 2));
    assert_texels("P4", &texels, &expected, 0.0);
}

#[test]
fn pam_decodes_gray_rgb_and_drops_alpha() {
    for (tupltype, channels, maxval) in [
        ("GRAYSCALE", 1, 255),
        ("RGB", 3, 65535),
        ("RGB_ALPHA", 4, 255),
        ("GRAYSCALE_ALPHA", 2, 65535),
    ] {
        let values = samples(2 * 2 * channels, maxval);
        let mut bytes = format!(
            "P7\nWIDTH 2\nHEIGHT 2\nDEPTH {channels}\nMAXVAL {maxval}\nTUPLTYPE {tupltype}\nENDHDR\n"
        )
        .into_bytes();
        for &s in &values {
            if maxval > 255 {
                bytes.extend((s as u16).to_be_bytes());
            } else {
                bytes.push(s as u8);
            }
        }
        let (w, h, texels) = decoded(&bytes);
        assert_eq!((w, h), (2, 2));
        let expected = match channels {
            2 => expected_texels(
                &values.chunks(2).map(|p| p[0]).collect::<Vec<_>>(),
                1,
                maxval,
            ),
            _ => expected_texels(&values, channels, maxval),
        };
        assert_texels(&format!("P7 {tupltype}"), &texels, &expected, F32_ROUNDING);
    }
}

/// A PNG of `samples` (8 or 16 bits each) written by `image`'s encoder.
fn png(color: ExtendedColorType, width: u32, height: u32, samples: &[u32]) -> Vec<u8> {
    let sixteen = matches!(
        color,
        ExtendedColorType::L16
            | ExtendedColorType::La16
            | ExtendedColorType::Rgb16
            | ExtendedColorType::Rgba16
    );
    // The encoders take 16-bit samples in native byte order.
    let data: Vec<u8> = if sixteen {
        samples
            .iter()
            .flat_map(|&s| (s as u16).to_ne_bytes())
            .collect()
    } else {
        samples.iter().map(|&s| s as u8).collect()
    };
    let mut bytes = Vec::new();
    PngEncoder::new(&mut bytes)
        .write_image(&data, width, height, color)
        .expect("encode PNG");
    bytes
}

#[test]
fn png_decodes_every_color_type_at_8_and_16_bits() {
    use ExtendedColorType::*;
    let (width, height) = (3, 2);
    for (color, channels, maxval) in [
        (L8, 1, 255),
        (La8, 2, 255),
        (Rgb8, 3, 255),
        (Rgba8, 4, 255),
        (L16, 1, 65535),
        (La16, 2, 65535),
        (Rgb16, 3, 65535),
        (Rgba16, 4, 65535),
    ] {
        let values = samples((width * height) as usize * channels, maxval);
        let (w, h, texels) = decoded(&png(color, width, height, &values));
        assert_eq!((w, h), (width, height));
        let expected = match channels {
            2 => expected_texels(
                &values.chunks(2).map(|p| p[0]).collect::<Vec<_>>(),
                1,
                maxval,
            ),
            _ => expected_texels(&values, channels, maxval),
        };
        assert_texels(&format!("PNG {color:?}"), &texels, &expected, F32_ROUNDING);
    }
}

/// A PNG written by the `png` crate, for what `image` does not encode.
fn png_raw(
    width: u32,
    height: u32,
    color: png::ColorType,
    depth: png::BitDepth,
    palette: Option<&[u8]>,
    data: &[u8],
) -> Vec<u8> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, width, height);
    encoder.set_color(color);
    encoder.set_depth(depth);
    if let Some(palette) = palette {
        encoder.set_palette(palette.to_vec());
    }
    let mut writer = encoder.write_header().expect("PNG header");
    writer.write_image_data(data).expect("PNG data");
    writer.finish().expect("PNG end");
    bytes
}

#[test]
fn png_palette_and_low_bit_gray_decode() {
    // Palette: red, green, blue, white; pixels 0 1 2 3 / 3 2 1 0.
    let palette = [255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255];
    let bytes = png_raw(
        4,
        2,
        png::ColorType::Indexed,
        png::BitDepth::Eight,
        Some(&palette),
        &[0, 1, 2, 3, 3, 2, 1, 0],
    );
    let (w, h, texels) = decoded(&bytes);
    assert_eq!((w, h), (4, 2));
    let colors: Vec<[f32; 3]> = palette
        .chunks(3)
        .map(|c| [c[0], c[1], c[2]].map(|v| f32::from(v) / 255.0))
        .collect();
    let order = [0, 1, 2, 3, 3, 2, 1, 0];
    let expected: Texels = order.iter().map(|&i| colors[i]).collect();
    assert_texels("PNG palette", &texels, &expected, F32_ROUNDING);

    // 2-bit gray: levels 0..=3 are 0, 1/3, 2/3, 1; one row of four packed
    // into one byte, most significant bits first.
    let bytes = png_raw(
        4,
        1,
        png::ColorType::Grayscale,
        png::BitDepth::Two,
        None,
        &[0b00_01_10_11],
    );
    let (_, _, texels) = decoded(&bytes);
    let expected: Texels = (0..4).map(|l| [l as f32 / 3.0; 3]).collect();
    assert_texels("PNG 2-bit gray", &texels, &expected, F32_ROUNDING);
}

#[test]
fn baseline_jpeg_decodes_close_to_what_was_encoded() {
    // Four flat 16 × 16 quadrants, so neither the 8 × 8 blocks nor the
    // chroma subsampling mixes colours inside a quadrant.
    let quadrants = [
        [200u8, 30, 40],
        [20, 180, 60],
        [30, 60, 220],
        [128, 128, 128],
    ];
    let side = 32;
    let colour_at = |x: u32, y: u32| quadrants[(y / 16 * 2 + x / 16) as usize];
    let rgb: Vec<u8> = (0..side)
        .flat_map(|y| (0..side).flat_map(move |x| colour_at(x, y)))
        .collect();
    let mut bytes = Vec::new();
    JpegEncoder::new_with_quality(&mut bytes, 95)
        .write_image(&rgb, side, side, ExtendedColorType::Rgb8)
        .expect("encode JPEG");
    let (w, h, texels) = decoded(&bytes);
    assert_eq!((w, h), (side, side));
    let expected: Texels = (0..side)
        .flat_map(|y| (0..side).map(move |x| colour_at(x, y).map(|v| f32::from(v) / 255.0)))
        .collect();
    // Lossy: within 4/255 of what was encoded.
    assert_texels("JPEG RGB", &texels, &expected, 4.0 / 255.0);

    let gray: Vec<u8> = (0..side * side)
        .map(|i| if i % side < 16 { 40 } else { 210 })
        .collect();
    let mut bytes = Vec::new();
    JpegEncoder::new_with_quality(&mut bytes, 95)
        .write_image(&gray, side, side, ExtendedColorType::L8)
        .expect("encode JPEG");
    let (_, _, texels) = decoded(&bytes);
    let expected: Texels = gray.iter().map(|&g| [f32::from(g) / 255.0; 3]).collect();
    assert_texels("JPEG gray", &texels, &expected, 4.0 / 255.0);
}

#[test]
fn textures_without_texels_are_refused() {
    for bytes in [
        &b"P6\n0 0\n255\n"[..],
        b"P5\n0 3\n255\n",
        b"P3\n4 0\n255\n",
        b"P7\nWIDTH 0\nHEIGHT 1\nDEPTH 3\nMAXVAL 255\nTUPLTYPE RGB\nENDHDR\n",
    ] {
        match decode(Cursor::new(bytes), MAX_TEXTURE_TEXELS) {
            Err(DecodeError::Empty { .. }) | Err(DecodeError::Image(_)) => {}
            other => panic!("{bytes:?}: expected a refusal, found {other:?}"),
        }
    }
    // The one the issue found: a header-only 0 × 0 P6 is `Empty`.
    assert!(matches!(
        decode(Cursor::new(&b"P6\n0 0\n255\n"[..]), MAX_TEXTURE_TEXELS),
        Err(DecodeError::Empty {
            width: 0,
            height: 0
        })
    ));
}

#[test]
fn a_one_texel_wide_texture_reads_by_row() {
    let (w, h, texels) = decoded(b"P5\n1 4\n255\n\x00\x55\xaa\xff");
    assert_eq!((w, h), (1, 4));
    let texture = Texture {
        path: "column.pgm".into(),
        format: TextureFormat::Ppm,
        width: w,
        height: h,
        texels,
    };
    // v = 1 is the top row; u does not matter.
    for (v, level) in [(0.99, 0.0), (0.6, 85.0), (0.3, 170.0), (0.0, 255.0)] {
        for u in [0.0, 0.5, 1.0] {
            let t = texel(&texture, u, v);
            assert_eq!(t.x, f64::from(level as f32 / 255.0), "u {u}, v {v}");
        }
    }
}

/// CRC-32 (ISO-HDLC) of PNG chunk type and data.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// A PNG that declares `width × height` 8-bit RGB and holds no pixel data
/// (an empty IDAT chunk, where a decoder stops reading the header).
fn png_header_only(width: u32, height: u32) -> Vec<u8> {
    let mut header = width.to_be_bytes().to_vec();
    header.extend(height.to_be_bytes());
    header.extend([8, 2, 0, 0, 0]);
    let mut bytes = b"\x89PNG\r\n\x1a\n".to_vec();
    for (kind, data) in [(b"IHDR", &header[..]), (b"IDAT", &[]), (b"IEND", &[])] {
        let mut chunk = kind.to_vec();
        chunk.extend(data);
        bytes.extend((data.len() as u32).to_be_bytes());
        bytes.extend(&chunk);
        bytes.extend(crc32(&chunk).to_be_bytes());
    }
    bytes
}

#[test]
fn huge_declared_sizes_are_refused_from_the_header() {
    let huge = [
        pnm("P6", 1, 100_000, 255, &[]),
        pnm("P5", 70_000, 70_000, 65535, &[]),
        png_header_only(100_000, 100_000),
        png_header_only(1, 1 << 30),
    ];
    for (i, bytes) in huge.iter().enumerate() {
        match decode(Cursor::new(bytes), MAX_TEXTURE_TEXELS) {
            Err(DecodeError::TooLarge { .. }) => {}
            other => panic!("case {i}: expected too large, found {other:?}"),
        }
    }
    // The same header at a small size passes the check and fails only
    // for want of pixels, so it is the size that was refused above.
    assert_eq!(crc32(b"IEND"), 0xAE42_6082);
    assert!(matches!(
        decode(Cursor::new(png_header_only(3, 2)), MAX_TEXTURE_TEXELS),
        Err(DecodeError::Image(_))
    ));
}

#[test]
fn truncated_files_are_refused_by_the_loader() {
    let dir = tempfile::tempdir().expect("temp dir");
    let whole_png = png(ExtendedColorType::Rgb16, 8, 8, &samples(8 * 8 * 3, 65535));
    let cases: [(&str, Vec<u8>); 4] = [
        ("short.ppm", b"P6\n4 4\n255\n\x01\x02".to_vec()),
        ("short16.ppm", b"P6\n2 2\n65535\n\x01\x02\x03".to_vec()),
        ("short.pgm", b"P2\n2 2\n255\n1 2\n".to_vec()),
        ("short.png", whole_png[..whole_png.len() / 2].to_vec()),
    ];
    for (name, bytes) in cases {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).expect("write");
        match load(&path, MAX_TEXTURE_TEXELS) {
            Err(TextureError::Truncated { .. } | TextureError::Decode { .. }) => {}
            other => panic!("{name}: expected truncated or undecodable, found {other:?}"),
        }
    }
}

#[test]
fn degenerate_textures_get_diagnostics_from_render_not_a_panic() {
    let dir = tempfile::tempdir().expect("temp dir");
    let d = dir.path();
    support::write(d, "zero.ppm", "P6\n0 0\n255\n");
    support::write(d, "short.ppm", b"P6\n4 4\n65535\n\x01\x02");
    support::write(
        d,
        "column.ppm",
        b"P6\n1 3\n65535\n\x00\x00\xff\xff\x00\x00\x00\x00\xff\xff\x00\x00\x00\x00\x00\x00\xff\xff",
    );
    let scene = |texture: &str| {
        support::write(
            d,
            "scene.txt",
            format!("camera 4\nsphere\n  dimension 1\n  center 0 0 -3\n  texture \"{texture}\"\n"),
        )
    };
    let out = d.join("out.png");
    let out = out.to_str().expect("UTF-8 path");
    for (texture, reason) in [
        ("zero.ppm", "0 × 0 texels: an image has at least one"),
        ("short.ppm", "the file ends before its last texel"),
    ] {
        let output = support::run(&["render", &scene(texture), out]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{texture}: {stderr}");
        assert!(
            stderr.contains("scene::texture_not_an_image") && stderr.contains(reason),
            "{texture}: {stderr}"
        );
        assert!(!d.join("out.png").exists());
    }
    // A 1 × 3 16-bit texture renders.
    let output = support::run(&["render", &scene("column.ppm"), out]);
    assert_eq!(output.status.code(), Some(0), "{output:?}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    /// For every size (0 included) and any texel count, the lookup returns
    /// without panicking; when the texels fill the size it returns the
    /// texel the nearest-texel rule names.
    #[test]
    fn texel_lookup_is_total_and_follows_the_rule(
        width in 0u32..40,
        height in 0u32..40,
        missing in 0usize..3,
        full in any::<bool>(),
        u in prop_oneof![-2.0..3.0f64, Just(0.0), Just(1.0), Just(1.0 - f64::EPSILON), Just(-0.0)],
        v in prop_oneof![-2.0..3.0f64, Just(0.0), Just(1.0), Just(1e-300), Just(1.0 + 1e-15)],
    ) {
        let area = (width * height) as usize;
        let count = if full { area } else { area.saturating_sub(missing + 1) };
        let texels: Texels = (0..count).map(|i| [i as f32, 0.5, 1.0]).collect();
        let texture = Texture { path: "t".into(), format: TextureFormat::Ppm, width, height, texels };
        let found = texel(&texture, u, v);
        if full && area > 0 {
            let x = ((u * f64::from(width)).floor().max(0.0) as usize).min(width as usize - 1);
            let y = (((1.0 - v) * f64::from(height)).floor().max(0.0) as usize)
                .min(height as usize - 1);
            prop_assert_eq!(found.x, (y * width as usize + x) as f32 as f64);
        } else {
            prop_assert!(found.is_finite());
        }
    }
}

/// A texture path that names no file, where a near one does (written
/// with `\`, in curly quotes, in another case, relative to the wrong
/// folder): the help asks "did you mean" the path that names it, and the
/// fix (unsafe) writes it, after which the scene checks clean.
#[test]
fn a_near_texture_path_is_suggested_and_fixed() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    let ppm = "P3 1 1 255 200 100 50\n";
    std::fs::create_dir_all(root.join("textures")).unwrap();
    std::fs::create_dir_all(root.join("scenes")).unwrap();
    std::fs::write(root.join("textures/wood_tex.ppm"), ppm).unwrap();
    std::fs::write(root.join("scenes/Wood.ppm"), ppm).unwrap();
    let scene = |texture: &str| {
        format!(
            "camera 4\nsphere dimension 1 center 0 0 -5 texture {texture}\nlight location 0 5 0 color 1 1 1\n"
        )
    };
    for (file, written, meant) in [
        ("a.txt", "textures\\wood_tex.ppm", "textures/wood_tex.ppm"),
        ("b.txt", "wood_tex.ppm", "textures/wood_tex.ppm"),
        ("scenes/c.txt", "wood.ppm", "Wood.ppm"),
        (
            "scenes/d.txt",
            "\u{201C}wood_tex.ppm\u{201D}",
            "../textures/wood_tex.ppm",
        ),
        (
            "scenes/e.txt",
            "\"textures/wood_tex.ppm\"",
            "../textures/wood_tex.ppm",
        ),
    ] {
        let path = root.join(file);
        let text = scene(written);
        std::fs::write(&path, &text).unwrap();
        let loaded = raytracer_scene::frontend::load(&path).unwrap();
        let entries: Vec<_> = loaded.report.entries().collect();
        assert_eq!(entries.len(), 1, "{written}: {entries:?}");
        assert_eq!(entries[0].code, "scene::texture_not_found");
        assert_eq!(
            entries[0].help.as_deref(),
            Some(format!("did you mean `{meant}`?").as_str()),
            "{written}"
        );
        let fixes = loaded
            .report
            .fixes_up_to(raytracer_scene::fix::Applicability::Unsafe);
        let (fixed, applied) = raytracer_scene::fix::apply(&text, fixes);
        assert_eq!(applied.len(), 1, "{written}");
        std::fs::write(&path, &fixed).unwrap();
        let again = raytracer_scene::frontend::load(&path).unwrap();
        assert_eq!(again.report.entries().count(), 0, "{written}: {fixed}");
    }
    // Nothing near: the path that was looked for, and no fix.
    let path = root.join("f.txt");
    std::fs::write(&path, scene("marble.ppm")).unwrap();
    let loaded = raytracer_scene::frontend::load(&path).unwrap();
    let entry = loaded.report.entries().next().unwrap();
    assert!(entry.help.unwrap().starts_with("looked for"));
    assert!(entry.fix.is_none());
}
