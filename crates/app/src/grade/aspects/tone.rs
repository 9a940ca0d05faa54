//! The student's tone curve: how their tracer turns light into 8-bit
//! values (clamping alone, a gamma for the screen, an sRGB curve, an
//! exposure that compresses highlights instead of clipping them, ACES's
//! filmic curve with its toe, on each channel or on a pixel's luminance
//! with its hue kept), which the assignment leaves open. One curve
//! shared by the three channels is fitted ([`Curve`]: a power for the
//! screen after a shoulder, an exposure's scale being any fit's gain),
//! and every aspect but geometry reads the student's image turned back
//! to linear light by it, so a curve changes neither a colour nor a
//! shadow. One curve for all channels: a per-channel fit would turn an
//! ignored light colour back into the right one.
//!
//! The curve is chosen by what it does to shapes, never to colours: on
//! each object that tells (plain objects and mirrors, by their pixels no
//! shadow, highlight lobe or clamping touches), the student's linearised
//! luminance must be a straight function of what ours sees there (the
//! light that reaches the point, and on a mirror the colour and light of
//! what it shows), and the curve whose fits leave the least
//! root-mean-square share of the image's spread unexplained (residuals
//! taken back to 8-bit values, where every curve rounds alike) wins. It
//! is kept only when it leaves less than nine tenths of what clamping
//! leaves ([`KEEP_CLAMPING`]): on a scene with little light to tell,
//! every curve fits about as well, and the image is then read as written.
//! The curves the best fit does not beat by that same share are kept
//! with the chosen one ([`Fitted::alike`]): the image cannot tell
//! them apart, so no verdict may rest on which of them is the student's.

use super::fit::{predict, robust_fit};
use std::collections::HashMap;
use std::sync::{Arc, LazyLock, Mutex, PoisonError};

/// A tone curve by its inverse: the light `x` a tracer wrote as the value
/// `v` in [0, 1], up to the scale every fit's gain takes. The value is
/// first raised to `gamma` (a screen's power), then a `shoulder` of
/// strength `m` in [0, 1) is undone: `x ∝ −ln(1 − m·p)` for an exposure
/// `p = 1 − e^(−k·x)`, `x ∝ p/(1 − m·p)` for Reinhard's
/// `p = x/(1 + x)`, or ACES's curve undone at `m·p` (its values
/// spanning that share of its range), each scaled to keep a middle grey
/// (`p` = ½) where it is, so the light keeps the scale of the image as
/// written (the aspects' bounds are in that scale) and only its spread
/// changes. With no shoulder (`m` = 0) it is the power alone; clamping
/// alone is `gamma` 1. sRGB's curve is a power of about 2.2 with a short
/// linear toe below the darkest few values. The shoulder compresses each
/// channel alone, or a pixel's luminance, `over` ([`Over`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Curve {
    pub gamma: f64,
    pub shoulder: Shoulder,
    pub over: Over,
}

/// What a [`Shoulder`] compresses: each channel alone (so a bright
/// colour pales toward white), or a pixel's luminance, its three channels
/// scaled by the one factor that takes the luminance there (so its hue is
/// kept), a tone curve the assignment leaves as open as any other.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Over {
    Channels,
    Luminance,
}

/// The highlight compression a [`Curve`] undoes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Shoulder {
    None,
    /// An exposure, `1 − e^(−k·x)`, of strength `m`.
    Exposure(f64),
    /// Reinhard's `x/(1 + x)`, of strength `m`.
    Reinhard(f64),
    /// ACES's filmic curve as games and tutorials write it (Narkowicz's
    /// fit, [`aces`]), a toe below a shoulder, of strength `m`.
    Aces(f64),
}

/// ACES's filmic curve by Narkowicz's fit,
/// `x(2.51x + 0.03)/(x(2.43x + 0.59) + 0.14)`: rising as the light
/// squared in the darks, to 1.033 in the brightest.
fn aces(x: f64) -> f64 {
    x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14)
}

/// The light [`aces`] writes as `v`, in [0, 1]: the root in [0, ∞) of
/// `(2.43v − 2.51)x² + (0.59v − 0.03)x + 0.14v = 0`.
fn aces_inverse(v: f64) -> f64 {
    let (a, b, c) = (2.43 * v - 2.51, 0.59 * v - 0.03, 0.14 * v);
    (-b - (b * b - 4.0 * a * c).sqrt()) / (2.0 * a)
}

impl Shoulder {
    /// The light, before its scale, that a shoulder turned into `p`.
    fn undo(self, p: f64) -> f64 {
        match self {
            Shoulder::None => p,
            Shoulder::Exposure(m) => -(-m * p).ln_1p(),
            Shoulder::Reinhard(m) => p / (1.0 - m * p),
            Shoulder::Aces(m) => aces_inverse(m * p),
        }
    }

