//! The scene language as data: which attributes each section takes (the
//! attribute table of docs/language.md), so the check pass's generic
//! checks (unknown, misplaced, duplicate, count, missing) need no
//! per-section code, and the English lists its messages and the JSON
//! reader's are worded with. Below the check pass and the JSON reader.

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
    /// The fields of a JSON scene object it is read from (`dimension` is
    /// `radius`, or `width` and `height`).
    pub json: &'static [&'static str],
    /// The value when it is not given, as scene text.
    pub default: Option<&'static str>,
    /// What it means, with units, on one line.
    pub description: &'static str,
    /// The rule its values must follow.
    pub rule: &'static str,
    /// An example line.
    pub example: &'static str,
}

const CENTER: AttrSpec = AttrSpec {
    name: AttrName::Center,
    arity: Arity::Numbers(3),
    placeholder: "X Y Z",
    required: true,
    json: &["center"],
    default: None,
    description: "the centre, in world units (the camera is at the origin looking down −z)",
    rule: "—",
    example: "center 0 0 -5",
};
const COLOR: AttrSpec = AttrSpec {
    name: AttrName::Color,
    arity: Arity::Numbers(3),
    placeholder: "R G B",
    required: false,
    json: &["color"],
    default: Some("1 1 1"),
    description: "the surface colour, linear RGB",
    rule: "each in [0, 1]",
    example: "color 1 0.5 0",
};
const REFLECTIVITY: AttrSpec = AttrSpec {
    name: AttrName::Reflectivity,
    arity: Arity::Numbers(1),
    placeholder: "K",
    required: false,
    json: &["reflectivity"],
    default: Some("0"),
    description: "the weight of the mirror reflection",
    rule: "in [0, 1]",
    example: "reflectivity 0.5",
};
const TEXTURE: AttrSpec = AttrSpec {
    name: AttrName::Texture,
    arity: Arity::Path,
    placeholder: "PATH",
    required: false,
    json: &["texture"],
    default: None,
    description: "an image (PPM, PNG or JPEG) replacing the colour, relative to the scene file",
    rule: "an image file that decodes",
    example: "texture wood_tex.ppm",
};

static SPHERE: [AttrSpec; 5] = [
    AttrSpec {
        name: AttrName::Dimension,
        arity: Arity::Numbers(1),
        placeholder: "RADIUS",
        required: true,
        json: &["radius"],
        default: None,
        description: "the radius, in world units",
        rule: "> 0",
        example: "dimension 1",
    },
    CENTER,
    COLOR,
    REFLECTIVITY,
    TEXTURE,
];

static PLANE: [AttrSpec; 7] = [
    AttrSpec {
        name: AttrName::Dimension,
        arity: Arity::Numbers(2),
        placeholder: "WIDTH HEIGHT",
        required: true,
        json: &["width", "height"],
        default: None,
        description: "the width (along `right`) and height (along `up`), in world units",
        rule: "each > 0",
        example: "dimension 4 4",
    },
    CENTER,
    AttrSpec {
        name: AttrName::Normal,
        arity: Arity::Numbers(3),
        placeholder: "X Y Z",
        required: true,
        json: &["normal"],
        default: None,
        description: "the direction the plane faces (normalised by the renderer)",
        rule: "not `0 0 0`; need not be unit length",
        example: "normal 0 1 0",
    },
    AttrSpec {
        name: AttrName::Headup,
        arity: Arity::Numbers(3),
        placeholder: "X Y Z",
        required: true,
        json: &["headup"],
        default: None,
        description: "which way is up on the plane (projected onto it)",
        rule: "not `0 0 0`; parallel to `normal` warns (an axis stands in)",
        example: "headup 0 0 -1",
    },
    COLOR,
    REFLECTIVITY,
    TEXTURE,
];

static LIGHT: [AttrSpec; 2] = [
    AttrSpec {
        name: AttrName::Location,
        arity: Arity::Numbers(3),
        placeholder: "X Y Z",
        required: true,
        json: &["location"],
        default: None,
        description: "the position of the point light, in world units",
        rule: "—",
        example: "location 0 5 0",
    },
    AttrSpec {
        name: AttrName::Color,
        arity: Arity::Numbers(3),
        placeholder: "R G B",
        required: true,
        json: &["color"],
        default: None,
        description: "the intensity per channel",
        rule: "each ≥ 0 (above 1 is allowed, with a warning)",
        example: "color 1 1 1",
    },
];

/// The sections that have attributes, for "belongs to" messages.
const WITH_ATTRIBUTES: [SectionKind; 3] =
    [SectionKind::Sphere, SectionKind::Plane, SectionKind::Light];

impl AttrSpec {
    /// The example line as the value of the attribute's `i`th JSON field:
    /// `"wood_tex.ppm"`, `[0, 0, -5]`, or one number of an attribute that
    /// JSON splits (`dimension 4 4` is `"width": 4, "height": 4`).
    pub fn json_example(&self, i: usize) -> String {
        let values: Vec<&str> = self.example.split_whitespace().skip(1).collect();
        match self.arity {
            Arity::Path => format!("{:?}", values.join(" ")),
            Arity::Numbers(n) if self.json.len() == n => {
                values.get(i).copied().unwrap_or_default().to_string()
            }
            Arity::Numbers(_) => format!("[{}]", values.join(", ")),
        }
    }

    /// The attribute described in one sentence for the JSON Schema and
    /// editors: meaning, rule, default and the scene-text spelling.
    pub fn summary(&self) -> String {
        let mut out = format!("{}.", capitalised(self.description));
        if self.rule != "—" {
            out.push_str(&format!(" Rule: {}.", self.rule));
        }
        if let Some(default) = self.default {
            out.push_str(&format!(" Default: `{default}`."));
        }
        out.push_str(&format!(" Scene text: `{}`.", self.example));
        out
    }
}

fn capitalised(text: &str) -> String {
    let mut chars = text.chars();
    chars.next().map_or_else(String::new, |first| {
        first.to_uppercase().chain(chars).collect()
    })
}

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

/// The attribute table of docs/language.md, one row per section and
/// attribute in print order (the order `convert --to scene` writes them),
/// after the camera's resolution. Generated, so the page cannot drift:
/// tests/language_table.rs compares it with the committed page.
pub fn markdown_table() -> String {
    let mut table = String::from(
        "| section | attribute | JSON | values | required | default | meaning | rule | example |\n\
         |---|---|---|---|---|---|---|---|---|\n\
         | camera | (resolution) | `camera.resolution` | 1 whole number N | exactly one camera | — \
         | the image is N × N pixels | 1 ≤ N ≤ 16384 | `camera 400` |\n",
    );
    for kind in WITH_ATTRIBUTES {
        for spec in attributes_of(&kind) {
            let json: Vec<String> = spec.json.iter().map(|f| format!("`{f}`")).collect();
            table.push_str(&format!(
                "| {} | `{}` | {} | {} | {} | {} | {} | {} | `{}` |\n",
                kind.as_str(),
                spec.name.as_str(),
                json.join(", "),
                spec.placeholder.to_lowercase(),
                if spec.required { "yes" } else { "no" },
                spec.default.map_or("—".to_string(), |d| format!("`{d}`")),
                spec.description,
                spec.rule,
                spec.example,
            ));
        }
    }
    table
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
