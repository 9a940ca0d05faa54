//! The canonical scene-text printer (`convert --to scene`).
//!
//! The layout is the formatter's, printed by its [`Printer`]: the camera line, then
//! each object in order, then each light, one blank line between sections;
//! attributes two spaces in, in the order of the language table
//! ([`crate::language`], which docs/language.md shows: `dimension`,
//! `center`, `normal`, `headup`, `color`, `reflectivity`, `texture`); a
//! `color` of `1 1 1` and a `reflectivity` of `0` (the defaults) are left out.
//!
//! Numbers are spelt as the formatter spells them, the shortest text that
//! reads back as the same `f64`, bit for bit ([`number`]), and the
//! attributes are in the formatter's order, so this text is what `fmt`
//! prints for it; texture paths are bare words where the grammar
//! reads them back as one, quoted strings otherwise ([`path`]).

use crate::ast::{AttrName, SectionKind};
use crate::format::{number, Printer};
use crate::language::attributes_of;
use crate::model::{self, Shape};
use crate::syntax::{is_line_end, is_word_char};

use super::UnprintablePath;

/// `scene` as canonical scene text, ending in a newline.
pub fn to_scene_text(scene: &model::Scene) -> Result<String, UnprintablePath> {
    let mut out = Printer::default();
    out.section(&format!("camera {}", scene.camera.resolution), []);
    for object in &scene.objects {
        let kind = match object.shape {
            Shape::Sphere { .. } => SectionKind::Sphere,
            Shape::Plane { .. } => SectionKind::Plane,
        };
        section(&mut out, &kind, |name| object_value(object, name))?;
    }
    for light in &scene.lights {
        section(&mut out, &SectionKind::Light, |name| match name {
            AttrName::Location => Printed::Numbers(light.location.to_vec()),
            AttrName::Color => Printed::Numbers(light.color.to_vec()),
            _ => Printed::Omitted,
        })?;
    }
    Ok(out.finish())
}

/// What an attribute line prints.
enum Printed<'a> {
    Numbers(Vec<f64>),
    Path(&'a str),
    /// Not printed: the default, or not an attribute of this object.
    Omitted,
}

/// The keyword, then each attribute `value_of` gives, in the order of the
/// language table ([`attributes_of`]).
fn section<'a>(
    out: &mut Printer,
    kind: &SectionKind,
    value_of: impl Fn(&AttrName) -> Printed<'a>,
) -> Result<(), UnprintablePath> {
    let mut lines = Vec::new();
    for spec in attributes_of(kind) {
        let name = spec.name.as_str();
        match value_of(&spec.attr_name()) {
            Printed::Numbers(values) => {
                let values: Vec<String> = values.into_iter().map(number).collect();
                lines.push(format!("{name} {}", values.join(" ")));
            }
            Printed::Path(texture) => lines.push(format!("{name} {}", path(texture)?)),
            Printed::Omitted => {}
        }
    }
    out.section(kind.as_str(), lines.iter().map(String::as_str));
    Ok(())
}

/// The value of attribute `name` of a sphere or plane; a `color` of
/// `1 1 1` and a `reflectivity` of `0` (the defaults) are omitted.
fn object_value<'a>(object: &'a model::Object, name: &AttrName) -> Printed<'a> {
    let material = &object.material;
    let default = model::Material::default();
    match (name, &object.shape) {
        (AttrName::Dimension, Shape::Sphere { radius, .. }) => Printed::Numbers(vec![*radius]),
        (AttrName::Dimension, Shape::Plane { width, height, .. }) => {
            Printed::Numbers(vec![*width, *height])
        }
        (AttrName::Center, Shape::Sphere { center, .. } | Shape::Plane { center, .. }) => {
            Printed::Numbers(center.to_vec())
        }
        (AttrName::Normal, Shape::Plane { normal, .. }) => Printed::Numbers(normal.to_vec()),
        (AttrName::Headup, Shape::Plane { headup, .. }) => Printed::Numbers(headup.to_vec()),
        (AttrName::Color, _) if !same_bits(&material.color, &default.color) => {
            Printed::Numbers(material.color.to_vec())
        }
        (AttrName::Reflectivity, _)
            if !same_bits(&[material.reflectivity], &[default.reflectivity]) =>
        {
            Printed::Numbers(vec![material.reflectivity])
        }
        (AttrName::Texture, _) => material
            .texture
            .as_deref()
            .map_or(Printed::Omitted, Printed::Path),
        _ => Printed::Omitted,
    }
}

/// Equal bit for bit, so a `-0` reflectivity is printed, not dropped.
fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.iter()
        .map(|x| x.to_bits())
        .eq(b.iter().map(|x| x.to_bits()))
}

/// A texture path as the grammar reads it back: a bare word when it is one
/// and is no keyword (which the parser would read as a keyword instead), a
/// double-quoted string with `\"` and `\\` escapes otherwise.
pub fn path(path: &str) -> Result<String, UnprintablePath> {
    if path.chars().any(is_line_end) {
        return Err(UnprintablePath {
            path: path.to_string(),
        });
    }
    let keyword = !matches!(SectionKind::from_word(path), SectionKind::Unknown(_))
        || !matches!(AttrName::from_word(path), AttrName::Unknown(_));
    if !path.is_empty() && !keyword && path.chars().all(is_word_char) {
        return Ok(path.to_string());
    }
    let escaped = path.replace('\\', "\\\\").replace('"', "\\\"");
    Ok(format!("\"{escaped}\""))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short_exact_and_grammatical() {
        for (x, text) in [
            (0.3, "0.3"),
            (1.0, "1"),
            (-2.0, "-2"),
            (16384.0, "16384"),
            (-0.0, "-0"),
            (0.0, "0"),
            (1e-5, "0.00001"),
            (1e-7, "1e-7"),
            (1e15, "1e15"),
            (1e300, "1e300"),
            (-1.5e-300, "-1.5e-300"),
            (f64::MAX, "1.7976931348623157e308"),
            (f64::MIN_POSITIVE, "2.2250738585072014e-308"),
            (5e-324, "5e-324"),
            (0.1 + 0.2, "0.30000000000000004"),
        ] {
            assert_eq!(number(x), text);
            let back: f64 = text.parse().unwrap();
            assert_eq!(back.to_bits(), x.to_bits(), "{text}");
            let parsed = crate::syntax::parse(&format!("camera {text}"));
            assert!(parsed.errors.is_empty(), "{text}: {:?}", parsed.errors);
        }
    }

    #[test]
    fn paths_are_bare_words_or_quoted_strings() {
        assert_eq!(path("wood_tex.ppm").unwrap(), "wood_tex.ppm");
        assert_eq!(path("dir/1.ppm").unwrap(), "dir/1.ppm");
        assert_eq!(path("my wood.ppm").unwrap(), "\"my wood.ppm\"");
        assert_eq!(path("a\"b\\c.ppm").unwrap(), r#""a\"b\\c.ppm""#);
        assert_eq!(path("#1.ppm").unwrap(), "\"#1.ppm\"");
        assert_eq!(path("").unwrap(), "\"\"");
        assert_eq!(path("color").unwrap(), "\"color\"");
        assert_eq!(path("plane").unwrap(), "\"plane\"");
        assert_eq!(path("a\u{2028}b").unwrap_err().path, "a\u{2028}b");
    }
}
