//! The Whitted integrator: what colour a camera ray sees (docs/rendering.md).
//!
//! Local light is `0.1·C + Σ C ⊙ I·max(0, N·L̂)` over the lights a shadow
//! ray reaches; a reflective surface adds `k ·` the colour along the mirror
//! direction, up to `max_depth` reflections. Those are the constants of the
//! default [`Model`]; another sets the ambient share, the diffuse weight, a
//! Phong highlight and blended reflection. The recursion is a loop that
//! carries the product of reflectivities, so depth costs no stack.
//!
//! Only the work a scene calls for is done: no reflection ray leaves a
//! surface with `k = 0`, no shadow ray is cast without lights, no texel is
//! read without a texture. With `skip` on (the default), work that cannot
//! change the 8-bit result is skipped too: a shadow ray towards a light
//! behind the surface or one whose contribution is black, and everything
//! after a path's colour has reached 1 in every channel (contributions are
//! never negative, so the clamp keeps it at 255). [`Counters`] records
//! every ray cast and every skip.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::geometry::{error_scale, offset_origin, Ray, Rect, Shape, Sphere};
use super::model::Model;
#[cfg(test)]
use super::model::AMBIENT;
use super::real::{Real, Vector};
use super::world::{Accel, Fan, Hit, Prim, World};
use crate::ir;

/// A row's camera rays, their directions per axis, and what they first
/// hit, as [`Tracer::first_hits`] found it (`distances[k]` is ∞ where ray
/// `k` misses).
pub struct FirstHits<'a, R: Real> {
    pub dirs: [&'a [R]; 3],
    pub distances: &'a [R],
    pub slots: &'a [u32],
}

/// What a render did, summed over every pixel.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, derive_more::AddAssign,
)]
pub struct Counters {
    pub primary_rays: u64,
    pub shadow_rays: u64,
    pub reflection_rays: u64,
    pub texture_lookups: u64,
    /// Shadow rays not cast: light behind the surface, black contribution,
    /// or colour already saturated.
    pub shadow_rays_skipped: u64,
    /// Paths ended early because every channel had reached 1.
    pub paths_saturated: u64,
    /// Samples whose colour, and texture lookups whose coordinates, were
    /// NaN or infinite: always 0 (counted in every build, so a release
    /// test can assert it; tests/stability.rs does).
    pub non_finite: u64,
    /// The wide nodes of the hierarchy rays walked, or 0 when every
    /// primitive was tested (brute force): which acceleration ran. Set once
    /// per render, not summed (`+=` keeps the left side's).
    #[add_assign(skip)]
    pub bvh_nodes: u64,
    /// Pixels adaptive antialiasing gave all their samples (0 with
    /// uniform sampling, where every pixel has them).
    #[serde(default)]
    pub pixels_refined: u64,
    /// Pixels adaptive antialiasing gave four of their samples, not all.
    #[serde(default)]
    pub pixels_partly_refined: u64,
}

/// A light in the tracer's precision.
pub(super) struct Light<R: Real> {
    pub(super) position: R::Vec,
    pub(super) color: DVec3,
}

/// Where a ray met a surface.
pub(super) struct Surface<R: Real> {
    pub(super) point: R::Vec,
    /// Unit normal facing the incoming ray.
    pub(super) normal: R::Vec,
    /// Texture coordinates, computed only for textured objects.
    pub(super) uv: Option<(f64, f64)>,
    /// The magnitude the point's rounding error is relative to.
    pub(super) error_scale: R,
}

/// Traces rays through one scene in precision `R`. What the renderer's
/// other passes read of a scene (the probes of [`super::probe`]) they ask
/// of its world, lights, surfaces and albedo, which are the module's
/// parent's to see.
pub struct Tracer<'a, R: Real> {
    scene: &'a ir::Scene,
    pub(super) world: World<R>,
    pub(super) lights: Vec<Light<R>>,
    max_depth: u32,
    skip: bool,
    model: Model,
    /// Whether shadow rays are cast; without them every light in front
    /// of a surface reaches it.
    shadows: bool,
}

