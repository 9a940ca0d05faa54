//! The light of the student's image, fitted once for the scene: how
//! bright each plain object is unlit (its intercept, for any ambient
//! term), how much a unit of our light brightens it (one gain for the
//! whole scene, as a tracer has one diffuse constant and our light
//! already holds each object's colour), and the falloff with distance
//! the assignment leaves open with the rest of its illumination model:
//! none, or a light that dims as `1/(1 + k·d̂ᵖ)` with the distance `d̂`
//! to the light (over the scene's mean distance, so a scene's scale
//! changes nothing), which with `p` of 1 or 2 and `k` from 1/16 to 64
//! covers linear, quadratic and nearly inverse-square falloff, and the
//! blends of them students write.
//!
//! The fit reads the pixels no shadow, highlight lobe or clamping
//! touches, and is robust to the rest (a bug's pixels, an edge). The
//! falloff whose fit leaves the least root-mean-square share of the
//! luminance's spread unexplained wins, as [`super::tone`] chooses a
//! curve; none is kept unless a falloff leaves less than [`KEEP_NONE`]
//! of what none leaves. One gain for every object is what keeps a bug
//! out of the fit: an object whose lit side a tracer darkens cannot get
//! a gain, or a falloff, of its own.

use super::fit::{outlier_bound, predict, robust_fit};
use raytracer_render::render::probe::Probe;

/// The share of none's unexplained spread a falloff must leave less
/// than to be read into the image: a falloff explains the light's
/// shape, not the rounding and the edges every fit leaves. Chosen on
/// tests/students/tune: its falloff left 0.07 to 0.71 of what none
/// leaves on the scenes that tell one; an image half a pixel off the
/// probes, 0.84 (docs/grading.md).
const KEEP_NONE: f64 = 0.75;

/// A tracer's falloff: the gain of a light at distance `d`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Falloff {
    /// `(p, k)` of `1/(1 + k·(d/scale)ᵖ)`; `None` for no falloff.
    shape: Option<(i32, f64)>,
    /// The scene's mean distance from a lit point to its lights.
    scale: f64,
}

impl Falloff {
    /// No falloff: every light's gain is 1.
    pub const NONE: Falloff = Falloff {
        shape: None,
        scale: 1.0,
    };

    /// The gain of a light `distance` away.
    pub fn gain(&self, distance: f64) -> f64 {
        match self.shape {
            None => 1.0,
            Some((p, k)) => 1.0 / (1.0 + k * (distance / self.scale).powi(p)),
        }
    }

    /// The light that reaches `probe`'s point, each light dimmed by its
    /// distance.
    pub fn lit(&self, probe: &Probe) -> f64 {
        probe
            .lights
            .iter()
            .filter(|l| l.reaches)
            .map(|l| l.lit * self.gain(l.distance))
            .sum()
    }

    /// The light of the scene's first two lights that reach `probe`'s
    /// point, and of the others together, each dimmed by its distance.
    pub fn shares(&self, probe: &Probe) -> [f64; 3] {
        let mut shares = [0.0; 3];
        for l in probe.lights.iter().filter(|l| l.reaches) {
            shares[l.light.min(2)] += l.lit * self.gain(l.distance);
        }
        shares
    }

    /// The same as [`Falloff::lit`], were nothing in the way.
    pub fn unshadowed(&self, probe: &Probe) -> f64 {
        probe
            .lights
            .iter()
            .map(|l| l.lit * self.gain(l.distance))
            .sum()
    }

    /// The falloff in words, for the report; `None` for none.
    pub fn words(&self) -> Option<String> {
        self.shape.map(|(p, k)| {
            let power = if p == 1 { "d" } else { "d²" };
            format!(
                "light falling off as 1/(1 + {:.3}·{power}) with distance d",
                k / self.scale.powi(p)
            )
        })
    }

    /// Every falloff tried: none, then [`Falloff::candidates`], at the
    /// scene's mean distance `scale` from a lit point to its lights.
    pub fn tried(scale: f64) -> impl Iterator<Item = Falloff> {
        std::iter::once(Falloff::NONE).chain(Falloff::candidates(scale))
    }

    /// The falloffs tried besides none.
    fn candidates(scale: f64) -> impl Iterator<Item = Falloff> {
        [1, 2].into_iter().flat_map(move |p| {
            (-4..=6).map(move |j| Falloff {
                shape: Some((p, 2f64.powi(j))),
                scale,
            })
        })
    }
}

