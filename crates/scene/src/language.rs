//! The scene language as data, one registry of rules in the manner of
//! ruff's: a row per section and attribute (and one for the camera's
//! resolution) with its arity, typed [`Constraint`], typed default, JSON
//! field names, meaning and example. Everything that states a rule of an
//! attribute reads it from here: the check pass's generic checks (unknown,
//! misplaced, duplicate, count, missing) and its single-attribute rules
//! (`check/rules.rs`) with their fixes, the messages, the model's defaults,
//! the JSON reader and the JSON Schema's bounds, editor hover and
//! completion, and the attribute table of docs/language.md. It also names
//! the two languages a scene is written in ([`Language`]) and writes a
//! row's line in either ([`AttrSpec::written`]), so every help line shows
//! a fix in the file's own syntax. Below the check pass and the JSON
//! reader.

use std::path::Path;

use crate::ast::{AttrName, SectionKind};

/// The languages a scene can be written in. The check pass words its
/// help lines in the file's own: a fix shown as `color 1 0 0` in scene
/// text is `"color": [1, 0, 0]` in a JSON scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Language {
    /// The scene language of docs/language.md.
    Text,
    /// The JSON layout of [`crate::model::Scene`].
    Json,
}

impl Language {
    /// JSON for a path ending in `.json` (any case), and for stdin whose
    /// first non-blank character is `{` (which no scene file starts with);
    /// scene text otherwise.
    pub fn of(path: &Path, bytes: &[u8]) -> Language {
        if path == Path::new("-") && bytes.trim_ascii_start().starts_with(b"{") {
            Language::Json
        } else {
            Language::of_name(path)
        }
    }

    /// By the name alone: JSON for a path ending in `.json` (any case),
    /// scene text otherwise. The one rule every caller that has a name
    /// (a file, an editor's document) goes by.
    pub fn of_name(path: &Path) -> Language {
        if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"))
        {
            Language::Json
        } else {
            Language::Text
        }
    }

    /// What one attribute of a section is called in messages: a `line` of
    /// scene text, a `field` of a JSON object.
    pub fn line(self) -> &'static str {
        match self {
            Language::Text => "line",
            Language::Json => "field",
        }
    }
}

/// What an attribute's values are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arity {
    /// Exactly this many numbers.
    Numbers(usize),
    /// One path (a word or a quoted string).
    Path,
}

/// What a row is about: an attribute, or the camera's resolution (the
/// number after the `camera` keyword).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Key {
    Resolution,
    Attribute(AttrName),
}

impl Key {
    /// The word a line of this row starts with: `camera` or the attribute.
    pub fn as_str(&self) -> &str {
        match self {
            Key::Resolution => "camera",
            Key::Attribute(name) => name.as_str(),
        }
    }
}

impl PartialEq<AttrName> for Key {
    fn eq(&self, name: &AttrName) -> bool {
        matches!(self, Key::Attribute(own) if own == name)
    }
}

/// The rule a row's values must follow on their own (rules between
/// attributes, such as `headup` against `normal`, live in the check pass).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Constraint {
    /// Any finite numbers (a position).
    Any,
    /// Each number in `[min, max]`. `scale`, when given, is another scale
    /// authors write these values on (0–255, percentages): values within it
    /// are read as meant on it.
    Range {
        min: f64,
        max: f64,
        scale: Option<Scale>,
    },
    /// Each number greater than 0.
    Positive,
    /// Each number 0 or more; above `warn_above` is allowed with a warning.
    NonNegative { warn_above: f64 },
    /// Not the zero vector; `stand_in` is what a fix writes instead.
    NonZero { stand_in: StandIn },
    /// A whole number in `[min, max]`.
    Whole { min: u32, max: u32 },
    /// A path to an image file that decodes (checked by the texture
    /// loader, against the file system).
    Image,
}

/// A scale values are written on by mistake: `top` on it is 1 on ours.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scale {
    pub top: f64,
    /// "0–255 values", "a percentage", for help lines.
    pub name: &'static str,
}

