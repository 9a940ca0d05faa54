//! Document symbols: the outline of a scene, one symbol per section
//! (`camera`, `sphere 1`, `plane 1`, `sphere 2`, …) with its attributes as
//! children, for scene text and JSON scenes alike (both parse into the
//! same tree).

use std::collections::HashMap;

use lsp_types::{DocumentSymbol, SymbolKind};

use super::document::Document;
use super::position::Positions;
use raytracer_scene::ast::{SectionKind, Value};
use raytracer_scene::frontend;

/// The outline of `document` (as far as it parses).
pub fn symbols(document: &Document) -> Vec<DocumentSymbol> {
    let Some(file) = frontend::parse(document.language, &document.text).0 else {
        return Vec::new();
    };
    let index = Positions::new(&document.text);
    let mut counts: HashMap<String, usize> = HashMap::new();
    file.sections
        .iter()
        .map(|section| {
            let keyword = section.kind.as_str();
            let count = counts.entry(keyword.to_string()).or_default();
            *count += 1;
            let name = match *section.kind {
                SectionKind::Camera => keyword.to_string(),
                _ => format!("{keyword} {count}"),
            };
            let children = section
                .attributes
                .iter()
                .map(|attribute| {
                    #[allow(deprecated)] // `deprecated` is a required field
                    DocumentSymbol {
                        name: attribute.name.as_str().to_string(),
                        detail: Some(values(&attribute.values)),
                        kind: SymbolKind::PROPERTY,
                        tags: None,
                        deprecated: None,
                        range: index.range(attribute.span),
                        selection_range: index.range(attribute.name.span),
                        children: None,
                    }
                })
                .collect();
            #[allow(deprecated)]
            DocumentSymbol {
                name,
                detail: (!section.args.is_empty()).then(|| values(&section.args)),
                kind: match *section.kind {
                    SectionKind::Camera => SymbolKind::EVENT,
                    SectionKind::Light => SymbolKind::CONSTANT,
                    _ => SymbolKind::OBJECT,
                },
                tags: None,
                deprecated: None,
                range: index.range(section.span),
                selection_range: index.range(section.kind.span),
                children: Some(children),
            }
        })
        .collect()
}

/// Values as the outline shows them: `0 1 -5`, `wood.ppm`.
fn values(values: &[raytracer_scene::span::Spanned<Value>]) -> String {
    values
        .iter()
        .map(|v| match &v.value {
            Value::Number(n) => n.to_string(),
            Value::Text(t) => t.to_string(),
            Value::Invalid => "?".to_string(),
        })
        .collect::<Vec<_>>()
        .join(" ")
}
