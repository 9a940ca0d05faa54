//! The checks every section shares: each attribute line is looked up in the
//! table of [`crate::language`] and its values read, reporting unknown and
//! misplaced names, duplicates, wrong value counts, strings where numbers
//! belong and missing required attributes; then each line's values are
//! held to its row's single-attribute rule ([`super::rules`]). What
//! survives is an [`Attributes`] the per-section builders query by name.

use arrayvec::ArrayVec;

use crate::ast::{AttrName, Attribute, Section, SectionKind, Value};
use crate::fix::{self, Applicability, Fix};
use crate::span::{Span, Spanned};
use crate::suggest;

use super::errors::CheckError;
use super::{rules, Checker};
use crate::language::{self as schema, Arity, AttrSpec};

/// The most numbers an attribute takes (a vector's three); the language
/// table is held to it by a test.
const MAX_NUMBERS: usize = 3;

/// The most attribute lines a section keeps: one per attribute name.
const MAX_GIVEN: usize = AttrName::KEYWORDS.len();

/// The values of one attribute line that passed the generic checks.
/// Inline, not on the heap: a large scene has millions of attribute lines.
#[derive(Debug)]
pub enum Read<'a> {
    Numbers(ArrayVec<Spanned<f64>, MAX_NUMBERS>),
    Path(Spanned<&'a str>),
}

/// One attribute line the section takes, with its values when they read.
#[derive(Debug)]
pub struct Given<'a> {
    pub attribute: &'a Attribute,
    /// Its row in the registry.
    spec: &'static AttrSpec,
    /// `None` when the values had a problem (already reported).
    pub read: Option<Read<'a>>,
}

/// The attributes of one section, first occurrence of each name.
#[derive(Debug)]
pub struct Attributes<'a> {
    given: ArrayVec<Given<'a>, MAX_GIVEN>,
}

impl<'a> Attributes<'a> {
    /// The attribute line for `name`, whether or not its values read.
    pub fn line(&self, name: &AttrName) -> Option<&'a Attribute> {
        self.find(name).map(|g| g.attribute)
    }

    fn find(&self, name: &AttrName) -> Option<&Given<'a>> {
        self.given.iter().find(|g| *g.attribute.name == *name)
    }

    /// The numbers of `name`, when given and valid.
    pub fn numbers(&self, name: &AttrName) -> Option<&[Spanned<f64>]> {
        match self.find(name)?.read.as_ref()? {
            Read::Numbers(numbers) => Some(numbers.as_slice()),
            Read::Path(_) => None,
        }
    }

    /// The three numbers of `name` as a vector, with the span of all three.
    pub fn vector(&self, name: &AttrName) -> Option<Spanned<[f64; 3]>> {
        match self.numbers(name)? {
            [x, y, z] => Some(Spanned::new(x.span.join(z.span), [**x, **y, **z])),
            _ => None,
        }
    }

    /// The path of `name`, when given and valid.
    pub fn path(&self, name: &AttrName) -> Option<Spanned<&'a str>> {
        match self.find(name)?.read.as_ref()? {
            Read::Path(path) => Some(*path),
            Read::Numbers(_) => None,
        }
    }
}

/// Read the attributes of `section` (a known section kind), reporting every
/// generic problem and every broken single-attribute rule.
pub fn collect<'a>(section: &'a Section, cx: &mut Checker<'_>) -> Attributes<'a> {
    let kind = &*section.kind;
    // At most one line per known name: unknown and repeated names are
    // reported and left out. Filled where it is returned from: it is
    // large, and a large scene has millions of sections.
    let mut attributes = Attributes {
        given: ArrayVec::new(),
    };
    let given = &mut attributes.given;
    // Names that "did you mean" already offered: not reported missing too.
    let mut suggested: Vec<&'static str> = Vec::new();
    for attribute in &section.attributes {
        let Some(spec) = schema::find(kind, &attribute.name) else {
            let problem = not_taken(kind, attribute, cx);
            if let CheckError::UnknownAttribute { found, .. } = &problem {
                suggested.extend(replacement(kind, found).map(|(name, _)| name));
            }
            cx.problems.push(problem);
            continue;
        };
        if let Some(first) = given.iter().find(|g| *g.attribute.name == *attribute.name) {
            let fix = cx.removal(
                &format!("remove the second `{}` line", attribute.name.as_str()),
                Applicability::Unsafe,
                attribute.span,
            );
            cx.problems.push(CheckError::DuplicateAttribute {
                fix,
                name: attribute.name.as_str().to_string(),
                section: kind.as_str().to_string(),
                first: first.attribute.name.span.into(),
                second: attribute.name.span.into(),
            });
            continue;
        }
        let read = read_values(spec, attribute.name.span, &attribute.values, cx);
        given.push(Given {
            attribute,
            spec,
            read,
        });
    }
    report_missing(section, given, &suggested, cx);
    attributes.apply_rules(cx);
    attributes
}

