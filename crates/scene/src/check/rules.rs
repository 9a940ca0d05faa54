//! The single-attribute rules of the registry ([`crate::language`]): each
//! row's [`Constraint`] checked against the numbers of one line, every
//! violation reported with a [`Fix`] whose message is the help line.
//!
//! Fixes edit only the numbers that change, so comments and spacing stay
//! as written and the same edits apply to a JSON scene, whose values carry
//! the spans of its JSON numbers. A fix here guesses what the author meant
//! (the nearest valid value, or the value on the scale the author likely
//! used), so each is unsafe: `check --fix --unsafe-fixes` applies it.

use crate::ast::AttrName;
use crate::fix::{Applicability, Edit, Fix};
use crate::geometry;
use crate::language::{AttrSpec, Constraint, Key, Language, Scale, StandIn};
use crate::span::{Span, Spanned};

use super::errors::CheckError;
use super::format;
use super::Checker;

/// Check the numbers of one line of `spec` (already counted) against its
/// constraint, reporting each violation. `sibling` gives the valid numbers
/// of another attribute of the same section (what a stand-in is derived
/// from). False when an error was reported: the values are not used.
pub fn check(
    spec: &AttrSpec,
    values: &[Spanned<f64>],
    sibling: &dyn Fn(&AttrName) -> Option<[f64; 3]>,
    cx: &mut Checker<'_>,
) -> bool {
    let line = Line {
        spec,
        values,
        language: cx.language(),
    };
    match spec.constraint {
        Constraint::Any | Constraint::Image => true,
        Constraint::Range { min, max, scale } => line.range(min, max, scale, cx),
        Constraint::Positive => line.positive(cx),
        Constraint::NonNegative { warn_above } => line.non_negative(warn_above, cx),
        Constraint::NonZero { stand_in } => line.non_zero(stand_in, sibling, cx),
        Constraint::Whole { min, max } => line.whole(min.into(), max.into(), cx),
    }
}

/// A fix and the help line that explains it.
struct Fixed {
    help: String,
    fix: Option<Box<Fix>>,
}

/// The numbers of one line, the row they belong to and the language of
/// the file (help lines show the new line in it).
struct Line<'a> {
    spec: &'a AttrSpec,
    values: &'a [Spanned<f64>],
    language: Language,
}

