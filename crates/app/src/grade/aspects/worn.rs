//! How bright a texture is worn: a texture's brightness against the
//! light is the tracer's to choose (its ambient and diffuse constants, a
//! texture times its object's colour), but one choice for the scene,
//! not one for each texture. So the textured objects of one colour are
//! held to one line: each pixel's luminance over that of the texel the
//! student's own mapping puts there ([`super::mapping`]) is `a + g·x`,
//! with `x` the light a white texel would get there (each light's
//! cosine, its colour seen through the texel, under the student's
//! falloff) and `a` the ambient share, the same `a` and `g` on every
//! object that wears a texture over the same colour. An object whose
//! pixels lie on the line scaled (its texture read a fifth as bright, as
//! when a texture's samples are divided by 255 whatever its maxval)
//! shows here, as a plain object with a gain of its own does in
//! [`super::falloff::object_gains`].
//!
//! An object is held to the line only where its fitted mapping explains
//! three quarters of its luminance's variance (it leaves less than half
//! its spread): a mapping outside the family the fit tries reads other
//! texels than the student's, whose ratio to theirs scales the object at
//! random. Only pixels every light of ours reaches, away from
//! highlights and clamped channels; not where the student's shadows fail
//! on the scene, as which points a light reaches is shadows' to judge.

use super::evidence::{clipped, Evidence, HIGHLIGHT_CONE};
use super::falloff::{straying, Falloff, GAIN_FACTOR, SIGNIFICANT};
use super::fit::{predict, robust_fit};
use super::mapping::{self, Mapping};
use super::tone::luminance_of;
use raytracer_render::render::probe::{Probe, Wears};

/// The share of an object's luminance variance its fitted mapping must
/// explain for the object to be held to the line: it then leaves less
/// than half the spread, the bound the tone fit gives a line shaped by
/// what it reads ([`super::tone`]).
const EXPLAINED: f64 = 0.75;

/// One textured object's judged pixels, with what each pixel's light
/// needs: the luminance of the texel the student's mapping reads there,
/// and per light that reaches the point its share of a white texel's
/// light (cosine times the light's colour seen through that texel, over
/// the texel's luminance) and its distance.
struct Worn {
    colour: [u64; 3],
    ks: Vec<usize>,
    texels: Vec<f64>,
    shares: Vec<Vec<(f64, f64)>>,
}

/// The luminance of the texel `mapping` reads at `probe`'s point, and
/// its lights' shares ([`Worn`]); `None` where a light's share cannot be
/// read (our texel there is black to that light) or the texel is darker
/// than one 8-bit step, which tells nothing of its brightness.
fn read(
    e: &Evidence,
    wears: Wears,
    mapping: Mapping,
    probe: &Probe,
) -> Option<(f64, Vec<(f64, f64)>)> {
    let theirs = mapping::texel_at(e.buffers, wears, mapping, probe);
    let ours = mapping::texel_at(e.buffers, wears, mapping::ours(wears.sphere), probe);
    let texel = luminance_of(theirs);
    if texel < 1.0 / 255.0 {
        return None;
    }
    let mut shares = Vec::with_capacity(probe.lights.len());
    for light in probe.lights.iter().filter(|l| l.reaches) {
        let colour = e.buffers.light_colours.get(light.light)?;
        let through = |t: [f64; 3]| luminance_of([0, 1, 2].map(|c| t[c] * colour[c]));
        let ours = through(ours);
        if ours <= 1e-9 {
            return None;
        }
        // `lit` is the luminance of our texel times the light, times the
        // cosine: the cosine, seen through the student's texel.
        shares.push((light.lit / ours * through(theirs) / texel, light.distance));
    }
    Some((texel, shares))
}

