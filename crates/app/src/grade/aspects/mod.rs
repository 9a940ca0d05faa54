//! A student's image judged aspect by aspect against what our reference
//! sees at each pixel ([`raytracer_render::render::probe`]): geometry
//! (which pixels see an object), shadows, reflection, textures and shading.
//!
//! Each measure is chosen to stay the same under the readings the course's
//! assignment leaves open (docs/grading.md, "Readings the assignment
//! allows") and to change under the bugs students make:
//!
//! - the student's pixel reading is fitted first: the image is judged on
//!   the probes through pixel centres or through their top-left corners,
//!   whichever explains it ([`geometry::pixel_reading`]), and only pixels
//!   *stable* for what a measure reads (the same at the pixel's centre
//!   and its four corners) are judged;
//! - brightness is fitted, `s ≈ a + b·lit` (and what a mirror shows, by
//!   its colour and light) by least squares on the student's own pixels,
//!   so any ambient and diffuse constants, and reflection added or
//!   blended, fit; on plain objects with one gain for the scene and the
//!   student's falloff with distance ([`falloff`]);
//! - the student's image is read in linear light, turned back by a tone
//!   curve (a power after a highlight shoulder) fitted once for the three
//!   channels ([`tone`]), so a gamma, sRGB or an exposure changes no
//!   colour and no shadow; a mirror may add what it shows to a power
//!   ([`reflection`]);
//! - textures are judged by their contrast over the object, and their
//!   colour against ours under the student's own texture mapping, fitted
//!   among those the assignment allows ([`mapping`]); the textures worn
//!   over one colour, by one brightness ([`worn`]);
//! - an image upside down, mirrored or transposed is turned back and
//!   judged so, its geometry failing and naming the transform, even on a
//!   scene whose coverage the transform keeps ([`recognise`]);
//! - a pixel of a plain object whose colour no light of the scene gives
//!   under any reading (a channel wrapped or mixed up as it was written)
//!   is shading's, and tells shadows nothing ([`palette`]);
//! - a bug costs its own aspect: the aspects are judged in
//!   [`REGISTRY`]'s order, each given the verdicts before it, and where
//!   the student's shadows fail on the scene, reflection and shading
//!   leave to them what shadow rays decide (what a mirror shows of
//!   points a light could reach, the hue of plain objects under coloured
//!   lights).
//!
//! Each aspect is a file of its own, with its measure, the map of where it
//! differs and its words in the report, over one [`evidence::Evidence`];
//! [`REGISTRY`] runs them in order. Adding an aspect is a new file, its
//! variant of [`Aspect`] and a registry line.
//!
//! Every measure is a fraction of the judged pixels that disagree (or, for
//! textures and shading, a ratio or a distance), with a bound in
//! [`AspectThresholds`]. A mirror must also show what ours shows (its fit's
//! gain on it), and a pixel a highlight may brighten is not held against a
//! mirror or a texture's colour. The class of test tracers in
//! tests/students/tune chose the bounds; tests/students/judge, graded by
//! them, found two misses, which these two mechanisms fixed, chosen on both
//! classes; tests/students/held_out judged them (docs/grading.md).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::compare::Picture;
use evidence::Evidence;
use raytracer_render::render::probe::Buffers;

mod background;
mod evidence;
mod falloff;
mod fit;
mod geometry;
mod lobe;
mod mapping;
mod palette;
mod reflection;
mod shading;
mod shadows;
mod textures;
mod tone;
mod transform;
mod unlit;
mod worn;

/// What a scene's image is judged on.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize, JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Aspect {
    /// The camera and the intersections: which pixels see an object.
    Geometry,
    /// Which lit points are shadowed.
    Shadows,
    /// What mirrors show.
    Reflection,
    /// That a textured object shows its texture.
    Textures,
    /// The colours of lit objects.
    Shading,
}

impl Aspect {
    pub const ALL: [Aspect; 5] = [
        Aspect::Geometry,
        Aspect::Shadows,
        Aspect::Reflection,
        Aspect::Textures,
        Aspect::Shading,
    ];

    /// Its name, as suite.json and summary.json spell it.
    pub fn name(self) -> &'static str {
        match self {
            Aspect::Geometry => "geometry",
            Aspect::Shadows => "shadows",
            Aspect::Reflection => "reflection",
            Aspect::Textures => "textures",
            Aspect::Shading => "shading",
        }
    }
}

