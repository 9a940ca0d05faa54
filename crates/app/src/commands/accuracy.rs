//! `raytracer accuracy SCENE...`: load and check every scene, lower each,
//! have [`crate::accuracy::study`] measure every accuracy setting against
//! converged references (at `--size` if given, else at each scene's
//! [`crate::accuracy::measured_size`]) and print the report as Markdown
//! on stdout; with
//! `--assets DIR`, also write each scene's plot data, its charts
//! ([`crate::plot`]) and its f32 − f64 difference map there, each file
//! whole or not at all, and link them from the report.
//!
//! With one scene and one threshold the report is that scene's. Otherwise
//! it starts with the verdict tables ([`summary`]): with several
//! `--aa-threshold` candidates, the SCENES choose one by the tuning rule;
//! the `--held-out` scenes are measured after the choice, at the chosen
//! threshold only, and judged in a table of their own.

use std::path::{Path, PathBuf};

use miette::Diagnostic;

use super::Outcome;
use crate::accuracy::study::{study, Pools, Settings};
use crate::accuracy::summary::{self, Measured};
use crate::accuracy::{report, Measurement};
use crate::cli::AccuracyArgs;
use crate::plot::{self, Chart, Corner};
use raytracer_render::ir;
use raytracer_render::output::{self, Format};
use raytracer_scene::diagnostic::{terminal_width, use_color};
use raytracer_scene::diagnostic::{BoxedDiagnostic, FileError};
use raytracer_scene::frontend::{load, Loaded};

/// A usage or I/O error of `accuracy`.
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum AccuracyError {
    #[error(transparent)]
    #[diagnostic(transparent)]
    Threads(#[from] super::ThreadsError),

    /// A chart could not be drawn.
    #[error("cannot draw `{path}`: {source}")]
    #[diagnostic(code(internal::plot))]
    Plot {
        path: String,
        #[source]
        source: plot::PlotError,
    },

    /// The assets folder could not be made or a file in it written.
    #[error(transparent)]
    #[diagnostic(code(io::write_assets))]
    Write(FileError),
}

/// Run `raytracer accuracy`.
pub fn run(args: AccuracyArgs) -> Result<Outcome, BoxedDiagnostic> {
    super::square_spp(args.reference_spp, "--reference-spp")?;
    let paths: Vec<&PathBuf> = args.scenes.iter().chain(&args.held_out).collect();
    let stems = stems(&paths);
    let assets = match &args.assets {
        Some(dir) => Some(
            stems
                .iter()
                .map(|stem| prepare_assets(dir, stem))
                .collect::<Result<Vec<_>, _>>()?,
        ),
        None => None,
    };
    let pool = |threads: usize| super::thread_pool(Some(threads), "measuring");
    let threads = args
        .threads
        .map_or_else(rayon::current_num_threads, |t| t as usize);
    let (all, single) = (pool(threads)?, pool(1)?);

    // Every scene checked before any is measured.
    let stderr = std::io::stderr();
    let mut scenes = Vec::new();
    let mut failed = false;
    for path in &paths {
        let Loaded {
            report: diagnostics,
            checked,
            ..
        } = load(path)?;
        if diagnostics.warning_count() > 0 || checked.is_none() {
            say!(
                "{}",
                diagnostics.render_human(terminal_width(), use_color(&stderr))
            );
        }
        match checked {
            Some(checked) => scenes.push(ir::lower(checked)),
            None => failed = true,
        }
    }
    if failed {
        return Ok(Outcome::SceneErrors);
    }

    // One plain line a step, on a terminal or not: a run takes about a
    // minute, and a log or CI job should show it is alive.
    let progress = |k: usize, step: &str| sayln!("{}: {step}", stems[k]);
    let mut named: Vec<(String, ir::Scene)> = paths
        .iter()
        .map(|path| path.display().to_string())
        .zip(scenes)
        .collect();
    let held_out = named.split_off(args.scenes.len());
    let settings = Settings {
        reps: args.reps as usize,
        reference_spp: args.reference_spp,
        size: args.size,
        candidates: args.aa_threshold.clone(),
    };
    let pools = Pools {
        all: &all,
        single: &single,
    };
    let study = study(named, held_out, &settings, &pools, &progress);

    let measured: Vec<&Measured> = study.measured().collect();
    let alone = measured.len() == 1 && args.aa_threshold.len() == 1;
    if !alone {
        out!(
            "{}",
            summary::verdicts(&study.tuning, &study.held_out, study.chosen)
        )?;
        out!("## Scene by scene\n\n")?;
    }
    for (k, (name, measurement)) in measured.into_iter().enumerate() {
        if !alone {
            out!("### `{name}`\n\n")?;
        }
        out!("{}", report::markdown(measurement, name))?;
        if let (Some(assets), Some(dir)) = (&assets, &args.assets) {
            let drawn = write_assets(measurement, &stems[k], &assets[k])?;
            let largest = report::numeric(measurement).max;
            out!(
                "{}",
                asset_links(dir, &stems[k], &assets[k], drawn, largest)
            )?;
        }
    }
    Ok(Outcome::Success)
}

/// The asset stem of each scene: its file stem, or, where two scenes
/// share one, its folder's name, a `-` and its file stem.
fn stems(paths: &[&PathBuf]) -> Vec<String> {
    let stem = |path: &Path| {
        path.file_stem()
            .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned())
    };
    paths
        .iter()
        .map(|path| {
            let shared = paths.iter().filter(|p| stem(p) == stem(path)).count() > 1;
            let folder = path
                .parent()
                .and_then(Path::file_name)
                .map(|f| f.to_string_lossy().into_owned());
            match folder {
                Some(folder) if shared => format!("{folder}-{}", stem(path)),
                _ => stem(path),
            }
        })
        .collect()
}

