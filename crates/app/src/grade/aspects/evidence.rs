//! What every aspect reads: the student's image, ours, and what our
//! renderer sees at each pixel (its probes), with the pixel-level
//! measures the aspects share (luminance, chromaticity, clipping, where
//! a highlight may lie) and the objects they judge, and the student's
//! image turned back to linear light by their fitted tone curve
//! ([`super::tone`]).

use super::background::Background;
use super::falloff::{self, Falloff, Group, LightFit};
use super::mapping;
use super::palette;
use super::tone::{self, luminance_of, Curve, Linearised, Reads, Row};
use super::unlit::{self, Mirrors};
use crate::compare::Picture;
use raytracer_render::render::probe::{Buffers, Probe, Wears};

/// The cosine between the mirror direction and a light's direction above
/// which a pixel may hold a specular highlight the tracer chose to draw: a
/// Phong highlight `k_s·(R·V)^n` is below 0.04 out of this cone (60°) for
/// any `k_s ≤ 1` and `n ≥ 5`. A highlight only ever brightens.
pub(super) const HIGHLIGHT_CONE: f64 = 0.5;

/// The fewest pixels an object needs to tell the tone curve.
const TONE_ROWS: usize = 30;

/// The most pixels of an object the tone curve is fitted on, evenly
/// spread over it: every curve tried is fitted to every object, and
/// hundreds of pixels tell a line as well as thousands (the rounding of
/// each value, not their number, limits the fit).
const TONE_SAMPLE: usize = 400;

/// At most [`TONE_SAMPLE`] of `rows`, evenly spaced.
fn thinned<T>(rows: Vec<T>) -> Vec<T> {
    let step = rows.len().div_ceil(TONE_SAMPLE).max(1);
    rows.into_iter().step_by(step).collect()
}

/// One scene's evidence: the two images (of one size) and the probes.
pub(super) struct Evidence<'a> {
    pub buffers: &'a Buffers,
    pub reference: &'a Picture,
    pub student: &'a Picture,
    /// The side of the (square) images.
    pub size: u32,
    /// Pixels in an image.
    pub n: usize,
    /// Every object some pixel's centre sees, by id.
    pub objects: Vec<u32>,
    /// The objects that neither reflect nor are textured: where shadows
    /// and shading are judged.
    pub plain: Vec<u32>,
    /// The student's fitted tone curve ([`super::tone`]), the curves the
    /// image cannot tell from it, and the least share of the image's
    /// spread a curve leaves unexplained: how well these probes explain
    /// the image.
    pub tone: tone::Fitted,
    /// The scene's fit of the student's light on plain objects, with
    /// its falloff with distance ([`super::falloff`]); `None` when no
    /// plain object tells it.
    pub light: Option<LightFit>,
    /// Per pixel: whether the student's pixel, on a plain object, shows
    /// a colour no light of the scene gives ([`super::palette`]); `None`
    /// where that is not judged (not a stable pixel of a plain object, or
    /// a channel clamped). A foreign pixel tells no fit: its channels
    /// were wrapped or mixed up.
    pub foreign: Vec<Option<bool>>,
    /// The student's pixels in linear light, through their curve.
    linear: Vec<[f64; 3]>,
    /// The student's background, fitted when first read
    /// ([`Evidence::background`]).
    background: std::sync::OnceLock<Background>,
    /// The mirrors the student draws without their own light, read when
    /// first asked ([`Evidence::unlit_mirrors`]).
    unlit_mirrors: std::sync::OnceLock<Mirrors>,
}

/// Whose colour [`Evidence::colour`] reads.
#[derive(Clone, Copy)]
pub(super) enum Whose {
    Ours,
    Theirs,
}

impl<'a> Evidence<'a> {
    pub fn new(buffers: &'a Buffers, reference: &'a Picture, student: &'a Picture) -> Self {
        let mut evidence = Evidence::unfitted(buffers, reference, student);
        evidence.read_light();
        // The pixels whose colour no light gives are read under that
        // reading; where there are any, the reading is fitted again
        // without them, as enough of them would bend it.
        evidence.foreign = evidence.foreign_pixels();
        if evidence.foreign.contains(&Some(true)) {
            evidence.read_light();
            evidence.foreign = evidence.foreign_pixels();
        }
        evidence
    }

