//! POV-Ray 3.7 export (`convert --to pov`): a scene that renders the same
//! picture as the render model of docs/rendering.md, within what POV-Ray can express.
//!
//! - POV-Ray is left-handed with the camera looking down +z, so every point
//!   and direction has its z negated; x and y are unchanged.
//! - The camera sits at the origin with `direction <0,0,1>`, `up <0,1,0>`
//!   and `right <1,0,0>`: POV-Ray's image plane is then z = 1 with x and y
//!   in [−0.5, 0.5], which is the model's z = −1 after the flip.
//! - A plane becomes a `polygon` through its four corners (the model's `right`
//!   and `up` from [`geometry::plane_basis`], as the renderer uses).
//! - Shading is `finish { ambient 0.1 diffuse 1 reflection K }` with
//!   `ambient_light 1`, no specular and no light fading: POV-Ray then
//!   computes the model's 0.1·C + Σ C⊙I·(N·L̂) + K·reflection. `assumed_gamma 1`
//!   keeps the arithmetic linear; the output file must be written with
//!   `File_Gamma=1` (the header comment gives the command line).
//! - `max_trace_level 9` allows the 8 reflections of `--max-depth 8` after
//!   the primary ray, and `adc_bailout 0` traces every one of them.
//! - Textures are `image_map`s placed so that their texel lookup matches
//!   the model's (see [`plane_texture`] and [`sphere_texture`]); docs/formats.md
//!   lists the remaining differences.

use std::fmt::Write;

use glam::DVec3;

use crate::check::Checked;
use crate::geometry;
use crate::model::{Material, Shape};
use crate::texture::TextureFormat;

use crate::format::number;

/// `checked` as a POV-Ray 3.7 scene, ending in a newline.
pub fn to_pov(checked: &Checked) -> String {
    let scene = &checked.scene;
    let n = scene.camera.resolution;
    let mut out = String::new();
    // Writing to a String cannot fail, here and below.
    let _ = write!(
        out,
        "// POV-Ray 3.7 scene written by `raytracer convert --to pov`.\n\
         // Render it from the folder it was written to (texture paths are relative to it):\n\
         //   povray +I<this file> +O<out>.png +W{n} +H{n} -A File_Gamma=1\n\
         \n\
         #version 3.7;\n\
         \n\
         global_settings {{\n  assumed_gamma 1\n  ambient_light 1\n  max_trace_level 9\n  \
         adc_bailout 0\n  charset utf8\n}}\n\
         \n\
         background {{ rgb 0 }}\n\
         \n\
         camera {{\n  perspective\n  location <0, 0, 0>\n  direction <0, 0, 1>\n  \
         up <0, 1, 0>\n  right <1, 0, 0>\n}}\n"
    );
    for object in &scene.objects {
        out.push('\n');
        match &object.shape {
            Shape::Sphere { center, radius } => {
                let c = pov_point(*center);
                let _ = writeln!(out, "sphere {{\n  {}, {}", vector(c), number(*radius));
                let pigment = object
                    .material
                    .texture
                    .as_deref()
                    .map(|path| sphere_texture(&image_map(checked, path, 1), c));
                material(&mut out, &object.material, pigment);
            }
            Shape::Plane {
                center,
                width,
                height,
                normal,
                headup,
            } => {
                let Some(basis) = geometry::plane_basis(*normal, *headup) else {
                    // A checked plane always has a basis.
                    continue;
                };
                let corners = geometry::corners(*center, &basis, *width, *height)
                    .map(|c| vector(pov_point(c.to_array())));
                // Closed explicitly: five points, the first repeated.
                let _ = writeln!(
                    out,
                    "polygon {{\n  5, {}, {}",
                    corners.join(", "),
                    corners[0]
                );
                let pigment = object.material.texture.as_deref().map(|path| {
                    plane_texture(
                        &image_map(checked, path, 0),
                        *center,
                        &basis,
                        *width,
                        *height,
                    )
                });
                material(&mut out, &object.material, pigment);
            }
        }
    }
    for light in &scene.lights {
        let _ = writeln!(
            out,
            "\nlight_source {{\n  {}\n  color rgb {}\n}}",
            vector(pov_point(light.location)),
            vector(light.color)
        );
    }
    out
}

/// A point or direction in POV-Ray's left-handed frame: z negated.
fn pov_point([x, y, z]: [f64; 3]) -> [f64; 3] {
    [x, y, -z]
}

/// `<x, y, z>` with exact numbers.
fn vector(v: [f64; 3]) -> String {
    format!("<{}, {}, {}>", number(v[0]), number(v[1]), number(v[2]))
}

/// The pigment and finish of an object, and its closing brace.
fn material(out: &mut String, material: &Material, pigment: Option<String>) {
    let pigment =
        pigment.unwrap_or_else(|| format!("pigment {{ color rgb {} }}", vector(material.color)));
    let _ = writeln!(
        out,
        "  texture {{\n    {pigment}\n    finish {{ ambient 0.1 diffuse 1 specular 0 phong 0 reflection {} }}\n  }}\n}}",
        number(material.reflectivity)
    );
}

