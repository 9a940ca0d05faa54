//! Hover: on a section keyword, what the section takes; on an attribute
//! name, what it means (units), its values, rule, default and an example,
//! and where it belongs, from the language table ([`crate::language`]); on a texture path, the file it resolves to (from
//! the document's folder, as the check pass resolves it) and its size.
//! Scene text only: a JSON scene's keys are described by its schema.

use lsp_types::{Hover, HoverContents, MarkupContent, MarkupKind};

use super::document::Document;
use super::position::LineIndex;
use crate::ast::{AttrName, SectionKind, Value};
use crate::frontend::{self, Language};
use crate::language::{self, Arity, AttrSpec};
use crate::span::Span;

/// The hover at byte `offset` of `document`, if it is on something known.
pub fn hover(document: &Document, offset: usize) -> Option<Hover> {
    if document.language != Language::Text {
        return None;
    }
    let file = frontend::parse(document.language, &document.text).0?;
    let within = |span: Span| span.start() <= offset && offset <= span.end();
    let section = file
        .sections
        .iter()
        .take_while(|s| s.kind.span.start() <= offset)
        .last()?;
    let (text, span) = if within(section.kind.span) {
        (describe_section(&section.kind), section.kind.span)
    } else {
        let attribute = section.attributes.iter().find(|a| within(a.span))?;
        if within(attribute.name.span) {
            let text = match language::find(&section.kind, &attribute.name) {
                Some(spec) => describe_attribute(&section.kind, spec),
                None => describe_misplaced(&section.kind, &attribute.name),
            };
            (text, attribute.name.span)
        } else {
            let path = attribute.values.first().filter(|v| within(v.span))?;
            match (&*attribute.name, &path.value) {
                (AttrName::Texture, Value::Text(text)) => {
                    (describe_texture(document, text), path.span)
                }
                _ => return None,
            }
        }
    };
    Some(Hover {
        contents: HoverContents::Markup(MarkupContent {
            kind: MarkupKind::Markdown,
            value: text,
        }),
        range: Some(LineIndex::new(&document.text).range(span)),
    })
}

fn form(spec: &AttrSpec) -> String {
    format!("{} {}", spec.name.as_str(), spec.placeholder)
}

fn values_of(spec: &AttrSpec) -> String {
    match spec.arity {
        Arity::Numbers(1) => "one number".to_string(),
        Arity::Numbers(n) => format!("{n} numbers"),
        Arity::Path => "a texture file, relative to the scene's folder".to_string(),
    }
}

fn describe_section(kind: &SectionKind) -> String {
    let keyword = kind.as_str();
    let attributes = language::attributes_of(kind);
    match kind {
        SectionKind::Camera => "**camera** `N`: the image is N × N pixels; one per scene, \
            at the origin, looking down −z"
            .to_string(),
        SectionKind::Unknown(_) => format!(
            "`{keyword}` is no section keyword; the sections are {}",
            language::list_or(&SectionKind::KEYWORDS)
        ),
        _ => {
            let mut text = format!("**{keyword}**: a section with these attributes\n");
            for spec in attributes {
                let need = if spec.required {
                    "required"
                } else {
                    "optional"
                };
                text.push_str(&format!(
                    "\n- `{}`: {}, {need}",
                    form(spec),
                    values_of(spec)
                ));
            }
            text
        }
    }
}

fn describe_attribute(kind: &SectionKind, spec: &AttrSpec) -> String {
    let need = match spec.default {
        _ if spec.required => format!("required in every `{}`", kind.as_str()),
        Some(default) => format!("optional in a `{}`; default `{default}`", kind.as_str()),
        None => format!("optional in a `{}`", kind.as_str()),
    };
    let sections = language::sections_taking(&spec.name);
    format!(
        "**{}** `{}`: {}\n\n{}, {need}; {}.\n\n```\n{}\n```\n\nTaken by {}.",
        spec.name.as_str(),
        spec.placeholder,
        spec.description,
        values_of(spec),
        spec.rule,
        spec.example,
        language::list(&sections)
    )
}

fn describe_misplaced(kind: &SectionKind, name: &AttrName) -> String {
    let sections = language::sections_taking(name);
    if sections.is_empty() {
        format!("`{}` is no attribute name", name.as_str())
    } else {
        format!(
            "`{}` belongs to {}, not to `{}`",
            name.as_str(),
            language::list(&sections),
            kind.as_str()
        )
    }
}

fn describe_texture(document: &Document, path: &str) -> String {
    let resolved = document.dir.join(path);
    match std::fs::metadata(&resolved) {
        Ok(meta) if meta.is_file() => {
            format!("texture `{}`\n\n{} bytes", resolved.display(), meta.len())
        }
        Ok(_) => format!("`{}` is not a file", resolved.display()),
        Err(_) => format!("`{}` does not exist", resolved.display()),
    }
}
