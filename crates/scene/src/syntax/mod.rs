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
//!
//! The cursor first tries the byte-level fast paths of [`fast`] for
//! trivia, words and plain decimals, and falls back to the nom rules
//! wherever the text leaves their ASCII subset; the `parity` tests hold the
//! two routes to the same tree, spans and errors.

mod commas;
pub mod errors;
mod fast;
mod punctuation;
pub mod trivia;

use nom::branch::alt;
use nom::bytes::complete::{take_till1, take_while1};
use nom::character::complete::{char, digit1, one_of};
use nom::combinator::{opt, recognize};
use nom::multi::many0_count;
use nom::sequence::preceded;
use nom::{IResult, Offset, Parser};

use crate::ast::{AttrName, Attribute, File, Section, SectionKind, Value, Values};
use crate::language;
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
    sections_by(text, Route::Fast)
}

/// The sections of `text[start..end]`, with spans into the whole of
/// `text`: for reading again a run of sections whose first starts at
/// `start` (a section keyword the parser found there) and whose last ends
/// at `end`. From a section start, parsing depends on nothing before it,
/// so these are the sections [`sections`] gave for that run.
pub fn sections_between(text: &str, start: usize, end: usize) -> Sections<'_> {
    let mut sections = sections(text);
    sections.cursor.rest = text.get(start..end).unwrap_or_default();
    sections
}

/// How the cursor reads tokens: the fast paths first, or the nom rules
/// alone (the reference the parity tests compare against).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Route {
    Fast,
    #[cfg(test)]
    General,
}

