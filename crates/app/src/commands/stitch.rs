//! `raytracer stitch OUT PARTS...`: put the tiles of `render --tile K/N`
//! together into one image, written atomically as `.png` or `.ppm`.
//!
//! Every part's metadata is read and judged first ([`tile::stitch`]):
//! each problem (a file that is no tile, a part of another scene, options
//! or size, a duplicate, an overlap, a missing band) is reported naming the
//! part, and the command exits 1 without touching OUT. An unreadable file
//! is an I/O error (exit 2).
//!
//! With `--stats-json PATH --part-stats TILE.json...`, the tiles'
//! `render --stats-json` files are merged into PATH: every ray counter and
//! every stage's seconds summed over the tiles, the frame's metadata, and
//! each tile's own statistics in frame order. Each part needs exactly one
//! statistics file, recognised by the `tile` metadata in it (not by its
//! name).

use std::path::{Path, PathBuf};
use std::time::Instant;

use miette::Diagnostic;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::stats::{Seconds, TileStats};
use super::Outcome;
use crate::cli::StitchArgs;
use raytracer_render::output::{self, Format};
use raytracer_render::render::Counters;
use raytracer_render::tile::file::{self, ReadTileError};
use raytracer_render::tile::stitch::{self, PairError, Part};
use raytracer_scene::diagnostic::BoxedDiagnostic;
use raytracer_scene::diagnostic::FileError;

/// Why the tiles' statistics cannot be merged.
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum StatsError {
    /// A statistics file cannot be read (exit 2).
    #[error(transparent)]
    #[diagnostic(code(io::read_stats))]
    Io(FileError),

    /// Not the `--stats-json` of a tile (exit 1).
    #[error("`{path}` is not the statistics of a tile: {reason}")]
    #[diagnostic(
        code(stitch::not_tile_stats),
        help("name the files that `raytracer render ... --tile K/N --stats-json PATH` wrote")
    )]
    NotTileStats { path: String, reason: String },

    /// The statistics do not pair with the parts one to one (exit 1).
    #[error(transparent)]
    #[diagnostic(transparent)]
    Pair(#[from] PairError),

    /// The merged statistics cannot be written (exit 2).
    #[error(transparent)]
    #[diagnostic(code(io::write_stats))]
    Write(FileError),
}

impl StatsError {
    fn is_io(&self) -> bool {
        matches!(self, StatsError::Io(_) | StatsError::Write(_))
    }
}

/// What `stitch --stats-json` writes.
#[derive(Serialize)]
struct MergedStats {
    /// The frame: the first tile's metadata less its own region.
    width: u32,
    height: u32,
    scene_hash: String,
    options_hash: String,
    options: Value,
    /// How many tiles were stitched.
    tiles: usize,
    /// Every counter, summed over the tiles.
    #[serde(flatten)]
    counters: Counters,
    /// Every stage's seconds, summed over the tiles.
    seconds: Seconds,
    /// This command's own time: reading, checking, writing.
    stitch_seconds: f64,
    /// Each tile's statistics as it wrote them, top band first.
    parts: Vec<Value>,
}