    /// Per pixel, for each stable pixel of a plain object with no channel
    /// clamped, whether its colour no light of the scene gives on that
    /// object nor on any other the image shows (a pixel showing another
    /// object is geometry's), under the curves read so far and under
    /// clamping alone ([`palette::outside`]). Clamping alone, the
    /// assignment's plain reading, as another bug can pull the fitted
    /// curve to a higher power, which reads a saturated colour written
    /// as it is as more saturated than any light gives.
    fn foreign_pixels(&self) -> Vec<Option<bool>> {
        let palettes: Vec<Vec<glam::DVec3>> = self
            .objects
            .iter()
            .map(|&object| palette::generators(self.buffers, object))
            .collect();
        let mut curves: Vec<Curve> = self.tone.plausible().collect();
        if !curves.contains(&Curve::CLAMPING) {
            curves.push(Curve::CLAMPING);
        }
        let mut foreign = vec![None; self.n];
        for (i, &object) in self.objects.iter().enumerate() {
            if !self.plain.contains(&object) {
                continue;
            }
            // Its own cone first, which holds nearly every pixel, then
            // every other object's.
            let cones: Vec<&[glam::DVec3]> = std::iter::once(i)
                .chain((0..palettes.len()).filter(|&j| j != i))
                .map(|j| palettes[j].as_slice())
                .collect();
            for k in self.pixels_of(object, &|_| 0) {
                let written = self.student_px(k);
                if !clipped(&written) {
                    foreign[k] = Some(palette::outside(&cones, written, &curves));
                }
            }
        }
        foreign
    }

    /// Fit the student's light and tone curve: the light's falloff on the
    /// image as written, the tone curve with the light that falloff
    /// leaves, and the falloff again in linear light, until the falloff
    /// settles. A falloff read as a curve would bend every colour, and a
    /// curve read as a falloff would dim every light.
    fn read_light(&mut self) {
        let mut light = falloff::fit(&self.light_groups());
        for _ in 0..2 {
            let falloff = light.as_ref().map(|l| l.falloff);
            self.read_tone(falloff.unwrap_or(Falloff::NONE));
            light = falloff::fit(&self.light_groups());
            if light.as_ref().map(|l| l.falloff) == falloff {
                break;
            }
        }
        self.light = light;
    }

    /// The evidence with no reading fitted: the image read as written,
    /// no light fit. Enough for geometry, which reads only coverage.
    pub fn unfitted(buffers: &'a Buffers, reference: &'a Picture, student: &'a Picture) -> Self {
        let size = buffers.size;
        let mut objects: Vec<u32> = buffers.centres.iter().filter_map(|p| p.object).collect();
        objects.sort_unstable();
        objects.dedup();
        let mut evidence = Evidence {
            buffers,
            reference,
            student,
            size,
            n: (size * size) as usize,
            objects,
            plain: Vec::new(),
            tone: tone::Fitted::NONE,
            light: None,
            foreign: vec![None; (size * size) as usize],
            linear: Vec::new(),
            background: std::sync::OnceLock::new(),
            unlit_mirrors: std::sync::OnceLock::new(),
        };
        evidence.plain = evidence
            .objects
            .iter()
            .copied()
            .filter(|&object| {
                let first = evidence.first_probe(object);
                first.reflectivity <= 0.0 && first.uv.is_none()
            })
            .collect();
        evidence.linear = student
            .rgb
            .chunks_exact(3)
            .map(|p| [0, 1, 2].map(|c| f64::from(p[c]) / 255.0))
            .collect();
        evidence
    }

