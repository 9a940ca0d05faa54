//! What our reference sees at each pixel, for judging a student's image
//! aspect by aspect: which object a camera ray meets, which lights reach
//! that point, how much direct light arrives with and without shadows,
//! what the mirror direction meets there, and the texture coordinates
//! with the light a texel is multiplied by there, so a judge can colour
//! the object under another texture mapping than ours.
//!
//! A separate pass from [`super::render`], so the normal render path is
//! untouched: [`buffers`] traces one ray through each pixel centre and one
//! through each pixel corner (`(size + 1)²` of them), in `f64`, and keeps a
//! [`Probe`] of each. A pixel whose five probes agree on a property is
//! *stable* for it: whichever point of the pixel a tracer's camera ray
//! passes through (centre or a corner), it sees the same.

use std::sync::Arc;

use rayon::prelude::*;

use glam::DVec3;

use super::geometry::{offset_origin, Ray};
use super::model::Reflection;
use super::real::Real;
use super::trace::{Counters, Tracer};
use super::{camera_ray, Accel, Model};
use crate::ir;

/// The most lights whose visibility [`Probe::visible`] records.
pub const MAX_PROBED_LIGHTS: usize = 64;

/// How far apart two readings' reflected luminances may be and still be
/// the same: two steps of an 8-bit channel.
pub const SETTLED: f64 = 2.0 / 255.0;

/// What one camera ray of our reference meets.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Probe {
    /// The object (its index in the IR) the ray meets first.
    pub object: Option<u32>,
    /// Bit `i` is set when light `i` lights the point: it lies in front of
    /// the surface and the shadow ray reaches it.
    pub visible: u64,
    /// The luminance of the direct light that arrives, `Σ albedo ⊙ I ·
    /// max(0, N·L̂)` over the lights that reach the point.
    pub lit: f64,
    /// The same sum over every light in front of the surface, as if
    /// nothing cast a shadow.
    pub unshadowed: f64,
    /// Each light in front of the surface, its share of
    /// [`Probe::unshadowed`] and how far it is: what a fit needs of a
    /// tracer whose light falls off with distance (the assignment leaves
    /// that open). Shared: a grader copies whole frames of probes (each
    /// pixel's corner read as its centre), and a copy then allocates
    /// nothing.
    pub lights: Arc<[LightShare]>,
    /// The object's reflectivity (0 for a miss).
    pub reflectivity: f64,
    /// The luminance of the object's colour (or texel) at the point.
    pub albedo: f64,
    /// The object the mirror direction meets (only on a reflective object).
    pub reflected: Option<u32>,
    /// What the mirror direction meets, when it is neither a mirror nor
    /// textured: its [`Probe::albedo`] and [`Probe::lit`] (both 0 for the
    /// background). A tracer shows there `k·(a·albedo + b·lit)` under its
    /// own constants, which ours (in [`Probe::reflected_radiance`]) fixes.
    pub shown: Option<[f64; 2]>,
    /// The luminance of our radiance along the mirror direction, each
    /// channel clamped to 1 (only on a reflective object).
    pub reflected_radiance: f64,
    /// The same radiance tinted by the mirror's own colour, channel by
    /// channel: what a tracer that multiplies a reflection by its
    /// mirror's colour (a coloured metal, a reading the assignment's "try
    /// different things" allows) adds there. On a black mirror it is 0
    /// (only on a reflective object).
    pub reflected_tinted: f64,
    /// What the lights could bring to the points the mirror shows, were
    /// nothing in their way: the luminance along the mirror direction
    /// without shadows less that of ambient light alone. A tracer whose
    /// shadow rays are wrong changes what the mirror shows by up to this
    /// much (only on a reflective object).
    pub reflected_direct: f64,
    /// Whether [`Probe::reflected_radiance`] is the same, within
    /// [`SETTLED`], under every reading the assignment allows: reflection
    /// added or blended, and any depth that recurses at all (two
    /// reflections from the camera or more). Where it is, what a mirror
    /// shows is judged even when it shows another mirror (a black one
    /// showing a coloured object, say); where not, it depends on a choice.
    pub reflection_settled: bool,
    /// The largest cosine between the mirror direction and the direction
    /// to a light that reaches the point: near 1 where a specular highlight
    /// may lie.
    pub highlight: f64,
    /// The texture coordinates, on a textured object.
    pub uv: Option<(f64, f64)>,
    /// Per channel, what our renderer multiplies the object's colour (or
    /// texel) by here, leaving out any highlight: the ambient share plus
    /// `diffuse · I · max(0, N·L̂)` of each light that reaches the point.
    pub light: [f64; 3],
}

