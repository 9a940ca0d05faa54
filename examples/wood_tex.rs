//! Writes the procedural wood texture the sample scene and the course's
//! scenes name (`wood_tex.ppm`): growth rings around an off-centre axis,
//! bent by smooth value noise, with a fine grain along the fibres.
//!
//! `cargo run --example wood_tex -- scenes/wood_tex.ppm [SIZE]` (default
//! 256). The output is deterministic: the same bytes on every machine.

use std::io::Write;

fn main() -> std::io::Result<()> {
    let mut args = std::env::args().skip(1);
    let path = args.next().unwrap_or_else(|| "wood_tex.ppm".to_string());
    let size: u32 = args.next().and_then(|s| s.parse().ok()).unwrap_or(256);
    let mut bytes = format!("P6\n{size} {size}\n255\n").into_bytes();
    for y in 0..size {
        for x in 0..size {
            let (u, v) = (
                f64::from(x) / f64::from(size),
                f64::from(y) / f64::from(size),
            );
            bytes.extend(wood(u, v).map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8));
        }
    }
    std::fs::File::create(&path)?.write_all(&bytes)
}

/// The wood colour at texture coordinates (u, v) in [0, 1).
fn wood(u: f64, v: f64) -> [f64; 3] {
    let (light, dark) = ([0.80, 0.58, 0.34], [0.48, 0.28, 0.13]);
    // Rings: distance from an axis below the board, stretched along u so
    // the rings run lengthwise, bent by noise.
    let (dx, dy) = ((u - 0.5) * 0.35, v + 0.6);
    let radius = (dx * dx + dy * dy).sqrt() + 0.06 * noise(u * 4.0, v * 4.0);
    let ring = (radius * 14.0).fract();
    // Sharp late-wood edge: mostly light, a short dark band.
    let t = smoothstep(0.55, 0.95, ring) * (1.0 - smoothstep(0.95, 1.0, ring));
    let grain = 0.06 * noise(u * 3.0, v * 90.0);
    let mix = (t + grain).clamp(0.0, 1.0);
    [0, 1, 2].map(|i| light[i] + (dark[i] - light[i]) * mix)
}

fn smoothstep(a: f64, b: f64, x: f64) -> f64 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Smooth value noise in [−1, 1] from a hashed integer lattice.
fn noise(x: f64, y: f64) -> f64 {
    let (xi, yi) = (x.floor(), y.floor());
    let (fx, fy) = (smoothstep(0.0, 1.0, x - xi), smoothstep(0.0, 1.0, y - yi));
    let at = |dx: f64, dy: f64| lattice((xi + dx) as i64, (yi + dy) as i64);
    let top = at(0.0, 0.0) + (at(1.0, 0.0) - at(0.0, 0.0)) * fx;
    let bottom = at(0.0, 1.0) + (at(1.0, 1.0) - at(0.0, 1.0)) * fx;
    top + (bottom - top) * fy
}

/// A value in [−1, 1] for a lattice point (SplitMix64 finaliser).
fn lattice(x: i64, y: i64) -> f64 {
    let mut z = (x as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ (y as u64).rotate_left(32);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}