/// The bounds of each aspect's measure.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, JsonSchema)]
pub struct AspectThresholds {
    /// The largest fraction of stable pixels whose coverage differs.
    pub geometry: f64,
    /// The largest fraction of shadowed (or of fully lit) pixels that
    /// look the other way.
    pub shadows: f64,
    /// The largest fraction, over the mirror pixels that show something,
    /// of mirror pixels the fit of what ours shows does not explain.
    pub reflection: f64,
    /// The least gain of what ours shows in a mirror, in the fit of the
    /// student's mirror, over the mirror's reflectivity: below it, the
    /// mirror does not show what ours shows, and all of its pixels that
    /// show something count as differing. What ours shows is taken as it
    /// arrives, or tinted by the mirror's colour where the image reads so.
    /// The same least gain holds the mirror's own light, over `1 −
    /// reflectivity` (its weight in a blended reflection).
    pub reflection_gain: f64,
    /// The least ratio of the student's texture contrast to ours.
    pub texture_contrast: f64,
    /// The largest distance between the mean chromaticities of a
    /// textured object, the student's and ours.
    pub texture_colour: f64,
    /// The largest distance between the median chromaticities of a lit
    /// object, the student's and ours.
    pub shading: f64,
}

/// The bounds chosen on tests/students/tune (docs/grading.md says how).
impl Default for AspectThresholds {
    fn default() -> Self {
        AspectThresholds {
            geometry: 0.02,
            shadows: 0.2,
            reflection: 0.25,
            reflection_gain: 0.25,
            texture_contrast: 0.5,
            texture_colour: 0.08,
            shading: 0.1,
        }
    }
}

/// One aspect's verdict on one scene: summary.json's `aspects`.
#[derive(Clone, Debug, Serialize, JsonSchema)]
pub struct AspectResult {
    pub aspect: Aspect,
    /// False when the scene has too few pixels that tell this aspect
    /// (the aspect is then passed).
    pub judged: bool,
    pub pass: bool,
    /// The measure (see [`AspectThresholds`]), `null` when not judged.
    pub measure: Option<f64>,
    /// Its bound.
    pub threshold: f64,
    /// How many pixels were judged.
    pub pixels: usize,
    /// The points the aspect is worth on this scene, and those earned.
    pub points: f64,
    pub score: f64,
    /// The measure in words.
    pub detail: String,
    /// The picture of where it differs, relative to the report folder.
    pub image: Option<String>,
}

/// What [`judge`] found: each aspect, a map per aspect, the readings the
/// image fits where they are not the plainest (the pixel reading, when
/// it tells; a tone curve other than clamping; a falloff with distance),
/// and the whole-image transform that explains a failed geometry, when
/// one does.
pub struct Judged {
    pub results: Vec<AspectResult>,
    /// Per aspect, per pixel: 0 not judged, 1 agrees, 2 differs.
    pub maps: Vec<Vec<u8>>,
    pub reading: Option<String>,
    /// What the image is, in words ("upside down (…)"), when geometry
    /// fails as it is and passes once the image is turned back.
    pub transform: Option<&'static str>,
}

impl AspectResult {
    /// Whether the aspect was judged and passed, its measure at least
    /// halfway from its bound to a perfect measure (0, or for textures'
    /// contrast, which must reach its bound, 1).
    fn clear_pass(&self) -> bool {
        match (self.judged && self.pass, self.measure, self.aspect) {
            (true, Some(m), Aspect::Textures) => m >= (1.0 + self.threshold) / 2.0,
            (true, Some(m), _) => m <= self.threshold / 2.0,
            _ => false,
        }
    }
}

/// The points of each aspect on a scene.
pub type AspectPoints = Vec<(Aspect, f64)>;

/// An aspect's judge: its verdict over the evidence, given the verdicts
/// of the aspects before it in [`REGISTRY`], marking the map of where it
/// differs (0 not judged, 1 agrees, 2 differs). An aspect reads an
/// earlier verdict only to leave to it what it already charges.
type Judge = fn(&Evidence, &AspectThresholds, &[AspectResult], &mut [u8]) -> AspectResult;

/// Every aspect's judge, in [`Aspect::ALL`]'s order.
const REGISTRY: [(Aspect, Judge); 5] = [
    (Aspect::Geometry, geometry::judge),
    (Aspect::Shadows, shadows::judge),
    (Aspect::Reflection, reflection::judge),
    (Aspect::Textures, textures::judge),
    (Aspect::Shading, shading::judge),
];