/// One light in front of a probed point ([`Probe::lights`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightShare {
    /// Which light of the scene it is (its index in the scene's lights).
    pub light: usize,
    /// Its term of [`Probe::unshadowed`]: `luminance(albedo ⊙ I)·N·L̂`.
    pub lit: f64,
    /// Its distance to the point.
    pub distance: f64,
    /// Whether its shadow ray reaches it (its term is then in
    /// [`Probe::lit`] too).
    pub reaches: bool,
}

/// A textured object: which of [`Buffers::textures`] it wears, and
/// whether it is a sphere (else a plane), which decides the mappings a
/// tracer may choose.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Wears {
    pub texture: usize,
    pub sphere: bool,
}

/// The probes of a whole frame.
#[derive(Clone, Debug)]
pub struct Buffers {
    pub size: u32,
    /// One per pixel centre, row-major, row 0 at the top.
    pub centres: Vec<Probe>,
    /// One per pixel corner, `(size + 1)²`, row-major: corner `(i, j)` is
    /// the top-left corner of pixel `(i, j)`.
    pub corners: Vec<Probe>,
    /// Per object of the IR: whether it is textured.
    pub textured: Vec<bool>,
    /// Per object of the IR: whether it reflects.
    pub reflective: Vec<bool>,
    /// The scene's textures, and per object of the IR the one it wears.
    pub textures: Vec<ir::Texture>,
    pub wears: Vec<Option<Wears>>,
    /// Per object of the IR: its colour, linear RGB (unused when
    /// textured).
    pub colours: Vec<[f64; 3]>,
    /// Each light's colour, in the scene's order.
    pub light_colours: Vec<[f64; 3]>,
    /// The probes of the same scene with each plane's two `dimension`
    /// values swapped, when a plane is not square: the assignment does not
    /// say which runs along `headup`, so a pixel is stable only where
    /// both readings see the same.
    pub swapped: Option<Box<Buffers>>,
}

impl Buffers {
    /// The same frame probed half a pixel up and to the left, as a tracer
    /// whose rays go through pixels' top-left corners sees it: each
    /// pixel's probe is its top-left corner's, and each corner's is the
    /// centre of the pixel up and to the left of it (the nearest pixel's
    /// centre on the top and left edges).
    pub fn through_corners(&self) -> Buffers {
        let size = self.size;
        let centres = (0..size)
            .flat_map(|y| (0..size).map(move |x| (x, y)))
            .map(|(x, y)| self.corner(x, y).clone())
            .collect();
        let corners = (0..=size)
            .flat_map(|y| (0..=size).map(move |x| (x, y)))
            .map(|(x, y)| {
                let back = |v: u32| v.saturating_sub(1).min(size - 1);
                self.centre(back(x), back(y)).clone()
            })
            .collect();
        Buffers {
            size,
            centres,
            corners,
            swapped: self
                .swapped
                .as_ref()
                .map(|other| Box::new(other.through_corners())),
            ..self.clone_without_probes()
        }
    }

    /// This frame's scene facts, with no probes.
    fn clone_without_probes(&self) -> Buffers {
        Buffers {
            size: self.size,
            centres: Vec::new(),
            corners: Vec::new(),
            textured: self.textured.clone(),
            reflective: self.reflective.clone(),
            textures: self.textures.clone(),
            wears: self.wears.clone(),
            colours: self.colours.clone(),
            light_colours: self.light_colours.clone(),
            swapped: None,
        }
    }

    /// The probe at the centre of pixel `(x, y)`.
    pub fn centre(&self, x: u32, y: u32) -> &Probe {
        &self.centres[(y * self.size + x) as usize]
    }