impl Attributes<'_> {
    /// Hold each line's numbers to its row's rule; a line that breaks it
    /// keeps no values.
    fn apply_rules(&mut self, cx: &mut Checker<'_>) {
        let mut broken = ArrayVec::<usize, MAX_GIVEN>::new();
        for (i, given) in self.given.iter().enumerate() {
            let Some(Read::Numbers(numbers)) = &given.read else {
                continue;
            };
            let sibling = |name: &AttrName| self.vector(name).map(|v| v.value);
            if !rules::check(given.spec, numbers, &sibling, cx) {
                broken.push(i);
            }
        }
        for i in broken {
            self.given[i].read = None;
        }
    }
}

/// The values after the `camera` keyword, checked against the registry's
/// camera row ([`schema::CAMERA`]): its count, that they are numbers, and
/// its rule. The resolution, when valid.
pub fn camera_values(
    keyword: &Spanned<SectionKind>,
    values: &[Spanned<Value>],
    cx: &mut Checker<'_>,
) -> Option<f64> {
    let spec = &schema::CAMERA;
    let Some(Read::Numbers(numbers)) = read_values(spec, keyword.span, values, cx) else {
        return None;
    };
    let nothing = |_: &AttrName| None;
    rules::check(spec, &numbers, &nothing, cx).then(|| numbers[0].value)
}

/// The diagnostic for an attribute `kind` does not take.
fn not_taken(kind: &SectionKind, attribute: &Attribute, cx: &Checker<'_>) -> CheckError {
    let section = kind.as_str().to_string();
    let takes = names_taken(kind);
    let takes_line = if takes.is_empty() {
        "the camera takes no attributes, only its resolution: `camera 400`".to_string()
    } else {
        format!("`{section}` takes {}", schema::list(&takes))
    };
    let span = attribute.name.span.into();
    match &*attribute.name {
        AttrName::Unknown(found) => {
            let near = replacement(kind, found);
            let help = match near {
                Some((near, Replacement::JsonName)) => format!(
                    "`{found}` is the JSON name; in scene text a {section}'s `{found}` is `{near}`"
                ),
                Some((near, Replacement::Near)) => format!("did you mean `{near}`?"),
                None => match suggest::nearest(found, &AttrName::KEYWORDS) {
                    Some((near, _)) => format!(
                        "`{near}` is an attribute of {}; {takes_line}",
                        schema::list_or(&schema::sections_taking(&AttrName::from_word(near)))
                    ),
                    None => takes_line,
                },
            };
            CheckError::UnknownAttribute {
                fix: near.map(|(near, replacement)| {
                    // A JSON field name has one scene-text name: safe.
                    let applicability = match replacement {
                        Replacement::JsonName => Applicability::Safe,
                        Replacement::Near => Applicability::Unsafe,
                    };
                    Fix::boxed(
                        format!("replace `{found}` with `{near}`"),
                        applicability,
                        attribute.name.span,
                        near,
                    )
                }),
                found: found.to_string(),
                section,
                span,
                help,
            }
        }
        name => {
            let owners = schema::sections_taking(name);
            // Under the camera, the line more likely lacks its section
            // keyword (which one is the author's call) than is misplaced.
            let fix = if takes.is_empty() {
                None
            } else {
                cx.removal(
                    &format!("remove the `{}` line", name.as_str()),
                    Applicability::Unsafe,
                    attribute.span,
                )
            };
            CheckError::MisplacedAttribute {
                fix,
                name: name.as_str().to_string(),
                belongs: format!("only {} take `{}`", plural_list(&owners), name.as_str()),
                section,
                span,
                help: if takes.is_empty() {
                    format!(
                        "the camera takes only its resolution; is a {} line missing?",
                        schema::list_or(&owners)
                    )
                } else {
                    format!("remove this line; {takes_line}")
                },
            }
        }
    }
}

