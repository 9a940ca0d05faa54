//! The check pass: validates the AST against every rule of docs/language.md and
//! builds the scene model.
//!
//! Every problem in the file is reported in one run. [`SceneCheck`] takes
//! the sections one at a time, so the front end checks each section as the
//! parser yields it and never holds a large scene's whole syntax tree. The shared attribute
//! checks live in [`attributes`] and the single-attribute rules in [`rules`]
//! (both driven by the registry in [`crate::language`]), the rules between
//! attributes in [`sections`] (with the vector geometry of
//! [`crate::geometry`]), texture files (through the caller's
//! [`TextureLoader`]: the pass does no I/O of its own) in [`textures`], the
//! light-inside-sphere warning in [`inside`], the
//! warning for text-direction controls in [`text_direction`], and the
//! diagnostics themselves in [`errors`], some carrying a structured
//! [`crate::fix::Fix`].

mod attributes;
pub mod errors;
pub mod format;
mod inside;
mod rules;
mod sections;
mod sink;
mod text_direction;
mod textures;

use std::collections::BTreeMap;

use crate::ast::{self, SectionKind};
use crate::diagnostic::SourceFile;
use crate::fix::{Applicability, Fix};
use crate::language;
use crate::limits::{MAX_LIGHTS, MAX_OBJECTS};
use crate::model;
use crate::span::Span;
use crate::suggest;
use crate::texture::{Header, Texture, TextureLoader};

pub use errors::CheckError;
pub use sink::{Collect, Sink, Summarise, Summary};

/// A scene that passed the check pass: its model and the header of each
/// texture, keyed by the path as written in the scene.
#[derive(Clone, Debug)]
pub struct Valid {
    pub scene: model::Scene,
    pub textures: BTreeMap<String, Header>,
}

/// A valid scene with its textures decoded, ready to lower
/// ([`crate::frontend::load`] makes one): the model and each texture,
/// keyed by the path as written in the scene.
#[derive(Clone, Debug)]
pub struct Checked {
    pub scene: model::Scene,
    pub textures: BTreeMap<String, Texture>,
}

/// The check pass, the one way in: fed one section at a time, as the
/// parser (or the JSON reader) yields them, so a caller that drops each
/// section once checked never holds a large scene's whole syntax tree.
/// Each valid object goes to the [`Sink`] `S`: [`Collect`] (the default)
/// builds the model, [`Summarise`] only counts. [`crate::frontend`] drives
/// it for every command.
pub struct SceneCheck<'a, S: Sink = Collect> {
    cx: Checker<'a>,
    /// The first camera's keyword and its resolution, if valid.
    camera: Option<(Span, Option<u32>)>,
    /// Where the first section starts: a missing camera goes before it.
    first_section: Option<Span>,
    /// Whether an unknown section was taken for a misspelt `camera`, whose
    /// "did you mean" already says what a missing camera would.
    camera_misspelt: bool,
    objects: S,
    /// Whether every object so far was valid.
    objects_valid: bool,
    lights: Vec<Option<model::Light>>,
    /// Objects and lights seen, for the limits.
    counts: [Count; 2],
}

/// How many sections of some kinds came, and the first beyond a limit.
struct Count {
    what: &'static str,
    kinds: &'static [SectionKind],
    limit: usize,
    found: usize,
    first_beyond: Option<Span>,
}

impl<'a> SceneCheck<'a> {
    /// A check of the scene whose text is `source` that builds its model,
    /// reading texture files through `textures`.
    pub fn new(source: &'a SourceFile, textures: &'a mut dyn TextureLoader) -> SceneCheck<'a> {
        SceneCheck::with_sink(source, Collect::default(), textures)
    }
}

