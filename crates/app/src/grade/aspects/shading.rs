//! Shading: the colours of lit objects, which the lights' colours and the
//! objects' (or their textures') colours give, and which no constant the
//! assignment leaves open changes much (brightness is the tracer's to
//! choose, the hue is not). On each lit plain object, its median
//! chromaticity against ours; on each textured object whose texture shows
//! (its contrast passes [`super::textures`], so a texture left out is
//! textures' failure alone), its mean chromaticity against what ours would
//! show under the student's own texture mapping, fitted among those the
//! assignment allows ([`super::mapping`]), as the mapping is theirs to
//! choose and changes which texels a visible half shows. Both away from
//! highlights and clamped channels, and in linear light ([`super::tone`]):
//! through the student's curve, or through any curve their image cannot
//! tell from it ([`super::tone::Fitted::plausible`]) that brings the colour
//! nearer ours, as a saturated colour read through a curve the image does
//! not tell says nothing of the student. On plain objects, only the points
//! the student's image shows lit, as the scene's light fit reads it: which
//! points a light reaches is shadows' to judge. Where the student's
//! shadows fail on the scene ([`super::shadows`], judged before), plain
//! objects are left to them: under lights of different colours a point's
//! hue is which of them its shadow rays let through, and the light fit
//! that tells a shadowed point from a lit one reads a light that the bug
//! has dimmed. A light's colour ignored shows here, on plain and textured
//! objects alike.
//!
//! Brightness is the tracer's to choose for the scene, not for each
//! object: a tracer has one diffuse constant, and our light already holds
//! each object's colour and each point's angle to the light. So each lit
//! plain object's own gain is held against the scene's
//! ([`super::falloff::object_gains`]), under the student's curve and
//! falloff. A normal or a light vector left unnormalised scales each
//! object's light by its radius or its distance, and shows here.
//!
//! And whatever the reading, a plain object shows only colours the
//! scene's lights and its own colour give ([`super::palette`]): a pixel
//! outside them had its channels wrapped or mixed up as it was written.
//! Judged on every stable pixel of a plain object, lit or not, as which
//! lights reach a point does not change which colours it may show; not
//! where geometry fails, as a pixel there may show another object.

use super::evidence::{clipped, Evidence, Whose, HIGHLIGHT_CONE};
use super::falloff::{object_gains, straying, Falloff, Points, GAIN_FACTOR, SIGNIFICANT};
use super::mapping;
use super::textures::{textured, LEAST_PIXELS};
use super::tone::Curve;
use super::{failed, verdict, Aspect, AspectResult, AspectThresholds};

/// The largest share of a scene's stable plain-object pixels that may
/// show a colour no light gives ([`Evidence::foreign`]): under every
/// reading none does, so this is the share geometry allows a tracer's
/// edges ([`AspectThresholds::geometry`]'s default), for the few pixels
/// a curve read off moves that far.
const FOREIGN: f64 = 0.02;

/// The L1 distance between two chromaticities.
fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|c| (a[c] - b[c]).abs()).sum()
}

/// The worst distance of a lit plain object's median chromaticity from
/// ours and the pixels judged, marking `map`; when `shadows_differ`, no
/// object is judged, and the pixels that would have been are left to
/// shadows (the third number).
fn plain(e: &Evidence, bound: f64, shadows_differ: bool, map: &mut [u8]) -> (f64, usize, usize) {
    let (mut worst, mut shaded, mut left) = (0.0f64, 0usize, 0usize);
    for &object in &e.plain {
        let ks: Vec<usize> = e
            .pixels_of(object, &|p| p.visible)
            .into_iter()
            .filter(|&k| {
                let p = &e.buffers.centres[k];
                // Lit in ours and in theirs: which points a light
                // reaches is shadows' to judge.
                let shadowed = e.light.as_ref().and_then(|light| {
                    light.looks_shadowed(object, p, e.luminance(Whose::Theirs, k))
                });
                p.lit > 0.05
                    && shadowed != Some(true)
                    && p.highlight < 0.9
                    && !clipped(&e.student_px(k))
                    && e.chroma(Whose::Theirs, k).is_some()
                    && e.chroma(Whose::Ours, k).is_some()
            })
            .collect();
        if ks.len() < 20 {
            continue;
        }
        if shadows_differ {
            left += ks.len();
            continue;
        }
        let median = |chroma: &dyn Fn(usize) -> Option<[f64; 3]>| {
            [0, 1, 2].map(|c| {
                let mut v: Vec<f64> = ks.iter().filter_map(|&k| chroma(k)).map(|v| v[c]).collect();
                let middle = v.len() / 2;
                *v.select_nth_unstable_by(middle, f64::total_cmp).1
            })
        };
        let ours = median(&|k| e.chroma(Whose::Ours, k));
        let d = nearest(e, &|curve| {
            let linear = curve.linearise();
            distance(ours, median(&|k| e.chroma_under(&linear, k)))
        });
        worst = worst.max(d);
        shaded += ks.len();
        for &k in &ks {
            map[k] = 1 + u8::from(d > bound);
        }
    }
    (worst, shaded, left)
}