/// What a fix writes for a zero vector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StandIn {
    /// `facing`, turned perpendicular to the `across` attribute of the
    /// same section when that is valid (the nearest such vector, or an
    /// axis when `facing` is parallel to it), so the fix brings no new
    /// problem between the two.
    Across {
        facing: [f64; 3],
        across: &'static AttrName,
    },
    /// A vector perpendicular to this attribute of the same section, when
    /// that is valid (else `0 1 0`).
    PerpendicularTo(&'static AttrName),
}

/// A row's value when it is not given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DefaultValue {
    Number(f64),
    Vector([f64; 3]),
}

impl DefaultValue {
    /// The default as scene text: `0`, `1 1 1`.
    pub fn text(&self) -> String {
        match self {
            DefaultValue::Number(x) => x.to_string(),
            DefaultValue::Vector(v) => v.map(|x| x.to_string()).join(" "),
        }
    }

    /// The default as JSON: `0`, `[1, 1, 1]`.
    pub fn json(&self) -> serde_json::Value {
        match self {
            DefaultValue::Number(x) => serde_json::json!(x),
            DefaultValue::Vector(v) => serde_json::json!(v),
        }
    }
}

/// One row of the registry.
#[derive(Debug)]
pub struct AttrSpec {
    pub name: Key,
    pub arity: Arity,
    /// Placeholder values for help lines: `X Y Z`.
    pub placeholder: &'static str,
    pub required: bool,
    /// The fields of a JSON scene object it is read from (`dimension` is
    /// `radius`, or `width` and `height`).
    pub json: &'static [&'static str],
    /// The value when it is not given.
    pub default: Option<DefaultValue>,
    /// What it means, with units, on one line.
    pub description: &'static str,
    /// The rule its values must follow on their own.
    pub constraint: Constraint,
    /// More about the rule, for people (`need not be unit length`).
    pub note: &'static str,
    /// An example line.
    pub example: &'static str,
}

/// The camera's resolution: `camera N` for an N × N image.
pub static CAMERA: AttrSpec = AttrSpec {
    name: Key::Resolution,
    arity: Arity::Numbers(1),
    placeholder: "N",
    required: true,
    json: &["resolution"],
    default: None,
    description: "the image is N × N pixels",
    constraint: Constraint::Whole { min: 1, max: 16384 },
    note: "",
    example: "camera 400",
};

const CENTER: AttrSpec = AttrSpec {
    name: Key::Attribute(AttrName::Center),
    arity: Arity::Numbers(3),
    placeholder: "X Y Z",
    required: true,
    json: &["center"],
    default: None,
    description: "the centre, in world units (the camera is at the origin looking down −z)",
    constraint: Constraint::Any,
    note: "",
    example: "center 0 0 -5",
};
const COLOR: AttrSpec = AttrSpec {
    name: Key::Attribute(AttrName::Color),
    arity: Arity::Numbers(3),
    placeholder: "R G B",
    required: false,
    json: &["color"],
    default: Some(DefaultValue::Vector([1.0, 1.0, 1.0])),
    description: "the surface colour, linear RGB",
    constraint: Constraint::Range {
        min: 0.0,
        max: 1.0,
        scale: Some(Scale {
            top: 255.0,
            name: "0–255 values",
        }),
    },
    note: "",
    example: "color 1 0.5 0",
};
const REFLECTIVITY: AttrSpec = AttrSpec {
    name: Key::Attribute(AttrName::Reflectivity),
    arity: Arity::Numbers(1),
    placeholder: "K",
    required: false,
    json: &["reflectivity"],
    default: Some(DefaultValue::Number(0.0)),
    description: "the weight of the mirror reflection",
    constraint: Constraint::Range {
        min: 0.0,
        max: 1.0,
        scale: Some(Scale {
            top: 100.0,
            name: "a percentage",
        }),
    },
    note: "",
    example: "reflectivity 0.5",
};
const TEXTURE: AttrSpec = AttrSpec {
    name: Key::Attribute(AttrName::Texture),
    arity: Arity::Path,
    placeholder: "PATH",
    required: false,
    json: &["texture"],
    default: None,
    description: "an image (PPM, PNG or JPEG) replacing the colour, relative to the scene file",
    constraint: Constraint::Image,
    note: "",
    example: "texture wood_tex.ppm",
};

