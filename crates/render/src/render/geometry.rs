//! Rays and the two primitives in the tracer's precision, with the
//! intersection routines and robust ray spawning.
//!
//! - Spheres use the stable quadratic of Ray Tracing Gems ch. 7: with unit
//!   `d`, `f = o − c`, `b = f·d`, `l = f − b·d`, the discriminant is
//!   `Δ = r² − l·l` (no `b² − c` cancellation) and the roots are `c/q` and
//!   `q` with `q = −b − sign(b)·√Δ`, `c = f·f − r²`.
//! - Rectangles intersect their plane, then set the hit point's plane
//!   coordinate exactly: `p = c + x·right + y·up`.
//! - A spawned ray starts on the face-forward side of its surface, moved
//!   off it by a bound on the hit point's rounding error that scales with
//!   the scene's coordinates (the isotropic form of pbrt's error-bound
//!   offset), and remembers the primitive it left. A ray cannot hit the rectangle it left again; from
//!   the sphere it left it can only hit the far root, and only when it heads
//!   inside. Both rules are exact, so no fixed epsilon is needed.

use super::real::{Real, Vector};

/// A ray `origin + t·dir`, `dir` of unit length.
#[derive(Clone, Copy, Debug)]
pub struct Ray<R: Real> {
    pub origin: R::Vec,
    pub dir: R::Vec,
    /// The slot of the primitive the ray was spawned from
    /// ([`super::world::World::prims`]), or [`Ray::FROM_NO_PRIMITIVE`].
    /// A plain integer, not an `Option`: a ray is copied by value on every
    /// bounce, and the optional's tag made the copy a wide load of
    /// narrower stores just made, which stalls the processor.
    pub from: u32,
}

impl<R: Real> Ray<R> {
    /// `from` of a ray that left no primitive (a camera ray): no slot, as
    /// a scene holds far fewer primitives ([`raytracer_scene::limits::MAX_OBJECTS`]).
    pub const FROM_NO_PRIMITIVE: u32 = u32::MAX;

    /// The ray from `origin` along `(x, y, z)`, a direction read from
    /// three per-axis lanes (a row's camera rays, a [`super::world::Fan`]).
    #[inline(always)]
    pub fn from_lanes(origin: R::Vec, (x, y, z): (R, R, R), from: u32) -> Ray<R> {
        Ray {
            origin,
            dir: R::Vec::new(x, y, z),
            from,
        }
    }
}

/// A sphere.
#[derive(Clone, Copy, Debug)]
pub struct Sphere<R: Real> {
    pub center: R::Vec,
    pub radius: R,
}

/// A finite two-sided rectangle.
#[derive(Clone, Copy, Debug)]
pub struct Rect<R: Real> {
    pub center: R::Vec,
    pub normal: R::Vec,
    pub right: R::Vec,
    pub up: R::Vec,
    pub half_width: R,
    pub half_height: R,
}

/// The geometry of a primitive. A rectangle is boxed so that a shape is
/// no larger than a sphere and its tag.
#[derive(Clone, Debug)]
pub enum Shape<R: Real> {
    Sphere(Sphere<R>),
    Rect(Box<Rect<R>>),
}

impl<R: Real> Shape<R> {
    /// The smallest `t` in `(0, t_max)` where `ray` meets the surface;
    /// `from_here` says the ray was spawned from this very primitive.
    #[inline(always)]
    pub fn hit(&self, ray: &Ray<R>, t_max: R, from_here: bool) -> Option<R> {
        match self {
            Shape::Sphere(s) => s.hit(ray, t_max, from_here),
            Shape::Rect(r) if !from_here => r.hit(ray, t_max),
            Shape::Rect(_) => None,
        }
    }

