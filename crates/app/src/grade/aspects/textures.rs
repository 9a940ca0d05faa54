//! Textures: that a textured object shows its texture, by the contrast
//! between neighbouring pixels over the object (relative to its mean
//! brightness) against ours, which no mapping changes. The student's
//! contrast is read under each tone curve their image cannot tell apart
//! ([`super::tone::Fitted::plausible`]), and the largest taken: a curve
//! stretches or squeezes contrast (a screen's power of 2.2 about
//! doubles it), and a curve the image does not tell says nothing of the
//! student. And the textures worn over one colour must be worn equally
//! bright ([`super::worn`]): a texture's samples read on the wrong scale
//! keep its contrast. The texture's colour under the lights is shading's
//! ([`super::shading`]): a light's colour ignored on a textured object
//! costs shading, not textures.

use super::evidence::{Evidence, Whose};
use super::falloff::GAIN_FACTOR;
use super::worn;
use super::{failed, Aspect, AspectResult, AspectThresholds};

/// The least number of pixels an object needs for its texture to be
/// judged, and for its colour.
pub(super) const LEAST_PIXELS: usize = 30;

/// The mean absolute difference between neighbouring pixels of `ks` in
/// an image's `luminance` (in linear light), over their mean luminance.
fn contrast(e: &Evidence, luminance: &dyn Fn(usize) -> f64, ks: &[usize], inside: &[bool]) -> f64 {
    let (size, n) = (e.size, e.n);
    let (mut sum, mut count, mut mean) = (0.0, 0usize, 0.0);
    for &k in ks {
        let s = luminance(k);
        mean += s;
        let x = k as u32 % size;
        for q in [(x + 1 < size).then_some(k + 1), Some(k + size as usize)]
            .into_iter()
            .flatten()
        {
            if q < n && inside[q] {
                sum += (s - luminance(q)).abs();
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
}

/// A textured object whose texture shows in our image: its stable
/// pixels and the contrast of ours and of the student's over them.
pub(super) struct Textured {
    pub object: u32,
    pub ks: Vec<usize>,
    pub ours: f64,
    pub theirs: f64,
}

/// Every textured object with [`LEAST_PIXELS`] stable pixels or more whose
/// texture shows in our image.
pub(super) fn textured(e: &Evidence) -> Vec<Textured> {
    let mut found = Vec::new();
    for &object in &e.objects {
        if e.first_probe(object).uv.is_none() {
            continue;
        }
        let ks = e.pixels_of(object, &|p| p.visible);
        if ks.len() < LEAST_PIXELS {
            continue;
        }
        let mut inside = vec![false; e.n];
        for &k in &ks {
            inside[k] = true;
        }
        let ours = contrast(e, &|k| e.luminance(Whose::Ours, k), &ks, &inside);
        if ours < 0.02 {
            continue;
        }
        let theirs = e
            .tone
            .plausible()
            .map(|curve| {
                let linear = curve.linearise();
                contrast(e, &|k| e.luminance_under(&linear, k), &ks, &inside)
            })
            .fold(0.0, f64::max);
        found.push(Textured {
            object,
            ks,
            ours,
            theirs,
        });
    }
    found
}

/// Judge textures, marking `map`: each texture's contrast, and how
/// bright it is worn against the other textures of its colour
/// ([`super::worn`]), the latter not where the student's shadows fail.
pub(super) fn judge(
    e: &Evidence,
    thresholds: &AspectThresholds,
    earlier: &[AspectResult],
    map: &mut [u8],
) -> AspectResult {
    let (mut worst_ratio, mut pixels) = (f64::INFINITY, 0usize);
    let objects = textured(e);
    for object in &objects {
        let ratio = object.theirs / object.ours;
        worst_ratio = worst_ratio.min(ratio);
        pixels += object.ks.len();
        let bad = ratio < thresholds.texture_contrast;
        for &k in &object.ks {
            map[k] = 1 + u8::from(bad);
        }
    }
    let shown: Vec<(u32, &[usize])> = objects
        .iter()
        .filter(|o| o.theirs / o.ours >= thresholds.texture_contrast)
        .map(|o| (o.object, o.ks.as_slice()))
        .collect();
    let worn = if failed(earlier, Aspect::Shadows) {
        None
    } else {
        worn::worst(e, &shown, LEAST_PIXELS, map)
    };
    let judged = pixels > 0;
    let contrast_pass = !judged || worst_ratio >= thresholds.texture_contrast;
    let mut detail = if judged {
        format!(
            "texture contrast {:.0} % of ours (at least {:.0} %)",
            100.0 * worst_ratio,
            100.0 * thresholds.texture_contrast
        )
    } else {
        format!("no textured object with {LEAST_PIXELS} stable pixels whose texture shows in ours")
    };
    if let Some((scale, _)) = worn {
        detail.push_str(&format!(
            "; one texture is worn {scale:.2} times as bright as the textures over its colour together (alike on every object, at most {GAIN_FACTOR} times either way)"
        ));
    }
    AspectResult {
        aspect: Aspect::Textures,
        judged,
        // Less contrast is worse: the bound is a least one.
        pass: contrast_pass && worn.is_none_or(|(scale, _)| worn::within(scale)),
        measure: judged.then_some(worst_ratio),
        threshold: thresholds.texture_contrast,
        pixels,
        points: 0.0,
        score: 0.0,
        detail,
        image: None,
    }
}