/// The scene's light fit: brightness `a_o + gain·lit` on each plain
/// object `o`, `lit` under [`LightFit::falloff`].
#[derive(Clone, Debug)]
pub(super) struct LightFit {
    pub falloff: Falloff,
    pub gain: f64,
    /// Each fitted object's id and intercept.
    pub intercepts: Vec<(u32, f64)>,
    /// The other falloffs tried (none among them) that the chosen one
    /// does not beat by the share a falloff must earn ([`KEEP_NONE`]):
    /// those the image cannot tell from it.
    alike: Vec<Falloff>,
}

impl LightFit {
    /// The chosen falloff, then every falloff the image cannot tell
    /// from it.
    pub fn plausible(&self) -> impl Iterator<Item = Falloff> + '_ {
        std::iter::once(self.falloff).chain(self.alike.iter().copied())
    }

    /// The intercept of `object`, when it was fitted.
    pub fn intercept(&self, object: u32) -> Option<f64> {
        self.intercepts
            .iter()
            .find(|(o, _)| *o == object)
            .map(|(_, a)| *a)
    }

    /// The gain, at least 5 % (a fit of a nearly unlit scene can say
    /// nothing of its light).
    pub fn least_gain(&self) -> f64 {
        self.gain.max(0.05)
    }

    /// Whether luminance `s` at `probe` (a point of a fitted object that
    /// ours lights) looks shadowed: darker than the fit by more than half
    /// the light that reaches it, and by more than 4 of 255.
    pub fn looks_shadowed(&self, object: u32, probe: &Probe, s: f64) -> Option<bool> {
        let a = self.intercept(object)?;
        let light = self.least_gain() * self.falloff.lit(probe);
        let r = s - (a + light);
        Some(r < -0.5 * light && r < -4.0 / 255.0)
    }
}

/// One object's pixels that tell the fit: its id, and each pixel's probe
/// and the student's luminance there in linear light
/// ([`super::evidence::Evidence::light_groups`]).
pub(super) type Group<'a> = (u32, Vec<(&'a Probe, f64)>);

/// One object's pixels as points of its line: its id, and each pixel's
/// light under a falloff (`x`) with the student's luminance there (`y`).
pub(super) type Points = (u32, Vec<(f64, f64)>);

/// `groups`' pixels as points of their lines under `falloff`.
fn points(groups: &[Group], falloff: Falloff) -> Vec<Points> {
    groups
        .iter()
        .map(|(object, rows)| {
            (
                *object,
                rows.iter().map(|(p, y)| (falloff.lit(p), *y)).collect(),
            )
        })
        .collect()
}

/// The robust least-squares fit of `y = a_o + gain·x` over `groups`
/// (their points under `falloff`): least squares, then again without the
/// points whose residual is over three times the median one, twice. With
/// the share of the spread it leaves unexplained; `None` when no
/// object's light varies.
fn fit_under(groups: &[&Points], falloff: Falloff) -> Option<(LightFit, f64)> {
    let xs: Vec<&[(f64, f64)]> = groups.iter().map(|(_, g)| g.as_slice()).collect();
    let mut keep: Vec<Vec<bool>> = xs.iter().map(|g| vec![true; g.len()]).collect();
    let mut fit = least_squares(&xs, &keep)?;
    let mut residuals = Vec::with_capacity(keep.iter().map(Vec::len).sum());
    for _ in 0..2 {
        let residual = |o: usize, (x, y): (f64, f64)| y - (fit.1[o] + fit.0 * x);
        residuals.clear();
        for (o, g) in xs.iter().enumerate() {
            residuals.extend(g.iter().map(|&r| residual(o, r).abs()));
        }
        let bound = outlier_bound(&mut residuals);
        for (o, (g, k)) in xs.iter().zip(&mut keep).enumerate() {
            for (&r, k) in g.iter().zip(k) {
                *k = residual(o, r).abs() <= bound;
            }
        }
        match least_squares(&xs, &keep) {
            Some(better) => fit = better,
            None => break,
        }
    }
    let (gain, intercepts) = fit;
    let (mut residual, mut total) = (0.0, 0.0);
    for (o, g) in xs.iter().enumerate() {
        let mean = g.iter().map(|r| r.1).sum::<f64>() / g.len() as f64;
        for &(x, y) in *g {
            residual += (y - (intercepts[o] + gain * x)).powi(2);
            total += (y - mean).powi(2);
        }
    }
    let light = LightFit {
        falloff,
        gain,
        intercepts: groups.iter().map(|(o, _)| *o).zip(intercepts).collect(),
        alike: Vec::new(),
    };
    (total > 0.0).then(|| (light, (residual / total).sqrt()))
}

/// One object's own gain, over the scene's ([`object_gains`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct ObjectGain {
    pub object: u32,
    /// The object's gain over the scene's.
    pub ratio: f64,
    /// The standard error of `ratio`, from the scatter of the object's
    /// pixels about its own line (their rounding, mostly).
    pub error: f64,
}

