//! Adaptive antialiasing (`render --aa adaptive`): the same image for any
//! number of threads, the uniform image where every pixel is refined, only
//! the shared corner samples (one per pixel, about) where the image is
//! flat, and never more than `spp` samples of a pixel's own.

use crate::support;

use std::path::Path;

use crate::support::{lower, lower_in, run};
use raytracer_render::render::Precision;
use raytracer_render::render::{
    adaptive::DEFAULT_THRESHOLD, render, render_radiance, Antialias, Counters, Image, Options,
};

const SPP: u32 = 16;

fn adaptive(threshold: f64) -> Options {
    Options {
        spp: SPP,
        antialias: Antialias::Adaptive { threshold },
        ..Options::default()
    }
}

/// The scenes of `scenes/` (textures and all) at a small size.
fn scenes() -> Vec<(String, raytracer_render::ir::Scene)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut scenes: Vec<_> = std::fs::read_dir(&root)
        .expect("scenes/")
        .map(|entry| entry.expect("entry").path())
        .filter(|path| path.extension().is_some_and(|e| e == "txt"))
        .map(|path| {
            let text = std::fs::read_to_string(&path).expect("read scene");
            let name = path.display().to_string();
            (name, lower_in(&text, &root, Some(48)))
        })
        .collect();
    scenes.sort_by(|a, b| a.0.cmp(&b.0));
    assert!(scenes.len() >= 5, "scenes/ lost its scenes");
    scenes
}

fn in_pool<T: Send>(threads: usize, work: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool")
        .install(work)
}

#[test]
fn adaptive_images_are_the_same_for_any_thread_count() {
    for (name, scene) in scenes() {
        let options = adaptive(DEFAULT_THRESHOLD);
        let one = in_pool(1, || render(Precision::F64, &scene, &options, &|| {}));
        let three = in_pool(3, || render(Precision::F64, &scene, &options, &|| {}));
        assert!(one.0 == three.0, "{name}: the image depends on threads");
        assert_eq!(one.1, three.1, "{name}: the counts depend on threads");
    }
}

#[test]
fn refining_every_pixel_gives_the_uniform_image_bit_for_bit() {
    let uniform = Options {
        spp: SPP,
        ..Options::default()
    };
    for (name, scene) in scenes() {
        let (all, all_counters) = render_radiance(Precision::F64, &scene, &adaptive(0.0), &|| {});
        let (same, counters) = render_radiance(Precision::F64, &scene, &uniform, &|| {});
        assert!(all == same, "{name}: refined radiance differs from uniform");
        let pixels = u64::from(scene.resolution).pow(2);
        assert_eq!(all_counters.pixels_refined, pixels, "{name}");
        assert_eq!(
            all_counters.primary_rays,
            counters.primary_rays + corners(scene.resolution),
            "{name}: the corners and every pixel's samples"
        );
        assert!(
            render(Precision::F32, &scene, &adaptive(0.0), &|| {}).0
                == render(Precision::F32, &scene, &uniform, &|| {}).0,
            "{name}: f32 differs"
        );
    }
}

/// The corner samples of a `size`² frame, shared by the pixels.
fn corners(size: u32) -> u64 {
    u64::from(size + 1).pow(2)
}

/// A pixel's own samples never exceed `spp`: unrefined pixels take none
/// beyond the shared corners, partly refined ones 4, refined ones `spp`,
/// and nothing else casts a camera ray.
fn assert_samples_bounded(name: &str, size: u32, counters: &Counters) {
    let pixels = u64::from(size).pow(2);
    assert!(
        counters.pixels_refined + counters.pixels_partly_refined <= pixels,
        "{name}"
    );
    assert_eq!(
        counters.primary_rays,
        corners(size)
            + counters.pixels_partly_refined * 4
            + counters.pixels_refined * u64::from(SPP),
        "{name}: samples are not the corners plus the refined pixels' own"
    );
    assert!(
        counters.primary_rays <= corners(size) + pixels * u64::from(SPP),
        "{name}"
    );
}

#[test]
fn adaptive_never_takes_more_than_spp_samples() {
    let mut refined_some = false;
    for (name, scene) in scenes() {
        for threshold in [0.0, 0.25, 1.0, DEFAULT_THRESHOLD, 64.0] {
            let (_, counters) = render(Precision::F64, &scene, &adaptive(threshold), &|| {});
            assert_samples_bounded(&name, scene.resolution, &counters);
            let pixels = u64::from(scene.resolution).pow(2);
            refined_some |= (1..pixels).contains(&counters.pixels_refined);
        }
    }
    assert!(refined_some, "no render refined some but not all pixels");
}

