//! The scene-language parser.
//!
//! Each lexical rule of `grammar/scene.ebnf` is a nom 8 parser function of the
//! same name whose doc comment quotes the rule. The structural rules (`file`,
//! `section`, `attribute`, `values`) are methods on a small cursor that calls
//! those token parsers, records every syntax error it meets, skips the bad
//! token and carries on, so one run reports every problem in the file.
//!
//! [`parse`] returns the whole tree; [`sections`] yields it a section at a
//! time, for a caller that checks each and lets it go.
//!
//! Spans are byte offsets into the parsed text, computed with nom's
//! [`Offset`] trait from the remaining input (as kdl-rs does).

pub mod errors;
pub mod trivia;

use nom::branch::alt;
use nom::bytes::complete::{take_till1, take_while1};
use nom::character::complete::{char, digit1, one_of};
use nom::combinator::{opt, recognize};
use nom::multi::many0_count;
use nom::sequence::preceded;
use nom::{IResult, Offset, Parser};

use crate::ast::{AttrName, Attribute, File, Section, SectionKind, Value};
use crate::span::{Span, Spanned};
use crate::suggest;
pub use errors::SyntaxError;

/// The result of parsing: the tree (always produced) and every syntax error.
#[derive(Debug)]
pub struct Parsed {
    pub file: File,
    pub errors: Vec<SyntaxError>,
}

/// Parse scene text. Never fails and never panics: problems are returned in
/// [`Parsed::errors`] and the tree holds everything that could be read.
pub fn parse(text: &str) -> Parsed {
    let mut sections = sections(text);
    let file = File {
        sections: sections.by_ref().collect(),
    };
    Parsed {
        file,
        errors: sections.into_errors(),
    }
}

/// Parse scene text one section at a time: the sections [`parse`] puts in
/// its tree, in order, so a caller can check each and drop it (a large
/// scene's tree then never exists whole). The syntax errors come after the
/// last section, from [`Sections::into_errors`].
pub fn sections(text: &str) -> Sections<'_> {
    Sections {
        cursor: Cursor {
            src: text,
            rest: text,
            errors: Vec::new(),
            scratch: Vec::new(),
        },
    }
}

/// The sections of a text, parsed as they are asked for.
pub struct Sections<'a> {
    cursor: Cursor<'a>,
}

impl Sections<'_> {
    /// Every syntax error met so far (all of them, once the sections ran out).
    pub fn into_errors(self) -> Vec<SyntaxError> {
        self.cursor.errors
    }
}

impl Iterator for Sections<'_> {
    type Item = Section;

    fn next(&mut self) -> Option<Section> {
        self.cursor.file()
    }
}

type Res<'a, T> = IResult<&'a str, T>;

/// `line_end = "\n" | "\r" | "\u{85}" | "\u{2028}" | "\u{2029}" ;`
pub fn is_line_end(c: char) -> bool {
    matches!(c, '\n' | '\r' | '\u{85}' | '\u{2028}' | '\u{2029}')
}

/// `space_char = ? any Unicode White_Space character ? | "\u{FEFF}" ;`
fn is_space_char(c: char) -> bool {
    c.is_whitespace() || c == '\u{FEFF}'
}

/// `word_char = ? any character ? - space_char - "#" - '"' ;`
pub fn is_word_char(c: char) -> bool {
    !is_space_char(c) && c != '#' && c != '"'
}

/// `whitespace = space_char , { space_char } ;`
fn whitespace(i: &str) -> Res<'_, &str> {
    take_while1(is_space_char).parse(i)
}

/// The rest of the line, up to (not including) a `line_end` or the end of
/// input.
///
/// Hand-written because nom 8.0.0's `take_till`/`digit0` on `&str` return a
/// remainder that points at the *start* of the input when they reach its
/// end, which breaks `recognize` and every offset computed from it.
fn rest_of_line(i: &str) -> Res<'_, &str> {
    let end = i.find(is_line_end).unwrap_or(i.len());
    Ok((&i[end..], &i[..end]))
}

/// `comment = "#" , { ? any character ? - line_end } ;`
fn comment(i: &str) -> Res<'_, &str> {
    recognize(preceded(char('#'), rest_of_line)).parse(i)
}

/// `trivia = { whitespace | comment } ;`
fn trivia(i: &str) -> Res<'_, usize> {
    many0_count(alt((whitespace, comment))).parse(i)
}

/// `word = word_char , { word_char } ;`
fn word(i: &str) -> Res<'_, &str> {
    take_till1(|c| !is_word_char(c)).parse(i)
}