impl<'a, S: Sink> SceneCheck<'a, S> {
    /// A check of the scene whose text is `source` that hands each valid
    /// object to `objects` and reads texture files through `textures`
    /// ([`crate::texture::HeaderReader`] to validate only,
    /// [`crate::texture::Decoder`] to decode them too).
    pub fn with_sink(
        source: &'a SourceFile,
        objects: S,
        textures: &'a mut dyn TextureLoader,
    ) -> SceneCheck<'a, S> {
        let count = |what, kinds, limit| Count {
            what,
            kinds,
            limit,
            found: 0,
            first_beyond: None,
        };
        SceneCheck {
            cx: Checker::new(source, textures),
            camera: None,
            first_section: None,
            camera_misspelt: false,
            objects,
            objects_valid: true,
            lights: Vec::new(),
            counts: [
                count(
                    "spheres and planes",
                    &[SectionKind::Sphere, SectionKind::Plane],
                    MAX_OBJECTS,
                ),
                count("lights", &[SectionKind::Light], MAX_LIGHTS),
            ],
        }
    }

    /// This check is fed the sections [`crate::syntax::sections`] reads from
    /// scene text (not JSON), so fixes may remove whole lines of it.
    pub fn fed_from_scene_text(mut self) -> Self {
        self.cx.scene_text = true;
        self
    }

    /// Check the next section of the file.
    pub fn section(&mut self, section: &ast::Section) {
        let cx = &mut self.cx;
        self.first_section.get_or_insert(section.kind.span);
        for count in &mut self.counts {
            if count.kinds.contains(&*section.kind) {
                if count.found == count.limit {
                    count.first_beyond = Some(section.kind.span);
                }
                count.found += 1;
            }
        }
        match &*section.kind {
            SectionKind::Camera => {
                let resolution = sections::camera(section, cx);
                match self.camera {
                    None => self.camera = Some((section.kind.span, resolution)),
                    Some((first, _)) => {
                        let line = section
                            .args
                            .last()
                            .map_or(section.kind.span, |last| section.kind.span.join(last.span));
                        // The line as one: the keyword and its values,
                        // without what lies between them.
                        let written = std::iter::once("camera".to_string())
                            .chain(section.args.iter().map(|v| cx.text(v.span)))
                            .collect::<Vec<_>>()
                            .join(" ");
                        let fix =
                            cx.removal(&format!("remove `{written}`"), Applicability::Unsafe, line);
                        cx.problems.push(CheckError::RepeatedCamera {
                            first: first.into(),
                            second: section.kind.span.into(),
                            help: format!(
                                "a scene has one camera: keep the first and remove `{written}`"
                            ),
                            fix,
                        })
                    }
                }
            }
            SectionKind::Sphere | SectionKind::Plane => {
                let object = if *section.kind == SectionKind::Sphere {
                    sections::sphere(section, cx)
                } else {
                    sections::plane(section, cx)
                };
                match object {
                    Some(object) => self.objects.object(object),
                    None => self.objects_valid = false,
                }
            }
            SectionKind::Light => self.lights.push(sections::light(section, cx)),
            SectionKind::Unknown(word) => {
                let near = suggest::nearest(word, &SectionKind::KEYWORDS).map(|(near, _)| near);
                self.camera_misspelt |= near == Some(SectionKind::Camera.as_str());
                cx.problems
                    .push(unknown_section(word, near, section.kind.span))
            }
        }
    }

    /// Tell the check that an earlier stage (the parser, the JSON reader)
    /// reported an error: the picture is not the one the file will give
    /// once mended, so the whole-scene warnings about it (no light,
    /// nothing in view) are not said.
    pub fn after_errors(&mut self) {
        self.cx.problems.mark_incomplete();
    }

    /// The checks that need the whole file, then what the sink makes of
    /// the scene when there were no errors, and every diagnostic in the
    /// order found.
    pub fn finish(self) -> (Option<S::Scene>, Vec<CheckError>) {
        let SceneCheck {
            mut cx,
            camera,
            first_section,
            camera_misspelt,
            objects,
            objects_valid,
            lights,
            counts,
        } = self;
        // A misspelt camera line is the one mistake, already reported.
        if camera.is_none() && !camera_misspelt {
            let fix = cx.scene_text.then(|| {
                let at = first_section.map_or(0, |s| s.start());
                let line = &cx.source.text[..at];
                let starts_line = line[line.rfind('\n').map_or(0, |i| i + 1)..]
                    .chars()
                    .all(|c| c == ' ' || c == '\t');
                let camera = language::CAMERA.example;
                let content = if starts_line {
                    format!("{camera}\n")
                } else {
                    format!("{camera} ")
                };
                Fix::boxed(
                    format!("add `{camera}`"),
                    Applicability::Unsafe,
                    Span::point(at),
                    &content,
                )
            });
            cx.problems.push(CheckError::MissingCamera {
                span: Span::point(0).into(),
                fix,
            });
        }
        // A scene that renders black, or nearly: said only of a scene
        // with no error, which is the picture it will be.
        if let (true, Some((camera_span, Some(_)))) = (cx.problems.clean(), camera) {
            if lights.is_empty() {
                let fix = cx.scene_text.then(|| {
                    let text = &cx.source.text;
                    let newline = if text.is_empty() || text.ends_with('\n') {
                        ""
                    } else {
                        "\n"
                    };
                    Fix::boxed(
                        "add `light` with `location 0 5 0` and `color 1 1 1`".to_string(),
                        Applicability::Unsafe,
                        Span::point(text.len()),
                        &format!("{newline}light\n  location 0 5 0\n  color 1 1 1\n"),
                    )
                });
                let help = if cx.scene_text {
                    "add a light: `light`, `location 0 5 0`, `color 1 1 1`"
                } else {
                    r#"add a light: `"lights": [{"location": [0, 5, 0], "color": [1, 1, 1]}]`"#
                };
                cx.problems.push(CheckError::NoLight {
                    span: camera_span.into(),
                    help: help.to_string(),
                    fix,
                });
            }
            // An object behind the camera is the mistake already named.
            let behind = cx
                .problems
                .list
                .iter()
                .any(|p| matches!(p, CheckError::ObjectBehindCamera { .. }));
            if !cx.in_view && !behind {
                let center = language::find(&SectionKind::Sphere, &ast::AttrName::Center)
                    .expect("a sphere has a centre")
                    .written(&["0", "0", "-5"], cx.language());
                cx.problems.push(CheckError::NothingInView {
                    span: camera_span.into(),
                    help: format!("the camera is at the origin looking down −z and sees x and y within ±z/2; put an object there, as in `{center}`"),
                });
            }
        }
        let inside = std::mem::take(&mut cx.inside);
        cx.problems.list.extend(inside.warnings());
        cx.problems
            .list
            .extend(text_direction::warnings(&cx.source.text));
        for count in counts {
            count.report(&mut cx.problems);
        }
        let Checker {
            problems, textures, ..
        } = cx;
        let resolution = camera.and_then(|(_, resolution)| resolution);
        let checked = match (problems.clean(), resolution) {
            (true, Some(resolution)) => objects_valid
                .then_some(objects)
                .zip(lights.into_iter().collect::<Option<Vec<_>>>())
                .map(|(objects, lights)| {
                    objects.scene(model::Camera { resolution }, lights, textures.into_loaded())
                }),
            _ => None,
        };
        (checked, problems.list)
    }
}