impl<'a, R: Real> Tracer<'a, R> {
    /// A tracer for `scene` reflecting up to `max_depth` times, finding
    /// hits as [`Accel::Auto`] chooses.
    pub fn new(scene: &'a ir::Scene, max_depth: u32, skip: bool) -> Self {
        Self::with_accel(scene, max_depth, skip, Accel::Auto)
    }

    /// [`Tracer::new`] with the way rays find primitives chosen.
    pub fn with_accel(scene: &'a ir::Scene, max_depth: u32, skip: bool, accel: Accel) -> Self {
        let lights = scene
            .lights
            .iter()
            .map(|l| Light {
                position: R::Vec::of(l.position),
                color: l.color,
            })
            .collect();
        Tracer {
            scene,
            world: World::new(scene, accel),
            lights,
            max_depth,
            skip,
            model: Model::default(),
            shadows: true,
        }
    }

    /// This tracer with the illumination model `model` instead of the
    /// default one.
    pub fn with_model(self, model: Model) -> Self {
        Tracer { model, ..self }
    }

    /// This tracer casting no shadow ray: what a scene would look like
    /// were nothing in any light's way.
    pub fn without_shadows(self) -> Self {
        Tracer {
            shadows: false,
            ..self
        }
    }

    /// The colour seen along a camera ray, before clamping.
    pub fn radiance(&self, ray: Ray<R>, counters: &mut Counters) -> DVec3 {
        counters.primary_rays += 1;
        match self.world.closest(&ray, R::infinity()) {
            None => DVec3::ZERO,
            Some(hit) => self.path(ray, hit, counters),
        }
    }

    /// What camera rays that leave `eye` along `dirs` (per axis) hit
    /// first, as [`Tracer::radiance`] finds it: `distances[k]` is ∞ where
    /// ray `k` misses (it sees black), else the hit's `t`, and `slots[k]`
    /// its slot ([`World::closest_fan`]). A caller finds the hits of many
    /// rays before shading them with [`Tracer::paths`].
    pub fn first_hits(&self, eye: R::Vec, dirs: [&[R]; 3], distances: &mut [R], slots: &mut [u32]) {
        distances.fill(R::infinity());
        self.world.closest_fan(Fan {
            origin: eye,
            from: Ray::<R>::FROM_NO_PRIMITIVE,
            dirs,
            distances,
            slots,
        });
    }

    /// The colour seen along camera ray `ray`, which first hits `first`,
    /// before clamping: [`Tracer::radiance`] of a ray that hits, except
    /// that the caller counts the camera ray
    /// ([`Counters::primary_rays`]). Out of line: most camera rays of a
    /// small scene miss, and the loops over samples that call
    /// [`Tracer::radiance`] stay small.
    #[inline(never)]
    fn path(&self, ray: Ray<R>, first: Hit<R>, counters: &mut Counters) -> DVec3 {
        self.trace_path(ray, first, counters)
    }

    /// [`Tracer::path`] of every camera ray [`Tracer::first_hits`] found
    /// a hit for (`distances[k]` finite), each colour handed to `put` with
    /// the ray's index; rays that miss are passed over. One call for a
    /// row, out of line, the counts tallied in locals and added to
    /// `counters` once.
    #[inline(never)]
    pub fn paths(
        &self,
        eye: R::Vec,
        rays: FirstHits<'_, R>,
        counters: &mut Counters,
        mut put: impl FnMut(usize, DVec3),
    ) {
        let mut tally = Counters::default();
        let FirstHits {
            dirs: [x, y, z],
            distances,
            slots,
        } = rays;
        let rays = x.iter().zip(y).zip(z);
        let hits = distances.iter().zip(slots);
        for (k, (((&x, &y), &z), (&t, &slot))) in rays.zip(hits).enumerate() {
            if t == R::infinity() {
                continue;
            }
            let ray = Ray::from_lanes(eye, (x, y, z), Ray::<R>::FROM_NO_PRIMITIVE);
            put(k, self.trace_path(ray, Hit { t, slot }, &mut tally));
        }
        *counters += tally;
    }

