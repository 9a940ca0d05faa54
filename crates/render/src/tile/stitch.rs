//! Putting tiles together: the parts must come from one scene, one set of
//! pixel options and one frame size, and cover the frame exactly once, in
//! any order.
//!
//! [`problems`] judges the parts from their metadata alone and returns
//! every problem, each naming the part at fault. The frame a part is judged
//! against is the one most parts agree on (the first part's, on a tie), so
//! a single foreign part among many is the one named. [`assemble`] then
//! decodes each part straight into its rows of the frame. [`pair`] matches
//! what else each tile wrote (its statistics, which carry its metadata) to
//! the parts by the same metadata, with the same care.

use std::collections::HashMap;
use std::path::PathBuf;

use miette::Diagnostic;

use super::file::{self, ReadTileError};
use super::{Band, TileInfo};
use crate::render::Image;

/// A part named on the command line, with its metadata.
#[derive(Clone, Debug)]
pub struct Part {
    pub path: PathBuf,
    pub info: TileInfo,
}

impl Part {
    fn name(&self) -> String {
        self.path.display().to_string()
    }
}

/// Why parts do not make one frame (exit 1).
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum StitchError {
    #[error("`{path}` is a tile of another scene than `{reference}`")]
    #[diagnostic(
        code(stitch::foreign_scene),
        help("its scene hash is {found}, and {expected} in `{reference}`; render every part from the same scene")
    )]
    ForeignScene {
        path: String,
        reference: String,
        found: String,
        expected: String,
    },

    #[error("`{path}` is a tile of a {found} frame, expected {expected} like `{reference}`")]
    #[diagnostic(
        code(stitch::other_size),
        help("render every part from the same scene")
    )]
    OtherSize {
        path: String,
        reference: String,
        found: String,
        expected: String,
    },

    #[error("`{path}` was rendered with other options than `{reference}`: expected {expected}, found {found}")]
    #[diagnostic(
        code(stitch::other_options),
        help(
            "render every part with the same `--precision`, `--spp`, `--aa`, `--aa-threshold`, `--max-depth` and `--no-skip`"
        )
    )]
    OtherOptions {
        path: String,
        reference: String,
        found: String,
        expected: String,
    },

    #[error(
        "`{path}` claims rows {start}..{end} of a {height}-row frame, which is not tile {band}"
    )]
    #[diagnostic(
        code(stitch::bad_region),
        help("its metadata was edited or damaged; render tile {band} again")
    )]
    BadRegion {
        path: String,
        band: Band,
        start: u32,
        end: u32,
        height: u32,
    },

    #[error("`{path}` is named twice (tile {band})")]
    #[diagnostic(code(stitch::named_twice), help("name each tile once"))]
    NamedTwice { path: String, band: Band },

    #[error("`{path}` duplicates `{first}`: both are tile {band}")]
    #[diagnostic(code(stitch::duplicate), help("name each tile once"))]
    Duplicate {
        path: String,
        first: String,
        band: Band,
    },

    #[error("`{path}` (tile {band}, rows {start}..{end}) overlaps `{other}` (tile {other_band}, rows {other_start}..{other_end})")]
    #[diagnostic(
        code(stitch::overlap),
        help("the parts of one frame must come from one `--tile K/N` split, or splits whose bands do not overlap")
    )]
    Overlap {
        path: String,
        band: Band,
        start: u32,
        end: u32,
        other: String,
        other_band: Band,
        other_start: u32,
        other_end: u32,
    },

    #[error("tile {band} is missing: no part covers rows {start}..{end}")]
    #[diagnostic(
        code(stitch::missing_tile),
        help("render it with `raytracer render SCENE PART.png --tile {band}` and name it too")
    )]
    MissingTile { band: Band, start: u32, end: u32 },

    #[error("rows {start}..{end} are missing: no part covers them")]
    #[diagnostic(
        code(stitch::missing_rows),
        help("render the tiles that hold them and name them too")
    )]
    MissingRows { start: u32, end: u32 },
}

