//! Fuzz target: the language server's edit path (`textDocument/didChange`
//! through [`Document::apply`], then [`Document::diagnostics`]).
//!
//! The input decodes into an initial text and batches of content changes,
//! as a client sends them: whole-text replacements and ranges in UTF-16
//! positions, including lines and columns past the end, inverted ranges,
//! columns inside a surrogate pair or a line end, and `u32::MAX`. The
//! properties:
//!
//! - nothing panics;
//! - the document's text equals that of a reference model which applies the
//!   same changes to the text's UTF-16 code units, with the clamping the
//!   server documents (`lsp::position::Positions::offset`): a line past the
//!   end is the end of the text, a column past its line's end (line ends
//!   excluded) is that end, a column inside a surrogate pair is the end of
//!   that character, and an end before the start is the start;
//! - the diagnostics for the final text are those of the front end call
//!   `raytracer check` makes (`frontend::load_bytes_as`), one for one: the
//!   same code, severity, message with its help, and the range of the first
//!   label (and of each labelled label) converted by the model's own UTF-16
//!   line and column count.

#![no_main]

use std::path::Path;

use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use lsp_types::{
    DiagnosticSeverity, NumberOrString, Position, Range, TextDocumentContentChangeEvent, Url,
};
use raytracer_scene::frontend::{load_bytes_as, Language};
use raytracer_app::lsp::Document;

fuzz_target!(|bytes: &[u8]| {
    let Ok((text, batches)) = decode(&mut Unstructured::new(bytes)) else {
        return;
    };
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/ui/scene"));
    let uri = Url::from_file_path(dir.join("fuzz.txt")).expect("an absolute path");
    let mut document = Document::new(uri, text.clone(), 0, "raytracer");
    let mut model: Vec<u16> = text.encode_utf16().collect();
    for (version, changes) in batches.into_iter().enumerate() {
        for change in &changes {
            apply(&mut model, change);
        }
        document.apply(changes, version as i32 + 1);
        let expected = String::from_utf16(&model).expect("the model splits no surrogate pair");
        assert_eq!(document.text, expected, "the text after version {version}");
    }

    document.check_if_changed(None);
    let text = &document.text;
    let loaded = load_bytes_as(
        Language::Text,
        &document.name(),
        &document.dir,
        text.as_bytes(),
    );
    let published = document.diagnostics();
    let entries: Vec<_> = loaded.report.entries().collect();
    assert_eq!(published.len(), entries.len(), "diagnostic count");
    let units: Vec<u16> = text.encode_utf16().collect();
    for ((diagnostic, _), entry) in published.iter().zip(&entries) {
        let code = (!entry.code.is_empty()).then(|| NumberOrString::String(entry.code.clone()));
        assert_eq!(diagnostic.code, code);
        let severity = match entry.severity {
            "error" => DiagnosticSeverity::ERROR,
            "warning" => DiagnosticSeverity::WARNING,
            _ => DiagnosticSeverity::HINT,
        };
        assert_eq!(diagnostic.severity, Some(severity), "{}", entry.code);
        let mut message = entry.message.clone();
        if let Some(help) = &entry.help {
            message.push_str(&format!("\nhelp: {help}"));
        }
        assert_eq!(diagnostic.message, message);
        let range_of = |offset: usize, length: usize| {
            Range::new(
                position(text, &units, offset),
                position(text, &units, offset + length),
            )
        };
        let first = entry.labels.first();
        let range = first.map_or(Range::default(), |l| range_of(l.byte_offset, l.byte_length));
        assert_eq!(diagnostic.range, range, "{}", entry.code);
        let labelled: Vec<(Range, String)> = entry
            .labels
            .iter()
            .filter_map(|l| Some((range_of(l.byte_offset, l.byte_length), l.label.clone()?)))
            .collect();
        let related = diagnostic
            .related_information
            .as_deref()
            .unwrap_or_default();
        assert!(related.len() >= labelled.len(), "{}", entry.code);
        for (info, (range, label)) in related.iter().zip(&labelled) {
            assert_eq!((&info.location.range, &info.message), (range, label));
        }
    }
});

/// An initial text, then batches (one `didChange` each) of one to four
/// changes.
type Input = (String, Vec<Vec<TextDocumentContentChangeEvent>>);

fn decode(u: &mut Unstructured) -> Result<Input> {
    let text: String = u.arbitrary()?;
    let mut batches = Vec::new();
    while !u.is_empty() && batches.len() < 16 {
        let count = u.int_in_range(1..=4)?;
        let mut changes = Vec::new();
        for _ in 0..count {
            let range = if u.ratio(1, 16)? {
                None
            } else {
                Some(Range::new(decode_position(u)?, decode_position(u)?))
            };
            changes.push(TextDocumentContentChangeEvent {
                range,
                range_length: None,
                text: u.arbitrary()?,
            });
        }
        batches.push(changes);
    }
    Ok((text, batches))
}

/// A position near the text, or (rarely) the largest a client can send.
fn decode_position(u: &mut Unstructured) -> Result<Position> {
    let mut coordinate = || -> Result<u32> {
        Ok(match u.arbitrary::<u8>()? {
            255 => u32::MAX,
            n => u32::from(n),
        })
    };
    Ok(Position::new(coordinate()?, coordinate()?))
}

/// The model's edit: the change applied to UTF-16 code units.
fn apply(model: &mut Vec<u16>, change: &TextDocumentContentChangeEvent) {
    let replacement = change.text.encode_utf16();
    match change.range {
        None => *model = replacement.collect(),
        Some(range) => {
            let start = unit_index(model, range.start);
            let end = unit_index(model, range.end).max(start);
            model.splice(start..end, replacement);
        }
    }
}

const CR: u16 = b'\r' as u16;
const LF: u16 = b'\n' as u16;

/// Where each line starts: after `\n`, and after a `\r` not followed by `\n`.
fn line_starts(units: &[u16]) -> Vec<usize> {
    let mut starts = vec![0];
    for (i, &unit) in units.iter().enumerate() {
        if unit == LF || (unit == CR && units.get(i + 1) != Some(&LF)) {
            starts.push(i + 1);
        }
    }
    starts
}

/// The code unit index of `position`, clamped as the server documents.
fn unit_index(units: &[u16], position: Position) -> usize {
    let Some(&start) = line_starts(units).get(position.line as usize) else {
        return units.len();
    };
    let line_end = units[start..]
        .iter()
        .position(|&u| u == CR || u == LF)
        .map_or(units.len(), |i| start + i);
    let index = start
        .saturating_add(position.character as usize)
        .min(line_end);
    let inside_pair = index > start
        && index < units.len()
        && (0xDC00..0xE000).contains(&units[index])
        && (0xD800..0xDC00).contains(&units[index - 1]);
    index + usize::from(inside_pair)
}

/// The position of byte `offset` of `text` (whose code units are `units`),
/// counted in code units from the line's start.
fn position(text: &str, units: &[u16], offset: usize) -> Position {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let index = text[..offset].encode_utf16().count();
    let starts = line_starts(units);
    let line = starts.partition_point(|&s| s <= index) - 1;
    Position::new(line as u32, (index - starts[line]) as u32)
}