    /// The one definition of [`Tracer::path`]: its first bounce, then
    /// [`Tracer::onwards`].
    #[inline(always)]
    fn trace_path(&self, ray: Ray<R>, first: Hit<R>, counters: &mut Counters) -> DVec3 {
        let prim = &self.world.prims[first.slot as usize];
        let material = &self.world.materials[prim.material as usize];
        let surface = self.surface(&ray, first.t, prim, material);
        let albedo = self.albedo(material, surface.uv, counters);
        let weight = self.model.local_weight(material.reflectivity);
        let local = self.local(
            &surface,
            ray.dir,
            first.slot,
            albedo,
            DVec3::ZERO,
            weight,
            counters,
        );
        self.onwards(
            ray,
            first.slot,
            surface,
            local,
            material.reflectivity,
            counters,
        )
    }

    /// The colour of a path whose camera ray `ray` met `surface` on
    /// primitive `slot`, which reflects `k`, and found `local` light
    /// there: that light, then the reflections, before clamping.
    #[inline(always)]
    fn onwards(
        &self,
        mut ray: Ray<R>,
        mut slot: u32,
        mut surface: Surface<R>,
        mut local: DVec3,
        mut k: f64,
        counters: &mut Counters,
    ) -> DVec3 {
        let mut color = DVec3::ZERO;
        let mut weight = 1.0;
        for depth in 0..=self.max_depth {
            if depth > 0 {
                let Some(hit) = self.world.closest(&ray, R::infinity()) else {
                    break;
                };
                slot = hit.slot;
                let prim = &self.world.prims[slot as usize];
                let material = &self.world.materials[prim.material as usize];
                surface = self.surface(&ray, hit.t, prim, material);
                let albedo = self.albedo(material, surface.uv, counters);
                k = material.reflectivity;
                let share = weight * self.model.local_weight(k);
                local = self.local(&surface, ray.dir, slot, albedo, color, share, counters);
            }
            // `weight · 1` when reflection is added: the same bits.
            color += local * (weight * self.model.local_weight(k));
            if k == 0.0 || depth == self.max_depth {
                break;
            }
            if self.skip && saturated(color) {
                counters.paths_saturated += 1;
                break;
            }
            weight *= k;
            let d = ray.dir;
            let n = surface.normal;
            ray = Ray {
                origin: offset_origin::<R>(surface.point, n, surface.error_scale),
                dir: (d - n * (R::of(2.0) * d.dot(n))).normalize(),
                from: slot,
            };
            counters.reflection_rays += 1;
        }
        debug_assert!(color.is_finite(), "non-finite colour {color}");
        if !color.is_finite() {
            counters.non_finite += 1;
        }
        color
    }

    /// The wide nodes of the hierarchy this tracer walks (0: brute force).
    pub fn bvh_nodes(&self) -> u64 {
        self.world.bvh_nodes()
    }

    /// The hit point (on the surface to rounding), the face-forward normal
    /// and, for textured objects, the texture coordinates.
    #[inline(always)]
    pub(super) fn surface(
        &self,
        ray: &Ray<R>,
        t: R,
        prim: &Prim<R>,
        material: &ir::Material,
    ) -> Surface<R> {
        let textured = material.texture.is_some();
        match &prim.shape {
            Shape::Sphere(s) => sphere_surface(s, ray, t, textured),
            Shape::Rect(r) => rect_surface(r, ray, t, textured),
        }
    }

    /// The surface colour: the texel at `uv`, or the material colour.
    #[inline(always)]
    pub(super) fn albedo(
        &self,
        material: &ir::Material,
        uv: Option<(f64, f64)>,
        counters: &mut Counters,
    ) -> DVec3 {
        match (material.texture, uv) {
            (Some(texture), Some((u, v))) => {
                counters.texture_lookups += 1;
                if !(u.is_finite() && v.is_finite()) {
                    counters.non_finite += 1;
                }
                texel(&self.scene.textures[texture], u, v)
            }
            _ => material.color,
        }
    }