/// Whether `aspect` was judged and failed among the verdicts `earlier`.
fn failed(earlier: &[AspectResult], aspect: Aspect) -> bool {
    earlier
        .iter()
        .any(|r| r.aspect == aspect && r.judged && !r.pass)
}

/// Every aspect's verdict on `evidence`, and its maps.
fn judge_all(
    evidence: &Evidence,
    thresholds: &AspectThresholds,
) -> (Vec<AspectResult>, Vec<Vec<u8>>) {
    let mut maps = vec![vec![0u8; evidence.n]; Aspect::ALL.len()];
    let mut results = Vec::with_capacity(REGISTRY.len());
    for ((_, judge), map) in REGISTRY.iter().zip(&mut maps) {
        let result = judge(evidence, thresholds, &results, map);
        results.push(result);
    }
    (results, maps)
}

/// The whole-image transform that turns a student's image back into one
/// ours explains, with the verdicts and maps of the image turned back;
/// `None` when none does. When geometry fails as the image is, turned
/// back it must pass, and the scene must tell the transform: our own
/// image so turned must fail geometry, else the scene's coverage is
/// symmetric under it (facing_mirrors.txt's under a transpose), and a bug
/// that fails geometry by a hair there is no transform. When it passes
/// (the transform keeps the scene's coverage, as a symmetric scene's
/// does), every aspect judged as the image is must be judged and pass
/// turned back, each that failed by a clear margin
/// ([`AspectResult::clear_pass`]): a lucky symmetry may bring a buggy
/// image to the bound, not well within it; and the scene must tell the
/// transform by its light, our own image so turned failing an aspect.
/// And no aspect may fail turned back, even one not judged as the image
/// is (shading leaves plain objects to failed shadows): the image turned
/// back must fit ours in every aspect, as the report then says.
fn recognise(
    buffers: &Buffers,
    reference: &Picture,
    student: &Picture,
    thresholds: &AspectThresholds,
    as_is: &[AspectResult],
) -> Option<(transform::Transform, Verdicts)> {
    let geometry_failed = as_is[0].judged && !as_is[0].pass;
    transform::Transform::ALL.into_iter().find_map(|t| {
        let turned = t.undo(student);
        // Geometry judged as the image is must be judged and pass turned
        // back, either way; it reads coverage alone, so it is judged
        // before the readings are fitted.
        let geometry = coverage(buffers, reference, &turned, thresholds);
        if as_is[0].judged && !(geometry.judged && geometry.pass) {
            return None;
        }
        // The scene tells the transform when our own image so turned
        // fails geometry.
        if geometry_failed {
            let ours = coverage(buffers, reference, &t.undo(reference), thresholds);
            if !ours.judged || ours.pass {
                return None;
            }
        }
        let evidence = Evidence::new(buffers, reference, &turned);
        let verdicts = judge_all(&evidence, thresholds);
        let explained = || {
            as_is.iter().zip(&verdicts.0).all(|(before, after)| {
                after.pass
                    && (!before.judged || (after.judged && (before.pass || after.clear_pass())))
            })
        };
        // Where the transform keeps the scene's coverage, the scene
        // tells it only when our own image so turned fails an aspect: a
        // scene that looks the same turned (a plane lit evenly, which
        // ours clamps all over) cannot name it.
        let told = || {
            let turned = t.undo(reference);
            judge_all(&Evidence::new(buffers, reference, &turned), thresholds)
                .0
                .iter()
                .any(|r| r.judged && !r.pass)
        };
        (geometry_failed || (explained() && told())).then_some((t, verdicts))
    })
}

/// Geometry's verdict on `picture`, which reads coverage alone: judged
/// before any reading is fitted.
fn coverage(
    buffers: &Buffers,
    reference: &Picture,
    picture: &Picture,
    thresholds: &AspectThresholds,
) -> AspectResult {
    let evidence = Evidence::unfitted(buffers, reference, picture);
    let mut map = vec![0u8; evidence.n];
    geometry::judge(&evidence, thresholds, &[], &mut map)
}

/// Every aspect's verdict and map.
type Verdicts = (Vec<AspectResult>, Vec<Vec<u8>>);