/// Each object's own gain (`y = a + g·x` fitted on its points alone,
/// robustly) over the scene's one gain, both under `falloff`, the one
/// `groups`' points were taken under. Every reading the assignment
/// leaves open keeps it at 1: a tracer has one diffuse constant and one
/// falloff, and our light already holds each object's colour and each
/// point's angle to the light. A normal or a light vector left
/// unnormalised does not: it scales each object's light by its radius
/// or its distance. An object whose own gain is not above 0 by
/// [`SIGNIFICANT`] errors shows no light at all, which is shadows' to
/// judge: it is left out, of the scene's gain too. Empty when the
/// scene's gain is below [`LightFit::least_gain`]'s floor (a nearly
/// unlit scene).
pub(super) fn object_gains(groups: &[Points], falloff: Falloff) -> Vec<ObjectGain> {
    let own: Vec<(usize, f64, f64)> = groups
        .iter()
        .enumerate()
        .filter_map(|(i, (_, rows))| {
            let (gain, error) = own_gain(rows)?;
            (gain > SIGNIFICANT * error).then_some((i, gain, error))
        })
        .collect();
    let lit: Vec<&Points> = own.iter().map(|&(i, ..)| &groups[i]).collect();
    let Some((scene, _)) = fit_under(&lit, falloff) else {
        return Vec::new();
    };
    if scene.gain < scene.least_gain() {
        return Vec::new();
    }
    own.iter()
        .map(|&(i, gain, error)| ObjectGain {
            object: groups[i].0,
            ratio: gain / scene.gain,
            error: error / scene.gain,
        })
        .collect()
}

/// The most an object's own gain may differ from the scene's, as a
/// factor either way ([`object_gains`], and a textured object's scale of
/// its line, [`super::worn`]). The falloff is read from a grid
/// whose `k` doubles at each step, so the one read can be off by half a
/// step, √2; for two objects at half and at twice the scene's mean
/// distance from the light, that moves the ratio of their gains by up
/// to 1.23 (quadratic falloff; 1.12 linear).
pub(super) const GAIN_FACTOR: f64 = 1.25;

/// How far a gain ratio strays from 1, either way: `|ln ratio|`. A
/// ratio of 0 or below (an object darker where more light reaches it)
/// strays as far as a thousandfold.
pub(super) fn straying(ratio: f64) -> f64 {
    ratio.max(1e-3).ln().abs()
}

/// The standard errors by which a gain must differ from another (or
/// from 0) to differ at all: an object whose light hardly varies over it
/// tells its gain only loosely.
pub(super) const SIGNIFICANT: f64 = 3.0;

/// The gain of `rows` (one object's points) fitted alone, robustly, with
/// its standard error: from the scatter of the rows about their line,
/// and never less than rounding to 8 bits leaves (a flat object's rows
/// all round alike).
fn own_gain(rows: &[(f64, f64)]) -> Option<(f64, f64)> {
    let xs: Vec<([f64; 1], f64)> = rows.iter().map(|&(x, y)| ([x], y)).collect();
    let beta = robust_fit(&xs)?;
    let n = xs.len() as f64;
    let mean = xs.iter().map(|r| r.0[0]).sum::<f64>() / n;
    let spread: f64 = xs.iter().map(|r| (r.0[0] - mean).powi(2)).sum();
    let mut residuals: Vec<f64> = xs
        .iter()
        .map(|r| (r.1 - predict(&beta, &r.0)).abs())
        .collect();
    let middle = residuals.len() / 2;
    let (_, median, _) = residuals.select_nth_unstable_by(middle, f64::total_cmp);
    // The median absolute residual as a standard deviation, at least
    // the uniform rounding error of one 8-bit step.
    let scatter = (1.4826 * *median).max(1.0 / 255.0 / 12f64.sqrt());
    (spread > 0.0).then(|| (beta[1], scatter / spread.sqrt()))
}