    /// Ambient plus every light a shadow ray reaches, times the albedo,
    /// for a ray along `dir`. `color` and `weight` (the weight this local
    /// light will be added with) are the path so far, for the saturation
    /// skip.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn local(
        &self,
        surface: &Surface<R>,
        dir: R::Vec,
        slot: u32,
        albedo: DVec3,
        color: DVec3,
        weight: f64,
        counters: &mut Counters,
    ) -> DVec3 {
        let mut local = albedo * self.model.ambient;
        for light in &self.lights {
            let step = self.light_step(light, surface, dir, slot, albedo, color, weight, local);
            counters.shadow_rays_skipped += u64::from(step.skipped);
            if step.cast {
                counters.shadow_rays += 1;
                if !self.shadows || !self.world.occluded(&step.ray, step.reach) {
                    local += step.lit;
                }
            }
        }
        local
    }

    /// What `light` does at `surface` (on primitive `slot`, of colour
    /// `albedo`), where the path so far is `color`, its weight `weight`
    /// and the local light of the lights before `local`: everything up to
    /// the shadow ray's test, computed whatever the outcome.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn light_step(
        &self,
        light: &Light<R>,
        surface: &Surface<R>,
        dir: R::Vec,
        slot: u32,
        albedo: DVec3,
        color: DVec3,
        weight: f64,
        local: DVec3,
    ) -> LightStep<R> {
        let contribution = albedo * light.color;
        let to_light = light.position - surface.point;
        let length = to_light.length();
        // A light at the hit point has no direction to normalise (it would
        // be NaN): it lights nothing there, and is not counted as skipped.
        let at_light = length.is_zero();
        let towards = to_light * length.recip();
        let cos = surface.normal.dot(towards).wide();
        // A black surface still shows a highlight when the model has one.
        let black = contribution.cmpeq(DVec3::ZERO).all() & (self.model.specular <= 0.0);
        let skipped =
            !at_light & self.skip & ((cos <= 0.0) | black | saturated(color + local * weight));
        let origin = offset_origin::<R>(surface.point, surface.normal, surface.error_scale);
        let to_light = light.position - origin;
        let distance = to_light.length();
        LightStep {
            skipped,
            // A light at the offset origin: nothing lies between.
            cast: !at_light & !skipped & !distance.is_zero(),
            ray: Ray {
                origin,
                dir: to_light * distance.recip(),
                from: slot,
            },
            reach: distance * R::SHADOW_REACH,
            // `cos · 1` with the default diffuse weight: the same bits.
            lit: contribution * (cos.max(0.0) * self.model.diffuse)
                + self.highlight(light, surface, dir, towards, cos),
        }
    }

    /// The white Phong highlight of `light` (towards it: `towards`, at
    /// cosine `cos` to the normal) seen along `dir`: `k_s·I·max(0,
    /// R·V)^n`, black when the model has none.
    #[inline(always)]
    fn highlight(
        &self,
        light: &Light<R>,
        surface: &Surface<R>,
        dir: R::Vec,
        towards: R::Vec,
        cos: f64,
    ) -> DVec3 {
        if self.model.specular <= 0.0 || cos <= 0.0 {
            return DVec3::ZERO;
        }
        let n = surface.normal;
        let mirror = dir - n * (R::of(2.0) * dir.dot(n));
        let alignment = mirror.dot(towards).wide();
        if alignment <= 0.0 {
            return DVec3::ZERO;
        }
        light.color * (self.model.specular * alignment.powf(self.model.exponent))
    }
}

/// What one light does at a surface, short of testing its shadow ray
/// ([`Tracer::light_step`]).
struct LightStep<R: Real> {
    /// Not cast, as it cannot change the 8-bit result (counted).
    skipped: bool,
    /// Cast along `ray` up to `reach`.
    cast: bool,
    ray: Ray<R>,
    reach: R,
    /// What the light adds when its shadow ray reaches it.
    lit: DVec3,
}

/// [`Tracer::surface`] of a sphere, for one ray or a lane of many.
#[inline(always)]
fn sphere_surface<R: Real>(s: &Sphere<R>, ray: &Ray<R>, t: R, textured: bool) -> Surface<R> {
    let along = ray.origin + ray.dir * t;
    let outward = (along - s.center).normalize();
    let point = s.center + outward * s.radius;
    let uv = textured.then(|| sphere_uv(outward.wide()));
    facing(ray, point, outward, uv, s.center)
}

