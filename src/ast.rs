//! The typed syntax tree of a scene file, as written.
//!
//! The parser produces this tree and nothing downstream reads source text
//! again. Keywords are resolved to enums here (an unrecognised word becomes an
//! `Unknown` variant, kept so the check pass can suggest the nearest name), but
//! nothing is validated: counts, ranges, duplicates and required attributes
//! are the check pass's job. Every node carries the byte span it came from.

use crate::span::{Span, Spanned};

/// A whole scene file: its sections in source order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct File {
    pub sections: Vec<Section>,
}

/// One section: a keyword, the values that follow it directly (the camera's
/// resolution), and its attributes up to the next section keyword.
/// Equality ignores spans.
#[derive(Clone, Debug)]
pub struct Section {
    pub kind: Spanned<SectionKind>,
    pub args: Box<[Spanned<Value>]>,
    pub attributes: Vec<Attribute>,
    /// From the keyword to the end of its last value.
    pub span: Span,
}

/// The section keywords of the language.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SectionKind {
    Camera,
    Sphere,
    Plane,
    Light,
    /// A word in section position that is no section keyword.
    Unknown(Box<str>),
}

impl SectionKind {
    /// Every known section keyword, in documentation order.
    pub const KEYWORDS: [&'static str; 4] = ["camera", "sphere", "plane", "light"];

    /// The keyword for `word`, or `Unknown`.
    pub fn from_word(word: &str) -> Self {
        match word {
            "camera" => SectionKind::Camera,
            "sphere" => SectionKind::Sphere,
            "plane" => SectionKind::Plane,
            "light" => SectionKind::Light,
            other => SectionKind::Unknown(other.into()),
        }
    }

    /// The keyword as written in scene files.
    pub fn as_str(&self) -> &str {
        match self {
            SectionKind::Camera => "camera",
            SectionKind::Sphere => "sphere",
            SectionKind::Plane => "plane",
            SectionKind::Light => "light",
            SectionKind::Unknown(word) => word,
        }
    }
}

/// One attribute line: a name and the values after it. Equality ignores spans.
#[derive(Clone, Debug)]
pub struct Attribute {
    pub name: Spanned<AttrName>,
    /// Boxed, not a `Vec`: 8 bytes less for each of a scene's attributes.
    pub values: Box<[Spanned<Value>]>,
    /// From the name to the end of its last value.
    pub span: Span,
}

impl PartialEq for Section {
    fn eq(&self, other: &Self) -> bool {
        self.kind == other.kind && self.args == other.args && self.attributes == other.attributes
    }
}

impl PartialEq for Attribute {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name && self.values == other.values
    }
}

/// The attribute names of the language.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum AttrName {
    Dimension,
    Center,
    Color,
    Reflectivity,
    Texture,
    Normal,
    Headup,
    Location,
    /// A word in attribute position that is no attribute name.
    Unknown(Box<str>),
}

impl AttrName {
    /// Every known attribute name, in documentation order.
    pub const KEYWORDS: [&'static str; 8] = [
        "dimension",
        "center",
        "color",
        "reflectivity",
        "texture",
        "normal",
        "headup",
        "location",
    ];

    /// The attribute for `word`, or `Unknown`.
    pub fn from_word(word: &str) -> Self {
        match word {
            "dimension" => AttrName::Dimension,
            "center" => AttrName::Center,
            "color" => AttrName::Color,
            "reflectivity" => AttrName::Reflectivity,
            "texture" => AttrName::Texture,
            "normal" => AttrName::Normal,
            "headup" => AttrName::Headup,
            "location" => AttrName::Location,
            other => AttrName::Unknown(other.into()),
        }
    }

    /// The name as written in scene files.
    pub fn as_str(&self) -> &str {
        match self {
            AttrName::Dimension => "dimension",
            AttrName::Center => "center",
            AttrName::Color => "color",
            AttrName::Reflectivity => "reflectivity",
            AttrName::Texture => "texture",
            AttrName::Normal => "normal",
            AttrName::Headup => "headup",
            AttrName::Location => "location",
            AttrName::Unknown(word) => word,
        }
    }
}

/// A value token.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A token that parsed as a finite number.
    Number(f64),
    /// A bare word (a texture path such as `wood_tex.ppm`) or the contents of
    /// a double-quoted string. (`Box<str>`, not `String`: a value is 16
    /// bytes, and a scene's syntax tree holds about eight per object.)
    Text(Box<str>),
    /// A token the parser already reported as a syntax error (a malformed
    /// number or an unterminated string). It keeps its place so value counts
    /// stay right, and the check pass reports nothing more about it.
    Invalid,
}

impl Value {
    /// The number, if this is one.
    pub fn as_number(&self) -> Option<f64> {
        match self {
            Value::Number(n) => Some(*n),
            Value::Text(_) | Value::Invalid => None,
        }
    }
}
