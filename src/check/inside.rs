//! The warning for a light strictly inside a sphere, without a record per
//! sphere.
//!
//! The warning names, for each light, the first sphere in the file whose
//! inside holds it, so every valid sphere has to be weighed against lights
//! that may come after it. Keeping each sphere's centre, radius and span
//! until the end would cost 40 bytes a sphere, 40 MB for a scene of a
//! million, a third more than its text. When the spheres come from scene
//! text, this keeps instead one [`Chunk`] per run of [`CHUNK`] valid spheres: the box
//! that holds all of them (widened a little, so that it holds every point
//! the exact test can call inside), and where in the text the run starts
//! and ends. At the end a light outside a chunk's box is outside its
//! spheres; a chunk whose box holds a light that has no answer yet is read
//! again from the text, by the same parser and the same attribute checks
//! that read it the first time, and its spheres are tested exactly. So the
//! warning is the one the whole list gave, at under a byte a sphere. Each
//! chunk is read again at most once, whatever the number of lights, so the
//! worst case (a light inside every box) costs one more reading of the
//! spheres' text; the usual scene, lights away from the crowd, costs none.
//!
//! Spheres read from JSON are kept whole: the scene parser cannot read
//! that text again.

use glam::DVec3;

use crate::ast::SectionKind;
use crate::diagnostic::SourceFile;
use crate::span::Span;
use crate::syntax;

use super::errors::CheckError;
use super::{attributes, format, sections, Checker};

/// Valid spheres per chunk: a chunk's 56 bytes are then under a byte a
/// sphere, and reading one again costs a few microseconds.
const CHUNK: u32 = 64;

/// A valid sphere, as the warning needs it.
#[derive(Clone, Copy, Debug)]
pub struct SphereAt {
    pub center: [f64; 3],
    pub radius: f64,
    /// The sphere's keyword.
    pub span: Span,
}

impl SphereAt {
    /// The exact test: the light is strictly inside.
    fn holds(&self, location: DVec3) -> bool {
        location.distance(DVec3::from_array(self.center)) < self.radius
    }
}

/// A valid light location.
#[derive(Clone, Copy, Debug)]
pub struct LightAt {
    pub location: [f64; 3],
    pub span: Span,
}

/// A run of consecutive valid spheres of scene text.
#[derive(Clone, Copy, Debug)]
struct Chunk {
    /// Corners of a box holding every point inside any of the spheres.
    low: [f64; 3],
    high: [f64; 3],
    /// From the first sphere's keyword to the end of the last sphere.
    start: u32,
    end: u32,
    spheres: u32,
}

impl Chunk {
    fn new(sphere: &SphereAt, end: usize) -> Chunk {
        let mut chunk = Chunk {
            low: [f64::INFINITY; 3],
            high: [f64::NEG_INFINITY; 3],
            start: sphere.span.start() as u32,
            end: 0,
            spheres: 0,
        };
        chunk.add(sphere, end);
        chunk
    }

    /// Widen the box to hold `sphere`, whose section ends at `end`.
    ///
    /// A light the exact test puts inside is within `radius` of the centre
    /// on each axis, give or take a few rounding errors of the distance it
    /// computes (relative 1e-15); the margin of 1e-9 of the coordinates'
    /// size covers those and the rounding of the corners themselves many
    /// times over. Overflow only widens the box.
    fn add(&mut self, sphere: &SphereAt, end: usize) {
        for axis in 0..3 {
            let center = sphere.center[axis];
            let reach = sphere.radius + (center.abs() + sphere.radius) * 1e-9;
            self.low[axis] = self.low[axis].min(center - reach);
            self.high[axis] = self.high[axis].max(center + reach);
        }
        self.end = end as u32;
        self.spheres += 1;
    }

    fn may_hold(&self, location: [f64; 3]) -> bool {
        (0..3).all(|axis| (self.low[axis]..=self.high[axis]).contains(&location[axis]))
    }
}

/// How the spheres are kept until the lights are all known.
#[derive(Debug)]
enum Spheres {
    /// Every valid sphere (spheres read from JSON).
    Kept(Vec<SphereAt>),
    /// Boxes over runs of spheres read from scene text, the last still
    /// open.
    Chunked(Vec<Chunk>),
}