/// The camera inside a large ambient-lit sphere: every pixel sees the
/// same colour.
const FLAT: &str = "camera 32\nsphere dimension 50 center 0 0 0 color .5 .3 .2\n";

#[test]
fn a_flat_image_takes_only_its_corner_samples() {
    let scene = lower(FLAT);
    let (image, counters) = render(Precision::F64, &scene, &adaptive(DEFAULT_THRESHOLD), &|| {});
    assert_eq!(counters.pixels_refined, 0);
    assert_eq!(counters.pixels_partly_refined, 0);
    assert_eq!(counters.primary_rays, corners(32));
    let (one, _) = render(Precision::F64, &scene, &Options::default(), &|| {});
    assert!(image == one, "a flat image is its 1-spp image");
}

/// A ball of radius 1 at (0, 0, −6) in front of [`FLAT`]'s wall: ambient
/// light only, so the ball is one flat colour and the wall another.
const BALL: &str = "sphere dimension 1 center 0 0 -6 color 1 1 1\n";

/// Whether the ray through corner (x, y) of a `size`² frame hits
/// [`BALL`], from docs/rendering.md's camera: the ray towards
/// (−0.5 + x/N, 0.5 − y/N, −1) passes the centre c at distance
/// √(|c|² − (c·d)²) for the unit direction d. Panics for a ray within
/// 1e-9 of tangent, which rounding could send either way.
fn corner_hits_ball(size: u32, (x, y): (u32, u32)) -> bool {
    let n = f64::from(size);
    let d = glam::DVec3::new(-0.5 + f64::from(x) / n, 0.5 - f64::from(y) / n, -1.0).normalize();
    let centre = glam::DVec3::new(0.0, 0.0, -6.0);
    let miss_distance = centre.length_squared() - centre.dot(d).powi(2);
    assert!(
        (miss_distance - 1.0).abs() > 1e-9,
        "corner ({x}, {y}) is tangent"
    );
    miss_distance < 1.0
}

/// The pixels of a `size`² frame whose four corners are not all on the
/// ball nor all off it: the pixels adaptive sampling must refine when the
/// image is two flat colours, and the only ones it may.
fn pixels_on_the_ball_edge(size: u32) -> u64 {
    let pixels = (0..size).flat_map(|j| (0..size).map(move |i| (i, j)));
    pixels
        .filter(|&(i, j)| {
            let hits = [(i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)]
                .map(|corner| corner_hits_ball(size, corner));
            hits.contains(&true) && hits.contains(&false)
        })
        .count() as u64
}

#[test]
fn only_pixels_the_edge_crosses_are_refined() {
    // A small ball inside the flat sphere: its silhouette has contrast.
    let scene = lower(&format!("{FLAT}{BALL}"));
    let (image, counters) = render(Precision::F64, &scene, &adaptive(DEFAULT_THRESHOLD), &|| {});
    assert_samples_bounded("ball", 32, &counters);
    // A pixel whose corners straddle the silhouette disagrees and bends
    // (two flat colours: its step differs from both sides' flat steps).
    let refined = counters.pixels_refined + counters.pixels_partly_refined;
    let edge = pixels_on_the_ball_edge(32);
    assert!(
        edge > 20,
        "the ball's rim crosses more than a few pixels: {edge}"
    );
    assert_eq!(refined, edge, "{counters:?}");
    let Image { rgb, .. } = image;
    let corner = &rgb[..3];
    assert_eq!(corner, [13, 8, 5], "the flat wall keeps its 1-spp value");
}

#[test]
fn the_cli_reports_adaptive_samples() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = support::write(dir.path(), "ball.txt", format!("{FLAT}{BALL}"));
    let out = dir.path().join("out.ppm");
    let json = dir.path().join("stats.json");
    let output = run(&[
        "render",
        &scene,
        out.to_str().unwrap(),
        "--spp",
        "16",
        "--aa",
        "adaptive",
        "--stats",
        "--stats-json",
        json.to_str().unwrap(),
    ]);
    assert!(output.status.success());
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(json).expect("stats")).expect("JSON");
    let refined = stats["pixels_refined"].as_u64().expect("pixels_refined");
    let partly = stats["pixels_partly_refined"]
        .as_u64()
        .expect("pixels_partly_refined");
    assert_eq!(refined + partly, pixels_on_the_ball_edge(32));
    assert_eq!(stats["primary_rays"], 33 * 33 + partly * 4 + refined * 16);
    assert_eq!(stats["antialias"], "adaptive");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains(&format!(
            "adaptive: of 1024 pixels {refined} took 16 samples, {partly} took 4, the rest only their corners"
        )),
        "{stderr}"
    );
}
