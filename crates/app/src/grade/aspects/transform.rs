//! Whole-image transforms a tracer may apply by mistake (rows written
//! bottom first, columns right to left, x and y swapped): when the
//! student's image fails geometry as it is but passes it once turned back
//! by one of them, on a scene whose coverage that transform does not
//! keep (or, where it keeps it, whose light tells it: ours so turned
//! fails an aspect), that transform is named as the likely cause, and
//! the other aspects are judged on the image turned back, so the mistake
//! costs geometry alone. A shift by half a pixel (rays through pixel corners)
//! needs no transform: only pixels stable at the centre and the corners
//! are judged, and the image's pixel reading names it.

use crate::compare::Picture;

/// One of the seven symmetries of a square other than the identity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Transform {
    UpsideDown,
    Mirrored,
    Transposed,
    HalfTurn,
    AntiTransposed,
    QuarterClockwise,
    QuarterAnticlockwise,
}

impl Transform {
    /// Every transform tried, the likeliest mistakes first.
    pub const ALL: [Transform; 7] = [
        Transform::UpsideDown,
        Transform::Mirrored,
        Transform::Transposed,
        Transform::HalfTurn,
        Transform::AntiTransposed,
        Transform::QuarterClockwise,
        Transform::QuarterAnticlockwise,
    ];

    /// What the student's image is, in words.
    pub fn words(self) -> &'static str {
        match self {
            Transform::UpsideDown => "upside down (rows in the wrong order)",
            Transform::Mirrored => "mirrored left to right (columns in the wrong order)",
            Transform::Transposed => "transposed (x and y swapped)",
            Transform::HalfTurn => "turned half a turn (rows and columns both reversed)",
            Transform::AntiTransposed => "transposed about the other diagonal",
            Transform::QuarterClockwise => "turned a quarter turn clockwise",
            Transform::QuarterAnticlockwise => "turned a quarter turn anticlockwise",
        }
    }

    /// The pixel of a `size`-square image that this transform moves to
    /// (`x`, `y`) when it turns an image back.
    fn source(self, size: u32, x: u32, y: u32) -> (u32, u32) {
        let last = size - 1;
        match self {
            Transform::UpsideDown => (x, last - y),
            Transform::Mirrored => (last - x, y),
            Transform::Transposed => (y, x),
            Transform::HalfTurn => (last - x, last - y),
            Transform::AntiTransposed => (last - y, last - x),
            Transform::QuarterClockwise => (y, last - x),
            Transform::QuarterAnticlockwise => (last - y, x),
        }
    }

    /// `picture` (square) turned back by this transform.
    pub fn undo(self, picture: &Picture) -> Picture {
        let size = picture.width;
        let mut rgb = Vec::with_capacity(picture.rgb.len());
        for y in 0..size {
            for x in 0..size {
                let (sx, sy) = self.source(size, x, y);
                let k = 3 * (sy * size + sx) as usize;
                rgb.extend_from_slice(&picture.rgb[k..k + 3]);
            }
        }
        Picture {
            width: size,
            height: size,
            rgb,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Transform;
    use crate::compare::Picture;

    #[test]
    fn each_transform_is_undone_by_itself_or_its_inverse() {
        let size = 5;
        let picture = Picture {
            width: size,
            height: size,
            rgb: (0..size * size * 3).map(|v| v as u8).collect(),
        };
        let mut seen = Vec::new();
        for t in Transform::ALL {
            let once = t.undo(&picture);
            assert_ne!(once.rgb, picture.rgb, "{t:?} moves something");
            assert!(!seen.contains(&once.rgb), "{t:?} is another's");
            seen.push(once.rgb.clone());
            let back = Transform::ALL
                .iter()
                .any(|u| u.undo(&once).rgb == picture.rgb);
            assert!(back, "{t:?} has an inverse among them");
        }
        // Upside down: the first row comes from the last.
        let flipped = Transform::UpsideDown.undo(&picture);
        assert_eq!(flipped.rgb[..3], picture.rgb[3 * 20..3 * 20 + 3]);
    }
}
