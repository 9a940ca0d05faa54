//! What each step of accuracy buys and costs, measured on this machine:
//! the report behind `make accuracy` (docs/accuracy.md).
//!
//! ```text
//! cargo run --release --example accuracy -- OUT.md ASSET_DIR [RUNS]
//! ```
//!
//! Every scene in scenes/ and the hard cases in scenes/hard/ (except the
//! far spheres, whose disks are below a pixel at this resolution; their
//! accuracy is in docs/numerics.md) is rendered in-process at
//! [`RESOLUTION`] under each [`SETTINGS`] row in RUNS timed batches
//! (default 5; a batch repeats the render for at least 50 ms),
//! and once as the reference (`f64`, [`REFERENCE_SPP`] samples, depth
//! [`REFERENCE_DEPTH`]). For each row the report gives the median time
//! per render over the batches and its ratio to the default, the rays cast, and the error against
//! the reference in 8-bit units: RMSE over all channels, the largest
//! absolute error, and the share of pixels off by more than 1/255; plus
//! the share of pixels that differ from the default image at all.
//!
//! ASSET_DIR receives `error_vs_time.csv` (for examples/plot.rs) and, for
//! the sample scene, the reference, the default render and their
//! difference (×8) as PNGs. The time is the render stage only (the pool
//! of rayon threads is the machine's); nothing else runs in between.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use raytracer::ir;
use raytracer::render::{render, Accel, Counters, Image, Options, Real};

/// Image side for every measured render.
const RESOLUTION: u32 = 128;
/// Samples per pixel of the reference.
const REFERENCE_SPP: u32 = 256;
/// Reflection depth of the reference.
const REFERENCE_DEPTH: u32 = 64;
/// A timed batch repeats a render until it lasts about this long, so
/// millisecond renders are not timed by the clock's and the pool's noise.
const BATCH_SECONDS: f64 = 0.05;

#[derive(Clone, Copy, PartialEq)]
enum Precision {
    F32,
    F64,
}

/// One row of a table: a setting and how it differs from the default.
struct Setting {
    name: &'static str,
    precision: Precision,
    options: Options,
}

const fn setting(
    name: &'static str,
    precision: Precision,
    spp: u32,
    max_depth: u32,
    skip: bool,
) -> Setting {
    Setting {
        name,
        precision,
        options: Options {
            spp,
            max_depth,
            skip,
            accel: Accel::Auto,
            antialias: raytracer::render::Antialias::Uniform,
            seed: 0,
        },
    }
}

/// The rows, the default first (every ratio is to it).
const SETTINGS: [Setting; 12] = [
    setting("default (f64, 1 spp, depth 8)", Precision::F64, 1, 8, true),
    setting("f32", Precision::F32, 1, 8, true),
    setting("--no-skip", Precision::F64, 1, 8, false),
    setting("depth 0", Precision::F64, 1, 0, true),
    setting("depth 1", Precision::F64, 1, 1, true),
    setting("depth 2", Precision::F64, 1, 2, true),
    setting("depth 4", Precision::F64, 1, 4, true),
    setting("depth 16", Precision::F64, 1, 16, true),
    setting("4 spp", Precision::F64, 4, 8, true),
    setting("16 spp", Precision::F64, 16, 8, true),
    setting("64 spp", Precision::F64, 64, 8, true),
    setting("f32, 16 spp", Precision::F32, 16, 8, true),
];

/// A measured row.
struct Row {
    seconds: f64,
    rays: u64,
    error: Error,
    changed: f64,
}

