//! The first bounces of a row's camera rays, shaded several at a time.
//!
//! In a scene of a few primitives tested one by one
//! ([`World::scans_few`](crate::render::world::World::scans_few)),
//! [`Tracer::paths`] groups a row's first hits by the primitive they hit
//! and runs each group's bounce as loops over its rays, laid out per axis
//! (structure of arrays): the surfaces; the albedo, one texel at a time;
//! then for each light the shadow rays' set-up, their any-hit test against
//! every primitive and the light they let through. The compiler vectorises
//! these loops for AVX2 (four `f64` lanes), chosen at run time as for the
//! first hits. Each step calls the function the tracer calls for one ray
//! (`sphere_surface`, `rect_surface`, [`Tracer::albedo`],
//! [`Tracer::light_step`], and the shapes' branch-free tests as
//! [`World::closest_fan`](crate::render::world::World::closest_fan)
//! does), with the path's colour and weight at their values at a first
//! bounce, and a shadow ray that is not cast changes nothing, so every
//! value has the bits a ray at a time gives it. Each path then goes on
//! ray by ray from its first bounce ([`Tracer::onwards`]).

use glam::DVec3;

use super::{Counters, Light, Surface, Tracer, AMBIENT};
use crate::render::geometry::{Ray, Rect, Shape};
use crate::render::real::{Real, Vector};

/// A row's camera rays, their directions per axis, and what they first
/// hit, as [`Tracer::first_hits`] found it (`distances[k]` is ∞ where ray
/// `k` misses).
pub struct FirstHits<'a, R: Real> {
    pub dirs: [&'a [R]; 3],
    pub distances: &'a [R],
    pub slots: &'a [u32],
}

/// Room for the bounces of a group of rays, one entry per ray (per axis
/// for vectors, per channel for colours); kept from row to row.
#[derive(Default)]
pub struct Lanes<R: Real> {
    /// The rays of the row that hit each primitive, by index.
    groups: Vec<Vec<u32>>,
    /// The ray's index in its row.
    pixel: Vec<u32>,
    dir: [Vec<R>; 3],
    t: Vec<R>,
    point: [Vec<R>; 3],
    normal: [Vec<R>; 3],
    error_scale: Vec<R>,
    uv: [Vec<f64>; 2],
    albedo: [Vec<f64>; 3],
    local: [Vec<f64>; 3],
    /// One light's shadow rays.
    origin: [Vec<R>; 3],
    shadow_dir: [Vec<R>; 3],
    reach: Vec<R>,
    lit: [Vec<f64>; 3],
    cast: Vec<bool>,
    skipped: Vec<bool>,
    blocked: Vec<bool>,
}

impl<R: Real> Lanes<R> {
    /// Sorts the rays of `hits` that hit something into one list per
    /// primitive, of `prims` (in one pass over the row).
    fn sort(&mut self, hits: &FirstHits<'_, R>, prims: usize) {
        self.groups.resize_with(prims, Vec::new);
        for group in &mut self.groups {
            group.clear();
        }
        for (k, (&t, &slot)) in hits.distances.iter().zip(hits.slots).enumerate() {
            if t != R::infinity() {
                self.groups[slot as usize].push(k as u32);
            }
        }
    }

    /// Takes the rays that hit the primitive in `slot` (after
    /// [`Lanes::sort`]), and makes room for their bounces; returns how
    /// many there are.
    fn gather(&mut self, hits: &FirstHits<'_, R>, slot: u32) -> usize {
        std::mem::swap(&mut self.pixel, &mut self.groups[slot as usize]);
        let n = self.pixel.len();
        // Buffers only grow, so that a smaller group does not refill them.
        fn fit<T: Copy>(buffer: &mut Vec<T>, n: usize, fill: T) {
            if buffer.len() < n {
                buffer.resize(n, fill);
            }
        }
        let reals = (self.dir.iter_mut().chain(&mut self.point))
            .chain(&mut self.normal)
            .chain(&mut self.origin)
            .chain(&mut self.shadow_dir)
            .chain([&mut self.t, &mut self.error_scale, &mut self.reach]);
        for buffer in reals {
            fit(buffer, n, R::zero());
        }
        let channels = (self.uv.iter_mut().chain(&mut self.albedo))
            .chain(&mut self.local)
            .chain(&mut self.lit);
        for buffer in channels {
            fit(buffer, n, 0.0);
        }
        for buffer in [&mut self.cast, &mut self.skipped, &mut self.blocked] {
            fit(buffer, n, false);
        }
        let [x, y, z] = hits.dirs;
        for (i, &k) in self.pixel.iter().enumerate() {
            let k = k as usize;
            (self.dir[0][i], self.dir[1][i], self.dir[2][i]) = (x[k], y[k], z[k]);
            self.t[i] = hits.distances[k];
        }
        n
    }
}

