//! The colours a plain object can show under any reading the assignment
//! leaves open. Whatever its constants, highlight model, falloff or
//! shadows, a tracer lights a point with a sum of non-negative terms:
//! ambient light (the object's colour, or white), each light's diffuse
//! term (the object's colour times the light's) and each light's
//! highlight (the light's colour, or that times the object's, which is a
//! diffuse term). So in linear light, under the student's own tone curve
//! (one for the three channels), every pixel of the object lies in the
//! cone those colours span, and a supersampled pixel, a mean of such
//! colours, does too. A pixel far outside it shows a colour no light of
//! the scene gives: its channels were mixed up or wrapped when written,
//! which is shading's fault and says nothing of which lights reach the
//! point. [`super::evidence::Evidence`] marks such pixels, and no
//! fit reads them.

use glam::{DMat2, DMat3, DVec2, DVec3};
use raytracer_render::render::probe::Buffers;

use super::tone::Curve;

/// How far a channel, as written, must lie from every colour of the cone
/// for the pixel to show a colour no light gives: a quarter of the
/// range. A tone curve read a little off bends a colour by a few steps
/// of 255, and a channel written past its top and wrapped jumps by 256.
const OUTSIDE: f64 = 64.0 / 255.0;

/// The colours whose non-negative sums `object` may show in linear light:
/// white and its own colour (ambient light), and for each light its
/// colour and its colour times the object's. A textured object's colour
/// is each of its texture's most saturated texels, toward and away from
/// each channel ([`texel_extremes`]); a mirror's, its own, as what it
/// shows is another object's.
pub(super) fn generators(buffers: &Buffers, object: u32) -> Vec<DVec3> {
    let colours = match buffers.wears[object as usize] {
        Some(wears) => texel_extremes(&buffers.textures[wears.texture].texels),
        None => vec![buffers.colours[object as usize]],
    };
    let colours: Vec<DVec3> = colours.into_iter().map(DVec3::from_array).collect();
    let mut generators = vec![DVec3::ONE];
    generators.extend(colours.iter().copied());
    for light in buffers.light_colours.iter().map(|&l| DVec3::from_array(l)) {
        generators.push(light);
        generators.extend(colours.iter().map(|&colour| colour * light));
    }
    generators.retain(|g| g.max_element() > 0.0);
    generators
}

/// The texels whose chromaticity is furthest toward and away from each
/// channel: the corners of the texture's colours that its cone needs
/// (a cone spanned by fewer colours than all of them, so a little
/// narrower).
fn texel_extremes(texels: &[[f32; 3]]) -> Vec<[f64; 3]> {
    let chromaticity = |t: &[f32; 3], c: usize| {
        let sum = t[0] + t[1] + t[2];
        if sum > 0.0 {
            f64::from(t[c] / sum)
        } else {
            1.0 / 3.0
        }
    };
    let mut extremes: Vec<&[f32; 3]> = Vec::new();
    for c in 0..3 {
        let by = |a: &&[f32; 3], b: &&[f32; 3]| chromaticity(a, c).total_cmp(&chromaticity(b, c));
        extremes.extend(texels.iter().max_by(by));
        extremes.extend(texels.iter().min_by(by));
    }
    let mut colours: Vec<[f64; 3]> = extremes.iter().map(|t| t.map(f64::from)).collect();
    colours.dedup();
    colours
}

/// Whether a pixel `written` (no channel clamped, which would say only
/// that the light there reached the top) shows a colour none of the
/// cones of `palettes` ([`generators`] of the objects it could show)
/// give under any tone curve in `curves` (those the student's image
/// cannot tell apart, [`super::tone::Fitted::plausible`]): under each,
/// some channel, as written, lies further than [`OUTSIDE`] from every
/// colour of each cone.
pub(super) fn outside(palettes: &[&[DVec3]], written: [u8; 3], curves: &[Curve]) -> bool {
    let written = written.map(|v| f64::from(v) / 255.0);
    !curves.iter().any(|curve| {
        let light = DVec3::from_array(curve.linear_pixel(written));
        let near = |point: DVec3| {
            let back = curve.value_pixel(point.to_array());
            (0..3).all(|c| (back[c] - written[c]).abs() <= OUTSIDE)
        };
        palettes
            .iter()
            .any(|generators| reaches(generators, light, &near))
    })
}