/// The share of the stable pixels of plain objects (with no channel
/// clamped) whose colour no light of the scene gives
/// ([`Evidence::foreign`]), the pixels judged, and how many are
/// outside, marking `map`.
fn foreign(e: &Evidence, map: &mut [u8]) -> (f64, usize, usize) {
    let (mut outside, mut judged) = (0usize, 0usize);
    for (k, foreign) in e.foreign.iter().enumerate() {
        let Some(foreign) = *foreign else {
            continue;
        };
        judged += 1;
        outside += usize::from(foreign);
        map[k] = map[k].max(1 + u8::from(foreign));
    }
    (outside as f64 / judged.max(1) as f64, judged, outside)
}

/// The lit plain object whose gain strays furthest from the scene's one
/// gain ([`object_gains`]), as its gain over the scene's (1 when none
/// strays), and the pixels judged, marking `map`. Each object is read
/// under the student's curve and falloff that bring its gain nearest
/// the scene's, among those their image cannot tell apart
/// ([`super::tone::Fitted::plausible`],
/// [`super::falloff::LightFit::plausible`]): a
/// curve bends a line over a dark object differently than over a bright
/// one, and a falloff read a little off dims a near object and a far one
/// differently. On the pixels that tell the light fit and that the
/// student shows lit, within the cone out of which no highlight lobe
/// lies ([`HIGHLIGHT_CONE`]), as a highlight steepens an object's line.
/// Not judged where the student's shadows fail ([`plain`]).
fn gains(e: &Evidence, shadows_differ: bool, map: &mut [u8]) -> (f64, usize) {
    let Some(light) = e.light.as_ref().filter(|_| !shadows_differ) else {
        return (1.0, 0);
    };
    // Only the points the student's image shows lit, on the objects it
    // shows lit: which points a light reaches is shadows' to judge.
    let objects: Vec<(u32, Vec<usize>)> = e
        .fully_lit(HIGHLIGHT_CONE)
        .into_iter()
        .filter(|(object, ks)| !mostly_unlit(e, *object, ks))
        .map(|(object, ks)| {
            let lit = ks
                .into_iter()
                .filter(|&k| {
                    let p = &e.buffers.centres[k];
                    light.looks_shadowed(object, p, e.luminance(Whose::Theirs, k)) != Some(true)
                })
                .collect();
            (object, lit)
        })
        .filter(|(_, ks): &(u32, Vec<usize>)| ks.len() >= 20)
        .collect();
    // Each object's gain over the scene's under each plausible curve
    // and falloff, 1 where it does not differ by more than its error
    // allows. A curve's luminances serve every falloff, and a falloff's
    // lights every curve. Once every object has a reading that keeps it
    // at 1, no other can stray less: a falloff's lights are worked out
    // when the search first reaches it.
    let falloffs: Vec<Falloff> = light.plausible().collect();
    let mut lights: Vec<Option<Vec<Vec<f64>>>> = vec![None; falloffs.len()];
    let mut ratios: Vec<Vec<(u32, f64)>> = Vec::new();
    let mut kept_at_one = vec![false; objects.len()];
    'readings: for curve in e.tone.plausible() {
        let linear = curve.linearise();
        let luminances: Vec<Vec<f64>> = objects
            .iter()
            .map(|(_, ks)| ks.iter().map(|&k| e.luminance_under(&linear, k)).collect())
            .collect();
        for (falloff, lights) in falloffs.iter().zip(&mut lights) {
            let lights = lights.get_or_insert_with(|| {
                let lit = |ks: &Vec<usize>| {
                    ks.iter()
                        .map(|&k| falloff.lit(&e.buffers.centres[k]))
                        .collect()
                };
                objects.iter().map(|(_, ks)| lit(ks)).collect()
            });
            let points: Vec<Points> = objects
                .iter()
                .zip(lights.iter().zip(&luminances))
                .map(|((object, _), (xs, ys))| {
                    (
                        *object,
                        xs.iter().copied().zip(ys.iter().copied()).collect(),
                    )
                })
                .collect();
            let gains: Vec<(u32, f64)> = object_gains(&points, *falloff)
                .into_iter()
                .map(|g| {
                    let differs = (g.ratio - 1.0).abs() > SIGNIFICANT * g.error;
                    (g.object, if differs { g.ratio } else { 1.0 })
                })
                .collect();
            for ((object, _), kept) in objects.iter().zip(&mut kept_at_one) {
                *kept |= gains.contains(&(*object, 1.0));
            }
            ratios.push(gains);
            if kept_at_one.iter().all(|&k| k) {
                break 'readings;
            }
        }
    }
    let (mut worst, mut judged) = (1.0f64, 0usize);
    for (object, ks) in &objects {
        let Some(ratio) = ratios
            .iter()
            .filter_map(|reading| reading.iter().find(|(o, _)| o == object).map(|g| g.1))
            .min_by(|a, b| straying(*a).total_cmp(&straying(*b)))
        else {
            continue;
        };
        if straying(ratio) > straying(worst) {
            worst = ratio;
        }
        judged += ks.len();
        for &k in ks {
            map[k] = map[k].max(1 + u8::from(straying(ratio) > GAIN_FACTOR.ln()));
        }
    }
    (worst, judged)
}

