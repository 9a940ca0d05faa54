//! Lowering: a checked scene model to the render IR.
//!
//! Built in dependency order (the pbrt-v4 way): textures first, each
//! decoded once however many objects use it, then the table of distinct
//! materials that index them, then the shapes with their derived geometry,
//! then the lights, and the [`Effects`] summary. The checked scene is taken
//! by value: its decoded textures move into the IR, so peak memory holds
//! their texels once. Every input was validated by the check pass, so each
//! step is a total function: there is nothing left to fail.

use std::collections::{BTreeMap, HashMap};

use glam::DVec3;

use super::{Effects, Light, Material, Object, Scene, Shape, Texture};
use raytracer_scene::check::Checked;
use raytracer_scene::geometry::{self, Basis};
use raytracer_scene::model;

/// Lower a checked scene to the render IR, moving its decoded textures
/// (never copying their texels).
///
/// ```
/// use std::path::Path;
/// use std::time::Instant;
///
/// let text = "camera 8\nsphere\n  dimension 1\n  center 0 0 -5\n  reflectivity 0.5\n";
/// let loaded = raytracer_scene::frontend::load_bytes("a.txt", Path::new("."), text.as_bytes());
/// let scene = raytracer_render::ir::lower(loaded.checked.unwrap());
/// assert_eq!(scene.resolution, 8);
/// assert_eq!(scene.objects.len(), 1);
/// assert_eq!(scene.material(&scene.objects[0]).reflectivity, 0.5);
/// ```
pub fn lower(checked: Checked) -> Scene {
    let Checked {
        scene,
        textures: mut decoded,
    } = checked;
    let effects = Effects::of(&scene);
    let mut textures: Vec<Texture> = Vec::new();
    let mut texture_index: BTreeMap<&str, usize> = BTreeMap::new();
    let mut materials: Vec<Material> = Vec::new();
    let mut material_index: HashMap<MaterialKey, u32> = HashMap::new();
    let objects: Vec<Object> = scene
        .objects
        .iter()
        .map(|object| {
            let texture = object.material.texture.as_deref().and_then(|path| {
                if let Some(&index) = texture_index.get(path) {
                    return Some(index);
                }
                textures.push(decoded.remove(path)?);
                texture_index.insert(path, textures.len() - 1);
                Some(textures.len() - 1)
            });
            let material = Material {
                color: DVec3::from_array(object.material.color),
                reflectivity: object.material.reflectivity,
                texture,
            };
            let material = *material_index
                .entry(MaterialKey::of(&material))
                .or_insert_with(|| {
                    materials.push(material);
                    materials.len() as u32 - 1
                });
            Object {
                shape: shape(&object.shape),
                material,
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
        materials,
        lights,
        textures,
        effects,
    }
}

/// A material's bits, to find equal materials: two objects share a table
/// entry only when every field is the same number.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
struct MaterialKey([u64; 4], Option<usize>);

impl MaterialKey {
    fn of(m: &Material) -> MaterialKey {
        let [r, g, b] = m.color.to_array().map(f64::to_bits);
        MaterialKey([r, g, b, m.reflectivity.to_bits()], m.texture)
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

/// The plane's frame of docs/rendering.md. The check pass rejects zero
/// vectors, so the fallback (the camera's own frame) is never reached by a
/// checked scene; it keeps lowering total.
fn frame(normal: [f64; 3], headup: [f64; 3]) -> Basis {
    geometry::plane_basis(normal, headup).unwrap_or(Basis {
        normal: DVec3::Z,
        right: DVec3::X,
        up: DVec3::Y,
    })
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use raytracer_scene::frontend::load_bytes;

    fn lowered(text: &str, dir: &Path) -> Scene {
        let loaded = load_bytes("t.txt", dir, text.as_bytes());
        lower(loaded.checked.expect("scene checks"))
    }

    #[test]
    fn the_ir_round_trips_through_json() {
        let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes"));
        let text = std::fs::read_to_string(dir.join("sample.txt")).expect("sample");
        let scene = lowered(&text, dir);
        let json = serde_json::to_string(&scene).expect("serialise");
        let back: Scene = serde_json::from_str(&json).expect("deserialise");
        assert_eq!(back, scene);
        assert_eq!(scene.textures.len(), 1);
    }

    #[test]
    fn derived_geometry_and_effects() {
        let scene = lowered(
            "camera 8
             plane dimension 2 4 center 0 0 -5 normal 0 0 2 headup 0 3 1 reflectivity .5
             sphere dimension 1 center 0 0 -9",
            Path::new("."),
        );
        let Shape::Rect {
            normal, right, up, ..
        } = scene.objects[0].shape
        else {
            panic!("not a rectangle")
        };
        assert_eq!(normal, DVec3::Z);
        assert!((up - DVec3::Y).length() < 1e-15, "headup is projected");
        assert!((right - DVec3::X).length() < 1e-15, "right = up × n");
        assert_eq!(
            scene.effects,
            crate::ir::Effects {
                shadows: false,
                reflection: true,
                textures: false
            }
        );
    }

    #[test]
    fn a_texture_named_twice_is_decoded_once() {
        let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes"));
        let scene = lowered(
            "camera 8
             sphere dimension 1 center 0 0 -5 texture wood_tex.ppm
             sphere dimension 1 center 2 0 -5 texture wood_tex.ppm",
            dir,
        );
        assert_eq!(scene.textures.len(), 1);
        assert_eq!(scene.material(&scene.objects[1]).texture, Some(0));
        assert_eq!(scene.materials.len(), 1);
    }

    #[test]
    fn objects_made_of_the_same_material_share_its_entry() {
        let scene = lowered(
            "camera 8
             sphere dimension 1 center 0 0 -5 color 1 0 0
             sphere dimension 1 center 2 0 -5 color 0 1 0
             sphere dimension 1 center 4 0 -5 color 1 0 0
             sphere dimension 1 center 6 0 -5 color 1 0 0 reflectivity 0.5",
            Path::new("."),
        );
        let indices: Vec<u32> = scene.objects.iter().map(|o| o.material).collect();
        assert_eq!(indices, [0, 1, 0, 2]);
        assert_eq!(scene.materials.len(), 3);
        assert_eq!(scene.material(&scene.objects[3]).reflectivity, 0.5);
    }
}