/// Least squares of `y = a_o + gain·x` on the kept rows: the gain from
/// the rows taken from their object's means, then each intercept.
/// `None` when the light varies on no object.
fn least_squares(xs: &[&[(f64, f64)]], keep: &[Vec<bool>]) -> Option<(f64, Vec<f64>)> {
    let means: Vec<Option<(f64, f64)>> = xs
        .iter()
        .zip(keep)
        .map(|(g, k)| {
            let kept = || g.iter().zip(k).filter(|(_, k)| **k).map(|(r, _)| r);
            let n = kept().count();
            (n > 0).then(|| {
                let n = n as f64;
                (
                    kept().map(|r| r.0).sum::<f64>() / n,
                    kept().map(|r| r.1).sum::<f64>() / n,
                )
            })
        })
        .collect();
    let (mut xy, mut xx) = (0.0, 0.0);
    for ((g, k), mean) in xs.iter().zip(keep).zip(&means) {
        let Some((mx, my)) = mean else { continue };
        for (&(x, y), _) in g.iter().zip(k).filter(|(_, k)| **k) {
            xy += (x - mx) * (y - my);
            xx += (x - mx).powi(2);
        }
    }
    if xx < 1e-12 {
        return None;
    }
    let gain = xy / xx;
    let intercepts = xs
        .iter()
        .zip(&means)
        .map(|(g, mean)| match mean {
            Some((mx, my)) => my - gain * mx,
            // Every row of this object an outlier: its median.
            None => {
                let mut ys: Vec<f64> = g.iter().map(|r| r.1).collect();
                ys.sort_by(f64::total_cmp);
                ys[ys.len() / 2]
            }
        })
        .collect();
    Some((gain, intercepts))
}

/// The scene's light fit of the student's image from the pixels of each
/// plain object that tell it; `None` when none does.
pub(super) fn fit(groups: &[Group]) -> Option<LightFit> {
    let (weighed, lit) = groups
        .iter()
        .flat_map(|(_, rows)| rows)
        .flat_map(|(p, _)| p.lights.iter())
        .fold((0.0, 0.0), |(w, l), share| {
            (w + share.lit * share.distance, l + share.lit)
        });
    let under = |falloff: Falloff| {
        let points = points(groups, falloff);
        fit_under(&points.iter().collect::<Vec<_>>(), falloff)
    };
    let (none, unexplained) = under(Falloff::NONE)?;
    if lit <= 0.0 || weighed <= 0.0 {
        return Some(none);
    }
    let tried: Vec<(LightFit, f64)> = Falloff::candidates(weighed / lit)
        .filter_map(under)
        .collect();
    let best = tried.iter().min_by(|a, b| a.1.total_cmp(&b.1));
    let (mut chosen, least) = match best {
        Some((light, u)) if *u < KEEP_NONE * unexplained => (light.clone(), *u),
        _ => (none, unexplained),
    };
    chosen.alike = std::iter::once((Falloff::NONE, unexplained))
        .chain(tried.iter().map(|(light, u)| (light.falloff, *u)))
        .filter(|&(f, u)| f != chosen.falloff && KEEP_NONE * u <= least)
        .map(|(f, _)| f)
        .collect();
    Some(chosen)
}

#[cfg(test)]
mod tests {
    use super::{object_gains, points, Falloff, Group};
    use raytracer_render::render::probe::{LightShare, Probe};

    /// Probes of one light's share running from 0.1 to 0.9.
    fn probes() -> Vec<Probe> {
        (0..100)
            .map(|i| {
                let lit = 0.1 + 0.8 * f64::from(i) / 99.0;
                Probe {
                    object: Some(0),
                    lit,
                    unshadowed: lit,
                    lights: [LightShare {
                        light: 0,
                        lit,
                        distance: 1.0,
                        reaches: true,
                    }]
                    .into(),
                    ..Probe::default()
                }
            })
            .collect()
    }

    /// Object `object`'s rows, written as `ambient + gain·lit` rounded
    /// to 8 bits.
    fn object(probes: &[Probe], object: u32, ambient: f64, gain: f64) -> Group<'_> {
        let rows = probes
            .iter()
            .map(|p| (p, ((ambient + gain * p.lit) * 255.0).round() / 255.0))
            .collect();
        (object, rows)
    }

    #[test]
    fn an_object_with_a_gain_of_its_own_strays_and_one_lit_nowhere_is_left_out() {
        let probes = probes();
        let ratio = |groups: &[Group], object: u32| {
            object_gains(&points(groups, Falloff::NONE), Falloff::NONE)
                .iter()
                .find(|g| g.object == object)
                .map(|g| g.ratio)
        };
        let alike = [object(&probes, 0, 0.05, 0.6), object(&probes, 1, 0.1, 0.6)];
        for o in [0, 1] {
            let r = ratio(&alike, o).unwrap();
            assert!((r - 1.0).abs() < 0.01, "object {o}: {r}");
        }
        let unlit = object(&probes, 3, 0.1, 0.0);
        let doubled = [
            alike[0].clone(),
            alike[1].clone(),
            object(&probes, 2, 0.02, 1.2),
            unlit,
        ];
        let (a, b) = (ratio(&doubled, 0).unwrap(), ratio(&doubled, 2).unwrap());
        assert!((b / a - 2.0).abs() < 0.02, "{a} and {b}");
        assert_eq!(
            ratio(&doubled, 3),
            None,
            "an object lit nowhere is shadows'"
        );
    }
}