/// `image_map { TYPE "path" map_type MAP }` (nearest texel: no
/// `interpolate`) for the texture
/// written as `path`: the type is what the `image` crate decoded the file
/// as (so a PPM named `.txt` still loads), else its extension's.
fn image_map(checked: &Checked, path: &str, map_type: u8) -> String {
    let format = checked.textures.get(path).map(|t| t.format);
    let kind = match format {
        Some(TextureFormat::Png) => "png",
        Some(TextureFormat::Jpeg) => "jpeg",
        Some(TextureFormat::Ppm) => "ppm",
        None => match image::ImageFormat::from_path(path) {
            Ok(image::ImageFormat::Png) => "png",
            Ok(image::ImageFormat::Jpeg) => "jpeg",
            _ => "ppm",
        },
    };
    let quoted = path.replace('\\', "\\\\").replace('"', "\\\"");
    format!("image_map {{ {kind} \"{quoted}\" map_type {map_type} }}")
}

/// A plane's texture: POV-Ray's planar map shows the image on the unit
/// square of the pattern's x-y plane, image row 0 at y = 1, which is the model's
/// lookup with u = x, v = y. The matrix takes pattern (u, v, w) to the world
/// point `c + (u − ½)·W·right + (v − ½)·H·up + w·n` (in POV-Ray's frame).
fn plane_texture(
    map: &str,
    center: [f64; 3],
    basis: &geometry::Basis,
    width: f64,
    height: f64,
) -> String {
    let flip = |v: DVec3| DVec3::from_array(pov_point(v.to_array()));
    let (right, up, normal) = (flip(basis.right), flip(basis.up), flip(basis.normal));
    let c = DVec3::from_array(pov_point(center));
    let origin = c - right * (width / 2.0) - up * (height / 2.0);
    let rows = [right * width, up * height, normal, origin].map(|r| {
        let [x, y, z] = r.to_array();
        format!("{}, {}, {}", number(x), number(y), number(z))
    });
    format!(
        "pigment {{\n      {map}\n      matrix <{}>\n    }}",
        rows.join(", ")
    )
}

/// A sphere's texture: POV-Ray's spherical map takes u as the angle from +x
/// towards +z over 2π and v = ½ + asin(y)/π around the pattern origin. With
/// the pattern's x negated (and z already negated by the frame flip), its
/// angle is the model's atan2(m.z, m.x) + π, so u is its ½ + atan2/2π and v is
/// unchanged.
fn sphere_texture(map: &str, center: [f64; 3]) -> String {
    format!(
        "pigment {{\n      {map}\n      matrix <-1, 0, 0, 0, 1, 0, 0, 0, 1, {}>\n    }}",
        vector(center).trim_start_matches('<').trim_end_matches('>')
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model;

    fn checked(objects: Vec<model::Object>) -> Checked {
        Checked {
            scene: model::Scene {
                format: model::FORMAT.to_string(),
                camera: model::Camera { resolution: 8 },
                objects,
                lights: vec![model::Light {
                    location: [1.0, 2.0, -3.0],
                    color: [1.0, 0.5, 0.25],
                }],
            },
            textures: Default::default(),
        }
    }

    #[test]
    fn negates_z_and_writes_exact_numbers() {
        let pov = to_pov(&checked(vec![model::Object {
            shape: model::Shape::Sphere {
                center: [0.1, 0.0, -5.0],
                radius: 1e-7,
            },
            material: model::Material {
                color: [0.3, 0.3, 0.3],
                reflectivity: 0.7,
                texture: None,
            },
        }]));
        assert!(pov.contains("sphere {\n  <0.1, 0, 5>, 1e-7\n"), "{pov}");
        assert!(
            pov.contains("pigment { color rgb <0.3, 0.3, 0.3> }"),
            "{pov}"
        );
        assert!(pov.contains("reflection 0.7 }"), "{pov}");
        assert!(pov.contains("light_source {\n  <1, 2, 3>\n  color rgb <1, 0.5, 0.25>\n}"));
        assert!(pov.contains("+W8 +H8"));
    }

    #[test]
    fn planes_are_polygons_through_their_corners() {
        let pov = to_pov(&checked(vec![model::Object {
            shape: model::Shape::Plane {
                center: [0.0, -1.0, -5.0],
                width: 4.0,
                height: 2.0,
                normal: [0.0, 1.0, 0.0],
                headup: [0.0, 0.0, -1.0],
            },
            material: model::Material::default(),
        }]));
        // up = −z (ours) → +z (POV); right = up × n = (1, 0, 0).
        assert!(
            pov.contains(
                "polygon {\n  5, <-2, -1, 4>, <2, -1, 4>, <2, -1, 6>, <-2, -1, 6>, <-2, -1, 4>\n"
            ),
            "{pov}"
        );
    }
}