    /// The probe at corner `(x, y)`, `0..=size` each.
    pub fn corner(&self, x: u32, y: u32) -> &Probe {
        &self.corners[(y * (self.size + 1) + x) as usize]
    }

    /// Whether `key` is the same at the centre and the four corners of
    /// pixel `(x, y)`.
    /// With [`Buffers::swapped`], the same must hold there, with the same
    /// key.
    pub fn stable<K: PartialEq>(&self, x: u32, y: u32, key: impl Fn(&Probe) -> K) -> bool {
        let k = key(self.centre(x, y));
        self.agree(x, y, &key, &k)
            && self
                .swapped
                .as_ref()
                .is_none_or(|other| other.agree(x, y, &key, &k))
    }

    /// Whether `key` is `k` at the centre and the four corners of pixel
    /// `(x, y)`, in these probes alone.
    fn agree<K: PartialEq>(&self, x: u32, y: u32, key: &impl Fn(&Probe) -> K, k: &K) -> bool {
        key(self.centre(x, y)) == *k
            && [(x, y), (x + 1, y), (x, y + 1), (x + 1, y + 1)]
                .iter()
                .all(|&(i, j)| key(self.corner(i, j)) == *k)
    }
}

/// Probe `scene` at every pixel centre and corner, reflecting up to
/// `max_depth` times under `model` for [`Probe::reflected_radiance`].
pub fn buffers(scene: &ir::Scene, max_depth: u32, model: Model) -> Buffers {
    let mut main = probe_all(scene, max_depth, model, true);
    settle(&mut main, scene, max_depth, model);
    main.swapped =
        swapped_planes(scene).map(|other| Box::new(probe_all(&other, max_depth, model, false)));
    main
}

/// Fill in [`Probe::reflection_settled`] of `main` (probed at
/// `max_depth` under `model`) from two more passes over the scene when it
/// has a mirror: two reflections from the camera, and the other way of
/// combining a reflection with a mirror's own colour.
fn settle(main: &mut Buffers, scene: &ir::Scene, max_depth: u32, model: Model) {
    let mirrors = main.reflective.iter().any(|&r| r);
    let passes = mirrors.then(|| {
        let other = Model {
            reflection: match model.reflection {
                Reflection::Added => Reflection::Blended,
                Reflection::Blended => Reflection::Added,
            },
            ..model
        };
        // The probe's radiance starts after the first reflection: depth 1
        // there is the second reflection as well.
        [
            probe_all(scene, max_depth.min(1), model, false),
            probe_all(scene, max_depth, other, false),
        ]
    });
    let settle = |probes: &mut [Probe], pick: &dyn Fn(&Buffers) -> &[Probe]| {
        for (k, probe) in probes.iter_mut().enumerate() {
            probe.reflection_settled = match &passes {
                None => true,
                Some(readings) => readings.iter().all(|reading| {
                    (probe.reflected_radiance - pick(reading)[k].reflected_radiance).abs()
                        <= SETTLED
                }),
            };
        }
    };
    settle(&mut main.centres, &|b| &b.centres);
    settle(&mut main.corners, &|b| &b.corners);
}

/// `scene` with each plane's width and height swapped, or `None` when
/// every plane is square.
pub fn swapped_planes(scene: &ir::Scene) -> Option<ir::Scene> {
    let mut other = scene.clone();
    let mut any = false;
    for object in &mut other.objects {
        if let ir::Shape::Rect { width, height, .. } = &mut object.shape {
            if width != height {
                std::mem::swap(width, height);
                any = true;
            }
        }
    }
    any.then_some(other)
}

/// The tracer a frame is probed with, under its reading, and, when the
/// pass records [`Probe::reflected_direct`], the same scene without
/// shadows and with ambient light alone.
struct Probing<'a> {
    tracer: Tracer<'a, f64>,
    /// The tracer without shadows, then the one by ambient light alone.
    direct: Option<[Tracer<'a, f64>; 2]>,
    model: Model,
}

