//! The typed syntax tree of a scene file, as written.
//!
//! The parser produces this tree and nothing downstream reads source text
//! again. Keywords are resolved to enums here (an unrecognised word becomes an
//! `Unknown` variant, kept so the check pass can suggest the nearest name), but
//! nothing is validated: counts, ranges, duplicates and required attributes
//! are the check pass's job. Every node carries the byte span it came from.

use smallvec::SmallVec;

use crate::span::{Span, Spanned};

/// The values after a keyword or attribute name, in order. Inline up to
/// the three of a vector, on the heap only past that, so a valid attribute
/// line allocates nothing of its own.
pub type Values = SmallVec<[Spanned<Value>; 3]>;

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
    pub args: Values,
    pub attributes: Vec<Attribute>,
    /// From the keyword to the end of its last value.
    pub span: Span,
}

/// A keyword enum spelled once: each variant with its word, plus
/// `Unknown` for any other word; `KEYWORDS` (in the order given),
/// `from_word` and `as_str` are derived from that one list.
macro_rules! keywords {
    (
        $(#[$meta:meta])*
        pub enum $name:ident { $($variant:ident = $word:literal,)+ }
        unknown: $unknown_doc:literal,
        keywords: $keywords_doc:literal,
    ) => {
        $(#[$meta])*
        #[derive(Clone, Debug, PartialEq, Eq)]
        pub enum $name {
            $($variant,)+
            #[doc = $unknown_doc]
            Unknown(Box<str>),
        }

        impl $name {
            #[doc = $keywords_doc]
            pub const KEYWORDS: [&'static str; [$($word),+].len()] = [$($word),+];

            /// The keyword for `word`, or `Unknown`.
            pub fn from_word(word: &str) -> Self {
                Self::known(word).unwrap_or_else(|| $name::Unknown(word.into()))
            }

            /// The keyword for `word`, or `None` when it is none (without
            /// the copy of the word `Unknown` keeps).
            pub fn known(word: &str) -> Option<Self> {
                match word {
                    $($word => Some($name::$variant),)+
                    _ => None,
                }
            }

            /// The keyword as written in scene files.
            pub fn as_str(&self) -> &str {
                match self {
                    $($name::$variant => $word,)+
                    $name::Unknown(word) => word,
                }
            }
        }
    };
}

keywords! {
    /// The section keywords of the language.
    pub enum SectionKind {
        Camera = "camera",
        Sphere = "sphere",
        Plane = "plane",
        Light = "light",
    }
    unknown: "A word in section position that is no section keyword.",
    keywords: "Every known section keyword, in documentation order.",
}

/// One attribute line: a name and the values after it. Equality ignores spans.
#[derive(Clone, Debug)]
pub struct Attribute {
    pub name: Spanned<AttrName>,
    pub values: Values,
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

keywords! {
    /// The attribute names of the language.
    pub enum AttrName {
        Dimension = "dimension",
        Center = "center",
        Color = "color",
        Reflectivity = "reflectivity",
        Texture = "texture",
        Normal = "normal",
        Headup = "headup",
        Location = "location",
    }
    unknown: "A word in attribute position that is no attribute name.",
    keywords: "Every known attribute name, in documentation order.",
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
