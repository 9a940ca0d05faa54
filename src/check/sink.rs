//! What the check pass keeps of a valid scene, chosen by the caller.
//!
//! Rendering and converting need the whole model, so [`Collect`] gathers
//! every valid object into a [`Checked`] scene. `raytracer check` needs only
//! the diagnostics and the effects the scene calls for, so [`Summarise`]
//! folds each valid object into a [`Summary`] and drops it: a scene of a
//! million spheres is checked without its model ever existing. The check
//! pass itself ([`super::SceneCheck`]) is the same for both, so they report
//! the same diagnostics.

use std::collections::BTreeMap;

use super::Checked;
use crate::model;
use crate::texture::Texture;

/// Where the check pass puts each valid object, and what it makes of a
/// valid scene at the end.
pub trait Sink: Default + Send {
    /// What a valid scene becomes.
    type Scene;

    /// Take the next valid object, in file order.
    fn object(&mut self, object: model::Object);

    /// Take, in order, what another sink took of the objects after these.
    fn append(&mut self, later: Self);

    /// The scene, once the whole file checked without errors.
    fn scene(
        self,
        camera: model::Camera,
        lights: Vec<model::Light>,
        textures: BTreeMap<String, Texture>,
    ) -> Self::Scene;
}

/// Keeps the whole model, for the commands that render or convert it.
#[derive(Debug, Default)]
pub struct Collect {
    objects: Vec<model::Object>,
}

/// Objects [`Collect::append`] moves at a time.
const MOVE_BLOCK: usize = 1 << 16;

impl Sink for Collect {
    type Scene = Checked;

    fn object(&mut self, object: model::Object) {
        self.objects.push(object);
    }

    /// The later list is moved over a block of [`MOVE_BLOCK`] objects at a
    /// time and shrunk after each, so the two lists never hold the later
    /// objects twice: for a million spheres checked in two halves, a
    /// second copy of half the model would be the run's peak. A list only
    /// shrinks from its end, so the later one is reversed first and its
    /// end is then its first objects.
    fn append(&mut self, later: Self) {
        let mut later = later.objects;
        self.objects.reserve_exact(later.len());
        later.reverse();
        while !later.is_empty() {
            let first = later.split_off(later.len().saturating_sub(MOVE_BLOCK));
            later.shrink_to_fit();
            self.objects.extend(first.into_iter().rev());
        }
    }

    fn scene(
        self,
        camera: model::Camera,
        lights: Vec<model::Light>,
        textures: BTreeMap<String, Texture>,
    ) -> Checked {
        let mut objects = self.objects;
        objects.shrink_to_fit();
        Checked {
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

    fn append(&mut self, later: Self) {
        let (summary, more) = (&mut self.summary, later.summary);
        summary.objects += more.objects;
        summary.reflective |= more.reflective;
        summary.textured |= more.textured;
    }

    fn scene(
        self,
        _camera: model::Camera,
        lights: Vec<model::Light>,
        _textures: BTreeMap<String, Texture>,
    ) -> Summary {
        Summary {
            lights: lights.len(),
            ..self.summary
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere(k: usize) -> model::Object {
        model::Object {
            shape: model::Shape::Sphere {
                center: [k as f64, 0.0, 0.0],
                radius: 1.0,
            },
            material: model::Material::default(),
        }
    }

    fn collect(range: std::ops::Range<usize>) -> Collect {
        let mut sink = Collect::default();
        for k in range {
            sink.object(sphere(k));
        }
        sink
    }

    #[test]
    fn appending_keeps_file_order_across_several_blocks() {
        let (first, total) = (1000, 1000 + 2 * MOVE_BLOCK + 123);
        let mut sink = collect(0..first);
        sink.append(collect(first..total));
        let checked = sink.scene(model::Camera { resolution: 4 }, Vec::new(), BTreeMap::new());
        let objects = checked.scene.objects;
        assert_eq!(objects.len(), total);
        assert!(objects.iter().enumerate().all(|(k, o)| *o == sphere(k)));
    }
}
