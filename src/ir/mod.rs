//! The render IR: the scene as the tracer needs it.
//!
//! No spans and nothing left to validate: normals are unit length, each
//! plane carries its precomputed `right`/`up` basis, textures are decoded,
//! and [`Effects`] records which effects the scene calls for so the tracer
//! casts no ray it does not need. Built by [`lower`] from a checked
//! [`crate::model::Scene`]; lowering cannot fail. The IR round-trips through
//! serde JSON.

mod lower;

use glam::DVec3;
use serde::{Deserialize, Serialize};

pub use lower::lower;

/// A scene ready to render.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Scene {
    /// Image width and height in pixels.
    pub resolution: u32,
    pub objects: Vec<Object>,
    pub lights: Vec<Light>,
    /// Decoded textures; [`Material::texture`] indexes this list.
    pub textures: Vec<Texture>,
    pub effects: Effects,
}

/// A primitive with its material.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Object {
    pub shape: Shape,
    pub material: Material,
}

/// Geometry in world space.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Shape {
    Sphere {
        center: DVec3,
        radius: f64,
    },
    /// A finite two-sided rectangle: `|(p−c)·right| ≤ half_width` and
    /// `|(p−c)·up| ≤ half_height` on the plane through `center`.
    Rect {
        center: DVec3,
        /// Unit normal.
        normal: DVec3,
        /// Unit, `up × normal`.
        right: DVec3,
        /// Unit, headup projected onto the plane.
        up: DVec3,
        width: f64,
        height: f64,
    },
}

/// Surface properties.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// Linear RGB in [0, 1]; unused when `texture` is set.
    pub color: DVec3,
    /// Mirror weight in [0, 1].
    pub reflectivity: f64,
    /// Index into [`Scene::textures`].
    pub texture: Option<usize>,
}

/// A point light.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Light {
    pub position: DVec3,
    /// Intensity per channel, ≥ 0.
    pub color: DVec3,
}

/// A decoded image, row 0 at the top, channels scaled to [0, 1].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Texture {
    /// The resolved path it was loaded from, for messages.
    pub path: String,
    pub width: u32,
    pub height: u32,
    /// `width × height` texels, row-major.
    pub texels: Vec<[f32; 3]>,
}

/// The effects a scene calls for; the tracer skips every other kind of work.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Effects {
    /// At least one light: shadow rays are cast.
    pub shadows: bool,
    /// At least one object with reflectivity > 0: reflection rays are cast.
    pub reflection: bool,
    /// At least one textured object: texture lookups happen.
    pub textures: bool,
}

impl Effects {
    /// The names of the effects in use, `["shadows", "reflection"]`.
    pub fn names(&self) -> Vec<&'static str> {
        [
            (self.shadows, "shadows"),
            (self.reflection, "reflection"),
            (self.textures, "textures"),
        ]
        .into_iter()
        .filter_map(|(on, name)| on.then_some(name))
        .collect()
    }

    /// [`Effects::names`] joined with commas, or `none`.
    pub fn summary(&self) -> String {
        let names = self.names();
        if names.is_empty() {
            "none".to_string()
        } else {
            names.join(", ")
        }
    }
}