/// The textured objects of `objects` (each with its stable pixels, its
/// texture showing) that may be held to the line: not mirrors, their
/// mapping explaining enough of them, with `least` pixels read.
fn worn(e: &Evidence, objects: &[(u32, &[usize])], least: usize) -> Vec<Worn> {
    // Each candidate with its colour; one alone with its colour has no
    // other to be held to, so its mapping is not fitted.
    let candidates: Vec<(&[usize], Wears, [u64; 3])> = objects
        .iter()
        .filter_map(|&(object, ks)| {
            let id = object as usize;
            let wears = e.buffers.wears.get(id).copied().flatten()?;
            let mirror = e.buffers.reflective.get(id).copied().unwrap_or(true);
            let colour = e.buffers.colours.get(id).copied().unwrap_or_default();
            (!mirror).then_some((ks, wears, colour.map(f64::to_bits)))
        })
        .collect();
    let mut found = Vec::new();
    for &(ks, wears, colour) in &candidates {
        if candidates.iter().filter(|c| c.2 == colour).count() < 2 {
            continue;
        }
        let ks: Vec<usize> = ks
            .iter()
            .copied()
            .filter(|&k| {
                let p = &e.buffers.centres[k];
                p.unshadowed - p.lit < 1e-9
                    && p.highlight <= HIGHLIGHT_CONE
                    && !clipped(&e.student_px(k))
            })
            .collect();
        let (mapping, explained) = e.mapping_of(wears, &ks);
        if explained < EXPLAINED {
            continue;
        }
        let (mut kept, mut texels, mut shares) = (Vec::new(), Vec::new(), Vec::new());
        for k in ks {
            if let Some((texel, share)) = read(e, wears, mapping, &e.buffers.centres[k]) {
                kept.push(k);
                texels.push(texel);
                shares.push(share);
            }
        }
        if kept.len() < least {
            continue;
        }
        found.push(Worn {
            colour,
            ks: kept,
            texels,
            shares,
        });
    }
    found
}

/// Each object's scale of the line its group shares, under one curve
/// (`luminance`, the student's in linear light at a pixel) and
/// `falloff`: the median of its points over the line, 1 where that does
/// not differ from 1 by [`SIGNIFICANT`] standard errors (of a median,
/// from the points' spread about it). `None` for a group whose line
/// cannot be fitted (no light varies over it).
fn scales(
    group: &[&Worn],
    least: usize,
    luminance: &dyn Fn(usize) -> f64,
    falloff: Falloff,
) -> Option<Vec<f64>> {
    let points: Vec<Vec<([f64; 1], f64)>> = group
        .iter()
        .map(|w| {
            w.ks.iter()
                .zip(&w.texels)
                .zip(&w.shares)
                .map(|((&k, texel), shares)| {
                    let x = shares.iter().map(|&(s, d)| s * falloff.gain(d)).sum();
                    ([x], luminance(k) / texel)
                })
                .collect()
        })
        .collect();
    let all: Vec<([f64; 1], f64)> = points.iter().flatten().copied().collect();
    let line = robust_fit(&all)?;
    let scales = points
        .iter()
        .map(|rows| {
            let mut ratios: Vec<f64> = rows
                .iter()
                .map(|(x, y)| (y, predict(&line, x)))
                .filter(|&(_, fitted)| fitted > 0.0)
                .map(|(y, fitted)| y / fitted)
                .collect();
            if ratios.len() < least {
                return 1.0;
            }
            let scale = median(&mut ratios);
            let mut spread: Vec<f64> = ratios.iter().map(|r| (r - scale).abs()).collect();
            // A median's standard error: 1.2533 σ/√n, σ from the median
            // absolute deviation.
            let error = 1.2533 * 1.4826 * median(&mut spread) / (ratios.len() as f64).sqrt();
            if (scale - 1.0).abs() > SIGNIFICANT * error {
                scale
            } else {
                1.0
            }
        })
        .collect();
    Some(scales)
}

/// The median of `values` (not empty); their order is lost.
fn median(values: &mut [f64]) -> f64 {
    let middle = values.len() / 2;
    *values.select_nth_unstable_by(middle, f64::total_cmp).1
}

/// The falloffs a textured object's light is read under: the scene's
/// light fit's, where plain objects tell it, else every one tried.
fn falloffs(e: &Evidence, worn: &[Worn]) -> Vec<Falloff> {
    if let Some(light) = &e.light {
        return light.plausible().collect();
    }
    let (weighed, lit) = worn
        .iter()
        .flat_map(|w| w.shares.iter().flatten())
        .fold((0.0, 0.0), |(w, l), &(s, d)| (w + s * d, l + s));
    Falloff::tried(if lit > 0.0 { weighed / lit } else { 1.0 }).collect()
}