/// [`Tracer::surface`] of a rectangle, for one ray or a lane of many.
#[inline(always)]
fn rect_surface<R: Real>(r: &Rect<R>, ray: &Ray<R>, t: R, textured: bool) -> Surface<R> {
    let along = ray.origin + ray.dir * t;
    let (x, y) = r.plane_coordinates(along);
    let uv = textured.then(|| {
        let width = (r.half_width + r.half_width).wide();
        let height = (r.half_height + r.half_height).wide();
        (x.wide() / width + 0.5, y.wide() / height + 0.5)
    });
    facing(ray, r.point(x, y), r.normal, uv, r.center)
}

/// The surface at `point` of a primitive centred at `center`, its normal
/// turned to face `ray`.
#[inline(always)]
fn facing<R: Real>(
    ray: &Ray<R>,
    point: R::Vec,
    normal: R::Vec,
    uv: Option<(f64, f64)>,
    center: R::Vec,
) -> Surface<R> {
    let normal = if normal.dot(ray.dir) > R::zero() {
        -normal
    } else {
        normal
    };
    Surface {
        point,
        normal,
        uv,
        error_scale: error_scale::<R>(center, point),
    }
}

/// Every channel at 1 or above: more light cannot change the clamped value.
fn saturated(color: DVec3) -> bool {
    color.min_element() >= 1.0
}

/// The sphere mapping of docs/rendering.md, from the outward unit normal.
pub fn sphere_uv(m: DVec3) -> (f64, f64) {
    let u = 0.5 + m.z.atan2(m.x) / std::f64::consts::TAU;
    let v = 0.5 + m.y.clamp(-1.0, 1.0).asin() / std::f64::consts::PI;
    (u, v)
}

