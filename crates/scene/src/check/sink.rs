//! What the check pass keeps of a valid scene, chosen by the caller.
//!
//! Rendering and converting need the whole model, so [`Collect`] gathers
//! every valid object into a [`Valid`] scene. `raytracer check` needs only
//! the diagnostics and the effects the scene calls for, so [`Summarise`]
//! folds each valid object into a [`Summary`] and drops it: a scene of a
//! million spheres is checked without its model ever existing. The check
//! pass itself ([`super::SceneCheck`]) is the same for both, so they report
//! the same diagnostics.

use std::collections::BTreeMap;

use super::Valid;
use crate::model;
use crate::texture::Header;

/// Where the check pass puts each valid object, and what it makes of a
/// valid scene at the end.
pub trait Sink: Default {
    /// What a valid scene becomes.
    type Scene;

    /// Take the next valid object, in file order.
    fn object(&mut self, object: model::Object);

    /// The scene, once the whole file checked without errors.
    fn scene(
        self,
        camera: model::Camera,
        lights: Vec<model::Light>,
        textures: BTreeMap<String, Header>,
    ) -> Self::Scene;
}

/// Keeps the whole model, for the commands that render or convert it.
#[derive(Debug, Default)]
pub struct Collect {
    objects: Vec<model::Object>,
}

impl Sink for Collect {
    type Scene = Valid;

    fn object(&mut self, object: model::Object) {
        self.objects.push(object);
    }

    fn scene(
        self,
        camera: model::Camera,
        lights: Vec<model::Light>,
        textures: BTreeMap<String, Header>,
    ) -> Valid {
        let mut objects = self.objects;
        objects.shrink_to_fit();
        Valid {
            scene: model::Scene {
                format: model::FORMAT.to_string(),
                camera,
                objects,
                lights,
            },
            textures,
        }
    }
}

/// What a valid scene holds, counted and flagged: all that the effects it
/// calls for depend on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Summary {
    /// Spheres and planes.
    pub objects: usize,
    pub lights: usize,
    /// Whether an object has reflectivity above 0.
    pub reflective: bool,
    /// Whether an object is textured.
    pub textured: bool,
}

impl Summary {
    /// The summary of a whole model.
    pub fn of(scene: &model::Scene) -> Summary {
        let mut summary = Summary {
            lights: scene.lights.len(),
            ..Summary::default()
        };
        for object in &scene.objects {
            summary.add(object);
        }
        summary
    }

    fn add(&mut self, object: &model::Object) {
        self.objects += 1;
        self.reflective |= object.material.reflectivity > 0.0;
        self.textured |= object.material.texture.is_some();
    }
}

/// Keeps only a [`Summary`], for `raytracer check`.
#[derive(Debug, Default)]
pub struct Summarise {
    summary: Summary,
}

impl Sink for Summarise {
    type Scene = Summary;

    fn object(&mut self, object: model::Object) {
        self.summary.add(&object);
    }

    fn scene(
        self,
        _camera: model::Camera,
        lights: Vec<model::Light>,
        _textures: BTreeMap<String, Header>,
    ) -> Summary {
        Summary {
            lights: lights.len(),
            ..self.summary
        }
    }
}
