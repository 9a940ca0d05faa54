//! The formatter behind `raytracer fmt` and the language server's document
//! formatting: scene text in one canonical layout, comments kept.
//!
//! The layout: each section keyword (and the camera's resolution) at column
//! 0, each attribute on its own line indented two spaces, in the order of
//! the language table ([`crate::language::attributes_of`]: `dimension`,
//! `center`, `normal`, `headup`, `color`, `reflectivity`, `texture`; a
//! name the section does not take after them, as written), one blank line
//! between sections. Numbers are spelt as [`number`] spells them (`.7` is
//! `0.7`, `1e2` is `100`), the same `f64` bit for bit; words and strings
//! are copied as written. `convert --to scene` prints a scene's model with
//! the same spelling and order through the same renderer ([`Printer`]),
//! so the two agree on one canonical form (they differ only in what the
//! model keeps: no comments, no attribute at its default value, the
//! lights after the objects).
//!
//! Comments come from [`syntax::trivia`] and are placed by where they stood
//! relative to the tree's nodes:
//! - a comment on the same line as a token stays at the end of that line
//!   (trailing comments of a section are aligned one space past its longest
//!   commented line);
//! - a comment on its own line leads the node after it: indented two spaces
//!   before an attribute, four among an attribute's values (which then
//!   continue on a line of their own, four spaces in), and at column 0
//!   before a section keyword or at the end of the file. An indented comment
//!   after a section's last attribute stays in that section (a commented-out
//!   attribute) rather than leading the next one.
//!
//! Blank lines are kept (one at most) only between comments and sections at
//! column 0, where they separate a file's header from its first section; a
//! comment at column 0 after a section is set off from it by one.
//! Text with syntax errors is not formatted: [`format`] returns the errors.

use crate::ast::Value;
use crate::language::attributes_of;
use crate::span::Span;
use crate::syntax::{self, is_line_end, SyntaxError};

/// What a token of the layout is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    Section,
    Attribute,
    Value,
    Comment,
}

/// One output line: indentation, code, and a trailing comment.
#[derive(Debug, Default)]
struct Line<'a> {
    indent: usize,
    code: String,
    comment: Option<&'a str>,
    blank_before: bool,
    /// A comment at column 0, outside any section's layout.
    file_level: bool,
}

/// One token of the text, with what the layout needs of where it stood.
#[derive(Clone, Debug)]
struct Token {
    span: Span,
    role: Role,
    /// Its canonical spelling, when not as written (a number).
    spelt: Option<String>,
    /// On the line of the token before it, in the text as written.
    same_line: bool,
    /// A blank line between it and the token before it, as written.
    after_blank: bool,
    /// The attribute it starts, by its place in the language table.
    rank: usize,
}