/// Judge `student` (of the reference's size) aspect by aspect, on the
/// probes of the pixel reading its image fits (centres or corners,
/// [`geometry::pixel_reading`]): `buffers`, probed through pixel centres,
/// or `through_corners`, the same made by [`Buffers::through_corners`]
/// (once for every image judged on the scene). When a whole-image
/// transform turns it back into one ours explains ([`recognise`]),
/// geometry fails naming it, and the other aspects are judged on the
/// image turned back.
pub fn judge(
    buffers: &Buffers,
    through_corners: &Buffers,
    reference: &Picture,
    student: &Picture,
    thresholds: &AspectThresholds,
    points: &AspectPoints,
) -> Judged {
    let centres = Evidence::new(buffers, reference, student);
    let corners = Evidence::new(through_corners, reference, student);
    let reading = geometry::pixel_reading(&centres, &corners);
    let (buffers, evidence) = match reading {
        Some(geometry::Reading::Corners) => (through_corners, corners),
        _ => (buffers, centres),
    };
    let readings: Vec<String> = reading
        .map(|r| r.words().to_string())
        .into_iter()
        .chain(evidence.tone.curve.words())
        .chain(
            (evidence.light.as_ref())
                .and_then(|l| l.falloff.words())
                .map(|falloff| format!("your image reads with {falloff}")),
        )
        .collect();
    let (mut results, mut maps) = judge_all(&evidence, thresholds);
    let geometry_failed = results[0].judged && !results[0].pass;
    let recognised = results
        .iter()
        .any(|r| !r.pass)
        .then(|| recognise(buffers, reference, student, thresholds, &results))
        .flatten();
    let transform = recognised.as_ref().map(|(t, _)| t.words());
    if let Some((t, (turned_results, turned_maps))) = recognised {
        // Geometry as the image is; the others turned back.
        for (k, (result, map)) in turned_results.into_iter().zip(turned_maps).enumerate() {
            if k > 0 {
                results[k] = result;
                maps[k] = map;
            }
        }
        let geometry = &mut results[0];
        geometry.detail = if geometry_failed {
            format!(
                "{}; turned back, your image fits ours: it is likely {}",
                geometry.detail,
                t.words()
            )
        } else {
            geometry.pass = false;
            format!(
                "{}, but only turned back does your image fit ours in every aspect: it is likely {}",
                geometry.detail,
                t.words()
            )
        };
    }
    for result in &mut results {
        result.points = points
            .iter()
            .filter(|(a, _)| *a == result.aspect)
            .map(|(_, p)| p)
            .sum::<f64>()
            + 0.0;
        result.score = if result.pass { result.points } else { 0.0 };
    }
    Judged {
        results,
        maps,
        reading: (!readings.is_empty()).then(|| readings.join("; ")),
        transform,
    }
}

fn ratio(a: usize, b: usize) -> f64 {
    if b == 0 {
        0.0
    } else {
        a as f64 / b as f64
    }
}

/// A verdict whose measure must not exceed `threshold`; `detail` says
/// what was measured, or, when not `judged`, what there was too little
/// of.
fn verdict(
    aspect: Aspect,
    judged: bool,
    measure: f64,
    threshold: f64,
    pixels: usize,
    detail: String,
) -> AspectResult {
    AspectResult {
        aspect,
        judged,
        pass: !judged || measure <= threshold,
        measure: judged.then_some(measure),
        threshold,
        pixels,
        points: 0.0,
        score: 0.0,
        detail,
        image: None,
    }
}

/// `part of whole` with its percentage, or "none of 0" never: `None`
/// when `whole` is 0.
fn fraction_words(part: usize, whole: usize, what: &str) -> Option<String> {
    (whole > 0).then(|| {
        format!(
            "{part} of {whole} {what} ({:.1} %)",
            100.0 * part as f64 / whole as f64
        )
    })
}

/// The picture of where an aspect differs: our image dimmed, the judged
/// pixels that agree tinted blue, those that differ red.
pub fn map_picture(reference: &Picture, map: &[u8]) -> Picture {
    let mut rgb = Vec::with_capacity(reference.rgb.len());
    for (k, state) in map.iter().enumerate() {
        let p = &reference.rgb[3 * k..3 * k + 3];
        let dim = |c: u8| c / 4;
        rgb.extend_from_slice(&match state {
            0 => [dim(p[0]), dim(p[1]), dim(p[2])],
            1 => [dim(p[0]), dim(p[1]), dim(p[2]).saturating_add(70)],
            _ => [255, 40, 40],
        });
    }
    Picture {
        width: reference.width,
        height: reference.height,
        rgb,
    }
}

#[cfg(test)]
mod tests {
    use super::{Aspect, REGISTRY};

    #[test]
    fn the_registry_judges_every_aspect_once_in_order() {
        let registered: Vec<Aspect> = REGISTRY.iter().map(|(aspect, _)| *aspect).collect();
        assert_eq!(registered, Aspect::ALL);
    }
}
