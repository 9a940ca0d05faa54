//! Which attributes each section takes: the attribute table of docs/language.md as
//! data, so the generic checks (unknown, misplaced, duplicate, count,
//! missing) need no per-section code.

use crate::ast::{AttrName, SectionKind};

/// What an attribute's values are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arity {
    /// Exactly this many numbers.
    Numbers(usize),
    /// One path (a word or a quoted string).
    Path,
}

/// One row of the attribute table.
#[derive(Debug)]
pub struct AttrSpec {
    pub name: AttrName,
    pub arity: Arity,
    /// Placeholder values for help lines: `X Y Z`.
    pub placeholder: &'static str,
    pub required: bool,
}

const fn spec(name: AttrName, arity: Arity, placeholder: &'static str, required: bool) -> AttrSpec {
    AttrSpec {
        name,
        arity,
        placeholder,
        required,
    }
}

const CENTER: AttrSpec = spec(AttrName::Center, Arity::Numbers(3), "X Y Z", true);
const COLOR: AttrSpec = spec(AttrName::Color, Arity::Numbers(3), "R G B", false);
const REFLECTIVITY: AttrSpec = spec(AttrName::Reflectivity, Arity::Numbers(1), "K", false);
const TEXTURE: AttrSpec = spec(AttrName::Texture, Arity::Path, "PATH", false);

static SPHERE: [AttrSpec; 5] = [
    spec(AttrName::Dimension, Arity::Numbers(1), "RADIUS", true),
    CENTER,
    COLOR,
    REFLECTIVITY,
    TEXTURE,
];

static PLANE: [AttrSpec; 7] = [
    spec(AttrName::Dimension, Arity::Numbers(2), "WIDTH HEIGHT", true),
    CENTER,
    spec(AttrName::Normal, Arity::Numbers(3), "X Y Z", true),
    spec(AttrName::Headup, Arity::Numbers(3), "X Y Z", true),
    COLOR,
    REFLECTIVITY,
    TEXTURE,
];

static LIGHT: [AttrSpec; 2] = [
    spec(AttrName::Location, Arity::Numbers(3), "X Y Z", true),
    spec(AttrName::Color, Arity::Numbers(3), "R G B", true),
];

/// The sections that have attributes, for "belongs to" messages.
const WITH_ATTRIBUTES: [SectionKind; 3] =
    [SectionKind::Sphere, SectionKind::Plane, SectionKind::Light];

/// The attributes `kind` takes, in documentation order (none for the camera
/// and for unknown sections).
pub fn attributes_of(kind: &SectionKind) -> &'static [AttrSpec] {
    match kind {
        SectionKind::Sphere => &SPHERE,
        SectionKind::Plane => &PLANE,
        SectionKind::Light => &LIGHT,
        SectionKind::Camera | SectionKind::Unknown(_) => &[],
    }
}

/// The row for `name` in `kind`, if `kind` takes it.
pub fn find(kind: &SectionKind, name: &AttrName) -> Option<&'static AttrSpec> {
    attributes_of(kind).iter().find(|s| &s.name == name)
}

/// The section keywords that take `name`, such as `["plane"]` for `normal`.
pub fn sections_taking(name: &AttrName) -> Vec<&'static str> {
    WITH_ATTRIBUTES
        .iter()
        .filter(|kind| find(kind, name).is_some())
        .map(|kind| match kind {
            SectionKind::Sphere => "sphere",
            SectionKind::Plane => "plane",
            _ => "light",
        })
        .collect()
}

/// "`a`", "`a` and `b`", "`a`, `b` and `c`".
pub fn list<S: AsRef<str>>(items: &[S]) -> String {
    joined(items, "and")
}

/// "`a`, `b` or `c`".
pub fn list_or<S: AsRef<str>>(items: &[S]) -> String {
    joined(items, "or")
}

fn joined<S: AsRef<str>>(items: &[S], conjunction: &str) -> String {
    let quoted: Vec<String> = items.iter().map(|s| format!("`{}`", s.as_ref())).collect();
    match quoted.split_last() {
        None => String::new(),
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} {conjunction} {last}", rest.join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_read_as_english() {
        assert_eq!(list(&["a"]), "`a`");
        assert_eq!(list(&["a", "b"]), "`a` and `b`");
        assert_eq!(list(&["a", "b", "c"]), "`a`, `b` and `c`");
        assert_eq!(list_or(&["a", "b", "c"]), "`a`, `b` or `c`");
    }

    #[test]
    fn normal_belongs_to_plane_and_color_to_all() {
        assert_eq!(sections_taking(&AttrName::Normal), ["plane"]);
        assert_eq!(
            sections_taking(&AttrName::Color),
            ["sphere", "plane", "light"]
        );
    }
}
