//! The check pass's diagnostics: one variant per problem, each with a stable
//! code under `scene::`, a doc line saying when it fires, labelled spans and,
//! where a fix exists, a help line that shows it (and, where the fix is
//! mechanical, the structured [`Fix`] that makes it). Errors stop a render;
//! warnings (marked `severity(Warning)`) do not.
//!
//! docs/diagnostics.md has a What / Why / Example / Fix section per code, and
//! tests/ui has one fixture per code; `tests/ui.rs` fails when a code listed
//! in [`CheckError::codes`] (derived from the variant names) lacks either.

use miette::{Diagnostic, SourceSpan};
use thiserror::Error;

use crate::fix::Fix;

/// A problem in the meaning of a scene file.
#[derive(Clone, Debug, Error, Diagnostic, PartialEq, Eq, strum::VariantNames)]
#[strum(serialize_all = "snake_case")]
pub enum CheckError {
    /// Fires on a word in section position that is no section keyword.
    #[error("unknown section `{found}`")]
    #[diagnostic(code(scene::unknown_section))]
    UnknownSection {
        found: String,
        #[label("not a section keyword")]
        span: SourceSpan,
        #[help]
        help: String,
        /// The nearest keyword, when one is close (unsafe).
        fix: Option<Box<Fix>>,
    },

    /// Fires on an attribute name that no section takes.
    #[error("unknown attribute `{found}` in `{section}`")]
    #[diagnostic(code(scene::unknown_attribute))]
    UnknownAttribute {
        found: String,
        section: String,
        #[label("not an attribute")]
        span: SourceSpan,
        #[help]
        help: String,
        /// The nearest attribute the section takes, when one is close
        /// (unsafe).
        fix: Option<Box<Fix>>,
    },

    /// Fires on an attribute of another section type, such as `normal` on a
    /// sphere, or any attribute on the camera.
    #[error("`{section}` has no attribute `{name}`")]
    #[diagnostic(code(scene::misplaced_attribute))]
    MisplacedAttribute {
        name: String,
        section: String,
        #[label("{belongs}")]
        span: SourceSpan,
        belongs: String,
        #[help]
        help: String,
        /// Removing the line, in scene text, when the section is not the
        /// camera (unsafe: the author may have meant another section).
        fix: Option<Box<Fix>>,
    },

    /// Fires when an attribute (or the camera line) has more or fewer values
    /// than it takes.
    #[error("expected {expected} for `{name}`, found {found}")]
    #[diagnostic(code(scene::wrong_value_count))]
    WrongValueCount {
        name: String,
        /// "3 values", "1 path".
        expected: String,
        found: usize,
        #[label("{label}")]
        span: SourceSpan,
        label: String,
        #[help]
        help: String,
        /// Dropping surplus values, or writing the registry's example
        /// values on a line that has none (unsafe).
        fix: Option<Box<Fix>>,
    },