    /// The inverse of [`Shoulder::undo`].
    fn redo(self, raw: f64) -> f64 {
        match self {
            Shoulder::None => raw,
            Shoulder::Exposure(m) => (1.0 - (-raw).exp()) / m,
            Shoulder::Reinhard(m) => raw / (1.0 + m * raw),
            Shoulder::Aces(m) => aces(raw) / m,
        }
    }

    /// The scale that keeps a middle grey where it is.
    fn scale(self) -> f64 {
        0.5 / self.undo(0.5)
    }

    /// What [`Shoulder::undo`] multiplies a luminance `p` by, the light
    /// over the value; its limit toward the darkest value where `p` is 0.
    fn factor(self, p: f64) -> f64 {
        let p = p.max(1e-12);
        self.undo(p) / p
    }

    /// The light of a pixel whose values before the screen's power were
    /// `before`, the shoulder (of scale `scale`) undone over its
    /// luminance, and the factor that took its channels there.
    fn undo_over_luminance(self, scale: f64, before: [f64; 3]) -> ([f64; 3], f64) {
        let k = scale * self.factor(luminance_of(before));
        (before.map(|c| c * k), k)
    }
}

impl Curve {
    /// Clamping alone: the value is the light.
    pub const CLAMPING: Curve = Curve::power(1.0);

    /// A power alone, with no shoulder.
    pub const fn power(gamma: f64) -> Curve {
        Curve {
            gamma,
            shoulder: Shoulder::None,
            over: Over::Channels,
        }
    }

    /// The light one value was written from, the curve taken as on each
    /// channel alone: a pixel's luminance under either [`Over`], or a
    /// channel under [`Over::Channels`].
    fn linear(&self, v: f64) -> f64 {
        self.shoulder.scale() * self.shoulder.undo(v.powf(self.gamma))
    }

    /// The light a pixel `written` (each channel in [0, 1]) was written
    /// from.
    pub fn linear_pixel(&self, written: [f64; 3]) -> [f64; 3] {
        match self.over {
            Over::Channels => written.map(|v| self.linear(v)),
            Over::Luminance => {
                let before = written.map(|v| v.powf(self.gamma));
                (self.shoulder)
                    .undo_over_luminance(self.shoulder.scale(), before)
                    .0
            }
        }
    }

    /// The curve made ready to turn many 8-bit pixels back to light,
    /// made once for the process: a fit tries the same few hundred curves
    /// on every image, and each aspect reads every curve an image leaves
    /// open ([`Fitted::plausible`]). The curves tried are a grid, so the
    /// made ones are few.
    pub fn linearise(&self) -> Arc<Linearised> {
        type Made = Mutex<HashMap<[u64; 4], Arc<Linearised>>>;
        static MADE: LazyLock<Made> = LazyLock::new(Made::default);
        let made = || MADE.lock().unwrap_or_else(PoisonError::into_inner);
        let key = self.key();
        let found = made().get(&key).cloned();
        found.unwrap_or_else(|| {
            let tables = Arc::new(self.tables());
            made().entry(key).or_insert(tables).clone()
        })
    }

    /// The curve as bits, for [`Curve::linearise`]'s tables.
    fn key(&self) -> [u64; 4] {
        let (kind, m) = match self.shoulder {
            Shoulder::None => (0, 0.0),
            Shoulder::Exposure(m) => (1, m),
            Shoulder::Reinhard(m) => (2, m),
            Shoulder::Aces(m) => (3, m),
        };
        let over = u64::from(self.over == Over::Luminance);
        [self.gamma.to_bits(), kind, m.to_bits(), over]
    }

    /// [`Curve::linearise`]'s tables, worked out.
    fn tables(&self) -> Linearised {
        let raised: [f64; 256] =
            std::array::from_fn(|v| (f64::from(v as u8) / 255.0).powf(self.gamma));
        let table = match self.over {
            Over::Channels => {
                let scale = self.shoulder.scale();
                raised.map(|p| scale * self.shoulder.undo(p))
            }
            Over::Luminance => raised,
        };
        let mut linear = Linearised {
            curve: *self,
            table,
            back: [0.0; 256],
            scale: self.shoulder.scale(),
            power: 1.0 / self.gamma,
        };
        // A value's own factor is the same there and back: 1 will do.
        linear.back = table.map(|x| linear.written(1.0, x));
        linear
    }

    /// The value one light `x` is written as, the inverse of
    /// [`Curve::linear`].
    #[cfg(test)]
    fn value(&self, x: f64) -> f64 {
        self.writer()(x)
    }

    /// [`Curve::value`], its constants worked out once for a pass over
    /// many lights.
    fn writer(&self) -> impl Fn(f64) -> f64 {
        let (shoulder, scale, power) = (self.shoulder, self.shoulder.scale(), 1.0 / self.gamma);
        move |x| shoulder.redo(x / scale).clamp(0.0, 1.0).powf(power)
    }

