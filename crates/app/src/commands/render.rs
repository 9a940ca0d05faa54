//! `raytracer render` (and the bare `raytracer SCENE OUT`): load and check
//! the scene, lower it, trace it on a rayon pool and write the image
//! atomically; report statistics when asked.
//!
//! Everything that can be refused cheaply is refused before any work: an
//! unknown output extension, an output that is the scene file (or, once
//! the scene is loaded, one of its textures), a folder, or in a folder
//! where no file can be created, a `--spp` that is not a square. The
//! scene's warnings go to stderr (not with `--quiet`); its errors go to
//! stderr and the command exits 1 without touching OUT.
//!
//! With `--tile K/N` only that band of rows is traced, through the same row
//! loop, and written as a tile PNG that records where it belongs
//! ([`raytracer_render::tile`]); a non-PNG OUT is refused before any work, and more
//! bands than rows once the scene is loaded.

use std::io::IsTerminal;
use std::ops::Range;
use std::path::Path;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use miette::Diagnostic;

use super::stats::{Seconds, Stats};
use super::Outcome;
use crate::cli::{Antialias, RenderArgs};
use raytracer_render::ir;
use raytracer_render::output::{self, Format};
use raytracer_render::render::{self, Counters, Image, Options, Precision};
use raytracer_render::tile::{self, Band, PixelOptions, TileInfo};
use raytracer_scene::check::Checked;
use raytracer_scene::diagnostic::{terminal_width, use_color};
use raytracer_scene::diagnostic::{BoxedDiagnostic, FileError};
use raytracer_scene::frontend::{load_timed, Loaded};

/// A usage error found after clap: a value clap's parsers cannot judge.
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum RenderUsageError {
    #[error(transparent)]
    #[diagnostic(transparent)]
    Threads(#[from] super::ThreadsError),

    /// `--tile` with an output that is not PNG.
    #[error("expected a `.png` output for `--tile`, found `{path}`")]
    #[diagnostic(
        code(usage::tile_not_png),
        help("a tile records where it belongs in a PNG text chunk: name it `PART.png`")
    )]
    TileNotPng { path: String },

    /// `--tile K/N` with more bands than the frame has rows.
    #[error("cannot cut {rows} rows into {tiles} tiles: expected N ≤ {rows} in `--tile K/N`, found {tiles}")]
    #[diagnostic(
        code(usage::too_many_tiles),
        help("each tile is a band of whole rows; use at most {rows} tiles for this scene")
    )]
    TooManyTiles { rows: u32, tiles: u32 },

    /// `--stats-json` could not be written.
    #[error(transparent)]
    #[diagnostic(code(io::write_stats))]
    WriteStats(FileError),
}

/// Run `raytracer render`.
pub fn run(args: RenderArgs) -> Result<Outcome, BoxedDiagnostic> {
    let start = Instant::now();
    let (format, pool) = preflight(&args)?;
    let threads = pool.current_num_threads();
    let (Loaded { report, checked }, loading) = load_timed(&args.scene, &|| start.elapsed())?;
    let show_diagnostics = || {
        let stderr = std::io::stderr();
        say!(
            "{}",
            report.render_human(terminal_width(), use_color(&stderr))
        );
    };
    let Some(checked) = checked else {
        show_diagnostics();
        return Ok(Outcome::SceneErrors);
    };
    for out in outputs(&args) {
        output::check_not_input(out, checked.textures.values().map(|t| Path::new(&t.path)))?;
    }
    if !args.quiet && report.warning_count() > 0 {
        show_diagnostics();
    }
    // Each phase frees what the next does not need: the source text once
    // the warnings are printed, the model once it is lowered. A large
    // scene's peak memory is then the larger of model plus IR and IR plus
    // the tracer's own (docs/performance.md).
    drop(report);
    let options = Options {
        spp: args.sampling.spp,
        antialias: args.sampling.aa.with_threshold(args.aa_threshold),
        max_depth: args.max_depth,
        skip: !args.no_skip,
        accel: args.accel.into(),
        seed: 0,
        model: Default::default(),
    };
    let precision = args.sampling.precision;
    let tile = match args.tile {
        Some(band) => Some(tile_info(band, &checked, &options, precision)?),
        None => None,
    };
    let lowering = Instant::now();
    let scene = ir::lower(checked);
    let lower = lowering.elapsed().as_secs_f64();

    let rows = tile.as_ref().map_or(0..scene.resolution, TileInfo::rows);
    let rendering = Instant::now();
    let (rgb, counters) = pool.install(|| trace(&scene, &options, precision, args.quiet, rows));
    let render = rendering.elapsed().as_secs_f64();

    let writing = Instant::now();
    write_image(&args.out, format, tile.as_ref(), scene.resolution, rgb)?;
    let write = writing.elapsed().as_secs_f64();

    let stats = Stats {
        counters,
        seconds: Seconds {
            parse: loading.parse.as_secs_f64(),
            check: loading.check.as_secs_f64(),
            lower,
            render,
            write,
            total: start.elapsed().as_secs_f64(),
        },
        threads,
        precision,
        spp: args.sampling.spp,
        antialias: match args.sampling.aa {
            Antialias::Uniform => "uniform",
            Antialias::Adaptive => "adaptive",
        },
        max_depth: args.max_depth,
        skip: options.skip,
        accel: options.accel,
        accel_used: if counters.bvh_nodes > 0 {
            "bvh"
        } else {
            "brute"
        },
        resolution: scene.resolution,
        effects: scene.effects,
        tile,
    };
    if args.stats {
        say!("{}", stats.human());
    }
    if let Some(path) = &args.stats_json {
        write_stats(path, &stats)?;
    }
    Ok(Outcome::Success)
}

