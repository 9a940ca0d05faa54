//! One builder per section kind: each runs the shared attribute checks,
//! then the range rules and warnings of its own attributes (docs/language.md), and
//! returns the model value when everything it needs is valid.

use arrayvec::ArrayVec;

use crate::ast::{AttrName, Section, Value};
use crate::fix::{Applicability, Edit, Fix};
use crate::model;
use crate::span::Spanned;

use super::attributes::{self, Attributes};
use super::errors::CheckError;
use super::format;
use super::inside::{LightAt, SphereAt};
use super::Checker;
use crate::geometry::{self, Headup};

/// The camera line: its resolution, when valid.
pub fn camera(section: &Section, cx: &mut Checker<'_>) -> Option<u32> {
    attributes::collect(section, &mut cx.problems);
    if let Some(problem) = attributes::count_problem(
        "camera",
        "1 value",
        1,
        section.kind.span,
        &section.args,
        "write `camera N` for an N × N image, such as `camera 400`",
    ) {
        cx.problems.push(problem);
        return None;
    }
    let arg = &section.args[0];
    let n = match &arg.value {
        Value::Number(n) => *n,
        Value::Text(text) => {
            cx.problems.push(CheckError::NotANumber {
                name: "camera".to_string(),
                found: text.to_string(),
                span: arg.span.into(),
            });
            return None;
        }
        Value::Invalid => {
            cx.problems.mark_incomplete();
            return None;
        }
    };
    let found = cx.text(arg.span);
    let nearest = n.round().clamp(1.0, 16384.0);
    if n.fract() != 0.0 {
        cx.problems.push(CheckError::ResolutionNotInteger {
            found,
            span: arg.span.into(),
            help: format!("write `camera {}`", format::number(nearest)),
        });
        return None;
    }
    if !(1.0..=16384.0).contains(&n) {
        cx.problems.push(CheckError::ResolutionOutOfRange {
            found,
            span: arg.span.into(),
            help: format!(
                "the image is N × N pixels with N from 1 to 16384: write `camera {}`",
                format::number(nearest)
            ),
        });
        return None;
    }
    // In 1..=16384 and whole, so the cast is exact.
    Some(n as u32)
}

