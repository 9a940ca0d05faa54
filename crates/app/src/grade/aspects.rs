//! A student's image judged aspect by aspect against what our reference
//! sees at each pixel ([`raytracer_render::render::probe`]): geometry
//! (which pixels see an object), shadows, reflection, textures and shading.
//!
//! Each measure is chosen to stay the same under the readings the course's
//! assignment leaves open (docs/grading.md, "Readings the assignment
//! allows") and to change under the bugs students make:
//!
//! - only pixels *stable* for what a measure reads (the same at the
//!   pixel's centre and its four corners) are judged, so rays through
//!   pixel centres or corners are both fine;
//! - brightness is fitted per object, `s ≈ a + b·lit` (and `+ c·reflected`
//!   on a mirror) by least squares on the student's own pixels, so any
//!   ambient and diffuse constants, and reflection added or blended, fit;
//! - textures are judged by their contrast and mean colour over the
//!   object, which no mapping changes.
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
use raytracer_render::render::probe::{Buffers, Probe};

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
    /// show something count as differing.
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

/// What [`judge`] found: each aspect, a map per aspect, and the pixel
/// reading the image fits, when it tells.
pub struct Judged {
    pub results: Vec<AspectResult>,
    /// Per aspect, per pixel: 0 not judged, 1 agrees, 2 differs.
    pub maps: Vec<Vec<u8>>,
    pub reading: Option<String>,
}

/// Luminance of an 8-bit pixel, in [0, 1].
fn luminance(p: &[u8]) -> f64 {
    (0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2])) / 255.0
}

/// Chromaticity of a pixel: each channel over their sum.
fn chroma(p: &[u8]) -> Option<[f64; 3]> {
    let sum = f64::from(p[0]) + f64::from(p[1]) + f64::from(p[2]);
    (sum > 15.0).then(|| [0, 1, 2].map(|c| f64::from(p[c]) / sum))
}

/// The cosine between the mirror direction and a light's direction above
/// which a pixel may hold a specular highlight the tracer chose to draw: a
/// Phong highlight `k_s·(R·V)^n` is below 0.04 out of this cone (60°) for
/// any `k_s ≤ 1` and `n ≥ 5`. A highlight only ever brightens.
const HIGHLIGHT_CONE: f64 = 0.5;

/// A channel at the top of its range: the tracer may have clamped it.
fn clipped(p: &[u8]) -> bool {
    p.iter().any(|&c| c >= 250)
}

/// Least squares of `y` on the columns of `x` (with an intercept), then
/// again without the points whose residual is over three times the median
/// one, twice: robust to a highlight or an edge.
fn robust_fit<const K: usize>(rows: &[([f64; K], f64)]) -> Option<Vec<f64>> {
    let mut keep: Vec<bool> = vec![true; rows.len()];
    let mut fit = None;
    for _ in 0..3 {
        let chosen: Vec<&([f64; K], f64)> = rows
            .iter()
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(r, _)| r)
            .collect();
        let Some(beta) = least_squares(&chosen) else {
            break;
        };
        let residuals: Vec<f64> = rows
            .iter()
            .map(|r| (r.1 - predict(&beta, &r.0)).abs())
            .collect();
        let mut sorted = residuals.clone();
        sorted.sort_by(f64::total_cmp);
        let median = sorted[sorted.len() / 2];
        let bound = (3.0 * median).max(3.0 / 255.0);
        keep = residuals.iter().map(|&r| r <= bound).collect();
        fit = Some(beta);
    }
    fit
}

fn predict(beta: &[f64], x: &[f64]) -> f64 {
    beta[0] + x.iter().zip(&beta[1..]).map(|(x, b)| x * b).sum::<f64>()
}