fn sections_by(text: &str, route: Route) -> Sections<'_> {
    Sections {
        cursor: Cursor {
            src: text,
            rest: text,
            route,
            last_word: None,
            marks: Vec::new(),
            errors: Vec::new(),
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

/// The first word of scene text, after its leading `trivia` (whitespace,
/// the byte-order mark and `#` comments), as the parser reads it: where a
/// scene has its first section keyword. `None` when the text holds only
/// trivia, or starts with a string.
pub fn first_word(text: &str) -> Option<&str> {
    let (rest, _) = trivia(text).ok()?;
    word(rest).ok().map(|(_, word)| word)
}

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

/// True when `word` is, whole, a finite number of the scene language
/// (`1`, `-.5`, `1e3`).
pub fn is_number(word: &str) -> bool {
    matches!(number(word), Ok(("", _))) && word.parse::<f64>().is_ok_and(f64::is_finite)
}

/// True for a word that starts like a number: a digit, a sign or a `.`.
fn looks_numeric(word: &str) -> bool {
    word.starts_with(|c: char| c.is_ascii_digit() || matches!(c, '+' | '-' | '.'))
}

/// True for `nan`, `inf` and `infinity` in any case and with any sign.
fn is_non_finite_word(word: &str) -> bool {
    let signs = word
        .bytes()
        .take_while(|b| matches!(b, b'+' | b'-'))
        .count();
    // Signs are ASCII: `signs` is a character boundary.
    let bare = &word[signs..];
    match bare.len() {
        3 => bare.eq_ignore_ascii_case("nan") || bare.eq_ignore_ascii_case("inf"),
        8 => bare.eq_ignore_ascii_case("infinity"),
        _ => false,
    }
}

/// True when a word in attribute position starts a new section: a section
/// keyword, or an unknown word nearer to a section keyword than to any
/// attribute name (`sphre` starts a section; `colr` is an attribute).
fn starts_section(word: &str) -> bool {
    if SectionKind::KEYWORDS.contains(&word) {
        return true;
    }
    if AttrName::KEYWORDS.contains(&word) {
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

/// The last word [`Cursor::peek`] read, kept because the rule that reads
/// a keyword or attribute name peeks it again after the loop that stopped
/// at it.
#[derive(Clone, Copy)]
struct PeekedWord<'a> {
    /// Where the word starts in the source.
    start: usize,
    text: &'a str,
    span: Span,
    /// The input after it.
    rest: &'a str,
}

/// The structural parser: the remaining input and the errors found so far.
struct Cursor<'a> {
    src: &'a str,
    rest: &'a str,
    route: Route,
    last_word: Option<PeekedWord<'a>>,
    /// Punctuation met after the name of the line being read (`center:`),
    /// reported with the rest of the line's by [`Cursor::values`].
    marks: Vec<Span>,
    errors: Vec<SyntaxError>,
}

impl<'a> Cursor<'a> {
    fn offset(&self) -> usize {
        self.src.offset(self.rest)
    }

    fn skip_trivia(&mut self) {
        if self.route == Route::Fast {
            let ascii = fast::ascii_trivia(self.rest.as_bytes());
            // Only ASCII bytes were skipped: still a character boundary.
            self.rest = &self.rest[ascii..];
            if self.rest.as_bytes().first().is_none_or(u8::is_ascii) && !self.rest.starts_with('#')
            {
                return;
            }
        }
        if let Ok((rest, _)) = trivia(self.rest) {
            self.rest = rest;
        }
    }

    /// The `word` at the start of the remaining input, by the fast path
    /// when it is all ASCII, with the input after it.
    fn word(&self) -> Option<(&'a str, &'a str)> {
        let rest = self.rest;
        if self.route == Route::Fast {
            if let Some(len) = fast::ascii_word(rest.as_bytes()) {
                // All ASCII: `len` is a character boundary.
                let (text, after) = rest.split_at(len);
                return Some((after, text));
            }
        }
        word(rest).ok()
    }

    /// The next token after trivia with its span and the input after it, or
    /// `None` at the end of input. Does not consume.
    fn peek(&mut self) -> Option<(Token<'a>, Span, &'a str)> {
        // The last word again, with the trivia before it skipped already:
        // a name is peeked three times and read once.
        let cached = |cursor: &Self| {
            let word = cursor
                .last_word
                .filter(|word| word.start == cursor.offset())?;
            Some((Token::Word(word.text), word.span, word.rest))
        };
        if let Some(peeked) = cached(self) {
            return Some(peeked);
        }
        self.skip_trivia();
        if self.rest.is_empty() {
            return None;
        }
        if let Some(peeked) = cached(self) {
            return Some(peeked);
        }
        let start = self.offset();
        // A quote opens a string, closed or not; anything else is a word.
        let (rest, token) = match self.rest.starts_with('"').then(|| string(self.rest)) {
            Some(Ok((rest, text))) => (rest, Token::Str(text)),
            Some(Err(_)) => {
                let line = rest_of_line(self.rest).map_or("", |(rest, _)| rest);
                (line, Token::UnterminatedStr)
            }
            None => match self.word() {
                Some((rest, text)) => (rest, Token::Word(text)),
                // Unreachable by construction (trivia stopped on a word or
                // string character), but never loop: treat one char as a word.
                None => {
                    let len = self.rest.chars().next().map_or(0, char::len_utf8);
                    (&self.rest[len..], Token::Word(&self.rest[..len]))
                }
            },
        };
        let span = Span::new(start, self.src.offset(rest));
        if let Token::Word(text) = token {
            self.last_word = Some(PeekedWord {
                start,
                text,
                span,
                rest,
            });
        }
        Some((token, span, rest))
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
                    let mut stray = Values::new();
                    self.values(&mut stray, false, None, "", span.start());
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
        let mut kw_span = kw_span;
        let kind = match punctuation::keyword(keyword) {
            Some(written) => {
                let start = kw_span.start();
                let end = start + written.len;
                if written.case {
                    self.errors.push(punctuation::keyword_case(
                        &keyword[..written.len],
                        written.kind.as_str(),
                        Span::new(start, end),
                    ));
                }
                if written.marks > 0 {
                    self.marks.push(Span::new(end, end + written.marks));
                }
                // The values start after the marks, in the same word or not.
                self.rest = &self.src[end + written.marks..];
                kw_span = Span::new(start, end);
                written.kind
            }
            None => SectionKind::from_word(keyword),
        };
        let kind = Spanned::new(kw_span, kind);
        let camera = (*kind == SectionKind::Camera).then(|| language::CAMERA.count());
        let mut args = Values::new();
        self.values(&mut args, false, camera, kind.as_str(), kw_span.end());
        let mut span = args.last().map_or(kw_span, |v| kw_span.join(v.span));
        let mut attributes = Vec::new();
        while let Some((Token::Word(w), _, _)) = self.peek() {
            // An attribute name is never a section keyword: only an
            // unknown word may start a section.
            let (name, written) = match AttrName::known(w) {
                Some(name) => (name, None),
                None => match punctuation::attribute_name(w) {
                    Some(written) => (written.name.clone(), Some(written)),
                    None if punctuation::keyword(w).is_some() => break,
                    None if starts_section(w) => break,
                    None => (AttrName::Unknown(w.into()), None),
                },
            };
            span = span.join(self.attribute(&kind, name, written, &mut attributes));
        }
        Section {
            kind,
            args,
            attributes,
            span,
        }
    }

    /// `attribute = attribute_name , { value } | "texture" , path ;`
    ///
    /// `name` is the next word, already looked up; `kind` is the section's.
    /// The attribute is read in its place at the end of `attributes` (it
    /// is large, and a large scene has millions: moving each from the
    /// stack to the vector cost more than reading it); its span is
    /// returned.
    fn attribute(
        &mut self,
        kind: &SectionKind,
        name: AttrName,
        written: Option<punctuation::Name>,
        attributes: &mut Vec<Attribute>,
    ) -> Span {
        let Some((Token::Word(word), mut name_span, rest)) = self.peek() else {
            unreachable!("attribute() is only called on a word");
        };
        self.rest = rest;
        if let Some(written) = written {
            let start = name_span.start();
            let end = start + written.len;
            if written.case {
                self.errors.push(punctuation::keyword_case(
                    &word[..written.len],
                    name.as_str(),
                    Span::new(start, end),
                ));
            }
            if written.marks > 0 {
                self.marks.push(Span::new(end, end + written.marks));
            }
            // The values start after the marks, in the same word or not.
            self.rest = &self.src[end + written.marks..];
            name_span = Span::new(start, end);
        }
        let takes_path = language::takes_path_somewhere(&name);
        let expected = language::find(kind, &name).map(|spec| spec.count());
        let index = attributes.len();
        attributes.push(Attribute {
            name: Spanned::new(name_span, name),
            values: Values::new(),
            span: name_span,
        });
        let attribute = &mut attributes[index];
        self.values(
            &mut attribute.values,
            takes_path,
            expected,
            attribute.name.as_str(),
            name_span.end(),
        );
        if let Some(last) = attribute.values.last() {
            attribute.span = name_span.join(last.span);
        }
        attribute.span
    }

    /// `values = { value } ;`
    /// `value = number | string | path ;`
    /// `path = word ;` (only as the first value of `texture`)
    ///
    /// Bad numbers and unterminated strings are reported and kept as
    /// [`Value::Invalid`]; the run of values ends at the first word that is neither a number nor a
    /// path. `expected` is how many values the registry says the line
    /// takes, which tells what commas in its numbers meant. The values are
    /// pushed onto `values`, which starts empty.
    ///
    /// Punctuation around the values (`= 1`, `(0, 0, -5)`, `0;`) is read
    /// past and reported once for the line, after `name` (which ends at
    /// `name_end`).
    fn values(
        &mut self,
        values: &mut Values,
        path_allowed: bool,
        expected: Option<usize>,
        name: &str,
        name_end: usize,
    ) {
        let mut with_commas = Vec::new();
        let mut marks = std::mem::take(&mut self.marks);
        let errors_before = self.errors.len();
        loop {
            // A path comes first, whatever it looks like.
            if self.route == Route::Fast && !(path_allowed && values.is_empty()) {
                if let Some((span, number)) = self.plain_number() {
                    values.push(Spanned::new(span, Value::Number(number)));
                    continue;
                }
            }
            let Some((token, span, rest)) = self.peek() else {
                break;
            };
            if let Token::Word(w) = token {
                if punctuation::is_only_punctuation(w) {
                    marks.push(span);
                    self.rest = rest;
                    continue;
                }
                if let Some((found, numbers)) = punctuation::bracketed(w, span.start()) {
                    marks.extend(found);
                    for at in numbers {
                        let text = &self.src[at.start()..at.end()];
                        let value = text.parse::<f64>().map_or(Value::Invalid, Value::Number);
                        values.push(Spanned::new(at, value));
                    }
                    self.rest = rest;
                    continue;
                }
            }
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
                        && !SectionKind::KEYWORDS.contains(&w)
                        && !AttrName::KEYWORDS.contains(&w) =>
                {
                    match punctuation::marked_path(w, span.start()) {
                        Some((found, path)) => {
                            marks.extend(found);
                            let text = &self.src[path.start()..path.end()];
                            values.push(Spanned::new(path, Value::Text(text.into())));
                        }
                        None => values.push(Spanned::new(span, Value::Text(w.into()))),
                    }
                }
                Token::Word(w) if looks_numeric(w) || is_non_finite_word(w) => {
                    let value = self
                        .number_value(w, span)
                        .map_or(Value::Invalid, Value::Number);
                    if value == Value::Invalid && w.contains(',') {
                        with_commas.push(commas::CommaToken {
                            error: self.errors.len() - 1,
                            index: values.len(),
                            span,
                            text: w,
                        });
                    }
                    values.push(Spanned::new(span, value));
                }
                Token::Word(..) => break,
            }
            self.rest = rest;
        }
        if !marks.is_empty() {
            self.report_marks(values, &with_commas, &marks, name, name_end, errors_before);
            return;
        }
        let separated = !with_commas.is_empty()
            && commas::explain(&with_commas, values.len(), expected, &mut self.errors);
        if separated {
            // Each token stands for its pieces, so the count is right and
            // the check pass reports nothing more about it.
            let mut expanded = Values::new();
            for (i, value) in values.drain(..).enumerate() {
                let copies = with_commas
                    .iter()
                    .find(|t| t.index == i)
                    .map_or(1, |t| commas::piece_count(t.text));
                for _ in 0..copies {
                    expanded.push(value.clone());
                }
            }
            *values = expanded;
        }
    }

    /// Report the punctuation `marks` of a line once. Commas between its
    /// values (`with_commas`, reported as bad numbers since
    /// `errors_before`) are marks too: their values are read, and their
    /// errors give way to the one diagnostic.
    fn report_marks(
        &mut self,
        values: &mut Values,
        with_commas: &[commas::CommaToken<'_>],
        marks: &[Span],
        name: &str,
        name_end: usize,
        errors_before: usize,
    ) {
        let mut marks = marks.to_vec();
        let mut dropped = Vec::new();
        let mut read = Values::new();
        for (i, value) in values.drain(..).enumerate() {
            let token = with_commas.iter().find(|t| t.index == i);
            match token
                .and_then(|t| punctuation::bracketed(&format!("({}", t.text), t.span.start() - 1))
            {
                Some((found, numbers)) => {
                    let token = token.expect("found above");
                    dropped.push(token.error);
                    // The `(` was added to read the word; it is not there.
                    marks.extend(
                        found
                            .into_iter()
                            .filter(|m| m.start() >= token.span.start()),
                    );
                    for at in numbers {
                        let text = &self.src[at.start()..at.end()];
                        let number = text.parse::<f64>().map_or(Value::Invalid, Value::Number);
                        read.push(Spanned::new(at, number));
                    }
                }
                None => read.push(value),
            }
        }
        *values = read;
        dropped.sort_unstable();
        for error in dropped.into_iter().rev() {
            if error >= errors_before && error < self.errors.len() {
                self.errors.remove(error);
            }
        }
        let readable =
            self.errors.len() == errors_before && values.iter().all(|v| v.value != Value::Invalid);
        let spans: Vec<Span> = values.iter().map(|v| v.span).collect();
        if let Some(error) =
            punctuation::diagnostic(self.src, name, name_end, &marks, &spans, readable)
        {
            self.errors.push(error);
        }
    }

    /// The common case of a value on the fast route, read in one pass:
    /// ASCII trivia, then a plain decimal, consumed with its span and
    /// value. `None` consumes at most trivia; when an ASCII word stopped
    /// it, that word is kept as the last word read, so [`Cursor::peek`]
    /// does not scan it again.
    fn plain_number(&mut self) -> Option<(Span, f64)> {
        let bytes = self.rest.as_bytes();
        let trivia = fast::ascii_trivia(bytes);
        let start = self.offset() + trivia;
        // Only ASCII bytes were read: `trivia` and every length below are
        // character boundaries.
        if let Some((len, value)) = fast::plain_decimal(&bytes[trivia..]) {
            self.rest = &self.rest[trivia + len..];
            return Some((Span::new(start, start + len), value));
        }
        // Trivia means nothing: skipped, whatever comes next.
        self.rest = &self.rest[trivia..];
        if let Some(len) = fast::ascii_word(self.rest.as_bytes()) {
            let (text, after) = self.rest.split_at(len);
            self.last_word = Some(PeekedWord {
                start,
                text,
                span: Span::new(start, start + len),
                rest: after,
            });
        }
        None
    }

    /// Convert a numeric-looking word, reporting why it is not a number.
    fn number_value(&mut self, w: &str, span: Span) -> Option<f64> {
        let found = || w.to_string();
        let error = if matches!(number(w), Ok(("", _))) {
            match w.parse::<f64>() {
                Ok(n) if n.is_finite() => return Some(n),
                _ => SyntaxError::NumberOutOfRange {
                    found: found(),
                    span: span.into(),
                },
            }
        } else if is_non_finite_word(w) {
            SyntaxError::NonFiniteNumber {
                found: found(),
                span: span.into(),
            }
        } else {
            SyntaxError::InvalidNumber {
                found: found(),
                span: span.into(),
            }
        };
        self.errors.push(error);
        None
    }
}

#[cfg(test)]
mod parity;
#[cfg(test)]
mod tests;