    /// Corners of the axis-aligned box around the primitive.
    pub fn bounds(&self) -> (R::Vec, R::Vec) {
        match self {
            Shape::Sphere(s) => {
                let r = R::Vec::new(s.radius, s.radius, s.radius);
                (s.center - r, s.center + r)
            }
            Shape::Rect(r) => {
                let half = |axis: R::Vec| {
                    let e = |a: R::Vec| a.dot(axis).abs();
                    e(r.right) * r.half_width + e(r.up) * r.half_height
                };
                let extent = R::Vec::new(
                    half(R::Vec::new(R::one(), R::zero(), R::zero())),
                    half(R::Vec::new(R::zero(), R::one(), R::zero())),
                    half(R::Vec::new(R::zero(), R::zero(), R::one())),
                );
                (r.center - extent, r.center + extent)
            }
        }
    }
}

/// Where a ray passes a sphere: the quantities its roots come from.
/// [`Sphere::hit`] stops here when `delta < 0` (the ray passes outside);
/// [`SphereApproach::root`] gives NaN for it too, so a lane that computes
/// on does not need the branch.
#[derive(Clone, Copy)]
pub struct SphereApproach<R: Real> {
    /// `f·d`, with `f = o − c`.
    b: R,
    /// `r² − l·l`, with `l = f − b·d`: the discriminant.
    delta: R,
    /// `f·f − r²`.
    c: R,
}

impl<R: Real> Sphere<R> {
    /// [`Shape::hit`] for a sphere.
    #[inline(always)]
    pub fn hit(&self, ray: &Ray<R>, t_max: R, from_here: bool) -> Option<R> {
        let approach = self.approach(ray);
        // With `b > 0` the sphere's centre lies behind the origin, so both
        // roots are behind it too when the origin is outside (`c > 0`)
        // and [`SphereApproach::root`] counts neither when the ray leaves
        // this sphere heading out: the same `None`, without the square
        // root and the division.
        if approach.b > R::zero() && (from_here || approach.c > R::zero()) {
            return None;
        }
        if approach.delta < R::zero() {
            return None;
        }
        let t = approach.root(from_here);
        (t < t_max).then_some(t)
    }

    /// The first half of the test: `b`, `Δ` and `c` of the ray.
    #[inline(always)]
    pub fn approach(&self, ray: &Ray<R>) -> SphereApproach<R> {
        let f = ray.origin - self.center;
        let b = f.dot(ray.dir);
        let l = f - ray.dir * b;
        let r2 = self.radius * self.radius;
        SphereApproach {
            b,
            delta: r2 - l.dot(l),
            c: f.dot(f) - r2,
        }
    }
}

impl<R: Real> SphereApproach<R> {
    /// The smallest root in `(0, ∞)` the ray counts, or NaN when none
    /// does. Written without branches (each choice is a select), so a
    /// loop over many rays runs it in vector lanes; [`Sphere::hit`] is
    /// this and a comparison with `t_max`.
    #[inline(always)]
    pub fn root(self, from_here: bool) -> R {
        let SphereApproach { b, delta, c } = self;
        let q = -b - b.signum() * delta.sqrt();
        let (t0, t1) = (c / q, q);
        let (near, far) = (t0.min(t1), t0.max(t1));
        let t = if from_here {
            // Leaving its own surface: the near root is the origin itself;
            // the far one counts only when the ray heads inside.
            select(b < R::zero(), far, R::nan())
        } else {
            select(near > R::zero(), near, far)
        };
        // `delta < 0`: the ray passes outside (√Δ is NaN, but say so).
        // `q = 0`: b = 0 and Δ = 0, the origin touches the sphere
        // tangentially.
        let counts = delta >= R::zero() && !q.is_zero() && t > R::zero();
        select(counts, t, R::nan())
    }
}

impl<R: Real> Rect<R> {
    #[inline(always)]
    fn hit(&self, ray: &Ray<R>, t_max: R) -> Option<R> {
        let t = self.plane_t(ray);
        if !(t > R::zero() && t < t_max) {
            return None;
        }
        self.contains_at(ray, t).then_some(t)
    }

    /// The `t` in `(0, ∞)` where `ray` crosses the rectangle, or NaN when
    /// it does not: [`Rect::hit`] without its early exit, written without
    /// branches, as [`SphereApproach::root`].
    #[inline(always)]
    pub fn root(&self, ray: &Ray<R>) -> R {
        let t = self.plane_t(ray);
        select(t > R::zero() && self.contains_at(ray, t), t, R::nan())
    }

