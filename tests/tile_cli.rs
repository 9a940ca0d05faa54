//! `render --tile K/N` and `stitch` end to end: tiles stitched in any order
//! are the whole render byte for byte, for several splits (one tile, two,
//! uneven bands, one row each), thread counts, `--spp` and `--precision`;
//! each tile's pixels are its region of the whole render; the tiles'
//! statistics sum to the whole render's; the scene hash is of the checked
//! scene (not its bytes) and sees a changed texture; and every way parts
//! can fail to make a frame is an exit code and a message naming the part.

use std::path::Path;
use std::process::Output;

use crate::support::{command, listing};
use serde_json::Value;

/// 29 rows: uneven bands for most N. A light, a mirror and a texture, so
/// shadow rays, reflections and texel reads all cross band edges.
const SCENE: &str = "camera 29
sphere dimension 1 center 0 .5 -4 reflectivity .6 color .4 .5 .6
plane dimension 6 6 center 0 -1 -4 normal 0 1 0 headup 0 0 1 texture tex.ppm
light location -1 2 0 color 1 .8 .8
";

/// A 2×2 texture.
const TEXTURE: &str = "P3 2 2 255\n255 0 0  0 255 0\n0 0 255  250 250 250\n";

/// A folder with `scene.txt` and its texture.
fn scene_dir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(dir.path().join("scene.txt"), SCENE).expect("write scene");
    std::fs::write(dir.path().join("tex.ppm"), TEXTURE).expect("write texture");
    dir
}

/// Run the binary in `dir` (so messages name files as given).
fn run_in(dir: &Path, args: &[&str]) -> Output {
    command(args)
        .current_dir(dir)
        .output()
        .expect("run raytracer")
}

fn ok(output: &Output) {
    assert!(
        output.status.success(),
        "exit {:?}:\n{}",
        output.status.code(),
        String::from_utf8_lossy(&output.stderr)
    );
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// Render `scene.txt` whole to `name` with `options`.
fn render_whole(dir: &Path, name: &str, options: &[&str]) {
    let mut args = vec!["render", "scene.txt", name, "--threads", "2"];
    args.extend(options);
    ok(&run_in(dir, &args));
}

/// Render every tile of `n` to `{prefix}{k}.png`, with `{prefix}{k}.json`
/// statistics, thread counts cycling through 1, 2 and 3.
fn render_tiles(dir: &Path, prefix: &str, n: u32, options: &[&str]) -> Vec<String> {
    (1..=n)
        .map(|k| {
            let part = format!("{prefix}{k}.png");
            let (band, stats, threads) = (
                format!("{k}/{n}"),
                format!("{prefix}{k}.json"),
                (k % 3 + 1).to_string(),
            );
            let mut args = vec![
                "render",
                "scene.txt",
                &part,
                "--tile",
                &band,
                "--threads",
                &threads,
                "--stats-json",
                &stats,
            ];
            args.extend(options);
            ok(&run_in(dir, &args));
            part
        })
        .collect()
}

/// `items` in a shuffled order (a fixed-seed linear congruential
/// generator, so a failure can be replayed).
fn shuffled<T>(mut items: Vec<T>, seed: u64) -> Vec<T> {
    let mut state = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
    for i in (1..items.len()).rev() {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        items.swap(i, (state >> 33) as usize % (i + 1));
    }
    items
}

/// The RGB bytes of a PNG or PPM file.
fn pixels(path: &Path) -> Vec<u8> {
    image::open(path)
        .expect("decode image")
        .to_rgb8()
        .into_raw()
}

fn stats(path: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(path).expect("read stats")).expect("stats JSON")
}

