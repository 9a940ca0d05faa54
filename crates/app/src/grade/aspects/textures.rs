//! Textures: that a textured object shows its texture, by the contrast
//! between neighbouring pixels over the object (relative to its mean
//! brightness) against ours, and by its mean chromaticity away from
//! highlights and clamped channels.

use super::evidence::{chroma, clipped, luminance, Evidence, HIGHLIGHT_CONE};
use super::{Aspect, AspectResult, AspectThresholds};
use crate::compare::Picture;

/// The least number of pixels an object needs for its texture to be
/// judged, and for its colour.
const LEAST_PIXELS: usize = 30;

/// The mean absolute difference between neighbouring pixels of `ks` in
/// `picture`, over their mean luminance.
fn contrast(e: &Evidence, picture: &Picture, ks: &[usize], inside: &[bool]) -> f64 {
    let (size, n) = (e.size, e.n);
    let (mut sum, mut count, mut mean) = (0.0, 0usize, 0.0);
    for &k in ks {
        let s = luminance(&e.px(picture, k));
        mean += s;
        let x = k as u32 % size;
        for q in [(x + 1 < size).then_some(k + 1), Some(k + size as usize)]
            .into_iter()
            .flatten()
        {
            if q < n && inside[q] {
                sum += (s - luminance(&e.px(picture, q))).abs();
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

/// Judge textures, marking `map`.
pub(super) fn judge(e: &Evidence, thresholds: &AspectThresholds, map: &mut [u8]) -> AspectResult {
    let (mut worst_ratio, mut worst_colour, mut textured) = (f64::INFINITY, 0.0f64, 0usize);
    let mut colour_judged = false;
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
        let ours = contrast(e, e.reference, &ks, &inside);
        if ours < 0.02 {
            continue;
        }
        let theirs = contrast(e, e.student, &ks, &inside);
        // The colour only away from highlights and clamped channels: a
        // highlight the tracer chose to draw whitens it (a smooth one
        // barely changes the contrast).
        let coloured: Vec<usize> = ks
            .iter()
            .copied()
            .filter(|&k| {
                e.buffers.centres[k].highlight <= HIGHLIGHT_CONE
                    && !clipped(&e.student_px(k))
                    && !clipped(&e.px(e.reference, k))
            })
            .collect();
        let mean_chroma = |pic| -> [f64; 3] {
            let all: Vec<[f64; 3]> = coloured
                .iter()
                .filter_map(|&k| chroma(&e.px(pic, k)))
                .collect();
            let count = all.len().max(1) as f64;
            [0, 1, 2].map(|c| all.iter().map(|v| v[c]).sum::<f64>() / count)
        };
        colour_judged |= coloured.len() >= LEAST_PIXELS;
        let distance = if coloured.len() >= LEAST_PIXELS {
            let (a, b) = (mean_chroma(e.reference), mean_chroma(e.student));
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
            map[k] = 1 + u8::from(bad);
        }
    }
    let judged = textured > 0;
    let pass = !judged
        || (worst_ratio >= thresholds.texture_contrast
            && worst_colour <= thresholds.texture_colour);
    AspectResult {
        aspect: Aspect::Textures,
        judged,
        pass,
        measure: judged.then_some(worst_ratio),
        threshold: thresholds.texture_contrast,
        pixels: textured,
        points: 0.0,
        score: 0.0,
        detail: if judged {
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
    }
}