/// Ordinary least squares with an intercept; `None` when singular.
fn least_squares<const K: usize>(rows: &[&([f64; K], f64)]) -> Option<Vec<f64>> {
    let n = K + 1;
    if rows.len() < n + 2 {
        return None;
    }
    let mut m = vec![vec![0.0; n + 1]; n];
    for (x, y) in rows {
        let mut v = vec![1.0];
        v.extend_from_slice(x);
        for i in 0..n {
            for j in 0..n {
                m[i][j] += v[i] * v[j];
            }
            m[i][n] += v[i] * y;
        }
    }
    // A small ridge keeps a column that never varies (no reflection
    // seen, say) from making the system singular.
    for (i, row) in m.iter_mut().enumerate().skip(1) {
        row[i] += 1e-6;
    }
    for col in 0..n {
        let pivot = (col..n).max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))?;
        if m[pivot][col].abs() < 1e-12 {
            return None;
        }
        m.swap(col, pivot);
        for row in 0..n {
            if row != col {
                let f = m[row][col] / m[col][col];
                let pivot_row = m[col].clone();
                for (value, p) in m[row].iter_mut().zip(&pivot_row).skip(col) {
                    *value -= f * p;
                }
            }
        }
    }
    Some((0..n).map(|i| m[i][n] / m[i][i]).collect())
}

/// The points of each aspect on a scene.
pub type AspectPoints = Vec<(Aspect, f64)>;