/// Why the files given beside the parts (each tile's statistics) do not
/// pair with them one to one (exit 1).
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum PairError {
    /// The statistics of a tile that is not among the parts.
    #[error("`{path}` is the statistics of tile {band} of another render than the parts")]
    #[diagnostic(
        code(stitch::foreign_stats),
        help("name the statistics of the parts being stitched, and only those")
    )]
    Foreign { path: String, band: Band },

    /// Two statistics files for one part.
    #[error("`{path}` and `{first}` are both the statistics of `{part}`")]
    #[diagnostic(
        code(stitch::duplicate_stats),
        help("name each tile's statistics once")
    )]
    Duplicate {
        path: String,
        first: String,
        part: String,
    },

    /// A part without statistics.
    #[error("no statistics were named for `{part}` (tile {band})")]
    #[diagnostic(
        code(stitch::missing_stats),
        help("add its `--stats-json` file to `--part-stats`")
    )]
    Missing { part: String, band: Band },
}

/// Each of `parts`' entry among `entries` (a file, the tile metadata it
/// carries, and what else was read from it), in the parts' order; or every
/// entry of no part, every second entry of a part and every part without
/// one.
pub fn pair<T>(
    parts: &[Part],
    entries: Vec<(PathBuf, TileInfo, T)>,
) -> Result<Vec<(PathBuf, T)>, Vec<PairError>> {
    let mut errors = Vec::new();
    let mut found: Vec<Option<(PathBuf, T)>> = parts.iter().map(|_| None).collect();
    for (path, info, entry) in entries {
        let Some(index) = parts.iter().position(|part| part.info == info) else {
            errors.push(PairError::Foreign {
                path: path.display().to_string(),
                band: info.band(),
            });
            continue;
        };
        match &found[index] {
            Some((first, _)) => errors.push(PairError::Duplicate {
                path: path.display().to_string(),
                first: first.display().to_string(),
                part: parts[index].name(),
            }),
            None => found[index] = Some((path, entry)),
        }
    }
    for (part, found) in parts.iter().zip(&found) {
        if found.is_none() {
            errors.push(PairError::Missing {
                part: part.name(),
                band: part.info.band(),
            });
        }
    }
    if errors.is_empty() {
        Ok(found.into_iter().flatten().collect())
    } else {
        Err(errors)
    }
}

/// What must be equal across the parts of one frame.
#[derive(Clone, PartialEq, Eq, Hash)]
struct Frame<'a> {
    scene_hash: &'a str,
    options_hash: &'a str,
    width: u32,
    height: u32,
}