/// Run `raytracer stitch`.
pub fn run(args: StitchArgs) -> Result<Outcome, BoxedDiagnostic> {
    let start = Instant::now();
    let format = Format::from_path(&args.out)?;
    let inputs: Vec<&Path> = args
        .parts
        .iter()
        .chain(&args.part_stats)
        .map(PathBuf::as_path)
        .collect();
    for out in std::iter::once(&args.out).chain(&args.stats_json) {
        output::check_not_input(out, inputs.iter().copied())?;
        output::check_writable(out)?;
    }

    let mut parts = Vec::new();
    let mut fine = true;
    for path in &args.parts {
        match file::read_info(path) {
            Ok(info) => parts.push(Part {
                path: path.clone(),
                info,
            }),
            Err(error) => fine = report(error, ReadTileError::is_io)? && fine,
        }
    }
    for problem in stitch::problems(&parts) {
        sayln!("{:?}", miette::Report::new(problem));
        fine = false;
    }
    if !fine {
        return Ok(Outcome::SceneErrors);
    }
    parts.sort_by_key(|part| part.info.region.y);

    let merged = match &args.stats_json {
        Some(_) => match merge_stats(&parts, &args.part_stats) {
            Ok(merged) => Some(merged),
            Err(errors) => {
                for error in errors {
                    report(error, StatsError::is_io)?;
                }
                return Ok(Outcome::SceneErrors);
            }
        },
        None => None,
    };

    let image = match stitch::assemble(&parts) {
        Ok(image) => image,
        Err(error) => {
            report(error, ReadTileError::is_io)?;
            return Ok(Outcome::SceneErrors);
        }
    };
    output::write(&image, format, &args.out)?;

    if let (Some(path), Some(mut merged)) = (&args.stats_json, merged) {
        merged.stitch_seconds = start.elapsed().as_secs_f64();
        let json = serde_json::to_vec_pretty(&merged).map_err(std::io::Error::from);
        output::write_atomically(path, |out| out.write_all(&json?)).map_err(|error| {
            StatsError::Write(FileError::written("write statistics to", path, &error))
        })?;
    }
    Ok(Outcome::Success)
}

/// Print a problem with the parts (and return `false`), or hand back an
/// I/O failure, which ends the command with exit 2.
fn report<E: Diagnostic + Send + Sync + 'static>(
    error: E,
    is_io: fn(&E) -> bool,
) -> Result<bool, BoxedDiagnostic> {
    if is_io(&error) {
        return Err(Box::new(error));
    }
    sayln!("{:?}", miette::Report::new(error));
    Ok(false)
}

/// The tiles' statistics merged, or every reason they cannot be: the
/// `parts` (frame order) must each have exactly one file in `paths`.
fn merge_stats(parts: &[Part], paths: &[PathBuf]) -> Result<MergedStats, Vec<StatsError>> {
    let mut errors = Vec::new();
    let mut entries = Vec::new();
    for path in paths {
        let text = std::fs::read(path).map_err(|error| {
            vec![StatsError::Io(FileError::new(
                "read statistics",
                path,
                &error,
            ))]
        })?;
        let parsed = serde_json::from_slice::<Value>(&text).and_then(|value| {
            let stats = TileStats::deserialize(&value)?;
            Ok((value, stats))
        });
        match parsed {
            Ok((value, stats)) => entries.push((path.clone(), stats.tile.clone(), (value, stats))),
            Err(error) => errors.push(StatsError::NotTileStats {
                path: path.display().to_string(),
                reason: error.to_string(),
            }),
        }
    }
    let paired = match stitch::pair(parts, entries) {
        Ok(paired) if errors.is_empty() => paired,
        Ok(_) => return Err(errors),
        Err(pairing) => {
            errors.extend(pairing.into_iter().map(StatsError::from));
            return Err(errors);
        }
    };
    let frame = &parts[0].info;
    let mut merged = MergedStats {
        width: frame.width,
        height: frame.height,
        scene_hash: frame.scene_hash.clone(),
        options_hash: frame.options_hash.clone(),
        options: frame.options.clone(),
        tiles: parts.len(),
        counters: Counters::default(),
        seconds: Seconds::default(),
        stitch_seconds: 0.0,
        parts: Vec::new(),
    };
    // Every part comes from one scene and one set of options, so one
    // hierarchy: the frame's node count is any part's.
    merged.counters.bvh_nodes = paired.first().map_or(0, |(_, (_, s))| s.counters.bvh_nodes);
    for (_, (value, stats)) in paired {
        merged.counters += stats.counters;
        merged.seconds += stats.seconds;
        merged.parts.push(value);
    }
    Ok(merged)
}