    /// The pixel a light `x` is written as: the inverse of
    /// [`Curve::linear_pixel`].
    pub fn value_pixel(&self, x: [f64; 3]) -> [f64; 3] {
        match self.over {
            Over::Channels => x.map(self.writer()),
            Over::Luminance => {
                let shoulder = self.shoulder;
                let before = x.map(|c| c / shoulder.scale());
                let k = 1.0 / shoulder.factor(shoulder.redo(luminance_of(before)));
                before.map(|c| (c * k).clamp(0.0, 1.0).powf(1.0 / self.gamma))
            }
        }
    }

    /// The curve in words, for the report; `None` for clamping alone.
    pub fn words(&self) -> Option<String> {
        let power = format!("a power of {:.2}", self.gamma);
        let over = match self.over {
            Over::Channels => "",
            Over::Luminance => " on each pixel's luminance, its hue kept,",
        };
        match self.shoulder {
            Shoulder::None if *self == Curve::CLAMPING => None,
            Shoulder::None => Some(format!("your tone curve reads as {power}")),
            Shoulder::Exposure(m) => Some(format!(
                "your tone curve reads as an exposure (strength {m:.2}){over} then {power}"
            )),
            Shoulder::Reinhard(m) => Some(format!(
                "your tone curve reads as Reinhard's (strength {m:.2}){over} then {power}"
            )),
            Shoulder::Aces(m) => Some(format!(
                "your tone curve reads as ACES's filmic curve (strength {m:.2}){over} then {power}"
            )),
        }
    }
}

/// A [`Curve`] made ready for a pass over many 8-bit pixels: each value's
/// light (or, under [`Over::Luminance`], each value before the screen's
/// power, the factor of its pixel's luminance yet to come), and each
/// value written back from it.
pub(super) struct Linearised {
    curve: Curve,
    table: [f64; 256],
    /// Each value there and back: the value its light is written as (its
    /// pixel's factor held), the same as the value but for the curve's
    /// rounding.
    back: [f64; 256],
    /// The shoulder's scale ([`Shoulder::scale`]).
    scale: f64,
    /// The inverse of the screen's power.
    power: f64,
}

impl Linearised {
    /// The light the 8-bit pixel `p` was written from.
    pub fn pixel(&self, p: [u8; 3]) -> [f64; 3] {
        self.pixel_and_factor(p).0
    }

    /// The light the 8-bit pixel `p` was written from, and under
    /// [`Over::Luminance`] what its values before the screen's power
    /// were multiplied by to give it (1 otherwise).
    fn pixel_and_factor(&self, p: [u8; 3]) -> ([f64; 3], f64) {
        let before = p.map(|v| self.table[usize::from(v)]);
        match self.curve.over {
            Over::Channels => (before, 1.0),
            Over::Luminance => (self.curve.shoulder).undo_over_luminance(self.scale, before),
        }
    }

    /// The value a channel of a pixel whose factor is `k`
    /// ([`Linearised::pixel_and_factor`]) would be written as, had its
    /// light been `x`.
    fn written(&self, k: f64, x: f64) -> f64 {
        match self.curve.over {
            Over::Channels => self.curve.shoulder.redo(x / self.scale),
            Over::Luminance => x / k,
        }
        .clamp(0.0, 1.0)
        .powf(self.power)
    }

    /// The 8-bit value `v` there and back.
    fn written_back(&self, v: u8) -> f64 {
        self.back[usize::from(v)]
    }
}

/// The powers tried: from 0.8 to 3 in steps of 0.05, which covers
/// clamping (1), the screen gammas of 1.8 to 2.4, and a square root (2).
fn powers() -> impl Iterator<Item = f64> {
    (16..=60).map(|k| f64::from(k) * 0.05)
}

/// The shoulders tried besides none: each kind at strengths from a
/// gentle compression to nearly the full curve, over each channel and
/// over a pixel's luminance; ACES's over each channel, as it is written.
fn shoulders() -> impl Iterator<Item = (Shoulder, Over)> {
    const STRENGTHS: [f64; 6] = [0.25, 0.5, 0.75, 0.9, 0.97, 0.99];
    STRENGTHS
        .into_iter()
        .flat_map(|m| [Shoulder::Exposure(m), Shoulder::Reinhard(m)])
        .flat_map(|shoulder| [Over::Channels, Over::Luminance].map(|over| (shoulder, over)))
        .chain(STRENGTHS.map(|m| (Shoulder::Aces(m), Over::Channels)))
}

/// The share of what clamping alone leaves unexplained that another
/// curve must leave less than to be read into the image: a curve's gain
/// over clamping is small where the light varies little
/// (tests/students/tune's gamma 2.2 left 0.77 of what 1 leaves on
/// field/texture.scene, whose only lit object is a mirror), and its
/// correct readings' best curves left 0.94 and more.
const KEEP_CLAMPING: f64 = 0.9;

