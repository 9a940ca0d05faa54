//! Completion at a cursor in scene text:
//! - after `texture`, the image files in the document's folder;
//! - where a number is still expected (an attribute short of its values,
//!   a camera without its size), nothing;
//! - inside a section, the attributes it can still take (not those already
//!   given, not those of other sections), and the section keywords;
//! - before any section, the section keywords.

use lsp_types::{CompletionItem, CompletionItemKind};

use super::document::Document;
use crate::ast::{AttrName, SectionKind};
use crate::frontend::{self, Language};
use crate::language::{self, Arity};
use crate::syntax::is_word_char;

/// Extensions of the texture formats the renderer reads.
const TEXTURE_EXTENSIONS: [&str; 5] = ["ppm", "pnm", "png", "jpg", "jpeg"];

/// The completions at byte `offset` of `document`.
pub fn complete(document: &Document, offset: usize) -> Vec<CompletionItem> {
    if document.language != Language::Text {
        return Vec::new();
    }
    let text = &document.text;
    let offset = crate::span::floor_char_boundary(text, offset);
    // The word being typed, and what came before it.
    let word_start = text[..offset]
        .char_indices()
        .rev()
        .take_while(|&(_, c)| is_word_char(c))
        .last()
        .map_or(offset, |(i, _)| i);
    let before = text[..word_start].trim_end();
    let previous_word = before
        .rsplit(|c: char| !is_word_char(c))
        .next()
        .unwrap_or("");
    if previous_word == "texture" && before.len() < word_start {
        return texture_files(document);
    }
    let Some(file) = frontend::parse(Language::Text, &text[..word_start]).0 else {
        return Vec::new();
    };
    let mut items = Vec::new();
    if let Some(section) = file.sections.last() {
        if let Some(last) = section.attributes.last() {
            if let Some(spec) = language::find(&section.kind, &last.name) {
                if let Arity::Numbers(n) = spec.arity {
                    if last.values.len() < n {
                        return Vec::new();
                    }
                }
            }
        } else if *section.kind == SectionKind::Camera && section.args.is_empty() {
            return Vec::new();
        }
        let given: Vec<&AttrName> = section.attributes.iter().map(|a| &*a.name).collect();
        for spec in language::attributes_of(&section.kind) {
            if !given.contains(&&spec.name) {
                items.push(CompletionItem {
                    label: spec.name.as_str().to_string(),
                    kind: Some(CompletionItemKind::PROPERTY),
                    detail: Some(format!("{} {}", spec.name.as_str(), spec.placeholder)),
                    ..CompletionItem::default()
                });
            }
        }
    }
    items.extend(SectionKind::KEYWORDS.iter().map(|keyword| CompletionItem {
        label: keyword.to_string(),
        kind: Some(CompletionItemKind::KEYWORD),
        detail: Some("section".to_string()),
        ..CompletionItem::default()
    }));
    items
}

/// The texture files in the document's folder, sorted.
fn texture_files(document: &Document) -> Vec<CompletionItem> {
    let Ok(entries) = std::fs::read_dir(&document.dir) else {
        return Vec::new();
    };
    let mut names: Vec<String> = entries
        .flatten()
        .map(|e| e.path())
        .filter(|p| {
            p.is_file()
                && p.extension()
                    .and_then(|e| e.to_str())
                    .is_some_and(|e| TEXTURE_EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()))
        })
        .filter_map(|p| Some(p.file_name()?.to_str()?.to_string()))
        .collect();
    names.sort();
    names
        .into_iter()
        .map(|name| CompletionItem {
            // A name with spaces, `#` or quotes is written as a string.
            insert_text: (!name.chars().all(is_word_char))
                .then(|| format!("\"{}\"", name.replace('\\', "\\\\").replace('"', "\\\""))),
            label: name,
            kind: Some(CompletionItemKind::FILE),
            ..CompletionItem::default()
        })
        .collect()
}