/// Error of an image against the reference, in 8-bit units.
struct Error {
    rmse: f64,
    max: u8,
    share_off: f64,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(
        args.next()
            .ok_or("usage: accuracy OUT.md ASSET_DIR [RUNS]")?,
    );
    let assets = PathBuf::from(
        args.next()
            .ok_or("usage: accuracy OUT.md ASSET_DIR [RUNS]")?,
    );
    let runs: usize = args.next().map_or(Ok(5), |r| r.parse())?;
    std::fs::create_dir_all(&assets)?;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut scenes = scene_files(&root.join("scenes"))?;
    scenes.extend(
        scene_files(&root.join("scenes/hard"))?
            .into_iter()
            .filter(|p| {
                !p.file_name().is_some_and(|n| {
                    n.to_string_lossy().starts_with("far_sphere_1e-")
                        && !n.to_string_lossy().ends_with("1e-2.txt")
                })
            }),
    );
    let started = Instant::now();
    let mut report = header(runs);
    let mut csv = String::from("series,x,y,label\n");
    for path in &scenes {
        let name = path
            .strip_prefix(root)
            .unwrap_or(path)
            .display()
            .to_string();
        eprintln!("{name}");
        let scene = load(path, RESOLUTION)?;
        let reference_options = Options {
            spp: REFERENCE_SPP,
            max_depth: REFERENCE_DEPTH,
            skip: true,
            accel: Accel::Auto,
            ..Options::default()
        };
        let clock = Instant::now();
        let (reference, reference_counters) = render::<f64>(&scene, &reference_options, &|| {});
        let reference_seconds = clock.elapsed().as_secs_f64();
        let mut rows = Vec::new();
        let mut default_image = None;
        for s in &SETTINGS {
            let (image, seconds, counters) = measure(&scene, s, runs);
            let error = error(&image, &reference);
            let changed = default_image
                .as_ref()
                .map_or(0.0, |d| share_changed(&image, d));
            rows.push(Row {
                seconds,
                rays: rays(&counters),
                error,
                changed,
            });
            default_image.get_or_insert(image);
        }
        let base = rows[0].seconds;
        writeln!(report, "\n## `{name}`\n")?;
        writeln!(
            report,
            "Reference: {:.3} s, {} rays.\n",
            reference_seconds,
            rays(&reference_counters)
        )?;
        writeln!(report, "| setting | time (s) | × default | rays | RMSE | max | off > 1/255 | changed vs default |")?;
        writeln!(report, "|---|---:|---:|---:|---:|---:|---:|---:|")?;
        for (s, row) in SETTINGS.iter().zip(&rows) {
            writeln!(
                report,
                "| {} | {:.4} | {:.2} | {} | {:.3} | {} | {:.2}% | {:.2}% |",
                s.name,
                row.seconds,
                row.seconds / base,
                row.rays,
                row.error.rmse,
                row.error.max,
                100.0 * row.error.share_off,
                100.0 * row.changed
            )?;
            if s.precision == Precision::F64 && s.options.max_depth == 8 && s.options.skip {
                let stem = Path::new(&name)
                    .file_stem()
                    .map_or(name.clone(), |s| s.to_string_lossy().into_owned());
                writeln!(
                    csv,
                    "{stem},{},{},{}",
                    row.seconds / base,
                    row.error.rmse,
                    s.options.spp
                )?;
            }
        }
        writeln!(report, "\n{}", findings(&rows))?;
        if name == "scenes/sample.txt" {
            let default = default_image.as_ref().expect("the default row ran");
            save(&reference, &assets.join("sample_reference.png"))?;
            save(default, &assets.join("sample_default.png"))?;
            save(
                &difference(default, &reference, 8),
                &assets.join("sample_difference.png"),
            )?;
        }
    }
    writeln!(
        report,
        "\nAll renders took {:.1} s in total.",
        started.elapsed().as_secs_f64()
    )?;
    std::fs::write(assets.join("error_vs_time.csv"), csv)?;
    std::fs::write(out, report)?;
    Ok(())
}

/// Row indices in [`SETTINGS`].
const DEFAULT: usize = 0;
const F32: usize = 1;
const NO_SKIP: usize = 2;
/// (depth, row) in increasing depth, the default's 8 among them.
const DEPTHS: [(u32, usize); 6] = [(0, 3), (1, 4), (2, 5), (4, 6), (8, DEFAULT), (16, 7)];
/// (samples, row) in increasing samples.
const SAMPLES: [(u32, usize); 4] = [(1, DEFAULT), (4, 8), (16, 9), (64, 10)];

