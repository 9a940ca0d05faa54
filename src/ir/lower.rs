//! Lowering: a checked scene model to the render IR.
//!
//! Built in dependency order (the pbrt-v4 way): textures first, each
//! decoded once however many objects use it, then the materials that index
//! them, then the shapes with their derived geometry, then the lights; the
//! [`super::Effects`] summary is the check pass's [`Checked::effects`]. Every input was validated by the check
//! pass, so each step is a total function: there is nothing left to fail.

use std::collections::BTreeMap;

use glam::DVec3;

use super::{Light, Material, Object, Scene, Shape, Texture};
use crate::check::geometry::{self, Basis};
use crate::check::Checked;
use crate::model;

/// Lower a checked scene to the render IR.
pub fn lower(checked: &Checked) -> Scene {
    let scene = &checked.scene;
    let mut textures: Vec<Texture> = Vec::new();
    let mut texture_index: BTreeMap<&str, usize> = BTreeMap::new();
    let objects: Vec<Object> = scene
        .objects
        .iter()
        .map(|object| {
            let texture = object.material.texture.as_deref().and_then(|path| {
                if let Some(&index) = texture_index.get(path) {
                    return Some(index);
                }
                let decoded = checked.textures.get(path)?;
                textures.push(decoded.clone());
                texture_index.insert(path, textures.len() - 1);
                Some(textures.len() - 1)
            });
            Object {
                shape: shape(&object.shape),
                material: Material {
                    color: DVec3::from_array(object.material.color),
                    reflectivity: object.material.reflectivity,
                    texture,
                },
            }
        })
        .collect();
    let lights: Vec<Light> = scene
        .lights
        .iter()
        .map(|light| Light {
            position: DVec3::from_array(light.location),
            color: DVec3::from_array(light.color),
        })
        .collect();
    Scene {
        resolution: scene.camera.resolution,
        objects,
        lights,
        textures,
        effects: checked.effects(),
    }
}

fn shape(shape: &model::Shape) -> Shape {
    match *shape {
        model::Shape::Sphere { center, radius } => Shape::Sphere {
            center: DVec3::from_array(center),
            radius,
        },
        model::Shape::Plane {
            center,
            width,
            height,
            normal,
            headup,
        } => {
            let Basis { normal, right, up } = frame(normal, headup);
            Shape::Rect {
                center: DVec3::from_array(center),
                normal,
                right,
                up,
                width,
                height,
            }
        }
    }
}

/// The plane's frame of SPEC.md §2. The check pass rejects zero and
/// parallel vectors, so the fallback (the camera's own frame) is never
/// reached by a checked scene; it keeps lowering total.
fn frame(normal: [f64; 3], headup: [f64; 3]) -> Basis {
    geometry::plane_basis(normal, headup).unwrap_or(Basis {
        normal: DVec3::Z,
        right: DVec3::X,
        up: DVec3::Y,
    })
}