/// Whether the projection of `x` on some face of the cone `generators`
/// span (their non-negative sums) is `near` it. The point of the cone
/// nearest `x` lies on a face spanned by at most three generators
/// (Carathéodory's theorem, in three dimensions), where it is the
/// least-squares fit of `x` by them with every weight non-negative; so
/// when the nearest point is near, some face's projection is, and the
/// search stops at the first that is.
fn reaches(generators: &[DVec3], x: DVec3, near: &dyn Fn(DVec3) -> bool) -> bool {
    let n = generators.len();
    let face = |set: &[usize]| {
        let columns: Vec<DVec3> = set.iter().map(|&i| generators[i]).collect();
        project(&columns, x).is_some_and(near)
    };
    near(DVec3::ZERO)
        || (0..n).any(|i| {
            face(&[i]) || (i + 1..n).any(|j| face(&[i, j]) || (j + 1..n).any(|l| face(&[i, j, l])))
        })
}

/// The least-squares fit of `x` by the columns, when they are
/// independent and every weight is non-negative: the normal equations of
/// one or two columns, the square system of three.
fn project(columns: &[DVec3], x: DVec3) -> Option<DVec3> {
    const SINGULAR: f64 = 1e-12;
    let weights = match *columns {
        [a] => {
            let norm = a.length_squared();
            (norm > SINGULAR).then(|| vec![a.dot(x) / norm])?
        }
        [a, b] => {
            let normal = DMat2::from_cols_array(&[a.dot(a), a.dot(b), a.dot(b), b.dot(b)]);
            (normal.determinant().abs() > SINGULAR).then(|| {
                let w = normal.inverse() * DVec2::new(a.dot(x), b.dot(x));
                vec![w.x, w.y]
            })?
        }
        [a, b, c] => {
            let square = DMat3::from_cols(a, b, c);
            (square.determinant().abs() > SINGULAR)
                .then(|| (square.inverse() * x).to_array().to_vec())?
        }
        _ => return None,
    };
    if weights.iter().any(|&w| w < 0.0) {
        return None;
    }
    Some(columns.iter().zip(&weights).map(|(c, &w)| *c * w).sum())
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::{outside, Curve};

    const PINK: DVec3 = DVec3::new(1.0, 0.5, 1.0);

    /// 8-bit values of a colour in linear light, clamping.
    fn written(c: [f64; 3]) -> [u8; 3] {
        c.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
    }

    #[test]
    fn a_sum_of_generators_lies_inside() {
        let generators = [DVec3::ONE, PINK, DVec3::new(0.3, 0.3, 1.0)];
        let x = [0.2 + 0.5 + 0.09, 0.2 + 0.25 + 0.09, 0.2 + 0.5 + 0.3];
        assert!(!outside(&[&generators], written(x), &[Curve::CLAMPING]));
    }

    #[test]
    fn a_wrapped_channel_lies_outside() {
        // A pink light on a pink plane, its red channel past 1 and
        // wrapped to 0.02.
        let generators = [
            DVec3::ONE,
            PINK,
            DVec3::new(1.0, 0.7, 0.7),
            DVec3::new(1.0, 0.35, 0.7),
        ];
        let x = [0.02, 0.5, 0.86];
        assert!(outside(&[&generators], written(x), &[Curve::CLAMPING]));
    }

    #[test]
    fn another_objects_colour_lies_inside_the_union() {
        let generators = [DVec3::ONE, PINK];
        let blue = [DVec3::ONE, DVec3::new(0.1, 0.2, 0.9)];
        let x = [0.0, 0.1, 0.6];
        assert!(outside(&[&generators], written(x), &[Curve::CLAMPING]));
        assert!(!outside(
            &[&generators, &blue],
            written(x),
            &[Curve::CLAMPING]
        ));
    }
}