    /// Fires on a quoted string where a number is expected.
    #[error("expected a number for `{name}`, found `\"{found}\"`")]
    #[diagnostic(
        code(scene::not_a_number),
        help("numbers are written without quotes, such as `1`, `-.5` or `1e3`")
    )]
    NotANumber {
        name: String,
        found: String,
        #[label("not a number")]
        span: SourceSpan,
        /// Removing the quotes, when what they hold is a number (safe: it
        /// has one reading).
        fix: Option<Box<Fix>>,
    },

    /// Fires when a section gives the same attribute twice.
    #[error("`{name}` is given twice in this `{section}`")]
    #[diagnostic(
        code(scene::duplicate_attribute),
        help("remove one of the two `{name}` lines")
    )]
    DuplicateAttribute {
        name: String,
        section: String,
        #[label("first given here")]
        first: SourceSpan,
        #[label("given again here")]
        second: SourceSpan,
        /// Removing the second line (unsafe: which one is wrong is the
        /// author's call).
        fix: Option<Box<Fix>>,
    },

    /// Fires when a section lacks one or more required attributes; one
    /// diagnostic per section lists them all.
    #[error("`{section}` is missing {names}")]
    #[diagnostic(code(scene::missing_attribute))]
    MissingAttribute {
        section: String,
        /// "`center`", "`normal` and `headup`".
        names: String,
        #[label("this {section} needs {names}")]
        span: SourceSpan,
        #[help]
        help: String,
        /// Adding the registry's example line of each, in scene text
        /// (unsafe: the values are placeholders).
        fix: Option<Box<Fix>>,
    },

    /// Fires when the file has no `camera` line (and no unknown section
    /// that is a misspelt `camera`, whose "did you mean" says it).
    #[error("the scene has no camera")]
    #[diagnostic(
        code(scene::missing_camera),
        help("add a first line `camera 400` (the image is 400 × 400 pixels)")
    )]
    MissingCamera {
        #[label("expected `camera N` in this file")]
        span: SourceSpan,
        /// Adding `camera 400` before the first section, in scene text
        /// (unsafe: the resolution is a guess).
        fix: Option<Box<Fix>>,
    },

    /// Fires on every `camera` after the first.
    #[error("the scene has more than one camera")]
    #[diagnostic(code(scene::repeated_camera))]
    RepeatedCamera {
        #[label("first camera")]
        first: SourceSpan,
        #[label("another camera")]
        second: SourceSpan,
        /// Which line to remove, quoted with its number.
        #[help]
        help: String,
        /// Removing the second camera line (unsafe).
        fix: Option<Box<Fix>>,
    },

    /// Fires when the camera resolution has a fractional part.
    #[error("the camera resolution must be a whole number, found `{found}`")]
    #[diagnostic(code(scene::resolution_not_integer))]
    ResolutionNotInteger {
        found: String,
        #[label("not a whole number")]
        span: SourceSpan,
        #[help]
        help: String,
        /// Writing the values the help line shows (unsafe).
        fix: Option<Box<Fix>>,
    },

    /// Fires when the camera resolution is outside the range of its row
    /// in the registry ([`crate::language::CAMERA`]).
    #[error("the camera resolution must be from {min} to {max}, found `{found}`")]
    #[diagnostic(code(scene::resolution_out_of_range))]
    ResolutionOutOfRange {
        min: String,
        max: String,
        found: String,
        #[label("out of range")]
        span: SourceSpan,
        #[help]
        help: String,
        /// Writing the values the help line shows (unsafe).
        fix: Option<Box<Fix>>,
    },

    /// Fires on values directly after a `sphere`, `plane` or `light` keyword.
    #[error("`{section}` takes no values after its keyword")]
    #[diagnostic(code(scene::section_values))]
    SectionValues {
        section: String,
        #[label("unexpected values")]
        span: SourceSpan,
        #[help]
        help: String,
        /// Removing the values (unsafe: they may be meant for an
        /// attribute).
        fix: Option<Box<Fix>>,
    },

    /// Fires when a sphere radius or a plane width or height is not > 0.
    #[error("the {what} must be greater than 0, found `{found}`")]
    #[diagnostic(code(scene::dimension_not_positive))]
    DimensionNotPositive {
        /// "radius", "width", "height".
        what: String,
        found: String,
        #[label("not greater than 0")]
        span: SourceSpan,
        #[help]
        help: String,
        /// Writing the values the help line shows (unsafe).
        fix: Option<Box<Fix>>,
    },

    /// Fires when an object colour has a channel outside [0, 1].
    #[error("colour channels must be from {min} to {max}, found `{found}`")]
    #[diagnostic(code(scene::color_out_of_range))]
    ColorOutOfRange {
        min: String,
        max: String,
        found: String,
        #[label("out of range")]
        span: SourceSpan,
        #[help]
        help: String,
        /// Writing the values the help line shows (unsafe).
        fix: Option<Box<Fix>>,
    },

    /// Fires when a reflectivity is outside [0, 1].
    #[error("reflectivity must be from {min} to {max}, found `{found}`")]
    #[diagnostic(code(scene::reflectivity_out_of_range))]
    ReflectivityOutOfRange {
        min: String,
        max: String,
        found: String,
        #[label("out of range")]
        span: SourceSpan,
        #[help]
        help: String,
        /// Writing the values the help line shows (unsafe).
        fix: Option<Box<Fix>>,
    },

    /// Fires when a light colour has a negative channel.
    #[error("light colour channels must be 0 or more, found `{found}`")]
    #[diagnostic(code(scene::negative_light_color))]
    NegativeLightColor {
        found: String,
        #[label("negative")]
        span: SourceSpan,
        #[help]
        help: String,
        /// Writing the values the help line shows (unsafe).
        fix: Option<Box<Fix>>,
    },

    /// Fires when a plane's normal is `0 0 0`.
    #[error("the plane normal must not be zero")]
    #[diagnostic(code(scene::zero_normal))]
    ZeroNormal {
        #[label("zero vector")]
        span: SourceSpan,
        #[help]
        help: String,
        /// Writing the values the help line shows (unsafe).
        fix: Option<Box<Fix>>,
    },

    /// Fires when a plane's headup is `0 0 0`.
    #[error("the plane headup must not be zero")]
    #[diagnostic(code(scene::zero_headup))]
    ZeroHeadup {
        #[label("zero vector")]
        span: SourceSpan,
        #[help]
        help: String,
        /// Writing the values the help line shows (unsafe).
        fix: Option<Box<Fix>>,
    },

    /// Fires when headup points along the normal (|n̂ × ĥ| ≤ 1e-9), so the
    /// plane has no up direction of its own; the renderer uses the axis
    /// least aligned with the normal.
    #[error("the plane headup is parallel to its normal")]
    #[diagnostic(code(scene::headup_parallel_to_normal), severity(Warning))]
    HeadupParallelToNormal {
        #[label("normal")]
        normal: SourceSpan,
        #[label("parallel to the normal")]
        headup: SourceSpan,
        #[help]
        help: String,
        /// Writing the stand-in headup (safe: the render is unchanged).
        fix: Option<Box<Fix>>,
    },

    /// Fires when a texture file does not exist (or cannot be read).
    #[error("cannot read texture `{path}`")]
    #[diagnostic(code(scene::texture_not_found))]
    TextureNotFound {
        path: String,
        reason: String,
        #[label("{reason}")]
        span: SourceSpan,
        #[help]
        help: String,
        /// A near path that names a file (`textures/wood_tex.ppm` for
        /// `textures\wood_tex.ppm`), written in the path's place (unsafe:
        /// a likely intent).
        fix: Option<Box<Fix>>,
    },

    /// Fires when a texture path names a folder or another non-file.
    #[error("texture `{path}` is not a file")]
    #[diagnostic(code(scene::texture_not_a_file))]
    TextureNotAFile {
        path: String,
        #[label("not a regular file")]
        span: SourceSpan,
        #[help]
        help: String,
    },

    /// Fires when a texture file exists but does not decode as an image.
    #[error("texture `{path}` is not an image")]
    #[diagnostic(code(scene::texture_not_an_image))]
    TextureNotAnImage {
        path: String,
        reason: String,
        #[label("{reason}")]
        span: SourceSpan,
        #[help]
        help: String,
    },

    /// Fires when a texture's header gives more texels than a texture may
    /// have (see docs/reliability.md), or when the scene's textures together
    /// do; the image is refused before its pixels are read.
    #[error("texture `{path}` is too large: expected {expected}, found {found}")]
    #[diagnostic(code(scene::texture_too_large))]
    TextureTooLarge {
        path: String,
        expected: String,
        found: String,
        #[label("too large")]
        span: SourceSpan,
        #[help]
        help: String,
    },

    /// Fires on the first sphere or plane beyond the limit on objects, or the
    /// first light beyond the limit on lights (see docs/reliability.md).
    #[error("too many {what}: expected at most {limit}, found {found}")]
    #[diagnostic(code(scene::too_many_objects))]
    TooManyObjects {
        what: &'static str,
        limit: usize,
        found: usize,
        #[label("{limit} {what} before this one")]
        span: SourceSpan,
        #[help]
        help: String,
    },

    /// Fires when headup is not perpendicular to the normal (|n̂ · ĥ| > 1e-6);
    /// the renderer uses its projection onto the plane.
    #[error("the plane headup is not perpendicular to its normal")]
    #[diagnostic(code(scene::headup_not_perpendicular), severity(Warning))]
    HeadupNotPerpendicular {
        #[label("normal")]
        normal: SourceSpan,
        #[label("not perpendicular to the normal")]
        headup: SourceSpan,
        #[help]
        help: String,
        /// The projection, number by number (safe).
        fix: Option<Box<Fix>>,
    },

    /// Fires when every point of an object has z ≥ 0, behind the camera at
    /// the origin that looks down −z.
    #[error("this {shape} is entirely behind the camera")]
    #[diagnostic(code(scene::object_behind_camera), severity(Warning))]
    ObjectBehindCamera {
        shape: String,
        #[label("every point has z ≥ 0")]
        span: SourceSpan,
        #[help]
        help: String,
        /// Negating the centre's z, when it is above 0 (unsafe).
        fix: Option<Box<Fix>>,
    },

    /// Fires when a scene without errors has no light: every surface
    /// shows only its ambient term, a tenth of its colour.
    #[error("the scene has no light, so it renders nearly black")]
    #[diagnostic(code(scene::no_light), severity(Warning))]
    NoLight {
        #[label("lit by nothing but the ambient tenth of each colour")]
        span: SourceSpan,
        /// A light, in the file's own language.
        #[help]
        help: String,
        /// A white light above the origin, at the end of the file
        /// (unsafe: where the light goes is the author's call).
        fix: Option<Box<Fix>>,
    },

    /// Fires when a scene without errors has no object in the camera's
    /// view (none at all, or each outside the pyramid it sees): the image
    /// is black.
    #[error("no object is in the camera's view, so the image is black")]
    #[diagnostic(code(scene::nothing_in_view), severity(Warning))]
    NothingInView {
        #[label("sees nothing")]
        span: SourceSpan,
        /// Where to put an object, in the file's language.
        #[help]
        help: String,
    },

    /// Fires when a light is strictly inside a sphere: it lights only the
    /// sphere's inside.
    #[error("this light is inside a sphere")]
    #[diagnostic(code(scene::light_inside_sphere), severity(Warning))]
    LightInsideSphere {
        #[label("light")]
        light: SourceSpan,
        #[label("{contains}")]
        sphere: SourceSpan,
        /// "radius 0.5 around `0.52 0 -4`".
        contains: String,
        #[help]
        help: String,
    },

    /// Fires when an object gives both `color` and `texture`.
    #[error("`color` is ignored because this {shape} has a texture")]
    #[diagnostic(code(scene::color_with_texture), severity(Warning))]
    ColorWithTexture {
        /// What to remove, in the file's language: the `color` line or field.
        #[help]
        help: String,
        shape: String,
        #[label("ignored")]
        color: SourceSpan,
        #[label("the texture wins")]
        texture: SourceSpan,
        /// Removing the ignored line (safe: the image is unchanged).
        fix: Option<Box<Fix>>,
    },

    /// Fires when a light colour channel is above 1 (it over-exposes).
    #[error("light colour above 1 over-exposes")]
    #[diagnostic(code(scene::light_color_above_one), severity(Warning))]
    LightColorAboveOne {
        #[label("a channel is above 1")]
        span: SourceSpan,
        #[help]
        help: String,
        /// Writing the values the help line shows (unsafe).
        fix: Option<Box<Fix>>,
    },

    /// Fires on each Unicode text-direction control (U+202A–U+202E,
    /// U+2066–U+2069) anywhere in the text, comments included: it can make
    /// the scene display differently from what it says.
    #[error("text-direction control {name} in the scene text")]
    #[diagnostic(code(scene::text_direction_control), severity(Warning))]
    TextDirectionControl {
        /// `U+202E (right-to-left override)`.
        name: String,
        #[label("reorders the text shown around it")]
        span: SourceSpan,
        #[help]
        help: String,
        /// Deleting the control (unsafe: inside a texture path it changes
        /// the path).
        fix: Option<Box<Fix>>,
    },
}

