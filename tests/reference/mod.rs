//! An independent float64 evaluation of docs/rendering.md's model for the stability
//! tests, which also knows where its answer is fragile.
//!
//! It shares no code with the tracer except the texel rule. Intersections
//! use the geometric forms (closest approach to a sphere's centre; plane
//! distance over the cosine); a surface's own other intersection is the
//! exact second root `−2 (p − c)·d` instead of an offset. A pixel is
//! [`Expected::Ambiguous`] when any decision on its path lies within
//! `margin` (relative) of flipping: a ray passing within `margin·r` of a
//! sphere's silhouette or within `margin` of a rectangle's edge, two
//! surfaces at nearly the same distance, a shadow ray grazing an occluder
//! or meeting one at its start, a texture coordinate on a texel boundary.

use glam::DVec3;
use raytracer_render::ir::{self, Shape};
use raytracer_render::render::model::AMBIENT;
use raytracer_render::render::trace::{texel, Counters};
use raytracer_render::render::{Image, Options};

/// What the reference expects of a pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Expected {
    Rgb([u8; 3]),
    Ambiguous,
}

pub struct Reference<'a> {
    scene: &'a ir::Scene,
    max_depth: u32,
    margin: f64,
}

/// A decision that may flip: bail out of the pixel.
struct Fragile;

type Outcome<T> = Result<T, Fragile>;

/// Where a line meets a surface, and whether that is within the margin
/// of changing.
#[derive(Clone, Copy)]
struct Root {
    t: f64,
    fragile: bool,
}

/// A surface met by a ray.
struct Hit {
    t: f64,
    object: usize,
}

impl<'a> Reference<'a> {
    pub fn new(scene: &'a ir::Scene, max_depth: u32, margin: f64) -> Self {
        Reference {
            scene,
            max_depth,
            margin,
        }
    }

