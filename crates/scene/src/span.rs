//! Byte spans into scene source text, and [`Spanned`] values that carry them.
//!
//! A [`Span`] is a half-open byte range `start..end` into the text the parser
//! saw, computed from nom's `Offset` trait. [`Spanned<T>`] pairs a value with
//! the span it came from; it dereferences to `T` and its equality ignores the
//! span, so AST tests can compare values without spelling out offsets
//! (the design of knuffel's `span.rs`).

use std::fmt;
use std::ops::{Deref, DerefMut};

/// A half-open byte range `start..end` into the source text, stored as
/// `u32` (8 bytes, not 16: a scene's syntax tree holds about twenty spans
/// per object). Scenes are at most `limits::MAX_SCENE_BYTES` (256 MiB), so
/// every offset fits; a larger one would saturate at `u32::MAX`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Span {
    start: u32,
    end: u32,
}

impl Span {
    /// The span `start..end`.
    pub fn new(start: usize, end: usize) -> Self {
        debug_assert!(start <= end, "span start after end");
        let narrow = |offset: usize| u32::try_from(offset).unwrap_or(u32::MAX);
        Span {
            start: narrow(start),
            end: narrow(end),
        }
    }

    /// The first byte.
    pub fn start(&self) -> usize {
        self.start as usize
    }

    /// One past the last byte.
    pub fn end(&self) -> usize {
        self.end as usize
    }

    /// An empty span at `offset`, for "expected X here" labels.
    pub fn point(offset: usize) -> Self {
        Span::new(offset, offset)
    }

    /// Length in bytes.
    pub fn len(&self) -> usize {
        self.end() - self.start()
    }

    /// True when the span covers no bytes.
    pub fn is_empty(&self) -> bool {
        self.start == self.end
    }

    /// The smallest span covering both `self` and `other`.
    pub fn join(self, other: Span) -> Span {
        Span::new(self.start().min(other.start()), self.end().max(other.end()))
    }
}

impl From<Span> for miette::SourceSpan {
    fn from(span: Span) -> Self {
        (span.start(), span.len()).into()
    }
}

impl From<std::ops::Range<usize>> for Span {
    fn from(range: std::ops::Range<usize>) -> Self {
        Span::new(range.start, range.end)
    }
}

/// The largest character boundary of `text` at or before `offset` (clamped
/// to the text), so a byte offset from a span or a parser can slice it.
pub fn floor_char_boundary(text: &str, offset: usize) -> usize {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    offset
}

/// A value together with the source span it was parsed from.
///
/// Equality, ordering-free hashing and `Debug` look only at the value, so two
/// ASTs parsed from differently laid-out text compare equal when they mean the
/// same thing.
#[derive(Clone, Copy)]
pub struct Spanned<T> {
    pub span: Span,
    pub value: T,
}

impl<T> Spanned<T> {
    /// Wrap `value` with `span`.
    pub fn new(span: impl Into<Span>, value: T) -> Self {
        Spanned {
            span: span.into(),
            value,
        }
    }
}

impl<T> Deref for Spanned<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.value
    }
}

impl<T> DerefMut for Spanned<T> {
    fn deref_mut(&mut self) -> &mut T {
        &mut self.value
    }
}

impl<T: PartialEq> PartialEq for Spanned<T> {
    fn eq(&self, other: &Self) -> bool {
        self.value == other.value
    }
}

impl<T: fmt::Debug> fmt::Debug for Spanned<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.value.fmt(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equality_ignores_span() {
        assert_eq!(Spanned::new(0..3, 1.5), Spanned::new(10..20, 1.5));
        assert_ne!(Spanned::new(0..3, 1.5), Spanned::new(0..3, 2.5));
    }

    #[test]
    fn join_covers_both() {
        assert_eq!(Span::new(4, 6).join(Span::new(1, 2)), Span::new(1, 6));
    }
}
