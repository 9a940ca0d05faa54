//! The student's highlight lobe on one object, read off the image: how
//! much brighter than the scene's light fit their fully lit points are,
//! against the cosine between the mirror direction and the direction to
//! a light ([`Probe::highlight`]). The assignment leaves the highlight
//! open (none, Phong, Blinn–Phong, any weight and exponent), and a light
//! that still reaches a shadowed point puts its highlight there as it
//! does on a lit one: shadows hold such a point to the brightening the
//! student's own lit points show at its cosine, not to none.
//!
//! The lobe is `k·c^n` of the cosine `c`, the shape of a Phong highlight
//! (a Blinn–Phong one is close to it at some other exponent), fitted by
//! least squares at exponents from 1 to 512 in quarter octaves, on the
//! points within [`HIGHLIGHT_CONE`], out of which no lobe brightens a
//! point by more than 0.04. A power of the cosine, not bins of it: a
//! highlight's centre can lie where the object is shadowed from another
//! light alone, beyond the cosines its fully lit points reach.
//!
//! [`Probe::highlight`]: raytracer_render::render::probe::Probe::highlight

use super::evidence::HIGHLIGHT_CONE;

/// The fewest points within the cone that tell a lobe.
const LEAST_POINTS: usize = 20;

/// A highlight lobe, `weight·c^exponent` of the cosine `c`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Lobe {
    weight: f64,
    exponent: f64,
}

impl Lobe {
    /// No highlight.
    pub const NONE: Lobe = Lobe {
        weight: 0.0,
        exponent: 1.0,
    };

    /// The brightening at `cosine`; none out of the cone.
    pub fn at(&self, cosine: f64) -> f64 {
        if cosine <= HIGHLIGHT_CONE {
            return 0.0;
        }
        self.weight * cosine.powf(self.exponent)
    }

    /// The lobe of `points`: each fully lit point's cosine and its
    /// brightness over the fit's line. Only the points within the cone
    /// tell it; [`Lobe::NONE`] when fewer than [`LEAST_POINTS`] do, or
    /// when they are no brighter than the line (a tracer with no
    /// highlight).
    pub fn fit(points: &[(f64, f64)]) -> Lobe {
        let within: Vec<(f64, f64)> = points
            .iter()
            .copied()
            .filter(|&(c, _)| c > HIGHLIGHT_CONE)
            .collect();
        if within.len() < LEAST_POINTS {
            return Lobe::NONE;
        }
        (0..=36)
            .map(|j| 2f64.powf(f64::from(j) / 4.0))
            .map(|exponent| {
                let shapes: Vec<f64> = within.iter().map(|&(c, _)| c.powf(exponent)).collect();
                let (mut across, mut own) = (0.0, 0.0);
                for (&shape, &(_, excess)) in shapes.iter().zip(&within) {
                    across += shape * excess;
                    own += shape * shape;
                }
                let weight = (across / own).max(0.0);
                let squares: f64 = shapes
                    .iter()
                    .zip(&within)
                    .map(|(&shape, &(_, excess))| (excess - weight * shape).powi(2))
                    .sum();
                (Lobe { weight, exponent }, squares)
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map_or(Lobe::NONE, |(lobe, _)| lobe)
    }
}

#[cfg(test)]
mod tests {
    use super::Lobe;

    #[test]
    fn a_phong_lobe_is_read_back_to_its_centre() {
        // A lobe 0.3·c^20 seen only up to a cosine of 0.97, as where its
        // centre lies in another light's shadow: read back at the centre.
        let points: Vec<(f64, f64)> = (0..200)
            .map(|i| {
                let c = 0.4 + 0.57 * f64::from(i) / 200.0;
                (c, 0.3 * c.powi(20))
            })
            .collect();
        let lobe = Lobe::fit(&points);
        assert!((lobe.at(1.0) - 0.3).abs() < 0.02, "{lobe:?}");
        assert_eq!(lobe.at(0.45), 0.0);
    }

    #[test]
    fn no_highlight_and_too_few_points_read_as_none() {
        let flat: Vec<(f64, f64)> = (0..200)
            .map(|i| (0.5 + 0.5 * f64::from(i) / 200.0, -0.01))
            .collect();
        assert_eq!(Lobe::fit(&flat).at(1.0), 0.0);
        let few: Vec<(f64, f64)> = (0..19).map(|i| (0.99, 0.1 + f64::from(i))).collect();
        assert_eq!(Lobe::fit(&few), Lobe::NONE);
    }
}
