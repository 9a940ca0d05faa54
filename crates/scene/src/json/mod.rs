//! Reading JSON scenes (the layout of [`crate::model::Scene`], documented in
//! docs/formats.md) into the same [`ast::File`] the scene-text parser builds.
//!
//! Every section, attribute and value in that tree carries the byte span of
//! the JSON text it came from, so the check pass runs unchanged on JSON input
//! and each of its `scene::` diagnostics labels the JSON value at fault. Only
//! what scene text cannot get wrong the same way is reported here, under
//! `json::` ([`JsonError`]): invalid JSON, a wrong type or length, missing,
//! unknown and repeated fields, an unsupported `format`.
//!
//! The text is parsed by `jsonc-parser` in strict mode (it keeps the byte
//! range of every value) and then validated by `serde_json`, the parser that
//! defines which JSON the scene model accepts, so nothing it rejects slips
//! through. Where this module reports a problem it puts placeholders
//! ([`Value::Invalid`]) in the tree, which the check pass reads as "already
//! reported": each mistake is reported once.

pub mod errors;

use jsonc_parser::ast::{Array, Object, ObjectProp, Value as Json};
use jsonc_parser::common::Ranged;
use jsonc_parser::{CollectOptions, ParseOptions};

use std::borrow::Cow;

use crate::ast::{AttrName, Attribute, File, Section, SectionKind, Value};
use crate::diagnostic::lowercase_first;
use crate::language::{self, Arity, AttrSpec};
use crate::model;
use crate::span::{floor_char_boundary, Span, Spanned};
use crate::suggest;
pub use errors::JsonError;

/// The result of reading a JSON scene: the tree and every problem found in
/// its text and shape.
#[derive(Debug)]
pub struct Parsed {
    /// `None` when there is no scene to check: the text is not JSON, not an
    /// object, or of another format version.
    pub file: Option<File>,
    pub errors: Vec<JsonError>,
}

/// Read a JSON scene into a whole tree. Never fails and never panics:
/// problems are returned in [`Parsed::errors`] and the tree holds everything
/// that could be read.
pub fn parse(text: &str) -> Parsed {
    let mut sections = Vec::new();
    let read = read(text, |section| sections.push(section));
    Parsed {
        file: read.is_scene.then_some(File { sections }),
        errors: read.errors,
    }
}

/// What [`read`] found besides the sections it handed on.
#[derive(Debug)]
pub struct Read {
    /// False when there is no scene to check: the text is not JSON, not an
    /// object, or of another format version. No section was handed on then.
    pub is_scene: bool,
    pub errors: Vec<JsonError>,
}

/// Read a JSON scene, handing each section to `each` as soon as it is
/// built (the camera, then the objects, then the lights), so a caller can
/// check it and drop it as it does for scene text.
pub fn read(text: &str, mut each: impl FnMut(Section)) -> Read {
    let mut reader = Reader {
        errors: Vec::new(),
        each: &mut each,
    };
    let is_scene = match syntax_tree(text) {
        Ok(root) => reader.root(&root),
        Err(error) => {
            reader.errors.push(error);
            false
        }
    };
    Read {
        is_scene,
        errors: reader.errors,
    }
}

/// The spanned tree of `text`, or its first syntax error.
fn syntax_tree(text: &str) -> Result<Json<'_>, JsonError> {
    let strict = ParseOptions {
        allow_comments: false,
        allow_loose_object_property_names: false,
        allow_trailing_commas: false,
        allow_missing_commas: false,
        allow_single_quoted_strings: false,
        allow_hexadecimal_numbers: false,
        allow_unary_plus_numbers: false,
        allow_bare_decimal_point_numbers: false,
        allow_non_finite_numbers: false,
        allow_extended_string_escapes: false,
    };
    let parsed =
        jsonc_parser::parse_to_ast(text, &CollectOptions::default(), &strict).map_err(|error| {
            let range = error.range();
            JsonError::Syntax {
                message: lowercase_first(&error.kind().to_string()),
                span: Span::new(range.start, range.end.max(range.start)).into(),
            }
        })?;
    // serde_json has the last word on what is JSON: it also rejects what a
    // JSONC parser lets through (control characters in strings, numbers
    // out of range, an empty file).
    if let Err(error) = serde_json::from_str::<serde_json::Value>(text) {
        return Err(serde_json_error(text, &error));
    }
    parsed.value.ok_or_else(|| JsonError::Syntax {
        message: "the file holds no JSON value".to_string(),
        span: Span::point(0).into(),
    })
}

