//! Plots a small CSV as a PNG scatter or line chart, for the measured
//! figures in docs/ (error against time, throughput against threads, …).
//!
//! ```text
//! cargo run --release --example plot -- DATA.csv OUT.png \
//!     [--title TEXT] [--x-label TEXT] [--y-label TEXT] \
//!     [--log-x] [--log-y] [--lines] [--size WIDTHxHEIGHT] \
//!     [--guide SERIES]... [--legend upper-left|upper-right|lower-left|lower-right]
//! ```
//!
//! DATA.csv has a header line, then rows `series,x,y[,label]`: one coloured
//! series per distinct `series` (in order of first appearance), a point at
//! (`x`, `y`), and an optional `label` written beside the point. A series
//! named by `--guide` is a reference line (thin, grey, no markers), not
//! data. Fields are
//! split on commas; there is no quoting. `--lines` joins each series' points
//! in file order. On a log axis, points with a value ≤ 0 cannot be drawn:
//! they are left out and counted on stderr.
//!
//! Text is drawn with DejaVu Sans, bundled from docs/fonts/ (Debian's
//! fonts-dejavu-core; licence beside it), so the output does not depend on
//! the fonts of the machine. The PNG is written atomically.

use std::error::Error;
use std::ops::Range;
use std::path::{Path, PathBuf};

use clap::Parser;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;
use plotters::style::FontStyle;

/// Bundled so every machine draws the same glyphs.
const FONT: &[u8] = include_bytes!("../docs/fonts/DejaVuSans.ttf");

#[derive(Parser)]
#[command(about = "Plot `series,x,y[,label]` rows of a CSV file as a PNG chart")]
struct Args {
    /// Input CSV: a header, then `series,x,y[,label]` rows.
    data: PathBuf,
    /// Output PNG.
    out: PathBuf,
    #[arg(long, default_value = "")]
    title: String,
    #[arg(long, default_value = "x")]
    x_label: String,
    #[arg(long, default_value = "y")]
    y_label: String,
    /// Logarithmic x axis.
    #[arg(long)]
    log_x: bool,
    /// Logarithmic y axis.
    #[arg(long)]
    log_y: bool,
    /// Join each series' points in file order.
    #[arg(long)]
    lines: bool,
    /// Image size in pixels, `WIDTHxHEIGHT`.
    #[arg(long, default_value = "900x600", value_parser = parse_size)]
    size: (u32, u32),
    /// A series drawn as a thin grey guide line without markers.
    #[arg(long)]
    guide: Vec<String>,
    /// Where the legend goes (where the data is not).
    #[arg(long, value_enum, default_value_t = Corner::UpperRight)]
    legend: Corner,
}

/// A corner of the plot area.
#[derive(Clone, Copy, clap::ValueEnum)]
enum Corner {
    UpperLeft,
    UpperRight,
    LowerLeft,
    LowerRight,
}

/// Distinct, saturated colours for the data series (Tableau 10), so a
/// few series per chart stay apart; guides are grey.
const COLOURS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// One row of the CSV.
struct Point {
    x: f64,
    y: f64,
    label: Option<String>,
}

/// The points of one series, in file order.
struct Series {
    name: String,
    points: Vec<Point>,
}

fn main() {
    let args = Args::parse();
    if let Err(error) = run(&args) {
        eprintln!("error: {error}");
        std::process::exit(2);
    }
}

fn run(args: &Args) -> Result<(), Box<dyn Error>> {
    let text = std::fs::read_to_string(&args.data)
        .map_err(|e| format!("cannot read `{}`: {e}", args.data.display()))?;
    let mut series = parse_csv(&text)?;
    let dropped = drop_unplottable(&mut series, args.log_x, args.log_y);
    if dropped > 0 {
        eprintln!("warning: left out {dropped} points with a value ≤ 0 on a log axis");
    }
    let (x, y) = extent(&series).ok_or("expected at least one point to plot, found none")?;
    plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
        .map_err(|_| "the bundled font does not parse")?;
    let (width, height) = args.size;
    let mut rgb = vec![255u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (width, height)).into_drawing_area();
        root.fill(&WHITE)?;
        let (x, y) = (pad(x, args.log_x), pad(y, args.log_y));
        match (args.log_x, args.log_y) {
            (false, false) => draw(&root, args, &series, x, y)?,
            (true, false) => draw(&root, args, &series, x.log_scale(), y)?,
            (false, true) => draw(&root, args, &series, x, y.log_scale())?,
            (true, true) => draw(&root, args, &series, x.log_scale(), y.log_scale())?,
        }
        root.present()?;
    }
    write_png(&args.out, width, height, rgb)
}

