//! The hierarchy must not change a single byte: every scene here renders
//! the same with `Accel::Bvh` as with `Accel::Brute`, in both precisions.
//! The scenes stress what a hierarchy can get wrong: many small spheres
//! with rays bouncing between them, rectangles (flat boxes) seen edge-on,
//! coincident primitives (ties in `t`, won by the lower index), spheres
//! touching a rectangle, and rays spawned from a primitive inside a leaf.
//! The counters say which acceleration ran, and every comparison checks
//! that it was the hierarchy, so none compares brute force with itself.

use crate::support;

use std::path::Path;

use raytracer_render::ir;
use raytracer_render::render::world::BRUTE_FORCE_MAX;
use raytracer_render::render::Precision;
use raytracer_render::render::{render, Accel, Counters, Options};
use raytracer_scene::frontend::load_bytes;

fn lower(text: &str) -> ir::Scene {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let loaded = load_bytes("test.txt", &dir, text.as_bytes());
    let checked = loaded.checked.expect("the test scene checks");
    ir::lower(checked)
}

/// The counters of the rays, without which acceleration ran.
fn rays(counters: Counters) -> Counters {
    Counters {
        bvh_nodes: 0,
        ..counters
    }
}

/// The hierarchy (`--accel bvh`, and `auto` when the scene is large enough
/// for it to choose one) renders the same bytes and casts the same rays as
/// brute force, in both precisions.
fn assert_same(name: &str, text: &str) {
    let scene = lower(text);
    let options = |accel| Options {
        accel,
        ..Options::default()
    };
    let brute = render(Precision::F64, &scene, &options(Accel::Brute), &|| {});
    assert_eq!(
        brute.1.bvh_nodes, 0,
        "{name}: brute force built a hierarchy"
    );
    let brute32 = render(Precision::F32, &scene, &options(Accel::Brute), &|| {});
    let mut compared = 0;
    for accel in [Accel::Bvh, Accel::Auto] {
        let fast = render(Precision::F64, &scene, &options(accel), &|| {});
        let hierarchy = accel == Accel::Bvh || scene.objects.len() > BRUTE_FORCE_MAX;
        assert_eq!(
            fast.1.bvh_nodes > 0,
            hierarchy,
            "{name}: {accel:?} ran the wrong acceleration ({} nodes)",
            fast.1.bvh_nodes
        );
        if !hierarchy {
            // `auto` chose brute force: the comparison above is the one.
            continue;
        }
        assert_eq!(
            rays(brute.1),
            rays(fast.1),
            "{name}: f64 {accel:?} ray counts differ"
        );
        assert!(brute.0 == fast.0, "{name}: f64 {accel:?} image differs");
        let fast = render(Precision::F32, &scene, &options(accel), &|| {});
        assert!(
            fast.1.bvh_nodes > 0,
            "{name}: f32 {accel:?} ran brute force"
        );
        assert!(brute32.0 == fast.0, "{name}: f32 {accel:?} image differs");
        compared += 1;
    }
    assert!(compared > 0);
}

/// `--stats-json` says which acceleration ran: brute force for the
/// two-object sample under `auto` and `brute`, a hierarchy under `bvh`.
#[test]
fn the_statistics_name_the_acceleration_that_ran() {
    let dir = tempfile::tempdir().unwrap();
    let sample = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/sample.txt");
    let out = dir.path().join("out.png");
    let json = dir.path().join("stats.json");
    for (accel, used) in [("auto", "brute"), ("brute", "brute"), ("bvh", "bvh")] {
        let output = support::run(&[
            "render",
            sample,
            out.to_str().unwrap(),
            "--quiet",
            "--accel",
            accel,
            "--stats",
            "--stats-json",
            json.to_str().unwrap(),
        ]);
        assert_eq!(output.status.code(), Some(0), "{output:?}");
        let stats: serde_json::Value =
            serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
        assert_eq!(stats["accel"], accel, "{stats:#}");
        assert_eq!(stats["accel_used"], used, "{stats:#}");
        let nodes = stats["bvh_nodes"].as_u64().unwrap();
        assert_eq!(nodes > 0, used == "bvh", "{stats:#}");
        assert_eq!(stats["non_finite"], 0, "{stats:#}");
        let human = String::from_utf8_lossy(&output.stderr);
        let expected = match nodes {
            0 => format!("acceleration       brute force (--accel {accel})"),
            1 => format!("acceleration       bvh, 1 node (--accel {accel})"),
            n => format!("acceleration       bvh, {n} nodes (--accel {accel})"),
        };
        assert!(human.contains(&expected), "{human}");
    }
}