/// `x` as the shortest scene-language number that reads back as exactly
/// `x`: plain decimals from 1e-5 up to 1e15 (`0.3`, `-2`, `16384`, `-0`),
/// an exponent outside that (`1e-7`, `1.5e300`). Rust's `Display` and
/// `LowerExp` for `f64` print the fewest digits that round-trip.
/// `x` must be finite, as every number in a checked scene is.
pub fn number(x: f64) -> String {
    let magnitude = x.abs();
    if magnitude == 0.0 || (1e-5..1e15).contains(&magnitude) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// `text` in the canonical layout, or the syntax errors that stop it from
/// being formatted (the text is then left as it is).
pub fn format(text: &str) -> Result<String, Vec<SyntaxError>> {
    let parsed = syntax::parse(text);
    if !parsed.errors.is_empty() {
        return Err(parsed.errors);
    }
    // Each token with its spelling and, for an attribute name, its rank.
    let mut tokens: Vec<(Span, Role, Option<String>, usize)> = Vec::new();
    let spelt = |value: &Value| match value {
        Value::Number(x) => Some(number(*x)),
        Value::Text(_) | Value::Invalid => None,
    };
    for section in &parsed.file.sections {
        tokens.push((section.kind.span, Role::Section, None, 0));
        let values = |values: &[crate::span::Spanned<Value>]| {
            values
                .iter()
                .map(|v| (v.span, Role::Value, spelt(&v.value), 0))
                .collect::<Vec<_>>()
        };
        tokens.extend(values(&section.args));
        let table = attributes_of(&section.kind);
        for attribute in &section.attributes {
            let rank = table
                .iter()
                .position(|spec| spec.attr_name() == *attribute.name)
                .unwrap_or(table.len());
            tokens.push((attribute.name.span, Role::Attribute, None, rank));
            tokens.extend(values(&attribute.values));
        }
    }
    tokens.extend(
        syntax::trivia::comments(text)
            .into_iter()
            .map(|span| (span, Role::Comment, None, 0)),
    );
    tokens.sort_by_key(|(span, ..)| span.start());
    let mut previous_end: Option<usize> = None;
    let tokens: Vec<Token> = tokens
        .into_iter()
        .map(|(span, role, spelt, rank)| {
            let gap = &text[previous_end.unwrap_or(0)..span.start()];
            let same_line = previous_end.is_some() && !gap.contains(is_line_end);
            previous_end = Some(span.end());
            Token {
                span,
                role,
                spelt,
                same_line,
                after_blank: has_blank_line(gap),
                rank,
            }
        })
        .collect();
    Ok(render(&lay_out(text, &in_table_order(tokens))))
}

/// The tokens with each section's attributes in the order of the language
/// table (stable: two of a name keep theirs). An attribute moves with its
/// values, the comments on their lines and the comments on lines of their
/// own before it; what comes before a section's first attribute (its
/// keyword and values) and the comments after its last stay in place.
fn in_table_order(tokens: Vec<Token>) -> Vec<Token> {
    let mut out: Vec<Token> = Vec::with_capacity(tokens.len());
    // The attributes of the current section, each with the tokens it
    // carries, and comments waiting for the token they lead.
    let mut units: Vec<Vec<Token>> = Vec::new();
    let mut waiting: Vec<Token> = Vec::new();
    let flush = |out: &mut Vec<Token>, units: &mut Vec<Vec<Token>>, waiting: &mut Vec<Token>| {
        units.sort_by_key(|unit| unit[0].rank);
        out.extend(units.drain(..).flatten());
        out.append(waiting);
    };
    for token in tokens {
        match token.role {
            Role::Section => {
                flush(&mut out, &mut units, &mut waiting);
                out.push(token);
            }
            Role::Attribute => {
                let mut unit = std::mem::take(&mut waiting);
                // The rank of a unit is its first token's.
                let rank = token.rank;
                unit.iter_mut().for_each(|t| t.rank = rank);
                unit.push(token);
                units.push(unit);
            }
            Role::Comment if !token.same_line => waiting.push(token),
            Role::Value | Role::Comment => {
                let carried = std::mem::take(&mut waiting);
                match units.last_mut() {
                    Some(unit) => {
                        unit.extend(carried);
                        unit.push(token);
                    }
                    None => {
                        out.extend(carried);
                        out.push(token);
                    }
                }
            }
        }
    }
    flush(&mut out, &mut units, &mut waiting);
    out
}

/// Place each token on a line.
fn lay_out<'a>(text: &'a str, tokens: &'a [Token]) -> Vec<Line<'a>> {
    let mut lines: Vec<Line<'a>> = Vec::new();
    let mut in_section = false;
    for (index, token_at) in tokens.iter().enumerate() {
        let (span, role, same_line) = (token_at.span, token_at.role, token_at.same_line);
        let token = token_at
            .spelt
            .as_deref()
            .unwrap_or(&text[span.start()..span.end()]);
        match role {
            Role::Section => {
                in_section = true;
                let lead = lines.iter().rev().take_while(|l| l.file_level).count();
                let first_lead = lines.len() - lead;
                if lead > 0 && first_lead > 0 {
                    lines[first_lead].blank_before = true;
                }
                lines.push(Line {
                    code: token.to_string(),
                    blank_before: if lead > 0 {
                        token_at.after_blank
                    } else {
                        !lines.is_empty()
                    },
                    ..Line::default()
                });
            }
            Role::Attribute => lines.push(Line {
                indent: 2,
                code: token.to_string(),
                ..Line::default()
            }),
            Role::Value => match lines.last_mut() {
                Some(line) if line.comment.is_none() => {
                    line.code.push(' ');
                    line.code.push_str(token);
                }
                _ => lines.push(Line {
                    indent: 4,
                    code: token.to_string(),
                    ..Line::default()
                }),
            },
            Role::Comment => {
                let comment = token.trim_end();
                match lines.last_mut() {
                    Some(line) if same_line && !line.code.is_empty() => {
                        line.comment = Some(comment);
                    }
                    _ => {
                        let next = tokens[index + 1..]
                            .iter()
                            .map(|t| t.role)
                            .find(|&role| role != Role::Comment);
                        let indented = column_of(text, span.start()) > 0;
                        let indent = match next {
                            _ if !in_section => 0,
                            Some(Role::Value) => 4,
                            Some(Role::Attribute) => 2,
                            _ if indented => 2,
                            _ => 0,
                        };
                        let file_level = indent == 0;
                        // A blank line ends a section, as between sections.
                        let after_section = lines.last().is_some_and(|l| !l.file_level);
                        lines.push(Line {
                            indent,
                            comment: Some(comment),
                            blank_before: file_level
                                && (after_section || !lines.is_empty() && token_at.after_blank),
                            file_level,
                            ..Line::default()
                        });
                    }
                }
            }
        }
    }
    lines
}

/// The lines as text, trailing comments aligned within each section.
fn render(lines: &[Line]) -> String {
    let mut out = String::new();
    let mut start = 0;
    while start < lines.len() {
        // A block: a section's lines, or one line outside a section.
        let mut end = start + 1;
        if !lines[start].file_level {
            while end < lines.len() && !lines[end].file_level && !is_section_start(&lines[end]) {
                end += 1;
            }
        }
        render_block(&lines[start..end], &mut out);
        start = end;
    }
    out
}

/// One block of lines (a section's, or one outside any) onto `out`, its
/// trailing comments aligned.
fn render_block(block: &[Line], out: &mut String) {
    let width = |line: &Line| line.indent + line.code.chars().count();
    let column = block
        .iter()
        .filter(|l| l.comment.is_some() && !l.code.is_empty())
        .map(width)
        .max()
        .unwrap_or(0);
    for line in block {
        if line.blank_before {
            out.push('\n');
        }
        out.extend(std::iter::repeat_n(' ', line.indent));
        out.push_str(&line.code);
        if let Some(comment) = line.comment {
            if !line.code.is_empty() {
                out.extend(std::iter::repeat_n(' ', column - width(line) + 1));
            }
            out.push_str(comment);
        }
        out.push('\n');
    }
}

/// Scene text in the canonical layout, written a section at a time from
/// values rather than laid out from a file: `convert --to scene` prints
/// with it, through the renderer `fmt` uses, so the two print one form.
#[derive(Debug, Default)]
pub struct Printer {
    out: String,
}

impl Printer {
    /// A section: its keyword line (`camera 400`, `sphere`), then each
    /// attribute line (`dimension 0.5`) in the order given.
    pub fn section<'a>(&mut self, keyword: &str, attributes: impl IntoIterator<Item = &'a str>) {
        let mut lines = vec![Line {
            code: keyword.to_string(),
            blank_before: !self.out.is_empty(),
            ..Line::default()
        }];
        lines.extend(attributes.into_iter().map(|attribute| Line {
            indent: 2,
            code: attribute.to_string(),
            ..Line::default()
        }));
        render_block(&lines, &mut self.out);
    }

    /// The text printed, ending in a newline unless empty.
    pub fn finish(self) -> String {
        self.out
    }
}

fn is_section_start(line: &Line) -> bool {
    line.indent == 0 && !line.code.is_empty()
}

/// True when `gap` (whitespace between two tokens) holds an empty line.
fn has_blank_line(gap: &str) -> bool {
    let breaks = gap.chars().filter(|&c| is_line_end(c)).count() - gap.matches("\r\n").count();
    breaks >= 2
}

/// The column (in bytes) of `offset` on its line.
fn column_of(text: &str, offset: usize) -> usize {
    let line_start = text[..offset].rfind(is_line_end).map_or(0, |i| {
        i + text[i..].chars().next().map_or(1, char::len_utf8)
    });
    offset - line_start
}

#[cfg(test)]
mod tests;
