//! One builder per section kind: each runs the shared attribute checks
//! (which hold every line to its row's rule in the registry), then the
//! rules between attributes (docs/language.md): `headup` against
//! `normal`, a texture that loads, `color` beside `texture`, an object
//! behind the camera. It returns the model value when everything it needs
//! is valid.

use crate::ast::{AttrName, Section, SectionKind};
use crate::fix::{Applicability, Edit, Fix};
use crate::language::Language;
use crate::model;
use crate::span::{Span, Spanned};

use super::attributes::{self, Attributes};
use super::errors::CheckError;
use super::format;
use super::inside::{LightAt, SphereAt};
use super::Checker;
use crate::geometry::{self, Headup};

/// The camera line: its resolution, when valid (its rule is the
/// registry's camera row, checked by [`attributes::camera_values`]).
pub fn camera(section: &Section, cx: &mut Checker<'_>) -> Option<u32> {
    attributes::collect(section, cx);
    let n = attributes::camera_values(&section.kind, &section.args, cx)?;
    // A whole number within the row's range, which a `u32` holds, so the
    // cast is exact.
    Some(n as u32)
}

/// A sphere, when valid.
pub fn sphere(section: &Section, cx: &mut Checker<'_>) -> Option<model::Object> {
    no_positional_values(section, "dimension 1", cx);
    let attrs = attributes::collect(section, cx);
    let (center, radius) = sphere_geometry(&attrs);
    let material = material(&attrs, "sphere", cx);
    let (center, radius) = (center?, radius?);
    if center[2] - radius >= 0.0 {
        cx.problems
            .push(behind_camera("sphere", center, &attrs, cx.language()));
    }
    if in_view(*center, radius) {
        cx.in_view = true;
    }
    let at = SphereAt {
        center: *center,
        radius,
        span: section.kind.span,
    };
    cx.inside.sphere(at);
    Some(model::Object {
        shape: model::Shape::Sphere {
            center: *center,
            radius,
        },
        material: material?,
    })
}

/// A sphere's centre and radius, each when valid: all of a sphere that the
/// light-inside-sphere warning weighs (the radius's own rule is checked
/// with the other single-attribute rules).
pub fn sphere_geometry(attrs: &Attributes<'_>) -> (Option<Spanned<[f64; 3]>>, Option<f64>) {
    let radius = attrs
        .numbers(&AttrName::Dimension)
        .and_then(|d| d.first())
        .map(|r| r.value);
    (attrs.vector(&AttrName::Center), radius)
}

/// A plane, when valid.
pub fn plane(section: &Section, cx: &mut Checker<'_>) -> Option<model::Object> {
    no_positional_values(section, "dimension 4 4", cx);
    let attrs = attributes::collect(section, cx);
    let size = attrs.numbers(&AttrName::Dimension);
    let center = attrs.vector(&AttrName::Center);
    let written_once = |name: AttrName| {
        section
            .attributes
            .iter()
            .filter(|a| *a.name == name)
            .count()
            == 1
    };
    let unique = written_once(AttrName::Normal) && written_once(AttrName::Headup);
    let orientation = orientation(&attrs, unique, cx);
    let material = material(&attrs, "plane", cx);
    let (size, center, (normal, headup)) = (size?, center?, orientation?);
    let (width, height) = (size[0].value, size[1].value);
    if let Some(basis) = geometry::plane_basis(normal, headup) {
        let corners = geometry::corners(*center, &basis, width, height);
        if corners.iter().all(|c| c.z >= 0.0) {
            cx.problems
                .push(behind_camera("plane", center, &attrs, cx.language()));
        }
        // Outside the view when every corner is beyond one of its sides
        // (the rectangle is convex, the view too).
        if !VIEW_SIDES
            .iter()
            .any(|side| corners.iter().all(|c| side.dot(*c) > 0.0))
        {
            cx.in_view = true;
        }
    }
    Some(model::Object {
        shape: model::Shape::Plane {
            center: *center,
            width,
            height,
            normal,
            headup,
        },
        material: material?,
    })
}