/// The nearest texel, row 0 at the top: `x = min(⌊u·w⌋, w−1)`,
/// `y = min(⌊(1−v)·h⌋, h−1)`. Coordinates a rounding step outside [0, 1]
/// land on the edge texel.
///
/// Total for any texture and any coordinates: the loader refuses an image
/// without texels, but a texture whose texels do not fill `w × h` (which
/// no loader builds) reads black where they are missing instead of
/// indexing out of range.
pub fn texel(texture: &ir::Texture, u: f64, v: f64) -> DVec3 {
    debug_assert!(
        u.is_finite() && v.is_finite(),
        "texture lookup at ({u}, {v})"
    );
    let (w, h) = (texture.width as usize, texture.height as usize);
    // `as usize` truncates, which is the floor for values ≥ 0, and
    // saturates: negative values (and NaN) become 0. (`floor` itself is a
    // libm call on baseline x86-64.)
    let x = ((u * w as f64) as usize).min(w.saturating_sub(1));
    let y = (((1.0 - v) * h as f64) as usize).min(h.saturating_sub(1));
    texture
        .texels
        .get(y * w + x)
        .map_or(DVec3::ZERO, |&[r, g, b]| {
            DVec3::new(f64::from(r), f64::from(g), f64::from(b))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texel_lookup_follows_the_spec_and_clamps_edges() {
        let texture = ir::Texture {
            path: "t.ppm".into(),
            format: raytracer_scene::texture::TextureFormat::Ppm,
            width: 2,
            height: 2,
            texels: vec![[0.0; 3], [0.25; 3], [0.5; 3], [1.0; 3]],
        };
        // Row 0 is the top: v near 1 reads row 0.
        assert_eq!(texel(&texture, 0.1, 0.9), DVec3::splat(0.0));
        assert_eq!(texel(&texture, 0.9, 0.9), DVec3::splat(0.25));
        assert_eq!(texel(&texture, 0.1, 0.1), DVec3::splat(0.5));
        assert_eq!(texel(&texture, 1.0, 0.0), DVec3::splat(1.0));
        assert_eq!(texel(&texture, -1e-17, 1.0 + 1e-17), DVec3::splat(0.0));
    }

    /// The colour of [`unit_sphere_lit_from`]'s sphere.
    const UNIT_SPHERE_ALBEDO: DVec3 = DVec3::new(0.5, 0.25, 1.0);

    /// A one-pixel scene: a sphere of radius 1 at `(0, 0, −5)`, of colour
    /// [`UNIT_SPHERE_ALBEDO`] and `reflectivity`, lit by one white light at
    /// `light`.
    fn unit_sphere_lit_from(light: DVec3, reflectivity: f64) -> ir::Scene {
        ir::Scene {
            resolution: 1,
            objects: vec![ir::Object {
                shape: ir::Shape::Sphere {
                    center: DVec3::new(0.0, 0.0, -5.0),
                    radius: 1.0,
                },
                material: 0,
            }],
            materials: vec![ir::Material {
                color: UNIT_SPHERE_ALBEDO,
                reflectivity,
                texture: None,
            }],
            lights: vec![ir::Light {
                position: light,
                color: DVec3::ONE,
            }],
            textures: Vec::new(),
            effects: ir::Effects::default(),
        }
    }

    /// A light exactly at the hit point (the sphere's front pole, which
    /// the centre ray hits and the reprojection puts exactly at
    /// `(0, 0, −4)`) is skipped before its direction would be normalised:
    /// ambient only, no shadow ray, nothing non-finite, in both precisions.
    #[test]
    fn a_light_at_distance_zero_is_skipped_not_normalised() {
        let scene = unit_sphere_lit_from(DVec3::new(0.0, 0.0, -4.0), 0.0);
        for skip in [true, false] {
            let mut counters = Counters::default();
            let ray = crate::render::camera_ray::<f64>(1, 0.5, 0.5);
            let color = Tracer::<f64>::new(&scene, 8, skip).radiance(ray, &mut counters);
            assert_eq!(color, UNIT_SPHERE_ALBEDO * AMBIENT);
            let ray = crate::render::camera_ray::<f32>(1, 0.5, 0.5);
            let color32 = Tracer::<f32>::new(&scene, 8, skip).radiance(ray, &mut counters);
            assert_eq!(color32, color);
            assert_eq!((counters.shadow_rays, counters.non_finite), (0, 0));
        }
    }

    /// Another model's constants: ambient and diffuse weights, a
    /// highlight, blended reflection, at the front pole of a sphere lit
    /// from the eye (`N·L = R·V = 1`), whose reflection sees nothing.
    #[test]
    fn a_models_constants_weigh_the_terms() {
        use super::super::model::{Model, Reflection};
        let albedo = UNIT_SPHERE_ALBEDO;
        let seen = |reflectivity: f64, model: Model| {
            let scene = unit_sphere_lit_from(DVec3::ZERO, reflectivity);
            let tracer = Tracer::<f64>::new(&scene, 8, false).with_model(model);
            let ray = crate::render::camera_ray::<f64>(1, 0.5, 0.5);
            tracer.radiance(ray, &mut Counters::default())
        };
        let close = |a: DVec3, b: DVec3| (a - b).abs().max_element() < 1e-12;
        assert!(close(seen(0.0, Model::default()), albedo * 1.1));
        let other = Model {
            ambient: 0.2,
            diffuse: 0.7,
            specular: 0.5,
            exponent: 20.0,
            ..Model::default()
        };
        assert!(close(seen(0.0, other), albedo * 0.9 + DVec3::splat(0.5)));
        let blended = Model {
            reflection: Reflection::Blended,
            ..Model::default()
        };
        assert!(close(seen(0.5, Model::default()), albedo * 1.1));
        assert!(close(seen(0.5, blended), albedo * 0.55));
    }

    #[test]
    fn sphere_uv_matches_the_spec_at_the_axes() {
        assert_eq!(sphere_uv(DVec3::X), (0.5, 0.5));
        assert_eq!(sphere_uv(DVec3::Y).1, 1.0);
        assert_eq!(sphere_uv(DVec3::Z), (0.75, 0.5));
    }
}
