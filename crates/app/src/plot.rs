//! Charts for the measured figures in docs/: a few series of points drawn
//! as a PNG scatter or line chart (error against samples per pixel, error
//! against time, render time against scene size).
//!
//! Data comes as CSV text with a header line, then rows
//! `series,x,y[,label]`: one coloured series per distinct `series` (in
//! order of first appearance), a point at (`x`, `y`), and an optional
//! `label` written beside the point. Fields are split on commas; there is
//! no quoting. Each data series has its own colour, marker and line dash,
//! the first a hollow ring that a later series' marker on the same point
//! leaves visible. A series the chart names as a guide is a reference line
//! (thin, grey, each guide its own dash, no markers), not data. On a log
//! axis, points with a value ≤ 0 cannot be drawn: they are left out, and
//! [`Drawn::left_out`] counts them. Log-axis ticks are placed by [`log_ticks`] across
//! the data's whole range, so a log axis spanning less than a power of ten
//! is still labelled.
//!
//! Text is drawn with DejaVu Sans, bundled from docs/fonts/ (Debian's
//! fonts-dejavu-core; licence beside it), so a chart does not depend on
//! the fonts of the machine that draws it.

use std::ops::Range;

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;
use plotters::style::FontStyle;

/// Bundled so every machine draws the same glyphs.
const FONT: &[u8] = include_bytes!("../../../docs/fonts/DejaVuSans.ttf");

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

/// How to draw a chart.
#[derive(Clone, Debug)]
pub struct Chart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub log_x: bool,
    pub log_y: bool,
    /// Join each series' points in file order.
    pub lines: bool,
    /// Width and height in pixels.
    pub size: (u32, u32),
    /// Series drawn as thin grey guide lines without markers.
    pub guides: Vec<String>,
    /// Where the legend goes (where the data is not).
    pub legend: Corner,
}

/// A corner of the plot area.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Corner {
    UpperLeft,
    UpperRight,
    LowerLeft,
    LowerRight,
}

/// One row of the CSV.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    pub x: f64,
    pub y: f64,
    pub label: Option<String>,
}

/// The points of one series, in file order.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub name: String,
    pub points: Vec<Point>,
}

/// Why a chart could not be drawn.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum PlotError {
    /// A CSV row is not `series,x,y[,label]`.
    #[error("line {line}: expected `series,x,y[,label]`, found {found} fields")]
    Fields { line: usize, found: usize },
    /// A coordinate is not a finite number.
    #[error("line {line}: expected a finite number, found `{found}`")]
    Number { line: usize, found: String },
    /// Nothing is left to draw.
    #[error("expected at least one point to plot, found none")]
    Empty,
    /// plotters or the PNG encoder failed.
    #[error("cannot draw the chart: {0}")]
    Draw(String),
}

/// A drawn chart: its PNG file and the points a log axis could not show.
#[derive(Debug)]
pub struct Drawn {
    pub png: Vec<u8>,
    pub left_out: usize,
}