#[test]
fn tiles_stitched_in_any_order_are_the_whole_render() {
    let dir = scene_dir();
    let d = dir.path();
    let cases: [(u32, &[&str]); 9] = [
        (1, &[]),
        (2, &[]),
        (3, &["--spp", "4"]),
        (7, &[]),
        (7, &["--precision", "f32"]),
        (
            29,
            &["--spp", "4", "--precision", "f32", "--max-depth", "2"],
        ),
        (4, &["--no-skip", "--accel", "brute"]),
        // Adaptive sampling decides from each pixel's corners, the
        // band's bottom edge (the next band's top) included.
        (5, &["--spp", "16", "--aa", "adaptive"]),
        (
            29,
            &["--spp", "4", "--aa", "adaptive", "--aa-threshold", "1"],
        ),
    ];
    for (case, (n, options)) in cases.into_iter().enumerate() {
        let whole = format!("whole{case}.ppm");
        render_whole(d, &whole, options);
        let whole_rgb = pixels(&d.join(&whole));
        let prefix = format!("c{case}-");
        let parts = render_tiles(d, &prefix, n, options);

        // Each tile is its band of the whole render.
        for (k, part) in (1..=n).zip(&parts) {
            let rows = (k - 1) * 29 / n..k * 29 / n;
            let band = &whole_rgb[rows.start as usize * 29 * 3..rows.end as usize * 29 * 3];
            assert_eq!(pixels(&d.join(part)), band, "tile {k}/{n} {options:?}");
        }

        for (order, format) in [(1, "ppm"), (2, "png")] {
            let out = format!("stitched{case}-{order}.{format}");
            let mut args = vec!["stitch", out.as_str()];
            let order = shuffled(parts.clone(), 1000 * case as u64 + order);
            args.extend(order.iter().map(String::as_str));
            ok(&run_in(d, &args));
            if format == "ppm" {
                assert_eq!(
                    std::fs::read(d.join(&out)).unwrap(),
                    std::fs::read(d.join(&whole)).unwrap(),
                    "{n} tiles {options:?} in order {order:?}"
                );
            } else {
                assert_eq!(pixels(&d.join(&out)), whole_rgb, "{n} tiles {options:?}");
            }
        }
    }
    assert!(!listing(d).iter().any(|name| name.ends_with(".tmp")));
}

/// Every counter of `--stats-json` that stitching sums over the tiles.
const COUNTERS: [&str; 9] = [
    "primary_rays",
    "shadow_rays",
    "reflection_rays",
    "texture_lookups",
    "shadow_rays_skipped",
    "paths_saturated",
    "pixels_refined",
    "pixels_partly_refined",
    "non_finite",
];

#[test]
fn tile_statistics_sum_to_the_whole_render() {
    let dir = scene_dir();
    let d = dir.path();
    // Uniform, and adaptive: each tile traces its neighbours' corner rows
    // too, and counts only its own, so the sums are the whole render's.
    let cases: [(u32, &[&str]); 4] = [
        (3, &[]),
        (3, &["--spp", "16", "--aa", "adaptive"]),
        (29, &["--spp", "16", "--aa", "adaptive"]),
        (
            4,
            &["--spp", "4", "--aa", "adaptive", "--aa-threshold", "0"],
        ),
    ];
    for (case, (n, options)) in cases.into_iter().enumerate() {
        let whole_json = format!("whole{case}.json");
        let mut whole_args = vec!["--stats-json", whole_json.as_str()];
        whole_args.extend(options);
        render_whole(d, &format!("whole{case}.png"), &whole_args);
        let prefix = format!("s{case}-");
        let parts = render_tiles(d, &prefix, n, options);
        let json = |k: u32| format!("{prefix}{k}.json");

        let first = stats(&d.join(json(1)));
        let tile = &first["tile"];
        assert_eq!(tile["tile"], 1);
        assert_eq!(tile["tiles"], n);
        let whole = stats(&d.join(&whole_json));
        assert!(whole.get("tile").is_none());

        let total_json = format!("total{case}.json");
        let out = format!("out{case}.png");
        let mut args = vec![
            "stitch",
            out.as_str(),
            "--stats-json",
            total_json.as_str(),
            "--part-stats",
        ];
        // The statistics in reverse order: matched by their `tile`.
        let jsons: Vec<String> = (1..=n).rev().map(json).collect();
        args.extend(jsons.iter().map(String::as_str));
        args.push("--");
        args.extend(parts.iter().map(String::as_str));
        ok(&run_in(d, &args));
        let total = stats(&d.join(&total_json));
        for counter in COUNTERS {
            assert_eq!(
                total[counter], whole[counter],
                "{counter} {n} tiles {options:?}"
            );
        }
        assert_eq!(total["tiles"], n);
        let parts = total["parts"].as_array().unwrap();
        let order: Vec<&Value> = parts.iter().map(|p| &p["tile"]["tile"]).collect();
        let expected: Vec<u32> = (1..=n).collect();
        assert_eq!(order, expected, "top band first");
        let summed: f64 = parts
            .iter()
            .map(|p| p["seconds"]["render"].as_f64().unwrap())
            .sum();
        assert!((total["seconds"]["render"].as_f64().unwrap() - summed).abs() < 1e-9);
        assert_eq!(total["scene_hash"], first["tile"]["scene_hash"]);
    }

    // The counts themselves: uniform 1 spp is one camera ray a pixel; a
    // first tile of 9 rows counts its 9 own rows, and adaptive's first
    // tile its own 9 corner rows of 30 corners besides its pixels' own.
    assert_eq!(stats(&d.join("s0-1.json"))["primary_rays"], 29 * 9);
    let whole = stats(&d.join("whole0.json"));
    assert!(whole["shadow_rays"].as_u64().unwrap() > 0);
    assert!(whole["reflection_rays"].as_u64().unwrap() > 0);
    assert!(whole["texture_lookups"].as_u64().unwrap() > 0);
    let adaptive = stats(&d.join("whole1.json"));
    assert!(adaptive["pixels_refined"].as_u64().unwrap() > 0);
    let first = stats(&d.join("s1-1.json"));
    let own = |field: &str| first[field].as_u64().unwrap();
    assert_eq!(
        own("primary_rays"),
        30 * 9 + 4 * own("pixels_partly_refined") + 16 * own("pixels_refined"),
        "{first}"
    );
    // Threshold 0 refines every pixel: the whole frame's 30² corners and
    // all 4 samples of each of its 29² pixels, whatever the tiles.
    let all = stats(&d.join("total3.json"));
    assert_eq!(all["primary_rays"], 30 * 30 + 29 * 29 * 4);
}