/// The outward normals of the sides of the pyramid the camera sees: from
/// the origin through the image plane z = −1, x and y in [−0.5, 0.5]
/// (docs/rendering.md), and the plane z = 0 behind it.
const VIEW_SIDES: [glam::DVec3; 5] = [
    glam::DVec3::new(1.0, 0.0, 0.5),
    glam::DVec3::new(-1.0, 0.0, 0.5),
    glam::DVec3::new(0.0, 1.0, 0.5),
    glam::DVec3::new(0.0, -1.0, 0.5),
    glam::DVec3::new(0.0, 0.0, 1.0),
];

/// Whether a sphere may be in the camera's view: it is not wholly beyond
/// one side of it (near the pyramid's edges this says yes for a sphere
/// just outside, so the warning never fires for a visible one).
fn in_view(center: [f64; 3], radius: f64) -> bool {
    let c = glam::DVec3::from_array(center);
    !VIEW_SIDES
        .iter()
        .any(|side| side.dot(c) / side.length() > radius)
}

/// A light, when valid.
pub fn light(section: &Section, cx: &mut Checker<'_>) -> Option<model::Light> {
    no_positional_values(section, "location 0 0 0", cx);
    let attrs = attributes::collect(section, cx);
    let location = attrs.vector(&AttrName::Location);
    let color = attrs.vector(&AttrName::Color);
    let location = location?;
    cx.inside.light(LightAt {
        location: *location,
        span: location.span,
    });
    Some(model::Light {
        location: *location,
        color: *color?,
    })
}

/// Report values written directly after a `sphere`, `plane` or `light`
/// keyword; `example` is an attribute line to suggest instead.
fn no_positional_values(section: &Section, example: &str, cx: &mut Checker<'_>) {
    let (Some(first), Some(last)) = (section.args.first(), section.args.last()) else {
        return;
    };
    let fix = Fix::boxed(
        format!("remove the values after `{}`", section.kind.as_str()),
        Applicability::Unsafe,
        Span::new(section.kind.span.end(), last.span.end()),
        "",
    );
    cx.problems.push(CheckError::SectionValues {
        section: section.kind.as_str().to_string(),
        span: first.span.join(last.span).into(),
        help: format!("write values after an attribute name, such as `{example}`"),
        fix: cx.scene_text.then_some(fix),
    });
}

/// A plane's `normal` and `headup`, when both are valid: non-zero and not
/// parallel. Warns when headup is not perpendicular.
/// `unique` says that `normal` and `headup` are each written once: with a
/// duplicate, which one to fix is the author's call, so no fix is offered.
fn orientation(
    attrs: &Attributes<'_>,
    unique: bool,
    cx: &mut Checker<'_>,
) -> Option<([f64; 3], [f64; 3])> {
    // Zero vectors were reported by their rows' rules and kept no values.
    let (normal, headup) = (
        attrs.vector(&AttrName::Normal)?,
        attrs.vector(&AttrName::Headup)?,
    );
    // Both headup fixes write the vector the renderer uses, when headup is
    // written once.
    let headup_fix = |used: [f64; 3], message: &str| {
        attrs
            .numbers(&AttrName::Headup)
            .filter(|_| unique)
            .and_then(|written| rewrite_headup(written, used, message))
            .map(Box::new)
    };
    match geometry::classify_headup(*normal, *headup)? {
        Headup::Perpendicular => {}
        Headup::Projected(projected) => cx.problems.push(CheckError::HeadupNotPerpendicular {
            normal: normal.span.into(),
            headup: headup.span.into(),
            help: format!(
                "the renderer projects it onto the plane: write `{}`",
                written_vector(&AttrName::Headup, projected, cx.language())
            ),
            fix: headup_fix(projected, "project `headup` onto the plane"),
        }),
        Headup::Parallel => {
            let stand_in = geometry::stand_in_headup(geometry::unit(*normal)?).to_array();
            cx.problems.push(CheckError::HeadupParallelToNormal {
                normal: normal.span.into(),
                headup: headup.span.into(),
                help: format!(
                    "the renderer uses `{}` instead: write it, or the up direction you mean",
                    written_vector(&AttrName::Headup, stand_in, cx.language())
                ),
                fix: headup_fix(
                    stand_in,
                    "replaced the parallel `headup` with the one the renderer uses",
                ),
            });
        }
    }
    Some((*normal, *headup))
}