/// Parse CSV text into series in order of first appearance.
pub fn parse_csv(text: &str) -> Result<Vec<Series>, PlotError> {
    let mut series: Vec<Series> = Vec::new();
    for (index, row) in text.lines().enumerate().skip(1) {
        let line = index + 1;
        if row.trim().is_empty() {
            continue;
        }
        let fields: Vec<&str> = row.split(',').map(str::trim).collect();
        if !(3..=4).contains(&fields.len()) {
            return Err(PlotError::Fields {
                line,
                found: fields.len(),
            });
        }
        let number_at = |i: usize| {
            fields[i]
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| PlotError::Number {
                    line,
                    found: fields[i].to_string(),
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

/// Draw `series` as `chart` says, to a PNG file's bytes.
pub fn draw(chart: &Chart, mut series: Vec<Series>) -> Result<Drawn, PlotError> {
    let left_out = drop_unplottable(&mut series, chart.log_x, chart.log_y);
    let (x, y) = extent(&series).ok_or(PlotError::Empty)?;
    plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
        .map_err(|_| PlotError::Draw("the bundled font does not parse".into()))?;
    let (width, height) = chart.size;
    let mut rgb = vec![255u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let (x, y) = (pad(x, chart.log_x), pad(y, chart.log_y));
        // A log axis is labelled at [`log_ticks`]; a linear one where
        // plotters' own choice of round steps puts its labels.
        match (chart.log_x, chart.log_y) {
            (false, false) => draw_on(&root, chart, &series, x, y)?,
            (true, false) => {
                let x_ticks = log_ticks(&x);
                draw_on(
                    &root,
                    chart,
                    &series,
                    x.log_scale().with_key_points(x_ticks),
                    y,
                )?
            }
            (false, true) => {
                let y_ticks = log_ticks(&y);
                draw_on(
                    &root,
                    chart,
                    &series,
                    x,
                    y.log_scale().with_key_points(y_ticks),
                )?
            }
            (true, true) => {
                let (x_ticks, y_ticks) = (log_ticks(&x), log_ticks(&y));
                draw_on(
                    &root,
                    chart,
                    &series,
                    x.log_scale().with_key_points(x_ticks),
                    y.log_scale().with_key_points(y_ticks),
                )?
            }
        }
        root.present().map_err(drawing)?;
    }
    let image = image::RgbImage::from_raw(width, height, rgb)
        .ok_or_else(|| PlotError::Draw("image buffer size mismatch".into()))?;
    let mut png = Vec::new();
    image
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .map_err(drawing)?;
    Ok(Drawn { png, left_out })
}

fn drawing(error: impl std::fmt::Display) -> PlotError {
    PlotError::Draw(error.to_string())
}

/// Draw the chart on `root` with the given axis coordinates.
fn draw_on<X, Y>(
    root: &DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>,
    chart: &Chart,
    series: &[Series],
    x: X,
    y: Y,
) -> Result<(), PlotError>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let mut context = ChartBuilder::on(root)
        .caption(&chart.title, ("sans-serif", 24))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(x, y)
        .map_err(drawing)?;
    context
        .configure_mesh()
        .x_desc(&chart.x_label)
        .y_desc(&chart.y_label)
        .x_labels(12)
        .y_labels(12)
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .light_line_style(WHITE)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()
        .map_err(drawing)?;
    let mut data_index = 0;
    for s in series {
        let xy: Vec<(f64, f64)> = s.points.iter().map(|p| (p.x, p.y)).collect();
        if let Some(guide) = chart.guides.iter().position(|g| *g == s.name) {
            let grey = RGBColor(130, 130, 130).stroke_width(1 + (guide % 3 == 2) as u32);
            let (dash, gap) = [(0, 0), (8, 5), (2, 4)][guide % 3];
            let line = if dash == 0 {
                context.draw_series(LineSeries::new(xy, grey))
            } else {
                context.draw_series(DashedLineSeries::new(xy, dash, gap, grey))
            };
            line.map_err(drawing)?
                .label(s.name.as_str())
                .legend(move |(x, y)| {
                    let ends = [(x - 10, y), (x + 10, y)];
                    PathElement::new(ends, grey)
                });
            continue;
        }
        let style = data_index % 4;
        let color = COLOURS[data_index % COLOURS.len()].to_rgba();
        data_index += 1;
        if chart.lines {
            let stroke = color.stroke_width(2);
            match style {
                0 => context.draw_series(LineSeries::new(xy.clone(), stroke)),
                1 => context.draw_series(DashedLineSeries::new(xy.clone(), 8, 5, stroke)),
                2 => context.draw_series(DashedLineSeries::new(xy.clone(), 2, 4, stroke)),
                _ => context.draw_series(LineSeries::new(xy.clone(), color.stroke_width(1))),
            }
            .map_err(drawing)?;
        }
        // Markers in turn: a hollow ring, a filled triangle, a cross, a
        // hollow square.
        let outline = color.stroke_width(2);
        let square = |at| EmptyElement::at(at) + Rectangle::new([(-4, -4), (4, 4)], outline);
        let points = xy.iter().copied();
        let markers = match style {
            0 => context.draw_series(points.map(|at| Circle::new(at, 6, outline))),
            1 => context.draw_series(points.map(|at| TriangleMarker::new(at, 5, color.filled()))),
            2 => context.draw_series(points.map(|at| Cross::new(at, 5, outline))),
            _ => context.draw_series(points.map(square)),
        }
        .map_err(drawing)?
        .label(s.name.as_str());
        match style {
            0 => markers.legend(move |at| Circle::new(at, 6, outline)),
            1 => markers.legend(move |at| TriangleMarker::new(at, 5, color.filled())),
            2 => markers.legend(move |at| Cross::new(at, 5, outline)),
            _ => markers.legend(move |at| {
                EmptyElement::at(at) + Rectangle::new([(-4, -4), (4, 4)], outline)
            }),
        };
        context
            .draw_series(s.points.iter().filter_map(|p| {
                let label = p.label.as_deref()?;
                Some(Text::new(
                    label.to_string(),
                    (p.x, p.y),
                    ("sans-serif", 12).into_font().color(&BLACK),
                ))
            }))
            .map_err(drawing)?;
    }
    let position = match chart.legend {
        Corner::UpperLeft => SeriesLabelPosition::UpperLeft,
        Corner::UpperRight => SeriesLabelPosition::UpperRight,
        Corner::LowerLeft => SeriesLabelPosition::LowerLeft,
        Corner::LowerRight => SeriesLabelPosition::LowerRight,
    };
    context
        .configure_series_labels()
        .position(position)
        .label_font(("sans-serif", 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(drawing)?;
    Ok(())
}

/// Where a log axis over `range` is labelled: 1, 2 and 5 times each power
/// of ten inside it, or every whole multiple 1–9 when that gives fewer
/// than four ticks (an axis spanning less than a decade, where powers of
/// ten alone would label nothing). Each tick has one significant digit, so
/// no two print alike.
fn log_ticks(range: &Range<f64>) -> Vec<f64> {
    let (low, high) = (range.start, range.end);
    let decades = low.log10().floor() as i32..=high.log10().ceil() as i32;
    let within = |multiples: &[f64]| -> Vec<f64> {
        decades
            .clone()
            .flat_map(|e| multiples.iter().map(move |m| m * 10f64.powi(e)))
            .filter(|v| (low..=high).contains(v))
            .collect()
    };
    let coarse = within(&[1.0, 2.0, 5.0]);
    if coarse.len() >= 4 {
        return coarse;
    }
    within(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0])
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

#[cfg(test)]
mod tests {
    use super::*;

    fn chart(log: bool) -> Chart {
        Chart {
            title: "t".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            log_x: log,
            log_y: log,
            lines: true,
            size: (200, 120),
            guides: vec!["guide".into()],
            legend: Corner::LowerLeft,
        }
    }

    #[test]
    fn rows_group_into_series_in_order_of_appearance() {
        let series = parse_csv("series,x,y\nb,1,2,one\na,3,4\nb,5,6\n").unwrap();
        let names: Vec<_> = series.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["b", "a"]);
        assert_eq!(series[0].points[0].label.as_deref(), Some("one"));
        assert_eq!(series[0].points[1].x, 5.0);
    }

    #[test]
    fn bad_rows_name_their_line() {
        assert_eq!(
            parse_csv("h\na,1\n"),
            Err(PlotError::Fields { line: 2, found: 2 })
        );
        assert_eq!(
            parse_csv("h\na,1,2\na,inf,2\n"),
            Err(PlotError::Number {
                line: 3,
                found: "inf".into()
            })
        );
    }

    #[test]
    fn log_ticks_label_the_whole_range_of_the_data() {
        let labels = |range| log_ticks(&range).iter().map(tick).collect::<Vec<_>>();
        // Inside one decade, where powers of ten label nothing and 1, 2, 5
        // too little: every multiple.
        assert_eq!(labels(0.25..0.75), ["0.3", "0.4", "0.5", "0.6", "0.7"]);
        // Over decades: 1, 2, 5 of each, each printed differently.
        assert_eq!(labels(0.8..130.0), ["1", "2", "5", "10", "20", "50", "100"]);
        assert_eq!(labels(0.04..0.7), ["0.05", "0.1", "0.2", "0.5"]);
    }

    #[test]
    fn a_chart_is_a_png_of_its_size_with_log_axes_dropping_zeros() {
        let series =
            parse_csv("h\ndata,1,1\ndata,10,0\ndata,100,0.1\nguide,1,1\nguide,100,0.01\n").unwrap();
        let drawn = draw(&chart(true), series).unwrap();
        assert_eq!(drawn.left_out, 1);
        let image = image::load_from_memory(&drawn.png).unwrap();
        assert_eq!((image.width(), image.height()), (200, 120));
        let empty = parse_csv("h\ndata,1,0\n").unwrap();
        assert_eq!(draw(&chart(true), empty).unwrap_err(), PlotError::Empty);
        assert!(draw(&chart(false), parse_csv("h\nd,0,0\n").unwrap()).is_ok());
    }
}