impl<R: Real> Tracer<'_, R> {
    /// [`Tracer::paths`] in a scene of a few primitives: the first bounces
    /// of each primitive's rays in lanes, then each path on its own.
    pub(super) fn first_bounces(
        &self,
        eye: R::Vec,
        hits: FirstHits<'_, R>,
        lanes: &mut Lanes<R>,
        counters: &mut Counters,
        put: &mut impl FnMut(usize, DVec3),
    ) {
        lanes.sort(&hits, self.world.prims.len());
        for (slot, prim) in self.world.prims.iter().enumerate() {
            let slot = slot as u32;
            let n = lanes.gather(&hits, slot);
            if n == 0 {
                continue;
            }
            self.bounce_lanes(eye, slot, lanes, counters);
            let k = self.world.materials[prim.material as usize].reflectivity;
            for i in 0..n {
                let at = |v: &[Vec<R>; 3]| R::Vec::new(v[0][i], v[1][i], v[2][i]);
                let surface = Surface {
                    point: at(&lanes.point),
                    normal: at(&lanes.normal),
                    uv: None,
                    error_scale: lanes.error_scale[i],
                };
                let ray = Ray::from_lanes(
                    eye,
                    (lanes.dir[0][i], lanes.dir[1][i], lanes.dir[2][i]),
                    Ray::<R>::FROM_NO_PRIMITIVE,
                );
                let [r, g, b] = &lanes.local;
                let local = DVec3::new(r[i], g[i], b[i]);
                let color = self.onwards(ray, slot, surface, local, k, counters);
                put(lanes.pixel[i] as usize, color);
            }
        }
    }

    /// The first bounce of the rays `lanes` holds, which hit the primitive
    /// in `slot`: their local light, in `lanes.local`. In AVX2 lanes where
    /// the processor has them.
    fn bounce_lanes(&self, eye: R::Vec, slot: u32, lanes: &mut Lanes<R>, counters: &mut Counters) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2, the one feature it enables.
            unsafe { self.bounce_lanes_avx2(eye, slot, lanes, counters) };
            return;
        }
        self.bounce_in_lanes(eye, slot, lanes, counters);
    }

    /// [`Tracer::bounce_in_lanes`] compiled for AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn bounce_lanes_avx2(
        &self,
        eye: R::Vec,
        slot: u32,
        lanes: &mut Lanes<R>,
        counters: &mut Counters,
    ) {
        self.bounce_in_lanes(eye, slot, lanes, counters);
    }

    /// [`Tracer::bounce_lanes`], loops the compiler vectorises.
    #[inline(always)]
    fn bounce_in_lanes(
        &self,
        eye: R::Vec,
        slot: u32,
        lanes: &mut Lanes<R>,
        counters: &mut Counters,
    ) {
        let prim = &self.world.prims[slot as usize];
        let material = &self.world.materials[prim.material as usize];
        let textured = material.texture.is_some();
        // One loop per shape and per texturing, so that none branches.
        match (&prim.shape, textured) {
            (Shape::Sphere(s), false) => {
                surfaces(lanes, eye, |ray, t| super::sphere_surface(s, ray, t, false))
            }
            (Shape::Sphere(s), true) => {
                surfaces(lanes, eye, |ray, t| super::sphere_surface(s, ray, t, true))
            }
            (Shape::Rect(r), false) => {
                let r: Rect<R> = **r;
                surfaces(lanes, eye, |ray, t| super::rect_surface(&r, ray, t, false));
            }
            (Shape::Rect(r), true) => {
                let r: Rect<R> = **r;
                surfaces(lanes, eye, |ray, t| super::rect_surface(&r, ray, t, true));
            }
        }
        let n = lanes.pixel.len();
        for i in 0..n {
            let uv = textured.then(|| (lanes.uv[0][i], lanes.uv[1][i]));
            let albedo = self.albedo(material, uv, counters);
            let local = albedo * AMBIENT;
            for c in 0..3 {
                lanes.albedo[c][i] = albedo[c];
                lanes.local[c][i] = local[c];
            }
        }
        for light in &self.lights {
            self.light_steps(light, slot, lanes);
            let count = |flags: &[bool]| flags.iter().filter(|&&flag| flag).count() as u64;
            counters.shadow_rays_skipped += count(&lanes.skipped[..n]);
            counters.shadow_rays += count(&lanes.cast[..n]);
            self.world.occluded_lanes(
                lanes.origin.each_ref().map(|v| &v[..n]),
                lanes.shadow_dir.each_ref().map(|v| &v[..n]),
                &lanes.reach[..n],
                slot,
                &mut lanes.blocked[..n],
            );
            let cast = &lanes.cast[..n];
            let blocked = &lanes.blocked[..n];
            for (local, lit) in lanes.local.iter_mut().zip(&lanes.lit) {
                let (local, lit) = (&mut local[..n], &lit[..n]);
                for i in 0..n {
                    local[i] = if cast[i] & !blocked[i] {
                        local[i] + lit[i]
                    } else {
                        local[i]
                    };
                }
            }
        }
    }

    /// [`Tracer::light_step`] of `light` at every surface of `lanes`, on
    /// the primitive in `slot`, at a first bounce (the path's colour black,
    /// its weight 1).
    #[inline(always)]
    fn light_steps(&self, light: &Light<R>, slot: u32, lanes: &mut Lanes<R>) {
        let n = lanes.pixel.len();
        fn first<T>(v: &[Vec<T>; 3], n: usize) -> [&[T]; 3] {
            v.each_ref().map(|v| &v[..n])
        }
        let Lanes {
            point,
            normal,
            error_scale,
            albedo,
            local,
            origin,
            shadow_dir,
            lit,
            reach,
            cast,
            skipped,
            ..
        } = lanes;
        let at = SurfaceLanes {
            point: first(point, n),
            normal: first(normal, n),
            error_scale: &error_scale[..n],
            albedo: first(albedo, n),
            local: first(local, n),
        };
        let [ox, oy, oz] = origin.each_mut().map(|v| &mut v[..n]);
        let [sx, sy, sz] = shadow_dir.each_mut().map(|v| &mut v[..n]);
        let [tr, tg, tb] = lit.each_mut().map(|v| &mut v[..n]);
        self.light_steps_into(
            light,
            slot,
            at,
            ox,
            oy,
            oz,
            sx,
            sy,
            sz,
            tr,
            tg,
            tb,
            &mut reach[..n],
            &mut cast[..n],
            &mut skipped[..n],
        );
    }

    /// [`Tracer::light_steps`] into its outputs: the shadow rays' origins
    /// and directions, the light they carry, their reach, whether each is
    /// cast or skipped. Each output is an argument of its own (not an
    /// array or a struct of slices), which the compiler knows overlaps no
    /// other memory, so it vectorises the loop with no run-time overlap
    /// checks (which it gives up on beyond a few).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn light_steps_into(
        &self,
        light: &Light<R>,
        slot: u32,
        at: SurfaceLanes<'_, R>,
        ox: &mut [R],
        oy: &mut [R],
        oz: &mut [R],
        sx: &mut [R],
        sy: &mut [R],
        sz: &mut [R],
        tr: &mut [f64],
        tg: &mut [f64],
        tb: &mut [f64],
        reach: &mut [R],
        cast: &mut [bool],
        skipped: &mut [bool],
    ) {
        let n = at.error_scale.len();
        let ([px, py, pz], [nx, ny, nz]) = (at.point, at.normal);
        let ([ar, ag, ab], [lr, lg, lb]) = (at.albedo, at.local);
        let (ox, oy, oz) = (&mut ox[..n], &mut oy[..n], &mut oz[..n]);
        let (sx, sy, sz) = (&mut sx[..n], &mut sy[..n], &mut sz[..n]);
        let (tr, tg, tb) = (&mut tr[..n], &mut tg[..n], &mut tb[..n]);
        let (reach, cast, skipped) = (&mut reach[..n], &mut cast[..n], &mut skipped[..n]);
        for i in 0..n {
            let surface = Surface {
                point: R::Vec::new(px[i], py[i], pz[i]),
                normal: R::Vec::new(nx[i], ny[i], nz[i]),
                uv: None,
                error_scale: at.error_scale[i],
            };
            let albedo = DVec3::new(ar[i], ag[i], ab[i]);
            let local = DVec3::new(lr[i], lg[i], lb[i]);
            let step = self.light_step(light, &surface, slot, albedo, DVec3::ZERO, 1.0, local);
            let (origin, dir) = (step.ray.origin, step.ray.dir);
            (ox[i], oy[i], oz[i]) = (origin.x(), origin.y(), origin.z());
            (sx[i], sy[i], sz[i]) = (dir.x(), dir.y(), dir.z());
            (tr[i], tg[i], tb[i]) = (step.lit.x, step.lit.y, step.lit.z);
            reach[i] = step.reach;
            cast[i] = step.cast;
            skipped[i] = step.skipped;
        }
    }
}

