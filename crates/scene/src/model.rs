//! The scene as data: what a checked scene file says, with defaults filled
//! in and nothing derived.
//!
//! This is the serde model that `convert --to json` writes and `.json` scenes
//! are read into, and what `convert --to scene|pov` print. Values are kept as
//! written (a non-unit normal stays non-unit, headup is not projected, the
//! texture path is relative to the scene file); everything derived for
//! rendering belongs to [`raytracer_render::ir`]. The top-level `format` field versions
//! the layout. The rules and defaults of each field are rows of the
//! registry ([`crate::language`]); the defaults here are read from it.

use serde::{Deserialize, Serialize};

use crate::ast::{AttrName, SectionKind};
use crate::language::{self, DefaultValue};

/// The value of [`Scene::format`] this version reads and writes.
pub const FORMAT: &str = "raytracer-scene/1";

/// A three-component vector or colour, `[x, y, z]` or `[r, g, b]`.
pub type Vec3 = [f64; 3];

/// A whole scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Layout version; always `"raytracer-scene/1"`.
    pub format: String,
    pub camera: Camera,
    /// Spheres and planes, in source order; default none.
    #[serde(default)]
    pub objects: Vec<Object>,
    /// Point lights, in source order; default none.
    #[serde(default)]
    pub lights: Vec<Light>,
}

/// The camera: fixed at the origin looking down −z; only the resolution varies.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Camera {
    /// Image width and height in pixels (the range is the registry's
    /// [`language::CAMERA`] row).
    pub resolution: u32,
}

/// A sphere or a finite plane with its material.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Object {
    #[serde(flatten)]
    pub shape: Shape,
    #[serde(flatten)]
    pub material: Material,
}

/// The geometry of an object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "type", rename_all = "lowercase")]
pub enum Shape {
    Sphere {
        center: Vec3,
        /// Radius (the scene language's `dimension`).
        radius: f64,
    },
    Plane {
        center: Vec3,
        /// Width along `right` and height along `up` (`dimension W H`).
        width: f64,
        height: f64,
        /// As written, not normalised.
        normal: Vec3,
        /// As written, not projected (one parallel to `normal` is warned
        /// about and an axis stands in).
        headup: Vec3,
    },
}

/// Surface properties shared by every object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Material {
    /// Ignored where a texture is given.
    #[serde(default = "default_color")]
    pub color: Vec3,
    /// Mirror weight.
    #[serde(default = "default_reflectivity")]
    pub reflectivity: f64,
    /// Image path as written, relative to the scene file's folder.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture: Option<String>,
}

/// The default of an object's attribute `name`, from the registry's row
/// (every optional material row has one: tested below).
fn object_default(name: AttrName) -> Option<DefaultValue> {
    language::default_of(&SectionKind::Sphere, &name)
}

/// The default object colour.
fn default_color() -> Vec3 {
    match object_default(AttrName::Color) {
        Some(DefaultValue::Vector(color)) => color,
        _ => Vec3::default(),
    }
}

/// The default reflectivity.
fn default_reflectivity() -> f64 {
    match object_default(AttrName::Reflectivity) {
        Some(DefaultValue::Number(k)) => k,
        _ => f64::default(),
    }
}

impl Default for Material {
    fn default() -> Self {
        Material {
            color: default_color(),
            reflectivity: default_reflectivity(),
            texture: None,
        }
    }
}

/// A point light.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Light {
    pub location: Vec3,
    /// Each channel ≥ 0; above 1 over-exposes.
    pub color: Vec3,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn material_defaults_are_the_registrys_for_both_shapes() {
        for kind in [SectionKind::Sphere, SectionKind::Plane] {
            assert_eq!(
                language::default_of(&kind, &AttrName::Color),
                Some(DefaultValue::Vector(Material::default().color))
            );
            assert_eq!(
                language::default_of(&kind, &AttrName::Reflectivity),
                Some(DefaultValue::Number(Material::default().reflectivity))
            );
        }
    }
}