/// What the rows say, in words, from the numbers alone.
fn findings(rows: &[Row]) -> String {
    let default = &rows[DEFAULT];
    let f32_row = &rows[F32];
    let mut lines = Vec::new();
    let extra_off = f32_row.error.share_off - default.error.share_off;
    lines.push(if extra_off <= 0.001 && f32_row.error.max <= default.error.max + 1 {
        format!(
            "- **f32 is enough here**: it changes {:.2}% of pixels and adds {:+.2} points to the share off by more than 1/255 (×{:.2} the time).",
            100.0 * f32_row.changed,
            100.0 * extra_off,
            f32_row.seconds / default.seconds
        )
    } else {
        format!(
            "- **f32 is not enough here**: {:.2}% more pixels are off by more than 1/255 (max error {} vs {} in f64).",
            100.0 * extra_off,
            f32_row.error.max,
            default.error.max
        )
    });
    let settled = DEPTHS
        .iter()
        .find(|&&(_, row)| rows[row].changed == 0.0)
        .map_or("none of the measured depths".to_string(), |(d, _)| {
            format!("depth {d}")
        });
    let rays: Vec<String> = DEPTHS
        .windows(2)
        .map(|w| {
            let (a, b) = (&rows[w[0].1], &rows[w[1].1]);
            format!(
                "{}→{}: {:+} rays (×{:.2} time)",
                w[0].0,
                w[1].0,
                b.rays as i64 - a.rays as i64,
                b.seconds / a.seconds
            )
        })
        .collect();
    lines.push(format!(
        "- **Reflection**: {settled} already gives the default (depth 8) image; each step adds {}.",
        rays.join(", ")
    ));
    let steps: Vec<String> = SAMPLES
        .windows(2)
        .map(|w| {
            let (a, b) = (&rows[w[0].1], &rows[w[1].1]);
            let gain = if a.error.rmse == 0.0 {
                "nothing left to gain".to_string()
            } else if b.error.rmse == 0.0 {
                "RMSE to 0".to_string()
            } else {
                format!("RMSE ÷{:.2}", a.error.rmse / b.error.rmse)
            };
            format!(
                "{}→{} spp: {gain} for ×{:.1} time",
                w[0].0,
                w[1].0,
                b.seconds / a.seconds
            )
        })
        .collect();
    // Past the sample count where at most 1% of pixels are off by more
    // than 1/255, more samples fix fewer pixels than they cost in time.
    let enough = SAMPLES
        .iter()
        .find(|&&(_, row)| rows[row].error.share_off <= 0.01);
    lines.push(format!(
        "- **Supersampling**: {}. {}",
        steps.join("; "),
        enough.map_or("Even 64 spp leaves more than 1% of pixels off by more than 1/255.".to_string(), |&(n, row)| format!(
            "At {n} spp (×{:.1} the time) at most 1% of pixels are off by more than 1/255; beyond it, samples stop paying.",
            rows[row].seconds / default.seconds
        ))
    ));
    let skip = &rows[NO_SKIP];
    lines.push(format!(
        "- **Skipping** work that cannot change an 8-bit value saves {} rays ({:.1}%), ×{:.2} the time without it; the image is {}.",
        skip.rays as i64 - default.rays as i64,
        100.0 * (skip.rays as f64 - default.rays as f64) / skip.rays as f64,
        default.seconds / skip.seconds,
        if skip.changed == 0.0 { "the same" } else { "different (a defect)" }
    ));
    lines.join("\n")
}

fn header(runs: usize) -> String {
    format!(
        "# What accuracy costs\n\n\
         Generated by `make accuracy` (`examples/accuracy.rs`); do not edit by hand.\n\
         Every scene is rendered at {RESOLUTION}×{RESOLUTION} under each setting in {runs} timed\n\
         batches (each repeats the render for at least 50 ms); the time is the median time\n\
         per render (render stage only) on {threads} threads of this machine.\n\
         Errors are against a reference render (f64, {REFERENCE_SPP} samples per pixel,\n\
         depth {REFERENCE_DEPTH}), in 8-bit units (1 = 1/255): RMSE over all channels, the\n\
         largest absolute error, and the share of pixels off by more than 1/255.\n\
         \"changed vs default\" is the share of pixels whose value differs at all\n\
         from the default image. Rays = primary + shadow + reflection.\n\n\
         Under each table, the findings are read off its numbers: f32 is *enough* when it\n\
         adds at most 0.1 points to the share of pixels off by more than 1/255 and at most\n\
         1 to the largest error; supersampling stops paying at the first sample count that\n\
         leaves at most 1% of pixels off by more than 1/255. Timings of renders this short\n\
         move by ±20% between runs on a shared machine; ray counts are exact.\n\n\
         ![RMSE against time for 1, 4, 16, 64 samples per pixel](accuracy/error_vs_time.png)\n\n\
         The sample scene's reference, its default render, and their difference (×8):\n\n\
         ![reference](accuracy/sample_reference.png) ![default](accuracy/sample_default.png) \
         ![difference](accuracy/sample_difference.png)\n",
        threads = rayon::current_num_threads()
    )
}

