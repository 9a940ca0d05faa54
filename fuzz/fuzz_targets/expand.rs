//! Fuzz target: the inputs a fuzzer's short inputs never are, made from
//! them. The first byte picks a shape and the rest is a unit it repeats:
//!
//! - one line past 65535 columns (the unit's line ends made spaces, the
//!   unit repeated), as a minified scene is;
//! - a file past 65535 lines (the unit's first 16 bytes repeated, one
//!   copy per line);
//! - many diagnostics: a camera, then the unit's first 256 bytes 2,000
//!   times;
//! - the unit as UTF-16 or UTF-32, with or without a byte-order mark.
//!
//! Each goes through the front end and every diagnostic format, the human
//! one both whole and capped as `check` caps it. A panic is a finding.

#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use raytracer_scene::frontend::load_bytes;

/// Past the 16-bit line and column numbers some renderers keep.
const PAST_U16: usize = 65_536 + 64;

fuzz_target!(|bytes: &[u8]| {
    let Some((&shape, unit)) = bytes.split_first() else {
        return;
    };
    if unit.is_empty() {
        return;
    }
    let expanded: Vec<u8> = match shape % 5 {
        0 => {
            let line: Vec<u8> = unit
                .iter()
                .map(|&b| if b == b'\n' || b == b'\r' { b' ' } else { b })
                .collect();
            line.iter()
                .chain(b" ")
                .copied()
                .cycle()
                .take(PAST_U16.max(line.len() + 1))
                .collect()
        }
        1 => unit[..unit.len().min(16)]
            .iter()
            .chain(b"\n")
            .copied()
            .cycle()
            .take((unit.len().min(16) + 1) * PAST_U16)
            .collect(),
        2 => b"camera 4\n"
            .iter()
            .chain(
                unit[..unit.len().min(256)]
                    .iter()
                    .chain(b"\n")
                    .cycle()
                    .take((unit.len().min(256) + 1) * 2_000),
            )
            .copied()
            .collect(),
        3 => {
            let text = String::from_utf8_lossy(unit);
            let bom = shape & 0x80 != 0;
            let units = bom.then_some(0xFEFF).into_iter().chain(text.encode_utf16());
            units.flat_map(u16::to_le_bytes).collect()
        }
        _ => {
            let text = String::from_utf8_lossy(unit);
            let bom = shape & 0x80 != 0;
            let chars = bom.then_some('\u{feff}').into_iter().chain(text.chars());
            chars.flat_map(|c| u32::from(c).to_be_bytes()).collect()
        }
    };
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/ui/scene"));
    let loaded = load_bytes("fuzz.txt", dir, &expanded);
    let report = &loaded.report;
    let _ = report.render_human_at_most(50, 80, false);
    let _ = report.render_human(80, false);
    let _ = report.render_short();
    let _ = serde_json::to_string(&report.entries().collect::<Vec<_>>());
});