static SPHERE: [AttrSpec; 5] = [
    AttrSpec {
        name: Key::Attribute(AttrName::Dimension),
        arity: Arity::Numbers(1),
        placeholder: "RADIUS",
        required: true,
        json: &["radius"],
        default: None,
        description: "the radius, in world units",
        constraint: Constraint::Positive,
        note: "",
        example: "dimension 1",
    },
    CENTER,
    COLOR,
    REFLECTIVITY,
    TEXTURE,
];

static PLANE: [AttrSpec; 7] = [
    AttrSpec {
        name: Key::Attribute(AttrName::Dimension),
        arity: Arity::Numbers(2),
        placeholder: "WIDTH HEIGHT",
        required: true,
        json: &["width", "height"],
        default: None,
        description: "the width (along `right`) and height (along `up`), in world units",
        constraint: Constraint::Positive,
        note: "",
        example: "dimension 4 4",
    },
    CENTER,
    AttrSpec {
        name: Key::Attribute(AttrName::Normal),
        arity: Arity::Numbers(3),
        placeholder: "X Y Z",
        required: true,
        json: &["normal"],
        default: None,
        description: "the direction the plane faces (normalised by the renderer)",
        // Facing the camera, which looks down −z, as nearly as a normal
        // perpendicular to the headup can.
        constraint: Constraint::NonZero {
            stand_in: StandIn::Across {
                facing: [0.0, 0.0, 1.0],
                across: &AttrName::Headup,
            },
        },
        note: "need not be unit length",
        example: "normal 0 1 0",
    },
    AttrSpec {
        name: Key::Attribute(AttrName::Headup),
        arity: Arity::Numbers(3),
        placeholder: "X Y Z",
        required: true,
        json: &["headup"],
        default: None,
        description: "which way is up on the plane (projected onto it)",
        constraint: Constraint::NonZero {
            stand_in: StandIn::PerpendicularTo(&AttrName::Normal),
        },
        note: "parallel to `normal` warns (an axis stands in)",
        example: "headup 0 0 -1",
    },
    COLOR,
    REFLECTIVITY,
    TEXTURE,
];

static LIGHT: [AttrSpec; 2] = [
    AttrSpec {
        name: Key::Attribute(AttrName::Location),
        arity: Arity::Numbers(3),
        placeholder: "X Y Z",
        required: true,
        json: &["location"],
        default: None,
        description: "the position of the point light, in world units",
        constraint: Constraint::Any,
        note: "",
        example: "location 0 5 0",
    },
    AttrSpec {
        name: Key::Attribute(AttrName::Color),
        arity: Arity::Numbers(3),
        placeholder: "R G B",
        required: true,
        json: &["color"],
        default: None,
        description: "the intensity per channel",
        constraint: Constraint::NonNegative { warn_above: 1.0 },
        note: "",
        example: "color 1 1 1",
    },
];

/// The sections that have attributes, for "belongs to" messages.
const WITH_ATTRIBUTES: [SectionKind; 3] =
    [SectionKind::Sphere, SectionKind::Plane, SectionKind::Light];

impl AttrSpec {
    /// The attribute name of a section's row, as the syntax tree holds it
    /// (the camera's row, which has none, gives its keyword as an unknown
    /// name).
    pub fn attr_name(&self) -> AttrName {
        match &self.name {
            Key::Attribute(name) => name.clone(),
            Key::Resolution => AttrName::Unknown(self.name.as_str().into()),
        }
    }

    /// How many numbers (or paths) a line of this row takes.
    pub fn count(&self) -> usize {
        match self.arity {
            Arity::Numbers(n) => n,
            Arity::Path => 1,
        }
    }

    /// The largest value of a row whose rule is a whole-number range (the
    /// camera's largest resolution); 0 for any other.
    pub const fn max_whole(&self) -> u32 {
        match self.constraint {
            Constraint::Whole { max, .. } => max,
            _ => 0,
        }
    }

