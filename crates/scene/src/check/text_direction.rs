//! The warning for Unicode text-direction controls anywhere in a scene's
//! text, comments and strings included (rustc's
//! `text_direction_codepoint_in_literal`): an editor or terminal that obeys
//! them shows the text reordered, so what a reviewer reads is not what the
//! renderer reads ("Trojan Source", CVE-2021-42574).

use crate::escape::is_text_direction_control;
use crate::fix::{Applicability, Fix};
use crate::span::Span;

use super::errors::CheckError;

/// One warning per text-direction control in `text`.
pub fn warnings(text: &str) -> impl Iterator<Item = CheckError> + '_ {
    // Every such control is encoded as three bytes led by 0xE2; finding
    // that byte first with memchr's vectorised search keeps the scan of a
    // large scene to a fraction of the time a byte loop takes.
    memchr::memchr_iter(0xE2, text.as_bytes()).filter_map(move |at| {
        let control = text.get(at..)?.chars().next()?;
        is_text_direction_control(control).then(|| {
            let span = Span::new(at, at + control.len_utf8());
            CheckError::TextDirectionControl {
                name: name(control),
                span: span.into(),
                help: "delete it: editors and terminals that obey it show the scene in another \
                       order than it is read"
                    .to_string(),
                fix: Some(Fix::boxed(
                    format!("delete the {}", name(control)),
                    Applicability::Unsafe,
                    span,
                    "",
                )),
            }
        })
    })
}

/// `U+202E (right-to-left override)`.
fn name(control: char) -> String {
    let name = match control {
        '\u{202A}' => "left-to-right embedding",
        '\u{202B}' => "right-to-left embedding",
        '\u{202C}' => "pop directional formatting",
        '\u{202D}' => "left-to-right override",
        '\u{202E}' => "right-to-left override",
        '\u{2066}' => "left-to-right isolate",
        '\u{2067}' => "right-to-left isolate",
        '\u{2068}' => "first strong isolate",
        _ => "pop directional isolate",
    };
    format!("U+{:04X} ({name})", u32::from(control))
}

#[cfg(test)]
mod tests {
    use miette::Diagnostic;

    use super::*;

    #[test]
    fn every_control_is_found_where_it_is_and_nothing_else() {
        let text = "# \u{202e}comment\nsphere \u{2066}\u{2069} \u{2014} é \u{200f}\n";
        let found: Vec<(usize, usize)> = warnings(text)
            .map(|w| {
                let label = w.labels().unwrap().next().unwrap();
                (label.offset(), label.len())
            })
            .collect();
        let expected: Vec<(usize, usize)> = text
            .char_indices()
            .filter(|&(_, c)| is_text_direction_control(c))
            .map(|(i, c)| (i, c.len_utf8()))
            .collect();
        assert_eq!(found.len(), 3);
        assert_eq!(found, expected);
        assert_eq!(name('\u{202e}'), "U+202E (right-to-left override)");
        assert_eq!(name('\u{2069}'), "U+2069 (pop directional isolate)");
    }
}
