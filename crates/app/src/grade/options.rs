//! The constants a course renders our reference with instead of ours:
//! `--reference-options FILE` or a suite.json's `reference`, a JSON
//! object with any of the illumination [`Model`]'s keys and `depth`.

use raytracer_render::render::{Model, Options};

/// The keys of `--reference-options`: the [`Model`]'s and `depth`.
const DEPTH: &str = "depth";

/// The most reflections `depth` may ask for.
const MAX_DEPTH: u64 = 64;

/// Our renderer's options as a `--reference-options` file gives them: a
/// JSON object with any of the [`Model`]'s keys and `depth`, the others
/// left at our renderer's own; a message in words for anything else.
pub fn read_options(text: &str) -> Result<Options, String> {
    let mut object = match serde_json::from_str::<serde_json::Value>(text) {
        Ok(serde_json::Value::Object(object)) => object,
        Ok(other) => {
            return Err(format!(
                "expected a JSON object, found {}",
                match other {
                    serde_json::Value::Array(_) => "an array",
                    serde_json::Value::String(_) => "a string",
                    serde_json::Value::Number(_) => "a number",
                    serde_json::Value::Bool(_) => "a boolean",
                    _ => "null",
                }
            ))
        }
        Err(error) => return Err(format!("not JSON: {error}")),
    };
    let mut options = Options::default();
    if let Some(depth) = object.remove(DEPTH) {
        options.max_depth = depth.as_u64().filter(|d| *d <= MAX_DEPTH).ok_or_else(|| {
            format!("expected a whole number from 0 to {MAX_DEPTH} for `{DEPTH}`, found {depth}")
        })? as u32;
    }
    options.model = serde_json::from_value::<Model>(serde_json::Value::Object(object))
        .map_err(|error| error.to_string())?;
    options.model.validate()?;
    Ok(options)
}