/// The spheres and lights the warning weighs.
#[derive(Debug)]
pub struct LightsInSpheres {
    spheres: Spheres,
    lights: Vec<LightAt>,
}

impl LightsInSpheres {
    /// Spheres kept whole.
    pub fn kept() -> LightsInSpheres {
        LightsInSpheres {
            spheres: Spheres::Kept(Vec::new()),
            lights: Vec::new(),
        }
    }

    /// Spheres kept as chunk boxes, to be read again from the source
    /// text: only for a check fed, in order, the sections that
    /// [`syntax::sections`] reads from that text.
    pub fn chunked() -> LightsInSpheres {
        LightsInSpheres {
            spheres: Spheres::Chunked(Vec::new()),
            lights: Vec::new(),
        }
    }

    /// The next valid sphere, whose section ends at `end`.
    pub fn sphere(&mut self, sphere: SphereAt, end: usize) {
        match &mut self.spheres {
            Spheres::Kept(spheres) => spheres.push(sphere),
            Spheres::Chunked(chunks) => match chunks.last_mut() {
                Some(last) if last.spheres < CHUNK => last.add(&sphere, end),
                _ => chunks.push(Chunk::new(&sphere, end)),
            },
        }
    }

    /// The next valid light.
    pub fn light(&mut self, light: LightAt) {
        self.lights.push(light);
    }

    /// Add the spheres and lights found after these (kept the same way).
    pub fn append(&mut self, later: LightsInSpheres) {
        match (&mut self.spheres, later.spheres) {
            (Spheres::Kept(spheres), Spheres::Kept(more)) => spheres.extend(more),
            (Spheres::Chunked(chunks), Spheres::Chunked(more)) => chunks.extend(more),
            _ => unreachable!("both halves of a check keep spheres the same way"),
        }
        self.lights.extend(later.lights);
    }

    /// One warning per light strictly inside a sphere, naming the first
    /// such sphere, in the order of the lights.
    pub fn warnings(self, source: &SourceFile) -> Vec<CheckError> {
        let mut first_holding: Vec<Option<SphereAt>> = vec![None; self.lights.len()];
        let locations: Vec<DVec3> = self
            .lights
            .iter()
            .map(|l| DVec3::from_array(l.location))
            .collect();
        match &self.spheres {
            Spheres::Kept(spheres) => {
                for (answer, &location) in first_holding.iter_mut().zip(&locations) {
                    *answer = spheres.iter().find(|s| s.holds(location)).copied();
                }
            }
            Spheres::Chunked(chunks) => {
                let mut pending: Vec<usize> = (0..self.lights.len()).collect();
                for chunk in chunks {
                    if pending.is_empty() {
                        break;
                    }
                    let candidates: Vec<usize> = pending
                        .iter()
                        .copied()
                        .filter(|&l| chunk.may_hold(self.lights[l].location))
                        .collect();
                    if candidates.is_empty() {
                        continue;
                    }
                    let spheres = reread(chunk, source);
                    for &light in &candidates {
                        first_holding[light] =
                            spheres.iter().find(|s| s.holds(locations[light])).copied();
                    }
                    pending.retain(|l| first_holding[*l].is_none());
                }
            }
        }
        self.lights
            .iter()
            .zip(first_holding)
            .filter_map(|(light, sphere)| {
                let sphere = sphere?;
                Some(CheckError::LightInsideSphere {
                    light: light.span.into(),
                    sphere: sphere.span.into(),
                    contains: format!(
                        "contains the light: radius {} around `{}`",
                        format::number(sphere.radius),
                        format::vector(sphere.center)
                    ),
                    help: "it lights only the inside of the sphere: move it out".to_string(),
                })
            })
            .collect()
    }
}