    /// The pixels of each plain object that tell the scene's light fit
    /// ([`super::falloff`]): stable, fully lit (no light of ours
    /// blocked), away from highlight lobes and clamping.
    pub fn light_groups(&self) -> Vec<Group<'a>> {
        self.fully_lit(0.8)
            .into_iter()
            .map(|(object, ks)| {
                let rows = ks
                    .into_iter()
                    .map(|k| (&self.buffers.centres[k], self.luminance(Whose::Theirs, k)))
                    .collect();
                (object, rows)
            })
            .collect()
    }

    /// The stable pixels of each plain object (at least ten) that no
    /// light of ours is blocked from, whose mirror direction is below
    /// `highlight` from every light's, and where no channel of theirs
    /// is clamped.
    pub fn fully_lit(&self, highlight: f64) -> Vec<(u32, Vec<usize>)> {
        let e = self;
        e.plain
            .iter()
            .map(|&object| {
                let ks = e
                    .pixels_of(object, &|p| p.visible)
                    .into_iter()
                    .filter(|&k| {
                        let p = &e.buffers.centres[k];
                        p.unshadowed - p.lit < 1e-9
                            && p.highlight < highlight
                            && !clipped(&e.student_px(k))
                            && e.foreign[k] != Some(true)
                    })
                    .collect();
                (object, ks)
            })
            .filter(|(_, ks): &(u32, Vec<usize>)| ks.len() >= 10)
            .collect()
    }

    /// The luminance of `whose` image where no light of ours reaches an
    /// object (facing away from every light, or shadowed from all): the
    /// median over those of its pixels `ks`, when ten or more tell it.
    pub fn unlit_level(&self, whose: Whose, ks: &[usize]) -> Option<f64> {
        let mut levels: Vec<f64> = ks
            .iter()
            .filter(|&&k| self.buffers.centres[k].lit <= 0.0)
            .map(|&k| self.luminance(whose, k))
            .collect();
        levels.sort_by(f64::total_cmp);
        (levels.len() >= 10).then(|| levels[levels.len() / 2])
    }

    /// Fit the tone curve with each light dimmed by `falloff`, and turn
    /// the student's image back to linear light by it.
    fn read_tone(&mut self, falloff: Falloff) {
        let [plain, mirrors] = self.tone_rows(falloff);
        self.tone = tone::fit(&plain, &mirrors, &|| self.textured_tone_rows());
        let linear = self.tone.curve.linearise();
        self.linear = self
            .student
            .rgb
            .chunks_exact(3)
            .map(|p| linear.pixel([p[0], p[1], p[2]]))
            .collect();
    }

    /// Whether pixel `k` tells the curve: no light of ours blocked there,
    /// out of the cone where any highlight lobe may lie, no channel
    /// clamped, and a colour some light gives.
    fn tells_tone(&self, k: usize) -> bool {
        let p = &self.buffers.centres[k];
        p.unshadowed - p.lit < 1e-9
            && p.highlight <= HIGHLIGHT_CONE
            && !clipped(&self.student_px(k))
            && self.foreign[k] != Some(true)
    }

    /// The pixels of each object that tell the curve ([`Self::tells_tone`]),
    /// with what ours sees there, each light dimmed by `falloff`, by kind.
    /// A plain object's three channels, each with the light of each lamp
    /// ([`Falloff::shares`]: a channel is a line in them, whatever the
    /// lights' colours); a mirror's luminance (where it shows nothing or
    /// an object that is neither a mirror nor textured), with the light
    /// that reaches it and the colour and light of what it shows.
    fn tone_rows(&self, falloff: Falloff) -> [Vec<tone::Group>; 2] {
        let e = self;
        let stable = |object: u32| {
            let ks = e.pixels_of(object, &|p| {
                p.visible ^ (u64::from(p.reflected.map_or(u32::MAX, |r| r)) << 32)
            });
            ks.into_iter().filter(|&k| e.tells_tone(k))
        };
        let enough = |g: &tone::Group| g.1.len() >= TONE_ROWS;
        let plain = e
            .plain
            .iter()
            .flat_map(|&object| {
                let rows: Vec<Row> = thinned(stable(object).collect())
                    .into_iter()
                    .map(|k| (e.student_px(k), falloff.shares(&e.buffers.centres[k])))
                    .collect();
                (0..3).map(move |c| (Reads::Channel(c), rows.clone()))
            })
            .filter(enough)
            .collect();
        let mirrors = e
            .objects
            .iter()
            .filter(|&&o| !e.plain.contains(&o) && e.first_probe(o).uv.is_none())
            .map(|&object| {
                let rows = stable(object)
                    .filter_map(|k| {
                        let p = &e.buffers.centres[k];
                        // What it shows must be an object that is neither
                        // a mirror nor textured, or nothing.
                        let shown = p.shown?;
                        Some((e.student_px(k), [falloff.lit(p), shown[0], shown[1]]))
                    })
                    .collect();
                (Reads::Luminance, thinned(rows))
            })
            .filter(enough)
            .collect();
        [plain, mirrors]
    }

    /// The pixels of each textured object that tell the curve, channel by
    /// channel, with what ours shows there under the student's own
    /// texture mapping ([`mapping::fit`], on the image as read so far):
    /// the light times the texel their mapping reads, and the texel alone
    /// (any ambient share of theirs), so the texture's pattern is in what
    /// ours sees, not left to the curve.
    fn textured_tone_rows(&self) -> Vec<tone::Group> {
        let e = self;
        e.objects
            .iter()
            .filter_map(|&object| {
                let wears = e.buffers.wears.get(object as usize).copied().flatten()?;
                let ks = thinned(
                    e.pixels_of(object, &|p| p.visible)
                        .into_iter()
                        .filter(|&k| e.tells_tone(k))
                        .collect(),
                );
                if ks.len() < TONE_ROWS {
                    return None;
                }
                let (fitted, _) = e.mapping_of(wears, &ks);
                let texels: Vec<[f64; 3]> = ks
                    .iter()
                    .map(|&k| mapping::texel_at(e.buffers, wears, fitted, &e.buffers.centres[k]))
                    .collect();
                Some((0..3).map(move |c| {
                    let rows = ks
                        .iter()
                        .zip(&texels)
                        .map(|(&k, texel)| {
                            let light = e.buffers.centres[k].light[c];
                            (e.student_px(k), [texel[c] * light, texel[c], 0.0])
                        })
                        .collect();
                    (Reads::Channel(c), rows)
                }))
            })
            .flatten()
            .collect()
    }

    /// The student's mapping of the texture `wears` on the object whose
    /// pixels are `ks`, fitted on their luminance as read so far, with
    /// the share of its variance the mapping explains ([`mapping::fit`]).
    pub fn mapping_of(&self, wears: Wears, ks: &[usize]) -> (mapping::Mapping, f64) {
        let theirs = |k| self.luminance(Whose::Theirs, k);
        let seen = mapping::Seen {
            buffers: self.buffers,
            theirs: &theirs,
        };
        mapping::fit(&seen, wears, ks)
    }

    /// Pixel `k` in linear light: ours as it is, in [0, 1], the student's
    /// turned back by their tone curve.
    pub fn colour(&self, whose: Whose, k: usize) -> [f64; 3] {
        match whose {
            Whose::Ours => self.reference.pixel(k).map(|c| f64::from(c) / 255.0),
            Whose::Theirs => self.linear[k],
        }
    }

    /// The luminance of pixel `k` in linear light.
    pub fn luminance(&self, whose: Whose, k: usize) -> f64 {
        luminance_of(self.colour(whose, k))
    }

    /// The chromaticity of pixel `k` in linear light, when the pixel as
    /// written is bright enough to have one ([`chroma`]).
    pub fn chroma(&self, whose: Whose, k: usize) -> Option<[f64; 3]> {
        let written = match whose {
            Whose::Ours => self.reference.pixel(k),
            Whose::Theirs => self.student_px(k),
        };
        chroma(&written)?;
        chroma_of_light(self.colour(whose, k))
    }

    /// The chromaticity of the student's pixel `k` in linear light under
    /// a curve (one of [`tone::Fitted::plausible`], [`Curve::linearise`]d),
    /// when the pixel as written is bright enough to have one.
    pub fn chroma_under(&self, linear: &Linearised, k: usize) -> Option<[f64; 3]> {
        let written = self.student_px(k);
        chroma(&written)?;
        chroma_of_light(linear.pixel(written))
    }

    /// The luminance of the student's pixel `k` in linear light under a
    /// curve (one of [`tone::Fitted::plausible`], [`Curve::linearise`]d).
    pub fn luminance_under(&self, linear: &Linearised, k: usize) -> f64 {
        luminance_of(linear.pixel(self.student_px(k)))
    }

    /// Pixel `k` of the student's image.
    pub fn student_px(&self, k: usize) -> [u8; 3] {
        self.student.pixel(k)
    }

    /// The student's background ([`Background`]), fitted once: geometry
    /// and the pixel reading read it, and reflection.
    pub fn background(&self) -> &Background {
        (self.background).get_or_init(|| Background::of(self.buffers, self.student))
    }

    /// The mirrors the student draws without their own light
    /// ([`unlit::mirrors`]), read once: the pixel reading and geometry
    /// read them.
    pub fn unlit_mirrors(&self) -> &Mirrors {
        (self.unlit_mirrors)
            .get_or_init(|| unlit::mirrors(self.buffers, self.background(), self.student))
    }

    /// The column and row of pixel `k`.
    pub fn xy(&self, k: usize) -> (u32, u32) {
        (k as u32 % self.size, k as u32 / self.size)
    }

    /// The probe at the centre of the first pixel that sees `object`.
    pub fn first_probe(&self, object: u32) -> &Probe {
        self.buffers
            .centres
            .iter()
            .find(|p| p.object == Some(object))
            .expect("an object of the list is seen by some pixel")
    }

    /// The pixels whose centre sees `object`, stable (the same at the
    /// centre and the four corners) for the object and for what `key`
    /// reads of the probe.
    pub fn pixels_of(&self, object: u32, key: &dyn Fn(&Probe) -> u64) -> Vec<usize> {
        (0..self.n)
            .filter(|&k| {
                let (x, y) = self.xy(k);
                self.buffers.centres[k].object == Some(object)
                    && self.buffers.stable(x, y, |p| (p.object, key(p)))
            })
            .collect()
    }
}

/// Chromaticity of an 8-bit pixel: each channel over their sum; `None`
/// when too dark for its rounding to leave a colour.
fn chroma(p: &[u8]) -> Option<[f64; 3]> {
    let sum = f64::from(p[0]) + f64::from(p[1]) + f64::from(p[2]);
    (sum > 15.0).then(|| [0, 1, 2].map(|c| f64::from(p[c]) / sum))
}

/// Each channel of a colour in linear light over their sum; `None` for
/// black.
fn chroma_of_light(c: [f64; 3]) -> Option<[f64; 3]> {
    let sum = c[0] + c[1] + c[2];
    (sum > 0.0).then(|| c.map(|v| v / sum))
}

/// A channel at the top of its range: the tracer may have clamped it.
pub(super) fn clipped(p: &[u8]) -> bool {
    p.iter().any(|&c| c >= 250)
}
