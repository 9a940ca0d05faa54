//! Whether a file's bytes are text a scene could be written in, judged from
//! its first [`SNIFF_BYTES`] before anything is parsed.
//!
//! A binary file, random bytes or a text saved as UTF-16 or UTF-32 would
//! otherwise be parsed as scene text and reported as hundreds of unknown
//! sections full of replacement characters. [`sniff`] names what the file
//! is instead, so it gets one diagnostic with the fix. UTF-16 and UTF-32
//! are recognised by their byte-order mark or, without one, by the zero
//! bytes ASCII characters leave in them; they are reported, not decoded:
//! every tool that rewrites a scene (`fmt`, `check --fix`) writes UTF-8,
//! and a scene's spans are byte offsets into the UTF-8 it was read as.
//! A file with a NUL byte, or in which invalid UTF-8 and control
//! characters are common, is binary; a few bad bytes in text (a Latin-1
//! `é`) are left to `syntax::invalid_utf8`, which parsing goes on after.

/// How much of a file is looked at.
pub const SNIFF_BYTES: usize = 8 * 1024;

/// What a file that is not scene text is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NotText {
    /// Text in UTF-16 or UTF-32.
    Unicode {
        /// `"UTF-16"` or `"UTF-32"`.
        encoding: &'static str,
        /// Least significant byte first.
        little_endian: bool,
        /// Whether it starts with a byte-order mark.
        bom: bool,
    },
    /// Not text: a NUL byte at `nul`, or mostly bytes text does not hold.
    Binary { nul: Option<usize> },
}

impl NotText {
    /// What the file was found to be, for "expected scene text in UTF-8,
    /// found …".
    pub fn found(&self) -> String {
        match *self {
            NotText::Unicode {
                encoding,
                little_endian,
                bom,
            } => {
                let order = if little_endian { "little" } else { "big" };
                let mark = if bom {
                    "with a byte-order mark"
                } else {
                    "without a byte-order mark"
                };
                format!("{encoding} text ({order}-endian, {mark})")
            }
            NotText::Binary { nul: Some(at) } => {
                format!("a binary file (a NUL byte at byte {at})")
            }
            NotText::Binary { nul: None } => {
                "a binary file (mostly bytes that are not UTF-8 text)".to_string()
            }
        }
    }

    /// The fix to suggest.
    pub fn help(&self) -> &'static str {
        match self {
            NotText::Unicode { .. } => {
                "save the file as UTF-8 (in Notepad: File, Save as, Encoding: UTF-8)"
            }
            NotText::Binary { .. } => "a scene is a text file: is this the scene file?",
        }
    }
}

/// What `bytes` is when it is not scene text, judged from its start.
pub fn sniff(bytes: &[u8]) -> Option<NotText> {
    let head = &bytes[..bytes.len().min(SNIFF_BYTES)];
    let unicode = |encoding, little_endian, bom| {
        Some(NotText::Unicode {
            encoding,
            little_endian,
            bom,
        })
    };
    // UTF-32's marks first: UTF-16LE's is a prefix of UTF-32LE's.
    if head.starts_with(&[0xFF, 0xFE, 0, 0]) {
        return unicode("UTF-32", true, true);
    }
    if head.starts_with(&[0, 0, 0xFE, 0xFF]) {
        return unicode("UTF-32", false, true);
    }
    if head.starts_with(&[0xFF, 0xFE]) {
        return unicode("UTF-16", true, true);
    }
    if head.starts_with(&[0xFE, 0xFF]) {
        return unicode("UTF-16", false, true);
    }
    let nul = head.iter().position(|&b| b == 0);
    if let Some(at) = nul {
        return Some(match zero_pattern(head) {
            Some((encoding, little_endian)) => NotText::Unicode {
                encoding,
                little_endian,
                bom: false,
            },
            None => NotText::Binary { nul: Some(at) },
        });
    }
    if mostly_not_text(head) {
        return Some(NotText::Binary { nul: None });
    }
    None
}