/// The attribute names `kind` takes.
fn names_taken(kind: &SectionKind) -> Vec<&'static str> {
    schema::attributes_of(kind)
        .iter()
        .map(|s| s.name.as_str())
        .collect()
}

/// Why an unknown attribute name is taken for another.
#[derive(Clone, Copy)]
enum Replacement {
    /// It is the JSON field name of an attribute named otherwise in scene
    /// text (`radius` for a sphere's `dimension`).
    JsonName,
    /// It is close to the name (a misspelling).
    Near,
}

/// The attribute of `kind` the unknown word `found` stands for, if any.
fn replacement(kind: &SectionKind, found: &str) -> Option<(&'static str, Replacement)> {
    if let Some(spec) = schema::from_json_name(kind, found) {
        return Some((spec.name.as_str(), Replacement::JsonName));
    }
    suggest::nearest(found, &names_taken(kind)).map(|(near, _)| (near, Replacement::Near))
}

/// "planes", "spheres and planes" for "only … take `x`".
fn plural_list(sections: &[&str]) -> String {
    let plural: Vec<String> = sections.iter().map(|s| format!("{s}s")).collect();
    match plural.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => plural.concat(),
    }
}

/// Read an attribute's values per its arity, reporting strings where
/// numbers belong and wrong counts. `None` when they do not read (also,
/// silently, when the parser already reported a malformed value).
fn read_values<'a>(
    spec: &AttrSpec,
    name_span: Span,
    values: &'a [Spanned<Value>],
    cx: &mut Checker<'_>,
) -> Option<Read<'a>> {
    let name = spec.name.as_str();
    let expected_count = spec.count();
    let mut ok = true;
    // The texts are built only for a wrong count: a large scene has
    // millions of attributes.
    if values.len() != expected_count {
        let expected = match spec.arity {
            Arity::Numbers(1) => "1 value".to_string(),
            Arity::Numbers(n) => format!("{n} values"),
            Arity::Path => "1 path".to_string(),
        };
        cx.problems
            .push(count_problem(spec, &expected, name_span, values, cx));
        ok = false;
    }
    let problems = &mut cx.problems;
    if values.iter().any(|v| v.value == Value::Invalid) {
        problems.mark_incomplete();
        ok = false;
    }
    match spec.arity {
        Arity::Numbers(_) => {
            let mut numbers = ArrayVec::new();
            for value in values {
                match &value.value {
                    // Kept only while the count is right (then at most
                    // MAX_NUMBERS); otherwise nothing is built anyway.
                    Value::Number(n) if ok => numbers.push(Spanned::new(value.span, *n)),
                    Value::Number(_) => {}
                    Value::Text(text) => {
                        // A number in quotes has one right reading.
                        let fix = crate::syntax::is_number(text.trim()).then(|| {
                            Fix::boxed(
                                format!("remove the quotes around `{}`", text.trim()),
                                Applicability::Safe,
                                value.span,
                                text.trim(),
                            )
                        });
                        problems.push(CheckError::NotANumber {
                            name: name.to_string(),
                            found: text.to_string(),
                            span: value.span.into(),
                            fix,
                        });
                        ok = false;
                    }
                    Value::Invalid => {}
                }
            }
            ok.then_some(Read::Numbers(numbers))
        }
        Arity::Path => match values.first().map(|v| (&v.value, v.span)) {
            Some((Value::Text(text), span)) if ok => Some(Read::Path(Spanned::new(span, &**text))),
            _ => None,
        },
    }
}

