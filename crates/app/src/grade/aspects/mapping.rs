//! The student's texture mapping, which the assignment leaves open: fitted
//! per textured object among the mappings a tracer may choose, so what
//! a texture looks like on the object is judged under the student's
//! mapping, not ours.
//!
//! On a sphere, any mapping that wraps the image once round the axis
//! with its rows from pole to pole: `u` turned by any offset, `u` running
//! either way round, `v` either way up. On a plane, the image upright,
//! flipped, mirrored or transposed (the eight symmetries of a square).
//! Our probes record the texture coordinates `(u, v)` our renderer used
//! at each pixel and the light it multiplied the texel by
//! ([`Probe::light`]); under a candidate mapping, the colour ours would
//! show there is that light times the texel the candidate reads. The
//! candidate whose luminance explains the student's (in linear light,
//! [`super::tone`]) best, as a straight line `a + b·x` with any gain and
//! ambient (the brightness fit's least squares, by their correlation),
//! is the student's mapping. Only luminance chooses it, never colour, so
//! an ignored light colour stays shading's to catch; and a texture left
//! out (a plain colour) is explained by no candidate, which textures'
//! contrast catches.
//!
//! Turns of a sphere's `u` are searched in steps of 1/64 of a turn, then
//! refined in steps of 1/1024 round the best: a texel of a 512-wide
//! texture.

use super::tone::luminance_of;
use raytracer_render::render::probe::{Buffers, Probe, Wears};
use raytracer_render::render::trace::texel;

/// One mapping of the family: how it turns our coordinates `(u, v)` into
/// the student's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Mapping {
    /// A sphere's: `u` turned by `offset` (a share of a turn), after
    /// running the other way round when `reversed`; `v` upside down when
    /// `flipped`.
    Sphere {
        offset: f64,
        reversed: bool,
        flipped: bool,
    },
    /// A plane's: `u` and `v` swapped when `transposed`, then each
    /// mirrored when its flag is set.
    Plane {
        transposed: bool,
        mirror_u: bool,
        mirror_v: bool,
    },
}

/// Our own mapping, for a sphere or a plane.
pub(super) fn ours(sphere: bool) -> Mapping {
    if sphere {
        Mapping::Sphere {
            offset: 0.0,
            reversed: false,
            flipped: false,
        }
    } else {
        Mapping::Plane {
            transposed: false,
            mirror_u: false,
            mirror_v: false,
        }
    }
}

impl Mapping {
    /// The student's coordinates where ours are `(u, v)`.
    pub fn apply(self, (u, v): (f64, f64)) -> (f64, f64) {
        match self {
            Mapping::Sphere {
                offset,
                reversed,
                flipped,
            } => {
                let u = if reversed { -u } else { u } + offset;
                (u.rem_euclid(1.0), if flipped { 1.0 - v } else { v })
            }
            Mapping::Plane {
                transposed,
                mirror_u,
                mirror_v,
            } => {
                let (u, v) = if transposed { (v, u) } else { (u, v) };
                (
                    if mirror_u { 1.0 - u } else { u },
                    if mirror_v { 1.0 - v } else { v },
                )
            }
        }
    }
}

/// Every mapping of a plane's family, ours first.
fn plane_family() -> Vec<Mapping> {
    (0..8)
        .map(|k| Mapping::Plane {
            transposed: k & 4 != 0,
            mirror_u: k & 1 != 0,
            mirror_v: k & 2 != 0,
        })
        .collect()
}

/// A sphere's mappings turned in `steps` steps of `step` turns either side
/// of `around` (or, with `around` `None`, all the way round from 0), each
/// way round and each way up.
fn sphere_family(around: Option<Mapping>, step: f64, steps: i32) -> Vec<Mapping> {
    let mut family = Vec::new();
    for (reversed, flipped) in [(false, false), (true, false), (false, true), (true, true)] {
        let (centre, range) = match around {
            Some(Mapping::Sphere {
                offset,
                reversed: r,
                flipped: f,
            }) if (r, f) == (reversed, flipped) => (offset, -steps..=steps),
            Some(_) => continue,
            None => (0.0, 0..=steps - 1),
        };
        for k in range {
            family.push(Mapping::Sphere {
                offset: centre + f64::from(k) * step,
                reversed,
                flipped,
            });
        }
    }
    family
}

