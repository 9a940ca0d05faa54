//! Properties of the intersection routines in both precisions (issue 5).
//!
//! Each input is drawn in `f64`, rounded to the precision under test, and
//! widened back, so the exact intersection of the *rounded* inputs can be
//! computed in `f64` as the reference. The stated bound: with
//! `scale = |o − c| + r` for a sphere and `|o| + |o − c| + w/2 + h/2` for a
//! rectangle (whose test rounds the point `o + t·d` itself),
//!
//! - a returned hit point `p = o + t·d` lies on the surface within
//!   `BOUND · ε · scale` (`| |p − c| − r |` for a sphere, `|(p − c)·n|` for
//!   a rectangle);
//! - the nearest hit is never behind the origin: `t > 0`, and when the
//!   near root is ahead of the origin it is the one returned;
//! - a ray that clearly passes through a primitive in front of it hits it;
//! - a ray leaving a sphere outwards never hits it again, and one leaving
//!   inwards hits its far side.
//!
//! `ε` is the precision's machine epsilon. The worst ratio seen over these
//! inputs is reported in docs/numerics.md.

use glam::DVec3;
use proptest::prelude::*;
use raytracer_render::render::geometry::{Ray, Rect, Shape, Sphere};
use raytracer_render::render::real::{Real, Vector};

/// The bound, in units of `ε · scale`.
const BOUND: f64 = 8.0;

/// A point with coordinates over many magnitudes.
fn point() -> impl Strategy<Value = DVec3> {
    ([-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64], -3i32..7)
        .prop_map(|(xyz, exponent)| DVec3::from_array(xyz) * 10f64.powi(exponent))
}

fn unit() -> impl Strategy<Value = DVec3> {
    [-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64]
        .prop_filter_map("non-zero", |v| DVec3::from_array(v).try_normalize())
}

fn length() -> impl Strategy<Value = f64> {
    (0.1..1.0f64, -3i32..6).prop_map(|(m, e)| m * 10f64.powi(e))
}

/// Round to precision `R` and back.
fn round<R: Real>(v: DVec3) -> R::Vec {
    R::Vec::of(v)
}

/// The exact roots (in `f64`) of the rounded ray against the rounded
/// sphere, and the ray's closest distance to the centre.
fn sphere_reference(o: DVec3, d: DVec3, c: DVec3, r: f64) -> (f64, f64, f64) {
    // `d` is not exactly unit after rounding: solve a·t² + 2b·t + k = 0.
    let f = o - c;
    let a = d.dot(d);
    let b = f.dot(d);
    let l = f - d * (b / a);
    let miss = l.length();
    let h = ((r - miss).max(0.0) * (r + miss)).sqrt() / a.sqrt();
    let mid = -b / a;
    (mid - h, mid + h, miss)
}

fn check_sphere<R: Real>(
    origin: DVec3,
    dir: DVec3,
    center: DVec3,
    radius: f64,
) -> Result<(), TestCaseError> {
    let ray = Ray::<R> {
        origin: round::<R>(origin),
        dir: round::<R>(dir).normalize(),
        from: Ray::<R>::FROM_NO_PRIMITIVE,
    };
    let sphere = Sphere {
        center: round::<R>(center),
        radius: R::of(radius),
    };
    let (o, d, c, r) = (
        ray.origin.wide(),
        ray.dir.wide(),
        sphere.center.wide(),
        sphere.radius.wide(),
    );
    let scale = (o - c).length() + r;
    let tolerance = BOUND * R::epsilon().wide() * scale;
    let (near, far, miss) = sphere_reference(o, d, c, r);
    let hit = Shape::Sphere(sphere).hit(&ray, R::infinity(), false);
    if let Some(t) = hit {
        let t = t.wide();
        prop_assert!(t > 0.0, "hit behind the origin: t = {t}");
        let p = o + d * t;
        let off = ((p - c).length() - r).abs();
        prop_assert!(
            off <= tolerance,
            "hit point {off:e} off the sphere, bound {tolerance:e}"
        );
        // Near a graze the two roots are ill-conditioned (an error δ in
        // the miss distance moves them by r·δ/√(r² − miss²)), so nearest
        // means closer to the near root than to the far one.
        // Within a chord of √(8·tolerance·r) the two roots are the same
        // graze to the precision: either one is the nearest.
        let graze = far - near <= (8.0 * tolerance * r).sqrt();
        if !graze && near > tolerance {
            prop_assert!(
                (t - near).abs() < (t - far).abs() || (t - near).abs() <= tolerance,
                "expected the near root {near}, found {t} (far root {far})"
            );
        } else if !graze {
            prop_assert!(
                (t - far).abs() <= (t - near).abs(),
                "expected the far root {far}, found {t}"
            );
        }
    } else {
        // Closer than the precision can resolve counts as a graze.
        let clearly_through = miss < r * (1.0 - 1e-3) - tolerance;
        prop_assert!(
            !(clearly_through && far > tolerance && near.abs() > tolerance),
            "missed a sphere the ray passes through (roots {near}, {far})"
        );
    }
    Ok(())
}