impl<'a> Probing<'a> {
    /// The tracers of a pass; those of [`Probe::reflected_direct`] only
    /// when `direct` (the main pass: the others read what a mirror shows
    /// alone, or which object a pixel sees).
    fn new(scene: &'a ir::Scene, max_depth: u32, model: Model, direct: bool) -> Self {
        let tracer = |model| {
            Tracer::<f64>::with_accel(scene, max_depth, false, Accel::Auto).with_model(model)
        };
        Probing {
            tracer: tracer(model),
            direct: direct.then(|| {
                [
                    tracer(model).without_shadows(),
                    tracer(Model {
                        diffuse: 0.0,
                        specular: 0.0,
                        ..model
                    }),
                ]
            }),
            model,
        }
    }
}

/// What camera ray `ray` meets: a caller of the tracer's parts, apart
/// from the integrator, so the render path is unchanged.
fn probe(probing: &Probing, ray: Ray<f64>) -> Probe {
    probe_to(probing, ray, true)
}

/// [`probe`], following the mirror direction when `reflect`.
fn probe_to(probing: &Probing, ray: Ray<f64>, reflect: bool) -> Probe {
    let Probing { tracer, model, .. } = probing;
    let luminance = |c: DVec3| 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
    let Some(hit) = tracer.world.closest(&ray, f64::INFINITY) else {
        return Probe::default();
    };
    let mut counters = Counters::default();
    let prim = &tracer.world.prims[hit.slot as usize];
    let material = &tracer.world.materials[prim.material as usize];
    let surface = tracer.surface(&ray, hit.t, prim, material);
    let albedo = tracer.albedo(material, surface.uv, &mut counters);
    let d = ray.dir;
    let n = surface.normal;
    let mirror = (d - n * (2.0 * d.dot(n))).normalize();
    let mut probe = Probe {
        object: Some(prim.id),
        reflectivity: material.reflectivity,
        albedo: luminance(albedo),
        uv: surface.uv,
        light: [model.ambient; 3],
        ..Probe::default()
    };
    let origin = offset_origin::<f64>(surface.point, n, surface.error_scale);
    let mut lights = Vec::with_capacity(tracer.lights.len());
    for (i, light) in tracer.lights.iter().enumerate() {
        let to_light = light.position - surface.point;
        let length = to_light.length();
        if length == 0.0 {
            continue;
        }
        let towards = to_light * length.recip();
        let cos = n.dot(towards).wide();
        if cos <= 0.0 {
            continue;
        }
        let lit = luminance(albedo * light.color) * cos;
        probe.unshadowed += lit;
        lights.push(LightShare {
            light: i,
            lit,
            distance: length.wide(),
            reaches: false,
        });
        let to_light = light.position - origin;
        let distance = to_light.length();
        let shadow = Ray {
            origin,
            dir: to_light * distance.recip(),
            from: hit.slot,
        };
        if distance == 0.0
            || !tracer
                .world
                .occluded(&shadow, distance * <f64 as Real>::SHADOW_REACH)
        {
            probe.lit += lit;
            if let Some(share) = lights.last_mut() {
                share.reaches = true;
            }
            for (c, channel) in probe.light.iter_mut().enumerate() {
                *channel += model.diffuse * light.color[c] * cos;
            }
            if i < MAX_PROBED_LIGHTS {
                probe.visible |= 1 << i;
            }
            probe.highlight = probe.highlight.max(mirror.dot(towards).wide());
        }
    }
    if !lights.is_empty() {
        probe.lights = lights.into();
    }
    if material.reflectivity > 0.0 && reflect {
        let reflected = Ray {
            origin,
            dir: mirror,
            from: hit.slot,
        };
        let seen = probe_to(probing, reflected, false);
        probe.reflected = seen.object;
        probe.shown = match seen.object {
            None => Some([0.0, 0.0]),
            Some(_) if seen.reflectivity == 0.0 && seen.uv.is_none() => {
                Some([seen.albedo, seen.lit])
            }
            Some(_) => None,
        };
        let c = tracer.radiance(reflected, &mut counters).min(DVec3::ONE);
        probe.reflected_radiance = luminance(c);
        probe.reflected_tinted = luminance(albedo * c);
        if let Some(direct) = &probing.direct {
            let [shadowless, unlit] = direct
                .each_ref()
                .map(|t| luminance(t.radiance(reflected, &mut counters).min(DVec3::ONE)));
            probe.reflected_direct = shadowless - unlit;
        }
    }
    probe
}