/// A sphere, when valid.
pub fn sphere(section: &Section, cx: &mut Checker<'_>) -> Option<model::Object> {
    no_positional_values(section, "dimension 1", cx);
    let attrs = attributes::collect(section, &mut cx.problems);
    let (center, radius) = sphere_geometry(&attrs, cx);
    let material = material(&attrs, "sphere", cx);
    let (center, radius) = (center?, radius?);
    if center[2] - radius >= 0.0 {
        cx.problems.push(behind_camera("sphere", center));
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
/// light-inside-sphere warning weighs.
pub fn sphere_geometry(
    attrs: &Attributes<'_>,
    cx: &mut Checker<'_>,
) -> (Option<Spanned<[f64; 3]>>, Option<f64>) {
    let radius = dimensions(attrs, &["radius"], cx).map(|d| d[0]);
    (attrs.vector(&AttrName::Center), radius)
}

/// A plane, when valid.
pub fn plane(section: &Section, cx: &mut Checker<'_>) -> Option<model::Object> {
    no_positional_values(section, "dimension 4 4", cx);
    let attrs = attributes::collect(section, &mut cx.problems);
    let size = dimensions(&attrs, &["width", "height"], cx);
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
    let (width, height) = (size[0], size[1]);
    if let Some(basis) = geometry::plane_basis(normal, headup) {
        let corners = geometry::corners(*center, &basis, width, height);
        if corners.iter().all(|c| c.z >= 0.0) {
            cx.problems.push(behind_camera("plane", center));
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

/// A light, when valid.
pub fn light(section: &Section, cx: &mut Checker<'_>) -> Option<model::Light> {
    no_positional_values(section, "location 0 0 0", cx);
    let attrs = attributes::collect(section, &mut cx.problems);
    let location = attrs.vector(&AttrName::Location);
    let color = attrs.vector(&AttrName::Color).and_then(|color| {
        let channels = attrs.numbers(&AttrName::Color)?;
        let negative: Vec<_> = channels.iter().filter(|c| ***c < 0.0).collect();
        let ok = negative.is_empty();
        if let (Some(first), Some(last)) = (negative.first(), negative.last()) {
            cx.problems.push(CheckError::NegativeLightColor {
                found: cx.text(color.span),
                span: first.span.join(last.span).into(),
                help: format!(
                    "write `color {}`",
                    format::vector(color.value.map(|c| c.max(0.0)))
                ),
            });
        }
        let brightest = color.iter().copied().fold(0.0, f64::max);
        if ok && brightest > 1.0 {
            cx.problems.push(CheckError::LightColorAboveOne {
                span: color.span.into(),
                help: format!(
                    "to keep the hue without clipping, write `color {}`",
                    format::vector(color.value.map(|c| c / brightest))
                ),
            });
        }
        ok.then_some(*color)
    });
    let location = location?;
    cx.inside.light(LightAt {
        location: *location,
        span: location.span,
    });
    Some(model::Light {
        location: *location,
        color: color?,
    })
}

/// Report values written directly after a `sphere`, `plane` or `light`
/// keyword; `example` is an attribute line to suggest instead.
fn no_positional_values(section: &Section, example: &str, cx: &mut Checker<'_>) {
    let (Some(first), Some(last)) = (section.args.first(), section.args.last()) else {
        return;
    };
    cx.problems.push(CheckError::SectionValues {
        section: section.kind.as_str().to_string(),
        span: first.span.join(last.span).into(),
        help: format!("write values after an attribute name, such as `{example}`"),
    });
}

/// The `dimension` values, each checked > 0; `names` says what each is.
fn dimensions(
    attrs: &Attributes<'_>,
    names: &[&str],
    cx: &mut Checker<'_>,
) -> Option<ArrayVec<f64, 2>> {
    let values = attrs.numbers(&AttrName::Dimension)?;
    // The suggested line, written only when a value is wrong.
    let fixed = || {
        let fixed: Vec<String> = values
            .iter()
            .map(|v| format::number(if **v == 0.0 { 1.0 } else { v.abs() }))
            .collect();
        fixed.join(" ")
    };
    let mut ok = true;
    for (value, what) in values.iter().zip(names) {
        if **value > 0.0 {
            continue;
        }
        ok = false;
        cx.problems.push(CheckError::DimensionNotPositive {
            what: what.to_string(),
            found: cx.text(value.span),
            span: value.span.into(),
            help: format!("write `dimension {}`", fixed()),
        });
    }
    ok.then(|| values.iter().map(|v| **v).collect())
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
    let normal = attrs.vector(&AttrName::Normal);
    let headup = attrs.vector(&AttrName::Headup);
    let normal_unit = normal.and_then(|n| geometry::unit(*n));
    if let (Some(n), None) = (normal, normal_unit) {
        cx.problems.push(CheckError::ZeroNormal {
            span: n.span.into(),
        });
    }
    if let Some(h) = headup.filter(|h| geometry::unit(**h).is_none()) {
        cx.problems.push(CheckError::ZeroHeadup {
            span: h.span.into(),
            help: match normal_unit {
                Some(_) => format!(
                    "write `headup {}`, perpendicular to the normal",
                    perpendicular_to(normal.map_or([0.0; 3], |n| *n))
                ),
                None => "give the plane's up direction, such as `headup 0 1 0`".to_string(),
            },
        });
    }
    let (normal, headup) = (normal?, headup?);
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
                "the renderer projects it onto the plane: write `headup {}`",
                format::vector(projected)
            ),
            fix: headup_fix(projected, "projected `headup` onto the plane"),
        }),
        Headup::Parallel => {
            let stand_in = geometry::stand_in_headup(geometry::unit(*normal)?).to_array();
            cx.problems.push(CheckError::HeadupParallelToNormal {
                normal: normal.span.into(),
                headup: headup.span.into(),
                help: format!(
                    "the renderer uses `headup {}` instead: write it, or the up direction you mean",
                    format::vector(stand_in)
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

/// A vector perpendicular to `normal` for help lines: the stand-in headup
/// of [`geometry::stand_in_headup`] projected onto the plane.
fn perpendicular_to(normal: [f64; 3]) -> String {
    let Some(n) = geometry::unit(normal) else {
        return "0 1 0".to_string();
    };
    let axis = geometry::stand_in_headup(n);
    format::vector((axis - axis.dot(n) * n).to_array())
}

/// An object's material: colour and reflectivity in [0, 1], a texture that
/// loads, and a warning when colour and texture are both given.
fn material(attrs: &Attributes<'_>, shape: &str, cx: &mut Checker<'_>) -> Option<model::Material> {
    let mut material = model::Material::default();
    let mut ok = true;
    if let Some(color) = attrs.vector(&AttrName::Color) {
        let bad = attrs.numbers(&AttrName::Color).and_then(|channels| {
            let out: Vec<_> = channels
                .iter()
                .filter(|c| !(0.0..=1.0).contains(&***c))
                .collect();
            Some(out.first()?.span.join(out.last()?.span))
        });
        if let Some(span) = bad {
            ok = false;
            let on_255_scale = color.iter().all(|c| (0.0..=255.0).contains(c));
            let fixed = if on_255_scale {
                color.value.map(|c| (c / 255.0 * 1000.0).round() / 1000.0)
            } else {
                color.value.map(|c| c.clamp(0.0, 1.0))
            };
            let help = if on_255_scale {
                format!(
                    "if these are 0–255 values, write `color {}`",
                    format::vector(fixed)
                )
            } else {
                format!("write `color {}`", format::vector(fixed))
            };
            cx.problems.push(CheckError::ColorOutOfRange {
                found: cx.text(color.span),
                span: span.into(),
                help,
            });
        }
        material.color = *color;
    } else if attrs.line(&AttrName::Color).is_some() {
        ok = false;
    }
    if let Some(k) = attrs
        .numbers(&AttrName::Reflectivity)
        .and_then(|k| k.first())
    {
        if !(0.0..=1.0).contains(&**k) {
            ok = false;
            cx.problems.push(CheckError::ReflectivityOutOfRange {
                found: cx.text(k.span),
                span: k.span.into(),
                help: format!("write `reflectivity {}`", format::number(k.clamp(0.0, 1.0))),
            });
        }
        material.reflectivity = **k;
    } else if attrs.line(&AttrName::Reflectivity).is_some() {
        ok = false;
    }
    if let Some(path) = attrs.path(&AttrName::Texture) {
        if let Err(problem) = cx.textures.load(path) {
            ok = false;
            cx.problems.push(problem);
        }
        material.texture = Some(path.value.to_string());
    } else if attrs.line(&AttrName::Texture).is_some() {
        ok = false;
    }
    if let (Some(color), Some(texture)) =
        (attrs.line(&AttrName::Color), attrs.line(&AttrName::Texture))
    {
        cx.problems.push(CheckError::ColorWithTexture {
            shape: shape.to_string(),
            color: color.span.into(),
            texture: texture.span.into(),
        });
    }
    ok.then_some(material)
}

/// The warning for an object with every point at z ≥ 0.
fn behind_camera(shape: &str, center: Spanned<[f64; 3]>) -> CheckError {
    let [x, y, z] = *center;
    let help = if z > 0.0 {
        format!(
            "the camera looks down −z; did you mean `center {}`?",
            format::vector([x, y, -z])
        )
    } else {
        format!("the camera looks down −z from the origin; move the {shape} to negative z")
    };
    CheckError::ObjectBehindCamera {
        shape: shape.to_string(),
        span: center.span.into(),
        help,
    }
}