/// The textured object whose scale of its group's line strays furthest
/// from 1, as that scale (1 when none strays), and the pixels judged,
/// marking `map` (2 where an object strays past [`GAIN_FACTOR`]). Each
/// object is read under the curve and falloff that bring it nearest,
/// among those the image cannot tell apart; an object with fewer than
/// `least` pixels left is not held to it. `None` when no group of two or
/// more objects is held to a line.
pub(super) fn worst(
    e: &Evidence,
    objects: &[(u32, &[usize])],
    least: usize,
    map: &mut [u8],
) -> Option<(f64, usize)> {
    let worn = worn(e, objects, least);
    let mut groups: Vec<Vec<&Worn>> = Vec::new();
    for w in &worn {
        match groups.iter_mut().find(|g| g[0].colour == w.colour) {
            Some(group) => group.push(w),
            None => groups.push(vec![w]),
        }
    }
    groups.retain(|g| g.len() >= 2);
    if groups.is_empty() {
        return None;
    }
    let falloffs = falloffs(e, &worn);
    let (mut worst, mut judged) = (1.0f64, 0usize);
    for group in &groups {
        let mut nearest: Vec<Option<f64>> = vec![None; group.len()];
        'readings: for curve in e.tone.plausible() {
            let linear = curve.linearise();
            let luminance = |k: usize| e.luminance_under(&linear, k);
            for &falloff in &falloffs {
                let Some(scales) = scales(group, least, &luminance, falloff) else {
                    continue;
                };
                for (best, scale) in nearest.iter_mut().zip(scales) {
                    if best.is_none_or(|b| straying(scale) < straying(b)) {
                        *best = Some(scale);
                    }
                }
                if nearest.iter().all(|s| *s == Some(1.0)) {
                    break 'readings;
                }
            }
        }
        for (w, scale) in group.iter().zip(nearest) {
            let Some(scale) = scale else { continue };
            if straying(scale) > straying(worst) {
                worst = scale;
            }
            judged += w.ks.len();
            for &k in &w.ks {
                map[k] = map[k].max(1 + u8::from(straying(scale) > GAIN_FACTOR.ln()));
            }
        }
    }
    (judged > 0).then_some((worst, judged))
}

/// Whether a scale lies within [`GAIN_FACTOR`] of 1, either way.
pub(super) fn within(scale: f64) -> bool {
    straying(scale) <= GAIN_FACTOR.ln()
}

#[cfg(test)]
mod tests {
    use super::super::evidence::Evidence;
    use super::super::mapping::tests::wearing;
    use super::super::textures::{textured, LEAST_PIXELS};
    use super::{within, worst};
    use crate::compare::Picture;
    use raytracer_render::ir;
    use raytracer_render::render::model::Model;
    use raytracer_render::render::probe::{self, Buffers};

    /// Two spheres of one colour under one light, both wearing a 16 × 8
    /// texture of uneven greys.
    fn scene() -> ir::Scene {
        let text = "camera 64\nsphere\ndimension 1\ncenter -1.05 0 -4.5\ncolor 1 1 1\n\
                    sphere\ndimension 1\ncenter 1.05 0 -4.5\ncolor 1 1 1\n\
                    light\nlocation 0 2 0\ncolor 1 1 1\n";
        wearing(text, 2)
    }

    /// The image a tracer writes that maps both textures as ours does
    /// (no highlight, clamped to 8 bits), the second sphere's texels
    /// read `second` times as bright.
    fn picture(buffers: &Buffers, second: f64) -> Picture {
        let rgb = buffers
            .centres
            .iter()
            .flat_map(|p| {
                let scale = match p.object {
                    Some(0) => 1.0,
                    Some(_) => second,
                    None => 0.0,
                };
                let texel = p.albedo;
                p.light
                    .map(|l| ((l * texel * scale).min(1.0) * 255.0).round() as u8)
            })
            .collect();
        Picture {
            width: buffers.size,
            height: buffers.size,
            rgb,
        }
    }

    /// The scale of the line that strays furthest, for an image whose
    /// second texture is read `second` times as bright.
    fn straying_scale(second: f64) -> f64 {
        let buffers = probe::buffers(&scene(), 4, Model::default());
        let student = picture(&buffers, second);
        let reference = picture(&buffers, 1.0);
        let e = Evidence::new(&buffers, &reference, &student);
        let mut map = vec![0; e.n];
        let objects = textured(&e);
        let objects: Vec<(u32, &[usize])> = objects
            .iter()
            .map(|o| (o.object, o.ks.as_slice()))
            .collect();
        let worst = worst(&e, &objects, LEAST_PIXELS, &mut map);
        worst.expect("two spheres of one colour").0
    }

    #[test]
    fn a_texture_read_a_fifth_as_bright_strays_and_one_read_alike_does_not() {
        let alike = straying_scale(1.0);
        assert!(within(alike) && (alike - 1.0).abs() < 0.02, "{alike}");
        let dimmed = straying_scale(0.2);
        assert!(!within(dimmed), "{dimmed}");
    }
}