/// Whether the student's image shows `object` unlit on half or more of
/// the points `ks` where ours shows light: at its unlit level (the
/// median of its points no light of ours reaches), within 4 of 255,
/// where ours is 8 of 255 above its own. Such an object's line is its
/// shadows', and no robust fit reads a gain from a line whose points
/// are half outliers.
fn mostly_unlit(e: &Evidence, object: u32, ks: &[usize]) -> bool {
    let seen: Vec<usize> = e
        .pixels_of(object, &|p| p.visible)
        .into_iter()
        .filter(|&k| !clipped(&e.student_px(k)))
        .collect();
    let (Some(ours), Some(theirs)) = (
        e.unlit_level(Whose::Ours, &seen),
        e.unlit_level(Whose::Theirs, &seen),
    ) else {
        return false;
    };
    let shown: Vec<usize> = ks
        .iter()
        .copied()
        .filter(|&k| e.luminance(Whose::Ours, k) - ours > 8.0 / 255.0)
        .collect();
    let dark = shown
        .iter()
        .filter(|&&k| e.luminance(Whose::Theirs, k) - theirs < 4.0 / 255.0)
        .count();
    !shown.is_empty() && 2 * dark >= shown.len()
}

/// The mean of `colours`, each channel.
fn mean(colours: impl Iterator<Item = [f64; 3]>) -> [f64; 3] {
    let (mut sum, mut count) = ([0.0; 3], 0.0);
    for c in colours {
        (0..3).for_each(|k| sum[k] += c[k]);
        count += 1.0;
    }
    sum.map(|v| v / f64::max(count, 1.0))
}

/// The least of `distance` under the curves the student's image cannot
/// tell apart ([`super::tone::Fitted::plausible`]): a colour is read through their
/// curve, and where the image leaves the curve open, the hue is judged
/// under the reading that explains it best.
fn nearest(e: &Evidence, distance: &dyn Fn(Curve) -> f64) -> f64 {
    e.tone
        .plausible()
        .map(distance)
        .fold(f64::INFINITY, f64::min)
}

/// The chromaticity of a colour in linear light, when bright enough to
/// have one (as [`Evidence::chroma`] asks of an 8-bit pixel).
fn chroma_of(c: [f64; 3]) -> Option<[f64; 3]> {
    let sum = c[0] + c[1] + c[2];
    (sum > 15.0 / 255.0).then(|| c.map(|v| v / sum))
}