fn scene_files(dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "txt"))
        .collect();
    files.sort();
    Ok(files)
}

fn load(path: &Path, resolution: u32) -> Result<ir::Scene, Box<dyn std::error::Error>> {
    let bytes = std::fs::read(path)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let loaded =
        raytracer::commands::load_bytes(&path.display().to_string(), dir, &bytes, Instant::now());
    let mut checked = loaded
        .checked
        .ok_or_else(|| format!("`{}` has errors", path.display()))?;
    checked.scene.camera.resolution = resolution;
    Ok(ir::lower(&checked))
}

/// Render once for the image and counters, then time `batches` batches of
/// enough renders to last [`BATCH_SECONDS`]; the median time per render.
fn measure(scene: &ir::Scene, setting: &Setting, batches: usize) -> (Image, f64, Counters) {
    let once = || match setting.precision {
        Precision::F32 => timed::<f32>(scene, &setting.options),
        Precision::F64 => timed::<f64>(scene, &setting.options),
    };
    let clock = Instant::now();
    let (image, counters) = once();
    let first = clock.elapsed().as_secs_f64();
    let repeats = ((BATCH_SECONDS / first).ceil() as usize).clamp(1, 1000);
    let mut times: Vec<f64> = (0..batches.max(1))
        .map(|_| {
            let clock = Instant::now();
            for _ in 0..repeats {
                std::hint::black_box(once());
            }
            clock.elapsed().as_secs_f64() / repeats as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    (image, times[times.len() / 2], counters)
}

fn timed<R: Real>(scene: &ir::Scene, options: &Options) -> (Image, Counters) {
    render::<R>(scene, options, &|| {})
}

fn rays(c: &Counters) -> u64 {
    c.primary_rays + c.shadow_rays + c.reflection_rays
}

fn error(image: &Image, reference: &Image) -> Error {
    let mut sum = 0.0;
    let mut max = 0u8;
    let mut off = 0usize;
    for (a, b) in image.rgb.chunks(3).zip(reference.rgb.chunks(3)) {
        let mut pixel_off = false;
        for (&x, &y) in a.iter().zip(b) {
            let d = x.abs_diff(y);
            sum += f64::from(d) * f64::from(d);
            max = max.max(d);
            pixel_off |= d > 1;
        }
        off += usize::from(pixel_off);
    }
    let pixels = image.rgb.len() / 3;
    Error {
        rmse: (sum / image.rgb.len() as f64).sqrt(),
        max,
        share_off: off as f64 / pixels as f64,
    }
}

fn share_changed(image: &Image, default: &Image) -> f64 {
    let changed = image
        .rgb
        .chunks(3)
        .zip(default.rgb.chunks(3))
        .filter(|(a, b)| a != b)
        .count();
    changed as f64 / (image.rgb.len() / 3) as f64
}

fn difference(a: &Image, b: &Image, gain: u8) -> Image {
    Image {
        size: a.size,
        rgb: a
            .rgb
            .iter()
            .zip(&b.rgb)
            .map(|(&x, &y)| x.abs_diff(y).saturating_mul(gain))
            .collect(),
    }
}

fn save(image: &Image, path: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let buffer = image::RgbImage::from_raw(image.size, image.size, image.rgb.clone())
        .ok_or("image size mismatch")?;
    buffer.save(path)?;
    Ok(())
}