    /// Where `ray` crosses the rectangle's plane; NaN when it runs
    /// parallel to it.
    #[inline(always)]
    fn plane_t(&self, ray: &Ray<R>) -> R {
        let denom = ray.dir.dot(self.normal);
        let t = (self.center - ray.origin).dot(self.normal) / denom;
        select(denom.is_zero(), R::nan(), t)
    }

    /// Whether the point of `ray` at `t` (on the plane) lies within the
    /// rectangle's edges.
    #[inline(always)]
    fn contains_at(&self, ray: &Ray<R>, t: R) -> bool {
        let (x, y) = self.plane_coordinates(ray.origin + ray.dir * t);
        x.abs() <= self.half_width && y.abs() <= self.half_height
    }

    /// Coordinates of `p` along `right` and `up`, from the centre.
    pub fn plane_coordinates(&self, p: R::Vec) -> (R, R) {
        let local = p - self.center;
        (local.dot(self.right), local.dot(self.up))
    }

    /// The point of the rectangle's plane at these coordinates.
    pub fn point(&self, x: R, y: R) -> R::Vec {
        self.center + self.right * x + self.up * y
    }
}

/// A bound on the magnitudes a hit point `p` of a primitive centred at
/// `center` is computed from, `‖p‖∞ + ‖centre‖∞`: the hit point (a
/// reprojection `c + r·m` or `c + x·right + y·up`) is exact to a few `ε`
/// of it.
#[inline(always)]
pub fn error_scale<R: Real>(center: R::Vec, p: R::Vec) -> R {
    max_abs::<R>(p) + max_abs::<R>(center)
}

/// How far a spawned ray's origin is moved off its surface, in units of
/// `ε · scale` (see [`offset_origin`]).
pub const OFFSET_ULPS: f64 = 64.0;

/// `p` moved off its surface along `n` (unit, on the side the new ray
/// leaves by) by `OFFSET_ULPS · ε · scale`, where `scale` is the hit's
/// [`error_scale`]: the rounding error of a computed hit point is a
/// few `ε · scale`, so the step clears it with a wide margin. The step is
/// proportional to the scene's coordinates, so a scene scaled about the
/// eye gets the same image at any scale (Wächter & Binder's fixed step
/// near the origin does not), and the step along `n` survives rounding:
/// each component rounds by at most `ε·|p|/2`, far below the step.
#[inline(always)]
pub fn offset_origin<R: Real>(p: R::Vec, n: R::Vec, scale: R) -> R::Vec {
    let step = R::of(OFFSET_ULPS) * R::epsilon() * scale.max(R::min_positive_value());
    p + n * step
}

/// `a` where `pick`, else `b`: a select, which the compiler keeps free of
/// branches (`&&` above is on comparisons only, which it evaluates
/// eagerly, so a vectorised loop computes every lane and chooses).
#[inline(always)]
fn select<R: Real>(pick: bool, a: R, b: R) -> R {
    if pick {
        a
    } else {
        b
    }
}