/// The worst distance of a textured object's mean chromaticity from what
/// ours would show under the student's own mapping ([`Evidence::mapping_of`]),
/// over the objects whose texture shows, and the pixels judged, marking
/// `map`.
fn textured_colour(e: &Evidence, thresholds: &AspectThresholds, map: &mut [u8]) -> (f64, usize) {
    let (mut worst, mut shaded) = (0.0f64, 0usize);
    for object in textured(e) {
        let Some(wears) = e
            .buffers
            .wears
            .get(object.object as usize)
            .copied()
            .flatten()
        else {
            continue;
        };
        if object.theirs / object.ours < thresholds.texture_contrast {
            continue;
        }
        // Away from highlights (a highlight the tracer chose to draw
        // whitens it) and clamped channels.
        let ks: Vec<usize> = object
            .ks
            .iter()
            .copied()
            .filter(|&k| {
                e.buffers.centres[k].highlight <= HIGHLIGHT_CONE && !clipped(&e.student_px(k))
            })
            .collect();
        let (fitted, _) = e.mapping_of(wears, &ks);
        let pairs: Vec<(usize, [f64; 3])> = ks
            .iter()
            .filter_map(|&k| {
                let predicted = mapping::colour(e.buffers, wears, fitted, &e.buffers.centres[k]);
                if predicted.iter().any(|&c| c >= 250.0 / 255.0) {
                    return None;
                }
                e.chroma(Whose::Theirs, k)?;
                Some((k, chroma_of(predicted)?))
            })
            .collect();
        if pairs.len() < LEAST_PIXELS {
            continue;
        }
        let ours = mean(pairs.iter().map(|p| p.1));
        let d = nearest(e, &|curve| {
            let linear = curve.linearise();
            let theirs = mean(pairs.iter().filter_map(|p| e.chroma_under(&linear, p.0)));
            distance(ours, theirs)
        });
        worst = worst.max(d);
        shaded += pairs.len();
        for &(k, _) in &pairs {
            map[k] = 1 + u8::from(d > thresholds.texture_colour);
        }
    }
    (worst, shaded)
}

/// Judge shading, marking `map`. The measure is the worst distance over
/// its bound (plain objects' [`AspectThresholds::shading`], textured
/// ones' [`AspectThresholds::texture_colour`]), so 1 is at the bound.
pub(super) fn judge(
    e: &Evidence,
    thresholds: &AspectThresholds,
    earlier: &[AspectResult],
    map: &mut [u8],
) -> AspectResult {
    let shadows_differ = failed(earlier, Aspect::Shadows);
    let (plain_worst, plain_pixels, left) = plain(e, thresholds.shading, shadows_differ, map);
    let (textured_worst, textured_pixels) = textured_colour(e, thresholds, map);
    let (gains_worst, gains_pixels) = gains(e, shadows_differ, map);
    // Where geometry fails, a pixel may show another object's colour.
    let (foreign_share, foreign_pixels, outside) = if failed(earlier, Aspect::Geometry) {
        (0.0, 0, 0)
    } else {
        foreign(e, map)
    };
    let foreign_judged = foreign_pixels >= 20;
    let measure = (plain_worst / thresholds.shading)
        .max(textured_worst / thresholds.texture_colour)
        .max(straying(gains_worst) / GAIN_FACTOR.ln())
        .max(if foreign_judged {
            foreign_share / FOREIGN
        } else {
            0.0
        });
    let mut parts = Vec::new();
    if foreign_judged && outside > 0 {
        parts.push(format!(
            "{outside} of {foreign_pixels} pixels of plain objects show a colour no light of the scene gives ({:.1} %, at most {:.0} %): a channel wrapped or mixed up as it was written",
            100.0 * foreign_share,
            100.0 * FOREIGN
        ));
    }
    if plain_pixels > 0 {
        parts.push(format!(
            "the colour of lit plain objects is {plain_worst:.3} from ours (chromaticity, at most {:.2})",
            thresholds.shading
        ));
    }
    if textured_pixels > 0 {
        parts.push(format!(
            "the mean colour of textured objects is {textured_worst:.3} from ours (at most {:.2})",
            thresholds.texture_colour
        ));
    }
    if gains_pixels > 0 {
        parts.push(format!(
            "a lit plain object takes {gains_worst:.2} times the scene's light (alike on every object, at most {GAIN_FACTOR} times either way)"
        ));
    }
    let judged = !parts.is_empty();
    let left_out = (left > 0).then(|| {
        format!("the colours of {left} lit pixels of plain objects are left to shadows, as yours differ from ours here")
    });
    let detail = match (judged, left_out) {
        (true, left_out) => parts.into_iter().chain(left_out).collect::<Vec<_>>().join("; "),
        (false, Some(left_out)) => {
            format!("{left_out}; no textured object whose texture shows with 30 stable pixels")
        }
        (false, None) => "no lit plain object with 20 stable pixels away from highlights, and no textured object whose texture shows with 30".to_string(),
    };
    verdict(
        Aspect::Shading,
        judged,
        measure,
        1.0,
        plain_pixels + textured_pixels + if foreign_judged { foreign_pixels } else { 0 },
        detail,
    )
}
