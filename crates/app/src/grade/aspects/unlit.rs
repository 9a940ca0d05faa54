//! Mirrors drawn without their own light. Where a lit mirror shows the
//! black background, a mirror that adds what it shows to no light of its
//! own (a reflection bug) is black, as a mirror that is not there at
//! all: the pixel alone cannot tell geometry from reflection. The rest
//! of the same mirror tells: where ours shows an object that is no
//! mirror in it, clearly above black at the mirror's weight `k`, any
//! mirror that is there shows something. A mirror whose lit pixels that
//! show something the student covers, while they leave the lit pixels
//! that show nothing uncovered at less than half that share, draws no
//! light of its own; geometry then judges it only where it shows
//! something, and the missing light is reflection's. A mirror misplaced
//! or of the wrong size covers both alike, and one that is not there
//! covers neither, so geometry still judges all of it. Where too few of
//! its lit pixels show something to tell (a mirror showing only mirrors
//! and the background), geometry judges all of it too: an image that
//! leaves it out must not pass.

use std::collections::BTreeMap;

use super::background::Background;
use crate::compare::Picture;
use raytracer_render::render::probe::{Buffers, Probe};

/// Whether ours shows, in the mirror at `probe`, an object that is no
/// mirror (how another mirror shows is the student's), clearly above
/// black at the mirror's weight, under the reading that shows least
/// (tinted by a grey mirror, it shows less).
pub(super) fn shows(probe: &Probe, buffers: &Buffers) -> bool {
    let no_mirror = probe
        .reflected
        .is_some_and(|r| !buffers.reflective.get(r as usize).copied().unwrap_or(true));
    let shown = probe.reflected_radiance.min(probe.reflected_tinted);
    no_mirror && probe.reflectivity * shown > 0.01
}

/// The mirrors of an image read as drawn without their own light.
pub(super) struct Mirrors(Vec<u32>);

impl Mirrors {
    pub fn holds(&self, object: u32) -> bool {
        self.0.contains(&object)
    }
}

/// The fewest lit pixels showing something a mirror needs for its
/// share of them covered to tell (as reflection needs to judge a
/// mirror).
const TELLS: usize = 20;

/// The mirrors the `student` draws without their own light, against
/// their `background` (read once per evidence): over each mirror's lit
/// pixels (its own light at the blended weight `1 − k` above black),
/// the share the student covers where it shows something, and where it
/// shows nothing.
pub(super) fn mirrors(buffers: &Buffers, background: &Background, student: &Picture) -> Mirrors {
    // Per mirror: lit pixels showing something, and those covered; lit
    // pixels showing nothing, and those covered.
    let mut counts: BTreeMap<u32, [usize; 4]> = BTreeMap::new();
    for (k, p) in buffers.centres.iter().enumerate() {
        let Some(object) = p.object else { continue };
        if p.reflectivity == 0.0 || (1.0 - p.reflectivity) * p.lit <= 0.01 {
            continue;
        }
        let at = if shows(p, buffers) { 0 } else { 2 };
        let c = counts.entry(object).or_default();
        c[at] += 1;
        c[at + 1] += usize::from(background.covered(student, k));
    }
    let share = |part: usize, whole: usize| part as f64 / whole as f64;
    Mirrors(
        counts
            .into_iter()
            .filter(|(_, [showing, covered, dark, dark_covered])| {
                *showing >= TELLS
                    && *dark > 0
                    && share(*dark_covered, *dark) < 0.5 * share(*covered, *showing)
            })
            .map(|(object, _)| object)
            .collect(),
    )
}