/// The valid spheres of `chunk`, read again from the text as the check
/// read them: the same parser, from a section start, and the same
/// attribute checks (their diagnostics, given the first time, are dropped).
fn reread(chunk: &Chunk, source: &SourceFile) -> Vec<SphereAt> {
    let mut scratch = Checker::new(source);
    let mut spheres = Vec::with_capacity(chunk.spheres as usize);
    let text = syntax::sections_between(&source.text, chunk.start as usize, chunk.end as usize);
    for section in text.filter(|s| *s.kind == SectionKind::Sphere) {
        let attrs = attributes::collect(&section, &mut scratch);
        if let (Some(center), Some(radius)) = sections::sphere_geometry(&attrs) {
            spheres.push(SphereAt {
                center: *center,
                radius,
                span: section.kind.span,
            });
        }
        scratch.problems.list.clear();
    }
    debug_assert_eq!(spheres.len(), chunk.spheres as usize, "chunk read again");
    spheres
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use proptest::prelude::*;

    use crate::check::SceneCheck;
    use crate::diagnostic::SourceFile;
    use crate::syntax;

    /// The check's diagnostics for scene `text`, its spheres kept whole or
    /// in chunks.
    fn problems(text: &str, chunked: bool) -> String {
        let (source, _) = SourceFile::from_bytes("t.txt", Path::new("."), text.as_bytes());
        let mut check = SceneCheck::new(&source);
        if chunked {
            check = check.fed_from_scene_text();
        }
        for section in syntax::sections(&source.text) {
            check.section(&section);
        }
        format!("{:?}", check.finish().1)
    }

    fn warned(text: &str) -> usize {
        let chunked = problems(text, true);
        assert_eq!(chunked, problems(text, false));
        chunked.matches("LightInsideSphere").count()
    }

    #[test]
    fn a_light_in_a_box_but_in_no_sphere_is_not_warned() {
        // The light is inside the chunk's box (the sphere's bounding cube)
        // but outside the sphere: the box alone would warn.
        let mut text = String::from("camera 4\nlight location 0.9 0.9 -5 color 1 1 1\n");
        text.push_str("sphere dimension 1 center 0 0 -5\n");
        assert_eq!(warned(&text), 0);
    }

    #[test]
    fn the_exact_test_decides_at_the_last_bit() {
        let sphere = "sphere dimension 1 center 0 0 -5\n";
        let at = |x: &str| format!("camera 4\nlight location {x} 0 -5 color 1 1 1\n{sphere}");
        assert_eq!(warned(&at("1")), 0);
        assert_eq!(warned(&at("0.9999999999999999")), 1);
    }

    #[test]
    fn the_first_holding_sphere_is_named_across_chunks() {
        // A light before 200 spheres, inside the 150th and the 180th only:
        // the warning names the 150th, as the whole list did.
        let mut text = String::from("camera 4\nlight location 50 0 -5 color 1 1 1\n");
        for n in 0..200 {
            let radius = if n == 150 || n == 180 { 200.0 } else { 0.5 };
            text.push_str(&format!("sphere dimension {radius} center {n} 10 -5\n"));
        }
        assert_eq!(warned(&text), 1);
        let named = text.find("sphere dimension 200").unwrap();
        assert!(problems(&text, true).contains(&format!("offset: SourceOffset({named})")));
    }

    /// A section of a scene crowded around the origin, lights among the
    /// spheres, with invalid spheres, planes and comments between.
    fn section() -> impl Strategy<Value = String> {
        let coordinate = prop::sample::select(vec!["-2", "-1", "0", "0.5", "1", "1.25", "2", "-5"]);
        let point = (coordinate.clone(), coordinate.clone(), coordinate);
        let radius = prop::sample::select(vec!["0.25", "1", "1.5", "0", "-1"]);
        prop_oneof![
            6 => (radius, point.clone()).prop_map(|(r, (x, y, z))| {
                format!("sphere dimension {r} center {x} {y} {z}\n")
            }),
            2 => point.prop_map(|(x, y, z)| format!("light location {x} {y} {z} color 1 1 1\n")),
            1 => Just("sphere center 1 2\n# a comment: sphere\n".to_string()),
            1 => Just(
                "plane dimension 1 1 center 0 0 -5 normal 0 0 1 headup 0 1 0\n".to_string()
            ),
        ]
    }

    proptest! {
        /// Chunks and the whole list give the same diagnostics, on scenes
        /// of up to several chunks.
        #[test]
        fn chunks_warn_as_the_whole_list_does(
            sections in prop::collection::vec(section(), 0..300),
        ) {
            let text = format!("camera 4\n{}", sections.concat());
            prop_assert_eq!(problems(&text, true), problems(&text, false));
        }
    }
}