impl CheckError {
    /// The structured fix this diagnostic carries, if any.
    pub fn fix(&self) -> Option<&Fix> {
        match self {
            CheckError::UnknownSection { fix, .. }
            | CheckError::UnknownAttribute { fix, .. }
            | CheckError::HeadupNotPerpendicular { fix, .. }
            | CheckError::HeadupParallelToNormal { fix, .. }
            | CheckError::ResolutionNotInteger { fix, .. }
            | CheckError::ResolutionOutOfRange { fix, .. }
            | CheckError::DimensionNotPositive { fix, .. }
            | CheckError::ColorOutOfRange { fix, .. }
            | CheckError::ReflectivityOutOfRange { fix, .. }
            | CheckError::NegativeLightColor { fix, .. }
            | CheckError::ZeroNormal { fix, .. }
            | CheckError::ZeroHeadup { fix, .. }
            | CheckError::LightColorAboveOne { fix, .. }
            | CheckError::ObjectBehindCamera { fix, .. }
            | CheckError::DuplicateAttribute { fix, .. }
            | CheckError::RepeatedCamera { fix, .. }
            | CheckError::ColorWithTexture { fix, .. }
            | CheckError::MisplacedAttribute { fix, .. }
            | CheckError::WrongValueCount { fix, .. }
            | CheckError::NotANumber { fix, .. }
            | CheckError::MissingAttribute { fix, .. }
            | CheckError::MissingCamera { fix, .. }
            | CheckError::NoLight { fix, .. }
            | CheckError::SectionValues { fix, .. }
            | CheckError::TextDirectionControl { fix, .. }
            | CheckError::TextureNotFound { fix, .. } => fix.as_deref(),
            CheckError::NothingInView { .. }
            | CheckError::TextureNotAFile { .. }
            | CheckError::TextureNotAnImage { .. }
            | CheckError::TextureTooLarge { .. }
            | CheckError::TooManyObjects { .. }
            | CheckError::LightInsideSphere { .. } => None,
        }
    }

    /// Every code this enum can produce: `scene::` and each variant's name
    /// in snake case, which is what each variant's `code(...)` says (the
    /// UI fixtures, one per code, check that).
    pub fn codes() -> Vec<String> {
        use strum::VariantNames;
        Self::VARIANTS
            .iter()
            .map(|v| format!("scene::{v}"))
            .collect()
    }
}