    /// The expected 8-bit value of pixel (i, j), through its centre.
    pub fn pixel(&self, i: u32, j: u32) -> Expected {
        let n = f64::from(self.scene.resolution);
        let dir = DVec3::new(
            -0.5 + (f64::from(i) + 0.5) / n,
            0.5 - (f64::from(j) + 0.5) / n,
            -1.0,
        )
        .normalize();
        match self.radiance(DVec3::ZERO, dir, None, 0) {
            Ok(c) => {
                Expected::Rgb([c.x, c.y, c.z].map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8))
            }
            Err(Fragile) => Expected::Ambiguous,
        }
    }

    fn radiance(
        &self,
        origin: DVec3,
        dir: DVec3,
        from: Option<DVec3>,
        depth: u32,
    ) -> Outcome<DVec3> {
        let Some(hit) = self.closest(origin, dir, from)? else {
            return Ok(DVec3::ZERO);
        };
        let object = &self.scene.objects[hit.object];
        let p = origin + dir * hit.t;
        let (outward, uv) = match object.shape {
            Shape::Sphere { center, radius } => {
                let m = (p - center) / radius;
                let u = 0.5 + m.z.atan2(m.x) / std::f64::consts::TAU;
                let v = 0.5 + m.y.clamp(-1.0, 1.0).asin() / std::f64::consts::PI;
                (m.normalize(), (u, v))
            }
            Shape::Rect {
                center,
                normal,
                right,
                up,
                width,
                height,
            } => {
                let local = p - center;
                (
                    normal,
                    (local.dot(right) / width + 0.5, local.dot(up) / height + 0.5),
                )
            }
        };
        let normal = if outward.dot(dir) > 0.0 {
            -outward
        } else {
            outward
        };
        let albedo = match self.scene.material(object).texture {
            Some(t) => {
                let texture = &self.scene.textures[t];
                self.texel_is_clear(uv.0, texture.width)?;
                self.texel_is_clear(1.0 - uv.1, texture.height)?;
                texel(texture, uv.0, uv.1)
            }
            None => self.scene.material(object).color,
        };
        let mut color = albedo * AMBIENT;
        for light in &self.scene.lights {
            let to_light = light.position - p;
            let distance = to_light.length();
            if distance == 0.0 {
                continue;
            }
            let l = to_light / distance;
            let cos = normal.dot(l);
            if cos <= 0.0 {
                continue;
            }
            if !self.occluded(p, l, distance, hit.object)? {
                color += albedo * light.color * cos;
            }
        }
        let k = self.scene.material(object).reflectivity;
        if k > 0.0 && depth < self.max_depth {
            let reflected = dir - normal * (2.0 * dir.dot(normal));
            let own = self.own_second_root(hit.object, p, reflected);
            color += self.radiance(p, reflected, own, depth + 1)? * k;
        }
        Ok(color)
    }

    /// The nearest surface along the ray. `from` is the primitive the ray
    /// leaves as (object index, t of its own other root).
    fn closest(&self, origin: DVec3, dir: DVec3, from: Option<DVec3>) -> Outcome<Option<Hit>> {
        let mut hits: Vec<Hit> = Vec::new();
        for (index, object) in self.scene.objects.iter().enumerate() {
            if let Some(from) = from {
                if from.x as usize == index {
                    // Leaving this surface: only its exact other root.
                    let t = from.y;
                    let scale = from.z;
                    if t > self.margin * scale {
                        hits.push(Hit { t, object: index });
                    } else if t > -self.margin * scale && t != 0.0 {
                        return Err(Fragile);
                    }
                    continue;
                }
            }
            if let Some(t) = self.hit(&object.shape, origin, dir)? {
                hits.push(Hit { t, object: index });
            }
        }
        hits.sort_by(|a, b| a.t.total_cmp(&b.t));
        if let [first, second, ..] = hits.as_slice() {
            if second.t - first.t <= self.margin * first.t {
                return Err(Fragile);
            }
        }
        Ok(hits.into_iter().next())
    }

    /// For a ray leaving `object` at `p`: (object, t of its other
    /// intersection with the same surface, the length scale), encoded in a
    /// vector to keep [`Reference::closest`]'s signature small.
    fn own_second_root(&self, object: usize, p: DVec3, dir: DVec3) -> Option<DVec3> {
        match self.scene.objects[object].shape {
            Shape::Sphere { center, radius } => Some(DVec3::new(
                object as f64,
                -2.0 * (p - center).dot(dir),
                radius,
            )),
            // A plane is met once: the ray leaves it for good.
            Shape::Rect { .. } => Some(DVec3::new(object as f64, -1.0, 1.0)),
        }
    }

    /// The smallest t > 0 where the ray meets `shape`, or [`Fragile`] when
    /// the answer is within the margin of changing.
    fn hit(&self, shape: &Shape, origin: DVec3, dir: DVec3) -> Outcome<Option<f64>> {
        let roots = self.roots(shape, origin, dir);
        let scale = self.scale(shape, origin);
        let mut best = None;
        for root in roots.into_iter().flatten() {
            let t = root.t;
            if root.fragile && t > 0.0 {
                return Err(Fragile);
            }
            if root.fragile {
                continue;
            }
            // The ray starts on this surface (a contact): only a far
            // tighter band than the margin, as the origin is exact here.
            if t.abs() <= self.margin * self.margin * scale {
                return Err(Fragile);
            }
            if t > 0.0 {
                best = Some(best.map_or(t, |b: f64| b.min(t)));
            }
        }
        Ok(best)
    }

    /// The surface's own length, which sets the band for `t` near 0.
    fn scale(&self, shape: &Shape, origin: DVec3) -> f64 {
        match *shape {
            Shape::Sphere { center, radius } => radius.min((origin - center).length().max(radius)),
            Shape::Rect { width, height, .. } => width.min(height),
        }
    }

    /// Both intersections of the line with the surface (any sign of t).
    /// A root is fragile when the line passes within the margin of the
    /// sphere's silhouette (then both roots are its tangent point) or of
    /// the rectangle's edge.
    fn roots(&self, shape: &Shape, origin: DVec3, dir: DVec3) -> [Option<Root>; 2] {
        match *shape {
            Shape::Sphere { center, radius } => {
                let to_center = center - origin;
                let along = to_center.dot(dir);
                let miss = (to_center - dir * along).length();
                if (miss - radius).abs() <= self.margin * radius {
                    let tangent = Some(Root {
                        t: along,
                        fragile: true,
                    });
                    return [tangent, None];
                }
                if miss > radius {
                    return [None, None];
                }
                let half = ((radius - miss) * (radius + miss)).sqrt();
                [along - half, along + half].map(|t| Some(Root { t, fragile: false }))
            }
            Shape::Rect {
                center,
                normal,
                right,
                up,
                width,
                height,
            } => {
                let height_above = (origin - center).dot(normal);
                let cos = dir.dot(normal);
                if cos == 0.0 {
                    // In the plane: met everywhere or nowhere.
                    let inside = (height_above == 0.0).then_some(Root {
                        t: 0.0,
                        fragile: true,
                    });
                    return [inside, None];
                }
                let t = -height_above / cos;
                let local = origin + dir * t - center;
                let x = local.dot(right).abs() / (width / 2.0);
                let y = local.dot(up).abs() / (height / 2.0);
                let fragile = (x - 1.0).abs() <= self.margin || (y - 1.0).abs() <= self.margin;
                let inside = x < 1.0 && y < 1.0;
                [(inside || fragile).then_some(Root { t, fragile }), None]
            }
        }
    }

    /// Whether anything lies strictly between `p` (on `object`) and the
    /// light at `distance` along unit `l`.
    fn occluded(&self, p: DVec3, l: DVec3, distance: f64, object: usize) -> Outcome<bool> {
        let mut occluded = false;
        for (index, other) in self.scene.objects.iter().enumerate() {
            let roots = if index == object {
                match other.shape {
                    Shape::Sphere { center, .. } => [
                        Some(Root {
                            t: -2.0 * (p - center).dot(l),
                            fragile: false,
                        }),
                        None,
                    ],
                    Shape::Rect { .. } => [None, None],
                }
            } else {
                self.roots(&other.shape, p, l)
            };
            for Root { t: s, fragile } in roots.into_iter().flatten() {
                if fragile && s > -self.margin * distance && s < distance * (1.0 + self.margin) {
                    return Err(Fragile);
                }
                if fragile {
                    continue;
                }
                // Exactly at the light: the light is on this surface, which
                // is not between.
                if (s - distance).abs() <= 1e-9 * distance {
                    continue;
                }
                let near_start = s.abs() <= self.margin * distance && index != object;
                let near_end = (s - distance).abs() <= self.margin * distance;
                if near_start || near_end {
                    return Err(Fragile);
                }
                occluded |= s > 0.0 && s < distance;
            }
        }
        Ok(occluded)
    }

    /// A texture coordinate in [0, 1] that is not within the margin of a
    /// boundary between two of `texels` texels (0 and 1 clamp, so they
    /// are not boundaries).
    fn texel_is_clear(&self, coordinate: f64, texels: u32) -> Outcome<()> {
        let scaled = coordinate * f64::from(texels);
        let boundary = scaled.round();
        let inner = boundary > 0.0 && boundary < f64::from(texels);
        if inner && (scaled - boundary).abs() <= self.margin * 10.0 {
            return Err(Fragile);
        }
        Ok(())
    }
}

