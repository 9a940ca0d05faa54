//! Hover: on a section keyword, what the section takes; on an attribute
//! name, what it means (units), its values, rule, default and an example,
//! and where it belongs, all from the registry ([`raytracer_scene::language`]); on a
//! texture path, the file it resolves to (from the document's folder, as
//! the check pass resolves it) and its size in pixels, read from the
//! image's header alone. Scene text only: a JSON scene's keys are
//! described by its schema.

use lsp_types::{Hover, HoverContents, MarkupContent, MarkupKind};

use super::document::Document;
use super::position::Positions;
use raytracer_scene::ast::{AttrName, SectionKind, Value};
use raytracer_scene::frontend::{self, Language};
use raytracer_scene::language::{self, Arity, AttrSpec, Key};
use raytracer_scene::span::Span;

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
                Some(spec) => describe_attribute(&section.kind, &attribute.name, spec),
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
        range: Some(Positions::new(&document.text).range(span)),
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

/// Whether `spec` must be given, and its default.
fn need(kind: &SectionKind, spec: &AttrSpec) -> String {
    match (&spec.name, spec.default) {
        (Key::Resolution, _) => "one per scene".to_string(),
        _ if spec.required => format!("required in every `{}`", kind.as_str()),
        (_, Some(default)) => format!(
            "optional in a `{}`; default `{}`",
            kind.as_str(),
            default.text()
        ),
        _ => format!("optional in a `{}`", kind.as_str()),
    }
}

fn describe_section(kind: &SectionKind) -> String {
    let keyword = kind.as_str();
    let attributes = language::attributes_of(kind);
    match kind {
        SectionKind::Camera => {
            let spec = &language::CAMERA;
            format!(
                "**camera** `{}`: {}; at the origin, looking down −z\n\n{}",
                spec.placeholder,
                spec.description,
                values_and_example(kind, spec),
            )
        }
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

fn describe_attribute(kind: &SectionKind, name: &AttrName, spec: &AttrSpec) -> String {
    let sections = language::sections_taking(name);
    format!(
        "**{}** `{}`: {}\n\n{}\n\nTaken by {}.",
        spec.name.as_str(),
        spec.placeholder,
        spec.description,
        values_and_example(kind, spec),
        language::list(&sections)
    )
}

/// What an attribute's values are, whether `kind` needs it, its rule and
/// an example line: the part of the camera's and every attribute's hover
/// they share.
fn values_and_example(kind: &SectionKind, spec: &AttrSpec) -> String {
    format!(
        "{}, {}; {}.\n\n```\n{}\n```",
        values_of(spec),
        need(kind, spec),
        spec.rule(),
        spec.example,
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
            let size = match header_dimensions(&resolved) {
                Some((width, height)) => format!("{width} × {height} pixels"),
                None => "not an image this renderer reads (PPM, PNG or JPEG)".to_string(),
            };
            format!("texture `{}`\n\n{size}", resolved.display())
        }
        Ok(_) => format!("`{}` is not a file", resolved.display()),
        Err(_) => format!("`{}` does not exist", resolved.display()),
    }
}

/// The width and height an image's header gives, without decoding its
/// pixels (a hover on a large texture reads a few bytes, not the image).
fn header_dimensions(path: &std::path::Path) -> Option<(u32, u32)> {
    image::ImageReader::open(path)
        .ok()?
        .with_guessed_format()
        .ok()?
        .into_dimensions()
        .ok()
}

#[cfg(test)]
mod tests {
    use lsp_types::Url;

    use super::*;

    fn hover_text(dir: &std::path::Path, text: &str, at: &str) -> String {
        let uri = Url::from_file_path(dir.join("scene.txt")).expect("an absolute path");
        let document = Document::new(uri, text.to_string(), 1, "raytracer");
        let offset = text.find(at).expect("the hovered word");
        match hover(&document, offset).map(|h| h.contents) {
            Some(HoverContents::Markup(markup)) => markup.value,
            other => panic!("no markdown hover: {other:?}"),
        }
    }

    #[test]
    fn positions_have_a_rule_and_the_camera_its_range() {
        let dir = std::env::temp_dir();
        let text = "camera 4\nsphere dimension 1 center 0 0 -5\nlight location 0 5 0 color 1 1 1\n";
        for word in ["center", "location"] {
            let shown = hover_text(&dir, text, word);
            assert!(!shown.contains('—'), "{shown}");
            assert!(shown.contains("any numbers"), "{shown}");
        }
        let camera = hover_text(&dir, text, "camera");
        assert!(
            camera.contains("a whole number from 1 to 16384"),
            "{camera}"
        );
    }

    #[test]
    fn a_texture_shows_its_pixel_size_from_the_header() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        // A header for 3 × 2 pixels and no pixel data: only the header is
        // read.
        std::fs::write(dir.path().join("wood.ppm"), "P6\n3 2\n255\n").expect("write");
        let text = "camera 4\nsphere dimension 1 center 0 0 -5 texture wood.ppm\n";
        let shown = hover_text(dir.path(), text, "wood.ppm");
        assert!(shown.contains("3 × 2 pixels"), "{shown}");
        assert!(!shown.contains("bytes"), "{shown}");
    }
}