/// Which charts [`write_assets`] drew (none when every RMSE is 0).
struct Drawn {
    sampling: bool,
    pareto: bool,
}

/// Write a scene's plot data, charts and difference map.
fn write_assets(m: &Measurement, stem: &str, assets: &Assets) -> Result<Drawn, BoxedDiagnostic> {
    let write_text = |path: &PathBuf, text: String| {
        output::write_atomically(path, |out| out.write_all(text.as_bytes()))
            .map_err(FileError::writing(path))
            .map_err(AccuracyError::Write)
    };
    let sampling = report::sampling_csv(m);
    let pareto = report::pareto_csv(m);
    write_text(&assets.sampling, sampling.clone())?;
    write_text(&assets.pareto, pareto.clone())?;
    let chart = |title: &str, x_label: &str, guides: &[&str]| Chart {
        title: format!("{stem}: {title}"),
        x_label: x_label.into(),
        y_label: "RMSE, in 1/255".into(),
        log_x: true,
        log_y: true,
        lines: true,
        size: (480, 340),
        guides: guides.iter().map(|g| g.to_string()).collect(),
        legend: Corner::LowerLeft,
    };
    let sampling_chart = chart(
        "RMSE against spp",
        "samples per pixel",
        &[report::GUIDE_HALF, report::GUIDE_ONE, report::FLOOR],
    );
    let pareto_chart = chart("RMSE against time", "time, × the default's", &[]);
    let drawn = Drawn {
        sampling: draw_chart(&sampling_chart, &sampling, &assets.sampling_png)?,
        pareto: draw_chart(&pareto_chart, &pareto, &assets.pareto_png)?,
    };
    let map = report::numeric_map(m);
    output::write(&map, Format::Png, &assets.map)?;
    Ok(drawn)
}

/// The Markdown that shows a scene's charts and difference map, linked by
/// the assets folder's last name (for a report written beside it).
fn asset_links(dir: &Path, stem: &str, assets: &Assets, drawn: Drawn, largest: f64) -> String {
    let folder = dir
        .file_name()
        .map_or_else(|| ".".into(), |f| f.to_string_lossy().into_owned());
    let link = |path: &Path| {
        let file = path.file_name().unwrap_or_default().to_string_lossy();
        format!("{folder}/{file}")
    };
    let mut out = String::from("\n");
    if drawn.sampling || drawn.pareto {
        let charts: Vec<String> = [
            (drawn.sampling, "RMSE against spp", &assets.sampling_png),
            (drawn.pareto, "RMSE against time", &assets.pareto_png),
        ]
        .into_iter()
        .filter(|(drawn, ..)| *drawn)
        .map(|(_, what, path)| format!("![{stem}: {what}]({})", link(path)))
        .collect();
        out.push_str(&charts.join(" "));
        out.push_str("\n\n");
    } else {
        out.push_str("No sampling charts: every RMSE is 0 here (a log axis cannot show it).\n\n");
    }
    out.push_str(&format!(
        "f32 − f64 difference map, on an absolute scale: black is equal, white a \
         difference of {scale}/255 or more in some channel ({largest:.4}/255 at most here):\n\n\
         ![{stem}: f32 − f64]({})\n\n",
        link(&assets.map),
        scale = report::MAP_WHITE,
    ));
    out
}
/// Draw `csv` as `chart` to `path`; nothing when every point has RMSE 0
/// (a log axis cannot show it), so no empty chart is written. Whether it
/// drew.
fn draw_chart(chart: &Chart, csv: &str, path: &Path) -> Result<bool, BoxedDiagnostic> {
    let failed = |source| AccuracyError::Plot {
        path: path.display().to_string(),
        source,
    };
    let series = plot::parse_csv(csv).map_err(failed)?;
    let drawn = match plot::draw(chart, series) {
        Err(plot::PlotError::Empty) => return Ok(false),
        drawn => drawn.map_err(failed)?,
    };
    output::write_atomically(path, |out| out.write_all(&drawn.png))
        .map_err(FileError::writing(path))
        .map_err(AccuracyError::Write)?;
    Ok(true)
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
    std::fs::create_dir_all(dir)
        .map_err(FileError::writing(dir))
        .map_err(AccuracyError::Write)?;
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