/// Compare every unambiguous pixel of each render with the reference to
/// 1/255; at least 80% of the pixels must be unambiguous, so a test cannot
/// pass by flagging everything.
pub fn assert_renders_match_reference(
    name: &str,
    scene: &ir::Scene,
    options: &Options,
    margin: f64,
    renders: impl IntoIterator<Item = (&'static str, Image, Counters)>,
) {
    let reference = Reference::new(scene, options.max_depth, margin);
    let expected: Vec<Expected> = (0..scene.resolution * scene.resolution)
        .map(|k| reference.pixel(k % scene.resolution, k / scene.resolution))
        .collect();
    let compared = expected
        .iter()
        .filter(|e| matches!(e, Expected::Rgb(_)))
        .count();
    let total = expected.len();
    assert!(
        compared * 10 >= total * 8,
        "{name}: only {compared} of {total} pixels are unambiguous"
    );
    for (precision, image, _) in renders {
        let mut bad = Vec::new();
        for (k, e) in expected.iter().enumerate() {
            let Expected::Rgb(want) = e else { continue };
            let got = &image.rgb[k * 3..k * 3 + 3];
            if got.iter().zip(want).any(|(&g, &w)| g.abs_diff(w) > 1) {
                bad.push((
                    k as u32 % scene.resolution,
                    k as u32 / scene.resolution,
                    [got[0], got[1], got[2]],
                    *want,
                ));
            }
        }
        assert!(
            bad.is_empty(),
            "{name} in {precision}: {} of {compared} pixels differ from the analytic value by more than 1/255, e.g. (column, row, found, expected) {:?}",
            bad.len(),
            &bad[..bad.len().min(5)]
        );
    }
}
