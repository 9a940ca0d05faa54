//! The formatter behind `raytracer fmt` and the language server's document
//! formatting: scene text in one canonical layout, comments kept.
//!
//! The layout: each section keyword (and the camera's resolution) at column
//! 0, each attribute on its own line indented two spaces, one blank line
//! between sections. Every token is copied as written (numbers keep their
//! spelling: `.7` stays `.7`), so only whitespace changes and the parsed
//! tree is the same before and after.
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

/// `text` in the canonical layout, or the syntax errors that stop it from
/// being formatted (the text is then left as it is).
pub fn format(text: &str) -> Result<String, Vec<SyntaxError>> {
    let parsed = syntax::parse(text);
    if !parsed.errors.is_empty() {
        return Err(parsed.errors);
    }
    let mut tokens: Vec<(Span, Role)> = Vec::new();
    for section in &parsed.file.sections {
        tokens.push((section.kind.span, Role::Section));
        tokens.extend(section.args.iter().map(|v| (v.span, Role::Value)));
        for attribute in &section.attributes {
            tokens.push((attribute.name.span, Role::Attribute));
            tokens.extend(attribute.values.iter().map(|v| (v.span, Role::Value)));
        }
    }
    tokens.extend(
        syntax::trivia::comments(text)
            .into_iter()
            .map(|span| (span, Role::Comment)),
    );
    tokens.sort_by_key(|(span, _)| span.start());
    Ok(render(&lay_out(text, &tokens)))
}

/// Place each token on a line.
fn lay_out<'a>(text: &'a str, tokens: &[(Span, Role)]) -> Vec<Line<'a>> {
    let mut lines: Vec<Line<'a>> = Vec::new();
    let mut previous_end: Option<usize> = None;
    let mut in_section = false;
    for (index, &(span, role)) in tokens.iter().enumerate() {
        let token = &text[span.start()..span.end()];
        let gap = &text[previous_end.unwrap_or(0)..span.start()];
        let same_line = previous_end.is_some() && !gap.contains(is_line_end);
        previous_end = Some(span.end());
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
                        has_blank_line(gap)
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
                            .map(|&(_, role)| role)
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
                                && (after_section || !lines.is_empty() && has_blank_line(gap)),
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
    let width = |line: &Line| line.indent + line.code.chars().count();
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
        let block = &lines[start..end];
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
        start = end;
    }
    out
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