/// A serde_json error as a diagnostic at the character it points after.
fn serde_json_error(text: &str, error: &serde_json::Error) -> JsonError {
    let suffix = format!(" at line {} column {}", error.line(), error.column());
    let message = error.to_string();
    let message = message.strip_suffix(&suffix).unwrap_or(&message);
    // serde_json's column counts bytes from the line start, up to and
    // including the character it stopped at.
    let line_start: usize = text
        .split_inclusive('\n')
        .take(error.line().saturating_sub(1))
        .map(str::len)
        .sum();
    let end = floor_char_boundary(text, line_start + error.column());
    let start = text[..end]
        .char_indices()
        .next_back()
        .map_or(end, |(i, _)| i.max(line_start));
    JsonError::Syntax {
        message: message.to_string(),
        span: Span::new(start, end).into(),
    }
}

/// A JSON Pointer (RFC 6901) to a value, for messages.
#[derive(Clone, Debug, Default)]
struct Pointer(String);

impl Pointer {
    fn child(&self, segment: &str) -> Pointer {
        Pointer(format!(
            "{}/{}",
            self.0,
            segment.replace('~', "~0").replace('/', "~1")
        ))
    }

    fn index(&self, i: usize) -> Pointer {
        Pointer(format!("{}/{i}", self.0))
    }

    /// "`/objects/2/normal`", or "the top level" for the whole document.
    fn place(&self) -> String {
        if self.0.is_empty() {
            "the top level".to_string()
        } else {
            format!("`{}`", self.0)
        }
    }
}

fn span_of(node: &impl Ranged) -> Span {
    let range = node.range();
    Span::new(range.start, range.end)
}

/// The opening brace of an object: where "this object" labels point.
fn brace(object: &Object<'_>) -> Span {
    Span::new(object.range.start, object.range.start + 1)
}

/// "a string", "an array of 2 values": what a JSON value is, for messages.
fn describe(value: &Json<'_>) -> String {
    match value {
        Json::StringLit(s) => format!("the string `{:?}`", s.value),
        Json::NumberLit(n) => format!("the number `{}`", n.value),
        Json::BooleanLit(b) => format!("`{}`", b.value),
        Json::NullKeyword(_) => "`null`".to_string(),
        Json::Object(_) => "an object".to_string(),
        Json::Array(a) => match a.elements.len() {
            0 => "an empty array".to_string(),
            1 => "an array of 1 value".to_string(),
            n => format!("an array of {n} values"),
        },
    }
}

/// One field an object takes: its name and a value to show in help lines.
struct Field {
    name: &'static str,
    example: Example,
    required: bool,
}

/// A field's example value, written out only for a help line.
enum Example {
    Written(&'static str),
    /// The `i`th JSON field of a row of the language table.
    Table(&'static AttrSpec, usize),
}

impl Example {
    fn text(&self) -> Cow<'static, str> {
        match *self {
            Example::Written(text) => Cow::Borrowed(text),
            Example::Table(spec, i) => Cow::Owned(spec.json_example(i)),
        }
    }
}

const fn field(name: &'static str, example: &'static str, required: bool) -> Field {
    Field {
        name,
        example: Example::Written(example),
        required,
    }
}

const ROOT: [Field; 4] = [
    field("format", "\"raytracer-scene/1\"", true),
    field("camera", "{\"resolution\": 400}", true),
    field("objects", "[]", false),
    field("lights", "[]", false),
];
const CAMERA: [Field; 1] = [field("resolution", "400", true)];
/// The `type` of an object, in documentation order.
const TYPES: [&str; 2] = ["sphere", "plane"];

/// The fields an object of `kind` takes, read off the language table
/// ([`language::attributes_of`]): an object's `type` (lights have none),
/// then each attribute's JSON fields in the table's order, with examples
/// taken from the table's example lines.
fn fields_of(kind: &SectionKind) -> Vec<Field> {
    let type_field = match kind {
        SectionKind::Sphere => Some(field("type", "\"sphere\"", true)),
        SectionKind::Plane => Some(field("type", "\"plane\"", true)),
        _ => None,
    };
    let attributes = language::attributes_of(kind).iter().flat_map(|spec| {
        spec.json.iter().enumerate().map(|(i, name)| Field {
            name,
            example: Example::Table(spec, i),
            required: spec.required,
        })
    });
    type_field.into_iter().chain(attributes).collect()
}

/// The fields of one object that it takes, first occurrence of each.
struct Fields<'v, 'a> {
    path: Pointer,
    given: Vec<&'v ObjectProp<'a>>,
}

impl<'v, 'a> Fields<'v, 'a> {
    fn get(&self, name: &str) -> Option<&'v ObjectProp<'a>> {
        self.given.iter().copied().find(|p| p.name.as_str() == name)
    }
}

/// The reading state: problems found so far, and where built sections go.
struct Reader<'s> {
    errors: Vec<JsonError>,
    each: &'s mut dyn FnMut(Section),
}