/// The largest magnitude of a vector's components.
#[inline(always)]
fn max_abs<R: Real>(v: R::Vec) -> R {
    v.x().abs().max(v.y().abs()).max(v.z().abs())
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;

    fn ray(origin: DVec3, dir: DVec3) -> Ray<f64> {
        Ray {
            origin,
            dir: dir.normalize(),
            from: Ray::<f64>::FROM_NO_PRIMITIVE,
        }
    }

    #[test]
    fn sphere_roots_in_front_and_inside() {
        let s = Sphere {
            center: DVec3::new(0.0, 0.0, -5.0),
            radius: 1.0,
        };
        let front = ray(DVec3::ZERO, -DVec3::Z);
        assert_eq!(s.hit(&front, f64::INFINITY, false), Some(4.0));
        let inside = ray(DVec3::new(0.0, 0.0, -5.0), DVec3::X);
        assert_eq!(s.hit(&inside, f64::INFINITY, false), Some(1.0));
        let behind = ray(DVec3::ZERO, DVec3::Z);
        assert_eq!(s.hit(&behind, f64::INFINITY, false), None);
        assert_eq!(s.hit(&front, 3.0, false), None);
    }

    #[test]
    fn leaving_a_sphere_hits_only_its_far_side_when_heading_in() {
        let s = Sphere {
            center: DVec3::ZERO,
            radius: 2.0,
        };
        let inward = ray(DVec3::new(0.0, 0.0, 2.0), -DVec3::Z);
        assert_eq!(s.hit(&inward, f64::INFINITY, true), Some(4.0));
        let outward = ray(DVec3::new(0.0, 0.0, 2.0), DVec3::new(0.0, 1.0, 1.0));
        assert_eq!(s.hit(&outward, f64::INFINITY, true), None);
    }

    #[test]
    fn sphere_hit_with_its_early_exits_agrees_with_the_branchless_root() {
        // Origins outside, inside and on the sphere (as a ray leaving it
        // starts), directions every way: `hit` is `root` below `t_max`.
        fn check<R: Real>() {
            let mut uniform = crate::render::fixture::uniform(0x9E37_79B9_7F4A_7C15);
            let mut random = move || uniform() * 2.0 - 1.0;
            let (mut behind, mut hits) = (0, 0);
            for k in 0..20_000 {
                let center = DVec3::new(random(), random(), random()) * 3.0;
                let radius = 0.1 + random().abs();
                let towards = DVec3::new(random(), random(), random()).normalize();
                let origin = match k % 3 {
                    0 => center + towards * radius,
                    1 => center + towards * radius * 0.5,
                    _ => center + towards * radius * 4.0,
                };
                let s = Sphere {
                    center: R::Vec::of(center),
                    radius: R::of(radius),
                };
                let ray = Ray {
                    origin: R::Vec::of(origin),
                    dir: R::Vec::of(DVec3::new(random(), random(), random()).normalize()),
                    from: Ray::<R>::FROM_NO_PRIMITIVE,
                };
                for from_here in [false, true] {
                    let approach = s.approach(&ray);
                    let root = approach.root(from_here);
                    let expected = (!root.is_nan() && root < R::infinity()).then_some(root);
                    assert_eq!(s.hit(&ray, R::infinity(), from_here), expected, "{k}");
                    behind += usize::from(approach.b > R::zero());
                    hits += usize::from(expected.is_some());
                }
            }
            assert!(behind > 10_000 && hits > 10_000, "{behind} {hits}");
        }
        check::<f32>();
        check::<f64>();
    }

    #[test]
    fn rect_is_finite_and_two_sided() {
        let r = Rect {
            center: DVec3::new(0.0, 0.0, -5.0),
            normal: DVec3::Z,
            right: DVec3::X,
            up: DVec3::Y,
            half_width: 1.0,
            half_height: 0.5,
        };
        assert_eq!(r.hit(&ray(DVec3::ZERO, -DVec3::Z), 10.0), Some(5.0));
        let back = ray(DVec3::new(0.0, 0.0, -10.0), DVec3::Z);
        assert_eq!(r.hit(&back, 10.0), Some(5.0));
        let past_edge = ray(DVec3::ZERO, DVec3::new(0.0, 0.11, -1.0));
        assert_eq!(r.hit(&past_edge, 10.0), None);
        let grazing = ray(DVec3::new(0.0, 0.0, -5.0), DVec3::X);
        assert_eq!(r.hit(&grazing, 10.0), None);
    }

    #[test]
    fn offset_moves_along_the_normal_in_proportion_to_scale() {
        fn check<R: Real>() {
            for scale in [1e-6, 1e-3, 1.0, 1e6] {
                let p = R::Vec::of(DVec3::new(0.3, -0.7, 0.2) * scale);
                let n = R::Vec::of(DVec3::new(1.0, 1e-9, -1.0).normalize());
                let s = R::of(scale);
                let moved = offset_origin::<R>(p, n, s);
                let along = (moved - p).dot(n).wide();
                let step = OFFSET_ULPS * R::epsilon().wide() * scale;
                assert!(
                    (along - step).abs() < 0.05 * step,
                    "scale {scale}: {along} vs {step}"
                );
            }
        }
        check::<f32>();
        check::<f64>();
    }
}
