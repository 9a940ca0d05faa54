//! Checking a large scene text on two threads.
//!
//! The text is cut at a section start near its middle, each half is parsed
//! and checked on its own thread, and the two checks are joined
//! ([`SceneCheck::then`]) before the checks that need the whole file. A
//! cut is safe where the parser, reading the whole text, would start a
//! section whatever came before: at a section keyword that begins a line
//! and is followed by an ASCII space. No token spans a `\n` (a comment or
//! a string, closed or not, ends at the line's end), so at the start of a
//! line the parser is between tokens, and a section keyword there ends any
//! section before it and is never a value (a keyword is no texture path).
//! The second half's spans are offsets into the whole text
//! ([`syntax::sections_between`]), and its syntax errors and diagnostics
//! follow the first half's, as one run gives them. When the second half
//! met something whose check depends on the first (a second camera, the
//! object limit, textures over the shared texel budget), the join declines
//! and the caller checks the whole text in one run instead.

use crate::syntax;

/// Texts shorter than this are checked on one thread: starting a thread
/// costs more than half of checking a small scene.
pub const PARALLEL_MIN_BYTES: usize = 4 << 20;

/// Section keywords that start a line and are followed by an ASCII space:
/// safe cuts, as offsets of the keyword. The first found at or after `from`.
pub fn cut_at_or_after(text: &str, from: usize) -> Option<usize> {
    let bytes = text.as_bytes();
    let mut at = from.min(bytes.len());
    while let Some(newline) = memchr::memchr(b'\n', &bytes[at..]) {
        let start = at + newline + 1;
        if is_cut(bytes, start) {
            return Some(start);
        }
        at = start;
    }
    None
}

/// True when `start`, just after a `\n`, begins a section keyword followed
/// by an ASCII space.
fn is_cut(bytes: &[u8], start: usize) -> bool {
    let line = &bytes[start..];
    crate::ast::SectionKind::KEYWORDS.iter().any(|keyword| {
        line.strip_prefix(keyword.as_bytes())
            .and_then(|after| after.first())
            .is_some_and(|b| matches!(b, b' ' | b'\t' | b'\n' | b'\r' | 0x0b | 0x0c))
    })
}

/// Where to cut `text` for two threads: the first safe cut past its
/// middle, when the text is long enough to gain from it.
pub fn cut(text: &str) -> Option<usize> {
    if text.len() < PARALLEL_MIN_BYTES {
        return None;
    }
    cut_at_or_after(text, text.len() / 2)
}

/// The sections of `text` before `cut` and from `cut` on, each with the
/// syntax errors of its part.
pub fn halves(text: &str, cut: usize) -> [syntax::Sections<'_>; 2] {
    [
        syntax::sections_between(text, 0, cut),
        syntax::sections_between(text, cut, text.len()),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cuts_only_at_line_starts_of_section_keywords() {
        let text =
            "camera 4\n# sphere\nx sphere 1\n\"sphere\nsphere\tdimension 1\nplane\nlights 1\nlight";
        let cuts: Vec<&str> =
            std::iter::successors(cut_at_or_after(text, 0), |&at| cut_at_or_after(text, at))
                .map(|at| &text[at..at + 6])
                .collect();
        // `light` at the very end is followed by no space: no cut there.
        assert_eq!(cuts, ["sphere", "plane\n"]);
    }

    #[test]
    fn only_large_texts_are_cut_near_their_middle() {
        let sphere = "sphere dimension 1 center 0 0 -5\n";
        let small = format!("camera 4\n{}", sphere.repeat(1000));
        assert_eq!(cut(&small), None);
        let large = format!(
            "camera 4\n{}",
            sphere.repeat(PARALLEL_MIN_BYTES / sphere.len() + 1)
        );
        let at = cut(&large).expect("a large text is cut");
        assert!(at >= large.len() / 2 && at - large.len() / 2 <= sphere.len());
        assert!(large[at..].starts_with("sphere "));
    }
}