    /// The rule in words: `each in [0, 1]`, `> 0`, `any numbers`, with the
    /// row's note.
    pub fn rule(&self) -> String {
        let each = if self.count() > 1 { "each " } else { "" };
        let rule = match self.constraint {
            Constraint::Any => "any numbers".to_string(),
            Constraint::Range { min, max, .. } => format!("{each}in [{min}, {max}]"),
            Constraint::Positive => format!("{each}> 0"),
            Constraint::NonNegative { warn_above } => {
                format!("{each}≥ 0 (above {warn_above} is allowed, with a warning)")
            }
            Constraint::NonZero { .. } => "not `0 0 0`".to_string(),
            Constraint::Whole { min, max } => format!("a whole number from {min} to {max}"),
            Constraint::Image => "an image file that decodes".to_string(),
        };
        if self.note.is_empty() {
            rule
        } else {
            format!("{rule}; {}", self.note)
        }
    }

    /// The bounds of each number, for the JSON Schema: `(minimum,
    /// exclusive, maximum)`, where `exclusive` says the minimum itself is
    /// out.
    pub fn bounds(&self) -> (Option<f64>, bool, Option<f64>) {
        match self.constraint {
            Constraint::Range { min, max, .. } => (Some(min), false, Some(max)),
            Constraint::Positive => (Some(0.0), true, None),
            Constraint::NonNegative { .. } => (Some(0.0), false, None),
            Constraint::Whole { min, max } => (Some(min.into()), false, Some(max.into())),
            Constraint::Any | Constraint::NonZero { .. } | Constraint::Image => (None, false, None),
        }
    }

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

    /// A line of this row holding `values` (numbers as written, or a path
    /// as it reads in a string), in the language of the file: scene text
    /// (`color 1 0 0`) or the JSON fields it is read from
    /// (`"color": [1, 0, 0]`, `"resolution": 400`, `"width": 4, "height": 4`),
    /// so help lines read as the file the student is editing.
    pub fn written<S: AsRef<str>>(&self, values: &[S], language: Language) -> String {
        let values: Vec<&str> = values.iter().map(AsRef::as_ref).collect();
        match language {
            Language::Text => format!("{} {}", self.name.as_str(), values.join(" ")),
            Language::Json => match self.arity {
                Arity::Path => {
                    format!(
                        "\"{}\": {}",
                        self.json[0],
                        serde_json::json!(values.join(" "))
                    )
                }
                Arity::Numbers(n) if self.json.len() == n && n > 1 => self
                    .json
                    .iter()
                    .zip(&values)
                    .map(|(field, value)| format!("\"{field}\": {value}"))
                    .collect::<Vec<_>>()
                    .join(", "),
                Arity::Numbers(1) => format!("\"{}\": {}", self.json[0], values.join(" ")),
                Arity::Numbers(_) => format!("\"{}\": [{}]", self.json[0], values.join(", ")),
            },
        }
    }

    /// The attribute described in one sentence for the JSON Schema and
    /// editors: meaning, rule, default and the scene-text spelling.
    pub fn summary(&self) -> String {
        let mut out = format!("{}.", capitalised(self.description));
        if self.constraint != Constraint::Any {
            out.push_str(&format!(" Rule: {}.", self.rule()));
        }
        if let Some(default) = self.default {
            out.push_str(&format!(" Default: `{}`.", default.text()));
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

/// The attributes `kind` takes, in documentation order (none for the camera,
/// whose one row is [`CAMERA`], and for unknown sections).
pub fn attributes_of(kind: &SectionKind) -> &'static [AttrSpec] {
    match kind {
        SectionKind::Sphere => &SPHERE,
        SectionKind::Plane => &PLANE,
        SectionKind::Light => &LIGHT,
        SectionKind::Camera | SectionKind::Unknown(_) => &[],
    }
}

/// Every row: the camera's, then each section's attributes.
pub fn rows() -> impl Iterator<Item = (SectionKind, &'static AttrSpec)> {
    std::iter::once((SectionKind::Camera, &CAMERA)).chain(
        WITH_ATTRIBUTES
            .into_iter()
            .flat_map(|kind| attributes_of(&kind).iter().map(move |s| (kind.clone(), s))),
    )
}

/// The row for `name` in `kind`, if `kind` takes it.
pub fn find(kind: &SectionKind, name: &AttrName) -> Option<&'static AttrSpec> {
    attributes_of(kind).iter().find(|s| s.name == *name)
}

/// The default of `name` in `kind`, when it has one.
pub fn default_of(kind: &SectionKind, name: &AttrName) -> Option<DefaultValue> {
    find(kind, name)?.default
}

/// The attribute of `kind` that takes a path (`texture`), if any.
pub fn path_attribute(kind: &SectionKind) -> Option<&'static AttrSpec> {
    attributes_of(kind).iter().find(|s| s.arity == Arity::Path)
}