/// The largest share of the image's spread a curve may leave unexplained
/// and still be read into it: lines that leave more explain less than
/// three quarters of its variance, so something other than a tone curve
/// shapes the image there (a bug that darkens lit points at random, say),
/// and a curve chosen over them would bend to it. Chosen on tune and
/// judge (docs/grading.md): their correct readings' first fits left at
/// most 0.31, their shadow acne up to 1.0.
const EXPLAINED: f64 = 0.5;

/// The least root-mean-square spread, as written, of an object that
/// tells the curve: three 8-bit steps. Below it the object's values vary
/// by rounding alone (an object no light of the student's reaches, say),
/// every curve leaves its rounding, and its share of the spread says
/// nothing of the curve. The robust fit's bound is the same: rounding
/// alone is never an outlier ([`super::fit::outlier_bound`]); and so is
/// the least spread of what a mirror shows that tells its gain on it
/// ([`super::reflection`]).
pub(super) const FLAT: f64 = 3.0 / 255.0;

/// The luminance of a colour in linear light, each channel in [0, 1].
pub(super) fn luminance_of(c: [f64; 3]) -> f64 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// One pixel that tells the curve: the student's 8-bit colour there, and
/// what ours sees (the light that reaches the point, and on a mirror the
/// colour and the light of what it shows, [`Probe::shown`]).
///
/// [`Probe::shown`]: raytracer_render::render::probe::Probe::shown
pub(super) type Row = ([u8; 3], [f64; 3]);

/// What a group's fit reads of the student's pixels: their luminance, or
/// one channel (the curve is shared by the channels, so each must follow
/// it over its own range: a saturated colour's channels lie far apart on
/// the curve, where the luminance sees one of them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Reads {
    Luminance,
    Channel(usize),
}

impl Reads {
    /// What this reads of a colour.
    fn of(self, c: [f64; 3]) -> f64 {
        match self {
            Reads::Luminance => luminance_of(c),
            Reads::Channel(k) => c[k],
        }
    }
}

/// The rows of one object (or one channel of it) fitted by one line.
pub(super) type Group = (Reads, Vec<Row>);

/// The fitted curve of the student's image from the rows of each object
/// that tells, by kind ([`super::evidence::Evidence::tone_rows`]): the
/// plain objects' alone when they tell a screen's curve from clamping
/// (a mirror's brightness also holds what it shows, which a bug of the
/// tracer's reflection changes, and a textured object's the texels the
/// student's mapping reads), else every object's, with the mirrors' and
/// the `textured` objects'.
pub(super) fn fit(plain: &[Group], mirrors: &[Group], textured: &dyn Fn() -> Vec<Group>) -> Fitted {
    if tells(plain) {
        return decide(plain);
    }
    let every: Vec<Group> = plain
        .iter()
        .chain(mirrors)
        .cloned()
        .chain(textured())
        .collect();
    decide(&every)
}

/// Whether `objects` tell clamping alone from a screen's curve (a power
/// of 2.2): one leaves less than [`KEEP_CLAMPING`] of what the other
/// leaves.
fn tells(objects: &[Group]) -> bool {
    let screen = Curve::power(2.2);
    let spreads = Spreads::of(objects);
    match (
        unexplained(objects, &spreads, Curve::CLAMPING, f64::INFINITY),
        unexplained(objects, &spreads, screen, f64::INFINITY),
    ) {
        (Some(a), Some(b)) => a.min(b) < KEEP_CLAMPING * a.max(b),
        _ => false,
    }
}

/// What a fit's residuals are measured against, the same under every
/// curve, so made once for all: each group's values as written, each as
/// its distance from the group's mean (`None` for a group whose values
/// hardly vary, [`FLAT`], which tells no curve), and the root mean square
/// of all of them and their number.
struct Spreads {
    each: Vec<Option<Vec<f64>>>,
    all: f64,
    count: usize,
}

impl Spreads {
    fn of(objects: &[Group]) -> Spreads {
        let each: Vec<Option<Vec<f64>>> = objects
            .iter()
            .map(|(reads, group)| {
                let written: Vec<f64> = group
                    .iter()
                    .map(|(p, _)| reads.of(p.map(|c| f64::from(c) / 255.0)))
                    .collect();
                let mean = written.iter().sum::<f64>() / written.len() as f64;
                let spread: Vec<f64> = written.iter().map(|w| (w - mean).abs()).collect();
                (root_mean_square(&spread) >= FLAT).then_some(spread)
            })
            .collect();
        let all: Vec<f64> = each.iter().flatten().flatten().copied().collect();
        Spreads {
            all: root_mean_square(&all),
            count: all.len(),
            each,
        }
    }
}

