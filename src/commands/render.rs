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

use std::io::IsTerminal;
use std::path::Path;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use miette::Diagnostic;
use serde::Serialize;

use super::{load, Failure, Loaded, Outcome};
use crate::cli::{Antialias, Precision, RenderArgs};
use crate::diagnostic::{terminal_width, use_color};
use crate::ir::{self, Effects};
use crate::output::{self, Format};
use crate::render::{self, Counters, Image, Options};

/// A usage error found after clap: a value clap's parsers cannot judge.
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum RenderUsageError {
    /// `--spp` is not a square number.
    #[error("expected a square number of samples for `--spp`, found {found}")]
    #[diagnostic(
        code(usage::spp_not_square),
        help("samples lie on a √N×√N grid: try {below} or {above}")
    )]
    SppNotSquare { found: u32, below: u32, above: u32 },

    /// The worker threads could not be started.
    #[error("cannot start {threads} render threads: {reason}")]
    #[diagnostic(code(io::threads))]
    Threads { threads: usize, reason: String },

    /// `--stats-json` could not be written.
    #[error("cannot write statistics to `{path}`: {source}")]
    #[diagnostic(code(io::write_stats))]
    WriteStats {
        path: String,
        #[source]
        source: std::io::Error,
    },
}

/// Seconds per stage.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Seconds {
    pub parse: f64,
    pub check: f64,
    pub lower: f64,
    pub render: f64,
    pub write: f64,
    pub total: f64,
}

/// What `--stats` prints and `--stats-json` writes.
#[derive(Clone, Debug, Serialize)]
pub struct Stats {
    #[serde(flatten)]
    pub counters: Counters,
    pub seconds: Seconds,
    pub threads: usize,
    pub precision: &'static str,
    pub spp: u32,
    pub antialias: &'static str,
    pub max_depth: u32,
    pub skip: bool,
    pub accel: render::Accel,
    pub resolution: u32,
    pub effects: Effects,
}

/// Run `raytracer render`.
pub fn run(args: RenderArgs) -> Result<Outcome, Failure> {
    let start = Instant::now();
    let format = Format::from_path(&args.out)?;
    // The files this command writes: the image, and the statistics.
    let outputs: Vec<&Path> = std::iter::once(args.out.as_path())
        .chain(args.stats_json.as_deref())
        .collect();
    let scene = (args.scene != Path::new("-")).then_some(args.scene.as_path());
    for out in &outputs {
        output::check_not_input(out, scene)?;
        output::check_writable(out)?;
    }
    let grid = args.spp.isqrt();
    if grid * grid != args.spp {
        return Err(Box::new(RenderUsageError::SppNotSquare {
            found: args.spp,
            below: grid * grid,
            above: (grid + 1) * (grid + 1),
        }));
    }
    let threads = args
        .threads
        .map_or_else(rayon::current_num_threads, |t| t as usize);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| RenderUsageError::Threads {
            threads,
            reason: e.to_string(),
        })?;

    let Loaded {
        report,
        checked,
        parse_seconds: parse,
        check_seconds: check,
    } = load(&args.scene)?;
    let show_diagnostics = || {
        let stderr = std::io::stderr();
        eprint!(
            "{}",
            report.render_human(terminal_width(), use_color(&stderr))
        );
    };
    let Some(checked) = checked else {
        show_diagnostics();
        return Ok(Outcome::SceneErrors);
    };
    for out in &outputs {
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
    let lowering = Instant::now();
    let scene = ir::lower(&checked);
    let lower = lowering.elapsed().as_secs_f64();
    drop(checked);

    let options = Options {
        spp: args.spp,
        antialias: match args.aa {
            Antialias::Uniform => render::Antialias::Uniform,
            Antialias::Adaptive => render::Antialias::Adaptive {
                threshold: args.aa_threshold,
            },
        },
        max_depth: args.max_depth,
        skip: !args.no_skip,
        accel: args.accel,
        seed: 0,
    };
    let rendering = Instant::now();
    let (image, counters) = pool.install(|| trace(&scene, &options, args.precision, args.quiet));
    let render = rendering.elapsed().as_secs_f64();

    let writing = Instant::now();
    output::write(&image, format, &args.out)?;
    let write = writing.elapsed().as_secs_f64();

    let stats = Stats {
        counters,
        seconds: Seconds {
            parse,
            check,
            lower,
            render,
            write,
            total: start.elapsed().as_secs_f64(),
        },
        threads,
        precision: match args.precision {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        },
        spp: args.spp,
        antialias: match args.aa {
            Antialias::Uniform => "uniform",
            Antialias::Adaptive => "adaptive",
        },
        max_depth: args.max_depth,
        skip: options.skip,
        accel: options.accel,
        resolution: scene.resolution,
        effects: scene.effects,
    };
    if args.stats {
        eprint!("{}", stats.human());
    }
    if let Some(path) = &args.stats_json {
        let json = serde_json::to_vec_pretty(&stats).map_err(std::io::Error::from);
        output::write_atomically(path, |out| out.write_all(&json?)).map_err(|source| {
            RenderUsageError::WriteStats {
                path: path.display().to_string(),
                source,
            }
        })?;
    }
    Ok(Outcome::Success)
}

/// Render in the chosen precision, with a progress bar on a terminal.
fn trace(
    scene: &ir::Scene,
    options: &Options,
    precision: Precision,
    quiet: bool,
) -> (Image, Counters) {
    let bar = if quiet || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        ProgressBar::with_draw_target(
            Some(u64::from(scene.resolution)),
            ProgressDrawTarget::stderr(),
        )
    };
    if let Ok(style) = ProgressStyle::with_template("{bar:40} {pos}/{len} rows, {eta} left") {
        bar.set_style(style);
    }
    let row_done = || bar.inc(1);
    let result = match precision {
        Precision::F32 => render::render::<f32>(scene, options, &row_done),
        Precision::F64 => render::render::<f64>(scene, options, &row_done),
    };
    bar.finish_and_clear();
    result
}

impl Stats {
    /// Which pixels took how many samples.
    fn sampling(&self) -> String {
        if self.antialias == "adaptive" {
            let pixels = u64::from(self.resolution).pow(2);
            format!(
                "adaptive: {} of {pixels} pixels took {}, the rest 1",
                self.counters.pixels_refined, self.spp
            )
        } else {
            format!("uniform: every pixel took {}", self.spp)
        }
    }

    /// The `--stats` block for stderr.
    fn human(&self) -> String {
        let c = &self.counters;
        let s = &self.seconds;
        format!(
            "effects            {}\n\
             primary rays       {} (samples; {})\n\
             shadow rays        {} ({} skipped)\n\
             reflection rays    {} ({} paths saturated)\n\
             texture lookups    {}\n\
             seconds            parse {:.4}, check {:.4}, lower {:.4}, render {:.4}, write {:.4}, total {:.4}\n\
             threads            {} ({}, {} spp, max depth {})\n",
            self.effects.summary(),
            c.primary_rays,
            self.sampling(),
            c.shadow_rays,
            c.shadow_rays_skipped,
            c.reflection_rays,
            c.paths_saturated,
            c.texture_lookups,
            s.parse,
            s.check,
            s.lower,
            s.render,
            s.write,
            s.total,
            self.threads,
            self.precision,
            self.spp,
            self.max_depth,
        )
    }
}