/// `string = '"' , { string_char | "\\" , ( '"' | "\\" ) } , '"' ;`
/// `string_char = ? any character ? - '"' - "\\" - line_end ;`
///
/// Fails with `nom::Err::Failure` when the line ends before the closing quote.
fn string(i: &str) -> Res<'_, String> {
    let (mut rest, _) = char('"').parse(i)?;
    let mut out = String::new();
    loop {
        let mut chars = rest.chars();
        match chars.next() {
            Some('"') => return Ok((chars.as_str(), out)),
            Some('\\') if matches!(chars.clone().next(), Some('"' | '\\')) => {
                out.extend(chars.next());
            }
            Some(c) if !is_line_end(c) => out.push(c),
            _ => {
                return Err(nom::Err::Failure(nom::error::Error::new(
                    i,
                    nom::error::ErrorKind::Char,
                )))
            }
        }
        rest = chars.as_str();
    }
}

/// `mantissa = digits , [ "." , [ digits ] ] | "." , digits ;`
fn mantissa(i: &str) -> Res<'_, &str> {
    alt((
        recognize((digit1, opt((char('.'), opt(digit1))))),
        recognize((char('.'), digit1)),
    ))
    .parse(i)
}

/// `exponent = ( "e" | "E" ) , [ sign ] , digits ;`
fn exponent(i: &str) -> Res<'_, &str> {
    recognize((one_of("eE"), opt(one_of("+-")), digit1)).parse(i)
}

/// `number = [ sign ] , mantissa , [ exponent ] ;`
///
/// Returns the number's text; the caller converts it (Rust's `f64` parser
/// rounds correctly and accepts exactly this syntax).
fn number(i: &str) -> Res<'_, &str> {
    recognize((opt(one_of("+-")), mantissa, opt(exponent))).parse(i)
}

/// True for a word that starts like a number: a digit, a sign or a `.`.
fn looks_numeric(word: &str) -> bool {
    word.starts_with(|c: char| c.is_ascii_digit() || matches!(c, '+' | '-' | '.'))
}

/// True for `nan`, `inf` and `infinity` in any case and with any sign.
fn is_non_finite_word(word: &str) -> bool {
    let bare = word.trim_start_matches(['+', '-']).to_ascii_lowercase();
    matches!(bare.as_str(), "nan" | "inf" | "infinity")
}

/// True when a word in attribute position starts a new section: a section
/// keyword, or an unknown word nearer to a section keyword than to any
/// attribute name (`sphre` starts a section; `colr` is an attribute).
fn starts_section(word: &str) -> bool {
    if !matches!(SectionKind::from_word(word), SectionKind::Unknown(_)) {
        return true;
    }
    if !matches!(AttrName::from_word(word), AttrName::Unknown(_)) {
        return false;
    }
    match suggest::nearest(word, &SectionKind::KEYWORDS) {
        Some((_, section_distance)) => suggest::nearest(word, &AttrName::KEYWORDS)
            .is_none_or(|(_, attr_distance)| section_distance < attr_distance),
        None => false,
    }
}

/// A token as the structural rules see it.
enum Token<'a> {
    Word(&'a str),
    Str(String),
    UnterminatedStr,
}

/// The structural parser: the remaining input and the errors found so far.
struct Cursor<'a> {
    src: &'a str,
    rest: &'a str,
    errors: Vec<SyntaxError>,
    /// The buffer [`Cursor::values`] gathers into.
    scratch: Vec<Spanned<Value>>,
}

impl<'a> Cursor<'a> {
    fn offset(&self) -> usize {
        self.src.offset(self.rest)
    }

    fn skip_trivia(&mut self) {
        if let Ok((rest, _)) = trivia(self.rest) {
            self.rest = rest;
        }
    }

    /// The next token after trivia with its span and the input after it, or
    /// `None` at the end of input. Does not consume.
    fn peek(&mut self) -> Option<(Token<'a>, Span, &'a str)> {
        self.skip_trivia();
        if self.rest.is_empty() {
            return None;
        }
        let start = self.offset();
        let (rest, token) = match string(self.rest) {
            Ok((rest, text)) => (rest, Token::Str(text)),
            Err(nom::Err::Failure(_)) => {
                let line = rest_of_line(self.rest).map_or("", |(rest, _)| rest);
                (line, Token::UnterminatedStr)
            }
            Err(_) => match word(self.rest) {
                Ok((rest, text)) => (rest, Token::Word(text)),
                // Unreachable by construction (trivia stopped on a word or
                // string character), but never loop: treat one char as a word.
                Err(_) => {
                    let len = self.rest.chars().next().map_or(0, char::len_utf8);
                    (&self.rest[len..], Token::Word(&self.rest[..len]))
                }
            },
        };
        let end = self.src.offset(rest);
        Some((token, Span::new(start, end), rest))
    }