/// Judge `student` (of the reference's size) aspect by aspect.
pub fn judge(
    buffers: &Buffers,
    reference: &Picture,
    student: &Picture,
    thresholds: &AspectThresholds,
    points: &AspectPoints,
) -> Judged {
    let size = buffers.size;
    let n = (size * size) as usize;
    let px = |pic: &Picture, k: usize| -> [u8; 3] {
        [pic.rgb[3 * k], pic.rgb[3 * k + 1], pic.rgb[3 * k + 2]]
    };
    let mut maps = vec![vec![0u8; n]; Aspect::ALL.len()];
    let mut results = Vec::new();

    // Geometry: background where ours sees nothing, an object where ours
    // sees a lit one; the student's background colour is theirs to choose.
    let mut background: Vec<[u8; 3]> = Vec::new();
    for k in 0..n {
        let (x, y) = (k as u32 % size, k as u32 / size);
        if buffers.centre(x, y).object.is_none() && buffers.stable(x, y, |p| p.object) {
            background.push(px(student, k));
        }
    }
    let bg = median_colour(&background);
    let covered = |p: [u8; 3]| (0..3).any(|c| p[c].abs_diff(bg[c]) > 6);
    let expect = |probe: &Probe| -> Option<bool> {
        match probe.object {
            None => Some(false),
            // A mirror's own light counts at its weight when blended,
            // `1 − k`, the least either reading gives it.
            Some(_)
                if (1.0 - probe.reflectivity) * probe.lit > 0.01
                    || probe.reflectivity * probe.reflected_radiance > 0.02 =>
            {
                Some(true)
            }
            Some(_) => None,
        }
    };
    let (mut judged, mut differ) = (0usize, 0usize);
    let (mut centre_miss, mut corner_miss, mut total) = (0usize, 0usize, 0usize);
    #[allow(clippy::needless_range_loop)] // `k` names a pixel of both images and the buffers
    for k in 0..n {
        let (x, y) = (k as u32 % size, k as u32 / size);
        let seen = covered(px(student, k));
        let centre = expect(buffers.centre(x, y));
        let corner = expect(buffers.corner(x, y));
        if let (Some(a), Some(b)) = (centre, corner) {
            total += 1;
            centre_miss += usize::from(a != seen);
            corner_miss += usize::from(b != seen);
        }
        if !buffers.stable(x, y, |p| p.object) {
            continue;
        }
        if let Some(want) = centre {
            judged += 1;
            let bad = want != seen;
            differ += usize::from(bad);
            maps[0][k] = 1 + u8::from(bad);
        }
    }
    let reading = if total > 0 && centre_miss.abs_diff(corner_miss) * 500 >= total {
        Some(if corner_miss < centre_miss {
            "your image fits rays through pixel corners (the assignment's \"usually the centre\" allows it)".to_string()
        } else {
            "your image fits rays through pixel centres".to_string()
        })
    } else {
        None
    };
    let fraction = ratio(differ, judged);
    results.push(verdict(
        Aspect::Geometry,
        judged >= 100,
        fraction,
        thresholds.geometry,
        judged,
        format!(
            "{differ} of {judged} pixels that are surely background or a lit object differ ({:.2} %)",
            100.0 * fraction
        ),
    ));

    // Shadows, on objects that neither reflect nor are textured.
    let objects: Vec<u32> = {
        let mut ids: Vec<u32> = buffers.centres.iter().filter_map(|p| p.object).collect();
        ids.sort_unstable();
        ids.dedup();
        ids
    };
    // The objects that neither reflect nor are textured: where shadows and
    // shading are judged.
    let plain: Vec<u32> = objects
        .iter()
        .copied()
        .filter(|&object| {
            buffers
                .centres
                .iter()
                .find(|p| p.object == Some(object))
                .is_some_and(|first| first.reflectivity <= 0.0 && first.uv.is_none())
        })
        .collect();
    let pixels_of = |object: u32, key: &dyn Fn(&Probe) -> u64| -> Vec<usize> {
        (0..n)
            .filter(|&k| {
                let (x, y) = (k as u32 % size, k as u32 / size);
                buffers.centres[k].object == Some(object)
                    && buffers.stable(x, y, |p| (p.object, key(p)))
            })
            .collect()
    };
    let (mut shadowed, mut shadowed_bad, mut lit, mut lit_bad) = (0usize, 0usize, 0usize, 0usize);
    for &object in &plain {
        let ks: Vec<usize> = pixels_of(object, &|p| p.visible)
            .into_iter()
            .filter(|&k| !clipped(&px(student, k)))
            .collect();
        let rows: Vec<([f64; 1], f64)> = ks
            .iter()
            .filter(|&&k| {
                let p = &buffers.centres[k];
                // Not where a specular highlight may brighten it.
                p.unshadowed - p.lit < 1e-9 && p.highlight < 0.8
            })
            .map(|&k| ([buffers.centres[k].lit], luminance(&px(student, k))))
            .collect();
        let Some(beta) = robust_fit(&rows) else {
            continue;
        };
        let (a, b) = (beta[0], beta[1].max(0.05));
        for &k in &ks {
            let probe = &buffers.centres[k];
            let s = luminance(&px(student, k));
            let r = s - (a + b * probe.lit);
            let blocked = probe.unshadowed - probe.lit;
            if blocked > 0.05 {
                shadowed += 1;
                let bad = r > 0.5 * b * blocked && r > 4.0 / 255.0;
                shadowed_bad += usize::from(bad);
                maps[1][k] = 1 + u8::from(bad);
            } else if blocked < 1e-9 && probe.lit > 0.05 {
                lit += 1;
                let bad = r < -0.5 * b * probe.lit && r < -4.0 / 255.0;
                lit_bad += usize::from(bad);
                maps[1][k] = 1 + u8::from(bad);
            }
        }
    }
    let missing = ratio(shadowed_bad, shadowed);
    let spurious = ratio(lit_bad, lit);
    let measure =
        if shadowed >= 20 { missing } else { 0.0 }.max(if lit >= 20 { spurious } else { 0.0 });
    results.push(verdict(
        Aspect::Shadows,
        shadowed >= 20 || lit >= 20,
        measure,
        thresholds.shadows,
        shadowed + lit,
        format!(
            "{shadowed_bad} of {shadowed} shadowed pixels look lit ({:.1} %); {lit_bad} of {lit} lit pixels look shadowed ({:.1} %)",
            100.0 * missing,
            100.0 * spurious
        ),
    ));

    // Reflection: on mirrors without a texture, the student's brightness
    // fitted as a + b·lit + c·(what ours sees in the mirror).
    let (mut showing, mut mirror_bad, mut mirror_judged) = (0usize, 0usize, 0usize);
    let mut weakest_gain = f64::INFINITY;
    for &object in &objects {
        let first = buffers
            .centres
            .iter()
            .find(|p| p.object == Some(object))
            .unwrap();
        if first.reflectivity == 0.0 || first.uv.is_some() {
            continue;
        }
        let ks: Vec<usize> = pixels_of(object, &|p| {
            p.visible ^ (u64::from(p.reflected.map_or(u32::MAX, |r| r)) << 32)
        })
        .into_iter()
        .filter(|&k| {
            let p = &buffers.centres[k];
            // What a mirror shows of a texture depends on the mapping,
            // which the assignment leaves open.
            // Nor what a mirror shows of a mirror, which depends on
            // whether reflection is added or blended.
            let indirect = p.reflected.is_some_and(|r| {
                buffers.textured.get(r as usize) == Some(&true)
                    || buffers.reflective.get(r as usize) == Some(&true)
            });
            !clipped(&px(student, k)) && p.highlight < 0.95 && !indirect
        })
        .collect();
        let rows: Vec<([f64; 2], f64)> = ks
            .iter()
            .map(|&k| {
                let p = &buffers.centres[k];
                ([p.lit, p.reflected_radiance], luminance(&px(student, k)))
            })
            .collect();
        let Some(beta) = robust_fit(&rows) else {
            continue;
        };
        // Whether the student's mirror shows what ours shows at all: the
        // fit's gain on it against the mirror's reflectivity, told only
        // where what ours shows varies enough over the mirror to tell a
        // gain from the intercept.
        let shown: Vec<f64> = rows.iter().map(|(x, _)| x[1]).collect();
        let gain = (spread(&shown) >= 0.03).then(|| beta[2] / first.reflectivity);
        if let Some(gain) = gain {
            weakest_gain = weakest_gain.min(gain);
        }
        let missing = gain.is_some_and(|g| g < thresholds.reflection_gain);
        for (&k, (x, s)) in ks.iter().zip(&rows) {
            let r = s - predict(&beta, x);
            // A highlight only brightens: not a reflection's error.
            let highlight = r > 0.0 && buffers.centres[k].highlight > HIGHLIGHT_CONE;
            let shows = x[1] > 0.03;
            let bad = (r.abs() > 0.06 && !highlight) || (missing && shows);
            showing += usize::from(shows);
            mirror_judged += 1;
            mirror_bad += usize::from(bad);
            maps[2][k] = 1 + u8::from(bad);
        }
    }
    let measure = ratio(mirror_bad, showing).min(1.0);
    results.push(verdict(
        Aspect::Reflection,
        showing >= 20,
        measure,
        thresholds.reflection,
        mirror_judged,
        format!(
            "{mirror_bad} of {mirror_judged} mirror pixels are not what ours shows, against {showing} that show something ({:.1} %){}",
            100.0 * measure,
            if weakest_gain.is_finite() {
                format!(
                    "; the mirror shows {:.0} % of what ours shows (at least {:.0} %)",
                    100.0 * weakest_gain,
                    100.0 * thresholds.reflection_gain
                )
            } else {
                String::new()
            }
        ),
    ));

    // Textures: contrast and mean colour over each textured object.
    let (mut worst_ratio, mut worst_colour, mut textured) = (f64::INFINITY, 0.0f64, 0usize);
    let mut colour_judged = false;
    for &object in &objects {
        let first = buffers
            .centres
            .iter()
            .find(|p| p.object == Some(object))
            .unwrap();
        if first.uv.is_none() {
            continue;
        }
        let ks = pixels_of(object, &|p| p.visible);
        if ks.len() < 30 {
            continue;
        }
        let mut inside = vec![false; n];
        for &k in &ks {
            inside[k] = true;
        }
        let contrast = |pic: &Picture| -> f64 {
            let (mut sum, mut count, mut mean) = (0.0, 0usize, 0.0);
            for &k in &ks {
                let s = luminance(&px(pic, k));
                mean += s;
                let x = k as u32 % size;
                for q in [(x + 1 < size).then_some(k + 1), Some(k + size as usize)]
                    .into_iter()
                    .flatten()
                {
                    if q < n && inside[q] {
                        sum += (s - luminance(&px(pic, q))).abs();
                        count += 1;
                    }
                }
            }
            mean /= ks.len() as f64;
            if count == 0 || mean <= 0.0 {
                0.0
            } else {
                sum / count as f64 / mean
            }
        };
        let ours = contrast(reference);
        if ours < 0.02 {
            continue;
        }
        let theirs = contrast(student);
        // The colour only away from highlights and clamped channels: a
        // highlight the tracer chose to draw whitens it (a smooth one
        // barely changes the contrast).
        let coloured: Vec<usize> = ks
            .iter()
            .copied()
            .filter(|&k| {
                buffers.centres[k].highlight <= HIGHLIGHT_CONE
                    && !clipped(&px(student, k))
                    && !clipped(&px(reference, k))
            })
            .collect();
        let mean_chroma = |pic: &Picture| -> [f64; 3] {
            let all: Vec<[f64; 3]> = coloured
                .iter()
                .filter_map(|&k| chroma(&px(pic, k)))
                .collect();
            let count = all.len().max(1) as f64;
            [0, 1, 2].map(|c| all.iter().map(|v| v[c]).sum::<f64>() / count)
        };
        colour_judged |= coloured.len() >= 30;
        let distance = if coloured.len() >= 30 {
            let (a, b) = (mean_chroma(reference), mean_chroma(student));
            (0..3).map(|c| (a[c] - b[c]).abs()).sum::<f64>()
        } else {
            0.0
        };
        worst_ratio = worst_ratio.min(theirs / ours);
        worst_colour = worst_colour.max(distance);
        textured += ks.len();
        let bad =
            theirs / ours < thresholds.texture_contrast || distance > thresholds.texture_colour;
        for &k in &ks {
            maps[3][k] = 1 + u8::from(bad);
        }
    }
    let judged_textures = textured > 0;
    let pass = !judged_textures
        || (worst_ratio >= thresholds.texture_contrast
            && worst_colour <= thresholds.texture_colour);
    results.push(AspectResult {
        aspect: Aspect::Textures,
        judged: judged_textures,
        pass,
        measure: judged_textures.then_some(worst_ratio),
        threshold: thresholds.texture_contrast,
        pixels: textured,
        points: 0.0,
        score: 0.0,
        detail: if judged_textures {
            format!(
                "texture contrast {:.0} % of ours (at least {:.0} %); {}",
                100.0 * worst_ratio,
                100.0 * thresholds.texture_contrast,
                if colour_judged {
                    format!(
                        "colour {worst_colour:.3} from ours (at most {:.3})",
                        thresholds.texture_colour
                    )
                } else {
                    "colour not judged (a highlight may lie anywhere on it)".to_string()
                }
            )
        } else {
            "no textured object to judge".into()
        },
        image: None,
    });

    // Shading: the median chromaticity of each lit, plain object.
    let (mut worst, mut shaded) = (0.0f64, 0usize);
    for &object in &plain {
        let ks: Vec<usize> = pixels_of(object, &|p| p.visible)
            .into_iter()
            .filter(|&k| {
                let p = &buffers.centres[k];
                p.lit > 0.05
                    && p.highlight < 0.9
                    && !clipped(&px(student, k))
                    && chroma(&px(student, k)).is_some()
                    && chroma(&px(reference, k)).is_some()
            })
            .collect();
        if ks.len() < 20 {
            continue;
        }
        let median = |pic: &Picture, c: usize| {
            let mut v: Vec<f64> = ks
                .iter()
                .filter_map(|&k| chroma(&px(pic, k)))
                .map(|v| v[c])
                .collect();
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let distance = (0..3)
            .map(|c| (median(reference, c) - median(student, c)).abs())
            .sum::<f64>();
        worst = worst.max(distance);
        shaded += ks.len();
        for &k in &ks {
            maps[4][k] = 1 + u8::from(distance > thresholds.shading);
        }
    }
    results.push(verdict(
        Aspect::Shading,
        shaded > 0,
        worst,
        thresholds.shading,
        shaded,
        format!("the colour of lit objects is {worst:.3} from ours (chromaticity)"),
    ));

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
        reading,
    }
}