/// Whether `name` takes a path in some section: the parser reads such a
/// line's first value as a path wherever the line stands, so a misplaced
/// `texture` still reads as one line.
pub fn takes_path_somewhere(name: &AttrName) -> bool {
    WITH_ATTRIBUTES
        .iter()
        .any(|kind| path_attribute(kind).is_some_and(|spec| spec.name == *name))
}

/// The attribute of `kind` a JSON field name stands for in scene text,
/// when the field is named otherwise there: `radius` is a sphere's
/// `dimension`.
pub fn from_json_name(kind: &SectionKind, field: &str) -> Option<&'static AttrSpec> {
    attributes_of(kind)
        .iter()
        .find(|s| s.json == [field] && s.name.as_str() != field)
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
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for (kind, spec) in rows() {
        let (attribute, json, values, required) = match spec.name {
            Key::Resolution => (
                "(resolution)".to_string(),
                format!("`camera.{}`", spec.json[0]),
                format!("1 whole number {}", spec.placeholder),
                "exactly one camera",
            ),
            Key::Attribute(ref name) => {
                let json: Vec<String> = spec.json.iter().map(|f| format!("`{f}`")).collect();
                (
                    format!("`{}`", name.as_str()),
                    json.join(", "),
                    spec.placeholder.to_lowercase(),
                    if spec.required { "yes" } else { "no" },
                )
            }
        };
        table.push_str(&format!(
            "| {} | {attribute} | {json} | {values} | {required} | {} | {} | {} | `{}` |\n",
            kind.as_str(),
            spec.default
                .map_or("—".to_string(), |d| format!("`{}`", d.text())),
            spec.description,
            spec.rule(),
            spec.example,
        ));
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

    #[test]
    fn every_position_has_a_rule_in_words() {
        let center = find(&SectionKind::Sphere, &AttrName::Center).unwrap();
        assert_eq!(center.rule(), "any numbers");
        assert_eq!(CAMERA.rule(), "a whole number from 1 to 16384");
    }

    #[test]
    fn a_line_is_written_in_the_files_language() {
        let plane = |name| find(&SectionKind::Plane, &name).unwrap();
        let sphere = |name| find(&SectionKind::Sphere, &name).unwrap();
        for (spec, values, text, json) in [
            (&CAMERA, &["400"][..], "camera 400", r#""resolution": 400"#),
            (
                sphere(AttrName::Dimension),
                &["1"],
                "dimension 1",
                r#""radius": 1"#,
            ),
            (
                plane(AttrName::Dimension),
                &["4", "2"],
                "dimension 4 2",
                r#""width": 4, "height": 2"#,
            ),
            (
                sphere(AttrName::Color),
                &["1", "0", "0.5"],
                "color 1 0 0.5",
                r#""color": [1, 0, 0.5]"#,
            ),
            (
                sphere(AttrName::Texture),
                &["my wood.ppm"],
                "texture my wood.ppm",
                r#""texture": "my wood.ppm""#,
            ),
        ] {
            assert_eq!(spec.written(values, Language::Text), text);
            assert_eq!(spec.written(values, Language::Json), json);
        }
    }

    #[test]
    fn radius_is_the_json_name_of_a_spheres_dimension() {
        let spec = from_json_name(&SectionKind::Sphere, "radius").unwrap();
        assert_eq!(spec.name, AttrName::Dimension);
        assert!(from_json_name(&SectionKind::Plane, "radius").is_none());
        assert!(from_json_name(&SectionKind::Sphere, "color").is_none());
    }
}
