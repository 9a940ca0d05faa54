//! The warning for a light strictly inside a sphere.
//!
//! The warning names, for each light, the first sphere in the file whose
//! inside holds it, so every valid sphere has to be weighed against lights
//! that may come after it: each valid sphere's centre, radius and keyword
//! are kept until the end of the file, then every light is tested against
//! them in file order.

use glam::DVec3;

use crate::span::Span;

use super::errors::CheckError;
use super::format;

/// A valid sphere, as the warning needs it.
#[derive(Clone, Copy, Debug)]
pub struct SphereAt {
    pub center: [f64; 3],
    pub radius: f64,
    /// The sphere's keyword.
    pub span: Span,
}

impl SphereAt {
    /// The exact test: the light is strictly inside.
    fn holds(&self, location: DVec3) -> bool {
        location.distance(DVec3::from_array(self.center)) < self.radius
    }
}

/// A valid light location.
#[derive(Clone, Copy, Debug)]
pub struct LightAt {
    pub location: [f64; 3],
    pub span: Span,
}

/// The spheres and lights the warning weighs.
#[derive(Debug, Default)]
pub struct LightsInSpheres {
    spheres: Vec<SphereAt>,
    lights: Vec<LightAt>,
}

impl LightsInSpheres {
    /// The next valid sphere.
    pub fn sphere(&mut self, sphere: SphereAt) {
        self.spheres.push(sphere);
    }

    /// The next valid light.
    pub fn light(&mut self, light: LightAt) {
        self.lights.push(light);
    }

    /// One warning per light strictly inside a sphere, naming the first
    /// such sphere, in the order of the lights.
    pub fn warnings(self) -> Vec<CheckError> {
        self.lights
            .iter()
            .filter_map(|light| {
                let location = DVec3::from_array(light.location);
                let sphere = self.spheres.iter().find(|s| s.holds(location))?;
                Some(CheckError::LightInsideSphere {
                    light: light.span.into(),
                    sphere: sphere.span.into(),
                    contains: format!(
                        "contains the light: radius {} around `{}`",
                        format::number(sphere.radius),
                        format::vector(sphere.center)
                    ),
                    help: "it lights only the inside of the sphere: move it out".to_string(),
                })
            })
            .collect()
    }
}