const SAMPLE_BODY: &str = "
plane
  dimension 4 4
  center 0 -1 -5
  normal 0 1 0
  headup 0 0 1
  texture wood_tex.ppm

light
  location -1 2 -2
  color 1 .7 .7
";

fn sphere(c: [f64; 3], r: f64, k: f64, color: [f64; 3]) -> String {
    format!(
        "\nsphere\n  dimension {r}\n  center {} {} {}\n  reflectivity {k}\n  color {} {} {}\n",
        c[0], c[1], c[2], color[0], color[1], color[2]
    )
}

#[test]
fn sample_scene() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/sample.txt"))
        .unwrap()
        .replace("camera 400", "camera 96");
    assert_same("sample", &text);
}

#[test]
fn sphere_grid_with_interreflections() {
    let mut text = format!("camera 80\n{SAMPLE_BODY}");
    for layer in 0..2 {
        for row in 0..12 {
            for column in 0..12 {
                let c = [
                    (column as f64 - 5.5) * 0.3,
                    (5.5 - row as f64) * 0.3,
                    -4.0 - layer as f64 * 0.5,
                ];
                let tint = column as f64 / 12.0;
                text += &sphere(c, 0.14, 0.6, [0.3 + 0.6 * tint, 0.5, 0.9 - 0.5 * tint]);
            }
        }
    }
    text += "\nlight\n  location 2 3 1\n  color .5 .5 .8\n";
    assert_same("grid", &text);
}

#[test]
fn ties_edges_and_touching() {
    let mut text = format!("camera 64\n{SAMPLE_BODY}");
    // The same sphere twice, with different colours: the first must win.
    text += &sphere([0.5, 0.0, -4.0], 0.5, 0.3, [1.0, 0.0, 0.0]);
    text += &sphere([0.5, 0.0, -4.0], 0.5, 0.3, [0.0, 0.0, 1.0]);
    // A sphere resting on the plane, and one cut by it.
    text += &sphere([-1.0, -0.5, -5.0], 0.5, 0.5, [0.2, 0.8, 0.2]);
    text += &sphere([1.2, -1.0, -5.5], 0.4, 0.0, [0.9, 0.9, 0.2]);
    // Two coincident mirrors facing the spheres, one seen edge-on.
    for color in ["1 0 0", "0 1 0"] {
        text += &format!(
            "\nplane\n  dimension 2 2\n  center 0 0 -7\n  normal 0 0 1\n  headup 0 1 0\n  reflectivity .8\n  color {color}\n"
        );
    }
    text += "\nplane\n  dimension 3 1\n  center 0 0 -3\n  normal 0 1 0\n  headup 0 0 1\n  color .5 .5 .5\n";
    for i in 0..20 {
        let t = f64::from(i) * 0.7;
        text += &sphere(
            [t.cos() * 2.0, t.sin(), -6.0 - t * 0.2],
            0.2,
            0.9,
            [0.8, 0.8, 0.8],
        );
    }
    assert_same("ties", &text);
}

#[test]
fn a_degenerate_chain_of_growing_spheres() {
    // Spheres at geometric distances, sizes spanning eleven orders of
    // magnitude: binned splits peel off a few at a time (a deep, lopsided
    // tree) and box padding differs by as much between neighbours.
    let mut text = format!("camera 48\n{SAMPLE_BODY}");
    for i in 0..150 {
        let d = 1.2f64.powi(i);
        text += &sphere([0.3 * d, 0.1 * d, -2.0 - d], 0.25 * d, 0.5, [0.6, 0.6, 0.9]);
    }
    assert_same("chain", &text);
}