/// The files this command writes: the image, and the statistics.
fn outputs(args: &RenderArgs) -> Vec<&Path> {
    std::iter::once(args.out.as_path())
        .chain(args.stats_json.as_deref())
        .collect()
}

/// Everything about the arguments that can be refused before the scene is
/// read: the output format, outputs that would overwrite the scene or
/// cannot be written, a sample count that is no square, the thread pool.
fn preflight(args: &RenderArgs) -> Result<(Format, rayon::ThreadPool), BoxedDiagnostic> {
    let format = Format::from_path(&args.out)?;
    if args.tile.is_some() && format != Format::Png {
        return Err(Box::new(RenderUsageError::TileNotPng {
            path: args.out.display().to_string(),
        }));
    }
    let scene = (args.scene != Path::new("-")).then_some(args.scene.as_path());
    for out in outputs(args) {
        output::check_not_input(out, scene)?;
        output::check_writable(out)?;
    }
    super::square_spp(args.sampling.spp, "--spp")?;
    Ok((format, thread_pool(args.sampling.threads)?))
}

/// The render pool of `--threads` (all cores without it).
pub(crate) fn thread_pool(threads: Option<u32>) -> Result<rayon::ThreadPool, RenderUsageError> {
    Ok(super::thread_pool(threads.map(|t| t as usize), "render")?)
}

/// Write the rendered rows to `path`: a tile when rendering one, else the
/// image in `format`.
fn write_image(
    path: &Path,
    format: Format,
    tile: Option<&TileInfo>,
    size: u32,
    rgb: Vec<u8>,
) -> Result<(), BoxedDiagnostic> {
    match tile {
        Some(info) => output::write_with(path, |out| tile::file::encode(info, &rgb, out))?,
        None => output::write(&Image { size, rgb }, format, path)?,
    }
    Ok(())
}

/// Write `--stats-json`.
fn write_stats(path: &Path, stats: &Stats) -> Result<(), BoxedDiagnostic> {
    let json = serde_json::to_vec_pretty(stats).map_err(std::io::Error::from);
    output::write_atomically(path, |out| out.write_all(&json?)).map_err(|error| {
        RenderUsageError::WriteStats(FileError::written("write statistics to", path, &error))
    })?;
    Ok(())
}

/// Where band `band` of the checked scene's frame belongs; refused when the
/// frame has fewer rows than bands.
fn tile_info(
    band: Band,
    checked: &Checked,
    options: &Options,
    precision: Precision,
) -> Result<TileInfo, RenderUsageError> {
    let rows = checked.scene.camera.resolution;
    if band.n > rows {
        return Err(RenderUsageError::TooManyTiles {
            rows,
            tiles: band.n,
        });
    }
    let options = PixelOptions {
        precision,
        render: options,
    };
    Ok(TileInfo::new(
        band,
        rows,
        tile::scene_hash(checked),
        &options,
    ))
}

/// Render `rows` of the frame in the chosen precision, with a progress bar
/// on a terminal.
fn trace(
    scene: &ir::Scene,
    options: &Options,
    precision: Precision,
    quiet: bool,
    rows: Range<u32>,
) -> (Vec<u8>, Counters) {
    let bar = if quiet || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        ProgressBar::with_draw_target(Some(rows.len() as u64), ProgressDrawTarget::stderr())
    };
    if let Ok(style) = ProgressStyle::with_template("{bar:40} {pos}/{len} rows, {eta} left") {
        bar.set_style(style);
    }
    let row_done = || bar.inc(1);
    let result = render::render_rows(precision, scene, options, rows, &row_done);
    bar.finish_and_clear();
    result
}