#[test]
fn the_scene_hash_is_of_the_checked_scene_and_its_texels() {
    let dir = scene_dir();
    let d = dir.path();
    render_tiles(d, "a", 2, &[]);
    // The same scene, reformatted and commented: the same hash.
    let reformatted = format!("# the same scene\n\n{}", SCENE.replace(' ', "   "));
    std::fs::write(d.join("scene.txt"), reformatted).unwrap();
    render_tiles(d, "b", 2, &[]);
    ok(&run_in(d, &["stitch", "ab.png", "a1.png", "b2.png"]));
    // Another texture with the same name: another scene.
    std::fs::write(d.join("tex.ppm"), TEXTURE.replace("250", "10")).unwrap();
    render_tiles(d, "c", 2, &[]);
    let mixed = run_in(d, &["stitch", "ac.png", "a1.png", "c2.png"]);
    assert_eq!(mixed.status.code(), Some(1), "{}", stderr(&mixed));
    assert!(!d.join("ac.png").exists());
    // `--threads` and `--accel` are not options that change pixels.
    std::fs::write(d.join("tex.ppm"), TEXTURE).unwrap();
    ok(&run_in(
        d,
        &[
            "render",
            "scene.txt",
            "x1.png",
            "--tile",
            "1/2",
            "--accel",
            "bvh",
            "--threads",
            "3",
        ],
    ));
    ok(&run_in(d, &["stitch", "ax.png", "x1.png", "a2.png"]));
}

/// The exit code and stderr of `args` run in a folder holding tiles
/// `t1..t3.png` of 3 (and `again2.png`, a copy of `t2.png`), `s1.png` rendered with `--spp 4`, `u1.png` of
/// another scene, `h1.png` of 2 and `whole.png`.
fn failing(args: &[&str]) -> (Option<i32>, String) {
    let dir = scene_dir();
    let d = dir.path();
    render_tiles(d, "t", 3, &[]);
    render_tiles(d, "h", 2, &[]);
    ok(&run_in(
        d,
        &[
            "render",
            "scene.txt",
            "s1.png",
            "--tile",
            "1/3",
            "--spp",
            "4",
        ],
    ));
    render_whole(d, "whole.png", &[]);
    std::fs::copy(d.join("t2.png"), d.join("again2.png")).unwrap();
    std::fs::write(d.join("other.txt"), SCENE.replace(".6 color", ".5 color")).unwrap();
    ok(&run_in(
        d,
        &["render", "other.txt", "u1.png", "--tile", "1/3"],
    ));
    std::fs::write(d.join("notes.png"), "not an image").unwrap();
    let before = listing(d);
    let output = run_in(d, args);
    assert_eq!(listing(d), before, "a failing command writes nothing");
    (output.status.code(), stderr(&output))
}

/// `text` with every SHA-256 in hex replaced by `<sha256>`: the hashes
/// change with the scene model's serialisation, not with the message.
fn without_hashes(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(start) = rest.find(|c: char| c.is_ascii_hexdigit()) {
        let run = rest[start..]
            .find(|c: char| !c.is_ascii_hexdigit())
            .unwrap_or(rest.len() - start);
        out.push_str(&rest[..start]);
        let word = &rest[start..start + run];
        out.push_str(if run == 64 { "<sha256>" } else { word });
        rest = &rest[start + run..];
    }
    out + rest
}

fn snapshot(name: &str, (code, stderr): (Option<i32>, String)) {
    let stderr = without_hashes(&stderr);
    insta::with_settings!({
        snapshot_path => "snapshots",
        prepend_module_to_snapshot => false,
        omit_expression => true,
    }, {
        insta::assert_snapshot!(name, format!("exit {code:?}\n{stderr}"));
    });
}