/// The standard deviation of `values` (0 for none).
fn spread(values: &[f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt()
}

fn ratio(a: usize, b: usize) -> f64 {
    if b == 0 {
        0.0
    } else {
        a as f64 / b as f64
    }
}

/// A verdict whose measure must not exceed `threshold`.
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
        detail: if judged {
            detail
        } else {
            "too few pixels tell this aspect on this scene".into()
        },
        image: None,
    }
}

/// The per-channel median, black for none.
fn median_colour(pixels: &[[u8; 3]]) -> [u8; 3] {
    if pixels.is_empty() {
        return [0; 3];
    }
    [0, 1, 2].map(|c| {
        let mut v: Vec<u8> = pixels.iter().map(|p| p[c]).collect();
        v.sort_unstable();
        v[v.len() / 2]
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
    use super::*;

    #[test]
    fn the_fit_finds_a_line_despite_outliers() {
        let mut rows: Vec<([f64; 1], f64)> = (0..50)
            .map(|i| ([f64::from(i) / 50.0], 0.2 + 0.7 * f64::from(i) / 50.0))
            .collect();
        rows.push(([0.5], 1.0));
        let beta = robust_fit(&rows).unwrap();
        assert!(
            (beta[0] - 0.2).abs() < 1e-3 && (beta[1] - 0.7).abs() < 1e-3,
            "{beta:?}"
        );
    }
}
