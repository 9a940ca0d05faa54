//! What the render module's unit tests share: a scene, a sphere resting
//! on a floor in front of the eye (camera rays hit either shape, miss
//! both, and graze the sphere's rim and the floor's edges; the sphere
//! shadows the floor and, when it reflects, sees it; each test adds what
//! it needs: lights, textures, a resolution), and a seeded source of
//! random numbers for tests that fire many rays.

use glam::DVec3;

use crate::ir;

/// A sphere of radius 1 at `(0, 0, −5)`, object 0 in material 0 (grey,
/// reflecting `reflectivity`), on a 4 × 4 rectangle at `y = −1` facing
/// up, object 1 in material 1 (orange, not reflecting); no lights, no
/// textures, one pixel.
pub fn sphere_on_floor(reflectivity: f64) -> ir::Scene {
    let material = |color, reflectivity| ir::Material {
        color,
        reflectivity,
        texture: None,
    };
    ir::Scene {
        resolution: 1,
        objects: vec![
            ir::Object {
                shape: ir::Shape::Sphere {
                    center: DVec3::new(0.0, 0.0, -5.0),
                    radius: 1.0,
                },
                material: 0,
            },
            ir::Object {
                shape: ir::Shape::Rect {
                    center: DVec3::new(0.0, -1.0, -5.0),
                    normal: DVec3::Y,
                    right: DVec3::X,
                    up: DVec3::NEG_Z,
                    width: 4.0,
                    height: 4.0,
                },
                material: 1,
            },
        ],
        materials: vec![
            material(DVec3::splat(0.4), reflectivity),
            material(DVec3::new(0.9, 0.5, 0.2), 0.0),
        ],
        lights: Vec::new(),
        textures: Vec::new(),
        effects: ir::Effects::default(),
    }
}

/// Numbers uniform in `[0, 1)`, the same sequence for the same `seed`
/// (xorshift64, Marsaglia 2003; `seed` must not be 0).
pub fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}
