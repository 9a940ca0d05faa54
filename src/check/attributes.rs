//! The checks every section shares: each attribute line is looked up in the
//! table of [`crate::language`] and its values read, reporting unknown and
//! misplaced names, duplicates, wrong value counts, strings where numbers
//! belong and missing required attributes. What survives is an
//! [`Attributes`] the per-section builders query by name.

use arrayvec::ArrayVec;

use crate::ast::{AttrName, Attribute, Section, SectionKind, Value};
use crate::fix::{Applicability, Fix};
use crate::span::{Span, Spanned};
use crate::suggest;

use super::errors::CheckError;
use super::Problems;
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
/// generic problem into `problems`.
pub fn collect<'a>(section: &'a Section, problems: &mut Problems) -> Attributes<'a> {
    let kind = &*section.kind;
    // At most one line per known name: unknown and repeated names are
    // reported and left out.
    let mut given = ArrayVec::<Given<'a>, MAX_GIVEN>::new();
    // Names that "did you mean" already offered: not reported missing too.
    let mut suggested: Vec<&'static str> = Vec::new();
    for attribute in &section.attributes {
        let Some(spec) = schema::find(kind, &attribute.name) else {
            let problem = not_taken(kind, attribute);
            if let CheckError::UnknownAttribute { found, .. } = &problem {
                suggested.extend(nearest_taken(kind, found));
            }
            problems.push(problem);
            continue;
        };
        if let Some(first) = given.iter().find(|g| *g.attribute.name == *attribute.name) {
            problems.push(CheckError::DuplicateAttribute {
                name: attribute.name.as_str().to_string(),
                section: kind.as_str().to_string(),
                first: first.attribute.name.span.into(),
                second: attribute.name.span.into(),
            });
            continue;
        }
        let read = read_values(spec, attribute, problems);
        given.push(Given { attribute, read });
    }
    report_missing(section, &given, &suggested, problems);
    Attributes { given }
}

/// The diagnostic for an attribute `kind` does not take.
fn not_taken(kind: &SectionKind, attribute: &Attribute) -> CheckError {
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
            let near = nearest_taken(kind, found);
            let help = match near {
                Some(near) => format!("did you mean `{near}`?"),
                None => match suggest::nearest(found, &AttrName::KEYWORDS) {
                    Some((near, _)) => format!(
                        "`{near}` is an attribute of {}; {takes_line}",
                        schema::list_or(&schema::sections_taking(&AttrName::from_word(near)))
                    ),
                    None => takes_line,
                },
            };
            CheckError::UnknownAttribute {
                fix: near.map(|near| {
                    Fix::boxed(
                        format!("replaced `{found}` with `{near}`"),
                        Applicability::Unsafe,
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
            CheckError::MisplacedAttribute {
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

/// The attribute of `kind` nearest to the unknown word `found`, if close.
fn nearest_taken(kind: &SectionKind, found: &str) -> Option<&'static str> {
    suggest::nearest(found, &names_taken(kind)).map(|(near, _)| near)
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
    attribute: &'a Attribute,
    problems: &mut Problems,
) -> Option<Read<'a>> {
    let name = attribute.name.as_str();
    let expected_count = match spec.arity {
        Arity::Numbers(n) => n,
        Arity::Path => 1,
    };
    let mut ok = true;
    // The texts are built only for a wrong count: a large scene has
    // millions of attributes.
    if attribute.values.len() != expected_count {
        let expected = match spec.arity {
            Arity::Numbers(1) => "1 value".to_string(),
            Arity::Numbers(n) => format!("{n} values"),
            Arity::Path => "1 path".to_string(),
        };
        if let Some(problem) = count_problem(
            name,
            &expected,
            expected_count,
            attribute.name.span,
            &attribute.values,
            &format!("write `{name} {}`", spec.placeholder),
        ) {
            problems.push(problem);
            ok = false;
        }
    }
    if attribute.values.iter().any(|v| v.value == Value::Invalid) {
        problems.mark_incomplete();
        ok = false;
    }
    match spec.arity {
        Arity::Numbers(_) => {
            let mut numbers = ArrayVec::new();
            for value in &attribute.values {
                match &value.value {
                    // Kept only while the count is right (then at most
                    // MAX_NUMBERS); otherwise nothing is built anyway.
                    Value::Number(n) if ok => numbers.push(Spanned::new(value.span, *n)),
                    Value::Number(_) => {}
                    Value::Text(text) => {
                        problems.push(CheckError::NotANumber {
                            name: name.to_string(),
                            found: text.to_string(),
                            span: value.span.into(),
                        });
                        ok = false;
                    }
                    Value::Invalid => {}
                }
            }
            ok.then_some(Read::Numbers(numbers))
        }
        Arity::Path => match attribute.values.first().map(|v| (&v.value, v.span)) {
            Some((Value::Text(text), span)) if ok => Some(Read::Path(Spanned::new(span, &**text))),
            _ => None,
        },
    }
}

/// The wrong-count diagnostic for `values` after `name_span`, if the count
/// is not `expected_count`. Shared with the camera line.
pub fn count_problem(
    name: &str,
    expected: &str,
    expected_count: usize,
    name_span: Span,
    values: &[Spanned<Value>],
    help: &str,
) -> Option<CheckError> {
    let found = values.len();
    if found == expected_count {
        return None;
    }
    let (span, label) = if found > expected_count {
        let extra = &values[expected_count..];
        let span = extra[0].span.join(extra[extra.len() - 1].span);
        let n = extra.len();
        (
            span,
            format!("{n} extra value{}", if n == 1 { "" } else { "s" }),
        )
    } else {
        let span = values.last().map_or(name_span, |v| name_span.join(v.span));
        (span, format!("{found} of {expected_count}"))
    };
    Some(CheckError::WrongValueCount {
        name: name.to_string(),
        expected: expected.to_string(),
        found,
        span: span.into(),
        label,
        help: help.to_string(),
    })
}

/// One diagnostic listing every required attribute `section` lacks.
/// `suggested` are names a misspelling was already matched to.
fn report_missing(
    section: &Section,
    given: &[Given<'_>],
    suggested: &[&str],
    problems: &mut Problems,
) {
    let missing: Vec<&AttrSpec> = schema::attributes_of(&section.kind)
        .iter()
        .filter(|s| s.required && !given.iter().any(|g| *g.attribute.name == s.name))
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
    problems.push(CheckError::MissingAttribute {
        section: kind,
        names: schema::list(&names),
        span: section.kind.span.into(),
        help,
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