/// Draw the chart on `root` with the given axis coordinates.
fn draw<X, Y>(
    root: &DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>,
    args: &Args,
    series: &[Series],
    x: X,
    y: Y,
) -> Result<(), Box<dyn Error>>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let mut chart = ChartBuilder::on(root)
        .caption(&args.title, ("sans-serif", 24))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(x, y)?;
    chart
        .configure_mesh()
        .x_desc(&args.x_label)
        .y_desc(&args.y_label)
        .x_labels(12)
        .y_labels(12)
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .light_line_style(WHITE)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()?;
    let mut data_index = 0;
    for s in series {
        let xy: Vec<(f64, f64)> = s.points.iter().map(|p| (p.x, p.y)).collect();
        if args.guide.contains(&s.name) {
            let grey = RGBColor(150, 150, 150);
            chart
                .draw_series(LineSeries::new(xy, grey.stroke_width(1)))?
                .label(s.name.as_str())
                .legend(move |(x, y)| PathElement::new([(x - 8, y), (x + 8, y)], grey));
            continue;
        }
        let color = COLOURS[data_index % COLOURS.len()].to_rgba();
        data_index += 1;
        if args.lines {
            chart.draw_series(LineSeries::new(xy.clone(), color.stroke_width(2)))?;
        }
        chart
            .draw_series(
                xy.iter()
                    .map(|&point| Circle::new(point, 4, color.filled())),
            )?
            .label(s.name.as_str())
            .legend(move |(x, y)| Circle::new((x, y), 4, color.filled()));
        chart.draw_series(s.points.iter().filter_map(|p| {
            let label = p.label.as_deref()?;
            Some(Text::new(
                label.to_string(),
                (p.x, p.y),
                ("sans-serif", 12).into_font().color(&BLACK),
            ))
        }))?;
    }
    let position = match args.legend {
        Corner::UpperLeft => SeriesLabelPosition::UpperLeft,
        Corner::UpperRight => SeriesLabelPosition::UpperRight,
        Corner::LowerLeft => SeriesLabelPosition::LowerLeft,
        Corner::LowerRight => SeriesLabelPosition::LowerRight,
    };
    chart
        .configure_series_labels()
        .position(position)
        .label_font(("sans-serif", 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    Ok(())
}

/// Parse the CSV into series in order of first appearance.
fn parse_csv(text: &str) -> Result<Vec<Series>, String> {
    let mut series: Vec<Series> = Vec::new();
    for (number, line) in text.lines().enumerate().skip(1) {
        if line.trim().is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if !(3..=4).contains(&fields.len()) {
            return Err(format!(
                "line {}: expected `series,x,y[,label]`, found {} fields",
                number + 1,
                fields.len()
            ));
        }
        let number_at = |i: usize| {
            fields[i]
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    format!(
                        "line {}: expected a finite number, found `{}`",
                        number + 1,
                        fields[i]
                    )
                })
        };
        let point = Point {
            x: number_at(1)?,
            y: number_at(2)?,
            label: fields
                .get(3)
                .filter(|l| !l.is_empty())
                .map(|l| l.to_string()),
        };
        match series.iter_mut().find(|s| s.name == fields[0]) {
            Some(s) => s.points.push(point),
            None => series.push(Series {
                name: fields[0].to_string(),
                points: vec![point],
            }),
        }
    }
    Ok(series)
}

/// Remove points a log axis cannot show; return how many.
fn drop_unplottable(series: &mut [Series], log_x: bool, log_y: bool) -> usize {
    let mut dropped = 0;
    for s in series {
        let before = s.points.len();
        s.points
            .retain(|p| (!log_x || p.x > 0.0) && (!log_y || p.y > 0.0));
        dropped += before - s.points.len();
    }
    dropped
}

/// The ranges of x and y over every point.
fn extent(series: &[Series]) -> Option<(Range<f64>, Range<f64>)> {
    let mut points = series.iter().flat_map(|s| &s.points);
    let first = points.next()?;
    let (mut x, mut y) = (first.x..first.x, first.y..first.y);
    for p in points {
        x = x.start.min(p.x)..x.end.max(p.x);
        y = y.start.min(p.y)..y.end.max(p.y);
    }
    Some((x, y))
}

/// Widen a range by a margin so points do not sit on the frame: a factor
/// on a log axis, a share of the span on a linear one.
fn pad(range: Range<f64>, log: bool) -> Range<f64> {
    if log {
        return range.start / 1.5..range.end * 1.5;
    }
    let span = range.end - range.start;
    let margin = if span > 0.0 {
        span * 0.08
    } else {
        range.start.abs().max(1.0) * 0.1
    };
    range.start - margin..range.end + margin
}

/// Encode and write the PNG: a temporary file beside `out`, then a rename.
fn write_png(out: &Path, width: u32, height: u32, rgb: Vec<u8>) -> Result<(), Box<dyn Error>> {
    let image =
        image::RgbImage::from_raw(width, height, rgb).ok_or("image buffer size mismatch")?;
    let mut temporary = out.as_os_str().to_owned();
    temporary.push(".partial");
    let temporary = PathBuf::from(temporary);
    let written = image
        .save_with_format(&temporary, image::ImageFormat::Png)
        .map_err(Box::<dyn Error>::from)
        .and_then(|()| std::fs::rename(&temporary, out).map_err(Box::<dyn Error>::from));
    if written.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    written
}

/// A tick label: three significant digits, in exponent form outside
/// [0.001, 10000).
fn tick(value: &f64) -> String {
    let v = *value;
    if v == 0.0 {
        return "0".to_string();
    }
    let rounded: f64 = format!("{v:.2e}").parse().unwrap_or(v);
    if (1e-3..1e4).contains(&rounded.abs()) {
        format!("{rounded}")
    } else {
        format!("{rounded:e}")
    }
}

fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once('x')
        .ok_or_else(|| format!("expected `WIDTHxHEIGHT`, found `{text}`"))?;
    let dimension = |s: &str| {
        s.parse::<u32>()
            .ok()
            .filter(|&v| (64..=8192).contains(&v))
            .ok_or_else(|| format!("expected a size from 64 to 8192, found `{s}`"))
    };
    Ok((dimension(w)?, dimension(h)?))
}