    /// `file = trivia , { section } ;`
    ///
    /// One step of the rule: the next section, or `None` at the end of the
    /// input. Values before a section are reported once per run of them.
    fn file(&mut self) -> Option<Section> {
        while let Some((token, span, _)) = self.peek() {
            match token {
                Token::Word(w) if !looks_numeric(w) && !is_non_finite_word(w) => {
                    return Some(self.section());
                }
                // A number or string: `values` consumes at least this token.
                _ => {
                    let stray = self.values(false);
                    // A run of only malformed values was reported already.
                    let reported = stray.iter().all(|v| v.value == Value::Invalid);
                    if let Some(last) = stray.last().filter(|_| !reported) {
                        let run = span.join(last.span);
                        self.errors.push(SyntaxError::ValueOutsideSection {
                            found: self.src[run.start()..run.end()].to_string(),
                            span: run.into(),
                        });
                    }
                }
            }
        }
        None
    }

    /// `section = section_keyword , { value } , { attribute } ;`
    fn section(&mut self) -> Section {
        let Some((Token::Word(keyword), kw_span, rest)) = self.peek() else {
            unreachable!("section() is only called on a word");
        };
        self.rest = rest;
        let kind = Spanned::new(kw_span, SectionKind::from_word(keyword));
        let args = self.values(false);
        let mut span = args.last().map_or(kw_span, |v| kw_span.join(v.span));
        let mut attributes = Vec::new();
        while let Some((Token::Word(w), _, _)) = self.peek() {
            if starts_section(w) {
                break;
            }
            let attribute = self.attribute();
            span = span.join(attribute.span);
            attributes.push(attribute);
        }
        Section {
            kind,
            args,
            attributes,
            span,
        }
    }

    /// `attribute = attribute_name , { value } | "texture" , path ;`
    fn attribute(&mut self) -> Attribute {
        let Some((Token::Word(name), name_span, rest)) = self.peek() else {
            unreachable!("attribute() is only called on a word");
        };
        self.rest = rest;
        let name = Spanned::new(name_span, AttrName::from_word(name));
        let values = self.values(*name == AttrName::Texture);
        let span = values.last().map_or(name_span, |v| name_span.join(v.span));
        Attribute { name, values, span }
    }

    /// `values = { value } ;`
    /// `value = number | string | path ;`
    /// `path = word ;` (only as the first value of `texture`)
    ///
    /// Bad numbers and unterminated strings are reported and kept as
    /// [`Value::Invalid`]; the run of values ends at the first word that is neither a number nor a
    /// path.
    fn values(&mut self, path_allowed: bool) -> Box<[Spanned<Value>]> {
        // Gathered in a reused buffer and copied out at their exact size:
        // a growing Vec per attribute would keep spare room (and leave the
        // allocator fragmented), most of a large scene's syntax tree.
        let mut values = std::mem::take(&mut self.scratch);
        values.clear();
        while let Some((token, span, rest)) = self.peek() {
            match token {
                Token::Str(text) => values.push(Spanned::new(span, Value::Text(text.into()))),
                Token::UnterminatedStr => {
                    self.errors
                        .push(SyntaxError::UnterminatedString { span: span.into() });
                    values.push(Spanned::new(span, Value::Invalid));
                }
                Token::Word(w)
                    if path_allowed
                        && values.is_empty()
                        && matches!(SectionKind::from_word(w), SectionKind::Unknown(_))
                        && matches!(AttrName::from_word(w), AttrName::Unknown(_)) =>
                {
                    values.push(Spanned::new(span, Value::Text(w.into())));
                }
                Token::Word(w) if looks_numeric(w) || is_non_finite_word(w) => {
                    let value = self
                        .number_value(w, span)
                        .map_or(Value::Invalid, Value::Number);
                    values.push(Spanned::new(span, value));
                }
                Token::Word(_) => break,
            }
            self.rest = rest;
        }
        let mut exact = Vec::with_capacity(values.len());
        exact.append(&mut values);
        self.scratch = values;
        exact.into_boxed_slice()
    }

    /// Convert a numeric-looking word, reporting why it is not a number.
    fn number_value(&mut self, w: &str, span: Span) -> Option<f64> {
        let found = w.to_string();
        let error = match number(w) {
            Ok(("", text)) => match text.parse::<f64>() {
                Ok(n) if n.is_finite() => return Some(n),
                _ => SyntaxError::NumberOutOfRange {
                    found,
                    span: span.into(),
                },
            },
            _ if is_non_finite_word(w) => SyntaxError::NonFiniteNumber {
                found,
                span: span.into(),
            },
            _ => SyntaxError::InvalidNumber {
                found,
                span: span.into(),
            },
        };
        self.errors.push(error);
        None
    }
}

#[cfg(test)]
mod tests;
