//! The render IR: the scene as the tracer needs it.
//!
//! No spans and nothing left to validate: normals are unit length, each
//! plane carries its precomputed `right`/`up` basis, textures are decoded,
//! and [`Effects`] records which effects the scene calls for so the tracer
//! casts no ray it does not need. Built by [`lower`] from a checked
//! [`raytracer_scene::model::Scene`]; lowering cannot fail. The IR round-trips through
//! serde JSON. Decoded textures are the [`Texture`]s of [`raytracer_scene::texture`],
//! moved here from the checked scene.

mod lower;

use glam::DVec3;
use serde::{Deserialize, Serialize};

pub use lower::lower;

use raytracer_scene::check::Summary;
use raytracer_scene::model;
pub use raytracer_scene::texture::Texture;

/// A scene ready to render.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Scene {
    /// Image width and height in pixels.
    pub resolution: u32,
    pub objects: Vec<Object>,
    /// The scene's distinct materials; [`Object::material`] indexes this
    /// list. Most scenes have a handful however many objects they hold, so
    /// shading reads a small table.
    pub materials: Vec<Material>,
    pub lights: Vec<Light>,
    /// Decoded textures; [`Material::texture`] indexes this list.
    pub textures: Vec<Texture>,
    pub effects: Effects,
}

impl Scene {
    /// The material `object` is made of.
    pub fn material(&self, object: &Object) -> &Material {
        &self.materials[object.material as usize]
    }
}

/// A primitive with its material.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Object {
    pub shape: Shape,
    /// Index into [`Scene::materials`].
    pub material: u32,
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

/// The effects a scene calls for; the tracer skips every other kind of work.
/// Computed here, where the IR is built ([`Effects::of`]).
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
    /// The effects `scene` calls for: shadows when it has lights,
    /// reflection when an object reflects, textures when one is textured.
    pub fn of(scene: &model::Scene) -> Effects {
        Effects::of_summary(&Summary::of(scene))
    }

    /// The effects of the scene `summary` describes, as [`Effects::of`]
    /// gives them for the scene itself.
    pub fn of_summary(summary: &Summary) -> Effects {
        Effects {
            shadows: summary.lights > 0,
            reflection: summary.reflective,
            textures: summary.textured,
        }
    }

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