impl Line<'_> {
    /// The numbers as a span: from the first to the last.
    fn span(&self) -> Span {
        let first = self.values.first().map_or(Span::point(0), |v| v.span);
        self.values.last().map_or(first, |v| first.join(v.span))
    }

    /// The span of the values `bad` picks, from the first to the last.
    fn span_of(&self, bad: impl Fn(f64) -> bool) -> Option<Span> {
        let mut picked = self.values.iter().filter(|v| bad(***v));
        let first = picked.next()?.span;
        Some(picked.last().map_or(first, |last| first.join(last.span)))
    }

    /// The unsafe fix that writes `new` (one number per value), titled
    /// "write `line`", with the help line `help(line)`, where `line` is
    /// the whole new line in the file's language, such as
    /// `reflectivity 0.7` or `"reflectivity": 0.7`.
    fn fix(&self, new: &[f64], write: fn(f64) -> String, help: impl Fn(&str) -> String) -> Fixed {
        let texts: Vec<String> = new.iter().map(|&x| write(x)).collect();
        let line = self.spec.written(&texts, self.language);
        let help = help(&line);
        let edits = self
            .values
            .iter()
            .zip(texts)
            .filter(|(value, text)| text.parse::<f64>().ok() != Some(value.value))
            .map(|(value, content)| Edit {
                span: value.span,
                content,
            })
            .collect();
        let fix = Fix {
            message: format!("write `{line}`"),
            applicability: Applicability::Unsafe,
            edits,
        };
        Fixed {
            help,
            fix: Some(Box::new(fix)),
        }
    }

    fn numbers(&self) -> Vec<f64> {
        self.values.iter().map(|v| v.value).collect()
    }

    /// Each number in `[min, max]`; whole numbers up to the top of `scale`
    /// are read as written on that scale.
    fn range(&self, min: f64, max: f64, scale: Option<Scale>, cx: &mut Checker<'_>) -> bool {
        let Some(span) = self.span_of(|x| !(min..=max).contains(&x)) else {
            return true;
        };
        let numbers = self.numbers();
        let on_scale = scale.filter(|scale| {
            numbers.iter().all(|&x| (min..=scale.top).contains(&x))
                && numbers
                    .iter()
                    .filter(|&&x| x > max)
                    .all(|x| x.fract() == 0.0)
        });
        let fix = match on_scale {
            Some(scale) => {
                let new: Vec<f64> = numbers.iter().map(|x| x / scale.top * max).collect();
                let found = self.values.len();
                self.fix(&new, format::short, |line| {
                    let these = if found == 1 { "this is" } else { "these are" };
                    format!("if {these} {}, write `{line}`", scale.name)
                })
            }
            None => {
                let new: Vec<f64> = numbers.iter().map(|x| x.clamp(min, max)).collect();
                self.fix(&new, format::short, |line| format!("write `{line}`"))
            }
        };
        let found = cx.text(self.span());
        let (min, max) = (format::short(min), format::short(max));
        let (span, help) = (span.into(), fix.help);
        let fix = fix.fix;
        // One line a variant: the two carry the same fields.
        #[rustfmt::skip]
        let problem = match self.spec.name {
            Key::Attribute(AttrName::Reflectivity) =>
                CheckError::ReflectivityOutOfRange { min, max, found, span, help, fix },
            _ => CheckError::ColorOutOfRange { min, max, found, span, help, fix },
        };
        cx.problems.push(problem);
        false
    }

    /// Each number greater than 0: a fix writes its size, or 1 for 0.
    fn positive(&self, cx: &mut Checker<'_>) -> bool {
        let new: Vec<f64> = self
            .numbers()
            .iter()
            .map(|&x| if x == 0.0 { 1.0 } else { x.abs() })
            .collect();
        let mut ok = true;
        for (value, what) in self.values.iter().zip(self.spec.json) {
            if **value > 0.0 {
                continue;
            }
            ok = false;
            let fix = self.fix(&new, format::short, |line| format!("write `{line}`"));
            cx.problems.push(CheckError::DimensionNotPositive {
                what: what.to_string(),
                found: cx.text(value.span),
                span: value.span.into(),
                help: fix.help,
                fix: fix.fix,
            });
        }
        ok
    }

    /// Each number 0 or more (a fix writes 0), and a warning above
    /// `warn_above` (a fix scales the brightest down to it, keeping the
    /// hue).
    fn non_negative(&self, warn_above: f64, cx: &mut Checker<'_>) -> bool {
        let numbers = self.numbers();
        if let Some(span) = self.span_of(|x| x < 0.0) {
            let new: Vec<f64> = numbers.iter().map(|x| x.max(0.0)).collect();
            let fix = self.fix(&new, format::short, |line| format!("write `{line}`"));
            cx.problems.push(CheckError::NegativeLightColor {
                found: cx.text(self.span()),
                span: span.into(),
                help: fix.help,
                fix: fix.fix,
            });
            return false;
        }
        let brightest = numbers.iter().copied().fold(0.0, f64::max);
        if brightest > warn_above {
            let new: Vec<f64> = numbers.iter().map(|x| x / brightest * warn_above).collect();
            let fix = self.fix(&new, format::short, |line| {
                format!("to keep the hue without clipping, write `{line}`")
            });
            cx.problems.push(CheckError::LightColorAboveOne {
                span: self.span().into(),
                help: fix.help,
                fix: fix.fix,
            });
        }
        true
    }

    /// Not the zero vector: a fix writes the row's stand-in.
    fn non_zero(
        &self,
        stand_in: StandIn,
        sibling: &dyn Fn(&AttrName) -> Option<[f64; 3]>,
        cx: &mut Checker<'_>,
    ) -> bool {
        let numbers = self.numbers();
        let Ok(vector) = <[f64; 3]>::try_from(numbers.as_slice()) else {
            return true;
        };
        if geometry::unit(vector).is_some() {
            return true;
        }
        let span = self.span().into();
        match stand_in {
            StandIn::Across { facing, across } => {
                let turned = sibling(across).and_then(|other| turned_across(facing, other));
                let fix = match turned {
                    Some(v) if v != facing => self.fix(&v, format::number, |line| {
                        format!(
                            "write `{line}`: a plane's {} is perpendicular to its {}",
                            self.spec.name.as_str(),
                            across.as_str()
                        )
                    }),
                    _ => self.fix(&facing, format::number, |line| {
                        format!("write `{line}`, facing the camera")
                    }),
                };
                cx.problems.push(CheckError::ZeroNormal {
                    span,
                    help: fix.help,
                    fix: fix.fix,
                });
            }
            StandIn::PerpendicularTo(other) => {
                let perpendicular = sibling(other).and_then(perpendicular_to);
                let fix = match perpendicular {
                    Some(v) => self.fix(&v, format::number, |line| {
                        format!("write `{line}`, perpendicular to the {}", other.as_str())
                    }),
                    None => self.fix(&[0.0, 1.0, 0.0], format::number, |line| {
                        format!("write the plane's up direction, such as `{line}`")
                    }),
                };
                cx.problems.push(CheckError::ZeroHeadup {
                    span,
                    help: fix.help,
                    fix: fix.fix,
                });
            }
        }
        false
    }

    /// A whole number in `[min, max]`: a fix writes the nearest one.
    fn whole(&self, min: f64, max: f64, cx: &mut Checker<'_>) -> bool {
        let Some(value) = self.values.first() else {
            return true;
        };
        let n = value.value;
        let nearest = n.round().clamp(min, max);
        let found = cx.text(value.span);
        let span = value.span.into();
        if n.fract() != 0.0 {
            let fix = self.fix(&[nearest], format::short, |line| format!("write `{line}`"));
            cx.problems.push(CheckError::ResolutionNotInteger {
                found,
                span,
                help: fix.help,
                fix: fix.fix,
            });
            return false;
        }
        if !(min..=max).contains(&n) {
            let fix = self.fix(&[nearest], format::short, |line| {
                format!(
                    "the image is {0} × {0} pixels with {0} from {min} to {max}: write `{line}`",
                    self.spec.placeholder
                )
            });
            cx.problems.push(CheckError::ResolutionOutOfRange {
                min: format::short(min),
                max: format::short(max),
                found,
                span,
                help: fix.help,
                fix: fix.fix,
            });
            return false;
        }
        true
    }
}

/// `facing` made perpendicular to `other` (its component along `other`
/// removed; an axis perpendicular to `other` when nothing is left), scaled
/// so its largest component is ±1: `0 1 0` for `facing` `0 0 1` across
/// `0 0 -1`. `None` for a zero `other`.
fn turned_across(facing: [f64; 3], other: [f64; 3]) -> Option<[f64; 3]> {
    let h = geometry::unit(other)?;
    let f = glam::DVec3::from_array(facing);
    let mut v = f - f.dot(h) * h;
    if v.length() <= geometry::PARALLEL {
        let axis = geometry::stand_in_headup(h);
        v = axis - axis.dot(h) * h;
    }
    Some((v / v.abs().max_element()).to_array())
}

/// A vector perpendicular to `normal`: the stand-in headup of
/// [`geometry::stand_in_headup`] projected onto the plane. `None` for a
/// zero normal.
fn perpendicular_to(normal: [f64; 3]) -> Option<[f64; 3]> {
    let n = geometry::unit(normal)?;
    let axis = geometry::stand_in_headup(n);
    Some((axis - axis.dot(n) * n).to_array())
}