/// The encoding whose zero bytes `head` has: ASCII characters leave three
/// zero bytes of four in UTF-32 and one of two in UTF-16, on the side
/// their byte order puts them.
fn zero_pattern(head: &[u8]) -> Option<(&'static str, bool)> {
    let mut zeros = [0usize; 4];
    for (i, &b) in head.iter().enumerate() {
        if b == 0 {
            zeros[i % 4] += 1;
        }
    }
    let per_slot = head.len() / 4;
    if per_slot == 0 {
        return None;
    }
    // A slot is "all zero" when nine in ten of its bytes are, and "text"
    // when fewer than one in ten are.
    let all = |slot: usize| zeros[slot] * 10 >= per_slot * 9;
    let text = |slot: usize| zeros[slot] * 10 < per_slot;
    if text(0) && all(1) && all(2) && all(3) {
        return Some(("UTF-32", true));
    }
    if all(0) && all(1) && all(2) && text(3) {
        return Some(("UTF-32", false));
    }
    if text(0) && text(2) && all(1) && all(3) {
        return Some(("UTF-16", true));
    }
    if all(0) && all(2) && text(1) && text(3) {
        return Some(("UTF-16", false));
    }
    None
}

/// Whether more than one byte in ten of `head` is in an invalid UTF-8
/// sequence or is a control character text does not use (any but tab,
/// line feed, vertical tab, form feed, carriage return and escape).
fn mostly_not_text(head: &[u8]) -> bool {
    let mut bad = 0;
    let mut rest = head;
    while !rest.is_empty() {
        match std::str::from_utf8(rest) {
            Ok(valid) => {
                bad += controls(valid);
                break;
            }
            Err(error) => {
                let valid = error.valid_up_to();
                // Checked by `from_utf8` up to `valid`.
                bad += controls(std::str::from_utf8(&rest[..valid]).unwrap_or_default());
                // A sequence cut by the end of the head is not bad.
                let Some(len) = error.error_len() else { break };
                bad += len;
                rest = &rest[valid + len..];
            }
        }
    }
    bad * 10 > head.len()
}

fn controls(text: &str) -> usize {
    text.bytes()
        .filter(|&b| {
            (b < 0x20 && !matches!(b, b'\t' | b'\n' | 0x0B | 0x0C | b'\r' | 0x1B)) || b == 0x7F
        })
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn utf16(text: &str, little_endian: bool, bom: bool) -> Vec<u8> {
        let mut bytes = Vec::new();
        let units = bom.then_some(0xFEFF).into_iter().chain(text.encode_utf16());
        for unit in units {
            let pair = if little_endian {
                unit.to_le_bytes()
            } else {
                unit.to_be_bytes()
            };
            bytes.extend(pair);
        }
        bytes
    }

    fn utf32(text: &str, little_endian: bool, bom: bool) -> Vec<u8> {
        let mut bytes = Vec::new();
        for c in bom.then_some('\u{feff}').into_iter().chain(text.chars()) {
            let quad = if little_endian {
                u32::from(c).to_le_bytes()
            } else {
                u32::from(c).to_be_bytes()
            };
            bytes.extend(quad);
        }
        bytes
    }

    const SCENE: &str = "camera 400\nsphere\n  dimension 1\n  center 0 0 -5\n";

    #[test]
    fn utf16_and_utf32_are_named_with_and_without_a_mark() {
        for little_endian in [true, false] {
            for bom in [true, false] {
                assert_eq!(
                    sniff(&utf16(SCENE, little_endian, bom)),
                    Some(NotText::Unicode {
                        encoding: "UTF-16",
                        little_endian,
                        bom
                    })
                );
                assert_eq!(
                    sniff(&utf32(SCENE, little_endian, bom)),
                    Some(NotText::Unicode {
                        encoding: "UTF-32",
                        little_endian,
                        bom
                    })
                );
            }
        }
    }

    #[test]
    fn text_is_text_even_with_a_few_bad_bytes() {
        assert_eq!(sniff(SCENE.as_bytes()), None);
        assert_eq!(sniff(b""), None);
        assert_eq!(sniff("\u{feff}camera 4".as_bytes()), None);
        assert_eq!(sniff(b"# sc\xe8ne en Latin-1\ncamera 400\n"), None);
        assert_eq!(sniff(b"camera 4 \x1b[31m # an escape\n"), None);
    }

    #[test]
    fn binaries_and_random_bytes_are_binary() {
        assert_eq!(
            sniff(b"\x7fELF\x02\x01\x01\0\0\0"),
            Some(NotText::Binary { nul: Some(7) })
        );
        // Bytes from a fixed linear congruential sequence, without NULs.
        let mut state = 12345u32;
        let noise: Vec<u8> = (0..4096)
            .map(|_| {
                state = state.wrapping_mul(1_103_515_245).wrapping_add(12345);
                ((state >> 16) as u8).max(1)
            })
            .collect();
        assert_eq!(sniff(&noise), Some(NotText::Binary { nul: None }));
    }
}