/// [`buffers`] of one reading, recording [`Probe::reflected_direct`]
/// when `direct`.
fn probe_all(scene: &ir::Scene, max_depth: u32, model: Model, direct: bool) -> Buffers {
    let size = scene.resolution;
    let probing = Probing::new(scene, max_depth, model, direct);
    let grid = |n: u32, offset: f64| -> Vec<Probe> {
        (0..n * n)
            .into_par_iter()
            .map(|k| {
                let (x, y) = (k % n, k / n);
                let ray = camera_ray::<f64>(size, f64::from(x) + offset, f64::from(y) + offset);
                probe(&probing, ray)
            })
            .collect()
    };
    Buffers {
        size,
        centres: grid(size, 0.5),
        corners: grid(size + 1, 0.0),
        textured: scene
            .objects
            .iter()
            .map(|o| scene.materials[o.material as usize].texture.is_some())
            .collect(),
        reflective: scene
            .objects
            .iter()
            .map(|o| scene.materials[o.material as usize].reflectivity > 0.0)
            .collect(),
        textures: scene.textures.clone(),
        wears: scene
            .objects
            .iter()
            .map(|o| {
                scene.materials[o.material as usize]
                    .texture
                    .map(|texture| Wears {
                        texture,
                        sphere: matches!(o.shape, ir::Shape::Sphere { .. }),
                    })
            })
            .collect(),
        colours: scene
            .objects
            .iter()
            .map(|o| scene.materials[o.material as usize].color.to_array())
            .collect(),
        light_colours: scene.lights.iter().map(|l| l.color.to_array()).collect(),
        swapped: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn scene(text: &str) -> ir::Scene {
        let loaded =
            raytracer_scene::frontend::load_bytes("a.txt", Path::new("."), text.as_bytes());
        ir::lower(loaded.checked.unwrap())
    }

    #[test]
    fn a_shadowed_floor_and_a_mirror_are_probed() {
        let s = scene(
            "camera 20\nsphere\ndimension .5\ncenter 0 0 -3\ncolor 1 0 0\n\
             plane\ndimension 8 8\ncenter 0 -.5 -3\nnormal 0 1 0\nheadup 0 0 -1\n\
             color 1 1 1\nreflectivity .5\nlight\nlocation 0 3 -3\ncolor 1 1 1\n",
        );
        let b = buffers(&s, 4, Model::default());
        assert_eq!(b.corners.len(), 21 * 21);
        // The middle pixel sees the sphere, lit from above.
        let mid = b.centre(10, 8);
        assert_eq!(mid.object, Some(0));
        // Below the sphere, on the floor: shadowed, and the mirror shows
        // the sphere.
        let floor = b.centre(10, 13);
        assert_eq!(floor.object, Some(1));
        assert_eq!(floor.visible, 0);
        assert!(floor.unshadowed > 0.0 && floor.lit == 0.0);
        assert_eq!(floor.reflected, Some(0));
        assert!(floor.reflected_radiance > 0.0);
        // A white mirror's tint changes nothing.
        assert!((floor.reflected_tinted - floor.reflected_radiance).abs() < 1e-12);
        // The top row misses everything.
        assert_eq!(b.centre(0, 0).object, None);
        assert!(b.stable(0, 0, |p| p.object));
        // A mirror showing a plain sphere shows it under every reading.
        assert!(floor.reflection_settled);
        // What it shows: the sphere's colour, and no light, as the sphere
        // hides its lit top from the floor.
        let shown = floor.shown.expect("a plain sphere");
        assert!(
            (shown[0] - 0.2126).abs() < 1e-9 && shown[1] == 0.0,
            "{shown:?}"
        );
        // The sphere's underside it shows faces away from the light:
        // no shadow ray decides what the floor shows.
        assert!(floor.reflected_direct.abs() < 1e-9, "{floor:?}");
        // The light above: one share, blocked, three units away less the
        // floor's half unit.
        assert_eq!(floor.lights.len(), 1);
        let share = floor.lights[0];
        assert!(!share.reaches && share.lit > 0.0, "{share:?}");
        assert!((share.distance - 3.5).abs() < 0.5, "{share:?}");
    }

    #[test]
    fn what_the_lights_could_bring_to_what_a_mirror_shows_is_probed() {
        // A mirror wall facing the camera shows, straight back, the face
        // of a red sphere behind the camera, which a light to the side
        // lights, or would light but for a small ball in its way.
        let text = |blocker: &str| {
            format!(
                "camera 9\nplane\ndimension 20 20\ncenter 0 0 -8\nnormal 0 0 1\nheadup 0 1 0\n\
                 color 0 0 0\nreflectivity .8\nsphere\ndimension 1.5\ncenter 0 0 3\ncolor 1 0 0\n\
                 {blocker}light\nlocation 3 0 0\ncolor 1 1 1\n"
            )
        };
        let ambient = Model::default().ambient * 0.2126;
        for blocked in [false, true] {
            let ball = "sphere\ndimension .3\ncenter 1.5 0 .75\ncolor 1 1 1\n";
            let b = buffers(
                &scene(&text(if blocked { ball } else { "" })),
                4,
                Model::default(),
            );
            let p = b.centre(4, 4);
            assert_eq!((p.object, p.reflected), (Some(0), Some(1)));
            // Lit, the mirror shows the light's share over the ambient;
            // shadowed, the ambient alone. Either way a tracer's shadow
            // rays decide that share.
            let shown = if blocked {
                ambient
            } else {
                ambient + p.reflected_direct
            };
            assert!((p.reflected_radiance - shown).abs() < 1e-9, "{p:?}");
            assert!(p.reflected_direct > 0.05, "{p:?}");
            // A black mirror tinted by its colour shows nothing.
            assert_eq!(p.reflected_tinted, 0.0, "{p:?}");
        }
    }

    #[test]
    fn through_corners_moves_the_probes_half_a_pixel_up_and_left() {
        let s = scene(
            "camera 8
sphere
dimension .4
center .1 .05 -2
color 1 1 1
             light
location 0 3 0
color 1 1 1
",
        );
        let b = buffers(&s, 2, Model::default());
        let moved = b.through_corners();
        for y in 0..8 {
            for x in 0..8 {
                assert_eq!(moved.centre(x, y), b.corner(x, y));
            }
        }
        for y in 1..=8 {
            for x in 1..=8 {
                let back = |v: u32| (v - 1).min(7);
                assert_eq!(moved.corner(x, y), b.centre(back(x), back(y)));
            }
        }
        assert_eq!(moved.corner(0, 0), b.centre(0, 0));
    }

    #[test]
    fn what_a_mirror_shows_of_a_mirror_is_settled_only_when_every_reading_agrees() {
        // A mirror wall facing the camera; in front of it and to the
        // right, a mirror ball, black or grey, lit: the wall shows it
        // beside the ball itself.
        let text = |ball: &str| {
            format!(
                "camera 21\nplane\ndimension 20 20\ncenter 0 0 -8\nnormal 0 0 1\nheadup 0 1 0\n\
                 color 0 0 0\nreflectivity .8\nsphere\ndimension 1\ncenter 2 0 -4\ncolor {ball}\n\
                 reflectivity .8\nsphere\ndimension 1.5\ncenter 0 0 3\ncolor 1 0 0\n\
                 light\nlocation 0 4 0\ncolor 1 1 1\n"
            )
        };
        let settled = |ball: &str| {
            let b = buffers(&scene(&text(ball)), 8, Model::default());
            // A pixel of the wall left of the ball, whose mirror
            // direction meets the ball.
            let p = b.centre(14, 10);
            assert_eq!((p.object, p.reflected), (Some(0), Some(1)), "{ball}");
            p.reflection_settled
        };
        // Black, the ball shows the red one alike whether a reflection is
        // added or blended; grey, the readings differ by its own colour.
        assert!(settled("0 0 0"));
        assert!(!settled(".5 .5 .5"));
    }
}