fn check_rect<R: Real>(
    origin: DVec3,
    dir: DVec3,
    center: DVec3,
    normal: DVec3,
    headup: DVec3,
    size: (f64, f64),
) -> Result<(), TestCaseError> {
    let Some(up) = (headup - normal * headup.dot(normal)).try_normalize() else {
        return Ok(());
    };
    let ray = Ray::<R> {
        origin: round::<R>(origin),
        dir: round::<R>(dir).normalize(),
        from: Ray::<R>::FROM_NO_PRIMITIVE,
    };
    let rect = Rect {
        center: round::<R>(center),
        normal: round::<R>(normal),
        right: round::<R>(up.cross(normal)),
        up: round::<R>(up),
        half_width: R::of(size.0 / 2.0),
        half_height: R::of(size.1 / 2.0),
    };
    let (o, d, c, n) = (
        ray.origin.wide(),
        ray.dir.wide(),
        rect.center.wide(),
        rect.normal.wide(),
    );
    let (hw, hh) = (rect.half_width.wide(), rect.half_height.wide());
    // The rectangle test computes the point `o + t·d` itself, so its
    // rounding is relative to `|o|` too.
    let scale = o.length() + (o - c).length() + hw + hh;
    let tolerance = BOUND * R::epsilon().wide() * scale;
    let exact_t = (c - o).dot(n) / d.dot(n);
    let local = o + d * exact_t - c;
    let (x, y) = (local.dot(rect.right.wide()), local.dot(rect.up.wide()));
    match Shape::Rect(Box::new(rect)).hit(&ray, R::infinity(), false) {
        Some(t) => {
            let t = t.wide();
            prop_assert!(t > 0.0, "hit behind the origin: t = {t}");
            let p = o + d * t;
            let off = (p - c).dot(n).abs();
            prop_assert!(
                off <= tolerance,
                "hit point {off:e} off the plane, bound {tolerance:e}"
            );
            let (px, py) = ((p - c).dot(rect.right.wide()), (p - c).dot(rect.up.wide()));
            prop_assert!(px.abs() <= hw + tolerance && py.abs() <= hh + tolerance);
        }
        None => {
            // A grazing ray's hit moves along the plane by the error of t
            // over the cosine: the edge margin grows by 1/|cos|.
            let margin = tolerance / d.dot(n).abs();
            let clearly_inside =
                x.abs() < hw * (1.0 - 1e-3) - margin && y.abs() < hh * (1.0 - 1e-3) - margin;
            let clearly_ahead = exact_t * d.dot(n).abs() > tolerance;
            prop_assert!(
                !(clearly_inside && clearly_ahead),
                "missed a rectangle the ray passes through at t = {exact_t}"
            );
        }
    }
    Ok(())
}