impl Count {
    /// Report the first section beyond the limit, if one came.
    fn report(self, problems: &mut Problems) {
        if let Some(first) = self.first_beyond {
            problems.push(CheckError::TooManyObjects {
                what: self.what,
                limit: self.limit,
                found: self.found,
                span: first.into(),
                help: format!(
                    "the limit bounds memory and time (docs/reliability.md): remove at least {} of them",
                    self.found - self.limit
                ),
            });
        }
    }
}

/// The diagnostic for `word` in section position, with `near`, the
/// nearest keyword if one is close.
fn unknown_section(word: &str, near: Option<&str>, span: Span) -> CheckError {
    let help = match near {
        Some(near) => format!("did you mean `{near}`?"),
        None => format!(
            "a section starts with {}",
            language::list_or(&SectionKind::KEYWORDS)
        ),
    };
    CheckError::UnknownSection {
        found: word.to_string(),
        fix: near.map(|near| {
            Fix::boxed(
                format!("replace `{word}` with `{near}`"),
                Applicability::Unsafe,
                span,
                near,
            )
        }),
        span: span.into(),
        help,
    }
}

/// The diagnostics found so far.
#[derive(Debug, Default)]
struct Problems {
    list: Vec<CheckError>,
    /// Set when a value the parser already reported keeps a section from
    /// being built; there is no scene, but nothing more to say.
    incomplete: bool,
}

impl Problems {
    fn push(&mut self, problem: CheckError) {
        self.list.push(problem);
    }

    fn mark_incomplete(&mut self) {
        self.incomplete = true;
    }

    /// No errors (warnings allowed) and nothing incomplete.
    fn clean(&self) -> bool {
        use miette::Diagnostic;
        !self.incomplete
            && self
                .list
                .iter()
                .all(|p| p.severity() == Some(miette::Severity::Warning))
    }
}