#[test]
fn stitch_names_the_part_at_fault() {
    let cases: [(&str, &[&str]); 9] = [
        ("stitch-missing", &["t3.png", "t1.png"]),
        (
            "stitch-duplicate",
            &["t1.png", "t2.png", "t3.png", "again2.png"],
        ),
        (
            "stitch-named_twice",
            &["t1.png", "t2.png", "t3.png", "t2.png"],
        ),
        (
            "stitch-foreign_scene",
            &["t1.png", "t2.png", "t3.png", "u1.png"],
        ),
        ("stitch-other_options", &["s1.png", "t2.png", "t3.png"]),
        ("stitch-overlap", &["h1.png", "t2.png", "t3.png"]),
        (
            "stitch-not_a_tile",
            &["t1.png", "t2.png", "t3.png", "whole.png", "notes.png"],
        ),
        (
            "stitch-unreadable",
            &["t1.png", "t2.png", "t3.png", "gone.png"],
        ),
        (
            "stitch-stats_missing",
            &[
                "t1.png",
                "t2.png",
                "t3.png",
                "--stats-json",
                "all.json",
                "--part-stats",
                "t1.json",
                "t3.json",
                "h1.json",
            ],
        ),
    ];
    for (name, parts) in cases {
        let mut args = vec!["stitch", "out.png"];
        args.extend(parts);
        let result = failing(&args);
        let expected = if name == "stitch-unreadable" { 2 } else { 1 };
        assert_eq!(result.0, Some(expected), "{name}: {}", result.1);
        snapshot(name, result);
    }
}

#[test]
fn bad_tiles_are_usage_errors() {
    let dir = scene_dir();
    let d = dir.path();
    for band in ["0/3", "4/3", "x", "3", "1/0", "-1/3"] {
        let tile = format!("--tile={band}");
        let output = run_in(d, &["render", "scene.txt", "t.png", &tile]);
        assert_eq!(output.status.code(), Some(2), "{band}");
        assert!(
            stderr(&output).contains(&format!(
                "expected `K/N` with whole numbers 1 ≤ K ≤ N, found `{band}`"
            )),
            "{band}: {}",
            stderr(&output)
        );
    }
    snapshot(
        "render-too_many_tiles",
        failing(&["render", "scene.txt", "t.png", "--tile", "1/30"]),
    );
    ok(&run_in(
        d,
        &["render", "scene.txt", "t.png", "--tile", "29/29"],
    ));
    snapshot(
        "render-tile_not_png",
        failing(&["render", "scene.txt", "t.ppm", "--tile", "1/3"]),
    );
}

#[test]
fn forged_metadata_and_outputs_among_the_inputs_are_refused() {
    let dir = scene_dir();
    let d = dir.path();
    let parts = render_tiles(d, "t", 2, &[]);
    let info = raytracer_render::tile::file::read_info(&d.join(&parts[0])).expect("a tile");
    let forge = |name: &str, edit: &dyn Fn(&mut raytracer_render::tile::TileInfo)| {
        let mut forged = info.clone();
        edit(&mut forged);
        let rgb = vec![0u8; 29 * 14 * 3];
        let mut bytes = Vec::new();
        raytracer_render::tile::file::encode(&forged, &rgb, &mut bytes).expect("encode");
        std::fs::write(d.join(name), bytes).unwrap();
    };
    forge("huge.png", &|i| {
        i.width = 1 << 30;
        i.height = 1 << 30;
    });
    forge("zero.png", &|i| i.tiles = 0);
    forge("v2.png", &|i| i.version = 2);
    for (part, message) in [
        (
            "huge.png",
            "expected a square frame of 1 to 16384 pixels a side, found 1073741824×1073741824",
        ),
        (
            "zero.png",
            "`zero.png` claims rows 0..14 of a 29-row frame, which is not tile 1/0",
        ),
        ("v2.png", "expected tile format version 1, found 2"),
    ] {
        let output = run_in(d, &["stitch", "out.png", part, &parts[1]]);
        assert_eq!(output.status.code(), Some(1), "{part}: {}", stderr(&output));
        let flat = stderr(&output)
            .split_whitespace()
            .filter(|w| *w != "│")
            .collect::<Vec<_>>()
            .join(" ");
        assert!(flat.contains(message), "{part}: {flat}");
    }
    let into_a_part = run_in(d, &["stitch", &parts[0], &parts[0], &parts[1]]);
    assert_eq!(
        into_a_part.status.code(),
        Some(2),
        "{}",
        stderr(&into_a_part)
    );
    assert!(stderr(&into_a_part).contains("io::output_is_input"));
    assert!(!d.join("out.png").exists());
}