/// The safe fix that writes the headup the renderer uses (a projection, or
/// the stand-in for a parallel one): one edit per number whose text
/// changes, so comments and spacing stay as written. `None` when no
/// written number would change.
fn rewrite_headup(written: &[Spanned<f64>], used: [f64; 3], message: &str) -> Option<Fix> {
    let edits: Vec<Edit> = written
        .iter()
        .zip(used)
        .filter(|(value, new)| value.value != format::number(*new).parse().unwrap_or(*new))
        .map(|(value, new)| Edit {
            span: value.span,
            content: format::number(new),
        })
        .collect();
    (!edits.is_empty()).then(|| Fix {
        message: message.to_string(),
        applicability: Applicability::Safe,
        edits,
    })
}

/// An object's material: colour and reflectivity (held to their rules
/// already), a texture that loads, and a warning when colour and texture
/// are both given.
fn material(attrs: &Attributes<'_>, shape: &str, cx: &mut Checker<'_>) -> Option<model::Material> {
    let mut material = model::Material::default();
    let mut ok = true;
    // Each value was held to its row's rule: a line without values broke it.
    match attrs.vector(&AttrName::Color) {
        Some(color) => material.color = *color,
        None => ok &= attrs.line(&AttrName::Color).is_none(),
    }
    match attrs
        .numbers(&AttrName::Reflectivity)
        .and_then(|k| k.first())
    {
        Some(k) => material.reflectivity = **k,
        None => ok &= attrs.line(&AttrName::Reflectivity).is_none(),
    }
    if let Some(path) = attrs.path(&AttrName::Texture) {
        if let Err(problem) = cx.textures.load(path) {
            ok = false;
            cx.problems.push(*problem);
        }
        material.texture = Some(path.value.to_string());
    } else if attrs.line(&AttrName::Texture).is_some() {
        ok = false;
    }
    // A `texture` line without a path sets no colour (its count is
    // reported): the `color` line is still the surface's.
    if let (Some(color), Some(texture), Some(_)) = (
        attrs.line(&AttrName::Color),
        attrs.line(&AttrName::Texture),
        attrs.path(&AttrName::Texture),
    ) {
        let help = format!(
            "remove the `color` {}; the texture sets the surface colour",
            cx.language().line()
        );
        let fix = cx.removal(&help, Applicability::Safe, color.span);
        cx.problems.push(CheckError::ColorWithTexture {
            help,
            fix,
            shape: shape.to_string(),
            color: color.span.into(),
            texture: texture.span.into(),
        });
    }
    ok.then_some(material)
}

/// A plane's `name` line with the vector `v`, in the file's language:
/// `headup 0 0 1` or `"headup": [0, 0, 1]`.
fn written_vector(name: &AttrName, v: [f64; 3], language: Language) -> String {
    let spec = crate::language::find(&SectionKind::Plane, name).expect("a plane row");
    spec.written(&v.map(format::number), language)
}

/// The warning for an object with every point at z ≥ 0; when its centre
/// has z > 0, the fix (unsafe) negates that z.
fn behind_camera(
    shape: &str,
    center: Spanned<[f64; 3]>,
    attrs: &Attributes<'_>,
    language: Language,
) -> CheckError {
    let [x, y, z] = *center;
    let written_z = attrs.numbers(&AttrName::Center).and_then(|c| c.get(2));
    let fix = written_z.filter(|_| z > 0.0).map(|written| {
        Fix::boxed(
            format!(
                "the camera looks down −z; did you mean `{}`?",
                written_vector(&AttrName::Center, [x, y, -z], language)
            ),
            Applicability::Unsafe,
            written.span,
            &format::number(-z),
        )
    });
    let help = match &fix {
        Some(fix) => fix.message.clone(),
        None => {
            format!("the camera looks down −z from the origin; move the {shape} to negative z")
        }
    };
    CheckError::ObjectBehindCamera {
        shape: shape.to_string(),
        span: center.span.into(),
        help,
        fix,
    }
}
