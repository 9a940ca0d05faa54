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

use super::fit::outlier_bound;
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
    fn gain(&self, distance: f64) -> f64 {
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
}

impl LightFit {
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

/// The robust least-squares fit of `y = a_o + gain·x` over `groups`
/// (`x` each pixel's light under `falloff`): least squares, then again
/// without the pixels whose residual is over three times the median one,
/// twice. With the share of the spread it leaves unexplained; `None`
/// when no object's light varies.
fn fit_under(groups: &[Group], falloff: Falloff) -> Option<(LightFit, f64)> {
    let xs: Vec<Vec<(f64, f64)>> = groups
        .iter()
        .map(|(_, rows)| rows.iter().map(|(p, y)| (falloff.lit(p), *y)).collect())
        .collect();
    let mut keep: Vec<Vec<bool>> = xs.iter().map(|g| vec![true; g.len()]).collect();
    let mut fitted = None;
    for _ in 0..3 {
        let Some(fit) = least_squares(&xs, &keep) else {
            break;
        };
        let residual = |o: usize, (x, y): (f64, f64)| y - (fit.1[o] + fit.0 * x);
        let bound = outlier_bound(
            xs.iter()
                .enumerate()
                .flat_map(|(o, g)| g.iter().map(move |&r| residual(o, r).abs()))
                .collect(),
        );
        keep = xs
            .iter()
            .enumerate()
            .map(|(o, g)| g.iter().map(|&r| residual(o, r).abs() <= bound).collect())
            .collect();
        fitted = Some(fit);
    }
    let (gain, intercepts) = fitted?;
    let (mut residual, mut total) = (0.0, 0.0);
    for (o, g) in xs.iter().enumerate() {
        let mean = g.iter().map(|r| r.1).sum::<f64>() / g.len() as f64;
        for &(x, y) in g {
            residual += (y - (intercepts[o] + gain * x)).powi(2);
            total += (y - mean).powi(2);
        }
    }
    let light = LightFit {
        falloff,
        gain,
        intercepts: groups.iter().map(|(o, _)| *o).zip(intercepts).collect(),
    };
    (total > 0.0).then(|| (light, (residual / total).sqrt()))
}

/// Least squares of `y = a_o + gain·x` on the kept rows: the gain from
/// the rows taken from their object's means, then each intercept.
/// `None` when the light varies on no object.
fn least_squares(xs: &[Vec<(f64, f64)>], keep: &[Vec<bool>]) -> Option<(f64, Vec<f64>)> {
    let means: Vec<Option<(f64, f64)>> = xs
        .iter()
        .zip(keep)
        .map(|(g, k)| {
            let kept: Vec<&(f64, f64)> = g
                .iter()
                .zip(k)
                .filter(|(_, k)| **k)
                .map(|(r, _)| r)
                .collect();
            let n = kept.len() as f64;
            (!kept.is_empty()).then(|| {
                (
                    kept.iter().map(|r| r.0).sum::<f64>() / n,
                    kept.iter().map(|r| r.1).sum::<f64>() / n,
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
        .flat_map(|(p, _)| &p.lights)
        .fold((0.0, 0.0), |(w, l), share| {
            (w + share.lit * share.distance, l + share.lit)
        });
    let (none, unexplained) = fit_under(groups, Falloff::NONE)?;
    if lit <= 0.0 || weighed <= 0.0 {
        return Some(none);
    }
    let best = Falloff::candidates(weighed / lit)
        .filter_map(|f| fit_under(groups, f))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    match best {
        Some((light, u)) if u < KEEP_NONE * unexplained => Some(light),
        _ => Some(none),
    }
}