/// The colour ours would show at pixel `k` (in linear light) if our
/// renderer mapped `wears`' texture by `mapping`: the light there times
/// the texel the mapping reads.
pub(super) fn colour(buffers: &Buffers, wears: Wears, mapping: Mapping, probe: &Probe) -> [f64; 3] {
    let t = texel_at(buffers, wears, mapping, probe);
    let l = probe.light;
    [t[0] * l[0], t[1] * l[1], t[2] * l[2]]
}

/// The texel `mapping` reads of `wears`' texture at `probe`'s point.
pub(super) fn texel_at(
    buffers: &Buffers,
    wears: Wears,
    mapping: Mapping,
    probe: &Probe,
) -> [f64; 3] {
    let (u, v) = mapping.apply(probe.uv.unwrap_or_default());
    let t = texel(&buffers.textures[wears.texture], u, v);
    [t.x, t.y, t.z].map(f64::from)
}

/// What a mapping is fitted to: our probes, and the student's luminance
/// in linear light at pixel `k` ([`super::evidence::Evidence::luminance`]).
pub(super) struct Seen<'a> {
    pub buffers: &'a Buffers,
    pub theirs: &'a dyn Fn(usize) -> f64,
}

/// How well `mapping` explains the student's luminance over pixels `ks`:
/// the squared correlation of theirs with what ours would show, the share
/// a least-squares line `a + b·x` explains (0 when either is flat).
fn explained(seen: &Seen, wears: Wears, mapping: Mapping, ks: &[usize]) -> f64 {
    let n = ks.len() as f64;
    let (mut sx, mut sy, mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for &k in ks {
        let x = luminance_of(colour(
            seen.buffers,
            wears,
            mapping,
            &seen.buffers.centres[k],
        ));
        let y = (seen.theirs)(k);
        sx += x;
        sy += y;
        sxx += x * x;
        syy += y * y;
        sxy += x * y;
    }
    let vx = sxx - sx * sx / n;
    let vy = syy - sy * sy / n;
    let cov = sxy - sx * sy / n;
    if vx <= 0.0 || vy <= 0.0 {
        0.0
    } else {
        cov * cov / (vx * vy)
    }
}

/// The mapping of `candidates` that explains the student's pixels `ks`
/// best; the first of the best on a tie, so ours wins where the texture
/// looks the same under several (a symmetric image).
fn best(seen: &Seen, wears: Wears, ks: &[usize], candidates: Vec<Mapping>) -> (Mapping, f64) {
    candidates
        .into_iter()
        .map(|m| (m, explained(seen, wears, m, ks)))
        .fold(None, |best: Option<(Mapping, f64)>, (m, s)| match best {
            Some((_, b)) if b >= s => best,
            _ => Some((m, s)),
        })
        .expect("every family has a mapping")
}

/// The student's mapping of the texture `wears` on the object whose
/// pixels are `ks`: the mapping of its family that explains them best,
/// with the share of their luminance's variance it explains
/// ([`explained`]; 0 for no pixels).
pub(super) fn fit(seen: &Seen, wears: Wears, ks: &[usize]) -> (Mapping, f64) {
    if ks.is_empty() {
        return (ours(wears.sphere), 0.0);
    }
    if !wears.sphere {
        return best(seen, wears, ks, plane_family());
    }
    let mut candidates = vec![ours(true)];
    candidates.extend(sphere_family(None, 1.0 / 64.0, 64));
    let (coarse, score) = best(seen, wears, ks, candidates);
    let (fine, fine_score) = best(
        seen,
        wears,
        ks,
        sphere_family(Some(coarse), 1.0 / 1024.0, 16),
    );
    if fine_score > score {
        (fine, fine_score)
    } else {
        (coarse, score)
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::super::evidence::{Evidence, Whose};
    use super::*;
    use crate::compare::Picture;
    use raytracer_render::ir;
    use raytracer_render::render::model::Model;
    use raytracer_render::render::probe::{self, Buffers};
    use raytracer_scene::texture::TextureFormat;
    use std::path::Path;

    /// `text`'s scene with its first object wearing a 16 × 8 texture of
    /// uneven greys that no turn, flip or mirror maps onto itself.
    fn scene(text: &str) -> ir::Scene {
        wearing(text, 1)
    }

    /// `text`'s scene with its first `objects` objects wearing the
    /// texture of [`scene`].
    pub(in super::super) fn wearing(text: &str, objects: usize) -> ir::Scene {
        let loaded =
            raytracer_scene::frontend::load_bytes("a.txt", Path::new("."), text.as_bytes());
        let mut scene = ir::lower(loaded.checked.unwrap());
        scene.textures.push(ir::Texture {
            path: "t.ppm".into(),
            format: TextureFormat::Ppm,
            width: 16,
            height: 8,
            texels: (0..128u32)
                .map(|k| [0.2 + 0.08 * ((k % 16 * 7 + k / 16 * 3) % 11) as f32; 3])
                .collect(),
        });
        for object in &scene.objects[..objects] {
            let material = object.material as usize;
            scene.materials[material].texture = Some(0);
        }
        scene
    }

    /// The image a tracer mapping the texture by `mapping` writes (no
    /// highlight, clamped to 8 bits).
    fn picture(buffers: &Buffers, mapping: Mapping) -> Picture {
        let wears = buffers.wears[0].unwrap();
        let rgb = buffers
            .centres
            .iter()
            .flat_map(|p| match p.object {
                Some(0) => colour(buffers, wears, mapping, p).map(|c| (c.min(1.0) * 255.0) as u8),
                _ => [0; 3],
            })
            .collect();
        Picture {
            width: buffers.size,
            height: buffers.size,
            rgb,
        }
    }

    /// The mapping fitted to an image made with `truth`.
    fn fitted(text: &str, truth: Mapping) -> Mapping {
        let buffers = probe::buffers(&scene(text), 4, Model::default());
        let student = picture(&buffers, truth);
        let e = Evidence::new(&buffers, &student, &student);
        let ks = e.pixels_of(0, &|p| p.visible);
        let theirs = |k| e.luminance(Whose::Theirs, k);
        let seen = Seen {
            buffers: &buffers,
            theirs: &theirs,
        };
        fit(&seen, buffers.wears[0].unwrap(), &ks).0
    }

    const SPHERE: &str = "camera 64\nsphere\ndimension 1\ncenter 0 0 -3\ncolor 1 1 1\n\
                          light\nlocation 1 2 0\ncolor 1 1 1\n";

    #[test]
    fn a_spheres_turned_reversed_or_flipped_mapping_is_found() {
        for (offset, reversed, flipped) in
            [(0.3, false, false), (0.55, true, true), (0.0, false, true)]
        {
            let truth = Mapping::Sphere {
                offset,
                reversed,
                flipped,
            };
            let Mapping::Sphere {
                offset: o,
                reversed: r,
                flipped: f,
            } = fitted(SPHERE, truth)
            else {
                panic!("a sphere's mapping");
            };
            let off = (o - offset)
                .rem_euclid(1.0)
                .min((offset - o).rem_euclid(1.0));
            assert!(
                (r, f) == (reversed, flipped) && off < 1.0 / 256.0,
                "{truth:?}: {o} {r} {f}"
            );
        }
    }

    #[test]
    fn a_planes_flipped_mirrored_or_transposed_image_is_found() {
        let plane = "camera 64\nplane\ndimension 2 2\ncenter 0 0 -3\nnormal 0 0 1\n\
                     headup 0 1 0\ncolor 1 1 1\nlight\nlocation 0 0 0\ncolor 1 1 1\n";
        for truth in plane_family() {
            assert_eq!(fitted(plane, truth), truth);
        }
    }

    #[test]
    fn each_mapping_turns_coordinates_as_it_says() {
        let turned = Mapping::Sphere {
            offset: 0.3,
            reversed: true,
            flipped: true,
        };
        let (u, v) = turned.apply((0.1, 0.25));
        assert!((u - 0.2).abs() < 1e-12 && (v - 0.75).abs() < 1e-12);
        let transposed = Mapping::Plane {
            transposed: true,
            mirror_u: true,
            mirror_v: false,
        };
        assert_eq!(transposed.apply((0.1, 0.25)), (0.75, 0.1));
        assert_eq!(ours(true).apply((0.1, 0.25)), (0.1, 0.25));
        assert_eq!(ours(false).apply((0.1, 0.25)), (0.1, 0.25));
    }

    #[test]
    fn the_families_hold_every_symmetry_and_every_turn() {
        assert_eq!(plane_family().len(), 8);
        assert_eq!(plane_family()[0], ours(false));
        let all = sphere_family(None, 1.0 / 64.0, 64);
        assert_eq!(all.len(), 4 * 64);
        let around = sphere_family(Some(all[70]), 1.0 / 1024.0, 16);
        assert_eq!(around.len(), 33);
        assert!(around.iter().all(|m| matches!(
            m,
            Mapping::Sphere {
                reversed: true,
                flipped: false,
                ..
            }
        )));
    }
}