/// The share of the image's spread the fits of `objects` leave
/// unexplained under `curve`, each group's spread being its [`Spreads`];
/// `None` when nothing varies or no fit, or once the share is sure to be
/// over `above`. The residuals' sum of squares only grows, group by
/// group, so a curve that will lose to one already tried is given up as
/// soon as it has, and its share is not worked out to the end.
fn unexplained(objects: &[Group], spreads: &Spreads, curve: Curve, above: f64) -> Option<f64> {
    if spreads.all <= 0.0 {
        return None;
    }
    // The sum of squares past which the share is over `above`, with room
    // for rounding: a curve is never given up that could be at it.
    let given_up = (above * spreads.all).powi(2) * spreads.count as f64 * (1.0 + 1e-9);
    let linear = curve.linearise();
    let value = curve.writer();
    let mut squares = 0.0;
    for ((reads, group), spread) in objects.iter().zip(&spreads.each) {
        if spread.is_none() {
            continue;
        }
        let (rows, factors): (Vec<([f64; 3], f64)>, Vec<f64>) = group
            .iter()
            .map(|&(p, x)| {
                let (light, k) = linear.pixel_and_factor(p);
                ((x, reads.of(light)), k)
            })
            .unzip();
        let beta = robust_fit(&rows)?;
        // Each residual taken back to the student's 8-bit scale, the
        // value the line's light is written as against the value
        // written there and back, where every curve's rounding is the
        // same.
        for (((x, y), (p, _)), &k) in rows.iter().zip(group).zip(&factors) {
            let line = predict(&beta, x).max(0.0);
            let residual = match reads {
                Reads::Channel(c) => (linear.written(k, line) - linear.written_back(p[*c])).abs(),
                Reads::Luminance => (value(line) - value(*y)).abs(),
            };
            squares += residual * residual;
        }
        if squares > given_up {
            return None;
        }
    }
    // The root mean square residual over the values' spread: the share
    // of the image's spread the curve and lines leave.
    Some((squares / spreads.count as f64).sqrt() / spreads.all)
}

/// The curve `objects` choose, each freedom kept only when it earns its
/// place as a curve does over clamping: a power other than 1 when it
/// leaves less than [`KEEP_CLAMPING`] of what clamping leaves, and a
/// shoulder when it leaves less than that share of what the power alone
/// leaves; either only when it leaves less than [`EXPLAINED`]. The powers
/// are tried alone in fine steps; with each shoulder, in steps of 0.2
/// first and then in fine steps around that shoulder's best. With it,
/// every curve tried that the best fit does not beat by that same share
/// ([`Fitted::alike`]).
fn decide(objects: &[Group]) -> Fitted {
    let spreads = Spreads::of(objects);
    let mut tried: Vec<(Curve, f64)> = Vec::new();
    let mut least_tried = f64::INFINITY;
    // The best of `curves` that beats `bar`, if any. A curve that loses
    // both to the best of them so far (or `bar`) and to what the best fit
    // may be alike to ([`Fitted::alike`]) is given up early: it could be
    // neither.
    let mut scored = |curves: &mut dyn Iterator<Item = Curve>, bar: f64| {
        let mut best: Option<(Curve, f64)> = None;
        for curve in curves {
            let beaten = best.map_or(bar, |(_, left)| left);
            let above = beaten.max(least_tried / KEEP_CLAMPING);
            if let Some(left) = unexplained(objects, &spreads, curve, above) {
                tried.push((curve, left));
                least_tried = least_tried.min(left);
                if left < beaten {
                    best = Some((curve, left));
                }
            }
        }
        best
    };
    let Some((best_power, power_left)) = scored(&mut powers().map(Curve::power), f64::INFINITY)
    else {
        return Fitted::NONE;
    };
    // Each shoulder at coarse powers, then each in fine steps around its
    // own best: a power and a shoulder's strength trade against each
    // other along a valley (most of all over a pixel's luminance, whose
    // channels share one shape), and every point of it the image cannot
    // tell from the best must be tried to be among the curves alike.
    let coarse: Vec<(Curve, f64)> = shoulders()
        .filter_map(|(shoulder, over)| {
            let mut at = powers().step_by(4).map(|gamma| Curve {
                gamma,
                shoulder,
                over,
            });
            scored(&mut at, f64::INFINITY)
        })
        .collect();
    // The coarse best is among its fine steps, tried already.
    let shouldered = coarse
        .iter()
        .map(|&(c, left)| {
            let mut around = powers()
                .filter(|g| (g - c.gamma).abs() < 0.16 && *g != c.gamma)
                .map(|gamma| Curve { gamma, ..c });
            scored(&mut around, left).unwrap_or((c, left))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1));
    let earns = |left: f64, before: f64| left < KEEP_CLAMPING * before && left < EXPLAINED;
    let mut curve = match unexplained(objects, &spreads, Curve::CLAMPING, f64::INFINITY) {
        Some(left) if !earns(power_left, left) => Curve::CLAMPING,
        _ => best_power,
    };
    let mut least = power_left;
    if let Some((with_shoulder, left)) = shouldered {
        least = least.min(left);
        if earns(left, power_left) {
            curve = with_shoulder;
        }
    }
    let alike = if least < EXPLAINED {
        tried
            .iter()
            .filter(|&&(c, left)| c != curve && least >= KEEP_CLAMPING * left)
            .map(|&(c, _)| c)
            .collect()
    } else {
        Vec::new()
    };
    Fitted {
        curve,
        unexplained: Some(least),
        alike,
    }
}