/// The surfaces of a group, per axis and per channel, with the albedo and
/// the local light so far.
struct SurfaceLanes<'a, R: Real> {
    point: [&'a [R]; 3],
    normal: [&'a [R]; 3],
    error_scale: &'a [R],
    albedo: [&'a [f64]; 3],
    local: [&'a [f64]; 3],
}

/// The surfaces where the rays of `lanes`, from `eye`, meet a primitive,
/// as `surface_of` finds one from a ray and its `t`.
#[inline(always)]
fn surfaces<R: Real>(
    lanes: &mut Lanes<R>,
    eye: R::Vec,
    surface_of: impl Fn(&Ray<R>, R) -> Surface<R>,
) {
    let n = lanes.pixel.len();
    let [dx, dy, dz] = lanes.dir.each_ref().map(|v| &v[..n]);
    let t = &lanes.t[..n];
    let [px, py, pz] = lanes.point.each_mut().map(|v| &mut v[..n]);
    let [nx, ny, nz] = lanes.normal.each_mut().map(|v| &mut v[..n]);
    let [u, v] = lanes.uv.each_mut().map(|v| &mut v[..n]);
    let error_scale = &mut lanes.error_scale[..n];
    for i in 0..n {
        let ray = Ray::from_lanes(eye, (dx[i], dy[i], dz[i]), Ray::<R>::FROM_NO_PRIMITIVE);
        let surface = surface_of(&ray, t[i]);
        let (point, normal) = (surface.point, surface.normal);
        (px[i], py[i], pz[i]) = (point.x(), point.y(), point.z());
        (nx[i], ny[i], nz[i]) = (normal.x(), normal.y(), normal.z());
        error_scale[i] = surface.error_scale;
        if let Some((a, b)) = surface.uv {
            (u[i], v[i]) = (a, b);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir;
    use crate::render::prim::Hit;
    use crate::render::world::Accel;
    use crate::render::{camera_ray, eye};

    /// The shared sphere on its floor, the sphere reflecting, either
    /// textured, lit by `lights`, at 25².
    fn scene(sphere_texture: bool, rect_texture: bool, lights: Vec<ir::Light>) -> ir::Scene {
        let checker = ir::Texture {
            path: "checker.ppm".into(),
            format: crate::texture::TextureFormat::Ppm,
            width: 4,
            height: 4,
            texels: (0..16)
                .map(|k| [(k % 3) as f32 / 2.0, 0.5, ((k / 4) % 2) as f32])
                .collect(),
        };
        let mut scene = crate::render::fixture::sphere_on_floor(0.7);
        scene.resolution = 25;
        for (material, textured) in scene
            .materials
            .iter_mut()
            .zip([sphere_texture, rect_texture])
        {
            material.texture = textured.then_some(0);
        }
        scene.lights = lights;
        scene.textures = vec![checker];
        scene
    }

    /// [`Tracer::paths`] with the first bounces in lanes (AVX2 where the
    /// processor has it) gives every pixel bit for bit, and the same
    /// counts, as [`Tracer::path`] ray by ray: textured and untextured
    /// spheres and rectangles, lights in front, behind, black, bright
    /// enough to saturate, and one exactly at the hit point of the centre
    /// ray (the sphere's front pole), with skipping on and off, in both
    /// precisions; and the bounce loops compiled for AVX2 give what the
    /// same loops give as the baseline compiles them.
    #[test]
    fn lanes_shade_as_a_ray_at_a_time() {
        fn check<R: Real>(scene: &ir::Scene, skip: bool) -> Counters {
            let tracer = Tracer::<R>::with_accel(scene, 8, skip, Accel::Brute);
            assert!(tracer.world.scans_few());
            let size = scene.resolution;
            let (mut by_lanes, mut by_ray) = (Counters::default(), Counters::default());
            let mut lanes = Lanes::default();
            let mut bounces_compared = 0;
            for j in 0..size {
                let rays: Vec<Ray<R>> = (0..size)
                    .map(|i| camera_ray::<R>(size, f64::from(i) + 0.5, f64::from(j) + 0.5))
                    .collect();
                let dirs = [0, 1, 2].map(|a| {
                    let axis = |d: R::Vec| [d.x(), d.y(), d.z()][a];
                    rays.iter().map(|r| axis(r.dir)).collect::<Vec<R>>()
                });
                let dirs = [&dirs[0][..], &dirs[1][..], &dirs[2][..]];
                let mut distances = vec![R::zero(); size as usize];
                let mut slots = vec![0; size as usize];
                tracer.first_hits(eye::<R>(), dirs, &mut distances, &mut slots);
                let mut row = vec![None; size as usize];
                let hits = FirstHits {
                    dirs,
                    distances: &distances,
                    slots: &slots,
                };
                tracer.paths(eye::<R>(), hits, &mut lanes, &mut by_lanes, |i, color| {
                    assert!(row[i].replace(color).is_none(), "pixel {i} twice");
                });
                // The bounce loops as compiled for AVX2 (where the processor
                // has it) and as the baseline compiles them agree too.
                let hits = FirstHits {
                    dirs,
                    distances: &distances,
                    slots: &slots,
                };
                lanes.sort(&hits, tracer.world.prims.len());
                for slot in 0..tracer.world.prims.len() as u32 {
                    let n = lanes.gather(&hits, slot);
                    bounces_compared += n;
                    let local_bits = |lanes: &Lanes<R>| {
                        let channels = lanes.local.each_ref();
                        channels.map(|c| c[..n].iter().map(|x| x.to_bits()).collect::<Vec<_>>())
                    };
                    let (mut dispatched, mut baseline) = (Counters::default(), Counters::default());
                    tracer.bounce_lanes(eye::<R>(), slot, &mut lanes, &mut dispatched);
                    let expected = local_bits(&lanes);
                    tracer.bounce_in_lanes(eye::<R>(), slot, &mut lanes, &mut baseline);
                    assert_eq!(local_bits(&lanes), expected, "row {j}, slot {slot}");
                    assert_eq!(baseline, dispatched);
                }
                for (i, ray) in rays.into_iter().enumerate() {
                    let expected = (distances[i] != R::infinity()).then(|| {
                        let hit = Hit {
                            t: distances[i],
                            slot: slots[i],
                        };
                        tracer.path(ray, hit, &mut by_ray)
                    });
                    let bits = |c: Option<DVec3>| c.map(|c| c.to_array().map(f64::to_bits));
                    assert_eq!(bits(row[i]), bits(expected), "pixel ({i}, {j})");
                }
            }
            assert_eq!(by_lanes, by_ray);
            assert!(bounces_compared > 0);
            by_lanes
        }
        let light = |x, y, z, color: DVec3| ir::Light {
            position: DVec3::new(x, y, z),
            color,
        };
        let warm = DVec3::new(1.0, 0.7, 0.7);
        let lightings = [
            vec![light(-1.0, 2.0, -2.0, warm)],
            vec![
                light(-1.0, 2.0, -2.0, warm),
                light(0.0, 0.5, -9.0, DVec3::ONE),
                light(2.0, 1.0, -3.0, DVec3::ZERO),
                light(1.0, 3.0, -4.0, DVec3::splat(20.0)),
            ],
            vec![light(0.0, 0.0, -4.0, warm), light(0.5, 2.0, -1.0, warm)],
        ];
        let mut seen = Counters::default();
        for lights in lightings {
            for (sphere_texture, rect_texture) in [(false, true), (true, false), (true, true)] {
                let scene = scene(sphere_texture, rect_texture, lights.clone());
                for skip in [true, false] {
                    seen += check::<f64>(&scene, skip);
                    seen += check::<f32>(&scene, skip);
                }
            }
        }
        // Every kind of work and skip happened somewhere.
        let Counters {
            shadow_rays,
            reflection_rays,
            texture_lookups,
            shadow_rays_skipped,
            paths_saturated,
            ..
        } = seen;
        let all = [shadow_rays, reflection_rays, texture_lookups];
        assert!(all.iter().all(|&count| count > 0), "{seen:?}");
        assert!(shadow_rays_skipped > 0 && paths_saturated > 0, "{seen:?}");
    }
}