impl<'a> Frame<'a> {
    fn of(info: &'a TileInfo) -> Frame<'a> {
        Frame {
            scene_hash: &info.scene_hash,
            options_hash: &info.options_hash,
            width: info.width,
            height: info.height,
        }
    }
}

/// Every reason `parts` do not make one frame; empty when they do.
pub fn problems(parts: &[Part]) -> Vec<StitchError> {
    let Some(reference) = reference(parts) else {
        return Vec::new();
    };
    let frame = Frame::of(&reference.info);
    let mut problems = Vec::new();
    let mut kept: Vec<&Part> = Vec::new();
    for part in parts {
        match mismatch(part, reference, &frame).or_else(|| bad_region(part)) {
            Some(problem) => problems.push(problem),
            None => kept.push(part),
        }
    }
    // Duplicates: the same rows named twice.
    let mut first_of: HashMap<(u32, u32), &Part> = HashMap::new();
    kept.retain(|part| {
        let rows = (part.info.region.y, part.info.region.height);
        match first_of.get(&rows) {
            Some(first) => {
                let (path, band) = (part.name(), part.info.band());
                problems.push(if first.path == part.path {
                    StitchError::NamedTwice { path, band }
                } else {
                    StitchError::Duplicate {
                        path,
                        first: first.name(),
                        band,
                    }
                });
                false
            }
            None => {
                first_of.insert(rows, part);
                true
            }
        }
    });
    kept.sort_by_key(|part| part.info.region.y);
    let splits: Vec<u32> = kept.iter().map(|part| part.info.tiles).collect();
    let one_split = splits
        .windows(2)
        .all(|w| w[0] == w[1])
        .then(|| splits.first().copied());
    let mut gaps = Vec::new();
    let mut covered = 0;
    let mut furthest: Option<&Part> = None;
    for part in &kept {
        let rows = part.info.rows();
        if rows.start > covered {
            gaps.push(covered..rows.start);
        } else if let Some(other) = furthest.filter(|_| rows.start < covered) {
            problems.push(overlap(part, other));
        }
        if rows.end > covered {
            covered = rows.end;
            furthest = Some(part);
        }
    }
    if covered < frame.height {
        gaps.push(covered..frame.height);
    }
    for gap in gaps {
        match one_split.flatten() {
            Some(n) => problems.extend(
                (1..=n)
                    .map(|k| Band { k, n })
                    .filter(|band| {
                        let rows = band.rows(frame.height);
                        gap.start <= rows.start && rows.end <= gap.end
                    })
                    .map(|band| {
                        let rows = band.rows(frame.height);
                        StitchError::MissingTile {
                            band,
                            start: rows.start,
                            end: rows.end,
                        }
                    }),
            ),
            None => problems.push(StitchError::MissingRows {
                start: gap.start,
                end: gap.end,
            }),
        }
    }
    problems
}

/// The first part of the frame most parts agree on.
fn reference(parts: &[Part]) -> Option<&Part> {
    let mut votes: HashMap<Frame, usize> = HashMap::new();
    for part in parts {
        *votes.entry(Frame::of(&part.info)).or_default() += 1;
    }
    let most = votes.values().copied().max()?;
    parts
        .iter()
        .find(|part| votes[&Frame::of(&part.info)] == most)
}

/// Why `part` is not of `frame` (that of `reference`), if it is not.
fn mismatch(part: &Part, reference: &Part, frame: &Frame) -> Option<StitchError> {
    let info = &part.info;
    let (path, reference_name) = (part.name(), reference.name());
    if info.scene_hash != frame.scene_hash {
        return Some(StitchError::ForeignScene {
            path,
            reference: reference_name,
            found: info.scene_hash.clone(),
            expected: frame.scene_hash.to_string(),
        });
    }
    if (info.width, info.height) != (frame.width, frame.height) {
        return Some(StitchError::OtherSize {
            path,
            reference: reference_name,
            found: format!("{}×{}", info.width, info.height),
            expected: format!("{}×{}", frame.width, frame.height),
        });
    }
    if info.options_hash != frame.options_hash {
        return Some(StitchError::OtherOptions {
            path,
            reference: reference_name,
            found: info.options.to_string(),
            expected: reference.info.options.to_string(),
        });
    }
    None
}

/// A region that is not the rows of the band the part says it is.
fn bad_region(part: &Part) -> Option<StitchError> {
    let info = &part.info;
    let band = info.band();
    let rows = info.rows();
    let valid_band = 1 <= band.k && band.k <= band.n && band.n <= info.height;
    let region_is_band = info.region.x == 0
        && info.region.width == info.width
        && valid_band
        && band.rows(info.height) == rows;
    (!region_is_band).then(|| StitchError::BadRegion {
        path: part.name(),
        band,
        start: rows.start,
        end: rows.end,
        height: info.height,
    })
}

fn overlap(part: &Part, other: &Part) -> StitchError {
    let (rows, other_rows) = (part.info.rows(), other.info.rows());
    StitchError::Overlap {
        path: part.name(),
        band: part.info.band(),
        start: rows.start,
        end: rows.end,
        other: other.name(),
        other_band: other.info.band(),
        other_start: other_rows.start,
        other_end: other_rows.end,
    }
}

/// The frame the `parts` make, decoded straight into place. The parts must
/// have passed [`problems`] (no problem), so they cover the frame once.
pub fn assemble(parts: &[Part]) -> Result<Image, ReadTileError> {
    let size = parts.first().map_or(0, |part| part.info.width);
    let row_bytes = size as usize * 3;
    let mut rgb = vec![0u8; row_bytes * size as usize];
    for part in parts {
        let rows = part.info.rows();
        let bytes = &mut rgb[rows.start as usize * row_bytes..rows.end as usize * row_bytes];
        file::read_pixels(&part.path, &part.info, bytes)?;
    }
    Ok(Image { size, rgb })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::Options;
    use crate::tile::PixelOptions;

    fn part(name: &str, k: u32, n: u32, scene: &str, spp: u32) -> Part {
        let options = Options {
            spp,
            ..Options::default()
        };
        let options = PixelOptions {
            precision: crate::render::Precision::F64,
            render: &options,
        };
        Part {
            path: PathBuf::from(name),
            info: TileInfo::new(Band { k, n }, 10, scene.to_string(), &options),
        }
    }

    fn codes(parts: &[Part]) -> Vec<String> {
        problems(parts)
            .iter()
            .map(|p| format!("{} {}", p.code().unwrap(), p))
            .collect()
    }

    #[test]
    fn statistics_pair_with_their_parts_one_to_one() {
        let parts = [part("a", 1, 2, "s", 1), part("b", 2, 2, "s", 1)];
        let entry = |name: &str, from: &Part| (PathBuf::from(name), from.info.clone(), name.len());
        let paired = pair(
            &parts,
            vec![entry("b.json", &parts[1]), entry("a.json", &parts[0])],
        );
        let names: Vec<PathBuf> = paired.unwrap().into_iter().map(|(path, _)| path).collect();
        assert_eq!(names, [PathBuf::from("a.json"), PathBuf::from("b.json")]);

        let other = part("x", 1, 2, "another scene", 1);
        let errors = pair(
            &parts,
            vec![
                entry("a.json", &parts[0]),
                entry("again.json", &parts[0]),
                entry("x.json", &other),
            ],
        )
        .unwrap_err();
        let codes: Vec<String> = errors
            .iter()
            .map(|e| format!("{} {}", e.code().unwrap(), e))
            .collect();
        assert_eq!(
            codes,
            [
                "stitch::duplicate_stats `again.json` and `a.json` are both the statistics of `a`",
                "stitch::foreign_stats `x.json` is the statistics of tile 1/2 of another render than the parts",
                "stitch::missing_stats no statistics were named for `b` (tile 2/2)",
            ]
        );
    }

    #[test]
    fn a_whole_split_in_any_order_has_no_problem() {
        let parts = [
            part("c", 3, 3, "s", 1),
            part("a", 1, 3, "s", 1),
            part("b", 2, 3, "s", 1),
        ];
        assert!(problems(&parts).is_empty());
        // Bands of two splits that happen to tile the frame.
        let mixed = [
            part("a", 1, 2, "s", 1),
            part("b", 3, 4, "s", 1),
            part("c", 4, 4, "s", 1),
        ];
        assert!(problems(&mixed).is_empty());
    }

    #[test]
    fn each_problem_names_its_part() {
        let missing = codes(&[part("a", 1, 3, "s", 1), part("c", 3, 3, "s", 1)]);
        assert_eq!(
            missing,
            ["stitch::missing_tile tile 2/3 is missing: no part covers rows 3..6"]
        );

        let duplicate = codes(&[
            part("a", 1, 2, "s", 1),
            part("b", 2, 2, "s", 1),
            part("b2", 2, 2, "s", 1),
        ]);
        assert_eq!(
            duplicate,
            ["stitch::duplicate `b2` duplicates `b`: both are tile 2/2"]
        );

        let foreign = codes(&[
            part("x", 1, 2, "other", 1),
            part("a", 1, 2, "s", 1),
            part("b", 2, 2, "s", 1),
        ]);
        assert_eq!(
            foreign,
            ["stitch::foreign_scene `x` is a tile of another scene than `a`"]
        );

        let options = codes(&[
            part("a", 1, 2, "s", 1),
            part("b", 2, 2, "s", 4),
            part("c", 1, 2, "s", 1),
        ]);
        assert_eq!(options.len(), 3, "{options:?}");
        assert!(
            options[0].starts_with("stitch::other_options `b` was rendered"),
            "{options:?}"
        );
        assert!(options[0].contains(r#""spp":4"#), "{options:?}");
        assert!(
            options[1].starts_with("stitch::duplicate `c` duplicates `a`"),
            "{options:?}"
        );
        assert!(
            options[2].starts_with("stitch::missing_tile tile 2/2"),
            "{options:?}"
        );

        let overlap = codes(&[
            part("a", 1, 2, "s", 1),
            part("b", 2, 3, "s", 1),
            part("c", 3, 3, "s", 1),
        ]);
        assert_eq!(
            overlap,
            ["stitch::overlap `b` (tile 2/3, rows 3..6) overlaps `a` (tile 1/2, rows 0..5)"]
        );

        let gap = codes(&[part("a", 1, 2, "s", 1), part("c", 3, 3, "s", 1)]);
        assert_eq!(
            gap,
            ["stitch::missing_rows rows 5..6 are missing: no part covers them"]
        );
    }

    #[test]
    fn a_region_that_is_not_its_band_is_refused() {
        let mut forged = part("f", 1, 2, "s", 1);
        forged.info.region.height = 4;
        let problems = codes(&[forged, part("b", 2, 2, "s", 1)]);
        assert_eq!(
            problems[0],
            "stitch::bad_region `f` claims rows 0..4 of a 10-row frame, which is not tile 1/2"
        );
    }
}
