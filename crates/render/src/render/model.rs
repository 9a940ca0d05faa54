//! The constants of the illumination model that the course's assignment
//! leaves open, as one value: the ambient share, the diffuse weight, a
//! Phong highlight (its weight and exponent), where in a pixel its camera
//! ray passes, and whether reflection is added to the local colour or
//! blended with it. [`Model::default`] is the renderer's own model
//! (docs/rendering.md), and with it every pixel is what it was before the
//! model could be set: each constant enters as an exact identity (a weight
//! of 1, an added 0, a shift of 0), so no default image changes by a bit.
//!
//! `raytracer grade --reference-options FILE` reads one from JSON, so our
//! renderer can stand in for a course's solution that reads the
//! assignment otherwise (docs/grading.md, "The reference's constants").

use serde::{Deserialize, Serialize};

/// The share of a surface's colour that is lit without any light, in
/// the default model.
pub const AMBIENT: f64 = 0.1;

/// The open constants of the illumination model.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Model {
    /// The share of a surface's colour lit without any light (`k_a`).
    pub ambient: f64,
    /// The weight of each light's diffuse term, `C ⊙ I·max(0, N·L̂)`.
    pub diffuse: f64,
    /// The weight of a white Phong highlight, `k_s·I·max(0, R·V)^n`, with
    /// `R` the light's direction mirrored about the normal; 0 for none.
    pub specular: f64,
    /// The highlight's exponent `n`.
    pub exponent: f64,
    /// Where a pixel's camera ray passes (its samples are shifted with it).
    pub pixel: PixelPoint,
    /// How a mirror's reflection combines with its own colour.
    pub reflection: Reflection,
}

/// Where the camera ray of a pixel passes through it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PixelPoint {
    /// The centre, which the assignment says is usually picked.
    #[default]
    #[serde(alias = "center")]
    Centre,
    /// The top-left corner: half a pixel up and to the left.
    Corner,
}

/// How reflection combines with a surface's own colour.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Reflection {
    /// `local + k·reflected`.
    #[default]
    Added,
    /// `(1 − k)·local + k·reflected`.
    Blended,
}

impl Default for Model {
    /// The renderer's model (docs/rendering.md).
    fn default() -> Self {
        Model {
            ambient: AMBIENT,
            diffuse: 1.0,
            specular: 0.0,
            exponent: 20.0,
            pixel: PixelPoint::Centre,
            reflection: Reflection::Added,
        }
    }
}

impl Model {
    /// Whether this is the renderer's own model.
    pub fn is_default(&self) -> bool {
        *self == Model::default()
    }

    /// What is added to a pixel's column and row to reach the point its
    /// camera ray passes through, from where the renderer's own model puts
    /// it: 0 for the centre, −½ for the corner.
    pub fn pixel_shift(&self) -> f64 {
        match self.pixel {
            PixelPoint::Centre => 0.0,
            PixelPoint::Corner => -0.5,
        }
    }

    /// The weight of a surface's local colour when it reflects `k`.
    pub fn local_weight(&self, k: f64) -> f64 {
        match self.reflection {
            Reflection::Added => 1.0,
            Reflection::Blended => 1.0 - k,
        }
    }

    /// A value a renderer can use: the constants finite, none negative,
    /// the exponent at least 1; else what is wrong, in words.
    pub fn validate(&self) -> Result<(), String> {
        for (name, value) in [
            ("ambient", self.ambient),
            ("diffuse", self.diffuse),
            ("specular", self.specular),
            ("exponent", self.exponent),
        ] {
            if !value.is_finite() || value < 0.0 {
                return Err(format!(
                    "expected a finite number of at least 0 for `{name}`, found {value}"
                ));
            }
        }
        if self.exponent < 1.0 {
            return Err(format!(
                "expected an `exponent` of at least 1, found {}",
                self.exponent
            ));
        }
        Ok(())
    }
}
