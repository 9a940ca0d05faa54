//! Vector geometry shared by the check pass, lowering and the POV-Ray
//! export, below all of them: robust normalisation, the headup tests with
//! their thresholds, and a plane's `right`/`up` basis
//! (docs/rendering.md). Vectors are scaled by their largest component before any
//! squaring, so components near `f64::MAX` or in the subnormal range neither
//! overflow nor underflow.

use glam::DVec3;

/// Headup counts as parallel to the normal when `|n̂ × ĥ| ≤ PARALLEL`, an
/// angle under 1e-9 rad: closer than that, the projected `up` would carry a
/// relative rounding error above about 1e-7.
pub const PARALLEL: f64 = 1e-9;

/// Headup counts as not perpendicular to the normal when
/// `|n̂ · ĥ| > NOT_PERPENDICULAR`, an angle more than 1e-6 rad (about
/// 0.00006°) off a right angle: well above the rounding of values typed with
/// six or more digits, well below any tilt a person means.
pub const NOT_PERPENDICULAR: f64 = 1e-6;

/// `v` scaled to unit length, or `None` for the zero vector.
pub fn unit(v: [f64; 3]) -> Option<DVec3> {
    let v = DVec3::from_array(v);
    let scale = v.abs().max_element();
    if scale == 0.0 || !scale.is_finite() {
        return None;
    }
    Some((v / scale).normalize())
}

/// How headup relates to the plane's normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Headup {
    /// Perpendicular within [`NOT_PERPENDICULAR`].
    Perpendicular,
    /// Usable, but the renderer projects it: this is the projection onto
    /// the plane, at headup's own scale.
    Projected([f64; 3]),
    /// Parallel within [`PARALLEL`]: the plane has no up direction.
    Parallel,
}

/// Classify `headup` against `normal`; `None` when either is zero.
pub fn classify_headup(normal: [f64; 3], headup: [f64; 3]) -> Option<Headup> {
    let n = unit(normal)?;
    let h = unit(headup)?;
    if n.cross(h).length() <= PARALLEL {
        return Some(Headup::Parallel);
    }
    let cos = n.dot(h);
    if cos.abs() <= NOT_PERPENDICULAR {
        return Some(Headup::Perpendicular);
    }
    let headup = DVec3::from_array(headup);
    let scale = headup.abs().max_element();
    let scaled = headup / scale;
    let projected = (scaled - scaled.dot(n) * n) * scale;
    Some(Headup::Projected(projected.to_array()))
}

/// A plane's orthonormal frame (docs/rendering.md): `up` is headup projected onto
/// the plane, `right = up × normal`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Basis {
    pub normal: DVec3,
    pub right: DVec3,
    pub up: DVec3,
}

/// The headup a plane whose headup is parallel to its normal is rendered
/// with: the coordinate axis least aligned with the normal (y, then z,
/// then x among equals). Its angle to the normal is at least
/// arccos(1/√3) ≈ 55°, so its projection onto the plane is well defined.
pub fn stand_in_headup(normal: DVec3) -> DVec3 {
    [DVec3::Y, DVec3::Z, DVec3::X]
        .into_iter()
        .min_by(|a, b| a.dot(normal).abs().total_cmp(&b.dot(normal).abs()))
        .unwrap_or(DVec3::Y)
}

/// The basis of a plane, or `None` when normal or headup is zero (the
/// check pass reports those). A headup parallel to the normal gives no up
/// direction, so [`stand_in_headup`] takes its place (the check pass warns).
pub fn plane_basis(normal: [f64; 3], headup: [f64; 3]) -> Option<Basis> {
    let n = unit(normal)?;
    let mut h = unit(headup)?;
    if n.cross(h).length() <= PARALLEL {
        h = stand_in_headup(n);
    }
    let up = (h - h.dot(n) * n).normalize();
    Some(Basis {
        normal: n,
        right: up.cross(n),
        up,
    })
}

/// The four corners of a `width` × `height` rectangle centred on `center`.
pub fn corners(center: [f64; 3], basis: &Basis, width: f64, height: f64) -> [DVec3; 4] {
    let c = DVec3::from_array(center);
    let r = basis.right * (width / 2.0);
    let u = basis.up * (height / 2.0);
    [c - r - u, c + r - u, c + r + u, c - r + u]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_survives_extreme_magnitudes() {
        let diagonal = unit([0.0, 1e300, 1e300]).unwrap();
        assert!((diagonal - DVec3::new(0.0, 1.0, 1.0).normalize()).length() < 1e-15);
        assert_eq!(unit([0.0, 0.0, 5e-324]), Some(DVec3::Z));
        assert_eq!(unit([0.0; 3]), None);
    }

    #[test]
    fn classifies_the_corpus_headups() {
        // corpus/field/2_lights_color.txt
        let Some(Headup::Projected(p)) = classify_headup([0.0, 0.5, 1.0], [0.0, 1.0, 0.0]) else {
            panic!("not projected")
        };
        assert!((DVec3::from_array(p) - DVec3::new(0.0, 0.8, -0.4)).length() < 1e-15);
        assert_eq!(
            classify_headup([0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
            Some(Headup::Perpendicular)
        );
        assert_eq!(
            classify_headup([0.0, 1.0, 0.0], [0.0, 2.0, 0.0]),
            Some(Headup::Parallel)
        );
        assert_eq!(
            classify_headup([0.0, 1.0, 0.0], [0.0, -1.0, 1e-12]),
            Some(Headup::Parallel)
        );
        assert_eq!(classify_headup([0.0; 3], [0.0, 1.0, 0.0]), None);
    }

    #[test]
    fn basis_is_right_handed_and_orthonormal() {
        let b = plane_basis([0.0, 0.0, 2.0], [0.0, 3.0, 1.0]).unwrap();
        assert!((b.up - DVec3::Y).length() < 1e-15);
        assert!((b.right - DVec3::X).length() < 1e-15);
        assert!(b.normal.dot(b.up).abs() < 1e-15);
    }

    #[test]
    fn a_parallel_headup_is_replaced_by_the_least_aligned_axis() {
        // corpus/field/reflection_91b7c2f_headup010.txt: normal = headup = y.
        let stand_in = plane_basis([0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
        assert_eq!(plane_basis([0.0, 1.0, 0.0], [0.0, 1.0, 0.0]), stand_in);
        assert_eq!(plane_basis([0.0, 1.0, 0.0], [0.0, -3.0, 1e-12]), stand_in);
        assert_eq!(stand_in_headup(DVec3::Z), DVec3::Y);
        assert_eq!(stand_in_headup(DVec3::Y), DVec3::Z);
        let tilted = DVec3::new(0.0, 1.0, 1.0).normalize();
        assert_eq!(stand_in_headup(tilted), DVec3::X);
        assert_eq!(plane_basis([0.0; 3], [0.0, 1.0, 0.0]), None);
        assert_eq!(plane_basis([0.0, 1.0, 0.0], [0.0; 3]), None);
    }
}