/// The state of one check run.
struct Checker<'a> {
    source: &'a SourceFile,
    problems: Problems,
    textures: textures::Textures<'a>,
    /// What the light-inside-sphere warning weighs.
    inside: inside::LightsInSpheres,
    /// Whether the source is scene text, where a fix may remove a line
    /// (in JSON it would leave a stray comma).
    scene_text: bool,
    /// Whether some valid object is in the camera's view.
    in_view: bool,
}

impl<'a> Checker<'a> {
    fn new(source: &'a SourceFile, textures: &'a mut dyn TextureLoader) -> Checker<'a> {
        Checker {
            source,
            problems: Problems::default(),
            textures: textures::Textures::new(&source.dir, &source.text, textures),
            inside: inside::LightsInSpheres::default(),
            scene_text: false,
            in_view: false,
        }
    }
}

impl Checker<'_> {
    /// The language of the file, for help lines.
    fn language(&self) -> language::Language {
        if self.scene_text {
            language::Language::Text
        } else {
            language::Language::Json
        }
    }

    /// A fix that removes `span` (and its line, when nothing else is on
    /// it), in scene text only.
    fn removal(&self, message: &str, applicability: Applicability, span: Span) -> Option<Box<Fix>> {
        self.scene_text.then(|| {
            let removed = crate::fix::removal(&self.source.text, span);
            Fix::boxed(message.to_string(), applicability, removed, "")
        })
    }

    /// The source text of `span`, as written.
    fn text(&self, span: Span) -> String {
        self.source
            .text
            .get(span.start()..span.end())
            .unwrap_or_default()
            .to_string()
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::fix::{self, Applicability};
    use crate::frontend::load_bytes;

    /// `text` with the fixes of at most `applicability` its diagnostics
    /// carry applied.
    fn fixed(text: &str, applicability: Applicability) -> String {
        let loaded = load_bytes("t.txt", Path::new("."), text.as_bytes());
        let report = &loaded.report;
        fix::apply(text, report.fixes_up_to(applicability)).0
    }

    #[test]
    fn the_headup_fix_projects_and_keeps_layout_comments_and_the_normal() {
        let text = "camera 4\nplane dimension 1 1 center 0 0 -5\n\tnormal 0 .5 1 # tilted\n\theadup\t0  1 0   # up\n";
        assert_eq!(
            fixed(text, Applicability::Safe),
            "camera 4\nplane dimension 1 1 center 0 0 -5\n\tnormal 0 .5 1 # tilted\n\theadup\t0  0.8 -0.4   # up\n"
        );
    }

    #[test]
    fn the_parallel_headup_fix_writes_the_stand_in() {
        let text = "camera 4 plane dimension 1 1 center 0 0 -5 normal 0 1 0 headup 0 2 0 # up";
        assert_eq!(
            fixed(text, Applicability::Safe),
            "camera 4 plane dimension 1 1 center 0 0 -5 normal 0 1 0 headup 0 0 1 # up"
        );
    }

    /// (Unsafe fixes remain for some: a zero normal's stand-in, the
    /// second of two `normal` lines removed.)
    #[test]
    fn good_and_hopeless_planes_get_no_safe_fix() {
        for plane in [
            "plane normal 0 1 0 headup 0 0 1",
            "plane normal 0 2 0 headup 0 0 1",
            "plane normal 0 0 0 headup 0 1 0",
            "plane normal 0 1 0 normal 0 1 0 headup 0 1 1",
            "sphere normal 0 2 0",
        ] {
            let text = format!("camera 4 {plane} dimension 1 1 center 0 0 -5");
            assert_eq!(fixed(&text, Applicability::Safe), text);
        }
    }

    #[test]
    fn fixed_text_has_nothing_left_to_fix() {
        let once = fixed(
            "camera 4 light location 0 5 0 color 1 1 1 plane dimension 1 1 center 0 0 -5 normal 1 2 3 headup 3 -1 7",
            Applicability::Safe,
        );
        assert_eq!(fixed(&once, Applicability::Unsafe), once);
    }

    #[test]
    fn did_you_mean_is_an_unsafe_fix() {
        let text = "camera 4\nsphre dimension 1 center 0 0 -5\nsphere dimension 1 center 0 0 -5 colour 1 0 0";
        assert_eq!(fixed(text, Applicability::Safe), text);
        assert_eq!(
            fixed(text, Applicability::Unsafe),
            "camera 4\nsphere dimension 1 center 0 0 -5\nsphere dimension 1 center 0 0 -5 color 1 0 0"
        );
    }
}