/// The fitted curve, and the least share of the image's spread a curve
/// leaves unexplained: how well what ours sees explains the image at all.
pub(super) struct Fitted {
    pub curve: Curve,
    pub unexplained: Option<f64>,
    /// Every other curve tried that the best fit does not beat by the
    /// share a freedom must earn ([`KEEP_CLAMPING`]): the readings the
    /// image cannot tell from the chosen one. None when no curve explains
    /// the image ([`EXPLAINED`]).
    alike: Vec<Curve>,
}

impl Fitted {
    /// Nothing fitted: the image read as written.
    pub const NONE: Fitted = Fitted {
        curve: Curve::CLAMPING,
        unexplained: None,
        alike: Vec::new(),
    };

    /// The chosen curve, then every curve the image cannot tell from it.
    pub fn plausible(&self) -> impl Iterator<Item = Curve> + '_ {
        std::iter::once(self.curve).chain(self.alike.iter().copied())
    }
}

/// The root mean square of `values`; 0 for none.
fn root_mean_square(values: &[f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    (values.iter().map(|v| v * v).sum::<f64>() / values.len() as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::{fit, powers, unexplained, Curve, Group, Over, Reads, Row, Shoulder, Spreads};

    /// An object whose light runs from 0.05 to 0.85, written through
    /// `curve` after `0.05 + 0.8·x`.
    fn written(curve: &dyn Fn(f64) -> f64) -> Group {
        written_over(curve, 0.05, 0.85)
    }

    /// The same with the light running from `least` to `most`.
    fn written_over(curve: &dyn Fn(f64) -> f64, least: f64, most: f64) -> Group {
        let rows = (0..200)
            .map(|i| {
                let lit = least + (most - least) * f64::from(i) / 200.0;
                let v = (255.0 * curve(0.05 + 0.8 * lit)).round() as u8;
                ([v, v, v], [lit, 0.0, 0.0])
            })
            .collect();
        (Reads::Luminance, rows)
    }

    /// The same through `v = x^(1/γ)`.
    fn object(gamma: f64) -> Group {
        written(&|x| x.powf(1.0 / gamma))
    }

    /// The largest distance, in 8-bit values, of `rows` read back through
    /// `curve` from the best line through them.
    fn misfit(curve: Curve, (_, rows): &Group) -> f64 {
        let xy: Vec<(f64, f64)> = rows
            .iter()
            .map(|(p, x)| (x[0], curve.linear(f64::from(p[0]) / 255.0)))
            .collect();
        let (first, last) = (xy[0], xy[xy.len() - 1]);
        let slope = (last.1 - first.1) / (last.0 - first.0);
        xy.iter()
            .map(|&(x, y)| {
                let line = first.1 + slope * (x - first.0);
                255.0 * (curve.value(line.max(0.0)) - curve.value(y)).abs()
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn a_curve_is_given_up_only_past_its_bar() {
        // Two objects, so the second is not looked at once the first has
        // left more than the bar allows.
        let objects = [object(2.2), object(2.2)];
        let spreads = Spreads::of(&objects);
        let share = |curve, above| unexplained(&objects, &spreads, curve, above);
        let clamping = share(Curve::CLAMPING, f64::INFINITY).unwrap();
        let screen = share(Curve::power(2.2), f64::INFINITY).unwrap();
        assert!(screen < 0.5 * clamping, "{screen} {clamping}");
        // At its own share, or past it, a curve is worked out to the end.
        assert_eq!(share(Curve::CLAMPING, clamping), Some(clamping));
        assert_eq!(share(Curve::CLAMPING, 2.0 * clamping), Some(clamping));
        // Below it (at the better curve's share, say), it is given up.
        assert_eq!(share(Curve::CLAMPING, screen), None);
        assert_eq!(share(Curve::power(2.2), screen), Some(screen));
    }

    #[test]
    fn a_screen_gamma_is_read_and_clamping_alone_is_kept() {
        let screen = fit(&[object(2.2)], &[], &Vec::new);
        assert!(
            (screen.curve.gamma - 2.2).abs() <= 0.1,
            "{:?}",
            screen.curve
        );
        assert_eq!(screen.curve.shoulder, Shoulder::None);
        assert_eq!(fit(&[object(1.0)], &[], &Vec::new).curve, Curve::CLAMPING);
    }

    #[test]
    fn curves_that_are_no_power_are_read_back_to_a_straight_light() {
        let srgb = |x: f64| {
            if x <= 0.003_130_8 {
                12.92 * x
            } else {
                1.055 * x.powf(1.0 / 2.4) - 0.055
            }
        };
        let exposure = |x: f64| 1.0 - (-2.0 * x).exp();
        let reinhard = |x: f64| 1.5 * x / (1.0 + 1.5 * x);
        let exposure_then_screen = |x: f64| (1.0 - (-x).exp()).powf(1.0 / 2.2);
        // ACES's filmic curve as games write it (Narkowicz's fit), with
        // its toe, after an exposure of 0.8.
        let filmic = |x: f64| super::aces(0.8 * x);
        for (name, curve) in [
            ("srgb", &srgb as &dyn Fn(f64) -> f64),
            ("exposure", &exposure),
            ("reinhard", &reinhard),
            ("exposure then screen", &exposure_then_screen),
            ("aces", &filmic),
        ] {
            let rows = written(curve);
            let fitted = fit(std::slice::from_ref(&rows), &[], &Vec::new).curve;
            let off = misfit(fitted, &rows);
            assert!(off < 1.5, "{name}: {fitted:?} leaves {off:.2} of 255");
            // Clamping alone reads none of them straight.
            assert!(misfit(Curve::CLAMPING, &rows) > 5.0, "{name}");
        }
    }

    #[test]
    fn the_channels_of_a_saturated_colour_tell_a_curve() {
        // An orange object (1, 0.3, 0.1) under a light from 0.45 to 0.85,
        // written through an exposure: each channel lies on its own
        // stretch of the curve, and the luminance (mostly green) on a
        // stretch where the curve is nearly straight.
        let albedo = [1.0, 0.3, 0.1];
        let exposure = |x: f64| (255.0 * (1.0 - (-2.0 * x).exp())).round() as u8;
        let rows: Vec<Row> = (0..200)
            .map(|i| {
                let lit = 0.45 + 0.4 * f64::from(i) / 200.0;
                (albedo.map(|a| exposure(a * (0.1 + lit))), [lit, 0.0, 0.0])
            })
            .collect();
        let channels: Vec<Group> = (0..3).map(|c| (Reads::Channel(c), rows.clone())).collect();
        let fitted = fit(&channels, &[], &Vec::new).curve;
        for c in 0..3 {
            let one: Group = (
                Reads::Luminance,
                rows.iter().map(|(p, x)| ([p[c]; 3], *x)).collect(),
            );
            let off = misfit(fitted, &one);
            assert!(off < 1.5, "channel {c}: {fitted:?} leaves {off:.2} of 255");
        }
    }

    #[test]
    fn a_narrow_light_leaves_the_curve_open() {
        // A grey object under little spread of light, written through
        // Reinhard's curve: a power fits it about as well, and both are
        // among the curves the image cannot tell apart.
        let reinhard = |x: f64| 2.0 * x / (1.0 + 2.0 * x);
        let narrow = fit(&[written_over(&reinhard, 0.3, 0.6)], &[], &Vec::new);
        let plausible: Vec<Curve> = narrow.plausible().collect();
        let reinhards = plausible
            .iter()
            .filter(|c| matches!(c.shoulder, Shoulder::Reinhard(_)))
            .count();
        let powers = plausible
            .iter()
            .filter(|c| c.shoulder == Shoulder::None)
            .count();
        assert!(reinhards > 0 && powers > 0, "{plausible:?}");
        assert!(!narrow.alike.contains(&narrow.curve));
        // Over a wide light, clamping is not among them.
        let wide = fit(&[written(&reinhard)], &[], &Vec::new);
        let wide_plausible: Vec<Curve> = wide.plausible().collect();
        assert!(
            !wide_plausible.contains(&Curve::CLAMPING),
            "{wide_plausible:?}"
        );
        assert!(wide_plausible.len() < plausible.len());
    }

    #[test]
    fn points_a_bug_leaves_unlit_bend_no_curve() {
        // Clamping alone, with every other point left at its ambient
        // light (a shadow ray that stops short of nothing, say): no
        // light of ours explains the pattern, and no curve may be read
        // from it, nor from an object no light reaches at all.
        let rows = (0..200)
            .map(|i| {
                let lit = 0.05 + 0.8 * f64::from(i) / 200.0;
                let shown = if i % 2 == 0 { 0.05 } else { 0.05 + 0.8 * lit };
                let v = (255.0 * shown).round() as u8;
                ([v, v, v], [lit, 0.0, 0.0])
            })
            .collect();
        let half_lit: Group = (Reads::Luminance, rows);
        let fitted = fit(&[half_lit], &[], &Vec::new);
        assert_eq!(fitted.curve, Curve::CLAMPING, "{:?}", fitted.unexplained);
        let unlit = written_over(&|_| 0.05, 0.05, 0.85);
        assert_eq!(fit(&[unlit], &[], &Vec::new).curve, Curve::CLAMPING);
    }

    /// The tables a curve makes once for the process hold, bit for bit,
    /// the light of each value and that light written back (with its
    /// pixel's factor held at 1), as the curve works them out one value
    /// at a time, on two powers tried and one off the grid.
    #[test]
    fn a_curves_tables_hold_its_own_values() {
        let shoulders = [
            Shoulder::None,
            Shoulder::Exposure(0.75),
            Shoulder::Reinhard(0.97),
            Shoulder::Aces(0.5),
        ];
        for gamma in [powers().next().unwrap(), 2.2, 1.0 / 0.45] {
            for shoulder in shoulders {
                for over in [Over::Channels, Over::Luminance] {
                    let curve = Curve {
                        gamma,
                        shoulder,
                        over,
                    };
                    let linearised = curve.linearise();
                    for v in 0..=255u8 {
                        let x = f64::from(v) / 255.0;
                        let table = match over {
                            Over::Channels => curve.linear(x),
                            Over::Luminance => x.powf(gamma),
                        };
                        let back = match over {
                            Over::Channels => curve.value(table),
                            Over::Luminance => table.clamp(0.0, 1.0).powf(1.0 / gamma),
                        };
                        let (a, b) = (
                            linearised.table[usize::from(v)],
                            linearised.back[usize::from(v)],
                        );
                        assert_eq!(a.to_bits(), table.to_bits(), "{curve:?} at {v}");
                        assert_eq!(b.to_bits(), back.to_bits(), "{curve:?} at {v}");
                    }
                }
            }
        }
    }

    #[test]
    fn a_curve_and_its_inverse_agree() {
        let shoulders = [
            Shoulder::None,
            Shoulder::Exposure(0.9),
            Shoulder::Reinhard(0.5),
            Shoulder::Aces(0.75),
        ];
        for shoulder in shoulders {
            for over in [Over::Channels, Over::Luminance] {
                let curve = Curve {
                    gamma: 1.8,
                    shoulder,
                    over,
                };
                let linearised = curve.linearise();
                for v in [0.01, 0.2, 0.5, 0.9, 1.0] {
                    let back = curve.value(curve.linear(v));
                    assert!((back - v).abs() < 1e-9, "{curve:?} at {v}: {back}");
                    let pixel = [v, 0.6 * v, 0.1];
                    let back = curve.value_pixel(curve.linear_pixel(pixel));
                    let off = (0..3)
                        .map(|c| (back[c] - pixel[c]).abs())
                        .fold(0.0, f64::max);
                    assert!(off < 1e-9, "{curve:?} at {pixel:?}: {back:?}");
                }
                let p = [200, 120, 30];
                let (a, b) = (
                    linearised.pixel(p),
                    curve.linear_pixel(p.map(|v| f64::from(v) / 255.0)),
                );
                assert!((0..3).all(|c| (a[c] - b[c]).abs() < 1e-12), "{a:?} {b:?}");
            }
        }
    }

    #[test]
    fn a_curve_on_luminance_is_read_with_its_hue_kept() {
        // An orange object under a light from 0.2 to 1.6, its colour
        // scaled by L/(1 + L) over its luminance L: each channel is
        // compressed by its pixel's luminance, not by its own value.
        let albedo = [1.0, 0.5, 0.2];
        let rows: Vec<Row> = (0..200)
            .map(|i| {
                let lit = 0.2 + 1.4 * f64::from(i) / 200.0;
                let x = albedo.map(|a| a * (0.1 + lit));
                let l = super::luminance_of(x);
                (
                    x.map(|c| (255.0 * (c / (1.0 + l)).min(1.0)).round() as u8),
                    [lit, 0.0, 0.0],
                )
            })
            .collect();
        let channels: Vec<Group> = (0..3).map(|c| (Reads::Channel(c), rows.clone())).collect();
        let fitted = fit(&channels, &[], &Vec::new);
        assert_eq!(fitted.curve.over, Over::Luminance, "{:?}", fitted.curve);
        // One object's hue does not tell the screen's power from the
        // shoulder's strength (its channels share one shape), so the
        // hue is read under some curve the image cannot tell from the
        // chosen one: under it, every pixel keeps the object's hue, red
        // to green.
        let keeps_hue = |curve: Curve| {
            let linear = curve.linearise();
            rows.iter().filter(|(p, _)| p[1] > 40).all(|(p, _)| {
                let x = linear.pixel(*p);
                (x[1] / x[0] - 0.5).abs() < 0.03
            })
        };
        assert!(fitted.plausible().any(keeps_hue));
    }

    #[test]
    fn plain_objects_that_tell_outvote_a_mirror() {
        // A mirror whose brightness bends (a bug of what it shows, say)
        // does not move the curve the plain objects tell.
        let fitted = fit(&[object(1.0)], &[object(2.2), object(2.2)], &Vec::new);
        assert_eq!(fitted.curve, Curve::CLAMPING);
        // With no plain object, the mirrors tell it.
        let fitted = fit(&[], &[object(2.2)], &Vec::new);
        assert!(
            (fitted.curve.gamma - 2.2).abs() <= 0.1,
            "{:?}",
            fitted.curve
        );
    }
}
