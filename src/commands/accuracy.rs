//! `raytracer accuracy SCENE`: load and check the scene, lower it (at
//! `--size` if given, else at [`measured_size`] of its own), measure every accuracy setting against a converged
//! reference ([`crate::accuracy`]) and print the report as Markdown on
//! stdout; with `--assets DIR`, also write the plot data, its charts
//! ([`crate::plot`]) and the f32 − f64 difference map there, each file
//! whole or not at all.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use miette::Diagnostic;

use super::Outcome;
use crate::accuracy::{measure, measured_size, report, Plan};
use crate::cli::AccuracyArgs;
use crate::diagnostic::BoxedDiagnostic;
use crate::diagnostic::{terminal_width, use_color};
use crate::frontend::{load, Loaded};
use crate::ir;
use crate::output::{self, Format};
use crate::plot::{self, Chart, Corner};
use crate::render::Options;

/// A usage or I/O error of `accuracy`.
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum AccuracyError {
    /// The worker threads could not be started.
    #[error("cannot start {threads} threads: {reason}")]
    #[diagnostic(code(io::threads))]
    Threads { threads: usize, reason: String },

    /// A chart could not be drawn.
    #[error("cannot draw `{path}`: {source}")]
    #[diagnostic(code(internal::plot))]
    Plot {
        path: String,
        #[source]
        source: plot::PlotError,
    },

    /// The assets folder could not be made or a file in it written.
    #[error("cannot write `{path}`: {source}")]
    #[diagnostic(code(io::write_assets))]
    Write {
        path: String,
        #[source]
        source: std::io::Error,
    },
}

/// Run `raytracer accuracy`.
pub fn run(args: AccuracyArgs) -> Result<Outcome, BoxedDiagnostic> {
    Options::square_spp(args.reference_spp, "--reference-spp")?;
    let stem = args
        .scene
        .file_stem()
        .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    let assets = args
        .assets
        .as_ref()
        .map(|dir| prepare_assets(dir, &stem))
        .transpose()?;
    let pool = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| AccuracyError::Threads {
                threads,
                reason: e.to_string(),
            })
    };
    let threads = args
        .threads
        .map_or_else(rayon::current_num_threads, |t| t as usize);
    let (all, single) = (pool(threads)?, pool(1)?);

    let Loaded {
        report: diagnostics,
        checked,
        ..
    } = load(&args.scene)?;
    let stderr = std::io::stderr();
    if diagnostics.warning_count() > 0 || checked.is_none() {
        eprint!(
            "{}",
            diagnostics.render_human(terminal_width(), use_color(&stderr))
        );
    }
    let Some(checked) = checked else {
        return Ok(Outcome::SceneErrors);
    };
    let mut scene = ir::lower(checked);
    let own_size = scene.resolution;
    scene.resolution = args.size.unwrap_or_else(|| measured_size(own_size));
    let plan = Plan {
        reps: args.reps as usize,
        reference_spp: args.reference_spp,
        threshold: args.aa_threshold,
        own_size,
    };
    let show_progress = stderr.is_terminal();
    let progress = |step: &str| {
        if show_progress {
            eprintln!("{stem}: {step}");
        }
    };
    let measurement = all.install(|| measure(&scene, plan, &single, &progress));
    print!(
        "{}",
        report::markdown(&measurement, &args.scene.display().to_string())
    );
    if let Some(assets) = assets {
        let write_text = |path: &PathBuf, text: String| {
            output::write_atomically(path, |out| out.write_all(text.as_bytes())).map_err(|source| {
                AccuracyError::Write {
                    path: path.display().to_string(),
                    source,
                }
            })
        };
        let sampling = report::sampling_csv(&measurement);
        let pareto = report::pareto_csv(&measurement);
        write_text(&assets.sampling, sampling.clone())?;
        write_text(&assets.pareto, pareto.clone())?;
        let chart = |title: &str, x_label: &str, guides: &[&str]| Chart {
            title: format!("{stem}: {title}"),
            x_label: x_label.into(),
            y_label: "RMSE, 1/255".into(),
            log_x: true,
            log_y: true,
            lines: true,
            size: (480, 340),
            guides: guides.iter().map(|g| g.to_string()).collect(),
            legend: Corner::LowerLeft,
        };
        let charts = [
            (
                chart(
                    "RMSE against spp",
                    "samples per pixel",
                    &[report::GUIDE_HALF, report::GUIDE_ONE],
                ),
                sampling,
                &assets.sampling_png,
            ),
            (
                chart("error against time", "time, × the default", &[]),
                pareto,
                &assets.pareto_png,
            ),
        ];
        for (chart, csv, path) in charts {
            draw_chart(&chart, &csv, path)?;
        }
        let (map, _) = report::numeric_map(&measurement);
        output::write(&map, Format::Png, &assets.map)?;
    }
    Ok(Outcome::Success)
}

/// Draw `csv` as `chart` to `path`; nothing when every point has RMSE 0
/// (a log axis cannot show it), so no empty chart is written.
fn draw_chart(chart: &Chart, csv: &str, path: &Path) -> Result<(), BoxedDiagnostic> {
    let failed = |source| AccuracyError::Plot {
        path: path.display().to_string(),
        source,
    };
    let series = plot::parse_csv(csv).map_err(failed)?;
    let drawn = match plot::draw(chart, series) {
        Err(plot::PlotError::Empty) => return Ok(()),
        drawn => drawn.map_err(failed)?,
    };
    output::write_atomically(path, |out| out.write_all(&drawn.png)).map_err(|source| {
        AccuracyError::Write {
            path: path.display().to_string(),
            source,
        }
    })?;
    Ok(())
}

/// The files `--assets DIR` writes for a scene.
struct Assets {
    sampling: PathBuf,
    pareto: PathBuf,
    sampling_png: PathBuf,
    pareto_png: PathBuf,
    map: PathBuf,
}

/// Make DIR and check its files can be written, before any work.
fn prepare_assets(dir: &Path, stem: &str) -> Result<Assets, BoxedDiagnostic> {
    std::fs::create_dir_all(dir).map_err(|source| AccuracyError::Write {
        path: dir.display().to_string(),
        source,
    })?;
    let assets = Assets {
        sampling: dir.join(format!("{stem}.sampling.csv")),
        pareto: dir.join(format!("{stem}.pareto.csv")),
        sampling_png: dir.join(format!("{stem}.sampling.png")),
        pareto_png: dir.join(format!("{stem}.pareto.png")),
        map: dir.join(format!("{stem}.f32_f64.png")),
    };
    for path in [
        &assets.sampling,
        &assets.pareto,
        &assets.sampling_png,
        &assets.pareto_png,
        &assets.map,
    ] {
        output::check_writable(path)?;
    }
    Ok(assets)
}
