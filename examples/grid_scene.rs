//! Writes the benchmark scenes of docs/performance.md: COUNT reflective
//! spheres (radius 0.035) on a grid with spacing 0.08, 100×100 per layer
//! centred on the view axis, layers 0.5 apart going away from z = −8, plus
//! the plane and light of scenes/sample.txt (whose texture, `wood_tex.ppm`,
//! must sit beside the output). Fewer than 10,000 spheres fill a centred
//! square of one layer row by row.
//!
//! `cargo run --release --example grid_scene -- COUNT OUT [RESOLUTION]`
//! (default resolution 1000). The output is deterministic.

use std::fmt::Write as _;

/// Spheres per row and per column of a full layer.
const SIDE: usize = 100;
const SPACING: f64 = 0.08;
const RADIUS: f64 = 0.035;
const FIRST_LAYER_Z: f64 = -8.0;
const LAYER_GAP: f64 = 0.5;

fn main() -> Result<(), String> {
    let usage = "usage: grid_scene COUNT OUT [RESOLUTION]";
    let mut args = std::env::args().skip(1);
    let count: usize = args
        .next()
        .and_then(|s| s.parse().ok())
        .ok_or_else(|| usage.to_string())?;
    let out = args.next().ok_or_else(|| usage.to_string())?;
    let resolution: u32 = match args.next() {
        Some(s) => s
            .parse()
            .map_err(|_| format!("expected a resolution, found `{s}`"))?,
        None => 1000,
    };
    let text = scene(count, resolution);
    std::fs::write(&out, text).map_err(|e| format!("cannot write `{out}`: {e}"))
}

/// The scene text with `count` spheres.
fn scene(count: usize, resolution: u32) -> String {
    let mut text = format!(
        "camera {resolution}\n\n\
         plane\n  dimension 4 4\n  center 0 -1 -5\n  normal 0 1 0\n  headup 0 0 1\n  texture wood_tex.ppm\n\n\
         light\n  location -1 2 -2\n  color 1 .7 .7\n"
    );
    // Columns and rows actually used: the full layer, or a centred square.
    let side = SIDE.min((count as f64).sqrt().ceil() as usize).max(1);
    let per_layer = side * side;
    for n in 0..count {
        let layer = n / per_layer;
        let (row, column) = ((n % per_layer) / side, n % side);
        let centre = (side as f64 - 1.0) / 2.0;
        let x = (column as f64 - centre) * SPACING;
        let y = (centre - row as f64) * SPACING;
        let z = FIRST_LAYER_Z - LAYER_GAP * layer as f64;
        // A colour that varies smoothly across the layer.
        let (u, v) = (column as f64 / side as f64, row as f64 / side as f64);
        let color = [0.3 + 0.6 * u, 0.3 + 0.6 * v, 0.9 - 0.5 * u];
        let _ = write!(
            text,
            "\nsphere\n  dimension {RADIUS}\n  center {x:.4} {y:.4} {z}\n  reflectivity .5\n  color {:.3} {:.3} {:.3}\n",
            color[0], color[1], color[2]
        );
    }
    text
}
