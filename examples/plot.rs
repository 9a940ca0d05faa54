//! Draws a CSV of `series,x,y[,label]` rows as a PNG chart with the
//! charting the product uses for `raytracer accuracy --assets`
//! ([`raytracer_app::plot`]); `make bench-scaling` plots docs/scaling.png
//! with it.
//!
//! ```text
//! cargo run --release --example plot -- DATA.csv OUT.png \
//!     [--title TEXT] [--x-label TEXT] [--y-label TEXT] \
//!     [--log-x] [--log-y] [--lines] [--size WIDTHxHEIGHT] \
//!     [--guide SERIES]... [--legend upper-left|upper-right|lower-left|lower-right]
//! ```

use std::path::PathBuf;

use clap::Parser;
use raytracer_app::plot::{draw, parse_csv, Chart, Corner};

#[derive(Parser)]
#[command(about = "Plot `series,x,y[,label]` rows of a CSV file as a PNG chart")]
struct Args {
    /// Input CSV: a header, then `series,x,y[,label]` rows.
    data: PathBuf,
    /// Output PNG, written whole or not at all.
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
    #[arg(long, value_enum, default_value_t = Legend::UpperRight)]
    legend: Legend,
}

/// `--legend`'s values.
#[derive(Clone, Copy, clap::ValueEnum)]
enum Legend {
    UpperLeft,
    UpperRight,
    LowerLeft,
    LowerRight,
}

fn main() {
    let args = Args::parse();
    if let Err(error) = run(args) {
        eprintln!("error: {error}");
        std::process::exit(2);
    }
}

fn run(args: Args) -> Result<(), String> {
    let text = std::fs::read_to_string(&args.data)
        .map_err(|e| format!("cannot read `{}`: {e}", args.data.display()))?;
    let series = parse_csv(&text).map_err(|e| e.to_string())?;
    let chart = Chart {
        title: args.title,
        x_label: args.x_label,
        y_label: args.y_label,
        log_x: args.log_x,
        log_y: args.log_y,
        lines: args.lines,
        size: args.size,
        guides: args.guide,
        legend: match args.legend {
            Legend::UpperLeft => Corner::UpperLeft,
            Legend::UpperRight => Corner::UpperRight,
            Legend::LowerLeft => Corner::LowerLeft,
            Legend::LowerRight => Corner::LowerRight,
        },
    };
    let drawn = draw(&chart, series).map_err(|e| e.to_string())?;
    if drawn.left_out > 0 {
        eprintln!(
            "warning: left out {} points with a value ≤ 0 on a log axis",
            drawn.left_out
        );
    }
    raytracer_render::output::write_atomically(&args.out, |out| out.write_all(&drawn.png))
        .map_err(|e| format!("cannot write `{}`: {e}", args.out.display()))
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