/// A ray leaving a sphere's surface point (rounded) along `dir`.
fn check_leaving_sphere<R: Real>(
    center: DVec3,
    radius: f64,
    on: DVec3,
    dir: DVec3,
) -> Result<(), TestCaseError> {
    let sphere = Sphere {
        center: round::<R>(center),
        radius: R::of(radius),
    };
    let origin = sphere.center + round::<R>(on) * sphere.radius;
    let ray = Ray::<R> {
        origin,
        dir: round::<R>(dir).normalize(),
        from: 0,
    };
    // The rounded origin is off the surface by up to δ = BOUND·ε·scale.
    // That can flip the sign of `d·m` only when |d·m| < δ/r; and a ray
    // heading in at angle α from a point δ outside misses the sphere when
    // δ > r(1 − cos α) ≈ r·α²/2. Only angles beyond both count.
    let scale = center.length() + radius;
    let off = BOUND * R::epsilon().wide() * scale / radius;
    let heading_in = on.dot(dir) < -(1e-3 + (2.0 * off).sqrt());
    let heading_out = on.dot(dir) > 1e-3 + off;
    let hit = Shape::Sphere(sphere).hit(&ray, R::infinity(), true);
    if heading_out {
        prop_assert!(
            hit.is_none(),
            "a ray leaving outwards hit its own sphere at {hit:?}"
        );
    }
    if heading_in {
        let t = hit.map(|t| t.wide());
        // The chord through the sphere has length −2 r (m·d). A short
        // chord is ill-conditioned: `Δ = r² − l·l` cancels to about
        // `(chord/2)²`, so its error grows like `ε·r²/chord`.
        let chord = -2.0 * radius * on.dot(dir);
        prop_assert!(
            t.is_some_and(|t| (t - chord).abs()
                <= BOUND * R::epsilon().wide() * scale * (1.0 + radius / chord)),
            "a ray leaving inwards found {t:?}, expected the far side at {chord}"
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 2000,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn sphere_hits_lie_on_the_surface_and_are_nearest(origin in point(), dir in unit(), center in point(), radius in length()) {
        check_sphere::<f32>(origin, dir, center, radius)?;
        check_sphere::<f64>(origin, dir, center, radius)?;
    }

    /// Rays aimed at the sphere, so most of them hit it.
    #[test]
    fn aimed_rays_hit_spheres_on_the_surface(origin in point(), aim in unit(), center in point(), radius in length()) {
        let Some(dir) = (center + aim * radius * 0.999 - origin).try_normalize() else { return Ok(()) };
        check_sphere::<f32>(origin, dir, center, radius)?;
        check_sphere::<f64>(origin, dir, center, radius)?;
    }

    #[test]
    fn rect_hits_lie_on_the_plane_inside_the_edges(
        origin in point(), dir in unit(), center in point(), normal in unit(), headup in unit(),
        width in length(), height in length(),
    ) {
        check_rect::<f32>(origin, dir, center, normal, headup, (width, height))?;
        check_rect::<f64>(origin, dir, center, normal, headup, (width, height))?;
    }

    /// Rays aimed inside the rectangle, so most of them hit it.
    #[test]
    fn aimed_rays_hit_rects_on_the_plane(
        origin in point(), center in point(), normal in unit(), headup in unit(),
        width in length(), height in length(), along in (-0.99..0.99f64, -0.99..0.99f64),
    ) {
        let Some(up) = (headup - normal * headup.dot(normal)).try_normalize() else { return Ok(()) };
        let target = center + up.cross(normal) * (along.0 * width / 2.0) + up * (along.1 * height / 2.0);
        let Some(dir) = (target - origin).try_normalize() else { return Ok(()) };
        check_rect::<f32>(origin, dir, center, normal, headup, (width, height))?;
        check_rect::<f64>(origin, dir, center, normal, headup, (width, height))?;
    }

    #[test]
    fn rays_leaving_a_sphere_hit_only_its_far_side(center in point(), radius in length(), on in unit(), dir in unit()) {
        check_leaving_sphere::<f32>(center, radius, on, dir)?;
        check_leaving_sphere::<f64>(center, radius, on, dir)?;
    }
}