/// The wrong-count diagnostic for `values` after `name_span` (whose count
/// is not `spec`'s). Surplus values get a fix that drops them, and a line
/// with no values one that writes the registry's example values (scene
/// text only); both unsafe: the values dropped or written are a guess. A
/// line short of some values gets none: which one is missing is unknown.
fn count_problem(
    spec: &AttrSpec,
    expected: &str,
    name_span: Span,
    values: &[Spanned<Value>],
    cx: &Checker<'_>,
) -> CheckError {
    let name = spec.name.as_str();
    let expected_count = spec.count();
    let found = values.len();
    let placeholder = format!("write `{name} {}`", spec.placeholder);
    let (span, label, fix) = if found > expected_count {
        let extra = &values[expected_count..];
        let span = extra[0].span.join(extra[extra.len() - 1].span);
        let n = extra.len();
        // From the end of the last value kept, so a JSON array keeps its
        // commas right.
        let kept = values[..expected_count]
            .last()
            .map_or(name_span, |v| v.span);
        // The name as the language spells it (`Camera` is the parser's
        // `syntax::keyword_case`), then the values kept as written.
        let written_name = cx.text(name_span);
        let kept_line = if written_name.eq_ignore_ascii_case(name) {
            format!("{name}{}", cx.text(Span::new(name_span.end(), kept.end())))
        } else {
            cx.text(name_span.join(kept))
        };
        let fix = Fix::boxed(
            format!("write `{kept_line}`"),
            Applicability::Unsafe,
            Span::new(kept.end(), span.end()),
            "",
        );
        let values = if n == 1 { "value" } else { "values" };
        (span, format!("{n} extra {values}"), Some(fix))
    } else {
        let span = values.last().map_or(name_span, |v| name_span.join(v.span));
        let example = &spec.example[spec.example.find(' ').unwrap_or(0)..];
        let numbers = matches!(spec.arity, Arity::Numbers(_));
        let fix = (found == 0 && numbers && cx.scene_text).then(|| {
            Fix::boxed(
                format!("write `{name}{example}`, the example values"),
                Applicability::Unsafe,
                Span::point(name_span.end()),
                example,
            )
        });
        (span, format!("{found} of {expected_count}"), fix)
    };
    CheckError::WrongValueCount {
        name: name.to_string(),
        expected: expected.to_string(),
        found,
        span: span.into(),
        label,
        help: fix.as_ref().map_or(placeholder, |f| f.message.clone()),
        fix,
    }
}

/// One diagnostic listing every required attribute `section` lacks.
/// `suggested` are names a misspelling was already matched to.
fn report_missing(
    section: &Section,
    given: &[Given<'_>],
    suggested: &[&str],
    cx: &mut Checker<'_>,
) {
    let missing: Vec<&AttrSpec> = schema::attributes_of(&section.kind)
        .iter()
        .filter(|s| s.required && !given.iter().any(|g| s.name == *g.attribute.name))
        .filter(|s| !suggested.contains(&s.name.as_str()))
        .collect();
    if missing.is_empty() {
        return;
    }
    let kind = section.kind.as_str().to_string();
    let names: Vec<&str> = missing.iter().map(|s| s.name.as_str()).collect();
    let lines: Vec<String> = missing
        .iter()
        .map(|s| format!("  {} {}", s.name.as_str(), s.placeholder))
        .collect();
    let help = if lines.len() == 1 {
        format!("add a line `{}` to this {kind}", lines[0].trim())
    } else {
        format!("add these lines to this {kind}:\n{}", lines.join("\n"))
    };
    let fix = cx.scene_text.then(|| {
        let examples: Vec<&str> = missing.iter().map(|s| s.example).collect();
        let last = section.attributes.last().map(|a| a.span);
        let last_value = section.args.last().map(|v| v.span);
        let after = last.or(last_value).unwrap_or(section.kind.span);
        Box::new(Fix {
            message: format!("add {}, the example values", schema::list(&examples)),
            applicability: Applicability::Unsafe,
            edits: vec![fix::insertion(
                &cx.source.text,
                after,
                last.is_none(),
                &examples,
            )],
        })
    });
    cx.problems.push(CheckError::MissingAttribute {
        section: kind,
        names: schema::list(&names),
        span: section.kind.span.into(),
        help,
        fix,
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_attribute_fits_the_inline_buffers() {
        for keyword in SectionKind::KEYWORDS {
            let specs = schema::attributes_of(&SectionKind::from_word(keyword));
            assert!(specs.len() <= MAX_GIVEN, "{keyword}");
            for spec in specs {
                if let Arity::Numbers(n) = spec.arity {
                    assert!(n <= MAX_NUMBERS, "{keyword} {}", spec.name.as_str());
                }
            }
        }
    }
}
