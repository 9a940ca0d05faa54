//! Completion at a cursor in scene text, from the registry
//! ([`raytracer_scene::language`]):
//! - in a comment, nothing;
//! - after an attribute that takes a path (`texture`), the image files in
//!   the document's folder;
//! - where a number is still expected (an attribute short of its values,
//!   a camera without its size), nothing;
//! - inside a section, the attributes it can still take (not those already
//!   given, not those of other sections), and the section keywords;
//! - before any section, the section keywords;
//!
//! and `camera` only while the document has none (a scene has one).

use lsp_types::{CompletionItem, CompletionItemKind};

use super::document::Document;
use raytracer_scene::ast::{AttrName, SectionKind};
use raytracer_scene::frontend::{self, Language};
use raytracer_scene::language::{self, Arity};
use raytracer_scene::syntax::{is_word_char, trivia};

/// Extensions of the texture formats the renderer reads.
const TEXTURE_EXTENSIONS: [&str; 5] = ["ppm", "pnm", "png", "jpg", "jpeg"];

/// The completions at byte `offset` of `document`.
pub fn complete(document: &Document, offset: usize) -> Vec<CompletionItem> {
    if document.language != Language::Text {
        return Vec::new();
    }
    let text = &document.text;
    let offset = raytracer_scene::span::floor_char_boundary(text, offset);
    // The word being typed, and what came before it.
    let word_start = text[..offset]
        .char_indices()
        .rev()
        .take_while(|&(_, c)| is_word_char(c))
        .last()
        .map_or(offset, |(i, _)| i);
    let in_comment = trivia::comments(&text[..offset])
        .last()
        .is_some_and(|comment| comment.end() == offset);
    if in_comment {
        return Vec::new();
    }
    let before = text[..word_start].trim_end();
    let previous_word = before
        .rsplit(|c: char| !is_word_char(c))
        .next()
        .unwrap_or("");
    if takes_path(previous_word) && before.len() < word_start {
        return texture_files(document);
    }
    let Some(file) = frontend::parse(Language::Text, &text[..word_start]).0 else {
        return Vec::new();
    };
    let word_end = text[offset..]
        .find(|c: char| !is_word_char(c))
        .map_or(text.len(), |i| offset + i);
    let has_camera = |file: &raytracer_scene::ast::File| {
        file.sections.iter().any(|s| *s.kind == SectionKind::Camera)
    };
    let camera_elsewhere = has_camera(&file)
        || frontend::parse(Language::Text, &text[word_end..])
            .0
            .is_some_and(|after| has_camera(&after));
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
            if !given.iter().any(|name| spec.name == **name) {
                items.push(CompletionItem {
                    label: spec.name.as_str().to_string(),
                    kind: Some(CompletionItemKind::PROPERTY),
                    detail: Some(format!("{} {}", spec.name.as_str(), spec.placeholder)),
                    ..CompletionItem::default()
                });
            }
        }
    }
    let keywords = SectionKind::KEYWORDS
        .iter()
        .filter(|keyword| !(camera_elsewhere && **keyword == SectionKind::Camera.as_str()));
    items.extend(keywords.map(|keyword| CompletionItem {
        label: keyword.to_string(),
        kind: Some(CompletionItemKind::KEYWORD),
        detail: Some("section".to_string()),
        ..CompletionItem::default()
    }));
    items
}

/// Whether `word` is an attribute that takes a path in some section.
fn takes_path(word: &str) -> bool {
    AttrName::known(word).is_some_and(|name| language::takes_path_somewhere(&name))
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

#[cfg(test)]
mod tests {
    use lsp_types::Url;

    use super::*;

    fn labels(text: &str, offset: usize) -> Vec<String> {
        let uri = Url::from_file_path(std::env::temp_dir().join("scene.txt")).expect("a path");
        let document = Document::new(uri, text.to_string(), 1, "raytracer");
        let mut labels: Vec<String> = complete(&document, offset)
            .into_iter()
            .map(|item| item.label)
            .collect();
        labels.sort();
        labels
    }

    #[test]
    fn nothing_is_offered_in_a_comment() {
        let text = "camera 4\n# a note about the ";
        assert_eq!(labels(text, text.len()), Vec::<String>::new());
        let text = "camera 4 # the size\n";
        assert_eq!(
            labels(text, text.find("size").unwrap() + 2),
            Vec::<String>::new()
        );
    }

    #[test]
    fn camera_is_offered_only_while_there_is_none() {
        assert_eq!(labels("", 0), ["camera", "light", "plane", "sphere"]);
        let text = "camera 4\n";
        assert_eq!(labels(text, text.len()), ["light", "plane", "sphere"]);
        // A camera further down counts too.
        let text = "\nsphere dimension 1 center 0 0 -5\ncamera 4\n";
        assert!(!labels(text, 0).contains(&"camera".to_string()));
        // The word being typed is not a camera yet.
        assert!(labels("cam", 3).contains(&"camera".to_string()));
    }
}