impl Reader<'_> {
    /// The whole document: `{"format", "camera", "objects", "lights"}`.
    /// False when it is no scene of this format at all.
    fn root(&mut self, root: &Json<'_>) -> bool {
        let path = Pointer::default();
        let Some(object) = self.object(root, &path) else {
            return false;
        };
        // The format first: another version's fields mean other things, so
        // with an unsupported one nothing else is read or reported.
        let format = object
            .properties
            .iter()
            .find(|p| p.name.as_str() == "format");
        if let Some(format) = format {
            match &format.value {
                Json::StringLit(s) if s.value == model::FORMAT => {}
                Json::StringLit(s) => {
                    self.errors.push(JsonError::UnsupportedFormat {
                        expected: model::FORMAT.to_string(),
                        found: s.value.to_string(),
                        span: span_of(s).into(),
                    });
                    return false;
                }
                other => self.wrong_type(
                    other,
                    &path.child("format"),
                    "a string",
                    format!("write `\"format\": \"{}\"`", model::FORMAT),
                ),
            }
        }
        let fields = self.fields(object, &path, &ROOT);
        self.require(&fields, &ROOT, brace(object));
        match fields.get("camera") {
            Some(camera) => self.camera(camera, &path.child("camera")),
            // Reported missing above; keep the check pass from saying so too.
            None => (self.each)(Section {
                kind: Spanned::new(brace(object), SectionKind::Camera),
                args: smallvec::smallvec![Spanned::new(brace(object), Value::Invalid)],
                attributes: Vec::new(),
                span: brace(object),
            }),
        }
        for (name, each) in [
            (
                "objects",
                Self::scene_object as fn(&mut Self, &Json<'_>, &Pointer),
            ),
            ("lights", Self::light),
        ] {
            let Some(list) = fields.get(name) else {
                continue;
            };
            let path = path.child(name);
            if let Some(array) = self.array(&list.value, &path) {
                for (i, element) in array.elements.iter().enumerate() {
                    each(self, element, &path.index(i));
                }
            }
        }
        true
    }

    /// `"camera": {"resolution": N}`.
    fn camera(&mut self, prop: &ObjectProp<'_>, path: &Pointer) {
        let key = span_of(&prop.name);
        let mut section = Section {
            kind: Spanned::new(key, SectionKind::Camera),
            args: Default::default(),
            attributes: Vec::new(),
            span: span_of(prop),
        };
        let resolution = match self.object(&prop.value, path) {
            Some(object) => {
                let fields = self.fields(object, path, &CAMERA);
                self.require(&fields, &CAMERA, brace(object));
                fields
                    .get("resolution")
                    .map(|r| self.number(&r.value, &path.child("resolution")))
            }
            None => None,
        };
        section.args = smallvec::smallvec![resolution.unwrap_or(Spanned::new(key, Value::Invalid))];
        (self.each)(section);
    }

    /// One element of `objects`: a sphere or a plane, by its `type`.
    fn scene_object(&mut self, value: &Json<'_>, path: &Pointer) {
        let Some(object) = self.object(value, path) else {
            return;
        };
        let type_prop = object.properties.iter().find(|p| p.name.as_str() == "type");
        let Some(type_prop) = type_prop else {
            self.errors.push(JsonError::MissingField {
                names: "`type`".to_string(),
                place: path.place(),
                span: brace(object).into(),
                help: "add `\"type\": \"sphere\"` or `\"type\": \"plane\"` to this object"
                    .to_string(),
            });
            return;
        };
        let type_path = path.child("type");
        let kind = match &type_prop.value {
            Json::StringLit(s) if s.value == "sphere" => SectionKind::Sphere,
            Json::StringLit(s) if s.value == "plane" => SectionKind::Plane,
            other => {
                let help = match other {
                    Json::StringLit(s) => suggest::nearest(&s.value, &TYPES)
                        .map(|(near, _)| format!("did you mean `\"{near}\"`?")),
                    _ => None,
                };
                self.errors.push(JsonError::Schema {
                    expected: "`\"sphere\"` or `\"plane\"`".to_string(),
                    place: type_path.place(),
                    found: describe(other),
                    span: span_of(other).into(),
                    help: help.unwrap_or_else(|| {
                        "an object's `type` is `\"sphere\"` or `\"plane\"`".to_string()
                    }),
                });
                return;
            }
        };
        let section = self.section(object, path, kind, span_of(&type_prop.value));
        (self.each)(section);
    }

    /// One element of `lights`.
    fn light(&mut self, value: &Json<'_>, path: &Pointer) {
        let Some(object) = self.object(value, path) else {
            return;
        };
        let section = self.section(object, path, SectionKind::Light, brace(object));
        (self.each)(section);
    }

    /// The section an object of `kind` describes: its fields checked
    /// against the language table, then one attribute per row of the table
    /// that the object gives (or must give: a missing required one gets a
    /// placeholder, reported once as a missing field).
    fn section(
        &mut self,
        object: &Object<'_>,
        path: &Pointer,
        kind: SectionKind,
        keyword: Span,
    ) -> Section {
        let takes = fields_of(&kind);
        let given = self.fields(object, path, &takes);
        self.require(&given, &takes, brace(object));
        let attributes = language::attributes_of(&kind)
            .iter()
            .filter_map(|spec| self.attribute(&given, spec, brace(object)))
            .collect();
        Section {
            kind: Spanned::new(keyword, kind),
            args: Default::default(),
            attributes,
            span: span_of(object),
        }
    }

    /// The attribute `spec` from its JSON fields, `None` when an optional
    /// one is absent (or a texture is `null`).
    fn attribute(
        &mut self,
        given: &Fields<'_, '_>,
        spec: &AttrSpec,
        missing: Span,
    ) -> Option<Attribute> {
        let first = given.get(spec.json[0]);
        match spec.arity {
            Arity::Path => self.texture(first?, spec.attr_name(), &given.path.child(spec.json[0])),
            Arity::Numbers(n) if spec.json.len() == n => {
                let any = spec.json.iter().any(|name| given.get(name).is_some());
                (any || spec.required).then(|| self.scalars(given, spec, missing))
            }
            Arity::Numbers(n) => match first {
                Some(prop) => {
                    Some(self.vector(prop, spec.attr_name(), n, &given.path.child(spec.json[0])))
                }
                None => spec.required.then(|| Attribute {
                    name: Spanned::new(missing, spec.attr_name()),
                    values: vec![Spanned::new(missing, Value::Invalid); n].into(),
                    span: missing,
                }),
            },
        }
    }

    /// An attribute whose numbers are separate fields, one each (`radius`;
    /// `width` and `height`; `reflectivity`), with a placeholder for each
    /// missing one.
    fn scalars(&mut self, given: &Fields<'_, '_>, spec: &AttrSpec, missing: Span) -> Attribute {
        let mut values = Vec::new();
        let mut name_span = None;
        let mut span = missing;
        for name in spec.json {
            match given.get(name) {
                Some(prop) => {
                    name_span.get_or_insert(span_of(&prop.name));
                    span = if values.is_empty() {
                        span_of(prop)
                    } else {
                        span.join(span_of(prop))
                    };
                    values.push(self.number(&prop.value, &given.path.child(name)));
                }
                None => values.push(Spanned::new(missing, Value::Invalid)),
            }
        }
        Attribute {
            name: Spanned::new(name_span.unwrap_or(missing), spec.attr_name()),
            values: values.into(),
            span,
        }
    }

    /// `[x, y, z]` as an attribute of `n` (three) values.
    fn vector(
        &mut self,
        prop: &ObjectProp<'_>,
        attr: AttrName,
        n: usize,
        path: &Pointer,
    ) -> Attribute {
        let values = match &prop.value {
            Json::Array(array) if array.elements.len() == n => array
                .elements
                .iter()
                .enumerate()
                .map(|(i, element)| self.number(element, &path.index(i)))
                .collect(),
            other => {
                self.wrong_type(
                    other,
                    path,
                    "an array of 3 numbers",
                    "write three numbers, such as `[0, 1, -5]`".to_string(),
                );
                vec![Spanned::new(span_of(other), Value::Invalid); n]
            }
        };
        attribute(prop, attr, values)
    }

    /// `"texture": "path"`; `null` means no texture, as in the serde model.
    fn texture(
        &mut self,
        prop: &ObjectProp<'_>,
        attr: AttrName,
        path: &Pointer,
    ) -> Option<Attribute> {
        let value = match &prop.value {
            Json::NullKeyword(_) => return None,
            Json::StringLit(s) => Spanned::new(span_of(s), Value::Text(s.value.as_ref().into())),
            other => {
                self.wrong_type(
                    other,
                    path,
                    "a string",
                    "write the image path as a string, such as `\"wood_tex.ppm\"`".to_string(),
                );
                Spanned::new(span_of(other), Value::Invalid)
            }
        };
        Some(attribute(prop, attr, vec![value]))
    }

    /// A number value, or a placeholder after reporting what is there.
    fn number(&mut self, value: &Json<'_>, path: &Pointer) -> Spanned<Value> {
        let span = span_of(value);
        match value {
            Json::NumberLit(n) => match n.value.parse::<f64>() {
                Ok(x) if x.is_finite() => Spanned::new(span, Value::Number(x)),
                // serde_json rejected this already; never trust it twice.
                _ => {
                    self.errors.push(JsonError::Syntax {
                        message: format!("number `{}` is out of range", n.value),
                        span: span.into(),
                    });
                    Spanned::new(span, Value::Invalid)
                }
            },
            other => {
                self.wrong_type(
                    other,
                    path,
                    "a number",
                    "numbers are written without quotes, such as `1`, `-0.5` or `1e3`".to_string(),
                );
                Spanned::new(span, Value::Invalid)
            }
        }
    }

    /// The object `value` is, or `None` after reporting what it is.
    fn object<'v, 'a>(&mut self, value: &'v Json<'a>, path: &Pointer) -> Option<&'v Object<'a>> {
        match value {
            Json::Object(object) => Some(object),
            other => {
                self.wrong_type(
                    other,
                    path,
                    "an object",
                    "see docs/formats.md for the layout of a JSON scene".to_string(),
                );
                None
            }
        }
    }

    /// The array `value` is, or `None` after reporting what it is.
    fn array<'v, 'a>(&mut self, value: &'v Json<'a>, path: &Pointer) -> Option<&'v Array<'a>> {
        match value {
            Json::Array(array) => Some(array),
            other => {
                self.wrong_type(
                    other,
                    path,
                    "an array",
                    "write a list in brackets, such as `[]` for none".to_string(),
                );
                None
            }
        }
    }

    fn wrong_type(&mut self, found: &Json<'_>, path: &Pointer, expected: &str, help: String) {
        self.errors.push(JsonError::Schema {
            expected: expected.to_string(),
            place: path.place(),
            found: describe(found),
            span: span_of(found).into(),
            help,
        });
    }

    /// The fields of `object` that `takes` lists, reporting unknown and
    /// repeated ones.
    fn fields<'v, 'a>(
        &mut self,
        object: &'v Object<'a>,
        path: &Pointer,
        takes: &[Field],
    ) -> Fields<'v, 'a> {
        let names: Vec<&str> = takes.iter().map(|f| f.name).collect();
        let mut given: Vec<&'v ObjectProp<'a>> = Vec::new();
        for prop in &object.properties {
            let name = prop.name.as_str();
            if let Some(first) = given.iter().find(|p| p.name.as_str() == name) {
                self.errors.push(JsonError::DuplicateField {
                    name: name.to_string(),
                    place: path.place(),
                    first: span_of(&first.name).into(),
                    second: span_of(&prop.name).into(),
                });
            } else if names.contains(&name) {
                given.push(prop);
            } else {
                let help = match suggest::nearest(name, &names) {
                    Some((near, _)) => format!("did you mean `{near}`?"),
                    None => format!("this object takes {}", language::list(&names)),
                };
                self.errors.push(JsonError::UnknownField {
                    found: name.to_string(),
                    place: path.place(),
                    span: span_of(&prop.name).into(),
                    help,
                });
            }
        }
        Fields {
            path: path.clone(),
            given,
        }
    }

    /// Report the required fields of `takes` that `given` lacks, in one
    /// diagnostic labelled at `at`.
    fn require(&mut self, given: &Fields<'_, '_>, takes: &[Field], at: Span) {
        let missing: Vec<&Field> = takes
            .iter()
            .filter(|f| f.required && given.get(f.name).is_none())
            .collect();
        if missing.is_empty() {
            return;
        }
        let names: Vec<&str> = missing.iter().map(|f| f.name).collect();
        let example: Vec<String> = missing
            .iter()
            .map(|f| format!("\"{}\": {}", f.name, f.example.text()))
            .collect();
        self.errors.push(JsonError::MissingField {
            names: language::list(&names),
            place: given.path.place(),
            span: at.into(),
            help: format!("add `{}` to this object", example.join(", ")),
        });
    }
}

/// An attribute named by an object field, spanning the whole field.
fn attribute(prop: &ObjectProp<'_>, name: AttrName, values: Vec<Spanned<Value>>) -> Attribute {
    Attribute {
        name: Spanned::new(span_of(&prop.name), name),
        values: values.into(),
        span: span_of(prop),
    }
}

#[cfg(test)]
mod tests;
