//! The JSON layout of a scene: `convert --to json` output and the JSON
//! Schema published as docs/scene.schema.json.
//!
//! Both come from the serde model ([`crate::model::Scene`]) and its
//! `schemars` derive, so neither can drift from what `.json` scenes are read
//! as; the schema's attribute descriptions and examples come from the
//! language table ([`crate::language`]), as docs/language.md's do. The output is serde's, laid out for people: two-space indentation,
//! one field per line, and vectors (arrays of numbers) on one line.

use serde_json::Value;

use crate::ast::SectionKind;
use crate::language;
use crate::model;

/// `scene` as pretty JSON, ending in a newline.
///
/// ```
/// use std::path::Path;
/// use std::time::Instant;
///
/// let text = "camera 4\nlight\n  location 0 5 0\n  color 1 1 1\n";
/// let loaded = raytracer_scene::frontend::load_bytes("a.txt", Path::new("."), text.as_bytes());
/// let json = raytracer_scene::convert::json::to_json(&loaded.checked.unwrap().scene);
/// assert!(json.contains("\"resolution\": 4"));
/// assert!(json.contains("\"location\""));
/// ```
pub fn to_json(scene: &model::Scene) -> String {
    // The model has only strings, numbers, arrays and maps with string
    // keys, so serialising it cannot fail.
    let mut value = serde_json::to_value(scene).unwrap_or(Value::Null);
    drop_default_color_beside_texture(&mut value);
    let mut out = String::new();
    layout(&value, 0, &mut out);
    out.push('\n');
    out
}

/// The JSON Schema of the scene layout, pretty, ending in a newline: the
/// shape from the serde model, each attribute's description and example
/// from the language table.
pub fn schema() -> String {
    let mut schema = serde_json::to_value(schemars::schema_for!(model::Scene)).unwrap_or_default();
    describe_attributes(&mut schema);
    let mut out = serde_json::to_string_pretty(&schema).unwrap_or_default();
    out.push('\n');
    out
}

/// Give every attribute field of the schema's camera, objects and lights
/// the description, example, bounds and default of its row in the
/// registry.
fn describe_attributes(schema: &mut Value) {
    let definitions = &mut schema["definitions"];
    if let Some(Value::Object(properties)) = definitions["Camera"].get_mut("properties") {
        describe_field(properties, &language::CAMERA);
    }
    describe(&mut definitions["Light"]["properties"], &SectionKind::Light);
    let object = &mut definitions["Object"];
    // The material's fields are the same row for spheres and planes.
    describe(&mut object["properties"], &SectionKind::Sphere);
    if let Some(Value::Array(shapes)) = object.get_mut("oneOf") {
        for shape in shapes {
            let kind = match shape["properties"]["type"]["enum"][0].as_str() {
                Some("sphere") => SectionKind::Sphere,
                Some("plane") => SectionKind::Plane,
                _ => continue,
            };
            describe(&mut shape["properties"], &kind);
        }
    }
}

fn describe(properties: &mut Value, kind: &SectionKind) {
    let Some(properties) = properties.as_object_mut() else {
        return;
    };
    for spec in language::attributes_of(kind) {
        describe_field(properties, spec);
    }
}

/// The fields of `spec` among `properties`, described from its row.
fn describe_field(properties: &mut serde_json::Map<String, Value>, spec: &language::AttrSpec) {
    for (i, name) in spec.json.iter().enumerate() {
        let Some(Value::Object(field)) = properties.get_mut(*name) else {
            continue;
        };
        field.insert("description".to_string(), Value::String(spec.summary()));
        if let Ok(example) = serde_json::from_str::<Value>(&spec.json_example(i)) {
            field.insert("examples".to_string(), Value::Array(vec![example]));
        }
        if let Some(default) = spec.default {
            field.insert("default".to_string(), default.json());
        }
        // A vector's bounds hold for each of its numbers.
        let numbers = match field.get_mut("items") {
            Some(Value::Object(items)) => items,
            _ => &mut *field,
        };
        let (minimum, exclusive, maximum) = spec.bounds();
        if let Some(minimum) = minimum {
            let key = if exclusive {
                "exclusiveMinimum"
            } else {
                "minimum"
            };
            numbers.insert(key.to_string(), json_number(minimum));
        }
        if let Some(maximum) = maximum {
            numbers.insert("maximum".to_string(), json_number(maximum));
        }
    }
}

/// `x` as JSON, a whole number written without a fraction (`1`, not `1.0`).
fn json_number(x: f64) -> Value {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        Value::from(x as i64)
    } else {
        Value::from(x)
    }
}

/// The model fills in white when no colour is given, and a colour beside a
/// texture is ignored (and warned about when read back): leave that default
/// out, as scene text would not have it.
fn drop_default_color_beside_texture(scene: &mut Value) {
    let Some(Value::Array(objects)) = scene.get_mut("objects") else {
        return;
    };
    for object in objects.iter_mut().filter_map(Value::as_object_mut) {
        let white = serde_json::json!(model::Material::default().color);
        if object.contains_key("texture") && object.get("color") == Some(&white) {
            object.shift_remove("color");
        }
    }
}

/// Write `value` at nesting depth `depth`: objects and arrays that hold
/// objects or arrays one item per line, other arrays on one line.
fn layout(value: &Value, depth: usize, out: &mut String) {
    let pad = |out: &mut String, depth: usize| out.push_str(&"  ".repeat(depth));
    match value {
        Value::Object(map) if !map.is_empty() => {
            out.push_str("{\n");
            for (i, (key, item)) in map.iter().enumerate() {
                pad(out, depth + 1);
                out.push_str(&Value::String(key.clone()).to_string());
                out.push_str(": ");
                layout(item, depth + 1, out);
                out.push_str(if i + 1 < map.len() { ",\n" } else { "\n" });
            }
            pad(out, depth);
            out.push('}');
        }
        Value::Array(items) if items.iter().any(|v| v.is_object() || v.is_array()) => {
            out.push_str("[\n");
            for (i, item) in items.iter().enumerate() {
                pad(out, depth + 1);
                layout(item, depth + 1, out);
                out.push_str(if i + 1 < items.len() { ",\n" } else { "\n" });
            }
            pad(out, depth);
            out.push(']');
        }
        Value::Array(items) => {
            let items: Vec<String> = items.iter().map(Value::to_string).collect();
            out.push('[');
            out.push_str(&items.join(", "));
            out.push(']');
        }
        scalar => out.push_str(&scalar.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lays_out_vectors_on_one_line() {
        let scene = model::Scene {
            format: model::FORMAT.to_string(),
            camera: model::Camera { resolution: 4 },
            objects: vec![model::Object {
                shape: model::Shape::Sphere {
                    center: [0.0, -0.0, -5.0],
                    radius: 1e300,
                },
                material: model::Material::default(),
            }],
            lights: Vec::new(),
        };
        assert_eq!(
            to_json(&scene),
            r#"{
  "format": "raytracer-scene/1",
  "camera": {
    "resolution": 4
  },
  "objects": [
    {
      "type": "sphere",
      "center": [0.0, -0.0, -5.0],
      "radius": 1e+300,
      "color": [1.0, 1.0, 1.0],
      "reflectivity": 0.0
    }
  ],
  "lights": []
}
"#
        );
        let back: model::Scene = serde_json::from_str(&to_json(&scene)).unwrap();
        assert_eq!(back, scene);
    }
}
